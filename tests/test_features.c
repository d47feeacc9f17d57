/* Tests for what the simplifier keeps in place (src/simplify/setup.c, collapse.c, output.c): vertices the caller
 * locks, against the input's own coordinates (a locked position is in every level bit-exact), and sharp features
 * against the analytic shapes of tools/shapes.h: a box keeps its corners and its faces flat, a flat panel stays
 * flat, a capped cylinder is no worse than plain edge collapse, while a smooth sphere still gains from
 * restoration. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

/* ---- helpers ------------------------------------------------------------------------------------------------- */

static int cmp_point(const void *a, const void *b)
{
    const double *p = a, *q = b;
    for (int k = 0; k < 3; ++k)
        if (p[k] != q[k])
            return p[k] < q[k] ? -1 : 1;
    return 0;
}

/* The mesh's positions, sorted (for exact look-ups). */
static double *sorted_positions(const resurf_mesh *m)
{
    double *p = malloc(3 * m->vertex_count * sizeof *p);
    ck_assert_ptr_nonnull(p);
    memcpy(p, m->positions, 3 * m->vertex_count * sizeof *p);
    qsort(p, m->vertex_count, 3 * sizeof *p, cmp_point);
    return p;
}

/* How many of the input's vertices v with lock[v] have their exact position among m's. */
static size_t locked_found(const resurf_mesh *in, const uint8_t *lock, const resurf_mesh *m)
{
    double *sorted = sorted_positions(m);
    size_t found = 0;
    for (size_t v = 0; v < in->vertex_count; ++v)
        if (lock[v])
            found += bsearch(in->positions + 3 * v, sorted, m->vertex_count, 3 * sizeof *sorted, cmp_point) != NULL;
    free(sorted);
    return found;
}

/* ---- vertex_lock --------------------------------------------------------------------------------------------- */

/* An irregular sphere (*welded, 2000 triangles) as a triangle soup, three vertices a triangle: each position's
 * second copy moved by `apart` × (1, 2, 3), its third by -apart × (1, 2, 3), the others exact copies. */
static resurf_mesh *sphere_soup(uint64_t seed, double apart, resurf_mesh **welded)
{
    *welded = shape_mesh(SHAPE_SPHERE, 2000, 0.3, seed, 0);
    ck_assert_ptr_nonnull(*welded);
    size_t nt = (*welded)->triangle_count;
    resurf_mesh *soup = NULL;
    ck_assert_int_eq(resurf_mesh_create(3 * nt, nt, 0, &soup, NULL), RESURF_OK);
    unsigned char *copies = calloc((*welded)->vertex_count, 1);
    for (size_t c = 0; c < 3 * nt; ++c) {
        uint32_t v = (*welded)->indices[c];
        unsigned k = copies[v] < 255 ? copies[v]++ : 255;
        double shift = k == 1 ? apart : k == 2 ? -apart : 0;
        for (int a = 0; a < 3; ++a)
            soup->positions[3 * c + a] = (*welded)->positions[3 * (size_t)v + a] + shift * (a + 1);
        soup->indices[c] = (uint32_t)c;
    }
    free(copies);
    return soup;
}

/* Every 7th vertex of an irregular sphere is locked; at 10% with inline restoration and the sag offset (which move
 * every other vertex off the input), with POST restoration, and through a LOD chain, each locked position is in
 * the result bit-exact. Without the lock most of them are gone, so the check can fail. */
START_TEST(vertex_lock_keeps_positions_exactly)
{
    resurf_mesh *in = shape_mesh(SHAPE_SPHERE, tu_light() ? 2000 : 6000, 0.3, 5, 0);
    ck_assert_ptr_nonnull(in);
    uint8_t *lock = calloc(in->vertex_count, 1);
    size_t locked = 0;
    for (size_t v = 0; v < in->vertex_count; v += 7)
        lock[v] = 1, ++locked;
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.1;
    o.measure_samples = 0;
    resurf_mesh *out = NULL;
    resurf_simplify_report r;
    ck_assert_int_eq(resurf_simplify(in, &o, &out, &r, NULL), RESURF_OK);
    size_t free_found = locked_found(in, lock, out);
    ck_assert_msg(free_found < locked / 4, "%zu of %zu kept without a lock", free_found, locked);
    resurf_mesh_free(out);

    o.vertex_lock = lock;
    ck_assert_int_eq(resurf_simplify(in, &o, &out, &r, NULL), RESURF_OK);
    ck_assert_uint_eq(locked_found(in, lock, out), locked);
    ck_assert_uint_gt(r.restored, 0); /* the others were restored: the lock is not restoration switched off */
    ck_assert_uint_le(out->triangle_count, (size_t)(0.25 * (double)in->triangle_count));
    resurf_mesh_free(out);

    o.restore = RESURF_RESTORE_POST;
    ck_assert_int_eq(resurf_simplify(in, &o, &out, &r, NULL), RESURF_OK);
    ck_assert_uint_eq(locked_found(in, lock, out), locked);
    ck_assert_uint_eq(r.restored, out->vertex_count - locked);
    resurf_mesh_free(out);

    o.restore = RESURF_RESTORE_INLINE;
    const double ratios[2] = {0.3, 0.1};
    resurf_mesh *levels[2] = {NULL, NULL};
    ck_assert_int_eq(resurf_simplify_lods(in, ratios, 2, &o, levels, NULL, NULL), RESURF_OK);
    for (int i = 0; i < 2; ++i) {
        ck_assert_uint_eq(locked_found(in, lock, levels[i]), locked);
        resurf_mesh_free(levels[i]);
    }
    free(lock);
    resurf_mesh_free(in);
}
END_TEST

