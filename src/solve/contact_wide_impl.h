/* The gather, scatter and pass loops of contact_wide.h for one width, the contacts' and
 * the revolute joints' (no include guard: included once per width, C only, each width in
 * a file of its own). Before including: contact_row.h for the width (contact_solver.h
 * and joint_row.h have made width 1, with joint_revolute_row.h), and KG_LANE_OF(v,
 * lane), one lane of a lane value as an lvalue. */

#if KG_W > 1
#include "solve/joint_revolute_row.h"
#endif
#include "core/prefetch.h"

#define KG_WIDE3(name, w) name##_w##w
#define KG_WIDE2(name, w) KG_WIDE3(name, w)
#define KG_WIDE(name) KG_WIDE2(name, KG_W)
#if KG_W == 1
#define KG_ROWFN(name) name
#define kg_wrow kg_contact_constraint
#define kg_wmotion kg_body_motion
#else
#define KG_ROWFN(name) KG_WIDE(name)
#define kg_wrow KG_WIDE(kg_contact_constraint)
#define kg_wmotion KG_WIDE(kg_body_motion)
#endif

#ifndef KG_TRANSPOSES
/* Lanes from rows: lane l of out[k] is rows[l][k], for k < W; data movement only, a float
 * at a time. (A width may bring its own, with SIMD shuffles: KG_TRANSPOSES, together
 * with kg_columns_to_rows.) */
static inline void KG_WIDE(kg_rows_to_lanes)(const float* const rows[KG_W], kg_lane out[KG_W])
{
    for (int lane = 0; lane < KG_W; ++lane) {
        for (int k = 0; k < KG_W; ++k) {
            KG_LANE_OF(out[k], lane) = rows[lane][k];
        }
    }
}

/* Bit l set where lane l's `moves` column (as gathered) is not zero. */
static inline unsigned KG_WIDE(kg_movers)(kg_lane moves)
{
    unsigned mask = 0u;
    for (int lane = 0; lane < KG_W; ++lane) {
        kg_u32 bits;
        memcpy(&bits, &KG_LANE_OF(moves, lane), sizeof bits);
        mask |= (bits != 0u ? 1u : 0u) << lane;
    }
    return mask;
}

/* Four columns back into four floats of the bodies of the lanes in movers, from float
 * `offset` of each (0: the velocities and dp.x; 3: the motion, dp and dq). */
static inline void KG_WIDE(kg_columns_to_rows)(kg_solver_body* bodies, kg_lindex slots, unsigned movers,
                                               const kg_lane columns[4], int offset)
{
    for (int lane = 0; lane < KG_W; ++lane) {
        float* row = (float*)&bodies[KG_LANE_OF(slots, lane)] + offset;
        for (int k = 0; (movers >> lane & 1u) && k < 4; ++k) {
            row[k] = KG_LANE_OF(columns[k], lane);
        }
    }
}
#endif

KG_STATIC_ASSERT(sizeof(KG_ROWFN(kg_prepare_input)) == KG_PREPARE_INPUT_FLOATS * sizeof(kg_lane),
                 prepare_input_is_lanes_of_floats);
KG_STATIC_ASSERT(KG_PREPARE_INPUT_FLOATS % KG_W == 0, prepare_input_in_whole_transposes);

#if KG_W > 1 && !defined(KG_ROWS8_TO_LANES)
KG_STATIC_ASSERT(8 % KG_W == 0, eight_floats_in_whole_transposes);
/* Eight columns from W rows at offset: lane l of out[k] is rows[l][offset + k], k < 8, W
 * floats at a time. (A width wider than 8 brings its own: KG_ROWS8_TO_LANES.) */
static inline void KG_WIDE(kg_rows8_to_lanes)(const float* const rows[KG_W], int offset, kg_lane out[8])
{
    for (int f = 0; f < 8; f += KG_W) {
        const float* part[KG_W];
        for (int lane = 0; lane < KG_W; ++lane) {
            part[lane] = rows[lane] + offset + f;
        }
        KG_WIDE(kg_rows_to_lanes)(part, out + f);
    }
}
#endif

/* A head's first eight fields are moved into lanes as floats, its last two one at a time. */
KG_STATIC_ASSERT(offsetof(kg_row_head, inv_i_a) == 7 * sizeof(float), head_starts_with_eight_fields);

extern const kg_contact_rows KG_WIDE(kg_contact_rows);

/* Block `block` from the heads and inputs staged in it (contact_wide.h), moved into lanes
 * by the width's transposes, all of them read before the rows are written over them. */
