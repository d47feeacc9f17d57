/* src/io.c, src/file.c, src/io_common.c and src/io_text.c: format choice, whole-file loading and its failures, the
 * atomic save, limits, progress and cancel, the number scanner (against the C library's correctly rounded strtod)
 * and locale independence. Format details are in test_io_obj/ply/off/stl.c, malformed files in test_io_corpus.c. */
#include <errno.h>
#include <locale.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io_internal.h"
#include "testutil.h"

static void write_text(const char *path, const char *text) { ck_assert_int_eq(tu_write_file(path, text, strlen(text)), 0); }

static const char *cube_obj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";

START_TEST(io_format_from_path_and_name)
{
    ck_assert_int_eq(resurf_format_from_path("a.obj"), RESURF_FORMAT_OBJ);
    ck_assert_int_eq(resurf_format_from_path("/x/y.z/A.PLY"), RESURF_FORMAT_PLY);
    ck_assert_int_eq(resurf_format_from_path("dir.stl/mesh.Off"), RESURF_FORMAT_OFF);
    ck_assert_int_eq(resurf_format_from_path("m.sTl"), RESURF_FORMAT_STL);
    ck_assert_int_eq(resurf_format_from_path("dir.stl/mesh"), RESURF_FORMAT_AUTO);
    ck_assert_int_eq(resurf_format_from_path(".ply"), RESURF_FORMAT_AUTO); /* a hidden file, no extension */
    ck_assert_int_eq(resurf_format_from_path("m.obj.gz"), RESURF_FORMAT_AUTO);
    ck_assert_int_eq(resurf_format_from_path("m."), RESURF_FORMAT_AUTO);
    ck_assert_int_eq(resurf_format_from_path(NULL), RESURF_FORMAT_AUTO);
    for (int f = RESURF_FORMAT_OBJ; f < RESURF_FORMAT_COUNT; ++f)
        ck_assert_int_eq(resurf_format_from_name(resurf_format_name((resurf_format)f)), f);
    ck_assert_str_eq(resurf_format_name(RESURF_FORMAT_PLY), "ply");
    ck_assert_int_eq(resurf_format_from_name("OBJ"), RESURF_FORMAT_OBJ);
    ck_assert_int_eq(resurf_format_from_name("gltf"), RESURF_FORMAT_AUTO);
    ck_assert_int_eq(resurf_format_from_name(NULL), RESURF_FORMAT_AUTO);
    ck_assert_ptr_null(resurf_format_name(RESURF_FORMAT_AUTO));
    ck_assert_ptr_null(resurf_format_name(RESURF_FORMAT_COUNT));
}
END_TEST

