/* Tests for the sag offset's amount (src/simplify/output.c, docs/restoring.md §8, "Why the median depth"), against
 * the analytic surface: a level's vertices are moved off S so that its facets straddle S, and the amount should be
 * the one that makes the level's mean distance to S least. The test scales every vertex's offset from its closest
 * point of S by a common factor λ and measures the mean distance to S (exactly, at 16 equal-area points of each
 * facet) at each λ: the level as made (λ = 1) must be within 2% of the best λ. At 2.5% of the 20k sphere and torus
 * it is within 0.5% (best λ 1.05); the rule before (the unweighted mean of the edges' sags, no median factor) lay
 * 6.6% above the best λ (1.10) on the sphere, and area weights without the median factor 4.4% and 2.9%. At 10% the
 * best λ is 1.10–1.15: there M's own depth under S, which the offset takes off to straddle M, is a tenth of the
 * level's sag. */
#include <math.h>

#include "testutil.h"

/* The mean distance to S of m's facets with every vertex's offset from S scaled by lambda. */
static double scaled_mean(shape_kind kind, const resurf_mesh *m, double lambda)
{
    double sum = 0, total = 0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
        vec3 p[3];
        for (int c = 0; c < 3; ++c) {
            const double *x = m->positions + 3 * (size_t)m->indices[3 * t + (size_t)c];
            double on[3];
            shape_closest(kind, x, on);
            vec3 a = v3(on[0], on[1], on[2]);
            p[c] = v3_madd(a, v3_sub(v3_load(x), a), lambda);
        }
        double area = 0.5 * v3_len(v3_tri_cross(p[0], p[1], p[2])), facet = 0;
        enum { SIDE = 4 };
        for (int i = 0; i < SIDE; ++i)
            for (int j = 0; i + j < SIDE; ++j)
                for (int up = 0; up < 2; ++up) {
                    if (up && i + j == SIDE - 1)
                        continue;
                    double b1 = (i + (up ? 2.0 : 1.0) / 3) / SIDE, b2 = (j + (up ? 2.0 : 1.0) / 3) / SIDE;
                    vec3 q = v3_add(v3_add(v3_scale(p[0], 1 - b1 - b2), v3_scale(p[1], b1)), v3_scale(p[2], b2));
                    double xq[3] = {q.x, q.y, q.z};
                    facet += shape_distance(kind, xq);
                }
        sum += area * facet / (SIDE * SIDE);
        total += area;
    }
    return sum / total;
}

START_TEST(sag_offset_is_best_for_the_mean)
{
    static const shape_kind kinds[] = {SHAPE_SPHERE, SHAPE_TORUS};
    for (int k = 0; k < 2; ++k) {
        resurf_mesh *m = shape_mesh(kinds[k], 20000, 0.3, 1, 0);
        resurf_simplify_options o = resurf_simplify_options_default();
        o.target_ratio = 0.025; /* coarse enough that M's own depth under S, which the offset leaves out, is negligible */
        o.measure_samples = 0;
        resurf_mesh *out = NULL;
        resurf_error e;
        ck_assert_msg(resurf_simplify(m, &o, &out, NULL, &e) == RESURF_OK, "%s", e.message);
        double at_one = scaled_mean(kinds[k], out, 1), best = at_one, best_lambda = 1;
        for (double lambda = 0.5; lambda <= 1.6 + 1e-9; lambda += 0.05) {
            double v = scaled_mean(kinds[k], out, lambda);
            if (v < best)
                best = v, best_lambda = lambda;
        }
        /* the offset matters: without it (λ = 0) the mean is several times larger */
        ck_assert(scaled_mean(kinds[k], out, 0) > 2 * at_one);
        ck_assert_msg(at_one <= 1.02 * best, "shape %d: mean %.4g at the offset made, %.4g at %.2f times it", k,
                      at_one, best, best_lambda);
        resurf_mesh_free(out);
        resurf_mesh_free(m);
    }
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("sag");
    TCase *tc = tcase_create("amount");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, sag_offset_is_best_for_the_mean);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
