/* Triangle-mesh adjacency in compressed (CSR) arrays: vertex → faces, the sorted unique edges, edge → faces,
 * face → edges, vertex classification (boundary, non-manifold, unreferenced), boundary loops and connected
 * components. No paper: counting sorts and union-find, O(n log d) for n triangles of largest degree d.
 *
 * Fans. The faces around a vertex v form one fan when they are connected by walking from face to face across
 * manifold edges (exactly two faces) that end at v. A manifold vertex has one fan (a disc, or an open sector on
 * the boundary); a "bow-tie" vertex, where two surface sheets touch at one point, has two or more:
 *
 *        a       c
 *        |\     /|        faces (a, b, v) and (v, d, c) share only v:
 *        | \   / |        two fans at v, so v is non-manifold
 *        |  \ /  |
 *        |   v   |
 *        |  / \  |
 *        | /   \ |
 *        |/     \|
 *        b       d
 *
 * Boundary loops are counted on the surface obtained by splitting every vertex into one copy per fan, which is a
 * manifold wherever no edge has more than two faces. A boundary edge joins the fan of its face at one end to the
 * fan of that face at the other end, and each connected set of fans joined this way is one loop. On a manifold
 * mesh every fan touches zero or two boundary edges, so these sets are exactly the boundary curves; at a bow-tie
 * vertex the two sheets keep their own loops instead of merging into a figure eight. */
#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "union_find.h"

/* Is triangle t usable: every index in range and no index repeated? */
static int triangle_valid(const uint32_t *t, size_t vertex_count)
{
    return t[0] < vertex_count && t[1] < vertex_count && t[2] < vertex_count && t[0] != t[1] && t[1] != t[2] &&
           t[0] != t[2];
}

static int compare_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* Sorts a short list in place: insertion sort for the usual handful of neighbours, qsort for high degrees. */
static void sort_u64(uint64_t *a, size_t n)
{
    if (n > 32) {
        qsort(a, n, sizeof *a, compare_u64);
        return;
    }
    for (size_t i = 1; i < n; ++i) {
        uint64_t x = a[i];
        size_t j = i;
        for (; j > 0 && a[j - 1] > x; --j)
            a[j] = a[j - 1];
        a[j] = x;
    }
}

/* Position of value x in the sorted list a[0..n), or n when absent. */
static size_t find_sorted(const uint32_t *a, size_t n, uint32_t x)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (a[mid] < x)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < n && a[lo] == x ? lo : n;
}

void resurfi_adjacency_free(resurfi_adjacency *adj)
{
    if (!adj)
        return;
    resurfi_free(&adj->alloc, adj->vertex_face_offset);
    resurfi_free(&adj->alloc, adj->vertex_faces);
    resurfi_free(&adj->alloc, adj->vertex_edge_offset);
    resurfi_free(&adj->alloc, adj->edge_vertices);
    resurfi_free(&adj->alloc, adj->edge_face_offset);
    resurfi_free(&adj->alloc, adj->edge_faces);
    resurfi_free(&adj->alloc, adj->face_edges);
    resurfi_free(&adj->alloc, adj->vertex_flags);
    memset(adj, 0, sizeof *adj);
}

void resurfi_adjacency_drop_edges(resurfi_adjacency *adj)
{
    resurfi_free(&adj->alloc, adj->vertex_edge_offset);
    resurfi_free(&adj->alloc, adj->edge_vertices);
    resurfi_free(&adj->alloc, adj->edge_face_offset);
    resurfi_free(&adj->alloc, adj->edge_faces);
    resurfi_free(&adj->alloc, adj->face_edges);
    adj->vertex_edge_offset = adj->edge_vertices = adj->edge_face_offset = adj->edge_faces = adj->face_edges = NULL;
    adj->edge_count = 0;
}

uint32_t resurfi_adjacency_find_edge(const resurfi_adjacency *adj, uint32_t a, uint32_t b)
{
    if (a == b || a >= adj->vertex_count || b >= adj->vertex_count)
        return UINT32_MAX;
    uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
    uint32_t first = adj->vertex_edge_offset[lo], last = adj->vertex_edge_offset[lo + 1];
    while (first < last) {
        uint32_t mid = first + (last - first) / 2;
        if (adj->edge_vertices[2 * (size_t)mid + 1] < hi)
            first = mid + 1;
        else
            last = mid;
    }
    if (first < adj->vertex_edge_offset[lo + 1] && adj->edge_vertices[2 * (size_t)first + 1] == hi)
        return first;
    return UINT32_MAX;
}

