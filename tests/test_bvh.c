/* Tests for src/bvh.c: the closest point on one triangle against hand-computed answers for each Voronoi region and
 * for degenerate triangles; the tree's closest-point query against a brute-force scan (same distance bit for bit,
 * same triangle) on a sphere mesh, on a random soup with degenerate and duplicate triangles, and on a large mesh
 * built on several threads; the reach cut-off; the radius walk. */
#include <math.h>
#include <string.h>

#include "testutil.h"

/* ---- closest point on one triangle ----------------------------------------------------------------------------- */

/* Checks the returned point against the expected one, the barycentrics against the expected ones (if given), and
 * that the barycentrics reproduce the point and sum to 1. */
static void check_closest(vec3 p, vec3 a, vec3 b, vec3 c, vec3 expect, const double *expect_bary)
{
    double bary[3];
    vec3 q = resurfi_closest_on_triangle(p, a, b, c, bary);
    ck_assert_msg(v3_dist(q, expect) < 1e-14, "closest (%g %g %g), expected (%g %g %g)", q.x, q.y, q.z, expect.x,
                  expect.y, expect.z);
    ck_assert_double_eq_tol(bary[0] + bary[1] + bary[2], 1.0, 1e-15);
    for (int k = 0; k < 3; ++k) {
        ck_assert(bary[k] >= 0 && bary[k] <= 1);
        if (expect_bary)
            ck_assert_double_eq_tol(bary[k], expect_bary[k], 1e-14);
    }
    vec3 r = v3_add(v3_add(v3_scale(a, bary[0]), v3_scale(b, bary[1])), v3_scale(c, bary[2]));
    ck_assert(v3_dist(r, q) < 1e-14);
    /* The NULL-barycentrics form gives the same point. */
    vec3 q2 = resurfi_closest_on_triangle(p, a, b, c, NULL);
    ck_assert(q2.x == q.x && q2.y == q.y && q2.z == q.z);
}

/*   c (0,1,0)
 *   |\
 *   | \
 *   a--b   a (0,0,0), b (1,0,0); each Voronoi region of the plane z = 0, points lifted off the plane. */
START_TEST(closest_on_triangle_regions)
{
    vec3 a = v3(0, 0, 0), b = v3(1, 0, 0), c = v3(0, 1, 0);
    check_closest(v3(-1, -1, 0.5), a, b, c, a, (double[]){1, 0, 0});
    check_closest(v3(2, -0.5, 1), a, b, c, b, (double[]){0, 1, 0});
    check_closest(v3(-0.5, 2, -1), a, b, c, c, (double[]){0, 0, 1});
    check_closest(v3(0.3, -1, 2), a, b, c, v3(0.3, 0, 0), (double[]){0.7, 0.3, 0});
    check_closest(v3(-2, 0.6, 0), a, b, c, v3(0, 0.6, 0), (double[]){0.4, 0, 0.6});
    check_closest(v3(1, 1, 0.5), a, b, c, v3(0.5, 0.5, 0), (double[]){0, 0.5, 0.5});
    check_closest(v3(0.2, 0.3, 5), a, b, c, v3(0.2, 0.3, 0), (double[]){0.5, 0.2, 0.3});
    check_closest(v3(0.2, 0.3, -5), a, b, c, v3(0.2, 0.3, 0), (double[]){0.5, 0.2, 0.3});
    /* On the triangle itself: a vertex, an edge point, an interior point. */
    check_closest(b, a, b, c, b, (double[]){0, 1, 0});
    check_closest(v3(0.25, 0.75, 0), a, b, c, v3(0.25, 0.75, 0), (double[]){0, 0.25, 0.75});
    check_closest(v3(0.25, 0.25, 0), a, b, c, v3(0.25, 0.25, 0), (double[]){0.5, 0.25, 0.25});
}
END_TEST

