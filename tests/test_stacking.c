/* Acceptance tests of the contact solver (issue 4): stacks that stand and piles that come
 * to rest. CPU backend, world defaults (4 sub-steps, contact_hertz 45), dt = 1/60.
 *
 *   test_stacking                 the quick set (also run by the sanitizer build)
 *   test_stacking NAME...         the named tests; tests/cases/solver_slow.cmake registers
 *                                 the long ones one per ctest entry, labelled slow
 *
 * Every test prints its measured numbers ("measured: ...") whether it passes or not. */
#include "kg_test.h"
#include "kgyro/kgyro.h"
#include "kgyro/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <stdarg.h>

/* Prints a line of measured numbers and flushes it, so that it comes out before the
 * harness's failure messages (on stderr) about the same numbers. */

#define DT (1.0f / 60.0f)

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The world's defaults, CPU backend. Stacks are tested with sleeping off, so that the
 * solver alone holds them up. */
static kg_world* make_world_with(int max_bodies, int sleep)
{
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    def.enable_sleep = sleep;
    if (max_bodies > def.max_bodies) {
        def.max_bodies = max_bodies;
    }
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    return w;
}

static kg_world* make_world(int max_bodies) { return make_world_with(max_bodies, 0); }

static kg_body add(kg_world* w, kg_body_type type, kg_shape_def shape, kg_vec2 pos, float angle)
{
    kg_body_def bd = kg_default_body_def(); /* density 1, friction 0.6, restitution 0 */
    bd.type = type;
    bd.shape = shape;
    bd.position = pos;
    bd.angle = angle;
    kg_body b = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    return b;
}

static double dist(kg_vec2 a, kg_vec2 b) { return hypot((double)a.x - b.x, (double)a.y - b.y); }

/* ---- stacks and pyramids --------------------------------------------------------------- */

typedef struct stand_run {
    double top_from_settled_max; /* largest distance of the top box from where it was at 1 s */
    double top_from_settled_end;
    double top_from_start_max; /* from where it was placed */
    double top_from_start_end;
    double any_from_settled_end; /* largest over all boxes, at the end, from their places at 1 s */
    double any_from_start_end;
    double top_angle_end;
    double wall_s;
} stand_run;

/* Steps the world for seconds, following bodies[top] every step and every body at
 * settle_s (the settling) and at the end. */
static stand_run run_standing(kg_world* w, const kg_body* bodies, int count, int top, double settle_s, double seconds)
{
    stand_run r;
    memset(&r, 0, sizeof r);
    kg_vec2* start = malloc((size_t)count * sizeof *start);
    kg_vec2* settled = malloc((size_t)count * sizeof *settled);
    kg_body_state* states = malloc((size_t)count * sizeof *states);
    KG_CHECK(start && settled && states);
    if (!start || !settled || !states) {
        free(start);
        free(settled);
        free(states);
        return r;
    }
    KG_CHECK_OK(kg_world_get_body_states(w, bodies, count, states));
    for (int i = 0; i < count; ++i) {
        start[i] = states[i].position;
    }
    int settle_steps = (int)lround(settle_s / DT), steps = (int)lround(seconds / DT);
    double t0 = now_s();
    for (int step = 1; step <= steps; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_body_state top_state;
        KG_CHECK_OK(kg_body_get_state(w, bodies[top], &top_state));
        double from_start = dist(top_state.position, start[top]);
        r.top_from_start_max = from_start > r.top_from_start_max ? from_start : r.top_from_start_max;
        if (step == settle_steps) {
            KG_CHECK_OK(kg_world_get_body_states(w, bodies, count, states));
            for (int i = 0; i < count; ++i) {
                settled[i] = states[i].position;
            }
        }
        if (step >= settle_steps) {
            double from_settled = dist(top_state.position, settled[top]);
            r.top_from_settled_max = from_settled > r.top_from_settled_max ? from_settled : r.top_from_settled_max;
        }
    }
    r.wall_s = now_s() - t0;
    KG_CHECK_OK(kg_world_get_body_states(w, bodies, count, states));
    r.top_from_settled_end = dist(states[top].position, settled[top]);
    r.top_from_start_end = dist(states[top].position, start[top]);
    r.top_angle_end = states[top].angle;
    for (int i = 0; i < count; ++i) {
        double a = dist(states[i].position, settled[i]), b = dist(states[i].position, start[i]);
        r.any_from_settled_end = a > r.any_from_settled_end ? a : r.any_from_settled_end;
        r.any_from_start_end = b > r.any_from_start_end ? b : r.any_from_start_end;
    }
    free(start);
    free(settled);
    free(states);
    return r;
}

