/* Collision of one body with one tile of a tile map, shared by the CPU backend and the OpenCL
 * kernels (same rules as manifold.h: no global pointers, no libc beyond sqrtf and friends).
 * The data layout is described in collide/tilemap.h.
 *
 * Ghost collisions. A tile is not collided as a closed polygon: only its exposed edges
 * (those not covered by a solid neighbour, flagged per cell in the map) take part, each as
 * a one-sided segment that knows how the terrain goes on past its ends: flat or concave
 * (the neighbour's edge carries on), convex (a corner, with the next edge's normal), or
 * free (nothing follows: the end of a one-way platform). Contacts are then kept only with
 * normals inside the segment's Voronoi region, the idea of Box2D's chain segments and
 * ghost vertices ("Ghost collisions", Catto 2020), here with the ghosts read from the grid:
 *
 *  - A body that is separated from the segment is measured by its closest features; a
 *    normal that leaves the segment's region past a convex end is skipped (the neighbour
 *    edge owns it), one that points into a flat or concave end is snapped to the segment.
 *  - A body that touches or overlaps is measured by separating axes: the segment's normal,
 *    the body's face normals that are admissible, and the neighbours' normals at convex
 *    ends; when a neighbour's axis separates best, the neighbour makes the contact.
 *  - A corner's vertex region belongs to the edge that starts there (edges run
 *    counter-clockwise round the solid), so a circle rolling over a corner gets one contact.
 *  - A body whose centre is behind the segment gets nothing from it, unless its centre is
 *    inside this tile: it then leaves through the tile's nearest exposed edge (a fast body
 *    that sank deep, or a tile built on top of a body).
 *
 * All of it works in the cell frame: the cell's lower-left corner is the origin, metres. */
#ifndef KG_TILE_COLLIDE_H
#define KG_TILE_COLLIDE_H

#include "collide/manifold.h"

/* ---- data layout ---- */

/* A cell is one 32-bit word: the tile id, and per polygon edge whether it is exposed near
 * its start vertex and near its end vertex (edges and vertices counter-clockwise). */
#define KG_CELL_ID_MASK 0xFFFFu
#define KG_CELL_START_SHIFT 16u
#define KG_CELL_END_SHIFT 24u

KG_FN kg_u32 kg_cell_id(kg_u32 word) { return word & KG_CELL_ID_MASK; }

KG_FN int kg_cell_exposed_start(kg_u32 word, int edge)
{
    return (int)((word >> (KG_CELL_START_SHIFT + (kg_u32)edge)) & 1u);
}

KG_FN int kg_cell_exposed_end(kg_u32 word, int edge)
{
    return (int)((word >> (KG_CELL_END_SHIFT + (kg_u32)edge)) & 1u);
}

KG_FN int kg_cell_collidable(kg_u32 word, int edge)
{
    return kg_cell_exposed_start(word, edge) | kg_cell_exposed_end(word, edge);
}

/* proto flags */
#define KG_TILE_FLAG_ONE_WAY 0x1u

/* A tile id's shape, ready for collision in the cell frame: a convex counter-clockwise
 * polygon with unit normals, a circle (count 1), or nothing (count 0). */
typedef struct kg_tile_proto {
    kg_shape shape;
    kg_u32 flags;
    kg_u32 pad;
} kg_tile_proto;

KG_STATIC_ASSERT(sizeof(kg_tile_proto) == 160, tile_proto_size);

/* The tile being collided and its eight neighbours in the same layer, which tell how the
 * terrain goes on past its edges. cells[(dy + 1) * 3 + dx + 1]; proto NULL = outside the
 * map. A proto is read where it lies (a kernel reads the proto buffer): copying nine of
 * them per cell would cost more than the collision reads of them. */
typedef struct kg_tile_cell {
    KG_GLOBAL const kg_tile_proto* proto;
    kg_u32 word;
} kg_tile_cell;

typedef struct kg_tile_neighbourhood {
    kg_tile_cell cells[9];
    kg_vec2 tile_size;
} kg_tile_neighbourhood;

/* ---- tolerances ---- */

/* Points this close (relative to the tile size) are the same vertex. */
#define KG_TILE_WELD 1.0e-4f
/* Sine of the angle below which two edges are taken as flat (Box2D's value). */
#define KG_TILE_ANGLE_TOLERANCE 0.01f
/* A neighbour's axis or a body face must beat the segment by this much to be chosen, so
 * float noise cannot flip the choice (and the feature ids) from step to step. */
