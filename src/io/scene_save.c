/* Saving worlds as scenes (include/kgyro/scene.h, "Saved worlds"): kg_scene_from_world
 * describes a world's bodies and built-in forces as a scene and keeps the world's
 * snapshot in it; kg_scene_save_file writes a scene as a JSON file that kg_scene_load_file
 * reads back, every float as "%.9g" (which gives back the same float: 9 significant
 * digits tell any two floats apart, and the parser's double rounds to the float it came
 * from), the snapshot as base64 in "state" (io/scene_state.c). */
#include "kgyro/scene.h"
#include "kgyro/force.h"
#include "kgyro/snapshot.h"

#include "core/body_pool.h"
#include "core/error.h"
#include "core/world.h"
#include "collide/tilemap.h"
#include "io/json_util.h"
#include "io/scene_state.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- from a world ---- */

/* Body slot i's definition as the world has it now: state, shape, material, filter. */
static kg_body_def kg_def_of(const kg_world* world, const kg_body_pool* p, kg_body body)
{
    int i = (int)body.index;
    kg_body_def def = kg_default_body_def();
    kg_body_state s;
    kg_body_get_type(world, body, &def.type);
    kg_body_get_state(world, body, &s);
    def.position = s.position;
    def.angle = def.type == KG_BODY_PARTICLE ? 0.0f : s.angle;
    def.velocity = s.velocity;
    def.angular_velocity = def.type == KG_BODY_PARTICLE ? 0.0f : s.angular_velocity;
    if (kg_body_get_shape(world, body, &def.shape) != KG_OK) {
        memset(&def.shape, 0, sizeof def.shape);
    }
    kg_mass_data md;
    int massive = def.type == KG_BODY_DYNAMIC || def.type == KG_BODY_PARTICLE;
    if (massive && kg_body_get_mass_data(world, body, &md) == KG_OK && md.mass > 0.0f) {
        def.mass = md.mass;
    }
    def.friction = p->friction[i];
    def.restitution = p->restitution[i];
    def.linear_damping = p->linear_damping[i];
    def.angular_damping = p->angular_damping[i];
    def.category = p->category[i];
    def.mask = p->mask[i];
    def.fixed_rotation = (p->flags[i] & KG_FLAG_FIXED_ROTATION) != 0u;
    def.bullet = (p->flags[i] & KG_FLAG_BULLET) != 0u;
    return def;
}

/* The scene index of each body slot (-1: none), from the scene's bodies in slot order. */
static int* kg_slot_indices(const kg_world* world, const kg_body* bodies, int count)
{
    int slots = kg_world_get_def(world)->max_bodies;
    int* index = malloc((size_t)slots * sizeof *index);
    for (int i = 0; index && i < slots; ++i) {
        index[i] = -1;
    }
    for (int k = 0; index && k < count; ++k) {
        index[bodies[k].index] = k;
    }
    return index;
}

/* The world's built-in applicators (gravity, wind) as scene forces, in slot order. */
static kg_result kg_add_world_forces(const kg_world* world, const kg_body* bodies, int count, kg_scene* scene)
{
    int* index = kg_slot_indices(world, bodies, count);
    int* listed = malloc((size_t)(count > 0 ? count : 1) * sizeof *listed);
    kg_result r = index && listed ? KG_OK : kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_from_world: out of memory");
    for (int a = 0; r == KG_OK && a < world->def.max_applicators; ++a) {
        const kg_applicator_slot* slot = &world->applicators[a];
        if (slot->kind != KG_APPLICATOR_GRAVITY && slot->kind != KG_APPLICATOR_WIND) {
            continue;
        }
        int n = 0;
        for (int k = 0; k < slot->body_count; ++k) {
            kg_body b = slot->bodies[k];
            if (kg_body_is_valid(world, b) && index[b.index] >= 0) {
                listed[n++] = index[b.index];
            }
        }
        kg_scene_force f = {slot->kind == KG_APPLICATOR_GRAVITY ? KG_SCENE_FORCE_GRAVITY : KG_SCENE_FORCE_WIND,
                            slot->vector, slot->strength, slot->drag, n, listed};
        r = slot->body_count > 0 && n == 0 ? KG_OK : kg_scene_add_force(scene, &f); /* every body it named is gone */
    }
    free(index);
    free(listed);
    return r;
}

