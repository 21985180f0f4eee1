/* The JSON scene loader: reads a document strictly (unknown fields, wrong types and
 * impossible values are errors naming their JSON path) into a kg_scene. Shapes are
 * checked by the library itself (kg_shape_mass), so the loader and the engine agree on
 * what a valid polygon is. docs/scene-format.md is the format's reference. */
#include "kgyro/scene.h"

#include "collide/shape.h"
#include "core/kg_math.h"
#include "io/json_util.h"
#include "io/scene_generate.h"
#include "io/scene_joints.h"
#include "io/scene_limits.h"
#include "io/scene_state.h"
#include "io/tiled.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct kg_loader {
    kg_json_reader reader;
    kg_scene* scene;
} kg_loader;

static const char* const kSceneFields[] = {"description", "gravity", "dt", "steps", "substeps", "sleep",
                                           "continuous", "bodies", "forces", "generators", "tilemap", "joints",
                                           "state", NULL};
static const char* const kBodyFields[] = {"name", "type", "position", "angle", "velocity", "angular_velocity",
                                          "shape", "shapes", "density", "mass", "friction", "restitution",
                                          "linear_damping", "angular_damping", "category", "mask",
                                          "fixed_rotation", "bullet", "sensor", "pivot", NULL};
static const char* const kBoxFields[] = {"type", "width", "height", "center", "angle", NULL};
static const char* const kCircleFields[] = {"type", "radius", "center", NULL};
static const char* const kPolygonFields[] = {"type", "vertices", NULL};
static const char* const kCapsuleFields[] = {"type", "center1", "center2", "radius", NULL};
static const char* const kSegmentFields[] = {"type", "point1", "point2", NULL};
static const char* const kChainFields[] = {"type", "points", "loop", NULL};
/* An entry of a body's "shapes": the geometry placed by "center" and "angle", and its own
 * material and filter (the body's when left out). */
#define KG_SHAPE_ENTRY_FIELDS "center", "angle", "density", "friction", "restitution", "category", "mask", "sensor"
static const char* const kBoxEntryFields[] = {"type", "width", "height", KG_SHAPE_ENTRY_FIELDS, NULL};
static const char* const kCircleEntryFields[] = {"type", "radius", KG_SHAPE_ENTRY_FIELDS, NULL};
static const char* const kPolygonEntryFields[] = {"type", "vertices", KG_SHAPE_ENTRY_FIELDS, NULL};
static const char* const kCapsuleEntryFields[] = {"type", "center1", "center2", "radius", KG_SHAPE_ENTRY_FIELDS, NULL};
static const char* const kSegmentEntryFields[] = {"type", "point1", "point2", KG_SHAPE_ENTRY_FIELDS, NULL};
/* No "sensor": a chain cannot be one. Its "density" has no effect, as a segment's: neither
 * has mass. */
static const char* const kChainEntryFields[] = {"type", "points", "loop", "center", "angle", "density",
                                                "friction", "restitution", "category", "mask", NULL};

static const char* const kBodyTypes[] = {"static", "dynamic", "kinematic", "particle", NULL};

/* A scene file bigger than this is refused before it is read: 64 MiB holds some 300,000
 * bodies written out one by one, more than any world the engine steps interactively. */
#define KG_SCENE_FILE_SIZE_MAX ((size_t)1 << 26)

/* The chains of the body being read, added to the scene after the body: their points (the
 * loader frees them) in the body frame. */
typedef struct kg_body_chains {
    kg_chain_def defs[KG_SCENE_MAX_SHAPES];
    int count;
} kg_body_chains;

/* The index of value's string in names, or a "must be one of" error. */
static kg_result kg_read_choice(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                                const char* key, const char* const* names, int* out)
{
    const char* text = NULL;
    KG_TRY(kg_json_string(reader, object, path, key, &text));
    if (!text) {
        return KG_OK;
    }
    for (int i = 0; names[i]; ++i) {
        if (strcmp(text, names[i]) == 0) {
            *out = i;
            return KG_OK;
        }
    }
    char list[160] = "";
    for (int i = 0; names[i]; ++i) {
        size_t used = strlen(list);
        snprintf(list + used, sizeof list - used, "%s\"%s\"", i > 0 ? ", " : "", names[i]);
    }
    kg_json_path field_path = kg_json_path_key(path, key);
    return kg_json_fail(reader, &field_path, "must be one of %s (got \"%s\")", list, text);
}

/* ---- shapes ---- */

static kg_result kg_read_box(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                             int entry, kg_shape_def* out)
{
    float width = 0.0f, height = 0.0f, angle = 0.0f;
    kg_vec2 center = {0.0f, 0.0f};
    KG_TRY(kg_json_check_object(reader, json, path, entry ? kBoxEntryFields : kBoxFields));
    KG_TRY(kg_json_require(reader, json, path, "width"));
    KG_TRY(kg_json_require(reader, json, path, "height"));
    KG_TRY(kg_json_float(reader, json, path, "width", KG_JSON_POSITIVE, &width));
    KG_TRY(kg_json_float(reader, json, path, "height", KG_JSON_POSITIVE, &height));
    KG_TRY(kg_json_vec2(reader, json, path, "center", &center));
    KG_TRY(kg_json_float(reader, json, path, "angle", KG_JSON_ANY, &angle));
    *out = kg_offset_box_shape(width, height, center, angle);
    return KG_OK;
}

static kg_result kg_read_circle(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                int entry, kg_shape_def* out)
{
    float radius = 0.0f;
    kg_vec2 center = {0.0f, 0.0f};
    KG_TRY(kg_json_check_object(reader, json, path, entry ? kCircleEntryFields : kCircleFields));
    KG_TRY(kg_json_require(reader, json, path, "radius"));
    KG_TRY(kg_json_float(reader, json, path, "radius", KG_JSON_POSITIVE, &radius));
    KG_TRY(kg_json_vec2(reader, json, path, "center", &center));
    *out = kg_circle_shape(radius);
    out->center = center;
    return KG_OK;
}

/* An entry of "shapes" placed in the body frame by its "center" and "angle" (a box and a
 * circle read their own placement). */
static kg_result kg_place_entry(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                kg_shape_def* out)
{
    kg_vec2 center = {0.0f, 0.0f};
    float angle = 0.0f;
    KG_TRY(kg_json_vec2(reader, json, path, "center", &center));
    KG_TRY(kg_json_float(reader, json, path, "angle", KG_JSON_ANY, &angle));
    *out = kg_shape_moved(*out, center, angle);
    return KG_OK;
}

static kg_result kg_read_capsule(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                 int entry, kg_shape_def* out)
{
    kg_vec2 center1 = {0.0f, 0.0f}, center2 = {0.0f, 0.0f};
    float radius = 0.0f;
    KG_TRY(kg_json_check_object(reader, json, path, entry ? kCapsuleEntryFields : kCapsuleFields));
    KG_TRY(kg_json_require(reader, json, path, "center1"));
    KG_TRY(kg_json_require(reader, json, path, "center2"));
    KG_TRY(kg_json_require(reader, json, path, "radius"));
    KG_TRY(kg_json_vec2(reader, json, path, "center1", &center1));
    KG_TRY(kg_json_vec2(reader, json, path, "center2", &center2));
    KG_TRY(kg_json_float(reader, json, path, "radius", KG_JSON_POSITIVE, &radius));
    *out = kg_capsule_shape(center1, center2, radius);
    return entry ? kg_place_entry(reader, json, path, out) : KG_OK;
}

static kg_result kg_read_segment(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                 int entry, kg_shape_def* out)
{
    kg_vec2 point1 = {0.0f, 0.0f}, point2 = {0.0f, 0.0f};
    KG_TRY(kg_json_check_object(reader, json, path, entry ? kSegmentEntryFields : kSegmentFields));
    KG_TRY(kg_json_require(reader, json, path, "point1"));
    KG_TRY(kg_json_require(reader, json, path, "point2"));
    KG_TRY(kg_json_vec2(reader, json, path, "point1", &point1));
    KG_TRY(kg_json_vec2(reader, json, path, "point2", &point2));
    *out = kg_segment_shape(point1, point2);
    return entry ? kg_place_entry(reader, json, path, out) : KG_OK;
}

/* A JSON array of 3 to KG_MAX_POLYGON_VERTICES [x, y] points, for body and tile polygons. */
static kg_result kg_read_vertex_list(const kg_json_reader* reader, const cJSON* vertices, const kg_json_path* path,
                                     kg_vec2* points, int* count)
{
    KG_TRY(kg_json_check_array(reader, vertices, path));
    *count = cJSON_GetArraySize(vertices);
    if (*count < 3 || *count > KG_MAX_POLYGON_VERTICES) {
        return kg_json_fail(reader, path, "must have 3 to %d vertices (got %d)", KG_MAX_POLYGON_VERTICES, *count);
    }
    int i = 0;
    for (const cJSON* vertex = vertices->child; vertex; vertex = vertex->next, ++i) {
        kg_json_path vertex_path = kg_json_path_index(path, i);
        KG_TRY(kg_json_vec2_value(reader, vertex, &vertex_path, &points[i]));
    }
    return KG_OK;
}

