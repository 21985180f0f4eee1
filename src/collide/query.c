/* The world queries (kgyro/query.h): the query index (collide/query_index.h) finds the
 * shapes near a ray, a sweep or a box, the narrow tests (collide/raycast.h, the distance
 * and time of impact of collide/toi.h) decide, and tile maps are walked cell by cell. */
#include "kgyro/query.h"
#include "collide/query_index.h"
#include "collide/raycast.h"
#include "collide/shape.h"
#include "collide/tilemap.h"
#include "collide/toi.h"
#include "core/error.h"

#include <math.h>
#include <string.h>

/* A shape cast hits when the cast shape comes this close (m). */
#define KG_CAST_TOLERANCE 1.0e-4f

kg_query_filter kg_default_query_filter(void)
{
    kg_query_filter filter;
    filter.category = 0xFFFFFFFFu;
    filter.mask = 0xFFFFFFFFu;
    filter.flags = 0u;
    return filter;
}

typedef enum kg_overlap_kind { KG_OVERLAP_BOX, KG_OVERLAP_POINT, KG_OVERLAP_SHAPE } kg_overlap_kind;

/* One query in flight. */
typedef struct kg_query {
    const kg_world* world;
    const kg_body_pool* p;
    const kg_shape_pool* sp;
    kg_query_filter filter;
    kg_u32 skip_body; /* a body slot whose shapes are left out (a body's own cast), or KG_NULL_INDEX */
    int stopped;
    /* ray and shape casts: the ray (for a cast, from the centre of the cast shape's bounds),
     * 1 / its translation, and how far each node's box is grown (a cast shape's half size) */
    kg_ray ray;
    kg_vec2 inverse;
    kg_vec2 reach;
    kg_ray_fn* fn;
    void* ctx;
    /* shape casts: the shape and its motion */
    const kg_shape* moving;
    kg_sweep sweep;
    /* overlaps: what is tested, the box that bounds it, the shape's pose */
    kg_overlap_kind kind;
    kg_aabb box;
    kg_vec2 point;
    kg_xf xf;
    kg_overlap_result_fn* found;
} kg_query;

static kg_query kg_start_query(const kg_world* world, kg_query_filter filter)
{
    kg_query q;
    memset(&q, 0, sizeof q);
    q.world = world;
    q.p = kg_world_read_pool(world); /* the OpenCL backend's bodies, read back */
    q.sp = &world->shapes;
    q.filter = filter;
    q.skip_body = KG_NULL_INDEX;
    return q;
}

/* ---- filters ---- */

static kg_u32 kg_kind_flag(kg_body_type type)
{
    return type == KG_BODY_STATIC ? KG_QUERY_SKIP_STATIC
                                  : (type == KG_BODY_KINEMATIC ? KG_QUERY_SKIP_KINEMATIC : KG_QUERY_SKIP_DYNAMIC);
}

static int kg_sees_shape(const kg_query* q, kg_u32 s, kg_u32 i)
{
    kg_u32 flags = q->filter.flags;
    if (i == q->skip_body || (flags & kg_kind_flag(kg_pool_type(q->p, (int)i))) ||
        ((flags & KG_QUERY_SKIP_SENSORS) && kg_shape_is_sensor(q->sp, s))) {
        return 0;
    }
    return (q->filter.category & q->sp->mask[s]) != 0u && (q->sp->category[s] & q->filter.mask) != 0u;
}

static int kg_sees_map(const kg_query* q, const kg_tile_map_info* m)
{
    return !(q->filter.flags & KG_QUERY_SKIP_TILES) && (q->filter.category & m->mask) != 0u &&
           (m->category & q->filter.mask) != 0u;
}

/* ---- results ---- */

static void kg_name_body(const kg_query* q, kg_u32 s, kg_u32 i, kg_body* body, kg_shape_id* shape, void** user_data)
{
    body->index = i;
    body->generation = q->p->generation[i];
    shape->index = s;
    shape->generation = q->sp->generation[s];
    *user_data = q->p->user_data[i];
}

static kg_ray_result kg_body_result(const kg_query* q, kg_u32 s, float fraction, kg_vec2 point, kg_vec2 normal)
{
    kg_ray_result r;
    memset(&r, 0, sizeof r);
    r.hit = 1;
    kg_name_body(q, s, q->sp->body[s], &r.body, &r.shape, &r.user_data);
    r.point = point;
    r.normal = normal;
    r.fraction = fraction;
    return r;
}

