/* Tests for src/simplify/, the edge-collapse simplifier with restoration, against independent truth:
 * hand-made meshes (a tetrahedron that cannot shrink, a cube, a planar grid whose border and area must stay, a
 * grid cut by a texture seam whose texcoords are a known linear function on each side), analytic shapes
 * (tools/shapes.h: every vertex of a restored sphere LOD on the unit sphere, targets reached on closed and open
 * surfaces with the topology kept), determinism over thread counts, LOD chains, error bounds, the guards, and
 * hostile inputs (non-manifold, degenerate, tiny, empty, invalid, cancelled). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

/* ---- helpers ------------------------------------------------------------------------------------------------- */

static resurf_mesh *simplify_ok(const resurf_mesh *in, const resurf_simplify_options *o, resurf_simplify_report *r)
{
    resurf_mesh *out = NULL;
    resurf_error e;
    resurf_status st = resurf_simplify(in, o, &out, r, &e);
    ck_assert_msg(st == RESURF_OK, "simplify failed: %s", e.message);
    ck_assert_ptr_nonnull(out);
    return out;
}

/* A valid, manifold, consistently oriented mesh without degenerate triangles. */
static void assert_clean(const resurf_mesh *m)
{
    resurf_validate_report v;
    ck_assert_int_eq(resurf_mesh_validate(m, &v, NULL), RESURF_OK);
    ck_assert(resurf_validation_ok(&v));
    ck_assert_uint_eq(v.nonmanifold_edges, 0);
    ck_assert_uint_eq(v.nonmanifold_vertices, 0);
    ck_assert_uint_eq(v.inconsistent_edges, 0);
    ck_assert_uint_eq(v.degenerate_triangles, 0);
    ck_assert_uint_eq(v.unreferenced_vertices, 0);
}

static resurf_validate_report validation(const resurf_mesh *m)
{
    resurf_validate_report v;
    ck_assert_int_eq(resurf_mesh_validate(m, &v, NULL), RESURF_OK);
    return v;
}

/* Six times the signed volume enclosed (positive for outward faces). */
static double volume6(const resurf_mesh *m)
{
    double v = 0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t *i = m->indices + 3 * t;
        v += v3_dot(resurfi_position(m, i[0]), v3_cross(resurfi_position(m, i[1]), resurfi_position(m, i[2])));
    }
    return v;
}

static double area(const resurf_mesh *m)
{
    double a = 0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t *i = m->indices + 3 * t;
        a += 0.5 * v3_len(v3_tri_cross(resurfi_position(m, i[0]), resurfi_position(m, i[1]),
                                       resurfi_position(m, i[2])));
    }
    return a;
}

static double max_shape_distance(shape_kind kind, const resurf_mesh *m)
{
    double mx = 0;
    for (size_t v = 0; v < m->vertex_count; ++v) {
        double d = shape_distance(kind, m->positions + 3 * v);
        mx = d > mx ? d : mx;
    }
    return mx;
}

/* Every face normal of m points to the same side as the analytic surface's normal at the face's centroid. */
static void assert_no_flips(shape_kind kind, const resurf_mesh *m)
{
    for (size_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t *i = m->indices + 3 * t;
        vec3 a = resurfi_position(m, i[0]), b = resurfi_position(m, i[1]), c = resurfi_position(m, i[2]);
        vec3 cen = v3_scale(v3_add(v3_add(a, b), c), 1.0 / 3);
        double p[3] = {cen.x, cen.y, cen.z}, n[3];
        shape_normal(kind, p, n);
        ck_assert_msg(v3_dot(v3_tri_cross(a, b, c), v3_load(n)) > 0, "triangle %zu is flipped", t);
    }
}

static int same_mesh_bytes(const resurf_mesh *a, const resurf_mesh *b)
{
    if (a->vertex_count != b->vertex_count || a->triangle_count != b->triangle_count)
        return 0;
    if (memcmp(a->positions, b->positions, 3 * a->vertex_count * sizeof(double)) ||
        memcmp(a->indices, b->indices, 3 * a->triangle_count * sizeof(uint32_t)))
        return 0;
    if ((a->normals == NULL) != (b->normals == NULL) ||
        (a->normals && memcmp(a->normals, b->normals, 3 * a->vertex_count * sizeof(double))))
        return 0;
    for (unsigned k = 0; k < RESURF_MAX_TEXCOORD_SETS; ++k)
        if ((a->texcoords[k] == NULL) != (b->texcoords[k] == NULL) ||
            (a->texcoords[k] && memcmp(a->texcoords[k], b->texcoords[k], 2 * a->vertex_count * sizeof(double))))
            return 0;
    return 1;
}

/* A grid over [0,1]² (n even) lifted by z = lift × ((x − ½)² + (y − ½)²), with a texture seam along x = ½: the
 * vertices there are split, texcoord u = x on the left side and x + 10 on the right, v = y; unit normals of the
 * surface. Seam vertices: the left copy first, then the right copy.
 *
 *     +---+---+===+---+---+        left chart: u = x          right chart: u = x + 10
 *     | / | / ‖ / | / | / |        ‖ = the seam (two vertices per position)
 *     +---+---+===+---+---+                                                                                       */
static resurf_mesh *seam_grid(unsigned n, double lift)
{
    unsigned half = n / 2, cols = n + 2; /* one extra column: the right copies of the seam */
    size_t nv = (size_t)(n + 1) * cols;
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(nv, 2 * (size_t)n * n, RESURF_ATTR_NORMALS | RESURF_ATTR_TEXCOORD0, &m, NULL),
                     RESURF_OK);
    for (unsigned j = 0; j <= n; ++j)
        for (unsigned c = 0; c < cols; ++c) {
            unsigned i = c <= half ? c : c - 1; /* column c = half + 1 is the right copy of column half */
            size_t v = (size_t)j * cols + c;
            double x = (double)i / n, y = (double)j / n;
            double z = lift * ((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5));
            v3_store(m->positions + 3 * v, v3(x, y, z));
            v3_store(m->normals + 3 * v, v3_normalize(v3(-2 * lift * (x - 0.5), -2 * lift * (y - 0.5), 1)));
            m->texcoords[0][2 * v] = c <= half ? x : x + 10;
            m->texcoords[0][2 * v + 1] = y;
        }
    uint32_t *t = m->indices;
    for (unsigned j = 0; j < n; ++j)
        for (unsigned i = 0; i < n; ++i) {
            /* columns of this square's corners: the right side of the seam uses the right copies */
            unsigned c0 = i < half ? i : i + 1, c1 = c0 + 1;
            uint32_t a = j * cols + c0, b = j * cols + c1, c = (j + 1) * cols + c1, d = (j + 1) * cols + c0;
            *t++ = a, *t++ = b, *t++ = c;
            *t++ = a, *t++ = c, *t++ = d;
        }
    return m;
}

/* ---- small hand-made meshes ---------------------------------------------------------------------------------- */

START_TEST(simplify_tetrahedron_stays)
{
    /* A tetrahedron cannot lose a vertex without becoming a double-sided sheet: the link condition refuses. */
    resurf_mesh *m = tu_tetrahedron();
    resurf_simplify_options o = resurf_simplify_options_default();
    o.feature_angle_deg = o.corner_angle_deg = 180; /* else its vertices are corners (test_features.c) */
    for (int mode = 0; mode < RESURF_RESTORE_MODE_COUNT; ++mode) {
        o.restore = (resurf_restore_mode)mode;
        resurf_simplify_report r;
        resurf_mesh *out = simplify_ok(m, &o, &r);
        ck_assert_uint_eq(out->triangle_count, 4);
        ck_assert_uint_eq(out->vertex_count, 4);
        ck_assert_int_eq(r.stop, RESURF_STOP_BLOCKED);
        ck_assert_uint_gt(r.blocked_link, 0);
        ck_assert_uint_eq(r.collapses, 0);
        assert_clean(out);
        ck_assert(volume6(out) > 0);
        resurf_mesh_free(out);
    }
    resurf_mesh_free(m);
}
END_TEST

