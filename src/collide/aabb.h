/* World bounds of a shape (shared by the CPU backend and the kernels). */
#ifndef KG_AABB_H
#define KG_AABB_H

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

#endif
