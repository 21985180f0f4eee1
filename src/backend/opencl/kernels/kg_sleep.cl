/* Sleeping on the device: the wake and sleep stages, with the CPU's results, from the
 * shared rules of solve/island.h.
 *
 *   wake  (after the collide stage, before the colouring that opens the solve): a contact
 *         between a body in motion and a sleeping one marks the sleeping one's island,
 *         then every sleeping body of a marked island wakes. Marks are set, never
 *         cleared, within the stage, so the order work-items run in does not matter;
 *         kg_bp_proxies zeroes them each step.
 *   sleep (last in the step): islands over the contacts and the least rest timer of
 *         each, the CPU's, by one work-group, or on a GPU with many bodies in rounds of
 *         hooks and shortened paths over the whole device; then every awake body of an
 *         island at rest for time_to_sleep falls asleep, one work-item per body. */
#include "collide/pair_contact.h"
#include "solve/island.h"
#include "kg_collide_shared.h"

/* Pair k, if it became a contact (index: the prefix sum of the touching pairs), marks the
 * island of its sleeping body when the other stirs. */
__kernel void kg_wake_touched(int count, __global const uint2* pairs, __global const uint* index,
                              __global const kg_u32* flags, __global const kg_vec2* velocity,
                              __global const float* omega, __global const kg_u32* island, __global uint* wake_marks)
{
    int k = (int)get_global_id(0);
    if (k < count && kg_pair_touches(index, k)) {
        kg_mark_woken(pairs[k].x, pairs[k].y, flags, velocity, omega, island, wake_marks);
    }
}

__kernel void kg_wake_marked(int count, __global kg_u32* flags, __global const kg_u32* island,
                             __global const uint* wake_marks, __global float* sleep_time)
{
    int i = (int)get_global_id(0);
    if (i < count) {
        kg_wake_if_marked((kg_u32)i, flags, island, wake_marks, sleep_time);
    }
}

__kernel void kg_find_islands(int bodies, int count, __global const kg_contact* contacts, __global const kg_u32* flags,
                              __global const kg_vec2* velocity, __global const float* omega,
                              __global const float* sleep_time, __global kg_u32* parent, __global float* least)
{
    __local int hooked;
    kg_find_islands_in_group((int)get_local_id(0), (int)get_local_size(0), &hooked, bodies, count, contacts, flags,
                             velocity, omega, sleep_time, parent, least);
}

/* The same in rounds: reset, then hooks and shortened paths until a round hooks nothing
 * (counted in counts[KG_CC_HOOKED + round % 2], the other word cleared for the next
 * round), then each island's least rest time and the kinematic bodies' stirs. */
__kernel void kg_reset_islands(int bodies, __global kg_u32* parent, __global float* least, __global uint* counts)
{
    int i = (int)get_global_id(0);
    if (i < bodies) {
        kg_island_reset((kg_u32)i, parent, least);
    }
    if (i == 0) {
        counts[KG_CC_HOOKED] = counts[KG_CC_HOOKED + 1] = 0u; /* no contacts: no round clears them */
    }
}

__kernel void kg_hook_round(int count, int round, __global const kg_contact* contacts, __global const kg_u32* flags,
                            __global kg_u32* parent, __global uint* counts)
{
    int k = (int)get_global_id(0);
    if (k == 0) {
        counts[KG_CC_HOOKED + ((round + 1) & 1)] = 0u;
    }
    if (k < count && kg_hook_islands(k, contacts, flags, parent)) {
        atomic_inc(&counts[KG_CC_HOOKED + (round & 1)]);
    }
}

__kernel void kg_shorten_islands(int bodies, __global kg_u32* parent)
{
    int i = (int)get_global_id(0);
    if (i < bodies) {
        kg_shorten_island_path((kg_u32)i, parent);
    }
}

__kernel void kg_island_least(int bodies, __global const kg_u32* flags, __global const float* sleep_time,
                              __global const kg_u32* parent, __global float* least)
{
    int i = (int)get_global_id(0);
    if (i < bodies) {
        kg_island_least_of((kg_u32)i, flags, sleep_time, parent, least);
    }
}

__kernel void kg_island_stirs(int count, __global const kg_contact* contacts, __global const kg_u32* flags,
                              __global const kg_vec2* velocity, __global const float* omega,
                              __global const kg_u32* parent, __global float* least)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_kinematic_stirs(k, contacts, flags, velocity, omega, parent, least);
    }
}

__kernel void kg_fall_asleep(int count, float time_to_sleep, __global const kg_u32* parent, __global const float* least,
                             __global kg_u32* flags, __global kg_u32* island, __global kg_vec2* velocity,
                             __global float* omega, __global const kg_vec2* center, __global const kg_rot* rot,
                             __global const kg_vec2* local_center, __global const kg_shape* shape, __global kg_xf* xf,
                             __global kg_aabb* aabb)
{
    int i = (int)get_global_id(0);
    if (i < count) {
        kg_fall_asleep_if_rested((kg_u32)i, time_to_sleep, parent, least, flags, island, velocity, omega, center, rot,
                                 local_center, shape, xf, aabb);
    }
}
