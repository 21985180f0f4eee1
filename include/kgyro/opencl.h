/* KineticGyro: the OpenCL backend's devices, device force applicators written once for
 * the CPU and the device, profiling, and partial reads of the state kept on the device.
 *
 * Every function here exists in every build; without OpenCL support compiled in, the
 * device queries return KG_ERROR_UNSUPPORTED and device force applicators run their C
 * function on the CPU backend. */
#ifndef KGYRO_OPENCL_H
#define KGYRO_OPENCL_H

#include "types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- devices ---------------------------------------------------------------------- */

typedef enum kg_opencl_device_type {
    KG_OPENCL_DEVICE_OTHER = 0,
    KG_OPENCL_DEVICE_CPU = 1,
    KG_OPENCL_DEVICE_GPU = 2,
    KG_OPENCL_DEVICE_ACCELERATOR = 3
} kg_opencl_device_type;

typedef struct kg_opencl_device_info {
    int index;                 /* kg_world_def.device_index: counted over all platforms */
    int platform_index;
    char platform_name[128];
    char platform_version[128];
    char name[128];
    char vendor[128];
    char version[128];         /* OpenCL version the device supports */
    char driver_version[64];
    kg_opencl_device_type type;
    int compute_units;
    int max_clock_mhz;
    uint64_t global_memory;    /* bytes */
    uint64_t max_allocation;   /* bytes, largest single buffer */
    uint64_t local_memory;     /* bytes per work-group */
    size_t max_work_group_size;
    int correctly_rounded_divide_sqrt; /* needed for results bitwise equal to the CPU's */
    int available;
} kg_opencl_device_info;

/* How many OpenCL devices the process sees (0 with no platform). KG_ERROR_UNSUPPORTED
 * when the backend is not compiled in; KG_ERROR_BACKEND when libOpenCL.so.1 cannot be
 * loaded (kg_last_error() says why). */
KG_API kg_result kg_opencl_device_count(int* count);
KG_API kg_result kg_opencl_get_device_info(int index, kg_opencl_device_info* out);

/* ---- device force applicators ----------------------------------------------------- */

/* What a device force function sees of one body, and adds its force to. */
typedef struct kg_force_body {
    kg_vec2 position;        /* centre of mass, world frame */
    kg_vec2 rotation;        /* (cos, sin) of the body's angle */
    kg_vec2 velocity;        /* of the centre of mass */
    float angular_velocity;
    float mass;
    float inertia;           /* about the centre of mass */
    float torque;            /* in: accumulated so far this step; out: add to it */
    kg_vec2 force;           /* in: accumulated so far this step; out: add to it */
    uint32_t index;          /* the body's slot (kg_body.index) */
    uint32_t pad;
} kg_force_body;

#define KG_DEVICE_FORCE_MAX_PARAMS 16

/* The signature of a device force function, the same in C and in OpenCL C:
 *     void my_force(kg_force_body* body, const float* params)
 * It is called once per target body per step, in the force stage, in registration order
 * with the other applicators; it may read the body and params and must change only
 * body->force and body->torque. On the device it is compiled after the engine's prelude,
 * which defines kg_force_body, kg_vec2 and the kg_math.h helpers (kg_add, kg_scale,
 * kg_dot, kg_length, ...); sqrtf, fabsf, fminf and fmaxf work on both sides. */
typedef void kg_device_force_fn(kg_force_body* body, const float* params);

typedef struct kg_device_force_def {
    const char* source;          /* OpenCL C source defining function_name */
    const char* function_name;
    kg_device_force_fn* cpu_fn;  /* the same function compiled as C: runs on the CPU backend,
                                    and after a fallback from the device. Required. */
    float params[KG_DEVICE_FORCE_MAX_PARAMS];
    int param_count;
    const kg_body* bodies;       /* NULL with body_count 0: every body, those created later too */
    int body_count;
} kg_device_force_def;

KG_API kg_device_force_def kg_default_device_force_def(void);

/* Registers a force applicator given as OpenCL C source (compiled into the device
 * pipeline when the world runs on OpenCL: a build error fails this call with the build
 * log in kg_last_error()) and as a C function (run on the CPU backend). It is removed
 * with kg_remove_applicator like any applicator. */
KG_API kg_result kg_add_device_force_applicator(kg_world* world, const kg_device_force_def* def,
                                                kg_applicator* out);
/* Replaces the parameters of a device force applicator, from the next step on. */
KG_API kg_result kg_set_device_force_params(kg_world* world, kg_applicator applicator, const float* params,
                                            int count);

/* Defines a device force function once: a static C function NAME and the string
 * NAME_source holding the same code for the device. The body, in braces, uses the
 * parameters `body` and `params` and must compile both as C and as OpenCL C: the public
 * C API has no vector helpers, so write the arithmetic on .x and .y, and use no
 * preprocessor directive. Compile the C side with -ffp-contract=off (the default of the
 * ISO C modes) for results bitwise equal to the device's.
 *     KG_DEVICE_FORCE(spring, {
 *         body->force.x -= params[0] * body->position.x;
 *         body->force.y -= params[0] * body->position.y;
 *     })
 *     def.source = spring_source; def.function_name = "spring"; def.cpu_fn = spring; */
#define KG_DEVICE_FORCE(NAME, ...)                                                        \
    static void NAME(kg_force_body* body, const float* params) __VA_ARGS__                 \
    static const char NAME##_source[] =                                                   \
        "void " #NAME "(kg_force_body* body, const float* params) " #__VA_ARGS__ "\n";

/* ---- profiling and partial reads ---------------------------------------------------- */

/* Per-kernel timings. When on (or with KGYRO_PROFILE=1 in the environment), an OpenCL
 * world times every kernel with profiling events and kg_world_get_stage_times() gives one
 * entry per kernel name (device time summed over the step, ms; the collide stage's
 * kernels summed per stage: kg_broadphase, kg_narrowphase, kg_color) and one per stage
 * run on the host ("collide (host)" while the world has a tile map). When off, it gives
 * the host's wall-clock time of each stage. The CPU backend always gives its stage
 * times. */
KG_API kg_result kg_world_set_profiling(kg_world* world, int enabled);

/* The origin positions and angles (radians) of count bodies. An OpenCL world copies from
 * the device only the transforms of the slot range the handles span, in one read, not
 * the whole state: the cheap way to feed a renderer. */
KG_API kg_result kg_world_get_transforms(const kg_world* world, const kg_body* bodies, int count,
                                         kg_vec2* positions, float* angles);

/* What a world copied between the host and its device since it was created (zeros on
 * the CPU backend): to check that reads copy only what they must. */
typedef struct kg_transfer_stats {
    uint64_t bytes_to_device;
    uint64_t bytes_to_host;
    int writes;
    int reads;
} kg_transfer_stats;
KG_API kg_result kg_world_get_transfer_stats(const kg_world* world, kg_transfer_stats* out);

#ifdef __cplusplus
}
#endif
#endif
