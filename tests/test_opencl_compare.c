/* The OpenCL backend against the CPU backend, scene by scene: the same scene built twice,
 * stepped 300 times on each, compared step by step (contact counts), every 50 steps (the
 * contact lists, impulses included: the device builds them from its own broadphase) and
 * at the end (every body's position, angle and velocities); piles falling asleep and
 * woken, every step. The two are expected bitwise equal: the kernels
 * call the same per-element functions on the same layout, both sides are compiled without
 * contraction or fast-math, and the device divides and takes square roots correctly
 * rounded. A device that cannot round them correctly is held to the 1e-4 m tolerance.
 * Skips (exit 77) when no OpenCL device exists. */
#include "kg_test.h"
#include "kg_test_world.h"
#include "kg_twin.h"
#include "kgyro/kgyro.h"
#include "kgyro/opencl.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define KG_SKIP 77
#define KG_DT (1.0f / 60.0f)

/* 300 steps; 100 under the sanitizers (make test-sanitize sets KGYRO_SANITIZED), where the
 * CPU twin runs several times slower and the release run already covers the 300. */
static int g_steps = 300;

typedef void kg_scene_fn(kg_world* world);

static int g_bitwise_expected;
static int g_max_bodies = 2100; /* of the worlds kg_make_world makes */

static void kg_ground(kg_world* world, float width)
{
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, -0.5f}, 0.0f, kg_box_shape(width, 1.0f));
}

static void kg_projectile_scene(kg_world* world)
{
    kg_body_def def = kg_default_body_def();
    def.shape = kg_box_shape(0.5f, 0.25f);
    def.velocity = (kg_vec2){7.0f, 12.0f};
    def.angular_velocity = 3.0f;
    def.linear_damping = 0.1f;
    def.angular_damping = 0.05f;
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &def, &body));
}

static void kg_stack_scene(kg_world* world)
{
    kg_ground(world, 40.0f);
    for (int i = 0; i < 10; ++i) {
        kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.5f + 1.0f * (float)i}, 0.0f, kg_box_shape(1.0f, 1.0f));
    }
}

static void kg_pyramid_scene(kg_world* world)
{
    const int base = 20;
    kg_ground(world, 80.0f);
    for (int row = 0; row < base; ++row) {
        for (int k = 0; k < base - row; ++k) {
            float x = ((float)k - 0.5f * (float)(base - row - 1)) * 1.05f;
            kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){x, 0.5f + (float)row}, 0.0f, kg_box_shape(1.0f, 1.0f));
        }
    }
}

static uint32_t kg_next(uint32_t* seed)
{
    *seed = *seed * 1664525u + 1013904223u;
    return *seed >> 8;
}

static float kg_uniform(uint32_t* seed, float lo, float hi)
{
    return lo + (hi - lo) * (float)(kg_next(seed) & 0xFFFFu) / 65535.0f;
}

/* 2,000 boxes, circles and triangles dropped in a 40 m wide column onto the ground. */
static void kg_rain_scene(kg_world* world)
{
    uint32_t seed = 12345u;
    kg_ground(world, 60.0f);
    for (int i = 0; i < 2000; ++i) {
        kg_vec2 p = {kg_uniform(&seed, -20.0f, 20.0f), 1.0f + 0.6f * (float)(i / 40) + kg_uniform(&seed, 0.0f, 0.3f)};
        float size = kg_uniform(&seed, 0.2f, 0.45f);
        kg_shape_def shape;
        switch (i % 3) {
        case 0: shape = kg_box_shape(size, 0.7f * size); break;
        case 1: shape = kg_circle_shape(0.5f * size); break;
        default: {
            kg_vec2 tri[3] = {{-0.5f * size, 0.0f}, {0.5f * size, 0.0f}, {0.0f, 0.6f * size}};
            shape = kg_polygon_shape(tri, 3);
        } break;
        }
        kg_test_add(world, KG_BODY_DYNAMIC, p, kg_uniform(&seed, 0.0f, 3.0f), shape);
    }
}

static float kg_log_uniform(uint32_t* seed, float lo, float hi)
{
    float t = kg_uniform(seed, 0.0f, 1.0f);
    return lo * powf(hi / lo, t);
}

/* What the broadphase must get right beyond a rain: sizes over two decades, zero-sized
 * particles, filters, kinematic sweepers (long runs of partners), a fast body (swept
 * bounds), a far-away pile (large coordinates), a static floor far wider than the rest,
 * and floors too wide for any grid level but the top one, each with a box falling on it. */
