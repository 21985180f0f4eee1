/* Sleeping (kg_world_def.enable_sleep, sleep_speed 0.05 m/s, time_to_sleep 0.5 s), checked
 * as physics: a resting box falls asleep on time and then does not change by a bit; a
 * bouncing ball and a slowly sliding box stay awake; a sleeping stack wakes when a ball
 * lands on it, stands, and sleeps again; the API wakes what it changes (velocity, destroy,
 * gravity); a moving kinematic platform wakes what sleeps on it; enable_sleep = 0 never
 * sleeps; a scene of 400 sleeping boxes still answers a falling body; and the device's
 * islands (found by one work-group, run here as a group of one) are the CPU's.
 *
 * CPU backend, world defaults (gravity -10, 4 sub-steps) unless a test says otherwise,
 * dt = 1/60. Every test prints its measured numbers ("measured: ..."). */
#include "kg_test.h"
#include "kgyro/kgyro.h"
#include "solve/island.h" /* white box: the two ways of finding islands */

#include <math.h>
#include <string.h>
#include <time.h>

#define DT (1.0f / 60.0f)

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static kg_world* make_world(int enable_sleep)
{
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    def.enable_sleep = enable_sleep;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    return w;
}

static kg_body add(kg_world* w, kg_body_type type, kg_shape_def shape, kg_vec2 pos, float friction,
                   float restitution)
{
    kg_body_def bd = kg_default_body_def();
    bd.type = type;
    bd.shape = shape;
    bd.position = pos;
    bd.friction = friction;
    bd.restitution = restitution;
    kg_body b = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    return b;
}

/* Static ground 200 m wide, 1 m thick, its top face at y = 0. */
static kg_body add_ground(kg_world* w, float friction)
{
    return add(w, KG_BODY_STATIC, kg_box_shape(200.0f, 1.0f), (kg_vec2){0.0f, -0.5f}, friction, 0.0f);
}

static kg_body_state state_of(kg_world* w, kg_body b)
{
    kg_body_state s;
    memset(&s, 0, sizeof s);
    KG_CHECK_OK(kg_body_get_state(w, b, &s));
    return s;
}

static void step(kg_world* w) { KG_CHECK_OK(kg_world_step(w, DT)); }

static int awake_count(kg_world* w, const kg_body* bodies, int count)
{
    int n = 0;
    for (int i = 0; i < count; ++i) {
        n += kg_body_is_awake(w, bodies[i]);
    }
    return n;
}

/* Steps until asleep_count reaches target or max_steps pass; returns the steps taken, or
 * -1 if it never did. */
static int step_until_asleep(kg_world* w, int target, int max_steps)
{
    for (int s = 1; s <= max_steps; ++s) {
        step(w);
        if (kg_world_asleep_count(w) == target) {
            return s;
        }
    }
    return -1;
}

/* Whether the last step reported a contact with a point between a and b. */
static int touching(kg_world* w, kg_body a, kg_body b)
{
    int n = kg_world_contact_count(w);
    for (int i = 0; i < n; ++i) {
        kg_contact_info ci;
        memset(&ci, 0, sizeof ci);
        KG_CHECK_OK(kg_world_get_contact(w, i, &ci));
        int ab = ci.a.index == a.index && ci.b.index == b.index;
        int ba = ci.a.index == b.index && ci.b.index == a.index;
        if ((ab || ba) && ci.point_count > 0) {
            return 1;
        }
    }
    return 0;
}

/* A column of count 1 m boxes (density 1, friction 0.6) on the ground at x, touching. */
static void add_stack(kg_world* w, kg_body* out, int count, float x)
{
    for (int i = 0; i < count; ++i) {
        out[i] = add(w, KG_BODY_DYNAMIC, kg_box_shape(1.0f, 1.0f), (kg_vec2){x, 0.5f + (float)i}, 0.6f, 0.0f);
    }
}

/* ---- 1. a resting box falls asleep and stays bitwise still ------------------------------ */

