/* Tests for src/quadric.c, the Garland–Heckbert error quadrics, against hand-computed values: the squared distance
 * to one plane, the area weight of a triangle's plane, sums of quadrics, the exact optimum at the corner of three
 * planes (also when they are not orthogonal), the damped optimum on a line (two planes) and a plane (one), and the
 * zero quadric. */
#include <math.h>

#include "testutil.h"

static void assert_vec_near(vec3 a, vec3 b, double tol)
{
    ck_assert_msg(v3_dist(a, b) <= tol, "(%.17g %.17g %.17g) vs (%.17g %.17g %.17g): %.3g > %.3g", a.x, a.y, a.z, b.x,
                  b.y, b.z, v3_dist(a, b), tol);
}

START_TEST(quadric_plane_is_squared_distance)
{
    /* the plane x + 2y + 2z = 6, unit normal (1,2,2)/3, d = −2 */
    vec3 n = v3(1.0 / 3, 2.0 / 3, 2.0 / 3);
    resurfi_quadric q = resurfi_quadric_plane(n, -2.0, 1.0);
    const vec3 points[] = {{0, 0, 0}, {6, 0, 0}, {1, 1, 1}, {-3, 4, 0.5}, {2, 2, 2}};
    for (size_t i = 0; i < sizeof points / sizeof points[0]; ++i) {
        vec3 p = points[i];
        double d = (p.x + 2 * p.y + 2 * p.z - 6) / 3;
        ck_assert_double_eq_tol(resurfi_quadric_eval(&q, p), d * d, 1e-12);
    }
    /* a weight scales it */
    resurfi_quadric q3 = resurfi_quadric_plane(n, -2.0, 3.0);
    ck_assert_double_eq_tol(resurfi_quadric_eval(&q3, v3(0, 0, 0)), 12.0, 1e-12);
    ck_assert_double_eq(q3.w, 3.0);
}
END_TEST

START_TEST(quadric_triangle_weighted_by_area)
{
    /* right triangle in z = 1 with legs 2 and 3: area 3 */
    resurfi_quadric q = resurfi_quadric_triangle(v3(0, 0, 1), v3(2, 0, 1), v3(0, 3, 1));
    ck_assert_double_eq_tol(q.w, 3.0, 1e-12);
    ck_assert_double_eq_tol(resurfi_quadric_eval(&q, v3(5, -7, 1)), 0.0, 1e-12);
    ck_assert_double_eq_tol(resurfi_quadric_eval(&q, v3(5, -7, 3)), 3.0 * 4.0, 1e-12);
    ck_assert_double_eq_tol(resurfi_quadric_eval(&q, v3(0, 0, -1)), 3.0 * 4.0, 1e-12);
    /* a degenerate triangle contributes nothing */
    resurfi_quadric z = resurfi_quadric_triangle(v3(0, 0, 0), v3(1, 1, 1), v3(2, 2, 2));
    ck_assert_double_eq(z.w, 0.0);
    ck_assert_double_eq(resurfi_quadric_eval(&z, v3(4, 5, 6)), 0.0);
}
END_TEST

START_TEST(quadric_sum_adds_distances)
{
    resurfi_quadric q = resurfi_quadric_plane(v3(1, 0, 0), -1.0, 2.0); /* x = 1, weight 2 */
    resurfi_quadric r = resurfi_quadric_plane(v3(0, 1, 0), 3.0, 0.5);  /* y = −3, weight 0.5 */
    resurfi_quadric_add(&q, &r);
    vec3 p = v3(4, 1, 9);
    ck_assert_double_eq_tol(resurfi_quadric_eval(&q, p), 2.0 * 9.0 + 0.5 * 16.0, 1e-12);
    ck_assert_double_eq(q.w, 2.5);
}
END_TEST

