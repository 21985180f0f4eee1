/* The constraint graph colouring (solve/coloring.h) on random contact graphs: a valid
 * colouring (no two constraints of a colour share a moving body), kept colours kept, the
 * greedy rule in priority order checked against a brute-force reference, and the device's
 * rounds (replayed here with the same functions, one contact after another) giving the
 * serial colours bit for bit in few rounds. */
#include "kg_test.h"
#include "solve/coloring.h"

#include "core/body_flags.h"

#include <stdint.h>

#define MAX_BODIES 4096
#define MAX_CONTACTS 20000

typedef struct graph {
    int body_count, contact_count;
    kg_u32 flags[MAX_BODIES];
    kg_contact contacts[MAX_CONTACTS];
} graph;

static graph g_graph, g_twin;
static kg_u32 g_used[MAX_BODIES];
static int g_colors[MAX_CONTACTS], g_round_colors[MAX_CONTACTS], g_kept[MAX_CONTACTS];
static int g_order[MAX_CONTACTS], g_rank[MAX_CONTACTS];
static int g_color_start[KG_COLOR_COUNT + 2];
static kg_u32 g_bids[2][MAX_BODIES];

static uint32_t g_seed = 12345u;
static uint32_t next_random(void)
{
    g_seed = g_seed * 1664525u + 1013904223u;
    return g_seed >> 8;
}

/* body_count bodies, one in static_every static (0: none), contacts between random
 * bodies near each other in slot order (a pile's contacts are local), sorted by (a, b)
 * as collide lists them, each pair once. */
static void make_graph(graph* g, int body_count, int contact_count, int static_every, int reach)
{
    memset(g, 0, sizeof *g);
    g->body_count = body_count;
    for (int i = 0; i < body_count; ++i) {
        int is_static = static_every && i % static_every == 0;
        g->flags[i] = is_static ? KG_FLAG_ALIVE : KG_FLAG_ALIVE | ((kg_u32)KG_BODY_DYNAMIC << KG_TYPE_SHIFT);
    }
    int n = 0;
    for (kg_u32 a = 0; a < (kg_u32)body_count && n < contact_count; ++a) {
        int per_body = (int)(next_random() % 5u);
        for (int j = 0; j < per_body && n < contact_count; ++j) {
            kg_u32 b = a + 1u + next_random() % (kg_u32)reach;
            int duplicate = 0;
            for (int k = n - 1; k >= 0 && g->contacts[k].a == a; --k) {
                duplicate |= g->contacts[k].b == b;
            }
            if (b < (kg_u32)body_count && !duplicate) {
                g->contacts[n].a = a;
                g->contacts[n].b = b;
                g->contacts[n].color = KG_NO_COLOR;
                n += 1;
            }
        }
    }
    /* sort each body's run by b: insertion sort, the runs are short */
    for (int k = 1; k < n; ++k) {
        kg_contact c = g->contacts[k];
        int j = k - 1;
        while (j >= 0 && g->contacts[j].a == c.a && g->contacts[j].b > c.b) {
            g->contacts[j + 1] = g->contacts[j];
            j -= 1;
        }
        g->contacts[j + 1] = c;
    }
    g->contact_count = n;
}

/* A wall of width x rows boxes on a static ground (slot 0): each box touches the one on
 * its right and the one above, the bottom row the ground; sorted by (a, b). */
static void make_wall(graph* g, int width, int rows)
{
    memset(g, 0, sizeof *g);
    g->body_count = 1 + width * rows;
    g->flags[0] = KG_FLAG_ALIVE;
    for (int i = 1; i < g->body_count; ++i) {
        g->flags[i] = KG_FLAG_ALIVE | ((kg_u32)KG_BODY_DYNAMIC << KG_TYPE_SHIFT);
    }
    int n = 0;
    for (int i = 1; i <= width; ++i) {
        g->contacts[n].a = 0u;
        g->contacts[n++].b = (kg_u32)i;
    }
    for (int i = 1; i < g->body_count; ++i) {
        int column = (i - 1) % width;
        if (column + 1 < width) {
            g->contacts[n].a = (kg_u32)i;
            g->contacts[n++].b = (kg_u32)(i + 1);
        }
        if (i + width < g->body_count) {
            g->contacts[n].a = (kg_u32)i;
            g->contacts[n++].b = (kg_u32)(i + width);
        }
    }
    g->contact_count = n;
    for (int k = 0; k < n; ++k) {
        g->contacts[k].color = KG_NO_COLOR;
    }
}

