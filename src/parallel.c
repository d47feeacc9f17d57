/* A minimal fork-join over blocks of an index range. Work is split into fixed blocks handed out in order, so each
 * block's result is the same whichever thread computes it: outputs never depend on the thread count. */
#include <pthread.h>
#include <stdatomic.h>
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
