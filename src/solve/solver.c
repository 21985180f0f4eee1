/* The solve stage (Box2D v3's soft step, see contact_solver.h and docs/design.md):
 *
 *   colour the constraint graph; prepare constraints from the contacts into their
 *   colours' rows
 *   for each sub-step:
 *       integrate velocities; warm start; solve (soft push-out);
 *       integrate positions; relax (no push-out)
 *   restitution; store the impulses back into the contacts for warm starting
 *
 * Every loop over constraints runs colour by colour; within a colour the constraints
 * share no moving body, so they run in parallel with results independent of the order. */
#include "solve/solver.h"
#include "core/parallel.h"
#include "collide/aabb.h"
#include "collide/collide.h"
#include "collide/continuous.h"
#include "collide/shape_index.h"
#include "collide/tilemap.h"
#include "core/alloc.h"
#include "core/error.h"
#include "core/joint.h"
#include "core/prefetch.h"
#include "solve/body_step.h"
#include "solve/contact_wide.h"
#include "solve/graph_color.h"
#include "solve/integrate.h"
#include "solve/island.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#define KG_CONSTRAINT_GRAIN 64
/* The contacts are prepared (and take their impulses back) a chunk of this many at a
 * time: a chunk's constraints of a colour follow those of the chunks before it, in
 * contact order, so chunks run in parallel, each with a running count per colour. */
#define KG_CHUNK 256
/* Rows beyond this many bytes are taken not to stay in the cache from one pass to the
 * next (contact_wide_impl.h, KG_ROWS_AHEAD): large_pyramid's 2.5 MB do, many_pyramids'
 * 9.7 MB do not (a core's share of the cache here is about 8 MB, measured by reading
 * buffers of growing size). */
#define KG_CACHED_ROW_BYTES (4u << 20)

/* A body's extents, computed once for each body that takes the slot and again when a
 * shape of the world was added or removed: generation is the body's (0: none yet). Each
 * slot is written by its own body only, so threads share nothing. */
typedef struct kg_cached_extents {
    kg_extents extents;
    kg_u32 generation;
    kg_u32 shapes_version; /* the shape pool's when computed: a shape added or removed moves it */
} kg_cached_extents;

struct kg_solver {
    const kg_contact_rows* rows; /* the SIMD width's row code */
    void* blocks;                /* rows of width lanes, colour by colour: what the passes run over */
    atomic_int* filled;          /* per block: the lanes staged so far by the ranges sharing it; 0 between steps */
    int block_capacity;
    int block_start[KG_COLOR_COUNT + 2]; /* colour c's blocks are [block_start[c], block_start[c+1]) */
    int* colors;                         /* per contact: its colour, KG_COLOR_COUNT for the overflow */
    int* chunk_start; /* per chunk, and one past the last: how many of each colour's constraints
                       * (KG_COLOR_COUNT + 1 ints) the chunks before it have; the last, the sizes */
    int chunks;
    int capacity;
    kg_graph_coloring coloring;
    kg_solver_body* bodies;           /* per body slot, then the still body (slot `still`) */
    kg_u32 still;                     /* what rows name for the static world and empty lanes */
    kg_velocity_step* velocity_steps; /* per body, made once a step */
    kg_static_list statics;           /* continuous collision's index of the static bodies, */
    int statics_listed;               /* made at statics.edits (statics_listed: ever) */
    kg_cached_extents* extents;         /* per body slot: its shape's, for continuous collision */
};

static kg_result kg_reserve_blocks(struct kg_solver* s, int blocks)
{
    kg_free(s->blocks);
    kg_free(s->filled);
    s->blocks = kg_alloc_zeroed((size_t)blocks * s->rows->block_size);
    s->filled = kg_alloc_zeroed((size_t)blocks * sizeof *s->filled);
    int ok = s->blocks && s->filled;
    s->block_capacity = ok ? blocks : 0;
    return ok ? KG_OK : kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate %d constraint blocks", blocks);
}

static void kg_free_constraints(struct kg_solver* s)
{
    kg_free(s->colors);
    kg_free(s->chunk_start);
    kg_graph_coloring_free(&s->coloring);
}

static kg_result kg_solver_reserve(struct kg_solver* s, int body_capacity, int capacity)
{
    kg_free_constraints(s);
    s->colors = kg_alloc_zeroed((size_t)capacity * sizeof *s->colors);
    s->chunk_start = kg_alloc_zeroed(((size_t)capacity / KG_CHUNK + 2) * (KG_COLOR_COUNT + 1) * sizeof(int));
    kg_result r = kg_graph_coloring_init(&s->coloring, body_capacity, capacity);
    if (r == KG_OK && (!s->colors || !s->chunk_start)) {
        r = kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate %d contact constraints", capacity);
    }
    s->capacity = r == KG_OK ? capacity : 0; /* a failed reserve is tried again next step */
    /* every colour's last block part empty, and a little overflow */
    int width = s->rows->width;
    return r == KG_OK ? kg_reserve_blocks(s, (capacity + width - 1) / width + 2 * KG_COLOR_COUNT) : r;
}

