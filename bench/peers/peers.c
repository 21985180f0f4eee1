/* The engine-independent half of the peer adapters: walking a kg_scene, driving pivoted
 * kinematic bodies, and the totals that show every engine got the same scene. */
#include "kg_peers.h"
#include "peer_adapter.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef KG_PEER_BOX2D_MISSING
#define KG_PEER_BOX2D_MISSING "not built"
#endif
#ifndef KG_PEER_CHIPMUNK_MISSING
#define KG_PEER_CHIPMUNK_MISSING "not built"
#endif

typedef struct kg_peer_pivot {
    int body;
    kg_vec2 point;
} kg_peer_pivot;

struct kg_peer_world {
    const kg_peer_adapter* adapter;
    void* impl;
    int body_count;
    int pivot_count;
    kg_peer_pivot* pivots;
};

static const char* const kEngineNames[KG_PEER_ENGINE_COUNT] = {"box2d", "chipmunk"};
static char kg_peer_error[512];

static kg_result kg_peer_fail(kg_result result, const char* format, ...)
{
    va_list args;
    va_start(args, format);
    vsnprintf(kg_peer_error, sizeof kg_peer_error, format, args);
    va_end(args);
    return result;
}

static const kg_peer_adapter* kg_peer_adapter_of(kg_peer_engine engine)
{
    switch (engine) {
#ifdef KG_PEER_HAVE_BOX2D
    case KG_PEER_BOX2D:
        return &kg_box2d_adapter;
#endif
#ifdef KG_PEER_HAVE_CHIPMUNK
    case KG_PEER_CHIPMUNK:
        return &kg_chipmunk_adapter;
#endif
    default:
        return NULL;
    }
}

static const char* kg_peer_missing_reason(kg_peer_engine engine)
{
    return engine == KG_PEER_BOX2D ? KG_PEER_BOX2D_MISSING : KG_PEER_CHIPMUNK_MISSING;
}

static int kg_peer_engine_valid(kg_peer_engine engine)
{
    return (int)engine >= 0 && engine < KG_PEER_ENGINE_COUNT;
}

const char* kg_peer_name(kg_peer_engine engine)
{
    return kg_peer_engine_valid(engine) ? kEngineNames[engine] : "unknown";
}

int kg_peer_find(const char* name)
{
    for (int i = 0; name && i < KG_PEER_ENGINE_COUNT; ++i) {
        if (strcmp(name, kEngineNames[i]) == 0) {
            return i;
        }
    }
    return -1;
}

int kg_peer_available(kg_peer_engine engine) { return kg_peer_adapter_of(engine) != NULL; }

const char* kg_peer_describe(kg_peer_engine engine, int threads)
{
    if (!kg_peer_engine_valid(engine)) {
        return "unknown engine";
    }
    const kg_peer_adapter* adapter = kg_peer_adapter_of(engine);
    return adapter ? adapter->describe(threads) : kg_peer_missing_reason(engine);
}

const char* kg_peer_last_error(void) { return kg_peer_error; }

/* The density that gives a shaped body its overriding mass, so that the engine derives
 * the matching rotational inertia from the shape as kgyro does. */
static float kg_peer_density(const kg_body_def* def)
{
    kg_mass_data unit;
    if (def->mass <= 0.0f || def->shape.type == KG_SHAPE_NONE || kg_shape_mass(&def->shape, 1.0f, &unit) != KG_OK ||
        !(unit.mass > 0.0f)) {
        return def->density;
    }
    return def->mass / unit.mass;
}

/* Mass data of shapes [0, count) at their densities, as kgyro computes a compound body's:
 * the masses summed, the centre their weighted mean, the inertia about it (parallel axis). */
