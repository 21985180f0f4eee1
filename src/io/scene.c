/* The scene container and builder: body definitions with unique names, forces that
 * refer to bodies by scene index, and turning all of it into a world. */
#include "kgyro/scene.h"
#include "kgyro/force.h"
#include "kgyro/shape.h"

#include "collide/shape.h"
#include "core/body_shapes.h"
#include "core/error.h"
#include "io/json_util.h"
#include "io/scene_joints.h"
#include "io/scene_limits.h"
#include "io/scene_props.h"
#include "io/scene_state.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define KG_SCENE_NAME_MAX 63

typedef struct kg_scene_pivot {
    int body;
    kg_vec2 point;
} kg_scene_pivot;

/* A body's shape after its first (kg_scene_add_body_shape), in its body's list. */
typedef struct kg_scene_shape {
    kg_body_shape_def def;
    int next; /* the body's next shape, or -1 */
} kg_scene_shape;

/* A body's chain (kg_scene_add_body_chain), in its body's list: def.points is the scene's
 * own copy. */
typedef struct kg_scene_chain {
    kg_chain_def def;
    int next; /* the body's next chain, or -1 */
} kg_scene_chain;

/* A tile map: def's shapes and tiles point at the scene's own copies. */
typedef struct kg_scene_tilemap {
    kg_tilemap_def def;
    kg_tile_shape* shapes;
    uint16_t* tiles;
} kg_scene_tilemap;

struct kg_scene {
    kg_scene_limits limits;
    kg_world_def world_def;
    float dt;
    int steps;

    int body_count, body_capacity;
    kg_body_def* bodies;
    int* first_extra;     /* per body: its second shape in shapes, or -1 */
    int* last_extra;
    int* extra_count;
    int shape_count, shape_capacity;
    kg_scene_shape* shapes; /* the bodies' shapes after their first */
    int* first_chain;       /* per body: its first chain in chains, or -1 */
    int* last_chain;
    int* chain_count;
    int chain_total, chain_capacity;
    kg_scene_chain* chains;
    size_t* name_offsets; /* into names, one per body */
    char* names;          /* NUL-terminated names back to back */
    size_t names_length, names_capacity;

    /* open addressing on name, holds body index + 1 (0 = empty); power-of-two size */
    int* name_table;
    int name_table_size;

    int force_count, force_capacity;
    kg_scene_force* forces; /* each owns its body_indices */

    int pivot_count, pivot_capacity;
    kg_scene_pivot* pivots;

    int tilemap_count, tilemap_capacity;
    kg_scene_tilemap* tilemaps;

    kg_scene_level* level; /* Tiled levels' properties and markers (scene_props.c), or NULL */
    int joint_count, joint_capacity; /* io/scene_joints.c makes them in a world */
    kg_scene_joint* joints;
    unsigned char* state; /* a saved world's snapshot (io/scene_state.h), or NULL */
    size_t state_size;
};

/* Grows *items to hold at least needed elements, doubling. */
static int kg_grow(void** items, int* capacity, int needed, size_t item_size)
{
    if (needed <= *capacity) {
        return 1;
    }
    int next = *capacity > 0 ? *capacity : 16;
    while (next < needed) {
        next *= 2;
    }
    void* grown = realloc(*items, (size_t)next * item_size);
    if (!grown) {
        return 0;
    }
    *items = grown;
    *capacity = next;
    return 1;
}

int kg_scene_grow(void** items, int* capacity, int needed, size_t item_size)
{
    return kg_grow(items, capacity, needed, item_size);
}

kg_scene_level* kg_scene_get_level(const kg_scene* scene) { return scene->level; }
void kg_scene_set_level(kg_scene* scene, kg_scene_level* level) { scene->level = level; }

