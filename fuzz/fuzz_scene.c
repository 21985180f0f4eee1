/* Fuzz target "scene": the JSON scene loader (kg_scene_parse) on arbitrary bytes, then
 * the scene it accepts, instantiated and stepped. Needs kgyro_io.
 *
 * Contracts checked:
 *  - a refused input answers KG_ERROR_PARSE (or KG_ERROR_OUT_OF_MEMORY), leaves *out
 *    NULL and a message "fuzz.json: ..." in kg_last_error();
 *  - an accepted scene is consistent: a finite dt > 0, steps >= 0, every body has a
 *    valid unique name that kg_scene_find_body finds again, every force names bodies
 *    of the scene;
 *  - an accepted scene instantiates (the loader checks what the engine checks), and
 *    its world steps with every body state finite. Scenes of more than
 *    KG_FUZZ_MAX_STEPPED_BODIES bodies (the benchmark generators) are only parsed, to
 *    keep each run short. */
#include "fuzz_common.h"

#include "kgyro/kgyro.h"
#include "kgyro/scene.h"

#include <math.h>

#define KG_FUZZ_SOURCE "fuzz.json"
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

static void check_refusal(kg_result r, const kg_scene* scene)
{
    FUZZ_REQUIRE(r == KG_ERROR_PARSE || r == KG_ERROR_OUT_OF_MEMORY, "a refused scene is a parse error");
    FUZZ_REQUIRE(scene == NULL, "a refused scene leaves *out NULL");
    const char* message = kg_last_error();
    FUZZ_REQUIRE(strncmp(message, KG_FUZZ_SOURCE ": ", strlen(KG_FUZZ_SOURCE ": ")) == 0,
                 "the message starts with the file name");
    FUZZ_REQUIRE(strlen(message) > strlen(KG_FUZZ_SOURCE ": "), "the message says what is wrong");
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

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    static char unset_marker;
    kg_scene* scene = (kg_scene*)(void*)&unset_marker; /* not NULL, so that leaving it unset shows */
    kg_result r = kg_scene_parse((const char*)data, size, KG_FUZZ_SOURCE, &scene);
    if (r != KG_OK) {
        check_refusal(r, scene);
        return 0;
    }
    FUZZ_REQUIRE(scene != NULL, "an accepted scene is returned");
    check_scene(scene);
    if (kg_scene_body_count(scene) <= KG_FUZZ_MAX_STEPPED_BODIES) {
        step_scene(scene);
    }
    kg_scene_destroy(scene);
    return 0;
}
