/* The scene file's "joints" (docs/scene-format.md, "Joints"): each entry is read strictly,
 * every option by the name its C field has, its bodies by name, its anchors in world
 * coordinates; kg_scene_instantiate turns them into the kind's definition and creates it. */
#include "io/scene_joints.h"

#include "core/error.h"
#include "core/joint.h"

#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

/* ---- the fields of an entry: one table a kind, read here and written by
 * kg_scene_joint_json (the file's keys are the C fields' names) ---- */

typedef enum kg_joint_field_kind { KG_FIELD_FLOAT, KG_FIELD_BOOL, KG_FIELD_VEC2 } kg_joint_field_kind;

/* An option: its key, what it holds (a float's rule) and where it lives in kg_scene_joint. */
typedef struct kg_joint_field {
    const char* key;
    kg_joint_field_kind kind;
    kg_json_rule rule;
    size_t offset;
} kg_joint_field;

/* How an anchor key is given. */
typedef enum kg_anchor_presence {
    KG_ANCHOR_REQUIRED,
    KG_ANCHOR_OPTIONAL, /* its default set before it is read */
    KG_ANCHOR_SECOND    /* anchor_b where it may differ from "anchor": anchor_a's unless given,
                         * written only where it differs (a solver's drift, a slider moved) */
} kg_anchor_presence;

/* An anchor (a world point or direction at the scene's start). */
typedef struct kg_joint_anchor {
    const char* key;
    kg_anchor_presence presence;
    size_t offset; /* of a kg_vec2 in kg_scene_joint */
} kg_joint_anchor;

typedef struct kg_joint_kind {
    const char* name;
    const kg_joint_anchor* anchors; /* key NULL ends them */
    const kg_joint_field* options;  /* key NULL ends them */
} kg_joint_kind;

#define KG_AT(member) offsetof(kg_scene_joint, member)
#define KG_F(def, field, rule) {#field, KG_FIELD_FLOAT, rule, KG_AT(def.field)}
#define KG_B(def, field) {#field, KG_FIELD_BOOL, KG_JSON_ANY, KG_AT(def.field)}
#define KG_V(def, field) {#field, KG_FIELD_VEC2, KG_JSON_ANY, KG_AT(def.field)}
/* kg_joint_base_def's options, first in every kind. */
#define KG_BASE(def)                                                                                        \
    KG_B(def, base.collide_connected), {"constraint_hertz", KG_FIELD_FLOAT, KG_JSON_NON_NEGATIVE,            \
                                        KG_AT(def.base.constraint_hertz)},                                  \
        {"constraint_damping_ratio", KG_FIELD_FLOAT, KG_JSON_NON_NEGATIVE,                                  \
         KG_AT(def.base.constraint_damping_ratio)},                                                         \
        {"break_force", KG_FIELD_FLOAT, KG_JSON_NON_NEGATIVE, KG_AT(def.base.break_force)},                 \
        {"break_torque", KG_FIELD_FLOAT, KG_JSON_NON_NEGATIVE, KG_AT(def.base.break_torque)}
#define KG_END {NULL, KG_FIELD_FLOAT, KG_JSON_ANY, 0}

static const kg_joint_field kRevoluteOptions[] = {
    KG_BASE(revolute), KG_F(revolute, reference_angle, KG_JSON_ANY), KG_B(revolute, enable_limit),
    KG_F(revolute, lower_angle, KG_JSON_ANY), KG_F(revolute, upper_angle, KG_JSON_ANY), KG_B(revolute, enable_motor),
    KG_F(revolute, motor_speed, KG_JSON_ANY), KG_F(revolute, max_motor_torque, KG_JSON_NON_NEGATIVE),
    KG_B(revolute, enable_spring), KG_F(revolute, hertz, KG_JSON_NON_NEGATIVE),
    KG_F(revolute, damping_ratio, KG_JSON_NON_NEGATIVE), KG_END};
