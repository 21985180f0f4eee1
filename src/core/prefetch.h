/* Software prefetches for the CPU's loops that stream through contacts (216 bytes, so
 * one spans four cache lines at most, in no fixed alignment). The hardware prefetcher
 * follows one stream well, but the loops that read or write the contacts also read the
 * bodies and write the constraint rows, and their first touch of each contact stalled
 * (many_pyramids, perf: a fifth of prepare's time on one load of the contact). */
#ifndef KG_PREFETCH_H
#define KG_PREFETCH_H

#include <stddef.h>

/* How many contacts ahead of the one a loop works on it asks for. */
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
