/* The contracts of the scene loader, shared by the targets that feed it: fuzz_scene
 * (kgyro scene files) and fuzz_tiled (Tiled maps, which kg_scene_parse reads as maps).
 *
 * fuzz_parse_scene(data, size, source, where, allow_io) checks:
 *  - a refused input answers KG_ERROR_PARSE (or KG_ERROR_OUT_OF_MEMORY, or KG_ERROR_IO
 *    when allow_io says a file it names may be missing), leaves *out NULL and a message
 *    in kg_last_error() that starts with where (the file name, or the directory of the
 *    files an input may name: a fault in an external tileset names the tileset);
 *  - an accepted scene is consistent: a finite dt > 0, steps >= 0, every body has a
 *    valid unique name that kg_scene_find_body finds again, every force names bodies
 *    of the scene, every tile map has sizes and shapes in range;
 *  - an accepted scene instantiates (the loader checks what the engine checks), and
 *    its world steps with every body state finite. Scenes of more than
 *    KG_FUZZ_MAX_STEPPED_BODIES bodies (the benchmark generators) are only parsed, to
 *    keep each run short. */
#ifndef KG_FUZZ_SCENE_CONTRACTS_H
#define KG_FUZZ_SCENE_CONTRACTS_H

#include "fuzz_common.h"

#include "kgyro/kgyro.h"
#include "kgyro/scene.h"

#include <math.h>

#define KG_FUZZ_MAX_STEPPED_BODIES 512
#define KG_FUZZ_STEPS 3

static int name_char_ok(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || strchr("_-.:/#", c);
}

static int name_ok(const char* name)
{
    size_t length = name ? strlen(name) : 0;
    for (size_t i = 0; i < length; ++i) {
        if (!name_char_ok(name[i])) {
            return 0;
        }
    }
    return length >= 1 && length <= 63;
}

static void check_refusal(kg_result r, const kg_scene* scene, const char* where, int allow_io)
{
    FUZZ_REQUIRE(r == KG_ERROR_PARSE || r == KG_ERROR_OUT_OF_MEMORY || (allow_io && r == KG_ERROR_IO),
                 "a refused scene is a parse error");
    FUZZ_REQUIRE(scene == NULL, "a refused scene leaves *out NULL");
    const char* message = kg_last_error();
    FUZZ_REQUIRE(strncmp(message, where, strlen(where)) == 0, "the message starts with the file name");
    FUZZ_REQUIRE(strlen(message) > strlen(where) + 2, "the message says what is wrong");
}

static void check_tilemap(const kg_tilemap_def* map)
{
    FUZZ_REQUIRE(map != NULL, "every tile map is readable");
    FUZZ_REQUIRE(map->width >= 1 && map->width <= 65536 && map->height >= 1 && map->height <= 65536 &&
                     map->layer_count >= 1,
                 "tile map sizes are in range");
    FUZZ_REQUIRE(isfinite(map->tile_size.x) && map->tile_size.x > 0.0f && isfinite(map->tile_size.y) &&
                     map->tile_size.y > 0.0f,
                 "tiles have a finite size > 0");
    FUZZ_REQUIRE(map->shapes != NULL && map->shape_count >= 1 && map->shape_count <= KG_MAX_TILE_ID + 1 &&
                     map->shapes[0].type == KG_TILE_SHAPE_EMPTY,
                 "tile shapes are in range and id 0 is empty");
    size_t cells = (size_t)map->width * (size_t)map->height * (size_t)map->layer_count;
    for (size_t i = 0; map->tiles && i < cells; ++i) {
        FUZZ_REQUIRE(map->tiles[i] < map->shape_count, "every tile id has a shape");
    }
}

