/* World queries (kgyro/query.h): ray casts against every shape kind and tile shape,
 * checked against analytic hits (point within 1e-5 m, normal within 1e-5), then the index
 * against brute-force scans of every shape written here (10,000 random rays in a world of
 * 10,000 random bodies: the same shape, the same bits), overlaps and shape casts the same
 * way, the callback's clipping, bad input, and the OpenCL backend (PoCL) against the CPU. */
#include "kg_test.h"
#include "kg_test_world.h"
#include "kg_twin.h"
#include "kgyro/kgyro.h"
#include "kgyro/opencl.h"
#include "collide/raycast.h"
#include "collide/shape.h"
#include "core/world.h"

#include <stdint.h>
#include <string.h>

#define KG_TOL 1.0e-5

static int kg_note(kg_body body, kg_shape_id shape, void* user_data, void* ctx);

static kg_world* kg_new_world(int max_bodies, kg_backend backend)
{
    kg_world_def def = kg_default_world_def();
    def.max_bodies = max_bodies;
    def.backend = backend;
    def.device_index = kg_test_opencl_device();
    kg_world* world = NULL;
    return kg_create_world(&def, &world) == KG_OK ? world : NULL;
}

/* Compared without the world's tag: hits in twin worlds are compared too (kg_twin.h). */
static int kg_same_body(kg_body a, kg_body b)
{
    return a.index == b.index && kg_untagged_body(a).generation == kg_untagged_body(b).generation;
}

/* Casts the ray and checks the hit against the analytic point and normal. */
static kg_ray_result kg_expect_hit(kg_world* world, kg_vec2 origin, kg_vec2 translation, double px, double py,
                                   double nx, double ny)
{
    kg_ray_result r;
    KG_CHECK_OK(kg_world_cast_ray_closest(world, origin, translation, kg_default_query_filter(), &r));
    KG_CHECK(r.hit);
    KG_CHECK_NEAR(r.point.x, px, KG_TOL);
    KG_CHECK_NEAR(r.point.y, py, KG_TOL);
    KG_CHECK_NEAR(r.normal.x, nx, KG_TOL);
    KG_CHECK_NEAR(r.normal.y, ny, KG_TOL);
    double length2 = (double)translation.x * translation.x + (double)translation.y * translation.y;
    double along = ((px - origin.x) * translation.x + (py - origin.y) * translation.y) / length2;
    KG_CHECK_NEAR(r.fraction, along, KG_TOL);
    return r;
}

static void test_ray_circle_and_polygon(void)
{
    kg_world* world = kg_new_world(64, KG_BACKEND_CPU);
    kg_body ball = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){3.0f, 1.0f}, 0.0f, kg_circle_shape(0.5f));
    kg_ray_result r = kg_expect_hit(world, (kg_vec2){0.0f, 1.2f}, (kg_vec2){10.0f, 0.0f}, 3.0 - sqrt(0.25 - 0.04), 1.2,
                                    -sqrt(0.25 - 0.04) / 0.5, 0.2 / 0.5);
    KG_CHECK(kg_same_body(r.body, ball));
    /* a box turned by 30 degrees: the ray along y = 10.2 from the left meets its lower-left
     * face, whose outward normal is (-sin 60, -cos 60) turned... solved here in double */
    float angle = 0.5235988f;
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){10.0f, 10.0f}, angle, kg_box_shape(2.0f, 1.0f));
    double c = cos((double)angle), s = sin((double)angle);
    /* the box's faces in the world: centre + t * axis; the ray y = 10.2 enters by the face
     * with the largest entering t among those facing against +x */
    double best_t = -1e9, bnx = 0, bny = 0;
    double axes[4][2] = {{c, s}, {-c, -s}, {-s, c}, {s, -c}}; /* normals: +x, -x, +y, -y of the box */
    double half[4] = {1.0, 1.0, 0.5, 0.5};
    for (int k = 0; k < 4; ++k) {
        double nx = axes[k][0], ny = axes[k][1];
        if (nx < 0.0) { /* faces the ray (direction +x) */
            /* n . (p - centre) = half, p = (x, 10.2) */
            double x = 10.0 + (half[k] - ny * 0.2) / nx;
            if (x > best_t) {
                best_t = x;
                bnx = nx;
                bny = ny;
            }
        }
    }
    kg_expect_hit(world, (kg_vec2){6.0f, 10.2f}, (kg_vec2){8.0f, 0.0f}, best_t, 10.2, bnx, bny);
    /* a triangle, hit on its slanted face from above */
    const kg_vec2 tri[3] = {{0.0f, 0.0f}, {2.0f, 0.0f}, {0.0f, 2.0f}};
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){20.0f, 0.0f}, 0.0f, kg_polygon_shape(tri, 3));
    kg_expect_hit(world, (kg_vec2){20.5f, 5.0f}, (kg_vec2){0.0f, -10.0f}, 20.5, 1.5, sqrt(0.5), sqrt(0.5));
    kg_destroy_world(world);
}

