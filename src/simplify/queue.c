/* The candidate queue (queue.h): the two radix sorts, the refresh between passes and its two-part merge. */
#include <string.h>

#include "queue.h"

#define NONE UINT32_MAX

/* Cost order as unsigned order: flip the sign bit of a non-negative float, every bit of a negative one (a cost a
 * rounding made slightly negative). */
static uint32_t cost_key(float cost)
{
    uint32_t u;
    memcpy(&u, &cost, sizeof u);
    return u & 0x80000000u ? ~u : u | 0x80000000u;
}

/* Sorts the first list of n candidates by cost, in place: a buffer as large as the list would be the simplifier's
 * second largest array, at the time the restorer's memory is taken too. A radix sort from the most significant byte
 * down, each bucket permuted in place (the "American flag" sort), small buckets by insertion. Equal costs end in an
 * order that depends on the input order only, never on the thread count. */
static void sort_in_place(candidate *c, size_t n, int shift)
{
    if (n <= 32) {
        for (size_t i = 1; i < n; ++i) {
            candidate x = c[i];
            uint32_t k = cost_key(x.cost);
            size_t j = i;
            for (; j > 0 && cost_key(c[j - 1].cost) > k; --j)
                c[j] = c[j - 1];
            c[j] = x;
        }
        return;
    }
    size_t count[256] = {0}, next[256], end[256];
    for (size_t i = 0; i < n; ++i)
        count[(cost_key(c[i].cost) >> shift) & 255]++;
    size_t sum = 0;
    for (int b = 0; b < 256; ++b) {
        next[b] = sum;
        sum += count[b];
        end[b] = sum;
    }
    for (int b = 0; b < 256; ++b)
        while (next[b] < end[b]) {
            candidate x = c[next[b]];
            unsigned d = (cost_key(x.cost) >> shift) & 255;
            while (d != (unsigned)b) { /* put x in its bucket, carry on with what was there */
                candidate y = c[next[d]];
                c[next[d]++] = x;
                x = y;
                d = (cost_key(x.cost) >> shift) & 255;
            }
            c[next[b]++] = x;
        }
    if (shift > 0)
        for (int b = 0; b < 256; ++b)
            if (count[b] > 1)
                sort_in_place(c + end[b] - count[b], count[b], shift - 8);
}

/* A stable merge sort of the n candidates of `from` by cost, `to` as the second buffer: runs of RUN sorted by
 * insertion, then merged in pairs from one buffer to the other. Returns the buffer that holds the result. */
enum { RUN = 16 };

static candidate *merge_sort_stable(candidate *from, candidate *to, size_t n)
{
    for (size_t lo = 0; lo < n; lo += RUN) {
        size_t hi = lo + RUN < n ? lo + RUN : n;
        for (size_t i = lo + 1; i < hi; ++i) {
            candidate x = from[i];
            uint32_t k = cost_key(x.cost);
            size_t j = i;
            for (; j > lo && cost_key(from[j - 1].cost) > k; --j)
                from[j] = from[j - 1];
            from[j] = x;
        }
    }
    for (size_t width = RUN; width < n; width *= 2) {
        for (size_t lo = 0; lo < n; lo += 2 * width) {
            size_t mid = lo + width < n ? lo + width : n, hi = lo + 2 * width < n ? lo + 2 * width : n;
            size_t a = lo, b = mid, o = lo;
            while (a < mid && b < hi) /* on equal keys the left run's first: stable */
                to[o++] = cost_key(from[b].cost) < cost_key(from[a].cost) ? from[b++] : from[a++];
            while (a < mid)
                to[o++] = from[a++];
            while (b < hi)
                to[o++] = from[b++];
        }
        candidate *t = from;
        from = to;
        to = t;
    }
    return from;
}

/* Sorts the n candidates of `from` by cost, stably, with `to` (n entries) as the second buffer: a radix sort from
 * the least significant of three 11-bit digits of the cost's key up, a digit all keys share skipped; below
 * MERGE_BELOW candidates a merge sort, since the radix sort's 3 x 2048 counters cost more than sorting a few
 * hundred (the refresh between passes sorts the fresh candidates of a pass: on 2CylinderEngine 2,305 sorts of at
 * most 1,024, 56 on average, whose counters were 2.7% of a `resurf lod` call's instructions). Measured on random
 * costs (ns per candidate, radix / merge): 16: 826 / 33, 64: 175 / 36, 256: 88 / 63, 512: 55-68 / 56-76, 1024:
 * 41-47 / 71-106, 4096: 42-51 / 274-316. Returns the buffer that holds the result. Stable, so equal costs keep
 * the order of the pass that planned them. */
