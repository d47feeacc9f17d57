/* bench-draco: the size of resurf's Draco-compressed glTF against what Google's draco_transcoder makes from the same
 * uncompressed glTF at equal quantization (positions 14 bits, normals 10, texture coordinates 12, colours 8, other
 * attributes 12; compression level 7, the transcoder's). The target is a Draco payload within 5% of the
 * transcoder's.
 *
 * usage: bench-draco [--check] [MESH ...]   (analytic shapes always; mesh files as extra rows)
 * --check exits 1 when a payload is more than 5% larger than the transcoder's. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>

#include "shapes.h"
#include "bench.h"
#include "resurf/resurf.h"

/* Total size and BIN chunk size of a .glb (0 when it cannot be read). */
static void glb_sizes(const char *path, size_t *total, size_t *bin)
{
    *total = *bin = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return;
    unsigned char h[20];
    if (fread(h, 1, 20, f) == 20) {
        uint32_t json = (uint32_t)h[12] | (uint32_t)h[13] << 8 | (uint32_t)h[14] << 16 | (uint32_t)h[15] << 24;
        unsigned char c[4];
        if (fseek(f, 20 + (long)json, SEEK_SET) == 0 && fread(c, 1, 4, f) == 4)
            *bin = (uint32_t)c[0] | (uint32_t)c[1] << 8 | (uint32_t)c[2] << 16 | (uint32_t)c[3] << 24;
        fseek(f, 0, SEEK_END);
        *total = (size_t)ftell(f);
    }
    fclose(f);
}

typedef struct row {
    char name[64];
    size_t triangles, ours_total, ours_bin, theirs_total, theirs_bin;
    double ours_s, theirs_s;
} row;

/* Writes the mesh as plain .gltf and as Draco .glb with resurf, runs the transcoder on the plain one. */
static int measure(const resurf_mesh *mesh, const char *name, const char *dir, row *r)
{
    memset(r, 0, sizeof *r);
    snprintf(r->name, sizeof r->name, "%s", name);
    r->triangles = mesh->triangle_count;
    resurf_scene *scene = NULL;
    resurf_error e;
    if (resurf_scene_from_mesh(mesh, &scene, &e) != RESURF_OK) {
        fprintf(stderr, "bench-draco: %s: %s\n", name, e.message);
        return 1;
    }
    char plain[512], ours[512], theirs[512], cmd[2048];
    snprintf(plain, sizeof plain, "%s/plain.gltf", dir);
    snprintf(ours, sizeof ours, "%s/ours.glb", dir);
    snprintf(theirs, sizeof theirs, "%s/theirs.glb", dir);
    resurf_scene_save_options o = resurf_scene_save_options_default();
    int rc = 0;
    if (resurf_scene_save(scene, plain, &o, NULL, &e) != RESURF_OK)
        rc = 1;
    o.draco = true;
    double t0 = bench_now();
    if (!rc && resurf_scene_save(scene, ours, &o, NULL, &e) != RESURF_OK)
        rc = 1;
    r->ours_s = bench_now() - t0;
    if (rc)
        fprintf(stderr, "bench-draco: %s: %s\n", name, e.message);
    snprintf(cmd, sizeof cmd,
             "draco_transcoder -i '%s' -o '%s' -qp %d -qn %d -qt %d -qc %d -qg %d -qtg %d -qw %d >/dev/null 2>&1",
             plain, theirs, o.position_bits, o.normal_bits, o.texcoord_bits, o.color_bits, o.generic_bits,
             o.generic_bits, o.generic_bits);
    t0 = bench_now();
    if (!rc && system(cmd) != 0) {
        fprintf(stderr, "bench-draco: draco_transcoder failed on %s\n", name);
        rc = 1;
    }
    r->theirs_s = bench_now() - t0;
    glb_sizes(ours, &r->ours_total, &r->ours_bin);
    glb_sizes(theirs, &r->theirs_total, &r->theirs_bin);
    resurf_scene_free(scene);
    return rc;
}

