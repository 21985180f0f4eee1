/* Every failure of the OpenCL backend, injected with KGYRO_CL_FAIL (cl_fault.h), hands the
 * world to the CPU backend without losing state:
 *  - at start (load, platform, build, alloc): the world runs on the CPU from creation;
 *  - inside a step (enqueue, finish, any read, a force callback's read included): the step
 *    is redone on the CPU from the checkpoint, and the world ends bitwise where a CPU-only
 *    world ends; a read failing in a force callback (a getter's, the transforms', the
 *    contacts') falls back only once the step has unwound, the callback still running on
 *    the OpenCL backend until it returns;
 *  - a failed read for a getter between steps (the contacts' included): tried again, same
 *    result;
 *  - a lost device: the world goes on from the last state and contacts the host read back
 *    whole;
 *  - bodies asleep, or woken in the step that fails: flags, rest timers and islands
 *    carried over with the rest of the state.
 * Skips (exit 77) when no OpenCL device exists. */
#include "kg_test.h"
#include "kg_twin.h"
#include "kgyro/kgyro.h"
#include "kgyro/opencl.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define KG_SKIP 77
#define KG_STEPS 120
#define KG_SYNC_EVERY 20
#define KG_DT (1.0f / 60.0f)

static void kg_add_box(kg_world* world, kg_body_type type, float x, float y, float w, float h)
{
    kg_body_def def = kg_default_body_def();
    def.type = type;
    def.position = (kg_vec2){x, y};
    def.shape = kg_box_shape(w, h);
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &def, &body));
}

/* What the force callback of the lost-device test saw: the step being taken, and the last
 * step in which it read the contacts and the state back from the device. */
typedef struct kg_read_probe {
    int step;
    int read_on_device;
} kg_read_probe;

/* A force callback that reads the state mid-step: reads happen inside steps too. Given a
 * probe in user_data, it reads the contacts back first, and records whether both reads
 * came from the device. */
static void kg_lift_highest(kg_world* world, const kg_body* bodies, int count, void* user_data)
{
    kg_read_probe* probe = user_data;
    if (probe) {
        kg_world_contact_count(world);
    }
    for (int i = 0; i < count; ++i) {
        kg_vec2 p;
        if (kg_body_get_position(world, bodies[i], &p) == KG_OK && p.y > 8.0f) {
            kg_body_apply_force_to_center(world, bodies[i], (kg_vec2){0.0f, 2.0f});
        }
    }
    if (probe && kg_world_backend(world) == KG_BACKEND_OPENCL) {
        probe->read_on_device = probe->step;
    }
}

/* An empty world on backend, with the faults injected and a contact pool of
 * max_contacts (0: the default). */
static kg_world* kg_make_empty_world(kg_backend backend, const char* faults, int max_contacts)
{
    if (faults) {
        setenv("KGYRO_CL_FAIL", faults, 1);
    } else {
        unsetenv("KGYRO_CL_FAIL");
    }
    kg_world_def def = kg_default_world_def();
    def.backend = backend;
    def.max_bodies = 64;
    def.max_contacts = max_contacts;
    kg_world* world = NULL;
    KG_CHECK_OK(kg_create_world(&def, &world));
    unsetenv("KGYRO_CL_FAIL");
    return world;
}

/* A ground and twelve boxes that fall, touch and stack. */
static void kg_add_ground_and_stack(kg_world* world)
{
    kg_add_box(world, KG_BODY_STATIC, 0.0f, -0.5f, 20.0f, 1.0f);
    for (int i = 0; i < 12; ++i) {
        kg_add_box(world, KG_BODY_DYNAMIC, 0.3f * (float)(i % 3), 0.6f + 1.1f * (float)i, 1.0f, 0.8f);
    }
}

/* Bodies that fall, touch and stack, with a wind applicator and the force callback fn:
 * every stage has work. A contact pool of max_contacts (0: the default). */
static kg_world* kg_make_stack_world(kg_backend backend, const char* faults, int max_contacts, kg_force_fn* fn,
                                     void* user_data)
{
    kg_world* world = kg_make_empty_world(backend, faults, max_contacts);
    if (!world) {
        return NULL;
    }
    kg_add_ground_and_stack(world);
    kg_applicator a;
    KG_CHECK_OK(kg_add_wind_applicator(world, (kg_vec2){1.0f, 0.0f}, 0.5f, 0.1f, NULL, 0, &a));
    KG_CHECK_OK(kg_add_force_applicator(world, fn, NULL, 0, user_data, &a));
    return world;
}

