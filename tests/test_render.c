/* The software renderer (tools/render): pixels of known scenes, the camera, tile layers,
 * text, and GIF and PNG files read back by an independent decoder (stb_image). Nothing
 * here needs contacts to be resolved: bodies are drawn where they are put, or after
 * falling freely. */
#include "kg_test.h"
#include "kg_test_world.h"

#include "canvas.h"
#include "draw.h"
#include "gif.h"
#include "image.h"
#include "palette.h"

#include "kgyro/kgyro.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#if KG_RENDER_HAVE_PNG
#include <stb_image.h>
#endif

/* 10 pixels per metre on a 100 x 100 canvas: world (0, 0) is pixel (50, 50), and world
 * (x, y) is pixel centre (50 + 10x, 50 - 10y) give or take half a pixel. */
static kg_camera kg_test_camera(void)
{
    return kg_camera_fit((kg_aabb){{-5.0f, -5.0f}, {5.0f, 5.0f}}, 100, 100, 0.0f);
}

static void kg_draw_plain(kg_canvas* canvas, const kg_world* world, int aabbs)
{
    kg_camera camera = kg_test_camera();
    kg_draw_options options = {0, aabbs, 1, 0};
    kg_draw_world(canvas, &camera, world, &options);
}

static void test_camera_maps_both_ways(void)
{
    kg_camera camera = kg_test_camera();
    KG_CHECK_NEAR(camera.scale, 10.0f, 1e-5);
    kg_point p = kg_camera_to_screen(&camera, (kg_vec2){2.0f, 3.0f});
    KG_CHECK_NEAR(p.x, 70.0f, 1e-4);
    KG_CHECK_NEAR(p.y, 20.0f, 1e-4);
    kg_vec2 back = kg_camera_to_world(&camera, p);
    KG_CHECK_NEAR(back.x, 2.0f, 1e-5);
    KG_CHECK_NEAR(back.y, 3.0f, 1e-5);

    /* a wide box on a square canvas: the width decides the scale, the box stays centred */
    kg_camera wide = kg_camera_fit((kg_aabb){{0.0f, 0.0f}, {20.0f, 5.0f}}, 100, 100, 0.0f);
    KG_CHECK_NEAR(wide.scale, 5.0f, 1e-5);
    KG_CHECK_NEAR(wide.center.x, 10.0f, 1e-5);
    KG_CHECK_NEAR(wide.center.y, 2.5f, 1e-5);

    kg_point anchor = {30.0f, 40.0f};
    kg_vec2 before = kg_camera_to_world(&camera, anchor);
    kg_camera_zoom_at(&camera, anchor, 2.0f);
    kg_vec2 after = kg_camera_to_world(&camera, anchor);
    KG_CHECK_NEAR(camera.scale, 20.0f, 1e-4);
    KG_CHECK_NEAR(after.x, before.x, 1e-5);
    KG_CHECK_NEAR(after.y, before.y, 1e-5);
}

/* A 2 m box at the origin and a static slab below: fill at the centres, outline on the
 * edge, background around. */
