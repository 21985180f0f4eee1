/* A world's tile maps as the renderer's tile layers (draw.h): one kg_tile_layer per map
 * layer, maps in the world's order, drawn under the bodies. The world's public API lists
 * its maps and reads their cells but not their tile shapes, so the looks come from the
 * scene the world was made from: kg_scene_instantiate creates the scene's maps in order,
 * and kg_world_get_tilemaps lists them in that order. */
#ifndef KG_RENDER_TILES_H
#define KG_RENDER_TILES_H

#include "draw.h"

#include "kgyro/scene.h"

typedef struct kg_tile_source {
    int map;    /* index in the world's map list */
    int layer;  /* layer of that map */
    int* cells; /* where its ids go: the layer's cells */
} kg_tile_source;

typedef struct kg_tile_view {
    kg_tile_layer* layers; /* layer_count of them, for kg_draw_options */
    kg_tile_source* sources;
    int layer_count;
    kg_tilemap* maps; /* the world's maps, listed again at each refresh */
    int map_count;
    kg_tile_look* looks; /* every map's looks, one map after another */
    int* cells;          /* every layer's cells, one layer after another */
} kg_tile_view;

/* Builds the layers of the maps world got from scene, every cell empty until refreshed.
 * KG_OK with no layers when the world has no maps. */
kg_result kg_tile_view_init(kg_tile_view* view, const kg_scene* scene, const kg_world* world);
/* Reads the cells camera shows (and a border of one, whose edges the outlines depend on)
 * from world, so tiles changed at run time show up. world may be a new world made from
 * the same scene: the maps are listed again. */
void kg_tile_view_refresh(kg_tile_view* view, const kg_world* world, const kg_camera* camera);
void kg_tile_view_free(kg_tile_view* view);

#endif
