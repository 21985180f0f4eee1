/* Scenes: the JSON loader (every field, every error with its exact message), the
 * generators (counts and positions, Box2D's benchmark layouts), the builder API and
 * kg_scene_instantiate. Runs in tests/, so data files are under data/scenes/. */
#include "kg_test.h"

#include "kgyro/kgyro.h"
#include "kgyro/scene.h"

#include <string.h>

#define SCENES "data/scenes/"

static kg_scene* load(const char* path)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_load_file(path, &scene));
    return scene;
}

static int same_vec(kg_vec2 a, kg_vec2 b) { return a.x == b.x && a.y == b.y; }

static int same_shape(const kg_shape_def* a, const kg_shape_def* b)
{
    if (a->type != b->type || a->count != b->count || a->radius != b->radius || !same_vec(a->center, b->center)) {
        return 0;
    }
    for (int i = 0; i < a->count; ++i) {
        if (!same_vec(a->vertices[i], b->vertices[i])) {
            return 0;
        }
    }
    return 1;
}

/* ---- loading ---- */

static void test_full_scene_fields(void)
{
    kg_scene* scene = load(SCENES "good_full.json");
    if (!scene) {
        return;
    }
    kg_world_def* world = kg_scene_world_def(scene);
    KG_CHECK(world->gravity.x == 0.5f && world->gravity.y == -9.5f);
    KG_CHECK(world->substeps == 6);
    KG_CHECK(kg_scene_dt(scene) == 0.005f);
    KG_CHECK(kg_scene_steps(scene) == 123);
    KG_CHECK(kg_scene_body_count(scene) == 6);

    const kg_body_def* ground = kg_scene_body_def(scene, 0);
    kg_shape_def ground_box = kg_box_shape(20.0f, 2.0f);
    KG_CHECK(strcmp(kg_scene_body_name(scene, 0), "ground") == 0);
    KG_CHECK(ground->type == KG_BODY_STATIC);
    KG_CHECK(same_vec(ground->position, (kg_vec2){0.0f, -1.0f}) && ground->angle == 0.1f);
    KG_CHECK(same_shape(&ground->shape, &ground_box));
    KG_CHECK(ground->friction == 0.9f && ground->restitution == 0.25f);

    const kg_body_def* crate = kg_scene_body_def(scene, 1);
    kg_shape_def crate_box = kg_offset_box_shape(2.0f, 0.5f, (kg_vec2){0.25f, 0.0f}, 0.5f);
    KG_CHECK(strcmp(kg_scene_body_name(scene, 1), "crate") == 0);
    KG_CHECK(crate->type == KG_BODY_DYNAMIC);
    KG_CHECK(same_vec(crate->position, (kg_vec2){1.5f, 2.5f}) && crate->angle == 0.75f);
    KG_CHECK(same_vec(crate->velocity, (kg_vec2){3.0f, -4.0f}) && crate->angular_velocity == 2.5f);
    KG_CHECK(same_shape(&crate->shape, &crate_box));
    KG_CHECK(crate->density == 2.5f && crate->mass == 0.0f);
    KG_CHECK(crate->friction == 0.3f && crate->restitution == 0.5f);
    KG_CHECK(crate->linear_damping == 0.1f && crate->angular_damping == 0.2f);
    KG_CHECK(crate->category == 2u && crate->mask == 4294967293u && crate->fixed_rotation == 1);

    const kg_body_def* ball = kg_scene_body_def(scene, 2);
    KG_CHECK(ball->shape.type == KG_SHAPE_CIRCLE && ball->shape.radius == 0.75f);
    KG_CHECK(same_vec(ball->shape.center, (kg_vec2){0.1f, 0.2f}));
    KG_CHECK(ball->mass == 7.0f);

    const kg_body_def* wedge = kg_scene_body_def(scene, 3);
    KG_CHECK(wedge->shape.type == KG_SHAPE_POLYGON && wedge->shape.count == 3);
    KG_CHECK(same_vec(wedge->shape.vertices[2], (kg_vec2){1.0f, 1.5f}));

    /* unnamed: named after its index */
    kg_vec2 pivot = {1.0f, 1.0f};
    KG_CHECK(strcmp(kg_scene_body_name(scene, 4), "body4") == 0);
    KG_CHECK(kg_scene_body_def(scene, 4)->type == KG_BODY_KINEMATIC);
    KG_CHECK(kg_scene_body_pivot(scene, 4, &pivot) && same_vec(pivot, (kg_vec2){0.0f, 0.0f}));
    KG_CHECK(!kg_scene_body_pivot(scene, 1, NULL));

    const kg_body_def* dust = kg_scene_body_def(scene, 5);
    KG_CHECK(dust->type == KG_BODY_PARTICLE && dust->shape.type == KG_SHAPE_NONE && dust->mass == 0.01f);

    KG_CHECK(kg_scene_force_count(scene) == 2);
    const kg_scene_force* gravity = kg_scene_get_force(scene, 0);
    KG_CHECK(gravity->type == KG_SCENE_FORCE_GRAVITY && same_vec(gravity->vector, (kg_vec2){0.0f, 2.0f}));
    KG_CHECK(gravity->body_count == 2 && gravity->body_indices[0] == 2 && gravity->body_indices[1] == 5);
    const kg_scene_force* wind = kg_scene_get_force(scene, 1);
    KG_CHECK(wind->type == KG_SCENE_FORCE_WIND && same_vec(wind->vector, (kg_vec2){-1.0f, 0.5f}));
    KG_CHECK(wind->strength == 3.0f && wind->drag == 0.4f && wind->body_count == 0);
    kg_scene_destroy(scene);
}

static void test_defaults(void)
{
    const char* json = "{\"bodies\": [{\"shape\": {\"type\": \"circle\", \"radius\": 1}}]}";
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_parse(json, strlen(json), "inline.json", &scene));
    if (!scene) {
        return;
    }
    kg_body_def expected = kg_default_body_def();
    expected.shape = kg_circle_shape(1.0f);
    KG_CHECK(memcmp(kg_scene_body_def(scene, 0), &expected, sizeof expected) == 0);
    KG_CHECK(strcmp(kg_scene_body_name(scene, 0), "body0") == 0);
    KG_CHECK(same_vec(kg_scene_world_def(scene)->gravity, (kg_vec2){0.0f, -10.0f}));
    KG_CHECK(kg_scene_dt(scene) == 1.0f / 60.0f && kg_scene_steps(scene) == 0);
    KG_CHECK(kg_scene_force_count(scene) == 0);
    kg_scene_destroy(scene);
}

/* Capsules and segments read into the shapes kg_capsule_shape and kg_segment_shape make. */
static void test_capsule_and_segment(void)
{
    const char* json = "{\"bodies\": ["
                       "{\"shape\": {\"type\": \"capsule\", \"center1\": [-0.5, 0], \"center2\": [0.5, 0.25], \"radius\": 0.3}},"
                       "{\"type\": \"static\", \"shape\": {\"type\": \"segment\", \"point1\": [-4, 0], \"point2\": [4, -1]}},"
                       "{\"type\": \"kinematic\", \"shape\": {\"type\": \"segment\", \"point1\": [0, 0], \"point2\": [1, 0]}}]}";
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_parse(json, strlen(json), "inline.json", &scene));
    if (!scene) {
        return;
    }
    kg_shape_def capsule = kg_capsule_shape((kg_vec2){-0.5f, 0.0f}, (kg_vec2){0.5f, 0.25f}, 0.3f);
    kg_shape_def segment = kg_segment_shape((kg_vec2){-4.0f, 0.0f}, (kg_vec2){4.0f, -1.0f});
    KG_CHECK(same_shape(&kg_scene_body_def(scene, 0)->shape, &capsule));
    KG_CHECK(same_shape(&kg_scene_body_def(scene, 1)->shape, &segment));
    KG_CHECK(kg_scene_body_def(scene, 2)->shape.type == KG_SHAPE_SEGMENT && kg_scene_body_def(scene, 2)->type == KG_BODY_KINEMATIC);
    kg_scene_destroy(scene);
}

typedef struct error_case {
    const char* file;
    const char* message; /* after "data/scenes/FILE: " */
} error_case;

