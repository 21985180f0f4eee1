#include "solve/graph_color.h"
#include "core/alloc.h"
#include "core/error.h"

#include <string.h>

kg_result kg_graph_coloring_init(kg_graph_coloring* g, int body_capacity, int constraint_capacity)
{
    memset(g, 0, sizeof *g);
    g->body_capacity = body_capacity;
    g->words_per_color = (body_capacity + 31) / 32;
    g->bits = kg_alloc_zeroed((size_t)KG_COLOR_COUNT * (size_t)g->words_per_color * sizeof *g->bits);
    g->order = kg_alloc_zeroed((size_t)constraint_capacity * sizeof *g->order);
    if (!g->bits || !g->order) {
        kg_graph_coloring_free(g);
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the constraint graph colouring");
    }
    return KG_OK;
}

void kg_graph_coloring_free(kg_graph_coloring* g)
{
    kg_free(g->bits);
    kg_free(g->order);
    g->bits = NULL;
    g->order = NULL;
}

/* A body takes part in colouring only if the solver writes to it. */
static int kg_takes_impulses(const kg_body_pool* bodies, kg_u32 slot)
{
    return slot != KG_NULL_INDEX && kg_pool_is_simulated(bodies, (int)slot);
}

static int kg_bit(const kg_u32* words, kg_u32 i) { return (words[i >> 5] >> (i & 31u)) & 1u; }
static void kg_set_bit(kg_u32* words, kg_u32 i) { words[i >> 5] |= 1u << (i & 31u); }
static void kg_clear_bit(kg_u32* words, kg_u32 i) { words[i >> 5] &= ~(1u << (i & 31u)); }

static int kg_pick_color(kg_graph_coloring* g, kg_u32 a, kg_u32 b, int a_moves, int b_moves)
{
    for (int c = 0; c < KG_COLOR_COUNT; ++c) {
        kg_u32* words = g->bits + (size_t)c * (size_t)g->words_per_color;
        if ((a_moves && kg_bit(words, a)) || (b_moves && kg_bit(words, b))) {
            continue;
        }
        if (a_moves) {
            kg_set_bit(words, a);
        }
        if (b_moves) {
            kg_set_bit(words, b);
        }
        return c;
    }
    return KG_COLOR_COUNT;
}

void kg_graph_color(kg_graph_coloring* g, const kg_contact* contacts, int count, const kg_body_pool* bodies,
                    int* scratch_colors)
{
    int sizes[KG_COLOR_COUNT + 1];
    memset(sizes, 0, sizeof sizes);
    for (int k = 0; k < count; ++k) {
        kg_u32 a = contacts[k].a, b = contacts[k].b;
        int color = kg_pick_color(g, a, b, kg_takes_impulses(bodies, a), kg_takes_impulses(bodies, b));
        scratch_colors[k] = color;
        sizes[color] += 1;
    }
    g->color_start[0] = 0;
    g->color_count = 0;
    for (int c = 0; c <= KG_COLOR_COUNT; ++c) {
        g->color_start[c + 1] = g->color_start[c] + sizes[c];
        if (c < KG_COLOR_COUNT && sizes[c] > 0) {
            g->color_count = c + 1;
        }
    }
    int fill[KG_COLOR_COUNT + 1];
    memcpy(fill, g->color_start, sizeof fill);
    for (int k = 0; k < count; ++k) {
        g->order[fill[scratch_colors[k]]++] = k;
    }
    /* clear only the bits set, so the cost follows the constraints, not the capacity */
    for (int k = 0; k < count; ++k) {
        int c = scratch_colors[k];
        if (c == KG_COLOR_COUNT) {
            continue;
        }
        kg_u32* words = g->bits + (size_t)c * (size_t)g->words_per_color;
        if (kg_takes_impulses(bodies, contacts[k].a)) {
            kg_clear_bit(words, contacts[k].a);
        }
        if (kg_takes_impulses(bodies, contacts[k].b)) {
            kg_clear_bit(words, contacts[k].b);
        }
    }
}