/* A locked vertex is bit-exact also where the weld joins it with copies a rounding apart: the sphere as a soup
 * whose second and third copies of each position are moved by 1e-12 of the diagonal (well within the default
 * weld_tolerance_rel), the second copy of every 5th position locked, so that another place comes first. Each locked
 * place is in the level exactly; the copies still weld (the level reaches its target as the welded sphere does). */
START_TEST(vertex_lock_keeps_its_place_in_a_tolerance_weld)
{
    resurf_mesh *welded = NULL, *soup = sphere_soup(11, 2e-12, &welded);
    size_t nt = welded->triangle_count;
    unsigned char *copies = calloc(welded->vertex_count, 1);
    uint8_t *lock = calloc(3 * nt, 1);
    size_t locked = 0;
    for (size_t c = 0; c < 3 * nt; ++c) { /* the second copy of every 5th position */
        uint32_t v = welded->indices[c];
        if (copies[v]++ == 1 && v % 5 == 0)
            lock[c] = 1, ++locked;
    }
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.1;
    o.measure_samples = 0;
    o.vertex_lock = lock;
    resurf_mesh *out = NULL;
    resurf_simplify_report r;
    ck_assert_int_eq(resurf_simplify(soup, &o, &out, &r, NULL), RESURF_OK);
    ck_assert_uint_eq(locked_found(soup, lock, out), locked);
    ck_assert_uint_le(out->triangle_count, (size_t)(0.25 * (double)nt)); /* welded: not held by the soup's rims */
    resurf_mesh_free(out);
    free(lock);
    free(copies);
    resurf_mesh_free(soup);
    resurf_mesh_free(welded);
}
END_TEST

/* A position is locked when any of its vertices is: the sphere as a triangle soup (three vertices per triangle),
 * one copy of each chosen position locked. */
START_TEST(vertex_lock_one_copy_locks_the_position)
{
    resurf_mesh *welded = NULL, *soup = sphere_soup(9, 0, &welded);
    size_t nt = welded->triangle_count;
    uint8_t *lock = calloc(3 * nt, 1), *chosen = calloc(welded->vertex_count, 1), *seen = calloc(welded->vertex_count, 1);
    for (size_t c = 0; c < 3 * nt; ++c) { /* the first copy of every 5th position */
        uint32_t v = welded->indices[c];
        if (v % 5 == 0 && !seen[v])
            lock[c] = 1, chosen[v] = 1;
        seen[v] = 1;
    }
    size_t locked = 0;
    for (size_t v = 0; v < welded->vertex_count; ++v)
        locked += chosen[v];
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.1;
    o.measure_samples = 0;
    o.vertex_lock = lock;
    resurf_mesh *out = NULL;
    ck_assert_int_eq(resurf_simplify(soup, &o, &out, NULL, NULL), RESURF_OK);
    ck_assert_uint_eq(locked_found(welded, chosen, out), locked);
    resurf_mesh_free(out);
    free(lock);
    free(chosen);
    free(seen);
    resurf_mesh_free(soup);
    resurf_mesh_free(welded);
}
END_TEST

/* ---- features ------------------------------------------------------------------------------------------------ */

static resurf_mesh *simplified(const resurf_mesh *in, double ratio, resurf_restore_mode mode)
{
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = ratio;
    o.restore = mode;
    o.measure_samples = 0;
    resurf_mesh *out = NULL;
    resurf_error e;
    ck_assert_msg(resurf_simplify(in, &o, &out, NULL, &e) == RESURF_OK, "%s", e.message);
    ck_assert_uint_le(out->triangle_count, (size_t)(ratio * (double)in->triangle_count));
    return out;
}

static double hausdorff_rel(const resurf_mesh *ref, const resurf_mesh *test)
{
    resurf_compare_report d = tu_compare(ref, test, 50000);
    return d.hausdorff / d.diagonal;
}

/* Mean distance to the analytic surface over the result's triangles (area-weighted; 10 points each: the corners'
 * Gauss points of a degree-3 rule are not needed, a fixed barycentric pattern is the same for both runs). */
static double true_mean(shape_kind kind, const resurf_mesh *m)
{
    static const double w[6][3] = {{1. / 3, 1. / 3, 1. / 3}, {0.6, 0.2, 0.2}, {0.2, 0.6, 0.2},
                                   {0.2, 0.2, 0.6}, {0.5, 0.5, 0},           {0, 0.5, 0.5}};
    double sum = 0, area_sum = 0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t *i = m->indices + 3 * t;
        vec3 a = resurfi_position(m, i[0]), b = resurfi_position(m, i[1]), c = resurfi_position(m, i[2]);
        double area = 0.5 * v3_len(v3_tri_cross(a, b, c));
        for (int k = 0; k < 6; ++k) {
            vec3 p = v3_add(v3_add(v3_scale(a, w[k][0]), v3_scale(b, w[k][1])), v3_scale(c, w[k][2]));
            double q[3] = {p.x, p.y, p.z};
            sum += area * shape_distance(kind, q) / 6;
        }
        area_sum += area;
    }
    return sum / area_sum;
}

/* The box [−1,1]³ at 10% and 2% (restored inline, the default): its 8 corners are in the result bit-exact and every
 * vertex lies on a face plane (max |coordinate| = 1) to 1e-12 of the diagonal. Before the feature rule the sag
 * offset pushed the vertices of its edges out by up to 1.2% of the diagonal. */
