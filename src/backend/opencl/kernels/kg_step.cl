/* The kernels of a step: one work-item per body, contact or constraint, each calling the
 * per-element functions the CPU backend calls, on the same data layout (the body pool's
 * arrays, kg_contact, kg_contact_constraint), so both backends compute the same bits.
 *
 * Work-items copy what they need from global memory into private variables, call the
 * shared function, and write back only the element they own (gather, never scatter).
 * Every kernel takes its element count and returns for the padding work-items.
 * The body types (KG_BODY_*), the pass and
 * applicator numbers (KG_PASS_*, KG_APPLICATOR_*_KIND) come as build options from the
 * host's definitions, so the two sides cannot disagree. */
#include "core/body_flags.h"
#include "core/kg_layout.h"
#include "collide/aabb.h"
#include "solve/integrate.h"
#include "solve/coloring.h"
#include "solve/contact_solver.h"
#include "solve/island.h"

/* kg_body_update_transform of core/body_pool.c: the origin transform from the centre. */
KG_FN kg_xf kg_origin_xf(kg_vec2 center, kg_rot q, kg_vec2 local_center)
{
    kg_xf t;
    t.q = q;
    t.p = kg_sub(center, kg_rotate(q, local_center));
    return t;
}

/* ---- forces ---------------------------------------------------------------------- */

/* A built-in applicator (gravity or wind) on every body (all != 0: work-item i is slot i)
 * or on a list of (slot, multiplicity) pairs, each slot once: a body listed twice gets
 * the force added twice, in sequence, as the CPU backend's loop over the list does. */
__kernel void kg_apply_builtin_force(int count, int all, __global const uint2* targets, int kind, float vx, float vy,
                                     float strength, float wind_drag, __global const kg_u32* flags,
                                     __global const float* mass, __global kg_vec2* force,
                                     __global float* drag)
{
    int k = (int)get_global_id(0);
    if (k >= count) {
        return;
    }
    kg_u32 i = all ? (kg_u32)k : targets[k].x;
    kg_u32 repeat = all ? 1u : targets[k].y;
    if (!kg_flags_simulated(flags[i])) {
        return;
    }
    int gravity = kind == KG_APPLICATOR_GRAVITY_KIND;
    kg_vec2 f = kg_scale(gravity ? mass[i] : strength, kg_v2(vx, vy));
    kg_vec2 sum = force[i];
    float drag_sum = drag[i];
    for (kg_u32 r = 0; r < repeat; ++r) {
        sum = kg_add(sum, f);
        drag_sum += gravity ? 0.0f : wind_drag;
    }
    force[i] = sum;
    drag[i] = drag_sum;
}

/* ---- solver ---------------------------------------------------------------------- */

/* kg_freeze of solve/solver.c: out of the simulation, back at its last finite pose (the
 * host warns when it next reads the flags back). */
KG_FN void kg_freeze_body(int i, __global kg_u32* flags, __global kg_vec2* velocity, __global float* omega,
                          __global kg_vec2* force, __global float* torque, __global kg_rot* rot,
                          __global kg_vec2* center, __global const kg_xf* xf, __global const kg_vec2* local_center)
{
    kg_xf last = xf[i];
    flags[i] |= KG_FLAG_FROZEN;
    velocity[i] = kg_v2(0.0f, 0.0f);
    omega[i] = 0.0f;
    force[i] = kg_v2(0.0f, 0.0f);
    torque[i] = 0.0f;
    rot[i] = last.q;
    center[i] = kg_xf_point(last, local_center[i]);
}

/* kg_load_bodies of solve/solver.c: what reached a body between steps non-finite (through
 * the API) is frozen before it is solved, so it cannot reach a neighbour. */
