/* The stages of the step (core/step.h) on the device: what each runs, what crosses the
 * bus and what runs on the host instead is told once, in docs/design.md, "The OpenCL
 * pipeline". Until the step's end the step's contact list does not become the current
 * one, and last step's contacts stay untouched on both sides, so a step that fails is
 * redone on the CPU exactly. Each kernel calls the shared per-element function the CPU
 * loop calls; each launch sets all of its kernel's arguments, in order, where it is
 * launched (KG_LAUNCH of cl_world.h). */
#ifdef KG_HAVE_OPENCL
#include "backend/opencl/cl_backend.h"
#include "collide/collide.h"
#include "collide/continuous.h"
#include "collide/tilemap.h"
#include "core/alloc.h"
#include "core/error.h"
#include "solve/contact_solver.h"
#include "solve/forces.h"
#include "solve/solver.h"
#include "solve/integrate.h"

#include <stdlib.h>
#include <string.h>


/* Up to this many contacts, each solver pass is one single-group launch: a world that
 * small cannot fill a GPU, and one launch instead of one per colour saves the launch
 * latency (5 to 50 us each, times colours x 3 passes x sub-steps). */
#define KG_CL_SINGLE_GROUP_CONTACTS 1024

/* ---- timing ----------------------------------------------------------------------- */

/* The begin and end of the step, timed on the host when not profiling (the kernels are
 * timed by their events then). */
static void kg_time_bracket(kg_world* world, const char* name, double start)
{
    const kg_backend_state* s = world->backend_state;
    kg_stage_times* t = &world->times;
    if (!s->profiling && t->count < KG_MAX_STAGE_TIMES) {
        t->names[t->count] = name;
        t->ms[t->count] = kg_now_ms() - start;
        t->count += 1;
    }
}

static void kg_add_kernel_times(kg_world* world, kg_cl_backend* b)
{
    kg_cl_collect_timing(b);
    kg_stage_times* t = &world->times;
    for (int k = 0; k < b->timing.count && t->count < KG_MAX_STAGE_TIMES; ++k) {
        t->names[t->count] = b->timing.names[k];
        t->ms[t->count] = (double)b->timing.ns[k] * 1e-6;
        t->count += 1;
    }
    memset(&b->timing, 0, sizeof b->timing);
}

/* ---- forces ----------------------------------------------------------------------- */

static int kg_target_compare(const void* a, const void* b)
{
    kg_u32 x = ((const kg_force_target*)a)->slot, y = ((const kg_force_target*)b)->slot;
    return (x > y) - (x < y);
}

static kg_result kg_reserve_targets(kg_cl_backend* b, int targets)
{
    if (targets <= b->target_capacity) {
        return KG_OK;
    }
    /* earlier lists of this step may still be read by non-blocking writes */
    KG_TRY(kg_cl_finish(b));
    kg_force_target* grown = kg_alloc_zeroed((size_t)targets * sizeof *grown);
    if (!grown) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate applicator targets");
    }
    kg_free(b->host_targets);
    b->host_targets = grown;
    b->target_capacity = targets;
    return KG_OK;
}

/* The live bodies of an applicator's list as targets sorted by slot, written at
 * targets[*used]; *count gets how many. A body listed n times is one target repeated n
 * times: the kernel adds its force n times in sequence, as the CPU loop does. */
static kg_result kg_list_targets(kg_world* world, kg_cl_backend* b, const kg_applicator_slot* a, int* used, int* count)
{
    KG_TRY(kg_reserve_targets(b, *used + a->body_count));
    kg_force_target* out = b->host_targets + *used;
    int n = 0;
    for (int k = 0; k < a->body_count; ++k) {
        if (kg_body_is_valid(world, a->bodies[k])) {
            out[n].slot = a->bodies[k].index;
            out[n].repeat = 1u;
            n++;
        }
    }
    qsort(out, (size_t)n, sizeof *out, kg_target_compare);
    int unique = 0;
    for (int k = 0; k < n; ++k) {
        if (unique > 0 && out[unique - 1].slot == out[k].slot) {
            out[unique - 1].repeat += 1u;
        } else {
            out[unique++] = out[k];
        }
    }
    *count = unique;
    return KG_OK;
}

