/* Acceptance tests of the contact solver (issue 4), physics checked as physics:
 * head-on collisions (restitution 1 swaps velocities, 0 leaves the bodies together),
 * an off-centre hit (both spin; linear and angular momentum conserved), a box on a
 * 30-degree slope (holds with friction 0.7, slides at g (sin 30 - mu cos 30) with 0.2),
 * and a ball bouncing to a quarter of its drop height with restitution 0.5.
 *
 * CPU backend, world defaults (4 sub-steps, contact_hertz 45) unless a test says
 * otherwise, dt = 1/60. Every test prints its measured numbers ("measured: ...") so
 * they can be quoted; the assertions use the numbers. */
#include "kg_test.h"
#include "kgyro/kgyro.h"

#include <math.h>
#include <string.h>
#include <stdarg.h>

/* Prints a line of measured numbers and flushes it, so that it comes out before the
 * harness's failure messages (on stderr) about the same numbers. */

#define DT (1.0f / 60.0f)
#define PI_D 3.14159265358979323846

/* Sleeping off: these measure the solver, and a body put to sleep would not drift. */
static kg_world* make_world(kg_vec2 gravity)
{
    kg_world_def def = kg_default_world_def();
    def.gravity = gravity;
    def.backend = KG_BACKEND_CPU;
    def.enable_sleep = 0;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    return w;
}

static kg_body add(kg_world* w, kg_body_type type, kg_shape_def shape, kg_vec2 pos, float angle, kg_vec2 vel,
                   float friction, float restitution)
{
    kg_body_def bd = kg_default_body_def();
    bd.type = type;
    bd.shape = shape;
    bd.position = pos;
    bd.angle = angle;
    bd.velocity = vel;
    bd.friction = friction;
    bd.restitution = restitution;
    kg_body b = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    return b;
}

static kg_body_state state_of(kg_world* w, kg_body b)
{
    kg_body_state s;
    memset(&s, 0, sizeof s);
    KG_CHECK_OK(kg_body_get_state(w, b, &s));
    return s;
}

static kg_mass_data mass_of(kg_world* w, kg_body b)
{
    kg_mass_data md;
    memset(&md, 0, sizeof md);
    KG_CHECK_OK(kg_body_get_mass_data(w, b, &md));
    return md;
}

/* Linear and angular momentum (about the fixed point o) of a set of bodies, in double:
 * L = sum I w + m (c - o) x v, c the centre of mass = position + rotate(angle, local centre). */
typedef struct momentum {
    double px, py, l;
} momentum;

static momentum momentum_of(kg_world* w, const kg_body* bodies, int count, double ox, double oy)
{
    momentum m = {0.0, 0.0, 0.0};
    for (int i = 0; i < count; ++i) {
        kg_body_state s = state_of(w, bodies[i]);
        kg_mass_data md = mass_of(w, bodies[i]);
        double c = cos((double)s.angle), sn = sin((double)s.angle);
        double cx = (double)s.position.x + c * md.center.x - sn * md.center.y;
        double cy = (double)s.position.y + sn * md.center.x + c * md.center.y;
        double vx = s.velocity.x, vy = s.velocity.y;
        m.px += md.mass * vx;
        m.py += md.mass * vy;
        m.l += md.inertia * (double)s.angular_velocity + md.mass * ((cx - ox) * vy - (cy - oy) * vx);
    }
    return m;
}

/* Contacts with at least one point (touching or within the speculative distance). Not
 * the stored impulses: they are those of the last sub-step and are 0 once two bodies
 * move on together. */
static int contact_points(kg_world* w)
{
    int n = kg_world_contact_count(w), points = 0;
    for (int i = 0; i < n; ++i) {
        kg_contact_info ci;
        KG_CHECK_OK(kg_world_get_contact(w, i, &ci));
        points += ci.point_count;
    }
    return points;
}

/* ---- head-on collisions -------------------------------------------------------------- */

