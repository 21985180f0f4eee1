/* The OpenCL backend's state, one struct a world (kg_cl_backend): its queue, kernels and
 * buffers (all sized once, when the backend starts, from the world's capacities), where
 * the newest copy of each body array is, and the host's side of the step (scratch, what
 * was read back, where the step's collide ran).
 *
 * Residency: each body pool array has a bit in host_stale (the device has newer data:
 * read it back before the host reads) and in device_stale (the host has newer data:
 * upload it before a kernel reads). Reads and uploads cover slots [0, high_water) only.
 *
 * Every OpenCL call goes through the wrappers below, which check its result, set the
 * error (KG_ERROR_BACKEND, naming the call and the CL error) and count injected faults
 * (cl_fault.h); the step stops at the first failure and the backend falls back. */
#ifndef KG_CL_WORLD_H
#define KG_CL_WORLD_H

#include "backend/opencl/cl_fault.h"
#include "backend/opencl/cl_runtime.h"
#include "backend/opencl/kernels/kg_collide_shared.h"
#include "core/error.h"
#include "core/world.h"
#include "kgyro/opencl.h"
#include "solve/force_body.h"
#include "solve/graph_color.h"
#include "solve/joint_row.h"

/* name, pool member, 1 if a step changes it (then it is checkpointed and read back) */
#define KG_CL_BODY_ARRAYS(X)                                                   \
    X(CENTER, center, 1) X(ROT, rot, 1) X(VELOCITY, velocity, 1)               \
    X(OMEGA, omega, 1) X(FORCE, force, 1) X(TORQUE, torque, 1) X(DRAG, drag, 1)                 \
    X(SLEEP_TIME, sleep_time, 1) X(ISLAND, island, 1) X(XF, xf, 1)              \
    X(AABB, aabb, 1) X(FLAGS, flags, 1) X(SHAPE, shape, 0)                      \
    X(LOCAL_CENTER, local_center, 0) X(MASS, mass, 0) X(INERTIA, inertia, 0)    \
    X(INV_MASS, inv_mass, 0) X(INV_INERTIA, inv_inertia, 0)                     \
    X(LINEAR_DAMPING, linear_damping, 0) X(ANGULAR_DAMPING, angular_damping, 0) \
    X(FRICTION, friction, 0) X(RESTITUTION, restitution, 0)                     \
    X(CATEGORY, category, 0) X(MASK, mask, 0) X(GENERATION, generation, 0)     \
    X(FIRST_SHAPE, first_shape, 0) X(SHAPE_COUNT, shape_count, 0)

typedef enum kg_cl_array {
#define KG_CL_ARRAY_ENUM(id, member, state) KG_CL_##id,
    KG_CL_BODY_ARRAYS(KG_CL_ARRAY_ENUM)
#undef KG_CL_ARRAY_ENUM
    KG_CL_ARRAY_COUNT
} kg_cl_array;

#define KG_CL_BIT(id) (1u << KG_CL_##id)
#define KG_CL_ALL_ARRAYS ((1u << KG_CL_ARRAY_COUNT) - 1u)

/* The step program's kernels: id, name, and the number of arguments of its .cl parameter
 * list. A launch (KG_LAUNCH) that passes another number does not compile; a table whose
 * count differs from the built kernel's (CL_KERNEL_NUM_ARGS) stops the backend's start,
 * naming the kernel. */
