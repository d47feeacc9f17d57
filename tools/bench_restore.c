/* bench-restore: wall time of resurf_restore (src/restore.c) on a large mesh.
 *
 *   bench-restore [triangles] [vertices] [paper|default]      defaults: 1000000 1000000 paper
 *
 * M is an irregular unit sphere of `triangles` triangles (tools/shapes.h, jitter 0.35, seed 1); M' is another
 * sphere mesh (seed 2) with about `vertices` vertices whose radii are perturbed by up to ±0.3 mean edge lengths of
 * M. Times the whole resurf_restore call (welding M, adjacency, normals, curvatures, BVH, then every vertex) on 1
 * thread and on 2, best of 3 (wall and process CPU time: on a busy machine the wall time overstates the cost), and
 * separately the set-up of M's services (resurfi_restorer_create). Checks that the results are bit-identical for
 * both thread counts and prints the vertex errors before and after. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench.h"
#include "internal.h"
#include "shapes.h"

/* CPU time of the whole process (all threads): with other work on the machine, wall time overstates the cost. */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void sphere_errors(const resurf_mesh *m, double *out_max, double *out_mean)
{
    double mx = 0, sum = 0;
    for (size_t v = 0; v < m->vertex_count; ++v) {
        double d = shape_distance(SHAPE_SPHERE, m->positions + 3 * v);
        mx = d > mx ? d : mx;
        sum += d;
    }
    *out_max = mx;
    *out_mean = m->vertex_count ? sum / (double)m->vertex_count : 0;
}

int main(int argc, char **argv)
{
    size_t triangles = argc > 1 ? strtoull(argv[1], NULL, 10) : 1000000;
    size_t vertices = argc > 2 ? strtoull(argv[2], NULL, 10) : 1000000;
    const char *preset = argc > 3 ? argv[3] : "paper";
    if (triangles == 0 || vertices == 0 || (strcmp(preset, "paper") && strcmp(preset, "default"))) {
        fprintf(stderr, "usage: bench-restore [triangles] [vertices] [paper|default]\n");
        return 2;
    }
    resurf_mesh *M = shape_mesh(SHAPE_SPHERE, triangles, 0.35, 1, 0);
    resurf_mesh *P = shape_mesh(SHAPE_SPHERE, 2 * vertices, 0.35, 2, 0); /* a closed mesh has ~ t/2 vertices */
    if (!M || !P) {
        fprintf(stderr, "bench-restore: out of memory\n");
        return 1;
    }
    double edge = sqrt(4 * M_PI / (double)M->triangle_count * 4 / sqrt(3.0)); /* equilateral of the mean area */
    uint64_t rng = 3;
    for (size_t v = 0; v < P->vertex_count; ++v) {
        double *p = P->positions + 3 * v;
        double s = 1 + 0.3 * edge * (2 * shape_rand_unit(&rng) - 1);
        p[0] *= s, p[1] *= s, p[2] *= s;
    }
    resurf_restore_options o = strcmp(preset, "paper") ? resurf_restore_options_default()
                                                       : resurf_restore_options_paper();
    printf("M: %zu triangles, %zu vertices; M': %zu vertices; preset %s\n", M->triangle_count, M->vertex_count,
           P->vertex_count, preset);

    for (unsigned threads = 1; threads <= 2; ++threads) {
        o.threads = threads;
        double best = INFINITY;
        for (int r = 0; r < 3; ++r) {
            resurfi_restorer *rs = NULL;
            double t0 = bench_now();
            if (resurfi_restorer_create(M, &o, &rs, NULL) != RESURF_OK) {
                fprintf(stderr, "bench-restore: set-up failed\n");
                return 1;
            }
            double t = bench_now() - t0;
            best = t < best ? t : best;
            resurfi_restorer_free(rs);
        }
        printf("set-up of M's services, %u thread%s: %.3f s\n", threads, threads > 1 ? "s" : "", best);
    }

    double before_max, before_mean;
    sphere_errors(P, &before_max, &before_mean);
    resurf_mesh *result[2] = {NULL, NULL};
    for (unsigned threads = 1; threads <= 2; ++threads) {
        o.threads = threads;
        double best = INFINITY, best_cpu = INFINITY;
        resurf_restore_report rep;
        for (int r = 0; r < 3; ++r) {
            resurf_mesh *R = NULL;
            if (resurf_mesh_clone(P, &R, NULL) != RESURF_OK) {
                fprintf(stderr, "bench-restore: out of memory\n");
                return 1;
            }
            resurf_error error;
            double t0 = bench_now(), c0 = cpu_now();
            if (resurf_restore(M, R, &o, &rep, &error) != RESURF_OK) {
                fprintf(stderr, "bench-restore: %s\n", error.message);
                return 1;
            }
            double t = bench_now() - t0, c = cpu_now() - c0;
            best = t < best ? t : best;
            best_cpu = c < best_cpu ? c : best_cpu;
            resurf_mesh_free(result[threads - 1]);
            result[threads - 1] = R;
        }
        printf("resurf_restore, %u thread%s: %.3f s wall, %.3f s CPU (moved %zu, least-outside %zu)\n", threads,
               threads > 1 ? "s" : "", best, best_cpu, rep.moved, rep.used_least_outside);
    }
    int same = memcmp(result[0]->positions, result[1]->positions, P->vertex_count * 3 * sizeof(double)) == 0;
    double after_max, after_mean;
    sphere_errors(result[0], &after_max, &after_mean);
    printf("vertex distance to the sphere: before max %.3g mean %.3g; after max %.3g mean %.3g\n", before_max,
           before_mean, after_max, after_mean);
    printf("1 and 2 threads bit-identical: %s\n", same ? "yes" : "NO");
    resurf_mesh_free(result[0]);
    resurf_mesh_free(result[1]);
    resurf_mesh_free(M);
    resurf_mesh_free(P);
    return same ? 0 : 1;
}
