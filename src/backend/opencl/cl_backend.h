/* The OpenCL backend: the step as kernels over the pools kept on the device (cl_step.c),
 * the backend operations and the fallback to the CPU (cl_backend.c). */
#ifndef KG_CL_BACKEND_H
#define KG_CL_BACKEND_H

#include "backend/backend.h"
#include "backend/backend_state.h"
#include "backend/opencl/cl_world.h"
#include "solve/solver.h"

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
 * contacts built into b->contacts[!b->current], b->step_pairs set. *fits is 0 when the
 * pairs (or, while a body has several shapes, the pairs of shapes) outgrow the contact
 * pool: then nothing is built, and the host's stage must run (it grows the pool). */
kg_result kg_cl_collide_on_device(kg_world* world, kg_cl_backend* b, int* fits);
/* Colours the contacts the device built (solve/coloring.h) and reads back how many there
 * are, *count, the first *body_count between bodies, with b->coloring's colour ranges set
 * for the solver. */
kg_result kg_cl_color_on_device(kg_world* world, kg_cl_backend* b, int* count, int* body_count);
/* Reads back how many contacts the device built, *count, the first *body_count between
 * bodies (warning once when tile contacts were dropped for room). */
kg_result kg_cl_count_contacts(kg_world* world, kg_cl_backend* b, int* count, int* body_count);
/* The one-way platform state (collide/tilemap.c's last origins) into the host's arrays,
 * when the device has it newer: before the host's collide stage runs, or the CPU backend
 * takes over. */
kg_result kg_cl_tile_state_to_host(kg_world* world, kg_cl_backend* b);
/* A step that collided tiles on the device makes its one-way state the current one. */
void kg_cl_commit_tile_state(kg_cl_backend* b);
/* The tile maps on the device as on the host (the collide stage's own does it too). */
kg_result kg_cl_sync_tiles(kg_world* world, kg_cl_backend* b);
/* Continuous collision's index of the static bodies (solver.h kg_continuous_statics) on
 * the device, sent again when it changed; *list gets it as the host has it. */
kg_result kg_cl_sync_statics(kg_world* world, kg_cl_backend* b, kg_static_list* list);
/* Reads the last step's contacts into the host's list, if it lacks them. */
kg_result kg_cl_read_contacts(kg_world* world, kg_cl_backend* b);
/* The step before's contacts (the device keeps them until the next step) into the host's
 * previous list, when stale. */
kg_result kg_cl_read_previous_contacts(kg_world* world, kg_cl_backend* b);

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
