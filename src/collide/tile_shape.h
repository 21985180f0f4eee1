/* Tile shapes: checking a user's kg_tile_shape and compiling it for a map's tile size.
 * Host only. */
#ifndef KG_TILE_SHAPE_H
#define KG_TILE_SHAPE_H

#include "collide/tile_collide.h"
#include "kgyro/tilemap.h"

/* A compiled tile shape, with what the host needs besides: the polygon's vertices in tile
 * coordinates (same order as proto.shape), to tell which cell side each edge lies on. */
typedef struct kg_tile_template {
    kg_tile_proto proto;
    kg_vec2 unit[KG_MAX_VERTS];
} kg_tile_template;

/* Checks shape and builds it for tiles of tile_size metres. The error message names what
 * is wrong, not which id (the caller adds that). */
kg_result kg_tile_template_build(const kg_tile_shape* shape, kg_vec2 tile_size, kg_tile_template* out);

/* The cell side (kg_tile_side) edge a -> b of a template lies on, or -1. */
int kg_tile_edge_side(kg_vec2 a, kg_vec2 b);

/* Whether a template covers its neighbours' edges: a solid polygon, not one-way. */
int kg_tile_template_is_solid(const kg_tile_template* t);

#endif
