/* The scene file's "joints" (docs/scene-format.md, "Joints"): each entry is read strictly,
 * every option by the name its C field has, its bodies by name, its anchors in world
 * coordinates; kg_scene_instantiate turns them into the kind's definition and creates it. */
#include "io/scene_joints.h"

#include "core/error.h"
#include "core/joint.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define KG_JOINT_COMMON                                                                                      \
    "type", "a", "b", "collide_connected", "constraint_hertz", "constraint_damping_ratio", "break_force", "break_torque"

static const char* const kRevoluteFields[] = {KG_JOINT_COMMON, "anchor", "reference_angle", "enable_limit",
                                              "lower_angle", "upper_angle", "enable_motor", "motor_speed",
                                              "max_motor_torque", "enable_spring", "hertz", "damping_ratio", NULL};
static const char* const kDistanceFields[] = {KG_JOINT_COMMON, "anchor_a", "anchor_b", "length", "enable_spring",
                                              "hertz", "damping_ratio", "enable_limit", "min_length", "max_length",
                                              NULL};
static const char* const kWeldFields[] = {KG_JOINT_COMMON,         "anchor",       "reference_angle",
                                          "linear_hertz",          "linear_damping_ratio", "angular_hertz",
                                          "angular_damping_ratio", NULL};
static const char* const kMouseFields[] = {KG_JOINT_COMMON, "target", "anchor", "hertz", "damping_ratio", "max_force",
                                           NULL};

static const char* const kPrismaticFields[] = {KG_JOINT_COMMON, "anchor", "axis", "reference_angle", "enable_limit",
                                               "lower_translation", "upper_translation", "enable_motor",
                                               "motor_speed", "max_motor_force", "enable_spring", "hertz",
                                               "damping_ratio", NULL};
static const char* const kWheelFields[] = {KG_JOINT_COMMON, "anchor", "axis", "enable_limit", "lower_translation",
                                           "upper_translation", "enable_motor", "motor_speed", "max_motor_torque",
                                           "enable_spring", "hertz", "damping_ratio", NULL};
static const char* const kMotorFields[] = {KG_JOINT_COMMON, "linear_offset", "angular_offset", "max_force",
                                           "max_torque", "correction_factor", NULL};

static const char* const kJointTypes[] = {"revolute", "distance", "weld", "mouse", "prismatic", "wheel", "motor", NULL};

/* The scene index of the body that object's key names: -1 when absent (the world) unless
 * required. */
static kg_result kg_read_joint_body(const kg_json_reader* reader, const kg_scene* scene, const cJSON* object,
                                    const kg_json_path* path, const char* key, int required, int* out)
{
    const char* name = NULL;
    *out = -1;
    if (required) {
        KG_TRY(kg_json_require(reader, object, path, key));
    }
    KG_TRY(kg_json_string(reader, object, path, key, &name));
    if (!name) {
        return KG_OK;
    }
    *out = kg_scene_find_body(scene, name);
    if (*out < 0) {
        kg_json_path at = kg_json_path_key(path, key);
        char clean[80];
        kg_json_clean_text(clean, sizeof clean, name);
        return kg_json_fail(reader, &at, "names no body of the scene (\"%s\")", clean);
    }
    return KG_OK;
}

/* A body's angle in the scene (0 for the world). */
static float kg_scene_angle(const kg_scene* scene, int index)
{
    return index < 0 ? 0.0f : kg_scene_body_def(scene, index)->angle;
}

static kg_vec2 kg_scene_position(const kg_scene* scene, int index)
{
    kg_vec2 zero = {0.0f, 0.0f};
    return index < 0 ? zero : kg_scene_body_def(scene, index)->position;
}

