/* Constraint graph colouring: constraints of one colour share no moving body, so a
 * colour can be solved in any order or all at once (threads, SIMD lanes, work-items)
 * with the same result. Colours are solved in sequence (Gauss-Seidel across colours).
 * Greedy, in constraint order, so the colouring itself is deterministic. Constraints
 * that fit no colour go to an overflow list solved serially, in order, after the colours. */
#ifndef KG_GRAPH_COLOR_H
#define KG_GRAPH_COLOR_H

#include "core/body_pool.h"
#include "solve/contact_solver.h"

#define KG_COLOR_COUNT 24

typedef struct kg_graph_coloring {
    kg_u32* used;           /* per body, one bit per colour: the colours its constraints took */
    int* order;             /* constraint indices grouped by colour, overflow last */
    int color_start[KG_COLOR_COUNT + 2]; /* colour c is order[color_start[c], color_start[c+1]); */
                                         /* index KG_COLOR_COUNT is the overflow */
    int color_count;        /* colours in use (overflow not counted) */
} kg_graph_coloring;

kg_result kg_graph_coloring_init(kg_graph_coloring* g, int body_capacity, int constraint_capacity);
void kg_graph_coloring_free(kg_graph_coloring* g);
/* Colours the constraints of contacts[0, count) by their bodies; scratch_colors holds
 * count ints. */
void kg_graph_color(kg_graph_coloring* g, const kg_contact* contacts, int count, const kg_body_pool* bodies,
                    int* scratch_colors);

#endif
