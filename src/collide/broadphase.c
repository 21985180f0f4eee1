#include "collide/broadphase.h"
#include "collide/aabb.h"
#include "core/alloc.h"
#include "core/counting_sort.h"
#include "core/prefix_sum.h"
#include "core/error.h"

#include <assert.h>
#include <limits.h>
#include <stdint.h>
#include <string.h>

/* Radix sort digits: 11 bits, so 32-bit keys take at most 3 passes and a histogram
 * (8 KiB) stays in L1. */
#define KG_RADIX_BITS 11
#define KG_RADIX_BUCKETS (1 << KG_RADIX_BITS)

/* Box extents are binned by their float bits >> 20: exponent plus 3 mantissa bits, so a
 * bin is at most 12.5% wide and a non-negative float falls in one of 2048 bins. */
#define KG_EXTENT_SHIFT 20
#define KG_EXTENT_BINS 2048

/* The cell size is the upper edge of the extent bin holding this quantile: 90% of the
 * boxes are small; the rest are few enough to handle one by one. */
#define KG_SMALL_QUANTILE 0.9

/* Cells never get smaller than this (m), so boxes of no size (particles without a margin)
 * still make a grid of sane resolution. */
#define KG_MIN_CELL_SIZE 1.0e-6f

/* Cells per axis stay exactly representable as floats, and the key fits 32 bits. */
#define KG_MAX_AXIS_BITS 24
#define KG_MAX_KEY_BITS 32

/* Runs of pairs up to this length are insertion sorted; longer ones radix sorted. */
#define KG_SHORT_RUN 32

/* A candidate body: its fattened box and what the pair test needs, 32 bytes. */
typedef struct kg_proxy {
    kg_aabb box;
    kg_u32 body;
    kg_u32 category;
    kg_u32 mask;
    kg_u32 moves; /* dynamic or particle */
} kg_proxy;

/* What the last search saw of a slot, all that decides its pairs: its fattened box, the
 * filter, and whether it took part (KG_SEEN_OUT: dead or not finite) and moves. */
typedef struct kg_seen {
    kg_aabb box;
    kg_u32 category;
    kg_u32 mask;
    kg_u32 state;
    kg_u32 pad;
} kg_seen;

#define KG_SEEN_OUT 0u
#define KG_SEEN_STILL 1u
#define KG_SEEN_MOVES 2u

typedef struct kg_grid {
    kg_vec2 origin;
    float cell_size;
    float inv_cell_size;
    kg_u32 width, height; /* cells; coordinates outside are clamped to the border cells */
    kg_u32 x_bits;        /* key = (row << x_bits) | column */
} kg_grid;

typedef enum kg_emit_mode {
    KG_EMIT_COUNT, /* count the pairs of each lower slot, and write them in discovery order
                    * while they fit the output */
    KG_EMIT_FILL   /* write them at their place in the output (they did not all fit) */
} kg_emit_mode;

struct kg_broadphase {
    int capacity;
    kg_grid grid;
    kg_proxy* proxies;     /* candidates, in slot order; after kg_broadphase_covers, indexed
                            * by slot (the boxes kg_broadphase_keep_pairs tests) */
    kg_proxy* sorted;      /* small proxies, in key order */
    int proxy_count;
    int small_count;
    int large_count;
    kg_u32* keys;          /* cell keys of the small proxies, sorted */
    kg_u32* items;         /* proxy index of each key */
    kg_u32* large_keys;    /* lower x of the large proxies (sortable bits), sorted */
    kg_u32* large_items;   /* proxy index of each large key */
    kg_u32* key_scratch;
    kg_u32* item_scratch;
    /* One slot's partners, when its run must be sorted apart: the two scratch buffers
     * above, free once the proxies are sorted (not allocated apart). */
    kg_u32* partners;
    kg_u32* partner_scratch;
    int* run_count;        /* per lower slot: how many pairs */
    int* run_start;        /* per lower slot: first output index, saturated at INT_MAX */
    int* run_next;         /* per lower slot: next output index while filling */
    kg_seen* seen;         /* per slot: what the last search saw */
    int seen_count;        /* slots the last search looked at */
    kg_u32 histogram[KG_RADIX_BUCKETS + 1]; /* and the prefix sum's total */

