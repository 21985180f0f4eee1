/* Worlds saved as scenes (include/kgyro/scene.h, "Saved worlds"; docs/scene-format.md):
 * floats written and read back bit for bit, a saved world continuing bitwise after a
 * load (through the library; the CLI's run in tests/cases/cli_save.cmake), an editor's
 * move of one body applied while the others continue untouched, the names of the scene
 * the world was made from kept (kg_scene_from_world_named), and the errors: a bad
 * "state" (version, base64, a snapshot of another world), an unwritable path, what the
 * writer cannot write yet. Files go to a fresh directory under /tmp. */
#define _POSIX_C_SOURCE 200809L

#include "kg_test.h"
#include "kg_test_world.h"
#include "kgyro/kgyro.h"
#include "kgyro/scene.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define KG_DT (1.0f / 60.0f)

static char g_dir[64];

static void kg_path(char* out, size_t size, const char* name) { snprintf(out, size, "%s/%s", g_dir, name); }

static char* kg_read_text(const char* path)
{
    FILE* f = fopen(path, "rb");
    if (!f) {
        return NULL;
    }
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char* text = calloc((size_t)n + 1, 1);
    if (text && fread(text, 1, (size_t)n, f) != (size_t)n) {
        free(text);
        text = NULL;
    }
    fclose(f);
    return text;
}

static uint32_t kg_next(uint32_t* seed)
{
    *seed = *seed * 1664525u + 1013904223u;
    return *seed;
}

/* A pile of boxes and balls on a ground box, stepped 90 times: contacts, some asleep. */
static kg_world* kg_pile(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, -10.0f});
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, -0.5f}, 0.0f, kg_box_shape(20.0f, 1.0f));
    for (int i = 0; i < 30; ++i) {
        kg_shape_def shape = i % 2 ? kg_circle_shape(0.3f) : kg_box_shape(0.5f, 0.4f);
        kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){-2.0f + 0.7f * (float)(i % 6), 0.5f + 0.6f * (float)(i / 6)},
                    0.1f * (float)i, shape);
    }
    kg_body all[4];
    int count = 0;
    KG_CHECK_OK(kg_world_get_bodies(world, all, 4, &count));
    kg_applicator wind;
    KG_CHECK_OK(kg_add_wind_applicator(world, (kg_vec2){1.0f, 0.0f}, 0.5f, 0.1f, all + 1, 3, &wind));
    for (int s = 0; s < 90; ++s) {
        KG_CHECK_OK(kg_world_step(world, KG_DT));
    }
    return world;
}

/* Saves world as a scene file at path. */
static void kg_save_world(const kg_world* world, const char* path)
{
    kg_scene* saved = NULL;
    KG_CHECK_OK(kg_scene_from_world(world, &saved));
    KG_CHECK_OK(kg_scene_save_file(saved, path));
    kg_scene_destroy(saved);
}

/* Saves world to name; returns the loaded scene (NULL on failure). */
static kg_scene* kg_save_and_load(const kg_world* world, const char* name)
{
    char path[128];
    kg_path(path, sizeof path, name);
    kg_save_world(world, path);
    kg_scene* loaded = NULL;
    KG_CHECK_OK(kg_scene_load_file(path, &loaded));
    return loaded;
}

/* Every body's state after steps more steps, into out (count of them). */
static void kg_states_after(kg_world* world, int steps, kg_body_state* out, int* count)
{
    for (int s = 0; s < steps; ++s) {
        KG_CHECK_OK(kg_world_step(world, KG_DT));
    }
    kg_body bodies[64];
    KG_CHECK_OK(kg_world_get_bodies(world, bodies, 64, count));
    KG_CHECK_OK(kg_world_get_body_states(world, bodies, *count, out));
}

/* Bodies at random float positions, angles and velocities of every magnitude: the file
 * gives each back bit for bit. */