static void test_bodies_fill_their_centres(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, 0.0f});
    kg_body box = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.0f}, 0.0f, kg_box_shape(2.0f, 2.0f));
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, -4.0f}, 0.0f, kg_box_shape(8.0f, 1.0f));
    kg_canvas canvas;
    KG_CHECK(kg_canvas_init(&canvas, 100, 100) == 0);
    kg_draw_plain(&canvas, world, 0);

    KG_CHECK(kg_canvas_get(&canvas, 50, 50) == kg_hue_fill(box.index));
    KG_CHECK(kg_canvas_get(&canvas, 45, 55) == kg_hue_fill(box.index));
    KG_CHECK(kg_canvas_get(&canvas, 40, 50) == kg_hue_line(box.index)); /* left edge, x = -1 m */
    KG_CHECK(kg_canvas_get(&canvas, 50, 90) == KG_COLOR_STATIC_FILL);   /* slab centre, y = -4 m */
    KG_CHECK(kg_canvas_get(&canvas, 10, 90) == KG_COLOR_STATIC_LINE);   /* slab left edge, x = -4 m */
    KG_CHECK(kg_canvas_get(&canvas, 5, 5) == KG_COLOR_BACKGROUND);
    KG_CHECK(kg_canvas_get(&canvas, 50, 30) == KG_COLOR_BACKGROUND);
    KG_CHECK(kg_canvas_get(&canvas, 70, 50) == KG_COLOR_BACKGROUND);
    KG_CHECK(kg_canvas_get(&canvas, 50, 75) == KG_COLOR_BACKGROUND);

    int box_pixels = 0;
    for (int i = 0; i < 100 * 100; ++i) {
        box_pixels += canvas.pixels[i] == kg_hue_fill(box.index) || canvas.pixels[i] == kg_hue_line(box.index);
    }
    KG_CHECK(box_pixels >= 20 * 20 && box_pixels <= 21 * 21); /* 2 m = 20 px square */
    kg_canvas_free(&canvas);
    kg_destroy_world(world);
}

/* A capsule 4 m long overall (core from x = -1 to 1, radius 1) and a static segment below:
 * the capsule fills its round ends and its middle, not the corners its box would have;
 * the segment is its line alone. */
static void test_capsules_and_segments(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, 0.0f});
    kg_body capsule = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 1.0f}, 0.0f,
                             kg_capsule_shape((kg_vec2){-1.0f, 0.0f}, (kg_vec2){1.0f, 0.0f}, 1.0f));
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, -3.0f}, 0.0f, kg_segment_shape((kg_vec2){-4.0f, 0.0f}, (kg_vec2){4.0f, 0.0f}));
    kg_canvas canvas;
    KG_CHECK(kg_canvas_init(&canvas, 100, 100) == 0);
    kg_draw_plain(&canvas, world, 0);
    KG_CHECK(kg_canvas_get(&canvas, 50, 45) == kg_hue_fill(capsule.index)); /* middle, above the core line */
    KG_CHECK(kg_canvas_get(&canvas, 33, 40) == kg_hue_fill(capsule.index)); /* left end, (-1.7, 1) */
    KG_CHECK(kg_canvas_get(&canvas, 67, 43) == kg_hue_fill(capsule.index)); /* right end, (1.7, 0.7) */
    KG_CHECK(kg_canvas_get(&canvas, 50, 40) == kg_hue_line(capsule.index)); /* the core's line */
    KG_CHECK(kg_canvas_get(&canvas, 30, 30) == KG_COLOR_BACKGROUND);        /* its box's corner, (-1.95, 1.95) */
    KG_CHECK(kg_canvas_get(&canvas, 50, 80) == KG_COLOR_STATIC_LINE);       /* the segment at y = -3 */
    KG_CHECK(kg_canvas_get(&canvas, 50, 78) == KG_COLOR_BACKGROUND);
    KG_CHECK(kg_canvas_get(&canvas, 50, 82) == KG_COLOR_BACKGROUND);
    kg_canvas_free(&canvas);
    kg_destroy_world(world);
}

/* A chain of 100 segments of 0.08 m along y = -2 is drawn to its last segment (a body's
 * shapes beyond the 64 that fit the stack are drawn too). */
static void test_long_chain(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, 0.0f});
    kg_body_def def = kg_default_body_def();
    def.type = KG_BODY_STATIC;
    kg_body ground = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(world, &def, &ground));
    kg_vec2 points[101];
    for (int i = 0; i <= 100; ++i) {
        points[i] = (kg_vec2){4.0f - 0.08f * (float)i, -2.0f};
    }
    kg_chain_def chain = kg_default_chain_def();
    chain.points = points;
    chain.count = 101;
    KG_CHECK_OK(kg_create_chain(world, ground, &chain, NULL));
    kg_canvas canvas;
    KG_CHECK(kg_canvas_init(&canvas, 100, 100) == 0);
    kg_draw_plain(&canvas, world, 0);
    for (int x = 12; x <= 88; x += 4) { /* world x from -3.8 to 3.8 */
        KG_CHECK(kg_canvas_get(&canvas, x, 70) == KG_COLOR_STATIC_LINE);
    }
    KG_CHECK(kg_canvas_get(&canvas, 50, 68) == KG_COLOR_BACKGROUND);
    kg_canvas_free(&canvas);
    kg_destroy_world(world);
}