static const error_case kErrorFiles[] = {
    {"bad_syntax.json", "line 3, column 19: malformed JSON (unexpected character)"},
    {"bad_empty.json", "line 1, column 1: malformed JSON (unexpected end of input)"},
    {"bad_root.json", "(root): must be an object"},
    {"bad_repeated_field.json", "dt: field given twice"},
    {"bad_dt.json", "dt: must be > 0"},
    {"bad_radius.json", "bodies[1].shape.radius: must be > 0"},
    {"bad_box_size.json", "bodies[0].shape.width: must be > 0"},
    {"bad_unknown_field.json", "bodies[0].colour: unknown field"},
    {"bad_wrong_type.json", "bodies[0].position: must be [x, y] (an array of two numbers)"},
    {"bad_body_type.json",
     "bodies[0].type: must be one of \"static\", \"dynamic\", \"kinematic\", \"particle\" (got \"rigid\")"},
    {"bad_restitution.json", "bodies[0].restitution: must be in [0, 1]"},
    {"bad_friction.json", "bodies[0].friction: must be >= 0"},
    {"bad_mass.json", "bodies[0].mass: must be > 0"},
    {"bad_density.json", "bodies[0].density: must be >= 0"},
    {"bad_density_and_mass.json", "bodies[0].mass: give density or mass, not both"},
    {"bad_infinite.json", "bodies[0].angle: must be a finite number (got inf)"},
    {"bad_mask.json", "bodies[0].mask: must be an integer in [0, 4294967295]"},
    {"bad_missing_shape.json",
     "bodies[0].shape: is required (only particles, static and kinematic bodies may omit it)"},
    {"bad_particle_no_mass.json", "bodies[0].mass: is required for a particle without a shape"},
    {"bad_particle_angle.json", "bodies[0].angle: particles do not rotate"},
    {"bad_pivot.json", "bodies[0].pivot: only kinematic bodies can have a pivot"},
    {"bad_degenerate_polygon.json",
     "bodies[0].shape.vertices: polygon has no area (its points are collinear or coincide)"},
    {"bad_capsule_centres.json", "bodies[0].shape: capsule points coincide (closer than 0.0001 m): use a circle"},
    {"bad_capsule_radius.json", "bodies[0].shape.radius: must be > 0"},
    {"bad_dynamic_segment.json", "bodies[0].shape: a segment has no area: only static and kinematic bodies may have one"},
    {"bad_segment_field.json", "bodies[0].shape.point3: unknown field"},
    {"bad_too_many_vertices.json", "bodies[0].shape.vertices: must have 3 to 8 vertices (got 9)"},
    {"bad_duplicate_name.json", "bodies[2].name: duplicate name 'box' (also bodies[1])"},
    {"bad_name_chars.json", "bodies[0].name: 'a,b' may only contain letters, digits and the characters _-.:/#"},
    {"bad_force_body.json", "forces[0].bodies[1]: unknown body 'nobody'"},
    {"bad_force_type.json", "forces[0].type: must be one of \"gravity\", \"wind\" (got \"magnetism\")"},
    {"bad_wildcard.json", "forces[0].bodies[0]: no body name matches 'drop*'"},
    {"bad_generator.json", "generators[0].base: must be an integer in [1, 2000]"},
    {"bad_rain_region.json", "generators[0].region: holds 16 bodies of max_size 0.8, not 100"},
};

static void check_error(kg_result r, kg_scene* scene, const char* expected)
{
    KG_CHECK(r == KG_ERROR_PARSE);
    KG_CHECK(scene == NULL);
    if (strcmp(kg_last_error(), expected) != 0) {
        fprintf(stderr, "  got      '%s'\n  expected '%s'\n", kg_last_error(), expected);
        kg_test_failures++;
    }
}

static void test_error_files(void)
{
    for (size_t i = 0; i < sizeof kErrorFiles / sizeof kErrorFiles[0]; ++i) {
        char path[128], expected[512];
        snprintf(path, sizeof path, SCENES "%s", kErrorFiles[i].file);
        snprintf(expected, sizeof expected, "%s: %s", path, kErrorFiles[i].message);
        kg_scene* scene = (kg_scene*)&i; /* must come back NULL */
        kg_result r = kg_scene_load_file(path, &scene);
        check_error(r, scene, expected);
    }
}