#define MERGE_BELOW 512

static candidate *sort_stable(candidate *from, candidate *to, size_t n)
{
    if (n < MERGE_BELOW)
        return merge_sort_stable(from, to, n);
    enum { BITS = 11, BUCKETS = 1 << BITS };
    size_t count[3][BUCKETS];
    memset(count, 0, sizeof count);
    for (size_t i = 0; i < n; ++i) {
        uint32_t k = cost_key(from[i].cost);
        count[0][k & (BUCKETS - 1)]++;
        count[1][(k >> BITS) & (BUCKETS - 1)]++;
        count[2][k >> 2 * BITS]++;
    }
    for (int d = 0; d < 3 && n > 0; ++d) {
        int shift = d * BITS;
        if (count[d][(cost_key(from[0].cost) >> shift) & (BUCKETS - 1)] == n)
            continue;
        size_t sum = 0;
        for (size_t b = 0; b < BUCKETS; ++b) {
            size_t c = count[d][b];
            count[d][b] = sum;
            sum += c;
        }
        for (size_t i = 0; i < n; ++i)
            to[count[d][(cost_key(from[i].cost) >> shift) & (BUCKETS - 1)]++] = from[i];
        candidate *t = from;
        from = to;
        to = t;
    }
    return from;
}


int simp_queue_reserve(simp_queue *q, size_t n)
{
    if (n <= q->list.cap)
        return 1;
    size_t cap = n + n / 8 + 64;
    candidate *c = resurfi_realloc(q->alloc, q->list.data, cap, sizeof *c);
    if (!c)
        return 0;
    q->list.data = c;
    q->list.cap = cap;
    return 1;
}

void simp_queue_seed(simp_queue *q, size_t n)
{
    candidate *c = q->list.data;
    size_t kept = 0;
    for (size_t i = 0; i < n; ++i)
        if (c[i].a != NONE)
            c[kept++] = c[i];
    sort_in_place(c, kept, 24);
    q->list.count = kept;
}

int simp_buf_append(const resurf_allocator *alloc, candidate_buf *buf, const candidate *c, size_t n)
{
    if (n == 0)
        return 1;
    if (buf->count + n > buf->cap) {
        size_t want = buf->cap ? 2 * buf->cap : 1024;
        want = want < buf->count + n ? buf->count + n : want;
        candidate *f = resurfi_realloc(alloc, buf->data, want, sizeof *f);
        if (!f)
            return 0;
        buf->data = f;
        buf->cap = want;
    }
    memcpy(buf->data + buf->count, c, n * sizeof *c);
    buf->count += n;
    return 1;
}

/* The list for the next pass: the current candidates keep their places (their ends' quadrics and flags, hence
 * their costs, are the same); those planned during the pass are sorted and merged in. Three jobs, on the pool's
 * threads: each half of the list keeps its current candidates at its front, and the fresh ones are filtered and
 * sorted; then the second half's move down to meet the first's, and the sorted fresh ones are merged in from the
 * back. */
typedef struct refresh_job {
    simp_queue *q;
    const uint32_t *gen;
    size_t half;         /* where the second half of the list starts */
    size_t kept[2];      /* current candidates of each half */
    size_t fresh_kept;
    const candidate *sorted; /* the current fresh ones, sorted (in q->fresh or q->sorted) */
} refresh_job;

/* Moves the current ones of the n candidates of c to its front; returns how many. */
static size_t keep_current(const uint32_t *gen, candidate *c, size_t n)
{
    size_t kept = 0;
    for (size_t i = 0; i < n; ++i) {
        if (i + 16 < n && c[i + 16].a != NONE) {
            PREFETCH(&gen[c[i + 16].a]);
            PREFETCH(&gen[c[i + 16].b]);
        }
        if (simp_candidate_current(gen, c[i]))
            c[kept++] = c[i];
    }
    return kept;
}

