/* src/adjacency.c: CSR adjacency, vertex classes, components and boundary loops against hand-counted meshes, a
 * brute-force recount on random meshes, and Euler's formula. */
#include <string.h>

#include "testutil.h"

static resurfi_adjacency build(const resurf_mesh *m)
{
    resurfi_adjacency adj;
    ck_assert_int_eq(resurfi_adjacency_build(NULL, m->indices, m->triangle_count, m->vertex_count, &adj), RESURF_OK);
    ck_assert_uint_eq(adj.vertex_count, m->vertex_count);
    ck_assert_uint_eq(adj.triangle_count, m->triangle_count);
    return adj;
}

static size_t count_edges_with(const resurfi_adjacency *adj, uint32_t faces)
{
    size_t n = 0;
    for (size_t e = 0; e < adj->edge_count; ++e)
        n += resurfi_edge_face_count(adj, (uint32_t)e) == faces;
    return n;
}

static size_t count_flag(const resurfi_adjacency *adj, uint8_t flag)
{
    size_t n = 0;
    for (size_t v = 0; v < adj->vertex_count; ++v)
        n += (adj->vertex_flags[v] & flag) != 0;
    return n;
}

/* The regular tetrahedron of testutil (faces 012, 023, 031, 132): edges sorted (0,1) (0,2) (0,3) (1,2) (1,3)
 * (2,3) = ids 0..5, each on two faces. */
START_TEST(adjacency_tetrahedron)
{
    resurf_mesh *m = tu_tetrahedron();
    resurfi_adjacency adj = build(m);
    ck_assert_uint_eq(adj.edge_count, 6);
    const uint32_t edges[] = {0, 1, 0, 2, 0, 3, 1, 2, 1, 3, 2, 3};
    for (int i = 0; i < 12; ++i)
        ck_assert_uint_eq(adj.edge_vertices[i], edges[i]);
    ck_assert_uint_eq(count_edges_with(&adj, 2), 6);
    /* Face 0 = (0,1,2): sides (0,1) (1,2) (2,0) are edges 0, 3, 1. Face 3 = (1,3,2): (1,3) (3,2) (2,1) = 4, 5, 3. */
    const uint32_t fe0[] = {0, 3, 1}, fe3[] = {4, 5, 3};
    for (int i = 0; i < 3; ++i) {
        ck_assert_uint_eq(adj.face_edges[i], fe0[i]);
        ck_assert_uint_eq(adj.face_edges[9 + i], fe3[i]);
    }
    /* Edge (0,1) lies on faces 0 (012) and 2 (031); edge (1,2) on faces 0 and 3. */
    ck_assert_uint_eq(adj.edge_faces[adj.edge_face_offset[0]], 0);
    ck_assert_uint_eq(adj.edge_faces[adj.edge_face_offset[0] + 1], 2);
    ck_assert_uint_eq(adj.edge_faces[adj.edge_face_offset[3]], 0);
    ck_assert_uint_eq(adj.edge_faces[adj.edge_face_offset[3] + 1], 3);
    /* Faces of vertex 3: 1, 2, 3 in order. */
    ck_assert_uint_eq(adj.vertex_face_offset[4] - adj.vertex_face_offset[3], 3);
    for (uint32_t k = 0; k < 3; ++k)
        ck_assert_uint_eq(adj.vertex_faces[adj.vertex_face_offset[3] + k], k + 1);
    for (size_t v = 0; v < 4; ++v)
        ck_assert_uint_eq(adj.vertex_flags[v], 0);
    ck_assert_uint_eq(resurfi_adjacency_boundary_loops(&adj), 0);
    uint32_t comp[4];
    ck_assert_uint_eq(resurfi_adjacency_components(&adj, m->indices, comp), 1);
    for (int t = 0; t < 4; ++t)
        ck_assert_uint_eq(comp[t], 0);
    resurfi_adjacency_free(&adj);
    resurf_mesh_free(m);
}
END_TEST

