/* The Tiled loader and the scene format's tilemap section: maps in Tiled's JSON format
 * (tests/data/tiled: embedded and external tilesets, CSV and base64 layers, a group layer,
 * flipped and rotated tiles, every kind of collision object, object layers with custom
 * properties), what they turn into, how the result behaves, and broken files. */
#include "kg_test.h"
#include "kgyro/kgyro.h"
#include "kgyro/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define DATA KG_SOURCE_DIR "/tests/data/tiled/"
#define DT (1.0f / 60.0f)

static kg_scene* load(const char* name)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_load_file(name, &scene));
    return scene;
}

/* The shape of tile id, which must be a polygon, has exactly the expected vertices (any
 * order, any start). */
static int polygon_is(const kg_tile_shape* shape, const kg_vec2* expected, int count)
{
    if (shape->type != KG_TILE_SHAPE_POLYGON || shape->count != count) {
        return 0;
    }
    for (int i = 0; i < count; ++i) {
        int found = 0;
        for (int j = 0; j < count; ++j) {
            found |= fabsf(shape->vertices[j].x - expected[i].x) < 1e-6f &&
                     fabsf(shape->vertices[j].y - expected[i].y) < 1e-6f;
        }
        if (!found) {
            return 0;
        }
    }
    return 1;
}

static int tile_at(const kg_tilemap_def* def, int layer, int x, int y)
{
    return def->tiles[(layer * def->height + y) * def->width + x];
}

/* What tests/data/tiled/embedded.tmj and external.tmj hold (see the comments per check):
 * the scene's first tile map and its bodies. */
