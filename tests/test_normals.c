/* Tests for src/normals.c: each weighting scheme against the exact normals of analytic surfaces (plane exact; Max
 * exact where the 1-ring lies on a sphere; measured accuracy on irregular sphere, torus and cubic meshes, with the
 * ordering of the schemes asserted), degenerate faces and isolated vertices, orientation, argument checks. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "testutil.h"

static const char *const scheme_names[RESURF_NORMALS_COUNT] = {"inverse-area", "area", "angle", "max", "jet"};

static double *normals_of(const resurf_mesh *m, resurf_normal_scheme scheme)
{
    double *n = malloc(3 * m->vertex_count * sizeof *n);
    ck_assert_ptr_nonnull(n);
    ck_assert_int_eq(resurfi_vertex_normals(NULL, m->positions, m->vertex_count, m->indices, m->triangle_count,
                                            scheme, n),
                     RESURF_OK);
    return n;
}

/* Angle in degrees between unit vectors, accurate for tiny angles (atan2 of |a × b| and a · b). */
static double angle_deg(vec3 a, vec3 b) { return atan2(v3_len(v3_cross(a, b)), v3_dot(a, b)) * 180.0 / M_PI; }

typedef struct error_stats {
    double mean, max;
} error_stats;

/* Angle error of each vertex normal against the exact normal the shape generator attached. */
static error_stats normal_errors(const resurf_mesh *m, const double *n)
{
    error_stats e = {0, 0};
    for (size_t v = 0; v < m->vertex_count; ++v) {
        vec3 got = v3_load(n + 3 * v);
        ck_assert_double_eq_tol(v3_len(got), 1.0, 1e-14);
        double a = angle_deg(got, v3_load(m->normals + 3 * v));
        e.mean += a;
        e.max = fmax(e.max, a);
    }
    e.mean /= (double)m->vertex_count;
    return e;
}

START_TEST(plane_gives_exact_up)
{
    resurf_mesh *m = shape_mesh(SHAPE_PLANE, 2000, 0.3, 3, 0);
    ck_assert_ptr_nonnull(m);
    for (int s = 0; s < RESURF_NORMALS_COUNT; ++s) {
        double *n = normals_of(m, (resurf_normal_scheme)s);
        for (size_t v = 0; v < m->vertex_count; ++v)
            ck_assert_msg(n[3 * v] == 0 && n[3 * v + 1] == 0 && n[3 * v + 2] == 1, "%s: vertex %zu (%g %g %g)",
                          scheme_names[s], v, n[3 * v], n[3 * v + 1], n[3 * v + 2]);
        free(n);
    }
    resurf_mesh_free(m);
}
END_TEST

/* A vertex p on a sphere (centre c, radius 2) with an irregular closed fan of 7 neighbours on the same sphere at
 * different distances and angles, counter-clockwise seen from outside:
 *
 *          3   2
 *      4           1       every triangle is (p, i, i+1); the fan closes from 7 back to 1
 *            p
 *      5           7
 *           6
 * Max's weights give the sphere's normal (p − c) / 2 exactly (Max 1999); the others do not. */
