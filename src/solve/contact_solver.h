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

typedef struct kg_constraint_point {
    kg_vec2 anchor_a, anchor_b; /* from each body's centre of mass, world axes, at step start */
    float base_separation;      /* separation minus the anchors' offset along the normal */
    float normal_impulse;
    float tangent_impulse;
    float max_normal_impulse;   /* largest over the sub-steps: a point that never pushed does not bounce */
    float normal_mass;
    float tangent_mass;
    float relative_velocity;    /* approach speed before solving, for restitution */
    float pad;
} kg_constraint_point;

typedef struct kg_contact_constraint {
    kg_constraint_point points[2];
    kg_vec2 normal;
    kg_u32 a, b;                /* body slots; KG_NULL_INDEX = the static world */
    float inv_mass_a, inv_i_a, inv_mass_b, inv_i_b;
    float friction, restitution;
    kg_softness softness;
    kg_i32 point_count;
    kg_u32 contact;             /* index of the contact it came from */
    float share_b;              /* b's share of the inverse mass: where the anchors meet */
} kg_contact_constraint;

KG_STATIC_ASSERT(sizeof(kg_softness) == 12, softness_size);
KG_STATIC_ASSERT(sizeof(kg_constraint_point) == 48, constraint_point_size);
KG_STATIC_ASSERT(sizeof(kg_contact_constraint) == 160, contact_constraint_size);

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

/* A body's motion seen by the solver: velocity, and how far it moved and turned since
 * the step began (to update separations without recomputing the manifold). */
typedef struct kg_body_motion {
    kg_vec2 v;
    float w;
    kg_vec2 dp;
    kg_rot dq;
} kg_body_motion;

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

KG_FN kg_vec2 kg_point_velocity(kg_vec2 v, float w, kg_vec2 r) { return kg_add(v, kg_cross_sv(w, r)); }

/* Builds the constraint of one contact from its manifold and the bodies' current state.
 * center_* are the centres of mass, origin_* the body origins (the manifold's anchors
 * are relative to the origins). */
KG_FN void kg_contact_prepare(kg_contact_constraint* c, const kg_manifold* m, kg_vec2 origin_a, kg_vec2 center_a,
                              kg_vec2 origin_b, kg_vec2 center_b, kg_vec2 va, float wa, kg_vec2 vb, float wb,
                              kg_solver_params prm)
{
    float ma = c->inv_mass_a, ia = c->inv_i_a, mb = c->inv_mass_b, ib = c->inv_i_b;
    int against_static = (ma == 0.0f && ia == 0.0f) || (mb == 0.0f && ib == 0.0f);
    c->share_b = ma + mb > 0.0f ? mb / (ma + mb) : 0.5f;
    c->softness = against_static ? prm.static_softness : prm.contact_softness;
    c->normal = m->normal;
    c->point_count = m->point_count;
    kg_vec2 n = m->normal, t = kg_right_perp(m->normal);
    for (int j = 0; j < m->point_count; ++j) {
        const kg_manifold_point* mp = &m->points[j];
        kg_constraint_point* cp = &c->points[j];
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
        kg_vec2 dv = kg_sub(kg_point_velocity(vb, wb, rb), kg_point_velocity(va, wa, ra));
        cp->relative_velocity = kg_dot(n, dv);
        cp->pad = 0.0f;
    }
}

KG_FN void kg_apply_impulse_pair(const kg_contact_constraint* c, kg_body_motion* a, kg_body_motion* b, kg_vec2 ra,
                                 kg_vec2 rb, kg_vec2 p)
{
    a->v = kg_mul_sub(a->v, c->inv_mass_a, p);
    a->w -= c->inv_i_a * kg_cross(ra, p);
    b->v = kg_mul_add(b->v, c->inv_mass_b, p);
    b->w += c->inv_i_b * kg_cross(rb, p);
}

/* The anchors an impulse acts at. Box2D keeps each body's anchor fixed relative to its
 * centre during the step; but the bodies move apart, so the equal and opposite impulses
 * (normal and friction) then act at two points and add a torque to the pair (angular
 * momentum drifted by 1e-3 in an off-centre hit). Both anchors are moved to one point,
 * weighted by inverse mass: against an immovable body it stays with the moving body
 * (exactly Box2D's anchor, so a sliding circle feels no lever arm), between equal bodies
 * it is halfway. Anchors do not turn with the bodies: a spinning circle's anchor must
 * stay at its bottom. */
