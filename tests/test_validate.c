/* src/validate.c: every field of resurf_validate_report against hand-counted meshes. */
#include <string.h>

#include "testutil.h"

static resurf_validate_report validate(const resurf_mesh *m)
{
    resurf_validate_report v;
    memset(&v, 0xab, sizeof v); /* every field must be written */
    resurf_error error;
    ck_assert_int_eq(resurf_mesh_validate(m, &v, &error), RESURF_OK);
    ck_assert_int_eq(error.status, RESURF_OK);
    return v;
}

/* Everything that a clean mesh has at zero / -1. */
static void assert_clean(const resurf_validate_report *v)
{
    ck_assert_uint_eq(v->nonfinite_vertices, 0);
    ck_assert_uint_eq(v->nonfinite_positions, 0);
    ck_assert_uint_eq(v->out_of_range_indices, 0);
    ck_assert_uint_eq(v->degenerate_triangles, 0);
    ck_assert_uint_eq(v->zero_area_triangles, 0);
    ck_assert_uint_eq(v->nonmanifold_edges, 0);
    ck_assert_uint_eq(v->nonmanifold_vertices, 0);
    ck_assert_uint_eq(v->inconsistent_edges, 0);
    ck_assert_uint_eq(v->unreferenced_vertices, 0);
    ck_assert_int_eq(v->first_nonfinite_vertex, -1);
    ck_assert_int_eq(v->first_out_of_range_triangle, -1);
    ck_assert_int_eq(v->first_degenerate_triangle, -1);
    ck_assert_int_eq(v->first_zero_area_triangle, -1);
    ck_assert_int_eq(v->first_nonmanifold_edge_vertex, -1);
    ck_assert_int_eq(v->first_inconsistent_triangle, -1);
    ck_assert_int_eq(resurf_validation_ok(v), 1);
}

START_TEST(validate_closed_tetrahedron_and_cube)
{
    resurf_mesh *m = tu_tetrahedron();
    resurf_validate_report v = validate(m);
    assert_clean(&v);
    ck_assert_uint_eq(v.vertex_count, 4);
    ck_assert_uint_eq(v.triangle_count, 4);
    ck_assert_uint_eq(v.position_count, 4);
    ck_assert_uint_eq(v.boundary_edges, 0);
    ck_assert_uint_eq(v.boundary_loops, 0);
    ck_assert_uint_eq(v.components, 1);
    resurf_mesh_free(m);

    m = tu_cube();
    v = validate(m);
    assert_clean(&v);
    ck_assert_uint_eq(v.vertex_count, 8);
    ck_assert_uint_eq(v.position_count, 8);
    ck_assert_uint_eq(v.boundary_edges, 0);
    ck_assert_uint_eq(v.boundary_loops, 0);
    ck_assert_uint_eq(v.components, 1);
    resurf_mesh_free(m);
}
END_TEST

/* An n×n grid: 4n boundary edges on one loop. */
START_TEST(validate_open_grid)
{
    for (unsigned n = 1; n <= 7; n += 3) {
        resurf_mesh *m = tu_grid(n);
        resurf_validate_report v = validate(m);
        assert_clean(&v);
        ck_assert_uint_eq(v.boundary_edges, 4 * n);
        ck_assert_uint_eq(v.boundary_loops, 1);
        ck_assert_uint_eq(v.components, 1);
        ck_assert_uint_eq(v.position_count, (n + 1) * (n + 1));
        resurf_mesh_free(m);
    }
}
END_TEST

/* 0-1-2 and 3-4-5 apart: two components, two loops, six boundary edges. */
START_TEST(validate_two_disjoint_triangles)
{
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 0, 0, 6, 0, 0, 5, 1, 0};
    const uint32_t t[] = {0, 1, 2, 3, 4, 5};
    resurf_mesh *m = tu_mesh(p, 6, t, 2);
    resurf_validate_report v = validate(m);
    assert_clean(&v);
    ck_assert_uint_eq(v.components, 2);
    ck_assert_uint_eq(v.boundary_loops, 2);
    ck_assert_uint_eq(v.boundary_edges, 6);
    resurf_mesh_free(m);
}
END_TEST

/* Three fins (0,1,2) (1,0,3) (0,1,4) on hinge (0,1), drawn in test_adjacency.c: one non-manifold edge, its two
 * ends non-manifold. */
