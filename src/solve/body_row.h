/* A body's sub-step, written once over a lane type and instantiated with the contacts'
 * passes (no include guard: contact_row.h includes it once per width, its lane macros
 * KG_L, kg_lv2 and kg_lq in force): semi-implicit Euler, velocities first from the
 * step's kg_velocity_step (solve/integrate.h), then the motion from the new velocities.
 *
 *   KG_W 1      a lane is a float: one body. solve/body_step.h runs it for body i, so
 *               the kernels and the CPU's last bodies of a range are this code.
 *   KG_W 4/8/16 W bodies of consecutive slots at a time (contact_wide_impl.h).
 *
 * There is no branch on a lane's data: a clamp is a select between two values both
 * computed, so a lane computes the bits the body computes alone at any width. */

#if KG_W == 1
#define KG_LABS(x) fabsf(x)
#define KG_LSQRT(x) sqrtf(x)
typedef kg_velocity_step kg_velocity_lanes;
#else
#define KG_LABS(x) ((kg_lane)((kg_lint)(x) & 0x7fffffff)) /* the sign bit cleared, as fabsf */
#define KG_LSQRT(x) kg_vsqrt(x)

/* kg_velocity_step in lanes. */
typedef struct KG_L(kg_velocity_lanes) {
    kg_lv2 dv;
    kg_lane dw, lin_factor, ang_factor;
} KG_L(kg_velocity_lanes);
#endif
#define kg_lvstep KG_L(kg_velocity_lanes)

/* The velocity after one sub-step: the step's acceleration added, implicit damping and
 * drag applied, the speed clamped along its direction (found from the velocity scaled to
 * its largest component first, so a huge but finite velocity does not overflow to
 * nothing) and the turn per sub-step to KG_MAX_ROTATION_PER_SUBSTEP. */
KG_FN void KG_L(kg_apply_velocity_lanes)(kg_lv2* v, kg_lane* w, const kg_lvstep* s, kg_integrate_params prm)
{
    kg_lane zero = KG_LZERO;
    kg_lv2 nv;
    nv.x = s->lin_factor * (v->x + s->dv.x);
    nv.y = s->lin_factor * (v->y + s->dv.y);
    kg_lane nw = s->ang_factor * (*w) + s->dw;
    float max_speed = prm.max_linear_speed;
    kg_lane ax = KG_LABS(nv.x), ay = KG_LABS(nv.y);
    kg_lane largest = KG_SEL(KG_LGT(ax, ay), ax, ay);
    kg_lmask too_fast = KG_LGT(largest, zero + max_speed) | KG_LGT(nv.x * nv.x + nv.y * nv.y, zero + max_speed * max_speed);
    kg_lane inv_largest = 1.0f / largest; /* inf or NaN where not too fast: not kept */
    kg_lane ux = inv_largest * nv.x, uy = inv_largest * nv.y;
    kg_lane length = KG_LSQRT(ux * ux + uy * uy);
    kg_lmask tiny = KG_LLT(length, zero + 1.0e-12f);
    kg_lane inv_length = 1.0f / length;
    kg_lane dx = KG_SEL(tiny, zero, inv_length * ux), dy = KG_SEL(tiny, zero, inv_length * uy);
    v->x = KG_SEL(too_fast, max_speed * dx, nv.x);
    v->y = KG_SEL(too_fast, max_speed * dy, nv.y);
    float max_w = KG_MAX_ROTATION_PER_SUBSTEP / prm.h;
    *w = KG_SEL(KG_LLT(nw, zero - max_w), zero - max_w, KG_SEL(KG_LGT(nw, zero + max_w), zero + max_w, nw));
}

/* The motion after one sub-step at velocities v and w: dp moved by h v, dq turned by h w
 * to first order and normalised again (Box2D v3's scheme: exact direction for small
 * angles, no trigonometry, the same bits on every backend). */
KG_FN void KG_L(kg_integrate_position_lanes)(kg_lv2* dp, kg_lq* dq, kg_lv2 v, kg_lane w, float h)
{
    kg_lane zero = KG_LZERO;
    dp->x = dp->x + h * v.x;
    dp->y = dp->y + h * v.y;
    kg_lane turn = h * w;
    kg_lane c = dq->c - turn * dq->s, s = dq->s + turn * dq->c;
    kg_lane magnitude = KG_LSQRT(s * s + c * c);
    kg_lane inv = KG_SEL(KG_LGT(magnitude, zero), 1.0f / magnitude, zero);
    dq->c = c * inv;
    dq->s = s * inv;
}

#undef kg_lvstep
#undef KG_LSQRT
#undef KG_LABS
