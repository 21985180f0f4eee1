/* Contact manifolds between two shapes (the narrowphase), shared by the CPU backend and the
 * OpenCL kernels. A shape with two or more vertices is a polygon with a radius: the points
 * within radius of its core, the convex polygon itself (today's polygons are sharp, radius 0;
 * a capsule is a 2-vertex core, its one segment run both ways, and a radius; a segment the
 * same with radius 0). The core manifold is computed and then rounded: separations lose both
 * radii and each point moves to the middle of the two rounded surfaces (Box2D v3's way). A
 * shape with one vertex is a circle around it, or a point when its radius is 0.
 *
 * Each pair is solved in shape a's body frame shifted to a's first vertex, so coordinates
 * stay small and float round-off low wherever the bodies are, then moved to the world frame.
 * Every contact point lies midway between the two surfaces: the surface of a is at
 * point - 0.5 * separation * normal, the surface of b at point + 0.5 * separation * normal. */
#ifndef KG_MANIFOLD_H
#define KG_MANIFOLD_H

#include "core/kg_layout.h"

/* Feature ids name a point by a vertex of a and a vertex of b, in (a, b) byte order, never
 * by which shape holds the reference face: a clipped point is named by the end of the
 * reference face on its side and the incident vertex on the same side, a pair that names
 * the same point when the reference passes to the other shape (loaded boxes that tilt
 * past the tolerance below flip it, and their warm starts would be lost). Circle contacts
 * always have id 0: a round shape's closest feature moves continuously, and so does its
 * impulse, which warm starting should keep. */

/* a's face stays the reference unless b's separation is larger by more than this (a tenth
 * of the 0.005 m linear slop), so float noise on nearly parallel faces cannot flip the
 * choice, and with it the feature ids, from one step to the next. Polygons farther apart
 * than this may touch corner to corner. */
#define KG_REFERENCE_TOLERANCE (0.1f * 0.005f)

/* Below this a length is treated as zero: no direction can be taken from it. */
#define KG_LENGTH_EPSILON 1.0e-6f

KG_FN int kg_next_vertex(int i, int count) { return i + 1 < count ? i + 1 : 0; }

KG_FN kg_manifold kg_empty_manifold(void)
{
    kg_manifold_point zero;
    zero.point = kg_v2(0.0f, 0.0f);
    zero.anchor_a = zero.point;
    zero.anchor_b = zero.point;
    zero.separation = 0.0f;
    zero.normal_impulse = 0.0f;
    zero.tangent_impulse = 0.0f;
    zero.normal_velocity = 0.0f;
    zero.id = 0u;
    zero.total_normal_impulse = 0.0f;
    kg_manifold m;
    m.points[0] = zero;
    m.points[1] = zero;
    m.normal = zero.point;
    m.point_count = 0;
    m.keepable = 0;
    return m;
}

/* Appends a point given in a's shifted frame (kept in .point until kg_manifold_to_world). */
KG_FN void kg_push_point(kg_manifold* m, kg_vec2 local_point, float separation, kg_u32 id)
{
    if (m->point_count >= 2) {
        return;
    }
    kg_manifold_point* mp = m->points + m->point_count;
    mp->point = local_point;
    mp->separation = separation;
    mp->id = id;
    m->point_count += 1;
}

/* The pose of b relative to a's frame shifted to origin (a point of a's body frame). */
KG_FN kg_xf kg_relative_xf(kg_xf xfa, kg_vec2 origin, kg_xf xfb)
{
    kg_xf shifted;
    shifted.p = kg_add(xfa.p, kg_rotate(xfa.q, origin));
    shifted.q = xfa.q;
    return kg_xf_inv_mul(shifted, xfb);
}

/* Moves a manifold built in a's frame shifted to origin into the world frame, keeping only the
 * points within the speculative distance (farther ones are not contacts; with none left the
 * manifold is wholly empty). The anchor on b is the anchor on a plus the difference of the
 * origins, exact to float precision even when both bodies are far from the world origin. */
