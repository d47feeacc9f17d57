/* Example: levels of detail for a mesh held in memory, as a game tool has it.
 *
 * The tool's vertex buffer is interleaved floats (position, normal, texture coordinate: 32 bytes a vertex) with
 * 16-bit indices. This program
 *   1. builds such a buffer for a UV sphere of radius 1 (so that the true surface is known),
 *   2. makes a resurf_mesh from it with resurf_mesh_from_arrays (one copy, floats to doubles),
 *   3. asks resurf_simplify_lods for a chain of three levels (50 %, 25 %, 10 % of the triangles), every level
 *      restored onto the smooth surface of the ORIGINAL mesh,
 *   4. prints each level's triangles, the error resurf measured (distance to the input surface, relative to the
 *      bounding-box diagonal) and the largest distance of its vertices to the true sphere,
 *   5. copies each level back into the same 32-byte vertex layout with resurf_mesh_to_arrays.
 * It uses nothing but <resurf/resurf.h>. Exit status 0 when everything worked and made sense.
 * Build: cc lod_in_memory.c $(pkg-config --cflags --libs resurf) -lm */
#include <resurf/resurf.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* The tool's own vertex format. */
typedef struct vertex {
    float position[3];
    float normal[3];
    float uv[2];
} vertex;

enum { RINGS = 48, SEGMENTS = 96 };

/* A UV sphere: (RINGS + 1) × (SEGMENTS + 1) vertices. The texture seam (u = 0 and u = 1) and the poles have one
 * vertex per texture coordinate at the same position, as in most game assets; resurf keeps such seams intact.
 * Positions at the seam and the poles are computed from the same angles so that they are bit-identical. */
static size_t make_sphere(vertex *v, uint16_t *indices)
{
    const double pi = 3.14159265358979323846;
    for (int r = 0; r <= RINGS; ++r) {
        double theta = pi * r / RINGS;
        for (int s = 0; s <= SEGMENTS; ++s) {
            double phi = 2 * pi * (s % SEGMENTS) / SEGMENTS;
            double p[3] = {sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta)};
            if (r == 0 || r == RINGS)
                p[0] = p[1] = 0, p[2] = r == 0 ? 1 : -1;
            vertex *out = &v[r * (SEGMENTS + 1) + s];
            for (int c = 0; c < 3; ++c)
                out->position[c] = out->normal[c] = (float)p[c]; /* unit sphere: the normal is the position */
            out->uv[0] = (float)s / SEGMENTS;
            out->uv[1] = (float)r / RINGS;
        }
    }
    /* Quads (a, b, c, d) between rings r and r + 1, counter-clockwise seen from outside; at the poles two corners
     * coincide and the quad is one triangle. */
    size_t n = 0;
    for (int r = 0; r < RINGS; ++r)
        for (int s = 0; s < SEGMENTS; ++s) {
            uint16_t a = (uint16_t)(r * (SEGMENTS + 1) + s), b = (uint16_t)(a + SEGMENTS + 1);
            uint16_t c = (uint16_t)(b + 1), d = (uint16_t)(a + 1);
            if (r != 0)
                indices[n++] = a, indices[n++] = b, indices[n++] = d;
            if (r != RINGS - 1)
                indices[n++] = d, indices[n++] = b, indices[n++] = c;
        }
    return n;
}

static int fail(const char *what, const resurf_error *error)
{
    char text[512];
    resurf_format_error(text, sizeof text, error);
    fprintf(stderr, "lod_in_memory: %s: %s\n", what, text);
    return 1;
}

