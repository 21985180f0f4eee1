/* Contact events (public API: include/kgyro/events.h), made on the host when asked for,
 * from the two contact lists the collide stage keeps, whichever backend made them. */
#ifndef KG_EVENTS_H
#define KG_EVENTS_H

#include "core/world.h"
#include "kgyro/events.h"

/* A list of events that grows with need (outside the stages). */
typedef struct kg_event_list {
    kg_contact_event* items;
    int count, capacity;
} kg_event_list;

/* Grows an array of items of size bytes to hold need (at least doubling); its contents
 * kept. KG_ERROR_OUT_OF_MEMORY, the array as it was, when it cannot. */
kg_result kg_grow(void** items, int* capacity, int need, size_t size);
kg_result kg_push(kg_event_list* list, const kg_contact_event* e);

/* Body slot is about to be destroyed: its touching contacts end now, reported with the
 * next step's events. */
void kg_events_body_destroyed(kg_world* world, kg_u32 slot);
void kg_events_destroy(kg_world* world);

/* Sensors (collide/sensor.c): after a step, each sensor shape's visitors found through the
 * world's queries and compared with the last step's. Fails only when the lists cannot
 * grow; the step itself stands. */
kg_result kg_sensors_after_step(kg_world* world);
void kg_sensors_destroy(kg_world* world);

#endif
