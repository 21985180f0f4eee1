/* The narrow tests of the world queries (collide/query.c, public API kgyro/query.h): a ray
 * against one shape, whether a shape holds a point, and the same against a tile. Written
 * as shared code (kg_shared.h's rules: no libc beyond sqrtf and friends, no global
 * pointers but KG_GLOBAL ones) so that a kernel can answer queries with the same bits;
 * today the host answers them on both backends, from the state read back.
 *
 * Rays are segments: from origin along translation, fractions in [0, max_fraction] of it.
 * Every test works in the shape's own frame (the caller moves the ray there) and gives a
 * fraction computed from origin and translation alone: max_fraction only accepts or
 * refuses it, so a hit has the same bits whatever the ray was clipped to before.
 *
 * A ray that starts inside a shape (or on its surface, going in) does not hit it: it
 * finds the shapes it enters, as Box2D v3's ray casts do. */
#ifndef KG_RAYCAST_H
#define KG_RAYCAST_H

#include "collide/chain.h"
#include "collide/tile_collide.h"
#include "collide/toi.h"

typedef struct kg_ray {
    kg_vec2 origin;
    kg_vec2 translation;
    float max_fraction;
} kg_ray;

/* Where a ray enters a shape: the fraction of its translation, and the outward unit normal
 * of the surface there (shape frame). feature: the polygon edge it entered by (-1 for a
 * round part), which a tile needs to know whether that edge is exposed. */
typedef struct kg_ray_hit {
    kg_i32 hit;
    kg_i32 feature;
    float fraction;
    kg_vec2 normal;
} kg_ray_hit;

KG_FN kg_ray_hit kg_ray_miss(void)
{
    kg_ray_hit h;
    h.hit = 0;
    h.feature = -1;
    h.fraction = 0.0f;
    h.normal = kg_v2(0.0f, 0.0f);
    return h;
}

KG_FN kg_ray_hit kg_ray_hit_at(float fraction, kg_vec2 normal, int feature)
{
    kg_ray_hit h;
    h.hit = 1;
    h.feature = feature;
    h.fraction = fraction;
    h.normal = normal;
    return h;
}

/* The ray moved into a frame: xf is the frame's pose in the ray's. */
KG_FN kg_ray kg_ray_in_frame(kg_ray ray, kg_xf xf)
{
    kg_ray r = ray;
    r.origin = kg_xf_inv_point(xf, ray.origin);
    r.translation = kg_inv_rotate(xf.q, ray.translation);
    return r;
}

/* The disc of radius r round c. Solved along the unit direction, from the point of the
 * line nearest the centre, which keeps the square root well conditioned for short and
 * long rays alike (Box2D v3's way). */
KG_FN kg_ray_hit kg_ray_circle(kg_vec2 c, float r, kg_ray ray)
{
    float length = kg_length(ray.translation);
    if (!(length > 0.0f)) {
        return kg_ray_miss();
    }
    kg_vec2 s = kg_sub(ray.origin, c);
    kg_vec2 d = kg_scale(1.0f / length, ray.translation);
    float along = -kg_dot(s, d);
    kg_vec2 nearest = kg_mul_add(s, along, d);
    float rr = r * r, cc = kg_length_sq(nearest);
    if (cc > rr) {
        return kg_ray_miss();
    }
    float distance = along - sqrtf(rr - cc);
    if (distance < 0.0f || distance > ray.max_fraction * length) {
        return kg_ray_miss(); /* starts inside, or the circle is behind or beyond */
    }
    return kg_ray_hit_at(distance / length, kg_normalize(kg_mul_add(s, distance, d)), -1);
}

/* Segment p1 -> p2, no thickness. Two-sided (the normal faces the ray's origin) unless
 * one_sided: then only the side its right-hand normal faces is solid, as a chain's
 * segment, and a ray from behind passes through. */
