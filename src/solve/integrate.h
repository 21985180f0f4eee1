/* Semi-implicit (symplectic) Euler, per body: velocities first from forces, gravity and
 * damping, then positions from the new velocities (solve/body_row.h, written over lanes;
 * this header holds its parameters and the velocity step made once a step). Shared by the
 * CPU backend and the kernels. Damping and drag are implicit, v' = (v + h a) / (1 + h c), so they are stable
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
 * sub-step. Eight floats, as a solver body, so that the CPU moves those of W bodies
 * into lanes with the same transposes (solve/contact_wide_impl.h). */
typedef struct kg_velocity_step {
    kg_vec2 dv;       /* h times the acceleration of gravity and the force */
    float dw;         /* h times the angular acceleration of the torque */
    float lin_factor; /* implicit linear damping and drag: 1 / (1 + h c) */
    float ang_factor; /* implicit angular damping */
    float unused[3];
} kg_velocity_step;

KG_STATIC_ASSERT(sizeof(kg_velocity_step) == 32, velocity_step_size);

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
    s.unused[0] = s.unused[1] = s.unused[2] = 0.0f;
    return s;
}

#endif
