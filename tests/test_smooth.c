/* src/smooth.c: the four filters against analytic truth — planes stay planes with fixed borders, Laplacian
 * shrinks a sphere and Taubin hardly does, cotangent weights have linear precision on flat meshes, seams move
 * together, cancel leaves the mesh unchanged, and bad input is refused. */
#include <stdio.h>
#include <string.h>

#include "testutil.h"

static const resurf_smooth_method all_methods[] = {RESURF_SMOOTH_LAPLACIAN, RESURF_SMOOTH_TAUBIN,
                                                   RESURF_SMOOTH_TAUBIN_COT, RESURF_SMOOTH_BILAPLACIAN};

static resurf_smooth_options options_for(resurf_smooth_method method, unsigned iterations)
{
    resurf_smooth_options o = resurf_smooth_options_default();
    o.method = method;
    o.iterations = iterations;
    return o;
}

/* Is a point of a mesh over [−1,1]² on the square's border (where shapes.c puts the unjittered grid ends)? */
static int on_square_border(const double *p) { return fabs(p[0]) == 1.0 || fabs(p[1]) == 1.0; }

static double mean_radius(const resurf_mesh *m)
{
    double sum = 0;
    for (size_t v = 0; v < m->vertex_count; ++v)
        sum += v3_len(resurfi_position(m, (uint32_t)v));
    return sum / (double)m->vertex_count;
}

/* A jittered plane z = 0: every filter keeps interior vertices at z = 0 (the umbrella of coplanar points is in
 * the plane), keeps the border bit-for-bit, and does move interior vertices (tangentially). */
START_TEST(smooth_plane_stays_plane_border_fixed)
{
    for (size_t k = 0; k < sizeof all_methods / sizeof all_methods[0]; ++k) {
        resurf_mesh *m = shape_mesh(SHAPE_PLANE, 2000, 0.35, 7, 0);
        resurf_mesh *before = NULL;
        ck_assert_int_eq(resurf_mesh_clone(m, &before, NULL), RESURF_OK);
        resurf_smooth_options o = options_for(all_methods[k], 20);
        ck_assert_int_eq(resurf_smooth(m, &o, NULL), RESURF_OK);
        double moved = 0;
        size_t border = 0;
        for (size_t v = 0; v < m->vertex_count; ++v) {
            const double *p = m->positions + 3 * v, *q = before->positions + 3 * v;
            ck_assert_double_eq(p[2], 0.0);
            if (on_square_border(q)) {
                ++border;
                ck_assert(memcmp(p, q, 3 * sizeof *p) == 0);
            } else {
                moved = fmax(moved, v3_dist(v3_load(p), v3_load(q)));
            }
        }
        ck_assert_uint_gt(border, 40);
        ck_assert_msg(moved > 1e-3, "%s moved nothing", resurf_smooth_method_name(all_methods[k]));
        resurf_mesh_free(m);
        resurf_mesh_free(before);
    }
}
END_TEST

/* A noisy plane: z = ±0.01 noise on the interior of a regular grid. Every filter must reduce the noise. */
START_TEST(smooth_reduces_noise_on_plane)
{
    for (size_t k = 0; k < sizeof all_methods / sizeof all_methods[0]; ++k) {
        resurf_mesh *m = tu_grid(24);
        uint64_t state = 5;
        double before = 0, after = 0;
        for (size_t v = 0; v < m->vertex_count; ++v) {
            double *p = m->positions + 3 * v;
            if (p[0] > 0 && p[0] < 1 && p[1] > 0 && p[1] < 1)
                p[2] = 0.02 * (shape_rand_unit(&state) - 0.5);
            before += p[2] * p[2];
        }
        resurf_smooth_options o = options_for(all_methods[k], 10);
        ck_assert_int_eq(resurf_smooth(m, &o, NULL), RESURF_OK);
        for (size_t v = 0; v < m->vertex_count; ++v)
            after += m->positions[3 * v + 2] * m->positions[3 * v + 2];
        ck_assert_msg(after < 0.25 * before, "%s: noise energy %g -> %g", resurf_smooth_method_name(all_methods[k]),
                      before, after);
        resurf_mesh_free(m);
    }
}
END_TEST

