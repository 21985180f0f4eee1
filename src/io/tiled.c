/* The Tiled map loader: Tiled's JSON map format (.tmj, or .json saved by Tiled) into a
 * scene. Orthogonal, finite maps; embedded and external (.tsj) tilesets; tile layers with
 * CSV or base64 data, uncompressed or zlib or gzip compressed (tiled_decode.c), flipped and
 * rotated tiles included; the collision shapes drawn in Tiled's tile collision editor;
 * object layers as bodies (polylines, and polygons on static layers, as chains; ellipses
 * as circles or capsules); point objects, and the objects of layers whose "physics" is
 * false, as markers; the custom properties of the map, layers and objects kept in the
 * scene (tiled_level.c). Tiled's y axis points
 * down, kgyro's up: the map's bottom-left corner is the world origin, pixels_per_meter
 * (a map property, the tile width by default) the scale. Anything this does not support is
 * an error naming the file, the JSON path and what is wrong (docs/tilemaps.md). */
#include "io/tiled.h"
#include "collide/shape.h"
#include "io/json_util.h"
#include "io/scene_limits.h"
#include "io/scene_props.h"
#include "io/tiled_decode.h"
#include "io/tiled_joints.h"
#include "io/tiled_level.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The flag bits of a global tile id (gid). */
#define KG_GID_FLIP_H 0x80000000u
#define KG_GID_FLIP_V 0x40000000u
#define KG_GID_FLIP_D 0x20000000u
#define KG_GID_ROTATE_HEX 0x10000000u
#define KG_GID_MASK 0x0FFFFFFFu
#define KG_FILE_NAME_MAX 1024
/* A tileset or map file bigger than this is not one: refused, not read. */
#define KG_FILE_SIZE_MAX ((size_t)1 << 28)
/* Shape points this far outside the tile (in tile sizes) are rounding, not design. */
#define KG_TILE_SLACK 1.0e-3f
/* How far (relative) an ellipse may be from round, or from twice as long as wide for a
 * capsule: hand-drawn sizes are rounded to pixels. */
#define KG_ELLIPSE_SLACK 1.0e-3f

typedef struct kg_tileset {
    int firstgid;
    int tilecount;
    cJSON* document;        /* an external tileset's file, owned */
    const cJSON* json;      /* the tileset object */
    kg_json_reader reader;  /* messages about it start "MAP: tilesets[i] (FILE)" when external */
    kg_json_path path;      /* the tileset in that file */
    char file[KG_FILE_NAME_MAX];
    char label[KG_FILE_NAME_MAX + 256];
} kg_tileset;

/* A flipped tile: its raw gid (flags included) and the id it got. */
typedef struct kg_variant {
    uint32_t raw;
    int id;
} kg_variant;

typedef struct kg_tiled {
    kg_scene* scene;
    kg_json_reader reader;
    int width, height, tile_width, tile_height;
    float pixels_per_meter;
    float friction, restitution;
    kg_tileset* tilesets;
    int tileset_count;
    /* shapes in Tiled's tile frame, as fractions of the tile, y down; index = gid */
    kg_tile_shape* raw_shapes;
    int gid_count;          /* largest gid + 1 */
    kg_variant* variants;
    int variant_count, variant_capacity;
    uint16_t* tiles;        /* layer after layer, bottom row first */
    int layer_count, layer_capacity;
    kg_vec2 object_offset;  /* of the object layer being read, pixels */
    int map_index;          /* this map's KG_SCENE_MAP index */
    int group;              /* the group layer being read (its scene layer index), or -1 */
    int layer_index;        /* the object layer being read (its scene layer index) */
    int layer_physics;      /* whether its objects are bodies (property "physics", default true) */
    kg_tiled_body* object_bodies; /* which object made which body, for joints to name them */
    int object_body_count, object_body_capacity;
    kg_tiled_joint* joints; /* the joint objects, made once every body is read */
    int joint_count, joint_capacity;
} kg_tiled;


static int kg_has(const cJSON* object, const char* key)
{
    return cJSON_GetObjectItemCaseSensitive(object, key) != NULL;
}

int kg_tiled_is_map(const cJSON* root)
{
    const cJSON* type = cJSON_GetObjectItemCaseSensitive(root, "type");
    return cJSON_IsObject(root) &&
           (kg_has(root, "tiledversion") || (cJSON_IsString(type) && strcmp(type->valuestring, "map") == 0));
}

/* ---- files ---- */

/* Parses the file at path, no larger than the limits of the scene it goes into allow. */
static kg_result kg_parse_file(const kg_scene* scene, const char* path, cJSON** out)
{
    char* text = NULL;
    size_t length = 0;
    size_t cap = kg_scene_file_cap(kg_scene_get_limits(scene), KG_FILE_SIZE_MAX);
    KG_TRY(kg_json_read_file(path, cap, &text, &length));
    kg_json_reader reader = {path};
    kg_result r = kg_json_parse(&reader, text, length, out);
    free(text);
    return r;
}

void kg_tiled_sibling_path(const char* from, const char* source, char* out, size_t size)
{
    const char* slash = strrchr(from, '/');
    if (source[0] == '/' || !slash) {
        snprintf(out, size, "%s", source);
    } else {
        snprintf(out, size, "%.*s/%s", (int)(slash - from), from, source);
    }
}

static int kg_ends_with(const char* text, const char* suffix)
{
    size_t n = strlen(text), m = strlen(suffix);
    return n >= m && strcmp(text + n - m, suffix) == 0;
}

/* ---- custom properties ---- */

/* The property object {"name", "type", "value"} called name, or NULL. */
static const cJSON* kg_property(const cJSON* owner, const char* name)
{
    const cJSON* list = cJSON_GetObjectItemCaseSensitive(owner, "properties");
    for (const cJSON* p = cJSON_IsArray(list) ? list->child : NULL; p; p = p->next) {
        const cJSON* key = cJSON_GetObjectItemCaseSensitive(p, "name");
        if (cJSON_IsString(key) && strcmp(key->valuestring, name) == 0) {
            return p;
        }
    }
    return NULL;
}

/* The path of a property: OWNER.properties.NAME (then .value). */
static kg_json_path kg_property_path(const kg_json_path* owner, const char* name)
{
    kg_json_path list = kg_json_path_key(owner, "properties");
    return kg_json_path_key(&list, name);
}

static kg_result kg_float_property(const kg_json_reader* reader, const cJSON* owner, const kg_json_path* path,
                                   const char* name, kg_json_rule rule, float* out)
{
    const cJSON* p = kg_property(owner, name);
    kg_json_path p_path = kg_property_path(path, name);
    return p ? kg_json_float(reader, p, &p_path, "value", rule, out) : KG_OK;
}

static kg_result kg_bool_property(const kg_json_reader* reader, const cJSON* owner, const kg_json_path* path,
                                  const char* name, int* out)
{
    const cJSON* p = kg_property(owner, name);
    kg_json_path p_path = kg_property_path(path, name);
    return p ? kg_json_bool(reader, p, &p_path, "value", out) : KG_OK;
}

static kg_result kg_string_property(const kg_json_reader* reader, const cJSON* owner, const kg_json_path* path,
                                    const char* name, const char** out)
{
    const cJSON* p = kg_property(owner, name);
    kg_json_path p_path = kg_property_path(path, name);
    return p ? kg_json_string(reader, p, &p_path, "value", out) : KG_OK;
}

/* ---- the map ---- */

/* The map's tiles in metres are what kg_create_tilemap gets (tile pixels / pixels_per_meter);
 * it refuses a size that is not finite, so a tiny pixels_per_meter (1e-38) is refused here
 * with its path rather than by the engine without one. */
static kg_result kg_check_tile_size_in_meters(const kg_tiled* t, const kg_json_reader* reader,
                                              const kg_json_path* root_path)
{
    float width = (float)t->tile_width / t->pixels_per_meter, height = (float)t->tile_height / t->pixels_per_meter;
    if (isfinite(width) && isfinite(height) && width > 0.0f && height > 0.0f) {
        return KG_OK;
    }
    kg_json_path path = kg_json_path_key(root_path, "properties.pixels_per_meter");
    return kg_json_fail(reader, &path, "%g is too small: the %d x %d pixel tiles would not be a finite size in metres",
                        (double)t->pixels_per_meter, t->tile_width, t->tile_height);
}

static kg_result kg_read_map_header(kg_tiled* t, const cJSON* root)
{
    const kg_json_reader* reader = &t->reader;
    kg_json_path root_path = {""};
    const char* orientation = "orthogonal";
    int infinite = 0;
    KG_TRY(kg_json_string(reader, root, &root_path, "orientation", &orientation));
    if (strcmp(orientation, "orthogonal") != 0) {
        kg_json_path p = kg_json_path_key(&root_path, "orientation");
        return kg_json_fail(reader, &p, "only orthogonal maps are supported (got \"%s\")", orientation);
    }
    KG_TRY(kg_json_bool(reader, root, &root_path, "infinite", &infinite));
    if (infinite) {
        kg_json_path p = kg_json_path_key(&root_path, "infinite");
        return kg_json_fail(reader, &p, "infinite maps are not supported: in Tiled, untick Map > Map Properties > "
                                        "Infinite, which gives the map a fixed size");
    }
    static const char* const sizes[] = {"width", "height", "tilewidth", "tileheight"};
    int* fields[] = {&t->width, &t->height, &t->tile_width, &t->tile_height};
    for (int i = 0; i < 4; ++i) {
        KG_TRY(kg_json_require(reader, root, &root_path, sizes[i]));
        KG_TRY(kg_json_int(reader, root, &root_path, sizes[i], 1, 65536, fields[i]));
    }
    if ((long long)t->width * t->height > (1LL << 28)) {
        return kg_json_fail(reader, &root_path, "the map is %d x %d tiles; at most 2^28 cells are supported",
                            t->width, t->height);
    }
    KG_TRY(kg_tiled_check_properties(reader, root, &root_path));
    t->pixels_per_meter = (float)t->tile_width;
    t->friction = 0.6f;
    KG_TRY(kg_float_property(reader, root, &root_path, "pixels_per_meter", KG_JSON_POSITIVE, &t->pixels_per_meter));
    KG_TRY(kg_check_tile_size_in_meters(t, reader, &root_path));
    KG_TRY(kg_float_property(reader, root, &root_path, "friction", KG_JSON_NON_NEGATIVE, &t->friction));
    return kg_float_property(reader, root, &root_path, "restitution", KG_JSON_UNIT, &t->restitution);
}

