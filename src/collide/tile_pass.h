/* The tile pass: one body against every tile map, over the maps as flat arrays. The CPU
 * backend (collide/tilemap.c) calls kg_tile_collide_body for each body slot in order,
 * the kernel kg_tile_collide_bodies for its work-item's, so both backends find the same
 * contacts, with the same bits, in the same order: per body, maps by key, layers, rows,
 * columns, so a body's contacts come out sorted by tile key. The layout of the arrays is
 * described in collide/tilemap.h, the collision with one tile in collide/tile_collide.h. */
#ifndef KG_TILE_PASS_H
#define KG_TILE_PASS_H

#include "collide/tile_collide.h"

/* A live tile map: its cells start at cell_offset in the world's cell array, its protos
 * (one per tile id) at proto_offset in the proto array. 64 bytes. */
typedef struct kg_tile_map_info {
    kg_vec2 origin;
    kg_vec2 tile_size;
    kg_i32 width, height, layer_count;
    kg_u32 cell_offset;
    kg_u32 proto_offset;
    kg_u32 key_base;
    float friction;
    float restitution;
    kg_u32 category;
    kg_u32 mask;
    kg_u32 pad[2];
} kg_tile_map_info;

KG_STATIC_ASSERT(sizeof(kg_tile_map_info) == 64, tile_map_info_size);

#endif
