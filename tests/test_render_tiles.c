/* Tile maps in the software renderer: a scene's maps drawn through the library's debug
 * draw (kg_world_draw), pixels checked as in test_render.c. Row 0 of a map is
 * at the bottom, tiles are drawn under the bodies, tiles changed at run time show up, and
 * a Tiled level (samples/platformer.tmj) draws its slopes and one-way platforms. */
#include "kg_test.h"

#include "canvas.h"
#include "draw.h"
#include "palette.h"

#include "kgyro/kgyro.h"
#include "kgyro/scene.h"

#include <math.h>
#include <string.h>

/* 10 pixels per metre on a 100 x 100 canvas: world (x, y) is pixel (50 + 10x, 50 - 10y). */
static kg_camera kg_test_camera(void)
{
    return kg_camera_fit((kg_aabb){{-5.0f, -5.0f}, {5.0f, 5.0f}}, 100, 100, 0.0f);
}

/* An 8 x 3 map of 1 m tiles at (-4, -4), cell (x, y) covering pixels 10 + 10x .. 20 + 10x
 * across and 80 - 10y .. 90 - 10y down:
 *   row 2   . . = = . . . .     = one-way platform (the top half)
 *   row 1   # . . . . . . .     # full square
 *   row 0   # # . . X . o .     X a square whose vertices are listed crossed; o a circle
 * and a 0.4 m box body over cell (0, 0). */
static kg_scene* kg_tile_scene(void)
{
    static const uint16_t tiles[24] = {1, 1, 0, 0, 3, 0, 4, 0, /* row 0, the bottom */
                                       1, 0, 0, 0, 0, 0, 0, 0, /* row 1 */
                                       0, 0, 2, 2, 0, 0, 0, 0};
    kg_tile_shape shapes[5] = {kg_tile_empty(), kg_tile_box(), kg_tile_platform(), kg_tile_box(),
                               kg_tile_circle((kg_vec2){0.5f, 0.5f}, 0.4f)};
    static const kg_vec2 crossed[4] = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};
    memcpy(shapes[3].vertices, crossed, sizeof crossed);
    kg_tilemap_def map = kg_default_tilemap_def();
    map.width = 8;
    map.height = 3;
    map.origin = (kg_vec2){-4.0f, -4.0f};
    map.shapes = shapes;
    map.shape_count = 5;
    map.tiles = tiles;
    kg_body_def box = kg_default_body_def();
    box.position = (kg_vec2){-3.5f, -3.5f};
    box.shape = kg_box_shape(0.4f, 0.4f);
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_create(&scene));
    kg_scene_world_def(scene)->gravity = (kg_vec2){0.0f, 0.0f};
    KG_CHECK_OK(kg_scene_add_tilemap(scene, &map));
    KG_CHECK_OK(kg_scene_add_body(scene, "box", &box));
    return scene;
}

typedef struct kg_tile_fixture {
    kg_scene* scene;
    kg_world* world;
    kg_body body;
    kg_canvas canvas;
    kg_camera camera;
} kg_tile_fixture;

static void kg_fixture_open(kg_tile_fixture* f, kg_scene* scene, kg_camera camera)
{
    memset(f, 0, sizeof *f);
    f->scene = scene;
    f->camera = camera;
    kg_world_def def = *kg_scene_world_def(scene);
    def.backend = KG_BACKEND_CPU;
    kg_body bodies[32];
    KG_CHECK(kg_scene_body_count(scene) <= 32);
    KG_CHECK_OK(kg_scene_instantiate(scene, &def, &f->world, bodies));
    f->body = bodies[0];
    KG_CHECK(kg_canvas_init(&f->canvas, camera.width, camera.height) == 0);
}

static void kg_fixture_draw(kg_tile_fixture* f, int tiles)
{
    kg_draw_options options = {0, 0, tiles, 0};
    kg_draw_world(&f->canvas, &f->camera, f->world, &options);
}

static void kg_fixture_close(kg_tile_fixture* f)
{
    kg_canvas_free(&f->canvas);
    kg_destroy_world(f->world);
    kg_scene_destroy(f->scene);
}

static int kg_pixel(const kg_tile_fixture* f, int x, int y) { return kg_canvas_get(&f->canvas, x, y); }

