/* An axis-aligned bounding-box tree over triangles and exact closest-point queries on it (docs/restoring.md §2:
 * the closest triangle of M, never a brute-force scan).
 *
 * Build: binned surface-area heuristic on triangle-box centroids (Wald 2007, "On fast construction of SAH-based
 * bounding volume hierarchies"), 16 bins on each axis (one per triangle in smaller nodes), leaves of at most 4
 * triangles. The tree is a flat array of 32-byte nodes with float boxes rounded outwards (a random query is bound by cache misses, and a sibling pair then
 * fills one cache line); the triangle corners are copied in float, in leaf order, so a leaf reads one contiguous
 * block. Distances stay exact: a float triangle is within `slack` of the true one, so one whose float distance
 * exceeds the best so far by more than that cannot win, and the few that might are measured again on the caller's
 * double positions (which the tree keeps pointers to). Half the bytes of double corners, and the same answers. The two subtrees of large nodes are built on separate threads into separate node arrays
 * that are then appended in a fixed order, so the tree does not depend on the thread count or on timing.
 *
 * Query: depth-first, nearer child first, pruning boxes by their squared distance (a lower bound of every
 * triangle inside). Closest point on one triangle: Ericson, "Real-Time Collision Detection" (2005) §5.1.5, the
 * Voronoi-region test, with a separate path for degenerate triangles. */
#include <float.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"

enum {
    LEAF_MAX = 4,          /* triangles per leaf at most */
    BIN_COUNT = 16,        /* SAH bins per axis: 16 is within a few % of a full sweep (Wald 2007) */
    SAH_DEPTH_LIMIT = 48,  /* below this depth split in halves: bounds the depth by 48 + 32 */
    STACK_SIZE = 128,      /* traversal stack, > the depth bound above */
    PARALLEL_MIN = 32768,  /* a subtree smaller than this is not worth a thread */
};

/* count > 0: a leaf over triangles [index, index + count) in leaf order; count == 0: an inner node whose children
 * are nodes index and index + 1. */
typedef struct bvh_node {
    float lo[3], hi[3]; /* rounded outwards from the padded double boxes: a lower bound of every distance inside */
    uint32_t index, count;
} bvh_node;

struct resurfi_bvh {
    resurf_allocator alloc; /* a copy of the build's allocator: every block below comes from it */
    void *node_block;       /* the allocation `nodes` is aligned within */
    bvh_node *nodes;
    size_t node_count;
    size_t triangle_count; /* triangles kept (valid ones) */
    float *corners;        /* 9 per kept triangle, in leaf order, rounded to nearest */
    double slack;          /* at least twice the largest distance between a float corner and its double */
    int exact_only;        /* coordinates beyond float's range: every triangle is measured in double */
    const double *positions; /* the caller's arrays (they outlive the tree): the exact corners */
    const uint32_t *indices;
    uint32_t *ids;         /* the caller's triangle index of each kept triangle, in leaf order */
};

/* ---- closest point on one triangle ----------------------------------------------------------------------------- */

/* Closest point of segment [a, b] to p; t is the parameter (0 at a). A zero-length segment gives a. */
static vec3 closest_on_segment(vec3 p, vec3 a, vec3 b, double *t)
{
    vec3 ab = v3_sub(b, a);
    double l2 = v3_len2(ab);
    double s = l2 > 0 ? v3_dot(v3_sub(p, a), ab) / l2 : 0.0;
    s = s < 0 ? 0 : s > 1 ? 1 : s;
    *t = s;
    return s == 1 ? b : v3_madd(a, ab, s);
}

/* Degenerate (or nearly so) triangles: the closest point is on the boundary unless the plane projection falls
 * inside. Ericson's face test divides by the squared area and its region tests lose their meaning when that
 * vanishes, so here each edge is treated as a segment and the nearest wins (first edge on exact ties). */