static kg_result kg_read_polygon(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                 int entry, kg_shape_def* out)
{
    KG_TRY(kg_json_check_object(reader, json, path, entry ? kPolygonEntryFields : kPolygonFields));
    KG_TRY(kg_json_require(reader, json, path, "vertices"));
    kg_json_path vertices_path = kg_json_path_key(path, "vertices");
    kg_vec2 points[KG_MAX_POLYGON_VERTICES];
    int count;
    KG_TRY(kg_read_vertex_list(reader, cJSON_GetObjectItemCaseSensitive(json, "vertices"), &vertices_path, points,
                               &count));
    *out = kg_polygon_shape(points, count);
    return entry ? kg_place_entry(reader, json, path, out) : KG_OK;
}

/* Whether the library accepts the shape: with its mass at density 1, or for a segment,
 * which has none, as a static body's. */
static kg_result kg_library_accepts(const kg_shape_def* shape)
{
    if (shape->type == KG_SHAPE_SEGMENT) {
        kg_body_def outline = kg_default_body_def();
        outline.type = KG_BODY_STATIC;
        outline.shape = *shape;
        return kg_check_body_def(&outline);
    }
    kg_mass_data mass;
    return kg_shape_mass(shape, 1.0f, &mass);
}

/* Lets the library judge the geometry (degenerate polygons above all). */
static kg_result kg_check_shape(const kg_json_reader* reader, const kg_shape_def* shape, const kg_json_path* path)
{
    if (kg_library_accepts(shape) == KG_OK) {
        return KG_OK;
    }
    char reason[256];
    snprintf(reason, sizeof reason, "%s", kg_last_error());
    kg_json_path where = shape->type == KG_SHAPE_POLYGON ? kg_json_path_key(path, "vertices") : *path;
    return kg_json_fail(reader, &where, "%s", reason);
}

/* A chain's "points", into a new array that the caller frees (kg_read_body); whether they
 * make a chain is judged after. */
static kg_result kg_read_chain_points(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                      kg_chain_def* def)
{
    KG_TRY(kg_json_require(reader, json, path, "points"));
    const cJSON* list = cJSON_GetObjectItemCaseSensitive(json, "points");
    kg_json_path points_path = kg_json_path_key(path, "points");
    KG_TRY(kg_json_check_array(reader, list, &points_path));
    int count = cJSON_GetArraySize(list);
    if (count > KG_MAX_CHAIN_POINTS) {
        return kg_json_fail(reader, &points_path, "must hold at most %d points (got %d)", KG_MAX_CHAIN_POINTS, count);
    }
    kg_vec2* points = malloc((size_t)(count > 0 ? count : 1) * sizeof *points);
    if (!points) {
        return kg_json_fail_message(KG_ERROR_OUT_OF_MEMORY, "%s: out of memory", reader->source);
    }
    def->points = points;
    def->count = count;
    int i = 0;
    for (const cJSON* point = list->child; point; point = point->next, ++i) {
        kg_json_path point_path = kg_json_path_index(&points_path, i);
        KG_TRY(kg_json_vec2_value(reader, point, &point_path, &points[i]));
    }
    return KG_OK;
}

/* An entry's chain placed in the body frame as kg_shape_moved places a polygon: turned by
 * "angle" about the origin, then moved by "center". */
static kg_result kg_place_chain(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                kg_chain_def* def)
{
    kg_vec2 center = {0.0f, 0.0f};
    float angle = 0.0f;
    KG_TRY(kg_json_vec2(reader, json, path, "center", &center));
    KG_TRY(kg_json_float(reader, json, path, "angle", KG_JSON_ANY, &angle));
    float c = cosf(angle), s = sinf(angle);
    kg_vec2* points = (kg_vec2*)def->points;
    for (int i = 0; i < def->count; ++i) {
        kg_vec2 p = points[i];
        points[i] = (kg_vec2){c * p.x - s * p.y + center.x, s * p.x + c * p.y + center.y};
    }
    return KG_OK;
}

/* A chain of a static or kinematic body, appended to chains with the body's material (an
 * entry's own is the caller's) and checked as kg_create_chain will check it. */
static kg_result kg_read_chain(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path, int entry,
                               const kg_body_def* body, kg_body_chains* chains)
{
    if (body->type != KG_BODY_STATIC && body->type != KG_BODY_KINEMATIC) {
        return kg_json_fail(reader, path, "a chain has no mass: only static and kinematic bodies may hold one "
                                          "(use capsules or polygons)");
    }
    KG_TRY(kg_json_check_object(reader, json, path, entry ? kChainEntryFields : kChainFields));
    kg_chain_def* def = &chains->defs[chains->count++];
    *def = kg_default_chain_def();
    def->friction = body->friction;
    def->restitution = body->restitution;
    def->category = body->category;
    def->mask = body->mask;
    KG_TRY(kg_json_bool(reader, json, path, "loop", &def->loop));
    KG_TRY(kg_read_chain_points(reader, json, path, def));
    if (entry) {
        KG_TRY(kg_place_chain(reader, json, path, def));
    }
    if (kg_check_chain_points(def->points, def->count, def->loop) != KG_OK) {
        char reason[256];
        snprintf(reason, sizeof reason, "%s", kg_last_error());
        kg_json_path points_path = kg_json_path_key(path, "points");
        return kg_json_fail(reader, &points_path, "%s", reason);
    }
    return KG_OK;
}

/* A shape: a body's "shape" (entry 0) or an entry of its "shapes" (entry 1: placed by
 * "center" and "angle", with material fields the caller reads). A chain goes to chains
 * and leaves *out of type NONE. */
static kg_result kg_read_shape(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path, int entry,
                               const kg_body_def* body, kg_shape_def* out, kg_body_chains* chains)
{
    static const char* const kinds[] = {"box", "circle", "polygon", "capsule", "segment", "chain", NULL};
    if (!cJSON_IsObject(json)) {
        return kg_json_fail(reader, path, "must be an object");
    }
    KG_TRY(kg_json_require(reader, json, path, "type"));
    int kind = 0;
    KG_TRY(kg_read_choice(reader, json, path, "type", kinds, &kind));
    switch (kind) {
    case 0:
        KG_TRY(kg_read_box(reader, json, path, entry, out));
        break;
    case 1:
        KG_TRY(kg_read_circle(reader, json, path, entry, out));
        break;
    case 3:
        KG_TRY(kg_read_capsule(reader, json, path, entry, out));
        break;
    case 4:
        KG_TRY(kg_read_segment(reader, json, path, entry, out));
        break;
    case 5:
        out->type = KG_SHAPE_NONE;
        return kg_read_chain(reader, json, path, entry, body, chains);
    default:
        KG_TRY(kg_read_polygon(reader, json, path, entry, out));
        break;
    }
    return kg_check_shape(reader, out, path);
}

/* ---- bodies ---- */

static int kg_has(const cJSON* object, const char* key) { return cJSON_GetObjectItemCaseSensitive(object, key) != NULL; }

static kg_result kg_read_mass(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                              kg_body_def* def)
{
    if (kg_has(json, "density") && kg_has(json, "mass")) {
        kg_json_path mass_path = kg_json_path_key(path, "mass");
        return kg_json_fail(reader, &mass_path, "give density or mass, not both");
    }
    KG_TRY(kg_json_float(reader, json, path, "density", KG_JSON_NON_NEGATIVE, &def->density));
    KG_TRY(kg_json_float(reader, json, path, "mass", KG_JSON_POSITIVE, &def->mass));
    int moves = def->type == KG_BODY_DYNAMIC || def->type == KG_BODY_PARTICLE;
    if (moves && def->mass == 0.0f && !(def->density > 0.0f)) {
        kg_json_path density_path = kg_json_path_key(path, "density");
        return kg_json_fail(reader, &density_path, "must be > 0 for a %s body", kBodyTypes[def->type]);
    }
    return KG_OK;
}

