/* Example: restoring the output of one's own filter.
 *
 * A tool has its own mesh processing, here a plain Laplacian smoothing written below, that works on its own
 * float arrays. Smoothing shrinks curved surfaces: the vertices sink below the surface the mesh approximates.
 * resurf_restore moves the processed vertices back onto the smooth surface of the original mesh (Semenova,
 * Savchenko, Hagiwara) without changing the connectivity, so the filter's effect on the triangles (more regular
 * shapes, less noise) stays while the shape comes back.
 *
 * The mesh is a sphere of radius 1.3 built in this file, so the true surface is known: the program prints the
 * mean and largest distance of the vertices to it before and after restoration, and fails unless both fall.
 * It uses nothing but <resurf/resurf.h>.
 * Build: cc restore_own_filter.c $(pkg-config --cflags --libs resurf) -lm */
#include <resurf/resurf.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { RINGS = 40, SEGMENTS = 80 };
#define RADIUS 1.3

/* A closed UV sphere with shared vertices (no texture seam): a pole, RINGS - 1 rings of SEGMENTS vertices, a pole.
 * The rings are spaced unevenly in latitude so that the triangles are not all alike. */
static size_t make_sphere(float *positions, uint32_t *indices)
{
    const double pi = 3.14159265358979323846;
    size_t v = 0;
    positions[v++] = 0, positions[v++] = 0, positions[v++] = (float)RADIUS;
    for (int r = 1; r < RINGS; ++r) {
        double t = (double)r / RINGS, theta = pi * (t + 0.08 * sin(2 * pi * t)); /* uneven, still monotone */
        for (int s = 0; s < SEGMENTS; ++s) {
            double phi = 2 * pi * (s + 0.5 * (r % 2)) / SEGMENTS;
            positions[v++] = (float)(RADIUS * sin(theta) * cos(phi));
            positions[v++] = (float)(RADIUS * sin(theta) * sin(phi));
            positions[v++] = (float)(RADIUS * cos(theta));
        }
    }
    positions[v++] = 0, positions[v++] = 0, positions[v++] = (float)-RADIUS;
    const uint32_t north = 0, south = 1 + (RINGS - 1) * SEGMENTS;
    size_t n = 0;
#define RING(r, s) (1 + (uint32_t)((r) - 1) * SEGMENTS + (uint32_t)((s) % SEGMENTS))
    for (int s = 0; s < SEGMENTS; ++s) {
        indices[n++] = north, indices[n++] = RING(1, s), indices[n++] = RING(1, s + 1);
        indices[n++] = south, indices[n++] = RING(RINGS - 1, s + 1), indices[n++] = RING(RINGS - 1, s);
    }
    for (int r = 1; r < RINGS - 1; ++r)
        for (int s = 0; s < SEGMENTS; ++s) {
            uint32_t a = RING(r, s), b = RING(r + 1, s), c = RING(r + 1, s + 1), d = RING(r, s + 1);
            indices[n++] = a, indices[n++] = b, indices[n++] = c;
            indices[n++] = a, indices[n++] = c, indices[n++] = d;
        }
#undef RING
    return n;
}

/* The tool's own filter: `steps` rounds of p ← p + λ (mean of the neighbours − p), all vertices at once.
 * Neighbours come from the triangles' edges; each interior edge is seen from both of its triangles, which weighs
 * every neighbour twice and so does not change the mean. */
static int my_laplacian(float *positions, size_t vertex_count, const uint32_t *indices, size_t index_count,
                        int steps, float lambda)
{
    float *sum = malloc(3 * vertex_count * sizeof *sum);
    float *count = malloc(vertex_count * sizeof *count);
    if (!sum || !count) {
        free(sum);
        free(count);
        return 1;
    }
    for (int step = 0; step < steps; ++step) {
        memset(sum, 0, 3 * vertex_count * sizeof *sum);
        memset(count, 0, vertex_count * sizeof *count);
        for (size_t i = 0; i < index_count; ++i) {
            uint32_t a = indices[i], b = indices[i - i % 3 + (i + 1) % 3]; /* the edge a → next corner */
            for (int c = 0; c < 3; ++c) {
                sum[3 * a + c] += positions[3 * b + c];
                sum[3 * b + c] += positions[3 * a + c];
            }
            count[a] += 1, count[b] += 1;
        }
        for (size_t v = 0; v < vertex_count; ++v)
            for (int c = 0; c < 3 && count[v] > 0; ++c)
                positions[3 * v + c] += lambda * (sum[3 * v + c] / count[v] - positions[3 * v + c]);
    }
    free(sum);
    free(count);
    return 0;
}

