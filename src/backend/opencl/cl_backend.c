/* The OpenCL backend's operations and its fallback to the CPU.
 *
 * Fallback. Any failure of an OpenCL call (or an injected one, cl_fault.h) hands the
 * world to the CPU backend, with one warning per kind of failure and process, and with
 * no state lost, which means precisely:
 *  - a failure inside a step: the state at the start of that step is read back from the
 *    checkpoint kept on the device, and the whole step is run again on the CPU; the result
 *    is the state the OpenCL step would have produced (bitwise: test_opencl_fallback). User
 *    force callbacks of that step may run twice.
 *  - a failure between steps (a read for a getter): the read is tried again. (A getter
 *    called by a force callback reads inside a step: that is a failure inside a step.)
 *  - if the device cannot be read at all (lost): the world continues from the last state
 *    the host read back whole: the state at creation, or as of the last getter or setter
 *    (a force callback's included), as read (transforms and bounds are recomputed only
 *    when a partial read left them newer than the rest), and, inside a step, the forces
 *    the step began with. The steps simulated on the device since are lost, and the
 *    warning says how many.
 * Contacts live on the device and are read back only when asked for (sync_contacts). A
 * fallback reads last step's back first (tried twice), so warm starting goes on
 * undisturbed; when the device cannot be read, the world goes on with no contacts, and
 * the first step after warm starts from zero.
 *
 * When. A fallback takes effect at once between steps, and at the end of the step inside
 * one. The step's own failures unwind it (KG_TRY) to kg_opencl_end_step; a failure the step
 * cannot see, of a read for a getter (or a transform read, a device force's build) that a
 * force callback calls, only records that a fallback is wanted, with its message
 * (kg_cl_request_fallback); the callback's later getters answer from the host's copy
 * without calling the device (the values of the last read, or of the part of the failed
 * one that arrived), and once the callback returns the step unwinds with KG_ERROR_BACKEND,
 * calling the device no more. Then, and only then, kg_opencl_end_step reads the state back,
 * stops the OpenCL backend and redoes the step on the CPU: nothing is freed while the step
 * uses it (test_callback_forces_fallback_mid_step, under ASan). */
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
void kg_cl_warn_new_frozen(kg_world* world, kg_cl_backend* b)
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

kg_result kg_cl_flags_to_host(kg_world* world, kg_cl_backend* b)
{
    int stale = (b->host_stale & KG_CL_BIT(FLAGS)) != 0;
    KG_TRY(kg_cl_to_host(b, &world->bodies, KG_CL_BIT(FLAGS)));
    if (stale) {
        kg_cl_warn_new_frozen(world, b);
    }
    return KG_OK;
}

/* Copies the state arrays (what a step changes) of slots [0, high_water) from one pool
 * to another. */
static void kg_copy_state(kg_body_pool* to, const kg_body_pool* from)
{
    size_t n = (size_t)from->high_water;
#define KG_CL_COPY_STATE(name, member, is_state)                          \
    if (is_state) {                                                       \
        memcpy(to->member, from->member, n * sizeof *to->member);         \
    }
    KG_CL_BODY_ARRAYS(KG_CL_COPY_STATE)
#undef KG_CL_COPY_STATE
}

/* Reads every state array into snapshot: from the checkpoint (the state at the start of
 * the step) or from the current buffers. */
static kg_result kg_read_state(kg_cl_backend* b, int from_checkpoint, kg_body_pool* snapshot)
{
    unsigned state = kg_cl_state_arrays();
    b->forces_cleared = 0;
    b->host_stale = state;
    return from_checkpoint ? kg_cl_read_checkpoint(b, snapshot) : kg_cl_download(b, snapshot, state);
}

/* The host's own copy when the device cannot be read, and inside a step the forces as
 * they were when it began (drag only ever comes from the step's applicators: none).
 * whole: every state array but the forces was read back since the device last changed
 * it, so the copy is the device's state as it stands, bounds included: those finalize
 * swept over the last step's motion, which the collide stage pairs from (recomputed, they
 * miss the pairs a body is about to reach). Else the arrays may come from different reads
 * (a partial one, of the transforms, or one that failed part way), and transforms and
 * bounds are recomputed from the centres. */
