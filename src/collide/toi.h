/* Continuous collision (time of impact), shared by the CPU backend and the OpenCL kernels.
 *
 * A body that moves fast (kg_moves_fast) is swept from its pose at the start of
 * the step to its pose at the end (kg_sweep); the time of impact with a shape is found by
 * conservative advancement: at fraction t of the sweep the exact distance d between the
 * two shapes is measured, and no point of the moving shape moves faster than `bound`
 * (metres per unit fraction), so the sweep can advance by (d - target) / bound without
 * the shapes coming closer than target. The result is never an overlap, whatever the
 * speed; it converges in one or two steps for a body hitting a wall head on, more slowly
 * for a spinning one (capped: an unconverged sweep stops early, never late).
 *
 * Only the moving shape, its sweep and the other shape with its pose are read, never the
 * body pool: a body with several shapes takes the earliest time of impact of each. */
#ifndef KG_TOI_H
#define KG_TOI_H

#include "core/kg_layout.h"

/* Conservative advancement steps before giving up (and stopping where it got to). */
#define KG_TOI_MAX_ITERATIONS 24

/* The turning speed bound of kg_sweep_motion_of at the largest turn it bounds. */
#define KG_TOI_WILD_TURN 8.72f

/* A moving body's motion over the step: its centre of mass goes from c1 to c2 in a
 * straight line and its rotation from q1 to q2 along the shorter arc (normalized linear
 * interpolation), with local_center its centre of mass in its own frame and max_extent
 * the farthest any point of it lies from there (kg_extents.max). */
typedef struct kg_sweep {
    kg_vec2 local_center;
    kg_vec2 c1, c2;
    kg_rot q1, q2;
    float max_extent;
} kg_sweep;

/* The rotation a fraction t along q1 -> q2. */
KG_FN kg_rot kg_sweep_rot(const kg_sweep* s, float t)
{
    kg_rot q;
    q.c = (1.0f - t) * s->q1.c + t * s->q2.c;
    q.s = (1.0f - t) * s->q1.s + t * s->q2.s;
    return kg_rot_normalize(q);
}

KG_FN kg_vec2 kg_sweep_center(const kg_sweep* s, float t) { return kg_lerp(s->c1, s->c2, t); }

/* The body origin's pose a fraction t along the sweep. */
KG_FN kg_xf kg_sweep_xf(const kg_sweep* s, float t)
{
    return kg_origin_xf(kg_sweep_center(s, t), kg_sweep_rot(s, t), s->local_center);
}

/* Round part of a shape: circles (count 1) and, later, capsules (count 2) carry their
 * radius; polygons are sharp (the narrowphase ignores theirs too). */
KG_FN float kg_round_radius(const kg_shape* s) { return s->count >= 3 ? 0.0f : s->radius; }

/* How large a body is for the continuous collision: min, the radius of the largest circle
 * around its shape's centroid within it; max, the farthest a point of it lies from its
 * centre of mass. A function of the shape alone, which the CPU backend keeps per body. */
typedef struct kg_extents {
    float min, max;
} kg_extents;

/* The least distance of the centroid to a face (to the rim for round shapes). */
KG_FN float kg_shape_min_extent(const kg_shape* s)
{
    if (s->count < 3) {
        return s->radius;
    }
    float least = KG_FLT_MAX;
    for (int i = 0; i < s->count; ++i) {
        least = kg_minf(least, kg_dot(s->normals[i], kg_sub(s->vertices[i], s->centroid)));
    }
    return least;
}

/* The farthest a point of the shape lies from the centre of mass c (body frame). */
KG_FN float kg_shape_max_extent(const kg_shape* s, kg_vec2 c)
{
    float far2 = 0.0f;
    for (int i = 0; i < s->count; ++i) {
        far2 = kg_maxf(far2, kg_length_sq(kg_sub(s->vertices[i], c)));
    }
    return sqrtf(far2) + kg_round_radius(s);
}

KG_FN kg_extents kg_shape_extents(const kg_shape* s, kg_vec2 local_center)
{
    kg_extents e;
    e.min = kg_shape_min_extent(s);
    e.max = kg_shape_max_extent(s, local_center);
    return e;
}

/* Whether a body moving at v and w may have passed through something in a step of dt:
 * a point of it moves more than half its least extent (Box2D v3's test). Slower bodies
 * cannot cross a shape as thick as themselves without a contact holding them, and pay
 * nothing more: most are told by squares alone, as (a + b)^2 <= 2 a^2 + 2 b^2. */
KG_FN int kg_moves_fast(kg_vec2 v, float w, float dt, kg_extents e)
{
    float half_extent = 0.5f * e.min;
    float linear2 = dt * dt * kg_length_sq(v);
    float turning2 = dt * dt * w * w * e.max * e.max;
    if (2.0f * (linear2 + turning2) <= half_extent * half_extent) {
        return 0;
    }
    return sqrtf(linear2) + sqrtf(turning2) > half_extent;
}

/* ---- distance ---- */