/* The targets of applicator a, for the first three arguments of its kernel (count, all,
 * targets): *all when it applies to every slot, else its list written to b->targets;
 * *count, the work-item count. Each list is written from its own range of the host
 * scratch (a non-blocking write reads it later); on the device they all go to the start
 * of the targets buffer, which the in-order queue makes safe. A list has at most one target
 * per slot, so the buffer, sized max_bodies, always holds it. */
static kg_result kg_write_targets(kg_world* world, kg_cl_backend* b, const kg_applicator_slot* a, int* used,
                                  int* count, int* all)
{
    *all = a->bodies == NULL;
    *count = world->bodies.high_water;
    if (!*all) {
        KG_TRY(kg_list_targets(world, b, a, used, count));
        KG_TRY(kg_cl_write(b, b->targets, 0, (size_t)*count * sizeof *b->host_targets, b->host_targets + *used, 0));
        *used += *count;
    }
    return KG_OK;
}

static kg_result kg_run_builtin_force(kg_world* world, kg_cl_backend* b, const kg_applicator_slot* a, int* used)
{
    int count = 0, all = 0;
    KG_TRY(kg_write_targets(world, b, a, used, &count, &all));
    kg_builtin_force f = kg_builtin_force_of(a);
    KG_LAUNCH(b, APPLY_BUILTIN_FORCE, count, NULL, KG_INT(count), KG_INT(all), KG_MEM(b->targets), KG_VALUE(f),
              KG_MEM(KG_A(FLAGS)), KG_MEM(KG_A(MASS)), KG_MEM(KG_A(FORCE)), KG_MEM(KG_A(DRAG)));
    return KG_OK;
}

static kg_result kg_run_device_force(kg_world* world, kg_cl_backend* b, int slot, kg_device_force* f, int* used)
{
    if (!b->force_kernels[slot]) {
        KG_TRY(kg_cl_prepare_device_force(world, b, slot));
    }
    int count = 0, all = 0;
    KG_TRY(kg_write_targets(world, b, &world->applicators[slot], used, &count, &all));
    KG_LAUNCH_DEVICE_FORCE(b, b->force_kernels[slot], b->force_group_sizes[slot], count, f->function_name,
                           KG_INT(count), KG_INT(all), KG_MEM(b->targets), KG_VALUE(f->params),
                           KG_MEM(KG_A(FLAGS)), KG_MEM(KG_A(CENTER)), KG_MEM(KG_A(ROT)), KG_MEM(KG_A(VELOCITY)),
                           KG_MEM(KG_A(OMEGA)), KG_MEM(KG_A(MASS)), KG_MEM(KG_A(INERTIA)), KG_MEM(KG_A(FORCE)),
                           KG_MEM(KG_A(TORQUE)));
    return KG_OK;
}

/* A fallback requested during the step (kg_cl_request_fallback) ends it here, before any
 * further device call. */
static kg_result kg_check_fallback(const kg_cl_backend* b)
{
    if (b->fallback_pending) {
        return kg_fail(KG_ERROR_BACKEND, "OpenCL: the device failed during a force callback (%s)", b->fallback_reason);
    }
    return KG_OK;
}

/* A C callback runs on the host. It reads and writes through the body API, whose getters
 * read back what the device changed (sync_to_host) and whose setters mark the host copy
 * changed (host_changed); what it changed is uploaded before the next kernel. A read of
 * its that fails requests the fallback, and the step ends when the callback returns. */
static kg_result kg_run_callback(kg_world* world, kg_cl_backend* b, const kg_applicator_slot* a)
{
    KG_TRY(kg_cl_flags_to_host(world, b)); /* the targets leave out the bodies asleep */
    int count = kg_applicator_targets(world, a);
    a->fn(world, world->handle_scratch, count, a->user_data);
    KG_TRY(kg_check_fallback(b));
    return kg_cl_to_device(b, &world->bodies, KG_CL_ALL_ARRAYS);
}

