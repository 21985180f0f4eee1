/* Constraint graph colouring, shared by the CPU backend (solve/graph_color.c) and the
 * kernels (kg_color.cl): constraints of one colour share no moving body, so a colour
 * can be solved in any order or all at once (threads, SIMD lanes, work-items) with the
 * same result; colours are solved one after another.
 *
 * A contact keeps the colour it took while it lives and its bodies move as they did then
 * (kg_kept_color: the colour is carried with its impulses from step to step). The others,
 * new ones first of all, are coloured greedily, in the order of a fixed scramble of the
 * constraint indices (kg_color_priority): each takes the lowest colour that no kept
 * constraint and no constraint before it in that order on one of its moving bodies took;
 * those that fit no colour go to an overflow list, solved serially, in constraint order,
 * after the colours. The result depends only on the contacts (bodies and carried colours)
 * and the bodies' motion.
 *
 * The CPU colours serially (kg_color_serially), walking the priorities or, when few
 * contacts wait, sorting them by priority.
 *
 * Why the scramble: a GPU colours large worlds in rounds (Jones-Plassmann): in each
 * round every constraint that comes first, in that order, among the uncoloured ones on each
 * of its moving bodies takes its colour (kg_color_bid, kg_color_take). It then sees exactly
 * the colours of the constraints before it, so the rounds give the serial greedy's colours
 * bit for bit, in as many rounds as the longest chain of constraints waiting for each
 * other. In constraint order (pairs sorted by body) a row of boxes is one such chain; in a
 * scrambled order chains stay a few constraints long. */
#ifndef KG_COLORING_H
#define KG_COLORING_H

#include "core/body_flags.h"
#include "core/kg_layout.h"
#include "core/prefetch.h"
#include "core/ranges.h"

#define KG_COLOR_COUNT 24
#define KG_ALL_COLORS ((1u << KG_COLOR_COUNT) - 1u)
#define KG_UNCOLORED (-1)

/* A body takes part in colouring only if the solver writes to it. */
KG_FN int kg_slot_takes_impulses(KG_GLOBAL const kg_u32* flags, kg_u32 slot)
{
    return slot != KG_NULL_INDEX && kg_flags_simulated(flags[slot]);
}

/* A constraint's two body slots, and whether each takes impulses. */
typedef struct kg_color_ends {
    kg_u32 a, b;
    int a_moves, b_moves;
} kg_color_ends;

KG_FN kg_color_ends kg_color_ends_of(kg_u32 k, KG_GLOBAL const kg_contact* contacts, KG_GLOBAL const kg_u32* flags)
{
    kg_color_ends e;
    e.a = contacts[k].a;
    e.b = contacts[k].b;
    e.a_moves = kg_slot_takes_impulses(flags, e.a);
    e.b_moves = kg_slot_takes_impulses(flags, e.b);
    return e;
}

/* Colour c marked as taken by the moving bodies of e (used: per body slot, a bit per
 * colour). */
KG_FN void kg_mark_color(KG_GLOBAL kg_u32* used, kg_color_ends e, int c)
{
    if (e.a_moves) {
        kg_atomic_or_u32(&used[e.a], 1u << c);
    }
    if (e.b_moves) {
        kg_atomic_or_u32(&used[e.b], 1u << c);
    }
}

/* The lowest colour neither moving body of e has taken yet, now taken by both, or
 * KG_COLOR_COUNT (the overflow). */
KG_FN int kg_pick_color(KG_GLOBAL kg_u32* used, kg_color_ends e)
{
    kg_u32 taken = (e.a_moves ? used[e.a] : 0u) | (e.b_moves ? used[e.b] : 0u);
    kg_u32 free = ~taken & KG_ALL_COLORS;
    if (free == 0u) {
        return KG_COLOR_COUNT;
    }
    int c = kg_lowest_bit(free);
    kg_mark_color(used, e, c);
    return c;
}

/* A constraint's priority: a bijection of [0, 2^bits) (kg_bits_for), two rounds of a
 * multiplication by an odd constant and a xor-shift by at least half the bits, each of
 * which is invertible modulo 2^bits. */