/* ---- build, in phase order ----------------------------------------------------------------------------------- */

/* Phase 1: vertex → faces, each list in increasing face order. */
static resurf_status build_vertex_faces(resurfi_adjacency *adj, const uint32_t *indices, uint32_t *cursor)
{
    const size_t nv = adj->vertex_count, nt = adj->triangle_count;
    uint32_t *offset = adj->vertex_face_offset = resurfi_calloc(&adj->alloc, nv + 1, sizeof *offset);
    if (!offset)
        return RESURF_ERR_OUT_OF_MEMORY;
    size_t total = 0;
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *tri = indices + 3 * t;
        if (!triangle_valid(tri, nv))
            continue;
        for (int i = 0; i < 3; ++i)
            offset[tri[i] + 1]++;
        total += 3;
    }
    for (size_t v = 0; v < nv; ++v)
        offset[v + 1] += offset[v];
    if (!(adj->vertex_faces = resurfi_alloc(&adj->alloc, total, sizeof *adj->vertex_faces)))
        return RESURF_ERR_OUT_OF_MEMORY;
    memcpy(cursor, offset, nv * sizeof *cursor);
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *tri = indices + 3 * t;
        if (triangle_valid(tri, nv))
            for (int i = 0; i < 3; ++i)
                adj->vertex_faces[cursor[tri[i]]++] = (uint32_t)t;
    }
    return RESURF_OK;
}

/* Phase 2: the unique edges (a, b), a < b, sorted: for each a in turn, the neighbours b > a found in a's faces.
 * Each such neighbour is the far end of one side of the face (a is a corner of it), so the same pass gives every
 * side its edge id: the face → edges table costs no edge look-up. scratch holds (b, side slot 3 f + i) pairs with b
 * in the high half, so sorting them groups the sides of each edge. */
static resurf_status build_edges(resurfi_adjacency *adj, const uint32_t *indices, uint64_t *scratch)
{
    const size_t nv = adj->vertex_count, nt = adj->triangle_count;
    const uint32_t *offset = adj->vertex_face_offset;
    size_t bound = offset[nv]; /* 3 per valid triangle: every edge has at least one face */
    uint32_t *edge_offset = adj->vertex_edge_offset = resurfi_alloc(&adj->alloc, nv + 1, sizeof *edge_offset);
    uint32_t *ev = adj->edge_vertices = resurfi_alloc(&adj->alloc, bound, 2 * sizeof *ev);
    uint32_t *fe = adj->face_edges = resurfi_alloc(&adj->alloc, nt, 3 * sizeof *fe);
    if (!edge_offset || !ev || !fe)
        return RESURF_ERR_OUT_OF_MEMORY;
    /* sides of ignored triangles keep UINT32_MAX; every side of a valid one is set below */
    for (size_t t = 0; t < nt; ++t)
        if (!triangle_valid(indices + 3 * t, nv))
            fe[3 * t] = fe[3 * t + 1] = fe[3 * t + 2] = UINT32_MAX;
    size_t count = 0;
    for (size_t a = 0; a < nv; ++a) {
        edge_offset[a] = (uint32_t)count;
        size_t n = 0;
        for (uint32_t k = offset[a]; k < offset[a + 1]; ++k) {
            const uint32_t f = adj->vertex_faces[k];
            const uint32_t *tri = indices + 3 * (size_t)f;
            int j = tri[0] == a ? 0 : tri[1] == a ? 1 : 2;
            int next = j == 2 ? 0 : j + 1, prev = j == 0 ? 2 : j - 1;
            /* side j runs from a to the next corner, side prev from the previous corner to a */
            if (tri[next] > a)
                scratch[n++] = (uint64_t)tri[next] << 32 | (3 * f + (uint32_t)j);
            if (tri[prev] > a)
                scratch[n++] = (uint64_t)tri[prev] << 32 | (3 * f + (uint32_t)prev);
        }
        sort_u64(scratch, n);
        for (size_t i = 0; i < n; ++i) {
            uint32_t b = (uint32_t)(scratch[i] >> 32);
            if (i == 0 || b != (uint32_t)(scratch[i - 1] >> 32)) {
                ev[2 * count] = (uint32_t)a;
                ev[2 * count + 1] = b;
                ++count;
            }
            fe[(uint32_t)scratch[i]] = (uint32_t)(count - 1);
        }
    }
    edge_offset[nv] = (uint32_t)count;
    adj->edge_count = count;
    uint32_t *shrunk = resurfi_realloc(&adj->alloc, ev, count, 2 * sizeof *ev);
    if (shrunk) /* a failed shrink leaves the larger block, which is still correct */
        adj->edge_vertices = shrunk;
    return RESURF_OK;
}

