/* KineticGyro: joints, constraints between two bodies (or a body and the world) solved
 * with the contacts in the same soft sub-steps (docs/joints.md).
 *
 * House style of the rest of the API (Box2D v3's): fill a definition from its default
 * (kg_default_revolute_joint_def()), set the bodies and anchors, create the joint
 * (kg_create_revolute_joint(world, &def, &joint)). A joint handle is generational like a
 * body handle: stale forever once the joint (or one of its bodies) is destroyed, and
 * refused by every other world. Destroying a body destroys its joints; the next step's
 * kg_world_get_joint_events lists them.
 *
 * Anchors are given in each body's frame (its origin, as kg_body_def.position places it),
 * or in world coordinates through kg_joint_local_point. body_a may be KG_NULL_BODY: the
 * joint then holds body_b to the world (its anchor_a is a world point). A joint between a
 * body and itself, a NaN anchor or option, or a stale body is refused
 * (KG_ERROR_INVALID_ARGUMENT / KG_ERROR_INVALID_HANDLE). Both backends solve them, to the
 * same bits. (The setters' names follow the kind: kg_revolute_joint_set_motor on a weld joint is
 * refused with KG_ERROR_INVALID_ARGUMENT.) */
#ifndef KGYRO_JOINT_H
#define KGYRO_JOINT_H

#include "body.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Generational handle of a joint. The all-zero handle is never valid. */
typedef struct kg_joint {
    uint32_t index;
    uint32_t generation;
} kg_joint;

#define KG_NULL_JOINT_INIT {0u, 0u}

typedef enum kg_joint_type {
    KG_JOINT_REVOLUTE = 0,
    KG_JOINT_DISTANCE = 1,
    KG_JOINT_WELD = 2,
    KG_JOINT_MOUSE = 3,
    KG_JOINT_PRISMATIC = 4,
    KG_JOINT_WHEEL = 5,
    KG_JOINT_MOTOR = 6
} kg_joint_type;

/* What every joint definition starts with. */
typedef struct kg_joint_base_def {
    kg_body body_a;          /* KG_NULL_BODY: the world */
    kg_body body_b;          /* required */
    int collide_connected;   /* non-zero: the two bodies still collide (default 0: they do not) */
    /* How stiff the rigid part of the joint is: its position error is corrected as a
     * spring of this frequency and damping ratio in the solve pass (never in the relax
     * pass), capped at three quarters of the sub-step rate. Default 0: that cap (180 Hz
     * at 4 sub-steps of 1/60 s, 360 at 8), damping ratio 5. Under a load F it settles F / (m (2 pi
     * hertz)^2) from its target, m the constraint's effective mass (docs/joints.md): more
     * sub-steps make joints stiffer. */
    float constraint_hertz;
    float constraint_damping_ratio;
    /* Breakable joints: 0 (the default) never breaks; else the joint breaks (is destroyed,
     * KG_JOINT_EVENT_BROKEN) at the end of a step whose reaction force on body_b exceeds
     * break_force (N) or whose torque exceeds break_torque (N m). */
    float break_force;
    float break_torque;
    void* user_data;
} kg_joint_base_def;

/* A hinge: anchor_a on body_a and anchor_b on body_b kept together; optionally the angle
 * of b relative to a (minus reference_angle) kept in [lower_angle, upper_angle], driven
 * at motor_speed with at most max_motor_torque, and pulled to 0 by a rotational spring. */
typedef struct kg_revolute_joint_def {
    kg_joint_base_def base;
    kg_vec2 local_anchor_a, local_anchor_b; /* in the bodies' frames (a world point when body_a is null) */
    float reference_angle;                  /* angle_b - angle_a at which the joint angle is 0 */
    int enable_limit;
    float lower_angle, upper_angle; /* radians, lower <= upper, within [-pi, pi] */
    int enable_motor;
    float motor_speed;      /* rad/s */
    float max_motor_torque; /* N m, >= 0 */
    int enable_spring;
    float hertz;            /* >= 0; 0: no spring */
    float damping_ratio;    /* >= 0 */
} kg_revolute_joint_def;

/* A rod, a rope or a spring between anchor_a and anchor_b: rigid at length; with
 * enable_spring a spring of hertz (0: none, a free slack) about length; with enable_limit
 * the distance kept within [min_length, max_length]. A rope: enable_spring with hertz 0,
 * enable_limit, min_length 0, max_length its length. */
