/* Tile-map terrain: seamless sliding over flat and sloped runs of tiles, the same resting
 * heights as the terrain built from static polygons, one-way platforms, tiles changed at
 * run time, and the API's checks. Every physics test prints what it measured. */
#include "kg_test.h"
#include "kgyro/kgyro.h"

#include <stdint.h>
#include <string.h>

#define DT (1.0f / 60.0f)

enum { EMPTY, BOX, SLOPE_UP, SLOPE_DOWN, GENTLE_LOW, GENTLE_HIGH, HALF, PLATFORM, SHAPE_COUNT };

static void standard_shapes(kg_tile_shape* shapes)
{
    shapes[EMPTY] = kg_tile_empty();
    shapes[BOX] = kg_tile_box();
    shapes[SLOPE_UP] = kg_tile_slope(KG_TILE_BOTTOM_RIGHT);
    shapes[SLOPE_DOWN] = kg_tile_slope(KG_TILE_BOTTOM_LEFT);
    shapes[GENTLE_LOW] = kg_tile_slope_low(KG_TILE_BOTTOM_RIGHT);
    shapes[GENTLE_HIGH] = kg_tile_slope_high(KG_TILE_BOTTOM_RIGHT);
    shapes[HALF] = kg_tile_half(KG_TILE_SIDE_BOTTOM);
    shapes[PLATFORM] = kg_tile_platform();
}

static kg_world* make_world_on(kg_vec2 gravity, kg_backend backend)
{
    kg_world_def def = kg_default_world_def();
    def.gravity = gravity;
    def.backend = backend;
    def.max_bodies = 16384;
    kg_world* w = NULL;
    if (kg_create_world(&def, &w) != KG_OK) {
        return NULL;
    }
    return w;
}

static kg_world* make_world(kg_vec2 gravity)
{
    kg_world* w = make_world_on(gravity, KG_BACKEND_CPU);
    KG_CHECK(w != NULL);
    return w;
}

/* A map of the standard shapes with its cell (0, 0) at origin, all empty. */
static kg_tilemap make_map(kg_world* w, int width, int height, kg_vec2 origin)
{
    kg_tile_shape shapes[SHAPE_COUNT];
    standard_shapes(shapes);
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = width;
    def.height = height;
    def.origin = origin;
    def.shapes = shapes;
    def.shape_count = SHAPE_COUNT;
    kg_tilemap map = KG_NULL_TILEMAP_INIT;
    KG_CHECK_OK(kg_create_tilemap(w, &def, &map));
    return map;
}

static kg_body add_body(kg_world* w, kg_body_type type, kg_shape_def shape, kg_vec2 position, float angle,
                        kg_vec2 velocity, float friction)
{
    kg_body_def bd = kg_default_body_def();
    bd.type = type;
    bd.shape = shape;
    bd.position = position;
    bd.angle = angle;
    bd.velocity = velocity;
    bd.friction = friction;
    kg_body b = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    return b;
}

static kg_body_state state_of(kg_world* w, kg_body b)
{
    kg_body_state s;
    memset(&s, 0, sizeof s);
    KG_CHECK_OK(kg_body_get_state(w, b, &s));
    return s;
}

/* ---- sliding without snagging ---- */

typedef enum terrain { FLAT, SLOPE45, GENTLE, HALF_TILES } terrain;

static const char* const kTerrainNames[] = {"flat tiles", "45-degree slope tiles", "1-in-2 slope tiles",
                                            "half tiles"};

/* The surface's unit tangent (direction of travel) and normal. */
static void terrain_axes(terrain kind, kg_vec2* tangent, kg_vec2* normal)
{
    float rise = kind == SLOPE45 ? 1.0f : (kind == GENTLE ? 0.5f : 0.0f);
    float length = sqrtf(1.0f + rise * rise);
    *tangent = (kg_vec2){1.0f / length, rise / length};
    *normal = (kg_vec2){-rise / length, 1.0f / length};
}

/* run tiles of the terrain going right (and up) from cell (0, 0), filled beneath. */
static void build_run(kg_world* w, kg_tilemap map, terrain kind, int run)
{
    for (int i = 0; i < run; ++i) {
        switch (kind) {
        case FLAT: KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, i, 0, BOX)); break;
        case HALF_TILES: KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, i, 0, HALF)); break;
        case SLOPE45:
            KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, i, i, SLOPE_UP));
            for (int y = 0; y < i; ++y) {
                KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, i, y, BOX));
            }
            break;
        case GENTLE:
            KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, i, i / 2, i % 2 == 0 ? GENTLE_LOW : GENTLE_HIGH));
            for (int y = 0; y < i / 2; ++y) {
                KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, i, y, BOX));
            }
            break;
        }
    }
}