#define KG_TILE_AXIS_TOLERANCE KG_REFERENCE_TOLERANCE
/* Below this gap a body counts as touching and separating axes decide. */
#define KG_TILE_TOUCHING (0.1f * 0.005f)

/* ---- segments ---- */

typedef enum kg_segment_end {
    KG_END_FLAT = 0,   /* the terrain carries on straight or turns concave: snap to the segment */
    KG_END_CORNER = 1, /* the terrain turns convex into another exposed edge */
    KG_END_FREE = 2    /* nothing follows: a convex end with a virtual side at right angles */
} kg_segment_end;

/* An exposed edge as a one-sided segment (solid on its left, normal on its right). */
typedef struct kg_tile_segment {
    kg_vec2 p1, p2;
    kg_vec2 direction;   /* unit, from p1 to p2 */
    kg_vec2 normal;      /* unit, outwards */
    kg_vec2 normal0;     /* the terrain's normal just before p1 (corner or free end) */
    kg_vec2 normal2;     /* the terrain's normal just after p2 */
    float length;
    kg_i32 end1, end2;   /* kg_segment_end */
    kg_u32 vertex1, vertex2, edge; /* tile features, for the feature ids */
} kg_tile_segment;

KG_FN int kg_near_point(kg_vec2 a, kg_vec2 b, float tolerance)
{
    return fabsf(a.x - b.x) <= tolerance && fabsf(a.y - b.y) <= tolerance;
}

/* The cell offset (-1, 0 or 1) towards which a coordinate lies on the cell's border. */
KG_FN int kg_border_side(float v, float size, float tolerance)
{
    return v <= tolerance ? -1 : (v >= size - tolerance ? 1 : 0);
}

/* Searches the neighbour at offset (dx, dy) for an exposed edge that ends at v (want_end)
 * or starts at v; on success writes its direction and normal. */
KG_FN int kg_find_edge_in_cell(const kg_tile_neighbourhood* nb, int dx, int dy, kg_vec2 v, int want_end,
                               kg_vec2* direction, kg_vec2* normal)
{
    kg_tile_cell cell = nb->cells[(dy + 1) * 3 + dx + 1];
    if (cell.proto == 0 || cell.proto->shape.count < 3) {
        return 0;
    }
    KG_GLOBAL const kg_shape* s = &cell.proto->shape;
    kg_vec2 in_cell = kg_v2(v.x - (float)dx * nb->tile_size.x, v.y - (float)dy * nb->tile_size.y);
    float tolerance = KG_TILE_WELD * fmaxf(nb->tile_size.x, nb->tile_size.y);
    for (int j = 0; j < s->count && j < KG_MAX_VERTS; ++j) {
        int k = kg_next_vertex(j, s->count);
        int exposed = want_end ? kg_cell_exposed_end(cell.word, j) : kg_cell_exposed_start(cell.word, j);
        kg_vec2 end = want_end ? s->vertices[k] : s->vertices[j];
        if (exposed && kg_near_point(end, in_cell, tolerance)) {
            *direction = kg_normalize(kg_sub(s->vertices[k], s->vertices[j]));
            *normal = s->normals[j];
            return 1;
        }
    }
    return 0;
}

/* Searches the cells that share the border point v (the one across a side, or the three
 * round a corner) for the exposed edge that ends (want_end) or starts at v. */
KG_FN int kg_find_neighbour_edge(const kg_tile_neighbourhood* nb, kg_vec2 v, int want_end, kg_vec2* direction,
                                 kg_vec2* normal)
{
    float tolerance = KG_TILE_WELD * fmaxf(nb->tile_size.x, nb->tile_size.y);
    int dx = kg_border_side(v.x, nb->tile_size.x, tolerance);
    int dy = kg_border_side(v.y, nb->tile_size.y, tolerance);
    if (dx != 0 && kg_find_edge_in_cell(nb, dx, 0, v, want_end, direction, normal)) {
        return 1;
    }
    if (dy != 0 && kg_find_edge_in_cell(nb, 0, dy, v, want_end, direction, normal)) {
        return 1;
    }
    return dx != 0 && dy != 0 && kg_find_edge_in_cell(nb, dx, dy, v, want_end, direction, normal);
}

/* How the terrain goes on at one end of the segment: at the start (is_start) it looks for
 * the edge arriving there, at the end for the edge leaving. The tile's own neighbouring
 * edge comes first; tiles are convex, so that is always a corner. */
