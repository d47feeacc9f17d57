/* Tests for src/optdir.c, the optimal direction: a hand-factored cubic, central projection on a sphere, the plain
 * and the oblique projection of a flat triangle, nearly equal normals (where naive root finding loses the root),
 * degenerate triangles, the root ranking, and on random configurations every root solving the defining equation
 * with as many roots as the determinant has sign changes. */
#include <math.h>

#include "testutil.h"

/* |p − Σ b_j (p_j + t N_j)|: zero for a root. */
static double residual(vec3 p, const vec3 pj[3], const vec3 nj[3], const resurfi_optdir_root *r)
{
    vec3 q = v3(0, 0, 0);
    for (int j = 0; j < 3; ++j)
        q = v3_madd(q, v3_madd(pj[j], nj[j], r->t), r->bary[j]);
    return v3_dist(q, p);
}

/* Is r a root to rounding, for corners and normals of size about 1? The sum's terms grow with |t| and |b_j|. */
static int solves(vec3 p, const vec3 pj[3], const vec3 nj[3], const resurfi_optdir_root *r)
{
    double size = 1 + fabs(r->t) + fabs(r->bary[0]) + fabs(r->bary[1]) + fabs(r->bary[2]);
    return residual(p, pj, nj, r) < 1e-14 * size * size;
}

/* A rigid motion (rotation about a generic axis, then a shift) applied to a point or a direction. */
static vec3 rotate(vec3 v)
{
    vec3 k = v3_normalize(v3(0.3, -0.5, 0.8));
    double a = 0.7, c = cos(a), s = sin(a);
    return v3_add(v3_add(v3_scale(v, c), v3_scale(v3_cross(k, v), s)), v3_scale(k, v3_dot(k, v) * (1 - c)));
}
static vec3 move(vec3 p) { return v3_add(rotate(p), v3(0.25, -1.5, 2.0)); }

/* p1 = 0, p2 = e_x, p3 = e_y, N1 = e_z, N2 = e_z + a e_x, N3 = e_z + b e_y. The offset triangle has sides
 * (1 + a t) e_x and (1 + b t) e_y at height t, so det = (1 + a t)(1 + b t)(z − t): roots t = z, −1/a, −1/b. At the
 * last two the offset triangle collapses (no barycentrics), so only t = z remains, with b2 = x / (1 + a z),
 * b3 = y / (1 + b z). The whole configuration is moved rigidly so that no coordinate is special. */
static void check_factored(double a, double b, vec3 p, double tol_t, double tol_b)
{
    vec3 pj[3] = {move(v3(0, 0, 0)), move(v3(1, 0, 0)), move(v3(0, 1, 0))};
    vec3 nj[3] = {rotate(v3(0, 0, 1)), rotate(v3(a, 0, 1)), rotate(v3(0, b, 1))};
    resurfi_optdir_root roots[3];
    int n = resurfi_optdir_solve(move(p), pj, nj, roots);
    ck_assert_int_eq(n, 1);
    ck_assert_msg(fabs(roots[0].t - p.z) <= tol_t, "t = %.17g, expected %.17g", roots[0].t, p.z);
    double b2 = p.x / (1 + a * p.z), b3 = p.y / (1 + b * p.z);
    ck_assert_msg(fabs(roots[0].bary[1] - b2) <= tol_b && fabs(roots[0].bary[2] - b3) <= tol_b,
                  "bary %.17g %.17g, expected %.17g %.17g", roots[0].bary[1], roots[0].bary[2], b2, b3);
    ck_assert_double_eq_tol(roots[0].bary[0] + roots[0].bary[1] + roots[0].bary[2], 1.0, 1e-15);
}

START_TEST(hand_factored_cubic)
{
    check_factored(0.5, -0.25, v3(0.2, 0.3, 0.4), 1e-14, 1e-14);
    check_factored(2.0, 3.0, v3(0.1, 0.6, -0.2), 1e-14, 1e-14);
    check_factored(-1.0, 0.7, v3(0.5, 0.5, 0.3), 1e-14, 1e-14); /* p above the edge p2 p3 */
}
END_TEST

