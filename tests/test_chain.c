/* Chains (collide/chain.h): one-sided segments that know their neighbours. A body sliding
 * along a straight run of many short segments must see only the run's normal, at every
 * join (no ghost collision); at a convex corner of a loop exactly one segment owns each
 * contact; a body behind a segment gets nothing from it; an open end is a free end. In a
 * world (kg_create_chain): a box sliding along 1,000 segments keeps its normal speed
 * under 1e-4 m/s; a bad chain is refused and changes nothing; the shape index finds for a
 * body pair what trying every shape finds, bit for bit. */
#include "kg_test.h"
#include "collide/chain.h"
#include "collide/shape.h"
#include "collide/collide.h"
#include "collide/shape_index.h"
#include "kgyro/kgyro.h"

#include <string.h>

static kg_shape built(kg_shape_def def)
{
    kg_shape s;
    KG_CHECK_OK(kg_shape_build(&def, &s));
    return s;
}

static kg_xf pose(float x, float y, float angle)
{
    kg_xf xf;
    xf.p = kg_v2(x, y);
    xf.q.c = cosf(angle);
    xf.q.s = sinf(angle);
    return xf;
}

static const kg_xf identity = {{0.0f, 0.0f}, {1.0f, 0.0f}};

/* The contacts of body at xf against every segment of the polyline: how many points, and
 * the largest deviation of their normals from expected. */
static void collide_along(const kg_vec2* points, int count, int loop, const kg_shape* body, kg_xf xf,
                          kg_vec2 expected, int* point_count, double* worst)
{
    KG_CHECK_OK(kg_check_chain_points(points, count, loop));
    *point_count = 0;
    int segments = loop ? count : count - 1;
    for (int i = 0; i < segments; ++i) {
        kg_shape seg = kg_chain_segment_build(points, count, loop, i);
        kg_manifold m = kg_collide_chain_segment(&seg, identity, body, xf, 0.02f);
        *point_count += m.point_count;
        if (m.point_count > 0) {
            double d = fabs((double)m.normal.x - expected.x) + fabs((double)m.normal.y - expected.y);
            *worst = d > *worst ? d : *worst;
        }
    }
}

enum { RUN = 1001 };

/* A straight run of 1,000 segments of 0.1 m along y = 0, listed right to left: solid on
 * the left of the direction (below), normal up. */
static void straight_run(kg_vec2* points)
{
    for (int i = 0; i < RUN; ++i) {
        points[i] = kg_v2(0.1f * (float)(RUN - 1 - i), 0.0f);
    }
}

static void test_box_sliding_along_a_run_sees_only_its_normal(void)
{
    static kg_vec2 points[RUN];
    straight_run(points);
    kg_shape box = built(kg_box_shape(0.5f, 0.5f));
    double worst = 0.0;
    int touching = 0, samples = 0;
    /* slightly sunk (1 mm), slightly tilted both ways, at positions that put its corners
     * on and near the joins */
    for (int k = 0; k < 2000; ++k) {
        float x = 1.0f + 0.0437f * (float)k;
        float angle = (k % 3 - 1) * 0.002f;
        int points_here = 0;
        collide_along(points, RUN, 0, &box, pose(x, 0.249f, angle), kg_v2(0.0f, 1.0f), &points_here, &worst);
        touching += points_here > 0;
        samples += 1;
    }
    measured("box on a 1000-segment run: %d of %d poses touching, largest normal deviation %.3g\n", touching,
             samples, worst);
    KG_CHECK(touching == samples);
    KG_CHECK(worst < 1e-6);
}

static void test_circle_rolling_along_a_run_sees_only_its_normal(void)
{
    static kg_vec2 points[RUN];
    straight_run(points);
    kg_shape ball = built(kg_circle_shape(0.3f));
    double worst = 0.0;
    int most = 0;
    for (int k = 0; k < 2000; ++k) {
        int points_here = 0;
        collide_along(points, RUN, 0, &ball, pose(1.0f + 0.0371f * (float)k, 0.299f, 0.0f), kg_v2(0.0f, 1.0f),
                      &points_here, &worst);
        most = points_here > most ? points_here : most;
    }
    KG_CHECK(worst < 1e-6);
    /* at a join both segments may report the same flat contact; never more */
    KG_CHECK(most <= 2);
}

