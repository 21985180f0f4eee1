/* The body pool: structure of arrays, one slot per body, sized once when the world is
 * created. A slot's index is stable for the body's life; its generation changes when the
 * body dies, so old handles are recognised as stale. Free slots are reused lowest first,
 * which keeps the live slots dense and the iteration order deterministic. */
#ifndef KG_BODY_POOL_H
#define KG_BODY_POOL_H

#include "core/body_flags.h"
#include "core/kg_layout.h"
#include "kgyro/body.h"


typedef struct kg_body_pool {
    int capacity;
    int high_water; /* slots [0, high_water) have been used; the rest never were */
    int count;      /* live bodies */
    int first_free; /* no free slot below this index */

    /* state advanced by the step */
    kg_vec2* center;       /* centre of mass, world frame */
    kg_rot* rot;
    kg_vec2* velocity;     /* of the centre of mass */
    float* omega;
    kg_vec2* force;        /* accumulated until the end of the step */
    float* torque;
    float* drag;           /* N s/m of drag accumulated until the end of the step (wind) */
    float* sleep_time;     /* s the body has been at rest (solve/sleep.h) */
    kg_u32* island;        /* while asleep: the island it fell asleep with */
    kg_xf* xf;             /* body origin transform, derived from center and rot */
    kg_aabb* aabb;         /* world bounds of the shape, derived */

    /* properties */
    kg_shape* shape;       /* in the body frame: its shape when it has one (the shape pool
                            * keeps no copy), else a box around its shapes; the bounds, the
                            * broadphase and sleeping's extent read it either way */
    kg_u32* first_shape;   /* its shapes (core/shape_pool.h), lowest slot first; KG_NULL_INDEX: none */
    kg_u32* shape_count;
    kg_vec2* local_center; /* centre of mass in the body frame */
    float* mass;
    float* inertia;        /* about the centre of mass */
    float* inv_mass;       /* 0 = infinite */
    float* inv_inertia;    /* 0 = infinite */
    float* friction;
    float* restitution;
    float* linear_damping;
    float* angular_damping;
    kg_u32* category;      /* of its solid shapes, or-ed: the broadphase pairs bodies whose */
    kg_u32* mask;          /* shapes may collide; the narrowphase filters the shapes */
    kg_u32* flags;
    kg_u32* generation;
    void** user_data;
} kg_body_pool;

static inline kg_body_type kg_pool_type(const kg_body_pool* p, int i) { return (kg_body_type)kg_flags_type(p->flags[i]); }
static inline int kg_pool_alive(const kg_body_pool* p, int i) { return kg_flags_alive(p->flags[i]); }
static inline int kg_pool_asleep(const kg_body_pool* p, int i) { return kg_flags_asleep(p->flags[i]); }
static inline int kg_pool_collides(const kg_body_pool* p, int i) { return kg_flags_collide(p->flags[i]); }
static inline int kg_pool_is_simulated(const kg_body_pool* p, int i) { return kg_flags_simulated(p->flags[i]); }
static inline int kg_pool_moves(const kg_body_pool* p, int i) { return kg_flags_move(p->flags[i]); }

kg_result kg_body_pool_init(kg_body_pool* pool, int capacity);
void kg_body_pool_free(kg_body_pool* pool);
/* Takes the lowest free slot; -1 when full. */
int kg_body_pool_acquire(kg_body_pool* pool);
void kg_body_pool_release(kg_body_pool* pool, int index);
/* The slot of a live handle, or -1 (with the error set) for a stale or foreign one. */
int kg_body_pool_resolve(const kg_body_pool* pool, kg_body handle);

/* Recomputes the origin transform and bounds of slot i from its centre and rotation. */
void kg_body_update_transform(kg_body_pool* pool, int i);

/* Snapshots (core/snapshot.c, core/snapshot_io.h): the element sizes of the pool's arrays
 * folded into h; the pool written (slots [0, high_water), and every slot's generation);
 * and read back into pool, initialised here at capacity, which must be the snapshot's
 * (else, or for values that do not fit together, an error and pool left unallocated). */
struct kg_snap_out;
struct kg_snap_in;
uint64_t kg_body_pool_layout(uint64_t h);
void kg_body_pool_snapshot(const kg_body_pool* pool, struct kg_snap_out* out);
kg_result kg_body_pool_from_snapshot(kg_body_pool* pool, int capacity, struct kg_snap_in* in);

#endif