/* The cubic surface is open: its border stays fixed under every filter, interior vertices move. */
START_TEST(smooth_open_surface_border_fixed)
{
    for (size_t k = 0; k < sizeof all_methods / sizeof all_methods[0]; ++k) {
        resurf_mesh *m = shape_mesh(SHAPE_CUBIC, 3000, 0.3, 3, 0);
        resurf_mesh *before = NULL;
        ck_assert_int_eq(resurf_mesh_clone(m, &before, NULL), RESURF_OK);
        resurf_smooth_options o = options_for(all_methods[k], 5);
        ck_assert_int_eq(resurf_smooth(m, &o, NULL), RESURF_OK);
        for (size_t v = 0; v < m->vertex_count; ++v) {
            const double *q = before->positions + 3 * v;
            if (on_square_border(q))
                ck_assert(memcmp(m->positions + 3 * v, q, 3 * sizeof *q) == 0);
        }
        resurf_mesh_free(m);
        resurf_mesh_free(before);
    }
}
END_TEST

/* Laplacian smoothing shrinks a sphere; Taubin's λ|μ pair passes the lowest frequencies (a sphere's radius is
 * one) with gain (1 − λk)(1 − μk) ≈ 1 + 0.01k against Laplacian's (1 − 0.5k)² per two steps, so with the same
 * number of umbrella steps the radius change must be well under a tenth of Laplacian's. */
