/* The revolute joint's passes (warm start, solve, relax), written once over a lane type
 * and instantiated per width as the contacts' are (contact_row.h; no include guard:
 * included once per width, after contact_row.h for that width).
 *
 *   KG_W 1      a lane is a float: kg_revolute_lanes is one joint. kg_joint_pass runs it
 *               for a revolute joint, so the OpenCL kernels and the CPU's scalar path
 *               (the overflow colour, width 1) are this code.
 *   KG_W 4/8/16 kg_revolute_lanes_wW holds W revolute joints of one colour (no two share
 *               a moving body), each field a vector of their W values; core/joint.c
 *               moves the rows into lanes once a step, and the impulses back after it.
 *
 * Every option (spring, motor, limit) runs in every lane and is kept or dropped by a
 * select of the old value, never by adding a zero impulse (v + 0 would turn -0 into +0):
 * a lane computes the bits the joint computes alone, whatever the width and whatever its
 * neighbours' options. A padding lane names the still body twice and changes nothing.
 *
 * Before including: what contact_row.h needs (KG_W, kg_lane, kg_lmask, kg_lindex,
 * kg_lint, KG_SEL, KG_LZERO), and contact_row.h for the width. */

#if KG_W == 1
#define KG_L(name) name
#define kg_lv2 kg_vec2
#define kg_lq kg_rot
#define KG_LABS(x) fabsf(x)
#else
#define KG_L3(name, w) name##_w##w
#define KG_L2(name, w) KG_L3(name, w)
#define KG_L(name) KG_L2(name, KG_W)
#define kg_lv2 KG_L(kg_lvec2)
#define kg_lq KG_L(kg_lrot)
#define KG_LABS(x) ((kg_lane)((kg_lint)(x) & 0x7fffffff)) /* the sign bit cleared, as fabsf */
#endif
#define kg_lmotion KG_L(kg_body_motion)
#define kg_lsoft KG_L(kg_lsoftness)
#define kg_lrev KG_L(kg_revolute_lanes)

#if KG_W == 1
#undef kg_lsoft
#define kg_lsoft kg_softness
#else
typedef struct KG_L(kg_lsoftness) {
    kg_lane bias_rate, mass_scale, impulse_scale;
} KG_L(kg_lsoftness);
#endif

/* A revolute joint's row as its passes read it: prepare's output, its options as 1 or 0,
 * its impulses. All 4-byte fields (core/joint.c moves them into lanes as such). */
typedef struct KG_L(kg_revolute_lanes) {
    kg_lv2 anchor_a, anchor_b, delta_center;
    kg_lane delta_angle, inv_mass_a, inv_i_a, inv_mass_b, inv_i_b, axial_mass;
    kg_lsoft soft, spring;
    kg_lane lower, upper, motor_speed, max_motor_torque;
    kg_lane has_spring, has_motor, has_limit; /* 1: on (the spring: with a hertz), 0: off */
    kg_lv2 linear_impulse;
    kg_lane spring_impulse, motor_impulse, lower_impulse, upper_impulse;
    kg_lindex a, b; /* body slots (the wide rows: the still body for the world) */
} KG_L(kg_revolute_lanes);

/* atan2(y, x) in [-pi, pi], the engine's own (no libm, the same bits in C and OpenCL C):
 * the octant reduced to [0, 1], then Abramowitz and Stegun 4.4.49 (error under 1e-5
 * rad in float). atan2(0, 0) is 0. */
KG_FN kg_lane KG_L(kg_atan2)(kg_lane y, kg_lane x)
{
    kg_lane zero = KG_LZERO, ax = KG_LABS(x), ay = KG_LABS(y);
    kg_lane mx = KG_L(kg_lmax)(ax, ay), mn = KG_L(kg_lmin)(ax, ay);
    kg_lane t = KG_SEL(KG_LGT(mx, zero), mn / mx, zero);
    kg_lane s = t * t;
    kg_lane p = zero + 0.0028662257f;
    p = p * s - 0.0161657367f;
    p = p * s + 0.0429096138f;
    p = p * s - 0.0752896400f;
    p = p * s + 0.1065626393f;
    p = p * s - 0.1420889944f;
    p = p * s + 0.1999355085f;
    p = p * s - 0.3333314528f;
    kg_lane r = t + t * s * p;
    r = KG_SEL(KG_LGT(ay, ax), 1.57079632679f - r, r);
    r = KG_SEL(KG_LLT(x, zero), KG_JOINT_PI - r, r);
    return KG_SEL(KG_LLT(y, zero), -r, r);
}

