#ifdef KG_HAVE_OPENCL
#include "backend/opencl/cl_loader.h"
#include "core/error.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static kg_cl_api g_api;
static const kg_cl_api* g_loaded;
static char g_load_error[256];
static pthread_once_t g_load_once = PTHREAD_ONCE_INIT;

static void kg_cl_load_once(void)
{
    const char* path = getenv("KGYRO_OPENCL_LIBRARY");
    if (!path || !*path) {
        path = "libOpenCL.so.1";
    }
    void* lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        snprintf(g_load_error, sizeof g_load_error, "cannot load %s: %s", path, dlerror());
        return;
    }
    /* POSIX guarantees that a function pointer round-trips through dlsym's void* */
#define KG_CL_RESOLVE(ret, name, args)                                                            \
    *(void**)(&g_api.name) = dlsym(lib, "cl" #name);                                              \
    if (!g_api.name) {                                                                            \
        snprintf(g_load_error, sizeof g_load_error, "%s has no cl%s (OpenCL 1.2 needed)", path, #name); \
        return;                                                                                   \
    }
    KG_CL_FUNCTIONS(KG_CL_RESOLVE)
#undef KG_CL_RESOLVE
    g_loaded = &g_api;
}

const kg_cl_api* kg_cl_load(void)
{
    pthread_once(&g_load_once, kg_cl_load_once);
    if (!g_loaded) {
        kg_fail(KG_ERROR_BACKEND, "OpenCL unavailable: %s", g_load_error);
    }
    return g_loaded;
}

const char* kg_cl_error_name(cl_int code)
{
    switch (code) {
#define KG_CL_CASE(c) case c: return #c;
        KG_CL_CASE(CL_SUCCESS)
        KG_CL_CASE(CL_DEVICE_NOT_FOUND)
        KG_CL_CASE(CL_DEVICE_NOT_AVAILABLE)
        KG_CL_CASE(CL_COMPILER_NOT_AVAILABLE)
        KG_CL_CASE(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        KG_CL_CASE(CL_OUT_OF_RESOURCES)
        KG_CL_CASE(CL_OUT_OF_HOST_MEMORY)
        KG_CL_CASE(CL_PROFILING_INFO_NOT_AVAILABLE)
        KG_CL_CASE(CL_BUILD_PROGRAM_FAILURE)
        KG_CL_CASE(CL_INVALID_VALUE)
        KG_CL_CASE(CL_INVALID_DEVICE)
        KG_CL_CASE(CL_INVALID_CONTEXT)
        KG_CL_CASE(CL_INVALID_COMMAND_QUEUE)
        KG_CL_CASE(CL_INVALID_MEM_OBJECT)
        KG_CL_CASE(CL_INVALID_BUILD_OPTIONS)
        KG_CL_CASE(CL_INVALID_PROGRAM_EXECUTABLE)
        KG_CL_CASE(CL_INVALID_KERNEL_NAME)
        KG_CL_CASE(CL_INVALID_KERNEL)
        KG_CL_CASE(CL_INVALID_ARG_INDEX)
        KG_CL_CASE(CL_INVALID_ARG_VALUE)
        KG_CL_CASE(CL_INVALID_ARG_SIZE)
        KG_CL_CASE(CL_INVALID_KERNEL_ARGS)
        KG_CL_CASE(CL_INVALID_WORK_GROUP_SIZE)
        KG_CL_CASE(CL_INVALID_GLOBAL_WORK_SIZE)
        KG_CL_CASE(CL_INVALID_BUFFER_SIZE)
        KG_CL_CASE(CL_INVALID_EVENT)
        case -1001: return "CL_PLATFORM_NOT_FOUND_KHR"; /* cl_ext.h: no ICD found */
#undef KG_CL_CASE
    }
    return "CL error";
}
#endif