START_TEST(max_exact_on_spherical_one_ring)
{
    const vec3 c = v3(0.3, -0.2, 0.5);
    const double radius = 2;
    vec3 out = v3_normalize(v3(1, 2, -0.5));
    vec3 t1 = v3_normalize(v3_cross(out, v3(0, 0, 1))), t2 = v3_cross(out, t1);
    const double turn[7] = {0.1, 0.9, 1.6, 2.9, 3.5, 4.4, 5.6};      /* direction around p, radians */
    const double reach[7] = {0.12, 0.05, 0.3, 0.2, 0.08, 0.25, 0.15}; /* angle at c between p and neighbour */
    double pos[3 * 8];
    v3_store(pos, v3_madd(c, out, radius));
    for (int i = 0; i < 7; ++i) {
        vec3 tangent = v3_add(v3_scale(t1, cos(turn[i])), v3_scale(t2, sin(turn[i])));
        vec3 d = v3_add(v3_scale(out, cos(reach[i])), v3_scale(tangent, sin(reach[i])));
        v3_store(pos + 3 * (i + 1), v3_madd(c, d, radius));
    }
    uint32_t idx[3 * 7];
    for (uint32_t i = 0; i < 7; ++i)
        idx[3 * i] = 0, idx[3 * i + 1] = i + 1, idx[3 * i + 2] = (i + 1) % 7 + 1;
    double n[3 * 8];
    ck_assert_int_eq(resurfi_vertex_normals(NULL, pos, 8, idx, 7, RESURF_NORMALS_MAX, n), RESURF_OK);
    ck_assert_msg(v3_dist(v3_load(n), out) < 1e-12, "max: error %g", v3_dist(v3_load(n), out));
    /* The fan is irregular enough that the other 1-ring schemes are visibly off. */
    for (int s = RESURF_NORMALS_INVERSE_AREA; s <= RESURF_NORMALS_ANGLE; ++s) {
        ck_assert_int_eq(resurfi_vertex_normals(NULL, pos, 8, idx, 7, (resurf_normal_scheme)s, n), RESURF_OK);
        ck_assert_msg(angle_deg(v3_load(n), out) > 0.1, "%s: %g°", scheme_names[s], angle_deg(v3_load(n), out));
    }
}
END_TEST

/* Irregular meshes (jitter 0.3) of a sphere, a torus and the cubic z = ½(x³ − 3xy²): the mean and largest angle error
 * of each scheme against the exact normals. Measured ordering, asserted: on the sphere Max is exact and the jet
 * beats the other three; on the torus and the cubic the jet beats every 1-ring scheme. */
START_TEST(accuracy_on_irregular_meshes)
{
    const shape_kind kinds[3] = {SHAPE_SPHERE, SHAPE_TORUS, SHAPE_CUBIC};
    printf("normals: angle error (degrees) against exact normals, jitter 0.3, ~5000 triangles\n");
    printf("%-10s %-14s %10s %10s\n", "shape", "scheme", "mean", "max");
    for (int k = 0; k < 3; ++k) {
        resurf_mesh *m = shape_mesh(kinds[k], 5000, 0.3, 17, 1);
        ck_assert_ptr_nonnull(m);
        error_stats e[RESURF_NORMALS_COUNT];
        for (int s = 0; s < RESURF_NORMALS_COUNT; ++s) {
            double *n = normals_of(m, (resurf_normal_scheme)s);
            e[s] = normal_errors(m, n);
            printf("%-10s %-14s %10.4f %10.4f\n", shape_name(kinds[k]), scheme_names[s], e[s].mean, e[s].max);
            free(n);
        }
        for (int s = RESURF_NORMALS_INVERSE_AREA; s <= RESURF_NORMALS_ANGLE; ++s)
            ck_assert_msg(e[RESURF_NORMALS_JET].mean < e[s].mean, "%s: jet %g° not below %s %g°",
                          shape_name(kinds[k]), e[RESURF_NORMALS_JET].mean, scheme_names[s], e[s].mean);
        if (kinds[k] == SHAPE_SPHERE)
            ck_assert_msg(e[RESURF_NORMALS_MAX].max < 1e-10, "max on a sphere: %g°", e[RESURF_NORMALS_MAX].max);
        else
            ck_assert_msg(e[RESURF_NORMALS_JET].mean < e[RESURF_NORMALS_MAX].mean, "%s: jet %g° not below max %g°",
                          shape_name(kinds[k]), e[RESURF_NORMALS_JET].mean, e[RESURF_NORMALS_MAX].mean);
        resurf_mesh_free(m);
    }
}
END_TEST

/* The estimates converge: halving the edge length shrinks the jet's error about fourfold (second order) on the
 * irregular torus, the 1-ring schemes' only about twofold (first order). */