KG_FN kg_manifold kg_manifold_to_world(kg_manifold built, kg_xf xfa, kg_vec2 origin, kg_xf xfb, float speculative_distance)
{
    kg_manifold m = kg_empty_manifold();
    kg_vec2 a_to_b = kg_sub(xfa.p, xfb.p);
    for (int i = 0; i < built.point_count; ++i) {
        kg_manifold_point mp = built.points[i];
        if (mp.separation > speculative_distance) {
            continue;
        }
        mp.anchor_a = kg_rotate(xfa.q, kg_add(mp.point, origin));
        mp.anchor_b = kg_add(mp.anchor_a, a_to_b);
        mp.point = kg_add(xfa.p, mp.anchor_a);
        m.points[m.point_count++] = mp;
    }
    if (m.point_count > 0) {
        m.normal = kg_rotate(xfa.q, built.normal);
    }
    return m;
}

/* The manifold of (b, a) from that of (a, b): the normal turns round, anchors and the two
 * bytes of each feature id trade places. */
KG_FN kg_manifold kg_flip_manifold(kg_manifold m)
{
    m.normal = kg_neg(m.normal);
    for (int i = 0; i < m.point_count; ++i) {
        kg_manifold_point* mp = m.points + i;
        kg_vec2 anchor = mp->anchor_a;
        mp->anchor_a = mp->anchor_b;
        mp->anchor_b = anchor;
        mp->id = KG_FEATURE_ID(mp->id & 0xFFu, mp->id >> 8);
    }
    return m;
}

/* What a polygon moved into another frame keeps as it is: its centroid (not moved), radius
 * and chain flags; the count is clamped so every loop below stays within the arrays.
 * Field by field, the vertices past the count not written: returned by value, or copied
 * whole and then moved, the shape was copied more than once (the smash's narrowphase
 * spent 7% of its instructions copying shapes). */
KG_FN void kg_polygon_fields(kg_shape* out, const kg_shape* polygon)
{
    out->centroid = polygon->centroid;
    out->radius = polygon->radius;
    out->chain = polygon->chain;
    out->parallelogram = polygon->parallelogram;
    out->count = polygon->count < KG_MAX_VERTS ? polygon->count : KG_MAX_VERTS;
}

/* A polygon's vertices moved by xf into *out (after kg_polygon_fields); its normals turned
 * by kg_polygon_normals_in_frame, apart, as the first separating axis test reads only the
 * vertices of the polygon it tests against, and most pairs of a scattering crowd end
 * there. */
KG_FN void kg_polygon_vertices_in_frame(kg_shape* out, const kg_shape* polygon, kg_xf xf)
{
    for (int i = 0; i < out->count; ++i) {
        out->vertices[i] = kg_xf_point(xf, polygon->vertices[i]);
    }
}

KG_FN void kg_polygon_normals_in_frame(kg_shape* out, const kg_shape* polygon, kg_rot q)
{
    for (int i = 0; i < out->count; ++i) {
        out->normals[i] = kg_rotate(q, polygon->normals[i]);
    }
}

/* A polygon moved by xf, into *out. */
KG_FN void kg_polygon_in_frame(kg_shape* out, const kg_shape* polygon, kg_xf xf)
{
    kg_polygon_fields(out, polygon);
    kg_polygon_vertices_in_frame(out, polygon, xf);
    kg_polygon_normals_in_frame(out, polygon, xf.q);
}

/* A body's shape moved by xf into *out, its centroid with it (the one-sided tests of chain
 * segments and tiles read it). */
KG_FN void kg_shape_in_frame(kg_shape* out, const kg_shape* shape, kg_xf xf)
{
    kg_polygon_in_frame(out, shape, xf);
    out->centroid = kg_xf_point(xf, shape->centroid);
}

/* A polygon moved by shift, not turned, into *out: its normals as they are. */
KG_FN void kg_polygon_shifted(kg_shape* out, const kg_shape* polygon, kg_vec2 shift)
{
    kg_polygon_fields(out, polygon);
    for (int i = 0; i < out->count; ++i) {
        out->vertices[i] = kg_add(polygon->vertices[i], shift);
        out->normals[i] = polygon->normals[i];
    }
}

