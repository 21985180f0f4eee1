/* Comparing worlds built the same way (other thread counts, other backends). Handles
 * carry their world (core/generation.h), so a handle of one world is invalid in its twin:
 * the twin's own handle of the same slot is looked up, and handles reported by the two
 * are compared with the world's tag taken out. */
#ifndef KG_TWIN_H
#define KG_TWIN_H

#include "core/generation.h"
#include "kgyro/kgyro.h"

/* twin's handle of the body in body's slot (twin's tag, as its first body's handle
 * shows it, with body's count of reuses). */
static inline kg_body kg_twin_body(const kg_world* twin, kg_body body)
{
    kg_body first = KG_NULL_BODY_INIT;
    int count = 0;
    kg_world_get_bodies(twin, &first, 1, &count);
    kg_body h = {body.index, (first.generation & ~KG_GENERATION_COUNT_MASK) | (body.generation & KG_GENERATION_COUNT_MASK)};
    return h;
}

static inline kg_body kg_untagged_body(kg_body body)
{
    body.generation &= KG_GENERATION_COUNT_MASK;
    return body;
}

static inline kg_shape_id kg_untagged_shape(kg_shape_id shape)
{
    shape.generation &= KG_GENERATION_COUNT_MASK;
    return shape;
}

static inline void kg_untag_contact(kg_contact_info* c)
{
    c->a = kg_untagged_body(c->a);
    c->b = kg_untagged_body(c->b);
    c->shape_a = kg_untagged_shape(c->shape_a);
    c->shape_b = kg_untagged_shape(c->shape_b);
}

#endif
