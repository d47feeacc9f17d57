/* src/metrics.c: surface distances, vertex distances, triangle quality and normal deviation against
 * hand-computed truth (self-comparison, a scaled sphere bounded by its chord sag, a shifted plane, a tilted plane
 * whose area mean is known), thread determinism, cancel and bad input. */
#include <stdio.h>
#include <string.h>

#include "testutil.h"

static resurf_compare_options compare_options(size_t samples, unsigned threads)
{
    resurf_compare_options o = resurf_compare_options_default();
    o.samples = samples;
    o.threads = threads;
    return o;
}

/* A mesh compared with itself: every distance and the normal deviation are zero (samples up to rounding). */
START_TEST(compare_self_is_zero)
{
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 4000, 0.3, 9, 0);
    double *vd = malloc(m->vertex_count * sizeof *vd);
    resurf_compare_report r;
    resurf_compare_options o = compare_options(20000, 0);
    ck_assert_int_eq(resurf_compare(m, m, &o, &r, vd, NULL), RESURF_OK);
    ck_assert_double_le(r.hausdorff, 1e-14);
    ck_assert_double_le(r.mean, 1e-15);
    ck_assert_double_le(r.rms, 1e-15);
    ck_assert_double_eq(r.vertex_max, 0);
    for (size_t v = 0; v < m->vertex_count; ++v)
        ck_assert_double_eq(vd[v], 0);
    ck_assert_double_le(r.mean_normal_deviation_deg, 1e-9);
    ck_assert_double_eq_tol(r.diagonal, sqrt(2.8 * 2.8 * 2 + 0.8 * 0.8), 0.05);
    free(vd);
    resurf_mesh_free(m);
}
END_TEST

/* The unit sphere mesh S against 1.01 S. S lies inside the unit ball (its points are convex combinations of unit
 * vectors) and outside the ball of radius 1 − s, s = 1 − the least distance of a face plane from the origin (the
 * chord sag); along any ray each surface is within that shell. So every TEST vertex (radius 1.01) is between
 * 0.01 and 0.01 + s from REF, and every point of either surface is within 0.01 + s of the other: the Hausdorff
 * distance lies in [0.01, 0.01 + s]. */
START_TEST(compare_scaled_sphere_hausdorff)
{
    resurf_mesh *ref = shape_mesh(SHAPE_SPHERE, 20000, 0.2, 3, 0), *test = NULL;
    ck_assert_int_eq(resurf_mesh_clone(ref, &test, NULL), RESURF_OK);
    for (size_t i = 0; i < 3 * test->vertex_count; ++i)
        test->positions[i] *= 1.01;
    double least_plane = 1;
    for (size_t t = 0; t < ref->triangle_count; ++t) {
        const uint32_t *f = ref->indices + 3 * t;
        vec3 a = resurfi_position(ref, f[0]);
        vec3 n = v3_normalize(v3_tri_cross(a, resurfi_position(ref, f[1]), resurfi_position(ref, f[2])));
        least_plane = fmin(least_plane, fabs(v3_dot(n, a)));
    }
    double sag = 1 - least_plane;
    ck_assert_double_lt(sag, 2e-3);
    double *vd = malloc(test->vertex_count * sizeof *vd);
    resurf_compare_report r;
    resurf_compare_options o = compare_options(50000, 0);
    ck_assert_int_eq(resurf_compare(ref, test, &o, &r, vd, NULL), RESURF_OK);
    const double eps = 1e-12;
    ck_assert_double_ge(r.hausdorff, 0.01 - eps);
    ck_assert_double_le(r.hausdorff, 0.01 + sag + eps);
    for (size_t v = 0; v < test->vertex_count; ++v) {
        ck_assert_double_ge(vd[v], 0.01 - eps);
        ck_assert_double_le(vd[v], 0.01 + sag + eps);
    }
    ck_assert_double_ge(r.vertex_mean, 0.01 - eps);
    ck_assert_double_le(r.mean, 0.01 + sag + eps);
    ck_assert_double_ge(r.mean, 0.01 * (1 - sag) - eps);
    free(vd);
    resurf_mesh_free(ref);
    resurf_mesh_free(test);
}
END_TEST