START_TEST(io_options_defaults_and_checks)
{
    resurf_load_options lo = resurf_load_options_default();
    ck_assert_uint_eq(lo.struct_size, sizeof lo);
    ck_assert_int_eq(lo.format, RESURF_FORMAT_AUTO);
    ck_assert_uint_eq(lo.max_triangles, 100000000);
    resurf_save_options so = resurf_save_options_default();
    ck_assert_uint_eq(so.struct_size, sizeof so);
    ck_assert_int_eq(so.binary, 1);
    ck_assert(so.write_normals && so.write_texcoords && so.write_colors && so.write_extras);

    resurf_mesh *mesh = NULL;
    resurf_error error;
    resurf_load_options zeroed;
    memset(&zeroed, 0, sizeof zeroed);
    ck_assert_int_eq(resurf_mesh_load_memory(cube_obj, strlen(cube_obj), RESURF_FORMAT_OBJ, NULL, &zeroed, &mesh,
                                             &error),
                     RESURF_ERR_INVALID_OPTIONS);
    ck_assert_ptr_null(mesh);
    ck_assert_int_eq(resurf_mesh_load(NULL, NULL, &mesh, &error), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurf_mesh_load("x.obj", NULL, NULL, &error), RESURF_ERR_INVALID_ARGUMENT);
    resurf_mesh *cube = tu_cube();
    resurf_save_options bad;
    memset(&bad, 0, sizeof bad);
    ck_assert_int_eq(resurf_mesh_save(cube, "/tmp/never-written.obj", &bad, &error), RESURF_ERR_INVALID_OPTIONS);
    ck_assert_int_eq(resurf_mesh_save(NULL, "/tmp/never-written.obj", NULL, &error), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurf_mesh_save(cube, NULL, NULL, &error), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(access("/tmp/never-written.obj", F_OK), -1);
    resurf_mesh_free(cube);
}
END_TEST

/* A file that cannot be opened: the message is strerror's, and the path is the one given, unchanged. */
START_TEST(io_load_missing_file)
{
    const char *path = "/nonexistent-resurf-dir/../nonexistent-resurf-dir/mesh.obj";
    resurf_mesh *mesh = NULL;
    resurf_error error;
    ck_assert_int_eq(resurf_mesh_load(path, NULL, &mesh, &error), RESURF_ERR_IO);
    ck_assert_ptr_null(mesh);
    char expected[300], text[600];
    snprintf(expected, sizeof expected, "%s: cannot open: %s", path, strerror(ENOENT));
    resurf_format_error(text, sizeof text, &error);
    ck_assert_str_eq(text, expected);
    ck_assert_str_eq(error.path, path);
}
END_TEST

START_TEST(io_load_directory_and_empty_file)
{
    char *dir = tu_tempdir(), *sub = tu_path(dir, "folder.obj"), *empty = tu_path(dir, "empty.ply");
    ck_assert_int_eq(mkdir(sub, 0700), 0);
    resurf_mesh *mesh = NULL;
    resurf_error error;
    char text[600], expected[600];
    ck_assert_int_eq(resurf_mesh_load(sub, NULL, &mesh, &error), RESURF_ERR_IO);
    resurf_format_error(text, sizeof text, &error);
    snprintf(expected, sizeof expected, "%s: is a directory, not a mesh file", sub);
    ck_assert_str_eq(text, expected);
    write_text(empty, "");
    ck_assert_int_eq(resurf_mesh_load(empty, NULL, &mesh, &error), RESURF_ERR_PARSE);
    resurf_format_error(text, sizeof text, &error);
    snprintf(expected, sizeof expected, "%s: the file is empty", empty);
    ck_assert_str_eq(text, expected);
    ck_assert_ptr_null(mesh);
    tu_rmtree(dir);
    free(dir), free(sub), free(empty);
}
END_TEST

/* The extension decides, options.format overrides it, and content decides when the name cannot. */
START_TEST(io_format_choice)
{
    char *dir = tu_tempdir(), *as_ply = tu_path(dir, "cube.ply"), *noext = tu_path(dir, "cube"),
         *junk = tu_path(dir, "junk.dat");
    write_text(as_ply, cube_obj);
    write_text(noext, cube_obj);
    write_text(junk, "hello world\n");
    resurf_mesh *mesh = NULL;
    resurf_error error;
    ck_assert_int_eq(resurf_mesh_load(as_ply, NULL, &mesh, &error), RESURF_ERR_PARSE); /* read as PLY */
    ck_assert_str_eq(error.message, "not a PLY file (the first line is not \"ply\")");
    resurf_load_options o = resurf_load_options_default();
    o.format = RESURF_FORMAT_OBJ;
    ck_assert_int_eq(resurf_mesh_load(as_ply, &o, &mesh, &error), RESURF_OK);
    ck_assert_uint_eq(mesh->triangle_count, 12);
    resurf_mesh_free(mesh);
    ck_assert_int_eq(resurf_mesh_load(noext, NULL, &mesh, &error), RESURF_OK); /* sniffed: OBJ statements */
    ck_assert_uint_eq(mesh->vertex_count, 8);
    resurf_mesh_free(mesh);
    ck_assert_int_eq(resurf_mesh_load(junk, NULL, &mesh, &error), RESURF_ERR_UNSUPPORTED);
    ck_assert_ptr_null(mesh);
    resurf_mesh *cube = tu_cube();
    ck_assert_int_eq(resurf_mesh_save(cube, junk, NULL, &error), RESURF_ERR_UNSUPPORTED);
    resurf_mesh_free(cube);
    tu_rmtree(dir);
    free(dir), free(as_ply), free(noext), free(junk);
}
END_TEST

/* Saves the cube in a format and variant; returns the bytes. */
static char *cube_bytes(resurf_format format, int binary, size_t *size)
{
    resurf_mesh *cube = tu_cube();
    char *dir = tu_tempdir(), *path = tu_path(dir, "cube.any");
    resurf_save_options o = resurf_save_options_default();
    o.format = format;
    o.binary = binary;
    ck_assert_int_eq(resurf_mesh_save(cube, path, &o, NULL), RESURF_OK);
    char *data = tu_read_file(path, size);
    tu_rmtree(dir);
    free(dir), free(path);
    resurf_mesh_free(cube);
    return data;
}

static const struct {
    resurf_format format;
    int binary;
} all_variants[] = {
    {RESURF_FORMAT_OBJ, 0}, {RESURF_FORMAT_PLY, 1}, {RESURF_FORMAT_PLY, 0},
    {RESURF_FORMAT_OFF, 0}, {RESURF_FORMAT_STL, 1}, {RESURF_FORMAT_STL, 0},
};

/* From memory without a name: each format is recognised by its content. */
START_TEST(io_sniffs_every_format)
{
    for (size_t k = 0; k < sizeof all_variants / sizeof *all_variants; ++k) {
        size_t size;
        char *data = cube_bytes(all_variants[k].format, all_variants[k].binary, &size);
        resurf_mesh *mesh = NULL;
        resurf_error error;
        ck_assert_msg(resurf_mesh_load_memory(data, size, RESURF_FORMAT_AUTO, NULL, NULL, &mesh, &error) ==
                          RESURF_OK,
                      "variant %zu: %s", k, error.message);
        ck_assert_uint_eq(mesh->triangle_count, 12);
        ck_assert_uint_eq(mesh->vertex_count, 8);
        resurf_mesh_free(mesh);
        free(data);
    }
}
END_TEST

/* max_triangles: 12 triangles load under a limit of 12 (and of 0 = none) and fail with LIMIT under 11. */
START_TEST(io_max_triangles_limit)
{
    for (size_t k = 0; k < sizeof all_variants / sizeof *all_variants; ++k) {
        size_t size;
        char *data = cube_bytes(all_variants[k].format, all_variants[k].binary, &size);
        resurf_load_options o = resurf_load_options_default();
        const size_t limits[] = {11, 12, 0};
        for (int i = 0; i < 3; ++i) {
            o.max_triangles = limits[i];
            resurf_mesh *mesh = NULL;
            resurf_error error;
            resurf_status s = resurf_mesh_load_memory(data, size, all_variants[k].format, "cube", &o, &mesh, &error);
            ck_assert_msg(s == (i == 0 ? RESURF_ERR_LIMIT : RESURF_OK), "variant %zu limit %zu: %s", k, limits[i],
                          error.message);
            if (i == 0)
                ck_assert_str_eq(error.message, "more than 11 triangles (the max_triangles limit)");
            resurf_mesh_free(mesh);
        }
        free(data);
    }
}
END_TEST

START_TEST(io_save_into_missing_folder_leaves_nothing)
{
    char *dir = tu_tempdir(), *path = tu_path(dir, "missing/cube.ply");
    resurf_mesh *cube = tu_cube();
    resurf_error error;
    ck_assert_int_eq(resurf_mesh_save(cube, path, NULL, &error), RESURF_ERR_IO);
    ck_assert_str_eq(error.path, path);
    ck_assert_ptr_nonnull(strstr(error.message, strerror(ENOENT)));
    ck_assert_int_eq(tu_count_entries(dir), 0);
    resurf_mesh_free(cube);
    tu_rmtree(dir);
    free(dir), free(path);
}
END_TEST

/* A mesh that cannot be saved (an index out of range, a NaN) leaves the old file as it was. */
START_TEST(io_invalid_mesh_keeps_old_file)
{
    char *dir = tu_tempdir(), *path = tu_path(dir, "cube.obj");
    write_text(path, "old content\n");
    resurf_mesh *cube = tu_cube();
    resurf_error error;
    cube->indices[7] = 8;
    ck_assert_int_eq(resurf_mesh_save(cube, path, NULL, &error), RESURF_ERR_INVALID_MESH);
    ck_assert_str_eq(error.message, "triangle 2 refers to vertex 8 of 8");
    cube->indices[7] = 5;
    cube->positions[4] = NAN;
    ck_assert_int_eq(resurf_mesh_save(cube, path, NULL, &error), RESURF_ERR_INVALID_MESH);
    ck_assert_str_eq(error.message, "vertex 1 has a non-finite coordinate");
    char *text = tu_read_file(path, NULL);
    ck_assert_str_eq(text, "old content\n");
    ck_assert_int_eq(tu_count_entries(dir), 1);
    free(text);
    resurf_mesh_free(cube);
    tu_rmtree(dir);
    free(dir), free(path);
}
END_TEST

/* A write that fails half-way (the file-size limit stops it) leaves the old file whole and no temporary file. */
START_TEST(io_failed_write_keeps_old_file)
{
    char *dir = tu_tempdir(), *path = tu_path(dir, "grid.obj");
    write_text(path, "old content\n");
    resurf_mesh *grid = tu_grid(60); /* 7200 triangles: far over 64 KiB as OBJ */
    struct rlimit old_limit, limit;
    ck_assert_int_eq(getrlimit(RLIMIT_FSIZE, &old_limit), 0);
    limit = old_limit;
    limit.rlim_cur = 65536;
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    ck_assert_int_eq(setrlimit(RLIMIT_FSIZE, &limit), 0);
    resurf_error error;
    resurf_status s = resurf_mesh_save(grid, path, NULL, &error);
    setrlimit(RLIMIT_FSIZE, &old_limit);
    signal(SIGXFSZ, old_handler);
    ck_assert_int_eq(s, RESURF_ERR_IO);
    char expected[300];
    snprintf(expected, sizeof expected, "cannot write: %s", strerror(EFBIG));
    ck_assert_str_eq(error.message, expected);
    char *text = tu_read_file(path, NULL);
    ck_assert_str_eq(text, "old content\n");
    ck_assert_int_eq(tu_count_entries(dir), 1);
    free(text);
    resurf_mesh_free(grid);
    tu_rmtree(dir);
    free(dir), free(path);
}
END_TEST

/* A successful save replaces the file, keeps its permissions and leaves no temporary file behind. */
START_TEST(io_save_replaces_file)
{
    char *dir = tu_tempdir(), *path = tu_path(dir, "mesh.off");
    write_text(path, "old content\n");
    ck_assert_int_eq(chmod(path, 0640), 0);
    resurf_mesh *cube = tu_cube();
    ck_assert_int_eq(resurf_mesh_save(cube, path, NULL, NULL), RESURF_OK);
    ck_assert_int_eq(tu_count_entries(dir), 1);
    struct stat st;
    ck_assert_int_eq(stat(path, &st), 0);
    ck_assert_int_eq(st.st_mode & 0777, 0640);
    resurf_mesh *back = NULL;
    ck_assert_int_eq(resurf_mesh_load(path, NULL, &back, NULL), RESURF_OK);
    ck_assert_uint_eq(back->triangle_count, 12);
    ck_assert_mem_eq(back->positions, cube->positions, 24 * sizeof(double));
    resurf_mesh_free(back);
    resurf_mesh_free(cube);
    tu_rmtree(dir);
    free(dir), free(path);
}
END_TEST

typedef struct progress_log {
    int calls, cancel_at;
    double last;
    int decreasing;
} progress_log;

static bool record_progress(void *user, resurf_stage stage, double fraction)
{
    progress_log *log = user;
    ck_assert(stage == RESURF_STAGE_LOAD || stage == RESURF_STAGE_SAVE);
    if (fraction < log->last)
        log->decreasing = 1;
    log->last = fraction;
    return ++log->calls == log->cancel_at;
}

/* Progress comes in non-decreasing fractions ending at 1; a cancel stops loading (no mesh) and saving (the old
 * file stays, no temporary file). */
START_TEST(io_progress_and_cancel)
{
    char *dir = tu_tempdir(), *path = tu_path(dir, "grid.obj");
    resurf_mesh *grid = tu_grid(300); /* 180,000 triangles: several progress steps */
    progress_log log = {0, 0, 0, 0};
    resurf_save_options so = resurf_save_options_default();
    so.progress = (resurf_progress){record_progress, &log};
    ck_assert_int_eq(resurf_mesh_save(grid, path, &so, NULL), RESURF_OK);
    ck_assert_int_ge(log.calls, 3);
    ck_assert(!log.decreasing);
    ck_assert_double_eq(log.last, 1.0);

    log = (progress_log){0, 0, 0, 0};
    resurf_load_options lo = resurf_load_options_default();
    lo.progress = (resurf_progress){record_progress, &log};
    resurf_mesh *mesh = NULL;
    ck_assert_int_eq(resurf_mesh_load(path, &lo, &mesh, NULL), RESURF_OK);
    ck_assert_int_ge(log.calls, 3);
    ck_assert(!log.decreasing);
    ck_assert_double_eq(log.last, 1.0);
    resurf_mesh_free(mesh);
    mesh = NULL;

    log = (progress_log){0, 2, 0, 0};
    resurf_error error;
    ck_assert_int_eq(resurf_mesh_load(path, &lo, &mesh, &error), RESURF_ERR_CANCELLED);
    ck_assert_ptr_null(mesh);

    size_t before_size;
    char *before = tu_read_file(path, &before_size);
    log = (progress_log){0, 1, 0, 0};
    grid->positions[0] = 0.5; /* a different mesh, that must not land */
    ck_assert_int_eq(resurf_mesh_save(grid, path, &so, &error), RESURF_ERR_CANCELLED);
    size_t after_size;
    char *after = tu_read_file(path, &after_size);
    ck_assert_uint_eq(before_size, after_size);
    ck_assert_mem_eq(before, after, before_size);
    ck_assert_int_eq(tu_count_entries(dir), 1);
    free(before), free(after);
    resurf_mesh_free(grid);
    tu_rmtree(dir);
    free(dir), free(path);
}
END_TEST

/* resurfi_parse_double gives exactly strtod's correctly rounded result, on the fast paths and off them. */
static void check_parse(const char *text)
{
    double mine = 0;
    const char *end = resurfi_parse_double(text, text + strlen(text), &mine);
    char *stop;
    double ref = strtod(text, &stop);
    if (*text == 0 || *stop != 0 || stop == text) {
        ck_assert_msg(end == NULL, "'%s' should not parse", text);
        return;
    }
    ck_assert_msg(end == text + strlen(text), "'%s' did not parse", text);
    if (isnan(ref)) {
        ck_assert(isnan(mine));
        return;
    }
    ck_assert_msg(memcmp(&mine, &ref, sizeof mine) == 0, "'%s': %.17g, strtod %.17g", text, mine, ref);
}

START_TEST(io_parse_double_matches_strtod)
{
    static const char *const fixed[] = {
        "0", "-0", "+1", ".5", "5.", "1e5", "1E-5", "1e+5", "-.25e1", "00012.5000", "inf", "-Infinity", "nan",
        "1e400", "-1e400", "1e-400", "4.9406564584124654e-324", "2.2250738585072011e-308", "1.7976931348623157e308",
        "9007199254740993", "9007199254740993.0", "9007199254740995", "18014398509481985", "0.1", "0.3",
        "123456789012345678", "1234567890123456789", "12345678901234567890", "1234567890123456789012345",
        "0.000000000000000000000000000000000000001", "1e22", "1e23", "8.98846567431158e307", "0x1p-3",
        "", ".", "-", "+", "e5", "1e", "1e+", "1.2.3", "0x", "1-2", "--1", "1e5x", "1,5",
    };
    for (size_t i = 0; i < sizeof fixed / sizeof *fixed; ++i)
        check_parse(fixed[i]);
    uint64_t state = 12345;
    char text[64];
    static const char *const formats[] = {"%.17g", "%.16g", "%.15g", "%.9g", "%.3e", "%.20g", "%.19e"};
    for (int i = 0; i < (tu_light() ? 40000 : 200000); ++i) { /* fewer under valgrind and the sanitizers */
        /* random bit patterns: every exponent, every mantissa */
        uint64_t bits = shape_rand_u64(&state);
        double x;
        memcpy(&x, &bits, sizeof x);
        if (!isfinite(x))
            continue;
        snprintf(text, sizeof text, formats[i % 7], x);
        check_parse(text);
        /* random decimals of up to 20 digits with exponents around the fast paths' limits */
        int digits = 1 + (int)(shape_rand_u64(&state) % 20), point = (int)(shape_rand_u64(&state) % (digits + 1));
        int n = 0;
        if (shape_rand_u64(&state) & 1)
            text[n++] = '-';
        for (int d = 0; d < digits; ++d) {
            if (d == point)
                text[n++] = '.';
            text[n++] = (char)('0' + shape_rand_u64(&state) % 10);
        }
        n += snprintf(text + n, sizeof text - (size_t)n, "e%d", (int)(shape_rand_u64(&state) % 61) - 30);
        check_parse(text);
    }
}
END_TEST

/* The scanner counts lines across "\r\n", comments and continuations, and integers report overflow. */
START_TEST(io_scanner_lines_and_integers)
{
    const char *text = "  12 -7 \r\n# comment\n\n  +3 x 99999999999999999999 \\\n 5";
    resurfi_scanner s;
    resurfi_scan_init(&s, text, strlen(text));
    long long v;
    ck_assert_int_eq(resurfi_scan_int(&s, &v), RESURFI_NUM_OK);
    ck_assert_int_eq(v, 12);
    ck_assert_int_eq(resurfi_scan_int(&s, &v), RESURFI_NUM_OK);
    ck_assert_int_eq(v, -7);
    ck_assert_int_eq(resurfi_scan_int(&s, &v), RESURFI_NUM_NONE);
    ck_assert(resurfi_scan_skip_space(&s, '#'));
    ck_assert_int_eq(s.line, 4);
    ck_assert_int_eq(resurfi_scan_int(&s, &v), RESURFI_NUM_OK);
    ck_assert_int_eq(v, 3);
    ck_assert_int_eq(resurfi_scan_int(&s, &v), RESURFI_NUM_BAD);
    s.p += 1;
    ck_assert_int_eq(resurfi_scan_int(&s, &v), RESURFI_NUM_RANGE);
    s.continuation = true;
    s.p = strstr(text, "\\");
    resurfi_scan_blanks(&s);
    ck_assert_int_eq(s.line, 5);
    double d;
    ck_assert_int_eq(resurfi_scan_double(&s, &d), RESURFI_NUM_OK);
    ck_assert_double_eq(d, 5);
    ck_assert(!resurfi_scan_skip_space(&s, 0));
}
END_TEST

/* Under a locale whose decimal point is a comma, files are still written and read with '.'. The locale is
 * compiled into the test's folder with localedef; where that tool or the locale sources are missing the test
 * says so and checks nothing else. */
START_TEST(io_ignores_the_locale)
{
    char *dir = tu_tempdir(), *path = tu_path(dir, "m.obj");
    char command[600];
    snprintf(command, sizeof command, "localedef -i de_DE -f UTF-8 '%s/de_DE.UTF-8'", dir);
    int made = tu_run(command, NULL);
    setenv("LOCPATH", dir, 1);
    if (made != 0 || !setlocale(LC_NUMERIC, "de_DE.UTF-8")) {
        fprintf(stderr, "io_ignores_the_locale: no de_DE locale could be made here; not checked\n");
        tu_rmtree(dir);
        free(dir), free(path);
        return;
    }
    char probe[16];
    snprintf(probe, sizeof probe, "%.1f", 0.5);
    ck_assert_str_eq(probe, "0,5"); /* the locale is really in effect */
    static const double p[] = {0.5, 1.25, -3.75, 1e-300, 2, 3, 4, 5, 6.125};
    static const uint32_t t[] = {0, 1, 2};
    resurf_mesh *m = tu_mesh(p, 3, t, 1);
    ck_assert_int_eq(resurf_mesh_save(m, path, NULL, NULL), RESURF_OK);
    char *text = tu_read_file(path, NULL);
    ck_assert_ptr_nonnull(strstr(text, "v 0.5 1.25 -3.75\n"));
    resurf_mesh *back = NULL;
    ck_assert_int_eq(resurf_mesh_load(path, NULL, &back, NULL), RESURF_OK);
    ck_assert_mem_eq(back->positions, p, sizeof p);
    snprintf(probe, sizeof probe, "%.1f", 0.5);
    ck_assert_str_eq(probe, "0,5"); /* and the caller's locale is back */
    setlocale(LC_NUMERIC, "C");
    free(text);
    resurf_mesh_free(m);
    resurf_mesh_free(back);
    tu_rmtree(dir);
    free(dir), free(path);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("io");
    TCase *tc = tcase_create("io");
    tcase_add_test(tc, io_format_from_path_and_name);
    tcase_add_test(tc, io_options_defaults_and_checks);
    tcase_add_test(tc, io_load_missing_file);
    tcase_add_test(tc, io_load_directory_and_empty_file);
    tcase_add_test(tc, io_format_choice);
    tcase_add_test(tc, io_sniffs_every_format);
    tcase_add_test(tc, io_max_triangles_limit);
    tcase_add_test(tc, io_save_into_missing_folder_leaves_nothing);
    tcase_add_test(tc, io_invalid_mesh_keeps_old_file);
    tcase_add_test(tc, io_failed_write_keeps_old_file);
    tcase_add_test(tc, io_save_replaces_file);
    tcase_add_test(tc, io_progress_and_cancel);
    tcase_add_test(tc, io_parse_double_matches_strtod);
    tcase_add_test(tc, io_scanner_lines_and_integers);
    tcase_add_test(tc, io_ignores_the_locale);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
