/* A device force function's view of one body (kg_force_body, kgyro/opencl.h), shared by
 * the CPU backend's loop (backend/opencl/device_force.c) and the kernel that runs the
 * function on the device (kg_force.cl): both hand the function the same body, run it
 * `repeat` times, and keep only the force and torque it returns. Also the applicators'
 * targets as the kernels of forces read them. */
#ifndef KG_FORCE_BODY_H
#define KG_FORCE_BODY_H

#include "core/body_flags.h"
#include "core/kg_math.h"

#ifdef __OPENCL_VERSION__
/* kgyro/opencl.h's, field for field (only its size is checked on both sides: keep the
 * two in step), which a kernel cannot include */
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
#define KG_DEVICE_FORCE_MAX_PARAMS 16
/* The function a device force program is built with: the user's, named by the build
 * option KG_USER_FORCE_FN (only the force programs define it). On the device the function
 * reference of kg_apply_device_force is a placeholder. */
#ifdef KG_USER_FORCE_FN
void KG_USER_FORCE_FN(kg_force_body* body, const float* params);
#define KG_CALL_FORCE_FN(fn, body, params) KG_USER_FORCE_FN(body, params)
#endif
typedef int kg_force_fn_ref;
#else
#include "kgyro/opencl.h"
typedef kg_device_force_fn* kg_force_fn_ref;
#define KG_CALL_FORCE_FN(fn, body, params) (fn)(body, params)
#endif

KG_STATIC_ASSERT(sizeof(kg_force_body) == 56, force_body_size);

/* A device force's parameters, passed to its kernel by value. */
typedef struct kg_force_params {
    float values[KG_DEVICE_FORCE_MAX_PARAMS];
} kg_force_params;

KG_STATIC_ASSERT(sizeof(kg_force_params) == KG_DEVICE_FORCE_MAX_PARAMS * 4, force_params_size);

/* A body an applicator acts on, and how many times its list names it (the force applied
 * that many times in sequence). */
typedef struct kg_force_target {
    kg_u32 slot;
    kg_u32 repeat;
} kg_force_target;

KG_STATIC_ASSERT(sizeof(kg_force_target) == 8, force_target_size);

/* The target of a force kernel's work-item k: slot k, once, when the applicator acts on
 * every slot (all), else the k-th of its list, which names each slot once. */
KG_FN kg_force_target kg_force_target_of(int k, int all, KG_GLOBAL const kg_force_target* targets)
{
    kg_force_target every = {(kg_u32)k, 1u};
    return all ? every : targets[k];
}

/* Body i as the function sees it. */
KG_FN kg_force_body kg_force_body_of(kg_u32 i, KG_GLOBAL const kg_vec2* center, KG_GLOBAL const kg_rot* rot,
                                     KG_GLOBAL const kg_vec2* velocity, KG_GLOBAL const float* omega,
                                     KG_GLOBAL const float* mass, KG_GLOBAL const float* inertia,
                                     KG_GLOBAL const kg_vec2* force, KG_GLOBAL const float* torque)
{
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
    return body;
}

/* What the function left of the body: its force and torque, nothing else. */
KG_FN void kg_force_body_store(kg_u32 i, const kg_force_body* body, KG_GLOBAL kg_vec2* force, KG_GLOBAL float* torque)
{
    force[i] = body->force;
    torque[i] = body->torque;
}

#ifdef KG_CALL_FORCE_FN
/* Force function fn run on target t's body, if it is simulated, t.repeat times. */
KG_FN void kg_apply_device_force(kg_force_target t, kg_force_fn_ref fn, const float* params,
                                 KG_GLOBAL const kg_u32* flags, KG_GLOBAL const kg_vec2* center,
                                 KG_GLOBAL const kg_rot* rot, KG_GLOBAL const kg_vec2* velocity,
                                 KG_GLOBAL const float* omega, KG_GLOBAL const float* mass,
                                 KG_GLOBAL const float* inertia, KG_GLOBAL kg_vec2* force, KG_GLOBAL float* torque)
{
    if (!kg_flags_simulated(flags[t.slot])) {
        return;
    }
    kg_force_body body = kg_force_body_of(t.slot, center, rot, velocity, omega, mass, inertia, force, torque);
    for (kg_u32 r = 0u; r < t.repeat; ++r) {
        KG_CALL_FORCE_FN(fn, &body, params);
    }
    kg_force_body_store(t.slot, &body, force, torque);
}
#endif

#endif
