/* The simplifier's candidate queue: a list of candidate collapses sorted by cost, with lazy invalidation.
 *
 * A candidate carries the sum of its ends' generations when it was planned; an end that changes bumps its
 * generation, and the candidate goes stale without being looked up. Candidates planned during a pass wait in
 * `fresh` and are merged in when the next pass opens (simp_queue_refresh); the list is read in place, by index,
 * between refreshes. Nothing here depends on the thread count: equal costs keep the order of the input (the
 * first list), then the list's candidates come before fresh ones, which keep the order they were added in.
 *
 * The interface is five calls: simp_queue_reserve and simp_queue_seed build the first list, simp_buf_append adds
 * candidates (to the queue's fresh ones or to a worker's buffer), simp_queue_refresh merges the fresh ones in and
 * drops the stale ones, simp_queue_free. */
#ifndef RESURF_SIMPLIFY_QUEUE_H
#define RESURF_SIMPLIFY_QUEUE_H

#include <stddef.h>
#include <stdint.h>

#include "../internal.h"

/* A candidate collapse of edge (a, b), planned when the ends' generations summed to stamp; a is UINT32_MAX once it
 * has been taken up. */
typedef struct candidate {
    float cost;
    uint32_t a, b, stamp;
} candidate;

typedef struct candidate_buf {
    candidate *data;
    size_t count, cap;
} candidate_buf;

/* The generation of a position is the low 30 bits of its gen word (the scheduler keeps marks in the top two). */
enum { SIMP_GEN = 0x3fffffffu };

typedef struct simp_queue {
    const resurf_allocator *alloc;
    candidate_buf list;   /* sorted by cost */
    candidate_buf fresh;  /* planned or requeued since the last refresh: merged into the list by the next */
    candidate *sorted;    /* where the fresh ones are sorted to (the stable sort's second buffer) */
    size_t sorted_cap;
} simp_queue;

/* Is candidate c still what its ends are (gen: per position)? Generations only grow, so the sum matches only if
 * neither end changed. */
static inline int simp_candidate_current(const uint32_t *gen, candidate c)
{
    return c.a != UINT32_MAX && ((gen[c.a] + gen[c.b]) & SIMP_GEN) == c.stamp;
}

/* Grows the list to hold n candidates (its count unchanged); 0 when out of memory. */
int simp_queue_reserve(simp_queue *q, size_t n);

/* The first list: of the list's first n slots (written by the caller after simp_queue_reserve), those whose a is
 * not UINT32_MAX, sorted by cost in place. */
void simp_queue_seed(simp_queue *q, size_t n);

/* Appends n candidates to buf; 0 when out of memory. */
int simp_buf_append(const resurf_allocator *alloc, candidate_buf *buf, const candidate *c, size_t n);

/* The list for the next pass: its current candidates keep their places, the current fresh ones are sorted (stably)
 * and merged in, on equal costs after the list's; stale ones (and those taken up) are dropped. Runs on pool's
 * threads (NULL: the calling thread). 0 when out of memory. */
int simp_queue_refresh(simp_queue *q, const uint32_t *gen, resurfi_pool *pool);

void simp_queue_free(simp_queue *q);

#endif
