/* Prefix sums and stable sorts on the device (kernels in kernels/kg_scan.cl, per-element
 * code in core/prefix_sum.h and core/counting_sort.h), for any stage that turns counts
 * into places or orders its elements by a key: the broadphase sorts its boxes by cell,
 * the colouring sorts contacts by colour. Every call only enqueues kernels. */
#ifndef KG_CL_SORT_H
#define KG_CL_SORT_H

#include "backend/opencl/cl_world.h"

/* A device sort pass orders by digits of this many bits at most (256 buckets): with
 * 32-bit keys, four passes, which leave the result where it started. */
#define KG_SORT_DEVICE_BITS 8
/* A pass cuts its keys into at most this many chunks, of at least KG_SORT_MIN_CHUNK
 * keys: the digit table (b->collide.sort_counts) holds 256 x 256 words, plus the total. */
#define KG_SORT_MAX_CHUNKS 256
#define KG_SORT_MIN_CHUNK 256
#define KG_SORT_COUNT_WORDS ((1 << KG_SORT_DEVICE_BITS) * KG_SORT_MAX_CHUNKS + 1)

/* Exclusive prefix sum of values[0, count) into offsets[0, count] (may be values), the
 * total also into b->collide.counts[total_slot] unless total_slot < 0. */
kg_result kg_cl_scan(kg_cl_backend* b, cl_mem values, cl_mem offsets, int count, int total_slot, const char* label);

/* One stable counting-sort pass: (keys_in, items_in)[0, count) ordered by the digit
 * (key >> shift) & ((1 << bits) - 1), bits <= KG_SORT_DEVICE_BITS, into
 * (keys_out, items_out). */
kg_result kg_cl_sort_pass(kg_cl_backend* b, cl_mem keys_in, cl_mem items_in, cl_mem keys_out, cl_mem items_out,
                          int count, int shift, int bits, const char* label);

/* Sorts (keys, items)[0, count) stably by the low key_bits bits of the keys (1 to 32),
 * in passes of KG_SORT_DEVICE_BITS bits through the scratch buffers (count words each);
 * the result ends in keys and items. */
kg_result kg_cl_sort(kg_cl_backend* b, cl_mem keys, cl_mem items, cl_mem key_scratch, cl_mem item_scratch, int count,
                     int key_bits, const char* label);

#endif