static void KG_WIDE(kg_prepare)(void* blocks, int block, kg_solver_params prm)
{
    const kg_contact_rows* rows = &KG_WIDE(kg_contact_rows);
    const kg_row_head* heads = kg_staged_head(blocks, rows, block, 0);
    const kg_prepare_input* inputs = kg_staged_input(blocks, rows, block, 0);
#if KG_W == 1
    kg_row_head head = heads[0];
#else
    kg_lane head[8], inv_mass_b, inv_i_b; /* a, b, contact, point_count, friction, restitution, inv_mass_a, inv_i_a */
    const float* head_rows[KG_W];
    for (int lane = 0; lane < KG_W; ++lane) {
        head_rows[lane] = (const float*)&heads[lane];
        KG_LANE_OF(inv_mass_b, lane) = heads[lane].inv_mass_b;
        KG_LANE_OF(inv_i_b, lane) = heads[lane].inv_i_b;
    }
    KG_WIDE(kg_rows8_to_lanes)(head_rows, 0, head);
#endif
    /* the inputs, all floats in the same order at every width, W fields at a time */
    KG_ROWFN(kg_prepare_input) in;
    kg_lane* fields = (kg_lane*)&in;
    for (int f = 0; f < KG_PREPARE_INPUT_FLOATS; f += KG_W) {
        const float* lanes[KG_W];
        for (int lane = 0; lane < KG_W; ++lane) {
            lanes[lane] = (const float*)&inputs[lane] + f;
        }
        KG_WIDE(kg_rows_to_lanes)(lanes, fields + f);
    }
    __asm__ __volatile__("" ::: "memory"); /* no read of the sources moved below a write of the rows */
    kg_wrow* r = (kg_wrow*)blocks + block;
#if KG_W == 1
    kg_constraint_head(r, &head);
#else
    r->a = (kg_lindex)head[0]; /* the bits, as they were staged */
    r->b = (kg_lindex)head[1];
    r->contact = (kg_lindex)head[2];
    r->point_count = (kg_lint)head[3];
    r->friction = head[4];
    r->restitution = head[5];
    r->inv_mass_a = head[6];
    r->inv_i_a = head[7];
    r->inv_mass_b = inv_mass_b;
    r->inv_i_b = inv_i_b;
#endif
    KG_ROWFN(kg_contact_prepare_lanes)(r, &in, prm);
}

KG_STATIC_ASSERT(sizeof(kg_wrow) == KG_W * sizeof(kg_contact_constraint), row_is_the_constraint_widened);
KG_STATIC_ASSERT(offsetof(kg_wrow, point_count) == KG_W * offsetof(kg_contact_constraint, point_count),
                 row_point_count_widened);
KG_STATIC_ASSERT(offsetof(kg_wrow, points[1].relative_velocity) ==
                     KG_W * offsetof(kg_contact_constraint, points[1].relative_velocity),
                 row_points_widened);

#if KG_W <= KG_BODY_FLOATS
/* The solver bodies of slots, a lane each, into the columns of their motions (column k's
 * lane l is float k of lane l's body; the last column is `moves`), W floats at a time.
 * (Lanes wider than a body bring their own: contact_wide16.c.) */
static inline void KG_WIDE(kg_rows_to_columns)(const kg_solver_body* bodies, kg_lindex slots,
                                               kg_lane columns[KG_BODY_FLOATS])
{
    for (int f = 0; f < KG_BODY_FLOATS; f += KG_W) {
        const float* rows[KG_W];
        for (int lane = 0; lane < KG_W; ++lane) {
            rows[lane] = (const float*)&bodies[KG_LANE_OF(slots, lane)] + f;
        }
        KG_WIDE(kg_rows_to_lanes)(rows, columns + f);
    }
}
#endif

/* The motions of the bodies of slots, in lanes; a lane without a body is still. */
static inline kg_wmotion KG_WIDE(kg_gather)(const kg_solver_body* bodies, kg_lindex slots, unsigned* movers)
{
    kg_lane c[KG_BODY_FLOATS];
    KG_WIDE(kg_rows_to_columns)(bodies, slots, c);
    *movers = KG_WIDE(kg_movers)(c[7]);
    kg_wmotion m;
    m.v.x = c[0];
    m.v.y = c[1];
    m.w = c[2];
    m.dp.x = c[3];
    m.dp.y = c[4];
    m.dq.c = c[5];
    m.dq.s = c[6];
    return m;
}

/* The velocities back to the bodies that take impulses (all a pass changes): the lanes
 * in movers. A moving body is in one lane of a colour at most, so no other lane or thread
 * writes it meanwhile. */
