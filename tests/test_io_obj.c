/* src/io_obj.c: Wavefront OBJ. Round trips are bit-exact (17 significant digits); each index form, negative
 * indices, polygons, groups, seams (one OBJ position with several texcoords), colours and the text conventions
 * (CRLF, comments, continuations, statements resurf skips) are checked against hand-written files. */
#include <stdio.h>
#include <string.h>

#include "testutil.h"

static resurf_mesh *load_text(const char *text)
{
    resurf_mesh *m = NULL;
    resurf_error error;
    resurf_status s = resurf_mesh_load_memory(text, strlen(text), RESURF_FORMAT_OBJ, "test.obj", NULL, &m, &error);
    ck_assert_msg(s == RESURF_OK, "%s (line %lld)", error.message, error.line);
    return m;
}

/* Saves m as OBJ and loads it back. */
static resurf_mesh *round_trip(const resurf_mesh *m, char **out_text)
{
    char *dir = tu_tempdir(), *path = tu_path(dir, "m.obj");
    resurf_error error;
    ck_assert_msg(resurf_mesh_save(m, path, NULL, &error) == RESURF_OK, "%s", error.message);
    resurf_mesh *back = NULL;
    ck_assert_msg(resurf_mesh_load(path, NULL, &back, &error) == RESURF_OK, "%s", error.message);
    if (out_text)
        *out_text = tu_read_file(path, NULL);
    tu_rmtree(dir);
    free(dir), free(path);
    return back;
}

/* Random bit patterns cover every exponent (subnormals, huge values, -0.0): %.17g brings each back exactly. */
START_TEST(obj_positions_round_trip_bit_exact)
{
    uint64_t state = 99;
    const size_t nv = 3000;
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(nv, nv / 3, 0, &m, NULL), RESURF_OK);
    for (size_t i = 0; i < 3 * nv; ++i) {
        double x;
        do {
            uint64_t bits = shape_rand_u64(&state);
            memcpy(&x, &bits, sizeof x);
        } while (!isfinite(x));
        m->positions[i] = i == 5 ? -0.0 : x;
    }
    for (size_t i = 0; i < 3 * m->triangle_count; ++i)
        m->indices[i] = (uint32_t)(shape_rand_u64(&state) % nv);
    resurf_mesh *back = round_trip(m, NULL);
    ck_assert_uint_eq(back->vertex_count, nv);
    ck_assert_uint_eq(back->triangle_count, m->triangle_count);
    ck_assert_mem_eq(back->positions, m->positions, 3 * nv * sizeof(double));
    ck_assert_mem_eq(back->indices, m->indices, 3 * m->triangle_count * sizeof(uint32_t));
    ck_assert(signbit(back->positions[5]));
    ck_assert_ptr_null(back->normals);
    ck_assert_ptr_null(back->colors);
    ck_assert_ptr_null(back->triangle_groups);
    resurf_mesh_free(m);
    resurf_mesh_free(back);
}
END_TEST

/* Normals, texcoords, colours (RGB: OBJ has no alpha) and groups come back; vertex order is kept. */
START_TEST(obj_attributes_round_trip)
{
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 2000, 0.3, 5, 1);
    const size_t nv = m->vertex_count, nt = m->triangle_count;
    m->texcoords[0] = malloc(2 * nv * sizeof(double));
    m->texcoord_count = 1;
    m->colors = malloc(4 * nv * sizeof(double));
    m->color_components = 3;
    for (size_t v = 0; v < nv; ++v) {
        m->texcoords[0][2 * v] = m->positions[3 * v] / 3;
        m->texcoords[0][2 * v + 1] = m->positions[3 * v + 1] / 7;
        for (int a = 0; a < 3; ++a)
            m->colors[4 * v + a] = fabs(m->normals[3 * v + a]);
        m->colors[4 * v + 3] = 1;
    }
    m->triangle_groups = malloc(nt * sizeof(uint32_t));
    m->group_count = 3;
    m->group_names = malloc(3 * sizeof(char *));
    m->group_names[0] = strdup("inner ring");
    m->group_names[1] = strdup("outer");
    m->group_names[2] = strdup("top");
    for (size_t t = 0; t < nt; ++t)
        m->triangle_groups[t] = (uint32_t)(t / 700); /* 0, 1, 2 in runs */
    resurf_mesh *back = round_trip(m, NULL);
    ck_assert_uint_eq(back->vertex_count, nv);
    ck_assert_mem_eq(back->positions, m->positions, 3 * nv * sizeof(double));
    ck_assert_mem_eq(back->normals, m->normals, 3 * nv * sizeof(double));
    ck_assert_uint_eq(back->texcoord_count, 1);
    ck_assert_mem_eq(back->texcoords[0], m->texcoords[0], 2 * nv * sizeof(double));
    ck_assert_ptr_nonnull(back->colors);
    ck_assert_uint_eq(back->color_components, 3);
    ck_assert_mem_eq(back->colors, m->colors, 4 * nv * sizeof(double));
    ck_assert_mem_eq(back->indices, m->indices, 3 * nt * sizeof(uint32_t));
    ck_assert_uint_eq(back->group_count, 3);
    for (size_t t = 0; t < nt; ++t)
        ck_assert_str_eq(back->group_names[back->triangle_groups[t]], m->group_names[m->triangle_groups[t]]);
    resurf_mesh_free(m);
    resurf_mesh_free(back);
}
END_TEST

