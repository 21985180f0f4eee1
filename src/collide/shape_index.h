/* The shapes of the bodies that have many (a chain's segments, above all), indexed so
 * that a body pair's pairs of shapes are found without trying every shape: a body near a
 * terrain chain of 10,000 segments tried all of them each step (200 balls resting on one:
 * 7.1 ms a step, 74 ms at 100,000 segments, linear in the chain's length).
 *
 * Each indexed body's shapes' world bounds (kg_shape_aabb at the body's transform, the
 * very floats kg_expand_pair computes) sorted along the body's longer extent
 * (collide/sorted_shapes.h, which continuous collision searches too). A static body's
 * bounds are made once; a kinematic body's again when it moves; all of them again when a
 * shape of the world changes (the shape pool's version).
 *
 * kg_shape_index_expand gives what kg_expand_pair gives (collide/pair_contact.h), the same
 * pairs of shapes in the same order, bit for bit, which the OpenCL backend (no index:
 * every shape tried, a work-item a body pair) and the CPU must agree on. CPU only; made
 * and grown inside the collide stage when shapes change, as the contact pool grows. */
#ifndef KG_SHAPE_INDEX_H
#define KG_SHAPE_INDEX_H

#include "collide/pair_contact.h"
#include "collide/sorted_shapes.h"
#include "core/world.h"

/* A body with at least this many shapes is indexed: below it, trying each is cheaper
 * than the search. */
#define KG_INDEXED_SHAPES 32

typedef struct kg_shape_index kg_shape_index;

kg_shape_index* kg_shape_index_create(void);
void kg_shape_index_destroy(kg_shape_index* index);

/* Brings the index up to date with the world's shapes and the indexed bodies' poses. */
/* Forgets what the index was made from: the next update makes it again (a restored
 * snapshot's shape pool may carry the version it was made at, with other shapes). */
void kg_shape_index_forget(kg_shape_index* index);
kg_result kg_shape_index_update(kg_shape_index* index, const kg_world* world);

/* kg_expand_pair for bodies a and b of world, through the index where one of them is
 * indexed: the pairs of shapes that may touch, those that fit below room written to out;
 * returns how many there are. */
int kg_shape_index_expand(kg_shape_index* index, const kg_world* world, kg_u32 a, kg_u32 b, kg_shape_pair* out,
                          int room);

/* Whether the index holds a body and was made for the world's shapes as they are (the
 * poses are this step's after kg_shape_index_update in its collide stage). */
int kg_shape_index_current(const kg_shape_index* index, const kg_world* world);
/* Its arrays as the shared code reads them (collide/sorted_shapes.h): per body slot its
 * span or -1, the spans, the sorted entries. */
void kg_shape_index_arrays(const kg_shape_index* index, const int** of_body, const kg_sorted_span** spans,
                           const kg_sorted_shape** shapes);

#endif