static void kg_sizes_scene(kg_world* world)
{
    uint32_t seed = 777u;
    kg_ground(world, 400.0f);
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){50000.0f, -0.5f}, 0.0f, kg_box_shape(20.0f, 1.0f));
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, -5000.0f}, 0.0f, kg_box_shape(2.0e7f, 2.0f));
    kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){30.0f, -4998.0f}, 0.3f, kg_box_shape(1.0f, 0.5f));
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, -20000.0f}, 0.0f, kg_box_shape(4.0e9f, 2.0f));
    kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){-30.0f, -19998.0f}, 0.3f, kg_box_shape(1.0f, 0.5f));
    for (int i = 0; i < 600; ++i) {
        float size = kg_log_uniform(&seed, 0.04f, 3.0f);
        int far = i % 10 == 9;
        kg_body_def def = kg_default_body_def();
        def.type = i % 13 == 5 ? KG_BODY_PARTICLE : KG_BODY_DYNAMIC;
        def.position = (kg_vec2){(far ? 50000.0f : 0.0f) + kg_uniform(&seed, -8.0f, 8.0f),
                                 1.0f + 0.15f * (float)i + kg_uniform(&seed, 0.0f, 0.5f)};
        def.angle = kg_uniform(&seed, 0.0f, 3.0f);
        def.shape = def.type == KG_BODY_PARTICLE ? (i % 2 ? def.shape : kg_circle_shape(0.05f))
                    : i % 2                      ? kg_circle_shape(0.5f * size)
                                                 : kg_box_shape(size, kg_uniform(&seed, 0.3f, 1.0f) * size);
        def.mass = def.type == KG_BODY_PARTICLE ? 0.01f : 0.0f; /* a point particle needs one */
        def.category = i % 7 == 3 ? 2u : 1u;
        def.mask = i % 7 == 3 ? ~2u : ~0u;
        kg_body body;
        KG_CHECK_OK(kg_create_body(world, &def, &body));
    }
    kg_body_def sweeper = kg_default_body_def();
    sweeper.type = KG_BODY_KINEMATIC;
    sweeper.position = (kg_vec2){-30.0f, 2.0f};
    sweeper.velocity = (kg_vec2){4.0f, 0.0f};
    sweeper.shape = kg_box_shape(2.0f, 3.0f);
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &sweeper, &body));
    kg_body_def bullet = kg_default_body_def();
    bullet.position = (kg_vec2){-20.0f, 3.0f};
    bullet.velocity = (kg_vec2){300.0f, -5.0f};
    bullet.shape = kg_circle_shape(0.1f);
    KG_CHECK_OK(kg_create_body(world, &bullet, &body));
}

/* What stresses the device broadphase's grid and sorts beyond the sizes scene: piles of
 * bodies created overlapping (crowded cells, long runs of partners, more pairs than the
 * first contact pool holds), tall and wide walls among them, tiny particles, a kinematic
 * slab crossing the piles, and a pile a million metres out where float cells are coarse. */
static void kg_piles_scene(kg_world* world)
{
    uint32_t seed = 4242u;
    kg_ground(world, 300.0f);
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){1.0e6f, -0.5f}, 0.0f, kg_box_shape(40.0f, 1.0f));
    for (int w = -1; w <= 1; w += 2) {
        kg_test_add(world, KG_BODY_STATIC, (kg_vec2){45.0f * (float)w, 50.0f}, 0.0f, kg_box_shape(1.0f, 100.0f));
    }
    for (int pile = 0; pile < 5; ++pile) {
        kg_vec2 centre = {pile == 4 ? 1.0e6f : -30.0f + 15.0f * (float)pile, 3.0f};
        for (int i = 0; i < 300; ++i) {
            float size = kg_log_uniform(&seed, 0.02f, 2.0f);
            kg_vec2 p = {centre.x + kg_uniform(&seed, -2.0f, 2.0f), centre.y + kg_uniform(&seed, 0.0f, 4.0f)};
            kg_shape_def shape = i % 3 == 0 ? kg_circle_shape(0.5f * size) : kg_box_shape(size, 0.5f * size);
            kg_test_add(world, i % 5 == 0 ? KG_BODY_PARTICLE : KG_BODY_DYNAMIC, p, kg_uniform(&seed, 0.0f, 3.0f), shape);
        }
    }
    kg_body slab = kg_test_add(world, KG_BODY_KINEMATIC, (kg_vec2){-40.0f, 1.5f}, 0.0f, kg_box_shape(20.0f, 0.5f));
    KG_CHECK_OK(kg_body_set_velocity(world, slab, (kg_vec2){6.0f, 0.0f}));
}

/* Pushes every body towards the origin in proportion to its height: a C callback that
 * reads state through the getters and writes forces through the body API. */
static void kg_pull_down(kg_world* world, const kg_body* bodies, int count, void* user_data)
{
    float k = *(const float*)user_data;
    for (int i = 0; i < count; ++i) {
        kg_vec2 p;
        if (kg_body_get_position(world, bodies[i], &p) == KG_OK) {
            kg_body_apply_force_to_center(world, bodies[i], (kg_vec2){0.0f, -k * p.y});
        }
    }
}

KG_DEVICE_FORCE(kg_swirl, {
    body->force.x += params[0] * body->position.y - params[1] * body->velocity.x;
    body->force.y -= params[0] * body->position.x + params[1] * body->velocity.y;
    body->torque += params[2] * body->mass;
})

/* Gravity on a list (one body listed twice), wind on all, a C callback, a device force,
 * over a ground with boxes and circles falling on it. */
static void kg_applicator_scene(kg_world* world)
{
    static float pull = 0.5f;
    kg_ground(world, 30.0f);
    kg_body bodies[12];
    for (int i = 0; i < 12; ++i) {
        kg_shape_def shape = i % 2 ? kg_circle_shape(0.3f) : kg_box_shape(0.6f, 0.4f);
        bodies[i] = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){-3.0f + 0.6f * (float)i, 2.0f + 0.7f * (float)i}, 0.1f * (float)i,
                           shape);
    }
    kg_body listed[4] = {bodies[1], bodies[5], bodies[1], bodies[9]};
    kg_applicator a;
    KG_CHECK_OK(kg_add_gravity_applicator(world, (kg_vec2){1.5f, -3.0f}, listed, 4, &a));
    KG_CHECK_OK(kg_add_wind_applicator(world, (kg_vec2){1.0f, 0.2f}, 2.0f, 0.3f, NULL, 0, &a));
    KG_CHECK_OK(kg_add_force_applicator(world, kg_pull_down, bodies + 2, 6, &pull, &a));
    kg_device_force_def def = kg_default_device_force_def();
    def.source = kg_swirl_source;
    def.function_name = "kg_swirl";
    def.cpu_fn = kg_swirl;
    def.params[0] = 0.8f;
    def.params[1] = 0.2f;
    def.params[2] = 0.05f;
    def.param_count = 3;
    KG_CHECK_OK(kg_add_device_force_applicator(world, &def, &a));
}

