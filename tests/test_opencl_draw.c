/* Debug draw on the OpenCL backend: after some steps, kg_world_draw makes the same calls
 * as on the CPU (state read back from the device first), positions within 1e-4 m (the
 * backends agree bitwise only on devices with correctly rounded divide and sqrt). Exits
 * 77 (skipped) without an OpenCL device. */
#include "kg_test.h"

#include "debug_draw_recorder.h"

#include "kgyro/opencl.h"

#include <stdio.h>
#include <stdlib.h>

#define KG_SKIP 77 /* ctest: skipped (tests/cases/opencl.cmake) */

static kg_world* kg_draw_scene(kg_backend backend)
{
    kg_world_def def = kg_default_world_def();
    def.backend = backend;
    def.device_index = kg_test_opencl_device();
    kg_world* world = NULL;
    KG_CHECK_OK(kg_create_world(&def, &world));
    if (!world) {
        return NULL;
    }
    kg_body_def ground = kg_default_body_def();
    ground.type = KG_BODY_STATIC;
    ground.shape = kg_box_shape(20.0f, 1.0f);
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &ground, &body));
    for (int i = 0; i < 12; ++i) {
        kg_body_def d = kg_default_body_def();
        d.position = (kg_vec2){-3.0f + 0.6f * (float)(i % 6), 1.0f + 1.2f * (float)(i / 6)};
        d.angle = 0.1f * (float)i;
        d.shape = i % 3 == 0 ? kg_circle_shape(0.25f)
                             : (i % 3 == 1 ? kg_box_shape(0.5f, 0.4f)
                                           : kg_capsule_shape((kg_vec2){-0.2f, 0.0f}, (kg_vec2){0.2f, 0.0f}, 0.15f));
        KG_CHECK_OK(kg_create_body(world, &d, &body));
    }
    return world;
}

static void test_opencl_draws_as_the_cpu(void)
{
    kg_world* worlds[2] = {kg_draw_scene(KG_BACKEND_CPU), kg_draw_scene(KG_BACKEND_OPENCL)};
    kg_recorder* rec = calloc(2, sizeof *rec);
    for (int w = 0; w < 2 && worlds[w]; ++w) {
        for (int s = 0; s < 60; ++s) {
            KG_CHECK_OK(kg_world_step(worlds[w], 1.0f / 60.0f));
        }
        kg_debug_draw draw = kg_recording_draw(&rec[w], KG_DEBUG_DRAW_SHAPES | KG_DEBUG_DRAW_AABBS |
                                                            KG_DEBUG_DRAW_CONTACT_POINTS | KG_DEBUG_DRAW_MASS);
        KG_CHECK_OK(kg_world_draw(worlds[w], &draw));
    }
    KG_CHECK(worlds[1] && kg_world_backend(worlds[1]) == KG_BACKEND_OPENCL);
    KG_CHECK(rec[0].count > 13 && rec[0].count == rec[1].count);
    double worst = 0.0;
    for (int i = 0; i < rec[0].count && rec[0].count == rec[1].count; ++i) {
        const kg_call *a = &rec[0].calls[i], *b = &rec[1].calls[i];
        KG_CHECK(a->kind == b->kind && a->color == b->color && a->count == b->count);
        for (int k = 0; k < a->count && k < b->count; ++k) {
            worst = fmax(worst, fmax(fabs((double)a->points[k].x - b->points[k].x),
                                     fabs((double)a->points[k].y - b->points[k].y)));
        }
    }
    measured("     %d calls on each backend, positions differ by up to %.3g m\n", rec[0].count, worst);
    KG_CHECK(worst <= 1e-4);
    /* the bodies moved: the drawing is the device's state, not the state at creation */
    KG_CHECK(rec[1].calls[1].points[0].y < 1.0f);
    free(rec);
    kg_destroy_world(worlds[0]);
    kg_destroy_world(worlds[1]);
}

int main(void)
{
    int devices = 0;
    if (kg_opencl_device_count(&devices) != KG_OK || devices == 0) {
        printf("skipped: no OpenCL device\n");
        return KG_SKIP;
    }
    static const kg_test_case tests[] = {KG_TEST(test_opencl_draws_as_the_cpu)};
    return kg_run_tests(tests, 1);
}
