/* src/repair.c: each repair flag on hand-made meshes, order and attribute arrays kept consistent, and a damaged
 * torus repaired back to exactly the original. */
#include <string.h>

#include "testutil.h"

static resurf_repair_report repair(resurf_mesh *m, const resurf_repair_options *o)
{
    resurf_repair_report r;
    memset(&r, 0xab, sizeof r);
    resurf_error error;
    ck_assert_int_eq(resurf_mesh_repair(m, o, &r, &error), RESURF_OK);
    ck_assert_int_eq(error.status, RESURF_OK);
    return r;
}

static void assert_triangles(const resurf_mesh *m, const uint32_t *expected, size_t count)
{
    ck_assert_uint_eq(m->triangle_count, count);
    for (size_t i = 0; i < 3 * count; ++i)
        ck_assert_uint_eq(m->indices[i], expected[i]);
}

static void assert_report(const resurf_repair_report *r, size_t invalid, size_t degenerate, size_t zero_area,
                          size_t welded, size_t unreferenced)
{
    ck_assert_uint_eq(r->dropped_invalid, invalid);
    ck_assert_uint_eq(r->dropped_degenerate, degenerate);
    ck_assert_uint_eq(r->dropped_zero_area, zero_area);
    ck_assert_uint_eq(r->welded_vertices, welded);
    ck_assert_uint_eq(r->removed_unreferenced, unreferenced);
}

/* A mesh whose every attribute records the vertex's original number v (and the triangle's number t):
 * normal (v, v + 0.5, v + 0.25), uv0 (v, −v), uv1 (2v, 3v), color (v, v, v, 1), extra "id" (v, 10v), group 7t. */
static resurf_mesh *tagged_mesh(const double *p, size_t nv, const uint32_t *t, size_t nt)
{
    resurf_mesh *m = NULL;
    unsigned attrs = RESURF_ATTR_NORMALS | RESURF_ATTR_COLORS | RESURF_ATTR_TEXCOORD0 | (RESURF_ATTR_TEXCOORD0 << 1);
    ck_assert_int_eq(resurf_mesh_create(nv, nt, attrs, &m, NULL), RESURF_OK);
    memcpy(m->positions, p, nv * 3 * sizeof *p);
    memcpy(m->indices, t, nt * 3 * sizeof *t);
    resurf_attribute *extra = NULL;
    ck_assert_int_eq(resurf_mesh_add_extra(m, "id", 2, &extra, NULL), RESURF_OK);
    for (size_t v = 0; v < nv; ++v) {
        double d = (double)v;
        double n[3] = {d, d + 0.5, d + 0.25}, c[4] = {d, d, d, 1};
        memcpy(m->normals + 3 * v, n, sizeof n);
        memcpy(m->colors + 4 * v, c, sizeof c);
        m->texcoords[0][2 * v] = d, m->texcoords[0][2 * v + 1] = -d;
        m->texcoords[1][2 * v] = 2 * d, m->texcoords[1][2 * v + 1] = 3 * d;
        extra->data[2 * v] = (float)d, extra->data[2 * v + 1] = (float)(10 * d);
    }
    m->triangle_groups = malloc((nt ? nt : 1) * sizeof *m->triangle_groups);
    for (size_t i = 0; i < nt; ++i)
        m->triangle_groups[i] = (uint32_t)(7 * i);
    return m;
}

/* Vertex k of the repaired mesh carries original vertex from[k] in every array. */
static void assert_vertices_from(const resurf_mesh *m, const resurf_mesh *original, const size_t *from, size_t count)
{
    ck_assert_uint_eq(m->vertex_count, count);
    for (size_t k = 0; k < count; ++k) {
        size_t v = from[k];
        double d = (double)v;
        ck_assert(memcmp(m->positions + 3 * k, original->positions + 3 * v, 3 * sizeof(double)) == 0);
        ck_assert_double_eq(m->normals[3 * k + 1], d + 0.5);
        ck_assert_double_eq(m->normals[3 * k + 2], d + 0.25);
        ck_assert_double_eq(m->texcoords[0][2 * k + 1], -d);
        ck_assert_double_eq(m->texcoords[1][2 * k + 1], 3 * d);
        ck_assert_double_eq(m->colors[4 * k + 2], d);
        ck_assert_float_eq(m->extras[0].data[2 * k + 1], (float)(10 * d));
    }
}

