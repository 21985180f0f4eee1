/* The contact constraint and its per-constraint solver functions, shared by the CPU
 * backend and the kernels. It is Box2D v3's "soft step" (Catto, Solver2D, 2024):
 *
 *  - Penetration is resolved inside the velocity solve by a soft constraint (a spring
 *    of contact_hertz with a damping ratio), so bodies are pushed apart at a bounded
 *    speed and, after each sub-step, a relax pass without the push removes the velocity
 *    the push added: the original engine's "interpenetration" pass, without adding energy.
 *  - Normal impulses are accumulated and clamped at zero; friction is bounded by
 *    friction * normal impulse (Coulomb); both are warm started from the last step.
 *  - Restitution is one pass at the end of the step, from the approach speed measured
 *    before solving, only above a threshold so resting contacts do not jitter: the
 *    original engine's "velocity" pass.
 *
 * The functions read and write body velocities passed by pointer (private memory in a
 * kernel); graph colouring guarantees no two constraints solved together share a body. */
#ifndef KG_CONTACT_SOLVER_H
#define KG_CONTACT_SOLVER_H

#include "core/kg_layout.h"

typedef struct kg_softness {
    float bias_rate;
    float mass_scale;
    float impulse_scale;
} kg_softness;

KG_STATIC_ASSERT(sizeof(kg_softness) == 12, softness_size);

/* Per-step solver parameters. */
typedef struct kg_solver_params {
    float h;                 /* sub-step */
    float inv_h;
    float max_push_out_speed;
    float linear_slop;
    float restitution_threshold;
    kg_softness contact_softness; /* between two moving bodies */
    kg_softness static_softness;  /* against an immovable body: stiffer */
} kg_solver_params;

/* The passes over one constraint, a float a lane (contact_row.h; the CPU's SIMD widths
 * are instantiated in solve/contact_wide.c). */
#define KG_W 1
#define kg_lane float
#define kg_lmask int
#define kg_lindex kg_u32
#define kg_lint kg_i32
#define KG_SEL(mask, a, b) ((mask) ? (a) : (b))
#define KG_LZERO 0.0f
#include "solve/contact_row.h"
#undef kg_lane
#undef kg_lmask
#undef kg_lindex
#undef kg_lint
#undef KG_SEL
#undef KG_LZERO
#undef KG_W

KG_STATIC_ASSERT(sizeof(kg_constraint_point) == 48, constraint_point_size);
KG_STATIC_ASSERT(sizeof(kg_contact_constraint) == 176, contact_constraint_size);

/* What the solver reads and writes of a body, packed in 32 bytes so a constraint
 * touches two cache-line halves instead of six scattered arrays. The pool's poses stay
 * put during the solve: dp and dq accumulate and are applied at the end. */
typedef struct kg_solver_body {
    kg_body_motion motion;
    kg_u32 moves; /* takes impulses: dynamic body or particle */
} kg_solver_body;

KG_STATIC_ASSERT(sizeof(kg_solver_body) == 32, solver_body_size);

KG_FN kg_softness kg_make_softness(float hertz, float damping_ratio, float h)
{
    kg_softness s;
    if (hertz == 0.0f) {
        s.bias_rate = 0.0f;
        s.mass_scale = 1.0f;
        s.impulse_scale = 0.0f;
        return s;
    }
    float omega = 2.0f * 3.14159265359f * hertz;
    float a1 = 2.0f * damping_ratio + h * omega;
    float a2 = h * omega * a1;
    float a3 = 1.0f / (1.0f + a2);
    s.bias_rate = omega / a1;
    s.mass_scale = a2 * a3;
    s.impulse_scale = a3;
    return s;
}

/* Above this condition number the two normal rows are nearly redundant and the 2x2
 * solve is unreliable (Box2D v2's limit). */
#define KG_MAX_BLOCK_CONDITION 1000.0f

/* The inverse of a two-point contact's 2x2 normal mass, from the anchors at prepare,
 * for the block solve; block 0 (one point at a time) when there is one point or the
 * rows are too nearly redundant. */
