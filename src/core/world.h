/* The world: pools sized once at creation, and the backend that steps them. */
#ifndef KG_WORLD_INTERNAL_H
#define KG_WORLD_INTERNAL_H

#include "core/body_pool.h"
#include "core/shape_pool.h"
#include "kgyro/collision.h"
#include "kgyro/force.h"
#include "kgyro/world.h"

typedef enum kg_applicator_kind {
    KG_APPLICATOR_FREE = 0,
    KG_APPLICATOR_USER,
    KG_APPLICATOR_GRAVITY,
    KG_APPLICATOR_WIND
} kg_applicator_kind;

typedef struct kg_applicator_slot {
    kg_applicator_kind kind;
    kg_u32 generation;
    kg_force_fn* fn;
    void* user_data;
    kg_vec2 vector;  /* gravity: acceleration; wind: unit direction */
    float strength;  /* wind force, N */
    float drag;      /* wind drag, N s/m */
    kg_body* bodies; /* NULL = all bodies */
    int body_count;
} kg_applicator_slot;

struct kg_backend_ops;
struct kg_thread_pool;
struct kg_tilemaps;
struct kg_collision;
struct kg_solver;
struct kg_sleep;
struct kg_events;
struct kg_sensors;
struct kg_query_index;
struct kg_joints;

struct kg_world {
    kg_world_def def;
    kg_body_pool bodies;
    kg_shape_pool shapes;
    kg_applicator_slot* applicators;
    kg_body* handle_scratch; /* capacity max_bodies: the body list handed to applicators */
    struct kg_collision* collision;
    struct kg_solver* solver;
    struct kg_sleep* sleep;
    struct kg_tilemaps* tilemaps;   /* NULL until a tile map is added */
    struct kg_events* events;       /* NULL until events are first asked for */
    struct kg_sensors* sensors;     /* NULL until a step with a sensor */
    int sensor_shapes_made;         /* ever: none, and a step looks for no sensor */
    struct kg_thread_pool* threads; /* CPU worker threads (NULL with one thread) */
    const struct kg_backend_ops* backend;
    void* backend_state;
    kg_stage_times times;
    float last_dt; /* of the step being taken (0 before the first): sizes speculative margins */
    kg_u32 static_edits; /* bumped when a static body or a bullet is made, removed or changed:
                          * continuous collision's list of them is then made again */
    uint64_t step_index;
    int lock; /* inside kg_world_step: KG_LOCK_STEP, and KG_LOCK_ALL while a pre-solve callback runs */
    kg_pre_solve_fn* pre_solve;
    void* pre_solve_context;
    kg_u32 pool_writes; /* bumped by every write to the body pool through the API (and a step
                         * moves step_index): the query index is made again when either moved */
    struct kg_query_index* query_index; /* NULL until the first query (collide/query_index.h) */
    struct kg_joints* joints;           /* NULL until the first joint (core/joint.h) */
};

/* What a callback inside a step may not do: change what the step is iterating over
 * (bodies, shapes, maps, applicators, another step), and inside a pre-solve callback
 * change anything at all. */
#define KG_LOCK_STEP 1
#define KG_LOCK_ALL 2

/* Whether the world refuses call now, at lock level level or above: then fails with
 * KG_ERROR_LOCKED naming call, and returns 1. */
int kg_world_refuses(const kg_world* world, const char* call, int level);

/* The pool for reading, as every getter reads it: the OpenCL backend may hold newer state
 * on the device, which this copies back first. */
const kg_body_pool* kg_world_read_pool(const kg_world* world);
/* The pool for writing, after the backend synced it (it uploads what changed). */
kg_body_pool* kg_world_write_pool(kg_world* world);
/* Wakes every sleeping body: for changes that reach them all (gravity, applicators). */
void kg_world_wake_all(kg_world* world);
/* Wakes the sleeping bodies near box: for changes of the static world there (tiles). */
void kg_world_wake_region(kg_world* world, kg_aabb box);

/* KG_OK when kg_create_world would accept def, else why not (a restored snapshot's). */
kg_result kg_world_def_check(const kg_world_def* def);

/* The slot of a live body handle, or -1 with the error set. */
int kg_world_resolve(const kg_world* world, kg_body body);

#endif