    /* the pair sink of the current pass */
    kg_emit_mode mode;
    int64_t total;
    kg_pair* out;
    int out_capacity;
    kg_u32 split_slot;     /* the slot whose run straddles out_capacity, or UINT32_MAX */
    int partner_count;
};

kg_result kg_broadphase_create(int capacity, kg_broadphase** out)
{
    *out = NULL;
    if (capacity < 0) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "broadphase capacity %d must be >= 0", capacity);
    }
    kg_broadphase* bp = kg_alloc_zeroed(sizeof *bp);
    if (!bp) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the broadphase");
    }
    bp->capacity = capacity;
    size_t n = (size_t)capacity;
    bp->proxies = kg_alloc_zeroed(n * sizeof *bp->proxies);
    bp->sorted = kg_alloc_zeroed(n * sizeof *bp->sorted);
    bp->keys = kg_alloc_zeroed(n * sizeof *bp->keys);
    bp->items = kg_alloc_zeroed(n * sizeof *bp->items);
    bp->large_keys = kg_alloc_zeroed(n * sizeof *bp->large_keys);
    bp->large_items = kg_alloc_zeroed(n * sizeof *bp->large_items);
    bp->key_scratch = kg_alloc_zeroed(n * sizeof *bp->key_scratch);
    bp->item_scratch = kg_alloc_zeroed(n * sizeof *bp->item_scratch);
    bp->run_count = kg_alloc_zeroed(n * sizeof *bp->run_count);
    bp->run_start = kg_alloc_zeroed(n * sizeof *bp->run_start);
    bp->run_next = kg_alloc_zeroed(n * sizeof *bp->run_next);
    bp->seen = kg_alloc_zeroed(n * sizeof *bp->seen);
    if (!bp->proxies || !bp->sorted || !bp->keys || !bp->items || !bp->large_keys || !bp->large_items ||
        !bp->key_scratch || !bp->item_scratch || !bp->run_count || !bp->run_start || !bp->run_next || !bp->seen) {
        kg_broadphase_destroy(bp);
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate a broadphase for %d bodies", capacity);
    }
    *out = bp;
    return KG_OK;
}

void kg_broadphase_destroy(kg_broadphase* bp)
{
    if (!bp) {
        return;
    }
    kg_free(bp->proxies);
    kg_free(bp->sorted);
    kg_free(bp->keys);
    kg_free(bp->items);
    kg_free(bp->large_keys);
    kg_free(bp->large_items);
    kg_free(bp->key_scratch);
    kg_free(bp->item_scratch);
    kg_free(bp->run_count);
    kg_free(bp->run_start);
    kg_free(bp->run_next);
    kg_free(bp->seen);
    kg_free(bp);
}

kg_broadphase_stats kg_broadphase_get_stats(const kg_broadphase* bp)
{
    kg_broadphase_stats stats;
    stats.cell_size = bp->grid.cell_size;
    stats.small_count = bp->small_count;
    stats.large_count = bp->large_count;
    return stats;
}

/* ---- radix sort ---- */

/* Stable LSD radix sort of count keys on their low key_bits bits, carrying items along:
 * counting-sort passes of one chunk (core/counting_sort.h, the device's passes too).
 * Ping-pongs with the scratch buffers and swaps the pointers, so the result is always in
 * *keys. A pass whose digit is the same for every key is skipped. */
