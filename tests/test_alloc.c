/* Caller-supplied allocators (resurf_allocator): every heap block a call makes goes through the callbacks, each one
 * comes back, a failing callback makes the call return RESURF_ERR_OUT_OF_MEMORY with the caller's data intact, and
 * no call given an allocator touches the C heap itself.
 *
 * The counting allocator puts a header with the block's size in front of each block, so that live bytes can be
 * tracked across reallocate; its counters are atomic because the calls' worker threads allocate at the same time.
 * This binary is linked with -Wl,--wrap for malloc and friends (tests/meson.build): the library's own C-heap calls
 * then go through __wrap_malloc & co. below and are counted while a call runs. The counting allocator itself uses
 * __real_malloc, so it is not counted. Calls to malloc made inside the C library (locales, threads) and by the C++
 * standard library are not wrapped: they are not resurf's allocations. */
#include <stdalign.h>
#include <stdatomic.h>
#include <stddef.h>
#include <string.h>

#include "testutil.h"

/* ---- the wrapped C heap -------------------------------------------------------------------------------------- */

void *__real_malloc(size_t size);
void *__real_calloc(size_t count, size_t size);
void *__real_realloc(void *p, size_t size);
void __real_free(void *p);
void *__wrap_malloc(size_t size);
void *__wrap_calloc(size_t count, size_t size);
void *__wrap_realloc(void *p, size_t size);
void __wrap_free(void *p);

static atomic_int heap_watch;          /* 1 while a call that was given an allocator runs */
static atomic_size_t heap_calls;       /* C-heap calls seen while watching */

static void heap_seen(void)
{
    if (atomic_load(&heap_watch))
        atomic_fetch_add(&heap_calls, 1);
}
void *__wrap_malloc(size_t size) { heap_seen(); return __real_malloc(size); }
void *__wrap_calloc(size_t count, size_t size) { heap_seen(); return __real_calloc(count, size); }
void *__wrap_realloc(void *p, size_t size) { heap_seen(); return __real_realloc(p, size); }
void __wrap_free(void *p)
{
    if (p)
        heap_seen();
    __real_free(p);
}

/* ---- the counting allocator ---------------------------------------------------------------------------------- */

typedef struct counter {
    atomic_size_t calls;      /* allocate + reallocate calls (failed ones included) */
    atomic_size_t releases;
    atomic_size_t live_blocks;
    atomic_llong live_bytes;
    atomic_size_t fail_at;    /* the fail_at-th allocate/reallocate call returns NULL; 0 = none */
    atomic_size_t failed;     /* calls that returned NULL */
    atomic_int misuse;        /* a size of 0 or a NULL block was passed (checked outside the callbacks: Check's
                                 assertions themselves allocate) */
} counter;

#define HEADER ((size_t)alignof(max_align_t) > sizeof(size_t) ? (size_t)alignof(max_align_t) : sizeof(size_t))

static int should_fail(counter *c)
{
    size_t n = atomic_fetch_add(&c->calls, 1) + 1;
    if (n == atomic_load(&c->fail_at)) {
        atomic_fetch_add(&c->failed, 1);
        return 1;
    }
    return 0;
}

static void *count_allocate(void *user, size_t size)
{
    counter *c = user;
    if (size == 0)
        atomic_store(&c->misuse, 1);
    if (should_fail(c))
        return NULL;
    unsigned char *p = __real_malloc(HEADER + size);
    if (!p)
        return NULL;
    memcpy(p, &size, sizeof size);
    atomic_fetch_add(&c->live_blocks, 1);
    atomic_fetch_add(&c->live_bytes, (long long)size);
    return p + HEADER;
}

static void *count_reallocate(void *user, void *block, size_t size)
{
    counter *c = user;
    if (!block || size == 0) {
        atomic_store(&c->misuse, 1);
        return NULL;
    }
    if (should_fail(c))
        return NULL;
    unsigned char *p = (unsigned char *)block - HEADER;
    size_t old;
    memcpy(&old, p, sizeof old);
    unsigned char *q = __real_realloc(p, HEADER + size);
    if (!q)
        return NULL;
    memcpy(q, &size, sizeof size);
    atomic_fetch_add(&c->live_bytes, (long long)size - (long long)old);
    return q + HEADER;
}

static void count_release(void *user, void *block)
{
    counter *c = user;
    if (!block) {
        atomic_store(&c->misuse, 1);
        return;
    }
    unsigned char *p = (unsigned char *)block - HEADER;
    size_t size;
    memcpy(&size, p, sizeof size);
    atomic_fetch_add(&c->releases, 1);
    atomic_fetch_sub(&c->live_blocks, 1);
    atomic_fetch_sub(&c->live_bytes, (long long)size);
    __real_free(p);
}

static counter the_counter;
static const resurf_allocator counting = {count_allocate, count_reallocate, count_release, &the_counter};

/* Load options whose allocator is the counting one. */
static resurf_load_options counted_load(void)
{
    resurf_load_options o = resurf_load_options_default();
    o.allocator = &counting;
    return o;
}

static void counter_reset(size_t fail_at)
{
    atomic_store(&the_counter.calls, 0);
    atomic_store(&the_counter.releases, 0);
    atomic_store(&the_counter.failed, 0);
    atomic_store(&the_counter.fail_at, fail_at);
}

