/* Broadphase: the pairs of bodies whose bounding boxes overlap.
 *
 * Design (sort-based, so it ports to OpenCL as histogram + prefix sum + scatter passes):
 *  - A uniform grid whose cell size is about the 90th percentile of the fattened box extents.
 *    Every box that spans at most 2x2 cells is "small" and is keyed once, by the cell of
 *    its lower corner (row-major key), and the keys are radix sorted. Two overlapping small
 *    boxes then have lower-corner cells at most one apart on each axis, so each small box
 *    scans its own cell, the cell to its right and the three cells above it: every pair once.
 *  - Boxes spanning more cells (grounds, walls, terrain) are "large": each one scans the
 *    sorted keys row by row over its own footprint, and large boxes meet each other in a
 *    sort-and-sweep along x. A few huge static walls therefore cost their footprint, never
 *    n per small body.
 *  - The pairs are counted per lower slot and written to the caller's buffer in discovery
 *    order, then moved in place into their slot's run (prefix-summed offsets), and each
 *    slot's short run is sorted by the upper slot: the output is sorted by (a, b) without
 *    a global sort of the pairs, and without a second pair buffer. When the pairs do not
 *    all fit the caller's buffer, the search runs again to count them per slot, to place
 *    those that fit, and to find the partners of the run the capacity cuts (no
 *    allocation).
 *  - Each step is a function of one element (collide/broadphase_grid.h), shared with the
 *    OpenCL kernels, which run the same algorithm; pairs go through a sink that counts
 *    them or writes them at an offset, so a device pass can count, sum and write.
 *  - Each search notes what it saw of every slot (box, filter, whether it moves), so that a
 *    search made with boxes enlarged beyond the margin can serve the next steps: while
 *    kg_broadphase_covers says every box is still within what was seen, its pairs hold
 *    every pair a search now would find, and kg_broadphase_keep_pairs picks those.
 * Everything is integer keyed, so the output depends only on the input.
 * Memory: 140 bytes per body of capacity (proxies twice and what was seen of each slot,
 * 32 each; six sort buffers and three run arrays, 4 each; room for a cut run's partners,
 * 8), all allocated by kg_broadphase_create. */
#ifndef KG_BROADPHASE_H
#define KG_BROADPHASE_H

#include "collide/broadphase_grid.h"
#include "core/body_pool.h"

typedef struct kg_broadphase kg_broadphase;

/* Allocates every scratch buffer for up to capacity bodies (slots [0, capacity)). */
kg_result kg_broadphase_create(int capacity, kg_broadphase** out);
void kg_broadphase_destroy(kg_broadphase* bp);

/* Finds every pair of slots (a, b), a < b, such that:
 *  - both are alive, with finite bounds (others are skipped);
 *  - at least one is a moving dynamic body or particle: static, kinematic and frozen
 *    bodies never pair with each other (a frozen body is as solid as a static one);
 *  - (category[a] & mask[b]) && (category[b] & mask[a]);
 *  - their aabb fattened by margin on every side overlap (touching counts, as in
 *    kg_aabb_overlap).
 * Writes the first min(total, capacity) of them, sorted by (a, b), into out (may be NULL
 * when capacity is 0) and returns the total, which exceeds capacity on overflow: the caller
 * grows its buffer to the returned count and calls again. Allocates nothing; the result
 * depends only on the input. bodies->high_water must not exceed the broadphase capacity,
 * and margin must be >= 0 (boxes turned inside out would escape the grid). */
int kg_broadphase_find_pairs(kg_broadphase* bp, const kg_body_pool* bodies, float margin, kg_pair* out,
                             int capacity);

/* Whether a search with margin now would find no pair that the last search did not: every
 * slot it looked at (and no other) is as it was then, alive or not, with the same filter
 * and motion type, and its box fattened by margin lies within the box that search saw
 * (fattened by its own margin). Then stores those boxes for kg_broadphase_keep_pairs. */
int kg_broadphase_covers(kg_broadphase* bp, const kg_body_pool* bodies, float margin);

/* kg_broadphase_covers in parts, for threads: whether the last search looked at the same
 * slots as the pool has now; then whether each slot of [begin, end) is covered (storing
 * their boxes). covers = same slots and every range covered. */
int kg_broadphase_same_slots(const kg_broadphase* bp, const kg_body_pool* bodies);
int kg_broadphase_covers_range(kg_broadphase* bp, const kg_body_pool* bodies, float margin, int begin, int end);

/* After kg_broadphase_covers said yes, given the last search's pairs (found, count): the
 * pairs a search with that margin would give now, in the same (a, b) order, as
 * kg_broadphase_find_pairs writes and counts them (the first capacity written, the total
 * returned). The other conditions of a pair are unchanged, so only the boxes are tested. */
int kg_broadphase_keep_pairs(const kg_broadphase* bp, const kg_pair* found, int count, kg_pair* out, int capacity);

/* kg_broadphase_keep_pairs in parts, for threads: marks kept[k] (1 or 0) for each found
 * pair k of [begin, end) and returns how many are kept; the caller then writes the kept
 * ones in order. */
int kg_broadphase_mark_kept(const kg_broadphase* bp, const kg_pair* found, int begin, int end, unsigned char* kept);

/* The grid of the last search, for tests and benchmarks (a step served by kept pairs
 * searches nothing): cell size (m) and how many boxes
 * were small (keyed in the grid) and large (handled apart). */
typedef struct kg_broadphase_stats {
    float cell_size;
    int small_count;
    int large_count;
} kg_broadphase_stats;

kg_broadphase_stats kg_broadphase_get_stats(const kg_broadphase* bp);

#endif
