/* Worlds saved as scenes (include/kgyro/scene.h, "Saved worlds"; docs/scene-format.md):
 * floats written and read back bit for bit, a saved world continuing bitwise after a
 * load (through the library; the CLI's run in tests/cases/cli_save.cmake), an editor's
 * move of one body applied while the others continue untouched, the names of the scene
 * the world was made from kept (kg_scene_from_world_named), a whole world (compound
 * bodies, chains, a pivot, a joint of each kind) coming back from the file alone, and the
 * errors: a bad "state" (version, base64, a snapshot of another world), an unwritable
 * path, what the reader would refuse. Files go to a fresh directory under /tmp. */
#define _POSIX_C_SOURCE 200809L

#include "kg_test.h"
#include "kg_test_world.h"
#include "kgyro/kgyro.h"
#include "kgyro/scene.h"
#include "core/joint.h"
#include "io/json_util.h"
#include "io/scene_joints.h"

#include <math.h>
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

/* Saves scene to name and loads it back (NULL on failure). */
static kg_scene* kg_resave(const kg_scene* scene, const char* name)
{
    char path[128];
    kg_path(path, sizeof path, name);
    KG_CHECK_OK(kg_scene_save_file(scene, path));
    kg_scene* loaded = NULL;
    KG_CHECK_OK(kg_scene_load_file(path, &loaded));
    remove(path);
    return loaded;
}

/* A compound body whose first shape is its sensor: the scene, and the file, say so (the
 * entry's flag goes next to the body's "sensor"), the other shape stays solid. */
static void test_first_shape_sensor(void)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_create(&scene));
    kg_body_def def = kg_default_body_def();
    def.shape = kg_circle_shape(2.0f);
    def.is_sensor = 1;
    KG_CHECK_OK(kg_scene_add_body(scene, "sensing", &def));
    kg_body_shape_def extra = kg_default_body_shape_def();
    extra.geometry = kg_box_shape(0.5f, 0.5f);
    KG_CHECK_OK(kg_scene_add_body_shape(scene, 0, &extra));
    kg_scene* loaded = kg_resave(scene, "sensor.json");
    kg_body_shape_def first, second;
    KG_CHECK_OK(kg_scene_get_body_shape(scene, 0, 0, &first));
    KG_CHECK(first.is_sensor == 1);
    KG_CHECK(loaded && kg_scene_body_def(loaded, 0)->is_sensor == 1);
    KG_CHECK(loaded && kg_scene_get_body_shape(loaded, 0, 0, &first) == KG_OK && first.is_sensor == 1 &&
             first.geometry.radius == 2.0f);
    KG_CHECK(loaded && kg_scene_get_body_shape(loaded, 0, 1, &second) == KG_OK && second.is_sensor == 0);
    kg_scene_destroy(loaded);
    kg_scene_destroy(scene);
}

/* Joint j between bodies "x" and "y" of a fresh scene: kg_scene_add_joint refuses it
 * with a message that has needle, and the scene, holding no joint, still saves. */
static void kg_check_joint_refused(const kg_scene_joint* j, const char* needle)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_create(&scene));
    kg_body_def def = kg_default_body_def();
    def.shape = kg_box_shape(0.5f, 0.5f);
    KG_CHECK_OK(kg_scene_add_body(scene, "x", &def));
    def.position.x = 2.0f;
    KG_CHECK_OK(kg_scene_add_body(scene, "y", &def));
    KG_CHECK(kg_scene_add_joint(scene, j) == KG_ERROR_INVALID_ARGUMENT);
    if (!strstr(kg_last_error(), needle)) {
        fprintf(stderr, "  message \"%s\" lacks \"%s\"\n", kg_last_error(), needle);
        kg_test_failures++;
    }
    KG_CHECK(kg_scene_joint_count(scene) == 0);
    kg_scene_destroy(kg_resave(scene, "no_joint.json"));
    kg_scene_destroy(scene);
}

/* What the reader refuses in a file, kg_scene_add_joint refuses in a call (one check):
 * an unknown type, a NaN option (which would be written as a bare nan), limits out of
 * order, a mouse joint with an "a"; the writer writes no non-finite float. A good joint
 * goes through the file. */
static void test_bad_joint_refused(void)
{
    kg_scene_joint j;
    kg_scene_joint_init(&j, KG_JOINT_REVOLUTE);
    j.body_a = 0;
    j.body_b = 1;
    j.anchor_a = j.anchor_b = (kg_vec2){1.0f, 0.0f};
    kg_scene_joint bad = j;
    bad.type = (kg_joint_type)1000000;
    kg_check_joint_refused(&bad, "kg_scene_add_joint: joint 0 (a 'x', b 'y').type: 1000000 is no joint type");
    bad = j;
    bad.revolute.hertz = NAN;
    kg_check_joint_refused(&bad, "joint 0 (a 'x', b 'y').hertz: must be a finite number");
    bad = j;
    bad.revolute.lower_angle = 1.0f;
    bad.revolute.upper_angle = -1.0f;
    kg_check_joint_refused(&bad, "lower_angle: must be <= upper_angle");
    kg_scene_joint_init(&bad, KG_JOINT_MOUSE);
    bad.body_a = 0;
    bad.body_b = 1;
    kg_check_joint_refused(&bad, ".a: a mouse joint drags \"b\" to its target");
    KG_CHECK(kg_float_json(NAN) == NULL && kg_float_json(INFINITY) == NULL);
    KG_CHECK(kg_json_add(NULL, "x", cJSON_CreateObject()) == 0); /* the item not added is freed (ASan: no leak) */
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_create(&scene));
    kg_body_def def = kg_default_body_def();
    def.shape = kg_box_shape(0.5f, 0.5f);
    KG_CHECK_OK(kg_scene_add_body(scene, "x", &def));
    def.position.x = 2.0f;
    KG_CHECK_OK(kg_scene_add_body(scene, "y", &def));
    j.revolute.lower_angle = -0.5f;
    j.revolute.enable_limit = 1;
    KG_CHECK_OK(kg_scene_add_joint(scene, &j));
    kg_scene* loaded = kg_resave(scene, "joint.json");
    KG_CHECK(loaded && kg_scene_joint_count(loaded) == 1 &&
             kg_scene_get_joint(loaded, 0)->revolute.lower_angle == -0.5f);
    kg_scene_destroy(loaded);
    kg_scene_destroy(scene);
}

