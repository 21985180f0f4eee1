/* The contact constraint's passes, written once over a lane type and instantiated per
 * width (no include guard: included once per width).
 *
 *   KG_W 1      a lane is a float: kg_contact_constraint is one constraint. The OpenCL
 *               kernels (one work-item a constraint), and the CPU where it has no SIMD.
 *   KG_W 4/8/16 a lane is a GCC/Clang vector of W floats: kg_contact_constraint_wW
 *               holds W constraints of one colour (no two share a moving body), each
 *               field a vector of their W values (structure of arrays); bodies are
 *               gathered into lanes before a pass and scattered back after it (solver.c).
 *
 * Every lane runs the same IEEE operations in the same order whatever the width: there
 * is no branch on a lane's data, only selects, so a constraint computes the same bits in
 * a kernel, a scalar loop or any lane of any width (no contraction into FMA: the build
 * says -ffp-contract=off and the kernels FP_CONTRACT OFF). A second point that a contact
 * does not have, or a padding lane, has zero masses and impulses and changes nothing.
 *
 * Before including: KG_W; kg_lane, kg_lmask, kg_lindex and kg_lint (the float,
 * comparison, slot and count types); KG_SEL(mask, a, b), KG_LZERO, and the comparisons
 * and the store where a mask is set of lane_compare.h; wider than 1, also
 * kg_vsqrt (contact_vector_lanes.h) for the bodies' sub-step (body_row.h, included at
 * the end). */

#if KG_W == 1
#define KG_L(name) name
#else
#define KG_L3(name, w) name##_w##w
#define KG_L2(name, w) KG_L3(name, w)
#define KG_L(name) KG_L2(name, KG_W)
#endif

#if KG_W == 1
#define kg_lv2 kg_vec2
#define kg_lq kg_rot
#else
typedef struct KG_L(kg_lvec2) {
    kg_lane x, y;
} KG_L(kg_lvec2);

typedef struct KG_L(kg_lrot) {
    kg_lane c, s;
} KG_L(kg_lrot);

#define kg_lv2 KG_L(kg_lvec2)
#define kg_lq KG_L(kg_lrot)
#endif

typedef struct KG_L(kg_constraint_point) {
    kg_lv2 anchor_a;         /* from a's centre of mass, world axes, at step start (on b:
                              * anchor_a + b_to_a, the constraint's) */
    kg_lane base_separation; /* at step start (kg_current_separation) */
    kg_lane normal_impulse;
    kg_lane tangent_impulse;
    kg_lane max_normal_impulse; /* largest over the sub-steps: a point that never pushed does not bounce */
    kg_lane normal_mass;
    kg_lane tangent_mass;
    kg_lane relative_velocity; /* approach speed before solving, for restitution */
    kg_lane total_normal_impulse; /* over the step: each sub-step's accumulated impulse (what
                                   * its warm start and passes applied), and the rebound */
} KG_L(kg_constraint_point);

typedef struct KG_L(kg_contact_constraint) {
    KG_L(kg_constraint_point) points[2];
    kg_lv2 normal;
    kg_lv2 b_to_a; /* from b's centre of mass to a's at step start: one for both points,
                    * each point's anchor on b its anchor on a plus this (two floats a
                    * constraint where b's own anchors were four) */
    kg_lane inv_mass_a, inv_i_a, inv_mass_b, inv_i_b;
    kg_lane friction, restitution;
    kg_lane bias_rate, mass_scale, impulse_scale; /* the contact's softness */
    kg_lane share_b;                              /* b's share of the inverse mass: where the anchors meet */
    /* the two normal rows' 2x2 mass at prepare: its coupling k12 (how far an impulse at
     * one point changes the other's normal velocity), and its inverse for the block
     * solve, zeros (no block solve) when the contact has one point or the rows are too
     * nearly redundant */
    kg_lane k12, inv_k11, inv_k12, inv_k22;
    kg_lindex a, b;    /* body slots; KG_NULL_INDEX = the static world (or a padding lane) */
    kg_lindex contact; /* index of the contact it came from */
    kg_lint point_count;
} KG_L(kg_contact_constraint);

/* A body's motion seen by the solver: velocity, and how far it moved and turned since
 * the step began (to update separations without recomputing the manifold). */