START_TEST(simplify_cube_closed_and_oriented)
{
    resurf_mesh *m = tu_cube();
    resurf_simplify_options o = resurf_simplify_options_default();
    o.restore = RESURF_RESTORE_NONE;
    o.target_triangles = 6;
    o.max_normal_change_deg = 180; /* a cube's corners need big turns to go */
    o.feature_angle_deg = o.corner_angle_deg = 180; /* and must not be corners that never move */
    resurf_simplify_report r;
    resurf_mesh *out = simplify_ok(m, &o, &r);
    ck_assert_uint_le(out->triangle_count, 6);
    ck_assert_uint_ge(out->triangle_count, 4);
    ck_assert_uint_eq(r.triangles, out->triangle_count);
    ck_assert_uint_eq(r.vertices, out->vertex_count);
    ck_assert_uint_eq(r.collapses, (12 - out->triangle_count) / 2);
    assert_clean(out);
    resurf_validate_report v = validation(out);
    ck_assert_uint_eq(v.boundary_edges, 0);
    ck_assert_uint_eq(out->vertex_count, out->triangle_count / 2 + 2); /* Euler: a closed genus-0 surface */
    ck_assert(volume6(out) > 0);
    resurf_mesh_free(out);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(simplify_grid_keeps_border_and_area)
{
    /* A flat square: every collapse is free of error, the border must stay on the square's sides (boundary
     * quadrics, border vertices only along the border) and the area stays 1. */
    resurf_mesh *m = tu_grid(12);
    for (int placement = 0; placement < RESURF_PLACEMENT_COUNT; ++placement) {
        resurf_simplify_options o = resurf_simplify_options_default();
        o.target_ratio = 0.1;
        o.placement = (resurf_placement)placement;
        resurf_simplify_report r;
        resurf_mesh *out = simplify_ok(m, &o, &r);
        ck_assert_uint_le(out->triangle_count, 28);
        assert_clean(out);
        resurf_validate_report v = validation(out);
        ck_assert_uint_eq(v.boundary_loops, 1);
        ck_assert_uint_eq(v.components, 1);
        ck_assert_double_eq_tol(area(out), 1.0, 1e-9);
        for (size_t i = 0; i < out->vertex_count; ++i) {
            vec3 p = resurfi_position(out, (uint32_t)i);
            ck_assert_double_eq_tol(p.z, 0.0, 1e-12);
            ck_assert(p.x >= -1e-12 && p.x <= 1 + 1e-12 && p.y >= -1e-12 && p.y <= 1 + 1e-12);
        }
        /* the four corners are still vertices */
        for (int c = 0; c < 4; ++c) {
            vec3 corner = v3(c & 1, c >> 1, 0);
            int found = 0;
            for (size_t i = 0; i < out->vertex_count; ++i)
                found |= v3_dist(resurfi_position(out, (uint32_t)i), corner) < 1e-12;
            ck_assert_msg(found, "corner %d lost", c);
        }
        resurf_mesh_free(out);
    }
    resurf_mesh_free(m);
}
END_TEST

START_TEST(simplify_lock_border_freezes_border)
{
    resurf_mesh *m = tu_grid(10);
    resurf_simplify_options o = resurf_simplify_options_default();
    o.lock_border = true;
    resurf_simplify_report r;
    resurf_mesh *out = simplify_ok(m, &o, &r);
    resurf_validate_report v = validation(out);
    ck_assert_uint_eq(v.boundary_edges, 40); /* all 4 × 10 border edges, untouched */
    ck_assert_uint_gt(r.blocked_border, 0);
    ck_assert_uint_lt(out->triangle_count, m->triangle_count);
    assert_clean(out);
    /* every border vertex of the input is still there, at its place */
    for (size_t i = 0; i < m->vertex_count; ++i) {
        vec3 p = resurfi_position(m, (uint32_t)i);
        if (p.x != 0 && p.x != 1 && p.y != 0 && p.y != 1)
            continue;
        int found = 0;
        for (size_t k = 0; k < out->vertex_count && !found; ++k)
            found = v3_dist(resurfi_position(out, (uint32_t)k), p) == 0;
        ck_assert_msg(found, "border vertex %zu moved", i);
    }
    resurf_mesh_free(out);
    resurf_mesh_free(m);
}
END_TEST

/* Checks the seam: every texcoord comes from its own side (u = x left of the seam, x + 10 right of it, by the
 * side of its triangle, within tol), the seam vertices stay on x = ½ (within seam_tol) and are still split. */
static void check_seam_grid(const resurf_mesh *out, double tol, double seam_tol)
{
    ck_assert_ptr_nonnull(out->texcoords[0]);
    ck_assert_ptr_nonnull(out->normals);
    size_t on_seam = 0;
    for (size_t t = 0; t < out->triangle_count; ++t) {
        const uint32_t *i = out->indices + 3 * t;
        double cx = 0;
        for (int k = 0; k < 3; ++k)
            cx += out->positions[3 * (size_t)i[k]] / 3;
        int right = cx > 0.5;
        for (int k = 0; k < 3; ++k) {
            const double *p = out->positions + 3 * (size_t)i[k];
            const double *uv = out->texcoords[0] + 2 * (size_t)i[k];
            ck_assert_msg(fabs(uv[0] - (p[0] + (right ? 10 : 0))) <= tol && fabs(uv[1] - p[1]) <= tol,
                          "triangle %zu (%s) corner %d: uv (%g, %g) at (%g, %g)", t, right ? "right" : "left", k, uv[0],
                          uv[1], p[0], p[1]);
        }
    }
    /* seam positions: vertices with x = ½ come in pairs (left and right copies) */
    for (size_t v = 0; v < out->vertex_count; ++v) {
        const double *p = out->positions + 3 * v;
        if (fabs(p[0] - 0.5) > seam_tol)
            continue;
        ++on_seam;
        size_t copies = 0;
        for (size_t w = 0; w < out->vertex_count; ++w)
            copies += out->positions[3 * w] == p[0] && out->positions[3 * w + 1] == p[1] &&
                      out->positions[3 * w + 2] == p[2];
        ck_assert_uint_eq(copies, 2);
        ck_assert_double_eq_tol(v3_len(v3_load(out->normals + 3 * v)), 1.0, 1e-9);
    }
    ck_assert_uint_ge(on_seam, 4); /* at least both ends, twice */
    /* no vertex lies across the seam from its triangles */
    for (size_t t = 0; t < out->triangle_count; ++t) {
        const uint32_t *i = out->indices + 3 * t;
        double lo = 1, hi = 0;
        for (int k = 0; k < 3; ++k) {
            double x = out->positions[3 * (size_t)i[k]];
            lo = x < lo ? x : lo;
            hi = x > hi ? x : hi;
        }
        ck_assert_msg(!(lo < 0.5 - seam_tol && hi > 0.5 + seam_tol), "triangle %zu straddles the seam", t);
    }
}

START_TEST(simplify_seam_kept_flat)
{
    resurf_mesh *m = seam_grid(16, 0);
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.1;
    resurf_simplify_report r;
    resurf_mesh *out = simplify_ok(m, &o, &r);
    ck_assert_uint_le(out->triangle_count, 52);
    ck_assert_uint_gt(r.positions, 0);
    ck_assert_uint_gt(r.vertices, r.positions); /* seam copies */
    check_seam_grid(out, 1e-9, 1e-12);
    resurf_validate_report v = validation(out);
    ck_assert_uint_eq(v.boundary_loops, 1); /* the seam is no border: topology over welded positions */
    ck_assert_uint_eq(v.nonmanifold_edges, 0);
    ck_assert_double_eq_tol(area(out), 1.0, 1e-9);
    resurf_mesh_free(out);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(simplify_seam_kept_curved)
{
    /* Lifted onto a paraboloid the vertices are restored: texcoords then come from the closest input triangle on
     * their own side, so they are the linear function of the foot point, within the restore's offset of x. Seam
     * vertices collapse along the seam (x = ½) and restoring moves them along S's normal, which has no x part
     * there. */
    resurf_mesh *m = seam_grid(24, 0.6);
    for (int mode = 0; mode < RESURF_RESTORE_MODE_COUNT; ++mode) {
        resurf_simplify_options o = resurf_simplify_options_default();
        o.target_ratio = 0.15;
        o.restore = (resurf_restore_mode)mode;
        resurf_simplify_report r;
        resurf_mesh *out = simplify_ok(m, &o, &r);
        check_seam_grid(out, 2e-3, 1e-6); /* the restorer's normals are not exactly symmetric about x = ½ */
        resurf_validate_report v = validation(out);
        ck_assert_uint_eq(v.boundary_loops, 1);
        ck_assert_uint_eq(v.nonmanifold_edges, 0);
        ck_assert_uint_eq(v.inconsistent_edges, 0);
        resurf_mesh_free(out);
    }
    resurf_mesh_free(m);
}
END_TEST

/* ---- analytic shapes ----------------------------------------------------------------------------------------- */

START_TEST(simplify_targets_reached)
{
    static const shape_kind kinds[] = {SHAPE_SPHERE, SHAPE_TORUS, SHAPE_CUBIC};
    for (size_t k = 0; k < 3; ++k) {
        resurf_mesh *m = shape_mesh(kinds[k], 6000, 0.3, 7, 0);
        resurf_validate_report vin = validation(m);
        for (int mode = 0; mode < RESURF_RESTORE_MODE_COUNT; mode += 2) { /* inline and none */
            resurf_simplify_options o = resurf_simplify_options_default();
            o.target_ratio = 0.05;
            o.restore = (resurf_restore_mode)mode;
            resurf_simplify_report r;
            resurf_mesh *out = simplify_ok(m, &o, &r);
            size_t target = (size_t)(0.05 * (double)m->triangle_count);
            ck_assert_msg(out->triangle_count <= target && out->triangle_count + 2 >= target,
                          "%s: %zu triangles for a target of %zu", shape_name(kinds[k]), out->triangle_count, target);
            ck_assert_int_eq(r.stop, RESURF_STOP_TARGET);
            assert_clean(out);
            resurf_validate_report v = validation(out);
            ck_assert_uint_eq(v.components, 1);
            ck_assert_uint_eq(v.boundary_loops, vin.boundary_loops);
            /* Euler characteristic kept: V − E + F */
            size_t e_in = (3 * vin.triangle_count + vin.boundary_edges) / 2;
            size_t e_out = (3 * v.triangle_count + v.boundary_edges) / 2;
            ck_assert_int_eq((long)v.position_count - (long)e_out + (long)v.triangle_count,
                             (long)vin.position_count - (long)e_in + (long)vin.triangle_count);
            assert_no_flips(kinds[k], out);
            ck_assert(r.max_distance >= r.mean_distance && r.mean_distance > 0);
            resurf_mesh_free(out);
        }
        resurf_mesh_free(m);
    }
}
END_TEST

/* Targets are unset by default and only those set count: a triangle count alone is reached (before 0.2 the default
 * ratio of 0.5 stopped it at half), an error bound alone goes past half, and no target at all goes as far as the
 * guards allow. */
START_TEST(simplify_only_the_targets_set_count)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 8000, 0.3, 5, 0);
    const size_t n = m->triangle_count;
    resurf_simplify_options o = resurf_simplify_options_default();
    ck_assert_uint_eq(o.target_triangles, 0);
    ck_assert(o.target_ratio == 0 && o.max_error == 0 && o.max_error_rel == 0);
    o.target_triangles = n / 8;
    resurf_simplify_report r;
    resurf_mesh *out = simplify_ok(m, &o, &r);
    ck_assert_msg(out->triangle_count <= n / 8 && out->triangle_count + 2 >= n / 8, "%zu triangles for %zu",
                  out->triangle_count, n / 8);
    ck_assert_int_eq(r.stop, RESURF_STOP_TARGET);
    resurf_mesh_free(out);

    o = resurf_simplify_options_default();
    o.max_error_rel = 0.01;
    out = simplify_ok(m, &o, &r);
    ck_assert_uint_lt(out->triangle_count, n / 4);
    ck_assert_int_eq(r.stop, RESURF_STOP_ERROR);
    resurf_mesh_free(out);

    o = resurf_simplify_options_default();
    o.restore = RESURF_RESTORE_NONE;
    out = simplify_ok(m, &o, &r);
    ck_assert_uint_lt(out->triangle_count, n / 20);
    ck_assert_int_eq(r.stop, RESURF_STOP_BLOCKED);
    resurf_mesh_free(out);
    resurf_mesh_free(m);
}
END_TEST

/* restore_options NULL is exactly resurf_restore_options_default(): byte-identical LODs, inline and post (before 0.2
 * NULL meant Max's normals and the defaults the jet fit, which the last comparison tells apart). */
START_TEST(simplify_null_restore_options_are_the_defaults)
{
    resurf_mesh *m = shape_mesh(SHAPE_CUBIC, 6000, 0.3, 3, 0);
    for (int mode = RESURF_RESTORE_INLINE; mode <= RESURF_RESTORE_POST; ++mode) {
        resurf_simplify_options o = resurf_simplify_options_default();
        o.target_ratio = 0.1;
        o.restore = (resurf_restore_mode)mode;
        o.measure_samples = 0;
        ck_assert_ptr_null(o.restore_options);
        resurf_mesh *by_null = simplify_ok(m, &o, NULL);
        const resurf_restore_options defaults = resurf_restore_options_default();
        o.restore_options = &defaults;
        resurf_mesh *by_defaults = simplify_ok(m, &o, NULL);
        ck_assert_msg(same_mesh_bytes(by_null, by_defaults), "mode %d: NULL and the defaults differ", mode);
        resurf_restore_options jet = defaults;
        jet.normals = RESURF_NORMALS_JET;
        o.restore_options = &jet;
        resurf_mesh *by_jet = simplify_ok(m, &o, NULL);
        ck_assert_msg(!same_mesh_bytes(by_null, by_jet), "mode %d: jet normals change nothing", mode);
        resurf_mesh_free(by_null);
        resurf_mesh_free(by_defaults);
        resurf_mesh_free(by_jet);
    }
    resurf_mesh_free(m);
}
END_TEST

START_TEST(simplify_sphere_lod_vertices_on_sphere)
{
    /* With restoration on and the straddling offset off, every vertex of the 20k irregular sphere at 10% lies on
     * the unit sphere (within 1e-4); without restoration they lie inside it by the quadric's sag. */
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 20000, 0.3, 1, 0);
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.1;
    o.sag_offset = 0;
    static const resurf_restore_mode modes[] = {RESURF_RESTORE_INLINE, RESURF_RESTORE_POST};
    for (int i = 0; i < 2; ++i) {
        o.restore = modes[i];
        resurf_simplify_report r;
        resurf_mesh *out = simplify_ok(m, &o, &r);
        ck_assert_uint_le(out->triangle_count, m->triangle_count / 10);
        double d = max_shape_distance(SHAPE_SPHERE, out);
        ck_assert_msg(d <= 1e-4, "%s: a vertex %.3g off the sphere", i ? "post" : "inline", d);
        ck_assert_uint_gt(r.restored, 0);
        ck_assert_uint_eq(r.restore_left, 0);
        resurf_mesh_free(out);
    }
    o.restore = RESURF_RESTORE_NONE;
    resurf_mesh *plain = simplify_ok(m, &o, NULL);
    ck_assert(max_shape_distance(SHAPE_SPHERE, plain) > 1e-4); /* the check above can fail */
    resurf_mesh_free(plain);
    /* the straddling offset moves vertices outward, by about the sag */
    o.restore = RESURF_RESTORE_INLINE;
    o.sag_offset = 1;
    resurf_mesh *off = simplify_ok(m, &o, NULL);
    for (size_t v = 0; v < off->vertex_count; ++v)
        ck_assert(v3_len(resurfi_position(off, (uint32_t)v)) >= 1 - 1e-4);
    ck_assert(max_shape_distance(SHAPE_SPHERE, off) > 1e-4);
    resurf_mesh_free(off);
    resurf_mesh_free(m);
}
END_TEST

