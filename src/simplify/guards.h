/* The guards of one collapse (guards.c), and the contract that lets the collapses of a chunk run in parallel.
 *
 * THE CONTRACT. Call a collapse's closed star its ends a and b with their neighbours. A collapse of edge (a, b)
 * applied inside a parallel chunk (schedule.c) may
 *   read   at most the 2-ring of its edge: the records (place, quadric, flags, list head), generations and homes of
 *          its star's positions, and the triangles around them (whose corners name the neighbours' neighbours:
 *          their ids and wedges are read, never their records), besides M (read-only);
 *   write  only its closed star: the records, generations and homes of its star's positions, and the triangles
 *          with a corner at a or b (corners' positions, wedges, list links, the dead mark). Everything else it
 *          produces goes to its worker's lane (new candidates, counters, marks, the neighbours to plan again) and
 *          is merged after the chunk, in the chunk's order.
 * The scheduler puts candidates in one chunk only when their closed stars are pairwise disjoint. Then what one
 * collapse writes, another never reads: a triangle with a corner at an end has all its corners in that end's star,
 * so it lies around no position of another star. Each collapse sees the mesh as if it ran alone, and the result
 * does not depend on the thread count. Work that reaches further (the edges of renewed neighbours, which end
 * outside the star) waits in the lane for after the chunk.
 * Debug builds (NDEBUG undefined) check the write side: the scheduler stamps each claimed star position with the
 * claiming entry (schedule.owner), and every write of a collapse asserts that it lands in its own star
 * (check_position_write, check_corner_write). */
#ifndef RESURF_SIMPLIFY_GUARDS_H
#define RESURF_SIMPLIFY_GUARDS_H

#include <assert.h>

#ifndef NDEBUG
/* Position x is written by the collapse running on lane L: inside a parallel chunk, x is in that collapse's star. */
static inline void check_position_write(const simplifier *s, const lane *L, uint32_t x)
{
    assert(L->writer == NONE || s->sched.owner[x] == L->writer);
}

/* Corner c's triangle is written by the collapse running on lane L, whose ends are a and b: inside a parallel
 * chunk, the triangle has a corner at a or b (it is in the closed star). */
static inline void check_corner_write(const simplifier *s, const lane *L, uint32_t c, uint32_t a, uint32_t b)
{
    if (L->writer == NONE)
        return;
    uint32_t t = c / 3;
    int in_star = 0;
    for (int k = 0; k < 3; ++k)
        in_star |= s->tri[t].v[k] == a || s->tri[t].v[k] == b;
    assert(in_star);
    (void)in_star;
}
#else
#define check_position_write(s, L, x) ((void)(s), (void)(L), (void)(x))
#define check_corner_write(s, L, c, a, b) ((void)(s), (void)(L), (void)(c), (void)(a), (void)(b))
#endif

/* Why geometry_ok refuses a collapse. */
enum { GEOMETRY_OK = 0, GEOMETRY_FLIP = 1, GEOMETRY_ANGLE = 2 };

int link_ok(const simplifier *s, lane *L, const u32vec *fan_a, const u32vec *fan_b, uint32_t a, uint32_t b,
            const plan *pl);
int geometry_ok(const simplifier *s, const u32vec *fan_a, const u32vec *fan_b, uint32_t a, uint32_t b, vec3 p,
                const plan *pl);
double distance_excess(const simplifier *s, lane *L, const u32vec *fan_a, const u32vec *fan_b, uint32_t a,
                       uint32_t b, vec3 p, const plan *pl, double err, uint32_t near);
double excess_penalty(const resurfi_quadric *q, double excess);
double facet_depth(const simplifier *s, uint32_t t);
int restore_keeps_reach(const simplifier *s, const u32vec *fan_a, const u32vec *fan_b, uint32_t a, uint32_t b,
                        const plan *pl, vec3 q, uint32_t q_home);
vec3 restore_point(const simplifier *s, vec3 p, double scale, uint32_t home, int *left, uint32_t *out_home);

#endif
