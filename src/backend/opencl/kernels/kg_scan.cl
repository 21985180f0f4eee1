/* Exclusive prefix sums over uint arrays, in at most KG_SCAN_MAX_BLOCKS blocks: the
 * building block of every stage that turns per-element counts into places. */
#include "core/kg_layout.h"
#include "kg_collide_shared.h"

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
