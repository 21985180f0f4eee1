/* Placeholder until tile maps land: a world without tile maps has no tile contacts. */
#include "collide/tilemap.h"

int kg_tilemap_collide(kg_world* world, kg_contact* out, int room, const kg_contact* previous, int previous_count)
{
    (void)world;
    (void)out;
    (void)room;
    (void)previous;
    (void)previous_count;
    return 0;
}

void kg_tilemaps_destroy(kg_world* world) { (void)world; }
