/* Deviation metrics between two meshes: one- and two-sided surface distances (Hausdorff, mean, RMS) from
 * area-uniform samples plus the vertices and, for the maximum, every triangle's centroid and edge midpoints (the
 * facet points), each measured exactly to the other surface through its BVH, the maximum then climbed to from the
 * best of them (max_climb.c); the
 * distances of TEST's vertices to REF; TEST's triangle quality; the normal deviation of TEST's faces; and, when both
 * carry TEXCOORD_0, the UV error at TEST's samples (its UV there against REF's at the closest point), whose helpers
 * the simplifier's report shares.
 *
 * Sampling follows Metro (P. Cignoni, C. Rocchini, R. Scopigno, "Metro: measuring error on simplified surfaces",
 * 1998) with random instead of stratified points: a triangle is drawn with probability proportional to its area
 * (binary search in the cumulative areas) and a point in it by the square-root warp b = (1 − √r1, √r1 (1 − r2),
 * √r1 r2) (Osada et al. 2002), which is uniform over the triangle.
 *
 * Determinism: sample i draws its three random numbers from positions 3i..3i+2 of a splitmix64 stream, which can
 * be evaluated at any position directly, so every point is a pure function of (seed, i); each point's distance
 * is written to its own slot, and the sums run afterwards in index order on one thread. The BVH is the same for
 * every thread count. So the figures do not depend on the number of threads. */
#include <stdlib.h>
#include <string.h>

#include "hash.h"
#include "internal.h"

#define DEG_PER_RAD (180.0 / 3.14159265358979323846)
/* Points per progress report (and per parallel batch). */
#define BATCH 65536
#define BLOCK 512

/* ---- random points ------------------------------------------------------------------------------------------- */

/* Output k of the splitmix64 stream that starts at state `seed` (Steele, Lea, Flood 2014), in [0, 1). */
static double splitmix_unit(uint64_t seed, uint64_t k)
{
    return (double)(resurfi_mix64(seed + (k + 1) * RESURFI_GOLDEN_GAMMA) >> 11) * 0x1.0p-53;
}

/* One surface to sample and the other one's tree to measure against. */
typedef struct side {
    const resurf_mesh *from;
    const double *cumulative_area; /* triangle_count inclusive prefix sums of the triangle areas */
    double total_area;
    size_t samples;                /* 0 when the surface has no area */
    uint64_t stream;
    const resurfi_bvh *to;
    const resurf_mesh *to_mesh;    /* the surface `to` is built over */
    size_t facets;                 /* facet points measured after the vertices (resurfi_side_max), or 0 */
    double *distance;              /* samples + from->vertex_count (+ facets) */
    double *uv;                    /* samples: UV errors, or NULL when not measured */
} side;