static inline void KG_WIDE(kg_scatter)(kg_solver_body* bodies, kg_lindex slots, unsigned movers, const kg_wmotion* m)
{
    const kg_lane c[4] = {m->v.x, m->v.y, m->w, m->dp.x};
    KG_WIDE(kg_columns_to_rows)(bodies, slots, movers, c, 0);
}

/* How many blocks ahead a pass asks for the rows it will read and write, where they do
 * not fit in the cache (kg_contact_rows.run's `stream`): about 2.7 KB, a 16-lane block.
 * The hardware prefetcher fell behind the passes, whose reads jump between the fields
 * of a block: asked for ahead, many_pyramids' passes (9.7 MB of rows) took 4.4 ms a step
 * where they took 5.9 (perf, alternated runs); one, two or four 16-lane blocks ahead did
 * as well, every other line did not. Rows in the cache gain nothing and pay the
 * instructions (large_pyramid's warm start, 2.5 MB of rows: 20% slower). */
#define KG_ROWS_AHEAD (KG_W < 16 ? 16 / KG_W : 1)

/* Blocks [begin, end) through one pass: gather, row code, scatter. */
static inline __attribute__((always_inline)) void KG_WIDE(kg_run_blocks)(void* blocks, int begin, int end,
                                                                         kg_solver_body* bodies, kg_solver_params prm,
                                                                         kg_constraint_pass pass, int stream)
{
    for (int k = begin; k < end; ++k) {
        kg_wrow* r = (kg_wrow*)blocks + k;
        if (stream && k + KG_ROWS_AHEAD < end) {
            kg_prefetch_bytes(r + KG_ROWS_AHEAD, sizeof *r, 1);
        }
        unsigned movers_a, movers_b;
        kg_wmotion a = KG_WIDE(kg_gather)(bodies, r->a, &movers_a), b = KG_WIDE(kg_gather)(bodies, r->b, &movers_b);
        KG_ROWFN(kg_contact_pass)(r, &a, &b, prm, pass);
        KG_WIDE(kg_scatter)(bodies, r->a, movers_a, &a);
        KG_WIDE(kg_scatter)(bodies, r->b, movers_b, &b);
    }
}

/* One loop per pass, each with its pass's row code inlined whole (flatten): the pass is
 * known in the loop, so the motions stay in registers instead of going through memory to
 * an out-of-line solve, and the relax drops the push-out's work. The same operations in
 * the same order: the bits do not change. large_pyramid's solve: 10% fewer instructions
 * (callgrind), the step 11% shorter; many_pyramids' 9% (one thread, 16 lanes). */
#define KG_PASS_LOOP(name, pass)                                                                                    \
    static __attribute__((flatten)) void KG_WIDE(name)(void* blocks, int begin, int end, kg_solver_body* bodies, \
                                                       kg_solver_params prm, int stream)                          \
    {                                                                                                               \
        KG_WIDE(kg_run_blocks)(blocks, begin, end, bodies, prm, pass, stream);                                      \
    }
KG_PASS_LOOP(kg_run_warm_start, KG_PASS_WARM_START)
KG_PASS_LOOP(kg_run_solve, KG_PASS_SOLVE)
KG_PASS_LOOP(kg_run_relax, KG_PASS_RELAX)
KG_PASS_LOOP(kg_run_restitution, KG_PASS_RESTITUTION)
#undef KG_PASS_LOOP

static void KG_WIDE(kg_run)(void* blocks, int begin, int end, kg_solver_body* bodies, kg_solver_params prm,
                            kg_constraint_pass pass, int stream)
{
    switch (pass) {
    case KG_PASS_WARM_START: KG_WIDE(kg_run_warm_start)(blocks, begin, end, bodies, prm, stream); break;
    case KG_PASS_SOLVE: KG_WIDE(kg_run_solve)(blocks, begin, end, bodies, prm, stream); break;
    case KG_PASS_RELAX: KG_WIDE(kg_run_relax)(blocks, begin, end, bodies, prm, stream); break;
    default: KG_WIDE(kg_run_restitution)(blocks, begin, end, bodies, prm, stream); break;
    }
}

#define kg_wrevolute KG_ROWFN(kg_revolute_lanes)
KG_STATIC_ASSERT(sizeof(kg_wrevolute) == KG_W * sizeof(kg_revolute_lanes), revolute_lanes_widened);
KG_STATIC_ASSERT(offsetof(kg_wrevolute, b) == KG_W * offsetof(kg_revolute_lanes, b), revolute_slots_widened);

/* Revolute joints W at a time, as the contacts: gather, the lanes' pass, scatter. The
 * pass and the iteration are known in the loop, once for all its blocks. */