START_TEST(repair_options_default_values)
{
    resurf_repair_options o = resurf_repair_options_default();
    ck_assert_uint_eq(o.struct_size, sizeof o);
    ck_assert_uint_eq(o.flags, RESURF_REPAIR_ALL);
    ck_assert_double_eq(o.weld_tolerance_rel, 0);
    ck_assert_int_eq(o.weld_ignore_attributes, 0);
}
END_TEST

START_TEST(repair_rejects_bad_options)
{
    resurf_mesh *m = tu_tetrahedron();
    m->indices[0] = 9;
    resurf_repair_options zeroed;
    memset(&zeroed, 0, sizeof zeroed);
    zeroed.flags = RESURF_REPAIR_ALL;
    resurf_error error;
    ck_assert_int_eq(resurf_mesh_repair(m, &zeroed, NULL, &error), RESURF_ERR_INVALID_OPTIONS);
    ck_assert_int_eq(error.status, RESURF_ERR_INVALID_OPTIONS);
    resurf_repair_options o = resurf_repair_options_default();
    o.flags = 1u << 7;
    ck_assert_int_eq(resurf_mesh_repair(m, &o, NULL, NULL), RESURF_ERR_INVALID_OPTIONS);
    o = resurf_repair_options_default();
    o.weld_tolerance_rel = -1e-3;
    ck_assert_int_eq(resurf_mesh_repair(m, &o, NULL, &error), RESURF_ERR_INVALID_OPTIONS);
    ck_assert(strstr(error.message, "weld_tolerance_rel") != NULL);
    o.weld_tolerance_rel = NAN;
    ck_assert_int_eq(resurf_mesh_repair(m, &o, NULL, NULL), RESURF_ERR_INVALID_OPTIONS);
    ck_assert_int_eq(resurf_mesh_repair(NULL, NULL, NULL, &error), RESURF_ERR_INVALID_ARGUMENT);
    /* Nothing changed. */
    ck_assert_uint_eq(m->triangle_count, 4);
    ck_assert_uint_eq(m->indices[0], 9);
    resurf_mesh_free(m);
}
END_TEST

/* The tetrahedron's four faces interleaved with T1 = (0,1,9) (out of range) and T3 = (0,1,4) (vertex 4 is NaN);
 * vertex 5 is unused. Repair keeps the four faces in order and drops vertices 4 and 5. */
START_TEST(repair_drops_invalid)
{
    const double p[] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1, NAN, 0, 0, 5, 5, 5};
    const uint32_t t[] = {0, 1, 2, 0, 1, 9, 0, 2, 3, 0, 1, 4, 0, 3, 1, 1, 3, 2};
    resurf_mesh *m = tagged_mesh(p, 6, t, 6);
    resurf_mesh *original = NULL;
    ck_assert_int_eq(resurf_mesh_clone(m, &original, NULL), RESURF_OK);
    resurf_repair_report r = repair(m, NULL);
    assert_report(&r, 2, 0, 0, 0, 2);
    const uint32_t expected[] = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
    assert_triangles(m, expected, 4);
    const uint32_t groups[] = {0, 14, 28, 35};
    for (int i = 0; i < 4; ++i)
        ck_assert_uint_eq(m->triangle_groups[i], groups[i]);
    const size_t from[] = {0, 1, 2, 3};
    assert_vertices_from(m, original, from, 4);
    resurf_validate_report v;
    ck_assert_int_eq(resurf_mesh_validate(m, &v, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_validation_ok(&v), 1);
    ck_assert_uint_eq(v.boundary_edges, 0);
    resurf_mesh_free(original);
    resurf_mesh_free(m);
}
END_TEST

/* T0 = (0,1,2) kept; T1 = (0,0,1) repeats an index; T2 = (4,1,0) repeats a position (4 sits on 0); T3 = (1,3,2)
 * kept. Vertex 4 is then unused.
 *
 *   2 ----- 3
 *   | \     |
 *   |   \   |
 *   0=4 --- 1
 */
START_TEST(repair_drops_degenerate)
{
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 0, 0};
    const uint32_t t[] = {0, 1, 2, 0, 0, 1, 4, 1, 0, 1, 3, 2};
    resurf_mesh *m = tu_mesh(p, 5, t, 4);
    resurf_repair_options o = resurf_repair_options_default();
    o.flags &= ~(unsigned)RESURF_REPAIR_WELD; /* so that vertex 4 is not merged away first */
    resurf_repair_report r = repair(m, &o);
    assert_report(&r, 0, 2, 0, 0, 1);
    const uint32_t expected[] = {0, 1, 2, 1, 3, 2};
    assert_triangles(m, expected, 2);
    ck_assert_uint_eq(m->vertex_count, 4);
    resurf_mesh_free(m);
}
END_TEST

