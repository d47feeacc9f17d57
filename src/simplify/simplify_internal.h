/* The simplifier's shared types and small helpers: the working mesh, the per-concern state the simplifier holds,
 * and the functions the files of src/simplify/ call across (simplify.c lists the files). The smallest helpers of
 * the collapse loop are static inline here, so that splitting the loop over files costs no inlining. */
#ifndef RESURF_SIMPLIFY_INTERNAL_H
#define RESURF_SIMPLIFY_INTERNAL_H

#include <string.h>

#include "../internal.h"
#include "queue.h"

#define NONE UINT32_MAX

enum {
    BLOCK_POSITIONS = 1024,       /* parallel block sizes */
    BLOCK_SAMPLES = 4096,
    CHUNK = 1024,                 /* candidates of a pass applied together, at most */
    WINDOW = 1536,                /* candidates whose stars are gathered for a chunk, besides those put aside */
    CHUNK_MIN = 16,               /* a chunk's size is alive positions / CHUNK_SPREAD, within [CHUNK_MIN, CHUNK] */
    CHUNK_SPREAD = 64,
    CHUNK_THREADS = 32,           /* smaller chunks run on one thread: handing them out would cost more than it saves */
};

/* A corner of crease curves held until the level's error reaches its feature's size (curves.c). */
typedef struct corner_release {
    double size; /* the longest feature curve from the corner to the next corner or end */
    uint32_t position;
} corner_release;

/* Per-position flags. */
typedef uint16_t pos_flags;
enum {
    POS_DEAD = 1,          /* collapsed away */
    POS_LOCKED = 2,        /* non-manifold or inconsistently oriented in the input, or locked by vertex_lock: never
                              moves, never restored nor offset */
    POS_LOCKED_BORDER = 4, /* on a border with lock_border */
    POS_BORDER = 8,        /* on an edge with one triangle */
    POS_SEAM = 16,         /* exactly two wedges, split by exactly two seam edges, not on a border */
    POS_COMPLEX = 32,      /* any other wedge arrangement (seam junctions, seams ending on a border): never moves */
    POS_BLOCKED = 64,      /* a collapse at it failed a geometric guard: retry once its neighbourhood changes */
    POS_RENEW = 128,       /* transient, while renewed neighbours are planned again (plan_renewed) */
    POS_CREASE = 256,      /* on a crease curve: exactly two feature edges, no border: never restored nor offset */
    POS_CORNER = 512,      /* three or more feature edges, a crease meeting a border, or a border turning by more
                              than corner_angle_deg: never moves */
    POS_TOUCHES_FEATURE = 1024, /* has a feature edge, or absorbed a position that had: neither restored nor
                              offset (the smooth-surface model does not hold there) */
    POS_RELEASED = 2048,   /* a corner of a feature smaller than the level's error: no longer held (curves.c) */
    POS_JUNCTION = 4096,   /* inside a junction line, where a sheet meets a surface: exactly two edges of three
                              triangles, one fan: moves only along the line (collapse.c) */
};

/* The normals of two triangles on an edge differ by more than this (cosine of 150°, see reliable_normal in
 * setup.c): a triangle with an angle over 150° has no normal to judge by. */
#define SLIVER_COS2 0.75

/* Why a candidate collapse cannot be done. */
enum {
    BLOCK_NONE = 0,
    BLOCK_STALE,       /* not an edge any more */
    BLOCK_SEAM,
    BLOCK_BORDER,
    BLOCK_FEATURE,     /* a crease vertex would leave its crease, a corner would move */
    BLOCK_NONMANIFOLD, /* most severe last: when both directions fail, the larger reason is reported */
    BLOCK_REASONS
};

/* The top bits of gen: TAKEN marks an end of a candidate taken up by the current pass, CLAIMED a position of the
 * star of a candidate of the current chunk (schedule.c); the rest is the generation (queue.h). */
enum { TAKEN = 0x80000000u, CLAIMED = 0x40000000u, GEN = SIMP_GEN };

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

/* A triangle's normal for the angle between two triangles: its cross product when it is well shaped (ok = 1),
 * else none (setup.c). */
