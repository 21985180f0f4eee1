/* Tile-map terrain in the collision stage (public API: include/kgyro/tilemap.h). After the
 * body pairs, the collision stage calls kg_tilemap_collide, which looks up, for every
 * moving body, the cells of every map that its bounds (fattened by the speculative
 * distance) cover, and collides the body with each tile there (collide/tile_pass.h).
 *
 * Data layout, the same on the host and in a device buffer:
 *
 *  - cells: one kg_u32 per cell and layer, layer after layer, each row by row from the
 *    bottom: index (layer * height + y) * width + x. Bits 0-15 hold the tile id, bit
 *    16 + i that polygon edge i is exposed near its start vertex, bit 24 + i that it is
 *    exposed near its end vertex (KG_CELL_* in tile_collide.h). An edge is exposed unless
 *    the neighbour across the cell side it lies on has a solid edge on that side covering
 *    it there; a one-way tile's edges that do not face up are never exposed. The flags of
 *    a cell and its four side neighbours are recomputed when a tile changes.
 *  - protos: one kg_tile_proto (160 bytes) per tile id of a map: the id's shape in the
 *    cell frame (origin at the cell's lower-left corner, metres), flags (one-way).
 *  - per map: origin, tile size, width, height, layer count, the offset of its cells and
 *    protos in those buffers, its first tile key, friction, restitution, category, mask.
 *
 * The host keeps these arrays as the device does (kg_tilemaps_arrays): the cells of every
 * live map one after the other in key order, their protos likewise, and a description
 * per map (kg_tile_map_info); both backends collide a body with them through the same
 * code (collide/tile_pass.h).
 *
 * Tile keys: each map owns a range [key_base, key_base + layer_count * width * height) of
 * 32-bit keys; a cell's key is key_base + (layer * height + y) * width + x, so sorting
 * contacts by (body, key) orders them by map, layer, row and column. */
#ifndef KG_TILEMAP_H
#define KG_TILEMAP_H

#include "collide/collide.h"
#include "collide/tile_pass.h"
#include "kgyro/tilemap.h"

/* Writes up to room contacts of bodies against the world's tile maps into out (b =
 * KG_NULL_INDEX, tile = the tile's key, impulses carried from previous[0, previous_count),
 * which is last step's tile contacts in the order this function wrote them). Returns how
 * many it found, which may exceed room. */
int kg_tilemap_collide(kg_world* world, kg_contact* out, int room, const kg_contact* previous, int previous_count);
void kg_tilemaps_destroy(kg_world* world);
/* The map (handle), layer and cell of a tile contact's key; 0 when no live map has it
 * (world->tilemaps may be NULL). Any out pointer may be NULL. */
int kg_tile_key_cell(const kg_world* world, kg_u32 key, kg_tilemap* out_map, int* out_layer, int* out_x, int* out_y);

/* ---- for the OpenCL backend, which keeps the maps in device buffers ---- */

/* Changes each time a map is created or destroyed (then every buffer is built again). */
kg_u32 kg_tilemaps_layout_version(const kg_world* world);
/* The live maps in key order (the order the collision visits them). */
int kg_tilemaps_live_count(const kg_world* world);
/* The live maps as the tile pass reads them, the same arrays on the host and the device
 * (collide/tile_pass.h): valid until a map is created or destroyed. */
typedef struct kg_tilemap_arrays {
    const kg_tile_map_info* maps;
    int map_count;
    const kg_u32* cells;
    size_t cell_count;
    const kg_tile_proto* protos;
    size_t proto_count;
} kg_tilemap_arrays;
void kg_tilemaps_arrays(const kg_world* world, kg_tilemap_arrays* out);
/* The handle of the live map at live_index in those arrays (the world queries name it). */
kg_tilemap kg_tilemaps_handle(const kg_world* world, int live_index);
/* Whether kg_tilemap_set_tile changed the map's cells since the last call (which clears it). */
int kg_tilemaps_take_dirty(kg_world* world, int live_index);
/* The one-way platform state, per body slot (world->def.max_bodies each): origin and
 * generation at the last collision (generation 0 = unknown). */
kg_vec2* kg_tilemaps_last_origin(kg_world* world);
kg_u32* kg_tilemaps_last_generation(kg_world* world);

/* The shape of tile id as a kg_tile_shape (a polygon's vertices as the map keeps them, the
 * hull of the given ones; a circle's in tile units again): what a saved scene writes. */
kg_result kg_tilemap_get_shape(const kg_world* world, kg_tilemap map, int id, kg_tile_shape* out);

/* ---- snapshots (core/snapshot.c) ---- */

struct kg_snap_out;
struct kg_snap_in;
/* The sizes of the structs a snapshot of the maps holds, folded into h. */
uint64_t kg_tilemaps_layout(uint64_t h);
/* The maps (none: a word saying so), their edited cells and the one-way state of the
 * body slots [0, high_water). */
void kg_tilemaps_snapshot(const kg_world* world, struct kg_snap_out* out);
/* Reads them into new maps (*out NULL when the snapshot has none), checked; the world is
 * not touched. Then discarded, or adopted by the world in place of its own. */
kg_result kg_tilemaps_from_snapshot(const kg_world* world, int high_water, struct kg_snap_in* in,
                                    struct kg_tilemaps** out);
void kg_tilemaps_discard(struct kg_tilemaps* staged);
void kg_tilemaps_adopt(kg_world* world, struct kg_tilemaps* staged);

#endif