static void print_stand(const char* label, double settle_s, double seconds, const stand_run* r)
{
    measured(
        "measured: %s for %.1f s: top box from its place at %.1f s: max %.3f mm, end %.3f mm; from its initial "
        "placement: max %.3f mm, end %.3f mm; top angle at the end %.3g rad; any box at the end: %.3f mm from "
        "%.1f s, %.3f mm from placement; %.1f s wall\n",
        label, seconds, settle_s, r->top_from_settled_max * 1e3, r->top_from_settled_end * 1e3,
        r->top_from_start_max * 1e3, r->top_from_start_end * 1e3, r->top_angle_end, r->any_from_settled_end * 1e3,
        settle_s, r->any_from_start_end * 1e3, r->wall_s);
}

/* Static ground: a box 240 m wide, 1 m thick, its top face at y = 0. */
static void add_ground(kg_world* w)
{
    add(w, KG_BODY_STATIC, kg_box_shape(240.0f, 1.0f), (kg_vec2){0.0f, -0.5f}, 0.0f);
}

/* 20 boxes of 1 m, density 1, each placed touching the one below (no gap). */
static void stack_of_20(double seconds)
{
    kg_world* w = make_world(0);
    add_ground(w);
    kg_body boxes[20];
    for (int i = 0; i < 20; ++i) {
        boxes[i] = add(w, KG_BODY_DYNAMIC, kg_box_shape(1.0f, 1.0f), (kg_vec2){0.0f, 0.5f + (float)i}, 0.0f);
    }
    stand_run r = run_standing(w, boxes, 20, 19, 1.0, seconds);
    print_stand("stack of 20", 1.0, seconds, &r);
    KG_CHECK(r.top_from_settled_max < 0.01);
    kg_destroy_world(w);
}

/* Box2D's pyramid layout: row i (from the bottom) has base - i boxes of 1 m, touching side
 * by side, each row centred on the one below. Returns the body count; the top box is last. */
static int pyramid(kg_world* w, int base, kg_body* out)
{
    int n = 0;
    const float h = 0.5f;
    for (int i = 0; i < base; ++i) {
        float y = (2.0f * (float)i + 1.0f) * h;
        for (int j = i; j < base; ++j) {
            float x = ((float)i + 1.0f) * h + 2.0f * (float)(j - i) * h - h * (float)base;
            out[n++] = add(w, KG_BODY_DYNAMIC, kg_box_shape(1.0f, 1.0f), (kg_vec2){x, y}, 0.0f);
        }
    }
    return n;
}

/* A pyramid of the given base at the world's defaults, its top box followed from
 * settle_s: with check_end, its drift is the distance between where it is at settle_s
 * and at the end (the measure), else the largest distance from there. */
static void pyramid_run(int base, double settle_s, double seconds, double top_limit, int check_end)
{
    int count = base * (base + 1) / 2;
    kg_world* w = make_world(count + 16);
    add_ground(w);
    kg_body* boxes = malloc((size_t)count * sizeof *boxes);
    KG_CHECK(boxes != NULL);
    if (!boxes) {
        kg_destroy_world(w);
        return;
    }
    KG_CHECK(pyramid(w, base, boxes) == count);
    stand_run r = run_standing(w, boxes, count, count - 1, settle_s, seconds);
    char label[64];
    snprintf(label, sizeof label, "pyramid base %d (%d boxes, %d sub-steps)", base, count,
             kg_default_world_def().substeps);
    print_stand(label, settle_s, seconds, &r);
    KG_CHECK((check_end ? r.top_from_settled_end : r.top_from_settled_max) < top_limit);
    free(boxes);
    kg_destroy_world(w);
}