/* Texture coordinates and colours on an analytic mesh, so that every quantized attribute kind is measured. */
static void add_uv_and_colors(resurf_mesh *m)
{
    m->texcoords[0] = malloc(m->vertex_count * 2 * sizeof(double));
    m->colors = malloc(m->vertex_count * 4 * sizeof(double));
    if (!m->texcoords[0] || !m->colors)
        exit(1);
    m->texcoord_count = 1;
    m->color_components = 3;
    for (size_t v = 0; v < m->vertex_count; ++v) {
        const double *p = m->positions + 3 * v;
        m->texcoords[0][2 * v] = 0.5 + 0.25 * p[0];
        m->texcoords[0][2 * v + 1] = 0.5 + 0.25 * p[1];
        for (int k = 0; k < 3; ++k)
            m->colors[4 * v + k] = 0.5 + 0.4 * p[k] / (1 + fabs(p[k]));
        m->colors[4 * v + 3] = 1;
    }
}

int main(int argc, char **argv)
{
    int check = 0, first = 1;
    if (argc > 1 && !strcmp(argv[1], "--check"))
        check = 1, first = 2;
    char dir[] = "/tmp/resurf-bench-draco-XXXXXX";
    if (!mkdtemp(dir))
        return 1;
    if (system("command -v draco_transcoder >/dev/null") != 0) {
        fprintf(stderr, "bench-draco: draco_transcoder is not installed (Debian package 'draco')\n");
        return 1;
    }
    row rows[64];
    size_t n = 0;
    struct {
        shape_kind kind;
        size_t triangles;
        int uv;
    } shapes[] = {
        {SHAPE_SPHERE, 20000, 0}, {SHAPE_SPHERE, 200000, 0}, {SHAPE_TORUS, 50000, 1},
        {SHAPE_CUBIC, 50000, 1},  {SHAPE_SADDLE, 20000, 0},
    };
    int failed = 0;
    for (size_t i = 0; i < sizeof shapes / sizeof *shapes; ++i) {
        resurf_mesh *m = shape_mesh(shapes[i].kind, shapes[i].triangles, 0.2, 1, 1);
        if (!m)
            return 1;
        if (shapes[i].uv)
            add_uv_and_colors(m);
        char name[64];
        snprintf(name, sizeof name, "%s%s", shape_name(shapes[i].kind), shapes[i].uv ? "+uv+rgb" : "");
        failed |= measure(m, name, dir, &rows[n++]);
        resurf_mesh_free(m);
    }
    for (int i = first; i < argc && n < 64; ++i) {
        resurf_mesh *m = NULL;
        resurf_error e;
        if (resurf_mesh_load(argv[i], NULL, &m, &e) != RESURF_OK) {
            fprintf(stderr, "bench-draco: %s: %s\n", argv[i], e.message);
            failed = 1;
            continue;
        }
        const char *base = strrchr(argv[i], '/');
        failed |= measure(m, base ? base + 1 : argv[i], dir, &rows[n++]);
        resurf_mesh_free(m);
    }
    printf("Draco at equal quantization (qp 14, qn 10, qt 12, qc 8, qg 12, level 7): resurf vs draco_transcoder\n\n");
    printf("%-22s %10s %12s %12s %8s %12s %12s %9s %9s\n", "mesh", "triangles", "payload", "transcoder", "ratio",
           ".glb", "transcoder", "resurf s", "transc. s");
    int over = 0;
    for (size_t i = 0; i < n; ++i) {
        const row *r = &rows[i];
        double ratio = r->theirs_bin ? (double)r->ours_bin / (double)r->theirs_bin : 0;
        over |= ratio > 1.05 || ratio == 0;
        printf("%-22s %10zu %12zu %12zu %8.4f %12zu %12zu %9.3f %9.3f\n", r->name, r->triangles, r->ours_bin,
               r->theirs_bin, ratio, r->ours_total, r->theirs_total, r->ours_s, r->theirs_s);
    }
    printf("\nratio = resurf's BIN chunk (the Draco payload) / the transcoder's; target <= 1.05\n");
    char cmd[256];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "bench-draco: could not remove %s\n", dir);
    return failed || (check && over) ? 1 : 0;
}
