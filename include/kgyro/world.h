/* KineticGyro: creating, configuring and stepping a world. */
#ifndef KGYRO_WORLD_H
#define KGYRO_WORLD_H

#include "types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum kg_backend {
    KG_BACKEND_AUTO = 0, /* an OpenCL GPU or accelerator when one works, else the CPU (an
                          * OpenCL CPU device such as PoCL is no faster than the CPU
                          * backend, so auto never picks one); KGYRO_BACKEND overrides */
    KG_BACKEND_CPU = 1,
    KG_BACKEND_OPENCL = 2
} kg_backend;

/* Everything a world is sized and tuned by. Start from kg_default_world_def(). */
/* The most CPU worker threads a world may have (kg_world_def.threads). */
#define KG_MAX_THREADS 256

typedef struct kg_world_def {
    kg_vec2 gravity;          /* m/s^2, applied to every dynamic body and particle */
    int max_bodies;           /* pool capacity: bodies and particles together */
    int max_contacts;         /* touching or nearly touching pairs the world may hold before
                               * it warns; 0 = 4 per body. Memory follows need, not this:
                               * the contact pool starts at one slot per body (at most this
                               * many) and grows to half again what a step needs, silently up
                               * to this value, with a warning (once) past it. While a tile
                               * map is live the pool holds this many (tile contacts past it
                               * are dropped, with a warning). After creation
                               * kg_world_get_def reports the pool's current capacity. */
    int max_applicators;      /* force applicators */
    int substeps;             /* solver sub-steps per step (>= 1; default 4) */
    float contact_hertz;      /* stiffness of the soft contact constraint (default 45; capped at a
                               * quarter of the sub-step rate, docs/design.md) */
    float contact_damping_ratio;
    float max_push_out_speed; /* m/s: penetration is resolved no faster than this */
    float restitution_threshold; /* m/s: slower impacts do not bounce */
    float linear_slop;        /* m: penetration allowed, to keep contacts stable */
    float speculative_distance; /* m: contacts are reported this far before touching */
    float max_linear_speed;   /* m/s: velocities are clamped to this (numerical safety) */
    int enable_sleep;         /* islands at rest stop being simulated until touched (default 1) */
    int enable_continuous;    /* continuous collision (default 1): a dynamic body moving more
                               * than half its size in a step is swept against the static
                               * bodies and tile maps, bullets (kg_body_def.bullet) also against
                               * the other dynamic and the kinematic bodies, and stopped at the
                               * first impact (docs/design.md, the finalize stage) */
    float hit_event_threshold; /* m/s: a point that pushes after closing faster than this is
                               * a hit event (default 1; include/kgyro/events.h) */
    float sleep_speed;        /* m/s: a body whose every point is slower than this is at rest */
    float time_to_sleep;      /* s: an island whose bodies all rest this long falls asleep */
    kg_backend backend;
    int device_index;         /* OpenCL device, counted over all platforms (kgyro info lists
                               * them); KGYRO_OPENCL_DEVICE=N overrides it */
    int threads;              /* CPU worker threads, 0 to KG_MAX_THREADS; 0 = 1 */
} kg_world_def;

KG_API kg_world_def kg_default_world_def(void);

/* Creates a world; its memory is allocated here, except the contact pool, which starts
 * at one slot a body and grows inside a step when the touching pairs outgrow it. */
KG_API kg_result kg_create_world(const kg_world_def* def, kg_world** out_world);
KG_API void kg_destroy_world(kg_world* world);

/* Advances the world by dt seconds (dt > 0 and finite). */
KG_API kg_result kg_world_step(kg_world* world, float dt);

KG_API kg_result kg_world_set_gravity(kg_world* world, kg_vec2 gravity);
KG_API kg_vec2 kg_world_get_gravity(const kg_world* world);
KG_API const kg_world_def* kg_world_get_def(const kg_world* world);

/* Number of live bodies (particles included). */
KG_API int kg_world_body_count(const kg_world* world);
/* Number of bodies asleep: islands at rest that cost no integration or solving until a
 * moving body touches them or the API changes them (docs/design.md, "Sleeping"). */
KG_API int kg_world_asleep_count(const kg_world* world);
/* Writes up to capacity live body handles, in slot order; *count gets how many. */
KG_API kg_result kg_world_get_bodies(const kg_world* world, kg_body* out, int capacity, int* count);

/* The backend actually running (never KG_BACKEND_AUTO). */
KG_API kg_backend kg_world_backend(const kg_world* world);

/* Room for the stages of a step, or with OpenCL profiling for its kernels. */
#define KG_MAX_STAGE_TIMES 32
/* Names of the stages of a step and their wall-clock time in the last step, in ms; and
 * how warm starting fared in that step. A point of a contact that also touched last step
 * either found last step's point of the same features (its impulses carried over) or
 * started cold; a resting pile should carry all of them. Points of new contacts count in
 * neither. The OpenCL backend computes contacts on the device and does not count: -1. */
typedef struct kg_stage_times {
    int count;
    const char* names[KG_MAX_STAGE_TIMES];
    double ms[KG_MAX_STAGE_TIMES];
    int warm_starts_carried;
    int warm_starts_missed;
} kg_stage_times;
KG_API kg_result kg_world_get_stage_times(const kg_world* world, kg_stage_times* out);

#ifdef __cplusplus
}
#endif
#endif