/* The angle of b relative to a, in [-pi, pi]. */
KG_FN kg_lane KG_L(kg_relative_angle)(kg_lq b, kg_lq a)
{
    kg_lane s = b.s * a.c - b.c * a.s;
    kg_lane c = b.c * a.c + b.s * a.s;
    return KG_L(kg_atan2)(s, c);
}

KG_FN kg_lane KG_L(kg_unwind_angle)(kg_lane angle)
{
    kg_lane pi = KG_LZERO + KG_JOINT_PI;
    kg_lane wrapped = KG_SEL(KG_LGT(angle, pi), angle - 2.0f * KG_JOINT_PI, angle);
    return KG_SEL(KG_LLT(angle, KG_LZERO - pi), angle + 2.0f * KG_JOINT_PI, wrapped);
}

/* The joint's bodies as the solver sees them now, with the anchors turned by the
 * rotation within the step (at width 1: kg_joint_pair, what every kind's rows use). */
typedef struct KG_L(kg_joint_pair) {
    kg_lmotion a, b;
    kg_lv2 ra, rb;
} KG_L(kg_joint_pair);

#define kg_lpair KG_L(kg_joint_pair)

/* The solution x of K x = b for a symmetric 2x2 K = [k11 k12; k12 k22] (0 when singular). */
KG_FN kg_lv2 KG_L(kg_solve22)(kg_lane k11, kg_lane k12, kg_lane k22, kg_lv2 b)
{
    kg_lane zero = KG_LZERO, det = k11 * k22 - k12 * k12;
    det = KG_SEL(KG_LNE(det, zero), 1.0f / det, zero);
    return KG_L(kg_lmake)(det * (k22 * b.x - k12 * b.y), det * (k11 * b.y - k12 * b.x));
}

/* The linear impulse p at the anchors and the torque `angular`, on a (minus) and b
 * (plus), with the bodies' inverse masses and inertias. */
KG_FN void KG_L(kg_joint_push)(kg_lane ma, kg_lane ia, kg_lane mb, kg_lane ib, kg_lpair* s, kg_lv2 p, kg_lane angular)
{
    s->a.v = KG_L(kg_lmake)(s->a.v.x - ma * p.x, s->a.v.y - ma * p.y);
    s->a.w = s->a.w - ia * (KG_L(kg_lcross)(s->ra, p) + angular);
    s->b.v = KG_L(kg_lmake)(s->b.v.x + mb * p.x, s->b.v.y + mb * p.y);
    s->b.w = s->b.w + ib * (KG_L(kg_lcross)(s->rb, p) + angular);
}

/* b's anchor point's velocity relative to a's. */
KG_FN kg_lv2 KG_L(kg_joint_relative_velocity)(const kg_lpair* s)
{
    kg_lv2 vb = KG_L(kg_lmake)(s->b.v.x + -s->b.w * s->rb.y, s->b.v.y + s->b.w * s->rb.x);
    kg_lv2 va = KG_L(kg_lmake)(s->a.v.x + -s->a.w * s->ra.y, s->a.v.y + s->a.w * s->ra.x);
    return KG_L(kg_lsub)(vb, va);
}

/* How far b's anchor is from a's now (delta_center: the centres' offset at the step's start). */
KG_FN kg_lv2 KG_L(kg_joint_offset)(kg_lv2 delta_center, const kg_lpair* s)
{
    kg_lv2 moved = KG_L(kg_lsub)(s->b.dp, s->a.dp);
    return KG_L(kg_ladd)(KG_L(kg_ladd)(moved, KG_L(kg_lsub)(s->rb, s->ra)), delta_center);
}

/* The angle of b relative to a now, less the reference (delta_angle: at the step's start). */
KG_FN kg_lane KG_L(kg_joint_angle)(kg_lane delta_angle, const kg_lpair* s)
{
    return KG_L(kg_unwind_angle)(delta_angle + KG_L(kg_relative_angle)(s->b.dq, s->a.dq));
}

/* The impulse x with K x = rhs, K the 2x2 mass of keeping b's anchor on a's (the
 * point-to-point part, and the mouse joint's pull). */
