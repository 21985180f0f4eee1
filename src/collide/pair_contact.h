/* A pair of shapes' contact, shared by the CPU's narrowphase (collide/collide.c) and the
 * kernels (kg_collide.cl): a pair of bodies expanded into the pairs of their shapes that
 * may touch, last step's contact of a pair found in last step's list (sorted by (a, b,
 * shape_a, shape_b), like the pairs), the manifold computed or kept (collide/recycle.h),
 * and the contact's bodies, shapes and material. The CPU builds its contacts in place, a
 * block of pairs at a time; the device in two passes over the pairs, a manifold each,
 * then, after the prefix sum of those that touch, their contacts. */
#ifndef KG_PAIR_CONTACT_H
#define KG_PAIR_CONTACT_H

#include "collide/aabb.h"
#include "collide/recycle.h"
#include "core/kg_layout.h"

/* What names a body contact, and orders the list: its two bodies (slots a < b), then its
 * two shapes (slots of the shape pool, core/shape_pool.h). A pair of one-shape bodies has
 * one key; a pair with a compound body has one per pair of shapes that may touch. */
typedef struct kg_shape_pair {
    kg_u32 a, b;
    kg_u32 shape_a, shape_b;
} kg_shape_pair;

KG_FN kg_shape_pair kg_shape_pair_make(kg_u32 a, kg_u32 b, kg_u32 shape_a, kg_u32 shape_b)
{
    kg_shape_pair k;
    k.a = a;
    k.b = b;
    k.shape_a = shape_a;
    k.shape_b = shape_b;
    return k;
}

KG_FN kg_shape_pair kg_contact_key(KG_GLOBAL const kg_contact* c)
{
    return kg_shape_pair_make(c->a, c->b, c->shape_a, c->shape_b);
}

/* (a, b) as one 64-bit key, ordered as the pair is: pairs compare in one comparison,
 * where || and && branched (the smash's narrowphase: 0.5 M instructions a step fewer,
 * callgrind). */
KG_FN kg_u64 kg_pair_key(kg_u32 a, kg_u32 b) { return ((kg_u64)a << 32) | b; }

KG_FN int kg_pair_less(kg_u32 a0, kg_u32 b0, kg_u32 a1, kg_u32 b1) { return kg_pair_key(a0, b0) < kg_pair_key(a1, b1); }

KG_FN int kg_shape_pair_less(kg_shape_pair p, kg_shape_pair q)
{
    kg_u64 bodies_p = kg_pair_key(p.a, p.b), bodies_q = kg_pair_key(q.a, q.b);
    return (bodies_p < bodies_q) | ((bodies_p == bodies_q) & kg_pair_less(p.shape_a, p.shape_b, q.shape_a, q.shape_b));
}

/* The first of last step's body contacts [0, count) not before key. */
KG_FN int kg_first_not_before(KG_GLOBAL const kg_contact* previous, int count, kg_shape_pair key)
{
    int lo = 0, hi = count;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (kg_shape_pair_less(kg_contact_key(&previous[mid]), key)) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    return lo;
}

/* Whether previous[at] (at < count) is last step's contact of key: the same two shapes
 * of the same two bodies, not of others that took over their slots. */
KG_FN int kg_is_contact_of(KG_GLOBAL const kg_contact* previous, int count, int at, kg_shape_pair key,
                           KG_GLOBAL const kg_u32* generation)
{
    return at < count && previous[at].a == key.a && previous[at].b == key.b && previous[at].shape_a == key.shape_a &&
           previous[at].shape_b == key.shape_b && previous[at].generation_a == generation[key.a] &&
           previous[at].generation_b == generation[key.b];
}

/* The manifold of shape_a of body a and shape_b of body b (each in its body's frame) and
 * its base: kept from prev (last step's contact of the pair, or NULL) while the pair
 * barely moved, else computed, within the pair's speculative distance. Returns 1 when
 * kept. */
