/* The constraint graph colouring's kernels (solve/coloring.h). */
#include "core/kg_layout.h"
#include "solve/coloring.h"
#include "kg_collide_shared.h"

/* Colours this step's contacts (solve/coloring.h), also copying color_start into the
 * counters for the host. One work-item: greedy colouring is serial. */
__kernel void kg_color_contacts(__global uint* counts, __global const kg_contact* contacts,
                                __global const kg_u32* flags, __global uint* used, __global int* colors,
                                __global int* order, __global int* color_start)
{
    if (get_global_id(0) != 0) {
        return;
    }
    kg_color_constraints((int)counts[KG_CC_CONTACTS], contacts, flags, used, colors, order, 0, color_start);
    for (int c = 0; c < KG_COLOR_COUNT + 2; ++c) {
        counts[KG_CC_COLOR_START + c] = (uint)color_start[c];
    }
}
