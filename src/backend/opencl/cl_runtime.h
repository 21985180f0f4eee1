/* What a device keeps for the whole process: its context, the built step program, and the
 * built device force programs. Building takes seconds on PoCL, so it is done once per
 * device and source and shared by every world on that device; worlds own only their
 * queue, kernels and buffers. Never released: the programs live as long as the process. */
#ifndef KG_CL_RUNTIME_H
#define KG_CL_RUNTIME_H

#include "backend/opencl/cl_device.h"

typedef struct kg_cl_runtime {
    const kg_cl_api* cl;
    const kg_cl_device* device;
    cl_context context;
    cl_program step_program; /* kernels/kg_step.cl, the collision stage's and kg_sleep.cl */
    char options[768];       /* the determinism options and constants every program is built with */
} kg_cl_runtime;

/* The runtime of device index, created and built on first use. fail_build injects a
 * build failure (KGYRO_CL_FAIL=build). KG_ERROR_BACKEND with the reason (the build log
 * for a build error) when the device cannot be used. */
kg_result kg_cl_runtime_get(int device_index, int fail_build, kg_cl_runtime** out);

/* The program of a device force applicator: the force prelude, then source; built once
 * per (source, function) and runtime. KG_ERROR_INVALID_ARGUMENT with the build log when
 * the user's source does not build. */
kg_result kg_cl_force_program(kg_cl_runtime* rt, const char* source, const char* function_name,
                              cl_program* out);

#endif