typedef struct KG_L(kg_body_motion) {
    kg_lv2 v;
    kg_lane w;
    kg_lv2 dp;
    kg_lq dq;
} KG_L(kg_body_motion);

#define kg_lmotion KG_L(kg_body_motion)
#define kg_lrow KG_L(kg_contact_constraint)
#define kg_lpoint KG_L(kg_constraint_point)

KG_FN kg_lv2 KG_L(kg_lmake)(kg_lane x, kg_lane y)
{
    kg_lv2 r;
    r.x = x;
    r.y = y;
    return r;
}
KG_FN kg_lv2 KG_L(kg_ladd)(kg_lv2 a, kg_lv2 b) { return KG_L(kg_lmake)(a.x + b.x, a.y + b.y); }
KG_FN kg_lv2 KG_L(kg_lsub)(kg_lv2 a, kg_lv2 b) { return KG_L(kg_lmake)(a.x - b.x, a.y - b.y); }
KG_FN kg_lv2 KG_L(kg_lscale)(kg_lane s, kg_lv2 v) { return KG_L(kg_lmake)(s * v.x, s * v.y); }
KG_FN kg_lane KG_L(kg_ldot)(kg_lv2 a, kg_lv2 b) { return a.x * b.x + a.y * b.y; }
KG_FN kg_lane KG_L(kg_lcross)(kg_lv2 a, kg_lv2 b) { return a.x * b.y - a.y * b.x; }
KG_FN kg_lv2 KG_L(kg_lright_perp)(kg_lv2 v) { return KG_L(kg_lmake)(v.y, -v.x); }
KG_FN kg_lv2 KG_L(kg_lrotate)(kg_lq q, kg_lv2 v)
{
    return KG_L(kg_lmake)(q.c * v.x - q.s * v.y, q.s * v.x + q.c * v.y);
}
/* v + w x r: the velocity of the point r of a body */
KG_FN kg_lv2 KG_L(kg_lpoint_velocity)(kg_lv2 v, kg_lane w, kg_lv2 r)
{
    return KG_L(kg_lmake)(v.x - w * r.y, v.y + w * r.x);
}
/* a > b ? a : b and a < b ? a : b, lane by lane; a width may give them as the x86
 * max and min instructions, which are defined as exactly these (KG_LMAX, KG_LMIN) */
#ifdef KG_LMAX
KG_FN kg_lane KG_L(kg_lmax)(kg_lane a, kg_lane b) { return KG_LMAX(a, b); }
KG_FN kg_lane KG_L(kg_lmin)(kg_lane a, kg_lane b) { return KG_LMIN(a, b); }
#else
KG_FN kg_lane KG_L(kg_lmax)(kg_lane a, kg_lane b) { return KG_SEL(KG_LGT(a, b), a, b); }
KG_FN kg_lane KG_L(kg_lmin)(kg_lane a, kg_lane b) { return KG_SEL(KG_LLT(a, b), a, b); }
#endif

/* What prepare reads of a contact besides the masses: its manifold (anchors relative to
 * a's origin; has_point 1 or 0 for each point) and the bodies' state. */
typedef struct KG_L(kg_prepare_input) {
    kg_lv2 anchor_a[2];
    kg_lane separation[2], normal_impulse[2], tangent_impulse[2], has_point[2];
    kg_lv2 normal;
    kg_lv2 origin_a, center_a, center_b; /* b's lever arms are a's plus center_a - center_b */
    kg_lv2 va, vb;
    kg_lane wa, wb;
    kg_lane unused[6]; /* to a whole number of 16-lane transposes; not written */
} KG_L(kg_prepare_input);

/* Above this condition number the two normal rows are nearly redundant and the 2x2
 * solve is unreliable (Box2D v2's limit). */
#define KG_MAX_BLOCK_CONDITION 1000.0f

/* Builds the constraint from a contact, its masses already set. A point the manifold
 * does not have is all zeros, so the passes, which always run both points, leave it at
 * zero. A two-point contact's 2x2 normal mass is made here, from the anchors at
 * prepare: its coupling for the points solved one after the other, its inverse for the
 * block solve (zeros, one point at a time, when there is one point or the rows are too
 * nearly redundant). */
