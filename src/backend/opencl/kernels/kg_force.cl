/* The prelude of a device force applicator's program: the user's source follows it, and
 * defines KG_USER_FORCE_FN (a build option naming the user's function), which
 * solve/force_body.h declares and calls. */
#include "solve/force_body.h"

/* Targets as in kg_apply_builtin_force: every slot (all != 0) or a list, each slot once. */
__kernel void kg_device_force(int count, int all, __global const kg_force_target* targets, kg_force_params params,
                              __global const kg_u32* flags, __global const kg_vec2* center, __global const kg_rot* rot,
                              __global const kg_vec2* velocity, __global const float* omega, __global const float* mass,
                              __global const float* inertia, __global kg_vec2* force, __global float* torque)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_apply_device_force(kg_force_target_of(k, all, targets), 0, params.values, flags, center, rot, velocity,
                              omega, mass, inertia, force, torque);
    }
}