/* The cube: 8 vertices, 18 edges (12 sides + 6 face diagonals), 12 faces, closed, V − E + F = 2. */
START_TEST(adjacency_cube)
{
    resurf_mesh *m = tu_cube();
    resurfi_adjacency adj = build(m);
    ck_assert_uint_eq(adj.edge_count, 18);
    ck_assert_uint_eq(count_edges_with(&adj, 2), 18);
    ck_assert_uint_eq(count_flag(&adj, 0xff), 0);
    ck_assert_uint_eq(resurfi_adjacency_boundary_loops(&adj), 0);
    ck_assert_uint_eq(resurfi_adjacency_components(&adj, m->indices, NULL), 1);
    resurfi_adjacency_free(&adj);
    resurf_mesh_free(m);
}
END_TEST

/* Edge lookup in both orders; absent, self and out-of-range pairs give UINT32_MAX. */
START_TEST(adjacency_find_edge)
{
    resurf_mesh *m = tu_cube();
    resurfi_adjacency adj = build(m);
    for (size_t e = 0; e < adj.edge_count; ++e) {
        uint32_t a = adj.edge_vertices[2 * e], b = adj.edge_vertices[2 * e + 1];
        ck_assert_uint_lt(a, b);
        if (e > 0) { /* sorted and unique */
            uint32_t pa = adj.edge_vertices[2 * e - 2], pb = adj.edge_vertices[2 * e - 1];
            ck_assert(pa < a || (pa == a && pb < b));
        }
        ck_assert_uint_eq(resurfi_adjacency_find_edge(&adj, a, b), e);
        ck_assert_uint_eq(resurfi_adjacency_find_edge(&adj, b, a), e);
    }
    /* 0 = (0,0,0) and 6 = (1,1,1) are opposite corners: no edge. */
    ck_assert_uint_eq(resurfi_adjacency_find_edge(&adj, 0, 6), UINT32_MAX);
    ck_assert_uint_eq(resurfi_adjacency_find_edge(&adj, 3, 3), UINT32_MAX);
    ck_assert_uint_eq(resurfi_adjacency_find_edge(&adj, 3, 8), UINT32_MAX);
    ck_assert_uint_eq(resurfi_adjacency_find_edge(&adj, 99, 1), UINT32_MAX);
    resurfi_adjacency_free(&adj);
    resurf_mesh_free(m);
}
END_TEST

/* The 3×3 grid of testutil (vertex j·4 + i at (i, j), square (i, j) split into triangles a b c and a c d):
 *
 *   12--13--14--15
 *    | / | / | / |
 *    8---9--10--11        33 edges: 12 horizontal + 12 vertical + 9 diagonals
 *    | / | / | / |        12 boundary edges (4n) on one loop, 12 boundary vertices
 *    4---5---6---7        interior vertices 5, 6, 9, 10
 *    | / | / | / |
 *    0---1---2---3
 */
START_TEST(adjacency_open_grid)
{
    resurf_mesh *m = tu_grid(3);
    resurfi_adjacency adj = build(m);
    ck_assert_uint_eq(adj.edge_count, 33);
    ck_assert_uint_eq(count_edges_with(&adj, 1), 12);
    ck_assert_uint_eq(count_edges_with(&adj, 2), 21);
    ck_assert_uint_eq(count_flag(&adj, RESURFI_VERTEX_BOUNDARY), 12);
    ck_assert_uint_eq(count_flag(&adj, RESURFI_VERTEX_NONMANIFOLD | RESURFI_VERTEX_UNREFERENCED), 0);
    const uint32_t interior[] = {5, 6, 9, 10};
    for (int i = 0; i < 4; ++i)
        ck_assert_uint_eq(adj.vertex_flags[interior[i]], 0);
    /* Faces around 5: (0,1,5) (0,5,4) (1,6,5) (4,5,9) (5,6,10) (5,10,9) = triangles 0 1 3 6 8 9. */
    const uint32_t faces5[] = {0, 1, 3, 6, 8, 9};
    ck_assert_uint_eq(adj.vertex_face_offset[6] - adj.vertex_face_offset[5], 6);
    for (int k = 0; k < 6; ++k)
        ck_assert_uint_eq(adj.vertex_faces[adj.vertex_face_offset[5] + k], faces5[k]);
    ck_assert_uint_eq(resurfi_adjacency_boundary_loops(&adj), 1);
    ck_assert_uint_eq(resurfi_adjacency_components(&adj, m->indices, NULL), 1);
    resurfi_adjacency_free(&adj);
    resurf_mesh_free(m);

    /* Bigger grids: 4n boundary edges, still one loop. */
    for (unsigned n = 1; n <= 12; n += 5) {
        m = tu_grid(n);
        adj = build(m);
        ck_assert_uint_eq(count_edges_with(&adj, 1), 4 * n);
        ck_assert_uint_eq(resurfi_adjacency_boundary_loops(&adj), 1);
        resurfi_adjacency_free(&adj);
        resurf_mesh_free(m);
    }
}
END_TEST

