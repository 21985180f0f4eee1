/* The step's stages, the same list and order on every backend (core/step.c walks it; a
 * backend says how to run each). */
#ifndef KG_STEP_H
#define KG_STEP_H

typedef enum kg_stage {
    KG_STAGE_FORCES,   /* applicators: gravity, wind, user and device forces (solve/forces.c) */
    KG_STAGE_COLLIDE,  /* broadphase pairs, manifolds, contacts with last step's impulses (collide/) */
    KG_STAGE_WAKE,     /* sleeping islands touched by moving bodies wake (solve/sleep.c) */
    KG_STAGE_PRE_SOLVE, /* the user's pre-solve callback may switch contacts off (collide/pre_solve.c) */
    KG_STAGE_SOLVE,    /* colour the contacts, then the soft step's sub-steps (solve/solver.c) */
    KG_STAGE_FINALIZE, /* forces cleared, poses and bounds updated (solve/body_step.h) */
    KG_STAGE_SLEEP,    /* islands at rest fall asleep (solve/sleep.c) */
    KG_STAGE_COUNT
} kg_stage;

/* "forces", "collide", ...: the name its time is reported under. */
const char* kg_stage_name(kg_stage stage);
/* A monotonic clock in milliseconds, for stage times. */
double kg_now_ms(void);

#endif
