/* The benchmark compares engines on the same scenes: every scene built in kgyro and in
 * each peer engine (Box2D 2.4, Chipmunk 7) must have the scene's body count, dynamic mass
 * and bounding box. A peer that is not built is reported and skipped (the sanitizer
 * build has none); tests/cases/bench.cmake links the peers in when they are. */
#include "kg_test.h"

#include "kgyro/kgyro.h"
#include "kgyro/scene.h"
#ifdef KG_HAVE_PEERS
#include "kg_peers.h"
#endif

#include <math.h>
#include <string.h>

/* Box2D rounds polygon corners (by 1 cm, see box2d_adapter.cpp), so a turned box's
 * bounding box is up to 4 mm smaller there. */
#define BOUNDS_TOLERANCE 0.005
#define MASS_RELATIVE_TOLERANCE 1e-4

static const char* const kScenes[] = {
    "large_pyramid", "many_pyramids", "smash", "tumbler", "rain_500", "particles_500", "pyramid_10", "joint_grid",
    "ragdoll_rain",
};

typedef struct scene_totals {
    int bodies;
    double dynamic_mass;
    kg_aabb bounds;
} scene_totals;

static kg_aabb empty_box(void) { return (kg_aabb){{INFINITY, INFINITY}, {-INFINITY, -INFINITY}}; }

static void include_point(kg_aabb* box, kg_vec2 p, float radius)
{
    box->lower.x = fminf(box->lower.x, p.x - radius);
    box->lower.y = fminf(box->lower.y, p.y - radius);
    box->upper.x = fmaxf(box->upper.x, p.x + radius);
    box->upper.y = fmaxf(box->upper.y, p.y + radius);
}

static int is_dynamic(kg_body_type type) { return type == KG_BODY_DYNAMIC || type == KG_BODY_PARTICLE; }

static void include_def(kg_aabb* box, const kg_body_def* def)
{
    float c = cosf(def->angle), s = sinf(def->angle);
    const kg_shape_def* shape = &def->shape;
    int count = shape->type == KG_SHAPE_POLYGON ? shape->count : 1;
    for (int i = 0; i < count; ++i) {
        kg_vec2 local = shape->type == KG_SHAPE_POLYGON  ? shape->vertices[i]
                        : shape->type == KG_SHAPE_CIRCLE ? shape->center
                                                         : (kg_vec2){0.0f, 0.0f};
        kg_vec2 p = {def->position.x + c * local.x - s * local.y, def->position.y + s * local.x + c * local.y};
        include_point(box, p, shape->type == KG_SHAPE_CIRCLE ? shape->radius : 0.0f);
    }
}

static double def_mass(const kg_body_def* def)
{
    kg_mass_data m = {0.0f, {0.0f, 0.0f}, 0.0f};
    if (def->mass > 0.0f || def->shape.type == KG_SHAPE_NONE) {
        return def->mass;
    }
    KG_CHECK_OK(kg_shape_mass(&def->shape, def->density, &m));
    return m.mass;
}

/* What the scene description itself says. */
static scene_totals described(const kg_scene* scene)
{
    scene_totals t = {kg_scene_body_count(scene), 0.0, empty_box()};
    for (int i = 0; i < t.bodies; ++i) {
        const kg_body_def* def = kg_scene_body_def(scene, i);
        t.dynamic_mass += is_dynamic(def->type) ? def_mass(def) : 0.0;
        include_def(&t.bounds, def);
    }
    return t;
}

static scene_totals built_in_kgyro(const kg_scene* scene)
{
    scene_totals t = {0, 0.0, empty_box()};
    int n = kg_scene_body_count(scene);
    kg_body* bodies = malloc((size_t)n * sizeof *bodies);
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    kg_world* world = NULL;
    KG_CHECK_OK(kg_scene_instantiate(scene, &def, &world, bodies));
    if (!world || !bodies) {
        free(bodies);
        return t;
    }
    t.bodies = kg_world_body_count(world);
    for (int i = 0; i < n; ++i) {
        kg_body_type type;
        kg_mass_data mass;
        kg_aabb box;
        KG_CHECK_OK(kg_body_get_type(world, bodies[i], &type));
        KG_CHECK_OK(kg_body_get_mass_data(world, bodies[i], &mass));
        KG_CHECK_OK(kg_body_get_aabb(world, bodies[i], &box));
        t.dynamic_mass += is_dynamic(type) ? mass.mass : 0.0;
        include_point(&t.bounds, box.lower, 0.0f);
        include_point(&t.bounds, box.upper, 0.0f);
    }
    kg_destroy_world(world);
    free(bodies);
    return t;
}

