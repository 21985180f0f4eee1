/* The CPU backend: the step as a short list of stages, each looping over the shared
 * per-element code. */
#include "backend/backend.h"
#include "collide/collide.h"
#include "solve/forces.h"
#include "solve/sleep.h"
#include "solve/solver.h"

#include <time.h>

static double kg_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static void kg_time_stage(kg_world* world, const char* name, double* start)
{
    double now = kg_now_ms();
    kg_stage_times* t = &world->times;
    t->names[t->count] = name;
    t->ms[t->count] = now - *start;
    t->count += 1;
    *start = now;
}

static kg_result kg_cpu_step(kg_world* world, float dt)
{
    world->times.count = 0;
    double t = kg_now_ms();
    kg_stage_apply_forces(world);
    kg_time_stage(world, "forces", &t);
    kg_result r = kg_stage_collide(world);
    if (r != KG_OK) {
        return r;
    }
    kg_collision_mark_rested(world);
    kg_time_stage(world, "collide", &t);
    kg_stage_wake(world);
    kg_time_stage(world, "wake", &t);
    kg_stage_solve(world, dt);
    kg_time_stage(world, "solve", &t);
    kg_stage_finalize(world);
    kg_time_stage(world, "finalize", &t);
    kg_stage_sleep(world);
    kg_time_stage(world, "sleep", &t);
    return KG_OK;
}

const kg_backend_ops kg_cpu_backend = {KG_BACKEND_CPU, "cpu", kg_cpu_step, NULL, NULL, NULL, NULL};
