/* KineticGyro: debug draw. kg_world_draw walks the world and hands every shape, tile,
 * bounding box and contact to callbacks of the game's, so the physics shows in the game's
 * own renderer (kgyro render and kgyro view draw through it too):
 *
 *   kg_debug_draw draw = kg_default_debug_draw();
 *   draw.draw_solid_polygon = my_polygon;  // any callback left NULL is skipped
 *   draw.draw_solid_circle = my_circle;
 *   draw.context = my_renderer;
 *   draw.use_bounds = 1;                   // only what the camera sees
 *   draw.bounds = camera_box;
 *   kg_world_draw(world, &draw);
 *
 * Positions are world metres; vertices given with a transform are in its frame. Colours
 * say what a body is (the table below, docs/debug-draw.md). The OpenCL backend's state is
 * read back first, as the getters do, so a draw shows the current step. Nothing is
 * allocated: a huge world or tile map costs what lies inside bounds. */
#ifndef KGYRO_DEBUG_DRAW_H
#define KGYRO_DEBUG_DRAW_H

#include "types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A colour as 0xRRGGBB. */
typedef uint32_t kg_color;

/* A body's shapes take the colour of its state, the first that applies, in this order: */
#define KG_DEBUG_COLOR_FROZEN 0xFF3030u    /* frozen (kg_body_is_frozen): its state became non-finite */
#define KG_DEBUG_COLOR_ASLEEP 0x8C8C8Cu    /* asleep (kg_body_is_awake is 0) */
#define KG_DEBUG_COLOR_BULLET 0xFFC640u    /* an awake bullet (kg_body_def.bullet) */
#define KG_DEBUG_COLOR_STATIC 0x80E680u
#define KG_DEBUG_COLOR_KINEMATIC 0x8080E6u
#define KG_DEBUG_COLOR_DYNAMIC 0xE6B380u   /* an awake dynamic body */
#define KG_DEBUG_COLOR_PARTICLE 0x66CCFFu  /* an awake particle */
/* and a sensor shape (kg_body_shape_def.is_sensor), outlined only, this colour whatever its body: */
#define KG_DEBUG_COLOR_SENSOR 0xF07AF0u
/* Tile maps: a tile's shape filled, and the edges that collide (those not hidden by a
 * solid neighbour; a one-way tile's upward-facing ones), solid tiles and one-way ones apart. */
#define KG_DEBUG_COLOR_TILE 0x6E5C48u
#define KG_DEBUG_COLOR_TILE_EDGE 0xC8B496u
#define KG_DEBUG_COLOR_ONE_WAY 0x48606Eu
#define KG_DEBUG_COLOR_ONE_WAY_EDGE 0x96C8E0u
/* Overlays. */
#define KG_DEBUG_COLOR_AABB 0xE6E64Du
#define KG_DEBUG_COLOR_CONTACT_POINT 0xFF5050u
#define KG_DEBUG_COLOR_CONTACT_NORMAL 0x50E6FFu
#define KG_DEBUG_COLOR_JOINT 0x50C8A0u          /* a joint: its anchors, joined */

/* A rigid transform: a position and a rotation as (cos, sin) of its angle. A point p of
 * its frame is at (position.x + c p.x - s p.y, position.y + s p.x + c p.y). */
typedef struct kg_transform {
    kg_vec2 position;
    float c, s;
} kg_transform;

/* What kg_world_draw draws (kg_debug_draw.flags). */
typedef enum kg_debug_draw_flags {
    KG_DEBUG_DRAW_SHAPES = 1 << 0,          /* every shape of every body, particles as points */
    KG_DEBUG_DRAW_TILES = 1 << 1,           /* tile maps: the tiles inside bounds, and their edges */
    KG_DEBUG_DRAW_AABBS = 1 << 2,           /* each body's bounding box (kg_body_get_aabb) */
    KG_DEBUG_DRAW_CONTACT_POINTS = 1 << 3,  /* the points of last step's contacts */
    KG_DEBUG_DRAW_CONTACT_NORMALS = 1 << 4, /* their normals, from each point, normal_length long */
    KG_DEBUG_DRAW_MASS = 1 << 5,            /* each moving body's centre of mass, as a transform */
    KG_DEBUG_DRAW_JOINTS = 1 << 6           /* each joint: a segment from its anchor on a to its anchor
                                             * on b (a mouse joint: from its target), and a point at each */
} kg_debug_draw_flags;