/* A static body of 71 boxes, more than a file's "shapes" takes (64): saved with a state,
 * the file gives it its first box and the state brings back all 71. */
static void test_many_shapes_with_state(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, -10.0f});
    kg_body ground = kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, 0.0f}, 0.0f, kg_box_shape(0.5f, 0.5f));
    for (int k = 1; k < 71; ++k) {
        kg_body_shape_def box = kg_default_body_shape_def();
        box.geometry = kg_shape_moved(kg_box_shape(0.5f, 0.5f), (kg_vec2){(float)k, 0.0f}, 0.0f);
        kg_shape_id id;
        KG_CHECK_OK(kg_create_shape(world, ground, &box, &id));
    }
    kg_scene* loaded = kg_save_and_load(world, "many.json");
    KG_CHECK(loaded && kg_scene_body_shape_count(loaded, 0) == 1 && kg_scene_body_chain_count(loaded, 0) == 0);
    kg_world* again = NULL;
    kg_body handle;
    KG_CHECK_OK(kg_scene_instantiate(loaded, NULL, &again, &handle));
    KG_CHECK(again && kg_body_shape_count(again, handle) == 71);
    kg_destroy_world(again);
    kg_scene_destroy(loaded);
    kg_destroy_world(world);
}

/* A dynamic box given a density-0 sensor and a density-2 circle, then the box destroyed:
 * the circle becomes the body's own shape (its density gives the mass), the sensor comes
 * after it, and the loaded world's body has the mass it had (pi 0.5^2 2). */
static void test_dense_shape_first(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, 0.0f});
    kg_body body = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.0f}, 0.0f, kg_box_shape(0.5f, 0.5f));
    kg_shape_id box, sensor, circle;
    int n = 0;
    KG_CHECK_OK(kg_body_get_shapes(world, body, &box, 1, &n));
    kg_body_shape_def def = kg_default_body_shape_def();
    def.geometry = kg_circle_shape(1.5f);
    def.density = 0.0f;
    def.is_sensor = 1;
    KG_CHECK_OK(kg_create_shape(world, body, &def, &sensor));
    def.geometry = kg_shape_moved(kg_circle_shape(0.5f), (kg_vec2){1.0f, 0.0f}, 0.0f);
    def.density = 2.0f;
    def.is_sensor = 0;
    KG_CHECK_OK(kg_create_shape(world, body, &def, &circle));
    KG_CHECK_OK(kg_destroy_shape(world, box));
    kg_mass_data before, after;
    KG_CHECK_OK(kg_body_get_mass_data(world, body, &before));
    kg_scene* loaded = kg_save_and_load(world, "dense.json");
    KG_CHECK(loaded && kg_scene_body_def(loaded, 0)->density == 2.0f &&
             kg_scene_body_def(loaded, 0)->shape.radius == 0.5f && kg_scene_body_shape_count(loaded, 0) == 2);
    kg_body_shape_def second;
    KG_CHECK(loaded && kg_scene_get_body_shape(loaded, 0, 1, &second) == KG_OK && second.is_sensor == 1 &&
             second.density == 0.0f);
    kg_world* again = NULL;
    kg_body handle;
    KG_CHECK_OK(kg_scene_instantiate(loaded, NULL, &again, &handle));
    KG_CHECK(again && kg_body_get_mass_data(again, handle, &after) == KG_OK);
    KG_CHECK_NEAR(before.mass, 3.14159265f * 0.25f * 2.0f, 1e-5f);
    KG_CHECK(again && after.mass == before.mass);
    kg_destroy_world(again);
    kg_scene_destroy(loaded);
    kg_destroy_world(world);
}

/* A static body of no shape, a hinge's anchor, and a kinematic one: the file omits their
 * "shape", the reader takes them, and the loaded world has them shapeless, the hinge
 * between the anchor and the box. */
static void test_shapeless_anchor(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, -10.0f});
    kg_shape_def none = kg_default_body_def().shape; /* KG_SHAPE_NONE */
    kg_body anchor = kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, 5.0f}, 0.0f, none);
    kg_test_add(world, KG_BODY_KINEMATIC, (kg_vec2){3.0f, 5.0f}, 0.0f, none);
    kg_body box = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){1.0f, 5.0f}, 0.0f, kg_box_shape(0.5f, 0.5f));
    kg_revolute_joint_def hinge = kg_default_revolute_joint_def();
    hinge.base.body_a = anchor;
    hinge.base.body_b = box;
    hinge.local_anchor_b = (kg_vec2){-1.0f, 0.0f};
    KG_CHECK_OK(kg_create_revolute_joint(world, &hinge, NULL));
    kg_scene* loaded = kg_save_and_load(world, "anchor.json");
    KG_CHECK(loaded && kg_scene_body_def(loaded, 0)->shape.type == KG_SHAPE_NONE &&
             kg_scene_body_def(loaded, 1)->shape.type == KG_SHAPE_NONE && kg_scene_joint_count(loaded) == 1);
    kg_world* again = NULL;
    kg_body handles[3];
    KG_CHECK_OK(kg_scene_instantiate(loaded, NULL, &again, handles));
    KG_CHECK(again && kg_body_shape_count(again, handles[0]) == 0 && kg_body_shape_count(again, handles[1]) == 0 &&
             kg_world_joint_count(again) == 1);
    kg_destroy_world(again);
    kg_scene_destroy(loaded);
    kg_destroy_world(world);
}