/* A tile's map, layer and cell; the map's user data. */
typedef struct kg_tile_at {
    int map; /* live index */
    int layer, x, y;
} kg_tile_at;

static void kg_name_tile(const kg_query* q, kg_tile_at at, kg_tilemap* map, void** user_data)
{
    *map = kg_tilemaps_handle(q->world, at.map);
    *user_data = kg_tilemap_get_user_data(q->world, *map);
}

static kg_ray_result kg_tile_result(const kg_query* q, kg_tile_at at, float fraction, kg_vec2 point, kg_vec2 normal)
{
    kg_ray_result r;
    memset(&r, 0, sizeof r);
    r.hit = 1;
    kg_name_tile(q, at, &r.map, &r.user_data);
    r.layer = at.layer;
    r.x = at.x;
    r.y = at.y;
    r.point = point;
    r.normal = normal;
    r.fraction = fraction;
    return r;
}

/* Hands a hit to the caller and clips the ray to the answer (kg_ray_fn): 0 stops, a
 * value in (0, clip) clips, anything else (1, a negative value: ignore this hit) goes on. */
static int kg_report_hit(kg_query* q, const kg_ray_result* r)
{
    float value = q->fn(r, q->ctx);
    if (value == 0.0f) {
        q->stopped = 1;
        return 0;
    }
    if (value > 0.0f && value < q->ray.max_fraction) {
        q->ray.max_fraction = value;
    }
    return 1;
}

/* Whether hit a comes before b at the same fraction: a body's shape before a tile, the
 * lower shape slot first; tiles in the order they were found. */
static int kg_tie_before(const kg_ray_result* a, const kg_ray_result* b)
{
    int a_body = a->body.generation != 0u, b_body = b->body.generation != 0u;
    return a_body && (!b_body || a->shape.index < b->shape.index);
}

/* Keeps the nearest hit. A hit at 0 (a cast that starts overlapping) is clipped to the
 * least float above 0 rather than 0, which would stop the query before a tie of a lower
 * slot is found. */
static float kg_keep_closest(const kg_ray_result* hit, void* ctx)
{
    kg_ray_result* best = (kg_ray_result*)ctx;
    if (!best->hit || hit->fraction < best->fraction || (hit->fraction == best->fraction && kg_tie_before(hit, best))) {
        *best = *hit;
    }
    return hit->fraction > 0.0f ? hit->fraction : nextafterf(0.0f, 1.0f);
}

/* ---- the index and the tile maps ---- */

static int kg_ray_node(kg_aabb box, const void* ctx)
{
    const kg_query* q = (const kg_query*)ctx;
    box.lower = kg_sub(box.lower, q->reach);
    box.upper = kg_add(box.upper, q->reach);
    return kg_ray_meets_box(box, q->ray.origin, q->inverse, q->ray.max_fraction);
}

static int kg_box_node(kg_aabb box, const void* ctx) { return kg_aabb_overlap(box, ((const kg_query*)ctx)->box); }

static kg_result kg_search(kg_query* q, kg_query_box_test* test, kg_query_leaf_fn* leaf)
{
    const kg_query_index* index = kg_query_index_current((kg_world*)q->world);
    if (!index) {
        return kg_last_result();
    }
    kg_query_index_search(index, test, q, leaf, q);
    return KG_OK;
}

/* Calls visit with every non-empty tile of the cells of the maps the filter sees that box
 * covers, map by map, layer by layer, row by row, until it returns 0. */
typedef int kg_tile_visit(kg_query* q, kg_tile_at at, KG_GLOBAL const kg_tile_proto* proto, kg_u32 word,
                          kg_vec2 corner);

static kg_vec2 kg_cell_corner(const kg_tile_map_info* m, int x, int y)
{
    return kg_v2(m->origin.x + (float)x * m->tile_size.x, m->origin.y + (float)y * m->tile_size.y);
}

/* Visits cell (x, y)'s tiles, every layer; 0 when visit stopped. */
static int kg_visit_cell(kg_query* q, const kg_tilemap_arrays* a, int map, int x, int y, kg_tile_visit* visit)
{
    const kg_tile_map_info* m = &a->maps[map];
    for (int layer = 0; layer < m->layer_count; ++layer) {
        kg_u32 word = a->cells[m->cell_offset + kg_tile_cell_index(m, layer, x, y)];
        KG_GLOBAL const kg_tile_proto* proto = &a->protos[m->proto_offset + kg_cell_id(word)];
        kg_tile_at at = {map, layer, x, y};
        if (proto->shape.count > 0 && !visit(q, at, proto, word, kg_cell_corner(m, x, y))) {
            return 0;
        }
    }
    return 1;
}