static vec3 closest_on_degenerate(vec3 p, vec3 a, vec3 b, vec3 c, vec3 n, double bary[3])
{
    double n2 = v3_len2(n);
    if (n2 > 0) {
        vec3 ap = v3_sub(p, a);
        vec3 q = v3_madd(p, n, -v3_dot(ap, n) / n2);
        vec3 aq = v3_sub(q, a);
        double v = v3_dot(v3_cross(aq, v3_sub(c, a)), n) / n2;
        double w = v3_dot(v3_cross(v3_sub(b, a), aq), n) / n2;
        if (v >= 0 && w >= 0 && v + w <= 1) {
            bary[0] = 1 - v - w, bary[1] = v, bary[2] = w;
            return q;
        }
    }
    const vec3 corner[3] = {a, b, c};
    vec3 best = a;
    double best_d2 = INFINITY;
    for (int e = 0; e < 3; ++e) {
        double t;
        vec3 q = closest_on_segment(p, corner[e], corner[(e + 1) % 3], &t);
        double d2 = v3_dist2(p, q);
        if (d2 < best_d2) {
            best_d2 = d2, best = q;
            bary[e] = 1 - t, bary[(e + 1) % 3] = t, bary[(e + 2) % 3] = 0;
        }
    }
    return best;
}

vec3 resurfi_closest_on_triangle(vec3 p, vec3 a, vec3 b, vec3 c, double out_bary[3])
{
    double scratch[3];
    double *bary = out_bary ? out_bary : scratch;
    vec3 ab = v3_sub(b, a), ac = v3_sub(c, a), ap = v3_sub(p, a);
    vec3 n = v3_cross(ab, ac);
    /* sin² of the angle at a below 1e-10: the region tests below rest on ratios of nearly cancelling products. */
    if (!(v3_len2(n) > 1e-10 * v3_len2(ab) * v3_len2(ac)))
        return closest_on_degenerate(p, a, b, c, n, bary);

    double d1 = v3_dot(ab, ap), d2 = v3_dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) { /* vertex region a */
        bary[0] = 1, bary[1] = 0, bary[2] = 0;
        return a;
    }
    vec3 bp = v3_sub(p, b);
    double d3 = v3_dot(ab, bp), d4 = v3_dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) { /* vertex region b */
        bary[0] = 0, bary[1] = 1, bary[2] = 0;
        return b;
    }
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) { /* edge region ab; d1 − d3 = |ab|² > 0 */
        double v = d1 / (d1 - d3);
        bary[0] = 1 - v, bary[1] = v, bary[2] = 0;
        return v3_madd(a, ab, v);
    }
    vec3 cp = v3_sub(p, c);
    double d5 = v3_dot(ab, cp), d6 = v3_dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) { /* vertex region c */
        bary[0] = 0, bary[1] = 0, bary[2] = 1;
        return c;
    }
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) { /* edge region ac */
        double w = d2 / (d2 - d6);
        bary[0] = 1 - w, bary[1] = 0, bary[2] = w;
        return v3_madd(a, ac, w);
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) { /* edge region bc */
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        bary[0] = 0, bary[1] = 1 - w, bary[2] = w;
        return v3_madd(b, v3_sub(c, b), w);
    }
    /* Face region. The point is the plane projection (accurate whatever the shape); the barycentrics come from
     * sub-triangle areas, which lose less to cancellation than Ericson's va, vb, vc on thin triangles. */
    double n2 = v3_len2(n);
    vec3 q = v3_madd(p, n, -v3_dot(ap, n) / n2);
    vec3 aq = v3_sub(q, a);
    double v = v3_dot(v3_cross(aq, ac), n) / n2;
    double w = v3_dot(v3_cross(ab, aq), n) / n2;
    v = v < 0 ? 0 : v > 1 ? 1 : v;
    w = w < 0 ? 0 : w > 1 - v ? 1 - v : w;
    bary[0] = 1 - v - w, bary[1] = v, bary[2] = w;
    return q;
}

/* ---- build ------------------------------------------------------------------------------------------------------- */

/* Float bounds that contain the double value: rounded down / up (and clamped to the float range). */
static float float_below(double x)
{
    if (x > FLT_MAX)
        return FLT_MAX;
    if (x < -FLT_MAX)
        return -INFINITY;
    float f = (float)x;
    return (double)f > x ? nextafterf(f, -INFINITY) : f;
}

static float float_above(double x)
{
    if (x > FLT_MAX)
        return INFINITY;
    if (x < -FLT_MAX)
        return -FLT_MAX;
    float f = (float)x;
    return (double)f < x ? nextafterf(f, INFINITY) : f;
}

/* A triangle during the build: its (padded, float) box and its caller index. Its centroid is lo + hi: the factor
 * ½ cancels in the binning. */
typedef struct prim {
    float lo[3], hi[3];
    uint32_t id;
} prim;

typedef struct box {
    float lo[3], hi[3];
} box;

static box box_empty(void) { return (box){{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}}; }

