/* Continuous collision: small boxes and circles fired at 30 to 1,000 m/s never pass a
 * static wall 0.2 m thick, a tile-map wall of 0.2 m tiles nor a chain (one-sided
 * segments, no thickness at all), bullets at 300 m/s never
 * pass a free dynamic plank 0.2 m thick; with continuous collision off most of them do
 * (so the tests can fail); the results are the same bits on 1, 2 and 4 threads. Every
 * test prints what it measured. */
#include "kg_test.h"
#include "kgyro/kgyro.h"
#include "kgyro/scene.h"

#include <stdint.h>
#include <string.h>

#define DT (1.0f / 60.0f)

static kg_vec2 kg_v2(float x, float y) { return (kg_vec2){x, y}; }
#define SHOTS 100       /* 50 boxes then 50 circles */
#define WALL_X 5.0f     /* the near face of every wall */
#define THICKNESS 0.2f
#define BULLET_SPEED 300.0f
#define START_X -0.3f /* not a whole number of steps from the wall at 300 m/s */
#define LANE 0.5f       /* vertical spacing of the shots: they never meet */

static kg_world* make_world(int continuous, int threads)
{
    kg_world_def def = kg_default_world_def();
    def.gravity = kg_v2(0.0f, 0.0f);
    def.backend = KG_BACKEND_CPU;
    def.max_bodies = 512;
    def.max_linear_speed = 2000.0f; /* the shots reach 1,000 m/s */
    def.enable_continuous = continuous;
    def.threads = threads;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    return w;
}

static float shot_speed(int k) { return 30.0f + (1000.0f - 30.0f) * (float)(k % 50) / 49.0f; }

/* Shot k: a 0.1 m box (k < 50) or a 0.05 m radius circle, in its lane, fired at the wall. */
static kg_body fire(kg_world* w, int k, float speed, int bullet)
{
    kg_body_def d = kg_default_body_def();
    d.shape = k < 50 ? kg_box_shape(0.1f, 0.1f) : kg_circle_shape(0.05f);
    d.position = kg_v2(START_X, LANE * (float)k);
    d.velocity = kg_v2(speed, 0.0f);
    d.bullet = bullet;
    kg_body b;
    KG_CHECK_OK(kg_create_body(w, &d, &b));
    return b;
}

static void static_wall(kg_world* w)
{
    kg_body_def d = kg_default_body_def();
    d.type = KG_BODY_STATIC;
    d.shape = kg_box_shape(THICKNESS, LANE * SHOTS + 2.0f);
    d.position = kg_v2(WALL_X + 0.5f * THICKNESS, 0.5f * LANE * SHOTS);
    kg_body b;
    KG_CHECK_OK(kg_create_body(w, &d, &b));
}

/* One column of 0.2 m box tiles from below the first lane to above the last. */
static void tile_wall(kg_world* w)
{
    enum { ROWS = (int)(LANE * SHOTS / THICKNESS) + 10 };
    static uint16_t tiles[ROWS];
    for (int y = 0; y < ROWS; ++y) {
        tiles[y] = 1;
    }
    kg_tile_shape shapes[2] = {kg_tile_empty(), kg_tile_box()};
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = 1;
    def.height = ROWS;
    def.tile_size = kg_v2(THICKNESS, THICKNESS);
    def.origin = kg_v2(WALL_X, -1.0f);
    def.shapes = shapes;
    def.shape_count = 2;
    def.tiles = tiles;
    kg_tilemap map;
    KG_CHECK_OK(kg_create_tilemap(w, &def, &map));
}

/* A chain from above the last lane down to below the first, in 0.5 m segments (a join at
 * every lane's height, 0.25 m from it): listed downwards, its normal faces the shots. */
static void chain_wall(kg_world* w)
{
    enum { POINTS = (int)(LANE * SHOTS / 0.5f) + 5 };
    kg_vec2 points[POINTS];
    for (int k = 0; k < POINTS; ++k) {
        points[k] = kg_v2(WALL_X, LANE * SHOTS + 1.25f - 0.5f * (float)k);
    }
    kg_body_def d = kg_default_body_def();
    d.type = KG_BODY_STATIC; /* and no shape: the chain is its only one */
    kg_body b;
    KG_CHECK_OK(kg_create_body(w, &d, &b));
    kg_chain_def c = kg_default_chain_def();
    c.points = points;
    c.count = POINTS;
    KG_CHECK_OK(kg_create_chain(w, b, &c, NULL));
}

