/* Stage 3 of a step: the solver's sub-steps (integrate velocities, solve contacts,
 * integrate positions, relax), then restitution. See docs/design.md. */
#ifndef KG_SOLVER_H
#define KG_SOLVER_H

#include "core/world.h"

kg_result kg_solver_create(kg_world* world);
void kg_solver_destroy(kg_world* world);
void kg_stage_solve(kg_world* world, float dt);

/* Stage 4: derived state (origin transforms, bounds), forces cleared, and bodies whose
 * state became non-finite frozen so they cannot poison their neighbours. */
void kg_stage_finalize(kg_world* world);

#endif
