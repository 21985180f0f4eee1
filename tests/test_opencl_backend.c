/* The OpenCL backend's interface: device queries, backend selection (definition and
 * KGYRO_BACKEND), lazy read-back of the state and the contacts kept on the device, partial
 * transform reads, C callbacks and setters between and inside steps, device force
 * applicators (build errors, parameters, removal), the collide stage on the device (tile
 * maps included), sleeping (callbacks given the awake bodies, a pile woken in a step whose
 * collide stage ran on the host), and per-kernel profiling. Worlds are compared with a CPU
 * twin, bitwise. Skips (exit 77) when no OpenCL device exists. */
#include "kg_test.h"
#include "kg_twin.h"
#include "kgyro/kgyro.h"
#include "kgyro/opencl.h"

#include <stdlib.h>
#include <string.h>

#define KG_SKIP 77
#define KG_DT (1.0f / 60.0f)
#define KG_CONTACT_BYTES 216 /* sizeof(kg_contact), the layout the device keeps contacts in */

static kg_world* kg_make_world(kg_backend backend)
{
    kg_world_def def = kg_default_world_def();
    def.backend = backend;
    def.max_bodies = 128;
    kg_world* world = NULL;
    KG_CHECK_OK(kg_create_world(&def, &world));
    return world;
}

static kg_body kg_add_box(kg_world* world, kg_body_type type, float x, float y)
{
    kg_body_def def = kg_default_body_def();
    def.type = type;
    def.position = (kg_vec2){x, y};
    def.shape = type == KG_BODY_STATIC ? kg_box_shape(30.0f, 1.0f) : kg_box_shape(0.8f, 0.6f);
    kg_body body = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(world, &def, &body));
    return body;
}

/* A ground and a column of boxes; bodies[i] gets the i-th box. */
static void kg_column(kg_world* world, kg_body* bodies, int count)
{
    kg_add_box(world, KG_BODY_STATIC, 0.0f, -0.5f);
    for (int i = 0; i < count; ++i) {
        bodies[i] = kg_add_box(world, KG_BODY_DYNAMIC, 0.2f * (float)(i % 2), 0.4f + 0.7f * (float)i);
    }
}

static int kg_same_state(kg_world* a, kg_world* b, kg_body body)
{
    kg_body_state sa, sb;
    KG_CHECK_OK(kg_body_get_state(a, kg_twin_body(a, body), &sa));
    KG_CHECK_OK(kg_body_get_state(b, kg_twin_body(b, body), &sb));
    return memcmp(&sa, &sb, sizeof sa) == 0;
}

static void test_device_queries(void)
{
    int count = 0;
    KG_CHECK_OK(kg_opencl_device_count(&count));
    KG_CHECK(count > 0);
    kg_opencl_device_info info;
    KG_CHECK_OK(kg_opencl_get_device_info(0, &info));
    KG_CHECK(info.index == 0 && info.name[0] != '\0' && info.compute_units > 0 && info.max_work_group_size > 0);
    KG_CHECK(kg_opencl_get_device_info(count, &info) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_opencl_get_device_info(0, NULL) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_opencl_device_count(NULL) == KG_ERROR_INVALID_ARGUMENT);
}

static kg_backend kg_backend_with_env(const char* env, kg_backend requested)
{
    setenv("KGYRO_BACKEND", env, 1);
    kg_world* world = kg_make_world(requested);
    unsetenv("KGYRO_BACKEND");
    kg_backend b = world ? kg_world_backend(world) : KG_BACKEND_AUTO;
    kg_destroy_world(world);
    return b;
}

/* auto takes a GPU or an accelerator, never a CPU device. */
static kg_backend kg_expected_auto(void)
{
    int count = 0;
    kg_opencl_device_count(&count);
    for (int i = 0; i < count; ++i) {
        kg_opencl_device_info info;
        kg_opencl_get_device_info(i, &info);
        if (info.available && (info.type == KG_OPENCL_DEVICE_GPU || info.type == KG_OPENCL_DEVICE_ACCELERATOR)) {
            return KG_BACKEND_OPENCL;
        }
    }
    return KG_BACKEND_CPU;
}