/* Nearly equal normals: the other roots are at −1/a ≈ −1e5 .. −1e11 while the wanted one is z. A closed-form
 * solve of the monic cubic loses it to cancellation; the scaled, polished solve keeps it to rounding. */
START_TEST(nearly_equal_normals_keep_precision)
{
    static const double eps[] = {1e-3, 1e-5, 1e-7, 1e-9, 1e-11, 1e-14};
    for (size_t i = 0; i < sizeof eps / sizeof eps[0]; ++i) {
        check_factored(eps[i], 0.6 * eps[i], v3(0.25, 0.35, 0.3), 1e-14, 1e-14);
        check_factored(-eps[i], 2 * eps[i], v3(0.1, 0.2, -0.7), 1e-14, 1e-14);
    }
}
END_TEST

/* Triangles on the unit sphere with exact normals N_j = p_j: Σ b_j N_j = p0, so the line is the ray from the
 * centre through p, and p0 is the central projection of p on the triangle's plane: t = |p| / |p0| − 1. */
START_TEST(sphere_root_is_central_projection)
{
    uint64_t rng = 7;
    int checked = 0;
    for (int it = 0; it < 200; ++it) {
        vec3 c = v3_normalize(
            v3(shape_rand_unit(&rng) - 0.5, shape_rand_unit(&rng) - 0.5, shape_rand_unit(&rng) - 0.5));
        vec3 pj[3];
        for (int j = 0; j < 3; ++j)
            pj[j] = v3_normalize(v3_add(c, v3_scale(v3(shape_rand_unit(&rng) - 0.5, shape_rand_unit(&rng) - 0.5,
                                                       shape_rand_unit(&rng) - 0.5),
                                                    0.2)));
        vec3 n = v3_tri_cross(pj[0], pj[1], pj[2]);
        if (v3_len(n) < 1e-3)
            continue;
        /* p: a point of the triangle pushed radially in or out */
        double w[3] = {shape_rand_unit(&rng) + 0.05, shape_rand_unit(&rng) + 0.05, shape_rand_unit(&rng) + 0.05};
        double ws = w[0] + w[1] + w[2];
        vec3 p0 = v3(0, 0, 0);
        for (int j = 0; j < 3; ++j)
            p0 = v3_madd(p0, pj[j], w[j] / ws);
        double radius = 0.8 + 0.4 * shape_rand_unit(&rng);
        vec3 p = v3_scale(v3_normalize(p0), radius);
        resurfi_optdir_root roots[3];
        int count = resurfi_optdir_solve(p, pj, pj, roots);
        ck_assert_int_ge(count, 1);
        ck_assert(roots[0].outside == 0);
        ck_assert_msg(fabs(roots[0].t - (radius / v3_len(p0) - 1)) < 1e-13, "t %.17g expected %.17g", roots[0].t,
                      radius / v3_len(p0) - 1);
        for (int j = 0; j < 3; ++j)
            ck_assert_double_eq_tol(roots[0].bary[j], w[j] / ws, 1e-13);
        for (int k = 0; k < count; ++k)
            ck_assert(solves(p, pj, pj, &roots[k]));
        ++checked;
    }
    ck_assert_int_gt(checked, 150);
}
END_TEST

/* A flat triangle whose three normals are its unit normal: the plain orthogonal projection, t = signed distance,
 * for points above, below, inside and outside the triangle. */
START_TEST(flat_equal_normals_is_orthogonal_projection)
{
    vec3 pj[3] = {move(v3(0, 0, 0)), move(v3(2, 0, 0)), move(v3(0.5, 1.5, 0))};
    vec3 n = rotate(v3(0, 0, 1));
    vec3 nj[3] = {n, n, n};
    static const double cases[][3] = {{0.5, 0.5, 0.3}, {0.5, 0.5, -0.3}, {3, 3, 1}, {-1, 0.2, 0}, {1, 0, 0}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        vec3 local = v3(cases[i][0], cases[i][1], cases[i][2]);
        vec3 p = move(local);
        resurfi_optdir_root roots[3];
        ck_assert_int_eq(resurfi_optdir_solve(p, pj, nj, roots), 1);
        ck_assert_double_eq_tol(roots[0].t, local.z, 1e-14);
        /* barycentrics of (x, y) in the base triangle (0,0), (2,0), (0.5,1.5): area 1.5 */
        double b2 = (local.x * 1.5 - local.y * 0.5) / 3.0, b3 = local.y / 1.5;
        ck_assert_double_eq_tol(roots[0].bary[1], b2, 1e-14);
        ck_assert_double_eq_tol(roots[0].bary[2], b3, 1e-14);
        double lowest = fmin(1 - b2 - b3, fmin(b2, b3));
        ck_assert_double_eq_tol(roots[0].outside, lowest < 0 ? -lowest : 0, 1e-14);
    }
}
END_TEST

