/* The joint constraints: one row per joint, prepared once a step and then warm started,
 * solved (with the soft bias) and relaxed (without) in every sub-step, as the contacts
 * are (contact_row.h, docs/joints.md). Written once as KG_FN functions over one lane (a
 * float): the CPU calls them joint by joint (core/joint.c), the kernels of
 * kernels/kg_joint.cl for their work-item, to the same bits.
 * Box2D v3's joint solvers are the reference design (soft constraints, sub-stepped,
 * anchors and separations from the bodies' motion within the step, dp and dq).
 *
 * A row reads and writes the solver bodies (kg_solver_body) of its two slots; the world
 * is KG_NULL_INDEX (still, at the origin). Only a body that takes impulses is written. */
#ifndef KG_JOINT_ROW_H
#define KG_JOINT_ROW_H

#include "solve/contact_solver.h"

/* kg_joint_row.type: the public kg_joint_type's values. */
#define KG_JOINT_ROW_REVOLUTE 0
#define KG_JOINT_ROW_DISTANCE 1
#define KG_JOINT_ROW_WELD 2
#define KG_JOINT_ROW_MOUSE 3
#define KG_JOINT_ROW_PRISMATIC 4
#define KG_JOINT_ROW_WHEEL 5
#define KG_JOINT_ROW_MOTOR 6

/* Joints take up to this many colours (no two joints of one share a body, static bodies
 * included), each solved in parallel; the rest are the overflow, solved serially after. */
#define KG_JOINT_COLORS 12

/* kg_joint_row.options */
#define KG_JOINT_OPT_LIMIT 1u
#define KG_JOINT_OPT_MOTOR 2u
#define KG_JOINT_OPT_SPRING 4u

typedef struct kg_joint_row {
    /* the joint's definition, set by the API */
    kg_u32 a, b;        /* body slots; KG_NULL_INDEX: the world */
    kg_i32 type;        /* KG_JOINT_ROW_* */
    kg_u32 options;     /* KG_JOINT_OPT_LIMIT | KG_JOINT_OPT_MOTOR | KG_JOINT_OPT_SPRING */
    kg_vec2 local_a;    /* anchor in a's origin frame (the world: a world point; mouse: the target) */
    kg_vec2 local_b;    /* anchor in b's origin frame */
    kg_vec2 local_axis; /* prismatic, wheel: the axis in a's frame (unit) */
    float reference_angle; /* motor joint: the angular offset */
    float lower, upper; /* revolute: angles (rad); distance: min and max length; prismatic, wheel: translations */
    float length;       /* distance: rest length; motor joint: the correction factor */
    float motor_speed, max_motor_torque; /* prismatic: max_motor_torque is the motor's largest force;
                                          * motor joint: the largest torque */
    float hertz, damping_ratio;   /* revolute and distance spring; weld linear; mouse */
    float hertz2, damping_ratio2; /* weld angular */
    float max_force;              /* mouse */
    float constraint_hertz, constraint_damping_ratio;
    /* made by prepare, once a step */
    float inv_mass_a, inv_i_a, inv_mass_b, inv_i_b; /* zero for a body that takes no impulse */
    kg_vec2 anchor_a, anchor_b; /* from the centres of mass, world axes, at the step's start */
    kg_vec2 delta_center;       /* centre b - centre a at the step's start (mouse: centre b - target) */
    kg_vec2 axis;               /* distance: the direction a to b of the last pass; prismatic,
                                 * wheel: the axis in world axes at the step's start */
    float delta_angle;          /* angle b - angle a - reference at the step's start, in [-pi, pi] */
    float axial_mass;           /* revolute, weld, mouse, motor: of the relative rotation; distance,
                                 * prismatic, wheel: along the axis */
    float angular_mass;         /* wheel: of the relative rotation (its motor) */
    kg_softness soft;           /* the rigid parts' position correction (solve pass only) */
    kg_softness spring;         /* the joint's own spring (every pass) */
    kg_softness spring2;        /* weld angular */
    kg_i32 active;              /* 0: neither body takes impulses (asleep, static): not solved */
    /* accumulated over a sub-step, carried to the next step (warm starting); prismatic:
     * linear_impulse.x across the axis, angular_impulse the rotation's; wheel:
     * linear_impulse.x across the axis */
    kg_vec2 linear_impulse;
    float angular_impulse, spring_impulse, motor_impulse, lower_impulse, upper_impulse;
} kg_joint_row;

KG_STATIC_ASSERT(sizeof(kg_joint_row) == 220, joint_row_size);

#define KG_JOINT_PI 3.14159265359f

