#ifdef KG_HAVE_OPENCL
#include "backend/opencl/cl_world.h"
#include "backend/opencl/cl_sort.h"
#include "backend/opencl/kernels/kg_collide_shared.h"
#include "collide/collide.h"
#include "collide/continuous.h"
#include "core/alloc.h"
#include "core/error.h"
#include "solve/contact_solver.h"
#include "solve/force_body.h"
#include "solve/graph_color.h"
#include "solve/integrate.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* Work-group size aimed at: a multiple of every GPU's SIMD width (32 or 64), and large
 * enough that a CPU device's per-group overhead stays small. */
#define KG_CL_GROUP_TARGET 64
#define KG_CL_SINGLE_GROUP_MAX 256

typedef struct kg_cl_host_array {
    void* data;
    size_t element_size;
    int state;
} kg_cl_host_array;

static kg_cl_host_array kg_cl_host_array_of(const kg_body_pool* pool, kg_cl_array id)
{
    kg_cl_host_array out = {NULL, 0, 0};
    switch (id) {
#define KG_CL_HOST_CASE(name, member, is_state)                                 \
    case KG_CL_##name:                                                          \
        out.data = (void*)pool->member;                                         \
        out.element_size = sizeof *pool->member;                                \
        out.state = is_state;                                                   \
        break;
        KG_CL_BODY_ARRAYS(KG_CL_HOST_CASE)
#undef KG_CL_HOST_CASE
    case KG_CL_ARRAY_COUNT: break;
    }
    return out;
}

unsigned kg_cl_state_arrays(void)
{
    unsigned mask = 0;
#define KG_CL_STATE_BIT(name, member, is_state) mask |= (is_state) ? KG_CL_BIT(name) : 0u;
    KG_CL_BODY_ARRAYS(KG_CL_STATE_BIT)
#undef KG_CL_STATE_BIT
    return mask;
}

/* ---- checked calls ------------------------------------------------------------------ */

static kg_result kg_cl_check(cl_int err, const char* what)
{
    return err == CL_SUCCESS ? KG_OK : kg_fail(KG_ERROR_BACKEND, "OpenCL: %s failed (%s)", what, kg_cl_error_name(err));
}

static kg_result kg_cl_injected(const char* what)
{
    return kg_fail(KG_ERROR_BACKEND, "OpenCL: %s failed (CL_OUT_OF_RESOURCES injected by KGYRO_CL_FAIL)", what);
}

/* The event to profile a command with, or NULL when not profiling (or the step's event
 * list is full: later commands then go untimed). */
static cl_event* kg_cl_event_for(kg_cl_backend* b, const char* name)
{
    if (!b->profiling || b->event_count >= KG_CL_MAX_EVENTS) {
        return NULL;
    }
    b->event_names[b->event_count] = name;
    b->events[b->event_count] = NULL;
    return &b->events[b->event_count];
}

static void kg_cl_event_done(kg_cl_backend* b, cl_event* event, cl_int err)
{
    if (event && err == CL_SUCCESS && *event) {
        b->event_count += 1;
    }
}

kg_result kg_cl_buffer(kg_cl_backend* b, size_t size, cl_mem* out)
{
    *out = NULL;
    if (kg_cl_fault(&b->faults, KG_CL_FAULT_ALLOC)) {
        return kg_fail(KG_ERROR_BACKEND, "OpenCL: cannot allocate a buffer of %zu bytes "
                       "(CL_MEM_OBJECT_ALLOCATION_FAILURE injected by KGYRO_CL_FAIL)", size);
    }
    cl_int err = CL_SUCCESS;
    *out = b->cl->CreateBuffer(b->rt->context, CL_MEM_READ_WRITE, size > 0 ? size : 4, NULL, &err);
    if (!*out || err != CL_SUCCESS) {
        *out = NULL;
        return kg_fail(KG_ERROR_BACKEND, "OpenCL: cannot allocate a buffer of %zu bytes on %s (%s)", size,
                       b->rt->device->info.name, kg_cl_error_name(err));
    }
    return KG_OK;
}

void kg_cl_release(kg_cl_backend* b, cl_mem* buffer)
{
    if (*buffer) {
        b->cl->ReleaseMemObject(*buffer);
        *buffer = NULL;
    }
}

