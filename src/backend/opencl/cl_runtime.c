#ifdef KG_HAVE_OPENCL
#include "backend/opencl/cl_runtime.h"
#include "backend/opencl/cl_sources.h"
#include "core/alloc.h"
#include "core/body_pool.h"
#include "core/error.h"

#include <pthread.h>
#include <stdio.h>
#include <string.h>

#define KG_CL_MAX_RUNTIMES 64

typedef struct kg_cl_force_program_entry {
    struct kg_cl_force_program_entry* next;
    const kg_cl_runtime* rt;
    char* source;
    char* function_name;
    cl_program program;
} kg_cl_force_program_entry;

static pthread_mutex_t g_lock = PTHREAD_MUTEX_INITIALIZER;
static kg_cl_runtime* g_runtimes[KG_CL_MAX_RUNTIMES];
static kg_cl_force_program_entry* g_force_programs;

/* Determinism: no fast-math or mad options, and correctly rounded division and square root
 * where the device offers them, so kernels compute what the C code computes. (Every
 * constant the kernels share with the host is in the shared headers they include.) */
static void kg_cl_make_options(kg_cl_runtime* rt)
{
    snprintf(rt->options, sizeof rt->options, "-cl-std=CL1.2 %s",
             rt->device->info.correctly_rounded_divide_sqrt ? "-cl-fp32-correctly-rounded-divide-sqrt" : "");
}

/* Builds lines into a program; on failure, the error names what and carries the log. */
static kg_result kg_cl_build(kg_cl_runtime* rt, const char** lines, int count, const char* extra_options,
                             kg_result code, const char* what, cl_program* out)
{
    const kg_cl_api* cl = rt->cl;
    cl_int err = CL_SUCCESS;
    cl_program program = cl->CreateProgramWithSource(rt->context, (cl_uint)count, lines, NULL, &err);
    if (!program || err != CL_SUCCESS) {
        return kg_fail(KG_ERROR_BACKEND, "OpenCL: cannot create the %s program (%s)", what, kg_cl_error_name(err));
    }
    char options[1024];
    snprintf(options, sizeof options, "%s %s", rt->options, extra_options ? extra_options : "");
    err = cl->BuildProgram(program, 1, &rt->device->id, options, NULL, NULL);
    if (err != CL_SUCCESS) {
        char log[2048] = "";
        cl->GetProgramBuildInfo(program, rt->device->id, CL_PROGRAM_BUILD_LOG, sizeof log - 1, log, NULL);
        cl->ReleaseProgram(program);
        return kg_fail(code, "OpenCL: the %s program does not build on %s (%s): %s", what,
                       rt->device->info.name, kg_cl_error_name(err), log);
    }
    *out = program;
    return KG_OK;
}

/* The step program: kg_step.cl, then the collision stage's files, the sleeping stages'
 * kg_sleep.cl and the joints' kg_joint.cl, which use its helpers (their shared headers,
 * inlined in each, are kept once by their include guards). */
static kg_result kg_cl_build_step_program(kg_cl_runtime* rt)
{
    const kg_cl_source* parts[] = {kg_cl_find_source("kg_step"),      kg_cl_find_source("kg_scan"),
                                   kg_cl_find_source("kg_broadphase"), kg_cl_find_source("kg_collide"),
                                   kg_cl_find_source("kg_color"),     kg_cl_find_source("kg_sleep"),
                                   kg_cl_find_source("kg_joint")};
    int part_count = (int)(sizeof parts / sizeof parts[0]), count = 0;
    for (int k = 0; k < part_count; ++k) {
        count += parts[k]->line_count;
    }
    const char** lines = kg_alloc_zeroed((size_t)count * sizeof *lines);
    if (!lines) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the step program's source");
    }
    for (int k = 0, at = 0; k < part_count; at += parts[k]->line_count, ++k) {
        memcpy(lines + at, parts[k]->lines, (size_t)parts[k]->line_count * sizeof *lines);
    }
    kg_result r = kg_cl_build(rt, lines, count, NULL, KG_ERROR_BACKEND, "step", &rt->step_program);
    kg_free(lines);
    return r;
}