static void test_resting_box_sleeps_on_time_and_is_frozen_bitwise(void)
{
    kg_world* w = make_world(1);
    add_ground(w, 0.6f);
    kg_body box = add(w, KG_BODY_DYNAMIC, kg_box_shape(1.0f, 1.0f), (kg_vec2){0.0f, 0.5f}, 0.6f, 0.0f);
    const float tts = kg_world_get_def(w)->time_to_sleep;
    int slept_at = -1;
    for (int s = 1; s <= 180 && slept_at < 0; ++s) {
        step(w);
        if (!kg_body_is_awake(w, box)) {
            slept_at = s;
        }
    }
    kg_body_state asleep = state_of(w, box);
    kg_aabb box_asleep;
    memset(&box_asleep, 0, sizeof box_asleep);
    KG_CHECK_OK(kg_body_get_aabb(w, box, &box_asleep));
    int changed_steps = 0, awake_steps = 0, count_wrong = 0;
    double worst_speed = 0.0;
    for (int s = 1; s <= 600; ++s) {
        step(w);
        kg_body_state now = state_of(w, box);
        kg_aabb bb;
        memset(&bb, 0, sizeof bb);
        KG_CHECK_OK(kg_body_get_aabb(w, box, &bb));
        changed_steps += memcmp(&now, &asleep, sizeof now) != 0 || memcmp(&bb, &box_asleep, sizeof bb) != 0;
        awake_steps += kg_body_is_awake(w, box);
        count_wrong += kg_world_asleep_count(w) != 1;
        double speed = fabs((double)now.velocity.x) + fabs((double)now.velocity.y) + fabs((double)now.angular_velocity);
        worst_speed = speed > worst_speed ? speed : worst_speed;
    }
    measured("measured: resting box asleep after step %d (%.4f s, time_to_sleep %.2f s) at y = %.6f, angle %.3g; "
             "over the next 10 s: %d steps changed state or bounds, %d steps awake, %d steps with asleep count != 1, "
             "largest |v|+|w| %.3g\n",
             slept_at, slept_at * (double)DT, (double)tts, (double)asleep.position.y, (double)asleep.angle,
             changed_steps, awake_steps, count_wrong, worst_speed);
    KG_CHECK(slept_at > 0);
    KG_CHECK(slept_at * (double)DT >= (double)tts - 1e-6);
    KG_CHECK(slept_at * (double)DT <= (double)tts + 1.0);
    KG_CHECK(asleep.velocity.x == 0.0f && asleep.velocity.y == 0.0f && asleep.angular_velocity == 0.0f);
    KG_CHECK_NEAR(asleep.position.y, 0.5, 0.01);
    KG_CHECK(changed_steps == 0);
    KG_CHECK(awake_steps == 0);
    KG_CHECK(count_wrong == 0);
    KG_CHECK(worst_speed == 0.0);
    KG_CHECK(kg_world_asleep_count(w) == 1);
    kg_destroy_world(w);
}

/* ---- 2. a bouncing ball stays awake ----------------------------------------------------- */

/* A ball of radius 0.25, restitution 0.8 (mixing: max), its bottom 2 m above the ground.
 * Every apex (vy turning from + to -) is found and the ball must be awake there while it
 * bounces higher than 3 cm; it may only be asleep below 3 cm, still. */