KG_FN kg_xf kg_translation(kg_vec2 p)
{
    kg_xf xf;
    xf.p = p;
    xf.q = kg_rot_identity();
    return xf;
}

/* ---- polygon against polygon ---- */

/* The largest separation of poly2 from poly1 along poly1's edge normals (the separating axis
 * test); *edge gets the index of that normal. Negative: the polygons overlap along every one.
 * The first separation past reach is returned as it is found: the pair is apart, and which
 * axis shows it most does not matter (most pairs of a scattering crowd stop there). */
KG_FN float kg_max_separation(const kg_shape* poly1, const kg_shape* poly2, float reach, int* edge)
{
    float best = -KG_FLT_MAX;
    *edge = 0;
    for (int i = 0; i < poly1->count; ++i) {
        kg_vec2 n = poly1->normals[i];
        kg_vec2 v = poly1->vertices[i];
        float deepest = KG_FLT_MAX;
        for (int j = 0; j < poly2->count; ++j) {
            deepest = kg_minf(deepest, kg_dot(n, kg_sub(poly2->vertices[j], v)));
        }
        if (deepest > best) {
            best = deepest;
            *edge = i;
        }
        if (best > reach) {
            break;
        }
    }
    return best;
}

/* kg_max_separation of two parallelograms (kg_shape.parallelogram), without trying every
 * vertex against every axis: poly2's vertices pair off through its centre, so it spans the
 * centre's projection on an axis plus or minus the larger of its two half-diagonals' (|n.h0|
 * and |n.h1|), and each axis n of poly1 serves two faces, its own and the one across, whose
 * normal is -n. (The smash and the tumbler: 2.5 times fewer instructions than the search.) */
KG_FN float kg_parallelogram_separation(const kg_shape* poly1, const kg_shape* poly2, int* edge)
{
    kg_vec2 center = kg_scale(0.5f, kg_add(poly2->vertices[0], poly2->vertices[2]));
    kg_vec2 h0 = kg_sub(poly2->vertices[0], center);
    kg_vec2 h1 = kg_sub(poly2->vertices[1], center);
    float separation[4];
    for (int i = 0; i < 2; ++i) {
        kg_vec2 n = poly1->normals[i];
        float mid = kg_dot(n, center);
        float spread = kg_maxf(fabsf(kg_dot(n, h0)), fabsf(kg_dot(n, h1)));
        separation[i] = (mid - spread) - kg_dot(n, poly1->vertices[i]);
        separation[i + 2] = kg_dot(n, poly1->vertices[i + 2]) - (mid + spread);
    }
    float best = separation[0];
    *edge = 0;
    for (int i = 1; i < 4; ++i) {
        if (separation[i] > best) {
            best = separation[i];
            *edge = i;
        }
    }
    return best;
}

/* The reference face (on ref) and the incident edge (on inc) of a polygon pair. ref is b when
 * flip is set; the manifold's normal then points against the reference normal. Positions
 * along the face are measured on the tangent from v11: the face spans [0, face_length], the
 * incident edge runs the other way, from upper (v21) down to lower (v22). */
typedef struct kg_face_contact {
    kg_vec2 v11, v12; /* reference face */
    kg_vec2 v21, v22; /* incident edge */
    kg_vec2 normal;   /* reference face normal */
    kg_vec2 tangent;  /* from v11 towards v12 */
    float face_length, upper, lower;
    int i11, i12, i21, i22;
    int flip;
} kg_face_contact;

KG_FN float kg_along_face(const kg_face_contact* fc, kg_vec2 p) { return kg_dot(kg_sub(p, fc->v11), fc->tangent); }

/* The edge of inc facing the reference face: among the edges turned against its normal that
 * reach between its side planes, the most anti-parallel, which holds inc's deepest point
 * between those planes; the most anti-parallel of all when none reaches (polygons meeting
 * corner first). The normal alone could pick a short edge wholly beside the face and lose
 * the contact. */
