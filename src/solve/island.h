/* Islands and rest: sleeping's rules, shared by the CPU backend (solve/sleep.c) and the
 * kernels (backend/opencl/kernels/kg_sleep.cl): when a body counts as at rest, which
 * contacts wake a sleeping island, and the union-find that groups bodies into islands
 * (bodies linked by contacts), serially on the CPU, by one work-group on the device.
 * docs/design.md, "Sleeping", tells the whole. */
#ifndef KG_ISLAND_H
#define KG_ISLAND_H

#include "collide/aabb.h"
#include "core/body_flags.h"
#include "core/kg_layout.h"
#include "solve/contact_solver.h"

/* The farthest a point of the shape lies from the centre of mass: the angular speed
 * times this is the fastest its surface moves. */
KG_FN float kg_shape_extent(const kg_shape* shape, kg_vec2 local_center)
{
    float far2 = 0.0f;
    for (int i = 0; i < shape->count; ++i) {
        kg_vec2 d = kg_sub(shape->vertices[i], local_center);
        far2 = fmaxf(far2, kg_dot(d, d));
    }
    return sqrtf(far2) + shape->radius;
}

/* How long a body has been at rest after a step that left it with velocities v, w and
 * moved it by dp, dq: reset whenever a point of it moves faster than sleep_speed, by its
 * velocity or by its motion over the step (a body pushed out of an overlap moves while
 * the relaxed velocity says it is still), and a slow spin counts as much as a drift. */
KG_FN float kg_rest_timer(float timer, kg_body_motion m, float extent, float dt, float sleep_speed)
{
    float limit = sleep_speed * dt;
    float spin = fmaxf(fabsf(m.w) * dt, fabsf(m.dq.s)) * extent;
    float drift = fmaxf(kg_length(m.v) * dt, kg_length(m.dp));
    return (drift > limit || spin > limit) ? 0.0f : timer + dt;
}

