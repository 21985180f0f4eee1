/* A Tiled joint object turned into the entry a scene file would have for it (its kind,
 * bodies, anchors and options as JSON fields), then read by the scene files' own joint
 * reader: the same checks, the same messages. */
#include "io/tiled_joints.h"

#include "io/scene_joints.h"

#include <string.h>

/* The scene name of the body made from Tiled object id, or NULL. */
static const char* kg_object_body_name(const kg_scene* scene, const kg_tiled_body* bodies, int count, int id)
{
    for (int i = 0; i < count; ++i) {
        if (bodies[i].object_id == id) {
            return kg_scene_body_name(scene, bodies[i].body);
        }
    }
    return NULL;
}

typedef struct kg_joint_entry {
    cJSON* item;       /* the entry being built */
    float axis[2];     /* from axis_x, axis_y */
    int has_axis;
} kg_joint_entry;

static int kg_add_point(cJSON* item, const char* key, kg_vec2 p)
{
    const float xy[2] = {p.x, p.y};
    return cJSON_AddItemToObject(item, key, cJSON_CreateFloatArray(xy, 2));
}

/* Property "a" or "b": an object reference (by id) or a body's name. */
static kg_result kg_body_field(const kg_json_reader* reader, const kg_scene* scene, const kg_tiled_body* bodies,
                               int count, const cJSON* property, const kg_json_path* path, kg_joint_entry* e)
{
    const cJSON* name = cJSON_GetObjectItemCaseSensitive(property, "name");
    const cJSON* type = cJSON_GetObjectItemCaseSensitive(property, "type");
    const cJSON* value = cJSON_GetObjectItemCaseSensitive(property, "value");
    kg_json_path at = kg_json_path_key(path, "value");
    if (cJSON_IsString(type) && strcmp(type->valuestring, "object") == 0 && cJSON_IsNumber(value)) {
        if (value->valueint == 0) {
            return KG_OK; /* no object: the world */
        }
        const char* body = kg_object_body_name(scene, bodies, count, value->valueint);
        if (!body) {
            return kg_json_fail(reader, &at, "object %d is not a body of this map", value->valueint);
        }
        cJSON_AddStringToObject(e->item, name->valuestring, body);
        return KG_OK;
    }
    if (!cJSON_IsString(value)) {
        return kg_json_fail(reader, &at, "must name a body: an object property, or a body's name");
    }
    cJSON_AddStringToObject(e->item, name->valuestring, value->valuestring);
    return KG_OK;
}

/* One property of the joint object into the entry: the bodies, the axis, or an option
 * under its own name (an unknown name or a wrong type is refused by the joint reader). */
static kg_result kg_property_field(const kg_json_reader* reader, const kg_scene* scene, const kg_tiled_body* bodies,
                                   int count, const cJSON* property, const kg_json_path* path, kg_joint_entry* e)
{
    const cJSON* name = cJSON_GetObjectItemCaseSensitive(property, "name");
    const cJSON* value = cJSON_GetObjectItemCaseSensitive(property, "value");
    if (!cJSON_IsString(name) || !value) {
        return kg_json_fail(reader, path, "must have a name and a value");
    }
    const char* key = name->valuestring;
    if (strcmp(key, "a") == 0 || strcmp(key, "b") == 0) {
        return kg_body_field(reader, scene, bodies, count, property, path, e);
    }
    int axis = strcmp(key, "axis_x") == 0 ? 0 : strcmp(key, "axis_y") == 0 ? 1 : -1;
    if (axis >= 0) {
        kg_json_path at = kg_json_path_key(path, "value");
        if (!cJSON_IsNumber(value)) {
            return kg_json_fail(reader, &at, "must be a number");
        }
        e->axis[axis] = (float)value->valuedouble;
        e->has_axis = 1;
        return KG_OK;
    }
    const char* field = strcmp(key, "joint") == 0 ? "type" : key;
    if (cJSON_GetObjectItemCaseSensitive(e->item, field)) {
        return kg_json_fail(reader, path, "a second property called '%s'", key);
    }
    cJSON_AddItemToObject(e->item, field, cJSON_Duplicate(value, 1));
    return KG_OK;
}

/* The anchors as the kind names them: one point, two ends, or a body point and a target. */
static void kg_anchor_fields(cJSON* item, const kg_tiled_joint* j)
{
    const cJSON* type = cJSON_GetObjectItemCaseSensitive(item, "type");
    const char* kind = cJSON_IsString(type) ? type->valuestring : "";
    if (strcmp(kind, "distance") == 0) {
        kg_add_point(item, "anchor_a", j->anchor_a);
        kg_add_point(item, "anchor_b", j->anchor_b);
    } else if (strcmp(kind, "mouse") == 0) {
        kg_add_point(item, "anchor", j->anchor_a);
        kg_add_point(item, "target", j->anchor_b);
    } else if (strcmp(kind, "motor") != 0) {
        kg_add_point(item, "anchor", j->anchor_a);
    }
}

kg_result kg_tiled_add_joint(const kg_json_reader* reader, kg_scene* scene, const kg_tiled_joint* j,
                             const kg_tiled_body* bodies, int body_count)
{
    kg_joint_entry e = {cJSON_CreateObject(), {0.0f, 0.0f}, 0};
    if (!e.item) {
        return kg_json_fail_message(KG_ERROR_OUT_OF_MEMORY, "%s: out of memory", reader->source);
    }
    const cJSON* properties = cJSON_GetObjectItemCaseSensitive(j->object, "properties");
    kg_json_path list_path = kg_json_path_key(&j->path, "properties");
    kg_result r = KG_OK;
    int i = 0;
    for (const cJSON* p = cJSON_IsArray(properties) ? properties->child : NULL; r == KG_OK && p; p = p->next, ++i) {
        kg_json_path at = kg_json_path_index(&list_path, i);
        r = kg_property_field(reader, scene, bodies, body_count, p, &at, &e);
    }
    if (r == KG_OK && !cJSON_GetObjectItemCaseSensitive(e.item, "type")) {
        r = kg_json_fail(reader, &j->path, "a joint object needs the string property \"joint\" (its kind)");
    }
    if (r == KG_OK) {
        kg_anchor_fields(e.item, j);
        if (e.has_axis) {
            cJSON_AddItemToObject(e.item, "axis", cJSON_CreateFloatArray(e.axis, 2));
        }
        r = kg_read_scene_joint(reader, scene, e.item, &j->path);
    }
    cJSON_Delete(e.item);
    return r;
}