/* Two triangles that share nothing:  0-1-2 and 3-4-5. Two components, two loops, 6 boundary edges. */
START_TEST(adjacency_two_disjoint_triangles)
{
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 0, 0, 6, 0, 0, 5, 1, 0};
    const uint32_t t[] = {0, 1, 2, 3, 4, 5};
    resurf_mesh *m = tu_mesh(p, 6, t, 2);
    resurfi_adjacency adj = build(m);
    ck_assert_uint_eq(adj.edge_count, 6);
    ck_assert_uint_eq(count_edges_with(&adj, 1), 6);
    ck_assert_uint_eq(count_flag(&adj, RESURFI_VERTEX_BOUNDARY), 6);
    ck_assert_uint_eq(count_flag(&adj, RESURFI_VERTEX_NONMANIFOLD), 0);
    ck_assert_uint_eq(resurfi_adjacency_boundary_loops(&adj), 2);
    uint32_t comp[2];
    ck_assert_uint_eq(resurfi_adjacency_components(&adj, m->indices, comp), 2);
    ck_assert_uint_eq(comp[0], 0);
    ck_assert_uint_eq(comp[1], 1);
    resurfi_adjacency_free(&adj);
    resurf_mesh_free(m);
}
END_TEST

/* Three fins on one hinge: triangles (0,1,2), (1,0,3), (0,1,4) all contain edge (0,1).
 *
 *            4 (up, z = 1)
 *            |
 *       2    |               hinge 0 ---- 1 along x; fins towards 2 (+y), 3 (−y) and 4 (+z)
 *        \   |
 *     0 ------------ 1
 *        /
 *       3
 *
 * Edge (0,1) has three faces; 0 and 1 are non-manifold (and on the boundary: each fin has two free sides).
 * Splitting 0 and 1 into their fans leaves three separate triangles: three boundary loops. */
START_TEST(adjacency_nonmanifold_edge)
{
    const double p[] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1};
    const uint32_t t[] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    resurf_mesh *m = tu_mesh(p, 5, t, 3);
    resurfi_adjacency adj = build(m);
    ck_assert_uint_eq(adj.edge_count, 7);
    uint32_t hinge = resurfi_adjacency_find_edge(&adj, 1, 0);
    ck_assert_uint_eq(hinge, 0);
    ck_assert_uint_eq(resurfi_edge_face_count(&adj, hinge), 3);
    ck_assert_uint_eq(count_edges_with(&adj, 1), 6);
    ck_assert_uint_eq(adj.vertex_flags[0], RESURFI_VERTEX_NONMANIFOLD | RESURFI_VERTEX_BOUNDARY);
    ck_assert_uint_eq(adj.vertex_flags[1], RESURFI_VERTEX_NONMANIFOLD | RESURFI_VERTEX_BOUNDARY);
    for (int v = 2; v < 5; ++v)
        ck_assert_uint_eq(adj.vertex_flags[v], RESURFI_VERTEX_BOUNDARY);
    ck_assert_uint_eq(resurfi_adjacency_boundary_loops(&adj), 3);
    ck_assert_uint_eq(resurfi_adjacency_components(&adj, m->indices, NULL), 1);
    resurfi_adjacency_free(&adj);
    resurf_mesh_free(m);
}
END_TEST

/* A bow-tie: two triangles touching at vertex 2 only.
 *
 *   0           3
 *   | \       / |
 *   |   \   /   |         (0,1,2) and (2,3,4): vertex 2 has two fans, so it is non-manifold;
 *   |     2     |         no edge is. One component (they share a vertex), two boundary loops.
 *   |   /   \   |
 *   | /       \ |
 *   1           4
 */
