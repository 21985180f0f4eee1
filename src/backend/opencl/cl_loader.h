/* libOpenCL loaded at run time: the core library links nothing but libc and libm, and a
 * machine without OpenCL runs the CPU backend. The entry points the backend uses are
 * resolved once per process into kg_cl; the library is never unloaded (ICDs such as
 * PoCL do not survive being unloaded and loaded again). */
#ifndef KG_CL_LOADER_H
#define KG_CL_LOADER_H

#include <CL/cl.h>

#include "kgyro/types.h"

#define KG_CL_FUNCTIONS(X)                                                                                        \
    X(cl_int, GetPlatformIDs, (cl_uint, cl_platform_id*, cl_uint*))                                                \
    X(cl_int, GetPlatformInfo, (cl_platform_id, cl_platform_info, size_t, void*, size_t*))                         \
    X(cl_int, GetDeviceIDs, (cl_platform_id, cl_device_type, cl_uint, cl_device_id*, cl_uint*))                    \
    X(cl_int, GetDeviceInfo, (cl_device_id, cl_device_info, size_t, void*, size_t*))                               \
    X(cl_context, CreateContext,                                                                                   \
      (const cl_context_properties*, cl_uint, const cl_device_id*,                                                 \
       void(CL_CALLBACK*)(const char*, const void*, size_t, void*), void*, cl_int*))                              \
    X(cl_int, ReleaseContext, (cl_context))                                                                        \
    X(cl_command_queue, CreateCommandQueue, (cl_context, cl_device_id, cl_command_queue_properties, cl_int*))       \
    X(cl_int, ReleaseCommandQueue, (cl_command_queue))                                                             \
    X(cl_program, CreateProgramWithSource, (cl_context, cl_uint, const char**, const size_t*, cl_int*))            \
    X(cl_int, BuildProgram,                                                                                        \
      (cl_program, cl_uint, const cl_device_id*, const char*, void(CL_CALLBACK*)(cl_program, void*), void*))      \
    X(cl_int, GetProgramBuildInfo, (cl_program, cl_device_id, cl_program_build_info, size_t, void*, size_t*))      \
    X(cl_int, ReleaseProgram, (cl_program))                                                                        \
    X(cl_kernel, CreateKernel, (cl_program, const char*, cl_int*))                                                 \
    X(cl_int, ReleaseKernel, (cl_kernel))                                                                          \
    X(cl_int, SetKernelArg, (cl_kernel, cl_uint, size_t, const void*))                                             \
    X(cl_int, GetKernelInfo, (cl_kernel, cl_kernel_info, size_t, void*, size_t*))                                  \
    X(cl_int, GetKernelWorkGroupInfo, (cl_kernel, cl_device_id, cl_kernel_work_group_info, size_t, void*, size_t*)) \
    X(cl_mem, CreateBuffer, (cl_context, cl_mem_flags, size_t, void*, cl_int*))                                    \
    X(cl_int, ReleaseMemObject, (cl_mem))                                                                          \
    X(cl_int, EnqueueWriteBuffer,                                                                                  \
      (cl_command_queue, cl_mem, cl_bool, size_t, size_t, const void*, cl_uint, const cl_event*, cl_event*))      \
    X(cl_int, EnqueueReadBuffer,                                                                                   \
      (cl_command_queue, cl_mem, cl_bool, size_t, size_t, void*, cl_uint, const cl_event*, cl_event*))            \
    X(cl_int, EnqueueCopyBuffer,                                                                                   \
      (cl_command_queue, cl_mem, cl_mem, size_t, size_t, size_t, cl_uint, const cl_event*, cl_event*))            \
    X(cl_int, EnqueueNDRangeKernel,                                                                                \
      (cl_command_queue, cl_kernel, cl_uint, const size_t*, const size_t*, const size_t*, cl_uint,                 \
       const cl_event*, cl_event*))                                                                                \
    X(cl_int, Finish, (cl_command_queue))                                                                          \
    X(cl_int, GetEventProfilingInfo, (cl_event, cl_profiling_info, size_t, void*, size_t*))                        \
    X(cl_int, ReleaseEvent, (cl_event))

typedef struct kg_cl_api {
#define KG_CL_POINTER(ret, name, args) ret(CL_API_CALL* name) args;
    KG_CL_FUNCTIONS(KG_CL_POINTER)
#undef KG_CL_POINTER
} kg_cl_api;

/* The loaded entry points, or NULL with the error set (KG_ERROR_BACKEND) when
 * libOpenCL.so.1 (or $KGYRO_OPENCL_LIBRARY) cannot be loaded or lacks one of them. */
const kg_cl_api* kg_cl_load(void);

/* The name of an OpenCL error code, such as "CL_OUT_OF_RESOURCES". */
const char* kg_cl_error_name(cl_int code);

#endif
