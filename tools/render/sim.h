/* A scene running in a world, as the render and view commands drive it. */
#ifndef KG_RENDER_SIM_H
#define KG_RENDER_SIM_H

#include "kgyro/kgyro.h"
#include "kgyro/scene.h"

typedef struct kg_sim {
    kg_scene* scene;
    kg_world* world;
    kg_body* bodies; /* the scene's bodies in scene order, then any added later */
    int body_count, body_capacity;
    float dt;
} kg_sim;

/* Whether text ends with suffix ("level.tmj", ".tmj"). */
int kg_ends_with(const char* text, const char* suffix);

/* Opens name as the tools take a scene: a path to a scene file or a Tiled map (.tmj),
 * read under max_bodies (-1: no limit; kg_scene_limits), its notes (what the loader
 * ignored, kg_scene_get_note) on stderr, else a generator name (kg_scene_generate_limited
 * with seed, under the same max_bodies). */
kg_result kg_open_scene(const char* name, uint32_t seed, int max_bodies, kg_scene** out);

/* Builds the world for scene on backend, with room for extra_bodies more bodies. The
 * sim owns the scene from here on, also on failure. */
kg_result kg_sim_start(kg_sim* sim, kg_scene* scene, kg_backend backend, int extra_bodies);
kg_result kg_sim_step(kg_sim* sim);
/* Adds a body and keeps its handle after the scene's ones. */
kg_result kg_sim_add_body(kg_sim* sim, const kg_body_def* def, kg_body* out);
void kg_sim_stop(kg_sim* sim);

/* "auto", "cpu" or "opencl"; -1 for anything else. */
int kg_parse_backend(const char* text, kg_backend* out);
const char* kg_backend_label(kg_backend backend);

#endif
