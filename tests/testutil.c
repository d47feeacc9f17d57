/* Shared helpers for the Check suites: temporary folders, files, commands, small fixture meshes and hand-written
 * glTF documents. */
#include <dirent.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "testutil.h"

char *tu_tempdir(void)
{
    char tmpl[] = "/tmp/resurf-test-XXXXXX";
    char *dir = mkdtemp(tmpl);
    ck_assert_ptr_nonnull(dir);
    return strdup(dir);
}

void tu_rmtree(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        char *p = tu_path(dir, e->d_name);
        struct stat st;
        if (lstat(p, &st) == 0 && S_ISDIR(st.st_mode)) {
            chmod(p, 0700);
            tu_rmtree(p);
        } else
            unlink(p);
        free(p);
    }
    closedir(d);
    rmdir(dir);
}

char *tu_path(const char *dir, const char *name)
{
    size_t n = strlen(dir) + strlen(name) + 2;
    char *p = malloc(n);
    snprintf(p, n, "%s/%s", dir, name);
    return p;
}

int tu_write_file(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    size_t w = fwrite(data, 1, size, f);
    return (fclose(f) == 0 && w == size) ? 0 : -1;
}

char *tu_read_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 4096, n = 0;
    char *buf = malloc(cap + 1);
    size_t r;
    while ((r = fread(buf + n, 1, cap - n, f)) > 0) {
        n += r;
        if (n == cap)
            buf = realloc(buf, (cap *= 2) + 1);
    }
    fclose(f);
    buf[n] = 0;
    if (size)
        *size = n;
    return buf;
}

int tu_run(const char *command, char **out)
{
    size_t n = strlen(command) + 16;
    char *full = malloc(n);
    snprintf(full, n, "%s 2>&1", command);
    FILE *p = popen(full, "r");
    free(full);
    if (!p)
        return -1;
    size_t cap = 4096, len = 0;
    char *buf = malloc(cap + 1);
    size_t r;
    while ((r = fread(buf + len, 1, cap - len, p)) > 0) {
        len += r;
        if (len == cap)
            buf = realloc(buf, (cap *= 2) + 1);
    }
    buf[len] = 0;
    int status = pclose(p);
    if (out)
        *out = buf;
    else
        free(buf);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int tu_light(void)
{
    const char *v = getenv("RESURF_TEST_LIGHT");
    return v && *v && strcmp(v, "0") != 0;
}

int tu_count_entries(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."))
            ++n;
    closedir(d);
    return n;
}

resurf_mesh *tu_mesh(const double *positions, size_t vertex_count, const uint32_t *indices, size_t triangle_count)
{
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(vertex_count, triangle_count, 0, &m, NULL), RESURF_OK);
    memcpy(m->positions, positions, vertex_count * 3 * sizeof(double));
    memcpy(m->indices, indices, triangle_count * 3 * sizeof(uint32_t));
    return m;
}

/* Regular tetrahedron on alternate corners of the cube [−1,1]³, faces outward:
 *        3
 *       /|\      0 = ( 1,  1,  1)   1 = ( 1, −1, −1)
 *      / | \     2 = (−1,  1, −1)   3 = (−1, −1,  1)
 *     0--+--2
 *      \ | /
 *       \|/
 *        1                                                                                                         */
resurf_mesh *tu_tetrahedron(void)
{
    static const double p[] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    static const uint32_t t[] = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
    return tu_mesh(p, 4, t, 4);
}

/* The cube [0,1]³, two triangles per face, faces outward.
 *      7-------6
 *     /|      /|      0 = (0,0,0) 1 = (1,0,0) 2 = (1,1,0) 3 = (0,1,0)
 *    4-------5 |      4 = (0,0,1) 5 = (1,0,1) 6 = (1,1,1) 7 = (0,1,1)
 *    | 3-----|-2
 *    |/      |/
 *    0-------1                                                                                                     */
resurf_mesh *tu_cube(void)
{
    static const double p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    static const uint32_t t[] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                 1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
    return tu_mesh(p, 8, t, 12);
}

/* n×n squares on z = 0 over [0,1]², each split by its (i,j)→(i+1,j+1) diagonal, counter-clockwise from +z. */
resurf_mesh *tu_grid(unsigned n)
{
    resurf_mesh *m = NULL;
    size_t nv = (size_t)(n + 1) * (n + 1);
    ck_assert_int_eq(resurf_mesh_create(nv, 2 * (size_t)n * n, 0, &m, NULL), RESURF_OK);
    for (unsigned j = 0; j <= n; ++j)
        for (unsigned i = 0; i <= n; ++i) {
            double *p = m->positions + 3 * ((size_t)j * (n + 1) + i);
            p[0] = (double)i / n, p[1] = (double)j / n, p[2] = 0;
        }
    uint32_t *t = m->indices;
    for (unsigned j = 0; j < n; ++j)
        for (unsigned i = 0; i < n; ++i) {
            uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
            *t++ = a, *t++ = b, *t++ = c;
            *t++ = a, *t++ = c, *t++ = d;
        }
    return m;
}