/* Map's shapes and tiles (cells as they are now, edits included) into the scene. */
static kg_result kg_add_world_map(const kg_world* world, kg_tilemap map, kg_scene* scene)
{
    kg_tilemap_def def;
    KG_TRY(kg_tilemap_get_def(world, map, &def));
    size_t cells = (size_t)def.width * (size_t)def.height * (size_t)def.layer_count;
    kg_tile_shape* shapes = calloc((size_t)def.shape_count, sizeof *shapes);
    uint16_t* tiles = calloc(cells, sizeof *tiles);
    kg_result r = shapes && tiles ? KG_OK : kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_from_world: out of memory");
    for (int id = 0; r == KG_OK && id < def.shape_count; ++id) {
        r = kg_tilemap_get_shape(world, map, id, &shapes[id]);
    }
    for (size_t k = 0; r == KG_OK && k < cells; ++k) {
        int x = (int)(k % (size_t)def.width), y = (int)(k / (size_t)def.width % (size_t)def.height);
        int layer = (int)(k / ((size_t)def.width * (size_t)def.height)), id = 0;
        r = kg_tilemap_get_tile(world, map, layer, x, y, &id);
        tiles[k] = (uint16_t)id;
    }
    def.shapes = shapes;
    def.tiles = tiles;
    def.user_data = NULL;
    if (r == KG_OK) {
        r = kg_scene_add_tilemap(scene, &def);
    }
    free(shapes);
    free(tiles);
    return r;
}

static kg_result kg_add_world_maps(const kg_world* world, kg_scene* scene)
{
    int count = kg_world_tilemap_count(world);
    kg_tilemap* maps = malloc((size_t)(count > 0 ? count : 1) * sizeof *maps);
    kg_result r = maps ? kg_world_get_tilemaps(world, maps, count, &count)
                       : kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_from_world: out of memory");
    for (int i = 0; r == KG_OK && i < count; ++i) {
        r = kg_add_world_map(world, maps[i], scene);
    }
    free(maps);
    return r;
}

static kg_result kg_add_world_state(kg_world* world, kg_scene* scene)
{
    size_t size = 0, written = 0;
    KG_TRY(kg_world_snapshot_size(world, &size));
    void* buffer = malloc(size);
    if (!buffer) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_from_world: no room for a snapshot of %zu bytes", size);
    }
    kg_result r = kg_world_snapshot(world, buffer, size, &written);
    if (r == KG_OK) {
        r = kg_scene_set_state(scene, buffer, written);
    }
    free(buffer);
    return r;
}

/* Whether a body of the original scene is called name (names: per slot, slots of them). */
static int kg_name_taken(const char* const* names, int slots, const char* name)
{
    for (int i = 0; i < slots; ++i) {
        if (names[i] && strcmp(names[i], name) == 0) {
            return 1;
        }
    }
    return 0;
}

/* Body k's name: the original scene's (names: per slot, NULL where none), else body<k>,
 * made unique with a suffix when the original scene already uses it. */
static void kg_name_of(const kg_scene* scene, const char* const* names, kg_body body, int k, char* out, size_t size)
{
    if (names && names[body.index]) {
        snprintf(out, size, "%s", names[body.index]);
        return;
    }
    snprintf(out, size, "body%d", k);
    int slots = kg_scene_world_def((kg_scene*)scene)->max_bodies;
    for (int n = 1; kg_scene_find_body(scene, out) >= 0 || (names && kg_name_taken(names, slots, out)); ++n) {
        snprintf(out, size, "body%d_%d", k, n);
    }
}

