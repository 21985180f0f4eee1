/* Scene generators: simple layouts (pyramid, stack, container, rain, particles) and the
 * benchmark scenes of Box2D v3 (shared/benchmarks.c), rebuilt body for body with one
 * shape per body. Float expressions of the benchmarks follow Box2D's own, so the
 * initial positions are the same bits. */
#include "io/scene_generate.h"

#include "core/error.h"
#include "io/json_util.h"
#include "io/scene_limits.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define KG_PI 3.14159265358979f

/* Cells are this many times max_size: a box of sides up to max_size fits a cell at any
 * angle (sqrt 2 = 1.414), with a little room to place it at random. */
#define KG_RAIN_CELL_SCALE 1.5f
/* Particle grid spacing in radii: a gap of half a radius between neighbours. */
#define KG_PARTICLE_SPACING 2.5f

kg_gen_material kg_gen_default_material(void)
{
    kg_body_def def = kg_default_body_def();
    return (kg_gen_material){def.density, def.friction, def.restitution};
}

kg_body_def kg_gen_def(kg_body_type type, kg_shape_def shape, kg_vec2 position, const kg_gen_material* material)
{
    kg_body_def def = kg_default_body_def();
    def.type = type;
    def.shape = shape;
    def.position = position;
    def.density = material->density;
    def.friction = material->friction;
    def.restitution = material->restitution;
    return def;
}

kg_result kg_gen_add(kg_scene* scene, const char* prefix, const char* role, int index, const kg_body_def* def)
{
    /* longer than a scene name may be, so an over-long prefix is reported, not cut */
    char name[160];
    if (index >= 0) {
        snprintf(name, sizeof name, "%s%s%d", prefix, role, index);
    } else {
        snprintf(name, sizeof name, "%s%s", prefix, role);
    }
    return kg_scene_add_body(scene, name, def);
}

/* ---- simple layouts ---- */

/* Box2D's CreateLargePyramid / CreateSmallPyramid layout with h the half extent. */
static kg_result kg_gen_pyramid_from(kg_scene* scene, const char* prefix, int first, const kg_gen_pyramid* p)
{
    float h = 0.5f * p->box_size;
    kg_shape_def box = kg_box_shape(p->box_size, p->box_size);
    int index = first;
    for (int i = 0; i < p->base; ++i) {
        float y = (2.0f * (float)i + 1.0f) * h + p->origin.y;
        for (int j = i; j < p->base; ++j) {
            float x = ((float)i + 1.0f) * h + 2.0f * (float)(j - i) * h - h * (float)p->base + p->origin.x;
            kg_body_def def = kg_gen_def(KG_BODY_DYNAMIC, box, (kg_vec2){x, y}, &p->material);
            KG_TRY(kg_gen_add(scene, prefix, "", index++, &def));
        }
    }
    return KG_OK;
}

kg_result kg_gen_pyramid_bodies(kg_scene* scene, const char* prefix, const kg_gen_pyramid* params)
{
    return kg_gen_pyramid_from(scene, prefix, 0, params);
}

kg_result kg_gen_stack_bodies(kg_scene* scene, const char* prefix, const kg_gen_stack* params)
{
    kg_shape_def box = kg_box_shape(params->box_size, params->box_size);
    for (int i = 0; i < params->count; ++i) {
        float y = params->origin.y + (float)i * (params->box_size + params->gap) + 0.5f * params->box_size;
        kg_body_def def = kg_gen_def(KG_BODY_DYNAMIC, box, (kg_vec2){params->origin.x, y}, &params->material);
        KG_TRY(kg_gen_add(scene, prefix, "", i, &def));
    }
    return KG_OK;
}

kg_result kg_gen_container_bodies(kg_scene* scene, const char* prefix, const kg_gen_container* params)
{
    float t = params->thickness;
    kg_vec2 o = params->origin;
    float wall_x = 0.5f * params->width + 0.5f * t;
    /* the walls reach down to the floor's bottom face, so the corners are closed */
    float wall_y = o.y + 0.5f * (params->height - t);
    kg_body_def floor = kg_gen_def(KG_BODY_STATIC, kg_box_shape(params->width + 2.0f * t, t),
                                   (kg_vec2){o.x, o.y - 0.5f * t}, &params->material);
    kg_shape_def wall = kg_box_shape(t, params->height + t);
    kg_body_def left = kg_gen_def(KG_BODY_STATIC, wall, (kg_vec2){o.x - wall_x, wall_y}, &params->material);
    kg_body_def right = kg_gen_def(KG_BODY_STATIC, wall, (kg_vec2){o.x + wall_x, wall_y}, &params->material);
    KG_TRY(kg_gen_add(scene, prefix, "", 0, &floor));
    KG_TRY(kg_gen_add(scene, prefix, "", 1, &left));
    return kg_gen_add(scene, prefix, "", 2, &right);
}

