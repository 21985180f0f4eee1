/* KineticGyro: basic types shared by the whole public API. */
#ifndef KGYRO_TYPES_H
#define KGYRO_TYPES_H

#include <stdint.h>
#include <stddef.h>

#if defined(_WIN32) && defined(KG_BUILD_SHARED)
#define KG_API __declspec(dllexport)
#elif defined(__GNUC__)
#define KG_API __attribute__((visibility("default")))
#else
#define KG_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Every call that can fail returns one of these; kg_last_error() gives the details. */
typedef enum kg_result {
    KG_OK = 0,
    KG_ERROR_INVALID_ARGUMENT = -1, /* NaN, infinity, negative or zero where not allowed, NULL */
    KG_ERROR_INVALID_HANDLE = -2,   /* stale, destroyed or foreign handle */
    KG_ERROR_POOL_FULL = -3,        /* capacity set in kg_world_def reached */
    KG_ERROR_OUT_OF_MEMORY = -4,
    KG_ERROR_DEGENERATE_SHAPE = -5, /* polygon with no area, too many vertices, coinciding capsule ends */
    KG_ERROR_IO = -6,               /* file could not be read or written */
    KG_ERROR_PARSE = -7,            /* malformed scene or map file */
    KG_ERROR_BACKEND = -8,          /* backend unavailable or failed */
    KG_ERROR_UNSUPPORTED = -9,      /* valid request this build or backend cannot do */
    KG_ERROR_LOCKED = -10,          /* a call a callback made inside kg_world_step that the step
                                     * cannot take then: docs/queries-events.md, "Callbacks" */
    KG_ERROR_NOT_FOUND = -11        /* a look-up by name found nothing (kg_scene_body_property...) */
} kg_result;

/* A short constant name for a result code, such as "invalid handle". */
KG_API const char* kg_result_string(kg_result result);

/* The message of the last error on this thread ("" if none). Valid until the next failing call. */
KG_API const char* kg_last_error(void);

typedef struct kg_vec2 {
    float x, y;
} kg_vec2;

/* Axis-aligned bounding box. */
typedef struct kg_aabb {
    kg_vec2 lower, upper;
} kg_aabb;

/* Generational handle of a body. A handle of a destroyed body stays invalid forever,
 * even when its slot is reused, because the slot's generation moves on.
 * The all-zero handle KG_NULL_BODY is never valid. */
typedef struct kg_body {
    uint32_t index;
    uint32_t generation;
} kg_body;

#define KG_NULL_BODY_INIT {0u, 0u}

/* Handle of a registered force applicator. */
typedef struct kg_applicator {
    uint32_t index;
    uint32_t generation;
} kg_applicator;

typedef struct kg_world kg_world;

/* Hard limits of the engine. */
#define KG_MAX_POLYGON_VERTICES 8

#ifdef __cplusplus
}
#endif
#endif
