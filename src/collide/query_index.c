#include "collide/query_index.h"
#include "collide/aabb.h"
#include "core/alloc.h"
#include "core/counting_sort.h"
#include "core/error.h"

#include <string.h>

/* Levels above the leaves: 4^15 nodes hold more shapes than a world can have. */
#define KG_QUERY_MAX_LEVELS 16
#define KG_QUERY_STACK (KG_QUERY_MAX_LEVELS * (KG_QUERY_FANOUT - 1) + 2)
#define KG_QUERY_SORT_BITS 8

struct kg_query_index {
    /* what the index was made from: the world as it was then */
    uint64_t step_index;
    kg_u32 pool_writes;
    kg_u32 shape_version;
    int made;

    int count;              /* leaves */
    int capacity;           /* leaves the arrays hold */
    int level_count;        /* levels, leaves included */
    int level_offset[KG_QUERY_MAX_LEVELS + 1]; /* of each level's first node in box */
    kg_aabb* box;           /* every level's node boxes, leaves first */
    kg_u32* leaf;           /* the shape slot of each leaf, Morton order */
    kg_aabb* leaf_box;      /* in slot gathering order, before sorting */
    kg_u32 *keys, *keys_out, *items, *items_out; /* the radix sort's */
};

static size_t kg_node_room(int capacity) { return (size_t)capacity + (size_t)capacity / 2u + KG_QUERY_MAX_LEVELS; }

static void kg_index_free_arrays(kg_query_index* q)
{
    kg_free(q->box);
    kg_free(q->leaf);
    kg_free(q->leaf_box);
    kg_free(q->keys);
    kg_free(q->keys_out);
    kg_free(q->items);
    kg_free(q->items_out);
}

void kg_query_index_destroy(kg_query_index* index)
{
    if (index) {
        kg_index_free_arrays(index);
        kg_free(index);
    }
}

int kg_query_index_count(const kg_query_index* index) { return index->count; }

/* Room for capacity leaves (half again what is asked, so a growing world reallocates
 * rarely); the index is left empty, to be made. */
static kg_result kg_index_reserve(kg_query_index* q, int needed)
{
    if (needed <= q->capacity) {
        return KG_OK;
    }
    int capacity = needed + needed / 2;
    kg_query_index grown = *q;
    grown.box = kg_alloc_zeroed(kg_node_room(capacity) * sizeof *grown.box);
    grown.leaf = kg_alloc_zeroed((size_t)capacity * sizeof *grown.leaf);
    grown.leaf_box = kg_alloc_zeroed((size_t)capacity * sizeof *grown.leaf_box);
    grown.keys = kg_alloc_zeroed((size_t)capacity * sizeof *grown.keys);
    grown.keys_out = kg_alloc_zeroed((size_t)capacity * sizeof *grown.keys_out);
    grown.items = kg_alloc_zeroed((size_t)capacity * sizeof *grown.items);
    grown.items_out = kg_alloc_zeroed((size_t)capacity * sizeof *grown.items_out);
    if (!grown.box || !grown.leaf || !grown.leaf_box || !grown.keys || !grown.keys_out || !grown.items ||
        !grown.items_out) {
        kg_index_free_arrays(&grown);
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "query index: cannot hold %d shapes", needed);
    }
    kg_index_free_arrays(q);
    grown.capacity = capacity;
    *q = grown;
    return KG_OK;
}

/* Gathers every live shape with finite bounds: its slot in items, its fattened bounds in
 * leaf_box, in body order then the body's shape order. */
static int kg_gather_shapes(kg_query_index* q, const kg_world* world)
{
    const kg_body_pool* p = &world->bodies;
    const kg_shape_pool* sp = &world->shapes;
    int n = 0;
    for (int i = 0; i < p->high_water; ++i) {
        if (!kg_pool_alive(p, i)) {
            continue;
        }
        for (kg_u32 s = p->first_shape[i]; s != KG_NULL_INDEX; s = sp->next[s]) {
            kg_aabb box = kg_aabb_fatten(kg_shape_aabb(kg_shape_geometry(p, sp, s), p->xf[i]), KG_QUERY_MARGIN);
            if (kg_vec_is_finite(box.lower) && kg_vec_is_finite(box.upper)) {
                q->items[n] = s;
                q->leaf_box[n] = box;
                n++;
            }
        }
    }
    return n;
}

/* 16 bits of x and y interleaved, x in the even bits. */
static kg_u32 kg_spread_bits(kg_u32 v)
{
    v &= 0xFFFFu;
    v = (v | (v << 8)) & 0x00FF00FFu;
    v = (v | (v << 4)) & 0x0F0F0F0Fu;
    v = (v | (v << 2)) & 0x33333333u;
    v = (v | (v << 1)) & 0x55555555u;
    return v;
}

static kg_vec2 kg_box_center(kg_aabb b) { return kg_scale(0.5f, kg_add(b.lower, b.upper)); }

static float kg_quantum(float lo, float hi) { return hi > lo ? 65535.0f / (hi - lo) : 0.0f; }

/* A coordinate's cell in [0, 65535]; 0 for what is not in it (a frozen body's non-finite
 * box: NaN fails both tests), whose leaf then sorts first and overlaps no query. */
static kg_u32 kg_cell_of(float offset, float quantum)
{
    float cell = offset * quantum;
    return cell >= 0.0f && cell <= 65535.0f ? (kg_u32)cell : 0u;
}

/* keys[k]: the Morton code of leaf k's centre over the centres' extent; items[k] its
 * index among the gathered leaves. */
