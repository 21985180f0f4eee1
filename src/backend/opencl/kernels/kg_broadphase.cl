/* The broadphase's kernels: one work-item per element of each step of the search, each
 * calling that step's function (collide/broadphase_grid.h), every pair in the order the
 * CPU backend lists them. Host side: cl_collide.c; the sorts are cl_sort.c's. */
#include "core/kg_layout.h"
#include "collide/broadphase_grid.h"
#include "kg_collide_shared.h"

/* Empties the extent histogram, the counters and the small and large counts; the grid
 * bounds start empty. */
__kernel void kg_bp_clear(__global uint* histogram, __global uint* counts, __global uint* words)
{
    int i = (int)get_global_id(0);
    if (i < KG_BP_EXTENT_BINS) {
        histogram[i] = 0u;
    }
    if (i < KG_CC_WORDS) {
        counts[i] = 0u;
    }
    if (i < KG_BP_WORDS) {
        words[i] = kg_bp_word_cleared(i);
    }
}

/* The proxy of slot i, its extent binned; the slot's per-step counters and marks zeroed
 * for the stages after. */
__kernel void kg_bp_proxies(int count, float margin, __global const kg_u32* flags, __global const kg_aabb* aabb,
                            __global const kg_u32* category, __global const kg_u32* mask,
                            __global kg_bp_proxy* proxies, __global uint* histogram, __global uint* run_count,
                            __global uint* run_fill, __global uint* wake_marks)
{
    int i = (int)get_global_id(0);
    if (i >= count) {
        return;
    }
    run_count[i] = run_fill[i] = wake_marks[i] = 0u;
    kg_bp_proxy p = kg_bp_proxy_of(flags[i], aabb[i], category[i], mask[i], margin, (kg_u32)i);
    proxies[i] = p;
    if (p.body != KG_NULL_INDEX) {
        atomic_inc(&histogram[kg_bp_extent_bin(p.box)]);
    }
}

/* The cell size, from the histogram: one work-item over its constant 2048 bins. */
__kernel void kg_bp_cells(__global const uint* histogram, __global kg_bp_grid* grid)
{
    if (get_global_id(0) == 0) {
        grid->cell_size = kg_bp_cell_size(histogram);
    }
}

/* Slot i's lower corner into the grid bounds (sortable bits: the same bits in any order;
 * read first, so that few work-items need the atomics). */
__kernel void kg_bp_bounds(int count, __global const kg_bp_proxy* proxies, __global const kg_bp_grid* grid,
                           __global uint* words)
{
    int i = (int)get_global_id(0);
    if (i >= count || proxies[i].body == KG_NULL_INDEX || !kg_bp_bounds_grid(proxies[i].box, grid->cell_size)) {
        return;
    }
    kg_vec2 corner = kg_bp_corner(proxies[i].box);
    uint x = kg_bp_sortable_bits(corner.x), y = kg_bp_sortable_bits(corner.y);
    __global uint* bounds = words + KG_BP_BOUNDS;
    if (x < bounds[0]) atomic_min(&bounds[0], x);
    if (y < bounds[1]) atomic_min(&bounds[1], y);
    if (x > bounds[2]) atomic_max(&bounds[2], x);
    if (y > bounds[3]) atomic_max(&bounds[3], y);
}

/* The grid over the bounds. One work-item. */
__kernel void kg_bp_build_grid(__global kg_bp_grid* grid, __global const uint* words)
{
    if (get_global_id(0) == 0) {
        *grid = kg_bp_grid_make(grid->cell_size, words + KG_BP_BOUNDS);
    }
}

/* Slot i's sort keys: its cell when small, its lower x when large (each sort puts the
 * others last). */
__kernel void kg_bp_keys(int count, __global const kg_bp_grid* grid, __global const kg_bp_proxy* proxies,
                         __global uint* keys, __global uint* items, __global uint* large_keys,
                         __global uint* large_items)
{
    int i = (int)get_global_id(0);
    if (i < count) {
        kg_bp_grid g = *grid;
        keys[i] = kg_bp_slot_key(&g, proxies[i]);
        large_keys[i] = kg_bp_large_key(proxies[i], keys[i]);
        items[i] = large_items[i] = (uint)i;
    }
}

/* The small proxies in key order; where the small and the large keys end. */
__kernel void kg_bp_gather(int count, __global const uint* keys, __global const uint* items,
                           __global const uint* large_keys, __global const kg_bp_proxy* proxies,
                           __global kg_bp_proxy* sorted, __global uint* words)
{
    int i = (int)get_global_id(0);
    if (i < count && keys[i] != KG_BP_NOT_KEYED) {
        sorted[i] = proxies[items[i]];
    }
    if (i < count && kg_bp_last_keyed(keys, i, count)) {
        words[KG_BP_SMALL] = (uint)i + 1u;
    }
    if (i < count && kg_bp_last_keyed(large_keys, i, count)) {
        words[KG_BP_LARGE] = (uint)i + 1u;
    }
}

/* How many pairs element e finds (kg_bp_find_element). */
__kernel void kg_bp_count_pairs(int slots, __global const kg_bp_grid* grid, __global const uint* keys,
                                __global const kg_bp_proxy* sorted, __global const uint* large_items,
                                __global const kg_bp_proxy* proxies, __global const uint* words,
                                __global uint* found)
{
    int e = (int)get_global_id(0);
    if (e < 2 * slots) {
        kg_bp_view v = kg_bp_view_make(*grid, keys, sorted, (int)words[KG_BP_SMALL], large_items, proxies,
                                       (int)words[KG_BP_LARGE]);
        kg_bp_sink s = kg_bp_sink_make(0, 0u, 0u, 0);
        kg_bp_find_element(&s, &v, e, slots);
        found[e] = s.at;
    }
}

/* Element e's pairs at its place (offsets: the prefix sum of the counts), within capacity. */
__kernel void kg_bp_write_pairs(int slots, int capacity, __global const kg_bp_grid* grid, __global const uint* keys,
                                __global const kg_bp_proxy* sorted, __global const uint* large_items,
                                __global const kg_bp_proxy* proxies, __global const uint* words,
                                __global const uint* offsets, __global kg_pair* raw)
{
    int e = (int)get_global_id(0);
    if (e < 2 * slots) {
        kg_bp_view v = kg_bp_view_make(*grid, keys, sorted, (int)words[KG_BP_SMALL], large_items, proxies,
                                       (int)words[KG_BP_LARGE]);
        kg_bp_sink s = kg_bp_sink_make(raw, offsets[e], (uint)capacity, 0);
        kg_bp_find_element(&s, &v, e, slots);
    }
}

/* Pair k counted in its lower slot's run. */
__kernel void kg_bp_count_runs(int count, __global const kg_pair* raw, __global uint* run_count)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        atomic_inc(&run_count[raw[k].a]);
    }
}

/* Pair k to the run of its lower slot (run_start: the prefix sum of the run counts); the
 * order within a run is the sort's. */
__kernel void kg_bp_scatter(int count, __global const kg_pair* raw, __global const uint* run_start,
                            __global uint* run_fill, __global kg_pair* pairs)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        pairs[run_start[raw[k].a] + atomic_inc(&run_fill[raw[k].a])] = raw[k];
    }
}

/* Run a in order of the upper slot. */
__kernel void kg_bp_sort_runs(int count, __global const uint* run_start, __global kg_pair* pairs)
{
    int a = (int)get_global_id(0);
    if (a < count) {
        kg_bp_sort_run(pairs + run_start[a], (int)(run_start[a + 1] - run_start[a]));
    }
}