static const kg_joint_field kDistanceOptions[] = {
    KG_BASE(distance), KG_F(distance, length, KG_JSON_POSITIVE), KG_B(distance, enable_spring),
    KG_F(distance, hertz, KG_JSON_NON_NEGATIVE), KG_F(distance, damping_ratio, KG_JSON_NON_NEGATIVE),
    KG_B(distance, enable_limit), KG_F(distance, min_length, KG_JSON_NON_NEGATIVE),
    KG_F(distance, max_length, KG_JSON_NON_NEGATIVE), KG_END};
static const kg_joint_field kWeldOptions[] = {
    KG_BASE(weld), KG_F(weld, reference_angle, KG_JSON_ANY), KG_F(weld, linear_hertz, KG_JSON_NON_NEGATIVE),
    KG_F(weld, linear_damping_ratio, KG_JSON_NON_NEGATIVE), KG_F(weld, angular_hertz, KG_JSON_NON_NEGATIVE),
    KG_F(weld, angular_damping_ratio, KG_JSON_NON_NEGATIVE), KG_END};
static const kg_joint_field kMouseOptions[] = {KG_BASE(mouse), KG_F(mouse, hertz, KG_JSON_POSITIVE),
                                               KG_F(mouse, damping_ratio, KG_JSON_NON_NEGATIVE),
                                               KG_F(mouse, max_force, KG_JSON_NON_NEGATIVE), KG_END};
static const kg_joint_field kPrismaticOptions[] = {
    KG_BASE(prismatic), KG_F(prismatic, reference_angle, KG_JSON_ANY), KG_B(prismatic, enable_limit),
    KG_F(prismatic, lower_translation, KG_JSON_ANY), KG_F(prismatic, upper_translation, KG_JSON_ANY),
    KG_B(prismatic, enable_motor), KG_F(prismatic, motor_speed, KG_JSON_ANY),
    KG_F(prismatic, max_motor_force, KG_JSON_NON_NEGATIVE), KG_B(prismatic, enable_spring),
    KG_F(prismatic, hertz, KG_JSON_NON_NEGATIVE), KG_F(prismatic, damping_ratio, KG_JSON_NON_NEGATIVE), KG_END};
static const kg_joint_field kWheelOptions[] = {
    KG_BASE(wheel), KG_B(wheel, enable_limit), KG_F(wheel, lower_translation, KG_JSON_ANY),
    KG_F(wheel, upper_translation, KG_JSON_ANY), KG_B(wheel, enable_motor), KG_F(wheel, motor_speed, KG_JSON_ANY),
    KG_F(wheel, max_motor_torque, KG_JSON_NON_NEGATIVE), KG_B(wheel, enable_spring),
    KG_F(wheel, hertz, KG_JSON_NON_NEGATIVE), KG_F(wheel, damping_ratio, KG_JSON_NON_NEGATIVE), KG_END};
static const kg_joint_field kMotorOptions[] = {
    KG_BASE(motor), KG_V(motor, linear_offset), KG_F(motor, angular_offset, KG_JSON_ANY),
    KG_F(motor, max_force, KG_JSON_NON_NEGATIVE), KG_F(motor, max_torque, KG_JSON_NON_NEGATIVE),
    KG_F(motor, correction_factor, KG_JSON_UNIT), KG_END};

#define KG_ANCHOR_END {NULL, KG_ANCHOR_OPTIONAL, 0}
static const kg_joint_anchor kPointAnchors[] = {{"anchor", KG_ANCHOR_REQUIRED, KG_AT(anchor_a)},
                                                {"anchor_b", KG_ANCHOR_SECOND, KG_AT(anchor_b)}, KG_ANCHOR_END};
static const kg_joint_anchor kDistanceAnchors[] = {{"anchor_a", KG_ANCHOR_REQUIRED, KG_AT(anchor_a)},
                                                   {"anchor_b", KG_ANCHOR_REQUIRED, KG_AT(anchor_b)}, KG_ANCHOR_END};
static const kg_joint_anchor kMouseAnchors[] = {{"target", KG_ANCHOR_REQUIRED, KG_AT(mouse.target)},
                                                {"anchor", KG_ANCHOR_OPTIONAL, KG_AT(anchor_b)}, KG_ANCHOR_END};
