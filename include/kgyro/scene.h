/* KineticGyro: scenes, a world's contents described as data, built from JSON files,
 * from Tiled maps, from generators (pyramids, rain, the benchmark set) or from code. One
 * scene can be instantiated in a kgyro world, or (in bench/) in a peer engine, from the
 * same data. Part of the kgyro_io library (needs cJSON). */
#ifndef KGYRO_SCENE_H
#define KGYRO_SCENE_H

#include "types.h"
#include "world.h"
#include "body.h"
#include "shape.h"
#include "tilemap.h"
#include "joint.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct kg_scene kg_scene;

typedef enum kg_scene_force_type {
    KG_SCENE_FORCE_GRAVITY = 0, /* vector = extra acceleration */
    KG_SCENE_FORCE_WIND = 1     /* vector = direction; strength (N); drag (N s/m) */
} kg_scene_force_type;

typedef struct kg_scene_force {
    kg_scene_force_type type;
    kg_vec2 vector;
    float strength;
    float drag;
    int body_count;          /* 0 = all bodies */
    const int* body_indices; /* scene body indices, body_count of them */
} kg_scene_force;

/* What a loader lets a file ask for, so that a level from an untrusted source cannot make
 * the program allocate without end (an 80-byte scene can ask a generator for a million
 * bodies). A file over a limit is refused with KG_ERROR_PARSE (KG_ERROR_IO for the file
 * size) and "FILE: JSON.PATH: what is wrong", before the bodies are allocated. */
typedef struct kg_scene_limits {
    int max_bodies;        /* bodies in the whole scene, generators' and Tiled maps' included */
    size_t max_file_bytes; /* each file read: the scene, a Tiled map, a tileset */
} kg_scene_limits;

/* The limits the loaders without _limited use: max_bodies INT_MAX (no limit beyond each
 * generator's own range) and max_file_bytes 256 MiB. Every format also keeps its own
 * cap, whichever is lower applies: 64 MiB for a scene file, 256 MiB for a Tiled map or
 * tileset. Lower both for untrusted levels. */
KG_API kg_scene_limits kg_default_scene_limits(void);

/* Loading. On failure the result is KG_ERROR_IO or KG_ERROR_PARSE and kg_last_error()
 * reads "FILE: JSON.PATH: what is wrong", e.g. "a.json: bodies[3].shape.radius: must be > 0".
 * A Tiled map (.tmj or .json saved by Tiled) loads as a scene too (kg_scene_load_tiled). */
KG_API kg_result kg_scene_load_file(const char* path, kg_scene** out);
KG_API kg_result kg_scene_parse(const char* json, size_t length, const char* source_name, kg_scene** out);
/* A Tiled map (orthogonal, JSON format, docs/tilemaps.md): its tile layers become one tile
 * map (one layer each), the collision shapes drawn in its tilesets the tile shapes, its
 * object layers bodies and markers, its custom properties the scene's (below, "Tiled
 * levels"). Errors read "FILE: JSON.PATH: what is wrong", as above. */
KG_API kg_result kg_scene_load_tiled(const char* path, kg_scene** out);
/* The same, under limits (NULL = kg_default_scene_limits()). */
KG_API kg_result kg_scene_load_file_limited(const char* path, const kg_scene_limits* limits, kg_scene** out);
KG_API kg_result kg_scene_parse_limited(const char* json, size_t length, const char* source_name,
                                        const kg_scene_limits* limits, kg_scene** out);
KG_API kg_result kg_scene_load_tiled_limited(const char* path, const kg_scene_limits* limits, kg_scene** out);

/* Building from code. A name is 1 to 63 characters among letters, digits and _-.:/#
 * (so that it goes into a CSV field as is), unique in the scene; NULL means "body<i>"
 * with i the new body's index. Bodies are checked when instantiated, not here. */
KG_API kg_result kg_scene_create(kg_scene** out);
KG_API void kg_scene_destroy(kg_scene* scene);
KG_API kg_result kg_scene_add_body(kg_scene* scene, const char* name, const kg_body_def* def);
/* Adds a shape to body index (a compound body): def.shape is its first shape, these
 * follow in the order added. Checked when instantiated, not here. */