static void kg_radix_sort(kg_u32** keys, kg_u32** items, kg_u32** key_scratch, kg_u32** item_scratch,
                          int count, int key_bits, kg_u32* histogram)
{
    for (int shift = 0; shift < key_bits; shift += KG_RADIX_BITS) {
        if (count == 0) {
            return;
        }
        kg_sort_count_chunk(*keys, count, count, 0, shift, KG_RADIX_BITS, histogram);
        if (histogram[kg_sort_digit((*keys)[0], shift, KG_RADIX_BITS)] == (kg_u32)count) {
            continue;
        }
        kg_scan_block_apply(histogram, histogram, KG_RADIX_BUCKETS, KG_RADIX_BUCKETS, 0, NULL);
        kg_sort_scatter_chunk(*keys, *items, count, count, 0, shift, KG_RADIX_BITS, histogram, *key_scratch,
                              *item_scratch);
        kg_u32* t = *key_scratch;
        *key_scratch = *keys;
        *keys = t;
        t = *item_scratch;
        *item_scratch = *items;
        *items = t;
    }
}

/* Bits of a float made unsigned-comparable in the same order as the floats. */
static kg_u32 kg_sortable_bits(float v)
{
    kg_u32 bits;
    memcpy(&bits, &v, sizeof bits);
    return (bits & 0x80000000u) ? ~bits : (bits | 0x80000000u);
}

/* Bits needed to number count things (0 for one thing). */
static kg_u32 kg_bits_for(kg_u32 count)
{
    kg_u32 bits = 0;
    while (bits < 32 && (count - 1) >> bits != 0) {
        bits += 1;
    }
    return bits;
}

/* ---- gathering and grid ---- */

/* Plain comparisons instead of fminf/fmaxf, which compile to library calls here. */
static float kg_min(float a, float b) { return a < b ? a : b; }
static float kg_max(float a, float b) { return a > b ? a : b; }

static float kg_extent(kg_aabb box)
{
    float e = kg_max(box.upper.x - box.lower.x, box.upper.y - box.lower.y);
    return e > 0.0f ? e : 0.0f;
}

static kg_u32 kg_extent_bin(float extent)
{
    kg_u32 bits;
    memcpy(&bits, &extent, sizeof bits);
    return bits >> KG_EXTENT_SHIFT;
}

static kg_seen kg_seen_of(const kg_proxy* p)
{
    kg_seen s;
    s.box = p->box;
    s.category = p->category;
    s.mask = p->mask;
    s.state = p->moves ? KG_SEEN_MOVES : KG_SEEN_STILL;
    s.pad = 0u;
    return s;
}

/* Copies the candidates out of the pool, bins their extents into the histogram and notes
 * what it saw of each slot. */
static void kg_gather_proxies(kg_broadphase* bp, const kg_body_pool* bodies, float margin)
{
    memset(bp->histogram, 0, sizeof bp->histogram);
    int n = 0;
    bp->seen_count = bodies->high_water;
    for (int i = 0; i < bodies->high_water; ++i) {
        bp->run_count[i] = 0;
        bp->seen[i].state = KG_SEEN_OUT;
        kg_aabb box;
        if (!kg_broadphase_box(bodies->flags[i], bodies->aabb[i], margin, &box)) {
            continue;
        }
        kg_proxy* p = &bp->proxies[n++];
        p->box = box;
        p->body = (kg_u32)i;
        p->category = bodies->category[i];
        p->mask = bodies->mask[i];
        p->moves = (kg_u32)kg_flags_collide(bodies->flags[i]);
        bp->seen[i] = kg_seen_of(p);
        bp->histogram[kg_extent_bin(kg_extent(box))] += 1;
    }
    bp->proxy_count = n;
}

/* The upper edge of the extent bin holding the small quantile: most boxes are below it. */
static float kg_small_extent(const kg_u32* histogram, int count)
{
    kg_u32 target = (kg_u32)(KG_SMALL_QUANTILE * count);
    if (target == 0) {
        target = 1;
    }
    kg_u32 seen = 0;
    kg_u32 bin = 0;
    while (bin + 1 < KG_EXTENT_BINS && seen + histogram[bin] < target) {
        seen += histogram[bin];
        bin += 1;
    }
    kg_u32 edge_bits = (bin + 1) << KG_EXTENT_SHIFT;
    float edge;
    memcpy(&edge, &edge_bits, sizeof edge);
    /* past the largest float when most boxes are infinitely wide */
    return kg_is_finite(edge) ? edge : KG_FLT_MAX;
}