/* ---- tilesets ---- */

static kg_result kg_load_external_tileset(kg_tiled* t, kg_tileset* ts, const char* source, const kg_json_path* path)
{
    if (kg_ends_with(source, ".tsx")) {
        kg_json_path p = kg_json_path_key(path, "source");
        return kg_json_fail(&t->reader, &p, "'%s' is an XML tileset, which is not supported: in Tiled, open it and "
                                            "export it as a JSON tileset (.tsj), then use that", source);
    }
    kg_tiled_sibling_path(t->reader.source, source, ts->file, sizeof ts->file);
    kg_result r = kg_parse_file(t->scene, ts->file, &ts->document);
    if (r != KG_OK) {
        char reason[512];
        snprintf(reason, sizeof reason, "%s", kg_last_error());
        kg_json_path p = kg_json_path_key(path, "source");
        return kg_json_fail(&t->reader, &p, "cannot load the tileset: %s", reason);
    }
    snprintf(ts->label, sizeof ts->label, "%s: %s (%s)", t->reader.source, path->text, ts->file);
    ts->json = ts->document;
    ts->reader.source = ts->label;
    ts->path.text[0] = '\0';
    if (!cJSON_IsObject(ts->document)) {
        return kg_json_fail(&ts->reader, &ts->path, "must be an object (a Tiled tileset)");
    }
    return KG_OK;
}

/* The tileset entry at path: its first gid, and its data here or in its source file. */
static kg_result kg_read_tileset_entry(kg_tiled* t, const cJSON* entry, const kg_json_path* path, kg_tileset* ts)
{
    const kg_json_reader* reader = &t->reader;
    if (!cJSON_IsObject(entry)) {
        return kg_json_fail(reader, path, "must be an object");
    }
    KG_TRY(kg_json_require(reader, entry, path, "firstgid"));
    KG_TRY(kg_json_int(reader, entry, path, "firstgid", 1, (int)KG_GID_MASK, &ts->firstgid));
    const char* source = NULL;
    KG_TRY(kg_json_string(reader, entry, path, "source", &source));
    if (source) {
        return kg_load_external_tileset(t, ts, source, path);
    }
    ts->json = entry;
    ts->reader = *reader;
    ts->path = *path;
    return KG_OK;
}

/* A tileset's tile size must be the map's: bigger tiles would reach out of their cell. */
static kg_result kg_read_tileset_size(const kg_tiled* t, kg_tileset* ts)
{
    int width = 0, height = 0;
    static const char* const keys[] = {"tilewidth", "tileheight", "tilecount"};
    int* fields[] = {&width, &height, &ts->tilecount};
    for (int i = 0; i < 3; ++i) {
        KG_TRY(kg_json_require(&ts->reader, ts->json, &ts->path, keys[i]));
        KG_TRY(kg_json_int(&ts->reader, ts->json, &ts->path, keys[i], i < 2 ? 1 : 0, (int)KG_GID_MASK, fields[i]));
    }
    if (width != t->tile_width || height != t->tile_height) {
        kg_json_path p = kg_json_path_key(&ts->path, "tilewidth");
        return kg_json_fail(&ts->reader, &p, "its tiles are %d x %d pixels but the map's are %d x %d: tiles must "
                                             "fit their cells", width, height, t->tile_width, t->tile_height);
    }
    if ((long long)ts->firstgid + ts->tilecount > (long long)KG_MAX_TILE_ID + 1) {
        return kg_json_fail(&ts->reader, &ts->path, "its tiles reach gid %lld; at most %d tile ids are supported",
                            (long long)ts->firstgid + ts->tilecount - 1, KG_MAX_TILE_ID);
    }
    return KG_OK;
}

/* ---- tile collision shapes ---- */

/* A point of a collision object in the tile's pixels, as a fraction of the tile (y down). */
static kg_vec2 kg_tile_fraction(const kg_tiled* t, double x, double y)
{
    return (kg_vec2){(float)(x / t->tile_width), (float)(y / t->tile_height)};
}

/* Rotation by degrees clockwise on screen, which in Tiled's y-down frame is the usual
 * counter-clockwise formula. */
static kg_vec2 kg_rotate_screen(double x, double y, double degrees)
{
    double a = degrees * 3.14159265358979323846 / 180.0, c = cos(a), s = sin(a);
    return (kg_vec2){(float)(c * x - s * y), (float)(s * x + c * y)};
}

typedef struct kg_object_frame {
    double x, y, rotation; /* pixels; degrees clockwise about (x, y) */
} kg_object_frame;

static kg_result kg_read_object_frame(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                                      kg_object_frame* out)
{
    float x = 0.0f, y = 0.0f, rotation = 0.0f;
    KG_TRY(kg_json_float(reader, object, path, "x", KG_JSON_ANY, &x));
    KG_TRY(kg_json_float(reader, object, path, "y", KG_JSON_ANY, &y));
    KG_TRY(kg_json_float(reader, object, path, "rotation", KG_JSON_ANY, &rotation));
    *out = (kg_object_frame){x, y, rotation};
    return KG_OK;
}

/* An object point (relative to the object, pixels) in the layer's pixels. */
static kg_vec2 kg_object_point(const kg_object_frame* f, double x, double y)
{
    kg_vec2 r = kg_rotate_screen(x, y, f->rotation);
    return (kg_vec2){(float)(f->x + r.x), (float)(f->y + r.y)};
}

/* The kinds of Tiled objects. */
typedef enum kg_object_kind { KG_OBJECT_RECTANGLE, KG_OBJECT_ELLIPSE, KG_OBJECT_POLYGON, KG_OBJECT_POINT,
                              KG_OBJECT_POLYLINE, KG_OBJECT_TEXT, KG_OBJECT_TILE } kg_object_kind;

static kg_result kg_object_kind_of(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                                   kg_object_kind* out)
{
    if (!cJSON_IsObject(object)) {
        return kg_json_fail(reader, path, "must be an object");
    }
    int ellipse = 0, point = 0;
    KG_TRY(kg_json_bool(reader, object, path, "ellipse", &ellipse));
    KG_TRY(kg_json_bool(reader, object, path, "point", &point));
    *out = ellipse ? KG_OBJECT_ELLIPSE
           : point ? KG_OBJECT_POINT
           : kg_has(object, "polygon") ? KG_OBJECT_POLYGON
           : kg_has(object, "polyline") ? KG_OBJECT_POLYLINE
           : kg_has(object, "text") ? KG_OBJECT_TEXT
           : kg_has(object, "gid") ? KG_OBJECT_TILE
                                   : KG_OBJECT_RECTANGLE;
    return KG_OK;
}

/* Whether the points (in any order, at least 3) turn one way only, allowing straight runs. */
static int kg_is_convex(const kg_vec2* p, int count)
{
    float scale = 0.0f;
    for (int i = 0; i < count; ++i) {
        scale = fmaxf(scale, fmaxf(fabsf(p[i].x), fabsf(p[i].y)));
    }
    float tolerance = 1.0e-6f * scale * scale;
    int left = 0, right = 0;
    for (int i = 0; i < count; ++i) {
        kg_vec2 a = p[i], b = p[(i + 1) % count], c = p[(i + 2) % count];
        float turn = (b.x - a.x) * (c.y - b.y) - (b.y - a.y) * (c.x - b.x);
        left |= turn > tolerance;
        right |= turn < -tolerance;
    }
    return !(left && right);
}

/* A point of a polygon or polyline object ({"x": X, "y": Y}, relative to the object) in
 * the layer's pixels. */
static kg_result kg_read_object_vertex(const kg_json_reader* reader, const cJSON* point, const kg_json_path* path,
                                       const kg_object_frame* frame, kg_vec2* out)
{
    float x = 0.0f, y = 0.0f;
    KG_TRY(kg_json_require(reader, point, path, "x"));
    KG_TRY(kg_json_require(reader, point, path, "y"));
    KG_TRY(kg_json_float(reader, point, path, "x", KG_JSON_ANY, &x));
    KG_TRY(kg_json_float(reader, point, path, "y", KG_JSON_ANY, &y));
    *out = kg_object_point(frame, x, y);
    return KG_OK;
}

