/* Sleeping on the OpenCL backend: solve/sleep.c's two stages as kernels
 * (kernels/kg_sleep.cl), with the CPU backend's results bit for bit:
 *
 *   wake   after the collide stage, before the colouring (in the solve stage), which
 *          must see the woken bodies as the CPU's does; on the host instead in the step
 *          whose collide stage ran there
 *   sleep  last in the step, after finalize
 *
 * Nothing crosses the bus: the flags, rest timers and islands stay on the device with the
 * rest of the state until a getter asks. */
#ifdef KG_HAVE_OPENCL
#include "backend/opencl/cl_backend.h"
#include "solve/sleep.h"

/* Every sleeping kernel's label in the profile. */
static const char* const kLabel = "kg_sleep";

kg_result kg_cl_wake_on_device(kg_world* world, kg_cl_backend* b, int pairs)
{
    if (!world->def.enable_sleep) {
        return KG_OK;
    }
    kg_cl_collide_buffers* c = &b->collide;
    int slots = world->bodies.high_water;
    KG_LAUNCH(b, WAKE_TOUCHED, pairs, kLabel, KG_INT(pairs), KG_MEM(b->step_pair_list), KG_MEM(c->touching),
              KG_MEM(KG_A(FLAGS)), KG_MEM(KG_A(VELOCITY)), KG_MEM(KG_A(OMEGA)), KG_MEM(KG_A(ISLAND)),
              KG_MEM(b->wake_marks));
    KG_TRY(kg_cl_wake_joined(world, b)); /* a joint wakes like a contact */
    KG_LAUNCH(b, WAKE_MARKED, slots, kLabel, KG_INT(slots), KG_MEM(KG_A(FLAGS)), KG_MEM(KG_A(ISLAND)),
              KG_MEM(b->wake_marks), KG_MEM(KG_A(SLEEP_TIME)));
    return KG_OK;
}

kg_result kg_cl_wake_on_host(kg_world* world, kg_cl_backend* b)
{
    if (!world->def.enable_sleep) {
        return KG_OK;
    }
    unsigned reads = KG_CL_BIT(ISLAND) | KG_CL_BIT(VELOCITY) | KG_CL_BIT(OMEGA) | KG_CL_BIT(SLEEP_TIME);
    KG_TRY(kg_cl_flags_to_host(world, b));
    KG_TRY(kg_cl_to_host(b, &world->bodies, reads));
    kg_stage_wake(world);
    /* the solver's kernels read the woken flags and advance the restarted timers */
    return kg_cl_upload(b, &world->bodies, KG_CL_BIT(FLAGS) | KG_CL_BIT(SLEEP_TIME));
}

/* The islands of slots bodies over count contacts in rounds over the whole device (see
 * kernels/kg_sleep.cl): every round hooks at least two islands while any two touching
 * ones are apart, so count + 1 rounds always end them. */
