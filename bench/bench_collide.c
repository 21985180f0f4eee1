/* Collision benchmark: broadphase and narrowphase time per step for growing body counts
 * at a constant density, so the per-body cost shows how each stage scales.
 *
 *   bench_collide [body_count ...]   (default: 1000 10000 100000)
 *
 * Random boxes and circles, mostly not touching, drift a little every step; the
 * broadphase pairs are then turned into manifolds by the narrowphase. */
#define _POSIX_C_SOURCE 200809L

#include "bench_util.h"
#include "collide/broadphase.h"
#include "collide/chain.h"
#include "collide/shape.h"
#include "core/body_pool.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define BODIES_PER_SQUARE_METRE 0.6f
#define MARGIN 0.1f
#define SPECULATIVE_DISTANCE 0.02f
#define WARMUP_STEPS 3
#define MAX_STEPS 100

typedef struct bench_scene {
    kg_body_pool pool;
    kg_vec2* drift; /* m per step */
    float side;     /* the bodies stay in [0, side]^2 */
    kg_u32 rng;
} bench_scene;

/* Per step: the median time, which a busy machine disturbs less than the mean. */
typedef struct bench_result {
    double broadphase_ms;
    double narrowphase_ms;
    double pairs;    /* mean */
    double touching; /* mean of the pairs whose manifold has points */
} bench_result;

static float random_range(bench_scene* s, float lo, float hi) { return bench_random_range(&s->rng, lo, hi); }

/* Two draws in a fixed order (the order of a call's arguments is unspecified in C). */
static kg_vec2 random_vec(bench_scene* s, float lo, float hi)
{
    float x = random_range(s, lo, hi);
    float y = random_range(s, lo, hi);
    return kg_v2(x, y);
}

/* Half boxes (0.2 to 1 m sides, any angle), half circles (0.1 to 0.5 m radius). */
static kg_shape_def random_shape(bench_scene* s, int k)
{
    if (k % 2 == 0) {
        return kg_circle_shape(random_range(s, 0.1f, 0.5f));
    }
    kg_vec2 size = random_vec(s, 0.2f, 1.0f);
    return kg_box_shape(size.x, size.y);
}

static int create_scene(bench_scene* s, int count)
{
    s->rng = 0x9E3779B9u;
    s->side = sqrtf((float)count / BODIES_PER_SQUARE_METRE);
    s->drift = malloc((size_t)count * sizeof *s->drift);
    if (!s->drift || kg_body_pool_init(&s->pool, count) != KG_OK) {
        return 0;
    }
    kg_body_pool* p = &s->pool;
    for (int k = 0; k < count; ++k) {
        int i = kg_body_pool_acquire(p);
        kg_shape_def def = random_shape(s, k);
        if (i < 0 || kg_shape_build(&def, &p->shape[i]) != KG_OK) {
            return 0;
        }
        p->flags[i] = KG_FLAG_ALIVE | ((kg_u32)KG_BODY_DYNAMIC << KG_TYPE_SHIFT);
        p->category[i] = 1u;
        p->mask[i] = 0xFFFFFFFFu;
        p->center[i] = random_vec(s, 0.0f, s->side);
        float angle = random_range(s, -3.14159f, 3.14159f);
        p->rot[i].c = cosf(angle);
        p->rot[i].s = sinf(angle);
        s->drift[i] = random_vec(s, -0.02f, 0.02f);
        kg_body_update_transform(p, i);
    }
    return 1;
}

static void destroy_scene(bench_scene* s)
{
    kg_body_pool_free(&s->pool);
    free(s->drift);
}

/* Drifts every body, bouncing off the region's sides, and turns it a little. */
static void move_scene(bench_scene* s)
{
    kg_body_pool* p = &s->pool;
    const kg_rot turn = kg_rot_normalize((kg_rot){.c = 1.0f, .s = 0.01f}); /* about 0.01 rad */
    for (int i = 0; i < p->high_water; ++i) {
        kg_vec2 c = kg_add(p->center[i], s->drift[i]);
        if (c.x < 0.0f || c.x > s->side) {
            s->drift[i].x = -s->drift[i].x;
        }
        if (c.y < 0.0f || c.y > s->side) {
            s->drift[i].y = -s->drift[i].y;
        }
        p->center[i] = c;
        p->rot[i] = kg_rot_normalize(kg_rot_mul(turn, p->rot[i]));
        kg_body_update_transform(p, i);
    }
}

