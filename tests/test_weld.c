/* src/weld.c: exact and tolerance welds number positions by first appearance and follow the documented rule. */
#include <string.h>

#include "testutil.h"

/* Exact weld of five vertices holding three positions A, B, C in the order A B A C B. */
START_TEST(weld_exact_numbers_by_first_appearance)
{
    const double p[] = {1, 2, 3, /* A */ 4, 5, 6, /* B */ 1, 2, 3, /* A */ 7, 8, 9, /* C */ 4, 5, 6 /* B */};
    uint32_t remap[5];
    size_t count = 99;
    ck_assert_int_eq(resurfi_weld_exact(NULL, p, 5, remap, &count), RESURF_OK);
    ck_assert_uint_eq(count, 3);
    const uint32_t expected[] = {0, 1, 0, 2, 1};
    for (int i = 0; i < 5; ++i)
        ck_assert_uint_eq(remap[i], expected[i]);
}
END_TEST

/* −0.0 == 0.0, so the two zeros are one position; a NaN welds only with the very same NaN bits. */
START_TEST(weld_exact_zero_signs_and_nan)
{
    const double p[] = {0, 0, 0, -0.0, 0, -0.0, NAN, 1, 1, NAN, 1, 1, 0, 1, 1};
    uint32_t remap[5];
    size_t count = 0;
    ck_assert_int_eq(resurfi_weld_exact(NULL, p, 5, remap, &count), RESURF_OK);
    ck_assert_uint_eq(remap[0], 0);
    ck_assert_uint_eq(remap[1], 0);
    ck_assert_uint_eq(remap[2], 1);
    ck_assert_uint_eq(remap[3], 1);
    ck_assert_uint_eq(remap[4], 2);
    ck_assert_uint_eq(count, 3);
}
END_TEST

START_TEST(weld_exact_empty)
{
    size_t count = 7;
    ck_assert_int_eq(resurfi_weld_exact(NULL, NULL, 0, NULL, &count), RESURF_OK);
    ck_assert_uint_eq(count, 0);
}
END_TEST

/* Many duplicates drawn from a small set of coordinates, against an O(n²) first-appearance numbering. */
START_TEST(weld_exact_matches_brute_force)
{
    const size_t n = 3000;
    double *p = malloc(n * 3 * sizeof *p);
    uint32_t *remap = malloc(n * sizeof *remap), *truth = malloc(n * sizeof *truth);
    uint64_t state = 42;
    for (size_t i = 0; i < 3 * n; ++i)
        p[i] = (double)(shape_rand_u64(&state) % 5) * 0.25 - 0.5; /* 125 possible positions, −0.0 never made */
    size_t count = 0, truth_count = 0;
    ck_assert_int_eq(resurfi_weld_exact(NULL, p, n, remap, &count), RESURF_OK);
    for (size_t i = 0; i < n; ++i) {
        size_t j = 0;
        while (j < i && memcmp(p + 3 * j, p + 3 * i, 3 * sizeof *p) != 0)
            ++j;
        truth[i] = j == i ? (uint32_t)truth_count++ : truth[j];
        ck_assert_uint_eq(remap[i], truth[i]);
    }
    ck_assert_uint_eq(count, truth_count);
    ck_assert_uint_le(count, 125);
    free(p);
    free(remap);
    free(truth);
}
END_TEST

/* A seam: a unit quad whose right edge is split for texcoords, so vertices 4 and 5 repeat 1 and 2 with other uvs.
 *
 *   3 ------ 2=5
 *   |      / |
 *   |    /   |         triangles (0, 1, 2) and (0, 5, 3) use the two copies of the same corner 2
 *   |  /     |
 *   0 ------ 1=4
 */
START_TEST(weld_map_seam_shares_position)
{
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(6, 2, RESURF_ATTR_TEXCOORD0, &m, NULL), RESURF_OK);
    const double p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0};
    const double uv[] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0, 0.5, 1};
    const uint32_t t[] = {0, 1, 2, 0, 5, 3};
    memcpy(m->positions, p, sizeof p);
    memcpy(m->texcoords[0], uv, sizeof uv);
    memcpy(m->indices, t, sizeof t);
    uint32_t ids[6];
    size_t count = 0;
    resurf_error error;
    ck_assert_int_eq(resurf_mesh_weld_map(m, 0, ids, &count, &error), RESURF_OK);
    ck_assert_int_eq(error.status, RESURF_OK);
    ck_assert_uint_eq(count, 4);
    const uint32_t expected[] = {0, 1, 2, 3, 1, 2};
    for (int i = 0; i < 6; ++i)
        ck_assert_uint_eq(ids[i], expected[i]);
    resurf_mesh_free(m);
}
END_TEST

