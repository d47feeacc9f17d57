/* The simplifier's report: the two-sided distance between a level and the input, and its UV error.
 *
 * Each side is a set of points on one surface measured to the other through a BVH over it, exactly (the closest
 * point on any triangle): measure_samples area-uniform samples, stratified over the cumulative area (sample i lies
 * in the slice [i, i + 1) / n of it), then the vertices, and on the result's side its facet points (each
 * triangle's centroid and edge midpoints, resurfi_facet_point): a level's long chords and coarse facets leave the
 * input farthest there, so its maximum needs no dense sampling (on a torus's 25% level, 5,000 samples and the
 * facet points find 0.996 of the maximum 2M samples find; 100k samples alone found 0.92). The samples then serve
 * the means, which converge fast; the maximum is then climbed to from the best points (max_climb.c), as
 * resurf_compare does. The result's points go to the input's tree (the one the
 * simplifier built for attributes), the input's points to a tree built over the level. A one-sided measure cannot
 * see what a level lost: a square of two triangles reduced to one lies on the input everywhere, and only the
 * input's points on the lost half find the distance. The figures are those of resurf_compare (metrics.c): the
 * maximum over the points, the mean over the samples, then max and mean of the two sides.
 *
 * The input's side is the same for every level of a chain: its cumulative areas and used vertices are found once
 * (measure_input) and its points drawn again from their indices. Points are pure functions of their index, each
 * block of BLOCK_SAMPLES writes its own max and sums, and those are combined in block order: the figures do not
 * depend on the thread count. */
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "simplify_internal.h"
#include "../hash.h"

/* A deterministic uniform number in [0, 1) for sample i, stream k. */
static double sample_unit(uint64_t i, uint64_t k)
{
    uint64_t z = i * RESURFI_GOLDEN_GAMMA + k * 0xd1b54a32d192ed03ull + 0x632be59bd9b4e019ull;
    return (double)(resurfi_mix64(z) >> 11) * 0x1.0p-53;
}

/* One side: the points of `from` (samples, then vertices) measured to the surface of `to_mesh` through `to`. */
typedef struct side {
    const resurf_mesh *from;
    const double *area_prefix;  /* from's triangle_count + 1 */
    size_t samples;
    const uint32_t *vertices;   /* the vertices measured after the samples, or NULL for all of from's */
    size_t vertex_count;
    size_t facets;              /* then its facet points (resurfi_facet_point), or 0 */
    uint64_t stream;            /* first of the three sample_unit streams of this side */
    const resurfi_bvh *to;
    const resurf_mesh *to_mesh;
    const uint32_t *rep;        /* per vertex of from: the vertex measured for its position (NONE: unused), or NULL
                                   when every vertex is measured */
    uint32_t *nearest;          /* per measured vertex of from: its closest triangle of to_mesh (the facet bound) */
    double *nearest_d;          /* and its distance to it */
    double vertex_floor;        /* the samples' maximum: a vertex within it of a triangle cannot raise the maximum */
    double facet_floor;         /* a facet point whose bound is at most this cannot raise the maximum: skipped */
    size_t first;               /* the first point of the running phase */
    double *block_max, *block_sum, *block_vertex_sum; /* per block of BLOCK_SAMPLES points */
    resurfi_max_starts *block_starts; /* per block: its best samples and facet points, to climb from */
    double *uv;                 /* per sample: the UV error, or NULL */
    double reject_scale, reject_bound; /* a point with reject_scale * d > reject_bound settles the level (0: off) */
    atomic_int *rejected;       /* set by the first such point: the other blocks stop */
} side;

static vec3 sample_point(const side *sd, size_t i, uint32_t *out_t, double b[3])
{
    const resurf_mesh *m = sd->from;
    size_t nt = m->triangle_count;
    double total = sd->area_prefix[nt];
    double target = ((double)i + sample_unit(i, sd->stream)) / (double)sd->samples * total;
    size_t lo = 0, hi = nt - 1;
    while (lo < hi) { /* first triangle whose prefix end exceeds target */
        size_t mid = (lo + hi) / 2;
        if (sd->area_prefix[mid + 1] > target)
            hi = mid;
        else
            lo = mid + 1;
    }
    double r1 = sqrt(sample_unit(i, sd->stream + 1)), r2 = sample_unit(i, sd->stream + 2);
    b[0] = 1 - r1, b[1] = r1 * (1 - r2), b[2] = r1 * r2;
    *out_t = (uint32_t)lo;
    const uint32_t *f = m->indices + 3 * lo;
    vec3 p = v3_scale(resurfi_position(m, f[0]), b[0]);
    p = v3_madd(p, resurfi_position(m, f[1]), b[1]);
    return v3_madd(p, resurfi_position(m, f[2]), b[2]);
}