START_TEST(features_cube_keeps_corners_and_flat_faces)
{
    resurf_mesh *in = shape_mesh(SHAPE_CUBE, tu_light() ? 4000 : 12000, 0.3, 3, 0);
    ck_assert_ptr_nonnull(in);
    uint8_t *corner = calloc(in->vertex_count, 1);
    size_t corners = 0;
    for (size_t v = 0; v < in->vertex_count; ++v) {
        const double *p = in->positions + 3 * v;
        if (fabs(p[0]) == 1 && fabs(p[1]) == 1 && fabs(p[2]) == 1)
            corner[v] = 1, ++corners;
    }
    ck_assert_uint_eq(corners, 8);
    const double ratios[2] = {0.1, 0.02};
    for (int r = 0; r < 2; ++r) {
        resurf_mesh *out = simplified(in, ratios[r], RESURF_RESTORE_INLINE);
        ck_assert_uint_eq(locked_found(in, corner, out), 8);
        double worst = 0, diagonal = sqrt(12.0);
        for (size_t v = 0; v < out->vertex_count; ++v) {
            const double *p = out->positions + 3 * v;
            double m = fmax(fabs(p[0]), fmax(fabs(p[1]), fabs(p[2])));
            worst = fmax(worst, fabs(m - 1));
        }
        ck_assert_msg(worst <= 1e-12 * diagonal, "%g%%: a vertex %g of the diagonal off the faces", 100 * ratios[r],
                      worst / diagonal);
        resurf_mesh_free(out);
    }
    free(corner);
    resurf_mesh_free(in);
}
END_TEST

/* A studded plate: n × n square cells of side 1/n (z = 0, open), and every `every`-th cell of every `every`-th row
 * raised by h into a stud with vertical walls, a hard-surface panel's greebles: each stud's 8 vertices are corners
 * of three crease edges. Vertex (i, j) of the plate is j (n + 1) + i; a stud's top corners follow. */
static resurf_mesh *studded_plate(unsigned n, unsigned every, double h)
{
    unsigned studs = (n / every) * (n / every), plate = (n + 1) * (n + 1);
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(plate + 4 * studs, 2 * n * n + 8 * studs, 0, &m, NULL), RESURF_OK);
    for (unsigned j = 0; j <= n; ++j)
        for (unsigned i = 0; i <= n; ++i)
            v3_store(m->positions + 3 * (j * (n + 1) + i), v3((double)i / n, (double)j / n, 0));
    uint32_t *t = m->indices, top = plate;
    for (unsigned j = 0; j < n; ++j)
        for (unsigned i = 0; i < n; ++i) {
            /* the cell's corners counter-clockwise seen from above, on the plate and (a stud) on its top */
            uint32_t c[4] = {j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i};
            uint32_t u[4];
            int stud = i % every == every / 2 && j % every == every / 2 && i / every < n / every &&
                       j / every < n / every;
            for (int k = 0; k < 4; ++k) {
                u[k] = c[k];
                if (stud) {
                    u[k] = top++;
                    v3_store(m->positions + 3 * u[k], v3_add(resurfi_position(m, c[k]), v3(0, 0, h)));
                }
            }
            *t++ = u[0], *t++ = u[1], *t++ = u[2];
            *t++ = u[0], *t++ = u[2], *t++ = u[3];
            for (int k = 0; stud && k < 4; ++k) { /* the wall under edge k, facing out */
                int l = (k + 1) % 4;
                *t++ = c[k], *t++ = c[l], *t++ = u[l];
                *t++ = c[k], *t++ = u[l], *t++ = u[k];
            }
        }
    ck_assert_uint_eq(top, m->vertex_count);
    ck_assert_uint_eq((size_t)(t - m->indices), 3 * m->triangle_count);
    return m;
}

/* The studded plate (40 × 40 cells, 16 studs of height 1/80, the plate's diagonal 1.41) at 10% and 2%: the studs'
 * corners are held only while they are no mere details (features of at most 2% of the diagonal), so the levels reach
 * their targets where the held studs stopped them above 10%, and they lose nothing but studs: within the stud height
 * of the input both ways, and the plate's four corners bit-exact. */
START_TEST(features_small_details_give_way)
{
    const unsigned n = 40;
    const double h = 1.0 / 80;
    resurf_mesh *in = studded_plate(n, 10, h);
    uint8_t *corner = calloc(in->vertex_count, 1);
    for (unsigned k = 0; k < 4; ++k)
        corner[(k & 1 ? n : 0) + (k & 2 ? n * (n + 1) : 0)] = 1;
    const double ratios[2] = {0.1, 0.02};
    for (int r = 0; r < 2; ++r) {
        resurf_mesh *out = simplified(in, ratios[r], RESURF_RESTORE_INLINE); /* asserts the target reached */
        ck_assert_uint_eq(locked_found(in, corner, out), 4);
        resurf_compare_report d = tu_compare(in, out, 50000);
        ck_assert_msg(d.hausdorff <= h * (1 + 1e-9), "%g%%: %g from the input, studs %g high", 100 * ratios[r],
                      d.hausdorff, h);
        resurf_mesh_free(out);
    }
    free(corner);
    resurf_mesh_free(in);
}
END_TEST

/* A flat panel (the plane z = 0 over [−1,1]², open, 4,050 triangles) with 64 small cards floating 0.05 above it (a
 * tuft's hair cards, a model's decals): each card a four-pointed star fanned from its centre, 8 triangles, whose
 * border turns by more than 80° at each of its 8 points and notches, so every border vertex is a corner; held, a
 * card keeps 6 triangles (its centre goes to a notch), 384 in all, more than the 5% level's 228: the level reaches
 * its target only if the cards give way, as parts of at most 2% of the diagonal do once nothing else can be
 * collapsed. The panel's own border corners stay bit-exact (its
 * part is the whole diagonal), and the level lies within a card's size plus its height of the input both ways. */