static void test_selection(void)
{
    KG_CHECK(kg_backend_with_env("", KG_BACKEND_OPENCL) == KG_BACKEND_OPENCL);
    KG_CHECK(kg_backend_with_env("", KG_BACKEND_CPU) == KG_BACKEND_CPU);
    KG_CHECK(kg_backend_with_env("", KG_BACKEND_AUTO) == kg_expected_auto());
    KG_CHECK(kg_backend_with_env("cpu", KG_BACKEND_OPENCL) == KG_BACKEND_CPU);
    KG_CHECK(kg_backend_with_env("opencl", KG_BACKEND_CPU) == KG_BACKEND_OPENCL);
    KG_CHECK(kg_backend_with_env("opencl:0", KG_BACKEND_CPU) == KG_BACKEND_OPENCL);
    KG_CHECK(kg_backend_with_env("auto", KG_BACKEND_OPENCL) == kg_expected_auto());
    /* a device that does not exist: the CPU, with a warning */
    KG_CHECK(kg_backend_with_env("opencl:99", KG_BACKEND_CPU) == KG_BACKEND_CPU);
    /* an unknown value is ignored with a warning: the definition decides */
    KG_CHECK(kg_backend_with_env("quantum", KG_BACKEND_OPENCL) == KG_BACKEND_OPENCL);
}

/* Steps read nothing back the getters have not asked for; the first getter after a step
 * reads the state once, and the next getters read nothing. */
static void test_lazy_read_back(void)
{
    kg_world* world = kg_make_world(KG_BACKEND_OPENCL);
    kg_body body = kg_add_box(world, KG_BODY_DYNAMIC, 0.0f, 5.0f);
    kg_transfer_stats before, after_step, after_get, after_more;
    KG_CHECK_OK(kg_world_step(world, KG_DT));
    KG_CHECK_OK(kg_world_get_transfer_stats(world, &before));
    KG_CHECK_OK(kg_world_step(world, KG_DT));
    KG_CHECK_OK(kg_world_get_transfer_stats(world, &after_step));
    kg_vec2 p;
    KG_CHECK_OK(kg_body_get_position(world, body, &p));
    KG_CHECK_OK(kg_world_get_transfer_stats(world, &after_get));
    kg_body_state s;
    KG_CHECK_OK(kg_body_get_state(world, body, &s));
    KG_CHECK_OK(kg_body_get_velocity(world, body, &p));
    KG_CHECK_OK(kg_world_get_transfer_stats(world, &after_more));
    KG_CHECK(after_get.reads > after_step.reads);
    KG_CHECK(after_more.reads == after_get.reads);
    KG_CHECK(after_more.bytes_to_host == after_get.bytes_to_host);
    KG_CHECK(after_more.writes == after_get.writes);
    kg_destroy_world(world);
}