static kg_result kg_fill_scene(kg_world* world, kg_scene* scene, const char* const* names)
{
    *kg_scene_world_def(scene) = *kg_world_get_def(world);
    if (world->last_dt > 0.0f) {
        KG_TRY(kg_scene_set_dt(scene, world->last_dt));
    }
    int count = kg_world_body_count(world);
    kg_body* bodies = malloc((size_t)(count > 0 ? count : 1) * sizeof *bodies);
    if (!bodies) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_from_world: out of memory");
    }
    kg_result r = kg_world_get_bodies(world, bodies, count, &count);
    const kg_body_pool* p = kg_world_read_pool(world);
    for (int k = 0; r == KG_OK && k < count; ++k) {
        kg_body_def def = kg_def_of(world, p, bodies[k]);
        char name[80];
        kg_name_of(scene, names, bodies[k], k, name, sizeof name);
        r = kg_scene_add_body(scene, name, &def);
    }
    if (r == KG_OK) {
        r = kg_add_world_forces(world, bodies, count, scene);
    }
    if (r == KG_OK) {
        r = kg_add_world_maps(world, scene);
    }
    free(bodies);
    return r == KG_OK ? kg_add_world_state(world, scene) : r;
}

/* The scene made from world, its bodies named from names (per slot, or NULL). */
static kg_result kg_scene_of_world(const kg_world* world, const char* const* names, kg_scene** out)
{
    *out = NULL;
    if (kg_world_refuses(world, "kg_scene_from_world", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    kg_scene* scene = NULL;
    KG_TRY(kg_scene_create(&scene));
    kg_result r = kg_fill_scene((kg_world*)world, scene, names);
    if (r != KG_OK) {
        kg_scene_destroy(scene);
        return r;
    }
    *out = scene;
    return KG_OK;
}

kg_result kg_scene_from_world(const kg_world* world, kg_scene** out)
{
    if (!world || !out) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_from_world: NULL argument");
    }
    return kg_scene_of_world(world, NULL, out);
}

kg_result kg_scene_from_world_named(const kg_world* world, const kg_scene* names_from, const kg_body* bodies,
                                    kg_scene** out)
{
    if (!world || !names_from || !bodies || !out) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_from_world_named: NULL argument");
    }
    int slots = kg_world_get_def(world)->max_bodies;
    const char** names = calloc((size_t)slots, sizeof *names);
    if (!names) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_from_world_named: out of memory");
    }
    for (int i = 0; i < kg_scene_body_count(names_from); ++i) {
        if (kg_body_is_valid(world, bodies[i])) {
            names[bodies[i].index] = kg_scene_body_name(names_from, i);
        }
    }
    kg_result r = kg_scene_of_world(world, names, out);
    free(names);
    return r;
}

/* ---- writing JSON ---- */

/* A float as "%.9g" (NULL: out of memory). */
static cJSON* kg_float_json(float v)
{
    char text[32];
    snprintf(text, sizeof text, "%.9g", (double)v);
    return cJSON_CreateRaw(text);
}

static cJSON* kg_vec2_json(kg_vec2 v)
{
    cJSON* a = cJSON_CreateArray();
    if (a && (!cJSON_AddItemToArray(a, kg_float_json(v.x)) || !cJSON_AddItemToArray(a, kg_float_json(v.y)))) {
        cJSON_Delete(a);
        return NULL;
    }
    return a;
}

/* Adds key: item to object; 0 when item is NULL (out of memory). */
static int kg_json_add(cJSON* object, const char* key, cJSON* item)
{
    return item && cJSON_AddItemToObject(object, key, item);
}

static int kg_json_add_float(cJSON* object, const char* key, float v)
{
    return kg_json_add(object, key, kg_float_json(v));
}

static int kg_json_add_vec2(cJSON* object, const char* key, kg_vec2 v)
{
    return kg_json_add(object, key, kg_vec2_json(v));
}