static kg_mass_data kg_peer_compound_mass(const kg_body_shape_def* shapes, int count)
{
    kg_mass_data parts[KG_PEER_MAX_SHAPES];
    double mass = 0.0, x = 0.0, y = 0.0, inertia = 0.0;
    for (int k = 0; k < count; ++k) {
        kg_mass_data unit = {0.0f, {0.0f, 0.0f}, 0.0f};
        kg_shape_mass(&shapes[k].geometry, 1.0f, &unit);
        parts[k] = unit;
        double m = (double)unit.mass * shapes[k].density;
        mass += m;
        x += m * unit.center.x;
        y += m * unit.center.y;
    }
    x = mass > 0.0 ? x / mass : 0.0;
    y = mass > 0.0 ? y / mass : 0.0;
    for (int k = 0; k < count; ++k) {
        double m = (double)parts[k].mass * shapes[k].density, dx = parts[k].center.x - x, dy = parts[k].center.y - y;
        inertia += (double)parts[k].inertia * shapes[k].density + m * (dx * dx + dy * dy);
    }
    kg_mass_data out = {(float)mass, {(float)x, (float)y}, (float)inertia};
    return out;
}

/* Body i's every shape into shapes (room for KG_PEER_MAX_SHAPES) and its peer body. */
static const char* kg_peer_compound(const kg_scene* scene, int i, kg_body_shape_def* shapes, kg_peer_body* body)
{
    int count = kg_scene_body_shape_count(scene, i);
    if (count > KG_PEER_MAX_SHAPES) {
        return "more shapes than the peer adapters take";
    }
    if (body->def->mass > 0.0f) {
        return "a compound body with a mass override (give its shapes densities)";
    }
    for (int k = 0; k < count; ++k) {
        kg_scene_get_body_shape(scene, i, k, &shapes[k]);
    }
    body->shapes = shapes;
    body->shape_count = count;
    body->mass = kg_peer_compound_mass(shapes, count);
    return NULL;
}

static kg_result kg_peer_add_bodies(kg_peer_world* world, const kg_scene* scene)
{
    kg_body_shape_def shapes[KG_PEER_MAX_SHAPES];
    for (int i = 0; i < world->body_count; ++i) {
        const kg_body_def* def = kg_scene_body_def(scene, i);
        kg_peer_body body = {def, kg_peer_density(def), NULL, 0, {0.0f, {0.0f, 0.0f}, 0.0f}};
        const char* why = NULL;
        if (kg_scene_body_chain_count(scene, i) > 0) {
            why = "chains are not supported by the peer adapters"; /* left out, the worlds would differ */
        } else if (kg_scene_body_shape_count(scene, i) > 1) {
            why = kg_peer_compound(scene, i, shapes, &body);
        }
        why = why ? why : world->adapter->add_body(world->impl, &body);
        if (why) {
            return kg_peer_fail(KG_ERROR_UNSUPPORTED, "%s: body %d ('%s'): %s", world->adapter->name, i,
                                kg_scene_body_name(scene, i), why);
        }
    }
    return KG_OK;
}

static kg_result kg_peer_add_joints(kg_peer_world* world, const kg_scene* scene)
{
    for (int i = 0; i < kg_scene_joint_count(scene); ++i) {
        const char* why = world->adapter->add_joint(world->impl, kg_scene_get_joint(scene, i));
        if (why) {
            return kg_peer_fail(KG_ERROR_UNSUPPORTED, "%s: joint %d: %s", world->adapter->name, i, why);
        }
    }
    return KG_OK;
}

static kg_result kg_peer_collect_pivots(kg_peer_world* world, const kg_scene* scene)
{
    for (int i = 0; i < world->body_count; ++i) {
        kg_vec2 point;
        if (!kg_scene_body_pivot(scene, i, &point)) {
            continue;
        }
        kg_peer_pivot* grown = realloc(world->pivots, (size_t)(world->pivot_count + 1) * sizeof *grown);
        if (!grown) {
            return kg_peer_fail(KG_ERROR_OUT_OF_MEMORY, "%s: out of memory", world->adapter->name);
        }
        world->pivots = grown;
        world->pivots[world->pivot_count++] = (kg_peer_pivot){i, point};
    }
    return KG_OK;
}

static kg_result kg_peer_fill(kg_peer_world* world, const kg_scene* scene, int threads)
{
    /* kg_scene_world_def has no const form; the def is only read here. */
    const kg_world_def* def = kg_scene_world_def((kg_scene*)scene);
    kg_peer_setup setup = {def->gravity, def->restitution_threshold, def->linear_slop, world->body_count, threads};
    world->impl = world->adapter->create(&setup);
    if (!world->impl) {
        return kg_peer_fail(KG_ERROR_OUT_OF_MEMORY, "%s: cannot create the world", world->adapter->name);
    }
    kg_result r = kg_peer_add_bodies(world, scene);
    r = r == KG_OK ? kg_peer_add_joints(world, scene) : r;
    return r == KG_OK ? kg_peer_collect_pivots(world, scene) : r;
}

