/* Mesh validation: counts what is wrong with a mesh without changing it. Per-vertex checks (non-finite values,
 * unreferenced vertices) are over the mesh's attribute vertices; topology (boundaries, manifoldness, orientation,
 * components) is over exactly-welded positions, so attribute seams are not mistaken for boundaries.
 * No paper; the definitions are the usual ones of mesh-repair tools, spelled out in resurf.h. */
#include <stdlib.h>
#include <string.h>

#include "internal.h"

/* Does vertex v carry a NaN or infinity in any optional attribute? */
static int attributes_nonfinite(const resurf_mesh *m, size_t v)
{
    if (m->normals && !v3_finite(v3_load(m->normals + 3 * v)))
        return 1;
    for (unsigned k = 0; k < RESURF_MAX_TEXCOORD_SETS; ++k)
        if (m->texcoords[k] && (!isfinite(m->texcoords[k][2 * v]) || !isfinite(m->texcoords[k][2 * v + 1])))
            return 1;
    if (m->colors)
        for (int c = 0; c < 4; ++c)
            if (!isfinite(m->colors[4 * v + c]))
                return 1;
    for (size_t i = 0; i < m->extra_count; ++i) {
        const resurf_attribute *a = &m->extras[i];
        if (a->data)
            for (unsigned c = 0; c < a->components; ++c)
                if (!isfinite(a->data[a->components * v + c]))
                    return 1;
    }
    return 0;
}

/* Does manifold edge e run the same way in both its triangles (one of them is flipped)? wi are welded indices. */
static int edge_inconsistent(const resurfi_adjacency *adj, const uint32_t *wi, uint32_t e)
{
    const uint32_t a = adj->edge_vertices[2 * (size_t)e];
    int forward = 0;
    for (uint32_t k = adj->edge_face_offset[e]; k < adj->edge_face_offset[e + 1]; ++k) {
        uint32_t f = adj->edge_faces[k];
        for (int i = 0; i < 3; ++i)
            if (adj->face_edges[3 * (size_t)f + i] == e)
                forward += wi[3 * (size_t)f + i] == a; /* side i runs from corner i to corner i + 1 */
    }
    return forward != 1;
}

static void set_first(long long *first, size_t index)
{
    if (*first < 0)
        *first = (long long)index;
}

