#include "collide/shape.h"
#include "core/error.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

kg_shape_def kg_box_shape(float width, float height)
{
    return kg_offset_box_shape(width, height, kg_v2(0.0f, 0.0f), 0.0f);
}

kg_shape_def kg_offset_box_shape(float width, float height, kg_vec2 center, float angle)
{
    kg_shape_def def;
    memset(&def, 0, sizeof def);
    def.type = KG_SHAPE_POLYGON;
    /* a box of no or negative size has no vertices, which making it refuses: its corners'
     * hull would otherwise quietly turn (-1, -1) into a 1 x 1 box (a size not finite keeps
     * its corners, refused as not finite) */
    int finite = isfinite(width) && isfinite(height);
    def.count = finite && (width <= 0.0f || height <= 0.0f) ? 0 : 4;
    float hx = 0.5f * width, hy = 0.5f * height;
    kg_rot q = {cosf(angle), sinf(angle)};
    kg_vec2 corners[4] = {{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}};
    for (int i = 0; i < 4; ++i) {
        def.vertices[i] = kg_add(center, kg_rotate(q, corners[i]));
    }
    return def;
}

kg_shape_def kg_circle_shape(float radius)
{
    kg_shape_def def;
    memset(&def, 0, sizeof def);
    def.type = KG_SHAPE_CIRCLE;
    def.radius = radius;
    return def;
}

kg_shape_def kg_polygon_shape(const kg_vec2* vertices, int count)
{
    kg_shape_def def;
    memset(&def, 0, sizeof def);
    def.type = KG_SHAPE_POLYGON;
    def.count = vertices ? count : 0; /* no vertices: refused when made, never read */
    for (int i = 0; vertices && i < count && i < KG_MAX_POLYGON_VERTICES; ++i) {
        def.vertices[i] = vertices[i];
    }
    return def;
}

kg_shape_def kg_capsule_shape(kg_vec2 center1, kg_vec2 center2, float radius)
{
    kg_shape_def def = kg_segment_shape(center1, center2);
    def.type = KG_SHAPE_CAPSULE;
    def.radius = radius;
    return def;
}

kg_shape_def kg_segment_shape(kg_vec2 point1, kg_vec2 point2)
{
    kg_shape_def def;
    memset(&def, 0, sizeof def);
    def.type = KG_SHAPE_SEGMENT;
    def.count = 2;
    def.vertices[0] = point1;
    def.vertices[1] = point2;
    return def;
}

static int kg_point_less(kg_vec2 p, kg_vec2 q) { return p.x < q.x || (p.x == q.x && p.y < q.y); }

/* Points welded: each closer than KG_WELD_DISTANCE to a kept one is dropped. Returns
 * how many are kept, sorted by x then y. */
static int kg_weld_sorted(const kg_vec2* in, int n, kg_vec2* pts)
{
    int m = 0;
    for (int i = 0; i < n; ++i) {
        int unique = 1;
        for (int j = 0; j < m && unique; ++j) {
            unique = kg_distance(in[i], pts[j]) >= KG_WELD_DISTANCE;
        }
        if (unique) {
            pts[m++] = in[i];
        }
    }
    for (int i = 1; i < m; ++i) {
        for (int j = i; j > 0 && kg_point_less(pts[j], pts[j - 1]); --j) {
            kg_vec2 t = pts[j];
            pts[j] = pts[j - 1];
            pts[j - 1] = t;
        }
    }
    return m;
}

/* Andrew's monotone chain: lower hull left to right, upper hull back, dropping every
 * point that does not turn left. It cannot cycle, whatever duplicates or collinear
 * runs it is given (gift wrapping could). */
/* In double: a float orientation test can call a slightly reflex vertex convex. */
static int kg_turns_left(kg_vec2 a, kg_vec2 b, kg_vec2 p)
{
    double cross = ((double)b.x - a.x) * ((double)p.y - a.y) - ((double)b.y - a.y) * ((double)p.x - a.x);
    return cross > 0.0;
}