static const error_case kErrorStrings[] = {
    {"{\"steps\": -1}", "steps: must be an integer in [0, 100000000]"},
    {"{\"substeps\": 0}", "substeps: must be an integer in [1, 64]"},
    {"{\"gravity\": [0, \"down\"]}", "gravity[1]: must be a number"},
    {"{\"bodies\": {}}", "bodies: must be an array"},
    {"{\"bodies\": [3]}", "bodies[0]: must be an object"},
    {"{\"bodies\": [{\"shape\": {\"type\": \"circle\"}}]}", "bodies[0].shape.radius: is required"},
    {"{\"bodies\": [{\"shape\": {\"type\": \"circle\", \"radius\": 1, \"width\": 2}}]}",
     "bodies[0].shape.width: unknown field"},
    {"{\"bodies\": [{\"shape\": {\"type\": \"polygon\", \"vertices\": [[0, 0], [1, 0], [1]]}}]}",
     "bodies[0].shape.vertices[2]: must be [x, y] (an array of two numbers)"},
    {"{\"bodies\": [{\"fixed_rotation\": 1, \"shape\": {\"type\": \"circle\", \"radius\": 1}}]}",
     "bodies[0].fixed_rotation: must be true or false"},
    {"{\"bodies\": [{\"name\": 7, \"shape\": {\"type\": \"circle\", \"radius\": 1}}]}",
     "bodies[0].name: must be a string"},
    {"{\"bodies\": [{\"density\": 0, \"shape\": {\"type\": \"circle\", \"radius\": 1}}]}",
     "bodies[0].density: must be > 0 for a dynamic body"},
    {"{\"forces\": [{\"type\": \"wind\", \"direction\": [0, 0], \"strength\": 1}]}",
     "forces[0].direction: must not be [0, 0] nor so short that it has no direction"},
    /* non-zero, but scaling it to unit length overflows: the engine would refuse it */
    {"{\"forces\": [{\"type\": \"wind\", \"direction\": [1e-45, 0], \"strength\": 1}]}",
     "forces[0].direction: must not be [0, 0] nor so short that it has no direction"},
    {"{\"forces\": [{\"type\": \"wind\", \"direction\": [1, 0]}]}", "forces[0].strength: is required"},
    {"{\"forces\": [{\"type\": \"gravity\", \"acceleration\": [0, 1], \"bodies\": []}]}",
     "forces[0].bodies: must name at least one body (leave it out for all bodies)"},
    {"{\"generators\": [{\"type\": \"smash\", \"count\": 3}]}", "generators[0].count: unknown field"},
    {"{\"generators\": [{\"type\": \"rain\", \"count\": 5, \"region\": [0, 0, -1, 5]}]}",
     "generators[0].region: must be [x0, y0, x1, y1] with x0 < x1 and y0 < y1"},
    {"{\"generators\": [{\"type\": \"rain\", \"count\": 5, \"region\": [0, 0, 9, 9], \"min_size\": 0.5, "
     "\"max_size\": 0.4}]}",
     "generators[0].max_size: must be >= min_size (0.5)"},
    {"{\"generators\": [{\"type\": \"stack\", \"name\": \"b\", \"count\": 2}, "
     "{\"type\": \"stack\", \"name\": \"b\", \"count\": 2}]}",
     "generators[1]: duplicate name 'b0' (body 0 has it)"},
    {"{\"generators\": [{\"type\": \"particles\", \"count\": 2, \"region\": [0, 0, 1, 1], \"mass\": 1, "
     "\"density\": 1}]}",
     "generators[0].mass: give density or mass, not both"},
    {"{\"bodies\": [{\"shape\": {\"type\": \"circle\", \"radius\": 1}, \"shapes\": []}]}",
     "bodies[0].shapes: give shape or shapes, not both"},
    {"{\"bodies\": [{\"shapes\": []}]}", "bodies[0].shapes: must hold 1 to 64 shapes (got 0)"},
    {"{\"bodies\": [{\"shapes\": [{\"type\": \"circle\", \"radius\": 1}]}], \"sensor\": true}",
     "sensor: unknown field"},
    {"{\"bodies\": [{\"shapes\": [{\"type\": \"circle\", \"radius\": 1}, {\"type\": \"box\", \"width\": 1, "
     "\"height\": 1, \"colour\": 2}]}]}",
     "bodies[0].shapes[1].colour: unknown field"},
    {"{\"bodies\": [{\"shapes\": [{\"type\": \"circle\", \"radius\": 1}, {\"type\": \"circle\", \"radius\": 1, "
     "\"restitution\": 2}]}]}",
     "bodies[0].shapes[1].restitution: must be in [0, 1]"},
    {"{\"bodies\": [{\"mass\": 2, \"shapes\": [{\"type\": \"circle\", \"radius\": 1}, {\"type\": \"circle\", "
     "\"radius\": 1}]}]}",
     "bodies[0].mass: is for a body of one shape: give each of its shapes a density"},
    {"{\"bodies\": [{\"shape\": {\"type\": \"chain\", \"points\": [[0, 0], [1, 0]]}}]}",
     "bodies[0].shape: a chain has no mass: only static and kinematic bodies may hold one (use capsules or polygons)"},
    {"{\"bodies\": [{\"type\": \"particle\", \"mass\": 1, \"shapes\": [{\"type\": \"chain\", \"points\": [[0, 0], [1, 0]]}]}]}",
     "bodies[0].shapes[0]: a chain has no mass: only static and kinematic bodies may hold one (use capsules or polygons)"},
    {"{\"bodies\": [{\"type\": \"static\", \"shape\": {\"type\": \"chain\", \"points\": [[0, 0]]}}]}",
     "bodies[0].shape.points: a chain needs at least 2 points (got 1)"},
    {"{\"bodies\": [{\"type\": \"static\", \"shape\": {\"type\": \"chain\", \"loop\": true, \"points\": [[0, 0], [1, 0]]}}]}",
     "bodies[0].shape.points: a chain loop needs at least 3 points (got 2)"},
    {"{\"bodies\": [{\"type\": \"static\", \"shape\": {\"type\": \"chain\", \"points\": [[0, 0], [1e999, 0]]}}]}",
     "bodies[0].shape.points[1][0]: must be a finite number (got inf)"},
    {"{\"bodies\": [{\"type\": \"static\", \"shapes\": [{\"type\": \"chain\", \"points\": [[0, 0], [3e38, 0]],"
     " \"center\": [3e38, 0]}]}]}",
     "bodies[0].shapes[0].points: chain point 1 is not finite"},
    {"{\"bodies\": [{\"type\": \"static\", \"shape\": {\"type\": \"chain\", \"points\": [[0, 0], [1, 0], [1, 0], [2, 0]]}}]}",
     "bodies[0].shape.points: chain segment 1 (points 1 and 2): segment points coincide (closer than 0.0001 m)"},
    {"{\"bodies\": [{\"type\": \"kinematic\", \"shape\": {\"type\": \"chain\", \"loop\": true,"
     " \"points\": [[0, 0], [1, 0], [1, 1], [0, 0]]}}]}",
     "bodies[0].shape.points: chain segment 3 (points 3 and 0): segment points coincide (closer than 0.0001 m)"},
    {"{\"bodies\": [{\"type\": \"static\", \"shape\": {\"type\": \"chain\", \"points\": 3}}]}",
     "bodies[0].shape.points: must be an array"},
    {"{\"bodies\": [{\"type\": \"static\", \"shape\": {\"type\": \"chain\", \"points\": [[0, 0], [1]]}}]}",
     "bodies[0].shape.points[1]: must be [x, y] (an array of two numbers)"},
    {"{\"bodies\": [{\"type\": \"static\", \"shape\": {\"type\": \"chain\"}}]}", "bodies[0].shape.points: is required"},
    {"{\"bodies\": [{\"type\": \"static\", \"shape\": {\"type\": \"chain\", \"loop\": 1, \"points\": [[0, 0], [1, 0]]}}]}",
     "bodies[0].shape.loop: must be true or false"},
    {"{\"bodies\": [{\"type\": \"static\", \"shape\": {\"type\": \"chain\", \"center\": [1, 0], \"points\": [[0, 0], [1, 0]]}}]}",
     "bodies[0].shape.center: unknown field"},
    {"{\"bodies\": [{\"type\": \"static\", \"shapes\": [{\"type\": \"chain\", \"sensor\": true, \"points\": [[0, 0], [1, 0]]}]}]}",
     "bodies[0].shapes[0].sensor: unknown field"},
    {"{\"bodies\": [{\"type\": \"static\", \"shape\": {\"type\": \"rope\"}}]}",
     "bodies[0].shape.type: must be one of \"box\", \"circle\", \"polygon\", \"capsule\", \"segment\", \"chain\" (got \"rope\")"},
};

static void test_error_strings(void)
{
    for (size_t i = 0; i < sizeof kErrorStrings / sizeof kErrorStrings[0]; ++i) {
        char expected[512];
        snprintf(expected, sizeof expected, "inline.json: %s", kErrorStrings[i].message);
        kg_scene* scene = (kg_scene*)&i; /* must come back NULL */
        const char* json = kErrorStrings[i].file;
        kg_result r = kg_scene_parse(json, strlen(json), "inline.json", &scene);
        check_error(r, scene, expected);
    }
}

/* "shapes": the first entry is the body def's shape with its material, the others follow
 * with theirs (the body's where left out), placed by "center" and "angle"; instantiated,
 * the body has them all and its mass is theirs. */
static void test_compound_body(void)
{
    const char* json = "{\"bodies\": [{\"name\": \"l\", \"friction\": 0.4, \"shapes\": ["
                       "{\"type\": \"box\", \"width\": 2, \"height\": 0.5, \"center\": [1, 0.25], \"density\": 2},"
                       "{\"type\": \"polygon\", \"vertices\": [[-0.25, -0.75], [0.25, -0.75], [0.25, 0.75], [-0.25, 0.75]],"
                       " \"center\": [0.25, 1.25], \"angle\": 0, \"restitution\": 0.5},"
                       "{\"type\": \"circle\", \"radius\": 0.1, \"center\": [2, 1], \"sensor\": true, \"mask\": 4}]}]}";
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_parse(json, strlen(json), "inline.json", &scene));
    if (!scene) {
        return;
    }
    KG_CHECK(kg_scene_body_shape_count(scene, 0) == 3);
    kg_body_shape_def first, second, third;
    KG_CHECK_OK(kg_scene_get_body_shape(scene, 0, 0, &first));
    KG_CHECK_OK(kg_scene_get_body_shape(scene, 0, 1, &second));
    KG_CHECK_OK(kg_scene_get_body_shape(scene, 0, 2, &third));
    KG_CHECK(first.density == 2.0f && first.friction == 0.4f && first.geometry.type == KG_SHAPE_POLYGON);
    KG_CHECK(second.density == 1.0f && second.restitution == 0.5f && second.friction == 0.4f);
    KG_CHECK(same_vec(second.geometry.vertices[0], (kg_vec2){0.0f, 0.5f}));
    KG_CHECK(third.is_sensor == 1 && third.mask == 4u && same_vec(third.geometry.center, (kg_vec2){2.0f, 1.0f}));
    KG_CHECK(kg_scene_get_body_shape(scene, 0, 3, &third) == KG_ERROR_INVALID_ARGUMENT);
    kg_world* world = NULL;
    kg_body body;
    KG_CHECK_OK(kg_scene_instantiate(scene, NULL, &world, &body));
    if (world) {
        KG_CHECK(kg_body_shape_count(world, body) == 3);
        kg_mass_data md;
        KG_CHECK_OK(kg_body_get_mass_data(world, body, &md));
        double circle = 3.14159265358979 * 0.01;
        KG_CHECK_NEAR(md.mass, 2.0 + 0.75 + circle, 1e-5);
        kg_destroy_world(world);
    }
    kg_scene_destroy(scene);
}

