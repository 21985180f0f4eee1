/* The collision stage's kernels: broadphase, narrowphase, persistent contacts and the
 * constraint graph colouring, with the prefix sums they share. Built in one program after
 * kg_step.cl, whose body flag helpers (kg_type_of, kg_is_simulated) they use.
 *
 * Each stage ends in the exact list the CPU backend builds, in the same order, although
 * some kernels append with integer atomics in whatever order work-items run: every
 * atomically filled list is either consumed by an order-independent step (counts, sets
 * of neighbours) or put in order before it is used (pair runs sorted by partner). No
 * float is ever accumulated atomically. Element counts the host does not know come from
 * the counters buffer (KG_CC_*); kernels return past them. */
#include "core/kg_layout.h"
#include "collide/aabb.h"
#include "collide/manifold.h"
#include "kg_collide_shared.h"

/* Cell coordinates are clamped to this (exact in float), so any finite position maps. */
#define KG_BP_COORD_LIMIT 1073741824.0f

/* Below this a cell never gets (m), as in collide/broadphase.c. */
#define KG_BP_MIN_CELL_SIZE 1.0e-6f

/* Runs of pairs up to this length are insertion sorted; longer ones heap sorted. */
#define KG_BP_SHORT_RUN 32

/* ---- prefix sums ------------------------------------------------------------------ */

KG_FN int kg_scan_block_count(int count, int block) { return count > 0 ? (count + block - 1) / block : 1; }

/* The sum of each block of values: work-item g sums [g * block, (g + 1) * block). */
__kernel void kg_scan_blocks(int count, int block, __global const uint* values, __global uint* block_sums)
{
    int g = (int)get_global_id(0);
    if (g >= kg_scan_block_count(count, block)) {
        return;
    }
    int end = min(count, (g + 1) * block);
    uint sum = 0u;
    for (int k = g * block; k < end; ++k) {
        sum += values[k];
    }
    block_sums[g] = sum;
}

/* Exclusive prefix sum of values[0, count) into offsets[0, count], offsets[count] being
 * the total, also written to counts[total_slot] unless total_slot < 0. values and offsets
 * may be the same buffer: each work-item reads an element before it writes its offset. */
__kernel void kg_scan_apply(int count, int block, __global const uint* values, __global uint* offsets,
                            __global const uint* block_sums, __global uint* counts, int total_slot)
{
    int g = (int)get_global_id(0);
    int blocks = kg_scan_block_count(count, block);
    if (g >= blocks) {
        return;
    }
    uint sum = 0u;
    for (int h = 0; h < g; ++h) {
        sum += block_sums[h];
    }
    int end = min(count, (g + 1) * block);
    for (int k = g * block; k < end; ++k) {
        uint v = values[k];
        offsets[k] = sum;
        sum += v;
    }
    if (g == blocks - 1) {
        offsets[count] = sum;
        if (total_slot >= 0) {
            counts[total_slot] = sum;
        }
    }
}

/* ---- broadphase: a hierarchical hash grid ------------------------------------------ */

/* The broadphase finds every pair collide/broadphase.h specifies (candidates, filter,
 * fattened boxes overlapping), each once, and lists them sorted by (a, b):
 *  - boxes are keyed by the cell of their lower corner, at the lowest grid level where
 *    they span at most two cells per axis (level 0's cells are the 90th percentile of the
 *    box extents, each level doubles them), in a hash table of singly linked lists;
 *  - each box looks for partners at its own level and above: a box overlapping it has its
 *    lower corner in the cells of its footprint widened by one cell down and left (cell
 *    coordinates are monotone in position, and a partner spans at most two cells). At
 *    its own level it takes partners of higher slots, above it takes every partner, so
 *    each pair is found once;
 *  - pairs are appended, counted per lower slot, scattered to their slot's run and each
 *    run sorted by the upper slot. */

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

KG_FN kg_u32 kg_bp_hash(kg_i32 x, kg_i32 y, kg_u32 level, kg_u32 table_mask)
{
    kg_u32 h = (kg_u32)x * 0x8DA6B343u ^ (kg_u32)y * 0xD8163841u ^ level * 0xCB1AB31Fu;
    h ^= h >> 15;
    h *= 0x2C1B3C6Du;
    h ^= h >> 12;
    return h & table_mask;
}

