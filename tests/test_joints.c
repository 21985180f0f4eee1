/* Joints (include/kgyro/joint.h, docs/joints.md): the acceptance of issue 17 that the
 * first kinds can meet, with the numbers asserted and printed. */
#include "kg_test.h"
#include "kg_test_world.h"
#include "core/joint.h" /* white box: the joints' colours and their overflow */
#include "solve/contact_wide.h" /* white box: which SIMD widths this CPU runs */
#include "kgyro/scene.h"

#define DT (1.0f / 60.0f)
#define PI_F 3.14159265359f
#define PI_D 3.14159265358979323846

/* A world on backend (the test's OpenCL device), else as joint_world. */
static kg_world* backend_world(kg_backend backend, int sleep)
{
    kg_world_def def = kg_default_world_def();
    def.backend = backend;
    def.device_index = kg_test_opencl_device();
    def.enable_sleep = sleep;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    return w;
}

/* How many backends to run a test on: the CPU, and OpenCL when a device is there. */
static int backend_count(void)
{
    int devices = 0;
    return kg_opencl_device_count(&devices) == KG_OK && devices > 0 ? 2 : 1;
}

static const kg_backend kBackends[2] = {KG_BACKEND_CPU, KG_BACKEND_OPENCL};

static kg_world* joint_world(int threads, int sleep)
{
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    def.threads = threads;
    def.enable_sleep = sleep;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    return w;
}

static kg_body add_body(kg_world* w, kg_vec2 at, kg_shape_def shape, float density)
{
    kg_body_def def = kg_default_body_def();
    def.position = at;
    def.shape = shape;
    def.density = density;
    kg_body b = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &def, &b));
    return b;
}

static kg_vec2 position_of(kg_world* w, kg_body b)
{
    kg_vec2 p = {0.0f, 0.0f};
    KG_CHECK_OK(kg_body_get_position(w, b, &p));
    return p;
}

static kg_body null_body(void)
{
    kg_body none = KG_NULL_BODY_INIT;
    return none;
}

/* A revolute joint between a (null: the world) and b at a world point. */
static kg_joint hinge(kg_world* w, kg_body a, kg_body b, kg_vec2 at, const kg_revolute_joint_def* base)
{
    kg_revolute_joint_def def = base ? *base : kg_default_revolute_joint_def();
    def.base.body_a = a;
    def.base.body_b = b;
    KG_CHECK_OK(kg_joint_local_point(w, a, at, &def.local_anchor_a));
    KG_CHECK_OK(kg_joint_local_point(w, b, at, &def.local_anchor_b));
    kg_joint j = KG_NULL_JOINT_INIT;
    KG_CHECK_OK(kg_create_revolute_joint(w, &def, &j));
    return j;
}

/* Time of the upward crossings of zero by a sampled signal (linear interpolation). */
typedef struct crossings {
    double first, last;
    int count;
    double previous;
} crossings;

static void crossing_sample(crossings* c, double t, double value)
{
    if (c->previous < 0.0 && value >= 0.0) {
        double at = t - DT * value / (value - c->previous);
        if (c->count == 0) {
            c->first = at;
        }
        c->last = at;
        c->count += 1;
    }
    c->previous = value;
}

static double crossing_period(const crossings* c) { return c->count > 1 ? (c->last - c->first) / (c->count - 1) : 0.0; }

/* A disc of radius 0.1 on a massless rod of 2 m (a revolute joint at the pivot, the disc's
 * own hinge point 2 m from its centre), released at 0.1 rad: the physical pendulum's
 * period T = 2 pi sqrt(I_pivot / (m g L)) (1 + theta^2 / 16) within 0.5% over 10 s, the
 * length within 1 mm, the swing energy within 1%. */
static void test_revolute_pendulum_period_length_energy(void)
{
    kg_world* w = joint_world(1, 0);
    const float length = 2.0f, theta0 = 0.1f, g = 10.0f;
    kg_vec2 pivot = {0.0f, 10.0f};
    kg_vec2 start = {pivot.x + length * sinf(theta0), pivot.y - length * cosf(theta0)};
    kg_body bob = add_body(w, start, kg_circle_shape(0.1f), 1.0f);
    hinge(w, null_body(), bob, pivot, NULL);
    kg_mass_data md;
    KG_CHECK_OK(kg_body_get_mass_data(w, bob, &md));
    double i_pivot = (double)md.inertia + (double)md.mass * length * length;
    double expected = 2.0 * PI_D * sqrt(i_pivot / ((double)md.mass * g * length)) * (1.0 + theta0 * theta0 / 16.0);
    crossings c = {0.0, 0.0, 0, -1.0};
    c.previous = start.x - pivot.x; /* positive: the first crossing is the return */
    double worst_length = 0.0, e0 = -1.0, e_first = 0.0, e_last = 0.0;
    int first_n = 0, last_n = 0;
    int steps = (int)(10.0f / DT);
    for (int s = 1; s <= steps; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_body_state st;
        KG_CHECK_OK(kg_body_get_state(w, bob, &st));
        double dx = st.position.x - pivot.x, dy = st.position.y - pivot.y;
        worst_length = fmax(worst_length, fabs(sqrt(dx * dx + dy * dy) - length));
        crossing_sample(&c, s * DT, -dx); /* x falls through zero: a full period between each */
        double v2 = (double)st.velocity.x * st.velocity.x + (double)st.velocity.y * st.velocity.y;
        double e = 0.5 * md.mass * v2 + 0.5 * md.inertia * (double)st.angular_velocity * st.angular_velocity +
                   md.mass * g * (dy + length); /* the swing's energy, 0 at rest at the bottom */
        if (e0 < 0.0) {
            e0 = md.mass * g * length * (1.0 - cos(theta0));
        }
        if (s <= (int)(expected / DT)) { /* the first period's mean and the last one's */
            e_first += e;
            first_n++;
        }
        if (s > steps - (int)(expected / DT)) {
            e_last += e;
            last_n++;
        }
    }
    double period = crossing_period(&c);
    e_first /= first_n;
    e_last /= last_n;
    measured("measured: pendulum period %.5f s against %.5f (%.3f%%) over %d periods, length off by %.3g mm at "
             "worst, swing energy %.6g J at release, mean over the first period %.6g, over the last %.6g (%.3f%% "
             "lost)\n",
             period, expected, 100.0 * (period - expected) / expected, c.count - 1, 1000.0 * worst_length, e0,
             e_first, e_last, 100.0 * (e_first - e_last) / e_first);
    KG_CHECK(c.count >= 3);
    KG_CHECK_NEAR(period, expected, 0.005 * expected);
    KG_CHECK(worst_length < 0.001);
    KG_CHECK(fabs(e_first - e_last) <= 0.01 * e_first);
    kg_destroy_world(w);
}

/* A world like joint_world with substeps sub-steps. */
static kg_world* substep_world(int substeps, int sleep)
{
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    def.substeps = substeps;
    def.enable_sleep = sleep;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    return w;
}

/* 40 links of 0.5 m hung from the world carry a load of `load` times a link's mass:
 * the chain's stretch once at rest and at worst on the way (it starts unstretched, the
 * load let go), and when it fell asleep (-1: not in 10 s). */
static void run_chain(float load, int substeps, double* final_stretch, double* worst, double* asleep_s,
                      double* fastest)
{
    kg_world* w = substep_world(substeps, 1);
    const int links = 40;
    const float link = 0.5f;
    kg_vec2 top = {0.0f, 30.0f};
    kg_body prev = null_body();
    kg_body body[41];
    for (int i = 0; i < links; ++i) {
        kg_vec2 at = {top.x, top.y - (i + 0.5f) * link};
        body[i] = add_body(w, at, kg_box_shape(0.1f, link), 1.0f);
        hinge(w, prev, body[i], (kg_vec2){top.x, top.y - i * link}, NULL);
        prev = body[i];
    }
    kg_mass_data md;
    KG_CHECK_OK(kg_body_get_mass_data(w, body[0], &md));
    kg_body_def def = kg_default_body_def();
    def.position = (kg_vec2){top.x, top.y - links * link - 0.25f};
    def.shape = kg_box_shape(0.5f, 0.5f);
    def.mass = load * md.mass;
    KG_CHECK_OK(kg_create_body(w, &def, &body[links]));
    kg_joint last = hinge(w, prev, body[links], (kg_vec2){top.x, top.y - links * link}, NULL);
    *worst = 0.0;
    *asleep_s = -1.0;
    kg_vec2 a, b;
    for (int s = 1; s <= 600; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
        KG_CHECK_OK(kg_joint_get_world_anchors(w, last, &a, &b));
        *worst = fmax(*worst, (top.y - b.y - links * link) / (links * link));
        if (*asleep_s < 0.0 && kg_world_asleep_count(w) == links + 1) {
            *asleep_s = s * DT;
        }
    }
    KG_CHECK_OK(kg_joint_get_world_anchors(w, last, &a, &b));
    *final_stretch = (top.y - b.y - links * link) / (links * link);
    *fastest = 0.0;
    for (int i = 0; i <= links; ++i) {
        kg_vec2 v;
        KG_CHECK_OK(kg_body_get_velocity(w, body[i], &v));
        *fastest = fmax(*fastest, sqrt((double)v.x * v.x + (double)v.y * v.y));
    }
    kg_destroy_world(w);
}