KG_FN kg_segment_end kg_segment_end_of(const kg_tile_neighbourhood* nb, const kg_tile_segment* s, int is_start,
                                       kg_vec2* ghost_normal)
{
    const kg_tile_cell centre = nb->cells[4];
    KG_GLOBAL const kg_shape* shape = &centre.proto->shape;
    int edge = (int)s->edge;
    int own = is_start ? (edge > 0 ? edge - 1 : shape->count - 1) : kg_next_vertex(edge, shape->count);
    int own_exposed = is_start ? kg_cell_exposed_end(centre.word, own) : kg_cell_exposed_start(centre.word, own);
    if (own_exposed) {
        *ghost_normal = shape->normals[own];
        return KG_END_CORNER;
    }
    kg_vec2 direction, normal;
    if (kg_find_neighbour_edge(nb, is_start ? s->p1 : s->p2, is_start, &direction, &normal)) {
        float turn = is_start ? kg_cross(direction, s->direction) : kg_cross(s->direction, direction);
        *ghost_normal = normal;
        return turn > KG_TILE_ANGLE_TOLERANCE ? KG_END_CORNER : KG_END_FLAT;
    }
    /* a free end: the virtual side goes straight down from it, at right angles */
    *ghost_normal = is_start ? kg_neg(s->direction) : s->direction;
    return KG_END_FREE;
}

/* Exposed edge `edge` of the centre tile as a segment with its two ends classified. */
KG_FN kg_tile_segment kg_tile_segment_of(const kg_tile_neighbourhood* nb, int edge)
{
    KG_GLOBAL const kg_shape* shape = &nb->cells[4].proto->shape;
    int next = kg_next_vertex(edge, shape->count);
    kg_tile_segment s;
    s.p1 = shape->vertices[edge];
    s.p2 = shape->vertices[next];
    s.length = kg_distance(s.p1, s.p2);
    s.direction = kg_scale(1.0f / s.length, kg_sub(s.p2, s.p1));
    s.normal = shape->normals[edge];
    s.vertex1 = (kg_u32)edge;
    s.vertex2 = (kg_u32)next;
    s.edge = (kg_u32)edge;
    s.normal0 = s.normal;
    s.normal2 = s.normal;
    s.end1 = (kg_i32)kg_segment_end_of(nb, &s, 1, &s.normal0);
    s.end2 = (kg_i32)kg_segment_end_of(nb, &s, 0, &s.normal2);
    if (s.end1 == KG_END_FLAT) {
        s.normal0 = s.normal;
    }
    if (s.end2 == KG_END_FLAT) {
        s.normal2 = s.normal;
    }
    return s;
}

/* ---- the Gauss map of a segment ---- */

typedef enum kg_normal_kind {
    KG_NORMAL_SKIP = 0,  /* past a convex end: the neighbour's */
    KG_NORMAL_ADMIT = 1, /* inside the segment's region */
    KG_NORMAL_SNAP = 2   /* into a flat or concave end: use the segment's normal */
} kg_normal_kind;

/* Classifies a contact normal n (from the tile to the body). */
KG_FN kg_normal_kind kg_classify_normal(const kg_tile_segment* s, kg_vec2 n)
{
    if (kg_dot(n, s->direction) <= 0.0f) {
        if (s->end1 == KG_END_FLAT) {
            return KG_NORMAL_SNAP;
        }
        return kg_cross(n, s->normal0) > KG_TILE_ANGLE_TOLERANCE ? KG_NORMAL_SKIP : KG_NORMAL_ADMIT;
    }
    if (s->end2 == KG_END_FLAT) {
        return KG_NORMAL_SNAP;
    }
    return kg_cross(s->normal2, n) > KG_TILE_ANGLE_TOLERANCE ? KG_NORMAL_SKIP : KG_NORMAL_ADMIT;
}

/* Whether the segment owns the vertex region at p1 (is_start) or p2: a corner belongs to
 * the edge that leaves it, a free end to its only edge. */
KG_FN int kg_owns_end(const kg_tile_segment* s, int is_start)
{
    return is_start ? s->end1 != KG_END_FLAT : s->end2 == KG_END_FREE;
}

/* ---- building manifolds (cell frame, normal from the tile to the body) ---- */

typedef struct kg_tile_hit {
    kg_manifold manifold; /* cell frame; normal from the tile to the body */
    float separation;     /* along the axis that made it: the best hit of a tile wins */
} kg_tile_hit;

KG_FN kg_tile_hit kg_tile_no_hit(void)
{
    kg_tile_hit hit;
    hit.manifold = kg_empty_manifold();
    hit.separation = KG_FLT_MAX;
    return hit;
}

/* Appends the point q of the incident surface against the reference plane (point on it
 * `plane`, unit normal n pointing at q): separation along n, point midway. */
