/* Hostile input at the command line. Every file of tests/corpus/ goes through `resurf convert` and `resurf info`:
 * each must fail with exit status 1, print exactly one line on stderr ("resurf: PATH...: message", the message of
 * tests/corpus/EXPECTED, written by hand) and nothing on stdout, and leave the output folder empty. Then what is
 * not a mesh file at all (folders, devices, FIFOs, endless pipes, paths through a file, missing or unreadable
 * files), the --max-triangles limit of every command that loads meshes, degenerate geometry (collinear,
 * coincident, a single triangle), and interrupts: SIGTERM or SIGINT while a big mesh is being written leaves no
 * temporary file and the previous output intact. */
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "testutil.h"

#define CORPUS RESURF_SOURCE_DIR "/tests/corpus"

static char *dir;    /* scratch: inputs and captured output */
static char *outdir; /* where the commands write; must stay empty after a failure */

static void setup(void)
{
    dir = tu_tempdir();
    outdir = tu_path(dir, "out");
    ck_assert_int_eq(mkdir(outdir, 0755), 0);
}

static void teardown(void)
{
    tu_rmtree(dir);
    free(dir);
    free(outdir);
}

/* What one CLI run left: exit status (128 + N after signal N, as the shell reports it), stdout, stderr. */
typedef struct run_result {
    int status;
    char *out, *err;
} run_result;

static void run_free(run_result *r)
{
    free(r->out);
    free(r->err);
}

/* Put before the CLI in run(): "" or a command that runs it as another user. */
static const char *run_as = "";

/* Runs `resurf ARGS` through the shell with stdout and stderr captured apart (in files of dir; the braces keep
 * the "2>&1" that tu_run appends from joining them). */
static run_result run(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static run_result run(const char *fmt, ...)
{
    char args[4096], cmd[8192];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(args, sizeof args, fmt, ap);
    va_end(ap);
    char *out = tu_path(dir, "stdout.txt"), *err = tu_path(dir, "stderr.txt");
    snprintf(cmd, sizeof cmd, "{ %s%s %s >'%s' 2>'%s' </dev/null; }", run_as, RESURF_CLI, args, out, err);
    run_result r;
    r.status = tu_run(cmd, NULL);
    r.out = tu_read_file(out, NULL);
    r.err = tu_read_file(err, NULL);
    ck_assert_ptr_nonnull(r.out);
    ck_assert_ptr_nonnull(r.err);
    unlink(out);
    unlink(err);
    free(out);
    free(err);
    return r;
}

/* A failed job: status 1, nothing on stdout, exactly `line` (plus a newline) on stderr, no file in outdir. */
static void expect_failure(run_result r, const char *line, const char *what)
{
    ck_assert_msg(r.status == 1, "%s: exit status %d (stderr: %s)", what, r.status, r.err);
    ck_assert_msg(r.out[0] == 0, "%s: stdout is not empty: %s", what, r.out);
    size_t n = strlen(r.err);
    ck_assert_msg(n > 0 && r.err[n - 1] == '\n' && strchr(r.err, '\n') == r.err + n - 1,
                  "%s: stderr is not one line: '%s'", what, r.err);
    r.err[n - 1] = 0;
    ck_assert_msg(!strcmp(r.err, line), "%s:\n  got      %s\n  expected %s", what, r.err, line);
    ck_assert_msg(tu_count_entries(outdir) == 0, "%s: a file was left in the output folder", what);
    run_free(&r);
}

/* Fails both ways a mesh is read: `convert PATH OUT.ply` and `info PATH` (extra: options for both). */
static void expect_unreadable(const char *path, const char *extra, const char *line)
{
    char what[1024];
    snprintf(what, sizeof what, "convert %s", path);
    expect_failure(run("convert '%s' '%s/out.ply' %s", path, outdir, extra), line, what);
    snprintf(what, sizeof what, "info %s", path);
    expect_failure(run("info '%s' %s", path, extra), line, what);
}

/* A tetrahedron in OBJ: 4 faces on lines 5-8, so a limit of 3 trips on line 8. */
static const char tetra_obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

/* ---- the corpus ---------------------------------------------------------------------------------------------- */

/* Every malformed file fails with the message EXPECTED gives for it. */
START_TEST(hostile_corpus_files_fail_with_one_line)
{
    char *text = tu_read_file(CORPUS "/EXPECTED", NULL);
    ck_assert_ptr_nonnull(text);
    size_t cases = 0;
    for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
        if (line[0] == '#' || !line[0])
            continue;
        char *tab1 = strchr(line, '\t'), *tab2 = tab1 ? strchr(tab1 + 1, '\t') : NULL;
        ck_assert_msg(tab1 && tab2, "bad manifest line: %s", line);
        *tab1 = 0;
        char path[512], expected[1024];
        snprintf(path, sizeof path, "%s/%s", CORPUS, line);
        snprintf(expected, sizeof expected, "resurf: %s%s", path, tab2 + 1);
        expect_unreadable(path, "", expected);
        ++cases;
    }
    free(text);
    /* The corpus covers each format with many cases; a manifest that lost its lines must not pass quietly. */
    ck_assert_uint_ge(cases, 70);
}
END_TEST

