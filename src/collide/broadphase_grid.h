/* The broadphase's per-element steps (collide/broadphase.h describes the algorithm),
 * shared by the CPU backend (collide/broadphase.c loops over them) and the OpenCL
 * kernels (backend/opencl/kernels/kg_broadphase.cl, one work-item per element). */
#ifndef KG_BROADPHASE_GRID_H
#define KG_BROADPHASE_GRID_H

#include "collide/aabb.h"
#include "core/kg_layout.h"
#include "core/ranges.h"

/* Box extents are binned by their float bits >> 20: exponent plus 3 mantissa bits, so a
 * bin is at most 12.5% wide and a non-negative float falls in one of 2048 bins. */
#define KG_BP_EXTENT_SHIFT 20
#define KG_BP_EXTENT_BINS 2048

/* Cells never get smaller than this (m), so boxes of no size (particles without a margin)
 * still make a grid of sane resolution. */
#define KG_BP_MIN_CELL_SIZE 1.0e-6f

/* Cells per axis stay exactly representable as floats, and a key fits 31 bits, so that
 * KG_BP_NOT_KEYED sorts after every key. */
#define KG_BP_MAX_AXIS_BITS 24
#define KG_BP_MAX_KEY_BITS 31

/* The key of what is not a small box (a large box, a slot that takes no part). */
#define KG_BP_NOT_KEYED 0xFFFFFFFFu

/* Runs of pairs up to this length are insertion sorted; longer ones heap sorted. */
#define KG_BP_SHORT_RUN 32

/* Two body slots whose fattened boxes overlap, a < b. */
typedef struct kg_pair {
    kg_u32 a, b;
} kg_pair;

/* A candidate body: its fattened box and what the pair test needs, 32 bytes. body is
 * KG_NULL_INDEX for a slot that takes no part (dead, or bounds not finite). */
typedef struct kg_bp_proxy {
    kg_aabb box;
    kg_u32 body;
    kg_u32 category;
    kg_u32 mask;
    kg_u32 moves; /* dynamic or particle */
} kg_bp_proxy;

typedef struct kg_bp_grid {
    kg_vec2 origin;
    float cell_size;
    float inv_cell_size;
    kg_u32 width, height; /* cells; coordinates outside are clamped to the border cells */
    kg_u32 x_bits;        /* key = (row << x_bits) | column */
    kg_u32 pad;
} kg_bp_grid;

KG_STATIC_ASSERT(sizeof(kg_bp_proxy) == 32, bp_proxy_size);
KG_STATIC_ASSERT(sizeof(kg_bp_grid) == 32, bp_grid_size);

/* ---- numbers ---- */

/* A float's bits and back, through a union: OpenCL C has no memcpy, and C99 allows it. */
typedef union kg_bp_pun {
    float f;
    kg_u32 u;
} kg_bp_pun;

KG_FN kg_u32 kg_bp_float_bits(float v) { kg_bp_pun p; p.f = v; return p.u; }

KG_FN float kg_bp_bits_float(kg_u32 bits) { kg_bp_pun p; p.u = bits; return p.f; }

/* Bits of a float made unsigned-comparable in the same order as the floats, and back. */
KG_FN kg_u32 kg_bp_sortable_bits(float v)
{
    kg_u32 bits = kg_bp_float_bits(v);
    return (bits & 0x80000000u) ? ~bits : (bits | 0x80000000u);
}

KG_FN float kg_bp_unsortable(kg_u32 bits) { return kg_bp_bits_float((bits & 0x80000000u) ? bits & 0x7FFFFFFFu : ~bits); }

/* ---- proxies and the grid ---- */

/* Slot i's proxy: its broadphase box (collide/aabb.h) and filter. */
KG_FN kg_bp_proxy kg_bp_proxy_of(kg_u32 flags, kg_aabb bounds, kg_u32 category, kg_u32 mask, float margin, kg_u32 i)
{
    kg_bp_proxy p;
    p.body = kg_broadphase_box(flags, bounds, margin, &p.box) ? i : KG_NULL_INDEX;
    p.category = category;
    p.mask = mask;
    p.moves = (kg_u32)kg_flags_collide(flags);
    return p;
}