int main(void)
{
    /* 1. The tool's buffers. */
    enum { VERTICES = (RINGS + 1) * (SEGMENTS + 1) };
    static vertex vertices[VERTICES];
    static uint16_t indices[6 * RINGS * SEGMENTS];
    size_t index_count = make_sphere(vertices, indices);

    /* 2. Describe the interleaved layout: one stride for every attribute, data pointers inside the first vertex. */
    resurf_mesh_arrays arrays = resurf_mesh_arrays_default();
    arrays.vertex_count = VERTICES;
    arrays.positions.data = vertices[0].position;
    arrays.positions.stride = sizeof(vertex);
    arrays.normals.data = vertices[0].normal;
    arrays.normals.stride = sizeof(vertex);
    arrays.texcoords[0].data = vertices[0].uv;
    arrays.texcoords[0].stride = sizeof(vertex);
    arrays.indices = indices;
    arrays.index_type = RESURF_INDEX_UINT16;
    arrays.index_count = index_count;
    resurf_error error;
    resurf_mesh *mesh = NULL;
    if (resurf_mesh_from_arrays(&arrays, &mesh, &error) != RESURF_OK)
        return fail("resurf_mesh_from_arrays", &error);
    printf("input: %zu vertices, %zu triangles\n", mesh->vertex_count, mesh->triangle_count);

    /* 3. The chain. Each level continues from the previous one but is restored onto the original surface. */
    const double ratios[3] = {0.5, 0.25, 0.1};
    resurf_mesh *levels[3] = {NULL, NULL, NULL};
    resurf_simplify_report reports[3];
    resurf_simplify_options options = resurf_simplify_options_default();
    if (resurf_simplify_lods(mesh, ratios, 3, &options, levels, reports, &error) != RESURF_OK) {
        resurf_mesh_free(mesh);
        return fail("resurf_simplify_lods", &error);
    }

    /* 4 and 5. Report each level and copy it back into the tool's own format. */
    int ok = 1;
    printf("%-6s %-6s %10s %16s %18s\n", "level", "ratio", "triangles", "measured error", "max |r - 1| (true)");
    for (int k = 0; k < 3; ++k) {
        const resurf_mesh *level = levels[k];
        vertex *out = malloc(level->vertex_count * sizeof *out);
        uint16_t *out_indices = malloc(3 * level->triangle_count * sizeof *out_indices);
        resurf_mesh_arrays_out dest = resurf_mesh_arrays_out_default();
        dest.vertex_capacity = level->vertex_count;
        dest.positions.data = out ? out[0].position : NULL;
        dest.positions.stride = sizeof(vertex);
        dest.normals.data = out ? out[0].normal : NULL;
        dest.normals.stride = sizeof(vertex);
        dest.texcoords[0].data = out ? out[0].uv : NULL;
        dest.texcoords[0].stride = sizeof(vertex);
        dest.indices = out_indices;
        dest.index_type = RESURF_INDEX_UINT16;
        dest.index_capacity = 3 * level->triangle_count;
        if (!out || !out_indices || resurf_mesh_to_arrays(level, &dest, &error) != RESURF_OK) {
            ok = !fail("resurf_mesh_to_arrays", &error);
        } else {
            /* The distance of the copied vertices to the true sphere: what restoration keeps small. It is not 0 by
             * design: resurf lifts each vertex by about the chord sag of its edges (sag_offset 1) so that the flat
             * triangles straddle the surface instead of cutting inside it. */
            double worst = 0;
            for (size_t v = 0; v < level->vertex_count; ++v) {
                const float *p = out[v].position;
                worst = fmax(worst, fabs(sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]) - 1));
            }
            printf("%-6d %-6g %10zu %16.3e %18.3e\n", k + 1, ratios[k], level->triangle_count,
                   reports[k].max_distance_rel, worst);
            printf("       copied back %zu vertices and %zu indices into 32-byte vertices\n", level->vertex_count,
                   3 * level->triangle_count);
            /* Sanity: at most the asked share of triangles, fewer than the level before, close to the sphere. */
            size_t before = k ? levels[k - 1]->triangle_count : mesh->triangle_count;
            if (level->triangle_count > ratios[k] * (double)mesh->triangle_count || level->triangle_count >= before ||
                worst > 0.05)
                ok = 0;
        }
        free(out);
        free(out_indices);
    }
    for (int k = 0; k < 3; ++k)
        resurf_mesh_free(levels[k]);
    resurf_mesh_free(mesh);
    if (!ok) {
        fprintf(stderr, "lod_in_memory: a level is not what it should be\n");
        return 1;
    }
    puts("lod_in_memory: ok");
    return 0;
}