typedef struct slide_result {
    double max_normal_speed;   /* |v . n| over the run */
    double max_speed_change;   /* |v . t - v0| / v0 over the run */
    double distance;           /* travelled along the surface */
} slide_result;

/* A frictionless body pressed onto the surface by gravity along its normal (so nothing
 * speeds it up or slows it down) slides at 10 m/s over run tiles. */
static slide_result slide(terrain kind, kg_shape_def shape, float half_height, int run, kg_world* w)
{
    kg_vec2 t, n;
    terrain_axes(kind, &t, &n);
    KG_CHECK_OK(kg_world_set_gravity(w, (kg_vec2){-10.0f * n.x, -10.0f * n.y}));
    int height = kind == SLOPE45 ? run + 2 : (kind == GENTLE ? run / 2 + 2 : 2);
    kg_vec2 origin = {-2.0f, kind == HALF_TILES ? -0.5f : (kind == FLAT ? -1.0f : 0.0f)};
    kg_tilemap map = make_map(w, run + 2, height, origin);
    build_run(w, map, kind, run);
    /* start 1 m along the surface from where it begins, touching it */
    kg_vec2 surface = kind == FLAT || kind == HALF_TILES ? (kg_vec2){origin.x, 0.0f} : origin;
    kg_vec2 start = {surface.x + t.x + half_height * n.x, surface.y + t.y + half_height * n.y};
    float angle = atan2f(t.y, t.x);
    kg_body b = add_body(w, KG_BODY_DYNAMIC, shape, start, angle, (kg_vec2){10.0f * t.x, 10.0f * t.y}, 0.0f);
    slide_result r = {0.0, 0.0, 0.0};
    float length = sqrtf(1.0f + t.y * t.y / (t.x * t.x)) * (float)(run - 2);
    int steps = (int)(length / 10.0f / DT);
    for (int step = 0; step < steps; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_body_state s = state_of(w, b);
        double vn = s.velocity.x * n.x + s.velocity.y * n.y;
        double vt = s.velocity.x * t.x + s.velocity.y * t.y;
        r.max_normal_speed = fmax(r.max_normal_speed, fabs(vn));
        r.max_speed_change = fmax(r.max_speed_change, fabs(vt - 10.0) / 10.0);
        r.distance = (s.position.x - start.x) * t.x + (s.position.y - start.y) * t.y;
    }
    kg_destroy_world(w);
    return r;
}

/* The bodies slid: on the OpenCL backend, slower under the sanitizers, the first two. */
static void check_slides(terrain kind, int run, kg_backend backend)
{
    struct {
        const char* name;
        kg_shape_def shape;
        float half_height;
    } bodies[] = {
        {"box 0.5 m", kg_box_shape(0.5f, 0.5f), 0.25f},
        {"circle r 0.25 m", kg_circle_shape(0.25f), 0.25f},
        {"box 1.6 x 0.4 m", kg_box_shape(1.6f, 0.4f), 0.2f},
        {"circle r 0.8 m", kg_circle_shape(0.8f), 0.8f},
        {"capsule 1.2 x 0.4 m", kg_capsule_shape((kg_vec2){-0.4f, 0.0f}, (kg_vec2){0.4f, 0.0f}, 0.2f), 0.2f},
    };
    const char* backend_name = backend == KG_BACKEND_OPENCL ? "opencl" : "cpu";
    size_t count = backend == KG_BACKEND_OPENCL ? 2 : sizeof bodies / sizeof bodies[0];
    for (size_t i = 0; i < count; ++i) {
        kg_world* w = make_world_on((kg_vec2){0.0f, -10.0f}, backend);
        if (!w) {
            printf("skipped on %s: %s\n", backend_name, kg_last_error());
            return;
        }
        slide_result r = slide(kind, bodies[i].shape, bodies[i].half_height, run, w);
        printf("measured (%s): %s on %d %s at 10 m/s: travelled %.2f m, largest normal speed %.3g m/s, largest "
               "change of speed along the surface %.3g%%\n", backend_name, bodies[i].name, run, kTerrainNames[kind],
               r.distance, r.max_normal_speed, 100.0 * r.max_speed_change);
        KG_CHECK(r.max_normal_speed < 1e-3);
        KG_CHECK(r.max_speed_change <= 1e-3);
        KG_CHECK(r.distance > 0.9 * (run - 3) * (kind == SLOPE45 ? 1.41421 : (kind == GENTLE ? 1.11803 : 1.0)));
    }
}

static void test_box_and_circle_slide_across_200_flat_tiles(void) { check_slides(FLAT, 200, KG_BACKEND_CPU); }

