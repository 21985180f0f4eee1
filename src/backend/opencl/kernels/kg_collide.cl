/* The narrowphase's kernels: each pair's manifold, the persistent contacts with their
 * carried impulses, and the tile maps' contacts; the per-element code is
 * collide/pair_contact.h's and collide/tile_pass.h's. Each ends in the exact list the CPU
 * backend builds, in the same order. No float is ever accumulated atomically. Element
 * counts the host does not know come from the counters buffer (KG_CC_*). */
#include "collide/pair_contact.h"
#include "collide/tile_pass.h"
#include "kg_collide_shared.h"

__kernel void kg_narrowphase(int count, float speculative_distance, float dt, __global const uint2* pairs,
                             __global const kg_shape* shape, __global const kg_xf* xf, __global const kg_vec2* velocity,
                             __global const kg_contact* previous, int previous_count, __global const kg_u32* generation,
                             __global const kg_u32* first_shape, __global kg_manifold* manifolds, __global kg_contact_base* bases, __global uint* touching)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_narrowphase_pair(k, pairs[k].x, pairs[k].y, speculative_distance, dt, shape, xf, velocity, previous,
                            previous_count, generation, first_shape, manifolds, bases, touching);
    }
}

/* index: the prefix sum of touching */
__kernel void kg_build_contacts(int count, __global const uint2* pairs, __global const kg_manifold* manifolds,
                                __global const kg_contact_base* bases, __global const uint* index,
                                __global const kg_contact* previous, int previous_count,
                                __global const kg_u32* generation, __global const kg_u32* first_shape,
                                __global const float* friction, __global const float* restitution,
                                __global kg_contact* contacts)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_build_pair_contact(k, pairs[k].x, pairs[k].y, manifolds, bases, index, previous, previous_count, generation,
                              first_shape, friction, restitution, contacts);
    }
}

/* ---- while a body has several shapes: pairs of shapes ---- */

/* The shape arrays (shape_count ... shape_mask) come in kg_shape_arrays' order. Written
 * out in each kernel: the embedding of the sources keeps no multi-line macro. */

/* run[k]: how many pairs of shapes body pair k gives. */
__kernel void kg_count_shape_pairs(int count, __global const uint2* pairs, __global const kg_u32* shape_count,
                                   __global const kg_u32* first_shape, __global const kg_shape* body_shape,
                                   __global const kg_shape* geometry, __global const kg_u32* next,
                                   __global const kg_u32* shape_flags, __global const kg_u32* shape_category,
                                   __global const kg_u32* shape_mask, __global const kg_xf* xf,
                                   __global const kg_vec2* velocity, __global const kg_aabb* aabb,
                                   float speculative_distance, float dt,
                                   __global uint* run)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_shape_arrays s = {shape_count, first_shape,  body_shape,     geometry,
                             next,        shape_flags, shape_category, shape_mask};
        run[k] = (uint)kg_expand_pair(pairs[k].x, pairs[k].y, &s, xf, velocity, aabb, speculative_distance, dt, 0, 0);
    }
}

/* run: the prefix sum of kg_count_shape_pairs'. */
__kernel void kg_write_shape_pairs(int count, __global const uint2* pairs, __global const kg_u32* shape_count,
                                   __global const kg_u32* first_shape, __global const kg_shape* body_shape,
                                   __global const kg_shape* geometry, __global const kg_u32* next,
                                   __global const kg_u32* shape_flags, __global const kg_u32* shape_category,
                                   __global const kg_u32* shape_mask, __global const kg_xf* xf,
                                   __global const kg_vec2* velocity, __global const kg_aabb* aabb,
                                   float speculative_distance, float dt,
                                   __global const uint* run, __global kg_shape_pair* items, __global uint* item_pairs)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_shape_arrays s = {shape_count, first_shape,  body_shape,     geometry,
                             next,        shape_flags, shape_category, shape_mask};
        kg_place_shape_pairs(k, pairs[k].x, pairs[k].y, &s, xf, velocity, aabb, speculative_distance, dt, run,
                             items, item_pairs);
    }
}