static kg_result kg_cl_runtime_create(const kg_cl_device* device, kg_cl_runtime** out)
{
    kg_cl_runtime* rt = kg_alloc_zeroed(sizeof *rt);
    if (!rt) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the OpenCL runtime");
    }
    rt->cl = kg_cl_load();
    rt->device = device;
    kg_cl_make_options(rt);
    cl_int err = CL_SUCCESS;
    cl_context_properties props[] = {CL_CONTEXT_PLATFORM, (cl_context_properties)device->platform, 0};
    rt->context = rt->cl->CreateContext(props, 1, &device->id, NULL, NULL, &err);
    if (!rt->context || err != CL_SUCCESS) {
        kg_free(rt);
        return kg_fail(KG_ERROR_BACKEND, "OpenCL: cannot create a context on %s (%s)", device->info.name,
                       kg_cl_error_name(err));
    }
    kg_result r = kg_cl_build_step_program(rt);
    if (r != KG_OK) {
        rt->cl->ReleaseContext(rt->context);
        kg_free(rt);
        return r;
    }
    *out = rt;
    return KG_OK;
}

kg_result kg_cl_runtime_get(int device_index, int fail_build, kg_cl_runtime** out)
{
    const kg_cl_device* devices;
    int count = 0;
    kg_result r = kg_cl_devices(&devices, &count);
    if (r != KG_OK) {
        return r;
    }
    if (device_index < 0 || device_index >= count || device_index >= KG_CL_MAX_RUNTIMES) {
        return kg_fail(KG_ERROR_BACKEND, "OpenCL: no device %d (%d found)", device_index, count);
    }
    if (fail_build) {
        return kg_fail(KG_ERROR_BACKEND, "OpenCL: the step program does not build on %s "
                       "(CL_BUILD_PROGRAM_FAILURE injected by KGYRO_CL_FAIL)", devices[device_index].info.name);
    }
    pthread_mutex_lock(&g_lock);
    r = KG_OK;
    if (!g_runtimes[device_index]) {
        r = kg_cl_runtime_create(&devices[device_index], &g_runtimes[device_index]);
    }
    *out = g_runtimes[device_index];
    pthread_mutex_unlock(&g_lock);
    return r;
}

static kg_cl_force_program_entry* kg_cl_find_force_program(const kg_cl_runtime* rt, const char* source,
                                                           const char* function_name)
{
    for (kg_cl_force_program_entry* e = g_force_programs; e; e = e->next) {
        if (e->rt == rt && strcmp(e->source, source) == 0 && strcmp(e->function_name, function_name) == 0) {
            return e;
        }
    }
    return NULL;
}

static kg_result kg_cl_build_force_program(kg_cl_runtime* rt, const char* source, const char* function_name,
                                           cl_program* out)
{
    const kg_cl_source* prelude = kg_cl_find_source("kg_force");
    const char* lines[2] = {NULL, source};
    size_t total = 0;
    for (int i = 0; i < prelude->line_count; ++i) {
        total += strlen(prelude->lines[i]);
    }
    char* text = kg_alloc_zeroed(total + 1);
    if (!text) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate a device force program");
    }
    for (int i = 0, at = 0; i < prelude->line_count; ++i) {
        size_t n = strlen(prelude->lines[i]);
        memcpy(text + at, prelude->lines[i], n);
        at += (int)n;
    }
    lines[0] = text;
    char define[160];
    snprintf(define, sizeof define, "-DKG_USER_FORCE_FN=%s", function_name);
    kg_result r = kg_cl_build(rt, lines, 2, define, KG_ERROR_INVALID_ARGUMENT, "device force", out);
    kg_free(text);
    return r;
}

kg_result kg_cl_force_program(kg_cl_runtime* rt, const char* source, const char* function_name, cl_program* out)
{
    pthread_mutex_lock(&g_lock);
    kg_cl_force_program_entry* e = kg_cl_find_force_program(rt, source, function_name);
    kg_result r = KG_OK;
    if (!e) {
        e = kg_alloc_zeroed(sizeof *e);
        r = e ? KG_OK : kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate a device force program");
        if (r == KG_OK) {
            e->rt = rt;
            e->source = kg_copy_text(source);
            e->function_name = kg_copy_text(function_name);
            r = (e->source && e->function_name) ? kg_cl_build_force_program(rt, source, function_name, &e->program)
                                                : kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot copy a device force source");
        }
        if (r == KG_OK) {
            e->next = g_force_programs;
            g_force_programs = e;
        } else if (e) {
            kg_free(e->source);
            kg_free(e->function_name);
            kg_free(e);
            e = NULL;
        }
    }
    *out = e ? e->program : NULL;
    pthread_mutex_unlock(&g_lock);
    return r;
}
#endif