static int moves(const graph* g, kg_u32 slot) { return kg_slot_takes_impulses(g->flags, slot); }

/* The brute-force reference: the contacts that kept no colour (kept[k] == KG_UNCOLORED)
 * in priority order, each the lowest colour that no kept contact and no earlier contact
 * on one of its moving bodies took. */
static int reference_color(const graph* g, int k, const int* colors, const int* kept)
{
    int bits = (int)kg_bits_for((kg_u32)g->contact_count);
    kg_u32 taken = 0u, mine = kg_color_priority((kg_u32)k, bits);
    for (int j = 0; j < g->contact_count; ++j) {
        int before = kept[j] != KG_UNCOLORED || kg_color_priority((kg_u32)j, bits) < mine;
        if (!before || colors[j] >= KG_COLOR_COUNT) {
            continue;
        }
        kg_u32 a = g->contacts[j].a, b = g->contacts[j].b;
        kg_u32 ka = g->contacts[k].a, kb = g->contacts[k].b;
        int shares = (moves(g, a) && (a == ka || a == kb)) || (moves(g, b) && (b == ka || b == kb));
        taken |= shares ? 1u << colors[j] : 0u;
    }
    kg_u32 free = ~taken & KG_ALL_COLORS;
    return free ? kg_lowest_bit(free) : KG_COLOR_COUNT;
}

/* The device's rounds, one contact after another; returns the number of rounds. */
static int color_in_rounds(graph* g, int* colors)
{
    int count = g->contact_count, bits = (int)kg_bits_for((kg_u32)count), round = 0;
    for (kg_u32 k = 0; k < (kg_u32)count; ++k) {
        kg_color_reset(k, g->contacts, g->flags, colors, g_used, g_bids[0]);
    }
    for (kg_u32 k = 0; k < (kg_u32)count; ++k) {
        kg_mark_kept_color(k, colors[k], g->contacts, g->flags, g_used);
    }
    for (int waiting = 1; waiting; ++round) {
        waiting = 0;
        for (kg_u32 k = 0; k < (kg_u32)count; ++k) {
            kg_color_bid(k, bits, g->contacts, g->flags, colors, g_bids[round & 1]);
        }
        for (kg_u32 k = 0; k < (kg_u32)count; ++k) {
            waiting += kg_color_take(k, bits, g->contacts, g->flags, colors, g_bids[round & 1],
                                     g_bids[(round + 1) & 1], g_used);
        }
    }
    return round;
}

/* Colours g serially and a copy of it in rounds: the same colours and colour words.
 * Returns the rounds. */
static int color_both_ways(graph* g)
{
    memcpy(&g_twin, g, sizeof *g);
    for (int k = 0; k < g->contact_count; ++k) {
        g_kept[k] = kg_kept_color(g->contacts[k].color, kg_color_ends_of((kg_u32)k, g->contacts, g->flags));
    }
    memset(g_used, 0, sizeof g_used);
    kg_color_constraints(g->contact_count, g->contacts, g->flags, g_used, g_colors, g_order, g_rank, g_color_start);
    int rounds = color_in_rounds(&g_twin, g_round_colors);
    int differ = 0;
    for (int k = 0; k < g->contact_count; ++k) {
        differ += g_colors[k] != g_round_colors[k] || g->contacts[k].color != g_twin.contacts[k].color;
    }
    KG_CHECK(differ == 0);
    return rounds;
}