static int kg_monotone_chain(const kg_vec2* pts, int m, kg_vec2* out)
{
    kg_vec2 hull[2 * KG_MAX_VERTS];
    int k = 0;
    for (int i = 0; i < m; ++i) {
        while (k >= 2 && !kg_turns_left(hull[k - 2], hull[k - 1], pts[i])) {
            k--;
        }
        hull[k++] = pts[i];
    }
    int lower = k + 1;
    for (int i = m - 2; i >= 0; --i) {
        while (k >= lower && !kg_turns_left(hull[k - 2], hull[k - 1], pts[i])) {
            k--;
        }
        hull[k++] = pts[i];
    }
    k--; /* the last point is the first again */
    for (int i = 0; i < k; ++i) {
        out[i] = hull[i];
    }
    return k;
}

/* Drops, one at a time and against its current neighbours, each vertex that lies within
 * half the weld distance of the line through them: removing one changes the lines its
 * neighbours are measured against. */
static int kg_drop_collinear(kg_vec2* v, int count)
{
    int removed = 1;
    while (removed && count >= 3) {
        removed = 0;
        for (int i = 0; i < count && !removed; ++i) {
            kg_vec2 prev = v[(i + count - 1) % count], next = v[(i + 1) % count];
            kg_vec2 edge = kg_sub(next, prev);
            float len = kg_length(edge);
            float dist = len > 0.0f ? kg_cross(edge, kg_sub(v[i], prev)) / len : 0.0f;
            if (fabsf(dist) <= 0.5f * KG_WELD_DISTANCE) {
                memmove(&v[i], &v[i + 1], (size_t)(count - i - 1) * sizeof *v);
                count--;
                removed = 1;
            }
        }
    }
    return count;
}

/* Counter-clockwise hull with welded duplicates and collinear points removed; returns
 * its vertex count (< 3 means no area). */
static int kg_convex_hull(const kg_vec2* in, int n, kg_vec2* out)
{
    kg_vec2 pts[KG_MAX_VERTS];
    int m = kg_weld_sorted(in, n, pts);
    if (m < 3) {
        return m;
    }
    return kg_drop_collinear(out, kg_monotone_chain(pts, m, out));
}

static float kg_polygon_area(const kg_vec2* v, int n)
{
    float area = 0.0f;
    for (int i = 0; i < n; ++i) {
        area += kg_cross(v[i], v[(i + 1) % n]);
    }
    return 0.5f * area;
}

static int kg_finite_vec(kg_vec2 v) { return isfinite(v.x) && isfinite(v.y); }

static kg_result kg_build_circle(const kg_shape_def* def, kg_shape* out)
{
    if (!kg_finite_vec(def->center) || !isfinite(def->radius) || !(def->radius > 0.0f)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "circle needs a finite centre and a radius > 0 (got %g)",
                       (double)def->radius);
    }
    out->count = 1;
    out->radius = def->radius;
    out->vertices[0] = def->center;
    out->centroid = def->center;
    return KG_OK;
}

/* Whether polygon s is a parallelogram, as kg_shape.parallelogram means it: four vertices,
 * each edge's normal exactly the opposite of the one across (a box; one turned by an angle
 * may miss by a rounding and take the general test). */
static kg_u32 kg_is_parallelogram(const kg_shape* s)
{
    return s->count == 4 && s->normals[2].x == -s->normals[0].x && s->normals[2].y == -s->normals[0].y &&
           s->normals[3].x == -s->normals[1].x && s->normals[3].y == -s->normals[1].y;
}