START_TEST(features_small_parts_give_way)
{
    resurf_mesh *panel = shape_mesh(SHAPE_PLANE, 4000, 0.3, 4, 0), *in = NULL;
    enum { CARDS = 8 * 8, POINTS = 8, CARD_V = POINTS + 1 };
    const double radius = 0.02, notch = 0.05 * radius, lift = 0.05;
    size_t nv = panel->vertex_count, nt = panel->triangle_count;
    ck_assert_int_eq(resurf_mesh_create(nv + CARDS * CARD_V, nt + CARDS * POINTS, 0, &in, NULL), RESURF_OK);
    memcpy(in->positions, panel->positions, 3 * nv * sizeof(double));
    memcpy(in->indices, panel->indices, 3 * nt * sizeof(uint32_t));
    uint32_t *t = in->indices + 3 * nt;
    for (int c = 0; c < CARDS; ++c) {
        vec3 centre = v3(-0.7 + 0.2 * (c % 8), -0.7 + 0.2 * (c / 8), lift);
        uint32_t base = (uint32_t)(nv + (size_t)c * CARD_V); /* the centre, then the rim */
        v3_store(in->positions + 3 * base, centre);
        for (int i = 0; i < POINTS; ++i) {
            double a = 2 * M_PI * i / POINTS, r = i % 2 ? notch : radius;
            v3_store(in->positions + 3 * (base + 1 + (uint32_t)i), v3_add(centre, v3(r * cos(a), r * sin(a), 0)));
            *t++ = base, *t++ = base + 1 + (uint32_t)i, *t++ = base + 1 + (uint32_t)((i + 1) % POINTS);
        }
    }
    ck_assert_ptr_eq(t, in->indices + 3 * in->triangle_count);
    uint8_t *corner = calloc(in->vertex_count, 1);
    for (size_t v = 0; v < nv; ++v)
        corner[v] = fabs(in->positions[3 * v]) == 1 && fabs(in->positions[3 * v + 1]) == 1;
    resurf_mesh *out = simplified(in, 0.05, RESURF_RESTORE_INLINE); /* asserts the target reached */
    ck_assert_uint_eq(locked_found(in, corner, out), 4);
    resurf_compare_report d = tu_compare(in, out, 50000);
    ck_assert_msg(d.hausdorff <= 2 * radius + lift, "%g from the input; a card is %g wide, %g above the panel",
                  d.hausdorff, 2 * radius, lift);
    resurf_mesh_free(out);
    free(corner);
    resurf_mesh_free(in);
    resurf_mesh_free(panel);
}
END_TEST

/* A flat panel (the plane z = 0 over [−1,1]², open) at 10% and 2%: every vertex on z = 0 to 1e-12 of the diagonal,
 * its four border corners bit-exact. */
START_TEST(features_flat_panel_stays_flat)
{
    resurf_mesh *in = shape_mesh(SHAPE_PLANE, tu_light() ? 4000 : 12000, 0.3, 4, 0);
    ck_assert_ptr_nonnull(in);
    uint8_t *corner = calloc(in->vertex_count, 1);
    size_t corners = 0;
    for (size_t v = 0; v < in->vertex_count; ++v)
        if (fabs(in->positions[3 * v]) == 1 && fabs(in->positions[3 * v + 1]) == 1)
            corner[v] = 1, ++corners;
    ck_assert_uint_eq(corners, 4);
    const double ratios[2] = {0.1, 0.02};
    for (int r = 0; r < 2; ++r) {
        resurf_mesh *out = simplified(in, ratios[r], RESURF_RESTORE_INLINE);
        ck_assert_uint_eq(locked_found(in, corner, out), 4);
        double worst = 0;
        for (size_t v = 0; v < out->vertex_count; ++v)
            worst = fmax(worst, fabs(out->positions[3 * v + 2]));
        ck_assert_msg(worst <= 1e-12 * sqrt(8.0), "a vertex %g off the plane", worst);
        resurf_mesh_free(out);
    }
    free(corner);
    resurf_mesh_free(in);
}
END_TEST

/* A piecewise-planar height field: a coarse grid of m × m cells, each split by its diagonal, with heights at its
 * nodes; the input is its fine grid of 4m × 4m cells split the same way, so every fine triangle lies in one coarse
 * facet (an asset subdivided without smoothing, a terrain). Height of the coarse surface at (x, y), in cells. */
static double coarse_height(const double *h, size_t m, double x, double y)
{
    size_t i = x >= (double)m ? m - 1 : (size_t)x, j = y >= (double)m ? m - 1 : (size_t)y;
    double fx = x - (double)i, fy = y - (double)j;
    double h00 = h[j * (m + 1) + i], h10 = h[j * (m + 1) + i + 1];
    double h01 = h[(j + 1) * (m + 1) + i], h11 = h[(j + 1) * (m + 1) + i + 1];
    return fx >= fy ? h00 + fx * (h10 - h00) + fy * (h11 - h10) : h00 + fy * (h01 - h00) + fx * (h11 - h01);
}

/* Simplified to 1/2, 1/4 and 1/8 of its triangles (the coarse grid has 1/16): every vertex of each level stays on the
 * coarse facets to 1e-12 of the diagonal. Where a collapse's place lies on every plane of M it merged, M is exactly
 * there, and restoring onto the smooth S (whose normals bend across the folds) would only leave it: without that
 * rule (collapse.c) vertices were 4e-4 to 1.7e-3 of the diagonal off. */