/* The smallest triangle index whose cumulative area exceeds u (so zero-area triangles are never drawn). */
static size_t pick_triangle(const double *cumulative, size_t count, double u)
{
    size_t lo = 0, hi = count - 1;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (cumulative[mid] > u)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

/* Sample i of a side: its point, its triangle and barycentrics there. */
static vec3 sample_point(const side *s, size_t i, uint32_t *out_t, double bary[3])
{
    const resurf_mesh *m = s->from;
    double r0 = splitmix_unit(s->stream, 3 * (uint64_t)i), r1 = splitmix_unit(s->stream, 3 * (uint64_t)i + 1),
           r2 = splitmix_unit(s->stream, 3 * (uint64_t)i + 2);
    size_t t = pick_triangle(s->cumulative_area, m->triangle_count, r0 * s->total_area);
    const uint32_t *f = m->indices + 3 * t;
    double q = sqrt(r1);
    bary[0] = 1.0 - q, bary[1] = q * (1.0 - r2), bary[2] = q * r2;
    *out_t = (uint32_t)t;
    vec3 p = v3_scale(resurfi_position(m, f[0]), bary[0]);
    p = v3_madd(p, resurfi_position(m, f[1]), bary[1]);
    return v3_madd(p, resurfi_position(m, f[2]), bary[2]);
}

/* Points [begin, end) of a side: samples first, then every vertex. At the samples, with uv set, the UV error
 * against the other surface too. */
static int measure_points(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    const side *s = ctx;
    size_t vertices_end = s->samples + s->from->vertex_count;
    /* Each search starts from the triangle the point before ended at: neighbouring vertices and facet points are
     * mostly near each other, and the answer is the same from any start. */
    uint32_t hint = UINT32_MAX;
    for (size_t i = begin; i < end; ++i) {
        if (i >= vertices_end) {
            vec3 p;
            double d2;
            if (!resurfi_facet_point(s->from, i - vertices_end, &p)) {
                s->distance[i] = 0;
                continue;
            }
            hint = resurfi_bvh_closest_near(s->to, p, hint, NULL, NULL, &d2);
            s->distance[i] = hint == UINT32_MAX ? INFINITY : sqrt(d2);
            continue;
        }
        if (i >= s->samples) {
            vec3 p = resurfi_position(s->from, (uint32_t)(i - s->samples));
            double d2;
            hint = resurfi_bvh_closest_near(s->to, p, hint, NULL, NULL, &d2);
            s->distance[i] = hint == UINT32_MAX ? INFINITY : sqrt(d2);
            continue;
        }
        uint32_t t;
        double b[3], cb[3], d2;
        vec3 p = sample_point(s, i, &t, b);
        uint32_t c = resurfi_bvh_closest(s->to, p, INFINITY, NULL, cb, &d2);
        s->distance[i] = c == UINT32_MAX ? INFINITY : sqrt(d2);
        if (s->uv)
            s->uv[i] = c == UINT32_MAX ? INFINITY : resurfi_uv_distance(s->from, t, b, s->to_mesh, c, cb);
    }
    return 0;
}

/* ---- UV error ------------------------------------------------------------------------------------------------ */

int resurfi_has_uv0(const resurf_mesh *m) { return m->texcoord_count >= 1 && m->texcoords[0] != NULL; }

static void uv_at(const resurf_mesh *m, uint32_t t, const double b[3], double uv[2])
{
    const uint32_t *f = m->indices + 3 * (size_t)t;
    const double *tc = m->texcoords[0];
    for (int c = 0; c < 2; ++c)
        uv[c] = b[0] * tc[2 * (size_t)f[0] + c] + b[1] * tc[2 * (size_t)f[1] + c] + b[2] * tc[2 * (size_t)f[2] + c];
}

double resurfi_uv_distance(const resurf_mesh *a, uint32_t ta, const double ba[3], const resurf_mesh *b, uint32_t tb,
                           const double bb[3])
{
    double ua[2], ub[2];
    uv_at(a, ta, ba, ua);
    uv_at(b, tb, bb, ub);
    return hypot(ua[0] - ub[0], ua[1] - ub[1]);
}

static int compare_doubles(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

void resurfi_uv_summary(double *values, size_t n, double *out_mean, double *out_p95)
{
    double sum = 0;
    for (size_t i = 0; i < n; ++i)
        sum += values[i];
    *out_mean = sum / (double)n;
    qsort(values, n, sizeof *values, compare_doubles);
    size_t rank = (size_t)ceil(0.95 * (double)n); /* nearest rank: the smallest value with 95% at or below it */
    *out_p95 = values[rank ? rank - 1 : 0];
}

/* ---- normal deviation ---------------------------------------------------------------------------------------- */

typedef struct normal_job {
    const resurf_mesh *test, *ref;
    const resurfi_bvh *ref_bvh;
    double *angle, *weight; /* per TEST triangle: the deviation in degrees and its area (0 = left out) */
} normal_job;

/* The angle between two unit vectors, accurate near 0 and 180 degrees (acos loses half the digits there). */
static double angle_deg(vec3 a, vec3 b) { return atan2(v3_len(v3_cross(a, b)), v3_dot(a, b)) * DEG_PER_RAD; }

static int measure_normals(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    const normal_job *j = ctx;
    for (size_t t = begin; t < end; ++t) {
        const uint32_t *f = j->test->indices + 3 * t;
        vec3 a = resurfi_position(j->test, f[0]), b = resurfi_position(j->test, f[1]),
             c = resurfi_position(j->test, f[2]);
        vec3 cross = v3_tri_cross(a, b, c);
        double area = 0.5 * v3_len(cross);
        j->angle[t] = 0;
        j->weight[t] = 0;
        if (!(area > 0))
            continue;
        vec3 centroid = v3_scale(v3_add(v3_add(a, b), c), 1.0 / 3.0);
        uint32_t r = resurfi_bvh_closest(j->ref_bvh, centroid, INFINITY, NULL, NULL, NULL);
        if (r == UINT32_MAX)
            continue;
        const uint32_t *g = j->ref->indices + 3 * (size_t)r;
        vec3 n = v3_normalize(v3_tri_cross(resurfi_position(j->ref, g[0]), resurfi_position(j->ref, g[1]),
                                           resurfi_position(j->ref, g[2])));
        if (v3_len2(n) == 0)
            continue; /* a zero-area REF triangle won the tie at the closest point: no normal to compare */
        j->angle[t] = angle_deg(v3_scale(cross, 0.5 / area), n);
        j->weight[t] = area;
    }
    return 0;
}

/* ---- checks -------------------------------------------------------------------------------------------------- */

/* Are the mesh's indices in range and the corners of its triangles finite? name is "REF", "TEST" or "mesh". */
static resurf_status check_triangles(const resurf_mesh *m, const char *name, resurf_error *error)
{
    if ((m->vertex_count && !m->positions) || (m->triangle_count && !m->indices))
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "%s has counts but no arrays", name);
    for (size_t i = 0; i < 3 * m->triangle_count; ++i) {
        uint32_t v = m->indices[i];
        if (v >= m->vertex_count)
            return resurfi_error(error, RESURF_ERR_INVALID_MESH, "%s: triangle %zu refers to vertex %u of %zu", name,
                                 i / 3, (unsigned)v, m->vertex_count);
        if (!v3_finite(resurfi_position(m, v)))
            return resurfi_error(error, RESURF_ERR_INVALID_MESH, "%s: vertex %u of triangle %zu is not finite", name,
                                 (unsigned)v, i / 3);
    }
    return RESURF_OK;
}

/* The smallest interior angle of triangle (a, b, c) in degrees; 0 for coincident or collinear corners. */
static double smallest_angle_deg(vec3 a, vec3 b, vec3 c)
{
    const vec3 p[3] = {a, b, c};
    double smallest = 180.0;
    for (int i = 0; i < 3; ++i) {
        vec3 e1 = v3_sub(p[(i + 1) % 3], p[i]), e2 = v3_sub(p[(i + 2) % 3], p[i]);
        if (v3_len2(e1) == 0 || v3_len2(e2) == 0)
            return 0;
        smallest = fmin(smallest, angle_deg(e1, e2));
    }
    return smallest;
}

/* Quality figures of a checked mesh. */
static void triangle_quality(const resurf_mesh *m, double *min_deg, double *mean_deg, double *share)
{
    double lo = m->triangle_count ? 180.0 : 0.0, sum = 0;
    size_t below = 0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t *f = m->indices + 3 * t;
        double a = smallest_angle_deg(resurfi_position(m, f[0]), resurfi_position(m, f[1]),
                                      resurfi_position(m, f[2]));
        lo = fmin(lo, a);
        sum += a;
        below += a < 10.0;
    }
    double n = m->triangle_count ? (double)m->triangle_count : 1.0;
    *min_deg = lo;
    *mean_deg = sum / n;
    *share = (double)below / n;
}