/* The zero-area example of test_validate.c: T1 (collinear) and T2 (sliver of height 1e-14) go, T0 and T3 stay;
 * vertices 3 and 4 are then unused, so vertex 5 becomes 3.
 *
 *   2
 *   |  \            5 = (0.5, 1e-13) just above the base, 4 = (0.5, 1e-14)
 *   |     \
 *   0---4---1---3
 */
START_TEST(repair_drops_zero_area)
{
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 0.5, 1e-14, 0, 0.5, 1e-13, 0};
    const uint32_t t[] = {0, 1, 2, 0, 1, 3, 0, 1, 4, 0, 1, 5};
    resurf_mesh *m = tagged_mesh(p, 6, t, 4);
    resurf_mesh *original = NULL;
    ck_assert_int_eq(resurf_mesh_clone(m, &original, NULL), RESURF_OK);
    resurf_repair_report r = repair(m, NULL);
    assert_report(&r, 0, 0, 2, 0, 2);
    const uint32_t expected[] = {0, 1, 2, 0, 1, 3};
    assert_triangles(m, expected, 2);
    ck_assert_uint_eq(m->triangle_groups[0], 0);
    ck_assert_uint_eq(m->triangle_groups[1], 21);
    const size_t from[] = {0, 1, 2, 5};
    assert_vertices_from(m, original, from, 4);
    resurf_mesh_free(original);
    resurf_mesh_free(m);
}
END_TEST

/* One flag at a time does only its own job; flags 0 changes nothing. */
START_TEST(repair_flags_are_independent)
{
    /* T0 fine, T1 out of range, T2 degenerate, T3 collinear; vertex 5 unused. */
    const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 0.5, 0.5, 0, 9, 9, 0};
    const uint32_t t[] = {0, 1, 2, 0, 1, 7, 2, 2, 0, 0, 1, 3};
    resurf_repair_options o = resurf_repair_options_default();

    resurf_mesh *m = tu_mesh(p, 6, t, 4);
    o.flags = 0;
    resurf_repair_report r = repair(m, &o);
    assert_report(&r, 0, 0, 0, 0, 0);
    assert_triangles(m, t, 4);
    ck_assert_uint_eq(m->vertex_count, 6);
    resurf_mesh_free(m);

    m = tu_mesh(p, 6, t, 4);
    o.flags = RESURF_REPAIR_DROP_DEGENERATE;
    r = repair(m, &o);
    assert_report(&r, 0, 1, 0, 0, 0);
    const uint32_t keep_invalid[] = {0, 1, 2, 0, 1, 7, 0, 1, 3};
    assert_triangles(m, keep_invalid, 3);
    resurf_mesh_free(m);

    m = tu_mesh(p, 6, t, 4);
    o.flags = RESURF_REPAIR_DROP_ZERO_AREA; /* the degenerate T2 is not "zero area" */
    r = repair(m, &o);
    assert_report(&r, 0, 0, 1, 0, 0);
    const uint32_t keep_degenerate[] = {0, 1, 2, 0, 1, 7, 2, 2, 0};
    assert_triangles(m, keep_degenerate, 3);
    resurf_mesh_free(m);

    /* Removing the unused vertices 4 and 5 renumbers nothing below them; the kept out-of-range index 7 moves
     * down by the two removed vertices to 5, still out of range of the 4 left. */
    m = tu_mesh(p, 6, t, 4);
    o.flags = RESURF_REPAIR_REMOVE_UNREFERENCED;
    r = repair(m, &o);
    assert_report(&r, 0, 0, 0, 0, 2);
    ck_assert_uint_eq(m->vertex_count, 4);
    const uint32_t renumbered[] = {0, 1, 2, 0, 1, 5, 2, 2, 0, 0, 1, 3};
    assert_triangles(m, renumbered, 4);
    resurf_mesh_free(m);

    m = tu_mesh(p, 6, t, 4);
    o.flags = RESURF_REPAIR_DROP_INVALID;
    r = repair(m, &o);
    assert_report(&r, 1, 0, 0, 0, 0);
    ck_assert_uint_eq(m->triangle_count, 3);
    resurf_mesh_free(m);
}
END_TEST

