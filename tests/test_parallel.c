/* src/parallel.c: every index visited exactly once in well-formed blocks for any count, block size and thread
 * count, and an early stop once a block fails; the same of a pool, loop after loop; and a host's pool
 * (resurf_thread_pool, a small job system made here) running the simplifier's loops with the same bytes out. */
#include <dirent.h>
#include <pthread.h>
#include <stdatomic.h>
#include <string.h>
#include <unistd.h>

#include "scene_internal.h"
#include "testutil.h"

typedef struct visit_ctx {
    size_t count, block_size;
    unsigned threads;
    atomic_int *visits;     /* per index */
    atomic_int bad_block;   /* a block that is not [k·block_size, min(count, (k+1)·block_size)) */
    atomic_int bad_worker;  /* a worker id >= threads */
    atomic_int calls;
    size_t fail_at;         /* the block containing this index returns 1 (SIZE_MAX: never) */
    int fail_all;           /* every block returns 1 */
} visit_ctx;

static int visit(void *p, size_t begin, size_t end, unsigned worker)
{
    visit_ctx *c = p;
    atomic_fetch_add(&c->calls, 1);
    size_t bs = c->block_size ? c->block_size : 1;
    size_t expected_end = begin + bs < c->count ? begin + bs : c->count;
    if (begin % bs != 0 || end != expected_end || begin >= end)
        atomic_store(&c->bad_block, 1);
    if (worker >= c->threads)
        atomic_store(&c->bad_worker, 1);
    for (size_t i = begin; i < end && i < c->count; ++i)
        atomic_fetch_add(&c->visits[i], 1);
    return c->fail_all || (c->fail_at >= begin && c->fail_at < end);
}

START_TEST(parallel_visits_every_index_once)
{
    const size_t counts[] = {0, 1, 2, 7, 64, 1000, 12345};
    const size_t blocks[] = {0, 1, 3, 64, 1000, 100000};
    const unsigned threads[] = {1, 2, 3, 8};
    for (size_t a = 0; a < sizeof counts / sizeof *counts; ++a)
        for (size_t b = 0; b < sizeof blocks / sizeof *blocks; ++b)
            for (size_t t = 0; t < sizeof threads / sizeof *threads; ++t) {
                visit_ctx c;
                memset(&c, 0, sizeof c);
                c.count = counts[a];
                c.block_size = blocks[b];
                c.threads = threads[t];
                c.fail_at = SIZE_MAX;
                c.visits = calloc(c.count + 1, sizeof *c.visits);
                ck_assert_int_eq(resurfi_parallel_for(c.count, c.block_size, c.threads, visit, &c), 0);
                for (size_t i = 0; i < c.count; ++i)
                    ck_assert_msg(atomic_load(&c.visits[i]) == 1,
                                  "count %zu block %zu threads %u: index %zu seen %d times", c.count, c.block_size,
                                  c.threads, i, atomic_load(&c.visits[i]));
                ck_assert_int_eq(atomic_load(&c.bad_block), 0);
                ck_assert_int_eq(atomic_load(&c.bad_worker), 0);
                size_t bs = c.block_size ? c.block_size : 1;
                ck_assert_int_eq(atomic_load(&c.calls), (int)((c.count + bs - 1) / bs));
                free(c.visits);
            }
}
END_TEST

/* One thread: blocks run in order, so a failure in block k means blocks 0..k ran and none after. */
START_TEST(parallel_stops_after_failure_single_thread)
{
    visit_ctx c;
    memset(&c, 0, sizeof c);
    c.count = 1000;
    c.block_size = 10;
    c.threads = 1;
    c.fail_at = 345; /* block 34 */
    c.visits = calloc(c.count, sizeof *c.visits);
    ck_assert_int_ne(resurfi_parallel_for(c.count, c.block_size, c.threads, visit, &c), 0);
    ck_assert_int_eq(atomic_load(&c.calls), 35);
    for (size_t i = 0; i < c.count; ++i)
        ck_assert_int_eq(atomic_load(&c.visits[i]), i < 350 ? 1 : 0);
    free(c.visits);
}
END_TEST

