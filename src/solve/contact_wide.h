/* The contact passes on the CPU, W constraints at a time (contact_row.h instantiated
 * over SIMD lanes): constraint rows in blocks of W lanes, all from one colour, so no two
 * lanes share a moving body; a colour's tail is padded with empty lanes (no body). The
 * width is chosen once, at run time: 16 (AVX-512F and VL) or 8 (AVX2) where the CPU has
 * them, else 4 (SSE2 on x86-64, NEON on ARM, GCC's generic vectors elsewhere); 1 runs
 * the scalar rows. Every width gives the same bits (tests/test_determinism.c). */
#ifndef KG_CONTACT_WIDE_H
#define KG_CONTACT_WIDE_H

#include "solve/body_step.h"
#include "solve/contact_solver.h"
#include "solve/joint_row.h"

#include <stddef.h>
#include <string.h>

#define KG_MAX_LANES 16

typedef struct kg_contact_rows {
    int width;
    size_t block_size; /* bytes of a block of width rows */
    /* Prepares block `block` from the sources of its width lanes, staged in it
     * (kg_staged_head, kg_staged_input). */
    void (*prepare)(void* blocks, int block, kg_solver_params prm);
    /* One pass over blocks [begin, end): gathers the lanes' bodies, runs the pass, scatters;
     * asking for the rows ahead (stream) where they do not fit in the cache. */
    void (*run)(void* blocks, int begin, int end, kg_solver_body* bodies, kg_solver_params prm, kg_constraint_pass pass,
                int stream);
    /* One pass over blocks [begin, end) of revolute joints (joint_revolute_row.h), in the
     * pass's last iteration or not: a block is width kg_revolute_lanes, each 4-byte field
     * widened to width lanes in the same order (kg_revolute_lane_field), the world's
     * slot and a padding lane's the still body. */
    void (*run_revolute)(void* blocks, int begin, int end, kg_solver_body* bodies, kg_solver_params prm, int pass,
                         int last_iteration);
    /* One sub-step's velocity update, then motion, of the bodies [begin, end)
     * (body_row.h), width consecutive slots at a time. */
    void (*integrate_velocities)(kg_solver_body* bodies, const kg_velocity_step* steps, int begin, int end,
                                 kg_integrate_params prm);
    void (*integrate_positions)(kg_solver_body* bodies, const kg_u32* flags, int begin, int end, float h);
} kg_contact_rows;

/* Lane `lane` of the 4-byte field at byte offset `offset` of kg_revolute_lanes, in block
 * `block` of revolute joints width lanes wide. */
static inline unsigned char* kg_revolute_lane_field(void* blocks, int width, int block, int lane, size_t offset)
{
    return (unsigned char*)blocks + (size_t)block * width * sizeof(kg_revolute_lanes) + (size_t)width * offset +
           4u * (size_t)lane;
}

/* A block of width W is the width-1 constraint (kg_contact_constraint) with each of its
 * 4-byte fields widened to W lanes, in the same order: lane l of the field at byte
 * offset f of the constraint is at byte W f + 4 l of the block (contact_wide_impl.h
 * checks it). */
static inline const unsigned char* kg_lane_field(const void* blocks, const kg_contact_rows* rows, int block, int lane,
                                                 size_t offset)
{
    return (const unsigned char*)blocks + (size_t)block * rows->block_size + (size_t)rows->width * offset +
           4u * (size_t)lane;
}

/* Until a block is prepared its own memory holds its lanes' sources: width heads, then
 * width prepare inputs (a lane's head and input fill its 168 bytes), so that they are written where
 * the rows will be, in the cache when prepare reads them, and need no memory of their
 * own. Prepare reads them all before it writes a row. */
KG_STATIC_ASSERT(sizeof(kg_row_head) + sizeof(kg_prepare_input) <= sizeof(kg_contact_constraint),
                 sources_fit_in_their_rows);

static inline kg_row_head* kg_staged_head(void* blocks, const kg_contact_rows* rows, int block, int lane)
{
    return (kg_row_head*)((unsigned char*)blocks + (size_t)block * rows->block_size) + lane;
}

static inline kg_prepare_input* kg_staged_input(void* blocks, const kg_contact_rows* rows, int block, int lane)
{
    unsigned char* heads = (unsigned char*)blocks + (size_t)block * rows->block_size;
    return (kg_prepare_input*)(heads + (size_t)rows->width * sizeof(kg_row_head)) + lane;
}

/* A solver body read as floats: v.x, v.y, w, dp.x, dp.y, dq.c, dq.s, then moves. */
#define KG_BODY_FLOATS 8
KG_STATIC_ASSERT(sizeof(kg_solver_body) == KG_BODY_FLOATS * sizeof(float), solver_body_is_eight_floats);

/* A prepare input read as floats. */
#define KG_PREPARE_INPUT_FLOATS 32
KG_STATIC_ASSERT(sizeof(kg_prepare_input) == KG_PREPARE_INPUT_FLOATS * sizeof(float), prepare_input_is_floats);

/* A row's body slots index the solver bodies directly: the static world and padding
 * lanes name a still body of their own after the pool's slots, which takes no impulses,
 * so a gather needs no test. A pass scatters the first four floats of a lane's body (the
 * velocities, and dp.x as gathered) where the body takes impulses (its `moves`, gathered
 * with it). */

/* The rows of width 1, 4, 8 or 16, or 0 for the widest this CPU runs (KGYRO_SIMD_WIDTH
 * in the environment, 1, 4, 8 or 16, overrides it, for tests and measurements); NULL for a
 * width this build or CPU cannot run. */
const kg_contact_rows* kg_contact_rows_of(int width);

#endif
