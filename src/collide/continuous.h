/* The continuous collision of one body, at the end of the solve, before its pose is
 * finalized: a dynamic body that moves fast (collide/toi.h, kg_moves_fast) is swept from
 * its pose at the start of the step (its origin transform, which finalize has not yet
 * updated) to its pose at the end (centre and rotation), against the static bodies and
 * the tile maps that the swept bounds overlap; a bullet also against the non-bullet
 * dynamic bodies and the kinematic ones, at their poses at the end of the step
 * (finalized before the bullets run). At the earliest time of impact the body is moved back on its sweep and keeps its
 * velocity: next step's contact, made just touching, stops it. Box2D v3's scheme.
 *
 * A body's result depends only on the start and end poses of the step and on bodies it
 * does not write, so the CPU backend runs bodies in parallel and the device one
 * work-item a body, with the same bits. */
#ifndef KG_CONTINUOUS_H
#define KG_CONTINUOUS_H

#include "collide/aabb.h"
#include "collide/chain.h"
#include "collide/pair_contact.h"
#include "collide/sorted_shapes.h"
#include "collide/tile_pass.h"
#include "collide/toi.h"

/* A static body in the index the sweeps search (made on the host when a static body
 * changes): the large ones first, in slot order, each tested; then the others sorted by
 * the lower x of their bounds, with reach the largest upper x of those up to this one,
 * so that a search walks back from the last one not past the sweep's upper x only while
 * some earlier one can still reach its lower x. */
typedef struct kg_static_entry {
    kg_u32 slot;
    float lower_x;
    float reach;
    kg_u32 pad;
} kg_static_entry;

KG_STATIC_ASSERT(sizeof(kg_static_entry) == 16, static_entry_size);

/* The body pool's arrays the pass reads, and the two it writes (centre and rotation). */
typedef struct kg_continuous_bodies {
    KG_GLOBAL const kg_u32* flags;
    KG_GLOBAL const kg_vec2* velocity;
    KG_GLOBAL const float* omega;
    KG_GLOBAL kg_vec2* center;
    KG_GLOBAL kg_rot* rot;
    KG_GLOBAL const kg_xf* xf; /* at the start of the step for the bodies being swept */
    KG_GLOBAL const kg_aabb* aabb;
    KG_GLOBAL const kg_vec2* local_center;
    KG_GLOBAL const kg_static_entry* statics; /* the static bodies' index, static_count long, */
    int static_count;
    int large_count;                 /* of which the first large_count are the large ones */
    int slot_count;                  /* the pool's high water: bullets look at [0, slot_count) */
    kg_shape_arrays shapes;          /* each body's shapes: a compound body is swept, and met, shape by shape */
    KG_GLOBAL const int* sorted_of;  /* per body slot: its span of sorted shapes, or -1 (a body of many
                                      * shapes, a chain's: collide/sorted_shapes.h); NULL: none */
    KG_GLOBAL const kg_sorted_span* sorted_spans;
    KG_GLOBAL const kg_sorted_shape* sorted_shapes;
} kg_continuous_bodies;

/* Which pass a body is swept in: the non-bullets first, then the bullets against them. */
#define KG_CONTINUOUS_PASS_BODIES 0
#define KG_CONTINUOUS_PASS_BULLETS 1

KG_FN int kg_is_bullet(kg_u32 flags) { return (flags & KG_FLAG_BULLET) != 0u; }

/* Whether slot i is swept in pass `pass`: an awake dynamic body of the pass's kind. */
KG_FN int kg_continuous_takes(kg_u32 flags, int pass)
{
    return kg_flags_simulated(flags) && kg_flags_type(flags) == (kg_u32)KG_BODY_DYNAMIC &&
           kg_is_bullet(flags) == (pass == KG_CONTINUOUS_PASS_BULLETS);
}

/* Whether finalize pass `pass` finalizes slot i: with continuous collision on, the bullets
 * wait for the second pass (they read the others' finalized poses); else all go in the
 * first. */
KG_FN int kg_finalized_in_pass(kg_u32 flags, int continuous, int pass)
{
    return continuous ? kg_is_bullet(flags) == (pass == KG_CONTINUOUS_PASS_BULLETS) : pass == KG_CONTINUOUS_PASS_BODIES;
}

/* What a bullet is swept against besides the static world: the other moving bodies,
 * dynamic (not bullets) or kinematic, at their poses at the end of the step. */
