/* The tile pass: one body against every tile map, over the maps as flat arrays. The CPU
 * backend (collide/tilemap.c) calls kg_tile_collide_body for each body slot in order,
 * the kernel kg_tile_collide_bodies for its work-item's, so both backends find the same
 * contacts, with the same bits, in the same order: per body, per shape (a compound body,
 * on the CPU: collide/tilemap.c), maps by key, layers, rows, columns, so a body's
 * contacts come out sorted by shape and tile key. The layout of the arrays is
 * described in collide/tilemap.h, the collision with one tile in collide/tile_collide.h. */
#ifndef KG_TILE_PASS_H
#define KG_TILE_PASS_H

#include "collide/aabb.h"
#include "collide/pair_contact.h"
#include "collide/recycle.h"
#include "collide/tile_collide.h"
#include "core/body_flags.h"

/* A live tile map: its cells start at cell_offset in the world's cell array, its protos
 * (one per tile id) at proto_offset in the proto array. 64 bytes. */
typedef struct kg_tile_map_info {
    kg_vec2 origin;
    kg_vec2 tile_size;
    kg_i32 width, height, layer_count;
    kg_u32 cell_offset;
    kg_u32 proto_offset;
    kg_u32 key_base;
    float friction;
    float restitution;
    kg_u32 category;
    kg_u32 mask;
    kg_u32 pad[2];
} kg_tile_map_info;

KG_STATIC_ASSERT(sizeof(kg_tile_map_info) == 64, tile_map_info_size);

/* The world's tile maps, and the distances of the pass. */
typedef struct kg_tile_terrain {
    KG_GLOBAL const kg_tile_map_info* maps;
    KG_GLOBAL const kg_u32* cells;
    KG_GLOBAL const kg_tile_proto* protos;
    int map_count;
    float speculative; /* the world's speculative distance */
    float linear_slop;
} kg_tile_terrain;

/* Last step's tile contacts, previous[begin, end) sorted by (body, shape, key), and where the
 * body's contacts go: the n-th to out[base + n] while base + n < room (room 0: counted
 * only). found counts them all; points and carried, the warm starts of those written. */
typedef struct kg_tile_contacts {
    KG_GLOBAL const kg_contact* previous;
    int previous_begin, previous_end;
    KG_GLOBAL kg_contact* out;
    kg_u32 base, room;
    kg_u32 found;
    int points, carried;
} kg_tile_contacts;

/* The body pool's arrays the pass reads. A body's fields are read where they are used,
 * not once up front: most bodies are near no tile. shape, category, mask, friction and
 * restitution are a shape's, at an index g of their own: the body pool's (g = the body's
 * slot) for a body of one shape, the shape pool's (g = the shape's slot) for each shape
 * of a compound body (on the CPU; the device collides compound worlds on the host). */
typedef struct kg_tile_bodies {
    KG_GLOBAL const kg_u32* flags;
    KG_GLOBAL const kg_aabb* aabb;
    KG_GLOBAL const kg_xf* xf;
    KG_GLOBAL const kg_shape* shape;
    KG_GLOBAL const kg_vec2* center;
    KG_GLOBAL const kg_u32* category;
    KG_GLOBAL const kg_u32* mask;
    KG_GLOBAL const kg_u32* generation;
    KG_GLOBAL const float* friction;
    KG_GLOBAL const float* restitution;
    KG_GLOBAL const kg_vec2* last_origin; /* at the last collision, where last_generation */
    KG_GLOBAL const kg_u32* last_generation; /* is the body's generation (else unknown) */
    KG_GLOBAL const kg_u32* first_shape;  /* names a one-shape body's shape in its contacts */
} kg_tile_bodies;

KG_FN kg_u32 kg_tile_cell_index(const kg_tile_map_info* m, int layer, int x, int y)
{
    return (kg_u32)((layer * m->height + y) * m->width + x);
}

/* The cells [lo, hi] along one axis that the interval [a, b] (map frame, in tiles)
 * covers; 0 when none. Clamped in floats first, so far-away bodies cannot overflow. */
KG_FN int kg_tile_span(float a, float b, int count, int* lo, int* hi)
{
    if (!(b >= 0.0f) || !(a < (float)count)) {
        return 0;
    }
    *lo = (int)floorf(fmaxf(a, 0.0f));
    *hi = (int)floorf(fminf(b, (float)count - 1.0f));
    if (*hi >= count) {
        *hi = count - 1;
    }
    return *lo <= *hi;
}

/* Last step's contact of (body, shape, key) among previous[begin, end), sorted so, or -1.
 * It matches slots and key only, as the pairs' do. */
