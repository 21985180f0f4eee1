/* A scene's Tiled level data (include/kgyro/scene.h, "Tiled levels"): the custom
 * properties of maps, layers, bodies and markers, the layers and markers themselves, the
 * bodies' classes and layers, and the loader's notes. Strings live in one pool and are
 * kept as offsets, turned into pointers when read; each owner's properties are one run
 * of the property array. */
#include "io/scene_props.h"
#include "core/error.h"

#include <stdlib.h>
#include <string.h>

#define KG_MAX_NOTES 100

/* An owner's properties: props[first .. first + count). */
typedef struct kg_prop_range {
    int first, count;
} kg_prop_range;

/* A property with its strings as offsets into the pool (text 0: none). */
typedef struct kg_prop_record {
    kg_scene_property value;
    size_t name, text;
} kg_prop_record;

/* Layers and markers start with their name, so that one look-up finds either. */
typedef struct kg_layer_record {
    size_t name, kind;
    kg_scene_layer value;
    kg_prop_range props;
} kg_layer_record;

typedef struct kg_marker_record {
    size_t name, class_name;
    kg_scene_marker value;
    kg_prop_range props;
} kg_marker_record;

/* Per body index; bodies past body_capacity, or not made from a Tiled object, have
 * class "" (offset 1), layer -1 and no properties. */
typedef struct kg_body_record {
    size_t class_name;
    int layer;
    kg_prop_range props;
} kg_body_record;

struct kg_scene_level {
    char* strings; /* offset 0 is never used (it means "none"), offset 1 is "" */
    size_t strings_length, strings_capacity;
    kg_prop_record* props;
    int prop_count, prop_capacity;
    kg_prop_range* maps;
    int map_count, map_capacity;
    kg_layer_record* layers;
    int layer_count, layer_capacity;
    kg_marker_record* markers;
    int marker_count, marker_capacity;
    kg_body_record* bodies;
    int body_capacity;
    size_t notes[KG_MAX_NOTES];
    int note_count;
};

void kg_scene_level_free(kg_scene_level* level)
{
    if (!level) {
        return;
    }
    free(level->strings);
    free(level->props);
    free(level->maps);
    free(level->layers);
    free(level->markers);
    free(level->bodies);
    free(level);
}

/* ---- building ---- */

static kg_result kg_out_of_memory(void)
{
    return kg_fail(KG_ERROR_OUT_OF_MEMORY, "scene: out of memory for the level's properties and markers");
}

/* The scene's level data, made when first needed; NULL when out of memory. */
static kg_scene_level* kg_level(kg_scene* scene)
{
    kg_scene_level* level = kg_scene_get_level(scene);
    if (level) {
        return level;
    }
    level = calloc(1, sizeof *level);
    char* strings = malloc(64);
    if (!level || !strings) {
        free(level);
        free(strings);
        return NULL;
    }
    strings[0] = strings[1] = '\0';
    level->strings = strings;
    level->strings_length = 2;
    level->strings_capacity = 64;
    kg_scene_set_level(scene, level);
    return level;
}

/* Copies text into the pool: its offset, or 0 when out of memory (NULL text: 1, ""). */
static size_t kg_intern(kg_scene_level* level, const char* text)
{
    if (!text || !text[0]) {
        return 1;
    }
    size_t length = strlen(text) + 1, needed = level->strings_length + length;
    if (needed > level->strings_capacity) {
        size_t capacity = level->strings_capacity;
        while (capacity < needed) {
            capacity *= 2;
        }
        char* grown = realloc(level->strings, capacity);
        if (!grown) {
            return 0;
        }
        level->strings = grown;
        level->strings_capacity = capacity;
    }
    size_t offset = level->strings_length;
    memcpy(level->strings + offset, text, length);
    level->strings_length = needed;
    return offset;
}

kg_result kg_scene_add_map(kg_scene* scene, int* index)
{
    kg_scene_level* level = kg_level(scene);
    if (!level || !kg_scene_grow((void**)&level->maps, &level->map_capacity, level->map_count + 1, sizeof *level->maps)) {
        return kg_out_of_memory();
    }
    level->maps[level->map_count] = (kg_prop_range){0, 0};
    *index = level->map_count++;
    return KG_OK;
}

kg_result kg_scene_add_layer(kg_scene* scene, const kg_scene_layer* layer, int* index)
{
    kg_scene_level* level = kg_level(scene);
    if (!level ||
        !kg_scene_grow((void**)&level->layers, &level->layer_capacity, level->layer_count + 1, sizeof *level->layers)) {
        return kg_out_of_memory();
    }
    kg_layer_record record = {kg_intern(level, layer->name), kg_intern(level, layer->kind), *layer, {0, 0}};
    if (record.name == 0 || record.kind == 0) {
        return kg_out_of_memory();
    }
    level->layers[level->layer_count] = record;
    *index = level->layer_count++;
    return KG_OK;
}