KG_FN int kg_bullet_target(kg_u32 flags)
{
    kg_u32 type = kg_flags_type(flags);
    int dynamic = type == (kg_u32)KG_BODY_DYNAMIC && !kg_is_bullet(flags);
    return kg_flags_alive(flags) && (flags & KG_FLAG_FROZEN) == 0u && (dynamic || type == (kg_u32)KG_BODY_KINEMATIC);
}

KG_FN int kg_filters_meet(kg_u32 category_a, kg_u32 mask_a, kg_u32 category_b, kg_u32 mask_b)
{
    return (category_a & mask_b) != 0u && (category_b & mask_a) != 0u;
}

/* A body's extents over its solid shapes: the least of their least extents (its thinnest
 * part decides whether it can pass through something) and the farthest any of their
 * points lies from its centre of mass. None solid: it is never fast. */
KG_FN kg_extents kg_body_extents(const kg_shape_arrays* shapes, kg_u32 i, kg_vec2 local_center)
{
    kg_extents e;
    e.min = KG_FLT_MAX;
    e.max = 0.0f;
    for (kg_u32 sa = shapes->first_shape[i]; sa != KG_NULL_INDEX; sa = shapes->next[sa]) {
        if ((shapes->flags[sa] & KG_SHAPE_SENSOR) == 0u) {
            KG_PRIVATE_VIEW(kg_shape, shape, *kg_shape_of(shapes, i, sa));
            kg_extents x = kg_shape_extents(shape, local_center);
            e.min = kg_minf(e.min, x.min);
            e.max = kg_maxf(e.max, x.max);
        }
    }
    return e;
}

/* Body slot i's sweep over the step. */
KG_FN kg_sweep kg_body_sweep(const kg_continuous_bodies* b, kg_u32 i, float max_extent)
{
    kg_sweep s;
    s.max_extent = max_extent;
    kg_xf start = b->xf[i];
    s.local_center = b->local_center[i];
    s.c1 = kg_xf_point(start, s.local_center);
    s.q1 = start.q;
    s.c2 = b->center[i];
    s.q2 = b->rot[i];
    return s;
}

/* Bounds of the shape all along the sweep: every point of it stays within its largest
 * extent of the centre, which runs straight from c1 to c2; fattened by the target. */
KG_FN kg_aabb kg_sweep_bounds(const kg_sweep* s, float target)
{
    kg_aabb box;
    box.lower = kg_vmin(s->c1, s->c2);
    box.upper = kg_vmax(s->c1, s->c2);
    return kg_aabb_fatten(box, target + s->max_extent);
}

/* A segment as a shape of two points (no radius), for the time of impact. */
KG_FN kg_shape kg_edge_shape(kg_vec2 p1, kg_vec2 p2)
{
    kg_shape s;
    for (int i = 0; i < KG_MAX_VERTS; ++i) {
        s.vertices[i] = p1;
        s.normals[i] = kg_v2(0.0f, 0.0f);
    }
    s.vertices[1] = p2;
    s.centroid = kg_lerp(p1, p2, 0.5f);
    s.radius = 0.0f;
    s.count = 2;
    s.chain = 0u;
    s.parallelogram = 0u;
    return s;
}

/* The earliest fraction at which the shape meets exposed edge [p1, p2] of a tile (cell
 * frame, at cell) or a chain segment (body frame, at the body's pose), as a one-sided
 * segment (Box2D v3's chain segments): only when the
 * centre crosses its line from the front (outside) to behind. So a body sliding along
 * a run of tiles, which sinks into it by a hair, never stops at the side of the next
 * tile (that side is covered, not exposed), nor at the next tile's top (it does not
 * cross it). */
KG_FN float kg_toi_with_edge(const kg_shape* shape, const kg_sweep* s, kg_vec2 p1, kg_vec2 p2, kg_xf cell,
                             kg_toi_params prm, float limit)
{
    kg_vec2 a = kg_xf_point(cell, p1), e = kg_sub(kg_xf_point(cell, p2), a);
    float front1 = kg_cross(kg_sub(s->c1, a), e), front2 = kg_cross(kg_sub(s->c2, a), e);
    if (front1 < 0.0f || front2 > 0.0f) {
        return limit;
    }
    kg_shape edge = kg_edge_shape(p1, p2);
    return kg_shape_time_of_impact(shape, s, &edge, cell, prm, limit);
}