typedef struct kg_distance_joint_def {
    kg_joint_base_def base;
    kg_vec2 local_anchor_a, local_anchor_b;
    float length; /* > 0; kg_default_distance_joint_def: 1 */
    int enable_spring;
    float hertz, damping_ratio;
    int enable_limit;
    float min_length, max_length; /* 0 <= min <= max */
} kg_distance_joint_def;

/* Glues body_b to body_a at an anchor, rigid, or soft with linear_hertz / angular_hertz
 * (0: rigid) and their damping ratios. */
typedef struct kg_weld_joint_def {
    kg_joint_base_def base;
    kg_vec2 local_anchor_a, local_anchor_b;
    float reference_angle;
    float linear_hertz, linear_damping_ratio;
    float angular_hertz, angular_damping_ratio;
} kg_weld_joint_def;

/* Drags body_b's anchor to target (a world point, kg_mouse_joint_set_target) with a soft
 * spring of hertz and damping ratio, never pushing harder than max_force; body_a is the
 * world (ignored). Its rotation is damped a little, as Box2D's. */
typedef struct kg_mouse_joint_def {
    kg_joint_base_def base;
    kg_vec2 target;         /* world point */
    kg_vec2 local_anchor_b; /* the point of body_b dragged there */
    float hertz;            /* > 0; default 5 */
    float damping_ratio;    /* default 0.7 */
    float max_force;        /* N, >= 0; default 1000 */
} kg_mouse_joint_def;

/* A slider: body_b moves along local_axis_a (in body_a's frame, through the anchors)
 * without turning relative to body_a; its translation (anchor b's offset from anchor a
 * along the axis) kept within [lower_translation, upper_translation], driven at
 * motor_speed (m/s) with at most max_motor_force, pulled to 0 by a spring. */
typedef struct kg_prismatic_joint_def {
    kg_joint_base_def base;
    kg_vec2 local_anchor_a, local_anchor_b;
    kg_vec2 local_axis_a; /* normalized when created; default (1, 0) */
    float reference_angle;
    int enable_limit;
    float lower_translation, upper_translation; /* m, lower <= upper */
    int enable_motor;
    float motor_speed, max_motor_force;
    int enable_spring;
    float hertz, damping_ratio;
} kg_prismatic_joint_def;

/* A wheel (cars): body_b's anchor stays on the line of local_axis_a through anchor a (the
 * suspension, with a spring of hertz and damping ratio about translation 0 and optional
 * limits along it), and turns freely, driven by a motor (motor_speed rad/s, at most
 * max_motor_torque). */
typedef struct kg_wheel_joint_def {
    kg_joint_base_def base;
    kg_vec2 local_anchor_a, local_anchor_b;
    kg_vec2 local_axis_a; /* default (0, 1): a suspension pointing up */
    int enable_limit;
    float lower_translation, upper_translation;
    int enable_motor;
    float motor_speed, max_motor_torque;
    int enable_spring; /* default on, 1 Hz, damping 0.7 */
    float hertz, damping_ratio;
} kg_wheel_joint_def;

/* Drives body_b to a pose relative to body_a: its origin to linear_offset (a point of
 * a's frame) and its angle to a's plus angular_offset, with at most max_force and
 * max_torque, correcting correction_factor (0 to 1) of the error each sub-step. */
typedef struct kg_motor_joint_def {
    kg_joint_base_def base;
    kg_vec2 linear_offset;
    float angular_offset;
    float max_force;         /* default 1 */
    float max_torque;        /* default 1 */
    float correction_factor; /* default 0.3 */
} kg_motor_joint_def;

KG_API kg_revolute_joint_def kg_default_revolute_joint_def(void);
KG_API kg_distance_joint_def kg_default_distance_joint_def(void);
KG_API kg_weld_joint_def kg_default_weld_joint_def(void);
KG_API kg_mouse_joint_def kg_default_mouse_joint_def(void);
KG_API kg_prismatic_joint_def kg_default_prismatic_joint_def(void);
KG_API kg_wheel_joint_def kg_default_wheel_joint_def(void);
KG_API kg_motor_joint_def kg_default_motor_joint_def(void);

