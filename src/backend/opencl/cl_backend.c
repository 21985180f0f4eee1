/* The OpenCL backend's operations and its fallback to the CPU.
 *
 * Fallback. Any failure of an OpenCL call (or an injected one, cl_fault.h) hands the
 * world to the CPU backend, with one warning per kind of failure and process, and with
 * no state lost, which means precisely:
 *  - a failure inside a step: the state at the start of that step is read back from the
 *    checkpoint kept on the device, and the whole step is run again on the CPU; the result
 *    is the state the OpenCL step would have produced (bitwise, see docs/design.md). User
 *    force callbacks of that step may run twice.
 *  - a failure between steps (a read for a getter): the read is tried again.
 *  - if the device cannot be read at all (lost): the world continues from the last state
 *    the host had whole: the state at creation, or as of the last getter, setter or force
 *    callback, or the last fallback. Transforms and bounds are recomputed from it; the
 *    steps simulated since then are lost, and the warning says how many.
 * Contacts always live on the host (the collide stage runs there), so warm starting goes
 * on undisturbed. */
#ifdef KG_HAVE_OPENCL
#include "backend/opencl/cl_backend.h"
#include "collide/collide.h"
#include "core/alloc.h"
#include "core/error.h"

#include <stdio.h>
#include <string.h>

static kg_backend_state* kg_state(kg_world* world) { return world->backend_state; }

/* ---- fallback --------------------------------------------------------------------- */

/* The bodies frozen on the device since the host last looked: warned of as the CPU
 * backend does when it freezes one. */
static void kg_warn_new_frozen(kg_world* world, kg_cl_backend* b)
{
    const kg_body_pool* p = &world->bodies;
    int frozen = 0, first = -1;
    for (int i = 0; i < p->high_water; ++i) {
        if (kg_pool_alive(p, i) && (p->flags[i] & KG_FLAG_FROZEN)) {
            first = first < 0 ? i : first;
            frozen++;
        }
    }
    if (frozen > b->frozen_count) {
        kg_warn_once("non-finite", "body %d got a non-finite state and was frozen", first);
    }
    b->frozen_count = frozen;
}

/* Reads every state array into a scratch copy first, and into the pool only when all
 * reads succeeded, so a failing device cannot leave the pool half old and half new. */
static kg_result kg_read_whole_state(kg_world* world, kg_cl_backend* b, int from_checkpoint)
{
    kg_body_pool copy = world->bodies;
    kg_body_pool scratch;
    kg_result r = kg_body_pool_init(&scratch, world->bodies.capacity);
    if (r != KG_OK) {
        return r;
    }
    scratch.high_water = copy.high_water;
    kg_cl_world* w = b->w;
    unsigned state = kg_cl_state_arrays();
    w->forces_cleared = 0;
    w->host_stale = state;
    r = from_checkpoint ? kg_cl_read_checkpoint(w, &scratch) : kg_cl_download(w, &scratch, state);
    if (r == KG_OK) {
        size_t n = (size_t)copy.high_water;
        memcpy(copy.center, scratch.center, n * sizeof *copy.center);
        memcpy(copy.rot, scratch.rot, n * sizeof *copy.rot);
        memcpy(copy.velocity, scratch.velocity, n * sizeof *copy.velocity);
        memcpy(copy.omega, scratch.omega, n * sizeof *copy.omega);
        memcpy(copy.force, scratch.force, n * sizeof *copy.force);
        memcpy(copy.torque, scratch.torque, n * sizeof *copy.torque);
        memcpy(copy.xf, scratch.xf, n * sizeof *copy.xf);
        memcpy(copy.aabb, scratch.aabb, n * sizeof *copy.aabb);
        memcpy(copy.flags, scratch.flags, n * sizeof *copy.flags);
    }
    kg_body_pool_free(&scratch);
    return r;
}

/* The host's last whole state, made consistent: transforms and bounds from the centres. */
static void kg_rebuild_derived(kg_world* world)
{
    kg_body_pool* p = &world->bodies;
    for (int i = 0; i < p->high_water; ++i) {
        if (kg_pool_alive(p, i)) {
            kg_body_update_transform(p, i);
        }
    }
}

void kg_cl_backend_stop(kg_world* world)
{
    kg_backend_state* s = kg_state(world);
    kg_cl_backend* b = s ? s->cl : NULL;
    if (!b) {
        return;
    }
    for (int slot = 0; b->force_kernels && slot < world->def.max_applicators; ++slot) {
        kg_cl_release_device_force(b, slot);
    }
    kg_cl_world_destroy(b->w);
    kg_free(b->force_kernels);
    kg_free(b->force_params);
    kg_free(b->target_pairs);
    kg_free(b->color_input);
    kg_free(b->color_scratch);
    kg_graph_coloring_free(&b->coloring);
    kg_free(b);
    s->cl = NULL;
}

