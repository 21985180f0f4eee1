/* KineticGyro: the contacts of the last step, for drawing and game logic. */
#ifndef KGYRO_COLLISION_H
#define KGYRO_COLLISION_H

#include "shape.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One touching (or speculatively close) pair of shapes. The normal points from a to b.
 * depth > 0 is penetration; depth < 0 is a gap within the speculative distance. A contact
 * with a tile map has b and shape_b null. */
typedef struct kg_contact_info {
    kg_body a, b;
    kg_shape_id shape_a, shape_b; /* the shapes that touch (null: a tile map's, or a shape
                                   * destroyed since the step) */
    kg_vec2 normal;
    int point_count;
    kg_vec2 points[2];          /* world frame */
    float depths[2];
    float normal_impulses[2];   /* of the last sub-step (N s); about 1/substeps of the step's */
    float tangent_impulses[2];
    float total_normal_impulses[2]; /* over the whole step, every sub-step's and the rebound's
                                     * (N s): a resting box of mass m gets m g dt in all */
    uint32_t feature_ids[2];
} kg_contact_info;

KG_API int kg_world_contact_count(const kg_world* world);
KG_API kg_result kg_world_get_contact(const kg_world* world, int index, kg_contact_info* out);

/* The pre-solve callback: called in each step, after the contacts are found and before
 * they are solved, for every contact of a body that asked for it (kg_body_def.
 * enable_pre_solve, kg_body_set_pre_solve), one call at a time in the contacts' order
 * (the same on every backend and thread count). Return 0 to switch the contact off for
 * this step (a one-way platform that lets a body through from below, a drop-through
 * platform), non-zero to keep it; contact is what kg_world_get_contact gives. A switched
 * off contact pushes nothing this step and starts cold when it comes back. The callback
 * may read the world (getters, queries) but not change it: a change fails with
 * KG_ERROR_LOCKED and changes nothing. On the OpenCL backend the step reads its contacts
 * back and writes the switched off ones to the device: pre-solve costs a round trip a
 * step there. */
typedef int kg_pre_solve_fn(const kg_contact_info* contact, void* context);
/* Sets the world's pre-solve callback (NULL: none). */
KG_API kg_result kg_world_set_pre_solve(kg_world* world, kg_pre_solve_fn* fn, void* context);

#ifdef __cplusplus
}
#endif
#endif