#define KG_PRIORITY_MUL1 0x9E3779B1u
#define KG_PRIORITY_MUL2 0x85EBCA77u
#define KG_PRIORITY_INV1 0x0E8B2F51u /* KG_PRIORITY_MUL1 * KG_PRIORITY_INV1 == 1 mod 2^32 */
#define KG_PRIORITY_INV2 0xB6C92F47u

/* x ^ (x >> s) with 2 s >= bits: its own inverse on [0, 2^bits). */
KG_FN kg_u32 kg_priority_shuffle(kg_u32 x, int bits) { return x ^ (x >> ((bits + 1) / 2)); }

KG_FN kg_u32 kg_color_priority(kg_u32 k, int bits)
{
    kg_u32 mask = (1u << bits) - 1u;
    k = kg_priority_shuffle((k * KG_PRIORITY_MUL1) & mask, bits);
    return kg_priority_shuffle((k * KG_PRIORITY_MUL2) & mask, bits);
}

/* The constraint of priority p: kg_color_priority's inverse. */
KG_FN kg_u32 kg_color_constraint_at(kg_u32 p, int bits)
{
    kg_u32 mask = (1u << bits) - 1u;
    p = (kg_priority_shuffle(p, bits) * KG_PRIORITY_INV2) & mask;
    return (kg_priority_shuffle(p, bits) * KG_PRIORITY_INV1) & mask;
}

/* A contact's colour word: its colour, and whether each body moved when it took it. */
KG_FN kg_u32 kg_color_word(int color, kg_color_ends e)
{
    return (kg_u32)color | (kg_u32)e.a_moves << 5 | (kg_u32)e.b_moves << 6;
}

/* The colour a contact of colour word `word` keeps, or KG_UNCOLORED: one of the colours
 * (the overflow is coloured again) taken while each of its bodies moved as it does now.
 * Kept colours stay a valid colouring: two contacts on a moving body that keep theirs
 * took them while it moved, each avoiding the other's. */
KG_FN int kg_kept_color(kg_u32 word, kg_color_ends e)
{
    int color = (int)(word & 31u);
    return color < KG_COLOR_COUNT && word == kg_color_word(color, e) ? color : KG_UNCOLORED;
}

/* Contact k's new colour, taken from used (kg_pick_color) and written to the contact. */
KG_FN int kg_color_contact(kg_u32 k, kg_color_ends e, KG_GLOBAL kg_contact* contacts, KG_GLOBAL kg_u32* used)
{
    int c = kg_pick_color(used, e);
    contacts[k].color = kg_color_word(c, e);
    return c;
}

/* Lists the contacts [0, count) by colour: order holds the contact indices grouped by
 * colour, overflow last, in contact order within each, rank (unless NULL) each contact's
 * place in order, and colour c is order[color_start[c], color_start[c + 1])
 * (color_start holds KG_COLOR_COUNT + 2 ints). */
KG_FN void kg_order_by_color(int count, KG_GLOBAL const int* colors, KG_GLOBAL int* order, KG_GLOBAL int* rank,
                             KG_GLOBAL int* color_start)
{
    int next[KG_COLOR_COUNT + 1];
    for (int c = 0; c <= KG_COLOR_COUNT; ++c) {
        next[c] = 0;
    }
    for (int k = 0; k < count; ++k) {
        next[colors[k]] += 1;
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
    }
}

/* The contacts are read in a scrambled order, from memory that would not be in the cache
 * yet: each is asked for this many contacts ahead (some 0.4 ms a step on large_pyramid
 * without). Priorities past the last map to some other contact, which only wastes a
 * request. */
#define KG_COLOR_LOOKAHEAD 16u
/* At most count / this many contacts to colour again are sorted by priority rather than
 * found by going through every priority (a sort costs some 40 log2(n) instructions a
 * contact, the walk some 50 per priority, up to 2 count priorities). */
#define KG_COLOR_FEW_WAITING 16

