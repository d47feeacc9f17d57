/* bench-borders: two ways to simplify a mesh made of several primitives (materials) without opening a crack
 * between them, measured on the same cut (issue 19, item 3):
 *   locked    each part on its own, the positions it shares with another part locked (what `resurf lod` does with
 *             keep_shared_borders);
 *   together  the whole mesh at once, the parts as triangle_groups: their borders are creases that slide along
 *             themselves (src/simplify/setup.c, group_border).
 * The mesh is cut into K slabs along its longest axis by triangle centroid. Both results are judged against the
 * uncut input by resurf_compare (two-sided, relative to the diagonal), at the same total triangle budget.
 *
 * usage: bench-borders [--parts K] [--samples N] MESH... (default: K = 2 and 4, the bundled dragon-48k) */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"

static const char *tool = "bench-borders";

/* The part of each triangle: its centroid's slab along the longest axis of the bounding box. */
static uint32_t *cut(const resurf_mesh *m, unsigned parts)
{
    double lo[3], hi[3];
    resurf_mesh_bounds(m, lo, hi);
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (hi[k] - lo[k] > hi[axis] - lo[axis])
            axis = k;
    uint32_t *part = malloc(m->triangle_count * sizeof *part);
    if (!part)
        exit(1);
    for (size_t t = 0; t < m->triangle_count; ++t) {
        double c = 0;
        for (int k = 0; k < 3; ++k)
            c += m->positions[3 * (size_t)m->indices[3 * t + k] + axis] / 3;
        double s = (c - lo[axis]) / (hi[axis] - lo[axis]) * parts;
        part[t] = s >= parts ? parts - 1 : s < 0 ? 0 : (uint32_t)s;
    }
    return part;
}

/* Part p of m as a mesh of its own (its vertices renumbered), with lock[v] set on the vertices that a triangle of
 * another part also uses. */
static resurf_mesh *extract(const resurf_mesh *m, const uint32_t *part, uint32_t p, const uint32_t *owner,
                            uint8_t **out_lock)
{
    uint32_t *map = malloc(m->vertex_count * sizeof *map);
    size_t nv = 0, nt = 0;
    for (size_t v = 0; v < m->vertex_count; ++v)
        map[v] = UINT32_MAX;
    for (size_t t = 0; t < m->triangle_count; ++t)
        if (part[t] == p) {
            ++nt;
            for (int k = 0; k < 3; ++k)
                if (map[m->indices[3 * t + k]] == UINT32_MAX)
                    map[m->indices[3 * t + k]] = (uint32_t)nv++;
        }
    resurf_mesh *out = NULL;
    resurf_error e;
    if (resurf_mesh_create(nv, nt, 0, &out, &e) != RESURF_OK)
        bench_fail(tool, "a part", &e);
    uint8_t *lock = calloc(nv, 1);
    for (size_t v = 0; v < m->vertex_count; ++v)
        if (map[v] != UINT32_MAX) {
            memcpy(out->positions + 3 * (size_t)map[v], m->positions + 3 * v, 3 * sizeof(double));
            lock[map[v]] = owner[v] == UINT32_MAX - 1; /* used by more than one part */
        }
    for (size_t t = 0, i = 0; t < m->triangle_count; ++t)
        if (part[t] == p)
            for (int k = 0; k < 3; ++k)
                out->indices[i++] = map[m->indices[3 * t + k]];
    free(map);
    *out_lock = lock;
    return out;
}

/* The parts side by side as one mesh (no welding: resurf_compare needs none). */
static resurf_mesh *join(resurf_mesh *const *parts, unsigned count)
{
    size_t nv = 0, nt = 0;
    for (unsigned p = 0; p < count; ++p)
        nv += parts[p]->vertex_count, nt += parts[p]->triangle_count;
    resurf_mesh *out = NULL;
    resurf_error e;
    if (resurf_mesh_create(nv, nt, 0, &out, &e) != RESURF_OK)
        bench_fail(tool, "joining", &e);
    size_t v0 = 0, t0 = 0;
    for (unsigned p = 0; p < count; ++p) {
        const resurf_mesh *m = parts[p];
        memcpy(out->positions + 3 * v0, m->positions, 3 * m->vertex_count * sizeof(double));
        for (size_t i = 0; i < 3 * m->triangle_count; ++i)
            out->indices[3 * t0 + i] = (uint32_t)(m->indices[i] + v0);
        v0 += m->vertex_count, t0 += m->triangle_count;
    }
    return out;
}

static resurf_mesh *simplify(const resurf_mesh *in, double ratio, const uint8_t *lock)
{
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = ratio;
    o.vertex_lock = lock;
    o.measure_samples = 0;
    resurf_mesh *out = NULL;
    resurf_error e;
    if (resurf_simplify(in, &o, &out, NULL, &e) != RESURF_OK)
        bench_fail(tool, "simplify", &e);
    return out;
}