static inline void box_grow(box *b, const float lo[3], const float hi[3])
{
    for (int k = 0; k < 3; ++k) {
        b->lo[k] = lo[k] < b->lo[k] ? lo[k] : b->lo[k];
        b->hi[k] = hi[k] > b->hi[k] ? hi[k] : b->hi[k];
    }
}

/* Half the surface area; 0 for an empty box. */
static double box_half_area(const box *b)
{
    double dx = (double)b->hi[0] - b->lo[0], dy = (double)b->hi[1] - b->lo[1], dz = (double)b->hi[2] - b->lo[2];
    if (!(dx >= 0))
        return 0;
    return dx * dy + dy * dz + dz * dx;
}

/* A growing node array holding one subtree: its root in slot 0, slot 1 unused, then sibling pairs at even slots
 * (so that a pair shares one 64-byte cache line once the array is aligned). */
typedef struct node_vec {
    bvh_node *nodes;
    size_t count, capacity;
    const resurf_allocator *alloc; /* the tree's, shared by the build's threads */
} node_vec;

static int vec_reserve(node_vec *v, size_t extra)
{
    if (v->count + extra <= v->capacity)
        return 0;
    size_t cap = v->capacity ? v->capacity : 64;
    while (cap < v->count + extra)
        cap *= 2;
    bvh_node *p = resurfi_realloc(v->alloc, v->nodes, cap, sizeof *p);
    if (!p)
        return -1;
    v->nodes = p, v->capacity = cap;
    return 0;
}

static int vec_start(node_vec *v)
{
    if (vec_reserve(v, 2) != 0)
        return -1;
    v->count = 2;
    memset(&v->nodes[1], 0, sizeof v->nodes[1]);
    return 0;
}

typedef struct subtree_job {
    prim *prims;
    size_t begin, end;
    box bounds, centroids;
    unsigned depth, threads;
    node_vec out;
    int failed;
} subtree_job;

static int build_node(prim *prims, node_vec *vec, size_t slot, size_t begin, size_t end, box bounds, box cbounds,
                      unsigned depth, unsigned threads);

static void *run_subtree(void *p)
{
    subtree_job *j = p;
    j->failed = vec_start(&j->out) != 0 ||
                build_node(j->prims, &j->out, 0, j->begin, j->end, j->bounds, j->centroids, j->depth, j->threads) != 0;
    return NULL;
}

/* Appends src (a subtree laid out as in node_vec) to dst, its root going to the already reserved dst slot. */
static void append_subtree(node_vec *dst, size_t slot, const node_vec *src)
{
    size_t base = dst->count; /* src slot k >= 2 lands at base + k − 2; base is even, so pairs stay aligned */
    for (size_t k = 0; k < src->count; ++k) {
        if (k == 1)
            continue;
        bvh_node n = src->nodes[k];
        if (n.count == 0)
            n.index = (uint32_t)(base + n.index - 2);
        dst->nodes[k == 0 ? slot : base + k - 2] = n;
    }
    dst->count = base + src->count - 2;
}

/* Centroid bin of a primitive along an axis. */
static inline int bin_of(const prim *p, int axis, float cmin, float scale, int bins)
{
    float x = (p->lo[axis] + p->hi[axis] - cmin) * scale;
    return !(x >= 1) ? 0 : x >= bins - 1 ? bins - 1 : (int)x; /* NaN-safe: no conversion out of range */
}

/* Bins for a node of `count` triangles: as many as triangles below BIN_COUNT. The fixed cost of the bins (their
 * set-up and the two sweeps) dominates the small nodes near the leaves, which are most of the nodes, and a node
 * with no more bins than triangles still has a boundary between most pairs of centroids. */
static inline int bins_for(size_t count) { return count < BIN_COUNT ? (int)count : BIN_COUNT; }

/* Picks the binned-SAH split: axis and last bin of the left side. Returns 0 when no bin boundary separates the
 * centroids (all in one bin on every axis). Ties go to the lower axis, then the lower bin: deterministic. */