static void check_same(const char* scene, const char* engine, const scene_totals* got, const scene_totals* want)
{
    int failures = kg_test_failures;
    KG_CHECK(got->bodies == want->bodies);
    KG_CHECK_NEAR(got->dynamic_mass, want->dynamic_mass, MASS_RELATIVE_TOLERANCE * want->dynamic_mass);
    KG_CHECK_NEAR(got->bounds.lower.x, want->bounds.lower.x, BOUNDS_TOLERANCE);
    KG_CHECK_NEAR(got->bounds.lower.y, want->bounds.lower.y, BOUNDS_TOLERANCE);
    KG_CHECK_NEAR(got->bounds.upper.x, want->bounds.upper.x, BOUNDS_TOLERANCE);
    KG_CHECK_NEAR(got->bounds.upper.y, want->bounds.upper.y, BOUNDS_TOLERANCE);
    if (kg_test_failures != failures) {
        fprintf(stderr, "  (scene %s in %s)\n", scene, engine);
    }
}

static kg_scene* generate(const char* name)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_generate(name, 1, &scene));
    return scene;
}

static void test_kgyro_builds_the_described_scenes(void)
{
    for (size_t i = 0; i < sizeof kScenes / sizeof kScenes[0]; ++i) {
        kg_scene* scene = generate(kScenes[i]);
        if (!scene) {
            continue;
        }
        scene_totals want = described(scene);
        scene_totals got = built_in_kgyro(scene);
        check_same(kScenes[i], "kgyro", &got, &want);
        kg_scene_destroy(scene);
    }
}

#ifdef KG_HAVE_PEERS

static scene_totals built_in_peer(kg_peer_engine engine, const kg_scene* scene)
{
    scene_totals t = {0, 0.0, empty_box()};
    kg_peer_world* world = NULL;
    kg_result r = kg_peer_create(engine, scene, 1, &world);
    if (r != KG_OK) {
        fprintf(stderr, "%s\n", kg_peer_last_error());
    }
    KG_CHECK(r == KG_OK);
    if (world) {
        t.bodies = kg_peer_body_count(world);
        t.dynamic_mass = kg_peer_dynamic_mass(world);
        t.bounds = kg_peer_bounds(world);
        kg_peer_destroy(world);
    }
    return t;
}

static void test_peers_build_the_described_scenes(void)
{
    for (int e = 0; e < KG_PEER_ENGINE_COUNT; ++e) {
        if (!kg_peer_available((kg_peer_engine)e)) {
            printf("skip %s: %s\n", kg_peer_name((kg_peer_engine)e), kg_peer_describe((kg_peer_engine)e, 1));
            continue;
        }
        for (size_t i = 0; i < sizeof kScenes / sizeof kScenes[0]; ++i) {
            kg_scene* scene = generate(kScenes[i]);
            if (!scene) {
                continue;
            }
            scene_totals want = described(scene);
            scene_totals got = built_in_peer((kg_peer_engine)e, scene);
            check_same(kScenes[i], kg_peer_name((kg_peer_engine)e), &got, &want);
            kg_scene_destroy(scene);
        }
    }
}

/* The tumbler's walls are kinematic bodies turning about a pivot: after one second every
 * wall is still 10 m from it, turned by 25 degrees, as in kgyro. */
static void test_peers_turn_the_tumbler_walls(void)
{
    const float omega = 25.0f * 3.14159265f / 180.0f;
    kg_scene* scene = generate("tumbler");
    for (int e = 0; scene && e < KG_PEER_ENGINE_COUNT; ++e) {
        kg_peer_world* world = NULL;
        if (!kg_peer_available((kg_peer_engine)e) || kg_peer_create((kg_peer_engine)e, scene, 1, &world) != KG_OK) {
            continue;
        }
        for (int s = 0; s < 60; ++s) {
            kg_peer_step(world, 1.0f / 60.0f);
        }
        kg_body_state* states = malloc((size_t)kg_peer_body_count(world) * sizeof *states);
        kg_peer_get_states(world, states);
        for (int wall = 0; wall < 4; ++wall) {
            kg_vec2 pivot;
            KG_CHECK(kg_scene_body_pivot(scene, wall, &pivot));
            KG_CHECK_NEAR(hypotf(states[wall].position.x - pivot.x, states[wall].position.y - pivot.y), 10.0f, 0.01f);
            KG_CHECK_NEAR(states[wall].angle, omega, 1e-3f);
        }
        free(states);
        kg_peer_destroy(world);
    }
    kg_scene_destroy(scene);
}

