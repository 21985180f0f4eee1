/* Saving worlds as scenes (include/kgyro/scene.h, "Saved worlds"): kg_scene_from_world
 * describes a world's bodies (every shape, chains), built-in forces, tile maps and joints
 * as a scene and keeps the world's snapshot in it; kg_scene_save_file writes a scene as a JSON file that kg_scene_load_file
 * reads back, every float as "%.9g" (which gives back the same float: 9 significant
 * digits tell any two floats apart, and the parser's double rounds to the float it came
 * from), the snapshot as base64 in "state" (io/scene_state.c). */
#include "kgyro/scene.h"
#include "kgyro/force.h"
#include "kgyro/snapshot.h"

#include "core/body_pool.h"
#include "core/error.h"
#include "core/world.h"
#include "core/joint.h"
#include "core/shape_pool.h"
#include "collide/chain.h"
#include "collide/tilemap.h"
#include "io/json_util.h"
#include "io/scene_joints.h"
#include "io/scene_state.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- from a world ---- */

/* Whether shape slot s of world is a segment of a chain. */
static int kg_is_chain_shape(const kg_world* world, kg_shape_id shape)
{
    return kg_is_chain_segment(kg_shape_geometry(&world->bodies, &world->shapes, shape.index));
}

/* The first of shapes that is not a chain segment (dense: and has a density > 0), or -1. */
static int kg_first_of(const kg_world* world, const kg_shape_id* shapes, int count, int dense)
{
    for (int k = 0; k < count; ++k) {
        kg_body_shape_def def;
        int solid = !kg_is_chain_shape(world, shapes[k]);
        if (solid && (!dense || (kg_shape_get_def(world, shapes[k], &def) == KG_OK && def.density > 0.0f))) {
            return k;
        }
    }
    return -1;
}

/* The shape that becomes the body def's own, or -1: the first that is not a chain segment,
 * on a moving body the first of those with a density > 0 if any (the body def's density
 * then gives the mass of a compound body, which a file cannot give a mass). */
static int kg_first_solid(const kg_world* world, kg_body body, const kg_shape_id* shapes, int count)
{
    kg_body_type type = KG_BODY_STATIC;
    kg_body_get_type(world, body, &type);
    int dense = type == KG_BODY_DYNAMIC || type == KG_BODY_PARTICLE ? kg_first_of(world, shapes, count, 1) : -1;
    return dense >= 0 ? dense : kg_first_of(world, shapes, count, 0);
}

/* Body slot i's definition as the world has it now: state, own shape (kg_first_solid) with
 * its material, filter and sensor flag, mass (of a body of one shape, or of one none of
 * whose shapes has a density: a compound body's follows from its shapes' densities). */
static kg_body_def kg_def_of(const kg_world* world, const kg_body_pool* p, kg_body body, const kg_shape_id* shapes,
                             int count)
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
    def.friction = p->friction[i];
    def.restitution = p->restitution[i];
    def.category = p->category[i];
    def.mask = p->mask[i];
    int first = kg_first_solid(world, body, shapes, count);
    kg_body_shape_def shape;
    if (first >= 0 && kg_shape_get_def(world, shapes[first], &shape) == KG_OK) {
        def.shape = shape.geometry;
        def.density = shape.density;
        def.friction = shape.friction;
        def.restitution = shape.restitution;
        def.category = shape.category;
        def.mask = shape.mask;
        def.is_sensor = shape.is_sensor;
    }
    kg_mass_data md;
    int massive = def.type == KG_BODY_DYNAMIC || def.type == KG_BODY_PARTICLE;
    int mass_needed = massive && (count <= 1 || !(def.density > 0.0f));
    if (mass_needed && kg_body_get_mass_data(world, body, &md) == KG_OK && md.mass > 0.0f) {
        def.mass = md.mass;
    }
    def.linear_damping = p->linear_damping[i];
    def.angular_damping = p->angular_damping[i];
    def.fixed_rotation = (p->flags[i] & KG_FLAG_FIXED_ROTATION) != 0u;
    def.bullet = (p->flags[i] & KG_FLAG_BULLET) != 0u;
    return def;
}