/* Equal normals not perpendicular to the triangle: the projection along that normal (oblique), t = z / n_z. */
START_TEST(flat_oblique_normals_project_along_them)
{
    vec3 pj[3] = {move(v3(0, 0, 0)), move(v3(1, 0, 0)), move(v3(0, 1, 0))};
    vec3 dir = v3(0.3, -0.2, 1.0);
    vec3 n = rotate(v3_normalize(dir));
    vec3 nj[3] = {n, n, n};
    vec3 local = v3(0.3, 0.3, 0.5);
    resurfi_optdir_root roots[3];
    ck_assert_int_eq(resurfi_optdir_solve(move(local), pj, nj, roots), 1);
    double t = 0.5 / v3_normalize(dir).z;
    ck_assert_double_eq_tol(roots[0].t, t, 1e-14);
    vec3 foot = v3_madd(local, v3_normalize(dir), -t);
    ck_assert_double_eq_tol(roots[0].bary[1], foot.x, 1e-14);
    ck_assert_double_eq_tol(roots[0].bary[2], foot.y, 1e-14);
}
END_TEST

START_TEST(degenerate_triangles)
{
    vec3 n = v3(0, 0, 1);
    vec3 nj[3] = {n, n, n};
    resurfi_optdir_root roots[3];
    /* collinear corners with equal normals: the offset triangle is a segment for every t, no solution */
    vec3 line[3] = {v3(0, 0, 0), v3(1, 0, 0), v3(2, 0, 0)};
    ck_assert_int_eq(resurfi_optdir_solve(v3(1, 1, 1), line, nj, roots), 0);
    /* a point-like triangle */
    vec3 point[3] = {v3(1, 2, 3), v3(1, 2, 3), v3(1, 2, 3)};
    ck_assert_int_eq(resurfi_optdir_solve(v3(1, 1, 1), point, nj, roots), 0);
    /* non-finite input gives no root rather than NaN roots */
    vec3 bad[3] = {v3(0, 0, 0), v3(NAN, 0, 0), v3(0, 1, 0)};
    ck_assert_int_eq(resurfi_optdir_solve(v3(0.2, 0.2, 1), bad, nj, roots), 0);
    /* collinear corners with differing normals: the offset triangle opens for t != 0; whatever roots exist must
     * solve the equation, with finite values */
    vec3 fan[3] = {v3(0, 0, 1), v3(0.5, 0, 1), v3(-0.5, 0, 1)};
    vec3 q = v3(0.1, 0.05, 0.3);
    int count = resurfi_optdir_solve(q, line, fan, roots);
    for (int k = 0; k < count; ++k) {
        ck_assert(isfinite(roots[k].t));
        ck_assert(solves(q, line, fan, &roots[k]));
    }
}
END_TEST

/* det(q2 − q1, q3 − q1, p − q1) evaluated directly. */
static double det_at(vec3 p, const vec3 pj[3], const vec3 nj[3], double t)
{
    vec3 q[3];
    for (int j = 0; j < 3; ++j)
        q[j] = v3_madd(pj[j], nj[j], t);
    return v3_dot(v3_cross(v3_sub(q[1], q[0]), v3_sub(q[2], q[0])), v3_sub(p, q[0]));
}

/* Random triangles with strongly varying normals: every root returned solves p = Σ b_j (p_j + t N_j), the
 * number of roots in [−T, T] equals the number of sign changes of the determinant sampled there (configurations
 * with a root near a sample or a near-double root are skipped), and the ranking holds. */
