/* The CPU backend's constraint graph colouring (solve/coloring.h holds the algorithm, shared
 * with the kernels) and its buffers. */
#ifndef KG_GRAPH_COLOR_H
#define KG_GRAPH_COLOR_H

#include "core/body_pool.h"
#include "solve/coloring.h"
#include "solve/contact_solver.h"

typedef struct kg_graph_coloring {
    kg_u32* used;           /* per body, one bit per colour: the colours its constraints took */
    int* order;             /* constraint indices grouped by colour, overflow last */
    int color_start[KG_COLOR_COUNT + 2]; /* colour c is order[color_start[c], color_start[c+1]); */
                                         /* index KG_COLOR_COUNT is the overflow */
    int color_count;        /* colours in use (overflow not counted) */
} kg_graph_coloring;

kg_result kg_graph_coloring_init(kg_graph_coloring* g, int body_capacity, int constraint_capacity);
void kg_graph_coloring_free(kg_graph_coloring* g);
/* Colours the constraints of contacts[0, count) by their bodies: colors[k] is contact k's
 * colour (or KG_COLOR_COUNT, the overflow), also written to its colour word (kept colours
 * are carried in it); the lists are not made (order is scratch). */
void kg_graph_color_contacts(kg_graph_coloring* g, kg_contact* contacts, int count, const kg_body_pool* bodies,
                             int* colors);
/* kg_graph_color_contacts, then the contacts listed by colour (order, color_start,
 * color_count); scratch_colors holds count ints. */
void kg_graph_color(kg_graph_coloring* g, kg_contact* contacts, int count, const kg_body_pool* bodies,
                    int* scratch_colors);

#endif