typedef struct shaped_normal {
    vec3 n;
    int ok;
} shaped_normal;

/* One worker's buffers for the parallel loops. */
typedef struct scratch {
    const resurf_allocator *alloc; /* the call's */
    u32vec fan;
    shaped_normal *shaped;         /* analyse_position: per fan triangle */
    size_t shaped_cap;
    u32vec group[2 * GATHER_GROUP]; /* star_block: the fans of a group of candidates' ends */
    fan_pair *pairs;
    uint32_t *uf;
    size_t pairs_cap;
    size_t blocked[BLOCK_REASONS]; /* candidates refused while seeding, by BLOCK_* reason */
    char pad[128];     /* one per worker, side by side: keeps their counters off each other's cache lines */
} scratch;

/* A planned collapse of edge (a, b). */
typedef struct plan {
    int block;               /* BLOCK_*; the rest is valid for BLOCK_NONE only */
    int a_removable, b_removable;
    int pinned;              /* 1: the position is that of the surviving end, already where it should be */
    int feature;             /* 1: along a crease, on the segment: not restored (it would leave the crease) */
    int curve;               /* 1: along a crease or border edge, or a crease vertex at an end: with inline
                                restoration the vertex goes onto M's curve there (curves.c), never across it */
    uint32_t shared[3];      /* the triangles on the edge: 3 along a junction line */
    int shared_count;
    vec3 p;
    double cost;             /* the quadric's at p, plus attr_cost */
    double attr_cost;        /* the attribute quadrics' (attributes.c), 0 without them */
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
    pos_flags flags;
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
    uint32_t *fans;                  /* its ends' fans as gathered with its star (na + nb corners), or NULL */
    uint32_t na, nb;
    uint32_t keep;                   /* the surviving end, when collapsed */
    size_t fresh_begin, fresh_end;   /* its new candidates in the lane's fresh */
    size_t renew_begin, renew_end;   /* its renewed neighbours in the lane's renew, planned after the chunk */
} pending;

/* What one collapse writes besides its own star: per worker, so that the collapses of a chunk run in parallel
 * (schedule.c). Merged into the simplifier after each chunk, in the chunk's order. */
typedef struct lane {
    u32vec fan_a, fan_b, fan_c, touched, renew;
    uint32_t *mark;         /* scratch stamps, see next_stamp (lane 0's is the simplifier's) */
    uint32_t stamp;
    candidate_buf fresh;    /* candidates planned or requeued, for the queue's fresh */
    resurf_simplify_report rep; /* counters to add to the simplifier's */
    size_t dead_tris, dead_positions;
    int skipped_error;
#ifndef NDEBUG
    uint32_t writer;        /* the pending entry whose collapse runs on this lane in a parallel chunk, else NONE */
#endif
    char pad[128]; /* side by side: keeps the lanes' counters off each other's cache lines */
} lane;

/* The scheduler's state (schedule.c): the open pass, its chunk and the workers' lanes. */
typedef struct schedule {
    lane *lanes;            /* one per thread */
    pending *pend;          /* CHUNK: the chunk's candidates being applied, pend_next the next one */
    size_t pend_count, pend_next;
    int pass_open;
    size_t pass_next;       /* the next candidate of the open pass */
    size_t pass_before;     /* collapses when it opened */
    float pass_limit;
    size_t chunk, window;   /* this pass's chunk size and window (open_pass) */
    u32vec taken;           /* the positions marked taken */
    u32vec claimed;         /* the positions marked claimed (stars of the chunk's candidates) */
    size_t *skip;           /* CHUNK: candidates of the pass whose star met a claimed one: for the next chunk */
    size_t skip_count;
    window_entry *win;      /* CHUNK + WINDOW: the candidates examined for a chunk */
    uint32_t *stars;        /* STAR_MAX per window entry: their stars */
#ifndef NDEBUG
    uint32_t *owner;        /* per position: the pending entry whose star claimed it in this chunk (guards.h) */
#endif
} schedule;