KG_FN kg_ray_hit kg_ray_segment(kg_vec2 p1, kg_vec2 p2, int one_sided, kg_ray ray)
{
    kg_vec2 e = kg_sub(p2, p1);
    float length = kg_length(e);
    if (!(length > 0.0f)) {
        return kg_ray_miss();
    }
    kg_vec2 unit = kg_scale(1.0f / length, e);
    kg_vec2 normal = kg_right_perp(unit);
    float numerator = kg_dot(normal, kg_sub(p1, ray.origin));
    float denominator = kg_dot(normal, ray.translation);
    if (denominator == 0.0f || (one_sided && numerator > 0.0f)) {
        return kg_ray_miss();
    }
    float t = numerator / denominator;
    if (t < 0.0f || t > ray.max_fraction) {
        return kg_ray_miss();
    }
    float s = kg_dot(kg_sub(kg_mul_add(ray.origin, t, ray.translation), p1), unit);
    if (s < 0.0f || s > length) {
        return kg_ray_miss();
    }
    return kg_ray_hit_at(t, numerator > 0.0f ? kg_neg(normal) : normal, 0);
}

/* A convex polygon (counter-clockwise, unit outward normals, no radius): the ray is
 * clipped by each edge's half plane (Box2D's b2RayCastPolygon); it hits where it last
 * enters one before leaving any. A ray starting inside never enters, so never hits. */
KG_FN kg_ray_hit kg_ray_polygon(const kg_shape* shape, kg_ray ray)
{
    float lower = 0.0f, upper = ray.max_fraction;
    int index = -1;
    for (int i = 0; i < shape->count && i < KG_MAX_VERTS; ++i) {
        float numerator = kg_dot(shape->normals[i], kg_sub(shape->vertices[i], ray.origin));
        float denominator = kg_dot(shape->normals[i], ray.translation);
        if (denominator == 0.0f) {
            if (numerator < 0.0f) {
                return kg_ray_miss(); /* parallel to the edge, outside it */
            }
        } else if (denominator < 0.0f && numerator < lower * denominator) {
            lower = numerator / denominator; /* entering this half plane */
            index = i;
        } else if (denominator > 0.0f && numerator < upper * denominator) {
            upper = numerator / denominator; /* leaving it */
        }
        if (upper < lower) {
            return kg_ray_miss();
        }
    }
    return index >= 0 ? kg_ray_hit_at(lower, shape->normals[index], index) : kg_ray_miss();
}

/* The earlier of two hits (the first on a tie, so the order of the tests decides). */
KG_FN kg_ray_hit kg_ray_first(kg_ray_hit a, kg_ray_hit b)
{
    return b.hit && (!a.hit || b.fraction < a.fraction) ? b : a;
}

/* A capsule: the points within r of segment p1 -> p2. A ray from outside enters by one of
 * its two flat sides or one of its two end circles, whichever comes first; from inside
 * it hits nothing. */
KG_FN kg_ray_hit kg_ray_capsule(kg_vec2 p1, kg_vec2 p2, float r, kg_ray ray)
{
    if (kg_length_sq(kg_sub(ray.origin, kg_closest_on_segment(ray.origin, p1, p2))) < r * r) {
        return kg_ray_miss();
    }
    kg_vec2 side = kg_scale(r, kg_right_perp(kg_normalize(kg_sub(p2, p1))));
    kg_ray_hit h = kg_ray_segment(kg_add(p1, side), kg_add(p2, side), 1, ray);
    h = kg_ray_first(h, kg_ray_segment(kg_sub(p2, side), kg_sub(p1, side), 1, ray));
    h = kg_ray_first(h, kg_ray_circle(p1, r, ray));
    h = kg_ray_first(h, kg_ray_circle(p2, r, ray));
    h.feature = -1;
    return h;
}

/* Any collision shape (kg_layout.h): circle, capsule, segment (one-sided for a chain's),
 * polygon. A point (a particle's) has nothing to hit. */