/* A polygon object's points in the layer's pixels (3 to 8, convex). */
static kg_result kg_read_polygon_points(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                                        const kg_object_frame* frame, kg_vec2* out, int* count)
{
    const cJSON* points = cJSON_GetObjectItemCaseSensitive(object, "polygon");
    kg_json_path points_path = kg_json_path_key(path, "polygon");
    KG_TRY(kg_json_check_array(reader, points, &points_path));
    int n = cJSON_GetArraySize(points);
    if (n < 3 || n > KG_MAX_POLYGON_VERTICES) {
        return kg_json_fail(reader, &points_path, "has %d points; a collision polygon needs 3 to %d: split it into "
                                                  "several objects or tiles", n, KG_MAX_POLYGON_VERTICES);
    }
    int i = 0;
    for (const cJSON* p = points->child; p; p = p->next, ++i) {
        kg_json_path p_path = kg_json_path_index(&points_path, i);
        KG_TRY(kg_read_object_vertex(reader, p, &p_path, frame, &out[i]));
    }
    if (!kg_is_convex(out, n)) {
        return kg_json_fail(reader, &points_path, "the polygon is concave; only convex shapes collide: split it "
                                                  "into convex pieces (in separate tiles or objects)");
    }
    *count = n;
    return KG_OK;
}

/* An object's size; both > 0. */
static kg_result kg_read_object_size(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                                     float* width, float* height)
{
    KG_TRY(kg_json_require(reader, object, path, "width"));
    KG_TRY(kg_json_require(reader, object, path, "height"));
    KG_TRY(kg_json_float(reader, object, path, "width", KG_JSON_POSITIVE, width));
    return kg_json_float(reader, object, path, "height", KG_JSON_POSITIVE, height);
}

/* An ellipse becomes a circle only when it is round; hint says what else it could be. */
static kg_result kg_check_round(const kg_json_reader* reader, const kg_json_path* path, float width, float height,
                                const char* hint)
{
    if (fabsf(width - height) > KG_ELLIPSE_SLACK * fmaxf(width, height)) {
        return kg_json_fail(reader, path, "the ellipse is %g x %g pixels; only round ellipses (circles) collide%s",
                            (double)width, (double)height, hint);
    }
    return KG_OK;
}

static kg_result kg_unsupported_object(const kg_json_reader* reader, const kg_json_path* path, kg_object_kind kind)
{
    const char* what = kind == KG_OBJECT_POLYLINE ? "a polyline has no area: draw a polygon instead"
                       : kind == KG_OBJECT_TILE   ? "tile objects are not supported as bodies: draw a rectangle, "
                                                    "ellipse or polygon (or give the object or its layer the "
                                                    "bool property \"physics\" false: a marker)"
                                                  : "this kind of object has no collision shape";
    return kg_json_fail(reader, path, "%s", what);
}

/* A tile collision object into a tile shape (fractions of the tile, y down). */
static kg_result kg_read_collision_object(const kg_tiled* t, const kg_tileset* ts, const cJSON* object,
                                          const kg_json_path* path, kg_tile_shape* out)
{
    const kg_json_reader* reader = &ts->reader;
    kg_object_kind kind = KG_OBJECT_RECTANGLE;
    kg_object_frame frame;
    KG_TRY(kg_object_kind_of(reader, object, path, &kind));
    KG_TRY(kg_read_object_frame(reader, object, path, &frame));
    if (kind == KG_OBJECT_POLYGON) {
        kg_vec2 points[KG_MAX_POLYGON_VERTICES];
        int count = 0;
        KG_TRY(kg_read_polygon_points(reader, object, path, &frame, points, &count));
        for (int i = 0; i < count; ++i) {
            points[i] = kg_tile_fraction(t, points[i].x, points[i].y);
        }
        *out = kg_tile_polygon(points, count);
        return KG_OK;
    }
    if (kind != KG_OBJECT_RECTANGLE && kind != KG_OBJECT_ELLIPSE) {
        return kg_unsupported_object(reader, path, kind);
    }
    float width = 0.0f, height = 0.0f;
    KG_TRY(kg_read_object_size(reader, object, path, &width, &height));
    if (kind == KG_OBJECT_ELLIPSE) {
        KG_TRY(kg_check_round(reader, path, width, height, ""));
        if (t->tile_width != t->tile_height) {
            return kg_json_fail(reader, path, "a circle collides only in square tiles (the map's are %d x %d)",
                                t->tile_width, t->tile_height);
        }
        kg_vec2 c = kg_object_point(&frame, 0.5 * width, 0.5 * height);
        *out = kg_tile_circle(kg_tile_fraction(t, c.x, c.y), 0.5f * width / (float)t->tile_width);
        return KG_OK;
    }
    kg_vec2 corners[4] = {kg_object_point(&frame, 0.0, 0.0), kg_object_point(&frame, width, 0.0),
                          kg_object_point(&frame, width, height), kg_object_point(&frame, 0.0, height)};
    for (int i = 0; i < 4; ++i) {
        corners[i] = kg_tile_fraction(t, corners[i].x, corners[i].y);
    }
    *out = kg_tile_polygon(corners, 4);
    return KG_OK;
}

/* The shape must lie within its tile. */
static kg_result kg_check_inside_tile(const kg_json_reader* reader, const kg_json_path* path,
                                      const kg_tile_shape* shape)
{
    float lo = -KG_TILE_SLACK, hi = 1.0f + KG_TILE_SLACK;
    int inside = 1;
    if (shape->type == KG_TILE_SHAPE_CIRCLE) {
        kg_vec2 c = shape->center;
        float r = shape->radius;
        inside = c.x - r >= lo && c.y - r >= lo && c.x + r <= hi && c.y + r <= hi;
    }
    for (int i = 0; shape->type == KG_TILE_SHAPE_POLYGON && i < shape->count; ++i) {
        kg_vec2 v = shape->vertices[i];
        inside &= v.x >= lo && v.y >= lo && v.x <= hi && v.y <= hi;
    }
    return inside ? KG_OK : kg_json_fail(reader, path, "the collision shape reaches outside its tile");
}

/* Lets the library judge the shape (a polygon with no area, above all), as it will when
 * the map is made. */
static kg_result kg_check_tile_shape(const kg_json_reader* reader, const kg_json_path* path,
                                     const kg_tile_shape* shape)
{
    if (kg_tile_shape_check(shape) == KG_OK) {
        return KG_OK;
    }
    char reason[256];
    snprintf(reason, sizeof reason, "%s", kg_last_error());
    return kg_json_fail(reader, path, "%s", reason);
}

/* The collision shape of a tileset's tile entry: none, or its one collision object. */
static kg_result kg_read_tile_shape(const kg_tiled* t, const kg_tileset* ts, const cJSON* tile,
                                    const kg_json_path* path, kg_tile_shape* out)
{
    const kg_json_reader* reader = &ts->reader;
    *out = kg_tile_empty();
    const cJSON* group = cJSON_GetObjectItemCaseSensitive(tile, "objectgroup");
    if (!group) {
        return KG_OK;
    }
    kg_json_path group_path = kg_json_path_key(path, "objectgroup");
    const cJSON* objects = cJSON_GetObjectItemCaseSensitive(group, "objects");
    kg_json_path objects_path = kg_json_path_key(&group_path, "objects");
    KG_TRY(kg_json_check_array(reader, objects, &objects_path));
    int found = 0, i = 0;
    for (const cJSON* object = objects->child; object; object = object->next, ++i) {
        kg_json_path object_path = kg_json_path_index(&objects_path, i);
        kg_object_kind kind = KG_OBJECT_RECTANGLE;
        KG_TRY(kg_object_kind_of(reader, object, &object_path, &kind));
        if (kind == KG_OBJECT_POINT) {
            continue; /* a marker: no area */
        }
        if (found++) {
            return kg_json_fail(reader, &object_path, "a second collision object: one convex shape per tile is "
                                                      "supported (split the tile, or draw the shapes' hull)");
        }
        KG_TRY(kg_read_collision_object(t, ts, object, &object_path, out));
        KG_TRY(kg_check_inside_tile(reader, &object_path, out));
        KG_TRY(kg_check_tile_shape(reader, &object_path, out));
    }
    int one_way = 0;
    KG_TRY(kg_tiled_check_properties(reader, tile, path));
    KG_TRY(kg_bool_property(reader, tile, path, "one_way", &one_way));
    if (one_way && out->type != KG_TILE_SHAPE_POLYGON) {
        kg_json_path p = kg_property_path(path, "one_way");
        return kg_json_fail(reader, &p, "only a tile with a rectangle or polygon collision shape can be one-way");
    }
    out->one_way = one_way;
    return KG_OK;
}

static kg_result kg_read_tileset_tiles(kg_tiled* t, const kg_tileset* ts)
{
    const cJSON* tiles = cJSON_GetObjectItemCaseSensitive(ts->json, "tiles");
    if (!tiles) {
        return KG_OK;
    }
    kg_json_path tiles_path = kg_json_path_key(&ts->path, "tiles");
    KG_TRY(kg_json_check_array(&ts->reader, tiles, &tiles_path));
    int i = 0;
    for (const cJSON* tile = tiles->child; tile; tile = tile->next, ++i) {
        kg_json_path tile_path = kg_json_path_index(&tiles_path, i);
        int id = -1;
        if (!cJSON_IsObject(tile)) {
            return kg_json_fail(&ts->reader, &tile_path, "must be an object");
        }
        KG_TRY(kg_json_require(&ts->reader, tile, &tile_path, "id"));
        KG_TRY(kg_json_int(&ts->reader, tile, &tile_path, "id", 0, ts->tilecount - 1, &id));
        KG_TRY(kg_read_tile_shape(t, ts, tile, &tile_path, &t->raw_shapes[ts->firstgid + id]));
    }
    return KG_OK;
}