static void kg_host_state(kg_world* world, kg_cl_backend* b, int in_step, int whole, kg_body_pool* snapshot)
{
    kg_body_pool* p = &world->bodies;
    for (int i = 0; i < p->high_water && !whole; ++i) {
        if (kg_pool_alive(p, i)) {
            kg_body_update_transform(p, i); /* needs the shapes, which only the world's pool has */
        }
    }
    kg_copy_state(snapshot, p);
    for (int i = 0; i < snapshot->high_water; ++i) {
        if (kg_pool_alive(snapshot, i) && in_step) {
            snapshot->force[i] = b->start_forces_saved ? b->start_force[i] : kg_v2(0.0f, 0.0f);
            snapshot->torque[i] = b->start_forces_saved ? b->start_torque[i] : 0.0f;
            snapshot->drag[i] = 0.0f;
        }
    }
}

/* The state the CPU backend goes on from (see the top of this file), into snapshot, a
 * pool sharing the world's properties. Returns 0 when the device could not be read. */
static int kg_recover_state(kg_world* world, kg_cl_backend* b, int in_step, kg_body_pool* snapshot)
{
    unsigned forces = KG_CL_BIT(FORCE) | KG_CL_BIT(TORQUE) | KG_CL_BIT(DRAG);
    int whole = (b->host_stale & ~forces) == 0; /* before a read marks every array stale */
    kg_result r = KG_OK;
    if (in_step && b->checkpoint_valid) {
        r = kg_read_state(b, 1, snapshot);
    } else if (b->host_stale != 0) {
        r = kg_read_state(b, 0, snapshot);
        if (r != KG_OK) {
            r = kg_read_state(b, 0, snapshot); /* a failed read may succeed when tried again */
        }
    } else {
        kg_copy_state(snapshot, &world->bodies);
    }
    if (r != KG_OK) {
        kg_host_state(world, b, in_step, whole, snapshot);
    }
    return r == KG_OK;
}

void kg_cl_backend_stop(kg_world* world)
{
    kg_backend_state* s = kg_state(world);
    kg_cl_backend* b = s ? s->cl : NULL;
    if (!b) {
        return;
    }
    kg_cl_drain(b);
    for (int slot = 0; b->force_kernels && slot <= world->def.max_applicators; ++slot) {
        kg_cl_release_device_force(b, slot);
    }
    kg_cl_close_device(b);
    kg_free(b->force_kernels);
    kg_free(b->force_group_sizes);
    kg_free(b->start_force);
    kg_free(b->start_torque);
    kg_free(b->host_targets);
    kg_free(b->color_scratch);
    kg_graph_coloring_free(&b->coloring);
    kg_free(b);
    s->cl = NULL;
}

/* Last step's contacts into the host's list, which the CPU backend goes on from, or none
 * when the device cannot be read. Returns 0 then. */
static int kg_recover_contacts(kg_world* world, kg_cl_backend* b)
{
    if (kg_cl_read_contacts(world, b) == KG_OK || kg_cl_read_contacts(world, b) == KG_OK) {
        return 1;
    }
    kg_collision_set_count(world, 0, 0);
    return 0;
}

void kg_cl_request_fallback(kg_cl_backend* b)
{
    if (!b->fallback_pending) {
        snprintf(b->fallback_reason, sizeof b->fallback_reason, "%s", kg_last_error());
        b->fallback_pending = 1;
    }
}

/* Hands the world to the CPU backend after the OpenCL failure described by the pending
 * request, else by the current error. in_step: the failure happened inside a step, whose
 * start state is wanted; called only once the step has unwound (kg_opencl_end_step), so that
 * nothing it frees is in use, and the start state can go straight into the world's pool
 * (no callback is running any more to write forces over it). */
