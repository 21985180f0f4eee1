/* What a Tiled map holds beside its physics, kept in the scene (io/scene_props.h): the
 * custom properties of the map, its layers and objects, each checked against its type,
 * class-typed ones flattened; objects' classes; notes on what is ignored. */
#include "io/tiled_level.h"
#include "io/scene_props.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* Class members nest at most this deep; flattened names are at most this long. */
#define KG_CLASS_DEPTH_MAX 8
#define KG_PROPERTY_NAME_MAX 256

/* Where the properties being read go. */
typedef struct kg_property_sink {
    kg_scene* scene;
    const kg_json_reader* reader;
    kg_scene_owner owner;
    int index;
} kg_property_sink;

static const char* const kPropertyTypes[] = {"string", "int", "float", "bool", "color", "file", "object", "class",
                                             NULL};
#define KG_PROPERTY_CLASS 7

static kg_result kg_keep(const kg_property_sink* sink, const kg_scene_property* p)
{
    return kg_scene_add_property(sink->scene, sink->owner, sink->index, p);
}

/* A whole number in [min, max] into *out. */
static int kg_whole(const cJSON* value, double min, double max, int* out)
{
    double d = cJSON_IsNumber(value) ? value->valuedouble : NAN;
    if (!(d >= min && d <= max) || d != floor(d)) {
        return 0;
    }
    *out = (int)d;
    return 1;
}

static int kg_hex_digit(char c)
{
    return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
}

/* Tiled's "#aarrggbb" or "#rrggbb" (alpha 0xff) into 0xAARRGGBB; "" (unset) is 0. */
static int kg_parse_color(const char* text, uint32_t* out)
{
    size_t n = strlen(text);
    *out = 0u;
    if (n == 0) {
        return 1;
    }
    if (text[0] != '#' || (n != 7 && n != 9)) {
        return 0;
    }
    uint32_t value = 0u;
    for (size_t i = 1; i < n; ++i) {
        int digit = kg_hex_digit(text[i]);
        if (digit < 0) {
            return 0;
        }
        value = value << 4 | (uint32_t)digit;
    }
    *out = n == 7 ? 0xFF000000u | value : value;
    return 1;
}

/* A value of a declared type (not class) into p; NULL, or what is wrong with it. */
static const char* kg_typed_value(const cJSON* value, int type, kg_scene_property* p)
{
    p->type = (kg_scene_property_type)type;
    switch (type) {
    case KG_PROPERTY_STRING:
    case KG_PROPERTY_FILE:
        p->text = cJSON_IsString(value) ? value->valuestring : NULL;
        return p->text ? NULL : "must be a string";
    case KG_PROPERTY_INT:
        if (!kg_whole(value, INT_MIN, INT_MAX, &p->integer)) {
            return "must be an integer in [-2147483648, 2147483647]";
        }
        p->number = p->integer;
        return NULL;
    case KG_PROPERTY_OBJECT:
        return kg_whole(value, 0, INT_MAX, &p->integer) ? NULL : "must be an object id (an integer >= 0)";
    case KG_PROPERTY_FLOAT:
        p->number = cJSON_IsNumber(value) ? value->valuedouble : NAN;
        return isfinite(p->number) ? NULL : "must be a finite number";
    case KG_PROPERTY_BOOL:
        p->boolean = cJSON_IsTrue(value);
        return cJSON_IsBool(value) ? NULL : "must be true or false";
    default: /* KG_PROPERTY_COLOR */
        p->text = cJSON_IsString(value) ? value->valuestring : NULL;
        return p->text && kg_parse_color(p->text, &p->color) ? NULL
                                                             : "must be a color, \"#aarrggbb\" or \"#rrggbb\"";
    }
}

/* The type a value without a declared one has: a class member's, or a property's that
 * does not say (Tiled's default is string, but the value tells better). */
static int kg_implied_type(const cJSON* value)
{
    int whole = 0;
    return cJSON_IsString(value) ? KG_PROPERTY_STRING
           : cJSON_IsBool(value) ? KG_PROPERTY_BOOL
           : cJSON_IsObject(value) ? KG_PROPERTY_CLASS
           : kg_whole(value, INT_MIN, INT_MAX, &whole) ? KG_PROPERTY_INT
           : cJSON_IsNumber(value) ? KG_PROPERTY_FLOAT
                                   : -1;
}

static kg_result kg_keep_value(const kg_property_sink* sink, const char* name, const cJSON* value, int type,
                               const kg_json_path* path, int depth);

/* A class-typed value: each member a property "NAME.MEMBER". */
static kg_result kg_keep_class(const kg_property_sink* sink, const char* name, const cJSON* value,
                               const kg_json_path* path, int depth)
{
    if (!cJSON_IsObject(value)) {
        return kg_json_fail(sink->reader, path, "must be an object (the members of a class)");
    }
    if (depth >= KG_CLASS_DEPTH_MAX) {
        return kg_json_fail(sink->reader, path, "classes nested more than %d deep", KG_CLASS_DEPTH_MAX);
    }
    for (const cJSON* member = value->child; member; member = member->next) {
        char member_name[KG_PROPERTY_NAME_MAX];
        kg_json_path member_path = kg_json_path_key(path, member->string);
        int written = snprintf(member_name, sizeof member_name, "%s.%s", name, member->string);
        if (written < 0 || (size_t)written >= sizeof member_name) {
            return kg_json_fail(sink->reader, &member_path, "the flattened name is longer than %d characters",
                                KG_PROPERTY_NAME_MAX - 1);
        }
        KG_TRY(kg_keep_value(sink, member_name, member, kg_implied_type(member), &member_path, depth + 1));
    }
    return KG_OK;
}

