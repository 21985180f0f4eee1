/* A backend runs the stages of a step (core/step.h) over the world's pools. The CPU
 * backend loops over the shared per-element code; the OpenCL backend runs it as kernels,
 * keeping the pools resident on the device. */
#ifndef KG_BACKEND_H
#define KG_BACKEND_H

#include "core/step.h"
#include "core/world.h"

typedef struct kg_backend_ops {
    kg_backend kind;
    const char* name;
    /* Before the first stage (NULL: nothing to do). */
    kg_result (*begin_step)(kg_world* world, float dt);
    kg_result (*run_stage)(kg_world* world, kg_stage stage, float dt);
    /* After the stages, given how they went (NULL: their result); sets *redo when the step
     * must be run again from its start, on the backend the world now has. */
    kg_result (*end_step)(kg_world* world, kg_result stages, int* redo);
    /* What a stage's time is reported as, or NULL for not at all (NULL: its name). */
    const char* (*stage_label)(const kg_world* world, kg_stage stage);
    /* Brings the host copy of the pools up to date (no-op on the CPU). */
    kg_result (*sync_to_host)(kg_world* world);
    /* Marks the host copy as changed by the user, to upload before the next step. */
    void (*host_changed)(kg_world* world);
    void (*destroy)(kg_world* world);
    /* Brings the host's contact list up to date (NULL when contacts are built on the host). */
    void (*sync_contacts)(kg_world* world);
    /* The same for the step before's list, which the device keeps until the next step
     * (NULL when contacts are built on the host). */
    void (*sync_previous_contacts)(kg_world* world);
    /* Brings to the host all a snapshot reads: the pools' state, the contacts and the tile
     * maps' one-way state (NULL when the host has it all). */
    void (*sync_for_snapshot)(kg_world* world);
    /* The host's state was replaced whole (a snapshot restored): what the backend holds
     * of it is stale, and is sent again before the next step (NULL: nothing held). */
    void (*restored)(kg_world* world);
} kg_backend_ops;

extern const kg_backend_ops kg_cpu_backend;

/* Starts the backend the definition and KGYRO_BACKEND ask for, falling back to the CPU
 * with one warning when OpenCL cannot be used. */
kg_result kg_backend_select(kg_world* world);

#endif