/* The default keeps, per level, the inline level where it lies as near the input as the plain one in maximum and
 * in mean, else the plain one. On the jittered cubic surface at 10% the plain collapse's two-sided maximum is
 * smaller (the restored vertices sit on S, and S rises above the input's facets); on the sphere with the sag
 * offset restoration wins both. Each default level is one of the two byte for byte, the one the dense evaluation
 * finds nearer by the rule, and its report says which. */
START_TEST(simplify_measured_restore_keeps_the_closer_level)
{
    static const shape_kind kinds[2] = {SHAPE_CUBIC, SHAPE_SPHERE};
    static const resurf_restore_mode winner[2] = {RESURF_RESTORE_NONE, RESURF_RESTORE_INLINE};
    for (int k = 0; k < 2; ++k) {
        resurf_mesh *m = shape_mesh(kinds[k], 8000, 0.3, 1, 0);
        resurf_simplify_options o = resurf_simplify_options_default();
        ck_assert_int_eq(o.restore, RESURF_RESTORE_MEASURED);
        o.target_ratio = 0.1;
        resurf_simplify_report r, ri, rn;
        resurf_mesh *chosen = simplify_ok(m, &o, &r);
        o.restore = RESURF_RESTORE_INLINE;
        resurf_mesh *restored = simplify_ok(m, &o, &ri);
        o.restore = RESURF_RESTORE_NONE;
        resurf_mesh *plain = simplify_ok(m, &o, &rn);
        resurf_compare_report di = tu_compare(m, restored, 200000), dn = tu_compare(m, plain, 200000);
        int inline_nearer = di.hausdorff <= dn.hausdorff && di.mean <= dn.mean;
        ck_assert_msg(inline_nearer == (winner[k] == RESURF_RESTORE_INLINE), "shape %d: inline %g / %g, none %g / %g",
                      k, di.hausdorff, di.mean, dn.hausdorff, dn.mean);
        if (winner[k] == RESURF_RESTORE_NONE) /* by a margin the report cannot miss */
            ck_assert_msg(dn.hausdorff < 0.97 * di.hausdorff, "cubic: inline %g, none %g", di.hausdorff, dn.hausdorff);
        ck_assert_int_eq(r.restore_used, winner[k]);
        ck_assert(same_mesh_bytes(chosen, winner[k] == RESURF_RESTORE_NONE ? plain : restored));
        ck_assert_int_eq(ri.restore_used, RESURF_RESTORE_INLINE);
        ck_assert_int_eq(rn.restore_used, RESURF_RESTORE_NONE);
        resurf_mesh_free(chosen);
        resurf_mesh_free(restored);
        resurf_mesh_free(plain);
        resurf_mesh_free(m);
    }
}
END_TEST

START_TEST(simplify_lod_chain_restored_onto_original)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 20000, 0.3, 1, 0);
    resurf_simplify_options o = resurf_simplify_options_default();
    o.restore = RESURF_RESTORE_INLINE; /* on S without the offset: the measured choice may keep the plain level */
    o.sag_offset = 0;
    const double ratios[] = {0.5, 0.25, 0.1, 0.02};
    resurf_mesh *levels[4];
    resurf_simplify_report reps[4];
    resurf_error e;
    ck_assert_int_eq(resurf_simplify_lods(m, ratios, 4, &o, levels, reps, &e), RESURF_OK);
    for (int i = 0; i < 4; ++i) {
        ck_assert_uint_le(levels[i]->triangle_count, (size_t)(ratios[i] * (double)m->triangle_count));
        ck_assert_uint_eq(reps[i].triangles, levels[i]->triangle_count);
        if (i)
            ck_assert_uint_gt(reps[i].collapses, reps[i - 1].collapses);
        ck_assert(max_shape_distance(SHAPE_SPHERE, levels[i]) <= 1e-4);
        assert_clean(levels[i]);
    }
    /* a single call to the same ratio gives the same mesh as the chain's level */
    o.target_ratio = 0.1;
    resurf_mesh *single = simplify_ok(m, &o, NULL);
    ck_assert(same_mesh_bytes(single, levels[2]));
    resurf_mesh_free(single);
    for (int i = 0; i < 4; ++i)
        resurf_mesh_free(levels[i]);
    /* bad ratios */
    const double bad[] = {0.2, 0.5};
    ck_assert_int_eq(resurf_simplify_lods(m, bad, 2, &o, levels, NULL, NULL), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(levels[0]);
    const double zero[] = {0.0};
    ck_assert_int_eq(resurf_simplify_lods(m, zero, 1, &o, levels, NULL, NULL), RESURF_ERR_INVALID_ARGUMENT);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(simplify_deterministic_over_threads)
{
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 8000, 0.3, 3, 0);
    /* attributes too: normals and a texcoord made from the position */
    resurf_mesh *a = NULL;
    ck_assert_int_eq(resurf_mesh_create(m->vertex_count, m->triangle_count,
                                        RESURF_ATTR_NORMALS | RESURF_ATTR_TEXCOORD0, &a, NULL),
                     RESURF_OK);
    memcpy(a->positions, m->positions, 3 * m->vertex_count * sizeof(double));
    memcpy(a->indices, m->indices, 3 * m->triangle_count * sizeof(uint32_t));
    for (size_t v = 0; v < m->vertex_count; ++v) {
        double n[3];
        shape_normal(SHAPE_TORUS, m->positions + 3 * v, n);
        memcpy(a->normals + 3 * v, n, sizeof n);
        a->texcoords[0][2 * v] = m->positions[3 * v];
        a->texcoords[0][2 * v + 1] = m->positions[3 * v + 2];
    }
    for (int mode = 0; mode < RESURF_RESTORE_MODE_COUNT; ++mode) {
        resurf_simplify_options o = resurf_simplify_options_default();
        o.target_ratio = 0.1;
        o.restore = (resurf_restore_mode)mode;
        o.threads = 1;
        resurf_simplify_report r1;
        resurf_mesh *first = simplify_ok(a, &o, &r1);
        for (unsigned threads = 2; threads <= 4; threads += 2) {
            o.threads = threads;
            resurf_simplify_report r2;
            resurf_mesh *again = simplify_ok(a, &o, &r2);
            ck_assert_msg(same_mesh_bytes(first, again), "mode %d: %u threads differ from 1", mode, threads);
            ck_assert(r1.max_distance == r2.max_distance && r1.mean_distance == r2.mean_distance);
            resurf_mesh_free(again);
        }
        o.threads = 1;
        resurf_mesh *repeat = simplify_ok(a, &o, NULL);
        ck_assert(same_mesh_bytes(first, repeat));
        resurf_mesh_free(repeat);
        resurf_mesh_free(first);
    }
    resurf_mesh_free(a);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(simplify_error_bound_stops)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 8000, 0.3, 5, 0);
    resurf_simplify_options o = resurf_simplify_options_default();
    o.max_error_rel = 1e-3;
    o.restore = RESURF_RESTORE_NONE;
    resurf_simplify_report r;
    resurf_mesh *out = simplify_ok(m, &o, &r);
    ck_assert_int_eq(r.stop, RESURF_STOP_ERROR);
    ck_assert_uint_gt(r.skipped_error, 0);
    ck_assert(r.max_error_estimate <= 1e-3 * r.diagonal);
    ck_assert_uint_lt(out->triangle_count, m->triangle_count / 2);
    ck_assert_uint_gt(out->triangle_count, 20);
    /* the bound limits the measured distance too: facets of a sphere sag by about as much as the estimate */
    ck_assert(r.max_distance_rel < 1e-2);
    /* a looser bound goes further; an absolute bound acts the same way */
    o.max_error_rel = 1e-2;
    resurf_mesh *loose = simplify_ok(m, &o, NULL);
    ck_assert_uint_lt(loose->triangle_count, out->triangle_count);
    o.max_error_rel = 0;
    o.max_error = 1e-3 * r.diagonal;
    resurf_simplify_report ra;
    resurf_mesh *abs = simplify_ok(m, &o, &ra);
    ck_assert_uint_eq(abs->triangle_count, out->triangle_count);
    /* a triangle target that comes first wins */
    o.target_ratio = 0.9;
    resurf_simplify_report rt;
    resurf_mesh *tgt = simplify_ok(m, &o, &rt);
    ck_assert_int_eq(rt.stop, RESURF_STOP_TARGET);
    ck_assert_uint_le(tgt->triangle_count, (size_t)(0.9 * (double)m->triangle_count));
    resurf_mesh_free(tgt);
    resurf_mesh_free(abs);
    resurf_mesh_free(loose);
    resurf_mesh_free(out);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(simplify_min_angle_guard)
{
    /* A regular (unjittered) sphere has no angle under 20°; with the guard no collapse makes one. */
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 6000, 0.0, 1, 0);
    double in_min;
    ck_assert_int_eq(resurf_triangle_quality(m, &in_min, NULL, NULL, NULL), RESURF_OK);
    ck_assert(in_min >= 20);
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.05;
    o.min_angle_deg = 20;
    o.sag_offset = 0;
    resurf_simplify_report r;
    resurf_mesh *out = simplify_ok(m, &o, &r);
    double out_min;
    ck_assert_int_eq(resurf_triangle_quality(out, &out_min, NULL, NULL, NULL), RESURF_OK);
    ck_assert_msg(out_min >= 20 - 1e-9, "smallest angle %g", out_min);
    ck_assert_uint_gt(r.blocked_min_angle, 0);
    resurf_mesh_free(out);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(simplify_keeps_attribute_layout)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 3000, 0.3, 2, 1);
    ck_assert_ptr_nonnull(m->normals);
    /* colours (3 components in the source), two texcoord sets, one extra, groups */
    m->colors = calloc(4 * m->vertex_count, sizeof(double));
    m->color_components = 3;
    m->texcoords[0] = calloc(2 * m->vertex_count, sizeof(double));
    m->texcoords[1] = calloc(2 * m->vertex_count, sizeof(double));
    m->texcoord_count = 2;
    resurf_attribute *ex = NULL;
    ck_assert_int_eq(resurf_mesh_add_extra(m, "weight", 2, &ex, NULL), RESURF_OK);
    for (size_t v = 0; v < m->vertex_count; ++v) {
        const double *p = m->positions + 3 * v;
        for (int c = 0; c < 3; ++c)
            m->colors[4 * v + c] = 0.5 + 0.5 * p[c];
        m->colors[4 * v + 3] = 1;
        m->texcoords[0][2 * v] = p[0], m->texcoords[0][2 * v + 1] = p[1];
        m->texcoords[1][2 * v] = p[2], m->texcoords[1][2 * v + 1] = 1;
        ex->data[2 * v] = (float)p[2], ex->data[2 * v + 1] = 3;
    }
    m->group_count = 2;
    m->group_names = calloc(2, sizeof(char *));
    m->group_names[0] = strdup("north");
    m->group_names[1] = strdup("south");
    m->triangle_groups = calloc(m->triangle_count, sizeof(uint32_t));
    for (size_t t = 0; t < m->triangle_count; ++t)
        m->triangle_groups[t] = m->positions[3 * (size_t)m->indices[3 * t] + 2] < 0;

    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.2;
    resurf_mesh *out = simplify_ok(m, &o, NULL);
    ck_assert_ptr_nonnull(out->normals);
    ck_assert_ptr_nonnull(out->colors);
    ck_assert_uint_eq(out->color_components, 3);
    ck_assert_uint_eq(out->texcoord_count, 2);
    ck_assert_ptr_nonnull(out->texcoords[1]);
    ck_assert_uint_eq(out->extra_count, 1);
    ck_assert_str_eq(out->extras[0].name, "weight");
    ck_assert_uint_eq(out->extras[0].components, 2);
    ck_assert_uint_eq(out->group_count, 2);
    ck_assert_str_eq(out->group_names[1], "south");
    ck_assert_ptr_nonnull(out->triangle_groups);
    for (size_t v = 0; v < out->vertex_count; ++v) {
        vec3 p = resurfi_position(out, (uint32_t)v);
        vec3 n = v3_load(out->normals + 3 * v);
        /* the smooth normal field of a sphere at a point of it is the radial direction */
        ck_assert_msg(v3_dot(n, v3_normalize(p)) > 0.999, "normal %zu off by %g", v, acos(v3_dot(n, v3_normalize(p))));
        /* attributes linear in the position are interpolated at the foot point: close to the vertex's own values */
        ck_assert_double_eq_tol(out->colors[4 * v], 0.5 + 0.5 * p.x, 2e-2);
        ck_assert_double_eq_tol(out->colors[4 * v + 3], 1.0, 1e-12);
        ck_assert_double_eq_tol(out->texcoords[0][2 * v + 1], p.y, 4e-2);
        ck_assert_double_eq_tol(out->texcoords[1][2 * v + 1], 1.0, 1e-12);
        ck_assert_double_eq_tol(out->extras[0].data[2 * v + 1], 3.0, 1e-6);
        ck_assert_double_eq_tol(out->extras[0].data[2 * v], p.z, 4e-2);
    }
    for (size_t t = 0; t < out->triangle_count; ++t) {
        double z = out->positions[3 * (size_t)out->indices[3 * t] + 2];
        if (fabs(z) > 0.2) /* well inside a hemisphere: the triangle descends from an input triangle there */
            ck_assert_uint_eq(out->triangle_groups[t], z < 0);
    }
    resurf_mesh_free(out);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(simplify_midpoint_placement)
{
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 6000, 0.3, 4, 0);
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.1;
    o.sag_offset = 0;
    o.placement = RESURF_PLACEMENT_MIDPOINT;
    resurf_simplify_report r;
    resurf_mesh *out = simplify_ok(m, &o, &r);
    assert_clean(out);
    ck_assert_uint_le(out->triangle_count, m->triangle_count / 10);
    ck_assert(max_shape_distance(SHAPE_TORUS, out) < 1e-3);
    resurf_mesh_free(out);
    resurf_mesh_free(m);
}
END_TEST