static void kg_fall_back(kg_world* world, int in_step)
{
    kg_backend_state* s = kg_state(world);
    kg_cl_backend* b = s->cl;
    char reason[sizeof b->fallback_reason];
    snprintf(reason, sizeof reason, "%s", b->fallback_pending ? b->fallback_reason : kg_last_error());
    kg_body_pool* snapshot = kg_alloc_zeroed(sizeof *snapshot);
    if (!snapshot || kg_body_pool_init(snapshot, world->bodies.capacity) != KG_OK) {
        kg_free(snapshot);
        kg_cl_backend_stop(world);
        kg_backend_use_cpu(world);
        kg_warn_once("opencl-oom", "OpenCL backend failed (%s) and no memory is left to read its state back; "
                     "continuing on the CPU backend from the host's copy", reason);
        return;
    }
    snapshot->high_water = world->bodies.high_water;
    int recovered = kg_recover_state(world, b, in_step, snapshot);
    int contacts_recovered = kg_recover_contacts(world, b);
    if (kg_cl_tile_state_to_host(world, b) != KG_OK) {
        kg_cl_tile_state_to_host(world, b); /* tried twice; else one-way platforms go on from older origins */
    }
    int lost_steps = recovered ? 0 : b->steps_since_snapshot;
    kg_copy_state(&world->bodies, snapshot);
    kg_body_pool_free(snapshot);
    kg_free(snapshot);
    kg_cl_backend_stop(world);
    kg_backend_use_cpu(world);
    if (!recovered || !contacts_recovered) {
        kg_warn_once("opencl-lost", "OpenCL device lost (%s); continuing on the CPU backend from the last state "
                     "read back (%d steps simulated since then are lost%s)", reason, lost_steps,
                     contacts_recovered ? "" : ", and the contacts: warm starting restarts");
    } else {
        kg_warn_once(in_step ? "opencl-step" : "opencl-read", "OpenCL backend failed (%s); continuing on the CPU "
                     "backend with the state intact", reason);
    }
}

/* ---- operations ------------------------------------------------------------------- */

static kg_result kg_opencl_begin_step(kg_world* world, float dt)
{
    (void)dt;
    return kg_cl_begin_step(world, kg_state(world)->cl);
}

static kg_result kg_opencl_run_stage(kg_world* world, kg_stage stage, float dt)
{
    return kg_cl_run_stage(world, kg_state(world)->cl, stage, dt);
}

static const char* kg_opencl_stage_label(const kg_world* world, kg_stage stage)
{
    return kg_cl_stage_label(world, ((const kg_backend_state*)world->backend_state)->cl, stage);
}

/* The one place a step falls back: once its stages have unwound, whatever failed in them;
 * the step is then run again, on the CPU, from its start. */
static kg_result kg_opencl_end_step(kg_world* world, kg_result stages, int* redo)
{
    kg_cl_backend* b = kg_state(world)->cl;
    kg_result r = stages == KG_OK ? kg_cl_end_step(world, b) : stages;
    b->in_step = 0;
    if (r != KG_OK) {
        kg_fall_back(world, 1);
        *redo = 1;
    }
    return KG_OK;
}

/* A failed device call of an operation other than the step (a read for a getter, a device
 * force's build): inside a step (a force callback calling it) the fallback waits for the
 * end of the step; between steps it is at once. */
static void kg_device_call_failed(kg_world* world, kg_cl_backend* b)
{
    if (b->in_step) {
        kg_cl_request_fallback(b);
    } else {
        kg_fall_back(world, 0);
    }
}

static kg_result kg_opencl_sync_to_host(kg_world* world)
{
    kg_cl_backend* b = kg_state(world)->cl;
    if (b->host_stale == 0 || b->fallback_pending) {
        return KG_OK; /* with a fallback pending, the host's copy answers: the step is redone */
    }
    int flags_stale = (b->host_stale & KG_CL_BIT(FLAGS)) != 0;
    kg_result r = kg_cl_download(b, &world->bodies, b->host_stale);
    if (r != KG_OK) {
        kg_device_call_failed(world, b);
        return KG_OK;
    }
    b->steps_since_snapshot = 0;
    if (flags_stale) {
        kg_cl_warn_new_frozen(world, b);
    }
    return KG_OK;
}

/* Reading the contacts failing is a read failure like any other: the world falls back,
 * and the fallback reads them again. */
static void kg_opencl_sync_contacts(kg_world* world)
{
    kg_cl_backend* b = kg_state(world)->cl;
    if (!b->fallback_pending && kg_cl_read_contacts(world, b) != KG_OK) {
        kg_device_call_failed(world, b);
    }
}

