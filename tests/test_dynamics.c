/* Integration and forces, checked against closed-form answers of the chosen integrator:
 * semi-implicit Euler on sub-steps h = dt / n, v += h a, then x += h v. */
#include "kg_test.h"
#include "kgyro/kgyro.h"

#include <string.h>

static kg_world* make_world(kg_vec2 gravity, int substeps)
{
    kg_world_def def = kg_default_world_def();
    def.gravity = gravity;
    def.substeps = substeps;
    def.backend = KG_BACKEND_CPU;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    return w;
}

static kg_body add_body(kg_world* w, kg_body_type type, kg_shape_def shape, kg_vec2 pos, kg_vec2 vel)
{
    kg_body_def bd = kg_default_body_def();
    bd.type = type;
    bd.shape = shape;
    bd.position = pos;
    bd.velocity = vel;
    kg_body b = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    return b;
}

static void test_projectile_matches_discrete_trajectory(void)
{
    const int substeps = 4, steps = 120;
    const double g = -9.81, dt = 1.0 / 60.0, h = dt / substeps;
    kg_world* w = make_world((kg_vec2){0.0f, (float)g}, substeps);
    kg_body b = add_body(w, KG_BODY_DYNAMIC, kg_circle_shape(0.1f), (kg_vec2){0, 0}, (kg_vec2){3, 12});
    for (int s = 0; s < steps; ++s) {
        KG_CHECK_OK(kg_world_step(w, (float)dt));
    }
    double k = (double)steps * substeps;
    double x = 3.0 * k * h;
    double y = 12.0 * k * h + g * h * h * k * (k + 1) / 2.0; /* sum of v_j h for v_j = v0 + j h g */
    double vy = 12.0 + g * k * h;
    kg_body_state s;
    KG_CHECK_OK(kg_body_get_state(w, b, &s));
    KG_CHECK_NEAR(s.position.x, x, 1e-4);
    KG_CHECK_NEAR(s.position.y, y, 1e-4);
    KG_CHECK_NEAR(s.velocity.y, vy, 1e-4);
    KG_CHECK_NEAR(s.velocity.x, 3.0, 1e-6);
    /* The scheme's known bias against the continuous parabola: g h t / 2. */
    double t = steps * dt;
    KG_CHECK_NEAR(s.position.y - (12.0 * t + 0.5 * g * t * t), g * h * t / 2.0, 1e-4);
    kg_destroy_world(w);
}

static void test_force_at_point_gives_expected_torque(void)
{
    kg_world* w = make_world((kg_vec2){0, 0}, 1);
    kg_body b = add_body(w, KG_BODY_DYNAMIC, kg_box_shape(2.0f, 1.0f), (kg_vec2){5, 5}, (kg_vec2){0, 0});
    kg_mass_data md;
    KG_CHECK_OK(kg_body_get_mass_data(w, b, &md));
    /* 10 N upwards at 1 m right of the centre: torque 10 N m */
    KG_CHECK_OK(kg_body_apply_force(w, b, (kg_vec2){0, 10}, (kg_vec2){6, 5}));
    const float dt = 0.01f;
    KG_CHECK_OK(kg_world_step(w, dt));
    kg_body_state s;
    KG_CHECK_OK(kg_body_get_state(w, b, &s));
    double alpha = 10.0 / md.inertia;
    KG_CHECK_NEAR(s.angular_velocity, alpha * dt, 1e-5 * alpha * dt);
    KG_CHECK_NEAR(s.velocity.y, 10.0 / md.mass * dt, 1e-6);
    KG_CHECK_NEAR(s.angle, alpha * dt * dt, 1e-6);
    /* forces last one step: the next step adds nothing */
    KG_CHECK_OK(kg_world_step(w, dt));
    KG_CHECK_OK(kg_body_get_state(w, b, &s));
    KG_CHECK_NEAR(s.angular_velocity, alpha * dt, 1e-5 * alpha * dt);
    /* a pure torque and an angular impulse */
    KG_CHECK_OK(kg_body_apply_angular_impulse(w, b, -(float)(alpha * dt * md.inertia)));
    KG_CHECK_OK(kg_body_get_state(w, b, &s));
    KG_CHECK_NEAR(s.angular_velocity, 0.0, 1e-5);
    KG_CHECK_OK(kg_body_apply_torque(w, b, 3.0f));
    KG_CHECK_OK(kg_world_step(w, dt));
    KG_CHECK_OK(kg_body_get_state(w, b, &s));
    KG_CHECK_NEAR(s.angular_velocity, 3.0 / md.inertia * dt, 1e-5);
    kg_destroy_world(w);
}