static void test_stack_of_20_stands_10_s(void) { stack_of_20(10.0); }
static void test_stack_of_20_stands_60_s(void) { stack_of_20(60.0); }
/* Base 20: the stack's limit, 1 cm, from 1 s on. Base 100 (Box2D's large pyramid): its
 * bottom rows carry 50 boxes and soft contacts sag by load / (m omega^2), 0.5 m at the
 * defaults, by 2.5 s; from there to 8.3 s the top box must drift less than 1.5 cm
 * (issue 13; the best engine measured did 1.2 cm). */
static void test_pyramid_20_stands_4_s(void) { pyramid_run(20, 1.0, 4.0, 0.01, 0); }
static void test_pyramid_20_stands_60_s(void) { pyramid_run(20, 1.0, 60.0, 0.01, 0); }
static void test_pyramid_100_holds_from_2_5_to_8_3_s(void) { pyramid_run(100, 2.5, 8.33, 0.015, 1); }

/* A loaded pyramid tilts its boxes past the narrowphase's reference tolerance, which
 * passes the reference face from one box to the other; with feature ids that named the
 * reference, a base-100 pyramid at 4 sub-steps started 1,000 of its 29,900 points cold
 * every step. Resting, every point of a persisting contact must carry its impulses:
 * at least 99.9% over 3 s after the first second, at the world's defaults. */
static void test_pyramid_keeps_its_warm_starts(void)
{
    enum { BASE = 40, COUNT = BASE * (BASE + 1) / 2 };
    kg_world* w = make_world(COUNT + 16);
    add_ground(w);
    static kg_body boxes[COUNT];
    KG_CHECK(pyramid(w, BASE, boxes) == COUNT);
    long carried = 0, missed = 0;
    for (int step = 1; step <= 240; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_stage_times times;
        KG_CHECK_OK(kg_world_get_stage_times(w, &times));
        KG_CHECK(times.warm_starts_carried >= 0 && times.warm_starts_missed >= 0);
        if (step > 60) {
            carried += times.warm_starts_carried;
            missed += times.warm_starts_missed;
        }
    }
    double share = (double)carried / (double)(carried + missed);
    measured("measured: pyramid base %d, 1 to 4 s: %ld points warm started, %ld started cold (%.4f%% carried)\n", BASE,
             carried, missed, 100.0 * share);
    KG_CHECK(carried > 180 * 2 * COUNT); /* two points a box on the one below, at least */
    KG_CHECK(share >= 0.999);
    kg_destroy_world(w);
}

/* ---- a pile comes to rest -------------------------------------------------------------- */

static uint32_t rng_state;
static float rnd(void) /* [0, 1), xorshift32 */
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 17;
    rng_state ^= rng_state << 5;
    return (float)(rng_state >> 8) * (1.0f / 16777216.0f);
}

/* Kinetic energy, translation and rotation. */
static double kinetic_energy(kg_world* w, const kg_body* bodies, int count, kg_body_state* states,
                             const kg_mass_data* md)
{
    KG_CHECK_OK(kg_world_get_body_states(w, bodies, count, states));
    double e = 0.0;
    for (int i = 0; i < count; ++i) {
        double vx = states[i].velocity.x, vy = states[i].velocity.y, om = states[i].angular_velocity;
        e += 0.5 * md[i].mass * (vx * vx + vy * vy) + 0.5 * md[i].inertia * om * om;
    }
    return e;
}

/* The first step from which every step to the end has all count bodies asleep; -1 if none. */
static int first_step_all_asleep(const int* asleep, int steps, int count)
{
    int first = -1;
    for (int step = steps; step >= 1 && asleep[step] == count; --step) {
        first = step;
    }
    return first;
}

/* The largest growth of kinetic energy between steps in [from, steps], and where. */
static double worst_growth_from(const double* energy, int from, int steps, int* at)
{
    double worst = 0.0;
    *at = -1;
    for (int step = from > 1 ? from : 1; step <= steps; ++step) {
        if (energy[step] - energy[step - 1] > worst) {
            worst = energy[step] - energy[step - 1];
            *at = step;
        }
    }
    return worst;
}