START_TEST(adjacency_bowtie_vertex)
{
    const double p[] = {-1, 1, 0, -1, -1, 0, 0, 0, 0, 1, 1, 0, 1, -1, 0};
    const uint32_t t[] = {0, 1, 2, 2, 3, 4};
    resurf_mesh *m = tu_mesh(p, 5, t, 2);
    resurfi_adjacency adj = build(m);
    ck_assert_uint_eq(adj.edge_count, 6);
    ck_assert_uint_eq(count_edges_with(&adj, 1), 6);
    ck_assert_uint_eq(adj.vertex_flags[2], RESURFI_VERTEX_NONMANIFOLD | RESURFI_VERTEX_BOUNDARY);
    ck_assert_uint_eq(count_flag(&adj, RESURFI_VERTEX_NONMANIFOLD), 1);
    ck_assert_uint_eq(resurfi_adjacency_boundary_loops(&adj), 2);
    ck_assert_uint_eq(resurfi_adjacency_components(&adj, m->indices, NULL), 1);
    resurfi_adjacency_free(&adj);
    resurf_mesh_free(m);
}
END_TEST

/* Two closed tetrahedra sharing apex 0 (the second one is the first mirrored through 0): no boundary at all,
 * yet 0 is non-manifold (two closed fans). */
START_TEST(adjacency_closed_bowtie)
{
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, -1, 0, 0, 0, -1, 0, 0, 0, -1};
    const uint32_t t[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3, /* tetrahedron 0 1 2 3 */
                          0, 4, 5, 0, 6, 4, 0, 5, 6, 4, 6, 5 /* tetrahedron 0 4 5 6 */};
    resurf_mesh *m = tu_mesh(p, 7, t, 8);
    resurfi_adjacency adj = build(m);
    ck_assert_uint_eq(adj.edge_count, 12);
    ck_assert_uint_eq(count_edges_with(&adj, 2), 12);
    ck_assert_uint_eq(adj.vertex_flags[0], RESURFI_VERTEX_NONMANIFOLD);
    ck_assert_uint_eq(count_flag(&adj, 0xff), 1);
    ck_assert_uint_eq(resurfi_adjacency_boundary_loops(&adj), 0);
    ck_assert_uint_eq(resurfi_adjacency_components(&adj, m->indices, NULL), 1);
    resurfi_adjacency_free(&adj);
    resurf_mesh_free(m);
}
END_TEST

/* Two holes in a 4×4 grid that touch at grid point (2,2): squares (1,1) and (2,2) removed.
 *
 *   +---+---+---+---+
 *   |   |   |   |   |
 *   +---+---+---+---+
 *   |   |   |###|   |        ### = removed square. Vertex (2,2) keeps one triangle of square (2,1) and one of
 *   +---+---*---+---+        square (1,2): two fans, non-manifold. Splitting it into its fans joins the two
 *   |   |###|   |   |        holes into one, so 2 loops in all (outer + holes), as Euler's formula says for a
 *   +---+---+---+---+        genus-0 surface: (V + 1) − E + F = 2 − loops with V 25, E 54, F 28.
 *   |   |   |   |   |
 *   +---+---+---+---+
 */
START_TEST(adjacency_holes_meeting_at_a_vertex)
{
    resurf_mesh *m = tu_grid(4);
    size_t out = 0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
        size_t square = t / 2, i = square % 4, j = square / 4;
        if ((i == 1 && j == 1) || (i == 2 && j == 2))
            continue;
        memmove(m->indices + 3 * out++, m->indices + 3 * t, 3 * sizeof(uint32_t));
    }
    m->triangle_count = out;
    ck_assert_uint_eq(out, 28);
    resurfi_adjacency adj = build(m);
    ck_assert_uint_eq(adj.edge_count, 54);
    ck_assert_uint_eq(count_edges_with(&adj, 1), 16 + 8);
    ck_assert_uint_eq(adj.vertex_flags[2 * 5 + 2], RESURFI_VERTEX_NONMANIFOLD | RESURFI_VERTEX_BOUNDARY);
    ck_assert_uint_eq(count_flag(&adj, RESURFI_VERTEX_NONMANIFOLD), 1);
    ck_assert_uint_eq(resurfi_adjacency_boundary_loops(&adj), 2);
    resurfi_adjacency_free(&adj);
    resurf_mesh_free(m);
}
END_TEST

/* Ignored triangles: T1 has index 9 of 6 vertices, T2 repeats index 3. Vertices 3 and 4 are used only by T2.
 *
 *   2 ---- 5
 *   | \    |        T0 = (0,1,2), T3 = (2,1,5) share edge (1,2)
 *   |  \   |
 *   0 ---- 1
 */
