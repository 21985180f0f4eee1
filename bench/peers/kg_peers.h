/* The peer engines of the benchmark (Box2D 2.4, Chipmunk 7) behind one C interface.
 * A peer world is built from the same kg_scene a kgyro world is built from, so every
 * engine steps the same bodies, shapes, masses and materials:
 *
 *   kg_peer_world* peer;
 *   if (kg_peer_create(KG_PEER_BOX2D, scene, 1, &peer) == KG_OK) {
 *       kg_peer_step(peer, kg_scene_dt(scene));
 *       kg_peer_destroy(peer);
 *   }
 *
 * Each peer is optional at build time: kg_peer_available() says whether it was built,
 * kg_peer_describe() says how it is set up, or why it is missing. */
#ifndef KG_PEERS_H
#define KG_PEERS_H

#include "kgyro/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum kg_peer_engine {
    KG_PEER_BOX2D = 0,
    KG_PEER_CHIPMUNK = 1,
    KG_PEER_ENGINE_COUNT = 2
} kg_peer_engine;

typedef struct kg_peer_world kg_peer_world;

/* "box2d" or "chipmunk". */
const char* kg_peer_name(kg_peer_engine engine);
/* The engine called name, or -1. */
int kg_peer_find(const char* name);
int kg_peer_available(kg_peer_engine engine);
/* One line: the version and the solver settings (for that many threads) when built,
 * else why it is missing. */
const char* kg_peer_describe(kg_peer_engine engine, int threads);

/* Builds the scene: gravity from its world def, every body in scene order, then its
 * joints (the kinds and options each engine has; the first it lacks is
 * KG_ERROR_UNSUPPORTED). Scene force applicators are not mapped (KG_ERROR_UNSUPPORTED);
 * pivoted kinematic bodies are driven round their pivots by kg_peer_step as
 * kg_scene_step does. threads > 1 only matters to
 * Chipmunk (its threaded solver, at most 2 threads); Box2D 2.4 is single-threaded.
 * On failure kg_peer_last_error() says why. */
kg_result kg_peer_create(kg_peer_engine engine, const kg_scene* scene, int threads, kg_peer_world** out);
void kg_peer_destroy(kg_peer_world* world);
const char* kg_peer_last_error(void);

/* Drives the pivoted kinematic bodies for this step, then steps the engine once. */
void kg_peer_step(kg_peer_world* world, float dt);

int kg_peer_body_count(const kg_peer_world* world);
/* Body origins, angles and velocities, kg_peer_body_count() of them in scene order. */
void kg_peer_get_states(const kg_peer_world* world, kg_body_state* out);
/* What the engine made of the scene, to check that every engine got the same one: the
 * mass of the dynamic bodies and particles, and the box around every shape (a body
 * without a shape counts as its origin). */
double kg_peer_dynamic_mass(const kg_peer_world* world);
kg_aabb kg_peer_bounds(const kg_peer_world* world);

#ifdef __cplusplus
}
#endif
#endif