START_TEST(quadric_corner_of_three_planes)
{
    /* x = 1, y = 2, z = 3: the optimum is the corner, with zero error, exactly (well conditioned: return 1) */
    resurfi_quadric q = resurfi_quadric_plane(v3(1, 0, 0), -1.0, 1.0);
    resurfi_quadric b = resurfi_quadric_plane(v3(0, 1, 0), -2.0, 2.0);
    resurfi_quadric c = resurfi_quadric_plane(v3(0, 0, 1), -3.0, 0.5);
    resurfi_quadric_add(&q, &b);
    resurfi_quadric_add(&q, &c);
    vec3 x;
    ck_assert_int_eq(resurfi_quadric_optimum(&q, v3(10, -4, 7), &x), 1);
    assert_vec_near(x, v3(1, 2, 3), 1e-12);
    ck_assert_double_eq_tol(resurfi_quadric_eval(&q, x), 0.0, 1e-12); /* Q's expanded form cancels: c = 14.5 */

    /* three oblique planes through (−1, 0.5, 2): normals (1,1,0)/√2, (0,1,1)/√2, (1,0,1)/√2 */
    vec3 corner = v3(-1, 0.5, 2);
    vec3 normals[3] = {v3_normalize(v3(1, 1, 0)), v3_normalize(v3(0, 1, 1)), v3_normalize(v3(1, 0, 1))};
    resurfi_quadric o = {{0, 0, 0, 0, 0, 0}, {0, 0, 0}, 0, 0};
    for (int i = 0; i < 3; ++i) {
        resurfi_quadric pi = resurfi_quadric_plane(normals[i], -v3_dot(normals[i], corner), 1.0 + i);
        resurfi_quadric_add(&o, &pi);
    }
    ck_assert_int_eq(resurfi_quadric_optimum(&o, v3(0, 0, 0), &x), 1);
    assert_vec_near(x, corner, 1e-12);
}
END_TEST

START_TEST(quadric_line_and_plane_stay_near_reference)
{
    /* two planes x = 1 and y = 2 meet in the line (1, 2, t): singular in z. The damped solve keeps z of the
     * reference point and moves x and y to the line up to the damping: λ/μ = 1e-3 × trace / 1 = 2e-3 of the step
     * after one solve, squared after the refinement step. */
    resurfi_quadric q = resurfi_quadric_plane(v3(1, 0, 0), -1.0, 1.0);
    resurfi_quadric r = resurfi_quadric_plane(v3(0, 1, 0), -2.0, 1.0);
    resurfi_quadric_add(&q, &r);
    vec3 x;
    ck_assert_int_eq(resurfi_quadric_optimum(&q, v3(0, 0, 5), &x), 2);
    ck_assert_double_eq_tol(x.z, 5.0, 1e-15);
    ck_assert_double_eq_tol(x.x, 1.0, 1e-5 * 1.0);
    ck_assert_double_eq_tol(x.y, 2.0, 1e-5 * 2.0);
    ck_assert(resurfi_quadric_eval(&q, x) < 1e-9);

    /* one plane z = 0: the reference point drops onto it, x and y stay */
    resurfi_quadric p = resurfi_quadric_plane(v3(0, 0, 1), 0.0, 4.0);
    ck_assert_int_eq(resurfi_quadric_optimum(&p, v3(3, -2, 1), &x), 2);
    ck_assert_double_eq_tol(x.x, 3.0, 1e-15);
    ck_assert_double_eq_tol(x.y, -2.0, 1e-15);
    ck_assert_double_eq_tol(x.z, 0.0, 1e-5);
}
END_TEST

START_TEST(quadric_zero_returns_reference)
{
    resurfi_quadric z = {{0, 0, 0, 0, 0, 0}, {0, 0, 0}, 0, 0};
    vec3 x;
    ck_assert_int_eq(resurfi_quadric_optimum(&z, v3(1, 2, 3), &x), 0);
    assert_vec_near(x, v3(1, 2, 3), 0);
    resurfi_quadric bad = resurfi_quadric_plane(v3(1, 0, 0), NAN, 1.0);
    ck_assert_int_eq(resurfi_quadric_optimum(&bad, v3(1, 2, 3), &x), 0);
    assert_vec_near(x, v3(1, 2, 3), 0);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("quadric");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, quadric_plane_is_squared_distance);
    tcase_add_test(tc, quadric_triangle_weighted_by_area);
    tcase_add_test(tc, quadric_sum_adds_distances);
    tcase_add_test(tc, quadric_corner_of_three_planes);
    tcase_add_test(tc, quadric_line_and_plane_stay_near_reference);
    tcase_add_test(tc, quadric_zero_returns_reference);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