kg_result kg_peer_create(kg_peer_engine engine, const kg_scene* scene, int threads, kg_peer_world** out)
{
    if (!out || !scene || !kg_peer_engine_valid(engine)) {
        return kg_peer_fail(KG_ERROR_INVALID_ARGUMENT, "kg_peer_create: bad arguments");
    }
    *out = NULL;
    const kg_peer_adapter* adapter = kg_peer_adapter_of(engine);
    if (!adapter) {
        return kg_peer_fail(KG_ERROR_UNSUPPORTED, "%s: %s", kg_peer_name(engine), kg_peer_missing_reason(engine));
    }
    if (kg_scene_force_count(scene) > 0) {
        return kg_peer_fail(KG_ERROR_UNSUPPORTED, "%s: scene force applicators are not mapped to the peer engines",
                            adapter->name);
    }
    kg_peer_world* world = calloc(1, sizeof *world);
    if (!world) {
        return kg_peer_fail(KG_ERROR_OUT_OF_MEMORY, "%s: out of memory", adapter->name);
    }
    world->adapter = adapter;
    world->body_count = kg_scene_body_count(scene);
    kg_result r = kg_peer_fill(world, scene, threads);
    if (r != KG_OK) {
        kg_peer_destroy(world);
        return r;
    }
    *out = world;
    return KG_OK;
}

void kg_peer_destroy(kg_peer_world* world)
{
    if (!world) {
        return;
    }
    if (world->impl) {
        world->adapter->destroy(world->impl);
    }
    free(world->pivots);
    free(world);
}

/* As kg_scene_step does it: the velocity that carries the rotation centre along the
 * chord of its circle about the pivot in one step, so the body turns rigidly about the
 * pivot instead of drifting outwards along the tangent. */
static void kg_peer_drive_pivot(kg_peer_world* world, const kg_peer_pivot* pivot, float dt)
{
    kg_body_state state;
    world->adapter->get_state(world->impl, pivot->body, &state);
    kg_vec2 center = world->adapter->rotation_center(world->impl, pivot->body);
    float turn = state.angular_velocity * dt;
    float c = cosf(turn), s = sinf(turn);
    kg_vec2 r = {center.x - pivot->point.x, center.y - pivot->point.y};
    kg_vec2 next = {pivot->point.x + c * r.x - s * r.y, pivot->point.y + s * r.x + c * r.y};
    kg_vec2 velocity = {(next.x - center.x) / dt, (next.y - center.y) / dt};
    world->adapter->set_velocity(world->impl, pivot->body, velocity);
}

void kg_peer_step(kg_peer_world* world, float dt)
{
    for (int i = 0; i < world->pivot_count; ++i) {
        kg_peer_drive_pivot(world, &world->pivots[i], dt);
    }
    world->adapter->step(world->impl, dt);
}

int kg_peer_body_count(const kg_peer_world* world) { return world ? world->body_count : 0; }

void kg_peer_get_states(const kg_peer_world* world, kg_body_state* out)
{
    for (int i = 0; i < world->body_count; ++i) {
        world->adapter->get_state(world->impl, i, &out[i]);
    }
}

double kg_peer_dynamic_mass(const kg_peer_world* world)
{
    double total = 0.0;
    for (int i = 0; i < world->body_count; ++i) {
        total += world->adapter->mass(world->impl, i);
    }
    return total;
}

kg_aabb kg_peer_bounds(const kg_peer_world* world)
{
    kg_aabb all = {{INFINITY, INFINITY}, {-INFINITY, -INFINITY}};
    for (int i = 0; i < world->body_count; ++i) {
        kg_aabb box = world->adapter->bounds(world->impl, i);
        all.lower.x = fminf(all.lower.x, box.lower.x);
        all.lower.y = fminf(all.lower.y, box.lower.y);
        all.upper.x = fmaxf(all.upper.x, box.upper.x);
        all.upper.y = fmaxf(all.upper.y, box.upper.y);
    }
    return all;
}