START_TEST(features_piecewise_flat_stays_on_its_facets)
{
    const size_t m = 8, n = 4 * m;
    double h[(8 + 1) * (8 + 1)];
    for (size_t j = 0; j <= m; ++j)
        for (size_t i = 0; i <= m; ++i)
            h[j * (m + 1) + i] = 0.6 * sin(1.3 * (double)i) * cos(0.7 * (double)j) + 0.05 * (double)(i * j % 3);
    resurf_mesh *in = NULL;
    ck_assert_int_eq(resurf_mesh_create((n + 1) * (n + 1), 2 * n * n, 0, &in, NULL), RESURF_OK);
    for (size_t j = 0; j <= n; ++j)
        for (size_t i = 0; i <= n; ++i) {
            double *p = in->positions + 3 * (j * (n + 1) + i);
            p[0] = (double)i * (double)m / (double)n, p[1] = (double)j * (double)m / (double)n, p[2] = coarse_height(h, m, p[0], p[1]);
        }
    for (size_t j = 0, t = 0; j < n; ++j)
        for (size_t i = 0; i < n; ++i, t += 2) {
            uint32_t v00 = (uint32_t)(j * (n + 1) + i), v10 = v00 + 1, v01 = v00 + (uint32_t)(n + 1), v11 = v01 + 1;
            uint32_t tri[6] = {v00, v10, v11, v00, v11, v01}; /* the coarse grid's diagonal direction */
            memcpy(in->indices + 3 * t, tri, sizeof tri);
        }
    double lo[3], hi[3], diagonal = resurf_mesh_bounds(in, lo, hi);
    const double ratios[3] = {0.5, 0.25, 0.125};
    for (int r = 0; r < 3; ++r) {
        resurf_mesh *out = simplified(in, ratios[r], RESURF_RESTORE_INLINE);
        double worst = 0;
        for (size_t v = 0; v < out->vertex_count; ++v) {
            const double *p = out->positions + 3 * v;
            worst = fmax(worst, fabs(p[2] - coarse_height(h, m, p[0], p[1])));
        }
        ck_assert_msg(worst <= 1e-12 * diagonal, "ratio %g: a vertex %g (%g of the diagonal) off the facets",
                      ratios[r], worst, worst / diagonal);
        resurf_mesh_free(out);
    }
    resurf_mesh_free(in);
}
END_TEST

/* A square [−1,1]² of two materials (OBJ groups), the left half and the right, meeting on the line x = 0. At 10% and
 * 2% the border stays where it was: every triangle of the left group lies in x ≤ 0 and every one of the right in
 * x ≥ 0, and each group keeps its area of 2 (the border's ends, where it meets the square's border, are corners;
 * its inner vertices slide along it). Without the group border as a feature, collapses cross it and both fail. */
START_TEST(features_material_border_stays)
{
    const size_t n = tu_light() ? 24 : 48; /* cells a side, even: x = 0 is a grid line */
    resurf_mesh *in = NULL;
    ck_assert_int_eq(resurf_mesh_create((n + 1) * (n + 1), 2 * n * n, 0, &in, NULL), RESURF_OK);
    for (size_t j = 0; j <= n; ++j)
        for (size_t i = 0; i <= n; ++i) {
            double *p = in->positions + 3 * (j * (n + 1) + i);
            p[0] = -1 + 2.0 * (double)i / (double)n, p[1] = -1 + 2.0 * (double)j / (double)n, p[2] = 0;
        }
    in->triangle_groups = malloc(in->triangle_count * sizeof *in->triangle_groups);
    in->group_names = calloc(2, sizeof *in->group_names);
    ck_assert(in->triangle_groups && in->group_names);
    in->group_names[0] = strdup("left"), in->group_names[1] = strdup("right");
    in->group_count = 2;
    for (size_t j = 0, t = 0; j < n; ++j)
        for (size_t i = 0; i < n; ++i, t += 2) {
            uint32_t a = (uint32_t)(j * (n + 1) + i), b = a + 1, c = a + (uint32_t)n + 1, d = c + 1;
            /* alternate diagonals, so no line but the grid's is special */
            const uint32_t q[6] = {a, b, (i + j) % 2 ? c : d, (i + j) % 2 ? b : a, d, c};
            memcpy(in->indices + 3 * t, q, sizeof q);
            in->triangle_groups[t] = in->triangle_groups[t + 1] = i < n / 2 ? 0 : 1;
        }
    const double ratios[2] = {0.1, 0.02};
    for (int r = 0; r < 2; ++r) {
        resurf_mesh *out = simplified(in, ratios[r], RESURF_RESTORE_INLINE);
        ck_assert_ptr_nonnull(out->triangle_groups);
        double area[2] = {0, 0}, wrong_side = 0;
        for (size_t t = 0; t < out->triangle_count; ++t) {
            const uint32_t *i = out->indices + 3 * t, g = out->triangle_groups[t];
            const double *p0 = out->positions + 3 * (size_t)i[0], *p1 = out->positions + 3 * (size_t)i[1],
                         *p2 = out->positions + 3 * (size_t)i[2];
            area[g] += 0.5 * ((p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1]));
            for (int k = 0; k < 3; ++k) {
                double x = out->positions[3 * (size_t)i[k]];
                wrong_side = fmax(wrong_side, g == 0 ? x : -x);
            }
        }
        ck_assert_msg(wrong_side <= 1e-12, "%g%%: a vertex %g across the material border", 100 * ratios[r],
                      wrong_side);
        ck_assert_msg(fabs(area[0] - 2) <= 1e-12 && fabs(area[1] - 2) <= 1e-12, "%g%%: areas %.15g and %.15g",
                      100 * ratios[r], area[0], area[1]);
        resurf_mesh_free(out);
    }
    resurf_mesh_free(in);
}
END_TEST