static __attribute__((flatten)) void KG_WIDE(kg_run_revolute)(void* blocks, int begin, int end,
                                                              kg_solver_body* bodies, kg_solver_params prm, int pass,
                                                              int last_iteration)
{
    for (int k = begin; k < end; ++k) {
        kg_wrevolute* r = (kg_wrevolute*)blocks + k;
        unsigned movers_a, movers_b;
        kg_wmotion a = KG_WIDE(kg_gather)(bodies, r->a, &movers_a), b = KG_WIDE(kg_gather)(bodies, r->b, &movers_b);
        KG_ROWFN(kg_revolute_pass)(r, &a, &b, prm, pass, last_iteration);
        KG_WIDE(kg_scatter)(bodies, r->a, movers_a, &a);
        KG_WIDE(kg_scatter)(bodies, r->b, movers_b, &b);
    }
}
#undef kg_wrevolute

/* ---- the bodies' sub-step, W consecutive slots at a time ---- */

#if KG_W > 1
/* The slots first, first + 1, ... in lanes. */
static inline kg_lindex KG_WIDE(kg_consecutive_slots)(int first)
{
    kg_lindex slots;
    for (int lane = 0; lane < KG_W; ++lane) {
        KG_LANE_OF(slots, lane) = (kg_u32)(first + lane);
    }
    return slots;
}
#endif

/* One sub-step's velocity update of the bodies [begin, end) that take impulses
 * (body_step.h's kg_integrate_body_velocity, W at a time; the last few one at a time). */
static void KG_WIDE(kg_integrate_velocities)(kg_solver_body* bodies, const kg_velocity_step* steps, int begin,
                                             int end, kg_integrate_params prm)
{
    int i = begin;
#if KG_W > 1 /* else every body goes through body_step.h's loop below */
    for (; i + KG_W <= end; i += KG_W) {
        kg_lindex slots = KG_WIDE(kg_consecutive_slots)(i);
        unsigned movers;
        kg_wmotion m = KG_WIDE(kg_gather)(bodies, slots, &movers);
        const float* rows[KG_W];
        for (int lane = 0; lane < KG_W; ++lane) {
            rows[lane] = (const float*)&steps[i + lane];
        }
        kg_lane c[8]; /* dv.x, dv.y, dw, lin_factor, ang_factor, unused */
        KG_WIDE(kg_rows8_to_lanes)(rows, 0, c);
        KG_ROWFN(kg_velocity_lanes) s;
        s.dv.x = c[0];
        s.dv.y = c[1];
        s.dw = c[2];
        s.lin_factor = c[3];
        s.ang_factor = c[4];
        KG_ROWFN(kg_apply_velocity_lanes)(&m.v, &m.w, &s, prm);
        KG_WIDE(kg_scatter)(bodies, slots, movers, &m);
    }
#endif
    for (; i < end; ++i) {
        kg_integrate_body_velocity((kg_u32)i, bodies, steps, prm);
    }
}

/* One sub-step's motion of the bodies [begin, end) that move (body_step.h's
 * kg_integrate_body_position, W at a time; the last few one at a time). */
static void KG_WIDE(kg_integrate_positions)(kg_solver_body* bodies, const kg_u32* flags, int begin, int end, float h)
{
    int i = begin;
#if KG_W > 1 /* else every body goes through body_step.h's loop below */
    for (; i + KG_W <= end; i += KG_W) {
        kg_lindex slots = KG_WIDE(kg_consecutive_slots)(i);
        unsigned takes_impulses, moving = 0u;
        kg_wmotion m = KG_WIDE(kg_gather)(bodies, slots, &takes_impulses);
        for (int lane = 0; lane < KG_W; ++lane) {
            moving |= (unsigned)kg_flags_move(flags[i + lane]) << lane;
        }
        KG_ROWFN(kg_integrate_position_lanes)(&m.dp, &m.dq, m.v, m.w, h);
        const kg_lane motion[4] = {m.dp.x, m.dp.y, m.dq.c, m.dq.s};
        KG_WIDE(kg_columns_to_rows)(bodies, slots, moving, motion, 3);
    }
#endif
    for (; i < end; ++i) {
        kg_integrate_body_position((kg_u32)i, h, flags, bodies);
    }
}

const kg_contact_rows KG_WIDE(kg_contact_rows) = {KG_W,
                                                  sizeof(kg_wrow),
                                                  KG_WIDE(kg_prepare),
                                                  KG_WIDE(kg_run),
                                                  KG_WIDE(kg_run_revolute),
                                                  KG_WIDE(kg_integrate_velocities),
                                                  KG_WIDE(kg_integrate_positions)};