static void test_bouncing_ball_stays_awake_until_it_stops(void)
{
    kg_world* w = make_world(1);
    add_ground(w, 0.6f);
    const float r = 0.25f;
    kg_body ball = add(w, KG_BODY_DYNAMIC, kg_circle_shape(r), (kg_vec2){0.0f, 2.0f + r}, 0.6f, 0.8f);
    double apex_h[32];
    int apex_awake[32], apexes = 0, slept_at = -1, bad_sleep = 0;
    float prev_vy = 0.0f;
    double max_h_asleep = 0.0;
    for (int s = 1; s <= 900 && slept_at < 0; ++s) {
        step(w);
        kg_body_state st = state_of(w, ball);
        double h = (double)st.position.y - r;
        if (prev_vy > 0.0f && st.velocity.y <= 0.0f && apexes < 32) {
            apex_h[apexes] = h;
            apex_awake[apexes] = kg_body_is_awake(w, ball);
            apexes++;
        }
        prev_vy = st.velocity.y;
        if (!kg_body_is_awake(w, ball)) {
            slept_at = s;
            max_h_asleep = h;
            bad_sleep += h > 0.03 || st.velocity.x != 0.0f || st.velocity.y != 0.0f;
        }
    }
    measured("measured: ball e=0.8 from 2 m: %d apexes, heights (m, awake):", apexes);
    for (int i = 0; i < apexes; ++i) {
        measured(" %.4f%s", apex_h[i], apex_awake[i] ? "" : " ASLEEP");
    }
    measured("; asleep at step %d (%.3f s) at height %.4f m\n", slept_at, slept_at * (double)DT, max_h_asleep);
    KG_CHECK(apexes >= 5);
    if (apexes > 0) {
        KG_CHECK_NEAR(apex_h[0], 2.0 * 0.64, 0.1); /* e^2 of the drop height */
    }
    for (int i = 0; i < apexes; ++i) {
        if (apex_h[i] > 0.03) {
            KG_CHECK(apex_awake[i]);
        }
    }
    KG_CHECK(slept_at > 0);
    KG_CHECK(bad_sleep == 0);
    kg_destroy_world(w);
}

/* ---- 3. slow sliding is not rest -------------------------------------------------------- */

static void test_box_sliding_slowly_never_sleeps(void)
{
    kg_world* w = make_world(1);
    add_ground(w, 0.0f);
    kg_body_def bd = kg_default_body_def();
    bd.shape = kg_box_shape(1.0f, 1.0f);
    bd.position = (kg_vec2){0.0f, 0.5f};
    bd.velocity = (kg_vec2){0.1f, 0.0f};
    bd.friction = 0.0f;
    kg_body box = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &box));
    int asleep_steps = 0;
    for (int s = 1; s <= 600; ++s) {
        step(w);
        asleep_steps += !kg_body_is_awake(w, box);
    }
    kg_body_state st = state_of(w, box);
    double travel = st.position.x;
    measured("measured: box sliding at 0.1 m/s on frictionless ground: %d of 600 steps asleep, travelled %.6f m in "
             "10 s (relative error %.3g), vx = %.6f m/s at the end, asleep count %d\n",
             asleep_steps, travel, fabs(travel - 1.0), (double)st.velocity.x, kg_world_asleep_count(w));
    KG_CHECK(asleep_steps == 0);
    KG_CHECK(kg_world_asleep_count(w) == 0);
    KG_CHECK_NEAR(travel, 1.0, 1e-3);
    kg_destroy_world(w);
}

/* ---- 4. a ball lands on a sleeping stack ------------------------------------------------ */