/* CAD-like analytic parts: the default (inline restoration, sag offset) against --restore none in two-sided
 * Hausdorff distance at 10% and 2%: no worse on the box (both keep it exactly), within 10% on the capped cylinder
 * (measured 1.08x at 10%, 1.00x at 2%: the target of 1.0x is not met there yet). Before the feature rule the
 * default was 40x worse on the capped cylinder (2.4% of the diagonal against 0.06%). */
START_TEST(features_parts_no_worse_than_no_restoration)
{
    const shape_kind kinds[2] = {SHAPE_CAPPED_CYLINDER, SHAPE_CUBE};
    const double bound[2] = {1.1, 1.0};
    const double ratios[2] = {0.1, 0.02};
    for (int k = 0; k < 2; ++k) {
        resurf_mesh *in = shape_mesh(kinds[k], tu_light() ? 8000 : 20000, 0.3, 1, 0);
        ck_assert_ptr_nonnull(in);
        for (int r = 0; r < 2; ++r) {
            resurf_mesh *none = simplified(in, ratios[r], RESURF_RESTORE_NONE);
            resurf_mesh *inline_ = simplified(in, ratios[r], RESURF_RESTORE_INLINE);
            double hn = hausdorff_rel(in, none), hi = hausdorff_rel(in, inline_);
            ck_assert_msg(hi <= hn * bound[k] + 1e-12, "%s at %g%%: inline %g, none %g", shape_name(kinds[k]),
                          100 * ratios[r], hi, hn);
            resurf_mesh_free(none);
            resurf_mesh_free(inline_);
        }
        resurf_mesh_free(in);
    }
}
END_TEST

/* The sag offset on an anisotropic level: quadric collapses on the capped cylinder's wall go along its axis first,
 * so at 10% the level keeps much of M's spacing around the axis and its facets lie under S by about as much as M's.
 * The offset, the LOD's facet depth less M's own there (docs/restoring.md §8), then leaves such vertices nearly
 * where they are, and the default's two-sided mean distance to M is no worse than plain edge collapse's: measured
 * 0.93x at 10% and 0.92x at 2% (20k triangles). The earlier rule, M's sag along the LOD's edge (a factor
 * 1 − h_M²/h² per edge), raised every wall vertex and measured 1.03x at 10%. The light run takes 20k too: at 12k the
 * jitter flips a triangle of a cap, a fold whose planes the quadric holds (FOLD_COS in src/simplify/setup.c), which
 * helps plain collapse more than the default there (2%: 0.94x before the fold rule, 1.015x with it). */
START_TEST(features_sag_offset_no_worse_on_a_cylinder)
{
    resurf_mesh *in = shape_mesh(SHAPE_CAPPED_CYLINDER, 20000, 0.3, 1, 0);
    ck_assert_ptr_nonnull(in);
    const double ratios[2] = {0.1, 0.02};
    for (int r = 0; r < 2; ++r) {
        resurf_mesh *none = simplified(in, ratios[r], RESURF_RESTORE_NONE);
        resurf_mesh *inline_ = simplified(in, ratios[r], RESURF_RESTORE_INLINE);
        double mn = tu_compare(in, none, 50000).mean, mi = tu_compare(in, inline_, 50000).mean;
        ck_assert_msg(mi <= mn, "at %g%%: inline %g, none %g", 100 * ratios[r], mi, mn);
        resurf_mesh_free(none);
        resurf_mesh_free(inline_);
    }
    resurf_mesh_free(in);
}
END_TEST

/* The smooth sphere still gains from restoration: at 10% its true-surface mean is under 0.8x that of plain edge
 * collapse (measured about 0.7x). */
START_TEST(features_sphere_still_gains)
{
    resurf_mesh *in = shape_mesh(SHAPE_SPHERE, tu_light() ? 8000 : 20000, 0.3, 1, 0);
    ck_assert_ptr_nonnull(in);
    resurf_mesh *none = simplified(in, 0.1, RESURF_RESTORE_NONE);
    resurf_mesh *inline_ = simplified(in, 0.1, RESURF_RESTORE_INLINE);
    double mn = true_mean(SHAPE_SPHERE, none), mi = true_mean(SHAPE_SPHERE, inline_);
    ck_assert_msg(mi < 0.8 * mn, "inline %g, none %g", mi, mn);
    resurf_mesh_free(none);
    resurf_mesh_free(inline_);
    resurf_mesh_free(in);
}
END_TEST

/* A curved crease is restored along itself (docs/restoring.md §8, "along the curve"): the capped cylinder's level
 * keeps its rim vertices on the analytic rim circles (x² + y² = 1, z = ±1), not on M's chords between them. The
 * vertices of the level within a quarter of M's rim spacing h of a rim are its rim vertices; M's own chords sag
 * h²/8 under the circle, and a vertex left on one (the quadric's place on the segment, as before the rule) lies
 * about that far inside. Measured at 20k triangles, as fractions of that sag: median distance to the circle 8e-6 at
 * 25% and 1e-4 at 10% (before the rule 0.084 and 0.64), mean 0.025 and 0.14 (before 0.145 and 0.63); the few left
 * off are vertices that touch the rim without being crease vertices (one feature edge), which the quadric places. */
static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

