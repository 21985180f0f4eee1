/* A body's shapes, as the body API (core/body.c) and the shape API (core/body_shape.c)
 * keep them: the shape pool's slots and each body's list, and what the body pool derives
 * from them (its bounds shape, filter, material and mass data). */
#ifndef KG_BODY_SHAPES_H
#define KG_BODY_SHAPES_H

#include "core/world.h"

/* A body definition's first shape: its geometry with the body's material and filter. */
kg_body_shape_def kg_first_shape_def(const kg_body_def* def);
/* Writes shape slot s (acquired) from def (its geometry aside: core/shape_pool.h) and
 * links it to body slot i. */
void kg_shape_attach(kg_world* world, int s, int i, const kg_body_shape_def* def);
/* What the body pool derives from body i's shapes' material: its filter (of its solid
 * shapes, or-ed) and the first shape's friction and restitution (what its tile contacts
 * use). */
void kg_body_material_changed(kg_world* world, kg_body_pool* p, int i);
/* Everything the body pool derives from body i's shapes, after one was added or removed
 * (shape_count_before: how many it had): its bounds shape, its material, and, for a
 * moving body whose mass was not given, its mass data, about a centre of mass that moves
 * while the body's origin stays. */
void kg_body_shapes_changed(kg_world* world, kg_body_pool* p, int i, int shape_count_before);
/* Releases every shape of body slot i (it is being destroyed). */
void kg_body_release_shapes(kg_world* world, int i);

#endif
