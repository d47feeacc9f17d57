/* Attributes in the simplifier's cost (src/simplify/attributes.c) and on the seams (output.c's find_sides),
 * checked against analytic truth: meshes whose texture coordinates and colours are known functions of the
 * position, so the level's interpolated values can be compared with the exact ones anywhere on its surface. */
#include <math.h>
#include <stdlib.h>

#include "testutil.h"

/* A texture coordinate with a strong gradient region: its slope runs from 0.1 (x = 0, 1) to 1.9 (x = 0.5). */
static double warp(double x) { return x - 0.9 * sin(2 * M_PI * x) / (2 * M_PI); }
/* A colour with a sharp edge along x = 0.5. */
static double edge(double x) { return 0.5 * (1 + tanh((x - 0.5) / 0.04)); }

/* An n × n grid on [0,1]² lifted to the gentle paraboloid z = 0.15 (x² + y²), with u = warp(x), v = y and the red
 * channel edge(x). */
static resurf_mesh *graded_grid(unsigned n)
{
    resurf_mesh *m = NULL;
    size_t nv = (size_t)(n + 1) * (n + 1);
    ck_assert_int_eq(resurf_mesh_create_with(nv, 2 * (size_t)n * n, RESURF_ATTR_TEXCOORD0 | RESURF_ATTR_COLORS, NULL,
                                             &m, NULL),
                     RESURF_OK);
    m->texcoord_count = 1;
    for (unsigned j = 0; j <= n; ++j)
        for (unsigned i = 0; i <= n; ++i) {
            size_t v = (size_t)j * (n + 1) + i;
            double x = (double)i / n, y = (double)j / n;
            m->positions[3 * v] = x, m->positions[3 * v + 1] = y, m->positions[3 * v + 2] = 0.15 * (x * x + y * y);
            m->texcoords[0][2 * v] = warp(x), m->texcoords[0][2 * v + 1] = y;
            m->colors[4 * v] = edge(x), m->colors[4 * v + 1] = 0, m->colors[4 * v + 2] = 0, m->colors[4 * v + 3] = 1;
        }
    uint32_t *t = m->indices;
    for (unsigned j = 0; j < n; ++j)
        for (unsigned i = 0; i < n; ++i) {
            uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
            *t++ = a, *t++ = b, *t++ = c;
            *t++ = a, *t++ = c, *t++ = d;
        }
    return m;
}

/* The area-weighted mean, over a fixed pattern of points of every triangle of m, of the distance between m's
 * interpolated texcoords (texcoords = 1) or red channel (0) and the truth at the point's x, y. */
static double attribute_error(const resurf_mesh *m, int texcoords)
{
    static const double pattern[][2] = {{1 / 3.0, 1 / 3.0}, {0.6, 0.2}, {0.2, 0.6}, {0.2, 0.2}, {0.45, 0.1},
                                        {0.1, 0.45}, {0.45, 0.45}, {0.8, 0.1}, {0.1, 0.8}, {0.1, 0.1}};
    double sum = 0, area = 0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t *idx = m->indices + 3 * t;
        vec3 p0 = resurfi_position(m, idx[0]), p1 = resurfi_position(m, idx[1]), p2 = resurfi_position(m, idx[2]);
        double a = 0.5 * v3_len(v3_tri_cross(p0, p1, p2));
        for (size_t k = 0; k < sizeof pattern / sizeof *pattern; ++k) {
            double w[3] = {1 - pattern[k][0] - pattern[k][1], pattern[k][0], pattern[k][1]};
            double x = 0, y = 0, u = 0, v = 0, r = 0;
            for (int c = 0; c < 3; ++c) {
                x += w[c] * m->positions[3 * idx[c]];
                y += w[c] * m->positions[3 * idx[c] + 1];
                if (texcoords)
                    u += w[c] * m->texcoords[0][2 * idx[c]], v += w[c] * m->texcoords[0][2 * idx[c] + 1];
                else
                    r += w[c] * m->colors[4 * idx[c]];
            }
            sum += a * (texcoords ? hypot(u - warp(x), v - y) : fabs(r - edge(x)));
        }
        area += a * (double)(sizeof pattern / sizeof *pattern);
    }
    return sum / area;
}

/* Simplifies m to `ratio` with the given weights; returns the level. */
static resurf_mesh *simplified(const resurf_mesh *m, double ratio, double texcoord_weight, double color_weight)
{
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = ratio;
    o.normal_weight = 0;
    o.texcoord_weight = texcoord_weight;
    o.color_weight = color_weight;
    o.measure_samples = 0;
    resurf_mesh *out = NULL;
    resurf_error e;
    ck_assert_msg(resurf_simplify(m, &o, &out, NULL, &e) == RESURF_OK, "%s", e.message);
    return out;
}