START_TEST(features_crease_vertices_on_the_rim)
{
    resurf_mesh *in = shape_mesh(SHAPE_CAPPED_CYLINDER, tu_light() ? 12000 : 20000, 0.3, 1, 0);
    ck_assert_ptr_nonnull(in);
    size_t rim = 0; /* M's vertices on the two rims */
    for (size_t v = 0; v < in->vertex_count; ++v) {
        const double *p = in->positions + 3 * v;
        rim += fabs(hypot(p[0], p[1]) - 1) < 1e-12 && fabs(fabs(p[2]) - 1) < 1e-12;
    }
    ck_assert_uint_gt(rim, 100);
    double h = 2 * M_PI / (0.5 * (double)rim), sag = h * h / 8;
    const double ratios[2] = {0.25, 0.1};
    for (int r = 0; r < 2; ++r) {
        resurf_mesh *out = simplified(in, ratios[r], RESURF_RESTORE_INLINE);
        double *d = malloc(out->vertex_count * sizeof *d), sum = 0;
        ck_assert_ptr_nonnull(d);
        size_t n = 0;
        for (size_t v = 0; v < out->vertex_count; ++v) {
            const double *p = out->positions + 3 * v;
            double e = hypot(hypot(p[0], p[1]) - 1, fabs(p[2]) - 1);
            if (e < 0.25 * h)
                sum += d[n++] = e;
        }
        ck_assert_msg(n >= 20, "%g%%: %zu rim vertices", 100 * ratios[r], n);
        qsort(d, n, sizeof *d, cmp_double);
        double median = d[n / 2], mean = sum / (double)n;
        ck_assert_msg(median <= 0.01 * sag && mean <= 0.3 * sag, "%g%%: rim vertices off the circle by %g (median), %g "
                      "(mean); M's chord sag %g", 100 * ratios[r], median, mean, sag);
        free(d);
        resurf_mesh_free(out);
    }
    resurf_mesh_free(in);
}
END_TEST

/* A flat-shaded mesh: every triangle with its own vertices, each carrying the triangle's unit normal (as an STL
 * export, or any flat-shaded asset, writes them). */
static resurf_mesh *flat_shaded(const resurf_mesh *welded)
{
    size_t nt = welded->triangle_count;
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(3 * nt, nt, RESURF_ATTR_NORMALS, &m, NULL), RESURF_OK);
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *i = welded->indices + 3 * t;
        vec3 n = v3_normalize(v3_tri_cross(resurfi_position(welded, i[0]), resurfi_position(welded, i[1]),
                                           resurfi_position(welded, i[2])));
        for (int k = 0; k < 3; ++k) {
            memcpy(m->positions + 3 * (3 * t + k), welded->positions + 3 * (size_t)i[k], 3 * sizeof(double));
            v3_store(m->normals + 3 * (3 * t + k), n);
            m->indices[3 * t + k] = (uint32_t)(3 * t + k);
        }
    }
    return m;
}

/* The largest angle (degrees) between a corner's normal and its triangle's normal. */
static double worst_corner_vs_face_deg(const resurf_mesh *m)
{
    double worst = 0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t *i = m->indices + 3 * t;
        vec3 f = v3_normalize(v3_tri_cross(resurfi_position(m, i[0]), resurfi_position(m, i[1]),
                                           resurfi_position(m, i[2])));
        for (int k = 0; k < 3; ++k) {
            double c = v3_dot(f, v3_normalize(v3_load(m->normals + 3 * (size_t)i[k])));
            double deg = acos(c > 1 ? 1 : c < -1 ? -1 : c) * 180 / M_PI;
            worst = deg > worst ? deg : worst;
        }
    }
    return worst;
}

/* A flat-shaded sphere splits its normals at every edge, so every edge is a normal seam. Such normals are the
 * faces' own (src/simplify/facets.c): at 10% the level is what the same triangles without normals give, position
 * for position, and it is shaded flat again (every corner's normal its face's, to 1e-3 degrees). The same sphere
 * shaded smooth keeps smooth normals (within 2° of the true radial one, where a face's normal is up to ~6° off). */
START_TEST(features_flat_shaded_mesh_is_simplified_and_stays_flat)
{
    resurf_mesh *welded = shape_mesh(SHAPE_SPHERE, tu_light() ? 4000 : 8000, 0.3, 1, 0);
    ck_assert_ptr_nonnull(welded);
    resurf_mesh *flat = flat_shaded(welded), *bare = NULL;
    ck_assert_int_eq(resurf_mesh_clone(flat, &bare, NULL), RESURF_OK);
    free(bare->normals);
    bare->normals = NULL;
    resurf_mesh *flat_out = simplified(flat, 0.1, RESURF_RESTORE_INLINE);
    resurf_mesh *bare_out = simplified(bare, 0.1, RESURF_RESTORE_INLINE);
    ck_assert_uint_eq(flat_out->triangle_count, bare_out->triangle_count);
    for (size_t c = 0; c < 3 * flat_out->triangle_count; ++c)
        for (int k = 0; k < 3; ++k)
            ck_assert_double_eq(flat_out->positions[3 * (size_t)flat_out->indices[c] + k],
                                bare_out->positions[3 * (size_t)bare_out->indices[c] + k]);
    double worst = worst_corner_vs_face_deg(flat_out);
    ck_assert_msg(worst < 1e-3, "a corner's normal is %g degrees off its face's", worst);

    resurf_mesh *smooth = shape_mesh(SHAPE_SPHERE, tu_light() ? 4000 : 8000, 0.3, 1, 1);
    ck_assert_ptr_nonnull(smooth);
    resurf_mesh *smooth_out = simplified(smooth, 0.1, RESURF_RESTORE_INLINE);
    double off = 0, face_off = worst_corner_vs_face_deg(smooth_out);
    for (size_t v = 0; v < smooth_out->vertex_count; ++v) {
        vec3 n = v3_normalize(v3_load(smooth_out->normals + 3 * v)), r = v3_normalize(resurfi_position(smooth_out, (uint32_t)v));
        double c = v3_dot(n, r), deg = acos(c > 1 ? 1 : c) * 180 / M_PI;
        off = deg > off ? deg : off;
    }
    ck_assert_msg(off < 2 && face_off > 4, "smooth normals %g degrees off radial, %g off the faces", off, face_off);
    resurf_mesh_free(smooth_out);
    resurf_mesh_free(smooth);
    resurf_mesh_free(flat_out);
    resurf_mesh_free(bare_out);
    resurf_mesh_free(flat);
    resurf_mesh_free(bare);
    resurf_mesh_free(welded);
}
END_TEST