/* Finds the pairs, growing the buffer when the broadphase reports more than fit. */
static int find_pairs(kg_broadphase* bp, const kg_body_pool* pool, kg_pair** pairs, int* capacity)
{
    int count = kg_broadphase_find_pairs(bp, pool, MARGIN, *pairs, *capacity);
    if (count <= *capacity) {
        return count;
    }
    free(*pairs);
    *capacity = count + count / 2;
    *pairs = malloc((size_t)*capacity * sizeof **pairs);
    return *pairs ? kg_broadphase_find_pairs(bp, pool, MARGIN, *pairs, *capacity) : 0;
}

/* Manifolds of every pair; returns how many have contact points. */
static int collide_pairs(const kg_body_pool* pool, const kg_pair* pairs, int count)
{
    int touching = 0;
    for (int k = 0; k < count; ++k) {
        kg_u32 a = pairs[k].a, b = pairs[k].b;
        kg_manifold m =
            kg_collide_shapes(&pool->shape[a], pool->xf[a], &pool->shape[b], pool->xf[b], SPECULATIVE_DISTANCE);
        touching += m.point_count > 0;
    }
    return touching;
}

static int run_case(int count, int steps, bench_result* result)
{
    bench_scene scene;
    kg_broadphase* bp = NULL;
    int pair_capacity = 4 * count;
    kg_pair* pairs = malloc((size_t)pair_capacity * sizeof *pairs);
    if (!pairs || !create_scene(&scene, count) || kg_broadphase_create(count, &bp) != KG_OK) {
        return 0;
    }
    double broadphase_ms[MAX_STEPS], narrowphase_ms[MAX_STEPS];
    double pair_sum = 0.0, touching_sum = 0.0;
    for (int step = -WARMUP_STEPS; step < steps; ++step) {
        move_scene(&scene);
        double t0 = bench_now_ms();
        int pair_count = find_pairs(bp, &scene.pool, &pairs, &pair_capacity);
        double t1 = bench_now_ms();
        int touching = collide_pairs(&scene.pool, pairs, pair_count);
        double t2 = bench_now_ms();
        if (step >= 0) {
            broadphase_ms[step] = t1 - t0;
            narrowphase_ms[step] = t2 - t1;
            pair_sum += pair_count;
            touching_sum += touching;
        }
    }
    result->broadphase_ms = bench_median(broadphase_ms, steps);
    result->narrowphase_ms = bench_median(narrowphase_ms, steps);
    result->pairs = pair_sum / steps;
    result->touching = touching_sum / steps;
    kg_broadphase_destroy(bp);
    destroy_scene(&scene);
    free(pairs);
    return 1;
}

int main(int argc, char** argv)
{
    int default_counts[] = {1000, 10000, 100000};
    int case_count = argc > 1 ? argc - 1 : 3;
    printf("%9s %9s %9s %14s %14s %14s %14s\n", "bodies", "pairs", "touching", "broad ms/step", "broad us/body",
           "narrow ms/step", "narrow us/body");
    for (int c = 0; c < case_count; ++c) {
        int count = argc > 1 ? atoi(argv[c + 1]) : default_counts[c];
        if (count <= 0) {
            fprintf(stderr, "bad body count '%s'\n", argv[c + 1]);
            return 1;
        }
        int steps = count >= 100000 ? 20 : MAX_STEPS;
        bench_result r;
        if (!run_case(count, steps, &r)) {
            fprintf(stderr, "cannot set up %d bodies\n", count);
            return 1;
        }
        printf("%9d %9.0f %9.0f %14.3f %14.4f %14.3f %14.4f\n", count, r.pairs, r.touching, r.broadphase_ms,
               1000.0 * r.broadphase_ms / count, r.narrowphase_ms, 1000.0 * r.narrowphase_ms / count);
    }
    return 0;
}