kg_result kg_scene_create(kg_scene** out)
{
    if (!out) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_create: out is NULL");
    }
    kg_scene* scene = calloc(1, sizeof *scene);
    if (!scene) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_create: out of memory");
    }
    scene->limits = kg_default_scene_limits();
    scene->world_def = kg_default_world_def();
    scene->world_def.gravity = (kg_vec2){0.0f, -10.0f};
    scene->dt = 1.0f / 60.0f;
    *out = scene;
    return KG_OK;
}

void kg_scene_destroy(kg_scene* scene)
{
    if (!scene) {
        return;
    }
    for (int i = 0; i < scene->force_count; ++i) {
        free((void*)scene->forces[i].body_indices);
    }
    free(scene->forces);
    free(scene->joints);
    free(scene->pivots);
    for (int i = 0; i < scene->tilemap_count; ++i) {
        free(scene->tilemaps[i].shapes);
        free(scene->tilemaps[i].tiles);
    }
    free(scene->tilemaps);
    free(scene->state);
    free(scene->name_table);
    free(scene->names);
    free(scene->name_offsets);
    free(scene->bodies);
    free(scene->first_extra);
    free(scene->last_extra);
    free(scene->extra_count);
    free(scene->shapes);
    for (int i = 0; i < scene->chain_total; ++i) {
        free((void*)scene->chains[i].def.points);
    }
    free(scene->chains);
    free(scene->first_chain);
    free(scene->last_chain);
    free(scene->chain_count);
    kg_scene_level_free(scene->level);
    free(scene);
}

kg_scene_limits kg_default_scene_limits(void)
{
    kg_scene_limits limits = {INT_MAX, (size_t)1 << 28};
    return limits;
}

void kg_scene_set_limits(kg_scene* scene, const kg_scene_limits* limits) { scene->limits = *limits; }
const kg_scene_limits* kg_scene_get_limits(const kg_scene* scene) { return &scene->limits; }
int kg_scene_body_room(const kg_scene* scene) { return scene->limits.max_bodies - scene->body_count; }

kg_result kg_check_scene_limits(const char* function, const kg_scene_limits* limits)
{
    if (limits->max_bodies < 0 || limits->max_file_bytes == 0) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: max_bodies must be >= 0 and max_file_bytes > 0", function);
    }
    return KG_OK;
}

size_t kg_scene_file_cap(const kg_scene_limits* limits, size_t format_cap)
{
    return limits->max_file_bytes < format_cap ? limits->max_file_bytes : format_cap;
}

kg_world_def* kg_scene_world_def(kg_scene* scene) { return scene ? &scene->world_def : NULL; }
float kg_scene_dt(const kg_scene* scene) { return scene ? scene->dt : 0.0f; }
int kg_scene_steps(const kg_scene* scene) { return scene ? scene->steps : 0; }
int kg_scene_body_count(const kg_scene* scene) { return scene ? scene->body_count : 0; }
int kg_scene_force_count(const kg_scene* scene) { return scene ? scene->force_count : 0; }
int kg_scene_tilemap_count(const kg_scene* scene) { return scene ? scene->tilemap_count : 0; }

kg_result kg_scene_set_dt(kg_scene* scene, float dt)
{
    if (!scene || !isfinite(dt) || !(dt > 0.0f)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_set_dt: dt must be finite and > 0");
    }
    scene->dt = dt;
    return KG_OK;
}

kg_result kg_scene_set_steps(kg_scene* scene, int steps)
{
    if (!scene || steps < 0) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_set_steps: steps must be >= 0");
    }
    scene->steps = steps;
    return KG_OK;
}

const kg_body_def* kg_scene_body_def(const kg_scene* scene, int index)
{
    return scene && index >= 0 && index < scene->body_count ? &scene->bodies[index] : NULL;
}

const char* kg_scene_body_name(const kg_scene* scene, int index)
{
    return scene && index >= 0 && index < scene->body_count ? scene->names + scene->name_offsets[index] : NULL;
}

const kg_scene_force* kg_scene_get_force(const kg_scene* scene, int index)
{
    return scene && index >= 0 && index < scene->force_count ? &scene->forces[index] : NULL;
}