resurf_status resurf_mesh_validate(const resurf_mesh *mesh, resurf_validate_report *out, resurf_error *error)
{
    if (!mesh || !out)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "mesh or out is NULL");
    const size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
    if ((nv && !mesh->positions) || (nt && !mesh->indices))
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "mesh has counts but no positions or indices");
    if (nv > UINT32_MAX || nt > UINT32_MAX)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "more than 2^32 vertices or triangles");

    resurf_validate_report r;
    memset(&r, 0, sizeof r);
    r.vertex_count = nv;
    r.triangle_count = nt;
    r.first_nonfinite_vertex = r.first_out_of_range_triangle = r.first_degenerate_triangle = -1;
    r.first_zero_area_triangle = r.first_nonmanifold_edge_vertex = r.first_inconsistent_triangle = -1;

    const resurf_allocator *alloc = &mesh->allocator; /* validate has no options: the mesh's own */
    uint32_t *pos = resurfi_alloc(alloc, nv, sizeof *pos);
    uint32_t *wi = resurfi_alloc(alloc, nt, 3 * sizeof *wi);
    uint32_t *first_vertex = resurfi_alloc(alloc, nv, sizeof *first_vertex);
    uint8_t *referenced = resurfi_calloc(alloc, nv, 1);
    uint32_t *component = resurfi_alloc(alloc, nt, sizeof *component);
    resurfi_adjacency adj;
    memset(&adj, 0, sizeof adj);
    resurf_status status = RESURF_ERR_OUT_OF_MEMORY;
    if (!pos || !wi || !first_vertex || !referenced || !component)
        goto done;

    /* Vertices: non-finite values, then the exact weld. */
    for (size_t v = 0; v < nv; ++v) {
        int bad_position = !v3_finite(resurfi_position(mesh, (uint32_t)v));
        r.nonfinite_positions += bad_position;
        if (bad_position || attributes_nonfinite(mesh, v)) {
            r.nonfinite_vertices++;
            set_first(&r.first_nonfinite_vertex, v);
        }
    }
    if ((status = resurfi_weld_exact(alloc, mesh->positions, nv, pos, &r.position_count)) != RESURF_OK)
        goto done;
    for (size_t v = 0, seen = 0; v < nv; ++v)
        if (pos[v] == seen)
            first_vertex[seen++] = (uint32_t)v;

    /* Triangles: range, repeated positions, zero area. Out-of-range corners get an id no vertex has, which the
     * adjacency ignores. */
    const double diagonal = resurfi_finite_diagonal(mesh);
    const double area_limit = 1e-14 * diagonal * diagonal;
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *tri = mesh->indices + 3 * t;
        int in_range = 1;
        for (int i = 0; i < 3; ++i) {
            if (tri[i] < nv) {
                wi[3 * t + i] = pos[tri[i]];
                referenced[tri[i]] = 1;
            } else {
                wi[3 * t + i] = UINT32_MAX;
                r.out_of_range_indices++;
                in_range = 0;
            }
        }
        if (!in_range) {
            set_first(&r.first_out_of_range_triangle, t);
            continue;
        }
        const uint32_t *w = wi + 3 * t;
        if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) {
            r.degenerate_triangles++;
            set_first(&r.first_degenerate_triangle, t);
            continue;
        }
        vec3 a = resurfi_position(mesh, tri[0]), b = resurfi_position(mesh, tri[1]), c = resurfi_position(mesh, tri[2]);
        if (!v3_finite(a) || !v3_finite(b) || !v3_finite(c))
            continue;
        if (v3_len(v3_tri_cross(a, b, c)) <= area_limit) {
            r.zero_area_triangles++;
            set_first(&r.first_zero_area_triangle, t);
        }
    }
    for (size_t v = 0; v < nv; ++v)
        r.unreferenced_vertices += !referenced[v];

    /* Topology over positions. */
    if ((status = resurfi_adjacency_build(alloc, wi, nt, r.position_count, &adj)) != RESURF_OK)
        goto done;
    long long first_bad_triangle = -1;
    for (size_t e = 0; e < adj.edge_count; ++e) {
        uint32_t n = resurfi_edge_face_count(&adj, (uint32_t)e);
        if (n == 1)
            r.boundary_edges++;
        else if (n > 2)
            r.nonmanifold_edges++;
        else if (edge_inconsistent(&adj, wi, (uint32_t)e)) {
            r.inconsistent_edges++;
            long long f = adj.edge_faces[adj.edge_face_offset[e]]; /* the lower of the two */
            if (first_bad_triangle < 0 || f < first_bad_triangle)
                first_bad_triangle = f;
        }
    }
    r.first_inconsistent_triangle = first_bad_triangle;
    for (size_t p = 0; p < r.position_count; ++p) {
        if (!(adj.vertex_flags[p] & RESURFI_VERTEX_NONMANIFOLD))
            continue;
        r.nonmanifold_vertices++;
        /* Positions are numbered by first appearance, so the first flagged one has the lowest vertex. */
        set_first(&r.first_nonmanifold_edge_vertex, first_vertex[p]);
    }
    r.boundary_loops = resurfi_adjacency_boundary_loops(&adj);
    r.components = resurfi_adjacency_components(&adj, wi, component);
    status = RESURF_OK;

done:
    resurfi_adjacency_free(&adj);
    resurfi_free(alloc, pos);
    resurfi_free(alloc, wi);
    resurfi_free(alloc, first_vertex);
    resurfi_free(alloc, referenced);
    resurfi_free(alloc, component);
    if (status != RESURF_OK)
        return resurfi_error(error, status, "validating a mesh of %zu vertices and %zu triangles: %s", nv, nt,
                             resurf_status_string(status));
    *out = r;
    resurfi_clear_error(error);
    return RESURF_OK;
}

bool resurf_validation_ok(const resurf_validate_report *v)
{
    return v && v->nonfinite_positions == 0 && v->out_of_range_indices == 0;
}