/* Two equal bodies on the x axis, zero gravity: a at x = -1.5 moving at +4 m/s, b at
 * x = +1.5 moving at -2 m/s (approach 6 m/s, far above the 1 m/s restitution threshold).
 * They meet at t ~ 0.33 s; we look at t = 1.5 s, then again at 2.5 s. */
static void head_on(const char* label, kg_shape_def shape, float restitution)
{
    kg_world* w = make_world((kg_vec2){0.0f, 0.0f});
    const float va = 4.0f, vb = -2.0f;
    kg_body bodies[2];
    bodies[0] = add(w, KG_BODY_DYNAMIC, shape, (kg_vec2){-1.5f, 0.0f}, 0.0f, (kg_vec2){va, 0.0f}, 0.6f, restitution);
    bodies[1] = add(w, KG_BODY_DYNAMIC, shape, (kg_vec2){1.5f, 0.0f}, 0.0f, (kg_vec2){vb, 0.0f}, 0.6f, restitution);
    kg_mass_data md = mass_of(w, bodies[0]);
    momentum m0 = momentum_of(w, bodies, 2, 0.0, 0.0);
    double p0 = hypot(m0.px, m0.py);
    double worst_dp = 0.0;
    int contact_steps = 0;
    kg_body_state sa_mid, sb_mid;
    memset(&sa_mid, 0, sizeof sa_mid);
    memset(&sb_mid, 0, sizeof sb_mid);
    for (int step = 1; step <= 150; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        contact_steps += contact_points(w) > 0;
        momentum m = momentum_of(w, bodies, 2, 0.0, 0.0);
        double dp = hypot(m.px - m0.px, m.py - m0.py) / p0;
        worst_dp = dp > worst_dp ? dp : worst_dp;
        if (step == 90) {
            sa_mid = state_of(w, bodies[0]);
            sb_mid = state_of(w, bodies[1]);
        }
    }
    kg_body_state sa = state_of(w, bodies[0]), sb = state_of(w, bodies[1]);
    measured("measured: head-on %s e=%.0f (m = %.4f kg, in %.0f m/s, %.0f m/s): at 1.5 s v1 = (%.6f, %.3g) w1 = %.3g, "
             "v2 = (%.6f, %.3g) w2 = %.3g; at 2.5 s v1 = %.6f, v2 = %.6f, gap = %.5f m; steps with a contact %d; "
             "worst |dP|/|P| over 150 steps = %.3g\n",
             label, (double)restitution, (double)md.mass, (double)va, (double)vb, (double)sa_mid.velocity.x,
             (double)sa_mid.velocity.y, (double)sa_mid.angular_velocity, (double)sb_mid.velocity.x,
             (double)sb_mid.velocity.y, (double)sb_mid.angular_velocity, (double)sa.velocity.x, (double)sb.velocity.x,
             (double)(sb.position.x - sa.position.x), contact_steps, worst_dp);
    KG_CHECK(contact_steps > 0);
    if (restitution == 1.0f) {
        /* the velocities are exchanged, within 1% */
        KG_CHECK_NEAR(sa_mid.velocity.x, vb, 0.01 * fabs(vb));
        KG_CHECK_NEAR(sb_mid.velocity.x, va, 0.01 * fabs(va));
        KG_CHECK_NEAR(sa.velocity.x, vb, 0.01 * fabs(vb));
        KG_CHECK_NEAR(sb.velocity.x, va, 0.01 * fabs(va));
    } else {
        /* they move on together at the common velocity (va + vb) / 2, within 1% of it,
         * and stay together */
        double common = 0.5 * (va + vb);
        KG_CHECK_NEAR(sa_mid.velocity.x, common, 0.01 * fabs(common));
        KG_CHECK_NEAR(sb_mid.velocity.x, common, 0.01 * fabs(common));
        KG_CHECK_NEAR(sa.velocity.x, common, 0.01 * fabs(common));
        KG_CHECK_NEAR(sb.velocity.x, common, 0.01 * fabs(common));
        double size = shape.type == KG_SHAPE_CIRCLE ? 2.0 * shape.radius : 1.0;
        KG_CHECK_NEAR(sb.position.x - sa.position.x, size, 0.01);
    }
    /* head-on and symmetric: no sideways motion and no spin. Spin is allowed only as far
     * as it moves the bodies' edges (0.5 m from the centre) by under 1% of the 6 m/s
     * approach speed, the 1% again. */
    double approach = va - vb;
    KG_CHECK_NEAR(sa.velocity.y, 0.0, 1e-4);
    KG_CHECK_NEAR(sb.velocity.y, 0.0, 1e-4);
    KG_CHECK_NEAR(0.5 * sa.angular_velocity, 0.0, 0.01 * approach);
    KG_CHECK_NEAR(0.5 * sb.angular_velocity, 0.0, 0.01 * approach);
    KG_CHECK(worst_dp <= 1e-5);
    kg_destroy_world(w);
}