KG_FN void kg_push_plane_point(kg_manifold* m, kg_vec2 q, kg_vec2 plane, kg_vec2 n, kg_u32 id, float speculative)
{
    float separation = kg_dot(kg_sub(q, plane), n);
    if (separation <= speculative) {
        kg_push_point(m, kg_mul_sub(q, 0.5f * separation, n), separation, id);
    }
}

/* Clips the incident edge b1 -> b2 to the reference edge r1 -> r2 (unit tangent along it,
 * unit normal n towards the incident side) and keeps the clipped ends within the
 * speculative distance. The ends keep their ids whether clipped or not. */
KG_FN void kg_clip_edge(kg_manifold* m, kg_vec2 r1, kg_vec2 r2, kg_vec2 n, kg_vec2 b1, kg_vec2 b2, kg_u32 id1,
                        kg_u32 id2, float speculative)
{
    kg_vec2 tangent = kg_left_perp(n);
    float length = kg_dot(kg_sub(r2, r1), tangent);
    float u1 = kg_dot(kg_sub(b1, r1), tangent);
    float u2 = kg_dot(kg_sub(b2, r1), tangent);
    float lo = fminf(u1, u2), hi = fmaxf(u1, u2);
    if (hi < 0.0f || lo > length) {
        return;
    }
    kg_vec2 q1 = b1, q2 = b2;
    float span = u2 - u1;
    if (fabsf(span) > KG_LENGTH_EPSILON) {
        q1 = kg_lerp(b1, b2, kg_clampf((kg_clampf(u1, 0.0f, length) - u1) / span, 0.0f, 1.0f));
        q2 = kg_lerp(b1, b2, kg_clampf((kg_clampf(u2, 0.0f, length) - u1) / span, 0.0f, 1.0f));
    }
    kg_push_plane_point(m, q1, r1, n, id1, speculative);
    kg_push_plane_point(m, q2, r1, n, id2, speculative);
}

/* The segment is the reference: the body's edge b_index -> next clipped to it. */
KG_FN kg_tile_hit kg_segment_reference(const kg_tile_segment* s, const kg_shape* body, int b_index, float separation,
                                       float speculative)
{
    int next = kg_next_vertex(b_index, body->count);
    kg_tile_hit hit;
    hit.manifold = kg_empty_manifold();
    hit.manifold.normal = s->normal;
    hit.separation = separation;
    kg_clip_edge(&hit.manifold, s->p1, s->p2, s->normal, body->vertices[b_index], body->vertices[next],
                 KG_FEATURE_ID((kg_u32)b_index, s->vertex2), KG_FEATURE_ID((kg_u32)next, s->vertex1), speculative);
    return hit;
}

/* The body's face k is the reference: the segment clipped to it. The normal from the tile
 * to the body is minus the face normal; the points' separations are measured from it. */
KG_FN kg_tile_hit kg_body_face_reference(const kg_tile_segment* s, const kg_shape* body, int k, float separation,
                                         float speculative)
{
    int next = kg_next_vertex(k, body->count);
    kg_vec2 n = body->normals[k];
    kg_tile_hit hit;
    hit.manifold = kg_empty_manifold();
    hit.manifold.normal = kg_neg(n);
    hit.separation = separation;
    kg_clip_edge(&hit.manifold, body->vertices[k], body->vertices[next], n, s->p1, s->p2,
                 KG_FEATURE_ID((kg_u32)next, s->vertex1), KG_FEATURE_ID((kg_u32)k, s->vertex2), speculative);
    return hit;
}

/* The body's edge next to vertex v that faces the segment most squarely. */
KG_FN int kg_incident_edge_at(const kg_shape* body, int v, kg_vec2 normal)
{
    int previous = v > 0 ? v - 1 : body->count - 1;
    return kg_dot(body->normals[previous], normal) < kg_dot(body->normals[v], normal) ? previous : v;
}

/* A single point between a tile point and a body point at distance d apart. */
KG_FN kg_tile_hit kg_point_hit(kg_vec2 on_tile, kg_vec2 on_body, kg_vec2 normal, float separation, kg_u32 id)
{
    kg_tile_hit hit;
    hit.manifold = kg_empty_manifold();
    hit.manifold.normal = normal;
    hit.separation = separation;
    kg_push_point(&hit.manifold, kg_lerp(on_tile, on_body, 0.5f), separation, id);
    return hit;
}

/* ---- polygon bodies ---- */