/* A loop of 5 points with segment 2 (p2 to p3) destroyed is one open chain, p3 p4 p0 p1
 * p2, its ends where the cut was; not two pieces split at the unbroken joint p4-p0. */
static void test_broken_loop_one_chain(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, -10.0f});
    kg_body ground = kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, 0.0f}, 0.0f, kg_default_body_def().shape);
    const kg_vec2 ring[] = {{0.0f, 0.0f}, {4.0f, 0.0f}, {5.0f, 3.0f}, {2.0f, 5.0f}, {-1.0f, 3.0f}};
    kg_chain_def def = kg_default_chain_def();
    def.points = ring;
    def.count = 5;
    def.loop = 1;
    kg_shape_id segments[5];
    KG_CHECK_OK(kg_create_chain(world, ground, &def, segments));
    KG_CHECK_OK(kg_destroy_shape(world, segments[2]));
    kg_scene* loaded = kg_save_and_load(world, "broken_loop.json");
    kg_chain_def chain;
    KG_CHECK(loaded && kg_scene_body_chain_count(loaded, 0) == 1);
    KG_CHECK(loaded && kg_scene_get_body_chain(loaded, 0, 0, &chain) == KG_OK && chain.count == 5 && !chain.loop);
    for (int k = 0; loaded && k < 5 && chain.count == 5; ++k) {
        KG_CHECK(memcmp(&chain.points[k], &ring[(k + 3) % 5], sizeof ring[0]) == 0);
    }
    kg_scene_destroy(loaded);
    kg_destroy_world(world);
}

/* A chain of point count on body 0 of scene. */
static void kg_add_test_chain(kg_scene* scene, const kg_vec2* points, int count, int loop, float friction)
{
    kg_chain_def chain = kg_default_chain_def();
    chain.points = points;
    chain.count = count;
    chain.loop = loop;
    chain.friction = friction;
    chain.category = 3u;
    KG_CHECK_OK(kg_scene_add_body_chain(scene, 0, &chain));
}

/* A shapeless static body of 64 chains: 64 entries in "shapes", as many as the reader
 * takes, so it is written (the body's absent own shape is no entry) and reads back. */
static void test_chains_only_body(void)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_create(&scene));
    kg_body_def body = kg_default_body_def();
    body.type = KG_BODY_STATIC;
    KG_CHECK_OK(kg_scene_add_body(scene, "rails", &body));
    for (int k = 0; k < 64; ++k) {
        const kg_vec2 rail[] = {{0.0f, (float)k}, {4.0f, (float)k}};
        kg_add_test_chain(scene, rail, 2, 0, 0.5f);
    }
    kg_scene* loaded = kg_resave(scene, "rails.json");
    KG_CHECK(loaded && kg_scene_body_chain_count(loaded, 0) == 64 && kg_scene_body_shape_count(loaded, 0) == 1 &&
             kg_scene_body_def(loaded, 0)->shape.type == KG_SHAPE_NONE);
    kg_scene_destroy(loaded);
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
    KG_CHECK_OK(kg_scene_create(&scene)); /* ...but not what the reader would refuse: */
    kg_body_def def = kg_default_body_def();
    def.shape = kg_circle_shape(0.5f);
    def.mass = 2.0f;
    KG_CHECK_OK(kg_scene_add_body(scene, NULL, &def));
    kg_body_shape_def extra = kg_default_body_shape_def();
    extra.geometry = kg_box_shape(1.0f, 1.0f);
    KG_CHECK_OK(kg_scene_add_body_shape(scene, 0, &extra));
    KG_CHECK(kg_scene_save_file(scene, path) == KG_ERROR_UNSUPPORTED); /* a mass with two shapes */
    KG_CHECK(strstr(kg_last_error(), "several shapes and a mass") != NULL);
    for (int k = 0; k < 64; ++k) {
        KG_CHECK_OK(kg_scene_add_body_shape(scene, 0, &extra));
    }
    KG_CHECK(kg_scene_save_file(scene, path) == KG_ERROR_UNSUPPORTED); /* 66 shapes */
    KG_CHECK(strstr(kg_last_error(), "more than a scene file's \"shapes\" holds (64)") != NULL);
    kg_scene_destroy(scene);
    kg_destroy_world(world);
}

/* ---- a whole world: compound bodies, chains, a pivot, a joint of each kind ---- */

#define KG_JOINED_BODIES 11

/* Bodies 0 to 2: a ground box with an open chain and a loop, a compound crate of four
 * shapes of their own materials (one a sensor), a kinematic wall turning about a pivot. */