/* The closest points of two shapes, or that they overlap: distance < 0 (then only the
 * separating axis depth, and no normal). normal is the unit direction from the first
 * shape's closest point to the second's. */
typedef struct kg_separation {
    float distance;
    kg_vec2 normal;
} kg_separation;

/* The point of segment [a, b] (a point when a == b) closest to p. */
KG_FN kg_vec2 kg_closest_on_segment(kg_vec2 p, kg_vec2 a, kg_vec2 b)
{
    kg_vec2 e = kg_sub(b, a);
    float ee = kg_length_sq(e);
    float t = ee > 0.0f ? kg_clampf(kg_dot(kg_sub(p, a), e) / ee, 0.0f, 1.0f) : 0.0f;
    return kg_mul_add(a, t, e);
}

/* The largest separation of hull q from hull p along p's edge normals (p counter-clockwise
 * with 2 or more points; a segment's two sides are its two edges). */
KG_FN float kg_hull_separation(const kg_vec2* p, int np, const kg_vec2* q, int nq)
{
    float best = -KG_FLT_MAX;
    for (int i = 0; np >= 2 && i < np; ++i) {
        kg_vec2 v = p[i];
        kg_vec2 n = kg_normalize(kg_right_perp(kg_sub(p[i + 1 < np ? i + 1 : 0], v)));
        float deepest = KG_FLT_MAX;
        for (int j = 0; j < nq; ++j) {
            deepest = kg_minf(deepest, kg_dot(n, kg_sub(q[j], v)));
        }
        best = kg_maxf(best, deepest);
    }
    return best;
}

/* Keeps in *best (squared distance, offset) the nearest of itself and the offsets from
 * p's edges (p's point when it has one) to q's points, turned round when flip is set. */
KG_FN void kg_hull_points_to_edges(const kg_vec2* p, int np, const kg_vec2* q, int nq, int flip, float* best,
                                   kg_vec2* offset)
{
    for (int i = 0; i < np; ++i) {
        kg_vec2 a = p[i], b = p[i + 1 < np ? i + 1 : 0];
        for (int j = 0; j < nq; ++j) {
            kg_vec2 d = kg_sub(q[j], kg_closest_on_segment(q[j], a, b));
            float d2 = kg_length_sq(d);
            if (d2 < *best) {
                *best = d2;
                *offset = flip ? kg_neg(d) : d;
            }
        }
    }
}

/* The separation of two convex hulls of up to KG_MAX_VERTS points (counter-clockwise).
 * Separated hulls are closest between a point of one and an edge of the other, so the
 * least of those distances is exact. Two single points have no edge, and no axis to
 * tell an overlap by. */
KG_FN kg_separation kg_hull_distance(const kg_vec2* p, int np, const kg_vec2* q, int nq)
{
    kg_separation s;
    s.distance = kg_maxf(kg_hull_separation(p, np, q, nq), kg_hull_separation(q, nq, p, np));
    s.normal = kg_v2(0.0f, 0.0f);
    if (s.distance < 0.0f && (np >= 2 || nq >= 2)) {
        return s;
    }
    float best = KG_FLT_MAX;
    kg_vec2 offset = s.normal;
    kg_hull_points_to_edges(p, np, q, nq, 0, &best, &offset);
    kg_hull_points_to_edges(q, nq, p, np, 1, &best, &offset);
    s.distance = sqrtf(best);
    s.normal = kg_normalize(offset);
    return s;
}

/* The points of a shape moved by xf, and their count (clamped to the arrays). */
KG_FN int kg_shape_points(const kg_shape* s, kg_xf xf, kg_vec2* out)
{
    int n = s->count < KG_MAX_VERTS ? s->count : KG_MAX_VERTS;
    for (int i = 0; i < n; ++i) {
        out[i] = kg_xf_point(xf, s->vertices[i]);
    }
    return n;
}

/* The separation of shapes a and b (body frames) at poses xfa and xfb, round parts
 * included; the normal from a to b. */
KG_FN kg_separation kg_shape_distance(const kg_shape* a, kg_xf xfa, const kg_shape* b, kg_xf xfb)
{
    kg_vec2 pa[KG_MAX_VERTS];
    kg_vec2 pb[KG_MAX_VERTS];
    /* measured around a's first point, so coordinates stay small far from the origin */
    kg_xf base;
    base.p = kg_xf_point(xfa, a->vertices[0]);
    base.q = kg_rot_identity();
    int na = kg_shape_points(a, kg_xf_inv_mul(base, xfa), pa);
    int nb = kg_shape_points(b, kg_xf_inv_mul(base, xfb), pb);
    kg_separation s = kg_hull_distance(pa, na, pb, nb);
    s.distance -= kg_round_radius(a) + kg_round_radius(b);
    return s;
}

/* ---- time of impact ---- */

/* What a time of impact search is after: how close the shapes may come (the linear slop,
 * so that the contact next step starts just touching) and within what of it a fraction
 * counts as the impact. */