KG_FN int kg_find_previous_tile(KG_GLOBAL const kg_contact* previous, int begin, int end, kg_u32 body, kg_u32 shape,
                                kg_u32 key)
{
    int lo = begin, hi = end;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        kg_u32 ma = previous[mid].a, ms = previous[mid].shape_a, mk = previous[mid].tile;
        if (ma < body || (ma == body && (ms < shape || (ms == shape && mk < key)))) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    return lo < end && previous[lo].a == body && previous[lo].shape_a == shape && previous[lo].tile == key ? lo : -1;
}

/* The tile at (layer, x, y) of map m and its eight neighbours. */
KG_FN kg_tile_neighbourhood kg_tile_neighbourhood_of(const kg_tile_terrain* t, const kg_tile_map_info* m, int layer,
                                                     int x, int y)
{
    kg_tile_neighbourhood nb;
    nb.tile_size = m->tile_size;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            int k = (dy + 1) * 3 + dx + 1, cx = x + dx, cy = y + dy;
            int inside = cx >= 0 && cy >= 0 && cx < m->width && cy < m->height;
            kg_u32 word = inside ? t->cells[m->cell_offset + kg_tile_cell_index(m, layer, cx, cy)] : 0u;
            nb.cells[k].proto = inside ? &t->protos[m->proto_offset + kg_cell_id(word)] : 0;
            nb.cells[k].word = word;
        }
    }
    return nb;
}

/* One-way platforms hold a body that comes from above: the contact existed last step, or
 * the body's deepest point was above the surface (within the linear slop) at the last
 * collision. A body can only cross the surface downwards by moving down, so this also
 * means "moving down or resting". The normal (tile to body) must point up. */
KG_FN int kg_one_way_accepts(const kg_tile_bodies* b, kg_u32 i, const kg_manifold* in_cell, int persisted,
                             float linear_slop)
{
    if (!(in_cell->normal.y > 0.0f)) {
        return 0;
    }
    if (persisted) {
        return 1;
    }
    kg_vec2 origin = b->xf[i].p;
    kg_vec2 last = b->last_generation[i] == b->generation[i] ? b->last_origin[i] : origin;
    kg_vec2 moved = kg_sub(origin, last);
    float previous_separation = kg_min_separation(in_cell) - kg_dot(moved, in_cell->normal);
    return previous_separation >= -linear_slop;
}

/* Counts the contact of body i's shape (g, named shape) with the tile of key, and writes
 * it if there is room: the manifold (cell frame, the body's pose in it xf) moved to the
 * world, last step's impulses and colour (previous[old], unless -1) carried over. */
KG_FN void kg_tile_emit(kg_tile_contacts* c, const kg_tile_bodies* b, kg_u32 i, kg_u32 g, kg_u32 shape,
                        const kg_tile_map_info* m, kg_u32 key, const kg_manifold* in_cell, kg_vec2 cell_origin,
                        kg_xf xf, int old)
{
    kg_u32 at = c->base + c->found;
    c->found += 1u;
    if (at >= c->room) {
        return;
    }
    kg_contact ct;
    ct.manifold = kg_contact_manifold(in_cell, cell_origin, xf, b->xf[i].p, b->center[i]);
    ct.color = KG_NO_COLOR;
    if (old >= 0) {
        KG_PRIVATE_VIEW(kg_manifold, carried, c->previous[old].manifold);
        c->points += ct.manifold.point_count;
        c->carried += kg_contact_carry_impulses(&ct.manifold, carried);
        ct.color = c->previous[old].color;
    }
    ct.a = i;
    ct.b = KG_NULL_INDEX;
    ct.shape_a = shape;
    ct.shape_b = KG_NULL_INDEX;
    ct.tile = key;
    ct.friction = sqrtf(b->friction[g] * m->friction);
    ct.restitution = fmaxf(b->restitution[g], m->restitution);
    ct.generation_a = b->generation[i];
    ct.generation_b = 0u;
    ct.base = kg_no_contact_base();
    c->out[at] = ct;
}

/* Whether the tile of cell `index` of map m can touch anything: a circle, or a tile with
 * an exposed edge (most cells a body's bounds cover have none, and end here). */
KG_FN int kg_tile_may_touch(const kg_tile_terrain* t, const kg_tile_map_info* m, kg_u32 index)
{
    kg_u32 word = t->cells[m->cell_offset + index];
    return t->protos[m->proto_offset + kg_cell_id(word)].shape.count == 1 || (word >> KG_CELL_START_SHIFT) != 0u;
}

/* Body i's shape (g, named shape) against the tile at (layer, x, y) of map m, one that
 * may touch. */