const kg_tilemap_def* kg_scene_get_tilemap(const kg_scene* scene, int index)
{
    return scene && index >= 0 && index < scene->tilemap_count ? &scene->tilemaps[index].def : NULL;
}

/* ---- names ---- */

static uint32_t kg_name_hash(const char* name)
{
    uint32_t h = 2166136261u; /* FNV-1a */
    for (const unsigned char* c = (const unsigned char*)name; *c; ++c) {
        h = (h ^ *c) * 16777619u;
    }
    return h;
}

/* The table slot holding name, or the empty slot where it would go. */
static int kg_name_slot(const kg_scene* scene, const char* name)
{
    uint32_t mask = (uint32_t)scene->name_table_size - 1u;
    uint32_t slot = kg_name_hash(name) & mask;
    while (scene->name_table[slot] != 0) {
        int body = scene->name_table[slot] - 1;
        if (strcmp(scene->names + scene->name_offsets[body], name) == 0) {
            break;
        }
        slot = (slot + 1u) & mask;
    }
    return (int)slot;
}

int kg_scene_find_body(const kg_scene* scene, const char* name)
{
    if (!scene || !name || scene->name_table_size == 0) {
        return -1;
    }
    return scene->name_table[kg_name_slot(scene, name)] - 1;
}

/* Keeps the table at most half full, so probes stay short. */
static int kg_name_table_reserve(kg_scene* scene, int count)
{
    if (2 * count <= scene->name_table_size) {
        return 1;
    }
    int size = scene->name_table_size > 0 ? scene->name_table_size : 64;
    while (size < 2 * count) {
        size *= 2;
    }
    int* table = calloc((size_t)size, sizeof *table);
    if (!table) {
        return 0;
    }
    free(scene->name_table);
    scene->name_table = table;
    scene->name_table_size = size;
    for (int body = 0; body < scene->body_count; ++body) {
        scene->name_table[kg_name_slot(scene, scene->names + scene->name_offsets[body])] = body + 1;
    }
    return 1;
}

static int kg_name_char_ok(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || strchr("_-.:/#", c);
}

static kg_result kg_check_name(const char* name)
{
    size_t length = strlen(name);
    if (length == 0 || length > KG_SCENE_NAME_MAX) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "must be 1 to %d characters long", KG_SCENE_NAME_MAX);
    }
    for (size_t i = 0; i < length; ++i) {
        if (!kg_name_char_ok(name[i])) {
            return kg_fail(KG_ERROR_INVALID_ARGUMENT,
                           "'%s' may only contain letters, digits and the characters _-.:/#", name);
        }
    }
    return KG_OK;
}

static int kg_append_name(kg_scene* scene, const char* name)
{
    size_t length = strlen(name) + 1;
    if (scene->names_length + length > scene->names_capacity) {
        size_t capacity = scene->names_capacity > 0 ? scene->names_capacity : 1024;
        while (capacity < scene->names_length + length) {
            capacity *= 2;
        }
        char* grown = realloc(scene->names, capacity);
        if (!grown) {
            return 0;
        }
        scene->names = grown;
        scene->names_capacity = capacity;
    }
    memcpy(scene->names + scene->names_length, name, length);
    scene->name_offsets[scene->body_count] = scene->names_length;
    scene->names_length += length;
    return 1;
}

/* ---- building ---- */

