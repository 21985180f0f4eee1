#include "sim.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int kg_ends_with(const char* text, const char* suffix)
{
    size_t length = strlen(text), suffix_length = strlen(suffix);
    return length >= suffix_length && strcmp(text + length - suffix_length, suffix) == 0;
}

/* kg_scene_load_file recognises a map saved by Tiled (.tmj, or .json) by its contents. */
kg_result kg_open_scene(const char* name, uint32_t seed, int max_bodies, kg_scene** out)
{
    kg_scene_limits limits = kg_default_scene_limits();
    limits.max_bodies = max_bodies >= 0 ? max_bodies : limits.max_bodies;
    if (access(name, F_OK) == 0 || strchr(name, '/') || kg_ends_with(name, ".json") || kg_ends_with(name, ".tmj")) {
        kg_result r = kg_scene_load_file_limited(name, &limits, out);
        for (int i = 0; r == KG_OK && i < kg_scene_note_count(*out); ++i) {
            fprintf(stderr, "kgyro: note: %s\n", kg_scene_get_note(*out, i));
        }
        return r;
    }
    return kg_scene_generate_limited(name, seed, &limits, out);
}

kg_result kg_sim_start(kg_sim* sim, kg_scene* scene, kg_backend backend, int extra_bodies)
{
    memset(sim, 0, sizeof *sim);
    sim->scene = scene;
    sim->dt = kg_scene_dt(scene);
    int scene_bodies = kg_scene_body_count(scene);
    sim->body_capacity = scene_bodies + extra_bodies;
    sim->bodies = malloc((size_t)(sim->body_capacity > 0 ? sim->body_capacity : 1) * sizeof *sim->bodies);
    if (!sim->bodies) {
        return KG_ERROR_OUT_OF_MEMORY;
    }
    kg_world_def def = *kg_scene_world_def(scene);
    def.backend = backend;
    def.max_bodies = sim->body_capacity > def.max_bodies ? sim->body_capacity : def.max_bodies;
    /* as kg_scene_instantiate sizes it, counting the bodies still to come */
    int contacts = 6 * sim->body_capacity + 64;
    def.max_contacts = contacts > def.max_contacts ? contacts : def.max_contacts;
    kg_result r = kg_scene_instantiate(scene, &def, &sim->world, sim->bodies);
    sim->body_count = r == KG_OK ? scene_bodies : 0;
    return r;
}

kg_result kg_sim_step(kg_sim* sim) { return kg_scene_step(sim->scene, sim->world, sim->bodies, sim->dt); }

kg_result kg_sim_add_body(kg_sim* sim, const kg_body_def* def, kg_body* out)
{
    if (sim->body_count >= sim->body_capacity) {
        return KG_ERROR_POOL_FULL;
    }
    kg_result r = kg_create_body(sim->world, def, &sim->bodies[sim->body_count]);
    if (r == KG_OK) {
        *out = sim->bodies[sim->body_count++];
    }
    return r;
}

void kg_sim_stop(kg_sim* sim)
{
    kg_destroy_world(sim->world);
    kg_scene_destroy(sim->scene);
    free(sim->bodies);
    memset(sim, 0, sizeof *sim);
}

int kg_parse_backend(const char* text, kg_backend* out)
{
    static const char* const kNames[] = {"auto", "cpu", "opencl"};
    for (int i = 0; i < 3; ++i) {
        if (strcmp(text, kNames[i]) == 0) {
            *out = (kg_backend)i;
            return 0;
        }
    }
    return -1;
}

const char* kg_backend_label(kg_backend backend)
{
    return backend == KG_BACKEND_OPENCL ? "OpenCL" : (backend == KG_BACKEND_CPU ? "CPU" : "auto");
}