static void test_head_on_boxes_elastic_exchange_velocities(void) { head_on("boxes", kg_box_shape(1.0f, 1.0f), 1.0f); }
static void test_head_on_boxes_inelastic_move_together(void) { head_on("boxes", kg_box_shape(1.0f, 1.0f), 0.0f); }
static void test_head_on_circles_elastic_exchange_velocities(void) { head_on("circles", kg_circle_shape(0.5f), 1.0f); }
static void test_head_on_circles_inelastic_move_together(void) { head_on("circles", kg_circle_shape(0.5f), 0.0f); }

/* ---- off-centre hit ------------------------------------------------------------------ */

/* Zero gravity. A moving body hits, away from its centre line, a resting 1.2 x 1.0 box of
 * density 2 whose shape is offset from its origin (centre of mass at (0.1, -0.05); its
 * left face at x = -0.5, spanning y in [-0.55, 0.45]). Friction 0.6 on both (mixing:
 * sqrt), restitution on the moving body (mixing: max). Momentum is measured about the
 * fixed point (1, -2), every step for 1.5 s; the hit happens at ~0.3 s. */
static void off_centre(const char* label, kg_shape_def shape_a, kg_vec2 pos_a, kg_vec2 vel_a, float restitution)
{
    kg_world* w = make_world((kg_vec2){0.0f, 0.0f});
    kg_body bodies[2];
    bodies[0] = add(w, KG_BODY_DYNAMIC, shape_a, pos_a, 0.0f, vel_a, 0.6f, restitution);
    kg_body_def bd = kg_default_body_def();
    bd.shape = kg_offset_box_shape(1.2f, 1.0f, (kg_vec2){0.1f, -0.05f}, 0.0f);
    bd.density = 2.0f;
    bd.friction = 0.6f;
    KG_CHECK_OK(kg_create_body(w, &bd, &bodies[1]));
    const double ox = 1.0, oy = -2.0;
    momentum m0 = momentum_of(w, bodies, 2, ox, oy);
    double p0 = hypot(m0.px, m0.py), l0 = fabs(m0.l);
    double worst_dp = 0.0, worst_dl = 0.0;
    int contact_steps = 0;
    for (int step = 1; step <= 90; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        contact_steps += contact_points(w) > 0;
        momentum m = momentum_of(w, bodies, 2, ox, oy);
        double dp = hypot(m.px - m0.px, m.py - m0.py) / p0, dl = fabs(m.l - m0.l) / l0;
        worst_dp = dp > worst_dp ? dp : worst_dp;
        worst_dl = dl > worst_dl ? dl : worst_dl;
    }
    momentum m1 = momentum_of(w, bodies, 2, ox, oy);
    kg_body_state sa = state_of(w, bodies[0]), sb = state_of(w, bodies[1]);
    measured("measured: off-centre %s e=%.1f: after 1.5 s w1 = %.5f rad/s, w2 = %.5f rad/s, v1 = (%.5f, %.5f), "
             "v2 = (%.5f, %.5f); P = (%.7g, %.7g) -> (%.7g, %.7g), L about (1,-2) = %.7g -> %.7g; "
             "worst over 90 steps |dP|/|P| = %.3g, |dL|/|L| = %.3g; steps with a contact %d\n",
             label, (double)restitution, (double)sa.angular_velocity, (double)sb.angular_velocity,
             (double)sa.velocity.x, (double)sa.velocity.y, (double)sb.velocity.x, (double)sb.velocity.y, m0.px, m0.py,
             m1.px, m1.py, m0.l, m1.l, worst_dp, worst_dl, contact_steps);
    KG_CHECK(contact_steps > 0);
    /* both spin: well above rounding (a clean hit gives tenths of rad/s here) */
    KG_CHECK(fabs(sa.angular_velocity) > 0.05);
    KG_CHECK(fabs(sb.angular_velocity) > 0.05);
    /* and the struck box was pushed along the hit */
    KG_CHECK(sb.velocity.x > 0.5f);
    KG_CHECK(worst_dp <= 1e-4);
    KG_CHECK(worst_dl <= 1e-4);
    KG_CHECK(worst_dp <= 1e-5); /* free bodies: linear momentum within 1e-5, as for every collision */
    kg_destroy_world(w);
}

