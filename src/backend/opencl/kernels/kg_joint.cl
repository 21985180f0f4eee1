/* The joints' kernels: each maps its work-item to a joint, a pair or a link and calls the
 * function the CPU's loops call (solve/joint_row.h, solve/island.h), so both backends
 * compute the same bits (test_joints compares them on PoCL). Launched by cl_step.c,
 * cl_collide.c and cl_sleep.c while the world has joints. */
#include "collide/pair_contact.h"
#include "solve/island.h"
#include "solve/joint_row.h"
#include "kg_collide_shared.h"

/* Joint j's row prepared for the step (rows are independent: a work-item each). */
__kernel void kg_prepare_joints(int count, __global const kg_solver_params* params, __global kg_joint_row* rows,
                                __global const kg_solver_body* bodies, __global const float* inv_mass,
                                __global const float* inv_inertia, __global const kg_vec2* center,
                                __global const kg_rot* rot, __global const kg_vec2* local_center)
{
    int j = (int)get_global_id(0);
    if (j < count) {
        kg_joint_prepare(rows, j, bodies, inv_mass, inv_inertia, center, rot, local_center, *params);
    }
}

/* One pass over the joints order[first, first + count): one colour in parallel, or,
 * serial != 0, the overflow in order by a single work-item (the CPU's kg_joints_pass). */
__kernel void kg_solve_joint_color(int first, int count, int serial, int pass, int last_iteration,
                                   __global const kg_solver_params* params, __global const int* order,
                                   __global kg_joint_row* rows, __global kg_solver_body* bodies)
{
    kg_joint_share((int)get_global_id(0), (int)get_global_size(0), order, first, first + count, serial, rows, bodies,
                   *params, pass, last_iteration);
}

/* A whole pass, iterations times over every colour, then the overflow, by a single
 * work-group with a barrier between them: one launch instead of one per colour and
 * iteration, for joints too few to fill the device. color_start is kg_joints_order's. */
__kernel void kg_solve_joint_colors_in_group(int iterations, int pass, __global const int* color_start,
                                             __global const kg_solver_params* params, __global const int* order,
                                             __global kg_joint_row* rows, __global kg_solver_body* bodies)
{
    for (int it = 0; it < iterations; ++it) {
        for (int c = 0; c <= KG_JOINT_COLORS; ++c) {
            kg_joint_share((int)get_local_id(0), (int)get_local_size(0), order, color_start[c], color_start[c + 1],
                           c == KG_JOINT_COLORS, rows, bodies, *params, pass, it == iterations - 1);
            barrier(CLK_GLOBAL_MEM_FENCE);
        }
    }
}

/* Pair k of bodies joined by a joint that does not collide_connected makes no contact:
 * its touching flag cleared before the prefix sum (the CPU drops the pair). */
__kernel void kg_drop_joined_pairs(int count, __global const uint2* pairs, __global const kg_u32* apart,
                                   int apart_count, __global uint* touching)
{
    int k = (int)get_global_id(0);
    if (k < count && kg_pair_is_joined(apart, apart_count, pairs[k].x, pairs[k].y)) {
        touching[k] = 0u;
    }
}

/* The same over the pairs of shapes (while a body has several). */
__kernel void kg_drop_joined_shape_pairs(int count, __global const kg_shape_pair* items, __global const kg_u32* apart,
                                         int apart_count, __global uint* touching)
{
    int k = (int)get_global_id(0);
    if (k < count && kg_pair_is_joined(apart, apart_count, items[k].a, items[k].b)) {
        touching[k] = 0u;
    }
}

/* Joint link k marks the island of its sleeping body when the other stirs. */
__kernel void kg_wake_joined(int count, __global const kg_u32* links, __global const kg_u32* flags,
                             __global const kg_vec2* velocity, __global const float* omega,
                             __global const kg_u32* island, __global uint* wake_marks)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_mark_woken(links[2 * k], links[2 * k + 1], flags, velocity, omega, island, wake_marks);
    }
}

/* kg_find_islands with the joints' links (one work-group). */
__kernel void kg_find_joined_islands(int bodies, int count, __global const kg_contact* contacts, int joints,
                                     __global const kg_u32* links, __global const kg_u32* flags,
                                     __global const kg_vec2* velocity, __global const float* omega,
                                     __global const float* sleep_time, __global kg_u32* parent, __global float* least)
{
    __local int hooked;
    kg_find_joined_islands_in_group((int)get_local_id(0), (int)get_local_size(0), &hooked, bodies, count, contacts,
                                    joints, links, flags, velocity, omega, sleep_time, parent, least);
}

/* In the rounds over the whole device: the joints' hooks of a round, after the
 * contacts' (kg_hook_round, which cleared the next round's counter). */
__kernel void kg_hook_joint_round(int joints, int round, __global const kg_u32* links, __global const kg_u32* flags,
                                  __global kg_u32* parent, __global uint* counts)
{
    int k = (int)get_global_id(0);
    if (k < joints && kg_hook_link(links[2 * k], links[2 * k + 1], flags, parent)) {
        atomic_inc(&counts[KG_CC_HOOKED + (round & 1)]);
    }
}

/* And after kg_island_stirs: a moving kinematic body keeps what it drives awake. */
__kernel void kg_joint_stirs(int joints, __global const kg_u32* links, __global const kg_u32* flags,
                             __global const kg_vec2* velocity, __global const float* omega,
                             __global const kg_u32* parent, __global float* least)
{
    int k = (int)get_global_id(0);
    if (k < joints) {
        kg_link_stirs(links[2 * k], links[2 * k + 1], flags, velocity, omega, parent, least);
    }
}
