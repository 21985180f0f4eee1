/* Sleeping (solve/sleep.c): the two stages of the step, and the wake-ups the API asks for. */
#ifndef KG_SLEEP_H
#define KG_SLEEP_H

#include "core/world.h"

kg_result kg_sleep_create(kg_world* world);
void kg_sleep_destroy(kg_world* world);

/* After collide: contacts from bodies in motion wake the islands they reach. */
void kg_stage_wake(kg_world* world);
/* Last: islands at rest for time_to_sleep fall asleep. */
void kg_stage_sleep(kg_world* world);

/* Wakes body slot i (its island follows at the next step, through its contacts). */
void kg_wake_slot(kg_body_pool* pool, int i);
/* Wakes every body whose bounds meet box grown by margin, and restarts its rest timer:
 * what rested on a body that is removed, moved or filtered out. */
void kg_wake_touching(kg_body_pool* pool, kg_aabb box, float margin);
int kg_pool_asleep_count(const kg_body_pool* pool);

#endif