/* The earliest fraction (below limit) at which the shape meets shape sb of body j, whose
 * bounds the sweep's reach. */
KG_FN float kg_toi_with_shape(const kg_continuous_bodies* b, const kg_shape* shape, const kg_sweep* s, kg_u32 j,
                              kg_u32 sb, kg_toi_params prm, float limit)
{
    KG_PRIVATE_VIEW(kg_shape, other, *kg_shape_of(&b->shapes, j, sb));
    return kg_is_chain_segment(other)
               ? kg_toi_with_edge(shape, s, other->vertices[0], other->vertices[1], b->xf[j], prm, limit)
               : kg_shape_time_of_impact(shape, s, other, b->xf[j], prm, limit);
}

/* Each of body j's solid shapes that the filter of shape sa meets and the sweep's bounds
 * box reach, in slot order: the earliest fraction below limit at which the shape meets one. */
KG_FN float kg_toi_with_each(const kg_continuous_bodies* b, kg_u32 sa, const kg_shape* shape, const kg_sweep* s,
                             kg_aabb box, kg_u32 j, kg_toi_params prm, float limit)
{
    for (kg_u32 sb = b->shapes.first_shape[j]; sb != KG_NULL_INDEX; sb = b->shapes.next[sb]) {
        KG_PRIVATE_VIEW(kg_shape, other, *kg_shape_of(&b->shapes, j, sb));
        if (kg_shapes_pair(&b->shapes, sa, sb) && kg_aabb_overlap(box, kg_shape_aabb(other, b->xf[j]))) {
            limit = kg_toi_with_shape(b, shape, s, j, sb, prm, limit);
        }
    }
    return limit;
}

/* Shapes of a sorted body one sweep meets, visited in slot order; a sweep that meets more
 * tries every shape instead. */
#define KG_SORTED_VISIT 32

/* kg_toi_with_each for a static body j of sorted shapes: the same shapes (their bounds
 * were made at the same pose by the same function), found by the search, then met in
 * slot order, so that each time of impact starts from the same limit, bit for bit. */
KG_FN float kg_toi_with_sorted(const kg_continuous_bodies* b, kg_u32 sa, const kg_shape* shape, const kg_sweep* s,
                               kg_aabb box, kg_u32 j, kg_toi_params prm, float limit)
{
    KG_GLOBAL const kg_sorted_shape* e = b->sorted_shapes;
    kg_sorted_span span = b->sorted_spans[b->sorted_of[j]];
    kg_u32 met[KG_SORTED_VISIT];
    int n = 0;
    for (int k = kg_sorted_end(e, span, box) - 1; kg_sorted_may_reach(e, k, span, box); --k) {
        if (kg_shapes_pair(&b->shapes, sa, e[k].slot) && kg_aabb_overlap(box, e[k].box)) {
            if (n == KG_SORTED_VISIT) {
                return kg_toi_with_each(b, sa, shape, s, box, j, prm, limit);
            }
            met[n++] = e[k].slot;
        }
    }
    for (int i = 1; i < n; ++i) { /* insertion sort: a handful */
        kg_u32 v = met[i];
        int at = i;
        for (; at > 0 && met[at - 1] > v; --at) {
            met[at] = met[at - 1];
        }
        met[at] = v;
    }
    for (int i = 0; i < n; ++i) {
        limit = kg_toi_with_shape(b, shape, s, j, met[i], prm, limit);
    }
    return limit;
}

/* The earliest fraction (below limit) at which the shape (slot sa of the body swept) meets
 * body slot j: each of j's solid shapes that its filter meets and the sweep's bounds reach
 * (a chain segment one-sided, as a tile's edge); a static body of many shapes through its
 * sorted shapes (on the CPU: the device tries each). */
KG_FN float kg_toi_with_body(const kg_continuous_bodies* b, kg_u32 sa, const kg_shape* shape, const kg_sweep* s,
                             kg_aabb box, kg_u32 j, kg_toi_params prm, float limit)
{
    if (!kg_aabb_overlap(box, b->aabb[j])) {
        return limit;
    }
    if (b->sorted_of && b->sorted_of[j] >= 0 && kg_flags_type(b->flags[j]) == (kg_u32)KG_BODY_STATIC) {
        return kg_toi_with_sorted(b, sa, shape, s, box, j, prm, limit);
    }
    return kg_toi_with_each(b, sa, shape, s, box, j, prm, limit);
}