START_TEST(validate_nonmanifold_edge)
{
    const double p[] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1};
    const uint32_t t[] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    resurf_mesh *m = tu_mesh(p, 5, t, 3);
    resurf_validate_report v = validate(m);
    ck_assert_uint_eq(v.nonmanifold_edges, 1);
    ck_assert_uint_eq(v.nonmanifold_vertices, 2);
    ck_assert_int_eq(v.first_nonmanifold_edge_vertex, 0);
    ck_assert_uint_eq(v.boundary_edges, 6);
    ck_assert_uint_eq(v.components, 1);
    ck_assert_uint_eq(v.inconsistent_edges, 0); /* a non-manifold edge is not an orientation flip */
    ck_assert_int_eq(resurf_validation_ok(&v), 1);
    resurf_mesh_free(m);
}
END_TEST

/* A bow-tie at vertex 2 (drawn in test_adjacency.c): no non-manifold edge, one non-manifold vertex, vertex 2. */
START_TEST(validate_bowtie_vertex)
{
    const double p[] = {-1, 1, 0, -1, -1, 0, 0, 0, 0, 1, 1, 0, 1, -1, 0};
    const uint32_t t[] = {0, 1, 2, 2, 3, 4};
    resurf_mesh *m = tu_mesh(p, 5, t, 2);
    resurf_validate_report v = validate(m);
    ck_assert_uint_eq(v.nonmanifold_edges, 0);
    ck_assert_uint_eq(v.nonmanifold_vertices, 1);
    ck_assert_int_eq(v.first_nonmanifold_edge_vertex, 2);
    ck_assert_uint_eq(v.components, 1);
    ck_assert_uint_eq(v.boundary_loops, 2);
    ck_assert_uint_eq(v.boundary_edges, 6);
    resurf_mesh_free(m);
}
END_TEST

/* The tetrahedron with face 0 = (0,1,2) turned into (0,2,1): its three edges now run the same way as in their
 * other face. The example is the lowest triangle on an inconsistent edge: 0. */
START_TEST(validate_flipped_triangle)
{
    resurf_mesh *m = tu_tetrahedron();
    uint32_t tmp = m->indices[1];
    m->indices[1] = m->indices[2];
    m->indices[2] = tmp;
    resurf_validate_report v = validate(m);
    ck_assert_uint_eq(v.inconsistent_edges, 3);
    ck_assert_int_eq(v.first_inconsistent_triangle, 0);
    ck_assert_uint_eq(v.boundary_edges, 0);
    ck_assert_uint_eq(v.nonmanifold_edges, 0);
    resurf_mesh_free(m);

    /* The 2×2 grid (vertex 3·j + i), triangle 4 = (3,4,7) flipped to (3,7,4):
     *
     *   6---7---8        T0 (0,1,4)  T1 (0,4,3)  T2 (1,2,5)  T3 (1,5,4)
     *   | 5/|7 /|        T4 (3,4,7)  T5 (3,7,6)  T6 (4,5,8)  T7 (4,8,7)
     *   |/4 |/6 |
     *   3---4---5        its edges (3,4), (4,7), (3,7) are shared with T1, T7, T5: three inconsistent edges whose
     *   | 1/|3 /|        lowest triangle is T1.
     *   |/0 |/2 |
     *   0---1---2
     */
    m = tu_grid(2);
    tmp = m->indices[3 * 4 + 1];
    m->indices[3 * 4 + 1] = m->indices[3 * 4 + 2];
    m->indices[3 * 4 + 2] = tmp;
    v = validate(m);
    ck_assert_uint_eq(v.inconsistent_edges, 3);
    ck_assert_int_eq(v.first_inconsistent_triangle, 1);
    resurf_mesh_free(m);
}
END_TEST

/* NaN and infinite coordinates: counted, named, and the mesh is not ok; non-finite attributes are counted but do
 * not stop processing. The diagonal ignores the infinite corner, so no finite triangle looks like zero area. */