START_TEST(jet_converges_faster)
{
    error_stats coarse[RESURF_NORMALS_COUNT], fine[RESURF_NORMALS_COUNT];
    resurf_mesh *a = shape_mesh(SHAPE_TORUS, 4000, 0.3, 5, 1), *b = shape_mesh(SHAPE_TORUS, 16000, 0.3, 5, 1);
    ck_assert(a && b);
    for (int s = 0; s < RESURF_NORMALS_COUNT; ++s) {
        double *n = normals_of(a, (resurf_normal_scheme)s);
        coarse[s] = normal_errors(a, n);
        free(n);
        n = normals_of(b, (resurf_normal_scheme)s);
        fine[s] = normal_errors(b, n);
        free(n);
    }
    printf("normals: torus mean error, 4000 -> 16000 triangles (ratio)\n");
    for (int s = 0; s < RESURF_NORMALS_COUNT; ++s)
        printf("  %-14s %8.4f -> %8.4f  (%.2f)\n", scheme_names[s], coarse[s].mean, fine[s].mean,
               coarse[s].mean / fine[s].mean);
    ck_assert(coarse[RESURF_NORMALS_JET].mean / fine[RESURF_NORMALS_JET].mean > 3.0);
    ck_assert(coarse[RESURF_NORMALS_INVERSE_AREA].mean / fine[RESURF_NORMALS_INVERSE_AREA].mean < 3.0);
    resurf_mesh_free(a);
    resurf_mesh_free(b);
}
END_TEST

/*   4 (0,0,2)
 *   3 (0,0,1)       face (0,3,4) is a segment standing on vertex 0: zero area, no contribution
 *   0-----1         face (0,1,2) in z = 0; vertex 5 is in no face
 *    \   /
 *     2            */
START_TEST(degenerate_faces_and_isolated_vertices)
{
    const double pos[] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0, 0, 1, 0, 0, 2, 5, 5, 5};
    const uint32_t idx[] = {0, 1, 2, 0, 3, 4, 1, 1, 2, 7, 0, 1};
    for (int s = 0; s < RESURF_NORMALS_COUNT; ++s) {
        double n[18];
        memset(n, 0x7f, sizeof n); /* every output is written */
        ck_assert_int_eq(resurfi_vertex_normals(NULL, pos, 6, idx, 4, (resurf_normal_scheme)s, n), RESURF_OK);
        for (int v = 0; v < 3; ++v)
            ck_assert(n[3 * v] == 0 && n[3 * v + 1] == 0 && n[3 * v + 2] == 1);
        for (int v = 3; v < 6; ++v)
            ck_assert(n[3 * v] == 0 && n[3 * v + 1] == 0 && n[3 * v + 2] == 0);
    }
}
END_TEST

/* Fewer than 6 neighbours in the 2-ring (a tetrahedron has 3): the jet keeps the angle-weighted normal. */
START_TEST(jet_falls_back_on_small_rings)
{
    resurf_mesh *m = tu_tetrahedron();
    ck_assert_ptr_nonnull(m);
    double *jet = normals_of(m, RESURF_NORMALS_JET), *angle = normals_of(m, RESURF_NORMALS_ANGLE);
    ck_assert(memcmp(jet, angle, 3 * m->vertex_count * sizeof *jet) == 0);
    for (size_t v = 0; v < m->vertex_count; ++v) /* a regular tetrahedron about its centre: normals point outwards */
        ck_assert_double_eq_tol(v3_dot(v3_load(jet + 3 * v), v3_normalize(resurfi_position(m, (uint32_t)v))), 1.0,
                                1e-12);
    free(jet);
    free(angle);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(flipped_orientation_flips_normals)
{
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 3000, 0.3, 9, 0);
    ck_assert_ptr_nonnull(m);
    for (int s = 0; s < RESURF_NORMALS_COUNT; ++s) {
        double *a = normals_of(m, (resurf_normal_scheme)s);
        for (size_t t = 0; t < m->triangle_count; ++t) {
            uint32_t x = m->indices[3 * t + 1];
            m->indices[3 * t + 1] = m->indices[3 * t + 2], m->indices[3 * t + 2] = x;
        }
        double *b = normals_of(m, (resurf_normal_scheme)s);
        for (size_t t = 0; t < m->triangle_count; ++t) { /* back */
            uint32_t x = m->indices[3 * t + 1];
            m->indices[3 * t + 1] = m->indices[3 * t + 2], m->indices[3 * t + 2] = x;
        }
        for (size_t v = 0; v < m->vertex_count; ++v)
            ck_assert_msg(v3_dist(v3_load(a + 3 * v), v3_neg(v3_load(b + 3 * v))) < 1e-12, "%s", scheme_names[s]);
        free(a);
        free(b);
    }
    resurf_mesh_free(m);
}
END_TEST