/* Attribute sides (setup.c, only when the input has attributes and seams): chart of each input triangle and
 * wedge. */
typedef struct charts {
    uint32_t *of_input_tri;
    uint32_t *of_wedge;
    uint32_t *first;        /* chart c's input triangles are tris[first[c] .. first[c + 1]), ascending */
    uint32_t *tris;
} charts;

/* Attribute quadrics (attributes.c), one record of `stride` doubles per wedge (indexed by its input vertex id), or
 * none (data NULL) when the input has no attribute the options weigh. */
enum { SKIN_FIELDS = 4 }; /* a skin's influences in the cost: a random projection to this many fields */
enum { ATTR_MORPH_TARGETS = 8 }; /* morph targets whose POSITION deltas are weighed at most (the largest) */
enum { ATTR_MAX = 3 + 2 * RESURF_MAX_TEXCOORD_SETS + 4 + SKIN_FIELDS + 3 * ATTR_MORPH_TARGETS }; /* components weighed
                                   at most: normal, texcoords, colour, skin fields, morph targets' position deltas */
typedef struct attr_quadrics {
    double *data;
    double *skin;                 /* SKIN_FIELDS per input vertex (skin_weight > 0 and a skin), else NULL */
    size_t stride;                /* ATTR_HEAD + 4 × count */
    unsigned count;               /* components weighed */
    const double *src[ATTR_MAX];  /* per component: the input's array (or srcf: an extra's floats), */
    const float *srcf[ATTR_MAX];
    unsigned step[ATTR_MAX];      /* its doubles per vertex, */
    unsigned offset[ATTR_MAX];    /* the component's place in a vertex's values */
    double scale[ATTR_MAX];       /* and its factor: weight × the diagonal */
} attr_quadrics;

/* The report's input side (measure.c), found at the first measured level and kept for the others. */
typedef struct measure_state {
    double *in_area_prefix;   /* the input's cumulative triangle areas, triangle_count + 1 */
    uint32_t *in_used;        /* the input's vertices that triangles use, one per position */
    size_t in_used_count;
    uint32_t *in_rep;         /* per input vertex: the one of in_used at its position, NONE if unused */
    /* A level whose maximum times reject_scale exceeds reject_bound is only said to be so (reject_scale 0: off): the
       scene budget turns such a run down whatever its figures, and a point above the bound settles it. */
    double reject_scale, reject_bound;
} measure_state;

