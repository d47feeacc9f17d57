/* Edge-collapse simplification with the new vertices restored onto the smooth surface of the ORIGINAL mesh.
 *
 * Sources: Garland & Heckbert, "Surface Simplification Using Quadric Error Metrics" (SIGGRAPH 1997) for the costs
 * and the placement (quadric.c); Hoppe, "New quadric metric for simplifying meshes with appearance attributes"
 * (1999) for wedges (attribute vertices that share a position); Dey, Edelsbrunner, Guha & Nekhayev, "Topology
 * preserving edge contraction" (1999) for the link condition; Semenova, Savchenko & Hagiwara, "Reconstruction of
 * Shapes Based on Normals Analysis", §4.2, for restoring every new vertex onto S as an intermediate step
 * (notes/restoring.md §8–§9).
 *
 * Phases (one function each, in this order):
 *   prepare_mesh      weld positions exactly, merge attribute vertices with equal attributes into wedges, drop
 *                     triangles with a repeated position, thread each position's corners into a list;
 *   analyse_position  per position (in parallel): border, seam, non-manifold flags and the quadric (area-weighted
 *                     triangle planes, plus planes through border and seam edges perpendicular to their triangles);
 *   seed_candidates   every edge's candidate collapse and cost (in parallel), sorted by cost;
 *   collapse_until    passes over the sorted candidates, each taking independent ones in cost order: planned
 *                     again, checked (link condition, flips and folds, minimum angle), restored, applied;
 *   build_output      the result: wedges become vertices, attributes are interpolated from the input, vertices
 *                     straddle S by the sag offset, the distance to the input is measured.
 *
 * Collapses work on welded positions. A triangle corner keeps its wedge (the id of an input attribute vertex); when
 * a position disappears, each corner takes the wedge of the surviving position on its side of any seam, which is
 * why a seam vertex may only collapse along its seam (the rule table is in plan_collapse).
 * Nothing here depends on the thread count: parallel phases write per-element results only, and the collapses
 * applied in parallel are those of a chunk with disjoint stars (collapse_until), whose results are merged in the
 * chunk's order. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"

#define NONE UINT32_MAX

enum {
    PROGRESS_COLLAPSES = 1 << 13, /* collapses between two progress calls */
    BLOCK_POSITIONS = 1024,       /* parallel block sizes */
    BLOCK_SAMPLES = 4096,
    SMALL_SORT = 24,              /* fans up to this size are insertion-sorted */
    CHUNK = 1024,                 /* candidates of a pass applied together, at most */
    WINDOW = 1536,                /* candidates whose stars are gathered for a chunk, besides those put aside */
    CHUNK_MIN = 16,               /* a chunk's size is alive positions / CHUNK_SPREAD, within [CHUNK_MIN, CHUNK] */
    CHUNK_SPREAD = 64,
    CHUNK_THREADS = 32,           /* smaller chunks run on one thread: handing them out would cost more than it saves */
};

/* The tip guard (tip_excess): an end's old position may lie TIP_GUARD × the edge's length, or TIP_ERROR × the
 * collapse's quadric error (RMS distance to the merged planes), whichever is more, from the triangles that replace
 * its own; beyond, the collapse is re-priced with TIP_PENALTY × its quadrics' weight × the excess² (large: such
 * collapses come last). Measured with bench_simplify on the Stanford dragon scan (871k triangles), Hausdorff and
 * mean distance over meshoptimizer's at 10% and 2%: 3.28/0.59 and 1.89/0.55 before, 0.80/0.59 and 0.89/0.56 after
 * (the 2% maximum is then a vertex off M, not a spike; without the error term 0.80 and 0.74, but coarse inputs
 * lose: bunny at 10% 0.73 -> 0.98, the 48k dragon's mean at 2% +16%; with it they keep their figures). Guards of
 * 0.2 and 0.3 did no better. The analytic surfaces of bench_simplify do not change. */
static const double TIP_GUARD = 0.25;
static const double TIP_ERROR = 2;
static const double TIP_PENALTY = 1e6;

/* A triangle's plane enters its corners' quadrics weighted by its area, but by at least AREA_FLOOR × the mean
 * triangle area: with the area alone, a dense cluster of tiny triangles (a small sharp feature or a scanning
 * artefact) is erased at almost no cost, though the Hausdorff distance counts it fully. Measured with
 * bench_simplify on the dragon scan (871k triangles), two-sided Hausdorff over meshoptimizer's at 50%, 10%, 2%:
 * without the floor 1.04, 0.63, 0.88 (--restore none) and 1.65, 0.87, 0.90 (inline); at 0.75: 0.23, 0.46, 0.61 and
 * 1.43, 0.60, 0.77 (0.5 and 1 did worse on the scan or on the analytic cubic surface, whose mean distances at 10% and
 * 2% move by 1% or less at 0.75). */
static const double AREA_FLOOR = 0.75;

/* A restored vertex rises over (or sinks under) the plane of M's triangle it was restored on by at most RISE_LIMIT ×
 * M's local edge length. On a smooth surface sampled so that an edge turns by angle hκ, S rises about hκ/6 of an edge
 * over a facet, so the limit binds only where M's normals turn by more than ~17° per edge: the 20k analytic shapes
 * rise 0.01 of an edge at most. But a scan's sharp ridges are such places, and there S, the smooth surface the
 * normals describe, bulges over the scanned points by up to 0.3 of an edge (the circle through a ridge triangle's
 * corners with their normals does too: the scan is sharper than its normals). Measured with bench_simplify on the
 * dragon scan (871k triangles), two-sided Hausdorff over meshoptimizer's at 50%: about 1.27 (no limit), 0.88 (0.07),
 * 0.75 (0.05), with the sag offset of place_output; the 20k analytic figures do not move. */
static const double RISE_LIMIT = 0.05;

/* A pass of collapse_until goes up to the cost of the candidate at PASS_SHARE of the sorted list. Measured with
 * bench_simplify on the 20k analytic shapes at 10% and 2%: at 0.05 the distances to the true surface are those of
 * one collapse at a time (the order of a binary heap) within ±1%, at 0.25 within 3%, at 1 up to 6% worse; the time
 * on 1M triangles hardly changes (most of a pass's cost is per collapse, not per pass). */
static const double PASS_SHARE = 0.05;

/* Whether collapse_until applies chunks of candidates with disjoint stars in parallel, with inline restoration and
 * without (see collapse_until). A choice by mode, never by thread count: results depend on it. Finding the stars
 * costs about 30% more work in all (so one thread is that much slower); measured on a 1M torus at 10% with 2 threads
 * on a quiet 2-core machine, three runs each: none 1.75–1.82 -> 1.38–1.53 s, inline 2.84–2.90 -> 2.41–2.49 s. On a
 * machine busy with other jobs the medians lose (a fork-join per chunk waits for a descheduled thread). With 0
 * both keep the one-by-one application, whose results are those of the sequential loop. */
static const int PARALLEL_INLINE = 1;
static const int PARALLEL_PLAIN = 1;

/* Per-position flags. */
enum {
    POS_DEAD = 1,          /* collapsed away */
    POS_LOCKED = 2,        /* non-manifold or inconsistently oriented in the input: never moves */
    POS_LOCKED_BORDER = 4, /* on a border with lock_border */
    POS_BORDER = 8,        /* on an edge with one triangle */
    POS_SEAM = 16,         /* exactly two wedges, split by exactly two seam edges, not on a border */
    POS_COMPLEX = 32,      /* any other wedge arrangement (seam junctions, seams ending on a border): never moves */
    POS_BLOCKED = 64,      /* a collapse at it failed a geometric guard: retry once its neighbourhood changes */
    POS_RENEW = 128,       /* transient, in try_candidate: its candidates are being planned again */
};


/* Why a candidate collapse cannot be done. */
enum {
    BLOCK_NONE = 0,
    BLOCK_STALE,       /* not an edge any more */
    BLOCK_SEAM,
    BLOCK_BORDER,
    BLOCK_NONMANIFOLD, /* most severe last: when both directions fail, the larger reason is reported */
};

/* A candidate collapse of edge (a, b), planned when the ends' generations summed to stamp; a is NONE once it has
 * been taken up. */
typedef struct candidate {
    float cost;
    uint32_t a, b, stamp;
} candidate;

typedef struct u32vec {
    uint32_t *data;
    size_t count, cap;
} u32vec;

/* A corner of a position's fan, sorted by the neighbour it leads to: the unit of the per-position analyses. */
typedef struct fan_pair {
    uint32_t x;    /* the neighbour position */
    uint32_t slot; /* index of the corner in the fan, times 2, plus 1 when x precedes the position in the face */
} fan_pair;

enum { GATHER_GROUP = 4 }; /* candidates whose fans star_block gathers together */

typedef struct scratch {
    const resurf_allocator *alloc; /* the call's */
    u32vec fan;
    u32vec group[2 * GATHER_GROUP]; /* star_block: the fans of a group of candidates' ends */
    fan_pair *pairs;
    uint32_t *uf;
    size_t pairs_cap;
    size_t blocked[5]; /* candidates refused while seeding, by BLOCK_* reason */
    char pad[128];     /* one per worker, side by side: keeps their counters off each other's cache lines */
} scratch;

/* A planned collapse of edge (a, b). */
typedef struct plan {
    int block;               /* BLOCK_*; the rest is valid for BLOCK_NONE only */
    int a_removable, b_removable;
    int pinned;              /* 1: the position is that of the surviving end, already where it should be */
    uint32_t shared[2];      /* the triangles on the edge */
    int shared_count;
    vec3 p;
    double cost;
} plan;

/* A working triangle: its corners 3t..3t+2 (corner c is triangle c / 3, slot c % 3). The arrays of one triangle
 * and of one position sit together: the collapse loop visits them at random and each miss then brings the rest. */
typedef struct work_tri {
    uint32_t v[3];    /* position of each corner */
    uint32_t w[3];    /* wedge of each corner: the lowest input vertex with the same position and attributes */
    uint32_t next[3]; /* next corner of the same position, NONE at the end */
    uint32_t dead;
} work_tri;

/* 128 bytes, allocated on a 64-byte boundary: the first cache line holds what every visit reads (flags, position,
 * list head), the quadric follows. */
typedef struct work_pos {
    vec3 p;
    uint32_t head;    /* first corner */
    uint32_t up;      /* while starting: its neighbours above it (its edges in the first list) */
    uint8_t flags;
    resurfi_quadric q;
} work_pos;

#define TV(c) (s->tri[(c) / 3].v[(c) % 3])
#define TW(c) (s->tri[(c) / 3].w[(c) % 3])
#define TNEXT(c) (s->tri[(c) / 3].next[(c) % 3])

/* Candidate `index` of the list as gathered ahead of the claims (star_block): its ends' fans (live corners, in
 * list order: what gather_fan returns) and its closed star (the ends and their neighbours, each once). count is 0
 * when the candidate has no business in this pass, STAR_OVERFLOW when it did not fit in STAR_MAX words (gathered
 * again where needed). */
typedef struct window_entry {
    size_t index;
    uint32_t count; /* of star positions */
    uint32_t na, nb;
} window_entry;

enum { STAR_MAX = 96, STAR_OVERFLOW = UINT32_MAX };

/* A candidate taken up by a pass: its place in the list and, with inline restoration, its placement restored.
 * Applied on a worker (apply_block), also where its results wait in that worker's lane. */
typedef struct pending {
    size_t index;
    vec3 p, restored;
    uint32_t home;
    uint8_t restore, left;
    unsigned worker;
    uint32_t window;                 /* its entry in the window (its ends' fans gathered), NONE if none */
    uint32_t keep;                   /* the surviving end, when collapsed */
    size_t fresh_begin, fresh_end;   /* its new candidates in the lane's fresh */
    size_t renew_begin, renew_end;   /* its renewed neighbours in the lane's renew, planned after the chunk */
} pending;

/* What one collapse writes besides its own star: per worker, so that the collapses of a chunk run in parallel
 * (see collapse_until). Merged into the simplifier after each chunk, in the chunk's order. */
typedef struct lane {
    u32vec fan_a, fan_b, fan_c, touched, renew;
    uint32_t *mark;         /* scratch stamps, see next_stamp (lane 0's is the simplifier's) */
    uint32_t stamp;
    candidate *fresh;       /* candidates planned or requeued, for the simplifier's fresh */
    size_t fresh_count, fresh_cap;
    resurf_simplify_report rep; /* counters to add to the simplifier's */
    size_t dead_tris, dead_positions;
    int skipped_error;
    char pad[128]; /* side by side: keeps the lanes' counters off each other's cache lines */
} lane;

typedef struct simplifier {
    const resurf_mesh *in;
    resurf_simplify_options opt;
    const resurf_allocator *alloc; /* the call's (options, else the input's): temporaries and the output */
    unsigned threads;
    resurfi_pool *pool;  /* threads - 1 workers waiting for the call's parallel loops (NULL with one thread) */
    double diagonal, max_error;
    double area_floor;   /* AREA_FLOOR × the mean triangle area */
    vec3 origin;         /* the bounding box's centre: quadrics are built around it, where their expanded form
                            xᵀAx + 2bᵀx + c loses the fewest digits to cancellation */

    size_t tri_count, alive_tris;
    work_tri *tri;
    uint32_t *src;     /* input triangle of each working triangle */
    uint32_t *remap;   /* while starting: position of each input vertex (resurfi_weld_exact) */
    size_t pos_count, alive_positions;
    work_pos *P;         /* inside P_mem, 64-byte aligned */
    void *P_mem;
    uint32_t *mark;    /* lane 0's scratch stamps (allocated with the working mesh) */

    /* attribute sides (only when the input has attributes and seams): chart of each input triangle and wedge */
    uint32_t *chart_of_input_tri;
    uint32_t *chart_of_wedge;

    candidate *cand;        /* the candidates, sorted by cost */
    size_t cand_count, cand_cap;
    candidate *fresh;       /* planned or requeued during a pass: merged into the list before the next */
    size_t fresh_count, fresh_cap;
    candidate *sorted;      /* where the fresh ones are sorted to (sort_stable's second buffer) */
    size_t sorted_cap;
    uint32_t *gen;          /* per position: bumped when it changes (its candidates then go stale); the top bit
                               marks an end of a candidate taken up by the current pass. Apart from the 128-byte
                               records: a pass reads it for every candidate. */
    u32vec taken;           /* the positions marked taken */
    int star_chunks;        /* chunks of candidates with disjoint stars, applied in parallel (else one by one) */
    size_t chunk, window;   /* this pass's chunk size and window (open_pass) */
    u32vec claimed;         /* the positions marked claimed (stars of the chunk's candidates) */
    size_t *skip;           /* CHUNK: candidates of the pass whose star met a claimed one: for the next chunk */
    size_t skip_count;
    struct window_entry *win; /* CHUNK + WINDOW: the candidates examined for a chunk */
    uint32_t *stars;        /* STAR_MAX per window entry: their stars */
    int skipped_error;      /* a candidate was skipped for max_error in this collapse_until */

    int last_level;             /* building the last output: the working mesh may go once read */
    resurfi_restorer *restorer;
    resurfi_bvh *own_bvh;       /* when there is no restorer */
    const resurfi_bvh *bvh;     /* over the input's triangles, input triangle ids */
    uint32_t *home;             /* inline restoration: per position, a triangle of the input near it */

    lane *lanes;            /* one per thread */
    pending *pend;          /* CHUNK: the pass's candidates being applied, pend_next the next one */
    size_t pend_count, pend_next;
    int pass_open;
    size_t pass_next;       /* the next candidate of the open pass */
    size_t pass_before;     /* collapses when it opened */
    float pass_limit;
    resurf_simplify_report rep;
} simplifier;

/* ---- small helpers ------------------------------------------------------------------------------------------- */

static int vec_push(const resurf_allocator *alloc, u32vec *v, uint32_t x)
{
    if (v->count == v->cap) {
        size_t cap = v->cap ? 2 * v->cap : 32;
        uint32_t *d = resurfi_realloc(alloc, v->data, cap, sizeof *d);
        if (!d)
            return 0;
        v->data = d;
        v->cap = cap;
    }
    v->data[v->count++] = x;
    return 1;
}

static void scratch_free(scratch *s)
{
    resurfi_free(s->alloc, s->fan.data);
    for (int i = 0; i < 2 * GATHER_GROUP; ++i)
        resurfi_free(s->alloc, s->group[i].data);
    resurfi_free(s->alloc, s->pairs);
    resurfi_free(s->alloc, s->uf);
}

/* A fresh stamp for lane L's mark array: a position is "marked" when mark[p] equals it. */
static uint32_t next_stamp(const simplifier *s, lane *L)
{
    if (L->stamp >= UINT32_MAX - 4) {
        memset(L->mark, 0, s->pos_count * sizeof *L->mark);
        L->stamp = 0;
    }
    L->stamp += 2;
    return L->stamp;
}

static uint32_t corner_next(uint32_t c) { return c - c % 3 + (c % 3 + 1) % 3; }
static uint32_t corner_prev(uint32_t c) { return c - c % 3 + (c % 3 + 2) % 3; }

/* The positions after and before corner c in its triangle: TV(corner_next(c)) and TV(corner_prev(c)) with one
 * division instead of four (the collapse loop asks this for every corner of every fan it looks at). */
static void corner_others(const simplifier *s, uint32_t c, uint32_t xs[2])
{
    uint32_t t = c / 3, k = c - 3 * t;
    xs[0] = s->tri[t].v[k == 2 ? 0 : k + 1];
    xs[1] = s->tri[t].v[k == 0 ? 2 : k - 1];
}