static void test_ball_wakes_sleeping_stack_which_stands_and_sleeps_again(void)
{
    kg_world* w = make_world(1);
    add_ground(w, 0.6f);
    kg_body boxes[5];
    add_stack(w, boxes, 5, 0.0f);
    int slept = step_until_asleep(w, 5, 300);
    kg_vec2 top0 = state_of(w, boxes[4]).position;
    /* ball of radius 0.25, density 4 (0.79 kg), 1 m above the top face, a little off centre */
    kg_body_def bd = kg_default_body_def();
    bd.shape = kg_circle_shape(0.25f);
    bd.density = 4.0f;
    bd.position = (kg_vec2){0.15f, 5.0f + 1.0f + 0.25f};
    kg_body ball = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &ball));
    int asleep_after_drop = kg_world_asleep_count(w);
    int touch_step = -1, awake_at_touch = -1, first_woken_step = -1, asleep_before_touch = 0;
    double gap_at_touch = 0.0, vy_at_touch = 0.0, top_vy_at_touch = 0.0;
    double worst_top_dx = 0.0, top_speed_max = 0.0;
    for (int s = 1; s <= 120 && touch_step < 0; ++s) {
        step(w);
        int awake = awake_count(w, boxes, 5);
        if (awake > 0 && first_woken_step < 0) {
            first_woken_step = s;
        }
        if (touching(w, ball, boxes[4])) {
            touch_step = s;
            awake_at_touch = awake;
            kg_body_state bs = state_of(w, ball);
            gap_at_touch = (double)bs.position.y - 0.25 - (double)state_of(w, boxes[4]).position.y - 0.5;
            vy_at_touch = bs.velocity.y;
            top_vy_at_touch = state_of(w, boxes[4]).velocity.y;
        } else {
            asleep_before_touch += awake == 0;
        }
    }
    int resleep = -1;
    for (int s = 1; s <= 600 && resleep < 0; ++s) {
        step(w);
        kg_body_state top = state_of(w, boxes[4]);
        double dx = fabs((double)top.position.x - top0.x);
        worst_top_dx = dx > worst_top_dx ? dx : worst_top_dx;
        double speed = hypot(top.velocity.x, top.velocity.y);
        top_speed_max = speed > top_speed_max ? speed : top_speed_max;
        if (kg_world_asleep_count(w) == 6) {
            resleep = s;
        }
    }
    kg_body_state top_end = state_of(w, boxes[4]), ball_end = state_of(w, ball);
    measured("measured: stack of 5 asleep after %d steps; ball dropped (asleep count then %d): first contact with "
             "the top box at step %d (ball %.4f m above the top face after it, vy %.3f m/s; top box vy %.4f m/s), boxes awake then %d of 5 "
             "(first woken at step %d, all asleep in %d steps before the touch); after it: top box fastest "
             "%.4f m/s, moved at most %.5f m sideways, ended at (%.5f, %.5f) angle %.3g; ball at (%.4f, %.4f); all 6 "
             "asleep again %d steps (%.2f s) after the touch\n",
             slept, asleep_after_drop, touch_step, gap_at_touch, vy_at_touch, top_vy_at_touch, awake_at_touch, first_woken_step,
             asleep_before_touch, top_speed_max, worst_top_dx,
             (double)top_end.position.x, (double)top_end.position.y, (double)top_end.angle,
             (double)ball_end.position.x, (double)ball_end.position.y, resleep, resleep * (double)DT);
    KG_CHECK(slept > 0);
    KG_CHECK(asleep_after_drop == 5);
    KG_CHECK(touch_step > 0);
    KG_CHECK(awake_at_touch == 5);
    KG_CHECK(first_woken_step > 0 && first_woken_step <= touch_step);
    KG_CHECK(asleep_before_touch == first_woken_step - 1); /* the falling ball alone does not wake it */
    KG_CHECK(top_vy_at_touch < 0.0); /* solved awake in the step of the hit: pushed down at once */
    KG_CHECK(top_speed_max > 0.0);
    KG_CHECK(worst_top_dx < 0.05);
    KG_CHECK_NEAR(top_end.position.y, 4.5, 0.05);
    KG_CHECK_NEAR(ball_end.position.y, 5.25, 0.05); /* the ball rests on the top box */
    KG_CHECK(resleep > 0);
    kg_destroy_world(w);
}

/* ---- 5. the API wakes what it changes --------------------------------------------------- */