KG_API kg_result kg_scene_add_body_shape(kg_scene* scene, int index, const kg_body_shape_def* def);
/* Adds a chain (kg_create_chain) to body index, which must be static or kinematic; its
 * points are copied. It is checked here as kg_create_chain will check it (the points and
 * the material), so that the scene instantiates. A body's chains are made after its
 * shapes, in the order added. */
KG_API kg_result kg_scene_add_body_chain(kg_scene* scene, int index, const kg_chain_def* def);
KG_API kg_result kg_scene_add_force(kg_scene* scene, const kg_scene_force* force);
KG_API kg_world_def* kg_scene_world_def(kg_scene* scene); /* editable in place */
KG_API float kg_scene_dt(const kg_scene* scene);
KG_API int kg_scene_steps(const kg_scene* scene); /* suggested step count, 0 = none */
KG_API kg_result kg_scene_set_dt(kg_scene* scene, float dt);    /* > 0, default 1/60 */
KG_API kg_result kg_scene_set_steps(kg_scene* scene, int steps); /* >= 0 */
/* Makes kinematic body index turn rigidly about the world point pivot at its angular
 * velocity (a wall of a rotating container): kg_scene_step re-aims its linear velocity
 * every step so that it stays on its circle. A kinematic body's velocity is otherwise
 * constant, so without a pivot it would fly off along the tangent. */
KG_API kg_result kg_scene_set_body_pivot(kg_scene* scene, int index, kg_vec2 pivot);
/* Adds a tile map, made when the scene is instantiated. def, its shapes and its tiles are
 * copied; they are checked when instantiated, not here. */
KG_API kg_result kg_scene_add_tilemap(kg_scene* scene, const kg_tilemap_def* def);

/* Reading. */
KG_API int kg_scene_body_count(const kg_scene* scene);
KG_API const kg_body_def* kg_scene_body_def(const kg_scene* scene, int index);
KG_API const char* kg_scene_body_name(const kg_scene* scene, int index);
/* How many shapes body index has (1 + those added by kg_scene_add_body_shape; 0 for an
 * index out of range), and shape k of them: k = 0 is the body def's shape with its
 * material and filter. */
KG_API int kg_scene_body_shape_count(const kg_scene* scene, int index);
KG_API kg_result kg_scene_get_body_shape(const kg_scene* scene, int index, int k, kg_body_shape_def* out);
/* How many chains body index has (0 for an index out of range), and chain k of them: its
 * points point into the scene. */
KG_API int kg_scene_body_chain_count(const kg_scene* scene, int index);
KG_API kg_result kg_scene_get_body_chain(const kg_scene* scene, int index, int k, kg_chain_def* out);
/* The index of the body called name, or -1. */
KG_API int kg_scene_find_body(const kg_scene* scene, const char* name);
/* Non-zero when body index has a pivot (then written to out, which may be NULL). */
KG_API int kg_scene_body_pivot(const kg_scene* scene, int index, kg_vec2* out);
KG_API int kg_scene_force_count(const kg_scene* scene);
KG_API const kg_scene_force* kg_scene_get_force(const kg_scene* scene, int index);
KG_API int kg_scene_tilemap_count(const kg_scene* scene);
/* The scene's copy (shapes and tiles point into the scene). */
KG_API const kg_tilemap_def* kg_scene_get_tilemap(const kg_scene* scene, int index);

/* Tiled levels: properties, markers, classes. What a Tiled map holds beside its physics
 * (docs/tilemaps.md, "Properties, markers and notes"): the custom properties of the map,
 * of its layers and of its objects, the objects that are not bodies (markers: spawn
 * points, checkpoints, trigger areas), the objects' classes, and notes on what the loader
 * ignored. Scenes built otherwise have none of these. Strings point into the scene and
 * stay valid until it is destroyed or added to. */