/* The corners of live triangles at each of n distinct positions v[i] (n <= 2 GATHER_GROUP), in list order, into
 * out[i]. With unlink, dead triangles' corners are dropped from the lists on the way (only the sequential collapse
 * loop may do that). The lists are walked in step: each step of a list is a cache miss on a large mesh, and the
 * misses of different lists then overlap instead of following one another. Returns 0 when out of memory. */
static int gather_fans(simplifier *s, const uint32_t *v, size_t n, u32vec *out, int unlink)
{
    uint32_t c[2 * GATHER_GROUP], prev[2 * GATHER_GROUP];
    for (size_t i = 0; i < n; ++i) {
        out[i].count = 0;
        c[i] = s->P[v[i]].head;
        prev[i] = NONE;
    }
    for (int live = 1; live;) {
        live = 0;
        for (size_t i = 0; i < n; ++i) {
            uint32_t cur = c[i];
            if (cur == NONE)
                continue;
            live = 1;
            c[i] = TNEXT(cur);
            if (!s->tri[cur / 3].dead) {
                if (!vec_push(s->alloc, &out[i], cur))
                    return 0;
                prev[i] = cur;
            } else if (!unlink) {
                prev[i] = cur;
            } else if (prev[i] == NONE) {
                s->P[v[i]].head = c[i];
            } else {
                TNEXT(prev[i]) = c[i];
            }
        }
    }
    return 1;
}

/* One position's fan (gather_fans). */
static int gather_fan(simplifier *s, uint32_t v, u32vec *out, int unlink)
{
    return gather_fans(s, &v, 1, out, unlink);
}

static int pair_less(fan_pair p, fan_pair q) { return p.x < q.x || (p.x == q.x && p.slot < q.slot); }

static int pair_cmp(const void *a, const void *b)
{
    const fan_pair *p = a, *q = b;
    return pair_less(*p, *q) ? -1 : pair_less(*q, *p) ? 1 : 0;
}

/* The (neighbour, corner) pairs of fan `fan` of position v, sorted by neighbour: a run of length 1 is a border edge,
 * 2 a manifold edge, 3 or more a non-manifold edge. Returns the pair count, or SIZE_MAX when out of memory. */
static size_t fan_pairs(const simplifier *s, const u32vec *fan, scratch *sc)
{
    size_t n = 2 * fan->count;
    if (n > sc->pairs_cap) {
        fan_pair *p = resurfi_realloc(s->alloc, sc->pairs, n, sizeof *p);
        uint32_t *uf = resurfi_realloc(s->alloc, sc->uf, fan->count, sizeof *uf);
        if (p)
            sc->pairs = p;
        if (uf)
            sc->uf = uf;
        if (!p || !uf)
            return SIZE_MAX;
        sc->pairs_cap = n;
    }
    for (size_t i = 0; i < fan->count; ++i) {
        uint32_t c = fan->data[i];
        sc->pairs[2 * i] = (fan_pair){TV(corner_next(c)), (uint32_t)(2 * i)};
        sc->pairs[2 * i + 1] = (fan_pair){TV(corner_prev(c)), (uint32_t)(2 * i + 1)};
    }
    if (n <= SMALL_SORT) {
        for (size_t i = 1; i < n; ++i) {
            fan_pair p = sc->pairs[i];
            size_t j = i;
            for (; j > 0 && pair_less(p, sc->pairs[j - 1]); --j)
                sc->pairs[j] = sc->pairs[j - 1];
            sc->pairs[j] = p;
        }
    } else {
        qsort(sc->pairs, n, sizeof *sc->pairs, pair_cmp);
    }
    return n;
}

static uint32_t uf_find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

/* The corner of triangle t at position v, or NONE. */
static uint32_t corner_at(const simplifier *s, uint32_t t, uint32_t v)
{
    for (uint32_t k = 0; k < 3; ++k)
        if (TV(3 * t + k) == v)
            return 3 * t + k;
    return NONE;
}

/* ---- phase 1: the working mesh ------------------------------------------------------------------------------- */

/* Do input vertices u and v carry the same attributes (bit for bit)? */
static int same_attributes(const resurf_mesh *m, uint32_t u, uint32_t v)
{
    if (m->normals && memcmp(m->normals + 3 * (size_t)u, m->normals + 3 * (size_t)v, 3 * sizeof(double)))
        return 0;
    for (unsigned k = 0; k < m->texcoord_count && k < RESURF_MAX_TEXCOORD_SETS; ++k)
        if (m->texcoords[k] &&
            memcmp(m->texcoords[k] + 2 * (size_t)u, m->texcoords[k] + 2 * (size_t)v, 2 * sizeof(double)))
            return 0;
    if (m->colors && memcmp(m->colors + 4 * (size_t)u, m->colors + 4 * (size_t)v, 4 * sizeof(double)))
        return 0;
    for (size_t e = 0; e < m->extra_count; ++e) {
        const resurf_attribute *a = &m->extras[e];
        if (a->data && memcmp(a->data + (size_t)a->components * u, a->data + (size_t)a->components * v,
                              a->components * sizeof(float)))
            return 0;
    }
    return 1;
}

static int has_attributes(const resurf_mesh *m)
{
    if (m->normals || m->colors || m->extra_count)
        return 1;
    for (unsigned k = 0; k < m->texcoord_count && k < RESURF_MAX_TEXCOORD_SETS; ++k)
        if (m->texcoords[k])
            return 1;
    return 0;
}

static resurf_status check_input(const resurf_mesh *in, resurf_error *error)
{
    if (in->triangle_count && !in->indices)
        return resurfi_error(error, RESURF_ERR_INVALID_MESH, "the mesh has triangles but no indices");
    if (in->vertex_count && !in->positions)
        return resurfi_error(error, RESURF_ERR_INVALID_MESH, "the mesh has vertices but no positions");
    if (in->triangle_count > (UINT32_MAX - 3) / 3 || in->vertex_count >= UINT32_MAX)
        return resurfi_error(error, RESURF_ERR_LIMIT, "%zu triangles and %zu vertices: simplification handles up to "
                             "%u triangles", in->triangle_count, in->vertex_count, (UINT32_MAX - 3) / 3);
    for (size_t t = 0; t < in->triangle_count; ++t)
        for (int k = 0; k < 3; ++k) {
            uint32_t v = in->indices[3 * t + k];
            if (v >= in->vertex_count)
                return resurfi_error(error, RESURF_ERR_INVALID_MESH, "triangle %zu refers to vertex %u of %zu", t, v,
                                     in->vertex_count);
            if (!v3_finite(resurfi_position(in, v)))
                return resurfi_error(error, RESURF_ERR_INVALID_MESH, "vertex %u has a non-finite position", v);
        }
    if (in->triangle_groups)
        for (size_t t = 0; t < in->triangle_count; ++t)
            if (in->triangle_groups[t] >= in->group_count && in->group_count)
                return resurfi_error(error, RESURF_ERR_INVALID_MESH, "triangle %zu is in group %u of %zu", t,
                                     in->triangle_groups[t], in->group_count);
    return RESURF_OK;
}

enum { FIN_DROP = 1, FIN_KEEP = 2 };

/* Triangle t, filed under its lowest position p, as the other two positions lo < hi and the way it runs: +1 for
 * (p, lo, hi), −1 for (p, hi, lo). */
static int fin_key(const resurf_mesh *in, const uint32_t *remap, uint32_t t, uint32_t p, uint32_t *lo, uint32_t *hi)
{
    const uint32_t *i = in->indices + 3 * (size_t)t;
    int k = remap[i[0]] == p ? 0 : remap[i[1]] == p ? 1 : 2;
    uint32_t u = remap[i[(k + 1) % 3]], w = remap[i[(k + 2) % 3]];
    *lo = u < w ? u : w;
    *hi = u < w ? w : u;
    return u < w ? 1 : -1;
}

/* The triangles drop_fins leaves out (see resurf_simplify_options): (*out_drop)[t] == FIN_DROP for them, or
 * *out_drop = NULL when there are none. Triangles over the same three positions share their lowest position, so
 * each is compared only with the few others filed under it. Of n+ triangles running one way and n− the other,
 * min(n+, n−) opposite pairs go, and of the rest all but the first. */
static resurf_status find_fins(simplifier *s, const uint32_t *remap, uint8_t **out_drop)
{
    const resurf_mesh *in = s->in;
    size_t nt = in->triangle_count, pc = s->pos_count;
    *out_drop = NULL;
    uint32_t *offset = resurfi_calloc(s->alloc, pc + 1, sizeof *offset);
    uint32_t *filed = resurfi_alloc(s->alloc, nt, sizeof *filed);
    uint8_t *drop = resurfi_calloc(s->alloc, nt, 1);
    size_t dropped = 0;
    if (!offset || !filed || !drop)
        goto oom;
    /* file every non-degenerate triangle under its lowest position */
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *i = in->indices + 3 * t;
        uint32_t a = remap[i[0]], b = remap[i[1]], c = remap[i[2]];
        if (a != b && b != c && a != c)
            offset[(a < b ? (a < c ? a : c) : (b < c ? b : c)) + 1]++;
    }
    for (size_t p = 0; p < pc; ++p)
        offset[p + 1] += offset[p];
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *i = in->indices + 3 * t;
        uint32_t a = remap[i[0]], b = remap[i[1]], c = remap[i[2]];
        if (a != b && b != c && a != c)
            filed[offset[a < b ? (a < c ? a : c) : (b < c ? b : c)]++] = (uint32_t)t;
    }
    for (size_t p = pc; p > 0; --p) /* back to the starts */
        offset[p] = offset[p - 1];
    offset[0] = 0;
    for (size_t p = 0; p < pc; ++p) {
        for (uint32_t x = offset[p]; x < offset[p + 1]; ++x) {
            uint32_t t = filed[x], lo, hi;
            if (drop[t])
                continue; /* decided with an earlier member of its group */
            int side = fin_key(in, remap, t, (uint32_t)p, &lo, &hi), balance = side;
            size_t members = 1;
            for (uint32_t y = x + 1; y < offset[p + 1]; ++y) {
                uint32_t lo2, hi2;
                int side2 = fin_key(in, remap, filed[y], (uint32_t)p, &lo2, &hi2);
                if (!drop[filed[y]] && lo2 == lo && hi2 == hi)
                    balance += side2, ++members;
            }
            if (members == 1)
                continue;
            /* the first member on the side with more members stays (none when the sides balance) */
            int keep = balance > 0 ? 1 : balance < 0 ? -1 : 0;
            for (uint32_t y = x; y < offset[p + 1]; ++y) {
                uint32_t lo2, hi2, m = filed[y];
                int side2 = fin_key(in, remap, m, (uint32_t)p, &lo2, &hi2);
                if (drop[m] || lo2 != lo || hi2 != hi)
                    continue;
                if (side2 == keep)
                    drop[m] = FIN_KEEP, keep = 0;
                else
                    drop[m] = FIN_DROP, ++dropped;
            }
        }
    }
    s->rep.dropped_fins = dropped;
    if (dropped) {
        *out_drop = drop;
        drop = NULL;
    }
    resurfi_free(s->alloc, offset);
    resurfi_free(s->alloc, filed);
    resurfi_free(s->alloc, drop);
    return RESURF_OK;
oom:
    resurfi_free(s->alloc, offset);
    resurfi_free(s->alloc, filed);
    resurfi_free(s->alloc, drop);
    return RESURF_ERR_OUT_OF_MEMORY;
}

typedef struct zero_job {
    unsigned char *base;
    size_t bytes;
} zero_job;

enum { ZERO_BLOCK = 1 << 18 };

static int zero_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    const zero_job *j = ctx;
    size_t from = begin * ZERO_BLOCK, to = end * ZERO_BLOCK < j->bytes ? end * ZERO_BLOCK : j->bytes;
    memset(j->base + from, 0, to - from);
    return 0;
}

/* resurfi_calloc(count, size) with the zeroing on the pool's threads: the first touch of a large block's pages is
 * what costs, and the threads then share it. */
static void *calloc_shared(const simplifier *s, size_t count, size_t size)
{
    if (count == 0 || size > SIZE_MAX / count)
        return resurfi_calloc(s->alloc, count, size);
    zero_job j = {resurfi_alloc(s->alloc, count, size), count * size};
    if (j.base)
        resurfi_pool_for(s->pool, (j.bytes + ZERO_BLOCK - 1) / ZERO_BLOCK, 1, zero_block, &j);
    return j.base;
}

static resurf_status prepare_mesh(simplifier *s, resurf_error *error)
{
    const resurf_mesh *in = s->in;
    size_t nv = in->vertex_count;
    uint32_t *remap = resurfi_alloc(s->alloc, nv, sizeof *remap);
    uint32_t *rep = resurfi_alloc(s->alloc, nv, sizeof *rep);
    uint32_t *first = NULL, *chain = NULL;
    uint8_t *drop = NULL;
    resurf_status st = RESURF_ERR_OUT_OF_MEMORY;
    if (!remap || !rep)
        goto done;
    size_t pc = 0;
    if ((st = resurfi_weld_exact(s->alloc, in->positions, nv, remap, &pc)) != RESURF_OK)
        goto done;
    st = RESURF_ERR_OUT_OF_MEMORY;
    s->pos_count = pc;
    s->remap = remap; /* for the restorer, which welds the same positions */

    /* Wedges: at each position, a vertex joins the lowest earlier vertex with equal attributes. Positions hold few
     * vertices, so the pairwise test is cheap. */
    if (!(first = resurfi_alloc(s->alloc, pc, sizeof *first)) || !(chain = resurfi_alloc(s->alloc, nv, sizeof *chain)))
        goto done;
    memset(first, 0xff, pc * sizeof *first);
    int attrs = has_attributes(in);
    for (size_t v = nv; v-- > 0;) {
        chain[v] = first[remap[v]];
        first[remap[v]] = (uint32_t)v;
    }
    for (size_t v = 0; v < nv; ++v) {
        rep[v] = (uint32_t)v;
        if (!attrs) {
            rep[v] = first[remap[v]];
            continue;
        }
        for (uint32_t u = first[remap[v]]; u < v; u = chain[u])
            if (same_attributes(in, u, (uint32_t)v)) {
                rep[v] = rep[u];
                break;
            }
    }

    if (s->opt.drop_fins && (st = find_fins(s, remap, &drop)) != RESURF_OK)
        goto done;
    st = RESURF_ERR_OUT_OF_MEMORY;
    size_t nt = 0;
    for (size_t t = 0; t < in->triangle_count; ++t) {
        const uint32_t *i = in->indices + 3 * t;
        uint32_t a = remap[i[0]], b = remap[i[1]], c = remap[i[2]];
        nt += a != b && b != c && a != c && !(drop && drop[t] == FIN_DROP);
    }
    s->tri_count = s->alive_tris = nt;
    s->tri = calloc_shared(s, nt, sizeof *s->tri);
    s->src = resurfi_alloc(s->alloc, nt, sizeof *s->src);
    /* the allocator promises malloc's alignment only: the block has room to align within */
    if (pc <= (SIZE_MAX - 63) / sizeof *s->P && (s->P_mem = calloc_shared(s, pc * sizeof *s->P + 63, 1)))
        s->P = (work_pos *)(((uintptr_t)s->P_mem + 63) & ~(uintptr_t)63);
    s->mark = resurfi_calloc(s->alloc, pc, sizeof *s->mark);
    if (!s->tri || !s->src || !s->P || !s->mark)
        goto done;
    nt = 0;
    double area = 0; /* for the quadrics' area floor (the input's positions: those of the working mesh) */
    for (size_t t = 0; t < in->triangle_count; ++t) {
        const uint32_t *i = in->indices + 3 * t;
        uint32_t a = remap[i[0]], b = remap[i[1]], c = remap[i[2]];
        if (a == b || b == c || a == c || (drop && drop[t] == FIN_DROP))
            continue;
        for (int k = 0; k < 3; ++k) {
            TV(3 * nt + k) = remap[i[k]];
            TW(3 * nt + k) = rep[i[k]];
        }
        area += 0.5 * v3_len(v3_tri_cross(resurfi_position(in, i[0]), resurfi_position(in, i[1]),
                                          resurfi_position(in, i[2])));
        s->src[nt++] = (uint32_t)t;
    }
    s->area_floor = nt ? AREA_FLOOR * area / (double)nt : 0;
    for (size_t v = 0; v < nv; ++v)
        s->P[remap[v]].p = resurfi_position(in, (uint32_t)v);
    /* Lists in increasing triangle order: insert from the back. The heads are built in the (still unused) marks,
     * 4 bytes per position, not in the 128-byte records: 3 random writes per triangle then stay in the cache. */
    uint32_t *head = s->mark;
    memset(head, 0xff, pc * sizeof *head);
    for (size_t c = 3 * nt; c-- > 0;) {
        TNEXT(c) = head[TV(c)];
        head[TV(c)] = (uint32_t)c;
    }
    for (size_t p = 0; p < pc; ++p) {
        s->P[p].head = head[p];
        if (head[p] == NONE)
            s->P[p].flags = POS_DEAD;
        else
            s->alive_positions++;
    }
    memset(head, 0, pc * sizeof *head);
    st = RESURF_OK;
done:
    if (s->remap != remap)
        resurfi_free(s->alloc, remap);
    resurfi_free(s->alloc, rep);
    resurfi_free(s->alloc, first);
    resurfi_free(s->alloc, chain);
    resurfi_free(s->alloc, drop);
    if (st == RESURF_ERR_OUT_OF_MEMORY)
        return resurfi_error(error, st, "out of memory preparing %zu triangles for simplification",
                             in->triangle_count);
    if (st != RESURF_OK)
        return resurfi_error(error, st, "cannot weld the mesh's positions");
    return RESURF_OK;
}