static int kg_reserve_bodies(kg_scene* scene, int needed)
{
    if (needed <= scene->body_capacity) {
        return 1;
    }
    int capacity = scene->body_capacity > 0 ? 2 * scene->body_capacity : 64;
    while (capacity < needed) {
        capacity *= 2;
    }
    kg_body_def* bodies = realloc(scene->bodies, (size_t)capacity * sizeof *bodies);
    if (!bodies) {
        return 0;
    }
    scene->bodies = bodies;
    size_t* offsets = realloc(scene->name_offsets, (size_t)capacity * sizeof *offsets);
    if (!offsets) {
        return 0;
    }
    scene->name_offsets = offsets;
    int** per_body[] = {&scene->first_extra, &scene->last_extra, &scene->extra_count,
                        &scene->first_chain, &scene->last_chain, &scene->chain_count};
    for (size_t k = 0; k < sizeof per_body / sizeof per_body[0]; ++k) {
        int* grown = realloc(*per_body[k], (size_t)capacity * sizeof *grown);
        if (!grown) {
            return 0;
        }
        *per_body[k] = grown;
    }
    scene->body_capacity = capacity;
    return 1;
}

kg_result kg_scene_add_body(kg_scene* scene, const char* name, const kg_body_def* def)
{
    if (!scene || !def) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_add_body: NULL argument");
    }
    char default_name[32];
    if (!name) {
        snprintf(default_name, sizeof default_name, "body%d", scene->body_count);
        name = default_name;
    }
    kg_result r = kg_check_name(name);
    if (r == KG_OK) {
        r = kg_check_body_def(def);
    }
    if (r != KG_OK) {
        return r;
    }
    int existing = kg_scene_find_body(scene, name);
    if (existing >= 0) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "duplicate name '%s' (body %d has it)", name, existing);
    }
    if (kg_scene_body_room(scene) < 1) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "more than max_bodies (%d) bodies", scene->limits.max_bodies);
    }
    int needed = scene->body_count + 1;
    if (!kg_reserve_bodies(scene, needed) || !kg_name_table_reserve(scene, needed) || !kg_append_name(scene, name)) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_add_body: out of memory");
    }
    scene->bodies[scene->body_count] = *def;
    scene->first_extra[scene->body_count] = -1;
    scene->last_extra[scene->body_count] = -1;
    scene->extra_count[scene->body_count] = 0;
    scene->first_chain[scene->body_count] = -1;
    scene->last_chain[scene->body_count] = -1;
    scene->chain_count[scene->body_count] = 0;
    scene->name_table[kg_name_slot(scene, name)] = scene->body_count + 1;
    scene->body_count++;
    return KG_OK;
}

kg_result kg_scene_add_body_shape(kg_scene* scene, int index, const kg_body_shape_def* def)
{
    if (!scene || !def || index < 0 || index >= scene->body_count) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_add_body_shape: NULL argument or body %d out of range",
                       index);
    }
    if (!kg_grow((void**)&scene->shapes, &scene->shape_capacity, scene->shape_count + 1, sizeof *scene->shapes)) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_add_body_shape: out of memory");
    }
    int at = scene->shape_count++;
    scene->shapes[at].def = *def;
    scene->shapes[at].next = -1;
    if (scene->last_extra[index] >= 0) {
        scene->shapes[scene->last_extra[index]].next = at;
    } else {
        scene->first_extra[index] = at;
    }
    scene->last_extra[index] = at;
    scene->extra_count[index] += 1;
    return KG_OK;
}

int kg_scene_body_shape_count(const kg_scene* scene, int index)
{
    return scene && index >= 0 && index < scene->body_count ? 1 + scene->extra_count[index] : 0;
}

kg_result kg_scene_get_body_shape(const kg_scene* scene, int index, int k, kg_body_shape_def* out)
{
    if (!out || k < 0 || k >= kg_scene_body_shape_count(scene, index)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_get_body_shape: no shape %d of body %d", k, index);
    }
    const kg_body_def* body = &scene->bodies[index];
    if (k == 0) {
        *out = kg_first_shape_def(body);
        return KG_OK;
    }
    int at = scene->first_extra[index];
    for (int step = 1; step < k; ++step) {
        at = scene->shapes[at].next;
    }
    *out = scene->shapes[at].def;
    return KG_OK;
}

/* What kg_create_chain checks, so that a scene holding the chain instantiates: the body
 * may hold one, its material is one a shape may have, its points make a chain. */
