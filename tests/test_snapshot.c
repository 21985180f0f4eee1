/* Snapshots (include/kgyro/snapshot.h). The rollback test: a rain of 2,000 mixed bodies
 * (boxes, circles, capsules, polygons) onto a tile map with an edit, sleeping on, a wind
 * and a user force applicator; a snapshot at step 200, the run on to 600 recorded (every
 * body's state bits, awake flag and every contact), then the world changed (a tile
 * edited, a body destroyed, one created), restored and run to 600 again: bitwise the
 * same; and the snapshot restored into a fresh world run to 600: the same again. With 1
 * and 4 threads on the CPU, and on OpenCL where a device is (bitwise equal to the CPU's
 * run where the device rounds correctly). Then the bad snapshots: wrong magic, version,
 * layout, truncated at many lengths, a flipped byte, forged contents, a buffer too
 * small, an incompatible world: each refused with its code and the world unchanged (a
 * snapshot taken after equals one taken before, byte for byte). */
#include "kg_test.h"
#include "kg_test_world.h"
#include "kg_twin.h"
#include "core/snapshot_io.h"
#include "kgyro/kgyro.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define KG_DT (1.0f / 60.0f)

/* the rain's size and steps; smaller under the sanitizers (make test-sanitize) */
static int g_bodies = 2000;
static int g_snap_step = 200;
static int g_last_step = 600;

/* ---- the scene ---- */

typedef struct kg_scene_world {
    kg_world* world;
    kg_tilemap map;
} kg_scene_world;

/* A user applicator: a small push to the right on the bodies it lists. */
static void kg_push_right(kg_world* world, const kg_body* bodies, int count, void* user_data)
{
    (void)user_data;
    for (int i = 0; i < count; ++i) {
        kg_body_apply_force_to_center(world, bodies[i], (kg_vec2){0.5f, 0.0f});
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

static kg_world* kg_empty_world(kg_backend backend, int threads)
{
    kg_world_def def = kg_default_world_def();
    def.backend = backend;
    def.device_index = kg_test_opencl_device();
    def.threads = threads;
    def.max_bodies = 2200;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    return w;
}

/* The applicator every world of the scene registers first: the user one's slot must
 * match (it is the world's own callback). The bodies it pushes come from the snapshot
 * when one is restored (bodies NULL: a placeholder list). */
static void kg_register_callbacks(kg_world* world, const kg_body* bodies, int count)
{
    kg_body placeholder = KG_NULL_BODY_INIT;
    kg_applicator user;
    KG_CHECK_OK(kg_add_force_applicator(world, kg_push_right, bodies ? bodies : &placeholder, bodies ? count : 1, NULL,
                                        &user));
}

/* A 60 x 4 map of boxes with slopes on top, walls at its ends. */
static kg_tilemap kg_add_ground(kg_world* world)
{
    static uint16_t tiles[60 * 4];
    for (int i = 0; i < 60 * 4; ++i) {
        tiles[i] = (uint16_t)(i / 60 == 3 && i % 7 == 0 ? 2 : 1);
    }
    kg_tile_shape shapes[3] = {kg_tile_empty(), kg_tile_box(), kg_tile_slope(KG_TILE_BOTTOM_RIGHT)};
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = 60;
    def.height = 4;
    def.origin = (kg_vec2){-30.0f, -4.0f};
    def.shapes = shapes;
    def.shape_count = 3;
    def.tiles = tiles;
    kg_tilemap map = {0, 0};
    KG_CHECK_OK(kg_create_tilemap(world, &def, &map));
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){-30.5f, 20.0f}, 0.0f, kg_box_shape(1.0f, 48.0f));
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){30.5f, 20.0f}, 0.0f, kg_box_shape(1.0f, 48.0f));
    return map;
}

static kg_shape_def kg_rain_shape(int i, float size)
{
    switch (i % 4) {
    case 0: return kg_box_shape(size, 0.7f * size);
    case 1: return kg_circle_shape(0.5f * size);
    case 2: return kg_capsule_shape((kg_vec2){-0.3f * size, 0.0f}, (kg_vec2){0.3f * size, 0.0f}, 0.25f * size);
    default: {
        kg_vec2 pentagon[5] = {{-0.5f * size, 0.0f}, {0.5f * size, 0.0f}, {0.6f * size, 0.4f * size},
                               {0.0f, 0.7f * size}, {-0.6f * size, 0.4f * size}};
        return kg_polygon_shape(pentagon, 5);
    }
    }
}

