#include "collide/collide.h"
#include "core/alloc.h"
#include "core/error.h"

#include <string.h>

struct kg_collision {
    kg_contact* contacts;
    int count;
    int capacity;
};

kg_result kg_collision_create(kg_world* world)
{
    struct kg_collision* c = kg_alloc_zeroed(sizeof *c);
    if (!c) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the collision state");
    }
    world->collision = c;
    return KG_OK;
}

void kg_collision_destroy(kg_world* world)
{
    if (world->collision) {
        kg_free(world->collision->contacts);
        kg_free(world->collision);
        world->collision = NULL;
    }
}

kg_result kg_stage_collide(kg_world* world)
{
    world->collision->count = 0;
    return KG_OK;
}

kg_contact* kg_collision_contacts(kg_world* world, int* count)
{
    *count = world->collision->count;
    return world->collision->contacts;
}

int kg_world_contact_count(const kg_world* world) { return world ? world->collision->count : 0; }

kg_result kg_world_get_contact(const kg_world* world, int index, kg_contact_info* out)
{
    if (!world || !out || index < 0 || index >= world->collision->count) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "contact index %d out of range", index);
    }
    const kg_contact* c = &world->collision->contacts[index];
    memset(out, 0, sizeof *out);
    out->a = (kg_body){c->a, world->bodies.generation[c->a]};
    out->b = (kg_body){c->b, world->bodies.generation[c->b]};
    out->normal = c->manifold.normal;
    out->point_count = c->manifold.point_count;
    for (int k = 0; k < c->manifold.point_count; ++k) {
        const kg_manifold_point* mp = &c->manifold.points[k];
        out->points[k] = mp->point;
        out->depths[k] = -mp->separation;
        out->normal_impulses[k] = mp->normal_impulse;
        out->tangent_impulses[k] = mp->tangent_impulse;
        out->feature_ids[k] = mp->id;
    }
    return KG_OK;
}
