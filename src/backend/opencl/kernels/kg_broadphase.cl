/* The broadphase's kernels: every pair collide/broadphase.h specifies, in the order the
 * CPU backend lists them. Pairs are appended with integer atomics in whatever order
 * work-items run, then put in order (runs sorted by partner) before they are used. */
#include "core/kg_layout.h"
#include "collide/aabb.h"
#include "kg_collide_shared.h"

/* Cell coordinates are clamped to this (exact in float), so any finite position maps. */
#define KG_BP_COORD_LIMIT 1073741824.0f

/* Cells are never smaller than this (m), as in collide/broadphase.c. */
#define KG_BP_MIN_CELL_SIZE 1.0e-6f

/* Runs of pairs up to this length are insertion sorted; longer ones heap sorted. */
#define KG_BP_SHORT_RUN 32

/* The broadphase finds every pair collide/broadphase.h specifies (candidates, filter,
 * fattened boxes overlapping), each once, and lists them sorted by (a, b):
 *  - boxes are keyed by the cell of their lower corner, at the lowest grid level where
 *    they span at most two cells per axis (level 0's cells are the 90th percentile of the
 *    box extents, each level doubles them), in a hash table of singly linked lists;
 *  - a box overlapping box i, keyed at level m, has its lower corner in the cells of i's
 *    footprint at level m widened by one cell down and left: cell coordinates are
 *    monotone in position, and a keyed box spans at most two cells. So two boxes of one
 *    level are at most one cell apart, and each finds the partners in its own cell of
 *    higher slot, in the cell on its right and in the three above (collide/broadphase.c's
 *    scheme): each pair once. Between two levels, either every box of the lower level
 *    looks up (3 x 3 cells), or every box of the upper level looks down (its footprint),
 *    whichever probes fewer cells (kg_bp_plan): a few grounds and walls look down rather
 *    than have every small box look up at them;
 *  - pairs are appended (in batches, and the last batches of a work-group together, to
 *    spare the shared counter), counted per lower slot, scattered to their slot's run and
 *    each run sorted by the upper slot. */

KG_FN float kg_bp_extent(kg_aabb box)
{
    float w = box.upper.x - box.lower.x, h = box.upper.y - box.lower.y;
    float e = w > h ? w : h;
    return e > 0.0f ? e : 0.0f;
}

KG_FN kg_u32 kg_bp_extent_bin(kg_aabb box) { return as_uint(kg_bp_extent(box)) >> KG_BP_EXTENT_SHIFT; }

/* The cell of v at level: monotone in v (which the partner search needs), the same bits
 * in every kernel that asks. */
KG_FN kg_i32 kg_bp_coord(float v, float inv_cell_size, kg_u32 level)
{
    if (level == KG_BP_TOP_LEVEL) {
        return 0;
    }
    float f = floor(v * ldexp(inv_cell_size, -(int)level));
    return (kg_i32)fmin(fmax(f, -KG_BP_COORD_LIMIT), KG_BP_COORD_LIMIT);
}

/* The cells whose keyed boxes may overlap box at level: its footprint widened by one cell
 * down and left. */
typedef struct kg_bp_range {
    kg_i32 x0, y0, x1, y1;
} kg_bp_range;

KG_FN kg_bp_range kg_bp_search_range(kg_aabb box, float inv_cell_size, kg_u32 level)
{
    kg_bp_range r;
    r.x0 = kg_bp_coord(box.lower.x, inv_cell_size, level) - 1;
    r.y0 = kg_bp_coord(box.lower.y, inv_cell_size, level) - 1;
    r.x1 = kg_bp_coord(box.upper.x, inv_cell_size, level);
    r.y1 = kg_bp_coord(box.upper.y, inv_cell_size, level);
    return r;
}

/* How many cells the range holds, saturated (the ranges of huge boxes overflow). */
KG_FN kg_u32 kg_bp_range_cells(kg_bp_range r)
{
    float cells = ((float)r.x1 - (float)r.x0 + 1.0f) * ((float)r.y1 - (float)r.y0 + 1.0f);
    return cells < 1073741824.0f ? (kg_u32)cells : 1073741824u;
}