/* A 0.8 m box (density 1) at (-2.5, 0.55) moving at 6 m/s: the overlap in y is
 * [0.15, 0.45], above the struck box's centre of mass and below the moving box's. */
static void test_off_centre_box_hit_inelastic_spins_and_conserves_momentum(void)
{
    off_centre("box on box", kg_box_shape(0.8f, 0.8f), (kg_vec2){-2.5f, 0.55f}, (kg_vec2){6.0f, 0.0f}, 0.0f);
}

static void test_off_centre_box_hit_bouncy_spins_and_conserves_momentum(void)
{
    off_centre("box on box", kg_box_shape(0.8f, 0.8f), (kg_vec2){-2.5f, 0.55f}, (kg_vec2){6.0f, 0.0f}, 0.3f);
}

/* A circle of radius 0.3 at (-2.5, -0.2) moving at (6, 1.2) m/s meets the face at
 * y ~ 0.14, above the struck box's centre of mass; friction spins the circle. */
static void test_off_centre_circle_hit_bouncy_spins_and_conserves_momentum(void)
{
    off_centre("circle on box", kg_circle_shape(0.3f), (kg_vec2){-2.5f, -0.2f}, (kg_vec2){6.0f, 1.2f}, 0.3f);
}

/* ---- a box on a 30-degree slope ------------------------------------------------------ */

typedef struct slope_run {
    double along0, along_settled, along_end; /* distance along the slope (up-slope positive) */
    double v_along_t1, v_along_t2, t1, t2;
    double accel_fit;    /* least-squares fit of positions over the window */
    double normal_drift; /* change of the distance from the slope surface */
    double angle_drift;
} slope_run;

/* A static 24 x 1 box turned 30 degrees about the origin; a 1 m box (density 1) turned
 * the same, resting on its upper face 4 m up the slope (touching, no gap). friction is
 * set on both (mixing sqrt(fa fb) gives friction). */
