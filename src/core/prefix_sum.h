/* Exclusive prefix sums in blocks (shared by the CPU backend and the OpenCL kernels): the
 * sum of each block, then each block's elements offset by the sums of the blocks before
 * it. The CPU sums with one block; the device with one work-item per block
 * (backend/opencl/kernels/kg_scan.cl). */
#ifndef KG_PREFIX_SUM_H
#define KG_PREFIX_SUM_H

#include "core/ranges.h"

/* At least one block, which writes the total (0) when count is. */
KG_FN int kg_scan_block_count(int count, int block) { return count > 0 ? kg_parts(count, block) : 1; }

/* The sum of block g of values: [g * block, (g + 1) * block). */
KG_FN kg_u32 kg_scan_block_sum(KG_GLOBAL const kg_u32* values, int count, int block, int g)
{
    kg_u32 sum = 0u;
    for (int k = g * block; k < kg_part_end(count, block, g); ++k) {
        sum += values[k];
    }
    return sum;
}

/* Exclusive prefix sum of block g of values into offsets (may be values: each element is
 * read before its offset is written), after the sums of blocks [0, g). The last block
 * also writes offsets[count], the total, and returns it. */
KG_FN kg_u32 kg_scan_block_apply(KG_GLOBAL const kg_u32* values, KG_GLOBAL kg_u32* offsets, int count, int block,
                                 int g, KG_GLOBAL const kg_u32* block_sums)
{
    kg_u32 sum = 0u;
    for (int h = 0; h < g; ++h) {
        sum += block_sums[h];
    }
    for (int k = g * block; k < kg_part_end(count, block, g); ++k) {
        kg_u32 v = values[k];
        offsets[k] = sum;
        sum += v;
    }
    if (g == kg_scan_block_count(count, block) - 1) {
        offsets[count] = sum;
    }
    return sum;
}

#endif