static void kg_tiles_in_box(kg_query* q, kg_aabb box, kg_tile_visit* visit)
{
    if (!q->world->tilemaps || q->stopped) {
        return;
    }
    kg_tilemap_arrays a;
    kg_tilemaps_arrays(q->world, &a);
    for (int map = 0; map < a.map_count; ++map) {
        const kg_tile_map_info* m = &a.maps[map];
        int x0, x1, y0, y1;
        if (!kg_sees_map(q, m) ||
            !kg_tile_span((box.lower.x - m->origin.x) / m->tile_size.x, (box.upper.x - m->origin.x) / m->tile_size.x,
                          m->width, &x0, &x1) ||
            !kg_tile_span((box.lower.y - m->origin.y) / m->tile_size.y, (box.upper.y - m->origin.y) / m->tile_size.y,
                          m->height, &y0, &y1)) {
            continue;
        }
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                if (!kg_visit_cell(q, &a, map, x, y, visit)) {
                    return;
                }
            }
        }
    }
}

/* The cells of map the ray crosses, in order along it (a grid walk, Amanatides and Woo),
 * until the ray's clip ends before the next one. */
static int kg_walk_map(kg_query* q, const kg_tilemap_arrays* a, int map, kg_tile_visit* visit)
{
    const kg_tile_map_info* m = &a->maps[map];
    kg_vec2 o = kg_v2((q->ray.origin.x - m->origin.x) / m->tile_size.x, (q->ray.origin.y - m->origin.y) / m->tile_size.y);
    kg_vec2 d = kg_v2(q->ray.translation.x / m->tile_size.x, q->ray.translation.y / m->tile_size.y);
    kg_vec2 inverse = kg_ray_inverse(d);
    float enter = 0.0f, leave = q->ray.max_fraction;
    if (!kg_ray_slab(0.0f, (float)m->width, o.x, inverse.x, &enter, &leave) ||
        !kg_ray_slab(0.0f, (float)m->height, o.y, inverse.y, &enter, &leave) || enter > leave) {
        return 1;
    }
    kg_vec2 start = kg_mul_add(o, enter, d);
    int x = (int)kg_clampf(floorf(start.x), 0.0f, (float)(m->width - 1));
    int y = (int)kg_clampf(floorf(start.y), 0.0f, (float)(m->height - 1));
    int step_x = inverse.x > 0.0f ? 1 : (inverse.x < 0.0f ? -1 : 0);
    int step_y = inverse.y > 0.0f ? 1 : (inverse.y < 0.0f ? -1 : 0);
    while (x >= 0 && x < m->width && y >= 0 && y < m->height) {
        if (!kg_visit_cell(q, a, map, x, y, visit)) {
            return 0;
        }
        /* where the ray leaves the cell across a column or a row line */
        float next_x = step_x ? ((float)(x + (step_x > 0)) - o.x) * inverse.x : KG_FLT_MAX;
        float next_y = step_y ? ((float)(y + (step_y > 0)) - o.y) * inverse.y : KG_FLT_MAX;
        if (kg_minf(next_x, next_y) > q->ray.max_fraction) {
            return 1;
        }
        if (next_x < next_y) {
            x += step_x;
        } else {
            y += step_y;
        }
    }
    return 1;
}

static void kg_tiles_along_ray(kg_query* q, kg_tile_visit* visit)
{
    if (!q->world->tilemaps || q->stopped) {
        return;
    }
    kg_tilemap_arrays a;
    kg_tilemaps_arrays(q->world, &a);
    for (int map = 0; map < a.map_count; ++map) {
        if (kg_sees_map(q, &a.maps[map]) && !kg_walk_map(q, &a, map, visit)) {
            return;
        }
    }
}

/* ---- ray casts ---- */