static int choose_split(const prim *prims, size_t begin, size_t end, const box *cbounds, int bin_count, int *out_axis,
                        int *out_bin, float scale[3])
{
    box bins[3][BIN_COUNT];
    uint32_t counts[3][BIN_COUNT];
    for (int k = 0; k < 3; ++k) {
        float extent = cbounds->hi[k] - cbounds->lo[k];
        scale[k] = extent > 0 ? (float)(bin_count * (1 - 1e-6) / extent) : 0;
        for (int b = 0; b < bin_count; ++b)
            bins[k][b] = box_empty(), counts[k][b] = 0;
    }
    for (size_t i = begin; i < end; ++i) {
        const prim *p = &prims[i];
        for (int k = 0; k < 3; ++k) {
            int b = bin_of(p, k, cbounds->lo[k], scale[k], bin_count);
            box_grow(&bins[k][b], p->lo, p->hi);
            counts[k][b]++;
        }
    }
    double best = INFINITY;
    int found = 0;
    for (int k = 0; k < 3; ++k) {
        if (scale[k] == 0)
            continue;
        /* right_cost[b] = area × count of bins b+1 .. end; −1 when they are empty */
        double right_cost[BIN_COUNT];
        box acc = box_empty();
        size_t n = 0;
        for (int b = bin_count - 1; b > 0; --b) {
            box_grow(&acc, bins[k][b].lo, bins[k][b].hi);
            n += counts[k][b];
            right_cost[b - 1] = n ? box_half_area(&acc) * (double)n : -1;
        }
        acc = box_empty();
        n = 0;
        for (int b = 0; b < bin_count - 1; ++b) {
            box_grow(&acc, bins[k][b].lo, bins[k][b].hi);
            n += counts[k][b];
            if (n == 0 || right_cost[b] < 0)
                continue;
            double cost = box_half_area(&acc) * (double)n + right_cost[b];
            if (cost < best)
                best = cost, *out_axis = k, *out_bin = b, found = 1;
        }
    }
    return found;
}

/* Box and centroid box of prims [begin, end). */
static void bound_range(const prim *prims, size_t begin, size_t end, box *bounds, box *cbounds)
{
    *bounds = box_empty(), *cbounds = box_empty();
    for (size_t i = begin; i < end; ++i) {
        const prim *p = &prims[i];
        float c[3] = {p->lo[0] + p->hi[0], p->lo[1] + p->hi[1], p->lo[2] + p->hi[2]};
        box_grow(bounds, p->lo, p->hi);
        box_grow(cbounds, c, c);
    }
}

/* Builds the subtree over prims [begin, end) whose root is vec->nodes[slot] (already reserved). threads > 1 lets
 * it hand halves to new threads. */
static int build_node(prim *prims, node_vec *vec, size_t slot, size_t begin, size_t end, box bounds, box cbounds,
                      unsigned depth, unsigned threads)
{
    size_t count = end - begin;
    bvh_node *node = &vec->nodes[slot];
    memcpy(node->lo, bounds.lo, sizeof node->lo), memcpy(node->hi, bounds.hi, sizeof node->hi);
    if (count <= LEAF_MAX) {
        node->index = (uint32_t)begin, node->count = (uint32_t)count;
        return 0;
    }

    int axis = 0, split = 0;
    float scale[3];
    size_t mid;
    box lb, lc, rb, rc;
    int bins = bins_for(count);
    if (depth < SAH_DEPTH_LIMIT && choose_split(prims, begin, end, &cbounds, bins, &axis, &split, scale)) {
        /* Partition in place, collecting each side's boxes on the way. */
        lb = box_empty(), lc = box_empty(), rb = box_empty(), rc = box_empty();
        size_t i = begin, j = end;
        while (i < j) {
            prim *p = &prims[i];
            float c[3] = {p->lo[0] + p->hi[0], p->lo[1] + p->hi[1], p->lo[2] + p->hi[2]};
            if (bin_of(p, axis, cbounds.lo[axis], scale[axis], bins) <= split) {
                box_grow(&lb, p->lo, p->hi), box_grow(&lc, c, c);
                ++i;
            } else {
                box_grow(&rb, p->lo, p->hi), box_grow(&rc, c, c);
                prim t = *p;
                *p = prims[--j];
                prims[j] = t;
            }
        }
        mid = i;
    } else {
        /* Coincident centroids or a pathological depth: halves in the current order keep the depth logarithmic. */
        mid = begin + count / 2;
        bound_range(prims, begin, mid, &lb, &lc);
        bound_range(prims, mid, end, &rb, &rc);
    }

    if (vec_reserve(vec, 2) != 0)
        return -1;
    size_t child = vec->count;
    vec->count += 2;
    node = &vec->nodes[slot]; /* the array may have moved */
    node->index = (uint32_t)child, node->count = 0;

    if (threads > 1 && count >= PARALLEL_MIN) {
        /* The right half goes to its own thread and node array; the thread budget is split between the halves.
         * Its nodes are appended after the left half's: the same layout as a one-thread build. */
        subtree_job job = {.prims = prims, .begin = mid, .end = end, .bounds = rb, .centroids = rc,
                           .depth = depth + 1, .threads = threads / 2, .out = {.alloc = vec->alloc}};
        pthread_t tid;
        if (pthread_create(&tid, NULL, run_subtree, &job) == 0) {
            int failed = build_node(prims, vec, child, begin, mid, lb, lc, depth + 1, threads - threads / 2);
            pthread_join(tid, NULL);
            if (!failed && !job.failed && vec_reserve(vec, job.out.count) == 0)
                append_subtree(vec, child + 1, &job.out);
            else
                failed = 1;
            resurfi_free(vec->alloc, job.out.nodes);
            return failed ? -1 : 0;
        }
    }
    if (build_node(prims, vec, child, begin, mid, lb, lc, depth + 1, 1) != 0)
        return -1;
    return build_node(prims, vec, child + 1, mid, end, rb, rc, depth + 1, 1);
}

