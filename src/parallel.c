/* A minimal fork-join over blocks of an index range. Work is split into fixed blocks handed out in order, so each
 * block's result is the same whichever thread computes it: outputs never depend on the thread count. */
#include <pthread.h>
#include <stdatomic.h>
#include <time.h>
#include <unistd.h>

#include "internal.h"

unsigned resurfi_thread_count(unsigned requested)
{
    if (requested > 0)
        return requested > 256 ? 256 : requested;
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > 256 ? 256 : (unsigned)n;
}

typedef struct job {
    size_t count, block_size;
    atomic_size_t next_block;
    atomic_int failed;
    int (*fn)(void *ctx, size_t begin, size_t end, unsigned worker);
    void *ctx;
} job;

typedef struct worker_arg {
    job *job;
    unsigned worker;
} worker_arg;

static void *run_blocks(void *p)
{
    worker_arg *arg = p;
    job *j = arg->job;
    for (;;) {
        if (atomic_load(&j->failed))
            break;
        size_t b = atomic_fetch_add(&j->next_block, 1);
        size_t begin = b * j->block_size;
        if (begin >= j->count)
            break;
        size_t end = begin + j->block_size < j->count ? begin + j->block_size : j->count;
        if (j->fn(j->ctx, begin, end, arg->worker))
            atomic_store(&j->failed, 1);
    }
    return NULL;
}

int resurfi_parallel_for(size_t count, size_t block_size, unsigned threads,
                         int (*fn)(void *ctx, size_t begin, size_t end, unsigned worker), void *ctx)
{
    if (count == 0)
        return 0;
    if (block_size == 0)
        block_size = 1;
    size_t blocks = (count + block_size - 1) / block_size;
    if (threads < 1)
        threads = 1;
    if (threads > blocks)
        threads = (unsigned)blocks;
    job j = {.count = count, .block_size = block_size, .fn = fn, .ctx = ctx};
    atomic_init(&j.next_block, 0);
    atomic_init(&j.failed, 0);
    pthread_t tid[256];
    worker_arg args[256];
    unsigned started = 0;
    for (unsigned w = 1; w < threads; ++w) {
        args[w] = (worker_arg){&j, w};
        if (pthread_create(&tid[w], NULL, run_blocks, &args[w]) != 0)
            break; /* fewer threads: the remaining blocks are still taken by those running */
        started = w;
    }
    args[0] = (worker_arg){&j, 0};
    run_blocks(&args[0]);
    for (unsigned w = 1; w <= started; ++w)
        pthread_join(tid[w], NULL);
    return atomic_load(&j.failed);
}

/* ---- a call's team: threads of its own, or the host's pool ------------------------------------------------- */

/* Waits block (condition variables, futexes underneath) and never spin: on a machine busy with other work a
 * spinning waiter takes the core from the thread it waits for (issue 20: 2 threads 1.75x slower than 1 on 20k
 * triangles while other processes kept both cores busy). Nor does a loop wait for a worker that has not woken
 * yet: once the calling thread has taken the last block, the loop closes, it waits only for the workers inside it
 * (those running blocks), and a worker that wakes later finds it closed and sleeps again. */

typedef struct pool_member {
    struct resurfi_pool *pool;
    unsigned worker;
} pool_member;

struct resurfi_pool {
    const resurf_allocator *alloc;
    unsigned threads;              /* the creating thread included; with a host pool, the tasks of each loop */
    const resurf_thread_pool *host; /* NULL: the threads below */
    pthread_mutex_t lock;
    pthread_cond_t wake, done;
    /* under lock: */
    uint_fast64_t round; /* bumped for each loop handed out */
    job *job;            /* the open loop, NULL once closed */
    unsigned inside;     /* workers that joined the loop and are still in it */
    int stop;
    double off_core;     /* the longest time a worker of the open loop spent off its core inside it */
    unsigned stalls;     /* loops kept waiting on a worker off its core (the creating thread's alone) */
    pthread_t tid[256];
    pool_member members[256];
};

/* A loop stalls when its caller, its own blocks done, waits over STALL_SECONDS for a worker that spent over
 * STALL_SECONDS of the loop off its core: other work on the machine took the core from it in mid-block (the
 * library's blocks compute, they never sleep; on an idle machine neither happens). After STALLS_ALONE such loops the
 * pool runs its loops on the caller alone for the rest of its call, so that a busy host loses to the call's
 * threads no more than those waits (issue 20: two threads are never to be slower than one). The results do not
 * change: a block is a pure function of its index. */
#define STALL_SECONDS 0.002
#define STALLS_ALONE 2

