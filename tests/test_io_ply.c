/* src/io_ply.c: Stanford PLY. Round trips (binary and ASCII) keep every attribute exactly; hand-built files check
 * both byte orders, every numeric type, colour scaling, the texcoord names, skipped elements and list properties,
 * polygons and index types. */
#include <stdio.h>
#include <string.h>

#include "testutil.h"

/* ---- a byte builder for hand-made files ---------------------------------------------------------------------- */

typedef struct bytes {
    unsigned char data[8192];
    size_t size;
    int big; /* byte order of the binary values */
} bytes;

static void put_text(bytes *b, const char *text)
{
    size_t n = strlen(text);
    ck_assert_uint_le(b->size + n, sizeof b->data);
    memcpy(b->data + b->size, text, n);
    b->size += n;
}

static int host_is_little_endian(void)
{
    uint16_t one = 1;
    unsigned char first;
    memcpy(&first, &one, 1);
    return first == 1;
}

/* Appends the n bytes of a host value in the file's byte order. */
static void put_raw(bytes *b, const void *p, size_t n)
{
    ck_assert_uint_le(b->size + n, sizeof b->data);
    const int reverse = b->big == host_is_little_endian();
    for (size_t i = 0; i < n; ++i)
        b->data[b->size + i] = ((const unsigned char *)p)[reverse ? n - 1 - i : i];
    b->size += n;
}

#define PUT(b, type, value)                                                                                        \
    do {                                                                                                           \
        type v_ = (type)(value);                                                                                   \
        put_raw((b), &v_, sizeof v_);                                                                              \
    } while (0)

static resurf_mesh *load_bytes(const bytes *b)
{
    resurf_mesh *m = NULL;
    resurf_error error;
    resurf_status s = resurf_mesh_load_memory(b->data, b->size, RESURF_FORMAT_PLY, "test.ply", NULL, &m, &error);
    ck_assert_msg(s == RESURF_OK, "%s (line %lld, byte %lld)", error.message, error.line, error.offset);
    return m;
}

static resurf_mesh *load_text(const char *text)
{
    bytes b = {.size = 0};
    put_text(&b, text);
    return load_bytes(&b);
}

static resurf_mesh *round_trip(const resurf_mesh *m, int binary, char **out_text)
{
    char *dir = tu_tempdir(), *path = tu_path(dir, "m.ply");
    resurf_save_options o = resurf_save_options_default();
    o.binary = binary;
    resurf_error error;
    ck_assert_msg(resurf_mesh_save(m, path, &o, &error) == RESURF_OK, "%s", error.message);
    resurf_mesh *back = NULL;
    ck_assert_msg(resurf_mesh_load(path, NULL, &back, &error) == RESURF_OK, "%s", error.message);
    if (out_text)
        *out_text = tu_read_file(path, NULL);
    tu_rmtree(dir);
    free(dir), free(path);
    return back;
}

/* A torus with every attribute: exact normals, texcoords, colours k/255 with alpha, a scalar and a 3-vector extra. */
static resurf_mesh *rich_mesh(void)
{
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 1500, 0.3, 9, 1);
    const size_t nv = m->vertex_count;
    m->texcoords[0] = malloc(2 * nv * sizeof(double));
    m->texcoord_count = 1;
    m->colors = malloc(4 * nv * sizeof(double));
    m->color_components = 4;
    resurf_attribute *q = NULL, *flow = NULL;
    ck_assert_int_eq(resurf_mesh_add_extra(m, "quality", 1, &q, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_mesh_add_extra(m, "flow", 3, &flow, NULL), RESURF_OK);
    q = &m->extras[0];
    for (size_t v = 0; v < nv; ++v) {
        m->texcoords[0][2 * v] = m->positions[3 * v] * 0.3;
        m->texcoords[0][2 * v + 1] = 1.0 / (double)(v + 3);
        for (int a = 0; a < 4; ++a)
            m->colors[4 * v + a] = (double)((v * 7 + (size_t)a * 50) % 256) / 255;
        q->data[v] = (float)v * 0.1f;
        for (int a = 0; a < 3; ++a)
            flow->data[3 * v + a] = (float)m->normals[3 * v + a];
    }
    return m;
}

