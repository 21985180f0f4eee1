/* What the tests of worlds with events, sensors and callbacks share: a world on a chosen
 * backend with sleeping off, handle comparison, and whether an OpenCL device is there to
 * compare with. Include after kg_test.h. */
#ifndef KG_TEST_WORLD_H
#define KG_TEST_WORLD_H

#include "kgyro/kgyro.h"
#include "kgyro/opencl.h"

/* A world at the defaults on backend (the test's OpenCL device), threads threads, sleeping
 * off so that every body takes part in every step. */
static inline kg_world* kg_test_world(kg_backend backend, int threads)
{
    kg_world_def def = kg_default_world_def();
    def.backend = backend;
    def.device_index = kg_test_opencl_device();
    def.threads = threads;
    def.enable_sleep = 0;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    return w;
}

/* A world on the CPU backend at the defaults but for gravity. */
static inline kg_world* kg_test_cpu_world(kg_vec2 gravity)
{
    kg_world_def def = kg_default_world_def();
    def.gravity = gravity;
    def.backend = KG_BACKEND_CPU;
    kg_world* world = NULL;
    KG_CHECK_OK(kg_create_world(&def, &world));
    return world;
}

/* A body of type at a pose with one shape (a particle without a shape gets 1 kg). */
static inline kg_body kg_test_add(kg_world* world, kg_body_type type, kg_vec2 at, float angle, kg_shape_def shape)
{
    kg_body_def def = kg_default_body_def();
    def.type = type;
    def.position = at;
    def.angle = angle;
    def.shape = shape;
    if (type == KG_BODY_PARTICLE && shape.type == KG_SHAPE_NONE) {
        def.mass = 1.0f;
    }
    kg_body body = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(world, &def, &body));
    return body;
}

static inline int kg_test_same_body(kg_body a, kg_body b) { return a.index == b.index && a.generation == b.generation; }

/* Whether an OpenCL device is there (else says the test part is skipped); *bitwise tells
 * whether it must agree with the CPU bit for bit (correctly rounded divide and sqrt). */
static inline int kg_test_opencl_ready(int* bitwise)
{
    int devices = 0;
    if (kg_opencl_device_count(&devices) != KG_OK || devices == 0) {
        printf("  OpenCL part skipped: no device\n");
        return 0;
    }
    kg_opencl_device_info info;
    KG_CHECK_OK(kg_opencl_get_device_info(kg_test_opencl_device(), &info));
    *bitwise = info.correctly_rounded_divide_sqrt;
    return 1;
}

#endif