static kg_result kg_read_base(const kg_json_reader* reader, const cJSON* item, const kg_json_path* path,
                              kg_joint_base_def* base)
{
    KG_TRY(kg_json_bool(reader, item, path, "collide_connected", &base->collide_connected));
    KG_TRY(kg_json_float(reader, item, path, "constraint_hertz", KG_JSON_NON_NEGATIVE, &base->constraint_hertz));
    KG_TRY(kg_json_float(reader, item, path, "break_force", KG_JSON_NON_NEGATIVE, &base->break_force));
    KG_TRY(kg_json_float(reader, item, path, "break_torque", KG_JSON_NON_NEGATIVE, &base->break_torque));
    return kg_json_float(reader, item, path, "constraint_damping_ratio", KG_JSON_NON_NEGATIVE,
                         &base->constraint_damping_ratio);
}

static kg_result kg_read_revolute(const kg_json_reader* reader, const cJSON* item, const kg_json_path* path,
                                  const kg_scene* scene, kg_scene_joint* j)
{
    kg_revolute_joint_def* d = &j->revolute;
    KG_TRY(kg_json_check_object(reader, item, path, kRevoluteFields));
    KG_TRY(kg_read_base(reader, item, path, &d->base));
    KG_TRY(kg_json_require(reader, item, path, "anchor"));
    KG_TRY(kg_json_vec2(reader, item, path, "anchor", &j->anchor_a));
    j->anchor_b = j->anchor_a;
    d->reference_angle = kg_scene_angle(scene, j->body_b) - kg_scene_angle(scene, j->body_a);
    KG_TRY(kg_json_float(reader, item, path, "reference_angle", KG_JSON_ANY, &d->reference_angle));
    KG_TRY(kg_json_bool(reader, item, path, "enable_limit", &d->enable_limit));
    KG_TRY(kg_json_float(reader, item, path, "lower_angle", KG_JSON_ANY, &d->lower_angle));
    KG_TRY(kg_json_float(reader, item, path, "upper_angle", KG_JSON_ANY, &d->upper_angle));
    KG_TRY(kg_json_bool(reader, item, path, "enable_motor", &d->enable_motor));
    KG_TRY(kg_json_float(reader, item, path, "motor_speed", KG_JSON_ANY, &d->motor_speed));
    KG_TRY(kg_json_float(reader, item, path, "max_motor_torque", KG_JSON_NON_NEGATIVE, &d->max_motor_torque));
    KG_TRY(kg_json_bool(reader, item, path, "enable_spring", &d->enable_spring));
    KG_TRY(kg_json_float(reader, item, path, "hertz", KG_JSON_NON_NEGATIVE, &d->hertz));
    KG_TRY(kg_json_float(reader, item, path, "damping_ratio", KG_JSON_NON_NEGATIVE, &d->damping_ratio));
    if (d->lower_angle > d->upper_angle) {
        kg_json_path at = kg_json_path_key(path, "lower_angle");
        return kg_json_fail(reader, &at, "must be <= upper_angle");
    }
    return KG_OK;
}

static kg_result kg_read_distance(const kg_json_reader* reader, const cJSON* item, const kg_json_path* path,
                                  kg_scene_joint* j)
{
    kg_distance_joint_def* d = &j->distance;
    KG_TRY(kg_json_check_object(reader, item, path, kDistanceFields));
    KG_TRY(kg_read_base(reader, item, path, &d->base));
    KG_TRY(kg_json_require(reader, item, path, "anchor_a"));
    KG_TRY(kg_json_require(reader, item, path, "anchor_b"));
    KG_TRY(kg_json_vec2(reader, item, path, "anchor_a", &j->anchor_a));
    KG_TRY(kg_json_vec2(reader, item, path, "anchor_b", &j->anchor_b));
    float dx = j->anchor_b.x - j->anchor_a.x, dy = j->anchor_b.y - j->anchor_a.y;
    d->length = sqrtf(dx * dx + dy * dy); /* default: as placed */
    KG_TRY(kg_json_float(reader, item, path, "length", KG_JSON_POSITIVE, &d->length));
    if (!(d->length > 0.0f)) {
        kg_json_path at = kg_json_path_key(path, "length");
        return kg_json_fail(reader, &at, "is required when the anchors coincide (must be > 0)");
    }
    KG_TRY(kg_json_bool(reader, item, path, "enable_spring", &d->enable_spring));
    KG_TRY(kg_json_float(reader, item, path, "hertz", KG_JSON_NON_NEGATIVE, &d->hertz));
    KG_TRY(kg_json_float(reader, item, path, "damping_ratio", KG_JSON_NON_NEGATIVE, &d->damping_ratio));
    KG_TRY(kg_json_bool(reader, item, path, "enable_limit", &d->enable_limit));
    KG_TRY(kg_json_float(reader, item, path, "min_length", KG_JSON_NON_NEGATIVE, &d->min_length));
    KG_TRY(kg_json_float(reader, item, path, "max_length", KG_JSON_NON_NEGATIVE, &d->max_length));
    if (d->min_length > d->max_length) {
        kg_json_path at = kg_json_path_key(path, "min_length");
        return kg_json_fail(reader, &at, "must be <= max_length");
    }
    return KG_OK;
}