/* 1000 bodies, every other one a box (sides 0.4 to 1.0 m) or a circle (radius 0.2 to
 * 0.5 m) at a random angle, one per 1.2 m cell of a 40 x 25 grid whose bottom row is 1 m
 * above the floor, dropped into a container 48 m wide (static floor and walls). Seed 1234.
 * Kinetic energy (translation and rotation) is measured after every step for 30 s.
 *
 * At rest means what the engine decides: from the step where every body is asleep (and
 * stays so to the end); from there kinetic energy must never grow by more than 1e-6 of
 * the peak, so a spontaneous wake-up or jitter fails. Kinetic energy falls below 1e-3 of
 * the peak well before (3 s), but bodies still tumble down the pile and the bottom layer
 * still settles until about 9 s (growth up to 3e-5 of the peak between steps, with
 * sleeping on or off): that figure is printed, not asserted. */
static void test_pile_of_1000_comes_to_rest(void)
{
    enum { COUNT = 1000, COLS = 40, STEPS = 1800 };
    const float cell = 1.2f, width = COLS * cell;
    kg_world* w = make_world_with(COUNT + 16, 1);
    add(w, KG_BODY_STATIC, kg_box_shape(width + 2.0f, 1.0f), (kg_vec2){0.0f, -0.5f}, 0.0f);
    add(w, KG_BODY_STATIC, kg_box_shape(1.0f, 80.0f), (kg_vec2){-0.5f * width - 0.5f, 39.0f}, 0.0f);
    add(w, KG_BODY_STATIC, kg_box_shape(1.0f, 80.0f), (kg_vec2){0.5f * width + 0.5f, 39.0f}, 0.0f);
    static kg_body bodies[COUNT];
    static kg_mass_data md[COUNT];
    static kg_body_state states[COUNT];
    static double energy[STEPS + 1];
    static int asleep[STEPS + 1];
    rng_state = 1234u;
    for (int i = 0; i < COUNT; ++i) {
        int row = i / COLS, col = i % COLS;
        kg_vec2 p = {-0.5f * width + ((float)col + 0.5f) * cell + 0.1f * (rnd() - 0.5f),
                     1.0f + 0.5f * cell + (float)row * cell};
        float angle = 6.2831853f * rnd();
        kg_shape_def shape = (i % 2 == 0) ? kg_box_shape(0.4f + 0.6f * rnd(), 0.4f + 0.6f * rnd())
                                          : kg_circle_shape(0.2f + 0.3f * rnd());
        bodies[i] = add(w, KG_BODY_DYNAMIC, shape, p, angle);
        KG_CHECK_OK(kg_body_get_mass_data(w, bodies[i], &md[i]));
    }
    double t0 = now_s();
    energy[0] = kinetic_energy(w, bodies, COUNT, states, md);
    double peak = energy[0];
    int peak_step = 0;
    for (int step = 1; step <= STEPS; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        energy[step] = kinetic_energy(w, bodies, COUNT, states, md);
        asleep[step] = kg_world_asleep_count(w);
        if (energy[step] > peak) {
            peak = energy[step];
            peak_step = step;
        }
    }
    double wall = now_s() - t0;
    int below_1e3 = -1;
    for (int step = peak_step; step <= STEPS && below_1e3 < 0; ++step) {
        below_1e3 = energy[step] < 1e-3 * peak ? step : -1;
    }
    int rest_step = first_step_all_asleep(asleep, STEPS, COUNT);
    int growth_at = -1, early_at = -1;
    double growth = worst_growth_from(energy, rest_step > 0 ? rest_step + 1 : STEPS + 1, STEPS, &growth_at);
    double early = worst_growth_from(energy, below_1e3 > 0 ? below_1e3 + 1 : STEPS + 1, STEPS, &early_at);
    measured("measured: pile of 1000 (seed 1234): peak kinetic energy %.6g J at %.3f s; below 1e-3 of it from %.3f s; "
             "all asleep from %.3f s (%s); largest growth between steps after that %.3g of the peak; after falling "
             "below 1e-3 (bodies still tumbling): largest growth %.3g of the peak at %.3f s; %.1f s wall\n",
             peak, peak_step * (double)DT, below_1e3 * (double)DT, rest_step * (double)DT,
             rest_step > 0 ? "reached" : "NOT reached", growth / peak, early / peak, early_at * (double)DT, wall);
    for (int step = 60; step <= STEPS; step += step < 600 ? 60 : 300) {
        measured("  at %5.2f s: kinetic energy %.3g of the peak, %d bodies asleep\n", step * (double)DT,
                 energy[step] / peak, asleep[step]);
    }
    KG_CHECK(peak > 0.0);
    KG_CHECK(below_1e3 > 0);
    KG_CHECK(rest_step > below_1e3 && rest_step < STEPS - 300); /* at rest with at least 5 s left to watch */
    KG_CHECK(growth <= 1e-6 * peak);
    kg_destroy_world(w);
}

