/* src/mesh.c: creation, deep copies, extra attributes, bounds and the checked allocation helpers. */
#include <string.h>

#include "testutil.h"

START_TEST(mesh_create_allocates_what_is_asked)
{
    resurf_mesh *m = NULL;
    resurf_error error;
    unsigned attrs = RESURF_ATTR_NORMALS | RESURF_ATTR_COLORS | (RESURF_ATTR_TEXCOORD0 << 1);
    ck_assert_int_eq(resurf_mesh_create(5, 3, attrs, &m, &error), RESURF_OK);
    ck_assert_uint_eq(m->vertex_count, 5);
    ck_assert_uint_eq(m->triangle_count, 3);
    for (size_t i = 0; i < 15; ++i)
        ck_assert_double_eq(m->positions[i], 0);
    for (size_t i = 0; i < 9; ++i)
        ck_assert_uint_eq(m->indices[i], 0);
    ck_assert_ptr_nonnull(m->normals);
    ck_assert_ptr_nonnull(m->colors);
    ck_assert_uint_eq(m->color_components, 4);
    ck_assert_ptr_null(m->texcoords[0]);
    ck_assert_ptr_nonnull(m->texcoords[1]);
    ck_assert_ptr_null(m->texcoords[2]);
    ck_assert_uint_eq(m->texcoord_count, 2);
    ck_assert_uint_eq(m->extra_count, 0);
    ck_assert_ptr_null(m->triangle_groups);
    for (size_t i = 0; i < 10; ++i)
        ck_assert_double_eq(m->texcoords[1][i], 0);
    resurf_mesh_free(m);

    ck_assert_int_eq(resurf_mesh_create(0, 0, 0, &m, NULL), RESURF_OK);
    ck_assert_ptr_nonnull(m);
    ck_assert_ptr_null(m->normals);
    ck_assert_uint_eq(m->texcoord_count, 0);
    resurf_mesh_free(m);
}
END_TEST

