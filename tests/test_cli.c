/* The resurf command-line tool: exit statuses, one-line errors, output safety, info and convert. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "testutil.h"

static char *dir;

static void setup(void) { dir = tu_tempdir(); }
static void teardown(void)
{
    tu_rmtree(dir);
    free(dir);
}

/* Runs the CLI with arguments; returns the exit status and the output in *out (caller frees). */
static int cli(char **out, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int cli(char **out, const char *fmt, ...)
{
    char args[4096], cmd[8192];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(args, sizeof args, fmt, ap);
    va_end(ap);
    snprintf(cmd, sizeof cmd, "%s %s", RESURF_CLI, args);
    return tu_run(cmd, out);
}

static char *save_shape(shape_kind kind, const char *name)
{
    resurf_mesh *m = shape_mesh(kind, 500, 0.3, 1, 0);
    char *path = tu_path(dir, name);
    ck_assert_int_eq(resurf_mesh_save(m, path, NULL, NULL), RESURF_OK);
    resurf_mesh_free(m);
    return path;
}

START_TEST(cli_version_and_help)
{
    char *out;
    ck_assert_int_eq(cli(&out, "--version"), 0);
    ck_assert_str_eq(out, "resurf " RESURF_VERSION_STRING "\n");
    free(out);
    ck_assert_int_eq(cli(&out, "--help"), 0);
    ck_assert_ptr_nonnull(strstr(out, "convert"));
    free(out);
    const char *commands[] = {"info", "convert", "restore", "smooth", "compare"};
    for (size_t i = 0; i < sizeof commands / sizeof *commands; ++i) {
        ck_assert_int_eq(cli(&out, "%s --help", commands[i]), 0);
        ck_assert_msg(strncmp(out, "usage: resurf ", 14) == 0, "%s --help: %s", commands[i], out);
        free(out);
    }
}
END_TEST

START_TEST(cli_usage_errors_exit_2)
{
    char *out;
    ck_assert_int_eq(cli(&out, "frobnicate"), 2);
    ck_assert_str_eq(out, "resurf: unknown command 'frobnicate' (see 'resurf --help')\n");
    free(out);
    ck_assert_int_eq(cli(&out, "info"), 2);
    ck_assert_str_eq(out, "resurf info: expected one FILE (see 'resurf info --help')\n");
    free(out);
    ck_assert_int_eq(cli(&out, "info --bogus x.obj"), 2);
    free(out);
    ck_assert_int_eq(cli(&out, "convert a.obj"), 2);
    free(out);
    ck_assert_int_eq(cli(&out, "convert a.obj b.xyz"), 2);
    free(out);
    ck_assert_int_eq(cli(&out, "lod a.glb -o b.glb --feature-angle 0"), 2);
    ck_assert_str_eq(out, "resurf lod: --feature-angle must be in (0, 180], not 0 (see 'resurf lod --help')\n");
    free(out);
    ck_assert_int_eq(cli(&out, "simplify a.obj -o b.obj --ratio 0.5 --corner-angle 181"), 2);
    ck_assert_str_eq(out, "resurf simplify: --corner-angle must be in (0, 180], not 181 (see 'resurf simplify --help')\n");
    free(out);
    /* a choice lists every name it accepts */
    ck_assert_int_eq(cli(&out, "simplify a.obj -o b.obj --restore bogus"), 2);
    ck_assert_str_eq(out, "resurf simplify: unknown --restore 'bogus' (inline, post, none, measured) "
                          "(see 'resurf simplify --help')\n");
    free(out);
    ck_assert_int_eq(cli(&out, "lod a.glb -o b.glb --restore bogus"), 2);
    ck_assert_str_eq(out, "resurf lod: unknown --restore 'bogus' (inline, post, none, measured) "
                          "(see 'resurf lod --help')\n");
    free(out);
}
END_TEST

/* A missing input is a failed job (1), reported on one line naming the file. */
START_TEST(cli_missing_file_exit_1)
{
    char *out;
    char *missing = tu_path(dir, "missing.obj");
    ck_assert_int_eq(cli(&out, "info %s", missing), 1);
    ck_assert_msg(strncmp(out, "resurf: ", 8) == 0 && strstr(out, missing), "got: %s", out);
    ck_assert_ptr_eq(strchr(out, '\n'), out + strlen(out) - 1); /* exactly one line */
    free(out);
    free(missing);
}
END_TEST

/* info reports the torus's topology: closed, one component, no boundary. */
START_TEST(cli_info_counts)
{
    char *path = save_shape(SHAPE_TORUS, "torus.ply");
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 500, 0.3, 1, 0);
    char *out, expect[128];
    ck_assert_int_eq(cli(&out, "info --json %s", path), 0);
    snprintf(expect, sizeof expect, "\"vertices\": %zu", m->vertex_count);
    ck_assert_ptr_nonnull(strstr(out, expect));
    snprintf(expect, sizeof expect, "\"triangles\": %zu", m->triangle_count);
    ck_assert_ptr_nonnull(strstr(out, expect));
    ck_assert_ptr_nonnull(strstr(out, "\"components\": 1,"));
    ck_assert_ptr_nonnull(strstr(out, "\"boundary_loops\": 0,"));
    free(out);
    ck_assert_int_eq(cli(&out, "info %s", path), 0);
    ck_assert_ptr_nonnull(strstr(out, "boundary loops       0\n"));
    free(out);
    resurf_mesh_free(m);
    free(path);
}
END_TEST

