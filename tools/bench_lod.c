/* bench-lod: the time of `resurf lod FILE -o OUT --levels R1,R2,...` against gltfpack's for the same levels
 * (`gltfpack -i FILE -o OUT -si R -se 1 -noq`, one run per level: gltfpack makes one level a run), in the same run
 * and on the same machine, so that both see the same load (issue 20 item 9).
 *
 *   bench-lod [--file F] [--levels 0.25,0.1] [--repeat N] [--threads N] [--resurf PATH] [--gltfpack CLI.js]
 *
 * Defaults: the file is Debian's assimp-testmodels 2CylinderEngine.glb (121k triangles in 29 meshes), the levels
 * 0.25,0.1, 5 repeats, the CLI the one built beside this benchmark, gltfpack the npm package in tools/node
 * (tools/bench-setup-assets.sh installs both). Each repeat runs resurf once as it is and once with --no-share (the
 * scene budget off: what its extra runs cost), then gltfpack once per level, so that a change of load falls on all; the table gives the median wall seconds and the median CPU seconds (user +
 * system, every thread; gltfpack's include node's start-up) of each, then resurf's time over the sum of gltfpack's
 * levels, and the target: at most 1 (wall). */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench.h"

#ifndef BENCH_SOURCE_ROOT
#define BENCH_SOURCE_ROOT "."
#endif
#ifndef BENCH_RESURF_CLI
#define BENCH_RESURF_CLI "resurf"
#endif

enum { MAX_LEVELS = 8, MAX_REPEAT = 64 };

static const char tool[] = "bench-lod";

/* Runs argv with its output in log; wall and CPU seconds of the child, 0 when it exited with 0. */
static int run(char *const *argv, const char *log, double *wall, double *cpu)
{
    double t0 = bench_now();
    pid_t pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        int fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
            close(fd);
        }
        execvp(argv[0], argv);
        _exit(127);
    }
    int status = 0;
    struct rusage ru;
    while (wait4(pid, &status, 0, &ru) < 0)
        if (errno != EINTR)
            return -1;
    *wall = bench_now() - t0;
    *cpu = (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec + (double)ru.ru_stime.tv_sec +
           1e-6 * (double)ru.ru_stime.tv_usec;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? 0 : 1;
}