/* A platform level as a tile map: a floor with a 45-degree and a gentle slope, a block,
 * a one-way platform that some bodies fall onto and one jumps up through, half tiles,
 * and a second map (other key range) with a step; boxes and circles dropped on them. */
static void kg_tiles_scene(kg_world* world)
{
    enum { W = 32, H = 12 };
    kg_tile_shape shapes[9] = {kg_tile_empty(),
                               kg_tile_box(),
                               kg_tile_slope(KG_TILE_BOTTOM_RIGHT),
                               kg_tile_slope(KG_TILE_BOTTOM_LEFT),
                               kg_tile_slope_low(KG_TILE_BOTTOM_RIGHT),
                               kg_tile_slope_high(KG_TILE_BOTTOM_RIGHT),
                               kg_tile_platform(),
                               kg_tile_half(KG_TILE_SIDE_BOTTOM),
                               kg_tile_circle((kg_vec2){0.5f, 0.5f}, 0.4f)};
    static uint16_t tiles[W * H];
    memset(tiles, 0, sizeof tiles);
    for (int x = 0; x < W; ++x) {
        tiles[x] = 1; /* the floor */
    }
    tiles[0 * W + 0] = tiles[1 * W + 0] = tiles[2 * W + 0] = 1; /* walls */
    tiles[1 * W + W - 1] = tiles[2 * W + W - 1] = 1;
    tiles[1 * W + 3] = 2;                                  /* a 45-degree ramp up to a block */
    tiles[1 * W + 4] = 1;
    tiles[1 * W + 5] = 3;
    tiles[1 * W + 8] = 4;                                  /* a gentle slope */
    tiles[1 * W + 9] = 5;
    tiles[1 * W + 10] = 1;
    tiles[2 * W + 10] = 7;
    tiles[1 * W + 22] = 8;                                 /* a round bump */
    for (int x = 13; x < 20; ++x) {
        tiles[4 * W + x] = 6;                              /* the one-way platform */
    }
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = W;
    def.height = H;
    def.origin = (kg_vec2){-16.0f, -1.0f};
    def.shapes = shapes;
    def.shape_count = 9;
    def.tiles = tiles;
    def.friction = 0.4f;
    kg_tilemap map;
    KG_CHECK_OK(kg_create_tilemap(world, &def, &map));
    uint16_t step[4 * 2] = {1, 1, 1, 1, 0, 1, 1, 0};
    kg_tilemap_def second = def;
    second.width = 4;
    second.height = 2;
    second.origin = (kg_vec2){20.0f, -1.0f};
    second.tiles = step;
    second.restitution = 0.3f;
    KG_CHECK_OK(kg_create_tilemap(world, &second, &map));
    uint32_t seed = 4242u;
    for (int i = 0; i < 90; ++i) {
        kg_vec2 p = {kg_uniform(&seed, -14.0f, 22.0f), 4.0f + 0.5f * (float)(i / 10) + kg_uniform(&seed, 0.0f, 0.3f)};
        float size = kg_uniform(&seed, 0.3f, 0.7f);
        kg_shape_def shape = i % 2 ? kg_circle_shape(0.5f * size) : kg_box_shape(size, 0.8f * size);
        kg_body body = kg_test_add(world, KG_BODY_DYNAMIC, p, kg_uniform(&seed, 0.0f, 3.0f), shape);
        if (i % 15 == 7) {
            KG_CHECK_OK(kg_body_set_velocity(world, body, (kg_vec2){kg_uniform(&seed, -6.0f, 6.0f), -8.0f}));
        }
    }
    /* one jumping up through the platform from below, one sliding fast along the floor */
    kg_body jumper = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){-0.5f, 0.4f}, 0.0f, kg_box_shape(0.5f, 0.5f));
    KG_CHECK_OK(kg_body_set_velocity(world, jumper, (kg_vec2){0.5f, 11.0f}));
    kg_body slider = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){-12.0f, 0.3f}, 0.0f, kg_circle_shape(0.25f));
    KG_CHECK_OK(kg_body_set_velocity(world, slider, (kg_vec2){10.0f, 0.0f}));
}

/* Capsules and segments (issue 15): capsules, balls and boxes falling on static segment
 * ramps, a box floor, a tile-map ledge and a kinematic segment sweeping under them. */