/* A joint's springs, its rigid parts' position correction included, are capped at this
 * fraction of the sub-step rate. Contacts stop at a quarter (stacks explode at half,
 * docs/design.md); a joint's rows, solved KG_JOINT_ITERATIONS times a pass, hold at three
 * quarters, and a soft constraint under a load F settles F / (m (2 pi hertz)^2) away from
 * its target, so the higher cap is what lets a 40-link chain carry 100 times a link's mass
 * within 1% (a quarter: 3.3%) and a 10-plank cantilever droop 5% of its length instead of
 * 42% (docs/joints.md has the measurements; a full sub-step rate made the chain
 * oscillate). */
#define KG_JOINT_HERTZ_CAP 0.75f

/* Each solve and relax pass runs over the joints this many times by default (warm
 * starting once): Gauss-Seidel over a chain of very unequal masses converges slowly, and
 * the soft constraint's equilibrium is the same fixed point however many times it is
 * iterated. 6 with the over-relaxed relax (below) holds the chain and the cantilever
 * better than 8 without it did (docs/joints.md). kg_world_set_joint_iterations changes
 * it. */
#define KG_JOINT_ITERATIONS 6

/* The relax pass over-relaxes the rigid rows by this factor in every iteration but its
 * last (successive over-relaxation). A chain's soft joints make it a spring on which a
 * heavy load rings slowly (40 links under 1,000 times a link's mass: 1.25 Hz, with a
 * damping ratio under 2%, the joints' damping being relative to a light link's mass); the
 * relax pass, a rigid projection, is what stills it, but plain Gauss-Seidel takes such a
 * long, smooth motion out at a rate of some link's mass over the load's a sweep: at 8
 * relax iterations that chain still rang after 10 s, at 32 it fell asleep at 3.9 s.
 * Over-relaxed sweeps carry it along the chain faster: at 6 iterations that chain falls
 * asleep at 3.5 s, and at 100 times a link's mass at 1.1 s instead of 4.1 s
 * (docs/joints.md). Gauss-Seidel over-relaxed converges for any factor in (0, 2); 1.5
 * stilled the chain at 5.9 s, and nearer 2 the sweeps' own overshoot dies out more
 * slowly (by at least the factor less 1 a sweep). */
#define KG_JOINT_OVERRELAX 1.8f

/* The revolute joint's passes and the angles (kg_atan2, kg_relative_angle,
 * kg_unwind_angle), one lane a float (joint_revolute_row.h; the CPU's SIMD widths are
 * instantiated in solve/contact_wide*.c). */
#define KG_W 1
#define kg_lane float
#define kg_lmask int
#define kg_lindex kg_u32
#define kg_lint kg_i32
#define KG_SEL(mask, a, b) ((mask) ? (a) : (b))
#define KG_LZERO 0.0f
#include "solve/lane_compare.h"
#include "solve/joint_revolute_row.h"
#undef kg_lane
#undef kg_lmask
#undef kg_lindex
#undef kg_lint
#undef KG_SEL
#undef KG_LZERO
#undef KG_W

KG_STATIC_ASSERT(sizeof(kg_revolute_lanes) == 33 * 4, revolute_lanes_size);

/* The softness of a hertz capped at KG_JOINT_HERTZ_CAP of the sub-step rate. */
KG_FN kg_softness kg_joint_softness(float hertz, float damping_ratio, kg_solver_params prm)
{
    return kg_make_softness(kg_minf(hertz, KG_JOINT_HERTZ_CAP * prm.inv_h), damping_ratio, prm.h);
}

/* What prepare reads of one side: the centre of mass and rotation at the step's start,
 * the local centre; the world: at the origin, unturned. */
KG_FN void kg_joint_side(kg_u32 slot, KG_GLOBAL const kg_vec2* center, KG_GLOBAL const kg_rot* rot,
                         KG_GLOBAL const kg_vec2* local_center, kg_vec2* c, kg_rot* q, kg_vec2* lc)
{
    *c = kg_v2(0.0f, 0.0f);
    *q = kg_rot_identity();
    *lc = kg_v2(0.0f, 0.0f);
    if (slot != KG_NULL_INDEX) {
        *c = center[slot];
        *q = rot[slot];
        *lc = local_center[slot];
    }
}

/* Joint j's row prepared for the step: masses of the bodies that take impulses, anchors
 * and offsets at the step's start, softness for the sub-step h. Impulses are kept (warm
 * starting). */