static void kg_add_test_bodies(kg_scene* scene)
{
    kg_body_def def = kg_default_body_def();
    def.type = KG_BODY_STATIC;
    def.position = (kg_vec2){0.0f, -0.5f};
    def.shape = kg_box_shape(40.0f, 1.0f);
    KG_CHECK_OK(kg_scene_add_body(scene, "ground", &def));
    const kg_vec2 hills[] = {{10.0f, 2.0f}, {5.0f, 1.0f}, {0.0f, 1.25f}, {-10.0f, 2.0f}};
    const kg_vec2 rock[] = {{3.0f, 5.0f}, {5.0f, 5.0f}, {4.0f, 6.0f}};
    kg_add_test_chain(scene, hills, 4, 0, 0.25f);
    kg_add_test_chain(scene, rock, 3, 1, 0.75f);
    def = kg_default_body_def();
    def.position = (kg_vec2){0.0f, 3.0f};
    def.shape = kg_box_shape(1.0f, 1.0f);
    def.density = 2.0f;
    KG_CHECK_OK(kg_scene_add_body(scene, "crate", &def));
    kg_body_shape_def extra = kg_default_body_shape_def();
    extra.geometry = kg_shape_moved(kg_circle_shape(0.25f), (kg_vec2){0.75f, 0.0f}, 0.0f);
    extra.friction = 0.875f;
    KG_CHECK_OK(kg_scene_add_body_shape(scene, 1, &extra));
    extra = kg_default_body_shape_def();
    extra.geometry = kg_capsule_shape((kg_vec2){0.0f, 0.5f}, (kg_vec2){0.0f, 1.0f}, 0.125f);
    extra.restitution = 0.5f;
    extra.category = 2u;
    extra.density = 3.0f;
    KG_CHECK_OK(kg_scene_add_body_shape(scene, 1, &extra));
    extra = kg_default_body_shape_def();
    const kg_vec2 triangle[] = {{-0.5f, 0.5f}, {-0.25f, 0.5f}, {-0.5f, 0.75f}};
    extra.geometry = kg_polygon_shape(triangle, 3);
    extra.is_sensor = 1;
    KG_CHECK_OK(kg_scene_add_body_shape(scene, 1, &extra));
    def = kg_default_body_def();
    def.type = KG_BODY_KINEMATIC;
    def.position = (kg_vec2){8.0f, 2.0f};
    def.shape = kg_box_shape(1.0f, 4.0f);
    def.angular_velocity = 0.5f;
    def.velocity = (kg_vec2){-1.0f, 0.0f}; /* 0.5 rad/s about (8, 0), 2 m away */
    KG_CHECK_OK(kg_scene_add_body(scene, "wall", &def));
    KG_CHECK_OK(kg_scene_set_body_pivot(scene, 2, (kg_vec2){8.0f, 0.0f}));
}

/* Bodies 3 to 10: boxes j0 ... j7 in a row at y = 8, x = -9, -7, ... (unturned, at
 * whole coordinates: a world anchor and a body's local one convert exactly). */
static void kg_add_joint_bodies(kg_scene* scene)
{
    for (int k = 0; k < 8; ++k) {
        kg_body_def def = kg_default_body_def();
        def.position = (kg_vec2){-9.0f + 2.0f * (float)k, 8.0f};
        def.shape = kg_box_shape(0.5f, 0.5f);
        char name[8];
        snprintf(name, sizeof name, "j%d", k);
        KG_CHECK_OK(kg_scene_add_body(scene, name, &def));
    }
}

/* One joint of each kind, every option away from its default. */
static void kg_add_test_joints(kg_scene* scene)
{
    kg_scene_joint j;
    memset(&j, 0, sizeof j);
    j.type = KG_JOINT_REVOLUTE;
    j.body_a = 3;
    j.body_b = 4;
    j.anchor_a = j.anchor_b = (kg_vec2){-8.0f, 8.0f};
    j.revolute = kg_default_revolute_joint_def();
    j.revolute.base.collide_connected = 1;
    j.revolute.base.constraint_hertz = 30.0f;
    j.revolute.base.constraint_damping_ratio = 2.0f;
    j.revolute.base.break_force = 1e6f;
    j.revolute.base.break_torque = 5e5f;
    j.revolute.reference_angle = 0.125f;
    j.revolute.enable_limit = 1;
    j.revolute.lower_angle = -0.5f;
    j.revolute.upper_angle = 0.75f;
    j.revolute.enable_spring = 1;
    j.revolute.hertz = 2.0f;
    j.revolute.damping_ratio = 0.25f;
    KG_CHECK_OK(kg_scene_add_joint(scene, &j));
    memset(&j, 0, sizeof j);
    j.type = KG_JOINT_DISTANCE;
    j.body_a = 4;
    j.body_b = 5;
    j.anchor_a = (kg_vec2){-7.0f, 8.25f};
    j.anchor_b = (kg_vec2){-5.0f, 8.25f};
    j.distance = kg_default_distance_joint_def();
    j.distance.length = 2.0f;
    j.distance.enable_spring = 1;
    j.distance.hertz = 3.0f;
    j.distance.damping_ratio = 0.5f;
    j.distance.enable_limit = 1;
    j.distance.min_length = 1.5f;
    j.distance.max_length = 2.5f;
    KG_CHECK_OK(kg_scene_add_joint(scene, &j));
    memset(&j, 0, sizeof j);
    j.type = KG_JOINT_WELD;
    j.body_a = 5;
    j.body_b = 6;
    j.anchor_a = j.anchor_b = (kg_vec2){-4.0f, 8.0f};
    j.weld = kg_default_weld_joint_def();
    j.weld.reference_angle = -0.25f;
    j.weld.linear_hertz = 5.0f;
    j.weld.linear_damping_ratio = 1.0f;
    KG_CHECK_OK(kg_scene_add_joint(scene, &j));
    memset(&j, 0, sizeof j);
    j.type = KG_JOINT_MOUSE;
    j.body_a = -1;
    j.body_b = 6;
    j.anchor_b = (kg_vec2){-3.0f, 8.25f};
    j.mouse = kg_default_mouse_joint_def();
    j.anchor_a = j.mouse.target = (kg_vec2){-3.0f, 9.0f};
    j.mouse.hertz = 4.0f;
    j.mouse.damping_ratio = 0.5f;
    KG_CHECK_OK(kg_scene_add_joint(scene, &j));
    memset(&j, 0, sizeof j);
    j.type = KG_JOINT_PRISMATIC;
    j.body_a = -1;
    j.body_b = 7;
    j.anchor_a = j.anchor_b = (kg_vec2){-1.0f, 8.0f};
    j.axis = (kg_vec2){1.0f, 0.0f};
    j.prismatic = kg_default_prismatic_joint_def();
    j.prismatic.enable_motor = 1;
    j.prismatic.motor_speed = 0.5f;
    j.prismatic.max_motor_force = 50.0f;
    j.prismatic.enable_spring = 1;
    j.prismatic.hertz = 1.5f;
    j.prismatic.damping_ratio = 0.75f;
    KG_CHECK_OK(kg_scene_add_joint(scene, &j));
    memset(&j, 0, sizeof j);
    j.type = KG_JOINT_WHEEL;
    j.body_a = 7;
    j.body_b = 8;
    j.anchor_a = j.anchor_b = (kg_vec2){1.0f, 8.0f};
    j.axis = (kg_vec2){0.0f, 1.0f};
    j.wheel = kg_default_wheel_joint_def();
    j.wheel.enable_limit = 1;
    j.wheel.lower_translation = -0.5f;
    j.wheel.upper_translation = 0.375f;
    j.wheel.enable_motor = 1;
    j.wheel.motor_speed = -3.0f;
    j.wheel.max_motor_torque = 20.0f;
    KG_CHECK_OK(kg_scene_add_joint(scene, &j));
    memset(&j, 0, sizeof j);
    j.type = KG_JOINT_MOTOR;
    j.body_a = 9;
    j.body_b = 10;
    j.motor = kg_default_motor_joint_def();
    j.motor.linear_offset = (kg_vec2){2.0f, 0.0f};
    j.motor.correction_factor = 0.5f;
    KG_CHECK_OK(kg_scene_add_joint(scene, &j));
}