static kg_result kg_read_tilesets(kg_tiled* t, const cJSON* root)
{
    kg_json_path root_path = {""};
    const cJSON* list = cJSON_GetObjectItemCaseSensitive(root, "tilesets");
    kg_json_path list_path = kg_json_path_key(&root_path, "tilesets");
    if (!list) {
        return KG_OK;
    }
    KG_TRY(kg_json_check_array(&t->reader, list, &list_path));
    t->tileset_count = cJSON_GetArraySize(list);
    t->tilesets = calloc((size_t)(t->tileset_count > 0 ? t->tileset_count : 1), sizeof *t->tilesets);
    if (!t->tilesets) {
        return kg_json_fail_message(KG_ERROR_OUT_OF_MEMORY, "%s: out of memory", t->reader.source);
    }
    int i = 0;
    t->gid_count = 1;
    for (const cJSON* entry = list->child; entry; entry = entry->next, ++i) {
        kg_json_path entry_path = kg_json_path_index(&list_path, i);
        KG_TRY(kg_read_tileset_entry(t, entry, &entry_path, &t->tilesets[i]));
        KG_TRY(kg_read_tileset_size(t, &t->tilesets[i]));
        int end = t->tilesets[i].firstgid + t->tilesets[i].tilecount;
        t->gid_count = end > t->gid_count ? end : t->gid_count;
    }
    t->raw_shapes = calloc((size_t)t->gid_count, sizeof *t->raw_shapes);
    if (!t->raw_shapes) {
        return kg_json_fail_message(KG_ERROR_OUT_OF_MEMORY, "%s: out of memory", t->reader.source);
    }
    for (i = 0; i < t->tileset_count; ++i) {
        KG_TRY(kg_read_tileset_tiles(t, &t->tilesets[i]));
    }
    return KG_OK;
}

/* ---- tile layers ---- */

/* Refuses a compression the loader cannot read, or one without base64. */
static kg_result kg_check_compression(const kg_json_reader* reader, const kg_json_path* path, const char* encoding,
                                      const char* compression)
{
    kg_json_path p = kg_json_path_key(path, "compression");
    if (compression[0] == '\0') {
        return KG_OK;
    }
    if (strcmp(compression, "zstd") == 0) {
        return kg_json_fail(reader, &p, "zstd-compressed layer data is not supported: in Tiled, set Map > Map "
                                        "Properties > Tile Layer Format to CSV, or to Base64 uncompressed, zlib or "
                                        "gzip compressed");
    }
    if (strcmp(compression, "zlib") != 0 && strcmp(compression, "gzip") != 0) {
        return kg_json_fail(reader, &p, "must be \"zlib\", \"gzip\" or \"\" (got \"%s\")", compression);
    }
    if (strcmp(encoding, "base64") != 0) {
        return kg_json_fail(reader, &p, "%s-compressed data must be base64-encoded (the encoding is \"%s\")",
                            compression, encoding);
    }
    return KG_OK;
}

/* A base64 layer (compressed or not) into its gids, row by row from the top. */
static kg_result kg_read_base64_gids(const kg_tiled* t, const cJSON* data, const kg_json_path* data_path,
                                     const char* compression, uint32_t* gids)
{
    size_t count = (size_t)t->width * (size_t)t->height;
    unsigned char* bytes = (unsigned char*)gids;
    const char* what = cJSON_IsString(data) ? kg_tiled_decode(data->valuestring, compression, bytes, 4 * count)
                                            : "is not a string";
    if (what && compression[0] == '\0') {
        return kg_json_fail(&t->reader, data_path, "must be base64 of %zu bytes (4 per cell)", 4 * count);
    }
    if (what) {
        return kg_json_fail(&t->reader, data_path, "the %s data %s; the layer needs %zu bytes (%d x %d tiles, 4 per "
                                                   "cell)", compression, what, 4 * count, t->width, t->height);
    }
    for (size_t i = 0; i < count; ++i) { /* little-endian, whatever the machine */
        const unsigned char* b = bytes + 4 * i;
        gids[i] = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
    }
    return KG_OK;
}

/* A CSV layer (in Tiled's JSON, an array of gids) into its gids, row by row from the top. */
static kg_result kg_read_csv_gids(const kg_tiled* t, const cJSON* data, const kg_json_path* data_path, uint32_t* gids)
{
    size_t count = (size_t)t->width * (size_t)t->height;
    if (!cJSON_IsArray(data) || (size_t)cJSON_GetArraySize(data) != count) {
        return kg_json_fail(&t->reader, data_path, "must be an array of %zu tile ids (width x height)", count);
    }
    size_t i = 0;
    for (const cJSON* item = data->child; item; item = item->next, ++i) {
        double v = cJSON_IsNumber(item) ? item->valuedouble : -1.0;
        if (!(v >= 0.0 && v <= 4294967295.0) || v != floor(v)) {
            kg_json_path p = kg_json_path_index(data_path, (int)i);
            return kg_json_fail(&t->reader, &p, "must be a tile id (an integer in [0, 4294967295])");
        }
        gids[i] = (uint32_t)v;
    }
    return KG_OK;
}

/* The layer's raw gids, row by row from the top, as Tiled stores them: CSV (a JSON array)
 * or base64, uncompressed or zlib or gzip compressed. */
static kg_result kg_read_layer_gids(const kg_tiled* t, const cJSON* layer, const kg_json_path* path, uint32_t* gids)
{
    const kg_json_reader* reader = &t->reader;
    const char* encoding = "csv";
    const char* compression = "";
    KG_TRY(kg_json_string(reader, layer, path, "encoding", &encoding));
    KG_TRY(kg_json_string(reader, layer, path, "compression", &compression));
    if (strcmp(encoding, "csv") != 0 && strcmp(encoding, "base64") != 0) {
        kg_json_path p = kg_json_path_key(path, "encoding");
        return kg_json_fail(reader, &p, "must be \"csv\" or \"base64\" (got \"%s\")", encoding);
    }
    KG_TRY(kg_check_compression(reader, path, encoding, compression));
    KG_TRY(kg_json_require(reader, layer, path, "data"));
    const cJSON* data = cJSON_GetObjectItemCaseSensitive(layer, "data");
    kg_json_path data_path = kg_json_path_key(path, "data");
    return strcmp(encoding, "base64") == 0 ? kg_read_base64_gids(t, data, &data_path, compression, gids)
                                           : kg_read_csv_gids(t, data, &data_path, gids);
}

/* Applies Tiled's flips to a point of the tile (fractions, y down): the diagonal flip
 * first (swapping x and y), then the horizontal and the vertical one. */
static kg_vec2 kg_flip_point(kg_vec2 p, uint32_t flags)
{
    if (flags & KG_GID_FLIP_D) {
        p = (kg_vec2){p.y, p.x};
    }
    if (flags & KG_GID_FLIP_H) {
        p.x = 1.0f - p.x;
    }
    if (flags & KG_GID_FLIP_V) {
        p.y = 1.0f - p.y;
    }
    return p;
}

/* A raw shape, flipped by flags, in kgyro's tile frame (y up). */
static kg_tile_shape kg_final_shape(kg_tile_shape shape, uint32_t flags)
{
    for (int i = 0; i < shape.count && i < KG_MAX_POLYGON_VERTICES; ++i) {
        kg_vec2 p = kg_flip_point(shape.vertices[i], flags);
        shape.vertices[i] = (kg_vec2){p.x, 1.0f - p.y};
    }
    kg_vec2 c = kg_flip_point(shape.center, flags);
    shape.center = (kg_vec2){c.x, 1.0f - c.y};
    return shape;
}

/* The tile id of a flipped tile: its shape flipped, under an id past the unflipped ones. */
static kg_result kg_variant_id(kg_tiled* t, uint32_t raw, const kg_json_path* path, int* id)
{
    for (int i = 0; i < t->variant_count; ++i) {
        if (t->variants[i].raw == raw) {
            *id = t->variants[i].id;
            return KG_OK;
        }
    }
    if ((raw & KG_GID_FLIP_D) && t->tile_width != t->tile_height) {
        return kg_json_fail(&t->reader, path, "a tile flipped diagonally (rotated) needs square tiles");
    }
    if (t->gid_count + t->variant_count > KG_MAX_TILE_ID) {
        return kg_json_fail(&t->reader, path, "more than %d distinct tiles and flipped tiles", KG_MAX_TILE_ID);
    }
    if (t->variant_count == t->variant_capacity) {
        int capacity = t->variant_capacity > 0 ? 2 * t->variant_capacity : 16;
        kg_variant* grown = realloc(t->variants, (size_t)capacity * sizeof *grown);
        if (!grown) {
            return kg_json_fail_message(KG_ERROR_OUT_OF_MEMORY, "%s: out of memory", t->reader.source);
        }
        t->variants = grown;
        t->variant_capacity = capacity;
    }
    *id = t->gid_count + t->variant_count;
    t->variants[t->variant_count++] = (kg_variant){raw, *id};
    return KG_OK;
}

static int kg_gid_in_tileset(const kg_tiled* t, uint32_t gid)
{
    for (int i = 0; i < t->tileset_count; ++i) {
        const kg_tileset* ts = &t->tilesets[i];
        if (gid >= (uint32_t)ts->firstgid && gid < (uint32_t)ts->firstgid + (uint32_t)ts->tilecount) {
            return 1;
        }
    }
    return 0;
}