/* The parallel set-up and tear-down passes: one prim per triangle, then corners in leaf order. */
typedef struct pass_ctx {
    const double *positions;
    size_t vertex_count;
    const uint32_t *indices;
    prim *prims;
    resurfi_bvh *bvh;
} pass_ctx;

static int make_prims(void *p, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    const pass_ctx *c = p;
    for (size_t t = begin; t < end; ++t) {
        const uint32_t *tri = c->indices + 3 * t;
        prim *pr = &c->prims[t];
        pr->id = UINT32_MAX; /* skipped */
        if (tri[0] >= c->vertex_count || tri[1] >= c->vertex_count || tri[2] >= c->vertex_count)
            continue;
        vec3 a = v3_load(c->positions + 3 * (size_t)tri[0]), b = v3_load(c->positions + 3 * (size_t)tri[1]),
             d = v3_load(c->positions + 3 * (size_t)tri[2]);
        if (!v3_finite(a) || !v3_finite(b) || !v3_finite(d))
            continue;
        double lo[3], hi[3];
        for (int k = 0; k < 3; ++k) { /* plain comparisons: the corners are finite, fmin's NaN rules cost a call */
            double x = v3_comp(a, k), y = v3_comp(b, k), z = v3_comp(d, k);
            lo[k] = x < y ? (x < z ? x : z) : (y < z ? y : z);
            hi[k] = x > y ? (x > z ? x : z) : (y > z ? y : z);
        }
        /* Pad: a computed closest point may stray from its triangle by rounding (most on thin triangles, whose
         * normal is least accurate), and the box must stay a lower bound of its computed distance. 2^-30 of the
         * largest coordinate is far above that and far below the float rounding the tree lives with anyway. */
        double big = 0;
        for (int k = 0; k < 3; ++k)
            big = fmax(big, fmax(fabs(lo[k]), fabs(hi[k])));
        double pad = big * 0x1p-30;
        for (int k = 0; k < 3; ++k)
            pr->lo[k] = float_below(lo[k] - pad), pr->hi[k] = float_above(hi[k] + pad);
        pr->id = (uint32_t)t;
    }
    return 0;
}

static int copy_corners(void *p, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    const pass_ctx *c = p;
    for (size_t i = begin; i < end; ++i) {
        const uint32_t *tri = c->indices + 3 * (size_t)c->bvh->ids[i];
        for (int k = 0; k < 3; ++k)
            for (int d = 0; d < 3; ++d)
                c->bvh->corners[9 * i + 3 * k + d] = (float)c->positions[3 * (size_t)tri[k] + d];
    }
    return 0;
}

