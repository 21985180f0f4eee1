/* The prelude of a device force applicator's program: the user's source follows it, and
 * defines KG_USER_FORCE_FN (a build option naming the user's function). The kernel gives
 * each target body to the function as kg_force_body (kgyro/opencl.h), the way the CPU
 * backend's loop does, and keeps only the force and torque it returns. */
#include "core/body_flags.h"
#include "core/kg_math.h"

typedef struct kg_force_body {
    kg_vec2 position;
    kg_vec2 rotation;
    kg_vec2 velocity;
    float angular_velocity;
    float mass;
    float inertia;
    float torque;
    kg_vec2 force;
    uint index;
    uint pad;
} kg_force_body;

KG_STATIC_ASSERT(sizeof(kg_force_body) == 56, force_body_size);

#define KG_DEVICE_FORCE_MAX_PARAMS 16

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
    kg_force_body body;
    body.position = center[i];
    body.rotation = kg_v2(rot[i].c, rot[i].s);
    body.velocity = velocity[i];
    body.angular_velocity = omega[i];
    body.mass = mass[i];
    body.inertia = inertia[i];
    body.torque = torque[i];
    body.force = force[i];
    body.index = i;
    body.pad = 0u;
    for (uint r = 0; r < repeat; ++r) {
        KG_USER_FORCE_FN(&body, params);
    }
    force[i] = body.force;
    torque[i] = body.torque;
}