#define KG_CL_KERNELS(X)                                                                                      \
    X(APPLY_BUILTIN_FORCE, kg_apply_builtin_force, 8)                                                         \
    X(INTEGRATE_VELOCITIES, kg_integrate_velocities, 4)                                                       \
    X(INTEGRATE_POSITIONS, kg_integrate_positions, 4) X(LOAD_BODIES, kg_load_bodies, 18)                      \
    X(STORE_BODIES, kg_store_bodies, 11) X(PREPARE_CONTACTS, kg_prepare_contacts, 9)                          \
    X(GATHER_COLORED, kg_gather_colored, 4) X(SOLVE_COLOR, kg_solve_color, 7)                                 \
    X(SOLVE_COLORS_IN_GROUP, kg_solve_colors_in_group, 5) X(STORE_IMPULSES, kg_store_impulses, 3)             \
    X(FINALIZE, kg_finalize, 32) X(SCAN_BLOCKS, kg_scan_blocks, 4) X(SCAN_APPLY, kg_scan_apply, 7)            \
    X(SORT_COUNT, kg_sort_count, 6) X(SORT_SCATTER, kg_sort_scatter, 9) X(BP_CLEAR, kg_bp_clear, 3)           \
    X(BP_PROXIES, kg_bp_proxies, 11) X(BP_CELLS, kg_bp_cells, 2) X(BP_BOUNDS, kg_bp_bounds, 4)                \
    X(BP_BUILD_GRID, kg_bp_build_grid, 2) X(BP_KEYS, kg_bp_keys, 7) X(BP_GATHER, kg_bp_gather, 7)             \
    X(BP_COUNT_PAIRS, kg_bp_count_pairs, 8) X(BP_WRITE_PAIRS, kg_bp_write_pairs, 10)                          \
    X(BP_COUNT_RUNS, kg_bp_count_runs, 3) X(BP_SCATTER, kg_bp_scatter, 5)                                     \
    X(BP_SORT_RUNS, kg_bp_sort_runs, 3) X(NARROWPHASE, kg_narrowphase, 14)                                    \
    X(BUILD_CONTACTS, kg_build_contacts, 12) X(COLOR_CONTACTS, kg_color_contacts, 7)                          \
    X(RESET_COLORS, kg_reset_colors, 8) X(KEEP_COLORS, kg_keep_colors, 5)                                     \
    X(BID_COLORS, kg_bid_colors, 6) X(TAKE_COLORS, kg_take_colors, 10)                                        \
    X(COLOR_RANGES, kg_color_ranges, 3) X(TILE_COLLIDE_BODIES, kg_tile_collide_bodies, 32)                    \
    X(TILE_TOTAL, kg_tile_total, 2) X(WAKE_TOUCHED, kg_wake_touched, 8)                                       \
    X(WAKE_MARKED, kg_wake_marked, 5) X(FIND_ISLANDS, kg_find_islands, 9)                                     \
    X(RESET_ISLANDS, kg_reset_islands, 4) X(HOOK_ROUND, kg_hook_round, 6)                                     \
    X(SHORTEN_ISLANDS, kg_shorten_islands, 2) X(ISLAND_LEAST, kg_island_least, 5)                             \
    X(ISLAND_STIRS, kg_island_stirs, 7) X(FALL_ASLEEP, kg_fall_asleep, 14)                                    \
    X(COUNT_SHAPE_PAIRS, kg_count_shape_pairs, 16) X(WRITE_SHAPE_PAIRS, kg_write_shape_pairs, 18)             \
    X(NARROWPHASE_SHAPES, kg_narrowphase_shapes, 20) X(BUILD_SHAPE_CONTACTS, kg_build_shape_contacts, 11)     \
    X(PREPARE_JOINTS, kg_prepare_joints, 9) X(SOLVE_JOINT_COLOR, kg_solve_joint_color, 9)                     \
    X(SOLVE_JOINT_COLORS_IN_GROUP, kg_solve_joint_colors_in_group, 7)                                         \
    X(DROP_JOINED_PAIRS, kg_drop_joined_pairs, 5) X(DROP_JOINED_SHAPE_PAIRS, kg_drop_joined_shape_pairs, 5)   \
    X(WAKE_JOINED, kg_wake_joined, 7) X(FIND_JOINED_ISLANDS, kg_find_joined_islands, 11)                      \
    X(HOOK_JOINT_ROUND, kg_hook_joint_round, 6) X(JOINT_STIRS, kg_joint_stirs, 7)

typedef enum kg_cl_kernel_id {
#define KG_CL_KERNEL_ENUM(id, name, args) KG_CL_K_##id,
    KG_CL_KERNELS(KG_CL_KERNEL_ENUM)
#undef KG_CL_KERNEL_ENUM
    KG_CL_KERNEL_COUNT
} kg_cl_kernel_id;

/* KG_CL_ARGS_<id>: the argument count of kernel id, for KG_LAUNCH's compile-time check. */
enum {
#define KG_CL_KERNEL_ARGS(id, name, args) KG_CL_ARGS_##id = (args),
    KG_CL_KERNELS(KG_CL_KERNEL_ARGS)
#undef KG_CL_KERNEL_ARGS
};

/* A device force applicator's kernel (kg_device_force of kernels/kg_force.cl, built per
 * force by cl_runtime.c): its arguments are the same whatever the user's function. */
#define KG_CL_DEVICE_FORCE_KERNEL "kg_device_force"
#define KG_CL_DEVICE_FORCE_ARGS 13