__kernel void kg_load_bodies(int count, __global kg_u32* flags, __global kg_vec2* velocity, __global float* omega,
                             __global kg_vec2* force, __global float* torque, __global kg_rot* rot,
                             __global kg_vec2* center, __global const kg_xf* xf,
                             __global const kg_vec2* local_center, __global kg_solver_body* bodies)
{
    int i = (int)get_global_id(0);
    if (i >= count) {
        return;
    }
    int inputs_finite = kg_vec_is_finite(velocity[i]) && kg_is_finite(omega[i]) && kg_vec_is_finite(force[i]) &&
                        kg_is_finite(torque[i]);
    if (kg_flags_simulated(flags[i]) && !inputs_finite) {
        kg_freeze_body(i, flags, velocity, omega, force, torque, rot, center, xf, local_center);
    }
    kg_solver_body sb;
    sb.motion.v = velocity[i];
    sb.motion.w = omega[i];
    sb.motion.dp = kg_v2(0.0f, 0.0f);
    sb.motion.dq = kg_rot_identity();
    sb.moves = (kg_u32)kg_flags_simulated(flags[i]);
    bodies[i] = sb;
}

__kernel void kg_integrate_velocities(int count, float h, float gx, float gy, float max_linear_speed,
                                      __global kg_solver_body* bodies, __global const kg_vec2* force,
                                      __global const float* torque, __global const float* drag,
                                      __global const float* inv_mass,
                                      __global const float* inv_inertia, __global const float* linear_damping,
                                      __global const float* angular_damping)
{
    int i = (int)get_global_id(0);
    if (i >= count || !bodies[i].moves) {
        return;
    }
    kg_integrate_params prm;
    prm.gravity = kg_v2(gx, gy);
    prm.h = h;
    prm.max_linear_speed = max_linear_speed;
    kg_body_motion m = bodies[i].motion;
    kg_integrate_velocity(&m.v, &m.w, force[i], torque[i], drag[i], inv_mass[i], inv_inertia[i], linear_damping[i],
                          angular_damping[i], prm);
    bodies[i].motion = m;
}

__kernel void kg_integrate_positions(int count, float h, __global const kg_u32* flags,
                                     __global kg_solver_body* bodies)
{
    int i = (int)get_global_id(0);
    if (i >= count || !kg_flags_move(flags[i])) {
        return;
    }
    kg_body_motion m = bodies[i].motion;
    kg_integrate_position(&m.dp, &m.dq, m.v, m.w, h);
    bodies[i].motion = m;
}

/* kg_store_bodies of solve/solver.c: velocities back to the pool, the motion applied, and
 * with sleeping on (sleep != 0) the rest timers advanced over the step's motion (dt: the
 * whole step's). */
__kernel void kg_store_bodies(int count, int sleep, float dt, float sleep_speed, __global const kg_u32* flags,
                              __global const kg_solver_body* bodies, __global kg_vec2* velocity,
                              __global float* omega, __global kg_vec2* center, __global kg_rot* rot,
                              __global const kg_shape* shape, __global const kg_vec2* local_center,
                              __global float* sleep_time)
{
    int i = (int)get_global_id(0);
    if (i >= count || !kg_flags_move(flags[i])) {
        return;
    }
    kg_body_motion m = bodies[i].motion;
    velocity[i] = m.v;
    omega[i] = m.w;
    center[i] = kg_add(center[i], m.dp);
    rot[i] = kg_rot_normalize(kg_rot_mul(m.dq, rot[i]));
    if (sleep && bodies[i].moves) {
        kg_shape s = shape[i];
        float extent = kg_shape_extent(&s, local_center[i]);
        sleep_time[i] = kg_rest_timer(sleep_time[i], m, extent, dt, sleep_speed);
    }
}

KG_FN kg_body_motion kg_load_motion(__global const kg_solver_body* bodies, kg_u32 slot)
{
    kg_body_motion still;
    still.v = kg_v2(0.0f, 0.0f);
    still.w = 0.0f;
    still.dp = kg_v2(0.0f, 0.0f);
    still.dq = kg_rot_identity();
    return slot == KG_NULL_INDEX ? still : bodies[slot].motion;
}

KG_FN void kg_store_motion(__global kg_solver_body* bodies, kg_u32 slot, kg_body_motion m)
{
    if (slot != KG_NULL_INDEX && bodies[slot].moves) {
        bodies[slot].motion.v = m.v;
        bodies[slot].motion.w = m.w;
    }
}

KG_FN int kg_takes_impulses(__global const kg_solver_body* bodies, kg_u32 slot)
{
    return slot != KG_NULL_INDEX && bodies[slot].moves;
}