/* A vertex-only mesh (no triangles: the diagonal spans all vertices). */
static resurf_mesh *points(const double *p, size_t n)
{
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(n, 0, 0, &m, NULL), RESURF_OK);
    memcpy(m->positions, p, n * 3 * sizeof *p);
    return m;
}

/* Points on the x axis, diagonal 1, tolerance 0.01:  x = 0, 0.006, 0.012, 1.
 * 0.006 joins 0; 0.012 is 0.012 from the representative 0 (only 0.006 from the non-representative 0.006), so it
 * starts a cluster: the weld does not chain. */
START_TEST(weld_map_tolerance_does_not_chain)
{
    const double p[] = {0, 0, 0, 0.006, 0, 0, 0.012, 0, 0, 1, 0, 0};
    resurf_mesh *m = points(p, 4);
    uint32_t ids[4];
    size_t count = 0;
    ck_assert_int_eq(resurf_mesh_weld_map(m, 0.01, ids, &count, NULL), RESURF_OK);
    ck_assert_uint_eq(ids[0], 0);
    ck_assert_uint_eq(ids[1], 0);
    ck_assert_uint_eq(ids[2], 1);
    ck_assert_uint_eq(ids[3], 2);
    ck_assert_uint_eq(count, 3);
    resurf_mesh_free(m);
}
END_TEST

/* x = 0, 0.015, 0.008, 1 with tolerance 0.01: 0.015 starts cluster 1; 0.008 is within reach of both
 * representatives (0.008 and 0.007) and joins the lowest-numbered, cluster 0. */
START_TEST(weld_map_tolerance_joins_lowest_cluster)
{
    const double p[] = {0, 0, 0, 0.015, 0, 0, 0.008, 0, 0, 1, 0, 0};
    resurf_mesh *m = points(p, 4);
    uint32_t ids[4];
    size_t count = 0;
    ck_assert_int_eq(resurf_mesh_weld_map(m, 0.01, ids, &count, NULL), RESURF_OK);
    const uint32_t expected[] = {0, 1, 0, 2};
    for (int i = 0; i < 4; ++i)
        ck_assert_uint_eq(ids[i], expected[i]);
    ck_assert_uint_eq(count, 3);
    resurf_mesh_free(m);
}
END_TEST

/* "Closer than" is strict: at exactly the tolerance (0.25 of a diagonal of 1, both exact in binary) no merge. */
START_TEST(weld_map_tolerance_is_strict)
{
    const double p[] = {0, 0, 0, 0.25, 0, 0, 1, 0, 0};
    resurf_mesh *m = points(p, 3);
    uint32_t ids[3];
    size_t count = 0;
    ck_assert_int_eq(resurf_mesh_weld_map(m, 0.25, ids, &count, NULL), RESURF_OK);
    ck_assert_uint_eq(count, 3);
    ck_assert_int_eq(resurf_mesh_weld_map(m, 0.2500001, ids, &count, NULL), RESURF_OK);
    ck_assert_uint_eq(count, 2);
    ck_assert_uint_eq(ids[1], 0);
    resurf_mesh_free(m);
}
END_TEST