static void check_scene(const kg_scene* scene)
{
    float dt = kg_scene_dt(scene);
    FUZZ_REQUIRE(isfinite(dt) && dt > 0.0f, "dt is finite and > 0");
    FUZZ_REQUIRE(kg_scene_steps(scene) >= 0, "steps >= 0");
    int body_count = kg_scene_body_count(scene);
    FUZZ_REQUIRE(body_count >= 0, "body count >= 0");
    for (int i = 0; i < body_count; ++i) {
        FUZZ_REQUIRE(kg_scene_body_def(scene, i) != NULL, "every body has a definition");
        const char* name = kg_scene_body_name(scene, i);
        FUZZ_REQUIRE(name_ok(name), "every body name is 1 to 63 allowed characters");
        FUZZ_REQUIRE(kg_scene_find_body(scene, name) == i, "names are unique and found again");
    }
    for (int f = 0; f < kg_scene_force_count(scene); ++f) {
        const kg_scene_force* force = kg_scene_get_force(scene, f);
        FUZZ_REQUIRE(force != NULL && force->body_count >= 0, "every force is readable");
        for (int k = 0; k < force->body_count; ++k) {
            FUZZ_REQUIRE(force->body_indices[k] >= 0 && force->body_indices[k] < body_count,
                         "forces name bodies of the scene");
        }
    }
    for (int m = 0; m < kg_scene_tilemap_count(scene); ++m) {
        check_tilemap(kg_scene_get_tilemap(scene, m));
    }
}

static int state_finite(const kg_body_state* s)
{
    return isfinite(s->position.x) && isfinite(s->position.y) && isfinite(s->angle) && isfinite(s->velocity.x) &&
           isfinite(s->velocity.y) && isfinite(s->angular_velocity);
}

static void step_scene(kg_scene* scene)
{
    int body_count = kg_scene_body_count(scene);
    kg_world_def def = *kg_scene_world_def(scene);
    def.backend = KG_BACKEND_CPU; /* an OpenCL device per run would be slow and nondeterministic */
    def.max_bodies = 1;           /* grown to fit by kg_scene_instantiate */
    def.max_contacts = 0;
    kg_body* bodies = malloc((size_t)(body_count > 0 ? body_count : 1) * sizeof *bodies);
    kg_body_state* states = malloc((size_t)(body_count > 0 ? body_count : 1) * sizeof *states);
    FUZZ_REQUIRE(bodies && states, "memory for the handles");
    kg_world* world = NULL;
    kg_result r = kg_scene_instantiate(scene, &def, &world, bodies);
    if (r != KG_OK) {
        fprintf(stderr, "kg_scene_instantiate: %s\n", kg_last_error());
    }
    FUZZ_REQUIRE(r == KG_OK, "an accepted scene instantiates");
    for (int s = 0; s < KG_FUZZ_STEPS; ++s) {
        FUZZ_REQUIRE(kg_scene_step(scene, world, bodies, kg_scene_dt(scene)) == KG_OK, "the world steps");
    }
    FUZZ_REQUIRE(kg_world_get_body_states(world, bodies, body_count, states) == KG_OK, "every body is alive");
    for (int i = 0; i < body_count; ++i) {
        FUZZ_REQUIRE(state_finite(&states[i]), "every body state stays finite");
    }
    kg_destroy_world(world);
    free(states);
    free(bodies);
}

static void fuzz_parse_scene(const uint8_t* data, size_t size, const char* source, const char* where, int allow_io)
{
    static char unset_marker;
    kg_scene* scene = (kg_scene*)(void*)&unset_marker; /* not NULL, so that leaving it unset shows */
    kg_result r = kg_scene_parse((const char*)data, size, source, &scene);
    if (r != KG_OK) {
        check_refusal(r, scene, where, allow_io);
        return;
    }
    FUZZ_REQUIRE(scene != NULL, "an accepted scene is returned");
    check_scene(scene);
    if (kg_scene_body_count(scene) <= KG_FUZZ_MAX_STEPPED_BODIES) {
        step_scene(scene);
    }
    kg_scene_destroy(scene);
}

#endif
