/* Semi-implicit (symplectic) Euler, per body: velocities first from forces, gravity and
 * damping, then positions from the new velocities. Shared by the CPU backend and the
 * kernels. Damping and drag are implicit, v' = (v + h a) / (1 + h c), so they are stable
 * for any h and c, and a constant force F against a drag d gives exactly F / d: an
 * explicit drag force -d v reverses and grows the velocity once d h / m > 2, which the
 * soak found on a 6 g body under three winds (400 m/s back and forth). */
#ifndef KG_INTEGRATE_H
#define KG_INTEGRATE_H

#include "core/kg_math.h"

/* Largest rotation per sub-step: beyond this the linearised rotation update loses accuracy. */
#define KG_MAX_ROTATION_PER_SUBSTEP (0.25f * 3.14159265f)

typedef struct kg_integrate_params {
    kg_vec2 gravity;
    float h;               /* sub-step length */
    float max_linear_speed;
} kg_integrate_params;

/* What a body's velocity update adds and scales by, constant over the sub-steps of a
 * step: made once a step (solve/body_step.h, kg_body_velocity_step), applied at every
 * sub-step. */
typedef struct kg_velocity_step {
    kg_vec2 dv;       /* h times the acceleration of gravity and the force */
    float dw;         /* h times the angular acceleration of the torque */
    float lin_factor; /* implicit linear damping and drag: 1 / (1 + h c) */
    float ang_factor; /* implicit angular damping */
} kg_velocity_step;

KG_STATIC_ASSERT(sizeof(kg_velocity_step) == 20, velocity_step_size);

/* drag: N s/m, the wind's; linear_damping: 1/s, the body's own. */
KG_FN kg_velocity_step kg_velocity_step_of(kg_vec2 force, float torque, float drag, float inv_mass, float inv_inertia,
                                           float linear_damping, float angular_damping, kg_integrate_params prm)
{
    float h = prm.h;
    kg_vec2 acc = inv_mass > 0.0f ? kg_mul_add(prm.gravity, inv_mass, force) : kg_v2(0.0f, 0.0f);
    kg_velocity_step s;
    s.dv = kg_scale(h, acc);
    s.dw = h * inv_inertia * torque;
    s.lin_factor = 1.0f / (1.0f + h * (linear_damping + inv_mass * drag));
    s.ang_factor = 1.0f / (1.0f + h * angular_damping);
    return s;
}

KG_FN void kg_apply_velocity_step(kg_vec2* v, float* w, kg_velocity_step s, kg_integrate_params prm)
{
    kg_vec2 nv = kg_scale(s.lin_factor, kg_add(*v, s.dv));
    float nw = s.ang_factor * (*w) + s.dw;
    /* Clamped along its direction, found from the velocity scaled to its largest
     * component first, so a huge but finite velocity does not overflow to nothing. */
    float max_speed = prm.max_linear_speed;
    float largest = kg_maxf(fabsf(nv.x), fabsf(nv.y));
    if (largest > max_speed || kg_length_sq(nv) > max_speed * max_speed) {
        nv = kg_scale(max_speed, kg_normalize(kg_scale(1.0f / largest, nv)));
    }
    float max_w = KG_MAX_ROTATION_PER_SUBSTEP / prm.h;
    *v = nv;
    *w = kg_clampf(nw, -max_w, max_w);
}

KG_FN void kg_integrate_position(kg_vec2* center, kg_rot* q, kg_vec2 v, float w, float h)
{
    *center = kg_mul_add(*center, h, v);
    *q = kg_rot_integrate(*q, h * w);
}

#endif