/* 40 links of 0.5 m hung from the world carry a load of 100 times a link's mass (4
 * sub-steps): the chain stretches less than 1% and comes to rest (falls asleep within the
 * 10 s). The same with 1,000 times at 8 sub-steps: the load rings on the soft chain at
 * 1.25 Hz, barely damped, until the over-relaxed relax pass stills it (KG_JOINT_OVERRELAX;
 * without it, it still moved at 0.17 m/s after 10 s, docs/joints.md). */
static void test_hanging_chain_with_heavy_load(void)
{
    double final_stretch, worst, asleep, fastest;
    run_chain(100.0f, 4, &final_stretch, &worst, &asleep, &fastest);
    measured("measured: chain of 40 links, load 100x, 4 sub-steps: stretch at rest %.4f%%, at worst %.4f%% (the "
             "load let go), asleep at %.2f s\n",
             100.0 * final_stretch, 100.0 * worst, asleep);
    KG_CHECK(final_stretch < 0.01);
    KG_CHECK(asleep > 0.0);
    run_chain(1000.0f, 8, &final_stretch, &worst, &asleep, &fastest);
    measured("measured: chain of 40 links, load 1000x, 8 sub-steps: stretch at 10 s %.4f%%, at worst %.4f%%, "
             "fastest body %.3g m/s at 10 s, asleep at %.2f s (-1: not yet)\n",
             100.0 * final_stretch, 100.0 * worst, fastest, asleep);
    KG_CHECK(final_stretch < 0.01);
    KG_CHECK(asleep > 0.0);
    KG_CHECK(fastest == 0.0); /* asleep: still */
}

/* A wheel on a motor (2 rad/s, at most 10 N m) turns against a load of 5 N m at its
 * target speed within 2%; against 20 N m it stalls, the motor's torque at its maximum
 * within 2%. */
static void test_revolute_motor_speed_and_stall(void)
{
    kg_world* w = joint_world(1, 0);
    KG_CHECK_OK(kg_world_set_gravity(w, (kg_vec2){0.0f, 0.0f}));
    kg_body wheel = add_body(w, (kg_vec2){0.0f, 0.0f}, kg_circle_shape(0.5f), 1.0f);
    kg_revolute_joint_def def = kg_default_revolute_joint_def();
    def.enable_motor = 1;
    def.motor_speed = 2.0f;
    def.max_motor_torque = 10.0f;
    kg_joint j = hinge(w, null_body(), wheel, (kg_vec2){0.0f, 0.0f}, &def);
    float omega = 0.0f, torque = 0.0f;
    kg_vec2 force;
    for (int s = 0; s < 120; ++s) {
        KG_CHECK_OK(kg_body_apply_torque(w, wheel, -5.0f));
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    KG_CHECK_OK(kg_body_get_angular_velocity(w, wheel, &omega));
    KG_CHECK_OK(kg_joint_get_reaction(w, j, &force, &torque));
    measured("measured: motor at %.5f rad/s against a target of 2 under 5 N m, its torque %.5f N m\n", (double)omega,
             (double)torque);
    KG_CHECK_NEAR(omega, 2.0f, 0.04f);
    KG_CHECK_NEAR(torque, 5.0f, 0.1f);
    for (int s = 0; s < 120; ++s) {
        KG_CHECK_OK(kg_body_apply_torque(w, wheel, -20.0f));
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    KG_CHECK_OK(kg_body_get_angular_velocity(w, wheel, &omega));
    KG_CHECK_OK(kg_joint_get_reaction(w, j, &force, &torque));
    measured("measured: stalled under 20 N m: %.4f rad/s, the motor's torque %.5f N m (max 10)\n", (double)omega,
             (double)torque);
    KG_CHECK(omega < 0.0f);
    KG_CHECK_NEAR(torque, 10.0f, 0.2f);
    kg_destroy_world(w);
}

/* A door (1 m x 0.1 m) hinged at its left end rests on its lower limit (0) under its
 * weight and a load of 10 times it at its tip: it goes less than 0.5 degrees past it. */
static void test_revolute_door_limit_under_load(void)
{
    kg_world* w = joint_world(1, 0);
    kg_body door = add_body(w, (kg_vec2){0.5f, 5.0f}, kg_box_shape(1.0f, 0.1f), 1.0f);
    kg_revolute_joint_def def = kg_default_revolute_joint_def();
    def.enable_limit = 1;
    def.lower_angle = 0.0f;
    def.upper_angle = 0.5f * PI_F;
    kg_joint j = hinge(w, null_body(), door, (kg_vec2){0.0f, 5.0f}, &def);
    kg_mass_data md;
    KG_CHECK_OK(kg_body_get_mass_data(w, door, &md));
    float worst = 0.0f, angle = 0.0f;
    for (int s = 0; s < 300; ++s) {
        kg_vec2 tip;
        kg_vec2 local_tip = {0.5f, 0.0f};
        kg_body_state st;
        KG_CHECK_OK(kg_body_get_state(w, door, &st));
        tip.x = st.position.x + cosf(st.angle) * local_tip.x;
        tip.y = st.position.y + sinf(st.angle) * local_tip.x;
        KG_CHECK_OK(kg_body_apply_force(w, door, (kg_vec2){0.0f, -10.0f * md.mass * 10.0f}, tip));
        KG_CHECK_OK(kg_world_step(w, DT));
        KG_CHECK_OK(kg_revolute_joint_get_angle(w, j, &angle));
        worst = fminf(worst, angle);
    }
    measured("measured: door past its limit by %.4f degrees at the end, %.4f at worst (10x load at its tip)\n",
             (double)(-angle * 180.0f / PI_F), (double)(-worst * 180.0f / PI_F));
    KG_CHECK(-worst * 180.0f / PI_F < 0.5f);
    kg_destroy_world(w);
}

/* A 1 kg disc on a distance spring of 2 Hz (damping ratio 0.02) to the world, pulled
 * 0.1 m out, no gravity: it oscillates at 2 Hz (less the damping's share) within 2%. */
static void test_distance_spring_frequency(void)
{
    kg_world* w = joint_world(1, 0);
    KG_CHECK_OK(kg_world_set_gravity(w, (kg_vec2){0.0f, 0.0f}));
    kg_body_def bd = kg_default_body_def();
    bd.position = (kg_vec2){1.1f, 0.0f};
    bd.shape = kg_circle_shape(0.1f);
    bd.mass = 1.0f;
    kg_body ball = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &ball));
    kg_distance_joint_def def = kg_default_distance_joint_def();
    def.base.body_b = ball;
    def.local_anchor_a = (kg_vec2){0.0f, 0.0f};
    def.length = 1.0f;
    def.enable_spring = 1;
    def.hertz = 2.0f;
    def.damping_ratio = 0.02f;
    kg_joint j = KG_NULL_JOINT_INIT;
    KG_CHECK_OK(kg_create_distance_joint(w, &def, &j));
    crossings c = {0.0, 0.0, 0, 1.0};
    for (int s = 1; s <= 300; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
        crossing_sample(&c, s * DT, position_of(w, ball).x - 1.0f);
    }
    double expected = 1.0 / (2.0 * sqrt(1.0 - 0.02 * 0.02));
    double period = crossing_period(&c);
    measured("measured: distance spring period %.5f s against %.5f (%.3f%%) over %d periods\n", period, expected,
             100.0 * (period - expected) / expected, c.count - 1);
    KG_CHECK(c.count >= 5);
    KG_CHECK_NEAR(period, expected, 0.02 * expected);
    kg_destroy_world(w);
}

/* A rope of 2 m (a distance joint with a maximum length only) catches a ball dropped
 * from beside its anchor and swings it: never longer than 2 m by more than 1%. */
static void test_rope_never_overstretches(void)
{
    kg_world* w = joint_world(1, 0);
    kg_body ball = add_body(w, (kg_vec2){1.0f, 10.0f}, kg_circle_shape(0.1f), 5.0f);
    kg_distance_joint_def def = kg_default_distance_joint_def();
    def.base.body_b = ball;
    def.local_anchor_a = (kg_vec2){0.0f, 10.0f};
    def.length = 2.0f;
    def.enable_spring = 1;
    def.hertz = 0.0f;
    def.enable_limit = 1;
    def.min_length = 0.0f;
    def.max_length = 2.0f;
    kg_joint j = KG_NULL_JOINT_INIT;
    KG_CHECK_OK(kg_create_distance_joint(w, &def, &j));
    double worst = 0.0, shortest = 10.0;
    for (int s = 0; s < 600; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_vec2 p = position_of(w, ball);
        double len = sqrt((double)p.x * p.x + (double)(p.y - 10.0f) * (p.y - 10.0f));
        worst = fmax(worst, len);
        shortest = fmin(shortest, len);
    }
    measured("measured: rope of 2 m at most %.5f m long (%.3f%% over), at least %.4f m (slack at the start)\n", worst,
             100.0 * (worst - 2.0) / 2.0, shortest);
    KG_CHECK(worst <= 2.0 * 1.01);
    KG_CHECK(shortest < 1.5);
    kg_destroy_world(w);
}