static void kg_opencl_sync_previous_contacts(kg_world* world)
{
    kg_cl_backend* b = kg_state(world)->cl;
    if (!b->fallback_pending && kg_cl_read_previous_contacts(world, b) != KG_OK) {
        kg_device_call_failed(world, b);
    }
}

static void kg_opencl_host_changed(kg_world* world)
{
    kg_cl_backend* b = kg_state(world)->cl;
    b->device_stale = KG_CL_ALL_ARRAYS;
}

/* A snapshot reads the state arrays a step changed, the contacts and the one-way state:
 * nothing else is newer on the device. A failed read falls back, as for a getter (the
 * fallback reads them itself). */
static void kg_opencl_sync_for_snapshot(kg_world* world)
{
    kg_opencl_sync_to_host(world);
    if (world->backend == &kg_opencl_backend) {
        kg_opencl_sync_contacts(world);
    }
    if (world->backend == &kg_opencl_backend) {
        kg_cl_backend* b = kg_state(world)->cl;
        if (kg_cl_tile_state_to_host(world, b) != KG_OK) {
            kg_device_call_failed(world, b);
        }
    }
}

static int kg_frozen_count(const kg_body_pool* p)
{
    int frozen = 0;
    for (int i = 0; i < p->high_water; ++i) {
        frozen += kg_pool_alive(p, i) && (p->flags[i] & KG_FLAG_FROZEN) != 0u;
    }
    return frozen;
}

/* The contacts of the restored host list as the device's last step's. */
static kg_result kg_upload_restored_contacts(kg_world* world, kg_cl_backend* b)
{
    int count = 0;
    const kg_contact* contacts = kg_collision_contacts(world, &count);
    KG_TRY(kg_cl_reserve_contacts(b, world->def.max_contacts > count ? world->def.max_contacts : count));
    if (count > 0) {
        KG_TRY(kg_cl_write(b, b->contacts[b->current], 0, (size_t)count * sizeof *contacts, contacts, 1));
    }
    b->body_contact_count = kg_collision_body_count(world);
    return KG_OK;
}

/* The host holds the whole state now: every body array, the shapes, tile maps, static
 * list and one-way state are sent again before the next step, and the contacts now. A
 * failure hands the world to the CPU, which goes on from the host's (restored) state. */
static void kg_opencl_restored(kg_world* world)
{
    kg_cl_backend* b = kg_state(world)->cl;
    b->host_stale = 0;
    b->device_stale = KG_CL_ALL_ARRAYS;
    b->forces_cleared = 0;
    b->checkpoint_valid = 0;
    b->steps_since_snapshot = 0;
    b->shape_version = world->shapes.version - 1u;
    b->collide.tiles_built = 0;
    b->collide.statics_sent = 0;
    b->tile_state_on_device = 0;
    b->contacts_stale = 0;
    b->previous_contacts_stale = 0;
    b->joint_lists_sent = 0;
    b->frozen_count = kg_frozen_count(&world->bodies);
    if (kg_upload_restored_contacts(world, b) != KG_OK) {
        char reason[512];
        snprintf(reason, sizeof reason, "%s", kg_last_error());
        kg_cl_backend_stop(world);
        kg_backend_use_cpu(world);
        kg_warn_once("opencl-restore", "OpenCL backend failed while restoring a snapshot (%s); continuing on the "
                     "CPU backend from the restored state", reason);
    }
}

static void kg_opencl_destroy(kg_world* world)
{
    kg_cl_backend_stop(world);
    kg_backend_state_free(world);
}

const kg_backend_ops kg_opencl_backend = {.kind = KG_BACKEND_OPENCL,
                                          .name = "opencl",
                                          .begin_step = kg_opencl_begin_step,
                                          .run_stage = kg_opencl_run_stage,
                                          .end_step = kg_opencl_end_step,
                                          .stage_label = kg_opencl_stage_label,
                                          .sync_to_host = kg_opencl_sync_to_host,
                                          .host_changed = kg_opencl_host_changed,
                                          .destroy = kg_opencl_destroy,
                                          .sync_contacts = kg_opencl_sync_contacts,
                                          .sync_previous_contacts = kg_opencl_sync_previous_contacts,
                                          .sync_for_snapshot = kg_opencl_sync_for_snapshot,
                                          .restored = kg_opencl_restored};

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

