#include "collide/shape_index.h"
#include "collide/sorted_shapes.h"
#include "collide/aabb.h"
#include "collide/collide.h"
#include "core/alloc.h"
#include "core/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* What the CPU keeps of an indexed body beside its span. */
typedef struct kg_indexed_body {
    kg_u32 body;
    kg_xf xf; /* the pose its entries were made at */
} kg_indexed_body;

struct kg_shape_index {
    int built;
    kg_u32 version;          /* the shape pool's, when built */
    int* of_body;            /* per body slot: its span, or -1 */
    int of_body_room;
    kg_indexed_body* bodies; /* per span */
    kg_sorted_span* spans;
    int body_count, body_room, span_room;
    kg_sorted_shape* entries;
    int entry_room;
    kg_u32* found;           /* a search's shapes */
    int found_room;
};

kg_shape_index* kg_shape_index_create(void) { return kg_alloc_zeroed(sizeof(kg_shape_index)); }

void kg_shape_index_destroy(kg_shape_index* index)
{
    if (index) {
        kg_free(index->of_body);
        kg_free(index->bodies);
        kg_free(index->spans);
        kg_free(index->entries);
        kg_free(index->found);
        kg_free(index);
    }
}

/* *buffer with room for at least need items of size bytes (contents not kept). */
static int kg_room(void** buffer, int* room, int need, size_t size)
{
    if (*room >= need) {
        return 1;
    }
    int grown = need + need / 2 + 16;
    void* fresh = kg_alloc_zeroed((size_t)grown * size);
    if (!fresh) {
        return 0;
    }
    kg_free(*buffer);
    *buffer = fresh;
    *room = grown;
    return 1;
}

/* By lower bound, then slot: a total order, so the same bounds sort the same way. One
 * comparison an axis: qsort passes no context, and a global would be shared by worlds
 * stepped on different threads. */
static int kg_by_lower(float la, float lb, kg_u32 sa, kg_u32 sb)
{
    return la < lb ? -1 : la > lb ? 1 : (sa > sb) - (sa < sb);
}

static int kg_by_lower_x(const void* l, const void* r)
{
    const kg_sorted_shape *a = l, *b = r;
    return kg_by_lower(a->box.lower.x, b->box.lower.x, a->slot, b->slot);
}

static int kg_by_lower_y(const void* l, const void* r)
{
    const kg_sorted_shape *a = l, *b = r;
    return kg_by_lower(a->box.lower.y, b->box.lower.y, a->slot, b->slot);
}

/* Span k's entries at its body's current pose, sorted, and their reach. */
static void kg_fill_body(kg_shape_index* index, const kg_world* world, int k)
{
    const kg_shape_pool* sp = &world->shapes;
    kg_indexed_body* ib = &index->bodies[k];
    kg_sorted_span* span = &index->spans[k];
    kg_xf xf = world->bodies.xf[ib->body];
    kg_sorted_shape* e = index->entries + span->first;
    kg_aabb all = {{INFINITY, INFINITY}, {-INFINITY, -INFINITY}};
    int n = 0;
    for (kg_u32 s = world->bodies.first_shape[ib->body]; s != KG_NULL_INDEX; s = sp->next[s], ++n) {
        memset(&e[n], 0, sizeof e[n]);
        e[n].box = kg_shape_aabb(&sp->geometry[s], xf);
        e[n].slot = s;
        all.lower = kg_vmin(all.lower, e[n].box.lower);
        all.upper = kg_vmax(all.upper, e[n].box.upper);
    }
    ib->xf = xf;
    span->axis = all.upper.y - all.lower.y > all.upper.x - all.lower.x;
    qsort(e, (size_t)span->count, sizeof *e, span->axis ? kg_by_lower_y : kg_by_lower_x);
    for (n = 0; n < span->count; ++n) {
        float upper = kg_upper_on(e[n].box, span->axis);
        e[n].reach = n > 0 && e[n - 1].reach > upper ? e[n - 1].reach : upper;
    }
}

/* Every body with KG_INDEXED_SHAPES shapes or more, indexed afresh. */
static kg_result kg_rebuild(kg_shape_index* index, const kg_world* world)
{
    const kg_body_pool* p = &world->bodies;
    int bodies = 0, entries = 0;
    for (int i = 0; i < p->high_water; ++i) {
        if (kg_pool_alive(p, i) && p->shape_count[i] >= KG_INDEXED_SHAPES) {
            bodies += 1;
            entries += (int)p->shape_count[i];
        }
    }
    if (!kg_room((void**)&index->of_body, &index->of_body_room, p->high_water, sizeof *index->of_body) ||
        !kg_room((void**)&index->bodies, &index->body_room, bodies, sizeof *index->bodies) ||
        !kg_room((void**)&index->spans, &index->span_room, bodies, sizeof *index->spans) ||
        !kg_room((void**)&index->entries, &index->entry_room, entries, sizeof *index->entries) ||
        !kg_room((void**)&index->found, &index->found_room, entries, sizeof *index->found)) {
        index->built = 0;
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot index the shapes of %d bodies (%d shapes)", bodies, entries);
    }
    index->body_count = 0;
    int first = 0;
    for (int i = 0; i < p->high_water; ++i) {
        int indexed = kg_pool_alive(p, i) && p->shape_count[i] >= KG_INDEXED_SHAPES;
        index->of_body[i] = indexed ? index->body_count : -1;
        if (indexed) {
            int k = index->body_count++;
            index->bodies[k].body = (kg_u32)i;
            kg_sorted_span span = {first, (int)p->shape_count[i], 0, 0};
            index->spans[k] = span;
            first += span.count;
            kg_fill_body(index, world, k);
        }
    }
    index->built = 1;
    index->version = world->shapes.version;
    return KG_OK;
}