KG_FN void kg_joint_prepare(KG_GLOBAL kg_joint_row* rows, int j, KG_GLOBAL const kg_solver_body* bodies,
                            KG_GLOBAL const float* inv_mass, KG_GLOBAL const float* inv_inertia,
                            KG_GLOBAL const kg_vec2* center, KG_GLOBAL const kg_rot* rot,
                            KG_GLOBAL const kg_vec2* local_center, kg_solver_params prm)
{
    kg_joint_row r = rows[j];
    int a_moves = kg_slot_moves(bodies, r.a), b_moves = kg_slot_moves(bodies, r.b);
    r.active = a_moves || b_moves;
    r.inv_mass_a = a_moves ? inv_mass[r.a] : 0.0f;
    r.inv_i_a = a_moves ? inv_inertia[r.a] : 0.0f;
    r.inv_mass_b = b_moves ? inv_mass[r.b] : 0.0f;
    r.inv_i_b = b_moves ? inv_inertia[r.b] : 0.0f;
    kg_vec2 ca, cb, lca, lcb;
    kg_rot qa, qb;
    kg_joint_side(r.a, center, rot, local_center, &ca, &qa, &lca);
    kg_joint_side(r.b, center, rot, local_center, &cb, &qb, &lcb);
    r.anchor_b = kg_rotate(qb, kg_sub(r.local_b, lcb));
    if (r.type == KG_JOINT_ROW_MOUSE) {
        r.anchor_a = kg_v2(0.0f, 0.0f);
        r.delta_center = kg_sub(cb, r.local_a);
    } else {
        r.anchor_a = kg_rotate(qa, kg_sub(r.local_a, lca));
        r.delta_center = kg_sub(cb, ca);
    }
    r.delta_angle = kg_unwind_angle(kg_relative_angle(qb, qa) - r.reference_angle);
    float k = r.inv_i_a + r.inv_i_b;
    r.axial_mass = k > 0.0f ? 1.0f / k : 0.0f;
    /* 0: as stiff as the sub-step allows (the cap) */
    float hertz = r.constraint_hertz > 0.0f ? r.constraint_hertz : KG_JOINT_HERTZ_CAP * prm.inv_h;
    r.soft = kg_joint_softness(hertz, r.constraint_damping_ratio, prm);
    r.spring = kg_joint_softness(r.hertz, r.damping_ratio, prm);
    r.spring2 = kg_joint_softness(r.hertz2, r.damping_ratio2, prm);
    if (r.type == KG_JOINT_ROW_DISTANCE) {
        kg_vec2 d = kg_add(kg_sub(r.anchor_b, r.anchor_a), r.delta_center);
        r.axis = kg_normalize(d);
        float cra = kg_cross(r.anchor_a, r.axis), crb = kg_cross(r.anchor_b, r.axis);
        float ka = r.inv_mass_a + r.inv_mass_b + r.inv_i_a * cra * cra + r.inv_i_b * crb * crb;
        r.axial_mass = ka > 0.0f ? 1.0f / ka : 0.0f;
    }
    r.angular_mass = r.axial_mass;
    if (r.type == KG_JOINT_ROW_PRISMATIC || r.type == KG_JOINT_ROW_WHEEL) {
        r.axis = kg_rotate(qa, r.local_axis);
        kg_vec2 d = kg_add(kg_sub(r.anchor_b, r.anchor_a), r.delta_center);
        float a1 = kg_cross(kg_add(d, r.anchor_a), r.axis), a2 = kg_cross(r.anchor_b, r.axis);
        float ka = r.inv_mass_a + r.inv_mass_b + r.inv_i_a * a1 * a1 + r.inv_i_b * a2 * a2;
        r.axial_mass = ka > 0.0f ? 1.0f / ka : 0.0f;
    }
    if (r.type == KG_JOINT_ROW_MOUSE) {
        /* Box2D's: the dragged body's spin is damped a little, with no target */
        r.spring2 = kg_joint_softness(0.5f, 0.1f, prm);
        r.axial_mass = r.inv_i_b > 0.0f ? 1.0f / r.inv_i_b : 0.0f;
    }
    rows[j] = r;
}

/* The passes' shared parts (joint_revolute_row.h, width 1) over a row. */
KG_FN void kg_joint_apply(const kg_joint_row* r, kg_joint_pair* s, kg_vec2 p, float angular)
{
    kg_joint_push(r->inv_mass_a, r->inv_i_a, r->inv_mass_b, r->inv_i_b, s, p, angular);
}

KG_FN kg_vec2 kg_joint_separation(const kg_joint_row* r, const kg_joint_pair* s)
{
    return kg_joint_offset(r->delta_center, s);
}

KG_FN float kg_joint_angle_now(const kg_joint_row* r, const kg_joint_pair* s)
{
    return kg_joint_angle(r->delta_angle, s);
}

KG_FN kg_vec2 kg_solve_point_mass(const kg_joint_row* r, const kg_joint_pair* s, kg_vec2 rhs)
{
    return kg_point_mass_solve(r->inv_mass_a, r->inv_i_a, r->inv_mass_b, r->inv_i_b, s, rhs);
}