/* ---- random layouts ---- */

/* PCG32: integer-only, so the same seed gives the same scene on every platform. */
typedef struct kg_rng {
    uint64_t state;
} kg_rng;

static uint32_t kg_rng_next(kg_rng* rng)
{
    uint64_t old = rng->state;
    rng->state = old * 6364136223846793005ull + 1442695040888963407ull;
    uint32_t shifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (shifted >> rot) | (shifted << ((32u - rot) & 31u));
}

static kg_rng kg_rng_seeded(uint32_t seed)
{
    kg_rng rng = {(uint64_t)seed + 1442695040888963407ull};
    kg_rng_next(&rng);
    return rng;
}

/* Uniform in [0, 1), 24 bits. */
static float kg_rng_unit(kg_rng* rng) { return (float)(kg_rng_next(rng) >> 8) * (1.0f / 16777216.0f); }

static float kg_rng_range(kg_rng* rng, float lo, float hi) { return lo + (hi - lo) * kg_rng_unit(rng); }

/* Cells of size cell that fit in region, saturating rather than overflowing. */
static int kg_grid_capacity(kg_aabb region, float cell, int* columns)
{
    double across = floor((double)(region.upper.x - region.lower.x) / cell);
    double up = floor((double)(region.upper.y - region.lower.y) / cell);
    /* a region wider than a billion cells still fills row by row: only the first
     * billion columns are ever needed */
    *columns = across > 0.0 ? (int)fmin(across, 1.0e9) : 0;
    double cells = *columns > 0 && up > 0.0 ? (double)*columns * up : 0.0;
    return cells > 2.0e9 ? 2000000000 : (int)cells;
}

static kg_vec2 kg_cell_center(kg_aabb region, float cell, int columns, int k)
{
    return (kg_vec2){region.lower.x + ((float)(k % columns) + 0.5f) * cell,
                     region.lower.y + ((float)(k / columns) + 0.5f) * cell};
}

int kg_gen_rain_capacity(const kg_gen_rain* params)
{
    int columns;
    return kg_grid_capacity(params->region, KG_RAIN_CELL_SCALE * params->max_size, &columns);
}

/* One rain drop: its shape, angle and the radius of a circle around it. */
static kg_body_def kg_rain_drop(kg_rng* rng, const kg_gen_rain* p, float* bound)
{
    kg_shape_def shape;
    float angle = 0.0f;
    if (kg_rng_next(rng) & 1u) {
        float diameter = kg_rng_range(rng, p->min_size, p->max_size);
        shape = kg_circle_shape(0.5f * diameter);
        *bound = 0.5f * diameter;
    } else {
        float width = kg_rng_range(rng, p->min_size, p->max_size);
        float height = kg_rng_range(rng, p->min_size, p->max_size);
        shape = kg_box_shape(width, height);
        angle = kg_rng_range(rng, -KG_PI, KG_PI);
        *bound = 0.5f * sqrtf(width * width + height * height);
    }
    kg_body_def def = kg_gen_def(KG_BODY_DYNAMIC, shape, (kg_vec2){0.0f, 0.0f}, &p->material);
    def.angle = angle;
    return def;
}

kg_result kg_gen_rain_bodies(kg_scene* scene, const char* prefix, const kg_gen_rain* params)
{
    float cell = KG_RAIN_CELL_SCALE * params->max_size;
    int columns;
    int capacity = kg_grid_capacity(params->region, cell, &columns);
    if (params->count > capacity) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "region holds %d bodies of max_size %g, not %d", capacity,
                       (double)params->max_size, params->count);
    }
    kg_rng rng = kg_rng_seeded(params->seed);
    for (int k = 0; k < params->count; ++k) {
        float bound;
        kg_body_def def = kg_rain_drop(&rng, params, &bound);
        /* the drop's bounding circle stays inside its own cell: no overlaps at start */
        float slack = 0.5f * cell - bound;
        kg_vec2 center = kg_cell_center(params->region, cell, columns, k);
        def.position.x = center.x + kg_rng_range(&rng, -slack, slack);
        def.position.y = center.y + kg_rng_range(&rng, -slack, slack);
        KG_TRY(kg_gen_add(scene, prefix, "", k, &def));
    }
    return KG_OK;
}

