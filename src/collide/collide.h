/* Stage 2 of a step: find touching pairs (broadphase), compute their manifolds
 * (narrowphase) and carry impulses over from last step's contacts (persistence). */
#ifndef KG_COLLIDE_H
#define KG_COLLIDE_H

#include "core/world.h"
#include "kgyro/collision.h"


kg_result kg_collision_create(kg_world* world);
void kg_collision_destroy(kg_world* world);
kg_result kg_stage_collide(kg_world* world);

/* Copies accumulated impulses from old to m where the feature ids match. */
void kg_contact_carry_impulses(kg_manifold* m, const kg_manifold* old);

/* The contacts of the current step: body pairs sorted by (a, b), then tile contacts. */
kg_contact* kg_collision_contacts(kg_world* world, int* count);

#endif