KG_FN kg_lv2 KG_L(kg_point_mass_solve)(kg_lane ma, kg_lane ia, kg_lane mb, kg_lane ib, const kg_lpair* s, kg_lv2 rhs)
{
    kg_lv2 ra = s->ra, rb = s->rb;
    kg_lane k11 = ma + mb + ra.y * ra.y * ia + rb.y * rb.y * ib;
    kg_lane k12 = -ra.y * ra.x * ia - rb.y * rb.x * ib;
    kg_lane k22 = ma + mb + ra.x * ra.x * ia + rb.x * rb.x * ib;
    return KG_L(kg_solve22)(k11, k12, k22, rhs);
}

/* The point-to-point part (revolute, weld): b's anchor on a's with the softness soft,
 * *acc its accumulated impulse. */
KG_FN void KG_L(kg_joint_point)(kg_lane ma, kg_lane ia, kg_lane mb, kg_lane ib, kg_lv2 delta_center, kg_lv2* acc,
                                kg_lpair* s, kg_lsoft soft)
{
    kg_lv2 cdot = KG_L(kg_joint_relative_velocity)(s);
    kg_lv2 bias = KG_L(kg_lscale)(soft.bias_rate, KG_L(kg_joint_offset)(delta_center, s));
    kg_lv2 x = KG_L(kg_point_mass_solve)(ma, ia, mb, ib, s, KG_L(kg_ladd)(cdot, bias));
    kg_lv2 impulse = KG_L(kg_lmake)(-soft.mass_scale * x.x - soft.impulse_scale * acc->x,
                                    -soft.mass_scale * x.y - soft.impulse_scale * acc->y);
    *acc = KG_L(kg_ladd)(*acc, impulse);
    KG_L(kg_joint_push)(ma, ia, mb, ib, s, impulse, KG_LZERO);
}

/* An angular or axial row pushing one way only (a limit): c is how far inside the limit
 * (>= 0 when satisfied), cdot the speed it grows at, *acc its accumulated impulse (>= 0),
 * kept where on. Returns the impulse to add along +cdot. Speculative when inside (it may
 * close the gap within the sub-step); past it, with the pass's rigid softness. */
KG_FN kg_lane KG_L(kg_one_sided)(kg_lmask on, kg_lane c, kg_lane cdot, kg_lane mass, kg_lane* acc, kg_lsoft rigid,
                                 kg_solver_params prm)
{
    kg_lane zero = KG_LZERO;
    kg_lmask inside = KG_LGT(c, zero);
    kg_lane bias = KG_SEL(inside, c * prm.inv_h, rigid.bias_rate * c);
    kg_lane mass_scale = KG_SEL(inside, zero + 1.0f, rigid.mass_scale);
    kg_lane impulse_scale = KG_SEL(inside, zero, rigid.impulse_scale);
    kg_lane impulse = -mass * mass_scale * (cdot + bias) - impulse_scale * (*acc);
    kg_lane next = KG_L(kg_lmax)(*acc + impulse, zero);
    impulse = next - *acc;
    *acc = KG_SEL(on, next, *acc);
    return impulse;
}

/* The torque `impulse` on a (minus) and b (plus) where on, else nothing. */
KG_FN void KG_L(kg_revolute_turn)(const kg_lrev* r, kg_lpair* s, kg_lmask on, kg_lane impulse)
{
    s->a.w = KG_SEL(on, s->a.w - r->inv_i_a * impulse, s->a.w);
    s->b.w = KG_SEL(on, s->b.w + r->inv_i_b * impulse, s->b.w);
}

/* The joint's own spring about its reference angle (every pass). */
KG_FN void KG_L(kg_revolute_spring)(kg_lrev* r, kg_lpair* s)
{
    kg_lmask on = KG_LNE(r->has_spring, KG_LZERO);
    kg_lane c = KG_L(kg_joint_angle)(r->delta_angle, s);
    kg_lane cdot = s->b.w - s->a.w;
    kg_lane impulse = -r->spring.mass_scale * r->axial_mass * (cdot + r->spring.bias_rate * c) -
                      r->spring.impulse_scale * r->spring_impulse;
    r->spring_impulse = KG_SEL(on, r->spring_impulse + impulse, r->spring_impulse);
    KG_L(kg_revolute_turn)(r, s, on, impulse);
}

