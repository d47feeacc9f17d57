/* Principal curvatures and directions per vertex, after Rusinkiewicz, "Estimating curvatures and their derivatives
 * on triangle meshes" (3DPVT 2004):
 *
 *   1. per face, the second fundamental form II (a symmetric 2×2 tensor in an orthonormal frame of the face) is
 *      fitted by least squares to its three edges: II · (e·u, e·v) = (Δn·u, Δn·v), with e an edge and Δn the
 *      difference of the given vertex normals along it (6 equations, 3 unknowns);
 *   2. each face tensor is carried into the frame of each of its corners (the face frame rotated onto the vertex's
 *      tangent plane by the smallest rotation) and averaged with the corner's Voronoi area as weight (Meyer, Desbrun,
 *      Schröder & Barr 2003, "mixed" areas: obtuse triangles split ½ / ¼ / ¼);
 *   3. the eigenvalues of the averaged tensor are the principal curvatures, its eigenvectors the directions.
 *
 * Sign: with Δn = II e, a sphere of radius r with outward normals (n = (p − c)/r) has II = I/r: k = +1/r. Flipping
 * all normals flips every curvature; the face orientation does not matter (each face frame is oriented by the
 * vertex normals it is compared with). */
#include <stdlib.h>
#include <string.h>

#include "internal.h"

/* A symmetric 2×2 tensor [[a, b], [b, c]] in some frame (u, v). */
typedef struct tensor2 {
    double a, b, c;
} tensor2;

/* A unit vector perpendicular to unit n, from the coordinate axis least aligned with it (deterministic). */
static vec3 perpendicular(vec3 n)
{
    double ax = fabs(n.x), ay = fabs(n.y), az = fabs(n.z);
    vec3 axis = ax <= ay && ax <= az ? v3(1, 0, 0) : ay <= az ? v3(0, 1, 0) : v3(0, 0, 1);
    return v3_normalize(v3_cross(n, axis));
}

/* Rotates x by the smallest rotation that takes unit `from` to unit `to` (from · to > −1). Rodrigues' formula
 * written without trigonometry: R x = x (from·to) + (k × x) + k (k·x) / (1 + from·to), k = from × to. */
static vec3 rotate_between(vec3 x, vec3 from, vec3 to)
{
    double c = v3_dot(from, to);
    vec3 k = v3_cross(from, to);
    return v3_add(v3_add(v3_scale(x, c), v3_cross(k, x)), v3_scale(k, v3_dot(k, x) / (1 + c)));
}

/* Least-squares II of one face in its frame (fu, fv) from its three edges and corner normals. Returns -1 when the
 * system is singular (a degenerate face). */
static int face_tensor(const vec3 p[3], const vec3 n[3], vec3 fu, vec3 fv, tensor2 *out)
{
    /* Normal equations of rows (eu, ev, 0 | dnu) and (0, eu, ev | dnv) summed over the edges. */
    double m00 = 0, m01 = 0, m11 = 0, m12 = 0, m22 = 0, r0 = 0, r1 = 0, r2 = 0;
    for (int k = 0; k < 3; ++k) {
        vec3 e = v3_sub(p[(k + 2) % 3], p[(k + 1) % 3]); /* the edge opposite corner k */
        vec3 dn = v3_sub(n[(k + 2) % 3], n[(k + 1) % 3]);
        double eu = v3_dot(e, fu), ev = v3_dot(e, fv), nu = v3_dot(dn, fu), nv = v3_dot(dn, fv);
        m00 += eu * eu, m01 += eu * ev, m11 += eu * eu + ev * ev, m12 += eu * ev, m22 += ev * ev;
        r0 += nu * eu, r1 += nu * ev + nv * eu, r2 += nv * ev;
    }
    /* Solve [[m00 m01 0] [m01 m11 m12] [0 m12 m22]] x = r by Cramer's rule (the matrix is 3×3 and well scaled
     * for any non-degenerate triangle: its eigenvalues are of the order of the squared edge lengths). */
    double det = m00 * (m11 * m22 - m12 * m12) - m01 * (m01 * m22);
    double scale = m00 + m11 + m22;
    if (!(fabs(det) > 1e-12 * scale * scale * scale))
        return -1;
    double x0 = (r0 * (m11 * m22 - m12 * m12) - m01 * (r1 * m22 - m12 * r2)) / det;
    double x1 = (m00 * (r1 * m22 - m12 * r2) - r0 * (m01 * m22)) / det;
    double x2 = (m00 * (m11 * r2 - r1 * m12) - m01 * (m01 * r2) + r0 * (m01 * m12)) / det;
    out->a = x0, out->b = x1, out->c = x2;
    return 0;
}

