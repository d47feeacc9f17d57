/* src/parallel.c: every index visited exactly once in well-formed blocks for any count, block size and thread
 * count, and an early stop once a block fails; the same of a pool, loop after loop. */
#include <stdatomic.h>
#include <string.h>

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
        ck_assert_int_eq(resurfi_pool_create(NULL, t, &pool), RESURF_OK);
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
        ck_assert_int_eq(resurfi_pool_create(NULL, threads[t], &pool), RESURF_OK);
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

START_TEST(parallel_thread_count)
{
    ck_assert_uint_ge(resurfi_thread_count(0), 1);
    ck_assert_uint_le(resurfi_thread_count(0), 256);
    ck_assert_uint_eq(resurfi_thread_count(1), 1);
    ck_assert_uint_eq(resurfi_thread_count(5), 5);
    ck_assert_uint_eq(resurfi_thread_count(1000), 256);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("parallel");
    TCase *tc = tcase_create("parallel");
    tcase_add_test(tc, parallel_visits_every_index_once);
    tcase_add_test(tc, parallel_stops_after_failure_single_thread);
    tcase_add_test(tc, parallel_stops_after_failure_many_threads);
    tcase_add_test(tc, parallel_results_independent_of_threads);
    tcase_add_test(tc, pool_runs_many_loops);
    tcase_add_test(tc, parallel_thread_count);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
