/* KineticGyro: bodies, particles and their shapes. */
#ifndef KGYRO_BODY_H
#define KGYRO_BODY_H

#include "types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum kg_body_type {
    KG_BODY_STATIC = 0,    /* never moves; infinite mass */
    KG_BODY_DYNAMIC = 1,   /* moved by forces and contacts */
    KG_BODY_KINEMATIC = 2, /* moved by its velocity only; infinite mass */
    KG_BODY_PARTICLE = 3   /* mass-aggregate point: position and velocity, never rotates */
} kg_body_type;

typedef enum kg_shape_type {
    KG_SHAPE_NONE = 0,    /* a particle's point (it then needs a mass); a static or kinematic
                           * body's no shape at all (add shapes or a chain later) */
    KG_SHAPE_CIRCLE = 1,
    KG_SHAPE_POLYGON = 2, /* convex, up to KG_MAX_POLYGON_VERTICES; boxes are polygons */
    KG_SHAPE_CAPSULE = 3, /* two centres and a radius: a segment swept by a disc */
    KG_SHAPE_SEGMENT = 4  /* two points, no thickness: for static outlines */
} kg_shape_type;

/* A shape in the body's local frame (around the body origin). Build it with
 * kg_box_shape, kg_circle_shape, kg_polygon_shape, kg_capsule_shape or kg_segment_shape:
 * polygon vertices may come in any order; the convex hull is taken and duplicate or
 * collinear points are dropped. A capsule or a segment keeps its two points in
 * vertices[0] and vertices[1] (count 2), a capsule its radius in radius. */
typedef struct kg_shape_def {
    kg_shape_type type;
    kg_vec2 center;  /* circle centre */
    float radius;    /* circle or capsule radius */
    int count;       /* polygon vertex count; 2 for capsules and segments */
    kg_vec2 vertices[KG_MAX_POLYGON_VERTICES];
} kg_shape_def;

/* A box of the given full width and height, centred on the body origin. */
KG_API kg_shape_def kg_box_shape(float width, float height);
/* A box centred at center, turned by angle (radians), in the body frame. */
KG_API kg_shape_def kg_offset_box_shape(float width, float height, kg_vec2 center, float angle);
KG_API kg_shape_def kg_circle_shape(float radius);
KG_API kg_shape_def kg_polygon_shape(const kg_vec2* vertices, int count);
/* A capsule: the points within radius of the segment from center1 to center2. The
 * centres must be finite and at least 1e-4 m apart (nearer ones are an error: use a
 * circle), the radius finite and > 0. Its mass is a rectangle's and a disc's. */
KG_API kg_shape_def kg_capsule_shape(kg_vec2 center1, kg_vec2 center2, float radius);
/* A segment from point1 to point2 (finite, at least 1e-4 m apart), radius 0: for static
 * and kinematic outlines (ground lines, ramps, moving platforms). It has no area, hence no
 * mass, and two lines of no thickness that come to lie on each other have no side to push
 * apart to, so a dynamic body or a particle with a segment shape is refused
 * (KG_ERROR_INVALID_ARGUMENT; give it a thin capsule or box), and so is kg_shape_mass of a
 * segment. */
KG_API kg_shape_def kg_segment_shape(kg_vec2 point1, kg_vec2 point2);

/* Mass, centre of mass (body frame) and rotational inertia about the centre of mass. */
typedef struct kg_mass_data {
    float mass;
    kg_vec2 center;
    float inertia;
} kg_mass_data;

/* Exact mass properties of a shape of uniform density (kg/m^2); a segment has none. */
KG_API kg_result kg_shape_mass(const kg_shape_def* shape, float density, kg_mass_data* out);

typedef struct kg_body_def {
    kg_body_type type;
    kg_vec2 position;         /* body origin, world frame (m) */
    float angle;              /* radians; ignored for particles */
    kg_vec2 velocity;         /* m/s */
    float angular_velocity;   /* rad/s */
    kg_shape_def shape;       /* the body's first shape, with the density, friction, restitution,
                               * category and mask below (more: kg_create_shape) */
    float density;            /* kg/m^2, used when mass is 0 */
    float mass;               /* kg; > 0 overrides density (and then adding or removing shapes
                               * leaves the mass as given) */
    float friction;           /* Coulomb coefficient, >= 0 */
    float restitution;        /* 0 = no bounce, 1 = elastic, in [0, 1] */
    float linear_damping;     /* 1/s, >= 0 */
    float angular_damping;    /* 1/s, >= 0 */
    uint32_t category;        /* collision filtering: a and b collide when */
    uint32_t mask;            /* (a.category & b.mask) && (b.category & a.mask) */
    int fixed_rotation;       /* non-zero: infinite rotational inertia */
    int bullet;               /* non-zero (dynamic bodies only): when fast, also kept from
                               * passing through the other (non-bullet) dynamic bodies and the
                               * kinematic ones; every dynamic body is kept from passing
                               * through static bodies and tile maps anyway
                               * (kg_world_def.enable_continuous) */
    int is_sensor;            /* non-zero: the first shape is a sensor (kg_body_shape_def.
                               * is_sensor): it pushes nothing and reports what overlaps it */
    int enable_pre_solve;     /* non-zero: its contacts go through the world's pre-solve
                               * callback (kgyro/collision.h), which may switch them off */
    void* user_data;
} kg_body_def;

/* A dynamic body at the origin with density 1, friction 0.6, restitution 0, no shape. */
KG_API kg_body_def kg_default_body_def(void);

