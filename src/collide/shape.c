#include "collide/shape.h"
#include "core/error.h"

#include <math.h>
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
    def.count = 4;
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
    def.count = count;
    for (int i = 0; i < count && i < KG_MAX_POLYGON_VERTICES; ++i) {
        def.vertices[i] = vertices[i];
    }
    return def;
}

/* Gift-wrapping hull, counter-clockwise, with welded duplicates and collinear points
 * removed. Returns the hull's vertex count (< 3 means no area). */
static int kg_convex_hull(const kg_vec2* in, int n, kg_vec2* out)
{
    kg_vec2 pts[KG_MAX_VERTS];
    int m = 0;
    for (int i = 0; i < n; ++i) {
        int unique = 1;
        for (int j = 0; j < m; ++j) {
            if (kg_distance(in[i], pts[j]) < KG_WELD_DISTANCE) {
                unique = 0;
                break;
            }
        }
        if (unique) {
            pts[m++] = in[i];
        }
    }
    if (m < 3) {
        return m;
    }
    int start = 0;
    for (int i = 1; i < m; ++i) {
        if (pts[i].x < pts[start].x || (pts[i].x == pts[start].x && pts[i].y < pts[start].y)) {
            start = i;
        }
    }
    int count = 0, current = start;
    do {
        out[count++] = pts[current];
        int next = current == 0 ? 1 : 0;
        for (int j = 0; j < m; ++j) {
            if (j == current) {
                continue;
            }
            float c = kg_cross(kg_sub(pts[next], pts[current]), kg_sub(pts[j], pts[current]));
            /* j lies to the right of current->next, or on the line but farther: wrap to it */
            if (c < 0.0f || (c == 0.0f && kg_length_sq(kg_sub(pts[j], pts[current])) >
                                              kg_length_sq(kg_sub(pts[next], pts[current])))) {
                next = j;
            }
        }
        current = next;
    } while (current != start && count < m);
    /* drop vertices that are (nearly) on the line through their neighbours */
    int kept = 0;
    kg_vec2 tmp[KG_MAX_VERTS];
    for (int i = 0; i < count; ++i) {
        kg_vec2 prev = out[(i + count - 1) % count], v = out[i], next = out[(i + 1) % count];
        kg_vec2 edge = kg_sub(next, prev);
        float len = kg_length(edge);
        float dist = len > 0.0f ? kg_cross(edge, kg_sub(v, prev)) / len : 0.0f;
        if (fabsf(dist) > 0.5f * KG_WELD_DISTANCE) {
            tmp[kept++] = v;
        }
    }
    memcpy(out, tmp, (size_t)kept * sizeof *tmp);
    return kept;
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

static kg_result kg_build_polygon(const kg_shape_def* def, kg_shape* out)
{
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
    }
    out->centroid = kg_shape_mass_of(out, 1.0f).center;
    return KG_OK;
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
    }
    return kg_fail(KG_ERROR_INVALID_ARGUMENT, "unknown shape type %d", (int)def->type);
}

kg_shape_def kg_shape_describe(const kg_shape* shape)
{
    if (shape->count >= 3) {
        return kg_polygon_shape(shape->vertices, shape->count);
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

kg_mass_data kg_shape_mass_of(const kg_shape* shape, float density)
{
    if (shape->count >= 3) {
        return kg_polygon_mass(shape, density);
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
    *out = kg_shape_mass_of(&shape, density);
    return KG_OK;
}
