/* Joints drawn in Tiled (issue 17; docs/tilemaps.md, "Joints"): objects of class "joint"
 * become the scene's joints, naming their bodies by object or by name, anchored where they
 * are drawn; wrong ones are refused with their path. */
#include "kg_test.h"
#include "kgyro/kgyro.h"
#include "kgyro/scene.h"

#include <math.h>
#include <string.h>

#define DATA KG_SOURCE_DIR "/tests/data/tiled/"

/* joints.tmj (16 px a metre, 12 m high): a static post at (10, 10.5) with bob1 hinged to
 * it at (11, 10.5) and bob2 hinged to bob1 at (13, 10.5) within +-0.5 rad; a weight at
 * (18, 6.5) on a 3 m rod (a polyline) from the world point (18, 9.5); a slider at (4, 4.5)
 * on a horizontal rail of +-1 m (a prismatic joint to the world, its body named by name).
 * The joints come before the bodies they name in the file. */
static void test_joint_objects_become_joints(void)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_load_file(DATA "joints.tmj", &scene));
    if (!scene) {
        return;
    }
    KG_CHECK(kg_scene_joint_count(scene) == 4);
    KG_CHECK(kg_scene_marker_count(scene) == 1); /* the spawn point; joint objects are not markers */
    const kg_joint_type kinds[4] = {KG_JOINT_REVOLUTE, KG_JOINT_REVOLUTE, KG_JOINT_DISTANCE, KG_JOINT_PRISMATIC};
    const char* const a[4] = {"post#2", "bob1#3", NULL, NULL};
    const char* const b[4] = {"bob1#3", "bob2#4", "weight#9", "slider#8"};
    for (int i = 0; i < 4 && i < kg_scene_joint_count(scene); ++i) {
        const kg_scene_joint* j = kg_scene_get_joint(scene, i);
        KG_CHECK(j->type == kinds[i]);
        KG_CHECK(a[i] ? strcmp(kg_scene_body_name(scene, j->body_a), a[i]) == 0 : j->body_a == -1);
        KG_CHECK(strcmp(kg_scene_body_name(scene, j->body_b), b[i]) == 0);
    }
    const kg_scene_joint* elbow = kg_scene_get_joint(scene, 1);
    KG_CHECK(elbow && elbow->revolute.enable_limit && elbow->revolute.lower_angle == -0.5f);
    KG_CHECK(elbow && elbow->anchor_a.x == 13.0f && elbow->anchor_a.y == 10.5f);
    const kg_scene_joint* rod = kg_scene_get_joint(scene, 2);
    KG_CHECK(rod && rod->anchor_a.x == 18.0f && rod->anchor_a.y == 9.5f && rod->anchor_b.y == 6.5f);

    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    kg_world* world = NULL;
    kg_body bodies[7];
    KG_CHECK_OK(kg_scene_instantiate(scene, &def, &world, bodies));
    KG_CHECK(kg_world_joint_count(world) == 4);
    for (int k = 0; world && k < 120; ++k) {
        KG_CHECK_OK(kg_world_step(world, 1.0f / 60.0f));
    }
    kg_body_state bob1, weight, slider;
    KG_CHECK_OK(kg_body_get_state(world, bodies[kg_scene_find_body(scene, "bob1#3")], &bob1));
    KG_CHECK_OK(kg_body_get_state(world, bodies[kg_scene_find_body(scene, "weight#9")], &weight));
    KG_CHECK_OK(kg_body_get_state(world, bodies[kg_scene_find_body(scene, "slider#8")], &slider));
    double arm = hypot(bob1.position.x - 11.0, bob1.position.y - 10.5);
    printf("     after 2 s: bob1 %.4f m from its hinge (1), weight at y %.4f (6.5), slider at y %.4f (4.5)\n", arm,
           (double)weight.position.y, (double)slider.position.y);
    KG_CHECK_NEAR(arm, 1.0, 0.001);
    KG_CHECK(bob1.position.y < 10.4f); /* it swung down */
    KG_CHECK_NEAR(weight.position.y, 6.5, 0.003);
    KG_CHECK_NEAR(slider.position.y, 4.5, 0.003);
    kg_destroy_world(world);
    kg_scene_destroy(scene);
}

static void test_bad_joint_objects(void)
{
    static const struct {
        const char* file;
        const char* message;
    } kCases[] = {
        {"bad_joint_kind.tmj", "layers[1].objects[0]: a joint object needs the string property \"joint\" (its kind)"},
        {"bad_joint_body.tmj", "layers[1].objects[0].properties[2].value: object 11 is not a body of this map"},
        {"bad_joint_shape.tmj", "layers[1].objects[0]: a joint object must be a point or a polyline of two points"},
        {"bad_joint_limits.tmj", "layers[1].objects[1].lower_angle: must be <= upper_angle"},
    };
    for (size_t i = 0; i < sizeof kCases / sizeof kCases[0]; ++i) {
        char path[512], expected[640];
        snprintf(path, sizeof path, DATA "%s", kCases[i].file);
        snprintf(expected, sizeof expected, "%s: %s", path, kCases[i].message);
        kg_scene* scene = NULL;
        KG_CHECK(kg_scene_load_file(path, &scene) == KG_ERROR_PARSE && scene == NULL);
        if (strcmp(kg_last_error(), expected) != 0) {
            fprintf(stderr, "  got      '%s'\n  expected '%s'\n", kg_last_error(), expected);
            kg_test_failures++;
        }
    }
}

KG_TEST_MAIN(KG_TEST(test_joint_objects_become_joints), KG_TEST(test_bad_joint_objects))
