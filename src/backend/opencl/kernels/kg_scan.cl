/* The device's prefix sums and stable sorts: the building blocks of every stage that
 * turns per-element counts into places (core/prefix_sum.h, core/counting_sort.h; the host
 * side is cl_sort.c). */
#include "core/kg_layout.h"
#include "core/counting_sort.h"
#include "core/prefix_sum.h"
#include "kg_collide_shared.h"

/* The sum of block g of values. */
__kernel void kg_scan_blocks(int count, int block, __global const uint* values, __global uint* block_sums)
{
    int g = (int)get_global_id(0);
    if (g < kg_scan_block_count(count, block)) {
        block_sums[g] = kg_scan_block_sum(values, count, block, g);
    }
}

/* Exclusive prefix sum of values[0, count) into offsets[0, count] (may be values), the
 * total also into counts[total_slot] unless total_slot < 0. */
__kernel void kg_scan_apply(int count, int block, __global const uint* values, __global uint* offsets,
                            __global const uint* block_sums, __global uint* counts, int total_slot)
{
    int g = (int)get_global_id(0);
    if (g >= kg_scan_block_count(count, block)) {
        return;
    }
    uint total = kg_scan_block_apply(values, offsets, count, block, g, block_sums);
    if (g == kg_scan_block_count(count, block) - 1 && total_slot >= 0) {
        counts[total_slot] = total;
    }
}

/* The digit counts of chunk g of a counting-sort pass. */
__kernel void kg_sort_count(int count, int chunk_size, int shift, int bits, __global const uint* keys,
                            __global uint* counts)
{
    int g = (int)get_global_id(0);
    if (g < kg_parts(count, chunk_size)) {
        kg_sort_count_chunk(keys, count, chunk_size, g, kg_parts(count, chunk_size), shift, bits, counts);
    }
}

/* Chunk g's keys and items to their places (offsets: the prefix sum of the counts). */
__kernel void kg_sort_scatter(int count, int chunk_size, int shift, int bits, __global const uint* keys,
                              __global const uint* items, __global uint* offsets, __global uint* keys_out,
                              __global uint* items_out)
{
    int g = (int)get_global_id(0);
    if (g < kg_parts(count, chunk_size)) {
        kg_sort_scatter_chunk(keys, items, count, chunk_size, g, kg_parts(count, chunk_size), shift, bits,
                              offsets, keys_out, items_out);
    }
}