static void check_rich(const resurf_mesh *m, const resurf_mesh *back)
{
    const size_t nv = m->vertex_count;
    ck_assert_uint_eq(back->vertex_count, nv);
    ck_assert_uint_eq(back->triangle_count, m->triangle_count);
    ck_assert_mem_eq(back->positions, m->positions, 3 * nv * sizeof(double));
    ck_assert_mem_eq(back->indices, m->indices, 3 * m->triangle_count * sizeof(uint32_t));
    ck_assert_mem_eq(back->normals, m->normals, 3 * nv * sizeof(double));
    ck_assert_uint_eq(back->texcoord_count, 1);
    ck_assert_mem_eq(back->texcoords[0], m->texcoords[0], 2 * nv * sizeof(double));
    ck_assert_uint_eq(back->color_components, 4);
    ck_assert_mem_eq(back->colors, m->colors, 4 * nv * sizeof(double));
    /* extras: one float property per component */
    ck_assert_uint_eq(back->extra_count, 4);
    static const char *const names[] = {"quality", "flow_0", "flow_1", "flow_2"};
    for (size_t k = 0; k < 4; ++k) {
        ck_assert_str_eq(back->extras[k].name, names[k]);
        ck_assert_uint_eq(back->extras[k].components, 1);
    }
    for (size_t v = 0; v < nv; ++v) {
        ck_assert(back->extras[0].data[v] == m->extras[0].data[v]);
        for (int a = 0; a < 3; ++a)
            ck_assert(back->extras[1 + a].data[v] == m->extras[1].data[3 * v + a]);
    }
}

