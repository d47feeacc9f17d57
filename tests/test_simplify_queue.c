/* src/simplify/queue.c, the simplifier's candidate queue, against a plain model: the first list comes out sorted
 * with every entry kept but the empty slots; a refresh keeps exactly the current candidates, keeps equal costs in
 * the order they were added in (the list's before the fresh ones), and its two-part parallel merge gives what one
 * plain sort of (cost, list before fresh, place) gives, on random input, for any thread count. */
#include <stdlib.h>
#include <string.h>

#include "simplify/queue.h"
#include "testutil.h"

#define NONE UINT32_MAX

/* A deterministic pseudo-random sequence (xorshift64*). */
static uint64_t next_random(uint64_t *state)
{
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    return *state * 0x2545f4914f6cdd1dull;
}

/* A cost from a small set, so that ties are common; some negative (a rounding can make a cost slightly negative),
 * some large. */
static float random_cost(uint64_t *state)
{
    static const float costs[] = {-2.5f, -1e-7f, 1e-30f, 0.125f, 0.5f, 1, 1, 3, 7.75f, 1e20f, 3.4e38f};
    return costs[next_random(state) % (sizeof costs / sizeof *costs)];
}

static int same_candidate(candidate x, candidate y)
{
    return x.cost == y.cost && x.a == y.a && x.b == y.b && x.stamp == y.stamp;
}

/* The model's entry: a candidate, whether it came from the fresh ones, and its place there. */
typedef struct model_entry {
    candidate c;
    int fresh;
    size_t place;
} model_entry;

static int model_cmp(const void *p, const void *q)
{
    const model_entry *x = p, *y = q;
    if (x->c.cost != y->c.cost)
        return x->c.cost < y->c.cost ? -1 : 1;
    if (x->fresh != y->fresh)
        return x->fresh - y->fresh;
    return x->place < y->place ? -1 : x->place > y->place;
}

static int by_cost_then_ends(const void *p, const void *q)
{
    const candidate *x = p, *y = q;
    if (x->cost != y->cost)
        return x->cost < y->cost ? -1 : 1;
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    return x->b < y->b ? -1 : x->b > y->b;
}

START_TEST(queue_seed_sorts_and_drops_empty_slots)
{
    uint64_t state = 0x9e3779b97f4a7c15ull;
    const size_t sizes[] = {0, 1, 2, 31, 33, 1000, 70000};
    for (size_t k = 0; k < sizeof sizes / sizeof *sizes; ++k) {
        size_t n = sizes[k];
        simp_queue q = {0};
        ck_assert(simp_queue_reserve(&q, n));
        candidate *expected = malloc((n + 1) * sizeof *expected);
        size_t kept = 0;
        for (size_t i = 0; i < n; ++i) {
            /* wide costs too, so that every byte of the radix sort's keys varies */
            float cost = i % 3 ? random_cost(&state) : (float)(next_random(&state) % 1000000) * 1e-3f;
            candidate c = {cost, (uint32_t)i, (uint32_t)(i + 1), 0};
            if (next_random(&state) % 5 == 0)
                c.a = NONE; /* an empty slot */
            q.list.data[i] = c;
            if (c.a != NONE)
                expected[kept++] = c;
        }
        simp_queue_seed(&q, n);
        ck_assert_uint_eq(q.list.count, kept);
        for (size_t i = 1; i < kept; ++i)
            ck_assert(q.list.data[i - 1].cost <= q.list.data[i].cost);
        /* the same candidates: equal as sets once both are ordered by (cost, ends) */
        if (kept) { /* (an empty list may have no buffer) */
            qsort(q.list.data, kept, sizeof *q.list.data, by_cost_then_ends);
            qsort(expected, kept, sizeof *expected, by_cost_then_ends);
        }
        for (size_t i = 0; i < kept; ++i)
            ck_assert(same_candidate(q.list.data[i], expected[i]));
        free(expected);
        simp_queue_free(&q);
    }
}
END_TEST