/* Several threads, every block failing: a thread checks for failure before taking each block, so each runs at
 * most the one block it took before any failure was recorded; at most `threads` of the 200000 blocks run. */
START_TEST(parallel_stops_after_failure_many_threads)
{
    visit_ctx c;
    memset(&c, 0, sizeof c);
    c.count = 200000;
    c.block_size = 1;
    c.threads = 4;
    c.fail_at = SIZE_MAX;
    c.fail_all = 1;
    c.visits = calloc(c.count, sizeof *c.visits);
    ck_assert_int_ne(resurfi_parallel_for(c.count, c.block_size, c.threads, visit, &c), 0);
    ck_assert_int_ge(atomic_load(&c.calls), 1);
    ck_assert_int_le(atomic_load(&c.calls), 4);
    ck_assert_int_eq(atomic_load(&c.visits[0]), 1);
    for (size_t i = 0; i < c.count; ++i)
        ck_assert_int_le(atomic_load(&c.visits[i]), 1);
    free(c.visits);
}
END_TEST

/* Per-block results written to their own slots do not depend on the thread count, nor on a pool's. */
typedef struct sum_ctx {
    const double *x;
    double *block_sum;
    size_t block_size;
} sum_ctx;

static int sum_block(void *p, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    sum_ctx *c = p;
    double s = 0;
    for (size_t i = begin; i < end; ++i)
        s += c->x[i];
    c->block_sum[begin / c->block_size] = s;
    return 0;
}

START_TEST(parallel_results_independent_of_threads)
{
    const size_t n = 100003, bs = 97, nb = (n + bs - 1) / bs;
    double *x = malloc(n * sizeof *x), *ref = malloc(nb * sizeof *ref), *got = malloc(nb * sizeof *got);
    uint64_t state = 5;
    for (size_t i = 0; i < n; ++i)
        x[i] = shape_rand_unit(&state) - 0.5;
    sum_ctx c = {x, ref, bs};
    ck_assert_int_eq(resurfi_parallel_for(n, bs, 1, sum_block, &c), 0);
    c.block_sum = got;
    for (unsigned t = 2; t <= 6; ++t) {
        ck_assert_int_eq(resurfi_parallel_for(n, bs, t, sum_block, &c), 0);
        ck_assert(memcmp(got, ref, nb * sizeof *got) == 0);
        resurfi_pool *pool; /* and on a pool of t threads, loop after loop */
        ck_assert_int_eq(resurfi_pool_create(NULL, t, NULL, &pool), RESURF_OK);
        for (int round = 0; round < 5; ++round) {
            memset(got, 0, nb * sizeof *got);
            ck_assert_int_eq(resurfi_pool_for(pool, n, bs, sum_block, &c), 0);
            ck_assert(memcmp(got, ref, nb * sizeof *got) == 0);
        }
        resurfi_pool_free(pool);
    }
    resurfi_pool_free(NULL);
    free(x);
    free(ref);
    free(got);
}
END_TEST

/* A pool runs loop after loop, each index of each once, in well-formed blocks, with worker ids below its size; a
 * failing block stops its loop and not the next; a pool of one thread is none (NULL) and still runs loops. */