/* ---- hostile and tiny inputs --------------------------------------------------------------------------------- */

START_TEST(simplify_nonmanifold_input)
{
    /* A 6×6 grid with a fin (a third triangle on an interior edge) and a second grid touching it at one corner
     * (a bow tie): non-manifold positions never move. */
    resurf_mesh *g = tu_grid(6);
    size_t nv = g->vertex_count, nt = g->triangle_count;
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(2 * nv + 1, 2 * nt + 1, 0, &m, NULL), RESURF_OK);
    memcpy(m->positions, g->positions, 3 * nv * sizeof(double));
    for (size_t v = 0; v < nv; ++v) { /* the second grid: [1,2]×[1,2], touching at (1,1) */
        m->positions[3 * (nv + v)] = g->positions[3 * v] + 1;
        m->positions[3 * (nv + v) + 1] = g->positions[3 * v + 1] + 1;
        m->positions[3 * (nv + v) + 2] = 0;
    }
    memcpy(m->indices, g->indices, 3 * nt * sizeof(uint32_t));
    for (size_t i = 0; i < 3 * nt; ++i)
        m->indices[3 * nt + i] = g->indices[i] + (uint32_t)nv;
    /* the fin on the interior edge (0,0)–(1/6,1/6) of the first grid: vertices 0 and 8 */
    v3_store(m->positions + 3 * (2 * nv), v3(0.1, 0.05, 0.3));
    m->indices[6 * nt] = 0, m->indices[6 * nt + 1] = 8, m->indices[6 * nt + 2] = (uint32_t)(2 * nv);
    resurf_validate_report vin = validation(m);
    ck_assert_uint_gt(vin.nonmanifold_edges, 0);
    ck_assert_uint_gt(vin.nonmanifold_vertices, 0);
    for (int mode = 0; mode < RESURF_RESTORE_MODE_COUNT; ++mode) {
        resurf_simplify_options o = resurf_simplify_options_default();
        o.restore = (resurf_restore_mode)mode;
        resurf_simplify_report r;
        resurf_mesh *out = simplify_ok(m, &o, &r);
        ck_assert_uint_lt(out->triangle_count, m->triangle_count);
        ck_assert_uint_gt(r.blocked_nonmanifold, 0);
        resurf_validate_report v = validation(out);
        ck_assert(resurf_validation_ok(&v));
        ck_assert_uint_eq(v.degenerate_triangles, 0);
        ck_assert_uint_le(v.nonmanifold_edges, vin.nonmanifold_edges);
        /* the non-manifold points (0,0), (1/6,1/6) and (1,1) are still there */
        const vec3 pins[] = {{0, 0, 0}, {1.0 / 6, 1.0 / 6, 0}, {1, 1, 0}};
        for (int k = 0; k < 3; ++k) {
            int found = 0;
            for (size_t i = 0; i < out->vertex_count; ++i)
                found |= v3_dist(resurfi_position(out, (uint32_t)i), pins[k]) < 1e-12;
            ck_assert_msg(found, "non-manifold vertex %d moved", k);
        }
        resurf_mesh_free(out);
    }
    resurf_mesh_free(g);
    resurf_mesh_free(m);
}
END_TEST

/* Fins: a closed sphere plus (i) a back-to-back pair (a, b, x), (b, a, x) hanging off an edge, which encloses
 * nothing, and (ii) a copy of a surface triangle T facing the same way and one facing the other way. By default
 * the pair and one of T's copies with the opposite one go (4 triangles), T itself stays, the result is a closed
 * manifold at the target; with drop_fins = 0 every triangle takes part and the pair's non-manifold edge blocks. */
START_TEST(simplify_drops_fins)
{
    resurf_mesh *sphere = shape_mesh(SHAPE_SPHERE, 4000, 0.3, 2, 0), *m = NULL;
    size_t nv = sphere->vertex_count, nt = sphere->triangle_count;
    ck_assert_int_eq(resurf_mesh_create(nv + 1, nt + 4, 0, &m, NULL), RESURF_OK);
    memcpy(m->positions, sphere->positions, 3 * nv * sizeof(double));
    memcpy(m->indices, sphere->indices, 3 * nt * sizeof(uint32_t));
    const uint32_t *t0 = sphere->indices; /* T: the first triangle; the fin hangs off its edge (t0[0], t0[1]) */
    vec3 a = resurfi_position(sphere, t0[0]), b = resurfi_position(sphere, t0[1]);
    v3_store(m->positions + 3 * nv, v3_scale(v3_add(a, b), 0.6)); /* x: outside, over the edge's midpoint */
    uint32_t extra[4][3] = {{t0[0], t0[1], (uint32_t)nv}, {t0[1], t0[0], (uint32_t)nv},
                            {t0[1], t0[2], t0[0]} /* T again, same way */, {t0[0], t0[2], t0[1]} /* the other way */};
    memcpy(m->indices + 3 * nt, extra, sizeof extra);
    resurf_validate_report vin = validation(m);
    ck_assert_uint_gt(vin.nonmanifold_edges, 0);

    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.2;
    o.restore = RESURF_RESTORE_NONE;
    resurf_simplify_report r;
    resurf_mesh *out = simplify_ok(m, &o, &r);
    ck_assert_uint_eq(r.dropped_fins, 4);
    ck_assert_uint_eq(r.input_triangles, nt);
    ck_assert_uint_le(out->triangle_count, (size_t)(0.2 * (double)m->triangle_count));
    resurf_validate_report v = validation(out);
    ck_assert_uint_eq(v.nonmanifold_edges, 0);
    ck_assert_uint_eq(v.boundary_edges, 0); /* T stayed: no hole */
    resurf_mesh_free(out);

    o.drop_fins = false;
    out = simplify_ok(m, &o, &r);
    ck_assert_uint_eq(r.dropped_fins, 0);
    ck_assert_uint_eq(r.input_triangles, nt + 4);
    ck_assert_uint_gt(r.blocked_nonmanifold, 0);
    resurf_mesh_free(out);
    resurf_mesh_free(sphere);
    resurf_mesh_free(m);
}
END_TEST

/* A double-sided sheet: a flat panel written twice over the same positions, the second copy with the winding
 * reversed, its normals -z and its texture mapped mirrored (u' = 1 - u), as exporters write a leaf card, a flag or a
 * sign. Every triangle is one of an opposite pair, yet the pairs are the sheet, not strays. Every level keeps both
 * sides: each triangle has a reversed twin over the same positions, each corner's normal is its face's, each side's
 * texture coordinates are that side's own mapping at the corner's position, and the level lies on the panel with
 * its outline, so the two-sided distance to the input is rounding. Before, both sides were dropped and the level
 * was empty; then one side stayed, invisible from behind with a one-sided material. */
START_TEST(simplify_keeps_double_sided_sheets)
{
    resurf_mesh *panel = shape_mesh(SHAPE_PLANE, 2000, 0.3, 4, 0), *m = NULL;
    size_t nv = panel->vertex_count, nt = panel->triangle_count;
    ck_assert_int_eq(resurf_mesh_create_with(2 * nv, 2 * nt, RESURF_ATTR_NORMALS | RESURF_ATTR_TEXCOORD0, NULL, &m,
                                             NULL),
                     RESURF_OK);
    for (size_t side = 0; side < 2; ++side)
        for (size_t v = 0; v < nv; ++v) {
            const double *p = panel->positions + 3 * v;
            size_t w = side * nv + v;
            memcpy(m->positions + 3 * w, p, 3 * sizeof(double));
            v3_store(m->normals + 3 * w, v3(0, 0, side ? -1 : 1));
            m->texcoords[0][2 * w] = side ? 1 - (p[0] + 1) / 2 : (p[0] + 1) / 2;
            m->texcoords[0][2 * w + 1] = (p[1] + 1) / 2;
        }
    for (size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) {
            m->indices[3 * t + (size_t)k] = panel->indices[3 * t + (size_t)k];
            m->indices[3 * (nt + t) + (size_t)k] = (uint32_t)nv + panel->indices[3 * t + (size_t)(2 - k)];
        }
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.25;
    resurf_simplify_report r;
    resurf_mesh *out = simplify_ok(m, &o, &r);
    ck_assert_uint_eq(r.dropped_fins, 0);
    ck_assert_uint_gt(out->triangle_count, 0);
    ck_assert_uint_le(out->triangle_count, nt / 2);
    ck_assert_uint_eq(r.triangles, out->triangle_count);
    size_t up = 0, twins = 0;
    for (size_t t = 0; t < out->triangle_count; ++t) {
        const uint32_t *f = out->indices + 3 * t;
        vec3 a = resurfi_position(out, f[0]), b = resurfi_position(out, f[1]), c = resurfi_position(out, f[2]);
        double z = v3_tri_cross(a, b, c).z, sign = z > 0 ? 1 : -1;
        ck_assert(z != 0);
        up += z > 0;
        for (int k = 0; k < 3; ++k) {
            const double *p = out->positions + 3 * f[k], *uv = out->texcoords[0] + 2 * f[k];
            ck_assert_double_eq_tol(out->normals[3 * f[k] + 2], sign, 1e-12);
            ck_assert_double_eq_tol(uv[0], z > 0 ? (p[0] + 1) / 2 : 1 - (p[0] + 1) / 2, 1e-9);
            ck_assert_double_eq_tol(uv[1], (p[1] + 1) / 2, 1e-9);
        }
        /* its twin: the same three positions, running the other way */
        for (size_t u = 0; u < out->triangle_count && z > 0; ++u) {
            const uint32_t *g = out->indices + 3 * u;
            int same = 0;
            for (int k = 0; k < 3; ++k)
                same += v3_dist2(a, resurfi_position(out, g[k])) == 0 &&
                        v3_dist2(b, resurfi_position(out, g[(k + 2) % 3])) == 0 &&
                        v3_dist2(c, resurfi_position(out, g[(k + 1) % 3])) == 0;
            twins += same;
        }
    }
    ck_assert_uint_eq(2 * up, out->triangle_count);
    ck_assert_uint_eq(twins, up);
    resurf_compare_report d = tu_compare(m, out, 20000);
    ck_assert_msg(d.hausdorff <= 1e-9 * d.diagonal, "the sheet's level is %g of the diagonal away",
                  d.hausdorff / d.diagonal);
    resurf_mesh_free(out);
    resurf_mesh_free(m);
    resurf_mesh_free(panel);
}
END_TEST

