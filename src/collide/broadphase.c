#include "collide/broadphase.h"
#include "core/alloc.h"
#include "core/counting_sort.h"
#include "core/error.h"
#include "core/prefix_sum.h"

#include <assert.h>
#include <limits.h>
#include <string.h>

/* Radix sort digits: 11 bits, so 32-bit keys take at most 3 passes and a histogram
 * (8 KiB) stays in L1. */
#define KG_RADIX_BITS 11
#define KG_RADIX_BUCKETS (1 << KG_RADIX_BITS)

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

struct kg_broadphase {
    int capacity;
    kg_bp_grid grid;
    kg_bp_proxy* proxies;  /* candidates, in slot order; after kg_broadphase_covers, indexed
                            * by slot (the boxes kg_broadphase_keep_pairs tests) */
    kg_bp_proxy* sorted;   /* small proxies, in key order */
    int proxy_count;
    int small_count;
    int large_count;
    kg_u32* keys;          /* cell keys of the small proxies, sorted */
    kg_u32* items;         /* proxy index of each key */
    kg_u32* large_keys;    /* lower x of the large proxies (sortable bits), sorted */
    kg_u32* large_items;   /* proxy index of each large key */
    kg_u32* key_scratch;
    kg_u32* item_scratch;
    kg_u32* run_count;     /* per lower slot: how many pairs; then room for the partners
                            * of the run the capacity cuts (a pair per slot) */
    int* run_start;        /* per lower slot: first output index, saturated at INT_MAX */
    kg_u32* run_next;      /* per lower slot: next output index while filling */
    kg_seen* seen;         /* per slot: what the last search saw */
    int seen_count;        /* slots the last search looked at */
    kg_u32 histogram[KG_RADIX_BUCKETS + 1]; /* and the prefix sum's total */
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
    bp->run_count = kg_alloc_zeroed(n * (sizeof *bp->run_count + sizeof(kg_pair)));
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
        kg_sort_count_chunk(*keys, count, count, 0, 1, shift, KG_RADIX_BITS, histogram);
        if (histogram[kg_sort_digit((*keys)[0], shift, KG_RADIX_BITS)] == (kg_u32)count) {
            continue;
        }
        kg_scan_block_apply(histogram, histogram, KG_RADIX_BUCKETS, KG_RADIX_BUCKETS, 0, NULL);
        kg_sort_scatter_chunk(*keys, *items, count, count, 0, 1, shift, KG_RADIX_BITS, histogram, *key_scratch,
                              *item_scratch);
        kg_u32* t = *key_scratch;
        *key_scratch = *keys;
        *keys = t;
        t = *item_scratch;
        *item_scratch = *items;
        *items = t;
    }
}

/* ---- gathering and grid ---- */

static kg_seen kg_seen_of(const kg_bp_proxy* p)
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
        bp->seen[i].state = KG_SEEN_OUT;
        kg_bp_proxy p = kg_bp_proxy_of(bodies->flags[i], bodies->aabb[i], bodies->category[i], bodies->mask[i],
                                       margin, (kg_u32)i);
        if (p.body == KG_NULL_INDEX) {
            continue;
        }
        bp->proxies[n++] = p;
        bp->seen[i] = kg_seen_of(&p);
        bp->histogram[kg_bp_extent_bin(p.box)] += 1;
    }
    bp->proxy_count = n;
}