static kg_result kg_read_motion(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                kg_body_def* def)
{
    if (def->type == KG_BODY_PARTICLE) {
        static const char* const turning[] = {"angle", "angular_velocity", "fixed_rotation", NULL};
        for (int i = 0; turning[i]; ++i) {
            if (kg_has(json, turning[i])) {
                kg_json_path field_path = kg_json_path_key(path, turning[i]);
                return kg_json_fail(reader, &field_path, "particles do not rotate");
            }
        }
    }
    KG_TRY(kg_json_vec2(reader, json, path, "position", &def->position));
    KG_TRY(kg_json_float(reader, json, path, "angle", KG_JSON_ANY, &def->angle));
    KG_TRY(kg_json_vec2(reader, json, path, "velocity", &def->velocity));
    KG_TRY(kg_json_float(reader, json, path, "angular_velocity", KG_JSON_ANY, &def->angular_velocity));
    KG_TRY(kg_json_bool(reader, json, path, "bullet", &def->bullet));
    if (def->bullet && def->type != KG_BODY_DYNAMIC) {
        kg_json_path bullet_path = kg_json_path_key(path, "bullet");
        return kg_json_fail(reader, &bullet_path, "only a dynamic body can be a bullet (this one is %s)",
                            kBodyTypes[def->type]);
    }
    return kg_json_bool(reader, json, path, "fixed_rotation", &def->fixed_rotation);
}

static kg_result kg_read_material(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                  kg_body_def* def)
{
    KG_TRY(kg_json_float(reader, json, path, "friction", KG_JSON_NON_NEGATIVE, &def->friction));
    KG_TRY(kg_json_float(reader, json, path, "restitution", KG_JSON_UNIT, &def->restitution));
    KG_TRY(kg_json_float(reader, json, path, "linear_damping", KG_JSON_NON_NEGATIVE, &def->linear_damping));
    KG_TRY(kg_json_float(reader, json, path, "angular_damping", KG_JSON_NON_NEGATIVE, &def->angular_damping));
    KG_TRY(kg_json_uint32(reader, json, path, "category", &def->category));
    return kg_json_uint32(reader, json, path, "mask", &def->mask);
}

static kg_result kg_read_body_shape(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                    kg_body_def* def, kg_body_chains* chains)
{
    const cJSON* shape = cJSON_GetObjectItemCaseSensitive(json, "shape");
    if (shape && kg_has(json, "shapes")) {
        kg_json_path shapes_path = kg_json_path_key(path, "shapes");
        return kg_json_fail(reader, &shapes_path, "give shape or shapes, not both");
    }
    if (kg_has(json, "shapes")) {
        return KG_OK; /* read after the body's material, their fallback (kg_read_shape_entries) */
    }
    if (shape) {
        kg_json_path shape_path = kg_json_path_key(path, "shape");
        kg_shape_def geometry;
        KG_TRY(kg_read_shape(reader, shape, &shape_path, 0, def, &geometry, chains));
        def->shape = geometry;
        int moves = def->type == KG_BODY_DYNAMIC || def->type == KG_BODY_PARTICLE;
        if (moves && def->shape.type == KG_SHAPE_SEGMENT) {
            return kg_json_fail(reader, &shape_path, "a segment has no area: only static and kinematic bodies may have one");
        }
        return KG_OK;
    }
    if (def->type == KG_BODY_STATIC || def->type == KG_BODY_KINEMATIC) {
        def->shape.type = KG_SHAPE_NONE; /* a joint's anchor, a pivot: touches nothing */
        return KG_OK;
    }
    if (def->type != KG_BODY_PARTICLE) {
        kg_json_path shape_path = kg_json_path_key(path, "shape");
        return kg_json_fail(reader, &shape_path,
                            "is required (only particles, static and kinematic bodies may omit it)");
    }
    if (!kg_has(json, "mass")) {
        kg_json_path mass_path = kg_json_path_key(path, "mass");
        return kg_json_fail(reader, &mass_path, "is required for a particle without a shape");
    }
    def->shape.type = KG_SHAPE_NONE;
    return KG_OK;
}

/* A chain entry's material and filter: its entry's. */
static void kg_give_chain_material(kg_chain_def* chain, const kg_body_shape_def* entry)
{
    chain->friction = entry->friction;
    chain->restitution = entry->restitution;
    chain->category = entry->category;
    chain->mask = entry->mask;
}

/* An entry of "shapes": its geometry, and its material and filter, the body's where left
 * out. A chain goes to chains, with that material, and leaves out->geometry of type NONE. */
static kg_result kg_read_shape_entry(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                     const kg_body_def* body, kg_body_shape_def* out, kg_body_chains* chains)
{
    *out = kg_default_body_shape_def();
    KG_TRY(kg_read_shape(reader, json, path, 1, body, &out->geometry, chains));
    out->density = body->density;
    out->friction = body->friction;
    out->restitution = body->restitution;
    out->category = body->category;
    out->mask = body->mask;
    out->is_sensor = body->is_sensor;
    KG_TRY(kg_json_float(reader, json, path, "density", KG_JSON_NON_NEGATIVE, &out->density));
    KG_TRY(kg_json_float(reader, json, path, "friction", KG_JSON_NON_NEGATIVE, &out->friction));
    KG_TRY(kg_json_float(reader, json, path, "restitution", KG_JSON_UNIT, &out->restitution));
    KG_TRY(kg_json_uint32(reader, json, path, "category", &out->category));
    KG_TRY(kg_json_uint32(reader, json, path, "mask", &out->mask));
    if (out->geometry.type == KG_SHAPE_NONE) {
        kg_give_chain_material(&chains->defs[chains->count - 1], out);
    }
    return kg_json_bool(reader, json, path, "sensor", &out->is_sensor);
}

/* A body's "shapes", non-empty: chains go to chains; the first other entry becomes the
 * body def's shape (so it must be massive on a moving body: the body is made with it; it
 * may be a sensor), the others *extras (*extra_count of them, at most KG_SCENE_MAX_SHAPES - 1). A
 * body of chains only has no shape of its own. */
static kg_result kg_read_shape_entries(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                       kg_body_def* def, kg_body_shape_def* extras, int* extra_count,
                                       kg_body_chains* chains)
{
    const cJSON* shapes = cJSON_GetObjectItemCaseSensitive(json, "shapes");
    *extra_count = 0;
    if (!shapes) {
        return KG_OK;
    }
    kg_json_path shapes_path = kg_json_path_key(path, "shapes");
    KG_TRY(kg_json_check_array(reader, shapes, &shapes_path));
    int count = cJSON_GetArraySize(shapes);
    if (count < 1 || count > KG_SCENE_MAX_SHAPES) {
        return kg_json_fail(reader, &shapes_path, "must hold 1 to %d shapes (got %d)", KG_SCENE_MAX_SHAPES, count);
    }
    if (count > 1 && def->mass > 0.0f) {
        kg_json_path mass_path = kg_json_path_key(path, "mass");
        return kg_json_fail(reader, &mass_path, "is for a body of one shape: give each of its shapes a density");
    }
    const kg_body_def body = *def; /* the fallbacks, before the first shape's material replaces them */
    int k = 0, first = 1;
    for (const cJSON* entry = shapes->child; entry; entry = entry->next, ++k) {
        kg_json_path entry_path = kg_json_path_index(&shapes_path, k);
        kg_body_shape_def shape;
        KG_TRY(kg_read_shape_entry(reader, entry, &entry_path, &body, &shape, chains));
        if (shape.geometry.type == KG_SHAPE_NONE) {
            continue; /* a chain */
        }
        if (!first) {
            extras[(*extra_count)++] = shape;
            continue;
        }
        first = 0;
        int moves = def->type == KG_BODY_DYNAMIC || def->type == KG_BODY_PARTICLE;
        if (moves && def->mass == 0.0f && !(shape.density > 0.0f)) {
            kg_json_path field_path = kg_json_path_key(&entry_path, "density");
            return kg_json_fail(reader, &field_path, "the first shape of a %s body must be of density > 0",
                                kBodyTypes[def->type]);
        }
        def->shape = shape.geometry;
        def->density = shape.density;
        def->friction = shape.friction;
        def->restitution = shape.restitution;
        def->category = shape.category;
        def->mask = shape.mask;
        def->is_sensor = shape.is_sensor;
    }
    return KG_OK;
}

static kg_result kg_add_named_body(kg_loader* loader, const cJSON* json, const kg_json_path* path,
                                   const kg_body_def* def)
{
    const char* name = NULL;
    KG_TRY(kg_json_string(&loader->reader, json, path, "name", &name));
    kg_json_path name_path = kg_json_path_key(path, "name");
    int existing = name ? kg_scene_find_body(loader->scene, name) : -1;
    if (existing >= 0) {
        return kg_json_fail(&loader->reader, &name_path, "duplicate name '%s' (also bodies[%d])", name, existing);
    }
    if (kg_scene_add_body(loader->scene, name, def) != KG_OK) {
        char reason[256];
        snprintf(reason, sizeof reason, "%s", kg_last_error());
        return kg_json_fail(&loader->reader, name ? &name_path : path, "%s", reason);
    }
    return KG_OK;
}