/* Constraint k from contact k: its head, prepare input and prepare are the shared ones. */
__kernel void kg_prepare_contacts(int count, __global const kg_solver_params* params, __global const kg_contact* contacts,
                                  __global kg_contact_constraint* constraints, __global const kg_solver_body* bodies,
                                  __global const float* inv_mass, __global const float* inv_inertia,
                                  __global const kg_xf* xf, __global const kg_vec2* center)
{
    int k = (int)get_global_id(0);
    if (k >= count) {
        return;
    }
    kg_solver_params prm = *params;
    kg_contact ct = contacts[k];
    kg_contact_constraint c;
    int a_moves = kg_takes_impulses(bodies, ct.a);
    int b_moves = kg_takes_impulses(bodies, ct.b);
    kg_row_head head = kg_row_head_of(&ct, (kg_u32)k, a_moves ? inv_mass[ct.a] : 0.0f, a_moves ? inv_inertia[ct.a] : 0.0f,
                                      b_moves ? inv_mass[ct.b] : 0.0f, b_moves ? inv_inertia[ct.b] : 0.0f);
    kg_constraint_head(&c, &head);
    kg_body_motion ma = kg_load_motion(bodies, ct.a), mb = kg_load_motion(bodies, ct.b);
    kg_vec2 origin_a = ct.a != KG_NULL_INDEX ? xf[ct.a].p : kg_v2(0.0f, 0.0f);
    kg_vec2 origin_b = ct.b != KG_NULL_INDEX ? xf[ct.b].p : kg_v2(0.0f, 0.0f);
    kg_vec2 center_a = ct.a != KG_NULL_INDEX ? center[ct.a] : origin_a;
    kg_vec2 center_b = ct.b != KG_NULL_INDEX ? center[ct.b] : origin_b;
    kg_prepare_input in = kg_prepare_input_of(&ct.manifold, origin_a, center_a, origin_b, center_b, ma.v, ma.w, mb.v, mb.w);
    kg_contact_prepare_lanes(&c, &in, prm);
    if (!a_moves && !b_moves) {
        c.point_count = 0; /* asleep or frozen on both sides: nothing to solve, impulses kept */
    }
    constraints[k] = c;
}

KG_FN void kg_solve_one(kg_contact_constraint* c, __global kg_solver_body* bodies, kg_solver_params prm, int pass)
{
    if (c->point_count == 0) {
        return; /* between sleeping or frozen bodies: nothing moves */
    }
    kg_body_motion a = kg_load_motion(bodies, c->a), b = kg_load_motion(bodies, c->b);
    if (pass == KG_PASS_WARM_START) {
        kg_contact_warm_start(c, &a, &b);
    } else if (pass == KG_PASS_SOLVE) {
        kg_contact_solve(c, &a, &b, prm, 1);
    } else if (pass == KG_PASS_RELAX) {
        kg_contact_solve(c, &a, &b, prm, 0);
    } else {
        kg_contact_restitution(c, &a, &b, prm);
    }
    kg_store_motion(bodies, c->a, a);
    kg_store_motion(bodies, c->b, b);
}

/* The constraints grouped by colour (order is solve/coloring.h's), so that each pass reads a
 * colour's constraints from one contiguous range, as the CPU solver does. */
__kernel void kg_gather_colored(int count, __global const int* order,
                                __global const kg_contact_constraint* constraints,
                                __global kg_contact_constraint* colored)
{
    int k = (int)get_global_id(0);
    if (k < count) {
        colored[k] = constraints[order[k]];
    }
}

KG_FN void kg_solve_at(__global kg_contact_constraint* colored, int index, __global kg_solver_body* bodies,
                       kg_solver_params prm, int pass)
{
    kg_contact_constraint c = colored[index];
    kg_solve_one(&c, bodies, prm, pass);
    colored[index] = c;
}

/* One pass over the colored constraints [first, first + count): one colour in parallel
 * (its constraints share no moving body), or, serial != 0, the overflow in order by a
 * single work-item. */
