#include "core/parallel.h"
#include "core/alloc.h"

#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdint.h>
#include <time.h>

/* How long an idle worker spins before sleeping. Most of a step's loops come less than
 * a microsecond apart, but a step also has serial parts between them (measured on
 * many_pyramids: 0.3 to 4 ms), and a worker that sleeps through one joins the next loops
 * late: spinning 1 ms instead of 5 made that scene 6% slower on 2 threads. Past this a
 * world that is not being stepped lets the core go (and the spin yields all along). */
#define KG_SPIN_NS 5000000
/* Pauses (about 6 us on a current x86) between two looks at the clock while spinning:
 * reading it costs more than a pause, but is no system call. */
#define KG_PAUSES_PER_CLOCK 256
/* How long the caller spins waiting for the workers' last chunks before it starts
 * yielding: a chunk takes microseconds, so only a worker preempted in the middle of
 * one takes that long, and then the caller may be the one holding its core. */
#define KG_CALLER_SPIN_NS 50000

/* Fields that threads write at different rates are kept on different cache lines, so a
 * worker claiming a chunk does not take the line the caller spins on, and so on. The
 * pads are plain bytes (no _Alignas: the pool comes from an allocator that only promises
 * KG_ALIGNMENT, and the sanitizers check alignment). */
#define KG_CACHE_LINE 64

/* The chunks of the current loop that one thread owns: work packs (job id, end, next
 * chunk) in one word so a late worker still holding an old job id can never claim a
 * chunk of a newer loop; the pool's plain fields are written before the words are
 * published and read only after a successful claim. Each thread takes its own range
 * first, then what is left of the others': a loop's thread t gets the same range every
 * time, so consecutive colours, passes and sub-steps find the bodies they share (the
 * contacts are in body order) in that thread's cache instead of the other core's. */
typedef struct kg_claims {
    _Atomic uint64_t work;
    char pad[KG_CACHE_LINE - sizeof(uint64_t)];
} kg_claims;

typedef struct kg_worker {
    struct kg_thread_pool* pool;
    int self;
} kg_worker;

struct kg_thread_pool {
    int threads;
    pthread_t* workers;
    pthread_mutex_t mutex;
    pthread_cond_t wake;
    char pad0[KG_CACHE_LINE];
    /* Written once per loop by the caller, read by spinning workers. */
    atomic_uint job;     /* incremented for every new loop (unsigned: it may wrap) */
    atomic_int stop;
    atomic_int sleepers; /* workers waiting (or about to wait) on wake */
    kg_range_fn* fn;
    void* context;
    int count;
    int chunk;
    kg_claims* claims;   /* one a thread, the caller's first */
    kg_worker* selves;   /* what each worker is started with */
    char pad1[KG_CACHE_LINE];
    atomic_int chunks_done; /* the caller spins on this one */
    char pad2[KG_CACHE_LINE];
};

#define KG_WORK(job, end, next) (((uint64_t)((job) & 0xFFFFu) << 48) | ((uint64_t)(end) << 24) | (uint64_t)(next))

/* Tells the core this is a spin-wait: it saves power and lets the sibling
 * hyper-thread run. */
static void kg_cpu_pause(void)
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

static int64_t kg_now_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (int64_t)t.tv_sec * 1000000000 + t.tv_nsec;
}

/* The next chunk of loop job in thread t's range, or -1 when none is left there (or the
 * loop is over). */
static int kg_claim_chunk(kg_thread_pool* p, int t, unsigned job)
{
    _Atomic uint64_t* work = &p->claims[t].work;
    uint64_t w = atomic_load(work);
    for (;;) {
        uint64_t end = (w >> 24) & 0xFFFFFFu, next = w & 0xFFFFFFu;
        if ((w >> 48) != (job & 0xFFFFu) || next >= end) {
            return -1;
        }
        if (atomic_compare_exchange_weak(work, &w, w + 1u)) {
            return (int)next;
        }
    }
}

/* Thread self's own chunks, then the others' that are left. */
static void kg_run_chunks(kg_thread_pool* p, int self, unsigned job)
{
    for (int i = 0; i < p->threads; ++i) {
        int t = (self + i) % p->threads;
        for (int c = kg_claim_chunk(p, t, job); c >= 0; c = kg_claim_chunk(p, t, job)) {
            int begin = c * p->chunk;
            int end = begin + p->chunk < p->count ? begin + p->chunk : p->count;
            p->fn(p->context, begin, end);
            atomic_fetch_add(&p->chunks_done, 1);
        }
    }
}

static int kg_job_changed(kg_thread_pool* p, unsigned seen)
{
    return atomic_load(&p->job) != seen || atomic_load(&p->stop);
}

/* Spins up to KG_SPIN_NS for a job newer than seen; 1 if one came (or stop). It yields
 * at each look at the clock: on an idle machine that returns at once, but on a loaded
 * one a worker that spun through its time slice would be preempted in the middle of its
 * next chunk, and the caller would wait for it (measured: 2 threads then ran a loop
 * 1.3 to 2.7 times slower than 1 thread; yielding keeps them at about 1 thread's pace). */