static void test_capsule_sliding_along_a_run_sees_only_its_normal(void)
{
    static kg_vec2 points[RUN];
    straight_run(points);
    kg_shape capsule = built(kg_capsule_shape(kg_v2(-0.4f, 0.0f), kg_v2(0.4f, 0.0f), 0.2f));
    double worst = 0.0;
    int touching = 0;
    for (int k = 0; k < 2000; ++k) {
        int points_here = 0;
        collide_along(points, RUN, 0, &capsule, pose(1.0f + 0.0413f * (float)k, 0.199f, 0.0f), kg_v2(0.0f, 1.0f),
                      &points_here, &worst);
        touching += points_here > 0;
    }
    KG_CHECK(touching == 2000);
    KG_CHECK(worst < 1e-6);
}

static void test_body_behind_a_segment_gets_nothing(void)
{
    static kg_vec2 points[RUN];
    straight_run(points);
    kg_shape box = built(kg_box_shape(0.5f, 0.5f));
    double worst = 0.0;
    int touching = 0;
    collide_along(points, 20, 0, &box, pose(1.0f, -0.2f, 0.3f), kg_v2(0.0f, 1.0f), &touching, &worst);
    KG_CHECK(touching == 0);
}

/* A 2 m square loop, counter-clockwise (solid inside): a box resting on its top face next
 * to the convex corner gets the top's normal only; a box beyond the corner, off the
 * diagonal, touches it through exactly one segment, with a normal between the two faces'. */
static void test_convex_corner_of_a_loop(void)
{
    const kg_vec2 square[4] = {{0.0f, 0.0f}, {2.0f, 0.0f}, {2.0f, 2.0f}, {0.0f, 2.0f}};
    kg_shape box = built(kg_box_shape(0.5f, 0.5f));
    double worst = 0.0;
    int touching = 0;
    collide_along(square, 4, 1, &box, pose(1.9f, 2.249f, 0.0f), kg_v2(0.0f, 1.0f), &touching, &worst);
    KG_CHECK(touching == 2);
    KG_CHECK(worst < 1e-6);

    int owners = 0;
    kg_xf beyond = pose(2.0f + 0.25f * 0.7071f + 0.01f, 2.0f + 0.25f * 0.7071f + 0.01f, 0.7854f);
    for (int i = 0; i < 4; ++i) {
        kg_shape seg = kg_chain_segment_build(square, 4, 1, i);
        kg_manifold m = kg_collide_chain_segment(&seg, identity, &box, beyond, 0.05f);
        if (m.point_count > 0) {
            owners += 1;
            KG_CHECK(m.normal.x > 0.0f && m.normal.y > 0.0f);
        }
    }
    KG_CHECK(owners == 1);
}

/* An open chain's end is free: a ball just past the last point, level with the run,
 * touches the end vertex with a normal along the run. */
static void test_open_end_is_free(void)
{
    const kg_vec2 line[3] = {{0.0f, 0.0f}, {1.0f, 0.0f}, {2.0f, 0.0f}};
    kg_shape ball = built(kg_circle_shape(0.25f));
    kg_shape last = kg_chain_segment_build(line, 3, 0, 1);
    kg_manifold m = kg_collide_chain_segment(&last, identity, &ball, pose(2.26f, 0.0f, 0.0f), 0.02f);
    KG_CHECK(m.point_count == 1);
    KG_CHECK_NEAR(m.normal.x, 1.0f, 1e-6);
    KG_CHECK_NEAR(m.points[0].separation, 0.01f, 1e-5);
}

/* Far from the origin the segment's own frame keeps the arithmetic small: a box resting
 * 1 mm deep on a run at x = 100 km reads the same depth as at the origin. */