/* Joints among the rain (issue 17): bodies 200 to 399 hinged in pairs at their midpoint,
 * and bodies 400 to 419 each on a 3 m rope from the world point above where it starts. */
static int g_joints; /* how many kg_add_rain_joints made (fewer under the sanitizers' smaller rain) */

static void kg_add_rain_joints(kg_world* world)
{
    kg_body bodies[420];
    int count = 0;
    KG_CHECK_OK(kg_world_get_bodies(world, bodies, 420, &count));
    kg_body_state a, b;
    for (int i = 200; i + 1 < 400 && i + 1 < count; i += 2) {
        KG_CHECK_OK(kg_body_get_state(world, bodies[i], &a));
        KG_CHECK_OK(kg_body_get_state(world, bodies[i + 1], &b));
        kg_vec2 middle = {0.5f * (a.position.x + b.position.x), 0.5f * (a.position.y + b.position.y)};
        kg_revolute_joint_def def = kg_default_revolute_joint_def();
        def.base.body_a = bodies[i];
        def.base.body_b = bodies[i + 1];
        KG_CHECK_OK(kg_joint_local_point(world, bodies[i], middle, &def.local_anchor_a));
        KG_CHECK_OK(kg_joint_local_point(world, bodies[i + 1], middle, &def.local_anchor_b));
        KG_CHECK_OK(kg_create_revolute_joint(world, &def, NULL));
    }
    for (int i = 400; i < 420 && i < count; ++i) {
        KG_CHECK_OK(kg_body_get_state(world, bodies[i], &a));
        kg_distance_joint_def rope = kg_default_distance_joint_def();
        rope.base.body_b = bodies[i];
        rope.local_anchor_a = (kg_vec2){a.position.x, a.position.y + 3.0f};
        rope.length = 3.0f;
        rope.enable_spring = 1;
        rope.enable_limit = 1;
        rope.max_length = 3.0f;
        KG_CHECK_OK(kg_create_distance_joint(world, &rope, NULL));
    }
    g_joints = kg_world_joint_count(world);
}

static kg_scene_world kg_rain_world(kg_backend backend, int threads)
{
    kg_scene_world s = {kg_empty_world(backend, threads), {0, 0}};
    s.map = kg_add_ground(s.world);
    uint32_t seed = 2024u;
    kg_body first[100];
    for (int i = 0; i < g_bodies; ++i) {
        kg_vec2 p = {kg_uniform(&seed, -20.0f, 20.0f), 1.0f + 0.6f * (float)(i / 40) + kg_uniform(&seed, 0.0f, 0.3f)};
        float size = kg_uniform(&seed, 0.2f, 0.45f);
        kg_body b = kg_test_add(s.world, KG_BODY_DYNAMIC, p, kg_uniform(&seed, 0.0f, 3.0f), kg_rain_shape(i, size));
        if (i < 100) {
            first[i] = b;
        }
    }
    kg_register_callbacks(s.world, first, 20);
    kg_applicator wind;
    KG_CHECK_OK(kg_add_wind_applicator(s.world, (kg_vec2){-1.0f, 0.0f}, 2.0f, 0.1f, first + 20, 40, &wind));
    kg_add_rain_joints(s.world);
    return s;
}

static void kg_step_to(kg_world* world, int* step, int last)
{
    for (; *step < last; ++*step) {
        KG_CHECK_OK(kg_world_step(world, KG_DT));
    }
}

/* ---- what is compared ---- */

typedef struct kg_record {
    int body_count, contact_count, awake, joint_count;
    kg_body* bodies;
    kg_body_state* states;
    int* awake_flags;
    kg_contact_info* contacts;
} kg_record;

static kg_record kg_take_record(const kg_world* world)
{
    kg_record r;
    memset(&r, 0, sizeof r);
    r.bodies = calloc(2200, sizeof *r.bodies);
    KG_CHECK_OK(kg_world_get_bodies(world, r.bodies, 2200, &r.body_count));
    r.states = calloc((size_t)r.body_count + 1, sizeof *r.states);
    r.awake_flags = calloc((size_t)r.body_count + 1, sizeof *r.awake_flags);
    KG_CHECK_OK(kg_world_get_body_states(world, r.bodies, r.body_count, r.states));
    for (int i = 0; i < r.body_count; ++i) {
        r.awake_flags[i] = kg_body_is_awake(world, r.bodies[i]);
        r.awake += r.awake_flags[i];
    }
    r.joint_count = kg_world_joint_count(world);
    r.contact_count = kg_world_contact_count(world);
    r.contacts = calloc((size_t)r.contact_count + 1, sizeof *r.contacts);
    for (int k = 0; k < r.contact_count; ++k) {
        KG_CHECK_OK(kg_world_get_contact(world, k, &r.contacts[k]));
    }
    return r;
}