START_TEST(pool_runs_many_loops)
{
    const unsigned threads[] = {1, 2, 3, 8};
    for (size_t t = 0; t < sizeof threads / sizeof *threads; ++t) {
        resurfi_pool *pool = (resurfi_pool *)1;
        ck_assert_int_eq(resurfi_pool_create(NULL, threads[t], NULL, &pool), RESURF_OK);
        ck_assert(threads[t] > 1 ? pool != NULL : pool == NULL);
        for (int round = 0; round < 3000; ++round) {
            visit_ctx c;
            memset(&c, 0, sizeof c);
            c.count = (size_t)(round % 7 == 0 ? 1 : round % 500);
            c.block_size = (size_t)(1 + round % 13);
            c.threads = threads[t];
            c.fail_at = round % 11 == 5 ? c.count / 2 : SIZE_MAX;
            c.visits = calloc(c.count + 1, sizeof *c.visits);
            int failed = resurfi_pool_for(pool, c.count, c.block_size, visit, &c);
            ck_assert_int_eq(failed, c.fail_at < c.count);
            for (size_t i = 0; i < c.count && c.fail_at == SIZE_MAX; ++i)
                ck_assert_msg(atomic_load(&c.visits[i]) == 1, "threads %u round %d: index %zu seen %d times",
                              threads[t], round, i, atomic_load(&c.visits[i]));
            ck_assert_int_eq(atomic_load(&c.bad_block), 0);
            ck_assert_int_eq(atomic_load(&c.bad_worker), 0);
            free(c.visits);
        }
        resurfi_pool_free(pool);
    }
}
END_TEST

/* A pool whose worker is kept off its core in mid-block (here it sleeps, as a thread that other processes took the
 * core from) while the caller waits for it goes on with its loops on the caller alone: the worker runs blocks in at
 * most STALLS_ALONE (2) loops, however many follow, and every index is still visited once. */
typedef struct stall_ctx {
    atomic_int *visits;
    atomic_int worker_blocks; /* blocks that a worker other than the caller ran in this loop */
} stall_ctx;

static int stall_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    stall_ctx *c = ctx;
    for (size_t i = begin; i < end; ++i)
        atomic_fetch_add(&c->visits[i], 1);
    if (worker != 0) {
        atomic_fetch_add(&c->worker_blocks, 1);
        usleep(200000); /* off its core for 200 ms: the caller's share (16 × 0.5 ms) is done long before, even
                           on a loaded machine, where each of its sleeps may last a few ms (20 ms was once not) */
    } else {
        usleep(500);
    }
    return 0;
}

START_TEST(pool_goes_alone_after_stalls)
{
    resurfi_pool *pool = NULL;
    ck_assert_int_eq(resurfi_pool_create(NULL, 2, NULL, &pool), RESURF_OK);
    ck_assert_ptr_nonnull(pool);
    enum { COUNT = 16, LOOPS = 40 };
    int loops_with_worker = 0;
    for (int loop = 0; loop < LOOPS; ++loop) {
        atomic_int visits[COUNT];
        for (int i = 0; i < COUNT; ++i)
            atomic_init(&visits[i], 0);
        stall_ctx c = {visits, 0};
        ck_assert_int_eq(resurfi_pool_for(pool, COUNT, 1, stall_block, &c), 0);
        for (int i = 0; i < COUNT; ++i)
            ck_assert_int_eq(atomic_load(&visits[i]), 1);
        loops_with_worker += atomic_load(&c.worker_blocks) > 0;
    }
    /* The worker woke in time for some loop (16 blocks of 0.5 ms leave it 8 ms), and each such loop stalled. */
    ck_assert_int_ge(loops_with_worker, 1);
    ck_assert_int_le(loops_with_worker, 2);
    resurfi_pool_free(pool);
}
END_TEST

START_TEST(parallel_thread_count)
{
    ck_assert_uint_ge(resurfi_thread_count(0), 1);
    ck_assert_uint_le(resurfi_thread_count(0), 256);
    ck_assert_uint_eq(resurfi_thread_count(1), 1);
    ck_assert_uint_eq(resurfi_thread_count(5), 5);
    ck_assert_uint_eq(resurfi_thread_count(1000), 256);
}
END_TEST

/* ---- the host's pool (resurf_thread_pool) ------------------------------------------------------------------ */

/* A small job system of the kind a game tool has: `workers` threads of its own take tasks of the current batch
 * from a shared index, and run() helps with them on the calling thread before it waits for the batch to end.
 * mode SERIAL runs every task on the calling thread in turn; mode LAZY starts none (resurf must finish alone). It
 * counts what it was asked to do and notes anything outside resurf_thread_pool's contract. */