#define KG_CL_MAX_TIMED (KG_MAX_STAGE_TIMES - 8) /* leaves room for the host stages */

/* Device time per kernel name over one step, from profiling events. */
typedef struct kg_cl_timing {
    int count;
    const char* names[KG_CL_MAX_TIMED];
    cl_ulong ns[KG_CL_MAX_TIMED];
} kg_cl_timing;

/* The collision stage's buffers (kernels/kg_broadphase.cl, kg_collide.cl, kg_color.cl): per body slot, sized once with
 * the other body buffers... */
typedef struct kg_cl_collide_buffers {
    cl_mem counts;         /* KG_CC_WORDS counters: what the host reads back of the stage */
    cl_mem proxies;        /* kg_bp_proxy per slot */
    cl_mem sorted;         /* the small proxies in key order */
    cl_mem keys, items;    /* per slot: cell keys (KG_BP_NOT_KEYED last) and slots, sorted */
    cl_mem large_keys, large_items; /* per slot: lower x of the large boxes, and slots, sorted */
    cl_mem key_scratch, item_scratch; /* the sorts' other halves */
    cl_mem found;          /* per search element (2 per slot): pairs, then their prefix sum */
    cl_mem histogram;      /* box extents, KG_BP_EXTENT_BINS */
    cl_mem grid;           /* kg_bp_grid */
    cl_mem bp_words;       /* KG_BP_WORDS: the grid's bounds, the small and large counts */
    cl_mem run;            /* pairs per lower slot, then their prefix sum (slots + 1) */
    cl_mem run_fill;
    cl_mem colors_used;    /* per slot, the colours its contacts took so far */
    cl_mem color_bids[2];  /* per slot, the least priority bid in a colouring round, this
                            * round's and the next's */
    cl_mem block_sums;     /* KG_SCAN_MAX_BLOCKS */
    cl_mem sort_counts;    /* a sort pass's digit counts per chunk, KG_SORT_COUNT_WORDS */
    cl_mem tile_run;       /* tile contacts per slot, then their prefix sum (slots + 1) */
    cl_mem statics;        /* continuous collision's index of the static bodies (kg_static_entry), */
    kg_u32 statics_edits;  /* as listed at world->static_edits then (statics_sent: ever) */
    int statics_sent;
    cl_mem last_origin[2]; /* one-way platforms: each slot's origin and generation at the */
    cl_mem last_generation[2]; /* last collision (collide/tilemap.c keeps the same on the
                            * host), [tile_state] the current, the other written by a step */
    int tile_state;
    /* the tile maps (collide/tilemap.h's layout), built when the maps are created or
     * destroyed, a map's cells written again when kg_tilemap_set_tile changed them */
    cl_mem tile_maps;      /* kg_tile_map_info per live map, in key order */
    cl_mem tile_cells;     /* every live map's cells, one after the other */
    cl_mem tile_protos;    /* every live map's kg_tile_proto per tile id */
    int tile_map_count;
    int tiles_built;       /* the buffers above match layout tile_layout */
    unsigned tile_layout;
    /* ...and per contact, sized with the contact pool */
    cl_mem raw_pairs;      /* pairs as found */
    cl_mem pairs;          /* pairs sorted by (a, b) */
    cl_mem manifolds;      /* one per pair */
    cl_mem bases;          /* one per pair: the manifold as computed (collide/recycle.h) */
    cl_mem touching;       /* per pair, then its prefix sum: the contact index (pairs + 1) */
    cl_mem shape_run;      /* per pair, then its prefix sum: its pairs of shapes (pairs + 1) */
    cl_mem shape_items;    /* the pairs of shapes (kg_shape_pair), while a body has several */
    cl_mem item_pairs;     /* each one's two bodies (uint2), what the wake stage reads */
    cl_mem colors;         /* colour per contact */
    cl_mem color_items;    /* per contact, its index: what the sort by colour carries */
    cl_mem sorted_colors;  /* the colours sorted */
} kg_cl_collide_buffers;

