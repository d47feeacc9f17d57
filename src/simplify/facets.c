/* Flat shading. An exporter that writes each face's own normal at its corners (STL, flat-shaded low-poly art, many
 * CAD exports) splits the normals wherever the surface bends: every bend is a normal seam, every position a junction
 * of wedges, and no collapse could be made. Such normals say nothing the geometry does not. So, per connected part
 * of the input: when every corner's normal is its own face's (within SAME_NORMAL_COS) and some position carries
 * split normals, the part is flat-shaded; the simplifier works on a copy whose normals there are zero (no normal:
 * equal wedges weld, no seam is read into them, the restorer sees no crease in them and estimates S's normals from
 * the geometry), and each level's vertices with no normal are shaded flat again from the level's own faces. A
 * smooth-shaded part keeps its normals: a vertex shared by faces that bend is not any one face's. */
#include <math.h>

#include "simplify_internal.h"
#include "../union_find.h"

/* A triangle's area vector, or zero when it is not finite. */
static vec3 face_cross(const resurf_mesh *m, uint32_t t)
{
    const uint32_t *i = m->indices + 3 * (size_t)t;
    vec3 n = v3_tri_cross(resurfi_position(m, i[0]), resurfi_position(m, i[1]), resurfi_position(m, i[2]));
    return v3_finite(n) ? n : v3(0, 0, 0);
}

/* Is unit vector u within SAME_NORMAL_COS of the direction of n (n non-zero)? */
static int same_direction(vec3 u, vec3 n) { return v3_dot(u, n) >= RESURFI_SAME_NORMAL_COS * sqrt(v3_len2(n)); }

/* The input's normal at v, unit, or zero when it has none (zero or not finite). */
static vec3 input_normal(const resurf_mesh *m, uint32_t v)
{
    vec3 n = v3_normalize(v3_load(m->normals + 3 * (size_t)v));
    return v3_finite(n) ? n : v3(0, 0, 0);
}

resurf_status facets_derive(const resurf_mesh *in, const resurf_allocator *alloc, resurf_mesh **out_derived)
{
    *out_derived = NULL;
    if (!in->normals || !in->triangle_count)
        return RESURF_OK;
    size_t nv = in->vertex_count, nt = in->triangle_count, np = 0;
    uint32_t *pos = resurfi_alloc(alloc, nv + 1, sizeof *pos);    /* per vertex: its position */
    uint32_t *part = resurfi_alloc(alloc, nv + 1, sizeof *part);   /* per position: union-find over edges */
    uint32_t *first = resurfi_alloc(alloc, nv + 1, sizeof *first); /* per position: its first vertex */
    uint8_t *flags = resurfi_calloc(alloc, nv + 1, 1);             /* per position, then per part: SMOOTH, SPLIT */
    resurf_status st = pos && part && first && flags ? RESURF_OK : RESURF_ERR_OUT_OF_MEMORY;
    if (st == RESURF_OK)
        st = resurfi_weld_exact(alloc, in->positions, nv, pos, &np);
    enum { SMOOTH = 1, SPLIT = 2 };
    size_t derived = 0;
    if (st == RESURF_OK) {
        for (size_t p = 0; p < np; ++p)
            part[p] = (uint32_t)p, first[p] = NONE;
        for (size_t t = 0; t < nt; ++t) {
            const uint32_t *i = in->indices + 3 * t;
            resurfi_uf_union(part, pos[i[0]], pos[i[1]]);
            resurfi_uf_union(part, pos[i[0]], pos[i[2]]);
            vec3 n = face_cross(in, (uint32_t)t);
            if (v3_len2(n) == 0)
                continue; /* a degenerate face has no normal to compare */
            for (int k = 0; k < 3; ++k) {
                vec3 u = input_normal(in, i[k]);
                if (v3_len2(u) > 0 && !same_direction(u, n))
                    flags[pos[i[k]]] |= SMOOTH; /* a normal that is not its face's */
            }
        }
        for (size_t v = 0; v < nv; ++v) {
            uint32_t p = pos[v];
            if (first[p] == NONE)
                first[p] = (uint32_t)v;
            else if (v3_dot(input_normal(in, first[p]), input_normal(in, (uint32_t)v)) < RESURFI_SAME_NORMAL_COS)
                flags[p] |= SPLIT;
        }
        for (size_t p = 0; p < np; ++p) { /* positions' flags to their parts' roots (a root is its part's lowest) */
            uint32_t r = resurfi_uf_find(part, (uint32_t)p);
            flags[r] |= flags[p];
        }
        for (size_t v = 0; v < nv; ++v)
            derived += flags[resurfi_uf_find(part, pos[v])] == SPLIT;
    }
    if (st == RESURF_OK && derived) {
        st = resurf_mesh_clone_with(in, alloc, out_derived, NULL);
        for (size_t v = 0; st == RESURF_OK && v < nv; ++v)
            if (flags[resurfi_uf_find(part, pos[v])] == SPLIT)
                v3_store((*out_derived)->normals + 3 * v, v3(0, 0, 0));
    }
    resurfi_free(alloc, pos);
    resurfi_free(alloc, part);
    resurfi_free(alloc, first);
    resurfi_free(alloc, flags);
    return st;
}