typedef enum host_mode { HOST_THREADS, HOST_SERIAL, HOST_LAZY } host_mode;

typedef struct host_pool {
    host_mode mode;
    unsigned workers;
    pthread_t tid[8];
    pthread_t caller;  /* the thread that called resurf */
    pthread_mutex_t lock;
    pthread_cond_t work, idle;
    void (*task)(void *, unsigned);
    void *task_context;
    unsigned next, count, running; /* the batch: next task to hand out, its size, tasks in progress */
    int stop;
    int in_run;        /* a run() in progress (so a second one at once, or one from a task, is seen) */
    size_t runs, tasks, tasks_on_workers;
    unsigned max_count;
    int broken;        /* run called from another thread, nested or concurrently, or with no tasks */
} host_pool;

/* Takes and runs the batch's tasks until none is left to hand out; called with the lock held, returns with it. */
static void host_take_tasks(host_pool *h, int on_worker)
{
    while (h->next < h->count) {
        unsigned i = h->next++;
        h->running++;
        pthread_mutex_unlock(&h->lock);
        h->task(h->task_context, i);
        pthread_mutex_lock(&h->lock);
        h->running--;
        h->tasks++;
        h->tasks_on_workers += on_worker != 0;
    }
    if (h->running == 0)
        pthread_cond_broadcast(&h->idle);
}

static void *host_worker(void *p)
{
    host_pool *h = p;
    pthread_mutex_lock(&h->lock);
    for (;;) {
        while (!h->stop && h->next >= h->count)
            pthread_cond_wait(&h->work, &h->lock);
        if (h->stop)
            break;
        host_take_tasks(h, 1);
    }
    pthread_mutex_unlock(&h->lock);
    return NULL;
}

static void host_run(void *user, void (*task)(void *, unsigned), void *task_context, unsigned count)
{
    host_pool *h = user;
    pthread_mutex_lock(&h->lock);
    if (!pthread_equal(pthread_self(), h->caller) || h->in_run || count == 0)
        h->broken = 1;
    h->in_run = 1;
    h->runs++;
    h->max_count = count > h->max_count ? count : h->max_count;
    if (h->mode == HOST_LAZY) {
        h->in_run = 0;
        pthread_mutex_unlock(&h->lock);
        return;
    }
    h->task = task;
    h->task_context = task_context;
    h->next = 0;
    h->count = count;
    if (h->mode == HOST_THREADS)
        pthread_cond_broadcast(&h->work);
    host_take_tasks(h, 0);
    while (h->running > 0)
        pthread_cond_wait(&h->idle, &h->lock);
    h->in_run = 0;
    pthread_mutex_unlock(&h->lock);
}

static void host_start(host_pool *h, host_mode mode, unsigned workers)
{
    memset(h, 0, sizeof *h);
    h->mode = mode;
    h->caller = pthread_self();
    pthread_mutex_init(&h->lock, NULL);
    pthread_cond_init(&h->work, NULL);
    pthread_cond_init(&h->idle, NULL);
    for (unsigned w = 0; w < workers && mode == HOST_THREADS; ++w) {
        ck_assert_int_eq(pthread_create(&h->tid[w], NULL, host_worker, h), 0);
        h->workers = w + 1;
    }
}

static void host_stop(host_pool *h)
{
    pthread_mutex_lock(&h->lock);
    h->stop = 1;
    pthread_cond_broadcast(&h->work);
    pthread_mutex_unlock(&h->lock);
    for (unsigned w = 0; w < h->workers; ++w)
        pthread_join(h->tid[w], NULL);
    pthread_cond_destroy(&h->work);
    pthread_cond_destroy(&h->idle);
    pthread_mutex_destroy(&h->lock);
}