static void kg_free_record(kg_record* r)
{
    free(r->bodies);
    free(r->states);
    free(r->awake_flags);
    free(r->contacts);
}

/* Bitwise the same bodies (handles, state bits, awake flags) and contacts. */
static int kg_same_record(const kg_record* a, const kg_record* b, const char* what)
{
    int same = a->body_count == b->body_count && a->contact_count == b->contact_count &&
               a->joint_count == b->joint_count &&
               memcmp(a->bodies, b->bodies, (size_t)a->body_count * sizeof *a->bodies) == 0 &&
               memcmp(a->states, b->states, (size_t)a->body_count * sizeof *a->states) == 0 &&
               memcmp(a->awake_flags, b->awake_flags, (size_t)a->body_count * sizeof *a->awake_flags) == 0 &&
               memcmp(a->contacts, b->contacts, (size_t)a->contact_count * sizeof *a->contacts) == 0;
    if (!same) {
        fprintf(stderr, "  %s: %d bodies and %d contacts against %d and %d\n", what, a->body_count, a->contact_count,
                b->body_count, b->contact_count);
    }
    return same;
}

/* The handles with their world's tag taken out, to compare worlds that were built apart. */
static void kg_untag_record(kg_record* r)
{
    for (int i = 0; i < r->body_count; ++i) {
        r->bodies[i] = kg_untagged_body(r->bodies[i]);
    }
    for (int k = 0; k < r->contact_count; ++k) {
        kg_untag_contact(&r->contacts[k]);
    }
}

static void* kg_take_snapshot(kg_world* world, size_t* size)
{
    KG_CHECK_OK(kg_world_snapshot_size(world, size));
    void* buffer = malloc(*size);
    size_t written = 0;
    KG_CHECK_OK(kg_world_snapshot(world, buffer, *size, &written));
    KG_CHECK(written == *size);
    return buffer;
}

/* Changes a restore must undo: a tile, a body destroyed, a jointed body destroyed (its
 * joint with it), a body created. */
static void kg_disturb(kg_scene_world* s)
{
    KG_CHECK_OK(kg_tilemap_set_tile(s->world, s->map, 0, 20, 3, 0));
    kg_body bodies[8];
    int count = 0;
    KG_CHECK_OK(kg_world_get_bodies(s->world, bodies, 8, &count));
    KG_CHECK_OK(kg_destroy_body(s->world, bodies[5]));
    kg_body jointed[202];
    KG_CHECK_OK(kg_world_get_bodies(s->world, jointed, 202, &count));
    KG_CHECK_OK(kg_destroy_body(s->world, jointed[201])); /* and its joint with it */
    kg_test_add(s->world, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 30.0f}, 0.0f, kg_box_shape(1.0f, 1.0f));
}

/* The rollback on one backend and thread count; *reference (NULL: none yet) is the first
 * configuration's final record, which every other must match where bitwise is expected. */