/* The vertex with this position, texcoord and normal (NaN = absent) exists at corner c of triangle t. */
static void check_corner(const resurf_mesh *m, size_t t, int c, const double p[3], const double *uv, const double *n)
{
    uint32_t v = m->indices[3 * t + c];
    ck_assert_mem_eq(m->positions + 3 * v, p, 3 * sizeof(double));
    static const double zero[3] = {0, 0, 0};
    ck_assert_mem_eq(m->texcoords[0] + 2 * v, uv ? uv : zero, 2 * sizeof(double));
    ck_assert_mem_eq(m->normals + 3 * v, n ? n : zero, 3 * sizeof(double));
}

/* f v, f v/vt, f v//vn, f v/vt/vn: one resurf vertex per distinct (v, vt, vn), each with the right data. */
START_TEST(obj_every_index_form)
{
    resurf_mesh *m = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                               "vt 0.5 0\nvt 1 0.5\nvt 0 1\n"
                               "vn 0 0 1\nvn 0 0 -1\n"
                               "f 1 2 3\n"
                               "f 2/2 4/1 3/3\n"
                               "f 1//1 2//1 3//2\n"
                               "f 1/1/1 2/2/1 3/3/1\n"
                               "f 1/1/1 2/2/1 3/3/1\n"); /* the same triples again: no new vertices */
    static const double p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    static const double uv[3][2] = {{0.5, 0}, {1, 0.5}, {0, 1}};
    static const double n[2][3] = {{0, 0, 1}, {0, 0, -1}};
    ck_assert_uint_eq(m->triangle_count, 5);
    ck_assert_uint_eq(m->vertex_count, 12);
    ck_assert_ptr_nonnull(m->normals);
    ck_assert_ptr_nonnull(m->texcoords[0]);
    check_corner(m, 0, 0, p[0], NULL, NULL);
    check_corner(m, 0, 2, p[2], NULL, NULL);
    check_corner(m, 1, 0, p[1], uv[1], NULL);
    check_corner(m, 1, 1, p[3], uv[0], NULL);
    check_corner(m, 1, 2, p[2], uv[2], NULL);
    check_corner(m, 2, 0, p[0], NULL, n[0]);
    check_corner(m, 2, 2, p[2], NULL, n[1]);
    check_corner(m, 3, 1, p[1], uv[1], n[0]);
    ck_assert_mem_eq(m->indices + 9, m->indices + 12, 3 * sizeof(uint32_t));
    resurf_mesh_free(m);
}
END_TEST

/* Negative indices count back from the last element defined above the face. */
START_TEST(obj_negative_indices)
{
    const char *head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvn 0 0 1\n";
    char positive[512], negative[512];
    snprintf(positive, sizeof positive, "%sf 1/1/1 2/2/1 4/2/1\nv 2 2 2\nf 5 4 1\n", head);
    snprintf(negative, sizeof negative, "%sf -4/-2/-1 -3/-1/-1 -1/-1/-1\nv 2 2 2\nf -1 -2 -5\n", head);
    resurf_mesh *a = load_text(positive), *b = load_text(negative);
    ck_assert_uint_eq(a->vertex_count, b->vertex_count);
    ck_assert_uint_eq(a->triangle_count, 2);
    ck_assert_uint_eq(b->triangle_count, 2);
    ck_assert_mem_eq(a->indices, b->indices, 6 * sizeof(uint32_t));
    ck_assert_mem_eq(a->positions, b->positions, 3 * a->vertex_count * sizeof(double));
    ck_assert_mem_eq(a->normals, b->normals, 3 * a->vertex_count * sizeof(double));
    ck_assert_mem_eq(a->texcoords[0], b->texcoords[0], 2 * a->vertex_count * sizeof(double));
    /* the second face's corners are positions 5, 4, 1 */
    static const double p5[3] = {2, 2, 2}, p4[3] = {1, 1, 0};
    ck_assert_mem_eq(b->positions + 3 * b->indices[3], p5, sizeof p5);
    ck_assert_mem_eq(b->positions + 3 * b->indices[4], p4, sizeof p4);
    resurf_mesh_free(a);
    resurf_mesh_free(b);
}
END_TEST