/* ---- phase 2: flags and quadrics per position ---------------------------------------------------------------- */

/* The plane through edge (p, q) perpendicular to triangle normal n (unit), as a quadric of weight w. */
static resurfi_quadric edge_plane(vec3 p, vec3 q, vec3 n, double w)
{
    vec3 m = v3_normalize(v3_cross(v3_sub(q, p), n));
    return resurfi_quadric_plane(m, -v3_dot(m, p), w);
}

/* Classifies position a from its fan (see POS_*); with out_q, also its quadric, with out_up the number of its
 * neighbours above a (its edges in the first list). Returns 0 when out of memory. */
static int analyse_position(simplifier *s, uint32_t a, scratch *sc, uint8_t *out_flags, resurfi_quadric *out_q,
                            uint32_t *out_up)
{
    if (!gather_fan(s, a, &sc->fan, 0))
        return 0;
    const u32vec *fan = &sc->fan;
    size_t n = fan_pairs(s, fan, sc);
    if (n == SIZE_MAX)
        return 0;
    uint8_t f = 0;
    for (size_t i = 0; i < fan->count; ++i)
        sc->uf[i] = (uint32_t)i;
    int seam_edges = 0;
    uint32_t wedges[3];
    int wedge_count = 0;
    for (size_t i = 0; i < fan->count && wedge_count < 3; ++i) {
        uint32_t w = TW(fan->data[i]);
        int seen = 0;
        for (int k = 0; k < wedge_count; ++k)
            seen |= wedges[k] == w;
        if (!seen)
            wedges[wedge_count++] = w;
    }
    resurfi_quadric q = {{0, 0, 0, 0, 0, 0}, {0, 0, 0}, 0, 0};
    if (out_q)
        for (size_t i = 0; i < fan->count; ++i) {
            uint32_t t = fan->data[i] / 3;
            resurfi_quadric tq = resurfi_quadric_triangle(v3_sub(s->P[TV(3 * t)].p, s->origin),
                                                          v3_sub(s->P[TV(3 * t + 1)].p, s->origin),
                                                          v3_sub(s->P[TV(3 * t + 2)].p, s->origin));
            if (tq.w > 0 && tq.w < s->area_floor) {
                double k = s->area_floor / tq.w;
                for (int j = 0; j < 6; ++j)
                    tq.a[j] *= k;
                for (int j = 0; j < 3; ++j)
                    tq.b[j] *= k;
                tq.c *= k;
                tq.w *= k;
            }
            resurfi_quadric_add(&q, &tq);
        }
    vec3 pa = s->P[a].p;
    uint32_t up = 0;
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && sc->pairs[j].x == sc->pairs[i].x)
            ++j;
        uint32_t x = sc->pairs[i].x;
        up += x > a;
        if (j - i == 1) {
            f |= POS_BORDER;
            if (out_q) {
                uint32_t c = fan->data[sc->pairs[i].slot / 2];
                uint32_t t = c / 3;
                vec3 n0 = v3_normalize(
                    v3_tri_cross(s->P[TV(3 * t)].p, s->P[TV(3 * t + 1)].p, s->P[TV(3 * t + 2)].p));
                double len2 = v3_dist2(pa, s->P[x].p);
                resurfi_quadric eq = edge_plane(v3_sub(pa, s->origin), v3_sub(s->P[x].p, s->origin), n0,
                                                s->opt.border_weight * len2);
                resurfi_quadric_add(&q, &eq);
            }
        } else if (j - i == 2) {
            uint32_t si = sc->pairs[i].slot, sj = sc->pairs[i + 1].slot;
            if ((si & 1) == (sj & 1))
                f |= POS_LOCKED; /* the edge is used twice in the same direction: orientation flips here */
            uint32_t ci = fan->data[si / 2], cj = fan->data[sj / 2];
            uint32_t ti = ci / 3, tj = cj / 3;
            uint32_t ra = uf_find(sc->uf, si / 2), rb = uf_find(sc->uf, sj / 2);
            if (ra != rb)
                sc->uf[ra < rb ? rb : ra] = ra < rb ? ra : rb;
            int seam_here = TW(ci) != TW(cj);
            int seam_there = TW(corner_at(s, ti, x)) != TW(corner_at(s, tj, x));
            seam_edges += seam_here;
            if (out_q && (seam_here || seam_there)) {
                /* Each side's triangle adds its own perpendicular plane, at half weight. */
                double len2 = v3_dist2(pa, s->P[x].p);
                for (int side = 0; side < 2; ++side) {
                    uint32_t t = side ? tj : ti;
                    vec3 n0 = v3_normalize(
                        v3_tri_cross(s->P[TV(3 * t)].p, s->P[TV(3 * t + 1)].p, s->P[TV(3 * t + 2)].p));
                    resurfi_quadric eq = edge_plane(v3_sub(pa, s->origin), v3_sub(s->P[x].p, s->origin), n0,
                                                    0.5 * s->opt.border_weight * len2);
                    resurfi_quadric_add(&q, &eq);
                }
            }
        } else {
            f |= POS_LOCKED;
        }
        i = j;
    }
    /* More than one fan of triangles around a (a bow tie): non-manifold. */
    for (size_t i = 1; i < fan->count; ++i)
        if (uf_find(sc->uf, (uint32_t)i) != uf_find(sc->uf, 0))
            f |= POS_LOCKED;
    if (wedge_count == 2 && seam_edges == 2 && !(f & POS_BORDER))
        f |= POS_SEAM;
    else if (wedge_count >= 2)
        f |= POS_COMPLEX;
    if ((f & POS_BORDER) && s->opt.lock_border)
        f |= POS_LOCKED_BORDER;
    *out_flags = f;
    if (out_q)
        *out_q = q;
    if (out_up)
        *out_up = up;
    return 1;
}

/* Charts: triangles connected across edges whose ends have the same wedges on both sides. A result vertex takes
 * its attributes from the closest input triangle of its wedge's chart, so texcoords never come from across a seam. */
