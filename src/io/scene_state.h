/* A scene's "state" (docs/scene-format.md, "Saved worlds"): the snapshot of a saved world
 * (include/kgyro/snapshot.h) that kg_scene_instantiate restores after building the scene,
 * so that the world continues bitwise where the saved one stopped. Written by
 * kg_scene_save_file (io/scene_save.c), read here. */
#ifndef KG_SCENE_STATE_H
#define KG_SCENE_STATE_H

#include "io/json_util.h"
#include "kgyro/scene.h"

/* The scene keeps a copy of the size bytes of a snapshot (replacing any it had). */
kg_result kg_scene_set_state(kg_scene* scene, const void* snapshot, size_t size);
/* The snapshot the scene holds (NULL, *size 0: none). */
const void* kg_scene_get_state(const kg_scene* scene, size_t* size);

/* Reads root's "state" object, if any, into scene (its max_bodies and max_applicators
 * into the scene's world definition, its snapshot decoded). */
kg_result kg_read_scene_state(kg_scene* scene, const cJSON* root, const kg_json_reader* reader);
/* The "state" object of scene for a file (NULL when it has none, or out of memory). */
cJSON* kg_scene_state_json(const kg_scene* scene);

/* After kg_scene_instantiate built world (handles: its bodies in scene order): restores
 * the scene's snapshot, points handles at the restored bodies (the snapshot's live
 * bodies in slot order are the scene's), and sets the bodies whose position, angle or
 * velocities the scene gives otherwise than the snapshot (an editor moved them). */
kg_result kg_scene_restore_state(const kg_scene* scene, kg_world* world, kg_body* handles);

#endif