/* ---- glTF documents ---- */

char *tu_strf(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    char *s = malloc((size_t)n + 1);
    va_start(ap, fmt);
    vsnprintf(s, (size_t)n + 1, fmt, ap);
    va_end(ap);
    return s;
}

int tu_validator_errors(const char *path)
{
    char *cmd = tu_strf("node '%s/tools/validate-gltf.js' '%s'", RESURF_SOURCE_DIR, path), *out = NULL;
    int rc = tu_run(cmd, &out);
    const char *p = out ? strstr(out, "numErrors ") : NULL;
    if (!p || rc == 2)
        ck_abort_msg("the glTF validator did not run (rc %d): %s", rc, out ? out : "");
    int errors = atoi(p + 10);
    if (errors)
        fprintf(stderr, "%s", out);
    free(cmd);
    free(out);
    return errors;
}

char *tu_node_eval(const char *dir, const char *script, const char *file)
{
    char *js = tu_path(dir, "check.js");
    ck_assert_int_eq(tu_write_file(js, script, strlen(script)), 0);
    char *cmd = tu_strf("node '%s' '%s'", js, file), *out = NULL;
    int rc = tu_run(cmd, &out);
    ck_assert_msg(rc == 0, "node script failed: %s", out);
    size_t n = strlen(out);
    while (n && (out[n - 1] == '\n' || out[n - 1] == ' '))
        out[--n] = 0;
    unlink(js);
    free(js);
    free(cmd);
    return out;
}

void tu_put(tu_bytes *b, const void *p, size_t n)
{
    b->data = realloc(b->data, b->size + n + 4);
    memcpy(b->data + b->size, p, n);
    b->size += n;
}
void tu_put_f32(tu_bytes *b, float x) { tu_put(b, &x, 4); }
void tu_put_u8(tu_bytes *b, uint8_t x) { tu_put(b, &x, 1); }
void tu_put_u16(tu_bytes *b, uint16_t x) { tu_put(b, &x, 2); }
void tu_put_i16(tu_bytes *b, int16_t x) { tu_put(b, &x, 2); }
void tu_align4(tu_bytes *b)
{
    while (b->size % 4)
        tu_put_u8(b, 0);
}

char *tu_write_gltf(const char *dir, const char *name, const char *json, const tu_bytes *bin)
{
    char *gltf = tu_strf("%s/%s.gltf", dir, name), *binp = tu_strf("%s/%s.bin", dir, name);
    ck_assert_int_eq(tu_write_file(gltf, json, strlen(json)), 0);
    if (bin)
        ck_assert_int_eq(tu_write_file(binp, bin->data, bin->size), 0);
    free(binp);
    return gltf;
}

resurf_scene *tu_load_scene_ok(const char *path)
{
    resurf_scene *s = NULL;
    resurf_error e;
    resurf_status st = resurf_scene_load(path, NULL, &s, &e);
    char msg[600];
    resurf_format_error(msg, sizeof msg, &e);
    ck_assert_msg(st == RESURF_OK, "loading %s: %s", path, msg);
    return s;
}

void tu_save_scene_ok(const resurf_scene *s, const char *path, const resurf_scene_save_options *o,
                      resurf_scene_save_report *r)
{
    resurf_error e;
    resurf_status st = resurf_scene_save(s, path, o, r, &e);
    char msg[600];
    resurf_format_error(msg, sizeof msg, &e);
    ck_assert_msg(st == RESURF_OK, "saving %s: %s", path, msg);
}

tu_bytes tu_tetra_bin(void)
{
    tu_bytes b = {0};
    static const float p[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    static const uint16_t t[12] = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
    for (int i = 0; i < 12; ++i)
        tu_put_f32(&b, p[i]);
    for (int i = 0; i < 12; ++i)
        tu_put_u16(&b, t[i]);
    return b;
}

resurf_compare_report tu_compare(const resurf_mesh *ref, const resurf_mesh *test, size_t samples)
{
    resurf_compare_options o = resurf_compare_options_default();
    o.samples = samples;
    resurf_compare_report r;
    resurf_error e;
    ck_assert_msg(resurf_compare(ref, test, &o, &r, NULL, &e) == RESURF_OK, "compare failed: %s", e.message);
    return r;
}