kg_result kg_solver_create(kg_world* world)
{
    struct kg_solver* s = kg_alloc_zeroed(sizeof *s);
    if (!s) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the solver");
    }
    world->solver = s;
    s->rows = kg_contact_rows_of(0);
    if (!s->rows) {
        kg_warn_once("simd-width", "KGYRO_SIMD_WIDTH names a width this build or CPU cannot run: using 1");
        s->rows = kg_contact_rows_of(1);
    }
    s->bodies = kg_alloc_zeroed(((size_t)world->def.max_bodies + 1) * sizeof *s->bodies);
    s->velocity_steps = kg_alloc_zeroed((size_t)world->def.max_bodies * sizeof *s->velocity_steps);
    s->statics.entries = kg_alloc_zeroed((size_t)world->def.max_bodies * sizeof *s->statics.entries);
    s->extents = kg_alloc_zeroed((size_t)world->def.max_bodies * sizeof *s->extents);
    if (!s->bodies || !s->velocity_steps || !s->statics.entries || !s->extents) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the solver");
    }
    s->still = (kg_u32)world->def.max_bodies;
    s->bodies[s->still].motion.dq = kg_rot_identity(); /* at rest, and never scattered to: moves 0 */
    return kg_solver_reserve(s, world->def.max_bodies, world->def.max_contacts);
}

void kg_solver_forget(kg_world* world)
{
    struct kg_solver* s = world->solver;
    s->statics_listed = 0;
    memset(s->extents, 0, (size_t)world->def.max_bodies * sizeof *s->extents); /* generation 0: none */
}

void kg_solver_destroy(kg_world* world)
{
    struct kg_solver* s = world->solver;
    if (!s) {
        return;
    }
    kg_free(s->blocks);
    kg_free(s->filled);
    kg_free_constraints(s);
    kg_free(s->bodies);
    kg_free(s->velocity_steps);
    kg_free(s->statics.entries);
    kg_free(s->extents);
    kg_free(s);
    world->solver = NULL;
}

/* ---- per-body loops ---------------------------------------------------------------- */

typedef struct kg_body_job {
    const kg_contact_rows* rows; /* the SIMD width's body loops */
    kg_body_pool* pool;
    kg_solver_body* bodies;
    kg_velocity_step* velocity_steps;
    kg_integrate_params prm;
    kg_rest_params rest;
    atomic_int froze; /* a body got a non-finite state when loaded */
} kg_body_job;

static void kg_warn_frozen(int i) { kg_warn_once("non-finite", "body %d got a non-finite state and was frozen", i); }

static void kg_load_bodies(void* context, int begin, int end)
{
    kg_body_job* job = context;
    kg_body_pool* p = job->pool;
    for (int i = begin; i < end; ++i) {
        if (kg_load_body_for_step((kg_u32)i, p->flags, p->velocity, p->omega, p->force, p->torque, p->rot, p->center,
                                  p->xf, p->local_center, job->bodies, p->drag, p->inv_mass, p->inv_inertia,
                                  p->linear_damping, p->angular_damping, job->prm, job->velocity_steps)) {
            kg_warn_frozen(i);
            atomic_store_explicit(&job->froze, 1, memory_order_relaxed);
        }
    }
}

static void kg_integrate_velocities(void* context, int begin, int end)
{
    kg_body_job* job = context;
    job->rows->integrate_velocities(job->bodies, job->velocity_steps, begin, end, job->prm);
}

static void kg_integrate_positions(void* context, int begin, int end)
{
    kg_body_job* job = context;
    job->rows->integrate_positions(job->bodies, job->pool->flags, begin, end, job->prm.h);
}

static void kg_store_bodies(void* context, int begin, int end)
{
    kg_body_job* job = context;
    kg_body_pool* p = job->pool;
    for (int i = begin; i < end; ++i) {
        kg_store_body((kg_u32)i, job->rest, p->flags, job->bodies, p->velocity, p->omega, p->center, p->rot, p->shape,
                      p->local_center, p->sleep_time);
    }
}

/* ---- per-constraint loops ---------------------------------------------------------- */