/* A body's chains, after the body (the last added) and its other shapes. */
static kg_result kg_add_body_chains(kg_loader* loader, const kg_json_path* path, const kg_body_chains* chains)
{
    int index = kg_scene_body_count(loader->scene) - 1;
    for (int k = 0; k < chains->count; ++k) {
        if (kg_scene_add_body_chain(loader->scene, index, &chains->defs[k]) != KG_OK) {
            char reason[256];
            snprintf(reason, sizeof reason, "%s", kg_last_error());
            return kg_json_fail(&loader->reader, path, "%s", reason);
        }
    }
    return KG_OK;
}

static kg_result kg_read_body_into(kg_loader* loader, const cJSON* json, const kg_json_path* path,
                                   kg_body_chains* chains)
{
    const kg_json_reader* reader = &loader->reader;
    KG_TRY(kg_json_check_object(reader, json, path, kBodyFields));
    kg_body_def def = kg_default_body_def();
    int type = (int)KG_BODY_DYNAMIC;
    KG_TRY(kg_read_choice(reader, json, path, "type", kBodyTypes, &type));
    def.type = (kg_body_type)type;
    KG_TRY(kg_read_motion(reader, json, path, &def));
    KG_TRY(kg_read_material(reader, json, path, &def)); /* before the shape: a chain there takes it */
    KG_TRY(kg_json_bool(reader, json, path, "sensor", &def.is_sensor)); /* its shapes', unless they say */
    KG_TRY(kg_read_body_shape(reader, json, path, &def, chains));
    KG_TRY(kg_read_mass(reader, json, path, &def));
    kg_body_shape_def extras[KG_SCENE_MAX_SHAPES];
    int extra_count = 0;
    KG_TRY(kg_read_shape_entries(reader, json, path, &def, extras, &extra_count, chains));
    kg_vec2 pivot;
    int has_pivot = kg_has(json, "pivot");
    KG_TRY(kg_json_vec2(reader, json, path, "pivot", &pivot));
    if (has_pivot && def.type != KG_BODY_KINEMATIC) {
        kg_json_path pivot_path = kg_json_path_key(path, "pivot");
        return kg_json_fail(reader, &pivot_path, "only kinematic bodies can have a pivot");
    }
    KG_TRY(kg_add_named_body(loader, json, path, &def));
    int index = kg_scene_body_count(loader->scene) - 1;
    for (int k = 0; k < extra_count; ++k) {
        if (kg_scene_add_body_shape(loader->scene, index, &extras[k]) != KG_OK) {
            return kg_json_fail(reader, path, "out of memory for its shapes");
        }
    }
    if (has_pivot) {
        KG_TRY(kg_scene_set_body_pivot(loader->scene, kg_scene_body_count(loader->scene) - 1, pivot));
    }
    return kg_add_body_chains(loader, path, chains);
}

static kg_result kg_read_body(kg_loader* loader, const cJSON* json, const kg_json_path* path)
{
    kg_body_chains chains;
    chains.count = 0;
    kg_result r = kg_read_body_into(loader, json, path, &chains);
    for (int k = 0; k < chains.count; ++k) {
        free((void*)chains.defs[k].points);
    }
    return r;
}

/* ---- generators ---- */

static kg_result kg_read_gen_material(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                      kg_gen_material* out)
{
    *out = kg_gen_default_material();
    KG_TRY(kg_json_float(reader, json, path, "density", KG_JSON_POSITIVE, &out->density));
    KG_TRY(kg_json_float(reader, json, path, "friction", KG_JSON_NON_NEGATIVE, &out->friction));
    return kg_json_float(reader, json, path, "restitution", KG_JSON_UNIT, &out->restitution);
}

/* "region": [x0, y0, x1, y1], required, non-empty. */
static kg_result kg_read_region(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                kg_aabb* out)
{
    KG_TRY(kg_json_require(reader, json, path, "region"));
    const cJSON* value = cJSON_GetObjectItemCaseSensitive(json, "region");
    kg_json_path region_path = kg_json_path_key(path, "region");
    float corners[4];
    int count = cJSON_IsArray(value) ? cJSON_GetArraySize(value) : 0;
    int i = 0;
    for (const cJSON* item = count == 4 ? value->child : NULL; item; item = item->next) {
        if (!cJSON_IsNumber(item) || !isfinite((float)item->valuedouble)) {
            break;
        }
        corners[i++] = (float)item->valuedouble;
    }
    if (i != 4 || !(corners[0] < corners[2]) || !(corners[1] < corners[3])) {
        return kg_json_fail(reader, &region_path, "must be [x0, y0, x1, y1] with x0 < x1 and y0 < y1");
    }
    *out = (kg_aabb){{corners[0], corners[1]}, {corners[2], corners[3]}};
    return KG_OK;
}

/* Refuses a generator asking for more bodies than the limits leave, before it allocates
 * any: key names the field that sets how many. */
static kg_result kg_check_room(kg_loader* loader, const kg_json_path* path, const char* key, long long bodies)
{
    int room = kg_scene_body_room(loader->scene);
    if (bodies <= room) {
        return KG_OK;
    }
    kg_json_path key_path = kg_json_path_key(path, key);
    return kg_json_fail(&loader->reader, &key_path, "asks for %lld bodies, but max_bodies (%d) leaves room for %d", bodies,
                        kg_scene_get_limits(loader->scene)->max_bodies, room);
}

/* Turns a generator's own failure (a bad name, say) into a message at its path. */
static kg_result kg_generated(const kg_json_reader* reader, const kg_json_path* path, kg_result result)
{
    if (result == KG_OK) {
        return KG_OK;
    }
    char reason[256];
    snprintf(reason, sizeof reason, "%s", kg_last_error());
    return kg_json_fail(reader, path, "%s", reason);
}

typedef kg_result kg_gen_reader(kg_loader* loader, const cJSON* json, const kg_json_path* path, const char* prefix);

static kg_result kg_read_pyramid(kg_loader* loader, const cJSON* json, const kg_json_path* path, const char* prefix)
{
    const kg_json_reader* reader = &loader->reader;
    kg_gen_pyramid p = {0, 1.0f, {0.0f, 0.0f}, kg_gen_default_material()};
    KG_TRY(kg_json_require(reader, json, path, "base"));
    KG_TRY(kg_json_int(reader, json, path, "base", 1, 2000, &p.base));
    KG_TRY(kg_check_room(loader, path, "base", (long long)p.base * (p.base + 1) / 2));
    KG_TRY(kg_json_float(reader, json, path, "box_size", KG_JSON_POSITIVE, &p.box_size));
    KG_TRY(kg_json_vec2(reader, json, path, "origin", &p.origin));
    KG_TRY(kg_read_gen_material(reader, json, path, &p.material));
    return kg_generated(reader, path, kg_gen_pyramid_bodies(loader->scene, prefix, &p));
}

static kg_result kg_read_stack(kg_loader* loader, const cJSON* json, const kg_json_path* path, const char* prefix)
{
    const kg_json_reader* reader = &loader->reader;
    kg_gen_stack p = {0, 1.0f, 0.0f, {0.0f, 0.0f}, kg_gen_default_material()};
    KG_TRY(kg_json_require(reader, json, path, "count"));
    KG_TRY(kg_json_int(reader, json, path, "count", 1, 100000, &p.count));
    KG_TRY(kg_check_room(loader, path, "count", p.count));
    KG_TRY(kg_json_float(reader, json, path, "box_size", KG_JSON_POSITIVE, &p.box_size));
    KG_TRY(kg_json_float(reader, json, path, "gap", KG_JSON_NON_NEGATIVE, &p.gap));
    KG_TRY(kg_json_vec2(reader, json, path, "origin", &p.origin));
    KG_TRY(kg_read_gen_material(reader, json, path, &p.material));
    return kg_generated(reader, path, kg_gen_stack_bodies(loader->scene, prefix, &p));
}

static kg_result kg_read_container(kg_loader* loader, const cJSON* json, const kg_json_path* path,
                                   const char* prefix)
{
    const kg_json_reader* reader = &loader->reader;
    kg_gen_container p = {{0.0f, 0.0f}, 0.0f, 0.0f, 1.0f, kg_gen_default_material()};
    KG_TRY(kg_json_require(reader, json, path, "width"));
    KG_TRY(kg_json_require(reader, json, path, "height"));
    KG_TRY(kg_json_vec2(reader, json, path, "origin", &p.origin));
    KG_TRY(kg_json_float(reader, json, path, "width", KG_JSON_POSITIVE, &p.width));
    KG_TRY(kg_json_float(reader, json, path, "height", KG_JSON_POSITIVE, &p.height));
    KG_TRY(kg_json_float(reader, json, path, "thickness", KG_JSON_POSITIVE, &p.thickness));
    KG_TRY(kg_read_gen_material(reader, json, path, &p.material));
    KG_TRY(kg_check_room(loader, path, "type", 3)); /* a floor and two walls */
    return kg_generated(reader, path, kg_gen_container_bodies(loader->scene, prefix, &p));
}

