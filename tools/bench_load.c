/* bench-load: how fast resurf loads large meshes. Generates a torus of about N triangles (default 1,000,000),
 * writes it as binary PLY, ASCII PLY, OBJ, OFF and binary STL into a temporary folder, loads each file R times
 * (default 5) and prints the best and median wall time, MB/s and triangles/s. Also checks that every load gives
 * the triangle count it should (and, for PLY binary, the exact positions), so a fast wrong loader cannot pass.
 *
 * usage: bench-load [TRIANGLES [REPEATS]] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "bench.h"
#include "resurf/resurf.h"
#include "shapes.h"

int main(int argc, char **argv)
{
    size_t triangles = argc > 1 ? (size_t)strtoull(argv[1], NULL, 10) : 1000000;
    int repeats = argc > 2 ? atoi(argv[2]) : 5;
    if (triangles < 100 || repeats < 1 || repeats > 1000) {
        fprintf(stderr, "usage: bench-load [TRIANGLES >= 100 [REPEATS 1..1000]]\n");
        return 2;
    }
    resurf_mesh *mesh = shape_mesh(SHAPE_TORUS, triangles, 0.3, 1, 0);
    if (!mesh) {
        fprintf(stderr, "bench-load: out of memory\n");
        return 1;
    }
    char dir[] = "/tmp/resurf-bench-load-XXXXXX";
    if (!mkdtemp(dir)) {
        perror("bench-load: mkdtemp");
        return 1;
    }
    static const struct {
        const char *name, *file;
        int binary;
    } cases[] = {
        {"PLY binary", "torus.ply", 1}, {"PLY ascii", "torus-ascii.ply", 0}, {"OBJ", "torus.obj", 0},
        {"OFF", "torus.off", 0},        {"STL binary", "torus.stl", 1},
    };
    const size_t case_count = sizeof cases / sizeof *cases;
    printf("torus: %zu vertices, %zu triangles; %d loads each; MB/s and Mtri/s at the median time\n\n", mesh->vertex_count,
           mesh->triangle_count, repeats);
    printf("%-11s %9s %9s %9s %10s %12s %10s\n", "format", "size MB", "best s", "median s", "MB/s", "Mtri/s",
           "save s");
    resurf_error error;
    double *times = malloc((size_t)repeats * sizeof *times);
    for (size_t c = 0; c < case_count; ++c) {
        char path[512];
        snprintf(path, sizeof path, "%s/%s", dir, cases[c].file);
        resurf_save_options save = resurf_save_options_default();
        save.binary = cases[c].binary;
        double t0 = bench_now();
        if (resurf_mesh_save(mesh, path, &save, &error) != RESURF_OK)
            bench_fail("bench-load", "save", &error);
        double save_time = bench_now() - t0;
        struct stat st;
        stat(path, &st);
        double megabytes = (double)st.st_size / 1e6;
        for (int r = 0; r < repeats; ++r) {
            resurf_mesh *loaded = NULL;
            t0 = bench_now();
            if (resurf_mesh_load(path, NULL, &loaded, &error) != RESURF_OK)
                bench_fail("bench-load", "load", &error);
            times[r] = bench_now() - t0;
            if (loaded->triangle_count != mesh->triangle_count) {
                fprintf(stderr, "bench-load: %s gave %zu triangles, not %zu\n", path, loaded->triangle_count,
                        mesh->triangle_count);
                return 1;
            }
            if (c == 0 && (loaded->vertex_count != mesh->vertex_count ||
                           memcmp(loaded->positions, mesh->positions, 3 * mesh->vertex_count * sizeof(double)))) {
                fprintf(stderr, "bench-load: %s: positions differ from the saved ones\n", path);
                return 1;
            }
            resurf_mesh_free(loaded);
        }
        qsort(times, (size_t)repeats, sizeof *times, bench_compare_doubles);
        double best = times[0], median = times[repeats / 2];
        printf("%-11s %9.1f %9.3f %9.3f %10.0f %12.2f %10.3f\n", cases[c].name, megabytes, best, median,
               megabytes / median, (double)mesh->triangle_count / median / 1e6, save_time);
        unlink(path);
    }
    rmdir(dir);
    free(times);
    resurf_mesh_free(mesh);
    return 0;
}
