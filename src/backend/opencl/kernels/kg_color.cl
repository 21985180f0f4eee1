/* The constraint graph colouring's kernels (solve/coloring.h). */
#include "core/kg_layout.h"
#include "solve/coloring.h"
#include "kg_collide_shared.h"

/* Few contacts: coloured serially (solve/coloring.h). One work-item, up to the backend's
 * color_serial_max contacts. */
__kernel void kg_color_contacts(int count, __global kg_contact* contacts,
                                __global const kg_u32* flags, __global uint* used, __global int* colors,
                                __global int* order, __global int* color_start)
{
    if (get_global_id(0) == 0) {
        kg_color_constraints(count, contacts, flags, used, colors, order, 0, color_start);
    }
}

/* Before either: the kept colours, the bodies' used colours and bids cleared. */
__kernel void kg_reset_colors(int count, __global const kg_contact* contacts, __global const kg_u32* flags,
                              __global int* colors, __global uint* used, __global uint* bids, __global uint* items,
                              __global uint* counts)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_color_reset((kg_u32)k, contacts, flags, colors, used, bids);
        items[k] = (uint)k;
    }
    if (k == 0) {
        counts[KG_CC_WAITING] = counts[KG_CC_WAITING + 1] = 0u;
    }
}

/* Many contacts: coloured in rounds (solve/coloring.h), then ordered by colour. */
__kernel void kg_keep_colors(int count, __global const kg_contact* contacts, __global const kg_u32* flags,
                             __global const int* colors, __global uint* used)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_mark_kept_color((kg_u32)k, colors[k], contacts, flags, used);
    }
}

__kernel void kg_bid_colors(int count, int bits, __global const kg_contact* contacts, __global const kg_u32* flags,
                            __global const int* colors, __global uint* bids)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        kg_color_bid((kg_u32)k, bits, contacts, flags, colors, bids);
    }
}

/* Counts the contacts left waiting in counts[KG_CC_WAITING + round % 2], the other word
 * cleared for the next round. */
__kernel void kg_take_colors(int count, int bits, int round, __global kg_contact* contacts,
                             __global const kg_u32* flags, __global int* colors, __global const uint* bids,
                             __global uint* next_bids, __global uint* used, __global uint* counts)
{
    int k = (int)get_global_id(0);
    if (k == 0) {
        counts[KG_CC_WAITING + ((round + 1) & 1)] = 0u;
    }
    if (k < count && kg_color_take((kg_u32)k, bits, contacts, flags, colors, bids, next_bids, used)) {
        atomic_inc(&counts[KG_CC_WAITING + (round & 1)]);
    }
}

/* Colour c's first place in the contacts sorted by colour (c up to KG_COLOR_COUNT + 1, one
 * past the overflow). */
__kernel void kg_color_ranges(int count, __global const uint* sorted_colors, __global int* color_start)
{
    int c = (int)get_global_id(0);
    if (c < KG_COLOR_COUNT + 2) {
        color_start[c] = kg_lower_bound(sorted_colors, 0, count, (kg_u32)c);
    }
}
