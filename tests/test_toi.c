/* The continuous collision's geometry (collide/toi.h) against dense references: the
 * distance of two shapes at random poses against the least distance of points sampled
 * every 2 mm along both outlines, and the time of impact of random sweeps, half of
 * them turning up to a radian, against 2,000 sampled times: never later than the first
 * at which the shapes come within the target (no overlap is ever allowed), and not
 * before they come within the target and its tolerance, by more than a centimetre of
 * the sweep. Every test prints what it measured. */
#include "collide/shape.h"
#include "collide/toi.h"
#include "kg_test.h"
#include "kgyro/kgyro.h"

#include <stdint.h>
#include <stdlib.h>

static uint32_t g_seed = 12345u;

static float uniform(float lo, float hi)
{
    g_seed = g_seed * 1664525u + 1013904223u;
    return lo + (hi - lo) * (float)(g_seed >> 8) / 16777216.0f;
}

static kg_shape build(kg_shape_def def)
{
    kg_shape s;
    KG_CHECK_OK(kg_shape_build(&def, &s));
    return s;
}

/* A box, a circle or a random polygon of size about 0.1 to 1 m. */
static kg_shape random_shape(int kind)
{
    if (kind == 0) {
        return build(kg_box_shape(uniform(0.1f, 1.0f), uniform(0.1f, 1.0f)));
    }
    if (kind == 1) {
        return build(kg_circle_shape(uniform(0.05f, 0.5f)));
    }
    kg_vec2 v[6];
    for (int i = 0; i < 6; ++i) {
        float a = 6.2831853f * ((float)i + uniform(0.0f, 0.8f)) / 6.0f, r = uniform(0.2f, 0.6f);
        v[i] = (kg_vec2){r * cosf(a), r * sinf(a)};
    }
    return build(kg_polygon_shape(v, 6));
}

static kg_xf random_pose(float spread)
{
    float a = uniform(-3.14159f, 3.14159f);
    kg_xf xf = {{uniform(-spread, spread), uniform(-spread, spread)}, {cosf(a), sinf(a)}};
    return xf;
}

/* Points every `step` metres along the shape's outline at xf (a circle's rim too). */
static int outline(const kg_shape* s, kg_xf xf, float step, kg_vec2* out, int room)
{
    int n = 0;
    if (s->count == 1) {
        kg_vec2 c = kg_xf_point(xf, s->vertices[0]);
        int k = (int)(6.2831853f * s->radius / step) + 8;
        for (int i = 0; i < k && n < room; ++i) {
            float a = 6.2831853f * (float)i / (float)k;
            out[n++] = (kg_vec2){c.x + s->radius * cosf(a), c.y + s->radius * sinf(a)};
        }
        return n;
    }
    for (int i = 0; i < s->count; ++i) {
        kg_vec2 a = kg_xf_point(xf, s->vertices[i]), b = kg_xf_point(xf, s->vertices[(i + 1) % s->count]);
        int k = (int)(kg_distance(a, b) / step) + 1;
        for (int j = 0; j < k && n < room; ++j) {
            out[n++] = kg_lerp(a, b, (float)j / (float)k);
        }
    }
    return n;
}

/* Whether shape a (at xa) holds b's first point (at xb). */
static int holds(const kg_shape* a, kg_xf xa, const kg_shape* b, kg_xf xb)
{
    kg_vec2 p = kg_xf_point(xb, b->vertices[0]);
    if (a->count == 1) {
        return kg_distance(p, kg_xf_point(xa, a->vertices[0])) < a->radius;
    }
    for (int i = 0; i < a->count; ++i) {
        if (kg_dot(kg_rotate(xa.q, a->normals[i]), kg_sub(p, kg_xf_point(xa, a->vertices[i]))) > 0.0f) {
            return 0;
        }
    }
    return 1;
}

#define ROOM 8192

/* 300 random pairs; 60 under the sanitizers (make test-sanitize sets KGYRO_SANITIZED),
 * where the sampled reference is slow and the release run covers the 300. */
static int pair_trials(void) { return getenv("KGYRO_SANITIZED") ? 60 : 300; }

