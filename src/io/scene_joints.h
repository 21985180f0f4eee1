/* The scene's joints: the "joints" array of a scene file (docs/scene-format.md) and
 * their creation in a world. */
#ifndef KG_SCENE_JOINTS_H
#define KG_SCENE_JOINTS_H

#include "io/json_util.h"
#include "kgyro/scene.h"

/* j of type with every kind's definition at its default and no bodies (body_a -1). */
void kg_scene_joint_init(kg_scene_joint* j, kg_joint_type type);

/* Every check the reader makes of an entry (its type, its bodies, each option's rule, the
 * options between them, the engine's own checks of the values, anchors a body's frame can
 * hold): a scene joint that passes instantiates and is written as a file that reads back.
 * Messages name path; reader NULL: a call's failure (KG_ERROR_INVALID_ARGUMENT, path
 * naming the call and the joint) rather than a file's. */
kg_result kg_check_joint_entry(const kg_json_reader* reader, const kg_json_path* path, const kg_scene* scene,
                               const kg_scene_joint* j);

/* The path kg_check_joint_entry names joint index of scene by when call checks it
 * ("call: joint 3 (a 'x', b 'y')"); j's bodies are the scene's. */
kg_json_path kg_joint_call_path(const char* call, const kg_scene* scene, int index, const kg_scene_joint* j);

/* Reads one joint entry (an object as the "joints" array holds them) into scene, whose
 * bodies are all read; messages name path. The Tiled loader builds such entries from
 * joint objects (tiled_joints.c). */
kg_result kg_read_scene_joint(const kg_json_reader* reader, kg_scene* scene, const cJSON* item,
                              const kg_json_path* path);

/* Reads root's "joints" (if any) into scene, whose bodies are all read. */
kg_result kg_read_scene_joints(const kg_json_reader* reader, kg_scene* scene, const cJSON* root);

/* The entry of the "joints" array that reads back as j (NULL: out of memory): its kind,
 * bodies by name, anchors, and every option from the table the reader reads. */
cJSON* kg_scene_joint_json(const kg_scene* scene, const kg_scene_joint* j);

/* Creates the scene's joints in world, whose scene bodies are handles. */
kg_result kg_create_scene_joints(const kg_scene* scene, kg_world* world, const kg_body* handles);

#endif