/* The threads of this process now (Linux: one entry per thread in /proc/self/task). */
static int thread_count(void)
{
    DIR *d = opendir("/proc/self/task");
    ck_assert_ptr_nonnull(d);
    int n = 0;
    for (struct dirent *e; (e = readdir(d));)
        n += e->d_name[0] != '.';
    closedir(d);
    return n;
}

/* The most threads seen by the simplifier's progress calls (made on the calling thread while its loops run). */
static bool most_threads(void *user, resurf_stage stage, double fraction)
{
    (void)stage;
    (void)fraction;
    int *most = user, n = thread_count();
    if (n > *most)
        *most = n;
    return false;
}

static void expect_same_mesh(const resurf_mesh *a, const resurf_mesh *b, const char *what)
{
    ck_assert_msg(a->vertex_count == b->vertex_count && a->triangle_count == b->triangle_count,
                  "%s: %zu/%zu vertices, %zu/%zu triangles", what, a->vertex_count, b->vertex_count,
                  a->triangle_count, b->triangle_count);
    ck_assert_msg(!memcmp(a->positions, b->positions, 3 * a->vertex_count * sizeof *a->positions), "%s: positions",
                  what);
    ck_assert_msg(!memcmp(a->indices, b->indices, 3 * a->triangle_count * sizeof *a->indices), "%s: indices", what);
    ck_assert(!a->normals == !b->normals);
    ck_assert_msg(!a->normals || !memcmp(a->normals, b->normals, 3 * a->vertex_count * sizeof *a->normals),
                  "%s: normals", what);
}

/* resurf_simplify_lods (two levels) with `threads` threads and the given host pool (NULL: resurf's own). */
static void simplify_with(const resurf_mesh *in, resurf_restore_mode restore, unsigned threads,
                          const resurf_thread_pool *pool, resurf_mesh *out[2], int *most)
{
    resurf_simplify_options o = resurf_simplify_options_default();
    resurf_restore_options ro = resurf_restore_options_default();
    ro.normals = RESURF_NORMALS_MAX; /* the jet fit starts threads of its own (resurf_thread_pool) */
    o.restore_options = &ro;
    o.restore = restore;
    o.threads = threads;
    o.thread_pool = pool;
    o.measure_samples = 5000;
    *most = thread_count();
    o.progress = (resurf_progress){most_threads, most};
    const double ratios[2] = {0.3, 0.05};
    resurf_error e;
    ck_assert_msg(resurf_simplify_lods(in, ratios, 2, &o, out, NULL, &e) == RESURF_OK, "%s", e.message);
}

/* The same levels, byte for byte, on the host's pool (threaded, serial, or starting no task), on resurf's own
 * threads and on one thread; with a pool resurf starts no thread, and every task index is below `threads`. The
 * torus of 8k triangles starts with chunks of about 60 candidates, which run on the threads (32 or more). */
START_TEST(host_pool_gives_the_same_bytes)
{
    resurf_mesh *in = shape_mesh(SHAPE_TORUS, 8000, 0.3, 7, 1);
    ck_assert_ptr_nonnull(in);
    const resurf_restore_mode modes[] = {RESURF_RESTORE_INLINE, RESURF_RESTORE_POST, RESURF_RESTORE_NONE};
    for (size_t m = 0; m < 3; ++m) {
        resurf_mesh *one[2], *own[2];
        int most_one, most_own;
        simplify_with(in, modes[m], 1, NULL, one, &most_one);
        simplify_with(in, modes[m], 4, NULL, own, &most_own);
        ck_assert_int_gt(most_own, thread_count()); /* resurf's own threads are seen (so the count can fail) */
        for (host_mode hm = HOST_THREADS; hm <= HOST_LAZY; ++hm) {
            host_pool h;
            host_start(&h, hm, 3);
            resurf_thread_pool pool = {host_run, &h};
            int before = thread_count(), most;
            resurf_mesh *got[2];
            simplify_with(in, modes[m], 4, &pool, got, &most);
            ck_assert_int_eq(most, before); /* no thread of resurf's */
            ck_assert_int_eq(h.broken, 0);
            ck_assert_uint_gt(h.runs, 10);
            ck_assert_uint_eq(h.max_count, 4);
            if (hm == HOST_THREADS)
                ck_assert_uint_gt(h.tasks_on_workers, 0);
            if (hm != HOST_LAZY)
                ck_assert_uint_eq(h.tasks, 4 * h.runs);
            for (int k = 0; k < 2; ++k) {
                expect_same_mesh(got[k], one[k], "host pool vs one thread");
                expect_same_mesh(got[k], own[k], "host pool vs resurf's threads");
                resurf_mesh_free(got[k]);
            }
            host_stop(&h);
        }
        for (int k = 0; k < 2; ++k) {
            resurf_mesh_free(one[k]);
            resurf_mesh_free(own[k]);
        }
    }
    resurf_mesh_free(in);
}
END_TEST

