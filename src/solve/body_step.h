/* What a step does to one body, over the body pool's arrays and a slot: the CPU backend
 * loops over these (solve/forces.c, solve/solver.c) and each kernel of kg_step.cl calls
 * one for its work-item, so both backends compute the same bits. */
#ifndef KG_BODY_STEP_H
#define KG_BODY_STEP_H

#include "collide/aabb.h"
#include "core/body_flags.h"
#include "solve/contact_solver.h"
#include "solve/force_body.h"
#include "solve/integrate.h"
#include "solve/island.h"

/* A built-in applicator, passed to its kernel by value: gravity accelerates by vector,
 * wind pushes along vector by strength and adds its drag (integrated implicitly,
 * solve/integrate.h). */
typedef struct kg_builtin_force {
    kg_vec2 vector;
    float strength;
    float wind_drag;
    kg_i32 gravity;
    kg_i32 pad;
} kg_builtin_force;

KG_STATIC_ASSERT(sizeof(kg_builtin_force) == 24, builtin_force_size);

/* Applicator f's force on target t's body, t.repeat times over (a body listed twice in an
 * applicator gets it twice, in sequence): gravity pulls by the body's mass. */
KG_FN void kg_builtin_force_on(kg_force_target t, kg_builtin_force f, KG_GLOBAL const kg_u32* flags,
                               KG_GLOBAL const float* mass, KG_GLOBAL kg_vec2* force, KG_GLOBAL float* drag)
{
    kg_u32 i = t.slot;
    if (!kg_flags_simulated(flags[i])) {
        return;
    }
    kg_vec2 push = kg_scale(f.gravity ? mass[i] : f.strength, f.vector);
    kg_vec2 sum = force[i];
    float drag_sum = drag[i];
    for (kg_u32 r = 0u; r < t.repeat; ++r) {
        sum = kg_add(sum, push);
        drag_sum += f.gravity ? 0.0f : f.wind_drag;
    }
    force[i] = sum;
    drag[i] = drag_sum;
}

/* Takes body i out of the simulation, back at its last finite pose, still. (The CPU
 * backend warns at once, the OpenCL backend when it next reads the flags back.) */
KG_FN void kg_freeze_body(kg_u32 i, KG_GLOBAL kg_u32* flags, KG_GLOBAL kg_vec2* velocity, KG_GLOBAL float* omega,
                          KG_GLOBAL kg_vec2* force, KG_GLOBAL float* torque, KG_GLOBAL kg_rot* rot,
                          KG_GLOBAL kg_vec2* center, KG_GLOBAL const kg_xf* xf, KG_GLOBAL const kg_vec2* local_center)
{
    kg_xf last = xf[i];
    flags[i] |= KG_FLAG_FROZEN;
    velocity[i] = kg_v2(0.0f, 0.0f);
    omega[i] = 0.0f;
    force[i] = kg_v2(0.0f, 0.0f);
    torque[i] = 0.0f;
    rot[i] = last.q;
    center[i] = kg_xf_point(last, local_center[i]);
}

/* What the integration of body i's velocity adds and scales by over the step's sub-steps
 * (solve/integrate.h), from its forces, drag, masses and damping. */
KG_FN kg_velocity_step kg_body_velocity_step(kg_u32 i, KG_GLOBAL const kg_vec2* force, KG_GLOBAL const float* torque,
                                             KG_GLOBAL const float* drag, KG_GLOBAL const float* inv_mass,
                                             KG_GLOBAL const float* inv_inertia, KG_GLOBAL const float* linear_damping,
                                             KG_GLOBAL const float* angular_damping, kg_integrate_params prm)
{
    return kg_velocity_step_of(force[i], torque[i], drag[i], inv_mass[i], inv_inertia[i], linear_damping[i],
                               angular_damping[i], prm);
}

