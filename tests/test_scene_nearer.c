/* Tests of src/scene_nearer.c: with the default restoring (RESURF_RESTORE_MEASURED), a scene's levels are never
 * farther from the input than the levels `restore none` makes, in the two-sided maximum or the mean.
 * The truths: the same scene made with RESURF_RESTORE_NONE, and resurf_compare of each level's world mesh against
 * level 0 with samples of its own (not the call's report). The scene: the Draco copy of 2CylinderEngine from
 * assimp-testmodels, 29 parts whose budget moves triangles differently in the two modes (restored, its 25% level
 * is nearer the input than the plain one; its 10% level farther), so that its levels come from both. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_internal.h"
#include "scene_lods_internal.h"
#include "testutil.h"

#define ENGINE "/usr/share/assimp/models/glTF2/draco/2CylinderEngine.gltf"
#define LEVELS 2

typedef struct made {
    resurf_scene_lod_report report;
    double hausdorff[LEVELS + 1], mean[LEVELS + 1];
    size_t triangles[LEVELS + 1];
} made;

/* Every mesh's levels have fewer triangles than the level before, and every primitive's. */
static void assert_chains(const resurf_scene *s)
{
    for (size_t m = 0; m < s->mesh_count; ++m) {
        size_t levels = 0;
        for (size_t p = s->mesh_first[m]; p < s->mesh_first[m + 1]; ++p) {
            const resurfi_scene_prim *prim = &s->prims[p];
            levels = prim->lod_count > levels ? prim->lod_count : levels;
            for (size_t k = 0; k < prim->lod_count; ++k)
                ck_assert_uint_lt(prim->lods[k]->triangle_count,
                                  k ? prim->lods[k - 1]->triangle_count : prim->mesh->triangle_count);
        }
        size_t before = SIZE_MAX;
        for (size_t k = 0; k <= levels; ++k) {
            size_t t = 0;
            for (size_t p = s->mesh_first[m]; p < s->mesh_first[m + 1]; ++p) {
                const resurfi_scene_prim *prim = &s->prims[p];
                size_t j = k < prim->lod_count ? k : prim->lod_count;
                t += j ? prim->lods[j - 1]->triangle_count : prim->mesh ? prim->mesh->triangle_count : 0;
            }
            ck_assert_msg(t < before, "mesh %zu: level %zu has %zu triangles, the one before %zu", m, k, t, before);
            before = t;
        }
    }
}

static void make(resurf_restore_mode mode, made *out)
{
    resurf_scene *s = NULL;
    resurf_error e;
    ck_assert_msg(resurf_scene_load(ENGINE, NULL, &s, &e) == RESURF_OK, "%s (assimp-testmodels: tools/setup.sh)",
                  e.message);
    const double ratios[LEVELS] = {0.25, 0.1};
    resurf_simplify_options so = resurf_simplify_options_default();
    so.restore = mode;
    if (tu_light()) /* under a sanitizer or valgrind: a fifth of the samples (the same paths) */
        so.measure_samples /= 5;
    ck_assert_msg(resurf_scene_build_lods(s, ratios, LEVELS, &so, NULL, &out->report, NULL, &e) == RESURF_OK, "%s",
                  e.message);
    ck_assert_uint_eq(out->report.levels, LEVELS + 1);
    assert_chains(s);
    resurf_mesh *full = NULL;
    ck_assert_int_eq(resurf_scene_world_mesh(s, 0, NULL, &full, NULL), RESURF_OK);
    for (int k = 1; k <= LEVELS; ++k) {
        resurf_mesh *level = NULL;
        ck_assert_int_eq(resurf_scene_world_mesh(s, k, NULL, &level, NULL), RESURF_OK);
        resurf_compare_report c = tu_compare(full, level, tu_light() ? 50000 : 200000);
        out->hausdorff[k] = c.hausdorff, out->mean[k] = c.mean, out->triangles[k] = level->triangle_count;
        resurf_mesh_free(level);
    }
    resurf_mesh_free(full);
    resurf_scene_free(s);
}