static void test_ray_capsule_and_segments(void)
{
    kg_world* world = kg_new_world(64, KG_BACKEND_CPU);
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, 5.0f}, 0.0f,
           kg_capsule_shape((kg_vec2){-1.0f, 0.0f}, (kg_vec2){1.0f, 0.0f}, 0.5f));
    kg_expect_hit(world, (kg_vec2){0.3f, 10.0f}, (kg_vec2){0.0f, -10.0f}, 0.3, 5.5, 0.0, 1.0);   /* flat side */
    kg_expect_hit(world, (kg_vec2){-5.0f, 5.2f}, (kg_vec2){10.0f, 0.0f}, -1.0 - sqrt(0.25 - 0.04), 5.2,
                  -sqrt(0.25 - 0.04) / 0.5, 0.4); /* round end */
    /* the same capsule turned upright */
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){10.0f, 5.0f}, 1.5707964f,
           kg_capsule_shape((kg_vec2){-1.0f, 0.0f}, (kg_vec2){1.0f, 0.0f}, 0.5f));
    kg_expect_hit(world, (kg_vec2){5.0f, 5.3f}, (kg_vec2){10.0f, 0.0f}, 9.5, 5.3, -1.0, 0.0);
    /* a two-sided segment: from below and from above */
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, -5.0f}, 0.0f, kg_segment_shape((kg_vec2){-2.0f, 0.0f}, (kg_vec2){2.0f, 0.0f}));
    kg_expect_hit(world, (kg_vec2){0.5f, -8.0f}, (kg_vec2){0.0f, 4.0f}, 0.5, -5.0, 0.0, -1.0);
    kg_expect_hit(world, (kg_vec2){0.5f, -2.0f}, (kg_vec2){0.0f, -4.0f}, 0.5, -5.0, 0.0, 1.0);
    /* a chain ground listed right to left (normal up): solid from above only */
    kg_body_def d = kg_default_body_def();
    d.type = KG_BODY_STATIC;
    d.position = (kg_vec2){0.0f, -20.0f};
    kg_body ground;
    KG_CHECK_OK(kg_create_body(world, &d, &ground));
    const kg_vec2 pts[3] = {{4.0f, 0.0f}, {0.0f, 0.0f}, {-4.0f, 1.0f}};
    kg_chain_def chain = kg_default_chain_def();
    chain.points = pts;
    chain.count = 3;
    KG_CHECK_OK(kg_create_chain(world, ground, &chain, NULL));
    kg_ray_result r = kg_expect_hit(world, (kg_vec2){1.0f, -17.0f}, (kg_vec2){0.0f, -6.0f}, 1.0, -20.0, 0.0, 1.0);
    KG_CHECK(kg_same_body(r.body, ground));
    /* the slanted segment from above: normal (-1, -4)/sqrt(17) turned right of (-8, 1)... */
    double len = sqrt(17.0);
    kg_expect_hit(world, (kg_vec2){-2.0f, -15.0f}, (kg_vec2){0.0f, -10.0f}, -2.0, -19.5, 1.0 / len, 4.0 / len);
    KG_CHECK_OK(kg_world_cast_ray_closest(world, (kg_vec2){1.0f, -23.0f}, (kg_vec2){0.0f, 6.0f},
                                          kg_default_query_filter(), &r));
    KG_CHECK(!r.hit); /* from behind, a chain lets the ray through */
    kg_destroy_world(world);
}

static void test_ray_grazing_inside_rotated(void)
{
    kg_world* world = kg_new_world(64, KG_BACKEND_CPU);
    kg_body a = kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, 0.0f}, 0.0f, kg_box_shape(1.0f, 1.0f));
    kg_body b = kg_test_add(world, KG_BODY_STATIC, (kg_vec2){4.0f, 0.0f}, 0.0f, kg_box_shape(1.0f, 1.0f));
    /* along the top face of a: it enters a by its left side at the corner */
    kg_ray_result r = kg_expect_hit(world, (kg_vec2){-5.0f, 0.5f}, (kg_vec2){20.0f, 0.0f}, -0.5, 0.5, -1.0, 0.0);
    KG_CHECK(kg_same_body(r.body, a));
    /* a grazing ray, 1 in 1024 (numbers exact in floats: at such an angle an error in the
     * origin's height moves the hit 1024 times as far), onto the top face of b */
    kg_expect_hit(world, (kg_vec2){2.0f, 0.501953125f}, (kg_vec2){8.0f, -0.0078125f}, 4.0, 0.5, 0.0, 1.0);
    /* from inside a: a is not hit, b is */
    r = kg_expect_hit(world, (kg_vec2){0.1f, 0.1f}, (kg_vec2){10.0f, 0.0f}, 3.5, 0.1, -1.0, 0.0);
    KG_CHECK(kg_same_body(r.body, b));
    /* a rotated, after a step of a moved body: the index follows the world */
    KG_CHECK_OK(kg_body_set_transform(world, a, (kg_vec2){0.0f, 3.0f}, 0.7853982f));
    double h = sqrt(0.5);
    kg_expect_hit(world, (kg_vec2){0.1f, 10.0f}, (kg_vec2){0.0f, -20.0f}, 0.1, 3.0 + h - 0.1, h, h);
    KG_CHECK_OK(kg_destroy_body(world, b));
    KG_CHECK_OK(kg_world_cast_ray_closest(world, (kg_vec2){2.5f, 0.0f}, (kg_vec2){10.0f, 0.0f},
                                          kg_default_query_filter(), &r));
    KG_CHECK(!r.hit);
    kg_destroy_world(world);
}