/* Voronoi ("mixed") area of each corner of a triangle, Meyer et al. 2003: the circumcentric cell for a non-obtuse
 * triangle, else half the area to the obtuse corner and a quarter to each other. */
static void corner_areas(const vec3 p[3], double area[3])
{
    vec3 e[3]; /* e[k]: edge opposite corner k */
    for (int k = 0; k < 3; ++k)
        e[k] = v3_sub(p[(k + 2) % 3], p[(k + 1) % 3]);
    double twice = v3_len(v3_cross(e[0], e[1]));
    double l2[3] = {v3_len2(e[0]), v3_len2(e[1]), v3_len2(e[2])};
    /* Barycentric weights of the circumcentre: l2[k] (l2[k+1] + l2[k+2] − l2[k]); negative at an obtuse corner. */
    double w[3];
    for (int k = 0; k < 3; ++k)
        w[k] = l2[k] * (l2[(k + 1) % 3] + l2[(k + 2) % 3] - l2[k]);
    double total = 0.5 * twice;
    if (w[0] <= 0 || w[1] <= 0 || w[2] <= 0) {
        for (int k = 0; k < 3; ++k)
            area[k] = w[k] <= 0 ? 0.5 * total : 0.25 * total;
        return;
    }
    /* Corner k's cell is the part closer to k: the two half-triangles towards the edge midpoints next to it,
     * ½·(area of triangle (circumcentre, edge)) for each of the two edges at k. */
    double sum = w[0] + w[1] + w[2];
    double sub[3]; /* area of the triangle (circumcentre, edge opposite corner k) */
    for (int k = 0; k < 3; ++k)
        sub[k] = total * w[k] / sum;
    for (int k = 0; k < 3; ++k)
        area[k] = 0.5 * (sub[(k + 1) % 3] + sub[(k + 2) % 3]);
}