static resurf_status find_charts(simplifier *s, scratch *sc)
{
    uint32_t *parent = resurfi_alloc(s->alloc, s->tri_count, sizeof *parent);
    s->chart_of_input_tri = resurfi_alloc(s->alloc, s->in->triangle_count, sizeof *s->chart_of_input_tri);
    s->chart_of_wedge = resurfi_alloc(s->alloc, s->in->vertex_count, sizeof *s->chart_of_wedge);
    if (!parent || !s->chart_of_input_tri || !s->chart_of_wedge) {
        resurfi_free(s->alloc, parent);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    for (size_t t = 0; t < s->tri_count; ++t)
        parent[t] = (uint32_t)t;
    for (size_t a = 0; a < s->pos_count; ++a) {
        if (s->P[a].flags & POS_DEAD)
            continue;
        if (!gather_fan(s, (uint32_t)a, &sc->fan, 0)) {
            resurfi_free(s->alloc, parent);
            return RESURF_ERR_OUT_OF_MEMORY;
        }
        size_t n = fan_pairs(s, &sc->fan, sc);
        if (n == SIZE_MAX) {
            resurfi_free(s->alloc, parent);
            return RESURF_ERR_OUT_OF_MEMORY;
        }
        for (size_t i = 0; i + 1 < n; ++i) {
            if (sc->pairs[i].x != sc->pairs[i + 1].x || sc->pairs[i].x < a ||
                (i + 2 < n && sc->pairs[i + 2].x == sc->pairs[i].x) || (i > 0 && sc->pairs[i - 1].x == sc->pairs[i].x))
                continue;
            uint32_t x = sc->pairs[i].x;
            uint32_t ci = sc->fan.data[sc->pairs[i].slot / 2], cj = sc->fan.data[sc->pairs[i + 1].slot / 2];
            uint32_t ti = ci / 3, tj = cj / 3;
            if (TW(ci) == TW(cj) && TW(corner_at(s, ti, x)) == TW(corner_at(s, tj, x))) {
                uint32_t ra = uf_find(parent, ti), rb = uf_find(parent, tj);
                if (ra != rb)
                    parent[ra < rb ? rb : ra] = ra < rb ? ra : rb;
            }
        }
    }
    memset(s->chart_of_input_tri, 0xff, s->in->triangle_count * sizeof *s->chart_of_input_tri);
    memset(s->chart_of_wedge, 0xff, s->in->vertex_count * sizeof *s->chart_of_wedge);
    for (size_t t = 0; t < s->tri_count; ++t) {
        uint32_t c = uf_find(parent, (uint32_t)t);
        s->chart_of_input_tri[s->src[t]] = c;
        for (int k = 0; k < 3; ++k)
            if (s->chart_of_wedge[TW(3 * t + k)] == NONE)
                s->chart_of_wedge[TW(3 * t + k)] = c;
    }
    resurfi_free(s->alloc, parent);
    return RESURF_OK;
}

/* ---- planning one collapse ----------------------------------------------------------------------------------- */

/* Q(p) for a quadric built around s->origin. */
static double qeval(const simplifier *s, const resurfi_quadric *q, vec3 p)
{
    return resurfi_quadric_eval(q, v3_sub(p, s->origin));
}

/* Counts a refused candidate in the report. */
static void count_block(resurf_simplify_report *r, int reason)
{
    if (reason == BLOCK_SEAM)
        r->blocked_seam++;
    else if (reason == BLOCK_BORDER)
        r->blocked_border++;
    else if (reason == BLOCK_NONMANIFOLD)
        r->blocked_nonmanifold++;
}

/* Where the free vertex of edge (a, b) goes. A seam edge keeps it on the segment (the minimiser of Q there): the
 * seam is a curve the restorer does not know, and off it the two sides' attributes would no longer meet. */
static vec3 free_placement(const simplifier *s, const resurfi_quadric *q, vec3 pa, vec3 pb, int on_segment)
{
    vec3 mid = v3_scale(v3_add(pa, pb), 0.5);
    if (s->opt.placement == RESURF_PLACEMENT_MIDPOINT)
        return mid;
    if (on_segment) {
        vec3 d = v3_sub(pb, pa), a0 = v3_sub(pa, s->origin);
        vec3 ad = resurfi_quadric_mul(q, d);
        double dad = v3_dot(d, ad);
        if (!(dad > 0))
            return mid;
        double t = -(v3_dot(ad, a0) + q->b[0] * d.x + q->b[1] * d.y + q->b[2] * d.z) / dad;
        t = t < 0 ? 0 : t > 1 ? 1 : t;
        return t == 0 ? pa : t == 1 ? pb : v3_lerp(pa, pb, t);
    }
    vec3 x;
    if (resurfi_quadric_optimum(q, v3_sub(mid, s->origin), &x)) {
        x = v3_add(x, s->origin);
        if (v3_dist2(x, mid) <= v3_dist2(pa, pb))
            return x;
    }
    /* Singular, or the optimum lies outside the edge's neighbourhood (a nearly flat quadric extrapolating): the
     * best of the three obvious points. */
    double ea = qeval(s, q, pa), eb = qeval(s, q, pb), em = qeval(s, q, mid);
    return em <= ea && em <= eb ? mid : ea <= eb ? pa : pb;
}

/* Plans collapsing edge (a, b), given a's fan (live corners). The rules, for removing x into y:
 *   x LOCKED / LOCKED_BORDER / COMPLEX        never
 *   x on a border                             only along a border edge (so y is on the same border)
 *   x a seam vertex (two wedges)              only along a seam edge whose triangles differ at y too, so each of
 *                                             x's wedges maps to its own wedge of y
 *   x with one wedge                          only if the edge's triangles share y's wedge (x's triangles then
 *                                             all take that wedge)
 * If both ends may go, the position is free (quadric or midpoint); if only x may go and y is held by one of the
 * rules above (y cannot leave its border, seam or place), the position is y's. */
static void plan_collapse(const simplifier *s, uint32_t a, uint32_t b, const u32vec *fan_a, plan *pl)
{
    memset(pl, 0, sizeof *pl);
    int n = 0;
    for (size_t i = 0; i < fan_a->count; ++i) {
        uint32_t c = fan_a->data[i];
        const uint32_t *v = s->tri[c / 3].v; /* a is one corner, so b is one of the others */
        if (v[0] == b || v[1] == b || v[2] == b) {
            if (n < 2)
                pl->shared[n] = c / 3;
            ++n;
        }
    }
    pl->shared_count = n;
    if (n == 0) {
        pl->block = BLOCK_STALE;
        return;
    }
    if (n > 2) {
        pl->block = BLOCK_NONMANIFOLD;
        return;
    }
    int border_edge = n == 1;
    int seam_a = 0, seam_b = 0;
    if (n == 2) {
        seam_a = TW(corner_at(s, pl->shared[0], a)) != TW(corner_at(s, pl->shared[1], a));
        seam_b = TW(corner_at(s, pl->shared[0], b)) != TW(corner_at(s, pl->shared[1], b));
    }
    uint8_t fa = s->P[a].flags, fb = s->P[b].flags;
    /* held: the end cannot move off its place along this edge */
    int reason_a = fa & POS_LOCKED ? BLOCK_NONMANIFOLD
                 : fa & POS_LOCKED_BORDER ? BLOCK_BORDER
                 : (fa & POS_BORDER) && !border_edge ? BLOCK_BORDER
                 : fa & POS_COMPLEX ? BLOCK_SEAM
                 : (fa & POS_SEAM) && !seam_a ? BLOCK_SEAM
                                              : BLOCK_NONE;
    int reason_b = fb & POS_LOCKED ? BLOCK_NONMANIFOLD
                 : fb & POS_LOCKED_BORDER ? BLOCK_BORDER
                 : (fb & POS_BORDER) && !border_edge ? BLOCK_BORDER
                 : fb & POS_COMPLEX ? BLOCK_SEAM
                 : (fb & POS_SEAM) && !seam_b ? BLOCK_SEAM
                                              : BLOCK_NONE;
    /* wedge maps: a seam end needs distinct images, a single-wedge end a single image */
    int map_a = (fa & POS_SEAM) ? seam_b : !seam_b;
    int map_b = (fb & POS_SEAM) ? seam_a : !seam_a;
    pl->a_removable = reason_a == BLOCK_NONE && map_a;
    pl->b_removable = reason_b == BLOCK_NONE && map_b;
    if (!pl->a_removable && !pl->b_removable) {
        int ra = reason_a != BLOCK_NONE ? reason_a : BLOCK_SEAM;
        int rb = reason_b != BLOCK_NONE ? reason_b : BLOCK_SEAM;
        pl->block = ra > rb ? ra : rb;
        return;
    }
    resurfi_quadric q = s->P[a].q;
    resurfi_quadric_add(&q, &s->P[b].q);
    vec3 pa = s->P[a].p, pb = s->P[b].p;
    int seam_edge = seam_a || seam_b;
    if (pl->a_removable && pl->b_removable) {
        pl->p = free_placement(s, &q, pa, pb, seam_edge);
    } else if (pl->a_removable) {
        pl->pinned = reason_b != BLOCK_NONE;
        pl->p = pl->pinned ? pb : free_placement(s, &q, pa, pb, seam_edge);
    } else {
        pl->pinned = reason_a != BLOCK_NONE;
        pl->p = pl->pinned ? pa : free_placement(s, &q, pa, pb, seam_edge);
    }
    pl->cost = qeval(s, &q, pl->p);
}

/* Restores p onto S of the original; `scale` is the length of the edges around p. *left is set when p stays where
 * it is: the restorer left it, or moved it implausibly far. A point near M moves onto S by about its distance to M
 * (M's own sag from S is far smaller), so a move beyond twice that distance plus a quarter of the local edge
 * length is a failure of the projection (seen near sliver triangles of scanned meshes), not a restoration; the
 * vertex then keeps its unrestored place rather than fold the mesh. `home` is a triangle of M near p: the
 * search for p's closest triangle walks from there (resurfi_restorer_point_walk). *out_home receives the triangle
 * p was restored on (NONE when left). */
static vec3 restore_point(const simplifier *s, vec3 p, double scale, uint32_t home, int *left, uint32_t *out_home)
{
    vec3 q;
    uint32_t t;
    resurfi_restore_outcome o = resurfi_restorer_point_walk(s->restorer, p, home, &q, &t, NULL);
    *left = o >= RESURFI_LEFT_FAR;
    *out_home = *left ? NONE : t;
    double moved = v3_dist(p, q);
    if (!*left && moved > 0.25 * scale) {
        double d2 = INFINITY, bary[3];
        resurfi_restorer_closest_walk(s->restorer, p, home, bary, &d2);
        if (!(moved <= 2 * sqrt(d2) + 0.25 * scale)) {
            *left = 1;
            *out_home = NONE;
            q = p;
        }
    }
    if (!*left)
        q = resurfi_restorer_limit_height(s->restorer, *out_home, q, RISE_LIMIT);
    return q;
}

/* The cost that ranks a planned collapse. */
static float rank_cost(const simplifier *s, uint32_t a, uint32_t b, const plan *pl)
{
    double cost = pl->cost;
    if (s->opt.cost_at_restored && s->restorer && !pl->pinned) {
        int left;
        uint32_t t;
        vec3 r = restore_point(s, pl->p, v3_dist(s->P[a].p, s->P[b].p), s->home[a], &left, &t);
        resurfi_quadric q = s->P[a].q;
        resurfi_quadric_add(&q, &s->P[b].q);
        cost = qeval(s, &q, r);
    }
    /* Costs are squared lengths times areas: divide by diagonal⁴ so that floats neither underflow nor overflow. */
    double d2 = s->diagonal * s->diagonal;
    double scaled = d2 > 0 ? cost / (d2 * d2) : cost;
    return scaled < FLT_MAX ? (float)scaled : FLT_MAX;
}

/* ---- the candidate list -------------------------------------------------------------------------------------- */

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

/* Sorts the n candidates of `from` by cost, stably, with `to` (n entries) as the second buffer: a radix sort from
 * the least significant of three 11-bit digits of the cost's key up, a digit all keys share skipped. Returns the
 * buffer that holds the result. Stable, so equal costs keep the order of the pass that planned them. */
static candidate *sort_stable(candidate *from, candidate *to, size_t n)
{
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

/* Grows the list to hold n candidates; 0 when out of memory. */
static int reserve_candidates(simplifier *s, size_t n)
{
    if (n <= s->cand_cap)
        return 1;
    size_t cap = n + n / 8 + 64;
    candidate *c = resurfi_realloc(s->alloc, s->cand, cap, sizeof *c);
    if (!c)
        return 0;
    s->cand = c;
    s->cand_cap = cap;
    return 1;
}

/* Appends n candidates to a fresh buffer (the simplifier's or a lane's); 0 when out of memory. */
static int append_fresh(const resurf_allocator *alloc, candidate **buf, size_t *count, size_t *cap,
                        const candidate *c, size_t n)
{
    if (n == 0)
        return 1;
    if (*count + n > *cap) {
        size_t want = *cap ? 2 * *cap : 1024;
        want = want < *count + n ? *count + n : want;
        candidate *f = resurfi_realloc(alloc, *buf, want, sizeof *f);
        if (!f)
            return 0;
        *buf = f;
        *cap = want;
    }
    memcpy(*buf + *count, c, n * sizeof *c);
    *count += n;
    return 1;
}

static int push_fresh(const simplifier *s, lane *L, candidate c)
{
    return append_fresh(s->alloc, &L->fresh, &L->fresh_count, &L->fresh_cap, &c, 1);
}

/* The top bits of gen: TAKEN marks an end of a candidate taken up by the current pass, CLAIMED a position of the
 * star of a candidate of the current chunk. */
enum { TAKEN = 0x80000000u, CLAIMED = 0x40000000u, GEN = 0x3fffffffu };

/* Position x changed: its candidates go stale. */
static void bump_gen(simplifier *s, uint32_t x)
{
    s->gen[x] = (s->gen[x] & ~GEN) | ((s->gen[x] + 1) & GEN);
}

/* Is candidate c still what its ends are? Generations only grow, so the sum matches only if neither changed. */
static int candidate_current(const simplifier *s, candidate c)
{
    return c.a != NONE && ((s->gen[c.a] + s->gen[c.b]) & GEN) == c.stamp;
}

/* Plans the candidates of position a (fan given) to every neighbour except `except` and those flagged POS_RENEW
 * (which plan their own), for the next pass. Returns 0 when out of memory. */
static int push_edges(simplifier *s, lane *L, uint32_t a, const u32vec *fan, uint32_t except)
{
    uint32_t st = next_stamp(s, L);
    for (size_t i = 0; i < fan->count; ++i) {
        uint32_t xs[2];
        corner_others(s, fan->data[i], xs);
        for (int k = 0; k < 2; ++k) {
            uint32_t x = xs[k];
            if (L->mark[x] == st || x == except || (s->P[x].flags & POS_RENEW))
                continue;
            L->mark[x] = st;
            plan pl;
            plan_collapse(s, a, x, fan, &pl);
            if (pl.block != BLOCK_NONE) {
                count_block(&L->rep, pl.block);
                continue;
            }
            candidate c = {rank_cost(s, a, x, &pl), a, x, (s->gen[a] + s->gen[x]) & GEN};
            if (!push_fresh(s, L, c))
                return 0;
        }
    }
    return 1;
}

/* The list for the next pass: the current candidates keep their places (their ends' quadrics and flags, hence
 * their costs, are the same); those planned during the pass are sorted and merged in. Three jobs, on the pool's
 * threads: each half of the list keeps its current candidates at its front, and the fresh ones are filtered and
 * sorted; then the second half's move down to meet the first's, and the sorted fresh ones are merged in from the
 * back. */
typedef struct refresh_job {
    simplifier *s;
    size_t half;         /* where the second half of the list starts */
    size_t kept[2];      /* current candidates of each half */
    size_t fresh_kept;
    const candidate *sorted; /* the current fresh ones, sorted (in s->fresh or s->sorted) */
} refresh_job;

/* Moves the current ones of the n candidates of c to its front; returns how many. */
static size_t keep_current(const simplifier *s, candidate *c, size_t n)
{
    size_t kept = 0;
    for (size_t i = 0; i < n; ++i) {
        if (i + 16 < n && c[i + 16].a != NONE) {
            PREFETCH(&s->gen[c[i + 16].a]);
            PREFETCH(&s->gen[c[i + 16].b]);
        }
        if (candidate_current(s, c[i]))
            c[kept++] = c[i];
    }
    return kept;
}

static int refresh_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    refresh_job *j = ctx;
    simplifier *s = j->s;
    for (size_t job = begin; job < end; ++job) {
        if (job == 2) {
            j->fresh_kept = keep_current(s, s->fresh, s->fresh_count);
            j->sorted = sort_stable(s->fresh, s->sorted, j->fresh_kept);
        } else {
            size_t lo = job == 0 ? 0 : j->half, hi = job == 0 ? j->half : s->cand_count;
            j->kept[job] = keep_current(s, s->cand + lo, hi - lo);
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

static int refresh_candidates(simplifier *s)
{
    if (s->fresh_count > s->sorted_cap) {
        candidate *buf = resurfi_realloc(s->alloc, s->sorted, s->fresh_cap, sizeof *buf);
        if (!buf)
            return 0;
        s->sorted = buf;
        s->sorted_cap = s->fresh_cap;
    }
    refresh_job j = {.s = s, .half = s->cand_count / 2};
    resurfi_pool_for(s->pool, 3, 1, refresh_block, &j);
    size_t n = j.kept[0] + j.kept[1], m = j.fresh_kept;
    if (j.kept[1])
        memmove(s->cand + j.kept[0], s->cand + j.half, j.kept[1] * sizeof *s->cand);
    if (!reserve_candidates(s, n + m))
        return 0;
    merge_job mj = {s->cand, j.sorted, j.sorted == s->fresh ? s->sorted : s->fresh, n, m, 0, (n + m) / 2};
    mj.i = merge_split(s->cand, n, j.sorted, m, mj.k);
    size_t copied = (mj.k < n ? mj.k : n) - mj.i; /* at most k - i <= m: the spare buffer holds as many as fresh */
    if (copied)
        memcpy(mj.spare, s->cand + mj.i, copied * sizeof *s->cand);
    resurfi_pool_for(s->pool, 2, 1, merge_block, &mj);
    s->cand_count = n + m;
    s->fresh_count = 0;
    return 1;
}

/* ---- phase 3: the first candidates --------------------------------------------------------------------------- */

typedef struct seed_job {
    simplifier *s;
    scratch *scratch;
    const size_t *offset; /* per position: its slots in the list */
} seed_job;

static int seed_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    seed_job *j = ctx;
    simplifier *s = j->s;
    scratch *sc = &j->scratch[worker];
    for (size_t a = begin; a < end; ++a) {
        candidate *slot = s->cand + j->offset[a];
        size_t room = j->offset[a + 1] - j->offset[a], used = 0;
        if (!(s->P[a].flags & POS_DEAD)) {
            if (!gather_fan(s, (uint32_t)a, &sc->fan, 0))
                return 1;
            size_t n = fan_pairs(s, &sc->fan, sc);
            if (n == SIZE_MAX)
                return 1;
            for (size_t i = 0; i < n; ++i) {
                uint32_t b = sc->pairs[i].x;
                if (b <= a || (i > 0 && sc->pairs[i - 1].x == b))
                    continue;
                plan pl;
                plan_collapse(s, (uint32_t)a, b, &sc->fan, &pl);
                if (pl.block != BLOCK_NONE) {
                    sc->blocked[pl.block]++;
                    continue;
                }
                slot[used++] = (candidate){rank_cost(s, (uint32_t)a, b, &pl), (uint32_t)a, b, 0};
            }
        }
        for (; used < room; ++used)
            slot[used].a = NONE;
    }
    return 0;
}

/* The first list: each position's edges to the neighbours above it (P[].up of them, from analyse_position) in
 * its own slots. */
static resurf_status seed_candidates(simplifier *s, scratch *scratch)
{
    size_t *offset = resurfi_alloc(s->alloc, s->pos_count + 1, sizeof *offset);
    if (!offset)
        return RESURF_ERR_OUT_OF_MEMORY;
    size_t total = 0;
    for (size_t p = 0; p < s->pos_count; ++p) {
        offset[p] = total;
        total += s->P[p].flags & POS_DEAD ? 0 : s->P[p].up;
    }
    offset[s->pos_count] = total;
    if (!reserve_candidates(s, total)) {
        resurfi_free(s->alloc, offset);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    seed_job job = {s, scratch, offset};
    if (resurfi_pool_for(s->pool, s->pos_count, BLOCK_POSITIONS, seed_block, &job)) {
        resurfi_free(s->alloc, offset);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    resurfi_free(s->alloc, offset);
    for (unsigned w = 0; w < s->threads; ++w)
        for (int reason = 0; reason < 5; ++reason) {
            size_t n = scratch[w].blocked[reason];
            s->rep.blocked_seam += reason == BLOCK_SEAM ? n : 0;
            s->rep.blocked_border += reason == BLOCK_BORDER ? n : 0;
            s->rep.blocked_nonmanifold += reason == BLOCK_NONMANIFOLD ? n : 0;
        }
    size_t n = 0;
    for (size_t i = 0; i < total; ++i)
        if (s->cand[i].a != NONE)
            s->cand[n++] = s->cand[i];
    sort_in_place(s->cand, n, 24);
    s->cand_count = n;
    return RESURF_OK;
}

/* ---- phase 4: collapsing ------------------------------------------------------------------------------------- */

/* Asks for what a collapse reads of the positions around a fan: their records (both cache lines: the checks read
 * their places, the new candidates their quadrics) and their marks (link_ok). One neighbour per corner covers a
 * closed fan. */
static void prefetch_ring(const simplifier *s, const lane *L, const u32vec *fan)
{
    for (size_t i = 0; i < fan->count; ++i) {
        uint32_t x = TV(corner_next(fan->data[i]));
        PREFETCH(&s->P[x]);
        PREFETCH(&s->P[x].q.c);
        PREFETCH(&L->mark[x]);
    }
}

/* Does collapsing (a, b) keep the mesh a manifold? The link condition: the positions adjacent to both a and b must
 * be exactly the third corners of the edge's triangles. Also refused: collapses that leave a double-sided sheet
 * (both ends also share a triangle with those two corners: a tetrahedron) or no triangle at all. */
static int link_ok(const simplifier *s, lane *L, const u32vec *fan_a, const u32vec *fan_b, uint32_t a, uint32_t b,
                   const plan *pl)
{
    if (fan_a->count + fan_b->count <= 2 * (size_t)pl->shared_count)
        return 0;
    uint32_t st = next_stamp(s, L);
    for (size_t i = 0; i < fan_a->count; ++i) {
        uint32_t xs[2];
        corner_others(s, fan_a->data[i], xs);
        L->mark[xs[0]] = st;
        L->mark[xs[1]] = st;
    }
    int common = 0;
    for (size_t i = 0; i < fan_b->count; ++i) {
        uint32_t xs[2];
        corner_others(s, fan_b->data[i], xs);
        for (int k = 0; k < 2; ++k)
            if (xs[k] != a && L->mark[xs[k]] == st) {
                L->mark[xs[k]] = st + 1; /* count once */
                ++common;
            }
    }
    if (common != pl->shared_count)
        return 0;
    if (pl->shared_count == 2) {
        uint32_t o[2] = {NONE, NONE};
        for (int k = 0; k < 2; ++k) {
            uint32_t t = pl->shared[k];
            for (int i = 0; i < 3; ++i)
                if (TV(3 * t + i) != a && TV(3 * t + i) != b)
                    o[k] = TV(3 * t + i);
        }
        int has[2] = {0, 0};
        const u32vec *fans[2] = {fan_a, fan_b};
        for (int side = 0; side < 2; ++side)
            for (size_t i = 0; i < fans[side]->count; ++i) {
                uint32_t c = fans[side]->data[i];
                uint32_t x = TV(corner_next(c)), y = TV(corner_prev(c));
                if ((x == o[0] && y == o[1]) || (x == o[1] && y == o[0]))
                    has[side] = 1;
            }
        if (has[0] && has[1])
            return 0;
    }
    return 1;
}

/* The smallest angle of a triangle, in degrees (0 for a degenerate one). */
static double min_angle_deg(vec3 p0, vec3 p1, vec3 p2)
{
    vec3 p[3] = {p0, p1, p2};
    double best = 180;
    for (int k = 0; k < 3; ++k) {
        vec3 u = v3_sub(p[(k + 1) % 3], p[k]), v = v3_sub(p[(k + 2) % 3], p[k]);
        double ang = atan2(v3_len(v3_cross(u, v)), v3_dot(u, v)) * (180.0 / M_PI);
        best = ang < best ? ang : best;
    }
    return best;
}

/* Does triangle t change shape in collapse pl (it is not one of the two that vanish)? If so, its corners before
 * (old, may be NULL) and after (neu) the ends a and b move to p. */
static int moved_triangle(const simplifier *s, uint32_t t, uint32_t a, uint32_t b, vec3 p, const plan *pl,
                          vec3 old[3], vec3 neu[3])
{
    if (t == pl->shared[0] || (pl->shared_count == 2 && t == pl->shared[1]))
        return 0;
    for (int k = 0; k < 3; ++k) {
        uint32_t v = TV(3 * t + k);
        if (old)
            old[k] = s->P[v].p;
        neu[k] = v == a || v == b ? p : s->P[v].p;
    }
    return 1;
}

/* Checks every triangle that changes (those of a and b except the edge's): no flip or fold beyond
 * max_normal_change_deg, no collapse to zero area, and the minimum-angle guard. Returns BLOCK_NONE (0), 1 for a
 * flip, 2 for an angle. */
static int geometry_ok(const simplifier *s, const u32vec *fan_a, const u32vec *fan_b, uint32_t a, uint32_t b,
                       vec3 p, const plan *pl)
{
    double cos_max = cos(s->opt.max_normal_change_deg * (M_PI / 180.0));
    const u32vec *fans[2] = {fan_a, fan_b};
    for (int side = 0; side < 2; ++side)
        for (size_t i = 0; i < fans[side]->count; ++i) {
            vec3 old[3], neu[3];
            if (!moved_triangle(s, fans[side]->data[i] / 3, a, b, p, pl, old, neu))
                continue;
            vec3 n0 = v3_tri_cross(old[0], old[1], old[2]), n1 = v3_tri_cross(neu[0], neu[1], neu[2]);
            double l0 = v3_len(n0), l1 = v3_len(n1);
            double longest = dmax(dmax(v3_dist2(neu[0], neu[1]), v3_dist2(neu[1], neu[2])), v3_dist2(neu[2], neu[0]));
            if (!(l1 > 1e-12 * longest))
                return 1;
            if (l0 > 0 && v3_dot(n0, n1) < cos_max * l0 * l1)
                return 1;
            if (s->opt.min_angle_deg > 0) {
                double after = min_angle_deg(neu[0], neu[1], neu[2]);
                if (after < s->opt.min_angle_deg && after < min_angle_deg(old[0], old[1], old[2]))
                    return 2;
            }
        }
    return 0;
}

/* How far (beyond the bound described at TIP_GUARD) an end's old position lies from its own triangles after they
 * move to p; 0 when both stay near. A one-sided Hausdorff bound that quadrics cannot see at a thin spike: its faces
 * lie nearly parallel to its axis, so moving the tip down the axis costs almost nothing, and collapse after
 * collapse shortens the spike. An end without triangles left (a fin's tip) has no surface to stay near. */
static double tip_excess(const simplifier *s, const u32vec *fan_a, const u32vec *fan_b, uint32_t a, uint32_t b,
                         vec3 p, const plan *pl, double err)
{
    const u32vec *fans[2] = {fan_a, fan_b};
    double bound = TIP_GUARD * v3_dist(s->P[a].p, s->P[b].p);
    bound = fmax(bound, TIP_ERROR * err);
    double excess = 0, bound2 = bound * bound;
    for (int side = 0; side < 2; ++side) {
        vec3 end = s->P[side ? b : a].p;
        double near2 = INFINITY;
        /* The first triangle within the bound settles this end (sqrt of a correctly rounded bound² is the bound). */
        for (size_t i = 0; i < fans[side]->count && !(near2 <= bound2); ++i) {
            vec3 neu[3];
            if (!moved_triangle(s, fans[side]->data[i] / 3, a, b, p, pl, NULL, neu))
                continue;
            double d2 = v3_dist2(end, resurfi_closest_on_triangle(end, neu[0], neu[1], neu[2], NULL));
            near2 = d2 < near2 ? d2 : near2;
        }
        if (near2 < INFINITY && sqrt(near2) - bound > excess)
            excess = sqrt(near2) - bound;
    }
    return excess;
}

/* The other side of the tip guard, for new edges longer than BRIDGE_RATIO × M's local edge length (late in a run):
 * how far (beyond the same bound) the midpoint of a new edge from p lies from M. A long edge may bridge a groove
 * or a notch whose walls the quadrics see as planes through its ends. Measured by walking M from `start`, a
 * triangle of M near p (so only with a restorer). Measured with bench_simplify on the dragon scan (871k triangles),
 * two-sided Hausdorff over meshoptimizer's at 2%: 0.86 before, 0.73 after (mean +0.2%; the 10% LOD does not
 * change). The ratio spares walks: 3 did no better. Against the mean edge length of M instead of the local one
 * (no look-up), the edge that decided the figure, 12 local edges long, went unchecked. */
static const double BRIDGE_RATIO = 6;

static double bridge_excess(const simplifier *s, lane *L, const u32vec *fan_a, const u32vec *fan_b, uint32_t a,
                            uint32_t b, vec3 p, const plan *pl, double err, uint32_t start)
{
    if (!s->restorer || start == NONE)
        return 0;
    double longest = BRIDGE_RATIO * resurfi_restorer_edge_length(s->restorer, start);
    uint32_t st = next_stamp(s, L); /* each neighbour once */
    double excess = 0;
    const u32vec *fans[2] = {fan_a, fan_b};
    for (int side = 0; side < 2; ++side)
        for (size_t i = 0; i < fans[side]->count; ++i) {
            uint32_t c = fans[side]->data[i], t = c / 3;
            if (t == pl->shared[0] || (pl->shared_count == 2 && t == pl->shared[1]))
                continue;
            uint32_t xs[2];
            corner_others(s, c, xs);
            for (int k = 0; k < 2; ++k) {
                uint32_t x = xs[k];
                if (x == a || x == b || L->mark[x] == st)
                    continue;
                L->mark[x] = st;
                double e = v3_dist(p, s->P[x].p);
                if (!(e > longest))
                    continue;
                double bary[3], d2 = INFINITY;
                vec3 mid = v3_scale(v3_add(p, s->P[x].p), 0.5);
                if (resurfi_restorer_closest_walk(s->restorer, mid, start, bary, &d2) == NONE)
                    continue;
                double over = sqrt(d2) - fmax(TIP_GUARD * e, TIP_ERROR * err);
                excess = over > excess ? over : excess;
            }
        }
    return excess;
}

/* Removes `gone` into `keep` at p, with the wedge map read from the edge's triangles. fan_keep and fan_gone are
 * the ends' fans before the collapse; L->fan_c receives keep's fan after it, L->touched the neighbours whose
 * flags must be recomputed (seam positions next to the edge) or whose blocked candidates are worth another try.
 * *refresh_keep is set when keep's flags must be recomputed from its fan. */
static int apply_collapse(simplifier *s, lane *L, uint32_t keep, uint32_t gone, vec3 p, const plan *pl,
                          const u32vec *fan_keep, const u32vec *fan_gone, int *refresh_keep)
{
    uint32_t from[2], to[2];
    int maps = pl->shared_count;
    for (int k = 0; k < maps; ++k) {
        from[k] = TW(corner_at(s, pl->shared[k], gone));
        to[k] = TW(corner_at(s, pl->shared[k], keep));
    }
    uint32_t opposite[2] = {NONE, NONE};
    for (int k = 0; k < maps; ++k) {
        uint32_t t = pl->shared[k];
        for (int i = 0; i < 3; ++i)
            if (TV(3 * t + i) != keep && TV(3 * t + i) != gone)
                opposite[k] = TV(3 * t + i);
        s->tri[t].dead = 1;
    }
    L->dead_tris += (size_t)maps;
    /* Re-label gone's live corners. keep's list becomes its fan after the collapse, gone's live corners first
     * (the order of splicing gone's list in front of keep's), without the dead corners either list held. */
    L->fan_c.count = 0;
    const u32vec *fans[2] = {fan_gone, fan_keep};
    for (int side = 0; side < 2; ++side)
        for (size_t i = 0; i < fans[side]->count; ++i) {
            uint32_t c = fans[side]->data[i];
            if (s->tri[c / 3].dead)
                continue;
            if (side == 0) {
                TV(c) = keep;
                uint32_t w = TW(c);
                TW(c) = maps == 1 || w == from[0] ? to[0] : w == from[1] ? to[1] : to[0];
            }
            if (!vec_push(s->alloc, &L->fan_c, c))
                return 0;
        }
    for (size_t i = 0; i < L->fan_c.count; ++i)
        TNEXT(L->fan_c.data[i]) = i + 1 < L->fan_c.count ? L->fan_c.data[i + 1] : NONE;
    s->P[keep].head = L->fan_c.count ? L->fan_c.data[0] : NONE;
    s->P[gone].head = NONE;
    s->P[keep].p = p;
    resurfi_quadric_add(&s->P[keep].q, &s->P[gone].q);
    /* Only wedges can change a position's flags here: the link condition keeps the mesh a manifold, a border vertex
     * goes only along its border (so keep was or becomes a border vertex) and the opposite corners keep their
     * border edges. Seam positions are analysed again. */
    uint8_t fk = s->P[keep].flags, fg = s->P[gone].flags;
    *refresh_keep = ((fk | fg) & (POS_SEAM | POS_COMPLEX)) != 0;
    s->P[keep].flags = (uint8_t)(fk | (fg & POS_BORDER));
    s->P[gone].flags = POS_DEAD;
    bump_gen(s, keep);
    bump_gen(s, gone);
    L->dead_positions++;

    /* Flags that may have changed: keep's, and the opposite corners' (they lost a triangle). A changed flag changes
     * that position's candidates: it is planned again, like a blocked neighbour. */
    L->touched.count = 0;
    uint32_t st = next_stamp(s, L);
    for (size_t i = 0; i < L->fan_c.count; ++i) {
        uint32_t xs[2];
        corner_others(s, L->fan_c.data[i], xs);
        for (int k = 0; k < 2; ++k) {
            uint32_t x = xs[k];
            if (L->mark[x] == st)
                continue;
            L->mark[x] = st;
            int again = (s->P[x].flags & POS_BLOCKED) != 0;
            if ((x == opposite[0] || x == opposite[1]) && (s->P[x].flags & (POS_SEAM | POS_COMPLEX)))
                again = 1;
            if (again && !vec_push(s->alloc, &L->touched, x))
                return 0;
        }
    }
    return 1;
}

/* Recomputes the flags of `v` (static locks are kept). Returns 0 when out of memory, else 1; *changed is set when
 * the flags differ. */
static int refresh_flags(simplifier *s, uint32_t v, scratch *sc, int *changed)
{
    uint8_t f;
    if (!analyse_position(s, v, sc, &f, NULL, NULL))
        return 0;
    uint8_t old = s->P[v].flags;
    uint8_t keep = old & (POS_LOCKED | POS_LOCKED_BORDER | POS_BLOCKED);
    /* lock_border freezes the input's borders only: a border created later (none: collapses keep borders) would
     * otherwise be locked as well. */
    f = (uint8_t)((f & ~POS_LOCKED_BORDER) | keep);
    s->P[v].flags = f;
    *changed = (f & ~POS_BLOCKED) != (old & ~POS_BLOCKED);
    return 1;
}

/* The start of the walk of a restoration `ahead` (1..3) places ahead in a loop, from position a's home: its home's
 * entry three ahead, then the triangle's corner ids, then what they point to (resurfi_restorer_prefetch). */
static void prefetch_walk(const simplifier *s, uint32_t a, size_t ahead)
{
    if (ahead >= 3)
        PREFETCH(&s->home[a]);
    else
        resurfi_restorer_prefetch(s->restorer, s->home[a], ahead == 1);
}

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
    scratch *sc = &j->scratch[worker];
    for (size_t i = begin; i < end; ++i) {
        pending *q = &s->pend[i];
        candidate c = s->cand[q->index];
        for (size_t k = 1; k <= 3 && i + k < end; ++k)
            prefetch_walk(s, s->cand[s->pend[i + k].index].a, k);
        q->restore = 0;
        if (!gather_fan(s, c.a, &sc->fan, 0))
            return 1;
        plan pl;
        plan_collapse(s, c.a, c.b, &sc->fan, &pl);
        if (pl.block != BLOCK_NONE || pl.pinned)
            continue;
        int left;
        q->p = pl.p;
        q->restored = restore_point(s, pl.p, v3_dist(s->P[c.a].p, s->P[c.b].p), s->home[c.a], &left, &q->home);
        q->left = (uint8_t)left;
        q->restore = 1;
    }
    return 0;
}

/* Tries the candidate of pending q: planned again on the current mesh, checked, restored, applied. A candidate
 * that is done or refused leaves the list; one whose cost went up, or that the tip guard defers, goes back in with
 * its new cost. New candidates, counters and scratch go to lane L. With `defer` (a chunk applied in parallel) the
 * neighbours to plan again are left in L->renew for plan_renewed (their edges reach beyond the star); q->keep
 * receives the surviving end. Returns 0 when out of memory. */
static int try_candidate(simplifier *s, pending *q, lane *L, scratch *sc, int defer)
{
    resurf_simplify_report *r = &L->rep;
    candidate *entry = &s->cand[q->index];
    candidate e = *entry;
    uint32_t a = e.a, b = e.b;
    entry->a = NONE;
    if (!candidate_current(s, e))
        return 1; /* an earlier collapse changed an end's flags: planned again */
    /* The ends' fans: gathered with the chunk's stars when applied in parallel (nothing in the star changed since) */
    u32vec view_a, view_b;
    const u32vec *fa = &L->fan_a, *fb = &L->fan_b;
    if (defer && q->window != NONE) {
        const window_entry *w = &s->win[q->window];
        uint32_t *words = s->stars + (size_t)q->window * STAR_MAX;
        view_a = (u32vec){words, w->na, w->na};
        view_b = (u32vec){words + w->na, w->nb, w->nb};
        fa = &view_a;
        fb = &view_b;
    } else { /* the lane's two fans, gathered together */
        u32vec pair[2] = {L->fan_a, L->fan_b};
        uint32_t ends[2] = {a, b};
        int ok = gather_fans(s, ends, 2, pair, 1);
        L->fan_a = pair[0];
        L->fan_b = pair[1];
        if (!ok)
            return 0;
    }
    prefetch_ring(s, L, fa);
    prefetch_ring(s, L, fb);
    plan pl;
    plan_collapse(s, a, b, fa, &pl);
    if (pl.block != BLOCK_NONE) {
        count_block(r, pl.block);
        return 1;
    }
    float now = rank_cost(s, a, b, &pl);
    if (now > e.cost * 1.000001f + FLT_MIN)
        return push_fresh(s, L, (candidate){now, a, b, e.stamp});
    if (!link_ok(s, L, fa, fb, a, b, &pl)) {
        r->blocked_link++;
        s->P[a].flags |= POS_BLOCKED;
        s->P[b].flags |= POS_BLOCKED;
        return 1;
    }
    /* Restored before the error and geometry checks: they judge the position the vertex will have. */
    resurfi_quadric qab = s->P[a].q;
    resurfi_quadric_add(&qab, &s->P[b].q);
    vec3 p = pl.p;
    int restored = 0, left = 0;
    uint32_t home = NONE;
    if (s->opt.restore == RESURF_RESTORE_INLINE && s->restorer && !pl.pinned) {
        if (q->restore && v3_dist2(q->p, pl.p) == 0) {
            p = q->restored;
            left = q->left;
            home = q->home;
        } else {
            p = restore_point(s, pl.p, v3_dist(s->P[a].p, s->P[b].p), s->home[a], &left, &home);
        }
        restored = 1;
    }
    double err = qab.w > 0 ? sqrt(qeval(s, &qab, p) / qab.w) : 0;
    if (err > s->max_error) {
        r->skipped_error++;
        L->skipped_error = 1;
        return 1;
    }
    int g = geometry_ok(s, fa, fb, a, b, p, &pl);
    if (g) {
        if (g == 1)
            r->blocked_flip++;
        else
            r->blocked_min_angle++;
        s->P[a].flags |= POS_BLOCKED;
        s->P[b].flags |= POS_BLOCKED;
        return 1;
    }
    /* The tip guard defers rather than refuses: such a collapse goes back into the list at its penalised cost (and
     * is done when its turn comes again), so targets stay reachable. */
    double excess = tip_excess(s, fa, fb, a, b, p, &pl, err);
    uint32_t near = home != NONE ? home : s->home ? s->home[a] : NONE; /* a triangle of M near p */
    excess = fmax(excess, bridge_excess(s, L, fa, fb, a, b, p, &pl, err, near));
    if (excess > 0) {
        double d2 = s->diagonal * s->diagonal;
        double cost = qeval(s, &qab, p) + TIP_PENALTY * qab.w * excess * excess;
        double scaled = d2 > 0 ? cost / (d2 * d2) : cost;
        float priced = scaled < FLT_MAX ? (float)scaled : FLT_MAX;
        if (e.cost < priced * 0.999999f) {
            r->blocked_distance++;
            return push_fresh(s, L, (candidate){priced, a, b, e.stamp});
        }
    }
    /* Which end survives: the one that must (held in place or not removable), else the one with more triangles
     * (fewer corners to relabel), else the lower id. */
    uint32_t keep, gone;
    if (!pl.a_removable)
        keep = a, gone = b;
    else if (!pl.b_removable)
        keep = b, gone = a;
    else if (fb->count > fa->count)
        keep = b, gone = a;
    else
        keep = a, gone = b;
    r->restored += (size_t)restored;
    r->restore_left += (size_t)left;
    if (err > r->max_error_estimate)
        r->max_error_estimate = err;
    r->collapses++;
    s->P[keep].flags &= (uint8_t)~POS_BLOCKED;
    int refresh_keep, changed = 0;
    if (!apply_collapse(s, L, keep, gone, p, &pl, keep == a ? fa : fb, keep == a ? fb : fa,
                        &refresh_keep))
        return 0;
    q->keep = keep;
    if (refresh_keep && !refresh_flags(s, keep, sc, &changed))
        return 0;
    if (home != NONE)
        s->home[keep] = home;
    size_t renew = 0;
    for (size_t i = 0; i < L->touched.count; ++i) {
        uint32_t x = L->touched.data[i];
        changed = 0;
        if ((s->P[x].flags & (POS_SEAM | POS_COMPLEX)) && !refresh_flags(s, x, sc, &changed))
            return 0;
        if (changed || (s->P[x].flags & POS_BLOCKED)) {
            s->P[x].flags &= (uint8_t)~POS_BLOCKED;
            bump_gen(s, x);
            L->touched.data[renew++] = x;
        }
    }
    /* Planned now, while their fans are in the cache. keep's candidates first (they reach every neighbour), then
     * those of renewed neighbours to the rest; each edge between two renewed neighbours is planned by the later
     * one. */
    if (!push_edges(s, L, keep, &L->fan_c, NONE))
        return 0;
    if (defer) {
        for (size_t i = 0; i < renew; ++i)
            if (!vec_push(s->alloc, &L->renew, L->touched.data[i]))
                return 0;
        return 1;
    }
    for (size_t i = 0; i < renew; ++i)
        s->P[L->touched.data[i]].flags |= POS_RENEW;
    int ok = 1;
    for (size_t i = 0; i < renew; ++i) {
        uint32_t x = L->touched.data[i];
        s->P[x].flags &= (uint8_t)~POS_RENEW;
        if (ok && !(gather_fan(s, x, &L->fan_b, 1) && push_edges(s, L, x, &L->fan_b, keep)))
            ok = 0;
    }
    return ok;
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
static int merge_lane(simplifier *s, lane *L)
{
    merge_lane_counts(s, L);
    int ok = append_fresh(s->alloc, &s->fresh, &s->fresh_count, &s->fresh_cap, L->fresh, L->fresh_count);
    L->fresh_count = 0;
    return ok;
}

/* Threads for a chunk's parallel steps (the result is the same for any number), and their pool (NULL: the calling
 * thread alone). */
static unsigned chunk_threads(const simplifier *s) { return s->chunk >= CHUNK_THREADS ? s->threads : 1; }
static resurfi_pool *chunk_pool(const simplifier *s) { return chunk_threads(s) > 1 ? s->pool : NULL; }

/* Whether this pass's chunks are of disjoint stars, applied in parallel. Chunks too small to be worth threads are
 * applied one collapse after the other, which needs no stars (gathering them was 7% of the time on a 20k sphere,
 * perf). Like the chunk size, a choice by counts only. */
static int star_pass(const simplifier *s) { return s->star_chunks && s->chunk >= CHUNK_THREADS; }

/* Opens a pass: the list brought up to date and the pass's cost limit. Returns 0 when out of memory. */
static int open_pass(simplifier *s)
{
    if (!refresh_candidates(s))
        return 0;
    s->pass_open = s->cand_count > 0;
    s->pass_next = 0;
    s->pass_before = s->rep.collapses;
    /* Stars of a chunk must be disjoint: the more of the mesh a chunk would cover, the more of its window's stars
     * meet claimed ones and are gathered again for the next chunk (on 20k triangles, chunks of 1024 made gathering
     * stars a sixth of the time). The size depends on the counts only, as the result must. */
    size_t chunk = s->alive_positions / CHUNK_SPREAD;
    s->chunk = chunk < CHUNK_MIN ? CHUNK_MIN : chunk > CHUNK ? CHUNK : chunk;
    s->window = s->chunk * WINDOW / CHUNK;
    if (s->pass_open) {
        size_t nth = (size_t)((double)s->cand_count * PASS_SHARE);
        nth = nth < 1 ? 1 : nth;
        s->pass_limit = s->cand[nth - 1].cost;
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
    scratch *sc = &j->scratch[worker];
    for (size_t k = begin; k < end;) {
        size_t group[GATHER_GROUP], n = 0;
        uint32_t ends[2 * GATHER_GROUP];
        for (; k < end && n < GATHER_GROUP; ++k) {
            window_entry *e = &s->win[k];
            candidate c = s->cand[e->index];
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
            window_entry *e = &s->win[group[i]];
            candidate c = s->cand[e->index];
            const u32vec *fa = &sc->group[2 * i], *fb = &sc->group[2 * i + 1];
            e->na = (uint32_t)fa->count;
            e->nb = (uint32_t)fb->count;
            e->count = gather_star(s, c, fa, fb, s->stars + group[i] * STAR_MAX, STAR_MAX);
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
    const window_entry *e = &s->win[k];
    candidate c = s->cand[e->index];
    if (e->count == 0 || ((s->gen[c.a] | s->gen[c.b]) & TAKEN))
        return 0;
    const uint32_t *star;
    size_t n = e->count;
    if (e->count == STAR_OVERFLOW) { /* a vertex of high valence: gathered here */
        lane *L = &s->lanes[0];
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
        star = s->stars + k * STAR_MAX + e->na + e->nb;
    }
    for (size_t i = 0; i < n; ++i)
        if (s->gen[star[i]] & CLAIMED)
            return 2;
    s->gen[c.a] |= TAKEN;
    s->gen[c.b] |= TAKEN;
    if (!vec_push(s->alloc, &s->taken, c.a) || !vec_push(s->alloc, &s->taken, c.b))
        return -1;
    for (size_t i = 0; i < n; ++i)
        if (!(s->gen[star[i]] & CLAIMED)) {
            s->gen[star[i]] |= CLAIMED;
            if (!vec_push(s->alloc, &s->claimed, star[i]))
                return -1;
        }
    uint32_t window = e->count == STAR_OVERFLOW ? NONE : (uint32_t)k;
    s->pend[s->pend_count++] = (pending){.index = e->index, .window = window};
    return 1;
}

/* Takes up the pass's next CHUNK candidates whose ends no earlier one of the pass took and whose stars are
 * disjoint (claim_candidate): first those an earlier chunk put aside (their stars met its claims), then the next
 * in the list. The stars of a window of candidates are gathered first, on all threads; the claims, in list order,
 * then only read their marks. Closes the pass when none is left under its limit. Past the limit, while the pass
 * has not done a collapse yet, one at a time (so a run of refused candidates at the front cannot make every pass a
 * walk over the whole list for one collapse). Returns 0 when out of memory. */
static int take_chunk_ends(simplifier *s);

static int take_chunk(simplifier *s, scratch *sc)
{
    if (!star_pass(s))
        return take_chunk_ends(s);
    for (size_t t = 0; t < s->claimed.count; ++t)
        s->gen[s->claimed.data[t]] &= ~CLAIMED;
    s->claimed.count = 0;
    s->pend_count = s->pend_next = 0;
    for (;;) {
        size_t n = 0;
        for (size_t k = 0; k < s->skip_count; ++k) /* in list order, all before pass_next */
            s->win[n++].index = s->skip[k];
        size_t nskip = n;
        for (size_t i = s->pass_next; n < nskip + s->window && i < s->cand_count; ++i) {
            if (s->cand[i].cost > s->pass_limit && s->rep.collapses > s->pass_before)
                break;
            s->win[n++].index = i;
        }
        chunk_job job = {s, sc};
        if (resurfi_pool_for(chunk_pool(s), n, 64, star_block, &job))
            return 0;
        s->skip_count = 0;
        size_t k = 0;
        for (; k < n && s->pend_count < s->chunk; ++k) {
            if (k >= nskip) {
                if (s->skip_count >= s->chunk)
                    break;
                candidate c = s->cand[s->win[k].index];
                if (c.cost > s->pass_limit && (s->rep.collapses > s->pass_before || s->pend_count > 0))
                    break;
            }
            if (k + 4 < n) { /* the marks the claim four ahead will read */
                const window_entry *ahead = &s->win[k + 4];
                if (ahead->count != STAR_OVERFLOW)
                    for (uint32_t i = 0; i < ahead->count; ++i)
                        PREFETCH(&s->gen[s->stars[(k + 4) * STAR_MAX + ahead->na + ahead->nb + i]]);
            }
            int r = claim_candidate(s, k);
            if (r < 0)
                return 0;
            if (r == 2)
                s->skip[s->skip_count++] = s->win[k].index;
        }
        if (k < nskip) {
            for (; k < nskip; ++k)
                s->skip[s->skip_count++] = s->win[k].index;
        } else {
            s->pass_next = k < n ? s->win[k].index : n > nskip ? s->win[n - 1].index + 1 : s->pass_next;
        }
        /* Nothing taken from a whole window that did not reach the limit: the next window. */
        if (s->pend_count > 0 || k < n || n == nskip || s->pass_next >= s->cand_count)
            break;
    }
    if (s->pend_count == 0) {
        for (size_t t = 0; t < s->taken.count; ++t)
            s->gen[s->taken.data[t]] &= ~TAKEN;
        s->taken.count = 0;
        s->skip_count = 0;
        s->pass_open = 0;
    }
    return 1;
}

/* take_chunk without stars, for chunks applied one collapse after the other: the pass's next CHUNK candidates
 * whose ends no earlier one of the pass took. Returns 0 when out of memory. */
static int take_chunk_ends(simplifier *s)
{
    s->pend_count = s->pend_next = 0;
    size_t i = s->pass_next;
    for (; s->pend_count < s->chunk && i < s->cand_count; ++i) {
        candidate c = s->cand[i];
        if (c.cost > s->pass_limit && (s->rep.collapses > s->pass_before || s->pend_count > 0))
            break;
        if (((s->gen[c.a] | s->gen[c.b]) & TAKEN) || !candidate_current(s, c))
            continue;
        s->gen[c.a] |= TAKEN;
        s->gen[c.b] |= TAKEN;
        if (!vec_push(s->alloc, &s->taken, c.a) || !vec_push(s->alloc, &s->taken, c.b))
            return 0;
        s->pend[s->pend_count++] = (pending){.index = i, .window = NONE};
    }
    s->pass_next = i;
    if (s->pend_count == 0) {
        for (size_t t = 0; t < s->taken.count; ++t)
            s->gen[s->taken.data[t]] &= ~TAKEN;
        s->taken.count = 0;
        s->pass_open = 0;
    }
    return 1;
}

/* Applies the chunk's collapses [begin, end) on worker `worker`: each into its worker's lane, its results' places
 * noted in its pending entry. */
static int apply_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    chunk_job *j = ctx;
    simplifier *s = j->s;
    lane *L = &s->lanes[worker];
    for (size_t i = begin; i < end; ++i) {
        pending *q = &s->pend[i];
        if (i + 2 < end) {
            candidate ahead = s->cand[s->pend[i + 2].index];
            PREFETCH(&s->P[ahead.a]);
            PREFETCH(&s->P[ahead.b]);
        }
        if (s->home && s->opt.restore == RESURF_RESTORE_INLINE)
            for (size_t k = 1; k <= 3 && i + k < end; ++k)
                prefetch_walk(s, s->cand[s->pend[i + k].index].a, k);
        q->worker = worker;
        q->fresh_begin = L->fresh_count;
        q->renew_begin = L->renew.count;
        if (!try_candidate(s, q, L, &j->scratch[worker], 1))
            return 1;
        q->fresh_end = L->fresh_count;
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
    for (size_t k = 0; k < s->pend_count; ++k) {
        const pending *q = &s->pend[k];
        const lane *L = &s->lanes[q->worker];
        size_t n = q->fresh_end - q->fresh_begin;
        if (n && !append_fresh(s->alloc, &s->fresh, &s->fresh_count, &s->fresh_cap, L->fresh + q->fresh_begin, n))
            return 0; /* (n = 0 may come with an empty lane: no pointer arithmetic on its NULL buffer) */
    }
    for (unsigned w = 0; w < s->threads; ++w) {
        s->lanes[w].fresh_count = 0;
        merge_lane_counts(s, &s->lanes[w]);
    }
    for (size_t k = 0; k < s->pend_count; ++k) {
        const pending *q = &s->pend[k];
        const lane *L = &s->lanes[q->worker];
        for (size_t i = q->renew_begin; i < q->renew_end; ++i)
            s->P[L->renew.data[i]].flags |= POS_RENEW;
    }
    lane *L0 = &s->lanes[0];
    int ok = 1;
    for (size_t k = 0; k < s->pend_count; ++k) {
        const pending *q = &s->pend[k];
        const lane *L = &s->lanes[q->worker];
        for (size_t i = q->renew_begin; i < q->renew_end; ++i) {
            uint32_t x = L->renew.data[i];
            s->P[x].flags &= (uint8_t)~POS_RENEW;
            if (ok && !(gather_fan(s, x, &L0->fan_b, 1) && push_edges(s, L0, x, &L0->fan_b, q->keep)))
                ok = 0;
        }
    }
    for (unsigned w = 0; w < s->threads; ++w)
        s->lanes[w].renew.count = 0;
    return merge_lane(s, L0) && ok;
}

/* Collapses until at most `target` triangles are left or nothing can be collapsed.
 *
 * The priority queue is a sorted array with lazy invalidation (generation stamps), taken in passes: a pass takes
 * the candidates in cost order up to a cost limit, each only if neither end was taken by an earlier one of the
 * same pass. A collapse changes only its ends' quadrics, so every other candidate's cost stays exact through the
 * pass and the order is the greedy one among independent collapses. The limit is the cost of the candidate at
 * PASS_SHARE of the list. The new candidates of a collapse are planned at once and wait for the next pass.
 *
 * A pass is taken in chunks of up to CHUNK candidates with disjoint closed stars (an end and its neighbours):
 * a collapse reads and writes its star's positions and its ends' triangles only, so the chunk's collapses are
 * applied on all threads, each as if alone, and their results merged in the chunk's order; the edges of renewed
 * neighbours, which reach outside the star, are planned after the chunk. Near the target (when the chunk could
 * remove all the triangles left above it) the chunk is applied one collapse after the other, stopping at the
 * target, with inline restoration planned and restored on all threads first; so are the chunks of passes whose
 * chunks are too small for threads, without stars (star_pass). Which way a chunk goes depends on the counts only:
 * the result is the same for every thread count.
 * Nothing depends on the target but where the work stops: a pass interrupted at one level goes on at the next, so
 * a LOD chain's level is the mesh a single call to its target makes. */
static resurf_status collapse_until(simplifier *s, size_t target, scratch *sc, resurf_error *error)
{
    size_t start = s->alive_tris;
    resurf_simplify_report *r = &s->rep;
    r->stop = RESURF_STOP_TARGET;
    s->skipped_error = 0;
    int batched = s->opt.restore == RESURF_RESTORE_INLINE && s->restorer && s->threads > 1;
    chunk_job job = {s, sc};
    lane *L0 = &s->lanes[0];
    while (s->alive_tris > target) {
        if (s->pend_next < s->pend_count) {
            size_t k = s->pend_next++;
            if (k + 2 < s->pend_count) {
                candidate ahead = s->cand[s->pend[k + 2].index];
                PREFETCH(&s->P[ahead.a]);
                PREFETCH(&s->P[ahead.b]);
            }
            if (!try_candidate(s, &s->pend[k], L0, sc, 0) || !merge_lane(s, L0))
                goto oom;
            if (s->pend_next == s->pend_count) {
                double done = start > target ? (double)(start - s->alive_tris) / (double)(start - target) : 1;
                if (resurfi_progress(&s->opt.progress, "simplify", done))
                    return resurfi_error(error, RESURF_ERR_CANCELLED, "simplification cancelled");
            }
            continue;
        }
        if (!s->pass_open) {
            if (!open_pass(s))
                goto oom;
            if (!s->pass_open) {
                r->stop = s->skipped_error ? RESURF_STOP_ERROR : RESURF_STOP_BLOCKED;
                break;
            }
        }
        if (!take_chunk(s, sc))
            goto oom;
        if (star_pass(s) && s->pend_count && s->alive_tris > target + 2 * s->pend_count) {
            /* each collapse removes at most two triangles: the whole chunk stays above the target */
            if (resurfi_pool_for(chunk_pool(s), s->pend_count, s->chunk / 64 + 1, apply_block, &job))
                goto oom;
            if (!finish_parallel_chunk(s))
                goto oom;
            s->pend_next = s->pend_count;
            double done = start > target ? (double)(start - s->alive_tris) / (double)(start - target) : 1;
            if (resurfi_progress(&s->opt.progress, "simplify", done))
                return resurfi_error(error, RESURF_ERR_CANCELLED, "simplification cancelled");
            continue;
        }
        if (batched && chunk_threads(s) > 1 &&
            resurfi_pool_for(chunk_pool(s), s->pend_count, s->chunk / 16 + 1, restore_chunk_block, &job))
            goto oom;
    }
    return RESURF_OK;
oom:
    return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory while simplifying");
}

/* ---- phase 5: the result ------------------------------------------------------------------------------------- */

/* One snapshot of the working mesh turned into a resurf_mesh. Used positions are numbered u = 0.. in order of
 * first use; output vertices are (position, wedge) pairs. */
typedef struct output {
    size_t nt, nu, nv;
    uint32_t *tris;       /* nt working triangles, in order */
    uint32_t *pos_index;  /* per position: its u, or NONE */
    uint32_t *upos;       /* per u: the position */
    uint32_t *ufirst;     /* per u: its first output vertex */
    uint32_t *ov_next, *ov_u, *ov_wedge; /* per output vertex */
    uint32_t *corner_ov;  /* 3 nt */
    vec3 *base;           /* per u: the position before the sag offset (on S with restoration) */
    vec3 *final;          /* per u: the output position */
    vec3 *normal;         /* per u: S's normal at base (sag offset only) */
    double *sag_sum;      /* per u */
    double *len;          /* per u: longest incident edge */
    uint32_t *sag_count;
    uint8_t *outcome;     /* per u: POST restoration left it (1) */
    double *area_prefix;  /* nt + 1 */
    double *block_max, *block_sum; /* per measurement block */
    size_t samples;
} output;

static void output_free(output *o, const resurf_allocator *alloc)
{
    resurfi_free(alloc, o->tris);
    resurfi_free(alloc, o->pos_index);
    resurfi_free(alloc, o->upos);
    resurfi_free(alloc, o->ufirst);
    resurfi_free(alloc, o->ov_next);
    resurfi_free(alloc, o->ov_u);
    resurfi_free(alloc, o->ov_wedge);
    resurfi_free(alloc, o->corner_ov);
    resurfi_free(alloc, o->base);
    resurfi_free(alloc, o->final);
    resurfi_free(alloc, o->normal);
    resurfi_free(alloc, o->sag_sum);
    resurfi_free(alloc, o->len);
    resurfi_free(alloc, o->sag_count);
    resurfi_free(alloc, o->outcome);
    resurfi_free(alloc, o->area_prefix);
    resurfi_free(alloc, o->block_max);
    resurfi_free(alloc, o->block_sum);
}

typedef struct output_job {
    simplifier *s;
    output *o;
    resurf_mesh *m;
} output_job;

static int post_restore_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    output_job *j = ctx;
    for (size_t u = begin; u < end; ++u) {
        for (size_t k = 1; k <= 3 && u + k < end; ++k)
            prefetch_walk(j->s, j->o->upos[u + k], k);
        int left;
        uint32_t t;
        j->o->base[u] = restore_point(j->s, j->o->base[u], j->o->len[u], j->s->home[j->o->upos[u]], &left, &t);
        j->o->outcome[u] = (uint8_t)left;
    }
    return 0;
}

static int normal_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    output_job *j = ctx;
    for (size_t u = begin; u < end; ++u) {
        for (size_t k = 1; k <= 3 && u + k < end; ++k)
            prefetch_walk(j->s, j->o->upos[u + k], k);
        double bary[3], d2;
        uint32_t t = resurfi_restorer_closest_walk(j->s->restorer, j->o->base[u], j->s->home[j->o->upos[u]], bary,
                                                   &d2);
        j->o->normal[u] = t == NONE ? v3(0, 0, 0) : resurfi_restorer_normal(j->s->restorer, t, bary);
    }
    return 0;
}

typedef struct chart_search {
    const uint32_t *chart_of_tri;
    uint32_t chart;
    uint32_t best;
    double best_d2;
    double bary[3];
} chart_search;

static int chart_visit(void *ctx, uint32_t t, vec3 point, const double bary[3], double d2)
{
    (void)point;
    chart_search *cs = ctx;
    if (cs->chart_of_tri[t] != cs->chart)
        return 0;
    if (d2 < cs->best_d2 || (d2 == cs->best_d2 && t < cs->best)) {
        cs->best = t;
        cs->best_d2 = d2;
        memcpy(cs->bary, bary, sizeof cs->bary);
    }
    return 0;
}

/* The input triangle that gives output vertex ov its attributes, with barycentrics: the closest one on the
 * vertex's side of any seam (its wedge's chart), else the closest one. */
static uint32_t attribute_source(const simplifier *s, const output *o, uint32_t ov, double bary[3])
{
    uint32_t u = o->ov_u[ov];
    vec3 p = o->base[u];
    double d2;
    uint32_t t = resurfi_bvh_closest(s->bvh, p, INFINITY, NULL, bary, &d2);
    if (t == NONE || !s->chart_of_wedge)
        return t;
    uint32_t chart = s->chart_of_wedge[o->ov_wedge[ov]];
    if (chart == NONE || s->chart_of_input_tri[t] == chart)
        return t;
    double reach = sqrt(d2) + o->len[u];
    chart_search cs = {s->chart_of_input_tri, chart, NONE, INFINITY, {0, 0, 0}};
    resurfi_bvh_within(s->bvh, p, reach * reach, chart_visit, &cs);
    if (cs.best == NONE)
        return t;
    memcpy(bary, cs.bary, sizeof cs.bary);
    return cs.best;
}

static int attribute_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    output_job *j = ctx;
    const simplifier *s = j->s;
    const resurf_mesh *in = s->in;
    resurf_mesh *m = j->m;
    for (size_t ov = begin; ov < end; ++ov) {
        double b[3];
        uint32_t t = attribute_source(s, j->o, (uint32_t)ov, b);
        uint32_t w = j->o->ov_wedge[ov];
        const uint32_t *idx = t == NONE ? NULL : in->indices + 3 * (size_t)t;
        if (m->normals) {
            vec3 n = v3(0, 0, 0);
            if (idx && s->restorer)
                n = resurfi_restorer_normal(s->restorer, t, b);
            else if (idx)
                for (int k = 0; k < 3; ++k)
                    n = v3_madd(n, v3_load(in->normals + 3 * (size_t)idx[k]), b[k]);
            n = v3_normalize(n);
            if (v3_len2(n) == 0)
                n = v3_load(in->normals + 3 * (size_t)w);
            v3_store(m->normals + 3 * ov, n);
        }
        for (unsigned k = 0; k < m->texcoord_count; ++k) {
            if (!m->texcoords[k])
                continue;
            const double *src = in->texcoords[k];
            for (int c = 0; c < 2; ++c) {
                double v = 0;
                if (idx)
                    for (int i = 0; i < 3; ++i)
                        v += b[i] * src[2 * (size_t)idx[i] + c];
                else
                    v = src[2 * (size_t)w + c];
                m->texcoords[k][2 * ov + c] = v;
            }
        }
        if (m->colors)
            for (int c = 0; c < 4; ++c) {
                double v = 0;
                if (idx)
                    for (int i = 0; i < 3; ++i)
                        v += b[i] * in->colors[4 * (size_t)idx[i] + c];
                else
                    v = in->colors[4 * (size_t)w + c];
                m->colors[4 * ov + c] = v;
            }
        for (size_t e = 0; e < m->extra_count; ++e) {
            const resurf_attribute *a = &in->extras[e];
            unsigned nc = a->components;
            for (unsigned c = 0; c < nc; ++c) {
                double v = 0;
                if (!a->data)
                    break;
                if (idx)
                    for (int i = 0; i < 3; ++i)
                        v += b[i] * (double)a->data[(size_t)nc * idx[i] + c];
                else
                    v = a->data[(size_t)nc * w + c];
                m->extras[e].data[(size_t)nc * ov + c] = (float)v;
            }
        }
    }
    return 0;
}

/* A deterministic uniform number in [0, 1) for sample i, stream k. */
static double sample_unit(uint64_t i, uint64_t k)
{
    uint64_t z = i * 0x9e3779b97f4a7c15ull + k * 0xd1b54a32d192ed03ull + 0x632be59bd9b4e019ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-53;
}

/* Blocks of area-uniform samples (stratified over the cumulative area), then the vertices. */
static int measure_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    output_job *j = ctx;
    const simplifier *s = j->s;
    const output *o = j->o;
    double mx = 0, sum = 0;
    double total = o->area_prefix[o->nt];
    for (size_t i = begin; i < end; ++i) {
        vec3 p;
        int is_sample = i < o->samples;
        if (is_sample) {
            double target = ((double)i + sample_unit(i, 0)) / (double)o->samples * total;
            size_t lo = 0, hi = o->nt - 1;
            while (lo < hi) { /* first triangle whose prefix end exceeds target */
                size_t mid = (lo + hi) / 2;
                if (o->area_prefix[mid + 1] > target)
                    hi = mid;
                else
                    lo = mid + 1;
            }
            const uint32_t *c = o->corner_ov + 3 * lo;
            vec3 p0 = o->final[o->ov_u[c[0]]], p1 = o->final[o->ov_u[c[1]]], p2 = o->final[o->ov_u[c[2]]];
            double r1 = sqrt(sample_unit(i, 1)), r2 = sample_unit(i, 2);
            p = v3_add(v3_add(v3_scale(p0, 1 - r1), v3_scale(p1, r1 * (1 - r2))), v3_scale(p2, r1 * r2));
        } else {
            p = o->final[i - o->samples];
        }
        double d2 = 0;
        if (resurfi_bvh_closest(s->bvh, p, INFINITY, NULL, NULL, &d2) == NONE)
            d2 = INFINITY;
        double d = sqrt(d2);
        mx = d > mx ? d : mx;
        if (is_sample)
            sum += d;
    }
    size_t block = begin / BLOCK_SAMPLES;
    o->block_max[block] = mx;
    o->block_sum[block] = sum;
    return 0;
}

/* Numbers the output vertices and positions of the current working mesh. */
static resurf_status number_output(simplifier *s, output *o)
{
    size_t nt = s->alive_tris;
    o->nt = nt;
    o->tris = resurfi_alloc(s->alloc, nt, sizeof *o->tris);
    o->pos_index = resurfi_alloc(s->alloc, s->pos_count, sizeof *o->pos_index);
    size_t cap_u = 3 * nt < s->pos_count ? 3 * nt : s->pos_count;
    o->upos = resurfi_alloc(s->alloc, cap_u, sizeof *o->upos);
    o->ufirst = resurfi_alloc(s->alloc, cap_u, sizeof *o->ufirst);
    /* Output vertices: at most one per corner, and at most one per input vertex: a wedge is an input vertex and
     * stays with its position (a collapse gives the removed end's corners the kept end's wedges), so no two
     * positions share one. The second bound is the smaller for all but the coarsest levels. */
    size_t cap_v = 3 * nt < s->in->vertex_count ? 3 * nt : s->in->vertex_count;
    o->ov_next = resurfi_alloc(s->alloc, cap_v, sizeof *o->ov_next);
    o->ov_u = resurfi_alloc(s->alloc, cap_v, sizeof *o->ov_u);
    o->ov_wedge = resurfi_alloc(s->alloc, cap_v, sizeof *o->ov_wedge);
    o->corner_ov = resurfi_alloc(s->alloc, 3 * nt, sizeof *o->corner_ov);
    if (!o->tris || !o->pos_index || !o->upos || !o->ufirst || !o->ov_next || !o->ov_u || !o->ov_wedge ||
        !o->corner_ov)
        return RESURF_ERR_OUT_OF_MEMORY;
    memset(o->pos_index, 0xff, s->pos_count * sizeof *o->pos_index);
    size_t k = 0;
    for (size_t t = 0; t < s->tri_count; ++t)
        if (!s->tri[t].dead)
            o->tris[k++] = (uint32_t)t;
    for (size_t i = 0; i < nt; ++i)
        for (int c = 0; c < 3; ++c) {
            uint32_t p = TV(3 * o->tris[i] + c), w = TW(3 * o->tris[i] + c);
            uint32_t u = o->pos_index[p];
            if (u == NONE) {
                u = o->pos_index[p] = (uint32_t)o->nu++;
                o->upos[u] = p;
                o->ufirst[u] = NONE;
            }
            uint32_t ov = o->ufirst[u];
            while (ov != NONE && o->ov_wedge[ov] != w)
                ov = o->ov_next[ov];
            if (ov == NONE) {
                if (o->nv == cap_v)
                    return RESURF_ERR_INTERNAL; /* the bound above broken: a bug, never a write past the end */
                ov = (uint32_t)o->nv++;
                o->ov_u[ov] = u;
                o->ov_wedge[ov] = w;
                o->ov_next[ov] = o->ufirst[u];
                o->ufirst[u] = ov;
            }
            o->corner_ov[3 * i + c] = ov;
        }
    return RESURF_OK;
}

/* len[u]: the longest edge at each used position (base positions). */
static void measure_edges(output *o)
{
    memset(o->len, 0, o->nu * sizeof *o->len);
    for (size_t i = 0; i < o->nt; ++i) {
        const uint32_t *c = o->corner_ov + 3 * i;
        for (int k = 0; k < 3; ++k) {
            uint32_t u = o->ov_u[c[k]], w = o->ov_u[c[(k + 1) % 3]];
            double l = v3_dist(o->base[u], o->base[w]);
            o->len[u] = l > o->len[u] ? l : o->len[u];
            o->len[w] = l > o->len[w] ? l : o->len[w];
        }
    }
}

/* Final positions: POST restoration, then the sag offset: each vertex moves along S's normal by sag_offset × the
 * mean over its incident triangle corners of −n·(p_w − p_v)/4 × (1 − h_M²/h²). For a vertex on S and a neighbour w
 * at chord length h where S bends by κ, −n·(p_w − p_v) ≈ h²κ/2, so the term is the chord's sag h²κ/8 less the sag
 * h_M²κ/8 of M's own edges (length h_M there): the facets straddle M, which lies under S by that much, and which
 * the reported distances measure against. At 10% and 2% the factor is 0.9 to 1; at 50% about 0.5. Measured with
 * bench_simplify, mean distance over meshoptimizer's: to the dragon scan at 50% 1.01 -> 0.51 (10%: 0.61 -> 0.55),
 * to the 20k sphere's true surface at 10% 0.23 -> 0.27, torus 0.36 -> 0.38, cubic unchanged, 2% within 2%. */
static resurf_status place_output(simplifier *s, output *o)
{
    size_t nu = o->nu;
    o->base = resurfi_alloc(s->alloc, nu, sizeof *o->base);
    o->final = resurfi_alloc(s->alloc, nu, sizeof *o->final);
    o->len = resurfi_calloc(s->alloc, nu, sizeof *o->len);
    if (!o->base || !o->final || !o->len)
        return RESURF_ERR_OUT_OF_MEMORY;
    for (size_t u = 0; u < nu; ++u)
        o->base[u] = s->P[o->upos[u]].p;
    if (s->last_level) { /* no more collapses: the working mesh goes before the output's arrays come */
        resurfi_free(s->alloc, s->P_mem);
        resurfi_free(s->alloc, s->tri);
        resurfi_free(s->alloc, s->mark);
        s->P_mem = NULL, s->P = NULL, s->tri = NULL, s->mark = NULL;
        if (s->lanes)
            for (unsigned w = 0; w < s->threads; ++w) {
                if (w > 0)
                    resurfi_free(s->alloc, s->lanes[w].mark);
                s->lanes[w].mark = NULL;
            }
    }
    measure_edges(o);
    output_job job = {s, o, NULL};
    if (s->opt.restore == RESURF_RESTORE_POST && s->restorer) {
        if (!(o->outcome = resurfi_alloc(s->alloc, nu, 1)))
            return RESURF_ERR_OUT_OF_MEMORY;
        resurfi_pool_for(s->pool, nu, BLOCK_POSITIONS, post_restore_block, &job);
        s->rep.restored += nu;
        for (size_t u = 0; u < nu; ++u)
            s->rep.restore_left += o->outcome[u];
    }
    int offset = s->restorer && s->opt.restore != RESURF_RESTORE_NONE && s->opt.sag_offset > 0;
    if (offset) {
        o->normal = resurfi_alloc(s->alloc, nu, sizeof *o->normal);
        o->sag_sum = resurfi_calloc(s->alloc, nu, sizeof *o->sag_sum);
        o->sag_count = resurfi_calloc(s->alloc, nu, sizeof *o->sag_count);
        if (!o->normal || !o->sag_sum || !o->sag_count)
            return RESURF_ERR_OUT_OF_MEMORY;
        resurfi_pool_for(s->pool, nu, BLOCK_POSITIONS, normal_block, &job);
    }
    if (s->opt.restore == RESURF_RESTORE_POST && s->restorer)
        measure_edges(o);
    for (size_t i = 0; i < o->nt && offset; ++i) {
        uint32_t u[3];
        for (int c = 0; c < 3; ++c)
            u[c] = o->ov_u[o->corner_ov[3 * i + c]];
        for (int c = 0; c < 3; ++c) {
            vec3 pv = o->base[u[c]];
            double hm = resurfi_restorer_edge_length(s->restorer, s->home[o->upos[u[c]]]); /* M's edges there */
            for (int d = 1; d < 3; ++d) {
                vec3 pw = o->base[u[(c + d) % 3]];
                double e2 = v3_dist2(pw, pv), keep = e2 > hm * hm ? 1 - hm * hm / e2 : 0;
                o->sag_sum[u[c]] -= keep * v3_dot(o->normal[u[c]], v3_sub(pw, pv));
                o->sag_count[u[c]]++;
            }
        }
    }
    for (size_t u = 0; u < nu; ++u) {
        o->final[u] = o->base[u];
        if (!offset || !o->sag_count[u])
            continue;
        double sag = s->opt.sag_offset * o->sag_sum[u] / (4.0 * o->sag_count[u]);
        double cap = 0.25 * o->len[u]; /* a fold or a spike, not a sag */
        sag = sag > cap ? cap : sag < -cap ? -cap : sag;
        o->final[u] = v3_madd(o->base[u], o->normal[u], sag);
    }
    return RESURF_OK;
}

static resurf_status measure_output(simplifier *s, output *o, resurf_simplify_report *rep)
{
    rep->max_distance = rep->mean_distance = rep->max_distance_rel = rep->mean_distance_rel = NAN;
    if (!s->opt.measure_samples || o->nt == 0 || !s->bvh)
        return RESURF_OK;
    o->area_prefix = resurfi_alloc(s->alloc, o->nt + 1, sizeof *o->area_prefix);
    if (!o->area_prefix)
        return RESURF_ERR_OUT_OF_MEMORY;
    o->area_prefix[0] = 0;
    for (size_t i = 0; i < o->nt; ++i) {
        const uint32_t *c = o->corner_ov + 3 * i;
        double a = 0.5 * v3_len(v3_tri_cross(o->final[o->ov_u[c[0]]], o->final[o->ov_u[c[1]]],
                                             o->final[o->ov_u[c[2]]]));
        o->area_prefix[i + 1] = o->area_prefix[i] + a;
    }
    o->samples = o->area_prefix[o->nt] > 0 ? s->opt.measure_samples : 0;
    size_t total = o->samples + o->nu;
    size_t blocks = (total + BLOCK_SAMPLES - 1) / BLOCK_SAMPLES;
    o->block_max = resurfi_alloc(s->alloc, blocks, sizeof *o->block_max);
    o->block_sum = resurfi_alloc(s->alloc, blocks, sizeof *o->block_sum);
    if (!o->block_max || !o->block_sum)
        return RESURF_ERR_OUT_OF_MEMORY;
    output_job job = {s, o, NULL};
    resurfi_pool_for(s->pool, total, BLOCK_SAMPLES, measure_block, &job);
    double mx = 0, sum = 0;
    for (size_t b = 0; b < blocks; ++b) {
        mx = o->block_max[b] > mx ? o->block_max[b] : mx;
        sum += o->block_sum[b];
    }
    rep->max_distance = mx;
    rep->mean_distance = o->samples ? sum / (double)o->samples : NAN;
    if (s->diagonal > 0) {
        rep->max_distance_rel = rep->max_distance / s->diagonal;
        rep->mean_distance_rel = rep->mean_distance / s->diagonal;
    }
    return RESURF_OK;
}

/* An empty mesh (or one of the given counts) with the input's attribute layout. */
static resurf_status create_like(const resurf_allocator *alloc, const resurf_mesh *in, size_t nv, size_t nt,
                                 resurf_mesh **out, resurf_error *error)
{
    unsigned attrs = 0;
    if (in->normals)
        attrs |= RESURF_ATTR_NORMALS;
    if (in->colors)
        attrs |= RESURF_ATTR_COLORS;
    for (unsigned k = 0; k < in->texcoord_count && k < RESURF_MAX_TEXCOORD_SETS; ++k)
        if (in->texcoords[k])
            attrs |= RESURF_ATTR_TEXCOORD0 << k;
    resurf_status st = resurf_mesh_create_with(nv, nt, attrs, alloc, out, error);
    if (st != RESURF_OK)
        return st;
    resurf_mesh *m = *out;
    m->texcoord_count = in->texcoord_count;
    if (in->colors)
        m->color_components = in->color_components;
    for (size_t e = 0; e < in->extra_count; ++e) {
        if ((st = resurf_mesh_add_extra(m, in->extras[e].name, in->extras[e].components, NULL, error)) != RESURF_OK)
            break;
    }
    if (st == RESURF_OK && in->triangle_groups && in->group_count) {
        m->triangle_groups = resurfi_calloc(&m->allocator, nt, sizeof *m->triangle_groups);
        m->group_names = resurfi_calloc(&m->allocator, in->group_count, sizeof *m->group_names);
        if (!m->triangle_groups || !m->group_names)
            st = RESURF_ERR_OUT_OF_MEMORY;
        else
            m->group_count = in->group_count;
        for (size_t g = 0; st == RESURF_OK && g < in->group_count; ++g) {
            const char *name = in->group_names[g] ? in->group_names[g] : "";
            size_t len = strlen(name);
            if (!(m->group_names[g] = resurfi_alloc(&m->allocator, len + 1, 1)))
                st = RESURF_ERR_OUT_OF_MEMORY;
            else
                memcpy(m->group_names[g], name, len + 1);
        }
        if (st == RESURF_ERR_OUT_OF_MEMORY)
            resurfi_error(error, st, "out of memory copying triangle groups");
    }
    if (st != RESURF_OK) {
        resurf_mesh_free(m);
        *out = NULL;
    }
    return st;
}

static resurf_status build_output(simplifier *s, resurf_mesh **out, resurf_simplify_report *rep, resurf_error *error)
{
    output o;
    memset(&o, 0, sizeof o);
    resurf_mesh *m = NULL;
    resurf_status st = number_output(s, &o);
    if (st == RESURF_OK)
        st = place_output(s, &o);
    if (st == RESURF_OK && (st = create_like(s->alloc, s->in, o.nv, o.nt, &m, error)) != RESURF_OK) {
        output_free(&o, s->alloc);
        return st;
    }
    if (st == RESURF_OK) {
        for (size_t v = 0; v < o.nv; ++v)
            v3_store(m->positions + 3 * v, o.final[o.ov_u[v]]);
        memcpy(m->indices, o.corner_ov, 3 * o.nt * sizeof *m->indices);
        if (m->triangle_groups)
            for (size_t i = 0; i < o.nt; ++i)
                m->triangle_groups[i] = s->in->triangle_groups[s->src[o.tris[i]]];
        if (has_attributes(s->in) && s->bvh) {
            output_job job = {s, &o, m};
            resurfi_pool_for(s->pool, o.nv, BLOCK_POSITIONS, attribute_block, &job);
        }
        *rep = s->rep;
        rep->triangles = o.nt;
        rep->vertices = o.nv;
        rep->positions = o.nu;
        st = measure_output(s, &o, rep);
    }
    output_free(&o, s->alloc);
    if (st != RESURF_OK) {
        resurf_mesh_free(m);
        return resurfi_error(error, st, st == RESURF_ERR_INTERNAL ? "internal error: a wedge at two positions"
                                                                  : "out of memory building the simplified mesh");
    }
    *out = m;
    return RESURF_OK;
}

/* ---- the public functions ------------------------------------------------------------------------------------ */

resurf_simplify_options resurf_simplify_options_default(void)
{
    resurf_simplify_options o;
    memset(&o, 0, sizeof o);
    o.struct_size = sizeof o;
    o.target_ratio = 0.5;
    o.placement = RESURF_PLACEMENT_QUADRIC;
    o.restore = RESURF_RESTORE_INLINE;
    o.sag_offset = 1.0;
    o.max_normal_change_deg = 60;
    o.border_weight = 1;
    o.drop_fins = 1;
    o.measure_samples = 100000;
    return o;
}

static resurf_status check_options(const resurf_simplify_options *o, resurf_error *error)
{
    RESURFI_CHECK_OPTIONS_ALLOC(o, resurf_simplify_options, error);
    if (!o)
        return RESURF_OK;
    const char *bad = NULL;
    if (!(o->target_ratio >= 0 && o->target_ratio <= 1))
        bad = "target_ratio must be in [0, 1]";
    else if (!(o->max_error >= 0 && isfinite(o->max_error)))
        bad = "max_error must be finite and >= 0";
    else if (!(o->max_error_rel >= 0 && isfinite(o->max_error_rel)))
        bad = "max_error_rel must be finite and >= 0";
    else if ((unsigned)o->placement >= RESURF_PLACEMENT_COUNT)
        bad = "placement is not a resurf_placement";
    else if ((unsigned)o->restore >= RESURF_RESTORE_MODE_COUNT)
        bad = "restore is not a resurf_restore_mode";
    else if (!(o->sag_offset >= 0 && o->sag_offset <= 4))
        bad = "sag_offset must be in [0, 4]";
    else if (!(o->min_angle_deg >= 0 && o->min_angle_deg < 60))
        bad = "min_angle_deg must be in [0, 60)";
    else if (!(o->max_normal_change_deg > 0 && o->max_normal_change_deg <= 180))
        bad = "max_normal_change_deg must be in (0, 180]";
    else if (!(o->border_weight >= 0 && isfinite(o->border_weight)))
        bad = "border_weight must be finite and >= 0";
    else if (o->restore_options && o->restore_options->struct_size != sizeof(resurf_restore_options))
        bad = "restore_options was not initialised by resurf_restore_options_default()";
    else if (o->thread_pool && !o->thread_pool->run)
        bad = "thread_pool has no run callback";
    if (bad)
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "resurf_simplify_options: %s", bad);
    return RESURF_OK;
}

static void simplifier_free(simplifier *s)
{
    resurfi_free(s->alloc, s->remap);
    resurfi_free(s->alloc, s->tri);
    resurfi_free(s->alloc, s->src);
    resurfi_free(s->alloc, s->P_mem);
    resurfi_free(s->alloc, s->mark);
    resurfi_free(s->alloc, s->chart_of_input_tri);
    resurfi_free(s->alloc, s->chart_of_wedge);
    resurfi_free(s->alloc, s->cand);
    resurfi_free(s->alloc, s->fresh);
    resurfi_free(s->alloc, s->sorted);
    resurfi_free(s->alloc, s->taken.data);
    resurfi_free(s->alloc, s->gen);
    resurfi_free(s->alloc, s->home);
    resurfi_free(s->alloc, s->claimed.data);
    resurfi_free(s->alloc, s->skip);
    resurfi_free(s->alloc, s->win);
    resurfi_free(s->alloc, s->stars);
    if (s->lanes)
        for (unsigned w = 0; w < s->threads; ++w) {
            lane *L = &s->lanes[w];
            resurfi_free(s->alloc, L->fan_a.data);
            resurfi_free(s->alloc, L->fan_b.data);
            resurfi_free(s->alloc, L->fan_c.data);
            resurfi_free(s->alloc, L->touched.data);
            resurfi_free(s->alloc, L->renew.data);
            resurfi_free(s->alloc, L->fresh);
            if (w > 0)
                resurfi_free(s->alloc, L->mark);
        }
    resurfi_free(s->alloc, s->lanes);
    resurfi_free(s->alloc, s->pend);
    resurfi_restorer_free(s->restorer);
    resurfi_bvh_free(s->own_bvh);
    resurfi_pool_free(s->pool);
}

/* The analysis, BLOCK_POSITIONS positions a job, with the restorer's set-up beside it: the two share nothing, so the
 * calling thread (worker 0) builds the restorer first, its loops on that thread alone, while the other threads
 * analyse; then it joins them. */
typedef struct setup_job {
    simplifier *s;
    scratch *scratch;  /* one per worker */
    int build_restorer; /* still to be built */
    resurf_restore_options restore_options;
    resurf_status restorer_status;
    resurf_error restorer_error;
} setup_job;

static int build_restorer(setup_job *j)
{
    simplifier *s = j->s;
    j->build_restorer = 0;
    /* Without its tree: every restored point has a triangle of M nearby to walk from (home). */
    j->restorer_status = resurfi_restorer_create_ex(s->in, &j->restore_options, 0, s->remap, s->pos_count,
                                                    &s->restorer, &j->restorer_error);
    return j->restorer_status == RESURF_OK;
}

static int setup_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    setup_job *j = ctx;
    simplifier *s = j->s;
    if (worker == 0 && j->build_restorer && !build_restorer(j))
        return 1;
    for (size_t p = begin * BLOCK_POSITIONS; p < end * BLOCK_POSITIONS && p < s->pos_count; ++p) {
        if (s->P[p].flags & POS_DEAD)
            continue;
        uint8_t f;
        if (!analyse_position(s, (uint32_t)p, &j->scratch[worker], &f, &s->P[p].q, &s->P[p].up))
            return 1;
        s->P[p].flags = f;
    }
    return 0;
}

/* Everything up to the first candidate: input checks, the working mesh, the restorer or a BVH, flags, quadrics,
 * charts and the first candidates. */
static resurf_status start(simplifier *s, scratch *scratch, resurf_error *error)
{
    resurf_status st = check_input(s->in, error);
    if (st != RESURF_OK)
        return st;
    double lo[3], hi[3];
    s->diagonal = resurf_mesh_bounds(s->in, lo, hi);
    s->origin = v3(0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2]));
    double bound = INFINITY;
    if (s->opt.max_error > 0)
        bound = s->opt.max_error;
    if (s->opt.max_error_rel > 0 && s->opt.max_error_rel * s->diagonal < bound)
        bound = s->opt.max_error_rel * s->diagonal;
    s->max_error = bound;
    if ((st = prepare_mesh(s, error)) != RESURF_OK)
        return st;
    s->rep.input_triangles = s->tri_count;
    s->rep.input_positions = s->alive_positions;
    s->rep.diagonal = s->diagonal;
    if (s->tri_count == 0)
        return RESURF_OK;
    setup_job sj = {.s = s, .scratch = scratch, .restorer_status = RESURF_OK};
    if (s->opt.restore != RESURF_RESTORE_NONE) {
        resurf_restore_options ro = resurf_restore_options_default();
        /* Max's normals, not the jet fit, unless asked: a LOD's distance to S is set by the chord sag, not by the
         * restorer's last digits (the analytic benchmark's figures agree to 2%), and the fit costs about a second
         * per million triangles. */
        ro.normals = RESURF_NORMALS_MAX;
        if (s->opt.restore_options)
            ro = *s->opt.restore_options;
        ro.threads = 1;
        ro.progress = (resurf_progress){NULL, NULL};
        ro.allocator = s->alloc;
        sj.restore_options = ro;
        sj.build_restorer = 1;
    }
    if (resurfi_progress(&s->opt.progress, "prepare", 0.5))
        return resurfi_error(error, RESURF_ERR_CANCELLED, "simplification cancelled");
    size_t blocks = (s->pos_count + BLOCK_POSITIONS - 1) / BLOCK_POSITIONS;
    int analysed = !resurfi_pool_for(s->pool, blocks, 1, setup_block, &sj);
    if (analysed && sj.build_restorer) /* the other threads took every block */
        build_restorer(&sj);
    if (!analysed || sj.restorer_status != RESURF_OK) {
        if (sj.restorer_status == RESURF_OK)
            return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory analysing the mesh");
        if (error)
            *error = sj.restorer_error;
        return sj.restorer_status;
    }
    if (s->restorer) {
        if (!(s->home = resurfi_alloc(s->alloc, s->pos_count, sizeof *s->home)))
            return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
        for (size_t p = 0; p < s->pos_count; ++p) /* the input triangle of its first corner */
            s->home[p] = s->P[p].head != NONE ? s->src[s->P[p].head / 3] : NONE;
    }
    resurfi_free(s->alloc, s->remap);
    s->remap = NULL;
    if (has_attributes(s->in) || s->opt.measure_samples) { /* with a host pool, no thread of ours: one */
        st = resurfi_bvh_build_threads(s->alloc, s->in->positions, s->in->vertex_count, s->in->indices,
                                       s->in->triangle_count, s->opt.thread_pool ? 1 : s->opt.threads,
                                       &s->own_bvh);
        if (st != RESURF_OK)
            return resurfi_error(error, st, "cannot build the input's BVH");
        s->bvh = s->own_bvh;
    }
    int seams = 0;
    for (size_t p = 0; p < s->pos_count && !seams; ++p)
        seams = (s->P[p].flags & (POS_SEAM | POS_COMPLEX)) != 0;
    if (seams && has_attributes(s->in) && find_charts(s, &scratch[0]) != RESURF_OK)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory finding attribute charts");
    if (!(s->gen = resurfi_calloc(s->alloc, s->pos_count, sizeof *s->gen)))
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    st = seed_candidates(s, scratch);
    if (st != RESURF_OK)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory queueing %zu edges",
                             3 * s->tri_count / 2);
    if (!(s->pend = resurfi_alloc(s->alloc, CHUNK, sizeof *s->pend)) ||
        !(s->skip = resurfi_alloc(s->alloc, CHUNK, sizeof *s->skip)) ||
        !(s->win = resurfi_alloc(s->alloc, CHUNK + WINDOW, sizeof *s->win)) ||
        !(s->stars = resurfi_alloc(s->alloc, (CHUNK + WINDOW) * (size_t)STAR_MAX, sizeof *s->stars)) ||
        !(s->lanes = resurfi_calloc(s->alloc, s->threads, sizeof *s->lanes)))
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    /* With chunks applied in parallel, each further thread has its own marks: 4 bytes per position. */
    s->star_chunks = s->opt.restore == RESURF_RESTORE_INLINE && s->restorer ? PARALLEL_INLINE : PARALLEL_PLAIN;
    s->lanes[0].mark = s->mark;
    for (unsigned w = 1; w < s->threads && s->star_chunks; ++w)
        if (!(s->lanes[w].mark = resurfi_calloc(s->alloc, s->pos_count, sizeof *s->lanes[w].mark)))
            return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    if (resurfi_progress(&s->opt.progress, "prepare", 1))
        return resurfi_error(error, RESURF_ERR_CANCELLED, "simplification cancelled");
    return RESURF_OK;
}

