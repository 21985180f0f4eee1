/* The body pool: structure of arrays, one slot per body, sized once when the world is
 * created. A slot's index is stable for the body's life; its generation changes when the
 * body dies, so old handles are recognised as stale. Free slots are reused lowest first,
 * which keeps the live slots dense and the iteration order deterministic. */
#ifndef KG_BODY_POOL_H
#define KG_BODY_POOL_H

#include "core/kg_layout.h"
#include "kgyro/body.h"

/* flags */
#define KG_FLAG_ALIVE 0x1u
#define KG_FLAG_FIXED_ROTATION 0x2u
#define KG_FLAG_FROZEN 0x4u /* its state became non-finite: kept out of the simulation */
#define KG_FLAG_ASLEEP 0x8u /* its island is at rest: still, until something wakes it (solve/sleep.c) */
#define KG_TYPE_SHIFT 4u
#define KG_TYPE_MASK 0x30u
/* static or asleep, and neither moved nor changed since the last collide stage: its
 * manifolds with another such body are last step's (collide/collide.c) */
#define KG_FLAG_RESTED 0x40u

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
    kg_shape* shape;
    kg_vec2* local_center; /* centre of mass in the body frame */
    float* mass;
    float* inertia;        /* about the centre of mass */
    float* inv_mass;       /* 0 = infinite */
    float* inv_inertia;    /* 0 = infinite */
    float* friction;
    float* restitution;
    float* linear_damping;
    float* angular_damping;
    kg_u32* category;
    kg_u32* mask;
    kg_u32* flags;
    kg_u32* generation;
    void** user_data;
} kg_body_pool;

static inline kg_body_type kg_pool_type(const kg_body_pool* p, int i)
{
    return (kg_body_type)((p->flags[i] & KG_TYPE_MASK) >> KG_TYPE_SHIFT);
}

static inline int kg_pool_alive(const kg_body_pool* p, int i) { return (p->flags[i] & KG_FLAG_ALIVE) != 0; }

/* Takes part in collisions as a body that can move: dynamic bodies and particles, asleep
 * or awake, unless frozen. */
static inline int kg_pool_collides(const kg_body_pool* p, int i)
{
    kg_u32 f = p->flags[i];
    kg_body_type t = (kg_body_type)((f & KG_TYPE_MASK) >> KG_TYPE_SHIFT);
    return (f & (KG_FLAG_ALIVE | KG_FLAG_FROZEN)) == KG_FLAG_ALIVE && (t == KG_BODY_DYNAMIC || t == KG_BODY_PARTICLE);
}

static inline int kg_pool_asleep(const kg_body_pool* p, int i) { return (p->flags[i] & KG_FLAG_ASLEEP) != 0; }

/* Moves under forces and contacts: a colliding body that is awake. */
static inline int kg_pool_is_simulated(const kg_body_pool* p, int i)
{
    return kg_pool_collides(p, i) && !kg_pool_asleep(p, i);
}

/* Its pose changes in a step: awake, not static, not frozen (kinematic bodies move too). */
static inline int kg_pool_moves(const kg_body_pool* p, int i)
{
    kg_u32 f = p->flags[i];
    return (f & (KG_FLAG_ALIVE | KG_FLAG_FROZEN | KG_FLAG_ASLEEP)) == KG_FLAG_ALIVE && kg_pool_type(p, i) != KG_BODY_STATIC;
}

kg_result kg_body_pool_init(kg_body_pool* pool, int capacity);
void kg_body_pool_free(kg_body_pool* pool);
/* Takes the lowest free slot; -1 when full. */
int kg_body_pool_acquire(kg_body_pool* pool);
void kg_body_pool_release(kg_body_pool* pool, int index);
/* The slot of a live handle, or -1 (with the error set) for a stale or foreign one. */
int kg_body_pool_resolve(const kg_body_pool* pool, kg_body handle);

/* Recomputes the origin transform and bounds of slot i from its centre and rotation. */
void kg_body_update_transform(kg_body_pool* pool, int i);

#endif