static kg_result kg_read_rain(kg_loader* loader, const cJSON* json, const kg_json_path* path, const char* prefix)
{
    const kg_json_reader* reader = &loader->reader;
    kg_gen_rain p = {0, 1u, {{0.0f, 0.0f}, {0.0f, 0.0f}}, 0.2f, 0.8f, kg_gen_default_material()};
    KG_TRY(kg_json_require(reader, json, path, "count"));
    KG_TRY(kg_json_int(reader, json, path, "count", 1, 1000000, &p.count));
    KG_TRY(kg_check_room(loader, path, "count", p.count));
    KG_TRY(kg_json_uint32(reader, json, path, "seed", &p.seed));
    KG_TRY(kg_read_region(reader, json, path, &p.region));
    KG_TRY(kg_json_float(reader, json, path, "min_size", KG_JSON_POSITIVE, &p.min_size));
    KG_TRY(kg_json_float(reader, json, path, "max_size", KG_JSON_POSITIVE, &p.max_size));
    if (p.max_size < p.min_size) {
        kg_json_path max_path = kg_json_path_key(path, "max_size");
        return kg_json_fail(reader, &max_path, "must be >= min_size (%g)", (double)p.min_size);
    }
    KG_TRY(kg_read_gen_material(reader, json, path, &p.material));
    int capacity = kg_gen_rain_capacity(&p);
    if (p.count > capacity) {
        kg_json_path region_path = kg_json_path_key(path, "region");
        return kg_json_fail(reader, &region_path, "holds %d bodies of max_size %g, not %d", capacity,
                            (double)p.max_size, p.count);
    }
    return kg_generated(reader, path, kg_gen_rain_bodies(loader->scene, prefix, &p));
}

static kg_result kg_read_particles(kg_loader* loader, const cJSON* json, const kg_json_path* path,
                                   const char* prefix)
{
    const kg_json_reader* reader = &loader->reader;
    kg_gen_particles p = {0, 1u, {{0.0f, 0.0f}, {0.0f, 0.0f}}, 0.05f, 0.0f, kg_gen_default_material()};
    KG_TRY(kg_json_require(reader, json, path, "count"));
    KG_TRY(kg_json_int(reader, json, path, "count", 1, 1000000, &p.count));
    KG_TRY(kg_check_room(loader, path, "count", p.count));
    KG_TRY(kg_json_uint32(reader, json, path, "seed", &p.seed));
    KG_TRY(kg_read_region(reader, json, path, &p.region));
    KG_TRY(kg_json_float(reader, json, path, "radius", KG_JSON_POSITIVE, &p.radius));
    if (kg_has(json, "density") && kg_has(json, "mass")) {
        kg_json_path mass_path = kg_json_path_key(path, "mass");
        return kg_json_fail(reader, &mass_path, "give density or mass, not both");
    }
    KG_TRY(kg_json_float(reader, json, path, "mass", KG_JSON_POSITIVE, &p.mass));
    KG_TRY(kg_read_gen_material(reader, json, path, &p.material));
    int capacity = kg_gen_particles_capacity(&p);
    if (p.count > capacity) {
        kg_json_path region_path = kg_json_path_key(path, "region");
        return kg_json_fail(reader, &region_path, "holds %d particles of radius %g, not %d", capacity,
                            (double)p.radius, p.count);
    }
    return kg_generated(reader, path, kg_gen_particle_bodies(loader->scene, prefix, &p));
}

typedef struct kg_gen_kind {
    const char* type;
    const char* const* fields;
    kg_gen_reader* read; /* NULL: a benchmark scene, which has no parameters */
} kg_gen_kind;

static const char* const kPyramidFields[] = {"type", "name", "base", "box_size", "origin",
                                             "density", "friction", "restitution", NULL};
static const char* const kStackFields[] = {"type", "name", "count", "box_size", "gap", "origin",
                                           "density", "friction", "restitution", NULL};
static const char* const kContainerFields[] = {"type", "name", "origin", "width", "height", "thickness",
                                               "friction", "restitution", NULL};
static const char* const kRainFields[] = {"type", "name", "count", "seed", "region", "min_size", "max_size",
                                          "density", "friction", "restitution", NULL};
static const char* const kParticleFields[] = {"type", "name", "count", "seed", "region", "radius", "mass",
                                              "density", "friction", "restitution", NULL};
static const char* const kBenchmarkFields[] = {"type", "name", NULL};

static const kg_gen_kind kGeneratorKinds[] = {
    {"pyramid", kPyramidFields, kg_read_pyramid},
    {"stack", kStackFields, kg_read_stack},
    {"container", kContainerFields, kg_read_container},
    {"rain", kRainFields, kg_read_rain},
    {"particles", kParticleFields, kg_read_particles},
    {"large_pyramid", kBenchmarkFields, NULL},
    {"many_pyramids", kBenchmarkFields, NULL},
    {"smash", kBenchmarkFields, NULL},
    {"tumbler", kBenchmarkFields, NULL},
};

#define KG_GENERATOR_KIND_COUNT ((int)(sizeof kGeneratorKinds / sizeof kGeneratorKinds[0]))

static kg_result kg_read_generator(kg_loader* loader, const cJSON* json, const kg_json_path* path, int index)
{
    const kg_json_reader* reader = &loader->reader;
    const char* types[KG_GENERATOR_KIND_COUNT + 1];
    for (int i = 0; i < KG_GENERATOR_KIND_COUNT; ++i) {
        types[i] = kGeneratorKinds[i].type;
    }
    types[KG_GENERATOR_KIND_COUNT] = NULL;
    if (!cJSON_IsObject(json)) {
        return kg_json_fail(reader, path, "must be an object");
    }
    KG_TRY(kg_json_require(reader, json, path, "type"));
    int kind_index = 0;
    KG_TRY(kg_read_choice(reader, json, path, "type", types, &kind_index));
    const kg_gen_kind* kind = &kGeneratorKinds[kind_index];
    KG_TRY(kg_json_check_object(reader, json, path, kind->fields));
    char prefix[64];
    snprintf(prefix, sizeof prefix, "%s%d_", kind->type, index);
    const char* name = prefix;
    KG_TRY(kg_json_string(reader, json, path, "name", &name));
    if (kind->read) {
        return kind->read(loader, json, path, name);
    }
    return kg_generated(reader, path, kg_gen_benchmark_bodies(loader->scene, name, kind->type));
}

/* ---- forces ---- */

static const char* const kGravityFields[] = {"type", "acceleration", "bodies", NULL};
static const char* const kWindFields[] = {"type", "direction", "strength", "drag", "bodies", NULL};

/* Marks the bodies that entry names: one name, or every name starting with the text
 * before a final '*'. */
static kg_result kg_mark_bodies(kg_loader* loader, const char* entry, const kg_json_path* path,
                                unsigned char* marks)
{
    size_t length = strlen(entry);
    if (length == 0 || entry[length - 1] != '*') {
        int body = kg_scene_find_body(loader->scene, entry);
        if (body < 0) {
            return kg_json_fail(&loader->reader, path, "unknown body '%s'", entry);
        }
        marks[body] = 1;
        return KG_OK;
    }
    int found = 0;
    int count = kg_scene_body_count(loader->scene);
    for (int i = 0; i < count; ++i) {
        if (strncmp(kg_scene_body_name(loader->scene, i), entry, length - 1) == 0) {
            marks[i] = 1;
            found = 1;
        }
    }
    return found ? KG_OK : kg_json_fail(&loader->reader, path, "no body name matches '%s'", entry);
}

static kg_result kg_mark_force_bodies(kg_loader* loader, const cJSON* list, const kg_json_path* path,
                                      unsigned char* marks)
{
    KG_TRY(kg_json_check_array(&loader->reader, list, path));
    if (cJSON_GetArraySize(list) == 0) {
        return kg_json_fail(&loader->reader, path, "must name at least one body (leave it out for all bodies)");
    }
    int i = 0;
    for (const cJSON* item = list->child; item; item = item->next, ++i) {
        kg_json_path item_path = kg_json_path_index(path, i);
        if (!cJSON_IsString(item)) {
            return kg_json_fail(&loader->reader, &item_path, "must be a string (a body name)");
        }
        KG_TRY(kg_mark_bodies(loader, item->valuestring, &item_path, marks));
    }
    return KG_OK;
}