/* The tile id of a raw gid: the gid itself, or a flipped variant's id. */
static kg_result kg_tile_id(kg_tiled* t, uint32_t raw, const kg_json_path* path, int* id)
{
    uint32_t gid = raw & KG_GID_MASK;
    if (gid == 0u) {
        *id = 0;
        return KG_OK;
    }
    if (raw & KG_GID_ROTATE_HEX) {
        return kg_json_fail(&t->reader, path, "the 120-degree rotation flag is for hexagonal maps only");
    }
    if (gid >= (uint32_t)t->gid_count || !kg_gid_in_tileset(t, gid)) {
        return kg_json_fail(&t->reader, path, "gid %u is in no tileset", (unsigned)gid);
    }
    if ((raw & ~KG_GID_MASK) == 0u) {
        *id = (int)gid;
        return KG_OK;
    }
    return kg_variant_id(t, raw, path, id);
}

static kg_result kg_add_layer_storage(kg_tiled* t)
{
    size_t cells = (size_t)t->width * (size_t)t->height;
    if ((long long)cells * (t->layer_count + 1) > (1LL << 28)) {
        return kg_json_fail_message(KG_ERROR_PARSE, "%s: the tile layers hold more than 2^28 cells in all", t->reader.source);
    }
    if (t->layer_count == t->layer_capacity) {
        int capacity = t->layer_capacity > 0 ? 2 * t->layer_capacity : 2;
        uint16_t* grown = realloc(t->tiles, (size_t)capacity * cells * sizeof *grown);
        if (!grown) {
            return kg_json_fail_message(KG_ERROR_OUT_OF_MEMORY, "%s: out of memory", t->reader.source);
        }
        t->tiles = grown;
        t->layer_capacity = capacity;
    }
    t->layer_count += 1;
    return KG_OK;
}

/* Converts a layer's gids (top row first) into the newest layer's tile ids (bottom first). */
static kg_result kg_store_layer(kg_tiled* t, const uint32_t* gids, const kg_json_path* path)
{
    KG_TRY(kg_add_layer_storage(t));
    uint16_t* layer = t->tiles + (size_t)(t->layer_count - 1) * (size_t)t->width * (size_t)t->height;
    kg_json_path data_path = kg_json_path_key(path, "data");
    for (int row = 0; row < t->height; ++row) {
        for (int x = 0; x < t->width; ++x) {
            int index = row * t->width + x, id = 0;
            kg_json_path cell_path = kg_json_path_index(&data_path, index);
            KG_TRY(kg_tile_id(t, gids[index], &cell_path, &id));
            layer[(t->height - 1 - row) * t->width + x] = (uint16_t)id;
        }
    }
    return KG_OK;
}

static kg_result kg_read_tile_layer(kg_tiled* t, const cJSON* layer, const kg_json_path* path)
{
    const kg_json_reader* reader = &t->reader;
    if (kg_has(layer, "chunks")) {
        kg_json_path p = kg_json_path_key(path, "chunks");
        return kg_json_fail(reader, &p, "chunked layers belong to infinite maps, which are not supported");
    }
    int width = t->width, height = t->height;
    float offset_x = 0.0f, offset_y = 0.0f;
    KG_TRY(kg_json_int(reader, layer, path, "width", 1, 65536, &width));
    KG_TRY(kg_json_int(reader, layer, path, "height", 1, 65536, &height));
    KG_TRY(kg_json_float(reader, layer, path, "offsetx", KG_JSON_ANY, &offset_x));
    KG_TRY(kg_json_float(reader, layer, path, "offsety", KG_JSON_ANY, &offset_y));
    if (width != t->width || height != t->height) {
        return kg_json_fail(reader, path, "the layer is %d x %d tiles but the map %d x %d", width, height, t->width,
                            t->height);
    }
    if (offset_x != 0.0f || offset_y != 0.0f) {
        return kg_json_fail(reader, path, "tile layer offsets are not supported (the layer is offset by %g, %g "
                                          "pixels)", (double)offset_x, (double)offset_y);
    }
    uint32_t* gids = malloc((size_t)width * (size_t)height * sizeof *gids);
    if (!gids) {
        return kg_json_fail_message(KG_ERROR_OUT_OF_MEMORY, "%s: out of memory", reader->source);
    }
    kg_result r = kg_read_layer_gids(t, layer, path, gids);
    if (r == KG_OK) {
        r = kg_store_layer(t, gids, path);
    }
    free(gids);
    return r;
}

/* ---- object layers ---- */

/* Tiled's pixels (y down from the map's top) to world metres (y up from its bottom). */
static kg_vec2 kg_world_point(const kg_tiled* t, kg_vec2 pixels)
{
    float map_height = (float)t->height * (float)t->tile_height;
    return (kg_vec2){pixels.x / t->pixels_per_meter, (map_height - pixels.y) / t->pixels_per_meter};
}

static const char* const kBodyTypeNames[] = {"static", "dynamic", "kinematic", "particle"};

static kg_result kg_read_body_type(const kg_json_reader* reader, const cJSON* owner, const kg_json_path* path,
                                   kg_body_type* type)
{
    const char* name = NULL;
    KG_TRY(kg_string_property(reader, owner, path, "type", &name));
    for (int i = 0; name && i < 4; ++i) {
        if (strcmp(name, kBodyTypeNames[i]) == 0) {
            *type = (kg_body_type)i;
            return KG_OK;
        }
    }
    if (!name) {
        return KG_OK;
    }
    kg_json_path p = kg_property_path(path, "type");
    return kg_json_fail(reader, &p, "must be \"static\", \"dynamic\", \"kinematic\" or \"particle\" (got \"%s\")",
                        name);
}

/* The body attributes in owner's custom properties (the layer's, then the object's). */
static kg_result kg_read_body_properties(const kg_json_reader* reader, const cJSON* owner, const kg_json_path* path,
                                         kg_body_def* def)
{
    KG_TRY(kg_tiled_check_properties(reader, owner, path));
    if (kg_property(owner, "density") && kg_property(owner, "mass")) {
        kg_json_path p = kg_property_path(path, "mass");
        return kg_json_fail(reader, &p, "give density or mass, not both");
    }
    if (kg_property(owner, "density")) {
        def->mass = 0.0f;
    }
    KG_TRY(kg_read_body_type(reader, owner, path, &def->type));
    KG_TRY(kg_float_property(reader, owner, path, "density", KG_JSON_NON_NEGATIVE, &def->density));
    KG_TRY(kg_float_property(reader, owner, path, "mass", KG_JSON_POSITIVE, &def->mass));
    KG_TRY(kg_float_property(reader, owner, path, "friction", KG_JSON_NON_NEGATIVE, &def->friction));
    KG_TRY(kg_float_property(reader, owner, path, "restitution", KG_JSON_UNIT, &def->restitution));
    KG_TRY(kg_float_property(reader, owner, path, "linear_damping", KG_JSON_NON_NEGATIVE, &def->linear_damping));
    KG_TRY(kg_float_property(reader, owner, path, "angular_damping", KG_JSON_NON_NEGATIVE, &def->angular_damping));
    KG_TRY(kg_bool_property(reader, owner, path, "fixed_rotation", &def->fixed_rotation));
    return kg_bool_property(reader, owner, path, "sensor", &def->is_sensor);
}

/* An ellipse object with the property "capsule" must be twice as long as wide. */
static kg_result kg_check_capsule_ellipse(const kg_json_reader* reader, const kg_json_path* path, float width,
                                          float height)
{
    float longer = fmaxf(width, height), shorter = fminf(width, height);
    if (fabsf(longer - 2.0f * shorter) > KG_ELLIPSE_SLACK * longer) {
        return kg_json_fail(reader, path, "the ellipse is %g x %g pixels; a capsule ellipse must be twice as long as "
                                          "wide", (double)width, (double)height);
    }
    return KG_OK;
}

/* The capsule of an ellipse's bounding box (metres, centred on the origin): the radius half
 * the short side, the centres on the long axis. */
static kg_shape_def kg_ellipse_capsule(float width, float height)
{
    float radius = 0.5f * fminf(width, height), reach = 0.5f * fabsf(width - height);
    kg_vec2 axis = width >= height ? (kg_vec2){reach, 0.0f} : (kg_vec2){0.0f, reach};
    return kg_capsule_shape((kg_vec2){-axis.x, -axis.y}, axis, radius);
}

/* An object's frame in the layer's pixels (the layer's offset applied), and the angle of
 * its body, from the object's rotation. */
static kg_result kg_read_layer_frame(const kg_tiled* t, const cJSON* object, const kg_json_path* path,
                                     kg_object_frame* frame)
{
    KG_TRY(kg_read_object_frame(&t->reader, object, path, frame));
    frame->x += t->object_offset.x;
    frame->y += t->object_offset.y;
    return KG_OK;
}

/* Tiled's rotation (degrees clockwise on screen) as kgyro's angle (radians, counter-clockwise). */
static float kg_world_angle(const kg_object_frame* frame)
{
    return (float)(-frame->rotation * 3.14159265358979323846 / 180.0);
}

static kg_result kg_read_body_frame(const kg_tiled* t, const cJSON* object, const kg_json_path* path,
                                    kg_object_frame* frame, kg_body_def* def)
{
    KG_TRY(kg_read_layer_frame(t, object, path, frame));
    def->angle = kg_world_angle(frame);
    return KG_OK;
}

/* An object's shape and pose: a rectangle turns about its top-left corner, the pose is its
 * centre; an ellipse is a circle (round) or a capsule (with the property "capsule"); a
 * polygon keeps the object's origin. */