static kg_result kg_stage_forces(kg_world* world, kg_cl_backend* b)
{
    int used = 0;
    for (int slot = 0; slot < world->def.max_applicators; ++slot) {
        const kg_applicator_slot* a = &world->applicators[slot];
        kg_device_force* f = kg_device_force_of(world, slot);
        if (a->kind == KG_APPLICATOR_FREE) {
            continue;
        }
        if (a->kind != KG_APPLICATOR_USER || f) {
            b->forces_cleared = 0;
            b->host_stale |= KG_CL_BIT(FORCE) | KG_CL_BIT(TORQUE) | KG_CL_BIT(DRAG);
        }
        if (f) {
            KG_TRY(kg_run_device_force(world, b, slot, f, &used));
        } else if (a->kind == KG_APPLICATOR_USER) {
            KG_TRY(kg_run_callback(world, b, a));
        } else {
            KG_TRY(kg_run_builtin_force(world, b, a, &used));
        }
    }
    return KG_OK;
}

/* ---- collide ---------------------------------------------------------------------- */

/* The contacts at the start of the list that are between two bodies. */
static int kg_body_contacts(const kg_contact* contacts, int count)
{
    int n = 0;
    while (n < count && contacts[n].b != KG_NULL_INDEX) {
        n++;
    }
    return n;
}

/* collide/collide.c's stage, from last step's contacts and the state it reads; its
 * contacts go to the device once coloured (kg_color_on_host). */
static kg_result kg_stage_collide_on_host(kg_world* world, kg_cl_backend* b)
{
    /* what collide/collide.c reads of the state: poses, bounds, flags, the velocities that
     * size the speculative margins, and the centres tile contacts are anchored to */
    unsigned reads = KG_CL_BIT(XF) | KG_CL_BIT(AABB) | KG_CL_BIT(VELOCITY) | KG_CL_BIT(CENTER);
    KG_TRY(kg_cl_read_contacts(world, b));
    KG_TRY(kg_cl_tile_state_to_host(world, b));
    KG_TRY(kg_cl_flags_to_host(world, b));
    KG_TRY(kg_cl_to_host(b, &world->bodies, reads));
    KG_TRY(kg_stage_collide(world));
    int count = 0;
    kg_contact* contacts = kg_collision_contacts(world, &count);
    b->step_count = count;
    b->step_body_count = kg_body_contacts(contacts, count);
    return kg_cl_reserve_contacts(b, kg_collision_capacity(world)); /* the host's stage may have grown it */
}

/* On the device, tile maps included, unless the pairs outgrow the contact pool. */
static kg_result kg_stage_collide_cl(kg_world* world, kg_cl_backend* b)
{
    KG_TRY(kg_cl_collide_on_device(world, b, &b->step_on_device));
    return b->step_on_device ? KG_OK : kg_stage_collide_on_host(world, b);
}

/* ---- wake ------------------------------------------------------------------------- */

static kg_result kg_stage_wake_cl(kg_world* world, kg_cl_backend* b)
{
    return b->step_on_device ? kg_cl_wake_on_device(world, b, b->step_pairs) : kg_cl_wake_on_host(world, b);
}

/* ---- pre-solve -------------------------------------------------------------------- */

/* The callback over this step's contacts: on the host list where the host made them
 * (sent to the device when coloured), else read from the device into the host list the
 * step will commit to, and what it switched off written back. The bodies' flags come
 * first: whether a body sleeps is the device's. */