/* Resolves "bodies" into scene indices, each once, in scene order. */
static kg_result kg_read_force_bodies(kg_loader* loader, const cJSON* json, const kg_json_path* path,
                                      kg_scene_force* force)
{
    const cJSON* list = cJSON_GetObjectItemCaseSensitive(json, "bodies");
    if (!list) {
        return KG_OK;
    }
    int count = kg_scene_body_count(loader->scene);
    unsigned char* marks = calloc((size_t)(count > 0 ? count : 1), 1);
    int* indices = malloc((size_t)(count > 0 ? count : 1) * sizeof *indices);
    if (!marks || !indices) {
        free(marks);
        free(indices);
        return kg_json_fail_message(KG_ERROR_OUT_OF_MEMORY, "%s: out of memory", loader->reader.source);
    }
    kg_json_path list_path = kg_json_path_key(path, "bodies");
    kg_result r = kg_mark_force_bodies(loader, list, &list_path, marks);
    for (int i = 0; i < count; ++i) {
        if (marks[i]) {
            indices[force->body_count++] = i;
        }
    }
    free(marks);
    force->body_indices = indices;
    return r;
}

/* Whether kg_add_wind_applicator will take direction: the loader makes the computation it
 * makes (solve/forces.c: scaled by its largest component, then normalised), so that a
 * direction such as [1e-45, 0], whose scale overflows, is refused here with its path
 * rather than by the engine later without one. */
static int kg_wind_direction_usable(kg_vec2 direction)
{
    float largest = fmaxf(fabsf(direction.x), fabsf(direction.y));
    if (!(largest > 0.0f) || !isfinite(largest)) {
        return 0;
    }
    return kg_length_sq(kg_normalize(kg_scale(1.0f / largest, direction))) > 0.0f;
}

static kg_result kg_read_force_fields(kg_loader* loader, const cJSON* json, const kg_json_path* path,
                                      kg_scene_force* force)
{
    const kg_json_reader* reader = &loader->reader;
    if (force->type == KG_SCENE_FORCE_GRAVITY) {
        KG_TRY(kg_json_check_object(reader, json, path, kGravityFields));
        KG_TRY(kg_json_require(reader, json, path, "acceleration"));
        return kg_json_vec2(reader, json, path, "acceleration", &force->vector);
    }
    KG_TRY(kg_json_check_object(reader, json, path, kWindFields));
    KG_TRY(kg_json_require(reader, json, path, "direction"));
    KG_TRY(kg_json_require(reader, json, path, "strength"));
    KG_TRY(kg_json_vec2(reader, json, path, "direction", &force->vector));
    if (!kg_wind_direction_usable(force->vector)) {
        kg_json_path direction_path = kg_json_path_key(path, "direction");
        return kg_json_fail(reader, &direction_path, "must not be [0, 0] nor so short that it has no direction");
    }
    KG_TRY(kg_json_float(reader, json, path, "strength", KG_JSON_NON_NEGATIVE, &force->strength));
    return kg_json_float(reader, json, path, "drag", KG_JSON_NON_NEGATIVE, &force->drag);
}

static kg_result kg_read_force(kg_loader* loader, const cJSON* json, const kg_json_path* path)
{
    static const char* const types[] = {"gravity", "wind", NULL};
    if (!cJSON_IsObject(json)) {
        return kg_json_fail(&loader->reader, path, "must be an object");
    }
    KG_TRY(kg_json_require(&loader->reader, json, path, "type"));
    int type = 0;
    KG_TRY(kg_read_choice(&loader->reader, json, path, "type", types, &type));
    kg_scene_force force;
    memset(&force, 0, sizeof force);
    force.type = (kg_scene_force_type)type;
    KG_TRY(kg_read_force_fields(loader, json, path, &force));
    kg_result r = kg_read_force_bodies(loader, json, path, &force);
    if (r == KG_OK) {
        r = kg_scene_add_force(loader->scene, &force);
    }
    free((void*)force.body_indices);
    return r;
}

/* ---- tile maps ---- */

static const char* const kTiledMapFields[] = {"tiled", NULL};
static const char* const kInlineMapFields[] = {"origin", "tile_size", "friction", "restitution", "tiles", "layers",
                                               NULL};
static const char* const kTileFields[] = {"shape", "polygon", "circle", "one_way", NULL};
static const char* const kTileCircleFields[] = {"center", "radius", NULL};

/* The standard tile shapes by name (docs/scene-format.md). */
typedef struct kg_named_tile {
    const char* name;
    kg_tile_shape (*make)(int variant);
    int variant;
} kg_named_tile;

static kg_tile_shape kg_make_box(int variant) { (void)variant; return kg_tile_box(); }
static kg_tile_shape kg_make_platform(int variant) { (void)variant; return kg_tile_platform(); }
static kg_tile_shape kg_make_half(int side) { return kg_tile_half((kg_tile_side)side); }
static kg_tile_shape kg_make_slope(int corner) { return kg_tile_slope((kg_tile_corner)corner); }
static kg_tile_shape kg_make_slope_low(int corner) { return kg_tile_slope_low((kg_tile_corner)corner); }
static kg_tile_shape kg_make_slope_high(int corner) { return kg_tile_slope_high((kg_tile_corner)corner); }

static const kg_named_tile kNamedTiles[] = {
    {"box", kg_make_box, 0},
    {"platform", kg_make_platform, 0},
    {"half_bottom", kg_make_half, KG_TILE_SIDE_BOTTOM},
    {"half_right", kg_make_half, KG_TILE_SIDE_RIGHT},
    {"half_top", kg_make_half, KG_TILE_SIDE_TOP},
    {"half_left", kg_make_half, KG_TILE_SIDE_LEFT},
    {"slope_bottom_left", kg_make_slope, KG_TILE_BOTTOM_LEFT},
    {"slope_bottom_right", kg_make_slope, KG_TILE_BOTTOM_RIGHT},
    {"slope_top_right", kg_make_slope, KG_TILE_TOP_RIGHT},
    {"slope_top_left", kg_make_slope, KG_TILE_TOP_LEFT},
    {"slope_low_bottom_left", kg_make_slope_low, KG_TILE_BOTTOM_LEFT},
    {"slope_low_bottom_right", kg_make_slope_low, KG_TILE_BOTTOM_RIGHT},
    {"slope_low_top_right", kg_make_slope_low, KG_TILE_TOP_RIGHT},
    {"slope_low_top_left", kg_make_slope_low, KG_TILE_TOP_LEFT},
    {"slope_high_bottom_left", kg_make_slope_high, KG_TILE_BOTTOM_LEFT},
    {"slope_high_bottom_right", kg_make_slope_high, KG_TILE_BOTTOM_RIGHT},
    {"slope_high_top_right", kg_make_slope_high, KG_TILE_TOP_RIGHT},
    {"slope_high_top_left", kg_make_slope_high, KG_TILE_TOP_LEFT},
};

#define KG_NAMED_TILE_COUNT ((int)(sizeof kNamedTiles / sizeof kNamedTiles[0]))

static kg_result kg_read_named_tile(const kg_json_reader* reader, const cJSON* value, const kg_json_path* path,
                                    kg_tile_shape* out)
{
    for (int i = 0; i < KG_NAMED_TILE_COUNT; ++i) {
        if (strcmp(value->valuestring, kNamedTiles[i].name) == 0) {
            *out = kNamedTiles[i].make(kNamedTiles[i].variant);
            return KG_OK;
        }
    }
    return kg_json_fail(reader, path, "unknown tile shape \"%s\" (box, platform, half_SIDE, slope_CORNER, "
                                      "slope_low_CORNER, slope_high_CORNER; docs/scene-format.md)", value->valuestring);
}

static kg_result kg_read_tile_polygon(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                      kg_tile_shape* out)
{
    kg_json_path vertices_path = kg_json_path_key(path, "polygon");
    kg_vec2 points[KG_MAX_POLYGON_VERTICES];
    int count;
    KG_TRY(kg_read_vertex_list(reader, cJSON_GetObjectItemCaseSensitive(json, "polygon"), &vertices_path, points,
                               &count));
    *out = kg_tile_polygon(points, count);
    return KG_OK;
}

static kg_result kg_read_tile_circle(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                     kg_tile_shape* out)
{
    const cJSON* circle = cJSON_GetObjectItemCaseSensitive(json, "circle");
    kg_json_path circle_path = kg_json_path_key(path, "circle");
    kg_vec2 center = {0.5f, 0.5f};
    float radius = 0.0f;
    KG_TRY(kg_json_check_object(reader, circle, &circle_path, kTileCircleFields));
    KG_TRY(kg_json_require(reader, circle, &circle_path, "radius"));
    KG_TRY(kg_json_vec2(reader, circle, &circle_path, "center", &center));
    KG_TRY(kg_json_float(reader, circle, &circle_path, "radius", KG_JSON_POSITIVE, &radius));
    *out = kg_tile_circle(center, radius);
    return KG_OK;
}