/* The motor: towards motor_speed with at most max_motor_torque. */
KG_FN void KG_L(kg_revolute_motor)(kg_lrev* r, kg_lpair* s, kg_solver_params prm)
{
    kg_lmask on = KG_LNE(r->has_motor, KG_LZERO);
    kg_lane cdot = s->b.w - s->a.w - r->motor_speed;
    kg_lane impulse = -r->axial_mass * cdot;
    kg_lane old = r->motor_impulse, most = prm.h * r->max_motor_torque, sum = old + impulse;
    kg_lane clamped = KG_SEL(KG_LLT(sum, -most), -most, KG_SEL(KG_LGT(sum, most), most, sum));
    r->motor_impulse = KG_SEL(on, clamped, old);
    KG_L(kg_revolute_turn)(r, s, on, clamped - old);
}

/* The limits on the angle, lower then upper. */
KG_FN void KG_L(kg_revolute_limits)(kg_lrev* r, kg_lpair* s, kg_solver_params prm, kg_lsoft rigid)
{
    kg_lmask on = KG_LNE(r->has_limit, KG_LZERO);
    kg_lane angle = KG_L(kg_joint_angle)(r->delta_angle, s);
    kg_lane lower =
        KG_L(kg_one_sided)(on, angle - r->lower, s->b.w - s->a.w, r->axial_mass, &r->lower_impulse, rigid, prm);
    KG_L(kg_revolute_turn)(r, s, on, lower);
    kg_lane upper =
        KG_L(kg_one_sided)(on, r->upper - angle, s->a.w - s->b.w, r->axial_mass, &r->upper_impulse, rigid, prm);
    KG_L(kg_revolute_turn)(r, s, on, -upper);
}

/* The softness of a joint's rigid parts in a pass (soft: the joint's): soft in the solve
 * pass; in the relax pass no bias and no leak, each iteration but the last over-relaxed
 * by KG_JOINT_OVERRELAX, the last a plain projection (a joint alone ends exactly rigid). */
KG_FN kg_lsoft KG_L(kg_rigid_softness)(kg_lsoft soft, int pass, int last_iteration)
{
    kg_lsoft rigid = soft;
    if (pass != KG_PASS_SOLVE) {
        kg_lane zero = KG_LZERO;
        rigid.bias_rate = zero;
        rigid.mass_scale = zero + (last_iteration ? 1.0f : KG_JOINT_OVERRELAX);
        rigid.impulse_scale = zero;
    }
    return rigid;
}

/* One pass over the joints (KG_PASS_WARM_START, _SOLVE or _RELAX) and their bodies. */
KG_FN void KG_L(kg_revolute_pass)(kg_lrev* r, kg_lmotion* a, kg_lmotion* b, kg_solver_params prm, int pass,
                                  int last_iteration)
{
    kg_lpair s;
    s.a = *a;
    s.b = *b;
    s.ra = KG_L(kg_lrotate)(a->dq, r->anchor_a);
    s.rb = KG_L(kg_lrotate)(b->dq, r->anchor_b);
    if (pass == KG_PASS_WARM_START) {
        kg_lane torque = r->spring_impulse + r->motor_impulse + r->lower_impulse - r->upper_impulse;
        KG_L(kg_joint_push)(r->inv_mass_a, r->inv_i_a, r->inv_mass_b, r->inv_i_b, &s, r->linear_impulse, torque);
    } else {
        kg_lsoft rigid = KG_L(kg_rigid_softness)(r->soft, pass, last_iteration);
        KG_L(kg_revolute_spring)(r, &s);
        KG_L(kg_revolute_motor)(r, &s, prm);
        KG_L(kg_revolute_limits)(r, &s, prm, rigid);
        KG_L(kg_joint_point)(r->inv_mass_a, r->inv_i_a, r->inv_mass_b, r->inv_i_b, r->delta_center,
                             &r->linear_impulse, &s, rigid);
    }
    *a = s.a;
    *b = s.b;
}

#undef kg_lpair
#undef kg_lrev
#undef kg_lsoft
#undef kg_lmotion
#undef kg_lv2
#undef kg_lq
#undef KG_LABS
#undef KG_L
#ifdef KG_L2
#undef KG_L2
#undef KG_L3
#endif
