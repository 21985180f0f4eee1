/* A device force function's view of one body (kg_force_body, kgyro/opencl.h), shared by
 * the CPU backend's loop (backend/opencl/device_force.c) and the kernel that runs the
 * function on the device (kg_force.cl): both hand the function the same body, run it
 * `repeat` times, and keep only the force and torque it returns. */
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
#else
#include "kgyro/opencl.h"
#endif

KG_STATIC_ASSERT(sizeof(kg_force_body) == 56, force_body_size);

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

#endif