static const kg_joint_anchor kAxisAnchors[] = {{"anchor", KG_ANCHOR_REQUIRED, KG_AT(anchor_a)},
                                               {"anchor_b", KG_ANCHOR_SECOND, KG_AT(anchor_b)},
                                               {"axis", KG_ANCHOR_REQUIRED, KG_AT(axis)}, KG_ANCHOR_END};
static const kg_joint_anchor kNoAnchors[] = {KG_ANCHOR_END};

/* By kg_joint_type. */
static const kg_joint_kind kJointKinds[] = {
    {"revolute", kPointAnchors, kRevoluteOptions},   {"distance", kDistanceAnchors, kDistanceOptions},
    {"weld", kPointAnchors, kWeldOptions},           {"mouse", kMouseAnchors, kMouseOptions},
    {"prismatic", kAxisAnchors, kPrismaticOptions}, {"wheel", kAxisAnchors, kWheelOptions},
    {"motor", kNoAnchors, kMotorOptions}};
#define KG_JOINT_KIND_COUNT ((int)(sizeof kJointKinds / sizeof kJointKinds[0]))

/* The most keys an entry may have, its NULL after them included; the largest kind
 * (prismatic: type, a, b, 3 anchors, 15 options) has 21, which the compiler checks below. */
#define KG_JOINT_MAX_KEYS 32
#define KG_ITEMS(table) (sizeof table / sizeof table[0] - 1) /* but its end */
#define KG_KEYS_FIT(anchors, options) (3 + KG_ITEMS(anchors) + KG_ITEMS(options) < KG_JOINT_MAX_KEYS)
typedef char kg_joint_keys_fit[KG_KEYS_FIT(kPointAnchors, kRevoluteOptions) &&
                                       KG_KEYS_FIT(kDistanceAnchors, kDistanceOptions) &&
                                       KG_KEYS_FIT(kPointAnchors, kWeldOptions) &&
                                       KG_KEYS_FIT(kMouseAnchors, kMouseOptions) &&
                                       KG_KEYS_FIT(kAxisAnchors, kPrismaticOptions) &&
                                       KG_KEYS_FIT(kAxisAnchors, kWheelOptions) &&
                                       KG_KEYS_FIT(kNoAnchors, kMotorOptions)
                                   ? 1
                                   : -1];

/* The keys an entry of kind may have, into keys (NULL-terminated; room for
 * KG_JOINT_MAX_KEYS). */
static void kg_joint_keys(const kg_joint_kind* kind, const char** keys)
{
    int n = 0;
    keys[n++] = "type";
    keys[n++] = "a";
    keys[n++] = "b";
    for (const kg_joint_anchor* a = kind->anchors; a->key; ++a) {
        keys[n++] = a->key;
    }
    for (const kg_joint_field* f = kind->options; f->key; ++f) {
        keys[n++] = f->key;
    }
    keys[n] = NULL;
}

static kg_vec2* kg_joint_vec2(kg_scene_joint* j, size_t offset) { return (kg_vec2*)((char*)j + offset); }

static kg_result kg_read_anchors(const kg_json_reader* reader, const cJSON* item, const kg_json_path* path,
                                 const kg_joint_kind* kind, kg_scene_joint* j)
{
    for (const kg_joint_anchor* a = kind->anchors; a->key; ++a) {
        if (a->presence == KG_ANCHOR_REQUIRED) {
            KG_TRY(kg_json_require(reader, item, path, a->key));
        }
        if (a->presence == KG_ANCHOR_SECOND) {
            j->anchor_b = j->anchor_a;
        }
        KG_TRY(kg_json_vec2(reader, item, path, a->key, kg_joint_vec2(j, a->offset)));
    }
    return KG_OK;
}