int kg_gen_particles_capacity(const kg_gen_particles* params)
{
    int columns;
    return kg_grid_capacity(params->region, KG_PARTICLE_SPACING * params->radius, &columns);
}

kg_result kg_gen_particle_bodies(kg_scene* scene, const char* prefix, const kg_gen_particles* params)
{
    float cell = KG_PARTICLE_SPACING * params->radius;
    int columns;
    int capacity = kg_grid_capacity(params->region, cell, &columns);
    if (params->count > capacity) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "region holds %d particles of radius %g, not %d", capacity,
                       (double)params->radius, params->count);
    }
    kg_rng rng = kg_rng_seeded(params->seed);
    /* a little jitter so that columns of particles do not balance on each other */
    float slack = 0.5f * cell - params->radius;
    kg_shape_def circle = kg_circle_shape(params->radius);
    for (int k = 0; k < params->count; ++k) {
        kg_vec2 center = kg_cell_center(params->region, cell, columns, k);
        center.x += kg_rng_range(&rng, -slack, slack);
        center.y += kg_rng_range(&rng, -slack, slack);
        kg_body_def def = kg_gen_def(KG_BODY_PARTICLE, circle, center, &params->material);
        def.mass = params->mass;
        KG_TRY(kg_gen_add(scene, prefix, "", k, &def));
    }
    return KG_OK;
}

/* ---- the benchmark set ---- */

static kg_result kg_gen_ground_box(kg_scene* scene, const char* prefix, int index, float half_width,
                                   float half_height, kg_vec2 center)
{
    kg_gen_material material = kg_gen_default_material();
    kg_body_def def = kg_gen_def(KG_BODY_STATIC, kg_box_shape(2.0f * half_width, 2.0f * half_height), center,
                                 &material);
    return kg_gen_add(scene, prefix, "ground", index, &def);
}

/* CreateLargePyramid: a 200 x 2 ground and a pyramid of base 100. */
static kg_result kg_gen_large_pyramid(kg_scene* scene, const char* prefix)
{
    KG_TRY(kg_gen_ground_box(scene, prefix, -1, 100.0f, 1.0f, (kg_vec2){0.0f, -1.0f}));
    kg_gen_pyramid pyramid = {100, 1.0f, {0.0f, 0.0f}, kg_gen_default_material()};
    char box_prefix[80];
    snprintf(box_prefix, sizeof box_prefix, "%sbox", prefix);
    return kg_gen_pyramid_from(scene, box_prefix, 0, &pyramid);
}

/* CreateManyPyramids: 20 rows of 20 pyramids of base 10. Box2D's ground is one body
 * with a 220 m segment under each row; here each row gets a static box 0.5 m thick
 * whose top face is that segment. */
static kg_result kg_gen_many_pyramids(kg_scene* scene, const char* prefix)
{
    const int base_count = 10, row_count = 20, column_count = 20;
    const float extent = 0.5f;
    float ground_delta_y = 2.0f * extent * ((float)base_count + 1.0f);
    float ground_width = 2.0f * extent * (float)column_count * ((float)base_count + 1.0f);
    const float ground_thickness = 0.5f;
    float ground_y = 0.0f;
    for (int i = 0; i < row_count; ++i) {
        kg_vec2 center = {0.0f, ground_y - 0.5f * ground_thickness};
        KG_TRY(kg_gen_ground_box(scene, prefix, i, 0.5f * ground_width, 0.5f * ground_thickness, center));
        ground_y += ground_delta_y;
    }
    char box_prefix[80];
    snprintf(box_prefix, sizeof box_prefix, "%sbox", prefix);
    float base_width = 2.0f * extent * (float)base_count;
    float base_y = 0.0f;
    int first = 0;
    for (int i = 0; i < row_count; ++i) {
        for (int j = 0; j < column_count; ++j) {
            float center_x = -0.5f * ground_width + (float)j * (base_width + 2.0f * extent) + 2.0f * extent;
            /* Box2D's bottom row starts at center_x - 0.5; origin is its middle */
            kg_gen_pyramid pyramid = {base_count, 2.0f * extent,
                                      {center_x - 0.5f + extent * (float)base_count, base_y},
                                      kg_gen_default_material()};
            KG_TRY(kg_gen_pyramid_from(scene, box_prefix, first, &pyramid));
            first += base_count * (base_count + 1) / 2;
        }
        base_y += ground_delta_y;
    }
    return KG_OK;
}