static void kg_rollback(kg_backend backend, int threads, kg_record* reference, int bitwise)
{
    kg_scene_world s = kg_rain_world(backend, threads);
    int step = 0;
    kg_step_to(s.world, &step, g_snap_step / 2);
    KG_CHECK_OK(kg_tilemap_set_tile(s.world, s.map, 0, 5, 3, 0)); /* an edit the snapshot holds */
    kg_step_to(s.world, &step, g_snap_step);
    size_t size = 0;
    void* snap = kg_take_snapshot(s.world, &size);
    kg_step_to(s.world, &step, g_last_step);
    kg_record first = kg_take_record(s.world);
    KG_CHECK(first.awake < first.body_count && first.contact_count > 0); /* sleeping and touching */
    KG_CHECK(first.joint_count == g_joints && g_joints > 0);

    kg_disturb(&s);
    KG_CHECK_OK(kg_world_restore(s.world, snap, size));
    int id = -1;
    KG_CHECK_OK(kg_tilemap_get_tile(s.world, s.map, 0, 20, 3, &id));
    KG_CHECK(id == 1);
    KG_CHECK_OK(kg_tilemap_get_tile(s.world, s.map, 0, 5, 3, &id));
    KG_CHECK(id == 0);
    step = g_snap_step;
    kg_step_to(s.world, &step, g_last_step);
    kg_record again = kg_take_record(s.world);
    KG_CHECK(kg_same_record(&first, &again, "restored into the same world"));

    kg_world* fresh = kg_empty_world(backend, threads == 1 ? 2 : 1);
    kg_register_callbacks(fresh, NULL, 0);
    KG_CHECK_OK(kg_world_restore(fresh, snap, size));
    step = g_snap_step;
    kg_step_to(fresh, &step, g_last_step);
    kg_record moved = kg_take_record(fresh);
    KG_CHECK(kg_same_record(&first, &moved, "restored into a fresh world"));

    kg_untag_record(&first);
    if (reference->bodies && bitwise) {
        KG_CHECK(kg_same_record(reference, &first, "against the first configuration"));
    }
    if (!reference->bodies) {
        *reference = first;
    } else {
        kg_free_record(&first);
    }
    printf("  backend %d, %d threads: %d bodies (%d awake), %d contacts, %d joints, snapshot %zu bytes\n",
           (int)backend, threads, again.body_count, again.awake, again.contact_count, again.joint_count, size);
    kg_free_record(&again);
    kg_free_record(&moved);
    free(snap);
    kg_destroy_world(fresh);
    kg_destroy_world(s.world);
}

static void test_rollback_bitwise(void)
{
    kg_record reference;
    memset(&reference, 0, sizeof reference);
    kg_rollback(KG_BACKEND_CPU, 1, &reference, 1);
    kg_rollback(KG_BACKEND_CPU, 4, &reference, 1);
    int bitwise = 0;
    if (kg_test_opencl_ready(&bitwise)) {
        kg_rollback(KG_BACKEND_OPENCL, 1, &reference, bitwise);
    }
    kg_free_record(&reference);
}

/* A snapshot taken on one backend steps on the other to the same bits. */
static void test_restore_across_backends(void)
{
    int bitwise = 0;
    if (!kg_test_opencl_ready(&bitwise) || !bitwise) {
        return;
    }
    kg_scene_world s = kg_rain_world(KG_BACKEND_OPENCL, 1);
    int step = 0;
    kg_step_to(s.world, &step, g_snap_step);
    size_t size = 0;
    void* snap = kg_take_snapshot(s.world, &size);
    kg_step_to(s.world, &step, g_snap_step + 60);
    kg_record device = kg_take_record(s.world);
    kg_world* cpu = kg_empty_world(KG_BACKEND_CPU, 1);
    kg_register_callbacks(cpu, NULL, 0);
    KG_CHECK_OK(kg_world_restore(cpu, snap, size));
    step = g_snap_step;
    kg_step_to(cpu, &step, g_snap_step + 60);
    kg_record host = kg_take_record(cpu);
    KG_CHECK(kg_same_record(&device, &host, "OpenCL snapshot stepped on the CPU"));
    kg_free_record(&device);
    kg_free_record(&host);
    free(snap);
    kg_destroy_world(cpu);
    kg_destroy_world(s.world);
}

/* ---- bad snapshots ---- */

typedef struct kg_small {
    kg_world* world;
    void* snap;
    size_t size;
} kg_small;

static kg_small kg_small_world(void)
{
    kg_small s;
    s.world = kg_empty_world(KG_BACKEND_CPU, 1);
    kg_register_callbacks(s.world, NULL, 0);
    kg_add_ground(s.world);
    for (int i = 0; i < 40; ++i) {
        kg_test_add(s.world, KG_BODY_DYNAMIC, (kg_vec2){0.3f * (float)(i % 8), 1.0f + (float)(i / 8)}, 0.1f,
                    kg_rain_shape(i, 0.4f));
    }
    for (int i = 0; i < 30; ++i) {
        KG_CHECK_OK(kg_world_step(s.world, KG_DT));
    }
    s.snap = kg_take_snapshot(s.world, &s.size);
    return s;
}

/* Restoring bytes fails with code and a message containing needle, and the world is as it was. */
static void kg_check_refused(kg_small* s, const void* bytes, size_t size, kg_result code, const char* needle)
{
    kg_result r = kg_world_restore(s->world, bytes, size);
    if (r != code || !strstr(kg_last_error(), needle)) {
        fprintf(stderr, "  restore of %zu bytes: %d \"%s\", expected %d with \"%s\"\n", size, (int)r, kg_last_error(),
                (int)code, needle);
        kg_test_failures++;
    }
    size_t size_after = 0;
    void* after = kg_take_snapshot(s->world, &size_after);
    KG_CHECK(size_after == s->size && memcmp(after, s->snap, s->size) == 0);
    free(after);
}