/* A fin modelled as two sheets: the unit disk in z = 0 seen from above (a polar grid, counter-clockwise from +z)
 * and from below (the same rings turned by half a step, wound the other way), sharing only the rim and the centre.
 * Every rim edge folds the surface back by 180°. */
static resurf_mesh *two_sheet_disk(unsigned rings, unsigned spokes)
{
    size_t nv = 1 + (size_t)spokes * (2 * rings - 1), nt = 2 * (size_t)spokes * (2 * rings - 1);
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(nv, nt, 0, &m, NULL), RESURF_OK);
    /* vertex 0: the centre; sheet s (0 top, 1 bottom), ring k (1..rings), spoke j; the rim (k = rings) is shared */
#define DISK_V(sh, k, j) ((k) == rings ? 1 + (uint32_t)((j) % spokes) \
                                       : 1 + spokes + (uint32_t)(((sh) * (rings - 1) + (k) - 1) * spokes + (j) % spokes))
    for (int sh = 0; sh < 2; ++sh)
        for (unsigned k = 1; k <= rings; ++k)
            for (unsigned j = 0; j < spokes; ++j) {
                double r = (double)k / rings, a = 2 * M_PI * (j + (sh && k < rings ? 0.5 : 0)) / spokes;
                double *p = m->positions + 3 * (size_t)DISK_V(sh, k, j);
                p[0] = r * cos(a), p[1] = r * sin(a), p[2] = 0;
            }
    size_t t = 0;
    for (int sh = 0; sh < 2; ++sh)
        for (unsigned k = 0; k < rings; ++k)
            for (unsigned j = 0; j < spokes; ++j) {
                /* ring k to ring k + 1; on the bottom sheet ring k is turned by half a step when 0 < k < rings */
                uint32_t q[2][2];
                for (int d = 0; d < 2; ++d)
                    for (int e = 0; e < 2; ++e)
                        q[d][e] = k + d == 0 ? 0 : DISK_V(sh, k + d, j + e);
                uint32_t tri[2][3] = {{q[0][0], q[1][0], q[1][1]}, {q[0][0], q[1][1], q[0][1]}};
                for (int u = 0; u < 2; ++u) {
                    if (k == 0 && u == 1)
                        continue; /* the centre's fan: one triangle a spoke */
                    uint32_t *i = m->indices + 3 * t++;
                    i[0] = tri[u][0], i[1] = sh ? tri[u][2] : tri[u][1], i[2] = sh ? tri[u][1] : tri[u][2];
                }
            }
#undef DISK_V
    m->triangle_count = t;
    return m;
}

/* The fin keeps its outline: the two sheets' planes are one plane and cannot hold the rim, so each folding rim edge
 * adds the planes through it across its triangles (FOLD_COS in src/simplify/setup.c). At 25% the interior goes and
 * the rim stays: the level's two-sided Hausdorff distance to the input is within 1e-12 of the diagonal, with or
 * without restoration (measured 1e-15; without the rule the rim is cut by chords at no cost, 2.6%). */
START_TEST(features_folded_fin_keeps_its_outline)
{
    resurf_mesh *in = two_sheet_disk(12, 64);
    ck_assert_uint_eq(in->triangle_count, 2 * 64 * 23);
    for (int mode = 0; mode < 2; ++mode) {
        resurf_mesh *out = simplified(in, 0.25, mode ? RESURF_RESTORE_INLINE : RESURF_RESTORE_NONE);
        double h = hausdorff_rel(in, out);
        ck_assert_msg(h < 1e-12, "restore %s: Hausdorff %g of the diagonal", mode ? "inline" : "none", h);
        resurf_mesh_free(out);
    }
    resurf_mesh_free(in);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("features");
    TCase *lock = tcase_create("lock");
    tcase_add_test(lock, vertex_lock_keeps_positions_exactly);
    tcase_add_test(lock, vertex_lock_one_copy_locks_the_position);
    tcase_add_test(lock, vertex_lock_keeps_its_place_in_a_tolerance_weld);
    suite_add_tcase(s, lock);
    TCase *features = tcase_create("features");
    tcase_add_test(features, features_cube_keeps_corners_and_flat_faces);
    tcase_add_test(features, features_flat_panel_stays_flat);
    tcase_add_test(features, features_piecewise_flat_stays_on_its_facets);
    tcase_add_test(features, features_material_border_stays);
    tcase_add_test(features, features_parts_no_worse_than_no_restoration);
    tcase_add_test(features, features_sag_offset_no_worse_on_a_cylinder);
    tcase_add_test(features, features_sphere_still_gains);
    tcase_add_test(features, features_crease_vertices_on_the_rim);
    tcase_add_test(features, features_flat_shaded_mesh_is_simplified_and_stays_flat);
    tcase_add_test(features, features_folded_fin_keeps_its_outline);
    tcase_add_test(features, features_small_details_give_way);
    tcase_add_test(features, features_small_parts_give_way);
    suite_add_tcase(s, features);
    return s;
}

RESURF_TEST_MAIN()