KG_FN void kg_joint_solve_point(kg_joint_row* r, kg_joint_pair* s, kg_softness soft)
{
    kg_joint_point(r->inv_mass_a, r->inv_i_a, r->inv_mass_b, r->inv_i_b, r->delta_center, &r->linear_impulse, s, soft);
}

KG_FN float kg_joint_one_sided(float c, float cdot, float mass, float* acc, kg_softness rigid, kg_solver_params prm)
{
    return kg_one_sided(1, c, cdot, mass, acc, rigid, prm);
}

/* A revolute row as its passes read it (the world: KG_NULL_INDEX, as in the row). */
KG_FN kg_revolute_lanes kg_revolute_lanes_of(const kg_joint_row* r)
{
    kg_revolute_lanes l;
    l.anchor_a = r->anchor_a;
    l.anchor_b = r->anchor_b;
    l.delta_center = r->delta_center;
    l.delta_angle = r->delta_angle;
    l.inv_mass_a = r->inv_mass_a;
    l.inv_i_a = r->inv_i_a;
    l.inv_mass_b = r->inv_mass_b;
    l.inv_i_b = r->inv_i_b;
    l.axial_mass = r->axial_mass;
    l.soft = r->soft;
    l.spring = r->spring;
    l.lower = r->lower;
    l.upper = r->upper;
    l.motor_speed = r->motor_speed;
    l.max_motor_torque = r->max_motor_torque;
    l.has_spring = (r->options & KG_JOINT_OPT_SPRING) && r->hertz > 0.0f ? 1.0f : 0.0f;
    l.has_motor = (r->options & KG_JOINT_OPT_MOTOR) ? 1.0f : 0.0f;
    l.has_limit = (r->options & KG_JOINT_OPT_LIMIT) ? 1.0f : 0.0f;
    l.linear_impulse = r->linear_impulse;
    l.spring_impulse = r->spring_impulse;
    l.motor_impulse = r->motor_impulse;
    l.lower_impulse = r->lower_impulse;
    l.upper_impulse = r->upper_impulse;
    l.a = r->a;
    l.b = r->b;
    return l;
}

/* The impulses a revolute row's passes accumulated, back into the row. */
KG_FN void kg_revolute_keep(kg_joint_row* r, const kg_revolute_lanes* l)
{
    r->linear_impulse = l->linear_impulse;
    r->spring_impulse = l->spring_impulse;
    r->motor_impulse = l->motor_impulse;
    r->lower_impulse = l->lower_impulse;
    r->upper_impulse = l->upper_impulse;
}

KG_FN void kg_distance_solve(kg_joint_row* r, kg_joint_pair* s, kg_solver_params prm, kg_softness rigid)
{
    kg_vec2 d = kg_joint_separation(r, s);
    float length = kg_length(d);
    kg_vec2 axis = kg_normalize(d);
    r->axis = axis;
    int limited = (r->options & KG_JOINT_OPT_LIMIT) != 0u;
    int soft = (r->options & KG_JOINT_OPT_SPRING) && (r->lower < r->upper || !limited);
    if (soft) {
        if (r->hertz > 0.0f) {
            float cdot = kg_dot(axis, kg_joint_relative_velocity(s));
            float c = length - r->length;
            float impulse = -r->spring.mass_scale * r->axial_mass * (cdot + r->spring.bias_rate * c) -
                            r->spring.impulse_scale * r->spring_impulse;
            r->spring_impulse += impulse;
            kg_joint_apply(r, s, kg_scale(impulse, axis), 0.0f);
        }
        if (limited) {
            float cdot = kg_dot(axis, kg_joint_relative_velocity(s));
            float lower = kg_joint_one_sided(length - r->lower, cdot, r->axial_mass, &r->lower_impulse, rigid, prm);
            kg_joint_apply(r, s, kg_scale(lower, axis), 0.0f);
            cdot = kg_dot(axis, kg_joint_relative_velocity(s));
            float upper = kg_joint_one_sided(r->upper - length, -cdot, r->axial_mass, &r->upper_impulse, rigid, prm);
            kg_joint_apply(r, s, kg_scale(-upper, axis), 0.0f);
        }
        return;
    }
    /* rigid at its length */
    float cdot = kg_dot(axis, kg_joint_relative_velocity(s));
    float bias = rigid.bias_rate * (length - r->length);
    float impulse = -rigid.mass_scale * r->axial_mass * (cdot + bias) - rigid.impulse_scale * r->spring_impulse;
    r->spring_impulse += impulse;
    kg_joint_apply(r, s, kg_scale(impulse, axis), 0.0f);
}

