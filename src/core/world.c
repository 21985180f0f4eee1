#include "core/world.h"
#include "core/parallel.h"
#include "backend/backend.h"
#include "core/alloc.h"
#include "core/error.h"
#include "core/generation.h"
#include "collide/collide.h"
#include "collide/events.h"
#include "collide/query_index.h"
#include "collide/tilemap.h"
#include "core/joint.h"
#include "solve/sleep.h"
#include "solve/solver.h"

#include <math.h>
#include <stdatomic.h>
#include <string.h>

kg_u32 kg_next_world_tag(void)
{
    static atomic_uint worlds_made;
    return (kg_u32)(atomic_fetch_add(&worlds_made, 1u) % 255u) + 1u;
}

/* Seeds every generation the world hands out with its tag (core/generation.h). */
static void kg_world_tag_slots(kg_world* w)
{
    kg_u32 tag = kg_next_world_tag();
    kg_generation_seed(w->bodies.generation, 0, w->bodies.capacity, tag);
    w->shapes.tag = tag;
    kg_generation_seed(w->shapes.generation, 0, w->shapes.capacity, tag);
    for (int i = 0; i <= w->def.max_applicators; ++i) {
        w->applicators[i].generation = kg_generation_first(tag);
    }
}

kg_world_def kg_default_world_def(void)
{
    kg_world_def def;
    memset(&def, 0, sizeof def);
    def.gravity = kg_v2(0.0f, -10.0f);
    def.max_bodies = 4096;
    def.max_contacts = 0; /* 0 = 4 per body: how far the contact pool grows before it warns */
    def.max_applicators = 32;
    /* Soft contacts sag by load / (mass * (2 pi hertz)^2) and hertz must stay under a
     * quarter of the sub-step rate. 4 sub-steps at 45 Hz, damping ratio 20 (static
     * contacts twice as stiff, up to that quarter) hold a base-100 pyramid within 1 cm
     * after it sags 0.5 m, at half the cost of 8 (docs/design.md has the measurements). */
    def.substeps = 4;
    def.contact_hertz = 45.0f;
    def.contact_damping_ratio = 20.0f;
    def.max_push_out_speed = 3.0f;
    def.restitution_threshold = 1.0f;
    def.linear_slop = 0.005f;
    def.speculative_distance = 0.02f;
    def.max_linear_speed = 400.0f;
    /* Box2D's values: slow enough that a resting pile's creep is rest, and half a second
     * so that a ball at the top of its bounce is not taken for one at rest. */
    def.enable_sleep = 1;
    def.enable_continuous = 1;
    def.sleep_speed = 0.05f;
    def.time_to_sleep = 0.5f;
    def.hit_event_threshold = 1.0f; /* Box2D's: a thud a game would play a sound for */
    def.backend = KG_BACKEND_AUTO;
    def.threads = 1;
    return def;
}

static int kg_positive_finite(float v) { return isfinite(v) && v > 0.0f; }

static kg_result kg_validate_world_def(const kg_world_def* d)
{
    if (!isfinite(d->gravity.x) || !isfinite(d->gravity.y)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "world gravity must be finite");
    }
    if (d->max_bodies <= 0 || d->max_bodies > (1 << 26) || d->max_applicators < 0 || d->max_contacts < 0) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "world capacities must be positive (max_bodies %d, max_contacts %d)",
                       d->max_bodies, d->max_contacts);
    }
    if (d->substeps < 1 || d->substeps > 64) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "substeps must be in [1, 64] (got %d)", d->substeps);
    }
    if (!kg_positive_finite(d->contact_hertz) || !kg_positive_finite(d->contact_damping_ratio) ||
        !kg_positive_finite(d->max_push_out_speed) || !kg_positive_finite(d->max_linear_speed) ||
        !isfinite(d->restitution_threshold) || d->restitution_threshold < 0.0f || !isfinite(d->linear_slop) ||
        d->linear_slop < 0.0f || !isfinite(d->speculative_distance) || d->speculative_distance < 0.0f ||
        !isfinite(d->sleep_speed) || d->sleep_speed < 0.0f || !kg_positive_finite(d->time_to_sleep) ||
        !isfinite(d->hit_event_threshold) || d->hit_event_threshold < 0.0f) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "world solver parameters must be finite and positive");
    }
    if (d->threads < 0 || d->threads > KG_MAX_THREADS || d->device_index < 0 || d->backend < KG_BACKEND_AUTO ||
        d->backend > KG_BACKEND_OPENCL) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "invalid backend, device index or thread count");
    }
    return KG_OK;
}

kg_result kg_world_def_check(const kg_world_def* def) { return kg_validate_world_def(def); }