static void test_box_and_circle_slide_across_200_slope_tiles(void) { check_slides(SLOPE45, 200, KG_BACKEND_CPU); }

static void test_box_and_circle_slide_across_gentle_slope_and_half_tiles(void)
{
    check_slides(GENTLE, 100, KG_BACKEND_CPU);
    check_slides(HALF_TILES, 100, KG_BACKEND_CPU);
}

/* The same runs on the OpenCL backend, where the maps are device buffers and tile
 * contacts are found by a kernel, when a device is there. */
static void test_slides_on_the_opencl_backend(void)
{
    check_slides(FLAT, 200, KG_BACKEND_OPENCL);
    check_slides(SLOPE45, 200, KG_BACKEND_OPENCL);
}


/* ---- the same terrain as static polygons ---- */

/* 1000 columns of terrain, 4 tiles wide with an empty tile between them, 40 to a row, the
 * rows 10 tiles apart: flat tops of full or half tiles 1 to 3 tiles high, or V-shaped
 * valleys of two 45-degree slopes. One body is dropped over each column, so bodies never
 * meet, and each comes to rest where the geometry alone decides its height: boxes (0.4
 * to 0.7 times as tall as wide, turned by up to 0.05 rad) and circles dropped 0.1 to 0.6 m
 * onto the middle of a flat top's second tile, which they land on wholly and settle on
 * without tipping over (a squarer box, or one dropped from higher, sometimes tips onto its
 * side by chance, in one world and not the other); circles into a valley, at whose
 * bottom they end. Where a body lands across the seam of two tiles,
 * the static polygons make it snag and bounce off sideways (the ghost collisions tile maps
 * avoid), which would compare two different motions rather than two terrains. */
#define DROP_COLUMNS 1000
#define DROP_PER_ROW 40
#define DROP_PITCH 5
#define DROP_ROW_PITCH 10
#define DROP_MAP_WIDTH (DROP_PER_ROW * DROP_PITCH)
#define DROP_MAP_HEIGHT ((DROP_COLUMNS / DROP_PER_ROW) * DROP_ROW_PITCH)

typedef struct drop_layout {
    uint16_t tiles[DROP_MAP_HEIGHT][DROP_MAP_WIDTH];
    kg_body_def bodies[DROP_COLUMNS];
} drop_layout;

static uint32_t next_random(uint32_t* state)
{
    *state ^= *state << 13;
    *state ^= *state >> 17;
    *state ^= *state << 5;
    return *state;
}

static float random_range(uint32_t* state, float lo, float hi)
{
    return lo + (hi - lo) * (float)(next_random(state) >> 8) * (1.0f / 16777216.0f);
}

static void layout_column(drop_layout* d, int column, uint32_t* rng)
{
    int x0 = (column % DROP_PER_ROW) * DROP_PITCH, row = (column / DROP_PER_ROW) * DROP_ROW_PITCH;
    int stack = 1 + (int)(next_random(rng) % 3u);
    int kind = (int)(next_random(rng) % 4u); /* 0, 1 full top, 2 half top, 3 valley */
    for (int x = x0; x < x0 + 4; ++x) {
        for (int y = row; y < row + stack; ++y) {
            d->tiles[y][x] = BOX;
        }
    }
    float top = (float)(row + stack);
    if (kind == 2) {
        for (int x = x0; x < x0 + 4; ++x) {
            d->tiles[row + stack][x] = HALF;
        }
        top += 0.5f;
    } else if (kind == 3) {
        d->tiles[row + stack][x0] = BOX;
        d->tiles[row + stack][x0 + 1] = SLOPE_DOWN;
        d->tiles[row + stack][x0 + 2] = SLOPE_UP;
        d->tiles[row + stack][x0 + 3] = BOX;
    }
    kg_body_def* bd = &d->bodies[column];
    *bd = kg_default_body_def();
    int circle = kind == 3 || next_random(rng) % 2u == 0u;
    float half_height;
    if (circle) {
        half_height = random_range(rng, 0.1f, 0.3f);
        bd->shape = kg_circle_shape(half_height);
    } else {
        float width = random_range(rng, 0.3f, 0.6f);
        half_height = 0.5f * width * random_range(rng, 0.4f, 0.7f);
        bd->shape = kg_box_shape(width, 2.0f * half_height);
        bd->angle = random_range(rng, -0.05f, 0.05f);
    }
    float x = kind == 3 ? 2.0f + random_range(rng, -0.3f, 0.3f) : 1.5f + random_range(rng, -0.1f, 0.1f);
    bd->position = (kg_vec2){(float)x0 + x, top + half_height + random_range(rng, 0.1f, 0.6f)};
}