START_TEST(random_roots_solve_the_equation)
{
    uint64_t rng = 99;
    int three = 0, checked = 0;
    const double T = 4.0;
    for (int it = 0; it < 2000; ++it) {
        vec3 pj[3], nj[3];
        for (int j = 0; j < 3; ++j) {
            pj[j] = v3(shape_rand_unit(&rng), shape_rand_unit(&rng), 0.2 * shape_rand_unit(&rng));
            nj[j] = v3_normalize(v3(2 * shape_rand_unit(&rng) - 1, 2 * shape_rand_unit(&rng) - 1, 0.5));
        }
        vec3 p = v3(shape_rand_unit(&rng), shape_rand_unit(&rng), 2 * shape_rand_unit(&rng) - 1);
        if (v3_len(v3_tri_cross(pj[0], pj[1], pj[2])) < 0.05)
            continue;
        resurfi_optdir_root roots[3];
        int count = resurfi_optdir_solve(p, pj, nj, roots);
        int in_range = 0;
        for (int k = 0; k < count; ++k) {
            ck_assert_msg(solves(p, pj, nj, &roots[k]), "residual %g t %g b %g %g %g", residual(p, pj, nj, &roots[k]),
                          roots[k].t, roots[k].bary[0], roots[k].bary[1], roots[k].bary[2]);
            if (fabs(roots[k].t) < T)
                ++in_range;
            if (k > 0) {
                int in_prev = roots[k - 1].outside <= RESURFI_OPTDIR_INSIDE_TOL;
                int in_this = roots[k].outside <= RESURFI_OPTDIR_INSIDE_TOL;
                ck_assert(in_prev >= in_this);
                if (in_prev && in_this)
                    ck_assert(fabs(roots[k - 1].t) <= fabs(roots[k].t));
                if (!in_prev && !in_this)
                    ck_assert(roots[k - 1].outside <= roots[k].outside);
            }
        }
        /* sign changes on a fine grid */
        int changes = 0, unclear = 0;
        const int samples = 4000;
        double prev = det_at(p, pj, nj, -T);
        double scale = 0;
        for (int i = 0; i <= samples; ++i)
            scale = fmax(scale, fabs(det_at(p, pj, nj, -T + 2 * T * i / samples)));
        for (int i = 1; i <= samples; ++i) {
            double d = det_at(p, pj, nj, -T + 2 * T * i / samples);
            if (fabs(d) < 1e-6 * scale)
                unclear = 1;
            if ((d < 0) != (prev < 0))
                ++changes;
            prev = d;
        }
        for (int k = 0; k < count; ++k)
            if (fabs(fabs(roots[k].t) - T) < 1e-3)
                unclear = 1;
        if (unclear)
            continue;
        /* a root where the offset triangle collapses has no barycentrics and is not returned */
        ck_assert_int_le(in_range, changes);
        int degenerate = 0;
        for (int i = 0; i <= samples; ++i) {
            double t = -T + 2 * T * i / samples;
            vec3 q[3];
            for (int j = 0; j < 3; ++j)
                q[j] = v3_madd(pj[j], nj[j], t);
            if (v3_len(v3_tri_cross(q[0], q[1], q[2])) < 1e-2)
                degenerate = 1;
        }
        if (!degenerate)
            ck_assert_int_eq(in_range, changes);
        three += count == 3;
        ++checked;
    }
    ck_assert_int_gt(checked, 500);
    ck_assert_int_gt(three, 10); /* the cubic case was exercised */
}
END_TEST

/* Two triangles sharing the edge through p's foot: the root is inside (on the edge) for both. */
START_TEST(point_on_edge_and_vertex)
{
    vec3 n = v3(0, 0, 1);
    vec3 nj[3] = {n, n, n};
    vec3 pj[3] = {v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0)};
    resurfi_optdir_root roots[3];
    ck_assert_int_eq(resurfi_optdir_solve(v3(0.5, 0.5, 0.25), pj, nj, roots), 1);
    ck_assert_double_eq_tol(roots[0].bary[0], 0, 1e-15);
    ck_assert(roots[0].outside <= RESURFI_OPTDIR_INSIDE_TOL);
    ck_assert_int_eq(resurfi_optdir_solve(v3(1, 0, 0), pj, nj, roots), 1);
    ck_assert_double_eq_tol(roots[0].t, 0, 1e-15);
    ck_assert_double_eq_tol(roots[0].bary[1], 1, 1e-15);
}
END_TEST