__kernel void kg_solve_color(int first, int count, int serial, int pass, __global const kg_solver_params* params,
                             __global kg_contact_constraint* colored, __global kg_solver_body* bodies)
{
    int k = (int)get_global_id(0);
    kg_solver_params prm = *params;
    if (!serial && k < count) {
        kg_solve_at(colored, first + k, bodies, prm, pass);
    }
    for (int j = 0; serial && k == 0 && j < count; ++j) {
        kg_solve_at(colored, first + j, bodies, prm, pass);
    }
}

/* One pass over every colour and the overflow, by a single work-group: the colours in
 * sequence with a barrier between them, the overflow by work-item 0. One launch instead
 * of one per colour, for worlds too small to fill the device, where launches cost more
 * than the work. color_start is solve/coloring.h's. */
__kernel void kg_solve_colors_in_group(int pass, __global const int* color_start,
                                       __global const kg_solver_params* params,
                                       __global kg_contact_constraint* colored, __global kg_solver_body* bodies)
{
    int lid = (int)get_local_id(0), size = (int)get_local_size(0);
    kg_solver_params prm = *params;
    for (int color = 0; color < KG_COLOR_COUNT; ++color) {
        for (int j = color_start[color] + lid; j < color_start[color + 1]; j += size) {
            kg_solve_at(colored, j, bodies, prm, pass);
        }
        barrier(CLK_GLOBAL_MEM_FENCE);
    }
    for (int j = color_start[KG_COLOR_COUNT]; lid == 0 && j < color_start[KG_COLOR_COUNT + 1]; ++j) {
        kg_solve_at(colored, j, bodies, prm, pass);
    }
}

/* kg_store_impulses_range of solve/solver.c: impulses back into the contacts, for warm
 * starting next step and for kg_world_get_contact. */
__kernel void kg_store_impulses(int count, __global const kg_contact_constraint* colored,
                                __global kg_contact* contacts)
{
    int k = (int)get_global_id(0);
    if (k >= count) {
        return;
    }
    kg_contact_constraint c = colored[k];
    for (int j = 0; j < c.point_count; ++j) {
        contacts[c.contact].manifold.points[j].normal_impulse = c.points[j].normal_impulse;
        contacts[c.contact].manifold.points[j].tangent_impulse = c.points[j].tangent_impulse;
        contacts[c.contact].manifold.points[j].normal_velocity = c.points[j].relative_velocity;
    }
}

/* ---- finalize -------------------------------------------------------------------- */

KG_FN int kg_state_finite(kg_vec2 c, kg_rot q, kg_vec2 v, float w)
{
    return kg_vec_is_finite(c) && kg_vec_is_finite(v) && kg_is_finite(w) && kg_is_finite(q.c) && kg_is_finite(q.s);
}

/* kg_stage_finalize of solve/solver.c with kg_body_update_transform of core/body_pool.c:
 * forces cleared, non-finite bodies frozen at their last finite pose (the host warns when
 * it next reads the flags back), origin transforms updated, and bounds swept over the
 * motion of the next step (dt of this one). */
__kernel void kg_finalize(int count, float dt, __global kg_u32* flags, __global kg_vec2* center, __global kg_rot* rot,
                          __global kg_vec2* velocity, __global float* omega, __global kg_vec2* force,
                          __global float* torque, __global float* drag, __global kg_xf* xf, __global kg_aabb* aabb,
                          __global const kg_shape* shape, __global const kg_vec2* local_center)
{
    int i = (int)get_global_id(0);
    if (i >= count) {
        return;
    }
    kg_u32 f = flags[i];
    if (!kg_flags_alive(f)) {
        return;
    }
    force[i] = kg_v2(0.0f, 0.0f);
    torque[i] = 0.0f;
    drag[i] = 0.0f;
    kg_vec2 c = center[i];
    kg_rot q = rot[i];
    if ((f & KG_FLAG_FROZEN) == 0u && !kg_state_finite(c, q, velocity[i], omega[i])) {
        kg_freeze_body(i, flags, velocity, omega, force, torque, rot, center, xf, local_center);
        return;
    }
    if (kg_flags_type(f) == KG_BODY_STATIC) {
        return;
    }
    kg_xf t = kg_origin_xf(c, q, local_center[i]);
    kg_shape s = shape[i];
    xf[i] = t;
    aabb[i] = kg_aabb_sweep(kg_shape_aabb(&s, t), kg_scale(dt, velocity[i]));
}
