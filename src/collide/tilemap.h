/* Tile-map terrain in the collision stage. Placeholder interface until tile maps land:
 * the collision stage calls kg_tilemap_collide after the body pairs. */
#ifndef KG_TILEMAP_H
#define KG_TILEMAP_H

#include "collide/collide.h"

/* Writes up to room contacts of bodies against the world's tile maps into out (b =
 * KG_NULL_INDEX, tile = the tile's key, impulses carried from previous[0, previous_count),
 * which is last step's tile contacts in the order this function wrote them). Returns how
 * many it found, which may exceed room. */
int kg_tilemap_collide(kg_world* world, kg_contact* out, int room, const kg_contact* previous, int previous_count);
void kg_tilemaps_destroy(kg_world* world);

#endif
