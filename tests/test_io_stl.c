/* src/io_stl.c: STL. Binary round trips keep positions at float precision, ASCII ones exactly; loading welds
 * equal positions (a closed cube has 8 vertices and every edge shared by two triangles); a binary file whose
 * header starts with "solid" is still read as binary; facet normals are ignored on load and computed on save. */
#include <stdio.h>
#include <string.h>

#include "testutil.h"

static resurf_mesh *load_bytes(const void *data, size_t size)
{
    resurf_mesh *m = NULL;
    resurf_error error;
    resurf_status s = resurf_mesh_load_memory(data, size, RESURF_FORMAT_STL, "test.stl", NULL, &m, &error);
    ck_assert_msg(s == RESURF_OK, "%s (line %lld, byte %lld)", error.message, error.line, error.offset);
    return m;
}

static char *save_bytes(const resurf_mesh *m, int binary, size_t *size)
{
    char *dir = tu_tempdir(), *path = tu_path(dir, "m.stl");
    resurf_save_options o = resurf_save_options_default();
    o.binary = binary;
    ck_assert_int_eq(resurf_mesh_save(m, path, &o, NULL), RESURF_OK);
    char *data = tu_read_file(path, size);
    tu_rmtree(dir);
    free(dir), free(path);
    return data;
}

/* Every corner of back has the position of the same corner of m, rounded to float when `as_float`. */
static void check_corners(const resurf_mesh *m, const resurf_mesh *back, int as_float)
{
    ck_assert_uint_eq(back->triangle_count, m->triangle_count);
    for (size_t i = 0; i < 3 * m->triangle_count; ++i)
        for (int a = 0; a < 3; ++a) {
            double want = m->positions[3 * (size_t)m->indices[i] + a];
            if (as_float)
                want = (double)(float)want;
            ck_assert(back->positions[3 * (size_t)back->indices[i] + a] == want);
        }
}

/* Binary: 84 + 50 n bytes, a header that does not start with "solid", float positions, welded back. */
START_TEST(stl_binary_round_trip)
{
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 3000, 0.3, 4, 0);
    size_t size;
    char *data = save_bytes(m, 1, &size);
    ck_assert_uint_eq(size, 84 + 50 * m->triangle_count);
    ck_assert(strncmp(data, "solid", 5) != 0);
    resurf_mesh *back = load_bytes(data, size);
    check_corners(m, back, 1);
    /* the torus's positions stay distinct in float, so welding restores the vertex count */
    ck_assert_uint_eq(back->vertex_count, m->vertex_count);
    ck_assert_ptr_null(back->normals);
    free(data);
    resurf_mesh_free(back);
    resurf_mesh_free(m);
}
END_TEST

/* ASCII: positions written with 17 digits come back exactly, and weld to the original vertex count. */
START_TEST(stl_ascii_round_trip)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 2000, 0.3, 4, 0);
    size_t size;
    char *data = save_bytes(m, 0, &size);
    ck_assert(strncmp(data, "solid resurf\n", 13) == 0);
    resurf_mesh *back = load_bytes(data, size);
    check_corners(m, back, 0);
    ck_assert_uint_eq(back->vertex_count, m->vertex_count);
    free(data);
    resurf_mesh_free(back);
    resurf_mesh_free(m);
}
END_TEST

/* Is the mesh closed? Every undirected edge in exactly two triangles (O(n²), fine for 12 triangles). */
static void check_closed_cube(const resurf_mesh *m)
{
    ck_assert_uint_eq(m->vertex_count, 8);
    ck_assert_uint_eq(m->triangle_count, 12);
    size_t edges = 0;
    for (size_t t = 0; t < 12; ++t)
        for (int i = 0; i < 3; ++i) {
            uint32_t a = m->indices[3 * t + i], b = m->indices[3 * t + (i + 1) % 3];
            int uses = 0;
            for (size_t u = 0; u < 12; ++u)
                for (int j = 0; j < 3; ++j) {
                    uint32_t c = m->indices[3 * u + j], d = m->indices[3 * u + (j + 1) % 3];
                    uses += (a == c && b == d) || (a == d && b == c);
                }
            ck_assert_int_eq(uses, 2);
            ++edges;
        }
    ck_assert_uint_eq(edges / 2, 18);
}

static void put_f32(unsigned char *p, float f) { memcpy(p, &f, 4); } /* the tests run on little-endian hosts */