static resurf_status build_tree(const resurf_allocator *alloc, const double *positions, size_t vertex_count,
                                const uint32_t *indices, size_t triangle_count, unsigned threads, resurfi_bvh **out)
{
    if (!out)
        return RESURF_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (triangle_count && (!indices || !positions))
        return RESURF_ERR_INVALID_ARGUMENT;
    if (triangle_count > UINT32_MAX / 2) /* node indices are 32-bit and a tree may have up to 2n nodes */
        return RESURF_ERR_LIMIT;
    resurfi_bvh *bvh = resurfi_calloc(alloc, 1, sizeof *bvh);
    if (bvh && alloc)
        bvh->alloc = *alloc;
    prim *prims = resurfi_alloc(alloc, triangle_count, sizeof *prims);
    node_vec vec = {.alloc = alloc};
    if (!bvh || !prims)
        goto oom;
    enum { BLOCK = 65536 };
    pass_ctx pc = {positions, vertex_count, indices, prims, bvh};
    resurfi_parallel_for(triangle_count, BLOCK, threads, make_prims, &pc);
    size_t n = 0; /* keep the valid triangles, in order */
    for (size_t t = 0; t < triangle_count; ++t)
        if (prims[t].id != UINT32_MAX)
            prims[n++] = prims[t];
    bvh->triangle_count = n;
    bvh->positions = positions;
    bvh->indices = indices;
    if (n > 0) {
        box bounds, cbounds;
        bound_range(prims, 0, n, &bounds, &cbounds);
        if (vec_reserve(&vec, n) != 0 || vec_start(&vec) != 0) /* typically about 0.6 n nodes; grows if needed */
            goto oom;
        if (build_node(prims, &vec, 0, 0, n, bounds, cbounds, 0, threads) != 0)
            goto oom;
        /* The final array is 64-byte aligned so that each sibling pair (32 bytes each, at even slots) is one line;
         * the allocator promises malloc's alignment only, so the block has room to align within. Each temporary
         * goes as soon as it is copied: the corners, the largest block, come when only the tree is left. */
        if (!(bvh->node_block = resurfi_alloc(alloc, vec.count * sizeof(bvh_node) + 63, 1)))
            goto oom;
        bvh->nodes = (bvh_node *)(((uintptr_t)bvh->node_block + 63) & ~(uintptr_t)63);
        memcpy(bvh->nodes, vec.nodes, vec.count * sizeof(bvh_node));
        bvh->node_count = vec.count;
        resurfi_free(alloc, vec.nodes);
        vec.nodes = NULL;
        if (!(bvh->ids = resurfi_alloc(alloc, n, sizeof(uint32_t))))
            goto oom;
        for (size_t i = 0; i < n; ++i)
            bvh->ids[i] = prims[i].id;
        resurfi_free(alloc, prims);
        prims = NULL;
        if (!(bvh->corners = resurfi_alloc(alloc, n, 9 * sizeof(float))))
            goto oom;
        resurfi_parallel_for(n, BLOCK, threads, copy_corners, &pc);
        /* Rounding to float moves a coordinate x by at most |x| 2^-24 (2^-150 below float's normal range), a
         * corner by √3 times that: 2^-21 of the largest coordinate covers it twice over. */
        double big = 0;
        for (size_t i = 0; i < 3 * vertex_count; ++i)
            if (isfinite(positions[i]))
                big = fmax(big, fabs(positions[i]));
        bvh->slack = big * 0x1p-21 + 0x1p-140;
        bvh->exact_only = big > 0x1p120;
    }
    resurfi_free(alloc, vec.nodes);
    resurfi_free(alloc, prims);
    *out = bvh;
    return RESURF_OK;
oom:
    resurfi_free(alloc, vec.nodes);
    resurfi_free(alloc, prims);
    resurfi_bvh_free(bvh);
    return RESURF_ERR_OUT_OF_MEMORY;
}

resurf_status resurfi_bvh_build(const resurf_allocator *alloc, const double *positions, size_t vertex_count,
                                const uint32_t *indices, size_t triangle_count, resurfi_bvh **out)
{
    return build_tree(alloc, positions, vertex_count, indices, triangle_count, resurfi_thread_count(0), out);
}

resurf_status resurfi_bvh_build_threads(const resurf_allocator *alloc, const double *positions, size_t vertex_count,
                                        const uint32_t *indices, size_t triangle_count, unsigned threads,
                                        resurfi_bvh **out)
{
    return build_tree(alloc, positions, vertex_count, indices, triangle_count, resurfi_thread_count(threads), out);
}

void resurfi_bvh_free(resurfi_bvh *bvh)
{
    if (!bvh)
        return;
    const resurf_allocator alloc = bvh->alloc; /* the struct holding it goes last */
    resurfi_free(&alloc, bvh->node_block);
    resurfi_free(&alloc, bvh->corners);
    resurfi_free(&alloc, bvh->ids);
    resurfi_free(&alloc, bvh);
}

size_t resurfi_bvh_triangle_count(const resurfi_bvh *bvh) { return bvh ? bvh->triangle_count : 0; }

/* ---- queries ------------------------------------------------------------------------------------------------------ */