/* A triangle soup of m: corner c gets its own vertex, moved by jitter × c along (1,1,1) (corner 0 stays put). */
static resurf_mesh *soup(const resurf_mesh *m, double jitter)
{
    resurf_mesh *s = NULL;
    ck_assert_int_eq(resurf_mesh_create(3 * m->triangle_count, m->triangle_count, 0, &s, NULL), RESURF_OK);
    for (size_t c = 0; c < 3 * m->triangle_count; ++c) {
        for (int a = 0; a < 3; ++a)
            s->positions[3 * c + a] = m->positions[3 * (size_t)m->indices[c] + a] + jitter * (double)c;
        s->indices[c] = (uint32_t)c;
    }
    return s;
}

/* The tetrahedron as an exact triangle soup welds back to it: 12 vertices → 4, numbered by first appearance,
 * so exactly the original indices. */
START_TEST(repair_weld_triangle_soup)
{
    resurf_mesh *tet = tu_tetrahedron();
    resurf_mesh *m = soup(tet, 0);
    resurf_validate_report v;
    ck_assert_int_eq(resurf_mesh_validate(m, &v, NULL), RESURF_OK);
    ck_assert_uint_eq(v.position_count, 4); /* already closed over welded positions */
    ck_assert_uint_eq(v.boundary_edges, 0);
    resurf_repair_report r = repair(m, NULL);
    assert_report(&r, 0, 0, 0, 8, 0);
    assert_triangles(m, tet->indices, 4);
    ck_assert(memcmp(m->positions, tet->positions, 12 * sizeof(double)) == 0);
    resurf_mesh_free(m);
    resurf_mesh_free(tet);
}
END_TEST

/* Copies up to 11e-9 apart (the diagonal is 2√3): a tolerance of 1e-6 welds them and snaps them onto the first
 * copy exactly; the exact weld leaves 12 vertices, i.e. four separate triangles. */
START_TEST(repair_weld_tolerance)
{
    resurf_mesh *tet = tu_tetrahedron();
    resurf_mesh *m = soup(tet, 1e-9);
    resurf_repair_report r = repair(m, NULL);
    assert_report(&r, 0, 0, 0, 0, 0);
    resurf_validate_report v;
    ck_assert_int_eq(resurf_mesh_validate(m, &v, NULL), RESURF_OK);
    ck_assert_uint_eq(v.components, 4);
    ck_assert_uint_eq(v.boundary_edges, 12);
    resurf_mesh_free(m);

    m = soup(tet, 1e-9);
    resurf_repair_options o = resurf_repair_options_default();
    o.weld_tolerance_rel = 1e-6;
    r = repair(m, &o);
    assert_report(&r, 0, 0, 0, 8, 0);
    /* The tetrahedron's vertex k is first met as corner 0, 1, 2, 5 of the soup (faces 012 and 023): each cluster
     * sits where that first copy was. */
    ck_assert_uint_eq(m->vertex_count, 4);
    assert_triangles(m, tet->indices, 4);
    const double first_corner[4] = {0, 1, 2, 5};
    for (size_t k = 0; k < 4; ++k)
        for (int a = 0; a < 3; ++a)
            ck_assert_double_eq(m->positions[3 * k + a], tet->positions[3 * k + a] + 1e-9 * first_corner[k]);
    ck_assert_int_eq(resurf_mesh_validate(m, &v, NULL), RESURF_OK);
    ck_assert_uint_eq(v.boundary_edges, 0);
    ck_assert_uint_eq(v.components, 1);
    resurf_mesh_free(m);
    resurf_mesh_free(tet);
}
END_TEST

/* The seam quad of test_weld.c plus vertex 6, an exact copy of vertex 0 with the same uv, used by a third face.
 *
 *   3 ------ 2=5          T0 (0,1,2), T1 (0,5,3), T2 (6,1,5)
 *   |      / |            4 = 1 and 5 = 2 in position, other uvs: a seam; 6 = 0 in position and uv.
 *   |    /   |
 *   |  /     |
 *   0=6 ---- 1=4
 */
static resurf_mesh *seam_quad(void)
{
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(7, 3, RESURF_ATTR_TEXCOORD0, &m, NULL), RESURF_OK);
    const double p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0};
    const double uv[] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0, 0.5, 1, 0, 0};
    const uint32_t t[] = {0, 1, 2, 0, 5, 3, 6, 1, 5};
    memcpy(m->positions, p, sizeof p);
    memcpy(m->texcoords[0], uv, sizeof uv);
    memcpy(m->indices, t, sizeof t);
    return m;
}