/* Point sizes, in pixels across: a renderer draws them the same at every zoom. */
#define KG_DEBUG_PARTICLE_SIZE 3.2f
#define KG_DEBUG_CONTACT_SIZE 3.0f

/* The callbacks and what to draw. Start from kg_default_debug_draw(). Every callback gets
 * context last; a callback left NULL is skipped, and so is what only it would draw. */
typedef struct kg_debug_draw {
    /* A closed outline (sensor polygons, bounding boxes), vertices in order round it. */
    void (*draw_polygon)(const kg_vec2* vertices, int count, kg_color color, void* context);
    /* A filled convex polygon with its outline: vertices (counter-clockwise) in the frame
     * of transform, rounded by radius (0 for every polygon a user makes). Polygons and
     * boxes of bodies, polygon tiles. */
    void (*draw_solid_polygon)(kg_transform transform, const kg_vec2* vertices, int count, float radius,
                               kg_color color, void* context);
    /* A circle's outline (sensor circles and capsule ends). */
    void (*draw_circle)(kg_vec2 center, float radius, kg_color color, void* context);
    /* A filled circle centred at transform's position; its rotation is the body's, for a
     * line from the centre that shows the body turn. Circle shapes, particles with a
     * radius, circle tiles. */
    void (*draw_solid_circle)(kg_transform transform, float radius, kg_color color, void* context);
    /* A filled capsule: the points within radius of the segment p1 - p2. */
    void (*draw_capsule)(kg_vec2 p1, kg_vec2 p2, float radius, kg_color color, void* context);
    /* A line: segment shapes and chain segments, tile edges, sensor capsules' sides,
     * contact normals. */
    void (*draw_segment)(kg_vec2 p1, kg_vec2 p2, kg_color color, void* context);
    /* A frame's axes (KG_DEBUG_DRAW_MASS): a renderer draws x red and y green, say. */
    void (*draw_transform)(kg_transform transform, void* context);
    /* A dot size pixels across: particles without a shape, contact points. */
    void (*draw_point)(kg_vec2 point, float size, kg_color color, void* context);
    /* Optional: the colour body's shapes are drawn in, given the colour of its state. NULL
     * keeps the state's colour; a game highlights a selection with it, our renderer gives
     * each dynamic body a hue of its own. Not asked for sensor shapes. */
    kg_color (*body_color)(kg_body body, kg_color state_color, void* context);
    unsigned flags;      /* kg_debug_draw_flags, or-ed */
    int use_bounds;      /* non-zero: only what overlaps bounds is drawn */
    kg_aabb bounds;      /* world metres: a camera's view */
    float normal_length; /* m: a contact normal's length (KG_DEBUG_DRAW_CONTACT_NORMALS) */
    void* context;       /* handed to every callback */
} kg_debug_draw;

/* No callbacks, flags SHAPES | TILES | JOINTS, no bounds, normals 0.3 m long, no context. */
KG_API kg_debug_draw kg_default_debug_draw(void);

/* Draws the world through draw's callbacks, in layers: tiles, then each body's shapes
 * (bodies in slot order, a body's shapes in kg_body_get_shapes order), bounding boxes,
 * centres of mass, joints (in slot order), contacts. Fails with KG_ERROR_INVALID_ARGUMENT for a NULL world or
 * draw, non-finite bounds, or a negative normal_length. */
KG_API kg_result kg_world_draw(const kg_world* world, const kg_debug_draw* draw);

#ifdef __cplusplus
}
#endif
#endif