/* The grid over the lower corners of the boxes below the cell size. */
static void kg_build_grid(kg_broadphase* bp)
{
    float cell_size = kg_bp_cell_size(bp->histogram);
    kg_vec2 lower = kg_v2(KG_FLT_MAX, KG_FLT_MAX), upper = kg_v2(-KG_FLT_MAX, -KG_FLT_MAX);
    for (int i = 0; i < bp->proxy_count; ++i) {
        if (kg_bp_bounds_grid(bp->proxies[i].box, cell_size)) {
            kg_vec2 corner = kg_bp_corner(bp->proxies[i].box);
            lower = kg_vmin(lower, corner);
            upper = kg_vmax(upper, corner);
        }
    }
    kg_u32 bounds[4] = {KG_BP_BOUNDS_EMPTY_MIN, KG_BP_BOUNDS_EMPTY_MIN, KG_BP_BOUNDS_EMPTY_MAX,
                        KG_BP_BOUNDS_EMPTY_MAX};
    if (lower.x <= upper.x) {
        bounds[0] = kg_bp_sortable_bits(lower.x);
        bounds[1] = kg_bp_sortable_bits(lower.y);
        bounds[2] = kg_bp_sortable_bits(upper.x);
        bounds[3] = kg_bp_sortable_bits(upper.y);
    }
    bp->grid = kg_bp_grid_make(cell_size, bounds);
}

/* Keys the small boxes by their lower corner's cell; lists the rest as large. Both lists
 * come out in slot order, which keeps the sorts deterministic. */