/* convert through every format keeps the geometry: the cubic patch has one boundary loop everywhere. */
START_TEST(cli_convert_chain)
{
    char *src = save_shape(SHAPE_CUBIC, "cubic.ply");
    const char *names[] = {"a.obj", "b.off", "c.stl", "d.ply"};
    const char *prev = src;
    char *paths[4];
    for (int i = 0; i < 4; ++i) {
        paths[i] = tu_path(dir, names[i]);
        char *out;
        ck_assert_int_eq(cli(&out, "convert %s %s", prev, paths[i]), 0);
        free(out);
        ck_assert_int_eq(cli(&out, "info --json %s", paths[i]), 0);
        ck_assert_msg(strstr(out, "\"boundary_loops\": 1,"), "%s: %s", names[i], out);
        free(out);
        prev = paths[i];
    }
    for (int i = 0; i < 4; ++i)
        free(paths[i]);
    free(src);
}
END_TEST

/* Writing onto the input is refused and the input is untouched; a failed run leaves no file behind. */
START_TEST(cli_convert_never_overwrites_input)
{
    char *src = save_shape(SHAPE_PLANE, "plane.obj");
    size_t before_size;
    char *before = tu_read_file(src, &before_size);
    char *out;
    ck_assert_int_eq(cli(&out, "convert %s %s", src, src), 1);
    ck_assert_ptr_nonnull(strstr(out, "refusing to overwrite an input file"));
    free(out);
    /* The same file through another spelling of its path. */
    ck_assert_int_eq(cli(&out, "convert %s %s/./plane.obj", src, dir), 1);
    free(out);
    size_t after_size;
    char *after = tu_read_file(src, &after_size);
    ck_assert_uint_eq(before_size, after_size);
    ck_assert_int_eq(memcmp(before, after, before_size), 0);
    ck_assert_int_eq(tu_count_entries(dir), 1);
    free(before);
    free(after);
    free(src);
}
END_TEST