/* The same in the default contact pool. */
static kg_world* kg_make_world_calling(kg_backend backend, const char* faults, kg_force_fn* fn, void* user_data)
{
    return kg_make_stack_world(backend, faults, 0, fn, user_data);
}

/* The same with kg_lift_highest as its callback. */
static kg_world* kg_make_world(kg_backend backend, const char* faults, kg_read_probe* probe)
{
    return kg_make_world_calling(backend, faults, kg_lift_highest, probe);
}

/* A hash of the bits of every body's state, read through the public getters. */
static uint64_t kg_state_hash(kg_world* world)
{
    kg_body bodies[64];
    int count = 0;
    kg_world_get_bodies(world, bodies, 64, &count);
    uint64_t h = 1469598103934665603ull;
    for (int i = 0; i < count; ++i) {
        kg_body_state s;
        kg_body_get_state(world, bodies[i], &s);
        const unsigned char* bytes = (const unsigned char*)&s;
        for (size_t k = 0; k < sizeof s; ++k) {
            h = (h ^ bytes[k]) * 1099511628211ull;
        }
    }
    return h;
}

/* hashes[s] is the CPU world's state after s steps. */
static void kg_reference(uint64_t* hashes)
{
    kg_world* cpu = kg_make_world(KG_BACKEND_CPU, NULL, NULL);
    hashes[0] = kg_state_hash(cpu);
    for (int s = 1; s <= KG_STEPS; ++s) {
        KG_CHECK_OK(kg_world_step(cpu, KG_DT));
        hashes[s] = kg_state_hash(cpu);
    }
    kg_destroy_world(cpu);
}

static uint64_t g_reference[KG_STEPS + 1];

/* Runs a world with the faults injected, reading its state back every KG_SYNC_EVERY
 * steps; returns the step after which it was on the CPU (0: from the start, -1: never). */
static int kg_run_with_faults(const char* faults, uint64_t* final_hash)
{
    kg_world* world = kg_make_world(KG_BACKEND_OPENCL, faults, NULL);
    if (!world) {
        return -2;
    }
    int fell_back_at = kg_world_backend(world) == KG_BACKEND_CPU ? 0 : -1;
    for (int s = 1; s <= KG_STEPS; ++s) {
        KG_CHECK_OK(kg_world_step(world, KG_DT));
        if (s % KG_SYNC_EVERY == 0) {
            kg_state_hash(world);
        }
        if (fell_back_at < 0 && kg_world_backend(world) == KG_BACKEND_CPU) {
            fell_back_at = s;
        }
    }
    *final_hash = kg_state_hash(world);
    kg_destroy_world(world);
    return fell_back_at;
}

/* The failure makes the world fall back, and it ends exactly where the CPU world ends. */
static void kg_expect_intact(const char* faults, int expect_at_start)
{
    uint64_t final_hash = 0;
    int at = kg_run_with_faults(faults, &final_hash);
    printf("     KGYRO_CL_FAIL=%-10s fell back %s %d, final state %s\n", faults, at == 0 ? "at creation" : "in step",
           at, final_hash == g_reference[KG_STEPS] ? "bitwise equal to the CPU's" : "DIFFERENT");
    KG_CHECK(expect_at_start ? at == 0 : at > 0);
    KG_CHECK(final_hash == g_reference[KG_STEPS]);
}

static void test_no_fault_no_fallback(void)
{
    uint64_t final_hash = 0;
    KG_CHECK(kg_run_with_faults(NULL, &final_hash) == -1);
    KG_CHECK(final_hash == g_reference[KG_STEPS]);
}

static void test_load_failure(void) { kg_expect_intact("load", 1); }
static void test_no_platform(void) { kg_expect_intact("platform", 1); }
static void test_build_failure(void) { kg_expect_intact("build", 1); }
static void test_alloc_failure(void) { kg_expect_intact("alloc:7", 1); }
/* Any failing command, wherever it falls (uploads, launches, the force callback's reads,
 * the collide stage's reads, the contacts' read, the final wait), leaves the state intact. */
static void kg_expect_intact_at(const char* site, const int* calls, int count)
{
    for (int i = 0; i < count; ++i) {
        char spec[32];
        snprintf(spec, sizeof spec, "%s:%d", site, calls[i]);
        kg_expect_intact(spec, 0);
    }
}