KG_FN void kg_set_incident_edge(kg_face_contact* fc, const kg_shape* inc)
{
    int best = 0, best_reaching = -1;
    float min_dot = KG_FLT_MAX, min_dot_reaching = KG_FLT_MAX;
    for (int i = 0; i < inc->count; ++i) {
        float d = kg_dot(fc->normal, inc->normals[i]);
        /* an edge turned against the normal runs against the tangent: upper end first */
        float upper = kg_along_face(fc, inc->vertices[i]);
        float lower = kg_along_face(fc, inc->vertices[kg_next_vertex(i, inc->count)]);
        if (d < min_dot) {
            min_dot = d;
            best = i;
        }
        if (d < 0.0f && upper >= 0.0f && lower <= fc->face_length && d < min_dot_reaching) {
            min_dot_reaching = d;
            best_reaching = i;
        }
    }
    fc->i21 = best_reaching >= 0 ? best_reaching : best;
    fc->i22 = kg_next_vertex(fc->i21, inc->count);
    fc->v21 = inc->vertices[fc->i21];
    fc->v22 = inc->vertices[fc->i22];
    fc->upper = kg_along_face(fc, fc->v21);
    fc->lower = kg_along_face(fc, fc->v22);
}

/* Reference face edge of ref against the polygon inc. */
KG_FN kg_face_contact kg_face_contact_of(const kg_shape* ref, int edge, const kg_shape* inc, int flip)
{
    kg_face_contact fc;
    fc.i11 = edge;
    fc.i12 = kg_next_vertex(edge, ref->count);
    fc.v11 = ref->vertices[fc.i11];
    fc.v12 = ref->vertices[fc.i12];
    fc.normal = ref->normals[edge];
    fc.tangent = kg_left_perp(fc.normal);
    fc.face_length = kg_along_face(&fc, fc.v12);
    fc.flip = flip;
    kg_set_incident_edge(&fc, inc);
    return fc;
}

/* A feature id with the reference's byte on the side of the shape that owns it. */
KG_FN kg_u32 kg_face_id(const kg_face_contact* fc, int ref_vertex, int inc_vertex)
{
    return fc->flip ? KG_FEATURE_ID(inc_vertex, ref_vertex) : KG_FEATURE_ID(ref_vertex, inc_vertex);
}

KG_FN kg_vec2 kg_face_manifold_normal(const kg_face_contact* fc, kg_vec2 ref_to_inc)
{
    return fc->flip ? kg_neg(ref_to_inc) : ref_to_inc;
}

/* One incident point v against the reference face: its separation along the face normal and
 * the point midway between v and the face, named by the face's end and the incident vertex
 * on its side. */
KG_FN void kg_push_face_point(kg_manifold* m, const kg_face_contact* fc, kg_vec2 v, int ref_vertex, int inc_vertex)
{
    float separation = kg_dot(kg_sub(v, fc->v11), fc->normal);
    kg_vec2 mid = kg_mul_sub(v, 0.5f * separation, fc->normal);
    kg_push_point(m, mid, separation, kg_face_id(fc, ref_vertex, inc_vertex));
}

/* Clips the incident edge to the side planes of the reference face (Sutherland-Hodgman on two
 * points) and keeps both clipped ends; none when the edge lies wholly beside the face. Each
 * point is named by the incident vertex it comes from and the face's end on the same side,
 * which stay the same whether or not it was clipped, so ids hold while an edge slides. */
KG_FN kg_manifold kg_clip_to_face(const kg_face_contact* fc)
{
    kg_manifold m = kg_empty_manifold();
    m.normal = kg_face_manifold_normal(fc, fc->normal);
    float span = fc->upper - fc->lower;
    float t_lower = 0.0f, t_upper = 1.0f;
    /* an incident edge (nearly) perpendicular to the face cannot be clipped along it; it is
     * kept whole, its deeper end giving the depth */
    if (span > KG_LENGTH_EPSILON) {
        t_lower = kg_maxf(-fc->lower / span, 0.0f);
        t_upper = kg_minf((fc->face_length - fc->lower) / span, 1.0f);
    }
    /* an unclipped edge wholly beside the face (a segment perpendicular to it) gives none */
    int beside = span <= KG_LENGTH_EPSILON && (fc->upper < 0.0f || fc->lower > fc->face_length);
    if (t_lower <= t_upper && !beside) {
        kg_push_face_point(&m, fc, kg_lerp(fc->v22, fc->v21, t_lower), fc->i11, fc->i22);
        kg_push_face_point(&m, fc, kg_lerp(fc->v22, fc->v21, t_upper), fc->i12, fc->i21);
    }
    return m;
}