/* Every corpus file has a manifest line (a file added without its expected message would go untested). */
START_TEST(hostile_corpus_manifest_lists_every_file)
{
    char *text = tu_read_file(CORPUS "/EXPECTED", NULL);
    ck_assert_ptr_nonnull(text);
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "ls '%s'", CORPUS);
    char *listing = NULL;
    ck_assert_int_eq(tu_run(cmd, &listing), 0);
    for (char *name = strtok(listing, "\n"); name; name = strtok(NULL, "\n")) {
        if (!strcmp(name, "EXPECTED"))
            continue;
        char needle[300];
        snprintf(needle, sizeof needle, "\n%s\t", name);
        ck_assert_msg(strstr(text, needle), "%s has no line in EXPECTED", name);
    }
    free(listing);
    free(text);
}
END_TEST

/* ---- what is not a mesh file --------------------------------------------------------------------------------- */

START_TEST(hostile_directory_missing_and_non_directory_paths)
{
    char line[1024];
    snprintf(line, sizeof line, "resurf: %s: is a directory, not a mesh file", outdir);
    expect_unreadable(outdir, "", line);

    char *missing = tu_path(dir, "missing.ply");
    snprintf(line, sizeof line, "resurf: %s: cannot open: No such file or directory", missing);
    expect_unreadable(missing, "", line);

    /* A path that goes through a regular file as if it were a folder. */
    char *file = tu_path(dir, "file.ply");
    ck_assert_int_eq(tu_write_file(file, "ply\n", 4), 0);
    char *through = tu_path(file, "x.ply");
    snprintf(line, sizeof line, "resurf: %s: cannot open: Not a directory", through);
    expect_unreadable(through, "", line);
    free(missing);
    free(file);
    free(through);
}
END_TEST

/* Devices are refused without reading them: /dev/zero would never end, /dev/null is not a mesh either. */
START_TEST(hostile_devices_are_refused)
{
    expect_unreadable("/dev/zero", "", "resurf: /dev/zero: is a device or socket, not a mesh file");
    expect_unreadable("/dev/null", "", "resurf: /dev/null: is a device or socket, not a mesh file");
}
END_TEST

/* A FIFO that no process writes to reads as empty at once (opening it must not wait for a writer forever). */
START_TEST(hostile_fifo_without_writer_does_not_hang)
{
    char *fifo = tu_path(dir, "fifo.obj");
    ck_assert_int_eq(mkfifo(fifo, 0644), 0);
    char line[1024];
    snprintf(line, sizeof line, "resurf: %s: the file is empty", fifo);
    time_t start = time(NULL);
    expect_unreadable(fifo, "", line);
    ck_assert_int_lt(time(NULL) - start, 30);
    free(fifo);
}
END_TEST