static void test_api_wakes_set_velocity_destroy_gravity(void)
{
    kg_world* w = make_world(1);
    add_ground(w, 0.6f);
    kg_body boxes[5];
    add_stack(w, boxes, 5, 0.0f);
    int slept = step_until_asleep(w, 5, 300);
    KG_CHECK(slept > 0);

    /* set_velocity on the top box */
    KG_CHECK_OK(kg_body_set_velocity(w, boxes[4], (kg_vec2){0.2f, 0.0f}));
    int top_awake_now = kg_body_is_awake(w, boxes[4]);
    int below_awake_now = kg_body_is_awake(w, boxes[3]);
    kg_vec2 v_now = {0.0f, 0.0f};
    KG_CHECK_OK(kg_body_get_velocity(w, boxes[4], &v_now));
    step(w);
    int awake_next = awake_count(w, boxes, 5);
    int slept2 = step_until_asleep(w, 5, 300);
    measured("measured: set_velocity(top, 0.2 m/s) on a stack asleep after %d steps: top awake at once %d (v %.3f), "
             "box below awake at once %d, boxes awake after one step %d of 5; asleep again after %d steps\n",
             slept, top_awake_now, (double)v_now.x, below_awake_now, awake_next, slept2);
    KG_CHECK(top_awake_now);
    KG_CHECK(v_now.x == 0.2f);
    KG_CHECK(awake_next == 5);
    KG_CHECK(slept2 > 0);

    /* destroying the bottom box */
    float y1_before = state_of(w, boxes[1]).position.y;
    KG_CHECK_OK(kg_destroy_body(w, boxes[0]));
    int awake_at_once = awake_count(w, boxes + 1, 4);
    int second_awake_at_once = kg_body_is_awake(w, boxes[1]);
    step(w);
    int awake_after_step = awake_count(w, boxes + 1, 4);
    for (int s = 2; s <= 60; ++s) {
        step(w);
    }
    float y1_after = state_of(w, boxes[1]).position.y;
    float y4_after = state_of(w, boxes[4]).position.y;
    int slept3 = step_until_asleep(w, 4, 300);
    measured("measured: bottom box destroyed: awake at once %d of 4 (the one resting on it: %d), after one step %d "
             "of 4; new bottom box y %.5f -> %.5f after 1 s (drop %.5f m), top box y %.5f; asleep again after %d "
             "more steps\n",
             awake_at_once, second_awake_at_once, awake_after_step, (double)y1_before, (double)y1_after,
             (double)(y1_before - y1_after), (double)y4_after, slept3);
    KG_CHECK(second_awake_at_once);
    KG_CHECK(awake_after_step == 4);
    KG_CHECK_NEAR(y1_before - y1_after, 1.0, 0.05);
    KG_CHECK_NEAR(y4_after, 3.5, 0.05);
    KG_CHECK(slept3 > 0);

    /* gravity */
    int before = kg_world_asleep_count(w);
    KG_CHECK_OK(kg_world_set_gravity(w, (kg_vec2){0.0f, -9.81f}));
    int after = kg_world_asleep_count(w);
    int awake_boxes = awake_count(w, boxes + 1, 4);
    measured("measured: set_gravity: asleep %d before, %d after (boxes awake %d of 4)\n", before, after, awake_boxes);
    KG_CHECK(before == 4);
    KG_CHECK(after == 0);
    KG_CHECK(awake_boxes == 4);
    kg_destroy_world(w);
}

/* ---- 6. a kinematic platform starts moving under a sleeping box ------------------------- */

static void test_moving_kinematic_platform_wakes_and_carries_box(void)
{
    kg_world* w = make_world(1);
    kg_body platform = add(w, KG_BODY_KINEMATIC, kg_box_shape(6.0f, 0.5f), (kg_vec2){0.0f, -0.25f}, 0.6f, 0.0f);
    kg_body box = add(w, KG_BODY_DYNAMIC, kg_box_shape(1.0f, 1.0f), (kg_vec2){0.0f, 0.5f}, 0.6f, 0.0f);
    int slept = step_until_asleep(w, 1, 180);
    KG_CHECK_OK(kg_body_set_velocity(w, platform, (kg_vec2){1.0f, 0.0f}));
    int awake_at_once = kg_body_is_awake(w, box);
    step(w);
    int awake_next = kg_body_is_awake(w, box);
    int asleep_steps = 0;
    for (int s = 2; s <= 120; ++s) {
        step(w);
        asleep_steps += !kg_body_is_awake(w, box);
    }
    kg_body_state bs = state_of(w, box), ps = state_of(w, platform);
    measured("measured: box asleep on a still kinematic platform after %d steps; platform set to 1 m/s: box awake "
             "at once %d, after one step %d, asleep in %d of the next 119 steps; after 2 s box v = (%.5f, %.3g), "
             "platform at x = %.4f, box %.4f from the platform's centre\n",
             slept, awake_at_once, awake_next, asleep_steps, (double)bs.velocity.x, (double)bs.velocity.y,
             (double)ps.position.x, (double)(bs.position.x - ps.position.x));
    KG_CHECK(slept > 0);
    KG_CHECK(awake_next);
    KG_CHECK(asleep_steps == 0);
    KG_CHECK_NEAR(bs.velocity.x, 1.0, 0.02);
    KG_CHECK_NEAR(ps.position.x, 2.0, 1e-3);
    kg_destroy_world(w);
}