START_TEST(smooth_laplacian_shrinks_sphere_taubin_does_not)
{
    resurf_mesh *lap = shape_mesh(SHAPE_SPHERE, 3000, 0.3, 11, 0);
    resurf_mesh *tau = NULL, *cot = NULL;
    ck_assert_int_eq(resurf_mesh_clone(lap, &tau, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_mesh_clone(lap, &cot, NULL), RESURF_OK);
    double r0 = mean_radius(lap);
    ck_assert_double_eq_tol(r0, 1.0, 1e-12);
    resurf_smooth_options o = options_for(RESURF_SMOOTH_LAPLACIAN, 20);
    ck_assert_int_eq(resurf_smooth(lap, &o, NULL), RESURF_OK);
    o = options_for(RESURF_SMOOTH_TAUBIN, 10); /* 10 λ|μ pairs = 20 umbrella steps */
    ck_assert_int_eq(resurf_smooth(tau, &o, NULL), RESURF_OK);
    o = options_for(RESURF_SMOOTH_TAUBIN_COT, 10);
    ck_assert_int_eq(resurf_smooth(cot, &o, NULL), RESURF_OK);
    double shrink_lap = 1.0 - mean_radius(lap), shrink_tau = fabs(1.0 - mean_radius(tau));
    double shrink_cot = fabs(1.0 - mean_radius(cot));
    ck_assert_msg(shrink_lap > 1e-3, "Laplacian shrink %g", shrink_lap);
    ck_assert_msg(shrink_tau < 0.1 * shrink_lap, "Taubin %g vs Laplacian %g", shrink_tau, shrink_lap);
    ck_assert_msg(shrink_cot < 0.1 * shrink_lap, "Taubin-cot %g vs Laplacian %g", shrink_cot, shrink_lap);
    resurf_mesh_free(lap);
    resurf_mesh_free(tau);
    resurf_mesh_free(cot);
}
END_TEST

/* A flat grid graded along x (x_i = (i/n)²) split into right triangles: Delaunay, so no cot weight is clamped,
 * and the cotangent Laplacian's linear precision makes it vanish at every interior vertex — nothing moves.
 * Uniform weights are pulled towards the denser side, which shows the test is not vacuous. */
static resurf_mesh *graded_grid(unsigned n)
{
    resurf_mesh *m = tu_grid(n);
    for (size_t v = 0; v < m->vertex_count; ++v)
        m->positions[3 * v] *= m->positions[3 * v];
    return m;
}

START_TEST(smooth_cot_keeps_flat_grid)
{
    resurf_mesh *m = graded_grid(12), *before = NULL, *uni = NULL;
    ck_assert_int_eq(resurf_mesh_clone(m, &before, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_mesh_clone(m, &uni, NULL), RESURF_OK);
    resurf_smooth_options o = options_for(RESURF_SMOOTH_TAUBIN_COT, 20);
    ck_assert_int_eq(resurf_smooth(m, &o, NULL), RESURF_OK);
    o.method = RESURF_SMOOTH_TAUBIN;
    ck_assert_int_eq(resurf_smooth(uni, &o, NULL), RESURF_OK);
    double cot_moved = 0, uni_moved = 0;
    for (uint32_t v = 0; v < m->vertex_count; ++v) {
        cot_moved = fmax(cot_moved, v3_dist(resurfi_position(m, v), resurfi_position(before, v)));
        uni_moved = fmax(uni_moved, v3_dist(resurfi_position(uni, v), resurfi_position(before, v)));
    }
    ck_assert_msg(cot_moved < 1e-14, "cot moved %g", cot_moved);
    ck_assert_msg(uni_moved > 1e-3, "uniform moved only %g", uni_moved);
    resurf_mesh_free(m);
    resurf_mesh_free(before);
    resurf_mesh_free(uni);
}
END_TEST

/* A triangle soup (every triangle its own three vertices: every position a seam) must smooth exactly like the
 * indexed mesh: duplicates move together and seams are not boundaries. */
START_TEST(smooth_seams_move_together)
{
    for (size_t k = 0; k < sizeof all_methods / sizeof all_methods[0]; ++k) {
        resurf_mesh *m = shape_mesh(SHAPE_TORUS, 1500, 0.3, 2, 0), *soup = NULL;
        ck_assert_int_eq(resurf_mesh_create(3 * m->triangle_count, m->triangle_count, 0, &soup, NULL), RESURF_OK);
        for (size_t c = 0; c < 3 * m->triangle_count; ++c) {
            memcpy(soup->positions + 3 * c, m->positions + 3 * (size_t)m->indices[c], 3 * sizeof(double));
            soup->indices[c] = (uint32_t)c;
        }
        resurf_smooth_options o = options_for(all_methods[k], 4);
        ck_assert_int_eq(resurf_smooth(m, &o, NULL), RESURF_OK);
        ck_assert_int_eq(resurf_smooth(soup, &o, NULL), RESURF_OK);
        /* Corners of one original vertex hold bit-identical positions; they match the indexed result up to the
         * summation order of the one-ring, which the different numbering changes. */
        double moved = 0;
        uint32_t *first = malloc(m->vertex_count * sizeof *first);
        for (size_t v = 0; v < m->vertex_count; ++v)
            first[v] = UINT32_MAX;
        for (size_t c = 0; c < 3 * m->triangle_count; ++c) {
            uint32_t v = m->indices[c];
            if (first[v] == UINT32_MAX)
                first[v] = (uint32_t)c;
            ck_assert(memcmp(soup->positions + 3 * c, soup->positions + 3 * (size_t)first[v], 3 * sizeof(double))
                      == 0);
            ck_assert(v3_dist(resurfi_position(soup, (uint32_t)c), resurfi_position(m, v)) < 1e-13);
        }
        free(first);
        resurf_mesh *orig = shape_mesh(SHAPE_TORUS, 1500, 0.3, 2, 0);
        for (uint32_t v = 0; v < m->vertex_count; ++v)
            moved = fmax(moved, v3_dist(resurfi_position(m, v), resurfi_position(orig, v)));
        ck_assert(moved > 1e-4);
        resurf_mesh_free(orig);
        resurf_mesh_free(m);
        resurf_mesh_free(soup);
    }
}
END_TEST

/* The bilaplacian with its largest allowed step stays bounded on a very irregular sphere over many iterations (an
 * unstable explicit step would grow the highest frequency by a factor |1 − λ × 4/ν| > 1 per step: within 300
 * steps the mesh would explode). */
START_TEST(smooth_bilaplacian_stable)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 2000, 0.45, 4, 0);
    resurf_smooth_options o = options_for(RESURF_SMOOTH_BILAPLACIAN, 300);
    o.lambda = 0.5;
    ck_assert_int_eq(resurf_smooth(m, &o, NULL), RESURF_OK);
    for (uint32_t v = 0; v < m->vertex_count; ++v) {
        double r = v3_len(resurfi_position(m, v));
        ck_assert_msg(r > 0.8 && r < 1.1, "radius %g", r); /* the flow bulges valence-3 corners a little */
    }
    resurf_mesh_free(m);
}
END_TEST

/* Taubin with cotangent weights stays bounded over many iterations on a very irregular sphere (weights that
 * followed the degenerating triangles made this flow blow up within a few hundred iterations). */