static kg_world* drop_world(const drop_layout* d, int as_tiles, kg_body* bodies)
{
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    def.max_bodies = 16384;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    kg_tile_shape shapes[SHAPE_COUNT];
    standard_shapes(shapes);
    if (as_tiles) {
        kg_tilemap_def md = kg_default_tilemap_def();
        md.width = DROP_MAP_WIDTH;
        md.height = DROP_MAP_HEIGHT;
        md.shapes = shapes;
        md.shape_count = SHAPE_COUNT;
        md.tiles = &d->tiles[0][0];
        kg_tilemap map;
        KG_CHECK_OK(kg_create_tilemap(w, &md, &map));
    } else {
        for (int y = 0; y < DROP_MAP_HEIGHT; ++y) {
            for (int x = 0; x < DROP_MAP_WIDTH; ++x) {
                const kg_tile_shape* ts = &shapes[d->tiles[y][x]];
                if (ts->type == KG_TILE_SHAPE_POLYGON) {
                    add_body(w, KG_BODY_STATIC, kg_polygon_shape(ts->vertices, ts->count),
                             (kg_vec2){(float)x, (float)y}, 0.0f, (kg_vec2){0.0f, 0.0f}, 0.6f);
                }
            }
        }
    }
    for (int i = 0; i < DROP_COLUMNS; ++i) {
        KG_CHECK_OK(kg_create_body(w, &d->bodies[i], &bodies[i]));
    }
    return w;
}

static void test_resting_heights_match_static_polygons(void)
{
    static drop_layout d;
    memset(&d, 0, sizeof d);
    uint32_t rng = 12345u;
    for (int i = 0; i < DROP_COLUMNS; ++i) {
        layout_column(&d, i, &rng);
    }
    static kg_body tiled_bodies[DROP_COLUMNS], static_bodies[DROP_COLUMNS];
    kg_world* tiled = drop_world(&d, 1, tiled_bodies);
    kg_world* polygons = drop_world(&d, 0, static_bodies);
    for (int step = 0; step < 120; ++step) {
        KG_CHECK_OK(kg_world_step(tiled, DT));
        KG_CHECK_OK(kg_world_step(polygons, DT));
    }
    double worst = 0.0, sum = 0.0, fastest = 0.0;
    int worst_body = 0;
    for (int i = 0; i < DROP_COLUMNS; ++i) {
        kg_body_state a = state_of(tiled, tiled_bodies[i]), b = state_of(polygons, static_bodies[i]);
        double dy = fabs((double)a.position.y - (double)b.position.y);
        sum += dy;
        if (dy > worst) {
            worst = dy;
            worst_body = i;
        }
        fastest = fmax(fastest, fmax(hypot(a.velocity.x, a.velocity.y), hypot(b.velocity.x, b.velocity.y)));
    }
    printf("measured: 1000 drops after 2 s, tile map vs static polygons: resting height difference mean %.3g m, "
           "largest %.3g m (body %d), fastest body %.3g m/s\n", sum / DROP_COLUMNS, worst, worst_body, fastest);
    KG_CHECK(worst <= 1e-3);
    KG_CHECK(fastest < 0.05);
    kg_destroy_world(tiled);
    kg_destroy_world(polygons);
}

/* ---- one-way platforms ---- */

/* Floor at y = 1 (row 0), a row of platforms in row 3: the slab y in [3.5, 4], surface 4. */
static kg_world* platform_world(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, -10.0f});
    kg_tilemap map = make_map(w, 12, 8, (kg_vec2){0.0f, 0.0f});
    for (int x = 0; x < 12; ++x) {
        KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, x, 0, BOX));
        if (x >= 2 && x < 10) {
            KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, x, 3, PLATFORM));
        }
    }
    return w;
}