KG_FN_NOINLINE void kg_tile_collide_cell(const kg_tile_terrain* t, const kg_tile_map_info* m, const kg_tile_bodies* b,
                                         kg_u32 i, kg_u32 g, kg_u32 shape, int layer, int x, int y,
                                         kg_tile_contacts* c)
{
    kg_u32 index = kg_tile_cell_index(m, layer, x, y);
    kg_u32 word = t->cells[m->cell_offset + index];
    KG_GLOBAL const kg_tile_proto* proto = &t->protos[m->proto_offset + kg_cell_id(word)];
    kg_vec2 cell_origin = kg_v2(m->origin.x + (float)x * m->tile_size.x, m->origin.y + (float)y * m->tile_size.y);
    kg_xf xf = b->xf[i];
    xf.p = kg_sub(xf.p, cell_origin);
    kg_shape in_cell;
    kg_shape_in_cell(&in_cell, &b->shape[g], xf);
    kg_tile_neighbourhood nb = kg_tile_neighbourhood_of(t, m, layer, x, y);
    kg_tile_hit hit = kg_tile_collide(&nb, &in_cell, t->speculative);
    if (hit.manifold.point_count == 0) {
        return;
    }
    kg_u32 key = m->key_base + index;
    int old = kg_find_previous_tile(c->previous, c->previous_begin, c->previous_end, i, shape, key);
    if ((proto->flags & KG_TILE_FLAG_ONE_WAY) && !kg_one_way_accepts(b, i, &hit.manifold, old >= 0, t->linear_slop)) {
        return;
    }
    kg_tile_emit(c, b, i, g, shape, m, key, &hit.manifold, cell_origin, xf, old);
}

/* Body i's shape (g, named shape) against the cells of map m that box (the body's
 * fattened bounds) covers, if the filters let them touch. */
KG_FN void kg_tile_collide_map(const kg_tile_terrain* t, const kg_tile_map_info* m, const kg_tile_bodies* b, kg_u32 i,
                               kg_u32 g, kg_u32 shape, kg_aabb box, kg_tile_contacts* c)
{
    if ((b->category[g] & m->mask) == 0u || (m->category & b->mask[g]) == 0u) {
        return;
    }
    kg_vec2 size = m->tile_size, origin = m->origin;
    int x0, x1, y0, y1;
    if (!kg_tile_span((box.lower.x - origin.x) / size.x, (box.upper.x - origin.x) / size.x, m->width, &x0, &x1) ||
        !kg_tile_span((box.lower.y - origin.y) / size.y, (box.upper.y - origin.y) / size.y, m->height, &y0, &y1)) {
        return;
    }
    for (int layer = 0; layer < m->layer_count; ++layer) {
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                if (kg_tile_may_touch(t, m, kg_tile_cell_index(m, layer, x, y))) {
                    kg_tile_collide_cell(t, m, b, i, g, shape, layer, x, y, c);
                }
            }
        }
    }
}

/* A shape of body slot i (g, named shape; see kg_tile_bodies) against every tile map: its
 * contacts into c. The body's bounds pick the cells to try. */
KG_FN void kg_tile_collide_shape(kg_u32 i, kg_u32 g, kg_u32 shape, const kg_tile_terrain* t, const kg_tile_bodies* b,
                                 kg_tile_contacts* c)
{
    kg_aabb box = kg_aabb_fatten(b->aabb[i], t->speculative);
    for (int n = 0; n < t->map_count; ++n) {
        KG_PRIVATE_VIEW(kg_tile_map_info, m, t->maps[n]);
        kg_tile_collide_map(t, m, b, i, g, shape, box, c);
    }
}

/* Body slot i, of one shape, against every tile map, if it collides: its contacts into c. */
KG_FN void kg_tile_collide_body(kg_u32 i, const kg_tile_terrain* t, const kg_tile_bodies* b, kg_tile_contacts* c)
{
    if (kg_flags_collide(b->flags[i])) {
        kg_tile_collide_shape(i, i, b->first_shape[i], t, b, c);
    }
}

/* Body slot i against the tile maps: its one shape (bodies: the body pool's arrays), or
 * each solid shape of a compound body (shapes: the shape pool's; s says which they are). */
KG_FN void kg_tile_collide_slot(kg_u32 i, const kg_tile_terrain* t, const kg_tile_bodies* bodies,
                                const kg_tile_bodies* shapes, const kg_shape_arrays* s, kg_tile_contacts* c)
{
    if (s->shape_count[i] <= 1u || !kg_flags_collide(bodies->flags[i])) {
        kg_tile_collide_body(i, t, bodies, c);
        return;
    }
    for (kg_u32 shape = s->first_shape[i]; shape != KG_NULL_INDEX; shape = s->next[shape]) {
        if ((s->flags[shape] & KG_SHAPE_SENSOR) == 0u) { /* a sensor's overlaps with tiles: issue 13, from here */
            kg_tile_collide_shape(i, shape, shape, t, shapes, c);
        }
    }
}

/* Where slot i is now, read by the next pass's one-way platforms (for every slot,
 * colliding or not). */