kg_result kg_cl_write(kg_cl_backend* b, cl_mem buffer, size_t offset, size_t size, const void* data, int blocking)
{
    if (size == 0) {
        return KG_OK;
    }
    if (kg_cl_fault(&b->faults, KG_CL_FAULT_ENQUEUE)) {
        return kg_cl_injected("a write to the device");
    }
    cl_event* event = kg_cl_event_for(b, "upload");
    cl_int err = b->cl->EnqueueWriteBuffer(b->queue, buffer, blocking ? CL_TRUE : CL_FALSE, offset, size, data, 0,
                                           NULL, event);
    kg_cl_event_done(b, event, err);
    b->transfers.bytes_to_device += size;
    b->transfers.writes += 1;
    return kg_cl_check(err, "a write to the device");
}

kg_result kg_cl_rounds_left(kg_cl_backend* b, int first, int round, cl_uint* left)
{
    size_t at = (size_t)(first + ((round - 1) & 1)) * sizeof *left;
    return kg_cl_read(b, b->collide.counts, at, sizeof *left, left);
}

kg_result kg_cl_read(kg_cl_backend* b, cl_mem buffer, size_t offset, size_t size, void* data)
{
    if (size == 0) {
        return KG_OK;
    }
    if (kg_cl_fault(&b->faults, KG_CL_FAULT_READ)) {
        return kg_cl_injected("a read from the device");
    }
    cl_event* event = kg_cl_event_for(b, "download");
    cl_int err = b->cl->EnqueueReadBuffer(b->queue, buffer, CL_TRUE, offset, size, data, 0, NULL, event);
    kg_cl_event_done(b, event, err);
    b->transfers.bytes_to_host += size;
    b->transfers.reads += 1;
    return kg_cl_check(err, "a read from the device");
}

kg_result kg_cl_copy(kg_cl_backend* b, cl_mem from, cl_mem to, size_t size)
{
    if (size == 0) {
        return KG_OK;
    }
    if (kg_cl_fault(&b->faults, KG_CL_FAULT_ENQUEUE)) {
        return kg_cl_injected("a copy on the device");
    }
    cl_event* event = kg_cl_event_for(b, "checkpoint");
    cl_int err = b->cl->EnqueueCopyBuffer(b->queue, from, to, 0, 0, size, 0, NULL, event);
    kg_cl_event_done(b, event, err);
    return kg_cl_check(err, "a copy on the device");
}

static kg_result kg_cl_launch(kg_cl_backend* b, cl_kernel kernel, size_t group_size, int count, const char* name)
{
    if (kg_cl_fault(&b->faults, KG_CL_FAULT_ENQUEUE)) {
        return kg_cl_injected(name);
    }
    size_t global = ((size_t)count + group_size - 1) / group_size * group_size;
    cl_event* event = kg_cl_event_for(b, name);
    cl_int err = b->cl->EnqueueNDRangeKernel(b->queue, kernel, 1, NULL, &global, &group_size, 0, NULL, event);
    kg_cl_event_done(b, event, err);
    if (err != CL_SUCCESS) {
        return kg_fail(KG_ERROR_BACKEND, "OpenCL: launching %s failed (%s)", name, kg_cl_error_name(err));
    }
    return KG_OK;
}

kg_result kg_cl_launch_kernel(kg_cl_backend* b, cl_kernel kernel, size_t group_size, int items, const char* label,
                              const kg_cl_kernel_arg* args, int count)
{
    if (items <= 0) {
        return KG_OK;
    }
    for (int k = 0; k < count; ++k) {
        cl_int err = b->cl->SetKernelArg(kernel, (cl_uint)k, args[k].size, args[k].value);
        if (err != CL_SUCCESS) {
            return kg_fail(KG_ERROR_BACKEND, "OpenCL: setting argument %d of %s failed (%s)", k, label,
                           kg_cl_error_name(err));
        }
    }
    return kg_cl_launch(b, kernel, group_size, items, label);
}

static const char* const kKernelNames[KG_CL_KERNEL_COUNT] = {
#define KG_CL_KERNEL_NAME(id, name, args) #name,
    KG_CL_KERNELS(KG_CL_KERNEL_NAME)
#undef KG_CL_KERNEL_NAME
};

static const int kKernelArgs[KG_CL_KERNEL_COUNT] = {
#define KG_CL_KERNEL_ARG_COUNT(id, name, args) args,
    KG_CL_KERNELS(KG_CL_KERNEL_ARG_COUNT)
#undef KG_CL_KERNEL_ARG_COUNT
};

kg_result kg_cl_launch_args(kg_cl_backend* b, kg_cl_kernel_id id, int items, const char* label,
                            const kg_cl_kernel_arg* args, int count)
{
    return kg_cl_launch_kernel(b, b->kernels[id], b->group_size[id], items, label ? label : kKernelNames[id], args,
                               count);
}