__kernel void kg_narrowphase_shapes(int count, float speculative_distance, float dt,
                                    __global const kg_shape_pair* items, __global const kg_u32* shape_count,
                                    __global const kg_u32* first_shape, __global const kg_shape* body_shape,
                                    __global const kg_shape* geometry, __global const kg_u32* next,
                                    __global const kg_u32* shape_flags, __global const kg_u32* shape_category,
                                    __global const kg_u32* shape_mask, __global const kg_xf* xf,
                                    __global const kg_vec2* velocity, __global const kg_contact* previous,
                                    int previous_count, __global const kg_u32* generation,
                                    __global kg_manifold* manifolds, __global kg_contact_base* bases,
                                    __global uint* touching)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_shape_arrays s = {shape_count, first_shape,  body_shape,     geometry,
                             next,        shape_flags, shape_category, shape_mask};
        kg_shape_pair key = items[k];
        kg_narrowphase_key(k, key, kg_shape_of(&s, key.a, key.shape_a), kg_shape_of(&s, key.b, key.shape_b),
                           speculative_distance, dt, xf, velocity, previous, previous_count, generation, manifolds,
                           bases, touching);
    }
}

/* index: the prefix sum of touching; friction and restitution: the shapes'. */
__kernel void kg_build_shape_contacts(int count, __global const kg_shape_pair* items,
                                      __global const kg_manifold* manifolds, __global const kg_contact_base* bases,
                                      __global const uint* index, __global const kg_contact* previous,
                                      int previous_count, __global const kg_u32* generation,
                                      __global const float* friction, __global const float* restitution,
                                      __global kg_contact* contacts)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_shape_pair key = items[k];
        kg_build_key_contact(k, key, friction[key.shape_a], friction[key.shape_b], restitution[key.shape_a],
                             restitution[key.shape_b], manifolds, bases, index, previous, previous_count, generation,
                             contacts);
    }
}

/* Run twice, counting then writing (prm.write); the contacts written after the body
 * contacts, and the one-way platforms' state into the other of its two copies (the step
 * may yet fail and be run again on the host). */
__kernel void kg_tile_collide_bodies(int count, kg_tile_pass_params prm, __global const kg_tile_map_info* maps,
                                     __global const kg_u32* cells, __global const kg_tile_proto* protos,
                                     __global const kg_u32* flags, __global const kg_aabb* aabb,
                                     __global const kg_xf* xf, __global const kg_shape* shape,
                                     __global const kg_vec2* center, __global const kg_u32* category,
                                     __global const kg_u32* mask, __global const kg_u32* generation,
                                     __global const float* friction, __global const float* restitution,
                                     __global const kg_contact* previous, __global const kg_vec2* last_origin,
                                     __global const kg_u32* last_generation, __global kg_vec2* next_origin,
                                     __global kg_u32* next_generation, __global const kg_u32* first_shape,
                                     __global const kg_u32* shape_count, __global const kg_u32* shape_next,
                                     __global const kg_u32* shape_flags, __global const kg_shape* shape_geometry,
                                     __global const kg_u32* shape_category, __global const kg_u32* shape_mask,
                                     __global const float* shape_friction, __global const float* shape_restitution,
                                     __global uint* tile_run, __global const uint* counts,
                                     __global kg_contact* contacts)
{
    int i = (int)get_global_id(0);
    if (i < count) {
        kg_tile_pass_slot((kg_u32)i, prm, maps, cells, protos, flags, aabb, xf, shape, center, category, mask,
                          generation, friction, restitution, previous, last_origin, last_generation, next_origin,
                          next_generation, first_shape, shape_count, shape_next, shape_flags, shape_geometry,
                          shape_category, shape_mask, shape_friction, shape_restitution, tile_run,
                          counts[KG_CC_BODY_CONTACTS], contacts);
    }
}

/* After the tile contacts' prefix sum, by one work-item. */
__kernel void kg_tile_total(int capacity, __global uint* counts)
{
    if (get_global_id(0) == 0) {
        kg_count_tile_contacts(&counts[KG_CC_CONTACTS], &counts[KG_CC_BODY_CONTACTS], counts[KG_CC_TILES],
                               (kg_u32)capacity);
    }
}
