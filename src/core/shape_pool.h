/* The shape pool: structure of arrays, one slot per shape, like the body pool
 * (core/body_pool.h): a slot's index is stable for the shape's life, its generation moves
 * on when the shape dies, and free slots are reused lowest first, but only after the next
 * step: contacts name their shapes by slot (kg_contact.shape_a, shape_b), and last step's
 * contact of a shape destroyed between two steps must not be taken for a new shape's that
 * took its slot (its warm start, or worse its kept manifold, of another outline). Unlike the body pool it
 * grows (outside the step: only kg_create_body and kg_create_shape add shapes), from
 * max_bodies slots, since most bodies have one shape.
 *
 * Each body's shapes form a list in slot order (body pool's first_shape, then next), so
 * a body pair's shape pairs, and so its contacts, come in (shape_a, shape_b) order
 * whatever order the shapes were added in. */
#ifndef KG_SHAPE_POOL_H
#define KG_SHAPE_POOL_H

#include "core/body_pool.h"
#include "kgyro/shape.h"

typedef struct kg_shape_pool {
    int capacity;
    int high_water; /* slots [0, high_water) have been used; the rest never were */
    int count;      /* live shapes */
    int first_free; /* no free slot below this index */
    int held;       /* destroyed shapes whose slots are not free yet */
    kg_u32 tag;     /* the world's (core/generation.h): seeds the slots the pool grows by */
    kg_u32 version; /* moves on with every change of a shape (the OpenCL backend uploads them) */
    int compound_bodies; /* bodies with more than one shape: the narrowphase then expands
                          * body pairs into shape pairs (collide/collide.c) */

    kg_shape* geometry; /* compiled, in the body frame, of the shapes of compound bodies only
                         * (a body's only shape is the body pool's shape): NULL until the
                         * first compound body, so that a world of one-shape bodies does not
                         * hold every shape twice (144 bytes a body) */
    kg_u32* body;       /* the owning body's slot */
    kg_u32* next;       /* the body's next shape (higher slot), KG_NULL_INDEX after the last */
    float* density;
    float* friction;
    float* restitution;
    kg_u32* category;
    kg_u32* mask;
    kg_u32* flags;
    kg_u32* generation;
    void** user_data;
} kg_shape_pool;

static inline int kg_shape_alive(const kg_shape_pool* s, int i) { return (s->flags[i] & KG_SHAPE_ALIVE) != 0u; }
static inline int kg_shape_is_sensor(const kg_shape_pool* s, kg_u32 i) { return (s->flags[i] & KG_SHAPE_SENSOR) != 0u; }

kg_result kg_shape_pool_init(kg_shape_pool* pool, int capacity);
void kg_shape_pool_free(kg_shape_pool* pool);
/* Takes the lowest free slot, growing the pool by half when full; -1 (with the error set)
 * when out of memory. */
int kg_shape_pool_acquire(kg_shape_pool* pool);
/* Destroys the shape in slot index: its handles turn stale now, the slot is held until
 * kg_shape_pool_free_held. */
void kg_shape_pool_release(kg_shape_pool* pool, int index);
/* Frees the held slots: after a step, whose contacts name no shape destroyed before it. */
void kg_shape_pool_free_held(kg_shape_pool* pool);
/* The slot of a live handle, or -1 (with the error set) for a stale or foreign one. */
int kg_shape_pool_resolve(const kg_shape_pool* pool, kg_shape_id handle);

/* Grows the pool, when needed, so that the next more acquisitions cannot fail; unchanged
 * (OUT_OF_MEMORY set) when it cannot. */
kg_result kg_shape_pool_reserve(kg_shape_pool* pool, int more);
/* Allocates the geometry array (at the pool's capacity) if it is not yet. */
kg_result kg_shape_pool_reserve_geometry(kg_shape_pool* pool);

/* Shape s's geometry: the shape pool's for a shape of a compound body, the body pool's
 * shape for a body's only one. */
static inline const kg_shape* kg_shape_geometry(const kg_body_pool* p, const kg_shape_pool* sp, kg_u32 s)
{
    kg_u32 i = sp->body[s];
    return p->shape_count[i] > 1u ? &sp->geometry[s] : &p->shape[i];
}

/* Snapshots (core/snapshot.c), as the body pool's (core/body_pool.h): the pool is read
 * at the snapshot's capacity; its shapes' bodies must be slots below bodies. */
uint64_t kg_shape_pool_layout(uint64_t h);
void kg_shape_pool_snapshot(const kg_shape_pool* pool, struct kg_snap_out* out);
kg_result kg_shape_pool_from_snapshot(kg_shape_pool* pool, int bodies, struct kg_snap_in* in);

/* Inserts shape slot into the list starting at *first, keeping it in slot order. */
void kg_shape_list_insert(kg_shape_pool* pool, kg_u32* first, kg_u32 slot);
/* Takes shape slot out of the list starting at *first. */
void kg_shape_list_remove(kg_shape_pool* pool, kg_u32* first, kg_u32 slot);

#endif