/* CreateSmash: a dense 8 x 8 box at 40 m/s into a 120 x 80 grid of 0.4 m boxes, no
 * gravity (the caller's part). Box2D starts the grid asleep; kgyro has no sleep. */
static kg_result kg_gen_smash(kg_scene* scene, const char* prefix)
{
    kg_gen_material heavy = kg_gen_default_material();
    heavy.density = 8.0f;
    kg_body_def projectile = kg_gen_def(KG_BODY_DYNAMIC, kg_box_shape(8.0f, 8.0f), (kg_vec2){-20.0f, 0.0f}, &heavy);
    projectile.velocity = (kg_vec2){40.0f, 0.0f};
    KG_TRY(kg_gen_add(scene, prefix, "projectile", -1, &projectile));

    const float d = 0.4f;
    const int columns = 120, rows = 80;
    kg_gen_material material = kg_gen_default_material();
    kg_shape_def box = kg_box_shape(d, d);
    int index = 0;
    for (int i = 0; i < columns; ++i) {
        for (int j = 0; j < rows; ++j) {
            kg_vec2 position = {(float)i * d + 30.0f, ((float)j - (float)rows / 2.0f) * d};
            kg_body_def def = kg_gen_def(KG_BODY_DYNAMIC, box, position, &material);
            KG_TRY(kg_gen_add(scene, prefix, "box", index++, &def));
        }
    }
    return KG_OK;
}

/* CreateTumbler's container is one dynamic body of four boxes turned by a motor at
 * 25 deg/s. A body here has one shape, so each wall is its own kinematic body turning
 * about the common centre (0, 10): its velocity is that of the rotation at its centre,
 * and its pivot keeps it on its circle (kg_scene_step). */
static kg_result kg_gen_tumbler_walls(kg_scene* scene, const char* prefix)
{
    const kg_vec2 center = {0.0f, 10.0f};
    const float omega = (KG_PI / 180.0f) * 25.0f;
    const kg_vec2 offsets[4] = {{10.0f, 0.0f}, {-10.0f, 0.0f}, {0.0f, 10.0f}, {0.0f, -10.0f}};
    const kg_vec2 sizes[4] = {{1.0f, 20.0f}, {1.0f, 20.0f}, {20.0f, 1.0f}, {20.0f, 1.0f}};
    kg_gen_material material = kg_gen_default_material();
    material.density = 50.0f;
    for (int k = 0; k < 4; ++k) {
        kg_vec2 position = {center.x + offsets[k].x, center.y + offsets[k].y};
        kg_body_def def = kg_gen_def(KG_BODY_KINEMATIC, kg_box_shape(sizes[k].x, sizes[k].y), position, &material);
        def.angular_velocity = omega;
        /* 0 - x rather than -x: no -0 in the CSV for the axis-aligned offsets */
        def.velocity = (kg_vec2){0.0f - omega * offsets[k].y, omega * offsets[k].x};
        KG_TRY(kg_gen_add(scene, prefix, "wall", k, &def));
        KG_TRY(kg_scene_set_body_pivot(scene, kg_scene_body_count(scene) - 1, center));
    }
    return KG_OK;
}

/* The 45 x 45 grid of 0.25 m boxes; positions accumulate as in Box2D's loop. */
static kg_result kg_gen_tumbler(kg_scene* scene, const char* prefix)
{
    KG_TRY(kg_gen_tumbler_walls(scene, prefix));
    const int grid_count = 45;
    kg_gen_material material = kg_gen_default_material();
    kg_shape_def box = kg_box_shape(0.25f, 0.25f);
    int index = 0;
    float y = -0.2f * (float)grid_count + 10.0f;
    for (int i = 0; i < grid_count; ++i) {
        float x = -0.2f * (float)grid_count;
        for (int j = 0; j < grid_count; ++j) {
            kg_body_def def = kg_gen_def(KG_BODY_DYNAMIC, box, (kg_vec2){x, y}, &material);
            KG_TRY(kg_gen_add(scene, prefix, "box", index++, &def));
            x += 0.4f;
        }
        y += 0.4f;
    }
    return KG_OK;
}

typedef struct kg_benchmark {
    const char* name;
    kg_result (*build)(kg_scene* scene, const char* prefix);
    int steps;
    kg_vec2 gravity;
} kg_benchmark;

