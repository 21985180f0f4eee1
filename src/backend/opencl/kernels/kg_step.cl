/* The kernels of a step: one work-item per body, contact or constraint, each calling the
 * per-element functions the CPU backend calls, on the same data layout (the body pool's
 * arrays, kg_contact, kg_contact_constraint), so both backends compute the same bits.
 *
 * Work-items copy what they need from global memory into private variables, call the
 * shared function, and write back only the element they own (gather, never scatter).
 * Every kernel takes its element count and returns for the padding work-items. */
#include "core/body_flags.h"
#include "core/kg_layout.h"
#include "collide/aabb.h"
#include "solve/integrate.h"
#include "solve/coloring.h"
#include "solve/contact_solver.h"
#include "solve/body_step.h"
#include "solve/island.h"

/* ---- forces ---------------------------------------------------------------------- */

/* A built-in applicator on every body (all != 0: work-item i is slot i) or on a list of
 * (slot, multiplicity) pairs, each slot once. */
__kernel void kg_apply_builtin_force(int count, int all, __global const uint2* targets, int gravity, float vx, float vy,
                                     float strength, float wind_drag, __global const kg_u32* flags,
                                     __global const float* mass, __global kg_vec2* force, __global float* drag)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_builtin_force_on(all ? (kg_u32)k : targets[k].x, all ? 1u : targets[k].y, gravity, kg_v2(vx, vy), strength,
                            wind_drag, flags, mass, force, drag);
    }
}

/* ---- solver ---------------------------------------------------------------------- */

__kernel void kg_load_bodies(int count, float gx, float gy, float h, __global kg_u32* flags,
                             __global kg_vec2* velocity, __global float* omega, __global kg_vec2* force,
                             __global float* torque, __global kg_rot* rot, __global kg_vec2* center,
                             __global const kg_xf* xf, __global const kg_vec2* local_center,
                             __global kg_solver_body* bodies, __global const float* drag,
                             __global const float* inv_mass, __global const float* inv_inertia,
                             __global const float* linear_damping, __global const float* angular_damping,
                             __global kg_velocity_step* steps)
{
    int i = (int)get_global_id(0);
    if (i < count) {
        kg_integrate_params prm = {kg_v2(gx, gy), h, 0.0f};
        kg_load_body_for_step((kg_u32)i, flags, velocity, omega, force, torque, rot, center, xf, local_center, bodies,
                              drag, inv_mass, inv_inertia, linear_damping, angular_damping, prm, steps);
    }
}

__kernel void kg_integrate_velocities(int count, float h, float max_linear_speed, __global kg_solver_body* bodies,
                                      __global const kg_velocity_step* steps)
{
    int i = (int)get_global_id(0);
    if (i < count) {
        kg_integrate_params prm = {kg_v2(0.0f, 0.0f), h, max_linear_speed};
        kg_integrate_body_velocity((kg_u32)i, bodies, steps, prm);
    }
}

__kernel void kg_integrate_positions(int count, float h, __global const kg_u32* flags,
                                     __global kg_solver_body* bodies)
{
    int i = (int)get_global_id(0);
    if (i >= count || !kg_flags_move(flags[i])) {
        return;
    }
    kg_body_motion m = bodies[i].motion;
    kg_integrate_position(&m.dp, &m.dq, m.v, m.w, h);
    bodies[i].motion = m;
}

__kernel void kg_store_bodies(int count, int sleep, float dt, float sleep_speed, __global const kg_u32* flags,
                              __global const kg_solver_body* bodies, __global kg_vec2* velocity,
                              __global float* omega, __global kg_vec2* center, __global kg_rot* rot,
                              __global const kg_shape* shape, __global const kg_vec2* local_center,
                              __global float* sleep_time)
{
    int i = (int)get_global_id(0);
    if (i < count) {
        kg_store_body((kg_u32)i, sleep, dt, sleep_speed, flags, bodies, velocity, omega, center, rot, shape,
                      local_center, sleep_time);
    }
}

/* Constraint k from contact k (contact_solver.h). */
__kernel void kg_prepare_contacts(int count, __global const kg_solver_params* params, __global const kg_contact* contacts,
                                  __global kg_contact_constraint* constraints, __global const kg_solver_body* bodies,
                                  __global const float* inv_mass, __global const float* inv_inertia,
                                  __global const kg_xf* xf, __global const kg_vec2* center)
{
    int k = (int)get_global_id(0);
    if (k >= count) {
        return;
    }
    kg_contact ct = contacts[k];
    kg_row_head head;
    kg_prepare_input in;
    kg_prepare_source(&ct, (kg_u32)k, bodies, inv_mass, inv_inertia, xf, center, &head, &in);
    kg_contact_constraint c;
    kg_constraint_head(&c, &head);
    kg_contact_prepare_lanes(&c, &in, *params);
    constraints[k] = c;
}