/* Empties the hash table, the extent histogram and the counters. */
__kernel void kg_bp_clear(int table_size, __global uint* heads, __global uint* histogram, __global uint* counts)
{
    int i = (int)get_global_id(0);
    if (i < table_size) {
        heads[i] = KG_NULL_INDEX;
    }
    if (i < KG_BP_EXTENT_BINS) {
        histogram[i] = 0u;
    }
    if (i < KG_CC_WORDS) {
        counts[i] = 0u;
    }
}

/* The proxy of slot i (kg_gather_proxies of collide/broadphase.c), its extent binned;
 * the slot's per-step counters zeroed for the stages after. */
__kernel void kg_bp_proxies(int count, float margin, __global const kg_u32* flags, __global const kg_aabb* aabb,
                            __global const kg_u32* category, __global const kg_u32* mask,
                            __global kg_bp_proxy* proxies, __global uint* histogram, __global uint* run_fill,
                            __global uint* degree, __global uint* degree_fill, __global uint* run_count)
{
    int i = (int)get_global_id(0);
    if (i >= count) {
        return;
    }
    run_count[i] = 0u;
    run_fill[i] = 0u;
    degree[i] = 0u;
    degree_fill[i] = 0u;
    kg_u32 f = flags[i];
    kg_u32 type = kg_type_of(f);
    kg_bp_proxy p;
    p.box = kg_aabb_fatten(aabb[i], margin);
    p.category = category[i];
    p.mask = mask[i];
    p.cell_x = 0;
    p.cell_y = 0;
    p.level = 0u;
    p.next = KG_NULL_INDEX;
    p.pad = 0u;
    int candidate = (f & (KG_FLAG_ALIVE | KG_FLAG_FROZEN)) == KG_FLAG_ALIVE && kg_vec_is_finite(p.box.lower) &&
                    kg_vec_is_finite(p.box.upper);
    int moves = type == KG_BODY_DYNAMIC || type == KG_BODY_PARTICLE;
    p.flags = (candidate ? KG_BP_CANDIDATE : 0u) | (moves ? KG_BP_MOVES : 0u);
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

/* Keys candidate i at the lowest level where it spans at most two cells per axis. */
__kernel void kg_bp_insert(int count, uint table_mask, __global const float* grid, __global kg_bp_proxy* proxies,
                           __global uint* heads, __global uint* counts)
{
    int i = (int)get_global_id(0);
    if (i >= count || !(proxies[i].flags & KG_BP_CANDIDATE)) {
        return;
    }
    kg_aabb box = proxies[i].box;
    float inv = grid[1];
    kg_u32 level = 0u;
    kg_i32 x0 = 0, y0 = 0;
    for (;; ++level) {
        x0 = kg_bp_coord(box.lower.x, inv, level);
        y0 = kg_bp_coord(box.lower.y, inv, level);
        kg_i32 x1 = kg_bp_coord(box.upper.x, inv, level), y1 = kg_bp_coord(box.upper.y, inv, level);
        if ((x1 - x0 <= 1 && y1 - y0 <= 1) || level == KG_BP_TOP_LEVEL) {
            break;
        }
    }
    proxies[i].level = level;
    proxies[i].cell_x = x0;
    proxies[i].cell_y = y0;
    proxies[i].next = atomic_xchg(&heads[kg_bp_hash(x0, y0, level, table_mask)], (uint)i);
    atomic_or(&counts[KG_CC_LEVELS], 1u << level);
}

/* kg_consider of collide/broadphase.c: one of them moves, the boxes overlap, the filters
 * accept each other. */
KG_FN int kg_bp_pairs_with(const kg_bp_proxy* p, const kg_bp_proxy* q)
{
    return ((p->flags | q->flags) & KG_BP_MOVES) && kg_aabb_overlap(p->box, q->box) && (p->category & q->mask) &&
           (q->category & p->mask);
}

/* Appends (a, b), and counts it in a's run, while the capacity lasts. */
KG_FN void kg_bp_emit(kg_u32 a, kg_u32 b, int capacity, __global uint* counts, __global uint2* raw,
                      __global uint* run_count)
{
    uint at = atomic_inc(&counts[KG_CC_PAIRS]);
    if (at < (uint)capacity) {
        raw[at] = (uint2)(a, b);
        atomic_inc(&run_count[a]);
    } else {
        atomic_or(&counts[KG_CC_OVERFLOW], 1u);
    }
}

/* The boxes keyed in cell (x, y) of level that pair with proxy i. */
KG_FN void kg_bp_scan_cell(kg_u32 i, const kg_bp_proxy* p, kg_i32 x, kg_i32 y, kg_u32 level, uint table_mask,
                           __global const kg_bp_proxy* proxies, __global const uint* heads, int capacity,
                           __global uint* counts, __global uint2* raw, __global uint* run_count)
{
    for (kg_u32 j = heads[kg_bp_hash(x, y, level, table_mask)]; j != KG_NULL_INDEX; j = proxies[j].next) {
        kg_bp_proxy q = proxies[j];
        if (q.level != level || q.cell_x != x || q.cell_y != y || (level == p->level && j <= i)) {
            continue;
        }
        if (kg_bp_pairs_with(p, &q)) {
            kg_bp_emit(min(i, j), max(i, j), capacity, counts, raw, run_count);
        }
    }
}

__kernel void kg_bp_find(int count, int capacity, uint table_mask, __global const float* grid,
                         __global const kg_bp_proxy* proxies, __global const uint* heads, __global uint* counts,
                         __global uint2* raw, __global uint* run_count)
{
    int i = (int)get_global_id(0);
    if (i >= count) {
        return;
    }
    kg_bp_proxy p = proxies[i];
    if (!(p.flags & KG_BP_CANDIDATE)) {
        return;
    }
    float inv = grid[1];
    uint levels = counts[KG_CC_LEVELS];
    for (kg_u32 level = p.level; level < KG_BP_LEVELS; ++level) {
        if (!((levels >> level) & 1u)) {
            continue;
        }
        kg_i32 x0 = kg_bp_coord(p.box.lower.x, inv, level) - 1, x1 = kg_bp_coord(p.box.upper.x, inv, level);
        kg_i32 y0 = kg_bp_coord(p.box.lower.y, inv, level) - 1, y1 = kg_bp_coord(p.box.upper.y, inv, level);
        for (kg_i32 y = y0; y <= y1; ++y) {
            for (kg_i32 x = x0; x <= x1; ++x) {
                kg_bp_scan_cell((kg_u32)i, &p, x, y, level, table_mask, proxies, heads, capacity, counts, raw,
                                run_count);
            }
        }
    }
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

/* ---- narrowphase and persistence ------------------------------------------------------ */

/* kg_narrowphase_range of collide/collide.c: the manifold of pair k, and whether it
 * touches (within its speculative distance). */
__kernel void kg_narrowphase(int count, float speculative_distance, float dt, __global const uint2* pairs,
                             __global const kg_shape* shape, __global const kg_xf* xf,
                             __global const kg_vec2* velocity, __global kg_manifold* manifolds,
                             __global uint* touching)
{
    int k = (int)get_global_id(0);
    if (k >= count) {
        return;
    }
    uint2 p = pairs[k];
    kg_shape a = shape[p.x], b = shape[p.y];
    float speculative = kg_pair_speculative(speculative_distance, velocity[p.x], velocity[p.y], dt);
    kg_manifold m = kg_collide_shapes(&a, xf[p.x], &b, xf[p.y], speculative);
    manifolds[k] = m;
    touching[k] = m.point_count > 0 ? 1u : 0u;
}

/* Last step's contact of pair (a, b) among its body contacts (sorted by (a, b)), or -1. */
KG_FN int kg_find_previous(__global const kg_contact* previous, int count, kg_u32 a, kg_u32 b)
{
    int lo = 0, hi = count;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        kg_u32 ma = previous[mid].a, mb = previous[mid].b;
        if (ma < a || (ma == a && mb < b)) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    return lo < count && previous[lo].a == a && previous[lo].b == b ? lo : -1;
}

/* kg_build_contacts of collide/collide.c: touching pair k becomes contact index[k] (the
 * prefix sum of touching keeps the pairs' order), with last step's impulses carried. */
__kernel void kg_build_contacts(int count, __global const uint2* pairs, __global const kg_manifold* manifolds,
                                __global const uint* index, __global const kg_contact* previous,
                                int previous_count, __global const float* friction,
                                __global const float* restitution, __global kg_contact* contacts)
{
    int k = (int)get_global_id(0);
    if (k >= count || index[k + 1] == index[k]) {
        return;
    }
    uint2 p = pairs[k];
    kg_contact c;
    c.manifold = manifolds[k];
    int old = kg_find_previous(previous, previous_count, p.x, p.y);
    if (old >= 0) {
        kg_manifold carried = previous[old].manifold;
        kg_contact_carry_impulses(&c.manifold, &carried);
    }
    c.a = p.x;
    c.b = p.y;
    c.tile = KG_NULL_INDEX;
    c.friction = sqrtf(friction[p.x] * friction[p.y]);
    c.restitution = fmaxf(restitution[p.x], restitution[p.y]);
    c.pad[0] = 0u;
    c.pad[1] = 0u;
    c.pad[2] = 0u;
    contacts[index[k]] = c;
}

/* ---- graph colouring ------------------------------------------------------------------ */

/* solve/graph_color.c colours contacts greedily in order: contact k takes the lowest
 * colour that no earlier contact sharing a moving body with it took, or the overflow when
 * all KG_COLOR_COUNT are taken. The same colours in parallel: contact k is decided as soon
 * as all its earlier neighbours are (rounds, one launch each), and a last work-item
 * decides the rest in order. Neighbours come from an incidence list per moving body. */

KG_FN int kg_slot_moves(__global const kg_u32* flags, kg_u32 slot)
{
    return slot != KG_NULL_INDEX && kg_is_simulated(flags[slot]);
}

/* Counts each moving body's contacts; marks every contact undecided. */
__kernel void kg_color_degrees(__global const uint* counts, __global const kg_contact* contacts,
                               __global const kg_u32* flags, __global uint* degree, __global uint* colors)
{
    int k = (int)get_global_id(0);
    if (k >= (int)counts[KG_CC_CONTACTS]) {
        return;
    }
    colors[k] = KG_COLOR_UNDECIDED;
    kg_u32 a = contacts[k].a, b = contacts[k].b;
    if (kg_slot_moves(flags, a)) {
        atomic_inc(&degree[a]);
    }
    if (kg_slot_moves(flags, b)) {
        atomic_inc(&degree[b]);
    }
}

/* Lists contact k under each of its moving bodies (start: prefix sum of the degrees). */
__kernel void kg_color_incidence(__global const uint* counts, __global const kg_contact* contacts,
                                 __global const kg_u32* flags, __global const uint* start, __global uint* fill,
                                 __global uint* incidence)
{
    int k = (int)get_global_id(0);
    if (k >= (int)counts[KG_CC_CONTACTS]) {
        return;
    }
    kg_u32 a = contacts[k].a, b = contacts[k].b;
    if (kg_slot_moves(flags, a)) {
        incidence[start[a] + atomic_inc(&fill[a])] = (uint)k;
    }
    if (kg_slot_moves(flags, b)) {
        incidence[start[b] + atomic_inc(&fill[b])] = (uint)k;
    }
}

/* Adds the colours of contact k's earlier neighbours through body slot to *used; 0 when
 * one of them is still undecided. */
KG_FN int kg_gather_colors(kg_u32 slot, uint k, __global const uint* start, __global const uint* incidence,
                           __global const uint* colors, uint* used)
{
    for (uint e = start[slot]; e < start[slot + 1u]; ++e) {
        uint j = incidence[e];
        if (j >= k) {
            continue;
        }
        uint c = colors[j];
        if (c == KG_COLOR_UNDECIDED) {
            return 0;
        }
        if (c < KG_COLOR_COUNT) {
            *used |= 1u << c;
        }
    }
    return 1;
}

/* kg_pick_color of solve/graph_color.c, or KG_COLOR_UNDECIDED while an earlier neighbour
 * is undecided. */
KG_FN uint kg_color_of(uint k, __global const kg_contact* contacts, __global const kg_u32* flags,
                       __global const uint* start, __global const uint* incidence, __global const uint* colors)
{
    kg_u32 a = contacts[k].a, b = contacts[k].b;
    uint used = 0u;
    int ready = (!kg_slot_moves(flags, a) || kg_gather_colors(a, k, start, incidence, colors, &used)) &&
                (!kg_slot_moves(flags, b) || kg_gather_colors(b, k, start, incidence, colors, &used));
    if (!ready) {
        return KG_COLOR_UNDECIDED;
    }
    uint c = 0u;
    while (c < KG_COLOR_COUNT && ((used >> c) & 1u)) {
        c += 1u;
    }
    return c;
}

/* One round: reads last round's colours, writes this round's (no work-item reads what
 * another writes in the same launch). */
__kernel void kg_color_round(__global const uint* counts, __global const kg_contact* contacts,
                             __global const kg_u32* flags, __global const uint* start,
                             __global const uint* incidence, __global const uint* colors_in, __global uint* colors_out)
{
    int k = (int)get_global_id(0);
    if (k >= (int)counts[KG_CC_CONTACTS]) {
        return;
    }
    uint c = colors_in[k];
    colors_out[k] = c != KG_COLOR_UNDECIDED ? c : kg_color_of((uint)k, contacts, flags, start, incidence, colors_in);
}

/* The contacts the rounds left undecided, in order, by one work-item: when it reaches
 * one, every earlier contact is decided. */
__kernel void kg_color_finish(__global const uint* counts, __global const kg_contact* contacts,
                              __global const kg_u32* flags, __global const uint* start,
                              __global const uint* incidence, __global uint* colors)
{
    if (get_global_id(0) != 0) {
        return;
    }
    uint count = counts[KG_CC_CONTACTS];
    for (uint k = 0u; k < count; ++k) {
        if (colors[k] == KG_COLOR_UNDECIDED) {
            colors[k] = kg_color_of(k, contacts, flags, start, incidence, colors);
        }
    }
}

/* How many contacts of each colour block g holds, at histogram[colour * blocks + g], so
 * that the prefix sum of the histogram gives each block's first place in each colour. */
__kernel void kg_color_count(int block, int blocks, __global const uint* counts, __global const uint* colors,
                             __global uint* histogram)
{
    int g = (int)get_global_id(0);
    if (g >= blocks) {
        return;
    }
    uint sizes[KG_COLOR_COUNT + 1];
    for (int c = 0; c <= KG_COLOR_COUNT; ++c) {
        sizes[c] = 0u;
    }
    int end = min((int)counts[KG_CC_CONTACTS], (g + 1) * block);
    for (int k = g * block; k < end; ++k) {
        sizes[colors[k]] += 1u;
    }
    for (int c = 0; c <= KG_COLOR_COUNT; ++c) {
        histogram[c * blocks + g] = sizes[c];
    }
}

/* graph_color.h's order: contact indices grouped by colour, in contact order within each
 * (each block places its own contacts in order from its offsets). */
__kernel void kg_color_scatter(int block, int blocks, __global const uint* counts, __global const uint* colors,
                               __global const uint* offsets, __global int* order)
{
    int g = (int)get_global_id(0);
    if (g >= blocks) {
        return;
    }
    uint next[KG_COLOR_COUNT + 1];
    for (int c = 0; c <= KG_COLOR_COUNT; ++c) {
        next[c] = offsets[c * blocks + g];
    }
    int end = min((int)counts[KG_CC_CONTACTS], (g + 1) * block);
    for (int k = g * block; k < end; ++k) {
        order[next[colors[k]]++] = k;
    }
}

/* graph_color.h's color_start, for the solver's kernels and, in the counters, the host. */
__kernel void kg_color_starts(int blocks, __global const uint* offsets, __global uint* counts,
                              __global int* color_start)
{
    if (get_global_id(0) != 0) {
        return;
    }
    for (int c = 0; c <= KG_COLOR_COUNT; ++c) {
        color_start[c] = (int)offsets[c * blocks];
        counts[KG_CC_COLOR_START + c] = offsets[c * blocks];
    }
    color_start[KG_COLOR_COUNT + 1] = (int)counts[KG_CC_CONTACTS];
    counts[KG_CC_COLOR_START + KG_COLOR_COUNT + 1] = counts[KG_CC_CONTACTS];
}