KG_FN void kg_weld_solve(kg_joint_row* r, kg_joint_pair* s, kg_softness rigid)
{
    /* angular: soft by its own hertz in every pass, else rigid */
    {
        kg_softness soft = r->hertz2 > 0.0f ? r->spring2 : rigid;
        float bias = soft.bias_rate * kg_joint_angle_now(r, s);
        float cdot = s->b.w - s->a.w;
        float impulse = -r->axial_mass * soft.mass_scale * (cdot + bias) - soft.impulse_scale * r->angular_impulse;
        r->angular_impulse += impulse;
        s->a.w -= r->inv_i_a * impulse;
        s->b.w += r->inv_i_b * impulse;
    }
    kg_joint_solve_point(r, s, r->hertz > 0.0f ? r->spring : rigid);
}

KG_FN void kg_mouse_solve(kg_joint_row* r, kg_joint_pair* s, kg_solver_params prm)
{
    {
        float impulse = -r->spring2.mass_scale * r->axial_mass * s->b.w - r->spring2.impulse_scale * r->angular_impulse;
        r->angular_impulse += impulse;
        s->b.w += r->inv_i_b * impulse;
    }
    float most = r->max_force * prm.h;
    kg_vec2 rb = s->rb;
    kg_vec2 cdot = kg_add(s->b.v, kg_cross_sv(s->b.w, rb));
    kg_vec2 separation = kg_add(kg_add(s->b.dp, rb), r->delta_center);
    kg_vec2 bias = kg_scale(r->spring.bias_rate, separation);
    float mb = r->inv_mass_b, ib = r->inv_i_b;
    float k11 = mb + ib * rb.y * rb.y, k12 = -ib * rb.x * rb.y, k22 = mb + ib * rb.x * rb.x;
    kg_vec2 x = kg_solve22(k11, k12, k22, kg_add(cdot, bias));
    kg_vec2 old = r->linear_impulse;
    kg_vec2 acc = kg_v2(old.x - r->spring.mass_scale * x.x - r->spring.impulse_scale * old.x,
                        old.y - r->spring.mass_scale * x.y - r->spring.impulse_scale * old.y);
    float mag = kg_length(acc);
    acc = mag > most ? kg_scale(most, kg_normalize(acc)) : acc;
    r->linear_impulse = acc;
    kg_vec2 impulse = kg_sub(acc, old);
    s->b.v = kg_mul_add(s->b.v, mb, impulse);
    s->b.w = s->b.w + ib * kg_cross(rb, impulse);
}

/* The geometry of a joint along an axis (prismatic, wheel) now: the axis turned with a,
 * the anchors' offset d, the lever arms along the axis (a1, a2) and across it (s1, s2). */
typedef struct kg_axis_frame {
    kg_vec2 axis, perp, d;
    float a1, a2, s1, s2, translation;
} kg_axis_frame;

KG_FN kg_axis_frame kg_axis_frame_of(const kg_joint_row* r, const kg_joint_pair* s)
{
    kg_axis_frame f;
    f.d = kg_joint_separation(r, s);
    f.axis = kg_rotate(s->a.dq, r->axis);
    f.perp = kg_left_perp(f.axis);
    kg_vec2 da = kg_add(f.d, s->ra);
    f.a1 = kg_cross(da, f.axis);
    f.a2 = kg_cross(s->rb, f.axis);
    f.s1 = kg_cross(da, f.perp);
    f.s2 = kg_cross(s->rb, f.perp);
    f.translation = kg_dot(f.axis, f.d);
    return f;
}

/* An impulse along the frame's axis (and one across it, and a pure torque). */
KG_FN void kg_axis_apply(const kg_joint_row* r, kg_joint_pair* s, const kg_axis_frame* f, float axial, float across,
                         float angular)
{
    kg_vec2 p = kg_add(kg_scale(axial, f->axis), kg_scale(across, f->perp));
    float la = axial * f->a1 + across * f->s1 + angular, lb = axial * f->a2 + across * f->s2 + angular;
    s->a.v = kg_mul_sub(s->a.v, r->inv_mass_a, p);
    s->a.w = s->a.w - r->inv_i_a * la;
    s->b.v = kg_mul_add(s->b.v, r->inv_mass_b, p);
    s->b.w = s->b.w + r->inv_i_b * lb;
}

/* The speed b moves along the axis relative to a. */
KG_FN float kg_axis_speed(const kg_joint_pair* s, const kg_axis_frame* f)
{
    return kg_dot(f->axis, kg_sub(s->b.v, s->a.v)) + f->a2 * s->b.w - f->a1 * s->a.w;
}

