/* The narrowphase's kernels: each pair's manifold, the persistent contacts with their
 * carried impulses, and the tile maps' contacts; the per-element code is the shared
 * headers'. Each ends in the exact list the CPU backend builds, in the same order. No
 * float is ever accumulated atomically. Element counts the host does not know come from
 * the counters buffer (KG_CC_*). */
#include "core/kg_layout.h"
#include "collide/aabb.h"
#include "collide/manifold.h"
#include "collide/pair_contact.h"
#include "collide/recycle.h"
#include "collide/tile_pass.h"
#include "kg_collide_shared.h"

/* Last step's contact of pair (a, b) among its body contacts, or -1. */
KG_FN int kg_previous_contact(__global const kg_contact* previous, int count, kg_u32 a, kg_u32 b,
                              __global const kg_u32* generation)
{
    int at = kg_first_not_before(previous, count, a, b);
    return kg_is_contact_of(previous, count, at, a, b, generation) ? at : -1;
}

/* Pair k's manifold and base (collide/pair_contact.h), and whether it touches. */
__kernel void kg_narrowphase(int count, float speculative_distance, float dt, __global const uint2* pairs,
                             __global const kg_shape* shape, __global const kg_xf* xf,
                             __global const kg_vec2* velocity, __global const kg_contact* previous,
                             int previous_count, __global const kg_u32* generation, __global kg_manifold* manifolds,
                             __global kg_contact_base* bases, __global uint* touching)
{
    int k = (int)get_global_id(0);
    if (k >= count) {
        return;
    }
    uint2 p = pairs[k];
    int old = kg_previous_contact(previous, previous_count, p.x, p.y, generation);
    kg_contact last;
    if (old >= 0) {
        last = previous[old];
    }
    kg_manifold m;
    kg_contact_base base;
    kg_pair_manifold(p.x, p.y, shape, xf, velocity, speculative_distance, dt, old >= 0 ? &last : 0, &m, &base);
    manifolds[k] = m;
    bases[k] = base;
    touching[k] = m.point_count > 0 ? 1u : 0u;
}

/* Touching pair k becomes contact index[k] (the prefix sum of touching keeps the pairs'
 * order), with last step's impulses carried. */
__kernel void kg_build_contacts(int count, __global const uint2* pairs, __global const kg_manifold* manifolds,
                                __global const kg_contact_base* bases, __global const uint* index,
                                __global const kg_contact* previous,
                                int previous_count, __global const kg_u32* generation,
                                __global const float* friction, __global const float* restitution,
                                __global kg_contact* contacts)
{
    int k = (int)get_global_id(0);
    if (k >= count || index[k + 1] == index[k]) {
        return;
    }
    uint2 p = pairs[k];
    kg_contact c;
    c.manifold = manifolds[k];
    c.base = bases[k];
    int old = kg_previous_contact(previous, previous_count, p.x, p.y, generation);
    if (old >= 0) {
        KG_PRIVATE_VIEW(kg_manifold, carried, previous[old].manifold);
        kg_contact_carry_impulses(&c.manifold, carried);
    }
    kg_contact_set_bodies(&c, p.x, p.y, generation, friction, restitution);
    contacts[index[k]] = c;
}

/* ---- tile maps ------------------------------------------------------------------------ */

/* The tile pass (collide/tile_pass.h), one work-item per body slot. Run twice: counting
 * (write 0: tile_run[i] = body i's contacts), then, after the prefix sum, writing them at
 * counts[KG_CC_BODY_CONTACTS] + tile_run[i] (those within capacity) and remembering every
 * slot's origin for the one-way platforms into the other of the two copies of that state
 * (the step may yet fail and be run again on the host). */
__kernel void kg_tile_collide_bodies(int count, int write, float speculative, float linear_slop, int map_count,
                                     __global const kg_tile_map_info* maps, __global const kg_u32* cells,
                                     __global const kg_tile_proto* protos, __global const kg_u32* flags,
                                     __global const kg_aabb* aabb, __global const kg_xf* xfs,
                                     __global const kg_shape* shapes, __global const kg_vec2* centers,
                                     __global const kg_u32* category, __global const kg_u32* mask,
                                     __global const kg_u32* generation, __global const float* friction,
                                     __global const float* restitution, __global const kg_contact* previous,
                                     int previous_begin, int previous_end, __global const kg_vec2* last_origin,
                                     __global const kg_u32* last_generation, __global kg_vec2* next_origin,
                                     __global kg_u32* next_generation, __global uint* tile_run,
                                     __global const uint* counts, int capacity, __global kg_contact* contacts)
{
    kg_u32 i = (kg_u32)get_global_id(0);
    if (i >= (kg_u32)count) {
        return;
    }
    kg_tile_terrain terrain = {maps, cells, protos, map_count, speculative, linear_slop};
    kg_tile_contacts found = {previous, previous_begin, previous_end, contacts,
                              write ? counts[KG_CC_BODY_CONTACTS] + tile_run[i] : 0u, write ? (uint)capacity : 0u,
                              0u, 0, 0};
    kg_tile_bodies bodies = {flags,      aabb,     xfs,         shapes,          centers,     category,
                             mask,       generation, friction, restitution, last_origin, last_generation};
    kg_tile_collide_body(i, &terrain, &bodies, &found);
    if (write) {
        kg_tile_remember_origin(i, xfs, generation, next_origin, next_generation);
    } else {
        tile_run[i] = found.found;
    }
}

/* After the tile contacts' prefix sum: the body contacts' count kept, the total (within
 * capacity, as the host keeps it) made this step's. One work-item. */
__kernel void kg_tile_total(int capacity, __global uint* counts)
{
    if (get_global_id(0) != 0) {
        return;
    }
    uint body = counts[KG_CC_CONTACTS];
    uint total = body + counts[KG_CC_TILES];
    counts[KG_CC_BODY_CONTACTS] = body;
    counts[KG_CC_CONTACTS] = min(total, (uint)capacity);
}
