/* One pass of a stable LSD counting sort, split in chunks (shared by the CPU backend and
 * the OpenCL kernels): the keys (and the items they carry) are cut into chunks of
 * chunk_size; each chunk counts its digits into counts[digit * chunks + chunk]; an
 * exclusive prefix sum over that table, digit-major, gives each (digit, chunk) its first
 * place; each chunk then scatters its keys in order. Equal digits keep their order within
 * a chunk, and the chunks' places follow the chunk order: the pass is stable and its
 * result depends only on the keys, whatever runs the chunks. The CPU sorts with one chunk
 * (the whole array); the device with one work-item per chunk (backend/opencl/cl_sort.h). */
#ifndef KG_COUNTING_SORT_H
#define KG_COUNTING_SORT_H

#include "core/ranges.h"

KG_FN kg_u32 kg_sort_digit(kg_u32 key, int shift, int bits) { return (key >> shift) & ((1u << bits) - 1u); }

/* Counts the digits of chunk's keys into counts[digit * chunks + chunk], 1 << bits of them.
 * chunks is kg_parts(count, chunk_size), passed so that a caller of one chunk gets
 * loops of constant stride. */
KG_FN void kg_sort_count_chunk(KG_GLOBAL const kg_u32* keys, int count, int chunk_size, int chunk, int chunks,
                               int shift, int bits, KG_GLOBAL kg_u32* counts)
{
    int end = kg_part_end(count, chunk_size, chunk);
    for (int d = 0; d < 1 << bits; ++d) {
        counts[d * chunks + chunk] = 0u;
    }
    for (int k = chunk * chunk_size; k < end; ++k) {
        counts[(int)kg_sort_digit(keys[k], shift, bits) * chunks + chunk] += 1u;
    }
}

/* Moves chunk's keys and items to their places: offsets is the exclusive prefix sum of
 * the counts above, and each (digit, chunk) entry is advanced as it is used. */
KG_FN void kg_sort_scatter_chunk(KG_GLOBAL const kg_u32* keys, KG_GLOBAL const kg_u32* items, int count,
                                 int chunk_size, int chunk, int chunks, int shift, int bits,
                                 KG_GLOBAL kg_u32* offsets, KG_GLOBAL kg_u32* keys_out, KG_GLOBAL kg_u32* items_out)
{
    int end = kg_part_end(count, chunk_size, chunk);
    for (int k = chunk * chunk_size; k < end; ++k) {
        kg_u32 place = offsets[(int)kg_sort_digit(keys[k], shift, bits) * chunks + chunk]++;
        keys_out[place] = keys[k];
        items_out[place] = items[k];
    }
}

#endif