START_TEST(closest_on_triangle_degenerate)
{
    /* Collinear, c between a and b: the triangle is the segment [a, b]. */
    vec3 a = v3(0, 0, 0), b = v3(2, 0, 0), c = v3(1, 0, 0);
    check_closest(v3(1.5, 1, 0), a, b, c, v3(1.5, 0, 0), NULL);
    check_closest(v3(0.2, -1, 3), a, b, c, v3(0.2, 0, 0), NULL);
    check_closest(v3(3, 0, 1), a, b, c, b, (double[]){0, 1, 0});
    check_closest(v3(-3, 2, 1), a, b, c, a, (double[]){1, 0, 0});
    /* Two corners equal: the segment from a = b to c. */
    vec3 d = v3(0, 0, 2);
    check_closest(v3(1, 0, 1), a, a, d, v3(0, 0, 1), NULL);
    check_closest(v3(1, 5, 3), a, a, d, d, (double[]){0, 0, 1});
    check_closest(v3(1, 5, 3), d, a, a, d, (double[]){1, 0, 0});
    /* Point-like: all three corners the same. */
    vec3 e = v3(1, 2, 3);
    double bary[3];
    vec3 q = resurfi_closest_on_triangle(v3(0, 0, 0), e, e, e, bary);
    ck_assert(q.x == 1 && q.y == 2 && q.z == 3);
    ck_assert_double_eq(bary[0] + bary[1] + bary[2], 1.0);
    /* A needle (sin of its angle at a is 1e-9): the closest point is the projection on its upper long edge a–f. */
    vec3 f = v3(1, 1e-9, 0), p = v3(0.5, 1, 0);
    double s = v3_dot(p, f) / v3_len2(f);
    check_closest(p, a, v3(1, 0, 0), f, v3_scale(f, s), NULL);
    check_closest(v3(0.5, -1, 0), a, v3(1, 0, 0), f, v3(0.5, 0, 0), NULL);
}
END_TEST

/* ---- the tree against a brute-force scan --------------------------------------------------------------------- */

typedef struct hit {
    uint32_t triangle;
    vec3 point;
    double bary[3], d2;
} hit;

/* Every valid triangle, lowest index first among exact ties: what resurfi_bvh_closest must return. */
static hit brute_force(const double *pos, size_t vertex_count, const uint32_t *idx, size_t triangle_count, vec3 p,
                       double max_d2)
{
    hit h = {UINT32_MAX, {0, 0, 0}, {0, 0, 0}, max_d2};
    for (size_t t = 0; t < triangle_count; ++t) {
        const uint32_t *tri = idx + 3 * t;
        if (tri[0] >= vertex_count || tri[1] >= vertex_count || tri[2] >= vertex_count)
            continue;
        vec3 a = v3_load(pos + 3 * tri[0]), b = v3_load(pos + 3 * tri[1]), c = v3_load(pos + 3 * tri[2]);
        if (!v3_finite(a) || !v3_finite(b) || !v3_finite(c))
            continue;
        double bary[3];
        vec3 q = resurfi_closest_on_triangle(p, a, b, c, bary);
        double d2 = v3_dist2(p, q);
        if (d2 < h.d2 || (d2 == h.d2 && t < h.triangle)) {
            h.triangle = (uint32_t)t, h.point = q, h.d2 = d2;
            memcpy(h.bary, bary, sizeof bary);
        }
    }
    return h;
}

static void check_against_brute_force(const resurfi_bvh *bvh, const double *pos, size_t vertex_count,
                                      const uint32_t *idx, size_t triangle_count, vec3 p)
{
    hit want = brute_force(pos, vertex_count, idx, triangle_count, p, INFINITY);
    vec3 q;
    double bary[3], d2;
    uint32_t t = resurfi_bvh_closest(bvh, p, INFINITY, &q, bary, &d2);
    ck_assert_msg(t == want.triangle && d2 == want.d2,
                  "p (%.17g %.17g %.17g): tree gives triangle %u at d2 %.17g, brute force %u at %.17g", p.x, p.y, p.z,
                  t, d2, want.triangle, want.d2);
    ck_assert(q.x == want.point.x && q.y == want.point.y && q.z == want.point.z);
    ck_assert(memcmp(bary, want.bary, sizeof bary) == 0);
}

static vec3 random_in_box(uint64_t *rng, double lo, double hi)
{
    double x = lo + (hi - lo) * shape_rand_unit(rng), y = lo + (hi - lo) * shape_rand_unit(rng),
           z = lo + (hi - lo) * shape_rand_unit(rng);
    return v3(x, y, z);
}

static vec3 random_direction(uint64_t *rng)
{
    for (;;) {
        vec3 d = random_in_box(rng, -1, 1);
        double l = v3_len(d);
        if (l > 0.1 && l <= 1)
            return v3_scale(d, 1 / l);
    }
}