START_TEST(rejects_bad_arguments)
{
    resurf_mesh *m = tu_tetrahedron();
    double n[12];
    ck_assert_int_eq(resurfi_vertex_normals(NULL, m->positions, 4, m->indices, 4, RESURF_NORMALS_COUNT, n),
                     RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurfi_vertex_normals(NULL, m->positions, 4, m->indices, 4, RESURF_NORMALS_AREA, NULL),
                     RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurfi_vertex_normals(NULL, m->positions, 4, NULL, 4, RESURF_NORMALS_AREA, n),
                     RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurfi_vertex_normals(NULL, NULL, 0, NULL, 0, RESURF_NORMALS_JET, NULL), RESURF_OK);
    resurf_mesh_free(m);
}
END_TEST

/* Vertices that split positions (as the restorer splits them along creases): reading the positions through the
 * triangles gives bit for bit the normals of the mesh whose positions are copied per vertex, degenerate faces with
 * a repeated position but distinct vertices included. */
START_TEST(split_vertices_match_copied_positions)
{
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 3000, 0.3, 5, 0);
    ck_assert_ptr_nonnull(m);
    size_t nt = m->triangle_count + 1, nv = m->vertex_count, ns = 2 * nv;
    uint32_t *tris = malloc(3 * nt * sizeof *tris), *split = malloc(3 * nt * sizeof *split);
    double *copied = malloc(3 * ns * sizeof *copied), *a = malloc(3 * ns * sizeof *a), *b = malloc(3 * ns * sizeof *b);
    ck_assert(tris && split && copied && a && b);
    memcpy(tris, m->indices, 3 * m->triangle_count * sizeof *tris);
    tris[3 * nt - 3] = 0, tris[3 * nt - 2] = 0, tris[3 * nt - 1] = 1; /* a repeated position */
    for (size_t i = 0; i < 3 * nt; ++i) /* vertex 2v or 2v + 1 of position v: by the triangle's parity */
        split[i] = 2 * tris[i] + (uint32_t)((i / 3) % 2);
    split[3 * nt - 2] ^= 1; /* distinct vertices on the repeated position */
    for (size_t v = 0; v < ns; ++v)
        memcpy(copied + 3 * v, m->positions + 3 * (v / 2), 3 * sizeof(double));
    for (int sc = 0; sc < RESURF_NORMALS_COUNT; ++sc) {
        resurf_normal_scheme scheme = (resurf_normal_scheme)sc;
        if (scheme == RESURF_NORMALS_JET) {
            ck_assert_int_eq(resurfi_vertex_normals_split(m->positions, tris, split, ns, nt, scheme, b),
                             RESURF_ERR_INVALID_ARGUMENT);
            continue;
        }
        ck_assert_int_eq(resurfi_vertex_normals(NULL, copied, ns, split, nt, scheme, a), RESURF_OK);
        ck_assert_int_eq(resurfi_vertex_normals_split(m->positions, tris, split, ns, nt, scheme, b), RESURF_OK);
        ck_assert_msg(memcmp(a, b, 3 * ns * sizeof *a) == 0, "%s: split normals differ", scheme_names[sc]);
    }
    free(tris), free(split), free(copied), free(a), free(b);
    resurf_mesh_free(m);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("normals");
    TCase *tc = tcase_create("normals");
    tcase_add_test(tc, plane_gives_exact_up);
    tcase_add_test(tc, max_exact_on_spherical_one_ring);
    tcase_add_test(tc, accuracy_on_irregular_meshes);
    tcase_add_test(tc, jet_converges_faster);
    tcase_add_test(tc, degenerate_faces_and_isolated_vertices);
    tcase_add_test(tc, jet_falls_back_on_small_rings);
    tcase_add_test(tc, flipped_orientation_flips_normals);
    tcase_add_test(tc, rejects_bad_arguments);
    tcase_add_test(tc, split_vertices_match_copied_positions);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