/* Ten planks of 0.5 m x 0.1 m welded end to end, the first welded to the world: a stiff
 * cantilever, which a rigid weld would hold level. Its tip drops (the soft constraints'
 * equilibrium, F / (m (2 pi hertz)^2) at each weld) by the returned fraction of its length. */
static float cantilever_drop(int substeps)
{
    kg_world* w = substep_world(substeps, 0);
    const int planks = 10;
    const float plank = 0.5f;
    kg_body prev = null_body();
    kg_body tip = KG_NULL_BODY_INIT;
    for (int i = 0; i < planks; ++i) {
        kg_body b = add_body(w, (kg_vec2){(i + 0.5f) * plank, 5.0f}, kg_box_shape(plank, 0.1f), 1.0f);
        kg_weld_joint_def def = kg_default_weld_joint_def();
        def.base.body_a = prev;
        def.base.body_b = b;
        kg_vec2 at = {i * plank, 5.0f};
        KG_CHECK_OK(kg_joint_local_point(w, prev, at, &def.local_anchor_a));
        KG_CHECK_OK(kg_joint_local_point(w, b, at, &def.local_anchor_b));
        kg_joint j = KG_NULL_JOINT_INIT;
        KG_CHECK_OK(kg_create_weld_joint(w, &def, &j));
        prev = b;
        tip = b;
    }
    for (int s = 0; s < 300; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_body_state st;
    KG_CHECK_OK(kg_body_get_state(w, tip, &st));
    float drop = 5.0f - (st.position.y + sinf(st.angle) * 0.5f * plank);
    measured("measured: welded cantilever of %d planks (%.1f m), %d sub-steps: tip drop %.4f m (%.3f%% of its "
             "length), tip angle %.4f rad\n",
             planks, (double)(planks * plank), substeps, (double)drop, (double)(100.0f * drop / (planks * plank)),
             (double)st.angle);
    kg_destroy_world(w);
    return drop / (planks * plank);
}

/* The cantilever's tip drops less than 10% of its length at 4 sub-steps (the issue's
 * "within 10% of the rigid value", a rigid beam's drop being 0, read against its length)
 * and 2% at 8. Soft welds bend as their angular hertz says: one plank on an angular spring
 * of 4 Hz sags m g d / (I (2 pi f)^2) within 10%. */
static void test_weld_cantilever_and_soft_weld(void)
{
    float four = cantilever_drop(4), eight = cantilever_drop(8);
    KG_CHECK(four < 0.10f);
    KG_CHECK(eight < 0.02f);
    kg_world* w = NULL;
    kg_body_state st;

    /* one soft weld */
    w = joint_world(1, 0);
    kg_body b = add_body(w, (kg_vec2){0.5f, 5.0f}, kg_box_shape(1.0f, 0.1f), 1.0f);
    kg_weld_joint_def def = kg_default_weld_joint_def();
    def.base.body_b = b;
    def.local_anchor_a = (kg_vec2){0.0f, 5.0f};
    def.local_anchor_b = (kg_vec2){-0.5f, 0.0f};
    def.angular_hertz = 4.0f;
    def.angular_damping_ratio = 1.0f;
    kg_joint j = KG_NULL_JOINT_INIT;
    KG_CHECK_OK(kg_create_weld_joint(w, &def, &j));
    for (int s = 0; s < 300; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_mass_data md;
    KG_CHECK_OK(kg_body_get_mass_data(w, b, &md));
    KG_CHECK_OK(kg_body_get_state(w, b, &st));
    double k = md.inertia * pow(2.0 * PI_D * 4.0, 2.0);
    /* the spring's torque k theta holds the weight's about the anchor, m g d cos(theta) */
    double expected = 0.0;
    for (int it = 0; it < 50; ++it) {
        expected = md.mass * 10.0 * 0.5 * cos(expected) / k;
    }
    measured("measured: soft weld (4 Hz) sags %.5f rad against %.5f (%.2f%%)\n", (double)-st.angle, expected,
             100.0 * (-st.angle - expected) / expected);
    KG_CHECK_NEAR(-st.angle, expected, 0.1 * expected);
    kg_destroy_world(w);
}

/* A mouse joint drags a 1 kg box to its target; a weak one (max force 2 N) never pulls
 * harder than that. */
static void test_mouse_joint_drags_to_target(void)
{
    kg_world* w = joint_world(1, 0);
    KG_CHECK_OK(kg_world_set_gravity(w, (kg_vec2){0.0f, 0.0f}));
    kg_body_def bd = kg_default_body_def();
    bd.shape = kg_box_shape(0.5f, 0.5f);
    bd.mass = 1.0f;
    kg_body box = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &box));
    kg_mouse_joint_def def = kg_default_mouse_joint_def();
    def.base.body_b = box;
    def.target = (kg_vec2){3.0f, 2.0f};
    def.max_force = 1000.0f;
    kg_joint j = KG_NULL_JOINT_INIT;
    KG_CHECK_OK(kg_create_mouse_joint(w, &def, &j));
    for (int s = 0; s < 180; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_vec2 p = position_of(w, box);
    double off = sqrt((double)(p.x - 3.0f) * (p.x - 3.0f) + (double)(p.y - 2.0f) * (p.y - 2.0f));
    measured("measured: mouse joint: box %.4g m from its target after 3 s\n", off);
    KG_CHECK(off < 0.01);
    KG_CHECK_OK(kg_mouse_joint_set_target(w, j, (kg_vec2){-10.0f, 2.0f}));
    KG_CHECK_OK(kg_mouse_joint_set_max_force(w, j, 2.0f));
    float most = 0.0f;
    for (int s = 0; s < 60; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_vec2 f;
        float t;
        KG_CHECK_OK(kg_joint_get_reaction(w, j, &f, &t));
        most = fmaxf(most, sqrtf(f.x * f.x + f.y * f.y));
    }
    kg_vec2 v;
    KG_CHECK_OK(kg_body_get_velocity(w, box, &v));
    measured("measured: weak mouse joint (2 N): its largest force %.5f N, the box at %.4f m/s after 1 s\n",
             (double)most, (double)sqrtf(v.x * v.x + v.y * v.y));
    KG_CHECK(most <= 2.0f * 1.0001f);
    KG_CHECK(sqrtf(v.x * v.x + v.y * v.y) < 2.0f * 1.01f);
    kg_destroy_world(w);
}

/* Two overlapping boxes joined by a hinge do not collide; with collide_connected they do
 * (on each backend). */
static void test_collide_connected(void)
{
    for (int k = 0; k < 2 * backend_count(); ++k) {
        int connected = k % 2;
        kg_world* w = backend_world(kBackends[k / 2], 0);
        KG_CHECK_OK(kg_world_set_gravity(w, (kg_vec2){0.0f, 0.0f}));
        kg_body a = add_body(w, (kg_vec2){0.0f, 0.0f}, kg_box_shape(1.0f, 0.2f), 1.0f);
        kg_body b = add_body(w, (kg_vec2){0.8f, 0.0f}, kg_box_shape(1.0f, 0.2f), 1.0f);
        kg_body c = add_body(w, (kg_vec2){-0.8f, 0.0f}, kg_box_shape(1.0f, 0.2f), 1.0f); /* touches a: not joined */
        kg_revolute_joint_def def = kg_default_revolute_joint_def();
        def.base.collide_connected = connected;
        hinge(w, a, b, (kg_vec2){0.4f, 0.0f}, &def);
        KG_CHECK_OK(kg_world_step(w, DT));
        int contacts = kg_world_contact_count(w);
        measured("measured: %s, collide_connected %d: %d contacts (a-c always, a-b only when connected)\n",
                 k / 2 ? "OpenCL" : "CPU", connected, contacts);
        KG_CHECK(contacts == 1 + connected);
        (void)c;
        kg_destroy_world(w);
    }
}

/* Bodies joined by a joint sleep as one island and wake as one (on each backend). */
static void test_joined_bodies_sleep_and_wake_together(void)
{
    for (int backend = 0; backend < backend_count(); ++backend) {
        kg_world* w = backend_world(kBackends[backend], 1);
        kg_body ground = KG_NULL_BODY_INIT;
        {
            kg_body_def def = kg_default_body_def();
            def.type = KG_BODY_STATIC;
            def.shape = kg_box_shape(20.0f, 1.0f);
            KG_CHECK_OK(kg_create_body(w, &def, &ground));
        }
        kg_body a = add_body(w, (kg_vec2){0.0f, 0.75f}, kg_box_shape(0.5f, 0.5f), 1.0f);
        kg_body b = add_body(w, (kg_vec2){3.0f, 0.75f}, kg_box_shape(0.5f, 0.5f), 1.0f);
        kg_distance_joint_def def = kg_default_distance_joint_def();
        def.base.body_a = a;
        def.base.body_b = b;
        def.length = 3.0f;
        kg_joint j = KG_NULL_JOINT_INIT;
        KG_CHECK_OK(kg_create_distance_joint(w, &def, &j));
        int asleep_at = -1;
        for (int s = 0; s < 120 && asleep_at < 0; ++s) {
            KG_CHECK_OK(kg_world_step(w, DT));
            KG_CHECK(kg_body_is_awake(w, a) == kg_body_is_awake(w, b));
            if (!kg_body_is_awake(w, a)) {
                asleep_at = s;
            }
        }
        KG_CHECK(asleep_at > 0);
        KG_CHECK_OK(kg_body_set_velocity(w, a, (kg_vec2){1.0f, 0.0f}));
        KG_CHECK_OK(kg_world_step(w, DT));
        measured("measured: %s: joined boxes asleep together at step %d; after a's push: a awake %d, b awake %d\n",
                 backend ? "OpenCL" : "CPU", asleep_at, kg_body_is_awake(w, a), kg_body_is_awake(w, b));
        KG_CHECK(kg_body_is_awake(w, a) && kg_body_is_awake(w, b));
        kg_destroy_world(w);
    }
}

/* A scene of every kind: a chain, a rope, welded planks, a motor, a mouse joint, boxes
 * falling on them; its bits after 240 steps on 1 and 4 threads. */
static void joint_scene(kg_world* w)
{
    kg_body_def gd = kg_default_body_def();
    gd.type = KG_BODY_STATIC;
    gd.shape = kg_box_shape(40.0f, 1.0f);
    kg_body ground = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &gd, &ground));
    kg_body prev = null_body();
    for (int i = 0; i < 12; ++i) {
        kg_body b = add_body(w, (kg_vec2){-5.0f + (i + 0.5f) * 0.8f, 8.0f}, kg_box_shape(0.8f, 0.1f), 1.0f);
        hinge(w, prev, b, (kg_vec2){-5.0f + i * 0.8f, 8.0f}, NULL);
        prev = b;
    }
    kg_body wheel = add_body(w, (kg_vec2){6.0f, 3.0f}, kg_circle_shape(0.6f), 1.0f);
    kg_revolute_joint_def md = kg_default_revolute_joint_def();
    md.enable_motor = 1;
    md.motor_speed = -3.0f;
    md.max_motor_torque = 50.0f;
    hinge(w, ground, wheel, (kg_vec2){6.0f, 3.0f}, &md);
    kg_body weld_prev = ground;
    for (int i = 0; i < 5; ++i) {
        kg_body b = add_body(w, (kg_vec2){10.0f + (i + 0.5f) * 0.6f, 4.0f}, kg_box_shape(0.6f, 0.15f), 1.0f);
        kg_weld_joint_def wd = kg_default_weld_joint_def();
        wd.base.body_a = weld_prev;
        wd.base.body_b = b;
        wd.angular_hertz = i == 2 ? 3.0f : 0.0f;
        kg_vec2 at = {10.0f + i * 0.6f, 4.0f};
        KG_CHECK_OK(kg_joint_local_point(w, weld_prev, at, &wd.local_anchor_a));
        KG_CHECK_OK(kg_joint_local_point(w, b, at, &wd.local_anchor_b));
        KG_CHECK_OK(kg_create_weld_joint(w, &wd, NULL));
        weld_prev = b;
    }
    kg_body ball = add_body(w, (kg_vec2){-8.0f, 6.0f}, kg_circle_shape(0.3f), 2.0f);
    kg_distance_joint_def rope = kg_default_distance_joint_def();
    rope.base.body_b = ball;
    rope.local_anchor_a = (kg_vec2){-10.0f, 9.0f};
    rope.enable_spring = 1;
    rope.enable_limit = 1;
    rope.max_length = 3.5f;
    rope.length = 3.5f;
    KG_CHECK_OK(kg_create_distance_joint(w, &rope, NULL));
    kg_body dragged = add_body(w, (kg_vec2){2.0f, 1.0f}, kg_box_shape(0.5f, 0.5f), 1.0f);
    kg_mouse_joint_def mouse = kg_default_mouse_joint_def();
    mouse.base.body_b = dragged;
    mouse.target = (kg_vec2){2.0f, 5.0f};
    KG_CHECK_OK(kg_create_mouse_joint(w, &mouse, NULL));
    kg_body cart = add_body(w, (kg_vec2){14.0f, 1.0f}, kg_box_shape(2.0f, 0.4f), 1.0f);
    kg_prismatic_joint_def pd = kg_default_prismatic_joint_def();
    pd.base.body_a = ground;
    pd.base.body_b = cart;
    KG_CHECK_OK(kg_joint_local_point(w, ground, (kg_vec2){14.0f, 1.0f}, &pd.local_anchor_a));
    pd.enable_motor = 1;
    pd.motor_speed = 1.0f;
    pd.max_motor_force = 30.0f;
    pd.enable_limit = 1;
    KG_CHECK_OK(kg_create_prismatic_joint(w, &pd, NULL));
    kg_body tyre = add_body(w, (kg_vec2){14.8f, 0.6f}, kg_circle_shape(0.25f), 1.0f);
    kg_wheel_joint_def wh = kg_default_wheel_joint_def();
    wh.base.body_a = cart;
    wh.base.body_b = tyre;
    KG_CHECK_OK(kg_joint_local_point(w, cart, (kg_vec2){14.8f, 0.6f}, &wh.local_anchor_a));
    wh.enable_motor = 1;
    wh.motor_speed = -4.0f;
    wh.max_motor_torque = 5.0f;
    KG_CHECK_OK(kg_create_wheel_joint(w, &wh, NULL));
    kg_body puppet = add_body(w, (kg_vec2){-12.0f, 3.0f}, kg_box_shape(0.5f, 0.5f), 1.0f);
    kg_motor_joint_def mo = kg_default_motor_joint_def();
    mo.base.body_b = puppet;
    mo.linear_offset = (kg_vec2){-12.0f, 5.0f};
    mo.angular_offset = 1.0f;
    mo.max_force = 40.0f;
    mo.max_torque = 5.0f;
    KG_CHECK_OK(kg_create_motor_joint(w, &mo, NULL));
    /* a hanging net of 16 x 16 balls, each hinged to its upper and left neighbours (the
     * top row to the world): colours of some 120 joints, split across threads and lanes;
     * the left hinges mix the options (none, a limit, a spring, all three), so that lanes
     * side by side take different ones */
    kg_body net[16][16];
    for (int r = 0; r < 16; ++r) {
        for (int c = 0; c < 16; ++c) {
            kg_vec2 at = {20.0f + 0.5f * (float)c, 12.0f - 0.5f * (float)r};
            net[r][c] = add_body(w, at, kg_circle_shape(0.15f), 1.0f);
            hinge(w, r > 0 ? net[r - 1][c] : null_body(), net[r][c], (kg_vec2){at.x, at.y + 0.25f}, NULL);
            kg_revolute_joint_def left = kg_default_revolute_joint_def();
            int options = (r + c) % 4;
            left.enable_limit = options == 1 || options == 3;
            left.lower_angle = -0.2f;
            left.upper_angle = 0.2f;
            left.enable_spring = options >= 2;
            left.hertz = 3.0f;
            left.damping_ratio = 0.3f;
            left.enable_motor = options == 3;
            left.motor_speed = 0.5f;
            left.max_motor_torque = 2.0f;
            if (c > 0) {
                hinge(w, net[r][c - 1], net[r][c], (kg_vec2){at.x - 0.25f, at.y}, &left);
            }
        }
    }
    for (int i = 0; i < 30; ++i) {
        add_body(w, (kg_vec2){-6.0f + 0.7f * (float)(i % 20), 11.0f + 0.8f * (float)(i / 20)}, kg_box_shape(0.4f, 0.4f),
                 1.0f);
    }
    /* a hub of 14 hinged spokes: more joints on one body than there are colours, so the
     * last two are the overflow's, solved serially */
    kg_body hub = add_body(w, (kg_vec2){-16.0f, 4.0f}, kg_circle_shape(0.5f), 1.0f);
    for (int k = 0; k < KG_JOINT_COLORS + 2; ++k) {
        float angle = 6.2831853f * (float)k / (float)(KG_JOINT_COLORS + 2);
        kg_vec2 dir = {cosf(angle), sinf(angle)};
        kg_body spoke = add_body(w, (kg_vec2){-16.0f + 1.2f * dir.x, 4.0f + 1.2f * dir.y}, kg_circle_shape(0.15f), 1.0f);
        hinge(w, hub, spoke, (kg_vec2){-16.0f + 0.6f * dir.x, 4.0f + 0.6f * dir.y}, NULL);
    }
    int color_start[KG_JOINT_COLORS + 2];
    kg_joints_order(w, color_start);
    KG_CHECK(color_start[KG_JOINT_COLORS + 1] - color_start[KG_JOINT_COLORS] == 2);
}