/* A body is drawn where the world has moved it: one second of free fall. */
static void test_bodies_are_drawn_at_their_pose(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, -10.0f});
    kg_body ball = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){-2.0f, 3.0f}, 0.0f, kg_circle_shape(0.8f));
    for (int i = 0; i < 60; ++i) {
        KG_CHECK_OK(kg_world_step(world, 1.0f / 60.0f));
    }
    kg_vec2 at;
    KG_CHECK_OK(kg_body_get_position(world, ball, &at));
    KG_CHECK(at.y < -1.5f && at.y > -2.5f);
    kg_canvas canvas;
    KG_CHECK(kg_canvas_init(&canvas, 100, 100) == 0);
    kg_draw_plain(&canvas, world, 0);
    kg_camera camera = kg_test_camera();
    kg_point now = kg_camera_to_screen(&camera, (kg_vec2){at.x, at.y - 0.4f}); /* below the radius line */
    KG_CHECK(kg_canvas_get(&canvas, (int)now.x, (int)now.y) == kg_hue_fill(ball.index));
    KG_CHECK(kg_canvas_get(&canvas, 30, 20) == KG_COLOR_BACKGROUND); /* where it started */
    kg_canvas_free(&canvas);
    kg_destroy_world(world);
}

/* A box turned by 45 degrees: its bounding box corner lies outside the body. */
static void test_bounding_boxes_and_rotation(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, 0.0f});
    kg_body box = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.0f}, 0.78539816f, kg_box_shape(4.0f, 4.0f));
    kg_canvas canvas;
    KG_CHECK(kg_canvas_init(&canvas, 100, 100) == 0);
    kg_draw_plain(&canvas, world, 0);
    KG_CHECK(kg_canvas_get(&canvas, 50, 50) == kg_hue_fill(box.index));
    KG_CHECK(kg_canvas_get(&canvas, 50, 25) == kg_hue_fill(box.index)); /* the top corner, 2.83 m up */
    KG_CHECK(kg_canvas_get(&canvas, 33, 33) == KG_COLOR_BACKGROUND);   /* where an upright box would be */

    kg_draw_plain(&canvas, world, 1);
    kg_aabb aabb;
    KG_CHECK_OK(kg_body_get_aabb(world, box, &aabb));
    kg_camera camera = kg_test_camera();
    kg_point corner = kg_camera_to_screen(&camera, (kg_vec2){aabb.lower.x, aabb.upper.y});
    KG_CHECK(kg_canvas_get(&canvas, (int)corner.x, (int)corner.y) == KG_COLOR_AABB);
    kg_canvas_free(&canvas);
    kg_destroy_world(world);
}

static void test_particles_and_kinematic_bodies(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, 0.0f});
    kg_body_def def = kg_default_body_def();
    def.type = KG_BODY_PARTICLE;
    def.mass = 1.0f;
    def.position = (kg_vec2){2.0f, 2.0f};
    kg_body particle;
    KG_CHECK_OK(kg_create_body(world, &def, &particle));
    kg_test_add(world, KG_BODY_KINEMATIC, (kg_vec2){-3.0f, -3.0f}, 0.0f, kg_box_shape(1.0f, 1.0f));
    kg_canvas canvas;
    KG_CHECK(kg_canvas_init(&canvas, 100, 100) == 0);
    kg_draw_plain(&canvas, world, 0);
    KG_CHECK(kg_canvas_get(&canvas, 70, 30) == KG_COLOR_PARTICLE);
    KG_CHECK(kg_canvas_get(&canvas, 74, 30) == KG_COLOR_BACKGROUND);
    KG_CHECK(kg_canvas_get(&canvas, 20, 80) == KG_COLOR_KINEMATIC_FILL);
    kg_canvas_free(&canvas);
    kg_destroy_world(world);
}

