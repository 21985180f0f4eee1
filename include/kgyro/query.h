/* KineticGyro: asking the world what is where. Ray casts, shape casts and overlap queries
 * over every shape of every body and every tile of every tile map, through an index of
 * the shapes' bounds: a query costs what it touches, not the size of the world.
 *
 *   kg_ray_result hit;
 *   kg_vec2 to_target = {target.x - eye.x, target.y - eye.y};
 *   kg_world_cast_ray_closest(world, eye, to_target, kg_default_query_filter(), &hit);
 *   int seen = hit.hit && hit.body.index == guard_target.index && hit.body.generation == guard_target.generation;
 *
 * The index is made again by the first query after the world changed (a step, a body
 * created, destroyed or changed through the API, a shape added or removed), so the
 * first query after a step pays for it (about 10 ms for 100,000 bodies) and the
 * following ones do not. Queries read the world as the last step left it, on either
 * backend (the OpenCL backend's state is read back first), and allocate nothing unless
 * the index must grow. A query's callback must not change the world, and one world's
 * queries must not run on several threads at once (the first may remake the index).
 *
 * Results are deterministic: the same world and query give the same hits, in the same
 * order, with the same bits, whatever the thread count or backend. Callbacks are called
 * in an order fixed by the world's content (not sorted by distance): use the _closest
 * calls, or keep the nearest hit in the callback, for the first thing along a ray.
 *
 * docs/queries-events.md, "Queries", has the details. */
#ifndef KGYRO_QUERY_H
#define KGYRO_QUERY_H

#include "shape.h"
#include "tilemap.h"