static kg_u32 kg_cell_coord(float v, float origin, float inv_cell_size, kg_u32 cells)
{
    /* Every step here is monotone in v (clamping too), which the neighbour argument needs.
     * The clamp is written so that a NaN lands in cell 0. */
    float f = floorf((v - origin) * inv_cell_size);
    f = f > 0.0f ? f : 0.0f;
    return (kg_u32)kg_min(f, (float)(cells - 1));
}

static kg_u32 kg_cell_x(const kg_grid* g, float x)
{
    return kg_cell_coord(x, g->origin.x, g->inv_cell_size, g->width);
}

static kg_u32 kg_cell_y(const kg_grid* g, float y)
{
    return kg_cell_coord(y, g->origin.y, g->inv_cell_size, g->height);
}

static kg_u32 kg_cell_key(const kg_grid* g, kg_u32 cx, kg_u32 cy) { return (cy << g->x_bits) | cx; }

/* Cells from lower to upper, or one more than the axis allows. In double, because the
 * span of two finite floats may overflow a float. */
static kg_u32 kg_axis_cells(float lower, float upper, float cell_size)
{
    double cells = floor(((double)upper - (double)lower) / (double)cell_size) + 1.0;
    double limit = (double)(1u << KG_MAX_AXIS_BITS);
    return cells < limit ? (kg_u32)cells : (1u << KG_MAX_AXIS_BITS) + 1u;
}

/* Sizes the grid over the lower corners of the boxes below the small extent, doubling
 * the cells until a key fits 32 bits. Only worlds spanning more than 2^32 cells need it,
 * and it ends: any span of finite floats fits 2^16 cells before the size overflows. */
static void kg_build_grid(kg_broadphase* bp)
{
    float cell_size = kg_max(kg_small_extent(bp->histogram, bp->proxy_count), KG_MIN_CELL_SIZE);
    kg_vec2 lower = kg_v2(KG_FLT_MAX, KG_FLT_MAX);
    kg_vec2 upper = kg_v2(-KG_FLT_MAX, -KG_FLT_MAX);
    for (int i = 0; i < bp->proxy_count; ++i) {
        kg_aabb box = bp->proxies[i].box;
        if (kg_extent(box) < cell_size) {
            lower = kg_v2(kg_min(lower.x, box.lower.x), kg_min(lower.y, box.lower.y));
            upper = kg_v2(kg_max(upper.x, box.lower.x), kg_max(upper.y, box.lower.y));
        }
    }
    if (lower.x > upper.x) {
        /* every box is infinitely wide: one cell at the origin holds them all */
        lower = kg_v2(0.0f, 0.0f);
        upper = lower;
    }
    kg_grid* g = &bp->grid;
    g->origin = lower;
    for (;;) {
        g->cell_size = cell_size;
        g->inv_cell_size = 1.0f / cell_size;
        g->width = kg_axis_cells(lower.x, upper.x, cell_size);
        g->height = kg_axis_cells(lower.y, upper.y, cell_size);
        kg_u32 x_bits = kg_bits_for(g->width);
        kg_u32 y_bits = kg_bits_for(g->height);
        if (x_bits <= KG_MAX_AXIS_BITS && y_bits <= KG_MAX_AXIS_BITS && x_bits + y_bits <= KG_MAX_KEY_BITS) {
            g->x_bits = x_bits;
            return;
        }
        cell_size *= 2.0f;
    }
}

/* Keys the boxes spanning at most 2x2 cells by their lower corner's cell; lists the rest
 * as large. Both lists come out in slot order, which keeps the sorts deterministic. */