static void test_one_way_platform_lets_a_jump_through_and_holds_a_fall(void)
{
    kg_world* w = platform_world();
    /* from the floor at 9 m/s: apex 4.05 m above the start, well clear of the platform */
    kg_body jumper = add_body(w, KG_BODY_DYNAMIC, kg_box_shape(0.5f, 0.5f), (kg_vec2){4.0f, 1.25f}, 0.0f,
                              (kg_vec2){0.0f, 9.0f}, 0.6f);
    kg_body ball = add_body(w, KG_BODY_DYNAMIC, kg_circle_shape(0.3f), (kg_vec2){6.0f, 1.3f}, 0.0f,
                            (kg_vec2){0.0f, 9.0f}, 0.6f);
    kg_body faller = add_body(w, KG_BODY_DYNAMIC, kg_box_shape(0.5f, 0.5f), (kg_vec2){8.0f, 7.0f}, 0.0f,
                              (kg_vec2){0.0f, 0.0f}, 0.6f);
    /* a weak jump whose top gets into the slab but whose bottom never clears it */
    kg_body short_jump = add_body(w, KG_BODY_DYNAMIC, kg_box_shape(0.5f, 0.5f), (kg_vec2){3.0f, 1.25f}, 0.0f,
                                  (kg_vec2){0.0f, 7.0f}, 0.6f);
    double apex = 0.0, worst_rise_error = 0.0, short_apex = 0.0;
    for (int step = 0; step < 180; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_body_state s = state_of(w, jumper);
        apex = fmax(apex, s.position.y);
        if (s.velocity.y > 0.0f) {
            /* rising freely: on the sub-stepped integrator's exact trajectory */
            double expected = 9.0 - 10.0 * DT * (step + 1);
            worst_rise_error = fmax(worst_rise_error, fabs(s.velocity.y - expected));
        }
        short_apex = fmax(short_apex, state_of(w, short_jump).position.y);
    }
    kg_body_state js = state_of(w, jumper), bs = state_of(w, ball), fs = state_of(w, faller);
    kg_body_state ss = state_of(w, short_jump);
    printf("measured: one-way platform (surface y = 4): jumper apex %.3f m, rising speed off free flight by at most "
           "%.3g m/s, rests at %.4f (expected 4.25); ball rests at %.4f (4.3); faller rests at %.4f (4.25); short "
           "jump apex %.3f, back on the floor at %.4f (1.25)\n", apex, worst_rise_error, js.position.y,
           bs.position.y, fs.position.y, short_apex, ss.position.y);
    KG_CHECK(apex > 5.0);
    KG_CHECK(worst_rise_error < 1e-4);
    KG_CHECK_NEAR(js.position.y, 4.25, 0.01);
    KG_CHECK_NEAR(bs.position.y, 4.3, 0.01);
    KG_CHECK_NEAR(fs.position.y, 4.25, 0.01);
    KG_CHECK(short_apex > 3.3 && short_apex < 3.75);
    KG_CHECK_NEAR(ss.position.y, 1.25, 0.01);
    kg_destroy_world(w);
}

/* ---- changing tiles at run time ---- */

static void test_resting_box_falls_when_its_tile_is_dug_out(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, -10.0f});
    kg_tilemap map = make_map(w, 5, 3, (kg_vec2){0.0f, -1.0f});
    for (int x = 0; x < 5; ++x) {
        KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, x, 1, BOX));
    }
    kg_body box = add_body(w, KG_BODY_DYNAMIC, kg_box_shape(0.6f, 0.6f), (kg_vec2){2.5f, 1.3f}, 0.0f,
                           (kg_vec2){0.0f, 0.0f}, 0.6f);
    for (int step = 0; step < 60; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_body_state rest = state_of(w, box);
    int layer = -1, x = -1, y = -1;
    KG_CHECK(kg_world_contact_count(w) == 1);
    KG_CHECK_OK(kg_world_get_contact_tile(w, 0, NULL, &layer, &x, &y));
    KG_CHECK(layer == 0 && x == 2 && y == 1);
    /* the contact, warm started step after step, carries the weight: m g h per sub-step */
    kg_contact_info info;
    kg_mass_data mass;
    KG_CHECK_OK(kg_world_get_contact(w, 0, &info));
    KG_CHECK_OK(kg_body_get_mass_data(w, box, &mass));
    KG_CHECK(info.point_count == 2);
    double h = DT / kg_world_get_def(w)->substeps;
    KG_CHECK_NEAR(info.normal_impulses[0] + info.normal_impulses[1], mass.mass * 10.0 * h, 1e-3 * mass.mass * h);
    KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, 2, 1, EMPTY));
    for (int step = 0; step < 30; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_body_state fallen = state_of(w, box);
    printf("measured: box resting at y = %.4f on tile (2, 1); 0.5 s after digging it out: y = %.4f, vy = %.3f\n",
           rest.position.y, fallen.position.y, fallen.velocity.y);
    KG_CHECK_NEAR(rest.position.y, 1.3, 1e-3);
    /* nothing below: in free fall since the tile went, 1.25 m in 0.5 s */
    KG_CHECK_NEAR(fallen.position.y, 1.3 - 1.25, 0.02);
    KG_CHECK_NEAR(fallen.velocity.y, -5.0, 0.01);
    kg_destroy_world(w);
}