/* The contacts that kept no colour (colors[k] == KG_UNCOLORED), coloured in priority order. */
KG_FN void kg_color_in_priority_order(int count, KG_GLOBAL kg_contact* contacts, KG_GLOBAL const kg_u32* flags,
                                      KG_GLOBAL kg_u32* used, KG_GLOBAL int* colors)
{
    int bits = (int)kg_bits_for((kg_u32)count);
    kg_u32 ahead[KG_COLOR_LOOKAHEAD]; /* the contacts of priorities p to p + lookahead - 1 */
    for (kg_u32 p = 0u; p < KG_COLOR_LOOKAHEAD; ++p) {
        ahead[p] = kg_color_constraint_at(p, bits);
    }
    for (kg_u32 p = 0u; p < (1u << bits); ++p) {
        kg_u32 k = ahead[p % KG_COLOR_LOOKAHEAD], later = kg_color_constraint_at(p + KG_COLOR_LOOKAHEAD, bits);
        ahead[p % KG_COLOR_LOOKAHEAD] = later;
        if (later < (kg_u32)count && colors[later] == KG_UNCOLORED) {
            kg_prefetch(&contacts[later].a);
        }
        if (k < (kg_u32)count && colors[k] == KG_UNCOLORED) {
            colors[k] = kg_color_contact(k, kg_color_ends_of(k, contacts, flags), contacts, used);
        }
    }
}

/* Moves keys[root] down the max-heap keys[0, n). */
KG_FN void kg_sift_down(KG_GLOBAL int* keys, int root, int n)
{
    for (int child = 2 * root + 1; child < n; root = child, child = 2 * root + 1) {
        if (child + 1 < n && keys[child + 1] > keys[child]) {
            child += 1;
        }
        if (keys[root] > keys[child]) {
            return;
        }
        int t = keys[root];
        keys[root] = keys[child];
        keys[child] = t;
    }
}

/* The contacts list[0, n) coloured in priority order: the list turned into their
 * priorities (distinct, below 2^31), heap sorted, and each turned back into its contact. */
KG_FN void kg_color_listed(KG_GLOBAL int* list, int n, int bits, KG_GLOBAL kg_contact* contacts,
                           KG_GLOBAL const kg_u32* flags, KG_GLOBAL kg_u32* used, KG_GLOBAL int* colors)
{
    for (int i = 0; i < n; ++i) {
        list[i] = (int)kg_color_priority((kg_u32)list[i], bits);
    }
    for (int root = n / 2 - 1; root >= 0; --root) {
        kg_sift_down(list, root, n);
    }
    for (int end = n - 1; end > 0; --end) {
        int t = list[0];
        list[0] = list[end];
        list[end] = t;
        kg_sift_down(list, 0, end);
    }
    for (int i = 0; i < n; ++i) {
        kg_u32 k = kg_color_constraint_at((kg_u32)list[i], bits);
        colors[k] = kg_color_contact(k, kg_color_ends_of(k, contacts, flags), contacts, used);
    }
}

/* Colours the constraints of contacts [0, count), serially: colors[k] is contact k's
 * colour (or KG_COLOR_COUNT), also in its colour word. used (per body slot: the colours
 * its contacts took) must be zero for the contacts' bodies before; it is left as the
 * colouring made it (clearing it through the contacts would read them a third time). The
 * contacts that kept no colour are listed in waiting (count ints); when they are few (a
 * settled pile: tens of 10,000), sorting them costs less than going through every
 * priority. */
KG_FN void kg_color_serially(int count, KG_GLOBAL kg_contact* contacts, KG_GLOBAL const kg_u32* flags,
                             KG_GLOBAL kg_u32* used, KG_GLOBAL int* colors, KG_GLOBAL int* waiting_list)
{
    int waiting = 0;
    for (kg_u32 k = 0u; k < (kg_u32)count; ++k) {
        kg_color_ends e = kg_color_ends_of(k, contacts, flags);
        int c = kg_kept_color(contacts[k].color, e);
        colors[k] = c;
        if (c != KG_UNCOLORED) {
            kg_mark_color(used, e, c);
        }
        waiting_list[waiting] = (int)k;
        waiting += c == KG_UNCOLORED;
    }
    if (waiting > 0 && waiting <= count / KG_COLOR_FEW_WAITING) {
        kg_color_listed(waiting_list, waiting, (int)kg_bits_for((kg_u32)count), contacts, flags, used, colors);
    } else if (waiting > 0) {
        kg_color_in_priority_order(count, contacts, flags, used, colors);
    }
}

