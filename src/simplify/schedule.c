/* The scheduler: passes over the candidate queue, taken in chunks, each chunk's collapses applied on all threads
 * (when their closed stars are disjoint) or one after the other. The only file of the collapse loop that knows
 * about threads: windows of candidates whose stars are gathered ahead on all threads, the claims that keep a
 * chunk's stars disjoint, the workers' lanes and their merge in the chunk's order, and the prefetches that walk
 * ahead of the work. guards.h states what a collapse of a chunk may read and write.
 *
 * A pass is taken in chunks of up to CHUNK candidates with disjoint closed stars (an end and its neighbours): a
 * collapse reads and writes its star's positions and its ends' triangles only, so the chunk's collapses are
 * applied on all threads, each as if alone, and their results merged in the chunk's order; the edges of renewed
 * neighbours, which reach outside the star, are planned after the chunk. Near the target (when the chunk could
 * remove all the triangles left above it) the chunk is applied one collapse after the other, stopping at the
 * target, with inline restoration planned and restored on all threads first; so are the chunks of passes whose
 * chunks are too small for threads, without stars (star_pass). Which way a chunk goes depends on the counts only:
 * the result is the same for every thread count. Finding the stars costs about 30% more work in all (so one thread
 * is that much slower); measured on a 1M torus at 10% with 2 threads on a quiet 2-core machine, three runs each:
 * none 1.75–1.82 -> 1.38–1.53 s, inline 2.84–2.90 -> 2.41–2.49 s. On a machine busy with other jobs the medians
 * lose (a fork-join per chunk waits for a descheduled thread). */
#include "simplify_internal.h"

/* A pass of collapse_until goes up to the cost of the candidate at PASS_SHARE of the sorted list. Measured with
 * bench_simplify on the 20k analytic shapes at 10% and 2%: at 0.05 the distances to the true surface are those of
 * one collapse at a time (the order of a binary heap) within ±1%, at 0.25 within 3%, at 1 up to 6% worse; the time
 * on 1M triangles hardly changes (most of a pass's cost is per collapse, not per pass). */
static const double PASS_SHARE = 0.05;

typedef struct chunk_job {
    simplifier *s;
    scratch *scratch;
} chunk_job;

/* Plans the chunk's candidates and restores their placements, on all threads (inline restoration). Each reads the
 * mesh only; collapse_until applies them afterwards, one after the other, planning each again. */
static int restore_chunk_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    chunk_job *j = ctx;
    simplifier *s = j->s;
    schedule *S = &s->sched;
    scratch *sc = &j->scratch[worker];
    for (size_t i = begin; i < end; ++i) {
        pending *q = &S->pend[i];
        candidate c = s->queue.list.data[q->index];
        for (size_t k = 1; k <= 3 && i + k < end; ++k)
            prefetch_walk(s, s->queue.list.data[S->pend[i + k].index].a, k);
        q->restore = 0;
        if (!gather_fan(s, c.a, &sc->fan, 0))
            return 1;
        plan pl;
        plan_collapse(s, c.a, c.b, &sc->fan, &pl);
        if (pl.block != BLOCK_NONE || pl.pinned || pl.feature || pl.curve)
            continue;
        int left;
        q->p = pl.p;
        q->restored = restore_point(s, pl.p, v3_dist(s->P[c.a].p, s->P[c.b].p), s->home[c.a], &left, &q->home);
        q->left = (uint8_t)left;
        q->restore = 1;
    }
    return 0;
}

/* Adds lane L's counters to the simplifier's and clears them (its fresh candidates are the caller's business). */
static void merge_lane_counts(simplifier *s, lane *L)
{
    resurf_simplify_report *r = &s->rep, *l = &L->rep;
    r->collapses += l->collapses;
    r->blocked_link += l->blocked_link;
    r->blocked_flip += l->blocked_flip;
    r->blocked_min_angle += l->blocked_min_angle;
    r->blocked_distance += l->blocked_distance;
    r->blocked_border += l->blocked_border;
    r->blocked_seam += l->blocked_seam;
    r->blocked_feature += l->blocked_feature;
    r->blocked_nonmanifold += l->blocked_nonmanifold;
    r->skipped_error += l->skipped_error;
    r->restored += l->restored;
    r->restore_left += l->restore_left;
    if (l->max_error_estimate > r->max_error_estimate)
        r->max_error_estimate = l->max_error_estimate;
    memset(l, 0, sizeof *l);
    s->alive_tris -= L->dead_tris;
    s->alive_positions -= L->dead_positions;
    L->dead_tris = L->dead_positions = 0;
    s->skipped_error |= L->skipped_error;
    L->skipped_error = 0;
}