static void test_far_from_the_origin(void)
{
    const kg_vec2 far_line[3] = {{100002.0f, 0.0f}, {100001.0f, 0.0f}, {100000.0f, 0.0f}};
    kg_shape box = built(kg_box_shape(0.5f, 0.5f));
    kg_shape seg = kg_chain_segment_build(far_line, 3, 0, 1);
    kg_manifold m = kg_collide_chain_segment(&seg, identity, &box, pose(100000.5f, 0.249f, 0.0f), 0.02f);
    KG_CHECK(m.point_count == 2);
    for (int i = 0; i < m.point_count; ++i) {
        KG_CHECK_NEAR(m.points[i].separation, -0.001f, 1e-5);
    }
}

/* A frictionless box settles on a run of 1,000 segments of 0.1 m (on a static body made
 * without a shape), is pushed to 10 m/s along it and slides over 900 joins: a ghost bump
 * at any of them would throw it up at a good fraction of a metre a second. */
static void test_box_slides_along_a_chain_of_1000_segments(void)
{
    static kg_vec2 points[RUN];
    straight_run(points);
    kg_world_def wd = kg_default_world_def();
    wd.backend = KG_BACKEND_CPU;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&wd, &w));
    kg_body_def gd = kg_default_body_def();
    gd.type = KG_BODY_STATIC;
    kg_body ground;
    KG_CHECK_OK(kg_create_body(w, &gd, &ground));
    kg_chain_def cd = kg_default_chain_def();
    cd.points = points;
    cd.count = RUN;
    cd.friction = 0.0f;
    KG_CHECK_OK(kg_create_chain(w, ground, &cd, NULL));
    KG_CHECK(kg_body_shape_count(w, ground) == RUN - 1);

    kg_body_def bd = kg_default_body_def();
    bd.shape = kg_box_shape(0.5f, 0.5f);
    bd.position = kg_v2(2.0f, 0.25f);
    bd.friction = 0.0f;
    kg_body box;
    KG_CHECK_OK(kg_create_body(w, &bd, &box));
    for (int k = 0; k < 60; ++k) {
        KG_CHECK_OK(kg_world_step(w, 1.0f / 60.0f));
    }
    KG_CHECK_OK(kg_body_set_velocity(w, box, kg_v2(10.0f, 0.0f)));
    double worst = 0.0;
    kg_body_state st;
    for (int k = 0; k < 540; ++k) {
        KG_CHECK_OK(kg_world_step(w, 1.0f / 60.0f));
        KG_CHECK_OK(kg_body_get_state(w, box, &st));
        worst = fabs((double)st.velocity.y) > worst ? fabs((double)st.velocity.y) : worst;
    }
    measured("box sliding at 10 m/s over a 1000-segment chain for 9 s: x %.3f m, vx %.5f m/s, largest |vy| %.3g m/s, "
             "height %.5f m\n",
             st.position.x, st.velocity.x, worst, st.position.y);
    KG_CHECK(worst < 1e-4);
    KG_CHECK_NEAR(st.velocity.x, 10.0, 1e-3);
    KG_CHECK(st.position.x > 91.0f);
    kg_destroy_world(w);
}

/* A chain on a dynamic body, too few points, coincident points or a NaN are refused, and
 * the body keeps the shapes it had. */
