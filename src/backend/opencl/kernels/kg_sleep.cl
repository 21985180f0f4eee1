/* Sleeping on the device: solve/sleep.c's two stages, with the same results.
 *
 *   wake  (in the collide stage, after the contacts, before the colouring): a contact
 *         between a body in motion and a sleeping one marks the sleeping one's island,
 *         then every sleeping body of a marked island wakes. Marks are set, never
 *         cleared, within the stage, so the order work-items run in does not matter;
 *         kg_bp_proxies zeroes them each step.
 *   sleep (last in the step): islands by union-find over the contacts, and the least
 *         rest timer of each, by one work-item in contact and slot order as the CPU does
 *         (island.h's roots are the lowest slot whatever the order, the least timer a
 *         minimum); then every awake body of an island at rest for time_to_sleep falls
 *         asleep, one work-item per body.
 *
 * Built after kg_step.cl, whose body predicates it uses. */
#include "solve/island.h"

/* kg_stirs of solve/sleep.c: a body whose contacts wake what they touch, awake and moving
 * or able to (a kinematic body only while it has a velocity). */
KG_FN int kg_stirs(kg_u32 flags, kg_vec2 v, float w)
{
    return kg_is_moving(flags) && (kg_type_of(flags) != KG_BODY_KINEMATIC || v.x != 0.0f || v.y != 0.0f || w != 0.0f);
}

/* Pair k, if it touches (index: the prefix sum of the touching pairs), marks the island
 * of its sleeping body when the other stirs. Tile contacts are left out: a tile never
 * stirs. */
__kernel void kg_wake_touched(int count, __global const uint2* pairs, __global const uint* index,
                              __global const kg_u32* flags, __global const kg_vec2* velocity,
                              __global const float* omega, __global const kg_u32* island,
                              __global uint* wake_marks)
{
    int k = (int)get_global_id(0);
    if (k >= count || index[k + 1] == index[k]) {
        return;
    }
    uint2 p = pairs[k];
    kg_u32 fa = flags[p.x], fb = flags[p.y];
    if (kg_stirs(fa, velocity[p.x], omega[p.x]) && kg_is_asleep(fb)) {
        wake_marks[island[p.y]] = 1u;
    } else if (kg_stirs(fb, velocity[p.y], omega[p.y]) && kg_is_asleep(fa)) {
        wake_marks[island[p.x]] = 1u;
    }
}

/* kg_wake_slot of solve/sleep.c for every sleeping body of a marked island. */
__kernel void kg_wake_marked(int count, __global kg_u32* flags, __global const kg_u32* island,
                             __global const uint* wake_marks, __global float* sleep_time)
{
    int i = (int)get_global_id(0);
    if (i >= count || !kg_is_asleep(flags[i]) || !wake_marks[island[i]]) {
        return;
    }
    flags[i] &= ~KG_FLAG_ASLEEP;
    sleep_time[i] = 0.0f;
}

KG_FN int kg_islander(__global const kg_u32* flags, kg_u32 slot)
{
    return slot != KG_NULL_INDEX && kg_collides(flags[slot]);
}

KG_FN int kg_stirring_kinematic(__global const kg_u32* flags, __global const kg_vec2* velocity,
                                __global const float* omega, kg_u32 slot)
{
    return slot != KG_NULL_INDEX && kg_type_of(flags[slot]) == KG_BODY_KINEMATIC &&
           kg_stirs(flags[slot], velocity[slot], omega[slot]);
}

/* kg_build_islands of solve/sleep.c, by one work-item: the islands of this step's
 * contacts, each colliding body's parent made its root (for kg_fall_asleep), and the
 * least rest timer of each island; a moving kinematic body keeps what it touches awake
 * without joining islands. */
__kernel void kg_find_islands(int bodies, int count, __global const kg_contact* contacts,
                              __global const kg_u32* flags, __global const kg_vec2* velocity,
                              __global const float* omega, __global const float* sleep_time,
                              __global kg_u32* parent, __global float* least)
{
    if (get_global_id(0) != 0) {
        return;
    }
    for (int i = 0; i < bodies; ++i) {
        parent[i] = (kg_u32)i;
        least[i] = KG_FLT_MAX;
    }
    for (int k = 0; k < count; ++k) {
        kg_u32 a = contacts[k].a, b = contacts[k].b;
        if (kg_islander(flags, a) && kg_islander(flags, b)) {
            kg_island_link(parent, a, b);
        }
    }
    for (int i = 0; i < bodies; ++i) {
        if (kg_collides(flags[i])) {
            kg_u32 r = kg_island_root(parent, (kg_u32)i);
            parent[i] = r;
            least[r] = fminf(least[r], sleep_time[i]);
        }
    }
    for (int k = 0; k < count; ++k) {
        kg_u32 a = contacts[k].a, b = contacts[k].b;
        if (kg_stirring_kinematic(flags, velocity, omega, a) && kg_islander(flags, b)) {
            least[kg_island_root(parent, b)] = 0.0f;
        } else if (kg_stirring_kinematic(flags, velocity, omega, b) && kg_islander(flags, a)) {
            least[kg_island_root(parent, a)] = 0.0f;
        }
    }
}

/* kg_sleep_slot of solve/sleep.c for an awake body whose island rested time_to_sleep:
 * still, named by its island, its bounds no longer swept over a motion. */
__kernel void kg_fall_asleep(int count, float time_to_sleep, __global const kg_u32* parent,
                             __global const float* least, __global kg_u32* flags, __global kg_u32* island,
                             __global kg_vec2* velocity, __global float* omega, __global const kg_vec2* center,
                             __global const kg_rot* rot, __global const kg_vec2* local_center,
                             __global const kg_shape* shape, __global kg_xf* xf, __global kg_aabb* aabb)
{
    int i = (int)get_global_id(0);
    if (i >= count || !kg_is_simulated(flags[i]) || !(least[parent[i]] >= time_to_sleep)) {
        return;
    }
    flags[i] |= KG_FLAG_ASLEEP;
    island[i] = parent[i];
    velocity[i] = kg_v2(0.0f, 0.0f);
    omega[i] = 0.0f;
    kg_xf t = kg_origin_xf(center[i], rot[i], local_center[i]);
    kg_shape s = shape[i];
    xf[i] = t;
    aabb[i] = kg_shape_aabb(&s, t);
}