KG_FN kg_ray_hit kg_ray_shape(const kg_shape* shape, kg_ray ray)
{
    if (shape->count == 1) {
        return shape->radius > 0.0f ? kg_ray_circle(shape->vertices[0], shape->radius, ray) : kg_ray_miss();
    }
    if (shape->count == 2) {
        if (shape->radius > 0.0f) {
            return kg_ray_capsule(shape->vertices[0], shape->vertices[1], shape->radius, ray);
        }
        return kg_ray_segment(shape->vertices[0], shape->vertices[1], kg_is_chain_segment(shape), ray);
    }
    return kg_ray_polygon(shape, ray);
}

/* 1 / translation per axis, 0 for an axis the ray barely moves along (so small that its
 * inverse would overflow): kg_ray_meets_box then only checks the origin's slab there,
 * which the margin of the boxes it is given covers. */
KG_FN kg_vec2 kg_ray_inverse(kg_vec2 translation)
{
    return kg_v2(fabsf(translation.x) > 1.0e-30f ? 1.0f / translation.x : 0.0f,
                 fabsf(translation.y) > 1.0e-30f ? 1.0f / translation.y : 0.0f);
}

/* One axis of the slab test: clips [*lower, *upper] to where the ray is within [lo, hi]. */
KG_FN int kg_ray_slab(float lo, float hi, float origin, float inverse, float* lower, float* upper)
{
    if (inverse == 0.0f) {
        return origin >= lo && origin <= hi;
    }
    float t1 = (lo - origin) * inverse, t2 = (hi - origin) * inverse;
    *lower = kg_maxf(*lower, kg_minf(t1, t2));
    *upper = kg_minf(*upper, kg_maxf(t1, t2));
    return 1;
}

/* Whether the ray meets box (touching counts) at a fraction within [0, max_fraction], for
 * the query index's nodes; inverse is kg_ray_inverse(translation). */
KG_FN int kg_ray_meets_box(kg_aabb box, kg_vec2 origin, kg_vec2 inverse, float max_fraction)
{
    float lower = 0.0f, upper = max_fraction;
    return kg_ray_slab(box.lower.x, box.upper.x, origin.x, inverse.x, &lower, &upper) &&
           kg_ray_slab(box.lower.y, box.upper.y, origin.y, inverse.y, &lower, &upper) && lower <= upper;
}

/* Whether a shape (its frame) holds point p, its surface included. Segments and points
 * have no area and hold nothing. */
KG_FN int kg_shape_holds_point(const kg_shape* shape, kg_vec2 p)
{
    if (shape->count == 1) {
        return kg_length_sq(kg_sub(p, shape->vertices[0])) <= shape->radius * shape->radius && shape->radius > 0.0f;
    }
    if (shape->count == 2) {
        kg_vec2 nearest = kg_closest_on_segment(p, shape->vertices[0], shape->vertices[1]);
        return kg_length_sq(kg_sub(p, nearest)) <= shape->radius * shape->radius && shape->radius > 0.0f;
    }
    for (int i = 0; i < shape->count && i < KG_MAX_VERTS; ++i) {
        if (kg_dot(shape->normals[i], kg_sub(p, shape->vertices[i])) > 0.0f) {
            return 0;
        }
    }
    return 1;
}

/* ---- tiles ---- */

/* A ray (cell frame) against a tile's shape, whose cell word says which polygon edges are
 * exposed. The ray must enter by an exposed edge: one covered by a solid neighbour is met
 * only by a ray coming out of that neighbour, which started inside the terrain (and so
 * hits none of it, as inside any shape). A one-way tile exposes its upward edges alone,
 * so a ray from below passes through it and one from above lands on it. */
KG_FN kg_ray_hit kg_ray_tile(KG_GLOBAL const kg_tile_proto* proto, kg_u32 word, kg_ray ray)
{
    KG_PRIVATE_VIEW(kg_shape, shape, proto->shape);
    if (shape->count == 1) {
        return kg_ray_circle(shape->vertices[0], shape->radius, ray);
    }
    if (shape->count < 3) {
        return kg_ray_miss();
    }
    kg_ray_hit h = kg_ray_polygon(shape, ray);
    return h.hit && kg_cell_collidable(word, h.feature) ? h : kg_ray_miss();
}

#endif