/* The documented rule, implemented the slow obvious way, against the grid on random clouds of many densities. */
START_TEST(weld_map_tolerance_matches_rule)
{
    uint64_t state = 7;
    const double tolerances[] = {1e-3, 0.02, 0.05, 0.1, 0.3};
    for (int trial = 0; trial < 5; ++trial) {
        const size_t n = 600;
        double *p = malloc(n * 3 * sizeof *p);
        for (size_t i = 0; i < 3 * n; ++i)
            p[i] = shape_rand_unit(&state);
        /* Exact duplicates and near-copies, to make clusters of every size. */
        for (size_t i = n / 2; i < n; ++i) {
            size_t j = shape_rand_u64(&state) % (n / 2);
            for (int a = 0; a < 3; ++a)
                p[3 * i + a] = p[3 * j + a] + (i % 3 ? 0.04 * (shape_rand_unit(&state) - 0.5) : 0);
        }
        resurf_mesh *m = points(p, n);
        double diagonal = resurf_mesh_bounds(m, NULL, NULL);
        double tol = tolerances[trial] * diagonal;
        uint32_t *ids = malloc(n * sizeof *ids), *truth = malloc(n * sizeof *truth);
        size_t *rep = malloc(n * sizeof *rep); /* truth: representative vertex of each cluster */
        size_t clusters = 0;
        for (size_t i = 0; i < n; ++i) {
            /* The same position as an earlier vertex: the same id. */
            size_t j = 0;
            while (j < i && memcmp(p + 3 * j, p + 3 * i, 3 * sizeof *p) != 0)
                ++j;
            if (j < i) {
                truth[i] = truth[j];
                continue;
            }
            size_t c = 0;
            while (c < clusters && v3_dist(v3_load(p + 3 * rep[c]), v3_load(p + 3 * i)) >= tol)
                ++c;
            if (c == clusters)
                rep[clusters++] = i;
            truth[i] = (uint32_t)c;
        }
        size_t count = 0;
        ck_assert_int_eq(resurf_mesh_weld_map(m, tolerances[trial], ids, &count, NULL), RESURF_OK);
        ck_assert_uint_eq(count, clusters);
        for (size_t i = 0; i < n; ++i)
            ck_assert_uint_eq(ids[i], truth[i]);
        free(p);
        free(ids);
        free(truth);
        free(rep);
        resurf_mesh_free(m);
    }
}
END_TEST

/* Well-separated blobs (each point within 0.3 tol of its blob's centre, centres ≥ 10 tol apart) weld to exactly
 * one id per blob, whatever the vertex order. */
START_TEST(weld_map_tolerance_separated_blobs)
{
    const size_t blobs = 40, per = 25, n = blobs * per;
    const double tol_rel = 1e-3;
    uint64_t state = 11;
    double *p = malloc(n * 3 * sizeof *p);
    size_t *blob = malloc(n * sizeof *blob);
    /* Centres on a 4×10 lattice of spacing 0.1 (diagonal ≈ 0.95, so tol ≈ 0.00095 and spacing ≈ 105 tol). */
    for (size_t i = 0; i < n; ++i) {
        size_t b = shape_rand_u64(&state) % blobs;
        blob[i] = b;
        double c[3] = {0.1 * (double)(b % 10), 0.1 * (double)(b / 10), 0};
        for (int a = 0; a < 3; ++a)
            p[3 * i + a] = c[a] + 1.5e-4 * (shape_rand_unit(&state) - 0.5); /* |offset| < 1.3e-4 < 0.3 tol */
    }
    resurf_mesh *m = points(p, n);
    uint32_t *ids = malloc(n * sizeof *ids);
    size_t count = 0;
    ck_assert_int_eq(resurf_mesh_weld_map(m, tol_rel, ids, &count, NULL), RESURF_OK);
    ck_assert_uint_eq(count, blobs);
    for (size_t i = 0; i < n; ++i)
        for (size_t j = i + 1; j < n; ++j)
            ck_assert_int_eq(ids[i] == ids[j], blob[i] == blob[j]);
    free(p);
    free(blob);
    free(ids);
    resurf_mesh_free(m);
}
END_TEST

/* Non-finite positions never join a cluster, and do not spoil the diagonal the tolerance is measured against. */
START_TEST(weld_map_tolerance_nonfinite)
{
    const double p[] = {0, 0, 0, INFINITY, 0, 0, 0.001, 0, 0, NAN, 0, 0, 1, 0, 0};
    resurf_mesh *m = points(p, 5);
    ck_assert_double_eq_tol(resurfi_finite_diagonal(m), 1.0, 1e-15);
    uint32_t ids[5];
    size_t count = 0;
    ck_assert_int_eq(resurf_mesh_weld_map(m, 0.01, ids, &count, NULL), RESURF_OK);
    const uint32_t expected[] = {0, 1, 0, 2, 3};
    for (int i = 0; i < 5; ++i)
        ck_assert_uint_eq(ids[i], expected[i]);
    ck_assert_uint_eq(count, 4);
    resurf_mesh_free(m);
}
END_TEST