/* An endless pipe stops at the stream limit: 64 MiB + 1 KiB per allowed triangle (1000 here: 68,132,864 bytes). */
START_TEST(hostile_endless_pipe_stops_at_the_stream_limit)
{
    const char *line = "resurf: /dev/stdin: the stream goes on past 68132864 bytes, more than the max_triangles limit "
                       "(1000 triangles) can need";
    char *out = tu_path(dir, "stdout.txt"), *err = tu_path(dir, "stderr.txt");
    const char *commands[2] = {"info /dev/stdin --max-triangles 1000", NULL};
    char convert[1024];
    snprintf(convert, sizeof convert, "convert /dev/stdin '%s/out.ply' --from obj --max-triangles 1000", outdir);
    commands[1] = convert;
    for (int k = 0; k < 2; ++k) {
        char cmd[4096];
        /* `yes` writes "v 1 2 3" lines forever; it dies of SIGPIPE once resurf closes the pipe. */
        snprintf(cmd, sizeof cmd, "{ yes 'v 1 2 3' | %s %s >'%s' 2>'%s'; }", RESURF_CLI, commands[k], out, err);
        run_result r;
        r.status = tu_run(cmd, NULL);
        r.out = tu_read_file(out, NULL);
        r.err = tu_read_file(err, NULL);
        expect_failure(r, line, commands[k]);
    }
    free(out);
    free(err);
}
END_TEST

/* An unreadable file. Root reads files whatever their permissions, so as root the CLI runs as user nobody
 * (setpriv, util-linux), for whom the file's mode 000 holds. */
START_TEST(hostile_unreadable_file)
{
    ck_assert_int_eq(chmod(dir, 0755), 0); /* nobody must reach the file itself */
    char *file = tu_path(dir, "secret.obj");
    ck_assert_int_eq(tu_write_file(file, tetra_obj, sizeof tetra_obj - 1), 0);
    ck_assert_int_eq(chmod(file, 0), 0);
    if (geteuid() == 0)
        run_as = "setpriv --reuid=65534 --regid=65534 --clear-groups ";
    char line[1024];
    snprintf(line, sizeof line, "resurf: %s: cannot open: Permission denied", file);
    expect_unreadable(file, "", line);
    run_as = "";
    free(file);
}
END_TEST

/* ---- --max-triangles ----------------------------------------------------------------------------------------- */

