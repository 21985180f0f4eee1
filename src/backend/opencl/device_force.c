/* Device force applicators: one force function given twice, as OpenCL C source for the
 * device and as the same code compiled as C for the CPU. Each is a C callback applicator
 * (forces.c keeps its slot, its body list and its place in the order) whose callback runs
 * the C function; the OpenCL backend recognises it by that callback and launches the
 * compiled source instead. */
#include "backend/backend_state.h"
#include "core/alloc.h"
#include "core/error.h"
#include "kgyro/force.h"
#include "solve/force_body.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

kg_device_force_def kg_default_device_force_def(void)
{
    kg_device_force_def def;
    memset(&def, 0, sizeof def);
    return def;
}

void kg_device_force_on_cpu(kg_world* world, const kg_body* bodies, int count, void* user_data)
{
    const kg_device_force* f = user_data;
    kg_body_pool* p = &world->bodies;
    for (int k = 0; k < count; ++k) {
        kg_force_target t = {bodies[k].index, 1u};
        kg_apply_device_force(t, f->cpu_fn, f->params.values, p->flags, p->center, p->rot, p->velocity, p->omega,
                              p->mass, p->inertia, p->force, p->torque);
    }
}

kg_device_force* kg_device_force_of(kg_world* world, int slot)
{
    const kg_backend_state* s = world->backend_state;
    const kg_applicator_slot* a = &world->applicators[slot];
    kg_device_force* f = s && s->forces ? &s->forces[slot] : NULL;
    int is_device_force = f && a->kind == KG_APPLICATOR_USER && a->fn == kg_device_force_on_cpu && a->user_data == f;
    return is_device_force ? f : NULL;
}

static int kg_is_identifier(const char* name)
{
    size_t n = name ? strlen(name) : 0;
    if (n == 0 || n > 63 || !(isalpha((unsigned char)name[0]) || name[0] == '_')) {
        return 0;
    }
    for (size_t i = 1; i < n; ++i) {
        if (!(isalnum((unsigned char)name[i]) || name[i] == '_')) {
            return 0;
        }
    }
    return 1;
}

static int kg_params_finite(const float* params, int count)
{
    for (int i = 0; i < count; ++i) {
        if (!isfinite(params[i])) {
            return 0;
        }
    }
    return 1;
}

static void kg_clear_device_force(kg_device_force* f)
{
    kg_free(f->source);
    kg_free(f->function_name);
    memset(f, 0, sizeof *f);
}

static kg_result kg_validate_device_force(const kg_world* world, const kg_device_force_def* def)
{
    if (!world || !def) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "device force applicator: NULL argument");
    }
    if (!def->source || !def->cpu_fn || !kg_is_identifier(def->function_name)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "device force applicator: needs source, a C function and a "
                       "function name that is a C identifier of at most 63 characters");
    }
    if (def->param_count < 0 || def->param_count > KG_DEVICE_FORCE_MAX_PARAMS ||
        !kg_params_finite(def->params, def->param_count)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "device force applicator: 0 to %d finite parameters",
                       KG_DEVICE_FORCE_MAX_PARAMS);
    }
    return KG_OK;
}

kg_result kg_add_device_force_applicator(kg_world* world, const kg_device_force_def* def, kg_applicator* out)
{
    kg_result r = kg_validate_device_force(world, def);
    if (r != KG_OK) {
        return r;
    }
    kg_backend_state* s = world->backend_state;
    char* source = kg_copy_text(def->source);
    char* name = kg_copy_text(def->function_name);
    r = (source && name) ? kg_add_force_applicator(world, kg_device_force_on_cpu, def->bodies, def->body_count, NULL, out)
                         : kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot copy a device force source");
    if (r != KG_OK) {
        kg_free(source);
        kg_free(name);
        return r;
    }
    kg_device_force* f = &s->forces[out->index];
    kg_clear_device_force(f);
    f->cpu_fn = def->cpu_fn;
    f->source = source;
    f->function_name = name;
    memcpy(f->params.values, def->params, (size_t)def->param_count * sizeof *def->params);
    world->applicators[out->index].user_data = f;
    r = kg_backend_prepare_device_force(world, (int)out->index);
    if (r != KG_OK) {
        kg_remove_applicator(world, *out);
        kg_clear_device_force(f);
    }
    return r;
}

kg_result kg_set_device_force_params(kg_world* world, kg_applicator applicator, const float* params, int count)
{
    if (!world || applicator.index >= (uint32_t)world->def.max_applicators ||
        world->applicators[applicator.index].generation != applicator.generation ||
        !kg_device_force_of(world, (int)applicator.index)) {
        return kg_fail(KG_ERROR_INVALID_HANDLE, "not a live device force applicator");
    }
    if (count < 0 || count > KG_DEVICE_FORCE_MAX_PARAMS || (count > 0 && !params) || !kg_params_finite(params, count)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "device force parameters: 0 to %d finite values",
                       KG_DEVICE_FORCE_MAX_PARAMS);
    }
    kg_device_force* f = kg_device_force_of(world, (int)applicator.index);
    memset(&f->params, 0, sizeof f->params);
    memcpy(f->params.values, params, (size_t)count * sizeof *params);
    return KG_OK;
}

kg_result kg_backend_state_create(kg_world* world)
{
    kg_backend_state* s = kg_alloc_zeroed(sizeof *s);
    if (s) {
        s->forces = kg_alloc_zeroed((size_t)(world->def.max_applicators + 1) * sizeof *s->forces);
    }
    if (!s || !s->forces) {
        kg_free(s);
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the backend state");
    }
    const char* profile = getenv("KGYRO_PROFILE");
    s->profiling = profile && *profile && strcmp(profile, "0") != 0;
    world->backend_state = s;
    return KG_OK;
}

void kg_backend_state_free(kg_world* world)
{
    kg_backend_state* s = world->backend_state;
    if (!s) {
        return;
    }
    for (int i = 0; i <= world->def.max_applicators; ++i) {
        kg_clear_device_force(&s->forces[i]);
    }
    kg_free(s->forces);
    kg_free(s);
    world->backend_state = NULL;
}