static kg_result kg_read_weld(const kg_json_reader* reader, const cJSON* item, const kg_json_path* path,
                              const kg_scene* scene, kg_scene_joint* j)
{
    kg_weld_joint_def* d = &j->weld;
    KG_TRY(kg_json_check_object(reader, item, path, kWeldFields));
    KG_TRY(kg_read_base(reader, item, path, &d->base));
    KG_TRY(kg_json_require(reader, item, path, "anchor"));
    KG_TRY(kg_json_vec2(reader, item, path, "anchor", &j->anchor_a));
    j->anchor_b = j->anchor_a;
    d->reference_angle = kg_scene_angle(scene, j->body_b) - kg_scene_angle(scene, j->body_a);
    KG_TRY(kg_json_float(reader, item, path, "reference_angle", KG_JSON_ANY, &d->reference_angle));
    KG_TRY(kg_json_float(reader, item, path, "linear_hertz", KG_JSON_NON_NEGATIVE, &d->linear_hertz));
    KG_TRY(kg_json_float(reader, item, path, "linear_damping_ratio", KG_JSON_NON_NEGATIVE, &d->linear_damping_ratio));
    KG_TRY(kg_json_float(reader, item, path, "angular_hertz", KG_JSON_NON_NEGATIVE, &d->angular_hertz));
    return kg_json_float(reader, item, path, "angular_damping_ratio", KG_JSON_NON_NEGATIVE,
                         &d->angular_damping_ratio);
}

static kg_result kg_read_mouse(const kg_json_reader* reader, const cJSON* item, const kg_json_path* path,
                               const kg_scene* scene, kg_scene_joint* j)
{
    kg_mouse_joint_def* d = &j->mouse;
    KG_TRY(kg_json_check_object(reader, item, path, kMouseFields));
    KG_TRY(kg_read_base(reader, item, path, &d->base));
    if (j->body_a >= 0) {
        kg_json_path at = kg_json_path_key(path, "a");
        return kg_json_fail(reader, &at, "a mouse joint drags \"b\" to its target: it has no \"a\"");
    }
    KG_TRY(kg_json_require(reader, item, path, "target"));
    KG_TRY(kg_json_vec2(reader, item, path, "target", &d->target));
    j->anchor_b = kg_scene_position(scene, j->body_b); /* default: the body's origin */
    KG_TRY(kg_json_vec2(reader, item, path, "anchor", &j->anchor_b));
    j->anchor_a = d->target;
    KG_TRY(kg_json_float(reader, item, path, "hertz", KG_JSON_POSITIVE, &d->hertz));
    KG_TRY(kg_json_float(reader, item, path, "damping_ratio", KG_JSON_NON_NEGATIVE, &d->damping_ratio));
    return kg_json_float(reader, item, path, "max_force", KG_JSON_NON_NEGATIVE, &d->max_force);
}

