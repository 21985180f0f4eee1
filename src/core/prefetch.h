/* Software prefetches for the CPU's loops that stream through more than the cache holds:
 * the narrowphase and prepare through the contacts (216 bytes, five cache lines at most,
 * in no fixed alignment), the solver's passes through the constraint rows, the colouring
 * through the contacts it colours again. The hardware prefetcher follows one plain stream
 * well, but these loops also read the bodies and jump between the fields of what they
 * stream, and their first touch of each line stalled. In an OpenCL kernel (shared code
 * includes this) kg_prefetch is nothing. */
#ifndef KG_PREFETCH_H
#define KG_PREFETCH_H

#if defined(__OPENCL_VERSION__) || defined(__OPENCL_C_VERSION__)
#define kg_prefetch(address) ((void)0)
#else
#include <stddef.h>

/* The cache line of address, asked for to be read. */
#define kg_prefetch(address) __builtin_prefetch(address)

/* How many contacts ahead of the one it works on the narrowphase (and prepare) asks for. */
#define KG_CONTACTS_AHEAD 8

/* Every cache line of the bytes [at, at + size), asked for to be read (write 0) or to be
 * written (write 1). */
static inline void kg_prefetch_bytes(const void* at, size_t size, int write)
{
    const char* p = (const char*)at;
    for (size_t offset = 0; offset < size; offset += 64) {
        if (write) {
            __builtin_prefetch(p + offset, 1);
        } else {
            __builtin_prefetch(p + offset, 0);
        }
    }
    if (write) {
        __builtin_prefetch(p + size - 1, 1);
    } else {
        __builtin_prefetch(p + size - 1, 0);
    }
}
#endif

#endif