/* Is facet point p (of from's triangle t) certainly no farther from to_mesh than floor? Its distance is at most
 * its distance to the triangles its corners are closest to, and that to the triangle of corner c is at most
 * |p - c| + c's own distance (the triangle inequality): that bound costs no search and settles most points; the
 * few it does not are tried on the three triangles (a corner not measured gives no bound). */
static int facet_within(const side *sd, uint32_t t, vec3 p, double floor, uint32_t *hint)
{
    const uint32_t *f = sd->from->indices + 3 * (size_t)t;
    uint32_t near[3];
    for (int k = 0; k < 3; ++k) {
        uint32_t v = sd->rep ? sd->rep[f[k]] : f[k];
        near[k] = v == NONE ? NONE : sd->nearest[v];
        if (near[k] != NONE && v3_dist(p, resurfi_position(sd->from, v)) + sd->nearest_d[v] <= floor)
            return 1;
    }
    double floor2 = floor * floor, best = INFINITY;
    for (int k = 0; k < 3; ++k) {
        if (near[k] == NONE)
            continue;
        const uint32_t *g = sd->to_mesh->indices + 3 * (size_t)near[k];
        vec3 q = resurfi_closest_on_triangle(p, resurfi_position(sd->to_mesh, g[0]),
                                             resurfi_position(sd->to_mesh, g[1]), resurfi_position(sd->to_mesh, g[2]),
                                             NULL);
        double d2 = v3_dist2(p, q);
        if (d2 <= floor2)
            return 1;
        if (d2 < best)
            best = d2, *hint = near[k];
    }
    return 0;
}

typedef struct within_hit {
    uint32_t t;
    double d2;
} within_hit;

static int first_within(void *ctx, uint32_t t, vec3 point, const double bary[3], double d2)
{
    (void)point, (void)bary;
    within_hit *hit = ctx;
    hit->t = t, hit->d2 = d2;
    return 1;
}

static int measure_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    const side *sd = ctx;
    double mx = 0, sum = 0, vertex_sum = 0;
    resurfi_max_starts *starts = &sd->block_starts[begin / BLOCK_SAMPLES];
    starts->count = 0;
    uint32_t hint = NONE; /* a triangle of `to` near the point, where the search starts (the answer is the same) */
    for (size_t i = sd->first + begin; i < sd->first + end; ++i) {
        if (atomic_load_explicit(sd->rejected, memory_order_relaxed))
            break;
        int is_sample = i < sd->samples, is_facet = i >= sd->samples + sd->vertex_count;
        uint32_t t = NONE, v = NONE;
        double b[3], cb[3], d2;
        vec3 p;
        if (is_sample) {
            p = sample_point(sd, i, &t, b);
        } else if (is_facet) {
            size_t k = i - sd->samples - sd->vertex_count;
            if (!resurfi_facet_point(sd->from, k, &p))
                continue;
            resurfi_facet_point_place(k, &t, b);
            if (facet_within(sd, t, p, sd->facet_floor, &hint))
                continue;
        } else {
            size_t k = i - sd->samples;
            v = sd->vertices ? sd->vertices[k] : (uint32_t)k;
            p = resurfi_position(sd->from, v);
        }
        int uv = is_sample && sd->uv;
        uint32_t c = NONE;
        if (!is_sample && !is_facet && sd->vertex_floor > 0) { /* any triangle within the floor will do */
            within_hit hit = {NONE, 0};
            resurfi_bvh_within(sd->to, p, sd->vertex_floor * sd->vertex_floor, first_within, &hit);
            c = hit.t, d2 = hit.d2;
        }
        if (c == NONE)
            c = resurfi_bvh_closest_near(sd->to, p, hint, NULL, uv ? cb : NULL, &d2);
        hint = c; /* the next sample lies in the next stretch of the cumulative area: mostly a neighbour */
        double d = c == NONE ? INFINITY : sqrt(d2);
        if (sd->reject_scale * d > sd->reject_bound) {
            atomic_store_explicit(sd->rejected, 1, memory_order_relaxed);
            break;
        }
        mx = d > mx ? d : mx;
        if (is_sample || is_facet)
            resurfi_max_starts_offer(starts, d, t, b);
        if (is_sample)
            sum += d;
        else if (!is_facet) {
            vertex_sum += d;
            sd->nearest[v] = c;
            sd->nearest_d[v] = d;
        }
        if (uv)
            sd->uv[i] = c == NONE ? INFINITY : resurfi_uv_distance(sd->from, t, b, sd->to_mesh, c, cb);
    }
    size_t block = begin / BLOCK_SAMPLES;
    sd->block_max[block] = mx;
    sd->block_sum[block] = sum;
    sd->block_vertex_sum[block] = vertex_sum;
    return 0;
}