/* ---- the comparison ------------------------------------------------------------------------------------------ */

typedef struct side_stats {
    double max, mean, mean_square;
} side_stats;

/* Cumulative triangle areas of a checked mesh. */
static double *cumulative_areas(const resurf_allocator *alloc, const resurf_mesh *m, double *out_total)
{
    double *cum = resurfi_alloc(alloc, m->triangle_count, sizeof *cum);
    if (!cum)
        return NULL;
    double total = 0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t *f = m->indices + 3 * t;
        total += 0.5 * v3_len(v3_tri_cross(resurfi_position(m, f[0]), resurfi_position(m, f[1]),
                                           resurfi_position(m, f[2])));
        cum[t] = total;
    }
    *out_total = total;
    return cum;
}

/* A parallel job over [base, base + n): parallel_for counts from 0, the batch adds its base. */
typedef struct batch {
    int (*fn)(void *ctx, size_t begin, size_t end, unsigned worker);
    void *ctx;
    size_t base;
} batch;

static int run_batch(void *ctx, size_t begin, size_t end, unsigned worker)
{
    const batch *b = ctx;
    return b->fn(b->ctx, b->base + begin, b->base + end, worker);
}

/* Runs fn over [0, count) on `threads` threads in batches, reporting progress before each; *done and total count
 * the whole call's work. Returns 1 when cancelled. */