/* p straight along a corner's normal from the corner (the sphere's exact normals, p below the vertex): the root
 * is at that corner, b = e_1, even though p − q1(t) vanishes there. */
START_TEST(point_on_a_corner_normal)
{
    vec3 pj[3] = {v3_normalize(v3(0.1, 0.2, 1)), v3_normalize(v3(0.2, 0.25, 1)), v3_normalize(v3(0.12, 0.3, 1))};
    static const double scale[] = {0.996, 1.004, 1.0};
    for (int i = 0; i < 3; ++i) {
        resurfi_optdir_root roots[3];
        int n = resurfi_optdir_solve(v3_scale(pj[0], scale[i]), pj, pj, roots);
        ck_assert_int_ge(n, 1);
        ck_assert_double_eq_tol(roots[0].t, scale[i] - 1, 1e-15);
        ck_assert_double_eq_tol(roots[0].bary[0], 1, 1e-14);
        ck_assert(roots[0].outside <= RESURFI_OPTDIR_INSIDE_TOL);
    }
}
END_TEST

/* Newton from a nearby guess finds the same root as the full solve (sphere triangles, p near the surface), and
 * from a guess near another root, that root. */
START_TEST(near_matches_solve)
{
    uint64_t rng = 21;
    for (int it = 0; it < 500; ++it) {
        vec3 c = v3_normalize(
            v3(shape_rand_unit(&rng) - 0.5, shape_rand_unit(&rng) - 0.5, shape_rand_unit(&rng) - 0.5));
        vec3 pj[3];
        for (int j = 0; j < 3; ++j)
            pj[j] = v3_normalize(v3_madd(c, v3(shape_rand_unit(&rng) - 0.5, shape_rand_unit(&rng) - 0.5,
                                               shape_rand_unit(&rng) - 0.5), 0.1));
        vec3 p = v3_scale(v3_normalize(v3_add(v3_add(pj[0], pj[1]), pj[2])), 0.99 + 0.02 * shape_rand_unit(&rng));
        resurfi_optdir_root roots[3], near;
        int n = resurfi_optdir_solve(p, pj, pj, roots);
        ck_assert_int_ge(n, 1);
        ck_assert(resurfi_optdir_near(p, pj, pj, roots[0].t + 0.003 * (shape_rand_unit(&rng) - 0.5), &near));
        ck_assert_double_eq_tol(near.t, roots[0].t, 1e-15);
        for (int j = 0; j < 3; ++j)
            ck_assert_double_eq_tol(near.bary[j], roots[0].bary[j], 1e-12);
        ck_assert_double_eq_tol(near.outside, roots[0].outside, 1e-12);
    }
    /* the hand-factored cubic of check_factored: only t = z is a genuine root */
    vec3 pj[3] = {v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0)};
    vec3 nj[3] = {v3(0, 0, 1), v3(0.5, 0, 1), v3(0, -0.25, 1)};
    resurfi_optdir_root r;
    ck_assert(resurfi_optdir_near(v3(0.2, 0.3, 0.4), pj, nj, 1.0, &r));
    ck_assert_double_eq_tol(r.t, 0.4, 1e-15);
    /* near t = −1/a = −2 the offset triangle collapses: no genuine root there */
    ck_assert(!resurfi_optdir_near(v3(0.2, 0.3, 0.4), pj, nj, -2.0, &r) || fabs(r.t - 0.4) < 1e-15);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("optdir");
    TCase *tc = tcase_create("optdir");
    tcase_add_test(tc, hand_factored_cubic);
    tcase_add_test(tc, nearly_equal_normals_keep_precision);
    tcase_add_test(tc, sphere_root_is_central_projection);
    tcase_add_test(tc, flat_equal_normals_is_orthogonal_projection);
    tcase_add_test(tc, flat_oblique_normals_project_along_them);
    tcase_add_test(tc, degenerate_triangles);
    tcase_add_test(tc, random_roots_solve_the_equation);
    tcase_add_test(tc, point_on_edge_and_vertex);
    tcase_add_test(tc, point_on_a_corner_normal);
    tcase_add_test(tc, near_matches_solve);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