/* Along the axis (prismatic, wheel): the spring about translation 0, the limits. */
KG_FN void kg_axis_spring_and_limits(kg_joint_row* r, kg_joint_pair* s, const kg_axis_frame* f, kg_solver_params prm,
                                     kg_softness rigid)
{
    if ((r->options & KG_JOINT_OPT_SPRING) && r->hertz > 0.0f) {
        float cdot = kg_axis_speed(s, f);
        float impulse = -r->spring.mass_scale * r->axial_mass * (cdot + r->spring.bias_rate * f->translation) -
                        r->spring.impulse_scale * r->spring_impulse;
        r->spring_impulse += impulse;
        kg_axis_apply(r, s, f, impulse, 0.0f, 0.0f);
    }
    if (r->options & KG_JOINT_OPT_LIMIT) {
        float lower = kg_joint_one_sided(f->translation - r->lower, kg_axis_speed(s, f), r->axial_mass,
                                         &r->lower_impulse, rigid, prm);
        kg_axis_apply(r, s, f, lower, 0.0f, 0.0f);
        float upper = kg_joint_one_sided(r->upper - f->translation, -kg_axis_speed(s, f), r->axial_mass,
                                         &r->upper_impulse, rigid, prm);
        kg_axis_apply(r, s, f, -upper, 0.0f, 0.0f);
    }
}

/* A slider: b moves along a's axis only, without turning relative to a; a motor
 * (max_motor_torque is its largest force), a spring and limits along the axis. */
KG_FN void kg_prismatic_solve(kg_joint_row* r, kg_joint_pair* s, kg_solver_params prm, kg_softness rigid)
{
    kg_axis_frame f = kg_axis_frame_of(r, s);
    if (r->options & KG_JOINT_OPT_MOTOR) {
        float impulse = r->axial_mass * (r->motor_speed - kg_axis_speed(s, &f));
        float old = r->motor_impulse, most = prm.h * r->max_motor_torque;
        r->motor_impulse = kg_clampf(old + impulse, -most, most);
        kg_axis_apply(r, s, &f, r->motor_impulse - old, 0.0f, 0.0f);
    }
    kg_axis_spring_and_limits(r, s, &f, prm, rigid);
    /* across the axis and the rotation, as one 2x2 block */
    float ma = r->inv_mass_a, mb = r->inv_mass_b, ia = r->inv_i_a, ib = r->inv_i_b;
    kg_vec2 cdot = kg_v2(kg_dot(f.perp, kg_sub(s->b.v, s->a.v)) + f.s2 * s->b.w - f.s1 * s->a.w, s->b.w - s->a.w);
    kg_vec2 bias = kg_scale(rigid.bias_rate, kg_v2(kg_dot(f.perp, f.d), kg_joint_angle_now(r, s)));
    float k11 = ma + mb + ia * f.s1 * f.s1 + ib * f.s2 * f.s2, k12 = ia * f.s1 + ib * f.s2, k22 = ia + ib;
    k22 = k22 == 0.0f ? 1.0f : k22; /* neither turns */
    kg_vec2 x = kg_solve22(k11, k12, k22, kg_add(cdot, bias));
    kg_vec2 acc = kg_v2(r->linear_impulse.x, r->angular_impulse);
    kg_vec2 impulse = kg_v2(-rigid.mass_scale * x.x - rigid.impulse_scale * acc.x,
                            -rigid.mass_scale * x.y - rigid.impulse_scale * acc.y);
    r->linear_impulse.x += impulse.x;
    r->angular_impulse += impulse.y;
    kg_axis_apply(r, s, &f, 0.0f, impulse.x, impulse.y);
}

/* A wheel: b's anchor on a's axis (the suspension: a spring and limits along it), b free
 * to turn, driven by a motor on the rotation. */
KG_FN void kg_wheel_solve(kg_joint_row* r, kg_joint_pair* s, kg_solver_params prm, kg_softness rigid)
{
    if (r->options & KG_JOINT_OPT_MOTOR) {
        float impulse = -r->angular_mass * (s->b.w - s->a.w - r->motor_speed);
        float old = r->motor_impulse, most = prm.h * r->max_motor_torque;
        r->motor_impulse = kg_clampf(old + impulse, -most, most);
        impulse = r->motor_impulse - old;
        s->a.w -= r->inv_i_a * impulse;
        s->b.w += r->inv_i_b * impulse;
    }
    kg_axis_frame f = kg_axis_frame_of(r, s);
    kg_axis_spring_and_limits(r, s, &f, prm, rigid);
    /* the point on the line */
    float cdot = kg_dot(f.perp, kg_sub(s->b.v, s->a.v)) + f.s2 * s->b.w - f.s1 * s->a.w;
    float bias = rigid.bias_rate * kg_dot(f.perp, f.d);
    float k = r->inv_mass_a + r->inv_mass_b + r->inv_i_a * f.s1 * f.s1 + r->inv_i_b * f.s2 * f.s2;
    float mass = k > 0.0f ? 1.0f / k : 0.0f;
    float impulse = -rigid.mass_scale * mass * (cdot + bias) - rigid.impulse_scale * r->linear_impulse.x;
    r->linear_impulse.x += impulse;
    kg_axis_apply(r, s, &f, 0.0f, impulse, 0.0f);
}