START_TEST(queue_refresh_is_stable_on_equal_costs)
{
    /* Candidate i is (i, i) with stamp 0 over generations 0: all current, and a gives the order of adding. Few
     * distinct costs: long runs of equal ones. */
    uint64_t state = 12345;
    const size_t n = 50000, added = 3000;
    uint32_t *gen = calloc(n + added, sizeof *gen);
    simp_queue q = {0};
    for (size_t i = 0; i < n; ++i) {
        candidate c = {random_cost(&state), (uint32_t)i, (uint32_t)i, 0};
        ck_assert(simp_buf_append(NULL, &q.fresh, &c, 1));
    }
    ck_assert(simp_queue_refresh(&q, gen, NULL));
    ck_assert_uint_eq(q.list.count, n);
    ck_assert_uint_eq(q.fresh.count, 0);
    for (size_t i = 1; i < n; ++i) {
        candidate x = q.list.data[i - 1], y = q.list.data[i];
        ck_assert(x.cost <= y.cost);
        if (x.cost == y.cost)
            ck_assert_uint_lt(x.a, y.a); /* the order of adding */
    }
    /* more fresh ones of the same costs: on each cost the list's come first, then the new ones in their order */
    for (size_t i = n; i < n + added; ++i) {
        candidate c = {random_cost(&state), (uint32_t)i, (uint32_t)i, 0};
        ck_assert(simp_buf_append(NULL, &q.fresh, &c, 1));
    }
    ck_assert(simp_queue_refresh(&q, gen, NULL));
    ck_assert_uint_eq(q.list.count, n + added);
    for (size_t i = 1; i < n + added; ++i) {
        candidate x = q.list.data[i - 1], y = q.list.data[i];
        ck_assert(x.cost <= y.cost);
        if (x.cost == y.cost)
            ck_assert_uint_lt(x.a, y.a);
    }
    free(gen);
    simp_queue_free(&q);
}
END_TEST

START_TEST(queue_refresh_drops_stale_entries)
{
    uint64_t state = 777;
    enum { POSITIONS = 200, LIST = 3000, FRESH = 2000 };
    uint32_t gen[POSITIONS] = {0};
    for (int p = 0; p < POSITIONS; ++p)
        gen[p] = (uint32_t)(next_random(&state) % 5);
    simp_queue q = {0};
    ck_assert(simp_queue_reserve(&q, LIST));
    for (size_t i = 0; i < LIST; ++i) {
        uint32_t a = (uint32_t)(next_random(&state) % POSITIONS), b = (uint32_t)(next_random(&state) % POSITIONS);
        q.list.data[i] = (candidate){random_cost(&state), a, b, (gen[a] + gen[b]) & SIMP_GEN};
    }
    simp_queue_seed(&q, LIST);
    for (size_t i = 0; i < FRESH; ++i) {
        uint32_t a = (uint32_t)(next_random(&state) % POSITIONS), b = (uint32_t)(next_random(&state) % POSITIONS);
        candidate c = {random_cost(&state), a, b, (gen[a] + gen[b]) & SIMP_GEN};
        ck_assert(simp_buf_append(NULL, &q.fresh, &c, 1));
    }
    /* a fifth of the positions change, and some candidates are taken up */
    for (int p = 0; p < POSITIONS; p += 5)
        gen[p]++;
    for (size_t i = 0; i < LIST; i += 7)
        q.list.data[i].a = NONE;
    for (size_t i = 0; i < FRESH; i += 11)
        q.fresh.data[i].a = NONE;
    size_t current = 0;
    for (size_t i = 0; i < LIST + FRESH; ++i) {
        candidate c = i < LIST ? q.list.data[i] : q.fresh.data[i - LIST];
        current += c.a != NONE && ((gen[c.a] + gen[c.b]) & SIMP_GEN) == c.stamp;
    }
    ck_assert_uint_gt(current, 0);
    ck_assert_uint_lt(current, LIST + FRESH);
    ck_assert(simp_queue_refresh(&q, gen, NULL));
    ck_assert_uint_eq(q.list.count, current);
    for (size_t i = 0; i < q.list.count; ++i) {
        candidate c = q.list.data[i];
        ck_assert_uint_ne(c.a, NONE);
        ck_assert_uint_eq((gen[c.a] + gen[c.b]) & SIMP_GEN, c.stamp);
    }
    simp_queue_free(&q);
}
END_TEST