typedef struct simplifier {
    const resurf_mesh *in;       /* M: the caller's mesh, or its copy with flat shading dropped (facets.c) */
    resurf_mesh *own_derived;    /* that copy when the call made it */
    int flat_shaded;             /* in is such a copy: the levels are shaded flat where it has no normals */
    size_t attached_sheets;      /* double-sided sheets attached along a line that the input has (kept or not) */
    resurf_simplify_options opt;
    const resurf_allocator *alloc; /* the call's (options, else the input's): temporaries and the output */
    unsigned threads;
    resurfi_pool *pool;  /* threads - 1 workers waiting for the call's parallel loops (NULL with one thread) */
    double diagonal, max_error;
    double feature_cos, corner_cos; /* cos of feature_angle_deg and corner_angle_deg */
    double smooth_cos;   /* cos of feature_angle_deg / 4: edges turning by less are smooth (setup.c) */
    double area_floor;   /* AREA_FLOOR × the mean triangle area */
    vec3 origin;         /* the bounding box's centre: quadrics are built around it, where their expanded form
                            xᵀAx + 2bᵀx + c loses the fewest digits to cancellation */

    /* the working mesh */
    size_t tri_count, alive_tris;
    work_tri *tri;
    uint32_t *src;     /* input triangle of each working triangle */
    uint32_t *mirror;  /* per input triangle: the mirror of a double-sided sheet's kept side (left out of the
                          working mesh, written back mirrored in every level), else NONE; NULL without sheets */
    uint32_t *remap;   /* while starting: position of each input vertex (resurfi_weld_exact) */
    size_t pos_count, alive_positions;
    work_pos *P;         /* inside P_mem, 64-byte aligned */
    void *P_mem;
    uint32_t *mark;    /* lane 0's scratch stamps (allocated with the working mesh) */
    uint32_t *gen;     /* per position: bumped when it changes (its candidates then go stale); the top bits are
                          the scheduler's marks. Apart from the 128-byte records: a pass reads it for every
                          candidate. */

    /* the original M: for restoring, attributes and measuring */
    const resurfi_simplify_services *lent; /* the services over M built before the call, or NULL */
    const resurfi_restorer *restorer;      /* the lent one or own_restorer */
    resurfi_restorer *own_restorer;
    resurfi_bvh *own_bvh;
    const resurfi_bvh *bvh;     /* over the input's triangles, input triangle ids: the lent one or own_bvh */
    uint32_t *home;             /* inline restoration: per position, a triangle of the input near it */
    uint32_t *curve_nb;         /* inline restoration: per position of M, its two neighbours along its crease or
                                   border curve (NONE, NONE at a corner or where it is on none; curves.c) */
    uint32_t *curve_at;         /* per position: the vertex of M's curve it lies at or next to, or NONE */
    vec3 *curve_p;              /* per position of M: its place in M */
    corner_release *release;    /* the corners of crease curves, smallest feature first (curves.c) */
    size_t release_count, release_next; /* ..., and how many were released */
    charts charts;
    uint32_t *wedge_root; /* with attributes: per input vertex, the wedge it became or merged into (a union-find
                             forest: follow it to a live wedge; output.c finds the triangles of a seam's side) */
    attr_quadrics attr;
    measure_state measure;

    simp_queue queue;
    schedule sched;
    int skipped_error;      /* a candidate was skipped for max_error in this collapse_until */
    int last_level;         /* building the last output: the working mesh may go once read */
    resurf_simplify_report rep;
} simplifier;

/* ---- small helpers ------------------------------------------------------------------------------------------- */

static inline int vec_push(const resurf_allocator *alloc, u32vec *v, uint32_t x)
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

/* A fresh stamp for lane L's mark array: a position is "marked" when mark[p] equals it. */
static inline uint32_t next_stamp(const simplifier *s, lane *L)
{
    if (L->stamp >= UINT32_MAX - 4) {
        memset(L->mark, 0, s->pos_count * sizeof *L->mark);
        L->stamp = 0;
    }
    L->stamp += 2;
    return L->stamp;
}

static inline uint32_t corner_next(uint32_t c) { return c - c % 3 + (c % 3 + 1) % 3; }
static inline uint32_t corner_prev(uint32_t c) { return c - c % 3 + (c % 3 + 2) % 3; }

/* The positions after and before corner c in its triangle: TV(corner_next(c)) and TV(corner_prev(c)) with one
 * division instead of four (the collapse loop asks this for every corner of every fan it looks at). */
static inline void corner_others(const simplifier *s, uint32_t c, uint32_t xs[2])
{
    uint32_t t = c / 3, k = c - 3 * t;
    xs[0] = s->tri[t].v[k == 2 ? 0 : k + 1];
    xs[1] = s->tri[t].v[k == 0 ? 2 : k - 1];
}

/* The corner of triangle t at position v, or NONE. */
static inline uint32_t corner_at(const simplifier *s, uint32_t t, uint32_t v)
{
    for (uint32_t k = 0; k < 3; ++k)
        if (TV(3 * t + k) == v)
            return 3 * t + k;
    return NONE;
}

/* The corners of live triangles at each of n distinct positions v[i] (n <= 2 GATHER_GROUP), in list order, into
 * out[i]. With unlink, dead triangles' corners are dropped from the lists on the way (only a collapse applied
 * alone may do that: it writes the lists' links). The lists are walked in step: each step of a list is a cache
 * miss on a large mesh, and the misses of different lists then overlap instead of following one another. Returns
 * 0 when out of memory. */
static inline int gather_fans(simplifier *s, const uint32_t *v, size_t n, u32vec *out, int unlink)
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
static inline int gather_fan(simplifier *s, uint32_t v, u32vec *out, int unlink)
{
    return gather_fans(s, &v, 1, out, unlink);
}