/* The joints' setters after creation, each changing what the scene said. */
static void kg_change_joints(kg_world* world)
{
    kg_joint j[7];
    for (uint32_t i = 0; i < 7; ++i) {
        j[i] = kg_joint_of_slot(world, i);
    }
    KG_CHECK_OK(kg_revolute_joint_set_motor(world, j[0], 1, 2.5f, 40.0f));
    KG_CHECK_OK(kg_distance_joint_set_length(world, j[1], 2.25f));
    KG_CHECK_OK(kg_joint_set_break_thresholds(world, j[1], 2e6f, 1e6f));
    KG_CHECK_OK(kg_weld_joint_set_stiffness(world, j[2], 4.0f, 0.5f, 3.0f, 0.25f));
    KG_CHECK_OK(kg_mouse_joint_set_target(world, j[3], (kg_vec2){-2.5f, 9.5f}));
    KG_CHECK_OK(kg_mouse_joint_set_max_force(world, j[3], 250.0f));
    KG_CHECK_OK(kg_prismatic_joint_set_limits(world, j[4], 1, -0.75f, 1.5f));
    KG_CHECK_OK(kg_joint_set_collide_connected(world, j[4], 1));
    KG_CHECK_OK(kg_wheel_joint_set_spring(world, j[5], 1, 6.0f, 0.375f));
    KG_CHECK_OK(kg_motor_joint_set_offsets(world, j[6], (kg_vec2){2.5f, 0.5f}, 0.25f));
    KG_CHECK_OK(kg_motor_joint_set_max(world, j[6], 30.0f, 12.0f));
}

/* The scene of the whole world, instantiated into *world (bodies: its handles). */
static kg_scene* kg_joined_world(kg_world** world, kg_body* bodies)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_create(&scene));
    kg_add_test_bodies(scene);
    kg_add_joint_bodies(scene);
    kg_add_test_joints(scene);
    KG_CHECK_OK(kg_scene_instantiate(scene, NULL, world, bodies));
    kg_change_joints(*world);
    return scene;
}

#define KG_SAME(a, b, field) (memcmp(&(a).field, &(b).field, sizeof(a).field) == 0)

static int kg_same_base(kg_joint_base_def a, kg_joint_base_def b)
{
    return a.body_a.index == b.body_a.index && a.body_b.index == b.body_b.index && KG_SAME(a, b, collide_connected) &&
           KG_SAME(a, b, constraint_hertz) && KG_SAME(a, b, constraint_damping_ratio) &&
           KG_SAME(a, b, break_force) && KG_SAME(a, b, break_torque);
}

/* The options of the springs, motors and limits the kinds share the names of. */
#define KG_SAME_SPRING(a, b) (KG_SAME(a, b, enable_spring) && KG_SAME(a, b, hertz) && KG_SAME(a, b, damping_ratio))
#define KG_SAME_ANCHORS(a, b) (KG_SAME(a, b, local_anchor_a) && KG_SAME(a, b, local_anchor_b))