static kg_result kg_read_options(const kg_json_reader* reader, const cJSON* item, const kg_json_path* path,
                                 const kg_joint_kind* kind, kg_scene_joint* j)
{
    for (const kg_joint_field* f = kind->options; f->key; ++f) {
        void* at = (char*)j + f->offset;
        switch (f->kind) {
        case KG_FIELD_FLOAT: KG_TRY(kg_json_float(reader, item, path, f->key, f->rule, (float*)at)); break;
        case KG_FIELD_BOOL: KG_TRY(kg_json_bool(reader, item, path, f->key, (int*)at)); break;
        default: KG_TRY(kg_json_vec2(reader, item, path, f->key, (kg_vec2*)at)); break;
        }
    }
    return KG_OK;
}

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

/* The defaults that come from the scene's bodies: the reference angles (b's angle minus
 * a's), the point a mouse joint drags (b's origin), a motor joint's offsets (b's pose in
 * a's frame). */
static void kg_joint_defaults(const kg_scene* scene, kg_scene_joint* j)
{
    float angle_a = kg_scene_angle(scene, j->body_a), relative = kg_scene_angle(scene, j->body_b) - angle_a;
    j->revolute.reference_angle = relative;
    j->weld.reference_angle = relative;
    j->prismatic.reference_angle = relative;
    j->anchor_b = j->type == KG_JOINT_MOUSE ? kg_scene_position(scene, j->body_b) : j->anchor_b;
    kg_vec2 pa = kg_scene_position(scene, j->body_a), pb = kg_scene_position(scene, j->body_b);
    float c = cosf(angle_a), s = sinf(angle_a), dx = pb.x - pa.x, dy = pb.y - pa.y;
    j->motor.linear_offset.x = c * dx + s * dy;
    j->motor.linear_offset.y = -s * dx + c * dy;
    j->motor.angular_offset = relative;
}

/* What follows from the anchors: a distance joint's length (as placed), a mouse joint's
 * world side (its target), an axis that is not zero. */
static kg_result kg_after_anchors(const kg_json_reader* reader, const kg_json_path* path, kg_scene_joint* j)
{
    if (j->type == KG_JOINT_DISTANCE) {
        float dx = j->anchor_b.x - j->anchor_a.x, dy = j->anchor_b.y - j->anchor_a.y;
        j->distance.length = sqrtf(dx * dx + dy * dy);
    }
    if (j->type == KG_JOINT_MOUSE) {
        j->anchor_a = j->mouse.target;
    }
    int axis = j->type == KG_JOINT_PRISMATIC || j->type == KG_JOINT_WHEEL;
    if (axis && j->axis.x * j->axis.x + j->axis.y * j->axis.y < 1e-12f) {
        kg_json_path at = kg_json_path_key(path, "axis");
        return kg_json_fail(reader, &at, "must not be zero");
    }
    return KG_OK;
}

/* A failure at path: the reader's (a file's path, KG_ERROR_PARSE), or with no reader a
 * call's (path names the call and the joint, KG_ERROR_INVALID_ARGUMENT). */
KG_PRINTF(3, 4)
static kg_result kg_joint_fail(const kg_json_reader* reader, const kg_json_path* path, const char* fmt, ...)
{
    char what[256];
    va_list args;
    va_start(args, fmt);
    vsnprintf(what, sizeof what, fmt, args);
    va_end(args);
    if (reader) {
        return kg_json_fail(reader, path, "%s", what);
    }
    return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: %s", path->text, what);
}

/* Fails at path.key with "must be <= other" when lower > upper. */
static kg_result kg_check_order(const kg_json_reader* reader, const kg_json_path* path, float lower, float upper,
                                const char* key, const char* other)
{
    if (lower > upper) {
        kg_json_path at = kg_json_path_key(path, key);
        return kg_joint_fail(reader, &at, "must be <= %s", other);
    }
    return KG_OK;
}

