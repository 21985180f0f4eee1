/* Stage 2 of a step: find touching pairs (broadphase), compute their manifolds
 * (narrowphase) and carry impulses over from last step's contacts (persistence). */
#ifndef KG_COLLIDE_H
#define KG_COLLIDE_H

#include "core/world.h"
#include "kgyro/collision.h"

/* A persistent contact between two bodies (slots a < b). */
typedef struct kg_contact {
    kg_manifold manifold;
    kg_u32 a, b;
    float friction;     /* mixed: sqrt(fa * fb) */
    float restitution;  /* mixed: max(ra, rb) */
} kg_contact;

kg_result kg_collision_create(kg_world* world);
void kg_collision_destroy(kg_world* world);
kg_result kg_stage_collide(kg_world* world);

/* The contacts of the current step, sorted by (a, b). */
kg_contact* kg_collision_contacts(kg_world* world, int* count);

#endif