START_TEST(closest_matches_brute_force_on_sphere)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 4000, 0.3, 7, 0);
    ck_assert_ptr_nonnull(m);
    resurfi_bvh *bvh = NULL;
    ck_assert_int_eq(resurfi_bvh_build(NULL, m->positions, m->vertex_count, m->indices, m->triangle_count, &bvh),
                     RESURF_OK);
    ck_assert_uint_eq(resurfi_bvh_triangle_count(bvh), m->triangle_count);
    uint64_t rng = 11;
    size_t n = 0;
    for (int i = 0; i < 1500; ++i, ++n) /* near the surface, inside and outside */
        check_against_brute_force(bvh, m->positions, m->vertex_count, m->indices, m->triangle_count,
                                  v3_scale(random_direction(&rng), 1 + 0.1 * (shape_rand_unit(&rng) - 0.5)));
    for (int i = 0; i < 500; ++i, ++n) /* far away, and deep inside */
        check_against_brute_force(bvh, m->positions, m->vertex_count, m->indices, m->triangle_count,
                                  i % 2 ? random_in_box(&rng, -20, 20) : random_in_box(&rng, -0.3, 0.3));
    for (size_t v = 0; v < m->vertex_count; v += 7, ++n) { /* exactly on vertices: distance 0, many ties */
        vec3 p = resurfi_position(m, (uint32_t)v);
        check_against_brute_force(bvh, m->positions, m->vertex_count, m->indices, m->triangle_count, p);
        double d2 = -1;
        ck_assert_uint_ne(resurfi_bvh_closest(bvh, p, INFINITY, NULL, NULL, &d2), UINT32_MAX);
        ck_assert(d2 == 0);
    }
    for (size_t t = 0; t < m->triangle_count; t += 5, ++n) { /* on edges: midpoints and other fractions */
        const uint32_t *tri = m->indices + 3 * t;
        vec3 a = resurfi_position(m, tri[t % 3]), b = resurfi_position(m, tri[(t + 1) % 3]);
        check_against_brute_force(bvh, m->positions, m->vertex_count, m->indices, m->triangle_count,
                                  v3_lerp(a, b, t % 2 ? 0.5 : 0.3));
    }
    ck_assert(n > 3000);
    resurfi_bvh_free(bvh);
    resurf_mesh_free(m);
}
END_TEST

/* A random soup in the unit cube: small and large triangles, collinear, two-equal-corner and point-like ones,
 * exact duplicates (ties), triangles with an out-of-range index and with a NaN corner (both skipped). */
START_TEST(closest_matches_brute_force_on_soup)
{
    enum { T = 1500 };
    double *pos = malloc(9 * T * sizeof(double));
    uint32_t *idx = malloc(3 * T * sizeof(uint32_t));
    ck_assert(pos && idx);
    uint64_t rng = 3;
    for (size_t t = 0; t < T; ++t) {
        vec3 a = random_in_box(&rng, 0, 1);
        double size = t % 3 ? 0.05 : 0.4;
        vec3 b = v3_add(a, v3_scale(random_in_box(&rng, -1, 1), size));
        vec3 c = v3_add(a, v3_scale(random_in_box(&rng, -1, 1), size));
        switch (t % 11) {
        case 1: c = v3_lerp(a, b, 0.3); break;                 /* collinear, c inside */
        case 2: c = v3_lerp(a, b, 1.7); break;                 /* collinear, c beyond b */
        case 3: b = a; break;                                  /* two corners equal */
        case 4: b = a, c = a; break;                           /* point-like */
        case 5: if (t > 11) { memcpy(pos + 9 * t, pos + 9 * (t - 11), 9 * sizeof(double)); goto indices; } break;
        default: break;
        }
        v3_store(pos + 9 * t, a), v3_store(pos + 9 * t + 3, b), v3_store(pos + 9 * t + 6, c);
    indices:
        for (int k = 0; k < 3; ++k)
            idx[3 * t + k] = (uint32_t)(3 * t + k);
    }
    idx[3 * 17 + 1] = 3 * T + 5;   /* out of range */
    pos[9 * 29 + 4] = NAN;         /* a non-finite corner */
    resurfi_bvh *bvh = NULL;
    ck_assert_int_eq(resurfi_bvh_build(NULL, pos, 3 * T, idx, T, &bvh), RESURF_OK);
    ck_assert_uint_eq(resurfi_bvh_triangle_count(bvh), T - 2);
    for (int i = 0; i < 2000; ++i)
        check_against_brute_force(bvh, pos, 3 * T, idx, T, random_in_box(&rng, i % 4 ? -0.1 : -3, i % 4 ? 1.1 : 4));
    for (size_t v = 0; v < 3 * T; v += 5) /* on corners (skipping the NaN one) */
        if (v3_finite(v3_load(pos + 3 * v)))
            check_against_brute_force(bvh, pos, 3 * T, idx, T, v3_load(pos + 3 * v));
    for (size_t t = 0; t < T; t += 3) /* on edges of the duplicated and degenerate ones too */
        check_against_brute_force(bvh, pos, 3 * T, idx, T, v3_lerp(v3_load(pos + 9 * t), v3_load(pos + 9 * t + 3), 0.5));
    /* A duplicate pair at distance 0: the lower index wins. */
    size_t dup = 5 + 11 * 4;
    ck_assert(memcmp(pos + 9 * dup, pos + 9 * (dup - 11), 9 * sizeof(double)) == 0);
    vec3 centre = v3_scale(v3_add(v3_add(v3_load(pos + 9 * dup), v3_load(pos + 9 * dup + 3)), v3_load(pos + 9 * dup + 6)),
                           1.0 / 3);
    uint32_t t = resurfi_bvh_closest(bvh, centre, INFINITY, NULL, NULL, NULL);
    ck_assert_uint_le(t, dup - 11);
    resurfi_bvh_free(bvh);
    free(pos);
    free(idx);
}
END_TEST