static kg_result kg_stage_pre_solve_cl(kg_world* world, kg_cl_backend* b)
{
    if (!world->pre_solve) {
        return KG_OK;
    }
    b->host_stale |= KG_CL_BIT(FLAGS); /* the wake stage may have woken bodies on the device */
    KG_TRY(kg_cl_flags_to_host(world, b));
    if (!b->step_on_device) {
        return kg_stage_pre_solve(world);
    }
    int count = 0, body_count = 0;
    KG_TRY(kg_cl_count_contacts(world, b, &count, &body_count));
    kg_contact* staged = kg_collision_next_list(world);
    size_t bytes = (size_t)count * sizeof *staged;
    KG_TRY(kg_cl_read(b, b->contacts[b->current ^ 1], 0, bytes, staged));
    if (kg_pre_solve_contacts(world, staged, count) > 0) {
        KG_TRY(kg_cl_write(b, b->contacts[b->current ^ 1], 0, bytes, staged, 0));
    }
    return KG_OK;
}

/* ---- solve ------------------------------------------------------------------------ */

static kg_result kg_reserve_coloring(kg_world* world, kg_cl_backend* b, int count)
{
    if (count <= b->color_capacity && b->coloring.order) {
        return KG_OK;
    }
    int capacity = count > world->def.max_contacts ? count : world->def.max_contacts;
    kg_free(b->color_scratch);
    kg_graph_coloring_free(&b->coloring);
    b->color_capacity = 0;
    b->color_scratch = kg_alloc_zeroed((size_t)capacity * sizeof *b->color_scratch);
    if (!b->color_scratch) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the colouring of %d contacts", capacity);
    }
    KG_TRY(kg_graph_coloring_init(&b->coloring, world->def.max_bodies, capacity));
    b->color_capacity = capacity;
    return KG_OK;
}

/* One pass over all constraints: the colours one launch each, then the overflow by one
 * work-item; or, when there are few constraints, all of it in one single-group launch. */
static kg_result kg_run_pass(kg_cl_backend* b, int pass)
{
    const kg_graph_coloring* g = &b->coloring;
    if (g->color_start[KG_COLOR_COUNT + 1] <= KG_CL_SINGLE_GROUP_CONTACTS) {
        KG_LAUNCH(b, SOLVE_COLORS_IN_GROUP, (int)b->group_size[KG_CL_K_SOLVE_COLORS_IN_GROUP], NULL, KG_INT(pass),
                  KG_MEM(b->color_start), KG_MEM(b->solver_params), KG_MEM(b->colored), KG_MEM(b->solver_bodies));
        return KG_OK;
    }
    for (int c = 0; c <= KG_COLOR_COUNT; ++c) {
        int serial = c == KG_COLOR_COUNT;
        int count = g->color_start[c + 1] - g->color_start[c];
        if (count == 0 || (!serial && c >= g->color_count)) {
            continue;
        }
        KG_LAUNCH(b, SOLVE_COLOR, serial ? 1 : count, NULL, KG_INT(g->color_start[c]), KG_INT(count), KG_INT(serial),
                  KG_INT(pass), KG_MEM(b->solver_params), KG_MEM(b->colored), KG_MEM(b->solver_bodies));
    }
    return KG_OK;
}

/* One sub-step's velocities: gravity, forces and damping (solve/integrate.h). */
static kg_result kg_integrate_velocities(kg_cl_backend* b, int bodies, const kg_integrate_params* ip)
{
    KG_LAUNCH(b, INTEGRATE_VELOCITIES, bodies, NULL, KG_INT(bodies), KG_VALUE(*ip), KG_MEM(b->solver_bodies),
              KG_MEM(b->velocity_steps));
    return KG_OK;
}

/* The host's contacts (after a host collide) coloured on the host, then sent to the device
 * with their colour words (carried to the next step), colour ranges and order. */
