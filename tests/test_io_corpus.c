/* The loaders against hostile input: the malformed files of tests/corpus/ (each with the status and the exact
 * message written by hand in tests/corpus/EXPECTED), and every cut-off and byte-flipped version of small valid
 * files in each format. Loading must fail cleanly with the right status and never crash or leak (run under ASan). */
#include <stdio.h>
#include <string.h>

#include "testutil.h"

#define CORPUS RESURF_SOURCE_DIR "/tests/corpus"

typedef struct corpus_case {
    char file[128];
    resurf_status status;
    char suffix[256]; /* resurf_format_error's text after the path */
} corpus_case;

static resurf_status status_from_word(const char *w)
{
    if (!strcmp(w, "parse"))
        return RESURF_ERR_PARSE;
    if (!strcmp(w, "limit"))
        return RESURF_ERR_LIMIT;
    if (!strcmp(w, "unsupported"))
        return RESURF_ERR_UNSUPPORTED;
    if (!strcmp(w, "io"))
        return RESURF_ERR_IO;
    ck_abort_msg("unknown status word '%s' in EXPECTED", w);
    return RESURF_OK;
}

/* Reads the manifest; returns the number of cases. */
static size_t read_manifest(corpus_case *cases, size_t max)
{
    char *text = tu_read_file(CORPUS "/EXPECTED", NULL);
    ck_assert_ptr_nonnull(text);
    size_t n = 0;
    for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
        if (line[0] == '#' || !line[0])
            continue;
        char *tab1 = strchr(line, '\t'), *tab2 = tab1 ? strchr(tab1 + 1, '\t') : NULL;
        ck_assert_msg(tab1 && tab2, "bad manifest line: %s", line);
        *tab1 = *tab2 = 0;
        ck_assert_uint_lt(n, max);
        snprintf(cases[n].file, sizeof cases[n].file, "%s", line);
        cases[n].status = status_from_word(tab1 + 1);
        snprintf(cases[n].suffix, sizeof cases[n].suffix, "%s", tab2 + 1);
        ++n;
    }
    free(text);
    return n;
}

/* Each corpus file fails with its status and exact message, from a path and from memory alike. */
START_TEST(corpus_files_fail_with_their_messages)
{
    corpus_case cases[128];
    size_t n = read_manifest(cases, 128);
    ck_assert_uint_ge(n, 30);
    for (size_t i = 0; i < n; ++i) {
        char path[512], expected[800], text[800];
        snprintf(path, sizeof path, "%s/%.127s", CORPUS, cases[i].file); /* precisions: gcc -O3 cannot bound them */
        resurf_mesh *mesh = (resurf_mesh *)&mesh; /* must be reset to NULL */
        resurf_error error;
        resurf_status s = resurf_mesh_load(path, NULL, &mesh, &error);
        resurf_format_error(text, sizeof text, &error);
        snprintf(expected, sizeof expected, "%s%s", path, cases[i].suffix);
        ck_assert_msg(s == cases[i].status, "%s: status %s, expected %s (%s)", cases[i].file,
                      resurf_status_string(s), resurf_status_string(cases[i].status), text);
        ck_assert_ptr_null(mesh);
        ck_assert_int_eq(error.status, s);
        ck_assert_str_eq(error.path, path);
        ck_assert_msg(!strcmp(text, expected), "%s:\n  got      %s\n  expected %s", cases[i].file, text, expected);

        /* The same bytes from memory, named by the file name only. */
        size_t size = 0;
        char *data = tu_read_file(path, &size);
        ck_assert_ptr_nonnull(data);
        s = resurf_mesh_load_memory(data, size, RESURF_FORMAT_AUTO, cases[i].file, NULL, &mesh, &error);
        resurf_format_error(text, sizeof text, &error);
        snprintf(expected, sizeof expected, "%.127s%.255s", cases[i].file, cases[i].suffix);
        ck_assert_int_eq(s, cases[i].status);
        ck_assert_str_eq(text, expected);
        free(data);
    }
}
END_TEST