/* Squared distance from p to a node's box, in double (the float box converts exactly). */
static inline double box_dist2(const bvh_node *n, vec3 p)
{
    double lx = n->lo[0], ly = n->lo[1], lz = n->lo[2], hx = n->hi[0], hy = n->hi[1], hz = n->hi[2];
    double dx = p.x < lx ? lx - p.x : p.x > hx ? p.x - hx : 0;
    double dy = p.y < ly ? ly - p.y : p.y > hy ? p.y - hy : 0;
    double dz = p.z < lz ? lz - p.z : p.z > hz ? p.z - hz : 0;
    return dx * dx + dy * dy + dz * dz;
}

/* Is a box at squared distance d2 possibly holding a triangle at squared distance <= limit? The relative slack
 * covers rounding in the two sums of squares (box and triangle distances are computed differently). */
static inline int box_in_reach(double d2, double limit) { return d2 <= limit + limit * 0x1p-44; }

/* Visits leaves in nearer-first order; visit() returns the current limit (it may shrink as results come in). */
typedef double (*leaf_fn)(void *ctx, const resurfi_bvh *bvh, const bvh_node *leaf, vec3 p);

static void traverse(const resurfi_bvh *bvh, vec3 p, double limit, leaf_fn visit, void *ctx)
{
    if (!bvh || bvh->node_count == 0)
        return;
    struct {
        uint32_t node;
        double d2;
    } stack[STACK_SIZE];
    int top = 0;
    uint32_t cur = 0;
    if (!box_in_reach(box_dist2(&bvh->nodes[0], p), limit))
        return;
    for (;;) {
        const bvh_node *n = &bvh->nodes[cur];
        int descend = 0;
        if (n->count) {
            limit = visit(ctx, bvh, n, p);
        } else {
            uint32_t l = n->index, r = n->index + 1;
            double dl = box_dist2(&bvh->nodes[l], p), dr = box_dist2(&bvh->nodes[r], p);
            if (dr < dl) {
                uint32_t t = l;
                l = r, r = t;
                double td = dl;
                dl = dr, dr = td;
            }
            if (box_in_reach(dl, limit)) {
                /* At most one entry per level: the depth bound (80) keeps this below STACK_SIZE. */
                if (box_in_reach(dr, limit) && top < STACK_SIZE)
                    stack[top].node = r, stack[top].d2 = dr, ++top;
                cur = l;
                descend = 1;
            }
        }
        if (descend)
            continue;
        /* Pop the next box still in reach. */
        while (top > 0) {
            --top;
            if (box_in_reach(stack[top].d2, limit)) {
                cur = stack[top].node;
                descend = 1;
                break;
            }
        }
        if (!descend)
            return;
    }
}

/* Could leaf triangle i be within squared distance limit2 of p? Measured on its float corners: the true distance
 * is at most slack less (the float distance's own rounding is covered by the 2^-40). */
static inline int may_reach(const resurfi_bvh *bvh, uint32_t i, vec3 p, double limit2)
{
    if (bvh->exact_only || !(limit2 < INFINITY))
        return 1;
    const float *c = bvh->corners + 9 * (size_t)i;
    double reach = sqrt(limit2) + bvh->slack, reach2 = reach * reach;
    /* First the float triangle's own box, a lower bound of its distance at a tenth of the cost: most of a leaf's
     * triangles that cannot win stop here. */
    double box2 = 0, q[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; ++k) {
        float x = c[k], y = c[3 + k], z = c[6 + k];
        double lo = x < y ? (x < z ? x : z) : (y < z ? y : z), hi = x > y ? (x > z ? x : z) : (y > z ? y : z);
        double e = q[k] < lo ? lo - q[k] : q[k] > hi ? q[k] - hi : 0;
        box2 += e * e;
    }
    if (box2 * (1 - 0x1p-40) > reach2)
        return 0;
    vec3 a = v3(c[0], c[1], c[2]), b = v3(c[3], c[4], c[5]), d = v3(c[6], c[7], c[8]);
    return v3_dist2(p, resurfi_closest_on_triangle(p, a, b, d, NULL)) * (1 - 0x1p-40) <= reach2;
}

/* The exact closest point on leaf triangle i, from the caller's double positions. */
static inline vec3 exact_closest(const resurfi_bvh *bvh, uint32_t i, vec3 p, double bary[3])
{
    const uint32_t *t = bvh->indices + 3 * (size_t)bvh->ids[i];
    return resurfi_closest_on_triangle(p, v3_load(bvh->positions + 3 * (size_t)t[0]),
                                       v3_load(bvh->positions + 3 * (size_t)t[1]),
                                       v3_load(bvh->positions + 3 * (size_t)t[2]), bary);
}