KG_FN void kg_tile_remember_origin(kg_u32 i, KG_GLOBAL const kg_xf* xf, KG_GLOBAL const kg_u32* generation,
                                   KG_GLOBAL kg_vec2* last_origin, KG_GLOBAL kg_u32* last_generation)
{
    last_origin[i] = xf[i].p;
    last_generation[i] = generation[i];
}

/* The step's contacts once the tile pass's follow the body contacts: the tile contacts
 * within the capacity kept, the rest dropped (the host warns). */
KG_FN kg_u32 kg_contacts_with_tiles(kg_u32 body_contacts, kg_u32 tiles, kg_u32 capacity)
{
    kg_u32 room = capacity - body_contacts;
    return body_contacts + (tiles < room ? tiles : room);
}

/* ---- on the device: one work-item per body slot ---- */

/* The pass's scalars, passed to its kernel by value: kg_tile_terrain's, last step's tile
 * contacts' range, the capacity of the contact list, and whether the pass writes. */
typedef struct kg_tile_pass_params {
    kg_i32 map_count;
    float speculative;
    float linear_slop;
    kg_i32 previous_begin, previous_end;
    kg_u32 capacity;
    kg_i32 write;
} kg_tile_pass_params;

KG_STATIC_ASSERT(sizeof(kg_tile_pass_params) == 28, tile_pass_params_size);

/* Slot i's share of the pass, run twice: counting (run[i] = its contacts), then, after
 * the prefix sum of run, writing them at first + run[i] (those within capacity), and
 * remembering the slot's origin into next_origin and next_generation. */
KG_FN void kg_tile_pass_slot(kg_u32 i, kg_tile_pass_params prm, KG_GLOBAL const kg_tile_map_info* maps,
                             KG_GLOBAL const kg_u32* cells, KG_GLOBAL const kg_tile_proto* protos,
                             KG_GLOBAL const kg_u32* flags, KG_GLOBAL const kg_aabb* aabb, KG_GLOBAL const kg_xf* xf,
                             KG_GLOBAL const kg_shape* shape, KG_GLOBAL const kg_vec2* center,
                             KG_GLOBAL const kg_u32* category, KG_GLOBAL const kg_u32* mask,
                             KG_GLOBAL const kg_u32* generation, KG_GLOBAL const float* friction,
                             KG_GLOBAL const float* restitution, KG_GLOBAL const kg_contact* previous,
                             KG_GLOBAL const kg_vec2* last_origin, KG_GLOBAL const kg_u32* last_generation,
                             KG_GLOBAL kg_vec2* next_origin, KG_GLOBAL kg_u32* next_generation,
                             KG_GLOBAL const kg_u32* first_shape, KG_GLOBAL const kg_u32* shape_count,
                             KG_GLOBAL const kg_u32* shape_next, KG_GLOBAL const kg_u32* shape_flags,
                             KG_GLOBAL const kg_shape* shape_geometry, KG_GLOBAL const kg_u32* shape_category,
                             KG_GLOBAL const kg_u32* shape_mask, KG_GLOBAL const float* shape_friction,
                             KG_GLOBAL const float* shape_restitution, KG_GLOBAL kg_u32* run, kg_u32 first,
                             KG_GLOBAL kg_contact* contacts)
{
    kg_tile_terrain terrain = {maps, cells, protos, prm.map_count, prm.speculative, prm.linear_slop};
    kg_tile_contacts found = {previous, prm.previous_begin, prm.previous_end, contacts,
                              prm.write ? first + run[i] : 0u, prm.write ? prm.capacity : 0u, 0u, 0, 0};
    kg_tile_bodies bodies = {flags, aabb,       xf,       shape,       center,      category,    mask,
                             generation, friction, restitution, last_origin, last_generation, first_shape};
    kg_tile_bodies shapes = {flags,       aabb,           xf,          shape_geometry, center,
                             shape_category, shape_mask,  generation,  shape_friction, shape_restitution,
                             last_origin, last_generation, first_shape};
    kg_shape_arrays arrays = {shape_count, first_shape, shape,       shape_geometry,
                              shape_next,  shape_flags, shape_category, shape_mask};
    kg_tile_collide_slot(i, &terrain, &bodies, &shapes, &arrays, &found);
    if (prm.write) {
        kg_tile_remember_origin(i, xf, generation, next_origin, next_generation);
    } else {
        run[i] = found.found;
    }
}

/* The device's counters after the prefix sum of the tile contacts: the body contacts'
 * count kept, the step's made kg_contacts_with_tiles'. */
KG_FN void kg_count_tile_contacts(KG_GLOBAL kg_u32* contacts, KG_GLOBAL kg_u32* body_contacts, kg_u32 tiles,
                                  kg_u32 capacity)
{
    *body_contacts = *contacts;
    *contacts = kg_contacts_with_tiles(*contacts, tiles, capacity);
}

#endif