KG_API kg_result kg_create_revolute_joint(kg_world* world, const kg_revolute_joint_def* def, kg_joint* out);
KG_API kg_result kg_create_distance_joint(kg_world* world, const kg_distance_joint_def* def, kg_joint* out);
KG_API kg_result kg_create_weld_joint(kg_world* world, const kg_weld_joint_def* def, kg_joint* out);
KG_API kg_result kg_create_mouse_joint(kg_world* world, const kg_mouse_joint_def* def, kg_joint* out);
KG_API kg_result kg_create_prismatic_joint(kg_world* world, const kg_prismatic_joint_def* def, kg_joint* out);
KG_API kg_result kg_create_wheel_joint(kg_world* world, const kg_wheel_joint_def* def, kg_joint* out);
KG_API kg_result kg_create_motor_joint(kg_world* world, const kg_motor_joint_def* def, kg_joint* out);

/* Destroys a joint; its bodies are woken and collide again. */
KG_API kg_result kg_destroy_joint(kg_world* world, kg_joint joint);
KG_API int kg_joint_is_valid(const kg_world* world, kg_joint joint);
KG_API int kg_world_joint_count(const kg_world* world);
/* How many times each solve and relax pass of a sub-step runs over the joints (in [1,
 * 64], default 6; warm starting is once; the relax pass over-relaxed but in its last):
 * fewer for many light joints (a 100 x 100 grid costs about iterations x 2 row
 * evaluations a joint a sub-step), more for long chains of unequal masses
 * (docs/joints.md). */
KG_API kg_result kg_world_set_joint_iterations(kg_world* world, int iterations);
KG_API int kg_world_get_joint_iterations(const kg_world* world);

/* A point given in world coordinates in body's frame (for anchors); the world's frame
 * (the point itself) for KG_NULL_BODY. */
KG_API kg_result kg_joint_local_point(const kg_world* world, kg_body body, kg_vec2 world_point, kg_vec2* out);

KG_API kg_result kg_joint_get_type(const kg_world* world, kg_joint joint, kg_joint_type* out);
/* The joint's bodies (body_a KG_NULL_BODY when it holds body_b to the world). */
KG_API kg_result kg_joint_get_bodies(const kg_world* world, kg_joint joint, kg_body* body_a, kg_body* body_b);
/* The anchors in world coordinates now (for drawing). */
KG_API kg_result kg_joint_get_world_anchors(const kg_world* world, kg_joint joint, kg_vec2* anchor_a,
                                            kg_vec2* anchor_b);
/* Prismatic and wheel: the axis in world coordinates now (unit, body_a's frame turned as
 * body_a is). */
KG_API kg_result kg_joint_get_world_axis(const kg_world* world, kg_joint joint, kg_vec2* out);
/* What the joint did to body_b in the last step's last sub-step: the force (N, world axes)
 * and the torque (N m) of its constraint, limits, motor and spring together. */
KG_API kg_result kg_joint_get_reaction(const kg_world* world, kg_joint joint, kg_vec2* force, float* torque);
KG_API void* kg_joint_get_user_data(const kg_world* world, kg_joint joint);
KG_API kg_result kg_joint_set_user_data(kg_world* world, kg_joint joint, void* user_data);
KG_API kg_result kg_joint_set_collide_connected(kg_world* world, kg_joint joint, int collide);
/* The break thresholds (kg_joint_base_def.break_force and break_torque; 0: never). */
KG_API kg_result kg_joint_set_break_thresholds(kg_world* world, kg_joint joint, float break_force,
                                               float break_torque);
/* Wakes the joint's bodies. */
KG_API kg_result kg_joint_wake(kg_world* world, kg_joint joint);

/* Revolute setters (each wakes the bodies). */
KG_API kg_result kg_revolute_joint_set_limits(kg_world* world, kg_joint joint, int enable, float lower, float upper);
KG_API kg_result kg_revolute_joint_set_motor(kg_world* world, kg_joint joint, int enable, float speed,
                                             float max_torque);
KG_API kg_result kg_revolute_joint_set_spring(kg_world* world, kg_joint joint, int enable, float hertz,
                                              float damping_ratio);
/* The joint angle now (radians, angle_b - angle_a - reference_angle, in [-pi, pi]). */
KG_API kg_result kg_revolute_joint_get_angle(const kg_world* world, kg_joint joint, float* out);

/* Distance setters. */
KG_API kg_result kg_distance_joint_set_length(kg_world* world, kg_joint joint, float length);
KG_API kg_result kg_distance_joint_set_limits(kg_world* world, kg_joint joint, int enable, float min_length,
                                              float max_length);
KG_API kg_result kg_distance_joint_set_spring(kg_world* world, kg_joint joint, int enable, float hertz,
                                              float damping_ratio);