static void test_floats_round_trip(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, 0.0f});
    uint32_t seed = 7u;
    for (int i = 0; i < 60; ++i) {
        kg_body_def def = kg_default_body_def();
        def.shape = kg_circle_shape(0.1f);
        float scale = powf(10.0f, (float)(i % 12) - 6.0f);
        def.position = (kg_vec2){scale * ((float)(kg_next(&seed) >> 8) / 16777216.0f - 0.5f),
                                 scale * ((float)(kg_next(&seed) >> 8) / 16777216.0f)};
        def.angle = (float)(kg_next(&seed) >> 8) / 16777216.0f * 3.0f;
        def.velocity = (kg_vec2){(float)(kg_next(&seed) >> 8) / 3.0e5f, -1.0f / 3.0f};
        def.angular_velocity = 1.0f / 7.0f;
        kg_body b;
        KG_CHECK_OK(kg_create_body(world, &def, &b));
    }
    kg_scene* loaded = kg_save_and_load(world, "floats.json");
    kg_body bodies[64];
    int count = 0;
    KG_CHECK_OK(kg_world_get_bodies(world, bodies, 64, &count));
    KG_CHECK(loaded && kg_scene_body_count(loaded) == count);
    for (int i = 0; loaded && i < count; ++i) {
        kg_body_state s;
        KG_CHECK_OK(kg_body_get_state(world, bodies[i], &s));
        const kg_body_def* d = kg_scene_body_def(loaded, i);
        KG_CHECK(memcmp(&d->position, &s.position, sizeof s.position) == 0);
        KG_CHECK(memcmp(&d->angle, &s.angle, sizeof s.angle) == 0);
        KG_CHECK(memcmp(&d->velocity, &s.velocity, sizeof s.velocity) == 0);
        KG_CHECK(memcmp(&d->angular_velocity, &s.angular_velocity, sizeof s.angular_velocity) == 0);
    }
    kg_scene_destroy(loaded);
    kg_destroy_world(world);
}

/* Saved after 90 steps, loaded and run 60 more: the states of the world run 150. */
static void test_loaded_world_continues(void)
{
    kg_world* world = kg_pile();
    kg_scene* loaded = kg_save_and_load(world, "pile.json");
    kg_world* again = NULL;
    KG_CHECK_OK(kg_scene_instantiate(loaded, NULL, &again, NULL));
    kg_body_state first[64], second[64];
    int n1 = 0, n2 = 0;
    kg_states_after(world, 60, first, &n1);
    if (again) {
        kg_states_after(again, 60, second, &n2);
    }
    KG_CHECK(n1 == 31 && n1 == n2 && memcmp(first, second, (size_t)n1 * sizeof first[0]) == 0);
    KG_CHECK(kg_world_contact_count(world) > 0 && kg_world_contact_count(world) == kg_world_contact_count(again));
    kg_destroy_world(again);
    kg_scene_destroy(loaded);
    kg_destroy_world(world);
}

/* Replaces the first "position" after body name's entry in text by value. */
static void kg_edit_position(char* text, const char* name, const char* value)
{
    char key[64];
    snprintf(key, sizeof key, "\"%s\"", name);
    char* at = strstr(text, key);
    at = at ? strstr(at, "\"position\":") : NULL;
    char* open = at ? strchr(at, '[') : NULL;
    char* close = open ? strchr(open, ']') : NULL;
    KG_CHECK(close != NULL && strlen(value) <= (size_t)(close - open + 1));
    if (close) {
        memset(open, ' ', (size_t)(close - open + 1));
        memcpy(open, value, strlen(value));
    }
}

/* An editor moves body 5 in the file: it is where the file says, every other body
 * exactly where the snapshot had it. */