/* A 4 x 2 map of 1 m tiles at (-2, -2): a full square, a slope rising to the right,
 * an empty cell and a one-way platform (the top quarter of its cell) in the bottom row;
 * a full square above the first. Edges shared by two full squares are not outlined. */
static void test_tile_layer_where_the_map_says(void)
{
    static const kg_vec2 platform[4] = {{0, 0.75f}, {1, 0.75f}, {1, 1}, {0, 1}};
    kg_tile_shape shapes[4] = {kg_tile_empty(), kg_tile_box(), kg_tile_slope(KG_TILE_BOTTOM_RIGHT),
                               kg_tile_polygon(platform, 4)};
    shapes[3].one_way = 1;
    static const uint16_t cells[8] = {1, 2, 0, 3, /* row 0, y in [-2, -1] */
                                      1, 0, 0, 0};
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = 4;
    def.height = 2;
    def.origin = (kg_vec2){-2.0f, -2.0f};
    def.shapes = shapes;
    def.shape_count = 4;
    def.tiles = cells;
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, 0.0f});
    kg_tilemap map;
    KG_CHECK_OK(kg_create_tilemap(world, &def, &map));
    kg_canvas canvas;
    KG_CHECK(kg_canvas_init(&canvas, 100, 100) == 0);
    kg_camera camera = kg_test_camera();
    kg_draw_options options = {0, 0, 1, 0};
    kg_draw_world(&canvas, &camera, world, &options);

    KG_CHECK(kg_canvas_get(&canvas, 35, 65) == KG_COLOR_TILE_FILL);  /* (-1.5, -1.5) full */
    KG_CHECK(kg_canvas_get(&canvas, 35, 55) == KG_COLOR_TILE_FILL);  /* (-1.5, -0.5) full, above */
    KG_CHECK(kg_canvas_get(&canvas, 35, 60) == KG_COLOR_TILE_FILL);  /* their shared edge: hidden */
    KG_CHECK(kg_canvas_get(&canvas, 35, 50) == KG_COLOR_TILE_LINE);  /* the top edge: outlined */
    KG_CHECK(kg_canvas_get(&canvas, 48, 68) == KG_COLOR_TILE_FILL);  /* slope, lower right */
    KG_CHECK(kg_canvas_get(&canvas, 42, 62) == KG_COLOR_BACKGROUND); /* slope, upper left */
    KG_CHECK(kg_canvas_get(&canvas, 55, 65) == KG_COLOR_BACKGROUND); /* empty cell */
    KG_CHECK(kg_canvas_get(&canvas, 65, 61) == KG_COLOR_ONE_WAY_FILL);
    KG_CHECK(kg_canvas_get(&canvas, 65, 67) == KG_COLOR_BACKGROUND); /* under the platform */
    KG_CHECK(kg_canvas_get(&canvas, 85, 65) == KG_COLOR_BACKGROUND); /* right of the map */

    /* scrolled so the map is off screen: nothing is drawn */
    camera.center.x = 100.0f;
    kg_draw_world(&canvas, &camera, world, &options);
    int drawn = 0;
    for (int i = 0; i < 100 * 100; ++i) {
        drawn += canvas.pixels[i] != KG_COLOR_BACKGROUND;
    }
    KG_CHECK(drawn == 0);
    kg_canvas_free(&canvas);
    kg_destroy_world(world);
}