/* One refresh of a random list and random fresh ones (some stale) on `pool`, against the model. */
static void check_merge(resurfi_pool *pool, uint64_t seed, size_t list, size_t fresh)
{
    uint64_t state = seed;
    enum { POSITIONS = 500 };
    uint32_t gen[POSITIONS];
    for (int p = 0; p < POSITIONS; ++p)
        gen[p] = (uint32_t)(next_random(&state) % 3);
    simp_queue q = {0};
    ck_assert(simp_queue_reserve(&q, list));
    for (size_t i = 0; i < list; ++i) {
        uint32_t a = (uint32_t)(next_random(&state) % POSITIONS), b = (uint32_t)(next_random(&state) % POSITIONS);
        q.list.data[i] = (candidate){random_cost(&state), a, b, (gen[a] + gen[b]) & SIMP_GEN};
    }
    simp_queue_seed(&q, list);
    for (size_t i = 0; i < fresh; ++i) {
        uint32_t a = (uint32_t)(next_random(&state) % POSITIONS), b = (uint32_t)(next_random(&state) % POSITIONS);
        candidate c = {random_cost(&state), a, b, (gen[a] + gen[b]) & SIMP_GEN};
        ck_assert(simp_buf_append(NULL, &q.fresh, &c, 1));
    }
    for (int p = 0; p < POSITIONS; p += 9)
        gen[p]++;
    /* the model: the current candidates, sorted by (cost, list before fresh, place) */
    model_entry *model = malloc((list + fresh + 1) * sizeof *model);
    size_t m = 0;
    for (size_t i = 0; i < q.list.count; ++i)
        if (simp_candidate_current(gen, q.list.data[i]))
            model[m++] = (model_entry){q.list.data[i], 0, i};
    for (size_t i = 0; i < q.fresh.count; ++i)
        if (simp_candidate_current(gen, q.fresh.data[i]))
            model[m++] = (model_entry){q.fresh.data[i], 1, i};
    qsort(model, m, sizeof *model, model_cmp);
    ck_assert(simp_queue_refresh(&q, gen, pool));
    ck_assert_uint_eq(q.list.count, m);
    for (size_t i = 0; i < m; ++i)
        ck_assert_msg(same_candidate(q.list.data[i], model[i].c), "list %zu fresh %zu: entry %zu differs", list,
                      fresh, i);
    free(model);
    simp_queue_free(&q);
}

START_TEST(queue_merge_equals_plain_merge)
{
    const size_t lists[] = {0, 1, 2, 17, 1000, 30000};
    const size_t freshes[] = {0, 1, 3, 40, 300, 511, 512, 999, 20000}; /* merge sort below 512, radix above */
    const unsigned threads[] = {1, 2, 3};
    uint64_t seed = 1;
    for (size_t t = 0; t < sizeof threads / sizeof *threads; ++t) {
        resurfi_pool *pool = NULL;
        ck_assert_int_eq(resurfi_pool_create(NULL, threads[t], NULL, &pool), RESURF_OK);
        for (size_t i = 0; i < sizeof lists / sizeof *lists; ++i)
            for (size_t j = 0; j < sizeof freshes / sizeof *freshes; ++j)
                check_merge(pool, seed++, lists[i], freshes[j]);
        resurfi_pool_free(pool);
    }
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("simplify_queue");
    TCase *tc = tcase_create("queue");
    tcase_add_test(tc, queue_seed_sorts_and_drops_empty_slots);
    tcase_add_test(tc, queue_refresh_is_stable_on_equal_costs);
    tcase_add_test(tc, queue_refresh_drops_stale_entries);
    tcase_add_test(tc, queue_merge_equals_plain_merge);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