/* Ends the part of a run that counts: later allocations (checks of the result) neither fail nor count. */
static size_t call_allocations;
static void end_call(void)
{
    atomic_store(&the_counter.fail_at, 0);
    call_allocations = atomic_load(&the_counter.calls);
}

static void assert_nothing_live(void)
{
    ck_assert_int_eq(atomic_load(&the_counter.misuse), 0);
    ck_assert_uint_eq(atomic_load(&the_counter.live_blocks), 0);
    ck_assert_int_eq(atomic_load(&the_counter.live_bytes), 0);
}

/* Watches the C heap around one call. */
static void watch_begin(void)
{
    atomic_store(&heap_calls, 0);
    atomic_store(&heap_watch, 1);
}
static size_t watch_end(void)
{
    atomic_store(&heap_watch, 0);
    return atomic_load(&heap_calls);
}
/* Runs one call while watching; heap_during receives the C-heap calls it made. No Check assertion may run inside
 * the window: they allocate themselves. */
static resurf_status watched_status;
static size_t heap_during;
#define WATCHED(call) (watch_begin(), watched_status = (call), heap_during = watch_end(), watched_status)

/* ---- fixtures ------------------------------------------------------------------------------------------------ */

static int same_mesh(const resurf_mesh *a, const resurf_mesh *b)
{
    return a->vertex_count == b->vertex_count && a->triangle_count == b->triangle_count &&
           memcmp(a->positions, b->positions, 3 * a->vertex_count * sizeof(double)) == 0 &&
           memcmp(a->indices, b->indices, 3 * a->triangle_count * sizeof(uint32_t)) == 0;
}

static int mesh_valid(const resurf_mesh *m)
{
    resurf_validate_report v;
    return resurf_mesh_validate(m, &v, NULL) == RESURF_OK && resurf_validation_ok(&v);
}

/* The bytes of m saved in a format (read back from a temporary file). */
static char *saved_bytes(const resurf_mesh *m, const char *name, int binary, size_t *size)
{
    char *dir = tu_tempdir();
    char *path = tu_path(dir, name);
    resurf_save_options so = resurf_save_options_default();
    so.binary = binary;
    ck_assert_int_eq(resurf_mesh_save(m, path, &so, NULL), RESURF_OK);
    char *bytes = tu_read_file(path, size);
    ck_assert_ptr_nonnull(bytes);
    free(path);
    tu_rmtree(dir);
    free(dir);
    return bytes;
}

/* ---- (a) every block goes through the allocator and comes back ----------------------------------------------- */

/* Meshes made with an allocator record it, and resurf_mesh_free gives every block back to it; clones use the
 * allocator asked for, else the source mesh's. */
START_TEST(alloc_meshes_remember_their_allocator)
{
    counter_reset(0);
    resurf_mesh *m = NULL, *c = NULL, *h = NULL;
    unsigned attrs = RESURF_ATTR_NORMALS | RESURF_ATTR_COLORS | RESURF_ATTR_TEXCOORD0;
    ck_assert_int_eq(WATCHED(resurf_mesh_create_with(10, 4, attrs, &counting, &m, NULL)), RESURF_OK);
    ck_assert_uint_eq(heap_during, 0);
    ck_assert_int_eq(WATCHED(resurf_mesh_add_extra(m, "weight", 2, NULL, NULL)), RESURF_OK);
    ck_assert_uint_eq(heap_during, 0);
    ck_assert_int_eq(WATCHED(resurf_mesh_clone(m, &c, NULL)), RESURF_OK);
    ck_assert_uint_eq(heap_during, 0);
    ck_assert_ptr_eq(m->allocator.user, &the_counter);
    ck_assert_ptr_eq(c->allocator.user, &the_counter);
    /* struct + positions, indices, normals, colors, texcoords + extras list and data, each */
    ck_assert_uint_eq(atomic_load(&the_counter.live_blocks), 2 * 8);
    ck_assert_int_eq(atomic_load(&the_counter.live_bytes) > 2 * (long long)(10 * 12 * sizeof(double)), 1);

    /* A C-heap copy of an allocator mesh: a zeroed allocator struct names the C heap. */
    const resurf_allocator heap = {0};
    ck_assert_int_eq(resurf_mesh_clone_with(m, &heap, &h, NULL), RESURF_OK);
    ck_assert_ptr_null(h->allocator.allocate);
    ck_assert_int_eq(same_mesh(m, h), 1);
    ck_assert_uint_eq(atomic_load(&the_counter.live_blocks), 2 * 8);
    resurf_mesh_free(h);
    watch_begin();
    resurf_mesh_free(m);
    resurf_mesh_free(c);
    ck_assert_uint_eq(watch_end(), 0);
    assert_nothing_live();
    ck_assert_uint_eq(atomic_load(&the_counter.releases), 2 * 8);

    /* The watch does see the library's own C-heap calls: a mesh made without an allocator takes at least three
     * blocks (struct, positions, indices) from malloc. */
    ck_assert_int_eq(WATCHED(resurf_mesh_create(3, 1, 0, &h, NULL)), RESURF_OK);
    ck_assert_uint_ge(heap_during, 3);
    resurf_mesh_free(h);

    /* A heap mesh cloned into the allocator, and back. */
    resurf_mesh *t = tu_tetrahedron();
    ck_assert_int_eq(resurf_mesh_clone_with(t, &counting, &c, NULL), RESURF_OK);
    ck_assert_uint_eq(atomic_load(&the_counter.live_blocks), 3);
    ck_assert_int_eq(same_mesh(t, c), 1);
    resurf_mesh_free(c);
    resurf_mesh_free(t);
    assert_nothing_live();
}
END_TEST

