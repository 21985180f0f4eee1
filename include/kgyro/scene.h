/* KineticGyro: scenes, a world's contents described as data, built from JSON files,
 * from generators (pyramids, rain, the benchmark set) or from code. One scene can be
 * instantiated in a kgyro world, or (in bench/) in a peer engine, from the same data.
 * Part of the kgyro_io library (needs cJSON). */
#ifndef KGYRO_SCENE_H
#define KGYRO_SCENE_H

#include "types.h"
#include "world.h"
#include "body.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct kg_scene kg_scene;

typedef enum kg_scene_force_type {
    KG_SCENE_FORCE_GRAVITY = 0, /* vector = extra acceleration */
    KG_SCENE_FORCE_WIND = 1     /* vector = direction; strength (N); drag (N s/m) */
} kg_scene_force_type;

typedef struct kg_scene_force {
    kg_scene_force_type type;
    kg_vec2 vector;
    float strength;
    float drag;
    int body_count;          /* 0 = all bodies */
    const int* body_indices; /* scene body indices, body_count of them */
} kg_scene_force;

/* Loading. On failure the result is KG_ERROR_IO or KG_ERROR_PARSE and kg_last_error()
 * reads "FILE: JSON.PATH: what is wrong", e.g. "a.json: bodies[3].shape.radius: must be > 0". */
KG_API kg_result kg_scene_load_file(const char* path, kg_scene** out);
KG_API kg_result kg_scene_parse(const char* json, size_t length, const char* source_name, kg_scene** out);

/* Building from code. */
KG_API kg_result kg_scene_create(kg_scene** out);
KG_API void kg_scene_destroy(kg_scene* scene);
KG_API kg_result kg_scene_add_body(kg_scene* scene, const char* name, const kg_body_def* def);
KG_API kg_result kg_scene_add_force(kg_scene* scene, const kg_scene_force* force);
KG_API kg_world_def* kg_scene_world_def(kg_scene* scene); /* editable in place */
KG_API float kg_scene_dt(const kg_scene* scene);
KG_API int kg_scene_steps(const kg_scene* scene); /* suggested step count, 0 = none */

/* Reading. */
KG_API int kg_scene_body_count(const kg_scene* scene);
KG_API const kg_body_def* kg_scene_body_def(const kg_scene* scene, int index);
KG_API const char* kg_scene_body_name(const kg_scene* scene, int index);
KG_API int kg_scene_force_count(const kg_scene* scene);
KG_API const kg_scene_force* kg_scene_get_force(const kg_scene* scene, int index);

/* Creates a world holding the scene (capacities grown to fit), its bodies and forces.
 * out_bodies, if not NULL, receives kg_scene_body_count() handles in scene order. */
KG_API kg_result kg_scene_instantiate(const kg_scene* scene, const kg_world_def* override_def,
                                      kg_world** out_world, kg_body* out_bodies);

/* Generators. Names: "pyramid_B" (base B), "stack_N", "rain_N" (mixed boxes and circles),
 * "particles_N", and the benchmark scenes "large_pyramid", "many_pyramids", "smash",
 * "tumbler". seed drives the random ones. */
KG_API kg_result kg_scene_generate(const char* name, uint32_t seed, kg_scene** out);

#ifdef __cplusplus
}
#endif
#endif