/* A closed tube: `rings` rings of `sides` corners on a circle of `radius`, `length` from the first ring to the last,
 * a cone tip `cap` beyond each end. With `slant`, every other ring is turned by half a side (an antiprism tube: every
 * triangle slants); without, each side is a quad cut by a diagonal. */
static resurf_mesh *tube(unsigned sides, unsigned rings, double radius, double length, double cap, int slant)
{
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(rings * sides + 2, 2 * sides * (rings - 1) + 2 * sides, 0, &m, NULL),
                     RESURF_OK);
    for (unsigned i = 0; i < rings; ++i)
        for (unsigned k = 0; k < sides; ++k) {
            double a = 2 * M_PI * (k + (slant && i % 2 ? 0.5 : 0)) / sides;
            v3_store(m->positions + 3 * (i * sides + k),
                     v3(radius * cos(a), radius * sin(a), length * i / (rings - 1)));
        }
    uint32_t bottom = rings * sides, top = bottom + 1;
    v3_store(m->positions + 3 * bottom, v3(0, 0, -cap));
    v3_store(m->positions + 3 * top, v3(0, 0, length + cap));
    uint32_t *t = m->indices;
    for (unsigned i = 0; i + 1 < rings; ++i)
        for (unsigned k = 0; k < sides; ++k) {
            /* lower corners l0, l1 (side k of ring i), upper u0, u1 (ring i + 1) */
            uint32_t l0 = i * sides + k, l1 = i * sides + (k + 1) % sides;
            uint32_t u0 = l0 + sides, u1 = l1 + sides;
            if (slant && i % 2 == 0) { /* u0 lies over the middle of (l0, l1) */
                *t++ = l0, *t++ = l1, *t++ = u0;
                *t++ = l1, *t++ = u1, *t++ = u0;
            } else { /* u1 does, or the quad's diagonal (l0, u1) */
                *t++ = l0, *t++ = l1, *t++ = u1;
                *t++ = l0, *t++ = u1, *t++ = u0;
            }
        }
    for (unsigned k = 0; k < sides; ++k) {
        *t++ = bottom, *t++ = (k + 1) % sides, *t++ = k;
        *t++ = top, *t++ = (rings - 1) * sides + k, *t++ = (rings - 1) * sides + (k + 1) % sides;
    }
    return m;
}

/* A closed tube (radius 0.5, length 2) with a fin: a flat panel written twice with opposite windings, hanging
 * from FIN_COLUMNS of the tube's vertices along a line and reaching 1 outward, in the plane y = 0 (a crest, a
 * dewlap). *fin: the fin's triangles, written after the tube's. */
enum { FIN_SIDES = 24, FIN_RINGS = 20, FIN_FIRST = 2, FIN_COLUMNS = 16, FIN_ROWS = 4 };
static resurf_mesh *tube_with_fin(size_t *fin_triangles)
{
    resurf_mesh *body = tube(FIN_SIDES, FIN_RINGS, 0.5, 2, 0.5, 0), *m = NULL;
    size_t nv = body->vertex_count, nt = body->triangle_count, fin = 2 * 2 * (FIN_COLUMNS - 1) * FIN_ROWS;
    ck_assert_int_eq(resurf_mesh_create(nv + FIN_COLUMNS * FIN_ROWS, nt + fin, 0, &m, NULL), RESURF_OK);
    memcpy(m->positions, body->positions, 3 * nv * sizeof(double));
    memcpy(m->indices, body->indices, 3 * nt * sizeof(uint32_t));
    /* fin vertex (column c, row j): row 0 the tube's vertex of side 0 on ring FIN_FIRST + c, rows 1..FIN_ROWS new */
#define FIN_V(c, j)                                                                                                \
    ((j) == 0 ? (uint32_t)((FIN_FIRST + (c)) * FIN_SIDES) : (uint32_t)(nv + (size_t)(c) * FIN_ROWS + (j) - 1))
    for (int c = 0; c < FIN_COLUMNS; ++c)
        for (int j = 1; j <= FIN_ROWS; ++j) {
            vec3 base = resurfi_position(body, FIN_V(c, 0));
            v3_store(m->positions + 3 * FIN_V(c, j), v3(base.x + (double)j / FIN_ROWS, 0, base.z));
        }
    uint32_t *t = m->indices + 3 * nt;
    for (int side = 0; side < 2; ++side)
        for (int c = 0; c + 1 < FIN_COLUMNS; ++c)
            for (int j = 0; j < FIN_ROWS; ++j) {
                uint32_t q[4] = {FIN_V(c, j), FIN_V(c + 1, j), FIN_V(c + 1, j + 1), FIN_V(c, j + 1)};
                uint32_t tri[2][3] = {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}};
                for (int h = 0; h < 2; ++h)
                    for (int k = 0; k < 3; ++k)
                        *t++ = tri[h][side ? 2 - k : k];
            }
#undef FIN_V
    ck_assert_ptr_eq(t, m->indices + 3 * (nt + fin));
    resurf_mesh_free(body);
    *fin_triangles = fin;
    return m;
}

/* A double-sided sheet attached along a line: the tube with its fin (tube_with_fin). Dropped with the fins, the
 * level loses the fin, whose far edge lies 1 from the tube; kept, the fin, a flat rectangle, stays whole. The
 * measured default makes both and keeps the nearer: at 50% that is the fin kept, its level within a tenth of the
 * dropped one's distance. A single restoring mode drops it unless attached_sheets says KEEP. */
START_TEST(simplify_chooses_attached_sheets_by_measure)
{
    size_t fin;
    resurf_mesh *m = tube_with_fin(&fin);

    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.5;
    resurf_simplify_report chosen, dropped, kept;
    resurf_mesh *out = simplify_ok(m, &o, &chosen);
    o.attached_sheets = RESURF_SHEETS_DROP;
    resurf_mesh *out_dropped = simplify_ok(m, &o, &dropped);
    ck_assert_uint_eq(dropped.dropped_fins, fin);
    ck_assert_int_eq(dropped.attached_sheets_used, RESURF_SHEETS_DROP);
    ck_assert_double_ge(dropped.input_to_result_max, 0.95); /* the fin's far edge, 1 from the tube */
    ck_assert_int_eq(chosen.attached_sheets_used, RESURF_SHEETS_KEEP);
    ck_assert_uint_eq(chosen.dropped_fins, 0);
    ck_assert_double_le(chosen.max_distance, 0.1 * dropped.max_distance);
    ck_assert_uint_le(chosen.triangles, m->triangle_count / 2);
    /* the fin's far corners are still there: border corners hold */
    vec3 ends[2] = {v3(1.5, 0, 2.0 * FIN_FIRST / (FIN_RINGS - 1)),
                    v3(1.5, 0, 2.0 * (FIN_FIRST + FIN_COLUMNS - 1) / (FIN_RINGS - 1))};
    for (int e = 0; e < 2; ++e) {
        int found = 0;
        for (size_t v = 0; v < out->vertex_count; ++v)
            found |= v3_dist(resurfi_position(out, (uint32_t)v), ends[e]) < 1e-12;
        ck_assert_msg(found, "the fin's far corner %d moved", e);
    }
    /* one restoring mode: dropped unless kept on request */
    o.restore = RESURF_RESTORE_INLINE;
    o.attached_sheets = RESURF_SHEETS_CHOOSE;
    resurf_mesh *out_inline = simplify_ok(m, &o, &kept);
    ck_assert_int_eq(kept.attached_sheets_used, RESURF_SHEETS_DROP);
    ck_assert_uint_eq(kept.dropped_fins, fin);
    resurf_mesh_free(out_inline);
    o.attached_sheets = RESURF_SHEETS_KEEP;
    out_inline = simplify_ok(m, &o, &kept);
    ck_assert_int_eq(kept.attached_sheets_used, RESURF_SHEETS_KEEP);
    ck_assert_double_le(kept.max_distance, 0.1 * dropped.max_distance);
    resurf_mesh_free(out_inline);
    resurf_mesh_free(out_dropped);
    resurf_mesh_free(out);
    resurf_mesh_free(m);
}
END_TEST

/* A closed tube (radius 0.5, length 2, cone caps) written double-sided as some exporters write it: every face and
 * then its mirror, but with the mirror first on every other face, so that the first-written triangles face both
 * ways; and its bottom cap written once, so that the double-sided part is a sheet attached along the cap's ring
 * (Sweet Home 3D's porch column: 3,082 such pairs and 24 single faces). The sheet's kept side must run the way the
 * cap does, which makes the kept triangles one closed, consistently oriented surface: the level then reaches its
 * target, every face of the sheet written with its mirror, and lies on the tube to rounding. Keeping the first-written
 * triangle of each pair instead left a surface folded along half its edges, which the collapses cannot cross: the
 * kept level stopped blocked, and the level chosen dropped the tube. */