static void test_tile_built_over_a_body_lifts_it_out(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, -10.0f});
    kg_tilemap map = make_map(w, 5, 4, (kg_vec2){0.0f, 0.0f});
    for (int x = 0; x < 5; ++x) {
        KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, x, 0, BOX));
        KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, x, 1, x == 2 ? EMPTY : BOX));
    }
    kg_body box = add_body(w, KG_BODY_DYNAMIC, kg_box_shape(0.6f, 0.6f), (kg_vec2){2.5f, 2.6f}, 0.0f,
                           (kg_vec2){0.0f, 0.0f}, 0.6f);
    for (int step = 0; step < 60; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_body_state in_pit = state_of(w, box);
    KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, 2, 1, BOX));
    for (int step = 0; step < 60; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_body_state lifted = state_of(w, box);
    printf("measured: box in a pit at y = %.4f; 1 s after filling the pit: y = %.4f (expected 2.3)\n",
           in_pit.position.y, lifted.position.y);
    KG_CHECK_NEAR(in_pit.position.y, 1.3, 1e-3);
    KG_CHECK_NEAR(lifted.position.y, 2.3, 1e-3);
    kg_destroy_world(w);
}

/* ---- seams ---- */

/* A box sliding along a flat run: every contact's normal is straight down (body to tile);
 * none comes from the vertical edges between the tiles. */
static void test_no_contact_comes_from_an_interior_edge(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, -10.0f});
    kg_tilemap map = make_map(w, 40, 1, (kg_vec2){0.0f, -1.0f});
    build_run(w, map, FLAT, 40);
    kg_body box = add_body(w, KG_BODY_DYNAMIC, kg_box_shape(1.0f, 0.5f), (kg_vec2){1.5f, 0.25f}, 0.0f,
                           (kg_vec2){3.0f, 0.0f}, 0.0f);
    double worst = 0.0;
    int tile_contacts = 0;
    for (int step = 0; step < 600; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        for (int c = 0; c < kg_world_contact_count(w); ++c) {
            kg_contact_info info;
            KG_CHECK_OK(kg_world_get_contact(w, c, &info));
            worst = fmax(worst, fabs(info.normal.x) + fabs(info.normal.y + 1.0f));
            tile_contacts += 1;
        }
    }
    printf("measured: box sliding over 30 of 40 flat tiles: %d tile contacts, largest deviation of a normal from "
           "straight down %.3g, ended at x = %.2f\n", tile_contacts, worst, state_of(w, box).position.x);
    KG_CHECK(tile_contacts > 600);
    KG_CHECK(worst < 1e-6);
    kg_destroy_world(w);
}

/* A box resting on a tile tilts a little either way, and the reference passes between
 * the tile's edge and the box's face: the points' feature ids must not change with it
 * (they name a vertex of each, on the point's side), or the contact starts cold (the
 * same rule as between two bodies, test_narrowphase). */
static void test_tile_contact_ids_survive_a_reference_switch(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, 0.0f});
    /* one tile, and a box wider than it, so that the box's face can be the better axis */
    kg_tilemap map = make_map(w, 1, 1, (kg_vec2){0.0f, -1.0f});
    build_run(w, map, FLAT, 1);
    kg_body box = add_body(w, KG_BODY_DYNAMIC, kg_box_shape(1.6f, 0.6f), (kg_vec2){0.5f, 0.299f}, 0.0f,
                           (kg_vec2){0.0f, 0.0f}, 0.6f);
    uint32_t rng = 0x7E57u, first[2] = {0u, 0u};
    int steady = 1, by_tile = 0, by_box = 0, trials = 0;
    for (int k = 0; k < 400; ++k) {
        KG_CHECK_OK(kg_body_set_transform(w, box, (kg_vec2){0.5f, 0.299f}, random_range(&rng, -0.004f, 0.004f)));
        KG_CHECK_OK(kg_body_set_velocity(w, box, (kg_vec2){0.0f, 0.0f}));
        KG_CHECK_OK(kg_body_set_angular_velocity(w, box, 0.0f));
        KG_CHECK_OK(kg_world_step(w, DT));
        KG_CHECK(kg_world_contact_count(w) == 1);
        kg_contact_info info;
        KG_CHECK_OK(kg_world_get_contact(w, 0, &info));
        KG_CHECK(info.point_count == 2);
        if (info.point_count != 2) {
            continue;
        }
        int tile_face = fabsf(info.normal.x) < 1e-7f;
        by_tile += tile_face;
        by_box += !tile_face;
        int left = info.points[0].x < info.points[1].x ? 0 : 1;
        uint32_t ids[2] = {info.feature_ids[left], info.feature_ids[1 - left]};
        if (trials++ == 0) {
            first[0] = ids[0];
            first[1] = ids[1];
        }
        steady &= ids[0] == first[0] && ids[1] == first[1];
    }
    printf("measured: box on a tile tilted at random: the tile's edge the reference %d times, the box's face %d times; "
           "ids steady: %s\n", by_tile, by_box, steady ? "yes" : "no");
    KG_CHECK(by_tile > 20 && by_box > 20);
    KG_CHECK(steady);
    kg_destroy_world(w);
}