static slope_run run_slope(float friction, double settle, double duration)
{
    const double theta = PI_D / 6.0;
    const double ux = cos(theta), uy = sin(theta), nx = -sin(theta), ny = cos(theta);
    kg_world* w = make_world((kg_vec2){0.0f, -10.0f});
    add(w, KG_BODY_STATIC, kg_box_shape(24.0f, 1.0f), (kg_vec2){0.0f, 0.0f}, (float)theta, (kg_vec2){0, 0}, friction,
        0.0f);
    const double s0 = 4.0, lift = 0.5 + 0.5;
    kg_vec2 p = {(float)(s0 * ux + lift * nx), (float)(s0 * uy + lift * ny)};
    kg_body box = add(w, KG_BODY_DYNAMIC, kg_box_shape(1.0f, 1.0f), p, (float)theta, (kg_vec2){0, 0}, friction, 0.0f);
    slope_run r;
    memset(&r, 0, sizeof r);
    int settle_steps = (int)lround(settle / DT), total = settle_steps + (int)lround(duration / DT);
    r.t1 = settle;
    r.t2 = settle + duration;
    double sum_t = 0, sum_t2 = 0, sum_t3 = 0, sum_t4 = 0, sum_s = 0, sum_ts = 0, sum_t2s = 0;
    int samples = 0;
    double normal0 = 0.0, angle0 = 0.0;
    kg_body_state s = state_of(w, box);
    r.along0 = s.position.x * ux + s.position.y * uy;
    for (int step = 0; step <= total; ++step) {
        if (step > 0) {
            KG_CHECK_OK(kg_world_step(w, DT));
        }
        s = state_of(w, box);
        double along = s.position.x * ux + s.position.y * uy;
        double normal = s.position.x * nx + s.position.y * ny;
        if (step == settle_steps) {
            r.along_settled = along;
            r.v_along_t1 = s.velocity.x * ux + s.velocity.y * uy;
            normal0 = normal;
            angle0 = s.angle;
        }
        if (step >= settle_steps) {
            double t = (step - settle_steps) * (double)DT;
            sum_t += t;
            sum_t2 += t * t;
            sum_t3 += t * t * t;
            sum_t4 += t * t * t * t;
            sum_s += along;
            sum_ts += t * along;
            sum_t2s += t * t * along;
            samples++;
            double dn = fabs(normal - normal0), da = fabs(s.angle - angle0);
            r.normal_drift = dn > r.normal_drift ? dn : r.normal_drift;
            r.angle_drift = da > r.angle_drift ? da : r.angle_drift;
        }
        if (step == total) {
            r.along_end = along;
            r.v_along_t2 = s.velocity.x * ux + s.velocity.y * uy;
        }
    }
    /* fit s(t) = c0 + c1 t + c2 t^2 by least squares (normal equations, 3x3, Cramer) */
    double n = samples;
    double a[3][3] = {{n, sum_t, sum_t2}, {sum_t, sum_t2, sum_t3}, {sum_t2, sum_t3, sum_t4}};
    double b[3] = {sum_s, sum_ts, sum_t2s};
    double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                 a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    double det2 = a[0][0] * (a[1][1] * b[2] - b[1] * a[2][1]) - a[0][1] * (a[1][0] * b[2] - b[1] * a[2][0]) +
                  b[0] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    r.accel_fit = 2.0 * det2 / det;
    kg_destroy_world(w);
    return r;
}

static void test_box_on_30_degree_slope_holds_with_friction_07(void)
{
    /* settled for 0.25 s, then 5 s: how far the box's origin moves along the slope */
    slope_run r = run_slope(0.7f, 0.25, 5.0);
    double drift = fabs(r.along_end - r.along_settled);
    measured("measured: slope friction 0.7: along-slope drift over 5 s after 0.25 s of settling = %.4g mm "
             "(from placement: %.4g mm over 5.25 s); velocity along the slope at 0.25 s %.3g m/s, at 5.25 s %.3g m/s; "
             "largest change of the distance to the slope surface %.3g mm, of the angle %.3g rad\n",
             drift * 1e3, fabs(r.along_end - r.along0) * 1e3, r.v_along_t1, r.v_along_t2, r.normal_drift * 1e3,
             r.angle_drift);
    KG_CHECK(drift < 1e-3);
    KG_CHECK(fabs(r.along_end - r.along0) < 1e-2); /* and it did not slip while settling either */
}

static void test_box_on_30_degree_slope_slides_with_friction_02(void)
{
    /* contact is established within a few steps; the window is [0.25 s, 1.75 s] */
    slope_run r = run_slope(0.2f, 0.25, 1.5);
    const double g = 10.0, theta = PI_D / 6.0;
    double expected = g * (sin(theta) - 0.2 * cos(theta));
    double a_vel = -(r.v_along_t2 - r.v_along_t1) / (r.t2 - r.t1);
    double a_fit = -r.accel_fit;
    measured(
        "measured: slope friction 0.2: acceleration down the slope over [%.2f s, %.2f s] from velocities %.5f m/s^2, "
        "from a quadratic fit of positions %.5f m/s^2, expected g (sin 30 - 0.2 cos 30) = %.5f m/s^2 "
        "(errors %.3f%%, %.3f%%); distance slid %.3f m; largest change of the distance to the slope surface %.3g mm\n",
        r.t1, r.t2, a_vel, a_fit, expected, 100.0 * (a_vel - expected) / expected,
        100.0 * (a_fit - expected) / expected, r.along0 - r.along_end, r.normal_drift * 1e3);
    KG_CHECK_NEAR(a_vel, expected, 0.02 * expected);
    KG_CHECK_NEAR(a_fit, expected, 0.02 * expected);
    KG_CHECK(r.normal_drift < 2e-3); /* it slides on the surface: neither sinks nor hops */
}

