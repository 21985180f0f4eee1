/* The benchmark scenes with joints (issue 17): joint_grid, a net of bodies joined by
 * hinges, as Box2D v3's benchmark of that name, and ragdoll_rain, ragdolls of 11 bodies
 * falling in a heap. Built from scene joints, so the peer engines get the same ones. */
#include "io/scene_generate.h"
#include "core/error.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A hinge between scene bodies a and b (a -1: the world) at a world point, with angle
 * limits when lower < upper. */
static kg_result kg_gen_hinge(kg_scene* scene, int a, int b, kg_vec2 anchor, float lower, float upper)
{
    kg_scene_joint joint;
    memset(&joint, 0, sizeof joint);
    joint.type = KG_JOINT_REVOLUTE;
    joint.body_a = a;
    joint.body_b = b;
    joint.anchor_a = anchor;
    joint.anchor_b = anchor;
    joint.revolute = kg_default_revolute_joint_def();
    joint.revolute.enable_limit = lower < upper;
    joint.revolute.lower_angle = lower;
    joint.revolute.upper_angle = upper;
    return kg_scene_add_joint(scene, &joint);
}

/* Box2D v3's joint_grid: a 100 x 100 grid of 0.4 m discs 1 m apart, each hinged to its
 * neighbours to the left and above at the midpoint between them, held by the seven middle
 * discs of the top row (static), so that the rest drapes down and swings. Joined bodies
 * do not collide (the default), and others start 1.4 m apart. */
kg_result kg_gen_joint_grid(kg_scene* scene, const char* prefix)
{
    const int n = 100;
    const float spacing = 1.0f;
    kg_gen_material material = kg_gen_default_material();
    int first = kg_scene_body_count(scene);
    for (int column = 0; column < n; ++column) {
        for (int row = 0; row < n; ++row) {
            kg_vec2 position = {(float)column * spacing, -(float)row * spacing};
            kg_body_def def =
                kg_gen_def(row == 0 && abs(column - n / 2) <= 3 ? KG_BODY_STATIC : KG_BODY_DYNAMIC,
                           kg_circle_shape(0.4f), position, &material);
            KG_TRY(kg_gen_add(scene, prefix, "disc", column * n + row, &def));
            int body = first + column * n + row;
            if (row == 0 && column > 0 && def.type == KG_BODY_STATIC &&
                kg_scene_body_def(scene, body - n)->type == KG_BODY_STATIC) {
                continue; /* no hinge between two static discs: it would hold nothing */
            }
            if (row > 0) {
                KG_TRY(kg_gen_hinge(scene, body - 1, body, (kg_vec2){position.x, position.y + 0.5f * spacing}, 0.0f,
                                    0.0f));
            }
            if (column > 0) {
                KG_TRY(kg_gen_hinge(scene, body - n, body, (kg_vec2){position.x - 0.5f * spacing, position.y}, 0.0f,
                                    0.0f));
            }
        }
    }
    return KG_OK;
}

/* One part of a ragdoll standing upright with its feet at the origin. */
typedef struct kg_ragdoll_part {
    const char* role;
    kg_vec2 center;
    kg_vec2 size; /* a box; x = 0: a disc of radius size.y */
} kg_ragdoll_part;

/* A hinge of the ragdoll between parts a and b, at a point in the same frame. */
typedef struct kg_ragdoll_hinge {
    int a, b;
    kg_vec2 anchor;
    float lower, upper;
} kg_ragdoll_hinge;

/* 1.8 m tall: a head, two torso parts, upper and lower arms and legs. */
static const kg_ragdoll_part kRagdollParts[11] = {
    {"head", {0.0f, 1.67f}, {0.0f, 0.12f}},          {"chest", {0.0f, 1.36f}, {0.36f, 0.36f}},
    {"hips", {0.0f, 1.03f}, {0.32f, 0.30f}},         {"upper_arm_l", {-0.23f, 1.37f}, {0.10f, 0.30f}},
    {"lower_arm_l", {-0.23f, 1.07f}, {0.09f, 0.30f}}, {"upper_arm_r", {0.23f, 1.37f}, {0.10f, 0.30f}},
    {"lower_arm_r", {0.23f, 1.07f}, {0.09f, 0.30f}},  {"upper_leg_l", {-0.09f, 0.70f}, {0.14f, 0.40f}},
    {"lower_leg_l", {-0.09f, 0.27f}, {0.12f, 0.46f}}, {"upper_leg_r", {0.09f, 0.70f}, {0.14f, 0.40f}},
    {"lower_leg_r", {0.09f, 0.27f}, {0.12f, 0.46f}},
};

