/* bench-bvh: build time of the triangle BVH (src/bvh.c) and its closest-point query rate.
 *
 *   bench-bvh [triangles] [queries] [shape]     defaults: 1000000 1000000 torus
 *
 * Builds the tree over an analytic mesh (tools/shapes.h, jitter 0.3) on 1 thread and on all cores (best of 3 each),
 * then times closest-point queries on one thread: points near the surface (a random point of a triangle moved
 * along the normal by up to two mean edge lengths), half of them over the triangles at random and half in triangle
 * order (coherent, as when restoring a mesh vertex by vertex), and as many points anywhere in the bounding box
 * grown by half its size on each side (many far from the surface, near its medial axis: the slow case). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench.h"
#include "internal.h"
#include "shapes.h"

/* Best of three builds on `threads` threads (0 = all cores). */
static double time_build(const resurf_mesh *m, unsigned threads)
{
    double best = INFINITY;
    for (int r = 0; r < 3; ++r) {
        resurfi_bvh *bvh = NULL;
        double t0 = bench_now();
        if (resurfi_bvh_build_threads(NULL, m->positions, m->vertex_count, m->indices, m->triangle_count, threads,
                                      &bvh) != RESURF_OK) {
            fprintf(stderr, "bench-bvh: build failed\n");
            exit(1);
        }
        double t = bench_now() - t0;
        best = t < best ? t : best;
        resurfi_bvh_free(bvh);
    }
    return best;
}

/* Queries per second over the given points, single thread; *checksum keeps the work from being optimised away. */
static double time_queries(const resurfi_bvh *bvh, const vec3 *points, size_t n, double *checksum)
{
    double t0 = bench_now(), sum = 0;
    for (size_t i = 0; i < n; ++i) {
        double d2 = 0;
        resurfi_bvh_closest(bvh, points[i], INFINITY, NULL, NULL, &d2);
        sum += d2;
    }
    double t = bench_now() - t0;
    *checksum = sum;
    return (double)n / t;
}

int main(int argc, char **argv)
{
    size_t triangles = argc > 1 ? strtoull(argv[1], NULL, 10) : 1000000;
    size_t queries = argc > 2 ? strtoull(argv[2], NULL, 10) : 1000000;
    shape_kind kind = argc > 3 ? shape_from_name(argv[3]) : SHAPE_TORUS;
    if (kind == SHAPE_COUNT || triangles == 0 || queries == 0) {
        fprintf(stderr, "usage: bench-bvh [triangles] [queries] [sphere|torus|cubic|cylinder|saddle|plane]\n");
        return 2;
    }
    resurf_mesh *m = shape_mesh(kind, triangles, 0.3, 1, 0);
    vec3 *near = malloc(queries * sizeof *near), *coherent = malloc(queries * sizeof *coherent),
         *box = malloc(queries * sizeof *box);
    if (!m || !near || !coherent || !box) {
        fprintf(stderr, "bench-bvh: out of memory\n");
        return 1;
    }
    vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3_neg(lo);
    for (size_t v = 0; v < m->vertex_count; ++v)
        lo = v3_min(lo, resurfi_position(m, (uint32_t)v)), hi = v3_max(hi, resurfi_position(m, (uint32_t)v));
    vec3 size = v3_sub(hi, lo);
    double edge = 0; /* mean edge length */
    for (size_t t = 0; t < m->triangle_count; ++t)
        for (int k = 0; k < 3; ++k)
            edge += v3_dist(resurfi_position(m, m->indices[3 * t + k]), resurfi_position(m, m->indices[3 * t + (k + 1) % 3]));
    edge /= 3.0 * (double)m->triangle_count;
    uint64_t rng = 42;
    for (size_t i = 0; i < queries; ++i) {
        /* Near: a random point of a triangle, moved along the exact normal by up to two edge lengths. The
         * coherent set takes the triangles in index order (as a restorer walking a mesh does), the other at random. */
        size_t t = i % 2 ? shape_rand_u64(&rng) % m->triangle_count : (i / 2) * m->triangle_count / ((queries + 1) / 2);
        const uint32_t *tri = m->indices + 3 * t;
        double u = shape_rand_unit(&rng), v = shape_rand_unit(&rng);
        if (u + v > 1)
            u = 1 - u, v = 1 - v;
        vec3 a = resurfi_position(m, tri[0]), b = resurfi_position(m, tri[1]), c = resurfi_position(m, tri[2]);
        vec3 p = v3_add(a, v3_add(v3_scale(v3_sub(b, a), u), v3_scale(v3_sub(c, a), v)));
        double n[3];
        shape_normal(kind, (const double[]){p.x, p.y, p.z}, n);
        p = v3_madd(p, v3_load(n), 2 * edge * (2 * shape_rand_unit(&rng) - 1));
        if (i % 2)
            near[i / 2] = p;
        else
            coherent[i / 2] = p;
        box[i] = v3(lo.x + size.x * (2 * shape_rand_unit(&rng) - 0.5), lo.y + size.y * (2 * shape_rand_unit(&rng) - 0.5),
                    lo.z + size.z * (2 * shape_rand_unit(&rng) - 0.5));
    }
    size_t half = queries / 2;

    double build1 = time_build(m, 1), build_all = time_build(m, 0);
    resurfi_bvh *bvh = NULL;
    if (resurfi_bvh_build(NULL, m->positions, m->vertex_count, m->indices, m->triangle_count, &bvh) !=
        RESURF_OK) {
        fprintf(stderr, "bench-bvh: build failed\n");
        return 1;
    }
    double sum_near, sum_coherent, sum_box;
    double rate_near = time_queries(bvh, near, half, &sum_near);
    double rate_coherent = time_queries(bvh, coherent, half, &sum_coherent);
    double rate_box = time_queries(bvh, box, queries, &sum_box);

    printf("bench-bvh: %s, %zu triangles (mean edge %.3g), %zu queries (half near at random, half near in mesh "
           "order, then as many anywhere)\n", shape_name(kind), m->triangle_count, edge, queries);
    printf("%-34s %14s\n", "measure", "value");
    printf("%-34s %14.3f\n", "build, 1 thread (s)", build1);
    printf("%-34s %14.3f\n", "build, all cores (s)", build_all);
    printf("%-34s %14u\n", "cores", resurfi_thread_count(0));
    printf("%-34s %14.0f\n", "queries/s near, random order", rate_near);
    printf("%-34s %14.0f\n", "queries/s near, mesh order", rate_coherent);
    printf("%-34s %14.0f\n", "queries/s anywhere in box", rate_box);
    printf("(checksums %.6g %.6g %.6g)\n", sum_near, sum_coherent, sum_box);
    resurfi_bvh_free(bvh);
    resurf_mesh_free(m);
    free(near);
    free(coherent);
    free(box);
    return 0;
}