static kg_result kg_build_polygon(const kg_shape_def* def, kg_shape* out)
{
    if (def->count == 0) {
        return kg_fail(KG_ERROR_DEGENERATE_SHAPE, "polygon has no vertices (a box whose width or height is not > 0, "
                                                  "or kg_polygon_shape given NULL)");
    }
    if (def->count < 3 || def->count > KG_MAX_POLYGON_VERTICES) {
        return kg_fail(KG_ERROR_DEGENERATE_SHAPE, "polygon needs 3 to %d vertices (got %d)",
                       KG_MAX_POLYGON_VERTICES, def->count);
    }
    for (int i = 0; i < def->count; ++i) {
        if (!kg_finite_vec(def->vertices[i])) {
            return kg_fail(KG_ERROR_INVALID_ARGUMENT, "polygon vertex %d is not finite", i);
        }
    }
    kg_vec2 hull[KG_MAX_VERTS];
    int n = kg_convex_hull(def->vertices, def->count, hull);
    if (n < 3 || kg_polygon_area(hull, n) < KG_MIN_AREA) {
        return kg_fail(KG_ERROR_DEGENERATE_SHAPE, "polygon has no area (its points are collinear or coincide)");
    }
    out->count = n;
    out->radius = 0.0f;
    for (int i = 0; i < n; ++i) {
        out->vertices[i] = hull[i];
        out->normals[i] = kg_normalize(kg_right_perp(kg_sub(hull[(i + 1) % n], hull[i])));
        if (fabsf(kg_length(out->normals[i]) - 1.0f) > 1.0e-3f) {
            return kg_fail(KG_ERROR_DEGENERATE_SHAPE, "polygon too large: its edges overflow single precision");
        }
    }
    kg_mass_data md = kg_shape_mass_of(out, 1.0f);
    if (!kg_finite_vec(md.center) || !isfinite(md.mass) || !isfinite(md.inertia) || !(md.inertia > 0.0f)) {
        return kg_fail(KG_ERROR_DEGENERATE_SHAPE, "polygon too large or too thin: its mass properties overflow");
    }
    out->centroid = md.center;
    out->parallelogram = kg_is_parallelogram(out);
    return KG_OK;
}

/* A capsule or a segment: a 2-vertex polygon (its two edges the same segment, run both
 * ways, with opposite normals) and a radius, so the polygon narrowphase collides its core
 * and rounds the result (collide/manifold.h). */
static kg_result kg_build_two_point(const kg_shape_def* def, const char* kind, kg_shape* out)
{
    kg_vec2 p1 = def->vertices[0], p2 = def->vertices[1];
    if (!kg_finite_vec(p1) || !kg_finite_vec(p2)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s points must be finite", kind);
    }
    if (!(kg_distance(p1, p2) >= KG_WELD_DISTANCE)) {
        return kg_fail(KG_ERROR_DEGENERATE_SHAPE, "%s points coincide (closer than %g m)%s", kind,
                       (double)KG_WELD_DISTANCE, def->type == KG_SHAPE_CAPSULE ? ": use a circle" : "");
    }
    kg_vec2 normal = kg_normalize(kg_right_perp(kg_sub(p2, p1)));
    if (!isfinite(kg_length(kg_sub(p2, p1))) || fabsf(kg_length(normal) - 1.0f) > 1.0e-3f) {
        return kg_fail(KG_ERROR_DEGENERATE_SHAPE, "%s too long: it overflows single precision", kind);
    }
    out->count = 2;
    out->radius = def->radius;
    out->vertices[0] = p1;
    out->vertices[1] = p2;
    out->normals[0] = normal;
    out->normals[1] = kg_neg(normal);
    out->centroid = kg_lerp(p1, p2, 0.5f);
    return KG_OK;
}

static kg_result kg_build_capsule(const kg_shape_def* def, kg_shape* out)
{
    if (!isfinite(def->radius) || !(def->radius > 0.0f)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "capsule needs a finite radius > 0 (got %g)", (double)def->radius);
    }
    kg_result r = kg_build_two_point(def, "capsule", out);
    if (r != KG_OK) {
        return r;
    }
    kg_mass_data md = kg_shape_mass_of(out, 1.0f);
    if (!isfinite(md.mass) || !isfinite(md.inertia) || !(md.inertia > 0.0f)) {
        return kg_fail(KG_ERROR_DEGENERATE_SHAPE, "capsule too large: its mass properties overflow");
    }
    return KG_OK;
}