/* A wall of stacked tiles stops a box: the exposed side faces do make contacts. (A
 * frictionless box keeps the small speed the push-out of its impact gave it, as it would
 * against static bodies.) */
static void test_exposed_wall_stops_a_sliding_box(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, -10.0f});
    kg_tilemap map = make_map(w, 20, 4, (kg_vec2){0.0f, -1.0f});
    build_run(w, map, FLAT, 20);
    for (int y = 1; y < 4; ++y) {
        KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, 15, y, BOX));
    }
    kg_body box = add_body(w, KG_BODY_DYNAMIC, kg_box_shape(0.5f, 0.5f), (kg_vec2){2.0f, 0.25f}, 0.0f,
                           (kg_vec2){8.0f, 0.0f}, 0.0f);
    double farthest = 0.0, wall_normal = 0.0;
    for (int step = 0; step < 120; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        farthest = fmax(farthest, state_of(w, box).position.x);
        for (int c = 0; c < kg_world_contact_count(w); ++c) {
            kg_contact_info info;
            KG_CHECK_OK(kg_world_get_contact(w, c, &info));
            wall_normal = fmax(wall_normal, info.normal.x);
        }
    }
    kg_body_state s = state_of(w, box);
    printf("measured: box sliding at 8 m/s into a wall at x = 15: farthest x %.4f (touching at 14.75), then x %.4f "
           "vx %.3g; wall contact normal x %.3g\n", farthest, s.position.x, s.velocity.x, wall_normal);
    KG_CHECK(farthest < 14.75 + 8.0 * DT);
    KG_CHECK(s.position.x < 14.76 && s.velocity.x <= 0.0f && s.velocity.x > -0.5f);
    KG_CHECK_NEAR(wall_normal, 1.0, 1e-6);
    kg_destroy_world(w);
}

/* ---- several maps and layers ---- */