/* ---- a rain of 100,000 drops --------------------------------------------------------- */

/* rain_100000 with seed 2: drops fall from up to 250 m onto the pile that grows below,
 * the late ones at 65 m/s and more. At step 393 a disc of 0.16 m falling at 65 m/s passed
 * between two others that pressed on it: the one point where its contacts' impulses acted
 * (contact_row.h, kg_current_anchors) followed the metre the bodies slid past each other
 * within the step, and the lever arms it gave were tens of times what the masses prepared
 * at the step's start allowed for, so every pass overshot the last. A step later bodies
 * turned at 1e36 rad/s, some went non-finite and were frozen, and the contact pool grew to
 * 4.6 GB. Over 400 steps no body may turn faster than 2,000 rad/s or move faster than
 * 150 m/s (the fastest drop falls at 67), and none may be frozen. About 15 s in a release
 * build on two cores. */
static void test_rain_of_100000_stays_bounded(void)
{
    enum { STEPS = 400 };
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_generate("rain_100000", 2u, &scene));
    if (!scene) {
        return;
    }
    kg_world_def def = *kg_scene_world_def(scene);
    def.backend = KG_BACKEND_CPU;
    def.threads = 2;
    int n = kg_scene_body_count(scene);
    kg_body* bodies = malloc((size_t)n * sizeof *bodies);
    kg_body_state* states = malloc((size_t)n * sizeof *states);
    kg_world* w = NULL;
    KG_CHECK_OK(bodies && states ? kg_scene_instantiate(scene, &def, &w, bodies) : KG_ERROR_OUT_OF_MEMORY);
    double spin = 0.0, speed = 0.0;
    int spin_step = 0, speed_step = 0;
    for (int step = 1; w && step <= STEPS; ++step) {
        KG_CHECK_OK(kg_scene_step(scene, w, bodies, DT));
        KG_CHECK_OK(kg_world_get_body_states(w, bodies, n, states));
        for (int i = 0; i < n; ++i) {
            double turn = fabs(states[i].angular_velocity), v = hypot(states[i].velocity.x, states[i].velocity.y);
            spin_step = turn > spin ? step : spin_step;
            spin = turn > spin ? turn : spin;
            speed_step = v > speed ? step : speed_step;
            speed = v > speed ? v : speed;
        }
    }
    int frozen = 0;
    for (int i = 0; w && i < n; ++i) {
        frozen += kg_body_is_frozen(w, bodies[i]);
    }
    measured("measured: rain_100000 (seed 2), %d steps: fastest turn %.1f rad/s (step %d), fastest body %.1f m/s "
             "(step %d), %d frozen\n", STEPS, spin, spin_step, speed, speed_step, frozen);
    KG_CHECK(spin < 2000.0);
    KG_CHECK(speed < 150.0);
    KG_CHECK(frozen == 0);
    kg_destroy_world(w);
    kg_scene_destroy(scene);
    free(bodies);
    free(states);
}

/* ---- main ----------------------------------------------------------------------------- */

static const kg_test_case all_tests[] = {
    KG_TEST(test_stack_of_20_stands_10_s), KG_TEST(test_pyramid_20_stands_4_s),
    KG_TEST(test_pyramid_keeps_its_warm_starts), KG_TEST(test_stack_of_20_stands_60_s), KG_TEST(test_pyramid_20_stands_60_s),
    KG_TEST(test_pyramid_100_holds_from_2_5_to_8_3_s), KG_TEST(test_pile_of_1000_comes_to_rest),
    KG_TEST(test_rain_of_100000_stays_bounded),
};
enum { QUICK_TESTS = 3, ALL_TESTS = (int)(sizeof all_tests / sizeof all_tests[0]) };

int main(int argc, char** argv) { return kg_run_chosen_tests(all_tests, ALL_TESTS, QUICK_TESTS, argc, argv); }