/* Triangles that float cannot tell apart (twins 1e-13 apart, at coordinates near 1) and a mesh far beyond float's
 * range (1e60): the tree keeps float corners, so its answers must still be the exact ones of a double scan. */
START_TEST(closest_exact_where_float_is_not)
{
    enum { T = 400 };
    double *pos = malloc(9 * T * sizeof *pos);
    uint32_t *idx = malloc(3 * T * sizeof *idx);
    uint64_t rng = 23;
    for (size_t t = 0; t < T; t += 2) {
        vec3 a = random_in_box(&rng, 0.9, 1.1), b = random_in_box(&rng, 0.9, 1.1), c = random_in_box(&rng, 0.9, 1.1);
        vec3 shift = v3_scale(random_direction(&rng), 1e-13);
        v3_store(pos + 9 * t, a), v3_store(pos + 9 * t + 3, b), v3_store(pos + 9 * t + 6, c);
        v3_store(pos + 9 * t + 9, v3_add(a, shift)), v3_store(pos + 9 * t + 12, v3_add(b, shift));
        v3_store(pos + 9 * t + 15, v3_add(c, shift));
    }
    for (size_t i = 0; i < 3 * T; ++i)
        idx[i] = (uint32_t)i;
    for (int scale = 0; scale < 2; ++scale) {
        if (scale)
            for (size_t i = 0; i < 9 * T; ++i)
                pos[i] *= 1e60;
        double k = scale ? 1e60 : 1;
        resurfi_bvh *bvh = NULL;
        ck_assert_int_eq(resurfi_bvh_build(NULL, pos, 3 * T, idx, T, &bvh), RESURF_OK);
        for (int i = 0; i < 1500; ++i)
            check_against_brute_force(bvh, pos, 3 * T, idx, T, v3_scale(random_in_box(&rng, 0.85, 1.15), k));
        for (size_t t = 0; t < T; t += 7) /* on a triangle: its twin is 1e-13 away */
            check_against_brute_force(bvh, pos, 3 * T, idx, T,
                                      v3_lerp(v3_load(pos + 9 * t), v3_load(pos + 9 * t + 3), 0.4));
        resurfi_bvh_free(bvh);
    }
    free(pos);
    free(idx);
}
END_TEST

/* A mesh large enough for the build to split across threads: the same answers whatever the thread count. Under
 * RESURF_TEST_LIGHT 80k triangles, whose halves still split again on the 3-thread build (over 2 x 32768). */
