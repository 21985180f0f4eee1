/* A body pair's contact, shared by the CPU's narrowphase (collide/collide.c) and the
 * kernels (kg_collide.cl): last step's contact of the pair found in last step's list
 * (sorted by (a, b), like the pairs), the manifold computed or kept (collide/recycle.h),
 * and the contact's bodies and material. */
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
    c->pad = 0u;
}

#endif