kg_result kg_create_world(const kg_world_def* def, kg_world** out_world)
{
    if (!def || !out_world) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_create_world: NULL argument");
    }
    *out_world = NULL;
    kg_result r = kg_validate_world_def(def);
    if (r != KG_OK) {
        return r;
    }
    kg_world* w = kg_alloc_zeroed(sizeof *w);
    if (!w) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate a world");
    }
    w->def = *def;
    if (w->def.max_contacts == 0) {
        w->def.max_contacts = 4 * def->max_bodies;
    }
    /* From here max_contacts is the contact pool's budget: kg_collision_create sizes the
     * pool from the body count instead and keeps def.max_contacts at its capacity, which
     * the solver (created after it) and the OpenCL backend size their arrays from. */
    if (w->def.threads == 0) {
        w->def.threads = 1;
    }
    r = kg_body_pool_init(&w->bodies, w->def.max_bodies);
    if (r == KG_OK) {
        r = kg_shape_pool_init(&w->shapes, w->def.max_bodies);
    }
    if (r == KG_OK) {
        w->applicators = kg_alloc_zeroed((size_t)(w->def.max_applicators + 1) * sizeof *w->applicators);
        w->handle_scratch = kg_alloc_zeroed((size_t)w->def.max_bodies * sizeof *w->handle_scratch);
        r = (w->applicators && w->handle_scratch) ? KG_OK : kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate a world");
    }
    if (r == KG_OK) {
        kg_world_tag_slots(w);
    }
    if (r == KG_OK && w->def.threads > 1) {
        w->threads = kg_thread_pool_create(w->def.threads);
        r = w->threads ? KG_OK : kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot start %d threads", w->def.threads);
    }
    if (r == KG_OK) {
        r = kg_collision_create(w);
    }
    if (r == KG_OK) {
        r = kg_solver_create(w);
    }
    if (r == KG_OK) {
        r = kg_sleep_create(w);
    }
    if (r == KG_OK) {
        r = kg_backend_select(w);
    }
    if (r != KG_OK) {
        kg_destroy_world(w);
        return r;
    }
    *out_world = w;
    return KG_OK;
}

void kg_destroy_world(kg_world* world)
{
    if (!world) {
        return;
    }
    if (world->backend && world->backend->destroy) {
        world->backend->destroy(world);
    }
    kg_solver_destroy(world);
    kg_joints_destroy(world);
    kg_sleep_destroy(world);
    kg_tilemaps_destroy(world);
    kg_collision_destroy(world);
    kg_events_destroy(world);
    kg_sensors_destroy(world);
    kg_query_index_destroy(world->query_index);
    kg_thread_pool_destroy(world->threads);
    for (int i = 0; world->applicators && i < world->def.max_applicators; ++i) {
        kg_free(world->applicators[i].bodies);
    }
    kg_free(world->applicators);
    kg_free(world->handle_scratch);
    kg_body_pool_free(&world->bodies);
    kg_shape_pool_free(&world->shapes);
    kg_free(world);
}

kg_result kg_world_set_gravity(kg_world* world, kg_vec2 gravity)
{
    if (!world || !isfinite(gravity.x) || !isfinite(gravity.y)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "gravity must be finite");
    }
    if (kg_world_refuses(world, "kg_world_set_gravity", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    world->def.gravity = gravity;
    kg_world_wake_all(world);
    return KG_OK;
}

kg_vec2 kg_world_get_gravity(const kg_world* world) { return world ? world->def.gravity : kg_v2(0.0f, 0.0f); }

const kg_world_def* kg_world_get_def(const kg_world* world) { return world ? &world->def : NULL; }

int kg_world_body_count(const kg_world* world) { return world ? world->bodies.count : 0; }

kg_result kg_world_get_bodies(const kg_world* world, kg_body* out, int capacity, int* count)
{
    if (!world || !count || (capacity > 0 && !out) || capacity < 0) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_world_get_bodies: bad arguments");
    }
    const kg_body_pool* p = &world->bodies;
    int n = 0;
    for (int i = 0; i < p->high_water && n < capacity; ++i) {
        if (kg_pool_alive(p, i)) {
            out[n].index = (uint32_t)i;
            out[n].generation = p->generation[i];
            n++;
        }
    }
    *count = n;
    return KG_OK;
}

kg_backend kg_world_backend(const kg_world* world) { return world ? world->backend->kind : KG_BACKEND_CPU; }

kg_result kg_world_get_stage_times(const kg_world* world, kg_stage_times* out)
{
    if (!world || !out) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_world_get_stage_times: NULL argument");
    }
    *out = world->times;
    return KG_OK;
}

int kg_world_refuses(const kg_world* world, const char* call, int level)
{
    if (!world || world->lock < level) {
        return 0;
    }
    kg_fail(KG_ERROR_LOCKED, "%s: called from a %s callback inside kg_world_step, where the world cannot change%s",
            call, world->lock == KG_LOCK_ALL ? "pre-solve" : "force applicator",
            world->lock == KG_LOCK_ALL ? "" : " this way (apply forces and set velocities there; create and destroy "
                                              "between steps)");
    return 1;
}

int kg_world_resolve(const kg_world* world, kg_body body)
{
    if (!world) {
        kg_fail(KG_ERROR_INVALID_ARGUMENT, "NULL world");
        return -1;
    }
    return kg_body_pool_resolve(&world->bodies, body);
}