/* The first of the sorted entries [lo, hi) whose lower x lies past x. */
KG_FN int kg_statics_past(KG_GLOBAL const kg_static_entry* e, int lo, int hi, float x)
{
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (e[mid].lower_x <= x) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    return lo;
}

/* The earliest fraction at which the shape meets a static body whose bounds meet box:
 * every large one, and the small ones from the last not past box back to the first
 * that nothing before can reach box from (kg_static_entry). */
KG_FN float kg_toi_with_statics(const kg_continuous_bodies* b, kg_u32 sa, const kg_shape* shape, const kg_sweep* s,
                                kg_aabb box, kg_toi_params prm, float limit)
{
    KG_GLOBAL const kg_static_entry* e = b->statics;
    for (int k = 0; k < b->large_count; ++k) {
        limit = kg_toi_with_body(b, sa, shape, s, box, e[k].slot, prm, limit);
    }
    int last = kg_statics_past(e, b->large_count, b->static_count, box.upper.x) - 1;
    for (int k = last; k >= b->large_count && e[k].reach >= box.lower.x; --k) {
        limit = kg_toi_with_body(b, sa, shape, s, box, e[k].slot, prm, limit);
    }
    return limit;
}

/* The earliest fraction at which the shape meets the tile at (layer, x, y) of map m:
 * its exposed edges (collide/tilemap.h), or a round tile whole. */
KG_FN float kg_toi_with_tile(const kg_tile_terrain* t, const kg_tile_map_info* m, int layer, int x, int y,
                             const kg_shape* shape, const kg_sweep* s, kg_toi_params prm, float limit)
{
    kg_u32 word = t->cells[m->cell_offset + kg_tile_cell_index(m, layer, x, y)];
    KG_GLOBAL const kg_tile_proto* proto = &t->protos[m->proto_offset + kg_cell_id(word)];
    kg_xf cell;
    cell.p = kg_v2(m->origin.x + (float)x * m->tile_size.x, m->origin.y + (float)y * m->tile_size.y);
    cell.q = kg_rot_identity();
    KG_PRIVATE_VIEW(kg_shape, tile, proto->shape);
    if (tile->count == 1) {
        return kg_shape_time_of_impact(shape, s, tile, cell, prm, limit);
    }
    for (int i = 0; i < tile->count; ++i) {
        if (kg_cell_collidable(word, i)) {
            kg_vec2 p1 = tile->vertices[i], p2 = tile->vertices[kg_next_vertex(i, tile->count)];
            limit = kg_toi_with_edge(shape, s, p1, p2, cell, prm, limit);
        }
    }
    return limit;
}

/* The earliest fraction at which the shape meets a tile of map m over the cells box
 * covers: tiles that may touch (a body reaches the others through those) and are not
 * one-way platforms (a body may pass those from below). */
KG_FN float kg_toi_with_map(const kg_tile_terrain* t, const kg_tile_map_info* m, const kg_shape* shape,
                            const kg_sweep* s, kg_aabb box, kg_toi_params prm, float limit)
{
    kg_vec2 size = m->tile_size, origin = m->origin;
    int x0, x1, y0, y1;
    if (!kg_tile_span((box.lower.x - origin.x) / size.x, (box.upper.x - origin.x) / size.x, m->width, &x0, &x1) ||
        !kg_tile_span((box.lower.y - origin.y) / size.y, (box.upper.y - origin.y) / size.y, m->height, &y0, &y1)) {
        return limit;
    }
    for (int layer = 0; layer < m->layer_count; ++layer) {
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                kg_u32 index = kg_tile_cell_index(m, layer, x, y);
                kg_u32 id = kg_cell_id(t->cells[m->cell_offset + index]);
                if (kg_tile_may_touch(t, m, index) && (t->protos[m->proto_offset + id].flags & KG_TILE_FLAG_ONE_WAY) == 0u) {
                    limit = kg_toi_with_tile(t, m, layer, x, y, shape, s, prm, limit);
                }
            }
        }
    }
    return limit;
}

/* The earliest fraction of the sweep, below limit, at which shape slot sa of slot i meets
 * what it is swept against. */