static kg_result kg_find_islands_in_rounds(kg_cl_backend* b, int slots, int count, cl_mem contacts, int joints)
{
    cl_mem parent = b->island_parent, least = b->island_least, counts = b->collide.counts;
    KG_LAUNCH(b, RESET_ISLANDS, slots, kLabel, KG_INT(slots), KG_MEM(parent), KG_MEM(least), KG_MEM(counts));
    int round = 0;
    for (cl_uint hooked = 1u; hooked != 0u;) {
        if (round > count + joints) {
            return kg_fail(KG_ERROR_BACKEND, "the device's islands did not settle in %d rounds", count + joints + 1);
        }
        for (int end = round + KG_CL_ROUNDS_PER_LOOK; round < end; ++round) {
            KG_LAUNCH(b, HOOK_ROUND, count, kLabel, KG_INT(count), KG_INT(round), KG_MEM(contacts),
                      KG_MEM(KG_A(FLAGS)), KG_MEM(parent), KG_MEM(counts));
            if (joints > 0) { /* the joints' links hook in the same round (cl_joint.c) */
                KG_LAUNCH(b, HOOK_JOINT_ROUND, joints, kLabel, KG_INT(joints), KG_INT(round), KG_MEM(b->joint_links),
                          KG_MEM(KG_A(FLAGS)), KG_MEM(parent), KG_MEM(counts));
            }
            KG_LAUNCH(b, SHORTEN_ISLANDS, slots, kLabel, KG_INT(slots), KG_MEM(parent));
        }
        KG_TRY(kg_cl_rounds_left(b, KG_CC_HOOKED, round, &hooked));
    }
    KG_LAUNCH(b, ISLAND_LEAST, slots, kLabel, KG_INT(slots), KG_MEM(KG_A(FLAGS)), KG_MEM(KG_A(SLEEP_TIME)),
              KG_MEM(parent), KG_MEM(least));
    KG_LAUNCH(b, ISLAND_STIRS, count, kLabel, KG_INT(count), KG_MEM(contacts), KG_MEM(KG_A(FLAGS)),
              KG_MEM(KG_A(VELOCITY)), KG_MEM(KG_A(OMEGA)), KG_MEM(parent), KG_MEM(least));
    if (joints > 0) {
        KG_LAUNCH(b, JOINT_STIRS, joints, kLabel, KG_INT(joints), KG_MEM(b->joint_links), KG_MEM(KG_A(FLAGS)),
                  KG_MEM(KG_A(VELOCITY)), KG_MEM(KG_A(OMEGA)), KG_MEM(parent), KG_MEM(least));
    }
    return KG_OK;
}

/* The islands: by one work-group up to b->island_group_max bodies, else in rounds. */
static kg_result kg_find_islands(kg_cl_backend* b, int slots, int count, cl_mem contacts, int joints)
{
    if (slots > b->island_group_max) {
        return kg_find_islands_in_rounds(b, slots, count, contacts, joints);
    }
    if (joints > 0) { /* with the joints' links (cl_joint.c) */
        KG_LAUNCH(b, FIND_JOINED_ISLANDS, (int)b->group_size[KG_CL_K_FIND_JOINED_ISLANDS], kLabel, KG_INT(slots),
                  KG_INT(count), KG_MEM(contacts), KG_INT(joints), KG_MEM(b->joint_links), KG_MEM(KG_A(FLAGS)),
                  KG_MEM(KG_A(VELOCITY)), KG_MEM(KG_A(OMEGA)), KG_MEM(KG_A(SLEEP_TIME)), KG_MEM(b->island_parent),
                  KG_MEM(b->island_least));
        return KG_OK;
    }
    KG_LAUNCH(b, FIND_ISLANDS, (int)b->group_size[KG_CL_K_FIND_ISLANDS], kLabel, KG_INT(slots), KG_INT(count),
              KG_MEM(contacts), KG_MEM(KG_A(FLAGS)), KG_MEM(KG_A(VELOCITY)), KG_MEM(KG_A(OMEGA)),
              KG_MEM(KG_A(SLEEP_TIME)), KG_MEM(b->island_parent), KG_MEM(b->island_least));
    return KG_OK;
}

kg_result kg_cl_sleep_on_device(kg_world* world, kg_cl_backend* b, int count)
{
    if (!world->def.enable_sleep) {
        return KG_OK;
    }
    int slots = world->bodies.high_water;
    cl_mem contacts = b->contacts[b->current ^ 1];
    KG_TRY(kg_find_islands(b, slots, count, contacts, kg_cl_joint_links(world, b)));
    KG_LAUNCH(b, FALL_ASLEEP, slots, kLabel, KG_INT(slots), KG_FLOAT(world->def.time_to_sleep),
              KG_MEM(b->island_parent), KG_MEM(b->island_least), KG_MEM(KG_A(FLAGS)), KG_MEM(KG_A(ISLAND)),
              KG_MEM(KG_A(VELOCITY)), KG_MEM(KG_A(OMEGA)), KG_MEM(KG_A(CENTER)), KG_MEM(KG_A(ROT)),
              KG_MEM(KG_A(LOCAL_CENTER)), KG_MEM(KG_A(SHAPE)), KG_MEM(KG_A(XF)), KG_MEM(KG_A(AABB)));
    return KG_OK;
}
#endif