static void kg_capsules_scene(kg_world* world)
{
    kg_ground(world, 40.0f);
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, 0.0f}, 0.0f, kg_segment_shape((kg_vec2){-12.0f, 6.0f}, (kg_vec2){-2.0f, 1.0f}));
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, 0.0f}, 0.0f, kg_segment_shape((kg_vec2){2.0f, 2.0f}, (kg_vec2){12.0f, 4.0f}));
    kg_tile_shape shapes[2] = {kg_tile_empty(), kg_tile_box()};
    uint16_t ledge[6] = {1, 1, 1, 1, 1, 1};
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = 6;
    def.height = 1;
    def.origin = (kg_vec2){-3.0f, 5.0f};
    def.shapes = shapes;
    def.shape_count = 2;
    def.tiles = ledge;
    kg_tilemap map;
    KG_CHECK_OK(kg_create_tilemap(world, &def, &map));
    uint32_t seed = 1515u;
    for (int i = 0; i < 80; ++i) {
        kg_vec2 p = {kg_uniform(&seed, -11.0f, 11.0f), 7.0f + 0.6f * (float)(i / 8) + kg_uniform(&seed, 0.0f, 0.3f)};
        float size = kg_uniform(&seed, 0.3f, 0.8f);
        kg_vec2 half = {0.5f * size * kg_uniform(&seed, 0.1f, 1.0f), 0.0f};
        kg_shape_def shape = kg_capsule_shape((kg_vec2){-half.x, 0.0f}, half, 0.3f * size);
        shape = i % 4 == 1 ? kg_circle_shape(0.4f * size) : (i % 4 == 2 ? kg_box_shape(size, 0.6f * size) : shape);
        kg_test_add(world, KG_BODY_DYNAMIC, p, kg_uniform(&seed, 0.0f, 3.0f), shape);
    }
    kg_body_def sweeper = kg_default_body_def();
    sweeper.type = KG_BODY_KINEMATIC;
    sweeper.shape = kg_segment_shape((kg_vec2){-1.5f, 0.0f}, (kg_vec2){1.5f, 0.0f});
    sweeper.position = (kg_vec2){-10.0f, 0.4f};
    sweeper.velocity = (kg_vec2){2.0f, 0.0f};
    sweeper.angular_velocity = 0.5f;
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &sweeper, &body));
}

/* Continuous collision: boxes and circles shot at 30 to 390 m/s at a wall of static
 * bricks 0.2 m thick (to the right) and at a wall of 0.2 m tiles (to the left), and bullets at a
 * standing dynamic plank, over a ground: times of impact every few steps. */
static void kg_tunnelling_scene(kg_world* world)
{
    kg_ground(world, 60.0f);
    for (int k = 0; k < 12; ++k) { /* a wall of bricks: the ground is a large static body then */
        kg_test_add(world, KG_BODY_STATIC, (kg_vec2){10.1f, 0.25f + 0.5f * (float)k}, 0.0f, kg_box_shape(0.2f, 0.5f));
    }
    static uint16_t column[30];
    for (int y = 0; y < 30; ++y) {
        column[y] = 1;
    }
    kg_tile_shape shapes[2] = {kg_tile_empty(), kg_tile_box()};
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = 1;
    def.height = 30;
    def.tile_size = (kg_vec2){0.2f, 0.2f};
    def.origin = (kg_vec2){-10.2f, 0.0f};
    def.shapes = shapes;
    def.shape_count = 2;
    def.tiles = column;
    kg_tilemap map;
    KG_CHECK_OK(kg_create_tilemap(world, &def, &map));
    kg_body_def plank = kg_default_body_def();
    plank.shape = kg_box_shape(0.2f, 4.0f);
    plank.position = (kg_vec2){0.0f, 12.0f};
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &plank, &body));
    for (int k = 0; k < 50; ++k) {
        int side = k % 3; /* 0: the static wall, 1: the tile wall, 2: the plank, as a bullet */
        kg_body_def d = kg_default_body_def();
        d.shape = k % 2 ? kg_circle_shape(0.05f) : kg_box_shape(0.1f, 0.1f);
        d.position = (kg_vec2){side == 1 ? -0.3f : -0.3f - 10.0f * (float)(side == 2), 0.5f + 0.3f * (float)(k / 3)};
        d.position.y += side == 2 ? 10.0f : 0.0f;
        d.velocity = (kg_vec2){(side == 1 ? -1.0f : 1.0f) * (30.0f + 20.0f * (float)(k / 3)), 0.0f};
        d.angular_velocity = 0.5f * (float)(k % 5);
        d.bullet = side == 2;
        KG_CHECK_OK(kg_create_body(world, &d, &body));
    }
}

/* Compound bodies (dumbbells of two discs and a bar, Ls of two boxes) piled with boxes on
 * the ground, and beside it on a tile map's slopes (per shape tile contacts); part way, an
 * L loses a shape and a box gains one (kg_compound_edit). */