/* A box held on the 30 degree slope by friction 0.7, its contact kept step after step
 * (collide/recycle.h), slides at once when its friction and the slope's are set to 0.2: a
 * kept contact takes the materials as they are now. */
static void test_friction_set_while_resting_takes_effect(void)
{
    const double theta = PI_D / 6.0, ux = cos(theta), uy = sin(theta);
    kg_world* w = make_world((kg_vec2){0.0f, -10.0f});
    kg_body slope = add(w, KG_BODY_STATIC, kg_box_shape(24.0f, 1.0f), (kg_vec2){0.0f, 0.0f}, (float)theta,
                        (kg_vec2){0, 0}, 0.7f, 0.0f);
    kg_vec2 p = {(float)(4.0 * ux - sin(theta)), (float)(4.0 * uy + cos(theta))};
    kg_body box = add(w, KG_BODY_DYNAMIC, kg_box_shape(1.0f, 1.0f), p, (float)theta, (kg_vec2){0, 0}, 0.7f, 0.0f);
    for (int step = 0; step < 60; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_body_state held = state_of(w, box);
    KG_CHECK_OK(kg_body_set_friction(w, slope, 0.2f));
    KG_CHECK_OK(kg_body_set_friction(w, box, 0.2f));
    for (int step = 0; step < 30; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_body_state slid = state_of(w, box);
    double v = -(slid.velocity.x * ux + slid.velocity.y * uy);
    double expected = 10.0 * (sin(theta) - 0.2 * cos(theta)) * 0.5; /* its speed after 0.5 s */
    measured("measured: held at %.3g m/s; 0.5 s after friction 0.7 -> 0.2, %.4f m/s down the slope (expected %.4f)\n",
             -(held.velocity.x * ux + held.velocity.y * uy), v, expected);
    KG_CHECK(fabs(held.velocity.x) < 1e-3 && fabs(held.velocity.y) < 1e-3);
    KG_CHECK_NEAR(v, expected, 0.05 * expected);
    kg_destroy_world(w);
}

/* ---- a bouncing ball ------------------------------------------------------------------- */

/* Static ground 40 x 1 with its top at y = 0; a ball of radius 0.25. */
static kg_world* ground_world(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, -10.0f});
    add(w, KG_BODY_STATIC, kg_box_shape(40.0f, 1.0f), (kg_vec2){0.0f, -0.5f}, 0.0f, (kg_vec2){0, 0}, 0.6f, 0.0f);
    return w;
}

/* The resting height of the ball's centre: a ball set down on the ground, after 2 s
 * (soft contacts hold it a little lower than its radius). */