#ifdef __cplusplus
extern "C" {
#endif

/* kg_query_filter.flags: kinds of shapes a query leaves out. */
#define KG_QUERY_SKIP_STATIC 0x1u    /* shapes of static bodies */
#define KG_QUERY_SKIP_KINEMATIC 0x2u /* shapes of kinematic bodies */
#define KG_QUERY_SKIP_DYNAMIC 0x4u   /* shapes of dynamic bodies and particles */
#define KG_QUERY_SKIP_SENSORS 0x8u   /* sensor shapes (kg_body_shape_def.is_sensor) */
#define KG_QUERY_SKIP_TILES 0x10u    /* tiles of tile maps */

/* Which shapes a query sees: a shape (or a tile map) is seen when
 * (filter.category & shape.mask) && (shape.category & filter.mask), as two shapes collide,
 * and its kind is not in flags. */
typedef struct kg_query_filter {
    uint32_t category; /* what the query is, for the shapes' masks */
    uint32_t mask;     /* the categories it sees */
    uint32_t flags;    /* KG_QUERY_SKIP_* */
} kg_query_filter;

/* Category all, mask all, no flags: sees every shape and tile, sensors included. */
KG_API kg_query_filter kg_default_query_filter(void);

/* A hit of a ray or shape cast. For a shape of a body: body, shape, and the body's user data
 * (kg_body_get_user_data); map is the null handle. For a tile: map, layer and cell (x, y)
 * of the tile, user_data the map's (kg_tilemap_get_user_data); body and shape null. */
typedef struct kg_ray_result {
    int hit;          /* 0: nothing was hit, and the other fields are zero */
    kg_body body;
    kg_shape_id shape;
    void* user_data;
    kg_tilemap map;
    int layer, x, y;  /* the tile's layer and cell, when map is not null */
    kg_vec2 point;    /* world frame: where the ray (the cast shape) meets the surface */
    kg_vec2 normal;   /* unit, the surface's outward normal there (towards the ray's origin side) */
    float fraction;   /* of the translation: point = origin + fraction * translation for a ray */
} kg_ray_result;

/* Called for each hit of kg_world_cast_ray and kg_world_cast_shape; returns the fraction the
 * ray is clipped to from then on (Box2D v3's convention): 0 stops the query, 1 (or any value
 * at or above the current clip) lets every hit through, hit->fraction keeps only hits that
 * are as near or nearer, a negative value ignores this hit and goes on unclipped. A hit
 * exactly at the clip is still reported. ctx is the caller's. */
typedef float kg_ray_fn(const kg_ray_result* hit, void* ctx);

/* Called for each shape or tile an overlap query finds: body and shape (null for a tile),
 * the body's user data (the map's for a tile); non-zero goes on, 0 stops. */
typedef int kg_overlap_fn(kg_body body, kg_shape_id shape, void* user_data, void* ctx);

/* A shape or tile an overlap query found, with the tile's map and cell: what
 * kg_overlap_tile_fn is given. */
typedef struct kg_overlap_result {
    kg_body body;
    kg_shape_id shape;
    void* user_data;
    kg_tilemap map;
    int layer, x, y;
} kg_overlap_result;

/* ---- ray casts ----
 * The ray is the segment from origin to origin + translation (finite; a zero translation
 * hits nothing). It hits the surface of a shape it enters: a ray that starts inside a
 * shape, or on its surface going in, does not hit that shape (it hits the others it then
 * enters), and a ray that starts inside a tile-map's terrain hits none of it until it
 * leaves and enters it again. Segments are hit from either side, a chain's segments from
 * their solid side only. A one-way tile is hit from above only: a ray from below passes
 * through it (kg_tile_shape.one_way). Fails with KG_ERROR_INVALID_ARGUMENT for a NULL world,
 * out or fn, or a non-finite origin or translation. */

/* The nearest hit; out->hit = 0 when there is none. Of hits at the same fraction, the one
 * of the lowest shape slot, then of the lowest map, layer, row and column. */
KG_API kg_result kg_world_cast_ray_closest(const kg_world* world, kg_vec2 origin, kg_vec2 translation,
                                           kg_query_filter filter, kg_ray_result* out);
/* Every hit (as long as fn goes on), through fn: see kg_ray_fn. Bodies' shapes first, in
 * the index's order, then the tile maps, oldest first, each cell along the ray in order. */
KG_API kg_result kg_world_cast_ray(const kg_world* world, kg_vec2 origin, kg_vec2 translation,
                                   kg_query_filter filter, kg_ray_fn* fn, void* ctx);

/* ---- shape casts ----
 * shape (a kg_shape_def, as kg_body_def.shape: circle, polygon, box, capsule or segment)
 * placed with its origin at position, turned by angle, swept without turning along
 * translation. A hit is the first fraction at which it comes within 1e-4 m of a shape;
 * point is the nearest point of the cast shape there, normal the hit surface's normal
 * (towards the cast shape). A cast that starts overlapping (or within 1e-4 m of) a shape
 * hits it at fraction 0, with the normal against translation (zero for a zero one): a
 * ground check cast down from inside the ground still finds it. One-way tiles stop only
 * casts that come down onto their upward faces. Fails with KG_ERROR_INVALID_ARGUMENT for a
 * NULL argument or a non-finite position, angle or translation, and with the shape's own
 * error (KG_ERROR_DEGENERATE_SHAPE, ...) for a shape kg_create_body would refuse; a
 * shape of type NONE is refused. */
KG_API kg_result kg_world_cast_shape(const kg_world* world, const kg_shape_def* shape, kg_vec2 position,
                                     float angle, kg_vec2 translation, kg_query_filter filter, kg_ray_fn* fn,
                                     void* ctx);
/* The first hit of the cast (the lowest fraction; ties as kg_world_cast_ray_closest). */
KG_API kg_result kg_world_cast_shape_closest(const kg_world* world, const kg_shape_def* shape, kg_vec2 position,
                                             float angle, kg_vec2 translation, kg_query_filter filter,
                                             kg_ray_result* out);
/* Each shape of body swept along translation from where it is now (the body's own shapes
 * are left out of what it can hit), the earliest hit of them all; out->shape is the shape
 * that was hit. For a character's move or a ground check. KG_ERROR_INVALID_HANDLE for a
 * stale body. */
KG_API kg_result kg_world_cast_body_closest(const kg_world* world, kg_body body, kg_vec2 translation,
                                            kg_query_filter filter, kg_ray_result* out);

/* ---- overlap queries ----
 * Each found shape or tile once, through fn (0 stops the query): bodies' shapes in the
 * index's order, then tiles map by map (oldest first), layer by layer, row by row from the
 * bottom. Tiles report their body and shape as null and the map's user data; the _tiles
 * variants give each result's map and cell (kg_overlap_result). Fails with
 * KG_ERROR_INVALID_ARGUMENT for a NULL world or fn or a non-finite or inverted box, point,
 * position or angle; a bad shape as kg_world_cast_shape. */

/* The shapes whose bounds (as kg_shape_aabb: the shape's own box, not the body's swept
 * one) overlap box, touching counted, and the tiles whose shape's bounds do. */
KG_API kg_result kg_world_overlap_aabb(const kg_world* world, kg_aabb box, kg_query_filter filter,
                                       kg_overlap_fn* fn, void* ctx);
/* The shapes and tiles that hold point (their surface included; segments hold none). */
KG_API kg_result kg_world_overlap_point(const kg_world* world, kg_vec2 point, kg_query_filter filter,
                                        kg_overlap_fn* fn, void* ctx);
/* The shapes and tiles that overlap or touch shape placed at position and turned by angle
 * (one-way tiles count: an overlap has no direction). */
KG_API kg_result kg_world_overlap_shape(const kg_world* world, const kg_shape_def* shape, kg_vec2 position,
                                        float angle, kg_query_filter filter, kg_overlap_fn* fn, void* ctx);

/* The same three with the whole result, tiles' maps and cells included: 0 stops. */
typedef int kg_overlap_result_fn(const kg_overlap_result* found, void* ctx);
KG_API kg_result kg_world_overlap_aabb_results(const kg_world* world, kg_aabb box, kg_query_filter filter,
                                               kg_overlap_result_fn* fn, void* ctx);
KG_API kg_result kg_world_overlap_point_results(const kg_world* world, kg_vec2 point, kg_query_filter filter,
                                                kg_overlap_result_fn* fn, void* ctx);
KG_API kg_result kg_world_overlap_shape_results(const kg_world* world, const kg_shape_def* shape, kg_vec2 position,
                                                float angle, kg_query_filter filter, kg_overlap_result_fn* fn,
                                                void* ctx);

#ifdef __cplusplus
}
#endif
#endif
