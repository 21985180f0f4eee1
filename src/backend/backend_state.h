/* What a world's backend keeps besides the pools, whichever backend runs: the device
 * force applicators (their C function runs on the CPU backend, their OpenCL C source on
 * the device), the profiling switch, and the OpenCL state while the world runs there.
 * world->backend_state points to it; it outlives a fallback from OpenCL to the CPU. */
#ifndef KG_BACKEND_STATE_H
#define KG_BACKEND_STATE_H

#include "core/world.h"
#include "kgyro/opencl.h"
#include "solve/force_body.h"

/* One per applicator slot; live while its slot holds the applicator registered with it. */
typedef struct kg_device_force {
    kg_device_force_fn* cpu_fn;
    char* source;
    char* function_name;
    kg_force_params params; /* passed to the kernel by value at each launch */
} kg_device_force;

struct kg_cl_backend;

typedef struct kg_backend_state {
    kg_device_force* forces; /* max_applicators */
    int profiling;
    struct kg_cl_backend* cl; /* NULL on the CPU backend */
} kg_backend_state;

/* Allocates world->backend_state (kg_backend_select does, before starting a backend). */
kg_result kg_backend_state_create(kg_world* world);
/* Frees it, the device forces' copies included: the destroy operation of every backend. */
void kg_backend_state_free(kg_world* world);
/* Runs the world on the CPU backend from now on. */
void kg_backend_use_cpu(kg_world* world);

/* Compiles the device force in slot for the world's device when it runs on OpenCL:
 * KG_ERROR_INVALID_ARGUMENT with the build log when its source does not build; a device
 * failure makes the world fall back to the CPU and is no error of the call. */
kg_result kg_backend_prepare_device_force(kg_world* world, int slot);
/* Brings the transforms of slots [first, first + count) to the host, and nothing else. */
kg_result kg_backend_read_transforms(kg_world* world, int first, int count);

/* The applicator's C callback that runs a device force on the CPU. */
void kg_device_force_on_cpu(kg_world* world, const kg_body* bodies, int count, void* user_data);

/* The device force registered in slot, or NULL if slot holds another kind of applicator. */
kg_device_force* kg_device_force_of(kg_world* world, int slot);

#endif
