/* The Tiled loader's level data (properties, classes, notes) going into a scene
 * (io/scene_props.h); tiled.c reads the rest of the map. */
#ifndef KG_TILED_LEVEL_H
#define KG_TILED_LEVEL_H

#include "io/json_util.h"
#include "kgyro/scene.h"

/* Refuses a "properties" field that is not an array (the pre-1.2 format). */
kg_result kg_tiled_check_properties(const kg_json_reader* reader, const cJSON* owner, const kg_json_path* path);

/* Adds the custom properties of owner_json (a map, layer or object at path) to the
 * scene's owner index, in file order: each checked against its type (a wrong value is
 * "PATH.properties.NAME.value: must be ..."), class-typed ones flattened into
 * "NAME.MEMBER" (docs/tilemaps.md). */
kg_result kg_tiled_keep_properties(kg_scene* scene, const kg_json_reader* reader, const cJSON* owner_json,
                                   const kg_json_path* path, kg_scene_owner owner, int index);

/* An object's class: "class" (Tiled 1.9) or "type" (before 1.9, and again from 1.10),
 * "" when neither; *out points into the document. */
kg_result kg_tiled_object_class(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                                const char** out);

/* Adds the note "SOURCE: PATH: what" to the scene (control characters cleaned). */
kg_result kg_tiled_note(kg_scene* scene, const kg_json_reader* reader, const kg_json_path* path, const char* what);

#endif
