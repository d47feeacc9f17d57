/* src/side_nearby.c: one side of a distance measured to only the part of the other surface near the points gives
 * the figure of the whole other surface, bit for bit, whatever margin was guessed. */
#include <string.h>

#include "testutil.h"

/* resurfi_side_max_nearby against resurfi_side_max over a tree of the whole other surface: the same figure bit for
 * bit whatever the margin guessed. The other surface is the unit grid (z = 0) and a wall x = 0.2 across it; the
 * measured patch [0.1, 0.3]² at z = 0.05 lies 0.05 above the grid, nearer than the wall (up to 0.1) at its edges.
 * With a margin of 0 only the wall meets the patch's box (0.1 > 0: measured again with the grid), a margin of 1
 * takes both at once, and a patch far from everything first finds no triangle at all. */
START_TEST(side_max_nearby_is_the_whole_side)
{
    resurf_mesh *grid = tu_grid(40);
    size_t gv = grid->vertex_count, gt = grid->triangle_count;
    resurf_mesh *to = NULL;
    ck_assert_int_eq(resurf_mesh_create(gv + 3, gt + 1, 0, &to, NULL), RESURF_OK);
    memcpy(to->positions, grid->positions, 3 * gv * sizeof(double));
    memcpy(to->indices, grid->indices, 3 * gt * sizeof(uint32_t));
    const double wall[9] = {0.2, -1, -1, 0.2, 2, -1, 0.2, 0.5, 2};
    memcpy(to->positions + 3 * gv, wall, sizeof wall);
    for (int k = 0; k < 3; ++k)
        to->indices[3 * gt + (size_t)k] = (uint32_t)(gv + (size_t)k);
    resurfi_bvh *whole = NULL;
    ck_assert_int_eq(resurfi_bvh_build(NULL, to->positions, to->vertex_count, to->indices, to->triangle_count, &whole),
                     RESURF_OK);
    const double offsets[2][3] = {{0.1, 0.1, 0.05}, {10, 10, 10}};
    for (int o = 0; o < 2; ++o) {
        resurf_mesh *patch = tu_grid(4);
        for (size_t v = 0; v < patch->vertex_count; ++v)
            for (int k = 0; k < 3; ++k)
                patch->positions[3 * v + (size_t)k] =
                    (k < 2 ? 0.2 * patch->positions[3 * v + (size_t)k] : 0) + offsets[o][k];
        for (int facets = 0; facets <= 1; ++facets) { /* with the patch's facet points too */
            double truth = NAN;
            ck_assert_int_eq(resurfi_side_max(NULL, patch, 3000, 7, facets, whole, 1, &truth), RESURF_OK);
            if (o == 0)
                ck_assert_double_eq_tol(truth, 0.05, 1e-12); /* the grid, not the wall, is nearest everywhere */
            const double margins[] = {0, 0.01, 1, INFINITY};
            for (size_t i = 0; i < sizeof margins / sizeof *margins; ++i)
                for (unsigned threads = 1; threads <= 2; ++threads) {
                    double d = NAN;
                    ck_assert_int_eq(resurfi_side_max_nearby(NULL, patch, 3000, 7, facets, to, margins[i], threads,
                                                             &d),
                                     RESURF_OK);
                    ck_assert_double_eq(d, truth);
                }
        }
        resurf_mesh_free(patch);
    }
    resurfi_bvh_free(whole);
    resurf_mesh_free(grid);
    resurf_mesh_free(to);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("side_nearby");
    TCase *tc = tcase_create("side_nearby");
    tcase_add_test(tc, side_max_nearby_is_the_whole_side);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN();