static int refresh_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    refresh_job *j = ctx;
    simp_queue *q = j->q;
    for (size_t job = begin; job < end; ++job) {
        if (job == 2) {
            j->fresh_kept = keep_current(j->gen, q->fresh.data, q->fresh.count);
            j->sorted = sort_stable(q->fresh.data, q->sorted, j->fresh_kept);
        } else {
            size_t lo = job == 0 ? 0 : j->half, hi = job == 0 ? j->half : q->list.count;
            /* (an empty list may have no buffer: no pointer arithmetic on NULL) */
            j->kept[job] = hi > lo ? keep_current(j->gen, q->list.data + lo, hi - lo) : 0;
        }
    }
    return 0;
}

/* The merge, in two jobs: the new list's first K candidates are the list's first I and the fresh ones' first
 * K - I (merge_split). Each part merges from the back into its own places, in place. The lower part writes over
 * [I, K) of the list, which the upper part reads: those go to a copy first (`spare`). */
typedef struct merge_job {
    candidate *list;
    const candidate *fresh;
    candidate *spare;
    size_t n, m, i, k; /* list and fresh counts; the split */
} merge_job;

/* The largest i in [k - m, k] (within [0, n]) whose c[i - 1] goes before f[k - i]: the merge's first k candidates
 * are c[0, i) and f[0, k - i). On equal costs the older candidate (the list's) comes first. */
static size_t merge_split(const candidate *c, size_t n, const candidate *f, size_t m, size_t k)
{
    size_t lo = k > m ? k - m : 0, hi = k < n ? k : n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo + 1) / 2;
        if (k - mid == m || c[mid - 1].cost <= f[k - mid].cost)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

static int merge_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    const merge_job *j = ctx;
    candidate *c = j->list;
    const candidate *f = j->fresh;
    for (size_t part = begin; part < end; ++part) {
        if (part == 0) { /* the lower part: c[0, i) and f[0, k - i) into [0, k) */
            size_t i = j->i, jf = j->k - j->i, k = j->k;
            while (jf > 0) {
                if (i > 0 && c[i - 1].cost > f[jf - 1].cost)
                    c[--k] = c[--i];
                else
                    c[--k] = f[--jf];
            }
            continue;
        }
        /* the upper part: c[i, n) (its [i, k) from the copy) and f[k - i, m) into [k, n + m) */
        size_t i = j->n, jf = j->m, k = j->n + j->m, jend = j->k - j->i;
        while (i > j->i) {
            const candidate *x = i - 1 >= j->k ? &c[i - 1] : &j->spare[i - 1 - j->i];
            if (jf > jend && f[jf - 1].cost >= x->cost)
                c[--k] = f[--jf];
            else
                c[--k] = *x, --i;
        }
        while (jf > jend)
            c[--k] = f[--jf];
    }
    return 0;
}

int simp_queue_refresh(simp_queue *q, const uint32_t *gen, resurfi_pool *pool)
{
    if (q->fresh.count > q->sorted_cap) {
        candidate *buf = resurfi_realloc(q->alloc, q->sorted, q->fresh.cap, sizeof *buf);
        if (!buf)
            return 0;
        q->sorted = buf;
        q->sorted_cap = q->fresh.cap;
    }
    refresh_job j = {.q = q, .gen = gen, .half = q->list.count / 2};
    resurfi_pool_for(pool, 3, 1, refresh_block, &j);
    size_t n = j.kept[0] + j.kept[1], m = j.fresh_kept;
    if (j.kept[1])
        memmove(q->list.data + j.kept[0], q->list.data + j.half, j.kept[1] * sizeof *q->list.data);
    if (!simp_queue_reserve(q, n + m))
        return 0;
    merge_job mj = {q->list.data, j.sorted, j.sorted == q->fresh.data ? q->sorted : q->fresh.data, n, m, 0,
                    (n + m) / 2};
    mj.i = merge_split(q->list.data, n, j.sorted, m, mj.k);
    size_t copied = (mj.k < n ? mj.k : n) - mj.i; /* at most k - i <= m: the spare buffer holds as many as fresh */
    if (copied)
        memcpy(mj.spare, q->list.data + mj.i, copied * sizeof *q->list.data);
    resurfi_pool_for(pool, 2, 1, merge_block, &mj);
    q->list.count = n + m;
    q->fresh.count = 0;
    return 1;
}

void simp_queue_free(simp_queue *q)
{
    resurfi_free(q->alloc, q->list.data);
    resurfi_free(q->alloc, q->fresh.data);
    resurfi_free(q->alloc, q->sorted);
    const resurf_allocator *alloc = q->alloc;
    memset(q, 0, sizeof *q);
    q->alloc = alloc;
}
