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

void kg_graph_color_contacts(kg_graph_coloring* g, kg_contact* contacts, int count, const kg_body_pool* bodies,
                             int* colors)
{
    memset(g->used, 0, (size_t)bodies->high_water * sizeof *g->used);
    kg_color_serially(count, contacts, bodies->flags, g->used, colors, g->order);
}

void kg_graph_color(kg_graph_coloring* g, kg_contact* contacts, int count, const kg_body_pool* bodies,
                    int* scratch_colors)
{
    kg_graph_color_contacts(g, contacts, count, bodies, scratch_colors);
    kg_order_by_color(count, scratch_colors, g->order, NULL, g->color_start);
    g->color_count = kg_colors_in_use(g->color_start);
}