typedef struct closest_state {
    double best_d2;
    uint32_t best_id;
    vec3 best_point;
    double best_bary[3];
} closest_state;

static double visit_closest(void *ctx, const resurfi_bvh *bvh, const bvh_node *leaf, vec3 p)
{
    closest_state *s = ctx;
    for (uint32_t i = leaf->index; i < leaf->index + leaf->count; ++i) {
        if (!may_reach(bvh, i, p, s->best_d2))
            continue;
        double bary[3];
        vec3 q = exact_closest(bvh, i, p, bary);
        double d2 = v3_dist2(p, q);
        uint32_t id = bvh->ids[i];
        /* Exact ties go to the lowest triangle index, so the answer does not depend on the tree's shape. */
        if (d2 < s->best_d2 || (d2 == s->best_d2 && id < s->best_id)) {
            s->best_d2 = d2, s->best_id = id, s->best_point = q;
            memcpy(s->best_bary, bary, sizeof bary);
        }
    }
    return s->best_d2;
}

uint32_t resurfi_bvh_closest(const resurfi_bvh *bvh, vec3 p, double max_dist2, vec3 *out_point, double out_bary[3],
                             double *out_dist2)
{
    closest_state s = {.best_d2 = max_dist2, .best_id = UINT32_MAX};
    if (v3_finite(p) && max_dist2 >= 0)
        traverse(bvh, p, max_dist2, visit_closest, &s);
    if (s.best_id == UINT32_MAX)
        return UINT32_MAX;
    if (out_point)
        *out_point = s.best_point;
    if (out_bary)
        memcpy(out_bary, s.best_bary, sizeof s.best_bary);
    if (out_dist2)
        *out_dist2 = s.best_d2;
    return s.best_id;
}

uint32_t resurfi_bvh_closest_near(const resurfi_bvh *bvh, vec3 p, uint32_t hint, vec3 *out_point, double out_bary[3],
                                  double *out_dist2)
{
    if (hint == UINT32_MAX || !v3_finite(p))
        return resurfi_bvh_closest(bvh, p, INFINITY, out_point, out_bary, out_dist2);
    /* The hint is the best so far: the search prunes from its distance on, and finds what a search from nothing
     * finds (the nearest, the lowest index among ties), since every triangle at most as far as the hint is still
     * in reach. */
    closest_state s = {.best_id = hint};
    const uint32_t *t = bvh->indices + 3 * (size_t)hint;
    s.best_point = resurfi_closest_on_triangle(p, v3_load(bvh->positions + 3 * (size_t)t[0]),
                                               v3_load(bvh->positions + 3 * (size_t)t[1]),
                                               v3_load(bvh->positions + 3 * (size_t)t[2]), s.best_bary);
    s.best_d2 = v3_dist2(p, s.best_point);
    traverse(bvh, p, s.best_d2, visit_closest, &s);
    if (out_point)
        *out_point = s.best_point;
    if (out_bary)
        memcpy(out_bary, s.best_bary, sizeof s.best_bary);
    if (out_dist2)
        *out_dist2 = s.best_d2;
    return s.best_id;
}

typedef struct within_state {
    double max_d2;
    int (*fn)(void *ctx, uint32_t triangle, vec3 point, const double bary[3], double dist2);
    void *ctx;
    int stopped;
} within_state;

static double visit_within(void *ctx, const resurfi_bvh *bvh, const bvh_node *leaf, vec3 p)
{
    within_state *s = ctx;
    for (uint32_t i = leaf->index; i < leaf->index + leaf->count && !s->stopped; ++i) {
        if (!may_reach(bvh, i, p, s->max_d2))
            continue;
        double bary[3];
        vec3 q = exact_closest(bvh, i, p, bary);
        double d2 = v3_dist2(p, q);
        if (d2 <= s->max_d2 && s->fn(s->ctx, bvh->ids[i], q, bary, d2) != 0)
            s->stopped = 1;
    }
    /* A stop request empties the reach: every remaining box is then pruned. */
    return s->stopped ? -1.0 : s->max_d2;
}

int resurfi_bvh_within(const resurfi_bvh *bvh, vec3 p, double max_dist2,
                       int (*fn)(void *ctx, uint32_t triangle, vec3 point, const double bary[3], double dist2),
                       void *ctx)
{
    within_state s = {.max_d2 = max_dist2, .fn = fn, .ctx = ctx};
    if (fn && v3_finite(p) && max_dist2 >= 0)
        traverse(bvh, p, max_dist2, visit_within, &s);
    return s.stopped;
}