static int kg_ray_leaf(kg_u32 s, void* ctx)
{
    kg_query* q = (kg_query*)ctx;
    kg_u32 i = q->sp->body[s];
    if (!kg_sees_shape(q, s, i)) {
        return 1;
    }
    kg_xf xf = q->p->xf[i];
    kg_ray_hit h = kg_ray_shape(kg_shape_geometry(q->p, q->sp, s), kg_ray_in_frame(q->ray, xf));
    if (!h.hit) {
        return 1;
    }
    kg_vec2 point = kg_mul_add(q->ray.origin, h.fraction, q->ray.translation);
    kg_ray_result r = kg_body_result(q, s, h.fraction, point, kg_rotate(xf.q, h.normal));
    return kg_report_hit(q, &r);
}

static int kg_ray_tile_visit(kg_query* q, kg_tile_at at, KG_GLOBAL const kg_tile_proto* proto, kg_u32 word,
                             kg_vec2 corner)
{
    kg_ray ray = q->ray;
    ray.origin = kg_sub(ray.origin, corner);
    kg_ray_hit h = kg_ray_tile(proto, word, ray);
    if (!h.hit) {
        return 1;
    }
    kg_vec2 point = kg_mul_add(q->ray.origin, h.fraction, q->ray.translation);
    kg_ray_result r = kg_tile_result(q, at, h.fraction, point, h.normal);
    return kg_report_hit(q, &r);
}

static kg_result kg_check_ray(const kg_world* world, kg_vec2 origin, kg_vec2 translation, const void* out)
{
    if (!world || !out) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "ray cast: NULL world, result or callback");
    }
    if (!kg_vec_is_finite(origin) || !kg_vec_is_finite(translation)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "ray cast: origin (%g, %g) and translation (%g, %g) must be finite",
                       (double)origin.x, (double)origin.y, (double)translation.x, (double)translation.y);
    }
    return KG_OK;
}

kg_result kg_world_cast_ray(const kg_world* world, kg_vec2 origin, kg_vec2 translation, kg_query_filter filter,
                            kg_ray_fn* fn, void* ctx)
{
    KG_TRY(kg_check_ray(world, origin, translation, (const void*)fn));
    kg_query q = kg_start_query(world, filter);
    q.ray.origin = origin;
    q.ray.translation = translation;
    q.ray.max_fraction = 1.0f;
    q.inverse = kg_ray_inverse(translation);
    q.fn = fn;
    q.ctx = ctx;
    if (kg_length_sq(translation) == 0.0f) {
        return KG_OK; /* a ray of no length enters nothing */
    }
    KG_TRY(kg_search(&q, kg_ray_node, kg_ray_leaf));
    kg_tiles_along_ray(&q, kg_ray_tile_visit);
    return KG_OK;
}

kg_result kg_world_cast_ray_closest(const kg_world* world, kg_vec2 origin, kg_vec2 translation,
                                    kg_query_filter filter, kg_ray_result* out)
{
    KG_TRY(kg_check_ray(world, origin, translation, out));
    memset(out, 0, sizeof *out);
    return kg_world_cast_ray(world, origin, translation, filter, kg_keep_closest, out);
}

/* ---- shape casts ---- */

/* The fraction of the sweep at which the cast shape comes within KG_CAST_TOLERANCE of
 * other (at xf), above the clip when it does not before it. The search is asked to look
 * just past the clip, so that a hit exactly at it (a tie) is still found. */
static float kg_cast_toi(const kg_query* q, const kg_shape* other, kg_xf xf)
{
    kg_toi_params prm = {0.0f, KG_CAST_TOLERANCE};
    return kg_time_of_impact(q->moving, &q->sweep, other, xf, prm, nextafterf(q->ray.max_fraction, 2.0f));
}

/* The point of the cast shape at pose xf farthest along direction. */
static kg_vec2 kg_support(const kg_shape* shape, kg_xf xf, kg_vec2 direction)
{
    kg_vec2 best = kg_xf_point(xf, shape->vertices[0]);
    for (int i = 1; i < shape->count; ++i) {
        kg_vec2 v = kg_xf_point(xf, shape->vertices[i]);
        if (kg_dot(v, direction) > kg_dot(best, direction)) {
            best = v;
        }
    }
    return kg_mul_add(best, kg_round_radius(shape), direction);
}

/* The hit of the cast with other (at xf) at fraction t: the nearest point of the cast
 * shape, the normal from other towards it; against the translation for a cast that
 * starts overlapping. */