/* Copies vertex src[i] of m to new vertex vertex_count + i, every attribute with it. */
static resurf_status append_copies(resurf_mesh *m, const uint32_t *src, size_t count)
{
    const resurf_allocator *a = &m->allocator;
    size_t nv = m->vertex_count, n = nv + count;
    double **d3[2] = {&m->positions, &m->normals};
    for (int k = 0; k < 2; ++k) {
        if (!*d3[k])
            continue;
        double *p = resurfi_realloc(a, *d3[k], n, 3 * sizeof *p);
        if (!p)
            return RESURF_ERR_OUT_OF_MEMORY;
        *d3[k] = p;
        for (size_t i = 0; i < count; ++i)
            memcpy(p + 3 * (nv + i), p + 3 * (size_t)src[i], 3 * sizeof *p);
    }
    for (unsigned k = 0; k < RESURF_MAX_TEXCOORD_SETS; ++k) {
        if (!m->texcoords[k])
            continue;
        double *p = resurfi_realloc(a, m->texcoords[k], n, 2 * sizeof *p);
        if (!p)
            return RESURF_ERR_OUT_OF_MEMORY;
        m->texcoords[k] = p;
        for (size_t i = 0; i < count; ++i)
            memcpy(p + 2 * (nv + i), p + 2 * (size_t)src[i], 2 * sizeof *p);
    }
    if (m->colors) {
        double *p = resurfi_realloc(a, m->colors, n, 4 * sizeof *p);
        if (!p)
            return RESURF_ERR_OUT_OF_MEMORY;
        m->colors = p;
        for (size_t i = 0; i < count; ++i)
            memcpy(p + 4 * (nv + i), p + 4 * (size_t)src[i], 4 * sizeof *p);
    }
    for (size_t e = 0; e < m->extra_count; ++e) {
        unsigned c = m->extras[e].components;
        float *p = resurfi_realloc(a, m->extras[e].data, n, c * sizeof *p);
        if (!p)
            return RESURF_ERR_OUT_OF_MEMORY;
        m->extras[e].data = p;
        for (size_t i = 0; i < count; ++i)
            memcpy(p + c * (nv + i), p + c * (size_t)src[i], c * sizeof *p);
    }
    m->vertex_count = n;
    return RESURF_OK;
}

/* A vertex's corners gathered by face direction: each group becomes one vertex with the area-weighted mean of its
 * faces' normals. A face joins the first group whose first face points its way (within PLANE_COS), so the faces of
 * one plane share a vertex and any bend splits it: the level is as flat-shaded as its input. PLANE_COS is about
 * 1.4e-5 radians: a planar region's level is planar to 1e-12 of the diagonal, its faces' normals to far less. */
static const double PLANE_COS = 1 - 1e-10;

typedef struct facet_group {
    vec3 first; /* unit normal of the group's first real face; zero while it has only degenerate ones */
    vec3 sum;   /* its faces' area vectors */
} facet_group;

