/* Scene generators, shared by kg_scene_generate (scenes by name) and the "generators"
 * of a JSON scene. Each appends its bodies to a scene; the parameters are checked by the
 * caller (the JSON loader reports them with their path), except what only the generator
 * can know, such as a region too small for its bodies. docs/scene-format.md describes
 * the layouts. */
#ifndef KG_SCENE_GENERATE_H
#define KG_SCENE_GENERATE_H

#include "kgyro/scene.h"

typedef struct kg_gen_material {
    float density;
    float friction;
    float restitution;
} kg_gen_material;

/* The material of kg_default_body_def(). */
kg_gen_material kg_gen_default_material(void);

/* Square boxes; row i (from 0 at the bottom) has base - i boxes. origin is the middle
 * of the bottom edge of the bottom row. */
typedef struct kg_gen_pyramid {
    int base;
    float box_size;
    kg_vec2 origin;
    kg_gen_material material;
} kg_gen_pyramid;

/* A column of square boxes, gap apart; origin is the middle of the bottom edge. */
typedef struct kg_gen_stack {
    int count;
    float box_size;
    float gap;
    kg_vec2 origin;
    kg_gen_material material;
} kg_gen_stack;

/* Three static boxes: a floor whose top face is centred on origin and two walls whose
 * inner faces are width apart, reaching height above the floor. */
typedef struct kg_gen_container {
    kg_vec2 origin;
    float width;
    float height;
    float thickness;
    kg_gen_material material;
} kg_gen_container;

/* Boxes and circles of sizes in [min_size, max_size], one per cell of a grid filling
 * region from the bottom, placed and turned at random inside their cells. */
typedef struct kg_gen_rain {
    int count;
    uint32_t seed;
    kg_aabb region;
    float min_size;
    float max_size;
    kg_gen_material material;
} kg_gen_rain;

/* Particles with a circle of radius radius, on a jittered grid filling region from the
 * bottom. mass > 0 gives every particle that mass; else material.density sets it. */
typedef struct kg_gen_particles {
    int count;
    uint32_t seed;
    kg_aabb region;
    float radius;
    float mass;
    kg_gen_material material;
} kg_gen_particles;

/* Bodies are named prefix + their index within the call: "box0", "box1"... */
kg_result kg_gen_pyramid_bodies(kg_scene* scene, const char* prefix, const kg_gen_pyramid* params);
kg_result kg_gen_stack_bodies(kg_scene* scene, const char* prefix, const kg_gen_stack* params);
kg_result kg_gen_container_bodies(kg_scene* scene, const char* prefix, const kg_gen_container* params);
kg_result kg_gen_rain_bodies(kg_scene* scene, const char* prefix, const kg_gen_rain* params);
kg_result kg_gen_particle_bodies(kg_scene* scene, const char* prefix, const kg_gen_particles* params);

/* How many bodies fit in the region (the grid's cell count). */
int kg_gen_rain_capacity(const kg_gen_rain* params);
int kg_gen_particles_capacity(const kg_gen_particles* params);

/* The bodies of a benchmark scene ("large_pyramid", "many_pyramids", "smash",
 * "tumbler", "joint_grid", "ragdoll_rain"), named prefix + their role ("ground", "box",
 * "wall"...) + index, and their joints. Only the bodies and joints: gravity and step
 * count are the caller's. */
kg_result kg_gen_benchmark_bodies(kg_scene* scene, const char* prefix, const char* name);

/* The benchmark scenes with joints (scene_generate_joints.c), as above. */
kg_result kg_gen_joint_grid(kg_scene* scene, const char* prefix);
kg_result kg_gen_ragdoll_rain(kg_scene* scene, const char* prefix);

/* A body def of the given type, shape, position and material, the rest default. */
kg_body_def kg_gen_def(kg_body_type type, kg_shape_def shape, kg_vec2 position, const kg_gen_material* material);
/* Adds def named prefix + role + index (index < 0: no number). */
kg_result kg_gen_add(kg_scene* scene, const char* prefix, const char* role, int index, const kg_body_def* def);

#endif