static void test_enqueue_failures(void)
{
    static const int calls[] = {1, 2, 3, 40, 777, 2000};
    kg_expect_intact_at("enqueue", calls, (int)(sizeof calls / sizeof calls[0]));
}

static void test_kernel_failures(void)
{
    static const int calls[] = {1, 37, 100};
    kg_expect_intact_at("finish", calls, (int)(sizeof calls / sizeof calls[0]));
}

static void test_read_failures(void)
{
    static const int calls[] = {1, 2, 9, 10, 11, 50, 80, 333};
    kg_expect_intact_at("read", calls, (int)(sizeof calls / sizeof calls[0]));
}

/* The contacts stay on the device until asked for. When reading them back between steps
 * fails, the world falls back, reads them again, and goes on with them intact: the
 * contacts and, steps later, the state are bitwise the CPU world's. */
static void test_contact_read_failure(void)
{
    const int steps = 40;
    kg_world* probe = kg_make_world(KG_BACKEND_OPENCL, NULL, NULL);
    for (int s = 0; s < steps; ++s) {
        KG_CHECK_OK(kg_world_step(probe, KG_DT));
    }
    kg_transfer_stats stats;
    KG_CHECK_OK(kg_world_get_transfer_stats(probe, &stats));
    kg_destroy_world(probe);
    char faults[32];
    snprintf(faults, sizeof faults, "read:%d", stats.reads + 1); /* the next read: the contacts' */
    kg_world* cpu = kg_make_world(KG_BACKEND_CPU, NULL, NULL);
    kg_world* world = kg_make_world(KG_BACKEND_OPENCL, faults, NULL);
    for (int s = 0; s < steps; ++s) {
        KG_CHECK_OK(kg_world_step(cpu, KG_DT));
        KG_CHECK_OK(kg_world_step(world, KG_DT));
    }
    KG_CHECK(kg_world_backend(world) == KG_BACKEND_OPENCL);
    int n = kg_world_contact_count(world);
    KG_CHECK(kg_world_backend(world) == KG_BACKEND_CPU);
    KG_CHECK(n > 0 && n == kg_world_contact_count(cpu));
    for (int k = 0; k < n; ++k) {
        kg_contact_info a, b;
        KG_CHECK_OK(kg_world_get_contact(cpu, k, &a));
        KG_CHECK_OK(kg_world_get_contact(world, k, &b));
        kg_untag_contact(&a);
        kg_untag_contact(&b);
        KG_CHECK(memcmp(&a, &b, sizeof a) == 0);
    }
    for (int s = steps; s < KG_STEPS; ++s) {
        KG_CHECK_OK(kg_world_step(cpu, KG_DT));
        KG_CHECK_OK(kg_world_step(world, KG_DT));
    }
    KG_CHECK(kg_state_hash(world) == kg_state_hash(cpu));
    kg_destroy_world(cpu);
    kg_destroy_world(world);
}

static void test_bad_spec_is_ignored(void) { kg_expect_intact("nonsense,build", 1); }

/* Two rows of boxes (ten islands of two) that fall asleep at about step 40, and a box
 * falling from high up that wakes two of them at about step 80. */
static kg_world* kg_make_sleeping_world(kg_backend backend, const char* faults)
{
    kg_world* world = kg_make_empty_world(backend, faults, 0);
    if (!world) {
        return NULL;
    }
    kg_add_box(world, KG_BODY_STATIC, 0.0f, -0.5f, 20.0f, 1.0f);
    for (int i = 0; i < 20; ++i) {
        kg_add_box(world, KG_BODY_DYNAMIC, -4.5f + 0.9f * (float)(i % 10), 0.35f + 0.65f * (float)(i / 10), 0.8f, 0.6f);
    }
    kg_add_box(world, KG_BODY_DYNAMIC, 0.2f, 10.0f, 0.5f, 0.5f);
    return world;
}

/* A fallback while bodies sleep, in the step that wakes them, or between steps (the read
 * of kg_world_asleep_count's at step 60 failing: read:121, after two reads per step)
 * carries the flags, rest timers and islands over: the world ends, and has as many bodies
 * asleep on the way, as a CPU-only world. */