KG_FN int kg_pair_manifold(kg_u32 a, kg_u32 b, KG_GLOBAL const kg_shape* shape_a, KG_GLOBAL const kg_shape* shape_b,
                           KG_GLOBAL const kg_xf* xf, KG_GLOBAL const kg_vec2* velocity, float speculative_distance,
                           float dt, const kg_contact* prev, kg_manifold* m, kg_contact_base* base)
{
    KG_PRIVATE_VIEW(kg_shape, sa, *shape_a);
    KG_PRIVATE_VIEW(kg_shape, sb, *shape_b);
    float speculative = kg_pair_speculative(speculative_distance, velocity[a], velocity[b], dt);
    return kg_collide_or_recycle(sa, xf[a], sb, xf[b], speculative, prev, m, base);
}

/* The contact's bodies a, b and shapes sa, sb, the bodies' generations and the shapes'
 * mixed material (friction fa, fb and restitution ra, rb). */
KG_FN void kg_contact_set_bodies(kg_contact* c, kg_u32 a, kg_u32 b, kg_u32 sa, kg_u32 sb,
                                 KG_GLOBAL const kg_u32* generation, float fa, float fb, float ra, float rb)
{
    c->a = a;
    c->b = b;
    c->shape_a = sa;
    c->shape_b = sb;
    c->tile = KG_NULL_INDEX;
    c->generation_a = generation[a];
    c->generation_b = generation[b];
    c->friction = sqrtf(fa * fb);
    c->restitution = kg_maxf(ra, rb);
    c->color = KG_NO_COLOR;
}

/* Last step's contact of key among its body contacts [0, count), or -1. */
KG_FN int kg_previous_contact(KG_GLOBAL const kg_contact* previous, int count, kg_shape_pair key,
                              KG_GLOBAL const kg_u32* generation)
{
    int at = kg_first_not_before(previous, count, key);
    return kg_is_contact_of(previous, count, at, key, generation) ? at : -1;
}

/* What the pairs of shapes read of the shapes (core/shape_pool.h), on either side. */
typedef struct kg_shape_arrays {
    KG_GLOBAL const kg_u32* shape_count; /* per body */
    KG_GLOBAL const kg_u32* first_shape; /* per body */
    KG_GLOBAL const kg_shape* body_shape; /* per body: a one-shape body's shape */
    KG_GLOBAL const kg_shape* geometry;   /* per shape slot: a compound body's shape */
    KG_GLOBAL const kg_u32* next;         /* per shape slot: its body's next shape */
    KG_GLOBAL const kg_u32* flags;
    KG_GLOBAL const kg_u32* category;
    KG_GLOBAL const kg_u32* mask;
} kg_shape_arrays;

/* Shape s of body i: the shape pool's geometry for a compound body's, the body pool's
 * shape for a body's only one. */
KG_FN KG_GLOBAL const kg_shape* kg_shape_of(const kg_shape_arrays* s, kg_u32 i, kg_u32 shape)
{
    return s->shape_count[i] > 1u ? &s->geometry[shape] : &s->body_shape[i];
}

/* Whether shapes sa and sb may collide: both solid, their filters agreeing. */
KG_FN int kg_shapes_pair(const kg_shape_arrays* s, kg_u32 sa, kg_u32 sb)
{
    /* A sensor never makes a contact; its overlap events (issue 13) are to be found here,
     * from the same pairs of shapes. */
    if (((s->flags[sa] | s->flags[sb]) & KG_SHAPE_SENSOR) != 0u) {
        return 0;
    }
    return (s->category[sa] & s->mask[sb]) != 0u && (s->category[sb] & s->mask[sa]) != 0u;
}

/* Shape i's bounds at xf (body i's transform) fattened by margin: a shape of a body pair
 * reaches the other's shapes within them. */
KG_FN kg_aabb kg_shape_reach(const kg_shape_arrays* s, kg_u32 i, kg_u32 shape, kg_xf xf, float margin)
{
    KG_PRIVATE_VIEW(kg_shape, view, *kg_shape_of(s, i, shape));
    return kg_aabb_fatten(kg_shape_aabb(view, xf), margin);
}

/* The pair (sa, sb) of bodies (a, b), counted in *n and written below room, when the
 * shapes may collide and shape_b's bounds at xf_b meet box_a, shape sa's reach. One test
 * for kg_expand_pair and the CPU's shape index (collide/shape_index.c), so that both find
 * the same pairs, bit for bit. */