static void judge(const resurf_mesh *ref, const resurf_mesh *test, size_t samples, double *h, double *mean)
{
    resurf_compare_options co = resurf_compare_options_default();
    co.samples = samples;
    resurf_compare_report r;
    resurf_error e;
    if (resurf_compare(ref, test, &co, &r, NULL, &e) != RESURF_OK)
        bench_fail(tool, "compare", &e);
    *h = r.hausdorff / r.diagonal, *mean = r.mean / r.diagonal;
}

static void run(const char *path, unsigned parts, size_t samples)
{
    resurf_mesh *m = NULL;
    resurf_error e;
    if (resurf_mesh_load(path, NULL, &m, &e) != RESURF_OK)
        bench_fail(tool, path, &e);
    uint32_t *part = cut(m, parts);
    /* owner[v]: the one part whose triangles use v, UINT32_MAX - 1 when several do */
    uint32_t *owner = malloc(m->vertex_count * sizeof *owner);
    for (size_t v = 0; v < m->vertex_count; ++v)
        owner[v] = UINT32_MAX;
    for (size_t t = 0; t < m->triangle_count; ++t)
        for (int k = 0; k < 3; ++k) {
            uint32_t *o = &owner[m->indices[3 * t + k]];
            *o = *o == UINT32_MAX || *o == part[t] ? part[t] : UINT32_MAX - 1;
        }
    size_t shared = 0;
    for (size_t v = 0; v < m->vertex_count; ++v)
        shared += owner[v] == UINT32_MAX - 1;
    const char *name = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    const double ratios[2] = {0.1, 0.02};
    for (int r = 0; r < 2; ++r) {
        /* locked: each part at the ratio, its shared positions locked */
        resurf_mesh *levels[16];
        for (unsigned p = 0; p < parts; ++p) {
            uint8_t *lock;
            resurf_mesh *piece = extract(m, part, p, owner, &lock);
            levels[p] = simplify(piece, ratios[r], lock);
            free(lock);
            resurf_mesh_free(piece);
        }
        resurf_mesh *locked = join(levels, parts);
        for (unsigned p = 0; p < parts; ++p)
            resurf_mesh_free(levels[p]);
        /* together: the whole mesh, the parts as groups, to the same number of triangles */
        resurf_mesh *grouped = NULL;
        if (resurf_mesh_clone(m, &grouped, &e) != RESURF_OK)
            bench_fail(tool, "clone", &e);
        grouped->triangle_groups = malloc(m->triangle_count * sizeof *part);
        grouped->group_names = calloc(parts, sizeof *grouped->group_names);
        memcpy(grouped->triangle_groups, part, m->triangle_count * sizeof *part);
        for (unsigned p = 0; p < parts; ++p)
            grouped->group_names[p] = calloc(1, 1);
        grouped->group_count = parts;
        resurf_mesh *together = simplify(grouped, (double)locked->triangle_count / (double)m->triangle_count, NULL);
        double hl, ml, ht, mt;
        judge(m, locked, samples, &hl, &ml);
        judge(m, together, samples, &ht, &mt);
        printf("%-16s %5u %7zu %5.0f%% %8zu %8zu  %9.3e %9.3e  %9.3e %9.3e  %5.2f %5.2f\n", name, parts, shared,
               100 * ratios[r], locked->triangle_count, together->triangle_count, hl, ml, ht, mt, ht / hl, mt / ml);
        resurf_mesh_free(locked);
        resurf_mesh_free(together);
        resurf_mesh_free(grouped);
    }
    free(owner);
    free(part);
    resurf_mesh_free(m);
}

int main(int argc, char **argv)
{
    unsigned parts[2] = {2, 4}, part_count = 2;
    size_t samples = 200000;
    const char *meshes[64];
    int mesh_count = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--parts") && i + 1 < argc) {
            long k = atol(argv[++i]);
            if (k < 1 || k > 16) {
                fprintf(stderr, "%s: --parts: 1 to 16\n", tool);
                return 2;
            }
            parts[0] = (unsigned)k, part_count = 1;
        } else if (!strcmp(argv[i], "--samples") && i + 1 < argc) {
            samples = (size_t)atol(argv[++i]);
        } else if (argv[i][0] == '-' || mesh_count == 64) {
            fprintf(stderr, "usage: %s [--parts K] [--samples N] MESH...\n", tool);
            return 2;
        } else {
            meshes[mesh_count++] = argv[i];
        }
    }
    if (!mesh_count)
        meshes[mesh_count++] = BENCH_SOURCE_ROOT "/data/scans/dragon-48k.ply";
    printf("locked: parts simplified alone, shared positions locked; together: one mesh, parts as groups.\n"
           "Two-sided distance to the uncut input, relative to its diagonal (resurf_compare, %zu samples).\n\n",
           samples);
    printf("%-16s %5s %7s %6s %8s %8s  %9s %9s  %9s %9s  %11s\n", "mesh", "parts", "shared", "level", "locked",
           "together", "H locked", "mean", "H togeth.", "mean", "together/locked");
    for (int i = 0; i < mesh_count; ++i)
        for (unsigned k = 0; k < part_count; ++k)
            run(meshes[i], parts[k], samples);
    return 0;
}