static void test_editor_move_applies(void)
{
    kg_world* world = kg_pile();
    char path[128];
    kg_path(path, sizeof path, "edited.json");
    kg_save_world(world, path);
    char* text = kg_read_text(path);
    KG_CHECK(text != NULL);
    if (!text) {
        kg_destroy_world(world);
        return;
    }
    kg_edit_position(text, "body5", "[1.5, 7]");
    kg_scene* loaded = NULL;
    KG_CHECK_OK(kg_scene_parse(text, strlen(text), "edited.json", &loaded));
    kg_world* again = NULL;
    kg_body handles[64];
    KG_CHECK_OK(kg_scene_instantiate(loaded, NULL, &again, handles));
    for (int i = 0; again && i < kg_scene_body_count(loaded); ++i) {
        kg_body_state s, t;
        KG_CHECK_OK(kg_body_get_state(again, handles[i], &s));
        KG_CHECK_OK(kg_body_get_state(world, handles[i], &t)); /* the same handles: the snapshot's */
        if (i == 5) {
            KG_CHECK(s.position.x == 1.5f && s.position.y == 7.0f);
        } else {
            KG_CHECK(memcmp(&s, &t, sizeof s) == 0);
        }
    }
    free(text);
    kg_destroy_world(again);
    kg_scene_destroy(loaded);
    kg_destroy_world(world);
}

/* Parses text as a scene; checks the code and that the message has needle. */
static void kg_check_parse_fails(const char* text, const char* needle)
{
    kg_scene* scene = NULL;
    kg_result r = kg_scene_parse(text, strlen(text), "s.json", &scene);
    KG_CHECK(r == KG_ERROR_PARSE && scene == NULL);
    if (!strstr(kg_last_error(), needle)) {
        fprintf(stderr, "  message \"%s\" lacks \"%s\"\n", kg_last_error(), needle);
        kg_test_failures++;
    }
}

/* A "state" object of this build's snapshot version and the fields after it. */
static void kg_check_state_fails(const char* fields, const char* needle)
{
    char text[256];
    snprintf(text, sizeof text, "{\"state\": {\"version\": %u%s}}", (unsigned)KG_SNAPSHOT_VERSION, fields);
    kg_check_parse_fails(text, needle);
}

static void test_bad_state(void)
{
    kg_check_parse_fails("{\"state\": {\"version\": 99, \"max_bodies\": 8, \"snapshot\": \"\"}}", "state.version");
    kg_check_state_fails(", \"max_bodies\": 8, \"snapshot\": \"abc\"", "state.snapshot");
    kg_check_state_fails(", \"max_bodies\": 8, \"snapshot\": \"ab=c\"", "state.snapshot");
    kg_check_state_fails(", \"snapshot\": \"\"", "max_bodies");
    kg_check_state_fails(", \"max_bodies\": 8, \"snapshot\": \"\", \"x\": 1", "state");
    /* base64 of bytes that are no snapshot: the loader tries it, as the instantiation would */
    kg_check_state_fails(", \"max_bodies\": 8, \"snapshot\": \"AAAAAAAA\"", "state.snapshot: not a KineticGyro snapshot");
}

/* A saved world's state in a scene of other bodies, or read into other capacities: refused
 * by the loader, which tries the snapshot as kg_scene_instantiate will. */
static void test_state_must_fit(void)
{
    kg_world* world = kg_pile();
    char path[128];
    kg_path(path, sizeof path, "fit.json");
    kg_save_world(world, path);
    char* text = kg_read_text(path);
    char* at = text ? strstr(text, "\"max_bodies\":") : NULL;
    KG_CHECK(at != NULL);
    if (at) {
        memcpy(strchr(at, ':') + 1, "\t4095", 5); /* 4096 written: one less */
        kg_check_parse_fails(text, "state.snapshot: snapshot of a world of max_bodies 4096");
    }
    free(text);
    remove(path);
    kg_destroy_world(world);
}

/* Names come from the scene the world was made from; a body it did not have gets
 * body<i>, made unique against the scene's names. */