/* The solve stage takes the colours the collide stage found each contact keeps; a body
 * woken after that (here by the platform it sleeps on, with no new contact that step)
 * changes what its contacts keep (asleep, they took theirs as between still bodies), and
 * they must be coloured again. Kept wrongly, contacts on one body would share a colour:
 * lanes of one block would then write the same body, and rows of 1 lane and of the
 * widest this CPU has (KGYRO_SIMD_WIDTH, read when the world is made) would part. */
static void woken_pile_run(const char* width, kg_body_state* out, int* slept, int* awake)
{
    if (width) {
        setenv("KGYRO_SIMD_WIDTH", width, 1);
    }
    kg_world* w = make_world(1);
    unsetenv("KGYRO_SIMD_WIDTH");
    kg_body platform = add(w, KG_BODY_KINEMATIC, kg_box_shape(12.0f, 0.5f), (kg_vec2){0.0f, -0.25f}, 0.6f, 0.0f);
    kg_body boxes[24];
    for (int i = 0; i < 24; ++i) {
        kg_vec2 at = {-3.0f + 1.0f * (float)(i % 6) + 0.25f * (float)(i / 6 % 2), 0.5f + (float)(i / 6)};
        boxes[i] = add(w, KG_BODY_DYNAMIC, kg_box_shape(0.98f, 0.98f), at, 0.6f, 0.0f);
    }
    /* a kinematic body turning far away keeps the solver running while the pile sleeps,
     * so the pile's contacts take their colours asleep */
    kg_body spinner = add(w, KG_BODY_KINEMATIC, kg_box_shape(1.0f, 1.0f), (kg_vec2){50.0f, 5.0f}, 0.6f, 0.0f);
    KG_CHECK_OK(kg_body_set_angular_velocity(w, spinner, 1.0f));
    *slept = step_until_asleep(w, 24, 600);
    step(w);
    KG_CHECK_OK(kg_body_set_velocity(w, platform, (kg_vec2){0.5f, 0.0f}));
    for (int s = 0; s < 60; ++s) {
        step(w);
    }
    *awake = awake_count(w, boxes, 24);
    for (int i = 0; i < 24; ++i) {
        out[i] = state_of(w, boxes[i]);
    }
    kg_destroy_world(w);
}

static void test_woken_pile_colored_again(void)
{
    kg_body_state one[24], widest[24];
    int slept[2], awake[2];
    woken_pile_run("1", one, &slept[0], &awake[0]);
    woken_pile_run(NULL, widest, &slept[1], &awake[1]);
    int differing = 0;
    for (int i = 0; i < 24; ++i) {
        differing += memcmp(&one[i], &widest[i], sizeof one[i]) != 0;
    }
    measured("measured: 24 boxes asleep on a still platform after %d steps; set moving: %d awake after 1 s; %d of "
             "24 states not bitwise equal between rows of 1 lane and the widest\n", slept[0], awake[0], differing);
    KG_CHECK(slept[0] > 0 && slept[1] == slept[0]);
    KG_CHECK(awake[0] == 24);
    KG_CHECK(differing == 0);
}

/* ---- 7. enable_sleep = 0 ---------------------------------------------------------------- */

static void test_sleep_disabled_never_sleeps(void)
{
    kg_world* w = make_world(0);
    add_ground(w, 0.6f);
    kg_body box = add(w, KG_BODY_DYNAMIC, kg_box_shape(1.0f, 1.0f), (kg_vec2){0.0f, 0.5f}, 0.6f, 0.0f);
    int asleep_steps = 0, worst_count = 0;
    for (int s = 1; s <= 300; ++s) {
        step(w);
        asleep_steps += !kg_body_is_awake(w, box);
        int c = kg_world_asleep_count(w);
        worst_count = c > worst_count ? c : worst_count;
    }
    kg_body_state st = state_of(w, box);
    measured("measured: enable_sleep 0, resting box for 5 s: %d steps asleep, largest asleep count %d, y = %.6f\n",
             asleep_steps, worst_count, (double)st.position.y);
    KG_CHECK(asleep_steps == 0);
    KG_CHECK(worst_count == 0);
    KG_CHECK_NEAR(st.position.y, 0.5, 0.01);
    kg_destroy_world(w);
}