START_TEST(cli_failed_convert_leaves_nothing)
{
    char *bad = tu_path(dir, "bad.obj");
    const char text[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
    ck_assert_int_eq(tu_write_file(bad, text, sizeof text - 1), 0);
    char *out;
    ck_assert_int_eq(cli(&out, "convert %s %s/out.ply", bad, dir), 1);
    ck_assert_msg(strncmp(out, "resurf: ", 8) == 0 && strstr(out, "bad.obj:4:"), "got: %s", out);
    free(out);
    ck_assert_int_eq(tu_count_entries(dir), 1);
    /* An output folder that does not exist: failure, nothing written anywhere. */
    char *good = save_shape(SHAPE_PLANE, "good.ply");
    ck_assert_int_eq(cli(&out, "convert %s %s/nope/out.ply", good, dir), 1);
    free(out);
    ck_assert_int_eq(tu_count_entries(dir), 2);
    free(good);
    free(bad);
}
END_TEST

/* The number after the n-th (0-based) `"key": ` in a JSON text, or NAN. */
static double json_nth(const char *json, const char *key, int n)
{
    char needle[128];
    snprintf(needle, sizeof needle, "\"%s\": ", key);
    const char *p = json;
    for (int i = 0; p && i <= n; ++i)
        if ((p = strstr(i ? p + 1 : p, needle)) == NULL)
            return NAN;
    char *end = NULL;
    double v = strtod(p + strlen(needle), &end);
    return end == p + strlen(needle) ? NAN : v;
}

/* compare reads scenes whole in world space, a level of detail with --level: a sphere as OBJ and as a one-mesh
 * .glb measure apart by the glTF's float rounding only; `resurf lod`'s 25% level, measured by compare from the files, is the two-sided error lod
 * printed for it within 10% (two measurements: lod's with its facet points and climb, compare's with 200k samples
 * a side), and its level 0 is the OBJ to float rounding (no Draco). --level on a mesh file is a usage error. */
START_TEST(cli_compare_reads_scenes)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 2000, 0.3, 1, 0);
    char *obj = tu_path(dir, "s.obj"), *glb = tu_path(dir, "s.glb"), *lod = tu_path(dir, "l.glb");
    ck_assert_int_eq(resurf_mesh_save(m, obj, NULL, NULL), RESURF_OK);
    resurf_scene *scene = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(m, &scene, NULL), RESURF_OK);
    tu_save_scene_ok(scene, glb, NULL, NULL);
    resurf_scene_free(scene);
    resurf_mesh_free(m);
    char *out;
    ck_assert_int_eq(cli(&out, "compare %s %s --json", obj, glb), 0);
    ck_assert_double_le(json_nth(out, "hausdorff_rel", 0), 1e-6);
    free(out);
    ck_assert_int_eq(cli(&out, "lod %s -o %s --levels 0.25 --no-draco --json", glb, lod), 0);
    double printed = json_nth(out, "error_rel", 1); /* level 1's: level 0's comes first */
    free(out);
    ck_assert_double_gt(printed, 0);
    ck_assert_int_eq(cli(&out, "compare %s %s --level 1 --json", glb, lod), 0);
    double measured = json_nth(out, "hausdorff_rel", 0);
    free(out);
    ck_assert_msg(fabs(measured - printed) <= 0.1 * printed, "compare %g, lod printed %g", measured, printed);
    ck_assert_int_eq(cli(&out, "compare %s %s --level 0 --json", obj, lod), 0);
    ck_assert_double_le(json_nth(out, "hausdorff_rel", 0), 1e-6);
    free(out);
    ck_assert_int_eq(cli(&out, "compare %s %s --level 1", glb, obj), 2);
    ck_assert_ptr_nonnull(strstr(out, "--level needs TEST to be a scene"));
    free(out);
    free(obj), free(glb), free(lod);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("cli");
    TCase *tc = tcase_create("cli");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, cli_version_and_help);
    tcase_add_test(tc, cli_usage_errors_exit_2);
    tcase_add_test(tc, cli_missing_file_exit_1);
    tcase_add_test(tc, cli_info_counts);
    tcase_add_test(tc, cli_convert_chain);
    tcase_add_test(tc, cli_convert_never_overwrites_input);
    tcase_add_test(tc, cli_failed_convert_leaves_nothing);
    tcase_add_test(tc, cli_compare_reads_scenes);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