/* Checks the lists and that no colour holds two contacts on one moving body; returns how
 * many contacts went to the overflow. */
static int check_valid(const graph* g)
{
    int count = g->contact_count, overflow = 0;
    for (int k = 0; k < count; ++k) {
        overflow += g_colors[k] == KG_COLOR_COUNT;
        KG_CHECK(g_order[g_rank[k]] == k);
        KG_CHECK(g_rank[k] >= g_color_start[g_colors[k]] && g_rank[k] < g_color_start[g_colors[k] + 1]);
    }
    KG_CHECK(g_color_start[KG_COLOR_COUNT + 1] == count);
    /* no colour holds two contacts on one moving body */
    static int last_seen[MAX_BODIES];
    for (int c = 0; c < KG_COLOR_COUNT; ++c) {
        for (int i = 0; i < g->body_count; ++i) {
            last_seen[i] = -1;
        }
        for (int at = g_color_start[c]; at < g_color_start[c + 1]; ++at) {
            const kg_contact* ct = &g->contacts[g_order[at]];
            kg_u32 ends[2] = {ct->a, ct->b};
            for (int e = 0; e < 2; ++e) {
                if (moves(g, ends[e])) {
                    KG_CHECK(last_seen[ends[e]] != c);
                    last_seen[ends[e]] = c;
                }
            }
        }
        for (int at = g_color_start[c] + 1; at < g_color_start[c + 1]; ++at) {
            KG_CHECK(g_order[at - 1] < g_order[at]); /* contact order within a colour */
        }
    }
    return overflow;
}

static void test_priority_is_a_bijection(void)
{
    for (int bits = 0; bits <= 16; ++bits) {
        kg_u32 size = 1u << bits;
        static unsigned char hit[1 << 16];
        memset(hit, 0, size);
        for (kg_u32 k = 0; k < size; ++k) {
            kg_u32 p = kg_color_priority(k, bits);
            KG_CHECK(p < size && !hit[p]);
            hit[p < size ? p : 0] = 1;
            KG_CHECK(kg_color_constraint_at(p, bits) == k);
        }
    }
}

static void test_serial_coloring_matches_the_reference(void)
{
    for (int trial = 0; trial < 6; ++trial) {
        graph* g = &g_graph;
        make_graph(g, 300 + trial * 150, MAX_CONTACTS, trial % 3 == 0 ? 0 : 7, 3 + trial * 4);
        color_both_ways(g);
        KG_CHECK(check_valid(g) == 0);
        int mismatches = 0;
        for (int k = 0; k < g->contact_count; ++k) {
            mismatches += g_colors[k] != reference_color(g, k, g_colors, g_kept);
        }
        KG_CHECK(mismatches == 0);
    }
}

static void test_rounds_give_the_serial_colors(void)
{
    int most_rounds = 0, most_colors = 0;
    for (int trial = 0; trial < 10; ++trial) {
        graph* g = &g_graph;
        if (trial < 8) {
            make_graph(g, MAX_BODIES, MAX_CONTACTS, trial % 2 ? 9 : 0, 1 + trial * 3);
        } else {
            make_wall(g, trial == 8 ? 64 : 4, trial == 8 ? 63 : 1000);
        }
        int rounds = color_both_ways(g);
        most_rounds = rounds > most_rounds ? rounds : most_rounds;
        int colors = kg_colors_in_use(g_color_start);
        most_colors = colors > most_colors ? colors : most_colors;
    }
    /* in contact order a chain of contacts (reach 1: each body touches the next, or a
     * wall's rows and columns) would need thousands of rounds */
    measured("colouring rounds: at most %d for up to %d contacts, %d colours\n", most_rounds, MAX_CONTACTS,
             most_colors);
    KG_CHECK(most_rounds <= 40);
}