KG_FN void kg_current_anchors(const kg_contact_constraint* c, const kg_constraint_point* cp, const kg_body_motion* a,
                              const kg_body_motion* b, kg_vec2* ra, kg_vec2* rb)
{
    kg_vec2 gap = kg_sub(b->dp, a->dp); /* how far b's anchor point moved from a's */
    *ra = kg_mul_add(cp->anchor_a, c->share_b, gap);
    *rb = kg_mul_sub(cp->anchor_b, 1.0f - c->share_b, gap);
}

KG_FN float kg_normal_velocity_at(const kg_contact_constraint* c, const kg_body_motion* a, const kg_body_motion* b,
                                  kg_vec2 ra, kg_vec2 rb)
{
    kg_vec2 dv = kg_sub(kg_point_velocity(b->v, b->w, rb), kg_point_velocity(a->v, a->w, ra));
    return kg_dot(dv, c->normal);
}

KG_FN float kg_normal_mass_at(const kg_contact_constraint* c, kg_vec2 ra, kg_vec2 rb)
{
    float rna = kg_cross(ra, c->normal), rnb = kg_cross(rb, c->normal);
    float k = c->inv_mass_a + c->inv_mass_b + c->inv_i_a * rna * rna + c->inv_i_b * rnb * rnb;
    return k > 0.0f ? 1.0f / k : 0.0f;
}

/* Applies last step's impulses at the start of a sub-step. */
KG_FN void kg_contact_warm_start(const kg_contact_constraint* c, kg_body_motion* a, kg_body_motion* b)
{
    kg_vec2 n = c->normal, t = kg_right_perp(c->normal);
    for (int j = 0; j < c->point_count; ++j) {
        const kg_constraint_point* cp = &c->points[j];
        kg_vec2 ra, rb;
        kg_current_anchors(c, cp, a, b, &ra, &rb);
        kg_vec2 p = kg_add(kg_scale(cp->normal_impulse, n), kg_scale(cp->tangent_impulse, t));
        kg_apply_impulse_pair(c, a, b, ra, rb, p);
    }
}

/* Separation of point j now, from how far the bodies moved since the manifold. */
KG_FN float kg_current_separation(const kg_contact_constraint* c, int j, const kg_body_motion* a,
                                  const kg_body_motion* b)
{
    const kg_constraint_point* cp = &c->points[j];
    kg_vec2 d = kg_add(kg_sub(b->dp, a->dp), kg_sub(kg_rotate(b->dq, cp->anchor_b), kg_rotate(a->dq, cp->anchor_a)));
    return kg_dot(d, c->normal) + cp->base_separation;
}

/* The velocity target of a point: a speculative gap may close within the sub-step;
 * a penetration is pushed out softly (use_bias) at a bounded speed. */
typedef struct kg_point_bias {
    float bias;
    float mass_scale;
    float impulse_scale;
} kg_point_bias;

KG_FN kg_point_bias kg_point_bias_of(const kg_contact_constraint* c, float s, kg_solver_params prm, int use_bias)
{
    kg_point_bias pb;
    pb.bias = 0.0f;
    pb.mass_scale = 1.0f;
    pb.impulse_scale = 0.0f;
    if (s > 0.0f) {
        pb.bias = s * prm.inv_h;
    } else if (use_bias) {
        pb.bias = kg_maxf(c->softness.bias_rate * s, -prm.max_push_out_speed);
        pb.mass_scale = c->softness.mass_scale;
        pb.impulse_scale = c->softness.impulse_scale;
    }
    return pb;
}

/* vn is the normal velocity the impulse answers. The first push of the step records it
 * as the approach speed for restitution: sampled at the start of the step it would miss
 * the speed gained (up to g dt) before the bodies actually met. */
KG_FN void kg_apply_normal_impulse(kg_contact_constraint* c, int j, kg_body_motion* a, kg_body_motion* b, kg_vec2 ra,
                                   kg_vec2 rb, float impulse, float vn)
{
    kg_constraint_point* cp = &c->points[j];
    if (cp->max_normal_impulse == 0.0f && impulse > 0.0f) {
        cp->relative_velocity = vn;
    }
    cp->normal_impulse += impulse;
    cp->max_normal_impulse = kg_maxf(cp->max_normal_impulse, impulse);
    kg_apply_impulse_pair(c, a, b, ra, rb, kg_scale(impulse, c->normal));
}

