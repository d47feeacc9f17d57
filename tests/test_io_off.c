/* src/io_off.c: Geomview OFF and its ST/C/N variants. Round trips keep positions, normals and texcoords
 * bit-exact and colours k/255 exact; hand-written files check the header forms, comments, polygons with face
 * colours and both colour conventions (integers 0..255, fractions 0..1). */
#include <stdio.h>
#include <string.h>

#include "testutil.h"

static resurf_mesh *load_text(const char *text)
{
    resurf_mesh *m = NULL;
    resurf_error error;
    resurf_status s = resurf_mesh_load_memory(text, strlen(text), RESURF_FORMAT_OFF, "test.off", NULL, &m, &error);
    ck_assert_msg(s == RESURF_OK, "%s (line %lld)", error.message, error.line);
    return m;
}

static resurf_mesh *round_trip(const resurf_mesh *m, char **out_text)
{
    char *dir = tu_tempdir(), *path = tu_path(dir, "m.off");
    resurf_error error;
    ck_assert_msg(resurf_mesh_save(m, path, NULL, &error) == RESURF_OK, "%s", error.message);
    resurf_mesh *back = NULL;
    ck_assert_msg(resurf_mesh_load(path, NULL, &back, &error) == RESURF_OK, "%s", error.message);
    *out_text = tu_read_file(path, NULL);
    tu_rmtree(dir);
    free(dir), free(path);
    return back;
}

/* Each combination of attributes gets its keyword and comes back exactly. */
START_TEST(off_round_trip_every_variant)
{
    static const char *const keywords[8] = {"OFF\n", "NOFF\n", "COFF\n", "CNOFF\n",
                                            "STOFF\n", "STNOFF\n", "STCOFF\n", "STCNOFF\n"};
    for (int mask = 0; mask < 8; ++mask) {
        resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 800, 0.3, (uint64_t)mask, mask & 1);
        const size_t nv = m->vertex_count;
        if (mask & 2) {
            m->colors = malloc(4 * nv * sizeof(double));
            m->color_components = mask == 2 ? 3 : 4;
            for (size_t i = 0; i < 4 * nv; ++i)
                m->colors[i] = (double)((i * 37) % 256) / 255;
            for (size_t v = 0; m->color_components == 3 && v < nv; ++v)
                m->colors[4 * v + 3] = 1;
        }
        if (mask & 4) {
            m->texcoords[0] = malloc(2 * nv * sizeof(double));
            m->texcoord_count = 1;
            for (size_t i = 0; i < 2 * nv; ++i)
                m->texcoords[0][i] = sin((double)i);
        }
        char *text = NULL;
        resurf_mesh *back = round_trip(m, &text);
        ck_assert_msg(strncmp(text, keywords[mask], strlen(keywords[mask])) == 0, "mask %d: %.10s", mask, text);
        ck_assert_uint_eq(back->vertex_count, nv);
        ck_assert_uint_eq(back->triangle_count, m->triangle_count);
        ck_assert_mem_eq(back->positions, m->positions, 3 * nv * sizeof(double));
        ck_assert_mem_eq(back->indices, m->indices, 3 * m->triangle_count * sizeof(uint32_t));
        ck_assert_int_eq(back->normals != NULL, (mask & 1) != 0);
        if (mask & 1)
            ck_assert_mem_eq(back->normals, m->normals, 3 * nv * sizeof(double));
        ck_assert_int_eq(back->colors != NULL, (mask & 2) != 0);
        if (mask & 2) {
            ck_assert_uint_eq(back->color_components, m->color_components);
            ck_assert_mem_eq(back->colors, m->colors, 4 * nv * sizeof(double));
        }
        ck_assert_uint_eq(back->texcoord_count, (mask & 4) ? 1 : 0);
        if (mask & 4)
            ck_assert_mem_eq(back->texcoords[0], m->texcoords[0], 2 * nv * sizeof(double));
        free(text);
        resurf_mesh_free(back);
        resurf_mesh_free(m);
    }
}
END_TEST

/* Counts on the keyword's line or the next, comments and blank lines anywhere, CRLF, no edge count, polygons
 * fanned, face colours ignored, and a file without the (optional) keyword. */