/* A polygon becomes the fan (0, i, i+1); with positions only, resurf vertex i is OBJ vertex i. */
START_TEST(obj_polygons_are_fanned)
{
    resurf_mesh *m = load_text("v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4 5\nf 5 4 3 2\n");
    static const uint32_t expected[] = {0, 1, 2, 0, 2, 3, 0, 3, 4, 4, 3, 2, 4, 2, 1};
    ck_assert_uint_eq(m->triangle_count, 5);
    ck_assert_mem_eq(m->indices, expected, sizeof expected);
    resurf_mesh_free(m);
}
END_TEST

/* o, g and usemtl start groups; a name seen before reuses its group; faces before any statement are "default". */
START_TEST(obj_groups)
{
    resurf_mesh *m = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                               "f 1 2 3\n"
                               "g body  \n"
                               "f 1 3 4\n"
                               "usemtl red\n"
                               "f 1 2 4\n"
                               "o thing\n"
                               "g body\n"
                               "f 2 3 4\n"
                               "g\n"
                               "f 1 2 3\n"
                               "g two words\n"
                               "f 1 2 3\n");
    ck_assert_uint_eq(m->triangle_count, 6);
    ck_assert_uint_eq(m->group_count, 4);
    static const char *const names[] = {"default", "body", "red", "body", "default", "two words"};
    for (size_t t = 0; t < 6; ++t)
        ck_assert_str_eq(m->group_names[m->triangle_groups[t]], names[t]);
    ck_assert_uint_eq(m->triangle_groups[1], m->triangle_groups[3]);
    ck_assert_uint_eq(m->triangle_groups[0], m->triangle_groups[4]);
    resurf_mesh_free(m);
    /* Without group statements there are no groups. */
    m = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    ck_assert_ptr_null(m->triangle_groups);
    ck_assert_uint_eq(m->group_count, 0);
    resurf_mesh_free(m);
}
END_TEST

/* Positions only: order and unreferenced vertices are kept. With a seam (one position, two texcoords) vertices
 * follow first use, and positions no face uses come last. */
START_TEST(obj_vertex_order_and_seams)
{
    resurf_mesh *m = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 9 9 9\nf 3 2 1\n");
    ck_assert_uint_eq(m->vertex_count, 4);
    static const uint32_t tri[] = {2, 1, 0};
    ck_assert_mem_eq(m->indices, tri, sizeof tri);
    ck_assert_double_eq(m->positions[9], 9);
    resurf_mesh_free(m);

    m = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 9 9 9\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n"
                  "f 1/1 2/2 3/3\nf 2/4 5/2 3/3\n");
    /* triples in order of first use: 1/1 2/2 3/3 2/4 5/2; then the unused position 4 */
    ck_assert_uint_eq(m->vertex_count, 6);
    static const uint32_t tris[] = {0, 1, 2, 3, 4, 2};
    ck_assert_mem_eq(m->indices, tris, sizeof tris);
    ck_assert_mem_eq(m->positions + 3 * 1, m->positions + 3 * 3, 3 * sizeof(double)); /* the seam */
    ck_assert_double_eq(m->texcoords[0][2 * 1], 1);
    ck_assert_double_eq(m->texcoords[0][2 * 3 + 1], 1);
    ck_assert_double_eq(m->positions[3 * 5], 9);
    resurf_mesh_free(m);
}
END_TEST

/* CRLF, comments (also after data), blank lines, backslash continuations, leading blanks and statements resurf
 * does not use (mtllib, s, l, vp, and unknown words). */