KG_FN void kg_store_motion(__global kg_solver_body* bodies, kg_u32 slot, kg_body_motion m)
{
    if (kg_slot_moves(bodies, slot)) {
        bodies[slot].motion.v = m.v;
        bodies[slot].motion.w = m.w;
    }
}

KG_FN void kg_solve_one(kg_contact_constraint* c, __global kg_solver_body* bodies, kg_solver_params prm, int pass)
{
    if (c->point_count == 0) {
        return; /* between sleeping or frozen bodies: nothing moves */
    }
    kg_body_motion a = kg_motion_of(bodies, c->a), b = kg_motion_of(bodies, c->b);
    kg_contact_pass(c, &a, &b, prm, pass);
    kg_store_motion(bodies, c->a, a);
    kg_store_motion(bodies, c->b, b);
}

/* The constraints grouped by colour (order is solve/coloring.h's), so that each pass reads a
 * colour's constraints from one contiguous range, as the CPU solver does. */
__kernel void kg_gather_colored(int count, __global const int* order,
                                __global const kg_contact_constraint* constraints,
                                __global kg_contact_constraint* colored)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        colored[k] = constraints[order[k]];
    }
}

KG_FN void kg_solve_at(__global kg_contact_constraint* colored, int index, __global kg_solver_body* bodies,
                       kg_solver_params prm, int pass)
{
    kg_contact_constraint c = colored[index];
    kg_solve_one(&c, bodies, prm, pass);
    colored[index] = c;
}

/* One pass over the colored constraints [first, first + count): one colour in parallel
 * (its constraints share no moving body), or, serial != 0, the overflow in order by a
 * single work-item. */
__kernel void kg_solve_color(int first, int count, int serial, int pass, __global const kg_solver_params* params,
                             __global kg_contact_constraint* colored, __global kg_solver_body* bodies)
{
    int k = (int)get_global_id(0);
    kg_solver_params prm = *params;
    if (!serial && k < count) {
        kg_solve_at(colored, first + k, bodies, prm, pass);
    }
    for (int j = 0; serial && k == 0 && j < count; ++j) {
        kg_solve_at(colored, first + j, bodies, prm, pass);
    }
}

/* One pass over every colour and the overflow, by a single work-group: the colours in
 * sequence with a barrier between them, the overflow by work-item 0. One launch instead
 * of one per colour, for worlds too small to fill the device, where launches cost more
 * than the work. color_start is solve/coloring.h's. */
__kernel void kg_solve_colors_in_group(int pass, __global const int* color_start,
                                       __global const kg_solver_params* params,
                                       __global kg_contact_constraint* colored, __global kg_solver_body* bodies)
{
    int lid = (int)get_local_id(0), size = (int)get_local_size(0);
    kg_solver_params prm = *params;
    for (int color = 0; color < KG_COLOR_COUNT; ++color) {
        for (int j = color_start[color] + lid; j < color_start[color + 1]; j += size) {
            kg_solve_at(colored, j, bodies, prm, pass);
        }
        barrier(CLK_GLOBAL_MEM_FENCE);
    }
    for (int j = color_start[KG_COLOR_COUNT]; lid == 0 && j < color_start[KG_COLOR_COUNT + 1]; ++j) {
        kg_solve_at(colored, j, bodies, prm, pass);
    }
}

/* Constraint k's impulses back into its contact. */
__kernel void kg_store_impulses(int count, __global const kg_contact_constraint* colored,
                                __global kg_contact* contacts)
{
    int k = (int)get_global_id(0);
    for (int j = 0; k < count && j < colored[k].point_count; ++j) {
        __global const kg_constraint_point* p = &colored[k].points[j];
        kg_store_point(&contacts[colored[k].contact].manifold.points[j], p->normal_impulse, p->tangent_impulse,
                       p->relative_velocity);
    }
}

/* ---- finalize -------------------------------------------------------------------- */

__kernel void kg_finalize(int count, float dt, __global kg_u32* flags, __global kg_vec2* center, __global kg_rot* rot,
                          __global kg_vec2* velocity, __global float* omega, __global kg_vec2* force,
                          __global float* torque, __global float* drag, __global kg_xf* xf, __global kg_aabb* aabb,
                          __global const kg_shape* shape, __global const kg_vec2* local_center)
{
    int i = (int)get_global_id(0);
    if (i < count) {
        kg_finalize_body((kg_u32)i, dt, flags, center, rot, velocity, omega, force, torque, drag, xf, aabb, shape,
                         local_center);
    }
}