/* The cube's 12 facets as a binary STL whose header starts with "solid", with nonsense facet normals. */
START_TEST(stl_binary_with_solid_header_and_cube_weld)
{
    uint16_t one = 1;
    unsigned char first;
    memcpy(&first, &one, 1);
    ck_assert_msg(first == 1, "this test writes little-endian floats directly");
    resurf_mesh *cube = tu_cube();
    unsigned char data[84 + 50 * 12];
    memset(data, 0, sizeof data);
    memcpy(data, "solid cube exported by some program", 35);
    data[80] = 12;
    for (size_t t = 0; t < 12; ++t) {
        unsigned char *f = data + 84 + 50 * t;
        put_f32(f, 7), put_f32(f + 4, -3), put_f32(f + 8, 1e30f);
        for (int c = 0; c < 3; ++c)
            for (int a = 0; a < 3; ++a)
                put_f32(f + 12 + 12 * c + 4 * a, (float)cube->positions[3 * cube->indices[3 * t + c] + a]);
    }
    resurf_mesh *m = load_bytes(data, sizeof data);
    check_closed_cube(m);
    check_corners(cube, m, 1);
    resurf_mesh_free(m);
    resurf_mesh_free(cube);
}
END_TEST

/* The cube as ASCII, by hand from its 12 triangles: 8 vertices, closed. */
START_TEST(stl_ascii_cube_welds)
{
    resurf_mesh *cube = tu_cube();
    char text[8192];
    size_t n = (size_t)snprintf(text, sizeof text, "solid cube\n");
    for (size_t t = 0; t < 12; ++t) {
        n += (size_t)snprintf(text + n, sizeof text - n, "  facet normal 0 0 0\n    outer loop\n");
        for (int c = 0; c < 3; ++c) {
            const double *p = cube->positions + 3 * cube->indices[3 * t + c];
            n += (size_t)snprintf(text + n, sizeof text - n, "      vertex %g %g %g\n", p[0], p[1], p[2]);
        }
        n += (size_t)snprintf(text + n, sizeof text - n, "    endloop\n  endfacet\n");
    }
    n += (size_t)snprintf(text + n, sizeof text - n, "endsolid cube\n");
    resurf_mesh *m = load_bytes(text, n);
    check_closed_cube(m);
    check_corners(cube, m, 0);
    resurf_mesh_free(m);
    resurf_mesh_free(cube);
}
END_TEST

/* A quad facet is fanned; several solids in one file; CRLF; "endsolid" without a name. */
START_TEST(stl_ascii_polygons_and_solids)
{
    const char *text = "solid a\r\nfacet normal 0 0 1\r\nouter loop\r\nvertex 0 0 0\r\nvertex 1 0 0\r\n"
                       "vertex 1 1 0\r\nvertex 0 1 0\r\nendloop\r\nendfacet\r\nendsolid a\r\n"
                       "solid\r\nfacet normal 0 0 1 outer loop vertex 1 1 0 vertex 2 1 0 vertex 1 2 0 endloop endfacet\r\n"
                       "endsolid\r\n";
    resurf_mesh *m = load_bytes(text, strlen(text));
    ck_assert_uint_eq(m->triangle_count, 3);
    ck_assert_uint_eq(m->vertex_count, 6); /* (1,1,0) is shared by both solids */
    static const uint32_t t[] = {0, 1, 2, 0, 2, 3, 2, 4, 5};
    ck_assert_mem_eq(m->indices, t, sizeof t);
    resurf_mesh_free(m);
}
END_TEST

/* The saved facet normal is the unit normal of the corners (counter-clockwise), 0 for a degenerate facet. */
START_TEST(stl_writer_normals)
{
    static const double p[] = {0, 0, 0, 2, 0, 0, 0, 3, 0, 4, 0, 0};
    static const uint32_t t[] = {0, 1, 2, 0, 1, 3};
    resurf_mesh *m = tu_mesh(p, 4, t, 2);
    size_t size;
    unsigned char *data = (unsigned char *)save_bytes(m, 1, &size);
    ck_assert_uint_eq(size, 84 + 100);
    float n[6];
    memcpy(n, data + 84, 12);
    memcpy(n + 3, data + 134, 12);
    ck_assert(n[0] == 0 && n[1] == 0 && n[2] == 1);
    ck_assert(n[3] == 0 && n[4] == 0 && n[5] == 0);
    free(data);
    char *text = save_bytes(m, 0, &size);
    ck_assert_ptr_nonnull(strstr(text, "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 2 0 0\n"));
    free(text);
    resurf_mesh_free(m);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("io_stl");
    TCase *tc = tcase_create("stl");
    tcase_add_test(tc, stl_binary_round_trip);
    tcase_add_test(tc, stl_ascii_round_trip);
    tcase_add_test(tc, stl_binary_with_solid_header_and_cube_weld);
    tcase_add_test(tc, stl_ascii_cube_welds);
    tcase_add_test(tc, stl_ascii_polygons_and_solids);
    tcase_add_test(tc, stl_writer_normals);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