KG_FN void kg_prepare_block(kg_contact_constraint* c)
{
    kg_vec2 n = c->normal;
    float ra0 = kg_cross(c->points[0].anchor_a, n), rb0 = kg_cross(c->points[0].anchor_b, n);
    float ra1 = kg_cross(c->points[1].anchor_a, n), rb1 = kg_cross(c->points[1].anchor_b, n);
    float m = c->inv_mass_a + c->inv_mass_b;
    float k11 = m + c->inv_i_a * ra0 * ra0 + c->inv_i_b * rb0 * rb0;
    float k22 = m + c->inv_i_a * ra1 * ra1 + c->inv_i_b * rb1 * rb1;
    float k12 = m + c->inv_i_a * ra0 * ra1 + c->inv_i_b * rb0 * rb1;
    float det = k11 * k22 - k12 * k12;
    int ok = c->point_count == 2 && k11 * k11 < KG_MAX_BLOCK_CONDITION * det;
    float inv_det = ok ? 1.0f / det : 0.0f;
    c->inv_k11 = inv_det * k22;
    c->inv_k12 = -inv_det * k12;
    c->inv_k22 = inv_det * k11;
    c->block = ok ? 1.0f : 0.0f;
}

/* Builds the constraint of one contact from its manifold and the bodies' current state.
 * center_* are the centres of mass, origin_* the body origins (the manifold's anchors
 * are relative to the origins). A point the manifold does not have is all zeros, so the
 * passes, which always run both points, leave it at zero. */
KG_FN void kg_contact_prepare(kg_contact_constraint* c, const kg_manifold* m, kg_vec2 origin_a, kg_vec2 center_a,
                              kg_vec2 origin_b, kg_vec2 center_b, kg_vec2 va, float wa, kg_vec2 vb, float wb,
                              kg_solver_params prm)
{
    float ma = c->inv_mass_a, ia = c->inv_i_a, mb = c->inv_mass_b, ib = c->inv_i_b;
    int against_static = (ma == 0.0f && ia == 0.0f) || (mb == 0.0f && ib == 0.0f);
    kg_softness soft = against_static ? prm.static_softness : prm.contact_softness;
    c->bias_rate = soft.bias_rate;
    c->mass_scale = soft.mass_scale;
    c->impulse_scale = soft.impulse_scale;
    c->share_b = ma + mb > 0.0f ? mb / (ma + mb) : 0.5f;
    c->normal = m->normal;
    c->point_count = m->point_count;
    kg_vec2 n = m->normal, t = kg_right_perp(m->normal);
    for (int j = 0; j < 2; ++j) {
        kg_constraint_point* cp = &c->points[j];
        if (j >= m->point_count) {
            kg_constraint_point none = {{0.0f, 0.0f}, {0.0f, 0.0f}, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
            *cp = none;
            continue;
        }
        const kg_manifold_point* mp = &m->points[j];
        kg_vec2 ra = kg_sub(kg_add(mp->anchor_a, origin_a), center_a);
        kg_vec2 rb = kg_sub(kg_add(mp->anchor_b, origin_b), center_b);
        cp->anchor_a = ra;
        cp->anchor_b = rb;
        cp->base_separation = mp->separation - kg_dot(kg_sub(rb, ra), n);
        cp->normal_impulse = mp->normal_impulse;
        cp->tangent_impulse = mp->tangent_impulse;
        cp->max_normal_impulse = 0.0f;
        float rna = kg_cross(ra, n), rnb = kg_cross(rb, n);
        float kn = ma + mb + ia * rna * rna + ib * rnb * rnb;
        cp->normal_mass = kn > 0.0f ? 1.0f / kn : 0.0f;
        float rta = kg_cross(ra, t), rtb = kg_cross(rb, t);
        float kt = ma + mb + ia * rta * rta + ib * rtb * rtb;
        cp->tangent_mass = kt > 0.0f ? 1.0f / kt : 0.0f;
        kg_vec2 dv = kg_sub(kg_lpoint_velocity(vb, wb, rb), kg_lpoint_velocity(va, wa, ra));
        cp->relative_velocity = kg_dot(n, dv);
        cp->pad = 0.0f;
    }
    kg_prepare_block(c);
}

#endif