static void test_tiles_where_the_map_says(void)
{
    kg_tile_fixture f;
    kg_fixture_open(&f, kg_tile_scene(), kg_test_camera());
    kg_fixture_draw(&f, 1);
    KG_CHECK(kg_pixel(&f, 15, 75) == KG_COLOR_TILE_FILL);  /* cell (0, 1): row 1 above row 0 */
    KG_CHECK(kg_pixel(&f, 25, 75) == KG_COLOR_BACKGROUND); /* cell (1, 1), empty */
    KG_CHECK(kg_pixel(&f, 25, 85) == KG_COLOR_TILE_FILL);  /* cell (1, 0) */
    KG_CHECK(kg_pixel(&f, 35, 85) == KG_COLOR_BACKGROUND); /* cell (2, 0), empty */
    KG_CHECK(kg_pixel(&f, 35, 62) == KG_COLOR_ONE_WAY_FILL); /* cell (2, 2), top half */
    KG_CHECK(kg_pixel(&f, 35, 68) == KG_COLOR_BACKGROUND);   /* and under it */
    KG_CHECK(kg_pixel(&f, 85, 85) == KG_COLOR_BACKGROUND);   /* right of the map */
    KG_CHECK(kg_pixel(&f, 50, 30) == KG_COLOR_BACKGROUND);   /* above it */
    /* the crossed square is filled whole: its vertices were put in order round it */
    KG_CHECK(kg_pixel(&f, 52, 82) == KG_COLOR_TILE_FILL);
    KG_CHECK(kg_pixel(&f, 58, 82) == KG_COLOR_TILE_FILL);
    KG_CHECK(kg_pixel(&f, 52, 88) == KG_COLOR_TILE_FILL);
    KG_CHECK(kg_pixel(&f, 58, 88) == KG_COLOR_TILE_FILL);
    /* the circle: filled at its centre, not in the cell's corner */
    KG_CHECK(kg_pixel(&f, 75, 85) == KG_COLOR_TILE_FILL);
    KG_CHECK(kg_pixel(&f, 71, 81) == KG_COLOR_BACKGROUND);
    /* the body over cell (0, 0) is drawn on top of the tile, the tile around it */
    KG_CHECK(kg_pixel(&f, 15, 85) == kg_hue_fill(f.body.index));
    KG_CHECK(kg_pixel(&f, 12, 88) == KG_COLOR_TILE_FILL);
    /* tiles off: only the body */
    kg_fixture_draw(&f, 0);
    KG_CHECK(kg_pixel(&f, 15, 75) == KG_COLOR_BACKGROUND);
    KG_CHECK(kg_pixel(&f, 15, 85) == kg_hue_fill(f.body.index));
    kg_fixture_close(&f);
}

static void test_tiles_changed_at_run_time_show_up(void)
{
    kg_tile_fixture f;
    kg_fixture_open(&f, kg_tile_scene(), kg_test_camera());
    kg_tilemap map;
    int count = 0;
    KG_CHECK_OK(kg_world_get_tilemaps(f.world, &map, 1, &count));
    KG_CHECK(count == 1);
    kg_fixture_draw(&f, 1);
    KG_CHECK(kg_pixel(&f, 35, 85) == KG_COLOR_BACKGROUND);
    KG_CHECK_OK(kg_tilemap_set_tile(f.world, map, 0, 2, 0, 1)); /* build at (2, 0) */
    KG_CHECK_OK(kg_tilemap_set_tile(f.world, map, 0, 1, 0, 0)); /* dig at (1, 0) */
    KG_CHECK_OK(kg_world_step(f.world, 1.0f / 60.0f));
    kg_fixture_draw(&f, 1);
    KG_CHECK(kg_pixel(&f, 35, 85) == KG_COLOR_TILE_FILL);
    KG_CHECK(kg_pixel(&f, 25, 85) == KG_COLOR_BACKGROUND);
    kg_fixture_close(&f);
}

/* Tile maps join the camera's default view like static terrain. */
static void test_view_box_holds_the_map(void)
{
    kg_tile_fixture f;
    kg_fixture_open(&f, kg_tile_scene(), kg_test_camera());
    KG_CHECK_OK(kg_destroy_body(f.world, f.body));
    kg_aabb box;
    KG_CHECK(kg_world_view_box(f.world, &box));
    KG_CHECK_NEAR(box.lower.x, -4.0f, 1e-6f);
    KG_CHECK_NEAR(box.lower.y, -4.0f, 1e-6f);
    KG_CHECK_NEAR(box.upper.x, 4.0f, 1e-6f);
    KG_CHECK_NEAR(box.upper.y, -1.0f, 1e-6f);
    kg_fixture_close(&f);
}