static kg_body dynamic_plank(kg_world* w)
{
    kg_body_def d = kg_default_body_def();
    d.shape = kg_box_shape(THICKNESS, LANE * SHOTS + 2.0f);
    d.position = kg_v2(WALL_X + 0.5f * THICKNESS, 0.5f * LANE * SHOTS);
    d.density = 5.0f;
    kg_body b;
    KG_CHECK_OK(kg_create_body(w, &d, &b));
    return b;
}

/* Steps a world of SHOTS shots one second and counts those whose centre got past the
 * wall's middle (past = through: nothing else is there), measured across the wall: the
 * plank, when there is one, is pushed and turned by the hits. */
static int count_passed(kg_world* w, const kg_body* shots, const kg_body* plank, float middle)
{
    for (int s = 0; s < 60; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_body_state wall = {{middle, 0.0f}, 0.0f, {0.0f, 0.0f}, 0.0f};
    if (plank) {
        KG_CHECK_OK(kg_body_get_state(w, *plank, &wall));
    }
    int passed = 0;
    for (int k = 0; k < SHOTS; ++k) {
        kg_vec2 p;
        KG_CHECK_OK(kg_body_get_position(w, shots[k], &p));
        float across = cosf(wall.angle) * (p.x - wall.position.x) + sinf(wall.angle) * (p.y - wall.position.y);
        passed += across > 0.0f;
    }
    return passed;
}

/* The wall as 0.2 x 0.5 m static bricks, over a static ground 200 m wide (a large static
 * body in the sweeps' index) and among 100 static pebbles scattered behind the shots. */
static void brick_wall(kg_world* w)
{
    kg_body_def d = kg_default_body_def();
    d.type = KG_BODY_STATIC;
    kg_body b;
    for (int k = 0; k < (int)(LANE * SHOTS / 0.5f) + 4; ++k) {
        d.shape = kg_box_shape(THICKNESS, 0.5f);
        d.position = kg_v2(WALL_X + 0.5f * THICKNESS, -1.0f + 0.25f + 0.5f * (float)k);
        KG_CHECK_OK(kg_create_body(w, &d, &b));
    }
    d.shape = kg_box_shape(200.0f, 1.0f);
    d.position = kg_v2(0.0f, -2.0f);
    KG_CHECK_OK(kg_create_body(w, &d, &b));
    for (int k = 0; k < 100; ++k) {
        d.shape = kg_circle_shape(0.05f);
        d.position = kg_v2(-2.0f - 0.3f * (float)(k % 10), 0.3f + 5.0f * (float)(k / 10));
        KG_CHECK_OK(kg_create_body(w, &d, &b));
    }
}

typedef enum wall_kind { STATIC_WALL, TILE_WALL, PLANK, BRICK_WALL, CHAIN_WALL } wall_kind;

static const char* const wall_names[] = {"static wall", "tile-map wall", "dynamic plank", "wall of static bricks",
                                         "chain wall"};

static int shoot(wall_kind kind, int continuous, int threads, kg_body_state* states)
{
    kg_world* w = make_world(continuous, threads);
    kg_body plank;
    if (kind == STATIC_WALL) {
        static_wall(w);
    } else if (kind == TILE_WALL) {
        tile_wall(w);
    } else if (kind == BRICK_WALL) {
        brick_wall(w);
    } else if (kind == CHAIN_WALL) {
        chain_wall(w);
    } else {
        plank = dynamic_plank(w);
    }
    kg_body shots[SHOTS];
    for (int k = 0; k < SHOTS; ++k) {
        shots[k] = fire(w, k, kind == PLANK ? BULLET_SPEED : shot_speed(k), kind == PLANK);
    }
    float middle = kind == CHAIN_WALL ? WALL_X : WALL_X + 0.5f * THICKNESS;
    int passed = count_passed(w, shots, kind == PLANK ? &plank : NULL, middle);
    if (states) {
        KG_CHECK_OK(kg_world_get_body_states(w, shots, SHOTS, states));
    }
    kg_destroy_world(w);
    return passed;
}

static void none_pass(wall_kind kind)
{
    int passed = shoot(kind, 1, 1, NULL);
    measured("%s: %d of %d shots (%s) passed with continuous collision\n", wall_names[kind], passed, SHOTS,
             kind == PLANK ? "bullets at 300 m/s" : "30 to 1000 m/s");
    KG_CHECK(passed == 0);
}

static void most_pass_without(wall_kind kind)
{
    int passed = shoot(kind, 0, 1, NULL);
    measured("%s: %d of %d shots passed with continuous collision off\n", wall_names[kind], passed, SHOTS);
    KG_CHECK(passed > SHOTS / 2);
}

static void test_static_wall(void) { none_pass(STATIC_WALL); }
static void test_tile_wall(void) { none_pass(TILE_WALL); }
static void test_bullets_and_plank(void) { none_pass(PLANK); }
static void test_brick_wall(void) { none_pass(BRICK_WALL); }
static void test_chain_wall(void) { none_pass(CHAIN_WALL); }
static void test_chain_wall_off(void) { most_pass_without(CHAIN_WALL); }
static void test_brick_wall_off(void) { most_pass_without(BRICK_WALL); }
static void test_static_wall_off(void) { most_pass_without(STATIC_WALL); }
static void test_tile_wall_off(void) { most_pass_without(TILE_WALL); }
static void test_bullets_and_plank_off(void) { most_pass_without(PLANK); }

/* Not bullets: the plank is a dynamic body, which only bullets are swept against. */
static void test_plank_needs_bullets(void)
{
    kg_world* w = make_world(1, 1);
    kg_body plank = dynamic_plank(w);
    kg_body shots[SHOTS];
    for (int k = 0; k < SHOTS; ++k) {
        shots[k] = fire(w, k, BULLET_SPEED, 0);
    }
    int passed = count_passed(w, shots, &plank, 0.0f);
    kg_destroy_world(w);
    measured("dynamic plank: %d of %d shots passed when they are not bullets\n", passed, SHOTS);
    KG_CHECK(passed > SHOTS / 2);
}

static void test_threads_agree(void)
{
    for (int kind = STATIC_WALL; kind <= CHAIN_WALL; ++kind) {
        kg_body_state one[SHOTS], many[SHOTS];
        shoot((wall_kind)kind, 1, 1, one);
        for (int threads = 2; threads <= 4; threads *= 2) {
            shoot((wall_kind)kind, 1, threads, many);
            int same = memcmp(one, many, sizeof one) == 0;
            measured("%s: 1 and %d threads %s\n", wall_names[kind], threads, same ? "bitwise equal" : "DIFFER");
            KG_CHECK(same);
        }
    }
}

/* A shot hitting the wall head on stops just short of it, keeping its velocity for the
 * contact, which then stops it against the face: it ends resting at the face. */
static void test_stops_at_the_face(void)
{
    kg_world* w = make_world(1, 1);
    static_wall(w);
    kg_body b = fire(w, 0, 30.0f, 0); /* a 0.1 m box */
    for (int s = 0; s < 11; ++s) { /* 5.3 m at 30 m/s: the wall is reached in the 11th step */
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_body_state st;
    KG_CHECK_OK(kg_body_get_state(w, b, &st));
    float gap = WALL_X - (st.position.x + 0.05f);
    measured("box at 30 m/s after 11 steps: gap to the wall %.4f m, velocity %.3f m/s\n", gap, st.velocity.x);
    KG_CHECK(gap > 0.0f && gap < 0.01f);
    KG_CHECK(st.velocity.x == 30.0f);
    for (int s = 0; s < 30; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    KG_CHECK_OK(kg_body_get_state(w, b, &st));
    /* the impact may turn the box a little: the gap from its foremost corner */
    gap = WALL_X - (st.position.x + 0.05f * (fabsf(cosf(st.angle)) + fabsf(sinf(st.angle))));
    measured("after 41 steps: gap %.4f m, velocity %.4f m/s, angle %.3f rad\n", gap, st.velocity.x, st.angle);
    KG_CHECK(gap > -0.01f && gap < 0.02f);
    KG_CHECK(fabsf(st.velocity.x) < 0.1f);
    kg_destroy_world(w);
}

/* A frictionless box sliding at 20 m/s along a floor of 1 m tiles, or along a static
 * ground, is never stopped by it: it sinks into the floor by a hair, and the side of the
 * next tile is covered (no ghost impact), the top is not crossed. */
static void slides_freely(int tiles)
{
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    if (tiles) {
        static uint16_t floor_tiles[40];
        for (int x = 0; x < 40; ++x) {
            floor_tiles[x] = 1;
        }
        kg_tile_shape shapes[2] = {kg_tile_empty(), kg_tile_box()};
        kg_tilemap_def td = kg_default_tilemap_def();
        td.width = 40;
        td.height = 1;
        td.origin = kg_v2(-5.0f, -1.0f);
        td.shapes = shapes;
        td.shape_count = 2;
        td.tiles = floor_tiles;
        td.friction = 0.0f;
        kg_tilemap map;
        KG_CHECK_OK(kg_create_tilemap(w, &td, &map));
    } else {
        kg_body_def g = kg_default_body_def();
        g.type = KG_BODY_STATIC;
        g.shape = kg_box_shape(40.0f, 1.0f);
        g.position = kg_v2(15.0f, -0.5f);
        g.friction = 0.0f;
        kg_body ground;
        KG_CHECK_OK(kg_create_body(w, &g, &ground));
    }
    kg_body_def d = kg_default_body_def();
    d.shape = kg_box_shape(0.5f, 0.5f);
    d.position = kg_v2(0.0f, 0.25f);
    d.velocity = kg_v2(20.0f, 0.0f);
    d.friction = 0.0f;
    kg_body box;
    KG_CHECK_OK(kg_create_body(w, &d, &box));
    for (int s = 0; s < 60; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_body_state st;
    KG_CHECK_OK(kg_body_get_state(w, box, &st));
    measured("box sliding at 20 m/s for 1 s along %s: x %.4f m (20 without a stop), vx %.4f m/s\n",
             tiles ? "a floor of tiles" : "a static ground", st.position.x, st.velocity.x);
    KG_CHECK_NEAR(st.position.x, 20.0, 0.01);
    KG_CHECK_NEAR(st.velocity.x, 20.0, 0.01);
    kg_destroy_world(w);
}

static void test_slides_along_tiles(void) { slides_freely(1); }
static void test_slides_along_ground(void) { slides_freely(0); }

/* Bodies that never move fast are not touched: the generated pyramid and tumbler end
 * bitwise as with continuous collision off. */
static void same_without_fast_bodies(const char* name)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_generate(name, 1u, &scene));
    if (!scene) {
        return;
    }
    int n = kg_scene_body_count(scene);
    kg_body* bodies = malloc((size_t)n * sizeof *bodies);
    kg_body_state* states[2] = {malloc((size_t)n * sizeof **states), malloc((size_t)n * sizeof **states)};
    for (int continuous = 0; continuous < 2; ++continuous) {
        kg_world_def def = *kg_scene_world_def(scene);
        def.backend = KG_BACKEND_CPU;
        def.enable_continuous = continuous;
        kg_world* w = NULL;
        KG_CHECK_OK(kg_scene_instantiate(scene, &def, &w, bodies));
        for (int step = 0; step < 120; ++step) {
            KG_CHECK_OK(kg_world_step(w, DT));
        }
        KG_CHECK_OK(kg_world_get_body_states(w, bodies, n, states[continuous]));
        kg_destroy_world(w);
    }
    int same = memcmp(states[0], states[1], (size_t)n * sizeof **states) == 0;
    measured("%s, %d bodies, 120 steps: continuous collision on and off %s\n", name, n,
             same ? "bitwise equal" : "DIFFER");
    KG_CHECK(same);
    free(bodies);
    free(states[0]);
    free(states[1]);
    kg_scene_destroy(scene);
}

static void test_slow_scenes_unchanged(void)
{
    same_without_fast_bodies("pyramid_20");
    same_without_fast_bodies("tumbler");
}

/* The scene format's "bullet" and "continuous", and its refusal of a static bullet. */
static void test_scene_fields(void)
{
    const char* json = "{\"continuous\": false, \"bodies\": [{\"name\": \"shot\", \"bullet\": true, "
                       "\"shape\": {\"type\": \"circle\", \"radius\": 0.1}}]}";
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_parse(json, strlen(json), "bullet.json", &scene));
    if (scene) {
        KG_CHECK(kg_scene_world_def(scene)->enable_continuous == 0);
        kg_world_def def = *kg_scene_world_def(scene);
        kg_world* w = NULL;
        kg_body body;
        KG_CHECK_OK(kg_scene_instantiate(scene, &def, &w, &body));
        KG_CHECK(kg_body_is_bullet(w, body));
        kg_destroy_world(w);
        kg_scene_destroy(scene);
    }
    const char* bad = "{\"bodies\": [{\"type\": \"static\", \"bullet\": true, "
                      "\"shape\": {\"type\": \"circle\", \"radius\": 0.1}}]}";
    KG_CHECK(kg_scene_parse(bad, strlen(bad), "bad.json", &scene) == KG_ERROR_PARSE);
    measured("a static bullet in a scene: %s\n", kg_last_error());
    KG_CHECK(strstr(kg_last_error(), "bodies[0].bullet: only a dynamic body can be a bullet") != NULL);
}

/* A body made in the slot of a destroyed one is swept as itself: a 0.1 m shot fired
 * where a 4 m box lived (whose half extent it moves less than a step) stops at the wall. */
static void test_slot_reused(void)
{
    kg_world* w = make_world(1, 1);
    static_wall(w);
    kg_body_def d = kg_default_body_def();
    d.shape = kg_box_shape(4.0f, 4.0f);
    d.position = kg_v2(-10.0f, 0.0f);
    d.velocity = kg_v2(1.0f, 0.0f);
    kg_body big;
    KG_CHECK_OK(kg_create_body(w, &d, &big));
    KG_CHECK_OK(kg_world_step(w, DT));
    KG_CHECK_OK(kg_destroy_body(w, big));
    kg_body shot = fire(w, 0, 60.0f, 0);
    KG_CHECK(shot.index == big.index);
    for (int s = 0; s < 30; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_vec2 p;
    KG_CHECK_OK(kg_body_get_position(w, shot, &p));
    measured("a 0.1 m shot at 60 m/s in a reused slot: x %.3f (the wall's face at %.1f)\n", p.x, WALL_X);
    KG_CHECK(p.x < WALL_X);
    kg_destroy_world(w);
}

static void test_bullet_flag(void)
{
    kg_world* w = make_world(1, 1);
    kg_body b = fire(w, 0, 30.0f, 0);
    KG_CHECK(!kg_body_is_bullet(w, b));
    KG_CHECK_OK(kg_body_set_bullet(w, b, 1));
    KG_CHECK(kg_body_is_bullet(w, b));
    KG_CHECK_OK(kg_body_set_bullet(w, b, 0));
    KG_CHECK(!kg_body_is_bullet(w, b));
    kg_body_def d = kg_default_body_def();
    d.type = KG_BODY_STATIC;
    d.shape = kg_box_shape(1.0f, 1.0f);
    kg_body wall;
    KG_CHECK_OK(kg_create_body(w, &d, &wall));
    KG_CHECK(kg_body_set_bullet(w, wall, 1) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(strstr(kg_last_error(), "only a dynamic body can be a bullet") != NULL);
    KG_CHECK(!kg_body_is_bullet(w, wall));
    KG_CHECK_OK(kg_body_set_bullet(w, wall, 0));
    d.bullet = 1;
    KG_CHECK(kg_create_body(w, &d, &wall) == KG_ERROR_INVALID_ARGUMENT);
    kg_destroy_world(w);
}

int main(void)
{
    const kg_test_case tests[] = {
        KG_TEST(test_static_wall),      KG_TEST(test_tile_wall),         KG_TEST(test_bullets_and_plank),
        KG_TEST(test_brick_wall),       KG_TEST(test_brick_wall_off),    KG_TEST(test_chain_wall),
        KG_TEST(test_chain_wall_off),
        KG_TEST(test_static_wall_off),  KG_TEST(test_tile_wall_off),     KG_TEST(test_bullets_and_plank_off),
        KG_TEST(test_plank_needs_bullets), KG_TEST(test_threads_agree), KG_TEST(test_stops_at_the_face),
        KG_TEST(test_bullet_flag),      KG_TEST(test_scene_fields),      KG_TEST(test_slides_along_tiles),
        KG_TEST(test_slides_along_ground), KG_TEST(test_slow_scenes_unchanged), KG_TEST(test_slot_reused),
    };
    return kg_run_tests(tests, (int)(sizeof tests / sizeof tests[0]));
}