START_TEST(simplify_sheet_side_follows_the_surface)
{
    enum { SIDES = 24, RINGS = 20 };
    resurf_mesh *body = tube(SIDES, RINGS, 0.5, 2, 0.5, 0), *m = NULL;
    size_t nv = body->vertex_count, nt = body->triangle_count, caps = 0;
    const uint32_t bottom = RINGS * SIDES;
    for (size_t t = 0; t < nt; ++t)
        caps += body->indices[3 * t] == bottom;
    ck_assert_uint_eq(caps, SIDES);
    size_t total = 2 * nt - caps;
    ck_assert_int_eq(resurf_mesh_create(nv, total, 0, &m, NULL), RESURF_OK);
    memcpy(m->positions, body->positions, 3 * nv * sizeof(double));
    uint32_t *w = m->indices;
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *f = body->indices + 3 * t;
        uint32_t mirror[3] = {f[0], f[2], f[1]};
        if (f[0] == bottom) { /* the cap: once */
            memcpy(w, f, sizeof mirror), w += 3;
            continue;
        }
        const uint32_t *first = t % 2 ? mirror : f, *second = t % 2 ? f : mirror;
        memcpy(w, first, sizeof mirror), w += 3;
        memcpy(w, second, sizeof mirror), w += 3;
    }
    ck_assert_ptr_eq(w, m->indices + 3 * total);

    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.25;
    resurf_simplify_report r;
    resurf_mesh *out = simplify_ok(m, &o, &r);
    ck_assert_int_eq(r.attached_sheets_used, RESURF_SHEETS_KEEP);
    ck_assert_uint_eq(r.dropped_fins, 0);
    ck_assert_int_eq(r.stop, RESURF_STOP_TARGET);
    ck_assert_uint_le(r.triangles, total / 4);
    /* every triangle off the cap has its mirror: the same three positions, running the other way */
    size_t twins = 0;
    for (size_t t = 0; t < out->triangle_count; ++t) {
        const uint32_t *f = out->indices + 3 * t;
        vec3 a = resurfi_position(out, f[0]), b = resurfi_position(out, f[1]), c = resurfi_position(out, f[2]);
        for (size_t u = 0; u < out->triangle_count; ++u) {
            const uint32_t *g = out->indices + 3 * u;
            for (int k = 0; k < 3; ++k)
                twins += v3_dist2(a, resurfi_position(out, g[k])) == 0 &&
                         v3_dist2(b, resurfi_position(out, g[(k + 2) % 3])) == 0 &&
                         v3_dist2(c, resurfi_position(out, g[(k + 1) % 3])) == 0;
        }
    }
    ck_assert_uint_ge(twins, out->triangle_count - SIDES);
    /* on the tube: its sides are straight along its length, so a quarter of its triangles still hold it exactly */
    resurf_compare_report d = tu_compare(m, out, 20000);
    ck_assert_msg(d.hausdorff <= 1e-9 * d.diagonal, "the level is %g of the diagonal from the tube",
                  d.hausdorff / d.diagonal);
    resurf_mesh_free(out);
    resurf_mesh_free(m);
    resurf_mesh_free(body);
}
END_TEST

/* The same tube and fin at 10%. The fin meets the tube along a line of 16 positions where three triangles share
 * each edge (the tube's two and the fin's kept side). Holding that line kept all 16 positions, and the level took
 * its 10% from the rest: 0.53% of the diagonal from the input. Inside a junction line a position now moves along
 * the line: both the tube's sides and the fin's line are straight, so the level reaches its target with the fin
 * kept, as close to the input as rounding. */
START_TEST(simplify_collapses_along_a_junction)
{
    size_t fin;
    resurf_mesh *m = tube_with_fin(&fin);
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.1;
    resurf_simplify_report r;
    resurf_mesh *out = simplify_ok(m, &o, &r);
    ck_assert_int_eq(r.attached_sheets_used, RESURF_SHEETS_KEEP);
    ck_assert_int_eq(r.stop, RESURF_STOP_TARGET);
    ck_assert_uint_le(r.triangles, m->triangle_count / 10);
    resurf_compare_report d = tu_compare(m, out, 20000);
    ck_assert_msg(d.hausdorff <= 1e-9 * d.diagonal, "the level is %g of the diagonal from the input",
                  d.hausdorff / d.diagonal);
    resurf_mesh_free(out);
    resurf_mesh_free(m);
}
END_TEST

/* A pencil: a thin closed hexagonal tube (radius 0.01, length 1) with short cone tips, 100 times longer than wide:
 * a thin feature must keep its length at 10% (its tips' cone planes pin them) whether or not it is restored. The
 * tip guard's own case, a scan's spike whose tip quadrics let shrink over many collapses, is the next test: no
 * small hand-made mesh reproduced it. */
static resurf_mesh *pencil(unsigned rings) { return tube(6, rings, 0.01, 1, 0.01, 0); }

/* A latitude-longitude sphere as exporters write it, each pole a ring of copies: at the north pole cos 0 and sin 0
 * are exact, so its copies are one place; at the south pole sin π is 1.2e-16, so its copies lie a rounding apart.
 * Welded exactly they are a hole whose rim the border guards hold, and the level stops well above its target
 * (weld_tolerance_rel 0); with the default tolerance they are one position: the level reaches 10% and every vertex
 * lies on the unit sphere up to the input's chord sag (restored onto S, without the sag offset). On a
 * finer sphere (32 × 16) the hole's rim shrinks along itself and exact welding reaches 10% too: the coarse levels of
 * small meshes are what the hole holds back. */
static resurf_mesh *lat_long_sphere(unsigned around, unsigned rings)
{
    resurf_mesh *m = NULL;
    size_t nv = (size_t)around * (rings + 1), nt = 2 * (size_t)around * (rings - 1);
    ck_assert_int_eq(resurf_mesh_create(nv, nt, 0, &m, NULL), RESURF_OK);
    for (unsigned j = 0; j <= rings; ++j)
        for (unsigned i = 0; i < around; ++i) {
            double th = M_PI * j / rings, ph = 2 * M_PI * i / around, *p = m->positions + 3 * (j * around + i);
            p[0] = sin(th) * cos(ph), p[1] = cos(th), p[2] = sin(th) * sin(ph);
        }
    size_t t = 0;
    for (unsigned j = 0; j < rings; ++j)
        for (unsigned i = 0; i < around; ++i) {
            uint32_t a = j * around + i, b = j * around + (i + 1) % around;
            uint32_t c = (j + 1) * around + (i + 1) % around, d = (j + 1) * around + i;
            if (j > 0)
                m->indices[3 * t] = a, m->indices[3 * t + 1] = c, m->indices[3 * t + 2] = b, ++t;
            if (j + 1 < rings)
                m->indices[3 * t] = a, m->indices[3 * t + 1] = d, m->indices[3 * t + 2] = c, ++t;
        }
    ck_assert_uint_eq(t, nt);
    return m;
}

START_TEST(simplify_welds_copies_a_rounding_apart)
{
    resurf_mesh *in = lat_long_sphere(16, 8); /* 224 triangles: the level has 22 */
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.1;
    o.restore = RESURF_RESTORE_INLINE;
    o.sag_offset = 0; /* the vertices on S, which lies within the input's chord sag (h²/8 = 0.019) of the sphere */
    size_t target = (size_t)(0.1 * (double)in->triangle_count);
    resurf_simplify_report r;
    resurf_mesh *out = simplify_ok(in, &o, &r);
    ck_assert_int_eq(r.stop, RESURF_STOP_TARGET);
    ck_assert_uint_le(out->triangle_count, target);
    assert_clean(out);
    for (size_t v = 0; v < out->vertex_count; ++v) {
        double l = v3_len(resurfi_position(out, (uint32_t)v));
        ck_assert_msg(fabs(l - 1) < 0.02, "vertex %zu at %.4f from the centre", v, l);
    }
    resurf_mesh_free(out);
    o.weld_tolerance_rel = 0; /* exact copies only */
    out = simplify_ok(in, &o, &r);
    ck_assert_int_eq(r.stop, RESURF_STOP_BLOCKED);
    ck_assert_uint_gt(r.blocked_border, 0);
    ck_assert_uint_gt(out->triangle_count, target + target / 2); /* 36 where 22 are asked */
    resurf_mesh_free(out);
    resurf_mesh_free(in);
}
END_TEST

START_TEST(simplify_keeps_a_pencils_length)
{
    resurf_mesh *m = pencil(60);
    ck_assert_int_eq(validation(m).nonmanifold_edges, 0);
    for (int mode = 0; mode < 2; ++mode) {
        resurf_simplify_options o = resurf_simplify_options_default();
        o.target_ratio = 0.1;
        o.restore = mode ? RESURF_RESTORE_INLINE : RESURF_RESTORE_NONE;
        resurf_simplify_report r;
        resurf_mesh *out = simplify_ok(m, &o, &r);
        ck_assert_uint_le(out->triangle_count, (size_t)(0.1 * m->triangle_count));
        double lo = INFINITY, hi = -INFINITY;
        for (size_t i = 0; i < out->vertex_count; ++i)
            lo = fmin(lo, out->positions[3 * i + 2]), hi = fmax(hi, out->positions[3 * i + 2]);
        ck_assert_msg(hi - lo > 0.95 * 1.02, "restore mode %d: the pencil is %g long of 1.02 (%zu triangles)", mode,
                      hi - lo, out->triangle_count);
        resurf_mesh_free(out);
    }
    resurf_mesh_free(m);
}
END_TEST

/* An antiprism tube of 30 octagons of radius 1, 0.66 apart so that every edge is about 0.765 long: its normals turn
 * by 45° per edge, and S, the smooth surface they describe, rises about 0.076 over the middle of a side, a tenth of
 * an edge, where the circle through the octagon would.
 * Where M's normals turn sharply, restored vertices stay near M: within 0.05 of M's local edge length of the plane
 * of the triangle they were restored on (the rise limit of src/simplify/guards.c), although S rises a tenth of an edge
 * there. Midpoint placement puts new vertices on M's chords, so every one is restored; the straddling offset is off.
 * Asserted against the brute-force distance to M, with 10% to spare: at most 0.05 × 1.1 × the longest edge at a
 * corner of the closest triangle (0.77 on the tube, 1.12 at the cones). */
START_TEST(simplify_restored_vertices_stay_near_sharp_bends)
{
    resurf_mesh *m = tube(8, 30, 1, 0.66 * 29, 0.5, 1);
    ck_assert_int_eq(validation(m).nonmanifold_edges, 0);
    double *longest = calloc(m->vertex_count, sizeof *longest); /* per vertex of M: its longest edge */
    ck_assert_ptr_nonnull(longest);
    for (size_t t = 0; t < m->triangle_count; ++t)
        for (int k = 0; k < 3; ++k) {
            uint32_t a = m->indices[3 * t + k], b = m->indices[3 * t + (k + 1) % 3];
            double l = v3_dist(resurfi_position(m, a), resurfi_position(m, b));
            longest[a] = fmax(longest[a], l), longest[b] = fmax(longest[b], l);
        }
    static const resurf_restore_mode modes[] = {RESURF_RESTORE_INLINE, RESURF_RESTORE_POST};
    for (int i = 0; i < 2; ++i) {
        resurf_simplify_options o = resurf_simplify_options_default();
        o.target_ratio = 0.25;
        o.placement = RESURF_PLACEMENT_MIDPOINT;
        o.restore = modes[i];
        o.sag_offset = 0;
        resurf_simplify_report r;
        resurf_mesh *out = simplify_ok(m, &o, &r);
        ck_assert_uint_le(out->triangle_count, m->triangle_count / 4);
        ck_assert_uint_gt(r.restored, 0);
        double worst = 0; /* distance over the bound */
        for (size_t v = 0; v < out->vertex_count; ++v) {
            vec3 p = resurfi_position(out, (uint32_t)v);
            double d2 = INFINITY;
            size_t near = 0;
            for (size_t t = 0; t < m->triangle_count; ++t) {
                const uint32_t *c = m->indices + 3 * t;
                vec3 q = resurfi_closest_on_triangle(p, resurfi_position(m, c[0]), resurfi_position(m, c[1]),
                                                     resurfi_position(m, c[2]), NULL);
                if (v3_dist2(p, q) < d2)
                    d2 = v3_dist2(p, q), near = t;
            }
            const uint32_t *c = m->indices + 3 * near;
            double edge = fmax(fmax(longest[c[0]], longest[c[1]]), longest[c[2]]);
            worst = fmax(worst, sqrt(d2) / (0.05 * 1.1 * edge));
        }
        ck_assert_msg(worst <= 1, "%s: a vertex %.2f x the bound from M", i ? "post" : "inline", worst);
        resurf_mesh_free(out);
    }
    free(longest);
    resurf_mesh_free(m);
}
END_TEST

