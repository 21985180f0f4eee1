/* A body's flags word and what it says, shared by the pool (core/body_pool.h) and the
 * kernels, so both backends ask the same questions of it. The body types (KG_BODY_*)
 * come from kgyro/body.h in C; the kernels, which cannot include the public headers,
 * get the same values here, checked against them in C. */
#ifndef KG_BODY_FLAGS_H
#define KG_BODY_FLAGS_H

#include "core/kg_shared.h"

#define KG_TYPE_STATIC 0
#define KG_TYPE_DYNAMIC 1
#define KG_TYPE_KINEMATIC 2
#define KG_TYPE_PARTICLE 3
#ifdef __OPENCL_VERSION__
#define KG_BODY_STATIC KG_TYPE_STATIC
#define KG_BODY_DYNAMIC KG_TYPE_DYNAMIC
#define KG_BODY_KINEMATIC KG_TYPE_KINEMATIC
#define KG_BODY_PARTICLE KG_TYPE_PARTICLE
#else
#include "kgyro/body.h"
KG_STATIC_ASSERT(KG_BODY_STATIC == KG_TYPE_STATIC && KG_BODY_DYNAMIC == KG_TYPE_DYNAMIC &&
                     KG_BODY_KINEMATIC == KG_TYPE_KINEMATIC && KG_BODY_PARTICLE == KG_TYPE_PARTICLE,
                 body_types_as_the_kernels_see_them);
#endif

#define KG_FLAG_ALIVE 0x1u
#define KG_FLAG_FIXED_ROTATION 0x2u
#define KG_FLAG_FROZEN 0x4u /* its state became non-finite: kept out of the simulation */
#define KG_FLAG_ASLEEP 0x8u /* its island is at rest: still, until something wakes it (solve/sleep.c) */
#define KG_TYPE_SHIFT 4u
#define KG_TYPE_MASK 0x30u
/* static or asleep, and neither moved nor changed since the last collide stage: its
 * manifolds with another such body are last step's (collide/collide.c) */
#define KG_FLAG_RESTED 0x40u
/* swept against dynamic bodies too in the continuous collision (collide/continuous.h) */
#define KG_FLAG_BULLET 0x80u
/* its mass was given (kg_body_def.mass, kg_body_set_inverse_mass): adding or removing a
 * shape leaves it (core/body_shape.c) */
#define KG_FLAG_MASS_SET 0x100u
/* Its contacts go through the world's pre-solve callback (kgyro/collision.h). */
#define KG_FLAG_PRE_SOLVE 0x200u

KG_FN kg_u32 kg_flags_type(kg_u32 f) { return (f & KG_TYPE_MASK) >> KG_TYPE_SHIFT; }
KG_FN int kg_flags_alive(kg_u32 f) { return (f & KG_FLAG_ALIVE) != 0u; }
KG_FN int kg_flags_asleep(kg_u32 f) { return (f & KG_FLAG_ASLEEP) != 0u; }

/* The moving types, dynamic bodies and particles, are the odd ones: one bit tells them. */
#define KG_FLAG_MOVING_TYPE (1u << KG_TYPE_SHIFT)
KG_STATIC_ASSERT((KG_TYPE_DYNAMIC & 1) && (KG_TYPE_PARTICLE & 1) && !(KG_TYPE_STATIC & 1) && !(KG_TYPE_KINEMATIC & 1),
                 moving_types_are_odd);

/* Takes part in collisions as a body that can move: dynamic bodies and particles, asleep
 * or awake, unless frozen. */
KG_FN int kg_flags_collide(kg_u32 f)
{
    kg_u32 mask = KG_FLAG_ALIVE | KG_FLAG_FROZEN | KG_FLAG_MOVING_TYPE;
    return (f & mask) == (KG_FLAG_ALIVE | KG_FLAG_MOVING_TYPE);
}

/* Moves under forces and contacts: a colliding body that is awake. One test, as the
 * colouring asks it of both bodies of every contact every step. */
KG_FN int kg_flags_simulated(kg_u32 f)
{
    kg_u32 mask = KG_FLAG_ALIVE | KG_FLAG_FROZEN | KG_FLAG_ASLEEP | KG_FLAG_MOVING_TYPE;
    return (f & mask) == (KG_FLAG_ALIVE | KG_FLAG_MOVING_TYPE);
}

/* Its pose changes in a step: awake, not static, not frozen (kinematic bodies move too). */
KG_FN int kg_flags_move(kg_u32 f)
{
    return (f & (KG_FLAG_ALIVE | KG_FLAG_FROZEN | KG_FLAG_ASLEEP)) == KG_FLAG_ALIVE &&
           kg_flags_type(f) != (kg_u32)KG_BODY_STATIC;
}

#endif
