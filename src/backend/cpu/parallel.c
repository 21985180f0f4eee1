#include "backend/cpu/parallel.h"
#include "core/alloc.h"

#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdint.h>

#define KG_SPINS_BEFORE_SLEEP 20000

struct kg_thread_pool {
    int threads;
    pthread_t* workers;
    pthread_mutex_t mutex;
    pthread_cond_t wake;
    atomic_int job;          /* incremented for every new loop */
    atomic_int stop;
    /* The current loop. work packs (job id, chunk count, next chunk) in one word so a
     * late worker still holding an old job id can never claim a chunk of a newer loop;
     * the plain fields below are written before work is published and read only after
     * a successful claim. */
    _Atomic uint64_t work;
    atomic_int chunks_done;
    kg_range_fn* fn;
    void* context;
    int count;
    int chunk;
};

#define KG_WORK(job, total, next) (((uint64_t)((job) & 0xFFFF) << 48) | ((uint64_t)(total) << 24) | (uint64_t)(next))

/* The next chunk of loop job, or -1 when that loop has no chunk left (or is over). */
static int kg_claim_chunk(kg_thread_pool* p, int job)
{
    uint64_t w = atomic_load(&p->work);
    for (;;) {
        uint64_t total = (w >> 24) & 0xFFFFFFu, next = w & 0xFFFFFFu;
        if ((int)(w >> 48) != (job & 0xFFFF) || next >= total) {
            return -1;
        }
        if (atomic_compare_exchange_weak(&p->work, &w, w + 1u)) {
            return (int)next;
        }
    }
}

static void kg_run_chunks(kg_thread_pool* p, int job)
{
    for (int c = kg_claim_chunk(p, job); c >= 0; c = kg_claim_chunk(p, job)) {
        int begin = c * p->chunk;
        int end = begin + p->chunk < p->count ? begin + p->chunk : p->count;
        p->fn(p->context, begin, end);
        atomic_fetch_add(&p->chunks_done, 1);
    }
}

/* Waits for a job newer than seen: spins first (loops in a step come microseconds
 * apart), then sleeps on the condition variable. */
static int kg_wait_for_job(kg_thread_pool* p, int seen)
{
    for (int spin = 0; spin < KG_SPINS_BEFORE_SLEEP; ++spin) {
        int job = atomic_load(&p->job);
        if (job != seen || atomic_load(&p->stop)) {
            return job;
        }
        if (spin > 100) {
            sched_yield();
        }
    }
    pthread_mutex_lock(&p->mutex);
    while (atomic_load(&p->job) == seen && !atomic_load(&p->stop)) {
        pthread_cond_wait(&p->wake, &p->mutex);
    }
    pthread_mutex_unlock(&p->mutex);
    return atomic_load(&p->job);
}

static void* kg_worker_main(void* arg)
{
    kg_thread_pool* p = arg;
    int seen = 0;
    for (;;) {
        seen = kg_wait_for_job(p, seen);
        if (atomic_load(&p->stop)) {
            return NULL;
        }
        kg_run_chunks(p, seen);
    }
}

kg_thread_pool* kg_thread_pool_create(int threads)
{
    kg_thread_pool* p = kg_alloc_zeroed(sizeof *p);
    if (!p) {
        return NULL;
    }
    p->threads = threads < 1 ? 1 : threads;
    pthread_mutex_init(&p->mutex, NULL);
    pthread_cond_init(&p->wake, NULL);
    if (p->threads > 1) {
        p->workers = kg_alloc_zeroed((size_t)(p->threads - 1) * sizeof *p->workers);
        for (int i = 0; p->workers && i < p->threads - 1; ++i) {
            if (pthread_create(&p->workers[i], NULL, kg_worker_main, p) != 0) {
                p->threads = i + 1; /* run with the workers we got */
                break;
            }
        }
    }
    return p;
}

void kg_thread_pool_destroy(kg_thread_pool* p)
{
    if (!p) {
        return;
    }
    pthread_mutex_lock(&p->mutex);
    atomic_store(&p->stop, 1);
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->mutex);
    for (int i = 0; i < p->threads - 1; ++i) {
        pthread_join(p->workers[i], NULL);
    }
    pthread_mutex_destroy(&p->mutex);
    pthread_cond_destroy(&p->wake);
    kg_free(p->workers);
    kg_free(p);
}

void kg_parallel_for(kg_thread_pool* p, int count, int grain, kg_range_fn* fn, void* context)
{
    if (count <= 0) {
        return;
    }
    if (!p || p->threads == 1 || count <= grain) {
        fn(context, 0, count);
        return;
    }
    int chunk = (count + 4 * p->threads - 1) / (4 * p->threads);
    p->chunk = chunk < grain ? grain : chunk;
    p->fn = fn;
    p->context = context;
    p->count = count;
    int chunk_count = (count + p->chunk - 1) / p->chunk;
    int job = atomic_load(&p->job) + 1;
    atomic_store(&p->chunks_done, 0);
    atomic_store(&p->work, KG_WORK(job, chunk_count, 0));
    pthread_mutex_lock(&p->mutex);
    atomic_store(&p->job, job);
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->mutex);
    kg_run_chunks(p, job);
    while (atomic_load(&p->chunks_done) < chunk_count) {
        sched_yield();
    }
}