static kg_ray_result kg_cast_hit(const kg_query* q, const kg_shape* other, kg_xf xf, float t)
{
    kg_xf at = kg_sweep_xf(&q->sweep, t);
    kg_separation sep = kg_shape_distance(q->moving, at, other, xf);
    kg_vec2 towards = sep.distance >= 0.0f ? sep.normal : kg_normalize(q->ray.translation);
    if (kg_length_sq(towards) == 0.0f) {
        towards = kg_normalize(q->ray.translation);
    }
    kg_ray_result r;
    memset(&r, 0, sizeof r);
    r.hit = 1;
    r.point = kg_support(q->moving, at, towards);
    r.normal = kg_neg(towards);
    r.fraction = t;
    return r;
}

static int kg_cast_leaf(kg_u32 s, void* ctx)
{
    kg_query* q = (kg_query*)ctx;
    kg_u32 i = q->sp->body[s];
    if (!kg_sees_shape(q, s, i)) {
        return 1;
    }
    const kg_shape* other = kg_shape_geometry(q->p, q->sp, s);
    float t = kg_cast_toi(q, other, q->p->xf[i]);
    if (!(t <= q->ray.max_fraction)) {
        return 1;
    }
    kg_ray_result r = kg_cast_hit(q, other, q->p->xf[i], t);
    kg_name_body(q, s, i, &r.body, &r.shape, &r.user_data);
    return kg_report_hit(q, &r);
}

/* A tile's shape sits at its cell's corner, unturned. */
static kg_xf kg_tile_xf(kg_vec2 corner)
{
    kg_xf xf;
    xf.p = corner;
    xf.q = kg_rot_identity();
    return xf;
}

/* A one-way tile stops a cast only where the cast comes down onto an upward face (the
 * normal the collision's exposed edges have: kg_tile_template, collide/tilemap.c). */
static int kg_cast_tile_visit(kg_query* q, kg_tile_at at, KG_GLOBAL const kg_tile_proto* proto, kg_u32 word,
                              kg_vec2 corner)
{
    (void)word;
    KG_PRIVATE_VIEW(kg_shape, shape, proto->shape);
    kg_xf xf = kg_tile_xf(corner);
    float t = kg_cast_toi(q, shape, xf);
    if (!(t <= q->ray.max_fraction)) {
        return 1;
    }
    kg_ray_result r = kg_cast_hit(q, shape, xf, t);
    if ((proto->flags & KG_TILE_FLAG_ONE_WAY) && !(t > 0.0f && r.normal.y > KG_TILE_ANGLE_TOLERANCE)) {
        return 1;
    }
    kg_ray_result tile = kg_tile_result(q, at, r.fraction, r.point, r.normal);
    return kg_report_hit(q, &tile);
}

/* Sweeps moving (at xf) along translation through the index and the tiles. */
static kg_result kg_run_cast(kg_query* q, const kg_shape* moving, kg_xf xf, kg_vec2 translation)
{
    q->moving = moving;
    q->sweep.local_center = kg_v2(0.0f, 0.0f);
    q->sweep.c1 = xf.p;
    q->sweep.c2 = kg_add(xf.p, translation);
    q->sweep.q1 = xf.q;
    q->sweep.q2 = xf.q;
    q->sweep.max_extent = 0.0f; /* it does not turn */
    kg_aabb start = kg_shape_aabb(moving, xf);
    float grow = KG_QUERY_MARGIN + KG_CAST_TOLERANCE;
    q->ray.origin = kg_scale(0.5f, kg_add(start.lower, start.upper));
    q->ray.translation = translation;
    q->reach = kg_add(kg_scale(0.5f, kg_sub(start.upper, start.lower)), kg_v2(grow, grow));
    q->inverse = kg_ray_inverse(translation);
    KG_TRY(kg_search(q, kg_ray_node, kg_cast_leaf));
    kg_tiles_in_box(q, kg_aabb_fatten(kg_aabb_sweep(start, translation), grow), kg_cast_tile_visit);
    return KG_OK;
}

/* The collision shape of a query's shape definition at position and angle. */
static kg_result kg_query_shape(const kg_shape_def* def, kg_vec2 position, float angle, kg_shape* shape, kg_xf* xf)
{
    if (!def) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "query: NULL shape");
    }
    if (def->type == KG_SHAPE_NONE) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "query: a shape of type NONE has nothing to test");
    }
    if (!kg_vec_is_finite(position) || !kg_is_finite(angle)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "query: position and angle must be finite");
    }
    KG_TRY(kg_shape_build(def, shape));
    xf->p = position;
    xf->q.c = cosf(angle);
    xf->q.s = sinf(angle);
    return KG_OK;
}