KG_FN_NOINLINE float kg_shape_sweep_impact(const kg_continuous_bodies* b, const kg_tile_terrain* t, kg_u32 i,
                                           kg_u32 sa, int pass, const kg_sweep* s, kg_toi_params prm, float limit)
{
    KG_PRIVATE_VIEW(kg_shape, shape, *kg_shape_of(&b->shapes, i, sa));
    kg_aabb box = kg_sweep_bounds(s, prm.target);
    limit = kg_toi_with_statics(b, sa, shape, s, box, prm, limit);
    for (int n = 0; n < t->map_count; ++n) {
        KG_PRIVATE_VIEW(kg_tile_map_info, m, t->maps[n]);
        if (kg_filters_meet(b->shapes.category[sa], b->shapes.mask[sa], m->category, m->mask)) {
            limit = kg_toi_with_map(t, m, shape, s, box, prm, limit);
        }
    }
    for (int j = 0; pass == KG_CONTINUOUS_PASS_BULLETS && j < b->slot_count; ++j) {
        if (kg_bullet_target(b->flags[j])) {
            limit = kg_toi_with_body(b, sa, shape, s, box, (kg_u32)j, prm, limit);
        }
    }
    return limit;
}

/* Whether a static body's bounds meet box: the index searched as kg_toi_with_statics
 * searches it, without a shape. */
KG_FN int kg_statics_near(const kg_continuous_bodies* b, kg_aabb box)
{
    KG_GLOBAL const kg_static_entry* e = b->statics;
    for (int k = 0; k < b->large_count; ++k) {
        if (kg_aabb_overlap(box, b->aabb[e[k].slot])) {
            return 1;
        }
    }
    int last = kg_statics_past(e, b->large_count, b->static_count, box.upper.x) - 1;
    for (int k = last; k >= b->large_count && e[k].reach >= box.lower.x; --k) {
        if (kg_aabb_overlap(box, b->aabb[e[k].slot])) {
            return 1;
        }
    }
    return 0;
}

/* The earliest fraction of the sweep at which slot i meets what it is swept against: the
 * earliest of its solid shapes'. Most fast bodies are far from everything (a third of a
 * rain's drops, high above the ground): one search for the whole body tells them, before
 * a search a shape (the sweep's bounds are the body's, the same for each). */
KG_FN float kg_body_time_of_impact(const kg_continuous_bodies* b, const kg_tile_terrain* t, kg_u32 i, int pass,
                                   const kg_sweep* s, kg_toi_params prm)
{
    if (pass != KG_CONTINUOUS_PASS_BULLETS && t->map_count == 0 && !kg_statics_near(b, kg_sweep_bounds(s, prm.target))) {
        return 1.0f;
    }
    float limit = 1.0f;
    for (kg_u32 sa = b->shapes.first_shape[i]; sa != KG_NULL_INDEX; sa = b->shapes.next[sa]) {
        if ((b->shapes.flags[sa] & KG_SHAPE_SENSOR) == 0u) {
            limit = kg_shape_sweep_impact(b, t, i, sa, pass, s, prm, limit);
        }
    }
    return limit;
}

/* Fast body slot i (kg_moves_fast) moved back to its earliest time of impact in pass
 * `pass`, keeping its velocity. */
KG_FN void kg_sweep_fast_body(const kg_continuous_bodies* b, const kg_tile_terrain* t, kg_u32 i, int pass,
                              kg_toi_params prm, float max_extent)
{
    kg_sweep s = kg_body_sweep(b, i, max_extent);
    float t_hit = kg_body_time_of_impact(b, t, i, pass, &s, prm);
    if (t_hit < 1.0f) {
        b->center[i] = kg_sweep_center(&s, t_hit);
        b->rot[i] = kg_sweep_rot(&s, t_hit);
    }
}

/* Slot i's continuous collision in pass `pass`, for a body that takes part in it
 * (kg_continuous_takes) with the given extents (kg_shape_extents of its shape): if it
 * moves fast in the step of dt, kg_sweep_fast_body. */
KG_FN void kg_continuous_body(const kg_continuous_bodies* b, const kg_tile_terrain* t, kg_u32 i, int pass,
                              kg_toi_params prm, float dt, kg_extents extents)
{
    if (kg_moves_fast(b->velocity[i], b->omega[i], dt, extents)) {
        kg_sweep_fast_body(b, t, i, pass, prm, extents.max);
    }
}

#endif