static void test_distance_against_sampled_outlines(void)
{
    static kg_vec2 pa[ROOM], pb[ROOM];
    int separated = 0, wrong = 0, trials = pair_trials();
    double worst = 0.0;
    for (int trial = 0; trial < trials; ++trial) {
        kg_shape a = random_shape(trial % 3), b = random_shape((trial / 3) % 3);
        kg_xf xa = random_pose(1.0f), xb = random_pose(1.0f);
        kg_separation s = kg_shape_distance(&a, xa, &b, xb);
        int na = outline(&a, xa, 0.002f, pa, ROOM), nb = outline(&b, xb, 0.002f, pb, ROOM);
        double least = 1e30;
        for (int i = 0; i < na; ++i) {
            for (int j = 0; j < nb; ++j) {
                least = fmin(least, kg_distance(pa[i], pb[j]));
            }
        }
        if (s.distance > 0.0f) {
            separated += 1;
            /* sampled points lie on the outlines: their least distance is an upper bound,
             * within a sample's spacing of the true one */
            double off = least - (double)s.distance;
            worst = fmax(worst, fabs(off));
            wrong += off < -1e-5 || off > 2e-3;
        } else {
            /* overlapping outlines cross, or one shape holds the other */
            wrong += least > 2e-3 && !holds(&a, xa, &b, xb) && !holds(&b, xb, &a, xa);
        }
    }
    measured("distance: %d of %d random pairs separated, sampled reference within %.2g m of the exact "
             "distance, %d wrong\n", separated, trials, worst, wrong);
    KG_CHECK(separated > trials / 3);
    KG_CHECK(wrong == 0);
}

static void test_time_of_impact_against_sampled_sweeps(void)
{
    kg_toi_params prm = {0.005f, 0.00125f};
    int hits = 0, late = 0;
    double worst_early = 0.0;
    for (int trial = 0; trial < 300; ++trial) {
        kg_shape moving = random_shape(trial % 3), other = random_shape((trial / 3) % 3);
        kg_xf wall = random_pose(0.2f);
        kg_sweep s;
        s.local_center = moving.centroid;
        s.c1 = (kg_vec2){uniform(-4.0f, -2.0f), uniform(-1.0f, 1.0f)};
        s.c2 = (kg_vec2){uniform(2.0f, 4.0f), uniform(-1.0f, 1.0f)};
        float a1 = uniform(-3.0f, 3.0f), turn = trial % 2 ? uniform(-1.0f, 1.0f) : 0.0f;
        s.q1 = (kg_rot){cosf(a1), sinf(a1)};
        s.q2 = (kg_rot){cosf(a1 + turn), sinf(a1 + turn)};
        s.max_extent = kg_shape_max_extent(&moving, s.local_center);
        if (kg_shape_distance(&moving, kg_sweep_xf(&s, 0.0f), &other, wall).distance < 0.05f) {
            continue;
        }
        float t = kg_time_of_impact(&moving, &s, &other, wall, prm, 1.0f);
        /* the sampled times the shapes first come within the target, and within the
         * target and its tolerance (where the search may stop) */
        float within = 1.0f, near = 1.0f;
        for (int k = 2000; k >= 0; --k) {
            float u = (float)k / 2000.0f;
            float d = kg_shape_distance(&moving, kg_sweep_xf(&s, u), &other, wall).distance;
            within = d < prm.target ? u : within;
            near = d < prm.target + prm.tolerance ? u : near;
        }
        hits += t < 1.0f;
        float at = kg_shape_distance(&moving, kg_sweep_xf(&s, t), &other, wall).distance;
        late += at < prm.target - 1e-4f || t > within + 1e-6f;
        worst_early = fmax(worst_early, (double)(near - t) * kg_distance(s.c1, s.c2));
    }
    measured("time of impact: %d of 300 sweeps hit, %d ended closer than the target or after the sampled "
             "impact, stopped at most %.3g m of sweep early\n", hits, late, worst_early);
    KG_CHECK(hits > 100);
    KG_CHECK(late == 0);
    KG_CHECK(worst_early < 0.01);
}

int main(void)
{
    const kg_test_case tests[] = {KG_TEST(test_distance_against_sampled_outlines),
                                  KG_TEST(test_time_of_impact_against_sampled_sweeps)};
    return kg_run_tests(tests, (int)(sizeof tests / sizeof tests[0]));
}