START_TEST(closest_same_for_any_thread_count)
{
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, tu_light() ? 80000 : 120000, 0.3, 5, 0);
    ck_assert_ptr_nonnull(m);
    resurfi_bvh *trees[3] = {NULL, NULL, NULL};
    const unsigned threads[3] = {1, 2, 3};
    for (int k = 0; k < 3; ++k)
        ck_assert_int_eq(resurfi_bvh_build_threads(NULL, m->positions, m->vertex_count, m->indices, m->triangle_count,
                                                   threads[k], &trees[k]),
                         RESURF_OK);
    uint64_t rng = 99;
    for (int i = 0; i < 2000; ++i) {
        vec3 p = random_in_box(&rng, -1.6, 1.6);
        vec3 q[3];
        double d2[3];
        uint32_t t[3];
        for (int k = 0; k < 3; ++k)
            t[k] = resurfi_bvh_closest(trees[k], p, INFINITY, &q[k], NULL, &d2[k]);
        ck_assert(t[0] == t[1] && t[0] == t[2] && d2[0] == d2[1] && d2[0] == d2[2]);
        if (i < 60) /* a brute-force check of a few (each scans every triangle) */
            check_against_brute_force(trees[1], m->positions, m->vertex_count, m->indices, m->triangle_count, p);
    }
    for (int k = 0; k < 3; ++k)
        resurfi_bvh_free(trees[k]);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(closest_respects_max_distance)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 2000, 0.2, 1, 0);
    ck_assert_ptr_nonnull(m);
    resurfi_bvh *bvh = NULL;
    ck_assert_int_eq(resurfi_bvh_build(NULL, m->positions, m->vertex_count, m->indices, m->triangle_count, &bvh),
                     RESURF_OK);
    uint64_t rng = 5;
    for (int i = 0; i < 300; ++i) {
        vec3 p = v3_scale(random_direction(&rng), 1.5 + shape_rand_unit(&rng));
        hit want = brute_force(m->positions, m->vertex_count, m->indices, m->triangle_count, p, INFINITY);
        /* Just short of the distance: nothing, and the outputs are left alone. */
        vec3 q = v3(7, 7, 7);
        double d2 = 7;
        ck_assert_uint_eq(resurfi_bvh_closest(bvh, p, want.d2 * (1 - 1e-9), &q, NULL, &d2), UINT32_MAX);
        ck_assert(q.x == 7 && d2 == 7);
        /* Exactly the distance: found (reach is inclusive). */
        ck_assert_uint_eq(resurfi_bvh_closest(bvh, p, want.d2, NULL, NULL, &d2), want.triangle);
        ck_assert(d2 == want.d2);
    }
    /* Reach 0 from a vertex finds it; reach 0 from anywhere else finds nothing. */
    ck_assert_uint_ne(resurfi_bvh_closest(bvh, resurfi_position(m, 3), 0, NULL, NULL, NULL), UINT32_MAX);
    ck_assert_uint_eq(resurfi_bvh_closest(bvh, v3(0, 0, 0), 0.5, NULL, NULL, NULL), UINT32_MAX);
    ck_assert_uint_eq(resurfi_bvh_closest(bvh, v3(NAN, 0, 0), INFINITY, NULL, NULL, NULL), UINT32_MAX);
    resurfi_bvh_free(bvh);
    resurf_mesh_free(m);
}
END_TEST