typedef struct kg_cl_backend {
    /* ---- the device (kg_cl_open_device) ---- */
    const kg_cl_api* cl;                  /* NULL while the device is closed */
    kg_cl_runtime* rt;
    kg_cl_faults faults;
    cl_command_queue queue;
    cl_kernel kernels[KG_CL_KERNEL_COUNT];
    size_t group_size[KG_CL_KERNEL_COUNT];
    cl_mem arrays[KG_CL_ARRAY_COUNT];
    cl_mem checkpoint[KG_CL_ARRAY_COUNT]; /* state arrays at the start of the step */
    cl_mem solver_bodies;                 /* kg_solver_body per slot: the solver's state */
    cl_mem velocity_steps;                /* kg_velocity_step per slot, made by kg_load_bodies */
    cl_mem solver_params;                 /* kg_solver_params of the step */
    cl_mem contacts[2];                   /* this step's and last step's, swapped each step */
    int current;                          /* contacts[current]: the last step's */
    cl_mem constraints, colored, order;   /* contact_capacity each */
    cl_mem color_start;                   /* kg_graph_coloring.color_start of the step */
    int contact_capacity;
    kg_cl_collide_buffers collide;
    /* the shape pool (core/shape_pool.h) while a body has several shapes: uploaded whole
     * when the host's changed, grown with it; one element each before */
    cl_mem shape_next, shape_flags, shape_geometry, shape_category, shape_mask, shape_friction, shape_restitution;
    int shape_capacity;   /* slots the shape buffers hold */
    int shape_geometry_held; /* whether shape_geometry holds them too (it waits for the first compound body) */
    unsigned shape_version; /* of the host's pool they hold */
    cl_mem step_pair_list; /* this step's items' bodies (uint2 each), step_pairs of them: the
                            * pairs, or the pairs of shapes' bodies */
    int color_serial_max;                 /* contacts coloured by one work-item at most */
    int island_group_max;                 /* bodies whose islands one work-group finds at most */
    int joint_group_max;                  /* joints whose passes one work-group solves at most */
    int joint_color_items;                /* work-items of a launch per joint colour at most */
    cl_mem targets;                       /* applicator targets (solve/force_body.h), max_bodies */
    /* sleeping (kernels/kg_sleep.cl), per body slot */
    cl_mem wake_marks;                    /* per island name: to be woken this step */
    cl_mem island_parent;                 /* union-find of this step's islands */
    cl_mem island_least;                  /* per island root: the shortest rest time of its bodies */
    unsigned host_stale;
    unsigned device_stale;
    int forces_cleared; /* the last step cleared force and torque of every live body */
    int profiling;
    cl_event* events;          /* profiled commands of this step, KG_CL_MAX_EVENTS */
    const char** event_names;
    int event_count;
    kg_cl_timing timing;
    kg_transfer_stats transfers;
    /* ---- the step on the host's side ---- */
    /* host scratch, grown (never in a steady state) when a step needs more */
    kg_force_target* host_targets;   /* the lists of this step's applicators */
    int target_capacity;
    int* color_scratch;
    int color_capacity;
    kg_graph_coloring coloring;
    kg_solver_params step_params;    /* the step's, read by a non-blocking write */
    cl_kernel* force_kernels;        /* per applicator slot, for device forces */
    size_t* force_group_sizes;
    int steps_since_snapshot;        /* steps since the host last had the whole state */
    int frozen_count;                /* frozen bodies the host knows of, to warn of new ones */
    int checkpoint_valid;            /* this step's start state is saved on the device */
    int in_step;                     /* a step is running (force callbacks run inside it) */
    int fallback_pending;            /* a failure inside the step: it unwinds, then falls back */
    char fallback_reason[512];       /* that failure's message */
    kg_vec2* start_force;            /* the forces the step began with, when the host set them */
    float* start_torque;
    int start_forces_saved;          /* else the step began with every force zero */
    /* contacts: the last step's are in contacts[current]; the host's list (collide.h)
     * is filled from there only when asked for (contacts_stale) */
    int body_contact_count;          /* the first ones, body pairs; tile contacts follow */
    int tile_state_on_device;        /* the one-way platform state is newer on the device */
    int tiles_ran;                   /* this step collided the tile maps on the device */
    int contacts_stale;
    int previous_contacts_stale;     /* the same for the host's list of the step before */
    cl_uint counters[KG_CC_WORDS];   /* the device collide stage's counters, read back */
    /* this step's collide stage: where it ran, the pairs it found on the device, the
     * contacts it made (the first step_body_count between bodies, tile contacts after) */
    int step_on_device;
    int step_pairs;
    int step_count;
    int step_body_count;
    /* joints (cl_joint.c): the rows during a step, the islands' links and the pairs kept
     * apart as of joint_version */
    cl_mem joint_rows, joint_links, joint_apart, joint_order;
    cl_mem joint_color_start; /* the order's colour ranges, as joint_colors */
    int joint_row_capacity, joint_link_capacity, joint_apart_capacity, joint_order_capacity;
    int joint_slots;      /* rows solved this step (0: none) */
    int joint_link_count, joint_apart_count;
    int joint_colors[KG_JOINT_COLORS + 2]; /* kg_joints_order's colour ranges */
    kg_u32 joint_version;
    int joint_lists_sent;
} kg_cl_backend;

