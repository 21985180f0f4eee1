#include "solve/graph_color.h"
#include "core/alloc.h"
#include "core/error.h"

#include <string.h>

kg_result kg_graph_coloring_init(kg_graph_coloring* g, int body_capacity, int constraint_capacity)
{
    memset(g, 0, sizeof *g);
    g->used = kg_alloc_zeroed((size_t)body_capacity * sizeof *g->used);
    g->order = kg_alloc_zeroed((size_t)constraint_capacity * sizeof *g->order);
    if (!g->used || !g->order) {
        kg_graph_coloring_free(g);
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the constraint graph colouring");
    }
    return KG_OK;
}

void kg_graph_coloring_free(kg_graph_coloring* g)
{
    kg_free(g->used);
    kg_free(g->order);
    g->used = NULL;
    g->order = NULL;
}

/* A body takes part in colouring only if the solver writes to it. */
static int kg_takes_impulses(const kg_body_pool* bodies, kg_u32 slot)
{
    return slot != KG_NULL_INDEX && kg_pool_is_simulated(bodies, (int)slot);
}

#define KG_ALL_COLORS ((1u << KG_COLOR_COUNT) - 1u)

/* The lowest colour neither moving body has taken yet, or KG_COLOR_COUNT (the overflow). */
static int kg_pick_color(kg_graph_coloring* g, kg_u32 a, kg_u32 b, int a_moves, int b_moves)
{
    kg_u32 taken = (a_moves ? g->used[a] : 0u) | (b_moves ? g->used[b] : 0u);
    kg_u32 free = ~taken & KG_ALL_COLORS;
    if (free == 0u) {
        return KG_COLOR_COUNT;
    }
    int c = __builtin_ctz(free);
    if (a_moves) {
        g->used[a] |= 1u << c;
    }
    if (b_moves) {
        g->used[b] |= 1u << c;
    }
    return c;
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
    /* clear only the bodies marked, so the cost follows the constraints, not the capacity */
    for (int k = 0; k < count; ++k) {
        if (contacts[k].a != KG_NULL_INDEX) {
            g->used[contacts[k].a] = 0u;
        }
        if (contacts[k].b != KG_NULL_INDEX) {
            g->used[contacts[k].b] = 0u;
        }
    }
}
