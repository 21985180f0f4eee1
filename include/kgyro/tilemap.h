/* KineticGyro: tile-map terrain. A tile map is a grid of tile ids laid on the world; each
 * id maps to a collision shape (empty, full square, slopes, half tiles, one-way platforms
 * or any convex polygon). Bodies collide with the cells their bounds cover, found by direct
 * look-up: no body or broadphase entry per tile, and a cost that does not grow with the
 * size of the map. Edges shared by two solid tiles never make contacts, and the vertices
 * where tiles meet are smoothed, so bodies slide across runs of tiles without snagging.
 *
 *   kg_tile_shape shapes[3] = {kg_tile_empty(), kg_tile_box(), kg_tile_slope(KG_TILE_BOTTOM_RIGHT)};
 *   kg_tilemap_def def = kg_default_tilemap_def();
 *   def.width = 64; def.height = 16; def.shapes = shapes; def.shape_count = 3;
 *   kg_tilemap map;
 *   kg_create_tilemap(world, &def, &map);
 *   kg_tilemap_set_tile(world, map, 0, 10, 0, 1);  // a full square at cell (10, 0)
 *
 * Cells are (x, y) with y up: cell (0, 0) is the lower-left one, its lower-left corner at
 * the map's origin. docs/tilemaps.md has the details and the Tiled loader. */
#ifndef KGYRO_TILEMAP_H
#define KGYRO_TILEMAP_H

#include "types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Generational handle of a tile map, like kg_body. The all-zero handle is never valid. */
typedef struct kg_tilemap {
    uint32_t index;
    uint32_t generation;
} kg_tilemap;

#define KG_NULL_TILEMAP_INIT {0u, 0u}

/* Tile id 0 is always empty; ids go up to KG_MAX_TILE_ID. */
#define KG_TILE_EMPTY_ID 0
#define KG_MAX_TILE_ID 0xFFFF

typedef enum kg_tile_shape_type {
    KG_TILE_SHAPE_EMPTY = 0,   /* no collision */
    KG_TILE_SHAPE_POLYGON = 1, /* convex, 3 to KG_MAX_POLYGON_VERTICES vertices */
    KG_TILE_SHAPE_CIRCLE = 2
} kg_tile_shape_type;

/* The collision shape of a tile id, in tile coordinates: (0, 0) is the cell's lower-left
 * corner, (1, 1) its upper-right one, whatever the tile size, so a shape fits any map.
 * Polygon vertices may come in any order (the convex hull is taken) and must lie in the
 * cell. A circle's radius is in units of the tile's width; it needs square tiles. */
typedef struct kg_tile_shape {
    kg_tile_shape_type type;
    int count;
    kg_vec2 vertices[KG_MAX_POLYGON_VERTICES];
    kg_vec2 center;
    float radius;
    int one_way; /* non-zero: only the upward-facing edges collide, with bodies coming from above */
} kg_tile_shape;

/* The corner a slope's right angle is in; the slope rises towards it. KG_TILE_BOTTOM_RIGHT
 * is a floor slope rising to the right, KG_TILE_TOP_LEFT a ceiling slope. */
typedef enum kg_tile_corner {
    KG_TILE_BOTTOM_LEFT = 0,
    KG_TILE_BOTTOM_RIGHT = 1,
    KG_TILE_TOP_RIGHT = 2,
    KG_TILE_TOP_LEFT = 3
} kg_tile_corner;

/* The side a half tile is against. */
typedef enum kg_tile_side {
    KG_TILE_SIDE_BOTTOM = 0,
    KG_TILE_SIDE_RIGHT = 1,
    KG_TILE_SIDE_TOP = 2,
    KG_TILE_SIDE_LEFT = 3
} kg_tile_side;

KG_API kg_tile_shape kg_tile_empty(void);
/* The full square. */
KG_API kg_tile_shape kg_tile_box(void);
/* The half of the tile against side. */
KG_API kg_tile_shape kg_tile_half(kg_tile_side side);
/* A 45-degree slope: the triangle with its right angle in corner. */
KG_API kg_tile_shape kg_tile_slope(kg_tile_corner corner);
/* The two tiles of a gentle slope that climbs half a tile per tile (1 in 2, about 26.6
 * degrees; the "22.5-degree" slope of tile sets), rising towards corner: the low part
 * goes from 0 to half the tile's height, the high part from half to the full height. */