KG_FN void kg_offer_shape_pair(const kg_shape_arrays* s, kg_aabb box_a, const kg_shape* shape_b, kg_xf xf_b, kg_u32 a,
                               kg_u32 b, kg_u32 sa, kg_u32 sb, KG_GLOBAL kg_shape_pair* out, int room, int* n)
{
    if (kg_shapes_pair(s, sa, sb) && kg_aabb_overlap(box_a, kg_shape_aabb(shape_b, xf_b))) {
        if (*n < room) {
            out[*n] = kg_shape_pair_make(a, b, sa, sb);
        }
        *n += 1;
    }
}

/* The pairs of shapes of body pair (a, b) that may touch, in (shape_a, shape_b) order:
 * solid shapes whose filters agree and whose bounds come within the pair's speculative
 * distance (beyond it the narrowphase finds no point). Writes those that fit below room
 * to out; returns how many there are. A pair of one-shape bodies is their one pair of
 * shapes (the broadphase filtered the bodies). A shape of a that does not reach b's
 * bounds (aabb, around all its shapes) reaches none of them: b's shapes are not tried
 * against it (a pile of compound bodies: a third of the expansion's cost). */
KG_FN int kg_expand_pair(kg_u32 a, kg_u32 b, const kg_shape_arrays* s, KG_GLOBAL const kg_xf* xf,
                         KG_GLOBAL const kg_vec2* velocity, KG_GLOBAL const kg_aabb* aabb, float speculative_distance,
                         float dt, KG_GLOBAL kg_shape_pair* out, int room)
{
    if (s->shape_count[a] == 1u && s->shape_count[b] == 1u) {
        if (room > 0) {
            out[0] = kg_shape_pair_make(a, b, s->first_shape[a], s->first_shape[b]);
        }
        return 1;
    }
    float margin = kg_pair_speculative(speculative_distance, velocity[a], velocity[b], dt);
    int n = 0;
    for (kg_u32 sa = s->first_shape[a]; sa != KG_NULL_INDEX; sa = s->next[sa]) {
        kg_aabb box_a = kg_shape_reach(s, a, sa, xf[a], margin);
        if (!kg_aabb_overlap(box_a, aabb[b])) {
            continue;
        }
        for (kg_u32 sb = s->first_shape[b]; sb != KG_NULL_INDEX; sb = s->next[sb]) {
            KG_PRIVATE_VIEW(kg_shape, shape_b, *kg_shape_of(s, b, sb));
            kg_offer_shape_pair(s, box_a, shape_b, xf[b], a, b, sa, sb, out, room, &n);
        }
    }
    return n;
}

/* Whether pair k became a contact: index is the prefix sum of the pairs that touch. */
KG_FN int kg_pair_touches(KG_GLOBAL const kg_u32* index, int k) { return index[k + 1] != index[k]; }

/* The key of body pair (a, b) where each body has one shape: it names each body's shape. */
KG_FN kg_shape_pair kg_one_shape_key(kg_u32 a, kg_u32 b, KG_GLOBAL const kg_u32* first_shape)
{
    return kg_shape_pair_make(a, b, first_shape[a], first_shape[b]);
}

/* Item k of the device's narrowphase, key, of shapes shape_a and shape_b: its manifold
 * and base, and whether it touches. */
KG_FN void kg_narrowphase_key(int k, kg_shape_pair key, KG_GLOBAL const kg_shape* shape_a,
                              KG_GLOBAL const kg_shape* shape_b, float speculative_distance, float dt,
                              KG_GLOBAL const kg_xf* xf, KG_GLOBAL const kg_vec2* velocity,
                              KG_GLOBAL const kg_contact* previous, int previous_count,
                              KG_GLOBAL const kg_u32* generation, KG_GLOBAL kg_manifold* manifolds,
                              KG_GLOBAL kg_contact_base* bases, KG_GLOBAL kg_u32* touching)
{
    int old = kg_previous_contact(previous, previous_count, key, generation);
    kg_contact last;
    if (old >= 0) {
        last = previous[old];
    }
    kg_manifold m;
    kg_contact_base base;
    kg_pair_manifold(key.a, key.b, shape_a, shape_b, xf, velocity, speculative_distance, dt, old >= 0 ? &last : 0, &m,
                     &base);
    manifolds[k] = m;
    bases[k] = base;
    touching[k] = m.point_count > 0 ? 1u : 0u;
}

