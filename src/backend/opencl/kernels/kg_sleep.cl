/* Sleeping on the device: the wake and sleep stages, with the CPU's results, from the
 * shared rules of solve/island.h.
 *
 *   wake  (after the collide stage, before the colouring that opens the solve): a contact
 *         between a body in motion and a sleeping one marks the sleeping one's island,
 *         then every sleeping body of a marked island wakes. Marks are set, never
 *         cleared, within the stage, so the order work-items run in does not matter;
 *         kg_bp_proxies zeroes them each step.
 *   sleep (last in the step): islands over the contacts and the least rest timer of
 *         each, the CPU's (kg_link_islands: an island named by its lowest slot) by one
 *         work-group hooking roots in parallel; then every awake body of an island at rest
 *         for time_to_sleep falls asleep, one work-item per body. */
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

/* The root above slot i, read only (hooks may be moving it meanwhile: every value read is
 * an ancestor, so the walk ends). */
KG_FN kg_u32 kg_island_top(__global const kg_u32* parent, kg_u32 i)
{
    while (parent[i] != i) {
        i = parent[i];
    }
    return i;
}

/* One round over the contacts this work-item owns: the two islands of a contact between
 * islanders hooked, the higher root under the lower (atomic_min). Roots only move down, so
 * no cycle forms, and an island's root ends as its lowest slot whatever the order: the
 * islands kg_link_islands makes. Returns whether it hooked any. */
KG_FN int kg_hook_islands(int first, int step, int count, __global const kg_contact* contacts,
                          __global const kg_u32* flags, __global kg_u32* parent)
{
    int hooked = 0;
    for (int k = first; k < count; k += step) {
        kg_u32 a = contacts[k].a, b = contacts[k].b;
        if (kg_islander(flags, a) && kg_islander(flags, b)) {
            kg_u32 ra = kg_island_top(parent, a), rb = kg_island_top(parent, b);
            if (ra != rb) {
                atomic_min(&parent[max(ra, rb)], min(ra, rb));
                hooked = 1;
            }
        }
    }
    return hooked;
}

/* The islands and their least rest timers (kg_link_islands' results), by one work-group:
 * rounds of hooks, each followed by every path shortened to its root, until a round hooks
 * nothing; then each island's least rest time by atomic_min on the timers' bits (they are
 * never negative, so their bits order as they do), and zero where a moving kinematic body
 * touches the island. */
__kernel void kg_find_islands(int bodies, int count, __global const kg_contact* contacts,
                              __global const kg_u32* flags, __global const kg_vec2* velocity,
                              __global const float* omega, __global const float* sleep_time,
                              __global kg_u32* parent, __global float* least)
{
    int lid = (int)get_local_id(0), size = (int)get_local_size(0);
    __local int hooked;
    for (int i = lid; i < bodies; i += size) {
        parent[i] = (kg_u32)i;
        least[i] = KG_FLT_MAX;
    }
    do {
        barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE); /* every work-item has read last round's flag */
        hooked = 0;
        barrier(CLK_LOCAL_MEM_FENCE);
        if (kg_hook_islands(lid, size, count, contacts, flags, parent)) {
            hooked = 1;
        }
        barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
        for (int i = lid; i < bodies; i += size) {
            parent[i] = kg_island_top(parent, (kg_u32)i);
        }
    } while (hooked);
    barrier(CLK_GLOBAL_MEM_FENCE);
    for (int i = lid; i < bodies; i += size) {
        if (kg_flags_collide(flags[i])) {
            atomic_min((__global uint*)&least[parent[i]], as_uint(sleep_time[i]));
        }
    }
    barrier(CLK_GLOBAL_MEM_FENCE);
    for (int k = lid; k < count; k += size) {
        kg_u32 a = contacts[k].a, b = contacts[k].b;
        if (kg_stirring_kinematic(flags, velocity, omega, a) && kg_islander(flags, b)) {
            least[parent[b]] = 0.0f;
        } else if (kg_stirring_kinematic(flags, velocity, omega, b) && kg_islander(flags, a)) {
            least[parent[a]] = 0.0f;
        }
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