static int kg_spin_for_job(kg_thread_pool* p, unsigned seen)
{
    int64_t give_up = kg_now_ns() + KG_SPIN_NS;
    for (;;) {
        for (int i = 0; i < KG_PAUSES_PER_CLOCK; ++i) {
            if (kg_job_changed(p, seen)) {
                return 1;
            }
            kg_cpu_pause();
        }
        if (kg_now_ns() > give_up) {
            return 0;
        }
        sched_yield();
    }
}

/* Waits for a job newer than seen: spins first, then sleeps on the condition variable.
 * The sleeper is counted before the job is checked again, and the publisher stores the
 * job before it reads the count (both sequentially consistent), so either this thread
 * sees the new job or the publisher sees the sleeper and broadcasts; the mutex, held
 * from the count to the wait, keeps that broadcast from landing before the wait. */
static unsigned kg_wait_for_job(kg_thread_pool* p, unsigned seen)
{
    if (!kg_spin_for_job(p, seen)) {
        pthread_mutex_lock(&p->mutex);
        atomic_fetch_add(&p->sleepers, 1);
        while (!kg_job_changed(p, seen)) {
            pthread_cond_wait(&p->wake, &p->mutex);
        }
        atomic_fetch_sub(&p->sleepers, 1);
        pthread_mutex_unlock(&p->mutex);
    }
    return atomic_load(&p->job);
}

static void* kg_worker_main(void* arg)
{
    const kg_worker* me = arg;
    kg_thread_pool* p = me->pool;
    unsigned seen = 0;
    for (;;) {
        seen = kg_wait_for_job(p, seen);
        if (atomic_load(&p->stop)) {
            return NULL;
        }
        kg_run_chunks(p, me->self, seen);
    }
}

kg_thread_pool* kg_thread_pool_create(int threads)
{
    kg_thread_pool* p = kg_alloc_zeroed(sizeof *p);
    if (!p) {
        return NULL;
    }
    p->threads = 1;
    pthread_mutex_init(&p->mutex, NULL);
    pthread_cond_init(&p->wake, NULL);
    if (threads > 1) {
        p->workers = kg_alloc_zeroed((size_t)(threads - 1) * sizeof *p->workers);
        p->selves = kg_alloc_zeroed((size_t)(threads - 1) * sizeof *p->selves);
        p->claims = kg_alloc_zeroed((size_t)threads * sizeof *p->claims);
        /* threads counts only the workers started, so destroy joins no more than that
         * (and without the worker arrays the caller runs every loop alone) */
        for (int i = 0; p->workers && p->selves && p->claims && i < threads - 1; ++i) {
            p->selves[i].pool = p;
            p->selves[i].self = i + 1;
            if (pthread_create(&p->workers[i], NULL, kg_worker_main, &p->selves[i]) != 0) {
                break;
            }
            p->threads = i + 2;
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
    kg_free(p->selves);
    kg_free(p->claims);
    kg_free(p);
}

/* Makes loop job visible to the workers: no lock and no system call while they spin;
 * the mutex and the broadcast only when one has gone to sleep (see kg_wait_for_job). */
static void kg_publish(kg_thread_pool* p, unsigned job)
{
    atomic_store(&p->job, job);
    if (atomic_load(&p->sleepers) > 0) {
        pthread_mutex_lock(&p->mutex);
        pthread_cond_broadcast(&p->wake);
        pthread_mutex_unlock(&p->mutex);
    }
}

/* Waits for the chunks other threads claimed. They are short and their threads are
 * running, so spinning beats a system call per look; yielding only after a long spin
 * lets a preempted worker have the core back on a loaded machine. */
static void kg_wait_for_chunks(kg_thread_pool* p, int chunk_count)
{
    int64_t yield_after = 0; /* read the clock only once the wait is no longer short */
    for (int spin = 1; atomic_load(&p->chunks_done) < chunk_count; ++spin) {
        kg_cpu_pause();
        if (spin % KG_PAUSES_PER_CLOCK == 0) {
            int64_t now = kg_now_ns();
            yield_after = yield_after ? yield_after : now + KG_CALLER_SPIN_NS;
            if (now > yield_after) {
                sched_yield();
            }
        }
    }
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
    chunk = chunk < grain ? grain : chunk;
    int chunk_count = (count + chunk - 1) / chunk;
    if (chunk_count == 1) {
        fn(context, 0, count); /* nothing to share: waking a worker would only cost */
        return;
    }
    p->chunk = chunk;
    p->fn = fn;
    p->context = context;
    p->count = count;
    unsigned job = atomic_load(&p->job) + 1u;
    atomic_store(&p->chunks_done, 0);
    for (int t = 0; t < p->threads; ++t) {
        int first = (int)((int64_t)chunk_count * t / p->threads);
        int end = (int)((int64_t)chunk_count * (t + 1) / p->threads);
        atomic_store(&p->claims[t].work, KG_WORK(job, end, first));
    }
    kg_publish(p, job);
    kg_run_chunks(p, 0, job);
    kg_wait_for_chunks(p, chunk_count);
}
