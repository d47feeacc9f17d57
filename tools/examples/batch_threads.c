/* Example: a multithreaded batch, several meshes simplified at the same time on different threads.
 *
 * resurf has no global state, so calls on different meshes may run concurrently (resurf.h, "Threads"). A batch
 * tool can therefore give each mesh its own thread; each call then gets `threads = 1` so that the batch, not
 * resurf, decides how many cores are busy. The results do not depend on any of this: this program simplifies
 * four meshes on four POSIX threads at once, then the same four one after the other on the main thread, and
 * checks that every result is bit for bit the same.
 * The meshes are tori of different sizes and proportions, generated here. It uses nothing but <resurf/resurf.h>.
 * Build: cc batch_threads.c $(pkg-config --cflags --libs resurf) -lm -pthread */
#include <resurf/resurf.h>

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { MESHES = 4 };

/* A torus around z with radii R (tube centre) and r (tube), n × m quads split in two triangles each, shared
 * vertices (closed, no seam), positions as tightly packed doubles. */
static resurf_mesh *make_torus(double R, double r, int n, int m, resurf_error *error)
{
    const double pi = 3.14159265358979323846;
    size_t vertex_count = (size_t)n * (size_t)m, index_count = 6 * vertex_count;
    double *positions = malloc(3 * vertex_count * sizeof *positions);
    uint32_t *indices = malloc(index_count * sizeof *indices);
    resurf_mesh *mesh = NULL;
    if (positions && indices) {
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < m; ++j) {
                double u = 2 * pi * i / n, v = 2 * pi * j / m;
                double *p = positions + 3 * ((size_t)i * (size_t)m + (size_t)j);
                p[0] = (R + r * cos(v)) * cos(u), p[1] = (R + r * cos(v)) * sin(u), p[2] = r * sin(v);
            }
        size_t k = 0;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < m; ++j) {
                /* Counter-clockwise seen from outside: u runs around z, v around the tube. */
                uint32_t a = (uint32_t)(i * m + j), b = (uint32_t)(((i + 1) % n) * m + j);
                uint32_t c = (uint32_t)(((i + 1) % n) * m + (j + 1) % m), d = (uint32_t)(i * m + (j + 1) % m);
                indices[k++] = a, indices[k++] = b, indices[k++] = c;
                indices[k++] = a, indices[k++] = c, indices[k++] = d;
            }
        resurf_mesh_arrays arrays = resurf_mesh_arrays_default();
        arrays.vertex_count = vertex_count;
        arrays.positions.data = positions;
        arrays.positions.type = RESURF_COMPONENT_DOUBLE;
        arrays.indices = indices;
        arrays.index_count = index_count;
        resurf_mesh_from_arrays(&arrays, &mesh, error);
    }
    free(positions);
    free(indices);
    return mesh;
}

/* One job of the batch: its input, its result and its own error struct (nothing is shared between threads). */
typedef struct job {
    const resurf_mesh *input;
    double ratio;
    resurf_mesh *result;
    resurf_simplify_report report;
    resurf_status status;
    resurf_error error;
} job;

static void run_job(job *j)
{
    resurf_simplify_options options = resurf_simplify_options_default();
    options.target_ratio = j->ratio;
    options.threads = 1; /* one core per job: the batch spreads the work */
    j->status = resurf_simplify(j->input, &options, &j->result, &j->report, &j->error);
}

static void *thread_main(void *arg)
{
    run_job(arg);
    return NULL;
}

static int same_mesh(const resurf_mesh *a, const resurf_mesh *b)
{
    return a->vertex_count == b->vertex_count && a->triangle_count == b->triangle_count &&
           memcmp(a->positions, b->positions, 3 * a->vertex_count * sizeof(double)) == 0 &&
           memcmp(a->indices, b->indices, 3 * a->triangle_count * sizeof(uint32_t)) == 0;
}

int main(void)
{
    static const struct { double R, r, ratio; int n, m; } spec[MESHES] = {
        {1.0, 0.40, 0.20, 64, 32}, {2.0, 0.50, 0.10, 96, 24}, {1.5, 0.70, 0.30, 48, 40}, {3.0, 0.25, 0.05, 128, 16},
    };
    resurf_mesh *inputs[MESHES] = {NULL};
    job threaded[MESHES], serial[MESHES];
    memset(threaded, 0, sizeof threaded);
    memset(serial, 0, sizeof serial);
    int ok = 1;
    for (int i = 0; i < MESHES && ok; ++i) {
        resurf_error error;
        if (!(inputs[i] = make_torus(spec[i].R, spec[i].r, spec[i].n, spec[i].m, &error))) {
            fprintf(stderr, "batch_threads: making torus %d: %s\n", i, error.message);
            ok = 0;
        }
        threaded[i].input = serial[i].input = inputs[i];
        threaded[i].ratio = serial[i].ratio = spec[i].ratio;
    }

    /* The batch: one thread per mesh, all at once. */
    pthread_t threads[MESHES];
    int started[MESHES] = {0};
    for (int i = 0; i < MESHES && ok; ++i)
        started[i] = pthread_create(&threads[i], NULL, thread_main, &threaded[i]) == 0;
    for (int i = 0; i < MESHES; ++i) {
        if (started[i])
            pthread_join(threads[i], NULL);
        else if (ok)
            run_job(&threaded[i]); /* no thread to be had: do it here */
    }

    /* The reference: the same jobs one after the other. */
    for (int i = 0; i < MESHES && ok; ++i)
        run_job(&serial[i]);

    for (int i = 0; i < MESHES && ok; ++i) {
        if (threaded[i].status != RESURF_OK || serial[i].status != RESURF_OK) {
            const job *bad = threaded[i].status != RESURF_OK ? &threaded[i] : &serial[i];
            fprintf(stderr, "batch_threads: mesh %d: %s\n", i, bad->error.message);
            ok = 0;
            break;
        }
        int same = same_mesh(threaded[i].result, serial[i].result);
        printf("mesh %d: torus R %.2f r %.2f, %zu -> %zu triangles (ratio %.2f), measured error %.3e: %s\n", i,
               spec[i].R, spec[i].r, inputs[i]->triangle_count, threaded[i].result->triangle_count, spec[i].ratio,
               threaded[i].report.max_distance_rel, same ? "identical" : "DIFFERENT");
        ok &= same;
    }
    for (int i = 0; i < MESHES; ++i) {
        resurf_mesh_free(threaded[i].result);
        resurf_mesh_free(serial[i].result);
        resurf_mesh_free(inputs[i]);
    }
    if (!ok) {
        fputs("batch_threads: the threaded batch differs from the serial run, or a job failed\n", stderr);
        return 1;
    }
    printf("batch_threads: ok, %d meshes on %d threads, results identical to the single-threaded run\n", MESHES,
           MESHES);
    return 0;
}