kg_result kg_cl_check_arg_count(kg_cl_backend* b, cl_kernel kernel, const char* name, int expected)
{
    cl_uint actual = 0;
    cl_int err = b->cl->GetKernelInfo(kernel, CL_KERNEL_NUM_ARGS, sizeof actual, &actual, NULL);
    if (err != CL_SUCCESS) {
        return kg_fail(KG_ERROR_BACKEND, "OpenCL: cannot read the argument count of kernel %s (%s)", name,
                       kg_cl_error_name(err));
    }
    if ((int)actual != expected) {
        return kg_fail(KG_ERROR_BACKEND, "OpenCL: kernel %s takes %u arguments in its source but %d in cl_world.h, "
                       "which its launches follow", name, (unsigned)actual, expected);
    }
    return KG_OK;
}

kg_result kg_cl_finish(kg_cl_backend* b)
{
    if (kg_cl_fault(&b->faults, KG_CL_FAULT_FINISH)) {
        return kg_fail(KG_ERROR_BACKEND, "OpenCL: a kernel failed while running (CL_OUT_OF_RESOURCES injected by "
                       "KGYRO_CL_FAIL)");
    }
    return kg_cl_check(b->cl->Finish(b->queue), "waiting for the device");
}

/* ---- residency ---------------------------------------------------------------------- */

static size_t kg_cl_span(const kg_body_pool* pool, kg_cl_host_array a)
{
    return (size_t)pool->high_water * a.element_size;
}

kg_result kg_cl_upload(kg_cl_backend* b, const kg_body_pool* pool, unsigned arrays)
{
    for (int id = 0; id < KG_CL_ARRAY_COUNT; ++id) {
        if (arrays & (1u << id)) {
            kg_cl_host_array a = kg_cl_host_array_of(pool, (kg_cl_array)id);
            /* blocking: user code may change the pool as soon as a callback returns */
            kg_result r = kg_cl_write(b, b->arrays[id], 0, kg_cl_span(pool, a), a.data, 1);
            if (r != KG_OK) {
                return r;
            }
            b->device_stale &= ~(1u << id);
        }
    }
    return KG_OK;
}

/* Force, torque and drag after a step are zero for every live body: no need to read them. */
static void kg_cl_clear_forces(kg_body_pool* pool)
{
    for (int i = 0; i < pool->high_water; ++i) {
        if (kg_pool_alive(pool, i)) {
            pool->force[i].x = 0.0f;
            pool->force[i].y = 0.0f;
            pool->torque[i] = 0.0f;
            pool->drag[i] = 0.0f;
        }
    }
}

kg_result kg_cl_download(kg_cl_backend* b, kg_body_pool* pool, unsigned arrays)
{
    unsigned forces = KG_CL_BIT(FORCE) | KG_CL_BIT(TORQUE) | KG_CL_BIT(DRAG);
    if (b->forces_cleared && (arrays & forces)) {
        kg_cl_clear_forces(pool);
        b->host_stale &= ~forces;
        arrays &= ~forces;
    }
    for (int id = 0; id < KG_CL_ARRAY_COUNT; ++id) {
        if (arrays & (1u << id)) {
            kg_cl_host_array a = kg_cl_host_array_of(pool, (kg_cl_array)id);
            kg_result r = kg_cl_read(b, b->arrays[id], 0, kg_cl_span(pool, a), a.data);
            if (r != KG_OK) {
                return r;
            }
            b->host_stale &= ~(1u << id);
        }
    }
    return KG_OK;
}

kg_result kg_cl_to_device(kg_cl_backend* b, const kg_body_pool* pool, unsigned arrays)
{
    return kg_cl_upload(b, pool, arrays & b->device_stale);
}

kg_result kg_cl_to_host(kg_cl_backend* b, kg_body_pool* pool, unsigned arrays)
{
    return kg_cl_download(b, pool, arrays & b->host_stale);
}

kg_result kg_cl_save_checkpoint(kg_cl_backend* b, const kg_body_pool* pool)
{
    unsigned state = kg_cl_state_arrays();
    for (int id = 0; id < KG_CL_ARRAY_COUNT; ++id) {
        if (state & (1u << id)) {
            kg_cl_host_array a = kg_cl_host_array_of(pool, (kg_cl_array)id);
            kg_result r = kg_cl_copy(b, b->arrays[id], b->checkpoint[id], kg_cl_span(pool, a));
            if (r != KG_OK) {
                return r;
            }
        }
    }
    return KG_OK;
}