/* The axis (required, not zero) and the translation limits of a prismatic or wheel joint. */
static kg_result kg_read_axis_limits(const kg_json_reader* reader, const cJSON* item, const kg_json_path* path,
                                     kg_scene_joint* j, int* enable, float* lower, float* upper)
{
    KG_TRY(kg_json_require(reader, item, path, "anchor"));
    KG_TRY(kg_json_vec2(reader, item, path, "anchor", &j->anchor_a));
    j->anchor_b = j->anchor_a;
    KG_TRY(kg_json_require(reader, item, path, "axis"));
    KG_TRY(kg_json_vec2(reader, item, path, "axis", &j->axis));
    if (j->axis.x * j->axis.x + j->axis.y * j->axis.y < 1e-12f) {
        kg_json_path at = kg_json_path_key(path, "axis");
        return kg_json_fail(reader, &at, "must not be zero");
    }
    KG_TRY(kg_json_bool(reader, item, path, "enable_limit", enable));
    KG_TRY(kg_json_float(reader, item, path, "lower_translation", KG_JSON_ANY, lower));
    KG_TRY(kg_json_float(reader, item, path, "upper_translation", KG_JSON_ANY, upper));
    if (*lower > *upper) {
        kg_json_path at = kg_json_path_key(path, "lower_translation");
        return kg_json_fail(reader, &at, "must be <= upper_translation");
    }
    return KG_OK;
}

static kg_result kg_read_prismatic(const kg_json_reader* reader, const cJSON* item, const kg_json_path* path,
                                   const kg_scene* scene, kg_scene_joint* j)
{
    kg_prismatic_joint_def* d = &j->prismatic;
    KG_TRY(kg_json_check_object(reader, item, path, kPrismaticFields));
    KG_TRY(kg_read_base(reader, item, path, &d->base));
    KG_TRY(kg_read_axis_limits(reader, item, path, j, &d->enable_limit, &d->lower_translation,
                               &d->upper_translation));
    d->reference_angle = kg_scene_angle(scene, j->body_b) - kg_scene_angle(scene, j->body_a);
    KG_TRY(kg_json_float(reader, item, path, "reference_angle", KG_JSON_ANY, &d->reference_angle));
    KG_TRY(kg_json_bool(reader, item, path, "enable_motor", &d->enable_motor));
    KG_TRY(kg_json_float(reader, item, path, "motor_speed", KG_JSON_ANY, &d->motor_speed));
    KG_TRY(kg_json_float(reader, item, path, "max_motor_force", KG_JSON_NON_NEGATIVE, &d->max_motor_force));
    KG_TRY(kg_json_bool(reader, item, path, "enable_spring", &d->enable_spring));
    KG_TRY(kg_json_float(reader, item, path, "hertz", KG_JSON_NON_NEGATIVE, &d->hertz));
    return kg_json_float(reader, item, path, "damping_ratio", KG_JSON_NON_NEGATIVE, &d->damping_ratio);
}

static kg_result kg_read_wheel(const kg_json_reader* reader, const cJSON* item, const kg_json_path* path,
                               kg_scene_joint* j)
{
    kg_wheel_joint_def* d = &j->wheel;
    KG_TRY(kg_json_check_object(reader, item, path, kWheelFields));
    KG_TRY(kg_read_base(reader, item, path, &d->base));
    KG_TRY(kg_read_axis_limits(reader, item, path, j, &d->enable_limit, &d->lower_translation,
                               &d->upper_translation));
    KG_TRY(kg_json_bool(reader, item, path, "enable_motor", &d->enable_motor));
    KG_TRY(kg_json_float(reader, item, path, "motor_speed", KG_JSON_ANY, &d->motor_speed));
    KG_TRY(kg_json_float(reader, item, path, "max_motor_torque", KG_JSON_NON_NEGATIVE, &d->max_motor_torque));
    KG_TRY(kg_json_bool(reader, item, path, "enable_spring", &d->enable_spring));
    KG_TRY(kg_json_float(reader, item, path, "hertz", KG_JSON_NON_NEGATIVE, &d->hertz));
    return kg_json_float(reader, item, path, "damping_ratio", KG_JSON_NON_NEGATIVE, &d->damping_ratio);
}

