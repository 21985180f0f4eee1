/* The prelude of a device force applicator's program: the user's source follows it, and
 * defines KG_USER_FORCE_FN (a build option naming the user's function). The kernel hands
 * each target body to the function as solve/force_body.h says, as the CPU backend's loop
 * does. */
#include "solve/force_body.h"

void KG_USER_FORCE_FN(kg_force_body* body, const float* params);

/* Targets as in kg_apply_builtin_force: every slot (all != 0) or (slot, multiplicity)
 * pairs, each slot once, the function called multiplicity times in sequence. */
__kernel void kg_device_force(int count, int all, __global const uint2* targets, __constant float* params_in,
                              __global const uint* flags, __global const kg_vec2* center,
                              __global const kg_rot* rot, __global const kg_vec2* velocity,
                              __global const float* omega, __global const float* mass,
                              __global const float* inertia, __global kg_vec2* force, __global float* torque)
{
    int k = (int)get_global_id(0);
    if (k >= count) {
        return;
    }
    uint i = all ? (uint)k : targets[k].x;
    uint repeat = all ? 1u : targets[k].y;
    if (!kg_flags_simulated(flags[i])) {
        return;
    }
    float params[KG_DEVICE_FORCE_MAX_PARAMS];
    for (int p = 0; p < KG_DEVICE_FORCE_MAX_PARAMS; ++p) {
        params[p] = params_in[p];
    }
    kg_force_body body = kg_force_body_of(i, center, rot, velocity, omega, mass, inertia, force, torque);
    for (uint r = 0; r < repeat; ++r) {
        KG_USER_FORCE_FN(&body, params);
    }
    kg_force_body_store(i, &body, force, torque);
}
