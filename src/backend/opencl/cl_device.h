/* The OpenCL devices of every platform, enumerated once per process and counted over all
 * platforms in order (that count is kg_world_def.device_index). */
#ifndef KG_CL_DEVICE_H
#define KG_CL_DEVICE_H

#include "backend/opencl/cl_loader.h"
#include "kgyro/opencl.h"

typedef struct kg_cl_device {
    cl_platform_id platform;
    cl_device_id id;
    kg_opencl_device_info info;
} kg_cl_device;

/* The devices found (count may be 0); KG_ERROR_BACKEND when OpenCL cannot be loaded. */
kg_result kg_cl_devices(const kg_cl_device** devices, int* count);

#endif