static int run_batches(size_t count, unsigned threads, int (*fn)(void *, size_t, size_t, unsigned), void *ctx,
                       const resurf_progress *progress, size_t *done, size_t total)
{
    for (size_t base = 0; base < count; base += BATCH) {
        size_t n = count - base < BATCH ? count - base : BATCH;
        if (resurfi_progress(progress, RESURF_STAGE_COMPARE, (double)*done / (double)total))
            return 1;
        batch b = {fn, ctx, base};
        resurfi_parallel_for(n, BLOCK, threads, run_batch, &b);
        *done += n;
    }
    return 0;
}

/* Max over samples and used vertices; mean and mean square over the samples (over the used vertices without
 * samples). used[v] says whether a triangle uses vertex v. */
static side_stats summarize(const side *s, const uint8_t *used)
{
    side_stats st = {0, 0, 0};
    double sum = 0, sum2 = 0;
    size_t n = 0;
    for (size_t i = 0; i < s->samples; ++i) {
        double d = s->distance[i];
        st.max = fmax(st.max, d);
        sum += d;
        sum2 += d * d;
        ++n;
    }
    for (size_t v = 0; v < s->from->vertex_count; ++v) {
        if (!used[v])
            continue;
        double d = s->distance[s->samples + v];
        st.max = fmax(st.max, d);
        if (s->samples == 0) {
            sum += d;
            sum2 += d * d;
            ++n;
        }
    }
    for (size_t k = 0; k < s->facets; ++k)
        st.max = fmax(st.max, s->distance[s->samples + s->from->vertex_count + k]);
    if (n) {
        st.mean = sum / (double)n;
        st.mean_square = sum2 / (double)n;
    }
    return st;
}

/* The side's maximum climbed to from its best samples and facet points (max_climb.c). */
static double climbed_max(const side *s, double max)
{
    resurfi_max_starts starts = {0};
    size_t facets_begin = s->samples + s->from->vertex_count;
    for (size_t i = 0; i < facets_begin + s->facets; ++i) {
        double d = s->distance[i], b[3];
        uint32_t t;
        if ((i >= s->samples && i < facets_begin) ||
            (starts.count == RESURFI_MAX_STARTS && d <= starts.start[RESURFI_MAX_STARTS - 1].d))
            continue;
        if (i < s->samples)
            sample_point(s, i, &t, b);
        else
            resurfi_facet_point_place(i - facets_begin, &t, b);
        resurfi_max_starts_offer(&starts, d, t, b);
    }
    return resurfi_max_starts_climb(&starts, s->from, s->to, max);
}

static uint8_t *used_vertices(const resurf_allocator *alloc, const resurf_mesh *m)
{
    uint8_t *used = resurfi_calloc(alloc, m->vertex_count, 1);
    if (used)
        for (size_t i = 0; i < 3 * m->triangle_count; ++i)
            used[m->indices[i]] = 1;
    return used;
}

/* Everything resurf_compare allocates, freed in one place. */
typedef struct compare_work {
    resurfi_bvh *ref_bvh, *test_bvh;
    double *ref_cum, *test_cum;
    double *ref_dist, *test_dist;
    double *angle, *weight;
    double *uv;                    /* per TEST sample: the UV error, when both carry UVs */
    uint8_t *ref_used, *test_used;
    const resurf_allocator *alloc; /* the call's, for everything above */
} compare_work;