static kg_result kg_build_segment(const kg_shape_def* def, kg_shape* out)
{
    kg_shape_def thin = *def;
    thin.radius = 0.0f;
    return kg_build_two_point(&thin, "segment", out);
}

/* Segment i of a chain, points i and i + 1 (the first again after the last). */
static kg_shape_def kg_chain_segment_def(const kg_vec2* points, int count, int i)
{
    return kg_segment_shape(points[i], points[(i + 1) % count]);
}

kg_result kg_check_chain_points(const kg_vec2* points, int count, int loop)
{
    int least = loop ? 3 : 2;
    if (!points || count < least) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "a chain%s needs at least %d points (got %d)", loop ? " loop" : "",
                       least, points ? count : 0);
    }
    for (int i = 0; i < count; ++i) {
        if (!kg_finite_vec(points[i])) {
            return kg_fail(KG_ERROR_INVALID_ARGUMENT, "chain point %d is not finite", i);
        }
    }
    int segments = loop ? count : count - 1;
    for (int i = 0; i < segments; ++i) {
        kg_shape segment;
        kg_shape_def def = kg_chain_segment_def(points, count, i);
        if (kg_build_segment(&def, &segment) != KG_OK) {
            char why[160];
            snprintf(why, sizeof why, "%s", kg_last_error());
            return kg_fail(KG_ERROR_DEGENERATE_SHAPE, "chain segment %d (points %d and %d): %s", i, i,
                           (i + 1) % count, why);
        }
    }
    return KG_OK;
}

kg_shape kg_chain_segment_build(const kg_vec2* points, int count, int loop, int i)
{
    kg_shape s;
    memset(&s, 0, sizeof s);
    kg_shape_def def = kg_chain_segment_def(points, count, i);
    kg_build_segment(&def, &s);
    s.chain = KG_CHAIN_SEGMENT;
    if (loop || i > 0) {
        s.vertices[2] = points[(i + count - 1) % count];
        s.chain |= KG_CHAIN_GHOST1;
    }
    if (loop || i + 2 < count) {
        s.vertices[3] = points[(i + 2) % count];
        s.chain |= KG_CHAIN_GHOST2;
    }
    return s;
}

kg_result kg_shape_build(const kg_shape_def* def, kg_shape* out)
{
    memset(out, 0, sizeof *out);
    switch (def->type) {
    case KG_SHAPE_NONE:
        out->count = 1; /* a point */
        return KG_OK;
    case KG_SHAPE_CIRCLE:
        return kg_build_circle(def, out);
    case KG_SHAPE_POLYGON:
        return kg_build_polygon(def, out);
    case KG_SHAPE_CAPSULE:
        return kg_build_capsule(def, out);
    case KG_SHAPE_SEGMENT:
        return kg_build_segment(def, out);
    }
    return kg_fail(KG_ERROR_INVALID_ARGUMENT, "unknown shape type %d", (int)def->type);
}

kg_shape_def kg_shape_describe(const kg_shape* shape)
{
    if (shape->count >= 3) {
        return kg_polygon_shape(shape->vertices, shape->count);
    }
    if (shape->count == 2) {
        return shape->radius > 0.0f ? kg_capsule_shape(shape->vertices[0], shape->vertices[1], shape->radius)
                                    : kg_segment_shape(shape->vertices[0], shape->vertices[1]);
    }
    kg_shape_def def = kg_circle_shape(shape->radius);
    def.center = shape->vertices[0];
    if (shape->radius == 0.0f) {
        def.type = KG_SHAPE_NONE;
    }
    return def;
}

/* Polygon mass in two fans: the first, from a vertex, finds the area and centroid; the
 * second, from the centroid (inside a convex polygon), integrates the inertia about it
 * directly, so every triangle adds a non-negative term and slivers cannot come out
 * with a negative inertia through cancellation. */