START_TEST(adjacency_ignores_invalid_triangles)
{
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 3, 3, 3, 4, 4, 4, 1, 1, 0};
    const uint32_t t[] = {0, 1, 2, 0, 1, 9, 3, 3, 4, 2, 1, 5};
    resurf_mesh *m = tu_mesh(p, 6, t, 4);
    resurfi_adjacency adj = build(m);
    ck_assert_uint_eq(adj.edge_count, 5);
    for (int i = 0; i < 3; ++i) {
        ck_assert_uint_eq(adj.face_edges[3 + i], UINT32_MAX);
        ck_assert_uint_eq(adj.face_edges[6 + i], UINT32_MAX);
        ck_assert_uint_ne(adj.face_edges[i], UINT32_MAX);
        ck_assert_uint_ne(adj.face_edges[9 + i], UINT32_MAX);
    }
    ck_assert_uint_eq(adj.vertex_face_offset[6], 6); /* only T0 and T3 are listed */
    ck_assert_uint_eq(adj.vertex_flags[3], RESURFI_VERTEX_UNREFERENCED);
    ck_assert_uint_eq(adj.vertex_flags[4], RESURFI_VERTEX_UNREFERENCED);
    ck_assert_uint_eq(count_flag(&adj, RESURFI_VERTEX_UNREFERENCED), 2);
    ck_assert_uint_eq(resurfi_edge_face_count(&adj, resurfi_adjacency_find_edge(&adj, 1, 2)), 2);
    uint32_t comp[4];
    ck_assert_uint_eq(resurfi_adjacency_components(&adj, m->indices, comp), 1);
    ck_assert_uint_eq(comp[0], 0);
    ck_assert_uint_eq(comp[1], UINT32_MAX);
    ck_assert_uint_eq(comp[2], UINT32_MAX);
    ck_assert_uint_eq(comp[3], 0);
    ck_assert_uint_eq(resurfi_adjacency_boundary_loops(&adj), 1);
    resurfi_adjacency_free(&adj);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(adjacency_empty)
{
    resurfi_adjacency adj;
    ck_assert_int_eq(resurfi_adjacency_build(NULL, NULL, 0, 0, &adj), RESURF_OK);
    ck_assert_uint_eq(adj.edge_count, 0);
    ck_assert_uint_eq(resurfi_adjacency_components(&adj, NULL, NULL), 0);
    ck_assert_uint_eq(resurfi_adjacency_boundary_loops(&adj), 0);
    resurfi_adjacency_free(&adj);
    resurfi_adjacency_free(&adj); /* freeing twice is harmless: free leaves it empty */

    /* Vertices without triangles: all unreferenced. */
    ck_assert_int_eq(resurfi_adjacency_build(NULL, NULL, 0, 3, &adj), RESURF_OK);
    ck_assert_uint_eq(count_flag(&adj, RESURFI_VERTEX_UNREFERENCED), 3);
    resurfi_adjacency_free(&adj);
    ck_assert_int_eq(resurfi_adjacency_build(NULL, NULL, 1, 3, &adj), RESURF_ERR_INVALID_ARGUMENT);
}
END_TEST

/* ---- brute force ----------------------------------------------------------------------------------------------- */

static int tri_valid(const uint32_t *t, size_t nv)
{
    return t[0] < nv && t[1] < nv && t[2] < nv && t[0] != t[1] && t[1] != t[2] && t[0] != t[2];
}

static int tri_has(const uint32_t *t, uint32_t v) { return t[0] == v || t[1] == v || t[2] == v; }

/* Faces containing both a and b, counted directly. */
static size_t naive_edge_faces(const resurf_mesh *m, uint32_t a, uint32_t b, uint32_t *out)
{
    size_t n = 0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t *tri = m->indices + 3 * t;
        if (tri_valid(tri, m->vertex_count) && tri_has(tri, a) && tri_has(tri, b)) {
            if (out)
                out[n] = (uint32_t)t;
            ++n;
        }
    }
    return n;
}