/* A jittered plane against itself moved by d along its normal: every distance is exactly d, no normal deviation. */
START_TEST(compare_shifted_plane_is_d_everywhere)
{
    const double d = 0.125;
    resurf_mesh *ref = shape_mesh(SHAPE_PLANE, 3000, 0.35, 5, 0), *test = NULL;
    ck_assert_int_eq(resurf_mesh_clone(ref, &test, NULL), RESURF_OK);
    for (size_t v = 0; v < test->vertex_count; ++v)
        test->positions[3 * v + 2] += d;
    double *vd = malloc(test->vertex_count * sizeof *vd);
    resurf_compare_report r;
    resurf_compare_options o = compare_options(30000, 0);
    ck_assert_int_eq(resurf_compare(ref, test, &o, &r, vd, NULL), RESURF_OK);
    const double eps = 1e-15;
    ck_assert_double_eq_tol(r.hausdorff, d, eps);
    ck_assert_double_eq_tol(r.mean, d, eps);
    ck_assert_double_eq_tol(r.rms, d, eps);
    ck_assert_double_eq_tol(r.test_to_ref_max, d, eps);
    ck_assert_double_eq_tol(r.test_to_ref_mean, d, eps);
    ck_assert_double_eq_tol(r.ref_to_test_max, d, eps);
    ck_assert_double_eq_tol(r.ref_to_test_mean, d, eps);
    ck_assert_double_eq_tol(r.vertex_max, d, eps);
    ck_assert_double_eq_tol(r.vertex_mean, d, eps);
    for (size_t v = 0; v < test->vertex_count; ++v)
        ck_assert_double_eq_tol(vd[v], d, eps);
    ck_assert_double_eq(r.mean_normal_deviation_deg, 0);
    ck_assert_double_eq_tol(r.diagonal, sqrt(8.0), 1e-15);
    free(vd);
    resurf_mesh_free(ref);
    resurf_mesh_free(test);
}
END_TEST

/* TEST = the tilted plane z = 0.1 x over a grid graded towards x = 0 (x_i = (i/n)²: most triangles are near
 * x = 0), REF = the plane z = 0 over [0,1]². A TEST point is 0.1 x from REF, and area-uniform points have x
 * uniform in [0,1]: the area mean is 0.05 and the RMS 0.1/√3. Picking triangles uniformly instead of by area
 * would give about 0.1 × E[x over triangles] ≈ 0.035. The normal deviation is atan(0.1) on every face. */
START_TEST(compare_area_uniform_sampling)
{
    resurf_mesh *ref = tu_grid(8), *test = tu_grid(40);
    for (size_t v = 0; v < test->vertex_count; ++v) {
        double *p = test->positions + 3 * v;
        p[0] *= p[0];
        p[2] = 0.1 * p[0];
    }
    resurf_compare_report r;
    resurf_compare_options o = compare_options(200000, 0);
    ck_assert_int_eq(resurf_compare(ref, test, &o, &r, NULL, NULL), RESURF_OK);
    /* standard error of the mean: 0.1 × 0.289 / √200000 ≈ 6.5e-5 */
    ck_assert_double_eq_tol(r.test_to_ref_mean, 0.05, 4e-4);
    ck_assert_double_eq_tol(r.test_to_ref_max, 0.1, 1e-15);
    ck_assert_double_eq_tol(r.mean_normal_deviation_deg, atan(0.1) * 180 / M_PI, 1e-9);
    resurf_mesh_free(ref);
    resurf_mesh_free(test);
}
END_TEST

/* The RMS of the tilted plane: both sides measure 0.1 x (TEST to REF) and 0.1 x / √1.01 (REF to TEST, the
 * perpendicular distance of (x, y, 0) to the plane z = 0.1 x), with x uniform on [0,1] on both: mean squares
 * 0.01/3 and 0.01/3.03, so rms = sqrt((0.01/3 + 0.01/3.03) / 2). */
START_TEST(compare_rms_of_tilted_plane)
{
    resurf_mesh *ref = tu_grid(10), *test = tu_grid(10);
    for (size_t v = 0; v < test->vertex_count; ++v)
        test->positions[3 * v + 2] = 0.1 * test->positions[3 * v];
    /* REF's points near x = 1 project beyond TEST's edge only if the foot leaves [0,1]: the foot of (x, y, 0) is
     * x / 1.01 along x, always inside. */
    resurf_compare_report r;
    resurf_compare_options o = compare_options(400000, 0);
    ck_assert_int_eq(resurf_compare(ref, test, &o, &r, NULL, NULL), RESURF_OK);
    ck_assert_double_eq_tol(r.rms, sqrt((0.01 / 3 + 0.01 / 3.03) / 2), 3e-4);
    ck_assert_double_eq_tol(r.ref_to_test_mean, 0.05 / sqrt(1.01), 3e-4);
    ck_assert_double_eq_tol(r.ref_to_test_max, 0.1 / sqrt(1.01), 1e-14);
    resurf_mesh_free(ref);
    resurf_mesh_free(test);
}
END_TEST

