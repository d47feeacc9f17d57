/* src/simplify/services.c, the services over the original built once and lent to several simplifications: a call
 * that borrows them makes the same level and the same report, bit for bit, as one that builds its own, in every
 * restoring mode, with and without attributes, with or without a measured report; services built for one mesh
 * are refused for another; bad input fails the build with the simplifier's own error. A run kept between targets
 * (resurfi_simplify_run, the scene budget's) makes each target's level as a call does. */
#include <math.h>
#include <string.h>

#include "internal.h"
#include "testutil.h"

static int same_mesh(const resurf_mesh *a, const resurf_mesh *b)
{
    if (a->vertex_count != b->vertex_count || a->triangle_count != b->triangle_count ||
        !a->normals != !b->normals)
        return 0;
    if (memcmp(a->positions, b->positions, 3 * a->vertex_count * sizeof *a->positions) ||
        memcmp(a->indices, b->indices, 3 * a->triangle_count * sizeof *a->indices))
        return 0;
    return !a->normals || !memcmp(a->normals, b->normals, 3 * a->vertex_count * sizeof *a->normals);
}

/* Distances are NaN when nothing was measured: compared as bits. */
static int same_report(const resurf_simplify_report *a, const resurf_simplify_report *b)
{
    return a->triangles == b->triangles && a->vertices == b->vertices && a->collapses == b->collapses &&
           !memcmp(&a->result_to_input_max, &b->result_to_input_max, sizeof(double)) &&
           !memcmp(&a->input_to_result_max, &b->input_to_result_max, sizeof(double)) &&
           !memcmp(&a->result_to_input_mean, &b->result_to_input_mean, sizeof(double)) &&
           !memcmp(&a->input_to_result_mean, &b->input_to_result_mean, sizeof(double));
}

/* Simplified to each target twice, with the services lent (built with `built`) and without. */
static void check_lent(const resurf_mesh *in, const resurf_simplify_options *built, resurf_simplify_options o)
{
    resurfi_simplify_services *sv = NULL;
    resurf_error e;
    ck_assert_int_eq(resurfi_simplify_services_build(in, built, &sv, &e), RESURF_OK);
    static const double ratios[] = {0.5, 0.2, 0.05};
    for (size_t k = 0; k < sizeof ratios / sizeof *ratios; ++k) {
        o.target_ratio = ratios[k];
        resurf_mesh *own = NULL, *lent = NULL;
        resurf_simplify_report ro, rl;
        ck_assert_int_eq(resurf_simplify(in, &o, &own, &ro, &e), RESURF_OK);
        ck_assert_int_eq(resurfi_simplify_lent(in, &o, sv, &lent, &rl, &e), RESURF_OK);
        ck_assert_msg(same_mesh(own, lent), "ratio %g: the lent services changed the level", ratios[k]);
        ck_assert_msg(same_report(&ro, &rl), "ratio %g: the lent services changed the report", ratios[k]);
        ck_assert_uint_lt(own->triangle_count, in->triangle_count);
        resurf_mesh_free(own);
        resurf_mesh_free(lent);
    }
    resurfi_simplify_services_free(sv);
}

START_TEST(lent_services_change_nothing)
{
    resurf_mesh *sphere = shape_mesh(SHAPE_SPHERE, 4000, 0.2, 7, 0);
    resurf_mesh *torus = shape_mesh(SHAPE_TORUS, 4000, 0.2, 3, 1); /* with normals: attributes to interpolate */
    resurf_mesh *cube = shape_mesh(SHAPE_CUBE, 3000, 0, 1, 0);     /* creases and corners: the curves */
    ck_assert(sphere && torus && cube);
    static const resurf_restore_mode modes[] = {RESURF_RESTORE_INLINE, RESURF_RESTORE_POST, RESURF_RESTORE_NONE};
    for (size_t m = 0; m < sizeof modes / sizeof *modes; ++m) {
        resurf_simplify_options o = resurf_simplify_options_default();
        o.restore = modes[m];
        check_lent(sphere, &o, o);
        check_lent(torus, &o, o);
        check_lent(cube, &o, o);
    }
    /* Built on several threads and without a report to measure, lent to a one-thread call that measures: the tree
     * the call needs and the services lack, it builds. */
    resurf_simplify_options built = resurf_simplify_options_default(), call = built;
    built.threads = 2;
    built.measure_samples = 0;
    call.threads = 1;
    check_lent(sphere, &built, call);
    resurf_mesh_free(sphere);
    resurf_mesh_free(torus);
    resurf_mesh_free(cube);
}
END_TEST

