/* The Tiled map loader (docs/tilemaps.md), for kg_scene_load_tiled and the scene format's
 * "tilemap": {"tiled": PATH} section. */
#ifndef KG_TILED_H
#define KG_TILED_H

#include "kgyro/scene.h"

#include <cjson/cJSON.h>

/* Whether a parsed JSON document is a Tiled map rather than a kgyro scene. */
int kg_tiled_is_map(const cJSON* root);

/* Adds the map in root (read from path, which names it in messages and is where external
 * tilesets are looked for) to scene: one tile map, the bodies and markers of its object
 * layers, its layers and the custom properties of the map, layers and objects. */
kg_result kg_tiled_read(kg_scene* scene, const cJSON* root, const char* path);

/* Reads the Tiled map file at path into scene, as kg_tiled_read. It and its tilesets
 * are read under the limits scene holds (io/scene_limits.h). */
kg_result kg_tiled_load_into(kg_scene* scene, const char* path);

/* source relative to the directory of the file `from` (as it is when absolute). */
void kg_tiled_sibling_path(const char* from, const char* source, char* out, size_t size);

#endif