START_TEST(repair_weld_keeps_seams)
{
    resurf_mesh *m = seam_quad();
    resurf_repair_report r = repair(m, NULL);
    /* 6 merges into 0; 4 and 5 differ in uv from 1 and 2 and stay. 4 is then unused (only listed, never used). */
    assert_report(&r, 0, 0, 0, 1, 1);
    ck_assert_uint_eq(m->vertex_count, 5);
    const uint32_t expected[] = {0, 1, 2, 0, 4, 3, 0, 1, 4}; /* old 5 is new 4 */
    assert_triangles(m, expected, 3);
    ck_assert_double_eq(m->texcoords[0][2 * 4], 0.5);
    resurf_mesh_free(m);

    m = seam_quad();
    resurf_repair_options o = resurf_repair_options_default();
    o.weld_ignore_attributes = true;
    r = repair(m, &o);
    assert_report(&r, 0, 0, 0, 3, 0);
    ck_assert_uint_eq(m->vertex_count, 4);
    const uint32_t merged[] = {0, 1, 2, 0, 2, 3, 0, 1, 2};
    assert_triangles(m, merged, 3);
    const double uv[] = {0, 0, 1, 0, 1, 1, 0, 1}; /* the first vertex's attributes win */
    for (int i = 0; i < 8; ++i)
        ck_assert_double_eq(m->texcoords[0][i], uv[i]);
    resurf_mesh_free(m);
}
END_TEST

/* With a tolerance, seam vertices are snapped onto their cluster's first position but kept apart. */
START_TEST(repair_weld_tolerance_snaps_seams)
{
    resurf_mesh *m = seam_quad();
    m->positions[3 * 5 + 0] += 1e-9; /* 5 is now near 2, not on it */
    resurf_repair_options o = resurf_repair_options_default();
    o.weld_tolerance_rel = 1e-6;
    o.flags &= ~(unsigned)RESURF_REPAIR_REMOVE_UNREFERENCED;
    resurf_repair_report r = repair(m, &o);
    assert_report(&r, 0, 0, 0, 1, 0);
    ck_assert_uint_eq(m->vertex_count, 6); /* 6 merged into 0; the unused 4 stays */
    /* 5 keeps its number and uv, but its position is now exactly vertex 2's. */
    ck_assert(memcmp(m->positions + 3 * 5, m->positions + 3 * 2, 3 * sizeof(double)) == 0);
    ck_assert_double_eq(m->texcoords[0][2 * 5 + 1], 1);
    ck_assert_double_eq(m->texcoords[0][2 * 5], 0.5);
    resurf_mesh_free(m);
}
END_TEST

/* Eight tagged vertices of which only 1, 3, 4, 6, 7 are used by kept triangles; T1 is dropped (out of range) and
 * takes the only use of vertex 0 with it. Every array follows: kept vertices 1 3 4 6 7 become 0..4 in order. */
START_TEST(repair_remove_unreferenced_compacts_arrays)
{
    double p[24];
    for (int v = 0; v < 8; ++v)
        p[3 * v] = v, p[3 * v + 1] = v * v, p[3 * v + 2] = (v % 3) * 0.5;
    const uint32_t t[] = {1, 3, 4, 0, 9, 1, 4, 6, 7, 3, 6, 4};
    resurf_mesh *m = tagged_mesh(p, 8, t, 4);
    resurf_mesh *original = NULL;
    ck_assert_int_eq(resurf_mesh_clone(m, &original, NULL), RESURF_OK);
    resurf_repair_report r = repair(m, NULL);
    assert_report(&r, 1, 0, 0, 0, 3);
    const uint32_t expected[] = {0, 1, 2, 2, 3, 4, 1, 3, 2};
    assert_triangles(m, expected, 3);
    const uint32_t groups[] = {0, 14, 21};
    for (int i = 0; i < 3; ++i)
        ck_assert_uint_eq(m->triangle_groups[i], groups[i]);
    const size_t from[] = {1, 3, 4, 6, 7};
    assert_vertices_from(m, original, from, 5);
    ck_assert_uint_eq(m->extra_count, 1);
    ck_assert_str_eq(m->extras[0].name, "id");
    resurf_mesh_free(original);
    resurf_mesh_free(m);
}
END_TEST