static void test_peers_say_what_they_are(void)
{
    for (int e = 0; e < KG_PEER_ENGINE_COUNT; ++e) {
        KG_CHECK(kg_peer_find(kg_peer_name((kg_peer_engine)e)) == e);
        KG_CHECK(strlen(kg_peer_describe((kg_peer_engine)e, 1)) > 0);
    }
    KG_CHECK(kg_peer_find("havok") == -1);
}

/* A scene of compound bodies (a dumbbell, an L with a heavier foot, a crate with a sensor,
 * a static table), level, so that kgyro's bounds, those of a box around each body's
 * shapes, are exactly theirs: each peer builds every shape with kgyro's masses, and the
 * dumbbell falls onto the table as in kgyro (its height after a second within 5 cm). */
static void test_peers_build_compound_bodies(void)
{
    const char* json = "{\"bodies\": ["
                       "{\"type\": \"static\", \"position\": [0, 0], \"shapes\": ["
                       " {\"type\": \"box\", \"width\": 4, \"height\": 0.2, \"center\": [0, 1]},"
                       " {\"type\": \"box\", \"width\": 0.2, \"height\": 1, \"center\": [-1.9, 0.5]},"
                       " {\"type\": \"box\", \"width\": 0.2, \"height\": 1, \"center\": [1.9, 0.5]}]},"
                       "{\"name\": \"dumbbell\", \"position\": [0, 3], \"shapes\": ["
                       " {\"type\": \"box\", \"width\": 2, \"height\": 0.1},"
                       " {\"type\": \"circle\", \"radius\": 0.3, \"center\": [-1, 0], \"density\": 2},"
                       " {\"type\": \"circle\", \"radius\": 0.3, \"center\": [1, 0], \"density\": 2}]},"
                       "{\"position\": [6, 0.5], \"shapes\": ["
                       " {\"type\": \"box\", \"width\": 1.5, \"height\": 0.3, \"center\": [0.75, 0.15],"
                       "  \"density\": 4},"
                       " {\"type\": \"box\", \"width\": 0.3, \"height\": 2, \"center\": [0.15, 1.3]}]},"
                       "{\"position\": [-6, 0.5], \"shapes\": ["
                       " {\"type\": \"box\", \"width\": 1, \"height\": 1},"
                       " {\"type\": \"polygon\", \"vertices\": [[-0.4, 0], [0.4, 0], [0, 0.5]], \"center\": [0, 0.5],"
                       "  \"sensor\": true}]}]}";
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_parse(json, strlen(json), "compound.json", &scene));
    if (!scene) {
        return;
    }
    scene_totals want = built_in_kgyro(scene);
    for (int e = 0; e < KG_PEER_ENGINE_COUNT; ++e) {
        if (!kg_peer_available((kg_peer_engine)e)) {
            continue;
        }
        scene_totals got = built_in_peer((kg_peer_engine)e, scene);
        check_same("compound", kg_peer_name((kg_peer_engine)e), &got, &want);
        kg_peer_world* world = NULL;
        KG_CHECK_OK(kg_peer_create((kg_peer_engine)e, scene, 1, &world));
        for (int k = 0; world && k < 60; ++k) {
            kg_peer_step(world, 1.0f / 60.0f);
        }
        kg_body_state states[4];
        if (world) {
            kg_peer_get_states(world, states);
            printf("     %s: the dumbbell at %.3f m after 1 s (on the table: 1.1 + 0.3 = 1.4)\n",
                   kg_peer_name((kg_peer_engine)e), (double)states[1].position.y);
            KG_CHECK_NEAR(states[1].position.y, 1.4, 0.05);
        }
        kg_peer_destroy(world);
    }
    kg_scene_destroy(scene);
}