/* {"shape": NAME} or {"polygon": [...]} or {"circle": {...}}, and "one_way". */
static kg_result kg_read_tile_object(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                     kg_tile_shape* out)
{
    KG_TRY(kg_json_check_object(reader, json, path, kTileFields));
    int kinds = kg_has(json, "shape") + kg_has(json, "polygon") + kg_has(json, "circle");
    if (kinds != 1) {
        return kg_json_fail(reader, path, "give exactly one of \"shape\", \"polygon\" or \"circle\"");
    }
    const cJSON* shape = cJSON_GetObjectItemCaseSensitive(json, "shape");
    kg_json_path shape_path = kg_json_path_key(path, "shape");
    if (shape && !cJSON_IsString(shape)) {
        return kg_json_fail(reader, &shape_path, "must be a string");
    }
    if (shape) {
        KG_TRY(kg_read_named_tile(reader, shape, &shape_path, out));
    } else if (kg_has(json, "polygon")) {
        KG_TRY(kg_read_tile_polygon(reader, json, path, out));
    } else {
        KG_TRY(kg_read_tile_circle(reader, json, path, out));
    }
    return kg_json_bool(reader, json, path, "one_way", &out->one_way);
}

/* A tile of the legend: a standard shape's name, or an object. */
static kg_result kg_read_legend_tile(const kg_json_reader* reader, const cJSON* value, const kg_json_path* path,
                                     kg_tile_shape* out)
{
    if (cJSON_IsString(value)) {
        KG_TRY(kg_read_named_tile(reader, value, path, out));
    } else if (cJSON_IsObject(value)) {
        KG_TRY(kg_read_tile_object(reader, value, path, out));
    } else {
        return kg_json_fail(reader, path, "must be a shape name or an object");
    }
    if (kg_tile_shape_check(out) != KG_OK) {
        char reason[256];
        snprintf(reason, sizeof reason, "%s", kg_last_error());
        return kg_json_fail(reader, path, "%s", reason);
    }
    return KG_OK;
}

/* The id of a grid character: 0 for ' ' and '.', its place in the legend plus 1, or -1. */
static int kg_legend_id(const char* keys, int count, char c)
{
    if (c == ' ' || c == '.') {
        return 0;
    }
    for (int i = 0; i < count; ++i) {
        if (keys[i] == c) {
            return i + 1;
        }
    }
    return -1;
}

/* "tiles": one character each, in order ids 1, 2, ...; shapes[0] stays empty. */
static kg_result kg_read_legend(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                kg_tile_shape* shapes, char* keys, int* count)
{
    const cJSON* tiles = cJSON_GetObjectItemCaseSensitive(json, "tiles");
    kg_json_path tiles_path = kg_json_path_key(path, "tiles");
    if (!cJSON_IsObject(tiles)) {
        return kg_json_fail(reader, &tiles_path, "must be an object");
    }
    shapes[0] = kg_tile_empty();
    int n = 0;
    for (const cJSON* tile = tiles->child; tile; tile = tile->next) {
        kg_json_path tile_path = kg_json_path_key(&tiles_path, tile->string);
        const char* key = tile->string;
        if (strlen(key) != 1 || key[0] == ' ' || key[0] == '.' || (unsigned char)key[0] > 126) {
            return kg_json_fail(reader, &tile_path, "tile keys are single characters other than ' ' and '.' "
                                                    "(which mean empty)");
        }
        if (kg_legend_id(keys, n, key[0]) > 0) {
            return kg_json_fail(reader, &tile_path, "field given twice");
        }
        KG_TRY(kg_read_legend_tile(reader, tile, &tile_path, &shapes[n + 1]));
        keys[n++] = key[0];
    }
    *count = n;
    return KG_OK;
}

/* The size of the grid: every layer an array of equally long strings, all alike. */
static kg_result kg_read_grid_size(const kg_json_reader* reader, const cJSON* layers, const kg_json_path* path,
                                   int* width, int* height)
{
    KG_TRY(kg_json_check_array(reader, layers, path));
    if (cJSON_GetArraySize(layers) < 1) {
        return kg_json_fail(reader, path, "must hold at least one layer");
    }
    *height = cJSON_GetArraySize(layers->child);
    *width = cJSON_IsArray(layers->child) && layers->child->child && cJSON_IsString(layers->child->child)
                 ? (int)strlen(layers->child->child->valuestring)
                 : 0;
    if (*width > 65536 || *height > 65536) {
        return kg_json_fail(reader, path, "the grid is %d x %d tiles; each side must be at most 65536", *width,
                            *height);
    }
    int l = 0;
    for (const cJSON* layer = layers->child; layer; layer = layer->next, ++l) {
        kg_json_path layer_path = kg_json_path_index(path, l);
        if (!cJSON_IsArray(layer) || cJSON_GetArraySize(layer) != *height || *height < 1) {
            return kg_json_fail(reader, &layer_path, "must be an array of %d rows (strings), like the first layer",
                                *height > 0 ? *height : 1);
        }
        int r = 0;
        for (const cJSON* row = layer->child; row; row = row->next, ++r) {
            kg_json_path row_path = kg_json_path_index(&layer_path, r);
            if (!cJSON_IsString(row) || (int)strlen(row->valuestring) != *width || *width < 1) {
                return kg_json_fail(reader, &row_path, "must be a string of %d tiles, like the first row",
                                    *width > 0 ? *width : 1);
            }
        }
    }
    return KG_OK;
}

/* The tiles of every layer, bottom row first. */
static kg_result kg_read_grid(const kg_json_reader* reader, const cJSON* layers, const kg_json_path* path,
                              const char* keys, int key_count, int width, int height, uint16_t* tiles)
{
    int l = 0;
    for (const cJSON* layer = layers->child; layer; layer = layer->next, ++l) {
        kg_json_path layer_path = kg_json_path_index(path, l);
        int r = 0;
        for (const cJSON* row = layer->child; row; row = row->next, ++r) {
            for (int x = 0; x < width; ++x) {
                int id = kg_legend_id(keys, key_count, row->valuestring[x]);
                if (id < 0) {
                    kg_json_path row_path = kg_json_path_index(&layer_path, r);
                    return kg_json_fail(reader, &row_path, "'%c' (column %d) is not one of the \"tiles\"",
                                        row->valuestring[x], x);
                }
                tiles[((size_t)l * (size_t)height + (size_t)(height - 1 - r)) * (size_t)width + (size_t)x] =
                    (uint16_t)id;
            }
        }
    }
    return KG_OK;
}

/* "tile_size": a number (square tiles) or [width, height]. */
static kg_result kg_read_tile_size(const kg_json_reader* reader, const cJSON* json, const kg_json_path* path,
                                   kg_vec2* out)
{
    const cJSON* size = cJSON_GetObjectItemCaseSensitive(json, "tile_size");
    kg_json_path size_path = kg_json_path_key(path, "tile_size");
    if (cJSON_IsNumber(size)) {
        float s = 0.0f;
        KG_TRY(kg_json_float(reader, json, path, "tile_size", KG_JSON_POSITIVE, &s));
        *out = (kg_vec2){s, s};
    } else if (size) {
        KG_TRY(kg_json_vec2(reader, json, path, "tile_size", out));
    }
    if (!(out->x > 0.0f && out->y > 0.0f)) {
        return kg_json_fail(reader, &size_path, "must be a number or [width, height], > 0");
    }
    return KG_OK;
}

static kg_result kg_read_inline_tilemap(kg_loader* loader, const cJSON* json, const kg_json_path* path)
{
    const kg_json_reader* reader = &loader->reader;
    kg_tilemap_def def = kg_default_tilemap_def();
    KG_TRY(kg_json_check_object(reader, json, path, kInlineMapFields));
    KG_TRY(kg_json_require(reader, json, path, "tiles"));
    KG_TRY(kg_json_require(reader, json, path, "layers"));
    KG_TRY(kg_json_vec2(reader, json, path, "origin", &def.origin));
    KG_TRY(kg_read_tile_size(reader, json, path, &def.tile_size));
    KG_TRY(kg_json_float(reader, json, path, "friction", KG_JSON_NON_NEGATIVE, &def.friction));
    KG_TRY(kg_json_float(reader, json, path, "restitution", KG_JSON_UNIT, &def.restitution));
    kg_tile_shape shapes[95];
    char keys[94];
    KG_TRY(kg_read_legend(reader, json, path, shapes, keys, &def.shape_count));
    const cJSON* layers = cJSON_GetObjectItemCaseSensitive(json, "layers");
    kg_json_path layers_path = kg_json_path_key(path, "layers");
    KG_TRY(kg_read_grid_size(reader, layers, &layers_path, &def.width, &def.height));
    def.layer_count = cJSON_GetArraySize(layers);
    size_t cells = (size_t)def.width * (size_t)def.height * (size_t)def.layer_count;
    if (cells > ((size_t)1 << 28)) {
        return kg_json_fail(reader, &layers_path, "the layers hold %zu cells; at most 2^28 are supported", cells);
    }
    for (int id = 1; id < def.shape_count + 1; ++id) {
        if (shapes[id].type == KG_TILE_SHAPE_CIRCLE && def.tile_size.x != def.tile_size.y) {
            kg_json_path size_path = kg_json_path_key(path, "tile_size");
            return kg_json_fail(reader, &size_path, "circle tiles need square tiles");
        }
    }
    uint16_t* tiles = malloc(cells * sizeof *tiles);
    if (!tiles) {
        return kg_json_fail_message(KG_ERROR_OUT_OF_MEMORY, "%s: out of memory", reader->source);
    }
    kg_result r = kg_read_grid(reader, layers, &layers_path, keys, def.shape_count, def.width, def.height, tiles);
    def.shape_count += 1;
    def.shapes = shapes;
    def.tiles = tiles;
    if (r == KG_OK) {
        r = kg_scene_add_tilemap(loader->scene, &def);
    }
    free(tiles);
    return r;
}