/* ---- 8. 400 sleeping boxes -------------------------------------------------------------- */

#define GRID_COLS 40
#define GRID_ROWS 10
#define GRID_N (GRID_COLS * GRID_ROWS)

/* 40 columns of 10 boxes of 0.5 m, 0.25 m apart: each column its own island. */
static void add_grid(kg_world* w, kg_body* out)
{
    add_ground(w, 0.6f);
    for (int c = 0; c < GRID_COLS; ++c) {
        for (int r = 0; r < GRID_ROWS; ++r) {
            float x = -15.0f + 0.75f * (float)c, y = 0.25f + 0.5f * (float)r;
            out[c * GRID_ROWS + r] = add(w, KG_BODY_DYNAMIC, kg_box_shape(0.5f, 0.5f), (kg_vec2){x, y}, 0.6f, 0.0f);
        }
    }
}

static double mean_step_ms(kg_world* w, int steps)
{
    double t0 = now_s();
    for (int s = 0; s < steps; ++s) {
        step(w);
    }
    return (now_s() - t0) * 1e3 / steps;
}

static void test_grid_of_400_sleeps_and_still_responds(void)
{
    static kg_body boxes[GRID_N];
    kg_world* w = make_world(1);
    add_grid(w, boxes);
    int slept = step_until_asleep(w, GRID_N, 300);
    double ms_asleep = mean_step_ms(w, 60);
    int asleep_after_timing = kg_world_asleep_count(w);
    kg_stage_times times;
    memset(&times, 0, sizeof times);
    KG_CHECK_OK(kg_world_get_stage_times(w, &times));
    measured("measured: grid of %d boxes, last all-asleep step by stage (ms):", GRID_N);
    for (int i = 0; i < times.count && i < 16; ++i) {
        measured(" %s %.4f", times.names[i], times.ms[i]);
    }
    measured("\n");

    kg_world* awake_world = make_world(0);
    static kg_body other[GRID_N];
    add_grid(awake_world, other);
    for (int s = 0; s < (slept > 0 ? slept : 60); ++s) {
        step(awake_world);
    }
    double ms_awake = mean_step_ms(awake_world, 60);
    int awake_world_asleep = kg_world_asleep_count(awake_world);
    kg_destroy_world(awake_world);

    /* a ball dropped onto column 5 */
    const int col = 5, far_col = 30;
    kg_vec2 top = state_of(w, boxes[col * GRID_ROWS + GRID_ROWS - 1]).position;
    kg_body_def bd = kg_default_body_def();
    bd.shape = kg_circle_shape(0.2f);
    bd.position = (kg_vec2){top.x, top.y + 0.25f + 0.5f + 0.2f};
    kg_body ball = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &ball));
    int touch_step = -1, hit_awake = -1, far_awake = -1, asleep_at_touch = -1;
    for (int s = 1; s <= 60 && touch_step < 0; ++s) {
        step(w);
        if (touching(w, ball, boxes[col * GRID_ROWS + GRID_ROWS - 1])) {
            touch_step = s;
            hit_awake = awake_count(w, boxes + col * GRID_ROWS, GRID_ROWS);
            far_awake = awake_count(w, boxes + far_col * GRID_ROWS, GRID_ROWS);
            asleep_at_touch = kg_world_asleep_count(w);
        }
    }
    int resleep = step_until_asleep(w, GRID_N + 1, 300);
    measured("measured: grid of %d boxes asleep after %d steps (%.2f s); mean step %.4f ms all asleep (asleep count "
             "%d) vs %.4f ms with enable_sleep 0 (asleep count %d), ratio %.1f; ball dropped on column %d touches at "
             "step %d: that column awake %d of %d, column %d awake %d, asleep count %d; all %d asleep again after %d "
             "steps\n",
             GRID_N, slept, slept * (double)DT, ms_asleep, asleep_after_timing, ms_awake, awake_world_asleep,
             ms_awake / (ms_asleep > 0.0 ? ms_asleep : 1e-9), col, touch_step, hit_awake, GRID_ROWS, far_col,
             far_awake, asleep_at_touch, GRID_N + 1, resleep);
    KG_CHECK(slept > 0);
    KG_CHECK(asleep_after_timing == GRID_N);
    KG_CHECK(awake_world_asleep == 0);
    KG_CHECK(touch_step > 0);
    KG_CHECK(hit_awake == GRID_ROWS);
    KG_CHECK(far_awake == 0);
    KG_CHECK(asleep_at_touch == GRID_N - GRID_ROWS);
    KG_CHECK(resleep > 0);
    kg_destroy_world(w);
}

