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
#include "solve/integrate.h"

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

/* The solver's passes over the constraints, in the order of a sub-step (restitution once
 * a step). */
typedef enum kg_constraint_pass {
    KG_PASS_WARM_START,
    KG_PASS_SOLVE,
    KG_PASS_RELAX,
    KG_PASS_RESTITUTION
} kg_constraint_pass;

/* The passes over one constraint, and a body's sub-step (body_row.h, which contact_row.h
 * includes), a float a lane (the CPU's SIMD widths are instantiated in
 * solve/contact_wide*.c). */
#define KG_W 1
#define kg_lane float
#define kg_lmask int
#define kg_lindex kg_u32
#define kg_lint kg_i32
#define KG_SEL(mask, a, b) ((mask) ? (a) : (b))
#define KG_LZERO 0.0f
#include "solve/lane_compare.h"
#include "solve/contact_row.h"
#undef kg_lane
#undef kg_lmask
#undef kg_lindex
#undef kg_lint
#undef KG_SEL
#undef KG_LZERO
#undef KG_W

KG_STATIC_ASSERT(sizeof(kg_constraint_point) == 40, constraint_point_size);
KG_STATIC_ASSERT(sizeof(kg_contact_constraint) == 168, contact_constraint_size);

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

/* The parts of a contact's constraint that prepare does not compute: its bodies, its
 * index, point count and material, and the inverse masses of the bodies that take
 * impulses (zero for the others). */
typedef struct kg_row_head {
    kg_u32 a, b, contact;
    kg_i32 point_count;
    float friction, restitution;
    float inv_mass_a, inv_i_a, inv_mass_b, inv_i_b;
} kg_row_head;

KG_STATIC_ASSERT(sizeof(kg_row_head) == 40, row_head_size);

KG_FN void kg_row_head_of(kg_row_head* h, const kg_contact* ct, kg_u32 index, float inv_mass_a, float inv_i_a,
                          float inv_mass_b, float inv_i_b)
{
    h->a = ct->a;
    h->b = ct->b;
    h->contact = index;
    h->point_count = ct->manifold.point_count;
    h->friction = ct->friction;
    h->restitution = ct->restitution;
    h->inv_mass_a = inv_mass_a;
    h->inv_i_a = inv_i_a;
    h->inv_mass_b = inv_mass_b;
    h->inv_i_b = inv_i_b;
}

/* The head into a constraint of width 1 (a kernel's). */
KG_FN void kg_constraint_head(kg_contact_constraint* c, const kg_row_head* h)
{
    c->a = h->a;
    c->b = h->b;
    c->contact = h->contact;
    c->point_count = h->point_count;
    c->friction = h->friction;
    c->restitution = h->restitution;
    c->inv_mass_a = h->inv_mass_a;
    c->inv_i_a = h->inv_i_a;
    c->inv_mass_b = h->inv_mass_b;
    c->inv_i_b = h->inv_i_b;
}

/* What prepare reads of a contact's manifold (a point it does not have reads zeros) and
 * of its bodies: a's origin (the manifold's anchors are relative to it), the centres of mass
 * and velocities. */
KG_FN void kg_prepare_input_of(kg_prepare_input* in, const kg_manifold* m, kg_vec2 origin_a, kg_vec2 center_a,
                               kg_vec2 center_b, kg_vec2 va, float wa, kg_vec2 vb, float wb)
{
    for (int j = 0; j < 2; ++j) {
        const kg_manifold_point* mp = &m->points[j];
        if (j < m->point_count) {
            in->anchor_a[j] = mp->anchor_a;
            in->separation[j] = mp->separation;
            in->normal_impulse[j] = mp->normal_impulse;
            in->tangent_impulse[j] = mp->tangent_impulse;
            in->has_point[j] = 1.0f;
        } else {
            in->anchor_a[j] = kg_v2(0.0f, 0.0f);
            in->separation[j] = in->normal_impulse[j] = in->tangent_impulse[j] = in->has_point[j] = 0.0f;
        }
    }
    in->normal = m->normal;
    in->origin_a = origin_a;
    in->center_a = center_a;
    in->center_b = center_b;
    in->va = va;
    in->wa = wa;
    in->vb = vb;
    in->wb = wb;
}