/* Moves lane L's fresh candidates to the simplifier's, with its counters; 0 when out of memory. */
int merge_lane(simplifier *s, lane *L)
{
    merge_lane_counts(s, L);
    int ok = simp_buf_append(s->alloc, &s->queue.fresh, L->fresh.data, L->fresh.count);
    L->fresh.count = 0;
    return ok;
}

/* Threads for a chunk's parallel steps (the result is the same for any number), and their pool (NULL: the calling
 * thread alone). */
static unsigned chunk_threads(const simplifier *s) { return s->sched.chunk >= CHUNK_THREADS ? s->threads : 1; }
static resurfi_pool *chunk_pool(const simplifier *s) { return chunk_threads(s) > 1 ? s->pool : NULL; }

/* Whether this pass's chunks are of disjoint stars, applied in parallel. Chunks too small to be worth threads are
 * applied one collapse after the other, which needs no stars (gathering them was 7% of the time on a 20k sphere,
 * perf). Like the chunk size, a choice by counts only. */
static int star_pass(const simplifier *s) { return s->sched.chunk >= CHUNK_THREADS; }

/* Opens a pass: the list brought up to date and the pass's cost limit. Returns 0 when out of memory. */
int open_pass(simplifier *s)
{
    schedule *S = &s->sched;
    if (!simp_queue_refresh(&s->queue, s->gen, s->pool))
        return 0;
    S->pass_open = s->queue.list.count > 0;
    S->pass_next = 0;
    S->pass_before = s->rep.collapses;
    /* Stars of a chunk must be disjoint: the more of the mesh a chunk would cover, the more of its window's stars
     * meet claimed ones and are gathered again for the next chunk (on 20k triangles, chunks of 1024 made gathering
     * stars a sixth of the time). The size depends on the counts only, as the result must. */
    size_t chunk = s->alive_positions / CHUNK_SPREAD;
    S->chunk = chunk < CHUNK_MIN ? CHUNK_MIN : chunk > CHUNK ? CHUNK : chunk;
    S->window = S->chunk * WINDOW / CHUNK;
    if (S->pass_open) {
        size_t nth = (size_t)((double)s->queue.list.count * PASS_SHARE);
        nth = nth < 1 ? 1 : nth;
        S->pass_limit = s->queue.list.data[nth - 1].cost;
    }
    return 1;
}

/* Fills words[]: a's corners, b's corners, then the star's positions (a, b and the other two corners of each
 * corner's triangle: most positions twice, which costs the claims less than sorting them out here costs the
 * gathering); returns the position count, or STAR_OVERFLOW when they may not fit in max words. Reads the mesh
 * only. */
static uint32_t gather_star(const simplifier *s, candidate c, const u32vec *fan_a, const u32vec *fan_b,
                            uint32_t *words, size_t max)
{
    size_t na = fan_a->count, nb = fan_b->count;
    if (3 * (na + nb) + 2 > max)
        return STAR_OVERFLOW;
    if (na)
        memcpy(words, fan_a->data, na * sizeof *words);
    if (nb)
        memcpy(words + na, fan_b->data, nb * sizeof *words);
    uint32_t *star = words + na + nb;
    uint32_t n = 0;
    star[n++] = c.a;
    star[n++] = c.b;
    for (size_t k = 0; k < na + nb; ++k) { /* claim_candidate marks each position once */
        corner_others(s, words[k], star + n);
        n += 2;
    }
    return n;
}

/* Gathers window entries [begin, end) (in parallel: nothing writes the mesh meanwhile), GATHER_GROUP candidates'
 * fans at a time. */