static double clock_seconds(clockid_t id)
{
    struct timespec t;
    clock_gettime(id, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void *pool_worker(void *p)
{
    const pool_member *me = p;
    resurfi_pool *pool = me->pool;
    uint_fast64_t seen = 0;
    pthread_mutex_lock(&pool->lock);
    for (;;) {
        while (!pool->stop && (pool->round == seen || !pool->job)) {
            seen = pool->round; /* a loop closed before this worker woke is none of its business */
            pthread_cond_wait(&pool->wake, &pool->lock);
        }
        if (pool->stop)
            break;
        seen = pool->round;
        worker_arg mine = {pool->job, me->worker};
        pool->inside++;
        pthread_mutex_unlock(&pool->lock);
        double wall = clock_seconds(CLOCK_MONOTONIC), core = clock_seconds(CLOCK_THREAD_CPUTIME_ID);
        run_blocks(&mine);
        /* Off its core: wall time less CPU time. A loop shorter than STALL_SECONDS cannot count, and is spared the
         * second CPU clock read. */
        double took = clock_seconds(CLOCK_MONOTONIC) - wall;
        double off = took > STALL_SECONDS ? took - (clock_seconds(CLOCK_THREAD_CPUTIME_ID) - core) : 0;
        pthread_mutex_lock(&pool->lock);
        pool->off_core = off > pool->off_core ? off : pool->off_core;
        if (--pool->inside == 0)
            pthread_cond_signal(&pool->done);
    }
    pthread_mutex_unlock(&pool->lock);
    return NULL;
}

resurf_status resurfi_pool_create(const resurf_allocator *alloc, unsigned threads, const resurf_thread_pool *host,
                                  resurfi_pool **out)
{
    *out = NULL;
    if (threads > 256)
        threads = 256;
    if (threads < 2)
        return RESURF_OK;
    resurfi_pool *pool = resurfi_calloc(alloc, 1, sizeof *pool);
    if (!pool)
        return RESURF_ERR_OUT_OF_MEMORY;
    pool->alloc = alloc;
    pthread_mutex_init(&pool->lock, NULL);
    pthread_cond_init(&pool->wake, NULL);
    pthread_cond_init(&pool->done, NULL);
    if (host) { /* no threads of ours: each loop goes to the host as `threads` tasks */
        pool->host = host;
        pool->threads = threads;
        *out = pool;
        return RESURF_OK;
    }
    pool->threads = 1;
    for (unsigned w = 1; w < threads; ++w) {
        pool->members[w] = (pool_member){pool, w};
        if (pthread_create(&pool->tid[w], NULL, pool_worker, &pool->members[w]) != 0)
            break;
        pool->threads = w + 1;
    }
    if (pool->threads < 2) {
        resurfi_pool_free(pool);
        return RESURF_OK;
    }
    *out = pool;
    return RESURF_OK;
}

void resurfi_pool_free(resurfi_pool *pool)
{
    if (!pool)
        return;
    pthread_mutex_lock(&pool->lock);
    pool->stop = 1;
    pthread_cond_broadcast(&pool->wake);
    pthread_mutex_unlock(&pool->lock);
    for (unsigned w = 1; w < pool->threads && !pool->host; ++w)
        pthread_join(pool->tid[w], NULL);
    pthread_cond_destroy(&pool->wake);
    pthread_cond_destroy(&pool->done);
    pthread_mutex_destroy(&pool->lock);
    resurfi_free(pool->alloc, pool);
}

/* A host task: the host's index is the worker id (below the pool's thread count, as the callers' scratch needs). */
static void host_task(void *ctx, unsigned index)
{
    worker_arg mine = {ctx, index};
    run_blocks(&mine);
}

int resurfi_pool_for(resurfi_pool *pool, size_t count, size_t block_size,
                     int (*fn)(void *ctx, size_t begin, size_t end, unsigned worker), void *ctx)
{
    if (count == 0)
        return 0;
    if (block_size == 0)
        block_size = 1;
    job j = {.count = count, .block_size = block_size, .fn = fn, .ctx = ctx};
    atomic_init(&j.next_block, 0);
    atomic_init(&j.failed, 0);
    worker_arg self = {&j, 0};
    if (!pool || count <= block_size || (!pool->host && pool->stalls >= STALLS_ALONE)) { /* no one to wake */
        run_blocks(&self);
        return atomic_load(&j.failed);
    }
    if (pool->host) {
        pool->host->run(pool->host->user, host_task, &j, pool->threads);
        /* Every task the host started has returned; blocks that none took (a host that started fewer tasks) are
         * done here, as worker 0, whose task is over or never began. */
        run_blocks(&self);
        return atomic_load(&j.failed);
    }
    pthread_mutex_lock(&pool->lock);
    pool->job = &j;
    pool->off_core = 0;
    pool->round++;
    pthread_cond_broadcast(&pool->wake);
    pthread_mutex_unlock(&pool->lock);
    run_blocks(&self); /* returns once every block is taken (or one failed) */
    double own = clock_seconds(CLOCK_MONOTONIC);
    pthread_mutex_lock(&pool->lock);
    pool->job = NULL;
    while (pool->inside != 0)
        pthread_cond_wait(&pool->done, &pool->lock);
    pool->stalls += clock_seconds(CLOCK_MONOTONIC) - own > STALL_SECONDS && pool->off_core > STALL_SECONDS;
    pthread_mutex_unlock(&pool->lock);
    return atomic_load(&j.failed);
}