/* Whether chain segment b goes on from segment a (b's start and ghosts are a's points). */
static int kg_chain_goes_on(const kg_shape* a, const kg_shape* b)
{
    return (a->chain & KG_CHAIN_GHOST2) && (b->chain & KG_CHAIN_GHOST1) &&
           memcmp(&a->vertices[1], &b->vertices[0], sizeof(kg_vec2)) == 0 &&
           memcmp(&a->vertices[3], &b->vertices[1], sizeof(kg_vec2)) == 0 &&
           memcmp(&b->vertices[2], &a->vertices[0], sizeof(kg_vec2)) == 0;
}

/* The chain of segments [0, count) (each going on from the one before) into scene body
 * index: a loop when the last goes on into the first, else open. Material: the first
 * segment's. A chain of which a segment was destroyed comes out as the pieces left, their
 * cut ends free (kg_add_world_runs). */
static kg_result kg_add_world_chain(const kg_world* world, const kg_shape_id* segments, int count, kg_scene* scene,
                                    int index)
{
    const kg_shape* first = kg_shape_geometry(&world->bodies, &world->shapes, segments[0].index);
    const kg_shape* last = kg_shape_geometry(&world->bodies, &world->shapes, segments[count - 1].index);
    int loop = count >= 3 && kg_chain_goes_on(last, first);
    kg_vec2* points = malloc((size_t)(count + 1) * sizeof *points);
    if (!points) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_from_world: out of memory");
    }
    for (int k = 0; k < count; ++k) {
        points[k] = kg_shape_geometry(&world->bodies, &world->shapes, segments[k].index)->vertices[0];
    }
    points[count] = last->vertices[1];
    kg_body_shape_def material;
    kg_result r = kg_shape_get_def(world, segments[0], &material);
    kg_chain_def def = kg_default_chain_def();
    def.points = points;
    def.count = loop ? count : count + 1;
    def.loop = loop;
    if (r == KG_OK) {
        def.friction = material.friction;
        def.restitution = material.restitution;
        def.category = material.category;
        def.mask = material.mask;
        r = kg_scene_add_body_chain(scene, index, &def);
    }
    free(points);
    return r;
}

/* Whether the run of segments starting at a goes on from the one ending at b (b: one past
 * its last). */
static int kg_run_goes_on(const kg_world* world, const kg_shape_id* segments, int end_b, int a)
{
    return kg_chain_goes_on(kg_shape_geometry(&world->bodies, &world->shapes, segments[end_b - 1].index),
                            kg_shape_geometry(&world->bodies, &world->shapes, segments[a].index));
}

/* The chains of segments (count, in the world's order) into scene body index, run by run
 * (each segment going on from the one before; starts: each run's first, then count). A
 * loop with a segment destroyed leaves two runs, the one after the gap going on into the
 * one before it: they are joined, as the one open chain the loop has become. */
static kg_result kg_add_world_runs(const kg_world* world, const kg_shape_id* segments, const int* starts, int runs,
                                   kg_shape_id* chain, int* used, kg_scene* scene, int index)
{
    kg_result r = KG_OK;
    for (int i = 0; r == KG_OK && i < runs; ++i) {
        if (used[i]) {
            continue;
        }
        int before = -1, length = 0;
        for (int j = i + 1; before < 0 && j < runs; ++j) {
            before = !used[j] && kg_run_goes_on(world, segments, starts[j + 1], starts[i]) ? j : -1;
        }
        if (before >= 0) {
            used[before] = 1;
            for (int k = starts[before]; k < starts[before + 1]; ++k) {
                chain[length++] = segments[k];
            }
        }
        for (int k = starts[i]; k < starts[i + 1]; ++k) {
            chain[length++] = segments[k];
        }
        r = kg_add_world_chain(world, chain, length, scene, index);
    }
    return r;
}