static const kg_benchmark kBenchmarks[] = {
    {"large_pyramid", kg_gen_large_pyramid, 500, {0.0f, -10.0f}},
    {"many_pyramids", kg_gen_many_pyramids, 200, {0.0f, -10.0f}},
    {"smash", kg_gen_smash, 300, {0.0f, 0.0f}},
    {"tumbler", kg_gen_tumbler, 750, {0.0f, -10.0f}},
    {"joint_grid", kg_gen_joint_grid, 300, {0.0f, -10.0f}},
    {"ragdoll_rain", kg_gen_ragdoll_rain, 600, {0.0f, -10.0f}},
};

static const kg_benchmark* kg_find_benchmark(const char* name)
{
    for (size_t i = 0; i < sizeof kBenchmarks / sizeof kBenchmarks[0]; ++i) {
        if (strcmp(name, kBenchmarks[i].name) == 0) {
            return &kBenchmarks[i];
        }
    }
    return NULL;
}

kg_result kg_gen_benchmark_bodies(kg_scene* scene, const char* prefix, const char* name)
{
    const kg_benchmark* benchmark = kg_find_benchmark(name);
    if (!benchmark) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "unknown benchmark scene '%s'", name);
    }
    return benchmark->build(scene, prefix);
}

/* ---- scenes by name ---- */

#define KG_GENERATOR_NAMES \
    "pyramid_B, stack_N, rain_N, particles_N, large_pyramid, many_pyramids, smash, tumbler, joint_grid, " \
    "ragdoll_rain"

/* The N of "prefixN": digits only, in [1, max]; 0 when name does not have that form. */
static int kg_sized_name(const char* name, const char* prefix, int max)
{
    size_t length = strlen(prefix);
    if (strncmp(name, prefix, length) != 0 || name[length] == '\0') {
        return 0;
    }
    long n = 0;
    for (const char* c = name + length; *c; ++c) {
        if (*c < '0' || *c > '9' || n > max) {
            return 0;
        }
        n = n * 10 + (*c - '0');
    }
    return n >= 1 && n <= max ? (int)n : 0;
}

/* A ground box of half extents (half_width, 1) whose top face is y = 0. */
static kg_result kg_gen_flat_ground(kg_scene* scene, float half_width)
{
    return kg_gen_ground_box(scene, "", -1, half_width, 1.0f, (kg_vec2){0.0f, -1.0f});
}

static kg_result kg_gen_named_pyramid(kg_scene* scene, int base)
{
    KG_TRY(kg_gen_flat_ground(scene, fmaxf((float)base, 10.0f)));
    kg_gen_pyramid pyramid = {base, 1.0f, {0.0f, 0.0f}, kg_gen_default_material()};
    return kg_gen_pyramid_bodies(scene, "box", &pyramid);
}

static kg_result kg_gen_named_stack(kg_scene* scene, int count)
{
    KG_TRY(kg_gen_flat_ground(scene, 10.0f));
    kg_gen_stack stack = {count, 1.0f, 0.0f, {0.0f, 0.0f}, kg_gen_default_material()};
    return kg_gen_stack_bodies(scene, "box", &stack);
}

/* A container sized to the grid the bodies start on, columns wide with a margin each
 * side: the grid starts one cell above the floor and the walls reach half its height.
 * The region is a margin larger than the grid up and right, so that rounding cannot
 * cost it a row or column of cells. */
static kg_result kg_gen_filled_container(kg_scene* scene, int count, float cell, int columns, kg_aabb* region)
{
    int rows = (count + columns - 1) / columns;
    const float margin = 0.05f;
    float width = (float)columns * cell + 2.0f * margin;
    float height = (float)rows * cell + margin;
    region->lower = (kg_vec2){-0.5f * width + margin, cell};
    region->upper = (kg_vec2){0.5f * width, cell + height};
    kg_gen_container container = {{0.0f, 0.0f}, width, fmaxf(5.0f * cell, 0.5f * height), 1.0f,
                                  kg_gen_default_material()};
    return kg_gen_container_bodies(scene, "container", &container);
}

static int kg_square_columns(int count, int at_least)
{
    int columns = (int)ceil(sqrt((double)count));
    return columns > at_least ? columns : at_least;
}

static kg_result kg_gen_named_rain(kg_scene* scene, int count, uint32_t seed)
{
    kg_gen_rain rain = {count, seed, {{0.0f, 0.0f}, {0.0f, 0.0f}}, 0.2f, 0.8f, kg_gen_default_material()};
    float cell = KG_RAIN_CELL_SCALE * rain.max_size;
    KG_TRY(kg_gen_filled_container(scene, count, cell, kg_square_columns(count, 10), &rain.region));
    return kg_gen_rain_bodies(scene, "drop", &rain);
}