/* min over the body's vertices of dot(n, w - p), and which vertex. */
KG_FN float kg_lowest_along(const kg_shape* body, kg_vec2 n, kg_vec2 p, int* index)
{
    float lowest = KG_FLT_MAX;
    *index = 0;
    for (int j = 0; j < body->count; ++j) {
        float d = kg_dot(n, kg_sub(body->vertices[j], p));
        if (d < lowest) {
            lowest = d;
            *index = j;
        }
    }
    return lowest;
}

/* The separation of the segment from the body along the body's face normal k. */
KG_FN float kg_face_separation(const kg_tile_segment* s, const kg_shape* body, int k)
{
    kg_vec2 n = body->normals[k], w = body->vertices[k];
    return fminf(kg_dot(n, kg_sub(s->p1, w)), kg_dot(n, kg_sub(s->p2, w)));
}

/* The closest features of a segment and a separated polygon body. */
typedef struct kg_closest {
    kg_vec2 on_segment, on_body;
    float distance;
    float fa, fb;  /* parameters along the segment and along the body edge */
    int body_edge;
} kg_closest;

KG_FN kg_closest kg_closest_features(const kg_tile_segment* s, const kg_shape* body)
{
    kg_closest best;
    best.distance = KG_FLT_MAX;
    best.on_segment = s->p1;
    best.on_body = s->p1;
    best.fa = 0.0f;
    best.fb = 0.0f;
    best.body_edge = 0;
    for (int k = 0; k < body->count; ++k) {
        kg_vec2 b1 = body->vertices[k], b2 = body->vertices[kg_next_vertex(k, body->count)];
        float fa, fb;
        kg_closest_on_segments(s->p1, s->p2, b1, b2, &fa, &fb);
        kg_vec2 on_segment = kg_lerp(s->p1, s->p2, fa), on_body = kg_lerp(b1, b2, fb);
        float distance = kg_distance(on_segment, on_body);
        if (distance < best.distance) {
            best.distance = distance;
            best.on_segment = on_segment;
            best.on_body = on_body;
            best.fa = fa;
            best.fb = fb;
            best.body_edge = k;
        }
    }
    /* A 2-vertex core (a capsule's, a segment's) has its one edge twice, facing both ways,
     * equally close: rounding picked either, and the one facing away from the segment
     * lost the contact at a segment's end. Take the one that faces it. */
    if (body->count == 2 && kg_dot(body->normals[best.body_edge], kg_sub(best.on_segment, best.on_body)) < 0.0f) {
        best.body_edge = 1 - best.body_edge;
        best.fb = 1.0f - best.fb;
    }
    return best;
}

/* Whether the segment's neighbour past the end nearest the body's face k faces that face
 * more squarely than the segment does: then the neighbour is the incident edge. A free
 * end has no neighbour (its side is only a limit on normals): a face tilted past 45
 * degrees over a ledge's end was dropped for a neighbour that is not there. */
KG_FN int kg_neighbour_is_incident(const kg_tile_segment* s, const kg_shape* body, int k)
{
    kg_vec2 n = body->normals[k], w = body->vertices[k];
    int start_deeper = kg_dot(n, kg_sub(s->p1, w)) < kg_dot(n, kg_sub(s->p2, w));
    if ((start_deeper ? s->end1 : s->end2) == KG_END_FREE) {
        return 0;
    }
    kg_vec2 ghost = start_deeper ? s->normal0 : s->normal2;
    return kg_dot(ghost, n) < kg_dot(s->normal, n);
}

/* A body face k as the reference, if its normal is admissible and no neighbour is the
 * better incident edge; SNAP falls back to the segment against the body edge k. */
KG_FN kg_tile_hit kg_body_face_contact(const kg_tile_segment* s, const kg_shape* body, int k, float separation,
                                       float speculative)
{
    kg_normal_kind kind = kg_classify_normal(s, kg_neg(body->normals[k]));
    if (kind == KG_NORMAL_SKIP) {
        return kg_tile_no_hit();
    }
    if (kind == KG_NORMAL_SNAP) {
        return kg_segment_reference(s, body, k, separation, speculative);
    }
    if (kg_neighbour_is_incident(s, body, k)) {
        return kg_tile_no_hit();
    }
    return kg_body_face_reference(s, body, k, separation, speculative);
}

/* A body clear of the segment by more than KG_TILE_TOUCHING: its closest features decide
 * the kind of contact, as Box2D's chain segments do with the distance algorithm. */