static kg_result kg_check_chain(const kg_body_def* body, const kg_chain_def* def)
{
    if (body->type != KG_BODY_STATIC && body->type != KG_BODY_KINEMATIC) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT,
                       "a chain has no mass: only static and kinematic bodies may hold one (use capsules or polygons)");
    }
    kg_body_def material = kg_default_body_def(); /* a static body of no shape: only its material is judged */
    material.type = KG_BODY_STATIC;
    material.friction = def->friction;
    material.restitution = def->restitution;
    KG_TRY(kg_check_body_def(&material));
    return kg_check_chain_points(def->points, def->count, def->loop);
}

kg_result kg_scene_add_body_chain(kg_scene* scene, int index, const kg_chain_def* def)
{
    if (!scene || !def || index < 0 || index >= scene->body_count) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_add_body_chain: NULL argument or body %d out of range",
                       index);
    }
    KG_TRY(kg_check_chain(&scene->bodies[index], def));
    kg_vec2* points = malloc((size_t)def->count * sizeof *points);
    if (!points ||
        !kg_grow((void**)&scene->chains, &scene->chain_capacity, scene->chain_total + 1, sizeof *scene->chains)) {
        free(points);
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_add_body_chain: out of memory");
    }
    memcpy(points, def->points, (size_t)def->count * sizeof *points);
    int at = scene->chain_total++;
    scene->chains[at].def = *def;
    scene->chains[at].def.points = points;
    scene->chains[at].next = -1;
    if (scene->last_chain[index] >= 0) {
        scene->chains[scene->last_chain[index]].next = at;
    } else {
        scene->first_chain[index] = at;
    }
    scene->last_chain[index] = at;
    scene->chain_count[index] += 1;
    return KG_OK;
}

int kg_scene_body_chain_count(const kg_scene* scene, int index)
{
    return scene && index >= 0 && index < scene->body_count ? scene->chain_count[index] : 0;
}

kg_result kg_scene_get_body_chain(const kg_scene* scene, int index, int k, kg_chain_def* out)
{
    if (!out || k < 0 || k >= kg_scene_body_chain_count(scene, index)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_get_body_chain: no chain %d of body %d", k, index);
    }
    int at = scene->first_chain[index];
    for (int step = 0; step < k; ++step) {
        at = scene->chains[at].next;
    }
    *out = scene->chains[at].def;
    return KG_OK;
}

static kg_result kg_check_force(const kg_scene* scene, const kg_scene_force* force)
{
    if (force->type != KG_SCENE_FORCE_GRAVITY && force->type != KG_SCENE_FORCE_WIND) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "unknown force type %d", (int)force->type);
    }
    if (!isfinite(force->vector.x) || !isfinite(force->vector.y) || !isfinite(force->strength) ||
        !isfinite(force->drag) || force->strength < 0.0f || force->drag < 0.0f) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "force needs a finite vector, strength >= 0 and drag >= 0");
    }
    if (force->body_count < 0 || (force->body_count > 0 && !force->body_indices)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "force body list: count %d with %s indices", force->body_count,
                       force->body_indices ? "some" : "no");
    }
    for (int i = 0; i < force->body_count; ++i) {
        int body = force->body_indices[i];
        if (body < 0 || body >= scene->body_count) {
            return kg_fail(KG_ERROR_INVALID_ARGUMENT, "force body %d is not a scene body (the scene has %d)", body,
                           scene->body_count);
        }
    }
    return KG_OK;
}

kg_result kg_scene_add_force(kg_scene* scene, const kg_scene_force* force)
{
    if (!scene || !force) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_add_force: NULL argument");
    }
    kg_result r = kg_check_force(scene, force);
    if (r != KG_OK) {
        return r;
    }
    int* indices = NULL;
    if (force->body_count > 0) {
        indices = malloc((size_t)force->body_count * sizeof *indices);
        if (!indices) {
            return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_add_force: out of memory");
        }
        memcpy(indices, force->body_indices, (size_t)force->body_count * sizeof *indices);
    }
    if (!kg_grow((void**)&scene->forces, &scene->force_capacity, scene->force_count + 1, sizeof *scene->forces)) {
        free(indices);
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_add_force: out of memory");
    }
    kg_scene_force* copy = &scene->forces[scene->force_count++];
    *copy = *force;
    copy->body_indices = indices;
    return KG_OK;
}