/* Polygons touching corner to corner within the tolerance, too close for the direction
 * between the corners to be trusted: the incident edge's end nearest the face, measured
 * along the face normal, stands for the contact. */
KG_FN kg_manifold kg_nearest_end_to_face(const kg_face_contact* fc)
{
    kg_manifold m = kg_empty_manifold();
    m.normal = kg_face_manifold_normal(fc, fc->normal);
    int beyond_upper = fc->lower > fc->face_length;
    if (beyond_upper) {
        kg_push_face_point(&m, fc, fc->v22, fc->i12, fc->i22);
    } else {
        kg_push_face_point(&m, fc, fc->v21, fc->i11, fc->i21);
    }
    return m;
}

KG_FN float kg_min_separation(const kg_manifold* m)
{
    float s = KG_FLT_MAX;
    for (int i = 0; i < m->point_count; ++i) {
        s = kg_minf(s, m->points[i].separation);
    }
    return s;
}

/* The closest points of an end vertex of the reference face and the incident polygon. */
typedef struct kg_corner {
    kg_vec2 on_ref, on_inc;
    float distance;
    int ref_vertex, inc_vertex;
} kg_corner;

/* Keeps in *best the closer of itself and the pair (corner, nearest point of inc's edge i). */
KG_FN void kg_closer_corner(kg_corner* best, const kg_shape* inc, int i, kg_vec2 corner, int corner_index)
{
    int j = kg_next_vertex(i, inc->count);
    kg_vec2 edge = kg_sub(inc->vertices[j], inc->vertices[i]);
    float t = kg_clampf(kg_dot(kg_sub(corner, inc->vertices[i]), edge) / kg_length_sq(edge), 0.0f, 1.0f);
    kg_vec2 on_inc = kg_mul_add(inc->vertices[i], t, edge);
    float distance = kg_distance(corner, on_inc);
    if (distance < best->distance) {
        best->on_ref = corner;
        best->on_inc = on_inc;
        best->distance = distance;
        best->ref_vertex = corner_index;
        best->inc_vertex = t < 0.5f ? i : j;
    }
}

/* Separated polygons can meet corner first: when an end vertex of the reference face is
 * nearer the incident polygon than the clipped points are to the face (by more than the
 * tolerance, so nearly parallel faces keep their two points), or no part of the incident
 * edge lies over the face at all, the gap is measured from that corner to the polygon, with
 * one point along the line between them. The face normal alone would report a gap larger
 * than the true one and let the bodies run into each other. The whole incident polygon is
 * searched: its nearest point need not be on the incident edge. separation is the larger
 * of the two separating axis gaps. */
KG_FN kg_manifold kg_polygon_manifold(const kg_face_contact* fc, const kg_shape* inc, float separation)
{
    kg_manifold clipped = kg_clip_to_face(fc);
    if (separation <= KG_REFERENCE_TOLERANCE) {
        return clipped.point_count > 0 ? clipped : kg_nearest_end_to_face(fc);
    }
    /* no corner is nearer than the separating axis gap, a lower bound of the true gap */
    if (kg_min_separation(&clipped) - KG_REFERENCE_TOLERANCE <= separation) {
        return clipped;
    }
    kg_corner c;
    c.on_ref = fc->v11;
    c.on_inc = fc->v11;
    c.distance = KG_FLT_MAX;
    c.ref_vertex = 0;
    c.inc_vertex = 0;
    for (int i = 0; i < inc->count; ++i) {
        kg_closer_corner(&c, inc, i, fc->v11, fc->i11);
        kg_closer_corner(&c, inc, i, fc->v12, fc->i12);
    }
    if (c.distance >= kg_min_separation(&clipped) - KG_REFERENCE_TOLERANCE) {
        return clipped;
    }
    /* apart by more than KG_REFERENCE_TOLERANCE: the gap has a direction */
    kg_manifold m = kg_empty_manifold();
    m.normal = kg_face_manifold_normal(fc, kg_scale(1.0f / c.distance, kg_sub(c.on_inc, c.on_ref)));
    kg_push_point(&m, kg_lerp(c.on_ref, c.on_inc, 0.5f), c.distance, kg_face_id(fc, c.ref_vertex, c.inc_vertex));
    return m;
}