/* kg_color_serially, then the lists of kg_order_by_color (order is the waiting list
 * until then). */
KG_FN void kg_color_constraints(int count, KG_GLOBAL kg_contact* contacts, KG_GLOBAL const kg_u32* flags,
                                KG_GLOBAL kg_u32* used, KG_GLOBAL int* colors, KG_GLOBAL int* order,
                                KG_GLOBAL int* rank, KG_GLOBAL int* color_start)
{
    kg_color_serially(count, contacts, flags, used, colors, order);
    kg_order_by_color(count, colors, order, rank, color_start);
}

/* ---- the device's rounds (see the top) ---- */

#define KG_NO_BID 0xFFFFFFFFu

/* Before the rounds: contact k's kept colour (or KG_UNCOLORED), its bodies with no colour
 * taken (kg_mark_kept_color then marks the kept ones) and no bid. */
KG_FN void kg_color_reset(kg_u32 k, KG_GLOBAL const kg_contact* contacts, KG_GLOBAL const kg_u32* flags,
                          KG_GLOBAL int* colors, KG_GLOBAL kg_u32* used, KG_GLOBAL kg_u32* bids)
{
    kg_color_ends e = kg_color_ends_of(k, contacts, flags);
    colors[k] = kg_kept_color(contacts[k].color, e);
    if (e.a != KG_NULL_INDEX) {
        used[e.a] = 0u;
        bids[e.a] = KG_NO_BID;
    }
    if (e.b != KG_NULL_INDEX) {
        used[e.b] = 0u;
        bids[e.b] = KG_NO_BID;
    }
}

/* After the resets: a kept colour c marked as taken by contact k's moving bodies. */
KG_FN void kg_mark_kept_color(kg_u32 k, int c, KG_GLOBAL const kg_contact* contacts, KG_GLOBAL const kg_u32* flags,
                              KG_GLOBAL kg_u32* used)
{
    if (c != KG_UNCOLORED) {
        kg_mark_color(used, kg_color_ends_of(k, contacts, flags), c);
    }
}

/* An uncoloured contact's bid: its priority on each of its moving bodies, the least kept. */
KG_FN void kg_color_bid(kg_u32 k, int bits, KG_GLOBAL const kg_contact* contacts, KG_GLOBAL const kg_u32* flags,
                        KG_GLOBAL const int* colors, KG_GLOBAL kg_u32* bids)
{
    if (colors[k] != KG_UNCOLORED) {
        return;
    }
    kg_color_ends e = kg_color_ends_of(k, contacts, flags);
    kg_u32 p = kg_color_priority(k, bits);
    if (e.a_moves) {
        kg_atomic_min_u32(&bids[e.a], p);
    }
    if (e.b_moves) {
        kg_atomic_min_u32(&bids[e.b], p);
    }
}

/* After the bids: an uncoloured contact that won on each of its moving bodies takes its
 * colour (the only one to touch their used colours this round), and clears its bodies'
 * bids for the next round (next_bids). Returns 1 when it waits for another round. */
KG_FN int kg_color_take(kg_u32 k, int bits, KG_GLOBAL kg_contact* contacts, KG_GLOBAL const kg_u32* flags,
                        KG_GLOBAL int* colors, KG_GLOBAL const kg_u32* bids, KG_GLOBAL kg_u32* next_bids,
                        KG_GLOBAL kg_u32* used)
{
    if (colors[k] != KG_UNCOLORED) {
        return 0;
    }
    kg_color_ends e = kg_color_ends_of(k, contacts, flags);
    kg_u32 p = kg_color_priority(k, bits);
    int wins = (!e.a_moves || bids[e.a] == p) && (!e.b_moves || bids[e.b] == p);
    if (e.a_moves) {
        next_bids[e.a] = KG_NO_BID;
    }
    if (e.b_moves) {
        next_bids[e.b] = KG_NO_BID;
    }
    if (wins) {
        colors[k] = kg_color_contact(k, e, contacts, used);
    }
    return !wins;
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
