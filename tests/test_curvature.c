/* Tests for src/curvature.c against the analytic curvatures of the test shapes: sphere (k1 = k2 = 1/r), cylinder
 * (1 and 0, with directions), torus (1/r along the tube, cos v / (R + r cos v) around the axis), saddle z = x² − y²
 * (±2 at the origin), plane (0); with the exact normals and with estimated ones; signs under flipped normals. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "testutil.h"

typedef struct curvatures {
    double *k1, *k2, *d1, *d2;
} curvatures;

static curvatures curvatures_of(const resurf_mesh *m, const double *normals)
{
    curvatures c = {malloc(m->vertex_count * sizeof(double)), malloc(m->vertex_count * sizeof(double)),
                    malloc(3 * m->vertex_count * sizeof(double)), malloc(3 * m->vertex_count * sizeof(double))};
    ck_assert(c.k1 && c.k2 && c.d1 && c.d2);
    ck_assert_int_eq(resurfi_principal_curvatures(NULL, m->positions, m->vertex_count, m->indices, m->triangle_count,
                                                  normals, c.k1, c.k2, c.d1, c.d2),
                     RESURF_OK);
    return c;
}

static void curvatures_free(curvatures *c) { free(c->k1), free(c->k2), free(c->d1), free(c->d2); }

static double *estimated_normals(const resurf_mesh *m, resurf_normal_scheme scheme)
{
    double *n = malloc(3 * m->vertex_count * sizeof *n);
    ck_assert_ptr_nonnull(n);
    ck_assert_int_eq(resurfi_vertex_normals(NULL, m->positions, m->vertex_count, m->indices, m->triangle_count,
                                            scheme, n),
                     RESURF_OK);
    return n;
}

/* Is v away from the open shapes' border (|x|, |y| < 0.9 or |z| < 0.9 for the cylinder)? The estimator is
 * one-sided there, and so is every estimate of the normals it starts from. */
static int interior(shape_kind kind, const double *p)
{
    if (kind == SHAPE_CYLINDER)
        return fabs(p[2]) < 0.9;
    if (kind == SHAPE_SPHERE || kind == SHAPE_TORUS)
        return 1;
    return fabs(p[0]) < 0.9 && fabs(p[1]) < 0.9;
}

/* Exact principal curvatures of the closed and cylindrical shapes at a point on them (k1 >= k2, outward normals). */
static void exact_curvatures(shape_kind kind, const double *p, double *k1, double *k2)
{
    switch (kind) {
    case SHAPE_SPHERE:
        *k1 = *k2 = 1;
        return;
    case SHAPE_CYLINDER:
        *k1 = 1, *k2 = 0;
        return;
    default: { /* torus, R = 1, r = 0.4: 1/r along the tube, cos v / (R + r cos v) along the parallel */
        double rho = hypot(p[0], p[1]), cosv = (rho - 1.0) / 0.4;
        double a = 1 / 0.4, b = cosv / rho;
        *k1 = fmax(a, b), *k2 = fmin(a, b);
        return;
    }
    }
}

typedef struct error_stats {
    double mean, max;
    size_t count;
} error_stats;

/* Mean and largest |k − k_exact| over interior vertices, both principal curvatures. */
static error_stats curvature_errors(shape_kind kind, const resurf_mesh *m, const curvatures *c)
{
    error_stats e = {0, 0, 0};
    for (size_t v = 0; v < m->vertex_count; ++v) {
        const double *p = m->positions + 3 * v;
        if (!interior(kind, p))
            continue;
        double k1, k2;
        exact_curvatures(kind, p, &k1, &k2);
        double e1 = fabs(c->k1[v] - k1), e2 = fabs(c->k2[v] - k2);
        e.mean += e1 + e2;
        e.max = fmax(e.max, fmax(e1, e2));
        e.count += 2;
    }
    e.mean /= (double)e.count;
    return e;
}

/* With the exact normals of a sphere, every edge has Δn = e exactly, so each face tensor is the identity: the
 * estimate is exact to rounding at every vertex, whatever the mesh irregularity; also with radius 2 (k = ½). */
START_TEST(sphere_exact_normals_exact_curvature)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 3000, 0.3, 4, 1);
    ck_assert_ptr_nonnull(m);
    curvatures c = curvatures_of(m, m->normals);
    for (size_t v = 0; v < m->vertex_count; ++v) {
        ck_assert_double_eq_tol(c.k1[v], 1.0, 1e-9);
        ck_assert_double_eq_tol(c.k2[v], 1.0, 1e-9);
    }
    curvatures_free(&c);
    for (size_t i = 0; i < 3 * m->vertex_count; ++i)
        m->positions[i] *= 2;
    c = curvatures_of(m, m->normals);
    for (size_t v = 0; v < m->vertex_count; ++v) {
        ck_assert_double_eq_tol(c.k1[v], 0.5, 1e-9);
        ck_assert_double_eq_tol(c.k2[v], 0.5, 1e-9);
    }
    curvatures_free(&c);
    resurf_mesh_free(m);
}
END_TEST