/* The glyph "1" of the 3x5 font: .#. / ##. / .#. / .#. / ### */
static void test_text(void)
{
    kg_canvas canvas;
    KG_CHECK(kg_canvas_init(&canvas, 16, 8) == 0);
    kg_canvas_clear(&canvas, KG_COLOR_BACKGROUND);
    int end = kg_canvas_text(&canvas, 1, 1, 1, "1", KG_COLOR_TEXT);
    KG_CHECK(end == 5);
    KG_CHECK(kg_text_width("abc", 2) == 24);
    static const char* const rows[5] = {".#.", "##.", ".#.", ".#.", "###"};
    for (int y = 0; y < 5; ++y) {
        for (int x = 0; x < 3; ++x) {
            int want = rows[y][x] == '#' ? KG_COLOR_TEXT : KG_COLOR_BACKGROUND;
            KG_CHECK(kg_canvas_get(&canvas, 1 + x, 1 + y) == want);
        }
    }
    kg_canvas_free(&canvas);
}

/* Shapes far off the canvas, and huge ones around it, are clipped without trouble. */
static void test_clipping(void)
{
    kg_canvas canvas;
    KG_CHECK(kg_canvas_init(&canvas, 20, 20) == 0);
    kg_canvas_clear(&canvas, KG_COLOR_BACKGROUND);
    kg_canvas_line(&canvas, (kg_point){-1e9f, -1e9f}, (kg_point){1e9f, 1e9f}, KG_COLOR_TEXT);
    kg_canvas_line(&canvas, (kg_point){-5e5f, 10.5f}, (kg_point){5e5f, 10.5f}, KG_COLOR_NORMAL);
    KG_CHECK(kg_canvas_get(&canvas, 3, 10) == KG_COLOR_NORMAL);
    kg_point huge[4] = {{-5e5f, -5e5f}, {5e5f, -5e5f}, {5e5f, 5e5f}, {-5e5f, 5e5f}};
    kg_canvas_fill_convex(&canvas, huge, 4, KG_COLOR_STATIC_FILL);
    KG_CHECK(kg_canvas_get(&canvas, 0, 0) == KG_COLOR_STATIC_FILL);
    KG_CHECK(kg_canvas_get(&canvas, 19, 19) == KG_COLOR_STATIC_FILL);
    kg_canvas_fill_circle(&canvas, (kg_point){1e30f, 0.0f}, 5.0f, KG_COLOR_TEXT);
    KG_CHECK(kg_canvas_get(&canvas, 19, 0) == KG_COLOR_STATIC_FILL);
    kg_canvas_free(&canvas);
}

#if KG_RENDER_HAVE_PNG

static void kg_temp_path(char* path, size_t size, const char* extension)
{
    const char* dir = getenv("TMPDIR");
    snprintf(path, size, "%s/kg_test_render_%ld.%s", dir && *dir ? dir : "/tmp", (long)getpid(), extension);
}

static unsigned char* kg_read_file(const char* path, int* length)
{
    FILE* file = fopen(path, "rb");
    unsigned char* data = file ? malloc(1 << 22) : NULL;
    *length = data ? (int)fread(data, 1, 1 << 22, file) : 0;
    if (file) {
        fclose(file);
    }
    return data;
}

/* Counts the pixels whose decoded colour is not the palette colour of the canvas. */
static int kg_count_wrong(const unsigned char* rgb, int stride, const kg_canvas* canvas)
{
    int wrong = 0;
    for (int i = 0; i < canvas->width * canvas->height; ++i) {
        kg_rgb want = kg_palette_color(canvas->pixels[i]);
        const unsigned char* got = rgb + (size_t)i * (size_t)stride;
        wrong += got[0] != want.r || got[1] != want.g || got[2] != want.b;
    }
    return wrong;
}

