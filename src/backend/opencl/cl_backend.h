/* The OpenCL backend: the step as kernels over the pools kept on the device (cl_step.c),
 * the backend operations and the fallback to the CPU (cl_backend.c). */
#ifndef KG_CL_BACKEND_H
#define KG_CL_BACKEND_H

#include "backend/backend.h"
#include "backend/backend_state.h"
#include "backend/opencl/cl_world.h"
#include "backend/opencl/kernels/kg_collide_shared.h"
#include "solve/graph_color.h"

typedef struct kg_cl_backend {
    kg_cl_world* w;
    /* host scratch, grown (never in a steady state) when a step needs more */
    kg_force_target* targets;        /* the lists of this step's applicators */
    int target_capacity;
    int* color_scratch;
    int color_capacity;
    kg_graph_coloring coloring;
    kg_solver_params solver_params;  /* the step's, read by a non-blocking write */
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
    /* contacts: the last step's are in w->contacts[w->current]; the host's list (collide.h)
     * is filled from there only when asked for (contacts_stale) */
    int body_contact_count;          /* the first ones, body pairs; tile contacts follow */
    int tile_state_on_device;        /* the one-way platform state is newer on the device */
    int tiles_ran;                   /* this step collided the tile maps on the device */
    int contacts_stale;
    cl_uint counters[KG_CC_WORDS];   /* the device collide stage's counters, read back */
    /* this step's collide stage: where it ran, the pairs it found on the device, the
     * contacts it made (the first step_body_count between bodies, tile contacts after) */
    int step_on_device;
    int step_pairs;
    int step_count;
    int step_body_count;
} kg_cl_backend;

extern const kg_backend_ops kg_opencl_backend;

/* Starts OpenCL on the device kg_backend_select chose. */
kg_result kg_cl_backend_start(kg_world* world, int device_index);
/* Releases the OpenCL state (not the backend state). */
void kg_cl_backend_stop(kg_world* world);

/* The step on the device (cl_step.c): its beginning, each stage of core/step.h, its end;
 * a failure leaves the error set. A failure that the step's own code did not see (a read
 * for a getter a force callback calls) is recorded with kg_cl_request_fallback, and the
 * step returns KG_ERROR_BACKEND once the callback has returned, with no device call after
 * it. Either way the backend falls back once the step has unwound (kg_opencl_end_step):
 * nothing the step uses is freed while it runs. */
kg_result kg_cl_begin_step(kg_world* world, kg_cl_backend* b);
kg_result kg_cl_run_stage(kg_world* world, kg_cl_backend* b, kg_stage stage, float dt);
kg_result kg_cl_end_step(kg_world* world, kg_cl_backend* b);
/* The label a stage's time is reported under (core/step.c), or NULL when its kernels are
 * timed by their events. */
const char* kg_cl_stage_label(const kg_world* world, const kg_cl_backend* b, kg_stage stage);
/* Records that the world must fall back at the end of the step, for the failure described
 * by the current error (the first one counts). */
void kg_cl_request_fallback(kg_cl_backend* b);
/* The collision stage on the device (cl_collide.c), tile maps included: this step's
 * contacts built into w->contacts[!w->current], b->step_pairs set. *fits is 0 when the
 * pairs outgrow the contact pool: then nothing is built, and the host's stage must run
 * (it grows the pool). */
kg_result kg_cl_collide_on_device(kg_world* world, kg_cl_backend* b, int* fits);
/* Colours the contacts the device built (solve/coloring.h) and reads back how many there
 * are, *count, the first *body_count between bodies, with b->coloring's colour ranges set
 * for the solver. */
kg_result kg_cl_color_on_device(kg_world* world, kg_cl_backend* b, int* count, int* body_count);
/* The one-way platform state (collide/tilemap.c's last origins) into the host's arrays,
 * when the device has it newer: before the host's collide stage runs, or the CPU backend
 * takes over. */
kg_result kg_cl_tile_state_to_host(kg_world* world, kg_cl_backend* b);
/* A step that collided tiles on the device makes its one-way state the current one. */
void kg_cl_commit_tile_state(kg_cl_backend* b);
/* Reads the last step's contacts into the host's list, if it lacks them. */
kg_result kg_cl_read_contacts(kg_world* world, kg_cl_backend* b);

/* Builds the program of the device force in slot and its kernel. */
kg_result kg_cl_prepare_device_force(kg_world* world, kg_cl_backend* b, int slot);
/* The device forces' kernels of slots no longer holding one are released. */
void kg_cl_release_device_force(kg_cl_backend* b, int slot);

/* Warns, as the CPU backend does, of bodies the device froze (non-finite state) since the
 * host last read the flags back. */
void kg_cl_warn_new_frozen(kg_world* world, kg_cl_backend* b);
/* The flags into the host's pool when the device has them newer (for the host code that
 * reads them: which bodies sleep, which froze), with that warning. */
kg_result kg_cl_flags_to_host(kg_world* world, kg_cl_backend* b);

/* Sleeping (cl_sleep.c), when the world's definition enables it. In the collide stage on
 * the device, before the colouring: the sleeping islands that this step's touching pairs
 * (pairs of them) reach from a body in motion wake. */
kg_result kg_cl_wake_on_device(kg_world* world, kg_cl_backend* b, int pairs);
/* The same on the host, from the host's contacts (the collide stage ran there), the woken
 * flags uploaded. */
kg_result kg_cl_wake_on_host(kg_world* world, kg_cl_backend* b);
/* Last in the step: the islands of this step's count contacts that rested time_to_sleep
 * fall asleep. */
kg_result kg_cl_sleep_on_device(kg_world* world, kg_cl_backend* b, int count);

/* Devices auto may choose: GPUs and accelerators (a CPU device through OpenCL is no
 * faster than the CPU backend, and compiling its kernels costs seconds). */
int kg_cl_auto_device(void);

#endif
