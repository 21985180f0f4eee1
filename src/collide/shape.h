/* Turning a user's shape description into a collision shape, and its mass. Host only. */
#ifndef KG_SHAPE_H
#define KG_SHAPE_H

#include "collide/aabb.h"
#include "collide/chain.h"
#include "kgyro/body.h"

/* Points closer than this are one point; a polygon needs area above KG_MIN_AREA. */
#define KG_WELD_DISTANCE 1.0e-4f
#define KG_MIN_AREA 1.0e-8f

/* Validates def and builds the collision shape (hull for polygons; a capsule or a segment
 * as a 2-vertex polygon with a radius). */
kg_result kg_shape_build(const kg_shape_def* def, kg_shape* out);
/* Whether points make a chain (collide/chain.h): enough of them, finite, no segment of two
 * coinciding points. */
kg_result kg_check_chain_points(const kg_vec2* points, int count, int loop);
/* Segment i of a checked chain (i < count for a loop, count - 1 for a polyline), with its
 * ghosts: the points before and after it, where there are some. */
kg_shape kg_chain_segment_build(const kg_vec2* points, int count, int loop, int i);
/* Back from a collision shape to a description (for kg_body_get_shape). */
kg_shape_def kg_shape_describe(const kg_shape* shape);
/* Mass properties of a built shape of uniform density (zero for a segment). */
kg_mass_data kg_shape_mass_of(const kg_shape* shape, float density);

#endif