static kg_result kg_gen_named_particles(kg_scene* scene, int count, uint32_t seed)
{
    kg_gen_particles particles = {count, seed, {{0.0f, 0.0f}, {0.0f, 0.0f}}, 0.05f, 0.0f,
                                  kg_gen_default_material()};
    float cell = KG_PARTICLE_SPACING * particles.radius;
    KG_TRY(kg_gen_filled_container(scene, count, cell, kg_square_columns(count, 20), &particles.region));
    return kg_gen_particle_bodies(scene, "particle", &particles);
}

typedef struct kg_sized_generator {
    const char* prefix; /* the name is prefix + N */
    int max;
    int steps;
    kg_result (*build)(kg_scene* scene, int n, uint32_t seed);
} kg_sized_generator;

static kg_result kg_build_pyramid(kg_scene* scene, int n, uint32_t seed)
{
    (void)seed;
    return kg_gen_named_pyramid(scene, n);
}

static kg_result kg_build_stack(kg_scene* scene, int n, uint32_t seed)
{
    (void)seed;
    return kg_gen_named_stack(scene, n);
}

static const kg_sized_generator kSizedGenerators[] = {
    {"pyramid_", 2000, 300, kg_build_pyramid},
    {"stack_", 100000, 300, kg_build_stack},
    {"rain_", 1000000, 600, kg_gen_named_rain},
    {"particles_", 1000000, 600, kg_gen_named_particles},
};

/* r, a generator's failure, with the scene's name before its message. */
static kg_result kg_named_failure(const char* name, kg_result r)
{
    if (r == KG_OK) {
        return r;
    }
    char why[256];
    snprintf(why, sizeof why, "%s", kg_last_error());
    return kg_fail(r, "scene '%s': %s", name, why);
}

static kg_result kg_generate_into(kg_scene* scene, const char* name, uint32_t seed)
{
    const kg_benchmark* benchmark = kg_find_benchmark(name);
    if (benchmark) {
        kg_scene_world_def(scene)->gravity = benchmark->gravity;
        KG_TRY(kg_scene_set_steps(scene, benchmark->steps));
        return kg_named_failure(name, benchmark->build(scene, ""));
    }
    for (size_t i = 0; i < sizeof kSizedGenerators / sizeof kSizedGenerators[0]; ++i) {
        const kg_sized_generator* g = &kSizedGenerators[i];
        if (strncmp(name, g->prefix, strlen(g->prefix)) != 0) {
            continue;
        }
        int n = kg_sized_name(name, g->prefix, g->max);
        if (n == 0) {
            return kg_fail(KG_ERROR_INVALID_ARGUMENT, "scene '%s': %sN needs N in [1, %d]", name, g->prefix, g->max);
        }
        if (n > kg_scene_body_room(scene)) { /* before any is made: the limit is there to spare the memory */
            return kg_fail(KG_ERROR_INVALID_ARGUMENT, "scene '%s': more than max_bodies (%d) bodies", name,
                           kg_scene_get_limits(scene)->max_bodies);
        }
        KG_TRY(kg_scene_set_steps(scene, g->steps));
        return kg_named_failure(name, g->build(scene, n, seed));
    }
    return kg_fail(KG_ERROR_INVALID_ARGUMENT, "unknown scene '%s' (generators: %s)", name, KG_GENERATOR_NAMES);
}

kg_result kg_scene_generate(const char* name, uint32_t seed, kg_scene** out)
{
    return kg_scene_generate_limited(name, seed, NULL, out);
}

kg_result kg_scene_generate_limited(const char* name, uint32_t seed, const kg_scene_limits* limits, kg_scene** out)
{
    if (!name || !out) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_generate: NULL argument");
    }
    *out = NULL;
    kg_scene_limits chosen = limits ? *limits : kg_default_scene_limits();
    KG_TRY(kg_check_scene_limits("kg_scene_generate_limited", &chosen));
    kg_scene* scene;
    KG_TRY(kg_scene_create(&scene));
    kg_scene_set_limits(scene, &chosen);
    kg_result r = kg_generate_into(scene, name, seed);
    if (r != KG_OK) {
        kg_scene_destroy(scene);
        return r;
    }
    kg_scene_limits defaults = kg_default_scene_limits();
    kg_scene_set_limits(scene, &defaults); /* as the loaders hand a scene over */
    *out = scene;
    return KG_OK;
}