/* The shared worker: one run of collapses, a snapshot at each target (non-increasing). */
static resurf_status simplify_levels(const resurf_mesh *in, const resurf_simplify_options *options,
                                     const size_t *targets, size_t count, resurf_mesh **outs,
                                     resurf_simplify_report *reports, resurf_error *error)
{
    simplifier s;
    memset(&s, 0, sizeof s);
    s.in = in;
    s.opt = options ? *options : resurf_simplify_options_default();
    s.threads = resurfi_thread_count(s.opt.threads);
    s.alloc = resurfi_allocator_of(s.opt.allocator, in);
    scratch *sc = resurfi_calloc(s.alloc, s.threads, sizeof *sc);
    if (!sc)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory starting the simplification");
    for (unsigned w = 0; w < s.threads; ++w)
        sc[w].alloc = s.alloc;
    resurf_status st = resurfi_pool_create(s.alloc, s.threads, s.opt.thread_pool, &s.pool);
    if (st != RESURF_OK)
        st = resurfi_error(error, st, "out of memory starting the simplification");
    else if (resurfi_progress(&s.opt.progress, "prepare", 0))
        st = resurfi_error(error, RESURF_ERR_CANCELLED, "simplification cancelled");
    if (st == RESURF_OK)
        st = start(&s, sc, error);
    for (size_t i = 0; i < count && st == RESURF_OK; ++i) {
        if (s.tri_count)
            st = collapse_until(&s, targets[i], sc, error);
        else
            s.rep.stop = RESURF_STOP_TARGET;
        if (st == RESURF_OK && resurfi_progress(&s.opt.progress, "finish", (double)i / (double)count))
            st = resurfi_error(error, RESURF_ERR_CANCELLED, "simplification cancelled");
        if (i + 1 == count) { /* no more collapses: the queue's memory goes before the output's comes */
            s.last_level = 1;
            resurfi_free(s.alloc, s.cand);
            resurfi_free(s.alloc, s.fresh);
            resurfi_free(s.alloc, s.sorted);
            s.cand = s.fresh = s.sorted = NULL;
            s.cand_count = s.cand_cap = s.fresh_count = s.fresh_cap = s.sorted_cap = 0;
        }
        resurf_simplify_report rep;
        if (st == RESURF_OK)
            st = build_output(&s, &outs[i], &rep, error);
        if (st == RESURF_OK && reports)
            reports[i] = rep;
    }
    if (st == RESURF_OK && resurfi_progress(&s.opt.progress, "finish", 1))
        st = resurfi_error(error, RESURF_ERR_CANCELLED, "simplification cancelled");
    for (unsigned w = 0; w < s.threads; ++w)
        scratch_free(&sc[w]);
    resurfi_free(s.alloc, sc);
    simplifier_free(&s);
    if (st != RESURF_OK)
        for (size_t i = 0; i < count; ++i) {
            resurf_mesh_free(outs[i]);
            outs[i] = NULL;
        }
    return st;
}