/* One sub-step's velocity update of body i, if it takes impulses. */
KG_FN void kg_integrate_body_velocity(kg_u32 i, KG_GLOBAL kg_solver_body* bodies,
                                      KG_GLOBAL const kg_velocity_step* steps, kg_integrate_params prm)
{
    if (bodies[i].moves) {
        kg_body_motion m = bodies[i].motion;
        kg_velocity_step s = steps[i];
        kg_apply_velocity_lanes(&m.v, &m.w, &s, prm);
        bodies[i].motion.v = m.v;
        bodies[i].motion.w = m.w;
    }
}

/* One sub-step's motion of body i, if it moves, from its velocities. */
KG_FN void kg_integrate_body_position(kg_u32 i, float h, KG_GLOBAL const kg_u32* flags,
                                      KG_GLOBAL kg_solver_body* bodies)
{
    if (kg_flags_move(flags[i])) {
        kg_body_motion m = bodies[i].motion;
        kg_integrate_position_lanes(&m.dp, &m.dq, m.v, m.w, h);
        bodies[i].motion.dp = m.dp;
        bodies[i].motion.dq = m.dq;
    }
}

/* Body i's solver body at the start of the solve. What reached it between steps
 * non-finite (an overflowing impulse or force through the API) is frozen first, so it
 * cannot reach a neighbour through a contact. Returns 1 when it froze the body. */
KG_FN int kg_load_body(kg_u32 i, KG_GLOBAL kg_u32* flags, KG_GLOBAL kg_vec2* velocity, KG_GLOBAL float* omega,
                       KG_GLOBAL kg_vec2* force, KG_GLOBAL float* torque, KG_GLOBAL kg_rot* rot,
                       KG_GLOBAL kg_vec2* center, KG_GLOBAL const kg_xf* xf, KG_GLOBAL const kg_vec2* local_center,
                       KG_GLOBAL kg_solver_body* bodies)
{
    int finite = kg_vec_is_finite(velocity[i]) && kg_is_finite(omega[i]) && kg_vec_is_finite(force[i]) &&
                 kg_is_finite(torque[i]);
    int freeze = kg_flags_simulated(flags[i]) && !finite;
    if (freeze) {
        kg_freeze_body(i, flags, velocity, omega, force, torque, rot, center, xf, local_center);
    }
    kg_solver_body sb;
    sb.motion.v = velocity[i];
    sb.motion.w = omega[i];
    sb.motion.dp = kg_v2(0.0f, 0.0f);
    sb.motion.dq = kg_rot_identity();
    sb.moves = (kg_u32)kg_flags_simulated(flags[i]);
    bodies[i] = sb;
    return freeze;
}

/* Body i loaded for the solve (kg_load_body) and, if it takes impulses, the velocity
 * step of its sub-steps made. Returns 1 when it froze the body. */
KG_FN int kg_load_body_for_step(kg_u32 i, KG_GLOBAL kg_u32* flags, KG_GLOBAL kg_vec2* velocity, KG_GLOBAL float* omega,
                                KG_GLOBAL kg_vec2* force, KG_GLOBAL float* torque, KG_GLOBAL kg_rot* rot,
                                KG_GLOBAL kg_vec2* center, KG_GLOBAL const kg_xf* xf,
                                KG_GLOBAL const kg_vec2* local_center, KG_GLOBAL kg_solver_body* bodies,
                                KG_GLOBAL const float* drag, KG_GLOBAL const float* inv_mass,
                                KG_GLOBAL const float* inv_inertia, KG_GLOBAL const float* linear_damping,
                                KG_GLOBAL const float* angular_damping, kg_integrate_params prm,
                                KG_GLOBAL kg_velocity_step* steps)
{
    int froze = kg_load_body(i, flags, velocity, omega, force, torque, rot, center, xf, local_center, bodies);
    if (bodies[i].moves) {
        steps[i] = kg_body_velocity_step(i, force, torque, drag, inv_mass, inv_inertia, linear_damping,
                                         angular_damping, prm);
    }
    return froze;
}