/* Hands the world to the CPU backend after the OpenCL failure described by the current
 * error. in_step: the failure happened inside a step, whose start state is wanted. */
static void kg_fall_back(kg_world* world, int in_step)
{
    char reason[512];
    snprintf(reason, sizeof reason, "%s", kg_last_error());
    kg_backend_state* s = kg_state(world);
    kg_cl_backend* b = s->cl;
    kg_result r = KG_OK;
    if (in_step && b->checkpoint_valid) {
        r = kg_read_whole_state(world, b, 1);
    } else if (b->w->host_stale != 0) {
        r = kg_read_whole_state(world, b, 0);
        if (r != KG_OK) {
            r = kg_read_whole_state(world, b, 0); /* a failed read may succeed when tried again */
        }
    }
    int lost_steps = r == KG_OK ? 0 : b->steps_since_snapshot;
    if (r != KG_OK) {
        kg_rebuild_derived(world);
    }
    kg_cl_backend_stop(world);
    kg_backend_use_cpu(world);
    if (lost_steps > 0) {
        kg_warn_once("opencl-lost", "OpenCL device lost (%s); continuing on the CPU backend from the last state "
                     "read back, %d steps earlier", reason, lost_steps);
    } else {
        kg_warn_once(in_step ? "opencl-step" : "opencl-read", "OpenCL backend failed (%s); continuing on the CPU "
                     "backend with the state intact", reason);
    }
}

/* ---- operations ------------------------------------------------------------------- */

static kg_result kg_opencl_step(kg_world* world, float dt)
{
    kg_cl_backend* b = kg_state(world)->cl;
    kg_result r = kg_cl_step(world, b, dt);
    if (r == KG_OK) {
        return KG_OK;
    }
    if (kg_state(world)->cl == b) {
        kg_fall_back(world, 1);
    }
    return world->backend->step(world, dt);
}

static kg_result kg_opencl_sync_to_host(kg_world* world)
{
    kg_cl_backend* b = kg_state(world)->cl;
    if (b->w->host_stale == 0) {
        return KG_OK;
    }
    int flags_stale = (b->w->host_stale & KG_CL_BIT(FLAGS)) != 0;
    kg_result r = kg_cl_download(b->w, &world->bodies, b->w->host_stale);
    if (r != KG_OK) {
        kg_fall_back(world, 0);
        return KG_OK;
    }
    b->steps_since_snapshot = 0;
    if (flags_stale) {
        kg_warn_new_frozen(world, b);
    }
    return KG_OK;
}

static void kg_opencl_host_changed(kg_world* world)
{
    kg_cl_backend* b = kg_state(world)->cl;
    b->w->device_stale = KG_CL_ALL_ARRAYS;
}

static void kg_opencl_destroy(kg_world* world)
{
    kg_cl_backend_stop(world);
    kg_backend_state_free(world);
}

const kg_backend_ops kg_opencl_backend = {KG_BACKEND_OPENCL, "opencl", kg_opencl_step, kg_opencl_sync_to_host,
                                          kg_opencl_host_changed, kg_opencl_destroy};

/* ---- start ------------------------------------------------------------------------ */

int kg_cl_auto_device(void)
{
    const kg_cl_device* devices;
    int count = 0;
    if (kg_cl_devices(&devices, &count) != KG_OK) {
        return -1;
    }
    for (int i = 0; i < count; ++i) {
        kg_opencl_device_type t = devices[i].info.type;
        if (devices[i].info.available && (t == KG_OPENCL_DEVICE_GPU || t == KG_OPENCL_DEVICE_ACCELERATOR)) {
            return i;
        }
    }
    return -1;
}

static kg_result kg_find_device(int device_index, kg_cl_faults* faults)
{
    if (kg_cl_fault(faults, KG_CL_FAULT_LOAD)) {
        return kg_fail(KG_ERROR_BACKEND, "OpenCL unavailable: cannot load libOpenCL.so.1 (injected by KGYRO_CL_FAIL)");
    }
    const kg_cl_device* devices;
    int count = 0;
    kg_result r = kg_cl_devices(&devices, &count);
    if (r != KG_OK) {
        return r;
    }
    if (kg_cl_fault(faults, KG_CL_FAULT_PLATFORM)) {
        count = 0;
    }
    if (count == 0) {
        return kg_fail(KG_ERROR_BACKEND, "no OpenCL platform or device found");
    }
    if (device_index >= count) {
        return kg_fail(KG_ERROR_BACKEND, "no OpenCL device %d (%d found; kgyro info lists them)", device_index, count);
    }
    return KG_OK;
}