static kg_result kg_read_motor(const kg_json_reader* reader, const cJSON* item, const kg_json_path* path,
                               const kg_scene* scene, kg_scene_joint* j)
{
    kg_motor_joint_def* d = &j->motor;
    KG_TRY(kg_json_check_object(reader, item, path, kMotorFields));
    KG_TRY(kg_read_base(reader, item, path, &d->base));
    /* default: the pose b has relative to a at the scene's start */
    float angle_a = kg_scene_angle(scene, j->body_a);
    kg_vec2 pa = kg_scene_position(scene, j->body_a), pb = kg_scene_position(scene, j->body_b);
    float c = cosf(angle_a), s = sinf(angle_a), dx = pb.x - pa.x, dy = pb.y - pa.y;
    d->linear_offset.x = c * dx + s * dy;
    d->linear_offset.y = -s * dx + c * dy;
    d->angular_offset = kg_scene_angle(scene, j->body_b) - angle_a;
    KG_TRY(kg_json_vec2(reader, item, path, "linear_offset", &d->linear_offset));
    KG_TRY(kg_json_float(reader, item, path, "angular_offset", KG_JSON_ANY, &d->angular_offset));
    KG_TRY(kg_json_float(reader, item, path, "max_force", KG_JSON_NON_NEGATIVE, &d->max_force));
    KG_TRY(kg_json_float(reader, item, path, "max_torque", KG_JSON_NON_NEGATIVE, &d->max_torque));
    return kg_json_float(reader, item, path, "correction_factor", KG_JSON_UNIT, &d->correction_factor);
}

/* Whether world point p stays a finite float in body index's frame at the scene's start
 * (the world's: itself): anchors far out of float range of their body are refused here,
 * so that an accepted scene instantiates. */
static int kg_local_fits(const kg_scene* scene, int index, kg_vec2 p)
{
    double x = p.x, y = p.y;
    if (index >= 0) {
        const kg_body_def* d = kg_scene_body_def(scene, index);
        x -= d->position.x;
        y -= d->position.y;
    }
    return fabs(x) < 1e37 && fabs(y) < 1e37;
}

/* The engine's own checks of the joint's values (core/joint.h), and the loader's of what
 * instantiating makes of its anchors and axis: a scene accepted here instantiates. */
static kg_result kg_check_scene_joint(const kg_json_reader* reader, const kg_json_path* path, const kg_scene* scene,
                                      const kg_scene_joint* j)
{
    if (!kg_local_fits(scene, j->body_a, j->anchor_a) || !kg_local_fits(scene, j->body_b, j->anchor_b)) {
        return kg_json_fail(reader, path, "an anchor is too far from its body (over 1e37 m)");
    }
    if (j->type == KG_JOINT_PRISMATIC || j->type == KG_JOINT_WHEEL) {
        double ax = j->axis.x, ay = j->axis.y;
        if (!(fabs(ax) < 1e18 && fabs(ay) < 1e18) || !(sqrt(ax * ax + ay * ay) > 1e-3)) {
            kg_json_path at = kg_json_path_key(path, "axis");
            return kg_json_fail(reader, &at, "must be longer than 0.001 and shorter than 1e18");
        }
    }
    const char* call = "joint";
    kg_result r = KG_OK;
    switch (j->type) {
    case KG_JOINT_REVOLUTE:
        r = kg_check_base_values(&j->revolute.base, call);
        r = r == KG_OK ? kg_check_revolute_values(&j->revolute, call) : r;
        break;
    case KG_JOINT_DISTANCE:
        r = kg_check_base_values(&j->distance.base, call);
        r = r == KG_OK ? kg_check_distance_values(&j->distance, call) : r;
        break;
    case KG_JOINT_WELD:
        r = kg_check_base_values(&j->weld.base, call);
        r = r == KG_OK ? kg_check_weld_values(&j->weld, call) : r;
        break;
    case KG_JOINT_MOUSE:
        r = kg_check_base_values(&j->mouse.base, call);
        r = r == KG_OK ? kg_check_mouse_values(&j->mouse, call) : r;
        break;
    case KG_JOINT_PRISMATIC: {
        kg_prismatic_joint_def d = j->prismatic;
        d.local_axis_a = j->axis;
        r = kg_check_base_values(&d.base, call);
        r = r == KG_OK ? kg_check_prismatic_values(&d, call) : r;
        break;
    }
    case KG_JOINT_WHEEL: {
        kg_wheel_joint_def d = j->wheel;
        d.local_axis_a = j->axis;
        r = kg_check_base_values(&d.base, call);
        r = r == KG_OK ? kg_check_wheel_values(&d, call) : r;
        break;
    }
    default:
        r = kg_check_base_values(&j->motor.base, call);
        r = r == KG_OK ? kg_check_motor_values(&j->motor, call) : r;
        break;
    }
    if (r != KG_OK) {
        char why[256];
        const char* message = kg_last_error();
        size_t skip = strncmp(message, "joint: ", 7) == 0 ? 7 : 0;
        snprintf(why, sizeof why, "%s", message + skip);
        return kg_json_fail(reader, path, "%s", why);
    }
    return KG_OK;
}