static void kg_classify_proxies(kg_broadphase* bp)
{
    const kg_grid* g = &bp->grid;
    int small = 0, large = 0;
    for (int i = 0; i < bp->proxy_count; ++i) {
        kg_aabb box = bp->proxies[i].box;
        kg_u32 x0 = kg_cell_x(g, box.lower.x), x1 = kg_cell_x(g, box.upper.x);
        kg_u32 y0 = kg_cell_y(g, box.lower.y), y1 = kg_cell_y(g, box.upper.y);
        if (x1 - x0 <= 1 && y1 - y0 <= 1) {
            bp->keys[small] = kg_cell_key(g, x0, y0);
            bp->items[small] = (kg_u32)i;
            small += 1;
        } else {
            bp->large_keys[large] = kg_sortable_bits(box.lower.x);
            bp->large_items[large] = (kg_u32)i;
            large += 1;
        }
    }
    bp->small_count = small;
    bp->large_count = large;
}

static void kg_sort_proxies(kg_broadphase* bp)
{
    int key_bits = (int)(bp->grid.x_bits + kg_bits_for(bp->grid.height));
    kg_radix_sort(&bp->keys, &bp->items, &bp->key_scratch, &bp->item_scratch, bp->small_count, key_bits,
                  bp->histogram);
    /* Copied in key order so the neighbour scans below read memory front to back. */
    for (int i = 0; i < bp->small_count; ++i) {
        bp->sorted[i] = bp->proxies[bp->items[i]];
    }
    kg_radix_sort(&bp->large_keys, &bp->large_items, &bp->key_scratch, &bp->item_scratch, bp->large_count,
                  32, bp->histogram);
}

/* ---- pair search ---- */

/* Writes a pair at the next place of its run, unless the run lies beyond the capacity. */
static void kg_place_pair(kg_broadphase* bp, kg_u32 a, kg_u32 b)
{
    if (a == bp->split_slot) {
        bp->partners[bp->partner_count++] = b;
    } else if (bp->run_next[a] < bp->out_capacity) {
        kg_pair* pair = &bp->out[bp->run_next[a]++];
        pair->a = a;
        pair->b = b;
    }
}

static void kg_emit(kg_broadphase* bp, kg_u32 p, kg_u32 q)
{
    kg_u32 a = p < q ? p : q;
    kg_u32 b = p < q ? q : p;
    if (bp->mode == KG_EMIT_FILL) {
        kg_place_pair(bp, a, b);
        return;
    }
    if (bp->total < bp->out_capacity) {
        bp->out[bp->total].a = a;
        bp->out[bp->total].b = b;
    }
    bp->run_count[a] += 1;
    bp->total += 1;
}

static void kg_consider(kg_broadphase* bp, const kg_proxy* p, const kg_proxy* q)
{
    if (kg_boxes_pair((int)p->moves, p->box, p->category, p->mask, (int)q->moves, q->box, q->category, q->mask)) {
        kg_emit(bp, p->body, q->body);
    }
}

/* Two overlapping small boxes have lower-corner cells at most one apart per axis (the cell
 * map is monotone and a small box spans at most one cell boundary per axis). So each entry
 * scans the rest of its cell, the cell on its right and the three cells above: every
 * neighbouring couple once. Rows above are found with a cursor that only moves forward,
 * because the first key of the row-above range grows with the entry's key. */
static void kg_find_small_pairs(kg_broadphase* bp)
{
    const kg_grid* g = &bp->grid;
    const kg_u32* keys = bp->keys;
    const kg_proxy* sorted = bp->sorted;
    int n = bp->small_count;
    kg_u32 column_mask = (1u << g->x_bits) - 1u;
    int above = 0;
    for (int i = 0; i < n; ++i) {
        kg_u32 key = keys[i];
        kg_u32 cx = key & column_mask;
        kg_u32 cy = key >> g->x_bits;
        kg_u32 right = cx + 1 < g->width ? key + 1 : key;
        for (int j = i + 1; j < n && keys[j] <= right; ++j) {
            kg_consider(bp, &sorted[i], &sorted[j]);
        }
        if (cy + 1 >= g->height) {
            continue;
        }
        kg_u32 first = kg_cell_key(g, cx > 0 ? cx - 1 : 0, cy + 1);
        kg_u32 last = kg_cell_key(g, cx + 1 < g->width ? cx + 1 : cx, cy + 1);
        while (above < n && keys[above] < first) {
            above += 1;
        }
        for (int j = above; j < n && keys[j] <= last; ++j) {
            kg_consider(bp, &sorted[i], &sorted[j]);
        }
    }
}