static double median(double *v, size_t n)
{
    qsort(v, n, sizeof *v, bench_compare_doubles);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static void show_log(const char *what, const char *log)
{
    fprintf(stderr, "%s: %s failed; its output:\n", tool, what);
    FILE *f = fopen(log, "r");
    char line[512];
    while (f && fgets(line, sizeof line, f))
        fputs(line, stderr);
    if (f)
        fclose(f);
}

int main(int argc, char **argv)
{
    const char *file = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
    const char *levels = "0.25,0.1", *threads = NULL;
    const char *resurf = BENCH_RESURF_CLI, *gltfpack = BENCH_SOURCE_ROOT "/tools/node/node_modules/gltfpack/cli.js";
    int repeat = 5;
    for (int i = 1; i < argc; ++i) {
        const char *value = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--file") && value)
            file = argv[++i];
        else if (!strcmp(argv[i], "--levels") && value)
            levels = argv[++i];
        else if (!strcmp(argv[i], "--repeat") && value)
            repeat = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--threads") && value)
            threads = argv[++i];
        else if (!strcmp(argv[i], "--resurf") && value)
            resurf = argv[++i];
        else if (!strcmp(argv[i], "--gltfpack") && value)
            gltfpack = argv[++i];
        else {
            fprintf(!strcmp(argv[i], "--help") ? stdout : stderr,
                    "usage: bench-lod [--file F] [--levels 0.25,0.1] [--repeat N] [--threads N] [--resurf PATH]"
                    " [--gltfpack CLI.js]\n");
            return !strcmp(argv[i], "--help") ? 0 : 2;
        }
    }
    if (repeat < 1 || repeat > MAX_REPEAT) {
        fprintf(stderr, "%s: --repeat takes 1 to %d\n", tool, MAX_REPEAT);
        return 2;
    }
    char ratio_text[MAX_LEVELS][32];
    size_t nr = 0;
    for (const char *p = levels; *p && nr < MAX_LEVELS;) {
        size_t n = strcspn(p, ",");
        if (n == 0 || n >= sizeof ratio_text[0]) {
            fprintf(stderr, "%s: --levels takes ratios separated by commas: '%s'\n", tool, levels);
            return 2;
        }
        memcpy(ratio_text[nr], p, n);
        ratio_text[nr++][n] = 0;
        p += n + (p[n] == ',');
    }
    struct stat st;
    if (stat(file, &st)) {
        fprintf(stderr, "%s: no %s (Debian's assimp-testmodels): run tools/bench-setup-assets.sh\n", tool, file);
        return 1;
    }
    if (stat(gltfpack, &st)) {
        fprintf(stderr, "%s: no %s (npm gltfpack): run tools/bench-setup-assets.sh\n", tool, gltfpack);
        return 1;
    }
    char dir[] = "/tmp/bench-lod-XXXXXX";
    if (!mkdtemp(dir)) {
        fprintf(stderr, "%s: mkdtemp: %s\n", tool, strerror(errno));
        return 1;
    }
    char out_r[64], out_g[64], log[64];
    snprintf(out_r, sizeof out_r, "%s/resurf.glb", dir);
    snprintf(out_g, sizeof out_g, "%s/gltfpack.glb", dir);
    snprintf(log, sizeof log, "%s/log", dir);

    /* The default, and --no-share (every primitive at its own ratio: what the scene budget costs). */
    char *resurf_argv[16] = {(char *)resurf, "lod", (char *)file, "-o", out_r, "--levels", (char *)levels};
    char *alone_argv[16] = {(char *)resurf, "lod", (char *)file, "-o", out_r, "--levels", (char *)levels,
                            "--no-share"};
    if (threads) {
        resurf_argv[7] = alone_argv[8] = "--threads";
        resurf_argv[8] = alone_argv[9] = (char *)threads;
    }
    static double r_wall[MAX_REPEAT], r_cpu[MAX_REPEAT], a_wall[MAX_REPEAT], a_cpu[MAX_REPEAT],
        g_wall[MAX_LEVELS][MAX_REPEAT], g_cpu[MAX_LEVELS][MAX_REPEAT];
    int failed = 0;
    for (int k = 0; k < repeat && !failed; ++k) {
        if (run(resurf_argv, log, &r_wall[k], &r_cpu[k]) || run(alone_argv, log, &a_wall[k], &a_cpu[k])) {
            show_log("resurf lod", log);
            failed = 1;
        }
        for (size_t l = 0; l < nr && !failed; ++l) {
            char *g_argv[] = {"node", (char *)gltfpack, "-i", (char *)file, "-o", out_g, "-si", ratio_text[l],
                              "-se", "1", "-noq", NULL};
            if (run(g_argv, log, &g_wall[l][k], &g_cpu[l][k])) {
                show_log("gltfpack", log);
                failed = 1;
            }
        }
    }
    unlink(out_r);
    unlink(out_g);
    unlink(log);
    rmdir(dir);
    if (failed)
        return 1;

    printf("%s on %s, %d repeats, median seconds\n", tool, file, repeat);
    printf("%-10s %-22s %8s %8s\n", "tool", "run", "wall", "cpu");
    double rw = median(r_wall, (size_t)repeat), rc = median(r_cpu, (size_t)repeat), gw = 0, gc = 0;
    char what[96];
    snprintf(what, sizeof what, "lod --levels %.60s", levels);
    printf("%-10s %-22s %8.3f %8.3f\n", "resurf", what, rw, rc);
    double aw = median(a_wall, (size_t)repeat), ac = median(a_cpu, (size_t)repeat);
    printf("%-10s %-22s %8.3f %8.3f\n", "resurf", "  ... --no-share", aw, ac);
    for (size_t l = 0; l < nr; ++l) {
        double w = median(g_wall[l], (size_t)repeat), c = median(g_cpu[l], (size_t)repeat);
        gw += w;
        gc += c;
        snprintf(what, sizeof what, "-si %.31s -se 1 -noq", ratio_text[l]);
        printf("%-10s %-22s %8.3f %8.3f\n", "gltfpack", what, w, c);
    }
    printf("%-10s %-22s %8.3f %8.3f\n", "gltfpack", "sum of the levels", gw, gc);
    printf("%-10s %-22s %8.3f %8.3f\n", "ratio", "resurf / gltfpack", rw / gw, rc / gc);
    printf("%-10s %-22s %8.3f %8.3f\n", "ratio", "--no-share / gltfpack", aw / gw, ac / gc);
    printf("target: resurf lod <= the sum of gltfpack's levels (wall): %.2f <= 1  %s\n", rw / gw,
           rw <= gw ? "met" : "MISSED");
    return 0;
}
