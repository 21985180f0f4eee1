/* Issue 17's acceptance for the joint samples: the ragdoll, the bridge, the windmill and the car
 * (samples/joint_*.json) run 60 s with nothing non-finite and no body faster than 50 m/s,
 * and end bitwise equal with 1 and 4 threads and on the OpenCL backend (PoCL). */
#include "kg_test.h"
#include "kg_test_world.h"
#include "kgyro/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SECONDS 60
#define MAX_SPEED 50.0f

static const char* const kSamples[] = {"joint_ragdoll.json", "joint_bridge.json", "joint_windmill.json", "joint_car.json"};

typedef struct sample_run {
    int bodies;
    kg_body_state* states; /* at the end */
    float fastest;         /* m/s, over every body and step */
    int non_finite;        /* steps with a non-finite state */
} sample_run;

static kg_scene* load_sample(const char* name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/samples/%s", KG_SOURCE_DIR, name);
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_load_file(path, &scene));
    return scene;
}

static void watch_states(sample_run* run)
{
    int bad = 0;
    for (int i = 0; i < run->bodies; ++i) {
        const kg_body_state* s = &run->states[i];
        float speed = hypotf(s->velocity.x, s->velocity.y);
        bad |= !isfinite(s->position.x) || !isfinite(s->position.y) || !isfinite(s->angle) || !isfinite(speed) ||
               !isfinite(s->angular_velocity);
        run->fastest = speed > run->fastest ? speed : run->fastest;
    }
    run->non_finite += bad;
}

/* The sample stepped for SECONDS on backend with threads threads. */
static sample_run run_sample(const kg_scene* scene, kg_backend backend, int threads)
{
    sample_run run = {kg_scene_body_count(scene), NULL, 0.0f, 0};
    run.states = calloc((size_t)run.bodies, sizeof *run.states);
    kg_body* bodies = calloc((size_t)run.bodies, sizeof *bodies);
    kg_world_def def = *kg_scene_world_def((kg_scene*)scene);
    def.backend = backend;
    def.device_index = kg_test_opencl_device();
    def.threads = threads;
    kg_world* world = NULL;
    KG_CHECK_OK(kg_scene_instantiate(scene, &def, &world, bodies));
    float dt = kg_scene_dt(scene);
    int steps = (int)lroundf((float)SECONDS / dt);
    for (int k = 0; world && k < steps; ++k) {
        KG_CHECK_OK(kg_scene_step(scene, world, bodies, dt));
        KG_CHECK_OK(kg_world_get_body_states(world, bodies, run.bodies, run.states));
        watch_states(&run);
    }
    kg_destroy_world(world);
    free(bodies);
    return run;
}

static int same_states(const sample_run* a, const sample_run* b)
{
    return a->bodies == b->bodies && memcmp(a->states, b->states, (size_t)a->bodies * sizeof *a->states) == 0;
}

static void test_samples_hold_together(void)
{
    int bitwise = 0;
    int opencl = kg_test_opencl_ready(&bitwise);
    for (size_t i = 0; i < sizeof kSamples / sizeof kSamples[0]; ++i) {
        kg_scene* scene = load_sample(kSamples[i]);
        if (!scene) {
            continue;
        }
        sample_run one = run_sample(scene, KG_BACKEND_CPU, 1);
        sample_run four = run_sample(scene, KG_BACKEND_CPU, 4);
        printf("     %s: %d s, fastest body %.2f m/s (< %.0f), %d non-finite steps, 1 and 4 threads %s\n", kSamples[i],
               SECONDS, (double)one.fastest, (double)MAX_SPEED, one.non_finite,
               same_states(&one, &four) ? "bitwise equal" : "DIFFERENT");
        KG_CHECK(one.non_finite == 0);
        KG_CHECK(one.fastest < MAX_SPEED);
        KG_CHECK(same_states(&one, &four));
        if (opencl) {
            sample_run device = run_sample(scene, KG_BACKEND_OPENCL, 1);
            printf("     %s on OpenCL: %s\n", kSamples[i], same_states(&one, &device) ? "bitwise equal" : "DIFFERENT");
            KG_CHECK(device.non_finite == 0 && device.fastest < MAX_SPEED);
            KG_CHECK(!bitwise || same_states(&one, &device));
            free(device.states);
        }
        free(one.states);
        free(four.states);
        kg_scene_destroy(scene);
    }
}

KG_TEST_MAIN(KG_TEST(test_samples_hold_together))