/* kg_world_get_transforms reads the transforms of the slots asked for, in one read. */
static void test_partial_transform_read(void)
{
    kg_world* world = kg_make_world(KG_BACKEND_OPENCL);
    kg_world* twin = kg_make_world(KG_BACKEND_CPU);
    kg_body bodies[20];
    kg_body twin_bodies[20];
    kg_column(world, bodies, 20);
    kg_column(twin, twin_bodies, 20);
    for (int s = 0; s < 30; ++s) {
        KG_CHECK_OK(kg_world_step(world, KG_DT));
        KG_CHECK_OK(kg_world_step(twin, KG_DT));
    }
    kg_transfer_stats before, after;
    KG_CHECK_OK(kg_world_get_transfer_stats(world, &before));
    kg_body asked[3] = {bodies[4], bodies[6], bodies[5]};
    kg_vec2 positions[3], twin_positions[3];
    float angles[3], twin_angles[3];
    KG_CHECK_OK(kg_world_get_transforms(world, asked, 3, positions, angles));
    KG_CHECK_OK(kg_world_get_transfer_stats(world, &after));
    KG_CHECK(after.reads == before.reads + 1);
    KG_CHECK(after.bytes_to_host - before.bytes_to_host == 3 * 16); /* slots 5..7, 16-byte transforms */
    kg_body twin_asked[3] = {kg_twin_body(twin, asked[0]), kg_twin_body(twin, asked[1]), kg_twin_body(twin, asked[2])};
    KG_CHECK_OK(kg_world_get_transforms(twin, twin_asked, 3, twin_positions, twin_angles));
    KG_CHECK(memcmp(positions, twin_positions, sizeof positions) == 0);
    KG_CHECK(memcmp(angles, twin_angles, sizeof angles) == 0);
    kg_body dead = bodies[0];
    KG_CHECK_OK(kg_destroy_body(world, dead));
    KG_CHECK(kg_world_get_transforms(world, &dead, 1, positions, angles) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK(kg_world_get_transforms(world, asked, 3, NULL, angles) == KG_ERROR_INVALID_ARGUMENT);
    kg_destroy_world(world);
    kg_destroy_world(twin);
}

/* Setters, impulses, body creation and destruction between steps go to the device. */
static void test_changes_between_steps(void)
{
    kg_world* world = kg_make_world(KG_BACKEND_OPENCL);
    kg_world* twin = kg_make_world(KG_BACKEND_CPU);
    kg_world* both[2] = {world, twin};
    kg_body bodies[8];
    for (int w = 0; w < 2; ++w) {
        kg_column(both[w], bodies, 8);
    }
    for (int s = 0; s < 90; ++s) {
        for (int w = 0; w < 2; ++w) {
            kg_world* x = both[w];
            if (s == 20) {
                KG_CHECK_OK(kg_body_set_velocity(x, kg_twin_body(x, bodies[7]), (kg_vec2){2.0f, 3.0f}));
                KG_CHECK_OK(kg_body_apply_impulse(x, kg_twin_body(x, bodies[3]), (kg_vec2){1.0f, 0.0f}, (kg_vec2){0.0f, 2.5f}));
            }
            if (s == 40) {
                KG_CHECK_OK(kg_destroy_body(x, kg_twin_body(x, bodies[2])));
                KG_CHECK_OK(kg_body_set_transform(x, kg_twin_body(x, bodies[6]), (kg_vec2){-3.0f, 6.0f}, 0.7f));
                KG_CHECK_OK(kg_body_apply_force(x, kg_twin_body(x, bodies[5]), (kg_vec2){0.0f, 40.0f}, (kg_vec2){0.1f, 3.0f}));
            }
            if (s == 60) {
                bodies[2] = kg_add_box(x, KG_BODY_DYNAMIC, 4.0f, 3.0f);
                KG_CHECK_OK(kg_body_set_damping(x, kg_twin_body(x, bodies[4]), 0.5f, 0.5f));
            }
            KG_CHECK_OK(kg_world_step(x, KG_DT));
        }
    }
    for (int i = 0; i < 8; ++i) {
        KG_CHECK(kg_same_state(world, twin, bodies[i]));
    }
    KG_CHECK(kg_world_backend(world) == KG_BACKEND_OPENCL);
    kg_destroy_world(world);
    kg_destroy_world(twin);
}

/* A C callback reads the state mid-step (read back from the device) and changes it with
 * setters (uploaded before the next kernel). */
static void kg_kick_callback(kg_world* world, const kg_body* bodies, int count, void* user_data)
{
    int* calls = user_data;
    *calls += 1;
    for (int i = 0; i < count; ++i) {
        kg_vec2 v;
        if (kg_body_get_velocity(world, bodies[i], &v) == KG_OK && v.y < -3.0f) {
            kg_body_set_velocity(world, bodies[i], (kg_vec2){v.x + 0.5f, -v.y});
        }
        kg_body_apply_torque(world, bodies[i], 0.2f);
    }
}

static void test_callbacks_mid_step(void)
{
    kg_world* world = kg_make_world(KG_BACKEND_OPENCL);
    kg_world* twin = kg_make_world(KG_BACKEND_CPU);
    kg_world* both[2] = {world, twin};
    int calls[2] = {0, 0};
    kg_body bodies[6];
    for (int w = 0; w < 2; ++w) {
        kg_column(both[w], bodies, 6);
        kg_applicator a;
        KG_CHECK_OK(kg_add_gravity_applicator(both[w], (kg_vec2){0.0f, -20.0f}, bodies, 3, &a));
        KG_CHECK_OK(kg_add_force_applicator(both[w], kg_kick_callback, bodies + 1, 4, &calls[w], &a));
        KG_CHECK_OK(kg_add_wind_applicator(both[w], (kg_vec2){-1.0f, 0.0f}, 3.0f, 0.2f, NULL, 0, &a));
    }
    for (int s = 0; s < 120; ++s) {
        KG_CHECK_OK(kg_world_step(world, KG_DT));
        KG_CHECK_OK(kg_world_step(twin, KG_DT));
    }
    KG_CHECK(calls[0] == 120 && calls[1] == 120);
    for (int i = 0; i < 6; ++i) {
        KG_CHECK(kg_same_state(world, twin, bodies[i]));
    }
    KG_CHECK(kg_world_backend(world) == KG_BACKEND_OPENCL);
    kg_destroy_world(world);
    kg_destroy_world(twin);
}

KG_DEVICE_FORCE(kg_spring_force, {
    body->force.x -= params[0] * body->position.x + params[1] * body->velocity.x;
    body->force.y -= params[0] * (body->position.y - params[2]) + params[1] * body->velocity.y;
})

static kg_device_force_def kg_spring_def(void)
{
    kg_device_force_def def = kg_default_device_force_def();
    def.source = kg_spring_force_source;
    def.function_name = "kg_spring_force";
    def.cpu_fn = kg_spring_force;
    def.params[0] = 30.0f;
    def.params[1] = 1.0f;
    def.params[2] = 4.0f;
    def.param_count = 3;
    return def;
}

static void test_device_force(void)
{
    kg_world* world = kg_make_world(KG_BACKEND_OPENCL);
    kg_world* twin = kg_make_world(KG_BACKEND_CPU);
    kg_world* both[2] = {world, twin};
    kg_body bodies[4];
    kg_applicator springs[2];
    for (int w = 0; w < 2; ++w) {
        kg_column(both[w], bodies, 4);
        kg_device_force_def def = kg_spring_def();
        kg_body listed[3] = {bodies[3], bodies[1], bodies[3]};
        def.bodies = listed;
        def.body_count = 3;
        KG_CHECK_OK(kg_add_device_force_applicator(both[w], &def, &springs[w]));
    }
    for (int s = 0; s < 120; ++s) {
        for (int w = 0; w < 2; ++w) {
            if (s == 50) {
                float stiffer[3] = {60.0f, 2.0f, 6.0f};
                KG_CHECK_OK(kg_set_device_force_params(both[w], springs[w], stiffer, 3));
            }
            if (s == 90) {
                KG_CHECK_OK(kg_remove_applicator(both[w], springs[w]));
            }
            KG_CHECK_OK(kg_world_step(both[w], KG_DT));
        }
    }
    for (int i = 0; i < 4; ++i) {
        KG_CHECK(kg_same_state(world, twin, bodies[i]));
    }
    float p = 1.0f;
    KG_CHECK(kg_set_device_force_params(world, springs[0], &p, 1) == KG_ERROR_INVALID_HANDLE);
    kg_destroy_world(world);
    kg_destroy_world(twin);
}

static void test_device_force_errors(void)
{
    kg_world* world = kg_make_world(KG_BACKEND_OPENCL);
    kg_device_force_def def = kg_spring_def();
    kg_applicator a;
    def.source = "void kg_spring_force(kg_force_body* body, const float* params) { body->force.x += undefined_name; }";
    KG_CHECK(kg_add_device_force_applicator(world, &def, &a) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(strstr(kg_last_error(), "undefined_name") != NULL);
    KG_CHECK(kg_world_backend(world) == KG_BACKEND_OPENCL);
    def = kg_spring_def();
    def.function_name = "not an identifier";
    KG_CHECK(kg_add_device_force_applicator(world, &def, &a) == KG_ERROR_INVALID_ARGUMENT);
    def = kg_spring_def();
    def.cpu_fn = NULL;
    KG_CHECK(kg_add_device_force_applicator(world, &def, &a) == KG_ERROR_INVALID_ARGUMENT);
    def = kg_spring_def();
    def.param_count = KG_DEVICE_FORCE_MAX_PARAMS + 1;
    KG_CHECK(kg_add_device_force_applicator(world, &def, &a) == KG_ERROR_INVALID_ARGUMENT);
    /* the failed registrations left no applicator behind: a step runs clean */
    kg_add_box(world, KG_BODY_DYNAMIC, 0.0f, 1.0f);
    KG_CHECK_OK(kg_world_step(world, KG_DT));
    def = kg_spring_def();
    KG_CHECK_OK(kg_add_device_force_applicator(world, &def, &a));
    KG_CHECK(kg_set_device_force_params(world, a, def.params, -1) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK_OK(kg_world_step(world, KG_DT));
    kg_destroy_world(world);
}

/* Kinematic bodies, particles, a frozen rotation, tiny contact pools (which both backends
 * grow mid-step) and several CPU threads on the twin: the state stays bitwise equal. */
static void kg_mixed_scene(kg_world* world)
{
    kg_add_box(world, KG_BODY_STATIC, 0.0f, -0.5f);
    kg_body_def def = kg_default_body_def();
    def.type = KG_BODY_KINEMATIC;
    def.position = (kg_vec2){0.0f, 1.5f};
    def.angular_velocity = 1.5f;
    def.velocity = (kg_vec2){0.3f, 0.0f};
    def.shape = kg_box_shape(4.0f, 0.2f);
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &def, &body));
    for (int i = 0; i < 40; ++i) {
        def = kg_default_body_def();
        def.type = i % 4 == 0 ? KG_BODY_PARTICLE : KG_BODY_DYNAMIC;
        def.position = (kg_vec2){-2.0f + 0.1f * (float)i, 3.0f + 0.3f * (float)i};
        def.shape = i % 4 == 0 ? kg_circle_shape(0.1f) : kg_box_shape(0.3f, 0.2f);
        def.fixed_rotation = i % 5 == 0;
        def.restitution = i % 3 == 0 ? 0.5f : 0.0f;
        def.friction = 0.1f * (float)(i % 7);
        KG_CHECK_OK(kg_create_body(world, &def, &body));
    }
}

static void test_mixed_bodies_and_pool_growth(void)
{
    kg_world* both[2] = {NULL, NULL};
    for (int w = 0; w < 2; ++w) {
        kg_world_def def = kg_default_world_def();
        def.backend = w == 0 ? KG_BACKEND_OPENCL : KG_BACKEND_CPU;
        def.max_bodies = 64;
        def.max_contacts = 4;
        def.threads = w == 0 ? 1 : 2;
        KG_CHECK_OK(kg_create_world(&def, &both[w]));
        kg_mixed_scene(both[w]);
    }
    for (int s = 0; s < 150; ++s) {
        KG_CHECK_OK(kg_world_step(both[0], KG_DT));
        KG_CHECK_OK(kg_world_step(both[1], KG_DT));
        KG_CHECK(kg_world_contact_count(both[0]) == kg_world_contact_count(both[1]));
    }
    kg_body bodies[64];
    int count = 0;
    kg_world_get_bodies(both[1], bodies, 64, &count);
    for (int i = 0; i < count; ++i) {
        KG_CHECK(kg_same_state(both[0], both[1], bodies[i]));
    }
    int n = kg_world_contact_count(both[0]);
    KG_CHECK(n > 4);
    for (int k = 0; k < n; ++k) {
        kg_contact_info a, b;
        KG_CHECK_OK(kg_world_get_contact(both[0], k, &a));
        KG_CHECK_OK(kg_world_get_contact(both[1], k, &b));
        kg_untag_contact(&a);
        kg_untag_contact(&b);
        KG_CHECK(memcmp(&a, &b, sizeof a) == 0);
    }
    KG_CHECK(kg_world_backend(both[0]) == KG_BACKEND_OPENCL);
    kg_destroy_world(both[0]);
    kg_destroy_world(both[1]);
}

static int kg_has_stage(const kg_stage_times* t, const char* name)
{
    for (int i = 0; i < t->count; ++i) {
        if (strcmp(t->names[i], name) == 0 && t->ms[i] >= 0.0) {
            return 1;
        }
    }
    return 0;
}

/* The contacts of both worlds, every field, impulses included. */
static int kg_same_contacts(kg_world* a, kg_world* b)
{
    int n = kg_world_contact_count(a), same = n == kg_world_contact_count(b);
    for (int k = 0; same && k < n; ++k) {
        kg_contact_info ca, cb;
        KG_CHECK_OK(kg_world_get_contact(a, k, &ca));
        KG_CHECK_OK(kg_world_get_contact(b, k, &cb));
        kg_untag_contact(&ca);
        kg_untag_contact(&cb);
        same = memcmp(&ca, &cb, sizeof ca) == 0;
    }
    return same;
}

/* A ground and rows of boxes: a pile with a few hundred contacts. */
static void kg_pile(kg_world* world, int count)
{
    kg_add_box(world, KG_BODY_STATIC, 0.0f, -0.5f);
    for (int i = 0; i < count; ++i) {
        kg_add_box(world, KG_BODY_DYNAMIC, -4.5f + 0.9f * (float)(i % 10) + 0.05f * (float)(i / 10 % 2),
                   0.35f + 0.65f * (float)(i / 10));
    }
}

static void kg_count_targets(kg_world* world, const kg_body* bodies, int count, void* user_data)
{
    (void)world;
    (void)bodies;
    *(int*)user_data = count;
}

/* A C callback is given the awake bodies only, as the device flags them: it reads no state
 * itself, so nothing but the backend brings the flags to the host. */
static void test_callback_leaves_out_sleepers(void)
{
    kg_world* both[2] = {kg_make_world(KG_BACKEND_OPENCL), kg_make_world(KG_BACKEND_CPU)};
    int targets[2] = {-1, -1}, mismatch = 0;
    for (int w = 0; w < 2; ++w) {
        kg_pile(both[w], 30);
        kg_applicator a;
        KG_CHECK_OK(kg_add_force_applicator(both[w], kg_count_targets, NULL, 0, &targets[w], &a));
    }
    for (int s = 0; s < 80; ++s) {
        KG_CHECK_OK(kg_world_step(both[0], KG_DT));
        KG_CHECK_OK(kg_world_step(both[1], KG_DT));
        mismatch += targets[0] != targets[1];
    }
    KG_CHECK(mismatch == 0);
    KG_CHECK(targets[1] < 31); /* of the ground and 30 boxes, the sleepers left out */
    KG_CHECK(kg_world_backend(both[0]) == KG_BACKEND_OPENCL);
    kg_destroy_world(both[0]);
    kg_destroy_world(both[1]);
}

/* A step moves no contact across the bus: it reads back a few counters, whatever the
 * contact count. The contacts cross once, when asked for, and equal the CPU's. */
static void test_contacts_stay_on_device(void)
{
    kg_world* world = kg_make_world(KG_BACKEND_OPENCL);
    kg_world* twin = kg_make_world(KG_BACKEND_CPU);
    kg_pile(world, 100);
    kg_pile(twin, 100);
    for (int s = 0; s < 60; ++s) {
        KG_CHECK_OK(kg_world_step(world, KG_DT));
        KG_CHECK_OK(kg_world_step(twin, KG_DT));
    }
    kg_transfer_stats before, after_step, after_count, after_get;
    KG_CHECK_OK(kg_world_get_transfer_stats(world, &before));
    KG_CHECK_OK(kg_world_step(world, KG_DT));
    KG_CHECK_OK(kg_world_step(twin, KG_DT));
    KG_CHECK_OK(kg_world_get_transfer_stats(world, &after_step));
    int n = kg_world_contact_count(world);
    KG_CHECK_OK(kg_world_get_transfer_stats(world, &after_count));
    kg_contact_info info;
    KG_CHECK_OK(kg_world_get_contact(world, n - 1, &info));
    KG_CHECK_OK(kg_world_get_transfer_stats(world, &after_get));
    printf("     %d contacts; a step read %llu bytes back and wrote %llu; the contacts read %llu\n", n,
           (unsigned long long)(after_step.bytes_to_host - before.bytes_to_host),
           (unsigned long long)(after_step.bytes_to_device - before.bytes_to_device),
           (unsigned long long)(after_count.bytes_to_host - after_step.bytes_to_host));
    KG_CHECK(n >= 100);
    KG_CHECK(after_step.bytes_to_host - before.bytes_to_host <= 256);
    KG_CHECK(after_step.bytes_to_device - before.bytes_to_device <= 256);
    KG_CHECK(after_count.bytes_to_host - after_step.bytes_to_host == (uint64_t)n * KG_CONTACT_BYTES);
    KG_CHECK(after_get.reads == after_count.reads);
    KG_CHECK(kg_same_contacts(world, twin));
    kg_destroy_world(world);
    kg_destroy_world(twin);
}

/* Tile contacts are built on the device too: a world that gets a tile map in mid-run
 * (and has a tile changed later) goes on with the collide stage on the device, bitwise. */
static void test_tile_map_collides_on_device(void)
{
    kg_world* both[2] = {kg_make_world(KG_BACKEND_OPENCL), kg_make_world(KG_BACKEND_CPU)};
    kg_tile_shape shapes[2] = {kg_tile_empty(), kg_tile_box()};
    uint16_t tiles[8] = {1, 1, 0, 0, 0, 0, 1, 1};
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = 8;
    def.height = 1;
    def.origin = (kg_vec2){-4.0f, 0.5f};
    def.shapes = shapes;
    def.shape_count = 2;
    def.tiles = tiles;
    for (int w = 0; w < 2; ++w) {
        kg_pile(both[w], 40);
    }
    for (int s = 0; s < 90; ++s) {
        for (int w = 0; w < 2; ++w) {
            kg_tilemap map;
            if (s == 30) {
                KG_CHECK_OK(kg_create_tilemap(both[w], &def, &map));
            }
            if (s == 60) {
                KG_CHECK_OK(kg_world_get_tilemaps(both[w], &map, 1, &(int){0}));
                KG_CHECK_OK(kg_tilemap_set_tile(both[w], map, 0, 2, 0, 1));
                KG_CHECK_OK(kg_tilemap_set_tile(both[w], map, 0, 0, 0, 0));
            }
            KG_CHECK_OK(kg_world_step(both[w], KG_DT));
        }
        KG_CHECK(kg_same_contacts(both[0], both[1]));
    }
    kg_body bodies[64];
    int count = 0;
    kg_world_get_bodies(both[1], bodies, 64, &count);
    for (int i = 0; i < count; ++i) {
        KG_CHECK(kg_same_state(both[0], both[1], bodies[i]));
    }
    kg_stage_times t;
    KG_CHECK_OK(kg_world_get_stage_times(both[0], &t));
    KG_CHECK(kg_has_stage(&t, "collide") && !kg_has_stage(&t, "collide (host)"));
    KG_CHECK(kg_world_backend(both[0]) == KG_BACKEND_OPENCL);
    kg_destroy_world(both[0]);
    kg_destroy_world(both[1]);
}

/* A pile asleep, and in one step as many boxes laid on it as it takes for the pairs to
 * outgrow the contact pool: that step's collide stage runs on the host, which wakes the
 * pile before it colours the contacts, as the device would. */
static void test_wake_in_collide_on_host(void)
{
    kg_world* both[2] = {NULL, NULL};
    for (int w = 0; w < 2; ++w) {
        kg_world_def def = kg_default_world_def();
        def.backend = w == 0 ? KG_BACKEND_OPENCL : KG_BACKEND_CPU;
        def.max_bodies = 128;
        def.max_contacts = 16;
        KG_CHECK_OK(kg_create_world(&def, &both[w]));
        kg_pile(both[w], 30);
    }
    int s = 0;
    while (s < 200 && kg_world_asleep_count(both[1]) < 30) {
        KG_CHECK_OK(kg_world_step(both[0], KG_DT));
        KG_CHECK_OK(kg_world_step(both[1], KG_DT));
        s++;
    }
    KG_CHECK(kg_world_asleep_count(both[0]) == 30 && kg_world_asleep_count(both[1]) == 30);
    /* each box makes a pair at least (with its neighbour, the last with the pile), on top
     * of the pile's own pairs, at least its contacts */
    int room = kg_world_get_def(both[0])->max_contacts - kg_world_contact_count(both[0]);
    int boxes = room + 1;
    float width = 8.0f / (float)boxes;
    printf("     pile asleep after %d steps; %d boxes laid on it to outgrow %d contacts\n", s, boxes,
           kg_world_get_def(both[0])->max_contacts);
    for (int w = 0; w < 2; ++w) {
        for (int k = 0; k < boxes; ++k) { /* on top of three rows of 0.6 m boxes */
            kg_body_def def = kg_default_body_def();
            def.position = (kg_vec2){-4.0f + width * ((float)k + 0.5f), 1.801f + 0.5f * width};
            def.shape = kg_box_shape(0.99f * width, width);
            kg_body body;
            KG_CHECK_OK(kg_create_body(both[w], &def, &body));
        }
    }
    KG_CHECK_OK(kg_world_step(both[0], KG_DT));
    KG_CHECK_OK(kg_world_step(both[1], KG_DT));
    kg_stage_times t;
    KG_CHECK_OK(kg_world_get_stage_times(both[0], &t));
    KG_CHECK(kg_has_stage(&t, "collide (host)"));
    int asleep = kg_world_asleep_count(both[0]);
    printf("     after that step: %d asleep (CPU %d)\n", asleep, kg_world_asleep_count(both[1]));
    KG_CHECK(asleep < 30 && asleep == kg_world_asleep_count(both[1]));
    for (int k = 0; k < 60; ++k) {
        KG_CHECK_OK(kg_world_step(both[0], KG_DT));
        KG_CHECK_OK(kg_world_step(both[1], KG_DT));
        KG_CHECK(kg_world_asleep_count(both[0]) == kg_world_asleep_count(both[1]));
    }
    kg_body bodies[128];
    int count = 0;
    kg_world_get_bodies(both[1], bodies, 128, &count);
    for (int i = 0; i < count; ++i) {
        KG_CHECK(kg_same_state(both[0], both[1], bodies[i]));
    }
    KG_CHECK(kg_same_contacts(both[0], both[1]));
    KG_CHECK(kg_world_backend(both[0]) == KG_BACKEND_OPENCL);
    kg_destroy_world(both[0]);
    kg_destroy_world(both[1]);
}

/* With profiling on, the stage times are the kernels' device times, the collide stage's
 * by stage (kg_broadphase, kg_narrowphase, kg_color); no stage runs on the host. */
static void test_profiling(void)
{
    kg_world* world = kg_make_world(KG_BACKEND_OPENCL);
    kg_body bodies[5];
    kg_column(world, bodies, 5);
    kg_stage_times t;
    KG_CHECK_OK(kg_world_step(world, KG_DT));
    KG_CHECK_OK(kg_world_get_stage_times(world, &t));
    KG_CHECK(kg_has_stage(&t, "forces") && kg_has_stage(&t, "collide") && kg_has_stage(&t, "solve") &&
             kg_has_stage(&t, "finalize"));
    KG_CHECK_OK(kg_world_set_profiling(world, 1));
    for (int s = 0; s < 60; ++s) { /* until the boxes touch: the solver's kernels run */
        KG_CHECK_OK(kg_world_step(world, KG_DT));
    }
    KG_CHECK_OK(kg_world_get_stage_times(world, &t));
    KG_CHECK(kg_has_stage(&t, "kg_broadphase") && kg_has_stage(&t, "kg_narrowphase") && kg_has_stage(&t, "kg_color"));
    KG_CHECK(kg_has_stage(&t, "kg_integrate_velocities") && kg_has_stage(&t, "kg_solve_colors_in_group") &&
             kg_has_stage(&t, "kg_finalize"));
    KG_CHECK(!kg_has_stage(&t, "collide (host)") && !kg_has_stage(&t, "collide") && !kg_has_stage(&t, "solve"));
    KG_CHECK(!kg_has_stage(&t, "other"));
    KG_CHECK(kg_world_set_profiling(NULL, 1) == KG_ERROR_INVALID_ARGUMENT);
    kg_destroy_world(world);
}

int main(void)
{
    int devices = 0;
    if (kg_opencl_device_count(&devices) != KG_OK || devices == 0) {
        printf("skipped: no OpenCL device (%s)\n", kg_last_error());
        return KG_SKIP;
    }
    unsetenv("KGYRO_BACKEND");
    unsetenv("KGYRO_PROFILE");
    static const kg_test_case tests[] = {
        KG_TEST(test_device_queries), KG_TEST(test_selection), KG_TEST(test_lazy_read_back),
        KG_TEST(test_partial_transform_read), KG_TEST(test_changes_between_steps), KG_TEST(test_callbacks_mid_step),
        KG_TEST(test_callback_leaves_out_sleepers), KG_TEST(test_device_force), KG_TEST(test_device_force_errors),
        KG_TEST(test_mixed_bodies_and_pool_growth), KG_TEST(test_contacts_stay_on_device),
        KG_TEST(test_tile_map_collides_on_device), KG_TEST(test_wake_in_collide_on_host), KG_TEST(test_profiling)};
    return kg_run_tests(tests, (int)(sizeof tests / sizeof tests[0]));
}