static double resting_height(float radius)
{
    kg_world* w = ground_world();
    kg_body rest =
        add(w, KG_BODY_DYNAMIC, kg_circle_shape(radius), (kg_vec2){0.0f, radius}, 0.0f, (kg_vec2){0, 0}, 0.6f, 0.5f);
    for (int step = 0; step < 120; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    double y = state_of(w, rest).position.y;
    kg_destroy_world(w);
    return y;
}

/* The ball's centre starts drop metres above its resting height, at rest. Restitution 0.5
 * on the ball, 0 on the ground (mixing: max). The apex of the first bounce is the highest
 * centre between the first upward velocity and the next downward one. */
static void bounce(double drop)
{
    const float radius = 0.25f;
    double rest_y = resting_height(radius);
    kg_world* w = ground_world();
    kg_body ball = add(w, KG_BODY_DYNAMIC, kg_circle_shape(radius), (kg_vec2){0.0f, (float)(rest_y + drop)}, 0.0f,
                       (kg_vec2){0, 0}, 0.6f, 0.5f);
    double start_y = state_of(w, ball).position.y;
    double impact_speed = 0.0, rebound_speed = 0.0, apex = -1.0, prev_vy = 0.0, lowest = 1e9;
    int phase = 0; /* 0 falling, 1 rising after the first bounce, 2 past the apex */
    for (int step = 0; step < 300 && phase < 2; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_body_state s = state_of(w, ball);
        lowest = s.position.y < lowest ? s.position.y : lowest;
        if (phase == 0 && s.velocity.y > 0.0f) {
            phase = 1;
            impact_speed = -prev_vy;
            rebound_speed = s.velocity.y;
        }
        if (phase == 1) {
            if (s.position.y > apex) {
                apex = s.position.y;
            }
            if (s.velocity.y < 0.0f) {
                phase = 2;
            }
        }
        prev_vy = s.velocity.y;
    }
    double height = start_y - rest_y, up = apex - rest_y;
    measured(
        "measured: ball e=0.5 dropped %.1f m: resting centre height %.5f m (radius %.2f), drop %.5f m, impact speed "
        "%.4f m/s, rebound speed %.4f m/s (ratio %.4f), lowest centre %.4f m, first apex %.5f m above rest = %.4f "
        "of the drop (expected 0.25, error %.2f%%)\n",
        drop, rest_y, (double)radius, height, impact_speed, rebound_speed, rebound_speed / impact_speed, lowest, up,
        up / height, 100.0 * (up / height - 0.25) / 0.25);
    KG_CHECK(phase == 2);
    KG_CHECK(impact_speed > 2.0); /* well above the 1 m/s restitution threshold */
    /* the bounce itself: half the speed of a fall from that height, within 3% */
    double fall_speed = sqrt(2.0 * 10.0 * height);
    KG_CHECK_NEAR(rebound_speed, 0.5 * fall_speed, 0.03 * 0.5 * fall_speed);
    /* the apex: within 3%, plus what semi-implicit Euler loses on the way up at any
     * restitution, half a sub-step of the rebound speed (4.6 mm at 2.2 m/s and the
     * default 4 sub-steps of 1/240 s) */
    double h = (double)DT / (double)kg_default_world_def().substeps;
    KG_CHECK_NEAR(up, 0.25 * height, 0.03 * 0.25 * height + 0.5 * rebound_speed * h);
    kg_destroy_world(w);
}

/* Drops of 1 to 3 m: impacts at 4.5 to 7.8 m/s, all well above the 1 m/s threshold, and
 * 3% of a quarter of the drop (7.5 mm at 1 m) above the 5 mm linear slop. Several
 * heights, because the outcome depends on where the ball is at the step in which its
 * contact appears: one lucky height would prove little. */
static void test_ball_with_restitution_05_bounces_to_a_quarter(void)
{
    static const double drops[] = {1.0, 1.5, 2.0, 2.5, 3.0};
    for (int i = 0; i < (int)(sizeof drops / sizeof drops[0]); ++i) {
        bounce(drops[i]);
    }
}

KG_TEST_MAIN(KG_TEST(test_head_on_boxes_elastic_exchange_velocities),
             KG_TEST(test_head_on_boxes_inelastic_move_together),
             KG_TEST(test_head_on_circles_elastic_exchange_velocities),
             KG_TEST(test_head_on_circles_inelastic_move_together),
             KG_TEST(test_off_centre_box_hit_inelastic_spins_and_conserves_momentum),
             KG_TEST(test_off_centre_box_hit_bouncy_spins_and_conserves_momentum),
             KG_TEST(test_off_centre_circle_hit_bouncy_spins_and_conserves_momentum),
             KG_TEST(test_box_on_30_degree_slope_holds_with_friction_07),
             KG_TEST(test_box_on_30_degree_slope_slides_with_friction_02),
             KG_TEST(test_friction_set_while_resting_takes_effect),
             KG_TEST(test_ball_with_restitution_05_bounces_to_a_quarter))
