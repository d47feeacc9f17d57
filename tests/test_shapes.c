/* tools/shapes.c: the analytic meshes that every accuracy test relies on must be exactly what they claim. */
#include <stdio.h>
#include <string.h>

#include "testutil.h"

/* Every vertex on the surface to double rounding, and the exact normals unit length and orthogonal to the mesh. */
START_TEST(shapes_vertices_lie_on_surface)
{
    for (int k = 0; k < SHAPE_COUNT; ++k) {
        resurf_mesh *m = shape_mesh((shape_kind)k, 5000, 0.4, 7, 1);
        ck_assert_ptr_nonnull(m);
        ck_assert_uint_ge(m->triangle_count, 4000);
        ck_assert_uint_le(m->triangle_count, 6000);
        double worst = 0;
        for (size_t v = 0; v < m->vertex_count; ++v) {
            double d = shape_distance((shape_kind)k, m->positions + 3 * v);
            worst = d > worst ? d : worst;
            vec3 n = v3_load(m->normals + 3 * v);
            ck_assert_double_eq_tol(v3_len(n), 1.0, 1e-12);
        }
        ck_assert_msg(worst < 4e-15, "%s: vertex off the surface by %g", shape_name((shape_kind)k), worst);
        resurf_mesh_free(m);
    }
}
END_TEST

/* Closed shapes are watertight: every directed edge appears once and its reverse once (so also consistently
 * oriented); Euler characteristic 2 for the sphere, 0 for the torus. */
static void check_closed(shape_kind kind, long euler)
{
    resurf_mesh *m = shape_mesh(kind, 3000, 0.3, 3, 0);
    size_t nt = m->triangle_count, nv = m->vertex_count;
    size_t matched = 0;
    /* O(n²) over a few thousand triangles is fine and independent of the library's adjacency code. */
    for (size_t t = 0; t < nt; ++t)
        for (int i = 0; i < 3; ++i) {
            uint32_t a = m->indices[3 * t + i], b = m->indices[3 * t + (i + 1) % 3];
            int reverse = 0, same = 0;
            for (size_t u = 0; u < nt; ++u)
                for (int j = 0; j < 3; ++j) {
                    uint32_t c = m->indices[3 * u + j], d = m->indices[3 * u + (j + 1) % 3];
                    reverse += (c == b && d == a);
                    same += (c == a && d == b);
                }
            ck_assert_int_eq(reverse, 1);
            ck_assert_int_eq(same, 1);
            ++matched;
        }
    long edges = (long)matched / 2;
    ck_assert_int_eq((long)nv - edges + (long)nt, euler);
    resurf_mesh_free(m);
}

START_TEST(shapes_sphere_and_torus_are_closed)
{
    check_closed(SHAPE_SPHERE, 2);
    check_closed(SHAPE_TORUS, 0);
}
END_TEST

/* Faces point outward: on the sphere every face normal points away from the centre. */
START_TEST(shapes_orientation_outward)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 2000, 0.4, 5, 0);
    for (size_t t = 0; t < m->triangle_count; ++t) {
        vec3 a = resurfi_position(m, m->indices[3 * t]), b = resurfi_position(m, m->indices[3 * t + 1]),
             c = resurfi_position(m, m->indices[3 * t + 2]);
        vec3 n = v3_tri_cross(a, b, c);
        ck_assert(v3_dot(n, v3_add(v3_add(a, b), c)) > 0);
    }
    resurf_mesh_free(m);
    m = shape_mesh(SHAPE_CUBIC, 2000, 0.4, 5, 0);
    for (size_t t = 0; t < m->triangle_count; ++t) {
        vec3 a = resurfi_position(m, m->indices[3 * t]), b = resurfi_position(m, m->indices[3 * t + 1]),
             c = resurfi_position(m, m->indices[3 * t + 2]);
        ck_assert(v3_tri_cross(a, b, c).z > 0);
    }
    resurf_mesh_free(m);
}
END_TEST