/* The body's chain segments (among its count shapes) into scene body index as chains. */
static kg_result kg_add_world_chains(const kg_world* world, const kg_shape_id* shapes, int count, kg_scene* scene,
                                     int index)
{
    size_t n = (size_t)(count > 0 ? count : 1);
    kg_shape_id* segments = malloc(2 * n * sizeof *segments); /* then room for a chain */
    int* starts = calloc(2 * n + 2, sizeof *starts);         /* then each run's used flag */
    kg_result r = segments && starts ? KG_OK : kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_from_world: out of memory");
    int m = 0, runs = 0;
    for (int k = 0; r == KG_OK && k < count; ++k) {
        if (kg_is_chain_shape(world, shapes[k])) {
            segments[m++] = shapes[k];
        }
    }
    for (int k = 0; r == KG_OK && k < m; ++k) {
        if (k == 0 || !kg_run_goes_on(world, segments, k, k)) {
            starts[runs++] = k;
        }
    }
    if (r == KG_OK) {
        starts[runs] = m;
        r = kg_add_world_runs(world, segments, starts, runs, segments + n, starts + n + 1, scene, index);
    }
    free(segments);
    free(starts);
    return r;
}

/* The body's shapes but the body def's own into scene body index (in the world's order),
 * then its chains. */
static kg_result kg_add_world_shapes(const kg_world* world, kg_body body, const kg_shape_id* shapes, int count,
                                     kg_scene* scene, int index)
{
    int first = kg_first_solid(world, body, shapes, count);
    kg_result r = KG_OK;
    for (int k = 0; r == KG_OK && k < count; ++k) {
        kg_body_shape_def def;
        if (k != first && !kg_is_chain_shape(world, shapes[k])) {
            r = kg_shape_get_def(world, shapes[k], &def);
            def.user_data = NULL;
            r = r == KG_OK ? kg_scene_add_body_shape(scene, index, &def) : r;
        }
    }
    return r == KG_OK ? kg_add_world_chains(world, shapes, count, scene, index) : r;
}