START_TEST(validate_nonfinite)
{
    resurf_mesh *m = tu_tetrahedron();
    m->positions[3 * 2 + 1] = NAN;
    resurf_validate_report v = validate(m);
    ck_assert_uint_eq(v.nonfinite_vertices, 1);
    ck_assert_uint_eq(v.nonfinite_positions, 1);
    ck_assert_int_eq(v.first_nonfinite_vertex, 2);
    ck_assert_int_eq(resurf_validation_ok(&v), 0);
    ck_assert_uint_eq(v.boundary_edges, 0); /* topology still counted */
    ck_assert_uint_eq(v.zero_area_triangles, 0);
    m->positions[3 * 2 + 1] = 1;
    m->positions[3 * 3 + 0] = -INFINITY;
    v = validate(m);
    ck_assert_uint_eq(v.nonfinite_positions, 1);
    ck_assert_int_eq(v.first_nonfinite_vertex, 3);
    ck_assert_uint_eq(v.zero_area_triangles, 0);
    resurf_mesh_free(m);

    /* A NaN normal on vertex 1 and an infinite extra on vertex 3 only. */
    m = NULL;
    ck_assert_int_eq(resurf_mesh_create(4, 0, RESURF_ATTR_NORMALS, &m, NULL), RESURF_OK);
    resurf_attribute *extra = NULL;
    ck_assert_int_eq(resurf_mesh_add_extra(m, "weight", 2, &extra, NULL), RESURF_OK);
    m->normals[3 * 1 + 2] = NAN;
    extra->data[2 * 3 + 1] = INFINITY;
    v = validate(m);
    ck_assert_uint_eq(v.nonfinite_vertices, 2);
    ck_assert_uint_eq(v.nonfinite_positions, 0);
    ck_assert_int_eq(v.first_nonfinite_vertex, 1);
    ck_assert_int_eq(resurf_validation_ok(&v), 1);
    ck_assert_uint_eq(v.unreferenced_vertices, 4);
    resurf_mesh_free(m);
}
END_TEST

/* Face 1 of the tetrahedron points at vertex 7 of 4: one out-of-range index, the mesh is not ok, and the
 * topology skips that face, leaving a triangular hole (3 boundary edges, 1 loop). */
START_TEST(validate_out_of_range)
{
    resurf_mesh *m = tu_tetrahedron();
    m->indices[3 * 1 + 2] = 7;
    resurf_validate_report v = validate(m);
    ck_assert_uint_eq(v.out_of_range_indices, 1);
    ck_assert_int_eq(v.first_out_of_range_triangle, 1);
    ck_assert_int_eq(resurf_validation_ok(&v), 0);
    ck_assert_uint_eq(v.boundary_edges, 3);
    ck_assert_uint_eq(v.boundary_loops, 1);
    ck_assert_uint_eq(v.components, 1);
    ck_assert_uint_eq(v.unreferenced_vertices, 0);
    m->indices[3 * 2 + 0] = UINT32_MAX;
    m->indices[3 * 2 + 1] = 4;
    v = validate(m);
    ck_assert_uint_eq(v.out_of_range_indices, 3);
    ck_assert_int_eq(v.first_out_of_range_triangle, 1);
    resurf_mesh_free(m);
}
END_TEST

/* Degenerate triangles: T1 repeats index 0; T2 uses vertex 4, a copy of vertex 0's position (so it is
 * degenerate after welding). T0 is fine.
 *
 *   2
 *   | \
 *   |  \         T0 = (0,1,2), T1 = (0,0,1), T2 = (4,1,0) with 4 at 0's place
 *   0=4-1
 */
START_TEST(validate_degenerate)
{
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0};
    const uint32_t t[] = {0, 1, 2, 0, 0, 1, 4, 1, 0};
    resurf_mesh *m = tu_mesh(p, 5, t, 3);
    resurf_validate_report v = validate(m);
    ck_assert_uint_eq(v.degenerate_triangles, 2);
    ck_assert_int_eq(v.first_degenerate_triangle, 1);
    ck_assert_uint_eq(v.zero_area_triangles, 0); /* degenerate ones are not also zero-area */
    ck_assert_uint_eq(v.position_count, 3);      /* vertices 3 and 4 share vertex 0's position */
    ck_assert_uint_eq(v.unreferenced_vertices, 1);
    ck_assert_uint_eq(v.boundary_edges, 3); /* only T0 has edges */
    ck_assert_uint_eq(v.components, 1);
    ck_assert_int_eq(resurf_validation_ok(&v), 1);
    resurf_mesh_free(m);
}
END_TEST

/* Zero area. The corners span [0,2]×[0,1]: diagonal √5, so the limit is |(b−a)×(c−a)| ≤ 5e-14.
 *
 *   2
 *   |  \              T0 = (0,1,2) fine; T1 = (0,1,3) collinear (cross 0, counted);
 *   |     \           T2 = (0,1,4), 4 = (0.5, 1e-14): cross 1e-14, counted;
 *   0---4---1---3     T3 = (0,1,5), 5 = (0.5, 1e-13): cross 1e-13 > 5e-14, not counted.
 */