/* The hash table's geometry: a power-of-two size and a row stride near its square root. */
typedef struct kg_bp_table {
    uint mask;
    uint row_stride;
} kg_bp_table;

/* The bucket of a cell. Neighbouring cells of a row get neighbouring buckets, and a block
 * of row_stride columns by size / row_stride rows none in common: the few cells a box
 * searches share cache lines, and a compact world has few collisions. */
KG_FN kg_u32 kg_bp_hash(kg_i32 x, kg_i32 y, kg_u32 level, kg_bp_table table)
{
    return ((kg_u32)x + (kg_u32)y * table.row_stride + level * 0x9E3779B1u) & table.mask;
}

KG_FN int kg_bp_occupied(uint levels, kg_u32 level) { return (levels >> level) & 1u; }

/* Whether the boxes of level upper look down at level lower (else those of lower look up). */
KG_FN int kg_bp_looks_down(__global const uint* plan, kg_u32 lower, kg_u32 upper)
{
    return (plan[KG_BP_PLAN_DOWN + upper] >> lower) & 1u;
}

/* Empties the hash table, the extent histogram, the level plan and the counters. */
__kernel void kg_bp_clear(int table_size, __global uint* heads, __global uint* histogram, __global uint* plan,
                          __global uint* counts)
{
    int i = (int)get_global_id(0);
    if (i < table_size) {
        heads[i] = KG_NULL_INDEX;
    }
    if (i < KG_BP_EXTENT_BINS) {
        histogram[i] = 0u;
    }
    if (i < KG_BP_PLAN_WORDS) {
        plan[i] = 0u;
    }
    if (i < KG_CC_WORDS) {
        counts[i] = 0u;
    }
}

/* The proxy of slot i (collide/aabb.h's broadphase box), its extent binned; the slot's
 * per-step counters and marks zeroed for the stages after. */
__kernel void kg_bp_proxies(int count, float margin, __global const kg_u32* flags, __global const kg_aabb* aabb,
                            __global const kg_u32* category, __global const kg_u32* mask,
                            __global kg_bp_proxy* proxies, __global uint* histogram, __global uint* run_count,
                            __global uint* run_fill, __global uint* colors_used, __global uint* wake_marks)
{
    int i = (int)get_global_id(0);
    if (i >= count) {
        return;
    }
    run_count[i] = 0u;
    run_fill[i] = 0u;
    colors_used[i] = 0u; /* solve/coloring.h leaves it zero; zeroed here too for a buffer just grown */
    wake_marks[i] = 0u;
    kg_u32 f = flags[i];
    kg_bp_proxy p;
    int candidate = kg_broadphase_box(f, aabb[i], margin, &p.box);
    p.category = category[i];
    p.mask = mask[i];
    p.cell_x = 0;
    p.cell_y = 0;
    p.level = 0u;
    p.next = KG_NULL_INDEX;
    p.pad = 0u;
    p.flags = (candidate ? KG_BP_CANDIDATE : 0u) | (kg_flags_collide(f) ? KG_BP_MOVES : 0u);
    proxies[i] = p;
    if (candidate) {
        atomic_inc(&histogram[kg_bp_extent_bin(p.box)]);
    }
}

/* Level 0's cell size: the upper edge of the extent bin holding the 90th percentile (as
 * collide/broadphase.c sizes its grid). One work-item. */
__kernel void kg_bp_grid(__global const uint* histogram, __global float* grid)
{
    if (get_global_id(0) != 0) {
        return;
    }
    uint total = 0u;
    for (int bin = 0; bin < KG_BP_EXTENT_BINS; ++bin) {
        total += histogram[bin];
    }
    uint target = max(total / 10u * 9u, 1u);
    uint seen = 0u, bin = 0u;
    while (bin + 1u < KG_BP_EXTENT_BINS && seen + histogram[bin] < target) {
        seen += histogram[bin];
        bin += 1u;
    }
    float edge = as_float((bin + 1u) << KG_BP_EXTENT_SHIFT);
    float cell = kg_is_finite(edge) ? fmax(edge, KG_BP_MIN_CELL_SIZE) : KG_FLT_MAX;
    grid[0] = cell;
    grid[1] = 1.0f / cell;
}

/* The lowest level where box spans at most two cells per axis, and its lower corner's
 * cell there. */