static kg_result kg_read_body_shape(const kg_tiled* t, const cJSON* object, const kg_json_path* path,
                                    kg_object_kind kind, kg_body_def* def)
{
    const kg_json_reader* reader = &t->reader;
    kg_object_frame frame;
    KG_TRY(kg_read_body_frame(t, object, path, &frame, def));
    float ppm = t->pixels_per_meter;
    if (kind == KG_OBJECT_POLYGON) {
        kg_object_frame unturned = {0.0, 0.0, 0.0};
        kg_vec2 points[KG_MAX_POLYGON_VERTICES];
        int count = 0;
        KG_TRY(kg_read_polygon_points(reader, object, path, &unturned, points, &count));
        for (int i = 0; i < count; ++i) {
            points[i] = (kg_vec2){points[i].x / ppm, -points[i].y / ppm};
        }
        def->shape = kg_polygon_shape(points, count);
        def->position = kg_world_point(t, (kg_vec2){(float)frame.x, (float)frame.y});
        return KG_OK;
    }
    if (kind != KG_OBJECT_RECTANGLE && kind != KG_OBJECT_ELLIPSE) {
        return kg_unsupported_object(reader, path, kind);
    }
    float width = 0.0f, height = 0.0f;
    KG_TRY(kg_read_object_size(reader, object, path, &width, &height));
    def->position = kg_world_point(t, kg_object_point(&frame, 0.5 * width, 0.5 * height));
    int capsule = 0;
    KG_TRY(kg_bool_property(reader, object, path, "capsule", &capsule));
    if (capsule) {
        KG_TRY(kg_check_capsule_ellipse(reader, path, width, height));
        def->shape = kg_ellipse_capsule(width / ppm, height / ppm);
    } else if (kind == KG_OBJECT_ELLIPSE) {
        KG_TRY(kg_check_round(reader, path, width, height,
                              ", and ellipses twice as long as wide with the bool property \"capsule\" (capsules)"));
        def->shape = kg_circle_shape(0.5f * width / ppm);
    } else {
        def->shape = kg_box_shape(width / ppm, height / ppm);
    }
    return KG_OK;
}

/* Lets the library judge the shape and the mass, as the scene loader does. */
static kg_result kg_check_body(const kg_json_reader* reader, const kg_json_path* path, const kg_body_def* def)
{
    kg_mass_data mass;
    if (kg_shape_mass(&def->shape, 1.0f, &mass) != KG_OK) {
        char reason[256];
        snprintf(reason, sizeof reason, "%s", kg_last_error());
        return kg_json_fail(reader, path, "%s", reason);
    }
    int moves = def->type == KG_BODY_DYNAMIC || def->type == KG_BODY_PARTICLE;
    if (moves && def->mass == 0.0f && !(def->density > 0.0f)) {
        kg_json_path p = kg_property_path(path, "density");
        return kg_json_fail(reader, &p, "must be > 0 for a %s body", kBodyTypeNames[def->type]);
    }
    return KG_OK;
}