kg_result kg_world_cast_shape(const kg_world* world, const kg_shape_def* shape, kg_vec2 position, float angle,
                              kg_vec2 translation, kg_query_filter filter, kg_ray_fn* fn, void* ctx)
{
    KG_TRY(kg_check_ray(world, position, translation, (const void*)fn));
    kg_shape moving;
    kg_xf xf = {{0.0f, 0.0f}, {1.0f, 0.0f}}; /* set by kg_query_shape; gcc cannot tell */
    KG_TRY(kg_query_shape(shape, position, angle, &moving, &xf));
    kg_query q = kg_start_query(world, filter);
    q.ray.max_fraction = 1.0f;
    q.fn = fn;
    q.ctx = ctx;
    return kg_run_cast(&q, &moving, xf, translation);
}

kg_result kg_world_cast_shape_closest(const kg_world* world, const kg_shape_def* shape, kg_vec2 position, float angle,
                                      kg_vec2 translation, kg_query_filter filter, kg_ray_result* out)
{
    KG_TRY(kg_check_ray(world, position, translation, out));
    memset(out, 0, sizeof *out);
    return kg_world_cast_shape(world, shape, position, angle, translation, filter, kg_keep_closest, out);
}

kg_result kg_world_cast_body_closest(const kg_world* world, kg_body body, kg_vec2 translation, kg_query_filter filter,
                                     kg_ray_result* out)
{
    KG_TRY(kg_check_ray(world, kg_v2(0.0f, 0.0f), translation, out));
    memset(out, 0, sizeof *out);
    int i = kg_world_resolve(world, body);
    if (i < 0) {
        return kg_last_result();
    }
    kg_query q = kg_start_query(world, filter);
    q.skip_body = (kg_u32)i;
    q.ray.max_fraction = 1.0f;
    q.fn = kg_keep_closest;
    q.ctx = out;
    for (kg_u32 s = q.p->first_shape[i]; s != KG_NULL_INDEX && !q.stopped; s = q.sp->next[s]) {
        KG_TRY(kg_run_cast(&q, kg_shape_geometry(q.p, q.sp, s), q.p->xf[i], translation));
    }
    return KG_OK;
}

/* ---- overlaps ---- */

static int kg_overlaps(const kg_query* q, const kg_shape* other, kg_xf xf)
{
    switch (q->kind) {
    case KG_OVERLAP_BOX:
        return kg_aabb_overlap(kg_shape_aabb(other, xf), q->box);
    case KG_OVERLAP_POINT:
        return kg_shape_holds_point(other, kg_xf_inv_point(xf, q->point));
    default:
        return kg_shape_distance(q->moving, q->xf, other, xf).distance <= 0.0f;
    }
}

static int kg_overlap_leaf(kg_u32 s, void* ctx)
{
    kg_query* q = (kg_query*)ctx;
    kg_u32 i = q->sp->body[s];
    if (!kg_sees_shape(q, s, i) || !kg_overlaps(q, kg_shape_geometry(q->p, q->sp, s), q->p->xf[i])) {
        return 1;
    }
    kg_overlap_result r;
    memset(&r, 0, sizeof r);
    kg_name_body(q, s, i, &r.body, &r.shape, &r.user_data);
    q->stopped = !q->found(&r, q->ctx);
    return !q->stopped;
}

static int kg_overlap_tile_visit(kg_query* q, kg_tile_at at, KG_GLOBAL const kg_tile_proto* proto, kg_u32 word,
                                 kg_vec2 corner)
{
    (void)word;
    KG_PRIVATE_VIEW(kg_shape, shape, proto->shape);
    kg_xf xf = kg_tile_xf(corner);
    if (!kg_overlaps(q, shape, xf)) {
        return 1;
    }
    kg_overlap_result r;
    memset(&r, 0, sizeof r);
    kg_name_tile(q, at, &r.map, &r.user_data);
    r.layer = at.layer;
    r.x = at.x;
    r.y = at.y;
    q->stopped = !q->found(&r, q->ctx);
    return !q->stopped;
}

static kg_result kg_run_overlap(kg_query* q, kg_overlap_result_fn* fn, void* ctx)
{
    q->found = fn;
    q->ctx = ctx;
    KG_TRY(kg_search(q, kg_box_node, kg_overlap_leaf));
    kg_tiles_in_box(q, q->box, kg_overlap_tile_visit);
    return KG_OK;
}