/* The chain of body index k of scene, which must be there. */
static kg_chain_def scene_chain(const kg_scene* scene, int index, int k)
{
    kg_chain_def def = kg_default_chain_def();
    KG_CHECK_OK(kg_scene_get_body_chain(scene, index, k, &def));
    return def;
}

/* good_chain.json: chains read with their material, placed by "center" and "angle"; the
 * world has one segment shape per segment; a box lands on the ground across a join, a ball
 * on the loop, and a box above a segment whose solid side is up falls through it. */
static void test_chains(void)
{
    kg_scene* scene = load(SCENES "good_chain.json");
    if (!scene) {
        return;
    }
    KG_CHECK(kg_scene_body_def(scene, 0)->shape.type == KG_SHAPE_NONE && kg_scene_body_chain_count(scene, 0) == 1);
    kg_chain_def ground = scene_chain(scene, 0, 0);
    KG_CHECK(ground.count == 5 && !ground.loop && ground.friction == 0.7f);
    KG_CHECK(same_vec(ground.points[0], (kg_vec2){10.0f, 0.0f}) && same_vec(ground.points[4], (kg_vec2){-10.0f, 0.0f}));
    /* the island's box is its own shape; its loop turned a quarter round, then moved up 1 m */
    KG_CHECK(kg_scene_body_shape_count(scene, 2) == 1 && kg_scene_body_chain_count(scene, 2) == 1);
    KG_CHECK(kg_scene_body_def(scene, 2)->shape.type == KG_SHAPE_POLYGON);
    kg_chain_def loop = scene_chain(scene, 2, 0);
    KG_CHECK(loop.count == 4 && loop.loop && loop.friction == 0.3f && loop.category == 2u && loop.mask == 0xFFFFFFFFu);
    KG_CHECK_NEAR(loop.points[0].x, 1.0, 1e-6);
    KG_CHECK_NEAR(loop.points[0].y, 0.0, 1e-6);
    KG_CHECK_NEAR(loop.points[2].x, -1.0, 1e-6);
    KG_CHECK_NEAR(loop.points[2].y, 2.0, 1e-6);
    KG_CHECK(kg_scene_get_body_chain(scene, 2, 1, &loop) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_scene_body_chain_count(scene, 3) == 0 && kg_scene_body_chain_count(scene, 99) == 0);

    kg_world* world = NULL;
    kg_body bodies[6];
    KG_CHECK_OK(kg_scene_instantiate(scene, NULL, &world, bodies));
    if (!world) {
        kg_scene_destroy(scene);
        return;
    }
    KG_CHECK(kg_body_shape_count(world, bodies[0]) == 4 && kg_body_shape_count(world, bodies[1]) == 1);
    kg_shape_id island[5];
    int count = 0;
    KG_CHECK_OK(kg_body_get_shapes(world, bodies[2], island, 5, &count));
    KG_CHECK(count == 5); /* the box, then the loop's 4 segments */
    kg_body_shape_def segment;
    KG_CHECK_OK(kg_shape_get_def(world, island[1], &segment));
    KG_CHECK(segment.geometry.type == KG_SHAPE_SEGMENT && segment.friction == 0.3f && segment.category == 2u);
    for (int step = 0; step < 120; ++step) {
        KG_CHECK_OK(kg_world_step(world, 1.0f / 60.0f));
    }
    kg_vec2 box, fallthrough, ball;
    KG_CHECK_OK(kg_body_get_position(world, bodies[3], &box));
    KG_CHECK_OK(kg_body_get_position(world, bodies[4], &fallthrough));
    KG_CHECK_OK(kg_body_get_position(world, bodies[5], &ball));
    printf("measured: good_chain.json after 2 s: box y %.5f (0.5), ball y %.5f (2.5), box behind a segment y %.3f "
           "(fell from 3)\n", box.y, ball.y, fallthrough.y);
    KG_CHECK_NEAR(box.y, 0.5, 5e-3);
    KG_CHECK_NEAR(box.x, 0.0, 5e-3);
    KG_CHECK_NEAR(ball.y, 2.5, 5e-3);
    KG_CHECK(fallthrough.y < -10.0f);
    kg_destroy_world(world);
    kg_scene_destroy(scene);
}

/* A chain of more points than a file may hold is refused before anything else. */
static void test_chain_points_cap(void)
{
    const int count = 100001;
    const char* head = "{\"bodies\": [{\"type\": \"static\", \"shape\": {\"type\": \"chain\", \"points\": [";
    size_t size = strlen(head) + 8 * (size_t)count + 16;
    char* json = malloc(size);
    size_t used = (size_t)snprintf(json, size, "%s", head);
    for (int i = 0; i < count; ++i) {
        used += (size_t)snprintf(json + used, size - used, "%s[%d, 0]", i > 0 ? "," : "", i % 10);
    }
    snprintf(json + used, size - used, "]}}]}");
    kg_scene* scene = (kg_scene*)json; /* must come back NULL */
    kg_result r = kg_scene_parse(json, strlen(json), "inline.json", &scene);
    check_error(r, scene, "inline.json: bodies[0].shape.points: must hold at most 100000 points (got 100001)");
    free(json);
}

static void test_unreadable_file(void)
{
    kg_scene* scene = NULL;
    KG_CHECK(kg_scene_load_file(SCENES "no_such_scene.json", &scene) == KG_ERROR_IO);
    KG_CHECK(scene == NULL);
    const char* prefix = SCENES "no_such_scene.json: cannot open (";
    KG_CHECK(strncmp(kg_last_error(), prefix, strlen(prefix)) == 0);
}

static void test_samples_load(void)
{
    static const char* const samples[] = {"box_stack.json", "pyramid.json", "rain_wind.json", "particles.json",
                                          "compound.json", "chain_terrain.json"};
    for (size_t i = 0; i < sizeof samples / sizeof samples[0]; ++i) {
        char path[512];
        snprintf(path, sizeof path, "%s/samples/%s", KG_SOURCE_DIR, samples[i]);
        kg_scene* scene = load(path);
        KG_CHECK(scene && kg_scene_body_count(scene) > 0);
        kg_scene_destroy(scene);
    }
}

/* ---- generators ---- */

static void test_json_generators(void)
{
    kg_scene* scene = load(SCENES "good_generators.json");
    if (!scene) {
        return;
    }
    /* marker, container 3, pyramid 10, stack 3, rain 20, particles 50 */
    KG_CHECK(kg_scene_body_count(scene) == 87);
    KG_CHECK(kg_scene_find_body(scene, "marker") == 0);
    KG_CHECK(kg_scene_find_body(scene, "container0_0") == 1);
    KG_CHECK(kg_scene_body_def(scene, 1)->type == KG_BODY_STATIC && kg_scene_body_def(scene, 1)->friction == 0.7f);
    int pyramid = kg_scene_find_body(scene, "pyr_0");
    KG_CHECK(pyramid == 4 && kg_scene_find_body(scene, "pyr_9") == 13);
    KG_CHECK(same_vec(kg_scene_body_def(scene, pyramid)->position, (kg_vec2){19.25f, 0.25f}));
    KG_CHECK(same_vec(kg_scene_body_def(scene, 13)->position, (kg_vec2){20.0f, 1.75f}));
    KG_CHECK(kg_scene_body_def(scene, pyramid)->density == 2.0f);
    int stack = kg_scene_find_body(scene, "stack2_0");
    KG_CHECK(stack == 14);
    KG_CHECK_NEAR(kg_scene_body_def(scene, stack + 2)->position.y, 2.0f * 2.1f + 1.0f, 1e-6);
    KG_CHECK(kg_scene_body_def(scene, stack)->restitution == 0.1f);
    KG_CHECK(kg_scene_find_body(scene, "drop19") == 36 && kg_scene_find_body(scene, "dust49") == 86);
    KG_CHECK(kg_scene_body_def(scene, 86)->type == KG_BODY_PARTICLE && kg_scene_body_def(scene, 86)->mass == 0.02f);

    const kg_scene_force* wind = kg_scene_get_force(scene, 0);
    KG_CHECK(wind->body_count == 21 && wind->body_indices[0] == 0 && wind->body_indices[1] == 17);
    const kg_scene_force* lift = kg_scene_get_force(scene, 1);
    KG_CHECK(lift->body_count == 50 && lift->body_indices[0] == 37);
    kg_scene_destroy(scene);
}