START_TEST(services_belong_to_their_mesh)
{
    resurf_mesh *a = shape_mesh(SHAPE_SPHERE, 500, 0, 1, 0), *b = shape_mesh(SHAPE_SPHERE, 500, 0, 1, 0);
    resurfi_simplify_services *sv = NULL;
    resurf_error e;
    ck_assert_int_eq(resurfi_simplify_services_build(a, NULL, &sv, &e), RESURF_OK);
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.5;
    resurf_mesh *out = NULL;
    ck_assert_int_eq(resurfi_simplify_lent(b, &o, sv, &out, NULL, &e), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(out);
    double ratios[] = {0.5};
    resurf_mesh *levels[1] = {NULL};
    ck_assert_int_eq(resurfi_simplify_lods_until(b, ratios, 1, &o, NULL, sv, NULL, levels, NULL, &e),
                     RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(levels[0]);
    resurfi_simplify_services_free(sv);
    resurfi_simplify_services_free(NULL);
    /* A triangle that names a vertex the mesh does not have: the simplifier's own check. */
    b->indices[4] = (uint32_t)b->vertex_count;
    ck_assert_int_eq(resurfi_simplify_services_build(b, NULL, &sv, &e), RESURF_ERR_INVALID_MESH);
    ck_assert_ptr_null(sv);
    ck_assert(strstr(e.message, "refers to vertex") != NULL);
    resurf_mesh_free(a);
    resurf_mesh_free(b);
}
END_TEST

/* A run kept between targets and asked for fewer triangles each time makes, at each, the level and report a call to
 * that target makes; it refuses to go back up and the measured choice (two runs). */
static void check_run(const resurf_mesh *in, resurf_restore_mode mode)
{
    resurf_simplify_options o = resurf_simplify_options_default();
    o.restore = mode;
    resurfi_simplify_services *sv = NULL;
    resurfi_simplify_run *run = NULL;
    resurf_error e;
    ck_assert_int_eq(resurfi_simplify_services_build(in, &o, &sv, &e), RESURF_OK);
    ck_assert_int_eq(resurfi_simplify_run_open(in, &o, sv, &run, &e), RESURF_OK);
    ck_assert_uint_eq(resurfi_simplify_run_reached(run), SIZE_MAX);
    const size_t n = in->triangle_count, targets[] = {n / 2, n / 2 - 1, n / 5, n / 20};
    for (size_t k = 0; k < sizeof targets / sizeof *targets; ++k) {
        resurf_mesh *call = NULL, *kept = NULL;
        resurf_simplify_report rc, rk;
        o.target_triangles = targets[k];
        ck_assert_int_eq(resurf_simplify(in, &o, &call, &rc, &e), RESURF_OK);
        ck_assert_int_eq(resurfi_simplify_run_to(run, targets[k], &kept, &rk, &e), RESURF_OK);
        ck_assert_msg(same_mesh(call, kept), "%zu triangles: the kept run's level differs from a call's", targets[k]);
        ck_assert_msg(same_report(&rc, &rk), "%zu triangles: the kept run's report differs from a call's", targets[k]);
        ck_assert_uint_eq(rk.restore_used, mode);
        ck_assert_uint_eq(resurfi_simplify_run_reached(run), targets[k]);
        resurf_mesh_free(call);
        resurf_mesh_free(kept);
    }
    resurf_mesh *up = NULL;
    ck_assert_int_eq(resurfi_simplify_run_to(run, n / 10, &up, NULL, &e), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(up);
    resurfi_simplify_run_free(run);
    o.restore = RESURF_RESTORE_MEASURED;
    ck_assert_int_eq(resurfi_simplify_run_open(in, &o, sv, &run, &e), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(run);
    resurfi_simplify_services_free(sv);
}

START_TEST(a_kept_run_makes_each_call_s_level)
{
    resurf_mesh *torus = shape_mesh(SHAPE_TORUS, 4000, 0.2, 3, 1);
    resurf_mesh *cube = shape_mesh(SHAPE_CUBE, 3000, 0, 1, 0);
    ck_assert(torus && cube);
    check_run(torus, RESURF_RESTORE_INLINE);
    check_run(cube, RESURF_RESTORE_INLINE);
    check_run(torus, RESURF_RESTORE_NONE);
    resurf_mesh_free(torus);
    resurf_mesh_free(cube);
}
END_TEST

/* A run told to reject above a bound (the scene budget's) reports a level whose maximum lies above it as +INFINITY
 * with NaN means, and any other level with the call's own report, bit for bit; the level itself is the call's either
 * way, and the run goes on to the next target as before. */
START_TEST(a_run_turned_down_says_only_so)
{
    resurf_mesh *torus = shape_mesh(SHAPE_TORUS, 4000, 0.2, 3, 1);
    ck_assert(torus);
    resurf_simplify_options o = resurf_simplify_options_default();
    o.restore = RESURF_RESTORE_INLINE;
    resurf_error e;
    static const size_t targets[] = {1500, 800, 300};
    resurf_simplify_report call[3];
    for (size_t k = 0; k < 3; ++k) {
        resurf_mesh *m = NULL;
        o.target_triangles = targets[k];
        ck_assert_int_eq(resurf_simplify(torus, &o, &m, &call[k], &e), RESURF_OK);
        ck_assert(call[k].max_distance > 0 && isfinite(call[k].max_distance));
        resurf_mesh_free(m);
    }
    o.target_triangles = 0;
    static const double scale = 3.0; /* the bound is in the caller's units: scale times the mesh's */
    for (int below = 0; below < 2; ++below) {
        resurfi_simplify_run *run = NULL;
        ck_assert_int_eq(resurfi_simplify_run_open(torus, &o, NULL, &run, &e), RESURF_OK);
        for (size_t k = 0; k < 3; ++k) {
            resurf_mesh *m = NULL;
            resurf_simplify_report r;
            /* just below the level's maximum, or exactly at it (within: the full report) */
            double bound = scale * call[k].max_distance * (below ? 0.999 : 1.0);
            resurfi_simplify_run_reject_above(run, scale, bound);
            ck_assert_int_eq(resurfi_simplify_run_to(run, targets[k], &m, &r, &e), RESURF_OK);
            ck_assert_uint_eq(m->triangle_count, call[k].triangles);
            if (below) {
                ck_assert(r.max_distance == INFINITY && r.result_to_input_max == INFINITY &&
                          r.input_to_result_max == INFINITY);
                ck_assert(isnan(r.mean_distance) && isnan(r.result_to_input_mean) &&
                          isnan(r.input_to_result_mean));
            } else {
                ck_assert_msg(same_report(&call[k], &r), "target %zu: the report within the bound is not the call's",
                              targets[k]);
            }
            resurf_mesh_free(m);
        }
        resurfi_simplify_run_free(run);
    }
    resurf_mesh_free(torus);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("simplify_services");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, lent_services_change_nothing);
    tcase_add_test(tc, services_belong_to_their_mesh);
    tcase_add_test(tc, a_kept_run_makes_each_call_s_level);
    tcase_add_test(tc, a_run_turned_down_says_only_so);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