void kg_shape_index_forget(kg_shape_index* index)
{
    if (index) {
        index->built = 0;
    }
}

kg_result kg_shape_index_update(kg_shape_index* index, const kg_world* world)
{
    if (!index->built || index->version != world->shapes.version || index->of_body_room < world->bodies.high_water) {
        return kg_rebuild(index, world);
    }
    for (int k = 0; k < index->body_count; ++k) {
        const kg_indexed_body* ib = &index->bodies[k];
        if (memcmp(&ib->xf, &world->bodies.xf[ib->body], sizeof ib->xf) != 0) { /* a kinematic body moved */
            kg_fill_body(index, world, k);
        }
    }
    return KG_OK;
}

static int kg_by_slot(const void* l, const void* r)
{
    kg_u32 a = *(const kg_u32*)l, b = *(const kg_u32*)r;
    return (a > b) - (a < b);
}

/* The shapes of span k whose bounds may reach box (on its axis; the caller tests the
 * rest), into found sorted, as a body's list of shapes runs; returns how many. */
static int kg_search(const kg_shape_index* index, int k, kg_aabb box, kg_u32* found)
{
    const kg_sorted_shape* e = index->entries;
    kg_sorted_span span = index->spans[k];
    int n = 0;
    for (int j = kg_sorted_end(e, span, box) - 1; kg_sorted_may_reach(e, j, span, box); --j) {
        if (kg_sorted_reaches(e, j, span, box)) {
            found[n++] = e[j].slot;
        }
    }
    qsort(found, (size_t)n, sizeof *found, kg_by_slot);
    return n;
}

/* a indexed: its shapes that reach b's bounds, each against b's shapes as they run. */
static int kg_expand_from_a(kg_shape_index* index, const kg_world* world, const kg_shape_arrays* s, kg_u32 a,
                            kg_u32 b, float margin, kg_shape_pair* out, int room)
{
    const kg_body_pool* p = &world->bodies;
    kg_u32* found = index->found;
    int count = kg_search(index, index->of_body[a], kg_aabb_fatten(p->aabb[b], margin), found);
    int n = 0;
    for (int k = 0; k < count; ++k) {
        kg_u32 sa = found[k];
        kg_aabb box_a = kg_shape_reach(s, a, sa, p->xf[a], margin);
        if (!kg_aabb_overlap(box_a, p->aabb[b])) {
            continue;
        }
        for (kg_u32 sb = s->first_shape[b]; sb != KG_NULL_INDEX; sb = s->next[sb]) {
            kg_offer_shape_pair(s, box_a, kg_shape_of(s, b, sb), p->xf[b], a, b, sa, sb, out, room, &n);
        }
    }
    return n;
}

/* b indexed: each shape of a that reaches b's bounds, against b's shapes that reach it. */
static int kg_expand_to_b(kg_shape_index* index, const kg_world* world, const kg_shape_arrays* s, kg_u32 a,
                          kg_u32 b, float margin, kg_shape_pair* out, int room)
{
    const kg_body_pool* p = &world->bodies;
    kg_u32* found = index->found;
    int n = 0;
    for (kg_u32 sa = s->first_shape[a]; sa != KG_NULL_INDEX; sa = s->next[sa]) {
        kg_aabb box_a = kg_shape_reach(s, a, sa, p->xf[a], margin);
        if (!kg_aabb_overlap(box_a, p->aabb[b])) {
            continue;
        }
        int count = kg_search(index, index->of_body[b], box_a, found);
        for (int k = 0; k < count; ++k) {
            kg_offer_shape_pair(s, box_a, kg_shape_of(s, b, found[k]), p->xf[b], a, b, sa, found[k], out, room, &n);
        }
    }
    return n;
}

int kg_shape_index_expand(kg_shape_index* index, const kg_world* world, kg_u32 a, kg_u32 b, kg_shape_pair* out,
                          int room)
{
    const kg_body_pool* p = &world->bodies;
    kg_shape_arrays s = kg_world_shape_arrays(world);
    float spec = world->def.speculative_distance, dt = world->last_dt;
    if (index->of_body[a] < 0 && index->of_body[b] < 0) {
        return kg_expand_pair(a, b, &s, p->xf, p->velocity, p->aabb, spec, dt, out, room);
    }
    float margin = kg_pair_speculative(spec, p->velocity[a], p->velocity[b], dt);
    return index->of_body[a] >= 0 ? kg_expand_from_a(index, world, &s, a, b, margin, out, room)
                                  : kg_expand_to_b(index, world, &s, a, b, margin, out, room);
}

int kg_shape_index_current(const kg_shape_index* index, const kg_world* world)
{
    return index->built && index->version == world->shapes.version && index->body_count > 0;
}

void kg_shape_index_arrays(const kg_shape_index* index, const int** of_body, const kg_sorted_span** spans,
                           const kg_sorted_shape** shapes)
{
    *of_body = index->of_body;
    *spans = index->spans;
    *shapes = index->entries;
}