#define KG_CL_MAX_EVENTS 4096

void kg_cl_release(kg_cl_backend* b, cl_mem* buffer);

/* Opens b's device side: the queue, kernels and buffers for world on rt. On failure what
 * was made is released (kg_cl_close_device). */
kg_result kg_cl_open_device(kg_world* world, kg_cl_backend* b, kg_cl_runtime* rt, const kg_cl_faults* faults);
/* Lets the commands still queued end before anything they use is released: after a
 * failure, non-blocking writes still read host memory about to be freed. On a lost device
 * it returns at once, with an error there is nothing more to do about. */
void kg_cl_drain(kg_cl_backend* b);
/* Releases what kg_cl_open_device made, once (b itself stays, with its host side). */
void kg_cl_close_device(kg_cl_backend* b);

/* The work-group size to launch kernel with: what the device allows for that kernel and
 * prefers as a multiple, aiming at KG_CL_GROUP_TARGET. */
size_t kg_cl_pick_group_size(kg_cl_backend* b, cl_kernel kernel);

/* Joints (cl_joint.c). */
kg_result kg_cl_drop_joined(kg_world* world, kg_cl_backend* b, cl_mem pairs, int count, int shape_pairs,
                            cl_mem touching);
kg_result kg_cl_wake_joined(kg_world* world, kg_cl_backend* b);
int kg_cl_joint_links(kg_world* world, kg_cl_backend* b); /* their count, written to the device */
kg_result kg_cl_prepare_joints(kg_world* world, kg_cl_backend* b);
kg_result kg_cl_solve_joints(kg_world* world, kg_cl_backend* b, int pass);
kg_result kg_cl_joints_to_host(kg_world* world, kg_cl_backend* b);
void kg_cl_release_joints(kg_cl_backend* b);

/* A buffer of size bytes (KGYRO_CL_FAIL=alloc counts here). */
kg_result kg_cl_buffer(kg_cl_backend* b, size_t size, cl_mem* out);
/* The shape pool on the device as the host's is (at least its capacity, its contents
 * when a body has several shapes). */
kg_result kg_cl_sync_shapes(kg_cl_backend* b, const kg_world* world);
/* Grows the contact buffers to hold capacity contacts (only when a step finds more than
 * ever before: the collide stage grows its pool then too). */
kg_result kg_cl_reserve_contacts(kg_cl_backend* b, int capacity);

/* Writes data into buffer. A non-blocking write reads data later: it must stay unchanged
 * until the next kg_cl_finish. */
kg_result kg_cl_write(kg_cl_backend* b, cl_mem buffer, size_t offset, size_t size, const void* data, int blocking);
kg_result kg_cl_read(kg_cl_backend* b, cl_mem buffer, size_t offset, size_t size, void* data);

/* Rounds over the whole device (the colouring's, the islands') run this many at a time
 * between two looks at what the last one left to do: each look waits for the queue, and
 * most worlds need 5 to 20 rounds (tests/test_coloring.c). */
#define KG_CL_ROUNDS_PER_LOOK 4
/* A round counts what it leaves to do in collide.counts[first + round % 2] (and clears
 * the other word for the next round): what the last of rounds [0, round) left, read
 * back. */
kg_result kg_cl_rounds_left(kg_cl_backend* b, int first, int round, cl_uint* left);
kg_result kg_cl_copy(kg_cl_backend* b, cl_mem from, cl_mem to, size_t size);

/* Body array name of the kg_cl_backend b in scope. */
#define KG_A(name) b->arrays[KG_CL_##name]

/* A kernel argument: its size and where its value is. */
typedef struct kg_cl_kernel_arg {
    size_t size;
    const void* value;
} kg_cl_kernel_arg;

#define KG_MEM(buffer) {sizeof(cl_mem), &(buffer)}
#define KG_INT(v) {sizeof(cl_int), &(cl_int){(v)}}
#define KG_UINT(v) {sizeof(cl_uint), &(cl_uint){(v)}}
#define KG_FLOAT(v) {sizeof(cl_float), &(cl_float){(v)}}
/* a struct passed by value (a shared header's, laid out alike on both sides) */
#define KG_VALUE(lvalue) {sizeof(lvalue), &(lvalue)}