/* Distances against hand-computed values. */
START_TEST(shapes_distance_hand_cases)
{
    double p[3] = {0, 0, 2};
    ck_assert_double_eq_tol(shape_distance(SHAPE_SPHERE, p), 1.0, 1e-15);
    double q[3] = {1.0, 0, 0.5}; /* torus tube centre (1,0,0), r = 0.4 */
    ck_assert_double_eq_tol(shape_distance(SHAPE_TORUS, q), 0.1, 1e-15);
    /* 0.01 along the exact normal of z = 0.5 x³ at x = 0.5 (slope 0.375, curvature radius ≈ 1): distance 0.01. */
    double l = sqrt(1 + 0.375 * 0.375);
    double c[3] = {0.5 - 0.01 * 0.375 / l, 0, 0.0625 + 0.01 / l};
    ck_assert_double_eq_tol(shape_distance(SHAPE_CUBIC, c), 0.01, 1e-15);
    /* Above the saddle's centre at height 1 the closest points are (±1/√2, 0, 1/2): g = x⁴ − x² + 1, min 3/4. */
    double s[3] = {0, 0, 1};
    double cl[3];
    shape_closest(SHAPE_SADDLE, s, cl);
    ck_assert_double_eq_tol(shape_distance(SHAPE_SADDLE, s), sqrt(0.75), 1e-12);
    ck_assert_double_eq_tol(fabs(cl[0]), sqrt(0.5), 1e-8);
    ck_assert_double_eq_tol(cl[2], cl[0] * cl[0] - cl[1] * cl[1], 1e-15);
    double z[3] = {2, 0, 0.5}; /* cylinder: radial 1, inside the height */
    ck_assert_double_eq_tol(shape_distance(SHAPE_CYLINDER, z), 1.0, 1e-15);
    double w[3] = {0.3, -0.2, -0.7};
    ck_assert_double_eq_tol(shape_distance(SHAPE_PLANE, w), 0.7, 1e-15);
}
END_TEST

/* The generator is deterministic for a seed and differs between seeds. */
START_TEST(shapes_deterministic)
{
    resurf_mesh *a = shape_mesh(SHAPE_TORUS, 1000, 0.3, 11, 0), *b = shape_mesh(SHAPE_TORUS, 1000, 0.3, 11, 0),
                *c = shape_mesh(SHAPE_TORUS, 1000, 0.3, 12, 0);
    ck_assert_uint_eq(a->vertex_count, b->vertex_count);
    ck_assert_int_eq(memcmp(a->positions, b->positions, a->vertex_count * 3 * sizeof(double)), 0);
    ck_assert_int_ne(memcmp(a->positions, c->positions, a->vertex_count * 3 * sizeof(double)), 0);
    resurf_mesh_free(a);
    resurf_mesh_free(b);
    resurf_mesh_free(c);
}
END_TEST

/* The bundled meshes in data/ are exactly what tools/make-data.sh generates: same counts, same positions. */
START_TEST(shapes_bundled_data_matches_generator)
{
    static const struct {
        const char *file;
        shape_kind kind;
        size_t triangles;
    } bundled[] = {{"sphere.ply", SHAPE_SPHERE, 20000}, {"torus.ply", SHAPE_TORUS, 20000}, {"cubic.ply", SHAPE_CUBIC, 8000}};
    for (size_t i = 0; i < sizeof bundled / sizeof *bundled; ++i) {
        char path[4096];
        snprintf(path, sizeof path, "%s/data/%s", RESURF_SOURCE_DIR, bundled[i].file);
        resurf_mesh *loaded = NULL;
        resurf_error error;
        ck_assert_msg(resurf_mesh_load(path, NULL, &loaded, &error) == RESURF_OK, "%s", error.message);
        resurf_mesh *made = shape_mesh(bundled[i].kind, bundled[i].triangles, 0.35, 1, 0);
        ck_assert_uint_eq(loaded->vertex_count, made->vertex_count);
        ck_assert_uint_eq(loaded->triangle_count, made->triangle_count);
        ck_assert_int_eq(memcmp(loaded->positions, made->positions, made->vertex_count * 3 * sizeof(double)), 0);
        ck_assert_int_eq(memcmp(loaded->indices, made->indices, made->triangle_count * 3 * sizeof(uint32_t)), 0);
        resurf_mesh_free(loaded);
        resurf_mesh_free(made);
    }
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("shapes");
    TCase *tc = tcase_create("shapes");
    tcase_add_test(tc, shapes_vertices_lie_on_surface);
    tcase_add_test(tc, shapes_sphere_and_torus_are_closed);
    tcase_add_test(tc, shapes_orientation_outward);
    tcase_add_test(tc, shapes_distance_hand_cases);
    tcase_add_test(tc, shapes_deterministic);
    tcase_add_test(tc, shapes_bundled_data_matches_generator);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
