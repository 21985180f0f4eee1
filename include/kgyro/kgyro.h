/* KineticGyro: a 2D rigid-body physics engine for games, on the CPU or any OpenCL device.
 *
 *   kg_world* world;
 *   kg_world_def def = kg_default_world_def();
 *   kg_create_world(&def, &world);
 *   kg_body_def bd = kg_default_body_def();
 *   bd.shape = kg_box_shape(1.0f, 1.0f);
 *   kg_body box;
 *   kg_create_body(world, &bd, &box);
 *   kg_world_step(world, 1.0f / 60.0f);
 *
 * Units are metres, kilograms, seconds and radians. */
#ifndef KGYRO_H
#define KGYRO_H

#include "types.h"
#include "world.h"
#include "body.h"
#include "shape.h"
#include "joint.h"
#include "force.h"
#include "collision.h"
#include "events.h"
#include "tilemap.h"
#include "debug_draw.h"
#include "query.h"
#include "snapshot.h"

#define KGYRO_VERSION_MAJOR 0
#define KGYRO_VERSION_MINOR 1
#define KGYRO_VERSION_PATCH 0

#endif
