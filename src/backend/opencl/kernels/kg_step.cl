/* The kernels of a step: one work-item per body, contact or constraint, each calling the
 * per-element function of solve/body_step.h or solve/contact_solver.h that the CPU
 * backend calls, on the same data layout, so both backends compute the same bits. Every
 * kernel takes its element count and returns for the padding work-items. */
#include "collide/continuous.h"
#include "solve/body_step.h"
#include "solve/coloring.h"

/* A built-in applicator on every body (all != 0: work-item k is slot k) or on a list of
 * targets, each slot once. */
__kernel void kg_apply_builtin_force(int count, int all, __global const kg_force_target* targets, kg_builtin_force f,
                                     __global const kg_u32* flags, __global const float* mass, __global kg_vec2* force,
                                     __global float* drag)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_builtin_force_on(kg_force_target_of(k, all, targets), f, flags, mass, force, drag);
    }
}

__kernel void kg_load_bodies(int count, kg_integrate_params prm, __global kg_u32* flags, __global kg_vec2* velocity,
                             __global float* omega, __global kg_vec2* force, __global float* torque,
                             __global kg_rot* rot, __global kg_vec2* center, __global const kg_xf* xf,
                             __global const kg_vec2* local_center, __global kg_solver_body* bodies,
                             __global const float* drag, __global const float* inv_mass,
                             __global const float* inv_inertia, __global const float* linear_damping,
                             __global const float* angular_damping, __global kg_velocity_step* steps)
{
    int i = (int)get_global_id(0);
    if (i < count) {
        kg_load_body_for_step((kg_u32)i, flags, velocity, omega, force, torque, rot, center, xf, local_center, bodies,
                              drag, inv_mass, inv_inertia, linear_damping, angular_damping, prm, steps);
    }
}

__kernel void kg_integrate_velocities(int count, kg_integrate_params prm, __global kg_solver_body* bodies,
                                      __global const kg_velocity_step* steps)
{
    int i = (int)get_global_id(0);
    if (i < count) {
        kg_integrate_body_velocity((kg_u32)i, bodies, steps, prm);
    }
}

__kernel void kg_integrate_positions(int count, float h, __global const kg_u32* flags, __global kg_solver_body* bodies)
{
    int i = (int)get_global_id(0);
    if (i < count) {
        kg_integrate_body_position((kg_u32)i, h, flags, bodies);
    }
}

__kernel void kg_store_bodies(int count, kg_rest_params rest, __global const kg_u32* flags,
                              __global const kg_solver_body* bodies, __global kg_vec2* velocity, __global float* omega,
                              __global kg_vec2* center, __global kg_rot* rot, __global const kg_shape* shape,
                              __global const kg_vec2* local_center, __global float* sleep_time)
{
    int i = (int)get_global_id(0);
    if (i < count) {
        kg_store_body((kg_u32)i, rest, flags, bodies, velocity, omega, center, rot, shape, local_center, sleep_time);
    }
}

__kernel void kg_prepare_contacts(int count, __global const kg_solver_params* params,
                                  __global const kg_contact* contacts, __global kg_contact_constraint* constraints,
                                  __global const kg_solver_body* bodies, __global const float* inv_mass,
                                  __global const float* inv_inertia, __global const kg_xf* xf,
                                  __global const kg_vec2* center)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_prepare_contact((kg_u32)k, *params, contacts, constraints, bodies, inv_mass, inv_inertia, xf, center);
    }
}

/* The constraints grouped by colour (order is solve/coloring.h's), so that each pass reads a
 * colour's constraints from one contiguous range, as the CPU solver does. */
__kernel void kg_gather_colored(int count, __global const int* order, __global const kg_contact_constraint* constraints,
                                __global kg_contact_constraint* colored)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        colored[k] = constraints[order[k]];
    }
}

/* One pass over the colored constraints [first, first + count): one colour in parallel,
 * or, serial != 0, the overflow in order by a single work-item. */
__kernel void kg_solve_color(int first, int count, int serial, int pass, __global const kg_solver_params* params,
                             __global kg_contact_constraint* colored, __global kg_solver_body* bodies)
{
    kg_solve_share((int)get_global_id(0), (int)get_global_size(0), first, first + count, serial, colored, bodies,
                   *params, pass);
}

/* One pass over every colour, then the overflow, by a single work-group with a barrier
 * between them: one launch instead of one per colour, for worlds too small to fill the
 * device, where launches cost more than the work. color_start is solve/coloring.h's. */
__kernel void kg_solve_colors_in_group(int pass, __global const int* color_start,
                                       __global const kg_solver_params* params, __global kg_contact_constraint* colored,
                                       __global kg_solver_body* bodies)
{
    for (int c = 0; c <= KG_COLOR_COUNT; ++c) {
        kg_solve_share((int)get_local_id(0), (int)get_local_size(0), color_start[c], color_start[c + 1],
                       c == KG_COLOR_COUNT, colored, bodies, *params, pass);
        barrier(CLK_GLOBAL_MEM_FENCE);
    }
}

__kernel void kg_store_impulses(int count, __global const kg_contact_constraint* colored, __global kg_contact* contacts)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_store_impulses_of(&colored[k], contacts);
    }
}

/* Finalize pass `pass` (collide/continuous.h): with continuous collision on, a body that
 * takes part is first moved back to its time of impact (its extents computed here, the
 * CPU keeps them per slot: the same function of the shapes). The shape arrays come in
 * kg_shape_arrays' order. */
__kernel void kg_finalize(int count, float dt, int pass, int continuous, kg_toi_params prm, __global kg_u32* flags,
                          __global kg_vec2* center, __global kg_rot* rot, __global kg_vec2* velocity,
                          __global float* omega, __global kg_vec2* force, __global float* torque, __global float* drag,
                          __global kg_xf* xf, __global kg_aabb* aabb, __global const kg_shape* shape,
                          __global const kg_vec2* local_center, __global const kg_static_entry* statics,
                          int static_count, int large_count, __global const kg_tile_map_info* maps,
                          __global const kg_u32* cells, __global const kg_tile_proto* protos, int map_count,
                          __global const kg_u32* shape_count, __global const kg_u32* first_shape,
                          __global const kg_shape* body_shape, __global const kg_shape* geometry, __global const kg_u32* next,
                          __global const kg_u32* shape_flags, __global const kg_u32* shape_category,
                          __global const kg_u32* shape_mask)
{
    int i = (int)get_global_id(0);
    if (i >= count || !kg_finalized_in_pass(flags[i], continuous, pass)) {
        return;
    }
    if (continuous && kg_continuous_takes(flags[i], pass)) {
        kg_shape_arrays s = {shape_count, first_shape, body_shape, geometry, next, shape_flags, shape_category, shape_mask};
        kg_continuous_bodies b = {flags,   velocity,     omega,       center,      rot,   xf, aabb,
                                  local_center, statics, static_count, large_count, count, s, 0, 0, 0};
        kg_tile_terrain t = {maps, cells, protos, map_count, 0.0f, 0.0f};
        kg_continuous_body(&b, &t, (kg_u32)i, pass, prm, dt, kg_body_extents(&s, (kg_u32)i, local_center[i]));
    }
    kg_finalize_body((kg_u32)i, dt, flags, center, rot, velocity, omega, force, torque, drag, xf, aabb, shape,
                     local_center);
}