/* issue 18: the default framing is the whole level. In samples/platformer.tmj the
 * crates that move are a small part of the map; the view holds the whole map and every
 * body, and no more. */
static void test_view_box_holds_the_whole_level(void)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_load_file(KG_SOURCE_DIR "/samples/platformer.tmj", &scene));
    if (!scene) {
        return;
    }
    kg_tile_fixture f;
    kg_fixture_open(&f, scene, kg_test_camera());
    kg_aabb box;
    KG_CHECK(kg_world_view_box(f.world, &box));
    const kg_tilemap_def* map = kg_scene_get_tilemap(scene, 0);
    kg_aabb expected = {map->origin, {map->origin.x + (float)map->width * map->tile_size.x,
                                      map->origin.y + (float)map->height * map->tile_size.y}};
    int body_count = kg_scene_body_count(scene);
    kg_body bodies[32];
    int got = 0;
    KG_CHECK_OK(kg_world_get_bodies(f.world, bodies, 32, &got));
    KG_CHECK(got == body_count && got > 0);
    for (int i = 0; i < got; ++i) {
        kg_aabb body;
        KG_CHECK_OK(kg_body_get_aabb(f.world, bodies[i], &body));
        expected.lower.x = fminf(expected.lower.x, body.lower.x);
        expected.lower.y = fminf(expected.lower.y, body.lower.y);
        expected.upper.x = fmaxf(expected.upper.x, body.upper.x);
        expected.upper.y = fmaxf(expected.upper.y, body.upper.y);
    }
    KG_CHECK(box.lower.x == expected.lower.x && box.lower.y == expected.lower.y);
    KG_CHECK(box.upper.x == expected.upper.x && box.upper.y == expected.upper.y);
    kg_fixture_close(&f);
}

/* samples/platformer.tmj: 1 m tiles from (0, 0). Cell (8, 2) is a slope rising to the
 * right, (15, 2) the same tile flipped (rising to the left), (7, 2) holds only grass (a
 * tile without a collision shape), and cells 16 to 19 of row 13 are one-way platforms. */
static void test_tiled_level(void)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_load_file(KG_SOURCE_DIR "/samples/platformer.tmj", &scene));
    if (!scene) {
        return;
    }
    kg_tile_fixture f;
    /* x in [6, 16], y in [0, 10]: world (x, y) is pixel (10x - 60, 100 - 10y) */
    kg_fixture_open(&f, scene, kg_camera_fit((kg_aabb){{6.0f, 0.0f}, {16.0f, 10.0f}}, 100, 100, 0.0f));
    kg_fixture_draw(&f, 1);
    KG_CHECK(kg_pixel(&f, 28, 78) == KG_COLOR_TILE_FILL);  /* (8, 2) lower right */
    KG_CHECK(kg_pixel(&f, 22, 72) == KG_COLOR_BACKGROUND); /* (8, 2) upper left */
    KG_CHECK(kg_pixel(&f, 92, 78) == KG_COLOR_TILE_FILL);  /* (15, 2) lower left */
    KG_CHECK(kg_pixel(&f, 98, 72) == KG_COLOR_BACKGROUND); /* (15, 2) upper right */
    KG_CHECK(kg_pixel(&f, 15, 75) == KG_COLOR_BACKGROUND); /* (7, 2): grass only */
    KG_CHECK(kg_pixel(&f, 15, 95) == KG_COLOR_TILE_FILL);  /* (7, 0): ground */
    /* x in [12.5, 22.5], y in [8.5, 18.5]: world (x, y) is pixel (10x - 125, 185 - 10y) */
    f.camera = kg_camera_fit((kg_aabb){{12.5f, 8.5f}, {22.5f, 18.5f}}, 100, 100, 0.0f);
    kg_fixture_draw(&f, 1);
    KG_CHECK(kg_pixel(&f, 50, 47) == KG_COLOR_ONE_WAY_FILL); /* (17, 13), top half */
    KG_CHECK(kg_pixel(&f, 50, 53) == KG_COLOR_BACKGROUND);   /* its bottom half */
    kg_fixture_close(&f);
}

KG_TEST_MAIN(KG_TEST(test_tiles_where_the_map_says), KG_TEST(test_tiles_changed_at_run_time_show_up),
             KG_TEST(test_view_box_holds_the_map), KG_TEST(test_view_box_holds_the_whole_level), KG_TEST(test_tiled_level))