static kg_result kg_color_on_host(kg_world* world, kg_cl_backend* b)
{
    int count = 0;
    kg_contact* contacts = kg_collision_contacts(world, &count);
    KG_TRY(kg_reserve_coloring(world, b, count));
    kg_graph_color(&b->coloring, contacts, count, &world->bodies, b->color_scratch); /* the CPU solver's colours */
    KG_TRY(kg_cl_write(b, b->contacts[b->current ^ 1], 0, (size_t)count * sizeof *contacts, contacts, 0));
    KG_TRY(kg_cl_write(b, b->color_start, 0, sizeof b->coloring.color_start, b->coloring.color_start, 0));
    return kg_cl_write(b, b->order, 0, (size_t)count * sizeof(int), b->coloring.order, 0);
}

static kg_result kg_stage_solve_on_device(kg_world* world, kg_cl_backend* b, float dt)
{
    if (b->step_on_device) {
        KG_TRY(kg_cl_color_on_device(world, b, &b->step_count, &b->step_body_count));
    } else {
        KG_TRY(kg_color_on_host(world, b));
    }
    const kg_world_def* def = &world->def;
    int count = b->step_count;
    int n = def->substeps;
    float h = dt / (float)n;
    int bodies = world->bodies.high_water;
    cl_mem contacts = b->contacts[b->current ^ 1];
    kg_integrate_params ip = {def->gravity, h, def->max_linear_speed};
    b->step_params = kg_solver_params_of(def, h);
    KG_TRY(kg_cl_write(b, b->solver_params, 0, sizeof b->step_params, &b->step_params, 0));
    KG_LAUNCH(b, LOAD_BODIES, bodies, NULL, KG_INT(bodies), KG_VALUE(ip), KG_MEM(KG_A(FLAGS)), KG_MEM(KG_A(VELOCITY)),
              KG_MEM(KG_A(OMEGA)), KG_MEM(KG_A(FORCE)), KG_MEM(KG_A(TORQUE)), KG_MEM(KG_A(ROT)), KG_MEM(KG_A(CENTER)),
              KG_MEM(KG_A(XF)), KG_MEM(KG_A(LOCAL_CENTER)), KG_MEM(b->solver_bodies), KG_MEM(KG_A(DRAG)),
              KG_MEM(KG_A(INV_MASS)), KG_MEM(KG_A(INV_INERTIA)), KG_MEM(KG_A(LINEAR_DAMPING)),
              KG_MEM(KG_A(ANGULAR_DAMPING)), KG_MEM(b->velocity_steps));
    KG_LAUNCH(b, PREPARE_CONTACTS, count, NULL, KG_INT(count), KG_MEM(b->solver_params), KG_MEM(contacts),
              KG_MEM(b->constraints), KG_MEM(b->solver_bodies), KG_MEM(KG_A(INV_MASS)), KG_MEM(KG_A(INV_INERTIA)),
              KG_MEM(KG_A(XF)), KG_MEM(KG_A(CENTER)));
    KG_LAUNCH(b, GATHER_COLORED, count, NULL, KG_INT(count), KG_MEM(b->order), KG_MEM(b->constraints),
              KG_MEM(b->colored));
    KG_TRY(kg_cl_prepare_joints(world, b)); /* the joints (cl_joint.c): each pass before the contacts', as on the CPU */
    for (int step = 0; step < n; ++step) {
        KG_TRY(kg_integrate_velocities(b, bodies, &ip));
        KG_TRY(kg_cl_solve_joints(world, b, KG_PASS_WARM_START));
        KG_TRY(kg_run_pass(b, KG_PASS_WARM_START));
        KG_TRY(kg_cl_solve_joints(world, b, KG_PASS_SOLVE));
        KG_TRY(kg_run_pass(b, KG_PASS_SOLVE));
        KG_LAUNCH(b, INTEGRATE_POSITIONS, bodies, NULL, KG_INT(bodies), KG_FLOAT(h), KG_MEM(KG_A(FLAGS)),
                  KG_MEM(b->solver_bodies));
        KG_TRY(kg_cl_solve_joints(world, b, KG_PASS_RELAX));
        KG_TRY(kg_run_pass(b, KG_PASS_RELAX));
    }
    KG_TRY(kg_run_pass(b, KG_PASS_RESTITUTION));
    KG_LAUNCH(b, STORE_IMPULSES, count, NULL, KG_INT(count), KG_MEM(b->colored), KG_MEM(contacts));
    kg_rest_params rest = kg_rest_params_of(def, dt);
    KG_LAUNCH(b, STORE_BODIES, bodies, NULL, KG_INT(bodies), KG_VALUE(rest), KG_MEM(KG_A(FLAGS)),
              KG_MEM(b->solver_bodies), KG_MEM(KG_A(VELOCITY)), KG_MEM(KG_A(OMEGA)), KG_MEM(KG_A(CENTER)),
              KG_MEM(KG_A(ROT)), KG_MEM(KG_A(SHAPE)), KG_MEM(KG_A(LOCAL_CENTER)), KG_MEM(KG_A(SLEEP_TIME)));
    return KG_OK;
}