static void check_level_contents(const kg_scene* scene)
{
    const kg_tilemap_def* def = kg_scene_get_tilemap(scene, 0);
    if (!def) {
        return;
    }
    /* 12 x 8 tiles of 16 px at the default 16 px per metre; two tile layers */
    KG_CHECK(def->width == 12 && def->height == 8 && def->layer_count == 2);
    KG_CHECK_NEAR(def->tile_size.x, 1.0, 1e-6);
    KG_CHECK_NEAR(def->tile_size.y, 1.0, 1e-6);
    KG_CHECK_NEAR(def->friction, 0.8, 1e-6); /* a map property */
    /* gids 1..16 keep their numbers; three flipped tiles get 17, 18, 19 */
    KG_CHECK(def->shape_count == 20);
    KG_CHECK(tile_at(def, 0, 0, 0) == 1 && tile_at(def, 0, 11, 0) == 1); /* Tiled's last row is the bottom */
    KG_CHECK(tile_at(def, 0, 3, 1) == 2 && tile_at(def, 0, 8, 1) == 4 && tile_at(def, 0, 6, 4) == 5);
    KG_CHECK(tile_at(def, 0, 10, 2) == 6);
    KG_CHECK(tile_at(def, 1, 0, 7) == 9 && def->shapes[9].type == KG_TILE_SHAPE_EMPTY); /* decoration only */
    kg_vec2 box[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    kg_vec2 slope_up[3] = {{0, 0}, {1, 0}, {1, 1}};
    kg_vec2 slope_down[3] = {{0, 0}, {1, 0}, {0, 1}};
    kg_vec2 half[4] = {{0, 0}, {1, 0}, {1, 0.5f}, {0, 0.5f}};
    kg_vec2 platform[4] = {{0, 0.5f}, {1, 0.5f}, {1, 1}, {0, 1}};
    kg_vec2 ceiling_wedge[3] = {{0, 1}, {1, 1}, {1, 0.5f}};
    KG_CHECK(polygon_is(&def->shapes[1], box, 4));
    KG_CHECK(polygon_is(&def->shapes[2], slope_up, 3));
    KG_CHECK(polygon_is(&def->shapes[3], slope_down, 3));
    KG_CHECK(polygon_is(&def->shapes[4], half, 4));
    KG_CHECK(polygon_is(&def->shapes[5], platform, 4) && def->shapes[5].one_way && !def->shapes[4].one_way);
    KG_CHECK(def->shapes[6].type == KG_TILE_SHAPE_CIRCLE);
    KG_CHECK_NEAR(def->shapes[6].radius, 0.25, 1e-6);
    KG_CHECK_NEAR(def->shapes[6].center.x, 0.5, 1e-6);
    KG_CHECK_NEAR(def->shapes[6].center.y, 0.5, 1e-6);
    /* flipped: a slope mirrored left-right, a gentle slope mirrored top-bottom, and a slope
     * turned 90 degrees clockwise (the diagonal and horizontal flags) */
    int mirrored = tile_at(def, 0, 5, 1), upside_down = tile_at(def, 0, 10, 1), turned = tile_at(def, 0, 11, 1);
    KG_CHECK(mirrored >= 17 && upside_down >= 17 && turned >= 17);
    KG_CHECK(mirrored != upside_down && mirrored != turned && upside_down != turned);
    KG_CHECK(polygon_is(&def->shapes[mirrored], slope_down, 3));
    KG_CHECK(polygon_is(&def->shapes[upside_down], ceiling_wedge, 3));
    KG_CHECK(polygon_is(&def->shapes[turned], slope_down, 3));

    /* the object layer: four bodies (the point object is a marker) */
    KG_CHECK(kg_scene_body_count(scene) == 4);
    int crate = kg_scene_find_body(scene, "crate#1"), ball = kg_scene_find_body(scene, "ball#2");
    int wedge = kg_scene_find_body(scene, "wedge#3"), plank = kg_scene_find_body(scene, "plank#5");
    KG_CHECK(crate == 0 && ball == 1 && wedge == 2 && plank == 3);
    if (crate < 0 || ball < 0 || wedge < 0 || plank < 0) {
        return;
    }
    const kg_body_def* c = kg_scene_body_def(scene, crate);
    KG_CHECK(c->type == KG_BODY_DYNAMIC && c->shape.type == KG_SHAPE_POLYGON);
    KG_CHECK_NEAR(c->position.x, 1.5, 1e-6); /* rectangle (16, 16) 16 x 16 px: centre (24, 24) px */
    KG_CHECK_NEAR(c->position.y, 6.5, 1e-6);
    KG_CHECK_NEAR(c->density, 2.0, 1e-6);
    const kg_body_def* b = kg_scene_body_def(scene, ball);
    KG_CHECK(b->shape.type == KG_SHAPE_CIRCLE);
    KG_CHECK_NEAR(b->shape.radius, 0.375, 1e-6);
    KG_CHECK_NEAR(b->position.x, 2.875, 1e-6);
    KG_CHECK_NEAR(b->position.y, 7.125, 1e-6);
    KG_CHECK_NEAR(b->friction, 0.2, 1e-6);
    KG_CHECK_NEAR(b->restitution, 0.5, 1e-6);
    /* a static polygon: a loop, its points as drawn (counter-clockwise once y is up) */
    const kg_body_def* w = kg_scene_body_def(scene, wedge);
    kg_chain_def outline;
    KG_CHECK(w->type == KG_BODY_STATIC && w->shape.type == KG_SHAPE_NONE);
    KG_CHECK(kg_scene_body_chain_count(scene, wedge) == 1);
    KG_CHECK_OK(kg_scene_get_body_chain(scene, wedge, 0, &outline));
    KG_CHECK(outline.loop && outline.count == 3);
    KG_CHECK_NEAR(outline.points[2].x, 0.5, 1e-6);
    KG_CHECK_NEAR(outline.points[2].y, 0.5, 1e-6);
    KG_CHECK_NEAR(outline.friction, 0.6, 1e-6);
    KG_CHECK_NEAR(w->position.x, 10.0, 1e-6);
    KG_CHECK_NEAR(w->position.y, 4.0, 1e-6);
    const kg_body_def* p = kg_scene_body_def(scene, plank);
    /* rectangle (120, 8) 16 x 8 px turned 90 degrees clockwise about its corner */
    KG_CHECK_NEAR(p->position.x, 7.25, 1e-5);
    KG_CHECK_NEAR(p->position.y, 7.0, 1e-5);
    KG_CHECK_NEAR(p->angle, -1.5707963, 1e-6);
    KG_CHECK_NEAR(p->mass, 3.0, 1e-6);
    KG_CHECK_NEAR(p->linear_damping, 0.1, 1e-6);
}

static void test_embedded_tileset_map(void)
{
    kg_scene* scene = load(DATA "embedded.tmj");
    if (scene) {
        KG_CHECK(kg_scene_tilemap_count(scene) == 1);
        check_level_contents(scene);
    }
    kg_scene_destroy(scene);
}

/* The same map with its tileset in terrain.tsj, its ground layer in base64 and inside a
 * group layer: the same contents. */
static void test_external_tileset_base64_and_groups(void)
{
    kg_scene* scene = load(DATA "external.tmj");
    kg_scene* reference = NULL;
    KG_CHECK_OK(kg_scene_load_tiled(DATA "embedded.tmj", &reference));
    if (scene && reference) {
        check_level_contents(scene);
        const kg_tilemap_def* a = kg_scene_get_tilemap(scene, 0);
        const kg_tilemap_def* b = kg_scene_get_tilemap(reference, 0);
        size_t cells = (size_t)a->width * a->height * a->layer_count;
        KG_CHECK(memcmp(a->tiles, b->tiles, cells * sizeof *a->tiles) == 0);
        KG_CHECK(memcmp(a->shapes, b->shapes, (size_t)a->shape_count * sizeof *a->shapes) == 0);
    }
    kg_scene_destroy(scene);
    kg_scene_destroy(reference);
}

/* The level runs: the crate and the ball land on the ground, the plank on the one-way
 * platform it was dropped on. */
static void test_loaded_level_runs(void)
{
    kg_scene* scene = load(DATA "embedded.tmj");
    kg_world_def def = *kg_scene_world_def(scene);
    def.backend = KG_BACKEND_CPU;
    kg_world* world = NULL;
    kg_body bodies[4];
    KG_CHECK_OK(kg_scene_instantiate(scene, &def, &world, bodies));
    KG_CHECK(kg_world_tilemap_count(world) == 1);
    for (int step = 0; step < 180; ++step) {
        KG_CHECK_OK(kg_scene_step(scene, world, bodies, DT));
    }
    kg_body_state crate, ball, plank;
    KG_CHECK_OK(kg_body_get_state(world, bodies[0], &crate));
    KG_CHECK_OK(kg_body_get_state(world, bodies[1], &ball));
    KG_CHECK_OK(kg_body_get_state(world, bodies[3], &plank));
    printf("measured: embedded.tmj after 3 s: crate y %.4f (1.5), ball y %.4f (1.375), plank y %.4f (5.5 on the "
           "one-way platform)\n", crate.position.y, ball.position.y, plank.position.y);
    KG_CHECK_NEAR(crate.position.y, 1.5, 1e-3);
    KG_CHECK_NEAR(ball.position.y, 1.375, 1e-3);
    KG_CHECK_NEAR(plank.position.y, 5.5, 1e-3);
    kg_destroy_world(world);
    kg_scene_destroy(scene);
}

/* ---- chains and capsules: tests/data/tiled/chains.tmj ---- */

/* The chain of body index (its only one), with the point count and loop flag expected. */
static kg_chain_def chain_of(const kg_scene* scene, int index, int count, int loop)
{
    kg_chain_def def = kg_default_chain_def();
    KG_CHECK(kg_scene_body_def(scene, index)->shape.type == KG_SHAPE_NONE);
    KG_CHECK(kg_scene_body_chain_count(scene, index) == 1);
    KG_CHECK_OK(kg_scene_get_body_chain(scene, index, 0, &def));
    KG_CHECK(def.count == count && def.loop == loop);
    return def;
}

/* Twice the signed area of a loop's points: > 0 when counter-clockwise (solid inside). */
static double twice_area(const kg_chain_def* def)
{
    double sum = 0.0;
    for (int i = 0; i < def->count; ++i) {
        kg_vec2 a = def->points[i], b = def->points[(i + 1) % def->count];
        sum += (double)a.x * b.y - (double)b.x * a.y;
    }
    return sum;
}

/* A static layer's polylines are open chains, its polygon (concave, 10 points) a loop; the
 * ellipses with "capsule" are capsules of their bounding boxes. */
static void test_chains_and_capsules_load(void)
{
    kg_scene* scene = load(DATA "chains.tmj");
    if (!scene) {
        return;
    }
    KG_CHECK(kg_scene_body_count(scene) == 9 && kg_scene_tilemap_count(scene) == 0);
    /* drawn left to right at y = 2 m: listed right to left, so that the normal is up */
    kg_chain_def ground = chain_of(scene, 0, 4, 0);
    KG_CHECK(ground.points[0].x == 12.0f && ground.points[3].x == 0.0f && ground.points[0].y == 0.0f);
    KG_CHECK_NEAR(kg_scene_body_def(scene, 0)->position.y, 2.0, 1e-6);
    /* drawn right to left with chain_flip: kept as drawn, right to left, normal up too */
    kg_chain_def ledge = chain_of(scene, 1, 2, 0);
    KG_CHECK(ledge.points[0].x == 0.0f && ledge.points[1].x == -5.0f);
    /* drawn clockwise: turned counter-clockwise, solid inside, area 2 x 2 + 2 x 1 + 2 x 3 */
    kg_chain_def block = chain_of(scene, 2, 10, 1);
    KG_CHECK_NEAR(twice_area(&block), 2.0 * 12.0, 1e-5);
    /* 32 x 16 px: radius 0.5 m, centres 0.5 m either side along x; 16 x 32 px: along y */
    const kg_body_def* pill = kg_scene_body_def(scene, 7);
    const kg_body_def* post = kg_scene_body_def(scene, 8);
    KG_CHECK(pill->type == KG_BODY_DYNAMIC && pill->shape.type == KG_SHAPE_CAPSULE && post->shape.type == KG_SHAPE_CAPSULE);
    KG_CHECK(pill->shape.radius == 0.5f && post->shape.radius == 0.5f);
    KG_CHECK(pill->shape.vertices[0].x == -0.5f && pill->shape.vertices[1].x == 0.5f);
    KG_CHECK(pill->shape.vertices[0].y == 0.0f && pill->shape.vertices[1].y == 0.0f);
    KG_CHECK(post->shape.vertices[0].x == 0.0f && post->shape.vertices[1].x == 0.0f);
    KG_CHECK(post->shape.vertices[0].y == -0.5f && post->shape.vertices[1].y == 0.5f);
    KG_CHECK_NEAR(pill->position.x, 8.0, 1e-6); /* centre (128, 24) px */
    KG_CHECK_NEAR(pill->position.y, 8.5, 1e-6);
    kg_scene_destroy(scene);
}

/* After 3 s: the balls rest on the ground, on the flipped ledge, on the block's top and in
 * its notch (a ball of 0.25 m); the capsules on the ground, lying and standing. */
static void test_chains_and_capsules_run(void)
{
    kg_scene* scene = load(DATA "chains.tmj");
    kg_world_def def = *kg_scene_world_def(scene);
    def.backend = KG_BACKEND_CPU;
    kg_world* world = NULL;
    kg_body bodies[9];
    KG_CHECK_OK(kg_scene_instantiate(scene, &def, &world, bodies));
    if (!world) {
        kg_scene_destroy(scene);
        return;
    }
    KG_CHECK(kg_body_shape_count(world, bodies[0]) == 3 && kg_body_shape_count(world, bodies[2]) == 10);
    for (int step = 0; step < 180; ++step) {
        KG_CHECK_OK(kg_scene_step(scene, world, bodies, DT));
    }
    static const double expected[] = {2.25, 4.25, 4.25, 3.25, 2.5, 3.0};
    printf("measured: chains.tmj after 3 s, y (expected):");
    for (int i = 0; i < 6; ++i) {
        kg_body_state state;
        KG_CHECK_OK(kg_body_get_state(world, bodies[3 + i], &state));
        printf(" %.5f (%.2f)", state.position.y, expected[i]);
        KG_CHECK_NEAR(state.position.y, expected[i], 5e-3);
    }
    printf("\n");
    kg_destroy_world(world);
    kg_scene_destroy(scene);
}

/* ---- broken files ---- */

static void check_refused(const char* file, kg_result expected, const char* where, const char* what)
{
    kg_scene* scene = NULL;
    kg_result r = kg_scene_load_file(file, &scene);
    const char* message = kg_last_error();
    int ok = r == expected && scene == NULL && strstr(message, where) && strstr(message, what);
    if (!ok) {
        printf("%s: got %d '%s', expected %d with '%s' and '%s'\n", file, (int)r, message, (int)expected, where,
               what);
    }
    KG_CHECK(ok);
    kg_scene_destroy(scene);
}

static void test_broken_maps_are_refused_clearly(void)
{
    static const struct {
        const char* file;
        kg_result result;
        const char* where;
        const char* what;
    } cases[] = {
        {DATA "bad_infinite.tmj", KG_ERROR_PARSE, "bad_infinite.tmj: infinite:", "infinite maps are not supported"},
        {DATA "bad_isometric.tmj", KG_ERROR_PARSE, "orientation:", "only orthogonal maps"},
        /* compressed layer data, hostile (tests/data/tiled/make_everything.py made these) */
        {DATA "bad_compressed.tmj", KG_ERROR_PARSE, "layers[0].data:",
         "the zlib data decompresses to fewer bytes than the layer needs; the layer needs 384 bytes (12 x 8 tiles"},
        {DATA "bad_layer_zlib_bomb.tmj", KG_ERROR_PARSE, "bad_layer_zlib_bomb.tmj: layers[0].data:",
         "the zlib data decompresses to more bytes than the layer needs; the layer needs 32 bytes (4 x 2 tiles"},
        {DATA "bad_layer_zlib_truncated.tmj", KG_ERROR_PARSE, "layers[0].data:", "the zlib data is truncated"},
        {DATA "bad_layer_zlib_short.tmj", KG_ERROR_PARSE, "layers[0].data:", "decompresses to fewer bytes"},
        {DATA "bad_layer_zlib_trailing.tmj", KG_ERROR_PARSE, "layers[0].data:",
         "has bytes after the end of the compressed stream"},
        {DATA "bad_layer_zlib_garbage.tmj", KG_ERROR_PARSE, "layers[0].data:", "is not valid compressed data"},
        {DATA "bad_layer_gzip_no_trailer.tmj", KG_ERROR_PARSE, "layers[0].data:", "the gzip data is truncated"},
        {DATA "bad_layer_gzip_bad_base64.tmj", KG_ERROR_PARSE, "layers[0].data:", "the gzip data is not base64"},
        {DATA "bad_layer_zstd.tmj", KG_ERROR_PARSE, "bad_layer_zstd.tmj: layers[0].compression:",
         "zstd-compressed layer data is not supported: in Tiled, set Map > Map Properties > Tile Layer Format"},
        {DATA "bad_layer_csv_compressed.tmj", KG_ERROR_PARSE, "layers[0].compression:",
         "zlib-compressed data must be base64-encoded (the encoding is \"csv\")"},
        {DATA "bad_concave.tmj", KG_ERROR_PARSE, "tilesets[0].tiles[1].objectgroup.objects[0].polygon:",
         "concave"},
        {DATA "bad_xml_tileset.tmj", KG_ERROR_PARSE, "tilesets[0].source:", "XML tileset"},
        {DATA "bad_missing_tileset.tmj", KG_ERROR_PARSE, "tilesets[0].source:", "missing.tsj: cannot open"},
        {DATA "bad_unknown_gid.tmj", KG_ERROR_PARSE, "layers[0].data[5]:", "gid 40 is in no tileset"},
        {DATA "bad_short_data.tmj", KG_ERROR_PARSE, "layers[0].data:", "must be an array of 96 tile ids"},
        {DATA "bad_two_shapes.tmj", KG_ERROR_PARSE, "tiles[0].objectgroup.objects[1]:", "one convex shape per tile"},
        {DATA "bad_oval.tmj", KG_ERROR_PARSE, "tiles[5].objectgroup.objects[0]:", "only round ellipses"},
        {DATA "bad_bad_property.tmj", KG_ERROR_PARSE, "layers[1].objects[0].properties.density.value:",
         "must be a number"},
        {DATA "bad_density_and_mass.tmj", KG_ERROR_PARSE, "layers[1].objects[0].properties.mass:",
         "give density or mass, not both"},
        {DATA "bad_outside_tile.tmj", KG_ERROR_PARSE, "tiles[0].objectgroup.objects[0]:", "reaches outside its tile"},
        {DATA "bad_tile_size.tmj", KG_ERROR_PARSE, "tilesets[0].tilewidth:", "tiles must fit their cells"},
        {DATA "bad_external_tile_size.tmj", KG_ERROR_PARSE, "bad_external_tile_size.tmj: tilesets[0] (",
         "terrain.tsj): tilewidth: its tiles are 16 x 16 pixels but the map's are 32 x 16"},
        {DATA "bad_syntax.tmj", KG_ERROR_PARSE, "bad_syntax.tmj: line 2, column", "malformed JSON"},
        {DATA "no_such_map.tmj", KG_ERROR_IO, "no_such_map.tmj: cannot open", ""},
        /* a device or a directory is refused at once, not read for ever */
        {DATA "bad_device_tileset.tmj", KG_ERROR_PARSE, "tilesets[0].source:",
         "/dev/zero: not a regular file (a device or socket)"},
        {DATA "bad_directory_tileset.tmj", KG_ERROR_PARSE, "tilesets[0].source:", "not a regular file (a directory)"},
        {"/dev/urandom", KG_ERROR_IO, "/dev/urandom: not a regular file", ""},
        /* loads only if the engine takes it: these tiles would be infinitely large */
        {DATA "bad_tiny_ppm.tmj", KG_ERROR_PARSE, "bad_tiny_ppm.tmj: properties.pixels_per_meter:", "is too small"},
        /* a file that is not JSON: where, but nothing of what it holds */
        {DATA "bad_secret_tileset.tmj", KG_ERROR_PARSE, "tilesets[0].source:",
         "not_json.txt: line 1, column 1: malformed JSON (unexpected character)"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        check_refused(cases[i].file, cases[i].result, cases[i].where, cases[i].what);
    }
    kg_scene* scene = NULL;
    KG_CHECK(kg_scene_load_tiled(DATA "bad_secret_tileset.tmj", &scene) == KG_ERROR_PARSE);
    KG_CHECK(strstr(kg_last_error(), "hunter2") == NULL);
}

/* ---- the scene format's tilemap section ---- */

static kg_scene* parse(const char* json)
{
    kg_scene* scene = NULL;
    kg_result r = kg_scene_parse(json, strlen(json), DATA "scene.json", &scene);
    KG_CHECK(r == KG_OK || scene == NULL);
    return scene;
}

/* A scene naming a FIFO as its Tiled map: refused at once (opening it would wait for a
 * writer that never comes), with the JSON path of the field. */
static void test_scene_naming_a_fifo_is_refused_at_once(void)
{
    char fifo[] = "/tmp/kg_fifo_XXXXXX";
    KG_CHECK(mkdtemp(fifo) != NULL);
    char path[64];
    snprintf(path, sizeof path, "%s/map.tmj", fifo);
    KG_CHECK(mkfifo(path, 0600) == 0);
    char json[160];
    snprintf(json, sizeof json, "{\"tilemap\": {\"tiled\": \"%s\"}}", path);
    KG_CHECK(parse(json) == NULL);
    KG_CHECK(strstr(kg_last_error(), "tilemap.tiled: ") && strstr(kg_last_error(), "not a regular file (a FIFO)"));
    kg_scene* scene = NULL;
    KG_CHECK(kg_scene_load_file(path, &scene) == KG_ERROR_IO && scene == NULL);
    KG_CHECK(strstr(kg_last_error(), "not a regular file (a FIFO)") != NULL);
    unlink(path);
    rmdir(fifo);
}

static void test_scene_with_inline_tilemap(void)
{
    const char* json = "{\"bodies\": [{\"name\": \"ball\", \"position\": [1.75, 3],"
                       " \"shape\": {\"type\": \"circle\", \"radius\": 0.25}}],"
                       " \"tilemap\": {\"origin\": [0, 0], \"tile_size\": 0.5,"
                       "  \"tiles\": {\"#\": \"box\", \"/\": \"slope_bottom_right\","
                       "            \"=\": {\"shape\": \"half_top\", \"one_way\": true},"
                       "            \"o\": {\"circle\": {\"radius\": 0.5}},"
                       "            \"v\": {\"polygon\": [[0, 1], [1, 1], [0.5, 0]]}},"
                       "  \"layers\": [[\"  ==  o \", \"./##..v.\", \"########\"],"
                       "             [\"........\", \"........\", \"#.......\"]]}}";
    kg_scene* scene = parse(json);
    KG_CHECK(scene != NULL);
    if (!scene) {
        printf("%s\n", kg_last_error());
        return;
    }
    const kg_tilemap_def* def = kg_scene_get_tilemap(scene, 0);
    KG_CHECK(def->width == 8 && def->height == 3 && def->layer_count == 2 && def->shape_count == 6);
    KG_CHECK_NEAR(def->tile_size.x, 0.5, 1e-6);
    KG_CHECK(tile_at(def, 0, 0, 0) == 1 && tile_at(def, 0, 1, 1) == 2 && tile_at(def, 0, 2, 2) == 3);
    KG_CHECK(tile_at(def, 0, 6, 2) == 4 && tile_at(def, 0, 6, 1) == 5 && tile_at(def, 0, 0, 1) == 0);
    KG_CHECK(tile_at(def, 1, 0, 0) == 1 && tile_at(def, 1, 1, 0) == 0);
    KG_CHECK(def->shapes[3].one_way && def->shapes[4].type == KG_TILE_SHAPE_CIRCLE);
    kg_world* world = NULL;
    kg_body ball;
    KG_CHECK_OK(kg_scene_instantiate(scene, NULL, &world, &ball));
    for (int step = 0; step < 120; ++step) {
        KG_CHECK_OK(kg_world_step(world, DT));
    }
    kg_vec2 at;
    KG_CHECK_OK(kg_body_get_position(world, ball, &at));
    KG_CHECK_NEAR(at.y, 1.5 + 0.25, 1e-3); /* on the one-way platform at column 3, row 2: top at 1.5 m */
    kg_destroy_world(world);
    kg_scene_destroy(scene);
}

static void test_scene_with_tiled_tilemap(void)
{
    kg_scene* scene = parse("{\"gravity\": [0, -5], \"tilemap\": [{\"tiled\": \"embedded.tmj\"},"
                            " {\"tiles\": {\"#\": \"box\"}, \"origin\": [20, 0], \"layers\": [[\"##\"]]}],"
                            " \"forces\": [{\"type\": \"wind\", \"direction\": [1, 0], \"strength\": 1,"
                            " \"bodies\": [\"crate#1\"]}]}");
    KG_CHECK(scene != NULL);
    if (scene) {
        KG_CHECK(kg_scene_tilemap_count(scene) == 2 && kg_scene_body_count(scene) == 4);
        KG_CHECK(kg_scene_force_count(scene) == 1);
        check_level_contents(scene);
    }
    kg_scene_destroy(scene);
}

static void check_scene_refused(const char* json, const char* where, const char* what)
{
    kg_scene* scene = parse(json);
    const char* message = kg_last_error();
    int ok = scene == NULL && strstr(message, where) && strstr(message, what);
    if (!ok) {
        printf("got '%s', expected '%s' and '%s'\n", message, where, what);
    }
    KG_CHECK(ok);
    kg_scene_destroy(scene);
}

static void test_bad_tilemap_sections(void)
{
    check_scene_refused("{\"tilemap\": {\"tiles\": {\"#\": \"bx\"}, \"layers\": [[\"#\"]]}}",
                        "scene.json: tilemap.tiles.#:", "unknown tile shape \"bx\"");
    check_scene_refused("{\"tilemap\": {\"tiles\": {\"#\": \"box\"}, \"layers\": [[\"#x\"]]}}",
                        "tilemap.layers[0][0]:", "'x' (column 1) is not one of the \"tiles\"");
    check_scene_refused("{\"tilemap\": {\"tiles\": {\"#\": \"box\"}, \"layers\": [[\"##\", \"#\"]]}}",
                        "tilemap.layers[0][1]:", "must be a string of 2 tiles");
    check_scene_refused("{\"tilemap\": {\"tiles\": {\"ab\": \"box\"}, \"layers\": [[\"#\"]]}}", "tilemap.tiles.ab:",
                        "single characters");
    check_scene_refused("{\"tilemap\": {\"tiles\": {\"#\": {\"polygon\": [[0, 0], [2, 0], [0, 1]]}},"
                        " \"layers\": [[\"#\"]]}}",
                        "tilemap.tiles.#:", "outside the cell");
    check_scene_refused("{\"tilemap\": {\"tiles\": {\"#\": \"box\"}, \"layers\": [[\"#\"]], \"size\": 1}}",
                        "tilemap.size:", "unknown field");
    check_scene_refused("{\"tilemap\": {\"tiled\": \"bad_infinite.tmj\"}}", "scene.json: tilemap.tiled:",
                        "infinite maps are not supported");
    check_scene_refused("{\"tilemap\": {\"tiled\": \"embedded.tmj\", \"origin\": [0, 0]}}", "tilemap.origin:",
                        "unknown field");
}

/* A map of 4 x 4 tiles of 16 px with one object layer, of body type layer_type, holding
 * object: refused at where with what. */
static void check_object_refused(const char* layer_type, const char* object, const char* where, const char* what)
{
    char json[1024];
    snprintf(json, sizeof json,
             "{\"type\": \"map\", \"width\": 4, \"height\": 4, \"tilewidth\": 16, \"tileheight\": 16,"
             " \"layers\": [{\"type\": \"objectgroup\", \"properties\": [{\"name\": \"type\", \"type\": \"string\","
             " \"value\": \"%s\"}], \"objects\": [%s]}]}",
             layer_type, object);
    check_scene_refused(json, where, what);
}

static void test_bad_chain_and_capsule_objects(void)
{
    check_object_refused("dynamic", "{\"id\": 1, \"polyline\": [{\"x\": 0, \"y\": 0}, {\"x\": 16, \"y\": 0}]}",
                         "scene.json: layers[0].objects[0]:",
                         "a polyline has no area: only static and kinematic bodies may have one");
    check_object_refused("static", "{\"id\": 1, \"polyline\": [{\"x\": 0, \"y\": 0}]}", "layers[0].objects[0].polyline:",
                         "a chain needs at least 2 points (got 1)");
    check_object_refused("static",
                         "{\"id\": 1, \"polygon\": [{\"x\": 0, \"y\": 0}, {\"x\": 16, \"y\": 0},"
                         " {\"x\": 16, \"y\": 0}, {\"x\": 0, \"y\": 16}]}",
                         "layers[0].objects[0].polygon:", "chain segment 1 (points 1 and 2): segment points coincide");
    check_object_refused("static", "{\"id\": 1, \"polyline\": [{\"x\": 0, \"y\": 0}, {\"x\": 16}]}",
                         "layers[0].objects[0].polyline[1].y:", "is required");
    check_object_refused("dynamic", "{\"id\": 1, \"ellipse\": true, \"width\": 10, \"height\": 8}",
                         "layers[0].objects[0]:", "the ellipse is 10 x 8 pixels; only round ellipses (circles) collide, "
                         "and ellipses twice as long as wide with the bool property \"capsule\" (capsules)");
    check_object_refused("dynamic",
                         "{\"id\": 1, \"ellipse\": true, \"width\": 30, \"height\": 16, \"properties\": [{\"name\":"
                         " \"capsule\", \"type\": \"bool\", \"value\": true}]}",
                         "layers[0].objects[0]:", "a capsule ellipse must be twice as long as wide");
    check_object_refused("dynamic",
                         "{\"id\": 1, \"width\": 32, \"height\": 16, \"properties\": [{\"name\": \"capsule\","
                         " \"type\": \"bool\", \"value\": true}]}",
                         "layers[0].objects[0].properties.capsule:", "only an ellipse object becomes a capsule");
    check_object_refused("dynamic",
                         "{\"id\": 1, \"polygon\": [{\"x\": 0, \"y\": 0}, {\"x\": 16, \"y\": 0}, {\"x\": 0, \"y\": 16}],"
                         " \"properties\": [{\"name\": \"chain_flip\", \"type\": \"bool\", \"value\": true}]}",
                         "layers[0].objects[0].properties.chain_flip:", "only a chain (a polyline, or a polygon on a static "
                         "layer) has a side to flip");
    check_object_refused("static",
                         "{\"id\": 1, \"polyline\": [{\"x\": 0, \"y\": 0}, {\"x\": 16, \"y\": 0}],"
                         " \"properties\": [{\"name\": \"chain_flip\", \"type\": \"int\", \"value\": 1}]}",
                         "layers[0].objects[0].properties.chain_flip.value:", "must be true or false");
}

/* Custom properties are kept, so each must hold a value of its type. */
static void test_bad_custom_properties(void)
{
    static const struct {
        const char* property;
        const char* where;
        const char* what;
    } cases[] = {
        {"{\"name\": \"hp\", \"type\": \"int\", \"value\": 1.5}", "objects[0].properties.hp.value:",
         "must be an integer in [-2147483648, 2147483647]"},
        {"{\"name\": \"hp\", \"type\": \"int\", \"value\": 3e9}", "objects[0].properties.hp.value:",
         "must be an integer"},
        {"{\"name\": \"w\", \"type\": \"float\", \"value\": \"2\"}", "properties.w.value:",
         "must be a finite number"},
        {"{\"name\": \"b\", \"type\": \"bool\", \"value\": 1}", "properties.b.value:", "must be true or false"},
        {"{\"name\": \"c\", \"type\": \"color\", \"value\": \"#12345\"}", "properties.c.value:",
         "must be a color, \"#aarrggbb\" or \"#rrggbb\""},
        {"{\"name\": \"c\", \"type\": \"color\", \"value\": \"#gg0000\"}", "properties.c.value:", "must be a color"},
        {"{\"name\": \"f\", \"type\": \"file\", \"value\": 7}", "properties.f.value:", "must be a string"},
        {"{\"name\": \"o\", \"type\": \"object\", \"value\": -1}", "properties.o.value:",
         "must be an object id (an integer >= 0)"},
        {"{\"name\": \"k\", \"type\": \"class\", \"value\": 5}", "properties.k.value:",
         "must be an object (the members of a class)"},
        {"{\"name\": \"k\", \"type\": \"class\", \"value\": {\"a\": [1]}}", "properties.k.value.a:",
         "must be a string, a number, true, false or an object"},
        {"{\"name\": \"k\", \"type\": \"class\", \"value\": {\"a\": {\"b\": {\"c\": {\"d\": {\"e\": {\"f\": "
         "{\"g\": {\"h\": {\"i\": 1}}}}}}}}}}", "properties.k.value.a.b.c.d.e.f.g.h:", "classes nested more than 8 deep"},
        {"{\"name\": \"v\", \"type\": \"vector\", \"value\": 1}", "properties.v.type:",
         "must be \"string\", \"int\", \"float\", \"bool\", \"color\", \"file\", \"object\" or \"class\" (got "
         "\"vector\")"},
        {"{\"name\": \"v\", \"type\": \"string\"}", "properties.v.value:", "is required"},
        {"{\"type\": \"string\", \"value\": \"x\"}", "objects[0].properties[0].name:", "is required"},
        {"7", "objects[0].properties[0]:", "must be an object (a property)"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        char object[512];
        snprintf(object, sizeof object, "{\"id\": 1, \"width\": 16, \"height\": 16, \"properties\": [%s]}",
                 cases[i].property);
        check_object_refused("static", object, cases[i].where, cases[i].what);
    }
}

KG_TEST_MAIN(KG_TEST(test_embedded_tileset_map), KG_TEST(test_external_tileset_base64_and_groups),
             KG_TEST(test_loaded_level_runs), KG_TEST(test_chains_and_capsules_load),
             KG_TEST(test_chains_and_capsules_run), KG_TEST(test_broken_maps_are_refused_clearly),
             KG_TEST(test_scene_with_inline_tilemap), KG_TEST(test_scene_with_tiled_tilemap),
             KG_TEST(test_scene_naming_a_fifo_is_refused_at_once),
             KG_TEST(test_bad_tilemap_sections), KG_TEST(test_bad_chain_and_capsule_objects),
             KG_TEST(test_bad_custom_properties))