/* Joint ja of world a and jb of world b: the same kind, bodies, anchors, every option. */
static int kg_same_joint(const kg_world* a, kg_joint ja, const kg_world* b, kg_joint jb)
{
    kg_joint_type type, other;
    KG_CHECK_OK(kg_joint_get_type(a, ja, &type));
    KG_CHECK_OK(kg_joint_get_type(b, jb, &other));
    if (type != other) {
        return 0;
    }
    switch (type) {
    case KG_JOINT_REVOLUTE: {
        kg_revolute_joint_def x, y;
        KG_CHECK_OK(kg_revolute_joint_get_def(a, ja, &x));
        KG_CHECK_OK(kg_revolute_joint_get_def(b, jb, &y));
        return kg_same_base(x.base, y.base) && KG_SAME_ANCHORS(x, y) && KG_SAME(x, y, reference_angle) &&
               KG_SAME(x, y, enable_limit) && KG_SAME(x, y, lower_angle) && KG_SAME(x, y, upper_angle) &&
               KG_SAME(x, y, enable_motor) && KG_SAME(x, y, motor_speed) && KG_SAME(x, y, max_motor_torque) &&
               KG_SAME_SPRING(x, y);
    }
    case KG_JOINT_DISTANCE: {
        kg_distance_joint_def x, y;
        KG_CHECK_OK(kg_distance_joint_get_def(a, ja, &x));
        KG_CHECK_OK(kg_distance_joint_get_def(b, jb, &y));
        return kg_same_base(x.base, y.base) && KG_SAME_ANCHORS(x, y) && KG_SAME(x, y, length) &&
               KG_SAME_SPRING(x, y) && KG_SAME(x, y, enable_limit) && KG_SAME(x, y, min_length) &&
               KG_SAME(x, y, max_length);
    }
    case KG_JOINT_WELD: {
        kg_weld_joint_def x, y;
        KG_CHECK_OK(kg_weld_joint_get_def(a, ja, &x));
        KG_CHECK_OK(kg_weld_joint_get_def(b, jb, &y));
        return kg_same_base(x.base, y.base) && KG_SAME_ANCHORS(x, y) && KG_SAME(x, y, reference_angle) &&
               KG_SAME(x, y, linear_hertz) && KG_SAME(x, y, linear_damping_ratio) && KG_SAME(x, y, angular_hertz) &&
               KG_SAME(x, y, angular_damping_ratio);
    }
    case KG_JOINT_MOUSE: {
        kg_mouse_joint_def x, y;
        KG_CHECK_OK(kg_mouse_joint_get_def(a, ja, &x));
        KG_CHECK_OK(kg_mouse_joint_get_def(b, jb, &y));
        return kg_same_base(x.base, y.base) && KG_SAME(x, y, target) && KG_SAME(x, y, local_anchor_b) &&
               KG_SAME(x, y, hertz) && KG_SAME(x, y, damping_ratio) && KG_SAME(x, y, max_force);
    }
    case KG_JOINT_PRISMATIC: {
        kg_prismatic_joint_def x, y;
        KG_CHECK_OK(kg_prismatic_joint_get_def(a, ja, &x));
        KG_CHECK_OK(kg_prismatic_joint_get_def(b, jb, &y));
        return kg_same_base(x.base, y.base) && KG_SAME_ANCHORS(x, y) && KG_SAME(x, y, local_axis_a) &&
               KG_SAME(x, y, reference_angle) && KG_SAME(x, y, enable_limit) && KG_SAME(x, y, lower_translation) &&
               KG_SAME(x, y, upper_translation) && KG_SAME(x, y, enable_motor) && KG_SAME(x, y, motor_speed) &&
               KG_SAME(x, y, max_motor_force) && KG_SAME_SPRING(x, y);
    }
    case KG_JOINT_WHEEL: {
        kg_wheel_joint_def x, y;
        KG_CHECK_OK(kg_wheel_joint_get_def(a, ja, &x));
        KG_CHECK_OK(kg_wheel_joint_get_def(b, jb, &y));
        return kg_same_base(x.base, y.base) && KG_SAME_ANCHORS(x, y) && KG_SAME(x, y, local_axis_a) &&
               KG_SAME(x, y, enable_limit) && KG_SAME(x, y, lower_translation) &&
               KG_SAME(x, y, upper_translation) && KG_SAME(x, y, enable_motor) && KG_SAME(x, y, motor_speed) &&
               KG_SAME(x, y, max_motor_torque) && KG_SAME_SPRING(x, y);
    }
    default: {
        kg_motor_joint_def x, y;
        KG_CHECK_OK(kg_motor_joint_get_def(a, ja, &x));
        KG_CHECK_OK(kg_motor_joint_get_def(b, jb, &y));
        return kg_same_base(x.base, y.base) && KG_SAME(x, y, linear_offset) && KG_SAME(x, y, angular_offset) &&
               KG_SAME(x, y, max_force) && KG_SAME(x, y, max_torque) && KG_SAME(x, y, correction_factor);
    }
    }
}

static int kg_same_shape(const kg_body_shape_def* a, const kg_body_shape_def* b)
{
    const kg_shape_def *g = &a->geometry, *h = &b->geometry;
    int same = g->type == h->type && g->count == h->count && KG_SAME(*g, *h, center) && KG_SAME(*g, *h, radius) &&
               KG_SAME(*a, *b, density) && KG_SAME(*a, *b, friction) && KG_SAME(*a, *b, restitution) &&
               a->category == b->category && a->mask == b->mask && a->is_sensor == b->is_sensor;
    for (int k = 0; same && k < g->count && k < KG_MAX_POLYGON_VERTICES; ++k) {
        same = KG_SAME(*g, *h, vertices[k]);
    }
    return same;
}

/* Body ba of world a and bb of world b: type, state, mass, every shape (geometry and
 * material, in order). Counts the shapes into *shapes. */
static int kg_same_body(const kg_world* a, kg_body ba, const kg_world* b, kg_body bb, int* shapes)
{
    kg_body_type ta, tb;
    kg_body_state sa, sb;
    kg_mass_data ma, mb;
    KG_CHECK_OK(kg_body_get_type(a, ba, &ta));
    KG_CHECK_OK(kg_body_get_type(b, bb, &tb));
    KG_CHECK_OK(kg_body_get_state(a, ba, &sa));
    KG_CHECK_OK(kg_body_get_state(b, bb, &sb));
    KG_CHECK_OK(kg_body_get_mass_data(a, ba, &ma));
    KG_CHECK_OK(kg_body_get_mass_data(b, bb, &mb));
    int count = kg_body_shape_count(a, ba), n = 0;
    int same = ta == tb && memcmp(&sa, &sb, sizeof sa) == 0 && memcmp(&ma, &mb, sizeof ma) == 0 &&
               count == kg_body_shape_count(b, bb) && count <= 16;
    kg_shape_id ids_a[16], ids_b[16];
    if (same) {
        KG_CHECK_OK(kg_body_get_shapes(a, ba, ids_a, 16, &n));
        KG_CHECK_OK(kg_body_get_shapes(b, bb, ids_b, 16, &n));
    }
    for (int k = 0; same && k < count; ++k) {
        kg_body_shape_def da, db;
        KG_CHECK_OK(kg_shape_get_def(a, ids_a[k], &da));
        KG_CHECK_OK(kg_shape_get_def(b, ids_b[k], &db));
        same = kg_same_shape(&da, &db);
    }
    *shapes += count;
    return same;
}

