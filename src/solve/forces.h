/* Stage 1 of a step: force applicators add to each body's force and torque. */
#ifndef KG_FORCES_H
#define KG_FORCES_H

#include "core/world.h"
#include "solve/body_step.h"

void kg_stage_apply_forces(kg_world* world);

/* The live bodies an applicator applies to (every live body, or the live ones of its
 * list in list order), written into world->handle_scratch; returns how many. */
int kg_applicator_targets(kg_world* world, const kg_applicator_slot* a);

/* A gravity or wind applicator as the per-body function (and its kernel) takes it. */
kg_builtin_force kg_builtin_force_of(const kg_applicator_slot* a);

#endif