/* ---- pivots ---- */

static kg_scene_pivot* kg_find_pivot(const kg_scene* scene, int index)
{
    for (int i = 0; i < scene->pivot_count; ++i) {
        if (scene->pivots[i].body == index) {
            return &scene->pivots[i];
        }
    }
    return NULL;
}

kg_result kg_scene_set_body_pivot(kg_scene* scene, int index, kg_vec2 pivot)
{
    if (!scene || index < 0 || index >= scene->body_count) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_set_body_pivot: no body %d", index);
    }
    if (scene->bodies[index].type != KG_BODY_KINEMATIC) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "only kinematic bodies can turn about a pivot");
    }
    if (!isfinite(pivot.x) || !isfinite(pivot.y)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "pivot must be finite");
    }
    kg_scene_pivot* existing = kg_find_pivot(scene, index);
    if (existing) {
        existing->point = pivot;
        return KG_OK;
    }
    if (!kg_grow((void**)&scene->pivots, &scene->pivot_capacity, scene->pivot_count + 1, sizeof *scene->pivots)) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_set_body_pivot: out of memory");
    }
    scene->pivots[scene->pivot_count++] = (kg_scene_pivot){index, pivot};
    return KG_OK;
}

int kg_scene_body_pivot(const kg_scene* scene, int index, kg_vec2* out)
{
    const kg_scene_pivot* pivot = scene ? kg_find_pivot(scene, index) : NULL;
    if (pivot && out) {
        *out = pivot->point;
    }
    return pivot != NULL;
}

/* ---- tile maps ---- */

/* A copy of count items of size bytes (NULL for none); 0 when out of memory. */
static int kg_copy_items(const void* items, size_t count, size_t size, void** out)
{
    *out = NULL;
    if (!items || count == 0) {
        return 1;
    }
    *out = malloc(count * size);
    if (*out) {
        memcpy(*out, items, count * size);
    }
    return *out != NULL;
}

kg_result kg_scene_add_tilemap(kg_scene* scene, const kg_tilemap_def* def)
{
    if (!scene || !def || !def->shapes || def->shape_count < 1 || def->width < 1 || def->height < 1 ||
        def->layer_count < 1) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_add_tilemap: NULL or empty definition");
    }
    size_t cells = (size_t)def->width * (size_t)def->height * (size_t)def->layer_count;
    kg_scene_tilemap map = {*def, NULL, NULL};
    int copied = kg_copy_items(def->shapes, (size_t)def->shape_count, sizeof *def->shapes, (void**)&map.shapes) &&
                 kg_copy_items(def->tiles, cells, sizeof *def->tiles, (void**)&map.tiles) &&
                 kg_grow((void**)&scene->tilemaps, &scene->tilemap_capacity, scene->tilemap_count + 1,
                         sizeof *scene->tilemaps);
    if (!copied) {
        free(map.shapes);
        free(map.tiles);
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_add_tilemap: out of memory");
    }
    map.def.shapes = map.shapes;
    map.def.tiles = map.tiles;
    scene->tilemaps[scene->tilemap_count++] = map;
    return KG_OK;
}

/* The velocity that carries the centre of mass along the chord of its circle about the
 * pivot in one step. The tangent velocity would move it outwards a little every step. */