static void test_several_maps_and_layers(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, -10.0f});
    kg_tile_shape shapes[SHAPE_COUNT];
    standard_shapes(shapes);
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = 4;
    def.height = 2;
    def.layer_count = 2;
    def.shapes = shapes;
    def.shape_count = SHAPE_COUNT;
    def.tile_size = (kg_vec2){0.5f, 0.5f};
    uint16_t tiles[2][2][4] = {{{0, 0, 0, 0}, {0, 0, 0, 0}}, {{BOX, BOX, BOX, BOX}, {0, 0, 0, 0}}};
    def.tiles = &tiles[0][0][0];
    kg_tilemap first, second;
    KG_CHECK_OK(kg_create_tilemap(w, &def, &first));
    def.origin = (kg_vec2){10.0f, 0.0f};
    def.tiles = NULL;
    KG_CHECK_OK(kg_create_tilemap(w, &def, &second));
    KG_CHECK_OK(kg_tilemap_set_tile(w, second, 0, 1, 0, HALF));
    KG_CHECK(kg_world_tilemap_count(w) == 2);
    kg_body a = add_body(w, KG_BODY_DYNAMIC, kg_circle_shape(0.1f), (kg_vec2){1.2f, 2.0f}, 0.0f,
                         (kg_vec2){0.0f, 0.0f}, 0.6f);
    kg_body b = add_body(w, KG_BODY_DYNAMIC, kg_circle_shape(0.1f), (kg_vec2){10.75f, 2.0f}, 0.0f,
                         (kg_vec2){0.0f, 0.0f}, 0.6f);
    for (int step = 0; step < 90; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    KG_CHECK_NEAR(state_of(w, a).position.y, 0.6, 1e-3);  /* layer 1, row 0 of 0.5 m tiles */
    KG_CHECK_NEAR(state_of(w, b).position.y, 0.35, 1e-3); /* a half of a 0.5 m tile */
    int seen_first = 0, seen_second = 0;
    for (int c = 0; c < kg_world_contact_count(w); ++c) {
        kg_tilemap map;
        int layer, x, y;
        KG_CHECK_OK(kg_world_get_contact_tile(w, c, &map, &layer, &x, &y));
        seen_first |= map.index == first.index && layer == 1 && x == 2 && y == 0;
        seen_second |= map.index == second.index && layer == 0 && x == 1 && y == 0;
    }
    KG_CHECK(seen_first && seen_second);
    KG_CHECK_OK(kg_destroy_tilemap(w, first));
    KG_CHECK(!kg_tilemap_is_valid(w, first));
    KG_CHECK(kg_tilemap_set_tile(w, first, 0, 0, 0, BOX) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK(kg_world_tilemap_count(w) == 1);
    KG_CHECK_OK(kg_world_step(w, DT));
    kg_destroy_world(w);
}

/* ---- the API's checks ---- */

static void test_bad_definitions_and_cells_are_refused(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, -10.0f});
    kg_tile_shape shapes[3] = {kg_tile_empty(), kg_tile_box(), kg_tile_box()};
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = 8;
    def.height = 8;
    def.shapes = shapes;
    def.shape_count = 3;
    kg_tilemap map;
    kg_vec2 outside[3] = {{0.0f, 0.0f}, {1.5f, 0.0f}, {0.0f, 1.0f}};
    shapes[2] = kg_tile_polygon(outside, 3);
    KG_CHECK(kg_create_tilemap(w, &def, &map) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(strstr(kg_last_error(), "tile id 2") != NULL);
    kg_vec2 line[3] = {{0.0f, 0.0f}, {0.5f, 0.5f}, {1.0f, 1.0f}};
    shapes[2] = kg_tile_polygon(line, 3);
    KG_CHECK(kg_create_tilemap(w, &def, &map) == KG_ERROR_DEGENERATE_SHAPE);
    shapes[2] = kg_tile_circle((kg_vec2){0.5f, 0.5f}, 0.4f);
    shapes[0] = kg_tile_box();
    KG_CHECK(kg_create_tilemap(w, &def, &map) == KG_ERROR_INVALID_ARGUMENT);
    shapes[0] = kg_tile_empty();
    def.width = 0;
    KG_CHECK(kg_create_tilemap(w, &def, &map) == KG_ERROR_INVALID_ARGUMENT);
    def.width = 8;
    def.tile_size.x = NAN;
    KG_CHECK(kg_create_tilemap(w, &def, &map) == KG_ERROR_INVALID_ARGUMENT);
    def.tile_size.x = 1.0f;
    uint16_t tiles[64] = {7};
    def.tiles = tiles;
    KG_CHECK(kg_create_tilemap(w, &def, &map) == KG_ERROR_INVALID_ARGUMENT);
    def.tiles = NULL;
    KG_CHECK_OK(kg_create_tilemap(w, &def, &map));
    KG_CHECK(kg_tilemap_set_tile(w, map, 0, 8, 0, 1) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_tilemap_set_tile(w, map, 1, 0, 0, 1) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_tilemap_set_tile(w, map, 0, 0, 0, 3) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, 7, 7, 2));
    int id = -1, x = -1, y = -1;
    KG_CHECK_OK(kg_tilemap_get_tile(w, map, 0, 7, 7, &id));
    KG_CHECK(id == 2);
    KG_CHECK_OK(kg_tilemap_cell_at(w, map, (kg_vec2){7.5f, 0.25f}, &x, &y));
    KG_CHECK(x == 7 && y == 0);
    KG_CHECK(kg_tilemap_cell_at(w, map, (kg_vec2){-0.5f, 0.25f}, &x, &y) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_tilemap_cell_at(w, map, (kg_vec2){1e30f, 0.25f}, &x, &y) == KG_ERROR_INVALID_ARGUMENT);
    kg_tilemap stale = {map.index, map.generation + 2u};
    KG_CHECK(kg_tilemap_get_tile(w, stale, 0, 0, 0, &id) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK(kg_create_tilemap(NULL, &def, &map) == KG_ERROR_INVALID_ARGUMENT);
    kg_destroy_world(w);
}

/* Line-buffered, so that each result shows as soon as its test ends (and is not lost when a
 * sanitizer report aborts a later one). */
__attribute__((constructor)) static void flush_every_line(void) { setvbuf(stdout, NULL, _IOLBF, 0); }

KG_TEST_MAIN(KG_TEST(test_box_and_circle_slide_across_200_flat_tiles),
             KG_TEST(test_box_and_circle_slide_across_200_slope_tiles),
             KG_TEST(test_box_and_circle_slide_across_gentle_slope_and_half_tiles),
             KG_TEST(test_slides_on_the_opencl_backend),
             KG_TEST(test_resting_heights_match_static_polygons),
             KG_TEST(test_one_way_platform_lets_a_jump_through_and_holds_a_fall),
             KG_TEST(test_resting_box_falls_when_its_tile_is_dug_out),
             KG_TEST(test_tile_built_over_a_body_lifts_it_out),
             KG_TEST(test_no_contact_comes_from_an_interior_edge),
             KG_TEST(test_tile_contact_ids_survive_a_reference_switch), KG_TEST(test_exposed_wall_stops_a_sliding_box),
             KG_TEST(test_several_maps_and_layers), KG_TEST(test_bad_definitions_and_cells_are_refused))