kg_result kg_cl_read_checkpoint(kg_cl_backend* b, kg_body_pool* pool)
{
    unsigned state = kg_cl_state_arrays();
    for (int id = 0; id < KG_CL_ARRAY_COUNT; ++id) {
        if (state & (1u << id)) {
            kg_cl_host_array a = kg_cl_host_array_of(pool, (kg_cl_array)id);
            kg_result r = kg_cl_read(b, b->checkpoint[id], 0, kg_cl_span(pool, a), a.data);
            if (r != KG_OK) {
                return r;
            }
        }
    }
    b->host_stale = 0;
    return KG_OK;
}

/* ---- profiling ---------------------------------------------------------------------- */

/* Sums ns under name; past KG_CL_MAX_TIMED names, the last entry becomes "other". */
static void kg_cl_add_time(kg_cl_timing* t, const char* name, cl_ulong ns)
{
    for (int k = 0; k < t->count; ++k) {
        if (strcmp(t->names[k], name) == 0) {
            t->ns[k] += ns;
            return;
        }
    }
    if (t->count == KG_CL_MAX_TIMED) {
        t->names[KG_CL_MAX_TIMED - 1] = "other";
        t->ns[KG_CL_MAX_TIMED - 1] += ns;
        return;
    }
    t->names[t->count] = name;
    t->ns[t->count++] = ns;
}

void kg_cl_collect_timing(kg_cl_backend* b)
{
    for (int k = 0; k < b->event_count; ++k) {
        cl_ulong start = 0, end = 0;
        if (b->cl->GetEventProfilingInfo(b->events[k], CL_PROFILING_COMMAND_START, sizeof start, &start, NULL) ==
                CL_SUCCESS &&
            b->cl->GetEventProfilingInfo(b->events[k], CL_PROFILING_COMMAND_END, sizeof end, &end, NULL) ==
                CL_SUCCESS &&
            end >= start) {
            kg_cl_add_time(&b->timing, b->event_names[k], end - start);
        }
        b->cl->ReleaseEvent(b->events[k]);
    }
    b->event_count = 0;
}

/* ---- creation ----------------------------------------------------------------------- */

size_t kg_cl_pick_group_size(kg_cl_backend* b, cl_kernel kernel)
{
    size_t max = 1, multiple = 1;
    cl_device_id device = b->rt->device->id;
    if (b->cl->GetKernelWorkGroupInfo(kernel, device, CL_KERNEL_WORK_GROUP_SIZE, sizeof max, &max, NULL) != CL_SUCCESS) {
        max = 1;
    }
    if (b->cl->GetKernelWorkGroupInfo(kernel, device, CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE, sizeof multiple,
                                      &multiple, NULL) != CL_SUCCESS || multiple == 0) {
        multiple = 1;
    }
    size_t size = max < KG_CL_GROUP_TARGET ? max : KG_CL_GROUP_TARGET;
    if (multiple <= size) {
        size -= size % multiple;
    }
    return size > 0 ? size : 1;
}

/* The one work-group of kg_solve_colors_in_group: as large as the kernel allows, up to
 * KG_CL_SINGLE_GROUP_MAX. */
static size_t kg_cl_single_group_size(kg_cl_backend* b, cl_kernel kernel)
{
    size_t max = 1;
    if (b->cl->GetKernelWorkGroupInfo(kernel, b->rt->device->id, CL_KERNEL_WORK_GROUP_SIZE, sizeof max, &max, NULL) !=
        CL_SUCCESS) {
        max = 1;
    }
    return max < KG_CL_SINGLE_GROUP_MAX ? max : KG_CL_SINGLE_GROUP_MAX;
}

static kg_result kg_cl_create_kernels(kg_cl_backend* b)
{
    for (int k = 0; k < KG_CL_KERNEL_COUNT; ++k) {
        cl_int err = CL_SUCCESS;
        b->kernels[k] = b->cl->CreateKernel(b->rt->step_program, kKernelNames[k], &err);
        if (!b->kernels[k] || err != CL_SUCCESS) {
            b->kernels[k] = NULL;
            return kg_fail(KG_ERROR_BACKEND, "OpenCL: no kernel %s in the step program (%s)", kKernelNames[k],
                           kg_cl_error_name(err));
        }
        KG_TRY(kg_cl_check_arg_count(b, b->kernels[k], kKernelNames[k], kKernelArgs[k]));
        b->group_size[k] = kg_cl_pick_group_size(b, b->kernels[k]);
    }
    b->group_size[KG_CL_K_SOLVE_COLORS_IN_GROUP] = kg_cl_single_group_size(b, b->kernels[KG_CL_K_SOLVE_COLORS_IN_GROUP]);
    return KG_OK;
}