/* The next step of g: one contact in `every` ends, as many begin (colour words
 * KG_NO_COLOR), one body in 5 every turns static or dynamic and one falls asleep or wakes;
 * the rest carry their words. */
static void next_step(graph* g, kg_u32 every)
{
    graph* next = &g_twin;
    int n = 0;
    for (int k = 0; k < g->contact_count && n + 1 < MAX_CONTACTS; ++k) {
        kg_contact c = g->contacts[k];
        if (next_random() % every != 0u) {
            next->contacts[n++] = c;
        }
        if (next_random() % every == 0u && c.b != KG_NULL_INDEX && c.b + 1u < (kg_u32)g->body_count) {
            next->contacts[n] = c; /* a new partner */
            next->contacts[n].b = c.b + 1u;
            next->contacts[n++].color = KG_NO_COLOR;
        }
    }
    memcpy(g->contacts, next->contacts, (size_t)n * sizeof *g->contacts);
    g->contact_count = n;
    for (int i = 0; i < g->body_count; ++i) {
        g->flags[i] ^= next_random() % (5u * every) == 0u ? (kg_u32)KG_BODY_DYNAMIC << KG_TYPE_SHIFT : 0u;
        g->flags[i] ^= next_random() % (5u * every) == 0u ? KG_FLAG_ASLEEP : 0u;
    }
}

/* g's body 0 made a hub of 40 contacts (more than the colours: some overflow), and one
 * body in 7 given a tile contact (no second body), in (a, b) order. */
static void add_hub_and_tiles(graph* g)
{
    graph* next = &g_twin;
    int n = 0;
    for (kg_u32 j = 1u; j <= 40u; ++j) {
        next->contacts[n].a = 0u;
        next->contacts[n].b = j;
        next->contacts[n++].color = KG_NO_COLOR;
    }
    for (int k = 0; k < g->contact_count && n + 1 < MAX_CONTACTS; ++k) {
        kg_contact c = g->contacts[k];
        int run_ends = k + 1 == g->contact_count || g->contacts[k + 1].a != c.a;
        if (c.a != 0u) {
            next->contacts[n++] = c;
        }
        if (run_ends && c.a % 7u == 3u) {
            next->contacts[n] = c;
            next->contacts[n].b = KG_NULL_INDEX;
            next->contacts[n++].color = KG_NO_COLOR;
        }
    }
    memcpy(g->contacts, next->contacts, (size_t)n * sizeof *g->contacts);
    g->contact_count = n;
}

static void test_kept_colors(void)
{
    graph* g = &g_graph;
    make_graph(g, 2000, 6000, 0, 12);
    add_hub_and_tiles(g);
    color_both_ways(g);
    int kept = 0, new_contacts = 0, mismatches = 0, overflow = 0;
    /* many new contacts (coloured by going through every priority), then few (sorted) */
    for (int step = 0; step < 6; ++step) {
        next_step(g, step < 3 ? 10u : 200u);
        color_both_ways(g);
        overflow += check_valid(g);
        for (int k = 0; k < g->contact_count; ++k) {
            kept += g_kept[k] != KG_UNCOLORED;
            new_contacts += g_kept[k] == KG_UNCOLORED;
            KG_CHECK(g_kept[k] == KG_UNCOLORED || g_colors[k] == g_kept[k]);
            mismatches += g_kept[k] == KG_UNCOLORED && g_colors[k] != reference_color(g, k, g_colors, g_kept);
        }
    }
    measured("kept colours: %d kept, %d coloured again over 6 steps, %d in the overflow\n", kept, new_contacts,
             overflow);
    KG_CHECK(kept > 4 * new_contacts && new_contacts > 0);
    KG_CHECK(overflow > 0); /* the hub's */
    KG_CHECK(mismatches == 0);
}

KG_TEST_MAIN(KG_TEST(test_priority_is_a_bijection), KG_TEST(test_serial_coloring_matches_the_reference),
             KG_TEST(test_rounds_give_the_serial_colors), KG_TEST(test_kept_colors))