/* Fans at v by relaxation: faces of v take the lowest label among faces across a two-face edge at v. */
static size_t naive_fans(const resurf_mesh *m, uint32_t v)
{
    size_t nt = m->triangle_count, fans = 0;
    uint32_t *label = malloc((nt ? nt : 1) * sizeof *label);
    for (size_t t = 0; t < nt; ++t)
        label[t] = (uint32_t)t;
    for (int changed = 1; changed;) {
        changed = 0;
        for (size_t f = 0; f < nt; ++f) {
            const uint32_t *a = m->indices + 3 * f;
            if (!tri_valid(a, m->vertex_count) || !tri_has(a, v))
                continue;
            for (size_t g = 0; g < nt; ++g) {
                const uint32_t *b = m->indices + 3 * g;
                if (g == f || !tri_valid(b, m->vertex_count) || !tri_has(b, v))
                    continue;
                for (int i = 0; i < 3; ++i) {
                    uint32_t w = a[i];
                    if (w != v && tri_has(b, w) && naive_edge_faces(m, v, w, NULL) == 2 && label[g] < label[f]) {
                        label[f] = label[g];
                        changed = 1;
                    }
                }
            }
        }
    }
    for (size_t f = 0; f < nt; ++f)
        fans += tri_valid(m->indices + 3 * f, m->vertex_count) && tri_has(m->indices + 3 * f, v) && label[f] == f;
    free(label);
    return fans;
}

/* Components of triangles across shared vertices (share_edge = 0) or shared edges (1), by relaxation. */
static size_t naive_components(const resurf_mesh *m, int share_edge)
{
    size_t nt = m->triangle_count, count = 0;
    uint32_t *label = malloc((nt ? nt : 1) * sizeof *label);
    for (size_t t = 0; t < nt; ++t)
        label[t] = (uint32_t)t;
    for (int changed = 1; changed;) {
        changed = 0;
        for (size_t f = 0; f < nt; ++f)
            for (size_t g = 0; g < nt; ++g) {
                const uint32_t *a = m->indices + 3 * f, *b = m->indices + 3 * g;
                if (!tri_valid(a, m->vertex_count) || !tri_valid(b, m->vertex_count))
                    continue;
                int shared = tri_has(b, a[0]) + tri_has(b, a[1]) + tri_has(b, a[2]);
                if (shared >= (share_edge ? 2 : 1) && label[g] < label[f]) {
                    label[f] = label[g];
                    changed = 1;
                }
            }
    }
    for (size_t t = 0; t < nt; ++t)
        count += tri_valid(m->indices + 3 * t, m->vertex_count) && label[t] == t;
    free(label);
    return count;
}