static int star_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    chunk_job *j = ctx;
    simplifier *s = j->s;
    schedule *S = &s->sched;
    scratch *sc = &j->scratch[worker];
    for (size_t k = begin; k < end;) {
        size_t group[GATHER_GROUP], n = 0;
        uint32_t ends[2 * GATHER_GROUP];
        for (; k < end && n < GATHER_GROUP; ++k) {
            window_entry *e = &S->win[k];
            candidate c = s->queue.list.data[e->index];
            e->count = 0;
            if (c.a == NONE || ((s->gen[c.a] | s->gen[c.b]) & TAKEN) || !candidate_current(s, c))
                continue;
            ends[2 * n] = c.a;
            ends[2 * n + 1] = c.b;
            group[n++] = k;
        }
        if (!gather_fans(s, ends, 2 * n, sc->group, 0))
            return 1;
        for (size_t i = 0; i < n; ++i) {
            window_entry *e = &S->win[group[i]];
            candidate c = s->queue.list.data[e->index];
            const u32vec *fa = &sc->group[2 * i], *fb = &sc->group[2 * i + 1];
            e->na = (uint32_t)fa->count;
            e->nb = (uint32_t)fb->count;
            e->count = gather_star(s, c, fa, fb, S->stars + group[i] * STAR_MAX, STAR_MAX);
        }
    }
    return 0;
}

/* Claims window entry k for the chunk if the candidate's closed star meets no star claimed before in the chunk:
 * its ends are marked taken for the pass, its star claimed for the chunk. Returns 1 when taken, 0 when it has no
 * business in this pass (done, stale, or an end taken), 2 when its star meets a claimed position (a later chunk
 * of the pass may take it), -1 when out of memory. */
static int claim_candidate(simplifier *s, size_t k)
{
    schedule *S = &s->sched;
    const window_entry *e = &S->win[k];
    candidate c = s->queue.list.data[e->index];
    if (e->count == 0 || ((s->gen[c.a] | s->gen[c.b]) & TAKEN))
        return 0;
    const uint32_t *star;
    size_t n = e->count;
    if (e->count == STAR_OVERFLOW) { /* a vertex of high valence: gathered here */
        lane *L = &S->lanes[0];
        if (!gather_fan(s, c.a, &L->fan_a, 0) || !gather_fan(s, c.b, &L->fan_b, 0))
            return -1;
        L->touched.count = 0;
        const u32vec *fans[2] = {&L->fan_a, &L->fan_b};
        if (!vec_push(s->alloc, &L->touched, c.a) || !vec_push(s->alloc, &L->touched, c.b))
            return -1;
        for (int side = 0; side < 2; ++side)
            for (size_t i = 0; i < fans[side]->count; ++i) {
                uint32_t xs[2];
                corner_others(s, fans[side]->data[i], xs);
                if (!vec_push(s->alloc, &L->touched, xs[0]) || !vec_push(s->alloc, &L->touched, xs[1]))
                    return -1;
            }
        star = L->touched.data;
        n = L->touched.count;
    } else {
        star = S->stars + k * STAR_MAX + e->na + e->nb;
    }
    for (size_t i = 0; i < n; ++i)
        if (s->gen[star[i]] & CLAIMED)
            return 2;
    s->gen[c.a] |= TAKEN;
    s->gen[c.b] |= TAKEN;
    if (!vec_push(s->alloc, &S->taken, c.a) || !vec_push(s->alloc, &S->taken, c.b))
        return -1;
    for (size_t i = 0; i < n; ++i) {
#ifndef NDEBUG
        S->owner[star[i]] = (uint32_t)S->pend_count; /* the contract's check (guards.h) */
#endif
        if (!(s->gen[star[i]] & CLAIMED)) {
            s->gen[star[i]] |= CLAIMED;
            if (!vec_push(s->alloc, &S->claimed, star[i]))
                return -1;
        }
    }
    pending *q = &S->pend[S->pend_count++];
    *q = (pending){.index = e->index};
    if (e->count != STAR_OVERFLOW) {
        q->fans = S->stars + k * STAR_MAX;
        q->na = e->na;
        q->nb = e->nb;
    }
    return 1;
}

/* Takes up the pass's next CHUNK candidates whose ends no earlier one of the pass took and whose stars are
 * disjoint (claim_candidate): first those an earlier chunk put aside (their stars met its claims), then the next
 * in the list. The stars of a window of candidates are gathered first, on all threads; the claims, in list order,
 * then only read their marks. Closes the pass when none is left under its limit. Past the limit, while the pass
 * has not done a collapse yet, one at a time (so a run of refused candidates at the front cannot make every pass a
 * walk over the whole list for one collapse). Returns 0 when out of memory. */