START_TEST(hostile_max_triangles_on_every_loading_command)
{
    char *tet = tu_path(dir, "tet.obj");
    ck_assert_int_eq(tu_write_file(tet, tetra_obj, sizeof tetra_obj - 1), 0);
    char line[1024];
    snprintf(line, sizeof line, "resurf: %s:8: more than 3 triangles (the max_triangles limit)", tet);
    expect_failure(run("info '%s' --max-triangles 3", tet), line, "info");
    expect_failure(run("convert '%s' '%s/o.ply' --max-triangles 3", tet, outdir), line, "convert");
    expect_failure(run("smooth '%s' -o '%s/o.ply' --max-triangles 3", tet, outdir), line, "smooth");
    expect_failure(run("compare '%s' '%s' --samples 10 --max-triangles 3", tet, tet), line, "compare");
    expect_failure(run("restore '%s' '%s' -o '%s/o.ply' --max-triangles 3", tet, tet, outdir), line, "restore");
    expect_failure(run("simplify '%s' -o '%s/o.ply' --ratio 0.5 --max-triangles 3", tet, outdir), line, "simplify");

    /* At the limit, and with no limit (0), the same commands succeed. */
    const char *limits[] = {"4", "0"};
    for (int k = 0; k < 2; ++k) {
        run_result r = run("info '%s' --max-triangles %s", tet, limits[k]);
        ck_assert_msg(r.status == 0, "info --max-triangles %s: %s", limits[k], r.err);
        ck_assert_ptr_nonnull(strstr(r.out, "triangles            4\n"));
        run_free(&r);
        r = run("convert '%s' '%s/o%d.ply' --max-triangles %s", tet, outdir, k, limits[k]);
        ck_assert_int_eq(r.status, 0);
        run_free(&r);
        r = run("smooth '%s' -o '%s/s%d.ply' --max-triangles %s", tet, outdir, k, limits[k]);
        ck_assert_int_eq(r.status, 0);
        run_free(&r);
        r = run("compare '%s' '%s' --samples 10 --max-triangles %s", tet, tet, limits[k]);
        ck_assert_int_eq(r.status, 0);
        run_free(&r);
        r = run("restore '%s' '%s' -o '%s/r%d.ply' --max-triangles %s", tet, tet, outdir, k, limits[k]);
        ck_assert_int_eq(r.status, 0);
        run_free(&r);
        r = run("simplify '%s' -o '%s/q%d.ply' --ratio 0.5 --max-triangles %s", tet, outdir, k, limits[k]);
        ck_assert_int_eq(r.status, 0);
        run_free(&r);
    }

    /* A binary PLY is refused at its header, before the data is read: line 7 declares the 4 faces. */
    char *ply = tu_path(dir, "tet.ply");
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_load(tet, NULL, &m, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_mesh_save(m, ply, NULL, NULL), RESURF_OK);
    resurf_mesh_free(m);
    char *header = tu_read_file(ply, NULL);
    const char *face = strstr(header, "element face 4\n");
    ck_assert_ptr_nonnull(face);
    int face_line = 1;
    for (const char *p = header; p < face; ++p)
        face_line += *p == '\n';
    free(header);
    snprintf(line, sizeof line, "resurf: %s:%d: more than 3 triangles (the max_triangles limit)", ply, face_line);
    tu_rmtree(outdir);
    ck_assert_int_eq(mkdir(outdir, 0755), 0);
    expect_failure(run("convert '%s' '%s/o.obj' --max-triangles 3", ply, outdir), line, "convert ply");

    /* Not a whole number: a usage error. */
    const char *bad[] = {"-1", "many", "", "1e9"};
    for (int k = 0; k < 4; ++k) {
        run_result r = run("info '%s' --max-triangles '%s'", tet, bad[k]);
        ck_assert_msg(r.status == 2, "--max-triangles '%s': status %d", bad[k], r.status);
        char expected[256];
        snprintf(expected, sizeof expected,
                 "resurf info: --max-triangles needs a whole number, not '%s' (see 'resurf info --help')\n", bad[k]);
        ck_assert_str_eq(r.err, expected);
        run_free(&r);
    }
    free(tet);
    free(ply);
}
END_TEST

/* ---- degenerate geometry ------------------------------------------------------------------------------------- */

/* Four points on the x axis, three triangles among them: every triangle has zero area. */
static const char collinear_obj[] = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\nf 2 3 4\nf 1 2 4\n";
/* Four vertices at one point, two triangles: both degenerate (a repeated position). */
static const char coincident_obj[] = "v 1 1 1\nv 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\nf 1 3 4\n";
/* One right triangle in the plane z = 0. */
static const char single_obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

/* The number after `"key": ` in a JSON text (NAN when absent or null). */
static double json_number(const char *json, const char *key)
{
    char needle[128];
    snprintf(needle, sizeof needle, "\"%s\": ", key);
    const char *p = strstr(json, needle);
    if (!p)
        return NAN;
    p += strlen(needle);
    char *end = NULL;
    double v = strtod(p, &end);
    return end == p ? NAN : v;
}