/* Two rods hinged to the world by an end, level at the start: a free one, and one whose
 * hinge stops it at -0.3 rad. After a second every engine has the free rod's centre 0.5 m
 * from its pivot (within 1 cm) and the limited one resting near its limit, as kgyro has
 * them: the peers got the joints, their anchors and their limits. */
static void test_peers_hinge_like_kgyro(void)
{
    const char* json = "{\"bodies\": ["
                       "{\"name\": \"free\", \"position\": [0.5, 0],"
                       " \"shape\": {\"type\": \"box\", \"width\": 1, \"height\": 0.1}},"
                       "{\"name\": \"limited\", \"position\": [0.5, 5],"
                       " \"shape\": {\"type\": \"box\", \"width\": 1, \"height\": 0.1}}],"
                       " \"joints\": ["
                       "{\"type\": \"revolute\", \"b\": \"free\", \"anchor\": [0, 0]},"
                       "{\"type\": \"revolute\", \"b\": \"limited\", \"anchor\": [0, 5], \"enable_limit\": true,"
                       " \"lower_angle\": -0.3, \"upper_angle\": 0.3}]}";
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_parse(json, strlen(json), "hinges.json", &scene));
    for (int e = -1; scene && e < KG_PEER_ENGINE_COUNT; ++e) {
        kg_body_state states[2];
        const char* name = e < 0 ? "kgyro" : kg_peer_name((kg_peer_engine)e);
        if (e < 0) {
            kg_world_def def = kg_default_world_def();
            def.backend = KG_BACKEND_CPU;
            kg_world* world = NULL;
            kg_body bodies[2];
            KG_CHECK_OK(kg_scene_instantiate(scene, &def, &world, bodies));
            for (int k = 0; world && k < 60; ++k) {
                KG_CHECK_OK(kg_world_step(world, 1.0f / 60.0f));
            }
            KG_CHECK_OK(kg_world_get_body_states(world, bodies, 2, states));
            kg_destroy_world(world);
        } else {
            kg_peer_world* world = NULL;
            if (!kg_peer_available((kg_peer_engine)e)) {
                continue;
            }
            KG_CHECK_OK(kg_peer_create((kg_peer_engine)e, scene, 1, &world));
            for (int k = 0; world && k < 60; ++k) {
                kg_peer_step(world, 1.0f / 60.0f);
            }
            if (world) {
                kg_peer_get_states(world, states);
            }
            kg_peer_destroy(world);
        }
        double arm = hypot(states[0].position.x, states[0].position.y);
        printf("     %s: free rod's centre %.4f m from its pivot (0.5), limited rod at %.3f rad (-0.3)\n", name, arm,
               (double)states[1].angle);
        KG_CHECK_NEAR(arm, 0.5, 0.01);
        KG_CHECK_NEAR(states[1].angle, -0.3, 0.03);
    }
    kg_scene_destroy(scene);
}

static void test_peers_refuse_scene_forces(void)
{
    kg_scene* scene = generate("pyramid_3");
    kg_scene_force wind = {KG_SCENE_FORCE_WIND, {1.0f, 0.0f}, 2.0f, 0.1f, 0, NULL};
    KG_CHECK_OK(kg_scene_add_force(scene, &wind));
    for (int e = 0; e < KG_PEER_ENGINE_COUNT; ++e) {
        kg_peer_world* world = NULL;
        KG_CHECK(kg_peer_create((kg_peer_engine)e, scene, 1, &world) == KG_ERROR_UNSUPPORTED);
        KG_CHECK(world == NULL);
        KG_CHECK(strlen(kg_peer_last_error()) > 0);
    }
    kg_scene_destroy(scene);
}

KG_TEST_MAIN(KG_TEST(test_kgyro_builds_the_described_scenes), KG_TEST(test_peers_build_the_described_scenes),
             KG_TEST(test_peers_turn_the_tumbler_walls), KG_TEST(test_peers_say_what_they_are),
             KG_TEST(test_peers_refuse_scene_forces), KG_TEST(test_peers_build_compound_bodies),
             KG_TEST(test_peers_hinge_like_kgyro))

#else

KG_TEST_MAIN(KG_TEST(test_kgyro_builds_the_described_scenes))

#endif