typedef enum kg_scene_property_type {
    KG_PROPERTY_STRING = 0, /* string: text */
    KG_PROPERTY_INT = 1,    /* integer (and number) */
    KG_PROPERTY_FLOAT = 2,  /* number */
    KG_PROPERTY_BOOL = 3,   /* boolean */
    KG_PROPERTY_COLOR = 4,  /* color (and text, as Tiled wrote it: "#aarrggbb", "" unset) */
    KG_PROPERTY_FILE = 5,   /* text: the path as Tiled wrote it, relative to the map */
    KG_PROPERTY_OBJECT = 6  /* integer: the id of the object referred to, 0 for none */
} kg_scene_property_type;

/* One custom property. Only the fields of its type are set, the others are zero (NULL).
 * A Tiled class-typed property is flattened: each of its members set in the map is a
 * property "CLASS_PROPERTY.MEMBER" (nested classes go on: "a.b.c"), typed by its JSON
 * value: a string STRING, a whole number INT, another number FLOAT, true/false BOOL. */
typedef struct kg_scene_property {
    const char* name;
    kg_scene_property_type type;
    const char* text;  /* STRING, FILE, COLOR */
    int integer;       /* INT, OBJECT */
    double number;     /* FLOAT, and INT as a double */
    int boolean;       /* BOOL: 0 or 1 */
    uint32_t color;    /* COLOR: 0xAARRGGBB (alpha 0xFF when Tiled wrote #rrggbb) */
} kg_scene_property;

/* Whose properties: the Tiled map (index: 0, or the order of the maps a scene file names),
 * a layer (kg_scene_get_layer's index), a body (its scene index) or a marker. */
typedef enum kg_scene_owner {
    KG_SCENE_MAP = 0,
    KG_SCENE_LAYER = 1,
    KG_SCENE_BODY = 2,
    KG_SCENE_MARKER = 3
} kg_scene_owner;

/* How many properties the owner has (0 for none, or an index out of range), property k
 * of them in the order of the file, and the one called name. A body's properties are its
 * object's own, those the loader interprets (type, density, sensor...) included; its
 * layer's are read through the layer (kg_scene_body_layer). Absent: KG_ERROR_NOT_FOUND;
 * NULL arguments: KG_ERROR_INVALID_ARGUMENT. */
KG_API int kg_scene_property_count(const kg_scene* scene, kg_scene_owner owner, int index);
KG_API kg_result kg_scene_get_property(const kg_scene* scene, kg_scene_owner owner, int index, int k,
                                       kg_scene_property* out);
KG_API kg_result kg_scene_find_property(const kg_scene* scene, kg_scene_owner owner, int index, const char* name,
                                        kg_scene_property* out);
/* kg_scene_find_property(scene, KG_SCENE_BODY, body_index, name, out). */
KG_API kg_result kg_scene_body_property(const kg_scene* scene, int body_index, const char* name,
                                        kg_scene_property* out);

/* The object's class ("class" in Tiled 1.9, "type" before and from 1.10) of body index: "" when it
 * has none or was not made from a Tiled object, NULL for an index out of range. */
KG_API const char* kg_scene_body_class(const kg_scene* scene, int index);
/* The layer (kg_scene_get_layer's index) of the Tiled object body index was made from,
 * or -1. */
KG_API int kg_scene_body_layer(const kg_scene* scene, int index);

/* Every layer of the Tiled maps read into the scene, in file order, a group before the
 * layers in it. */
typedef struct kg_scene_layer {
    const char* name;  /* Tiled's (layer names need not be unique) */
    const char* kind;  /* "tilelayer", "objectgroup", "imagelayer" or "group" */
    int map;           /* which Tiled map (KG_SCENE_MAP's index) */
    int parent;        /* the group layer it is in, or -1 */
    int tile_layer;    /* a tile layer's layer in its tile map, else -1 */
    int markers;       /* an object layer whose objects are markers, not bodies */
} kg_scene_layer;