/* Runs a command that must succeed (status 0, nothing on stderr); returns its stdout (caller frees). */
static char *run_ok(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static char *run_ok(const char *fmt, ...)
{
    char args[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(args, sizeof args, fmt, ap);
    va_end(ap);
    run_result r = run("%s", args);
    ck_assert_msg(r.status == 0 && r.err[0] == 0, "%s: status %d, stderr: %s", args, r.status, r.err);
    free(r.err);
    return r.out;
}

/* Loads a file the CLI wrote and checks its counts and that its positions are finite. vertices SIZE_MAX (a
 * simplified mesh): any number of vertices and at most `triangles` triangles; else both exact. */
static void expect_mesh_file(const char *path, size_t vertices, size_t triangles)
{
    resurf_mesh *m = NULL;
    resurf_error e;
    ck_assert_msg(resurf_mesh_load(path, NULL, &m, &e) == RESURF_OK, "%s: %s", path, e.message);
    if (vertices == SIZE_MAX) {
        ck_assert_uint_le(m->triangle_count, triangles);
    } else {
        ck_assert_uint_eq(m->vertex_count, vertices);
        ck_assert_uint_eq(m->triangle_count, triangles);
    }
    for (size_t i = 0; i < 3 * m->vertex_count; ++i)
        ck_assert(isfinite(m->positions[i]));
    resurf_mesh_free(m);
}

/* Two mesh files hold the same vertices (positions bit for bit) and triangles. */
static void expect_same_positions(const char *a, const char *b)
{
    resurf_mesh *x = NULL, *y = NULL;
    ck_assert_int_eq(resurf_mesh_load(a, NULL, &x, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_mesh_load(b, NULL, &y, NULL), RESURF_OK);
    ck_assert_uint_eq(x->vertex_count, y->vertex_count);
    ck_assert_uint_eq(x->triangle_count, y->triangle_count);
    ck_assert(memcmp(x->positions, y->positions, 3 * x->vertex_count * sizeof(double)) == 0);
    ck_assert(memcmp(x->indices, y->indices, 3 * x->triangle_count * sizeof(uint32_t)) == 0);
    resurf_mesh_free(x);
    resurf_mesh_free(y);
}

START_TEST(hostile_degenerate_geometry_through_every_command)
{
    static const struct {
        const char *name, *text;
        size_t vertices, triangles, zero_area, degenerate;
    } shapes[] = {
        {"collinear", collinear_obj, 4, 3, 3, 0},
        {"coincident", coincident_obj, 4, 2, 0, 2},
        {"single", single_obj, 3, 1, 0, 0},
    };
    char *single = tu_path(dir, "single.obj");
    ck_assert_int_eq(tu_write_file(single, single_obj, sizeof single_obj - 1), 0);
    for (size_t k = 0; k < sizeof shapes / sizeof *shapes; ++k) {
        char name[64], out[64];
        snprintf(name, sizeof name, "%s.obj", shapes[k].name);
        char *in = tu_path(dir, name);
        ck_assert_int_eq(tu_write_file(in, shapes[k].text, strlen(shapes[k].text)), 0);

        char *json = run_ok("info '%s' --json", in);
        ck_assert_double_eq(json_number(json, "triangles"), (double)shapes[k].triangles);
        ck_assert_double_eq(json_number(json, "zero_area_triangles"), (double)shapes[k].zero_area);
        ck_assert_double_eq(json_number(json, "degenerate_triangles"), (double)shapes[k].degenerate);
        free(json);

        snprintf(out, sizeof out, "%s_converted.ply", shapes[k].name);
        char *converted = tu_path(outdir, out);
        free(run_ok("convert '%s' '%s'", in, converted));
        expect_mesh_file(converted, shapes[k].vertices, shapes[k].triangles);

        snprintf(out, sizeof out, "%s_smoothed.ply", shapes[k].name);
        char *smoothed = tu_path(outdir, out);
        const char *methods[] = {"laplacian", "taubin", "taubin-cot", "bilaplacian"};
        for (int m = 0; m < 4; ++m) {
            free(run_ok("smooth '%s' -o '%s' --method %s --iterations 3", in, smoothed, methods[m]));
            expect_mesh_file(smoothed, shapes[k].vertices, shapes[k].triangles);
        }

        /* Restored onto itself nothing moves (the vertices of M lie on S); onto and from the single triangle the
         * result has the processed mesh's counts and finite positions. */
        snprintf(out, sizeof out, "%s_restored.ply", shapes[k].name);
        char *restored = tu_path(outdir, out);
        free(run_ok("restore '%s' '%s' -o '%s'", in, in, restored));
        expect_same_positions(in, restored);
        free(run_ok("restore '%s' '%s' -o '%s'", single, in, restored));
        expect_mesh_file(restored, shapes[k].vertices, shapes[k].triangles);
        free(run_ok("restore '%s' '%s' -o '%s'", in, single, restored));
        expect_mesh_file(restored, 3, 1);

        /* Simplification keeps at most the triangles that take part (a degenerate one takes none). */
        const char *modes[] = {"inline", "post", "none"};
        for (int m = 0; m < 3; ++m) {
            free(run_ok("simplify '%s' -o '%s' --ratio 0.5 --restore %s", in, restored, modes[m]));
            expect_mesh_file(restored, SIZE_MAX, shapes[k].triangles - shapes[k].degenerate);
        }
        free(restored);

        /* Against itself every distance is 0; against the single triangle, both ways, the figures are finite. */
        json = run_ok("compare '%s' '%s' --json --samples 100", in, in);
        ck_assert_double_eq(json_number(json, "hausdorff"), 0);
        free(json);
        json = run_ok("compare '%s' '%s' --json --samples 100", single, in);
        ck_assert(isfinite(json_number(json, "hausdorff")));
        free(json);
        json = run_ok("compare '%s' '%s' --json --samples 100", in, single);
        ck_assert(isfinite(json_number(json, "hausdorff")));
        free(json);
        free(in);
        free(converted);
        free(smoothed);
    }

    /* Hand-computed for the point (1,1,1) against the triangle (0,0,0) (1,0,0) (0,1,0): its closest point is
     * (1/2,1/2,0) on the hypotenuse, at sqrt(1/4 + 1/4 + 1) = sqrt(1.5); the triangle's farthest point from it is
     * the corner (0,0,0), at sqrt(3). */
    char *coincident = tu_path(dir, "coincident.obj");
    char *json = run_ok("compare '%s' '%s' --json --samples 1000", single, coincident);
    ck_assert_double_eq_tol(json_number(json, "test_to_ref_max"), sqrt(1.5), 1e-12);
    ck_assert_double_eq_tol(json_number(json, "ref_to_test_max"), sqrt(3.0), 1e-12);
    ck_assert_double_eq_tol(json_number(json, "hausdorff"), sqrt(3.0), 1e-12);
    free(json);
    free(coincident);
    free(single);
}
END_TEST

/* ---- interrupts ---------------------------------------------------------------------------------------------- */

/* Starts `resurf convert IN OUT` in the background with stderr to err_path; returns its pid. */
static pid_t spawn_convert(const char *in, const char *out, const char *err_path)
{
    pid_t pid = fork();
    ck_assert_int_ge(pid, 0);
    if (pid == 0) {
        int fd = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd < 0 || dup2(fd, 2) < 0)
            _exit(99);
        execl(RESURF_CLI, RESURF_CLI, "convert", in, out, (char *)NULL);
        _exit(98);
    }
    return pid;
}

/* Is there a temporary file (".NAME.tmp-XXXXXX") in the folder? */
static int has_temp_file(const char *folder)
{
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "ls -A '%s' | grep -q '\\.tmp-'", folder);
    return tu_run(cmd, NULL) == 0;
}

static double now_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Sends `signo` to a CLI converting a 2M-triangle mesh to OBJ once its temporary file exists (it is writing), and
 * checks: exit status 128 + signo within seconds, one line on stderr, no temporary file, and the previous output
 * (if any) byte-identical. */
static void interrupt_while_writing(int signo, int with_previous_output)
{
    char *in = tu_path(dir, "big.ply");
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 2000000, 0.2, 7, 0);
    ck_assert_ptr_nonnull(m);
    ck_assert_uint_ge(m->triangle_count, 1900000);
    ck_assert_int_eq(resurf_mesh_save(m, in, NULL, NULL), RESURF_OK);
    resurf_mesh_free(m);

    char *out = tu_path(outdir, "big.obj");
    static const char previous[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    if (with_previous_output)
        ck_assert_int_eq(tu_write_file(out, previous, sizeof previous - 1), 0);
    char *err = tu_path(dir, "stderr.txt");
    pid_t pid = spawn_convert(in, out, err);

    /* Wait until the temporary file appears: the CLI has loaded the mesh and is writing it. */
    double start = now_seconds();
    while (!has_temp_file(outdir)) {
        int status;
        ck_assert_msg(waitpid(pid, &status, WNOHANG) == 0, "the CLI ended before it began writing");
        ck_assert_msg(now_seconds() - start < 120, "no temporary file after 120 s");
        usleep(2000);
    }
    double sent = now_seconds();
    ck_assert_int_eq(kill(pid, signo), 0);
    int status = 0;
    ck_assert_int_eq(waitpid(pid, &status, 0), pid);
    double took = now_seconds() - sent;

    ck_assert_msg(WIFEXITED(status), "the CLI died of signal %d instead of cleaning up",
                  WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    ck_assert_int_eq(WEXITSTATUS(status), 128 + signo);
    ck_assert_msg(took < 10, "the CLI took %.1f s to stop", took);
    char *text = tu_read_file(err, NULL);
    ck_assert_str_eq(text, signo == SIGINT ? "resurf: interrupted by SIGINT\n" : "resurf: interrupted by SIGTERM\n");
    free(text);

    ck_assert_msg(!has_temp_file(outdir), "a temporary file was left behind");
    if (with_previous_output) {
        ck_assert_int_eq(tu_count_entries(outdir), 1);
        size_t size = 0;
        text = tu_read_file(out, &size);
        ck_assert_uint_eq(size, sizeof previous - 1);
        ck_assert(memcmp(text, previous, size) == 0);
        free(text);
    } else {
        ck_assert_int_eq(tu_count_entries(outdir), 0);
    }
    free(in);
    free(out);
    free(err);
}

START_TEST(hostile_sigterm_while_writing_keeps_the_old_output)
{
    interrupt_while_writing(SIGTERM, 1);
}
END_TEST

START_TEST(hostile_sigint_while_writing_leaves_nothing)
{
    interrupt_while_writing(SIGINT, 0);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("hostile");
    TCase *tc = tcase_create("corpus");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, hostile_corpus_files_fail_with_one_line);
    tcase_add_test(tc, hostile_corpus_manifest_lists_every_file);
    tcase_add_test(tc, hostile_directory_missing_and_non_directory_paths);
    tcase_add_test(tc, hostile_devices_are_refused);
    tcase_add_test(tc, hostile_fifo_without_writer_does_not_hang);
    tcase_add_test(tc, hostile_endless_pipe_stops_at_the_stream_limit);
    tcase_add_test(tc, hostile_unreadable_file);
    suite_add_tcase(s, tc);

    tc = tcase_create("limits");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, hostile_max_triangles_on_every_loading_command);
    tcase_add_test(tc, hostile_degenerate_geometry_through_every_command);
    suite_add_tcase(s, tc);

    tc = tcase_create("interrupts");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, hostile_sigterm_while_writing_keeps_the_old_output);
    tcase_add_test(tc, hostile_sigint_while_writing_leaves_nothing);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