/* Mean and largest distance of the mesh's vertices to the true sphere. */
static void distance_to_sphere(const resurf_mesh *m, double *mean, double *max)
{
    *mean = *max = 0;
    for (size_t v = 0; v < m->vertex_count; ++v) {
        const double *p = m->positions + 3 * v;
        double d = fabs(sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - RADIUS);
        *mean += d / (double)m->vertex_count;
        *max = fmax(*max, d);
    }
}

static int fail(const char *what, const resurf_error *error)
{
    char text[512];
    resurf_format_error(text, sizeof text, error);
    fprintf(stderr, "restore_own_filter: %s: %s\n", what, text);
    return 1;
}

int main(void)
{
    enum { VERTICES = 2 + (RINGS - 1) * SEGMENTS, INDICES = 6 * SEGMENTS * (RINGS - 1) };
    static float positions[3 * VERTICES], filtered[3 * VERTICES];
    static uint32_t indices[INDICES];
    size_t index_count = make_sphere(positions, indices);

    /* The original mesh M, from the tool's arrays (tightly packed: the strides stay 0). */
    resurf_mesh_arrays arrays = resurf_mesh_arrays_default();
    arrays.vertex_count = VERTICES;
    arrays.positions.data = positions;
    arrays.indices = indices;
    arrays.index_count = index_count;
    resurf_error error;
    resurf_mesh *original = NULL, *processed = NULL;
    if (resurf_mesh_from_arrays(&arrays, &original, &error) != RESURF_OK)
        return fail("resurf_mesh_from_arrays (original)", &error);

    /* The tool's filter runs on its own float copy; the result becomes the processed mesh M'. */
    memcpy(filtered, positions, sizeof filtered);
    if (my_laplacian(filtered, VERTICES, indices, index_count, 10, 0.5f)) {
        resurf_mesh_free(original);
        fputs("restore_own_filter: out of memory\n", stderr);
        return 1;
    }
    arrays.positions.data = filtered;
    if (resurf_mesh_from_arrays(&arrays, &processed, &error) != RESURF_OK) {
        resurf_mesh_free(original);
        return fail("resurf_mesh_from_arrays (processed)", &error);
    }

    double mean_before, max_before, mean_after, max_after;
    distance_to_sphere(processed, &mean_before, &max_before);

    /* Restore M' onto the smooth surface of M, in place, with resurf's default options. */
    resurf_restore_report report;
    if (resurf_restore(original, processed, NULL, &report, &error) != RESURF_OK) {
        resurf_mesh_free(original);
        resurf_mesh_free(processed);
        return fail("resurf_restore", &error);
    }
    distance_to_sphere(processed, &mean_after, &max_after);

    /* The restored positions, back in the tool's float array. */
    resurf_mesh_arrays_out out = resurf_mesh_arrays_out_default();
    out.vertex_capacity = VERTICES;
    out.positions.data = filtered;
    resurf_status status = resurf_mesh_to_arrays(processed, &out, &error);
    resurf_mesh_free(original);
    resurf_mesh_free(processed);
    if (status != RESURF_OK)
        return fail("resurf_mesh_to_arrays", &error);

    printf("sphere of radius %.1f: %d vertices, %zu triangles; 10 Laplacian steps (lambda 0.5) of our own\n", RADIUS,
           (int)VERTICES, index_count / 3);
    printf("distance to the true sphere   mean         max\n");
    printf("  after our filter            %.3e    %.3e\n", mean_before, max_before);
    printf("  after resurf_restore        %.3e    %.3e\n", mean_after, max_after);
    printf("restored %zu of %zu vertices (mean move %.3e)\n", report.moved, report.vertices,
           report.mean_displacement);
    if (!(mean_after < mean_before && max_after < max_before)) {
        fputs("restore_own_filter: restoration did not bring the vertices closer to the surface\n", stderr);
        return 1;
    }
    printf("restore_own_filter: ok, mean distance fell %.0f-fold\n", mean_before / mean_after);
    return 0;
}