START_TEST(empty_tree_finds_nothing)
{
    resurfi_bvh *bvh = NULL;
    ck_assert_int_eq(resurfi_bvh_build(NULL, NULL, 0, NULL, 0, &bvh), RESURF_OK);
    ck_assert_uint_eq(resurfi_bvh_closest(bvh, v3(0, 0, 0), INFINITY, NULL, NULL, NULL), UINT32_MAX);
    resurfi_bvh_free(bvh);
    /* Only invalid triangles. */
    const double pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t idx[6] = {0, 1, 3, 5, 1, 2};
    ck_assert_int_eq(resurfi_bvh_build(NULL, pos, 3, idx, 2, &bvh), RESURF_OK);
    ck_assert_uint_eq(resurfi_bvh_triangle_count(bvh), 0);
    ck_assert_uint_eq(resurfi_bvh_closest(bvh, v3(0, 0, 0), INFINITY, NULL, NULL, NULL), UINT32_MAX);
    resurfi_bvh_free(bvh);
    ck_assert_int_eq(resurfi_bvh_build(NULL, NULL, 3, idx, 2, &bvh), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(bvh);
    resurfi_bvh_free(NULL);
}
END_TEST

typedef struct collect {
    unsigned char *seen;
    size_t count;
    double max_d2;
    int bad;
} collect;

static int collect_hit(void *ctx, uint32_t triangle, vec3 point, const double bary[3], double dist2)
{
    (void)point, (void)bary;
    collect *c = ctx;
    if (c->seen[triangle] || dist2 > c->max_d2)
        c->bad = 1;
    c->seen[triangle] = 1;
    c->count++;
    return 0;
}

static int stop_at_first(void *ctx, uint32_t triangle, vec3 point, const double bary[3], double dist2)
{
    (void)triangle, (void)point, (void)bary, (void)dist2;
    ++*(int *)ctx;
    return 1;
}

START_TEST(within_finds_every_triangle_in_reach)
{
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 3000, 0.3, 2, 0);
    ck_assert_ptr_nonnull(m);
    resurfi_bvh *bvh = NULL;
    ck_assert_int_eq(resurfi_bvh_build(NULL, m->positions, m->vertex_count, m->indices, m->triangle_count, &bvh),
                     RESURF_OK);
    unsigned char *seen = calloc(m->triangle_count, 1);
    uint64_t rng = 8;
    for (int i = 0; i < 200; ++i) {
        vec3 p = random_in_box(&rng, -1.5, 1.5);
        double r2 = 0.02 + 0.1 * shape_rand_unit(&rng);
        memset(seen, 0, m->triangle_count);
        collect c = {seen, 0, r2, 0};
        ck_assert_int_eq(resurfi_bvh_within(bvh, p, r2, collect_hit, &c), 0);
        ck_assert(!c.bad);
        size_t expected = 0;
        for (size_t t = 0; t < m->triangle_count; ++t) {
            const uint32_t *tri = m->indices + 3 * t;
            vec3 q = resurfi_closest_on_triangle(p, resurfi_position(m, tri[0]), resurfi_position(m, tri[1]),
                                                 resurfi_position(m, tri[2]), NULL);
            int in = v3_dist2(p, q) <= r2;
            expected += (size_t)in;
            ck_assert_int_eq(in, seen[t]);
        }
        ck_assert_uint_eq(c.count, expected);
    }
    int calls = 0;
    ck_assert_int_eq(resurfi_bvh_within(bvh, resurfi_position(m, 0), 1.0, stop_at_first, &calls), 1);
    ck_assert_int_eq(calls, 1);
    free(seen);
    resurfi_bvh_free(bvh);
    resurf_mesh_free(m);
}
END_TEST

/* Queries from several threads at once give what one thread gives. */
typedef struct query_job {
    const resurfi_bvh *bvh;
    const vec3 *points;
    uint32_t *result;
    double *d2;
} query_job;

static int run_queries(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    query_job *j = ctx;
    for (size_t i = begin; i < end; ++i)
        j->result[i] = resurfi_bvh_closest(j->bvh, j->points[i], INFINITY, NULL, NULL, &j->d2[i]);
    return 0;
}

START_TEST(queries_are_thread_safe)
{
    enum { N = 20000 };
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 20000, 0.3, 4, 0);
    resurfi_bvh *bvh = NULL;
    ck_assert_int_eq(resurfi_bvh_build(NULL, m->positions, m->vertex_count, m->indices, m->triangle_count, &bvh),
                     RESURF_OK);
    vec3 *pts = malloc(N * sizeof *pts);
    uint32_t *r1 = malloc(N * sizeof *r1), *r2 = malloc(N * sizeof *r2);
    double *d1 = malloc(N * sizeof *d1), *d2 = malloc(N * sizeof *d2);
    uint64_t rng = 1;
    for (int i = 0; i < N; ++i)
        pts[i] = random_in_box(&rng, -1.2, 1.2);
    query_job a = {bvh, pts, r1, d1}, b = {bvh, pts, r2, d2};
    ck_assert_int_eq(resurfi_parallel_for(N, N, 1, run_queries, &a), 0);
    ck_assert_int_eq(resurfi_parallel_for(N, 64, 4, run_queries, &b), 0);
    ck_assert(memcmp(r1, r2, N * sizeof *r1) == 0 && memcmp(d1, d2, N * sizeof *d1) == 0);
    free(pts), free(r1), free(r2), free(d1), free(d2);
    resurfi_bvh_free(bvh);
    resurf_mesh_free(m);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("bvh");
    TCase *tc = tcase_create("bvh");
    tcase_add_test(tc, closest_on_triangle_regions);
    tcase_add_test(tc, closest_on_triangle_degenerate);
    tcase_add_test(tc, closest_matches_brute_force_on_sphere);
    tcase_add_test(tc, closest_matches_brute_force_on_soup);
    tcase_add_test(tc, closest_exact_where_float_is_not);
    tcase_add_test(tc, closest_same_for_any_thread_count);
    tcase_add_test(tc, closest_respects_max_distance);
    tcase_add_test(tc, empty_tree_finds_nothing);
    tcase_add_test(tc, within_finds_every_triangle_in_reach);
    tcase_add_test(tc, queries_are_thread_safe);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
