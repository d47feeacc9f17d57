/* Tests for src/glide.c, the gliding-normal displacement δ_j: on a sphere with exact normals each corner alone gives
 * the exact displacement onto the sphere (max algorithm outside-in, min algorithm for inward normals, the
 * normal-section variant for both without being told), on a plane δ is the signed distance, a corner at the point
 * itself gives 0, the wrong max/min choice is wrong by 2|u| tan(α/2), and the normal section ignores a normal's
 * twist out of the chord's plane (a cylinder's axial chords are exact for both). */
#include <math.h>

#include "testutil.h"

static vec3 random_unit(uint64_t *rng)
{
    for (;;) {
        vec3 v = v3(2 * shape_rand_unit(rng) - 1, 2 * shape_rand_unit(rng) - 1, 2 * shape_rand_unit(rng) - 1);
        double l = v3_len(v);
        if (l > 0.1 && l <= 1)
            return v3_scale(v, 1 / l);
    }
}

/* A sphere of centre c and radius R; p on a line through c along n_opt (in or out); a corner p_j on the sphere
 * near where the line meets it. With outward normals the max algorithm gives p + δ n_opt on the sphere, with
 * inward normals (seen from inside, a concave surface) the min algorithm does; in both cases n_opt is the
 * interpolated normal there, so it points out for the first and in for the second. */
START_TEST(sphere_each_corner_is_exact)
{
    uint64_t rng = 3;
    for (int it = 0; it < 1000; ++it) {
        vec3 c = v3(3 * shape_rand_unit(&rng), -2 * shape_rand_unit(&rng), shape_rand_unit(&rng));
        double R = 0.2 + 5 * shape_rand_unit(&rng);
        vec3 dir = random_unit(&rng);
        double radius = R * (0.7 + 0.6 * shape_rand_unit(&rng)); /* p inside or outside the sphere */
        vec3 p = v3_madd(c, dir, radius);
        /* corner: a nearby direction, up to ~20° away */
        vec3 dj = v3_normalize(v3_madd(dir, random_unit(&rng), 0.35 * shape_rand_unit(&rng)));
        vec3 pj = v3_madd(c, dj, R);
        double exact = R - radius; /* along dir */

        double d_max = resurfi_glide_paper(p, pj, dj, dir, +1);
        ck_assert_msg(fabs(d_max - exact) < 1e-14 * (1 + R), "max: %.17g, expected %.17g", d_max, exact);
        double d_ns = resurfi_glide_normal_section(p, pj, dj, dir);
        ck_assert_msg(fabs(d_ns - exact) < 1e-14 * (1 + R), "normal section: %.17g, expected %.17g", d_ns, exact);
        ck_assert(fabs(v3_dist(v3_madd(p, dir, d_max), c) - R) < 1e-14 * (1 + R));

        /* inward normals: the displacement along −dir is the same distance */
        vec3 in = v3_neg(dir), nin = v3_neg(dj);
        double d_min = resurfi_glide_paper(p, pj, nin, in, -1);
        ck_assert_msg(fabs(d_min + exact) < 1e-14 * (1 + R), "min: %.17g, expected %.17g", d_min, -exact);
        ck_assert(fabs(resurfi_glide_normal_section(p, pj, nin, in) + exact) < 1e-14 * (1 + R));

        /* the wrong choice is off by 2 |u| tan(α/2) */
        vec3 chord = v3_sub(pj, p);
        double u = v3_len(v3_madd(chord, dir, -v3_dot(chord, dir)));
        double alpha = acos(fmin(1, v3_dot(dir, dj)));
        double wrong = resurfi_glide_paper(p, pj, dj, dir, -1);
        ck_assert(fabs((d_max - wrong) - 2 * u * tan(alpha / 2)) < 1e-13 * (1 + R));
    }
}
END_TEST

/* A plane with its normal everywhere: δ is the signed distance from p to the plane along the normal, whatever the
 * side rule and for both formulas. */
START_TEST(plane_is_signed_distance)
{
    uint64_t rng = 5;
    for (int it = 0; it < 200; ++it) {
        vec3 n = random_unit(&rng);
        vec3 o = v3(shape_rand_unit(&rng), shape_rand_unit(&rng), shape_rand_unit(&rng));
        vec3 t1 = v3_normalize(v3_cross(n, random_unit(&rng)));
        vec3 t2 = v3_cross(n, t1);
        vec3 pj = v3_madd(v3_madd(o, t1, 2 * shape_rand_unit(&rng) - 1), t2, 2 * shape_rand_unit(&rng) - 1);
        double h = 2 * shape_rand_unit(&rng) - 1;
        vec3 p = v3_madd(v3_madd(o, t1, shape_rand_unit(&rng)), n, h);
        ck_assert_double_eq_tol(resurfi_glide_paper(p, pj, n, n, +1), -h, 1e-14);
        ck_assert_double_eq_tol(resurfi_glide_paper(p, pj, n, n, -1), -h, 1e-14);
        ck_assert_double_eq_tol(resurfi_glide_normal_section(p, pj, n, n), -h, 1e-14);
    }
}
END_TEST