static void test_impulse_at_point(void)
{
    kg_world* w = make_world((kg_vec2){0, 0}, 1);
    kg_body b = add_body(w, KG_BODY_DYNAMIC, kg_circle_shape(0.5f), (kg_vec2){0, 0}, (kg_vec2){0, 0});
    kg_mass_data md;
    KG_CHECK_OK(kg_body_get_mass_data(w, b, &md));
    KG_CHECK_OK(kg_body_apply_impulse(w, b, (kg_vec2){2, 0}, (kg_vec2){0, 0.5f}));
    kg_body_state s;
    KG_CHECK_OK(kg_body_get_state(w, b, &s));
    KG_CHECK_NEAR(s.velocity.x, 2.0 / md.mass, 1e-6);
    KG_CHECK_NEAR(s.angular_velocity, -1.0 / md.inertia, 1e-5); /* r x J = (0, .5) x (2, 0) = -1 */
    kg_destroy_world(w);
}

static void test_damping_is_implicit(void)
{
    const int substeps = 4, steps = 90;
    const float dt = 1.0f / 60.0f, c_lin = 0.8f, c_ang = 2.0f;
    kg_world* w = make_world((kg_vec2){0, 0}, substeps);
    kg_body b = add_body(w, KG_BODY_DYNAMIC, kg_box_shape(1, 1), (kg_vec2){0, 0}, (kg_vec2){10, -4});
    KG_CHECK_OK(kg_body_set_angular_velocity(w, b, 3.0f));
    KG_CHECK_OK(kg_body_set_damping(w, b, c_lin, c_ang));
    for (int s = 0; s < steps; ++s) {
        KG_CHECK_OK(kg_world_step(w, dt));
    }
    double h = (double)dt / substeps, k = (double)steps * substeps;
    double f_lin = pow(1.0 / (1.0 + h * c_lin), k), f_ang = pow(1.0 / (1.0 + h * c_ang), k);
    kg_body_state s;
    KG_CHECK_OK(kg_body_get_state(w, b, &s));
    KG_CHECK_NEAR(s.velocity.x, 10.0 * f_lin, 1e-4);
    KG_CHECK_NEAR(s.velocity.y, -4.0 * f_lin, 1e-4);
    KG_CHECK_NEAR(s.angular_velocity, 3.0 * f_ang, 1e-4);
    /* and it tends to exp(-c t) as h -> 0 */
    KG_CHECK_NEAR(f_lin, exp(-c_lin * steps * dt), 2e-3);
    kg_destroy_world(w);
}

static void test_particles_never_rotate(void)
{
    kg_world* w = make_world((kg_vec2){0, -10}, 4);
    kg_body_def bd = kg_default_body_def();
    bd.type = KG_BODY_PARTICLE;
    bd.shape.type = KG_SHAPE_NONE;
    bd.mass = 0.5f;
    bd.angle = 1.0f;
    bd.angular_velocity = 5.0f;
    kg_body p;
    KG_CHECK_OK(kg_create_body(w, &bd, &p));
    kg_body c = add_body(w, KG_BODY_PARTICLE, kg_circle_shape(0.05f), (kg_vec2){100, 0}, (kg_vec2){0, 0});
    for (int s = 0; s < 60; ++s) {
        KG_CHECK_OK(kg_body_apply_force(w, p, (kg_vec2){1, 0}, (kg_vec2){0.3f, 0.7f}));
        KG_CHECK_OK(kg_body_apply_torque(w, c, 5.0f));
        KG_CHECK_OK(kg_body_set_angular_velocity(w, c, 2.0f));
        KG_CHECK_OK(kg_world_step(w, 1.0f / 60.0f));
    }
    kg_body_state s;
    KG_CHECK_OK(kg_body_get_state(w, p, &s));
    KG_CHECK(s.angle == 0.0f && s.angular_velocity == 0.0f);
    KG_CHECK_NEAR(s.velocity.x, 2.0, 1e-4); /* 1 N on 0.5 kg for 1 s */
    KG_CHECK_NEAR(s.velocity.y, -10.0, 1e-4);
    KG_CHECK_OK(kg_body_get_state(w, c, &s));
    KG_CHECK(s.angle == 0.0f && s.angular_velocity == 0.0f);
    kg_destroy_world(w);
}