KG_API kg_tile_shape kg_tile_slope_low(kg_tile_corner corner);
KG_API kg_tile_shape kg_tile_slope_high(kg_tile_corner corner);
/* A one-way platform: the top half of the tile, solid from above only. */
KG_API kg_tile_shape kg_tile_platform(void);
/* Any convex polygon (tile coordinates). */
KG_API kg_tile_shape kg_tile_polygon(const kg_vec2* vertices, int count);
KG_API kg_tile_shape kg_tile_circle(kg_vec2 center, float radius);
/* Checks a tile shape as kg_create_tilemap does (for square tiles). */
KG_API kg_result kg_tile_shape_check(const kg_tile_shape* shape);

/* Everything a tile map is made from. Start from kg_default_tilemap_def(). */
typedef struct kg_tilemap_def {
    int width, height;   /* cells, each in [1, 65536], width * height * layer_count <= 2^28 */
    int layer_count;     /* >= 1; each layer is its own grid of ids over the same cells */
    kg_vec2 tile_size;   /* m, > 0 */
    kg_vec2 origin;      /* world position of cell (0, 0)'s lower-left corner */
    const kg_tile_shape* shapes; /* shapes[id] for id in [0, shape_count); shapes[0] must be empty */
    int shape_count;             /* in [1, KG_MAX_TILE_ID + 1] */
    /* Initial ids, layer after layer, each row by row from the bottom (index
     * (layer * height + y) * width + x); NULL = every cell empty. Copied. */
    const uint16_t* tiles;
    float friction;      /* mixed with a body's like two bodies: sqrt(fa * fb) */
    float restitution;   /* mixed as max(ra, rb) */
    uint32_t category;   /* collision filtering, as kg_body_def's */
    uint32_t mask;
    void* user_data;
} kg_tilemap_def;

/* 1 m tiles at the origin, one layer, friction 0.6, restitution 0, colliding with all. */
KG_API kg_tilemap_def kg_default_tilemap_def(void);

/* Adds a map to the world; a world holds any number of them. Its memory is 4 bytes per
 * cell and layer. The shapes are checked and copied. */
KG_API kg_result kg_create_tilemap(kg_world* world, const kg_tilemap_def* def, kg_tilemap* out_map);
KG_API kg_result kg_destroy_tilemap(kg_world* world, kg_tilemap map);
KG_API int kg_tilemap_is_valid(const kg_world* world, kg_tilemap map);

/* Changes one cell in constant time (dig, build). Bodies touching it react in the next
 * step: there is no sleeping, so every body is simulated every step. id must be below the
 * map's shape_count. */
KG_API kg_result kg_tilemap_set_tile(kg_world* world, kg_tilemap map, int layer, int x, int y, int id);
KG_API kg_result kg_tilemap_get_tile(const kg_world* world, kg_tilemap map, int layer, int x, int y, int* out_id);
/* The cell holding a world point; KG_ERROR_INVALID_ARGUMENT when outside the map. */
KG_API kg_result kg_tilemap_cell_at(const kg_world* world, kg_tilemap map, kg_vec2 point, int* out_x, int* out_y);
/* The map's definition as created (shapes and tiles are NULL: read them with the calls
 * above). */
KG_API kg_result kg_tilemap_get_def(const kg_world* world, kg_tilemap map, kg_tilemap_def* out);
KG_API void* kg_tilemap_get_user_data(const kg_world* world, kg_tilemap map);

KG_API int kg_world_tilemap_count(const kg_world* world);
/* Writes up to capacity live map handles, oldest first; *count gets how many. */
KG_API kg_result kg_world_get_tilemaps(const kg_world* world, kg_tilemap* out, int capacity, int* count);

/* Which tile contact index of the last step touches (kg_contact_info.b is the null body for
 * those): its map, layer and cell. KG_ERROR_INVALID_ARGUMENT for a contact between bodies. */
KG_API kg_result kg_world_get_contact_tile(const kg_world* world, int index, kg_tilemap* out_map, int* out_layer,
                                           int* out_x, int* out_y);

#ifdef __cplusplus
}
#endif
#endif