static void kg_classify_proxies(kg_broadphase* bp)
{
    int small = 0, large = 0;
    for (int i = 0; i < bp->proxy_count; ++i) {
        kg_u32 key = kg_bp_slot_key(&bp->grid, bp->proxies[i]);
        if (key != KG_BP_NOT_KEYED) {
            bp->keys[small] = key;
            bp->items[small] = (kg_u32)i;
            small += 1;
        } else {
            bp->large_keys[large] = kg_bp_large_key(bp->proxies[i], key);
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
    /* Copied in key order so the neighbour scans read memory front to back. */
    for (int i = 0; i < bp->small_count; ++i) {
        bp->sorted[i] = bp->proxies[bp->items[i]];
    }
    kg_radix_sort(&bp->large_keys, &bp->large_items, &bp->key_scratch, &bp->item_scratch, bp->large_count,
                  32, bp->histogram);
}

/* ---- pair search ---- */

/* Every pair into sink: those the small entries find, then those the large ones find. */
static void kg_find_all_pairs(const kg_broadphase* bp, kg_bp_sink* sink)
{
    kg_bp_view v = kg_bp_view_make(bp->grid, bp->keys, bp->sorted, bp->small_count, bp->large_items, bp->proxies,
                                   bp->large_count);
    for (int i = 0, above = 0; i < bp->small_count; ++i) {
        above = kg_bp_find_small(sink, &v, i, above);
    }
    for (int i = 0; i < bp->large_count; ++i) {
        kg_bp_find_large(sink, &v, i);
    }
}

/* ---- output ---- */

/* Turns the per-slot counts into output offsets (the cursors saturated at capacity, where
 * nothing more is written); returns the slot whose run the capacity cuts, or -1. */
static int kg_plan_output(kg_broadphase* bp, int slot_count, int capacity)
{
    int64_t offset = 0;
    int split = -1;
    for (int a = 0; a < slot_count; ++a) {
        int count = (int)bp->run_count[a];
        bp->run_start[a] = offset < INT_MAX ? (int)offset : INT_MAX;
        bp->run_next[a] = offset < capacity ? (kg_u32)offset : (kg_u32)capacity;
        if (offset < capacity && offset + count > capacity) {
            split = a;
        }
        offset += count;
    }
    return split;
}

/* Moves the pairs, written to the output in discovery order, into their runs in place:
 * each pair is swapped straight to the next free place of its run (a bucket permutation,
 * every pair moved once). Only the order inside a run depends on the moves, and the runs
 * are sorted next. Slower than a scatter (each move waits for the last one's load): for
 * more pairs than the scatter's scratch holds. */
static void kg_permute_into_runs(kg_broadphase* bp, kg_pair* out, int slot_count)
{
    for (int a = 0; a < slot_count; ++a) {
        kg_u32 end = (kg_u32)bp->run_start[a] + bp->run_count[a];
        while (bp->run_next[a] < end) {
            kg_pair p = out[bp->run_next[a]];
            while (p.a != (kg_u32)a) {
                kg_u32 place = bp->run_next[p.a]++;
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
static int kg_scatter_into_runs(kg_broadphase* bp, kg_pair* out, int total)
{
    size_t room = (size_t)bp->capacity * sizeof(kg_bp_proxy) / sizeof(kg_pair); /* per array */
    size_t n = (size_t)total;
    if (n > 2 * room) {
        return 0;
    }
    unsigned char* chunk[2] = {(unsigned char*)bp->proxies, (unsigned char*)bp->sorted};
    size_t count[2] = {n < room ? n : room, 0};
    count[1] = n - count[0];
    memcpy(chunk[0], out, count[0] * sizeof(kg_pair));
    memcpy(chunk[1], out + count[0], count[1] * sizeof(kg_pair));
    for (int c = 0; c < 2; ++c) {
        for (size_t k = 0; k < count[c]; ++k) {
            kg_pair p;
            memcpy(&p, chunk[c] + k * sizeof p, sizeof p);
            out[bp->run_next[p.a]++] = p;
        }
    }
    return 1;
}

/* All the pairs were written in discovery order: counted per lower slot and moved to
 * their runs. */
static void kg_runs_from_output(kg_broadphase* bp, kg_pair* out, int total, int slot_count)
{
    memset(bp->run_count, 0, (size_t)slot_count * sizeof *bp->run_count);
    for (int k = 0; k < total; ++k) {
        bp->run_count[out[k].a] += 1;
    }
    kg_plan_output(bp, slot_count, total);
    if (!kg_scatter_into_runs(bp, out, total)) {
        kg_permute_into_runs(bp, out, slot_count);
    }
}

/* They did not all fit: the search counts them per lower slot, places those whose run
 * fits, and finds the partners of the run the capacity cuts (after the counts in
 * run_count: every other slot's cursor starts past their room), which keeps its smallest
 * ones, as a full sort would. Returns that run's slot, or -1. */
static int kg_runs_by_search(kg_broadphase* bp, kg_pair* out, int capacity, int slot_count)
{
    memset(bp->run_count, 0, (size_t)slot_count * sizeof *bp->run_count);
    kg_bp_sink sink = kg_bp_sink_make(NULL, 0u, 0u, bp->run_count);
    kg_find_all_pairs(bp, &sink);
    int split = kg_plan_output(bp, slot_count, capacity);
    sink = kg_bp_sink_make(out, 0u, (kg_u32)capacity, bp->run_next);
    kg_find_all_pairs(bp, &sink);
    if (split < 0) {
        return split;
    }
    kg_pair* partners = (kg_pair*)(void*)(bp->run_count + bp->capacity);
    int start = bp->run_start[split], count = (int)bp->run_count[split];
    for (int a = 0; a < slot_count; ++a) {
        bp->run_next[a] = a == split ? 0u : (kg_u32)slot_count;
    }
    sink = kg_bp_sink_make(partners, 0u, (kg_u32)slot_count, bp->run_next);
    kg_find_all_pairs(bp, &sink);
    kg_bp_sort_run(partners, count);
    memcpy(out + start, partners, (size_t)(capacity - start) * sizeof *out);
    return split;
}

/* A long run (a large box's: a ground's, a wall's) in order of the upper slot, through
 * bits, a bitmap of the slots (zeros, left so): the slots of a run are distinct, so a bit
 * is set for each and they are read off in order. The tumbler's four walls pair with most
 * of its boxes, found in grid order: a heap sort of their runs cost its search 0.08 M
 * instructions a step more (callgrind). */
static void kg_sort_long_run(kg_pair* run, int count, kg_u32* bits)
{
    kg_u32 a = run[0].a, low = run[0].b, high = run[0].b;
    for (int i = 0; i < count; ++i) {
        kg_u32 b = run[i].b;
        bits[b >> 5] |= 1u << (b & 31u);
        low = b < low ? b : low;
        high = b > high ? b : high;
    }
    int n = 0;
    for (kg_u32 word = low >> 5; word <= high >> 5; ++word) {
        for (kg_u32 set = bits[word]; set != 0u; set &= set - 1u) {
            run[n].a = a;
            run[n].b = (word << 5) | (kg_u32)__builtin_ctz(set);
            n += 1;
        }
        bits[word] = 0u;
    }
}

/* Puts the pairs found into out in (a, b) order, as many as fit: each slot's run placed,
 * then sorted by the upper slot (the long ones through a bitmap in run_next, free once
 * the runs are placed). */
static void kg_write_output(kg_broadphase* bp, kg_pair* out, int total, int capacity, int slot_count)
{
    if (total == 0 || capacity == 0) {
        return;
    }
    int split = -1;
    if (total <= capacity) {
        kg_runs_from_output(bp, out, total, slot_count);
    } else {
        split = kg_runs_by_search(bp, out, capacity, slot_count);
    }
    memset(bp->run_next, 0, ((size_t)slot_count + 31u) / 32u * sizeof *bp->run_next);
    for (int a = 0; a < slot_count; ++a) {
        int count = (int)bp->run_count[a], start = bp->run_start[a];
        if (count < 2 || a == split || start >= capacity) {
            continue; /* in order already, or not (wholly) written */
        }
        if (count > KG_BP_SHORT_RUN) {
            kg_sort_long_run(out + start, count, bp->run_next);
        } else {
            kg_bp_sort_run(out + start, count);
        }
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

    capacity = out && capacity > 0 ? capacity : 0;
    kg_bp_sink sink = kg_bp_sink_make(out, 0u, (kg_u32)capacity, NULL);
    kg_find_all_pairs(bp, &sink);
    int total = sink.at < INT_MAX ? (int)sink.at : INT_MAX;
    kg_write_output(bp, out, total, capacity, slot_count);
    return total;
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

int kg_broadphase_same_slots(const kg_broadphase* bp, const kg_body_pool* bodies)
{
    return bodies->high_water == bp->seen_count;
}

int kg_broadphase_covers_range(kg_broadphase* bp, const kg_body_pool* bodies, float margin, int begin, int end)
{
    for (int i = begin; i < end; ++i) {
        kg_aabb box;
        int takes_part = kg_broadphase_box(bodies->flags[i], bodies->aabb[i], margin, &box);
        if (!kg_seen_covers(&bp->seen[i], bodies, i, box, takes_part)) {
            return 0;
        }
        bp->proxies[i].box = box;
    }
    return 1;
}

int kg_broadphase_covers(kg_broadphase* bp, const kg_body_pool* bodies, float margin)
{
    return kg_broadphase_same_slots(bp, bodies) &&
           kg_broadphase_covers_range(bp, bodies, margin, 0, bodies->high_water);
}

static int kg_pair_kept(const kg_broadphase* bp, kg_pair pair)
{
    return kg_aabb_overlap(bp->proxies[pair.a].box, bp->proxies[pair.b].box);
}

int kg_broadphase_keep_pairs(const kg_broadphase* bp, const kg_pair* found, int count, kg_pair* out, int capacity)
{
    int n = 0;
    for (int k = 0; k < count; ++k) {
        if (kg_pair_kept(bp, found[k])) {
            if (n < capacity) {
                out[n] = found[k];
            }
            n += 1;
        }
    }
    return n;
}

int kg_broadphase_mark_kept(const kg_broadphase* bp, const kg_pair* found, int begin, int end, unsigned char* kept)
{
    int n = 0;
    for (int k = begin; k < end; ++k) {
        kept[k] = (unsigned char)kg_pair_kept(bp, found[k]);
        n += kept[k];
    }
    return n;
}