static kg_scene* generate(const char* name, uint32_t seed)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_generate(name, seed, &scene));
    return scene;
}

/* The ground box's half extents, from its vertices. */
static kg_vec2 half_extents(const kg_body_def* def)
{
    kg_vec2 h = {0.0f, 0.0f};
    for (int i = 0; i < def->shape.count; ++i) {
        h.x = fmaxf(h.x, fabsf(def->shape.vertices[i].x));
        h.y = fmaxf(h.y, fabsf(def->shape.vertices[i].y));
    }
    return h;
}

static void test_large_pyramid(void)
{
    kg_scene* scene = generate("large_pyramid", 0);
    if (!scene) {
        return;
    }
    KG_CHECK(kg_scene_body_count(scene) == 5051);
    KG_CHECK(kg_scene_steps(scene) == 500);
    KG_CHECK(same_vec(kg_scene_world_def(scene)->gravity, (kg_vec2){0.0f, -10.0f}));
    KG_CHECK(kg_scene_dt(scene) == 1.0f / 60.0f);
    const kg_body_def* ground = kg_scene_body_def(scene, 0);
    KG_CHECK(ground->type == KG_BODY_STATIC && same_vec(ground->position, (kg_vec2){0.0f, -1.0f}));
    KG_CHECK(same_vec(half_extents(ground), (kg_vec2){100.0f, 1.0f}));
    int index = 1, misplaced = 0;
    for (int i = 0; i < 100; ++i) {
        for (int j = i; j < 100; ++j, ++index) {
            const kg_body_def* box = kg_scene_body_def(scene, index);
            kg_vec2 expected = {(float)(i + 1) * 0.5f + (float)(j - i) - 50.0f, (float)(2 * i + 1) * 0.5f};
            misplaced += !same_vec(box->position, expected) || box->type != KG_BODY_DYNAMIC ||
                         box->density != 1.0f || !same_vec(half_extents(box), (kg_vec2){0.5f, 0.5f});
        }
    }
    KG_CHECK(misplaced == 0);
    KG_CHECK(same_vec(kg_scene_body_def(scene, 5050)->position, (kg_vec2){0.0f, 99.5f}));
    KG_CHECK(strcmp(kg_scene_body_name(scene, 5050), "box5049") == 0);
    kg_scene_destroy(scene);
}

static void test_many_pyramids(void)
{
    kg_scene* scene = generate("many_pyramids", 0);
    if (!scene) {
        return;
    }
    KG_CHECK(kg_scene_body_count(scene) == 20 + 22000);
    KG_CHECK(kg_scene_steps(scene) == 200);
    for (int row = 0; row < 20; ++row) {
        const kg_body_def* ground = kg_scene_body_def(scene, row);
        /* top face on Box2D's ground segment y = 11 * row, 220 m wide */
        KG_CHECK(ground->type == KG_BODY_STATIC);
        KG_CHECK_NEAR(ground->position.y + half_extents(ground).y, 11.0f * (float)row, 1e-5);
        KG_CHECK(half_extents(ground).x == 110.0f && ground->position.x == 0.0f);
    }
    /* first pyramid: centerX = -110 + 2 * 0.5 = -109; its first box at centerX + 0.5 - 0.5 */
    KG_CHECK(same_vec(kg_scene_body_def(scene, 20)->position, (kg_vec2){-109.0f, 0.5f}));
    /* its top box: row 9 at y = 9.5, x = centerX + 10 * 0.5 - 0.5 */
    KG_CHECK(same_vec(kg_scene_body_def(scene, 20 + 54)->position, (kg_vec2){-104.5f, 9.5f}));
    /* second pyramid of the first row: 11 m further */
    KG_CHECK(same_vec(kg_scene_body_def(scene, 20 + 55)->position, (kg_vec2){-98.0f, 0.5f}));
    /* the last pyramid (row 19, column 19): its first box */
    KG_CHECK(same_vec(kg_scene_body_def(scene, 20 + 399 * 55)->position, (kg_vec2){-109.0f + 19.0f * 11.0f, 209.5f}));
    kg_scene_destroy(scene);
}

static void test_smash(void)
{
    kg_scene* scene = generate("smash", 0);
    if (!scene) {
        return;
    }
    KG_CHECK(kg_scene_body_count(scene) == 1 + 120 * 80);
    KG_CHECK(kg_scene_steps(scene) == 300);
    KG_CHECK(same_vec(kg_scene_world_def(scene)->gravity, (kg_vec2){0.0f, 0.0f}));
    const kg_body_def* projectile = kg_scene_body_def(scene, 0);
    KG_CHECK(same_vec(projectile->position, (kg_vec2){-20.0f, 0.0f}));
    KG_CHECK(same_vec(projectile->velocity, (kg_vec2){40.0f, 0.0f}));
    KG_CHECK(projectile->density == 8.0f && same_vec(half_extents(projectile), (kg_vec2){4.0f, 4.0f}));
    const float d = 0.4f;
    int misplaced = 0;
    for (int i = 0; i < 120; ++i) {
        for (int j = 0; j < 80; ++j) {
            const kg_body_def* box = kg_scene_body_def(scene, 1 + i * 80 + j);
            kg_vec2 expected = {(float)i * d + 30.0f, ((float)j - 40.0f) * d};
            misplaced += !same_vec(box->position, expected) || !same_vec(half_extents(box), (kg_vec2){0.2f, 0.2f});
        }
    }
    KG_CHECK(misplaced == 0);
    kg_scene_destroy(scene);
}

static void test_tumbler_layout(void)
{
    kg_scene* scene = generate("tumbler", 0);
    if (!scene) {
        return;
    }
    KG_CHECK(kg_scene_body_count(scene) == 4 + 45 * 45);
    KG_CHECK(kg_scene_steps(scene) == 750);
    const float omega = 25.0f * 3.14159265358979f / 180.0f;
    for (int k = 0; k < 4; ++k) {
        const kg_body_def* wall = kg_scene_body_def(scene, k);
        kg_vec2 pivot, r;
        KG_CHECK(wall->type == KG_BODY_KINEMATIC);
        KG_CHECK(kg_scene_body_pivot(scene, k, &pivot) && same_vec(pivot, (kg_vec2){0.0f, 10.0f}));
        r = (kg_vec2){wall->position.x - pivot.x, wall->position.y - pivot.y};
        KG_CHECK_NEAR(sqrtf(r.x * r.x + r.y * r.y), 10.0f, 1e-6);
        KG_CHECK_NEAR(wall->angular_velocity, omega, 1e-7);
        KG_CHECK_NEAR(wall->velocity.x, -omega * r.y, 1e-6);
        KG_CHECK_NEAR(wall->velocity.y, omega * r.x, 1e-6);
        kg_vec2 h = half_extents(wall);
        KG_CHECK(fminf(h.x, h.y) == 0.5f && fmaxf(h.x, h.y) == 10.0f);
    }
    KG_CHECK(same_vec(kg_scene_body_def(scene, 4)->position, (kg_vec2){-9.0f, 1.0f}));
    KG_CHECK(same_vec(half_extents(kg_scene_body_def(scene, 4)), (kg_vec2){0.125f, 0.125f}));
    const kg_body_def* last = kg_scene_body_def(scene, 4 + 45 * 45 - 1);
    KG_CHECK_NEAR(last->position.x, 8.6f, 1e-4);
    KG_CHECK_NEAR(last->position.y, 18.6f, 1e-4);
    kg_scene_destroy(scene);
}

/* A drop's bounding radius: half the diagonal of a box, the radius of a circle. */
static float bound_radius(const kg_body_def* def)
{
    if (def->shape.type == KG_SHAPE_CIRCLE) {
        return def->shape.radius;
    }
    kg_vec2 h = half_extents(def);
    return sqrtf(h.x * h.x + h.y * h.y);
}