/* Above this condition number the two rows are nearly redundant and the 2x2 solve is
 * unreliable (Box2D v2's limit). */
#define KG_MAX_BLOCK_CONDITION 1000.0f

/* The 2x2 effective mass of a two-point contact's normal rows; 0 when the rows are too
 * nearly redundant to invert reliably. */
typedef struct kg_block_mass {
    float k11, k12, k22, det;
} kg_block_mass;

KG_FN int kg_make_block_mass(const kg_contact_constraint* c, const kg_vec2* ra, const kg_vec2* rb, kg_block_mass* k)
{
    kg_vec2 n = c->normal;
    float ra0 = kg_cross(ra[0], n), rb0 = kg_cross(rb[0], n);
    float ra1 = kg_cross(ra[1], n), rb1 = kg_cross(rb[1], n);
    float m = c->inv_mass_a + c->inv_mass_b;
    k->k11 = m + c->inv_i_a * ra0 * ra0 + c->inv_i_b * rb0 * rb0;
    k->k22 = m + c->inv_i_a * ra1 * ra1 + c->inv_i_b * rb1 * rb1;
    k->k12 = m + c->inv_i_a * ra0 * ra1 + c->inv_i_b * rb0 * rb1;
    k->det = k->k11 * k->k22 - k->k12 * k->k12;
    return k->k11 * k->k11 < KG_MAX_BLOCK_CONDITION * k->det;
}

/* Both points of a two-point manifold at once (the "block solver", Box2D v2): solving
 * them one after the other leaves a small torque each time, which a tall stack
 * amplifies until it topples. Applies the impulses and returns 1 when both points stay
 * pushing in the same regime; returns 0 (nothing applied) to fall back to one at a time. */
KG_FN int kg_contact_solve_block(kg_contact_constraint* c, kg_body_motion* a, kg_body_motion* b, const kg_vec2* ra,
                                 const kg_vec2* rb, kg_solver_params prm, int use_bias)
{
    kg_point_bias p0 = kg_point_bias_of(c, kg_current_separation(c, 0, a, b), prm, use_bias);
    kg_point_bias p1 = kg_point_bias_of(c, kg_current_separation(c, 1, a, b), prm, use_bias);
    if (p0.mass_scale != p1.mass_scale) {
        return 0;
    }
    kg_block_mass k;
    if (!kg_make_block_mass(c, ra, rb, &k)) {
        return 0;
    }
    float vn0 = kg_normal_velocity_at(c, a, b, ra[0], rb[0]), vn1 = kg_normal_velocity_at(c, a, b, ra[1], rb[1]);
    float rhs0 = p0.mass_scale * (vn0 + p0.bias);
    float rhs1 = p1.mass_scale * (vn1 + p1.bias);
    float inv_det = 1.0f / k.det;
    float acc0 = c->points[0].normal_impulse, acc1 = c->points[1].normal_impulse;
    float x0 = -inv_det * (k.k22 * rhs0 - k.k12 * rhs1) - p0.impulse_scale * acc0;
    float x1 = -inv_det * (k.k11 * rhs1 - k.k12 * rhs0) - p1.impulse_scale * acc1;
    if (acc0 + x0 < 0.0f || acc1 + x1 < 0.0f) {
        return 0;
    }
    kg_apply_normal_impulse(c, 0, a, b, ra[0], rb[0], x0, vn0);
    kg_apply_normal_impulse(c, 1, a, b, ra[1], rb[1], x1, vn1);
    return 1;
}

/* One Gauss-Seidel pass over the constraint: normal impulses (soft when use_bias), then
 * friction bounded by the new normal impulses. */