KG_FN float kg_bp_extent(kg_aabb box)
{
    float e = kg_maxf(box.upper.x - box.lower.x, box.upper.y - box.lower.y);
    return e > 0.0f ? e : 0.0f;
}

KG_FN kg_u32 kg_bp_extent_bin(kg_aabb box) { return kg_bp_float_bits(kg_bp_extent(box)) >> KG_BP_EXTENT_SHIFT; }

/* The cell size: the upper edge of the extent bin holding the 90th percentile, so 90% of
 * the boxes are small and the rest few enough to handle one by one. */
KG_FN float kg_bp_cell_size(KG_GLOBAL const kg_u32* histogram)
{
    kg_u32 count = 0u;
    for (int bin = 0; bin < KG_BP_EXTENT_BINS; ++bin) {
        count += histogram[bin];
    }
    kg_u32 target = count - (count + 9u) / 10u; /* floor(0.9 count) */
    target = target > 0u ? target : 1u;
    kg_u32 seen = 0u, bin = 0u;
    while (bin + 1u < KG_BP_EXTENT_BINS && seen + histogram[bin] < target) {
        seen += histogram[bin];
        bin += 1u;
    }
    float edge = kg_bp_bits_float((bin + 1u) << KG_BP_EXTENT_SHIFT);
    /* past the largest float when most boxes are infinitely wide */
    return kg_is_finite(edge) ? kg_maxf(edge, KG_BP_MIN_CELL_SIZE) : KG_FLT_MAX;
}

/* Whether box's lower corner bounds the grid: the boxes below the cell size (the others
 * are mostly large, and a huge wall would stretch the grid). */
KG_FN int kg_bp_bounds_grid(kg_aabb box, float cell_size) { return kg_bp_extent(box) < cell_size; }

/* The lower corner that bounds the grid, -0 made +0: then the floats' order and their
 * sortable bits' order agree, and a minimum of the floats (the CPU's) and one of their
 * bits (the device's atomics) pick the same bits. */
KG_FN kg_vec2 kg_bp_corner(kg_aabb box) { return kg_v2(box.lower.x + 0.0f, box.lower.y + 0.0f); }

/* The grid's bounds, kg_bp_sortable_bits of the lower corners: min x, min y, max x,
 * max y, from these when no corner counts. */
#define KG_BP_BOUNDS_EMPTY_MIN 0xFFFFFFFFu
#define KG_BP_BOUNDS_EMPTY_MAX 0u

/* Cells from lower to upper, or one more than the axis allows. Halved first, because the
 * span of two finite floats may overflow a float. */
KG_FN kg_u32 kg_bp_axis_cells(float lower, float upper, float cell_size)
{
    float cells = floorf((0.5f * upper - 0.5f * lower) / (0.5f * cell_size)) + 1.0f;
    float limit = (float)(1u << KG_BP_MAX_AXIS_BITS);
    return cells < limit ? (kg_u32)cells : (1u << KG_BP_MAX_AXIS_BITS) + 1u;
}

/* The grid over the bounds, doubling the cells until a key fits KG_BP_MAX_KEY_BITS. Only
 * worlds spanning more than 2^31 cells need it, and it ends: an infinite cell size
 * makes one cell. */
KG_FN kg_bp_grid kg_bp_grid_make(float cell_size, KG_GLOBAL const kg_u32* bounds)
{
    kg_vec2 lower = kg_v2(kg_bp_unsortable(bounds[0]), kg_bp_unsortable(bounds[1]));
    kg_vec2 upper = kg_v2(kg_bp_unsortable(bounds[2]), kg_bp_unsortable(bounds[3]));
    if (bounds[0] > bounds[2]) {
        /* every box is infinitely wide: one cell at the origin holds them all */
        lower = kg_v2(0.0f, 0.0f);
        upper = lower;
    }
    kg_bp_grid g;
    g.origin = lower;
    g.pad = 0u;
    for (;;) {
        g.cell_size = cell_size;
        g.inv_cell_size = 1.0f / cell_size;
        g.width = kg_bp_axis_cells(lower.x, upper.x, cell_size);
        g.height = kg_bp_axis_cells(lower.y, upper.y, cell_size);
        g.x_bits = kg_bits_for(g.width);
        kg_u32 y_bits = kg_bits_for(g.height);
        if (g.x_bits <= KG_BP_MAX_AXIS_BITS && y_bits <= KG_BP_MAX_AXIS_BITS &&
            g.x_bits + y_bits <= KG_BP_MAX_KEY_BITS) {
            return g;
        }
        cell_size *= 2.0f;
    }
}