static void test_names_kept(void)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_create(&scene));
    kg_body_def def = kg_default_body_def();
    def.shape = kg_circle_shape(0.5f);
    KG_CHECK_OK(kg_scene_add_body(scene, "body2", &def));
    def.position.x = 3.0f;
    KG_CHECK_OK(kg_scene_add_body(scene, "x", &def));
    kg_world* world = NULL;
    kg_body handles[2];
    KG_CHECK_OK(kg_scene_instantiate(scene, NULL, &world, handles));
    kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){6.0f, 0.0f}, 0.0f, kg_circle_shape(0.5f));
    kg_scene* saved = NULL;
    KG_CHECK_OK(kg_scene_from_world_named(world, scene, handles, &saved));
    KG_CHECK(saved && kg_scene_body_count(saved) == 3);
    KG_CHECK(saved && strcmp(kg_scene_body_name(saved, 0), "body2") == 0);
    KG_CHECK(saved && strcmp(kg_scene_body_name(saved, 1), "x") == 0);
    KG_CHECK(saved && strcmp(kg_scene_body_name(saved, 2), "body2_1") == 0);
    kg_scene_destroy(saved);
    kg_destroy_world(world);
    kg_scene_destroy(scene);
}

static void test_save_errors(void)
{
    kg_world* world = kg_pile();
    kg_scene* saved = NULL;
    KG_CHECK_OK(kg_scene_from_world(world, &saved));
    KG_CHECK(kg_scene_save_file(saved, "/nonexistent-dir/x.json") == KG_ERROR_IO);
    KG_CHECK(kg_scene_save_file(NULL, "x.json") == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_scene_from_world(NULL, &saved) == KG_ERROR_INVALID_ARGUMENT);
    kg_scene_destroy(saved);
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_create(&scene));
    kg_tile_shape shapes[2] = {kg_tile_empty(), kg_tile_box()};
    kg_tilemap_def map = kg_default_tilemap_def();
    map.width = 4;
    map.height = 1;
    map.shapes = shapes;
    map.shape_count = 2;
    KG_CHECK_OK(kg_scene_add_tilemap(scene, &map));
    char path[128];
    kg_path(path, sizeof path, "map.json");
    KG_CHECK_OK(kg_scene_save_file(scene, path)); /* a map is written... */
    kg_scene* loaded = NULL;
    KG_CHECK_OK(kg_scene_load_file(path, &loaded));
    KG_CHECK(loaded && kg_scene_tilemap_count(loaded) == 1);
    kg_scene_destroy(loaded);
    kg_scene_destroy(scene);
    remove(path);
    KG_CHECK_OK(kg_scene_create(&scene)); /* ...but not a body of two shapes, without a state */
    kg_body_def def = kg_default_body_def();
    def.shape = kg_circle_shape(0.5f);
    KG_CHECK_OK(kg_scene_add_body(scene, NULL, &def));
    kg_body_shape_def extra = kg_default_body_shape_def();
    extra.geometry = kg_box_shape(1.0f, 1.0f);
    KG_CHECK_OK(kg_scene_add_body_shape(scene, 0, &extra));
    KG_CHECK(kg_scene_save_file(scene, path) == KG_ERROR_UNSUPPORTED);
    kg_scene_destroy(scene);
    kg_destroy_world(world);
}

int main(void)
{
    snprintf(g_dir, sizeof g_dir, "/tmp/kg_scene_save_XXXXXX");
    if (!mkdtemp(g_dir)) {
        fprintf(stderr, "cannot make a directory under /tmp\n");
        return 1;
    }
    static const kg_test_case tests[] = {
        KG_TEST(test_floats_round_trip), KG_TEST(test_loaded_world_continues), KG_TEST(test_editor_move_applies),
        KG_TEST(test_bad_state),         KG_TEST(test_state_must_fit),          KG_TEST(test_names_kept),             KG_TEST(test_save_errors),
    };
    int code = kg_run_tests(tests, (int)(sizeof tests / sizeof tests[0]));
    const char* names[] = {"floats.json", "pile.json", "edited.json"};
    for (int i = 0; i < 3; ++i) {
        char path[128];
        kg_path(path, sizeof path, names[i]);
        remove(path);
    }
    rmdir(g_dir);
    return code;
}