static int kg_lower_bound(const kg_u32* keys, int count, kg_u32 key)
{
    int lo = 0, hi = count;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (keys[mid] < key) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    return lo;
}

/* A small box overlapping the large one has its lower corner's cell in the large box's
 * cell range, widened by one cell down and left. Each row of that range is one run of
 * keys; empty rows are jumped over by the search itself. */
static void kg_query_large(kg_broadphase* bp, const kg_proxy* large)
{
    const kg_grid* g = &bp->grid;
    kg_u32 x0 = kg_cell_x(g, large->box.lower.x), x1 = kg_cell_x(g, large->box.upper.x);
    kg_u32 y0 = kg_cell_y(g, large->box.lower.y), y1 = kg_cell_y(g, large->box.upper.y);
    x0 = x0 > 0 ? x0 - 1 : 0;
    y0 = y0 > 0 ? y0 - 1 : 0;
    kg_u32 row = y0;
    while (row <= y1) {
        int j = kg_lower_bound(bp->keys, bp->small_count, kg_cell_key(g, x0, row));
        if (j == bp->small_count) {
            return;
        }
        kg_u32 found_row = bp->keys[j] >> g->x_bits;
        if (found_row > row) {
            row = found_row;
            continue;
        }
        kg_u32 last = kg_cell_key(g, x1, row);
        for (; j < bp->small_count && bp->keys[j] <= last; ++j) {
            kg_consider(bp, large, &bp->sorted[j]);
        }
        row += 1;
    }
}

/* Large boxes against each other: sort and sweep along x, in lower-x order. */
static void kg_sweep_large(kg_broadphase* bp)
{
    for (int i = 0; i < bp->large_count; ++i) {
        const kg_proxy* p = &bp->proxies[bp->large_items[i]];
        for (int j = i + 1; j < bp->large_count; ++j) {
            const kg_proxy* q = &bp->proxies[bp->large_items[j]];
            if (q->box.lower.x > p->box.upper.x) {
                break;
            }
            kg_consider(bp, p, q);
        }
    }
}

static void kg_find_all_pairs(kg_broadphase* bp)
{
    kg_find_small_pairs(bp);
    for (int i = 0; i < bp->large_count; ++i) {
        kg_query_large(bp, &bp->proxies[bp->large_items[i]]);
    }
    kg_sweep_large(bp);
}

/* ---- output ---- */

/* Turns the per-slot counts into output offsets and finds the run cut by the capacity. */
static void kg_plan_output(kg_broadphase* bp, int slot_count)
{
    int64_t offset = 0;
    bp->split_slot = UINT32_MAX;
    for (int a = 0; a < slot_count; ++a) {
        int count = bp->run_count[a];
        bp->run_start[a] = offset < INT_MAX ? (int)offset : INT_MAX;
        bp->run_next[a] = bp->run_start[a];
        if (offset < bp->out_capacity && offset + count > bp->out_capacity) {
            bp->split_slot = (kg_u32)a;
        }
        offset += count;
    }
    bp->partner_count = 0;
}

/* Moves the pairs, written to the output in discovery order, into their runs in place:
 * each pair is swapped straight to the next free place of its run (a bucket permutation,
 * every pair moved once). Only the order inside a run depends on the moves, and the runs
 * are sorted next. Slower than a scatter (each move waits for the last one's load): for
 * more pairs than the scatter's scratch holds. */
static void kg_permute_into_runs(kg_broadphase* bp, int slot_count)
{
    kg_pair* out = bp->out;
    for (int a = 0; a < slot_count; ++a) {
        int end = bp->run_start[a] + bp->run_count[a];
        while (bp->run_next[a] < end) {
            kg_pair p = out[bp->run_next[a]];
            while (p.a != (kg_u32)a) {
                int place = bp->run_next[p.a]++;
                kg_pair displaced = out[place];
                out[place] = p;
                p = displaced;
            }
            out[bp->run_next[a]++] = p;
        }
    }
}