/* Every step here is monotone in v (clamping too), which the neighbour argument needs.
 * The clamp is written so that a NaN lands in cell 0. The conversion truncates a value
 * clamped to be non-negative: its floor, without floorf (a library call on the CPU's
 * baseline build). */
KG_FN kg_u32 kg_bp_cell_coord(float v, float origin, float inv_cell_size, kg_u32 cells)
{
    float f = (v - origin) * inv_cell_size;
    f = f > 0.0f ? f : 0.0f;
    return (kg_u32)kg_minf(f, (float)(cells - 1u));
}

KG_FN kg_u32 kg_bp_cell_x(const kg_bp_grid* g, float x) { return kg_bp_cell_coord(x, g->origin.x, g->inv_cell_size, g->width); }

KG_FN kg_u32 kg_bp_cell_y(const kg_bp_grid* g, float y) { return kg_bp_cell_coord(y, g->origin.y, g->inv_cell_size, g->height); }

KG_FN kg_u32 kg_bp_cell_key(const kg_bp_grid* g, kg_u32 cx, kg_u32 cy) { return (cy << g->x_bits) | cx; }

/* A box spanning at most 2x2 cells is small, keyed by its lower corner's cell; a larger
 * one is KG_BP_NOT_KEYED. */
KG_FN kg_u32 kg_bp_small_key(const kg_bp_grid* g, kg_aabb box)
{
    kg_u32 x0 = kg_bp_cell_x(g, box.lower.x), x1 = kg_bp_cell_x(g, box.upper.x);
    kg_u32 y0 = kg_bp_cell_y(g, box.lower.y), y1 = kg_bp_cell_y(g, box.upper.y);
    return x1 - x0 <= 1u && y1 - y0 <= 1u ? kg_bp_cell_key(g, x0, y0) : KG_BP_NOT_KEYED;
}

/* Slot p's two sort keys: its cell key when it is a small box, and the sortable bits of
 * its lower x when it is a large one; KG_BP_NOT_KEYED otherwise, which sorts after both
 * (no finite float has those bits). */
KG_FN kg_u32 kg_bp_large_key(kg_bp_proxy p, kg_u32 small_key)
{
    return p.body != KG_NULL_INDEX && small_key == KG_BP_NOT_KEYED ? kg_bp_sortable_bits(p.box.lower.x)
                                                                   : KG_BP_NOT_KEYED;
}

KG_FN kg_u32 kg_bp_slot_key(const kg_bp_grid* g, kg_bp_proxy p)
{
    return p.body != KG_NULL_INDEX ? kg_bp_small_key(g, p.box) : KG_BP_NOT_KEYED;
}

/* ---- pair search ---- */

/* Where the pairs found go: counted from at, and written to out[at] while at < capacity
 * (out NULL: counted only). With runs (the CPU's serial passes only: no atomics), the
 * place is runs[a] of the pair's lower slot, advanced: counted per slot with out NULL,
 * placed in the slot's run otherwise. */
typedef struct kg_bp_sink {
    KG_GLOBAL kg_pair* out;
    kg_u32 at;
    kg_u32 capacity;
    KG_GLOBAL kg_u32* runs;
} kg_bp_sink;

KG_FN kg_bp_sink kg_bp_sink_make(KG_GLOBAL kg_pair* out, kg_u32 at, kg_u32 capacity, KG_GLOBAL kg_u32* runs)
{
    kg_bp_sink s;
    s.out = out;
    s.at = at;
    s.capacity = capacity;
    s.runs = runs;
    return s;
}

