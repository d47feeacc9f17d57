/* Shared helpers for resurf's Check suites. */
#ifndef RESURF_TESTUTIL_H
#define RESURF_TESTUTIL_H

#include <check.h>
#include <stdlib.h>

#include "internal.h"
#include "shapes.h"

/* Each test file defines `Suite *make_suite(void)` and ends with RESURF_TEST_MAIN(). A run that ran no test (a
 * CK_RUN_CASE naming no case) fails. */
#define RESURF_TEST_MAIN()                                                                                      \
    int main(void)                                                                                              \
    {                                                                                                           \
        SRunner *runner = srunner_create(make_suite());                                                         \
        srunner_run_all(runner, CK_NORMAL);                                                                     \
        int failed = srunner_ntests_failed(runner) + (srunner_ntests_run(runner) == 0);                         \
        srunner_free(runner);                                                                                   \
        return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;                                                       \
    }

/* A fresh empty directory under /tmp for one test; removed with tu_rmtree. Returns a static-lifetime copy. */
char *tu_tempdir(void);
void tu_rmtree(const char *dir);
/* path = dir + "/" + name, malloc'ed. */
char *tu_path(const char *dir, const char *name);
/* Writes bytes to a file; returns 0 on success. */
int tu_write_file(const char *path, const void *data, size_t size);
/* Reads a whole file (malloc'ed, NUL-terminated); *size may be NULL. NULL on error. */
char *tu_read_file(const char *path, size_t *size);
/* Runs a shell command, capturing stdout+stderr into *out (malloc'ed, may be NULL); returns the exit status. */
int tu_run(const char *command, char **out);
/* Number of entries in a directory (excluding . and ..). */
int tu_count_entries(const char *dir);
/* Whether the suite runs under a sanitizer or valgrind (RESURF_TEST_LIGHT, set by tests/meson.build), where the
 * few inputs that cost minutes there shrink or run fewer times, taking the same code paths. */
int tu_light(void);

/* A mesh from literal arrays (copies them). */
resurf_mesh *tu_mesh(const double *positions, size_t vertex_count, const uint32_t *indices, size_t triangle_count);
/* Fixtures, drawn in testutil.c: a regular tetrahedron (closed, 4 v, 4 t), an axis cube (closed, 8 v, 12 t),
 * an n×n grid of squares on z = 0 over [0,1]² (open, 2n² triangles). */
resurf_mesh *tu_tetrahedron(void);
resurf_mesh *tu_cube(void);
resurf_mesh *tu_grid(unsigned n);

#endif