static kg_mass_data kg_polygon_mass(const kg_shape* s, float density)
{
    kg_vec2 origin = s->vertices[0];
    float area = 0.0f;
    kg_vec2 center = kg_v2(0.0f, 0.0f);
    for (int i = 1; i < s->count - 1; ++i) {
        kg_vec2 e1 = kg_sub(s->vertices[i], origin);
        kg_vec2 e2 = kg_sub(s->vertices[i + 1], origin);
        float tri = 0.5f * kg_cross(e1, e2);
        area += tri;
        center = kg_mul_add(center, tri / 3.0f, kg_add(e1, e2));
    }
    kg_mass_data md;
    md.mass = density * area;
    md.center = kg_add(origin, kg_scale(1.0f / area, center));
    float inertia = 0.0f;
    for (int i = 0; i < s->count; ++i) {
        kg_vec2 e1 = kg_sub(s->vertices[i], md.center);
        kg_vec2 e2 = kg_sub(s->vertices[(i + 1) % s->count], md.center);
        float d = kg_cross(e1, e2);
        float intx2 = e1.x * e1.x + e2.x * e1.x + e2.x * e2.x;
        float inty2 = e1.y * e1.y + e2.y * e1.y + e2.y * e2.y;
        inertia += (0.25f / 3.0f) * d * (intx2 + inty2);
    }
    md.inertia = density * inertia;
    return md;
}

/* A capsule of core length L and radius r: a 2r by L rectangle and a disc split into two
 * half discs at the ends. Each half disc's inertia about the capsule's middle is its own
 * about its centroid (which lies 4r / (3 pi) out from its flat side) moved there by the
 * parallel axis theorem; both together come to m_disc (r^2 / 2 + L^2 / 4 + L 4r / (3 pi)).
 * A segment (r = 0) has no area and no mass. */
static kg_mass_data kg_capsule_mass(const kg_shape* s, float density)
{
    float r = s->radius, length = kg_distance(s->vertices[0], s->vertices[1]);
    float box_mass = density * 2.0f * r * length;
    float disc_mass = density * 3.14159265358979f * r * r;
    float half_disc_offset = 4.0f * r / (3.0f * 3.14159265358979f);
    kg_mass_data md;
    md.mass = box_mass + disc_mass;
    md.center = s->centroid;
    md.inertia = box_mass * (length * length + 4.0f * r * r) / 12.0f +
                 disc_mass * (0.5f * r * r + 0.25f * length * length + length * half_disc_offset);
    return md;
}

kg_mass_data kg_shape_mass_of(const kg_shape* shape, float density)
{
    if (shape->count >= 3) {
        return kg_polygon_mass(shape, density);
    }
    if (shape->count == 2) {
        return kg_capsule_mass(shape, density);
    }
    kg_mass_data md;
    float r2 = shape->radius * shape->radius;
    md.mass = density * 3.14159265358979f * r2;
    md.center = shape->vertices[0];
    md.inertia = 0.5f * md.mass * r2;
    return md;
}

kg_result kg_shape_mass(const kg_shape_def* def, float density, kg_mass_data* out)
{
    if (!out || !def) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_shape_mass: NULL argument");
    }
    if (!isfinite(density) || density <= 0.0f) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "density must be finite and > 0 (got %g)", (double)density);
    }
    kg_shape shape;
    kg_result r = kg_shape_build(def, &shape);
    if (r != KG_OK) {
        return r;
    }
    if (def->type == KG_SHAPE_SEGMENT) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "a segment has no area: a density gives it no mass");
    }
    *out = kg_shape_mass_of(&shape, density);
    if (!isfinite(out->mass) || !isfinite(out->inertia) || !(out->mass > 0.0f) || !(out->inertia >= 0.0f)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT,
                       "mass properties of this shape at density %g are not representable (mass %g, inertia %g)",
                       (double)density, (double)out->mass, (double)out->inertia);
    }
    return KG_OK;
}
