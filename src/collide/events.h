/* Contact events (public API: include/kgyro/events.h), made on the host when asked for,
 * from the two contact lists the collide stage keeps, whichever backend made them. */
#ifndef KG_EVENTS_H
#define KG_EVENTS_H

#include "core/world.h"

/* Body slot is about to be destroyed: its touching contacts end now, reported with the
 * next step's events. */
void kg_events_body_destroyed(kg_world* world, kg_u32 slot);
void kg_events_destroy(kg_world* world);

#endif