/* The island of body i: the root of its union-find tree, halving the path on the way. */
KG_FN kg_u32 kg_island_root(KG_GLOBAL kg_u32* parent, kg_u32 i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

/* Joins the islands of a and b under the lower root: every island ends up named by its
 * lowest slot, whatever order the links come in. */
KG_FN void kg_island_link(KG_GLOBAL kg_u32* parent, kg_u32 a, kg_u32 b)
{
    kg_u32 ra = kg_island_root(parent, a), rb = kg_island_root(parent, b);
    if (ra < rb) {
        parent[rb] = ra;
    } else if (rb < ra) {
        parent[ra] = rb;
    }
}

/* A body whose contacts wake what they touch: awake and moving, or able to (a kinematic
 * body only while it has a velocity). */
KG_FN int kg_flags_stir(kg_u32 f, kg_vec2 v, float w)
{
    return kg_flags_move(f) && (kg_flags_type(f) != (kg_u32)KG_BODY_KINEMATIC || v.x != 0.0f || v.y != 0.0f || w != 0.0f);
}

/* Contact (a, b) marks the island of its sleeping body when the other stirs (marks is
 * indexed by island name; marks are only ever set, so the order contacts come in does
 * not matter). A tile contact (b null) wakes nothing: a tile never stirs. */
KG_FN void kg_mark_woken(kg_u32 a, kg_u32 b, KG_GLOBAL const kg_u32* flags, KG_GLOBAL const kg_vec2* velocity,
                         KG_GLOBAL const float* omega, KG_GLOBAL const kg_u32* island, KG_GLOBAL kg_u32* marks)
{
    if (b == KG_NULL_INDEX) {
        return;
    }
    if (kg_flags_stir(flags[a], velocity[a], omega[a]) && kg_flags_asleep(flags[b])) {
        marks[island[b]] = 1u;
    } else if (kg_flags_stir(flags[b], velocity[b], omega[b]) && kg_flags_asleep(flags[a])) {
        marks[island[a]] = 1u;
    }
}

KG_FN int kg_islander(KG_GLOBAL const kg_u32* flags, kg_u32 slot)
{
    return slot != KG_NULL_INDEX && kg_flags_collide(flags[slot]);
}

KG_FN int kg_stirring_kinematic(KG_GLOBAL const kg_u32* flags, KG_GLOBAL const kg_vec2* velocity,
                                KG_GLOBAL const float* omega, kg_u32 slot)
{
    return slot != KG_NULL_INDEX && kg_flags_type(flags[slot]) == (kg_u32)KG_BODY_KINEMATIC &&
           kg_flags_stir(flags[slot], velocity[slot], omega[slot]);
}

/* Slot i before the islands are found: an island of its own, no rest time yet. */
KG_FN void kg_island_reset(kg_u32 i, KG_GLOBAL kg_u32* parent, KG_GLOBAL float* least)
{
    parent[i] = i;
    least[i] = KG_FLT_MAX;
}

/* A link between a and b (a contact's or a joint's), once every islander's parent is its
 * island's root: a moving kinematic body keeps the island it touches awake (its least
 * rest time zero) without joining it. */
KG_FN void kg_link_stirs(kg_u32 a, kg_u32 b, KG_GLOBAL const kg_u32* flags, KG_GLOBAL const kg_vec2* velocity,
                         KG_GLOBAL const float* omega, KG_GLOBAL const kg_u32* parent, KG_GLOBAL float* least)
{
    if (kg_stirring_kinematic(flags, velocity, omega, a) && kg_islander(flags, b)) {
        least[parent[b]] = 0.0f;
    } else if (kg_stirring_kinematic(flags, velocity, omega, b) && kg_islander(flags, a)) {
        least[parent[a]] = 0.0f;
    }
}

/* Contact k's kg_link_stirs. */
KG_FN void kg_kinematic_stirs(int k, KG_GLOBAL const kg_contact* contacts, KG_GLOBAL const kg_u32* flags,
                              KG_GLOBAL const kg_vec2* velocity, KG_GLOBAL const float* omega,
                              KG_GLOBAL const kg_u32* parent, KG_GLOBAL float* least)
{
    kg_link_stirs(contacts[k].a, contacts[k].b, flags, velocity, omega, parent, least);
}

/* The islands of a step's contacts, serially, in contact and slot order: every colliding
 * body's parent becomes its island's root (the lowest slot), and least[root] the
 * shortest rest time of the island's bodies; a moving kinematic body keeps what it
 * touches awake without joining islands. */
KG_FN void kg_link_joined_islands(int bodies, int count, KG_GLOBAL const kg_contact* contacts, int joints,
                                  KG_GLOBAL const kg_u32* joined, KG_GLOBAL const kg_u32* flags,
                                  KG_GLOBAL const kg_vec2* velocity, KG_GLOBAL const float* omega,
                                  KG_GLOBAL const float* sleep_time, KG_GLOBAL kg_u32* parent, KG_GLOBAL float* least)
{
    for (int i = 0; i < bodies; ++i) {
        kg_island_reset((kg_u32)i, parent, least);
    }
    for (int k = 0; k < count; ++k) {
        kg_u32 a = contacts[k].a, b = contacts[k].b;
        if (kg_islander(flags, a) && kg_islander(flags, b)) {
            kg_island_link(parent, a, b);
        }
    }
    for (int k = 0; k < joints; ++k) { /* a joint links its two bodies as a contact does */
        kg_u32 a = joined[2 * k], b = joined[2 * k + 1];
        if (kg_islander(flags, a) && kg_islander(flags, b)) {
            kg_island_link(parent, a, b);
        }
    }
    for (int i = 0; i < bodies; ++i) {
        if (kg_flags_collide(flags[i])) {
            kg_u32 r = kg_island_root(parent, (kg_u32)i);
            parent[i] = r;
            least[r] = fminf(least[r], sleep_time[i]);
        }
    }
    for (int k = 0; k < count; ++k) {
        kg_kinematic_stirs(k, contacts, flags, velocity, omega, parent, least);
    }
    for (int k = 0; k < joints; ++k) { /* a moving kinematic body keeps what it drives awake */
        kg_link_stirs(joined[2 * k], joined[2 * k + 1], flags, velocity, omega, parent, least);
    }
}

/* The islands of the contacts alone (kg_link_joined_islands without joints). */
KG_FN void kg_link_islands(int bodies, int count, KG_GLOBAL const kg_contact* contacts, KG_GLOBAL const kg_u32* flags,
                           KG_GLOBAL const kg_vec2* velocity, KG_GLOBAL const float* omega,
                           KG_GLOBAL const float* sleep_time, KG_GLOBAL kg_u32* parent, KG_GLOBAL float* least)
{
    kg_link_joined_islands(bodies, count, contacts, 0, (KG_GLOBAL const kg_u32*)0,
                           flags, velocity, omega, sleep_time, parent, least);
}

/* The root above slot i, read only (on the device hooks may be moving it meanwhile:
 * every value read is an ancestor, so the walk ends). */
KG_FN kg_u32 kg_island_top(KG_GLOBAL const kg_u32* parent, kg_u32 i)
{
    while (parent[i] != i) {
        i = parent[i];
    }
    return i;
}

/* A link (a contact's, kg_hook_islands, or a joint's) between two islanders hooks their
 * islands, the higher root under the lower (an atomic min): roots only move down, so no
 * cycle forms, and an island's root ends as its lowest slot whatever the order. Returns
 * whether it hooked. */
KG_FN int kg_hook_link(kg_u32 a, kg_u32 b, KG_GLOBAL const kg_u32* flags, KG_GLOBAL kg_u32* parent)
{
    if (!kg_islander(flags, a) || !kg_islander(flags, b)) {
        return 0;
    }
    kg_u32 ra = kg_island_top(parent, a), rb = kg_island_top(parent, b);
    if (ra != rb) {
        kg_atomic_min_u32(&parent[ra > rb ? ra : rb], ra < rb ? ra : rb);
    }
    return ra != rb;
}

KG_FN int kg_hook_islands(int k, KG_GLOBAL const kg_contact* contacts, KG_GLOBAL const kg_u32* flags,
                          KG_GLOBAL kg_u32* parent)
{
    return kg_hook_link(contacts[k].a, contacts[k].b, flags, parent);
}

/* Body i's path shortened to its island's root, between rounds of hooks. */
KG_FN void kg_shorten_island_path(kg_u32 i, KG_GLOBAL kg_u32* parent) { parent[i] = kg_island_top(parent, i); }

/* Body i's rest time into its island's least (an atomic min), once the islands are found. */
KG_FN void kg_island_least_of(kg_u32 i, KG_GLOBAL const kg_u32* flags, KG_GLOBAL const float* sleep_time,
                              KG_GLOBAL const kg_u32* parent, KG_GLOBAL float* least)
{
    if (kg_flags_collide(flags[i])) {
        kg_atomic_min_unsigned_float(&least[parent[i]], sleep_time[i]);
    }
}

/* kg_link_joined_islands' results by one work-group (work-item `item` of `items`; hooked:
 * the group's shared flag): rounds of hooks over the contacts and the joints' links (two
 * slots a link), each followed by every path shortened to its root, until a round hooks
 * nothing; then each island's least rest time by atomic minima, and zero where a moving
 * kinematic body touches or drives the island. */
KG_FN void kg_find_joined_islands_in_group(int item, int items, KG_LOCAL int* hooked, int bodies, int count,
                                           KG_GLOBAL const kg_contact* contacts, int joints,
                                           KG_GLOBAL const kg_u32* joined, KG_GLOBAL const kg_u32* flags,
                                           KG_GLOBAL const kg_vec2* velocity, KG_GLOBAL const float* omega,
                                           KG_GLOBAL const float* sleep_time, KG_GLOBAL kg_u32* parent,
                                           KG_GLOBAL float* least)
{
    for (int i = item; i < bodies; i += items) {
        kg_island_reset((kg_u32)i, parent, least);
    }
    do {
        kg_group_barrier(); /* every work-item has read last round's flag */
        *hooked = 0;
        kg_group_barrier();
        int mine = 0;
        for (int k = item; k < count; k += items) {
            mine |= kg_hook_islands(k, contacts, flags, parent);
        }
        for (int k = item; k < joints; k += items) {
            mine |= kg_hook_link(joined[2 * k], joined[2 * k + 1], flags, parent);
        }
        if (mine) {
            *hooked = 1;
        }
        kg_group_barrier();
        for (int i = item; i < bodies; i += items) {
            kg_shorten_island_path((kg_u32)i, parent);
        }
    } while (*hooked);
    kg_group_barrier();
    for (int i = item; i < bodies; i += items) {
        kg_island_least_of((kg_u32)i, flags, sleep_time, parent, least);
    }
    kg_group_barrier();
    for (int k = item; k < count; k += items) {
        kg_kinematic_stirs(k, contacts, flags, velocity, omega, parent, least);
    }
    for (int k = item; k < joints; k += items) {
        kg_link_stirs(joined[2 * k], joined[2 * k + 1], flags, velocity, omega, parent, least);
    }
}

/* kg_link_islands' results by one work-group: kg_find_joined_islands_in_group without
 * joints. */
KG_FN void kg_find_islands_in_group(int item, int items, KG_LOCAL int* hooked, int bodies, int count,
                                    KG_GLOBAL const kg_contact* contacts, KG_GLOBAL const kg_u32* flags,
                                    KG_GLOBAL const kg_vec2* velocity, KG_GLOBAL const float* omega,
                                    KG_GLOBAL const float* sleep_time, KG_GLOBAL kg_u32* parent,
                                    KG_GLOBAL float* least)
{
    kg_find_joined_islands_in_group(item, items, hooked, bodies, count, contacts, 0, (KG_GLOBAL const kg_u32*)0, flags,
                                    velocity, omega, sleep_time, parent, least);
}

/* Body i wakes: awake, its rest timer restarted. */
KG_FN void kg_wake_body(kg_u32 i, KG_GLOBAL kg_u32* flags, KG_GLOBAL float* sleep_time)
{
    flags[i] &= ~(KG_FLAG_ASLEEP | KG_FLAG_RESTED);
    sleep_time[i] = 0.0f;
}

/* Body i falls asleep in the island named island_id: still, its bounds no longer swept
 * over a motion (it moved since the collide stage, so it is not rested). */
KG_FN void kg_sleep_body(kg_u32 i, kg_u32 island_id, KG_GLOBAL kg_u32* flags, KG_GLOBAL kg_u32* island,
                         KG_GLOBAL kg_vec2* velocity, KG_GLOBAL float* omega, KG_GLOBAL const kg_vec2* center,
                         KG_GLOBAL const kg_rot* rot, KG_GLOBAL const kg_vec2* local_center,
                         KG_GLOBAL const kg_shape* shape, KG_GLOBAL kg_xf* xf, KG_GLOBAL kg_aabb* aabb)
{
    flags[i] = (flags[i] | KG_FLAG_ASLEEP) & ~KG_FLAG_RESTED;
    island[i] = island_id;
    velocity[i] = kg_v2(0.0f, 0.0f);
    omega[i] = 0.0f;
    kg_xf t = kg_origin_xf(center[i], rot[i], local_center[i]);
    KG_PRIVATE_VIEW(kg_shape, s, shape[i]);
    xf[i] = t;
    aabb[i] = kg_shape_aabb(s, t);
}

/* Body i, asleep, wakes when its island is marked. */
KG_FN void kg_wake_if_marked(kg_u32 i, KG_GLOBAL kg_u32* flags, KG_GLOBAL const kg_u32* island,
                             KG_GLOBAL const kg_u32* marks, KG_GLOBAL float* sleep_time)
{
    if (kg_flags_asleep(flags[i]) && marks[island[i]]) {
        kg_wake_body(i, flags, sleep_time);
    }
}

/* Once the islands are found (parent: each body's root, least: per root): an awake body
 * whose whole island rested time_to_sleep falls asleep. */
KG_FN void kg_fall_asleep_if_rested(kg_u32 i, float time_to_sleep, KG_GLOBAL const kg_u32* parent,
                                    KG_GLOBAL const float* least, KG_GLOBAL kg_u32* flags, KG_GLOBAL kg_u32* island,
                                    KG_GLOBAL kg_vec2* velocity, KG_GLOBAL float* omega,
                                    KG_GLOBAL const kg_vec2* center, KG_GLOBAL const kg_rot* rot,
                                    KG_GLOBAL const kg_vec2* local_center, KG_GLOBAL const kg_shape* shape,
                                    KG_GLOBAL kg_xf* xf, KG_GLOBAL kg_aabb* aabb)
{
    if (kg_flags_simulated(flags[i]) && least[parent[i]] >= time_to_sleep) {
        kg_sleep_body(i, parent[i], flags, island, velocity, omega, center, rot, local_center, shape, xf, aabb);
    }
}

#endif
