/* A small thread pool for the stages' loops over their elements on the CPU (it lives
 * in core, below the stages, which know no backend). Work is split into fixed chunks of
 * the index range, and every element's result depends only on its own inputs, so the
 * answer is the same bits whatever the thread count. Workers spin briefly between the
 * many short loops of a step (colours x sub-steps) and sleep between steps. */
#ifndef KG_PARALLEL_H
#define KG_PARALLEL_H

typedef void kg_range_fn(void* context, int begin, int end);

typedef struct kg_thread_pool kg_thread_pool;

/* threads counts the caller: 1 creates no worker. NULL on failure. */
kg_thread_pool* kg_thread_pool_create(int threads);
void kg_thread_pool_destroy(kg_thread_pool* pool);
/* Runs fn over [0, count) in chunks of at least grain; returns when all are done.
 * pool may be NULL (runs inline). */
void kg_parallel_for(kg_thread_pool* pool, int count, int grain, kg_range_fn* fn, void* context);

/* The grain of a loop over bodies: a body's work is small. */
#define KG_BODY_GRAIN 256

#endif
