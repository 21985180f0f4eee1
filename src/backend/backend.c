#include "backend/backend.h"
#include "core/error.h"

#include <stdlib.h>
#include <string.h>

/* KGYRO_BACKEND=cpu|opencl|auto overrides the world definition. */
static kg_backend kg_requested_backend(const kg_world_def* def)
{
    const char* env = getenv("KGYRO_BACKEND");
    if (env && strcmp(env, "cpu") == 0) {
        return KG_BACKEND_CPU;
    }
    if (env && strcmp(env, "opencl") == 0) {
        return KG_BACKEND_OPENCL;
    }
    if (env && strcmp(env, "auto") == 0) {
        return KG_BACKEND_AUTO;
    }
    return def->backend;
}

kg_result kg_backend_select(kg_world* world)
{
    kg_backend wanted = kg_requested_backend(&world->def);
    world->backend = &kg_cpu_backend;
    if (wanted == KG_BACKEND_OPENCL) {
        kg_warn_once("no-opencl", "the OpenCL backend is not available in this build; using the CPU backend");
    }
    return KG_OK;
}