static void compare_work_free(compare_work *w)
{
    resurfi_bvh_free(w->ref_bvh);
    resurfi_bvh_free(w->test_bvh);
    resurfi_free(w->alloc, w->ref_cum);
    resurfi_free(w->alloc, w->test_cum);
    resurfi_free(w->alloc, w->ref_dist);
    resurfi_free(w->alloc, w->test_dist);
    resurfi_free(w->alloc, w->angle);
    resurfi_free(w->alloc, w->weight);
    resurfi_free(w->alloc, w->uv);
    resurfi_free(w->alloc, w->ref_used);
    resurfi_free(w->alloc, w->test_used);
}

static resurf_status compare_fail(compare_work *w, resurf_error *error, resurf_status st, const char *what)
{
    compare_work_free(w);
    if (st == RESURF_ERR_CANCELLED)
        return resurfi_error(error, st, "comparison cancelled");
    return resurfi_error(error, st, "%s while %s", resurf_status_string(st), what);
}

/* One side alone (resurf_compare's points and figures): for scene measurements that reuse one tree many times. */
int resurfi_facet_point(const resurf_mesh *m, size_t k, vec3 *out)
{
    const uint32_t *f = m->indices + 3 * (k / RESURFI_FACET_POINTS);
    size_t j = k % RESURFI_FACET_POINTS;
    if (j == 0) {
        vec3 a = resurfi_position(m, f[0]), b = resurfi_position(m, f[1]), c = resurfi_position(m, f[2]);
        *out = v3_scale(v3_add(v3_add(a, b), c), 1.0 / 3);
        return 1;
    }
    uint32_t u = f[j - 1], v = f[j % 3];
    if (u > v)
        return 0;
    *out = v3_scale(v3_add(resurfi_position(m, u), resurfi_position(m, v)), 0.5);
    return 1;
}

/* Where facet point k lies: its triangle, and its barycentrics there (the order of resurfi_facet_point). */
void resurfi_facet_point_place(size_t k, uint32_t *t, double b[3])
{
    *t = (uint32_t)(k / RESURFI_FACET_POINTS);
    size_t j = k % RESURFI_FACET_POINTS;
    if (j == 0) {
        b[0] = b[1] = b[2] = 1.0 / 3;
        return;
    }
    b[0] = b[1] = b[2] = 0;
    b[j - 1] = b[j % 3] = 0.5;
}

resurf_status resurfi_side_max(const resurf_allocator *alloc, const resurf_mesh *from, size_t samples, uint64_t seed,
                               int facet_points, const resurfi_bvh *to, unsigned threads, double *out_max)
{
    *out_max = NAN;
    if (from->triangle_count == 0)
        return RESURF_OK;
    double area = 0;
    double *cum = cumulative_areas(alloc, from, &area);
    uint8_t *used = used_vertices(alloc, from);
    side sd = {from, cum, area, area > 0 ? samples : 0, seed, to, NULL, 0, NULL, NULL};
    sd.facets = facet_points ? RESURFI_FACET_POINTS * from->triangle_count : 0;
    size_t points = sd.samples + from->vertex_count + sd.facets;
    sd.distance = resurfi_alloc(alloc, points + 1, sizeof *sd.distance);
    resurf_status st = cum && used && sd.distance ? RESURF_OK : RESURF_ERR_OUT_OF_MEMORY;
    if (st == RESURF_OK) {
        resurfi_parallel_for(points, BLOCK, threads, measure_points, &sd);
        *out_max = climbed_max(&sd, summarize(&sd, used).max);
    }
    resurfi_free(alloc, sd.distance);
    resurfi_free(alloc, used);
    resurfi_free(alloc, cum);
    return st;
}

/* ---- public -------------------------------------------------------------------------------------------------- */

resurf_compare_options resurf_compare_options_default(void)
{
    resurf_compare_options o;
    memset(&o, 0, sizeof o);
    o.struct_size = sizeof o;
    o.samples = 200000;
    o.seed = 1;
    o.threads = 0;
    return o;
}

