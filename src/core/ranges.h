/* Index arithmetic shared by the step's parallel building blocks (prefix sums, sorts, the
 * broadphase grid, the colouring), in C and OpenCL C: a range cut in parts, the bits that
 * number a count of things, the first place of a key in sorted keys. */
#ifndef KG_RANGES_H
#define KG_RANGES_H

#include "core/kg_shared.h"

/* How many parts of size elements [0, count) makes (the last one may be shorter). */
KG_FN int kg_parts(int count, int size) { return (count + size - 1) / size; }

/* The end of part g of [0, count). */
KG_FN int kg_part_end(int count, int size, int g) { return (g + 1) * size < count ? (g + 1) * size : count; }

/* The bits that number count things: 2^bits >= count (0 for one thing or none). */
KG_FN kg_u32 kg_bits_for(kg_u32 count)
{
    kg_u32 bits = 0u;
    while (count > 1u && bits < 32u && (count - 1u) >> bits != 0u) {
        bits += 1u;
    }
    return bits;
}

/* The first place in keys[lo, hi) (sorted) whose key is not below key, or hi. */
KG_FN int kg_lower_bound(KG_GLOBAL const kg_u32* keys, int lo, int hi, kg_u32 key)
{
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (keys[mid] < key) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    return lo;
}

#endif