KG_FN void kg_contact_solve(kg_contact_constraint* c, kg_body_motion* a, kg_body_motion* b, kg_solver_params prm,
                            int use_bias)
{
    kg_vec2 ra[2], rb[2];
    for (int j = 0; j < c->point_count; ++j) {
        kg_current_anchors(c, &c->points[j], a, b, &ra[j], &rb[j]);
    }
    if (c->point_count != 2 || !kg_contact_solve_block(c, a, b, ra, rb, prm, use_bias)) {
        for (int j = 0; j < c->point_count; ++j) {
            kg_point_bias pb = kg_point_bias_of(c, kg_current_separation(c, j, a, b), prm, use_bias);
            kg_constraint_point* cp = &c->points[j];
            float vn = kg_normal_velocity_at(c, a, b, ra[j], rb[j]);
            float impulse = -cp->normal_mass * pb.mass_scale * (vn + pb.bias) - pb.impulse_scale * cp->normal_impulse;
            float applied = kg_maxf(cp->normal_impulse + impulse, 0.0f) - cp->normal_impulse;
            kg_apply_normal_impulse(c, j, a, b, ra[j], rb[j], applied, vn);
        }
    }
    kg_vec2 t = kg_right_perp(c->normal);
    for (int j = 0; j < c->point_count; ++j) {
        kg_constraint_point* cp = &c->points[j];
        kg_vec2 dv = kg_sub(kg_point_velocity(b->v, b->w, rb[j]), kg_point_velocity(a->v, a->w, ra[j]));
        float vt = kg_dot(dv, t);
        float impulse = -cp->tangent_mass * vt;
        float max_friction = c->friction * cp->normal_impulse;
        float accumulated = kg_clampf(cp->tangent_impulse + impulse, -max_friction, max_friction);
        impulse = accumulated - cp->tangent_impulse;
        cp->tangent_impulse = accumulated;
        kg_apply_impulse_pair(c, a, b, ra[j], rb[j], kg_scale(impulse, t));
    }
}

KG_FN int kg_bounces(const kg_constraint_point* cp, kg_solver_params prm)
{
    return cp->relative_velocity < -prm.restitution_threshold && cp->max_normal_impulse > 0.0f;
}

/* Both points of a bouncing two-point contact at once, so two equal boxes meeting face
 * to face exchange their velocities instead of starting to spin. Returns 0 (nothing
 * applied) when the block solution would pull. */
KG_FN int kg_restitution_block(kg_contact_constraint* c, kg_body_motion* a, kg_body_motion* b, const kg_vec2* ra,
                               const kg_vec2* rb)
{
    kg_block_mass k;
    if (!kg_make_block_mass(c, ra, rb, &k)) {
        return 0;
    }
    float rhs0 = kg_normal_velocity_at(c, a, b, ra[0], rb[0]) + c->restitution * c->points[0].relative_velocity;
    float rhs1 = kg_normal_velocity_at(c, a, b, ra[1], rb[1]) + c->restitution * c->points[1].relative_velocity;
    float x0 = -(k.k22 * rhs0 - k.k12 * rhs1) / k.det;
    float x1 = -(k.k11 * rhs1 - k.k12 * rhs0) / k.det;
    if (c->points[0].normal_impulse + x0 < 0.0f || c->points[1].normal_impulse + x1 < 0.0f) {
        return 0;
    }
    float x[2] = {x0, x1};
    for (int j = 0; j < 2; ++j) {
        c->points[j].normal_impulse += x[j];
        kg_apply_impulse_pair(c, a, b, ra[j], rb[j], kg_scale(x[j], c->normal));
    }
    return 1;
}

/* The restitution pass: where a point was approaching faster than the threshold and
 * did push, the rebound speed becomes restitution times the approach speed. */
KG_FN void kg_contact_restitution(kg_contact_constraint* c, kg_body_motion* a, kg_body_motion* b,
                                  kg_solver_params prm)
{
    if (c->restitution == 0.0f) {
        return;
    }
    kg_vec2 ra[2], rb[2];
    for (int j = 0; j < c->point_count; ++j) {
        kg_current_anchors(c, &c->points[j], a, b, &ra[j], &rb[j]);
    }
    int both = c->point_count == 2 && kg_bounces(&c->points[0], prm) && kg_bounces(&c->points[1], prm);
    if (both && kg_restitution_block(c, a, b, ra, rb)) {
        return;
    }
    for (int j = 0; j < c->point_count; ++j) {
        kg_constraint_point* cp = &c->points[j];
        if (!kg_bounces(cp, prm)) {
            continue;
        }
        float vn = kg_normal_velocity_at(c, a, b, ra[j], rb[j]);
        float impulse = -kg_normal_mass_at(c, ra[j], rb[j]) * (vn + c->restitution * cp->relative_velocity);
        float accumulated = kg_maxf(cp->normal_impulse + impulse, 0.0f);
        impulse = accumulated - cp->normal_impulse;
        cp->normal_impulse = accumulated;
        kg_apply_impulse_pair(c, a, b, ra[j], rb[j], kg_scale(impulse, c->normal));
    }
}

#endif