static cJSON* kg_shape_json(const kg_shape_def* s)
{
    cJSON* o = cJSON_CreateObject();
    int ok = o != NULL;
    static const char* const names[] = {"none", "circle", "polygon", "capsule", "segment"};
    ok = ok && cJSON_AddStringToObject(o, "type", names[s->type]);
    if (s->type == KG_SHAPE_CIRCLE) {
        ok = ok && kg_json_add_float(o, "radius", s->radius) && kg_json_add_vec2(o, "center", s->center);
    } else if (s->type == KG_SHAPE_POLYGON) {
        cJSON* list = cJSON_CreateArray();
        ok = ok && kg_json_add(o, "vertices", list);
        for (int k = 0; ok && k < s->count; ++k) {
            ok = cJSON_AddItemToArray(list, kg_vec2_json(s->vertices[k]));
        }
    } else {
        int capsule = s->type == KG_SHAPE_CAPSULE;
        ok = ok && kg_json_add_vec2(o, capsule ? "center1" : "point1", s->vertices[0]) &&
             kg_json_add_vec2(o, capsule ? "center2" : "point2", s->vertices[1]) &&
             (!capsule || kg_json_add_float(o, "radius", s->radius));
    }
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

static int kg_add_material(cJSON* o, const kg_body_def* d)
{
    return (d->mass > 0.0f ? kg_json_add_float(o, "mass", d->mass) : kg_json_add_float(o, "density", d->density)) &&
           kg_json_add_float(o, "friction", d->friction) && kg_json_add_float(o, "restitution", d->restitution) &&
           kg_json_add_float(o, "linear_damping", d->linear_damping) &&
           kg_json_add_float(o, "angular_damping", d->angular_damping) &&
           cJSON_AddNumberToObject(o, "category", (double)d->category) &&
           cJSON_AddNumberToObject(o, "mask", (double)d->mask) &&
           (!d->fixed_rotation || cJSON_AddBoolToObject(o, "fixed_rotation", 1)) &&
           (!d->bullet || cJSON_AddBoolToObject(o, "bullet", 1));
}

static cJSON* kg_body_json(const kg_scene* scene, int i)
{
    static const char* const types[] = {"static", "dynamic", "kinematic", "particle"};
    const kg_body_def* d = kg_scene_body_def(scene, i);
    cJSON* o = cJSON_CreateObject();
    int rotates = d->type != KG_BODY_PARTICLE;
    int ok = o && cJSON_AddStringToObject(o, "name", kg_scene_body_name(scene, i)) &&
             cJSON_AddStringToObject(o, "type", types[d->type]) && kg_json_add_vec2(o, "position", d->position) &&
             (!rotates || kg_json_add_float(o, "angle", d->angle)) && kg_json_add_vec2(o, "velocity", d->velocity) &&
             (!rotates || kg_json_add_float(o, "angular_velocity", d->angular_velocity)) &&
             (d->shape.type == KG_SHAPE_NONE || kg_json_add(o, "shape", kg_shape_json(&d->shape))) &&
             kg_add_material(o, d);
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

static cJSON* kg_force_json(const kg_scene* scene, const kg_scene_force* f)
{
    cJSON* o = cJSON_CreateObject();
    int gravity = f->type == KG_SCENE_FORCE_GRAVITY;
    int ok = o && cJSON_AddStringToObject(o, "type", gravity ? "gravity" : "wind") &&
             kg_json_add_vec2(o, gravity ? "acceleration" : "direction", f->vector) &&
             (gravity || (kg_json_add_float(o, "strength", f->strength) && kg_json_add_float(o, "drag", f->drag)));
    cJSON* list = ok && f->body_count > 0 ? cJSON_CreateArray() : NULL;
    ok = ok && (f->body_count == 0 || kg_json_add(o, "bodies", list));
    for (int k = 0; ok && k < f->body_count; ++k) {
        ok = cJSON_AddItemToArray(list, cJSON_CreateString(kg_scene_body_name(scene, f->body_indices[k])));
    }
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

/* The legend's characters, one per tile id from 1 (docs/scene-format.md: any but ' ' and
 * '.'; '"' and '\\' left out to keep the rows readable). */
static const char kLegend[] = "#ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789!$%&'()*+,-/:;<=>?@[]^_`{|}~";
#define KG_LEGEND_SIZE ((int)sizeof kLegend - 1)

/* The legend character of each tile id (' ' for an empty shape: the file's rows have no
 * other empty character, so empty ids past 0 become 0), into chars (shape_count); 0 when
 * the map has more solid shapes than the legend has characters. */
static int kg_legend_of(const kg_tilemap_def* map, char* chars)
{
    int next = 0;
    for (int id = 0; id < map->shape_count; ++id) {
        int empty = id == 0 || map->shapes[id].type == KG_TILE_SHAPE_EMPTY;
        if (!empty && next == KG_LEGEND_SIZE) {
            return 0;
        }
        chars[id] = empty ? ' ' : kLegend[next++];
    }
    return 1;
}

/* Whether the file's legend can name map's tile shapes. */
static int kg_map_writable(const kg_tilemap_def* map)
{
    char* chars = malloc((size_t)map->shape_count);
    int ok = chars && kg_legend_of(map, chars);
    free(chars);
    return ok;
}

static cJSON* kg_tile_shape_json(const kg_tile_shape* t)
{
    cJSON* o = cJSON_CreateObject();
    int ok = o != NULL;
    if (t->type == KG_TILE_SHAPE_CIRCLE) {
        cJSON* circle = cJSON_CreateObject();
        ok = ok && kg_json_add(o, "circle", circle) && kg_json_add_vec2(circle, "center", t->center) &&
             kg_json_add_float(circle, "radius", t->radius);
    } else {
        cJSON* list = cJSON_CreateArray();
        ok = ok && kg_json_add(o, "polygon", list) && cJSON_AddBoolToObject(o, "one_way", t->one_way != 0);
        for (int k = 0; ok && k < t->count; ++k) {
            ok = cJSON_AddItemToArray(list, kg_vec2_json(t->vertices[k]));
        }
    }
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

/* One layer's rows, top row first, a legend character per cell (' ' for id 0). */
static cJSON* kg_layer_json(const kg_tilemap_def* map, const char* chars, int layer)
{
    cJSON* rows = cJSON_CreateArray();
    char* row = malloc((size_t)map->width + 1);
    int ok = rows && row;
    for (int y = map->height - 1; ok && y >= 0; --y) {
        for (int x = 0; x < map->width; ++x) {
            size_t cell = ((size_t)layer * (size_t)map->height + (size_t)y) * (size_t)map->width + (size_t)x;
            row[x] = map->tiles ? chars[map->tiles[cell]] : ' ';
        }
        row[map->width] = '\0';
        ok = cJSON_AddItemToArray(rows, cJSON_CreateString(row));
    }
    free(row);
    if (!ok) {
        cJSON_Delete(rows);
        return NULL;
    }
    return rows;
}

/* The legend: each solid tile shape under its character. */
static int kg_add_legend(cJSON* legend, const kg_tilemap_def* map, const char* chars)
{
    int ok = 1;
    for (int id = 1; ok && id < map->shape_count; ++id) {
        char key[2] = {chars[id], '\0'};
        ok = chars[id] == ' ' || kg_json_add(legend, key, kg_tile_shape_json(&map->shapes[id]));
    }
    return ok;
}

static cJSON* kg_tilemap_json(const kg_tilemap_def* map)
{
    char* chars = malloc((size_t)map->shape_count);
    cJSON* o = chars && kg_legend_of(map, chars) ? cJSON_CreateObject() : NULL;
    int ok = o && kg_json_add(o, "origin", kg_vec2_json(map->origin)) &&
             kg_json_add(o, "tile_size", kg_vec2_json(map->tile_size)) &&
             kg_json_add_float(o, "friction", map->friction) && kg_json_add_float(o, "restitution", map->restitution);
    cJSON* legend = ok ? cJSON_CreateObject() : NULL;
    ok = ok && kg_json_add(o, "tiles", legend) && kg_add_legend(legend, map, chars);
    cJSON* layers = ok ? cJSON_CreateArray() : NULL;
    ok = ok && kg_json_add(o, "layers", layers);
    for (int layer = 0; ok && layer < map->layer_count; ++layer) {
        ok = cJSON_AddItemToArray(layers, kg_layer_json(map, chars, layer));
    }
    free(chars);
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

/* The scene's tile maps the legend can name (with a state, the others come back from it). */
static int kg_add_tilemaps(cJSON* root, const kg_scene* scene)
{
    cJSON* maps = cJSON_CreateArray();
    int ok = kg_json_add(root, "tilemap", maps);
    for (int i = 0; ok && i < kg_scene_tilemap_count(scene); ++i) {
        const kg_tilemap_def* map = kg_scene_get_tilemap(scene, i);
        ok = !kg_map_writable(map) || cJSON_AddItemToArray(maps, kg_tilemap_json(map));
    }
    return ok;
}

static int kg_add_settings(cJSON* root, kg_scene* scene)
{
    const kg_world_def* def = kg_scene_world_def(scene);
    return cJSON_AddStringToObject(root, "description", "saved by kg_scene_save_file") &&
           kg_json_add_vec2(root, "gravity", def->gravity) && kg_json_add_float(root, "dt", kg_scene_dt(scene)) &&
           cJSON_AddNumberToObject(root, "steps", kg_scene_steps(scene)) &&
           cJSON_AddNumberToObject(root, "substeps", def->substeps) &&
           cJSON_AddBoolToObject(root, "sleep", def->enable_sleep != 0) &&
           cJSON_AddBoolToObject(root, "continuous", def->enable_continuous != 0);
}

static cJSON* kg_scene_json(const kg_scene* scene)
{
    cJSON* root = cJSON_CreateObject();
    cJSON* bodies = cJSON_CreateArray();
    cJSON* forces = cJSON_CreateArray();
    int ok = root && kg_add_settings(root, (kg_scene*)scene) && kg_json_add(root, "bodies", bodies);
    bodies = ok ? bodies : (cJSON_Delete(bodies), NULL);
    ok = ok && kg_json_add(root, "forces", forces);
    forces = ok ? forces : (cJSON_Delete(forces), NULL);
    for (int i = 0; ok && i < kg_scene_body_count(scene); ++i) {
        ok = cJSON_AddItemToArray(bodies, kg_body_json(scene, i));
    }
    for (int i = 0; ok && i < kg_scene_force_count(scene); ++i) {
        ok = cJSON_AddItemToArray(forces, kg_force_json(scene, kg_scene_get_force(scene, i)));
    }
    if (ok && kg_scene_tilemap_count(scene) > 0) {
        ok = kg_add_tilemaps(root, scene);
    }
    size_t state_size = 0;
    if (ok && kg_scene_get_state(scene, &state_size)) {
        ok = kg_json_add(root, "state", kg_scene_state_json(scene));
    }
    if (!ok) {
        cJSON_Delete(root);
        return NULL;
    }
    return root;
}

/* What a scene file cannot say yet; KG_OK when the scene has none of it, or holds a
 * state (which carries all of it). */
static kg_result kg_check_writable(const kg_scene* scene)
{
    size_t size = 0;
    if (kg_scene_get_state(scene, &size)) {
        return KG_OK;
    }
    for (int i = 0; i < kg_scene_body_count(scene); ++i) {
        if (kg_scene_body_shape_count(scene, i) > 1 || kg_scene_body_chain_count(scene, i) > 0 ||
            kg_scene_body_pivot(scene, i, NULL)) {
            return kg_fail(KG_ERROR_UNSUPPORTED, "kg_scene_save_file: body %d ('%s') has several shapes, a chain or "
                           "a pivot, which the writer does not write yet", i, kg_scene_body_name(scene, i));
        }
    }
    for (int i = 0; i < kg_scene_tilemap_count(scene); ++i) {
        if (!kg_map_writable(kg_scene_get_tilemap(scene, i))) {
            return kg_fail(KG_ERROR_UNSUPPORTED, "kg_scene_save_file: tile map %d has more than %d solid tile shapes, "
                           "which a scene file's legend cannot name", i, KG_LEGEND_SIZE);
        }
    }
    return KG_OK;
}

kg_result kg_scene_save_file(const kg_scene* scene, const char* path)
{
    if (!scene || !path) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_save_file: NULL argument");
    }
    KG_TRY(kg_check_writable(scene));
    cJSON* root = kg_scene_json(scene);
    char* text = root ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    if (!text) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_save_file: out of memory");
    }
    FILE* f = fopen(path, "wb");
    size_t length = strlen(text);
    int written = f && fwrite(text, 1, length, f) == length && fputc('\n', f) != EOF;
    written = (f && fclose(f) == 0) && written;
    free(text);
    if (!written) {
        return kg_json_fail_message(KG_ERROR_IO, "%s: cannot write the scene", path);
    }
    return KG_OK;
}