/* {"tiled": PATH}: a Tiled map, PATH relative to this file. */
static kg_result kg_read_tiled_tilemap(kg_loader* loader, const cJSON* json, const kg_json_path* path)
{
    const char* source = NULL;
    KG_TRY(kg_json_check_object(&loader->reader, json, path, kTiledMapFields));
    KG_TRY(kg_json_string(&loader->reader, json, path, "tiled", &source));
    char file[1024];
    kg_tiled_sibling_path(loader->reader.source, source, file, sizeof file);
    kg_result r = kg_tiled_load_into(loader->scene, file);
    if (r != KG_OK) {
        char reason[512];
        snprintf(reason, sizeof reason, "%s", kg_last_error());
        kg_json_path tiled_path = kg_json_path_key(path, "tiled");
        return kg_json_fail(&loader->reader, &tiled_path, "%s", reason);
    }
    return KG_OK;
}

static kg_result kg_read_tilemap_entry(kg_loader* loader, const cJSON* json, const kg_json_path* path)
{
    if (!cJSON_IsObject(json)) {
        return kg_json_fail(&loader->reader, path, "must be an object");
    }
    return kg_has(json, "tiled") ? kg_read_tiled_tilemap(loader, json, path)
                                 : kg_read_inline_tilemap(loader, json, path);
}

/* "tilemap": one map (an object) or several (an array of them). */
static kg_result kg_read_tilemaps(kg_loader* loader, const cJSON* root)
{
    const cJSON* tilemap = cJSON_GetObjectItemCaseSensitive(root, "tilemap");
    kg_json_path root_path = {""};
    kg_json_path path = kg_json_path_key(&root_path, "tilemap");
    if (!tilemap || !cJSON_IsArray(tilemap)) {
        return tilemap ? kg_read_tilemap_entry(loader, tilemap, &path) : KG_OK;
    }
    int i = 0;
    for (const cJSON* entry = tilemap->child; entry; entry = entry->next, ++i) {
        kg_json_path entry_path = kg_json_path_index(&path, i);
        KG_TRY(kg_read_tilemap_entry(loader, entry, &entry_path));
    }
    return KG_OK;
}

/* ---- the document ---- */

typedef kg_result kg_item_reader(kg_loader* loader, const cJSON* json, const kg_json_path* path, int index);

static kg_result kg_read_body_item(kg_loader* loader, const cJSON* json, const kg_json_path* path, int index)
{
    (void)index;
    return kg_read_body(loader, json, path);
}

static kg_result kg_read_force_item(kg_loader* loader, const cJSON* json, const kg_json_path* path, int index)
{
    (void)index;
    return kg_read_force(loader, json, path);
}

static kg_result kg_read_list(kg_loader* loader, const cJSON* root, const char* key, kg_item_reader* read)
{
    const cJSON* list = cJSON_GetObjectItemCaseSensitive(root, key);
    if (!list) {
        return KG_OK;
    }
    kg_json_path root_path = {""};
    kg_json_path list_path = kg_json_path_key(&root_path, key);
    KG_TRY(kg_json_check_array(&loader->reader, list, &list_path));
    int i = 0;
    for (const cJSON* item = list->child; item; item = item->next, ++i) {
        kg_json_path item_path = kg_json_path_index(&list_path, i);
        KG_TRY(read(loader, item, &item_path, i));
    }
    return KG_OK;
}

static kg_result kg_read_settings(kg_loader* loader, const cJSON* root)
{
    const kg_json_reader* reader = &loader->reader;
    kg_json_path root_path = {""};
    kg_world_def* def = kg_scene_world_def(loader->scene);
    const char* description = NULL;
    float dt = kg_scene_dt(loader->scene);
    int steps = 0;
    KG_TRY(kg_json_string(reader, root, &root_path, "description", &description));
    KG_TRY(kg_json_vec2(reader, root, &root_path, "gravity", &def->gravity));
    KG_TRY(kg_json_float(reader, root, &root_path, "dt", KG_JSON_POSITIVE, &dt));
    KG_TRY(kg_json_int(reader, root, &root_path, "steps", 0, 100000000, &steps));
    KG_TRY(kg_json_int(reader, root, &root_path, "substeps", 1, 64, &def->substeps));
    KG_TRY(kg_json_bool(reader, root, &root_path, "sleep", &def->enable_sleep));
    KG_TRY(kg_json_bool(reader, root, &root_path, "continuous", &def->enable_continuous));
    KG_TRY(kg_scene_set_dt(loader->scene, dt));
    return kg_scene_set_steps(loader->scene, steps);
}

/* Bodies first, then generators, so an explicit body's scene index is its place in
 * "bodies"; then the tile maps (a Tiled map's objects are bodies too); forces and joints
 * last, so they can name any body. A Tiled map document is read as a map. */
static kg_result kg_read_scene(kg_loader* loader, const cJSON* root)
{
    if (kg_tiled_is_map(root)) {
        return kg_tiled_read(loader->scene, root, loader->reader.source);
    }
    kg_json_path root_path = {""};
    KG_TRY(kg_json_check_object(&loader->reader, root, &root_path, kSceneFields));
    KG_TRY(kg_read_settings(loader, root));
    KG_TRY(kg_read_list(loader, root, "bodies", kg_read_body_item));
    KG_TRY(kg_read_list(loader, root, "generators", kg_read_generator));
    KG_TRY(kg_read_tilemaps(loader, root));
    KG_TRY(kg_read_list(loader, root, "forces", kg_read_force_item));
    KG_TRY(kg_read_scene_joints(&loader->reader, loader->scene, root)); /* they name any body */
    return kg_read_scene_state(loader->scene, root, &loader->reader);
}

/* Reads root into a new scene under limits, which the scene keeps only while it is read. */
static kg_result kg_read_new_scene(kg_loader* loader, const cJSON* root, const kg_scene_limits* limits)
{
    KG_TRY(kg_scene_create(&loader->scene));
    kg_scene_set_limits(loader->scene, limits);
    kg_result r = kg_read_scene(loader, root);
    kg_scene_limits defaults = kg_default_scene_limits();
    kg_scene_set_limits(loader->scene, &defaults);
    return r;
}

kg_result kg_scene_parse_limited(const char* json, size_t length, const char* source_name,
                                 const kg_scene_limits* limits, kg_scene** out)
{
    if (!out) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_parse: out is NULL");
    }
    *out = NULL;
    if (!json) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_parse: json is NULL");
    }
    kg_scene_limits defaults = kg_default_scene_limits();
    limits = limits ? limits : &defaults;
    KG_TRY(kg_check_scene_limits("kg_scene_parse", limits));
    kg_loader loader = {{source_name ? source_name : "(scene)"}, NULL};
    cJSON* root = NULL;
    KG_TRY(kg_json_parse(&loader.reader, json, length, &root));
    kg_result r = kg_read_new_scene(&loader, root, limits);
    cJSON_Delete(root);
    if (r != KG_OK) {
        kg_scene_destroy(loader.scene);
        return r;
    }
    *out = loader.scene;
    return KG_OK;
}

kg_result kg_scene_parse(const char* json, size_t length, const char* source_name, kg_scene** out)
{
    return kg_scene_parse_limited(json, length, source_name, NULL, out);
}

kg_result kg_scene_load_file_limited(const char* path, const kg_scene_limits* limits, kg_scene** out)
{
    if (!path || !out) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_load_file: NULL argument");
    }
    *out = NULL;
    kg_scene_limits defaults = kg_default_scene_limits();
    limits = limits ? limits : &defaults;
    KG_TRY(kg_check_scene_limits("kg_scene_load_file", limits));
    char* text = NULL;
    size_t length = 0;
    KG_TRY(kg_json_read_file(path, kg_scene_file_cap(limits, KG_SCENE_FILE_SIZE_MAX), &text, &length));
    kg_result r = kg_scene_parse_limited(text, length, path, limits, out);
    free(text);
    return r;
}

kg_result kg_scene_load_file(const char* path, kg_scene** out)
{
    return kg_scene_load_file_limited(path, NULL, out);
}