kg_result kg_cl_backend_start(kg_world* world, int device_index)
{
    kg_cl_faults faults;
    kg_cl_faults_from_env(&faults);
    kg_result r = kg_find_device(device_index, &faults);
    kg_cl_runtime* rt = NULL;
    if (r == KG_OK) {
        r = kg_cl_runtime_get(device_index, kg_cl_fault(&faults, KG_CL_FAULT_BUILD), &rt);
    }
    kg_cl_backend* b = NULL;
    if (r == KG_OK) {
        b = kg_alloc_zeroed(sizeof *b);
        int slots = world->def.max_applicators + 1;
        if (b) {
            b->force_kernels = kg_alloc_zeroed((size_t)slots * sizeof *b->force_kernels);
            b->force_params = kg_alloc_zeroed((size_t)slots * sizeof *b->force_params);
        }
        r = (b && b->force_kernels && b->force_params) ? KG_OK
                                                        : kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the OpenCL backend");
    }
    if (b) {
        kg_state(world)->cl = b;
    }
    if (r == KG_OK) {
        r = kg_cl_world_create(world, rt, &faults, &b->w);
    }
    if (r != KG_OK) {
        kg_cl_backend_stop(world);
        return r;
    }
    world->backend = &kg_opencl_backend;
    return KG_OK;
}

/* ---- device forces ------------------------------------------------------------------ */

void kg_cl_release_device_force(kg_cl_backend* b, int slot)
{
    if (b->force_kernels[slot]) {
        b->w->cl->ReleaseKernel(b->force_kernels[slot]);
        b->force_kernels[slot] = NULL;
    }
    if (b->force_params[slot]) {
        b->w->cl->ReleaseMemObject(b->force_params[slot]);
        b->force_params[slot] = NULL;
    }
}

kg_result kg_cl_prepare_device_force(kg_world* world, kg_cl_backend* b, int slot)
{
    kg_device_force* f = &kg_state(world)->forces[slot];
    kg_cl_release_device_force(b, slot);
    cl_program program = NULL;
    kg_result r = kg_cl_force_program(b->w->rt, f->source, f->function_name, &program);
    if (r != KG_OK) {
        return r;
    }
    cl_int err = CL_SUCCESS;
    b->force_kernels[slot] = b->w->cl->CreateKernel(program, "kg_device_force", &err);
    if (!b->force_kernels[slot] || err != CL_SUCCESS) {
        b->force_kernels[slot] = NULL;
        return kg_fail(KG_ERROR_BACKEND, "OpenCL: no kernel in the device force program (%s)", kg_cl_error_name(err));
    }
    r = kg_cl_buffer(b->w, sizeof f->params, &b->force_params[slot]);
    if (r == KG_OK) {
        r = kg_cl_write(b->w, b->force_params[slot], 0, sizeof f->params, f->params, 1);
    }
    if (r != KG_OK) {
        kg_cl_release_device_force(b, slot);
        return r;
    }
    f->params_changed = 0;
    return KG_OK;
}

/* Compiles a newly registered device force on the world's device: a build error is the
 * user's (KG_ERROR_INVALID_ARGUMENT, reported to the caller); any other failure is the
 * device's, and the world falls back to the CPU, where the force runs as C. */
kg_result kg_backend_prepare_device_force(kg_world* world, int slot)
{
    kg_cl_backend* b = kg_state(world)->cl;
    if (!b) {
        return KG_OK;
    }
    kg_result r = kg_cl_prepare_device_force(world, b, slot);
    if (r == KG_OK || r == KG_ERROR_INVALID_ARGUMENT) {
        return r;
    }
    kg_fall_back(world, 0);
    return KG_OK;
}

/* ---- partial reads ------------------------------------------------------------------ */

kg_result kg_backend_read_transforms(kg_world* world, int first, int count)
{
    kg_cl_backend* b = kg_state(world)->cl;
    if (!b || !(b->w->host_stale & KG_CL_BIT(XF)) || count <= 0) {
        return KG_OK;
    }
    kg_result r = kg_cl_read(b->w, b->w->arrays[KG_CL_XF], (size_t)first * sizeof(kg_xf), (size_t)count * sizeof(kg_xf),
                             world->bodies.xf + first);
    if (r != KG_OK) {
        kg_fall_back(world, 0);
    }
    return KG_OK;
}
#endif
