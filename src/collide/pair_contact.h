/* A body pair's contact, shared by the CPU's narrowphase (collide/collide.c) and the
 * kernels (kg_collide.cl): last step's contact of the pair found in last step's list
 * (sorted by (a, b), like the pairs), the manifold computed or kept (collide/recycle.h),
 * and the contact's bodies and material. The CPU builds its contacts in place, a block
 * of pairs at a time; the device in two passes over the pairs, a manifold each, then,
 * after the prefix sum of those that touch, their contacts. */
#ifndef KG_PAIR_CONTACT_H
#define KG_PAIR_CONTACT_H

#include "collide/aabb.h"
#include "collide/recycle.h"
#include "core/kg_layout.h"

KG_FN int kg_pair_less(kg_u32 a0, kg_u32 b0, kg_u32 a1, kg_u32 b1) { return a0 < a1 || (a0 == a1 && b0 < b1); }

/* The first of last step's body contacts [0, count) not before the pair (a, b). */
KG_FN int kg_first_not_before(KG_GLOBAL const kg_contact* previous, int count, kg_u32 a, kg_u32 b)
{
    int lo = 0, hi = count;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (kg_pair_less(previous[mid].a, previous[mid].b, a, b)) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    return lo;
}

/* Whether previous[at] (at < count) is last step's contact of the pair (a, b): the same
 * two bodies, not others that took over their slots. */
KG_FN int kg_is_contact_of(KG_GLOBAL const kg_contact* previous, int count, int at, kg_u32 a, kg_u32 b,
                           KG_GLOBAL const kg_u32* generation)
{
    return at < count && previous[at].a == a && previous[at].b == b && previous[at].generation_a == generation[a] &&
           previous[at].generation_b == generation[b];
}

/* The pair's manifold and its base: kept from prev (last step's contact of the pair, or
 * NULL) while the pair barely moved, else computed, within the pair's speculative
 * distance. Returns 1 when kept. */
KG_FN int kg_pair_manifold(kg_u32 a, kg_u32 b, KG_GLOBAL const kg_shape* shape, KG_GLOBAL const kg_xf* xf,
                           KG_GLOBAL const kg_vec2* velocity, float speculative_distance, float dt,
                           const kg_contact* prev, kg_manifold* m, kg_contact_base* base)
{
    KG_PRIVATE_VIEW(kg_shape, sa, shape[a]);
    KG_PRIVATE_VIEW(kg_shape, sb, shape[b]);
    float speculative = kg_pair_speculative(speculative_distance, velocity[a], velocity[b], dt);
    return kg_collide_or_recycle(sa, xf[a], sb, xf[b], speculative, prev, m, base);
}

/* The contact's bodies, their generations and the pair's material. */
KG_FN void kg_contact_set_bodies(kg_contact* c, kg_u32 a, kg_u32 b, KG_GLOBAL const kg_u32* generation,
                                 KG_GLOBAL const float* friction, KG_GLOBAL const float* restitution)
{
    c->a = a;
    c->b = b;
    c->tile = KG_NULL_INDEX;
    c->generation_a = generation[a];
    c->generation_b = generation[b];
    c->friction = sqrtf(friction[a] * friction[b]);
    c->restitution = kg_maxf(restitution[a], restitution[b]);
    c->color = KG_NO_COLOR;
}

/* Last step's contact of pair (a, b) among its body contacts [0, count), or -1. */
KG_FN int kg_previous_contact(KG_GLOBAL const kg_contact* previous, int count, kg_u32 a, kg_u32 b,
                              KG_GLOBAL const kg_u32* generation)
{
    int at = kg_first_not_before(previous, count, a, b);
    return kg_is_contact_of(previous, count, at, a, b, generation) ? at : -1;
}

/* Whether pair k became a contact: index is the prefix sum of the pairs that touch. */
KG_FN int kg_pair_touches(KG_GLOBAL const kg_u32* index, int k) { return index[k + 1] != index[k]; }

/* Pair k, (a, b), on the device: its manifold and base, and whether it touches. */
KG_FN void kg_narrowphase_pair(int k, kg_u32 a, kg_u32 b, float speculative_distance, float dt,
                               KG_GLOBAL const kg_shape* shape, KG_GLOBAL const kg_xf* xf,
                               KG_GLOBAL const kg_vec2* velocity, KG_GLOBAL const kg_contact* previous,
                               int previous_count, KG_GLOBAL const kg_u32* generation,
                               KG_GLOBAL kg_manifold* manifolds, KG_GLOBAL kg_contact_base* bases,
                               KG_GLOBAL kg_u32* touching)
{
    int old = kg_previous_contact(previous, previous_count, a, b, generation);
    kg_contact last;
    if (old >= 0) {
        last = previous[old];
    }
    kg_manifold m;
    kg_contact_base base;
    kg_pair_manifold(a, b, shape, xf, velocity, speculative_distance, dt, old >= 0 ? &last : 0, &m, &base);
    manifolds[k] = m;
    bases[k] = base;
    touching[k] = m.point_count > 0 ? 1u : 0u;
}

/* Pair k, (a, b), on the device, if it touches: contact index[k] (the prefix sum keeps the
 * pairs' order), with last step's impulses and colour carried. */
KG_FN void kg_build_pair_contact(int k, kg_u32 a, kg_u32 b, KG_GLOBAL const kg_manifold* manifolds,
                                 KG_GLOBAL const kg_contact_base* bases, KG_GLOBAL const kg_u32* index,
                                 KG_GLOBAL const kg_contact* previous, int previous_count,
                                 KG_GLOBAL const kg_u32* generation, KG_GLOBAL const float* friction,
                                 KG_GLOBAL const float* restitution, KG_GLOBAL kg_contact* contacts)
{
    if (!kg_pair_touches(index, k)) {
        return;
    }
    kg_contact c;
    c.manifold = manifolds[k];
    c.base = bases[k];
    int old = kg_previous_contact(previous, previous_count, a, b, generation);
    kg_contact_set_bodies(&c, a, b, generation, friction, restitution);
    if (old >= 0) {
        KG_PRIVATE_VIEW(kg_manifold, carried, previous[old].manifold);
        kg_contact_carry_impulses(&c.manifold, carried);
        c.color = previous[old].color;
    }
    contacts[index[k]] = c;
}

#endif