START_TEST(smooth_taubin_cot_stable)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 2000, 0.45, 4, 0);
    resurf_smooth_options o = options_for(RESURF_SMOOTH_TAUBIN_COT, 1500);
    ck_assert_int_eq(resurf_smooth(m, &o, NULL), RESURF_OK);
    for (uint32_t v = 0; v < m->vertex_count; ++v) {
        double r = v3_len(resurfi_position(m, v));
        ck_assert_msg(r > 0.8 && r < 1.2, "radius %g", r);
    }
    resurf_mesh_free(m);
}
END_TEST

/* `resurf smooth` gives what the library gives (OBJ keeps 17 digits), and refuses bad arguments with status 2. */
START_TEST(smooth_cli)
{
    char *dir = tu_tempdir(), *in = tu_path(dir, "in.obj"), *out = tu_path(dir, "out.obj");
    resurf_mesh *m = shape_mesh(SHAPE_CUBIC, 600, 0.3, 8, 0), *back = NULL;
    ck_assert_int_eq(resurf_mesh_save(m, in, NULL, NULL), RESURF_OK);
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s smooth %s -o %s --method taubin --iterations 3 --lambda 0.3 --mu -0.32",
             RESURF_CLI, in, out);
    char *text = NULL;
    ck_assert_int_eq(tu_run(cmd, &text), 0);
    free(text);
    resurf_smooth_options o = options_for(RESURF_SMOOTH_TAUBIN, 3);
    o.lambda = 0.3;
    o.mu = -0.32;
    ck_assert_int_eq(resurf_smooth(m, &o, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_mesh_load(out, NULL, &back, NULL), RESURF_OK);
    ck_assert_uint_eq(back->vertex_count, m->vertex_count);
    ck_assert(memcmp(back->positions, m->positions, 3 * m->vertex_count * sizeof(double)) == 0);
    const char *bad[] = {"--method nope", "--iterations -1", "--lambda 2", "--mu 0.5",
                         "--method bilaplacian --lambda 0.7", ""};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        snprintf(cmd, sizeof cmd, "%s smooth %s %s%s %s", RESURF_CLI, in, *bad[i] ? "-o " : "", *bad[i] ? out : "",
                 bad[i]);
        ck_assert_int_eq(tu_run(cmd, &text), 2);
        free(text);
    }
    snprintf(cmd, sizeof cmd, "%s smooth %s -o %s", RESURF_CLI, in, in);
    ck_assert_int_eq(tu_run(cmd, &text), 1);
    free(text);
    resurf_mesh_free(m);
    resurf_mesh_free(back);
    free(in);
    free(out);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

typedef struct progress_log {
    int calls, cancel_at;
    double last;
    int decreasing;
} progress_log;

static bool log_progress(void *user, resurf_stage stage, double fraction)
{
    progress_log *l = user;
    ck_assert_int_eq(stage, RESURF_STAGE_SMOOTH);
    if (fraction < l->last)
        l->decreasing = 1;
    l->last = fraction;
    return ++l->calls == l->cancel_at;
}

/* A cancel at any progress call returns CANCELLED with the positions bit-for-bit unchanged; without a cancel the
 * callback is called once per iteration plus once at the end, with non-decreasing fractions. */
START_TEST(smooth_cancel_leaves_mesh_unchanged)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 800, 0.3, 1, 0), *before = NULL;
    ck_assert_int_eq(resurf_mesh_clone(m, &before, NULL), RESURF_OK);
    const unsigned iterations = 6;
    for (int cancel_at = 1; cancel_at <= (int)iterations + 1; ++cancel_at) {
        progress_log log = {0, cancel_at, 0, 0};
        resurf_smooth_options o = options_for(RESURF_SMOOTH_TAUBIN, iterations);
        o.progress = (resurf_progress){log_progress, &log};
        resurf_error error;
        ck_assert_int_eq(resurf_smooth(m, &o, &error), RESURF_ERR_CANCELLED);
        ck_assert_int_eq(error.status, RESURF_ERR_CANCELLED);
        ck_assert(memcmp(m->positions, before->positions, 3 * m->vertex_count * sizeof(double)) == 0);
    }
    progress_log log = {0, -1, 0, 0};
    resurf_smooth_options o = options_for(RESURF_SMOOTH_TAUBIN, iterations);
    o.progress = (resurf_progress){log_progress, &log};
    ck_assert_int_eq(resurf_smooth(m, &o, NULL), RESURF_OK);
    ck_assert_int_eq(log.calls, (int)iterations + 1);
    ck_assert_int_eq(log.decreasing, 0);
    ck_assert_double_eq(log.last, 1.0);
    resurf_mesh_free(m);
    resurf_mesh_free(before);
}
END_TEST