static void test_ray_tiles(void)
{
    kg_world* world = kg_new_world(16, KG_BACKEND_CPU);
    kg_tile_shape shapes[4] = {kg_tile_empty(), kg_tile_box(), kg_tile_slope(KG_TILE_BOTTOM_RIGHT), kg_tile_platform()};
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = 16;
    def.height = 8;
    def.origin = (kg_vec2){-4.0f, -2.0f};
    def.tile_size = (kg_vec2){0.5f, 0.5f};
    def.shapes = shapes;
    def.shape_count = 4;
    int dummy = 7;
    def.user_data = &dummy;
    kg_tilemap map;
    KG_CHECK_OK(kg_create_tilemap(world, &def, &map));
    for (int x = 0; x < 16; ++x) {
        KG_CHECK_OK(kg_tilemap_set_tile(world, map, 0, x, 0, 1)); /* a floor */
    }
    KG_CHECK_OK(kg_tilemap_set_tile(world, map, 0, 4, 1, 2));  /* a slope on it */
    KG_CHECK_OK(kg_tilemap_set_tile(world, map, 0, 10, 4, 3)); /* a platform in the air */
    /* the floor's top: y = -2 + 0.5 = -1.5 */
    kg_ray_result r = kg_expect_hit(world, (kg_vec2){0.3f, 3.0f}, (kg_vec2){0.0f, -10.0f}, 0.3, -1.5, 0.0, 1.0);
    KG_CHECK(r.map.index == map.index && r.map.generation == map.generation && r.x == 8 && r.y == 0 && r.layer == 0);
    KG_CHECK(r.user_data == &dummy && r.body.generation == 0u);
    /* the slope of cell (4, 1): x in [-2, -1.5], rising to the right from y = -1.5 */
    r = kg_expect_hit(world, (kg_vec2){-1.6f, 3.0f}, (kg_vec2){0.0f, -10.0f}, -1.6, -1.5 + 0.4, -sqrt(0.5), sqrt(0.5));
    KG_CHECK(r.x == 4 && r.y == 1);
    /* a diagonal ray onto the floor, walking many cells */
    kg_expect_hit(world, (kg_vec2){-3.9f, 1.9f}, (kg_vec2){6.0f, -6.0f}, -3.9 + 3.4, -1.5, 0.0, 1.0);
    /* the platform of cell (10, 4): x in [1, 1.5], its top half y in [0.25, 0.5] */
    r = kg_expect_hit(world, (kg_vec2){1.2f, 3.0f}, (kg_vec2){0.0f, -4.0f}, 1.2, 0.5, 0.0, 1.0);
    KG_CHECK(r.x == 10 && r.y == 4);
    /* from below the ray passes through the platform and stops on nothing above */
    KG_CHECK_OK(kg_world_cast_ray_closest(world, (kg_vec2){1.2f, -1.0f}, (kg_vec2){0.0f, 3.0f},
                                          kg_default_query_filter(), &r));
    KG_CHECK(!r.hit);
    /* from inside the floor: no tile of it is entered */
    KG_CHECK_OK(kg_world_cast_ray_closest(world, (kg_vec2){-3.9f, -1.8f}, (kg_vec2){7.0f, 0.0f},
                                          kg_default_query_filter(), &r));
    KG_CHECK(!r.hit);
    /* along the floor from its left side, outside the map: enters its left face */
    kg_expect_hit(world, (kg_vec2){-6.0f, -1.8f}, (kg_vec2){4.0f, 0.0f}, -4.0, -1.8, -1.0, 0.0);
    /* filtered out, and skipped */
    kg_query_filter filter = kg_default_query_filter();
    filter.flags = KG_QUERY_SKIP_TILES;
    KG_CHECK_OK(kg_world_cast_ray_closest(world, (kg_vec2){0.3f, 3.0f}, (kg_vec2){0.0f, -10.0f}, filter, &r));
    KG_CHECK(!r.hit);
    filter = kg_default_query_filter();
    filter.mask = 2u; /* the map's category is 1 */
    KG_CHECK_OK(kg_world_cast_ray_closest(world, (kg_vec2){0.3f, 3.0f}, (kg_vec2){0.0f, -10.0f}, filter, &r));
    KG_CHECK(!r.hit);
    kg_destroy_world(world);
}

/* ---- callbacks ---- */

typedef struct kg_hits {
    int count;
    float answer; /* < 0: return the hit's fraction */
    float fractions[16];
} kg_hits;

static float kg_collect(const kg_ray_result* hit, void* ctx)
{
    kg_hits* h = (kg_hits*)ctx;
    if (h->count < 16) {
        h->fractions[h->count] = hit->fraction;
    }
    h->count++;
    return h->answer < 0.0f ? hit->fraction : h->answer;
}

