/* World bounds of a shape (shared by the CPU backend and the kernels). */
#ifndef KG_AABB_H
#define KG_AABB_H

#include "core/body_flags.h"
#include "core/kg_layout.h"

KG_FN kg_aabb kg_shape_aabb(const kg_shape* shape, kg_xf xf)
{
    kg_vec2 lower = kg_xf_point(xf, shape->vertices[0]);
    kg_vec2 upper = lower;
    for (int i = 1; i < shape->count; ++i) {
        kg_vec2 v = kg_xf_point(xf, shape->vertices[i]);
        lower = kg_vmin(lower, v);
        upper = kg_vmax(upper, v);
    }
    kg_vec2 r = kg_v2(shape->radius, shape->radius);
    kg_aabb box;
    box.lower = kg_sub(lower, r);
    box.upper = kg_add(upper, r);
    return box;
}

KG_FN kg_aabb kg_aabb_fatten(kg_aabb box, float margin)
{
    kg_vec2 m = kg_v2(margin, margin);
    box.lower = kg_sub(box.lower, m);
    box.upper = kg_add(box.upper, m);
    return box;
}

/* Bounds swept over the motion expected in the next step, so the broadphase pairs a
 * fast body with what it is about to reach. */
KG_FN kg_aabb kg_aabb_sweep(kg_aabb box, kg_vec2 displacement)
{
    kg_aabb swept;
    swept.lower = kg_vmin(box.lower, kg_add(box.lower, displacement));
    swept.upper = kg_vmax(box.upper, kg_add(box.upper, displacement));
    return swept;
}

/* Largest speculative distance, as a multiple of the base one: enough for bounces within
 * 1.6% of restitution squared (a ball falling 0.13 m a step), while a body at hundreds
 * of m/s does not pair with everything in metres around it. Its separating-axis
 * "separation" is a lower bound of the distance, so a larger margin can stop a body
 * short (a ghost contact) but never push it. */
#define KG_MAX_SPECULATIVE_SCALE 4.0f

/* How close a pair must come to get a speculative contact: the base distance plus how
 * far they can close in one step, up to a cap. With the base alone, a ball falling
 * 0.1 m a step sank up to 8 cm before its contact existed, and bounced 5% low. */
KG_FN float kg_pair_speculative(float base, kg_vec2 va, kg_vec2 vb, float dt)
{
    return kg_minf(base + dt * kg_length(kg_sub(vb, va)), KG_MAX_SPECULATIVE_SCALE * base);
}

/* A body's broadphase box: its bounds fattened by margin. Returns whether it takes part:
 * alive, with finite bounds. A frozen body stays where it froze, as solid as a static
 * one; a sleeping one keeps its contacts, so that its stack wakes warm. */
KG_FN int kg_broadphase_box(kg_u32 flags, kg_aabb bounds, float margin, kg_aabb* box)
{
    *box = kg_aabb_fatten(bounds, margin);
    return kg_flags_alive(flags) && kg_vec_is_finite(box->lower) && kg_vec_is_finite(box->upper);
}

/* Whether two broadphase boxes make a pair: one of them moves, they overlap, and each
 * one's filter accepts the other's category. */
KG_FN int kg_boxes_pair(int moves_p, kg_aabb box_p, kg_u32 category_p, kg_u32 mask_p, int moves_q, kg_aabb box_q,
                        kg_u32 category_q, kg_u32 mask_q)
{
    /* bitwise, not &&: see kg_aabb_overlap */
    return ((moves_p | moves_q) != 0) & kg_aabb_overlap(box_p, box_q) & ((category_p & mask_q) != 0u) &
           ((category_q & mask_p) != 0u);
}

#endif