/* What the solve leaves in a contact's point: its impulses, for warm starting the next
 * step and for the API, and the approach speed it measured. */
KG_FN void kg_store_point(KG_GLOBAL kg_manifold_point* mp, float normal_impulse, float tangent_impulse,
                          float relative_velocity, float total_normal_impulse)
{
    mp->normal_impulse = normal_impulse;
    mp->tangent_impulse = tangent_impulse;
    mp->normal_velocity = relative_velocity;
    mp->total_normal_impulse = total_normal_impulse;
}

/* The motion of a body slot as the solver sees it: still for KG_NULL_INDEX (the static
 * world). */
KG_FN kg_body_motion kg_motion_of(KG_GLOBAL const kg_solver_body* bodies, kg_u32 slot)
{
    kg_body_motion still;
    still.v = kg_v2(0.0f, 0.0f);
    still.w = 0.0f;
    still.dp = kg_v2(0.0f, 0.0f);
    still.dq = kg_rot_identity();
    return slot == KG_NULL_INDEX ? still : bodies[slot].motion;
}

KG_FN int kg_slot_moves(KG_GLOBAL const kg_solver_body* bodies, kg_u32 slot)
{
    return slot != KG_NULL_INDEX && bodies[slot].moves;
}

/* What prepare reads of one body of a contact: its origin, centre of mass and velocity;
 * the static world (KG_NULL_INDEX) is still, at the origin. */
typedef struct kg_side_state {
    kg_vec2 origin, center, v;
    float w;
} kg_side_state;

KG_FN kg_side_state kg_side_state_of(kg_u32 slot, KG_GLOBAL const kg_solver_body* bodies, KG_GLOBAL const kg_xf* xf,
                                     KG_GLOBAL const kg_vec2* center)
{
    kg_side_state s;
    s.origin = s.center = s.v = kg_v2(0.0f, 0.0f);
    s.w = 0.0f;
    if (slot != KG_NULL_INDEX) {
        s.origin = xf[slot].p;
        s.center = center[slot];
        s.v = bodies[slot].motion.v;
        s.w = bodies[slot].motion.w;
    }
    return s;
}

/* The head and prepare input of the constraint of contact ct (the index-th): the
 * masses of the bodies that take impulses, anchors from the body origins, velocities
 * from the solver bodies. Returns 0, with an empty head (no bodies, no points) and zero
 * inputs, when neither body takes impulses (both asleep or frozen): nothing to solve,
 * the contact's impulses kept as they are. */
KG_FN_INLINE int kg_prepare_source(const kg_contact* ct, kg_u32 index, KG_GLOBAL const kg_solver_body* bodies,
                                   KG_GLOBAL const float* inv_mass, KG_GLOBAL const float* inv_inertia,
                                   KG_GLOBAL const kg_xf* xf, KG_GLOBAL const kg_vec2* center, kg_row_head* head,
                                   kg_prepare_input* in)
{
    int a_moves = kg_slot_moves(bodies, ct->a), b_moves = kg_slot_moves(bodies, ct->b);
    if (!a_moves && !b_moves) {
        kg_contact empty = *ct;
        empty.a = KG_NULL_INDEX;
        empty.b = KG_NULL_INDEX;
        empty.manifold.point_count = 0;
        empty.manifold.normal = kg_v2(0.0f, 0.0f);
        empty.friction = empty.restitution = 0.0f;
        kg_vec2 zero = kg_v2(0.0f, 0.0f);
        kg_row_head_of(head, &empty, 0u, 0.0f, 0.0f, 0.0f, 0.0f);
        kg_prepare_input_of(in, &empty.manifold, zero, zero, zero, zero, 0.0f, zero, 0.0f);
        return 0;
    }
    kg_row_head_of(head, ct, index, a_moves ? inv_mass[ct->a] : 0.0f, a_moves ? inv_inertia[ct->a] : 0.0f,
                   b_moves ? inv_mass[ct->b] : 0.0f, b_moves ? inv_inertia[ct->b] : 0.0f);
    kg_side_state sa = kg_side_state_of(ct->a, bodies, xf, center), sb = kg_side_state_of(ct->b, bodies, xf, center);
    kg_prepare_input_of(in, &ct->manifold, sa.origin, sa.center, sb.center, sa.v, sa.w, sb.v, sb.w);
    return 1;
}