/* The closest points of segment [a1, a2] and segment [b1, b2] (Ericson 5.1.9), as the
 * parameters along each. */
KG_FN void kg_closest_on_segments(kg_vec2 a1, kg_vec2 a2, kg_vec2 b1, kg_vec2 b2, float* fa, float* fb)
{
    kg_vec2 d1 = kg_sub(a2, a1), d2 = kg_sub(b2, b1), r = kg_sub(a1, b1);
    float dd1 = kg_dot(d1, d1), dd2 = kg_dot(d2, d2), d12 = kg_dot(d1, d2);
    float rd1 = kg_dot(r, d1), rd2 = kg_dot(r, d2);
    float denominator = dd1 * dd2 - d12 * d12;
    float s = denominator > 0.0f ? kg_clampf((d12 * rd2 - rd1 * dd2) / denominator, 0.0f, 1.0f) : 0.0f;
    float t = (d12 * s + rd2) / dd2;
    if (t < 0.0f) {
        t = 0.0f;
        s = kg_clampf(-rd1 / dd1, 0.0f, 1.0f);
    } else if (t > 1.0f) {
        t = 1.0f;
        s = kg_clampf((d12 - rd1) / dd1, 0.0f, 1.0f);
    }
    *fa = s;
    *fb = t;
}

/* The closest points of two disjoint cores, edge against edge, each named by the vertex of
 * its edge nearer to it: a's in on_ref and ref_vertex, b's in on_inc and inc_vertex. */
KG_FN kg_corner kg_closest_cores(const kg_shape* a, const kg_shape* b)
{
    kg_corner best;
    best.on_ref = a->vertices[0];
    best.on_inc = b->vertices[0];
    best.distance = KG_FLT_MAX;
    best.ref_vertex = 0;
    best.inc_vertex = 0;
    for (int i = 0; i < a->count; ++i) {
        int i2 = kg_next_vertex(i, a->count);
        for (int j = 0; j < b->count; ++j) {
            int j2 = kg_next_vertex(j, b->count);
            float fa, fb;
            kg_closest_on_segments(a->vertices[i], a->vertices[i2], b->vertices[j], b->vertices[j2], &fa, &fb);
            kg_vec2 on_a = kg_lerp(a->vertices[i], a->vertices[i2], fa);
            kg_vec2 on_b = kg_lerp(b->vertices[j], b->vertices[j2], fb);
            float distance = kg_distance(on_a, on_b);
            if (distance < best.distance) {
                best.on_ref = on_a;
                best.on_inc = on_b;
                best.distance = distance;
                best.ref_vertex = fa < 0.5f ? i : i2;
                best.inc_vertex = fb < 0.5f ? j : j2;
            }
        }
    }
    return best;
}

/* A 2-vertex core has no area, and the separating axes of its pair miss the axis along it:
 * two segments in a line, end to end, look touching along their normals however far apart
 * they are. So a pair with one whose separating axis gap (separation) does not prove them
 * overlapping is checked against the cores' true distance: when they are apart and the
 * manifold's nearest point is not at that distance, the closest points make one point along
 * the line between them. (Polygons keep the separating axes alone.) */
KG_FN kg_manifold kg_check_thin_cores(kg_manifold m, const kg_shape* a, const kg_shape* b, float separation)
{
    if (separation < -KG_REFERENCE_TOLERANCE) {
        return m;
    }
    kg_corner c = kg_closest_cores(a, b);
    if (c.distance <= KG_REFERENCE_TOLERANCE ||
        (m.point_count > 0 && fabsf(kg_min_separation(&m) - c.distance) <= KG_REFERENCE_TOLERANCE)) {
        return m;
    }
    kg_manifold one = kg_empty_manifold();
    one.normal = kg_scale(1.0f / c.distance, kg_sub(c.on_inc, c.on_ref));
    kg_push_point(&one, kg_lerp(c.on_ref, c.on_inc, 0.5f), c.distance, KG_FEATURE_ID(c.ref_vertex, c.inc_vertex));
    return one;
}