/* World b holds what world a does (bodies: the handles of each, in the same order): the
 * same bodies, shapes and joints; *shapes and *joints count what was compared. */
static int kg_same_world(const kg_world* a, const kg_body* ba, const kg_world* b, const kg_body* bb, int* shapes,
                         int* joints)
{
    int same = kg_world_body_count(a) == kg_world_body_count(b) && kg_world_joint_count(a) == kg_world_joint_count(b);
    *shapes = *joints = 0;
    for (int i = 0; same && i < kg_world_body_count(a); ++i) {
        same = kg_same_body(a, ba[i], b, bb[i], shapes);
    }
    for (uint32_t i = 0; same && i < (uint32_t)kg_joints_slots(a); ++i) {
        kg_joint ja = kg_joint_of_slot(a, i), jb = kg_joint_of_slot(b, i);
        same = ja.generation != 0u && jb.generation != 0u && kg_same_joint(a, ja, b, jb);
        *joints += same;
    }
    return same;
}

/* Every body's state after steps of kg_scene_step. */
static void kg_scene_states_after(const kg_scene* scene, kg_world* world, const kg_body* bodies, int steps,
                                  kg_body_state* out)
{
    for (int s = 0; s < steps; ++s) {
        KG_CHECK_OK(kg_scene_step(scene, world, bodies, KG_DT));
    }
    KG_CHECK_OK(kg_world_get_body_states(world, bodies, kg_scene_body_count(scene), out));
}

/* text with its "state" (the last field) cut off: the scene an editor made afresh. */
static void kg_drop_state(char* text)
{
    char* state = strstr(text, "\"state\":");
    char* comma = state;
    while (comma && comma > text && *comma != ',') {
        --comma;
    }
    KG_CHECK(comma != NULL && *comma == ',');
    if (comma && *comma == ',') {
        strcpy(comma, "\n}\n");
    }
}

/* Saves the world of scene (bodies its handles) to name; returns the file's text. */
static char* kg_save_named(const kg_world* world, const kg_scene* scene, const kg_body* bodies, const char* name)
{
    char path[128];
    kg_path(path, sizeof path, name);
    kg_scene* saved = NULL;
    KG_CHECK_OK(kg_scene_from_world_named(world, scene, bodies, &saved));
    KG_CHECK_OK(kg_scene_save_file(saved, path));
    kg_scene_destroy(saved);
    char* text = kg_read_text(path);
    KG_CHECK(text != NULL);
    return text;
}

/* The world of text (its "state" dropped when fresh) into *world, handles into bodies. */
static kg_scene* kg_load_world(char* text, int fresh, kg_world** world, kg_body* bodies)
{
    kg_scene* scene = NULL;
    *world = NULL;
    if (fresh) {
        kg_drop_state(text);
    }
    KG_CHECK_OK(kg_scene_parse(text, strlen(text), "whole.json", &scene));
    if (scene) {
        KG_CHECK_OK(kg_scene_instantiate(scene, NULL, world, bodies));
    }
    return scene;
}

/* Saved before its first step, the world comes back from the file alone (no state): the
 * same 11 bodies and their 20 shapes (6 of them the chains' segments; compared field by
 * field),
 * its pivot, the 7 joints with the values their setters gave, and 120 steps of both give
 * the same bits. Every conversion is exact here (bodies unturned at whole coordinates,
 * axes along x and y), so nothing but the file could make them differ. */
static void test_whole_world_from_file(void)
{
    kg_world* world = NULL;
    kg_body bodies[KG_JOINED_BODIES], again_bodies[KG_JOINED_BODIES];
    kg_scene* scene = kg_joined_world(&world, bodies);
    char* text = kg_save_named(world, scene, bodies, "whole.json");
    KG_CHECK(text && strstr(text, "\"joints\":") && strstr(text, "\"pivot\":") && strstr(text, "\"chain\""));
    kg_world* again = NULL;
    kg_scene* loaded = text ? kg_load_world(text, 1, &again, again_bodies) : NULL;
    int shapes = 0, joints = 0;
    KG_CHECK(loaded && kg_scene_body_count(loaded) == KG_JOINED_BODIES && kg_scene_joint_count(loaded) == 7);
    KG_CHECK(loaded && kg_scene_body_shape_count(loaded, 1) == 4 && kg_scene_body_chain_count(loaded, 0) == 2);
    kg_vec2 pivot = {0.0f, 0.0f};
    KG_CHECK(loaded && kg_scene_body_pivot(loaded, 2, &pivot) && pivot.x == 8.0f && pivot.y == 0.0f);
    KG_CHECK(again && kg_same_world(world, bodies, again, again_bodies, &shapes, &joints));
    measured("  fresh from the file: %d shapes and %d joints the same as the saved world's\n", shapes, joints);
    KG_CHECK(shapes == 1 + 3 + 3 + 4 + 1 + 8 && joints == 7); /* ground: box, hills, rock; crate; wall; j0-j7 */
    kg_distance_joint_def rope;
    KG_CHECK_OK(kg_distance_joint_get_def(again, kg_joint_of_slot(again, 1), &rope));
    KG_CHECK(rope.length == 2.25f && rope.base.break_force == 2e6f && rope.min_length == 1.5f);
    kg_revolute_joint_def hinge;
    KG_CHECK_OK(kg_revolute_joint_get_def(again, kg_joint_of_slot(again, 0), &hinge));
    KG_CHECK(hinge.motor_speed == 2.5f && hinge.max_motor_torque == 40.0f && hinge.base.break_torque == 5e5f);
    KG_CHECK(kg_revolute_joint_get_def(again, kg_joint_of_slot(again, 1), &hinge) == KG_ERROR_INVALID_ARGUMENT);
    kg_body_state first[KG_JOINED_BODIES], second[KG_JOINED_BODIES];
    kg_scene_states_after(scene, world, bodies, 120, first);
    if (again) {
        kg_scene_states_after(loaded, again, again_bodies, 120, second);
    }
    KG_CHECK(memcmp(first, second, sizeof first) == 0);
    KG_CHECK_NEAR(first[2].angle, 1.0f, 1e-5f); /* the wall turned about its pivot: 0.5 rad/s for 2 s */
    KG_CHECK_NEAR(first[2].position.x, 8.0f - 2.0f * sinf(1.0f), 1e-4f);
    KG_CHECK_NEAR(first[2].position.y, 2.0f * cosf(1.0f), 1e-4f);
    free(text);
    kg_destroy_world(again);
    kg_scene_destroy(loaded);
    kg_destroy_world(world);
    kg_scene_destroy(scene);
}