static void kg_compound_scene(kg_world* world)
{
    kg_ground(world, 40.0f);
    kg_tile_shape tile_shapes[3] = {kg_tile_empty(), kg_tile_box(), kg_tile_slope(KG_TILE_BOTTOM_RIGHT)};
    uint16_t tiles[2 * 12] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0, 2, 0, 0, 2, 1, 0, 0, 0, 2, 1, 1};
    kg_tilemap_def map = kg_default_tilemap_def();
    map.width = 12;
    map.height = 2;
    map.origin = (kg_vec2){21.0f, -1.0f};
    map.shapes = tile_shapes;
    map.shape_count = 3;
    map.tiles = tiles;
    kg_tilemap handle;
    KG_CHECK_OK(kg_create_tilemap(world, &map, &handle));
    for (int k = 0; k < 4; ++k) {
        kg_body body = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){23.0f + 2.5f * (float)k, 2.0f}, 0.3f * (float)k,
                              kg_box_shape(1.4f, 0.2f));
        kg_body_shape_def disc = kg_default_body_shape_def();
        disc.geometry = kg_shape_moved(kg_circle_shape(0.25f), (kg_vec2){0.7f, 0.0f}, 0.0f);
        kg_shape_id id;
        KG_CHECK_OK(kg_create_shape(world, body, &disc, &id));
    }
    for (int k = 0; k < 60; ++k) {
        float x = -6.0f + (float)(k % 6) * 2.2f, y = 1.0f + (float)(k / 6) * 1.3f;
        kg_body body = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){x, y}, 0.2f * (float)(k % 7), kg_box_shape(1.2f, 0.3f));
        kg_body_shape_def part = kg_default_body_shape_def();
        kg_shape_id id;
        if (k % 3 == 0) {
            part.geometry = kg_shape_moved(kg_circle_shape(0.3f), (kg_vec2){-0.7f, 0.0f}, 0.0f);
            KG_CHECK_OK(kg_create_shape(world, body, &part, &id));
            part.geometry = kg_shape_moved(kg_circle_shape(0.3f), (kg_vec2){0.7f, 0.0f}, 0.0f);
            part.friction = 0.2f;
            KG_CHECK_OK(kg_create_shape(world, body, &part, &id));
        } else if (k % 3 == 1) {
            part.geometry = kg_offset_box_shape(0.3f, 1.2f, (kg_vec2){0.45f, 0.45f}, 0.0f);
            part.density = 2.0f;
            part.restitution = 0.3f;
            KG_CHECK_OK(kg_create_shape(world, body, &part, &id));
        }
    }
}

static kg_world* kg_make_world(kg_backend backend, kg_scene_fn* scene)
{
    kg_world_def def = kg_default_world_def();
    def.backend = backend;
    def.max_bodies = g_max_bodies;
    kg_world* world = NULL;
    KG_CHECK_OK(kg_create_world(&def, &world));
    if (world) {
        KG_CHECK(kg_world_backend(world) == backend);
        scene(world);
    }
    return world;
}

static int kg_same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* Whether both worlds have the same contacts, every field (impulses included) the same. */
static int kg_same_contacts(kg_world* cpu, kg_world* cl)
{
    int n = kg_world_contact_count(cpu), same = n == kg_world_contact_count(cl);
    for (int k = 0; same && k < n; ++k) {
        kg_contact_info a, b;
        KG_CHECK_OK(kg_world_get_contact(cpu, k, &a));
        KG_CHECK_OK(kg_world_get_contact(cl, k, &b));
        kg_untag_contact(&a);
        kg_untag_contact(&b);
        same = memcmp(&a, &b, sizeof a) == 0;
        kg_tilemap ma = {0, 0}, mb = {0, 0};
        int ta[3] = {-1, -1, -1}, tb[3] = {-1, -1, -1};
        int ra = kg_world_get_contact_tile(cpu, k, &ma, &ta[0], &ta[1], &ta[2]);
        int rb = kg_world_get_contact_tile(cl, k, &mb, &tb[0], &tb[1], &tb[2]);
        same = same && ra == rb && memcmp(&ma, &mb, sizeof ma) == 0 && memcmp(ta, tb, sizeof ta) == 0;
    }
    return same;
}

static double kg_abs(double v) { return v < 0.0 ? -v : v; }

/* Compares every body; returns how many floats differ in their bits, and the largest
 * position difference in *max_position. */
static int kg_compare_states(kg_world* cpu, kg_world* cl, double* max_position)
{
    static kg_body bodies[2100];
    int count = 0, count_cl = 0, differing = 0;
    kg_world_get_bodies(cpu, bodies, 2100, &count);
    kg_world_get_bodies(cl, bodies, 2100, &count_cl);
    KG_CHECK(count == count_cl);
    *max_position = 0.0;
    for (int i = 0; i < count; ++i) {
        kg_body_state a, b;
        KG_CHECK_OK(kg_body_get_state(cpu, kg_twin_body(cpu, bodies[i]), &a));
        KG_CHECK_OK(kg_body_get_state(cl, bodies[i], &b));
        float fa[6] = {a.position.x, a.position.y, a.angle, a.velocity.x, a.velocity.y, a.angular_velocity};
        float fb[6] = {b.position.x, b.position.y, b.angle, b.velocity.x, b.velocity.y, b.angular_velocity};
        for (int k = 0; k < 6; ++k) {
            differing += !kg_same_bits(fa[k], fb[k]);
        }
        double dx = kg_abs((double)a.position.x - b.position.x), dy = kg_abs((double)a.position.y - b.position.y);
        *max_position = dx > *max_position ? dx : *max_position;
        *max_position = dy > *max_position ? dy : *max_position;
    }
    return differing;
}

/* Body 2 (an L) loses its post and body 3 (a box) gains a disc, as the pile settles. */
static void kg_compound_edit(kg_world* world)
{
    kg_body bodies[4];
    int count = 0;
    KG_CHECK_OK(kg_world_get_bodies(world, bodies, 4, &count));
    kg_shape_id shapes[2];
    KG_CHECK_OK(kg_body_get_shapes(world, bodies[2], shapes, 2, &count));
    KG_CHECK_OK(kg_destroy_shape(world, shapes[1]));
    kg_body_shape_def disc = kg_default_body_shape_def();
    disc.geometry = kg_shape_moved(kg_circle_shape(0.4f), (kg_vec2){0.0f, 0.4f}, 0.0f);
    KG_CHECK_OK(kg_create_shape(world, bodies[3], &disc, &shapes[0]));
}

/* Chains: a hilly ground of 40 one-sided segments on a static body made without a shape,
 * a square loop standing on it, a kinematic chain sweeping above, and boxes, circles and
 * capsules dropped on them, some of them fast enough (40 to 200 m/s, downwards) for times
 * of impact against the chain. */