/* From the manifold of the cores to that of the shapes a rounded by radius_a and b by
 * radius_b: the surfaces move out along the normal, a's by radius_a, b's back by radius_b. */
KG_FN void kg_round_manifold(kg_manifold* m, float radius_a, float radius_b)
{
    if (radius_a + radius_b > 0.0f) {
        for (int i = 0; i < m->point_count; ++i) {
            kg_manifold_point* mp = m->points + i;
            mp->point = kg_mul_add(mp->point, 0.5f * (radius_a - radius_b), m->normal);
            mp->separation -= radius_a + radius_b;
        }
    }
}

KG_FN kg_manifold kg_collide_polygons(const kg_shape* a, kg_xf xfa, const kg_shape* b, kg_xf xfb, float speculative_distance)
{
    kg_vec2 origin = a->vertices[0];
    kg_shape poly_a, poly_b;
    kg_polygon_shifted(&poly_a, a, kg_neg(origin));
    kg_xf b_in_a = kg_relative_xf(xfa, origin, xfb);
    kg_polygon_fields(&poly_b, b);
    kg_polygon_vertices_in_frame(&poly_b, b, b_in_a);
    float reach = speculative_distance + (a->radius + b->radius);

    int edge_a, edge_b;
    int parallelograms = a->parallelogram && b->parallelogram;
    float separation_a = parallelograms ? kg_parallelogram_separation(&poly_a, &poly_b, &edge_a)
                                        : kg_max_separation(&poly_a, &poly_b, reach, &edge_a);
    if (separation_a > reach) { /* apart along one of a's normals: b's need not be tried */
        return kg_empty_manifold();
    }
    kg_polygon_normals_in_frame(&poly_b, b, b_in_a.q);
    float separation_b = parallelograms ? kg_parallelogram_separation(&poly_b, &poly_a, &edge_b)
                                        : kg_max_separation(&poly_b, &poly_a, reach, &edge_b);
    if (separation_b > reach) {
        return kg_empty_manifold();
    }

    int flip = separation_b > separation_a + KG_REFERENCE_TOLERANCE;
    const kg_shape* ref = flip ? &poly_b : &poly_a;
    const kg_shape* inc = flip ? &poly_a : &poly_b;
    kg_face_contact fc = kg_face_contact_of(ref, flip ? edge_b : edge_a, inc, flip);

    float separation = kg_maxf(separation_a, separation_b);
    kg_manifold m = kg_polygon_manifold(&fc, inc, separation);
    if (poly_a.count == 2 || poly_b.count == 2) {
        m = kg_check_thin_cores(m, &poly_a, &poly_b, separation);
    }
    kg_round_manifold(&m, a->radius, b->radius);
    return kg_manifold_to_world(m, xfa, origin, xfb, speculative_distance);
}

/* ---- circles and points ---- */

/* Polygon a (its core, then rounded) against circle b. The circle's centre is tested against
 * a's faces; outside a corner's Voronoi region the face normal is the contact normal (this
 * also covers a centre inside the polygon), inside it the direction from the corner to the
 * centre. */