/* An allocator without all three callbacks is refused where it is given. */
START_TEST(alloc_incomplete_allocator_is_refused)
{
    resurf_allocator half = counting;
    half.reallocate = NULL;
    resurf_mesh *m = NULL;
    resurf_error error;
    ck_assert_int_eq(resurf_mesh_create_with(3, 1, 0, &half, &m, &error), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(m);
    resurf_load_options lo = resurf_load_options_default();
    lo.allocator = &half;
    ck_assert_int_eq(resurf_mesh_load_memory("v 0 0 0\n", 8, RESURF_FORMAT_OBJ, NULL, &lo, &m, &error),
                     RESURF_ERR_INVALID_OPTIONS);
    ck_assert(strstr(error.message, "allocator") != NULL);
    resurf_mesh *t = tu_tetrahedron();
    resurf_smooth_options so = resurf_smooth_options_default();
    so.allocator = &half;
    ck_assert_int_eq(resurf_smooth(t, &so, NULL), RESURF_ERR_INVALID_OPTIONS);
    resurf_restore_options ro = resurf_restore_options_default();
    ro.allocator = &half;
    ck_assert_int_eq(resurf_restore(t, t, &ro, NULL, NULL), RESURF_ERR_INVALID_OPTIONS);
    resurf_simplify_options sio = resurf_simplify_options_default();
    sio.allocator = &half;
    ck_assert_int_eq(resurf_simplify(t, &sio, &m, NULL, NULL), RESURF_ERR_INVALID_OPTIONS);
    resurf_mesh_free(t);
}
END_TEST

/* The whole pipeline with the counting allocator: load, validate, repair, restore on 2 threads, smooth, compare,
 * simplify_lods. Each call uses the allocator (count > 0), makes no C-heap call of its own, and after the meshes
 * are freed nothing is left. */
START_TEST(alloc_pipeline_uses_only_the_allocator)
{
    resurf_mesh *sphere = shape_mesh(SHAPE_SPHERE, 2000, 0.2, 7, 0);
    ck_assert_ptr_nonnull(sphere);
    size_t size = 0;
    char *obj = saved_bytes(sphere, "s.obj", 0, &size);
    counter_reset(0);
    resurf_error error;

    /* load: the new mesh records the allocator */
    resurf_load_options lo = counted_load();
    resurf_mesh *m = NULL;
    ck_assert_int_eq(WATCHED(resurf_mesh_load_memory(obj, size, RESURF_FORMAT_OBJ, "s.obj", &lo, &m, &error)),
                     RESURF_OK);
    ck_assert_uint_eq(heap_during, 0);
    ck_assert_ptr_eq(m->allocator.user, &the_counter);
    ck_assert_uint_eq(m->vertex_count, sphere->vertex_count);
    size_t after_load = atomic_load(&the_counter.calls);
    ck_assert_uint_gt(after_load, 0);

    /* validate: no options, so the mesh's allocator */
    resurf_validate_report v;
    ck_assert_int_eq(WATCHED(resurf_mesh_validate(m, &v, &error)), RESURF_OK);
    ck_assert_uint_eq(heap_during, 0);
    ck_assert_uint_eq(v.boundary_edges, 0);
    size_t after_validate = atomic_load(&the_counter.calls);
    ck_assert_uint_gt(after_validate, after_load);

    /* repair (weld with a tolerance: the clustering path) */
    resurf_repair_options rpo = resurf_repair_options_default();
    rpo.weld_tolerance_rel = 1e-9;
    rpo.allocator = &counting;
    ck_assert_int_eq(WATCHED(resurf_mesh_repair(m, &rpo, NULL, &error)), RESURF_OK);
    ck_assert_uint_eq(heap_during, 0);
    size_t after_repair = atomic_load(&the_counter.calls);
    ck_assert_uint_gt(after_repair, after_validate);

    /* smooth the loaded mesh (its own allocator, no options allocator), then restore it onto the sphere on 2
     * threads with the allocator given in the options while the original is a C-heap mesh */
    resurf_smooth_options smo = resurf_smooth_options_default();
    smo.method = RESURF_SMOOTH_TAUBIN_COT;
    ck_assert_int_eq(WATCHED(resurf_smooth(m, &smo, &error)), RESURF_OK);
    ck_assert_uint_eq(heap_during, 0);
    size_t after_smooth = atomic_load(&the_counter.calls);
    ck_assert_uint_gt(after_smooth, after_repair);

    resurf_restore_options ro = resurf_restore_options_default();
    ro.threads = 2;
    ro.allocator = &counting;
    resurf_restore_report rr;
    ck_assert_int_eq(WATCHED(resurf_restore(sphere, m, &ro, &rr, &error)), RESURF_OK);
    ck_assert_uint_eq(heap_during, 0);
    ck_assert_uint_gt(rr.moved, 0);
    for (size_t i = 0; i < m->vertex_count; ++i) /* restored onto the unit sphere again */
        ck_assert_double_lt(fabs(v3_len(resurfi_position(m, (uint32_t)i)) - 1), 5e-3);
    size_t after_restore = atomic_load(&the_counter.calls);
    ck_assert_uint_gt(after_restore, after_smooth);

    /* compare: ref is the allocator mesh, no options allocator */
    resurf_compare_options co = resurf_compare_options_default();
    co.samples = 5000;
    co.threads = 2;
    resurf_compare_report metrics;
    ck_assert_int_eq(WATCHED(resurf_compare(m, sphere, &co, &metrics, NULL, &error)), RESURF_OK);
    ck_assert_uint_eq(heap_during, 0);
    ck_assert_double_lt(metrics.hausdorff, 0.05);
    size_t after_compare = atomic_load(&the_counter.calls);
    ck_assert_uint_gt(after_compare, after_restore);

    /* simplify_lods of a C-heap mesh into allocator meshes */
    resurf_simplify_options sio = resurf_simplify_options_default();
    sio.threads = 2;
    sio.measure_samples = 2000;
    sio.allocator = &counting;
    const double ratios[2] = {0.5, 0.2};
    resurf_mesh *lods[2] = {NULL, NULL};
    ck_assert_int_eq(WATCHED(resurf_simplify_lods(sphere, ratios, 2, &sio, lods, NULL, &error)), RESURF_OK);
    ck_assert_uint_eq(heap_during, 0);
    ck_assert_uint_gt(atomic_load(&the_counter.calls), after_compare);
    for (int i = 0; i < 2; ++i) {
        ck_assert_ptr_eq(lods[i]->allocator.user, &the_counter);
        ck_assert_int_eq(mesh_valid(lods[i]), 1);
    }

    /* simplify of the allocator mesh with no options allocator: the output takes the input's */
    resurf_simplify_options sio2 = resurf_simplify_options_default();
    sio2.measure_samples = 0;
    resurf_mesh *half = NULL;
    size_t before = atomic_load(&the_counter.calls);
    ck_assert_int_eq(WATCHED(resurf_simplify(m, &sio2, &half, NULL, &error)), RESURF_OK);
    ck_assert_uint_eq(heap_during, 0);
    ck_assert_uint_gt(atomic_load(&the_counter.calls), before);
    ck_assert_ptr_eq(half->allocator.user, &the_counter);

    ck_assert_uint_gt(atomic_load(&the_counter.live_blocks), 0);
    watch_begin();
    resurf_mesh_free(half);
    resurf_mesh_free(lods[0]);
    resurf_mesh_free(lods[1]);
    resurf_mesh_free(m);
    ck_assert_uint_eq(watch_end(), 0);
    assert_nothing_live();
    ck_assert_uint_eq(atomic_load(&the_counter.failed), 0);
    resurf_mesh_free(sphere);
    free(obj);
}
END_TEST

/* Loading from a file: the read buffer and the mesh both come from the allocator. */
START_TEST(alloc_load_file_and_save)
{
    resurf_mesh *t = tu_cube();
    char *dir = tu_tempdir();
    char *path = tu_path(dir, "c.ply");
    counter_reset(0);
    resurf_save_options so = resurf_save_options_default();
    so.allocator = &counting;
    ck_assert_int_eq(WATCHED(resurf_mesh_save(t, path, &so, NULL)), RESURF_OK);
    ck_assert_uint_eq(heap_during, 0);
    ck_assert_uint_gt(atomic_load(&the_counter.calls), 0);
    assert_nothing_live();
    resurf_load_options lo = counted_load();
    resurf_mesh *m = NULL;
    size_t before = atomic_load(&the_counter.calls);
    ck_assert_int_eq(WATCHED(resurf_mesh_load(path, &lo, &m, NULL)), RESURF_OK);
    ck_assert_uint_eq(heap_during, 0);
    ck_assert_uint_gt(atomic_load(&the_counter.calls), before);
    ck_assert_int_eq(same_mesh(t, m), 1);
    resurf_mesh_free(m);
    assert_nothing_live();
    resurf_mesh_free(t);
    free(path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* ---- (b) failure injection ----------------------------------------------------------------------------------- */

/* One call under test: runs with the counting allocator (all its blocks from it), returns the status; on success
 * it checks and frees what the call made. */
typedef resurf_status (*call_fn)(void *ctx);

/* Runs the call once to count its allocations (n), then for k = 1..n with the k-th allocation failing: every run
 * either fails with RESURF_ERR_OUT_OF_MEMORY or (when the failed block was optional, a shrinking reallocate) still
 * succeeds; either way every block comes back and `intact` (the caller's data) holds. Returns n. */
static size_t inject_failures_every(call_fn call, void *ctx, int (*intact)(void *ctx), size_t runs,
                                    size_t *out_failed_runs)
{
    counter_reset(0);
    ck_assert_int_eq(call(ctx), RESURF_OK);
    assert_nothing_live();
    size_t n = call_allocations;
    ck_assert_uint_gt(n, 0);
    size_t failed_runs = 0, step = runs && n > runs ? n / runs : 1;
    for (size_t k = 1; k <= n; k += step) {
        counter_reset(k);
        resurf_status st = call(ctx);
        if (st != RESURF_OK) {
            ck_assert_msg(st == RESURF_ERR_OUT_OF_MEMORY, "allocation %zu of %zu failing gave status %d", k, n,
                          (int)st);
            ++failed_runs;
        }
        ck_assert_msg(atomic_load(&the_counter.live_blocks) == 0, "allocation %zu of %zu failing leaked %zu blocks",
                      k, n, (size_t)atomic_load(&the_counter.live_blocks));
        ck_assert_msg(intact(ctx), "allocation %zu of %zu failing damaged the caller's data", k, n);
    }
    *out_failed_runs = failed_runs;
    return n;
}

/* Every allocation failing in turn. */
static size_t inject_failures(call_fn call, void *ctx, int (*intact)(void *ctx), size_t *out_failed_runs)
{
    return inject_failures_every(call, ctx, intact, 0, out_failed_runs);
}

typedef struct restore_case {
    resurf_mesh *original, *processed, *before;
    unsigned threads;
} restore_case;

static resurf_status run_restore(void *p)
{
    restore_case *c = p;
    resurf_mesh *work = NULL;
    ck_assert_int_eq(resurf_mesh_clone(c->processed, &work, NULL), RESURF_OK);
    resurf_restore_options o = resurf_restore_options_default();
    o.threads = c->threads;
    o.allocator = &counting;
    resurf_error error;
    resurf_status st = resurf_restore(c->original, work, &o, NULL, &error);
    end_call();
    if (st != RESURF_OK) /* nothing moved */
        ck_assert_int_eq(same_mesh(work, c->before), 1);
    else
        ck_assert_int_eq(same_mesh(work, c->before), 0);
    if (st != RESURF_OK)
        ck_assert_int_eq(error.status, st);
    resurf_mesh_free(work);
    return st;
}

static int restore_intact(void *p)
{
    restore_case *c = p;
    return same_mesh(c->processed, c->before) && mesh_valid(c->original);
}

START_TEST(alloc_restore_failures)
{
    restore_case c = {shape_mesh(SHAPE_TORUS, 300, 0.2, 3, 0), NULL, NULL, 2};
    resurf_mesh *p = shape_mesh(SHAPE_TORUS, 120, 0.3, 4, 0);
    for (size_t i = 0; i < 3 * p->vertex_count; ++i)
        p->positions[i] *= 1.02;
    c.processed = p;
    ck_assert_int_eq(resurf_mesh_clone(p, &c.before, NULL), RESURF_OK);
    size_t failed = 0, n = inject_failures(run_restore, &c, restore_intact, &failed);
    ck_assert_uint_gt(failed, 0);
    ck_assert_uint_ge(n, 10);
    resurf_mesh_free(c.original);
    resurf_mesh_free(c.processed);
    resurf_mesh_free(c.before);
}
END_TEST

typedef struct simplify_case {
    resurf_mesh *in, *before;
    resurf_restore_mode mode;
    int lods;
} simplify_case;

static resurf_status run_simplify(void *p)
{
    simplify_case *c = p;
    resurf_simplify_options o = resurf_simplify_options_default();
    o.threads = 2;
    o.restore = c->mode;
    o.measure_samples = 300;
    o.allocator = &counting;
    resurf_mesh *out[2] = {(resurf_mesh *)&out, (resurf_mesh *)&out}; /* must be overwritten */
    const double ratios[2] = {0.6, 0.3};
    resurf_status st = c->lods ? resurf_simplify_lods(c->in, ratios, 2, &o, out, NULL, NULL)
                               : resurf_simplify(c->in, &o, &out[0], NULL, NULL);
    end_call();
    for (int i = 0; i < (c->lods ? 2 : 1); ++i) {
        if (st != RESURF_OK) {
            ck_assert_ptr_null(out[i]);
            continue;
        }
        ck_assert_int_eq(mesh_valid(out[i]), 1);
        ck_assert_uint_lt(out[i]->triangle_count, c->in->triangle_count);
        resurf_mesh_free(out[i]);
    }
    return st;
}

static int simplify_intact(void *p)
{
    simplify_case *c = p;
    return same_mesh(c->in, c->before);
}

START_TEST(alloc_simplify_failures)
{
    /* a cube-sphere with normals and texcoords (attribute seams take the chart path), groups too */
    resurf_mesh *s = shape_mesh(SHAPE_SPHERE, 200, 0.2, 5, 1);
    resurf_mesh *in = NULL;
    ck_assert_int_eq(resurf_mesh_create(s->vertex_count, s->triangle_count,
                                        RESURF_ATTR_NORMALS | RESURF_ATTR_TEXCOORD0, &in, NULL), RESURF_OK);
    memcpy(in->positions, s->positions, 3 * s->vertex_count * sizeof(double));
    memcpy(in->indices, s->indices, 3 * s->triangle_count * sizeof(uint32_t));
    memcpy(in->normals, s->normals, 3 * s->vertex_count * sizeof(double));
    for (size_t v = 0; v < in->vertex_count; ++v) {
        in->texcoords[0][2 * v] = in->positions[3 * v] > 0 ? 0.25 : 0.75; /* a seam where x changes sign */
        in->texcoords[0][2 * v + 1] = in->positions[3 * v + 2];
    }
    simplify_case c = {in, NULL, RESURF_RESTORE_INLINE, 0};
    ck_assert_int_eq(resurf_mesh_clone(in, &c.before, NULL), RESURF_OK);
    size_t total = 0;
    for (int variant = 0; variant < 3; ++variant) {
        c.mode = variant == 1 ? RESURF_RESTORE_POST : RESURF_RESTORE_INLINE;
        c.lods = variant == 2;
        size_t failed = 0, n = inject_failures(run_simplify, &c, simplify_intact, &failed);
        ck_assert_uint_gt(failed, 0);
        total += n;
    }
    ck_assert_uint_ge(total, 100);
    resurf_mesh_free(s);
    resurf_mesh_free(in);
    resurf_mesh_free(c.before);
}
END_TEST

typedef struct load_case {
    const char *bytes;
    size_t size;
    resurf_format format;
    const resurf_mesh *expect;
} load_case;

static resurf_status run_load(void *p)
{
    load_case *c = p;
    resurf_load_options o = counted_load();
    resurf_mesh *m = (resurf_mesh *)c; /* must be overwritten */
    resurf_status st = resurf_mesh_load_memory(c->bytes, c->size, c->format, NULL, &o, &m, NULL);
    end_call();
    if (st != RESURF_OK) {
        ck_assert_ptr_null(m);
        return st;
    }
    ck_assert_uint_eq(m->triangle_count, c->expect->triangle_count);
    ck_assert_int_eq(mesh_valid(m), 1);
    resurf_mesh_free(m);
    return st;
}

static int load_intact(void *p)
{
    (void)p;
    return 1; /* the input bytes are const */
}

START_TEST(alloc_load_failures)
{
    resurf_mesh *s = shape_mesh(SHAPE_CYLINDER, 150, 0.2, 9, 1);
    static const struct {
        const char *name;
        int binary;
        resurf_format format;
    } files[] = {
        {"a.obj", 0, RESURF_FORMAT_OBJ}, {"a.ply", 1, RESURF_FORMAT_PLY}, {"b.ply", 0, RESURF_FORMAT_PLY},
        {"a.off", 0, RESURF_FORMAT_OFF}, {"a.stl", 1, RESURF_FORMAT_STL}, {"b.stl", 0, RESURF_FORMAT_STL},
    };
    size_t total = 0;
    for (size_t f = 0; f < sizeof files / sizeof files[0]; ++f) {
        size_t size = 0;
        char *bytes = saved_bytes(s, files[f].name, files[f].binary, &size);
        load_case c = {bytes, size, files[f].format, s};
        size_t failed = 0, n = inject_failures(run_load, &c, load_intact, &failed);
        ck_assert_uint_gt(failed, 0);
        total += n;
        free(bytes);
    }
    ck_assert_uint_ge(total, 20);
    resurf_mesh_free(s);
}
END_TEST

/* In-place calls (repair, smooth) and compare: a failure leaves the mesh exactly as it was. */
typedef struct inplace_case {
    resurf_mesh *mesh, *before;
    int which; /* 0 repair, 1 smooth, 2 compare, 3 validate */
} inplace_case;

static resurf_status run_inplace(void *p)
{
    inplace_case *c = p;
    resurf_mesh *work = NULL;
    resurf_status st = resurf_mesh_clone_with(c->mesh, &counting, &work, NULL);
    if (st != RESURF_OK) { /* the failure hit the copy the call works on */
        end_call();
        ck_assert_int_eq(st, RESURF_ERR_OUT_OF_MEMORY);
        ck_assert_ptr_null(work);
        return st;
    }
    ck_assert_ptr_eq(work->allocator.user, &the_counter);
    {
        if (c->which == 0) {
            resurf_repair_options o = resurf_repair_options_default();
            o.weld_tolerance_rel = 1e-3;
            st = resurf_mesh_repair(work, &o, NULL, NULL);
        } else if (c->which == 1) {
            resurf_smooth_options o = resurf_smooth_options_default();
            o.method = RESURF_SMOOTH_BILAPLACIAN;
            st = resurf_smooth(work, &o, NULL);
        } else if (c->which == 2) {
            resurf_compare_options o = resurf_compare_options_default();
            o.samples = 500;
            resurf_compare_report m;
            st = resurf_compare(work, c->mesh, &o, &m, NULL, NULL);
        } else {
            resurf_validate_report v;
            st = resurf_mesh_validate(work, &v, NULL);
        }
        end_call();
        if (st != RESURF_OK)
            ck_assert_int_eq(same_mesh(work, c->before), 1);
        ck_assert_int_eq(mesh_valid(work), 1);
    }
    resurf_mesh_free(work);
    return st;
}

static int inplace_intact(void *p)
{
    inplace_case *c = p;
    return same_mesh(c->mesh, c->before);
}

START_TEST(alloc_inplace_failures)
{
    /* a grid with duplicated vertices (the weld has work) */
    resurf_mesh *g = tu_grid(6);
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_create(g->vertex_count + 3, g->triangle_count, 0, &m, NULL), RESURF_OK);
    memcpy(m->positions, g->positions, 3 * g->vertex_count * sizeof(double));
    memcpy(m->positions + 3 * g->vertex_count, g->positions + 3 * 8, 9 * sizeof(double));
    memcpy(m->indices, g->indices, 3 * g->triangle_count * sizeof(uint32_t));
    /* three exact duplicates at the end; the first triangle uses the copy of its first corner */
    memcpy(m->positions + 3 * g->vertex_count, g->positions + 3 * (size_t)g->indices[0], 3 * sizeof(double));
    m->indices[0] = (uint32_t)g->vertex_count;
    for (size_t i = 0; i < 3 * m->vertex_count; i += 3)
        m->positions[i + 2] = 0.1 * sin(7 * m->positions[i]) * cos(5 * m->positions[i + 1]); /* something to smooth */
    inplace_case c = {m, NULL, 0};
    ck_assert_int_eq(resurf_mesh_clone(m, &c.before, NULL), RESURF_OK);
    for (c.which = 0; c.which < 4; ++c.which) {
        size_t failed = 0;
        inject_failures(run_inplace, &c, inplace_intact, &failed);
        ck_assert_uint_gt(failed, 0);
    }
    resurf_mesh_free(g);
    resurf_mesh_free(m);
    resurf_mesh_free(c.before);
}
END_TEST

/* ---- scenes: the C side of a scene (its bookkeeping and meshes) uses the allocator ----------------------------- */

/* A scene made from an allocator's mesh keeps everything in that allocator, levels set on it are copied into it,
 * and resurf_scene_free gives it all back; a .glb loaded with the allocator in the load options likewise. */
START_TEST(alloc_scene_blocks_come_back)
{
    resurf_mesh *s = shape_mesh(SHAPE_TORUS, 400, 0.2, 11, 1);
    resurf_mesh *m = NULL, *lod = NULL;
    counter_reset(0);
    ck_assert_int_eq(resurf_mesh_clone_with(s, &counting, &m, NULL), RESURF_OK);
    resurf_scene *scene = NULL;
    size_t before = atomic_load(&the_counter.calls);
    ck_assert_int_eq(resurf_scene_from_mesh(m, &scene, NULL), RESURF_OK);
    ck_assert_uint_gt(atomic_load(&the_counter.calls), before);
    ck_assert_ptr_eq(resurf_scene_primitive_mesh(scene, 0)->allocator.user, &the_counter);
    resurf_simplify_options so = resurf_simplify_options_default();
    so.measure_samples = 0;
    ck_assert_int_eq(resurf_simplify(s, &so, &lod, NULL, NULL), RESURF_OK); /* a C-heap level */
    const resurf_mesh *levels[1] = {lod};
    before = atomic_load(&the_counter.calls);
    ck_assert_int_eq(resurf_scene_set_lods(scene, 0, levels, 1, NULL), RESURF_OK);
    ck_assert_uint_gt(atomic_load(&the_counter.calls), before); /* the copy is the scene's */
    resurf_mesh_free(lod);

    char *dir = tu_tempdir();
    char *path = tu_path(dir, "t.glb");
    resurf_scene_save_options sso = resurf_scene_save_options_default();
    sso.allocator = &counting;
    before = atomic_load(&the_counter.calls);
    ck_assert_int_eq(resurf_scene_save(scene, path, &sso, NULL, NULL), RESURF_OK);
    ck_assert_uint_gt(atomic_load(&the_counter.calls), before);
    resurf_scene_free(scene);
    resurf_mesh_free(m);
    assert_nothing_live();

    resurf_load_options lo = counted_load();
    before = atomic_load(&the_counter.calls);
    ck_assert_int_eq(resurf_scene_load(path, &lo, &scene, NULL), RESURF_OK);
    ck_assert_uint_gt(atomic_load(&the_counter.calls), before);
    const resurf_mesh *loaded = resurf_scene_primitive_mesh(scene, 0);
    ck_assert_ptr_eq(loaded->allocator.user, &the_counter);
    ck_assert_uint_eq(loaded->triangle_count, s->triangle_count);
    resurf_scene_free(scene);
    assert_nothing_live();
    free(path);
    tu_rmtree(dir);
    free(dir);
    resurf_mesh_free(s);
}
END_TEST

typedef struct scene_case {
    const char *bytes;
    size_t size;
    size_t triangles;
} scene_case;

static resurf_status run_scene_load(void *p)
{
    scene_case *c = p;
    resurf_load_options o = counted_load();
    resurf_scene *scene = NULL;
    resurf_status st = resurf_scene_load_memory(c->bytes, c->size, RESURF_SCENE_FORMAT_GLB, &o, &scene, NULL);
    end_call();
    if (st != RESURF_OK) {
        ck_assert_ptr_null(scene);
        return st;
    }
    ck_assert_uint_eq(resurf_scene_primitive_mesh(scene, 0)->triangle_count, c->triangles);
    resurf_scene_free(scene);
    return st;
}

/* Every allocation of a .glb load failing in turn: OUT_OF_MEMORY, no scene, nothing left over. */
START_TEST(alloc_scene_load_failures)
{
    resurf_mesh *s = shape_mesh(SHAPE_CYLINDER, 100, 0.2, 12, 1);
    resurf_scene *scene = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(s, &scene, NULL), RESURF_OK);
    char *dir = tu_tempdir();
    char *path = tu_path(dir, "c.glb");
    ck_assert_int_eq(resurf_scene_save(scene, path, NULL, NULL, NULL), RESURF_OK);
    resurf_scene_free(scene);
    size_t size = 0;
    char *bytes = tu_read_file(path, &size);
    ck_assert_ptr_nonnull(bytes);
    scene_case c = {bytes, size, s->triangle_count};
    size_t failed = 0;
    inject_failures(run_scene_load, &c, load_intact, &failed);
    ck_assert_uint_gt(failed, 0);
    free(bytes);
    free(path);
    tu_rmtree(dir);
    free(dir);
    resurf_mesh_free(s);
}
END_TEST

/* Two spheres of about 200 triangles as two meshes of one glTF (positions, then uint32 indices, per sphere). */
static char *write_two_spheres(const char *dir)
{
    resurf_mesh *m[2] = {shape_mesh(SHAPE_SPHERE, 200, 0.2, 7, 0), shape_mesh(SHAPE_SPHERE, 200, 0.2, 8, 0)};
    tu_bytes b = {NULL, 0};
    size_t at[4];
    for (int i = 0; i < 2; ++i) {
        at[2 * i] = b.size;
        for (size_t v = 0; v < 3 * m[i]->vertex_count; ++v)
            tu_put_f32(&b, (float)m[i]->positions[v]);
        at[2 * i + 1] = b.size;
        tu_put(&b, m[i]->indices, 3 * m[i]->triangle_count * sizeof(uint32_t));
    }
    char *json = tu_strf(
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
        "\"nodes\":[{\"mesh\":0},{\"mesh\":1,\"translation\":[3,0,0]}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]},"
        "{\"primitives\":[{\"attributes\":{\"POSITION\":2},\"indices\":3}]}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\","
        "\"min\":[-1.5,-1.5,-1.5],\"max\":[1.5,1.5,1.5]},"
        "{\"bufferView\":1,\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"},"
        "{\"bufferView\":2,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\","
        "\"min\":[-1.5,-1.5,-1.5],\"max\":[1.5,1.5,1.5]},"
        "{\"bufferView\":3,\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},{\"buffer\":0,\"byteOffset\":%zu,"
        "\"byteLength\":%zu},{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}],"
        "\"buffers\":[{\"uri\":\"two.bin\",\"byteLength\":%zu}]}",
        m[0]->vertex_count, 3 * m[0]->triangle_count, m[1]->vertex_count, 3 * m[1]->triangle_count, at[0],
        at[1] - at[0], at[1], at[2] - at[1], at[2], at[3] - at[2], at[3], b.size - at[3], b.size);
    char *path = tu_write_gltf(dir, "two", json, &b);
    free(json);
    free(b.data);
    resurf_mesh_free(m[0]);
    resurf_mesh_free(m[1]);
    return path;
}