/* The shape arrays, in kg_shape_arrays' order (collide/pair_contact.h), as the kernels
 * that read a body's shapes take them. */
#define KG_SHAPE_ARGS(b)                                                                                        \
    KG_MEM(KG_A(SHAPE_COUNT)), KG_MEM(KG_A(FIRST_SHAPE)), KG_MEM(KG_A(SHAPE)), KG_MEM((b)->shape_geometry),      \
        KG_MEM((b)->shape_next), KG_MEM((b)->shape_flags), KG_MEM((b)->shape_category), KG_MEM((b)->shape_mask)

/* The launch convention, the only one: every argument of the kernel set in order at the
 * call site, then the kernel launched over items work-items (rounded up to its work-group
 * size; the kernels return early past their count), labelled label in the profile. No
 * argument outlives its launch: nothing is bound once and relied on later. Nothing is
 * done when items is 0. */
kg_result kg_cl_launch_kernel(kg_cl_backend* b, cl_kernel kernel, size_t group_size, int items, const char* label,
                              const kg_cl_kernel_arg* args, int count);
/* The same for kernel id of the step program; label NULL labels it with its name. */
kg_result kg_cl_launch_args(kg_cl_backend* b, kg_cl_kernel_id id, int items, const char* label,
                            const kg_cl_kernel_arg* args, int count);

/* Launches kernel id of KG_CL_KERNELS with the arguments that follow, all of them, in
 * order; their count must be the table's, else it does not compile. */
#define KG_LAUNCH(b, id, items, label, ...)                                                                      \
    do {                                                                                                         \
        const kg_cl_kernel_arg args_[] = {__VA_ARGS__};                                                          \
        _Static_assert(sizeof args_ / sizeof args_[0] == KG_CL_ARGS_##id,                                        \
                       "KG_LAUNCH(" #id "): not as many arguments as KG_CL_KERNELS gives the kernel");           \
        KG_TRY(kg_cl_launch_args(b, KG_CL_K_##id, items, label, args_, (int)(sizeof args_ / sizeof args_[0]))); \
    } while (0)

/* Launches a device force applicator's kernel, every argument in order, as KG_LAUNCH. */
#define KG_LAUNCH_DEVICE_FORCE(b, kernel, group_size, items, label, ...)                                         \
    do {                                                                                                         \
        const kg_cl_kernel_arg args_[] = {__VA_ARGS__};                                                          \
        _Static_assert(sizeof args_ / sizeof args_[0] == KG_CL_DEVICE_FORCE_ARGS,                                \
                       "KG_LAUNCH_DEVICE_FORCE: not as many arguments as kg_device_force has");                  \
        KG_TRY(kg_cl_launch_kernel(b, kernel, group_size, items, label, args_,                                   \
                                   (int)(sizeof args_ / sizeof args_[0])));                                      \
    } while (0)

/* KG_OK when kernel (named name) takes expected arguments (CL_KERNEL_NUM_ARGS); else a
 * backend error naming the kernel and both counts. */
kg_result kg_cl_check_arg_count(kg_cl_backend* b, cl_kernel kernel, const char* name, int expected);

/* Waits for the queue; errors of kernels that failed while running surface here. */
kg_result kg_cl_finish(kg_cl_backend* b);

/* Residency (see above). */
kg_result kg_cl_upload(kg_cl_backend* b, const kg_body_pool* pool, unsigned arrays);
kg_result kg_cl_download(kg_cl_backend* b, kg_body_pool* pool, unsigned arrays);
/* Uploads what the host changed, downloads what the device changed, for the given arrays. */
kg_result kg_cl_to_device(kg_cl_backend* b, const kg_body_pool* pool, unsigned arrays);
kg_result kg_cl_to_host(kg_cl_backend* b, kg_body_pool* pool, unsigned arrays);
/* Copies the state arrays into the checkpoint buffers (on the device), or reads the
 * checkpoint back into the host pool. */
kg_result kg_cl_save_checkpoint(kg_cl_backend* b, const kg_body_pool* pool);
kg_result kg_cl_read_checkpoint(kg_cl_backend* b, kg_body_pool* pool);

/* The mask of the arrays a step changes. */
unsigned kg_cl_state_arrays(void);

/* Adds the device time of the step's profiled commands to b->timing, and releases them. */
void kg_cl_collect_timing(kg_cl_backend* b);

#endif