/* Irregular meshes (jitter 0.3, ~5000 triangles) with exact normals and with estimated (jet, Max, inverse-area)
 * normals: the mean error over interior vertices, printed, and bounded; the estimator's error follows the normals'
 * (measured: jet < Max < inverse area, Max exact on the sphere). */
START_TEST(accuracy_on_irregular_meshes)
{
    const shape_kind kinds[3] = {SHAPE_SPHERE, SHAPE_CYLINDER, SHAPE_TORUS};
    const int schemes[4] = {-1, RESURF_NORMALS_JET, RESURF_NORMALS_MAX, RESURF_NORMALS_INVERSE_AREA};
    const char *const names[4] = {"exact", "jet", "max", "inverse-area"};
    /* Bounds on the mean error relative to the largest |k| of the shape (1, 1, 2.5), per normal source. */
    const double bound[3][4] = {{1e-9, 0.002, 1e-9, 0.2}, {0.001, 0.002, 0.03, 0.1}, {0.01, 0.01, 0.03, 0.1}};
    const double kmax[3] = {1, 1, 2.5};
    printf("curvature: |k - exact| over interior vertices, jitter 0.3, ~5000 triangles\n");
    printf("%-10s %-14s %10s %10s\n", "shape", "normals", "mean", "max");
    for (int k = 0; k < 3; ++k) {
        resurf_mesh *m = shape_mesh(kinds[k], 5000, 0.3, 21, 1);
        ck_assert_ptr_nonnull(m);
        double mean[4];
        for (int s = 0; s < 4; ++s) {
            double *n = schemes[s] < 0 ? m->normals : estimated_normals(m, (resurf_normal_scheme)schemes[s]);
            curvatures c = curvatures_of(m, n);
            error_stats e = curvature_errors(kinds[k], m, &c);
            printf("%-10s %-14s %10.5f %10.5f\n", shape_name(kinds[k]), names[s], e.mean, e.max);
            ck_assert_msg(e.mean < bound[k][s] * kmax[k], "%s with %s normals: mean error %g", shape_name(kinds[k]),
                          names[s], e.mean);
            mean[s] = e.mean;
            curvatures_free(&c);
            if (n != m->normals)
                free(n);
        }
        ck_assert(mean[3] > mean[2] && (kinds[k] == SHAPE_SPHERE || mean[2] > mean[1]));
        resurf_mesh_free(m);
    }
}
END_TEST

/* On the cylinder the k1 direction runs around the axis and the k2 direction along it. */
START_TEST(cylinder_directions)
{
    resurf_mesh *m = shape_mesh(SHAPE_CYLINDER, 5000, 0.3, 8, 1);
    ck_assert_ptr_nonnull(m);
    curvatures c = curvatures_of(m, m->normals);
    for (size_t v = 0; v < m->vertex_count; ++v) {
        if (!interior(SHAPE_CYLINDER, m->positions + 3 * v))
            continue;
        vec3 d1 = v3_load(c.d1 + 3 * v), d2 = v3_load(c.d2 + 3 * v), n = v3_load(m->normals + 3 * v);
        ck_assert_double_eq_tol(v3_len(d1), 1, 1e-12);
        ck_assert_double_eq_tol(v3_dot(v3_cross(d1, d2), n), 1, 1e-12); /* right-handed (d1, d2, n) */
        ck_assert_msg(fabs(d1.z) < 0.1, "vertex %zu: d1 (%g %g %g)", v, d1.x, d1.y, d1.z);
        ck_assert(fabs(d2.z) > 0.99);
    }
    curvatures_free(&c);
    resurf_mesh_free(m);
}
END_TEST

/* z = x² − y² with normals towards +z: at the origin k1 = +2 along y (the surface falls away from the normal),
 * k2 = −2 along x. A regular grid with an even number of cells has a vertex at the origin. */