KG_FN void KG_L(kg_contact_prepare_lanes)(kg_lrow* c, const KG_L(kg_prepare_input)* in, kg_solver_params prm)
{
    kg_lane zero = KG_LZERO, ma = c->inv_mass_a, ia = c->inv_i_a, mb = c->inv_mass_b, ib = c->inv_i_b;
    kg_lmask against_static = (KG_LEQ(ma, zero) & KG_LEQ(ia, zero)) | (KG_LEQ(mb, zero) & KG_LEQ(ib, zero));
    c->bias_rate = KG_SEL(against_static, zero + prm.static_softness.bias_rate, zero + prm.contact_softness.bias_rate);
    c->mass_scale = KG_SEL(against_static, zero + prm.static_softness.mass_scale, zero + prm.contact_softness.mass_scale);
    c->impulse_scale =
        KG_SEL(against_static, zero + prm.static_softness.impulse_scale, zero + prm.contact_softness.impulse_scale);
    c->share_b = KG_SEL(KG_LGT(ma + mb, zero), mb / (ma + mb), zero + 0.5f);
    c->normal = in->normal;
    kg_lv2 n = in->normal, t = KG_L(kg_lright_perp)(in->normal);
    /* a point is one point of both bodies: its anchor on b differs from its anchor on a
     * by the centres' offset, the same for both points */
    kg_lv2 b_to_a = KG_L(kg_lsub)(in->center_a, in->center_b);
    c->b_to_a = b_to_a;
    kg_lane rn[2][2]; /* cross(r, n) of each point, on a and on b */
    for (int j = 0; j < 2; ++j) {
        kg_lpoint* cp = &c->points[j];
        kg_lmask has = KG_LGT(in->has_point[j], zero);
        kg_lv2 ra = KG_L(kg_lsub)(KG_L(kg_ladd)(in->anchor_a[j], in->origin_a), in->center_a);
        kg_lv2 rb = KG_L(kg_ladd)(ra, b_to_a);
        rn[j][0] = KG_SEL(has, KG_L(kg_lcross)(ra, n), zero);
        rn[j][1] = KG_SEL(has, KG_L(kg_lcross)(rb, n), zero);
        kg_lane kn = ma + mb + ia * rn[j][0] * rn[j][0] + ib * rn[j][1] * rn[j][1];
        kg_lane rta = KG_L(kg_lcross)(ra, t), rtb = KG_L(kg_lcross)(rb, t);
        kg_lane kt = ma + mb + ia * rta * rta + ib * rtb * rtb;
        kg_lv2 dv = KG_L(kg_lsub)(KG_L(kg_lpoint_velocity)(in->vb, in->wb, rb), KG_L(kg_lpoint_velocity)(in->va, in->wa, ra));
        cp->anchor_a = KG_L(kg_lmake)(KG_SEL(has, ra.x, zero), KG_SEL(has, ra.y, zero));
        cp->base_separation = KG_SEL(has, in->separation[j], zero);
        cp->normal_impulse = KG_SEL(has, in->normal_impulse[j], zero);
        cp->tangent_impulse = KG_SEL(has, in->tangent_impulse[j], zero);
        cp->max_normal_impulse = zero;
        cp->normal_mass = KG_SEL(has & KG_LGT(kn, zero), 1.0f / kn, zero);
        cp->tangent_mass = KG_SEL(has & KG_LGT(kt, zero), 1.0f / kt, zero);
        cp->relative_velocity = KG_SEL(has, KG_L(kg_ldot)(n, dv), zero);
        cp->total_normal_impulse = zero;
    }
    kg_lane m = ma + mb;
    kg_lane k11 = m + ia * rn[0][0] * rn[0][0] + ib * rn[0][1] * rn[0][1];
    kg_lane k22 = m + ia * rn[1][0] * rn[1][0] + ib * rn[1][1] * rn[1][1];
    kg_lane k12 = m + ia * rn[0][0] * rn[1][0] + ib * rn[0][1] * rn[1][1];
    kg_lane det = k11 * k22 - k12 * k12;
    kg_lmask ok = KG_LGT(in->has_point[1], zero) & KG_LLT(k11 * k11, KG_MAX_BLOCK_CONDITION * det);
    kg_lane inv_det = KG_SEL(ok, 1.0f / det, zero);
    c->inv_k11 = inv_det * k22;
    c->inv_k12 = -inv_det * k12;
    c->inv_k22 = inv_det * k11;
    c->k12 = k12;
}

