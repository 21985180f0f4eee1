/* Sleeping: islands at rest stop costing integration and solving until something wakes
 * them (docs/design.md, "Sleeping"). Two stages of the step:
 *
 *   wake  (after collide, before solve): a contact between a body in motion and a
 *         sleeping one wakes the sleeping one's whole island, before the solver sees it;
 *   sleep (last): bodies linked by contacts make islands; an island whose every body
 *         has rested time_to_sleep (timers the solver advances, island.h) falls asleep.
 *
 * A sleeping body keeps its contacts (collide still finds them and carries their
 * impulses, so a stack wakes warm) but is neither integrated nor solved: to the solver it
 * is as immovable as a static body. Everything here is serial and in slot order, so the
 * result does not depend on the thread count. */
#include "solve/sleep.h"
#include "collide/aabb.h"
#include "collide/collide.h"
#include "solve/island.h"
#include "core/alloc.h"
#include "core/error.h"
#include "core/joint.h"

struct kg_sleep {
    kg_u32* parent; /* union-find of this step's islands */
    float* least;   /* per island root: the shortest rest time of its bodies */
    kg_u32* wake;   /* per island name: to be woken this step */
};

kg_result kg_sleep_create(kg_world* world)
{
    struct kg_sleep* s = kg_alloc_zeroed(sizeof *s);
    world->sleep = s;
    size_t n = (size_t)world->def.max_bodies;
    if (s) {
        s->parent = kg_alloc_zeroed(n * sizeof *s->parent);
        s->least = kg_alloc_zeroed(n * sizeof *s->least);
        s->wake = kg_alloc_zeroed(n * sizeof *s->wake);
    }
    if (!s || !s->parent || !s->least || !s->wake) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the island scratch of %d bodies", world->def.max_bodies);
    }
    return KG_OK;
}

void kg_sleep_destroy(kg_world* world)
{
    struct kg_sleep* s = world->sleep;
    if (s) {
        kg_free(s->parent);
        kg_free(s->least);
        kg_free(s->wake);
        kg_free(s);
    }
    world->sleep = NULL;
}

void kg_wake_slot(kg_body_pool* p, int i) { kg_wake_body((kg_u32)i, p->flags, p->sleep_time); }

void kg_wake_touching(kg_body_pool* p, kg_aabb box, float margin)
{
    box = kg_aabb_fatten(box, margin);
    for (int i = 0; i < p->high_water; ++i) {
        if (kg_pool_collides(p, i) && kg_aabb_overlap(box, p->aabb[i])) {
            kg_wake_slot(p, i);
        }
    }
}

int kg_pool_asleep_count(const kg_body_pool* p)
{
    int n = 0;
    for (int i = 0; i < p->high_water; ++i) {
        n += kg_pool_alive(p, i) && kg_pool_asleep(p, i);
    }
    return n;
}

void kg_stage_wake(kg_world* world)
{
    if (!world->def.enable_sleep) {
        return;
    }
    struct kg_sleep* s = world->sleep;
    kg_body_pool* p = &world->bodies;
    int count = 0;
    const kg_contact* contacts = kg_collision_contacts(world, &count);
    for (int k = 0; k < count; ++k) {
        kg_mark_woken(contacts[k].a, contacts[k].b, p->flags, p->velocity, p->omega, p->island, s->wake);
    }
    int links = 0;
    const kg_u32* joined = kg_joints_links(world, &links);
    for (int k = 0; k < links; ++k) { /* a joint wakes its sleeping body's island like a contact */
        kg_mark_woken(joined[2 * k], joined[2 * k + 1], p->flags, p->velocity, p->omega, p->island, s->wake);
    }
    int woke = 0;
    for (int i = 0; i < p->high_water; ++i) {
        kg_u32 before = p->flags[i];
        kg_wake_if_marked((kg_u32)i, p->flags, p->island, s->wake, p->sleep_time);
        woke |= p->flags[i] != before;
    }
    if (woke) { /* a contact on a woken body takes its colour again */
        kg_collision_forget_kept_colors(world);
    }
    for (int i = 0; i < p->high_water; ++i) {
        s->wake[i] = 0u;
    }
}

void kg_stage_sleep(kg_world* world)
{
    if (!world->def.enable_sleep) {
        return;
    }
    struct kg_sleep* s = world->sleep;
    kg_body_pool* p = &world->bodies;
    int count = 0;
    const kg_contact* contacts = kg_collision_contacts(world, &count);
    int links = 0;
    const kg_u32* joined = kg_joints_links(world, &links);
    kg_link_joined_islands(p->high_water, count, contacts, links, joined, p->flags, p->velocity, p->omega,
                           p->sleep_time, s->parent, s->least);
    for (int i = 0; i < p->high_water; ++i) {
        kg_fall_asleep_if_rested((kg_u32)i, world->def.time_to_sleep, s->parent, s->least, p->flags, p->island,
                                 p->velocity, p->omega, p->center, p->rot, p->local_center, p->shape, p->xf, p->aabb);
    }
}
