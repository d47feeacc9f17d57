/* bench-preview: how long the preview sheet takes. Loads a mesh (default the dragon scan, data/scans/dragon-48k.ply),
 * builds the main job's levels (0.5, 0.25, 0.1: 4 levels in all), then renders a 1600 x 900 sheet R times (default
 * 5) and writes it as PNG (resurf_preview_save_png to a temporary file), and prints the best and median wall time:
 * the drawing alone (measure 0), with each level's error measured (resurf_compare, the default), and both with the
 * heat map, with the CPU time of all threads beside. Target: under 0.5 s for the sheet.
 *
 * usage: bench-preview [MESH [REPEATS [THREADS]]] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "bench.h"
#include "resurf/resurf.h"

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "data/scans/dragon-48k.ply";
    int repeats = argc > 2 ? atoi(argv[2]) : 5;
    unsigned threads = argc > 3 ? (unsigned)atoi(argv[3]) : 0;
    if (repeats < 1 || repeats > 1000) {
        fprintf(stderr, "usage: bench-preview [MESH [REPEATS 1..1000 [THREADS]]]\n");
        return 2;
    }
    resurf_error error;
    resurf_scene *scene = NULL;
    if (resurf_scene_load(path, NULL, &scene, &error) != RESURF_OK)
        bench_fail("bench-preview", path, &error);
    resurf_simplify_options so = resurf_simplify_options_default();
    so.threads = threads;
    const double ratios[3] = {0.5, 0.25, 0.1};
    if (resurf_scene_build_lods(scene, ratios, 3, &so, NULL, NULL, NULL, &error) != RESURF_OK)
        bench_fail("bench-preview", "levels", &error);
    char png[] = "/tmp/resurf-bench-preview-XXXXXX.png";
    int fd = mkstemps(png, 4);
    if (fd < 0) {
        perror("bench-preview: mkstemps");
        return 1;
    }
    close(fd);
    printf("%s, 4 levels, 1600 x 900, %d runs, threads %u\n", path, repeats, threads);
    printf("%-32s %10s %10s %12s\n", "", "best (s)", "median (s)", "CPU best (s)");
    for (int heat = 0; heat < 2; ++heat)
        for (int measure = 0; measure < 2; ++measure) {
            double *t = calloc((size_t)repeats, sizeof *t), cpu_best = INFINITY;
            resurf_preview_report rep;
            for (int r = 0; r < repeats; ++r) {
                resurf_preview_options o = resurf_preview_options_default();
                o.heatmap = heat;
                o.measure = measure;
                o.threads = threads;
                resurf_preview_image img;
                double t0 = bench_now(), c0 = bench_cpu_now();
                if (resurf_preview_render(scene, &o, &img, &rep, &error) != RESURF_OK)
                    bench_fail("bench-preview", "render", &error);
                if (resurf_preview_save_png(&img, png, &error) != RESURF_OK)
                    bench_fail("bench-preview", "save", &error);
                t[r] = bench_now() - t0;
                cpu_best = fmin(cpu_best, bench_cpu_now() - c0);
                resurf_preview_image_free(&img);
            }
            qsort(t, (size_t)repeats, sizeof *t, bench_compare_doubles);
            char name[64];
            snprintf(name, sizeof name, "%s%s", measure ? "sheet with errors" : "drawing alone",
                     heat ? " + heat map" : "");
            printf("%-32s %10.3f %10.3f %12.3f\n", name, t[0], t[repeats / 2], cpu_best);
            if (rep.levels != 4) {
                fprintf(stderr, "bench-preview: %zu levels, not 4\n", rep.levels);
                return 1;
            }
            free(t);
        }
    unlink(png);
    resurf_scene_free(scene);
    return 0;
}