/* The scene stepped on backend with threads threads, the CPU's lanes width wide (0: the
 * widest this CPU runs). */
static void run_joint_scene_wide(kg_backend backend, int threads, int width, int steps, kg_body_state* out,
                                 int* count)
{
    kg_world_def def = kg_default_world_def();
    def.backend = backend;
    def.device_index = kg_test_opencl_device();
    def.threads = threads;
    char forced[8];
    snprintf(forced, sizeof forced, "%d", width);
    if (width > 0) {
        setenv("KGYRO_SIMD_WIDTH", forced, 1); /* read when the world is made */
    }
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    unsetenv("KGYRO_SIMD_WIDTH");
    KG_CHECK(kg_world_backend(w) == backend);
    joint_scene(w);
    for (int s = 0; s < steps; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_body bodies[512];
    KG_CHECK_OK(kg_world_get_bodies(w, bodies, 512, count));
    KG_CHECK_OK(kg_world_get_body_states(w, bodies, *count, out));
    kg_destroy_world(w);
}

static void run_joint_scene_on(kg_backend backend, int threads, int steps, kg_body_state* out, int* count)
{
    run_joint_scene_wide(backend, threads, 0, steps, out, count);
}

static void run_joint_scene(int threads, kg_body_state* out, int* count)
{
    run_joint_scene_on(KG_BACKEND_CPU, threads, 240, out, count);
}

static void test_bitwise_equal_on_1_and_4_threads(void)
{
    kg_body_state one[512], four[512];
    int n1 = 0, n4 = 0;
    run_joint_scene(1, one, &n1);
    run_joint_scene(4, four, &n4);
    int same = n1 == n4 && memcmp(one, four, (size_t)n1 * sizeof one[0]) == 0;
    int finite = 1;
    for (int i = 0; i < n1; ++i) {
        finite &= isfinite(one[i].position.x) && isfinite(one[i].position.y);
    }
    measured("measured: joint scene of %d bodies after 4 s: 1 and 4 threads %s\n", n1,
             same ? "bitwise equal" : "DIFFER");
    KG_CHECK(same);
    KG_CHECK(finite);
}

/* The revolute joints solved 1, 4, 8 and 16 at a time (KGYRO_SIMD_WIDTH; 8 and 16 where
 * the CPU has AVX2 and AVX-512), on 1 and 4 threads: the same bits. */
static void test_bitwise_equal_at_every_width(void)
{
    kg_body_state one[512], wide[512];
    int n1 = 0, n = 0;
    run_joint_scene_wide(KG_BACKEND_CPU, 1, 1, 240, one, &n1);
    static const int widths[] = {1, 4, 8, 16};
    for (int k = 0; k < 4; ++k) {
        for (int threads = 1; threads <= 4; threads += 3) {
            if (!kg_contact_rows_of(widths[k])) {
                measured("measured: joint scene: %d lanes not run here (the CPU lacks them)\n", widths[k]);
                break;
            }
            run_joint_scene_wide(KG_BACKEND_CPU, threads, widths[k], 240, wide, &n);
            int same = n1 == n && memcmp(one, wide, (size_t)n1 * sizeof one[0]) == 0;
            measured("measured: joint scene of %d bodies after 4 s: %d lanes on %d threads %s 1 lane on 1\n", n,
                     widths[k], threads, same ? "bitwise equal to" : "DIFFER from");
            KG_CHECK(same);
        }
    }
}

/* The OpenCL backend solves the same scene (sleeping on: the device's islands and wake
 * with the joints' links; collide_connected on the device's pairs) to the same bits as
 * the CPU on PoCL, step after step. */
static void test_cpu_and_opencl_bitwise_equal(void)
{
    int bitwise = 0;
    if (!kg_test_opencl_ready(&bitwise)) {
        return;
    }
    kg_body_state cpu[512], cl[512];
    int n_cpu = 0, n_cl = 0, first_differing = -1, steps[] = {1, 30, 120, 240};
    for (int k = 0; k < 4; ++k) {
        run_joint_scene_on(KG_BACKEND_CPU, 1, steps[k], cpu, &n_cpu);
        run_joint_scene_on(KG_BACKEND_OPENCL, 1, steps[k], cl, &n_cl);
        int same = n_cpu == n_cl && memcmp(cpu, cl, (size_t)n_cpu * sizeof cpu[0]) == 0;
        if (!same && first_differing < 0) {
            first_differing = steps[k];
        }
    }
    double worst = 0.0;
    for (int i = 0; i < n_cpu && i < n_cl; ++i) {
        worst = fmax(worst, fabs((double)cpu[i].position.x - cl[i].position.x));
        worst = fmax(worst, fabs((double)cpu[i].position.y - cl[i].position.y));
    }
    measured("measured: joint scene of %d bodies, CPU against OpenCL (%s): %s after 1, 30, 120 and 240 steps "
             "(largest position difference at 240: %.3g m)\n",
             n_cpu, bitwise ? "bitwise expected" : "no correctly rounded divide: close expected",
             first_differing < 0 ? "bitwise equal" : "DIFFER", worst);
    KG_CHECK(n_cpu == n_cl);
    if (bitwise) {
        KG_CHECK(first_differing < 0);
    } else {
        KG_CHECK(worst < 0.01);
    }
    /* the islands and the colours in rounds over the whole device, and the joints' passes
     * in one work-group of 64 work-items, as a GPU runs them */
    setenv("KGYRO_CL_ISLAND_GROUP_MAX", "16", 1);
    setenv("KGYRO_CL_COLOR_SERIAL_MAX", "16", 1);
    setenv("KGYRO_CL_JOINT_GROUP_SIZE", "64", 1);
    run_joint_scene_on(KG_BACKEND_CPU, 1, 240, cpu, &n_cpu);
    run_joint_scene_on(KG_BACKEND_OPENCL, 1, 240, cl, &n_cl);
    unsetenv("KGYRO_CL_ISLAND_GROUP_MAX");
    unsetenv("KGYRO_CL_COLOR_SERIAL_MAX");
    unsetenv("KGYRO_CL_JOINT_GROUP_SIZE");
    int same = n_cpu == n_cl && memcmp(cpu, cl, (size_t)n_cpu * sizeof cpu[0]) == 0;
    measured("measured: the same with the device's islands and colours in rounds, the joints in a group of 64: %s "
             "after 240 steps\n",
             same ? "bitwise equal" : "DIFFER");
    KG_CHECK(same || !bitwise);
    /* the joints' passes a launch per colour and iteration, as a GPU runs thousands */
    setenv("KGYRO_CL_JOINT_GROUP_MAX", "16", 1);
    run_joint_scene_on(KG_BACKEND_OPENCL, 1, 240, cl, &n_cl);
    unsetenv("KGYRO_CL_JOINT_GROUP_MAX");
    same = n_cpu == n_cl && memcmp(cpu, cl, (size_t)n_cpu * sizeof cpu[0]) == 0;
    measured("measured: the same with a launch per joint colour: %s after 240 steps\n",
             same ? "bitwise equal" : "DIFFER");
    KG_CHECK(same || !bitwise);
    /* a device failure inside a step hands the world to the CPU, which redoes the step
     * from its start: the joints' rows on the host are that start (cl_joint.c) */
    const char* faults[] = {"enqueue:300", "enqueue:2500", "enqueue:9000", "read:40"};
    run_joint_scene_on(KG_BACKEND_CPU, 1, 240, cpu, &n_cpu);
    for (int f = 0; f < 4; ++f) {
        setenv("KGYRO_CL_FAIL", faults[f], 1);
        kg_world_def def = kg_default_world_def();
        def.backend = KG_BACKEND_OPENCL;
        def.device_index = kg_test_opencl_device();
        kg_world* w = NULL;
        KG_CHECK_OK(kg_create_world(&def, &w));
        unsetenv("KGYRO_CL_FAIL");
        joint_scene(w);
        int fell_at = -1;
        for (int s = 0; s < 240; ++s) {
            KG_CHECK_OK(kg_world_step(w, DT));
            if (fell_at < 0 && kg_world_backend(w) == KG_BACKEND_CPU) {
                fell_at = s;
            }
        }
        kg_body bodies[512];
        KG_CHECK_OK(kg_world_get_bodies(w, bodies, 512, &n_cl));
        KG_CHECK_OK(kg_world_get_body_states(w, bodies, n_cl, cl));
        kg_destroy_world(w);
        same = n_cpu == n_cl && memcmp(cpu, cl, (size_t)n_cpu * sizeof cpu[0]) == 0;
        measured("measured: KGYRO_CL_FAIL=%s: fell back to the CPU in step %d, after 240 steps %s the CPU's\n",
                 faults[f], fell_at, same ? "bitwise equal to" : "DIFFERENT from");
        KG_CHECK(same || !bitwise);
    }
}

/* Bad input is refused with a clear error and changes nothing. */
static void test_bad_input(void)
{
    kg_world* w = joint_world(1, 0);
    kg_world* other = joint_world(1, 0);
    kg_body a = add_body(w, (kg_vec2){0.0f, 0.0f}, kg_circle_shape(0.5f), 1.0f);
    kg_body b = add_body(w, (kg_vec2){1.0f, 0.0f}, kg_circle_shape(0.5f), 1.0f);
    kg_body foreign = add_body(other, (kg_vec2){1.0f, 0.0f}, kg_circle_shape(0.5f), 1.0f);
    kg_revolute_joint_def def = kg_default_revolute_joint_def();
    kg_joint j = KG_NULL_JOINT_INIT;
    def.base.body_a = a;
    def.base.body_b = a;
    KG_CHECK(kg_create_revolute_joint(w, &def, &j) == KG_ERROR_INVALID_ARGUMENT); /* a body and itself */
    def.base.body_b = foreign;
    KG_CHECK(kg_create_revolute_joint(w, &def, &j) == KG_ERROR_INVALID_HANDLE); /* another world's body */
    def.base.body_b = b;
    def.local_anchor_a.x = NAN;
    KG_CHECK(kg_create_revolute_joint(w, &def, &j) == KG_ERROR_INVALID_ARGUMENT);
    def.local_anchor_a.x = 0.0f;
    def.lower_angle = 1.0f;
    def.upper_angle = -1.0f;
    KG_CHECK(kg_create_revolute_joint(w, &def, &j) == KG_ERROR_INVALID_ARGUMENT);
    def.lower_angle = -1.0f;
    def.hertz = -1.0f;
    KG_CHECK(kg_create_revolute_joint(w, &def, &j) == KG_ERROR_INVALID_ARGUMENT);
    def.hertz = 0.0f;
    KG_CHECK(kg_create_revolute_joint(w, NULL, &j) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_joint_count(w) == 0);
    KG_CHECK(kg_world_set_joint_iterations(w, 0) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_set_joint_iterations(w, 65) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_get_joint_iterations(w) == 6);
    kg_distance_joint_def dd = kg_default_distance_joint_def();
    dd.base.body_b = b;
    dd.length = 0.0f;
    KG_CHECK(kg_create_distance_joint(w, &dd, &j) == KG_ERROR_INVALID_ARGUMENT);
    dd.length = 1.0f;
    dd.min_length = 2.0f;
    dd.max_length = 1.0f;
    KG_CHECK(kg_create_distance_joint(w, &dd, &j) == KG_ERROR_INVALID_ARGUMENT);
    kg_mouse_joint_def mj = kg_default_mouse_joint_def();
    mj.base.body_b = b;
    mj.target.y = INFINITY;
    KG_CHECK(kg_create_mouse_joint(w, &mj, &j) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_joint_count(w) == 0);

    /* a live joint, then a foreign, a wrong-type and a stale handle */
    KG_CHECK_OK(kg_create_revolute_joint(w, &def, &j));
    KG_CHECK(kg_joint_is_valid(w, j));
    KG_CHECK(!kg_joint_is_valid(other, j));
    KG_CHECK(kg_destroy_joint(other, j) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK(kg_distance_joint_set_length(w, j, 2.0f) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_revolute_joint_set_limits(w, j, 1, NAN, 1.0f) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK_OK(kg_revolute_joint_set_limits(w, j, 1, -0.5f, 0.5f));
    kg_joint none = KG_NULL_JOINT_INIT;
    KG_CHECK(kg_destroy_joint(w, none) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK_OK(kg_world_step(w, DT));

    /* a destroyed body takes its joint with it, and the next step says so */
    int tag = 7;
    KG_CHECK_OK(kg_joint_set_user_data(w, j, &tag));
    KG_CHECK_OK(kg_destroy_body(w, a));
    KG_CHECK(!kg_joint_is_valid(w, j));
    KG_CHECK(kg_world_joint_count(w) == 0);
    kg_vec2 f;
    float t;
    KG_CHECK(kg_joint_get_reaction(w, j, &f, &t) == KG_ERROR_INVALID_HANDLE);
    def.base.body_a = a; /* now dead */
    KG_CHECK(kg_create_revolute_joint(w, &def, &j) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK_OK(kg_world_step(w, DT));
    kg_joint_events ev = kg_world_get_joint_events(w);
    measured("measured: after destroying a body: %d joint event(s), kind %d, user data %s\n", ev.count,
             ev.count > 0 ? (int)ev.events[0].kind : -1, ev.count > 0 && ev.events[0].user_data == &tag ? "kept" : "lost");
    KG_CHECK(ev.count == 1 && ev.events[0].kind == KG_JOINT_EVENT_BODY_DESTROYED && ev.events[0].user_data == &tag &&
             kg_test_same_body(ev.events[0].body, a));
    KG_CHECK_OK(kg_world_step(w, DT));
    KG_CHECK(kg_world_get_joint_events(w).count == 0);
    kg_destroy_world(other);
    kg_destroy_world(w);
}

/* A scene file's "joints": every kind made when instantiated, a pendulum from the file
 * swinging as the API's does; a wrong entry refused with its JSON path. */
static void test_scene_joints(void)
{
    const char* json = "{\"gravity\": [0, -10], \"bodies\": ["
                       "{\"name\": \"bob\", \"position\": [2, 10], \"shape\": {\"type\": \"circle\", \"radius\": 0.1}},"
                       "{\"name\": \"p1\", \"position\": [5, 5], \"shape\": {\"type\": \"box\", \"width\": 1, \"height\": 0.2}},"
                       "{\"name\": \"p2\", \"position\": [6, 5], \"shape\": {\"type\": \"box\", \"width\": 1, \"height\": 0.2}},"
                       "{\"name\": \"ball\", \"position\": [-5, 5], \"shape\": {\"type\": \"circle\", \"radius\": 0.2}},"
                       "{\"name\": \"car\", \"position\": [10, 5], \"shape\": {\"type\": \"box\", \"width\": 2, \"height\": 0.4}},"
                       "{\"name\": \"tyre\", \"position\": [10.8, 4.5], \"shape\": {\"type\": \"circle\", \"radius\": 0.3}},"
                       "{\"name\": \"crate\", \"position\": [15, 5], \"angle\": 0.3, \"shape\": {\"type\": \"box\", \"width\": 0.5, \"height\": 0.5}}],"
                       "\"joints\": ["
                       "{\"type\": \"revolute\", \"b\": \"bob\", \"anchor\": [0, 10], \"enable_motor\": false},"
                       "{\"type\": \"weld\", \"b\": \"p1\", \"anchor\": [4.5, 5]},"
                       "{\"type\": \"weld\", \"a\": \"p1\", \"b\": \"p2\", \"anchor\": [5.5, 5], \"angular_hertz\": 5},"
                       "{\"type\": \"distance\", \"b\": \"ball\", \"anchor_a\": [-5, 8], \"anchor_b\": [-5, 5.2],"
                       " \"enable_spring\": true, \"hertz\": 2, \"damping_ratio\": 0.1},"
                       "{\"type\": \"mouse\", \"b\": \"ball\", \"target\": [-4, 5], \"max_force\": 50},"
                       "{\"type\": \"prismatic\", \"b\": \"car\", \"anchor\": [10, 5], \"axis\": [1, 0],"
                       " \"enable_limit\": true, \"lower_translation\": -1, \"upper_translation\": 1},"
                       "{\"type\": \"wheel\", \"a\": \"car\", \"b\": \"tyre\", \"anchor\": [10.8, 4.5], \"axis\": [0, 1],"
                       " \"enable_motor\": true, \"motor_speed\": -5, \"max_motor_torque\": 10, \"hertz\": 4},"
                       "{\"type\": \"motor\", \"b\": \"crate\", \"max_force\": 100, \"max_torque\": 100}]}";
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_parse(json, strlen(json), "joints.json", &scene));
    KG_CHECK(kg_scene_joint_count(scene) == 8);
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    def.enable_sleep = 0;
    kg_world* w = NULL;
    kg_body handles[7];
    KG_CHECK_OK(kg_scene_instantiate(scene, &def, &w, handles));
    KG_CHECK(kg_world_joint_count(w) == 8);
    for (int s = 0; s < 120; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_vec2 p = position_of(w, handles[0]);
    double len = sqrt((double)p.x * p.x + (double)(p.y - 10.0f) * (p.y - 10.0f));
    kg_body_state crate;
    KG_CHECK_OK(kg_body_get_state(w, handles[6], &crate));
    float spin = 0.0f;
    KG_CHECK_OK(kg_body_get_angular_velocity(w, handles[5], &spin));
    measured("measured: scene pendulum length %.5f m after 2 s (2 m), weld tip at y %.4f, tyre spinning at %.3f "
             "rad/s (motor -5), crate held at (%.4f, %.4f) turned %.4f (the motor joint's start pose)\n",
             len, (double)position_of(w, handles[2]).y, (double)spin, (double)crate.position.x,
             (double)crate.position.y, (double)crate.angle);
    KG_CHECK_NEAR(len, 2.0, 0.001);
    KG_CHECK_NEAR(spin, -5.0f, 0.1f);
    KG_CHECK_NEAR(crate.position.x, 15.0f, 0.01f);
    KG_CHECK_NEAR(crate.angle, 0.3f, 0.01f);
    kg_destroy_world(w);
    kg_scene_destroy(scene);

    const char* bad[] = {
        "{\"bodies\": [{\"name\": \"x\", \"shape\": {\"type\": \"circle\", \"radius\": 1}}], \"joints\": [{\"type\": \"hinge\", \"b\": \"x\"}]}",
        "{\"bodies\": [{\"name\": \"x\", \"shape\": {\"type\": \"circle\", \"radius\": 1}}], \"joints\": [{\"type\": \"revolute\", \"b\": \"y\", \"anchor\": [0, 0]}]}",
        "{\"bodies\": [{\"name\": \"x\", \"shape\": {\"type\": \"circle\", \"radius\": 1}}], \"joints\": [{\"type\": \"revolute\", \"b\": \"x\"}]}",
        "{\"bodies\": [{\"name\": \"x\", \"shape\": {\"type\": \"circle\", \"radius\": 1}}], \"joints\": [{\"type\": \"revolute\", \"b\": \"x\", \"anchor\": [0, 0], \"hertz\": -1}]}",
        "{\"bodies\": [{\"name\": \"x\", \"shape\": {\"type\": \"circle\", \"radius\": 1}}], \"joints\": [{\"type\": \"weld\", \"a\": \"x\", \"b\": \"x\", \"anchor\": [0, 0]}]}",
        "{\"bodies\": [{\"name\": \"x\", \"shape\": {\"type\": \"circle\", \"radius\": 1}}], \"joints\": [{\"type\": \"distance\", \"b\": \"x\", \"anchor_a\": [0, 0], \"anchor_b\": [0, 1], \"spring\": 1}]}",
        "{\"bodies\": [{\"name\": \"x\", \"shape\": {\"type\": \"circle\", \"radius\": 1}}], \"joints\": [{\"type\": \"prismatic\", \"b\": \"x\", \"anchor\": [0, 0], \"axis\": [0, 0]}]}",
        "{\"bodies\": [{\"name\": \"x\", \"shape\": {\"type\": \"circle\", \"radius\": 1}}], \"joints\": [{\"type\": \"revolute\", \"b\": \"x\", \"anchor\": [0, 0], \"lower_angle\": -4}]}",
        "{\"bodies\": [{\"name\": \"x\", \"shape\": {\"type\": \"circle\", \"radius\": 1}}], \"joints\": [{\"type\": \"distance\", \"b\": \"x\", \"anchor_a\": [1, 0], \"anchor_b\": [1, 0]}]}",
        "{\"bodies\": [{\"name\": \"x\", \"position\": [-3e38, 0], \"shape\": {\"type\": \"circle\", \"radius\": 1}}], \"joints\": [{\"type\": \"weld\", \"b\": \"x\", \"anchor\": [3e38, 0]}]}",
    };
    const char* paths[] = {"joints[0].type", "joints[0].b", "joints[0].anchor", "joints[0].hertz", "joints[0].b",
                           "joints[0].spring", "joints[0].axis", "joints[0]: angle limits", "joints[0].length",
                           "joints[0]: an anchor is too far"};
    for (int i = 0; i < (int)(sizeof bad / sizeof bad[0]); ++i) {
        kg_scene* sc = NULL;
        kg_result r = kg_scene_parse(bad[i], strlen(bad[i]), "bad.json", &sc);
        int names_path = strstr(kg_last_error(), paths[i]) != NULL;
        if (r != KG_ERROR_PARSE || !names_path) {
            fprintf(stderr, "bad scene %d: result %d, message \"%s\" (expected the path %s)\n", i, (int)r,
                    kg_last_error(), paths[i]);
        }
        KG_CHECK(r == KG_ERROR_PARSE && names_path);
        kg_scene_destroy(sc);
    }
    measured("measured: a bad joint entry is refused: \"%s\"\n", kg_last_error());
}

typedef struct drawn {
    int segments, points;
    kg_vec2 a, b;
} drawn;

static void draw_segment(kg_vec2 p1, kg_vec2 p2, kg_color color, void* context)
{
    drawn* d = context;
    if (color == KG_DEBUG_COLOR_JOINT) {
        d->segments += 1;
        d->a = p1;
        d->b = p2;
    }
}

static void draw_point(kg_vec2 p, float size, kg_color color, void* context)
{
    (void)p;
    (void)size;
    drawn* d = context;
    d->points += color == KG_DEBUG_COLOR_JOINT;
}

/* Debug draw shows a joint as a segment between its anchors, a dot at each. */
static void test_debug_draw_joints(void)
{
    kg_world* w = joint_world(1, 0);
    kg_body a = add_body(w, (kg_vec2){0.0f, 0.0f}, kg_circle_shape(0.2f), 1.0f);
    kg_body b = add_body(w, (kg_vec2){2.0f, 0.0f}, kg_circle_shape(0.2f), 1.0f);
    kg_distance_joint_def def = kg_default_distance_joint_def();
    def.base.body_a = a;
    def.base.body_b = b;
    def.length = 2.0f;
    KG_CHECK_OK(kg_create_distance_joint(w, &def, NULL));
    drawn d;
    memset(&d, 0, sizeof d);
    kg_debug_draw draw = kg_default_debug_draw();
    draw.draw_segment = draw_segment;
    draw.draw_point = draw_point;
    draw.context = &d;
    KG_CHECK_OK(kg_world_draw(w, &draw));
    measured("measured: debug draw: %d joint segment(s) from (%g, %g) to (%g, %g), %d anchor dots\n", d.segments,
             (double)d.a.x, (double)d.a.y, (double)d.b.x, (double)d.b.y, d.points);
    KG_CHECK(d.segments == 1 && d.points == 2 && d.a.x == 0.0f && d.b.x == 2.0f);
    draw.flags &= ~(unsigned)KG_DEBUG_DRAW_JOINTS;
    memset(&d, 0, sizeof d);
    KG_CHECK_OK(kg_world_draw(w, &draw));
    KG_CHECK(d.segments == 0);
    kg_destroy_world(w);
}

/* A 1 kg box on a vertical prismatic joint to the world, its range [-1, 1] m, falls to its
 * lower limit and is pushed into it by ten times its weight: it stays within 5 mm of its
 * range, on its axis, unturned. A motor along a level slider reaches 1 m/s within 2%
 * against a 20 N load and stalls at its 50 N against 100 N. */
static void test_prismatic_limits_and_motor(void)
{
    kg_world* w = joint_world(1, 0);
    kg_body_def bd = kg_default_body_def();
    bd.position = (kg_vec2){0.0f, 5.0f};
    bd.shape = kg_box_shape(0.5f, 0.5f);
    bd.mass = 1.0f;
    kg_body box = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &box));
    kg_prismatic_joint_def def = kg_default_prismatic_joint_def();
    def.base.body_b = box;
    def.local_anchor_a = (kg_vec2){0.0f, 5.0f};
    def.local_axis_a = (kg_vec2){0.0f, 1.0f};
    def.enable_limit = 1;
    def.lower_translation = -1.0f;
    def.upper_translation = 1.0f;
    kg_joint j = KG_NULL_JOINT_INIT;
    KG_CHECK_OK(kg_create_prismatic_joint(w, &def, &j));
    float lowest = 0.0f, translation = 0.0f, worst_x = 0.0f, worst_angle = 0.0f;
    for (int s = 0; s < 240; ++s) {
        if (s >= 60) {
            KG_CHECK_OK(kg_body_apply_force_to_center(w, box, (kg_vec2){0.0f, -100.0f}));
        }
        KG_CHECK_OK(kg_world_step(w, DT));
        KG_CHECK_OK(kg_joint_get_translation(w, j, &translation));
        lowest = fminf(lowest, translation);
        kg_body_state st;
        KG_CHECK_OK(kg_body_get_state(w, box, &st));
        worst_x = fmaxf(worst_x, fabsf(st.position.x));
        worst_angle = fmaxf(worst_angle, fabsf(st.angle));
    }
    measured("measured: prismatic slider at its lower limit (-1 m) under 11x its weight: lowest %.5f m (%.3f mm "
             "past), at the end %.5f; off its axis %.3g m, turned %.3g rad at most\n",
             (double)lowest, (double)(-1000.0f * (lowest + 1.0f)), (double)translation, (double)worst_x,
             (double)worst_angle);
    KG_CHECK(lowest > -1.005f);
    KG_CHECK(worst_x < 0.001f && worst_angle < 0.001f);
    kg_destroy_world(w);

    w = joint_world(1, 0);
    KG_CHECK_OK(kg_world_set_gravity(w, (kg_vec2){0.0f, 0.0f}));
    bd.position = (kg_vec2){0.0f, 0.0f};
    KG_CHECK_OK(kg_create_body(w, &bd, &box));
    def = kg_default_prismatic_joint_def();
    def.base.body_b = box;
    def.enable_motor = 1;
    def.motor_speed = 1.0f;
    def.max_motor_force = 50.0f;
    KG_CHECK_OK(kg_create_prismatic_joint(w, &def, &j));
    kg_vec2 v, f;
    float t;
    for (int s = 0; s < 60; ++s) {
        KG_CHECK_OK(kg_body_apply_force_to_center(w, box, (kg_vec2){-20.0f, 0.0f}));
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    KG_CHECK_OK(kg_body_get_velocity(w, box, &v));
    KG_CHECK_OK(kg_joint_get_reaction(w, j, &f, &t));
    measured("measured: prismatic motor at %.5f m/s (target 1) against 20 N, its force %.4f N\n", (double)v.x,
             (double)f.x);
    KG_CHECK_NEAR(v.x, 1.0f, 0.02f);
    KG_CHECK_NEAR(f.x, 20.0f, 0.4f);
    for (int s = 0; s < 60; ++s) {
        KG_CHECK_OK(kg_body_apply_force_to_center(w, box, (kg_vec2){-100.0f, 0.0f}));
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    KG_CHECK_OK(kg_body_get_velocity(w, box, &v));
    KG_CHECK_OK(kg_joint_get_reaction(w, j, &f, &t));
    measured("measured: prismatic motor stalled by 100 N: %.4f m/s, its force %.4f N (max 50)\n", (double)v.x,
             (double)f.x);
    KG_CHECK(v.x < 0.0f);
    KG_CHECK_NEAR(f.x, 50.0f, 1.0f);
    kg_destroy_world(w);
}

/* A wheel hung from the world on a suspension of 2 Hz (damping 0.02) bounces at 2 Hz
 * within 2%, and its motor spins it at 10 rad/s within 2%. */
static void test_wheel_suspension_and_motor(void)
{
    kg_world* w = joint_world(1, 0);
    kg_body_def bd = kg_default_body_def();
    bd.position = (kg_vec2){0.0f, 5.0f};
    bd.shape = kg_circle_shape(0.4f);
    bd.mass = 2.0f;
    kg_body wheel = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &wheel));
    kg_wheel_joint_def def = kg_default_wheel_joint_def();
    def.base.body_b = wheel;
    def.local_anchor_a = (kg_vec2){0.0f, 5.0f};
    def.hertz = 2.0f;
    def.damping_ratio = 0.02f;
    def.enable_motor = 1;
    def.motor_speed = 10.0f;
    def.max_motor_torque = 100.0f;
    kg_joint j = KG_NULL_JOINT_INIT;
    KG_CHECK_OK(kg_create_wheel_joint(w, &def, &j));
    crossings c = {0.0, 0.0, 0, 1.0};
    float worst_x = 0.0f;
    for (int s = 1; s <= 300; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_vec2 v;
        KG_CHECK_OK(kg_body_get_velocity(w, wheel, &v));
        crossing_sample(&c, s * DT, v.y);
        worst_x = fmaxf(worst_x, fabsf(position_of(w, wheel).x));
    }
    float omega = 0.0f;
    KG_CHECK_OK(kg_body_get_angular_velocity(w, wheel, &omega));
    double expected = 1.0 / (2.0 * sqrt(1.0 - 0.02 * 0.02));
    double period = crossing_period(&c);
    measured("measured: wheel suspension period %.5f s against %.5f (%.3f%%) over %d periods; off its axis %.3g m; "
             "motor at %.4f rad/s (target 10)\n",
             period, expected, 100.0 * (period - expected) / expected, c.count - 1, (double)worst_x, (double)omega);
    KG_CHECK(c.count >= 5);
    KG_CHECK_NEAR(period, expected, 0.02 * expected);
    KG_CHECK_NEAR(omega, 10.0f, 0.2f);
    KG_CHECK(worst_x < 0.001f);
    kg_destroy_world(w);
}

/* A motor joint drives a box to a pose relative to the world: (2, 3) turned 0.5 rad. */
static void test_motor_joint_drives_to_pose(void)
{
    kg_world* w = joint_world(1, 0);
    KG_CHECK_OK(kg_world_set_gravity(w, (kg_vec2){0.0f, 0.0f}));
    kg_body box = add_body(w, (kg_vec2){0.0f, 0.0f}, kg_box_shape(0.5f, 0.5f), 1.0f);
    kg_motor_joint_def def = kg_default_motor_joint_def();
    def.base.body_b = box;
    def.linear_offset = (kg_vec2){2.0f, 3.0f};
    def.angular_offset = 0.5f;
    def.max_force = 50.0f;
    def.max_torque = 20.0f;
    KG_CHECK_OK(kg_create_motor_joint(w, &def, NULL));
    for (int s = 0; s < 300; ++s) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_body_state st;
    KG_CHECK_OK(kg_body_get_state(w, box, &st));
    measured("measured: motor joint: box at (%.4f, %.4f) turned %.4f rad (target (2, 3), 0.5)\n",
             (double)st.position.x, (double)st.position.y, (double)st.angle);
    KG_CHECK_NEAR(st.position.x, 2.0f, 0.01f);
    KG_CHECK_NEAR(st.position.y, 3.0f, 0.01f);
    KG_CHECK_NEAR(st.angle, 0.5f, 0.01f);
    kg_destroy_world(w);
}

/* A breakable hinge holding a 10 kg disc to the world: a threshold below its weight
 * breaks it at the end of the first step (an event with the force that broke it), one
 * above holds; the threshold set later breaks it then. On each backend. */
static void test_breakable_joint(void)
{
    for (int backend = 0; backend < backend_count(); ++backend) {
        kg_world* w = backend_world(kBackends[backend], 0);
        kg_body_def bd = kg_default_body_def();
        bd.position = (kg_vec2){0.0f, 5.0f};
        bd.shape = kg_circle_shape(0.2f);
        bd.mass = 10.0f;
        kg_body heavy = KG_NULL_BODY_INIT, light = KG_NULL_BODY_INIT;
        KG_CHECK_OK(kg_create_body(w, &bd, &heavy));
        bd.position = (kg_vec2){3.0f, 5.0f};
        KG_CHECK_OK(kg_create_body(w, &bd, &light));
        kg_revolute_joint_def def = kg_default_revolute_joint_def();
        def.base.break_force = 50.0f; /* the weight is 100 N */
        kg_joint weak = hinge(w, null_body(), heavy, (kg_vec2){0.0f, 5.0f}, &def);
        def.base.break_force = 150.0f;
        kg_joint strong = hinge(w, null_body(), light, (kg_vec2){3.0f, 5.0f}, &def);
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_joint_events ev = kg_world_get_joint_events(w);
        measured("measured: %s: after one step %d joint(s) left, %d event(s): kind %d, force %.3f N (threshold 50)\n",
                 backend ? "OpenCL" : "CPU", kg_world_joint_count(w), ev.count, ev.count ? (int)ev.events[0].kind : -1,
                 ev.count ? (double)sqrtf(ev.events[0].force.x * ev.events[0].force.x +
                                          ev.events[0].force.y * ev.events[0].force.y)
                          : 0.0);
        KG_CHECK(!kg_joint_is_valid(w, weak) && kg_joint_is_valid(w, strong));
        KG_CHECK(ev.count == 1 && ev.events[0].kind == KG_JOINT_EVENT_BROKEN && ev.events[0].joint.index == weak.index);
        for (int s = 0; s < 30; ++s) {
            KG_CHECK_OK(kg_world_step(w, DT));
        }
        KG_CHECK(kg_joint_is_valid(w, strong));
        KG_CHECK(position_of(w, heavy).y < 4.0f); /* fell */
        KG_CHECK_OK(kg_joint_set_break_thresholds(w, strong, 0.0f, 0.0f));
        KG_CHECK_OK(kg_world_step(w, DT));
        KG_CHECK(kg_joint_is_valid(w, strong));
        KG_CHECK_OK(kg_joint_set_break_thresholds(w, strong, 99.0f, 0.0f));
        KG_CHECK_OK(kg_world_step(w, DT));
        KG_CHECK(!kg_joint_is_valid(w, strong) && kg_world_get_joint_events(w).count == 1);
        KG_CHECK(kg_joint_set_break_thresholds(w, strong, 1.0f, 0.0f) == KG_ERROR_INVALID_HANDLE);
        kg_destroy_world(w);
    }
}

KG_TEST_MAIN(KG_TEST(test_revolute_pendulum_period_length_energy), KG_TEST(test_hanging_chain_with_heavy_load),
             KG_TEST(test_revolute_motor_speed_and_stall), KG_TEST(test_revolute_door_limit_under_load),
             KG_TEST(test_distance_spring_frequency), KG_TEST(test_rope_never_overstretches),
             KG_TEST(test_weld_cantilever_and_soft_weld), KG_TEST(test_mouse_joint_drags_to_target),
             KG_TEST(test_collide_connected), KG_TEST(test_joined_bodies_sleep_and_wake_together),
             KG_TEST(test_bitwise_equal_on_1_and_4_threads), KG_TEST(test_bitwise_equal_at_every_width),
             KG_TEST(test_cpu_and_opencl_bitwise_equal),
             KG_TEST(test_bad_input), KG_TEST(test_scene_joints), KG_TEST(test_debug_draw_joints), KG_TEST(test_prismatic_limits_and_motor),
             KG_TEST(test_wheel_suspension_and_motor), KG_TEST(test_motor_joint_drives_to_pose), KG_TEST(test_breakable_joint))
