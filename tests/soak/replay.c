/* kg_soak_replay: the soak's checks on saved scenes, as a ctest (soak_regress).
 *
 *   kg_soak_replay SCENE.json...
 *
 * Each scene (tests/regress/soak/: states the soak ran into trouble with, written out
 * in the scene format) is instantiated on the CPU and stepped for its "steps" (120 when
 * it gives none). It fails when a body state is not finite, a body is frozen, or a body
 * runs faster than the soak allows (SOAK_RUNAWAY_SPEED in soak.c). */
#include "kgyro/kgyro.h"
#include "kgyro/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define REPLAY_RUNAWAY_SPEED 150.0f
#define REPLAY_DEFAULT_STEPS 120

/* The first problem of this step, or NULL. */
static const char* check_step(const kg_world* world, const kg_body* bodies, int count, float* fastest)
{
    for (int i = 0; i < count; ++i) {
        kg_body_state st;
        if (kg_body_get_state(world, bodies[i], &st) != KG_OK) {
            return "a body was lost";
        }
        if (kg_body_is_frozen(world, bodies[i])) {
            return "a body was frozen";
        }
        float speed = hypotf(st.velocity.x, st.velocity.y);
        if (!isfinite(st.position.x) || !isfinite(st.position.y) || !isfinite(speed) || !isfinite(st.angular_velocity)) {
            return "a body state is not finite";
        }
        *fastest = fmaxf(*fastest, speed);
    }
    return *fastest > REPLAY_RUNAWAY_SPEED ? "a body runs away" : NULL;
}

static int replay(const char* path)
{
    kg_scene* scene = NULL;
    if (kg_scene_load_file(path, &scene) != KG_OK) {
        fprintf(stderr, "%s\n", kg_last_error());
        return 0;
    }
    int count = kg_scene_body_count(scene);
    kg_body* bodies = malloc((size_t)(count > 0 ? count : 1) * sizeof *bodies);
    kg_world_def def = *kg_scene_world_def(scene);
    def.backend = KG_BACKEND_CPU;
    kg_world* world = NULL;
    const char* problem = NULL;
    if (!bodies || kg_scene_instantiate(scene, &def, &world, bodies) != KG_OK) {
        problem = kg_last_error();
    }
    int steps = kg_scene_steps(scene) > 0 ? kg_scene_steps(scene) : REPLAY_DEFAULT_STEPS;
    float fastest = 0.0f;
    int step = 0;
    for (; !problem && step < steps; ++step) {
        problem = kg_scene_step(scene, world, bodies, kg_scene_dt(scene)) == KG_OK
                      ? check_step(world, bodies, count, &fastest)
                      : "the world does not step";
    }
    if (problem) {
        fprintf(stderr, "%s: step %d: %s (fastest body %.4g m/s)\n", path, step, problem, (double)fastest);
    } else {
        printf("%s: %d steps, fastest body %.3g m/s\n", path, steps, (double)fastest);
    }
    kg_destroy_world(world);
    kg_scene_destroy(scene);
    free(bodies);
    return problem == NULL;
}

int main(int argc, char** argv)
{
    int ok = argc > 1;
    for (int i = 1; i < argc; ++i) {
        ok = replay(argv[i]) && ok;
    }
    return ok ? 0 : 1;
}