/* Layer index into out; KG_ERROR_INVALID_ARGUMENT for an index out of range or NULL out. */
KG_API int kg_scene_layer_count(const kg_scene* scene);
KG_API kg_result kg_scene_get_layer(const kg_scene* scene, int index, kg_scene_layer* out);
/* The index of the first layer called name, or -1. */
KG_API int kg_scene_find_layer(const kg_scene* scene, const char* name);

typedef enum kg_scene_marker_shape {
    KG_MARKER_POINT = 0,
    KG_MARKER_RECTANGLE = 1,
    KG_MARKER_ELLIPSE = 2,
    KG_MARKER_POLYGON = 3,
    KG_MARKER_POLYLINE = 4,
    KG_MARKER_TILE = 5 /* a tile object */
} kg_scene_marker_shape;

/* A Tiled object that is not a body: a point object on any layer, and every object
 * (text objects aside) on a layer with the bool property "physics" false or with that
 * property itself; its body properties (type, density...) are not read. Positions are
 * in metres in the frame of the bodies (y up, the map's bottom-left corner at the
 * origin). */
typedef struct kg_scene_marker {
    const char* name;        /* the object's name, "" when unnamed */
    const char* class_name;  /* its class (or type), "" when none */
    int id;                  /* its Tiled object id */
    kg_scene_marker_shape shape;
    kg_vec2 position;        /* a point: the point; a rectangle, ellipse or tile: its centre;
                              * a polygon or polyline: the object's origin */
    kg_vec2 size;            /* width and height (0 for a point, a polygon, a polyline) */
    float angle;             /* radians, counter-clockwise (Tiled's rotation, which is clockwise) */
    int layer;               /* kg_scene_get_layer's index */
} kg_scene_marker;

/* Marker index into out; KG_ERROR_INVALID_ARGUMENT for an index out of range or NULL out. */
KG_API int kg_scene_marker_count(const kg_scene* scene);
KG_API kg_result kg_scene_get_marker(const kg_scene* scene, int index, kg_scene_marker* out);
/* The index of the first marker called name, or -1. */
KG_API int kg_scene_find_marker(const kg_scene* scene, const char* name);

/* What the loader ignored, one note each ("FILE: JSON.PATH: an image layer is ignored"):
 * image layers, text objects. The first 100 are kept. */
KG_API int kg_scene_note_count(const kg_scene* scene);
KG_API const char* kg_scene_get_note(const kg_scene* scene, int index);

/* Joints (kgyro/joint.h, the scene file's "joints"). A scene joint names its bodies by
 * scene index (body_a -1: held to the world) and places its anchors in world
 * coordinates at the scene's start: anchor_a is body_a's anchor (a revolute, weld,
 * prismatic or wheel joint's "anchor", distance's end on body_a), anchor_b body_b's (the
 * file's "anchor_b", anchor_a's when it has none; the point of body_b a mouse joint
 * drags to mouse.target); axis the world
 * direction of a prismatic or wheel joint's axis. The definition of its type gives every
 * other option; its bodies, local anchors and local axis are ignored (kg_scene_instantiate
 * makes them).
 * Checked when instantiated (the kind's kg_create_*_joint), but for the body indices. */
typedef struct kg_scene_joint {
    kg_joint_type type;
    int body_a, body_b;
    kg_vec2 anchor_a, anchor_b;
    kg_vec2 axis;
    kg_revolute_joint_def revolute;
    kg_distance_joint_def distance;
    kg_weld_joint_def weld;
    kg_mouse_joint_def mouse;
    kg_prismatic_joint_def prismatic;
    kg_wheel_joint_def wheel;
    kg_motor_joint_def motor;
} kg_scene_joint;

KG_API kg_result kg_scene_add_joint(kg_scene* scene, const kg_scene_joint* joint);
KG_API int kg_scene_joint_count(const kg_scene* scene);
KG_API const kg_scene_joint* kg_scene_get_joint(const kg_scene* scene, int index);