START_TEST(ply_binary_round_trip_keeps_everything)
{
    resurf_mesh *m = rich_mesh();
    char *text = NULL;
    resurf_mesh *back = round_trip(m, 1, &text);
    ck_assert_ptr_nonnull(strstr(text, "ply\nformat binary_little_endian 1.0\n"));
    ck_assert_ptr_nonnull(strstr(text, "\nproperty double x\nproperty double y\nproperty double z\n"));
    ck_assert_ptr_nonnull(strstr(text, "\nproperty uchar alpha\n"));
    ck_assert_ptr_nonnull(strstr(text, "\nproperty float flow_2\n"));
    ck_assert_ptr_nonnull(strstr(text, "\nproperty list uchar int vertex_indices\nend_header\n"));
    check_rich(m, back);
    free(text);
    resurf_mesh_free(back);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(ply_ascii_round_trip_keeps_everything)
{
    resurf_mesh *m = rich_mesh();
    char *text = NULL;
    resurf_mesh *back = round_trip(m, 0, &text);
    ck_assert_ptr_nonnull(strstr(text, "ply\nformat ascii 1.0\n"));
    check_rich(m, back);
    free(text);
    resurf_mesh_free(back);
    /* RGB only: no alpha property, alpha reads back as 1 */
    m->color_components = 3;
    back = round_trip(m, 0, &text);
    ck_assert_ptr_null(strstr(text, "alpha"));
    ck_assert_uint_eq(back->color_components, 3);
    for (size_t v = 0; v < m->vertex_count; ++v) {
        ck_assert_mem_eq(back->colors + 4 * v, m->colors + 4 * v, 3 * sizeof(double));
        ck_assert_double_eq(back->colors[4 * v + 3], 1.0);
    }
    free(text);
    resurf_mesh_free(back);
    resurf_mesh_free(m);
}
END_TEST

/* Two vertices with a property of every type (x double, y float, z int, and extras of each type), a triangle
 * and a quad, written big-endian, little-endian and ASCII: all three read the same values. */
static const char *const typed_header =
    "element vertex 4\n"
    "property double x\nproperty float y\nproperty int z\n"
    "property char e_char\nproperty uchar e_uchar\nproperty short e_short\nproperty ushort e_ushort\n"
    "property int e_int\nproperty uint e_uint\nproperty float32 e_float\nproperty float64 e_double\n"
    "property int8 e_int8\nproperty uint16 e_uint16\n"
    "element face 2\nproperty list uchar uint vertex_indices\nend_header\n";

static const double typed_values[4][13] = {
    {1.5, -2.25, -7, -100, 200, -30000, 60000, -2000000000, 4000000000.0, 0.5, 0.25, -128, 65535},
    {-0.125, 3.5, 2147483647, 127, 255, 32767, 0, 2147483647, 0, -1.5, 1e30, 127, 1},
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {1e300, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1},
};

static void put_typed_binary(bytes *b)
{
    for (int v = 0; v < 4; ++v) {
        const double *x = typed_values[v];
        PUT(b, double, x[0]);
        PUT(b, float, x[1]);
        PUT(b, int32_t, x[2]);
        PUT(b, int8_t, x[3]);
        PUT(b, uint8_t, x[4]);
        PUT(b, int16_t, x[5]);
        PUT(b, uint16_t, x[6]);
        PUT(b, int32_t, x[7]);
        PUT(b, uint32_t, x[8]);
        PUT(b, float, x[9]);
        PUT(b, double, x[10]);
        PUT(b, int8_t, x[11]);
        PUT(b, uint16_t, x[12]);
    }
    PUT(b, uint8_t, 3);
    PUT(b, uint32_t, 0); PUT(b, uint32_t, 1); PUT(b, uint32_t, 2);
    PUT(b, uint8_t, 4);
    PUT(b, uint32_t, 3); PUT(b, uint32_t, 2); PUT(b, uint32_t, 1); PUT(b, uint32_t, 0);
}

static void check_typed(const resurf_mesh *m)
{
    ck_assert_uint_eq(m->vertex_count, 4);
    ck_assert_uint_eq(m->extra_count, 10);
    static const char *const names[] = {"e_char", "e_uchar", "e_short", "e_ushort", "e_int",
                                        "e_uint", "e_float", "e_double", "e_int8", "e_uint16"};
    for (int v = 0; v < 4; ++v) {
        for (int a = 0; a < 3; ++a)
            ck_assert_double_eq(m->positions[3 * v + a], typed_values[v][a]);
        for (int k = 0; k < 10; ++k) {
            ck_assert_str_eq(m->extras[k].name, names[k]);
            ck_assert_msg(m->extras[k].data[v] == (float)typed_values[v][3 + k], "vertex %d %s: %g", v, names[k],
                          m->extras[k].data[v]);
        }
    }
    static const uint32_t tris[] = {0, 1, 2, 3, 2, 1, 3, 1, 0};
    ck_assert_uint_eq(m->triangle_count, 3);
    ck_assert_mem_eq(m->indices, tris, sizeof tris);
}

START_TEST(ply_every_type_in_every_encoding)
{
    for (int big = 0; big < 2; ++big) {
        bytes b = {.size = 0, .big = big};
        put_text(&b, big ? "ply\nformat binary_big_endian 1.0\n" : "ply\nformat binary_little_endian 1.0\n");
        put_text(&b, typed_header);
        put_typed_binary(&b);
        resurf_mesh *m = load_bytes(&b);
        check_typed(m);
        resurf_mesh_free(m);
    }
    bytes b = {.size = 0};
    put_text(&b, "ply\nformat ascii 1.0\n");
    put_text(&b, typed_header);
    for (int v = 0; v < 4; ++v) {
        char line[600];
        int n = 0;
        for (int k = 0; k < 13; ++k)
            n += snprintf(line + n, sizeof line - (size_t)n, "%.17g ", typed_values[v][k]);
        put_text(&b, line);
        put_text(&b, "\n");
    }
    put_text(&b, "3 0 1 2\n4 3 2 1 0\n");
    resurf_mesh *m = load_bytes(&b);
    check_typed(m);
    resurf_mesh_free(m);
}
END_TEST

/* Integer colours scale to [0,1] by their type's maximum; float colours are taken as they are. */
START_TEST(ply_color_scaling)
{
    resurf_mesh *m = load_text("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                               "property float z\nproperty uchar red\nproperty ushort green\nproperty float blue\n"
                               "end_header\n0 0 0 255 65535 0.25\n1 0 0 51 13107 0.5\n");
    ck_assert_uint_eq(m->color_components, 3);
    static const double c[] = {1, 1, 0.25, 1, 51.0 / 255, 13107.0 / 65535, 0.5, 1};
    ck_assert_mem_eq(m->colors, c, sizeof c);
    ck_assert_double_eq(m->colors[4], 0.2); /* 51/255 = 13107/65535 = 1/5 exactly */
    ck_assert_double_eq(m->colors[5], 0.2);
    resurf_mesh_free(m);
    m = load_text("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                  "property float z\nproperty uchar diffuse_red\nproperty uchar alpha\nend_header\n0 0 0 0 255\n");
    ck_assert_uint_eq(m->color_components, 4);
    static const double d[] = {0, 0, 0, 1};
    ck_assert_mem_eq(m->colors, d, sizeof d);
    resurf_mesh_free(m);
}
END_TEST

/* u v, s t, texture_u texture_v and texture_s texture_t all name texcoord set 0. */
START_TEST(ply_texcoord_names)
{
    static const char *const pairs[][2] = {{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"},
                                           {"texture_s", "texture_t"}};
    for (int k = 0; k < 4; ++k) {
        char text[400];
        snprintf(text, sizeof text,
                 "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                 "property float %s\nproperty float %s\nend_header\n1 2 3 0.25 0.75\n",
                 pairs[k][0], pairs[k][1]);
        resurf_mesh *m = load_text(text);
        ck_assert_uint_eq(m->texcoord_count, 1);
        ck_assert_double_eq(m->texcoords[0][0], 0.25);
        ck_assert_double_eq(m->texcoords[0][1], 0.75);
        ck_assert_uint_eq(m->extra_count, 0);
        resurf_mesh_free(m);
    }
}
END_TEST

/* Elements other than vertex and face are skipped whatever they hold (lists too, in any position), as are the
 * face element's other properties; values may spread over lines; polygons are fanned; vertex_index works too. */
START_TEST(ply_skips_what_it_does_not_use)
{
    resurf_mesh *m = load_text("ply\nformat ascii 1.0\ncomment made by hand\nobj_info nothing\n"
                               "element material 2\nproperty list uchar float values\nproperty uchar id\n"
                               "element vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
                               "property list uchar int neighbours\n"
                               "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
                               "element face 2\nproperty uchar flags\nproperty list uchar float texcoord\n"
                               "property list short ushort vertex_index\nproperty float quality\n"
                               "end_header\n"
                               "3 0.1 0.2 0.3 7\n0 9\n"
                               "0 0 0 2 1 2\n1 0 0 0\n1 1 0 1 4\n0 1 0 0\n2 2 2 3 0 1 2\n"
                               "0 1\n"
                               "5 6 0 0 1 0 1 1 4 0 1 2 3\n0.5\n"
                               "1 0\n3 4 3 2 0.25\n");
    ck_assert_uint_eq(m->vertex_count, 5);
    ck_assert_uint_eq(m->extra_count, 0);
    static const double p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 2, 2, 2};
    ck_assert_mem_eq(m->positions, p, sizeof p);
    static const uint32_t t[] = {0, 1, 2, 0, 2, 3, 4, 3, 2};
    ck_assert_uint_eq(m->triangle_count, 3);
    ck_assert_mem_eq(m->indices, t, sizeof t);
    resurf_mesh_free(m);
}
END_TEST

/* A header with CRLF line ends; a binary body right after "end_header\r\n"; no face element (a point cloud). */
START_TEST(ply_crlf_header_and_point_cloud)
{
    bytes b = {.size = 0, .big = 0};
    put_text(&b, "ply\r\nformat binary_little_endian 1.0\r\nelement vertex 2\r\nproperty float x\r\n"
                 "property float y\r\nproperty float z\r\nproperty float confidence\r\nend_header\r\n");
    PUT(&b, float, 13); PUT(&b, float, 10); PUT(&b, float, 0.5); PUT(&b, float, 0.75);
    PUT(&b, float, 1); PUT(&b, float, 2); PUT(&b, float, 3); PUT(&b, float, 4);
    resurf_mesh *m = load_bytes(&b);
    ck_assert_uint_eq(m->triangle_count, 0);
    static const double p[] = {13, 10, 0.5, 1, 2, 3};
    ck_assert_mem_eq(m->positions, p, sizeof p);
    ck_assert_uint_eq(m->extra_count, 1);
    ck_assert_str_eq(m->extras[0].name, "confidence");
    ck_assert(m->extras[0].data[0] == 0.75f && m->extras[0].data[1] == 4.0f);
    resurf_mesh_free(m);
}
END_TEST

/* Giant element counts on an element with no properties cost nothing (nothing to read), and a giant list
 * length in an ASCII file fails without allocating for it. */
START_TEST(ply_giant_counts_are_harmless)
{
    resurf_mesh *m = load_text("ply\nformat ascii 1.0\nelement nothing 9223372036854775807\n"
                               "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                               "end_header\n1 2 3\n");
    ck_assert_uint_eq(m->vertex_count, 1);
    resurf_mesh_free(m);
    const char *text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                       "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n"
                       "0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n";
    resurf_error error;
    ck_assert_int_eq(resurf_mesh_load_memory(text, strlen(text), RESURF_FORMAT_PLY, "g.ply", NULL, &m, &error),
                     RESURF_ERR_PARSE);
    ck_assert_str_eq(error.message, "the file ends inside face 0 of 1");
    ck_assert_int_eq(error.line, 13);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("io_ply");
    TCase *tc = tcase_create("ply");
    tcase_add_test(tc, ply_binary_round_trip_keeps_everything);
    tcase_add_test(tc, ply_ascii_round_trip_keeps_everything);
    tcase_add_test(tc, ply_every_type_in_every_encoding);
    tcase_add_test(tc, ply_color_scaling);
    tcase_add_test(tc, ply_texcoord_names);
    tcase_add_test(tc, ply_skips_what_it_does_not_use);
    tcase_add_test(tc, ply_crlf_header_and_point_cloud);
    tcase_add_test(tc, ply_giant_counts_are_harmless);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
