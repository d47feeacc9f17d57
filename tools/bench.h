/* What the benchmarks and the Table 1 tool share: clocks, a sort order for timings, and the one-line failure. */
#ifndef RESURF_TOOLS_BENCH_H
#define RESURF_TOOLS_BENCH_H

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "resurf/resurf.h"

/* Wall-clock seconds from an arbitrary origin. */
static inline double bench_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU seconds of the whole process (every thread): on a shared, loaded machine the wall time says little. */
static inline double bench_cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* qsort order of doubles, ascending (for medians and best-of-N). */
static inline int bench_compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* "TOOL: WHAT: the error" on stderr, then exit 1 (tools may exit; the library never does). */
static inline void bench_fail(const char *tool, const char *what, const resurf_error *error)
{
    char text[600];
    resurf_format_error(text, sizeof text, error);
    fprintf(stderr, "%s: %s: %s\n", tool, what, text);
    exit(1);
}

#endif