static void kg_chains_scene(kg_world* world)
{
    kg_body_def d = kg_default_body_def();
    d.type = KG_BODY_STATIC;
    kg_body ground, sweeper;
    KG_CHECK_OK(kg_create_body(world, &d, &ground));
    kg_vec2 hills[41];
    for (int i = 0; i <= 40; ++i) { /* right to left: the normal up */
        float x = 20.0f - (float)i;
        hills[i] = (kg_vec2){x, 0.6f * sinf(0.4f * x) + 0.02f * x};
    }
    kg_chain_def chain = kg_default_chain_def();
    chain.points = hills;
    chain.count = 41;
    KG_CHECK_OK(kg_create_chain(world, ground, &chain, NULL));
    const kg_vec2 square[4] = {{-2.0f, 1.0f}, {2.0f, 1.0f}, {2.0f, 3.0f}, {-2.0f, 3.0f}};
    chain.points = square;
    chain.count = 4;
    chain.loop = 1;
    KG_CHECK_OK(kg_create_chain(world, ground, &chain, NULL));
    d.type = KG_BODY_KINEMATIC;
    d.position = (kg_vec2){-12.0f, 6.0f};
    d.velocity = (kg_vec2){1.5f, 0.0f};
    KG_CHECK_OK(kg_create_body(world, &d, &sweeper));
    const kg_vec2 bar[3] = {{1.5f, 0.0f}, {0.0f, -0.3f}, {-1.5f, 0.0f}};
    chain.points = bar;
    chain.count = 3;
    chain.loop = 0;
    KG_CHECK_OK(kg_create_chain(world, sweeper, &chain, NULL));
    for (int k = 0; k < 60; ++k) {
        kg_shape_def shape = k % 3 == 0   ? kg_box_shape(0.4f, 0.3f)
                             : k % 3 == 1 ? kg_circle_shape(0.2f)
                                          : kg_capsule_shape((kg_vec2){-0.2f, 0.0f}, (kg_vec2){0.2f, 0.0f}, 0.15f);
        kg_body body = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){-15.0f + 0.5f * (float)k, 8.0f + 0.3f * (float)(k % 7)},
                              0.1f * (float)k, shape);
        if (k % 10 == 5) {
            KG_CHECK_OK(kg_body_set_velocity(world, body, (kg_vec2){0.0f, -40.0f - 16.0f * (float)(k / 10)}));
        }
    }
}

static int kg_compare_scene_edited(const char* name, kg_scene_fn* scene, kg_scene_fn* edit_at_100);

/* At step 100 the world's first compound body appears: a shot at the static wall of the
 * tunnelling scene gains a second shape, so that continuous collision walks a list of
 * shapes whose geometry the device had no buffer for until then. */
static void kg_first_compound_edit(kg_world* world)
{
    kg_body bodies[64];
    int count = 0;
    KG_CHECK_OK(kg_world_get_bodies(world, bodies, 64, &count));
    kg_body_shape_def tail = kg_default_body_shape_def();
    tail.geometry = kg_offset_box_shape(0.3f, 0.05f, (kg_vec2){-0.2f, 0.0f}, 0.0f);
    kg_shape_id id;
    KG_CHECK_OK(kg_create_shape(world, bodies[count - 1], &tail, &id));
}

static void kg_compare_scene(const char* name, kg_scene_fn* scene) { kg_compare_scene_edited(name, scene, NULL); }

/* Whether the world's last step ran its collide stage on the host. */
static int kg_collided_on_host(const kg_world* world)
{
    kg_stage_times t;
    KG_CHECK_OK(kg_world_get_stage_times(world, &t));
    for (int k = 0; k < t.count; ++k) {
        if (strcmp(t.names[k], "collide (host)") == 0) {
            return 1;
        }
    }
    return 0;
}

/* Steps a scene on both backends and compares them; edit_at_100 (or NULL) changes both
 * worlds after step 100. Returns how many steps the OpenCL world collided on the host. */
static int kg_compare_scene_edited(const char* name, kg_scene_fn* scene, kg_scene_fn* edit_at_100)
{
    kg_world* cpu = kg_make_world(KG_BACKEND_CPU, scene);
    kg_world* cl = kg_make_world(KG_BACKEND_OPENCL, scene);
    if (!cpu || !cl) {
        kg_destroy_world(cpu);
        kg_destroy_world(cl);
        return 0;
    }
    int count_mismatch = 0, list_mismatch = 0, max_contacts = 0, on_host = 0;
    for (int s = 0; s < g_steps; ++s) {
        if (s == 100 && edit_at_100) {
            edit_at_100(cpu);
            edit_at_100(cl);
        }
        KG_CHECK_OK(kg_world_step(cpu, KG_DT));
        KG_CHECK_OK(kg_world_step(cl, KG_DT));
        on_host += kg_collided_on_host(cl);
        int nc = kg_world_contact_count(cpu);
        count_mismatch += nc != kg_world_contact_count(cl);
        max_contacts = nc > max_contacts ? nc : max_contacts;
        if ((s + 1) % 50 == 0 && g_bitwise_expected) {
            list_mismatch += !kg_same_contacts(cpu, cl);
        }
    }
    KG_CHECK(count_mismatch == 0);
    KG_CHECK(list_mismatch == 0);
    KG_CHECK(kg_world_backend(cl) == KG_BACKEND_OPENCL);
    double max_position = 0.0;
    int differing = kg_compare_states(cpu, cl, &max_position);
    printf("     %-12s %4d bodies, up to %4d contacts: %d steps with other contact counts, %d floats not bitwise "
           "equal, positions within %.3g m; %d steps collided on the host\n",
           name, kg_world_body_count(cpu), max_contacts, count_mismatch, differing, max_position, on_host);
    KG_CHECK_NEAR(max_position, 0.0, 1e-4);
    if (g_bitwise_expected) {
        KG_CHECK(differing == 0);
    }
    kg_destroy_world(cpu);
    kg_destroy_world(cl);
    return on_host;
}