static void test_refuses_bad_header(void)
{
    kg_small s = kg_small_world();
    unsigned char* copy = malloc(s.size + 1);
    memcpy(copy, s.snap, s.size);
    copy[0] ^= 0x20u;
    kg_check_refused(&s, copy, s.size, KG_ERROR_INVALID_ARGUMENT, "not a KineticGyro snapshot");
    memcpy(copy, s.snap, s.size);
    copy[8] += 1u; /* the format version */
    kg_check_refused(&s, copy, s.size, KG_ERROR_UNSUPPORTED, "format version");
    memcpy(copy, s.snap, s.size);
    copy[36] += 4u; /* sizeof(float) in the layout fingerprint */
    kg_check_refused(&s, copy, s.size, KG_ERROR_UNSUPPORTED, "sizeof(float)");
    memcpy(copy, s.snap, s.size);
    copy[s.size] = 0u;
    kg_check_refused(&s, copy, s.size + 1, KG_ERROR_INVALID_ARGUMENT, "its header says");
    kg_check_refused(&s, NULL, 0, KG_ERROR_INVALID_ARGUMENT, "not a KineticGyro snapshot");
    free(copy);
    free(s.snap);
    kg_destroy_world(s.world);
}

static void test_refuses_truncated(void)
{
    kg_small s = kg_small_world();
    size_t lengths[] = {0, 3, 8, 11, 12, 40, 63, 64, 65, 200, s.size / 3, s.size / 2, s.size - 8, s.size - 1};
    for (size_t k = 0; k < sizeof lengths / sizeof lengths[0]; ++k) {
        void* cut = malloc(lengths[k] + 1);
        memcpy(cut, s.snap, lengths[k]);
        kg_result r = kg_world_restore(s.world, cut, lengths[k]);
        KG_CHECK(r == KG_ERROR_INVALID_ARGUMENT);
        KG_CHECK(lengths[k] < 8 || strstr(kg_last_error(), "truncated") != NULL);
        free(cut);
    }
    kg_check_refused(&s, s.snap, s.size - 1, KG_ERROR_INVALID_ARGUMENT, "truncated");
    free(s.snap);
    kg_destroy_world(s.world);
}

static void test_refuses_flipped_byte(void)
{
    kg_small s = kg_small_world();
    unsigned char* copy = malloc(s.size);
    size_t at[] = {16, 24, 72, 73, 100, s.size / 2, s.size - 1}; /* total size, checksum, then the contents */
    for (size_t k = 0; k < sizeof at / sizeof at[0]; ++k) {
        memcpy(copy, s.snap, s.size);
        copy[at[k]] ^= 0x01u;
        kg_check_refused(&s, copy, s.size, KG_ERROR_INVALID_ARGUMENT, k == 0 ? "its header says" : "");
        KG_CHECK(k < 2 || strstr(kg_last_error(), "checksum") != NULL);
    }
    free(copy);
    free(s.snap);
    kg_destroy_world(s.world);
}

/* Contents changed with the checksum made right again (a forged snapshot, or one of a
 * build that lays a struct out otherwise at the same size): refused or restored, never a
 * crash, and a restored one steps (the sanitizer build checks the memory). */
static void test_forged_contents(void)
{
    kg_small s = kg_small_world();
    unsigned char* copy = malloc(s.size);
    uint32_t seed = 99u;
    int refused = 0, tries = getenv("KG_FORGED_TRIES") ? atoi(getenv("KG_FORGED_TRIES")) : 300;
    for (int k = 0; k < tries; ++k) {
        memcpy(copy, s.snap, s.size);
        size_t at = 72 + (size_t)kg_next(&seed) % (s.size - 72);
        for (int j = 0; j < 4 && at + (size_t)j < s.size; ++j) {
            copy[at + (size_t)j] = (unsigned char)kg_next(&seed);
        }
        kg_snapshot_reseal(copy, s.size);
        kg_world* w = kg_empty_world(KG_BACKEND_CPU, 1);
        kg_register_callbacks(w, NULL, 0);
        if (kg_world_restore(w, copy, s.size) == KG_OK) {
            for (int i = 0; i < 3; ++i) {
                kg_world_step(w, KG_DT);
            }
        } else {
            refused++;
        }
        kg_destroy_world(w);
    }
    printf("  forged snapshots: %d of %d refused\n", refused, tries);
    KG_CHECK(refused > 0);
    free(copy);
    free(s.snap);
    kg_destroy_world(s.world);
}

