/* Stage 2 of a step: find touching pairs (broadphase), compute their manifolds
 * (narrowphase) and carry impulses over from last step's contacts (persistence). */
#ifndef KG_COLLIDE_H
#define KG_COLLIDE_H

#include "collide/pair_contact.h"
#include "core/world.h"
#include "kgyro/collision.h"


kg_result kg_collision_create(kg_world* world);
void kg_collision_destroy(kg_world* world);
kg_result kg_stage_collide(kg_world* world);
/* After the stage, on the CPU backend: marks the static and sleeping bodies, which cannot
 * move before the next collide stage unless woken or changed (that clears the mark,
 * solve/sleep.c kg_wake_slot), so that the next stage keeps the manifolds between two of
 * them instead of computing them again. The OpenCL backend computes them every step
 * and leaves the marks alone (a mark it did not clear would keep a stale manifold after
 * a fallback to the CPU). */
void kg_collision_mark_rested(kg_world* world);

/* For a backend that builds contacts itself (OpenCL): starts a step by making the
 * current list the previous one (returned with its count, body pairs first, then tile
 * contacts) and returns the buffer, kg_collision_capacity() long, to fill; then
 * kg_collision_set_count says how many it holds and how many are body pairs. */
kg_contact* kg_collision_begin_step(kg_world* world, kg_contact** previous, int* previous_count);
void kg_collision_set_count(kg_world* world, int count, int body_count);
/* The contact pool's capacity for this step's contacts (world->def.max_contacts follows
 * it). It is sized from need (docs/design.md, "Pools and handles"); while a tile map is
 * live this first grows it to the budget, the room tile contacts get (they cannot grow
 * it in the middle of a stage). */
int kg_collision_capacity(kg_world* world);
/* How far the pool may grow without a warning: kg_world_def.max_contacts as the world was
 * created with (0 made 4 per body), or as raised when the pairs outgrew it. The OpenCL
 * backend reserves its device buffers for this many, so that the pool's growth on the
 * host never leaves the device short. */
int kg_collision_budget(const kg_world* world);

/* Adds a persisting contact's points to the step's warm-start counts (kg_stage_times):
 * carried of its points found last step's impulses, the rest started cold. */
void kg_count_warm_starts(kg_world* world, int points, int carried);

/* The index of the shapes of the bodies that have many (collide/shape_index.h), as this
 * step's collide stage left it. */
const struct kg_shape_index* kg_collision_shape_index(const kg_world* world);

/* The world's shapes as the shared pair code reads them (collide/pair_contact.h). */
kg_shape_arrays kg_world_shape_arrays(const kg_world* world);

/* The handle a contact's body had when the contact was made: stale if it died since; the
 * null body for KG_NULL_INDEX. */
kg_body kg_handle_of(kg_u32 slot, kg_u32 generation);
/* The handle of a contact's shape while it is alive on the same body (a slot freed and
 * taken since is another shape): null otherwise. */
kg_shape_id kg_shape_handle_of(const kg_shape_pool* sp, kg_u32 slot, kg_u32 body);
/* What kg_world_get_contact tells of contact c. */
void kg_contact_info_of(const kg_world* world, const kg_contact* c, kg_contact_info* out);
/* The host list the next kg_collision_begin_step makes current: free until then, so that
 * a backend building contacts on a device may stage them there in the middle of a step. */
kg_contact* kg_collision_next_list(kg_world* world);
/* The pre-solve stage (kgyro/collision.h, kg_world_set_pre_solve) over the current list. */
kg_result kg_stage_pre_solve(kg_world* world);
/* The pre-solve callback over contacts [0, count): switches off (point_count 0) those it
 * refuses; returns how many. */
int kg_pre_solve_contacts(kg_world* world, kg_contact* contacts, int count);
/* The contacts of the current step: body pairs sorted by (a, b), then tile contacts. */
kg_contact* kg_collision_contacts(kg_world* world, int* count);
/* The same, brought up to date first where the backend builds them (OpenCL). */
const kg_contact* kg_collision_synced_contacts(const kg_world* world, int* count);
/* The step before's contacts, as it left them (kept until the next step's collide), and
 * the same brought up to date first. */
kg_contact* kg_collision_previous(kg_world* world, int* count);
const kg_contact* kg_collision_synced_previous(const kg_world* world, int* count);

/* The colour each current contact keeps from the last step (solve/coloring.h,
 * kg_kept_color, KG_UNCOLORED for none) as the CPU's collide stage found it, and in
 * *waiting how many keep none; -1 when unknown (a backend that builds contacts itself, a
 * write to the body pool through the API since, or a body's motion changed since:
 * kg_collision_forget_kept_colors). */
const int* kg_collision_kept_colors(const kg_world* world, int* waiting);
void kg_collision_forget_kept_colors(kg_world* world);

/* How many of the current contacts are body pairs (the tile contacts follow). */
int kg_collision_body_count(const kg_world* world);

/* Snapshots (core/snapshot.c): the contact list written; read into a new collision state
 * (no broadphase yet: it is the world's, adopted with the caches forgotten), checked
 * against the world's body capacity and shape_capacity; discarded, or adopted by the
 * world in place of its own. */
struct kg_snap_out;
struct kg_snap_in;
void kg_collision_snapshot(const kg_world* world, struct kg_snap_out* out);
kg_result kg_collision_from_snapshot(const kg_world* world, struct kg_snap_in* in, int shape_capacity,
                                     struct kg_collision** out);
void kg_collision_discard(struct kg_collision* staged);
void kg_collision_adopt(kg_world* world, struct kg_collision* staged);

#endif