/* Cumulative triangle areas of m, count + 1 entries. */
static double *area_prefix(const resurf_allocator *alloc, const resurf_mesh *m)
{
    double *a = resurfi_alloc(alloc, m->triangle_count + 1, sizeof *a);
    if (!a)
        return NULL;
    a[0] = 0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t *f = m->indices + 3 * t;
        a[t + 1] = a[t] + 0.5 * v3_len(v3_tri_cross(resurfi_position(m, f[0]), resurfi_position(m, f[1]),
                                                    resurfi_position(m, f[2])));
    }
    return a;
}

typedef struct placed_vertex {
    double p[3];
    uint32_t v;
} placed_vertex;

static int by_place(const void *pa, const void *pb)
{
    const placed_vertex *a = pa, *b = pb;
    for (int k = 0; k < 3; ++k)
        if (a->p[k] != b->p[k])
            return a->p[k] < b->p[k] ? -1 : 1;
    return (a->v > b->v) - (a->v < b->v);
}

/* Keeps one of the vertices at each position (the lowest index), in the order of their places: copies of a position
 * at a seam (split normals or texcoords) are one point of the surface, and CAD exports split most of theirs.
 * rep[v] (vertex_count entries, NONE before) becomes the vertex kept for v's position. */
static void one_per_position(const resurf_allocator *alloc, const resurf_mesh *in, uint32_t *vertices, size_t *count,
                             uint32_t *rep)
{
    placed_vertex *pv = resurfi_alloc(alloc, *count ? *count : 1, sizeof *pv);
    if (!pv) { /* measuring every copy gives the same figures, only slower */
        for (size_t i = 0; i < *count; ++i)
            rep[vertices[i]] = vertices[i];
        return;
    }
    for (size_t i = 0; i < *count; ++i) {
        memcpy(pv[i].p, in->positions + 3 * (size_t)vertices[i], sizeof pv[i].p);
        pv[i].v = vertices[i];
    }
    qsort(pv, *count, sizeof *pv, by_place);
    size_t n = 0;
    for (size_t i = 0; i < *count; ++i) {
        if (i == 0 || memcmp(pv[i].p, pv[i - 1].p, sizeof pv[i].p))
            vertices[n++] = pv[i].v;
        rep[pv[i].v] = vertices[n - 1];
    }
    *count = n;
    resurfi_free(alloc, pv);
}