static kg_result kg_cl_backend_alloc(const kg_world* world, kg_cl_backend** out)
{
    kg_cl_backend* b = kg_alloc_zeroed(sizeof *b);
    *out = b;
    if (!b) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the OpenCL backend");
    }
    size_t slots = (size_t)world->def.max_applicators + 1u, bodies = (size_t)world->def.max_bodies;
    b->force_kernels = kg_alloc_zeroed(slots * sizeof *b->force_kernels);
    b->force_group_sizes = kg_alloc_zeroed(slots * sizeof *b->force_group_sizes);
    b->start_force = kg_alloc_zeroed(bodies * sizeof *b->start_force);
    b->start_torque = kg_alloc_zeroed(bodies * sizeof *b->start_torque);
    int ok = b->force_kernels && b->force_group_sizes && b->start_force && b->start_torque;
    return ok ? KG_OK : kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the OpenCL backend");
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
    if (r == KG_OK) {
        r = kg_cl_backend_alloc(world, &kg_state(world)->cl);
    }
    if (r == KG_OK) {
        r = kg_cl_open_device(world, kg_state(world)->cl, rt, &faults);
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
        b->cl->ReleaseKernel(b->force_kernels[slot]);
        b->force_kernels[slot] = NULL;
    }
}

kg_result kg_cl_prepare_device_force(kg_world* world, kg_cl_backend* b, int slot)
{
    kg_device_force* f = &kg_state(world)->forces[slot];
    kg_cl_release_device_force(b, slot);
    cl_program program = NULL;
    kg_result r = kg_cl_force_program(b->rt, f->source, f->function_name, &program);
    if (r != KG_OK) {
        return r;
    }
    cl_int err = CL_SUCCESS;
    b->force_kernels[slot] = b->cl->CreateKernel(program, KG_CL_DEVICE_FORCE_KERNEL, &err);
    if (!b->force_kernels[slot] || err != CL_SUCCESS) {
        b->force_kernels[slot] = NULL;
        return kg_fail(KG_ERROR_BACKEND, "OpenCL: no kernel in the device force program (%s)", kg_cl_error_name(err));
    }
    b->force_group_sizes[slot] = kg_cl_pick_group_size(b, b->force_kernels[slot]);
    r = kg_cl_check_arg_count(b, b->force_kernels[slot], KG_CL_DEVICE_FORCE_KERNEL, KG_CL_DEVICE_FORCE_ARGS);
    if (r != KG_OK) {
        kg_cl_release_device_force(b, slot);
    }
    return r;
}

/* Compiles a newly registered device force on the world's device: a build error is the
 * user's (KG_ERROR_INVALID_ARGUMENT, reported to the caller); any other failure is the
 * device's, and the world falls back to the CPU, where the force runs as C. */
kg_result kg_backend_prepare_device_force(kg_world* world, int slot)
{
    kg_cl_backend* b = kg_state(world)->cl;
    if (!b || b->fallback_pending) {
        return KG_OK; /* the world is, or is about to be, on the CPU */
    }
    kg_result r = kg_cl_prepare_device_force(world, b, slot);
    if (r == KG_OK || r == KG_ERROR_INVALID_ARGUMENT) {
        return r;
    }
    kg_device_call_failed(world, b);
    return KG_OK;
}

/* ---- partial reads ------------------------------------------------------------------ */

kg_result kg_backend_read_transforms(kg_world* world, int first, int count)
{
    kg_cl_backend* b = kg_state(world)->cl;
    if (!b || b->fallback_pending || !(b->host_stale & KG_CL_BIT(XF)) || count <= 0) {
        return KG_OK;
    }
    kg_result r = kg_cl_read(b, b->arrays[KG_CL_XF], (size_t)first * sizeof(kg_xf), (size_t)count * sizeof(kg_xf),
                             world->bodies.xf + first);
    if (r != KG_OK) {
        kg_device_call_failed(world, b);
    }
    return KG_OK;
}
#endif
