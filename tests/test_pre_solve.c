/* The pre-solve callback (a one-way platform made of a body, on both backends) and the
 * step's lock: what a callback inside kg_world_step may not do fails with
 * KG_ERROR_LOCKED and changes nothing. */
#include "kg_test.h"
#include "kgyro/kgyro.h"
#include "kg_test_world.h"

#include <math.h>
#include <string.h>

#define DT (1.0f / 60.0f)

typedef struct one_way {
    kg_world* world;
    kg_body platform;
    int calls;
    int refused;
    kg_result tried[6]; /* what changing the world from inside the callback returned */
} one_way;

/* The platform lets a body through unless the body is above its top surface: Box2D's
 * one-way platform, decided from the contact's normal (platform to body, up when the body
 * comes from above) and the body's position. */
static int let_through_from_below(const kg_contact_info* c, void* context)
{
    one_way* ow = context;
    ow->calls += 1;
    kg_body other = c->a.index == ow->platform.index ? c->b : c->a;
    float sign = c->a.index == ow->platform.index ? 1.0f : -1.0f;
    kg_vec2 p;
    kg_body_get_position(ow->world, other, &p);
    if (ow->calls == 1) {
        ow->tried[0] = kg_body_set_velocity(ow->world, other, (kg_vec2){0.0f, 0.0f});
        ow->tried[1] = kg_destroy_body(ow->world, other);
        ow->tried[2] = kg_world_step(ow->world, DT);
        /* a shape's material or filter: it would wake the body after the colours were
         * found (solve/solver.c, kg_color_step) */
        kg_shape_id shape = c->a.index == ow->platform.index ? c->shape_b : c->shape_a;
        ow->tried[3] = kg_shape_set_friction(ow->world, shape, 0.1f);
        ow->tried[4] = kg_shape_set_restitution(ow->world, shape, 0.5f);
        ow->tried[5] = kg_shape_set_filter(ow->world, shape, 1u, 0xFFFFFFFFu);
    }
    int from_above = sign * c->normal.y > 0.5f && p.y > 2.0f + 0.25f - 0.05f;
    ow->refused += !from_above;
    return from_above;
}

/* A ball shot up through a static platform (top at y = 2) comes down on it and rests. */
static void run_one_way(kg_backend backend, kg_vec2* rest, one_way* ow)
{
    kg_world_def def = kg_default_world_def();
    def.backend = backend;
    def.device_index = kg_test_opencl_device();
    def.enable_sleep = 0;
    memset(ow, 0, sizeof *ow);
    KG_CHECK_OK(kg_create_world(&def, &ow->world));
    kg_body_def bd = kg_default_body_def();
    bd.type = KG_BODY_STATIC;
    bd.position = (kg_vec2){0.0f, 1.75f};
    bd.shape = kg_box_shape(4.0f, 0.5f);
    bd.enable_pre_solve = 1;
    KG_CHECK_OK(kg_create_body(ow->world, &bd, &ow->platform));
    bd = kg_default_body_def();
    bd.position = (kg_vec2){0.0f, 0.0f};
    bd.shape = kg_circle_shape(0.25f);
    kg_body ball;
    KG_CHECK_OK(kg_create_body(ow->world, &bd, &ball));
    KG_CHECK_OK(kg_body_set_velocity(ow->world, ball, (kg_vec2){0.0f, 9.0f})); /* rises 4 m */
    KG_CHECK_OK(kg_world_set_pre_solve(ow->world, let_through_from_below, ow));
    for (int step = 0; step < 180; ++step) {
        KG_CHECK_OK(kg_world_step(ow->world, DT));
    }
    KG_CHECK_OK(kg_body_get_position(ow->world, ball, rest));
    kg_destroy_world(ow->world);
}

static void test_one_way_platform_from_a_body(void)
{
    one_way ow;
    kg_vec2 rest;
    run_one_way(KG_BACKEND_CPU, &rest, &ow);
    measured("the ball rests at y = %.4f (on the platform: 2.25), %d calls, %d refused", (double)rest.y, ow.calls,
             ow.refused);
    KG_CHECK_NEAR(rest.y, 2.25f, 0.01f);
    KG_CHECK(ow.refused > 0 && ow.calls > ow.refused);
    for (int i = 0; i < 6; ++i) {
        KG_CHECK(ow.tried[i] == KG_ERROR_LOCKED);
    }
}

