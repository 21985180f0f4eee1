/* Joints drawn in Tiled (docs/tilemaps.md, "Joints"): an object of class "joint" on an
 * object layer. tiled.c finds them and their anchors; this turns each into an entry of a
 * scene file's "joints" (io/scene_joints.h) once every body of the map is read, so that a
 * joint may name an object that comes after it. */
#ifndef KG_TILED_JOINTS_H
#define KG_TILED_JOINTS_H

#include "io/json_util.h"
#include "kgyro/scene.h"

#define KG_TILED_JOINT_CLASS "joint"

/* A Tiled object made a body: its object id and its scene index. */
typedef struct kg_tiled_body {
    int object_id;
    int body;
} kg_tiled_body;

/* A joint object as found: the object (in the map's document), where it is, and its
 * anchors in metres: a point object's point twice, a polyline's first two points. */
typedef struct kg_tiled_joint {
    const cJSON* object;
    kg_json_path path;
    kg_vec2 anchor_a, anchor_b;
} kg_tiled_joint;

/* Adds the joint of j to scene. Its properties: "joint" (the kind: revolute, distance,
 * weld, prismatic, wheel, motor, mouse; required), "a" and "b" (the bodies: an object
 * property naming a Tiled object that became a body, or the body's scene name; "a"
 * absent: the world), "axis_x" and "axis_y" (a prismatic or wheel joint's axis, world
 * frame, y up), and every other option by the name its C field has. Checked as a scene
 * file's joint is, the messages naming the object's path. */
kg_result kg_tiled_add_joint(const kg_json_reader* reader, kg_scene* scene, const kg_tiled_joint* j,
                             const kg_tiled_body* bodies, int body_count);

#endif
