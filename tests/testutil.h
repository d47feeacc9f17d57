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
/* resurf_compare of test against ref with `samples` samples a side (the other options the defaults), asserted OK:
 * a measurement apart from the simplifier's report. */
resurf_compare_report tu_compare(const resurf_mesh *ref, const resurf_mesh *test, size_t samples);

/* ---- glTF documents (the test_gltf_* suites) ---- */

/* printf into a malloc'ed string. */
char *tu_strf(const char *fmt, ...);
/* Errors the Khronos validator finds in a .gltf/.glb (fails the test when the validator cannot run). */
int tu_validator_errors(const char *path);
/* Runs a node script (JavaScript source) with the file as its argument; returns its trimmed stdout. */
char *tu_node_eval(const char *dir, const char *script, const char *file);
/* The JSON of a .gltf or of a .glb's first chunk, as a JavaScript expression `doc` in node scripts. */
#define TU_JS_LOAD                                                                                              \
    "const fs=require('fs');const b=fs.readFileSync(process.argv[2]);"                                        \
    "const doc=JSON.parse(b.slice(0,4).toString()==='glTF'?b.slice(20,20+b.readUInt32LE(12)).toString():b.toString());"

/* A growable byte buffer for hand-written .bin files (little-endian, as glTF requires). */
typedef struct tu_bytes {
    unsigned char *data;
    size_t size;
} tu_bytes;

void tu_put(tu_bytes *b, const void *p, size_t n);
void tu_put_f32(tu_bytes *b, float x);
void tu_put_u8(tu_bytes *b, uint8_t x);
void tu_put_u16(tu_bytes *b, uint16_t x);
void tu_put_i16(tu_bytes *b, int16_t x);
void tu_align4(tu_bytes *b);
/* Writes DIR/NAME.gltf with the JSON and DIR/NAME.bin with the bytes; returns the .gltf path. */
char *tu_write_gltf(const char *dir, const char *name, const char *json, const tu_bytes *bin);
/* resurf_scene_load and resurf_scene_save that fail the test, with the library's message, unless they succeed. */
resurf_scene *tu_load_scene_ok(const char *path);
void tu_save_scene_ok(const resurf_scene *s, const char *path, const resurf_scene_save_options *o,
                      resurf_scene_save_report *r);
/* A tetrahedron (4 positions, 4 triangles) in a .bin: positions at 0..47, indices (uint16) at 48..71, described
 * by TU_TETRA_ACCESSORS (0: POSITION, 1: indices) over TU_TETRA_VIEWS (0 and 1) of buffer 0. */
tu_bytes tu_tetra_bin(void);
#define TU_TETRA_ACCESSORS                                                                                     \
    "{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\"min\":[-1,-1,-1],\"max\":[1,1,1]}," \
    "{\"bufferView\":1,\"componentType\":5123,\"count\":12,\"type\":\"SCALAR\"}"
#define TU_TETRA_VIEWS "{\"buffer\":0,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,\"byteLength\":24}"

#endif