/* Q(p) for a quadric built around s->origin. */
static inline double qeval(const simplifier *s, const resurfi_quadric *q, vec3 p)
{
    return resurfi_quadric_eval(q, v3_sub(p, s->origin));
}

/* Position x changed: its candidates go stale. */
static inline void bump_gen(simplifier *s, uint32_t x)
{
    s->gen[x] = (s->gen[x] & ~GEN) | ((s->gen[x] + 1) & GEN);
}

/* Is candidate c still what its ends are? */
static inline int candidate_current(const simplifier *s, candidate c) { return simp_candidate_current(s->gen, c); }

/* The start of the walk of a restoration `ahead` (1..3) places ahead in a loop, from position a's home: its home's
 * entry three ahead, then the triangle's corner ids, then what they point to (resurfi_restorer_prefetch). */
static inline void prefetch_walk(const simplifier *s, uint32_t a, size_t ahead)
{
    if (ahead >= 3)
        PREFETCH(&s->home[a]);
    else
        resurfi_restorer_prefetch(s->restorer, s->home[a], ahead == 1);
}

/* Asks for what a collapse reads of the positions around a fan: their records (both cache lines: the checks read
 * their places, the new candidates their quadrics), their marks (link_ok) and their wedges' attribute quadrics. One neighbour per corner covers a
 * closed fan. */
static inline void prefetch_ring(const simplifier *s, const lane *L, const u32vec *fan)
{
    for (size_t i = 0; i < fan->count; ++i) {
        uint32_t x = TV(corner_next(fan->data[i]));
        PREFETCH(&s->P[x]);
        PREFETCH(&s->P[x].q.c);
        PREFETCH(&L->mark[x]);
        if (s->attr.data) { /* the neighbour's wedge's attribute quadric, which the new candidates price */
            const double *r = s->attr.data + s->attr.stride * TW(corner_next(fan->data[i]));
            for (size_t k = 0; k < s->attr.stride; k += 8)
                PREFETCH(r + k);
        }
    }
}

/* ---- across the files ---------------------------------------------------------------------------------------- */

/* setup.c: everything up to the first candidates; the per-position analysis collapses reuse */
int has_attributes(const resurf_mesh *m);
size_t fan_pairs(const simplifier *s, const u32vec *fan, scratch *sc);
int analyse_position(simplifier *s, uint32_t a, scratch *sc, pos_flags *out_flags, resurfi_quadric *out_q,
                     uint32_t *out_up);
int feature_edge(const simplifier *s, uint32_t ti, uint32_t tj, uint32_t ci, uint32_t cj);
int group_border(const simplifier *s, uint32_t ti, uint32_t tj);
resurf_status simplify_start(simplifier *s, scratch *scratch, resurf_error *error);
/* Fins and double-sided sheets (fins.c). resurfi_find_fins: (*out_drop)[t] says what drop_fins does with input
 * triangle t (0: an ordinary triangle), or *out_drop = NULL when no triangle is left out or mirrored; a sheet's
 * mirrors go to s->mirror. */
enum { FIN_DROP = 1, FIN_KEEP = 2, FIN_SHEET = 3, FIN_MIRROR = 4 };
resurf_status resurfi_find_fins(simplifier *s, const uint32_t *remap, uint8_t **out_drop);
static inline int resurfi_fin_left_out(const uint8_t *drop, size_t t)
{
    return drop && (drop[t] == FIN_DROP || drop[t] == FIN_MIRROR);
}
/* Flat shading (facets.c). facets_derive: *out_derived is NULL, or a copy of in whose flat-shaded parts have zero
 * normals (the call simplifies it instead). facets_shade: each vertex of a level with a zero normal is split by
 * the directions of its faces and given their normal. */