static void test_sleep_state_carried_over(void)
{
    enum { STEPS = 150, PROBE = 60 };
    static const char* const faults[] = {"finish:50", "finish:80", "finish:81", "read:121", "read:150", "enqueue:4000"};
    kg_world* cpu = kg_make_sleeping_world(KG_BACKEND_CPU, NULL);
    int cpu_asleep[STEPS + 1];
    for (int s = 1; s <= STEPS; ++s) {
        KG_CHECK_OK(kg_world_step(cpu, KG_DT));
        cpu_asleep[s] = s == PROBE || s == STEPS ? kg_world_asleep_count(cpu) : 0;
    }
    uint64_t reference = kg_state_hash(cpu);
    KG_CHECK(cpu_asleep[PROBE] == 20);
    kg_destroy_world(cpu);
    for (int f = 0; f < (int)(sizeof faults / sizeof faults[0]); ++f) {
        kg_world* world = kg_make_sleeping_world(KG_BACKEND_OPENCL, faults[f]);
        int fell_back_at = -1, same_asleep = 1;
        for (int s = 1; s <= STEPS; ++s) {
            KG_CHECK_OK(kg_world_step(world, KG_DT));
            same_asleep &= s != PROBE || kg_world_asleep_count(world) == cpu_asleep[s];
            fell_back_at = fell_back_at < 0 && kg_world_backend(world) == KG_BACKEND_CPU ? s : fell_back_at;
        }
        same_asleep &= kg_world_asleep_count(world) == cpu_asleep[STEPS];
        uint64_t hash = kg_state_hash(world);
        printf("     KGYRO_CL_FAIL=%-12s fell back in step %d, final state %s, bodies asleep %s\n", faults[f],
               fell_back_at, hash == reference ? "bitwise equal to the CPU's" : "DIFFERENT",
               same_asleep ? "the same" : "DIFFERENT");
        KG_CHECK(fell_back_at > 0);
        KG_CHECK(hash == reference);
        KG_CHECK(same_asleep);
        kg_destroy_world(world);
    }
}

/* ---- a fallback forced by a force callback, mid-step ------------------------------- */

enum { KG_FIRST_GETTER, KG_FIRST_TRANSFORMS, KG_FIRST_CONTACTS, KG_FIRST_CALL_KINDS };

/* What the callback of the mid-step tests does and saw. In every step it first makes the
 * call of kind first (a body getter, kg_world_get_transforms or the contact count; in
 * fail_step, the read of that call is the one that fails), then lifts as kg_lift_highest
 * does (so the world moves as the reference world does), then reads everything else
 * back: transforms, contacts, every body's state. */
typedef struct kg_midstep_probe {
    int first;
    int step;                 /* the step being taken */
    int fail_step;
    int reads_at_entry;       /* the device reads made before the callback of fail_step */
    int first_call_read;      /* the first call of that callback read the device */
    int reads_at_exit;        /* the device reads made when it returned */
    int calls[KG_STEPS + 2];  /* callback calls per step */
    int on_opencl[KG_STEPS + 2]; /* ... of which while the world reported the OpenCL backend */
    int insane;               /* values read back that were not finite, or getters failing */
} kg_midstep_probe;

static int kg_device_reads(kg_world* world)
{
    kg_transfer_stats stats;
    KG_CHECK_OK(kg_world_get_transfer_stats(world, &stats));
    return stats.reads;
}

static int kg_finite_state(const kg_body_state* s)
{
    return isfinite(s->position.x) && isfinite(s->position.y) && isfinite(s->angle) && isfinite(s->velocity.x) &&
           isfinite(s->velocity.y) && isfinite(s->angular_velocity);
}

static void kg_midstep_first_call(kg_world* world, const kg_body* bodies, int count, int first)
{
    kg_vec2 p;
    float angle;
    if (count == 0) {
        return;
    }
    if (first == KG_FIRST_GETTER) {
        kg_body_get_position(world, bodies[0], &p);
    } else if (first == KG_FIRST_TRANSFORMS) {
        kg_world_get_transforms(world, bodies, 1, &p, &angle);
    } else {
        kg_world_contact_count(world);
    }
}