static void kg_morton_keys(kg_query_index* q, int n)
{
    kg_aabb extent;
    extent.lower = extent.upper = kg_box_center(q->leaf_box[0]);
    for (int k = 1; k < n; ++k) {
        kg_vec2 c = kg_box_center(q->leaf_box[k]);
        extent.lower = kg_vmin(extent.lower, c);
        extent.upper = kg_vmax(extent.upper, c);
    }
    float sx = kg_quantum(extent.lower.x, extent.upper.x), sy = kg_quantum(extent.lower.y, extent.upper.y);
    for (int k = 0; k < n; ++k) {
        kg_vec2 c = kg_box_center(q->leaf_box[k]);
        kg_u32 x = kg_cell_of(c.x - extent.lower.x, sx), y = kg_cell_of(c.y - extent.lower.y, sy);
        q->keys[k] = kg_spread_bits(x) | (kg_spread_bits(y) << 1);
        q->leaf[k] = q->items[k]; /* the slots, until the sort orders them */
        q->items[k] = (kg_u32)k;
    }
}

/* A stable LSD radix sort of (keys, items), one chunk (core/counting_sort.h). */
static void kg_sort_keys(kg_query_index* q, int n)
{
    kg_u32 counts[1u << KG_QUERY_SORT_BITS];
    for (int shift = 0; shift < 32; shift += KG_QUERY_SORT_BITS) {
        kg_sort_count_chunk(q->keys, n, n, 0, 1, shift, KG_QUERY_SORT_BITS, counts);
        kg_u32 sum = 0u;
        for (int d = 0; d < 1 << KG_QUERY_SORT_BITS; ++d) {
            kg_u32 c = counts[d];
            counts[d] = sum;
            sum += c;
        }
        kg_sort_scatter_chunk(q->keys, q->items, n, n, 0, 1, shift, KG_QUERY_SORT_BITS, counts, q->keys_out,
                              q->items_out);
        kg_u32* t = q->keys;
        q->keys = q->keys_out;
        q->keys_out = t;
        t = q->items;
        q->items = q->items_out;
        q->items_out = t;
    }
}

static kg_aabb kg_box_union(kg_aabb a, kg_aabb b)
{
    kg_aabb u;
    u.lower = kg_vmin(a.lower, b.lower);
    u.upper = kg_vmax(a.upper, b.upper);
    return u;
}

/* Leaves in sorted order, then each level's nodes over the one below. */
static void kg_build_levels(kg_query_index* q, int n)
{
    for (int k = 0; k < n; ++k) {
        kg_u32 from = q->items[k];
        q->box[k] = q->leaf_box[from];
        q->items_out[k] = q->leaf[from];
    }
    memcpy(q->leaf, q->items_out, (size_t)n * sizeof *q->leaf);
    q->level_offset[0] = 0;
    q->level_count = 1;
    int below = n;
    while (below > 1) {
        int first = q->level_offset[q->level_count - 1], at = first + below;
        int nodes = (below + KG_QUERY_FANOUT - 1) / KG_QUERY_FANOUT;
        for (int j = 0; j < nodes; ++j) {
            int c = first + j * KG_QUERY_FANOUT, end = c + KG_QUERY_FANOUT < at ? c + KG_QUERY_FANOUT : at;
            kg_aabb u = q->box[c];
            for (++c; c < end; ++c) {
                u = kg_box_union(u, q->box[c]);
            }
            q->box[at + j] = u;
        }
        q->level_offset[q->level_count++] = at;
        below = nodes;
    }
    q->level_offset[q->level_count] = q->level_offset[q->level_count - 1] + 1;
}

static int kg_index_is_current(const kg_query_index* q, const kg_world* world)
{
    return q->made && q->step_index == world->step_index && q->pool_writes == world->pool_writes &&
           q->shape_version == world->shapes.version;
}

const kg_query_index* kg_query_index_current(kg_world* world)
{
    if (!world->query_index) {
        world->query_index = kg_alloc_zeroed(sizeof *world->query_index);
        if (!world->query_index) {
            kg_fail(KG_ERROR_OUT_OF_MEMORY, "query index");
            return NULL;
        }
    }
    kg_query_index* q = world->query_index;
    if (kg_index_is_current(q, world)) {
        return q;
    }
    if (kg_index_reserve(q, world->shapes.count > 0 ? world->shapes.count : 1) != KG_OK) {
        return NULL;
    }
    int n = kg_gather_shapes(q, world);
    q->count = n;
    q->level_count = 0;
    if (n > 0) {
        kg_morton_keys(q, n);
        kg_sort_keys(q, n);
        kg_build_levels(q, n);
    }
    q->step_index = world->step_index;
    q->pool_writes = world->pool_writes;
    q->shape_version = world->shapes.version;
    q->made = 1;
    return q;
}

void kg_query_index_search(const kg_query_index* index, kg_query_box_test* test, const void* test_ctx,
                           kg_query_leaf_fn* leaf, void* leaf_ctx)
{
    if (index->count == 0) {
        return;
    }
    /* (level, node) pairs; children pushed last first, so they come off in order */
    int level[KG_QUERY_STACK], node[KG_QUERY_STACK];
    int top = 0;
    level[0] = index->level_count - 1;
    node[0] = 0;
    top = 1;
    while (top > 0) {
        --top;
        int l = level[top], j = node[top];
        if (!test(index->box[index->level_offset[l] + j], test_ctx)) {
            continue;
        }
        if (l == 0) {
            if (!leaf(index->leaf[j], leaf_ctx)) {
                return;
            }
            continue;
        }
        int below = index->level_offset[l] - index->level_offset[l - 1];
        int first = j * KG_QUERY_FANOUT, end = first + KG_QUERY_FANOUT < below ? first + KG_QUERY_FANOUT : below;
        for (int c = end - 1; c >= first; --c) {
            level[top] = l - 1;
            node[top] = c;
            top++;
        }
    }
}