/* A motor joint: drives b's origin to the point local_a of a's frame and its angle to
 * a's plus reference_angle, with at most max_force and max_motor_torque, correcting a
 * share (length: the correction factor) of the error each sub-step. */
KG_FN void kg_motor_joint_solve(kg_joint_row* r, kg_joint_pair* s, kg_solver_params prm)
{
    {
        float bias = prm.inv_h * r->length * kg_joint_angle_now(r, s);
        float impulse = -r->axial_mass * (s->b.w - s->a.w + bias);
        float old = r->angular_impulse, most = prm.h * r->max_motor_torque;
        r->angular_impulse = kg_clampf(old + impulse, -most, most);
        impulse = r->angular_impulse - old;
        s->a.w -= r->inv_i_a * impulse;
        s->b.w += r->inv_i_b * impulse;
    }
    kg_vec2 cdot = kg_joint_relative_velocity(s);
    kg_vec2 bias = kg_scale(prm.inv_h * r->length, kg_joint_separation(r, s));
    kg_vec2 x = kg_solve_point_mass(r, s, kg_add(cdot, bias));
    kg_vec2 old = r->linear_impulse;
    kg_vec2 acc = kg_sub(old, x);
    float most = prm.h * r->max_force, mag = kg_length(acc);
    acc = mag > most ? kg_scale(most, kg_normalize(acc)) : acc;
    r->linear_impulse = acc;
    kg_joint_apply(r, s, kg_sub(acc, old), 0.0f);
}

/* The impulses of last sub-step applied again at the start of a sub-step. */
KG_FN void kg_joint_warm_start(const kg_joint_row* r, kg_joint_pair* s)
{
    switch (r->type) {
    case KG_JOINT_ROW_DISTANCE: {
        kg_vec2 d = kg_joint_separation(r, s);
        float axial = r->spring_impulse + r->lower_impulse - r->upper_impulse;
        kg_joint_apply(r, s, kg_scale(axial, kg_normalize(d)), 0.0f);
        break;
    }
    case KG_JOINT_ROW_WELD:
    case KG_JOINT_ROW_MOTOR: kg_joint_apply(r, s, r->linear_impulse, r->angular_impulse); break;
    case KG_JOINT_ROW_PRISMATIC: {
        kg_axis_frame f = kg_axis_frame_of(r, s);
        kg_axis_apply(r, s, &f, r->spring_impulse + r->motor_impulse + r->lower_impulse - r->upper_impulse,
                      r->linear_impulse.x, r->angular_impulse);
        break;
    }
    case KG_JOINT_ROW_WHEEL: {
        kg_axis_frame f = kg_axis_frame_of(r, s);
        kg_axis_apply(r, s, &f, r->spring_impulse + r->lower_impulse - r->upper_impulse, r->linear_impulse.x,
                      r->motor_impulse);
        break;
    }
    default: /* mouse: b alone */
        s->b.v = kg_mul_add(s->b.v, r->inv_mass_b, r->linear_impulse);
        s->b.w = s->b.w + r->inv_i_b * (kg_cross(s->rb, r->linear_impulse) + r->angular_impulse);
        break;
    }
}

/* One pass over a joint of a kind other than revolute and its bodies s. */
KG_FN void kg_joint_kind_pass(kg_joint_row* r, kg_joint_pair* s, kg_solver_params prm, int pass, int last_iteration)
{
    s->ra = kg_rotate(s->a.dq, r->anchor_a);
    s->rb = kg_rotate(s->b.dq, r->anchor_b);
    kg_softness rigid = kg_rigid_softness(r->soft, pass, last_iteration);
    if (pass == KG_PASS_WARM_START) {
        kg_joint_warm_start(r, s);
    } else if (r->type == KG_JOINT_ROW_DISTANCE) {
        kg_distance_solve(r, s, prm, rigid);
    } else if (r->type == KG_JOINT_ROW_WELD) {
        kg_weld_solve(r, s, rigid);
    } else if (r->type == KG_JOINT_ROW_PRISMATIC) {
        kg_prismatic_solve(r, s, prm, rigid);
    } else if (r->type == KG_JOINT_ROW_WHEEL) {
        kg_wheel_solve(r, s, prm, rigid);
    } else if (r->type == KG_JOINT_ROW_MOTOR) {
        kg_motor_joint_solve(r, s, prm);
    } else {
        kg_mouse_solve(r, s, prm);
    }
}