/* Two piles of 50 boxes apart on the ground, and a kinematic pusher sliding towards the
 * right one: the piles fall asleep, a box dropped on the left one wakes that island
 * alone, and the pusher later wakes the right one (a moving kinematic body also keeps
 * awake what it touches). */
static void kg_sleep_scene(kg_world* world)
{
    kg_ground(world, 60.0f);
    for (int i = 0; i < 100; ++i) {
        int k = i % 50, row = k / 10;
        float x = (i < 50 ? -12.0f : 3.0f) + 0.95f * (float)(k % 10) + 0.3f * (float)(row % 2);
        kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){x, 0.45f + 0.92f * (float)row}, 0.0f, kg_box_shape(0.9f, 0.9f));
    }
    kg_body_def pusher = kg_default_body_def();
    pusher.type = KG_BODY_KINEMATIC;
    pusher.position = (kg_vec2){14.5f, 1.0f};
    pusher.velocity = (kg_vec2){-0.6f, 0.0f};
    pusher.shape = kg_box_shape(1.0f, 2.0f);
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &pusher, &body));
}

/* Sleeping and waking, compared every step: the states bitwise (the timers, islands and
 * wake-ups decide who moves, so any difference shows at once), the bodies asleep, and the
 * contact lists (the CPU keeps the manifolds between sleeping bodies from the step
 * before, the device computes them again: they must be the same bits). */
static void test_sleep_and_wake(void)
{
    kg_world* both[2] = {kg_make_world(KG_BACKEND_CPU, kg_sleep_scene),
                         kg_make_world(KG_BACKEND_OPENCL, kg_sleep_scene)};
    if (!both[0] || !both[1]) {
        kg_destroy_world(both[0]);
        kg_destroy_world(both[1]);
        return;
    }
    int dropped = -1, fewest_after_drop = 100, asleep_mismatch = 0, differing = 0, list_mismatch = 0;
    double max_position = 0.0;
    for (int s = 0; s < 240; ++s) {
        int asleep = kg_world_asleep_count(both[0]);
        for (int w = 0; dropped < 0 && asleep == 100 && w < 2; ++w) {
            kg_test_add(both[w], KG_BODY_DYNAMIC, (kg_vec2){-7.5f, 4.5f}, 0.3f, kg_box_shape(0.6f, 0.6f));
        }
        dropped = dropped < 0 && asleep == 100 ? s : dropped;
        fewest_after_drop = dropped >= 0 && asleep < fewest_after_drop ? asleep : fewest_after_drop;
        KG_CHECK_OK(kg_world_step(both[0], KG_DT));
        KG_CHECK_OK(kg_world_step(both[1], KG_DT));
        asleep_mismatch += kg_world_asleep_count(both[0]) != kg_world_asleep_count(both[1]);
        list_mismatch += !kg_same_contacts(both[0], both[1]);
        double position = 0.0;
        differing += kg_compare_states(both[0], both[1], &position);
        max_position = position > max_position ? position : max_position;
    }
    printf("     all 100 asleep at step %d, down to %d asleep after the drop, %d at the end; %d steps with other "
           "counts asleep, %d with other contact lists, %d floats not bitwise equal, positions within %.3g m\n",
           dropped, fewest_after_drop, kg_world_asleep_count(both[0]), asleep_mismatch, list_mismatch, differing,
           max_position);
    KG_CHECK(dropped > 0);
    KG_CHECK(fewest_after_drop < 100);
    KG_CHECK_NEAR(max_position, 0.0, 1e-4);
    if (g_bitwise_expected) {
        KG_CHECK(asleep_mismatch == 0);
        KG_CHECK(list_mismatch == 0);
        KG_CHECK(differing == 0);
    }
    KG_CHECK(kg_world_backend(both[1]) == KG_BACKEND_OPENCL);
    kg_destroy_world(both[0]);
    kg_destroy_world(both[1]);
}

/* On a CPU device one work-group finds the islands of any number of bodies; a GPU uses
 * rounds over the whole device past a few thousand. Here the rounds run every step. */
static void test_sleep_and_wake_islands_in_rounds(void)
{
    setenv("KGYRO_CL_ISLAND_GROUP_MAX", "16", 1);
    test_sleep_and_wake();
    unsetenv("KGYRO_CL_ISLAND_GROUP_MAX");
}

static void test_projectile(void) { kg_compare_scene("projectile", kg_projectile_scene); }
static void test_applicators(void) { kg_compare_scene("applicators", kg_applicator_scene); }
static void test_stack(void) { kg_compare_scene("stack", kg_stack_scene); }
static void test_pyramid_20(void) { kg_compare_scene("pyramid 20", kg_pyramid_scene); }
static void test_rain_2000(void) { kg_compare_scene("rain 2000", kg_rain_scene); }
static void test_sizes(void) { kg_compare_scene("sizes", kg_sizes_scene); }
static void test_piles(void) { kg_compare_scene("piles", kg_piles_scene); }