KG_FN void kg_bp_put(kg_bp_sink* s, kg_u32 p, kg_u32 q)
{
    kg_u32 a = p < q ? p : q;
    kg_u32 place = s->runs ? s->runs[a]++ : s->at;
    if (s->out && place < s->capacity) {
        s->out[place].a = a;
        s->out[place].b = p < q ? q : p;
    }
    s->at += 1u;
}

KG_FN void kg_bp_consider(kg_bp_sink* s, kg_bp_proxy p, kg_bp_proxy q)
{
    if (kg_boxes_pair((int)p.moves, p.box, p.category, p.mask, (int)q.moves, q.box, q.category, q.mask)) {
        kg_bp_put(s, p.body, q.body);
    }
}

/* What a search reads: the small proxies in key order with their sorted keys, and the
 * large ones in order of lower x (their indices into proxies). */
typedef struct kg_bp_view {
    kg_bp_grid grid;
    KG_GLOBAL const kg_u32* keys;
    KG_GLOBAL const kg_bp_proxy* sorted;
    int small_count;
    KG_GLOBAL const kg_u32* large_items;
    KG_GLOBAL const kg_bp_proxy* proxies;
    int large_count;
} kg_bp_view;

/* The first of keys[from, hi) not below key, galloping from from: cheap when it is near,
 * as the row above an entry mostly is. */
KG_FN int kg_bp_gallop(KG_GLOBAL const kg_u32* keys, int from, int hi, kg_u32 key)
{
    int step = 1;
    while (from + step < hi && keys[from + step - 1] < key) {
        from += step;
        step *= 2;
    }
    return kg_lower_bound(keys, from, from + step < hi ? from + step : hi, key);
}

/* Partners of p among the small entries [from, small_count) keyed up to last. */
KG_FN void kg_bp_scan_keys(kg_bp_sink* s, const kg_bp_view* v, kg_bp_proxy p, int from, kg_u32 last)
{
    for (int j = from; j < v->small_count && v->keys[j] <= last; ++j) {
        kg_bp_consider(s, p, v->sorted[j]);
    }
}

/* The pairs small entry i finds. Two overlapping small boxes have lower-corner cells at
 * most one apart per axis (the cell map is monotone and a small box spans at most one
 * cell boundary per axis). So each entry scans the rest of its cell, the cell on its
 * right and the three cells above: every neighbouring couple once. The row above is
 * searched from hint, which must not be past its first entry: i + 1, or what this
 * returned for an earlier entry (the first key of the range above grows with the key). */
KG_FN int kg_bp_find_small(kg_bp_sink* s, const kg_bp_view* v, int i, int hint)
{
    const kg_bp_grid* g = &v->grid;
    kg_u32 key = v->keys[i];
    kg_u32 cx = key & ((1u << g->x_bits) - 1u), cy = key >> g->x_bits;
    kg_bp_proxy p = v->sorted[i];
    kg_bp_scan_keys(s, v, p, i + 1, cx + 1u < g->width ? key + 1u : key);
    if (cy + 1u >= g->height) {
        return hint;
    }
    kg_u32 first = kg_bp_cell_key(g, cx > 0u ? cx - 1u : 0u, cy + 1u);
    int above = kg_bp_gallop(v->keys, hint, v->small_count, first);
    kg_bp_scan_keys(s, v, p, above, kg_bp_cell_key(g, cx + 1u < g->width ? cx + 1u : cx, cy + 1u));
    return above;
}

/* A small box overlapping large box p has its lower corner's cell in p's cell range,
 * widened by one cell down and left. Each row of that range is one run of keys; empty
 * rows are jumped over by the search itself. */
