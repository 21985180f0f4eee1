/* Snapshot benchmark: what kg_world_snapshot and kg_world_restore cost for a settled
 * rain of bodies (include/kgyro/snapshot.h).
 *
 *   bench_snapshot [body_count] [backend]   (default: 10000 cpu; backend cpu or opencl)
 *
 * Boxes and circles dropped on a ground box and stepped 300 times (sleeping on), so the
 * contact list is a pile's; then 200 snapshots into one buffer and 50 restores from it,
 * timed one by one. Reported: the snapshot's size, its median and fastest time, and the
 * restore's median. docs/benchmarks.md quotes the figure. */
#define _POSIX_C_SOURCE 200809L

#include "bench_util.h"
#include "kgyro/kgyro.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define SETTLE_STEPS 300
#define SNAPSHOTS 200
#define RESTORES 50

static uint32_t g_rng = 0x9E3779B9u;
static float random_range(float lo, float hi) { return bench_random_range(&g_rng, lo, hi); }

static kg_world* make_rain(int count, kg_backend backend)
{
    kg_world_def wd = kg_default_world_def();
    wd.max_bodies = count + 1;
    wd.backend = backend;
    kg_world* world = NULL;
    if (kg_create_world(&wd, &world) != KG_OK) {
        return NULL;
    }
    float width = 0.35f * (float)count / 40.0f;
    kg_body_def ground = kg_default_body_def();
    ground.type = KG_BODY_STATIC;
    ground.position = (kg_vec2){0.0f, -0.5f};
    ground.shape = kg_box_shape(width + 4.0f, 1.0f);
    kg_body body;
    kg_create_body(world, &ground, &body);
    for (int i = 0; i < count; ++i) {
        kg_body_def def = kg_default_body_def();
        def.position = (kg_vec2){random_range(-0.5f * width, 0.5f * width), 0.5f + 0.5f * (float)(i / 400)};
        def.shape = i % 2 ? kg_circle_shape(random_range(0.1f, 0.2f)) : kg_box_shape(random_range(0.2f, 0.4f), 0.25f);
        kg_create_body(world, &def, &body);
    }
    for (int s = 0; s < SETTLE_STEPS; ++s) {
        kg_world_step(world, 1.0f / 60.0f);
    }
    return world;
}

int main(int argc, char** argv)
{
    int count = argc > 1 ? atoi(argv[1]) : 10000;
    kg_backend backend = argc > 2 && strcmp(argv[2], "opencl") == 0 ? KG_BACKEND_OPENCL : KG_BACKEND_CPU;
    kg_world* world = count > 0 ? make_rain(count, backend) : NULL;
    size_t size = 0, written = 0;
    if (!world || kg_world_snapshot_size(world, &size) != KG_OK) {
        fprintf(stderr, "bench_snapshot: %s\n", kg_last_error());
        return 1;
    }
    void* buffer = malloc(size);
    static double taken[SNAPSHOTS], restored[RESTORES];
    for (int k = 0; k < SNAPSHOTS; ++k) {
        double t = bench_now_ms();
        kg_result r = kg_world_snapshot(world, buffer, size, &written);
        taken[k] = bench_now_ms() - t;
        if (r != KG_OK) {
            fprintf(stderr, "bench_snapshot: %s\n", kg_last_error());
            return 1;
        }
    }
    for (int k = 0; k < RESTORES; ++k) {
        double t = bench_now_ms();
        kg_result r = kg_world_restore(world, buffer, written);
        restored[k] = bench_now_ms() - t;
        if (r != KG_OK) {
            fprintf(stderr, "bench_snapshot: %s\n", kg_last_error());
            return 1;
        }
    }
    bench_sort(taken, SNAPSHOTS);
    bench_sort(restored, RESTORES);
    printf("bodies %d, contacts %d, backend %s: snapshot %.2f MB, snapshot median %.3f ms (fastest %.3f), "
           "restore median %.3f ms\n", count, kg_world_contact_count(world),
           backend == KG_BACKEND_CPU ? "cpu" : "opencl", (double)written / 1.0e6, taken[SNAPSHOTS / 2], taken[0],
           restored[RESTORES / 2]);
    free(buffer);
    kg_destroy_world(world);
    return 0;
}
