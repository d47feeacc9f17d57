/* One side of a two-sided distance against only the part of the other surface that can be nearest.
 *
 * resurf_scene_build_lods measures a few instances of a scene to the whole scene at the other level. A tree over the
 * whole scene costs far more than the few thousand points measured (on 2CylinderEngine the three trees of a 2-level
 * chain were 0.86 of the call's 8.0 G instructions, the points 0.43 G), so the tree is built over the triangles near
 * the points only. The answer is exact: every point (a sample, a vertex, a facet's centroid or edge midpoint) lies
 * in the box A of `from`'s vertices; a triangle of `to` whose box misses A grown by a margin m is, on some axis,
 * more than m away from every such point. When the largest distance found over the near triangles is at most m, each
 * point's nearest triangle among them is nearer than any triangle left out, so every distance (and the maximum) is
 * the one over all of `to`, bit for bit (the tree's closest point is exact). Otherwise the measure is made again with
 * m = that largest distance, which the larger set of triangles can only lower: two runs at most. */
#include <math.h>

#include "internal.h"

/* The triangles of `to` whose box meets [lo - m, hi + m] (all of them for an infinite m) into tris; their count. */
static size_t near_triangles(const resurf_mesh *to, const double lo[3], const double hi[3], double m, uint32_t *tris)
{
    size_t n = 0;
    for (size_t t = 0; t < to->triangle_count; ++t) {
        const uint32_t *f = to->indices + 3 * t;
        int in = 1;
        for (int k = 0; k < 3 && in && isfinite(m); ++k) {
            double a = to->positions[3 * (size_t)f[0] + k], b = to->positions[3 * (size_t)f[1] + k],
                   c = to->positions[3 * (size_t)f[2] + k];
            double tlo = dmin(a, dmin(b, c)), thi = dmax(a, dmax(b, c)); /* NaN either way: the tree skips it */
            in = !(tlo > hi[k] + m || thi < lo[k] - m);
        }
        if (in) {
            tris[3 * n] = f[0], tris[3 * n + 1] = f[1], tris[3 * n + 2] = f[2];
            ++n;
        }
    }
    return n;
}

resurf_status resurfi_side_max_nearby(const resurf_allocator *alloc, const resurf_mesh *from, size_t samples,
                                      uint64_t seed, int facet_points, const resurf_mesh *to, double margin,
                                      unsigned threads, double *out_max)
{
    *out_max = NAN;
    if (from->triangle_count == 0)
        return RESURF_OK;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, size = 0;
    for (size_t v = 0; v < from->vertex_count; ++v)
        for (int k = 0; k < 3; ++k) {
            double x = from->positions[3 * v + (size_t)k];
            lo[k] = fmin(lo[k], x), hi[k] = fmax(hi[k], x);
        }
    for (int k = 0; k < 3; ++k)
        size = fmax(size, fmax(fabs(lo[k]), fabs(hi[k])));
    /* A sample is a sum of three weighted corners: it may stand outside the corners' box by a rounding. */
    double slack = 1e-9 * size;
    uint32_t *tris = resurfi_alloc(alloc, 3 * to->triangle_count + 3, sizeof *tris);
    if (!tris)
        return RESURF_ERR_OUT_OF_MEMORY;
    double m = margin > 0 ? margin : 0;
    resurf_status st = RESURF_OK;
    for (;;) {
        size_t n = near_triangles(to, lo, hi, m + slack, tris);
        resurfi_bvh *bvh = NULL;
        double d = INFINITY;
        st = resurfi_bvh_build_threads(alloc, to->positions, to->vertex_count, tris, n, threads, &bvh);
        if (st == RESURF_OK)
            st = resurfi_side_max(alloc, from, samples, seed, facet_points, bvh, threads, &d);
        resurfi_bvh_free(bvh);
        if (st != RESURF_OK)
            break;
        if (!(d > m) || n == to->triangle_count) { /* within the margin (or NaN: nothing measured), or all of to */
            *out_max = d;
            break;
        }
        m = isfinite(d) ? d : INFINITY;
    }
    resurfi_free(alloc, tris);
    return st;
}
