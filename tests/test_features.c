/* Tests for what the simplifier keeps in place (src/simplify/setup.c, collapse.c, output.c): vertices the caller
 * locks, against the input's own coordinates (a locked position is in every level bit-exact). */
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

/* A position is locked when any of its vertices is: the sphere as a triangle soup (three vertices per triangle),
 * one copy of each chosen position locked. */
START_TEST(vertex_lock_one_copy_locks_the_position)
{
    resurf_mesh *welded = shape_mesh(SHAPE_SPHERE, 2000, 0.3, 9, 0);
    ck_assert_ptr_nonnull(welded);
    size_t nt = welded->triangle_count;
    resurf_mesh *soup = NULL;
    ck_assert_int_eq(resurf_mesh_create(3 * nt, nt, 0, &soup, NULL), RESURF_OK);
    for (size_t c = 0; c < 3 * nt; ++c) {
        memcpy(soup->positions + 3 * c, welded->positions + 3 * welded->indices[c], 3 * sizeof(double));
        soup->indices[c] = (uint32_t)c;
    }
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

Suite *make_suite(void)
{
    Suite *s = suite_create("features");
    TCase *lock = tcase_create("lock");
    tcase_add_test(lock, vertex_lock_keeps_positions_exactly);
    tcase_add_test(lock, vertex_lock_one_copy_locks_the_position);
    suite_add_tcase(s, lock);
    return s;
}

RESURF_TEST_MAIN()