typedef struct applicator_log {
    int calls;
    int last_count;
    kg_body seen[8];
} applicator_log;

static void record_and_push(kg_world* w, const kg_body* bodies, int count, void* user)
{
    applicator_log* log = user;
    log->calls++;
    log->last_count = count;
    for (int i = 0; i < count && i < 8; ++i) {
        log->seen[i] = bodies[i];
        kg_body_apply_force_to_center(w, bodies[i], (kg_vec2){1, 0});
    }
}

static void test_applicator_called_once_per_step_with_its_bodies(void)
{
    kg_world* w = make_world((kg_vec2){0, 0}, 4);
    kg_body b[3];
    for (int i = 0; i < 3; ++i) {
        b[i] = add_body(w, KG_BODY_DYNAMIC, kg_box_shape(1, 1), (kg_vec2){(float)i * 3, 0}, (kg_vec2){0, 0});
    }
    applicator_log listed = {0}, all = {0};
    kg_body chosen[2] = {b[0], b[2]};
    kg_applicator a1, a2;
    KG_CHECK_OK(kg_add_force_applicator(w, record_and_push, chosen, 2, &listed, &a1));
    KG_CHECK_OK(kg_add_force_applicator(w, record_and_push, NULL, 0, &all, &a2));
    for (int s = 0; s < 5; ++s) {
        KG_CHECK_OK(kg_world_step(w, 0.1f));
    }
    KG_CHECK(listed.calls == 5 && all.calls == 5);
    KG_CHECK(listed.last_count == 2 && all.last_count == 3);
    KG_CHECK(listed.seen[0].index == b[0].index && listed.seen[1].index == b[2].index);
    kg_vec2 v0, v1;
    KG_CHECK_OK(kg_body_get_velocity(w, b[0], &v0));
    KG_CHECK_OK(kg_body_get_velocity(w, b[1], &v1));
    KG_CHECK_NEAR(v0.x, 2.0 * 0.5, 1e-5); /* pushed by both: 2 N on 1 kg for 0.5 s */
    KG_CHECK_NEAR(v1.x, 0.5, 1e-5);
    KG_CHECK_OK(kg_destroy_body(w, b[2]));
    KG_CHECK_OK(kg_world_step(w, 0.1f));
    KG_CHECK(listed.last_count == 1 && all.last_count == 2); /* dead bodies are skipped */
    KG_CHECK_OK(kg_remove_applicator(w, a1));
    KG_CHECK(kg_remove_applicator(w, a1) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK_OK(kg_world_step(w, 0.1f));
    KG_CHECK(listed.calls == 6 && all.calls == 7);
    kg_destroy_world(w);
}

static void test_builtin_gravity_and_wind(void)
{
    kg_world* w = make_world((kg_vec2){0, 0}, 2);
    kg_body a = add_body(w, KG_BODY_DYNAMIC, kg_box_shape(1, 2), (kg_vec2){0, 0}, (kg_vec2){0, 0});
    kg_body b = add_body(w, KG_BODY_DYNAMIC, kg_box_shape(1, 1), (kg_vec2){5, 0}, (kg_vec2){0, 0});
    kg_applicator g, wind;
    KG_CHECK_OK(kg_add_gravity_applicator(w, (kg_vec2){0, -3}, &a, 1, &g));
    KG_CHECK_OK(kg_add_wind_applicator(w, (kg_vec2){2, 0}, 4.0f, 0.0f, &b, 1, &wind));
    KG_CHECK(kg_add_wind_applicator(w, (kg_vec2){0, 0}, 4.0f, 0.0f, NULL, 0, &wind) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK_OK(kg_world_step(w, 0.5f));
    kg_vec2 va, vb;
    KG_CHECK_OK(kg_body_get_velocity(w, a, &va));
    KG_CHECK_OK(kg_body_get_velocity(w, b, &vb));
    KG_CHECK_NEAR(va.y, -1.5, 1e-6); /* acceleration, whatever the mass */
    KG_CHECK_NEAR(va.x, 0.0, 1e-7);
    KG_CHECK_NEAR(vb.x, 2.0, 1e-6);  /* 4 N on 1 kg for 0.5 s */
    kg_destroy_world(w);
}

static void test_wind_drag_reaches_terminal_velocity(void)
{
    kg_world* w = make_world((kg_vec2){0, 0}, 4);
    kg_body b = add_body(w, KG_BODY_DYNAMIC, kg_box_shape(1, 1), (kg_vec2){0, 0}, (kg_vec2){0, 0});
    kg_applicator wind;
    KG_CHECK_OK(kg_add_wind_applicator(w, (kg_vec2){1, 0}, 3.0f, 1.5f, NULL, 0, &wind));
    for (int s = 0; s < 600; ++s) {
        KG_CHECK_OK(kg_world_step(w, 1.0f / 60.0f));
    }
    kg_vec2 v;
    KG_CHECK_OK(kg_body_get_velocity(w, b, &v));
    KG_CHECK_NEAR(v.x, 3.0 / 1.5, 1e-3); /* strength = drag * v */
    kg_destroy_world(w);
}

/* A 6 g body under three winds of drag 0.5 N s/m each: d h / m = 4 at dt = 1/60, where
 * an explicit drag force reversed the velocity every step and grew it to the speed clamp
 * (the soak's bug 19). It must rise to the terminal speed and never pass it. */
static void test_light_body_under_strong_drag_stays_stable(void)
{
    kg_world* w = make_world((kg_vec2){0, 0}, 4);
    kg_body b = add_body(w, KG_BODY_DYNAMIC, kg_box_shape(0.1f, 0.06f), (kg_vec2){0, 0}, (kg_vec2){0, 0});
    kg_applicator wind;
    for (int k = 0; k < 3; ++k) {
        KG_CHECK_OK(kg_add_wind_applicator(w, (kg_vec2){1, 0}, 0.5f, 0.5f, NULL, 0, &wind));
    }
    double previous = 0.0, worst_overshoot = 0.0;
    int decreasing = 0;
    for (int s = 0; s < 120; ++s) {
        KG_CHECK_OK(kg_world_step(w, 1.0f / 60.0f));
        kg_vec2 v;
        KG_CHECK_OK(kg_body_get_velocity(w, b, &v));
        worst_overshoot = fmax(worst_overshoot, v.x - 1.0);
        decreasing += v.x < previous;
        previous = v.x;
    }
    measured("measured: 6 g body, three winds (terminal 1 m/s): speed after 2 s %.6f m/s, largest overshoot %.3g m/s, "
             "steps slowing down %d\n", previous, worst_overshoot, decreasing);
    KG_CHECK_NEAR(previous, 1.0, 1e-4);
    KG_CHECK(worst_overshoot <= 1e-6);
    KG_CHECK(decreasing == 0);
    kg_destroy_world(w);
}

static void test_static_and_kinematic_bodies(void)
{
    kg_world* w = make_world((kg_vec2){0, -10}, 4);
    kg_body s = add_body(w, KG_BODY_STATIC, kg_box_shape(4, 1), (kg_vec2){0, 0}, (kg_vec2){1, 1});
    kg_body k = add_body(w, KG_BODY_KINEMATIC, kg_box_shape(1, 1), (kg_vec2){0, 5}, (kg_vec2){2, 0});
    KG_CHECK_OK(kg_body_set_angular_velocity(w, k, 1.0f));
    for (int i = 0; i < 60; ++i) {
        KG_CHECK_OK(kg_world_step(w, 1.0f / 60.0f));
    }
    kg_body_state st;
    KG_CHECK_OK(kg_body_get_state(w, s, &st));
    KG_CHECK(st.position.x == 0.0f && st.position.y == 0.0f && st.velocity.x == 0.0f);
    KG_CHECK_OK(kg_body_get_state(w, k, &st));
    KG_CHECK_NEAR(st.position.x, 2.0, 1e-4);
    KG_CHECK_NEAR(st.position.y, 5.0, 1e-6); /* gravity does not move it */
    KG_CHECK_NEAR(st.angle, 1.0, 1e-3);
    kg_destroy_world(w);
}

KG_TEST_MAIN(KG_TEST(test_projectile_matches_discrete_trajectory), KG_TEST(test_force_at_point_gives_expected_torque),
             KG_TEST(test_impulse_at_point), KG_TEST(test_damping_is_implicit), KG_TEST(test_particles_never_rotate),
             KG_TEST(test_applicator_called_once_per_step_with_its_bodies), KG_TEST(test_builtin_gravity_and_wind),
             KG_TEST(test_wind_drag_reaches_terminal_velocity),
             KG_TEST(test_light_body_under_strong_drag_stays_stable), KG_TEST(test_static_and_kinematic_bodies))
