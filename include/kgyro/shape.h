/* KineticGyro: the shapes of a body. A body holds any number of shapes (a compound
 * body), each with its own geometry (in the body frame), density, friction, restitution,
 * collision filter and sensor flag. kg_body_def.shape makes a body's first shape; more are
 * added and removed with kg_create_shape and kg_destroy_shape. Mass, centre of mass and
 * rotational inertia follow from the shapes (parallel axis theorem), recomputed whenever
 * a shape is added or removed, unless the body's mass was given explicitly
 * (kg_body_def.mass, kg_body_set_inverse_mass). Contacts are between shapes: two shapes of
 * one body never collide, and each touching pair of shapes has its own contact, feature
 * ids and warm starts. */
#ifndef KGYRO_SHAPE_H
#define KGYRO_SHAPE_H

#include "body.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Generational handle of a shape, like kg_body: stale forever once the shape (or its
 * body) is destroyed. The all-zero handle is never valid. */
typedef struct kg_shape_id {
    uint32_t index;
    uint32_t generation;
} kg_shape_id;

#define KG_NULL_SHAPE_INIT {0u, 0u}

/* A shape of a body. geometry is in the body frame: place a shape with
 * kg_offset_box_shape or kg_shape_moved. Two shapes a and b collide when
 * (a.category & b.mask) && (b.category & a.mask) and neither is a sensor. */
typedef struct kg_body_shape_def {
    kg_shape_def geometry;
    float density;      /* kg/m^2, >= 0 (0: massless) */
    float friction;     /* Coulomb coefficient, >= 0; a contact mixes sqrt(fa * fb) */
    float restitution;  /* in [0, 1]; a contact takes the larger */
    uint32_t category;
    uint32_t mask;
    int is_sensor;      /* non-zero: detects overlaps only (never pushes); its events come later */
    void* user_data;
} kg_body_shape_def;

/* Density 1, friction 0.6, restitution 0, category 1, mask all, solid, no geometry. */
KG_API kg_body_shape_def kg_default_body_shape_def(void);

/* def moved into a body frame: turned by angle (radians) about its own origin, then its
 * origin placed at center. Circles and polygons alike (kg_offset_box_shape is a box's
 * kg_shape_moved). */
KG_API kg_shape_def kg_shape_moved(kg_shape_def def, kg_vec2 center, float angle);

/* Adds a shape to body; its mass data is recomputed (unless set explicitly) and the body
 * is woken. Fails with KG_ERROR_INVALID_HANDLE for a stale body, INVALID_ARGUMENT or
 * DEGENERATE_SHAPE for a bad definition (a shape of type NONE is refused: only a
 * particle's first shape may be a point), OUT_OF_MEMORY when the pool cannot grow. */
KG_API kg_result kg_create_shape(kg_world* world, kg_body body, const kg_body_shape_def* def, kg_shape_id* out);
/* Removes a shape; its contacts end with the next step. The mass data of its body is
 * recomputed from the shapes left (kept as it was when none with mass is left). A body
 * left with no shape collides with nothing. */
KG_API kg_result kg_destroy_shape(kg_world* world, kg_shape_id shape);
KG_API int kg_shape_is_valid(const kg_world* world, kg_shape_id shape);

/* How many shapes body has (0 for a stale handle). */
KG_API int kg_body_shape_count(const kg_world* world, kg_body body);
/* Writes up to capacity of body's shapes to out, in a fixed order (creation order as long
 * as no shape of the world was destroyed: slot order), and their number to *count. */
KG_API kg_result kg_body_get_shapes(const kg_world* world, kg_body body, kg_shape_id* out, int capacity,
                                    int* count);

KG_API kg_result kg_shape_get_body(const kg_world* world, kg_shape_id shape, kg_body* out);
/* The shape's definition: its geometry as built, in the body frame (a polygon as its
 * counter-clockwise hull, as kg_body_get_shape gives it), and its material and filter. */
KG_API kg_result kg_shape_get_def(const kg_world* world, kg_shape_id shape, kg_body_shape_def* out);
KG_API kg_result kg_shape_set_friction(kg_world* world, kg_shape_id shape, float friction);
KG_API kg_result kg_shape_set_restitution(kg_world* world, kg_shape_id shape, float restitution);
KG_API kg_result kg_shape_set_filter(kg_world* world, kg_shape_id shape, uint32_t category, uint32_t mask);

/* A chain: a polyline (or, with loop, a closed outline) of one-sided segments that know
 * their neighbours, so that a body sliding along it never catches on a join (no ghost
 * collision), as tile-map edges. For terrain outlines and Tiled polylines. Each segment
 * is solid on the left of its direction from point i to point i + 1: its normal points
 * to the right. A ground listed right to left has its normal up; a loop listed
 * counter-clockwise is solid inside (a wall around a room: clockwise). A body behind a
 * segment gets nothing from it. Points are in the body frame; the chain keeps a copy. */
typedef struct kg_chain_def {
    const kg_vec2* points;
    int count;          /* at least 2 (3 for a loop); consecutive points distinct */
    int loop;           /* non-zero: the last point joins the first */
    float friction;     /* every segment's, as kg_body_shape_def's */
    float restitution;
    uint32_t category;
    uint32_t mask;
    void* user_data;    /* every segment's */
} kg_chain_def;

/* No points, friction 0.6, restitution 0, category 1, mask all. */
KG_API kg_chain_def kg_default_chain_def(void);

/* Adds a chain to a static or kinematic body (a body with no shape may be created for it:
 * kg_body_def.shape left at type NONE): one shape a segment, in order, listed by
 * kg_body_get_shapes and removable one by one with kg_destroy_shape. Segments have no
 * mass, so a dynamic body or a particle is refused (give it capsules or polygons). Fails,
 * changing nothing, with KG_ERROR_INVALID_HANDLE for a stale body, INVALID_ARGUMENT for
 * too few or non-finite points or a bad material, DEGENERATE_SHAPE naming the segment
 * whose points coincide, OUT_OF_MEMORY when the shape pool cannot grow. out_segments
 * (optional, NULL for none) receives the segments' shapes in order: count - 1 of them,
 * count for a loop. */
KG_API kg_result kg_create_chain(kg_world* world, kg_body body, const kg_chain_def* def, kg_shape_id* out_segments);

#ifdef __cplusplus
}
#endif
#endif