resurf_status resurf_triangle_quality(const resurf_mesh *mesh, double *out_min_deg, double *out_mean_min_deg,
                                      double *out_share_below_10, resurf_error *error)
{
    resurfi_clear_error(error);
    if (!mesh)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "mesh is NULL");
    resurf_status st = check_triangles(mesh, "mesh", error);
    if (st != RESURF_OK)
        return st;
    double lo, mean, share;
    triangle_quality(mesh, &lo, &mean, &share);
    if (out_min_deg)
        *out_min_deg = lo;
    if (out_mean_min_deg)
        *out_mean_min_deg = mean;
    if (out_share_below_10)
        *out_share_below_10 = share;
    return RESURF_OK;
}

resurf_status resurf_compare(const resurf_mesh *ref, const resurf_mesh *test, const resurf_compare_options *options,
                             resurf_compare_report *out_report, double *out_vertex_distance, resurf_error *error)
{
    resurfi_clear_error(error);
    if (!ref || !test || !out_report)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "%s is NULL",
                             !ref ? "ref" : !test ? "test" : "out_report");
    RESURFI_CHECK_OPTIONS_ALLOC(options, resurf_compare_options, error);
    const resurf_compare_options o = options ? *options : resurf_compare_options_default();
    if (o.samples > 1000000000u)
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "samples %zu is above 10^9", o.samples);
    resurf_status st = check_triangles(ref, "REF", error);
    if (st == RESURF_OK)
        st = check_triangles(test, "TEST", error);
    if (st != RESURF_OK)
        return st;
    if (ref->triangle_count == 0 || test->triangle_count == 0)
        return resurfi_error(error, RESURF_ERR_INVALID_MESH, "%s has no triangles",
                             ref->triangle_count == 0 ? "REF" : "TEST");
    unsigned threads = resurfi_thread_count(o.threads);

    compare_work w;
    memset(&w, 0, sizeof w);
    w.alloc = resurfi_allocator_of(o.allocator, ref);
    double ref_area = 0, test_area = 0;
    w.ref_cum = cumulative_areas(w.alloc, ref, &ref_area);
    w.test_cum = cumulative_areas(w.alloc, test, &test_area);
    w.ref_used = used_vertices(w.alloc, ref);
    w.test_used = used_vertices(w.alloc, test);
    if (!w.ref_cum || !w.test_cum || !w.ref_used || !w.test_used)
        return compare_fail(&w, error, RESURF_ERR_OUT_OF_MEMORY, "preparing the comparison");
    /* A surface of zero area has nothing to sample: its vertices alone stand for it. */
    side test_side = {test, w.test_cum, test_area, test_area > 0 ? o.samples : 0, o.seed, NULL, ref, 0, NULL, NULL};
    side ref_side = {ref, w.ref_cum, ref_area, ref_area > 0 ? o.samples : 0, o.seed ^ 0xd1b54a32d192ed03ull, NULL,
                     test, 0, NULL, NULL};
    /* Each side's facet points too: a chord or a coarse facet leaves the other surface farthest at an edge's midpoint
     * or a centroid, a point that area samples may miss however many there are. */
    test_side.facets = RESURFI_FACET_POINTS * test->triangle_count;
    ref_side.facets = RESURFI_FACET_POINTS * ref->triangle_count;
    size_t test_points = test_side.samples + test->vertex_count + test_side.facets;
    size_t ref_points = ref_side.samples + ref->vertex_count + ref_side.facets;
    w.test_dist = resurfi_alloc(w.alloc, test_points, sizeof *w.test_dist);
    w.ref_dist = resurfi_alloc(w.alloc, ref_points, sizeof *w.ref_dist);
    w.angle = resurfi_alloc(w.alloc, test->triangle_count, sizeof *w.angle);
    w.weight = resurfi_alloc(w.alloc, test->triangle_count, sizeof *w.weight);
    if (test_side.samples && resurfi_has_uv0(test) && resurfi_has_uv0(ref) &&
        !(w.uv = test_side.uv = resurfi_alloc(w.alloc, test_side.samples, sizeof *w.uv)))
        return compare_fail(&w, error, RESURF_ERR_OUT_OF_MEMORY, "allocating the samples");
    if (!w.test_dist || !w.ref_dist || !w.angle || !w.weight)
        return compare_fail(&w, error, RESURF_ERR_OUT_OF_MEMORY, "allocating the samples");

    if (resurfi_progress(&o.progress, RESURF_STAGE_COMPARE, 0.0))
        return compare_fail(&w, error, RESURF_ERR_CANCELLED, NULL);
    st = resurfi_bvh_build_threads(w.alloc, ref->positions, ref->vertex_count, ref->indices, ref->triangle_count,
                                   threads, &w.ref_bvh);
    if (st != RESURF_OK)
        return compare_fail(&w, error, st, "building REF's tree");
    st = resurfi_bvh_build_threads(w.alloc, test->positions, test->vertex_count, test->indices, test->triangle_count,
                                   threads, &w.test_bvh);
    if (st != RESURF_OK)
        return compare_fail(&w, error, st, "building TEST's tree");
    test_side.to = w.ref_bvh;
    test_side.distance = w.test_dist;
    ref_side.to = w.test_bvh;
    ref_side.distance = w.ref_dist;

    size_t total = test_points + ref_points + test->triangle_count, done = 0;
    normal_job nj = {test, ref, w.ref_bvh, w.angle, w.weight};
    if (run_batches(test_points, threads, measure_points, &test_side, &o.progress, &done, total) ||
        run_batches(ref_points, threads, measure_points, &ref_side, &o.progress, &done, total) ||
        run_batches(test->triangle_count, threads, measure_normals, &nj, &o.progress, &done, total) ||
        resurfi_progress(&o.progress, RESURF_STAGE_COMPARE, 1.0))
        return compare_fail(&w, error, RESURF_ERR_CANCELLED, NULL);

    resurf_compare_report m;
    memset(&m, 0, sizeof m);
    double lo[3], hi[3];
    m.diagonal = resurf_mesh_bounds(ref, lo, hi);
    side_stats t2r = summarize(&test_side, w.test_used), r2t = summarize(&ref_side, w.ref_used);
    t2r.max = climbed_max(&test_side, t2r.max);
    r2t.max = climbed_max(&ref_side, r2t.max);
    m.test_to_ref_max = t2r.max;
    m.test_to_ref_mean = t2r.mean;
    m.ref_to_test_max = r2t.max;
    m.ref_to_test_mean = r2t.mean;
    m.hausdorff = fmax(t2r.max, r2t.max);
    m.mean = 0.5 * (t2r.mean + r2t.mean);
    m.rms = sqrt(0.5 * (t2r.mean_square + r2t.mean_square));
    size_t used = 0;
    for (size_t v = 0; v < test->vertex_count; ++v) {
        if (!w.test_used[v])
            continue;
        double d = w.test_dist[test_side.samples + v];
        m.vertex_max = fmax(m.vertex_max, d);
        m.vertex_mean += d;
        ++used;
    }
    m.vertex_mean /= used ? (double)used : 1.0;
    triangle_quality(test, &m.min_angle_deg, &m.mean_min_angle_deg, &m.share_below_10deg);
    double angle_sum = 0, weight_sum = 0;
    for (size_t t = 0; t < test->triangle_count; ++t) {
        angle_sum += w.angle[t] * w.weight[t];
        weight_sum += w.weight[t];
    }
    m.mean_normal_deviation_deg = weight_sum > 0 ? angle_sum / weight_sum : 0;
    m.uv_error_mean = m.uv_error_p95 = NAN;
    if (w.uv)
        resurfi_uv_summary(w.uv, test_side.samples, &m.uv_error_mean, &m.uv_error_p95);
    if (out_vertex_distance)
        memcpy(out_vertex_distance, w.test_dist + test_side.samples, test->vertex_count * sizeof(double));
    *out_report = m;
    compare_work_free(&w);
    return RESURF_OK;
}
