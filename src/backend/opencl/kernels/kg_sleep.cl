/* Sleeping on the device: solve/sleep.c's two stages, with the same results, from the
 * same rules (solve/island.h).
 *
 *   wake  (in the collide stage, after the contacts, before the colouring): a contact
 *         between a body in motion and a sleeping one marks the sleeping one's island,
 *         then every sleeping body of a marked island wakes. Marks are set, never
 *         cleared, within the stage, so the order work-items run in does not matter;
 *         kg_bp_proxies zeroes them each step.
 *   sleep (last in the step): islands by union-find over the contacts, and the least
 *         rest timer of each, by one work-item in contact and slot order as the CPU does;
 *         then every awake body of an island at rest for time_to_sleep falls asleep, one
 *         work-item per body. */
#include "solve/island.h"

/* Pair k, if it touches (index: the prefix sum of the touching pairs), marks the island
 * of its sleeping body when the other stirs. */
__kernel void kg_wake_touched(int count, __global const uint2* pairs, __global const uint* index,
                              __global const kg_u32* flags, __global const kg_vec2* velocity,
                              __global const float* omega, __global const kg_u32* island,
                              __global uint* wake_marks)
{
    int k = (int)get_global_id(0);
    if (k >= count || index[k + 1] == index[k]) {
        return;
    }
    kg_mark_woken(pairs[k].x, pairs[k].y, flags, velocity, omega, island, wake_marks);
}

/* Every sleeping body of a marked island wakes. */
__kernel void kg_wake_marked(int count, __global kg_u32* flags, __global const kg_u32* island,
                             __global const uint* wake_marks, __global float* sleep_time)
{
    int i = (int)get_global_id(0);
    if (i < count && kg_flags_asleep(flags[i]) && wake_marks[island[i]]) {
        kg_wake_body((kg_u32)i, flags, sleep_time);
    }
}

/* The islands and their least rest timers, by one work-item, as the CPU's sleep stage
 * runs it. */
__kernel void kg_find_islands(int bodies, int count, __global const kg_contact* contacts,
                              __global const kg_u32* flags, __global const kg_vec2* velocity,
                              __global const float* omega, __global const float* sleep_time,
                              __global kg_u32* parent, __global float* least)
{
    if (get_global_id(0) == 0) {
        kg_link_islands(bodies, count, contacts, flags, velocity, omega, sleep_time, parent, least);
    }
}

/* An awake body whose island rested time_to_sleep falls asleep. */
__kernel void kg_fall_asleep(int count, float time_to_sleep, __global const kg_u32* parent,
                             __global const float* least, __global kg_u32* flags, __global kg_u32* island,
                             __global kg_vec2* velocity, __global float* omega, __global const kg_vec2* center,
                             __global const kg_rot* rot, __global const kg_vec2* local_center,
                             __global const kg_shape* shape, __global kg_xf* xf, __global kg_aabb* aabb)
{
    int i = (int)get_global_id(0);
    if (i < count && kg_falls_asleep(flags[i], parent[i], least, time_to_sleep)) {
        kg_sleep_body((kg_u32)i, parent[i], flags, island, velocity, omega, center, rot, local_center, shape, xf,
                      aabb);
    }
}