/* Loads bytes in a format; the outcome must be success or a clean, described failure. */
static void load_must_not_crash(const char *data, size_t size, resurf_format format, const char *what)
{
    resurf_mesh *mesh = NULL;
    resurf_error error;
    resurf_status s = resurf_mesh_load_memory(data, size, format, "cut", NULL, &mesh, &error);
    if (s == RESURF_OK) {
        ck_assert_ptr_nonnull(mesh);
        for (size_t i = 0; i < 3 * mesh->triangle_count; ++i)
            ck_assert_uint_lt(mesh->indices[i], mesh->vertex_count);
        for (size_t i = 0; i < 3 * mesh->vertex_count; ++i)
            ck_assert(isfinite(mesh->positions[i]));
        resurf_mesh_free(mesh);
        return;
    }
    ck_assert_ptr_null(mesh);
    ck_assert_msg(s == RESURF_ERR_PARSE || s == RESURF_ERR_UNSUPPORTED || s == RESURF_ERR_LIMIT, "%s: status %s (%s)", what,
                  resurf_status_string(s), error.message);
    ck_assert_int_gt((int)strlen(error.message), 0);
    ck_assert_ptr_null(strchr(error.message, '\n'));
}

/* A small mesh with every attribute each format can hold, saved in each format and variant. */
static char *saved_bytes(resurf_format format, int binary, size_t *size)
{
    resurf_mesh *m = tu_cube();
    m->normals = calloc(3 * m->vertex_count, sizeof(double));
    m->colors = calloc(4 * m->vertex_count, sizeof(double));
    m->color_components = 4;
    m->texcoords[0] = calloc(2 * m->vertex_count, sizeof(double));
    m->texcoord_count = 1;
    for (size_t v = 0; v < m->vertex_count; ++v) {
        m->normals[3 * v + 2] = 1;
        m->colors[4 * v] = (double)v / 8;
        m->colors[4 * v + 3] = 1;
        m->texcoords[0][2 * v] = 0.25 * (double)v;
    }
    ck_assert_int_eq(resurf_mesh_add_extra(m, "quality", 1, NULL, NULL), RESURF_OK);
    char *dir = tu_tempdir(), *path = tu_path(dir, "m.bin");
    resurf_save_options o = resurf_save_options_default();
    o.format = format;
    o.binary = binary;
    ck_assert_int_eq(resurf_mesh_save(m, path, &o, NULL), RESURF_OK);
    char *data = tu_read_file(path, size);
    tu_rmtree(dir);
    free(dir);
    free(path);
    resurf_mesh_free(m);
    return data;
}

/* Every prefix of a valid file (the file cut off anywhere), and every single byte replaced by a few hostile
 * values, loads or fails cleanly. */
START_TEST(cut_and_flipped_files_fail_cleanly)
{
    static const struct {
        resurf_format format;
        int binary;
    } variants[] = {
        {RESURF_FORMAT_OBJ, 0}, {RESURF_FORMAT_PLY, 1}, {RESURF_FORMAT_PLY, 0},
        {RESURF_FORMAT_OFF, 0}, {RESURF_FORMAT_STL, 1}, {RESURF_FORMAT_STL, 0},
    };
    for (size_t k = 0; k < sizeof variants / sizeof *variants; ++k) {
        size_t size = 0;
        char *data = saved_bytes(variants[k].format, variants[k].binary, &size);
        ck_assert_uint_gt(size, 50);
        for (size_t cut = 0; cut < size; ++cut) {
            /* An exact-size copy, so that ASan catches any read past the end. */
            char *copy = malloc(cut ? cut : 1);
            memcpy(copy, data, cut);
            load_must_not_crash(copy, cut, variants[k].format, "cut");
            free(copy);
        }
        static const unsigned char hostile[] = {0x00, 0xff, '\n', '-', '9', 0x80};
        char *copy = malloc(size);
        for (size_t i = 0; i < size; ++i)
            for (size_t h = 0; h < sizeof hostile; ++h) {
                memcpy(copy, data, size);
                copy[i] = (char)hostile[h];
                load_must_not_crash(copy, size, variants[k].format, "flip");
            }
        free(copy);
        free(data);
    }
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("io_corpus");
    TCase *tc = tcase_create("corpus");
    tcase_add_test(tc, corpus_files_fail_with_their_messages);
    tcase_add_test(tc, cut_and_flipped_files_fail_cleanly);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