/* Reversed winding: every TEST face normal points against REF's: 180°. */
START_TEST(compare_flipped_normals)
{
    resurf_mesh *ref = tu_grid(6), *test = tu_grid(6);
    for (size_t t = 0; t < test->triangle_count; ++t) {
        uint32_t *f = test->indices + 3 * t, s = f[1];
        f[1] = f[2], f[2] = s;
    }
    resurf_compare_report r;
    resurf_compare_options o = compare_options(1000, 0);
    ck_assert_int_eq(resurf_compare(ref, test, &o, &r, NULL, NULL), RESURF_OK);
    ck_assert_double_eq_tol(r.mean_normal_deviation_deg, 180, 1e-9);
    resurf_mesh_free(ref);
    resurf_mesh_free(test);
}
END_TEST

/* Triangle quality by hand: an equilateral triangle (60°), a right isosceles one (45°), a 5° sliver and a
 * triangle with two coincident corners (0°). */
START_TEST(quality_hand_triangles)
{
    const double s3 = sqrt(3.0) / 2, c5 = cos(5 * M_PI / 180), s5 = sin(5 * M_PI / 180);
    const double p[] = {0, 0, 0, 1, 0, 0, 0.5, s3, 0, /* equilateral */
                        2, 0, 0, 3, 0, 0, 2, 1, 0,    /* right isosceles */
                        5, 0, 0, 6, 0, 0, 5 + c5, s5, 0, /* 5° at the first corner */
                        7, 0, 0, 7, 0, 0, 8, 1, 1};    /* coincident corners */
    const uint32_t t[] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
    resurf_mesh *m = tu_mesh(p, 3, t, 1);
    double lo = -1, mean = -1, share = -1;
    ck_assert_int_eq(resurf_triangle_quality(m, &lo, &mean, &share, NULL), RESURF_OK);
    ck_assert_double_eq_tol(lo, 60, 1e-12);
    ck_assert_double_eq_tol(mean, 60, 1e-12);
    ck_assert_double_eq(share, 0);
    resurf_mesh_free(m);

    m = tu_mesh(p, 12, t, 4);
    ck_assert_int_eq(resurf_triangle_quality(m, &lo, &mean, &share, NULL), RESURF_OK);
    ck_assert_double_eq(lo, 0);
    ck_assert_double_eq_tol(mean, (60 + 45 + 5 + 0) / 4.0, 1e-12);
    ck_assert_double_eq(share, 0.5);
    ck_assert_int_eq(resurf_triangle_quality(m, NULL, NULL, NULL, NULL), RESURF_OK);
    resurf_mesh_free(m);

    ck_assert_int_eq(resurf_mesh_create(0, 0, 0, &m, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_triangle_quality(m, &lo, &mean, &share, NULL), RESURF_OK);
    ck_assert_double_eq(lo, 0);
    ck_assert_double_eq(mean, 0);
    ck_assert_double_eq(share, 0);
    resurf_mesh_free(m);
}
END_TEST

/* resurf_compare reports TEST's quality: the regular grid's right isosceles triangles have 45° everywhere. */
START_TEST(compare_reports_test_quality)
{
    resurf_mesh *ref = shape_mesh(SHAPE_PLANE, 500, 0.4, 1, 0), *test = tu_grid(5);
    resurf_compare_report r;
    resurf_compare_options o = compare_options(1000, 0);
    ck_assert_int_eq(resurf_compare(ref, test, &o, &r, NULL, NULL), RESURF_OK);
    ck_assert_double_eq_tol(r.min_angle_deg, 45, 1e-12);
    ck_assert_double_eq_tol(r.mean_min_angle_deg, 45, 1e-12);
    ck_assert_double_eq(r.share_below_10deg, 0);
    resurf_mesh_free(ref);
    resurf_mesh_free(test);
}
END_TEST

/* The figures are bit-identical for 1, 2 and 3 threads (several batches of samples). */
START_TEST(compare_threads_deterministic)
{
    resurf_mesh *ref = shape_mesh(SHAPE_SPHERE, 6000, 0.35, 2, 0), *test = NULL;
    ck_assert_int_eq(resurf_mesh_clone(ref, &test, NULL), RESURF_OK);
    resurf_smooth_options so = resurf_smooth_options_default();
    ck_assert_int_eq(resurf_smooth(test, &so, NULL), RESURF_OK);
    resurf_compare_report r[3];
    double *vd[3];
    for (unsigned k = 0; k < 3; ++k) {
        vd[k] = malloc(test->vertex_count * sizeof *vd[k]);
        resurf_compare_options o = compare_options(150000, k + 1);
        ck_assert_int_eq(resurf_compare(ref, test, &o, &r[k], vd[k], NULL), RESURF_OK);
    }
    ck_assert_double_gt(r[0].hausdorff, 1e-4);
    for (unsigned k = 1; k < 3; ++k) {
        ck_assert(memcmp(&r[0], &r[k], sizeof r[0]) == 0);
        ck_assert(memcmp(vd[0], vd[k], test->vertex_count * sizeof(double)) == 0);
    }
    /* Another seed draws other samples: the sampled means change, the vertex figures do not. */
    resurf_compare_report other;
    resurf_compare_options o = compare_options(150000, 0);
    o.seed = 77;
    ck_assert_int_eq(resurf_compare(ref, test, &o, &other, NULL, NULL), RESURF_OK);
    ck_assert_double_ne(other.test_to_ref_mean, r[0].test_to_ref_mean);
    ck_assert_double_eq(other.vertex_max, r[0].vertex_max);
    ck_assert_double_eq(other.vertex_mean, r[0].vertex_mean);
    for (unsigned k = 0; k < 3; ++k)
        free(vd[k]);
    resurf_mesh_free(ref);
    resurf_mesh_free(test);
}
END_TEST

/* With samples = 0 only the vertices (and, for the max, the facet points) are measured: two grids of different spacing on the
 * parallel planes z = 0 and z = 0.25 are 0.25 apart from every vertex. */
START_TEST(compare_without_samples)
{
    resurf_mesh *ref = tu_grid(3), *test = tu_grid(5);
    for (size_t v = 0; v < test->vertex_count; ++v)
        test->positions[3 * v + 2] = 0.25;
    resurf_compare_report r;
    resurf_compare_options o = compare_options(0, 1);
    ck_assert_int_eq(resurf_compare(ref, test, &o, &r, NULL, NULL), RESURF_OK);
    ck_assert_double_eq(r.hausdorff, 0.25);
    ck_assert_double_eq(r.mean, 0.25);
    ck_assert_double_eq(r.rms, 0.25);
    resurf_mesh_free(ref);
    resurf_mesh_free(test);
}
END_TEST

/* The facet points find a chord's farthest point: REF is the valley z = |x| (x in [-1, 1], y in [0, 1]), TEST its
 * lid z = 1, two triangles whose corners all lie on the valley's rims. With no samples the vertices are 0 away; the
 * midpoint of the lid's edge from (-1, 0, 1) to (1, 0, 1) lies over the valley's floor, 1/sqrt(2) from its planes,
 * which is the true one-sided maximum (without facet points: 0). */
START_TEST(compare_facet_points_find_a_chord)
{
    const double valley[] = {-1, 0, 1, 0, 0, 0, 1, 0, 1, -1, 1, 1, 0, 1, 0, 1, 1, 1};
    const uint32_t vt[] = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4};
    const double lid[] = {-1, 0, 1, 1, 0, 1, 1, 1, 1, -1, 1, 1};
    const uint32_t lt[] = {0, 1, 2, 0, 2, 3};
    resurf_mesh *ref = tu_mesh(valley, 6, vt, 4), *test = tu_mesh(lid, 4, lt, 2);
    resurf_compare_report r;
    resurf_compare_options o = compare_options(0, 1);
    ck_assert_int_eq(resurf_compare(ref, test, &o, &r, NULL, NULL), RESURF_OK);
    ck_assert_double_eq(r.vertex_max, 0);
    ck_assert_double_eq_tol(r.test_to_ref_max, sqrt(0.5), 1e-15);
    ck_assert_double_eq(r.ref_to_test_max, 1); /* the valley's floor, under the lid */
    resurf_mesh_free(ref);
    resurf_mesh_free(test);
}
END_TEST