static kg_result kg_drive_pivot(kg_world* world, kg_body body, kg_vec2 pivot, float dt)
{
    kg_body_state state;
    kg_mass_data mass;
    KG_TRY(kg_body_get_state(world, body, &state));
    KG_TRY(kg_body_get_mass_data(world, body, &mass));
    float c = cosf(state.angle), s = sinf(state.angle);
    kg_vec2 com = {state.position.x + c * mass.center.x - s * mass.center.y,
                   state.position.y + s * mass.center.x + c * mass.center.y};
    float turn = state.angular_velocity * dt;
    float tc = cosf(turn), ts = sinf(turn);
    kg_vec2 r = {com.x - pivot.x, com.y - pivot.y};
    kg_vec2 next = {pivot.x + tc * r.x - ts * r.y, pivot.y + ts * r.x + tc * r.y};
    return kg_body_set_velocity(world, body, (kg_vec2){(next.x - com.x) / dt, (next.y - com.y) / dt});
}

kg_result kg_scene_step(const kg_scene* scene, kg_world* world, const kg_body* bodies, float dt)
{
    if (!scene || !world || (scene->pivot_count > 0 && !bodies)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_step: NULL argument");
    }
    if (!isfinite(dt) || !(dt > 0.0f)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_step: dt must be finite and > 0 (got %g)", (double)dt);
    }
    for (int i = 0; i < scene->pivot_count; ++i) {
        KG_TRY(kg_drive_pivot(world, bodies[scene->pivots[i].body], scene->pivots[i].point, dt));
    }
    return kg_world_step(world, dt);
}

/* ---- instantiating ---- */

static int kg_max_int(int a, int b) { return a > b ? a : b; }

/* Room for the scene: pairs in contact stay below a few per body even in dense piles. */
static kg_world_def kg_fitted_world_def(const kg_scene* scene, const kg_world_def* override_def)
{
    kg_world_def def = override_def ? *override_def : scene->world_def;
    if (scene->state) { /* the capacities of the saved world, which its snapshot needs */
        def.max_bodies = scene->world_def.max_bodies;
        def.max_applicators = scene->world_def.max_applicators;
    }
    def.max_bodies = kg_max_int(def.max_bodies, scene->body_count);
    def.max_contacts = kg_max_int(def.max_contacts, 6 * scene->body_count + 64);
    def.max_applicators = kg_max_int(def.max_applicators, scene->force_count);
    return def;
}

static kg_result kg_create_scene_bodies(const kg_scene* scene, kg_world* world, kg_body* handles)
{
    for (int i = 0; i < scene->body_count; ++i) {
        kg_result r = kg_create_body(world, &scene->bodies[i], &handles[i]);
        for (int at = scene->first_extra[i]; r == KG_OK && at >= 0; at = scene->shapes[at].next) {
            kg_shape_id shape;
            r = kg_create_shape(world, handles[i], &scene->shapes[at].def, &shape);
        }
        for (int at = scene->first_chain[i]; r == KG_OK && at >= 0; at = scene->chains[at].next) {
            r = kg_create_chain(world, handles[i], &scene->chains[at].def, NULL);
        }
        if (r != KG_OK) {
            char reason[256];
            snprintf(reason, sizeof reason, "%s", kg_last_error());
            return kg_fail(r, "body %d ('%s'): %s", i, kg_scene_body_name(scene, i), reason);
        }
    }
    return KG_OK;
}

static kg_result kg_add_scene_force(const kg_scene_force* force, kg_world* world, const kg_body* handles)
{
    kg_body* subset = NULL;
    if (force->body_count > 0) {
        subset = malloc((size_t)force->body_count * sizeof *subset);
        if (!subset) {
            return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_instantiate: out of memory");
        }
        for (int i = 0; i < force->body_count; ++i) {
            subset[i] = handles[force->body_indices[i]];
        }
    }
    kg_result r;
    kg_applicator applicator;
    if (force->type == KG_SCENE_FORCE_GRAVITY) {
        r = kg_add_gravity_applicator(world, force->vector, subset, force->body_count, &applicator);
    } else {
        r = kg_add_wind_applicator(world, force->vector, force->strength, force->drag, subset, force->body_count,
                                   &applicator);
    }
    free(subset);
    return r;
}