KG_FN void kg_bp_query_large(kg_bp_sink* s, const kg_bp_view* v, kg_bp_proxy p)
{
    const kg_bp_grid* g = &v->grid;
    kg_u32 x0 = kg_bp_cell_x(g, p.box.lower.x), x1 = kg_bp_cell_x(g, p.box.upper.x);
    kg_u32 y0 = kg_bp_cell_y(g, p.box.lower.y), y1 = kg_bp_cell_y(g, p.box.upper.y);
    x0 = x0 > 0u ? x0 - 1u : 0u;
    kg_u32 row = y0 > 0u ? y0 - 1u : 0u;
    while (row <= y1) {
        int j = kg_lower_bound(v->keys, 0, v->small_count, kg_bp_cell_key(g, x0, row));
        if (j == v->small_count) {
            return;
        }
        kg_u32 found_row = v->keys[j] >> g->x_bits;
        if (found_row > row) {
            row = found_row;
            continue;
        }
        kg_bp_scan_keys(s, v, p, j, kg_bp_cell_key(g, x1, row));
        row += 1u;
    }
}

/* The pairs large entry i finds: the small boxes over its footprint, then the large
 * boxes after it in lower-x order up to its upper x (a sort and sweep). */
KG_FN void kg_bp_find_large(kg_bp_sink* s, const kg_bp_view* v, int i)
{
    kg_bp_proxy p = v->proxies[v->large_items[i]];
    kg_bp_query_large(s, v, p);
    for (int j = i + 1; j < v->large_count; ++j) {
        kg_bp_proxy q = v->proxies[v->large_items[j]];
        if (q.box.lower.x > p.box.upper.x) {
            break;
        }
        kg_bp_consider(s, p, q);
    }
}

KG_FN kg_bp_view kg_bp_view_make(kg_bp_grid grid, KG_GLOBAL const kg_u32* keys, KG_GLOBAL const kg_bp_proxy* sorted,
                                 int small_count, KG_GLOBAL const kg_u32* large_items,
                                 KG_GLOBAL const kg_bp_proxy* proxies, int large_count)
{
    kg_bp_view v = {grid, keys, sorted, small_count, large_items, proxies, large_count};
    return v;
}

/* Whether entry i of keys sorted with KG_BP_NOT_KEYED last (the device's lists of every
 * slot) is the last one keyed: then i + 1 entries are. */
KG_FN int kg_bp_last_keyed(KG_GLOBAL const kg_u32* keys, int i, int count)
{
    return keys[i] != KG_BP_NOT_KEYED && (i + 1 == count || keys[i + 1] == KG_BP_NOT_KEYED);
}

/* The pairs of element e of 2 * slots: small entry e, then large entry e - slots. */
KG_FN void kg_bp_find_element(kg_bp_sink* s, const kg_bp_view* v, int e, int slots)
{
    if (e < v->small_count) {
        kg_bp_find_small(s, v, e, e + 1);
    } else if (e >= slots && e - slots < v->large_count) {
        kg_bp_find_large(s, v, e - slots);
    }
}

/* ---- output ---- */

KG_FN void kg_bp_insertion_sort(KG_GLOBAL kg_pair* run, int count)
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

KG_FN void kg_bp_sift_down(KG_GLOBAL kg_pair* run, int root, int count)
{
    for (;;) {
        int child = 2 * root + 1;
        if (child >= count) {
            return;
        }
        if (child + 1 < count && run[child + 1].b > run[child].b) {
            child += 1;
        }
        if (run[root].b >= run[child].b) {
            return;
        }
        kg_pair t = run[root];
        run[root] = run[child];
        run[child] = t;
        root = child;
    }
}

/* A run of one lower slot's pairs in order of the upper slot: the slots of a run are
 * distinct, so any sort gives the one order. In place: insertion for the short runs
 * of small boxes, a heap sort for the long ones of large boxes (grounds, walls). */
KG_FN void kg_bp_sort_run(KG_GLOBAL kg_pair* run, int count)
{
    if (count <= KG_BP_SHORT_RUN) {
        kg_bp_insertion_sort(run, count);
        return;
    }
    for (int i = count / 2; i > 0; --i) {
        kg_bp_sift_down(run, i - 1, count);
    }
    for (int end = count - 1; end > 0; --end) {
        kg_pair t = run[0];
        run[0] = run[end];
        run[end] = t;
        kg_bp_sift_down(run, 0, end);
    }
}

#endif