/* A triangle measured to its own three corners (tiny triangles hanging below them): the farthest point is its
 * circumcentre, at the circumradius R, away from every vertex, centroid and edge midpoint (which give 0.509 and
 * below). The climb from the best of those finds R. Corners (0,0), (1,0), (0.3,0.8): the circumcentre is
 * (0.5, 0.26875), R = sqrt(0.25 + 0.26875^2). */
START_TEST(compare_climbs_to_the_farthest_point)
{
    const double e = 1e-12;
    const double tri[] = {0, 0, 0, 1, 0, 0, 0.3, 0.8, 0};
    const uint32_t tt[] = {0, 1, 2};
    double corners[27];
    uint32_t ct[9];
    for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j)
                corners[9 * c + 3 * k + j] = tri[3 * c + j] + (k == 1 && j == 0 ? e : k == 2 && j == 1 ? e : 0) -
                                             (k && j == 2 ? e : 0);
        for (int k = 0; k < 3; ++k)
            ct[3 * c + k] = (uint32_t)(3 * c + k);
    }
    resurf_mesh *ref = tu_mesh(corners, 9, ct, 3), *test = tu_mesh(tri, 3, tt, 1);
    resurf_compare_report r;
    resurf_compare_options o = compare_options(0, 1);
    ck_assert_int_eq(resurf_compare(ref, test, &o, &r, NULL, NULL), RESURF_OK);
    double R = sqrt(0.25 + 0.26875 * 0.26875);
    ck_assert_msg(fabs(r.test_to_ref_max - R) <= 5e-4 * R, "found %.9g, R %.9g", r.test_to_ref_max, R);
    ck_assert_double_le(r.test_to_ref_max, R);
    resurf_mesh_free(ref);
    resurf_mesh_free(test);
}
END_TEST