/* ---- constraints of width 1, one per work-item (the CPU runs rows of SIMD lanes) ---- */

/* Constraint k prepared from contact k (kg_prepare_source's, its bodies as the contact
 * names them). */
KG_FN void kg_prepare_contact(kg_u32 k, kg_solver_params prm, KG_GLOBAL const kg_contact* contacts,
                              KG_GLOBAL kg_contact_constraint* constraints, KG_GLOBAL const kg_solver_body* bodies,
                              KG_GLOBAL const float* inv_mass, KG_GLOBAL const float* inv_inertia,
                              KG_GLOBAL const kg_xf* xf, KG_GLOBAL const kg_vec2* center)
{
    KG_PRIVATE_VIEW(kg_contact, ct, contacts[k]);
    kg_row_head head;
    kg_prepare_input in;
    kg_prepare_source(ct, k, bodies, inv_mass, inv_inertia, xf, center, &head, &in);
    kg_contact_constraint c;
    kg_constraint_head(&c, &head);
    kg_contact_prepare_lanes(&c, &in, prm);
    constraints[k] = c;
}

/* A pass's velocities back to a body slot, if it takes impulses. */
KG_FN void kg_store_motion(KG_GLOBAL kg_solver_body* bodies, kg_u32 slot, kg_body_motion m)
{
    if (kg_slot_moves(bodies, slot)) {
        bodies[slot].motion.v = m.v;
        bodies[slot].motion.w = m.w;
    }
}

/* One pass over constraints[index] and its bodies. */
KG_FN void kg_solve_constraint(KG_GLOBAL kg_contact_constraint* constraints, int index,
                               KG_GLOBAL kg_solver_body* bodies, kg_solver_params prm, int pass)
{
    kg_contact_constraint c = constraints[index];
    if (c.point_count == 0) {
        return; /* between sleeping or frozen bodies: nothing moves */
    }
    kg_body_motion a = kg_motion_of(bodies, c.a), b = kg_motion_of(bodies, c.b);
    kg_contact_pass(&c, &a, &b, prm, pass);
    kg_store_motion(bodies, c.a, a);
    kg_store_motion(bodies, c.b, b);
    constraints[index] = c;
}

/* Work-item `item` of `items` in a pass over the constraints [begin, end) of a colour:
 * every items-th from begin + item (they share no moving body); or, serial (the
 * overflow, whose constraints may), all of them in order by work-item 0. */
KG_FN void kg_solve_share(int item, int items, int begin, int end, int serial,
                          KG_GLOBAL kg_contact_constraint* constraints, KG_GLOBAL kg_solver_body* bodies,
                          kg_solver_params prm, int pass)
{
    int step = serial ? 1 : items;
    for (int j = begin + item; (!serial || item == 0) && j < end; j += step) {
        kg_solve_constraint(constraints, j, bodies, prm, pass);
    }
}

/* Constraint c's impulses back into its contact. */
KG_FN void kg_store_impulses_of(KG_GLOBAL const kg_contact_constraint* c, KG_GLOBAL kg_contact* contacts)
{
    for (int j = 0; j < c->point_count; ++j) {
        KG_GLOBAL const kg_constraint_point* p = &c->points[j];
        kg_store_point(&contacts[c->contact].manifold.points[j], p->normal_impulse, p->tangent_impulse,
                       p->relative_velocity, p->total_normal_impulse);
    }
}

#endif