START_TEST(smooth_rejects_bad_input)
{
    resurf_mesh *m = tu_grid(3);
    resurf_error error;
    resurf_smooth_options o = resurf_smooth_options_default();
    ck_assert_int_eq(resurf_smooth(NULL, &o, &error), RESURF_ERR_INVALID_ARGUMENT);
    resurf_smooth_options zeroed;
    memset(&zeroed, 0, sizeof zeroed);
    ck_assert_int_eq(resurf_smooth(m, &zeroed, &error), RESURF_ERR_INVALID_OPTIONS);
    o.method = RESURF_SMOOTH_COUNT;
    ck_assert_int_eq(resurf_smooth(m, &o, &error), RESURF_ERR_INVALID_OPTIONS);
    o = options_for(RESURF_SMOOTH_BILAPLACIAN, 1);
    o.lambda = 0.6;
    ck_assert_int_eq(resurf_smooth(m, &o, &error), RESURF_ERR_INVALID_OPTIONS);
    o = options_for(RESURF_SMOOTH_TAUBIN, 1);
    o.mu = 0.2;
    ck_assert_int_eq(resurf_smooth(m, &o, &error), RESURF_ERR_INVALID_OPTIONS);
    o.mu = 0;
    o.lambda = NAN;
    ck_assert_int_eq(resurf_smooth(m, &o, &error), RESURF_ERR_INVALID_OPTIONS);

    m->indices[7] = 99;
    ck_assert_int_eq(resurf_smooth(m, NULL, &error), RESURF_ERR_INVALID_MESH);
    ck_assert_ptr_nonnull(strstr(error.message, "triangle 2"));
    m->indices[7] = 1;
    m->positions[4] = NAN;
    ck_assert_int_eq(resurf_smooth(m, NULL, &error), RESURF_ERR_INVALID_MESH);
    ck_assert_ptr_nonnull(strstr(error.message, "vertex 1"));
    resurf_mesh_free(m);
}
END_TEST

/* An empty mesh and a mesh of lone vertices are fine and untouched. */
START_TEST(smooth_empty_and_no_triangles)
{
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(0, 0, 0, &m, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_smooth(m, NULL, NULL), RESURF_OK);
    resurf_mesh_free(m);
    ck_assert_int_eq(resurf_mesh_create(3, 0, 0, &m, NULL), RESURF_OK);
    m->positions[0] = 1;
    ck_assert_int_eq(resurf_smooth(m, NULL, NULL), RESURF_OK);
    ck_assert_double_eq(m->positions[0], 1);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(smooth_method_names)
{
    ck_assert_str_eq(resurf_smooth_method_name(RESURF_SMOOTH_LAPLACIAN), "laplacian");
    ck_assert_str_eq(resurf_smooth_method_name(RESURF_SMOOTH_TAUBIN), "taubin");
    ck_assert_str_eq(resurf_smooth_method_name(RESURF_SMOOTH_TAUBIN_COT), "taubin-cot");
    ck_assert_str_eq(resurf_smooth_method_name(RESURF_SMOOTH_BILAPLACIAN), "bilaplacian");
    ck_assert_str_eq(resurf_smooth_method_name(RESURF_SMOOTH_COUNT), "unknown");
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("smooth");
    TCase *tc = tcase_create("smooth");
    tcase_add_test(tc, smooth_plane_stays_plane_border_fixed);
    tcase_add_test(tc, smooth_reduces_noise_on_plane);
    tcase_add_test(tc, smooth_open_surface_border_fixed);
    tcase_add_test(tc, smooth_laplacian_shrinks_sphere_taubin_does_not);
    tcase_add_test(tc, smooth_cot_keeps_flat_grid);
    tcase_add_test(tc, smooth_seams_move_together);
    tcase_add_test(tc, smooth_bilaplacian_stable);
    tcase_add_test(tc, smooth_taubin_cot_stable);
    tcase_add_test(tc, smooth_cli);
    tcase_add_test(tc, smooth_cancel_leaves_mesh_unchanged);
    tcase_add_test(tc, smooth_rejects_bad_input);
    tcase_add_test(tc, smooth_empty_and_no_triangles);
    tcase_add_test(tc, smooth_method_names);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN();