KG_FN kg_tile_hit kg_separated_polygon(const kg_tile_segment* s, const kg_shape* body, float speculative)
{
    kg_closest c = kg_closest_features(s, body);
    if (c.distance > speculative) {
        return kg_tile_no_hit();
    }
    int next = kg_next_vertex(c.body_edge, body->count);
    int on_segment_end = c.fa <= 0.0f || c.fa >= 1.0f;
    int on_body_vertex = c.fb <= 0.0f || c.fb >= 1.0f;
    if (!on_segment_end) {
        int vertex = c.fb >= 1.0f ? next : c.body_edge;
        int edge = on_body_vertex ? kg_incident_edge_at(body, vertex, s->normal) : c.body_edge;
        return kg_segment_reference(s, body, edge, c.distance, speculative);
    }
    if (!on_body_vertex) {
        return kg_body_face_contact(s, body, c.body_edge, c.distance, speculative);
    }
    /* corner against corner */
    int is_start = c.fa <= 0.0f;
    int vertex = c.fb >= 1.0f ? next : c.body_edge;
    kg_vec2 normal = kg_scale(1.0f / c.distance, kg_sub(c.on_body, c.on_segment));
    kg_normal_kind kind = kg_classify_normal(s, normal);
    if (kind == KG_NORMAL_SNAP) {
        return kg_segment_reference(s, body, kg_incident_edge_at(body, vertex, s->normal), c.distance, speculative);
    }
    if (kind == KG_NORMAL_SKIP || !kg_owns_end(s, is_start)) {
        return kg_tile_no_hit();
    }
    kg_u32 tile_vertex = is_start ? s->vertex1 : s->vertex2;
    return kg_point_hit(c.on_segment, c.on_body, normal, c.distance, KG_FEATURE_ID((kg_u32)vertex, tile_vertex));
}

/* The best separating axis among the admissible ones of a touching or overlapping body. */
typedef enum kg_axis_kind { KG_AXIS_SEGMENT = 0, KG_AXIS_NEIGHBOUR = 1, KG_AXIS_BODY_FACE = 2 } kg_axis_kind;

KG_FN kg_tile_hit kg_touching_polygon(const kg_tile_segment* s, const kg_shape* body, float speculative)
{
    int deepest = 0, unused = 0;
    float separation = kg_lowest_along(body, s->normal, s->p1, &deepest);
    kg_axis_kind kind = KG_AXIS_SEGMENT;
    if (s->end1 != KG_END_FLAT) {
        float s0 = kg_lowest_along(body, s->normal0, s->p1, &unused);
        if (s0 > separation + KG_TILE_AXIS_TOLERANCE) {
            separation = s0;
            kind = KG_AXIS_NEIGHBOUR;
        }
    }
    if (s->end2 != KG_END_FLAT) {
        float s2 = kg_lowest_along(body, s->normal2, s->p2, &unused);
        if (s2 > separation + KG_TILE_AXIS_TOLERANCE) {
            separation = s2;
            kind = KG_AXIS_NEIGHBOUR;
        }
    }
    int face = -1;
    float face_separation = -KG_FLT_MAX;
    for (int k = 0; k < body->count; ++k) {
        if (kg_classify_normal(s, kg_neg(body->normals[k])) != KG_NORMAL_ADMIT) {
            continue;
        }
        float sk = kg_face_separation(s, body, k);
        if (sk > face_separation) {
            face_separation = sk;
            face = k;
        }
    }
    if (face >= 0 && face_separation > separation + KG_TILE_AXIS_TOLERANCE) {
        if (kg_neighbour_is_incident(s, body, face)) {
            return kg_tile_no_hit();
        }
        return kg_body_face_reference(s, body, face, face_separation, speculative);
    }
    if (kind == KG_AXIS_NEIGHBOUR) {
        return kg_tile_no_hit();
    }
    return kg_segment_reference(s, body, kg_incident_edge_at(body, deepest, s->normal), separation, speculative);
}

/* The largest separation over every axis of the segment and the body: a lower bound of
 * their distance, exact when a face meets a vertex. */
KG_FN float kg_sat_separation(const kg_tile_segment* s, const kg_shape* body)
{
    int unused = 0;
    float separation = kg_lowest_along(body, s->normal, s->p1, &unused);
    for (int k = 0; k < body->count; ++k) {
        separation = fmaxf(separation, kg_face_separation(s, body, k));
    }
    return separation;
}

/* Whether the point c is behind the segment and behind its neighbours' planes at convex
 * ends: then the body it belongs to is the business of other edges (Box2D's one-sided test). */