static int take_chunk_ends(simplifier *s);
static void close_pass(simplifier *s);

int take_chunk(simplifier *s, scratch *sc)
{
    schedule *S = &s->sched;
    if (!star_pass(s))
        return take_chunk_ends(s);
    for (size_t t = 0; t < S->claimed.count; ++t)
        s->gen[S->claimed.data[t]] &= ~CLAIMED;
    S->claimed.count = 0;
    S->pend_count = S->pend_next = 0;
    for (;;) {
        size_t n = 0;
        for (size_t k = 0; k < S->skip_count; ++k) /* in list order, all before pass_next */
            S->win[n++].index = S->skip[k];
        size_t nskip = n;
        for (size_t i = S->pass_next; n < nskip + S->window && i < s->queue.list.count; ++i) {
            if (s->queue.list.data[i].cost > S->pass_limit && s->rep.collapses > S->pass_before)
                break;
            S->win[n++].index = i;
        }
        chunk_job job = {s, sc};
        if (resurfi_pool_for(chunk_pool(s), n, 64, star_block, &job))
            return 0;
        S->skip_count = 0;
        size_t k = 0;
        for (; k < n && S->pend_count < S->chunk; ++k) {
            if (k >= nskip) {
                if (S->skip_count >= S->chunk)
                    break;
                candidate c = s->queue.list.data[S->win[k].index];
                if (c.cost > S->pass_limit && (s->rep.collapses > S->pass_before || S->pend_count > 0))
                    break;
            }
            if (k + 4 < n) { /* the marks the claim four ahead will read */
                const window_entry *ahead = &S->win[k + 4];
                if (ahead->count != STAR_OVERFLOW)
                    for (uint32_t i = 0; i < ahead->count; ++i)
                        PREFETCH(&s->gen[S->stars[(k + 4) * STAR_MAX + ahead->na + ahead->nb + i]]);
            }
            int r = claim_candidate(s, k);
            if (r < 0)
                return 0;
            if (r == 2)
                S->skip[S->skip_count++] = S->win[k].index;
        }
        if (k < nskip) {
            for (; k < nskip; ++k)
                S->skip[S->skip_count++] = S->win[k].index;
        } else {
            S->pass_next = k < n ? S->win[k].index : n > nskip ? S->win[n - 1].index + 1 : S->pass_next;
        }
        /* Nothing taken from a whole window that did not reach the limit: the next window. */
        if (S->pend_count > 0 || k < n || n == nskip || S->pass_next >= s->queue.list.count)
            break;
    }
    if (S->pend_count == 0)
        close_pass(s);
    return 1;
}

/* take_chunk without stars, for chunks applied one collapse after the other: the pass's next CHUNK candidates
 * whose ends no earlier one of the pass took. Returns 0 when out of memory. */
static int take_chunk_ends(simplifier *s)
{
    schedule *S = &s->sched;
    S->pend_count = S->pend_next = 0;
    size_t i = S->pass_next;
    for (; S->pend_count < S->chunk && i < s->queue.list.count; ++i) {
        candidate c = s->queue.list.data[i];
        if (c.cost > S->pass_limit && (s->rep.collapses > S->pass_before || S->pend_count > 0))
            break;
        if (((s->gen[c.a] | s->gen[c.b]) & TAKEN) || !candidate_current(s, c))
            continue;
        s->gen[c.a] |= TAKEN;
        s->gen[c.b] |= TAKEN;
        if (!vec_push(s->alloc, &S->taken, c.a) || !vec_push(s->alloc, &S->taken, c.b))
            return 0;
        S->pend[S->pend_count++] = (pending){.index = i};
    }
    S->pass_next = i;
    if (S->pend_count == 0)
        close_pass(s);
    return 1;
}

/* Closes the pass: nothing left under its limit. Its ends are free again. */
static void close_pass(simplifier *s)
{
    schedule *S = &s->sched;
    for (size_t t = 0; t < S->taken.count; ++t)
        s->gen[S->taken.data[t]] &= ~TAKEN;
    S->taken.count = 0;
    S->skip_count = 0;
    S->pass_open = 0;
}

