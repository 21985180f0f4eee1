/* The step: the stages of core/step.h, in order, on whichever backend the world runs.
 * A backend brackets them (the OpenCL backend uploads what the host changed and keeps a
 * checkpoint before, drains its queue after) and runs each one its own way: a loop over
 * the shared per-element code on the CPU, kernels on a device. docs/design.md, "The
 * stages of a step", tells the whole. */
#include "backend/backend.h"
#include "collide/events.h"
#include "core/error.h"
#include "core/joint.h"
#include "core/step.h"
#include "core/world.h"

#include <math.h>
#include <time.h>

static const char* const kg_stage_names[KG_STAGE_COUNT] = {"forces", "collide", "wake", "pre_solve", "solve",
                                                                   "finalize", "sleep"};

const char* kg_stage_name(kg_stage stage) { return kg_stage_names[stage]; }

double kg_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* The time since *start under the stage's label (none: the backend times it another way). */
static void kg_time_stage(kg_world* world, kg_stage stage, double* start)
{
    const kg_backend_ops* b = world->backend;
    const char* label = b->stage_label ? b->stage_label(world, stage) : kg_stage_name(stage);
    double now = kg_now_ms();
    kg_stage_times* t = &world->times;
    if (label && t->count < KG_MAX_STAGE_TIMES) {
        t->names[t->count] = label;
        t->ms[t->count] = now - *start;
        t->count += 1;
    }
    *start = now;
}

/* The stages once; *redo is set when the step must run again from its start (the
 * backend fell back to the CPU on a failure). */
static kg_result kg_run_stages(kg_world* world, float dt, int* redo)
{
    const kg_backend_ops* b = world->backend;
    world->times.count = 0;
    kg_result r = b->begin_step ? b->begin_step(world, dt) : KG_OK;
    double t = kg_now_ms();
    for (int s = 0; r == KG_OK && s < KG_STAGE_COUNT; ++s) {
        r = b->run_stage(world, (kg_stage)s, dt);
        kg_time_stage(world, (kg_stage)s, &t);
    }
    return b->end_step ? b->end_step(world, r, redo) : r;
}

kg_result kg_world_step(kg_world* world, float dt)
{
    if (!world) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_world_step: NULL world");
    }
    if (kg_world_refuses(world, "kg_world_step", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    if (!(isfinite(dt) && dt > 0.0f)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "time step must be finite and > 0 (got %g)", (double)dt);
    }
    world->last_dt = dt;
    kg_joints_begin_step(world);
    world->lock = KG_LOCK_STEP;
    int redo = 0;
    kg_result r = kg_run_stages(world, dt, &redo);
    if (redo) {
        r = kg_run_stages(world, dt, &redo);
    }
    world->lock = 0;
    if (r == KG_OK) {
        kg_joints_after_step(world); /* breakable joints past their thresholds */
        kg_shape_pool_free_held(&world->shapes); /* the new contacts name no shape destroyed before the step */
        r = world->sensor_shapes_made ? kg_sensors_after_step(world) : KG_OK;
    }
    world->step_index += 1;
    return r;
}