/* A thin spike of the Stanford dragon scan (tests/data/dragon-spike.obj, 2,590 triangles). Its tip's triangles lie
 * nearly parallel to its axis, so quadrics price sliding the tip down at almost nothing: without the tip guard the
 * 10% LOD loses the tip (two-sided Hausdorff distance 4.8% of the diagonal), with it 0.7%. Asserted: under 2%. */
START_TEST(simplify_keeps_a_scanned_spike)
{
    resurf_mesh *m = NULL;
    resurf_error e;
    ck_assert_msg(resurf_mesh_load(RESURF_SOURCE_DIR "/tests/data/dragon-spike.obj", NULL, &m, &e) == RESURF_OK, "%s",
                  e.message);
    for (int mode = 0; mode < 2; ++mode) {
        resurf_simplify_options o = resurf_simplify_options_default();
        o.target_ratio = 0.1;
        o.restore = mode ? RESURF_RESTORE_INLINE : RESURF_RESTORE_NONE;
        resurf_simplify_report r;
        resurf_mesh *out = simplify_ok(m, &o, &r);
        ck_assert_uint_le(out->triangle_count, (size_t)(0.1 * m->triangle_count));
        resurf_compare_report d;
        ck_assert_int_eq(resurf_compare(m, out, NULL, &d, NULL, NULL), RESURF_OK);
        ck_assert_msg(d.hausdorff < 0.02 * d.diagonal, "restore mode %d: Hausdorff %g of the diagonal", mode,
                      d.hausdorff / d.diagonal);
        ck_assert_uint_gt(r.blocked_distance, 0);
        resurf_mesh_free(out);
    }
    resurf_mesh_free(m);
}
END_TEST

/* The Stanford bunny (tests/data/bunny.obj, 3,674 triangles, a coarse scan): at an ear's rim the quadric's place
 * lies 0.07 outside M and restoring it onto M pulls the rim in, so M's ear tip ends farther from the level than
 * from `none`'s (two-sided Hausdorff distance over `none`'s without the reach gate 1.09 at 25%, 1.13 at 10%; with
 * it and the sag offset at such a fan's vertices 1.0005 and 0.9994 by resurf_compare's climbed maximum).
 * Asserted against the independent two-sided measure: inline within 1.002 of `none` (the gate), and the default,
 * which keeps the closer of the two per level, not above `none` in Hausdorff distance nor in mean distance
 * (issue 19's target). */
START_TEST(simplify_restored_scan_covers_its_tips)
{
    resurf_mesh *m = NULL;
    resurf_error e;
    ck_assert_msg(resurf_mesh_load(RESURF_SOURCE_DIR "/tests/data/bunny.obj", NULL, &m, &e) == RESURF_OK, "%s",
                  e.message);
    static const double ratios[] = {0.25, 0.1};
    static const resurf_restore_mode modes[3] = {RESURF_RESTORE_NONE, RESURF_RESTORE_INLINE, RESURF_RESTORE_MEASURED};
    for (int i = 0; i < 2; ++i) {
        resurf_compare_report d[3];
        for (int k = 0; k < 3; ++k) {
            resurf_simplify_options o = resurf_simplify_options_default();
            o.target_ratio = ratios[i];
            o.restore = modes[k];
            resurf_simplify_report r;
            resurf_mesh *out = simplify_ok(m, &o, &r);
            ck_assert_int_eq(resurf_compare(m, out, NULL, &d[k], NULL, NULL), RESURF_OK);
            resurf_mesh_free(out);
        }
        ck_assert_msg(d[1].hausdorff <= 1.002 * d[0].hausdorff, "ratio %g: inline Hausdorff %.5g x none's",
                      ratios[i], d[1].hausdorff / d[0].hausdorff);
        ck_assert_msg(d[2].hausdorff <= d[0].hausdorff, "ratio %g: Hausdorff %.5g x none's", ratios[i],
                      d[2].hausdorff / d[0].hausdorff);
        ck_assert_msg(d[2].mean <= d[0].mean, "ratio %g: mean %.5g x none's", ratios[i], d[2].mean / d[0].mean);
    }
    resurf_mesh_free(m);
}
END_TEST

/* A thin notch of the Stanford dragon scan (tests/data/dragon-notch.obj, 2,131 triangles, edges about 0.19 mm near
 * it): at 5%, new edges 2.4–3 mm long, 12 to 16 of M's local edges, span it, and without the bridge guard the
 * triangles over them lie 1.0 mm from M (two-sided Hausdorff distance 8.3% of the diagonal inline, 8.1% post); with
 * it 4.4% and 3.7%. Asserted: under 6%. */
START_TEST(simplify_does_not_bridge_a_notch)
{
    resurf_mesh *m = NULL;
    resurf_error e;
    ck_assert_msg(resurf_mesh_load(RESURF_SOURCE_DIR "/tests/data/dragon-notch.obj", NULL, &m, &e) == RESURF_OK, "%s",
                  e.message);
    static const resurf_restore_mode modes[] = {RESURF_RESTORE_INLINE, RESURF_RESTORE_POST};
    for (int i = 0; i < 2; ++i) {
        resurf_simplify_options o = resurf_simplify_options_default();
        o.target_ratio = 0.05;
        o.restore = modes[i];
        resurf_simplify_report r;
        resurf_mesh *out = simplify_ok(m, &o, &r);
        ck_assert_uint_le(out->triangle_count, (size_t)(0.05 * m->triangle_count));
        resurf_compare_report d;
        ck_assert_int_eq(resurf_compare(m, out, NULL, &d, NULL, NULL), RESURF_OK);
        ck_assert_msg(d.hausdorff < 0.06 * d.diagonal, "%s: Hausdorff %g of the diagonal", i ? "post" : "inline",
                      d.hausdorff / d.diagonal);
        resurf_mesh_free(out);
    }
    resurf_mesh_free(m);
}
END_TEST

START_TEST(simplify_degenerate_and_tiny_inputs)
{
    /* 1 to 4 triangles, with repeated indices, zero-area triangles, duplicated triangles and unused vertices */
    static const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 2, 2, 0, 0.5, 0.5, 0, 9, 9, 9};
    static const uint32_t tris[][12] = {
        {0, 1, 2},                            /* one triangle */
        {0, 1, 2, 1, 3, 2},                   /* a quad */
        {0, 1, 2, 1, 3, 2, 3, 4, 2},          /* a strip */
        {0, 1, 2, 1, 3, 2, 0, 0, 1, 0, 3, 4}, /* a repeated index, a collinear triangle */
        {0, 1, 2, 0, 1, 2, 2, 1, 0, 5, 5, 5}, /* duplicates, both orientations, a point */
        {0, 1, 5, 1, 3, 5, 3, 2, 5, 2, 0, 5}, /* a fan around the centre */
    };
    static const size_t counts[] = {1, 2, 3, 4, 4, 4};
    for (size_t c = 0; c < sizeof counts / sizeof counts[0]; ++c)
        for (int mode = 0; mode < RESURF_RESTORE_MODE_COUNT; ++mode)
            for (int placement = 0; placement < RESURF_PLACEMENT_COUNT; ++placement) {
                resurf_mesh *m = tu_mesh(p, 7, tris[c], counts[c]);
                resurf_simplify_options o = resurf_simplify_options_default();
                o.restore = (resurf_restore_mode)mode;
                o.placement = (resurf_placement)placement;
                resurf_simplify_report r;
                resurf_mesh *out = simplify_ok(m, &o, &r);
                resurf_validate_report v = validation(out);
                ck_assert(resurf_validation_ok(&v));
                ck_assert_uint_eq(v.unreferenced_vertices, 0);
                ck_assert_uint_ge(out->triangle_count, out->triangle_count ? 1 : 0);
                ck_assert_uint_le(out->triangle_count, counts[c]);
                ck_assert_uint_eq(v.degenerate_triangles, 0);
                if (c == 0 || c == 1 || c == 2 || c == 5)
                    ck_assert_uint_ge(out->triangle_count, 1); /* a sheet never vanishes */
                resurf_mesh_free(out);
                resurf_mesh_free(m);
            }
}
END_TEST