typedef struct kg_cl_sized_buffer {
    cl_mem* buffer;
    size_t size;
} kg_cl_sized_buffer;

static kg_result kg_cl_buffers(kg_cl_backend* b, const kg_cl_sized_buffer* list, int count)
{
    for (int k = 0; k < count; ++k) {
        kg_result r = kg_cl_buffer(b, list[k].size, list[k].buffer);
        if (r != KG_OK) {
            return r;
        }
    }
    return KG_OK;
}

/* The collision stage's buffers of one entry per body slot or fewer. */
static kg_result kg_cl_create_collide_buffers(kg_cl_backend* b, int slots)
{
    kg_cl_collide_buffers* c = &b->collide;
    size_t n = (size_t)slots, words = sizeof(cl_uint);
    const kg_cl_sized_buffer list[] = {
        {&c->counts, KG_CC_WORDS * words},
        {&c->proxies, n * sizeof(kg_bp_proxy)},
        {&c->sorted, n * sizeof(kg_bp_proxy)},
        {&c->keys, n * words},
        {&c->items, n * words},
        {&c->large_keys, n * words},
        {&c->large_items, n * words},
        {&c->key_scratch, n * words},
        {&c->item_scratch, n * words},
        {&c->found, (2 * n + 1) * words},
        {&c->histogram, KG_BP_EXTENT_BINS * words},
        {&c->grid, sizeof(kg_bp_grid)},
        {&c->bp_words, KG_BP_WORDS * words},
        {&c->run, (n + 1) * words},
        {&c->run_fill, n * words},
        {&c->colors_used, n * words},
        {&c->color_bids[0], n * words},
        {&c->color_bids[1], n * words},
        {&c->block_sums, KG_SCAN_MAX_BLOCKS * words},
        {&c->sort_counts, KG_SORT_COUNT_WORDS * words},
        {&c->tile_run, (n + 1) * words},
        {&c->statics, n * sizeof(kg_static_entry)},
        {&c->last_origin[0], n * sizeof(kg_vec2)},
        {&c->last_origin[1], n * sizeof(kg_vec2)},
        {&c->last_generation[0], n * words},
        {&c->last_generation[1], n * words},
    };
    return kg_cl_buffers(b, list, (int)(sizeof list / sizeof list[0]));
}

static kg_result kg_cl_create_buffers(kg_cl_backend* b, const kg_world* world)
{
    const kg_body_pool* pool = &world->bodies;
    unsigned state = kg_cl_state_arrays();
    kg_result r = KG_OK;
    for (int id = 0; id < KG_CL_ARRAY_COUNT && r == KG_OK; ++id) {
        size_t size = (size_t)pool->capacity * kg_cl_host_array_of(pool, (kg_cl_array)id).element_size;
        r = kg_cl_buffer(b, size, &b->arrays[id]);
        if (r == KG_OK && (state & (1u << id))) {
            r = kg_cl_buffer(b, size, &b->checkpoint[id]);
        }
    }
    const kg_cl_sized_buffer list[] = {
        {&b->solver_bodies, (size_t)pool->capacity * sizeof(kg_solver_body)},
        {&b->velocity_steps, (size_t)pool->capacity * sizeof(kg_velocity_step)},
        {&b->solver_params, sizeof(kg_solver_params)},
        {&b->color_start, (KG_COLOR_COUNT + 2) * sizeof(int)},
        {&b->targets, (size_t)pool->capacity * sizeof(kg_force_target)},
        {&b->wake_marks, (size_t)pool->capacity * sizeof(cl_uint)},
        {&b->island_parent, (size_t)pool->capacity * sizeof(kg_u32)},
        {&b->island_least, (size_t)pool->capacity * sizeof(float)},
    };
    if (r == KG_OK) {
        r = kg_cl_buffers(b, list, (int)(sizeof list / sizeof list[0]));
    }
    if (r == KG_OK) {
        r = kg_cl_create_collide_buffers(b, pool->capacity);
    }
    if (r == KG_OK) {
        /* For the budget, not the host's pool (sized from need): the device grows its
         * contact buffers only when the contacts outgrow its colouring, so pairs that
         * outgrew a smaller device pool would send every step to the host. */
        r = kg_cl_reserve_contacts(b, kg_collision_budget(world));
    }
    return r;
}

static void kg_cl_release_shapes(kg_cl_backend* b)
{
    cl_mem* list[] = {&b->shape_next, &b->shape_flags,    &b->shape_geometry,   &b->shape_category,
                      &b->shape_mask, &b->shape_friction, &b->shape_restitution};
    for (int k = 0; k < (int)(sizeof list / sizeof list[0]); ++k) {
        kg_cl_release(b, list[k]);
    }
    b->shape_capacity = 0;
    b->shape_geometry_held = 0;
}