/* A torus damaged in every way repairs back to exactly the torus: duplicate vertices (exact copies, used by some
 * faces), a NaN vertex and its face, an out-of-range face, a degenerate face, a collinear face through a new
 * midpoint vertex, and stray unused vertices. Damage is appended, so the original comes first everywhere. */
START_TEST(repair_damaged_torus_back_to_original)
{
    resurf_mesh *torus = shape_mesh(SHAPE_TORUS, 5000, 0.3, 8, 0);
    ck_assert_ptr_nonnull(torus);
    const size_t nv = torus->vertex_count, nt = torus->triangle_count, copies = 50;
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(nv + copies + 3, nt + 4, 0, &m, NULL), RESURF_OK);
    memcpy(m->positions, torus->positions, nv * 3 * sizeof(double));
    memcpy(m->indices, torus->indices, nt * 3 * sizeof(uint32_t));
    for (size_t k = 0; k < copies; ++k) /* vertex nv + k copies vertex 7k */
        memcpy(m->positions + 3 * (nv + k), torus->positions + 3 * (7 * k), 3 * sizeof(double));
    for (size_t k = 0; k < copies; ++k) { /* the first use of vertex 7k now goes to its copy */
        size_t i = 0;
        while (m->indices[i] != 7 * k)
            ++i;
        m->indices[i] = (uint32_t)(nv + k);
    }
    const uint32_t nan_v = (uint32_t)(nv + copies), mid = nan_v + 1, stray = nan_v + 2;
    m->positions[3 * nan_v] = NAN;
    for (int a = 0; a < 3; ++a) {
        m->positions[3 * mid + a] = 0.5 * (torus->positions[3 * 10 + a] + torus->positions[3 * 200 + a]);
        m->positions[3 * stray + a] = 100.0 + a;
    }
    const uint32_t extra[] = {1, 2, nan_v, 3, 4, (uint32_t)(nv + copies + 3), 5, 5, 6, 10, mid, 200};
    memcpy(m->indices + 3 * nt, extra, sizeof extra);

    resurf_validate_report v;
    ck_assert_int_eq(resurf_mesh_validate(m, &v, NULL), RESURF_OK);
    ck_assert_uint_eq(v.nonfinite_positions, 1);
    ck_assert_uint_eq(v.out_of_range_indices, 1);
    ck_assert_uint_eq(v.degenerate_triangles, 1);
    ck_assert_uint_eq(v.zero_area_triangles, 1);
    ck_assert_uint_eq(v.unreferenced_vertices, 1);

    resurf_repair_report r = repair(m, NULL);
    assert_report(&r, 2, 1, 1, copies, 3);
    ck_assert_uint_eq(m->vertex_count, nv);
    ck_assert(memcmp(m->positions, torus->positions, nv * 3 * sizeof(double)) == 0);
    assert_triangles(m, torus->indices, nt);
    ck_assert_int_eq(resurf_mesh_validate(m, &v, NULL), RESURF_OK);
    ck_assert_uint_eq(v.boundary_edges, 0);
    ck_assert_uint_eq(v.components, 1);
    ck_assert_uint_eq(v.position_count, nv);
    resurf_mesh_free(m);
    resurf_mesh_free(torus);
}
END_TEST

START_TEST(repair_empty_mesh)
{
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(0, 0, RESURF_ATTR_NORMALS, &m, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_mesh_repair(m, NULL, NULL, NULL), RESURF_OK);
    ck_assert_uint_eq(m->vertex_count, 0);
    ck_assert_uint_eq(m->triangle_count, 0);
    resurf_mesh_free(m);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("repair");
    TCase *tc = tcase_create("repair");
    tcase_add_test(tc, repair_options_default_values);
    tcase_add_test(tc, repair_rejects_bad_options);
    tcase_add_test(tc, repair_drops_invalid);
    tcase_add_test(tc, repair_drops_degenerate);
    tcase_add_test(tc, repair_drops_zero_area);
    tcase_add_test(tc, repair_flags_are_independent);
    tcase_add_test(tc, repair_weld_triangle_soup);
    tcase_add_test(tc, repair_weld_tolerance);
    tcase_add_test(tc, repair_weld_keeps_seams);
    tcase_add_test(tc, repair_weld_tolerance_snaps_seams);
    tcase_add_test(tc, repair_remove_unreferenced_compacts_arrays);
    tcase_add_test(tc, repair_damaged_torus_back_to_original);
    tcase_add_test(tc, repair_empty_mesh);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
