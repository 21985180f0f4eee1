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

#ifdef __cplusplus
}
#endif
#endif
