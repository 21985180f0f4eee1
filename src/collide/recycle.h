/* Contact recycling, shared by the CPU backend and the kernels: a body pair that touched
 * last step keeps its manifold while its relative pose has moved less than a tolerance
 * since the manifold was computed; only the points' positions and separations follow the
 * bodies, as the solver's sub-steps already do within a step. The narrowphase (a few
 * hundred operations a pair) then runs only for pairs that really moved: in a resting
 * pile almost none. The manifold kept in the contact is always the one rebuilt from its
 * base (kg_contact_base) at the current poses, whether the base is new or kept, so a
 * contact kept whole between two resting bodies is the same bits as one rebuilt. */
#ifndef KG_RECYCLE_H
#define KG_RECYCLE_H

#include "collide/chain.h"

/* Within these a pair's relative pose counts as unchanged: 2 mm, and a turn of 4 mrad
 * (2 mm at the corner of a 1 m box), under the 5 mm linear slop. Measured on the
 * 1000-body pile of boxes and balls: 1 mm and 2 mrad, all asleep at 8.6 s; these, 8.2 s;
 * 5 mm and 10 mrad (the newest engines' order), 24 s: stale manifolds kept the pile
 * creeping. */
#define KG_RECYCLE_DISTANCE 0.002f
#define KG_RECYCLE_SINE 0.004f

/* The base of a contact that is not recycled (a tile contact) or has no points: zeros. */
KG_FN kg_contact_base kg_no_contact_base(void)
{
    kg_contact_base base;
    for (int i = 0; i < 2; ++i) {
        base.point_a[i] = kg_v2(0.0f, 0.0f);
        base.point_b[i] = kg_v2(0.0f, 0.0f);
        base.separation[i] = 0.0f;
    }
    base.normal = kg_v2(0.0f, 0.0f);
    base.pose.p = kg_v2(0.0f, 0.0f);
    base.pose.q.c = 0.0f;
    base.pose.q.s = 0.0f;
    return base;
}

KG_FN kg_contact_base kg_contact_base_of(const kg_manifold* m, kg_xf xfa, kg_xf xfb)
{
    kg_contact_base base;
    base.pose = kg_xf_inv_mul(xfa, xfb);
    base.normal = kg_inv_rotate(xfa.q, m->normal);
    for (int i = 0; i < 2; ++i) {
        int has = i < m->point_count;
        base.point_a[i] = has ? kg_inv_rotate(xfa.q, m->points[i].anchor_a) : kg_v2(0.0f, 0.0f);
        base.point_b[i] = has ? kg_inv_rotate(xfb.q, m->points[i].anchor_b) : kg_v2(0.0f, 0.0f);
        base.separation[i] = has ? m->points[i].separation : 0.0f;
    }
    return base;
}

/* m's points (its point_count of them, their ids and impulses kept) placed from base at
 * the poses xfa and xfb: each point moves with both bodies; the separation grows by how
 * far its two copies moved apart along the normal, and the point sits midway between
 * them. In place, so that a contact kept whole is updated where it lies. */
KG_FN void kg_place_base_points(kg_manifold* m, const kg_contact_base* base, kg_xf xfa, kg_xf xfb)
{
    m->normal = kg_rotate(xfa.q, base->normal);
    kg_vec2 a_to_b = kg_sub(xfa.p, xfb.p);
    for (int i = 0; i < m->point_count && i < 2; ++i) {
        kg_vec2 ra = kg_rotate(xfa.q, base->point_a[i]);
        kg_vec2 rb = kg_rotate(xfb.q, base->point_b[i]);
        kg_vec2 apart = kg_sub(kg_sub(rb, ra), a_to_b); /* (pb + rb) - (pa + ra) */
        kg_manifold_point* mp = &m->points[i];
        mp->separation = base->separation[i] + kg_dot(apart, m->normal);
        mp->anchor_a = kg_mul_add(ra, 0.5f, apart);
        mp->anchor_b = kg_add(mp->anchor_a, a_to_b);
        mp->point = kg_add(xfa.p, mp->anchor_a);
        mp->normal_velocity = 0.0f;
        mp->total_normal_impulse = 0.0f;
    }
}