static void test_ray_callback_clips(void)
{
    kg_world* world = kg_new_world(64, KG_BACKEND_CPU);
    for (int i = 0; i < 5; ++i) {
        kg_test_add(world, KG_BODY_STATIC, (kg_vec2){2.0f + 2.0f * (float)i, 0.0f}, 0.0f, kg_box_shape(1.0f, 1.0f));
    }
    kg_vec2 o = {0.0f, 0.0f}, t = {20.0f, 0.0f};
    kg_hits all = {0, 1.0f, {0}};
    KG_CHECK_OK(kg_world_cast_ray(world, o, t, kg_default_query_filter(), kg_collect, &all));
    KG_CHECK(all.count == 5);
    kg_hits first = {0, 0.0f, {0}};
    KG_CHECK_OK(kg_world_cast_ray(world, o, t, kg_default_query_filter(), kg_collect, &first));
    KG_CHECK(first.count == 1);
    kg_hits ignore = {0, -1.0f, {0}}; /* clipping to each hit: never more than all, the last the nearest */
    KG_CHECK_OK(kg_world_cast_ray(world, o, t, kg_default_query_filter(), kg_collect, &ignore));
    KG_CHECK(ignore.count >= 1 && ignore.count <= 5);
    KG_CHECK_NEAR(ignore.fractions[ignore.count - 1], 1.5 / 20.0, KG_TOL);
    kg_destroy_world(world);
}