START_TEST(obj_text_conventions)
{
    resurf_mesh *m = load_text("# header\r\nmtllib a.mtl\r\n\r\n  v 0 0 0 # first\r\nv 1 \\\r\n 0 0\r\n"
                               "vp 0.5\r\nv 0 1 0\r\ns off\r\nl 1 2\r\ncstype bspline\r\nf 1 2 \\\r\n 3\r\n"
                               "frobnicate 1 2 3 \\\n  4 5\nf 3 2 1 # reversed\n");
    ck_assert_uint_eq(m->vertex_count, 3);
    ck_assert_uint_eq(m->triangle_count, 2);
    static const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    ck_assert_mem_eq(m->positions, p, sizeof p);
    static const uint32_t t[] = {0, 1, 2, 2, 1, 0};
    ck_assert_mem_eq(m->indices, t, sizeof t);
    resurf_mesh_free(m);
}
END_TEST

/* "v x y z w" (w ignored), "v x y z r g b" and "v x y z r g b a"; vertices without a colour are white. */
START_TEST(obj_vertex_colors)
{
    resurf_mesh *m = load_text("v 0 0 0 1\nv 1 0 0\nf 1 2 2\n");
    ck_assert_ptr_null(m->colors);
    resurf_mesh_free(m);
    m = load_text("v 0 0 0\nv 1 0 0 0.25 0.5 0.75\nv 0 1 0 0.1 0.2 0.3 0.4\nf 1 2 3\n");
    ck_assert_ptr_nonnull(m->colors);
    ck_assert_uint_eq(m->color_components, 4);
    static const double c[] = {1, 1, 1, 1, 0.25, 0.5, 0.75, 1, 0.1, 0.2, 0.3, 0.4};
    ck_assert_mem_eq(m->colors, c, sizeof c);
    resurf_mesh_free(m);
    m = load_text("v 0 0 0 0 0 0\nv 1 0 0\nf 1 2 2\n");
    ck_assert_uint_eq(m->color_components, 3);
    resurf_mesh_free(m);
}
END_TEST

/* What the writer prints: 17 digits, v/vt/vn forms, g lines only where the group changes. */
START_TEST(obj_writer_output)
{
    static const double p[] = {0.1, 0, 0, 1, 0, 0, 0, 1, 0};
    static const uint32_t t[] = {0, 1, 2, 0, 2, 1};
    resurf_mesh *m = tu_mesh(p, 3, t, 2);
    char *text = NULL;
    resurf_mesh *back = round_trip(m, &text);
    ck_assert_ptr_nonnull(strstr(text, "\nv 0.10000000000000001 0 0\n"));
    ck_assert_ptr_nonnull(strstr(text, "\nf 1 2 3\nf 1 3 2\n"));
    free(text);
    resurf_mesh_free(back);
    m->normals = calloc(9, sizeof(double));
    back = round_trip(m, &text);
    ck_assert_ptr_nonnull(strstr(text, "\nf 1//1 2//2 3//3\n"));
    free(text);
    resurf_mesh_free(back);
    m->texcoords[0] = calloc(6, sizeof(double));
    m->texcoord_count = 1;
    m->triangle_groups = calloc(2, sizeof(uint32_t));
    m->group_names = calloc(1, sizeof(char *));
    m->group_names[0] = strdup("a\nb");
    m->group_count = 1;
    back = round_trip(m, &text);
    ck_assert_ptr_nonnull(strstr(text, "\ng a_b\nf 1/1/1 2/2/2 3/3/3\nf 1/1/1 3/3/3 2/2/2\n"));
    ck_assert_str_eq(back->group_names[0], "a_b");
    free(text);
    resurf_mesh_free(back);
    resurf_save_options o = resurf_save_options_default();
    o.write_normals = false;
    char *dir = tu_tempdir(), *path = tu_path(dir, "x.obj");
    ck_assert_int_eq(resurf_mesh_save(m, path, &o, NULL), RESURF_OK);
    text = tu_read_file(path, NULL);
    ck_assert_ptr_null(strstr(text, "vn "));
    ck_assert_ptr_nonnull(strstr(text, "\nf 1/1 2/2 3/3\n"));
    free(text);
    tu_rmtree(dir);
    free(dir), free(path);
    resurf_mesh_free(m);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("io_obj");
    TCase *tc = tcase_create("obj");
    tcase_add_test(tc, obj_positions_round_trip_bit_exact);
    tcase_add_test(tc, obj_attributes_round_trip);
    tcase_add_test(tc, obj_every_index_form);
    tcase_add_test(tc, obj_negative_indices);
    tcase_add_test(tc, obj_polygons_are_fanned);
    tcase_add_test(tc, obj_groups);
    tcase_add_test(tc, obj_vertex_order_and_seams);
    tcase_add_test(tc, obj_text_conventions);
    tcase_add_test(tc, obj_vertex_colors);
    tcase_add_test(tc, obj_writer_output);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