/* One pass (KG_PASS_WARM_START, _SOLVE or _RELAX; joints have no restitution) over row
 * j and its bodies, in the pass's last iteration or not (kg_rigid_softness). A revolute
 * joint runs its lane code one lane wide (joint_revolute_row.h), the code the CPU runs
 * W joints at a time. */
KG_FN void kg_joint_pass(KG_GLOBAL kg_joint_row* rows, int j, KG_GLOBAL kg_solver_body* bodies,
                         kg_solver_params prm, int pass, int last_iteration)
{
    kg_joint_row r = rows[j];
    if (!r.active || pass == KG_PASS_RESTITUTION) {
        return;
    }
    kg_joint_pair s;
    s.a = kg_motion_of(bodies, r.a);
    s.b = kg_motion_of(bodies, r.b);
    if (r.type == KG_JOINT_ROW_REVOLUTE) {
        kg_revolute_lanes l = kg_revolute_lanes_of(&r);
        kg_revolute_pass(&l, &s.a, &s.b, prm, pass, last_iteration);
        kg_revolute_keep(&r, &l);
    } else {
        kg_joint_kind_pass(&r, &s, prm, pass, last_iteration);
    }
    kg_store_motion(bodies, r.a, s.a);
    kg_store_motion(bodies, r.b, s.b);
    rows[j] = r;
}

/* Work-item `item` of `items` in a pass over the joints order[begin, end) of a colour:
 * every items-th from begin + item (they share no body); or, serial (the overflow, whose
 * joints may), all of them in order by work-item 0. */
KG_FN void kg_joint_share(int item, int items, KG_GLOBAL const kg_i32* order, int begin, int end, int serial,
                          KG_GLOBAL kg_joint_row* rows, KG_GLOBAL kg_solver_body* bodies, kg_solver_params prm,
                          int pass, int last_iteration)
{
    int step = serial ? 1 : items;
    for (int k = begin + item; (!serial || item == 0) && k < end; k += step) {
        kg_joint_pass(rows, order[k], bodies, prm, pass, last_iteration);
    }
}

/* Whether the pair of body slots (a, b), a < b, is in apart (count pairs of two slots,
 * sorted by (a, b), unique): two bodies joined by a joint that does not
 * collide_connected, whose pair makes no contact. A binary search; the CPU's collide
 * stage and the device's kernel ask it of every pair. */
KG_FN int kg_pair_is_joined(KG_GLOBAL const kg_u32* apart, int count, kg_u32 a, kg_u32 b)
{
    int lo = 0, hi = count;
    while (lo < hi) {
        int mid = (lo + hi) >> 1;
        kg_u32 ma = apart[2 * mid], mb = apart[2 * mid + 1];
        if (ma < a || (ma == a && mb < b)) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    return lo < count && apart[2 * lo] == a && apart[2 * lo + 1] == b;
}

/* What the joint did to body b in the last sub-step (inv_h: one over its length): the
 * force and the torque about b's centre beyond the force's own. */
KG_FN void kg_joint_reaction(const kg_joint_row* r, float inv_h, kg_vec2* force, float* torque)
{
    kg_vec2 p = r->linear_impulse;
    float t = 0.0f;
    switch (r->type) {
    case KG_JOINT_ROW_REVOLUTE: t = r->spring_impulse + r->motor_impulse + r->lower_impulse - r->upper_impulse; break;
    case KG_JOINT_ROW_DISTANCE:
        p = kg_scale(r->spring_impulse + r->lower_impulse - r->upper_impulse, r->axis);
        break;
    case KG_JOINT_ROW_PRISMATIC:
    case KG_JOINT_ROW_WHEEL: {
        /* along the axis and across it, at the step's start axis */
        float axial = r->spring_impulse + r->lower_impulse - r->upper_impulse +
                      (r->type == KG_JOINT_ROW_PRISMATIC ? r->motor_impulse : 0.0f);
        p = kg_add(kg_scale(axial, r->axis), kg_scale(r->linear_impulse.x, kg_left_perp(r->axis)));
        t = r->type == KG_JOINT_ROW_PRISMATIC ? r->angular_impulse : r->motor_impulse;
        break;
    }
    default: t = r->angular_impulse; break;
    }
    *force = kg_scale(inv_h, p);
    *torque = inv_h * t;
}

#endif