/* Shape buffers of capacity slots (geometry too when the host has it), contents lost. */
static kg_result kg_cl_size_shapes(kg_cl_backend* b, const kg_shape_pool* sp, int capacity)
{
    kg_cl_release_shapes(b);
    size_t n = (size_t)capacity, words = sizeof(cl_uint);
    const kg_cl_sized_buffer list[] = {
        {&b->shape_next, n * words},
        {&b->shape_flags, n * words},
        {&b->shape_geometry, (sp->geometry ? n : 1u) * sizeof(kg_shape)},
        {&b->shape_category, n * words},
        {&b->shape_mask, n * words},
        {&b->shape_friction, n * sizeof(float)},
        {&b->shape_restitution, n * sizeof(float)},
    };
    KG_TRY(kg_cl_buffers(b, list, (int)(sizeof list / sizeof list[0])));
    b->shape_capacity = capacity;
    b->shape_geometry_held = sp->geometry != NULL;
    b->shape_version = sp->version - 1u; /* what the buffers hold is no version */
    return KG_OK;
}

kg_result kg_cl_sync_shapes(kg_cl_backend* b, const kg_world* world)
{
    const kg_shape_pool* sp = &world->shapes;
    /* the pairs of shapes read them while a body has several; continuous collision walks
     * every body's list of shapes */
    if (sp->compound_bodies == 0 && !world->def.enable_continuous) {
        return b->shape_capacity > 0 ? KG_OK : kg_cl_size_shapes(b, sp, 1); /* read by no kernel yet */
    }
    if (b->shape_capacity < sp->capacity || b->shape_capacity == 1 || (sp->geometry && !b->shape_geometry_held)) {
        KG_TRY(kg_cl_size_shapes(b, sp, sp->capacity));
    }
    if (b->shape_version == sp->version) {
        return KG_OK;
    }
    size_t n = (size_t)sp->high_water;
    const struct {
        cl_mem buffer;
        const void* data;
        size_t size;
    } list[] = {
        {b->shape_next, sp->next, n * sizeof *sp->next},
        {b->shape_flags, sp->flags, n * sizeof *sp->flags},
        {b->shape_geometry, sp->geometry, n * sizeof *sp->geometry},
        {b->shape_category, sp->category, n * sizeof *sp->category},
        {b->shape_mask, sp->mask, n * sizeof *sp->mask},
        {b->shape_friction, sp->friction, n * sizeof *sp->friction},
        {b->shape_restitution, sp->restitution, n * sizeof *sp->restitution},
    };
    for (int k = 0; k < (int)(sizeof list / sizeof list[0]); ++k) {
        if (list[k].data) { /* no geometry before the first compound body: one-shape bodies' is the body pool's */
            KG_TRY(kg_cl_write(b, list[k].buffer, 0, list[k].size, list[k].data, 1));
        }
    }
    b->shape_version = sp->version;
    return KG_OK;
}

static void kg_cl_release_contact_buffers(kg_cl_backend* b)
{
    kg_cl_collide_buffers* c = &b->collide;
    cl_mem* list[] = {&b->contacts[0], &b->contacts[1], &b->constraints, &b->colored, &b->order,
                      &c->raw_pairs, &c->pairs, &c->manifolds, &c->bases, &c->touching, &c->colors,
                      &c->color_items, &c->sorted_colors, &c->shape_run, &c->shape_items, &c->item_pairs};
    for (int k = 0; k < (int)(sizeof list / sizeof list[0]); ++k) {
        kg_cl_release(b, list[k]);
    }
    b->contact_capacity = 0;
}

/* Both contact lists are reallocated empty: only the host's collide stage grows the pool,
 * after it has read the last step's contacts back. */
