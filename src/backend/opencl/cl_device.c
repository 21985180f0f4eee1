#ifdef KG_HAVE_OPENCL
#include "backend/opencl/cl_device.h"
#include "core/error.h"

#include <pthread.h>
#include <string.h>

#define KG_CL_MAX_PLATFORMS 16
#define KG_CL_MAX_DEVICES 64

static kg_cl_device g_devices[KG_CL_MAX_DEVICES];
static int g_device_count;
static pthread_once_t g_enumerate_once = PTHREAD_ONCE_INIT;

static void kg_cl_text(const kg_cl_api* cl, cl_device_id device, cl_device_info what, char* out, size_t size)
{
    out[0] = '\0';
    if (cl->GetDeviceInfo(device, what, size - 1, out, NULL) != CL_SUCCESS) {
        out[0] = '\0';
    }
    out[size - 1] = '\0';
}

/* A scalar device property, 0 when the query fails. */
static uint64_t kg_cl_number(const kg_cl_api* cl, cl_device_id device, cl_device_info what, size_t size)
{
    uint64_t value = 0;
    unsigned char bytes[8] = {0};
    if (cl->GetDeviceInfo(device, what, size, bytes, NULL) == CL_SUCCESS) {
        if (size == sizeof(cl_uint)) {
            cl_uint v;
            memcpy(&v, bytes, sizeof v);
            value = v;
        } else {
            memcpy(&value, bytes, sizeof value);
        }
    }
    return value;
}

static kg_opencl_device_type kg_cl_type(cl_device_type t)
{
    if (t & CL_DEVICE_TYPE_GPU) {
        return KG_OPENCL_DEVICE_GPU;
    }
    if (t & CL_DEVICE_TYPE_ACCELERATOR) {
        return KG_OPENCL_DEVICE_ACCELERATOR;
    }
    return (t & CL_DEVICE_TYPE_CPU) ? KG_OPENCL_DEVICE_CPU : KG_OPENCL_DEVICE_OTHER;
}

static void kg_cl_describe(const kg_cl_api* cl, kg_cl_device* d)
{
    kg_opencl_device_info* info = &d->info;
    kg_cl_text(cl, d->id, CL_DEVICE_NAME, info->name, sizeof info->name);
    kg_cl_text(cl, d->id, CL_DEVICE_VENDOR, info->vendor, sizeof info->vendor);
    kg_cl_text(cl, d->id, CL_DEVICE_VERSION, info->version, sizeof info->version);
    kg_cl_text(cl, d->id, CL_DRIVER_VERSION, info->driver_version, sizeof info->driver_version);
    info->type = kg_cl_type((cl_device_type)kg_cl_number(cl, d->id, CL_DEVICE_TYPE, sizeof(cl_device_type)));
    info->compute_units = (int)kg_cl_number(cl, d->id, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof(cl_uint));
    info->max_clock_mhz = (int)kg_cl_number(cl, d->id, CL_DEVICE_MAX_CLOCK_FREQUENCY, sizeof(cl_uint));
    info->global_memory = kg_cl_number(cl, d->id, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof(cl_ulong));
    info->max_allocation = kg_cl_number(cl, d->id, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof(cl_ulong));
    info->local_memory = kg_cl_number(cl, d->id, CL_DEVICE_LOCAL_MEM_SIZE, sizeof(cl_ulong));
    info->max_work_group_size = (size_t)kg_cl_number(cl, d->id, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof(size_t));
    cl_device_fp_config fp = (cl_device_fp_config)kg_cl_number(cl, d->id, CL_DEVICE_SINGLE_FP_CONFIG,
                                                               sizeof(cl_device_fp_config));
    info->correctly_rounded_divide_sqrt = (fp & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) != 0;
    info->available = kg_cl_number(cl, d->id, CL_DEVICE_AVAILABLE, sizeof(cl_bool)) != 0;
}

static void kg_cl_add_platform(const kg_cl_api* cl, cl_platform_id platform, int platform_index)
{
    cl_device_id ids[KG_CL_MAX_DEVICES];
    cl_uint n = 0;
    if (cl->GetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, KG_CL_MAX_DEVICES, ids, &n) != CL_SUCCESS) {
        return; /* a platform without devices reports CL_DEVICE_NOT_FOUND */
    }
    char name[128] = "", version[128] = "";
    cl->GetPlatformInfo(platform, CL_PLATFORM_NAME, sizeof name - 1, name, NULL);
    cl->GetPlatformInfo(platform, CL_PLATFORM_VERSION, sizeof version - 1, version, NULL);
    for (cl_uint k = 0; k < n && k < KG_CL_MAX_DEVICES && g_device_count < KG_CL_MAX_DEVICES; ++k) {
        kg_cl_device* d = &g_devices[g_device_count];
        d->platform = platform;
        d->id = ids[k];
        d->info.index = g_device_count;
        d->info.platform_index = platform_index;
        memcpy(d->info.platform_name, name, sizeof name);
        memcpy(d->info.platform_version, version, sizeof version);
        kg_cl_describe(cl, d);
        g_device_count += 1;
    }
}

static void kg_cl_enumerate(void)
{
    const kg_cl_api* cl = kg_cl_load();
    cl_platform_id platforms[KG_CL_MAX_PLATFORMS];
    cl_uint n = 0;
    if (!cl || cl->GetPlatformIDs(KG_CL_MAX_PLATFORMS, platforms, &n) != CL_SUCCESS) {
        return; /* no ICD installed: CL_PLATFORM_NOT_FOUND_KHR */
    }
    for (cl_uint p = 0; p < n && p < KG_CL_MAX_PLATFORMS; ++p) {
        kg_cl_add_platform(cl, platforms[p], (int)p);
    }
}

kg_result kg_cl_devices(const kg_cl_device** devices, int* count)
{
    *devices = g_devices;
    *count = 0;
    if (!kg_cl_load()) {
        return KG_ERROR_BACKEND;
    }
    pthread_once(&g_enumerate_once, kg_cl_enumerate);
    *count = g_device_count;
    return KG_OK;
}

kg_result kg_opencl_device_count(int* count)
{
    if (!count) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_opencl_device_count: NULL argument");
    }
    const kg_cl_device* devices;
    return kg_cl_devices(&devices, count);
}

kg_result kg_opencl_get_device_info(int index, kg_opencl_device_info* out)
{
    const kg_cl_device* devices;
    int count = 0;
    if (!out) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_opencl_get_device_info: NULL argument");
    }
    kg_result r = kg_cl_devices(&devices, &count);
    if (r != KG_OK) {
        return r;
    }
    if (index < 0 || index >= count) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "OpenCL device %d does not exist (%d found)", index, count);
    }
    *out = devices[index].info;
    return KG_OK;
}
#endif