static bool cancel_at(void *user, resurf_stage stage, double fraction)
{
    (void)fraction;
    ck_assert_int_eq(stage, RESURF_STAGE_COMPARE);
    int *left = user;
    return --*left == 0;
}

/* A cancel at each progress call returns CANCELLED and leaves the outputs untouched. */
START_TEST(compare_cancel)
{
    resurf_mesh *ref = shape_mesh(SHAPE_SPHERE, 2000, 0.3, 1, 0), *test = shape_mesh(SHAPE_SPHERE, 1000, 0.3, 2, 0);
    int calls = 1000000;
    resurf_compare_options o = compare_options(70000, 2); /* two batches of samples per side */
    o.progress = (resurf_progress){cancel_at, &calls};
    resurf_compare_report r;
    ck_assert_int_eq(resurf_compare(ref, test, &o, &r, NULL, NULL), RESURF_OK);
    int total = 1000000 - calls;
    ck_assert_int_ge(total, 4);
    double *vd = malloc(test->vertex_count * sizeof *vd);
    for (int k = 1; k <= total; ++k) {
        int left = k;
        o.progress.user = &left;
        memset(&r, 0xab, sizeof r);
        for (size_t v = 0; v < test->vertex_count; ++v)
            vd[v] = -7;
        resurf_error error;
        ck_assert_int_eq(resurf_compare(ref, test, &o, &r, vd, &error), RESURF_ERR_CANCELLED);
        ck_assert_int_eq(error.status, RESURF_ERR_CANCELLED);
        unsigned char bytes[sizeof r];
        memset(bytes, 0xab, sizeof bytes);
        ck_assert(memcmp(&r, bytes, sizeof r) == 0);
        for (size_t v = 0; v < test->vertex_count; ++v)
            ck_assert_double_eq(vd[v], -7);
    }
    free(vd);
    resurf_mesh_free(ref);
    resurf_mesh_free(test);
}
END_TEST

/* Reads the number after "KEY": in a JSON text, or NAN. */
static double json_number(const char *text, const char *key)
{
    char pattern[128];
    snprintf(pattern, sizeof pattern, "\"%s\": ", key);
    const char *p = strstr(text, pattern);
    return p ? strtod(p + strlen(pattern), NULL) : NAN;
}