/* Phase 3: edge → faces (each list in increasing face order), a counting sort of the face → edges table. */
static resurf_status build_edge_faces(resurfi_adjacency *adj)
{
    const size_t nt = adj->triangle_count, ne = adj->edge_count;
    const uint32_t *fe = adj->face_edges;
    uint32_t *offset = adj->edge_face_offset = resurfi_calloc(&adj->alloc, ne + 1, sizeof *offset);
    if (!offset)
        return RESURF_ERR_OUT_OF_MEMORY;
    for (size_t k = 0; k < 3 * nt; ++k)
        if (fe[k] != UINT32_MAX)
            offset[fe[k] + 1]++;
    for (size_t e = 0; e < ne; ++e)
        offset[e + 1] += offset[e];
    uint32_t *cursor = resurfi_alloc(&adj->alloc, ne, sizeof *cursor);
    if (!cursor || !(adj->edge_faces = resurfi_alloc(&adj->alloc, offset[ne], sizeof *adj->edge_faces))) {
        resurfi_free(&adj->alloc, cursor);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    memcpy(cursor, offset, ne * sizeof *cursor);
    for (size_t k = 0; k < 3 * nt; ++k)
        if (fe[k] != UINT32_MAX)
            adj->edge_faces[cursor[fe[k]]++] = (uint32_t)(k / 3);
    resurfi_free(&adj->alloc, cursor);
    return RESURF_OK;
}

/* The face across manifold edge e from face f, or UINT32_MAX when e is not manifold. */
static uint32_t other_face(const resurfi_adjacency *adj, uint32_t e, uint32_t f)
{
    if (e == UINT32_MAX || resurfi_edge_face_count(adj, e) != 2)
        return UINT32_MAX;
    const uint32_t *faces = adj->edge_faces + adj->edge_face_offset[e];
    return faces[0] == f ? faces[1] : faces[0];
}

/* Phase 4: flags, fans (fan[k] = global fan id of the k-th vertex_faces entry) and the number of fans. */
static void classify_vertices(resurfi_adjacency *adj, const uint32_t *indices, uint32_t *local, uint32_t *fan,
                              size_t *out_fans)
{
    const size_t nv = adj->vertex_count;
    const uint32_t *offset = adj->vertex_face_offset;
    for (size_t e = 0; e < adj->edge_count; ++e) {
        uint32_t n = resurfi_edge_face_count(adj, (uint32_t)e);
        uint8_t flag = n == 1 ? RESURFI_VERTEX_BOUNDARY : n > 2 ? RESURFI_VERTEX_NONMANIFOLD : 0;
        adj->vertex_flags[adj->edge_vertices[2 * e]] |= flag;
        adj->vertex_flags[adj->edge_vertices[2 * e + 1]] |= flag;
    }
    size_t fans = 0;
    for (size_t v = 0; v < nv; ++v) {
        const uint32_t *faces = adj->vertex_faces + offset[v];
        const size_t deg = offset[v + 1] - offset[v];
        if (deg == 0) {
            adj->vertex_flags[v] |= RESURFI_VERTEX_UNREFERENCED;
            continue;
        }
        for (size_t i = 0; i < deg; ++i)
            local[i] = (uint32_t)i;
        for (size_t i = 0; i < deg; ++i) {
            const uint32_t f = faces[i];
            const uint32_t *tri = indices + 3 * (size_t)f;
            int j = tri[0] == v ? 0 : tri[1] == v ? 1 : 2;
            /* The two sides of f that end at v: (v, next) is side j, (prev, v) is side j − 1. */
            const uint32_t *fe = adj->face_edges + 3 * (size_t)f;
            const uint32_t sides[2] = {fe[j], fe[(j + 2) % 3]};
            for (int s = 0; s < 2; ++s) {
                uint32_t g = other_face(adj, sides[s], f);
                if (g == UINT32_MAX)
                    continue;
                size_t k = find_sorted(faces, deg, g);
                if (k < deg)
                    resurfi_uf_union(local, (uint32_t)i, (uint32_t)k);
            }
        }
        /* Number the fans of v by their lowest face; roots are the lowest member, so one pass suffices. */
        size_t first = fans;
        for (size_t i = 0; i < deg; ++i) {
            uint32_t r = resurfi_uf_find(local, (uint32_t)i);
            if (r == i)
                fan[offset[v] + i] = (uint32_t)fans++;
            else
                fan[offset[v] + i] = fan[offset[v] + r];
        }
        if (fans - first > 1)
            adj->vertex_flags[v] |= RESURFI_VERTEX_NONMANIFOLD;
    }
    *out_fans = fans;
}

/* Phase 5: boundary loops = connected sets of fans joined by boundary edges (see the top of the file). */
static resurf_status count_boundary_loops(resurfi_adjacency *adj, const uint32_t *fan, size_t fan_count)
{
    uint32_t *parent = resurfi_alloc(&adj->alloc, fan_count, sizeof *parent);
    uint8_t *touched = resurfi_calloc(&adj->alloc, fan_count, 1);
    if (!parent || !touched) {
        resurfi_free(&adj->alloc, parent);
        resurfi_free(&adj->alloc, touched);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    for (size_t i = 0; i < fan_count; ++i)
        parent[i] = (uint32_t)i;
    const uint32_t *offset = adj->vertex_face_offset;
    for (size_t e = 0; e < adj->edge_count; ++e) {
        if (resurfi_edge_face_count(adj, (uint32_t)e) != 1)
            continue;
        const uint32_t f = adj->edge_faces[adj->edge_face_offset[e]];
        uint32_t ends[2];
        for (int s = 0; s < 2; ++s) {
            uint32_t v = adj->edge_vertices[2 * e + s];
            size_t deg = offset[v + 1] - offset[v];
            size_t k = find_sorted(adj->vertex_faces + offset[v], deg, f);
            ends[s] = fan[offset[v] + k]; /* f is one of v's faces: k < deg */
            touched[ends[s]] = 1;
        }
        resurfi_uf_union(parent, ends[0], ends[1]);
    }
    size_t loops = 0;
    for (size_t i = 0; i < fan_count; ++i)
        loops += touched[i] && resurfi_uf_find(parent, (uint32_t)i) == i;
    adj->boundary_loop_count = loops;
    resurfi_free(&adj->alloc, parent);
    resurfi_free(&adj->alloc, touched);
    return RESURF_OK;
}

/* The build; classify = 0 stops after phase 3 (see resurfi_adjacency_build_edges). */
static resurf_status build(const resurf_allocator *alloc, const uint32_t *indices, size_t triangle_count,
                           size_t vertex_count, int classify, resurfi_adjacency *out)
{
    if (!out)
        return RESURF_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    if (alloc)
        out->alloc = *alloc;
    if (triangle_count && !indices)
        return RESURF_ERR_INVALID_ARGUMENT;
    /* Offsets are 32-bit: 3 entries per triangle must fit, and vertex + 1 must not wrap. */
    if (triangle_count > (UINT32_MAX - 1) / 3 || vertex_count > UINT32_MAX - 1)
        return RESURF_ERR_LIMIT;
    out->vertex_count = vertex_count;
    out->triangle_count = triangle_count;
    uint32_t *scratch = NULL, *fan = NULL;
    uint64_t *pairs = NULL;
    resurf_status status = RESURF_ERR_OUT_OF_MEMORY;
    if (!(scratch = resurfi_alloc(&out->alloc, vertex_count, sizeof *scratch)))
        goto fail;
    if ((status = build_vertex_faces(out, indices, scratch)) != RESURF_OK)
        goto fail;
    /* Phase 2 needs 2 pairs per face of the busiest vertex, phase 4 one entry. */
    size_t max_degree = 0;
    for (size_t v = 0; v < vertex_count; ++v) {
        size_t d = out->vertex_face_offset[v + 1] - out->vertex_face_offset[v];
        max_degree = d > max_degree ? d : max_degree;
    }
    resurfi_free(&out->alloc, scratch);
    status = RESURF_ERR_OUT_OF_MEMORY;
    scratch = NULL;
    if (!(pairs = resurfi_alloc(&out->alloc, 2 * max_degree + 1, sizeof *pairs)))
        goto fail;
    if ((status = build_edges(out, indices, pairs)) != RESURF_OK)
        goto fail;
    resurfi_free(&out->alloc, pairs);
    pairs = NULL;
    if ((status = build_edge_faces(out)) != RESURF_OK)
        goto fail;
    if (!classify)
        return RESURF_OK;
    status = RESURF_ERR_OUT_OF_MEMORY;
    size_t fan_count = 0;
    scratch = resurfi_alloc(&out->alloc, max_degree + 1, sizeof *scratch);
    out->vertex_flags = resurfi_calloc(&out->alloc, vertex_count, sizeof *out->vertex_flags);
    fan = resurfi_alloc(&out->alloc, out->vertex_face_offset[vertex_count], sizeof *fan);
    if (!scratch || !out->vertex_flags || !fan)
        goto fail;
    classify_vertices(out, indices, scratch, fan, &fan_count);
    if ((status = count_boundary_loops(out, fan, fan_count)) != RESURF_OK)
        goto fail;
    resurfi_free(&out->alloc, scratch);
    resurfi_free(&out->alloc, fan);
    return RESURF_OK;
fail:
    resurfi_free(&out->alloc, scratch);
    resurfi_free(&out->alloc, pairs);
    resurfi_free(&out->alloc, fan);
    resurfi_adjacency_free(out);
    return status;
}

resurf_status resurfi_adjacency_build(const resurf_allocator *alloc, const uint32_t *indices, size_t triangle_count,
                                      size_t vertex_count, resurfi_adjacency *out)
{
    return build(alloc, indices, triangle_count, vertex_count, 1, out);
}

resurf_status resurfi_adjacency_build_edges(const resurf_allocator *alloc, const uint32_t *indices,
                                            size_t triangle_count, size_t vertex_count, resurfi_adjacency *out)
{
    return build(alloc, indices, triangle_count, vertex_count, 0, out);
}

size_t resurfi_adjacency_components(const resurfi_adjacency *adj, const uint32_t *indices, uint32_t *component)
{
    const size_t nt = adj->triangle_count;
    uint32_t *parent = component ? component : resurfi_alloc(&adj->alloc, nt, sizeof *parent);
    if (!parent)
        return SIZE_MAX;
    for (size_t t = 0; t < nt; ++t)
        parent[t] = adj->face_edges[3 * t] == UINT32_MAX ? UINT32_MAX : (uint32_t)t;
    /* Join each triangle to the first face of each of its corners: all faces of a vertex end up together. */
    for (size_t t = 0; t < nt; ++t) {
        if (parent[t] == UINT32_MAX)
            continue;
        for (int i = 0; i < 3; ++i) {
            uint32_t v = indices[3 * t + i];
            resurfi_uf_union(parent, (uint32_t)t, adj->vertex_faces[adj->vertex_face_offset[v]]);
        }
    }
    /* Point every triangle straight at its root, the lowest triangle of its component. Numbering in triangle
     * order then reaches each root before its members, so labels can overwrite the links in place. */
    for (size_t t = 0; t < nt; ++t)
        if (parent[t] != UINT32_MAX)
            parent[t] = resurfi_uf_find(parent, (uint32_t)t);
    size_t count = 0;
    for (size_t t = 0; t < nt; ++t) {
        if (parent[t] == UINT32_MAX)
            continue;
        uint32_t r = parent[t];
        parent[t] = r == t ? (uint32_t)count++ : parent[r];
    }
    if (!component)
        resurfi_free(&adj->alloc, parent);
    return count;
}

size_t resurfi_adjacency_boundary_loops(const resurfi_adjacency *adj) { return adj->boundary_loop_count; }