/* Weld setters: 0 hertz is rigid. */
KG_API kg_result kg_weld_joint_set_stiffness(kg_world* world, kg_joint joint, float linear_hertz,
                                             float linear_damping_ratio, float angular_hertz,
                                             float angular_damping_ratio);

/* Mouse setters. */
KG_API kg_result kg_mouse_joint_set_target(kg_world* world, kg_joint joint, kg_vec2 target);
KG_API kg_result kg_mouse_joint_set_max_force(kg_world* world, kg_joint joint, float max_force);

/* Prismatic and wheel setters: limits (translations), motor (prismatic: speed m/s and
 * largest force; wheel: speed rad/s and largest torque), spring. */
KG_API kg_result kg_prismatic_joint_set_limits(kg_world* world, kg_joint joint, int enable, float lower,
                                               float upper);
KG_API kg_result kg_prismatic_joint_set_motor(kg_world* world, kg_joint joint, int enable, float speed,
                                              float max_force);
KG_API kg_result kg_prismatic_joint_set_spring(kg_world* world, kg_joint joint, int enable, float hertz,
                                               float damping_ratio);
KG_API kg_result kg_wheel_joint_set_limits(kg_world* world, kg_joint joint, int enable, float lower, float upper);
KG_API kg_result kg_wheel_joint_set_motor(kg_world* world, kg_joint joint, int enable, float speed,
                                          float max_torque);
KG_API kg_result kg_wheel_joint_set_spring(kg_world* world, kg_joint joint, int enable, float hertz,
                                           float damping_ratio);
/* The translation now (prismatic, wheel): anchor b's offset from anchor a along the axis. */
KG_API kg_result kg_joint_get_translation(const kg_world* world, kg_joint joint, float* out);

/* Motor joint setters. */
KG_API kg_result kg_motor_joint_set_offsets(kg_world* world, kg_joint joint, kg_vec2 linear_offset,
                                            float angular_offset);
KG_API kg_result kg_motor_joint_set_max(kg_world* world, kg_joint joint, float max_force, float max_torque);

/* The joint's definition as it is now, the setters' changes included: its bodies (body_a
 * KG_NULL_BODY for the world), anchors and axis in the bodies' frames (the axis unit),
 * every option and its user data; creating a joint from it makes the same joint. Each
 * kind's getter refuses a joint of another kind (KG_ERROR_INVALID_ARGUMENT). For saving
 * a world (kg_scene_from_world) and editors. */
KG_API kg_result kg_revolute_joint_get_def(const kg_world* world, kg_joint joint, kg_revolute_joint_def* out);
KG_API kg_result kg_distance_joint_get_def(const kg_world* world, kg_joint joint, kg_distance_joint_def* out);
KG_API kg_result kg_weld_joint_get_def(const kg_world* world, kg_joint joint, kg_weld_joint_def* out);
KG_API kg_result kg_mouse_joint_get_def(const kg_world* world, kg_joint joint, kg_mouse_joint_def* out);
KG_API kg_result kg_prismatic_joint_get_def(const kg_world* world, kg_joint joint, kg_prismatic_joint_def* out);
KG_API kg_result kg_wheel_joint_get_def(const kg_world* world, kg_joint joint, kg_wheel_joint_def* out);
KG_API kg_result kg_motor_joint_get_def(const kg_world* world, kg_joint joint, kg_motor_joint_def* out);

/* Why a joint ended without kg_destroy_joint. */
typedef enum kg_joint_event_kind {
    KG_JOINT_EVENT_BODY_DESTROYED = 0, /* one of its bodies was destroyed: the joint went with it */
    KG_JOINT_EVENT_BROKEN = 1          /* its reaction passed a break threshold in the last step */
} kg_joint_event_kind;

typedef struct kg_joint_event {
    kg_joint joint;      /* stale by now: for matching with handles the game kept */
    kg_joint_event_kind kind;
    kg_body body;        /* the destroyed body (BODY_DESTROYED); KG_NULL_BODY for BROKEN */
    void* user_data;     /* the joint's */
    kg_vec2 force;       /* BROKEN: the reaction force and torque that broke it */
    float torque;
} kg_joint_event;

typedef struct kg_joint_events {
    const kg_joint_event* events;
    int count;
} kg_joint_events;

/* The joints destroyed with their bodies between the previous step and the last one
 * (handed out after the step that follows the destruction, as contact end events of a
 * destroyed body are), then those the last step broke, in slot order. Valid until the
 * next step. */
KG_API kg_joint_events kg_world_get_joint_events(const kg_world* world);

#ifdef __cplusplus
}
#endif
#endif