resurf_status facets_shade(resurf_mesh *m)
{
    if (!m->normals || !m->triangle_count)
        return RESURF_OK;
    const resurf_allocator *a = &m->allocator;
    size_t nv = m->vertex_count, nt = m->triangle_count, nc = 3 * nt;
    uint32_t *start = resurfi_calloc(a, nv + 2, sizeof *start);
    uint32_t *corners = resurfi_alloc(a, nc + 1, sizeof *corners);
    uint32_t *group_of = resurfi_alloc(a, nc + 1, sizeof *group_of); /* per corner of a vertex with no normal */
    vec3 *face = resurfi_alloc(a, nt, sizeof *face);
    u32vec copies = {0};       /* the vertex each new vertex copies */
    double *copy_normals = NULL; /* 3 per new vertex */
    size_t copy_cap = 0;
    facet_group *groups = NULL;
    size_t groups_cap = 0;
    resurf_status st = start && corners && group_of && face ? RESURF_OK : RESURF_ERR_OUT_OF_MEMORY;
    if (st != RESURF_OK)
        goto done;
    for (size_t t = 0; t < nt; ++t)
        face[t] = face_cross(m, (uint32_t)t);
    /* The corners of every vertex with no normal, vertex by vertex (a counting sort). */
    for (size_t c = 0; c < nc; ++c)
        if (v3_len2(v3_load(m->normals + 3 * (size_t)m->indices[c])) == 0)
            start[m->indices[c] + 2]++;
    for (size_t v = 0; v < nv; ++v)
        start[v + 2] += start[v + 1];
    for (size_t c = 0; c < nc; ++c)
        if (v3_len2(v3_load(m->normals + 3 * (size_t)m->indices[c])) == 0)
            corners[start[m->indices[c] + 1]++] = (uint32_t)c;
    for (size_t v = 0; v < nv && st == RESURF_OK; ++v) {
        size_t count = 0, begin = start[v], end = start[v + 1];
        if (begin == end)
            continue;
        if (end - begin > groups_cap) {
            facet_group *g = resurfi_realloc(a, groups, end - begin, sizeof *g);
            if (!g) {
                st = RESURF_ERR_OUT_OF_MEMORY;
                break;
            }
            groups = g, groups_cap = end - begin;
        }
        for (size_t i = begin; i < end; ++i) {
            vec3 n = face[corners[i] / 3];
            size_t g = 0;
            if (v3_len2(n) > 0) /* a degenerate face joins the first group */
                while (g < count && v3_len2(groups[g].first) > 0 &&
                       v3_dot(groups[g].first, n) < PLANE_COS * sqrt(v3_len2(n)))
                    ++g;
            if (g == count)
                groups[count++] = (facet_group){v3_normalize(n), v3(0, 0, 0)};
            else if (v3_len2(groups[g].first) == 0)
                groups[g].first = v3_normalize(n);
            groups[g].sum = v3_add(groups[g].sum, n);
            group_of[i] = (uint32_t)g;
        }
        if (copies.count + count > copy_cap) {
            size_t cap = 2 * (copies.count + count);
            double *p = resurfi_realloc(a, copy_normals, cap, 3 * sizeof *p);
            if (!p) {
                st = RESURF_ERR_OUT_OF_MEMORY;
                break;
            }
            copy_normals = p, copy_cap = cap;
        }
        size_t first_copy = copies.count;
        for (size_t g = 0; g < count; ++g) {
            vec3 n = v3_normalize(groups[g].sum);
            if (!(v3_len2(n) > 0))
                n = v3(0, 0, 1); /* only degenerate faces: any unit normal will do */
            if (g == 0) {
                v3_store(m->normals + 3 * v, n);
            } else {
                v3_store(copy_normals + 3 * copies.count, n);
                if (!vec_push(a, &copies, (uint32_t)v)) {
                    st = RESURF_ERR_OUT_OF_MEMORY;
                    break;
                }
            }
        }
        for (size_t i = begin; i < end && st == RESURF_OK; ++i)
            if (group_of[i])
                m->indices[corners[i]] = (uint32_t)(nv + first_copy + group_of[i] - 1);
    }
    if (st == RESURF_OK && copies.count && (st = append_copies(m, copies.data, copies.count)) == RESURF_OK)
        memcpy(m->normals + 3 * nv, copy_normals, 3 * copies.count * sizeof *copy_normals);
done:
    resurfi_free(a, start);
    resurfi_free(a, corners);
    resurfi_free(a, group_of);
    resurfi_free(a, face);
    resurfi_free(a, groups);
    resurfi_free(a, copy_normals);
    resurfi_free(a, copies.data);
    return st;
}