kg_result kg_scene_add_marker(kg_scene* scene, const kg_scene_marker* marker, int* index)
{
    kg_scene_level* level = kg_level(scene);
    if (!level || !kg_scene_grow((void**)&level->markers, &level->marker_capacity, level->marker_count + 1,
                                 sizeof *level->markers)) {
        return kg_out_of_memory();
    }
    kg_marker_record record = {kg_intern(level, marker->name), kg_intern(level, marker->class_name), *marker, {0, 0}};
    if (record.name == 0 || record.class_name == 0) {
        return kg_out_of_memory();
    }
    level->markers[level->marker_count] = record;
    *index = level->marker_count++;
    return KG_OK;
}

/* The record of body index, the array grown to hold it (new records blank). */
static kg_body_record* kg_body_record_of(kg_scene_level* level, int index)
{
    int old = level->body_capacity;
    if (!kg_scene_grow((void**)&level->bodies, &level->body_capacity, index + 1, sizeof *level->bodies)) {
        return NULL;
    }
    for (int i = old; i < level->body_capacity; ++i) {
        level->bodies[i] = (kg_body_record){1, -1, {0, 0}};
    }
    return &level->bodies[index];
}

kg_result kg_scene_set_body_origin(kg_scene* scene, int index, const char* class_name, int layer)
{
    if (index < 0 || index >= kg_scene_body_count(scene)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_set_body_origin: no body %d", index);
    }
    kg_scene_level* level = kg_level(scene);
    kg_body_record* body = level ? kg_body_record_of(level, index) : NULL;
    size_t name = body ? kg_intern(level, class_name) : 0;
    if (name == 0) {
        return kg_out_of_memory();
    }
    body->class_name = name;
    body->layer = layer;
    return KG_OK;
}

/* The property range of an owner, or NULL when there is no such owner. */
static const kg_prop_range* kg_owner_range(const kg_scene_level* level, kg_scene_owner owner, int index)
{
    if (!level || index < 0) {
        return NULL;
    }
    switch (owner) {
    case KG_SCENE_MAP: return index < level->map_count ? &level->maps[index] : NULL;
    case KG_SCENE_LAYER: return index < level->layer_count ? &level->layers[index].props : NULL;
    case KG_SCENE_MARKER: return index < level->marker_count ? &level->markers[index].props : NULL;
    case KG_SCENE_BODY: return index < level->body_capacity ? &level->bodies[index].props : NULL;
    }
    return NULL;
}

static kg_result kg_add_property(kg_scene_level* level, const kg_scene_property* property)
{
    if (!kg_scene_grow((void**)&level->props, &level->prop_capacity, level->prop_count + 1, sizeof *level->props)) {
        return kg_out_of_memory();
    }
    kg_prop_record record = {*property, kg_intern(level, property->name), 0};
    record.text = property->text ? kg_intern(level, property->text) : 0;
    if (record.name == 0 || (property->text && record.text == 0)) {
        return kg_out_of_memory();
    }
    record.value.name = NULL;
    record.value.text = NULL;
    level->props[level->prop_count++] = record;
    return KG_OK;
}

kg_result kg_scene_add_property(kg_scene* scene, kg_scene_owner owner, int index, const kg_scene_property* property)
{
    kg_scene_level* level = kg_level(scene);
    if (!level) {
        return kg_out_of_memory();
    }
    if (owner == KG_SCENE_BODY && index >= 0 && index < kg_scene_body_count(scene) &&
        !kg_body_record_of(level, index)) {
        return kg_out_of_memory();
    }
    kg_prop_range* range = (kg_prop_range*)kg_owner_range(level, owner, index); /* level is ours to change */
    if (!range || (range->count > 0 && range->first + range->count != level->prop_count)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_add_property: no owner %d of kind %d, or its "
                                                  "properties were not added together", index, (int)owner);
    }
    KG_TRY(kg_add_property(level, property));
    range->first = range->count > 0 ? range->first : level->prop_count - 1;
    range->count += 1;
    return KG_OK;
}

kg_result kg_scene_add_note(kg_scene* scene, const char* text)
{
    kg_scene_level* level = kg_level(scene);
    if (!level) {
        return kg_out_of_memory();
    }
    if (level->note_count == KG_MAX_NOTES) {
        return KG_OK;
    }
    size_t offset = kg_intern(level, text);
    if (offset == 0) {
        return kg_out_of_memory();
    }
    level->notes[level->note_count++] = offset;
    return KG_OK;
}

/* ---- reading ---- */

static const kg_scene_level* kg_level_of(const kg_scene* scene)
{
    return scene ? kg_scene_get_level(scene) : NULL;
}

static const char* kg_text(const kg_scene_level* level, size_t offset)
{
    return offset ? level->strings + offset : NULL;
}

int kg_scene_property_count(const kg_scene* scene, kg_scene_owner owner, int index)
{
    const kg_prop_range* range = kg_owner_range(kg_level_of(scene), owner, index);
    return range ? range->count : 0;
}

static void kg_read_property(const kg_scene_level* level, int i, kg_scene_property* out)
{
    const kg_prop_record* record = &level->props[i];
    *out = record->value;
    out->name = kg_text(level, record->name);
    out->text = kg_text(level, record->text);
}

