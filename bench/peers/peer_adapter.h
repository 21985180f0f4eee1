/* What each peer adapter implements: a handful of per-body primitives. peers.c does the
 * rest once for every engine (walking the scene, pivots, totals), so the adapters stay
 * a direct translation of a kg_body_def into the engine's own calls. */
#ifndef KG_PEER_ADAPTER_H
#define KG_PEER_ADAPTER_H

#include "kgyro/scene.h"
#include "kgyro/shape.h"

#ifdef __cplusplus
extern "C" {
#endif

#define KG_PEER_MAX_SHAPES 64 /* of one body, as the scene format allows */

typedef struct kg_peer_setup {
    kg_vec2 gravity;
    float restitution_threshold; /* m/s, from the scene's world def */
    float linear_slop;           /* m: overlap allowed to keep contacts, from the world def */
    int body_count;              /* bodies that will be added, for sizing */
    int threads;
} kg_peer_setup;

/* A body to add. density is resolved: a def with a mass override and a shape comes with
 * the density that gives that mass; a def without a shape (a point particle) uses
 * def->mass. A compound body comes with all its shapes (the def's first, each with its
 * own material and filter) and their mass data, kgyro's, for the engine to be given. */
typedef struct kg_peer_body {
    const kg_body_def* def;
    float density;
    const kg_body_shape_def* shapes; /* NULL for a body of one shape (def->shape) */
    int shape_count;
    kg_mass_data mass;               /* of the shapes, when shapes is not NULL */
} kg_peer_body;

typedef struct kg_peer_adapter {
    const char* name;
    const char* (*describe)(int threads);
    void* (*create)(const kg_peer_setup* setup);
    void (*destroy)(void* world);
    /* Adds the next body (bodies are numbered in the order added). NULL on success, else
     * why the engine cannot take it. */
    const char* (*add_body)(void* world, const kg_peer_body* body);
    /* Adds a scene joint between bodies already added (body_a -1: the world); anchors
     * in world coordinates at the start. NULL on success, else why the engine cannot
     * take it (a kind or option it lacks). */
    const char* (*add_joint)(void* world, const kg_scene_joint* joint);
    void (*step)(void* world, float dt);
    void (*get_state)(const void* world, int index, kg_body_state* out);
    /* The world point the engine turns the body about (its centre of mass). */
    kg_vec2 (*rotation_center)(const void* world, int index);
    void (*set_velocity)(void* world, int index, kg_vec2 velocity);
    double (*mass)(const void* world, int index); /* 0 unless dynamic */
    kg_aabb (*bounds)(const void* world, int index);
} kg_peer_adapter;

#ifdef KG_PEER_HAVE_BOX2D
extern const kg_peer_adapter kg_box2d_adapter;
#endif
#ifdef KG_PEER_HAVE_CHIPMUNK
extern const kg_peer_adapter kg_chipmunk_adapter;
#endif

#ifdef __cplusplus
}
#endif
#endif