KG_FN kg_manifold kg_collide_polygon_circle(const kg_shape* a, kg_xf xfa, const kg_shape* b, kg_xf xfb,
                                            float speculative_distance)
{
    kg_vec2 origin = a->vertices[0];
    kg_shape poly;
    kg_polygon_shifted(&poly, a, kg_neg(origin));
    kg_vec2 center = kg_xf_point(kg_relative_xf(xfa, origin, xfb), b->vertices[0]);
    float radius = b->radius;
    float reach = radius + a->radius;

    int edge = 0;
    float separation = -KG_FLT_MAX;
    for (int i = 0; i < poly.count; ++i) {
        float s = kg_dot(poly.normals[i], kg_sub(center, poly.vertices[i]));
        if (s > separation) {
            separation = s;
            edge = i;
        }
    }
    if (separation > reach + speculative_distance) {
        return kg_empty_manifold();
    }

    kg_vec2 v1 = poly.vertices[edge];
    kg_vec2 v2 = poly.vertices[kg_next_vertex(edge, poly.count)];
    int before_v1 = kg_dot(kg_sub(center, v1), kg_sub(v2, v1)) < 0.0f;
    int after_v2 = kg_dot(kg_sub(center, v2), kg_sub(v1, v2)) < 0.0f;
    kg_vec2 normal = poly.normals[edge];
    kg_vec2 on_polygon = kg_mul_sub(center, separation, normal);
    /* a centre within epsilon of the polygon takes the face normal: no direction can be
     * taken from a corner it (nearly) sits on. A 2-vertex core's faces are one line, which a
     * centre beyond an end, in line with it, is on: there the distance to the end decides. */
    kg_vec2 corner = before_v1 ? v1 : v2;
    int off_corner = separation > KG_LENGTH_EPSILON || (poly.count == 2 && kg_distance(center, corner) > KG_LENGTH_EPSILON);
    if ((before_v1 || after_v2) && off_corner) {
        on_polygon = corner;
        kg_vec2 offset = kg_sub(center, on_polygon);
        separation = kg_length(offset);
        normal = kg_scale(1.0f / separation, offset);
    }

    kg_manifold m = kg_empty_manifold();
    m.normal = normal;
    kg_vec2 on_circle = kg_mul_sub(center, radius, normal);
    kg_push_point(&m, kg_lerp(on_polygon, on_circle, 0.5f), separation - radius, 0u);
    kg_round_manifold(&m, a->radius, 0.0f);
    return kg_manifold_to_world(m, xfa, origin, xfb, speculative_distance);
}

/* Circle (or point) against circle (or point). Coincident centres have no direction between
 * them; a's local y axis is used, any unit vector being as right as another. */
KG_FN kg_manifold kg_collide_circles(const kg_shape* a, kg_xf xfa, const kg_shape* b, kg_xf xfb, float speculative_distance)
{
    kg_vec2 origin = a->vertices[0];
    kg_vec2 center_b = kg_xf_point(kg_relative_xf(xfa, origin, xfb), b->vertices[0]);
    float distance = kg_length(center_b);
    float separation = distance - a->radius - b->radius;
    if (separation > speculative_distance) {
        return kg_empty_manifold();
    }
    kg_vec2 normal = distance > KG_LENGTH_EPSILON ? kg_scale(1.0f / distance, center_b) : kg_v2(0.0f, 1.0f);
    kg_vec2 on_a = kg_scale(a->radius, normal);
    kg_vec2 on_b = kg_mul_sub(center_b, b->radius, normal);

    kg_manifold m = kg_empty_manifold();
    m.normal = normal;
    kg_push_point(&m, kg_lerp(on_a, on_b, 0.5f), separation, 0u);
    return kg_manifold_to_world(m, xfa, origin, xfb, speculative_distance);
}

/* ---- dispatch ---- */

/* The contact manifold of convex shapes a and b (in their bodies' frames) with the bodies at
 * xfa and xfb: normal from a to b, up to two points with separation <= speculative_distance.
 * A shape with 2 or more vertices is a (rounded) polygon, any other a circle (a point when its
 * radius is 0). Chain segments, one-sided, go through collide/chain.h's kg_collide_shapes. */
KG_FN kg_manifold kg_collide_convex(const kg_shape* a, kg_xf xfa, const kg_shape* b, kg_xf xfb, float speculative_distance)
{
    int a_is_polygon = a->count >= 2;
    int b_is_polygon = b->count >= 2;
    if (a_is_polygon && b_is_polygon) {
        return kg_collide_polygons(a, xfa, b, xfb, speculative_distance);
    }
    if (a_is_polygon) {
        return kg_collide_polygon_circle(a, xfa, b, xfb, speculative_distance);
    }
    if (b_is_polygon) {
        return kg_flip_manifold(kg_collide_polygon_circle(b, xfb, a, xfa, speculative_distance));
    }
    return kg_collide_circles(a, xfa, b, xfb, speculative_distance);
}

#endif