KG_FN int kg_behind_segment(const kg_tile_segment* s, kg_vec2 c)
{
    int behind1 = kg_dot(s->normal, kg_sub(c, s->p1)) < 0.0f;
    int behind0 = s->end1 == KG_END_FLAT || kg_dot(s->normal0, kg_sub(c, s->p1)) < 0.0f;
    int behind2 = s->end2 == KG_END_FLAT || kg_dot(s->normal2, kg_sub(c, s->p2)) < 0.0f;
    return behind0 && behind1 && behind2;
}

/* A polygon body (cell frame) against a segment; exit: the body's centre is inside this
 * tile and this is the tile's nearest exposed edge, through which it must leave. */
KG_FN kg_tile_hit kg_tile_collide_polygon(const kg_tile_segment* s, const kg_shape* body, int exit, float speculative)
{
    if (exit) {
        int deepest = 0;
        float separation = kg_lowest_along(body, s->normal, s->p1, &deepest);
        return kg_segment_reference(s, body, kg_incident_edge_at(body, deepest, s->normal), separation, speculative);
    }
    if (kg_behind_segment(s, body->centroid)) {
        return kg_tile_no_hit();
    }
    float separation = kg_sat_separation(s, body);
    if (separation > speculative) {
        return kg_tile_no_hit();
    }
    if (separation > KG_TILE_TOUCHING) {
        return kg_separated_polygon(s, body, speculative);
    }
    return kg_touching_polygon(s, body, speculative);
}

/* A polygon body with a radius (a capsule: its 2-vertex core) against a segment: the core
 * collided within the speculative distance plus the radius, then rounded as in manifold.h.
 * Sharp polygons (radius 0) come out as kg_tile_collide_polygon gives them. */
KG_FN kg_tile_hit kg_tile_collide_rounded(const kg_tile_segment* s, const kg_shape* body, int exit, float speculative)
{
    kg_tile_hit hit = kg_tile_collide_polygon(s, body, exit, speculative + body->radius);
    kg_round_manifold(&hit.manifold, 0.0f, body->radius);
    hit.separation -= body->radius;
    return hit;
}

/* ---- circles and points ---- */

/* A circle against one of the segment's end vertices, in its vertex region. */
KG_FN kg_tile_hit kg_circle_at_vertex(kg_vec2 p, kg_vec2 center, float radius, kg_vec2 fallback_normal)
{
    kg_vec2 offset = kg_sub(center, p);
    float distance = kg_length(offset);
    kg_vec2 normal = distance > KG_LENGTH_EPSILON ? kg_scale(1.0f / distance, offset) : fallback_normal;
    return kg_point_hit(p, kg_mul_sub(center, radius, normal), normal, distance - radius, 0u);
}

/* A circle (or a point, radius 0) against a segment; exit as for polygons. Circle points
 * have id 0, as in manifold.h: the closest feature of a round shape moves continuously,
 * and so should its warm-started impulse. */
KG_FN kg_tile_hit kg_tile_collide_circle(const kg_tile_segment* s, kg_vec2 center, float radius, int exit,
                                         float speculative)
{
    float along = kg_dot(kg_sub(center, s->p1), s->direction);
    float height = kg_dot(kg_sub(center, s->p1), s->normal);
    /* a flat end's region is the next segment's, but rounding in the two cell frames can
     * put a centre on the join just outside both: each takes it up to the weld distance */
    float weld = KG_TILE_WELD * s->length;
    float from = s->end1 == KG_END_FLAT ? -weld : 0.0f;
    float to = s->end2 == KG_END_FLAT ? s->length + weld : s->length;
    kg_tile_hit hit = kg_tile_no_hit();
    if (exit || (along >= from && along < to && height >= 0.0f)) {
        kg_vec2 on_segment = kg_mul_sub(center, height, s->normal);
        hit = kg_point_hit(on_segment, kg_mul_sub(center, radius, s->normal), s->normal, height - radius, 0u);
    } else if (along < 0.0f && kg_owns_end(s, 1)) {
        /* the corner's region, unless the centre is over the edge arriving at p1 */
        if (kg_dot(kg_left_perp(s->normal0), kg_sub(center, s->p1)) > 0.0f) {
            hit = kg_circle_at_vertex(s->p1, center, radius, s->normal);
        }
    } else if (along >= s->length && kg_owns_end(s, 0)) {
        if (kg_dot(kg_left_perp(s->normal2), kg_sub(center, s->p2)) <= 0.0f) {
            hit = kg_circle_at_vertex(s->p2, center, radius, s->normal);
        }
    }
    if (hit.manifold.point_count > 0 && hit.manifold.points[0].separation > speculative) {
        return kg_tile_no_hit();
    }
    return hit;
}

