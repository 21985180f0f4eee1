/* 2D math shared by the CPU backend and the OpenCL kernels. Rotations are kept as
 * (cos, sin) pairs and advanced without trigonometry, so both sides compute the same
 * bits from the same inputs. */
#ifndef KG_MATH_H
#define KG_MATH_H

#include "kg_shared.h"

typedef struct kg_rot {
    float c, s;
} kg_rot;

typedef struct kg_xf {
    kg_vec2 p;
    kg_rot q;
} kg_xf;

KG_FN kg_vec2 kg_v2(float x, float y) { kg_vec2 v; v.x = x; v.y = y; return v; }
KG_FN kg_vec2 kg_add(kg_vec2 a, kg_vec2 b) { return kg_v2(a.x + b.x, a.y + b.y); }
KG_FN kg_vec2 kg_sub(kg_vec2 a, kg_vec2 b) { return kg_v2(a.x - b.x, a.y - b.y); }
KG_FN kg_vec2 kg_neg(kg_vec2 a) { return kg_v2(-a.x, -a.y); }
KG_FN kg_vec2 kg_scale(float s, kg_vec2 a) { return kg_v2(s * a.x, s * a.y); }
/* a + s * b */
KG_FN kg_vec2 kg_mul_add(kg_vec2 a, float s, kg_vec2 b) { return kg_v2(a.x + s * b.x, a.y + s * b.y); }
/* a - s * b */
KG_FN kg_vec2 kg_mul_sub(kg_vec2 a, float s, kg_vec2 b) { return kg_v2(a.x - s * b.x, a.y - s * b.y); }
KG_FN float kg_dot(kg_vec2 a, kg_vec2 b) { return a.x * b.x + a.y * b.y; }
KG_FN float kg_cross(kg_vec2 a, kg_vec2 b) { return a.x * b.y - a.y * b.x; }
/* cross(v, s) = (s v.y, -s v.x) */
KG_FN kg_vec2 kg_cross_vs(kg_vec2 v, float s) { return kg_v2(s * v.y, -s * v.x); }
/* cross(s, v) = (-s v.y, s v.x): the velocity of a point at v on a body spinning at s */
KG_FN kg_vec2 kg_cross_sv(float s, kg_vec2 v) { return kg_v2(-s * v.y, s * v.x); }
KG_FN kg_vec2 kg_left_perp(kg_vec2 v) { return kg_v2(-v.y, v.x); }
KG_FN kg_vec2 kg_right_perp(kg_vec2 v) { return kg_v2(v.y, -v.x); }
KG_FN float kg_length(kg_vec2 v) { return sqrtf(v.x * v.x + v.y * v.y); }
KG_FN float kg_length_sq(kg_vec2 v) { return v.x * v.x + v.y * v.y; }
KG_FN float kg_distance(kg_vec2 a, kg_vec2 b) { return kg_length(kg_sub(b, a)); }
KG_FN kg_vec2 kg_lerp(kg_vec2 a, kg_vec2 b, float t) { return kg_v2(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)); }
/* Compare-and-select: with strict float flags (no fast math) gcc calls fmaxf and fminf in
 * libm instead of inlining them, which cost about 3% of a step in the solver's rows.
 * For numbers (not NaN) they give the bits glibc's x86-64 fminf and fmaxf give, signed
 * zeros included: those are minss and maxss, which are these selects. */
KG_FN float kg_maxf(float a, float b) { return a > b ? a : b; }
KG_FN float kg_minf(float a, float b) { return a < b ? a : b; }
KG_FN kg_vec2 kg_vmin(kg_vec2 a, kg_vec2 b) { return kg_v2(kg_minf(a.x, b.x), kg_minf(a.y, b.y)); }
KG_FN kg_vec2 kg_vmax(kg_vec2 a, kg_vec2 b) { return kg_v2(kg_maxf(a.x, b.x), kg_maxf(a.y, b.y)); }
KG_FN float kg_clampf(float v, float lo, float hi) { return v < lo ? lo : (v > hi ? hi : v); }

KG_FN kg_vec2 kg_normalize(kg_vec2 v)
{
    float len = kg_length(v);
    if (len < 1.0e-12f) {
        return kg_v2(0.0f, 0.0f);
    }
    float inv = 1.0f / len;
    return kg_v2(inv * v.x, inv * v.y);
}

KG_FN kg_rot kg_rot_identity(void) { kg_rot q; q.c = 1.0f; q.s = 0.0f; return q; }
KG_FN kg_vec2 kg_rotate(kg_rot q, kg_vec2 v) { return kg_v2(q.c * v.x - q.s * v.y, q.s * v.x + q.c * v.y); }
KG_FN kg_vec2 kg_inv_rotate(kg_rot q, kg_vec2 v) { return kg_v2(q.c * v.x + q.s * v.y, -q.s * v.x + q.c * v.y); }

/* Renormalised rotation, so repeated integration cannot drift off the unit circle. */
KG_FN kg_rot kg_rot_normalize(kg_rot q)
{
    float mag = sqrtf(q.s * q.s + q.c * q.c);
    float inv = mag > 0.0f ? 1.0f / mag : 0.0f;
    kg_rot r;
    r.c = q.c * inv;
    r.s = q.s * inv;
    return r;
}

/* q applied after r. */
KG_FN kg_rot kg_rot_mul(kg_rot q, kg_rot r)
{
    kg_rot m;
    m.c = q.c * r.c - q.s * r.s;
    m.s = q.s * r.c + q.c * r.s;
    return m;
}

/* Relative rotation b * inverse(a). */
KG_FN kg_rot kg_rot_inv_mul(kg_rot a, kg_rot b)
{
    kg_rot r;
    r.s = a.c * b.s - a.s * b.c;
    r.c = a.c * b.c + a.s * b.s;
    return r;
}

KG_FN kg_vec2 kg_xf_point(kg_xf t, kg_vec2 p) { return kg_add(kg_rotate(t.q, p), t.p); }

/* The pose of a body's origin from its centre of mass and rotation. */
KG_FN kg_xf kg_origin_xf(kg_vec2 center, kg_rot q, kg_vec2 local_center)
{
    kg_xf t;
    t.q = q;
    t.p = kg_sub(center, kg_rotate(q, local_center));
    return t;
}
KG_FN kg_vec2 kg_xf_inv_point(kg_xf t, kg_vec2 p) { return kg_inv_rotate(t.q, kg_sub(p, t.p)); }

/* B expressed in A's frame: inverse(A) * B. */
KG_FN kg_xf kg_xf_inv_mul(kg_xf a, kg_xf b)
{
    kg_xf r;
    r.q = kg_rot_inv_mul(a.q, b.q);
    r.p = kg_inv_rotate(a.q, kg_sub(b.p, a.p));
    return r;
}

/* The four comparisons joined bitwise, not by ||: a broadphase meets pairs whose overlap
 * no branch predictor can guess (a tumbling crowd), and one test is cheaper than up to
 * four mispredicted branches. */
KG_FN int kg_aabb_overlap(kg_aabb a, kg_aabb b)
{
    return !((b.lower.x > a.upper.x) | (b.lower.y > a.upper.y) | (a.lower.x > b.upper.x) | (a.lower.y > b.upper.y));
}

KG_FN int kg_is_finite(float v) { return (v - v) == 0.0f; }
KG_FN int kg_vec_is_finite(kg_vec2 v) { return kg_is_finite(v.x) && kg_is_finite(v.y); }

#endif