/* Angle limits in radians, the right side mirroring the left. */
static const kg_ragdoll_hinge kRagdollHinges[10] = {
    {1, 0, {0.0f, 1.55f}, -0.5f, 0.5f},     {1, 2, {0.0f, 1.18f}, -0.4f, 0.4f},
    {1, 3, {-0.23f, 1.52f}, -2.5f, 0.5f},   {3, 4, {-0.23f, 1.22f}, 0.0f, 2.4f},
    {1, 5, {0.23f, 1.52f}, -0.5f, 2.5f},    {5, 6, {0.23f, 1.22f}, -2.4f, 0.0f},
    {2, 7, {-0.09f, 0.90f}, -1.6f, 0.5f},   {7, 8, {-0.09f, 0.50f}, -0.1f, 2.2f},
    {2, 9, {0.09f, 0.90f}, -0.5f, 1.6f},    {9, 10, {0.09f, 0.50f}, -2.2f, 0.1f},
};

/* A ragdoll of prefix + "partK", its feet's middle at origin, turned by angle. */
static kg_result kg_gen_ragdoll(kg_scene* scene, const char* prefix, int k, kg_vec2 origin, float angle)
{
    kg_gen_material material = kg_gen_default_material();
    material.friction = 0.6f;
    float c = cosf(angle), s = sinf(angle);
    int first = kg_scene_body_count(scene);
    for (int i = 0; i < 11; ++i) {
        const kg_ragdoll_part* part = &kRagdollParts[i];
        kg_vec2 p = {origin.x + c * part->center.x - s * part->center.y,
                     origin.y + s * part->center.x + c * part->center.y};
        kg_shape_def shape = part->size.x > 0.0f ? kg_box_shape(part->size.x, part->size.y) : kg_circle_shape(part->size.y);
        kg_body_def def = kg_gen_def(KG_BODY_DYNAMIC, shape, p, &material);
        def.angle = angle;
        char role[48];
        snprintf(role, sizeof role, "%s_", part->role);
        KG_TRY(kg_gen_add(scene, prefix, role, k, &def));
    }
    for (int j = 0; j < 10; ++j) {
        const kg_ragdoll_hinge* h = &kRagdollHinges[j];
        kg_vec2 anchor = {origin.x + c * h->anchor.x - s * h->anchor.y, origin.y + s * h->anchor.x + c * h->anchor.y};
        KG_TRY(kg_gen_hinge(scene, first + h->a, first + h->b, anchor, h->lower, h->upper));
    }
    return KG_OK;
}

/* 50 ragdolls in 5 rows of 10, 4 m by 3 m apart, each turned differently (a 1.8 m
 * ragdoll turned by up to 1.4 rad fits its cell), above a ground box 46 m wide between two
 * walls: they fall, tumble and pile up. */
kg_result kg_gen_ragdoll_rain(kg_scene* scene, const char* prefix)
{
    kg_gen_material material = kg_gen_default_material();
    const kg_vec2 sizes[3] = {{46.0f, 1.0f}, {1.0f, 20.0f}, {1.0f, 20.0f}};
    const kg_vec2 centers[3] = {{0.0f, -0.5f}, {-23.5f, 10.0f}, {23.5f, 10.0f}};
    for (int w = 0; w < 3; ++w) {
        kg_body_def def = kg_gen_def(KG_BODY_STATIC, kg_box_shape(sizes[w].x, sizes[w].y), centers[w], &material);
        KG_TRY(kg_gen_add(scene, prefix, "ground", w, &def));
    }
    for (int k = 0; k < 50; ++k) {
        int column = k % 10, row = k / 10;
        kg_vec2 origin = {-18.0f + 4.0f * (float)column, 2.0f + 3.0f * (float)row};
        float angle = 0.35f * (float)((k * 7) % 9 - 4); /* -1.4 to 1.4 rad */
        KG_TRY(kg_gen_ragdoll(scene, prefix, k, origin, angle));
    }
    return KG_OK;
}