/* The checks between options. */
static kg_result kg_check_options(const kg_json_reader* reader, const kg_json_path* path, const kg_scene_joint* j)
{
    switch (j->type) {
    case KG_JOINT_REVOLUTE:
        return kg_check_order(reader, path, j->revolute.lower_angle, j->revolute.upper_angle, "lower_angle",
                              "upper_angle");
    case KG_JOINT_DISTANCE:
        if (!(j->distance.length > 0.0f)) {
            kg_json_path at = kg_json_path_key(path, "length");
            return kg_joint_fail(reader, &at, "is required when the anchors coincide (must be > 0)");
        }
        return kg_check_order(reader, path, j->distance.min_length, j->distance.max_length, "min_length",
                              "max_length");
    case KG_JOINT_PRISMATIC:
        return kg_check_order(reader, path, j->prismatic.lower_translation, j->prismatic.upper_translation,
                              "lower_translation", "upper_translation");
    case KG_JOINT_WHEEL:
        return kg_check_order(reader, path, j->wheel.lower_translation, j->wheel.upper_translation,
                              "lower_translation", "upper_translation");
    default: return KG_OK;
    }
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
        return kg_joint_fail(reader, path, "an anchor is too far from its body (over 1e37 m)");
    }
    if (j->type == KG_JOINT_PRISMATIC || j->type == KG_JOINT_WHEEL) {
        double ax = j->axis.x, ay = j->axis.y;
        if (!(fabs(ax) < 1e18 && fabs(ay) < 1e18) || !(sqrt(ax * ax + ay * ay) > 1e-3)) {
            kg_json_path at = kg_json_path_key(path, "axis");
            return kg_joint_fail(reader, &at, "must be longer than 0.001 and shorter than 1e18");
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
        return kg_joint_fail(reader, path, "%s", why);
    }
    return KG_OK;
}

/* Each float option of j's kind by the rule the reader reads it with. */
static kg_result kg_check_fields(const kg_json_reader* reader, const kg_json_path* path, const kg_scene_joint* j)
{
    for (const kg_joint_field* f = kJointKinds[j->type].options; f->key; ++f) {
        const float* at = (const float*)((const char*)j + f->offset);
        int floats = f->kind == KG_FIELD_FLOAT ? 1 : f->kind == KG_FIELD_VEC2 ? 2 : 0;
        for (int k = 0; k < floats; ++k) {
            const char* broken = kg_json_rule_broken(at[k], f->rule);
            if (broken) {
                kg_json_path at_key = kg_json_path_key(path, f->key);
                return kg_joint_fail(reader, &at_key, "%s", broken);
            }
        }
    }
    return KG_OK;
}

kg_result kg_check_joint_entry(const kg_json_reader* reader, const kg_json_path* path, const kg_scene* scene,
                               const kg_scene_joint* j)
{
    if ((int)j->type < 0 || (int)j->type >= KG_JOINT_KIND_COUNT) {
        kg_json_path at = kg_json_path_key(path, "type");
        return kg_joint_fail(reader, &at, "%d is no joint type (0 to %d)", (int)j->type, KG_JOINT_KIND_COUNT - 1);
    }
    if (j->body_a == j->body_b) {
        kg_json_path at = kg_json_path_key(path, "b");
        return kg_joint_fail(reader, &at, "names the same body as \"a\": a joint needs two bodies");
    }
    if (j->type == KG_JOINT_MOUSE && j->body_a >= 0) {
        kg_json_path at = kg_json_path_key(path, "a");
        return kg_joint_fail(reader, &at, "a mouse joint drags \"b\" to its target: it has no \"a\"");
    }
    KG_TRY(kg_check_fields(reader, path, j));
    KG_TRY(kg_check_options(reader, path, j));
    return kg_check_scene_joint(reader, path, scene, j);
}

kg_json_path kg_joint_call_path(const char* call, const kg_scene* scene, int index, const kg_scene_joint* j)
{
    kg_json_path path;
    const char* a = j->body_a < 0 ? "(the world)" : kg_scene_body_name(scene, j->body_a);
    char clean_a[64], clean_b[64];
    kg_json_clean_text(clean_a, sizeof clean_a, a);
    kg_json_clean_text(clean_b, sizeof clean_b, kg_scene_body_name(scene, j->body_b));
    snprintf(path.text, sizeof path.text, "%s: joint %d (a '%s', b '%s')", call, index, clean_a, clean_b);
    return path;
}