KG_FN void KG_L(kg_apply_impulse_pair)(const kg_lrow* c, kg_lmotion* a, kg_lmotion* b, kg_lv2 ra, kg_lv2 rb, kg_lv2 p)
{
    a->v = KG_L(kg_lsub)(a->v, KG_L(kg_lscale)(c->inv_mass_a, p));
    a->w = a->w - c->inv_i_a * KG_L(kg_lcross)(ra, p);
    b->v = KG_L(kg_ladd)(b->v, KG_L(kg_lscale)(c->inv_mass_b, p));
    b->w = b->w + c->inv_i_b * KG_L(kg_lcross)(rb, p);
}

/* The anchors an impulse acts at. Box2D keeps each body's anchor fixed relative to its
 * centre during the step; but the bodies move apart, so the equal and opposite impulses
 * (normal and friction) then act at two points and add a torque to the pair (angular
 * momentum drifted by 1e-3 in an off-centre hit). Both anchors are moved to one point,
 * weighted by inverse mass: against an immovable body it stays with the moving body
 * (exactly Box2D's anchor, so a sliding circle feels no lever arm), between equal bodies
 * it is halfway. Anchors do not turn with the bodies: a spinning circle's anchor must
 * stay at its bottom. The one point follows the bodies' slide past each other since the
 * step began, but the masses were prepared with the lever arms at its start: a pair that
 * has slid farther than half the radius of gyration of either body (gap^2 inv_i >
 * inv_mass / 4) keeps each body's own anchor, Box2D's, where the lever arms stay what the
 * masses assumed. Else they grew without bound and each pass overshot the last (a disc
 * falling at 65 m/s between two others, rain_100000: 1e36 rad/s a step later). */
KG_FN void KG_L(kg_current_anchors)(const kg_lrow* c, const kg_lpoint* cp, const kg_lmotion* a, const kg_lmotion* b,
                                    kg_lv2* ra, kg_lv2* rb)
{
    kg_lv2 gap = KG_L(kg_lsub)(b->dp, a->dp); /* how far b's anchor point moved from a's */
    kg_lane reach = KG_L(kg_ldot)(gap, gap), zero = KG_LZERO;
    kg_lmask near = KG_LGE(0.25f * c->inv_mass_a, reach * c->inv_i_a) &
                    KG_LGE(0.25f * c->inv_mass_b, reach * c->inv_i_b); /* else Box2D's anchors */
    gap = KG_L(kg_lmake)(KG_SEL(near, gap.x, zero), KG_SEL(near, gap.y, zero));
    *ra = KG_L(kg_ladd)(cp->anchor_a, KG_L(kg_lscale)(c->share_b, gap));
    *rb = KG_L(kg_ladd)(*ra, KG_L(kg_lsub)(c->b_to_a, gap)); /* b's anchor at step start, less (1 - share_b) gap */
}

KG_FN kg_lane KG_L(kg_normal_velocity_at)(const kg_lrow* c, const kg_lmotion* a, const kg_lmotion* b, kg_lv2 ra,
                                          kg_lv2 rb)
{
    kg_lv2 dv = KG_L(kg_lsub)(KG_L(kg_lpoint_velocity)(b->v, b->w, rb), KG_L(kg_lpoint_velocity)(a->v, a->w, ra));
    return KG_L(kg_ldot)(dv, c->normal);
}

/* Applies last step's impulses at the start of a sub-step. */
KG_FN void KG_L(kg_contact_warm_start)(const kg_lrow* c, kg_lmotion* a, kg_lmotion* b)
{
    kg_lv2 t = KG_L(kg_lright_perp)(c->normal);
    for (int j = 0; j < 2; ++j) {
        const kg_lpoint* cp = &c->points[j];
        kg_lv2 ra, rb;
        KG_L(kg_current_anchors)(c, cp, a, b, &ra, &rb);
        kg_lv2 p = KG_L(kg_ladd)(KG_L(kg_lscale)(cp->normal_impulse, c->normal), KG_L(kg_lscale)(cp->tangent_impulse, t));
        KG_L(kg_apply_impulse_pair)(c, a, b, ra, rb, p);
    }
}