/* Applies the chunk's collapses [begin, end) on worker `worker`: each into its worker's lane, its results' places
 * noted in its pending entry. */
static int apply_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    chunk_job *j = ctx;
    simplifier *s = j->s;
    schedule *S = &s->sched;
    lane *L = &S->lanes[worker];
    for (size_t i = begin; i < end; ++i) {
        pending *q = &S->pend[i];
        if (i + 2 < end) {
            candidate ahead = s->queue.list.data[S->pend[i + 2].index];
            PREFETCH(&s->P[ahead.a]);
            PREFETCH(&s->P[ahead.b]);
        }
        if (s->home && s->opt.restore == RESURF_RESTORE_INLINE)
            for (size_t k = 1; k <= 3 && i + k < end; ++k)
                prefetch_walk(s, s->queue.list.data[S->pend[i + k].index].a, k);
        q->worker = worker;
        q->fresh_begin = L->fresh.count;
        q->renew_begin = L->renew.count;
#ifndef NDEBUG
        L->writer = (uint32_t)i;
#endif
        int ok = try_candidate(s, q, L, &j->scratch[worker], 1);
#ifndef NDEBUG
        L->writer = NONE;
#endif
        if (!ok)
            return 1;
        q->fresh_end = L->fresh.count;
        q->renew_end = L->renew.count;
    }
    return 0;
}

/* After a chunk applied in parallel: the lanes' candidates moved to the list's fresh part in the chunk's order (so
 * that nothing downstream depends on which worker did what), then the renewed neighbours' edges planned, in the
 * chunk's order (they reach positions of other stars, which were changing during the chunk). As in try_candidate,
 * each edge between two renewed positions is planned by the later one. Returns 0 when out of memory. */
static int finish_parallel_chunk(simplifier *s)
{
    schedule *S = &s->sched;
    for (size_t k = 0; k < S->pend_count; ++k) {
        const pending *q = &S->pend[k];
        const lane *L = &S->lanes[q->worker];
        size_t n = q->fresh_end - q->fresh_begin;
        if (n && !simp_buf_append(s->alloc, &s->queue.fresh, L->fresh.data + q->fresh_begin, n))
            return 0; /* (n = 0 may come with an empty lane: no pointer arithmetic on its NULL buffer) */
    }
    for (unsigned w = 0; w < s->threads; ++w) {
        S->lanes[w].fresh.count = 0;
        merge_lane_counts(s, &S->lanes[w]);
    }
    for (size_t k = 0; k < S->pend_count; ++k) {
        const pending *q = &S->pend[k];
        const lane *L = &S->lanes[q->worker];
        for (size_t i = q->renew_begin; i < q->renew_end; ++i)
            s->P[L->renew.data[i]].flags |= POS_RENEW;
    }
    lane *L0 = &S->lanes[0];
    for (size_t k = 0; k < S->pend_count; ++k) {
        const pending *q = &S->pend[k];
        const lane *L = &S->lanes[q->worker];
        for (size_t i = q->renew_begin; i < q->renew_end; ++i)
            if (!plan_renewed(s, L0, L->renew.data[i], q->keep))
                return 0;
    }
    for (unsigned w = 0; w < s->threads; ++w)
        S->lanes[w].renew.count = 0;
    return merge_lane(s, L0);
}

/* Whether the chunk just taken is applied on all threads: a pass of stars, and the whole chunk stays above the
 * target (each collapse removes at most two triangles). */
int chunk_in_parallel(const simplifier *s, size_t target)
{
    const schedule *S = &s->sched;
    return star_pass(s) && S->pend_count && s->alive_tris > target + 2 * S->pend_count;
}

/* Applies the chunk on all threads, then merges the lanes in the chunk's order. Returns 0 when out of memory. */
int apply_chunk_parallel(simplifier *s, scratch *sc)
{
    schedule *S = &s->sched;
    chunk_job job = {s, sc};
    if (resurfi_pool_for(chunk_pool(s), S->pend_count, S->chunk / 64 + 1, apply_block, &job))
        return 0;
    if (!finish_parallel_chunk(s))
        return 0;
    S->pend_next = S->pend_count;
    return 1;
}