/* NAME#ID, with characters a scene name cannot hold replaced by '_'; "object#ID" unnamed. */
static void kg_body_name(const cJSON* object, char* out, size_t size)
{
    const cJSON* name = cJSON_GetObjectItemCaseSensitive(object, "name");
    const cJSON* id = cJSON_GetObjectItemCaseSensitive(object, "id");
    const char* base = cJSON_IsString(name) && name->valuestring[0] != '\0' ? name->valuestring : "object";
    snprintf(out, size, "%.40s#%.0f", base, cJSON_IsNumber(id) ? id->valuedouble : 0.0);
    for (char* c = out; *c; ++c) {
        int ok = (*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') ||
                 strchr("_-.:/#", *c) != NULL;
        *c = ok ? *c : '_';
    }
}

/* Adds the object's body, named after the object. */
static kg_result kg_add_object_body(kg_tiled* t, const cJSON* object, const kg_json_path* path,
                                    const kg_body_def* def)
{
    const kg_json_reader* reader = &t->reader;
    char name[64];
    kg_body_name(object, name, sizeof name);
    if (kg_scene_find_body(t->scene, name) >= 0) {
        return kg_json_fail(reader, path, "a second body named '%s' (object ids must be unique)", name);
    }
    if (kg_scene_add_body(t->scene, name, def) != KG_OK) {
        char reason[256];
        snprintf(reason, sizeof reason, "%s", kg_last_error());
        return kg_json_fail(reader, path, "%s", reason);
    }
    int index = kg_scene_body_count(t->scene) - 1;
    const char* class_name = "";
    KG_TRY(kg_tiled_object_class(reader, object, path, &class_name));
    KG_TRY(kg_scene_set_body_origin(t->scene, index, class_name, t->layer_index));
    int id = 0;
    KG_TRY(kg_json_int(reader, object, path, "id", 0, INT_MAX, &id));
    if (!kg_scene_grow((void**)&t->object_bodies, &t->object_body_capacity, t->object_body_count + 1,
                       sizeof *t->object_bodies)) {
        return kg_json_fail_message(KG_ERROR_OUT_OF_MEMORY, "%s: out of memory", reader->source);
    }
    t->object_bodies[t->object_body_count++] = (kg_tiled_body){id, index};
    return kg_tiled_keep_properties(t->scene, reader, object, path, KG_SCENE_BODY, index);
}

/* ---- chains: polylines, and polygons on static layers ---- */

/* Whether an object becomes a chain: a polyline (which has no area) always, a polygon on a
 * static body (an outline of any shape, concave included; a moving body's polygon stays a
 * convex polygon, which has mass). */
static int kg_is_chain_object(kg_object_kind kind, kg_body_type type)
{
    return kind == KG_OBJECT_POLYLINE || (kind == KG_OBJECT_POLYGON && type == KG_BODY_STATIC);
}

/* The points of a polyline or polygon object (its field key) in the body frame (metres, y
 * up), into a new array *out that the caller frees. */
static kg_result kg_read_chain_points(const kg_tiled* t, const cJSON* object, const kg_json_path* path,
                                      const char* key, kg_vec2** out, int* count)
{
    const kg_json_reader* reader = &t->reader;
    const cJSON* list = cJSON_GetObjectItemCaseSensitive(object, key);
    kg_json_path list_path = kg_json_path_key(path, key);
    KG_TRY(kg_json_check_array(reader, list, &list_path));
    int n = cJSON_GetArraySize(list);
    if (n > KG_MAX_CHAIN_POINTS) {
        return kg_json_fail(reader, &list_path, "has %d points; a chain may have at most %d", n, KG_MAX_CHAIN_POINTS);
    }
    *out = malloc((size_t)(n > 0 ? n : 1) * sizeof **out);
    if (!*out) {
        return kg_json_fail_message(KG_ERROR_OUT_OF_MEMORY, "%s: out of memory", reader->source);
    }
    *count = n;
    const kg_object_frame unturned = {0.0, 0.0, 0.0};
    int i = 0;
    for (const cJSON* p = list->child; p; p = p->next, ++i) {
        kg_json_path p_path = kg_json_path_index(&list_path, i);
        kg_vec2 pixels;
        KG_TRY(kg_read_object_vertex(reader, p, &p_path, &unturned, &pixels));
        (*out)[i] = (kg_vec2){pixels.x / t->pixels_per_meter, -pixels.y / t->pixels_per_meter};
    }
    return KG_OK;
}

/* Twice the signed area of a closed outline: > 0 counter-clockwise (y up). */
static double kg_twice_area(const kg_vec2* p, int count)
{
    double sum = 0.0;
    for (int i = 0; i < count; ++i) {
        kg_vec2 a = p[i], b = p[(i + 1) % count];
        sum += (double)a.x * b.y - (double)b.x * a.y;
    }
    return sum;
}

static void kg_reverse_points(kg_vec2* p, int count)
{
    for (int i = 0, j = count - 1; i < j; ++i, --j) {
        kg_vec2 swap = p[i];
        p[i] = p[j];
        p[j] = swap;
    }
}

/* Orders a chain object's points (body frame, y up, where a chain is solid on the left of
 * its direction) so that a polygon is solid inside whichever way it was drawn, and a
 * polyline solid on the right of the way it was drawn, as seen in Tiled: drawn left to
 * right it is ground, its normal up. chain_flip turns either over. */
static void kg_orient_chain(kg_vec2* points, int count, int loop, int flip)
{
    int reverse = loop ? kg_twice_area(points, count) < 0.0 : 1;
    if (reverse != flip) {
        kg_reverse_points(points, count);
    }
}

/* The body of a chain object, at the object's origin with no shape of its own, and its
 * chain of the given points (the body frame), after the checks kg_create_chain makes. */
static kg_result kg_add_chain_object(kg_tiled* t, const cJSON* object, const kg_json_path* path, kg_object_kind kind,
                                     kg_body_def* def, kg_vec2* points, int count)
{
    const kg_json_reader* reader = &t->reader;
    kg_chain_def chain = kg_default_chain_def();
    chain.points = points;
    chain.count = count;
    chain.loop = kind == KG_OBJECT_POLYGON;
    chain.friction = def->friction;
    chain.restitution = def->restitution;
    chain.category = def->category;
    chain.mask = def->mask;
    if (kg_check_chain_points(points, count, chain.loop) != KG_OK) { /* in drawing order: its indices are Tiled's */
        char reason[256];
        snprintf(reason, sizeof reason, "%s", kg_last_error());
        kg_json_path points_path = kg_json_path_key(path, chain.loop ? "polygon" : "polyline");
        return kg_json_fail(reader, &points_path, "%s", reason);
    }
    int flip = 0;
    KG_TRY(kg_bool_property(reader, object, path, "chain_flip", &flip));
    kg_orient_chain(points, count, chain.loop, flip);
    kg_object_frame frame;
    KG_TRY(kg_read_body_frame(t, object, path, &frame, def));
    def->position = kg_world_point(t, (kg_vec2){(float)frame.x, (float)frame.y});
    def->shape.type = KG_SHAPE_NONE;
    KG_TRY(kg_add_object_body(t, object, path, def));
    if (kg_scene_add_body_chain(t->scene, kg_scene_body_count(t->scene) - 1, &chain) != KG_OK) {
        char reason[256];
        snprintf(reason, sizeof reason, "%s", kg_last_error());
        return kg_json_fail(reader, path, "%s", reason);
    }
    return KG_OK;
}

/* A chain object. Only a polyline can be on a moving body's layer here: a polygon there
 * stays a convex polygon. */
static kg_result kg_read_object_chain(kg_tiled* t, const cJSON* object, const kg_json_path* path,
                                      kg_object_kind kind, kg_body_def* def)
{
    if (def->type != KG_BODY_STATIC && def->type != KG_BODY_KINEMATIC) {
        return kg_json_fail(&t->reader, path, "a polyline has no area: only static and kinematic bodies may have one "
                                              "(it becomes a chain); draw a polygon for a moving body");
    }
    kg_vec2* points = NULL;
    int count = 0;
    kg_result r = kg_read_chain_points(t, object, path, kind == KG_OBJECT_POLYGON ? "polygon" : "polyline", &points,
                                       &count);
    if (r == KG_OK) {
        r = kg_add_chain_object(t, object, path, kind, def, points, count);
    }
    free(points);
    return r;
}

/* The shape properties belong to the objects they shape: "capsule" to ellipses,
 * "chain_flip" to chains. */
static kg_result kg_check_shape_properties(const kg_json_reader* reader, const cJSON* object,
                                          const kg_json_path* path, kg_object_kind kind, int chain)
{
    int capsule = 0, flip = 0;
    KG_TRY(kg_bool_property(reader, object, path, "capsule", &capsule));
    KG_TRY(kg_bool_property(reader, object, path, "chain_flip", &flip));
    if (capsule && kind != KG_OBJECT_ELLIPSE) {
        kg_json_path p = kg_property_path(path, "capsule");
        return kg_json_fail(reader, &p, "only an ellipse object becomes a capsule");
    }
    if (flip && !chain) {
        kg_json_path p = kg_property_path(path, "chain_flip");
        return kg_json_fail(reader, &p, "only a chain (a polyline, or a polygon on a static layer) has a side to "
                                        "flip");
    }
    return KG_OK;
}

/* The marker shape of each kg_object_kind (a text object makes no marker). */
static const kg_scene_marker_shape kMarkerShapes[] = {KG_MARKER_RECTANGLE, KG_MARKER_ELLIPSE, KG_MARKER_POLYGON,
                                                      KG_MARKER_POINT, KG_MARKER_POLYLINE, KG_MARKER_POINT,
                                                      KG_MARKER_TILE};

/* Where a marker is: a point at its point; a rectangle, ellipse or tile object at its
 * centre (a tile object's origin is its bottom-left corner, the others' the top-left);
 * a polygon or polyline at its origin. Size in metres, 0 when it has none. */
static kg_result kg_read_marker_place(const kg_tiled* t, const cJSON* object, const kg_json_path* path,
                                      kg_object_kind kind, kg_scene_marker* m)
{
    const kg_json_reader* reader = &t->reader;
    kg_object_frame frame;
    float width = 0.0f, height = 0.0f;
    KG_TRY(kg_read_layer_frame(t, object, path, &frame));
    int sized = kind == KG_OBJECT_RECTANGLE || kind == KG_OBJECT_ELLIPSE || kind == KG_OBJECT_TILE;
    if (sized) {
        KG_TRY(kg_json_float(reader, object, path, "width", KG_JSON_NON_NEGATIVE, &width));
        KG_TRY(kg_json_float(reader, object, path, "height", KG_JSON_NON_NEGATIVE, &height));
    }
    double down = kind == KG_OBJECT_TILE ? -0.5 * height : 0.5 * height;
    kg_vec2 anchor = kg_object_point(&frame, 0.5 * width, down);
    m->position = kg_world_point(t, anchor);
    m->size = (kg_vec2){width / t->pixels_per_meter, height / t->pixels_per_meter};
    m->angle = kg_world_angle(&frame);
    return KG_OK;
}

/* An object that is not a body (a point, or any object where "physics" is false): a
 * marker, with its properties. */
static kg_result kg_add_object_marker(kg_tiled* t, const cJSON* object, const kg_json_path* path, kg_object_kind kind)
{
    const kg_json_reader* reader = &t->reader;
    kg_scene_marker m;
    memset(&m, 0, sizeof m);
    m.name = "";
    m.shape = kMarkerShapes[kind];
    m.layer = t->layer_index;
    KG_TRY(kg_json_string(reader, object, path, "name", &m.name));
    KG_TRY(kg_tiled_object_class(reader, object, path, &m.class_name));
    KG_TRY(kg_json_int(reader, object, path, "id", 0, INT_MAX, &m.id));
    KG_TRY(kg_read_marker_place(t, object, path, kind, &m));
    int index = 0;
    KG_TRY(kg_scene_add_marker(t->scene, &m, &index));
    return kg_tiled_keep_properties(t->scene, reader, object, path, KG_SCENE_MARKER, index);
}

/* A joint object (class "joint"), kept for kg_add_joints: a point object's point is its
 * anchor, a polyline's first two points its two ends (a distance joint's). */
static kg_result kg_keep_joint_object(kg_tiled* t, const cJSON* object, const kg_json_path* path, kg_object_kind kind)
{
    const kg_json_reader* reader = &t->reader;
    if (kind != KG_OBJECT_POINT && kind != KG_OBJECT_POLYLINE) {
        return kg_json_fail(reader, path, "a joint object must be a point or a polyline of two points");
    }
    kg_object_frame frame;
    KG_TRY(kg_read_layer_frame(t, object, path, &frame));
    kg_vec2 ends[2] = {kg_object_point(&frame, 0.0, 0.0), kg_object_point(&frame, 0.0, 0.0)};
    if (kind == KG_OBJECT_POLYLINE) {
        const cJSON* points = cJSON_GetObjectItemCaseSensitive(object, "polyline");
        kg_json_path points_path = kg_json_path_key(path, "polyline");
        KG_TRY(kg_json_check_array(reader, points, &points_path));
        if (cJSON_GetArraySize(points) != 2) {
            return kg_json_fail(reader, &points_path, "a joint's polyline has two points (its ends)");
        }
        for (int i = 0; i < 2; ++i) {
            kg_json_path at = kg_json_path_index(&points_path, i);
            KG_TRY(kg_read_object_vertex(reader, cJSON_GetArrayItem(points, i), &at, &frame, &ends[i]));
        }
    }
    if (!kg_scene_grow((void**)&t->joints, &t->joint_capacity, t->joint_count + 1, sizeof *t->joints)) {
        return kg_json_fail_message(KG_ERROR_OUT_OF_MEMORY, "%s: out of memory", reader->source);
    }
    t->joints[t->joint_count++] = (kg_tiled_joint){object, *path, kg_world_point(t, ends[0]), kg_world_point(t, ends[1])};
    return KG_OK;
}

/* The joints of the map's joint objects, now that every body is known. */
static kg_result kg_add_joints(kg_tiled* t)
{
    for (int i = 0; i < t->joint_count; ++i) {
        KG_TRY(kg_tiled_add_joint(&t->reader, t->scene, &t->joints[i], t->object_bodies, t->object_body_count));
    }
    return KG_OK;
}

static kg_result kg_read_object_body(kg_tiled* t, const cJSON* object, const kg_json_path* path,
                                     const kg_body_def* layer_def)
{
    const kg_json_reader* reader = &t->reader;
    kg_object_kind kind = KG_OBJECT_RECTANGLE;
    int physics = t->layer_physics;
    KG_TRY(kg_object_kind_of(reader, object, path, &kind));
    if (kind == KG_OBJECT_TEXT) {
        return kg_tiled_note(t->scene, reader, path, "a text object is ignored");
    }
    KG_TRY(kg_tiled_check_properties(reader, object, path));
    const char* class_name = "";
    KG_TRY(kg_tiled_object_class(reader, object, path, &class_name));
    if (strcmp(class_name, KG_TILED_JOINT_CLASS) == 0) {
        return kg_keep_joint_object(t, object, path, kind);
    }
    KG_TRY(kg_bool_property(reader, object, path, "physics", &physics));
    if (kind == KG_OBJECT_POINT || !physics) {
        return kg_add_object_marker(t, object, path, kind);
    }
    kg_body_def def = *layer_def;
    KG_TRY(kg_read_body_properties(reader, object, path, &def));
    int chain = kg_is_chain_object(kind, def.type);
    KG_TRY(kg_check_shape_properties(reader, object, path, kind, chain));
    if (chain) {
        return kg_read_object_chain(t, object, path, kind, &def);
    }
    KG_TRY(kg_read_body_shape(t, object, path, kind, &def));
    KG_TRY(kg_check_body(reader, path, &def));
    return kg_add_object_body(t, object, path, &def);
}

/* An object layer: bodies, or markers where its property "physics" is false. */
static kg_result kg_read_object_layer(kg_tiled* t, const cJSON* layer, const kg_json_path* path)
{
    const kg_json_reader* reader = &t->reader;
    kg_body_def layer_def = kg_default_body_def();
    if (t->layer_physics) {
        KG_TRY(kg_read_body_properties(reader, layer, path, &layer_def));
    }
    t->object_offset = (kg_vec2){0.0f, 0.0f};
    KG_TRY(kg_json_float(reader, layer, path, "offsetx", KG_JSON_ANY, &t->object_offset.x));
    KG_TRY(kg_json_float(reader, layer, path, "offsety", KG_JSON_ANY, &t->object_offset.y));
    const cJSON* objects = cJSON_GetObjectItemCaseSensitive(layer, "objects");
    kg_json_path objects_path = kg_json_path_key(path, "objects");
    KG_TRY(kg_json_check_array(reader, objects, &objects_path));
    int i = 0;
    for (const cJSON* object = objects->child; object; object = object->next, ++i) {
        kg_json_path object_path = kg_json_path_index(&objects_path, i);
        KG_TRY(kg_read_object_body(t, object, &object_path, &layer_def));
    }
    return KG_OK;
}

/* ---- layers ---- */

static kg_result kg_read_layers(kg_tiled* t, const cJSON* owner, const kg_json_path* path, int depth);

static kg_result kg_read_group(kg_tiled* t, const cJSON* group, const kg_json_path* path, int depth, int index)
{
    float offset_x = 0.0f, offset_y = 0.0f;
    KG_TRY(kg_json_float(&t->reader, group, path, "offsetx", KG_JSON_ANY, &offset_x));
    KG_TRY(kg_json_float(&t->reader, group, path, "offsety", KG_JSON_ANY, &offset_y));
    if (offset_x != 0.0f || offset_y != 0.0f) {
        return kg_json_fail(&t->reader, path, "group layer offsets are not supported (the group is offset by %g, "
                                              "%g pixels)", (double)offset_x, (double)offset_y);
    }
    int outer = t->group;
    t->group = index;
    kg_result r = kg_read_layers(t, group, path, depth + 1);
    t->group = outer;
    return r;
}

/* Records the layer (kind: its index in types) in the scene, with its properties;
 * *index gets its scene index. An object layer's "physics" says whether its objects are
 * bodies. */
static kg_result kg_add_scene_layer(kg_tiled* t, const cJSON* layer, const kg_json_path* path, int kind,
                                    const char* type, int* index)
{
    const kg_json_reader* reader = &t->reader;
    kg_scene_layer record = {"", type, t->map_index, t->group, kind == 0 ? t->layer_count : -1, 0};
    KG_TRY(kg_json_string(reader, layer, path, "name", &record.name));
    KG_TRY(kg_tiled_check_properties(reader, layer, path));
    t->layer_physics = 1;
    KG_TRY(kg_bool_property(reader, layer, path, "physics", &t->layer_physics));
    record.markers = kind == 1 && !t->layer_physics;
    KG_TRY(kg_scene_add_layer(t->scene, &record, index));
    t->layer_index = *index;
    return kg_tiled_keep_properties(t->scene, reader, layer, path, KG_SCENE_LAYER, *index);
}

static kg_result kg_read_layer(kg_tiled* t, const cJSON* layer, const kg_json_path* path, int depth)
{
    static const char* const types[] = {"tilelayer", "objectgroup", "group", "imagelayer", NULL};
    if (!cJSON_IsObject(layer)) {
        return kg_json_fail(&t->reader, path, "must be an object");
    }
    const char* type = NULL;
    KG_TRY(kg_json_require(&t->reader, layer, path, "type"));
    KG_TRY(kg_json_string(&t->reader, layer, path, "type", &type));
    int kind = 0, index = 0;
    while (types[kind] && strcmp(types[kind], type) != 0) {
        kind++;
    }
    if (!types[kind]) {
        kg_json_path p = kg_json_path_key(path, "type");
        return kg_json_fail(&t->reader, &p, "must be \"tilelayer\", \"objectgroup\", \"group\" or \"imagelayer\" "
                                            "(got \"%s\")", type);
    }
    KG_TRY(kg_add_scene_layer(t, layer, path, kind, type, &index));
    switch (kind) {
    case 0: return kg_read_tile_layer(t, layer, path);
    case 1: return kg_read_object_layer(t, layer, path);
    case 2: return kg_read_group(t, layer, path, depth, index);
    default: return kg_tiled_note(t->scene, &t->reader, path, "an image layer is ignored (pictures only)");
    }
}

/* The layers of the map or of a group, in order (groups flattened). */
static kg_result kg_read_layers(kg_tiled* t, const cJSON* owner, const kg_json_path* path, int depth)
{
    const cJSON* list = cJSON_GetObjectItemCaseSensitive(owner, "layers");
    kg_json_path list_path = kg_json_path_key(path, "layers");
    if (depth > 32) {
        return kg_json_fail(&t->reader, &list_path, "groups nested more than 32 deep");
    }
    KG_TRY(kg_json_require(&t->reader, owner, path, "layers"));
    KG_TRY(kg_json_check_array(&t->reader, list, &list_path));
    int i = 0;
    for (const cJSON* layer = list->child; layer; layer = layer->next, ++i) {
        kg_json_path layer_path = kg_json_path_index(&list_path, i);
        KG_TRY(kg_read_layer(t, layer, &layer_path, depth));
    }
    return KG_OK;
}

/* ---- the tile map ---- */

static kg_result kg_add_tilemap_to_scene(kg_tiled* t)
{
    if (t->layer_count == 0) {
        return KG_OK;
    }
    int shape_count = t->gid_count + t->variant_count;
    kg_tile_shape* shapes = calloc((size_t)shape_count, sizeof *shapes);
    if (!shapes) {
        return kg_json_fail_message(KG_ERROR_OUT_OF_MEMORY, "%s: out of memory", t->reader.source);
    }
    for (int id = 0; id < t->gid_count; ++id) {
        shapes[id] = kg_final_shape(t->raw_shapes[id], 0u);
    }
    for (int i = 0; i < t->variant_count; ++i) {
        const kg_variant* v = &t->variants[i];
        shapes[v->id] = kg_final_shape(t->raw_shapes[v->raw & KG_GID_MASK], v->raw);
    }
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = t->width;
    def.height = t->height;
    def.layer_count = t->layer_count;
    def.tile_size = (kg_vec2){(float)t->tile_width / t->pixels_per_meter, (float)t->tile_height / t->pixels_per_meter};
    def.shapes = shapes;
    def.shape_count = shape_count;
    def.tiles = t->tiles;
    def.friction = t->friction;
    def.restitution = t->restitution;
    kg_result r = kg_scene_add_tilemap(t->scene, &def);
    free(shapes);
    return r;
}

static void kg_tiled_free(kg_tiled* t)
{
    for (int i = 0; t->tilesets && i < t->tileset_count; ++i) {
        cJSON_Delete(t->tilesets[i].document);
    }
    free(t->tilesets);
    free(t->raw_shapes);
    free(t->variants);
    free(t->tiles);
    free(t->object_bodies);
    free(t->joints);
}

kg_result kg_tiled_read(kg_scene* scene, const cJSON* root, const char* path)
{
    kg_tiled t;
    memset(&t, 0, sizeof t);
    t.scene = scene;
    t.reader.source = path;
    t.group = -1;
    kg_json_path root_path = {""};
    kg_result r = cJSON_IsObject(root) ? KG_OK : kg_json_fail(&t.reader, &root_path, "must be an object");
    if (r == KG_OK) {
        r = kg_read_map_header(&t, root);
    }
    if (r == KG_OK) {
        r = kg_scene_add_map(scene, &t.map_index);
    }
    if (r == KG_OK) {
        r = kg_tiled_keep_properties(scene, &t.reader, root, &root_path, KG_SCENE_MAP, t.map_index);
    }
    if (r == KG_OK) {
        r = kg_read_tilesets(&t, root);
    }
    if (r == KG_OK) {
        r = kg_read_layers(&t, root, &root_path, 0);
    }
    if (r == KG_OK) {
        r = kg_add_joints(&t);
    }
    if (r == KG_OK) {
        r = kg_add_tilemap_to_scene(&t);
    }
    kg_tiled_free(&t);
    return r;
}

kg_result kg_tiled_load_into(kg_scene* scene, const char* path)
{
    cJSON* root = NULL;
    KG_TRY(kg_parse_file(scene, path, &root));
    kg_result r = kg_tiled_read(scene, root, path);
    cJSON_Delete(root);
    return r;
}

kg_result kg_scene_load_tiled_limited(const char* path, const kg_scene_limits* limits, kg_scene** out)
{
    if (!path || !out) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_scene_load_tiled: NULL argument");
    }
    *out = NULL;
    kg_scene_limits defaults = kg_default_scene_limits();
    limits = limits ? limits : &defaults;
    KG_TRY(kg_check_scene_limits("kg_scene_load_tiled", limits));
    kg_scene* scene = NULL;
    KG_TRY(kg_scene_create(&scene));
    kg_scene_set_limits(scene, limits);
    kg_result r = kg_tiled_load_into(scene, path);
    kg_scene_set_limits(scene, &defaults);
    if (r != KG_OK) {
        kg_scene_destroy(scene);
        return r;
    }
    *out = scene;
    return KG_OK;
}

kg_result kg_scene_load_tiled(const char* path, kg_scene** out)
{
    return kg_scene_load_tiled_limited(path, NULL, out);
}