resurf_status facets_derive(const resurf_mesh *in, const resurf_allocator *alloc, resurf_mesh **out_derived);
resurf_status facets_shade(resurf_mesh *m);
/* The input's indices, positions, counts and groups checked (the start's first step). */
resurf_status simplify_check_input(const resurf_mesh *in, resurf_error *error);
/* The services over M (services.c): what they hold, and the restoring options a call builds its restorer with. */
struct resurfi_simplify_services {
    resurfi_restorer *restorer; /* NULL without restoration */
    resurfi_bvh *bvh;
    const resurf_mesh *in;      /* the input they were built for */
    resurf_mesh *derived;       /* its copy without its flat-shaded normals (facets.c), or NULL; what they are over */
    resurf_allocator alloc;     /* a copy of the build's allocator */
    struct services_analysis *analysis; /* the first call's per-position analysis, kept for the later ones */
};
/* The per-position analysis (flags, quadric, neighbours above) of the first call that borrows the services, copied
 * into a later call whose options it depends on are the same (services_take_analysis returns 1); a call that finds
 * none keeps its own (services_keep_analysis). Safe for calls on several threads at once. */
int services_take_analysis(simplifier *s);
void services_keep_analysis(const simplifier *s);
resurf_restore_options services_restore_options(const resurf_simplify_options *o, const resurf_allocator *alloc);
resurf_status services_build_restorer(const resurf_mesh *in, const resurf_simplify_options *o,
                                      const resurf_allocator *alloc, const uint32_t *remap, size_t positions,
                                      resurfi_restorer **out, resurf_error *error);
resurf_status services_build_bvh(const resurf_mesh *in, const resurf_simplify_options *o,
                                 const resurf_allocator *alloc, resurfi_bvh **out);
/* Does the call need the tree over the input (attributes to interpolate, or a report to measure)? */
int services_need_bvh(const resurf_mesh *in, const resurf_simplify_options *o);

/* curves.c: M's crease and border curves, and a collapse's place on them (curve_place: 0 when a and b are not on
 * one curve of M within reach; else *out on it and *out_at the curve's vertex of M next to it); the corners of
 * creases and their features' sizes (corners_start), released by collapse.c's pass loop */
resurf_status curves_start(simplifier *s, scratch *sc);
void curves_free(simplifier *s);
int curve_place(const simplifier *s, uint32_t a, uint32_t b, vec3 p, vec3 *out, uint32_t *out_at);
resurf_status corners_start(simplifier *s, scratch *sc);

/* attributes.c: the attribute quadrics of the wedges */
resurf_status attributes_start(simplifier *s, scratch *scratch);
double attribute_cost(const simplifier *s, const plan *pl, uint32_t a, uint32_t b, vec3 p);
void attribute_merge(simplifier *s, uint32_t to, uint32_t from);

/* collapse.c: planning, the first candidates, applying, the pass loop */
void plan_collapse(const simplifier *s, uint32_t a, uint32_t b, const u32vec *fan_a, plan *pl);
resurf_status seed_candidates(simplifier *s, scratch *scratch);
int try_candidate(simplifier *s, pending *q, lane *L, scratch *sc, int defer);
int plan_renewed(simplifier *s, lane *L, uint32_t x, uint32_t keep);
resurf_status collapse_until(simplifier *s, size_t target, scratch *sc, resurf_error *error);

/* schedule.c: passes, chunks, lanes (guards.h states what a collapse of a chunk may touch) */
resurf_status schedule_init(simplifier *s);
void schedule_drop_marks(simplifier *s);
void schedule_free(simplifier *s);
int open_pass(simplifier *s);
int take_chunk(simplifier *s, scratch *sc);
int chunk_in_parallel(const simplifier *s, size_t target);
int apply_chunk_parallel(simplifier *s, scratch *sc);
int restore_chunk_ahead(simplifier *s, scratch *sc);
int apply_next_alone(simplifier *s, scratch *sc);
int merge_lane(simplifier *s, lane *L);

/* output.c */
resurf_status build_output(simplifier *s, resurf_mesh **out, resurf_simplify_report *rep, resurf_error *error);

/* measure.c: the report's distances between level m and the input, and its UV error */
resurf_status measure_level(simplifier *s, const resurf_mesh *m, resurf_simplify_report *rep);
void measure_free(simplifier *s);

#include "guards.h"

#endif