/* For a chunk applied one collapse after the other: with inline restoration, its placements planned and restored
 * on all threads first (when it is worth threads). Returns 0 when out of memory. */
int restore_chunk_ahead(simplifier *s, scratch *sc)
{
    schedule *S = &s->sched;
    int batched = s->opt.restore == RESURF_RESTORE_INLINE && s->restorer && s->threads > 1;
    if (!batched || chunk_threads(s) <= 1)
        return 1;
    chunk_job job = {s, sc};
    return !resurfi_pool_for(chunk_pool(s), S->pend_count, S->chunk / 16 + 1, restore_chunk_block, &job);
}

/* Applies the chunk's next collapse alone, on the calling thread. Returns 0 when out of memory. */
int apply_next_alone(simplifier *s, scratch *sc)
{
    schedule *S = &s->sched;
    size_t k = S->pend_next++;
    if (k + 2 < S->pend_count) {
        candidate ahead = s->queue.list.data[S->pend[k + 2].index];
        PREFETCH(&s->P[ahead.a]);
        PREFETCH(&s->P[ahead.b]);
    }
    lane *L0 = &S->lanes[0];
    return try_candidate(s, &S->pend[k], L0, sc, 0) && merge_lane(s, L0);
}

/* The scheduler's buffers and the lanes; each lane but the first has its own marks (4 bytes per position). */
resurf_status schedule_init(simplifier *s)
{
    schedule *S = &s->sched;
    if (!(S->pend = resurfi_alloc(s->alloc, CHUNK, sizeof *S->pend)) ||
        !(S->skip = resurfi_alloc(s->alloc, CHUNK, sizeof *S->skip)) ||
        !(S->win = resurfi_alloc(s->alloc, CHUNK + WINDOW, sizeof *S->win)) ||
        !(S->stars = resurfi_alloc(s->alloc, (CHUNK + WINDOW) * (size_t)STAR_MAX, sizeof *S->stars)) ||
        !(S->lanes = resurfi_calloc(s->alloc, s->threads, sizeof *S->lanes)))
        return RESURF_ERR_OUT_OF_MEMORY;
    S->lanes[0].mark = s->mark;
    for (unsigned w = 1; w < s->threads; ++w)
        if (!(S->lanes[w].mark = resurfi_calloc(s->alloc, s->pos_count, sizeof *S->lanes[w].mark)))
            return RESURF_ERR_OUT_OF_MEMORY;
#ifndef NDEBUG
    for (unsigned w = 0; w < s->threads; ++w)
        S->lanes[w].writer = NONE;
    if (!(S->owner = resurfi_alloc(s->alloc, s->pos_count, sizeof *S->owner)))
        return RESURF_ERR_OUT_OF_MEMORY;
    memset(S->owner, 0xff, s->pos_count * sizeof *S->owner);
#endif
    return RESURF_OK;
}

/* The working mesh is going: the lanes' marks go with it. */
void schedule_drop_marks(simplifier *s)
{
    schedule *S = &s->sched;
    if (S->lanes)
        for (unsigned w = 0; w < s->threads; ++w) {
            if (w > 0)
                resurfi_free(s->alloc, S->lanes[w].mark);
            S->lanes[w].mark = NULL;
        }
}

void schedule_free(simplifier *s)
{
    schedule *S = &s->sched;
    resurfi_free(s->alloc, S->taken.data);
    resurfi_free(s->alloc, S->claimed.data);
    resurfi_free(s->alloc, S->skip);
    resurfi_free(s->alloc, S->win);
    resurfi_free(s->alloc, S->stars);
#ifndef NDEBUG
    resurfi_free(s->alloc, S->owner);
#endif
    if (S->lanes)
        for (unsigned w = 0; w < s->threads; ++w) {
            lane *L = &S->lanes[w];
            resurfi_free(s->alloc, L->fan_a.data);
            resurfi_free(s->alloc, L->fan_b.data);
            resurfi_free(s->alloc, L->fan_c.data);
            resurfi_free(s->alloc, L->touched.data);
            resurfi_free(s->alloc, L->renew.data);
            resurfi_free(s->alloc, L->fresh.data);
            if (w > 0)
                resurfi_free(s->alloc, L->mark);
        }
    resurfi_free(s->alloc, S->lanes);
    resurfi_free(s->alloc, S->pend);
}