/* ---- finalize --------------------------------------------------------------------- */

/* One finalize pass over every slot (collide/continuous.h: the bullets' comes second). */
static kg_result kg_finalize_pass(kg_world* world, kg_cl_backend* b, float dt, int pass, const kg_static_list* statics)
{
    int bodies = world->bodies.high_water, continuous = world->def.enable_continuous;
    int maps = continuous ? kg_tilemaps_live_count(world) : 0;
    kg_toi_params prm = kg_toi_params_of(&world->def);
    kg_cl_collide_buffers* c = &b->collide;
    KG_LAUNCH(b, FINALIZE, bodies, NULL, KG_INT(bodies), KG_FLOAT(dt), KG_INT(pass), KG_INT(continuous), KG_VALUE(prm),
              KG_MEM(KG_A(FLAGS)), KG_MEM(KG_A(CENTER)), KG_MEM(KG_A(ROT)), KG_MEM(KG_A(VELOCITY)),
              KG_MEM(KG_A(OMEGA)), KG_MEM(KG_A(FORCE)), KG_MEM(KG_A(TORQUE)), KG_MEM(KG_A(DRAG)), KG_MEM(KG_A(XF)),
              KG_MEM(KG_A(AABB)), KG_MEM(KG_A(SHAPE)), KG_MEM(KG_A(LOCAL_CENTER)), KG_MEM(c->statics),
              KG_INT(statics->count), KG_INT(statics->large_count), KG_MEM(c->tile_maps), KG_MEM(c->tile_cells),
              KG_MEM(c->tile_protos), KG_INT(maps), KG_SHAPE_ARGS(b));
    return KG_OK;
}

static kg_result kg_stage_finalize_on_device(kg_world* world, kg_cl_backend* b, float dt)
{
    kg_static_list statics = {NULL, 0, 0, 0, 0u};
    if (world->def.enable_continuous) {
        KG_TRY(kg_cl_sync_shapes(b, world));
        KG_TRY(kg_cl_sync_statics(world, b, &statics));
        KG_TRY(kg_cl_sync_tiles(world, b));
    }
    KG_TRY(kg_finalize_pass(world, b, dt, KG_CONTINUOUS_PASS_BODIES, &statics));
    return statics.bullets > 0 ? kg_finalize_pass(world, b, dt, KG_CONTINUOUS_PASS_BULLETS, &statics) : KG_OK;
}

/* The queue drained, so that errors surface inside the step; the state is the device's. */
static kg_result kg_drain_step(kg_cl_backend* b)
{
    KG_TRY(kg_cl_finish(b));
    b->host_stale |= kg_cl_state_arrays();
    b->forces_cleared = 1;
    return KG_OK;
}

/* ---- the step --------------------------------------------------------------------- */

/* The step's contacts become the current ones, on the device (where the solver left their
 * impulses) and in the host's list, which is read back when asked for. A list built on
 * the device starts a new step of the host's list here, where nothing can fail any more. */