kg_result kg_read_scene_joint(const kg_json_reader* reader, kg_scene* scene, const cJSON* item,
                              const kg_json_path* path)
{
    if (!cJSON_IsObject(item)) {
        return kg_json_fail(reader, path, "must be an object");
    }
    KG_TRY(kg_json_require(reader, item, path, "type"));
    const char* type = NULL;
    KG_TRY(kg_json_string(reader, item, path, "type", &type));
    int kind = -1;
    for (int i = 0; kJointTypes[i]; ++i) {
        kind = strcmp(type, kJointTypes[i]) == 0 ? i : kind;
    }
    kg_json_path type_path = kg_json_path_key(path, "type");
    if (kind < 0) {
        return kg_json_fail(reader, &type_path,
                            "must be one of revolute, distance, weld, mouse, prismatic, wheel, motor");
    }
    kg_scene_joint j;
    memset(&j, 0, sizeof j);
    j.type = (kg_joint_type)kind;
    j.revolute = kg_default_revolute_joint_def();
    j.distance = kg_default_distance_joint_def();
    j.weld = kg_default_weld_joint_def();
    j.mouse = kg_default_mouse_joint_def();
    j.prismatic = kg_default_prismatic_joint_def();
    j.wheel = kg_default_wheel_joint_def();
    j.motor = kg_default_motor_joint_def();
    KG_TRY(kg_read_joint_body(reader, scene, item, path, "a", 0, &j.body_a));
    KG_TRY(kg_read_joint_body(reader, scene, item, path, "b", 1, &j.body_b));
    if (j.body_a == j.body_b) {
        kg_json_path at = kg_json_path_key(path, "b");
        return kg_json_fail(reader, &at, "names the same body as \"a\": a joint needs two bodies");
    }
    switch (j.type) {
    case KG_JOINT_REVOLUTE: KG_TRY(kg_read_revolute(reader, item, path, scene, &j)); break;
    case KG_JOINT_DISTANCE: KG_TRY(kg_read_distance(reader, item, path, &j)); break;
    case KG_JOINT_WELD: KG_TRY(kg_read_weld(reader, item, path, scene, &j)); break;
    case KG_JOINT_MOUSE: KG_TRY(kg_read_mouse(reader, item, path, scene, &j)); break;
    case KG_JOINT_PRISMATIC: KG_TRY(kg_read_prismatic(reader, item, path, scene, &j)); break;
    case KG_JOINT_WHEEL: KG_TRY(kg_read_wheel(reader, item, path, &j)); break;
    default: KG_TRY(kg_read_motor(reader, item, path, scene, &j)); break;
    }
    KG_TRY(kg_check_scene_joint(reader, path, scene, &j));
    if (kg_scene_add_joint(scene, &j) != KG_OK) {
        return kg_json_fail(reader, path, "%s", kg_last_error());
    }
    return KG_OK;
}

kg_result kg_read_scene_joints(const kg_json_reader* reader, kg_scene* scene, const cJSON* root)
{
    const cJSON* list = cJSON_GetObjectItemCaseSensitive(root, "joints");
    if (!list) {
        return KG_OK;
    }
    kg_json_path root_path = {""};
    kg_json_path list_path = kg_json_path_key(&root_path, "joints");
    KG_TRY(kg_json_check_array(reader, list, &list_path));
    int i = 0;
    for (const cJSON* item = list->child; item; item = item->next, ++i) {
        kg_json_path item_path = kg_json_path_index(&list_path, i);
        KG_TRY(kg_read_scene_joint(reader, scene, item, &item_path));
    }
    return KG_OK;
}