/* ---- the body in the cell frame, and its contact back in the world (collide/tile_pass.h)
 * ---- */

/* A body's shape moved into a cell's frame, into *out: xf is the body's pose relative to
 * the cell (kg_shape_in_frame, from the shape in global memory). */
KG_FN void kg_shape_in_cell(kg_shape* out, KG_GLOBAL const kg_shape* shape, kg_xf xf)
{
    KG_PRIVATE_VIEW(kg_shape, s, *shape);
    kg_shape_in_frame(out, s, xf);
}

/* A contact from a manifold in the cell frame (normal from the tile to the body): normal
 * from the body to the tile, anchor_a from the body's origin. The world never moves, so
 * the solver's result does not depend on anchor_b (it enters only as anchor_b - r_a, the
 * lever arm r_a = anchor_a + origin - centre of mass, in terms that cancel); anchor_b is
 * set to r_a itself, so they cancel exactly. The world point (anchor_b relative to the
 * world origin) would leave float round-off of the size of the coordinates, 1e-5 m at
 * 100 m, which the contact spring turns into millimetres per second of jitter. */
KG_FN kg_manifold kg_contact_manifold(const kg_manifold* in_cell, kg_vec2 cell_origin, kg_xf body_in_cell,
                                      kg_vec2 body_origin, kg_vec2 body_center)
{
    kg_manifold m = *in_cell;
    m.normal = kg_neg(in_cell->normal);
    for (int k = 0; k < m.point_count; ++k) {
        kg_manifold_point* mp = &m.points[k];
        mp->anchor_a = kg_sub(in_cell->points[k].point, body_in_cell.p);
        mp->point = kg_add(cell_origin, in_cell->points[k].point);
        mp->anchor_b = kg_sub(kg_add(mp->anchor_a, body_origin), body_center);
        mp->normal_impulse = 0.0f;
        mp->tangent_impulse = 0.0f;
        mp->normal_velocity = 0.0f;
    }
    return m;
}

/* ---- one tile ---- */

/* The exposed edge through which a point inside the tile leaves it (the one it is least
 * deep behind), or -1 when the point is outside or no edge is exposed. */
KG_FN int kg_exit_edge(KG_GLOBAL const kg_shape* tile, kg_u32 word, kg_vec2 c)
{
    int exit = -1;
    float best = -KG_FLT_MAX;
    for (int i = 0; i < tile->count; ++i) {
        float d = kg_dot(tile->normals[i], kg_sub(c, tile->vertices[i]));
        if (d > 0.0f) {
            return -1;
        }
        if (kg_cell_collidable(word, i) && d > best) {
            best = d;
            exit = i;
        }
    }
    return exit;
}

/* The manifold of a body (its shape already in the cell frame) against the centre tile of
 * nb: the best of its exposed edges' hits (largest separation along the axis that made
 * it), normal from the tile to the body. A circle tile is collided as it is. */
KG_FN kg_tile_hit kg_tile_collide(const kg_tile_neighbourhood* nb, const kg_shape* body, float speculative)
{
    kg_tile_cell centre = nb->cells[4];
    KG_GLOBAL const kg_shape* tile = &centre.proto->shape;
    if (tile->count < 3) {
        KG_PRIVATE_VIEW(kg_shape, circle_tile, centre.proto->shape);
        kg_tile_hit hit = kg_tile_no_hit();
        hit.manifold = kg_collide_convex(circle_tile, kg_translation(kg_v2(0.0f, 0.0f)), body,
                                         kg_translation(kg_v2(0.0f, 0.0f)), speculative);
        hit.separation = kg_min_separation(&hit.manifold);
        return hit;
    }
    int body_is_polygon = body->count >= 2;
    kg_vec2 center = body_is_polygon ? body->centroid : body->vertices[0];
    int exit = kg_exit_edge(tile, centre.word, center);
    kg_tile_hit best = kg_tile_no_hit();
    for (int i = 0; i < tile->count; ++i) {
        if (!kg_cell_collidable(centre.word, i)) {
            continue;
        }
        kg_tile_segment s = kg_tile_segment_of(nb, i);
        kg_tile_hit hit = body_is_polygon ? kg_tile_collide_rounded(&s, body, i == exit, speculative)
                                          : kg_tile_collide_circle(&s, center, body->radius, i == exit, speculative);
        if (hit.manifold.point_count > 0 && (best.manifold.point_count == 0 || hit.separation > best.separation)) {
            best = hit;
        }
    }
    return best;
}

#endif
