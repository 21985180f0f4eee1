/* Stage 1 of a step: force applicators add to each body's force and torque. */
#ifndef KG_FORCES_H
#define KG_FORCES_H

#include "core/world.h"

void kg_stage_apply_forces(kg_world* world);

#endif