typedef struct kg_constraint_job {
    kg_body_pool* pool;
    kg_solver_body* bodies;
    kg_contact* contacts;
    int count;
    const struct kg_solver* solver;
    int first_block; /* of the colour a pass runs over */
    atomic_int* bounces; /* set by prepare when a constraint has restitution */
    kg_solver_params prm;
    kg_constraint_pass pass;
    int stream_rows; /* the rows are more than the cache holds: the passes ask for them ahead */
} kg_constraint_job;

static void kg_pass_range(void* context, int begin, int end)
{
    const kg_constraint_job* job = context;
    int first = job->first_block;
    job->solver->rows->run(job->solver->blocks, first + begin, first + end, job->bodies, job->prm, job->pass,
                           job->stream_rows);
}

/* One pass over all constraints: the colours' blocks in parallel one colour after
 * another, then the overflow serially in order. */
static void kg_constraint_pass_run(kg_world* world, kg_constraint_job* job, kg_constraint_pass pass)
{
    const struct kg_solver* s = world->solver;
    int grain = KG_CONSTRAINT_GRAIN / s->rows->width;
    job->pass = pass;
    for (int c = 0; c <= KG_COLOR_COUNT; ++c) {
        job->first_block = s->block_start[c];
        int blocks = s->block_start[c + 1] - s->block_start[c];
        if (c < KG_COLOR_COUNT) {
            kg_parallel_for(world->threads, blocks, grain, kg_pass_range, job);
        } else {
            kg_pass_range(job, 0, blocks);
        }
    }
}