/* Without the callback the platform stops the ball from below: it never gets higher than
 * the platform's underside (y = 1.5) less its radius. */
static void test_without_callback_the_platform_is_solid(void)
{
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    kg_body_def bd = kg_default_body_def();
    bd.type = KG_BODY_STATIC;
    bd.position = (kg_vec2){0.0f, 1.75f};
    bd.shape = kg_box_shape(4.0f, 0.5f);
    bd.enable_pre_solve = 1;
    kg_body platform, ball;
    KG_CHECK_OK(kg_create_body(w, &bd, &platform));
    bd = kg_default_body_def();
    bd.shape = kg_circle_shape(0.25f);
    KG_CHECK_OK(kg_create_body(w, &bd, &ball));
    KG_CHECK_OK(kg_body_set_velocity(w, ball, (kg_vec2){0.0f, 9.0f}));
    float highest = 0.0f;
    for (int step = 0; step < 60; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_vec2 p;
        KG_CHECK_OK(kg_body_get_position(w, ball, &p));
        highest = p.y > highest ? p.y : highest;
    }
    KG_CHECK(highest > 1.2f && highest < 1.26f);
    kg_destroy_world(w);
}

static void test_one_way_platform_same_on_opencl(void)
{
    int bitwise = 0;
    if (!kg_test_opencl_ready(&bitwise)) {
        return;
    }
    one_way cpu, cl;
    kg_vec2 cpu_rest, cl_rest;
    run_one_way(KG_BACKEND_CPU, &cpu_rest, &cpu);
    run_one_way(KG_BACKEND_OPENCL, &cl_rest, &cl);
    measured("cpu: %d calls, %d refused, rests at %.6f; opencl: %d, %d, %.6f", cpu.calls, cpu.refused,
             (double)cpu_rest.y, cl.calls, cl.refused, (double)cl_rest.y);
    KG_CHECK(cpu.calls == cl.calls && cpu.refused == cl.refused);
    if (bitwise) {
        KG_CHECK(memcmp(&cpu_rest, &cl_rest, sizeof cpu_rest) == 0);
    } else {
        KG_CHECK_NEAR(cl_rest.y, cpu_rest.y, 1e-4f);
    }
}

/* A force applicator may push bodies, not make or destroy them. */
typedef struct applicator_probe {
    kg_result created, destroyed, pushed;
    kg_body body;
} applicator_probe;

static void probe_forces(kg_world* world, const kg_body* bodies, int count, void* user_data)
{
    applicator_probe* probe = user_data;
    (void)bodies;
    (void)count;
    kg_body_def bd = kg_default_body_def();
    bd.shape = kg_circle_shape(0.1f);
    kg_body made;
    probe->created = kg_create_body(world, &bd, &made);
    probe->destroyed = kg_destroy_body(world, probe->body);
    probe->pushed = kg_body_apply_force_to_center(world, probe->body, (kg_vec2){0.0f, 10.0f});
}

static void test_applicators_may_push_not_create(void)
{
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    applicator_probe probe;
    memset(&probe, 0, sizeof probe);
    kg_body_def bd = kg_default_body_def();
    bd.shape = kg_box_shape(1.0f, 1.0f); /* mass 1: the applicator's 10 N cancel gravity */
    KG_CHECK_OK(kg_create_body(w, &bd, &probe.body));
    kg_applicator a;
    KG_CHECK_OK(kg_add_force_applicator(w, probe_forces, NULL, 0, &probe, &a));
    KG_CHECK_OK(kg_world_step(w, DT));
    KG_CHECK(probe.created == KG_ERROR_LOCKED && probe.destroyed == KG_ERROR_LOCKED && probe.pushed == KG_OK);
    KG_CHECK(kg_world_body_count(w) == 1 && kg_body_is_valid(w, probe.body));
    kg_vec2 v;
    KG_CHECK_OK(kg_body_get_velocity(w, probe.body, &v));
    KG_CHECK(fabsf(v.y) < 1e-6f);
    KG_CHECK(strstr(kg_result_string(KG_ERROR_LOCKED), "locked") != NULL);
    kg_destroy_world(w);
}

KG_TEST_MAIN(KG_TEST(test_one_way_platform_from_a_body), KG_TEST(test_without_callback_the_platform_is_solid),
             KG_TEST(test_one_way_platform_same_on_opencl), KG_TEST(test_applicators_may_push_not_create))