/* On a CPU device the colouring runs on one work-item at any size; a GPU colours more
 * than a few thousand contacts in rounds (solve/coloring.h). Here the rounds run for
 * every step with more than 16 contacts. */
static void test_rain_2000_colored_in_rounds(void)
{
    setenv("KGYRO_CL_COLOR_SERIAL_MAX", "16", 1);
    kg_compare_scene("rain rounds", kg_rain_scene);
    unsetenv("KGYRO_CL_COLOR_SERIAL_MAX");
}
static void test_tiles(void) { kg_compare_scene("tiles", kg_tiles_scene); }
static void test_capsules(void) { kg_compare_scene("capsules", kg_capsules_scene); }
static void test_tunnelling(void) { kg_compare_scene("tunnelling", kg_tunnelling_scene); }
static void test_chains(void) { kg_compare_scene("chains", kg_chains_scene); }
static void test_tunnelling_first_compound(void)
{
    kg_compare_scene_edited("tunnelling, first compound body at step 100", kg_tunnelling_scene, kg_first_compound_edit);
}
/* Twelve bodies of five shapes each in a world of 16 bodies: the shape pool grows past
 * its first 16 slots (twice) before the first step, on the host and so on the device. */
static void kg_many_shapes_scene(kg_world* world)
{
    kg_ground(world, 40.0f);
    for (int k = 0; k < 12; ++k) {
        kg_body body = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){-4.0f + 0.7f * (float)k, 1.0f + 0.6f * (float)(k % 3)},
                              k % 2 ? 3.0f : 0.2f, kg_box_shape(1.0f, 0.2f)); /* every other one discs down */
        for (int j = 0; j < 4; ++j) {
            kg_body_shape_def part = kg_default_body_shape_def();
            part.geometry = kg_shape_moved(kg_circle_shape(0.1f), (kg_vec2){-0.45f + 0.3f * (float)j, 0.2f}, 0.0f);
            kg_shape_id id;
            KG_CHECK_OK(kg_create_shape(world, body, &part, &id));
        }
    }
}

static void test_compound_shape_pool_grows(void)
{
    g_max_bodies = 16;
    int on_host = kg_compare_scene_edited("many shapes", kg_many_shapes_scene, NULL);
    g_max_bodies = 2100;
    KG_CHECK(on_host <= 2);
}

/* Compound bodies collide on the device (the pairs of shapes found there), all but the
 * steps where the pool grows. */
static void test_compound(void)
{
    int on_host = kg_compare_scene_edited("compound", kg_compound_scene, kg_compound_edit);
    KG_CHECK(on_host <= 2);
}

/* With a tile map, the collide stage runs on the device: no "collide (host)" in the
 * stage times, with profiling off or on, and the world stays on the OpenCL backend. */
static void test_tiles_collide_on_device(void)
{
    kg_world* world = kg_make_world(KG_BACKEND_OPENCL, kg_tiles_scene);
    if (!world) {
        return;
    }
    int host = 0, device = 0;
    for (int s = 0; s < 40; ++s) {
        KG_CHECK_OK(kg_world_set_profiling(world, s >= 20));
        KG_CHECK_OK(kg_world_step(world, KG_DT));
        kg_stage_times t;
        KG_CHECK_OK(kg_world_get_stage_times(world, &t));
        for (int i = 0; i < t.count; ++i) {
            host += strcmp(t.names[i], "collide (host)") == 0;
            device += strcmp(t.names[i], "collide") == 0 || strcmp(t.names[i], "kg_narrowphase") == 0;
        }
    }
    KG_CHECK(host == 0);
    KG_CHECK(device == 40);
    KG_CHECK(kg_world_contact_count(world) > 0);
    KG_CHECK(kg_world_backend(world) == KG_BACKEND_OPENCL);
    kg_destroy_world(world);
}

int main(void)
{
    int devices = 0;
    if (kg_opencl_device_count(&devices) != KG_OK || devices == 0) {
        printf("skipped: no OpenCL device (%s)\n", devices == 0 && kg_last_error()[0] ? kg_last_error() : "none found");
        return KG_SKIP;
    }
    if (getenv("KGYRO_SANITIZED")) {
        g_steps = 100;
    }
    kg_opencl_device_info info;
    kg_opencl_get_device_info(kg_test_opencl_device(), &info);
    g_bitwise_expected = info.correctly_rounded_divide_sqrt;
    printf("device 0: %s (%s), %d steps, bitwise agreement %s\n", info.name, info.platform_name, g_steps,
           g_bitwise_expected ? "required" : "not required (no correctly rounded divide/sqrt)");
    static const kg_test_case tests[] = {KG_TEST(test_projectile), KG_TEST(test_applicators), KG_TEST(test_stack),
                                         KG_TEST(test_pyramid_20), KG_TEST(test_rain_2000), KG_TEST(test_rain_2000_colored_in_rounds),
                                         KG_TEST(test_sizes), KG_TEST(test_piles), KG_TEST(test_compound), KG_TEST(test_compound_shape_pool_grows),
                                         KG_TEST(test_tiles), KG_TEST(test_tiles_collide_on_device), KG_TEST(test_capsules),
                                         KG_TEST(test_tunnelling), KG_TEST(test_tunnelling_first_compound), KG_TEST(test_chains),
                                         KG_TEST(test_sleep_and_wake), KG_TEST(test_sleep_and_wake_islands_in_rounds)};
    return kg_run_tests(tests, (int)(sizeof tests / sizeof tests[0]));
}
