/* Prefix sums and stable sorts on the device: see cl_sort.h. */
#ifdef KG_HAVE_OPENCL
#include "backend/opencl/cl_sort.h"
#include "backend/opencl/kernels/kg_collide_shared.h"
#include "core/counting_sort.h"
#include "core/prefix_sum.h"

/* Parts of count elements: at least min_size elements each, at most max_parts of them. */
static int kg_part_size(int count, int max_parts, int min_size)
{
    int size = kg_parts(count, max_parts);
    return size > min_size ? size : min_size;
}

kg_result kg_cl_scan(kg_cl_backend* b, cl_mem values, cl_mem offsets, int count, int total_slot, const char* label)
{
    kg_cl_collide_buffers* c = &b->collide;
    int block = kg_part_size(count, KG_SCAN_MAX_BLOCKS, KG_SCAN_MIN_BLOCK);
    int blocks = kg_scan_block_count(count, block);
    KG_LAUNCH(b, SCAN_BLOCKS, blocks, label, KG_INT(count), KG_INT(block), KG_MEM(values), KG_MEM(c->block_sums));
    KG_LAUNCH(b, SCAN_APPLY, blocks, label, KG_INT(count), KG_INT(block), KG_MEM(values), KG_MEM(offsets),
              KG_MEM(c->block_sums), KG_MEM(c->counts), KG_INT(total_slot));
    return KG_OK;
}

kg_result kg_cl_sort_pass(kg_cl_backend* b, cl_mem keys_in, cl_mem items_in, cl_mem keys_out, cl_mem items_out,
                          int count, int shift, int bits, const char* label)
{
    cl_mem table = b->collide.sort_counts;
    int chunk_size = kg_part_size(count, KG_SORT_MAX_CHUNKS, KG_SORT_MIN_CHUNK);
    int chunks = kg_parts(count, chunk_size);
    KG_LAUNCH(b, SORT_COUNT, chunks, label, KG_INT(count), KG_INT(chunk_size), KG_INT(shift), KG_INT(bits),
              KG_MEM(keys_in), KG_MEM(table));
    KG_TRY(kg_cl_scan(b, table, table, chunks << bits, -1, label));
    KG_LAUNCH(b, SORT_SCATTER, chunks, label, KG_INT(count), KG_INT(chunk_size), KG_INT(shift), KG_INT(bits),
              KG_MEM(keys_in), KG_MEM(items_in), KG_MEM(table), KG_MEM(keys_out), KG_MEM(items_out));
    return KG_OK;
}

kg_result kg_cl_sort(kg_cl_backend* b, cl_mem keys, cl_mem items, cl_mem key_scratch, cl_mem item_scratch, int count,
                     int key_bits, const char* label)
{
    cl_mem from[2] = {keys, items}, to[2] = {key_scratch, item_scratch};
    for (int shift = 0; shift < key_bits; shift += KG_SORT_DEVICE_BITS) {
        int bits = key_bits - shift < KG_SORT_DEVICE_BITS ? key_bits - shift : KG_SORT_DEVICE_BITS;
        KG_TRY(kg_cl_sort_pass(b, from[0], from[1], to[0], to[1], count, shift, bits, label));
        for (int k = 0; k < 2; ++k) {
            cl_mem t = from[k];
            from[k] = to[k];
            to[k] = t;
        }
    }
    if (from[0] != keys) { /* an odd number of passes */
        KG_TRY(kg_cl_copy(b, from[0], keys, (size_t)count * sizeof(cl_uint)));
        KG_TRY(kg_cl_copy(b, from[1], items, (size_t)count * sizeof(cl_uint)));
    }
    return KG_OK;
}
#endif