static void test_rain(void)
{
    kg_scene* scene = generate("rain_200", 5);
    kg_scene* again = generate("rain_200", 5);
    kg_scene* other = generate("rain_200", 6);
    if (!scene || !again || !other) {
        return;
    }
    KG_CHECK(kg_scene_body_count(scene) == 3 + 200);
    int circles = 0, overlaps = 0, outside = 0, same = 1, differ = 0;
    float inner = half_extents(kg_scene_body_def(scene, 0)).x - 1.0f; /* floor minus a wall */
    for (int i = 3; i < 203; ++i) {
        const kg_body_def* a = kg_scene_body_def(scene, i);
        circles += a->shape.type == KG_SHAPE_CIRCLE;
        float size = a->shape.type == KG_SHAPE_CIRCLE ? 2.0f * a->shape.radius : 2.0f * half_extents(a).x;
        KG_CHECK(size >= 0.2f - 1e-6f && size <= 0.8f + 1e-6f);
        outside += fabsf(a->position.x) + bound_radius(a) > inner || a->position.y - bound_radius(a) < 0.0f;
        for (int j = 3; j < i; ++j) {
            const kg_body_def* b = kg_scene_body_def(scene, j);
            float dx = a->position.x - b->position.x, dy = a->position.y - b->position.y;
            overlaps += sqrtf(dx * dx + dy * dy) < bound_radius(a) + bound_radius(b);
        }
        same &= memcmp(a, kg_scene_body_def(again, i), sizeof *a) == 0;
        differ |= !same_vec(a->position, kg_scene_body_def(other, i)->position);
    }
    KG_CHECK(circles > 50 && circles < 150);
    KG_CHECK(overlaps == 0 && outside == 0);
    KG_CHECK(same && differ);
    kg_scene_destroy(scene);
    kg_scene_destroy(again);
    kg_scene_destroy(other);
}

static void test_particles_and_small_generators(void)
{
    kg_scene* particles = generate("particles_300", 1);
    kg_scene* pyramid = generate("pyramid_20", 1);
    kg_scene* stack = generate("stack_7", 1);
    if (!particles || !pyramid || !stack) {
        return;
    }
    KG_CHECK(kg_scene_body_count(particles) == 3 + 300);
    const kg_body_def* p = kg_scene_body_def(particles, 3);
    KG_CHECK(p->type == KG_BODY_PARTICLE && p->shape.type == KG_SHAPE_CIRCLE && p->shape.radius == 0.05f);
    KG_CHECK(kg_scene_body_count(pyramid) == 1 + 210);
    KG_CHECK(same_vec(kg_scene_body_def(pyramid, 210)->position, (kg_vec2){0.0f, 19.5f}));
    KG_CHECK(kg_scene_body_count(stack) == 8);
    KG_CHECK(same_vec(kg_scene_body_def(stack, 7)->position, (kg_vec2){0.0f, 6.5f}));
    kg_scene_destroy(particles);
    kg_scene_destroy(pyramid);
    kg_scene_destroy(stack);
}

static void test_generator_names(void)
{
    static const char* const bad[] = {"pyramid_0", "pyramid_", "pyramid_2x", "pyramid_2001", "stack_-1",
                                      "rain", "volcano", "", "particles_99999999999"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        kg_scene* scene = NULL;
        KG_CHECK(kg_scene_generate(bad[i], 1, &scene) == KG_ERROR_INVALID_ARGUMENT);
        KG_CHECK(scene == NULL);
    }
    kg_scene* scene = NULL;
    kg_scene_generate("pyramid_0", 1, &scene);
    KG_CHECK(strcmp(kg_last_error(), "scene 'pyramid_0': pyramid_N needs N in [1, 2000]") == 0);
    kg_scene_generate("volcano", 1, &scene);
    KG_CHECK(strncmp(kg_last_error(), "unknown scene 'volcano' (generators: pyramid_B,", 46) == 0);
}

/* ---- building and instantiating ---- */

static kg_body_def circle_at(float x, float y)
{
    kg_body_def def = kg_default_body_def();
    def.shape = kg_circle_shape(0.5f);
    def.position = (kg_vec2){x, y};
    return def;
}

static void test_builder(void)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_create(&scene));
    kg_body_def def = circle_at(0.0f, 0.0f);
    KG_CHECK_OK(kg_scene_add_body(scene, "a", &def));
    KG_CHECK_OK(kg_scene_add_body(scene, NULL, &def));
    KG_CHECK(kg_scene_add_body(scene, "a", &def) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_scene_add_body(scene, "has space", &def) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_scene_add_body(scene, "", &def) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_scene_body_count(scene) == 2);
    KG_CHECK(strcmp(kg_scene_body_name(scene, 1), "body1") == 0);
    KG_CHECK(kg_scene_find_body(scene, "body1") == 1 && kg_scene_find_body(scene, "zz") == -1);
    KG_CHECK(kg_scene_body_def(scene, 2) == NULL && kg_scene_body_name(scene, -1) == NULL);

    int indices[1] = {1};
    kg_scene_force force = {KG_SCENE_FORCE_WIND, {1.0f, 0.0f}, 2.0f, 0.5f, 1, indices};
    KG_CHECK_OK(kg_scene_add_force(scene, &force));
    indices[0] = 0; /* the scene keeps its own copy */
    KG_CHECK(kg_scene_get_force(scene, 0)->body_indices[0] == 1);
    indices[0] = 2;
    KG_CHECK(kg_scene_add_force(scene, &force) == KG_ERROR_INVALID_ARGUMENT);
    force.body_count = 0;
    force.strength = -1.0f;
    KG_CHECK(kg_scene_add_force(scene, &force) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_scene_force_count(scene) == 1);

    KG_CHECK(kg_scene_set_body_pivot(scene, 0, (kg_vec2){0.0f, 0.0f}) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK_OK(kg_scene_set_dt(scene, 0.01f));
    KG_CHECK(kg_scene_set_dt(scene, 0.0f) == KG_ERROR_INVALID_ARGUMENT && kg_scene_dt(scene) == 0.01f);
    KG_CHECK_OK(kg_scene_set_steps(scene, 42));
    KG_CHECK(kg_scene_steps(scene) == 42);
    kg_scene_world_def(scene)->substeps = 8;
    KG_CHECK(kg_scene_world_def(scene)->substeps == 8);
    kg_scene_destroy(scene);
}

static void test_instantiate_bodies(void)
{
    kg_scene* scene = load(SCENES "good_full.json");
    if (!scene) {
        return;
    }
    kg_world* world = NULL;
    kg_body bodies[6];
    KG_CHECK_OK(kg_scene_instantiate(scene, NULL, &world, bodies));
    if (!world) {
        kg_scene_destroy(scene);
        return;
    }
    KG_CHECK(kg_world_body_count(world) == 6);
    KG_CHECK(same_vec(kg_world_get_gravity(world), (kg_vec2){0.5f, -9.5f}));
    KG_CHECK(kg_world_get_def(world)->substeps == 6);
    for (int i = 0; i < 6; ++i) {
        const kg_body_def* def = kg_scene_body_def(scene, i);
        kg_body_state state;
        kg_body_type type;
        KG_CHECK_OK(kg_body_get_state(world, bodies[i], &state));
        KG_CHECK_OK(kg_body_get_type(world, bodies[i], &type));
        KG_CHECK(type == def->type);
        KG_CHECK_NEAR(state.position.x, def->position.x, 1e-5);
        KG_CHECK_NEAR(state.position.y, def->position.y, 1e-5);
    }
    kg_mass_data mass;
    KG_CHECK_OK(kg_body_get_mass_data(world, bodies[2], &mass));
    KG_CHECK_NEAR(mass.mass, 7.0f, 1e-5);
    kg_destroy_world(world);

    /* an override replaces the scene's world settings; capacities still grow to fit */
    kg_world_def def = kg_default_world_def();
    def.gravity = (kg_vec2){0.0f, -1.0f};
    def.max_bodies = 2;
    KG_CHECK_OK(kg_scene_instantiate(scene, &def, &world, NULL));
    if (world) {
        KG_CHECK(same_vec(kg_world_get_gravity(world), (kg_vec2){0.0f, -1.0f}));
        KG_CHECK(kg_world_body_count(world) == 6);
        kg_destroy_world(world);
    }
    kg_scene_destroy(scene);
}