static kg_result kg_create_scene_tilemaps(const kg_scene* scene, kg_world* world)
{
    for (int i = 0; i < scene->tilemap_count; ++i) {
        kg_tilemap map;
        kg_result r = kg_create_tilemap(world, &scene->tilemaps[i].def, &map);
        if (r != KG_OK) {
            char reason[256];
            snprintf(reason, sizeof reason, "%s", kg_last_error());
            return kg_fail(r, "tile map %d: %s", i, reason);
        }
    }
    return KG_OK;
}

static kg_result kg_fill_world(const kg_scene* scene, kg_world* world, kg_body* handles)
{
    KG_TRY(kg_create_scene_bodies(scene, world, handles));
    for (int i = 0; i < scene->force_count; ++i) {
        KG_TRY(kg_add_scene_force(&scene->forces[i], world, handles));
    }
    KG_TRY(kg_create_scene_tilemaps(scene, world));
    return kg_create_scene_joints(scene, world, handles);
}

kg_result kg_scene_add_joint(kg_scene* scene, const kg_scene_joint* joint)
{
    if (!scene || !joint) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_add_joint: NULL argument");
    }
    if (joint->body_b < 0 || joint->body_b >= scene->body_count || joint->body_a < -1 ||
        joint->body_a >= scene->body_count) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_add_joint: body index out of range (a %d, b %d, %d bodies)",
                       joint->body_a, joint->body_b, scene->body_count);
    }
    kg_json_path path = kg_joint_call_path("kg_scene_add_joint", scene, scene->joint_count, joint);
    KG_TRY(kg_check_joint_entry(NULL, &path, scene, joint));
    if (!kg_grow((void**)&scene->joints, &scene->joint_capacity, scene->joint_count + 1, sizeof *scene->joints)) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_add_joint: out of memory");
    }
    scene->joints[scene->joint_count++] = *joint;
    return KG_OK;
}

int kg_scene_joint_count(const kg_scene* scene) { return scene ? scene->joint_count : 0; }

const kg_scene_joint* kg_scene_get_joint(const kg_scene* scene, int index)
{
    return scene && index >= 0 && index < scene->joint_count ? &scene->joints[index] : NULL;
}

kg_result kg_scene_instantiate(const kg_scene* scene, const kg_world_def* override_def, kg_world** out_world,
                               kg_body* out_bodies)
{
    if (!scene || !out_world) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_instantiate: NULL argument");
    }
    *out_world = NULL;
    kg_body* handles = out_bodies;
    if (!handles) {
        handles = malloc((size_t)kg_max_int(scene->body_count, 1) * sizeof *handles);
        if (!handles) {
            return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_instantiate: out of memory");
        }
    }
    kg_world_def def = kg_fitted_world_def(scene, override_def);
    kg_world* world = NULL;
    kg_result r = kg_create_world(&def, &world);
    if (r == KG_OK) {
        r = kg_fill_world(scene, world, handles);
    }
    if (r == KG_OK) {
        r = kg_scene_restore_state(scene, world, handles);
    }
    if (handles != out_bodies) {
        free(handles);
    }
    if (r != KG_OK) {
        if (world) {
            kg_destroy_world(world);
        }
        return r;
    }
    *out_world = world;
    return KG_OK;
}

/* ---- a saved world's state (io/scene_state.h) ---- */

kg_result kg_scene_set_state(kg_scene* scene, const void* snapshot, size_t size)
{
    unsigned char* copy = size > 0 ? malloc(size) : NULL;
    if (size > 0 && !copy) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot keep a snapshot of %zu bytes in the scene", size);
    }
    if (size > 0) {
        memcpy(copy, snapshot, size);
    }
    free(scene->state);
    scene->state = copy;
    scene->state_size = size;
    return KG_OK;
}

const void* kg_scene_get_state(const kg_scene* scene, size_t* size)
{
    *size = scene->state_size;
    return scene->state;
}