static kg_result kg_check_overlap(const kg_world* world, const void* fn)
{
    return world && fn ? KG_OK : kg_fail(KG_ERROR_INVALID_ARGUMENT, "overlap query: NULL world or callback");
}

kg_result kg_world_overlap_aabb_results(const kg_world* world, kg_aabb box, kg_query_filter filter,
                                        kg_overlap_result_fn* fn, void* ctx)
{
    KG_TRY(kg_check_overlap(world, (const void*)fn));
    if (!kg_vec_is_finite(box.lower) || !kg_vec_is_finite(box.upper) || box.lower.x > box.upper.x ||
        box.lower.y > box.upper.y) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "overlap query: the box must be finite, lower <= upper");
    }
    kg_query q = kg_start_query(world, filter);
    q.kind = KG_OVERLAP_BOX;
    q.box = box;
    return kg_run_overlap(&q, fn, ctx);
}

kg_result kg_world_overlap_point_results(const kg_world* world, kg_vec2 point, kg_query_filter filter,
                                         kg_overlap_result_fn* fn, void* ctx)
{
    KG_TRY(kg_check_overlap(world, (const void*)fn));
    if (!kg_vec_is_finite(point)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "overlap query: the point must be finite");
    }
    kg_query q = kg_start_query(world, filter);
    q.kind = KG_OVERLAP_POINT;
    q.point = point;
    q.box.lower = point;
    q.box.upper = point;
    return kg_run_overlap(&q, fn, ctx);
}

kg_result kg_world_overlap_shape_results(const kg_world* world, const kg_shape_def* shape, kg_vec2 position,
                                         float angle, kg_query_filter filter, kg_overlap_result_fn* fn, void* ctx)
{
    KG_TRY(kg_check_overlap(world, (const void*)fn));
    kg_shape moving;
    kg_query q = kg_start_query(world, filter);
    KG_TRY(kg_query_shape(shape, position, angle, &moving, &q.xf));
    q.kind = KG_OVERLAP_SHAPE;
    q.moving = &moving;
    q.box = kg_shape_aabb(&moving, q.xf);
    return kg_run_overlap(&q, fn, ctx);
}

kg_result kg_overlap_of_shape(const kg_world* world, kg_u32 s, kg_query_filter filter, kg_overlap_result_fn* fn,
                              void* ctx)
{
    kg_query q = kg_start_query(world, filter);
    kg_u32 i = q.sp->body[s];
    q.skip_body = i;
    q.kind = KG_OVERLAP_SHAPE;
    q.moving = kg_shape_geometry(q.p, q.sp, s);
    q.xf = q.p->xf[i];
    q.box = kg_shape_aabb(q.moving, q.xf);
    return kg_run_overlap(&q, fn, ctx);
}

/* The plain callbacks, through the full results. */
typedef struct kg_plain_overlap {
    kg_overlap_fn* fn;
    void* ctx;
} kg_plain_overlap;

static int kg_call_plain(const kg_overlap_result* found, void* ctx)
{
    const kg_plain_overlap* plain = (const kg_plain_overlap*)ctx;
    return plain->fn(found->body, found->shape, found->user_data, plain->ctx);
}

kg_result kg_world_overlap_aabb(const kg_world* world, kg_aabb box, kg_query_filter filter, kg_overlap_fn* fn,
                                void* ctx)
{
    kg_plain_overlap plain = {fn, ctx};
    return kg_world_overlap_aabb_results(world, box, filter, fn ? kg_call_plain : NULL, &plain);
}

kg_result kg_world_overlap_point(const kg_world* world, kg_vec2 point, kg_query_filter filter, kg_overlap_fn* fn,
                                 void* ctx)
{
    kg_plain_overlap plain = {fn, ctx};
    return kg_world_overlap_point_results(world, point, filter, fn ? kg_call_plain : NULL, &plain);
}

kg_result kg_world_overlap_shape(const kg_world* world, const kg_shape_def* shape, kg_vec2 position, float angle,
                                 kg_query_filter filter, kg_overlap_fn* fn, void* ctx)
{
    kg_plain_overlap plain = {fn, ctx};
    return kg_world_overlap_shape_results(world, shape, position, angle, filter, fn ? kg_call_plain : NULL, &plain);
}