/* How a body's turn q since the step's start changes the reach of its points along the
 * normal n: the point r's by dot(r, m) for m = q^-1 n - n (dot(q r, n) = dot(r, q^-1 n)),
 * one m a body for both points. No turn gives exactly zero whatever r's size: an anchor
 * on the static world is a world position, hundreds of metres along a long slope of
 * tiles, where q r - r lost its last places, a different error at every step, and a box
 * sliding across it bounced. */
KG_FN kg_lv2 KG_L(kg_lturn_of_normal)(kg_lq q, kg_lv2 n)
{
    kg_lv2 unturned = KG_L(kg_lmake)(q.c * n.x + q.s * n.y, q.c * n.y - q.s * n.x);
    return KG_L(kg_lsub)(unturned, n);
}

/* Separation of point j now, from how far the bodies moved since the manifold: its two
 * copies moved apart by the bodies' displacements and turns. */
KG_FN kg_lane KG_L(kg_current_separation)(const kg_lrow* c, const kg_lpoint* cp, const kg_lmotion* a,
                                          const kg_lmotion* b)
{
    kg_lv2 anchor_b = KG_L(kg_ladd)(cp->anchor_a, c->b_to_a);
    kg_lane moved = KG_L(kg_ldot)(KG_L(kg_lsub)(b->dp, a->dp), c->normal);
    kg_lane turned = KG_L(kg_ldot)(anchor_b, KG_L(kg_lturn_of_normal)(b->dq, c->normal)) -
                     KG_L(kg_ldot)(cp->anchor_a, KG_L(kg_lturn_of_normal)(a->dq, c->normal));
    return (moved + turned) + cp->base_separation;
}

/* The velocity target of a point: a speculative gap (s > 0) may close within the
 * sub-step; a penetration is pushed out softly (use_bias) at a bounded speed. */
typedef struct KG_L(kg_point_bias) {
    kg_lane bias, mass_scale, impulse_scale;
} KG_L(kg_point_bias);

KG_FN KG_L(kg_point_bias) KG_L(kg_point_bias_of)(const kg_lrow* c, kg_lane s, kg_solver_params prm, int use_bias)
{
    KG_L(kg_point_bias) pb;
    kg_lmask apart = KG_LGT(s, KG_LZERO);
    kg_lane zero = KG_LZERO;
    kg_lane push = use_bias ? KG_L(kg_lmax)(c->bias_rate * s, zero - prm.max_push_out_speed) : zero;
    pb.bias = KG_SEL(apart, s * prm.inv_h, push);
    pb.mass_scale = use_bias ? KG_SEL(apart, zero + 1.0f, c->mass_scale) : zero + 1.0f;
    pb.impulse_scale = use_bias ? KG_SEL(apart, zero, c->impulse_scale) : zero;
    return pb;
}

/* Adds an impulse (already clamped so that the total stays >= 0) to point cp's
 * accumulated normal impulse, where vn is the normal velocity it answers. The first push
 * of the step records vn as the approach speed for restitution: sampled at the start of
 * the step it would miss the speed gained (up to g dt) before the bodies actually met.
 * Both records are written only where they change (KG_STORE_WHERE): after the first
 * sub-step they seldom do, and a row line left unwritten need not go back to memory. */
KG_FN void KG_L(kg_accumulate_normal)(kg_lpoint* cp, kg_lane applied, kg_lane vn)
{
    kg_lane most = cp->max_normal_impulse;
    KG_STORE_WHERE(KG_LEQ(most, KG_LZERO) & KG_LGT(applied, KG_LZERO), cp->relative_velocity, vn);
    cp->normal_impulse = cp->normal_impulse + applied;
    KG_STORE_WHERE(KG_LGT(applied, most), cp->max_normal_impulse, applied);
}

/* One Gauss-Seidel pass over the constraint: normal impulses (soft when use_bias), then
 * friction bounded by the new normal impulses.
 *
 * A two-point contact's normal impulses are solved together as a 2x2 problem (Box2D
 * v2's block solver) where both points stay pushing and in the same regime: solving
 * them one after the other leaves a small torque each time, which a 20-box stack
 * amplifies until it topples (measured at 4 sub-steps, where it leans 1.5 m in 10 s).
 * Elsewhere the points go one after the other. Both are computed, and a select keeps
 * one, so every lane runs the same operations. */