kg_result kg_cl_reserve_contacts(kg_cl_backend* b, int capacity)
{
    if (capacity <= b->contact_capacity && b->contacts[0]) {
        return KG_OK;
    }
    kg_cl_release_contact_buffers(b);
    kg_cl_collide_buffers* c = &b->collide;
    size_t n = (size_t)(capacity > 0 ? capacity : 1), words = sizeof(cl_uint);
    const kg_cl_sized_buffer list[] = {
        {&b->contacts[0], n * sizeof(kg_contact)},
        {&b->contacts[1], n * sizeof(kg_contact)},
        {&b->constraints, n * sizeof(kg_contact_constraint)},
        {&b->colored, n * sizeof(kg_contact_constraint)},
        {&b->order, n * sizeof(int)},
        {&c->raw_pairs, n * 2u * words},
        {&c->pairs, n * 2u * words},
        {&c->manifolds, n * sizeof(kg_manifold)},
        {&c->bases, n * sizeof(kg_contact_base)},
        {&c->touching, (n + 1) * words},
        {&c->colors, n * words},
        {&c->color_items, n * words},
        {&c->sorted_colors, n * words},
        {&c->shape_run, (n + 1) * words},
        {&c->shape_items, n * 4u * words},
        {&c->item_pairs, n * 2u * words},
    };
    kg_result r = kg_cl_buffers(b, list, (int)(sizeof list / sizeof list[0]));
    if (r == KG_OK) {
        b->contact_capacity = (int)n;
    }
    return r;
}

/* Up to these many contacts a GPU colours them on one work-item (kg_color_constraints),
 * and finds the islands of this many bodies with one work-group: past them, rounds of
 * launches over the whole device (two a round) cost less than the lone work-item or
 * group. */
#define KG_COLOR_SERIAL_MAX 2048
#define KG_ISLAND_GROUP_MAX 4096

/* The environment variable name's value (clamped to [0, INT_MAX]) where it is set, else
 * otherwise: the limits below, forced by tests. */
static int kg_cl_limit(const char* name, int otherwise)
{
    const char* value = getenv(name);
    if (value && *value) {
        long max = strtol(value, NULL, 10);
        return max < 0 ? 0 : max > INT_MAX ? INT_MAX : (int)max;
    }
    return otherwise;
}

/* Where a device goes from one work-item or work-group to rounds over the whole device:
 * on a GPU gpu_max, where rounds use its thousands of lanes; on a CPU device never, as a
 * work-item there runs as fast as a host thread and each round costs two launches (on
 * PoCL, rain_4000: 1.0 ms a step more when colouring in rounds). The environment variable
 * `forced` sets it, for tests of the rounds on a CPU device. */
static int kg_cl_rounds_past(const kg_cl_device* device, const char* forced, int gpu_max)
{
    return kg_cl_limit(forced, device->info.type == KG_OPENCL_DEVICE_CPU ? INT_MAX : gpu_max);
}

/* How the joints' passes are launched (cl_joint.c). Up to joint_group_max joints a pass is
 * one launch of kg_solve_joint_colors_in_group, a lone work-group looping over the
 * iterations and colours; past it kg_solve_joint_color once per colour and iteration. On
 * a GPU the lone group is as wide as the kernel allows (up to KG_CL_SINGLE_GROUP_MAX) and
 * saves colours x iterations launches of 5 to 50 us while a colour fits in it; past 1,024
 * joints a colour takes a launch of a work-item a joint. A CPU device runs a work-group on
 * one core, so its lone group is one work-item (wider ones only add the barriers' cost),
 * and a launch per colour, worth it only for colours of thousands of joints, takes one
 * work-item per core (groups of one, each striding over the colour: the device pays for
 * every work-group it schedules). PoCL on 2 shared cores, ms a step (docs/joints.md):
 * ragdoll_rain's 500 joints 2.9 on one work-item, 3.8 launched per colour; joint_grid's
 * 19,794 43 on one work-item, 36.5 launched per colour while the other core is free (46
 * while it is busy). KGYRO_CL_JOINT_GROUP_MAX and KGYRO_CL_JOINT_GROUP_SIZE set the limit
 * and the lone group's width, for tests. */
#define KG_JOINT_GROUP_MAX_GPU 1024
#define KG_JOINT_GROUP_MAX_CPU 8192

static void kg_cl_joint_launches(kg_cl_backend* b, const kg_cl_device* device)
{
    int cpu = device->info.type == KG_OPENCL_DEVICE_CPU;
    b->joint_group_max = kg_cl_limit("KGYRO_CL_JOINT_GROUP_MAX", cpu ? KG_JOINT_GROUP_MAX_CPU : KG_JOINT_GROUP_MAX_GPU);
    size_t widest = kg_cl_single_group_size(b, b->kernels[KG_CL_K_SOLVE_JOINT_COLORS_IN_GROUP]);
    size_t size = (size_t)kg_cl_limit("KGYRO_CL_JOINT_GROUP_SIZE", cpu ? 1 : (int)widest);
    b->group_size[KG_CL_K_SOLVE_JOINT_COLORS_IN_GROUP] = size < 1 ? 1 : size > widest ? widest : size;
    b->joint_color_items = cpu ? (device->info.compute_units > 1 ? device->info.compute_units : 1) : INT_MAX;
    if (cpu) {
        b->group_size[KG_CL_K_SOLVE_JOINT_COLOR] = 1;
    }
}