/* The diagonal counts only vertices referenced by triangles (as resurf_mesh_bounds does). */
START_TEST(weld_map_diagonal_of_referenced_vertices)
{
    /* Triangle over (0,0,0) (1,0,0) (0,1,0): diagonal √2. Vertex 3 is far away and unreferenced; vertex 4 lies
     * 0.01 from vertex 0: merged with tolerance_rel 0.01 (0.0141) but not with 0.005 (0.0071). */
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 100, 100, 100, 0.01, 0, 0};
    const uint32_t t[] = {0, 1, 2};
    resurf_mesh *m = tu_mesh(p, 5, t, 1);
    ck_assert_double_eq_tol(resurfi_finite_diagonal(m), sqrt(2.0), 1e-15);
    uint32_t ids[5];
    size_t count = 0;
    ck_assert_int_eq(resurf_mesh_weld_map(m, 0.01, ids, &count, NULL), RESURF_OK);
    ck_assert_uint_eq(count, 4);
    ck_assert_uint_eq(ids[4], 0);
    ck_assert_int_eq(resurf_mesh_weld_map(m, 0.005, ids, &count, NULL), RESURF_OK);
    ck_assert_uint_eq(count, 5);
    resurf_mesh_free(m);
}
END_TEST

/* tolerance 0 is the exact weld, position count optional. */
START_TEST(weld_map_zero_tolerance_is_exact)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 2000, 0.2, 5, 0);
    ck_assert_ptr_nonnull(m);
    /* Duplicate every vertex once more at the end: each copy must map onto its original. */
    size_t n = m->vertex_count;
    resurf_mesh *d = NULL;
    ck_assert_int_eq(resurf_mesh_create(2 * n, 0, 0, &d, NULL), RESURF_OK);
    memcpy(d->positions, m->positions, n * 3 * sizeof(double));
    memcpy(d->positions + 3 * n, m->positions, n * 3 * sizeof(double));
    uint32_t *ids = malloc(2 * n * sizeof *ids);
    ck_assert_int_eq(resurf_mesh_weld_map(d, 0, ids, NULL, NULL), RESURF_OK);
    for (size_t v = 0; v < n; ++v) {
        ck_assert_uint_eq(ids[v], v); /* the generator already welded exactly: all distinct */
        ck_assert_uint_eq(ids[n + v], v);
    }
    free(ids);
    resurf_mesh_free(d);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(weld_map_rejects_bad_arguments)
{
    resurf_mesh *m = tu_tetrahedron();
    uint32_t ids[4];
    resurf_error error;
    ck_assert_int_eq(resurf_mesh_weld_map(m, -0.1, ids, NULL, &error), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(error.status, RESURF_ERR_INVALID_ARGUMENT);
    ck_assert(strstr(error.message, "tolerance") != NULL);
    ck_assert_int_eq(resurf_mesh_weld_map(m, NAN, ids, NULL, NULL), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurf_mesh_weld_map(m, INFINITY, ids, NULL, NULL), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurf_mesh_weld_map(m, 0, NULL, NULL, NULL), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurf_mesh_weld_map(NULL, 0, ids, NULL, NULL), RESURF_ERR_INVALID_ARGUMENT);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(weld_map_empty_mesh)
{
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(0, 0, 0, &m, NULL), RESURF_OK);
    size_t count = 5;
    ck_assert_int_eq(resurf_mesh_weld_map(m, 0.1, NULL, &count, NULL), RESURF_OK);
    ck_assert_uint_eq(count, 0);
    resurf_mesh_free(m);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("weld");
    TCase *tc = tcase_create("weld");
    tcase_add_test(tc, weld_exact_numbers_by_first_appearance);
    tcase_add_test(tc, weld_exact_zero_signs_and_nan);
    tcase_add_test(tc, weld_exact_empty);
    tcase_add_test(tc, weld_exact_matches_brute_force);
    tcase_add_test(tc, weld_map_seam_shares_position);
    tcase_add_test(tc, weld_map_tolerance_does_not_chain);
    tcase_add_test(tc, weld_map_tolerance_joins_lowest_cluster);
    tcase_add_test(tc, weld_map_tolerance_is_strict);
    tcase_add_test(tc, weld_map_tolerance_matches_rule);
    tcase_add_test(tc, weld_map_tolerance_separated_blobs);
    tcase_add_test(tc, weld_map_tolerance_nonfinite);
    tcase_add_test(tc, weld_map_diagonal_of_referenced_vertices);
    tcase_add_test(tc, weld_map_zero_tolerance_is_exact);
    tcase_add_test(tc, weld_map_rejects_bad_arguments);
    tcase_add_test(tc, weld_map_empty_mesh);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
