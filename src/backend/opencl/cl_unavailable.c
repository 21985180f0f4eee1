/* The device queries of kgyro/opencl.h in a build without the OpenCL backend. */
#ifndef KG_HAVE_OPENCL
#include "core/error.h"
#include "kgyro/opencl.h"

#include <stddef.h>

kg_result kg_opencl_device_count(int* count)
{
    if (count) {
        *count = 0;
    }
    return kg_fail(KG_ERROR_UNSUPPORTED, "this build of kgyro has no OpenCL backend (no OpenCL headers at build time)");
}

kg_result kg_opencl_get_device_info(int index, kg_opencl_device_info* out)
{
    (void)out;
    return kg_fail(KG_ERROR_UNSUPPORTED, "no OpenCL device %d: this build of kgyro has no OpenCL backend", index);
}
#endif