static void kg_midstep_callback(kg_world* world, const kg_body* bodies, int count, void* user_data)
{
    kg_midstep_probe* probe = user_data;
    int s = probe->step;
    probe->calls[s] += 1;
    probe->on_opencl[s] += kg_world_backend(world) == KG_BACKEND_OPENCL;
    int reads = kg_device_reads(world);
    if (s == probe->fail_step && probe->calls[s] == 1) {
        probe->reads_at_entry = reads;
    }
    kg_midstep_first_call(world, bodies, count, probe->first);
    if (s == probe->fail_step && probe->calls[s] == 1) {
        probe->first_call_read = kg_device_reads(world) > reads;
    }
    kg_lift_highest(world, bodies, count, NULL);
    kg_vec2 positions[64];
    float angles[64];
    int n = count < 64 ? count : 64;
    probe->insane |= kg_world_get_transforms(world, bodies, n, positions, angles) != KG_OK;
    for (int i = 0; i < n; ++i) {
        probe->insane |= !isfinite(positions[i].x) || !isfinite(positions[i].y) || !isfinite(angles[i]);
    }
    int contacts = kg_world_contact_count(world);
    for (int k = 0; k < contacts; ++k) {
        kg_contact_info info;
        probe->insane |= kg_world_get_contact(world, k, &info) != KG_OK;
    }
    for (int i = 0; i < count; ++i) {
        kg_body_state state;
        probe->insane |= kg_body_get_state(world, bodies[i], &state) != KG_OK || !kg_finite_state(&state);
    }
    if (s == probe->fail_step && probe->calls[s] == 1) {
        probe->reads_at_exit = kg_device_reads(world);
    }
}

/* Steps a world whose callback is probe's through steps [from, to], each expected OK. */
static void kg_midstep_run(kg_world* world, kg_midstep_probe* probe, int from, int to)
{
    for (int s = from; s <= to; ++s) {
        probe->step = s;
        KG_CHECK_OK(kg_world_step(world, KG_DT));
    }
}

/* A force callback's read fails in step FAIL_STEP (the first read of its first call, of
 * kind first), which makes the world fall back in the middle of the step, with the
 * callback still running. The fallback takes effect once the step has unwound: the
 * callback goes on on the OpenCL backend, its getters answer from the host's copy
 * (finite values, no error) without calling the device again; the step returns KG_OK,
 * redone on the CPU (the callback runs twice in that step); the world holds the same
 * bodies, bitwise in the CPU world's state; the next steps run on the CPU. ASan and UBSan
 * watch that nothing is used after it is freed. */
static void kg_expect_midstep_fallback(int first)
{
    enum { FAIL_STEP = 30 };
    static const char* const names[] = {"a body getter", "kg_world_get_transforms", "the contact count"};
    kg_midstep_probe* probe = calloc(1, sizeof *probe);
    probe->first = first;
    probe->fail_step = FAIL_STEP;
    kg_world* clean = kg_make_world_calling(KG_BACKEND_OPENCL, NULL, kg_midstep_callback, probe);
    kg_midstep_run(clean, probe, 1, FAIL_STEP);
    KG_CHECK(kg_world_backend(clean) == KG_BACKEND_OPENCL);
    KG_CHECK(probe->first_call_read);
    KG_CHECK(kg_state_hash(clean) == g_reference[FAIL_STEP]);
    kg_destroy_world(clean);

    char faults[32];
    snprintf(faults, sizeof faults, "read:%d", probe->reads_at_entry + 1);
    int reads_at_entry = probe->reads_at_entry;
    memset(probe, 0, sizeof *probe);
    probe->first = first;
    probe->fail_step = FAIL_STEP;
    kg_world* world = kg_make_world_calling(KG_BACKEND_OPENCL, faults, kg_midstep_callback, probe);
    kg_midstep_run(world, probe, 1, FAIL_STEP - 1);
    KG_CHECK(kg_world_backend(world) == KG_BACKEND_OPENCL);
    kg_midstep_run(world, probe, FAIL_STEP, FAIL_STEP);
    KG_CHECK(probe->reads_at_entry == reads_at_entry); /* the failing read is the callback's */
    KG_CHECK(probe->reads_at_exit == reads_at_entry);  /* and no read was tried after it */
    KG_CHECK(probe->calls[FAIL_STEP] == 2);     /* on the device, then redone on the CPU */
    KG_CHECK(probe->on_opencl[FAIL_STEP] == 1); /* the world was not switched under the callback */
    KG_CHECK(kg_world_backend(world) == KG_BACKEND_CPU);
    KG_CHECK(kg_world_body_count(world) == 13);
    KG_CHECK(kg_state_hash(world) == g_reference[FAIL_STEP]);
    kg_midstep_run(world, probe, FAIL_STEP + 1, KG_STEPS);
    KG_CHECK(probe->calls[FAIL_STEP + 1] == 1 && probe->on_opencl[FAIL_STEP + 1] == 0);
    KG_CHECK(kg_world_backend(world) == KG_BACKEND_CPU);
    KG_CHECK(kg_device_reads(world) == 0); /* no device behind the world any more */
    KG_CHECK(!probe->insane);
    uint64_t hash = kg_state_hash(world);
    printf("     KGYRO_CL_FAIL=%-9s (%s, in the callback of step %d): step OK, next steps on the CPU, final state "
           "%s\n", faults, names[first], FAIL_STEP, hash == g_reference[KG_STEPS] ? "bitwise equal to the CPU's"
                                                                                   : "DIFFERENT");
    KG_CHECK(hash == g_reference[KG_STEPS]);
    kg_destroy_world(world);
    free(probe);
}