void kg_scene_joint_init(kg_scene_joint* j, kg_joint_type type)
{
    memset(j, 0, sizeof *j);
    j->type = type;
    j->body_a = -1;
    j->revolute = kg_default_revolute_joint_def();
    j->distance = kg_default_distance_joint_def();
    j->weld = kg_default_weld_joint_def();
    j->mouse = kg_default_mouse_joint_def();
    j->prismatic = kg_default_prismatic_joint_def();
    j->wheel = kg_default_wheel_joint_def();
    j->motor = kg_default_motor_joint_def();
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
    for (int i = 0; i < KG_JOINT_KIND_COUNT; ++i) {
        kind = strcmp(type, kJointKinds[i].name) == 0 ? i : kind;
    }
    kg_json_path type_path = kg_json_path_key(path, "type");
    if (kind < 0) {
        return kg_json_fail(reader, &type_path,
                            "must be one of revolute, distance, weld, mouse, prismatic, wheel, motor");
    }
    const char* keys[KG_JOINT_MAX_KEYS];
    kg_joint_keys(&kJointKinds[kind], keys);
    KG_TRY(kg_json_check_object(reader, item, path, keys));
    kg_scene_joint j;
    kg_scene_joint_init(&j, (kg_joint_type)kind);
    KG_TRY(kg_read_joint_body(reader, scene, item, path, "a", 0, &j.body_a));
    KG_TRY(kg_read_joint_body(reader, scene, item, path, "b", 1, &j.body_b));
    kg_joint_defaults(scene, &j);
    KG_TRY(kg_read_anchors(reader, item, path, &kJointKinds[kind], &j));
    KG_TRY(kg_after_anchors(reader, path, &j));
    KG_TRY(kg_read_options(reader, item, path, &kJointKinds[kind], &j));
    KG_TRY(kg_check_joint_entry(reader, path, scene, &j));
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

/* ---- writing ---- */

static int kg_add_anchors(cJSON* o, const kg_joint_kind* kind, const kg_scene_joint* j)
{
    int ok = 1;
    for (const kg_joint_anchor* a = kind->anchors; ok && a->key; ++a) {
        kg_vec2 v = *kg_joint_vec2((kg_scene_joint*)j, a->offset);
        int same = memcmp(&j->anchor_b, &j->anchor_a, sizeof v) == 0;
        ok = (a->presence == KG_ANCHOR_SECOND && same) || kg_json_add_vec2(o, a->key, v);
    }
    return ok;
}

static int kg_add_options(cJSON* o, const kg_joint_kind* kind, const kg_scene_joint* j)
{
    int ok = 1;
    for (const kg_joint_field* f = kind->options; ok && f->key; ++f) {
        const void* at = (const char*)j + f->offset;
        switch (f->kind) {
        case KG_FIELD_FLOAT: ok = kg_json_add_float(o, f->key, *(const float*)at); break;
        case KG_FIELD_BOOL: ok = cJSON_AddBoolToObject(o, f->key, *(const int*)at != 0) != NULL; break;
        default: ok = kg_json_add_vec2(o, f->key, *(const kg_vec2*)at); break;
        }
    }
    return ok;
}

cJSON* kg_scene_joint_json(const kg_scene* scene, const kg_scene_joint* j)
{
    if ((int)j->type < 0 || (int)j->type >= KG_JOINT_KIND_COUNT) {
        return NULL; /* kg_check_joint_entry refuses it first, with a message */
    }
    const kg_joint_kind* kind = &kJointKinds[j->type];
    cJSON* o = cJSON_CreateObject();
    int ok = o && cJSON_AddStringToObject(o, "type", kind->name) &&
             (j->body_a < 0 || cJSON_AddStringToObject(o, "a", kg_scene_body_name(scene, j->body_a))) &&
             cJSON_AddStringToObject(o, "b", kg_scene_body_name(scene, j->body_b)) &&
             kg_add_anchors(o, kind, j) && kg_add_options(o, kind, j);
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}