static void test_bad_input(void)
{
    kg_world* world = kg_new_world(16, KG_BACKEND_CPU);
    kg_ray_result r;
    kg_query_filter f = kg_default_query_filter();
    kg_vec2 o = {0.0f, 0.0f}, t = {1.0f, 0.0f};
    KG_CHECK(kg_world_cast_ray_closest(NULL, o, t, f, &r) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_cast_ray_closest(world, o, t, f, NULL) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_cast_ray(world, o, t, f, NULL, NULL) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_cast_ray_closest(world, (kg_vec2){NAN, 0.0f}, t, f, &r) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_cast_ray_closest(world, o, (kg_vec2){INFINITY, 0.0f}, f, &r) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK_OK(kg_world_cast_ray_closest(world, o, (kg_vec2){0.0f, 0.0f}, f, &r));
    KG_CHECK(!r.hit);
    kg_vec2 two[2] = {{0.0f, 0.0f}, {1.0f, 0.0f}};
    kg_shape_def flat = kg_polygon_shape(two, 2);
    KG_CHECK(kg_world_cast_shape_closest(world, &flat, o, 0.0f, t, f, &r) == KG_ERROR_DEGENERATE_SHAPE);
    kg_shape_def none = kg_circle_shape(1.0f);
    none.type = KG_SHAPE_NONE;
    KG_CHECK(kg_world_cast_shape_closest(world, &none, o, 0.0f, t, f, &r) == KG_ERROR_INVALID_ARGUMENT);
    kg_shape_def ball = kg_circle_shape(1.0f);
    KG_CHECK(kg_world_cast_shape_closest(world, &ball, o, NAN, t, f, &r) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_cast_shape_closest(world, NULL, o, 0.0f, t, f, &r) == KG_ERROR_INVALID_ARGUMENT);
    kg_aabb inverted = {{1.0f, 1.0f}, {0.0f, 0.0f}};
    KG_CHECK(kg_world_overlap_aabb(world, inverted, f, NULL, NULL) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_overlap_point(world, (kg_vec2){0.0f, NAN}, f, NULL, NULL) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_overlap_shape(world, &flat, o, 0.0f, f, kg_note, NULL) == KG_ERROR_DEGENERATE_SHAPE);
    kg_body stale = {3u, 1u};
    KG_CHECK(kg_world_cast_body_closest(world, stale, t, f, &r) == KG_ERROR_INVALID_HANDLE);
    kg_destroy_world(world);
}

/* ---- the index against brute force ---- */

static uint32_t g_seed = 12345u;
static float kg_rand(float lo, float hi)
{
    g_seed = g_seed * 1664525u + 1013904223u;
    return lo + (hi - lo) * (float)(g_seed >> 8) * (1.0f / 16777216.0f);
}

static kg_shape_def kg_random_shape(void)
{
    int kind = (int)kg_rand(0.0f, 4.0f);
    float a = kg_rand(0.2f, 1.5f), b = kg_rand(0.2f, 1.5f);
    if (kind == 0) {
        return kg_circle_shape(a);
    }
    if (kind == 1) {
        return kg_box_shape(a, b);
    }
    if (kind == 2) {
        return kg_capsule_shape((kg_vec2){-a, 0.0f}, (kg_vec2){a, 0.0f}, 0.3f * b);
    }
    const kg_vec2 tri[3] = {{-a, -b}, {a, -0.5f * b}, {0.0f, b}};
    return kg_polygon_shape(tri, 3);
}

#define KG_SIDE 400.0f

/* n random bodies of every kind in [0, KG_SIDE]^2, every 40th compound, a chain. */
static kg_world* kg_random_world(int n, kg_backend backend)
{
    kg_world* world = kg_new_world(n + 8, backend);
    if (!world) {
        return NULL;
    }
    g_seed = 777u;
    for (int i = 0; i < n; ++i) {
        kg_body_def def = kg_default_body_def();
        int k = (int)kg_rand(0.0f, 10.0f);
        def.type = k < 3 ? KG_BODY_STATIC : (k < 4 ? KG_BODY_KINEMATIC : KG_BODY_DYNAMIC);
        def.position = (kg_vec2){kg_rand(0.0f, KG_SIDE), kg_rand(0.0f, KG_SIDE)};
        def.angle = kg_rand(-3.1f, 3.1f);
        def.shape = kg_random_shape();
        def.category = 1u << (int)kg_rand(0.0f, 3.0f);
        kg_body body;
        KG_CHECK_OK(kg_create_body(world, &def, &body));
        if (i % 40 == 0) {
            kg_body_shape_def extra = kg_default_body_shape_def();
            extra.geometry = kg_shape_moved(kg_random_shape(), (kg_vec2){kg_rand(-2.0f, 2.0f), kg_rand(-2.0f, 2.0f)}, 0.3f);
            extra.is_sensor = i % 80 == 0;
            kg_shape_id extra_id;
            KG_CHECK_OK(kg_create_shape(world, body, &extra, &extra_id));
        }
    }
    kg_body_def d = kg_default_body_def();
    d.type = KG_BODY_STATIC;
    kg_body ground;
    KG_CHECK_OK(kg_create_body(world, &d, &ground));
    kg_vec2 hills[41];
    for (int i = 0; i <= 40; ++i) {
        hills[i] = (kg_vec2){KG_SIDE - 10.0f * (float)i, 50.0f + 5.0f * sinf(0.5f * (float)i)};
    }
    kg_chain_def chain = kg_default_chain_def();
    chain.points = hills;
    chain.count = 41;
    KG_CHECK_OK(kg_create_chain(world, ground, &chain, NULL));
    return world;
}

static int kg_brute_sees(const kg_world* world, kg_query_filter f, kg_u32 s)
{
    const kg_shape_pool* sp = &world->shapes;
    return (f.category & sp->mask[s]) && (sp->category[s] & f.mask) &&
           !((f.flags & KG_QUERY_SKIP_SENSORS) && (sp->flags[s] & KG_SHAPE_SENSOR));
}

/* Every live shape, in slot order, with its body's transform. */
#define KG_FOR_EACH_SHAPE(world, s, i, xf, shape)                                                   \
    for (kg_u32 s = 0; s < (kg_u32)(world)->shapes.high_water; ++s)                                 \
        for (kg_u32 i = (world)->shapes.body[s], once_ = kg_shape_alive(&(world)->shapes, (int)s); once_; once_ = 0) \
            for (kg_xf xf = (world)->bodies.xf[i]; once_; once_ = 0)                                 \
                for (const kg_shape* shape = kg_shape_geometry(&(world)->bodies, &(world)->shapes, s); once_; once_ = 0)

/* Each shape slot's bounds (kg_shape_aabb), for the scans to skip what a ray cannot reach:
 * made by kg_note_bounds, when the world is as the scans see it. */
static kg_aabb g_bounds[16384];

static void kg_note_bounds(const kg_world* world)
{
    KG_FOR_EACH_SHAPE(world, s, i, xf, shape) {
        g_bounds[s] = kg_shape_aabb(shape, xf);
    }
}

static kg_ray_result kg_brute_ray(const kg_world* world, kg_vec2 o, kg_vec2 t, kg_query_filter f)
{
    kg_ray_result best;
    memset(&best, 0, sizeof best);
    kg_ray ray = {o, t, 1.0f};
    /* the segment's bounds, a centimetre wider: a shape whose bounds miss them cannot be hit
     * (which only saves the scan time, as the index is not asked) */
    kg_aabb reach = {{fminf(o.x, o.x + t.x) - 0.01f, fminf(o.y, o.y + t.y) - 0.01f},
                     {fmaxf(o.x, o.x + t.x) + 0.01f, fmaxf(o.y, o.y + t.y) + 0.01f}};
    KG_FOR_EACH_SHAPE(world, s, i, xf, shape) {
        if (!kg_brute_sees(world, f, s) || !kg_aabb_overlap(reach, g_bounds[s])) {
            continue;
        }
        kg_ray_hit h = kg_ray_shape(shape, kg_ray_in_frame(ray, xf));
        if (h.hit && (!best.hit || h.fraction < best.fraction)) {
            best.hit = 1;
            best.fraction = h.fraction;
            best.point = kg_mul_add(o, h.fraction, t);
            best.normal = kg_rotate(xf.q, h.normal);
            best.body.index = i;
            best.body.generation = world->bodies.generation[i];
            best.shape.index = s;
            best.shape.generation = world->shapes.generation[s];
        }
    }
    return best;
}

static int kg_same_hit(const kg_ray_result* a, const kg_ray_result* b)
{
    if (a->hit != b->hit) {
        return 0;
    }
    return !a->hit || (kg_same_body(a->body, b->body) && a->shape.index == b->shape.index &&
                       memcmp(&a->fraction, &b->fraction, sizeof a->fraction) == 0 &&
                       memcmp(&a->point, &b->point, sizeof a->point) == 0 &&
                       memcmp(&a->normal, &b->normal, sizeof a->normal) == 0);
}

static kg_query_filter kg_random_filter(int k)
{
    kg_query_filter f = kg_default_query_filter();
    if (k % 3 == 1) {
        f.mask = 2u | 4u;
    } else if (k % 3 == 2) {
        f.flags = KG_QUERY_SKIP_SENSORS;
    }
    return f;
}

static int kg_quick(void) { return getenv("KGYRO_SANITIZED") != NULL; }

/* How many of count random rays the index answers as brute force does, and how many hit. */
static int kg_compare_rays(const kg_world* world, int count, int* hits)
{
    int agree = 0;
    *hits = 0;
    g_seed = 99u;
    kg_note_bounds(world);
    for (int k = 0; k < count; ++k) {
        kg_vec2 o = {kg_rand(-10.0f, KG_SIDE + 10.0f), kg_rand(-10.0f, KG_SIDE + 10.0f)};
        float angle = kg_rand(-3.2f, 3.2f), length = k % 10 == 0 ? kg_rand(20.0f, 300.0f) : kg_rand(0.5f, 20.0f);
        kg_vec2 t = {length * cosf(angle), length * sinf(angle)};
        kg_query_filter f = kg_random_filter(k);
        kg_ray_result r, expected = kg_brute_ray(world, o, t, f);
        KG_CHECK_OK(kg_world_cast_ray_closest(world, o, t, f, &r));
        agree += kg_same_hit(&r, &expected);
        *hits += expected.hit;
    }
    return agree;
}

static void test_rays_match_brute_force(void)
{
    kg_world* world = kg_random_world(10000, KG_BACKEND_CPU);
    int rays = kg_quick() ? 1000 : 10000, hits = 0;
    int agree = kg_compare_rays(world, rays, &hits);
    measured("rays: %d of %d agree with brute force bit for bit (%d hit something)\n", agree, rays, hits);
    KG_CHECK(agree == rays);
    KG_CHECK(hits > rays / 4 && hits < rays); /* the test means something */
    /* after a step, the index follows the bodies */
    KG_CHECK_OK(kg_world_step(world, 1.0f / 60.0f));
    agree = kg_compare_rays(world, rays / 10, &hits);
    KG_CHECK(agree == rays / 10);
    kg_destroy_world(world);
}

/* ---- overlaps ---- */

typedef struct kg_found {
    int count;
    kg_u32 shapes[4096];
} kg_found;

static int kg_note(kg_body body, kg_shape_id shape, void* user_data, void* ctx)
{
    (void)body;
    (void)user_data;
    kg_found* f = (kg_found*)ctx;
    if (f->count < 4096) {
        f->shapes[f->count] = shape.index;
    }
    f->count++;
    return 1;
}

static int kg_compare_u32(const void* a, const void* b)
{
    kg_u32 x = *(const kg_u32*)a, y = *(const kg_u32*)b;
    return (x > y) - (x < y);
}

/* Whether found (any order) is expected (slot order), each once. */
static int kg_same_set(kg_found* found, const kg_found* expected)
{
    qsort(found->shapes, (size_t)found->count, sizeof found->shapes[0], kg_compare_u32);
    return found->count == expected->count &&
           memcmp(found->shapes, expected->shapes, (size_t)found->count * sizeof found->shapes[0]) == 0;
}

static void test_overlaps_match_brute_force(void)
{
    kg_world* world = kg_random_world(10000, KG_BACKEND_CPU);
    int queries = kg_quick() ? 100 : 1000, agree[3] = {0, 0, 0}, found_any = 0;
    for (int k = 0; k < queries; ++k) {
        kg_query_filter f = kg_random_filter(k);
        kg_vec2 c = {kg_rand(0.0f, KG_SIDE), kg_rand(0.0f, KG_SIDE)};
        kg_aabb box = {{c.x - kg_rand(0.0f, 8.0f), c.y - kg_rand(0.0f, 8.0f)}, {c.x + kg_rand(0.0f, 8.0f), c.y + kg_rand(0.0f, 8.0f)}};
        kg_shape_def def = kg_random_shape();
        float angle = kg_rand(-3.0f, 3.0f);
        kg_shape probe;
        kg_xf pxf = {c, {cosf(angle), sinf(angle)}};
        KG_CHECK_OK(kg_shape_build(&def, &probe));
        static kg_found expected[3], got[3];
        memset(expected, 0, sizeof expected);
        memset(got, 0, sizeof got);
        KG_FOR_EACH_SHAPE(world, s, i, xf, shape) {
            if (!kg_brute_sees(world, f, s)) {
                continue;
            }
            if (kg_aabb_overlap(kg_shape_aabb(shape, xf), box)) {
                expected[0].shapes[expected[0].count++] = s;
            }
            if (kg_shape_holds_point(shape, kg_xf_inv_point(xf, c))) {
                expected[1].shapes[expected[1].count++] = s;
            }
            if (kg_aabb_overlap(kg_aabb_fatten(kg_shape_aabb(&probe, pxf), 0.01f), kg_shape_aabb(shape, xf)) &&
                kg_shape_distance(&probe, pxf, shape, xf).distance <= 0.0f) {
                expected[2].shapes[expected[2].count++] = s;
            }
        }
        KG_CHECK_OK(kg_world_overlap_aabb(world, box, f, kg_note, &got[0]));
        KG_CHECK_OK(kg_world_overlap_point(world, c, f, kg_note, &got[1]));
        KG_CHECK_OK(kg_world_overlap_shape(world, &def, c, angle, f, kg_note, &got[2]));
        for (int q = 0; q < 3; ++q) {
            agree[q] += kg_same_set(&got[q], &expected[q]);
            found_any += expected[q].count > 0;
        }
    }
    measured("overlaps agreeing with brute force: boxes %d, points %d, shapes %d of %d (%d found some)\n", agree[0],
             agree[1], agree[2], queries, found_any);
    KG_CHECK(agree[0] == queries && agree[1] == queries && agree[2] == queries);
    KG_CHECK(found_any > queries);
    kg_destroy_world(world);
}

/* ---- shape casts ---- */

static void test_shape_cast_analytic(void)
{
    kg_world* world = kg_new_world(16, KG_BACKEND_CPU);
    kg_body ground = kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, -0.5f}, 0.0f, kg_box_shape(20.0f, 1.0f));
    kg_shape_def ball = kg_circle_shape(0.5f);
    kg_ray_result r;
    KG_CHECK_OK(kg_world_cast_shape_closest(world, &ball, (kg_vec2){1.0f, 5.0f}, 0.0f, (kg_vec2){0.0f, -10.0f},
                                            kg_default_query_filter(), &r));
    KG_CHECK(r.hit && kg_same_body(r.body, ground));
    KG_CHECK_NEAR(r.fraction, 0.45, 1.0e-5); /* 1e-4 m of tolerance over 10 m */
    KG_CHECK_NEAR(r.point.x, 1.0, 1.0e-5);
    KG_CHECK_NEAR(r.point.y, 0.0, 1.0e-4);
    KG_CHECK_NEAR(r.normal.x, 0.0, 1.0e-5);
    KG_CHECK_NEAR(r.normal.y, 1.0, 1.0e-5);
    /* a box turned 45 degrees, corner first, onto the ground */
    kg_shape_def box = kg_box_shape(1.0f, 1.0f);
    KG_CHECK_OK(kg_world_cast_shape_closest(world, &box, (kg_vec2){0.0f, 3.0f}, 0.7853982f, (kg_vec2){0.0f, -4.0f},
                                            kg_default_query_filter(), &r));
    KG_CHECK_NEAR(r.fraction, (3.0 - sqrt(0.5)) / 4.0, 1.0e-5);
    KG_CHECK_NEAR(r.point.x, 0.0, 1.0e-5);
    KG_CHECK_NEAR(r.point.y, 0.0, 1.0e-4);
    /* starting inside the ground: a hit at 0 against the motion */
    KG_CHECK_OK(kg_world_cast_shape_closest(world, &ball, (kg_vec2){0.0f, 0.2f}, 0.0f, (kg_vec2){0.0f, -1.0f},
                                            kg_default_query_filter(), &r));
    KG_CHECK(r.hit && r.fraction == 0.0f && r.normal.y == 1.0f);
    /* a body's own cast leaves the body out */
    kg_body drop = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){5.0f, 2.0f}, 0.0f, kg_box_shape(1.0f, 1.0f));
    KG_CHECK_OK(kg_world_cast_body_closest(world, drop, (kg_vec2){0.0f, -3.0f}, kg_default_query_filter(), &r));
    KG_CHECK(r.hit && kg_same_body(r.body, ground));
    KG_CHECK_NEAR(r.fraction, 1.5 / 3.0, 1.0e-5);
    /* one-way tiles: from above a cast lands, from below it passes */
    kg_tile_shape shapes[2] = {kg_tile_empty(), kg_tile_platform()};
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = 4;
    def.height = 4;
    def.origin = (kg_vec2){20.0f, 0.0f};
    def.shapes = shapes;
    def.shape_count = 2;
    kg_tilemap map;
    KG_CHECK_OK(kg_create_tilemap(world, &def, &map));
    KG_CHECK_OK(kg_tilemap_set_tile(world, map, 0, 1, 2, 1)); /* top half of [21, 22] x [2, 3] */
    KG_CHECK_OK(kg_world_cast_shape_closest(world, &ball, (kg_vec2){21.5f, 6.0f}, 0.0f, (kg_vec2){0.0f, -4.0f},
                                            kg_default_query_filter(), &r));
    KG_CHECK(r.hit && r.map.index == map.index && r.x == 1 && r.y == 2);
    KG_CHECK_NEAR(r.fraction, 2.5 / 4.0, 1.0e-5);
    KG_CHECK_OK(kg_world_cast_shape_closest(world, &ball, (kg_vec2){21.5f, 1.0f}, 0.0f, (kg_vec2){0.0f, 2.5f},
                                            kg_default_query_filter(), &r));
    KG_CHECK(!r.hit);
    kg_destroy_world(world);
}