typedef struct lods_case {
    const char *path;
    unsigned threads;
} lods_case;

static resurf_status run_scene_lods(void *p)
{
    lods_case *c = p;
    resurf_load_options lo = counted_load();
    resurf_scene *scene = NULL;
    resurf_status st = resurf_scene_load(c->path, &lo, &scene, NULL);
    if (st == RESURF_OK) {
        const double ratios[2] = {0.5, 0.25};
        resurf_simplify_options so = resurf_simplify_options_default();
        so.measure_samples = 2000;
        so.threads = c->threads;
        resurf_scene_lod_report r;
        st = resurf_scene_build_lods(scene, ratios, 2, &so, NULL, &r, NULL, NULL);
        if (st == RESURF_OK)
            ck_assert_uint_eq(r.levels, 3);
    }
    resurf_scene_free(scene);
    end_call();
    return st;
}

/* Allocations of a scene's levels failing in turn (its load included; 100 of them spread over the call's
 * thousands, 24 under a sanitizer or valgrind), with the default restoring, whose plain pass runs beside the
 * default's on two threads and after it on one: OUT_OF_MEMORY, nothing left over. */
START_TEST(alloc_scene_lods_failures)
{
    char *dir = tu_tempdir();
    char *path = write_two_spheres(dir);
    for (unsigned threads = 1; threads <= 2; ++threads) {
        lods_case c = {path, threads};
        size_t failed = 0;
        inject_failures_every(run_scene_lods, &c, load_intact, tu_light() ? 24 : 100, &failed);
        ck_assert_uint_gt(failed, 0);
    }
    free(path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("alloc");
    TCase *tc = tcase_create("alloc");
    tcase_set_timeout(tc, 600);
    tcase_add_test(tc, alloc_meshes_remember_their_allocator);
    tcase_add_test(tc, alloc_incomplete_allocator_is_refused);
    tcase_add_test(tc, alloc_pipeline_uses_only_the_allocator);
    tcase_add_test(tc, alloc_load_file_and_save);
    tcase_add_test(tc, alloc_restore_failures);
    tcase_add_test(tc, alloc_simplify_failures);
    tcase_add_test(tc, alloc_load_failures);
    tcase_add_test(tc, alloc_inplace_failures);
    tcase_add_test(tc, alloc_scene_blocks_come_back);
    tcase_add_test(tc, alloc_scene_load_failures);
    tcase_add_test(tc, alloc_scene_lods_failures);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