/* Creates a world holding the scene, its bodies, forces, tile maps and joints (in scene order, so
 * kg_world_get_tilemaps lists them in that order). The world is made from
 * override_def when given (the scene's gravity and substeps are then not used), else
 * from the scene's own def; either way max_bodies, max_contacts and max_applicators are
 * grown to fit the scene. out_bodies, if not NULL, receives kg_scene_body_count()
 * handles in scene order. */
KG_API kg_result kg_scene_instantiate(const kg_scene* scene, const kg_world_def* override_def,
                                      kg_world** out_world, kg_body* out_bodies);

/* Steps a world made by kg_scene_instantiate: drives the pivoted kinematic bodies round
 * their pivots for this step, then calls kg_world_step. bodies are the handles that
 * kg_scene_instantiate returned. With no pivots this is just kg_world_step. */
KG_API kg_result kg_scene_step(const kg_scene* scene, kg_world* world, const kg_body* bodies, float dt);

/* Generators. Names: "pyramid_B" (base B), "stack_N", "rain_N" (mixed boxes and circles),
 * "particles_N", and the benchmark scenes "large_pyramid", "many_pyramids", "smash",
 * "tumbler" (as in Box2D v3's benchmark set). seed drives the random ones. An unknown
 * name or a size out of range is KG_ERROR_INVALID_ARGUMENT. docs/scene-format.md has
 * the layouts. */
KG_API kg_result kg_scene_generate(const char* name, uint32_t seed, kg_scene** out);
/* The same under limits (NULL = kg_default_scene_limits()): a name asking for more than
 * limits->max_bodies bodies is KG_ERROR_INVALID_ARGUMENT, "rain_N" and the like before
 * any body is made. For names typed by users of a game's console or a server's config. */
KG_API kg_result kg_scene_generate_limited(const char* name, uint32_t seed, const kg_scene_limits* limits,
                                           kg_scene** out);

/* ---- Saved worlds (docs/scene-format.md, "Saved worlds") ----
 *
 * A world saved as a scene continues bitwise where it stopped: kg_scene_instantiate
 * builds the scene's bodies and forces, then restores the world's snapshot that the scene
 * holds ("state" in the file: include/kgyro/snapshot.h), which brings back everything
 * else (contacts and their warm starts, sleep, tile maps with their edits, the step
 * count), and finally applies to each body the position, angle and velocities the scene
 * gives where they differ from the snapshot's (a level editor moved it). The scene's
 * bodies are the world's live bodies in slot order. A snapshot that cannot be restored
 * (corrupted, or of a world the scene does not describe) is refused by the loader, which
 * tries it: KG_ERROR_PARSE and "FILE: state.snapshot: why". */

/* Describes world as a scene: its settings and dt, each live body (type, position,
 * angle, velocities, every shape with its material, filter and sensor flag, chains
 * rebuilt from their segments, the mass of a body of one shape), its gravity and wind
 * applicators, its tile maps (cells as they are now), its live joints (anchors in world
 * coordinates now, every option as it is now), and its snapshot. On the OpenCL backend
 * the state is read back. */
KG_API kg_result kg_scene_from_world(const kg_world* world, kg_scene** out);
/* The same, the bodies named as in the scene the world was made from: bodies are the
 * handles kg_scene_instantiate gave for names_from's bodies; a live body that is one of
 * them keeps its name and its pivot, any other is body<i> (made unique). */
KG_API kg_result kg_scene_from_world_named(const kg_world* world, const kg_scene* names_from, const kg_body* bodies,
                                           kg_scene** out);

/* Writes scene as a JSON scene file that kg_scene_load_file reads back (floats as %.9g,
 * which gives back the same float; compound bodies and chains as "shapes", pivots, joints,
 * tile maps as inline grids; a snapshot as base64). What the reader would refuse is
 * KG_ERROR_UNSUPPORTED: a body of more than 64 shapes and chains, one of several shapes
 * with a mass, and in a scene without a state a tile map of more than 91 solid tile
 * shapes; KG_ERROR_IO when the file cannot be written. */
KG_API kg_result kg_scene_save_file(const kg_scene* scene, const char* path);

#ifdef __cplusplus
}
#endif
#endif