static void test_bad_chains_are_refused(void)
{
    kg_world_def wd = kg_default_world_def();
    wd.backend = KG_BACKEND_CPU;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&wd, &w));
    kg_body_def bd = kg_default_body_def();
    bd.shape = kg_box_shape(1.0f, 1.0f);
    kg_body moving, ground;
    KG_CHECK_OK(kg_create_body(w, &bd, &moving));
    bd.type = KG_BODY_STATIC;
    KG_CHECK_OK(kg_create_body(w, &bd, &ground));
    const kg_vec2 good[3] = {{0.0f, 0.0f}, {1.0f, 0.0f}, {2.0f, 0.5f}};
    const kg_vec2 twice[3] = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 0.0f}};
    const kg_vec2 nan_point[3] = {{0.0f, 0.0f}, {NAN, 0.0f}, {2.0f, 0.0f}};
    kg_chain_def cd = kg_default_chain_def();
    cd.points = good;
    cd.count = 3;
    KG_CHECK(kg_create_chain(w, moving, &cd, NULL) == KG_ERROR_INVALID_ARGUMENT);
    cd.count = 1;
    KG_CHECK(kg_create_chain(w, ground, &cd, NULL) == KG_ERROR_INVALID_ARGUMENT);
    cd.count = 3;
    cd.points = twice;
    KG_CHECK(kg_create_chain(w, ground, &cd, NULL) == KG_ERROR_DEGENERATE_SHAPE);
    cd.points = nan_point;
    KG_CHECK(kg_create_chain(w, ground, &cd, NULL) == KG_ERROR_INVALID_ARGUMENT);
    cd.points = good;
    cd.friction = -1.0f;
    KG_CHECK(kg_create_chain(w, ground, &cd, NULL) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_body_shape_count(w, ground) == 1);
    KG_CHECK(kg_body_shape_count(w, moving) == 1);

    cd.friction = 0.6f;
    cd.loop = 1;
    kg_shape_id segments[3];
    KG_CHECK_OK(kg_create_chain(w, ground, &cd, segments));
    KG_CHECK(kg_body_shape_count(w, ground) == 4);
    for (int k = 0; k < 3; ++k) {
        kg_body_shape_def sd;
        KG_CHECK_OK(kg_shape_get_def(w, segments[k], &sd));
        KG_CHECK(sd.geometry.type == KG_SHAPE_SEGMENT);
        KG_CHECK_NEAR(sd.geometry.vertices[0].x, good[k].x, 0.0);
        KG_CHECK_NEAR(sd.geometry.vertices[1].x, good[(k + 1) % 3].x, 0.0);
    }
    kg_destroy_world(w);
}

/* A chain body of count points on a zigzag, listed from start by step. */
static kg_body zigzag_chain(kg_world* w, kg_body_type type, kg_vec2 at, float angle, kg_vec2 start, kg_vec2 step,
                            int count)
{
    static kg_vec2 points[400];
    for (int i = 0; i < count; ++i) {
        kg_vec2 across = kg_v2(-step.y, step.x);
        float wiggle = (i % 3 == 1) ? 0.6f : (i % 3 == 2 ? -0.3f : 0.0f);
        points[i] = kg_add(kg_add(start, kg_scale((float)i, step)), kg_scale(wiggle, across));
    }
    kg_body_def d = kg_default_body_def();
    d.type = type;
    d.position = at;
    d.angle = angle;
    d.velocity = type == KG_BODY_KINEMATIC ? kg_v2(1.0f, -0.5f) : kg_v2(0.0f, 0.0f);
    d.angular_velocity = type == KG_BODY_KINEMATIC ? 0.3f : 0.0f;
    kg_body b;
    KG_CHECK_OK(kg_create_body(w, &d, &b));
    kg_chain_def c = kg_default_chain_def();
    c.points = points;
    c.count = count;
    KG_CHECK_OK(kg_create_chain(w, b, &c, NULL));
    return b;
}

/* Every ordered pair of bodies: the pairs of shapes through the index and by trying every
 * shape (kg_expand_pair) are the same, in the same order. Returns how many it found. */
static int compare_expansions(kg_world* w, kg_shape_index* index, int* differing)
{
    static kg_shape_pair fast[4096], slow[4096];
    KG_CHECK_OK(kg_shape_index_update(index, w));
    kg_shape_arrays s = kg_world_shape_arrays(w);
    const kg_body_pool* p = &w->bodies;
    int total = 0;
    for (kg_u32 a = 0; a < (kg_u32)p->high_water; ++a) {
        for (kg_u32 b = 0; b < (kg_u32)p->high_water; ++b) {
            if (a == b || !kg_aabb_overlap(p->aabb[a], kg_aabb_fatten(p->aabb[b], 0.5f))) {
                continue;
            }
            int n = kg_shape_index_expand(index, w, a, b, fast, 4096);
            int m = kg_expand_pair(a, b, &s, p->xf, p->velocity, p->aabb, w->def.speculative_distance, w->last_dt,
                                   slow, 4096);
            *differing += n != m || memcmp(fast, slow, (size_t)(n < 4096 ? n : 4096) * sizeof *fast) != 0;
            total += m;
        }
    }
    return total;
}