KG_FN void KG_L(kg_contact_solve)(kg_lrow* c, kg_lmotion* a, kg_lmotion* b, kg_solver_params prm, int use_bias)
{
    kg_lv2 ra[2], rb[2];
    KG_L(kg_point_bias) pb[2];
    kg_lane vn[2];
    for (int j = 0; j < 2; ++j) {
        KG_L(kg_current_anchors)(c, &c->points[j], a, b, &ra[j], &rb[j]);
        pb[j] = KG_L(kg_point_bias_of)(c, KG_L(kg_current_separation)(c, &c->points[j], a, b), prm, use_bias);
        vn[j] = KG_L(kg_normal_velocity_at)(c, a, b, ra[j], rb[j]);
    }
    kg_lane zero = KG_LZERO;
    /* the block candidate, from the velocities before either point */
    kg_lane rhs0 = pb[0].mass_scale * (vn[0] + pb[0].bias), rhs1 = pb[1].mass_scale * (vn[1] + pb[1].bias);
    kg_lane acc0 = c->points[0].normal_impulse, acc1 = c->points[1].normal_impulse;
    kg_lane x0 = -(c->inv_k11 * rhs0 + c->inv_k12 * rhs1) - pb[0].impulse_scale * acc0;
    kg_lane x1 = -(c->inv_k12 * rhs0 + c->inv_k22 * rhs1) - pb[1].impulse_scale * acc1;
    kg_lmask use_block = KG_LGT(c->inv_k11, zero) & KG_LEQ(pb[0].mass_scale, pb[1].mass_scale) &
                         KG_LGE(acc0 + x0, zero) & KG_LGE(acc1 + x1, zero);
    /* one point after the other: the second sees the first's impulse, through the
     * coupling k12 (a one-point contact's second point has no mass: it pushes nothing) */
    kg_lane seq[2];
    kg_lane v = vn[0];
    for (int j = 0; j < 2; ++j) {
        kg_lpoint* cp = &c->points[j];
        kg_lane impulse = -cp->normal_mass * pb[j].mass_scale * (v + pb[j].bias) - pb[j].impulse_scale * cp->normal_impulse;
        seq[j] = KG_L(kg_lmax)(cp->normal_impulse + impulse, zero) - cp->normal_impulse;
        vn[j] = KG_SEL(use_block, vn[j], v);
        v = vn[1] + c->k12 * seq[0];
    }
    /* either way, the chosen impulses applied in point order: the same operations as
     * the sequential candidate's where it is chosen */
    kg_lane block_x[2] = {x0, x1};
    for (int j = 0; j < 2; ++j) {
        kg_lane applied = KG_SEL(use_block, block_x[j], seq[j]);
        KG_L(kg_accumulate_normal)(&c->points[j], applied, vn[j]);
        KG_L(kg_apply_impulse_pair)(c, a, b, ra[j], rb[j], KG_L(kg_lscale)(applied, c->normal));
    }

    kg_lv2 t = KG_L(kg_lright_perp)(c->normal);
    for (int j = 0; j < 2; ++j) {
        kg_lpoint* cp = &c->points[j];
        kg_lv2 dv = KG_L(kg_lsub)(KG_L(kg_lpoint_velocity)(b->v, b->w, rb[j]), KG_L(kg_lpoint_velocity)(a->v, a->w, ra[j]));
        kg_lane vt = KG_L(kg_ldot)(dv, t);
        kg_lane max_friction = c->friction * cp->normal_impulse;
        kg_lane accumulated = KG_L(kg_lmin)(KG_L(kg_lmax)(cp->tangent_impulse - cp->tangent_mass * vt, -max_friction),
                                            max_friction);
        kg_lane impulse = accumulated - cp->tangent_impulse;
        cp->tangent_impulse = accumulated;
        KG_L(kg_apply_impulse_pair)(c, a, b, ra[j], rb[j], KG_L(kg_lscale)(impulse, t));
    }
    if (!use_bias) { /* the relax ends a sub-step: its accumulated impulse is what the sub-step applied */
        for (int j = 0; j < 2; ++j) {
            c->points[j].total_normal_impulse = c->points[j].total_normal_impulse + c->points[j].normal_impulse;
        }
    }
}