START_TEST(simplify_empty_input)
{
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(3, 0, RESURF_ATTR_NORMALS | RESURF_ATTR_TEXCOORD0, &m, NULL), RESURF_OK);
    resurf_simplify_report r;
    resurf_mesh *out = simplify_ok(m, NULL, &r);
    ck_assert_uint_eq(out->triangle_count, 0);
    ck_assert_uint_eq(out->vertex_count, 0);
    ck_assert_ptr_nonnull(out->normals);
    ck_assert_uint_eq(out->texcoord_count, 1);
    ck_assert_uint_eq(r.triangles, 0);
    ck_assert(isnan(r.max_distance));
    resurf_mesh_free(out);
    const double levels[] = {0.5, 0.1};
    resurf_mesh *lods[2];
    ck_assert_int_eq(resurf_simplify_lods(m, levels, 2, NULL, lods, NULL, NULL), RESURF_OK);
    ck_assert_uint_eq(lods[1]->triangle_count, 0);
    resurf_mesh_free(lods[0]);
    resurf_mesh_free(lods[1]);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(simplify_rejects_bad_input_and_options)
{
    resurf_mesh *m = tu_cube();
    resurf_mesh *out = (resurf_mesh *)1;
    resurf_error e;
    ck_assert_int_eq(resurf_simplify(NULL, NULL, &out, NULL, &e), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(out);
    ck_assert_int_eq(resurf_simplify(m, NULL, NULL, NULL, &e), RESURF_ERR_INVALID_ARGUMENT);

    resurf_simplify_options zeroed;
    memset(&zeroed, 0, sizeof zeroed);
    ck_assert_int_eq(resurf_simplify(m, &zeroed, &out, NULL, &e), RESURF_ERR_INVALID_OPTIONS);
    ck_assert_int_eq(e.status, RESURF_ERR_INVALID_OPTIONS);
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 1.5;
    ck_assert_int_eq(resurf_simplify(m, &o, &out, NULL, &e), RESURF_ERR_INVALID_OPTIONS);
    ck_assert(strstr(e.message, "target_ratio"));
    o = resurf_simplify_options_default();
    o.max_normal_change_deg = 0;
    ck_assert_int_eq(resurf_simplify(m, &o, &out, NULL, &e), RESURF_ERR_INVALID_OPTIONS);
    o = resurf_simplify_options_default();
    o.placement = RESURF_PLACEMENT_COUNT;
    ck_assert_int_eq(resurf_simplify(m, &o, &out, NULL, &e), RESURF_ERR_INVALID_OPTIONS);
    o = resurf_simplify_options_default();
    o.attached_sheets = RESURF_SHEETS_COUNT;
    ck_assert_int_eq(resurf_simplify(m, &o, &out, NULL, &e), RESURF_ERR_INVALID_OPTIONS);
    ck_assert(strstr(e.message, "attached_sheets"));
    o = resurf_simplify_options_default();
    o.max_error = NAN;
    ck_assert_int_eq(resurf_simplify(m, &o, &out, NULL, &e), RESURF_ERR_INVALID_OPTIONS);
    for (int k = 0; k < 3; ++k) {
        o = resurf_simplify_options_default();
        o.weld_tolerance_rel = k == 0 ? -1e-9 : k == 1 ? 2e-3 : NAN;
        ck_assert_int_eq(resurf_simplify(m, &o, &out, NULL, &e), RESURF_ERR_INVALID_OPTIONS);
        ck_assert(strstr(e.message, "weld_tolerance_rel"));
    }
    o = resurf_simplify_options_default();
    resurf_restore_options ro;
    memset(&ro, 0, sizeof ro);
    o.restore_options = &ro;
    ck_assert_int_eq(resurf_simplify(m, &o, &out, NULL, &e), RESURF_ERR_INVALID_OPTIONS);
    ck_assert_ptr_null(out);

    m->indices[5] = 8; /* vertex 8 of 8 */
    ck_assert_int_eq(resurf_simplify(m, NULL, &out, NULL, &e), RESURF_ERR_INVALID_MESH);
    ck_assert(strstr(e.message, "triangle 1"));
    m->indices[5] = 1;
    m->positions[4] = NAN;
    ck_assert_int_eq(resurf_simplify(m, NULL, &out, NULL, &e), RESURF_ERR_INVALID_MESH);
    ck_assert(strstr(e.message, "vertex 1"));
    ck_assert_ptr_null(out);
    resurf_mesh_free(m);
}
END_TEST

typedef struct cancel_state {
    int calls, cancel_at;
    resurf_stage stage[64]; /* of the first 64 calls, when counting */
} cancel_state;

static bool cancel_cb(void *user, resurf_stage stage, double fraction)
{
    ck_assert(stage == RESURF_STAGE_PREPARE || stage == RESURF_STAGE_SIMPLIFY || stage == RESURF_STAGE_FINISH);
    ck_assert(fraction >= 0 && fraction <= 1);
    cancel_state *c = user;
    if (c->calls < 64 && c->cancel_at < 0)
        c->stage[c->calls] = stage;
    return c->calls++ == c->cancel_at;
}

/* Cancelled at a progress call, resurf_simplify and resurf_simplify_lods return CANCELLED with no output (and,
 * under the sanitizers and valgrind, free all they held). Each call site is cancelled at: every "prepare" and
 * "finish" call, and "simplify" calls (one site per kind of chunk, all alike but for how far the run got) at its
 * first three, its last and the (2^k)th after the first, so that late ones are few. On the 40k sphere at 20%
 * every "simplify" call follows a parallel chunk (the stars of a pass applied on the threads), on the 4k sphere
 * every one follows a chunk applied in order, on the 10k sphere 39 and 80 of its calls do (counted with a debugger
 * on the two call sites), so both sites are taken; the 10k sphere stands for the 40k one under RESURF_TEST_LIGHT.
 * (Cancelling at every one of the 40k sphere's 134 calls once took 96 s of a loaded machine, 10 minutes under
 * ASan.) */
static void cancel_everywhere(size_t triangles)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, triangles, 0.3, 1, 0);
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.2;
    cancel_state count = {0, -1, {0}};
    o.progress = (resurf_progress){cancel_cb, &count};
    resurf_mesh *out = simplify_ok(m, &o, NULL);
    resurf_mesh_free(out);
    ck_assert_int_ge(count.calls, 20);
    ck_assert_int_eq(count.stage[0], RESURF_STAGE_PREPARE);
    ck_assert_int_eq(count.stage[3], RESURF_STAGE_SIMPLIFY);
    int tried = 0;
    for (int at = 0; at < count.calls; ++at) {
        int simplify_call = at >= 3 && at < count.calls - 2; /* three "prepare" first, two "finish" last */
        unsigned j = (unsigned)(at - 3);
        if (simplify_call && j >= 3 && (j & (j - 1)) != 0 && at != count.calls - 3)
            continue;
        tried++;
        cancel_state c = {0, at, {0}};
        o.progress = (resurf_progress){cancel_cb, &c};
        out = (resurf_mesh *)1;
        resurf_error e;
        ck_assert_int_eq(resurf_simplify(m, &o, &out, NULL, &e), RESURF_ERR_CANCELLED);
        ck_assert_ptr_null(out);
        const double levels[] = {0.5, 0.2};
        resurf_mesh *lods[2] = {(resurf_mesh *)1, (resurf_mesh *)1};
        c = (cancel_state){0, at, {0}};
        ck_assert_int_eq(resurf_simplify_lods(m, levels, 2, &o, lods, NULL, &e), RESURF_ERR_CANCELLED);
        ck_assert_ptr_null(lods[0]);
        ck_assert_ptr_null(lods[1]);
    }
    ck_assert_int_ge(tried, 12);
    resurf_mesh_free(m);
}

/* The measured default's second, plain run still asks the callback (at FINISH 1), so a cancel stops it too: more
 * calls than the inline run alone, and a cancel at the last one returns CANCELLED with no output. */
START_TEST(simplify_measured_plain_run_can_be_cancelled)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 4000, 0.3, 1, 0);
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.2;
    cancel_state inline_calls = {0, -1, {0}}, measured_calls = {0, -1, {0}};
    o.restore = RESURF_RESTORE_INLINE;
    o.progress = (resurf_progress){cancel_cb, &inline_calls};
    resurf_mesh_free(simplify_ok(m, &o, NULL));
    o.restore = RESURF_RESTORE_MEASURED;
    o.progress = (resurf_progress){cancel_cb, &measured_calls};
    resurf_mesh_free(simplify_ok(m, &o, NULL));
    ck_assert_int_gt(measured_calls.calls, inline_calls.calls);
    cancel_state c = {0, measured_calls.calls - 1, {0}};
    o.progress = (resurf_progress){cancel_cb, &c};
    resurf_mesh *out = (resurf_mesh *)1;
    resurf_error e;
    ck_assert_int_eq(resurf_simplify(m, &o, &out, NULL, &e), RESURF_ERR_CANCELLED);
    ck_assert_ptr_null(out);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(simplify_cancel_at_every_step)
{
    cancel_everywhere(tu_light() ? 10000 : 40000);
    cancel_everywhere(4000);
}
END_TEST

/* ---- the command line ---------------------------------------------------------------------------------------- */

START_TEST(simplify_cli_levels_and_json)
{
    char *dir = tu_tempdir();
    char *in = tu_path(dir, "torus.ply"), *out = tu_path(dir, "lod.obj");
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 4000, 0.3, 1, 0);
    ck_assert_int_eq(resurf_mesh_save(m, in, NULL, NULL), RESURF_OK);
    char cmd[4096], *text = NULL;
    snprintf(cmd, sizeof cmd, "%s simplify %s -o %s --levels 0.5,0.1 --json --threads 2", RESURF_CLI, in, out);
    ck_assert_int_eq(tu_run(cmd, &text), 0);
    ck_assert_ptr_nonnull(strstr(text, "\"levels\": ["));
    ck_assert_ptr_nonnull(strstr(text, "lod_lod2.obj"));
    free(text);
    const size_t expect[2] = {m->triangle_count / 2, m->triangle_count / 10};
    for (int level = 1; level <= 2; ++level) {
        char name[32];
        snprintf(name, sizeof name, "lod_lod%d.obj", level);
        char *path = tu_path(dir, name);
        resurf_mesh *lod = NULL;
        ck_assert_int_eq(resurf_mesh_load(path, NULL, &lod, NULL), RESURF_OK);
        ck_assert_uint_le(lod->triangle_count, expect[level - 1]);
        ck_assert_uint_ge(lod->triangle_count + 2, expect[level - 1]);
        resurf_mesh_free(lod);
        free(path);
    }
    ck_assert_int_eq(tu_count_entries(dir), 3); /* torus.ply and the two levels: OUT itself is not written */
    /* one result, text report */
    snprintf(cmd, sizeof cmd, "%s simplify %s -o %s --triangles 300 --restore none --placement midpoint", RESURF_CLI,
             in, out);
    ck_assert_int_eq(tu_run(cmd, &text), 0);
    ck_assert_ptr_nonnull(strstr(text, "stopped by           target"));
    free(text);
    resurf_mesh *lod = NULL;
    ck_assert_int_eq(resurf_mesh_load(out, NULL, &lod, NULL), RESURF_OK);
    ck_assert_uint_le(lod->triangle_count, 300);
    resurf_mesh_free(lod);
    /* usage errors: no target, a bad choice, rising levels; and refusing to overwrite the input */
    snprintf(cmd, sizeof cmd, "%s simplify %s -o %s", RESURF_CLI, in, out);
    ck_assert_int_eq(tu_run(cmd, NULL), 2);
    snprintf(cmd, sizeof cmd, "%s simplify %s -o %s --ratio 0.5 --restore sometimes", RESURF_CLI, in, out);
    ck_assert_int_eq(tu_run(cmd, NULL), 2);
    snprintf(cmd, sizeof cmd, "%s simplify %s -o %s --levels 0.1,0.5", RESURF_CLI, in, out);
    ck_assert_int_eq(tu_run(cmd, NULL), 2);
    snprintf(cmd, sizeof cmd, "%s simplify %s -o %s --ratio 0.5", RESURF_CLI, in, in);
    ck_assert_int_eq(tu_run(cmd, NULL), 1);
    resurf_mesh_free(m);
    free(in);
    free(out);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* Cases that tests/meson.build runs as suites of their own (CK_RUN_CASE), so that each stays short. */
Suite *make_suite(void)
{
    Suite *s = suite_create("simplify");
    TCase *shapes = tcase_create("shapes");
    tcase_add_test(shapes, simplify_tetrahedron_stays);
    tcase_add_test(shapes, simplify_cube_closed_and_oriented);
    tcase_add_test(shapes, simplify_grid_keeps_border_and_area);
    tcase_add_test(shapes, simplify_lock_border_freezes_border);
    tcase_add_test(shapes, simplify_seam_kept_flat);
    tcase_add_test(shapes, simplify_seam_kept_curved);
    tcase_add_test(shapes, simplify_targets_reached);
    tcase_add_test(shapes, simplify_keeps_attribute_layout);
    tcase_add_test(shapes, simplify_midpoint_placement);
    tcase_add_test(shapes, simplify_only_the_targets_set_count);
    tcase_add_test(shapes, simplify_null_restore_options_are_the_defaults);
    suite_add_tcase(s, shapes);
    TCase *levels = tcase_create("levels");
    tcase_add_test(levels, simplify_sphere_lod_vertices_on_sphere);
    tcase_add_test(levels, simplify_lod_chain_restored_onto_original);
    tcase_add_test(levels, simplify_measured_restore_keeps_the_closer_level);
    tcase_add_test(levels, simplify_deterministic_over_threads);
    tcase_add_test(levels, simplify_error_bound_stops);
    tcase_add_test(levels, simplify_min_angle_guard);
    suite_add_tcase(s, levels);
    TCase *guards = tcase_create("guards");
    tcase_add_test(guards, simplify_nonmanifold_input);
    tcase_add_test(guards, simplify_drops_fins);
    tcase_add_test(guards, simplify_keeps_double_sided_sheets);
    tcase_add_test(guards, simplify_chooses_attached_sheets_by_measure);
    tcase_add_test(guards, simplify_sheet_side_follows_the_surface);
    tcase_add_test(guards, simplify_collapses_along_a_junction);
    tcase_add_test(guards, simplify_keeps_a_pencils_length);
    tcase_add_test(guards, simplify_welds_copies_a_rounding_apart);
    tcase_add_test(guards, simplify_keeps_a_scanned_spike);
    tcase_add_test(guards, simplify_restored_scan_covers_its_tips);
    tcase_add_test(guards, simplify_does_not_bridge_a_notch);
    tcase_add_test(guards, simplify_restored_vertices_stay_near_sharp_bends);
    suite_add_tcase(s, guards);
    TCase *hostile = tcase_create("hostile");
    tcase_add_test(hostile, simplify_degenerate_and_tiny_inputs);
    tcase_add_test(hostile, simplify_empty_input);
    tcase_add_test(hostile, simplify_rejects_bad_input_and_options);
    tcase_add_test(hostile, simplify_cancel_at_every_step);
    tcase_add_test(hostile, simplify_measured_plain_run_can_be_cancelled);
    tcase_add_test(hostile, simplify_cli_levels_and_json);
    suite_add_tcase(s, hostile);
    return s;
}

RESURF_TEST_MAIN()