KG_API kg_result kg_create_body(kg_world* world, const kg_body_def* def, kg_body* out_body);
/* Whether kg_create_body would accept def (pool capacity aside), with the same error. */
KG_API kg_result kg_check_body_def(const kg_body_def* def);
KG_API kg_result kg_destroy_body(kg_world* world, kg_body body);
KG_API int kg_body_is_valid(const kg_world* world, kg_body body);
/* A body whose state became non-finite (an overflowing force, say) is frozen at its last
 * finite pose, reported once on stderr, and left out of the simulation so it cannot
 * poison its neighbours; forces and impulses on it are ignored. Setting its transform or
 * velocity brings it back. */
KG_API int kg_body_is_frozen(const kg_world* world, kg_body body);
/* Sleeping (kg_world_def.enable_sleep): a body at rest with its whole island is asleep,
 * not simulated, until a moving body touches it or it is changed through the API (every
 * setter, force and impulse wakes the body; removing or moving a body, or changing its
 * filter, also wakes what rested on it). kg_body_wake wakes it without changing it. */
KG_API int kg_body_is_awake(const kg_world* world, kg_body body);
KG_API kg_result kg_body_wake(kg_world* world, kg_body body);

/* The state a renderer or game reads: origin position, angle and velocities. */
typedef struct kg_body_state {
    kg_vec2 position;
    float angle;
    kg_vec2 velocity;
    float angular_velocity;
} kg_body_state;

KG_API kg_result kg_body_get_state(const kg_world* world, kg_body body, kg_body_state* out);
/* Reads the states of count bodies in one call (the cheap way to feed a renderer). */
KG_API kg_result kg_world_get_body_states(const kg_world* world, const kg_body* bodies, int count,
                                          kg_body_state* out);
KG_API kg_result kg_body_get_position(const kg_world* world, kg_body body, kg_vec2* out);
KG_API kg_result kg_body_get_angle(const kg_world* world, kg_body body, float* out);
KG_API kg_result kg_body_get_velocity(const kg_world* world, kg_body body, kg_vec2* out);
KG_API kg_result kg_body_get_angular_velocity(const kg_world* world, kg_body body, float* out);
KG_API kg_result kg_body_get_type(const kg_world* world, kg_body body, kg_body_type* out);
/* The body's first shape (kgyro/shape.h has them all: kg_body_get_shapes). */
KG_API kg_result kg_body_get_shape(const kg_world* world, kg_body body, kg_shape_def* out);
KG_API kg_result kg_body_get_mass_data(const kg_world* world, kg_body body, kg_mass_data* out);
/* Inverse mass and inverse rotational inertia; 0 means infinite. */
KG_API kg_result kg_body_get_inverse_mass(const kg_world* world, kg_body body, float* inv_mass,
                                          float* inv_inertia);
/* World bounds of the shape (of a compound body: of the box around its shapes, in its
 * frame), swept by the body's motion over one more step of the last dt. */
KG_API kg_result kg_body_get_aabb(const kg_world* world, kg_body body, kg_aabb* out);
/* The pointer given in kg_body_def.user_data or set since (NULL for a stale handle); it
 * comes back in every query result and event that names the body. */
KG_API void* kg_body_get_user_data(const kg_world* world, kg_body body);
KG_API kg_result kg_body_set_user_data(kg_world* world, kg_body body, void* user_data);

KG_API kg_result kg_body_set_transform(kg_world* world, kg_body body, kg_vec2 position, float angle);
KG_API kg_result kg_body_set_velocity(kg_world* world, kg_body body, kg_vec2 velocity);
KG_API kg_result kg_body_set_angular_velocity(kg_world* world, kg_body body, float omega);
/* Overrides mass properties. inv_mass/inv_inertia 0 = infinite; only for dynamic bodies.
 * Adding or removing shapes later leaves them as set. */
KG_API kg_result kg_body_set_inverse_mass(kg_world* world, kg_body body, float inv_mass,
                                          float inv_inertia);
/* Friction, restitution and filter of every shape of the body (kg_shape_set_* sets one's). */
KG_API kg_result kg_body_set_friction(kg_world* world, kg_body body, float friction);
KG_API kg_result kg_body_set_restitution(kg_world* world, kg_body body, float restitution);
KG_API kg_result kg_body_set_damping(kg_world* world, kg_body body, float linear, float angular);
KG_API kg_result kg_body_set_filter(kg_world* world, kg_body body, uint32_t category, uint32_t mask);
/* Makes a dynamic body a bullet (non-zero) or not: kg_body_def.bullet. */
KG_API kg_result kg_body_set_bullet(kg_world* world, kg_body body, int bullet);
KG_API int kg_body_is_bullet(const kg_world* world, kg_body body);
/* Sends the body's contacts through the pre-solve callback (non-zero) or not:
 * kg_body_def.enable_pre_solve. */
KG_API kg_result kg_body_set_pre_solve(kg_world* world, kg_body body, int enabled);

/* Forces and torques accumulate until the end of the next step. Impulses act at once. */
KG_API kg_result kg_body_apply_force(kg_world* world, kg_body body, kg_vec2 force, kg_vec2 world_point);
KG_API kg_result kg_body_apply_force_to_center(kg_world* world, kg_body body, kg_vec2 force);
KG_API kg_result kg_body_apply_torque(kg_world* world, kg_body body, float torque);
KG_API kg_result kg_body_apply_impulse(kg_world* world, kg_body body, kg_vec2 impulse, kg_vec2 world_point);
KG_API kg_result kg_body_apply_angular_impulse(kg_world* world, kg_body body, float impulse);

#ifdef __cplusplus
}
#endif
#endif