KG_FN kg_u32 kg_bp_level_of(kg_aabb box, float inv_cell_size, kg_i32* x, kg_i32* y)
{
    for (kg_u32 level = 0u;; ++level) {
        *x = kg_bp_coord(box.lower.x, inv_cell_size, level);
        *y = kg_bp_coord(box.lower.y, inv_cell_size, level);
        kg_i32 x1 = kg_bp_coord(box.upper.x, inv_cell_size, level), y1 = kg_bp_coord(box.upper.y, inv_cell_size, level);
        if ((x1 - *x <= 1 && y1 - *y <= 1) || level == KG_BP_TOP_LEVEL) {
            return level;
        }
    }
}

/* Keys candidate i in the hash grid. The boxes per level are counted in the work-group
 * first, so that the shared counters see one atomic per group and level. */
__kernel void kg_bp_insert(int count, uint table_mask, uint row_stride, __global const float* grid,
                           __global kg_bp_proxy* proxies, __global uint* heads, __global uint* plan,
                           __global uint* counts)
{
    __local uint level_counts[KG_BP_LEVELS];
    int i = (int)get_global_id(0), lid = (int)get_local_id(0), size = (int)get_local_size(0);
    for (int level = lid; level < KG_BP_LEVELS; level += size) {
        level_counts[level] = 0u;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (i < count && (proxies[i].flags & KG_BP_CANDIDATE)) {
        kg_bp_table table = {table_mask, row_stride};
        kg_i32 x = 0, y = 0;
        kg_u32 level = kg_bp_level_of(proxies[i].box, grid[1], &x, &y);
        proxies[i].level = level;
        proxies[i].cell_x = x;
        proxies[i].cell_y = y;
        proxies[i].next = atomic_xchg(&heads[kg_bp_hash(x, y, level, table)], (uint)i);
        atomic_inc(&level_counts[level]);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    for (int level = lid; level < KG_BP_LEVELS; level += size) {
        if (level_counts[level] > 0u) {
            atomic_add(&plan[KG_BP_PLAN_COUNTS + level], level_counts[level]);
            atomic_or(&counts[KG_CC_LEVELS], 1u << level);
        }
    }
}

/* For each lower occupied level, the largest footprint a box of i's level would search
 * there: what looking down would cost. */
__kernel void kg_bp_measure(int count, __global const float* grid, __global const kg_bp_proxy* proxies,
                            __global uint* plan, __global const uint* counts)
{
    int i = (int)get_global_id(0);
    if (i >= count || !(proxies[i].flags & KG_BP_CANDIDATE)) {
        return;
    }
    kg_aabb box = proxies[i].box;
    kg_u32 level = proxies[i].level;
    uint levels = counts[KG_CC_LEVELS];
    for (kg_u32 lower = 0u; lower < level; ++lower) {
        if (kg_bp_occupied(levels, lower)) {
            kg_u32 cells = kg_bp_range_cells(kg_bp_search_range(box, grid[1], lower));
            atomic_max(&plan[KG_BP_PLAN_FOOTPRINTS + lower * KG_BP_LEVELS + level], cells);
        }
    }
}

/* Which way each couple of occupied levels searches: down when the upper level's boxes
 * would probe fewer cells over their footprints than the lower level's would probe
 * looking up (3 x 3 each). One work-item. */
__kernel void kg_bp_plan(__global uint* plan, __global const uint* counts)
{
    if (get_global_id(0) != 0) {
        return;
    }
    uint levels = counts[KG_CC_LEVELS];
    for (kg_u32 upper = 1u; upper < KG_BP_LEVELS; ++upper) {
        uint down = 0u;
        for (kg_u32 lower = 0u; lower < upper && kg_bp_occupied(levels, upper); ++lower) {
            float up_cost = 9.0f * (float)plan[KG_BP_PLAN_COUNTS + lower];
            float down_cost = (float)plan[KG_BP_PLAN_COUNTS + upper] *
                              (float)plan[KG_BP_PLAN_FOOTPRINTS + lower * KG_BP_LEVELS + upper];
            down |= (kg_bp_occupied(levels, lower) && down_cost < up_cost) ? 1u << lower : 0u;
        }
        plan[KG_BP_PLAN_DOWN + upper] = down;
    }
}

KG_FN int kg_bp_pairs_with(const kg_bp_proxy* p, const kg_bp_proxy* q)
{
    return kg_boxes_pair((p->flags & KG_BP_MOVES) != 0u, p->box, p->category, p->mask, (q->flags & KG_BP_MOVES) != 0u,
                         q->box, q->category, q->mask);
}

/* Pairs found by one work-item, appended to the shared list a batch at a time. */
#define KG_BP_BATCH 16

typedef struct kg_bp_batch {
    uint2 pairs[KG_BP_BATCH];
    int count;
} kg_bp_batch;

/* Writes the batch at raw[at, at + count), and counts each pair in its lower slot's run,
 * while the capacity lasts; past it, raises the overflow. */
KG_FN void kg_bp_store(kg_bp_batch* batch, uint at, int capacity, __global uint* counts, __global uint2* raw,
                       __global uint* run_count)
{
    for (int k = 0; k < batch->count; ++k) {
        if (at + (uint)k < (uint)capacity) {
            raw[at + (uint)k] = batch->pairs[k];
            atomic_inc(&run_count[batch->pairs[k].x]);
        } else {
            atomic_or(&counts[KG_CC_OVERFLOW], 1u);
        }
    }
    batch->count = 0;
}

KG_FN void kg_bp_emit(kg_bp_batch* batch, kg_u32 p, kg_u32 q, int capacity, __global uint* counts,
                      __global uint2* raw, __global uint* run_count)
{
    if (batch->count == KG_BP_BATCH) {
        uint at = atomic_add(&counts[KG_CC_PAIRS], (uint)batch->count);
        kg_bp_store(batch, at, capacity, counts, raw, run_count);
    }
    batch->pairs[batch->count++] = (uint2)(min(p, q), max(p, q));
}

/* The boxes keyed in cell (x, y) of level that pair with proxy i; in i's own cell only
 * those of higher slots. */
KG_FN void kg_bp_scan_cell(kg_bp_batch* batch, kg_u32 i, const kg_bp_proxy* p, kg_i32 x, kg_i32 y, kg_u32 level,
                           kg_bp_table table, __global const kg_bp_proxy* proxies, __global const uint* heads,
                           int capacity, __global uint* counts, __global uint2* raw, __global uint* run_count)
{
    int own_cell = level == p->level && x == p->cell_x && y == p->cell_y;
    for (kg_u32 j = heads[kg_bp_hash(x, y, level, table)]; j != KG_NULL_INDEX; j = proxies[j].next) {
        kg_bp_proxy q = proxies[j];
        if (q.level != level || q.cell_x != x || q.cell_y != y || (own_cell && j <= i)) {
            continue;
        }
        if (kg_bp_pairs_with(p, &q)) {
            kg_bp_emit(batch, i, j, capacity, counts, raw, run_count);
        }
    }
}

/* Every partner of proxy i that i is the one to find (see above), into batch. */
KG_FN void kg_bp_search(kg_bp_batch* batch, kg_u32 i, const kg_bp_proxy* p, float inv_cell_size, kg_bp_table table,
                        __global const kg_bp_proxy* proxies, __global const uint* heads, __global const uint* plan,
                        int capacity, __global uint* counts, __global uint2* raw, __global uint* run_count)
{
    uint levels = counts[KG_CC_LEVELS];
    kg_u32 own = p->level;
    kg_i32 x = p->cell_x, y = p->cell_y;
    /* own level: the rest of its cell, the cell on its right, the three above */
    kg_bp_scan_cell(batch, i, p, x, y, own, table, proxies, heads, capacity, counts, raw, run_count);
    kg_bp_scan_cell(batch, i, p, x + 1, y, own, table, proxies, heads, capacity, counts, raw, run_count);
    for (kg_i32 dx = -1; dx <= 1 && own != KG_BP_TOP_LEVEL; ++dx) {
        kg_bp_scan_cell(batch, i, p, x + dx, y + 1, own, table, proxies, heads, capacity, counts, raw, run_count);
    }
    for (kg_u32 level = 0u; level < KG_BP_LEVELS; ++level) {
        int mine = level < own ? kg_bp_looks_down(plan, level, own) : !kg_bp_looks_down(plan, own, level);
        if (level == own || !kg_bp_occupied(levels, level) || !mine) {
            continue;
        }
        kg_bp_range r = kg_bp_search_range(p->box, inv_cell_size, level);
        for (kg_i32 cy = r.y0; cy <= r.y1; ++cy) {
            for (kg_i32 cx = r.x0; cx <= r.x1; ++cx) {
                kg_bp_scan_cell(batch, i, p, cx, cy, level, table, proxies, heads, capacity, counts, raw, run_count);
            }
        }
    }
}

/* The last batch of each work-item is placed with one shared atomic per work-group: the
 * group's batches are counted in local memory, the group reserves their total, and each
 * writes at its offset in the group's range. */
__kernel void kg_bp_find(int count, int capacity, uint table_mask, uint row_stride, __global const float* grid,
                         __global const kg_bp_proxy* proxies, __global const uint* heads, __global const uint* plan,
                         __global uint* counts, __global uint2* raw, __global uint* run_count)
{
    __local uint group_count, group_at;
    int i = (int)get_global_id(0);
    kg_bp_batch batch;
    batch.count = 0;
    if (get_local_id(0) == 0) {
        group_count = 0u;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (i < count && (proxies[i].flags & KG_BP_CANDIDATE)) {
        kg_bp_proxy p = proxies[i];
        kg_bp_table table = {table_mask, row_stride};
        kg_bp_search(&batch, (kg_u32)i, &p, grid[1], table, proxies, heads, plan, capacity, counts, raw, run_count);
    }
    uint offset = atomic_add(&group_count, (uint)batch.count);
    barrier(CLK_LOCAL_MEM_FENCE);
    if (get_local_id(0) == 0) {
        group_at = atomic_add(&counts[KG_CC_PAIRS], group_count);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    kg_bp_store(&batch, group_at + offset, capacity, counts, raw, run_count);
}

/* Pair k to the run of its lower slot (run_start: the prefix sum of the run counts). */
__kernel void kg_bp_scatter(int count, __global const uint2* raw, __global const uint* run_start,
                            __global uint* run_fill, __global uint2* pairs)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        uint2 p = raw[k];
        pairs[run_start[p.x] + atomic_inc(&run_fill[p.x])] = p;
    }
}

KG_FN void kg_bp_insertion_sort(__global uint2* run, uint count)
{
    for (uint i = 1u; i < count; ++i) {
        uint2 p = run[i];
        uint j = i;
        while (j > 0u && run[j - 1u].y > p.y) {
            run[j] = run[j - 1u];
            j -= 1u;
        }
        run[j] = p;
    }
}

KG_FN void kg_bp_sift_down(__global uint2* run, uint root, uint count)
{
    for (;;) {
        uint child = 2u * root + 1u;
        if (child >= count) {
            return;
        }
        if (child + 1u < count && run[child + 1u].y > run[child].y) {
            child += 1u;
        }
        if (run[root].y >= run[child].y) {
            return;
        }
        uint2 t = run[root];
        run[root] = run[child];
        run[child] = t;
        root = child;
    }
}

/* In place, in O(n log n): long runs belong to large boxes (grounds, walls). */
KG_FN void kg_bp_heap_sort(__global uint2* run, uint count)
{
    for (uint i = count / 2u; i > 0u; --i) {
        kg_bp_sift_down(run, i - 1u, count);
    }
    for (uint end = count - 1u; end > 0u; --end) {
        uint2 t = run[0];
        run[0] = run[end];
        run[end] = t;
        kg_bp_sift_down(run, 0u, end);
    }
}

/* Run a in order of the upper slot; the slots of a run are distinct, so any sort gives
 * the one order. */
__kernel void kg_bp_sort_runs(int count, __global const uint* run_start, __global uint2* pairs)
{
    int a = (int)get_global_id(0);
    if (a >= count) {
        return;
    }
    uint n = run_start[a + 1] - run_start[a];
    if (n <= KG_BP_SHORT_RUN) {
        kg_bp_insertion_sort(pairs + run_start[a], n);
    } else {
        kg_bp_heap_sort(pairs + run_start[a], n);
    }
}