kg_result kg_scene_get_property(const kg_scene* scene, kg_scene_owner owner, int index, int k,
                                kg_scene_property* out)
{
    if (!scene || !out) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_get_property: NULL argument");
    }
    const kg_scene_level* level = kg_level_of(scene);
    const kg_prop_range* range = kg_owner_range(level, owner, index);
    if (!range || k < 0 || k >= range->count) {
        return kg_fail(KG_ERROR_NOT_FOUND, "kg_scene_get_property: owner %d of kind %d has no property %d", index,
                       (int)owner, k);
    }
    kg_read_property(level, range->first + k, out);
    return KG_OK;
}

kg_result kg_scene_find_property(const kg_scene* scene, kg_scene_owner owner, int index, const char* name,
                                 kg_scene_property* out)
{
    if (!scene || !name || !out) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_find_property: NULL argument");
    }
    const kg_scene_level* level = kg_level_of(scene);
    const kg_prop_range* range = kg_owner_range(level, owner, index);
    for (int i = 0; range && i < range->count; ++i) {
        if (strcmp(level->strings + level->props[range->first + i].name, name) == 0) {
            kg_read_property(level, range->first + i, out);
            return KG_OK;
        }
    }
    return kg_fail(KG_ERROR_NOT_FOUND, "kg_scene_find_property: owner %d of kind %d has no property '%.64s'", index,
                   (int)owner, name);
}

kg_result kg_scene_body_property(const kg_scene* scene, int body_index, const char* name, kg_scene_property* out)
{
    return kg_scene_find_property(scene, KG_SCENE_BODY, body_index, name, out);
}

const char* kg_scene_body_class(const kg_scene* scene, int index)
{
    if (index < 0 || index >= kg_scene_body_count(scene)) {
        return NULL;
    }
    const kg_scene_level* level = kg_level_of(scene);
    return level && index < level->body_capacity ? level->strings + level->bodies[index].class_name : "";
}

int kg_scene_body_layer(const kg_scene* scene, int index)
{
    const kg_scene_level* level = kg_level_of(scene);
    int known = level && index >= 0 && index < level->body_capacity && index < kg_scene_body_count(scene);
    return known ? level->bodies[index].layer : -1;
}

int kg_scene_layer_count(const kg_scene* scene)
{
    const kg_scene_level* level = kg_level_of(scene);
    return level ? level->layer_count : 0;
}

kg_result kg_scene_get_layer(const kg_scene* scene, int index, kg_scene_layer* out)
{
    if (!out || index < 0 || index >= kg_scene_layer_count(scene)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_get_layer: no layer %d, or out is NULL", index);
    }
    const kg_scene_level* level = kg_level_of(scene);
    const kg_layer_record* record = &level->layers[index];
    *out = record->value;
    out->name = kg_text(level, record->name);
    out->kind = kg_text(level, record->kind);
    return KG_OK;
}

/* The index of the first of count records (size bytes each, starting with their name's
 * offset) called name, or -1. */
static int kg_find_named(const kg_scene_level* level, const void* records, int count, size_t size, const char* name)
{
    for (int i = 0; name && i < count; ++i) {
        size_t offset;
        memcpy(&offset, (const char*)records + (size_t)i * size, sizeof offset);
        if (strcmp(level->strings + offset, name) == 0) {
            return i;
        }
    }
    return -1;
}

int kg_scene_find_layer(const kg_scene* scene, const char* name)
{
    const kg_scene_level* level = kg_level_of(scene);
    return level ? kg_find_named(level, level->layers, level->layer_count, sizeof *level->layers, name) : -1;
}

int kg_scene_marker_count(const kg_scene* scene)
{
    const kg_scene_level* level = kg_level_of(scene);
    return level ? level->marker_count : 0;
}

kg_result kg_scene_get_marker(const kg_scene* scene, int index, kg_scene_marker* out)
{
    if (!out || index < 0 || index >= kg_scene_marker_count(scene)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_get_marker: no marker %d, or out is NULL", index);
    }
    const kg_scene_level* level = kg_level_of(scene);
    const kg_marker_record* record = &level->markers[index];
    *out = record->value;
    out->name = kg_text(level, record->name);
    out->class_name = kg_text(level, record->class_name);
    return KG_OK;
}

int kg_scene_find_marker(const kg_scene* scene, const char* name)
{
    const kg_scene_level* level = kg_level_of(scene);
    return level ? kg_find_named(level, level->markers, level->marker_count, sizeof *level->markers, name) : -1;
}

int kg_scene_note_count(const kg_scene* scene)
{
    const kg_scene_level* level = kg_level_of(scene);
    return level ? level->note_count : 0;
}

const char* kg_scene_get_note(const kg_scene* scene, int index)
{
    const kg_scene_level* level = kg_level_of(scene);
    return level && index >= 0 && index < level->note_count ? level->strings + level->notes[index] : NULL;
}
