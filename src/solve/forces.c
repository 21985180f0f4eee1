#include "solve/forces.h"
#include "core/alloc.h"
#include "core/error.h"

#include <math.h>
#include <string.h>

static kg_result kg_add_applicator(kg_world* world, const kg_applicator_slot* proto, const kg_body* bodies, int count,
                                   kg_applicator* out)
{
    if (!world || !out || count < 0 || (count > 0 && !bodies)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "force applicator: bad arguments");
    }
    if (kg_world_refuses(world, "adding a force applicator", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    if (count > world->def.max_bodies) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "force applicator: %d bodies listed, more than max_bodies (%d)",
                       count, world->def.max_bodies);
    }
    int slot = -1;
    for (int i = 0; i < world->def.max_applicators && slot < 0; ++i) {
        if (world->applicators[i].kind == KG_APPLICATOR_FREE) {
            slot = i;
        }
    }
    if (slot < 0) {
        return kg_fail(KG_ERROR_POOL_FULL, "applicator pool full (max_applicators = %d)", world->def.max_applicators);
    }
    kg_body* copy = NULL;
    if (count > 0) {
        copy = kg_alloc_zeroed((size_t)count * sizeof *copy);
        if (!copy) {
            return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot copy the applicator's body list");
        }
        memcpy(copy, bodies, (size_t)count * sizeof *copy);
    }
    kg_applicator_slot* a = &world->applicators[slot];
    kg_u32 generation = a->generation + 1u == 0u ? 1u : a->generation + 1u; /* 0 never names one */
    *a = *proto;
    a->generation = generation;
    a->bodies = copy;
    a->body_count = count;
    out->index = (uint32_t)slot;
    out->generation = generation;
    kg_world_wake_all(world); /* sleeping bodies rest under the forces they fell asleep with */
    return KG_OK;
}

kg_result kg_add_force_applicator(kg_world* world, kg_force_fn* fn, const kg_body* bodies, int count,
                                  void* user_data, kg_applicator* out)
{
    if (!fn) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "force applicator: NULL callback");
    }
    kg_applicator_slot proto = {KG_APPLICATOR_USER, 0, fn, user_data, {0.0f, 0.0f}, 0.0f, 0.0f, NULL, 0};
    return kg_add_applicator(world, &proto, bodies, count, out);
}

kg_result kg_add_gravity_applicator(kg_world* world, kg_vec2 acceleration, const kg_body* bodies, int count,
                                    kg_applicator* out)
{
    if (!isfinite(acceleration.x) || !isfinite(acceleration.y)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "gravity applicator: acceleration must be finite");
    }
    kg_applicator_slot proto = {KG_APPLICATOR_GRAVITY, 0, NULL, NULL, acceleration, 0.0f, 0.0f, NULL, 0};
    return kg_add_applicator(world, &proto, bodies, count, out);
}

kg_result kg_add_wind_applicator(kg_world* world, kg_vec2 direction, float strength, float drag,
                                 const kg_body* bodies, int count, kg_applicator* out)
{
    /* scaled down first, so a huge finite direction does not overflow to no direction */
    float largest = fmaxf(fabsf(direction.x), fabsf(direction.y));
    kg_vec2 unit = largest > 0.0f && isfinite(largest) ? kg_normalize(kg_scale(1.0f / largest, direction)) : kg_v2(0.0f, 0.0f);
    int direction_ok = isfinite(direction.x) && isfinite(direction.y) && (kg_length_sq(unit) > 0.0f || strength == 0.0f);
    if (!direction_ok || !isfinite(strength) || !isfinite(drag) || drag < 0.0f) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT,
                       "wind applicator: direction must be finite and non-zero, strength finite, drag >= 0");
    }
    kg_applicator_slot proto = {KG_APPLICATOR_WIND, 0, NULL, NULL, unit, strength, drag, NULL, 0};
    return kg_add_applicator(world, &proto, bodies, count, out);
}

kg_result kg_remove_applicator(kg_world* world, kg_applicator applicator)
{
    if (!world) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_remove_applicator: NULL world");
    }
    if (kg_world_refuses(world, "kg_remove_applicator", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    if (applicator.index >= (uint32_t)world->def.max_applicators) {
        return kg_fail(KG_ERROR_INVALID_HANDLE, "applicator handle does not name an applicator");
    }
    kg_applicator_slot* a = &world->applicators[applicator.index];
    if (a->kind == KG_APPLICATOR_FREE || a->generation != applicator.generation) {
        return kg_fail(KG_ERROR_INVALID_HANDLE, "applicator handle is stale");
    }
    kg_free(a->bodies);
    kg_u32 generation = a->generation;
    memset(a, 0, sizeof *a);
    a->generation = generation;
    kg_world_wake_all(world);
    return KG_OK;
}

int kg_applicator_targets(kg_world* world, const kg_applicator_slot* a)
{
    const kg_body_pool* p = &world->bodies;
    kg_body* out = world->handle_scratch;
    int n = 0;
    if (!a->bodies) {
        for (int i = 0; i < p->high_water; ++i) {
            if (kg_pool_alive(p, i) && !kg_pool_asleep(p, i)) {
                out[n].index = (uint32_t)i;
                out[n++].generation = p->generation[i];
            }
        }
        return n;
    }
    for (int k = 0; k < a->body_count; ++k) {
        if (kg_body_is_valid(world, a->bodies[k]) && !kg_pool_asleep(p, (int)a->bodies[k].index)) {
            out[n++] = a->bodies[k];
        }
    }
    return n;
}

kg_builtin_force kg_builtin_force_of(const kg_applicator_slot* a)
{
    kg_builtin_force f = {a->vector, a->strength, a->drag, a->kind == KG_APPLICATOR_GRAVITY, 0};
    return f;
}

static void kg_apply_builtin(kg_body_pool* p, const kg_applicator_slot* a, const kg_body* targets, int count)
{
    kg_builtin_force f = kg_builtin_force_of(a);
    for (int k = 0; k < count; ++k) {
        kg_force_target t = {targets[k].index, 1u};
        kg_builtin_force_on(t, f, p->flags, p->mass, p->force, p->drag);
    }
}

void kg_stage_apply_forces(kg_world* world)
{
    for (int k = 0; k < world->def.max_applicators; ++k) {
        const kg_applicator_slot* a = &world->applicators[k];
        if (a->kind == KG_APPLICATOR_FREE) {
            continue;
        }
        int count = kg_applicator_targets(world, a);
        if (a->kind == KG_APPLICATOR_USER) {
            a->fn(world, world->handle_scratch, count, a->user_data);
        } else {
            kg_apply_builtin(&world->bodies, a, world->handle_scratch, count);
        }
    }
}