/* The input's side, once per call: its cumulative areas and the vertices its triangles use, one per position. */
static resurf_status measure_input(simplifier *s)
{
    measure_state *ms = &s->measure;
    if (ms->in_area_prefix)
        return RESURF_OK;
    const resurf_mesh *in = s->in;
    uint8_t *used = resurfi_calloc(s->alloc, in->vertex_count, 1);
    ms->in_area_prefix = area_prefix(s->alloc, in);
    if (!used || !ms->in_area_prefix) {
        resurfi_free(s->alloc, used);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    for (size_t i = 0; i < 3 * in->triangle_count; ++i)
        used[in->indices[i]] = 1;
    size_t n = 0;
    for (size_t v = 0; v < in->vertex_count; ++v)
        n += used[v];
    if (!(ms->in_used = resurfi_alloc(s->alloc, n ? n : 1, sizeof *ms->in_used))) {
        resurfi_free(s->alloc, used);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    for (size_t v = 0; v < in->vertex_count; ++v)
        if (used[v])
            ms->in_used[ms->in_used_count++] = (uint32_t)v;
    resurfi_free(s->alloc, used);
    if (!(ms->in_rep = resurfi_alloc(s->alloc, in->vertex_count ? in->vertex_count : 1, sizeof *ms->in_rep)))
        return RESURF_ERR_OUT_OF_MEMORY;
    for (size_t v = 0; v < in->vertex_count; ++v)
        ms->in_rep[v] = NONE;
    one_per_position(s->alloc, in, ms->in_used, &ms->in_used_count, ms->in_rep);
    return RESURF_OK;
}

void measure_free(simplifier *s)
{
    resurfi_free(s->alloc, s->measure.in_area_prefix);
    resurfi_free(s->alloc, s->measure.in_used);
    resurfi_free(s->alloc, s->measure.in_rep);
    memset(&s->measure, 0, sizeof s->measure);
}

/* Points [first, first + count) of a side on the call's threads, their maximum, sums and best points merged into
 * the side's (in block order: the same for any thread count). */
static resurf_status run_phase(simplifier *s, side *sd, size_t first, size_t count, double acc[3],
                               resurfi_max_starts *starts)
{
    size_t blocks = (count + BLOCK_SAMPLES - 1) / BLOCK_SAMPLES;
    if (!blocks)
        return RESURF_OK;
    sd->block_max = resurfi_alloc(s->alloc, blocks, 3 * sizeof(double));
    sd->block_starts = resurfi_alloc(s->alloc, blocks, sizeof *sd->block_starts);
    resurf_status st = sd->block_max && sd->block_starts ? RESURF_OK : RESURF_ERR_OUT_OF_MEMORY;
    if (st == RESURF_OK) {
        sd->block_sum = sd->block_max + blocks;
        sd->block_vertex_sum = sd->block_sum + blocks;
        sd->first = first;
        resurfi_pool_for(s->pool, count, BLOCK_SAMPLES, measure_block, sd);
        for (size_t b = 0; b < blocks; ++b) {
            acc[0] = fmax(acc[0], sd->block_max[b]);
            acc[1] += sd->block_sum[b];
            acc[2] += sd->block_vertex_sum[b];
            for (size_t k = 0; k < sd->block_starts[b].count; ++k)
                resurfi_max_starts_offer(starts, sd->block_starts[b].start[k].d, sd->block_starts[b].start[k].t,
                                         sd->block_starts[b].start[k].b);
        }
    }
    resurfi_free(s->alloc, sd->block_starts);
    resurfi_free(s->alloc, sd->block_max);
    sd->block_starts = NULL;
    sd->block_max = sd->block_sum = sd->block_vertex_sum = NULL;
    return st;
}

/* A side's max and mean (over the samples, else over the vertices). The samples run first. Then the vertices,
 * which serve the maximum only: a vertex within the samples' maximum of some triangle cannot raise it, so its
 * search stops at the first such triangle (kept as its closest for the facet points' bound, an upper bound of its
 * distance as that bound needs); the others are measured exactly. Then the facet points, each skipped when its
 * distance to the triangles its corners are closest to (an upper bound of its distance) is at most the maximum so
 * far: it cannot raise it, so the maximum is the one over every facet point, exactly, at a few point-triangle tests
 * for most of them. Last the climb from the best points. */
static resurf_status run_side(simplifier *s, side *sd, double *out_max, double *out_mean)
{
    size_t points = sd->samples + sd->vertex_count, total = points + sd->facets;
    double acc[3] = {0, 0, 0}; /* max, sample sum, vertex sum */
    resurfi_max_starts starts = {0};
    sd->nearest = resurfi_alloc(s->alloc, sd->from->vertex_count ? sd->from->vertex_count : 1, sizeof *sd->nearest);
    sd->nearest_d = resurfi_alloc(s->alloc, sd->from->vertex_count ? sd->from->vertex_count : 1,
                                  sizeof *sd->nearest_d);
    if (!sd->nearest || !sd->nearest_d) {
        resurfi_free(s->alloc, sd->nearest);
        resurfi_free(s->alloc, sd->nearest_d);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    for (size_t v = 0; v < sd->from->vertex_count; ++v)
        sd->nearest[v] = NONE;
    resurf_status st = run_phase(s, sd, 0, sd->samples, acc, &starts);
    sd->vertex_floor = acc[0];
    if (st == RESURF_OK && !atomic_load(sd->rejected))
        st = run_phase(s, sd, sd->samples, sd->vertex_count, acc, &starts);
    sd->facet_floor = acc[0];
    if (st == RESURF_OK && !atomic_load(sd->rejected))
        st = run_phase(s, sd, points, sd->facets, acc, &starts);
    resurfi_free(s->alloc, sd->nearest);
    resurfi_free(s->alloc, sd->nearest_d);
    sd->nearest = NULL;
    sd->nearest_d = NULL;
    if (st != RESURF_OK)
        return st;
    if (atomic_load(sd->rejected)) {
        *out_max = INFINITY, *out_mean = NAN;
        return RESURF_OK;
    }
    *out_max = total ? resurfi_max_starts_climb(&starts, sd->from, sd->to, acc[0]) : NAN;
    *out_mean = sd->samples ? acc[1] / (double)sd->samples
                            : sd->vertex_count ? acc[2] / (double)sd->vertex_count : NAN;
    return RESURF_OK;
}

resurf_status measure_level(simplifier *s, const resurf_mesh *m, resurf_simplify_report *rep)
{
    rep->max_distance = rep->mean_distance = rep->max_distance_rel = rep->mean_distance_rel = NAN;
    rep->result_to_input_max = rep->result_to_input_mean = NAN;
    rep->input_to_result_max = rep->input_to_result_mean = NAN;
    rep->uv_error_mean = rep->uv_error_p95 = NAN;
    if (!s->opt.measure_samples || m->triangle_count == 0 || !s->bvh)
        return RESURF_OK;
    resurf_status st = measure_input(s);
    resurfi_bvh *level_bvh = NULL;
    double *level_area = NULL, *uv = NULL;
    if (st == RESURF_OK && !(level_area = area_prefix(s->alloc, m)))
        st = RESURF_ERR_OUT_OF_MEMORY;
    size_t n = s->opt.measure_samples;
    const double reject_scale = s->measure.reject_scale, reject_bound = s->measure.reject_bound;
    atomic_int rejected;
    atomic_init(&rejected, 0);
    side result = {.from = m, .area_prefix = level_area,
                   .samples = level_area && level_area[m->triangle_count] > 0 ? n : 0,
                   .vertex_count = m->vertex_count, .facets = RESURFI_FACET_POINTS * m->triangle_count,
                   .stream = 0, .to = s->bvh, .to_mesh = s->in, .reject_scale = reject_scale,
                   .reject_bound = reject_bound, .rejected = &rejected};
    const double *in_area = s->measure.in_area_prefix;
    side input = {.from = s->in, .area_prefix = in_area,
                  .samples = in_area && in_area[s->in->triangle_count] > 0 ? n : 0,
                  .vertices = s->measure.in_used, .vertex_count = s->measure.in_used_count,
                  .facets = RESURFI_FACET_POINTS * s->in->triangle_count, .stream = 3, .to_mesh = m,
                  .rep = s->measure.in_rep, .reject_scale = reject_scale, .reject_bound = reject_bound,
                  .rejected = &rejected};
    if (st == RESURF_OK && result.samples && resurfi_has_uv0(s->in) && resurfi_has_uv0(m) &&
        !(s->opt.unsampled_texcoords & 1) && /* a set nothing shows has no error to report */
        !(uv = result.uv = resurfi_alloc(s->alloc, result.samples, sizeof *uv)))
        st = RESURF_ERR_OUT_OF_MEMORY;
    if (st == RESURF_OK)
        st = run_side(s, &result, &rep->result_to_input_max, &rep->result_to_input_mean);
    /* The result's side settled a rejected level: the input's side is left unmeasured. */
    int settled = reject_scale * rep->result_to_input_max > reject_bound;
    if (st == RESURF_OK && !settled)
        st = resurfi_bvh_build_threads(s->alloc, m->positions, m->vertex_count, m->indices, m->triangle_count,
                                       s->opt.thread_pool ? 1 : s->opt.threads, &level_bvh);
    input.to = level_bvh;
    if (st == RESURF_OK && !settled)
        st = run_side(s, &input, &rep->input_to_result_max, &rep->input_to_result_mean);
    if (st == RESURF_OK && (settled || atomic_load(&rejected))) {
        /* Above the bound: said so, with no figures that could pass for measured ones. */
        rep->max_distance = rep->result_to_input_max = rep->input_to_result_max = INFINITY;
        rep->mean_distance = rep->result_to_input_mean = rep->input_to_result_mean = NAN;
        rep->max_distance_rel = s->diagonal > 0 ? INFINITY : NAN;
    } else if (st == RESURF_OK) {
        rep->max_distance = fmax(rep->result_to_input_max, rep->input_to_result_max);
        rep->mean_distance = 0.5 * (rep->result_to_input_mean + rep->input_to_result_mean);
        if (s->diagonal > 0) {
            rep->max_distance_rel = rep->max_distance / s->diagonal;
            rep->mean_distance_rel = rep->mean_distance / s->diagonal;
        }
        if (uv)
            resurfi_uv_summary(uv, result.samples, &rep->uv_error_mean, &rep->uv_error_p95);
    }
    resurfi_free(s->alloc, uv);
    resurfi_free(s->alloc, level_area);
    resurfi_bvh_free(level_bvh);
    return st;
}