resurf_status resurf_simplify(const resurf_mesh *in, const resurf_simplify_options *options, resurf_mesh **out,
                              resurf_simplify_report *out_report, resurf_error *error)
{
    resurfi_clear_error(error);
    if (!out)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "out is NULL");
    *out = NULL;
    if (!in)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "the input mesh is NULL");
    resurf_status st = check_options(options, error);
    if (st != RESURF_OK)
        return st;
    resurf_simplify_options o = options ? *options : resurf_simplify_options_default();
    /* Whichever target comes first is the larger triangle count. */
    size_t target = 0;
    if (o.target_triangles)
        target = o.target_triangles;
    if (o.target_ratio > 0) {
        size_t r = (size_t)floor(o.target_ratio * (double)in->triangle_count * (1 + 1e-12));
        target = r > target ? r : target;
    }
    resurf_simplify_report rep;
    st = simplify_levels(in, &o, &target, 1, out, out_report ? &rep : NULL, error);
    if (st == RESURF_OK && out_report)
        *out_report = rep;
    return st;
}

resurf_status resurf_simplify_lods(const resurf_mesh *in, const resurf_simplify_options *options, const double *ratios,
                                   size_t count, resurf_mesh **out_levels, resurf_simplify_report *out_reports,
                                   resurf_error *error)
{
    resurfi_clear_error(error);
    if (!out_levels || (count && !ratios))
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "%s is NULL", out_levels ? "ratios" : "out_levels");
    for (size_t i = 0; i < count; ++i)
        out_levels[i] = NULL;
    if (!in)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "the input mesh is NULL");
    resurf_status st = check_options(options, error);
    if (st != RESURF_OK)
        return st;
    const resurf_allocator *alloc = resurfi_allocator_of(options ? options->allocator : NULL, in);
    size_t *targets = resurfi_alloc(alloc, count, sizeof *targets);
    if (!targets)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    for (size_t i = 0; i < count; ++i) {
        if (!(ratios[i] > 0 && ratios[i] <= 1) || (i > 0 && ratios[i] > ratios[i - 1])) {
            resurfi_free(alloc, targets);
            return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT,
                                 "ratio %zu (%g) must be in (0, 1] and not above the previous one", i, ratios[i]);
        }
        targets[i] = (size_t)floor(ratios[i] * (double)in->triangle_count * (1 + 1e-12));
    }
    st = simplify_levels(in, options, targets, count, out_levels, out_reports, error);
    resurfi_free(alloc, targets);
    return st;
}