static kg_u32 next_random(kg_u32* state)
{
    *state = *state * 1664525u + 1013904223u;
    return *state >> 8;
}

/* Random bodies of every type (some frozen, some asleep, kinematic ones moving or not)
 * and random contacts among them, tile contacts included: kg_find_islands_in_group, the
 * kernel's algorithm, gives kg_link_islands' parents and least rest times bit for bit. */
static void test_islands_by_group_are_the_serial_ones(void)
{
    enum { BODIES = 300, CONTACTS = 400, ROUNDS = 20 };
    static kg_u32 flags[BODIES], parent[2][BODIES];
    static kg_vec2 velocity[BODIES];
    static float omega[BODIES], sleep_time[BODIES], least[2][BODIES];
    static kg_contact contacts[CONTACTS];
    kg_u32 seed = 7u;
    int differing = 0, islands = 0;
    for (int round = 0; round < ROUNDS; ++round) {
        for (int i = 0; i < BODIES; ++i) {
            kg_u32 r = next_random(&seed);
            flags[i] = KG_FLAG_ALIVE | ((r % 4u) << KG_TYPE_SHIFT) | (r % 23u == 0u ? KG_FLAG_FROZEN : 0u) |
                       (r % 5u == 0u ? KG_FLAG_ASLEEP : 0u);
            velocity[i] = (kg_vec2){r % 3u == 0u ? 1.0f : 0.0f, 0.0f};
            omega[i] = 0.0f;
            sleep_time[i] = (float)(next_random(&seed) % 100u) * 0.01f;
        }
        int count = CONTACTS * (round + 1) / ROUNDS;
        for (int k = 0; k < count; ++k) {
            kg_u32 a = next_random(&seed) % BODIES, b = next_random(&seed) % BODIES;
            contacts[k].a = a < b ? a : b;
            contacts[k].b = a == b || next_random(&seed) % 10u == 0u ? KG_NULL_INDEX : (a < b ? b : a);
        }
        int hooked = 0;
        kg_link_islands(BODIES, count, contacts, flags, velocity, omega, sleep_time, parent[0], least[0]);
        kg_find_islands_in_group(0, 1, &hooked, BODIES, count, contacts, flags, velocity, omega, sleep_time,
                                 parent[1], least[1]);
        differing += memcmp(parent[0], parent[1], sizeof parent[0]) != 0 ||
                     memcmp(least[0], least[1], sizeof least[0]) != 0;
        for (int i = 0; i < BODIES; ++i) {
            islands += kg_flags_collide(flags[i]) && parent[0][i] == (kg_u32)i;
        }
    }
    measured("measured: %d rounds of %d bodies and up to %d contacts, %d islands in all, %d rounds differing\n",
             ROUNDS, BODIES, CONTACTS, islands, differing);
    KG_CHECK(differing == 0);
    KG_CHECK(islands > ROUNDS);
}

KG_TEST_MAIN(KG_TEST(test_resting_box_sleeps_on_time_and_is_frozen_bitwise),
             KG_TEST(test_bouncing_ball_stays_awake_until_it_stops), KG_TEST(test_box_sliding_slowly_never_sleeps),
             KG_TEST(test_ball_wakes_sleeping_stack_which_stands_and_sleeps_again),
             KG_TEST(test_api_wakes_set_velocity_destroy_gravity),
             KG_TEST(test_moving_kinematic_platform_wakes_and_carries_box),
             KG_TEST(test_woken_pile_colored_again), KG_TEST(test_sleep_disabled_never_sleeps),
             KG_TEST(test_grid_of_400_sleeps_and_still_responds),
             KG_TEST(test_islands_by_group_are_the_serial_ones))