/* Adds the live body into scene under name, with all its shapes and chains. */
static kg_result kg_add_world_body(const kg_world* world, kg_body body, const char* name, kg_scene* scene)
{
    const kg_body_pool* p = kg_world_read_pool(world);
    int count = kg_body_shape_count(world, body);
    kg_shape_id* shapes = malloc((size_t)(count > 0 ? count : 1) * sizeof *shapes);
    kg_result r = shapes ? kg_body_get_shapes(world, body, shapes, count, &count)
                         : kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_from_world: out of memory");
    if (r == KG_OK) {
        kg_body_def def = kg_def_of(world, p, body, shapes, count);
        r = kg_scene_add_body(scene, name, &def);
    }
    if (r == KG_OK) {
        r = kg_add_world_shapes(world, body, shapes, count, scene, kg_scene_body_count(scene) - 1);
    } else {
        char why[256];
        snprintf(why, sizeof why, "%s", kg_last_error());
        r = kg_fail(r, "kg_scene_from_world: body '%s': %s", name, why);
    }
    free(shapes);
    return r;
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

/* The world's live joints, in slot order, as scene joints between the scene's bodies
 * (index: the scene index of each body slot), anchors and axes where they are now. */
static kg_result kg_add_world_joints(const kg_world* world, const int* index, kg_scene* scene)
{
    kg_result r = KG_OK;
    for (int slot = 0; r == KG_OK && slot < kg_joints_slots(world); ++slot) {
        kg_joint joint = kg_joint_of_slot(world, (uint32_t)slot);
        kg_joint_type type;
        kg_body a, b;
        if (joint.generation == 0u || kg_joint_get_type(world, joint, &type) != KG_OK) {
            continue;
        }
        kg_scene_joint j;
        kg_scene_joint_init(&j, type);
        r = kg_joint_get_bodies(world, joint, &a, &b);
        if (r != KG_OK) {
            break;
        }
        j.body_a = a.generation == 0u ? -1 : index[a.index];
        j.body_b = index[b.index];
        r = kg_joint_get_world_anchors(world, joint, &j.anchor_a, &j.anchor_b);
        if (r == KG_OK && (type == KG_JOINT_PRISMATIC || type == KG_JOINT_WHEEL)) {
            r = kg_joint_get_world_axis(world, joint, &j.axis);
        }
        switch (type) {
        case KG_JOINT_REVOLUTE: r = r == KG_OK ? kg_revolute_joint_get_def(world, joint, &j.revolute) : r; break;
        case KG_JOINT_DISTANCE: r = r == KG_OK ? kg_distance_joint_get_def(world, joint, &j.distance) : r; break;
        case KG_JOINT_WELD: r = r == KG_OK ? kg_weld_joint_get_def(world, joint, &j.weld) : r; break;
        case KG_JOINT_MOUSE: r = r == KG_OK ? kg_mouse_joint_get_def(world, joint, &j.mouse) : r; break;
        case KG_JOINT_PRISMATIC: r = r == KG_OK ? kg_prismatic_joint_get_def(world, joint, &j.prismatic) : r; break;
        case KG_JOINT_WHEEL: r = r == KG_OK ? kg_wheel_joint_get_def(world, joint, &j.wheel) : r; break;
        default: r = r == KG_OK ? kg_motor_joint_get_def(world, joint, &j.motor) : r; break;
        }
        r = r == KG_OK ? kg_scene_add_joint(scene, &j) : r;
    }
    return r;
}

/* The bodies' pivots in the scene the world was made from (origin: per body slot, its
 * index there or -1). */
static kg_result kg_add_pivots(const kg_scene* names_from, const int* origin, const kg_body* bodies, int count,
                               kg_scene* scene)
{
    kg_vec2 pivot;
    for (int k = 0; names_from && k < count; ++k) {
        int from = origin[bodies[k].index];
        if (from >= 0 && kg_scene_body_pivot(names_from, from, &pivot) &&
            kg_scene_body_def(scene, k)->type == KG_BODY_KINEMATIC) {
            KG_TRY(kg_scene_set_body_pivot(scene, k, pivot));
        }
    }
    return KG_OK;
}

/* Fills scene from world; names_from and origin (per body slot, the body's index in
 * names_from or -1) give the bodies' names and pivots, when given. */
static kg_result kg_fill_scene(kg_world* world, kg_scene* scene, const kg_scene* names_from, const int* origin,
                               const char* const* names)
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
    for (int k = 0; r == KG_OK && k < count; ++k) {
        char name[80];
        kg_name_of(scene, names, bodies[k], k, name, sizeof name);
        r = kg_add_world_body(world, bodies[k], name, scene);
    }
    r = r == KG_OK ? kg_add_pivots(names_from, origin, bodies, count, scene) : r;
    r = r == KG_OK ? kg_add_world_forces(world, bodies, count, scene) : r;
    r = r == KG_OK ? kg_add_world_maps(world, scene) : r;
    int* index = r == KG_OK ? kg_slot_indices(world, bodies, count) : NULL;
    r = r == KG_OK && !index ? kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_from_world: out of memory") : r;
    r = r == KG_OK ? kg_add_world_joints(world, index, scene) : r;
    free(index);
    free(bodies);
    return r == KG_OK ? kg_add_world_state(world, scene) : r;
}

/* The scene made from world, its bodies named (and pivoted) from names_from through
 * origin when given. */
static kg_result kg_scene_of_world(const kg_world* world, const kg_scene* names_from, const int* origin,
                                   kg_scene** out)
{
    *out = NULL;
    if (kg_world_refuses(world, "kg_scene_from_world", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    int slots = kg_world_get_def(world)->max_bodies;
    const char** names = names_from ? calloc((size_t)slots, sizeof *names) : NULL;
    if (names_from && !names) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_from_world_named: out of memory");
    }
    for (int i = 0; names && i < slots; ++i) {
        names[i] = origin[i] >= 0 ? kg_scene_body_name(names_from, origin[i]) : NULL;
    }
    kg_scene* scene = NULL;
    kg_result r = kg_scene_create(&scene);
    r = r == KG_OK ? kg_fill_scene((kg_world*)world, scene, names_from, origin, names) : r;
    free(names);
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
    return kg_scene_of_world(world, NULL, NULL, out);
}

kg_result kg_scene_from_world_named(const kg_world* world, const kg_scene* names_from, const kg_body* bodies,
                                    kg_scene** out)
{
    if (!world || !names_from || !bodies || !out) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_from_world_named: NULL argument");
    }
    int slots = kg_world_get_def(world)->max_bodies;
    int* origin = malloc((size_t)slots * sizeof *origin);
    if (!origin) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_from_world_named: out of memory");
    }
    for (int i = 0; i < slots; ++i) {
        origin[i] = -1;
    }
    for (int i = 0; i < kg_scene_body_count(names_from); ++i) {
        if (kg_body_is_valid(world, bodies[i])) {
            origin[bodies[i].index] = i;
        }
    }
    kg_result r = kg_scene_of_world(world, names_from, origin, out);
    free(origin);
    return r;
}