/* The manifold of base at the poses xfa and xfb, with the ids and point count of like. */
KG_FN kg_manifold kg_manifold_of_base(const kg_contact_base* base, const kg_manifold* like, kg_xf xfa, kg_xf xfb)
{
    kg_manifold m = kg_empty_manifold();
    m.point_count = like->point_count;
    for (int i = 0; i < like->point_count && i < 2; ++i) {
        m.points[i].id = like->points[i].id;
    }
    kg_place_base_points(&m, base, xfa, xfb);
    return m;
}

/* Whether b's pose in a's frame is still within the tolerances of the base's. */
KG_FN int kg_pose_kept(const kg_contact_base* base, kg_xf xfa, kg_xf xfb)
{
    kg_xf now = kg_xf_inv_mul(xfa, xfb);
    kg_vec2 moved = kg_sub(now.p, base->pose.p);
    float sine = base->pose.q.c * now.q.s - base->pose.q.s * now.q.c;
    float cosine = base->pose.q.c * now.q.c + base->pose.q.s * now.q.s;
    return kg_dot(moved, moved) <= KG_RECYCLE_DISTANCE * KG_RECYCLE_DISTANCE && fabsf(sine) <= KG_RECYCLE_SINE &&
           cosine > 0.0f;
}

/* kg_contact_carry_impulses for a manifold m kept from old: m is a copy of old, so each
 * point already holds old's impulses of its id (found without a search), but for a second
 * point that shares the first's id and so takes the first's. */
KG_FN int kg_carry_kept_impulses(kg_manifold* m, const kg_manifold* old)
{
    if (m->point_count == 2 && old->points[1].id == old->points[0].id) {
        m->points[1].normal_impulse = old->points[0].normal_impulse;
        m->points[1].tangent_impulse = old->points[0].tangent_impulse;
    }
    return m->point_count;
}

/* Whether a pair of these shapes may keep its manifold: only two polygons. A kept point
 * turns with its bodies, which is right for a corner but not for a round shape, whose
 * contact stays below its centre however it turns. A rolling ball's point, carried round
 * with it, gave the ball a lever arm that drove the roll (a pile of boxes and balls crept
 * and never fell asleep), and its manifold costs little to compute anyway. */
KG_FN int kg_recyclable(const kg_shape* a, const kg_shape* b) { return a->count >= 3 && b->count >= 3; }

/* The largest separation of m's points (-infinity with none; NaN when one is NaN, so that
 * such a manifold is never within a distance). */
KG_FN float kg_farthest_point(const kg_manifold* m)
{
    float farthest = -INFINITY;
    for (int i = 0; i < m->point_count; ++i) {
        float s = m->points[i].separation;
        farthest = farthest != farthest || s <= farthest ? farthest : s;
    }
    return farthest;
}

/* Last step's manifold m, computed at base, kept and moved to the poses xfa and xfb in
 * place when the pair has barely moved since base and every point stays within the
 * speculative distance. Returns 1 when kept; else m is to be computed anew. */
KG_FN int kg_keep_manifold(kg_manifold* m, const kg_contact_base* base, kg_xf xfa, kg_xf xfb, float speculative)
{
    if (!kg_pose_kept(base, xfa, xfb)) {
        return 0;
    }
    kg_place_base_points(m, base, xfa, xfb);
    return kg_farthest_point(m) <= speculative;
}

/* The manifold of a body pair and its base: last step's (old, may be NULL) kept when
 * kg_keep_manifold allows, else computed anew. Returns 1 when kept. */
KG_FN int kg_collide_or_recycle(const kg_shape* a, kg_xf xfa, const kg_shape* b, kg_xf xfb, float speculative,
                                const kg_contact* old, kg_manifold* m, kg_contact_base* base)
{
    if (old && old->manifold.keepable) {
        *m = old->manifold;
        if (kg_keep_manifold(m, &old->base, xfa, xfb, speculative)) {
            *base = old->base;
            return 1;
        }
    }
    kg_manifold fresh = kg_collide_shapes(a, xfa, b, xfb, speculative);
    if (fresh.point_count > 0) {
        *base = kg_contact_base_of(&fresh, xfa, xfb);
        *m = kg_manifold_of_base(base, &fresh, xfa, xfb);
    } else { /* apart (most pairs of a scattering crowd): no points to place */
        *base = kg_no_contact_base();
        *m = fresh;
    }
    m->keepable = kg_recyclable(a, b);
    return 0;
}

#endif