/* Forces land on the bodies they name only. */
static void test_instantiate_forces(void)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_create(&scene));
    kg_scene_world_def(scene)->gravity = (kg_vec2){0.0f, 0.0f};
    kg_body_def a = circle_at(-10.0f, 0.0f), b = circle_at(10.0f, 0.0f);
    KG_CHECK_OK(kg_scene_add_body(scene, "a", &a));
    KG_CHECK_OK(kg_scene_add_body(scene, "b", &b));
    int only_b[1] = {1};
    kg_scene_force lift = {KG_SCENE_FORCE_GRAVITY, {0.0f, 6.0f}, 0.0f, 0.0f, 1, only_b};
    kg_scene_force wind = {KG_SCENE_FORCE_WIND, {1.0f, 0.0f}, 3.0f, 0.0f, 0, NULL};
    KG_CHECK_OK(kg_scene_add_force(scene, &lift));
    KG_CHECK_OK(kg_scene_add_force(scene, &wind));
    kg_world* world = NULL;
    kg_body bodies[2];
    KG_CHECK_OK(kg_scene_instantiate(scene, NULL, &world, bodies));
    if (world) {
        float dt = kg_scene_dt(scene);
        KG_CHECK_OK(kg_scene_step(scene, world, bodies, dt));
        kg_vec2 va, vb;
        kg_mass_data mass;
        KG_CHECK_OK(kg_body_get_velocity(world, bodies[0], &va));
        KG_CHECK_OK(kg_body_get_velocity(world, bodies[1], &vb));
        KG_CHECK_OK(kg_body_get_mass_data(world, bodies[0], &mass));
        KG_CHECK(va.y == 0.0f);
        KG_CHECK_NEAR(vb.y, 6.0f * dt, 1e-5);
        KG_CHECK_NEAR(va.x, 3.0f / mass.mass * dt, 1e-5);
        KG_CHECK_NEAR(vb.x, va.x, 1e-7);
        kg_destroy_world(world);
    }
    kg_scene_destroy(scene);
}

/* The tumbler's walls turn about the common centre: after one second they are 25
 * degrees round, still 10 m from it. */
static void test_pivots_keep_walls_on_circle(void)
{
    kg_scene* scene = generate("tumbler", 0);
    if (!scene) {
        return;
    }
    kg_world* world = NULL;
    kg_body* bodies = malloc((size_t)kg_scene_body_count(scene) * sizeof *bodies);
    KG_CHECK_OK(kg_scene_instantiate(scene, NULL, &world, bodies));
    for (int step = 0; world && step < 60; ++step) {
        KG_CHECK_OK(kg_scene_step(scene, world, bodies, 1.0f / 60.0f));
    }
    const float turn = 25.0f * 3.14159265358979f / 180.0f;
    for (int k = 0; world && k < 4; ++k) {
        kg_body_state s;
        KG_CHECK_OK(kg_body_get_state(world, bodies[k], &s));
        const kg_body_def* def = kg_scene_body_def(scene, k);
        kg_vec2 r0 = {def->position.x, def->position.y - 10.0f};
        kg_vec2 expected = {cosf(turn) * r0.x - sinf(turn) * r0.y, sinf(turn) * r0.x + cosf(turn) * r0.y + 10.0f};
        KG_CHECK_NEAR(s.position.x, expected.x, 2e-3);
        KG_CHECK_NEAR(s.position.y, expected.y, 2e-3);
        KG_CHECK_NEAR(s.angle, turn, 1e-4);
    }
    if (world) {
        kg_destroy_world(world);
    }
    free(bodies);
    kg_scene_destroy(scene);
}

/* The builder checks a body as kg_create_body would, so a scene it accepts always
 * instantiates (the scene fuzzer found definitions that did not). */
/* kg_scene_add_body_chain checks what kg_create_chain will, and keeps its own copy. */
static void test_builder_chains(void)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_create(&scene));
    kg_body_def ground = kg_default_body_def();
    ground.type = KG_BODY_STATIC;
    kg_body_def ball = circle_at(0.0f, 1.0f);
    KG_CHECK_OK(kg_scene_add_body(scene, "ground", &ground));
    KG_CHECK_OK(kg_scene_add_body(scene, "ball", &ball));
    kg_vec2 points[3] = {{2.0f, 0.0f}, {0.0f, 0.0f}, {-2.0f, 0.0f}};
    kg_chain_def def = kg_default_chain_def();
    def.points = points;
    def.count = 3;
    KG_CHECK(kg_scene_add_body_chain(scene, 1, &def) == KG_ERROR_INVALID_ARGUMENT); /* a dynamic body */
    KG_CHECK(kg_scene_add_body_chain(scene, 2, &def) == KG_ERROR_INVALID_ARGUMENT);
    points[1].y = NAN;
    KG_CHECK(kg_scene_add_body_chain(scene, 0, &def) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(strcmp(kg_last_error(), "chain point 1 is not finite") == 0);
    points[1].y = 0.0f;
    def.friction = -1.0f;
    KG_CHECK(kg_scene_add_body_chain(scene, 0, &def) == KG_ERROR_INVALID_ARGUMENT);
    def.friction = 0.6f;
    KG_CHECK(kg_scene_body_chain_count(scene, 0) == 0 && kg_scene_body_chain_count(scene, 1) == 0);
    KG_CHECK_OK(kg_scene_add_body_chain(scene, 0, &def));
    points[0].x = 5.0f; /* the scene has its own copy */
    kg_chain_def copy = kg_default_chain_def();
    KG_CHECK_OK(kg_scene_get_body_chain(scene, 0, 0, &copy));
    KG_CHECK(copy.count == 3 && copy.points != points && copy.points[0].x == 2.0f);
    kg_world* world = NULL;
    kg_body bodies[2];
    KG_CHECK_OK(kg_scene_instantiate(scene, NULL, &world, bodies));
    if (world) {
        KG_CHECK(kg_body_shape_count(world, bodies[0]) == 2);
        kg_destroy_world(world);
    }
    kg_scene_destroy(scene);
}

static void test_builder_refuses_bad_body(void)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_create(&scene));
    kg_body_def def = circle_at(0.0f, 0.0f);
    def.friction = -1.0f;
    KG_CHECK(kg_scene_add_body(scene, "slippery", &def) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(strstr(kg_last_error(), "friction") != NULL);
    def = circle_at(0.0f, 0.0f);
    def.shape = kg_circle_shape(100.0f);
    def.density = 1.0e38f; /* a mass of 3e42 kg: beyond single precision */
    KG_CHECK(kg_scene_add_body(scene, "heavy", &def) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_scene_body_count(scene) == 0);
    kg_scene_destroy(scene);
}

static void test_generated_scenes_instantiate(void)
{
    static const char* const names[] = {"large_pyramid", "many_pyramids", "smash", "tumbler", "rain_500",
                                        "particles_1000", "pyramid_30", "stack_20"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i) {
        kg_scene* scene = generate(names[i], 1);
        kg_world* world = NULL;
        if (!scene) {
            continue;
        }
        kg_world_def def = *kg_scene_world_def(scene);
        def.backend = KG_BACKEND_CPU;
        KG_CHECK_OK(kg_scene_instantiate(scene, &def, &world, NULL));
        if (world) {
            KG_CHECK(kg_world_body_count(world) == kg_scene_body_count(scene));
            kg_destroy_world(world);
        }
        kg_scene_destroy(scene);
    }
}

/* issue 18: an 80-byte file asks a generator for a million bodies; under max_bodies it is
 * refused at the field that asks, before they are allocated, and the file size cap holds
 * too. Without limits the same scene loads (checked with a smaller count). */