static void test_shape_casts_match_brute_force(void)
{
    kg_world* world = kg_random_world(10000, KG_BACKEND_CPU);
    int casts = kg_quick() ? 30 : 300, agree = 0, hits = 0;
    kg_toi_params prm = {0.0f, 1.0e-4f};
    for (int k = 0; k < casts; ++k) {
        kg_query_filter f = kg_random_filter(k);
        kg_vec2 c = {kg_rand(0.0f, KG_SIDE), kg_rand(0.0f, KG_SIDE)};
        float angle = kg_rand(-3.0f, 3.0f), heading = kg_rand(-3.2f, 3.2f), length = kg_rand(1.0f, 30.0f);
        kg_vec2 t = {length * cosf(heading), length * sinf(heading)};
        kg_shape_def def = kg_random_shape();
        kg_shape moving;
        KG_CHECK_OK(kg_shape_build(&def, &moving));
        kg_sweep sweep = {{0.0f, 0.0f}, c, {c.x + t.x, c.y + t.y}, {cosf(angle), sinf(angle)}, {cosf(angle), sinf(angle)}, 0.0f};
        float best = 2.0f;
        kg_u32 best_s = 0;
        KG_FOR_EACH_SHAPE(world, s, i, xf, shape) {
            if (kg_brute_sees(world, f, s)) {
                float toi = kg_time_of_impact(&moving, &sweep, shape, xf, prm, nextafterf(1.0f, 2.0f));
                if (toi <= 1.0f && toi < best) {
                    best = toi;
                    best_s = s;
                }
            }
        }
        kg_ray_result r;
        KG_CHECK_OK(kg_world_cast_shape_closest(world, &def, c, angle, t, f, &r));
        int same = best <= 1.0f ? r.hit && r.shape.index == best_s && memcmp(&r.fraction, &best, sizeof best) == 0 : !r.hit;
        agree += same;
        hits += best <= 1.0f;
        if (!same) {
            fprintf(stderr, "cast %d: brute %.9g shape %u, index %d %.9g shape %u\n", k, (double)best, best_s, r.hit,
                    (double)r.fraction, r.shape.index);
        }
    }
    measured("shape casts: %d of %d agree with brute force (%d hit)\n", agree, casts, hits);
    KG_CHECK(agree == casts);
    KG_CHECK(hits > casts / 4);
    kg_destroy_world(world);
}

