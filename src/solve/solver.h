/* Stage 3 of a step: the solver's sub-steps (integrate velocities, solve contacts,
 * integrate positions, relax), then restitution. See docs/design.md. */
#ifndef KG_SOLVER_H
#define KG_SOLVER_H

#include "core/world.h"
#include "collide/continuous.h"
#include "solve/body_step.h"

kg_result kg_solver_create(kg_world* world);
void kg_solver_destroy(kg_world* world);
/* Forgets what the solver keeps from step to step for speed (continuous collision's list
 * of the static bodies, the bodies' extents): a restored snapshot may carry the edit
 * counts and versions they were made at, with other bodies. */
void kg_solver_forget(kg_world* world);
void kg_stage_solve(kg_world* world, float dt);

/* The solver's parameters for sub-steps of length h: both backends use this one. */
kg_solver_params kg_solver_params_of(const kg_world_def* def, float h);
/* How the end of a step of dt keeps the rest timers: both backends use this one. */
kg_rest_params kg_rest_params_of(const kg_world_def* def, float dt);

/* What continuous collision's time of impact searches aim at: both backends use this one. */
kg_toi_params kg_toi_params_of(const kg_world_def* def);

/* Continuous collision's index of the static bodies (collide/continuous.h), with the live
 * bullets' count and world->static_edits when it was made (the OpenCL backend uploads it
 * when that changes). */
typedef struct kg_static_list {
    kg_static_entry* entries; /* count long, the first large_count the large ones */
    int count;
    int large_count;
    int bullets;
    kg_u32 edits;
} kg_static_list;
kg_static_list kg_continuous_statics(kg_world* world);

/* Stage 4: derived state (origin transforms, bounds), forces cleared, and bodies whose
 * state became non-finite frozen so they cannot poison their neighbours. */
void kg_stage_finalize(kg_world* world);

#endif