/* How the end of the solve keeps the rest timers (passed to its kernel by value). */
typedef struct kg_rest_params {
    float dt;          /* of the whole step */
    float sleep_speed; /* kg_world_def's */
    kg_i32 sleep;      /* kg_world_def.enable_sleep: rest timers are kept */
} kg_rest_params;

KG_STATIC_ASSERT(sizeof(kg_rest_params) == 12, rest_params_size);

/* Body i's velocities back to the pool and the step's motion applied to its pose; with
 * sleeping on, its rest timer advanced over the step's motion. */
KG_FN void kg_store_body(kg_u32 i, kg_rest_params rest, KG_GLOBAL const kg_u32* flags,
                         KG_GLOBAL const kg_solver_body* bodies, KG_GLOBAL kg_vec2* velocity, KG_GLOBAL float* omega,
                         KG_GLOBAL kg_vec2* center, KG_GLOBAL kg_rot* rot, KG_GLOBAL const kg_shape* shape,
                         KG_GLOBAL const kg_vec2* local_center, KG_GLOBAL float* sleep_time)
{
    if (!kg_flags_move(flags[i])) {
        return;
    }
    kg_body_motion m = bodies[i].motion;
    velocity[i] = m.v;
    omega[i] = m.w;
    center[i] = kg_add(center[i], m.dp);
    rot[i] = kg_rot_normalize(kg_rot_mul(m.dq, rot[i]));
    if (rest.sleep && bodies[i].moves) {
        KG_PRIVATE_VIEW(kg_shape, s, shape[i]);
        float extent = kg_shape_extent(s, local_center[i]);
        sleep_time[i] = kg_rest_timer(sleep_time[i], m, extent, rest.dt, rest.sleep_speed);
    }
}

KG_FN int kg_state_finite(kg_vec2 c, kg_rot q, kg_vec2 v, float w)
{
    return kg_vec_is_finite(c) && kg_vec_is_finite(v) && kg_is_finite(w) && kg_is_finite(q.c) && kg_is_finite(q.s);
}

/* The end of body i's step: forces cleared; a body whose state became non-finite frozen
 * at its last finite pose; the origin's pose updated, and the bounds swept over the
 * motion of the next step (dt of this one). Returns 1 when it froze the body. */
KG_FN int kg_finalize_body(kg_u32 i, float dt, KG_GLOBAL kg_u32* flags, KG_GLOBAL kg_vec2* center,
                           KG_GLOBAL kg_rot* rot, KG_GLOBAL kg_vec2* velocity, KG_GLOBAL float* omega,
                           KG_GLOBAL kg_vec2* force, KG_GLOBAL float* torque, KG_GLOBAL float* drag,
                           KG_GLOBAL kg_xf* xf, KG_GLOBAL kg_aabb* aabb, KG_GLOBAL const kg_shape* shape,
                           KG_GLOBAL const kg_vec2* local_center)
{
    kg_u32 f = flags[i];
    if (!kg_flags_alive(f)) {
        return 0;
    }
    force[i] = kg_v2(0.0f, 0.0f);
    torque[i] = 0.0f;
    drag[i] = 0.0f;
    kg_vec2 c = center[i];
    kg_rot q = rot[i];
    if ((f & KG_FLAG_FROZEN) == 0u && !kg_state_finite(c, q, velocity[i], omega[i])) {
        kg_freeze_body(i, flags, velocity, omega, force, torque, rot, center, xf, local_center);
        return 1;
    }
    if (kg_flags_type(f) == KG_BODY_STATIC) {
        return 0;
    }
    kg_xf t = kg_origin_xf(c, q, local_center[i]);
    KG_PRIVATE_VIEW(kg_shape, s, shape[i]);
    xf[i] = t;
    aabb[i] = kg_aabb_sweep(kg_shape_aabb(s, t), kg_scale(dt, velocity[i]));
    return 0;
}

#endif
