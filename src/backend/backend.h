/* A backend runs the stages of a step over the world's pools. The CPU backend loops
 * over the shared per-element code; the OpenCL backend runs it as kernels, keeping
 * the pools resident on the device. */
#ifndef KG_BACKEND_H
#define KG_BACKEND_H

#include "core/world.h"

typedef struct kg_backend_ops {
    kg_backend kind;
    const char* name;
    kg_result (*step)(kg_world* world, float dt);
    /* Brings the host copy of the pools up to date (no-op on the CPU). */
    kg_result (*sync_to_host)(kg_world* world);
    /* Marks the host copy as changed by the user, to upload before the next step. */
    void (*host_changed)(kg_world* world);
    void (*destroy)(kg_world* world);
    /* Brings the host's contact list up to date (NULL when contacts are built on the host). */
    void (*sync_contacts)(kg_world* world);
} kg_backend_ops;

extern const kg_backend_ops kg_cpu_backend;

/* Starts the backend the definition and KGYRO_BACKEND ask for, falling back to the CPU
 * with one warning when OpenCL cannot be used. */
kg_result kg_backend_select(kg_world* world);

#endif