/* Scatters the pairs, written to the output in discovery order, into their runs through
 * the proxy arrays, free once the search is done: they hold 8 pairs per body of capacity
 * (physical scenes have 1 to 5). Every scratch access is a memcpy, as the memory is
 * typed as proxies elsewhere. 0 when the pairs do not fit. */
static int kg_scatter_into_runs(kg_broadphase* bp)
{
    size_t room = (size_t)bp->capacity * sizeof(kg_proxy) / sizeof(kg_pair); /* per array */
    size_t total = (size_t)bp->total;
    if (total > 2 * room) {
        return 0;
    }
    unsigned char* chunk[2] = {(unsigned char*)bp->proxies, (unsigned char*)bp->sorted};
    size_t count[2] = {total < room ? total : room, 0};
    count[1] = total - count[0];
    memcpy(chunk[0], bp->out, count[0] * sizeof(kg_pair));
    memcpy(chunk[1], bp->out + count[0], count[1] * sizeof(kg_pair));
    for (int c = 0; c < 2; ++c) {
        for (size_t k = 0; k < count[c]; ++k) {
            kg_pair p;
            memcpy(&p, chunk[c] + k * sizeof p, sizeof p);
            kg_place_pair(bp, p.a, p.b);
        }
    }
    return 1;
}

/* Puts the pairs in their runs: from the discovery order when the search could write them
 * all, else by searching them again, each written at its place while that is within the
 * capacity. */
static void kg_fill_output(kg_broadphase* bp, int slot_count)
{
    if (bp->total <= bp->out_capacity) {
        if (!kg_scatter_into_runs(bp)) {
            kg_permute_into_runs(bp, slot_count);
        }
        return;
    }
    bp->mode = KG_EMIT_FILL;
    kg_find_all_pairs(bp);
}

static void kg_sort_partners(kg_broadphase* bp, int count, int slot_bits)
{
    /* the proxies' keys and items are free once the pairs are found: they carry the
     * sort's items, which nothing reads */
    kg_u32* items = bp->keys;
    kg_u32* item_scratch = bp->items;
    kg_radix_sort(&bp->partners, &items, &bp->partner_scratch, &item_scratch, count, slot_bits, bp->histogram);
}

static void kg_insertion_sort_run(kg_pair* run, int count)
{
    for (int i = 1; i < count; ++i) {
        kg_pair p = run[i];
        int j = i - 1;
        while (j >= 0 && run[j].b > p.b) {
            run[j + 1] = run[j];
            j -= 1;
        }
        run[j + 1] = p;
    }
}

/* Each slot's run holds its partners in discovery order; sort them by the upper slot. */
static void kg_sort_runs(kg_broadphase* bp, int slot_count, int slot_bits)
{
    for (int a = 0; a < slot_count; ++a) {
        int count = bp->run_count[a];
        int start = bp->run_start[a];
        if (count < 2 || (kg_u32)a == bp->split_slot || start >= bp->out_capacity) {
            continue;
        }
        kg_pair* run = bp->out + start;
        if (count <= KG_SHORT_RUN) {
            kg_insertion_sort_run(run, count);
            continue;
        }
        for (int i = 0; i < count; ++i) {
            bp->partners[i] = run[i].b;
        }
        kg_sort_partners(bp, count, slot_bits);
        for (int i = 0; i < count; ++i) {
            run[i].b = bp->partners[i];
        }
    }
}

/* The run cut by the capacity keeps its smallest partners, as a full sort would. */
static void kg_write_split_run(kg_broadphase* bp, int slot_bits)
{
    if (bp->split_slot == UINT32_MAX) {
        return;
    }
    kg_sort_partners(bp, bp->partner_count, slot_bits);
    int start = bp->run_start[bp->split_slot];
    for (int i = 0; start + i < bp->out_capacity; ++i) {
        bp->out[start + i].a = bp->split_slot;
        bp->out[start + i].b = bp->partners[i];
    }
}