/* resurf_scene_build_lods passes its simplify options' pool on; with one thread the pool is not called; a pool
 * without run is refused. */
START_TEST(host_pool_in_scene_lods_and_options)
{
    resurf_mesh *in = shape_mesh(SHAPE_SPHERE, 3000, 0.2, 3, 0);
    const double ratios[2] = {0.5, 0.1};
    resurf_scene *mine = NULL, *theirs = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(in, &mine, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_scene_from_mesh(in, &theirs, NULL), RESURF_OK);
    host_pool h;
    host_start(&h, HOST_THREADS, 2);
    resurf_thread_pool pool = {host_run, &h};
    resurf_simplify_options o = resurf_simplify_options_default();
    o.threads = 3;
    ck_assert_int_eq(resurf_scene_build_lods(theirs, ratios, 2, &o, NULL, NULL, NULL, NULL), RESURF_OK);
    o.thread_pool = &pool;
    ck_assert_int_eq(resurf_scene_build_lods(mine, ratios, 2, &o, NULL, NULL, NULL, NULL), RESURF_OK);
    ck_assert_uint_gt(h.runs, 0);
    ck_assert_int_eq(h.broken, 0);
    for (int k = 0; k < 2; ++k)
        expect_same_mesh(mine->prims[0].lods[k], theirs->prims[0].lods[k], "scene level");
    size_t runs = h.runs;
    resurf_mesh *out = NULL;
    o.threads = 1;
    ck_assert_int_eq(resurf_simplify(in, &o, &out, NULL, NULL), RESURF_OK);
    ck_assert_uint_eq(h.runs, runs);
    resurf_mesh_free(out);
    resurf_thread_pool no_run = {NULL, &h};
    o.thread_pool = &no_run;
    resurf_error e;
    ck_assert_int_eq(resurf_simplify(in, &o, &out, NULL, &e), RESURF_ERR_INVALID_OPTIONS);
    ck_assert_str_eq(e.message, "resurf_simplify_options: thread_pool has no run callback");
    ck_assert_ptr_null(out);
    host_stop(&h);
    resurf_scene_free(mine);
    resurf_scene_free(theirs);
    resurf_mesh_free(in);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("parallel");
    TCase *tc = tcase_create("loops");
    tcase_add_test(tc, parallel_visits_every_index_once);
    tcase_add_test(tc, parallel_stops_after_failure_single_thread);
    tcase_add_test(tc, parallel_stops_after_failure_many_threads);
    tcase_add_test(tc, parallel_results_independent_of_threads);
    tcase_add_test(tc, pool_runs_many_loops);
    tcase_add_test(tc, pool_goes_alone_after_stalls);
    tcase_add_test(tc, parallel_thread_count);
    suite_add_tcase(s, tc);
    TCase *host = tcase_create("host");
    tcase_add_test(host, host_pool_gives_the_same_bytes);
    tcase_add_test(host, host_pool_in_scene_lods_and_options);
    suite_add_tcase(s, host);
    return s;
}

RESURF_TEST_MAIN()