START_TEST(validate_zero_area)
{
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 0.5, 1e-14, 0, 0.5, 1e-13, 0};
    const uint32_t t[] = {0, 1, 2, 0, 1, 3, 0, 1, 4, 0, 1, 5};
    resurf_mesh *m = tu_mesh(p, 6, t, 4);
    resurf_validate_report v = validate(m);
    ck_assert_uint_eq(v.zero_area_triangles, 2);
    ck_assert_int_eq(v.first_zero_area_triangle, 1);
    ck_assert_uint_eq(v.degenerate_triangles, 0);
    ck_assert_uint_eq(v.nonmanifold_edges, 1); /* (0,1) carries all four */
    ck_assert_int_eq(resurf_validation_ok(&v), 1);
    resurf_mesh_free(m);
}
END_TEST

/* The tetrahedron plus two vertices no face uses. */
START_TEST(validate_unreferenced)
{
    const double p[] = {1, 1, 1, 1, -1, -1, 9, 9, 9, -1, 1, -1, -1, -1, 1, 8, 8, 8};
    const uint32_t t[] = {0, 1, 3, 0, 3, 4, 0, 4, 1, 1, 4, 3};
    resurf_mesh *m = tu_mesh(p, 6, t, 4);
    resurf_validate_report v = validate(m);
    ck_assert_uint_eq(v.unreferenced_vertices, 2);
    ck_assert_uint_eq(v.position_count, 6);
    ck_assert_uint_eq(v.boundary_edges, 0);
    ck_assert_uint_eq(v.components, 1);
    ck_assert_int_eq(resurf_validation_ok(&v), 1);
    resurf_mesh_free(m);
}
END_TEST

/* A texture seam: the tetrahedron's vertex 0 is split into 0 and 4 (same position, other texcoords), faces 1 and 2
 * use the copy. Over welded positions the mesh is still closed: no boundary. */
START_TEST(validate_seam_is_not_a_boundary)
{
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(5, 4, RESURF_ATTR_TEXCOORD0, &m, NULL), RESURF_OK);
    const double p[] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1, 1, 1, 1};
    const uint32_t t[] = {0, 1, 2, 4, 2, 3, 4, 3, 1, 1, 3, 2};
    memcpy(m->positions, p, sizeof p);
    memcpy(m->indices, t, sizeof t);
    m->texcoords[0][2 * 4] = 0.5;
    resurf_validate_report v = validate(m);
    assert_clean(&v);
    ck_assert_uint_eq(v.vertex_count, 5);
    ck_assert_uint_eq(v.position_count, 4);
    ck_assert_uint_eq(v.boundary_edges, 0);
    ck_assert_uint_eq(v.components, 1);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(validate_empty_and_null)
{
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(0, 0, 0, &m, NULL), RESURF_OK);
    resurf_validate_report v = validate(m);
    assert_clean(&v);
    ck_assert_uint_eq(v.vertex_count, 0);
    ck_assert_uint_eq(v.components, 0);
    ck_assert_uint_eq(v.boundary_loops, 0);
    resurf_error error;
    ck_assert_int_eq(resurf_mesh_validate(NULL, &v, &error), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(error.status, RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurf_mesh_validate(m, NULL, NULL), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurf_validation_ok(NULL), 0);
    resurf_mesh_free(m);
}
END_TEST

/* The analytic torus: clean, closed, consistently oriented, one component. */
START_TEST(validate_torus)
{
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 20000, 0.3, 4, 0);
    ck_assert_ptr_nonnull(m);
    resurf_validate_report v = validate(m);
    assert_clean(&v);
    ck_assert_uint_eq(v.position_count, m->vertex_count);
    ck_assert_uint_eq(v.boundary_edges, 0);
    ck_assert_uint_eq(v.boundary_loops, 0);
    ck_assert_uint_eq(v.components, 1);
    resurf_mesh_free(m);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("validate");
    TCase *tc = tcase_create("validate");
    tcase_add_test(tc, validate_closed_tetrahedron_and_cube);
    tcase_add_test(tc, validate_open_grid);
    tcase_add_test(tc, validate_two_disjoint_triangles);
    tcase_add_test(tc, validate_nonmanifold_edge);
    tcase_add_test(tc, validate_bowtie_vertex);
    tcase_add_test(tc, validate_flipped_triangle);
    tcase_add_test(tc, validate_nonfinite);
    tcase_add_test(tc, validate_out_of_range);
    tcase_add_test(tc, validate_degenerate);
    tcase_add_test(tc, validate_zero_area);
    tcase_add_test(tc, validate_unreferenced);
    tcase_add_test(tc, validate_seam_is_not_a_boundary);
    tcase_add_test(tc, validate_empty_and_null);
    tcase_add_test(tc, validate_torus);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