/* Every array of the adjacency recounted the slow way. */
static void check_against_brute_force(const resurf_mesh *m)
{
    resurfi_adjacency adj = build(m);
    const size_t nv = m->vertex_count, nt = m->triangle_count;
    /* Edges: exactly the sorted pairs with at least one face. */
    size_t e = 0;
    uint32_t *faces = malloc((nt ? nt : 1) * sizeof *faces);
    for (uint32_t a = 0; a < nv; ++a)
        for (uint32_t b = a + 1; b < nv; ++b) {
            size_t n = naive_edge_faces(m, a, b, faces);
            if (n == 0) {
                ck_assert_uint_eq(resurfi_adjacency_find_edge(&adj, a, b), UINT32_MAX);
                continue;
            }
            ck_assert_uint_lt(e, adj.edge_count);
            ck_assert_uint_eq(adj.edge_vertices[2 * e], a);
            ck_assert_uint_eq(adj.edge_vertices[2 * e + 1], b);
            ck_assert_uint_eq(resurfi_edge_face_count(&adj, (uint32_t)e), n);
            for (size_t k = 0; k < n; ++k)
                ck_assert_uint_eq(adj.edge_faces[adj.edge_face_offset[e] + k], faces[k]);
            ++e;
        }
    ck_assert_uint_eq(e, adj.edge_count);
    /* Face → edges. */
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *tri = m->indices + 3 * t;
        for (int i = 0; i < 3; ++i) {
            uint32_t id = adj.face_edges[3 * t + i];
            if (!tri_valid(tri, nv)) {
                ck_assert_uint_eq(id, UINT32_MAX);
                continue;
            }
            uint32_t a = tri[i], b = tri[(i + 1) % 3];
            ck_assert_uint_eq(adj.edge_vertices[2 * id], a < b ? a : b);
            ck_assert_uint_eq(adj.edge_vertices[2 * id + 1], a < b ? b : a);
        }
    }
    /* Vertex → faces and flags. */
    for (uint32_t v = 0; v < nv; ++v) {
        size_t k = adj.vertex_face_offset[v];
        int boundary = 0, nonmanifold_edge = 0;
        for (size_t t = 0; t < nt; ++t)
            if (tri_valid(m->indices + 3 * t, nv) && tri_has(m->indices + 3 * t, v))
                ck_assert_uint_eq(adj.vertex_faces[k++], t);
        ck_assert_uint_eq(k, adj.vertex_face_offset[v + 1]);
        for (uint32_t w = 0; w < nv; ++w) {
            size_t n = w == v ? 0 : naive_edge_faces(m, v, w, NULL);
            boundary |= n == 1;
            nonmanifold_edge |= n > 2;
        }
        size_t fans = naive_fans(m, v);
        uint8_t expected = (boundary ? RESURFI_VERTEX_BOUNDARY : 0) |
                           (nonmanifold_edge || fans > 1 ? RESURFI_VERTEX_NONMANIFOLD : 0) |
                           (k == adj.vertex_face_offset[v] ? RESURFI_VERTEX_UNREFERENCED : 0);
        ck_assert_uint_eq(adj.vertex_flags[v], expected);
    }
    ck_assert_uint_eq(resurfi_adjacency_components(&adj, m->indices, NULL), naive_components(m, 0));
    /* The edge-only build: the same tables (checked above), no flags, no loop count. */
    resurfi_adjacency lite;
    ck_assert_int_eq(resurfi_adjacency_build_edges(NULL, m->indices, nt, nv, &lite), RESURF_OK);
    ck_assert_uint_eq(lite.edge_count, adj.edge_count);
    ck_assert_ptr_null(lite.vertex_flags);
    ck_assert_uint_eq(lite.boundary_loop_count, 0);
    ck_assert_mem_eq(lite.vertex_face_offset, adj.vertex_face_offset, (nv + 1) * sizeof(uint32_t));
    ck_assert_mem_eq(lite.vertex_faces, adj.vertex_faces, adj.vertex_face_offset[nv] * sizeof(uint32_t));
    ck_assert_mem_eq(lite.vertex_edge_offset, adj.vertex_edge_offset, (nv + 1) * sizeof(uint32_t));
    ck_assert_mem_eq(lite.edge_vertices, adj.edge_vertices, 2 * adj.edge_count * sizeof(uint32_t));
    ck_assert_mem_eq(lite.edge_face_offset, adj.edge_face_offset, (adj.edge_count + 1) * sizeof(uint32_t));
    ck_assert_mem_eq(lite.edge_faces, adj.edge_faces, adj.edge_face_offset[adj.edge_count] * sizeof(uint32_t));
    ck_assert_mem_eq(lite.face_edges, adj.face_edges, 3 * nt * sizeof(uint32_t));
    resurfi_adjacency_free(&lite);
    free(faces);
    resurfi_adjacency_free(&adj);
}

/* Random soups over few vertices: many non-manifold edges and vertices, invalid and repeated indices. */
START_TEST(adjacency_random_soup_matches_brute_force)
{
    uint64_t state = 2024;
    for (int trial = 0; trial < 6; ++trial) {
        size_t nv = 8 + trial * 6, nt = 10 + trial * 8;
        resurf_mesh *m = NULL;
        ck_assert_int_eq(resurf_mesh_create(nv, nt, 0, &m, NULL), RESURF_OK);
        for (size_t i = 0; i < 3 * nt; ++i)
            m->indices[i] = (uint32_t)(shape_rand_u64(&state) % (nv + 1)); /* value nv is out of range */
        check_against_brute_force(m);
        resurf_mesh_free(m);
    }
}
END_TEST

/* Grids with random triangles removed: pinched vertices and holes of every shape. The surface is planar (genus 0)
 * and every edge has at most two faces, so after splitting each vertex into its fans Euler's formula gives the
 * loops: Σ_components (2 − loops) = fans − E + F, with components connected across edges. */
