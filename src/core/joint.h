/* The world's joints (include/kgyro/joint.h): a pool of solver rows (solve/joint_row.h)
 * beside the host's bookkeeping, generational handles carrying the world's tag, and what
 * the other stages ask of it: the solver's passes, the pairs of bodies that must not
 * collide, the links of the islands, and the joints a destroyed body took with it. */
#ifndef KG_JOINT_INTERNAL_H
#define KG_JOINT_INTERNAL_H

#include "core/world.h"
#include "kgyro/joint.h"
#include "solve/joint_row.h"

struct kg_joints;
struct kg_pair;

void kg_joints_destroy(kg_world* world);
/* How many live joints (0 without a pool). */
int kg_joints_live(const kg_world* world);

/* The checks of a definition's values that kg_create_*_joint makes (all but the bodies
 * and the world): the scene loader asks them too, so that a scene it accepts
 * instantiates. call names the caller in the message. */
kg_result kg_check_base_values(const kg_joint_base_def* base, const char* call);
kg_result kg_check_revolute_values(const kg_revolute_joint_def* def, const char* call);
kg_result kg_check_distance_values(const kg_distance_joint_def* def, const char* call);
kg_result kg_check_weld_values(const kg_weld_joint_def* def, const char* call);
kg_result kg_check_mouse_values(const kg_mouse_joint_def* def, const char* call);
kg_result kg_check_prismatic_values(const kg_prismatic_joint_def* def, const char* call);
kg_result kg_check_wheel_values(const kg_wheel_joint_def* def, const char* call);
kg_result kg_check_motor_values(const kg_motor_joint_def* def, const char* call);

struct kg_contact_rows;

/* The solve stage's share: rows prepared once a step (after the bodies are loaded), then
 * one pass over every joint (warm start, solve, relax): colour by colour, each colour's
 * joints in parallel (its revolute joints `lanes->width` at a time, in the solver's
 * lanes; `still` is the solver's still body), then the overflow serially; after the
 * sub-steps kg_joints_finish keeps the lanes' impulses in the rows. */
void kg_joints_prepare(kg_world* world, const kg_solver_body* bodies, kg_solver_params prm,
                       const struct kg_contact_rows* lanes, kg_u32 still);
void kg_joints_pass(kg_world* world, kg_solver_body* bodies, kg_solver_params prm, int pass);
void kg_joints_finish(kg_world* world);

/* Drops from pairs (count of them, sorted by (a, b), a < b) the pairs of bodies joined
 * by a joint that does not collide_connected; returns how many are left. A merge with
 * the sorted list of such pairs: one pass over the pairs while such a joint exists,
 * nothing otherwise. */
int kg_joints_filter_pairs(kg_world* world, struct kg_pair* pairs, int count);

/* The islands' links: body slot pairs (2 a link) of the joints between two bodies, and
 * their number in *count. */
const kg_u32* kg_joints_links(kg_world* world, int* count);

/* The sorted pairs kept apart (two slots each, kg_pair_is_joined's list) and their
 * number; the rows of slots [0, *slots) (a free slot's row has no bodies, so it is never
 * active); a count that moves whenever the links or pairs change. For the OpenCL backend. */
const kg_u32* kg_joints_apart(kg_world* world, int* count);
kg_joint_row* kg_joints_rows(kg_world* world, int* slots);
kg_u32 kg_joints_version(const kg_world* world);
/* The live joints colour by colour, the overflow's last (the order the passes take them
 * in: within a colour any order gives the same bits); colour c's are order[color_start[c],
 * color_start[c + 1]), the overflow is c = KG_JOINT_COLORS, and color_start[KG_JOINT_COLORS
 * + 1] is their number (all zero without joints). */
const kg_i32* kg_joints_order(kg_world* world, int color_start[KG_JOINT_COLORS + 2]);

/* Body slot `slot` (handle body) is being destroyed: its joints go with it, each listed
 * for kg_world_get_joint_events, the other bodies woken. */
void kg_joints_body_destroyed(kg_world* world, kg_u32 slot, kg_body body);

/* The slots a joint may hold ([0, slots)) and the handle of slot i's live joint (all
 * zero when none): for walking the joints in slot order (debug draw). */
int kg_joints_slots(const kg_world* world);
kg_joint kg_joint_of_slot(const kg_world* world, uint32_t i);

/* A step ended (its stages done): the joints whose reaction passed a break threshold are
 * destroyed, each listed as KG_JOINT_EVENT_BROKEN. Serial, in slot order, on the host
 * (either backend leaves the rows there). */
void kg_joints_after_step(kg_world* world);

/* A step begins: the joints destroyed since the last one become its events. */
void kg_joints_begin_step(kg_world* world);

/* Snapshots (core/snapshot.c): the pool's slots, rows and generations are written; read
 * back into a pool of their own, checked against the snapshot's bodies (a forged one is
 * rejected on the reader), adopted by the world when the whole snapshot was read. Joint
 * events of the step before are not kept, nor the colours and lists made from the rows
 * (made again to the same bits). */
struct kg_snap_out;
struct kg_snap_in;
void kg_joints_snapshot(const kg_world* world, struct kg_snap_out* out);
kg_result kg_joints_from_snapshot(const kg_body_pool* bodies, struct kg_snap_in* in, struct kg_joints** out);
void kg_joints_adopt(kg_world* world, struct kg_joints* restored);
void kg_joints_discard(struct kg_joints* j);
/* The pool's element sizes folded into h, for the snapshot's layout fingerprint. */
uint64_t kg_joints_layout(uint64_t h);

#endif