/* Counts that do not fit 32-bit indices are refused, with no mesh returned. */
START_TEST(mesh_create_refuses_counts_over_uint32)
{
#if SIZE_MAX > UINT32_MAX
    resurf_mesh *m = (resurf_mesh *)&m; /* must be reset to NULL */
    resurf_error error;
    ck_assert_int_eq(resurf_mesh_create((size_t)UINT32_MAX + 1, 0, 0, &m, &error), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(m);
    ck_assert_int_eq(error.status, RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_uint_gt(strlen(error.message), 0);
    ck_assert_int_eq(resurf_mesh_create(3, (size_t)UINT32_MAX + 1, 0, &m, NULL), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(m);
#endif
    ck_assert_int_eq(resurf_mesh_create(3, 1, 0, NULL, NULL), RESURF_ERR_INVALID_ARGUMENT);
}
END_TEST

START_TEST(mesh_free_null)
{
    resurf_mesh_free(NULL);
}
END_TEST

/* A clone equals the original field by field, owns fresh copies, and does not change when the original does. */
START_TEST(mesh_clone_is_deep)
{
    resurf_mesh *m = NULL;
    unsigned attrs = RESURF_ATTR_NORMALS | RESURF_ATTR_COLORS | RESURF_ATTR_TEXCOORD0;
    ck_assert_int_eq(resurf_mesh_create(3, 1, attrs, &m, NULL), RESURF_OK);
    for (size_t i = 0; i < 9; ++i)
        m->positions[i] = (double)i + 0.5, m->normals[i] = -(double)i;
    for (size_t i = 0; i < 6; ++i)
        m->texcoords[0][i] = (double)i / 8;
    for (size_t i = 0; i < 12; ++i)
        m->colors[i] = (double)i / 16;
    m->color_components = 3;
    m->indices[0] = 0, m->indices[1] = 1, m->indices[2] = 2;
    resurf_attribute *extra = NULL;
    ck_assert_int_eq(resurf_mesh_add_extra(m, "curv", 2, &extra, NULL), RESURF_OK);
    for (size_t i = 0; i < 6; ++i)
        extra->data[i] = (float)i * 1.5f;
    m->triangle_groups = malloc(sizeof(uint32_t));
    m->triangle_groups[0] = 1;
    m->group_count = 2;
    m->group_names = malloc(2 * sizeof(char *));
    m->group_names[0] = strdup("left");
    m->group_names[1] = strdup("right");

    resurf_mesh *c = NULL;
    ck_assert_int_eq(resurf_mesh_clone(m, &c, NULL), RESURF_OK);
    ck_assert_ptr_ne(c->positions, m->positions);
    ck_assert_ptr_ne(c->extras, m->extras);
    ck_assert_ptr_ne(c->extras[0].data, m->extras[0].data);
    ck_assert_ptr_ne(c->group_names[1], m->group_names[1]);
    ck_assert_uint_eq(c->vertex_count, 3);
    ck_assert_uint_eq(c->triangle_count, 1);
    ck_assert_uint_eq(c->color_components, 3);
    ck_assert_uint_eq(c->texcoord_count, 1);
    ck_assert(memcmp(c->positions, m->positions, 9 * sizeof(double)) == 0);
    ck_assert(memcmp(c->normals, m->normals, 9 * sizeof(double)) == 0);
    ck_assert(memcmp(c->texcoords[0], m->texcoords[0], 6 * sizeof(double)) == 0);
    ck_assert(memcmp(c->colors, m->colors, 12 * sizeof(double)) == 0);
    ck_assert(memcmp(c->indices, m->indices, 3 * sizeof(uint32_t)) == 0);
    ck_assert_uint_eq(c->extra_count, 1);
    ck_assert_str_eq(c->extras[0].name, "curv");
    ck_assert_uint_eq(c->extras[0].components, 2);
    ck_assert(memcmp(c->extras[0].data, extra->data, 6 * sizeof(float)) == 0);
    ck_assert_uint_eq(c->triangle_groups[0], 1);
    ck_assert_uint_eq(c->group_count, 2);
    ck_assert_str_eq(c->group_names[0], "left");
    ck_assert_str_eq(c->group_names[1], "right");

    m->positions[0] = 99;
    extra->data[0] = 99;
    m->group_names[0][0] = 'X';
    ck_assert_double_eq(c->positions[0], 0.5);
    ck_assert_float_eq(c->extras[0].data[0], 0);
    ck_assert_str_eq(c->group_names[0], "left");
    resurf_mesh_free(m);
    resurf_mesh_free(c);

    ck_assert_int_eq(resurf_mesh_clone(NULL, &c, NULL), RESURF_ERR_INVALID_ARGUMENT);
}
END_TEST

START_TEST(mesh_add_extra)
{
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(4, 0, 0, &m, NULL), RESURF_OK);
    resurf_attribute *a = NULL;
    ck_assert_int_eq(resurf_mesh_add_extra(m, "quality", 1, &a, NULL), RESURF_OK);
    ck_assert_str_eq(a->name, "quality");
    ck_assert_uint_eq(a->components, 1);
    for (int i = 0; i < 4; ++i)
        ck_assert_float_eq(a->data[i], 0);
    ck_assert_int_eq(resurf_mesh_add_extra(m, "tensor", 16, NULL, NULL), RESURF_OK);
    ck_assert_uint_eq(m->extra_count, 2);
    ck_assert_uint_eq(m->extras[1].components, 16);
    /* A name longer than the field is cut, NUL-terminated. */
    char long_name[100];
    memset(long_name, 'n', sizeof long_name - 1);
    long_name[99] = 0;
    ck_assert_int_eq(resurf_mesh_add_extra(m, long_name, 3, &a, NULL), RESURF_OK);
    ck_assert_uint_eq(strlen(a->name), sizeof a->name - 1);
    resurf_error error;
    ck_assert_int_eq(resurf_mesh_add_extra(m, "zero", 0, NULL, &error), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(error.status, RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurf_mesh_add_extra(m, "many", 17, NULL, NULL), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurf_mesh_add_extra(m, NULL, 2, NULL, NULL), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurf_mesh_add_extra(NULL, "x", 2, NULL, NULL), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_uint_eq(m->extra_count, 3);
    resurf_mesh_free(m);
}
END_TEST

/* The tetrahedron spans [−1,1]³: diagonal 2√3. Unreferenced and out-of-range vertices do not count while some
 * triangle refers to a vertex; without triangles every vertex counts; an empty mesh gives zeros. */
START_TEST(mesh_bounds)
{
    double lo[3], hi[3];
    resurf_mesh *m = tu_tetrahedron();
    ck_assert_double_eq_tol(resurf_mesh_bounds(m, lo, hi), 2 * sqrt(3.0), 1e-15);
    for (int a = 0; a < 3; ++a) {
        ck_assert_double_eq(lo[a], -1);
        ck_assert_double_eq(hi[a], 1);
    }
    resurf_mesh_free(m);

    const double p[] = {0, 0, 0, 3, 0, 0, 0, 4, 0, 50, 50, 50};
    const uint32_t t[] = {0, 1, 2, 0, 1, 9};
    m = tu_mesh(p, 4, t, 2);
    ck_assert_double_eq_tol(resurf_mesh_bounds(m, lo, hi), 5.0, 1e-15);
    ck_assert_double_eq(hi[0], 3);
    ck_assert_double_eq(hi[1], 4);
    m->triangle_count = 0;
    ck_assert_double_eq_tol(resurf_mesh_bounds(m, NULL, hi), sqrt(3.0) * 50, 1e-12);
    ck_assert_double_eq(hi[2], 50);
    resurf_mesh_free(m);

    ck_assert_int_eq(resurf_mesh_create(0, 0, 0, &m, NULL), RESURF_OK);
    lo[0] = hi[0] = 7;
    ck_assert_double_eq(resurf_mesh_bounds(m, lo, hi), 0);
    ck_assert_double_eq(lo[0], 0);
    ck_assert_double_eq(hi[0], 0);
    resurf_mesh_free(m);
    ck_assert_double_eq(resurf_mesh_bounds(NULL, lo, hi), 0);
}
END_TEST

/* The allocation helpers refuse a count × size that overflows, and give a valid block for a count of 0. */
START_TEST(mesh_alloc_helpers)
{
    ck_assert_ptr_null(resurfi_alloc(NULL, SIZE_MAX / 2, 4));
    ck_assert_ptr_null(resurfi_calloc(NULL, SIZE_MAX / 8 + 1, 16));
    void *p = resurfi_alloc(NULL, 0, 8);
    ck_assert_ptr_nonnull(p);
    void *q = resurfi_realloc(NULL, p, SIZE_MAX / 4, 8);
    ck_assert_ptr_null(q); /* p is still ours */
    q = resurfi_realloc(NULL, p, 4, sizeof(double));
    ck_assert_ptr_nonnull(q);
    resurfi_free(NULL, q);
    double *z = resurfi_calloc(NULL, 5, sizeof *z);
    for (int i = 0; i < 5; ++i)
        ck_assert_double_eq(z[i], 0);
    free(z); /* NULL is the C heap */
    resurfi_free(NULL, NULL);
    char *d = resurfi_strdup(NULL, "seam");
    ck_assert_str_eq(d, "seam");
    free(d);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("mesh");
    TCase *tc = tcase_create("mesh");
    tcase_add_test(tc, mesh_create_allocates_what_is_asked);
    tcase_add_test(tc, mesh_create_refuses_counts_over_uint32);
    tcase_add_test(tc, mesh_free_null);
    tcase_add_test(tc, mesh_clone_is_deep);
    tcase_add_test(tc, mesh_add_extra);
    tcase_add_test(tc, mesh_bounds);
    tcase_add_test(tc, mesh_alloc_helpers);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