START_TEST(corner_at_the_point_gives_zero)
{
    vec3 p = v3(1, 2, 3);
    vec3 n = v3_normalize(v3(1, 1, 1)), nj = v3_normalize(v3(1, 0.5, 1));
    ck_assert(resurfi_glide_paper(p, p, nj, n, +1) == 0);
    ck_assert(resurfi_glide_paper(p, p, nj, n, -1) == 0);
    ck_assert(resurfi_glide_normal_section(p, p, nj, n) == 0);
}
END_TEST

/* Unit cylinder x² + y² = 1 with exact normals; p on a radial line. A corner straight along the axis from where
 * the line meets the cylinder has the same normal: δ is exact for both formulas. A corner around the cylinder
 * (a circle) is exact for both too. */
START_TEST(cylinder_axial_and_circular_chords)
{
    vec3 dir = v3(1, 0, 0);
    for (double rho = 0.8; rho < 1.25; rho += 0.1) {
        vec3 p = v3(rho, 0, 0);
        vec3 pj = v3(1, 0, 0.3), nj = v3(1, 0, 0);
        ck_assert_double_eq_tol(resurfi_glide_paper(p, pj, nj, dir, +1), 1 - rho, 1e-15);
        ck_assert_double_eq_tol(resurfi_glide_normal_section(p, pj, nj, dir), 1 - rho, 1e-15);
        double th = 0.3;
        vec3 pk = v3(cos(th), sin(th), 0), nk = v3(cos(th), sin(th), 0);
        ck_assert_double_eq_tol(resurfi_glide_paper(p, pk, nk, dir, +1), 1 - rho, 1e-15);
        ck_assert_double_eq_tol(resurfi_glide_normal_section(p, pk, nk, dir), 1 - rho, 1e-15);
    }
}
END_TEST

/* A normal tilted only out of the chord's plane (a twist, no bending along the chord): the chord's normal section
 * is straight, so the normal section gives the straight part N_opt·c, while formula (2) counts the twist as a
 * bend of angle α and adds |u| tan(α/2). */
START_TEST(normal_section_ignores_twist)
{
    vec3 p = v3(0, 0, 0.2), dir = v3(0, 0, 1);
    vec3 pj = v3(0.5, 0, 0); /* chord's tangential part along x */
    double a = 0.4;
    vec3 nj = v3(0, sin(a), cos(a)); /* tilted about x only */
    ck_assert_double_eq_tol(resurfi_glide_normal_section(p, pj, nj, dir), -0.2, 1e-15);
    ck_assert_double_eq_tol(resurfi_glide_paper(p, pj, nj, dir, +1), -0.2 + 0.5 * tan(a / 2), 1e-15);
    /* bending in the chord's plane: both agree, and the normal section picks the sign itself */
    vec3 bend_out = v3(sin(a), 0, cos(a)), bend_in = v3(-sin(a), 0, cos(a));
    ck_assert_double_eq_tol(resurfi_glide_normal_section(p, pj, bend_out, dir),
                            resurfi_glide_paper(p, pj, bend_out, dir, +1), 1e-15);
    ck_assert_double_eq_tol(resurfi_glide_normal_section(p, pj, bend_in, dir),
                            resurfi_glide_paper(p, pj, bend_in, dir, -1), 1e-15);
}
END_TEST

/* Normals 90° or more apart carry no arc: only the straight part is returned, never an infinity. */
START_TEST(opposite_normals_stay_finite)
{
    vec3 p = v3(0, 0, 0.2), dir = v3(0, 0, 1), pj = v3(0.5, 0, 0);
    ck_assert_double_eq_tol(resurfi_glide_paper(p, pj, v3(0, 0, -1), dir, +1), -0.2, 1e-15);
    ck_assert_double_eq_tol(resurfi_glide_normal_section(p, pj, v3(0, 0, -1), dir), -0.2, 1e-15);
    ck_assert(isfinite(resurfi_glide_normal_section(p, pj, v3(0, 1, 0), dir)));
    /* 100° apart is past the arc model too (tan 50° would still be finite, but the corner is on another sheet) */
    vec3 folded = v3(sin(100 * M_PI / 180), 0, cos(100 * M_PI / 180));
    ck_assert_double_eq_tol(resurfi_glide_paper(p, pj, folded, dir, +1), -0.2, 1e-15);
    ck_assert_double_eq_tol(resurfi_glide_normal_section(p, pj, folded, dir), -0.2, 1e-15);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("glide");
    TCase *tc = tcase_create("glide");
    tcase_add_test(tc, sphere_each_corner_is_exact);
    tcase_add_test(tc, plane_is_signed_distance);
    tcase_add_test(tc, corner_at_the_point_gives_zero);
    tcase_add_test(tc, cylinder_axial_and_circular_chords);
    tcase_add_test(tc, normal_section_ignores_twist);
    tcase_add_test(tc, opposite_normals_stay_finite);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
