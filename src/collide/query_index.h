/* The index the world queries (collide/query.c) search: every shape of every live body,
 * its world bounds, in a bounding volume hierarchy made from Morton codes. The step's
 * broadphase (collide/broadphase.h) keeps nothing between steps that a query could use,
 * so queries keep their own, made again lazily by the first query after the world changed
 * (a step, a write to the body pool through the API, a shape added or removed).
 *
 * Build: the shapes' bounds (kg_shape_aabb at the body's transform, fattened by
 * KG_QUERY_MARGIN so that rounding in a node test can never drop a shape the narrow test
 * hits) are keyed by the Morton code of their centres, quantised over the centres'
 * extent, and radix sorted (stable, so equal codes stay in slot order). The sorted leaves
 * are grouped KG_QUERY_FANOUT at a time into nodes, the nodes likewise, up to one root:
 * no pointers, each level an array. O(n) after the sort, deterministic: the index depends
 * only on the slots and their bounds. Memory grows with the shapes and is kept.
 *
 * Search: depth first, children in order, so leaves are visited in Morton order, each
 * node pruned by the caller's test (a ray's slab test, a box overlap). */
#ifndef KG_QUERY_INDEX_H
#define KG_QUERY_INDEX_H

#include "core/world.h"
#include "kgyro/query.h"

/* Nodes group this many children. */
#define KG_QUERY_FANOUT 4
/* Bounds are fattened by this (m) in the index. */
#define KG_QUERY_MARGIN 1.0e-3f

typedef struct kg_query_index kg_query_index;

/* The world's index, made again first when the world changed since it was made; NULL with
 * KG_ERROR_OUT_OF_MEMORY set when it cannot grow. */
const kg_query_index* kg_query_index_current(kg_world* world);
void kg_query_index_destroy(kg_query_index* index);

/* How many shapes it holds. */
int kg_query_index_count(const kg_query_index* index);

/* Called with each indexed shape slot whose node passes; returns 0 to stop the search. */
typedef int kg_query_leaf_fn(kg_u32 shape, void* ctx);

/* The leaves whose boxes (and their ancestors') box_test accepts. */
typedef int kg_query_box_test(kg_aabb box, const void* ctx);
void kg_query_index_search(const kg_query_index* index, kg_query_box_test* test, const void* test_ctx,
                           kg_query_leaf_fn* leaf, void* leaf_ctx);

/* The shapes and tiles that live shape slot s overlaps at its body's pose, its body's own
 * shapes left out (a sensor's visitors), as kg_world_overlap_shape_results finds them
 * (collide/query.c). */
kg_result kg_overlap_of_shape(const kg_world* world, kg_u32 s, kg_query_filter filter, kg_overlap_result_fn* fn,
                              void* ctx);

#endif