typedef struct kg_toi_params {
    float target;
    float tolerance;
} kg_toi_params;

/* How a shape moves along a sweep, in metres per unit fraction: its centre's
 * displacement, and how fast its farthest point can turn round it. The normalized
 * interpolation of a turn by angle a turns fastest halfway, at 2 tan(a / 2) per unit
 * fraction, which is 2 sin a / (1 + cos a) of the relative rotation. Past about 155
 * degrees a step (a body spinning at over 160 rad/s at 60 Hz) that grows without bound
 * and the search would stop the body where it started: it takes KG_TOI_WILD_TURN, the
 * bound at 155 degrees, which may let such a spinner's corner graze a wall but never its
 * centre pass it. */
typedef struct kg_sweep_motion {
    kg_vec2 displacement;
    float turning; /* the farthest point's speed round the centre, at most */
} kg_sweep_motion;

KG_FN kg_sweep_motion kg_sweep_motion_of(const kg_sweep* s)
{
    kg_rot dq = kg_rot_inv_mul(s->q1, s->q2);
    float turn = dq.c > -0.9f ? 2.0f * (dq.s < 0.0f ? -dq.s : dq.s) / (1.0f + dq.c) : KG_TOI_WILD_TURN;
    kg_sweep_motion m;
    m.displacement = kg_sub(s->c2, s->c1);
    m.turning = turn * s->max_extent;
    return m;
}

/* The first fraction of the sweep, below limit, at which moving (swept by s) comes
 * within target of other (at its pose other_xf), by conservative advancement: limit when
 * it does not come that close before limit; 0 when it is that close already at the start
 * (a shape resting on the other, which the contact handles). The plane through the
 * closest points, normal to the gap, keeps other behind it; moving's nearest point to it
 * approaches it no faster than the displacement along the normal plus the turning, so
 * the gap cannot close before that rate has covered it. A body sliding along a wall
 * therefore never stops for it. */
KG_FN float kg_time_of_impact(const kg_shape* moving, const kg_sweep* s, const kg_shape* other, kg_xf other_xf,
                              kg_toi_params prm, float limit)
{
    kg_sweep_motion m = kg_sweep_motion_of(s);
    float t = 0.0f;
    for (int k = 0; k < KG_TOI_MAX_ITERATIONS; ++k) {
        kg_separation sep = kg_shape_distance(moving, kg_sweep_xf(s, t), other, other_xf);
        float gap = sep.distance - prm.target;
        if (gap < prm.tolerance) {
            return t;
        }
        float closing = kg_maxf(kg_dot(m.displacement, sep.normal), 0.0f) + m.turning;
        if (closing * (limit - t) <= gap) {
            return limit;
        }
        t += gap / closing;
    }
    return t;
}

/* A circle at the shape's centroid, a quarter of its least extent in radius: the core
 * that still finds a wall when the whole shape starts touching something (a box
 * sliding on the ground into a wall), as Box2D v3 does. */
KG_FN kg_shape kg_shape_core(const kg_shape* shape)
{
    kg_shape core = *shape;
    core.vertices[0] = shape->centroid;
    core.centroid = shape->centroid;
    core.radius = 0.25f * kg_shape_min_extent(shape);
    core.count = 1;
    return core;
}

/* Whether an impact at fraction t is a graze the contact handles: past t the centre goes
 * on towards the other shape, along the gap's normal, by less than the core's radius, so
 * it stays in front and the overlap at the end of the step stays small (Box2D v3 keeps
 * chain segments from clipping a body this way). Without it a body that tumbles or rolls
 * fast over the ground was moved back at every bounce of its corners (a capsule rolling
 * end over end down a slope went 12% slower); one that would sink deep or pass through
 * still stops. */
KG_FN int kg_toi_is_graze(const kg_shape* moving, const kg_sweep* s, const kg_shape* other, kg_xf other_xf, float t)
{
    kg_separation sep = kg_shape_distance(moving, kg_sweep_xf(s, t), other, other_xf);
    float onwards = kg_dot(kg_sub(s->c2, kg_sweep_center(s, t)), sep.normal);
    return onwards < 0.25f * kg_shape_min_extent(moving);
}

/* The time of impact of a body's shape with another shape, as kg_time_of_impact (a graze
 * aside), and when the shape starts too close, that of its core: the fraction the body
 * may move to, never below 0, limit when nothing is hit before it. */
KG_FN float kg_shape_time_of_impact(const kg_shape* moving, const kg_sweep* s, const kg_shape* other, kg_xf other_xf,
                                    kg_toi_params prm, float limit)
{
    float t = kg_time_of_impact(moving, s, other, other_xf, prm, limit);
    if (t > 0.0f) {
        return t < limit && kg_toi_is_graze(moving, s, other, other_xf, t) ? limit : t;
    }
    kg_shape core = kg_shape_core(moving);
    t = kg_time_of_impact(&core, s, other, other_xf, prm, limit);
    return t > 0.0f ? t : limit;
}

#endif
