/* The Tiled level data a scene keeps beside its physics (include/kgyro/scene.h, "Tiled
 * levels"): properties of maps, layers, bodies and markers, the layers, the markers, the
 * bodies' classes and the loader's notes. scene_props.c stores them; the Tiled loader
 * (tiled.c) fills them. */
#ifndef KG_SCENE_PROPS_H
#define KG_SCENE_PROPS_H

#include "kgyro/scene.h"

typedef struct kg_scene_level kg_scene_level;

/* scene.c: the scene's level data (NULL until something is added), and its grow helper
 * (doubling *items to hold needed; 0 when out of memory, the array unchanged). */
kg_scene_level* kg_scene_get_level(const kg_scene* scene);
void kg_scene_set_level(kg_scene* scene, kg_scene_level* level);
int kg_scene_grow(void** items, int* capacity, int needed, size_t item_size);

void kg_scene_level_free(kg_scene_level* level);

/* A new Tiled map's index (KG_SCENE_MAP's), its properties still to be set. */
kg_result kg_scene_add_map(kg_scene* scene, int* index);
/* Adds a layer (its strings copied); *index gets its index. */
kg_result kg_scene_add_layer(kg_scene* scene, const kg_scene_layer* layer, int* index);
/* Adds a marker (its strings copied); *index gets its index. */
kg_result kg_scene_add_marker(kg_scene* scene, const kg_scene_marker* marker, int* index);
/* The Tiled object body index came from: its class ("" for none) and layer. */
kg_result kg_scene_set_body_origin(kg_scene* scene, int index, const char* class_name, int layer);
/* Adds a property (its strings copied) to the owner, after those it has: an owner's
 * properties are added one after the other, with no other owner's in between
 * (KG_ERROR_INVALID_ARGUMENT otherwise, or for an owner that does not exist). */
kg_result kg_scene_add_property(kg_scene* scene, kg_scene_owner owner, int index, const kg_scene_property* property);
/* Adds a note (what a loader ignored); past the 100th, notes are dropped. */
kg_result kg_scene_add_note(kg_scene* scene, const char* text);

#endif
