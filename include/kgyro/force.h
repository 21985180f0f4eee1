/* KineticGyro: force applicators, called once per step before integration. */
#ifndef KGYRO_FORCE_H
#define KGYRO_FORCE_H

#include "types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A user force applicator. bodies lists the awake bodies it applies to (every live awake
 * body when it was registered for all); it adds forces with kg_body_apply_force* and may
 * read state. Sleeping bodies are left out: they rest under the forces they fell asleep
 * with. Adding or removing an applicator wakes every body; a callback whose forces change
 * on their own (a wind that starts) wakes the bodies it means with kg_body_wake. */
typedef void kg_force_fn(kg_world* world, const kg_body* bodies, int count, void* user_data);

/* bodies == NULL with count == 0 means all bodies (those created later too). The list is
 * copied and holds at most max_bodies handles. Handles in it that die later are skipped. */
KG_API kg_result kg_add_force_applicator(kg_world* world, kg_force_fn* fn, const kg_body* bodies,
                                         int count, void* user_data, kg_applicator* out);
/* Extra gravity (m/s^2, a force of mass * acceleration) on some bodies. */
KG_API kg_result kg_add_gravity_applicator(kg_world* world, kg_vec2 acceleration, const kg_body* bodies,
                                           int count, kg_applicator* out);
/* Wind: a force of strength newtons along direction, minus drag * velocity (N s/m). The
 * drag is integrated implicitly, at every sub-step, so however light the body and however
 * many winds, the velocity tends to the terminal one (strength / drag) and never past it. */
KG_API kg_result kg_add_wind_applicator(kg_world* world, kg_vec2 direction, float strength, float drag,
                                        const kg_body* bodies, int count, kg_applicator* out);
KG_API kg_result kg_remove_applicator(kg_world* world, kg_applicator applicator);

#ifdef __cplusplus
}
#endif
#endif