/* ---- OpenCL ---- */

static void kg_drop_scene(kg_world* world)
{
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, -0.5f}, 0.0f, kg_box_shape(60.0f, 1.0f));
    g_seed = 5u;
    for (int i = 0; i < 400; ++i) {
        kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){kg_rand(-25.0f, 25.0f), kg_rand(1.0f, 30.0f)}, kg_rand(-3.0f, 3.0f),
               kg_random_shape());
    }
}

static void test_opencl_matches_cpu(void)
{
    kg_world* cl = kg_new_world(512, KG_BACKEND_OPENCL);
    if (!cl || kg_world_backend(cl) != KG_BACKEND_OPENCL) {
        measured("no OpenCL device: the OpenCL comparison is skipped\n");
        kg_destroy_world(cl);
        return;
    }
    kg_world* cpu = kg_new_world(512, KG_BACKEND_CPU);
    kg_drop_scene(cl);
    kg_drop_scene(cpu);
    for (int step = 0; step < 40; ++step) {
        KG_CHECK_OK(kg_world_step(cl, 1.0f / 60.0f));
        KG_CHECK_OK(kg_world_step(cpu, 1.0f / 60.0f));
    }
    /* the device's state equal to the CPU's makes its answers equal too */
    static kg_body bodies[512];
    static kg_body_state a[512], b[512];
    int n = 0;
    KG_CHECK_OK(kg_world_get_bodies(cpu, bodies, 512, &n));
    KG_CHECK_OK(kg_world_get_body_states(cpu, bodies, n, a));
    KG_CHECK_OK(kg_world_get_bodies(cl, bodies, 512, &n));
    KG_CHECK_OK(kg_world_get_body_states(cl, bodies, n, b));
    int same_state = memcmp(a, b, (size_t)n * sizeof a[0]) == 0;
    int rays = 500, agree_brute = 0, agree_cpu = 0;
    kg_note_bounds(cl); /* the host copy is current: kg_world_get_body_states read it back */
    g_seed = 31u;
    for (int k = 0; k < rays; ++k) {
        kg_vec2 o = {kg_rand(-30.0f, 30.0f), kg_rand(0.0f, 20.0f)};
        float angle = kg_rand(-3.2f, 3.2f);
        kg_vec2 t = {15.0f * cosf(angle), 15.0f * sinf(angle)};
        kg_ray_result rc, rg;
        KG_CHECK_OK(kg_world_cast_ray_closest(cl, o, t, kg_default_query_filter(), &rg));
        KG_CHECK_OK(kg_world_cast_ray_closest(cpu, o, t, kg_default_query_filter(), &rc));
        kg_ray_result expected = kg_brute_ray(cl, o, t, kg_default_query_filter());
        agree_brute += kg_same_hit(&rg, &expected);
        agree_cpu += kg_same_hit(&rg, &rc);
    }
    measured("OpenCL: %d of %d rays as brute force on its state, %d as the CPU (states %s)\n", agree_brute, rays,
             agree_cpu, same_state ? "bitwise equal" : "differ");
    KG_CHECK(agree_brute == rays);
    KG_CHECK(!same_state || agree_cpu == rays);
    kg_destroy_world(cl);
    kg_destroy_world(cpu);
}

KG_TEST_MAIN(KG_TEST(test_ray_circle_and_polygon), KG_TEST(test_ray_capsule_and_segments),
             KG_TEST(test_ray_grazing_inside_rotated), KG_TEST(test_ray_tiles), KG_TEST(test_ray_callback_clips),
             KG_TEST(test_bad_input), KG_TEST(test_rays_match_brute_force), KG_TEST(test_overlaps_match_brute_force),
             KG_TEST(test_shape_cast_analytic), KG_TEST(test_shape_casts_match_brute_force),
             KG_TEST(test_opencl_matches_cpu))