static void test_png_round_trip(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, 0.0f});
    kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){1.0f, 1.0f}, 0.3f, kg_box_shape(3.0f, 2.0f));
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){-2.0f, -2.0f}, 0.0f, kg_circle_shape(1.5f));
    kg_canvas canvas;
    KG_CHECK(kg_canvas_init(&canvas, 100, 100) == 0);
    kg_draw_plain(&canvas, world, 1);
    char path[256];
    kg_temp_path(path, sizeof path, "png");
    KG_CHECK(kg_write_png(path, &canvas) == 0);
    int width = 0, height = 0;
    uint8_t* rgb = kg_read_png_rgb(path, &width, &height);
    KG_CHECK(rgb != NULL && width == 100 && height == 100);
    if (rgb) {
        KG_CHECK(kg_count_wrong(rgb, 3, &canvas) == 0);
    }
    free(rgb);
    remove(path);
    kg_canvas_free(&canvas);
    kg_destroy_world(world);
}

/* Frames of a falling body, a frame that repeats the last one, and a frame of noise that
 * fills the LZW table several times over: each decodes to exactly what was drawn. */
static void test_gif_round_trip(void)
{
    enum { kFrames = 5, kSize = 100 };
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, -10.0f});
    kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 3.0f}, 0.2f, kg_box_shape(2.0f, 1.0f));
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, -4.0f}, 0.0f, kg_box_shape(8.0f, 1.0f));
    kg_canvas frames[kFrames];
    char path[256];
    kg_temp_path(path, sizeof path, "gif");
    kg_gif* gif = kg_gif_open(path, kSize, kSize, kg_palette_rgb());
    KG_CHECK(gif != NULL);
    uint32_t noise = 12345u;
    for (int f = 0; f < kFrames; ++f) {
        KG_CHECK(kg_canvas_init(&frames[f], kSize, kSize) == 0);
        kg_draw_plain(&frames[f], world, 0);
        for (int i = 0; f == kFrames - 1 && i < kSize * kSize; ++i) {
            noise = noise * 1664525u + 1013904223u;
            frames[f].pixels[i] = (uint8_t)((noise >> 24) % 255); /* index 255 is the GIF's own */
        }
        KG_CHECK(gif && kg_gif_add_frame(gif, frames[f].pixels, 4) == 0);
        for (int s = 0; f != 2 && s < 10; ++s) { /* frame 3 repeats frame 2 */
            KG_CHECK_OK(kg_world_step(world, 1.0f / 60.0f));
        }
    }
    KG_CHECK(kg_gif_close(gif) == 0);

    int length, *delays = NULL, width = 0, height = 0, count = 0, channels;
    unsigned char* data = kg_read_file(path, &length);
    unsigned char* decoded = data ? stbi_load_gif_from_memory(data, length, &delays, &width, &height, &count, &channels, 3)
                                  : NULL;
    KG_CHECK(decoded != NULL && width == kSize && height == kSize && count == kFrames);
    for (int f = 0; decoded && f < count && f < kFrames; ++f) {
        KG_CHECK(delays[f] == 40);
        int wrong = kg_count_wrong(decoded + (size_t)f * kSize * kSize * 3, 3, &frames[f]);
        if (wrong != 0) {
            fprintf(stderr, "frame %d: %d pixels differ\n", f, wrong);
        }
        KG_CHECK(wrong == 0);
    }
    stbi_image_free(decoded);
    free(delays);
    free(data);
    remove(path);
    for (int f = 0; f < kFrames; ++f) {
        kg_canvas_free(&frames[f]);
    }
    kg_destroy_world(world);
}

#endif

#if KG_RENDER_HAVE_PNG
#define KG_FILE_TESTS , KG_TEST(test_png_round_trip), KG_TEST(test_gif_round_trip)
#else
#define KG_FILE_TESTS
#endif

KG_TEST_MAIN(KG_TEST(test_camera_maps_both_ways), KG_TEST(test_bodies_fill_their_centres), KG_TEST(test_capsules_and_segments), KG_TEST(test_long_chain),
             KG_TEST(test_bodies_are_drawn_at_their_pose), KG_TEST(test_bounding_boxes_and_rotation),
             KG_TEST(test_particles_and_kinematic_bodies), KG_TEST(test_tile_layer_where_the_map_says),
             KG_TEST(test_text), KG_TEST(test_clipping) KG_FILE_TESTS)
