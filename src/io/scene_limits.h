/* The limits a loader works under (kg_scene_limits), kept in the scene it fills so that
 * every part of the loading (the scene file, the Tiled maps and tilesets it names, the
 * generators) obeys the same ones. */
#ifndef KG_SCENE_LIMITS_H
#define KG_SCENE_LIMITS_H

#include "kgyro/scene.h"

/* Refuses limits that no file could meet sensibly (a negative count, a zero size), the
 * message starting with function. */
kg_result kg_check_scene_limits(const char* function, const kg_scene_limits* limits);

/* A new scene has kg_default_scene_limits(); a loader sets its caller's while it reads
 * and puts the defaults back before it hands the scene over. */
void kg_scene_set_limits(kg_scene* scene, const kg_scene_limits* limits);
const kg_scene_limits* kg_scene_get_limits(const kg_scene* scene);

/* How many more bodies the limits let scene hold. */
int kg_scene_body_room(const kg_scene* scene);

/* The cap on one file: the limits' or the format's own, whichever is lower. */
size_t kg_scene_file_cap(const kg_scene_limits* limits, size_t format_cap);

#endif