static void test_callback_forces_fallback_mid_step(void)
{
    for (int first = 0; first < KG_FIRST_CALL_KINDS; ++first) {
        kg_expect_midstep_fallback(first);
    }
}

/* Six boxes thrown up through the one-way platforms of a tile map above the ground and
 * the stack of kg_make_world, in a world whose contact pool starts at 2 slots: the pairs
 * outgrow it in several steps, whose collide stage then runs on the host (it grows the
 * pool) while the rest of the step runs on the device. */
static kg_world* kg_make_growing_world(kg_backend backend, const char* faults)
{
    static kg_tile_shape shapes[3];
    static uint16_t tiles[8 * 6];
    kg_world* world = kg_make_empty_world(backend, faults, 2);
    if (!world) {
        return NULL;
    }
    kg_add_ground_and_stack(world);
    shapes[0] = kg_tile_empty();
    shapes[1] = kg_tile_box();
    shapes[2] = kg_tile_platform();
    for (int x = 0; x < 8; ++x) {
        tiles[x] = 1;
        tiles[3 * 8 + x] = 2;
    }
    kg_tilemap_def map = kg_default_tilemap_def();
    map.width = 8;
    map.height = 6;
    map.origin = (kg_vec2){-8.0f, 2.0f};
    map.shapes = shapes;
    map.shape_count = 3;
    map.tiles = tiles;
    kg_tilemap handle;
    KG_CHECK_OK(kg_create_tilemap(world, &map, &handle));
    for (int i = 0; i < 6; ++i) {
        kg_body_def def = kg_default_body_def();
        def.position = (kg_vec2){-7.0f + 1.1f * (float)i, 4.0f + 0.3f * (float)i};
        def.velocity = (kg_vec2){0.0f, 6.0f};
        def.shape = kg_box_shape(0.3f, 0.3f);
        kg_body body;
        KG_CHECK_OK(kg_create_body(world, &def, &body));
    }
    return world;
}

/* Whether the last step's collide stage ran on the host. */
static int kg_collided_on_host(kg_world* world)
{
    kg_stage_times t;
    KG_CHECK_OK(kg_world_get_stage_times(world, &t));
    int on_host = 0;
    for (int k = 0; k < t.count; ++k) {
        on_host |= strcmp(t.names[k], "collide (host)") == 0;
    }
    return on_host;
}

/* Steps the growing world with the faults injected; the number of its steps whose
 * collide stage ran on the host. */
static int kg_run_growing(const char* faults, int steps, uint64_t* final_hash)
{
    kg_world* world = kg_make_growing_world(faults ? KG_BACKEND_OPENCL : KG_BACKEND_CPU, faults);
    int on_host = 0;
    for (int s = 0; world && s < steps; ++s) {
        KG_CHECK_OK(kg_world_step(world, KG_DT));
        on_host += kg_collided_on_host(world);
    }
    *final_hash = world ? kg_state_hash(world) : 0u;
    kg_destroy_world(world);
    return on_host;
}

/* A failure of any command in a step whose collide stage ran on the host (after the
 * host's contact lists and one-way platform state have moved on), or around it, leaves
 * the world bitwise where the CPU-only world is: the fallback reads last step's contacts
 * and one-way state back from the device. */