/* `resurf compare` on REF = the plane z = 0 and TEST = the plane z = d (x + 1) / 2 over [−1,1]²: the vertex
 * distances run from 0 (x = −1) to d (x = 1), vertically. The JSON carries the figures with their relative
 * versions, and the heatmap colours the x = −1 vertices pure blue and the x = 1 vertices pure red. */
START_TEST(compare_cli_json_and_heatmap)
{
    const double d = 0.25;
    char *dir = tu_tempdir(), *ref_path = tu_path(dir, "ref.ply"), *test_path = tu_path(dir, "test.ply"),
         *heat_path = tu_path(dir, "heat.ply");
    resurf_mesh *ref = shape_mesh(SHAPE_PLANE, 800, 0.3, 3, 0), *test = NULL, *heat = NULL;
    ck_assert_int_eq(resurf_mesh_clone(ref, &test, NULL), RESURF_OK);
    for (size_t v = 0; v < test->vertex_count; ++v)
        test->positions[3 * v + 2] = d * (test->positions[3 * v] + 1) / 2;
    ck_assert_int_eq(resurf_mesh_save(ref, ref_path, NULL, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_mesh_save(test, test_path, NULL, NULL), RESURF_OK);
    char cmd[2048], *text = NULL;
    snprintf(cmd, sizeof cmd, "%s compare %s %s --json --samples 5000 --threads 2 --heatmap %s", RESURF_CLI,
             ref_path, test_path, heat_path);
    ck_assert_int_eq(tu_run(cmd, &text), 0);
    /* The tilted plane's vertex at x = 1 is d above REF's border; its perpendicular distance is d itself (REF
     * ends at x = 1). */
    ck_assert_double_eq_tol(json_number(text, "vertex_max"), d, 1e-12);
    ck_assert_double_eq_tol(json_number(text, "diagonal"), sqrt(8.0), 1e-12);
    ck_assert_double_eq_tol(json_number(text, "vertex_max_rel"), d / sqrt(8.0), 1e-12);
    ck_assert_double_eq_tol(json_number(text, "mean_normal_deviation_deg"), atan(d / 2) * 180 / M_PI, 1e-9);
    free(text);
    ck_assert_int_eq(resurf_mesh_load(heat_path, NULL, &heat, NULL), RESURF_OK);
    ck_assert_ptr_nonnull(heat->colors);
    ck_assert_uint_eq(heat->vertex_count, test->vertex_count);
    size_t blue = 0, red = 0;
    for (size_t v = 0; v < heat->vertex_count; ++v) {
        const double *c = heat->colors + 4 * v, x = heat->positions[3 * v];
        if (x == -1.0) {
            ck_assert(c[0] == 0 && c[1] == 0 && c[2] == 1);
            ++blue;
        } else if (x == 1.0) {
            ck_assert(c[0] == 1 && c[1] == 0 && c[2] == 0);
            ++red;
        }
    }
    ck_assert_uint_gt(blue, 5);
    ck_assert_uint_gt(red, 5);
    /* The text table shows absolute and relative columns; bad arguments exit with 2. */
    snprintf(cmd, sizeof cmd, "%s compare %s %s --samples 100", RESURF_CLI, ref_path, test_path);
    ck_assert_int_eq(tu_run(cmd, &text), 0);
    ck_assert_ptr_nonnull(strstr(text, "relative"));
    ck_assert_ptr_nonnull(strstr(text, "hausdorff"));
    free(text);
    snprintf(cmd, sizeof cmd, "%s compare %s --samples x", RESURF_CLI, ref_path);
    ck_assert_int_eq(tu_run(cmd, &text), 2);
    free(text);
    snprintf(cmd, sizeof cmd, "%s compare %s %s --heatmap %s", RESURF_CLI, ref_path, test_path, test_path);
    ck_assert_int_eq(tu_run(cmd, &text), 1);
    free(text);
    resurf_mesh_free(ref);
    resurf_mesh_free(test);
    resurf_mesh_free(heat);
    free(ref_path);
    free(test_path);
    free(heat_path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* A REF that is a single point has no scale: the relative figures are null in JSON and "-" in the table, never
 * a made-up 0, while the absolute ones stay exact (the unit right triangle's farthest point is 1 away). */
START_TEST(compare_cli_point_ref_has_no_relative_figures)
{
    char *dir = tu_tempdir(), *ref_path = tu_path(dir, "point.obj"), *test_path = tu_path(dir, "tri.obj");
    const char point[] = "v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n", tri[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    ck_assert_int_eq(tu_write_file(ref_path, point, sizeof point - 1), 0);
    ck_assert_int_eq(tu_write_file(test_path, tri, sizeof tri - 1), 0);
    char cmd[2048], *text = NULL;
    snprintf(cmd, sizeof cmd, "%s compare %s %s --json --samples 100", RESURF_CLI, ref_path, test_path);
    ck_assert_int_eq(tu_run(cmd, &text), 0);
    ck_assert_double_eq(json_number(text, "diagonal"), 0);
    ck_assert_double_eq_tol(json_number(text, "hausdorff"), 1, 1e-15);
    ck_assert_ptr_nonnull(strstr(text, "\"hausdorff_rel\": null"));
    ck_assert_ptr_null(strstr(text, "_rel\": 0"));
    free(text);
    snprintf(cmd, sizeof cmd, "%s compare %s %s --samples 100", RESURF_CLI, ref_path, test_path);
    ck_assert_int_eq(tu_run(cmd, &text), 0);
    ck_assert_ptr_nonnull(strstr(text, "hausdorff                                   1                -"));
    free(text);
    free(ref_path);
    free(test_path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(compare_rejects_bad_input)
{
    resurf_mesh *a = tu_grid(2), *b = tu_grid(2), *empty = NULL;
    ck_assert_int_eq(resurf_mesh_create(3, 0, 0, &empty, NULL), RESURF_OK);
    resurf_compare_report r;
    resurf_error e;
    ck_assert_int_eq(resurf_compare(NULL, b, NULL, &r, NULL, &e), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurf_compare(a, b, NULL, NULL, NULL, &e), RESURF_ERR_INVALID_ARGUMENT);
    resurf_compare_options zeroed;
    memset(&zeroed, 0, sizeof zeroed);
    ck_assert_int_eq(resurf_compare(a, b, &zeroed, &r, NULL, &e), RESURF_ERR_INVALID_OPTIONS);
    ck_assert_int_eq(resurf_compare(a, empty, NULL, &r, NULL, &e), RESURF_ERR_INVALID_MESH);
    ck_assert_ptr_nonnull(strstr(e.message, "TEST"));
    b->indices[4] = 50;
    ck_assert_int_eq(resurf_compare(a, b, NULL, &r, NULL, &e), RESURF_ERR_INVALID_MESH);
    ck_assert_ptr_nonnull(strstr(e.message, "TEST: triangle 1"));
    b->indices[4] = 1;
    a->positions[3] = INFINITY;
    ck_assert_int_eq(resurf_compare(a, b, NULL, &r, NULL, &e), RESURF_ERR_INVALID_MESH);
    ck_assert_ptr_nonnull(strstr(e.message, "REF"));
    ck_assert_int_eq(resurf_triangle_quality(a, NULL, NULL, NULL, &e), RESURF_ERR_INVALID_MESH);
    ck_assert_int_eq(resurf_triangle_quality(NULL, NULL, NULL, NULL, &e), RESURF_ERR_INVALID_ARGUMENT);
    resurf_mesh_free(a);
    resurf_mesh_free(b);
    resurf_mesh_free(empty);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("metrics");
    TCase *tc = tcase_create("metrics");
    tcase_add_test(tc, compare_self_is_zero);
    tcase_add_test(tc, compare_scaled_sphere_hausdorff);
    tcase_add_test(tc, compare_shifted_plane_is_d_everywhere);
    tcase_add_test(tc, compare_area_uniform_sampling);
    tcase_add_test(tc, compare_rms_of_tilted_plane);
    tcase_add_test(tc, compare_flipped_normals);
    tcase_add_test(tc, quality_hand_triangles);
    tcase_add_test(tc, compare_reports_test_quality);
    tcase_add_test(tc, compare_threads_deterministic);
    tcase_add_test(tc, compare_without_samples);
    tcase_add_test(tc, compare_facet_points_find_a_chord);
    tcase_add_test(tc, compare_climbs_to_the_farthest_point);
    tcase_add_test(tc, compare_cancel);
    tcase_add_test(tc, compare_rejects_bad_input);
    tcase_add_test(tc, compare_cli_json_and_heatmap);
    tcase_add_test(tc, compare_cli_point_ref_has_no_relative_figures);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN();
