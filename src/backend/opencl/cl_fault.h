/* Failure injection, to test every error path of the host code without a broken device.
 *
 *   KGYRO_CL_FAIL=site[:N][,site[:N]...]
 *
 * makes the Nth call (default 1) at that site fail as the device would, counted per world
 * from its creation. Sites:
 *   load      libOpenCL cannot be loaded
 *   platform  no platform or device is found
 *   build     the kernel program does not build
 *   alloc     a buffer cannot be allocated
 *   enqueue   a kernel launch or a write is refused
 *   finish    a kernel fails while running (reported when the queue is drained)
 *   read      a read back fails
 *   lost      the device is lost: from the Nth enqueue on, every command fails, reads too
 * The variable is read when a world starts its backend. */
#ifndef KG_CL_FAULT_H
#define KG_CL_FAULT_H

typedef enum kg_cl_fault_site {
    KG_CL_FAULT_LOAD,
    KG_CL_FAULT_PLATFORM,
    KG_CL_FAULT_BUILD,
    KG_CL_FAULT_ALLOC,
    KG_CL_FAULT_ENQUEUE,
    KG_CL_FAULT_FINISH,
    KG_CL_FAULT_READ,
    KG_CL_FAULT_LOST,
    KG_CL_FAULT_SITE_COUNT
} kg_cl_fault_site;

typedef struct kg_cl_faults {
    int fail_at[KG_CL_FAULT_SITE_COUNT]; /* 0 = never */
    int calls[KG_CL_FAULT_SITE_COUNT];
    int lost;
} kg_cl_faults;

/* Parses KGYRO_CL_FAIL; an unknown site is reported once and ignored. */
void kg_cl_faults_from_env(kg_cl_faults* faults);

/* Counts a call at site; non-zero when it must fail. A lost device fails every enqueue,
 * finish and read from the Nth enqueue on. */
int kg_cl_fault(kg_cl_faults* faults, kg_cl_fault_site site);

#endif
