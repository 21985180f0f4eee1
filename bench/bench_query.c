/* World query benchmark: what a short ray costs in a world of many bodies through the
 * query index (kgyro/query.h), against a scan that tries the ray on every shape.
 *
 *   bench_query [body_count ...]   (default: 1000 10000 100000)
 *
 * Random boxes and circles, static, at 0.6 bodies per square metre; rays of 2 m from
 * random points in random directions. Reported per query: the index's ray, the scan's,
 * their ratio, and an overlap box (4 m) and a circle cast (2 m), with the time to make
 * the index (paid by the first query after a step or an edit). */
#define _POSIX_C_SOURCE 200809L

#include "bench_util.h"
#include "collide/raycast.h"
#include "core/world.h"
#include "kgyro/kgyro.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define BODIES_PER_SQUARE_METRE 0.6f
#define RAY_LENGTH 2.0f
#define QUERIES 20000
#define SCANNED_RAYS 50

static uint32_t g_rng = 0x9E3779B9u;
static float random_range(float lo, float hi) { return bench_random_range(&g_rng, lo, hi); }

static kg_world* make_world(int count, float* side)
{
    kg_world_def wd = kg_default_world_def();
    wd.max_bodies = count;
    wd.backend = KG_BACKEND_CPU;
    kg_world* world = NULL;
    if (kg_create_world(&wd, &world) != KG_OK) {
        return NULL;
    }
    *side = sqrtf((float)count / BODIES_PER_SQUARE_METRE);
    for (int i = 0; i < count; ++i) {
        kg_body_def def = kg_default_body_def();
        def.type = KG_BODY_STATIC;
        float x = random_range(0.0f, *side), y = random_range(0.0f, *side);
        def.position = kg_v2(x, y);
        def.angle = random_range(-3.1f, 3.1f);
        def.shape = i % 2 ? kg_box_shape(random_range(0.2f, 1.0f), random_range(0.2f, 1.0f))
                          : kg_circle_shape(random_range(0.1f, 0.5f));
        kg_body body;
        kg_create_body(world, &def, &body);
    }
    return world;
}

/* The nearest hit of the ray over every shape, tried one by one. */
static float scan_ray(const kg_world* world, kg_ray ray)
{
    const kg_body_pool* p = &world->bodies;
    const kg_shape_pool* sp = &world->shapes;
    float best = 2.0f;
    for (int s = 0; s < sp->high_water; ++s) {
        if (kg_shape_alive(sp, s)) {
            kg_u32 i = sp->body[s];
            kg_ray_hit h = kg_ray_shape(kg_shape_geometry(p, sp, (kg_u32)s), kg_ray_in_frame(ray, p->xf[i]));
            best = h.hit && h.fraction < best ? h.fraction : best;
        }
    }
    return best;
}

static kg_ray random_ray(float side)
{
    kg_ray ray;
    ray.origin = kg_v2(random_range(0.0f, side), random_range(0.0f, side));
    float angle = random_range(-3.14159f, 3.14159f);
    ray.translation = kg_v2(RAY_LENGTH * cosf(angle), RAY_LENGTH * sinf(angle));
    ray.max_fraction = 1.0f;
    return ray;
}

static int count_found(kg_body body, kg_shape_id shape, void* user_data, void* ctx)
{
    (void)body;
    (void)shape;
    (void)user_data;
    *(int*)ctx += 1;
    return 1;
}

static void run(int count)
{
    float side = 0.0f;
    kg_world* world = make_world(count, &side);
    if (!world) {
        fprintf(stderr, "cannot make a world of %d bodies: %s\n", count, kg_last_error());
        return;
    }
    kg_query_filter filter = kg_default_query_filter();
    kg_ray_result r;
    double t0 = bench_now_ms();
    kg_world_cast_ray_closest(world, kg_v2(0.0f, 0.0f), kg_v2(1.0f, 0.0f), filter, &r); /* makes the index */
    double build_ms = bench_now_ms() - t0;
    int hits = 0;
    t0 = bench_now_ms();
    for (int k = 0; k < QUERIES; ++k) {
        kg_ray ray = random_ray(side);
        kg_world_cast_ray_closest(world, ray.origin, ray.translation, filter, &r);
        hits += r.hit;
    }
    double ray_us = 1000.0 * (bench_now_ms() - t0) / QUERIES;
    float sink = 0.0f;
    t0 = bench_now_ms();
    for (int k = 0; k < SCANNED_RAYS; ++k) {
        sink += scan_ray(world, random_ray(side));
    }
    double scan_us = 1000.0 * (bench_now_ms() - t0) / SCANNED_RAYS;
    int found = 0;
    t0 = bench_now_ms();
    for (int k = 0; k < QUERIES; ++k) {
        kg_vec2 c = kg_v2(random_range(0.0f, side), random_range(0.0f, side));
        kg_aabb box = {{c.x - 2.0f, c.y - 2.0f}, {c.x + 2.0f, c.y + 2.0f}};
        kg_world_overlap_aabb(world, box, filter, count_found, &found);
    }
    double box_us = 1000.0 * (bench_now_ms() - t0) / QUERIES;
    kg_shape_def ball = kg_circle_shape(0.25f);
    t0 = bench_now_ms();
    for (int k = 0; k < QUERIES; ++k) {
        kg_ray ray = random_ray(side);
        kg_world_cast_shape_closest(world, &ball, ray.origin, 0.0f, ray.translation, filter, &r);
    }
    double cast_us = 1000.0 * (bench_now_ms() - t0) / QUERIES;
    printf("%8d bodies: index made in %7.2f ms; 2 m ray %6.2f us (%4.1f%% hit), scan %9.1f us, ratio %7.0f; "
           "4 m box %6.2f us (%.1f found); 2 m circle cast %6.2f us%s\n",
           count, build_ms, ray_us, 100.0 * hits / QUERIES, scan_us, scan_us / ray_us, box_us,
           (double)found / QUERIES, cast_us, sink < 0.0f ? "!" : "");
    kg_destroy_world(world);
}

int main(int argc, char** argv)
{
    if (argc > 1) {
        for (int a = 1; a < argc; ++a) {
            run(atoi(argv[a]));
        }
        return 0;
    }
    run(1000);
    run(10000);
    run(100000);
    return 0;
}