START_TEST(adjacency_damaged_grid_matches_euler)
{
    uint64_t state = 99;
    for (int trial = 0; trial < 8; ++trial) {
        resurf_mesh *m = tu_grid(6);
        size_t out = 0;
        for (size_t t = 0; t < m->triangle_count; ++t) {
            if (shape_rand_unit(&state) < 0.35)
                continue;
            memmove(m->indices + 3 * out++, m->indices + 3 * t, 3 * sizeof(uint32_t));
        }
        m->triangle_count = out;
        check_against_brute_force(m);
        resurfi_adjacency adj = build(m);
        long fans = 0;
        for (uint32_t v = 0; v < m->vertex_count; ++v)
            fans += (long)naive_fans(m, v);
        long chi = fans - (long)adj.edge_count + (long)out;
        long loops = 2 * (long)naive_components(m, 1) - chi;
        ck_assert_int_eq((long)resurfi_adjacency_boundary_loops(&adj), loops);
        resurfi_adjacency_free(&adj);
        resurf_mesh_free(m);
    }
}
END_TEST

/* A jittered torus of ~20000 triangles: closed, every edge on two faces, V − E + F = 0 (genus 1), one piece. */
START_TEST(adjacency_torus_is_closed_genus_one)
{
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        resurf_mesh *m = shape_mesh(SHAPE_TORUS, 20000, 0.3, seed, 0);
        ck_assert_ptr_nonnull(m);
        resurfi_adjacency adj = build(m);
        ck_assert_uint_eq(count_edges_with(&adj, 2), adj.edge_count);
        ck_assert_uint_eq(count_flag(&adj, 0xff), 0);
        long chi = (long)m->vertex_count - (long)adj.edge_count + (long)m->triangle_count;
        ck_assert_int_eq(chi, 0);
        ck_assert_uint_eq(resurfi_adjacency_boundary_loops(&adj), 0);
        ck_assert_uint_eq(resurfi_adjacency_components(&adj, m->indices, NULL), 1);
        resurfi_adjacency_free(&adj);
        resurf_mesh_free(m);
    }
}
END_TEST

/* Cutting the torus along one parameter circle (dropping the triangles that touch it) keeps one piece, a
 * cylinder: two boundary loops. */
START_TEST(adjacency_cut_torus_has_two_loops)
{
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 20000, 0.0, 1, 0);
    ck_assert_ptr_nonnull(m);
    /* Vertices with y = 0 and x > 0 (angle 0 around the z axis) lie on one meridian circle. */
    size_t out = 0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
        int touches = 0;
        for (int i = 0; i < 3; ++i) {
            const double *p = m->positions + 3 * (size_t)m->indices[3 * t + i];
            touches |= fabs(p[1]) < 1e-12 && p[0] > 0;
        }
        if (!touches)
            memmove(m->indices + 3 * out++, m->indices + 3 * t, 3 * sizeof(uint32_t));
    }
    ck_assert_uint_lt(out, m->triangle_count);
    m->triangle_count = out;
    resurfi_adjacency adj = build(m);
    ck_assert_uint_eq(count_flag(&adj, RESURFI_VERTEX_NONMANIFOLD), 0);
    ck_assert_uint_eq(resurfi_adjacency_boundary_loops(&adj), 2);
    ck_assert_uint_eq(resurfi_adjacency_components(&adj, m->indices, NULL), 1);
    resurfi_adjacency_free(&adj);
    resurf_mesh_free(m);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("adjacency");
    TCase *tc = tcase_create("adjacency");
    tcase_add_test(tc, adjacency_tetrahedron);
    tcase_add_test(tc, adjacency_cube);
    tcase_add_test(tc, adjacency_find_edge);
    tcase_add_test(tc, adjacency_open_grid);
    tcase_add_test(tc, adjacency_two_disjoint_triangles);
    tcase_add_test(tc, adjacency_nonmanifold_edge);
    tcase_add_test(tc, adjacency_bowtie_vertex);
    tcase_add_test(tc, adjacency_closed_bowtie);
    tcase_add_test(tc, adjacency_holes_meeting_at_a_vertex);
    tcase_add_test(tc, adjacency_ignores_invalid_triangles);
    tcase_add_test(tc, adjacency_empty);
    tcase_add_test(tc, adjacency_random_soup_matches_brute_force);
    tcase_add_test(tc, adjacency_damaged_grid_matches_euler);
    tcase_add_test(tc, adjacency_torus_is_closed_genus_one);
    tcase_add_test(tc, adjacency_cut_torus_has_two_loops);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
