/* Data layout shared by the host and the OpenCL kernels: the compiled shape of a body
 * and the contact manifold. Sizes are asserted at the bottom, on both sides, so a
 * change that breaks the agreement fails to compile. */
#ifndef KG_LAYOUT_H
#define KG_LAYOUT_H

#include "kg_math.h"

#define KG_MAX_VERTS 8

/* A contact's body index meaning "no body": the static world (tile maps). */
#define KG_NULL_INDEX 0xFFFFFFFFu

/* A body's collision shape in the body's frame (around its origin), ready for
 * collision: polygons are convex, counter-clockwise, with unit outward edge normals, and
 * rounded by radius (0 for the polygons a user gives). count 2 is a capsule (or a segment
 * when radius is 0): the segment from vertices[0] to vertices[1] as a 2-vertex polygon,
 * run both ways with opposite normals. count 1 is a circle (or a point when radius is 0)
 * centred at vertices[0]. */
typedef struct kg_shape {
    kg_vec2 vertices[KG_MAX_VERTS];
    kg_vec2 normals[KG_MAX_VERTS];
    kg_vec2 centroid;
    float radius;
    kg_i32 count;
    kg_u32 chain; /* a chain segment's flags (collide/chain.h); 0 for every other shape */
    kg_u32 parallelogram; /* 1: four vertices, each edge's normal exactly the opposite of the
                           * one across (a box); the separating axis test's shortcut */
} kg_shape;

/* A shape's flags in the shape pool (core/shape_pool.h), read by the shared pair code. */
#define KG_SHAPE_ALIVE 0x1u
#define KG_SHAPE_SENSOR 0x2u /* never makes a solid contact */
#define KG_SHAPE_HELD 0x4u   /* destroyed; the slot is free after the next step */

/* Feature id of a contact point: which features of a and b made it, stable across
 * steps while the same features touch, so impulses can be carried over. */
#define KG_FEATURE_ID(a, b) ((((kg_u32)(a) & 0xFFu) << 8) | ((kg_u32)(b) & 0xFFu))

typedef struct kg_manifold_point {
    kg_vec2 point;          /* world frame, midway between the two surfaces */
    kg_vec2 anchor_a;       /* point relative to body a's origin (world frame axes) */
    kg_vec2 anchor_b;       /* point relative to body b's origin (world frame axes) */
    float separation;       /* < 0 when overlapping */
    float normal_impulse;   /* accumulated, carried across steps for warm starting */
    float tangent_impulse;
    float normal_velocity;  /* relative approach speed before solving (restitution) */
    kg_u32 id;              /* KG_FEATURE_ID */
    float total_normal_impulse; /* over the whole step, all sub-steps (N s): what hit events
                                 * and kg_contact_info report; 0 until solved */
} kg_manifold_point;

typedef struct kg_manifold {
    kg_manifold_point points[2];
    kg_vec2 normal;         /* unit, from shape a towards shape b */
    kg_i32 point_count;     /* 0 when not touching within the speculative distance */
    kg_i32 keepable;        /* its shapes let it be kept while they barely move (collide/recycle.h):
                             * known from the contact alone, the shapes not read again */
} kg_manifold;

/* A body pair's manifold as it was computed, in the bodies' own frames, so that it can
 * be kept while the pair's relative pose barely moves (collide/recycle.h). Zeros for tile
 * contacts, which are computed every step. */
typedef struct kg_contact_base {
    kg_vec2 point_a[2]; /* each point in a's frame */
    kg_vec2 point_b[2]; /* the same point in b's frame */
    float separation[2];
    kg_vec2 normal;     /* in a's frame */
    kg_xf pose;         /* b's pose in a's frame */
} kg_contact_base;

/* A persistent contact: between a shape of body a and a shape of body b (body slots
 * a < b, shape slots shape_a and shape_b of the shape pool, tile == KG_NULL_INDEX), or
 * between body a and a tile of a tile map (b, shape_a and shape_b == KG_NULL_INDEX,
 * tile = its key). Body contacts are kept sorted by (a, b, shape_a, shape_b). */
typedef struct kg_contact {
    kg_manifold manifold;
    kg_u32 a, b;
    kg_u32 color;       /* the colour it took and its bodies' motion then (solve/coloring.h's
                         * kg_color_word), carried from step to step; KG_NO_COLOR when new.
                         * Beside a and b: the colouring reads these three alone of every
                         * contact, now from one cache line in 7 contacts of 8 (after the
                         * materials it was 4 of 8; many_pyramids: its share of the step
                         * 5.5% to 4.0%, perf) */
    kg_u32 tile;        /* tile key (map, layer, cell) for tile contacts */
    kg_u32 shape_a, shape_b; /* the shapes that touch (core/shape_pool.h), slots */
    float friction;     /* mixed: sqrt(fa * fb) */
    float restitution;  /* mixed: max(ra, rb) */
    kg_u32 generation_a, generation_b; /* of the bodies when the contact was made: a slot
                                        * reused by a new body is not mistaken for the old */
    kg_contact_base base;
} kg_contact;

#define KG_NO_COLOR 0xFFFFFFFFu

/* Carries last step's accumulated impulses over to m, point by point, where the feature
 * ids match: the warm start of a persistent contact. Returns how many points matched. */
KG_FN int kg_contact_carry_impulses(kg_manifold* m, const kg_manifold* old)
{
    int matched = 0;
    for (int i = 0; i < m->point_count; ++i) {
        for (int j = 0; j < old->point_count; ++j) {
            if (m->points[i].id == old->points[j].id) {
                m->points[i].normal_impulse = old->points[j].normal_impulse;
                m->points[i].tangent_impulse = old->points[j].tangent_impulse;
                matched += 1;
                break;
            }
        }
    }
    return matched;
}

KG_STATIC_ASSERT(sizeof(kg_vec2) == 8, vec2_size);
KG_STATIC_ASSERT(sizeof(kg_shape) == 152, shape_size);
KG_STATIC_ASSERT(sizeof(kg_manifold_point) == 48, manifold_point_size);
KG_STATIC_ASSERT(sizeof(kg_manifold) == 112, manifold_size);
KG_STATIC_ASSERT(sizeof(kg_contact_base) == 64, contact_base_size);
KG_STATIC_ASSERT(sizeof(kg_contact) == 216, contact_size);

#endif
