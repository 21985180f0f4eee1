/* KineticGyro: what the last step did to contacts, for game logic and sound: pairs of
 * shapes that began touching, that stopped touching, and impacts harder than a threshold.
 *
 *   kg_world_step(world, dt);
 *   kg_contact_events ev = kg_world_get_contact_events(world);
 *   for (int i = 0; i < ev.hit_count; ++i) {
 *       play_thud(ev.hit[i].point, ev.hit[i].approach_speed);
 *   }
 *
 * Two shapes touch when their contact has a point closer than kg_world_def.linear_slop
 * (a resting contact sits about a slop deep, a contact held by nothing at 0: neither
 * flickers); a speculative contact further apart does not touch yet. A step's events are
 * made when first asked for, from its contacts and the step before's, which the world
 * keeps until the next step: a step whose events nobody reads costs nothing. They stay
 * valid until the next step. Their order is deterministic: the contacts' order (body
 * pairs by slot and shape, then tile contacts by body and tile), the same with any thread
 * count and on both backends. docs/queries-events.md tells the whole. */
#ifndef KGYRO_EVENTS_H
#define KGYRO_EVENTS_H

#include "collision.h"
#include "tilemap.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum kg_event_kind {
    KG_EVENT_BEGIN = 0, /* two shapes began touching */
    KG_EVENT_END,       /* they stopped: apart, filtered out, a shape or body destroyed */
    KG_EVENT_HIT,       /* a point pushed this step after approaching faster than the threshold */
    KG_EVENT_SENSOR_BEGIN, /* a shape (or tile) began overlapping a sensor: a is the sensor's body */
    KG_EVENT_SENSOR_END    /* it stopped: moved out, filtered out, destroyed */
} kg_event_kind;

/* One event. b is the null body when a touched a tile: map, layer, x and y name it. An end
 * event of a body destroyed since the step before has that body's handle null (no event
 * names a dead body) and its user data as it was, and comes first in the next step's end
 * events. */
typedef struct kg_contact_event {
    kg_event_kind kind;
    kg_body a, b;
    kg_shape_id shape_a, shape_b; /* null for a tile, and for a shape destroyed since */
    void* user_data_a;            /* the bodies' (kg_body_get_user_data) */
    void* user_data_b;
    kg_tilemap map;               /* when b is a tile */
    int layer, x, y;
    kg_vec2 normal;               /* unit, from a to b (begin and hit) */
    kg_vec2 point;                /* begin: the deepest point; hit: the point that hit (world) */
    float approach_speed;         /* hit: m/s at which the point closed when it first pushed */
    float normal_impulse;         /* begin and hit: the contact's total normal impulse over
                                   * the step, every sub-step's (N s) */
    int point_count;              /* begin: the manifold's points */
    kg_vec2 points[2];
    float depths[2];              /* > 0: penetration */
} kg_contact_event;

/* The last step's events, by kind, each list in the contacts' order. */
typedef struct kg_contact_events {
    const kg_contact_event* begin;
    int begin_count;
    const kg_contact_event* end;
    int end_count;
    const kg_contact_event* hit;
    int hit_count;
} kg_contact_events;

/* The events of the last step (all counts 0 before the first step and for a NULL world;
 * also when their lists cannot grow, with the error set). On the OpenCL backend the first
 * call after a step reads the step's contacts and the step before's back from the device. */
KG_API kg_contact_events kg_world_get_contact_events(const kg_world* world);

/* The last step's sensor events (kg_body_shape_def.is_sensor, "sensor" in scenes): a shape
 * of another body, or a tile, that began or stopped overlapping a sensor shape (touching
 * counts). a and shape_a are the sensor's body and shape, b and shape_b the visitor's (b
 * null for a tile: map, layer, x and y name it). A sensor sees static, kinematic and
 * dynamic bodies and tile maps its filter agrees with, never another sensor nor its own
 * body. An end event of a body destroyed since has its handle null and its user data as
 * it was. Ordered by sensor shape slot, then visitor (bodies by slot and shape, then tiles
 * by map, layer, row and column): the same with any thread count and on both backends.
 * Sensors are found after every step where the world has any, through the same index as
 * the queries (include/kgyro/query.h), which they keep current. */
typedef struct kg_sensor_events {
    const kg_contact_event* begin;
    int begin_count;
    const kg_contact_event* end;
    int end_count;
} kg_sensor_events;

KG_API kg_sensor_events kg_world_get_sensor_events(const kg_world* world);

/* Writes up to capacity of body's current contacts (the last step's, touching or
 * speculative) to out and how many it has to *count; kg_contact_info as
 * kg_world_get_contact gives it. KG_ERROR_INVALID_HANDLE for a stale body. */
KG_API kg_result kg_body_get_contacts(const kg_world* world, kg_body body, kg_contact_info* out, int capacity,
                                      int* count);

#ifdef __cplusplus
}
#endif
#endif