START_TEST(scene_levels_never_farther_than_plain)
{
    made d, n;
    make(RESURF_RESTORE_MEASURED, &d);
    make(RESURF_RESTORE_NONE, &n);
    int nearer = 0, plain = 0;
    for (int k = 1; k <= LEVELS; ++k) {
        printf("level %d: default %zu triangles, H %.4e, mean %.4e (plain: %d); none %zu, H %.4e, mean %.4e\n", k,
               d.triangles[k], d.hausdorff[k], d.mean[k], d.report.level_plain[k], n.triangles[k], n.hausdorff[k],
               n.mean[k]);
        /* By the call's own measure, exactly; by an independent one, within its sampling noise. */
        ck_assert_double_le(d.report.level_error_rel[k], n.report.level_error_rel[k]);
        ck_assert_double_le(d.report.level_mean_rel[k], n.report.level_mean_rel[k]);
        ck_assert_double_le(d.hausdorff[k], 1.02 * n.hausdorff[k]);
        ck_assert_double_le(d.mean[k], 1.02 * n.mean[k]);
        nearer += d.hausdorff[k] <= n.hausdorff[k] && d.mean[k] < 0.95 * n.mean[k];
        plain += d.report.level_plain[k];
    }
    /* Restoration's gain is kept where it is one, and the plain level taken where it is not (with the full samples:
     * a fifth of them, under a sanitizer, decides otherwise where the two are within a few percent). */
    if (!tu_light()) {
        ck_assert_int_ge(nearer, 1);
        ck_assert_int_ge(plain, 1);
    }
}
END_TEST

/* The plain pass's levels that are the default's (resurfi_find_twin_levels, whose figures are copied rather than
 * measured again): level k is one where every primitive shows the same surface, byte for byte, with the same
 * figures, at the same place in its chain; a copy counts as the same, one moved position or one report figure does
 * not. Two primitives: the first with two levels, the second ended after one (it shows its level 1 at level 2). */
START_TEST(twin_levels_are_the_same_surfaces)
{
    resurf_mesh *a1 = shape_mesh(SHAPE_SPHERE, 400, 0.1, 1, 0), *a2 = shape_mesh(SHAPE_SPHERE, 100, 0.1, 2, 0);
    resurf_mesh *b1 = shape_mesh(SHAPE_TORUS, 200, 0.1, 3, 0), *a1c = NULL, *a2c = NULL, *b1c = NULL;
    ck_assert(a1 && a2 && b1);
    ck_assert_int_eq(resurf_mesh_clone(a1, &a1c, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_mesh_clone(a2, &a2c, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_mesh_clone(b1, &b1c, NULL), RESURF_OK);
    resurf_mesh *plain_a[2] = {a1, a2}, *plain_b[2] = {b1, NULL}, *d_a[2] = {a1c, a2c}, *d_b[2] = {b1c, NULL};
    resurf_mesh *const *plain_chains[2] = {plain_a, plain_b}, *const *d_chains[2] = {d_a, d_b};
    size_t kept[2] = {2, 1};
    resurf_simplify_report plain_r[4], d_r[4];
    memset(plain_r, 0, sizeof plain_r);
    for (int i = 0; i < 4; ++i)
        plain_r[i].result_to_input_max = plain_r[i].input_to_result_max = 0.01 * (i + 1),
        plain_r[i].result_to_input_mean = plain_r[i].input_to_result_mean = 0.001 * (i + 1);
    memcpy(d_r, plain_r, sizeof d_r);
    resurfi_lod_levels_view plain = {plain_chains, kept, plain_r, NULL, 2}, d = {d_chains, kept, d_r, NULL, 2};
    resurf_scene scene;
    memset(&scene, 0, sizeof scene);
    scene.prim_count = 2;
    bool twin[RESURF_SCENE_MAX_LEVELS] = {0};

    resurfi_find_twin_levels(&scene, &plain, &d, 3, twin);
    ck_assert(twin[1] && twin[2]); /* copies throughout */
    const double was = a2c->positions[7];
    a2c->positions[7] += 1e-12;    /* the first primitive's level 2 moved: level 1 alike, level 2 not */
    resurfi_find_twin_levels(&scene, &plain, &d, 3, twin);
    ck_assert(twin[1] && !twin[2]);
    d_r[2].input_to_result_mean = nextafter(d_r[2].input_to_result_mean, 1); /* the second's level 1 figure */
    resurfi_find_twin_levels(&scene, &plain, &d, 3, twin);
    ck_assert(!twin[1] && !twin[2]);
    d_r[2] = plain_r[2];
    size_t longer[2] = {2, 2}; /* the default's second primitive not ended: another place in its chain */
    d_b[1] = b1c;
    d.kept = longer;
    a2c->positions[7] = was;
    resurfi_find_twin_levels(&scene, &plain, &d, 3, twin);
    ck_assert(twin[1] && !twin[2]);
    resurf_mesh_free(a1), resurf_mesh_free(a2), resurf_mesh_free(b1);
    resurf_mesh_free(a1c), resurf_mesh_free(a2c), resurf_mesh_free(b1c);
}
END_TEST

static Suite *make_suite(void)
{
    Suite *s = suite_create("scene_nearer");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 600);
    tcase_add_test(tc, scene_levels_never_farther_than_plain);
    tcase_add_test(tc, twin_levels_are_the_same_surfaces);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
