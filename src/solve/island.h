/* Islands and rest, the pieces of sleeping shared by the CPU backend (solve/sleep.c) and
 * the kernels: when a body counts as at rest, and the union-find that groups bodies into
 * islands (bodies linked by contacts). docs/design.md, "Sleeping", tells the whole. */
#ifndef KG_ISLAND_H
#define KG_ISLAND_H

#include "core/kg_layout.h"
#include "solve/contact_solver.h"

/* The farthest a point of the shape lies from the centre of mass: the angular speed
 * times this is the fastest its surface moves. */
KG_FN float kg_shape_extent(const kg_shape* shape, kg_vec2 local_center)
{
    float far2 = 0.0f;
    for (int i = 0; i < shape->count; ++i) {
        kg_vec2 d = kg_sub(shape->vertices[i], local_center);
        far2 = fmaxf(far2, kg_dot(d, d));
    }
    return sqrtf(far2) + shape->radius;
}

/* How long a body has been at rest after a step that left it with velocities v, w and
 * moved it by dp, dq: reset whenever a point of it moves faster than sleep_speed, by its
 * velocity or by its motion over the step (a body pushed out of an overlap moves while
 * the relaxed velocity says it is still), and a slow spin counts as much as a drift. */
KG_FN float kg_rest_timer(float timer, kg_body_motion m, float extent, float dt, float sleep_speed)
{
    float limit = sleep_speed * dt;
    float spin = fmaxf(fabsf(m.w) * dt, fabsf(m.dq.s)) * extent;
    float drift = fmaxf(kg_length(m.v) * dt, kg_length(m.dp));
    return (drift > limit || spin > limit) ? 0.0f : timer + dt;
}

/* The island of body i: the root of its union-find tree, halving the path on the way. */
KG_FN kg_u32 kg_island_root(KG_GLOBAL kg_u32* parent, kg_u32 i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

/* Joins the islands of a and b under the lower root: every island ends up named by its
 * lowest slot, whatever order the links come in. */
KG_FN void kg_island_link(KG_GLOBAL kg_u32* parent, kg_u32 a, kg_u32 b)
{
    kg_u32 ra = kg_island_root(parent, a), rb = kg_island_root(parent, b);
    if (ra < rb) {
        parent[rb] = ra;
    } else if (rb < ra) {
        parent[ra] = rb;
    }
}

#endif
