/* The pre-solve stage: the user's callback may switch contacts off for one step. It runs
 * on the host, one contact at a time in the contacts' order, with the world locked
 * against changes (core/world.h, KG_LOCK_ALL). */
#include "collide/collide.h"
#include "core/body_flags.h"
#include "core/error.h"

/* A body that asked for pre-solve and takes part in the step: between two bodies at rest
 * (static or asleep) the contact is kept whole from step to step, so switching it off
 * would last until they woke. */
static int kg_asks(const kg_body_pool* p, kg_u32 i) { return i != KG_NULL_INDEX && (p->flags[i] & KG_FLAG_PRE_SOLVE); }

static int kg_at_rest(const kg_body_pool* p, kg_u32 i)
{
    return i == KG_NULL_INDEX || kg_pool_type(p, (int)i) == KG_BODY_STATIC || kg_pool_asleep(p, (int)i);
}

int kg_pre_solve_contacts(kg_world* world, kg_contact* contacts, int count)
{
    const kg_body_pool* p = &world->bodies;
    int switched_off = 0;
    int lock = world->lock;
    world->lock = KG_LOCK_ALL;
    for (int k = 0; k < count; ++k) {
        kg_contact* c = &contacts[k];
        if (c->manifold.point_count == 0 || !(kg_asks(p, c->a) || kg_asks(p, c->b)) ||
            (kg_at_rest(p, c->a) && kg_at_rest(p, c->b))) {
            continue;
        }
        kg_contact_info info;
        kg_contact_info_of(world, c, &info);
        if (!world->pre_solve(&info, world->pre_solve_context)) {
            c->manifold.point_count = 0;
            switched_off += 1;
        }
    }
    world->lock = lock;
    return switched_off;
}

kg_result kg_stage_pre_solve(kg_world* world)
{
    if (world->pre_solve) {
        int count = 0;
        kg_contact* contacts = kg_collision_contacts(world, &count);
        kg_pre_solve_contacts(world, contacts, count);
    }
    return KG_OK;
}

kg_result kg_world_set_pre_solve(kg_world* world, kg_pre_solve_fn* fn, void* context)
{
    if (!world) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_world_set_pre_solve: NULL world");
    }
    if (kg_world_refuses(world, "kg_world_set_pre_solve", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    world->pre_solve = fn;
    world->pre_solve_context = fn ? context : NULL;
    return KG_OK;
}
