/* The joints' kernels (solve/joint_row.h): each maps its work-item to a joint and calls
 * the function the CPU's loop calls (core/joint.c), so both backends would compute the
 * same bits. Not yet launched: the host side (uploading the rows when joints change,
 * checkpointing them, the passes in the sub-step loop, joint links in the device's
 * islands and the collide_connected filter on the device's pairs) is docs/joints.md's
 * "What is left"; until then an OpenCL world refuses joints (KG_ERROR_UNSUPPORTED).
 * Built with the program, so the shared rows are checked as OpenCL C on every build. */
#include "solve/joint_row.h"

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

/* One pass over every joint, serially in slot order, iterations times, by work-item 0:
 * the CPU's order (joints are not coloured yet). */
__kernel void kg_solve_joints(int count, int iterations, int pass, __global const kg_solver_params* params,
                              __global kg_joint_row* rows, __global kg_solver_body* bodies)
{
    if (get_global_id(0) != 0) {
        return;
    }
    for (int it = 0; it < iterations; ++it) {
        for (int j = 0; j < count; ++j) {
            kg_joint_pass(rows, j, bodies, *params, pass);
        }
    }
}