static void kg_commit_contacts(kg_world* world, kg_cl_backend* b)
{
    if (b->step_on_device) {
        kg_contact* previous = NULL;
        int previous_count = 0;
        kg_collision_begin_step(world, &previous, &previous_count);
        kg_collision_set_count(world, b->step_count, b->step_body_count);
    }
    b->current ^= 1;
    kg_cl_commit_tile_state(b);
    b->body_contact_count = b->step_body_count;
    b->contacts_stale = b->step_count > 0;
    b->previous_contacts_stale = 1;
}

/* The forces the step begins with, for a fallback that cannot read the device: zero after
 * a step, unless the host set some since (then they are about to be uploaded). */
static void kg_save_start_forces(kg_world* world, kg_cl_backend* b)
{
    const kg_body_pool* p = &world->bodies;
    b->start_forces_saved = (b->device_stale & (KG_CL_BIT(FORCE) | KG_CL_BIT(TORQUE))) != 0;
    if (b->start_forces_saved) {
        memcpy(b->start_force, p->force, (size_t)p->high_water * sizeof *p->force);
        memcpy(b->start_torque, p->torque, (size_t)p->high_water * sizeof *p->torque);
    }
}

kg_result kg_cl_begin_step(kg_world* world, kg_cl_backend* b)
{
    b->in_step = 1;
    b->fallback_pending = 0;
    b->checkpoint_valid = 0;
    b->step_on_device = 1;
    b->step_pairs = b->step_count = b->step_body_count = 0;
    b->joint_slots = 0;
    world->times.warm_starts_carried = -1; /* contacts are built on the device, uncounted */
    world->times.warm_starts_missed = -1;
    b->profiling = ((kg_backend_state*)world->backend_state)->profiling;
    double t = kg_now_ms();
    kg_save_start_forces(world, b);
    KG_TRY(kg_cl_to_device(b, &world->bodies, KG_CL_ALL_ARRAYS));
    KG_TRY(kg_cl_save_checkpoint(b, &world->bodies));
    b->checkpoint_valid = 1;
    kg_time_bracket(world, "upload", t);
    return KG_OK;
}

kg_result kg_cl_run_stage(kg_world* world, kg_cl_backend* b, kg_stage stage, float dt)
{
    switch (stage) {
    case KG_STAGE_FORCES: return kg_stage_forces(world, b);
    case KG_STAGE_COLLIDE: return kg_stage_collide_cl(world, b);
    case KG_STAGE_WAKE: return kg_stage_wake_cl(world, b);
    case KG_STAGE_PRE_SOLVE: return kg_stage_pre_solve_cl(world, b);
    case KG_STAGE_SOLVE: return kg_stage_solve_on_device(world, b, dt);
    case KG_STAGE_FINALIZE: return kg_stage_finalize_on_device(world, b, dt);
    case KG_STAGE_SLEEP: return kg_cl_sleep_on_device(world, b, b->step_count);
    case KG_STAGE_COUNT: break;
    }
    return KG_OK;
}

const char* kg_cl_stage_label(const kg_world* world, const kg_cl_backend* b, kg_stage stage)
{
    int on_host = !b->step_on_device && (stage == KG_STAGE_COLLIDE || stage == KG_STAGE_WAKE);
    if (((const kg_backend_state*)world->backend_state)->profiling && !on_host) {
        return NULL; /* its kernels are timed by their events */
    }
    return stage == KG_STAGE_COLLIDE && on_host ? "collide (host)" : kg_stage_name(stage);
}

kg_result kg_cl_end_step(kg_world* world, kg_cl_backend* b)
{
    double t = kg_now_ms();
    KG_TRY(kg_drain_step(b));
    kg_time_bracket(world, "finish", t);
    KG_TRY(kg_check_fallback(b)); /* only callbacks request one; checked before the commit all the same */
    KG_TRY(kg_cl_joints_to_host(world, b)); /* the joints' impulses, for the next step and the getters */
    kg_commit_contacts(world, b);
    if (b->profiling) {
        kg_add_kernel_times(world, b);
    }
    b->steps_since_snapshot += 1;
    return KG_OK;
}
#endif