START_TEST(off_header_forms_and_polygons)
{
    static const char *const texts[] = {
        "OFF 5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 2 2\n4 0 1 2 3\n3 4 3 2 255 0 0\n",
        ("# comment first\r\n\r\nOFF\r\n# counts next\r\n5 2\r\n0 0 0\r\n1 0 0 # trailing\r\n1 1 0\r\n\r\n"
         "0 1 0\r\n# between\r\n2 2 2\r\n4 0 1 2 3 0.5 0.5 0.5 1\r\n3 4 3 2\r\n"),
        "5 2 9\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 2 2\n4  0 1 2 3\n3\t4 3 2\n",
    };
    static const double p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 2, 2, 2};
    static const uint32_t t[] = {0, 1, 2, 0, 2, 3, 4, 3, 2};
    for (size_t k = 0; k < 3; ++k) {
        resurf_mesh *m = load_text(texts[k]);
        ck_assert_uint_eq(m->vertex_count, 5);
        ck_assert_mem_eq(m->positions, p, sizeof p);
        ck_assert_uint_eq(m->triangle_count, 3);
        ck_assert_mem_eq(m->indices, t, sizeof t);
        ck_assert_ptr_null(m->colors);
        resurf_mesh_free(m);
    }
}
END_TEST

/* COFF colours: integers are 0..255, numbers with a decimal point 0..1; 3 or 4 values per vertex. CNOFF puts
 * the normal first, STOFF the texcoord last. */
START_TEST(off_colors_normals_texcoords)
{
    resurf_mesh *m = load_text("COFF\n3 1 0\n0 0 0 255 0 51\n1 0 0 0.5 0.25 1.0 0.5\n0 1 0 0 0 0 255\n3 0 1 2\n");
    ck_assert_uint_eq(m->color_components, 4);
    static const double c[] = {1, 0, 0.2, 1, 0.5, 0.25, 1, 0.5, 0, 0, 0, 1};
    ck_assert_mem_eq(m->colors, c, sizeof c);
    resurf_mesh_free(m);
    m = load_text("CNOFF\n1 0 0\n1 2 3 0 0 1 10 20 30\n");
    ck_assert_uint_eq(m->color_components, 3);
    static const double n[] = {0, 0, 1}, c2[] = {10.0 / 255, 20.0 / 255, 30.0 / 255, 1}, p[] = {1, 2, 3};
    ck_assert_mem_eq(m->positions, p, sizeof p);
    ck_assert_mem_eq(m->normals, n, sizeof n);
    ck_assert_mem_eq(m->colors, c2, sizeof c2);
    resurf_mesh_free(m);
    m = load_text("STCOFF\n1 0 0\n1 2 3 0.5 0.5 0.5 0.25 0.75\n");
    static const double uv[] = {0.25, 0.75}, c3[] = {0.5, 0.5, 0.5, 1};
    ck_assert_mem_eq(m->texcoords[0], uv, sizeof uv);
    ck_assert_mem_eq(m->colors, c3, sizeof c3);
    resurf_mesh_free(m);
}
END_TEST

/* The written text: keyword, counts with 0 edges, 17 digits, colours as integers. */
START_TEST(off_writer_output)
{
    static const double p[] = {0.1, 0, 0, 1, 0, 0, 0, 1, 0};
    static const uint32_t t[] = {0, 1, 2};
    resurf_mesh *m = tu_mesh(p, 3, t, 1);
    m->colors = calloc(12, sizeof(double));
    m->color_components = 3;
    m->colors[0] = 1, m->colors[1] = 0.2, m->colors[2] = 2; /* 2 is clamped to 255 */
    char *text = NULL;
    resurf_mesh *back = round_trip(m, &text);
    ck_assert_str_eq(text, "COFF\n3 1 0\n0.10000000000000001 0 0 255 51 255\n1 0 0 0 0 0\n0 1 0 0 0 0\n3 0 1 2\n");
    free(text);
    resurf_mesh_free(back);
    resurf_mesh_free(m);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("io_off");
    TCase *tc = tcase_create("off");
    tcase_add_test(tc, off_round_trip_every_variant);
    tcase_add_test(tc, off_header_forms_and_polygons);
    tcase_add_test(tc, off_colors_normals_texcoords);
    tcase_add_test(tc, off_writer_output);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
