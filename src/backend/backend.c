/* Backend selection, and what every backend shares: the backend state (device forces,
 * profiling switch), stage-time profiling and partial transform reads.
 *
 *   KGYRO_BACKEND=cpu | opencl | opencl:N | auto   overrides kg_world_def.backend
 *                                                   (and device_index with opencl:N)
 *   KGYRO_OPENCL_DEVICE=N                           overrides device_index alone: the
 *                                                   device of the worlds that ask for
 *                                                   OpenCL (a test's CPU world stays one)
 *   cpu     the CPU backend
 *   opencl  OpenCL device device_index (any type, PoCL's CPU device included); if it
 *           cannot be used, the CPU backend with one warning
 *   auto    the first OpenCL GPU or accelerator, silently the CPU backend when there is
 *           none: an OpenCL CPU device is no faster than the CPU backend */
#include "backend/backend.h"
#include "backend/backend_state.h"
#include "core/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifdef KG_HAVE_OPENCL
#include "backend/opencl/cl_backend.h"
#endif

void kg_backend_use_cpu(kg_world* world) { world->backend = &kg_cpu_backend; }

/* The backend asked for, and the device index for OpenCL. */
static kg_backend kg_requested_backend(const kg_world_def* def, int* device_index)
{
    const char* env = getenv("KGYRO_BACKEND");
    const char* device = getenv("KGYRO_OPENCL_DEVICE");
    *device_index = def->device_index;
    if (device && *device) {
        char* end = NULL;
        long n = strtol(device, &end, 10);
        if (*end == '\0' && n >= 0 && n < 1000) {
            *device_index = (int)n;
        } else {
            kg_warn_once("device-env", "KGYRO_OPENCL_DEVICE=%s is not a device number; ignored", device);
        }
    }
    if (env && strcmp(env, "cpu") == 0) {
        return KG_BACKEND_CPU;
    }
    if (env && strncmp(env, "opencl", 6) == 0 && (env[6] == '\0' || env[6] == ':')) {
        if (env[6] == ':') {
            *device_index = atoi(env + 7);
        }
        return KG_BACKEND_OPENCL;
    }
    if (env && strcmp(env, "auto") == 0) {
        return KG_BACKEND_AUTO;
    }
    if (env && *env) {
        kg_warn_once("backend-env", "KGYRO_BACKEND=%s is not cpu, opencl, opencl:N or auto; ignored", env);
    }
    return def->backend;
}

#ifdef KG_HAVE_OPENCL
static void kg_start_opencl(kg_world* world, kg_backend wanted, int device_index)
{
    if (wanted == KG_BACKEND_AUTO) {
        device_index = kg_cl_auto_device();
        if (device_index < 0) {
            return;
        }
    }
    if (kg_cl_backend_start(world, device_index) != KG_OK) {
        kg_warn_once("opencl-start", "the OpenCL backend cannot start (%s); using the CPU backend", kg_last_error());
        kg_clear_error();
    }
}
#else
static void kg_start_opencl(kg_world* world, kg_backend wanted, int device_index)
{
    (void)world;
    (void)device_index;
    if (wanted == KG_BACKEND_OPENCL) {
        kg_warn_once("no-opencl", "the OpenCL backend is not available in this build; using the CPU backend");
    }
}

kg_result kg_backend_prepare_device_force(kg_world* world, int slot)
{
    (void)world;
    (void)slot;
    return KG_OK;
}

kg_result kg_backend_read_transforms(kg_world* world, int first, int count)
{
    (void)world;
    (void)first;
    (void)count;
    return KG_OK;
}
#endif

kg_result kg_world_get_transfer_stats(const kg_world* world, kg_transfer_stats* out)
{
    if (!world || !out) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_world_get_transfer_stats: NULL argument");
    }
    memset(out, 0, sizeof *out);
#ifdef KG_HAVE_OPENCL
    const kg_backend_state* s = world->backend_state;
    if (s && s->cl) {
        *out = s->cl->transfers;
    }
#endif
    return KG_OK;
}

kg_result kg_backend_select(kg_world* world)
{
    kg_result r = kg_backend_state_create(world);
    if (r != KG_OK) {
        return r;
    }
    kg_backend_use_cpu(world);
    int device_index = 0;
    kg_backend wanted = kg_requested_backend(&world->def, &device_index);
    if (wanted != KG_BACKEND_CPU) {
        kg_start_opencl(world, wanted, device_index);
    }
    return KG_OK;
}

kg_result kg_world_set_profiling(kg_world* world, int enabled)
{
    if (!world || !world->backend_state) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_world_set_profiling: NULL world");
    }
    ((kg_backend_state*)world->backend_state)->profiling = enabled != 0;
    return KG_OK;
}

/* The slot range [first, last] the handles span; KG_ERROR_INVALID_HANDLE for a dead one. */
static kg_result kg_slot_span(const kg_world* world, const kg_body* bodies, int count, int* first, int* last)
{
    *first = world->bodies.capacity;
    *last = -1;
    for (int k = 0; k < count; ++k) {
        if (!kg_body_is_valid(world, bodies[k])) {
            return kg_fail(KG_ERROR_INVALID_HANDLE, "body handle {%u, %u} is stale or invalid", bodies[k].index,
                           bodies[k].generation);
        }
        int i = (int)bodies[k].index;
        *first = i < *first ? i : *first;
        *last = i > *last ? i : *last;
    }
    return KG_OK;
}

kg_result kg_world_get_transforms(const kg_world* world, const kg_body* bodies, int count, kg_vec2* positions,
                                  float* angles)
{
    if (!world || count < 0 || (count > 0 && (!bodies || !positions || !angles))) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_world_get_transforms: bad arguments");
    }
    int first = 0, last = -1;
    kg_result r = kg_slot_span(world, bodies, count, &first, &last);
    if (r != KG_OK) {
        return r;
    }
    kg_world* w = (kg_world*)world; /* reading back is no change of the world */
    kg_backend_read_transforms(w, first, last - first + 1);
    for (int k = 0; k < count; ++k) {
        kg_xf xf = world->bodies.xf[bodies[k].index];
        positions[k] = xf.p;
        angles[k] = atan2f(xf.q.s, xf.q.c);
    }
    return KG_OK;
}