/* A long static zigzag turned 0.3 rad, a tall one (indexed along y), a kinematic one
 * that moves and turns, a short chain (not indexed) and 150 boxes, balls and two-shape
 * bodies falling among them: at every 10th step of 120, the index and the plain search
 * agree on every pair of bodies. */
static void test_shape_index_finds_what_trying_every_shape_finds(void)
{
    kg_world_def wd = kg_default_world_def();
    wd.backend = KG_BACKEND_CPU;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&wd, &w));
    zigzag_chain(w, KG_BODY_STATIC, kg_v2(0.0f, 0.0f), 0.3f, kg_v2(20.0f, -2.0f), kg_v2(-0.25f, 0.0f), 200);
    zigzag_chain(w, KG_BODY_STATIC, kg_v2(-22.0f, 0.0f), 0.0f, kg_v2(0.0f, 20.0f), kg_v2(0.0f, -0.3f), 90);
    zigzag_chain(w, KG_BODY_KINEMATIC, kg_v2(-5.0f, 6.0f), 0.0f, kg_v2(5.0f, 0.0f), kg_v2(-0.2f, 0.0f), 60);
    zigzag_chain(w, KG_BODY_STATIC, kg_v2(10.0f, 8.0f), 0.0f, kg_v2(2.0f, 0.0f), kg_v2(-0.5f, 0.0f), 9);
    for (int k = 0; k < 150; ++k) {
        kg_body_def d = kg_default_body_def();
        d.position = kg_v2(-18.0f + 0.25f * (float)k, 4.0f + 2.0f * (float)(k % 7));
        d.angle = 0.37f * (float)k;
        d.shape = k % 3 == 0 ? kg_box_shape(0.5f, 0.3f) : kg_circle_shape(0.2f);
        kg_body b;
        KG_CHECK_OK(kg_create_body(w, &d, &b));
        if (k % 5 == 0) {
            kg_body_shape_def extra = kg_default_body_shape_def();
            extra.geometry = kg_offset_box_shape(0.6f, 0.1f, kg_v2(0.3f, 0.0f), 0.5f);
            kg_shape_id id;
            KG_CHECK_OK(kg_create_shape(w, b, &extra, &id));
        }
    }
    kg_shape_index* index = kg_shape_index_create();
    int differing = 0, found = 0;
    for (int step = 0; step <= 120; ++step) {
        if (step % 10 == 0) {
            found += compare_expansions(w, index, &differing);
        }
        KG_CHECK_OK(kg_world_step(w, 1.0f / 60.0f));
    }
    kg_shape_index_destroy(index);
    measured("shape index: %d pairs of shapes over 13 looks at every pair of bodies, %d body pairs differing\n", found,
             differing);
    KG_CHECK(differing == 0);
    KG_CHECK(found > 1000);
    kg_destroy_world(w);
}

int main(void)
{
    const kg_test_case tests[] = {
        KG_TEST(test_box_sliding_along_a_run_sees_only_its_normal),
        KG_TEST(test_circle_rolling_along_a_run_sees_only_its_normal),
        KG_TEST(test_capsule_sliding_along_a_run_sees_only_its_normal),
        KG_TEST(test_body_behind_a_segment_gets_nothing),
        KG_TEST(test_convex_corner_of_a_loop),
        KG_TEST(test_open_end_is_free),
        KG_TEST(test_far_from_the_origin),
        KG_TEST(test_box_slides_along_a_chain_of_1000_segments),
        KG_TEST(test_bad_chains_are_refused),
        KG_TEST(test_shape_index_finds_what_trying_every_shape_finds),
    };
    return kg_run_tests(tests, (int)(sizeof tests / sizeof tests[0]));
}