static void test_failures_around_host_collide(void)
{
    enum { STEPS = 90 };
    uint64_t reference = 0, hash = 0;
    kg_run_growing(NULL, STEPS, &reference);
    int on_host = kg_run_growing("", STEPS, &hash);
    KG_CHECK(on_host > 0 && hash == reference);
    static const struct {
        const char* site;
        int first, last, stride;
    } sweeps[] = {{"enqueue", 1, 600, 5}, {"finish", 1, 60, 1}, {"read", 1, 120, 2}};
    int runs = 0, different = 0;
    for (int w = 0; w < (int)(sizeof sweeps / sizeof sweeps[0]); ++w) {
        for (int n = sweeps[w].first; n <= sweeps[w].last; n += sweeps[w].stride) {
            char spec[32];
            snprintf(spec, sizeof spec, "%s:%d", sweeps[w].site, n);
            kg_run_growing(spec, STEPS, &hash);
            different += hash != reference;
            runs += 1;
        }
    }
    printf("     %d steps of %d collided on the host; %d failures injected, %d runs ended off the CPU world's state\n",
           on_host, STEPS, runs, different);
    KG_CHECK(different == 0);
}

/* ---- a lost device ------------------------------------------------------------------ */

/* A lost-device run is compared with the CPU world after the step it fell back in and
 * after this one. */
#define KG_LOST_STEPS 40

/* kg_make_world's in a contact pool of 2 slots: the pairs outgrow it in some steps, whose
 * collide stage then runs on the host. */
static kg_world* kg_make_small_pool_world(kg_backend backend, const char* faults, kg_read_probe* probe)
{
    return kg_make_stack_world(backend, faults, 2, kg_lift_highest, probe);
}

/* A world of the lost-device test: its CPU world's state after each step, and the two
 * steps a loss is tried in, the first whose collide stage ran on the host and the next
 * one (on_host), else the first two in which the contacts grew (a pair a fallback finds
 * only from the bounds swept over the last step's motion). */
typedef struct kg_lost_scene {
    const char* name;
    kg_world* (*make)(kg_backend backend, const char* faults, kg_read_probe* probe);
    int on_host;
    uint64_t reference[KG_LOST_STEPS + 1];
    int steps[2];
} kg_lost_scene;

/* The scene's reference, and its steps from a run on the device without faults. */
static void kg_plan_lost_scene(kg_lost_scene* scene)
{
    kg_world* cpu = scene->make(KG_BACKEND_CPU, NULL, NULL);
    kg_world* world = scene->make(KG_BACKEND_OPENCL, NULL, NULL);
    scene->reference[0] = kg_state_hash(cpu);
    int found = 0, contacts = 0;
    for (int s = 1; s <= KG_LOST_STEPS; ++s) {
        KG_CHECK_OK(kg_world_step(cpu, KG_DT));
        KG_CHECK_OK(kg_world_step(world, KG_DT));
        scene->reference[s] = kg_state_hash(cpu);
        int grew = kg_world_contact_count(world) > contacts;
        contacts = kg_world_contact_count(world);
        int pick = scene->on_host ? kg_collided_on_host(world) || (found == 1 && scene->steps[0] == s - 1) : grew;
        if (found < 2 && pick) {
            scene->steps[found++] = s;
        }
    }
    KG_CHECK(found == 2 && kg_world_backend(world) == KG_BACKEND_OPENCL);
    kg_destroy_world(cpu);
    kg_destroy_world(world);
}

/* What a run with the device lost from the nth enqueue on, through step last, gave: the
 * step it fell back in (KG_LOST_STEPS + 1: none), whether that step's callback had read
 * the contacts and the state back from the device before, and whether the world was then
 * bitwise in the CPU world's state, after that step and after the last. */
typedef struct kg_lost_run {
    int step;
    int read_first;
    int intact;
} kg_lost_run;

static kg_lost_run kg_run_lost(const kg_lost_scene* scene, int n, int last)
{
    char faults[32];
    snprintf(faults, sizeof faults, "lost:%d", n);
    kg_read_probe probe = {0, 0};
    kg_world* world = scene->make(KG_BACKEND_OPENCL, faults, &probe);
    kg_lost_run run = {KG_LOST_STEPS + 1, 0, world != NULL};
    for (int s = 1; world && s <= last; ++s) {
        probe.step = s;
        KG_CHECK_OK(kg_world_step(world, KG_DT));
        if (run.step > s && kg_world_backend(world) == KG_BACKEND_CPU) {
            run.step = s;
            run.read_first = probe.read_on_device == s;
            run.intact = kg_state_hash(world) == scene->reference[s];
        }
    }
    run.intact = run.intact && kg_state_hash(world) == scene->reference[last];
    kg_destroy_world(world);
    return run;
}