resurf_status resurfi_principal_curvatures(const resurf_allocator *alloc, const double *positions, size_t vertex_count,
                                           const uint32_t *indices, size_t triangle_count, const double *normals,
                                           double *out_k1, double *out_k2, double *out_dir1, double *out_dir2)
{
    if ((vertex_count && (!positions || !normals || !out_k1 || !out_k2)) || (triangle_count && !indices))
        return RESURF_ERR_INVALID_ARGUMENT;
    if (vertex_count == 0)
        return RESURF_OK;
    /* Per vertex: its frame (u; v = n × u) and the weighted tensor sum. */
    vec3 *frame = resurfi_alloc(alloc, vertex_count, sizeof *frame);
    double *sum = resurfi_calloc(alloc, vertex_count, 4 * sizeof *sum); /* a, b, c, weight */
    if (!frame || !sum) {
        resurfi_free(alloc, frame);
        resurfi_free(alloc, sum);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    for (size_t v = 0; v < vertex_count; ++v) {
        vec3 n = v3_load(normals + 3 * v);
        frame[v] = v3_len2(n) > 0 ? perpendicular(v3_normalize(n)) : v3(0, 0, 0);
    }

    for (size_t t = 0; t < triangle_count; ++t) {
        const uint32_t *tri = indices + 3 * t;
        if (tri[0] >= vertex_count || tri[1] >= vertex_count || tri[2] >= vertex_count || tri[0] == tri[1] ||
            tri[1] == tri[2] || tri[2] == tri[0])
            continue;
        vec3 p[3], n[3];
        int usable = 1;
        for (int k = 0; k < 3; ++k) {
            p[k] = v3_load(positions + 3 * (size_t)tri[k]);
            n[k] = v3_load(normals + 3 * (size_t)tri[k]);
            usable &= v3_len2(n[k]) > 0;
        }
        vec3 fn = v3_normalize(v3_tri_cross(p[0], p[1], p[2]));
        if (!usable || v3_len2(fn) == 0)
            continue;
        /* Orient the face by its corner normals, so that a mesh whose winding disagrees with its normals still
         * carries each tensor onto nearby tangent planes (the smallest rotation is then small). */
        if (v3_dot(fn, v3_add(v3_add(n[0], n[1]), n[2])) < 0)
            fn = v3_neg(fn);
        vec3 fu = v3_normalize(v3_sub(p[1], p[0])), fv = v3_cross(fn, fu);
        tensor2 ii;
        if (face_tensor(p, n, fu, fv, &ii) != 0)
            continue;
        double area[3];
        corner_areas(p, area);
        for (int k = 0; k < 3; ++k) {
            uint32_t v = tri[k];
            vec3 nv = v3_normalize(n[k]);
            if (v3_dot(nv, fn) <= -1 + 1e-12) /* the planes agree but the sides are opposite: no smallest rotation */
                continue;
            /* The vertex frame rotated into the face plane, expressed in the face frame. */
            vec3 vu = frame[v], vv = v3_cross(nv, vu);
            vec3 ru = rotate_between(vu, nv, fn), rv = rotate_between(vv, nv, fn);
            double u1 = v3_dot(ru, fu), v1 = v3_dot(ru, fv), u2 = v3_dot(rv, fu), v2 = v3_dot(rv, fv);
            /* II in the rotated vertex frame: [u1 v1; u2 v2] II [u1 v1; u2 v2]ᵀ. */
            double a = ii.a * u1 * u1 + 2 * ii.b * u1 * v1 + ii.c * v1 * v1;
            double b = ii.a * u1 * u2 + ii.b * (u1 * v2 + u2 * v1) + ii.c * v1 * v2;
            double c = ii.a * u2 * u2 + 2 * ii.b * u2 * v2 + ii.c * v2 * v2;
            double *s = sum + 4 * (size_t)v;
            s[0] += area[k] * a, s[1] += area[k] * b, s[2] += area[k] * c, s[3] += area[k];
        }
    }

    for (size_t v = 0; v < vertex_count; ++v) {
        const double *s = sum + 4 * v;
        double k1 = 0, k2 = 0;
        vec3 d1 = v3(0, 0, 0), d2 = v3(0, 0, 0);
        if (s[3] > 0) {
            double a = s[0] / s[3], b = s[1] / s[3], c = s[2] / s[3];
            double mean = 0.5 * (a + c), dev = hypot(0.5 * (a - c), b);
            k1 = mean + dev, k2 = mean - dev;
            /* The k1 direction is at angle ½ atan2(2b, a − c) from u in the vertex frame. */
            double phi = 0.5 * atan2(2 * b, a - c);
            vec3 nv = v3_normalize(v3_load(normals + 3 * v));
            vec3 vu = frame[v], vv = v3_cross(nv, vu);
            d1 = v3_add(v3_scale(vu, cos(phi)), v3_scale(vv, sin(phi)));
            d2 = v3_cross(nv, d1);
        }
        out_k1[v] = k1, out_k2[v] = k2;
        if (out_dir1)
            v3_store(out_dir1 + 3 * v, d1);
        if (out_dir2)
            v3_store(out_dir2 + 3 * v, d2);
    }
    resurfi_free(alloc, frame);
    resurfi_free(alloc, sum);
    return RESURF_OK;
}