static unsigned grid_size(void) { return tu_light() ? 24 : 48; }

START_TEST(texcoords_in_the_cost_follow_the_gradient)
{
    resurf_mesh *m = graded_grid(grid_size());
    resurf_mesh *off = simplified(m, 0.1, 0, 0), *on = simplified(m, 0.1, 1, 0);
    double e_off = attribute_error(off, 1), e_on = attribute_error(on, 1);
    ck_assert_msg(e_on < 0.5 * e_off, "UV error with the weight %g, without %g", e_on, e_off);
    /* the default weight helps too */
    resurf_simplify_options d = resurf_simplify_options_default();
    resurf_mesh *def = simplified(m, 0.1, d.texcoord_weight, 0);
    double e_def = attribute_error(def, 1);
    ck_assert_msg(e_def < e_off, "UV error with the default weight %g, without %g", e_def, e_off);
    resurf_mesh_free(def);
    resurf_mesh_free(on);
    resurf_mesh_free(off);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(colours_in_the_cost_keep_their_edge)
{
    resurf_mesh *m = graded_grid(grid_size());
    resurf_mesh *off = simplified(m, 0.1, 0, 0), *on = simplified(m, 0.1, 0, 1);
    double e_off = attribute_error(off, 0), e_on = attribute_error(on, 0);
    ck_assert_msg(e_on < 0.5 * e_off, "colour error with the weight %g, without %g", e_on, e_off);
    resurf_mesh_free(on);
    resurf_mesh_free(off);
    resurf_mesh_free(m);
}
END_TEST

/* An open cylinder x² + y² = 1, z in [−1, 1], of nth × nz quads, u = θ / 2π, v = (z + 1) / 2, with its UV seam at
 * θ = 0: the column of vertices there is doubled, u = 0 on one side and u = 1 on the other. The seam does not cut
 * the chart in two: both sides are one chart. */
static resurf_mesh *seamed_cylinder(unsigned nth, unsigned nz)
{
    resurf_mesh *m = NULL;
    size_t nv = (size_t)(nth + 1) * (nz + 1);
    ck_assert_int_eq(resurf_mesh_create_with(nv, 2 * (size_t)nth * nz, RESURF_ATTR_TEXCOORD0, NULL, &m, NULL),
                     RESURF_OK);
    m->texcoord_count = 1;
    for (unsigned j = 0; j <= nz; ++j)
        for (unsigned i = 0; i <= nth; ++i) {
            size_t v = (size_t)j * (nth + 1) + i;
            double th = 2 * M_PI * (i % nth) / nth, z = -1 + 2.0 * j / nz;
            m->positions[3 * v] = cos(th), m->positions[3 * v + 1] = sin(th), m->positions[3 * v + 2] = z;
            m->texcoords[0][2 * v] = (double)i / nth, m->texcoords[0][2 * v + 1] = 0.5 * (z + 1);
        }
    uint32_t *t = m->indices;
    for (unsigned j = 0; j < nz; ++j)
        for (unsigned i = 0; i < nth; ++i) {
            uint32_t a = j * (nth + 1) + i, b = a + 1, c = a + nth + 2, d = a + nth + 1;
            *t++ = a, *t++ = b, *t++ = c;
            *t++ = a, *t++ = c, *t++ = d;
        }
    return m;
}

START_TEST(a_uv_seam_stays_a_seam)
{
    unsigned nth = tu_light() ? 32 : 96, nz = tu_light() ? 12 : 32;
    resurf_mesh *m = seamed_cylinder(nth, nz);
    double ratios[2] = {0.25, 0.1};
    resurf_mesh *levels[2] = {NULL, NULL};
    resurf_simplify_options o = resurf_simplify_options_default();
    o.measure_samples = 0;
    resurf_error e;
    ck_assert_msg(resurf_simplify_lods(m, ratios, 2, &o, levels, NULL, &e) == RESURF_OK, "%s", e.message);
    for (int l = 0; l < 2; ++l) {
        const resurf_mesh *r = levels[l];
        /* No triangle interpolates across the seam: its corners' u all lie on one side of it. */
        for (size_t t = 0; t < r->triangle_count; ++t) {
            double lo = 1, hi = 0;
            for (int c = 0; c < 3; ++c) {
                double u = r->texcoords[0][2 * r->indices[3 * t + c]];
                lo = u < lo ? u : lo, hi = u > hi ? u : hi;
            }
            ck_assert_msg(hi - lo < 0.5, "level %d: triangle %zu spans u %g .. %g", l + 1, t, lo, hi);
        }
        /* Every vertex on the seam curve keeps its side's values: u = 0 or 1, v the input's at its height; and the
         * seam's positions carry both sides. */
        size_t on_seam = 0, low = 0, high = 0;
        for (size_t v = 0; v < r->vertex_count; ++v) {
            const double *p = r->positions + 3 * v, *uv = r->texcoords[0] + 2 * v;
            if (fabs(atan2(p[1], p[0])) > 1e-9)
                continue;
            ++on_seam;
            low += fabs(uv[0]) < 1e-9, high += fabs(uv[0] - 1) < 1e-9;
            ck_assert_msg(fabs(uv[0]) < 1e-9 || fabs(uv[0] - 1) < 1e-9, "level %d: u %g on the seam", l + 1, uv[0]);
            ck_assert_msg(fabs(uv[1] - 0.5 * (p[2] + 1)) < 1e-3, "level %d: v %g at z %g", l + 1, uv[1], p[2]);
        }
        ck_assert_msg(on_seam >= 4 && low == high, "level %d: %zu seam vertices, %zu at u = 0, %zu at u = 1", l + 1,
                      on_seam, low, high);
        resurf_mesh_free(levels[l]);
    }
    resurf_mesh_free(m);
}
END_TEST

/* The same cylinder when no texture samples its texcoords (unsampled_texcoords, which resurf_scene_build_lods sets
 * from the materials): the seam holds nothing back. Every level has one vertex per position (nothing split: the
 * seamed run above keeps both sides of the seam apart), still carries texcoords, each within the input's range,
 * and its surface is no farther from the input than the seamed level's. */
START_TEST(an_unsampled_seam_holds_nothing)
{
    unsigned nth = tu_light() ? 32 : 96, nz = tu_light() ? 12 : 32;
    resurf_mesh *m = seamed_cylinder(nth, nz);
    double ratios[2] = {0.25, 0.1};
    resurf_mesh *free_levels[2] = {NULL, NULL}, *seamed[2] = {NULL, NULL};
    resurf_simplify_options o = resurf_simplify_options_default();
    resurf_error e;
    ck_assert_msg(resurf_simplify_lods(m, ratios, 2, &o, seamed, NULL, &e) == RESURF_OK, "%s", e.message);
    o.unsampled_texcoords = 1;
    ck_assert_msg(resurf_simplify_lods(m, ratios, 2, &o, free_levels, NULL, &e) == RESURF_OK, "%s", e.message);
    for (int l = 0; l < 2; ++l) {
        const resurf_mesh *r = free_levels[l];
        ck_assert_ptr_nonnull(r->texcoords[0]);
        uint32_t *remap = malloc(r->vertex_count * sizeof *remap);
        size_t positions = 0;
        ck_assert_int_eq(resurfi_weld_exact(NULL, r->positions, r->vertex_count, remap, &positions), RESURF_OK);
        ck_assert_uint_eq(positions, r->vertex_count);
        free(remap);
        for (size_t v = 0; v < 2 * r->vertex_count; ++v)
            ck_assert(r->texcoords[0][v] >= 0 && r->texcoords[0][v] <= 1);
        resurf_compare_report d_free = tu_compare(m, r, 20000), d_seamed = tu_compare(m, seamed[l], 20000);
        /* a level on the input to rounding on both runs (the light run's 25%) compares rounding: its floor */
        ck_assert_msg(d_free.hausdorff <= d_seamed.hausdorff * (1 + 1e-9) + 1e-12 * d_free.diagonal,
                      "level %d: %g from the input, seamed %g", l + 1, d_free.hausdorff, d_seamed.hausdorff);
        resurf_mesh_free(free_levels[l]);
        resurf_mesh_free(seamed[l]);
    }
    resurf_mesh_free(m);
}
END_TEST

START_TEST(weights_are_checked)
{
    resurf_mesh *m = graded_grid(4);
    resurf_simplify_options o = resurf_simplify_options_default();
    o.target_ratio = 0.5;
    double bad[] = {-1, NAN, INFINITY};
    for (size_t k = 0; k < 3 * 3; ++k) {
        resurf_simplify_options x = o;
        double *w = k / 3 == 0 ? &x.normal_weight : k / 3 == 1 ? &x.texcoord_weight : &x.color_weight;
        *w = bad[k % 3];
        resurf_mesh *out = NULL;
        resurf_error e;
        ck_assert_int_eq(resurf_simplify(m, &x, &out, NULL, &e), RESURF_ERR_INVALID_OPTIONS);
        ck_assert_ptr_null(out);
    }
    resurf_mesh_free(m);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("attributes");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, texcoords_in_the_cost_follow_the_gradient);
    tcase_add_test(tc, colours_in_the_cost_keep_their_edge);
    tcase_add_test(tc, a_uv_seam_stays_a_seam);
    tcase_add_test(tc, an_unsampled_seam_holds_nothing);
    tcase_add_test(tc, weights_are_checked);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