static kg_body kg_handle_or_world(const kg_body* handles, int index)
{
    kg_body none = KG_NULL_BODY_INIT;
    return index < 0 ? none : handles[index];
}

/* A world direction in body's frame (the world's for KG_NULL_BODY). */
static kg_vec2 kg_local_axis(const kg_world* world, kg_body body, kg_vec2 axis)
{
    kg_vec2 origin = {0.0f, 0.0f}, o, p;
    if (kg_joint_local_point(world, body, origin, &o) != KG_OK ||
        kg_joint_local_point(world, body, axis, &p) != KG_OK) {
        return axis;
    }
    kg_vec2 d = {p.x - o.x, p.y - o.y};
    return d;
}

kg_result kg_create_scene_joints(const kg_scene* scene, kg_world* world, const kg_body* handles)
{
    for (int i = 0; i < kg_scene_joint_count(scene); ++i) {
        const kg_scene_joint* j = kg_scene_get_joint(scene, i);
        kg_body a = kg_handle_or_world(handles, j->body_a), b = handles[j->body_b];
        kg_vec2 la, lb;
        KG_TRY(kg_joint_local_point(world, a, j->anchor_a, &la));
        KG_TRY(kg_joint_local_point(world, b, j->anchor_b, &lb));
        kg_result r;
        switch (j->type) {
        case KG_JOINT_REVOLUTE: {
            kg_revolute_joint_def d = j->revolute;
            d.base.body_a = a;
            d.base.body_b = b;
            d.local_anchor_a = la;
            d.local_anchor_b = lb;
            r = kg_create_revolute_joint(world, &d, NULL);
            break;
        }
        case KG_JOINT_DISTANCE: {
            kg_distance_joint_def d = j->distance;
            d.base.body_a = a;
            d.base.body_b = b;
            d.local_anchor_a = la;
            d.local_anchor_b = lb;
            r = kg_create_distance_joint(world, &d, NULL);
            break;
        }
        case KG_JOINT_WELD: {
            kg_weld_joint_def d = j->weld;
            d.base.body_a = a;
            d.base.body_b = b;
            d.local_anchor_a = la;
            d.local_anchor_b = lb;
            r = kg_create_weld_joint(world, &d, NULL);
            break;
        }
        case KG_JOINT_MOUSE: {
            kg_mouse_joint_def d = j->mouse;
            d.base.body_b = b;
            d.local_anchor_b = lb;
            r = kg_create_mouse_joint(world, &d, NULL);
            break;
        }
        case KG_JOINT_PRISMATIC: {
            kg_prismatic_joint_def d = j->prismatic;
            d.base.body_a = a;
            d.base.body_b = b;
            d.local_anchor_a = la;
            d.local_anchor_b = lb;
            d.local_axis_a = kg_local_axis(world, a, j->axis);
            r = kg_create_prismatic_joint(world, &d, NULL);
            break;
        }
        case KG_JOINT_WHEEL: {
            kg_wheel_joint_def d = j->wheel;
            d.base.body_a = a;
            d.base.body_b = b;
            d.local_anchor_a = la;
            d.local_anchor_b = lb;
            d.local_axis_a = kg_local_axis(world, a, j->axis);
            r = kg_create_wheel_joint(world, &d, NULL);
            break;
        }
        case KG_JOINT_MOTOR: {
            kg_motor_joint_def d = j->motor;
            d.base.body_a = a;
            d.base.body_b = b;
            r = kg_create_motor_joint(world, &d, NULL);
            break;
        }
        default: r = kg_fail(KG_ERROR_UNSUPPORTED, "joint %d: unknown type", i); break;
        }
        if (r != KG_OK) {
            char why[256];
            snprintf(why, sizeof why, "%s", kg_last_error());
            return kg_fail(r, "scene joint %d: %s", i, why);
        }
    }
    return KG_OK;
}