/* Whether a loss from the nth enqueue on falls after step s, or in it after the
 * callback's reads (after_reads). */
static int kg_lost_past(const kg_lost_scene* scene, int n, int s, int after_reads)
{
    kg_lost_run run = kg_run_lost(scene, n, s);
    return run.step > s || (after_reads && run.step == s && run.read_first);
}

/* The least n from lo on whose loss falls past (kg_lost_past): the bound doubled until
 * it does, then bisected. */
static int kg_first_lost_past(const kg_lost_scene* scene, int lo, int s, int after_reads)
{
    int width = 64, hi = lo + width;
    while (!kg_lost_past(scene, hi, s, after_reads)) {
        lo = hi + 1;
        width *= 2;
        hi = lo + width;
    }
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (kg_lost_past(scene, mid, s, after_reads)) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    return lo;
}

/* The N after n in a scan up to end: every stride-th, and the last always. */
static int kg_next_lost(int n, int end, int stride)
{
    return n + stride < end || n == end - 1 ? n + stride : end - 1;
}

/* Every command fails from the Nth enqueue on, reads too. The world goes on from the last
 * state and contacts the host read back whole. When the force callback has read both in
 * the step that fails, that is the start of the step and nothing is lost: the world ends
 * bitwise where the CPU world ends, wherever in the rest of the step the device is lost
 * (the uploads, each stage's launches and reads, a collide stage on the host, the final
 * wait). Each N from just after the callback's reads to the step's last command is tried
 * (every 4th under the sanitizers), in the steps each scene picks; where they fall is
 * found by bisection, so that the scan follows any change in the commands a step takes.
 * (Lost before the callback's reads, the step since the last reads is lost, and so are
 * the contacts kept on the device. Tile maps are left out: their one-way state goes on
 * from the host's last read of it, a host collide stage's or a fallback's.) */
static void test_device_lost(void)
{
    static kg_lost_scene scenes[] = {{"the stack", kg_make_world, 0, {0}, {0}},
                                     {"the stack in 2 contact slots", kg_make_small_pool_world, 1, {0}, {0}}};
    int stride = getenv("KGYRO_SANITIZED") ? 4 : 1;
    for (int k = 0; k < (int)(sizeof scenes / sizeof scenes[0]); ++k) {
        kg_lost_scene* scene = &scenes[k];
        kg_plan_lost_scene(scene);
        int lo = 1;
        for (int t = 0; t < 2; ++t) {
            int s = scene->steps[t];
            int first = kg_first_lost_past(scene, lo, s, 1);
            lo = kg_first_lost_past(scene, first, s, 0);
            int tried = 0, intact = 0;
            for (int n = first; n < lo; n = kg_next_lost(n, lo, stride)) {
                kg_lost_run run = kg_run_lost(scene, n, KG_LOST_STEPS);
                KG_CHECK(run.step == s && run.read_first);
                intact += run.intact;
                tried += 1;
            }
            printf("     %s, step %d: lost:%d to lost:%d fall after its callback's reads; %d of %d tried end bitwise "
                   "equal to the CPU world\n", scene->name, s, first, lo - 1, intact, tried);
            KG_CHECK(tried >= 10 && intact == tried);
        }
    }
}

int main(void)
{
    int devices = 0;
    if (kg_opencl_device_count(&devices) != KG_OK || devices == 0) {
        printf("skipped: no OpenCL device (%s)\n", kg_last_error());
        return KG_SKIP;
    }
    kg_reference(g_reference);
    static const kg_test_case tests[] = {
        KG_TEST(test_no_fault_no_fallback), KG_TEST(test_load_failure), KG_TEST(test_no_platform),
        KG_TEST(test_build_failure), KG_TEST(test_alloc_failure), KG_TEST(test_enqueue_failures),
        KG_TEST(test_kernel_failures), KG_TEST(test_read_failures), KG_TEST(test_contact_read_failure),
        KG_TEST(test_device_lost), KG_TEST(test_bad_spec_is_ignored), KG_TEST(test_sleep_state_carried_over),
        KG_TEST(test_callback_forces_fallback_mid_step), KG_TEST(test_failures_around_host_collide)};
    return kg_run_tests(tests, (int)(sizeof tests / sizeof tests[0]));
}