/* The restitution pass: where a point was approaching faster than the threshold and
 * did push, the rebound speed becomes restitution times the approach speed. Both
 * points of a bouncing two-point contact at once where the block solution pushes, so
 * two equal boxes meeting face to face exchange their velocities instead of starting
 * to spin; else one after the other. A constraint with no bouncing point is left
 * exactly as it was (a zero impulse could still turn a -0 velocity into +0), so the CPU
 * may skip the pass when nothing bounces and stay bitwise equal to the kernels. */
KG_FN void KG_L(kg_contact_restitution)(kg_lrow* c, kg_lmotion* a, kg_lmotion* b, kg_solver_params prm)
{
    kg_lmotion a0 = *a, b0 = *b;
    kg_lv2 ra[2], rb[2];
    kg_lmask bounces[2];
    kg_lane rhs[2];
    kg_lane zero = KG_LZERO;
    for (int j = 0; j < 2; ++j) {
        const kg_lpoint* cp = &c->points[j];
        KG_L(kg_current_anchors)(c, cp, a, b, &ra[j], &rb[j]);
        bounces[j] = KG_LLT(cp->relative_velocity, zero - prm.restitution_threshold) &
                     KG_LGT(cp->max_normal_impulse, zero) & KG_LNE(c->restitution, zero);
        rhs[j] = KG_L(kg_normal_velocity_at)(c, a, b, ra[j], rb[j]) + c->restitution * cp->relative_velocity;
    }
    kg_lane x0 = -(c->inv_k11 * rhs[0] + c->inv_k12 * rhs[1]);
    kg_lane x1 = -(c->inv_k12 * rhs[0] + c->inv_k22 * rhs[1]);
    kg_lmask use_block = bounces[0] & bounces[1] & KG_LGT(c->inv_k11, zero) &
                         KG_LGE(c->points[0].normal_impulse + x0, zero) & KG_LGE(c->points[1].normal_impulse + x1, zero);
    kg_lane block_x[2] = {x0, x1};
    for (int j = 0; j < 2; ++j) {
        kg_lpoint* cp = &c->points[j];
        kg_lane vn = KG_L(kg_normal_velocity_at)(c, a, b, ra[j], rb[j]);
        kg_lane impulse = -cp->normal_mass * (vn + c->restitution * cp->relative_velocity);
        kg_lane applied = KG_L(kg_lmax)(cp->normal_impulse + impulse, zero) - cp->normal_impulse;
        applied = KG_SEL(use_block, block_x[j], KG_SEL(bounces[j], applied, zero));
        cp->normal_impulse = KG_SEL(bounces[j], cp->normal_impulse + applied, cp->normal_impulse);
        cp->total_normal_impulse = KG_SEL(bounces[j], cp->total_normal_impulse + applied, cp->total_normal_impulse);
        KG_L(kg_apply_impulse_pair)(c, a, b, ra[j], rb[j], KG_L(kg_lscale)(applied, c->normal));
    }
    kg_lmask touched = bounces[0] | bounces[1];
    a->v = KG_L(kg_lmake)(KG_SEL(touched, a->v.x, a0.v.x), KG_SEL(touched, a->v.y, a0.v.y));
    a->w = KG_SEL(touched, a->w, a0.w);
    b->v = KG_L(kg_lmake)(KG_SEL(touched, b->v.x, b0.v.x), KG_SEL(touched, b->v.y, b0.v.y));
    b->w = KG_SEL(touched, b->w, b0.w);
}

/* One pass of the solver over the constraint. */
KG_FN void KG_L(kg_contact_pass)(kg_lrow* c, kg_lmotion* a, kg_lmotion* b, kg_solver_params prm, int pass)
{
    switch (pass) {
    case KG_PASS_WARM_START: KG_L(kg_contact_warm_start)(c, a, b); break;
    case KG_PASS_SOLVE: KG_L(kg_contact_solve)(c, a, b, prm, 1); break;
    case KG_PASS_RELAX: KG_L(kg_contact_solve)(c, a, b, prm, 0); break;
    default: KG_L(kg_contact_restitution)(c, a, b, prm); break;
    }
}

/* the bodies' sub-step over the same lanes */
#include "solve/body_row.h"

#undef kg_lv2
#undef kg_lq
#undef kg_lmotion
#undef kg_lrow
#undef kg_lpoint
#undef KG_MAX_BLOCK_CONDITION
#undef KG_L
#ifdef KG_L2
#undef KG_L2
#undef KG_L3
#endif