static kg_result kg_keep_value(const kg_property_sink* sink, const char* name, const cJSON* value, int type,
                               const kg_json_path* path, int depth)
{
    if (type == KG_PROPERTY_CLASS) {
        return kg_keep_class(sink, name, value, path, depth);
    }
    if (type < 0) {
        return kg_json_fail(sink->reader, path, "must be a string, a number, true, false or an object");
    }
    kg_scene_property p;
    memset(&p, 0, sizeof p);
    p.name = name;
    const char* wrong = kg_typed_value(value, type, &p);
    return wrong ? kg_json_fail(sink->reader, path, "%s", wrong) : kg_keep(sink, &p);
}

/* The declared type of property p (at path), or the one its value implies. */
static kg_result kg_property_type(const kg_json_reader* reader, const cJSON* p, const kg_json_path* path, int* type)
{
    const char* name = NULL;
    KG_TRY(kg_json_string(reader, p, path, "type", &name));
    const cJSON* value = cJSON_GetObjectItemCaseSensitive(p, "value");
    if (!name) {
        *type = kg_implied_type(value);
        return KG_OK;
    }
    for (*type = 0; kPropertyTypes[*type] && strcmp(kPropertyTypes[*type], name) != 0; ++*type) {
    }
    if (kPropertyTypes[*type]) {
        return KG_OK;
    }
    kg_json_path type_path = kg_json_path_key(path, "type");
    return kg_json_fail(reader, &type_path, "must be \"string\", \"int\", \"float\", \"bool\", \"color\", \"file\", "
                                            "\"object\" or \"class\" (got \"%s\")", name);
}

/* Property entry i of list (at list_path): {"name", "type", "value"}. */
static kg_result kg_keep_property(const kg_property_sink* sink, const cJSON* p, const kg_json_path* list_path, int i)
{
    kg_json_path entry_path = kg_json_path_index(list_path, i);
    const char* name = NULL;
    if (!cJSON_IsObject(p)) {
        return kg_json_fail(sink->reader, &entry_path, "must be an object (a property)");
    }
    KG_TRY(kg_json_require(sink->reader, p, &entry_path, "name"));
    KG_TRY(kg_json_string(sink->reader, p, &entry_path, "name", &name));
    kg_json_path p_path = kg_json_path_key(list_path, name); /* OWNER.properties.NAME, as the loader's messages */
    int type = 0;
    KG_TRY(kg_json_require(sink->reader, p, &p_path, "value"));
    KG_TRY(kg_property_type(sink->reader, p, &p_path, &type));
    kg_json_path value_path = kg_json_path_key(&p_path, "value");
    return kg_keep_value(sink, name, cJSON_GetObjectItemCaseSensitive(p, "value"), type, &value_path, 0);
}

kg_result kg_tiled_check_properties(const kg_json_reader* reader, const cJSON* owner, const kg_json_path* path)
{
    const cJSON* list = cJSON_GetObjectItemCaseSensitive(owner, "properties");
    if (list && !cJSON_IsArray(list)) {
        kg_json_path list_path = kg_json_path_key(path, "properties");
        return kg_json_fail(reader, &list_path, "must be an array (the format of Tiled 1.2 and later: save the "
                                                "map again with a recent Tiled)");
    }
    return KG_OK;
}

kg_result kg_tiled_keep_properties(kg_scene* scene, const kg_json_reader* reader, const cJSON* owner_json,
                                   const kg_json_path* path, kg_scene_owner owner, int index)
{
    KG_TRY(kg_tiled_check_properties(reader, owner_json, path));
    const cJSON* list = cJSON_GetObjectItemCaseSensitive(owner_json, "properties");
    kg_json_path list_path = kg_json_path_key(path, "properties");
    if (!list) {
        return KG_OK;
    }
    kg_property_sink sink = {scene, reader, owner, index};
    int i = 0;
    for (const cJSON* p = list->child; p; p = p->next, ++i) {
        KG_TRY(kg_keep_property(&sink, p, &list_path, i));
    }
    return KG_OK;
}

kg_result kg_tiled_object_class(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                                const char** out)
{
    *out = "";
    KG_TRY(kg_json_string(reader, object, path, "type", out));
    return kg_json_string(reader, object, path, "class", out);
}

kg_result kg_tiled_note(kg_scene* scene, const kg_json_reader* reader, const kg_json_path* path, const char* what)
{
    char raw[512], clean[512];
    snprintf(raw, sizeof raw, "%s: %s: %s", reader->source, path->text, what);
    kg_json_clean_text(clean, sizeof clean, raw);
    return kg_scene_add_note(scene, clean);
}