/* ---- writing JSON ---- */

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

/* The shape and material of an entry of a body's "shapes" (body_sensor: the body's sensor
 * flag, the entry's default). */
static cJSON* kg_shape_entry_json(const kg_body_shape_def* s, int body_sensor)
{
    cJSON* o = kg_shape_json(&s->geometry);
    int ok = o && kg_json_add_float(o, "density", s->density) && kg_json_add_float(o, "friction", s->friction) &&
             kg_json_add_float(o, "restitution", s->restitution) &&
             cJSON_AddNumberToObject(o, "category", (double)s->category) &&
             cJSON_AddNumberToObject(o, "mask", (double)s->mask) &&
             ((s->is_sensor != 0) == (body_sensor != 0) || cJSON_AddBoolToObject(o, "sensor", s->is_sensor != 0));
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

static cJSON* kg_chain_entry_json(const kg_chain_def* c)
{
    cJSON* o = cJSON_CreateObject();
    cJSON* points = cJSON_CreateArray();
    int ok = o && cJSON_AddStringToObject(o, "type", "chain") && kg_json_add(o, "points", points);
    points = ok ? points : (cJSON_Delete(points), NULL);
    for (int k = 0; ok && k < c->count; ++k) {
        ok = cJSON_AddItemToArray(points, kg_vec2_json(c->points[k]));
    }
    ok = ok && cJSON_AddBoolToObject(o, "loop", c->loop != 0) && kg_json_add_float(o, "friction", c->friction) &&
         kg_json_add_float(o, "restitution", c->restitution) &&
         cJSON_AddNumberToObject(o, "category", (double)c->category) &&
         cJSON_AddNumberToObject(o, "mask", (double)c->mask);
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

/* How many entries body i's "shapes" would hold (its own shape only if it has one). */
static int kg_entry_count(const kg_scene* scene, int i)
{
    int own = kg_scene_body_def(scene, i)->shape.type != KG_SHAPE_NONE;
    return own + kg_scene_body_shape_count(scene, i) - 1 + kg_scene_body_chain_count(scene, i);
}

/* Whether the scene has a state, which brings back every shape of its bodies. */
static int kg_has_state(const kg_scene* scene)
{
    size_t size = 0;
    return kg_scene_get_state(scene, &size) != NULL;
}

/* Whether body i is written with "shapes" (several shapes, or chains) rather than "shape".
 * A body of more entries than the reader takes is written with its own shape alone when
 * the scene has a state, which brings back the others. */
static int kg_has_entries(const kg_scene* scene, int i)
{
    int several = kg_scene_body_shape_count(scene, i) > 1 || kg_scene_body_chain_count(scene, i) > 0;
    return several && !(kg_entry_count(scene, i) > KG_SCENE_MAX_SHAPES && kg_has_state(scene));
}

/* Body i's "shapes": its own shape (if any), the others, then its chains. */
static cJSON* kg_entries_json(const kg_scene* scene, int i)
{
    const kg_body_def* d = kg_scene_body_def(scene, i);
    cJSON* list = cJSON_CreateArray();
    int ok = list != NULL;
    for (int k = d->shape.type == KG_SHAPE_NONE ? 1 : 0; ok && k < kg_scene_body_shape_count(scene, i); ++k) {
        kg_body_shape_def shape;
        ok = kg_scene_get_body_shape(scene, i, k, &shape) == KG_OK &&
             cJSON_AddItemToArray(list, kg_shape_entry_json(&shape, d->is_sensor));
    }
    for (int k = 0; ok && k < kg_scene_body_chain_count(scene, i); ++k) {
        kg_chain_def chain;
        ok = kg_scene_get_body_chain(scene, i, k, &chain) == KG_OK &&
             cJSON_AddItemToArray(list, kg_chain_entry_json(&chain));
    }
    if (!ok) {
        cJSON_Delete(list);
        return NULL;
    }
    return list;
}

static int kg_add_shapes(cJSON* o, const kg_scene* scene, int i)
{
    const kg_body_def* d = kg_scene_body_def(scene, i);
    if (kg_has_entries(scene, i)) {
        return kg_json_add(o, "shapes", kg_entries_json(scene, i));
    }
    return d->shape.type == KG_SHAPE_NONE || kg_json_add(o, "shape", kg_shape_json(&d->shape));
}

static cJSON* kg_body_json(const kg_scene* scene, int i)
{
    static const char* const types[] = {"static", "dynamic", "kinematic", "particle"};
    const kg_body_def* d = kg_scene_body_def(scene, i);
    cJSON* o = cJSON_CreateObject();
    int rotates = d->type != KG_BODY_PARTICLE;
    kg_vec2 pivot;
    int ok = o && cJSON_AddStringToObject(o, "name", kg_scene_body_name(scene, i)) &&
             cJSON_AddStringToObject(o, "type", types[d->type]) && kg_json_add_vec2(o, "position", d->position) &&
             (!rotates || kg_json_add_float(o, "angle", d->angle)) && kg_json_add_vec2(o, "velocity", d->velocity) &&
             (!rotates || kg_json_add_float(o, "angular_velocity", d->angular_velocity)) &&
             kg_add_shapes(o, scene, i) && kg_add_material(o, d) &&
             (!d->is_sensor || cJSON_AddBoolToObject(o, "sensor", 1)) &&
             (!kg_scene_body_pivot(scene, i, &pivot) || kg_json_add_vec2(o, "pivot", pivot));
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

static int kg_add_joints(cJSON* root, const kg_scene* scene)
{
    cJSON* joints = cJSON_CreateArray();
    int ok = kg_json_add(root, "joints", joints);
    for (int i = 0; ok && i < kg_scene_joint_count(scene); ++i) {
        ok = cJSON_AddItemToArray(joints, kg_scene_joint_json(scene, kg_scene_get_joint(scene, i)));
    }
    return ok;
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
    if (ok && kg_scene_joint_count(scene) > 0) {
        ok = kg_add_joints(root, scene);
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

/* A body the reader would refuse: more entries in "shapes" than it takes (without a state
 * to bring them back), or a mass with several shapes written (the file gives each shape a
 * density). */
static kg_result kg_check_body_writable(const kg_scene* scene, int i)
{
    int entries = kg_entry_count(scene, i);
    const char* name = kg_scene_body_name(scene, i);
    if (entries > KG_SCENE_MAX_SHAPES && !kg_has_state(scene)) {
        return kg_fail(KG_ERROR_UNSUPPORTED, "kg_scene_save_file: body %d ('%s') has %d shapes and chains, more "
                       "than a scene file's \"shapes\" holds (%d)", i, name, entries, KG_SCENE_MAX_SHAPES);
    }
    int compound = kg_has_entries(scene, i) && kg_scene_body_shape_count(scene, i) > 1;
    if (compound && kg_scene_body_def(scene, i)->mass > 0.0f) {
        return kg_fail(KG_ERROR_UNSUPPORTED, "kg_scene_save_file: body %d ('%s') has several shapes and a mass: "
                       "a scene file gives each shape a density", i, name);
    }
    return KG_OK;
}

/* What a scene file cannot say: KG_OK when the scene has none of it. A tile map the
 * legend cannot name is left to the state, when there is one. */
static kg_result kg_check_writable(const kg_scene* scene)
{
    for (int i = 0; i < kg_scene_body_count(scene); ++i) {
        KG_TRY(kg_check_body_writable(scene, i));
    }
    for (int i = 0; i < kg_scene_joint_count(scene); ++i) {
        const kg_scene_joint* j = kg_scene_get_joint(scene, i);
        kg_json_path path = kg_joint_call_path("kg_scene_save_file", scene, i, j);
        KG_TRY(kg_check_joint_entry(NULL, &path, scene, j));
    }
    for (int i = 0; !kg_has_state(scene) && i < kg_scene_tilemap_count(scene); ++i) {
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
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "kg_scene_save_file: out of memory, or a value not finite");
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
