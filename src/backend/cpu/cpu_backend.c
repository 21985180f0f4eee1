/* The CPU backend: each stage of the step (core/step.h) a loop over the shared
 * per-element code, on the world's thread pool. */
#include "backend/backend.h"
#include "backend/backend_state.h"
#include "collide/collide.h"
#include "solve/forces.h"
#include "solve/sleep.h"
#include "solve/solver.h"

static kg_result kg_cpu_run_stage(kg_world* world, kg_stage stage, float dt)
{
    switch (stage) {
    case KG_STAGE_FORCES: kg_stage_apply_forces(world); break;
    case KG_STAGE_COLLIDE: {
        kg_result r = kg_stage_collide(world);
        if (r != KG_OK) {
            return r;
        }
        kg_collision_mark_rested(world);
        break;
    }
    case KG_STAGE_WAKE: kg_stage_wake(world); break;
    case KG_STAGE_PRE_SOLVE: return kg_stage_pre_solve(world);
    case KG_STAGE_SOLVE: kg_stage_solve(world, dt); break;
    case KG_STAGE_FINALIZE: kg_stage_finalize(world); break;
    case KG_STAGE_SLEEP: kg_stage_sleep(world); break;
    case KG_STAGE_COUNT: break;
    }
    return KG_OK;
}

/* The backend state (device forces, profiling switch) that every world has is freed with
 * the world. */
const kg_backend_ops kg_cpu_backend = {.kind = KG_BACKEND_CPU, .name = "cpu", .run_stage = kg_cpu_run_stage,
                                       .destroy = kg_backend_state_free};