kg_result kg_cl_open_device(kg_world* world, kg_cl_backend* b, kg_cl_runtime* rt, const kg_cl_faults* faults)
{
    b->cl = rt->cl;
    b->rt = rt;
    b->faults = *faults;
    b->events = kg_alloc_zeroed(KG_CL_MAX_EVENTS * sizeof *b->events);
    b->event_names = kg_alloc_zeroed(KG_CL_MAX_EVENTS * sizeof *b->event_names);
    kg_result r = (b->events && b->event_names) ? KG_OK : kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate events");
    if (r == KG_OK) {
        cl_int err = CL_SUCCESS;
        b->queue = b->cl->CreateCommandQueue(rt->context, rt->device->id, CL_QUEUE_PROFILING_ENABLE, &err);
        r = (b->queue && err == CL_SUCCESS) ? KG_OK : kg_cl_check(err != CL_SUCCESS ? err : CL_INVALID_COMMAND_QUEUE,
                                                                   "creating a command queue");
    }
    if (r == KG_OK) {
        r = kg_cl_create_kernels(b);
    }
    if (r == KG_OK) {
        r = kg_cl_create_buffers(b, world);
    }
    if (r != KG_OK) {
        kg_cl_close_device(b);
        return r;
    }
    b->color_serial_max = kg_cl_rounds_past(rt->device, "KGYRO_CL_COLOR_SERIAL_MAX", KG_COLOR_SERIAL_MAX);
    b->island_group_max = kg_cl_rounds_past(rt->device, "KGYRO_CL_ISLAND_GROUP_MAX", KG_ISLAND_GROUP_MAX);
    kg_cl_joint_launches(b, rt->device);
    /* everything the host has is newer than the empty buffers */
    b->device_stale = KG_CL_ALL_ARRAYS;
    return KG_OK;
}

void kg_cl_drain(kg_cl_backend* b)
{
    if (b->queue) {
        b->cl->Finish(b->queue);
    }
}

void kg_cl_close_device(kg_cl_backend* b)
{
    if (!b->cl) {
        return;
    }
    kg_cl_drain(b);
    for (int k = 0; k < b->event_count; ++k) {
        b->cl->ReleaseEvent(b->events[k]);
    }
    b->event_count = 0;
    for (int id = 0; id < KG_CL_ARRAY_COUNT; ++id) {
        kg_cl_release(b, &b->arrays[id]);
        kg_cl_release(b, &b->checkpoint[id]);
    }
    kg_cl_release(b, &b->solver_bodies);
    kg_cl_release(b, &b->velocity_steps);
    kg_cl_release(b, &b->solver_params);
    kg_cl_release(b, &b->color_start);
    kg_cl_release(b, &b->targets);
    kg_cl_release(b, &b->wake_marks);
    kg_cl_release(b, &b->island_parent);
    kg_cl_release(b, &b->island_least);
    kg_cl_release_joints(b);
    kg_cl_release_contact_buffers(b);
    kg_cl_release_shapes(b);
    kg_cl_collide_buffers* c = &b->collide;
    cl_mem* list[] = {&c->counts, &c->proxies, &c->sorted, &c->keys, &c->items, &c->large_keys,
                      &c->large_items, &c->key_scratch, &c->item_scratch, &c->found, &c->histogram, &c->grid,
                      &c->bp_words, &c->run, &c->run_fill, &c->colors_used, &c->color_bids[0], &c->color_bids[1],
                      &c->block_sums, &c->sort_counts, &c->tile_run, &c->statics,
                      &c->last_origin[0], &c->last_origin[1], &c->last_generation[0], &c->last_generation[1],
                      &c->tile_maps, &c->tile_cells, &c->tile_protos};
    for (int k = 0; k < (int)(sizeof list / sizeof list[0]); ++k) {
        kg_cl_release(b, list[k]);
    }
    c->statics_sent = 0;
    for (int k = 0; k < KG_CL_KERNEL_COUNT; ++k) {
        if (b->kernels[k]) {
            b->cl->ReleaseKernel(b->kernels[k]);
            b->kernels[k] = NULL;
        }
    }
    if (b->queue) {
        b->cl->ReleaseCommandQueue(b->queue);
        b->queue = NULL;
    }
    kg_free(b->events);
    kg_free(b->event_names);
    b->events = NULL;
    b->event_names = NULL;
    b->cl = NULL;
}
#endif