static void test_capacity_and_arguments(void)
{
    kg_small s = kg_small_world();
    void* buffer = malloc(s.size);
    size_t written = 0;
    KG_CHECK(kg_world_snapshot(s.world, buffer, s.size - 1, &written) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(written == s.size);
    KG_CHECK(strstr(kg_last_error(), "needs") != NULL);
    KG_CHECK(kg_world_snapshot(NULL, buffer, s.size, &written) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_snapshot(s.world, NULL, 10, &written) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_snapshot_size(s.world, NULL) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_restore(NULL, s.snap, s.size) == KG_ERROR_INVALID_ARGUMENT);
    /* the same state twice gives the same bytes */
    KG_CHECK_OK(kg_world_snapshot(s.world, buffer, s.size, &written));
    KG_CHECK(written == s.size && memcmp(buffer, s.snap, s.size) == 0);
    free(buffer);
    free(s.snap);
    kg_destroy_world(s.world);
}

/* Worlds a snapshot does not fit: another max_bodies, or no user applicator where the
 * snapshot's world had one. Each is refused and left unchanged. */
static void test_refuses_incompatible_world(void)
{
    kg_small s = kg_small_world();
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    kg_world* other = NULL;
    KG_CHECK_OK(kg_create_world(&def, &other)); /* max_bodies 4096 */
    kg_register_callbacks(other, NULL, 0);
    KG_CHECK(kg_world_restore(other, s.snap, s.size) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(strstr(kg_last_error(), "max_bodies") != NULL);
    KG_CHECK(kg_world_body_count(other) == 0);
    kg_destroy_world(other);
    kg_world* bare = kg_empty_world(KG_BACKEND_CPU, 1);
    kg_body own = kg_test_add(bare, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.0f}, 0.0f, kg_circle_shape(0.5f));
    KG_CHECK(kg_world_restore(bare, s.snap, s.size) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(strstr(kg_last_error(), "user force applicator") != NULL);
    KG_CHECK(kg_world_body_count(bare) == 1 && kg_body_is_valid(bare, own));
    kg_destroy_world(bare);
    free(s.snap);
    kg_destroy_world(s.world);
}

/* Handles: the snapshot's world's are valid in a fresh world restored from it, the fresh
 * world's own earlier ones are not. */
static void test_handles_across_worlds(void)
{
    kg_small s = kg_small_world();
    kg_body source[64];
    int count = 0;
    KG_CHECK_OK(kg_world_get_bodies(s.world, source, 64, &count));
    kg_world* fresh = kg_empty_world(KG_BACKEND_CPU, 1);
    kg_register_callbacks(fresh, NULL, 0);
    kg_body own = kg_test_add(fresh, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 50.0f}, 0.0f, kg_circle_shape(0.5f));
    KG_CHECK(!kg_body_is_valid(fresh, source[count - 1]));
    KG_CHECK_OK(kg_world_restore(fresh, s.snap, s.size));
    KG_CHECK(kg_world_body_count(fresh) == count);
    for (int i = 0; i < count; ++i) {
        KG_CHECK(kg_body_is_valid(fresh, source[i]));
    }
    kg_vec2 p;
    KG_CHECK(kg_body_get_position(fresh, own, &p) == KG_ERROR_INVALID_HANDLE);
    kg_destroy_world(fresh);
    free(s.snap);
    kg_destroy_world(s.world);
}

int main(int argc, char** argv)
{
    if (getenv("KGYRO_SANITIZED")) {
        g_bodies = 400;
        g_snap_step = 60;
        g_last_step = 150;
    }
    static const kg_test_case tests[] = {
        KG_TEST(test_refuses_bad_header),     KG_TEST(test_refuses_truncated),
        KG_TEST(test_refuses_flipped_byte),   KG_TEST(test_forged_contents),
        KG_TEST(test_capacity_and_arguments), KG_TEST(test_refuses_incompatible_world),
        KG_TEST(test_handles_across_worlds),  KG_TEST(test_rollback_bitwise),
        KG_TEST(test_restore_across_backends),
    };
    int count = (int)(sizeof tests / sizeof tests[0]);
    return kg_run_chosen_tests(tests, count, count, argc, argv);
}
