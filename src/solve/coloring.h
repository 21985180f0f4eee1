/* Constraint graph colouring, shared by the CPU backend (solve/graph_color.c) and the
 * kernels (kg_color.cl): constraints of one colour share no moving body, so a colour
 * can be solved in any order or all at once (threads, SIMD lanes, work-items) with the
 * same result; colours are solved one after another. Greedy in constraint order, so the
 * colouring is deterministic; constraints that fit no colour go to an overflow list,
 * solved serially, in order, after the colours. Serial by nature: on the device it runs
 * as one work-item. */
#ifndef KG_COLORING_H
#define KG_COLORING_H

#include "core/body_flags.h"
#include "core/kg_layout.h"

#define KG_COLOR_COUNT 24
#define KG_ALL_COLORS ((1u << KG_COLOR_COUNT) - 1u)

/* A body takes part in colouring only if the solver writes to it. */
KG_FN int kg_slot_takes_impulses(KG_GLOBAL const kg_u32* flags, kg_u32 slot)
{
    return slot != KG_NULL_INDEX && kg_flags_simulated(flags[slot]);
}

/* The lowest colour neither moving body of a constraint has taken yet (used: per body
 * slot, a bit per colour), now taken by both, or KG_COLOR_COUNT (the overflow). */
KG_FN int kg_pick_color(KG_GLOBAL kg_u32* used, kg_u32 a, kg_u32 b, int a_moves, int b_moves)
{
    kg_u32 taken = (a_moves ? used[a] : 0u) | (b_moves ? used[b] : 0u);
    kg_u32 free = ~taken & KG_ALL_COLORS;
    if (free == 0u) {
        return KG_COLOR_COUNT;
    }
    int c = kg_lowest_bit(free);
    if (a_moves) {
        used[a] |= 1u << c;
    }
    if (b_moves) {
        used[b] |= 1u << c;
    }
    return c;
}

/* Colours the constraints of contacts [0, count): colors[k] is contact k's colour (or
 * KG_COLOR_COUNT), order lists the contact indices grouped by colour, overflow last, in
 * contact order within each, rank (unless NULL) each contact's place in order, and
 * colour c is order[color_start[c], color_start[c + 1]) (color_start holds
 * KG_COLOR_COUNT + 2 ints). used (per body slot) is all zeros before and after. */
KG_FN void kg_color_constraints(int count, KG_GLOBAL const kg_contact* contacts, KG_GLOBAL const kg_u32* flags,
                                KG_GLOBAL kg_u32* used, KG_GLOBAL int* colors, KG_GLOBAL int* order,
                                KG_GLOBAL int* rank, KG_GLOBAL int* color_start)
{
    int next[KG_COLOR_COUNT + 1];
    for (int c = 0; c <= KG_COLOR_COUNT; ++c) {
        next[c] = 0;
    }
    for (int k = 0; k < count; ++k) {
        kg_u32 a = contacts[k].a, b = contacts[k].b;
        int c = kg_pick_color(used, a, b, kg_slot_takes_impulses(flags, a), kg_slot_takes_impulses(flags, b));
        colors[k] = c;
        next[c] += 1;
    }
    int start = 0;
    for (int c = 0; c <= KG_COLOR_COUNT; ++c) {
        int size = next[c];
        color_start[c] = start;
        next[c] = start;
        start += size;
    }
    color_start[KG_COLOR_COUNT + 1] = count;
    for (int k = 0; k < count; ++k) {
        int at = next[colors[k]]++;
        order[at] = k;
        if (rank) {
            rank[k] = at;
        }
        /* cleared by the constraints, so the cost follows them, not the bodies */
        kg_u32 a = contacts[k].a, b = contacts[k].b;
        if (a != KG_NULL_INDEX) {
            used[a] = 0u;
        }
        if (b != KG_NULL_INDEX) {
            used[b] = 0u;
        }
    }
}

/* How many colours are in use (the overflow not counted): one past the last non-empty. */
KG_FN int kg_colors_in_use(const int* color_start)
{
    int count = 0;
    for (int c = 0; c < KG_COLOR_COUNT; ++c) {
        count = color_start[c + 1] > color_start[c] ? c + 1 : count;
    }
    return count;
}

#endif