/* Puts the pairs found into bp->out in (a, b) order, as many as fit. */
static void kg_write_output(kg_broadphase* bp, int slot_count)
{
    if (bp->total > 0 && bp->out_capacity > 0) {
        int slot_bits = (int)kg_bits_for((kg_u32)slot_count);
        /* the sort scratch is free now: it holds the partners of a run sorted apart */
        bp->partners = bp->key_scratch;
        bp->partner_scratch = bp->item_scratch;
        kg_plan_output(bp, slot_count);
        kg_fill_output(bp, slot_count);
        kg_write_split_run(bp, slot_bits);
        kg_sort_runs(bp, slot_count, slot_bits);
    }
}

int kg_broadphase_find_pairs(kg_broadphase* bp, const kg_body_pool* bodies, float margin, kg_pair* out,
                             int capacity)
{
    int slot_count = bodies->high_water;
    assert(slot_count <= bp->capacity && margin >= 0.0f);
    kg_gather_proxies(bp, bodies, margin);
    bp->small_count = 0;
    bp->large_count = 0;
    if (bp->proxy_count == 0) {
        bp->grid.cell_size = 0.0f;
        return 0;
    }
    kg_build_grid(bp);
    kg_classify_proxies(bp);
    kg_sort_proxies(bp);

    bp->out = out;
    bp->out_capacity = out && capacity > 0 ? capacity : 0;
    bp->mode = KG_EMIT_COUNT;
    bp->total = 0;
    kg_find_all_pairs(bp);

    kg_write_output(bp, slot_count);
    bp->out = NULL;
    return bp->total < INT_MAX ? (int)bp->total : INT_MAX;
}

/* ---- pairs kept across steps ---- */

/* False when inner has a NaN or an infinity (outer, seen in a search, is finite). */
static int kg_box_within(kg_aabb inner, kg_aabb outer)
{
    return inner.lower.x >= outer.lower.x && inner.lower.y >= outer.lower.y && inner.upper.x <= outer.upper.x &&
           inner.upper.y <= outer.upper.y;
}

/* Whether slot i, as it is now (box fattened by margin; takes_part: kg_broadphase_box's
 * answer), pairs with nothing the last search's view of it would not have paired it with. */
static int kg_seen_covers(const kg_seen* seen, const kg_body_pool* bodies, int i, kg_aabb box, int takes_part)
{
    if (!takes_part || seen->state == KG_SEEN_OUT) { /* out then and now, or not both */
        return !takes_part && seen->state == KG_SEEN_OUT;
    }
    kg_u32 state = kg_pool_collides(bodies, i) ? KG_SEEN_MOVES : KG_SEEN_STILL;
    return seen->state == state && seen->category == bodies->category[i] && seen->mask == bodies->mask[i] &&
           kg_box_within(box, seen->box);
}

int kg_broadphase_covers(kg_broadphase* bp, const kg_body_pool* bodies, float margin)
{
    if (bodies->high_water != bp->seen_count) {
        return 0;
    }
    for (int i = 0; i < bodies->high_water; ++i) {
        kg_aabb box;
        int takes_part = kg_broadphase_box(bodies->flags[i], bodies->aabb[i], margin, &box);
        if (!kg_seen_covers(&bp->seen[i], bodies, i, box, takes_part)) {
            return 0;
        }
        bp->proxies[i].box = box;
    }
    return 1;
}

int kg_broadphase_keep_pairs(const kg_broadphase* bp, const kg_pair* found, int count, kg_pair* out, int capacity)
{
    int n = 0;
    for (int k = 0; k < count; ++k) {
        kg_pair pair = found[k];
        if (kg_aabb_overlap(bp->proxies[pair.a].box, bp->proxies[pair.b].box)) {
            if (n < capacity) {
                out[n] = pair;
            }
            n += 1;
        }
    }
    return n;
}