/* Item k of the device's narrowphase, key, if it touches: contact index[k] (the prefix
 * sum keeps the items' order), its material mixed from its shapes' (fa, fb, ra, rb), with
 * last step's impulses and colour carried. */
KG_FN void kg_build_key_contact(int k, kg_shape_pair key, float fa, float fb, float ra, float rb,
                                KG_GLOBAL const kg_manifold* manifolds, KG_GLOBAL const kg_contact_base* bases,
                                KG_GLOBAL const kg_u32* index, KG_GLOBAL const kg_contact* previous,
                                int previous_count, KG_GLOBAL const kg_u32* generation, KG_GLOBAL kg_contact* contacts)
{
    if (!kg_pair_touches(index, k)) {
        return;
    }
    kg_contact c;
    c.manifold = manifolds[k];
    c.base = bases[k];
    int old = kg_previous_contact(previous, previous_count, key, generation);
    kg_contact_set_bodies(&c, key.a, key.b, key.shape_a, key.shape_b, generation, fa, fb, ra, rb);
    if (old >= 0) {
        KG_PRIVATE_VIEW(kg_manifold, carried, previous[old].manifold);
        kg_contact_carry_impulses(&c.manifold, carried);
        c.color = previous[old].color;
    }
    contacts[index[k]] = c;
}

/* Pair k, (a, b), of one-shape bodies on the device: kg_narrowphase_key of their shapes. */
KG_FN void kg_narrowphase_pair(int k, kg_u32 a, kg_u32 b, float speculative_distance, float dt,
                               KG_GLOBAL const kg_shape* shape, KG_GLOBAL const kg_xf* xf,
                               KG_GLOBAL const kg_vec2* velocity, KG_GLOBAL const kg_contact* previous,
                               int previous_count, KG_GLOBAL const kg_u32* generation,
                               KG_GLOBAL const kg_u32* first_shape, KG_GLOBAL kg_manifold* manifolds,
                               KG_GLOBAL kg_contact_base* bases, KG_GLOBAL kg_u32* touching)
{
    kg_narrowphase_key(k, kg_one_shape_key(a, b, first_shape), &shape[a], &shape[b], speculative_distance, dt, xf,
                       velocity, previous, previous_count, generation, manifolds, bases, touching);
}

/* Pair k, (a, b), of one-shape bodies on the device, if it touches: its contact, with the
 * bodies' material. */
KG_FN void kg_build_pair_contact(int k, kg_u32 a, kg_u32 b, KG_GLOBAL const kg_manifold* manifolds,
                                 KG_GLOBAL const kg_contact_base* bases, KG_GLOBAL const kg_u32* index,
                                 KG_GLOBAL const kg_contact* previous, int previous_count,
                                 KG_GLOBAL const kg_u32* generation, KG_GLOBAL const kg_u32* first_shape,
                                 KG_GLOBAL const float* friction, KG_GLOBAL const float* restitution,
                                 KG_GLOBAL kg_contact* contacts)
{
    kg_build_key_contact(k, kg_one_shape_key(a, b, first_shape), friction[a], friction[b], restitution[a],
                         restitution[b], manifolds, bases, index, previous, previous_count, generation, contacts);
}

/* Pair of bodies k on the device, while a body has several shapes: its pairs of shapes
 * written from run[k] (the prefix sum of their counts, kg_expand_pair's), and each one's
 * bodies beside it in item_pairs (what the wake stage reads). */
KG_FN void kg_place_shape_pairs(int k, kg_u32 a, kg_u32 b, const kg_shape_arrays* s, KG_GLOBAL const kg_xf* xf,
                                KG_GLOBAL const kg_vec2* velocity, KG_GLOBAL const kg_aabb* aabb,
                                float speculative_distance, float dt,
                                KG_GLOBAL const kg_u32* run, KG_GLOBAL kg_shape_pair* out,
                                KG_GLOBAL kg_u32* item_pairs)
{
    kg_u32 first = run[k], n = run[k + 1] - run[k];
    kg_expand_pair(a, b, s, xf, velocity, aabb, speculative_distance, dt, out + first, (int)n);
    for (kg_u32 j = first; j < first + n; ++j) {
        item_pairs[2u * j] = a;
        item_pairs[2u * j + 1u] = b;
    }
}

#endif