/* An empty lane: no bodies (the still one), no points, zero masses and inputs. */
static void kg_empty_source(kg_u32 still, kg_row_head* head, kg_prepare_input* in)
{
    static const kg_prepare_input none; /* all zeros */
    kg_row_head h = {still, still, 0u, 0, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
    *head = h;
    *in = none;
}

/* Contact k's constraint head and prepare input (contact_solver.h), its bodies named as
 * the rows name them: the still body for the static world and for an empty lane. Not
 * inlined: in kg_prepare_chunks' loop it spilled registers (some 30 instructions a
 * contact more, measured with callgrind). */
KG_FN_NOINLINE void kg_prepare_source_of(const kg_constraint_job* job, int k, kg_row_head* head,
                                          kg_prepare_input* in)
{
    const kg_body_pool* p = job->pool;
    kg_u32 still = job->solver->still;
    if (!kg_prepare_source(&job->contacts[k], (kg_u32)k, job->bodies, p->inv_mass, p->inv_inertia, p->xf, p->center,
                           head, in)) {
        kg_empty_source(still, head, in);
        return;
    }
    head->a = head->a != KG_NULL_INDEX ? head->a : still;
    head->b = head->b != KG_NULL_INDEX ? head->b : still;
    if (head->restitution != 0.0f) {
        atomic_store_explicit(job->bounces, 1, memory_order_relaxed);
    }
}

/* Where chunk `chunk`'s constraints start in each colour (KG_COLOR_COUNT + 1 ints); at
 * chunk s->chunks, the colours' sizes. */
static const int* kg_chunk_start(const struct kg_solver* s, int chunk)
{
    return s->chunk_start + (size_t)chunk * (KG_COLOR_COUNT + 1);
}

typedef struct kg_count_job {
    struct kg_solver* solver;
    int count; /* contacts */
} kg_count_job;

/* The counts of chunks [begin, end)'s constraints per colour, chunk k's in row k + 1 of
 * chunk_start (kg_count_colors sums them into places). */
static void kg_count_chunk_colors(void* context, int begin, int end)
{
    const kg_count_job* job = context;
    struct kg_solver* s = job->solver;
    for (int chunk = begin; chunk < end; ++chunk) {
        int* counts = s->chunk_start + (size_t)(chunk + 1) * (KG_COLOR_COUNT + 1);
        memset(counts, 0, (KG_COLOR_COUNT + 1) * sizeof *counts);
        int last = (chunk + 1) * KG_CHUNK < job->count ? (chunk + 1) * KG_CHUNK : job->count;
        for (int k = chunk * KG_CHUNK; k < last; ++k) {
            counts[s->colors[k]] += 1;
        }
    }
}

/* The chunks' places in their colours and the colours' sizes (kg_chunk_start), counted
 * from the contacts' colours: each chunk's counts in parallel (serial, this loop was 2%
 * of large_pyramid's step on two threads, the other thread waiting), then summed. */
static void kg_count_colors(kg_world* world, struct kg_solver* s, int count)
{
    kg_count_job job = {s, count};
    s->chunks = (count + KG_CHUNK - 1) / KG_CHUNK;
    memset(s->chunk_start, 0, (KG_COLOR_COUNT + 1) * sizeof *s->chunk_start);
    kg_parallel_for(world->threads, s->chunks, 1, kg_count_chunk_colors, &job);
    for (int chunk = 1; chunk <= s->chunks; ++chunk) {
        const int* before = kg_chunk_start(s, chunk - 1);
        int* place = s->chunk_start + (size_t)chunk * (KG_COLOR_COUNT + 1);
        for (int c = 0; c <= KG_COLOR_COUNT; ++c) {
            place[c] += before[c];
        }
    }
}

/* Where a range of chunks writes a colour's constraints: the lane (block * width + lane)
 * of the next one, how far the next one's is (1, or a block for the overflow's), the
 * lane past the range's last one, and the first lane of the current block it holds. */
typedef struct kg_color_cursor {
    int lane, step, stop, first;
    int holds_end; /* the colour's last constraint: the range prepares the empty lanes after it */
} kg_color_cursor;

/* The lane of the at-th constraint of colour c. */
static int kg_lane_at(const struct kg_solver* s, int c, int at)
{
    int width = s->rows->width;
    return s->block_start[c] * width + (c == KG_COLOR_COUNT ? at * width : at);
}

/* Block `block` prepared once the lanes [first, end) that a range of chunks holds of it
 * are staged: at once where they are all of its lanes, else by whichever of the ranges
 * sharing it (where one's constraints of a colour end and the next's begin) stages its
 * last lanes; the count of lanes staged passes the others' writes on to it. */
static void kg_prepare_when_staged(const kg_constraint_job* job, int block, int first, int end)
{
    const struct kg_solver* s = job->solver;
    int width = s->rows->width, lanes = end - first;
    if (lanes < width && atomic_fetch_add_explicit(&s->filled[block], lanes, memory_order_acq_rel) + lanes < width) {
        return;
    }
    atomic_store_explicit(&s->filled[block], 0, memory_order_relaxed); /* for the next step */
    s->rows->prepare(s->blocks, block, job->prm);
}

/* A range's part of the block of `lane` (the lane it staged last) staged: the empty
 * lanes after a colour's last constraint staged too, and the block prepared when it can
 * be. Out of line, as it runs once a block: the contacts' loop keeps fewer values alive
 * across its calls. */
KG_FN_NOINLINE void kg_close_block(const kg_constraint_job* job, kg_color_cursor* at, int lane)
{
    const struct kg_solver* s = job->solver;
    int width = s->rows->width, block = lane / width;
    int full = (at->lane & (width - 1)) == 0;
    int staged = full || at->holds_end ? width : lane % width + 1;
    for (int empty = lane % width + 1; empty < staged; ++empty) {
        kg_empty_source(s->still, kg_staged_head(s->blocks, s->rows, block, empty),
                        kg_staged_input(s->blocks, s->rows, block, empty));
    }
    kg_prepare_when_staged(job, block, at->first, staged);
    at->first = 0;
}

/* The lines of a prepare input, asked for (to be written) the block's lane before it is
 * staged: that of the colour's next contact, some 25 contacts ahead as the colours take
 * turns (or an empty lane of the overflow's block). The rows are out of the cache by
 * then, and their writes, a stream per colour, are too many streams for the hardware to
 * foresee (many_pyramids: prepare's share of the step 15.4% to 12.5%, perf). */
static void kg_prefetch_input(const kg_prepare_input* input) { kg_prefetch_bytes(input, sizeof *input, 1); }

/* Chunks [begin, end): the contacts, read in their own order (a stream, where reading
 * them in colour order jumps through megabytes), stage their sources in their lanes, and
 * a block is prepared as soon as its lanes are staged, its sources still in the cache.
 * The range with a colour's last constraint stages the empty lanes after it. The width
 * is a power of two. */
static void kg_prepare_chunks(void* context, int begin, int end)
{
    const kg_constraint_job* job = context;
    const struct kg_solver* s = job->solver;
    const int *from = kg_chunk_start(s, begin), *to = kg_chunk_start(s, end), *sizes = kg_chunk_start(s, s->chunks);
    int width = s->rows->width, shift = kg_lowest_bit((unsigned)width);
    kg_color_cursor cursors[KG_COLOR_COUNT + 1];
    for (int c = 0; c <= KG_COLOR_COUNT; ++c) {
        kg_color_cursor* at = &cursors[c];
        at->lane = kg_lane_at(s, c, from[c]);
        at->step = c == KG_COLOR_COUNT ? width : 1;
        at->stop = kg_lane_at(s, c, to[c]);
        at->first = at->lane & (width - 1);
        at->holds_end = to[c] == sizes[c];
    }
    void* blocks = s->blocks;
    const kg_contact_rows* rows = s->rows;
    const int* colors = s->colors;
    int last = end * KG_CHUNK < job->count ? end * KG_CHUNK : job->count;
    for (int k = begin * KG_CHUNK; k < last; ++k) {
        kg_color_cursor* at = &cursors[colors[k]];
        if (k + KG_CONTACTS_AHEAD < last) { /* what prepare reads: the manifold, bodies and material */
            kg_prefetch_bytes(&job->contacts[k + KG_CONTACTS_AHEAD], offsetof(kg_contact, generation_a), 0);
        }
        int lane = at->lane, block = lane >> shift, in_block = lane & (width - 1);
        kg_prepare_input* input = kg_staged_input(blocks, rows, block, in_block);
        if (in_block + 1 < width) {
            kg_prefetch_input(input + 1);
        }
        kg_prepare_source_of(job, k, kg_staged_head(blocks, rows, block, in_block), input);
        at->lane = lane + at->step;
        if ((at->lane & (width - 1)) == 0 || at->lane == at->stop) {
            kg_close_block(job, at, lane);
        }
    }
}

/* Chunks [begin, end): the contacts, in their own order, take their impulses back for
 * warm starting the next step (and the API), read from their lanes, found with a running
 * count per colour as prepare found them: the writes a stream, the reads from a few
 * blocks at a time (one per colour). An empty lane (nothing solved) leaves its contact's
 * impulses as they were. */
static void kg_store_impulses_range(void* context, int begin, int end)
{
    const kg_constraint_job* job = context;
    const struct kg_solver* s = job->solver;
    const int* from = kg_chunk_start(s, begin);
    int width = s->rows->width, shift = kg_lowest_bit((unsigned)width); /* a power of two */
    int lanes[KG_COLOR_COUNT + 1], steps[KG_COLOR_COUNT + 1];
    for (int c = 0; c <= KG_COLOR_COUNT; ++c) {
        lanes[c] = kg_lane_at(s, c, from[c]);
        steps[c] = c == KG_COLOR_COUNT ? width : 1;
    }
    size_t point_at[2] = {offsetof(kg_contact_constraint, points[0]), offsetof(kg_contact_constraint, points[1])};
    int last = end * KG_CHUNK < job->count ? end * KG_CHUNK : job->count;
    for (int k = begin * KG_CHUNK; k < last; ++k) {
        int c = s->colors[k], block = lanes[c] >> shift, lane = lanes[c] & (width - 1);
        lanes[c] += steps[c];
        kg_i32 point_count;
        memcpy(&point_count, kg_lane_field(s->blocks, s->rows, block, lane, offsetof(kg_contact_constraint, point_count)),
               sizeof point_count);
        kg_manifold* m = &job->contacts[k].manifold;
        for (int j = 0; j < point_count; ++j) {
            float impulse[4]; /* normal, tangent, approach speed, the step's total normal */
            size_t fields[4] = {offsetof(kg_constraint_point, normal_impulse),
                                offsetof(kg_constraint_point, tangent_impulse),
                                offsetof(kg_constraint_point, relative_velocity),
                                offsetof(kg_constraint_point, total_normal_impulse)};
            for (int f = 0; f < 4; ++f) {
                memcpy(&impulse[f], kg_lane_field(s->blocks, s->rows, block, lane, point_at[j] + fields[f]),
                       sizeof impulse[f]);
            }
            kg_store_point(&m->points[j], impulse[0], impulse[1], impulse[2], impulse[3]);
        }
    }
}

/* The colours' block ranges, from the colouring; grows the blocks (with a warning) when
 * an unusual colouring needs more than were reserved. */
static kg_result kg_plan_blocks(struct kg_solver* s)
{
    const int* sizes = kg_chunk_start(s, s->chunks);
    int width = s->rows->width;
    s->block_start[0] = 0;
    for (int c = 0; c <= KG_COLOR_COUNT; ++c) {
        int n = sizes[c];
        s->block_start[c + 1] = s->block_start[c] + (c == KG_COLOR_COUNT ? n : (n + width - 1) / width);
    }
    int needed = s->block_start[KG_COLOR_COUNT + 1];
    if (needed <= s->block_capacity) {
        return KG_OK;
    }
    kg_warn_once("solver-blocks", "constraint blocks grown to %d (a large overflow colour)", 2 * needed);
    kg_result r = kg_reserve_blocks(s, 2 * needed);
    if (r != KG_OK) {
        memset(s->block_start, 0, sizeof s->block_start); /* nothing solved this step */
    }
    return r;
}

/* The contacts' colours: those the collide stage found they keep when all of them keep
 * one and no body's motion changed since (what colouring them would give, without reading
 * every contact again), else coloured. */
static void kg_color_step(kg_world* world, struct kg_solver* s, kg_contact* contacts, int count, int froze)
{
    int waiting = -1;
    const int* kept = kg_collision_kept_colors(world, &waiting);
    if (waiting == 0 && !froze) {
        memcpy(s->colors, kept, (size_t)count * sizeof *s->colors);
    } else {
        kg_graph_color_contacts(&s->coloring, contacts, count, &world->bodies, s->colors);
    }
}

kg_rest_params kg_rest_params_of(const kg_world_def* def, float dt)
{
    kg_rest_params rest = {dt, def->sleep_speed, def->enable_sleep};
    return rest;
}

kg_solver_params kg_solver_params_of(const kg_world_def* def, float h)
{
    kg_solver_params prm;
    prm.h = h;
    prm.inv_h = 1.0f / h;
    prm.max_push_out_speed = def->max_push_out_speed;
    prm.linear_slop = def->linear_slop;
    prm.restitution_threshold = def->restitution_threshold;
    /* Springs stiffer than a quarter of the sub-step rate go unstable (measured: stacks
     * explode at half of it), and that holds for the stiffer static contacts too. */
    float max_hertz = 0.25f * prm.inv_h;
    float hertz = fminf(def->contact_hertz, max_hertz);
    prm.contact_softness = kg_make_softness(hertz, def->contact_damping_ratio, h);
    prm.static_softness = kg_make_softness(fminf(2.0f * hertz, max_hertz), def->contact_damping_ratio, h);
    return prm;
}

void kg_stage_solve(kg_world* world, float dt)
{
    struct kg_solver* s = world->solver;
    int count = 0;
    kg_contact* contacts = kg_collision_contacts(world, &count);
    if (count > s->capacity && kg_solver_reserve(s, world->def.max_bodies, world->def.max_contacts) != KG_OK) {
        kg_warn_once("solver-grow", "out of memory for contact constraints: contacts ignored this step");
        count = 0;
    }
    int n = world->def.substeps;
    float h = dt / (float)n;
    kg_body_pool* p = &world->bodies;
    kg_body_job bjob = {s->rows, p, s->bodies, s->velocity_steps, {world->def.gravity, h, world->def.max_linear_speed},
                        kg_rest_params_of(&world->def, dt), 0};
    atomic_int bounces = 0;
    kg_constraint_job cjob = {p, s->bodies, contacts, count, s, 0, &bounces, kg_solver_params_of(&world->def, h),
                              KG_PASS_SOLVE, 0};

    kg_parallel_for(world->threads, p->high_water, KG_BODY_GRAIN, kg_load_bodies, &bjob);
    kg_color_step(world, s, contacts, count, atomic_load(&bjob.froze));
    kg_count_colors(world, s, count);
    if (kg_plan_blocks(s) != KG_OK) {
        kg_warn_once("solver-grow", "out of memory for contact constraints: contacts ignored this step");
    }
    int blocks = s->block_start[KG_COLOR_COUNT + 1];
    cjob.stream_rows = (size_t)blocks * s->rows->block_size > KG_CACHED_ROW_BYTES;
    if (blocks > 0) { /* else there are no contacts, or no rows to put them in */
        kg_parallel_for(world->threads, s->chunks, 1, kg_prepare_chunks, &cjob);
    }
    /* Joints (core/joint.h): prepared once, then each pass colour by colour before the
     * contacts' colours, as Box2D's overflow constraints go first. */
    kg_joints_prepare(world, s->bodies, cjob.prm, s->rows, s->still);
    for (int step = 0; step < n; ++step) {
        kg_parallel_for(world->threads, p->high_water, KG_BODY_GRAIN, kg_integrate_velocities, &bjob);
        kg_joints_pass(world, s->bodies, cjob.prm, KG_PASS_WARM_START);
        kg_constraint_pass_run(world, &cjob, KG_PASS_WARM_START);
        kg_joints_pass(world, s->bodies, cjob.prm, KG_PASS_SOLVE);
        kg_constraint_pass_run(world, &cjob, KG_PASS_SOLVE);
        kg_parallel_for(world->threads, p->high_water, KG_BODY_GRAIN, kg_integrate_positions, &bjob);
        kg_joints_pass(world, s->bodies, cjob.prm, KG_PASS_RELAX);
        kg_constraint_pass_run(world, &cjob, KG_PASS_RELAX);
    }
    kg_joints_finish(world);
    if (atomic_load(&bounces)) { /* else the pass, a loop per colour, would change nothing */
        kg_constraint_pass_run(world, &cjob, KG_PASS_RESTITUTION);
    }
    if (blocks > 0) {
        kg_parallel_for(world->threads, s->chunks, 1, kg_store_impulses_range, &cjob);
    }
    kg_parallel_for(world->threads, p->high_water, KG_BODY_GRAIN, kg_store_bodies, &bjob);
}

/* ---- finalize, with continuous collision ------------------------------------------ */

typedef struct kg_finalize_job {
    kg_body_pool* pool;
    struct kg_solver* solver;
    float dt;
    int continuous;             /* world->def.enable_continuous */
    int pass;                   /* KG_CONTINUOUS_PASS_*: bullets are finalized in the second */
    kg_continuous_bodies bodies;
    kg_tile_terrain terrain;
    kg_toi_params toi;
    kg_u32 shapes_version; /* the shape pool's (the extents cache's key) */
} kg_finalize_job;

/* Slot i's extents, from the cache (kg_cached_extents). */
static kg_extents kg_extents_of(kg_cached_extents* cache, const kg_continuous_bodies* b, kg_u32 generation,
                                kg_u32 shapes_version, int i)
{
    kg_cached_extents e = cache[i];
    if (e.generation != generation || e.shapes_version != shapes_version) {
        e.extents = kg_body_extents(&b->shapes, (kg_u32)i, b->local_center[i]);
        e.generation = generation;
        e.shapes_version = shapes_version;
        cache[i] = e;
    }
    return e.extents;
}

/* Bodies a block of the finalize loop tells fast, then sweeps: a third of a rain's drops
 * are fast in no order, and a branch per body on it was mispredicted. */
#define KG_SWEEP_BLOCK 64

/* The continuous collision of the pass's bodies in [begin, end) (at most KG_SWEEP_BLOCK):
 * they read only what this pass does not write (static bodies, tiles, and in the
 * bullets' pass the others, whose pass is done), and write only their own pose. */
static void kg_continuous_block(const kg_finalize_job* job, int begin, int end)
{
    kg_body_pool* p = job->pool;
    kg_cached_extents* cache = job->solver->extents;
    kg_u32 fast[KG_SWEEP_BLOCK];
    float reach[KG_SWEEP_BLOCK];
    int n = 0;
    for (int i = begin; i < end; ++i) {
        if (!kg_continuous_takes(p->flags[i], job->pass)) {
            continue; /* a dead slot's shape is no body's: its extents are not kept */
        }
        kg_extents e = kg_extents_of(cache, &job->bodies, p->generation[i], job->shapes_version, i);
        fast[n] = (kg_u32)i;
        reach[n] = e.max;
        n += kg_moves_fast(p->velocity[i], p->omega[i], job->dt, e);
    }
    for (int k = 0; k < n; ++k) {
        kg_sweep_fast_body(&job->bodies, &job->terrain, fast[k], job->pass, job->toi, reach[k]);
    }
}

/* The pass's bodies in [begin, end) finalized. */
static void kg_finalize_block(const kg_finalize_job* job, int begin, int end)
{
    kg_body_pool* p = job->pool;
    for (int i = begin; i < end; ++i) {
        if (kg_finalized_in_pass(p->flags[i], job->continuous, job->pass) &&
            kg_finalize_body((kg_u32)i, job->dt, p->flags, p->center, p->rot, p->velocity, p->omega, p->force,
                             p->torque, p->drag, p->xf, p->aabb, p->shape, p->local_center)) {
            kg_warn_frozen(i);
        }
    }
}

static void kg_finalize_range(void* context, int begin, int end)
{
    const kg_finalize_job* job = context;
    for (int block = begin; block < end; block += KG_SWEEP_BLOCK) {
        int block_end = end - block < KG_SWEEP_BLOCK ? end : block + KG_SWEEP_BLOCK;
        if (job->continuous) {
            kg_continuous_block(job, block, block_end);
        }
        kg_finalize_block(job, block, block_end);
    }
}

/* Entries of the small static bodies in order of lower x (then slot: each order is one). */
static int kg_compare_entries(const void* pa, const void* pb)
{
    const kg_static_entry* a = pa;
    const kg_static_entry* b = pb;
    if (a->lower_x != b->lower_x) {
        return a->lower_x < b->lower_x ? -1 : 1;
    }
    return a->slot < b->slot ? -1 : (a->slot > b->slot ? 1 : 0);
}

/* Wider than this many times the static bodies' mean width, a static body is large: a
 * ground under a thousand boxes would make every reach (kg_static_entry) reach as far as
 * it, and every search walk back to it. */
#define KG_LARGE_STATIC_WIDTHS 8.0f

/* The index of the static bodies (collide/continuous.h, kg_static_entry) and the live
 * bullets' count, made again when a static body or a bullet changed (world->static_edits)
 * since they were. */
static void kg_list_statics(kg_world* world, struct kg_solver* s)
{
    if (s->statics_listed && s->statics.edits == world->static_edits) {
        return;
    }
    const kg_body_pool* p = &world->bodies;
    kg_static_entry* e = s->statics.entries;
    int n = 0, bullets = 0;
    float widths = 0.0f;
    for (int i = 0; i < p->high_water; ++i) {
        kg_u32 f = p->flags[i];
        if (kg_flags_alive(f) && kg_flags_type(f) == (kg_u32)KG_BODY_STATIC) {
            kg_static_entry entry = {(kg_u32)i, p->aabb[i].lower.x, p->aabb[i].upper.x, 0u};
            e[n++] = entry;
            widths += p->aabb[i].upper.x - p->aabb[i].lower.x;
        }
        bullets += kg_flags_alive(f) && kg_is_bullet(f);
    }
    float large = n > 0 ? KG_LARGE_STATIC_WIDTHS * widths / (float)n : 0.0f;
    int large_count = 0;
    for (int k = 0; k < n; ++k) { /* the large ones to the front, in slot order */
        if (e[k].reach - e[k].lower_x > large) {
            kg_static_entry t = e[k];
            memmove(e + large_count + 1, e + large_count, (size_t)(k - large_count) * sizeof *e);
            e[large_count++] = t;
        }
    }
    qsort(e + large_count, (size_t)(n - large_count), sizeof *e, kg_compare_entries);
    for (int k = large_count + 1; k < n; ++k) {
        e[k].reach = kg_maxf(e[k].reach, e[k - 1].reach);
    }
    s->statics.count = n;
    s->statics.large_count = large_count;
    s->statics.bullets = bullets;
    s->statics.edits = world->static_edits;
    s->statics_listed = 1;
}

static kg_tile_terrain kg_terrain_of(const kg_world* world)
{
    kg_tile_terrain t = {0, 0, 0, 0, world->def.speculative_distance, world->def.linear_slop};
    if (kg_tilemaps_live_count(world) > 0) {
        kg_tilemap_arrays a;
        kg_tilemaps_arrays(world, &a);
        t.maps = a.maps;
        t.cells = a.cells;
        t.protos = a.protos;
        t.map_count = a.map_count;
    }
    return t;
}

/* What the time of impact searches aim at: the linear slop, as Box2D v3. */
kg_toi_params kg_toi_params_of(const kg_world_def* def)
{
    kg_toi_params prm = {def->linear_slop, 0.25f * def->linear_slop};
    return prm;
}

kg_static_list kg_continuous_statics(kg_world* world)
{
    kg_list_statics(world, world->solver);
    return world->solver->statics;
}

void kg_stage_finalize(kg_world* world)
{
    kg_body_pool* p = &world->bodies;
    struct kg_solver* s = world->solver;
    kg_finalize_job job;
    memset(&job, 0, sizeof job);
    job.pool = p;
    job.solver = s;
    job.dt = world->last_dt;
    job.continuous = world->def.enable_continuous;
    if (job.continuous) {
        kg_list_statics(world, s);
        kg_continuous_bodies b = {p->flags,         p->velocity,       p->omega,
                                  p->center,        p->rot,            p->xf,
                                  p->aabb,          p->local_center,   s->statics.entries,
                                  s->statics.count, s->statics.large_count, p->high_water,
                                  kg_world_shape_arrays(world), NULL, NULL, NULL};
        const kg_shape_index* index = kg_collision_shape_index(world);
        if (kg_shape_index_current(index, world)) { /* a chain: its segments near a sweep by a search */
            kg_shape_index_arrays(index, &b.sorted_of, &b.sorted_spans, &b.sorted_shapes);
        }
        job.bodies = b;
        job.shapes_version = world->shapes.version;
        job.terrain = kg_terrain_of(world);
        job.toi = kg_toi_params_of(&world->def);
    }
    job.pass = KG_CONTINUOUS_PASS_BODIES;
    kg_parallel_for(world->threads, p->high_water, KG_BODY_GRAIN, kg_finalize_range, &job);
    if (job.continuous && s->statics.bullets > 0) { /* against the others' poses at the end of the step, finalized above */
        job.pass = KG_CONTINUOUS_PASS_BULLETS;
        kg_parallel_for(world->threads, p->high_water, KG_BODY_GRAIN, kg_finalize_range, &job);
    }
}