START_TEST(saddle_at_origin)
{
    resurf_mesh *m = shape_mesh(SHAPE_SADDLE, 20000, 0.0, 1, 1);
    ck_assert_ptr_nonnull(m);
    size_t origin = SIZE_MAX;
    for (size_t v = 0; v < m->vertex_count; ++v)
        if (fabs(m->positions[3 * v]) < 1e-12 && fabs(m->positions[3 * v + 1]) < 1e-12)
            origin = v;
    ck_assert_uint_ne(origin, SIZE_MAX);
    const int schemes[2] = {-1, RESURF_NORMALS_JET};
    for (int s = 0; s < 2; ++s) {
        double *n = schemes[s] < 0 ? m->normals : estimated_normals(m, (resurf_normal_scheme)schemes[s]);
        curvatures c = curvatures_of(m, n);
        printf("curvature: saddle origin (%s normals): k1 %.5f k2 %.5f\n", s ? "jet" : "exact", c.k1[origin],
               c.k2[origin]);
        ck_assert_double_eq_tol(c.k1[origin], 2, 0.02);
        ck_assert_double_eq_tol(c.k2[origin], -2, 0.02);
        ck_assert(fabs(c.d1[3 * origin + 1]) > 0.999 && fabs(c.d2[3 * origin]) > 0.999);
        curvatures_free(&c);
        if (n != m->normals)
            free(n);
    }
    resurf_mesh_free(m);
}
END_TEST

START_TEST(plane_is_flat)
{
    resurf_mesh *m = shape_mesh(SHAPE_PLANE, 3000, 0.3, 2, 1);
    ck_assert_ptr_nonnull(m);
    double *n = estimated_normals(m, RESURF_NORMALS_JET);
    curvatures c = curvatures_of(m, n);
    for (size_t v = 0; v < m->vertex_count; ++v)
        ck_assert(c.k1[v] == 0 && c.k2[v] == 0);
    curvatures_free(&c);
    free(n);
    resurf_mesh_free(m);
}
END_TEST

/* Negated normals negate the curvatures (k1' = −k2, k2' = −k1); the triangles' winding does not matter. */
START_TEST(orientation_flip_flips_signs)
{
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 4000, 0.3, 6, 1);
    ck_assert_ptr_nonnull(m);
    double *n = estimated_normals(m, RESURF_NORMALS_JET);
    curvatures a = curvatures_of(m, n);
    /* Flip the winding and the normals, as a flipped mesh would have them. */
    for (size_t t = 0; t < m->triangle_count; ++t) {
        uint32_t x = m->indices[3 * t + 1];
        m->indices[3 * t + 1] = m->indices[3 * t + 2], m->indices[3 * t + 2] = x;
    }
    double *f = estimated_normals(m, RESURF_NORMALS_JET);
    curvatures b = curvatures_of(m, f);
    size_t negative = 0;
    for (size_t v = 0; v < m->vertex_count; ++v) {
        ck_assert_double_eq_tol(b.k1[v], -a.k2[v], 1e-9);
        ck_assert_double_eq_tol(b.k2[v], -a.k1[v], 1e-9);
        negative += a.k2[v] < 0; /* the inner side of the torus is a saddle region */
    }
    ck_assert(negative > m->vertex_count / 4);
    /* The winding alone (normals unchanged) gives the same curvatures. */
    curvatures w = curvatures_of(m, n);
    for (size_t v = 0; v < m->vertex_count; ++v) {
        ck_assert_double_eq_tol(w.k1[v], a.k1[v], 1e-9);
        ck_assert_double_eq_tol(w.k2[v], a.k2[v], 1e-9);
    }
    curvatures_free(&a), curvatures_free(&b), curvatures_free(&w);
    free(n), free(f);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(isolated_and_bad_input)
{
    /* Vertex 3 is in no face, face 1 is out of range: k = 0 there, no crash, directions optional. */
    const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 4, 4, 4};
    const double nrm[] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const uint32_t idx[] = {0, 1, 2, 0, 1, 9};
    double k1[4], k2[4];
    ck_assert_int_eq(resurfi_principal_curvatures(NULL, pos, 4, idx, 2, nrm, k1, k2, NULL, NULL), RESURF_OK);
    for (int v = 0; v < 4; ++v)
        ck_assert(k1[v] == 0 && k2[v] == 0);
    ck_assert_int_eq(resurfi_principal_curvatures(NULL, pos, 4, idx, 2, NULL, k1, k2, NULL, NULL),
                     RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurfi_principal_curvatures(NULL, NULL, 0, NULL, 0, NULL, NULL, NULL, NULL, NULL), RESURF_OK);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("curvature");
    TCase *tc = tcase_create("curvature");
    tcase_add_test(tc, sphere_exact_normals_exact_curvature);
    tcase_add_test(tc, accuracy_on_irregular_meshes);
    tcase_add_test(tc, cylinder_directions);
    tcase_add_test(tc, saddle_at_origin);
    tcase_add_test(tc, plane_is_flat);
    tcase_add_test(tc, orientation_flip_flips_signs);
    tcase_add_test(tc, isolated_and_bad_input);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