/* The world of text without its state, stepped 60 times, against first (the saved
 * world's states after as many): close, not the same bits. The file holds everything a
 * level needs, but not what the solver carries between steps: the contacts and joints'
 * warm-start impulses and the sleep timers start over, and a joint's local anchors go
 * through world coordinates (their rounding) once the bodies have turned. */
static void kg_check_fresh_close(const char* text, const kg_body_state* first)
{
    char* copy = text ? strdup(text) : NULL;
    kg_world* fresh = NULL;
    kg_body handles[KG_JOINED_BODIES];
    kg_scene* scene = copy ? kg_load_world(copy, 1, &fresh, handles) : NULL;
    kg_body_state states[KG_JOINED_BODIES];
    float worst = 0.0f;
    if (fresh) {
        kg_scene_states_after(scene, fresh, handles, 60, states);
        for (int i = 0; i < KG_JOINED_BODIES; ++i) {
            worst = fmaxf(worst, fmaxf(fabsf(states[i].position.x - first[i].position.x),
                                       fabsf(states[i].position.y - first[i].position.y)));
        }
    }
    measured("  fresh from the file after 90 steps, 60 more: positions within %.3g m of the saved world's\n",
             (double)worst);
    KG_CHECK(fresh && worst < 0.02f);
    kg_destroy_world(fresh);
    kg_scene_destroy(scene);
    free(copy);
}

/* Saved after 90 steps: with its state the world continues bitwise, saving the loaded
 * world again gives the same bytes, and so does saving the loaded scene. */
static void test_whole_world_continues(void)
{
    kg_world* world = NULL;
    kg_body bodies[KG_JOINED_BODIES], again_bodies[KG_JOINED_BODIES];
    kg_scene* scene = kg_joined_world(&world, bodies);
    for (int s = 0; s < 90; ++s) {
        KG_CHECK_OK(kg_scene_step(scene, world, bodies, KG_DT));
    }
    char* text = kg_save_named(world, scene, bodies, "whole90.json");
    char* copy = text ? strdup(text) : NULL;
    kg_world* again = NULL;
    kg_scene* loaded = copy ? kg_load_world(copy, 0, &again, again_bodies) : NULL;
    char* resaved = again ? kg_save_named(again, loaded, again_bodies, "whole90b.json") : NULL;
    KG_CHECK(text && resaved && strcmp(text, resaved) == 0);
    char path[128];
    kg_path(path, sizeof path, "whole90c.json");
    KG_CHECK_OK(kg_scene_save_file(loaded, path));
    char* scene_saved = kg_read_text(path);
    KG_CHECK(text && scene_saved && strcmp(text, scene_saved) == 0);
    kg_body_state first[KG_JOINED_BODIES], second[KG_JOINED_BODIES];
    kg_scene_states_after(scene, world, bodies, 60, first);
    if (again) {
        kg_scene_states_after(loaded, again, again_bodies, 60, second);
    }
    KG_CHECK(memcmp(first, second, sizeof first) == 0);
    kg_check_fresh_close(text, first);
    free(text);
    free(copy);
    free(resaved);
    free(scene_saved);
    kg_destroy_world(again);
    kg_scene_destroy(loaded);
    kg_destroy_world(world);
    kg_scene_destroy(scene);
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
        KG_TEST(test_bad_state),         KG_TEST(test_state_must_fit),          KG_TEST(test_names_kept),
        KG_TEST(test_first_shape_sensor),  KG_TEST(test_bad_joint_refused),
        KG_TEST(test_many_shapes_with_state), KG_TEST(test_dense_shape_first),
        KG_TEST(test_shapeless_anchor),    KG_TEST(test_broken_loop_one_chain),
        KG_TEST(test_chains_only_body),    KG_TEST(test_save_errors),
        KG_TEST(test_whole_world_from_file), KG_TEST(test_whole_world_continues),
    };
    int code = kg_run_tests(tests, (int)(sizeof tests / sizeof tests[0]));
    const char* names[] = {"floats.json", "pile.json", "edited.json", "whole.json", "whole90.json", "whole90b.json",
                           "whole90c.json"};
    for (int i = 0; i < 7; ++i) {
        char path[128];
        kg_path(path, sizeof path, names[i]);
        remove(path);
    }
    rmdir(g_dir);
    return code;
}