static void test_limits_refuse_generators(void)
{
    kg_scene_limits limits = kg_default_scene_limits();
    limits.max_bodies = 1000;
    kg_scene* scene = (kg_scene*)&limits; /* must come back NULL */
    kg_result r = kg_scene_load_file_limited(SCENES "hostile_million_bodies.json", &limits, &scene);
    check_error(r, scene,
                SCENES "hostile_million_bodies.json: generators[0].count: asks for 1000000 bodies, but max_bodies (1000) "
                       "leaves room for 1000");
    const char* pyramid = "{\"generators\": [{\"type\": \"pyramid\", \"base\": 45}]}"; /* 1035 boxes */
    r = kg_scene_parse_limited(pyramid, strlen(pyramid), "p.json", &limits, &scene);
    check_error(r, scene, "p.json: generators[0].base: asks for 1035 bodies, but max_bodies (1000) leaves room for 1000");
    limits.max_file_bytes = 16;
    KG_CHECK(kg_scene_load_file_limited(SCENES "hostile_million_bodies.json", &limits, &scene) == KG_ERROR_IO);
    KG_CHECK(scene == NULL && strstr(kg_last_error(), "hostile_million_bodies.json") != NULL);
}

/* Explicit bodies count as well, and the generators get only the room left; a scene at
 * exactly the limit loads, and afterwards is an ordinary scene that code can add to. */
static void test_limits_count_every_body(void)
{
    const char* json = "{\"bodies\": [{\"shape\": {\"type\": \"circle\", \"radius\": 1}}],"
                       " \"generators\": [{\"type\": \"stack\", \"count\": 4}]}";
    kg_scene_limits limits = kg_default_scene_limits();
    limits.max_bodies = 4;
    kg_scene* scene = NULL;
    kg_result r = kg_scene_parse_limited(json, strlen(json), "s.json", &limits, &scene);
    check_error(r, scene, "s.json: generators[0].count: asks for 4 bodies, but max_bodies (4) leaves room for 3");
    limits.max_bodies = 5;
    KG_CHECK_OK(kg_scene_parse_limited(json, strlen(json), "s.json", &limits, &scene));
    KG_CHECK(kg_scene_body_count(scene) == 5);
    kg_body_def def = kg_default_body_def();
    def.type = KG_BODY_STATIC;
    KG_CHECK_OK(kg_scene_add_body(scene, "extra", &def));
    kg_scene_destroy(scene);
    limits.max_bodies = -1;
    KG_CHECK(kg_scene_parse_limited(json, strlen(json), "s.json", &limits, &scene) == KG_ERROR_INVALID_ARGUMENT);
}

/* A generator's name under limits: refused before a body is made when it asks for more,
 * at exactly the limit it is the scene kg_scene_generate makes, and handed back with the
 * default limits like a loaded one. */
static void test_limits_generator_names(void)
{
    kg_scene_limits limits = kg_default_scene_limits();
    limits.max_bodies = 1000;
    kg_scene* scene = (kg_scene*)&limits; /* must come back NULL */
    const char* names[2] = {"rain_1000000", "many_pyramids"};
    for (int i = 0; i < 2; ++i) {
        char expected[128];
        snprintf(expected, sizeof expected, "scene '%s': more than max_bodies (1000) bodies", names[i]);
        KG_CHECK(kg_scene_generate_limited(names[i], 1u, &limits, &scene) == KG_ERROR_INVALID_ARGUMENT);
        KG_CHECK(scene == NULL && strcmp(kg_last_error(), expected) == 0);
    }
    kg_scene* unlimited = NULL;
    KG_CHECK_OK(kg_scene_generate("pyramid_10", 1u, &unlimited));
    limits.max_bodies = kg_scene_body_count(unlimited);
    KG_CHECK_OK(kg_scene_generate_limited("pyramid_10", 1u, &limits, &scene));
    KG_CHECK(kg_scene_body_count(scene) == kg_scene_body_count(unlimited));
    kg_body_def def = kg_default_body_def();
    def.type = KG_BODY_STATIC;
    KG_CHECK_OK(kg_scene_add_body(scene, "extra", &def));
    kg_scene_destroy(scene);
    kg_scene_destroy(unlimited);
    limits.max_bodies = -1;
    KG_CHECK(kg_scene_generate_limited("pyramid_10", 1u, &limits, &scene) == KG_ERROR_INVALID_ARGUMENT);
}

/* A Tiled map's object bodies count too (the map loaded once without limits to know how
 * many it has). */
static void test_limits_tiled_objects(void)
{
    const char* map = KG_SOURCE_DIR "/tests/data/tiled/embedded.tmj";
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_load_tiled(map, &scene));
    int bodies = kg_scene_body_count(scene);
    kg_scene_destroy(scene);
    KG_CHECK(bodies > 0);
    kg_scene_limits limits = kg_default_scene_limits();
    limits.max_bodies = bodies - 1;
    KG_CHECK(kg_scene_load_tiled_limited(map, &limits, &scene) == KG_ERROR_PARSE && scene == NULL);
    KG_CHECK(strstr(kg_last_error(), "max_bodies") != NULL);
    limits.max_bodies = bodies;
    KG_CHECK_OK(kg_scene_load_tiled_limited(map, &limits, &scene));
    kg_scene_destroy(scene);
}

/* Whether a message holds no control character (C0 or DEL) and none of the bytes that
 * are never valid UTF-8 which the hostile names below use. */
static int kg_message_is_clean(const char* text)
{
    for (const unsigned char* c = (const unsigned char*)text; *c; ++c) {
        if (*c < 0x20 || *c == 0x7f || *c == 0xff || *c == 0xfe || *c == 0xc0) {
            return 0;
        }
    }
    return 1;
}

/* issue 18: names, keys and file paths echoed in loader messages lose their control
 * characters and invalid UTF-8 (a terminal would run "\x1b[31m"), keeping the rest,
 * valid UTF-8 included. */
static void test_messages_echo_clean_names(void)
{
    const char* bad_name = "{\"bodies\": [{\"name\": \"\\u001b[31mred\xff\xfe\xc0\xaf\xc3\xa9\", "
                           "\"shape\": {\"type\": \"circle\", \"radius\": 1}}]}";
    kg_scene* scene = NULL;
    KG_CHECK(kg_scene_parse(bad_name, strlen(bad_name), "n.json", &scene) == KG_ERROR_PARSE && scene == NULL);
    KG_CHECK(kg_message_is_clean(kg_last_error()));
    KG_CHECK(strstr(kg_last_error(), "n.json: bodies[0].name: '?[31mred????\xc3\xa9' may only contain") != NULL);

    const char* bad_key = "{\"bodies\": [{\"\\u001b]0;title\\u0007\xff\": 1}]}";
    KG_CHECK(kg_scene_parse(bad_key, strlen(bad_key), "k.json", &scene) == KG_ERROR_PARSE);
    KG_CHECK(kg_message_is_clean(kg_last_error()));
    KG_CHECK(strcmp(kg_last_error(), "k.json: bodies[0].?]0;title??: unknown field") == 0);

    KG_CHECK(kg_scene_load_file(SCENES "missing\x1b[2J\xfe.json", &scene) == KG_ERROR_IO);
    KG_CHECK(kg_message_is_clean(kg_last_error()));
    KG_CHECK(strstr(kg_last_error(), SCENES "missing?[2J?.json: cannot open") != NULL);
}

KG_TEST_MAIN(KG_TEST(test_full_scene_fields), KG_TEST(test_defaults), KG_TEST(test_capsule_and_segment), KG_TEST(test_error_files),
             KG_TEST(test_error_strings), KG_TEST(test_compound_body), KG_TEST(test_chains),
             KG_TEST(test_chain_points_cap), KG_TEST(test_unreadable_file), KG_TEST(test_samples_load),
             KG_TEST(test_json_generators), KG_TEST(test_large_pyramid), KG_TEST(test_many_pyramids),
             KG_TEST(test_smash), KG_TEST(test_tumbler_layout), KG_TEST(test_rain),
             KG_TEST(test_particles_and_small_generators), KG_TEST(test_generator_names), KG_TEST(test_builder),
             KG_TEST(test_instantiate_bodies), KG_TEST(test_instantiate_forces),
             KG_TEST(test_pivots_keep_walls_on_circle), KG_TEST(test_builder_chains), KG_TEST(test_builder_refuses_bad_body),
             KG_TEST(test_generated_scenes_instantiate), KG_TEST(test_limits_refuse_generators),
             KG_TEST(test_limits_count_every_body), KG_TEST(test_limits_generator_names), KG_TEST(test_limits_tiled_objects), KG_TEST(test_messages_echo_clean_names))
