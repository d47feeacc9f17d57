/* Tests of src/scene_lods.c: resurf_scene_build_lods, the one-call levels of detail of a glTF scene, and the
 * `resurf lod` command that is now a thin layer over it (--max-triangles included).
 * The truths: each primitive's chain equals what resurf_simplify_lods makes of that primitive alone; the screen
 * coverage follows the formula documented in resurf.h from the reported errors; the reported errors bound the
 * distances resurf_compare measures independently; a failed or cancelled call leaves the scene as it was. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scene_internal.h"
#include "testutil.h"

/* ---- a two-mesh glTF written by hand ------------------------------------------------------------------------ */

static void base64(const unsigned char *in, size_t n, char *out)
{
    static const char t[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)in[i] << 16 | (i + 1 < n ? (uint32_t)in[i + 1] << 8 : 0) | (i + 2 < n ? in[i + 2] : 0);
        out[o++] = t[v >> 18 & 63];
        out[o++] = t[v >> 12 & 63];
        out[o++] = i + 1 < n ? t[v >> 6 & 63] : '=';
        out[o++] = i + 2 < n ? t[v & 63] : '=';
    }
    out[o] = 0;
}

/* Appends a mesh's float positions and uint32 indices to buf; writes the two accessors' JSON into acc, the index
 * accessor over its first `indexed` triangles. */
static size_t append_mesh(const resurf_mesh *m, unsigned char *buf, size_t at, char *acc, size_t acc_size,
                          int first_view, size_t indexed)
{
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < 3 * m->vertex_count; ++i) {
        float f = (float)m->positions[i];
        memcpy(buf + at + 4 * i, &f, 4);
        lo[i % 3] = fminf(lo[i % 3], f);
        hi[i % 3] = fmaxf(hi[i % 3], f);
    }
    size_t pos_bytes = 12 * m->vertex_count, idx_bytes = 12 * m->triangle_count;
    memcpy(buf + at + pos_bytes, m->indices, idx_bytes);
    snprintf(acc, acc_size,
             "{\"bufferView\":%d,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\",\"min\":[%.9g,%.9g,%.9g],"
             "\"max\":[%.9g,%.9g,%.9g]},{\"bufferView\":%d,\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"}",
             first_view, m->vertex_count, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], first_view + 1, 3 * indexed);
    return pos_bytes + idx_bytes;
}

/* A glTF of meshes a and b in one embedded buffer (a's positions and indices, then b's: bufferViews 0-3, accessors
 * 0-3, b's index accessor over its first b_indexed triangles), with the caller's scene node list, nodes, meshes and
 * further accessors (NULL: none). Returns the path (malloc'ed). */
static char *write_pair_gltf(const char *dir, const char *name, const resurf_mesh *a, const resurf_mesh *b,
                             size_t b_indexed, const char *scene_nodes, const char *nodes, const char *meshes,
                             const char *more_accessors)
{
    size_t a_pos = 12 * a->vertex_count, a_idx = 12 * a->triangle_count;
    size_t b_pos = 12 * b->vertex_count, b_idx = 12 * b->triangle_count;
    size_t total = a_pos + a_idx + b_pos + b_idx;
    unsigned char *buf = malloc(total);
    char acc_a[512], acc_b[512];
    append_mesh(a, buf, 0, acc_a, sizeof acc_a, 0, a->triangle_count);
    append_mesh(b, buf, a_pos + a_idx, acc_b, sizeof acc_b, 2, b_indexed);
    char *b64 = malloc(total / 3 * 4 + 8);
    base64(buf, total, b64);
    char *json = tu_strf(
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[%s]}],\"nodes\":[%s],\"meshes\":[%s],"
        "\"accessors\":[%s,%s%s%s],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":%zu},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}],"
        "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"data:application/octet-stream;base64,%s\"}]}",
        scene_nodes, nodes, meshes, acc_a, acc_b, more_accessors ? "," : "", more_accessors ? more_accessors : "",
        a_pos, a_pos, a_idx, a_pos + a_idx, b_pos, a_pos + a_idx + b_pos, b_idx, total, b64);
    char *path = tu_path(dir, name);
    ck_assert_int_eq(tu_write_file(path, json, strlen(json)), 0);
    free(json);
    free(b64);
    free(buf);
    return path;
}

/* meshes[0]: a sphere (one triangle primitive); meshes[1]: a torus (a triangle primitive and a points primitive
 * over the same positions); meshes[2]: the sphere again with a morph target (its own positions as displacements).
 * Node k shows mesh k. Returns the path (malloc'ed). */
static char *write_two_mesh_gltf(const char *dir, resurf_mesh **out_sphere, resurf_mesh **out_torus)
{
    resurf_mesh *a = shape_mesh(SHAPE_SPHERE, 1200, 0.3, 1, 0), *b = shape_mesh(SHAPE_TORUS, 1600, 0.3, 2, 0);
    char *path = write_pair_gltf(
        dir, "two.gltf", a, b, b->triangle_count, "0,1,2",
        "{\"mesh\":0},{\"mesh\":1,\"translation\":[3,0,0]},{\"mesh\":2,\"translation\":[0,3,0]}",
        "{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]},"
        "{\"primitives\":[{\"attributes\":{\"POSITION\":2},\"indices\":3},{\"attributes\":{\"POSITION\":2},\"mode\":0}]},"
        "{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,\"targets\":[{\"POSITION\":0}]}],"
        "\"weights\":[0]}",
        NULL);
    *out_sphere = a;
    *out_torus = b;
    return path;
}

static resurf_scene *load(const char *path)
{
    resurf_scene *s = NULL;
    resurf_error e;
    ck_assert_msg(resurf_scene_load(path, NULL, &s, &e) == RESURF_OK, "load: %s", e.message);
    return s;
}

/* Options that make the test fast but still measure: fewer samples than the default. */
static resurf_simplify_options fast_options(void)
{
    resurf_simplify_options o = resurf_simplify_options_default();
    o.measure_samples = 5000;
    return o;
}

static int same_mesh(const resurf_mesh *a, const resurf_mesh *b)
{
    return a->vertex_count == b->vertex_count && a->triangle_count == b->triangle_count &&
           !memcmp(a->positions, b->positions, 3 * a->vertex_count * sizeof(double)) &&
           !memcmp(a->indices, b->indices, 3 * a->triangle_count * sizeof(uint32_t));
}

/* The MSFT_screencoverage arrays of the written file, in node order (the full-detail nodes carry them). */
static size_t read_coverage(const char *gltf_path, double out[][RESURF_SCENE_MAX_LEVELS], size_t *counts)
{
    char *text = tu_read_file(gltf_path, NULL);
    ck_assert_ptr_nonnull(text);
    size_t found = 0;
    for (const char *p = text; (p = strstr(p, "\"MSFT_screencoverage\"")) != NULL; ++found) {
        p = strchr(p, '[');
        ck_assert_ptr_nonnull(p);
        counts[found] = 0;
        for (++p;;) {
            char *end;
            double v = strtod(p, &end);
            if (end == p)
                break;
            out[found][counts[found]++] = v;
            p = end;
            while (*p == ' ' || *p == ',' || *p == '\n')
                ++p;
        }
    }
    free(text);
    return found;
}

/* ---- tests --------------------------------------------------------------------------------------------------- */

START_TEST(scene_lods_equal_per_primitive_chains)
{
    char *dir = tu_tempdir();
    resurf_mesh *sphere, *torus;
    char *path = write_two_mesh_gltf(dir, &sphere, &torus);
    resurf_scene *s = load(path);
    ck_assert_uint_eq(resurf_scene_primitive_count(s), 4);

    const double ratios[2] = {0.5, 0.2};
    resurf_simplify_options so = fast_options();
    so.measure_samples = 20000; /* three simplified meshes share the budget: 5,000 can miss the max by over 20% */
    /* One restoring mode: the measured default chooses per level by the report, which here has the primitive's
       share of the samples and alone has them all. */
    so.restore = RESURF_RESTORE_INLINE;
    resurf_scene_lod_options lo = resurf_scene_lod_options_default();
    lo.pixels = 1; /* small enough that no level's coverage is clamped at 1 */
    lo.screen_height = 720;
    lo.share_triangles = false; /* each chain its own (the shared budget has its own test) */
    resurf_scene_lod_report r;
    resurf_simplify_report pr[4 * 2];
    memset(pr, 0xFF, sizeof pr);
    resurf_error e;
    ck_assert_msg(resurf_scene_build_lods(s, ratios, 2, &so, &lo, &r, pr, &e) == RESURF_OK, "%s", e.message);
    ck_assert_uint_eq(r.levels, 3);
    ck_assert_uint_eq(r.primitives, 3); /* the morphed one included (since 0.3.0) */
    ck_assert_uint_eq(r.morphed, 1);
    ck_assert_uint_eq(r.other, 1);

    /* Each chain is what resurf_simplify_lods makes of that primitive alone. */
    const size_t tri_prims[3] = {0, 1, 3};
    size_t level_tris[3] = {0, 0, 0};
    double mesh_err[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    for (int i = 0; i < 3; ++i) {
        size_t p = tri_prims[i];
        const resurf_mesh *in = resurf_scene_primitive_mesh(s, p);
        resurf_mesh *alone[2] = {NULL, NULL};
        resurf_simplify_report ar[2];
        ck_assert_int_eq(resurf_simplify_lods(in, ratios, 2, &so, alone, ar, NULL), RESURF_OK);
        resurf_scene_primitive info;
        ck_assert_int_eq(resurf_scene_primitive_info(s, p, &info, NULL), RESURF_OK);
        ck_assert_uint_eq(info.lod_count, 2);
        level_tris[0] += in->triangle_count;
        for (int k = 0; k < 2; ++k) {
            ck_assert(same_mesh(s->prims[p].lods[k], alone[k]));
            ck_assert_uint_eq(pr[p * 2 + k].triangles, alone[k]->triangle_count);
            ck_assert_uint_le(alone[k]->triangle_count, (size_t)(ratios[k] * (double)in->triangle_count));
            level_tris[k + 1] += alone[k]->triangle_count;
            /* Independent bound: the reported error covers every vertex's exact distance to the input surface. */
            resurf_compare_options co = resurf_compare_options_default();
            co.samples = 0;
            resurf_compare_report mt;
            ck_assert_int_eq(resurf_compare(in, alone[k], &co, &mt, NULL, NULL), RESURF_OK);
            ck_assert(ar[k].max_distance_rel >= mt.vertex_max / mt.diagonal - 1e-12);
            ck_assert(ar[k].max_distance_rel > 0);
            /* The scene's report of the primitive is measured with its share of the samples (by area), so it is
             * not ar's figure, but it covers the vertices just as well. */
            ck_assert(pr[p * 2 + k].max_distance_rel >= mt.vertex_max / mt.diagonal - 1e-12);
            /* The mesh's own two-sided error (node k shows mesh k untransformed), densely measured. */
            co.samples = 40000;
            ck_assert_int_eq(resurf_compare(in, alone[k], &co, &mt, NULL, NULL), RESURF_OK);
            mesh_err[i][k + 1] = mt.hausdorff / mt.diagonal;
            ck_assert_msg(fabs(pr[p * 2 + k].max_distance_rel - mesh_err[i][k + 1]) <= 0.2 * mesh_err[i][k + 1],
                          "primitive %zu level %d: %g, dense %g", p, k + 1, pr[p * 2 + k].max_distance_rel,
                          mesh_err[i][k + 1]);
            resurf_mesh_free(alone[k]);
        }
    }
    /* The points primitive got nothing, and its reports are zeroed. */
    resurf_scene_primitive info;
    ck_assert_int_eq(resurf_scene_primitive_info(s, 2, &info, NULL), RESURF_OK);
    ck_assert_int_eq(info.kind, RESURF_PRIMITIVE_OTHER);
    ck_assert_uint_eq(info.lod_count, 0);
    ck_assert_uint_eq(pr[2 * 2].triangles, 0);
    ck_assert_uint_eq(pr[2 * 2 + 1].input_triangles, 0);
    ck_assert_int_eq(resurf_scene_primitive_info(s, 3, &info, NULL), RESURF_OK);
    ck_assert_int_eq(info.kind, RESURF_PRIMITIVE_MORPHED);
    /* The level errors are the whole scene's, in world space: the two-sided error (the larger of the two sides'
     * maxima) and the mean within 20% of a dense resurf_compare between the world meshes of the level and of
     * level 0. */
    resurf_mesh *w0 = NULL;
    ck_assert_int_eq(resurf_scene_world_mesh(s, 0, NULL, &w0, NULL), RESURF_OK);
    ck_assert_double_eq(r.diagonal, resurf_mesh_bounds(w0, NULL, NULL));
    for (int k = 0; k < 3; ++k) {
        ck_assert_uint_eq(r.level_triangles[k], level_tris[k]);
        if (k == 0) {
            ck_assert(r.level_error_rel[0] == 0);
            continue;
        }
        resurf_mesh *wk = NULL;
        ck_assert_int_eq(resurf_scene_world_mesh(s, k, NULL, &wk, NULL), RESURF_OK);
        resurf_compare_report mt = tu_compare(w0, wk, 200000);
        ck_assert_msg(fabs(r.level_error[k] - mt.hausdorff) <= 0.2 * mt.hausdorff, "level %d: %g, dense %g", k,
                      r.level_error[k], mt.hausdorff);
        ck_assert(r.level_error_rel[k] == r.level_error[k] / r.diagonal);
        ck_assert(r.level_error_rel[k] == fmax(r.level_to_full_rel[k], r.level_from_full_rel[k]));
        double mean = mt.mean / mt.diagonal;
        ck_assert_msg(fabs(r.level_mean_rel[k] - mean) <= 0.2 * mean, "level %d: mean %g, dense %g", k,
                      r.level_mean_rel[k], mean);
        resurf_mesh_free(wk);
    }
    resurf_mesh_free(w0);

    /* Saved: the file's level triangles agree with the report, and each mesh's coverage follows the documented
     * formula c_k = min(1, (pixels / (e_k · H))²), non-increasing, 0 for the coarsest level, where e_k is the
     * mesh's own two-sided error against its own diagonal (within 20% of the dense one measured above). */
    char *out = tu_path(dir, "out.gltf");
    resurf_scene_save_options sv = resurf_scene_save_options_default();
    sv.embed_buffers = true;
    resurf_scene_save_report saved;
    ck_assert_msg(resurf_scene_save(s, out, &sv, &saved, &e) == RESURF_OK, "%s", e.message);
    ck_assert_uint_eq(saved.levels, 3);
    for (int k = 0; k < 3; ++k)
        ck_assert_uint_eq(saved.level_triangles[k], r.level_triangles[k]);
    double cov[4][RESURF_SCENE_MAX_LEVELS];
    size_t counts[4];
    ck_assert_uint_eq(read_coverage(out, cov, counts), 3);
    for (int i = 0; i < 3; ++i) {
        ck_assert_uint_eq(counts[i], 3);
        /* c = (pixels / (e·H))² gives back e = pixels / (H·√c) where c is neither clamped nor held down. */
        ck_assert_msg(cov[i][0] < 1, "mesh %d: coverage %g, dense error %g", i, cov[i][0], mesh_err[i][1]);
        double e1 = 1.0 / (720 * sqrt(cov[i][0]));
        ck_assert_msg(fabs(e1 - mesh_err[i][1]) <= 0.2 * mesh_err[i][1], "mesh %d: %g, dense %g", i, e1,
                      mesh_err[i][1]);
        if (cov[i][1] < cov[i][0]) {
            double e2 = 1.0 / (720 * sqrt(cov[i][1]));
            ck_assert_msg(fabs(e2 - mesh_err[i][2]) <= 0.2 * mesh_err[i][2], "mesh %d: %g, dense %g", i, e2,
                          mesh_err[i][2]);
        }
        ck_assert(cov[i][2] == 0);
        ck_assert(cov[i][0] > 0 && cov[i][0] <= 1 && cov[i][1] <= cov[i][0]);
    }
    resurf_scene_free(s);
    resurf_mesh_free(sphere);
    resurf_mesh_free(torus);
    free(out);
    free(path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* A progress callback that records what it sees and cancels at a chosen moment. */
typedef struct watch {
    int calls;
    double last;
    int monotone;
    double cancel_from;    /* cancel at the first fraction >= this (> 1: never) */
    resurf_stage cancel_at; /* ... or at the end of this stage (RESURF_STAGE_COUNT: never) */
} watch;

static bool watch_fn(void *user, resurf_stage stage, double fraction)
{
    watch *w = user;
    w->calls++;
    if (fraction < w->last || fraction < 0 || fraction > 1)
        w->monotone = 0;
    w->last = fraction;
    if (fraction >= w->cancel_from)
        return 1;
    return stage == w->cancel_at && fraction >= 1.0;
}

START_TEST(scene_lods_cancel_leaves_scene_unchanged)
{
    char *dir = tu_tempdir();
    resurf_mesh *sphere, *torus;
    char *path = write_two_mesh_gltf(dir, &sphere, &torus);
    resurf_scene *s = load(path);
    resurf_simplify_options so = fast_options();

    /* A first, complete run: levels and coverage in place, progress monotone from 0 to 1. */
    const double first[1] = {0.5};
    resurf_scene_lod_options lo = resurf_scene_lod_options_default();
    watch w = {0, 0, 1, 2, RESURF_STAGE_COUNT};
    lo.progress.fn = watch_fn;
    lo.progress.user = &w;
    ck_assert_int_eq(resurf_scene_build_lods(s, first, 1, &so, &lo, NULL, NULL, NULL), RESURF_OK);
    ck_assert_int_gt(w.calls, 2);
    ck_assert(w.monotone);
    ck_assert(w.last == 1.0);
    resurf_mesh *before[2] = {s->prims[0].lods[0], s->prims[1].lods[0]};
    double cov0 = s->coverage[0][0];

    /* Cancelled in the second primitive (the sphere has 1200 of the 2800 triangles: its share ends near 0.43),
     * then at the very end, after every primitive is done: each time CANCELLED, and the scene is as it was. */
    const double second[2] = {0.3, 0.1};
    const double cancel_from[2] = {0.6, 2};
    for (int run = 0; run < 2; ++run) {
        watch c = {0, 0, 1, cancel_from[run], run == 1 ? RESURF_STAGE_FINISH : RESURF_STAGE_COUNT};
        lo.progress.user = &c;
        resurf_scene_lod_report r;
        memset(&r, 0x11, sizeof r);
        resurf_error e;
        ck_assert_int_eq(resurf_scene_build_lods(s, second, 2, &so, &lo, &r, NULL, &e), RESURF_ERR_CANCELLED);
        ck_assert_int_eq(e.status, RESURF_ERR_CANCELLED);
        ck_assert(c.last >= cancel_from[run] || run == 1);
        for (int p = 0; p < 2; ++p) {
            ck_assert_uint_eq(s->prims[p].lod_count, 1);
            ck_assert_ptr_eq(s->prims[p].lods[0], before[p]);
        }
        ck_assert_uint_eq(s->coverage_count[0], 2);
        ck_assert(s->coverage[0][0] == cov0);
        ck_assert_uint_eq(r.levels, 0x1111111111111111ull); /* the report is not written either */
    }
    /* The scene still saves as it was: two levels. */
    char *out = tu_path(dir, "after.glb");
    resurf_scene_save_report saved;
    ck_assert_int_eq(resurf_scene_save(s, out, NULL, &saved, NULL), RESURF_OK);
    ck_assert_uint_eq(saved.levels, 2);
    resurf_scene_free(s);
    resurf_mesh_free(sphere);
    resurf_mesh_free(torus);
    free(out);
    free(path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* Eight meshes of one triangle primitive each (the sphere and the torus of write_two_mesh_gltf, alternately,
 * node k at x = 3k): primitives enough for the side-by-side run on 2 and 4 threads. */
static char *write_eight_mesh_gltf(const char *dir)
{
    resurf_mesh *a = shape_mesh(SHAPE_SPHERE, 1200, 0.3, 1, 0), *b = shape_mesh(SHAPE_TORUS, 1600, 0.3, 2, 0);
    char nodes[1024] = "", meshes[2048] = "", list[64] = "";
    for (int k = 0; k < 8; ++k) {
        const char *sep = k ? "," : "";
        snprintf(nodes + strlen(nodes), sizeof nodes - strlen(nodes), "%s{\"mesh\":%d,\"translation\":[%d,0,0]}",
                 sep, k, 3 * k);
        snprintf(meshes + strlen(meshes), sizeof meshes - strlen(meshes),
                 "%s{\"primitives\":[{\"attributes\":{\"POSITION\":%d},\"indices\":%d}]}", sep, 2 * (k % 2),
                 2 * (k % 2) + 1);
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%d", sep, k);
    }
    char *path = write_pair_gltf(dir, "eight.gltf", a, b, b->triangle_count, list, nodes, meshes, NULL);
    resurf_mesh_free(a);
    resurf_mesh_free(b);
    return path;
}

/* Primitives simplified side by side (2 and 4 threads, one each) give what one thread gives, one primitive after
 * the other: the same levels bit for bit, the same reports, the same world errors and coverage, the same bytes
 * saved with Draco on as many threads; and a cancel during the side-by-side run leaves the scene as it was. */
START_TEST(scene_lods_side_by_side_same_as_one_thread)
{
    char *dir = tu_tempdir();
    char *path = write_eight_mesh_gltf(dir);
    const double ratios[2] = {0.5, 0.2};
    resurf_scene *one = NULL;
    resurf_scene_lod_report r1;
    resurf_simplify_report pr1[8 * 2];
    const unsigned threads[3] = {1, 2, 4};
    char *file1 = NULL;
    size_t size1 = 0;
    for (int t = 0; t < 3; ++t) {
        resurf_scene *s = load(path);
        ck_assert_uint_eq(resurf_scene_primitive_count(s), 8);
        resurf_simplify_options so = fast_options();
        so.threads = threads[t];
        resurf_scene_lod_report r;
        resurf_simplify_report pr[8 * 2];
        memset(pr, 0, sizeof pr);
        resurf_error e;
        ck_assert_msg(resurf_scene_build_lods(s, ratios, 2, &so, NULL, &r, pr, &e) == RESURF_OK, "%s", e.message);
        ck_assert_uint_eq(r.primitives, 8);
        /* Saved with Draco on as many threads (the payloads made side by side): the same bytes. */
        resurf_scene_save_options save = resurf_scene_save_options_default();
        save.draco = true;
        save.threads = threads[t];
        char *out = tu_path(dir, t == 0 ? "one.glb" : "many.glb");
        ck_assert_msg(resurf_scene_save(s, out, &save, NULL, &e) == RESURF_OK, "%s", e.message);
        size_t size = 0;
        char *file = tu_read_file(out, &size);
        ck_assert_ptr_nonnull(file);
        free(out);
        if (t > 0) {
            ck_assert_uint_eq(size, size1);
            ck_assert(memcmp(file, file1, size) == 0);
            free(file);
        } else {
            file1 = file, size1 = size;
        }
        /* A cancel while the payloads are made: CANCELLED, no file, the progress rising until then. */
        watch w = {0, 0, 1, 0.25, RESURF_STAGE_COUNT};
        save.progress = (resurf_progress){watch_fn, &w};
        char *cancelled = tu_path(dir, "cancelled.glb");
        ck_assert_int_eq(resurf_scene_save(s, cancelled, &save, NULL, &e), RESURF_ERR_CANCELLED);
        ck_assert_int_eq(e.status, RESURF_ERR_CANCELLED);
        ck_assert(w.monotone && w.calls >= 1 && w.last >= 0.25);
        ck_assert_int_ne(access(cancelled, F_OK), 0);
        free(cancelled);
        if (t == 0) {
            one = s;
            r1 = r;
            memcpy(pr1, pr, sizeof pr);
            ck_assert_uint_eq(r.levels, 3);
            continue;
        }
        for (size_t p = 0; p < 8; ++p) {
            ck_assert_uint_eq(s->prims[p].lod_count, one->prims[p].lod_count);
            for (size_t k = 0; k < s->prims[p].lod_count; ++k)
                ck_assert(same_mesh(s->prims[p].lods[k], one->prims[p].lods[k]));
            for (size_t k = 0; k < 2; ++k) {
                ck_assert_uint_eq(pr[2 * p + k].triangles, pr1[2 * p + k].triangles);
                ck_assert(pr[2 * p + k].max_distance_rel == pr1[2 * p + k].max_distance_rel);
            }
        }
        for (size_t k = 0; k < r.levels; ++k) {
            ck_assert_uint_eq(r.level_triangles[k], r1.level_triangles[k]);
            ck_assert(r.level_error_rel[k] == r1.level_error_rel[k] ||
                      (isnan(r.level_error_rel[k]) && isnan(r1.level_error_rel[k])));
        }
        for (size_t m = 0; m < 8; ++m) {
            ck_assert_uint_eq(s->coverage_count[m], one->coverage_count[m]);
            for (size_t k = 0; k < s->coverage_count[m]; ++k)
                ck_assert(s->coverage[m][k] == one->coverage[m][k]);
        }
        resurf_scene_free(s);
    }
    resurf_scene_free(one);
    free(file1);

    /* Cancelled halfway through the side-by-side run: CANCELLED, no levels set. */
    resurf_scene *s = load(path);
    resurf_simplify_options so = fast_options();
    so.threads = 2;
    resurf_scene_lod_options lo = resurf_scene_lod_options_default();
    watch c = {0, 0, 1, 0.5, RESURF_STAGE_COUNT};
    lo.progress.fn = watch_fn;
    lo.progress.user = &c;
    resurf_error e;
    ck_assert_int_eq(resurf_scene_build_lods(s, ratios, 2, &so, &lo, NULL, NULL, &e), RESURF_ERR_CANCELLED);
    ck_assert_int_eq(e.status, RESURF_ERR_CANCELLED);
    ck_assert(c.monotone);
    for (size_t p = 0; p < 8; ++p)
        ck_assert_uint_eq(s->prims[p].lod_count, 0);
    resurf_scene_free(s);
    free(path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(scene_lods_errors_named_and_scene_unchanged)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 300, 0.2, 3, 0);
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(m, &s, NULL), RESURF_OK);
    const double ratios[2] = {0.5, 0.25}, rising[2] = {0.25, 0.5};
    resurf_error e;

    ck_assert_int_eq(resurf_scene_build_lods(NULL, ratios, 2, NULL, NULL, NULL, NULL, &e),
                     RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurf_scene_build_lods(s, NULL, 2, NULL, NULL, NULL, NULL, &e), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurf_scene_build_lods(s, ratios, 0, NULL, NULL, NULL, NULL, &e), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_str_eq(e.message, "0 levels of detail (1 to 15)");
    ck_assert_int_eq(resurf_scene_build_lods(s, rising, 2, NULL, NULL, NULL, NULL, &e), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_str_eq(e.message, "ratios[1] = 0.5: ratios must lie in (0, 1] and never increase");

    resurf_scene_lod_options lo;
    memset(&lo, 0, sizeof lo);
    ck_assert_int_eq(resurf_scene_build_lods(s, ratios, 2, NULL, &lo, NULL, NULL, &e), RESURF_ERR_INVALID_OPTIONS);
    lo = resurf_scene_lod_options_default();
    lo.pixels = 0;
    ck_assert_int_eq(resurf_scene_build_lods(s, ratios, 2, NULL, &lo, NULL, NULL, &e), RESURF_ERR_INVALID_OPTIONS);
    ck_assert_ptr_nonnull(strstr(e.message, "pixels (0) and screen_height (1080) must be positive"));

    /* The simplifier refuses its options: the message names the primitive first. */
    resurf_simplify_options so = resurf_simplify_options_default();
    so.max_normal_change_deg = -1;
    ck_assert_int_eq(resurf_scene_build_lods(s, ratios, 2, &so, NULL, NULL, NULL, &e), RESURF_ERR_INVALID_OPTIONS);
    ck_assert_msg(!strncmp(e.message, "meshes[0].primitives[0]: ", 25), "message '%s'", e.message);
    ck_assert_uint_eq(s->prims[0].lod_count, 0);
    ck_assert_ptr_null(s->coverage[0]);

    /* With defaults (NULL options) it works, and set_screen_coverage 0 leaves the coverage unset. */
    lo = resurf_scene_lod_options_default();
    lo.set_screen_coverage = false;
    ck_assert_int_eq(resurf_scene_build_lods(s, ratios, 2, NULL, &lo, NULL, NULL, &e), RESURF_OK);
    ck_assert_uint_eq(s->prims[0].lod_count, 2);
    ck_assert_ptr_null(s->coverage[0]);
    ck_assert_int_eq(resurf_scene_build_lods(s, ratios, 1, NULL, NULL, NULL, NULL, &e), RESURF_OK);
    ck_assert_uint_eq(s->prims[0].lod_count, 1); /* replaced, not added */
    ck_assert_uint_eq(s->coverage_count[0], 2);
    resurf_scene_free(s);
    resurf_mesh_free(m);
}
END_TEST

/* `resurf lod` honours --max-triangles (it loads through resurf_scene_load) and prints the library's errors. */
START_TEST(scene_lods_cli_max_triangles_and_errors)
{
    char *dir = tu_tempdir();
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 600, 0.2, 4, 0);
    char *ply = tu_path(dir, "ball.ply"), *glb = tu_path(dir, "ball.glb");
    ck_assert_int_eq(resurf_mesh_save(m, ply, NULL, NULL), RESURF_OK);
    char *text = NULL;

    char *cmd = tu_strf("'%s' lod '%s' -o '%s' --levels 0.5 --max-triangles %zu 2>&1", RESURF_CLI, ply, glb,
                     m->triangle_count - 1);
    ck_assert_int_eq(tu_run(cmd, &text), 1);
    ck_assert_msg(strstr(text, "limit") || strstr(text, "max"), "no word of the limit in: %s", text);
    ck_assert_msg(access(glb, F_OK) != 0, "an output was written: %s", text);
    free(cmd);
    free(text);

    cmd = tu_strf("'%s' lod '%s' -o '%s' --levels 0.5 --max-triangles %zu --json", RESURF_CLI, ply, glb,
               m->triangle_count);
    ck_assert_int_eq(tu_run(cmd, &text), 0);
    free(cmd);
    /* The table's level-1 error is the library's, for the same input and default options. */
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_load(ply, NULL, &s, NULL), RESURF_OK);
    const double ratio = 0.5;
    resurf_scene_lod_report r;
    ck_assert_int_eq(resurf_scene_build_lods(s, &ratio, 1, NULL, NULL, &r, NULL, NULL), RESURF_OK);
    const char *at = strstr(text, "\"level\": 1");
    ck_assert_ptr_nonnull(at);
    at = strstr(at, "\"error_rel\": ");
    ck_assert_ptr_nonnull(at);
    double printed = strtod(at + 13, NULL);
    ck_assert_msg(fabs(printed - r.level_error_rel[1]) <= 1e-9 * r.level_error_rel[1], "CLI %.17g, library %.17g",
                  printed, r.level_error_rel[1]);
    /* Each phase's time is printed, none negative; the library's phases took time of their own too. */
    static const char *const phases[] = {"\"load\": ", "\"chains\": ", "\"errors\": ", "\"save\": "};
    at = strstr(text, "\"seconds\": {");
    ck_assert_ptr_nonnull(at);
    for (int i = 0; i < 4; ++i) {
        const char *f = strstr(at, phases[i]);
        ck_assert_msg(f != NULL, "no %s in %s", phases[i], at);
        ck_assert(strtod(f + strlen(phases[i]), NULL) >= 0);
    }
    ck_assert(r.chains_seconds > 0 && r.errors_seconds > 0);
    free(text);
    resurf_scene_free(s);

    cmd = tu_strf("'%s' lod '%s' -o '%s' --max-triangles 0", RESURF_CLI, ply, glb); /* 0 = no limit */
    ck_assert_int_eq(tu_run(cmd, &text), 0);
    free(cmd);
    free(text);

    resurf_mesh_free(m);
    free(ply);
    free(glb);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* Two spheres side by side as two meshes: a fine one (about 4,000 triangles) and a coarse one (about 500), which
 * cannot lose three quarters of its triangles without a large error; split = 1 makes the coarse one two primitives
 * (its halves over one POSITION accessor), which are simplified together. The truths: the scene's level keeps the
 * coarse one's triangles where its error was the scene's (more of them than its own chain), the scene's total
 * still meets the ratio, and a dense resurf_compare of the world meshes finds the scene's error smaller than with
 * each primitive at its own ratio, and within 20% of the reported one. */
static char *write_sphere_pair_gltf(const char *dir, int split)
{
    resurf_mesh *a = shape_mesh(SHAPE_SPHERE, 4000, 0.3, 1, 0), *b = shape_mesh(SHAPE_SPHERE, 500, 0.3, 2, 0);
    size_t upper = 0; /* b's triangles over z = 0 first */
    for (size_t t = 0; split && t < b->triangle_count; ++t) {
        double z = 0;
        for (int k = 0; k < 3; ++k)
            z += b->positions[3 * b->indices[3 * t + k] + 2];
        if (z > 0) {
            for (int k = 0; k < 3; ++k) {
                uint32_t x = b->indices[3 * upper + k];
                b->indices[3 * upper + k] = b->indices[3 * t + k], b->indices[3 * t + k] = x;
            }
            upper++;
        }
    }
    char *halves = tu_strf("{\"bufferView\":3,\"byteOffset\":%zu,\"componentType\":5125,\"count\":%zu,"
                           "\"type\":\"SCALAR\"}", 12 * upper, 3 * (b->triangle_count - upper));
    char *meshes = tu_strf("{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]},"
                           "{\"primitives\":[{\"attributes\":{\"POSITION\":2},\"indices\":3}%s]}",
                           split ? ",{\"attributes\":{\"POSITION\":2},\"indices\":4}" : "");
    /* The first primitive's accessor: the upper half when split. */
    char *path = write_pair_gltf(dir, split ? "halves.gltf" : "pair.gltf", a, b, split ? upper : b->triangle_count,
                                 "0,1", "{\"mesh\":0},{\"mesh\":1,\"translation\":[3,0,0]}", meshes,
                                 split ? halves : NULL);
    free(meshes);
    free(halves);
    resurf_mesh_free(a);
    resurf_mesh_free(b);
    return path;
}

START_TEST(scene_lods_triangles_go_where_the_error_is)
{
    char *dir = tu_tempdir();
    int split = _i; /* 1: the coarse sphere's halves are simplified together, one unit of the budget */
    char *path = write_sphere_pair_gltf(dir, split);
    const double ratios[1] = {0.25};
    resurf_simplify_options so = fast_options();
    so.measure_samples = 20000;
    double dense[2];
    size_t coarse_tris[2], totals[2], input = 0;
    resurf_scene_lod_report r[2];
    for (int shared = 0; shared < 2; ++shared) {
        resurf_scene *s = load(path);
        resurf_scene_lod_options lo = resurf_scene_lod_options_default();
        lo.share_triangles = shared;
        resurf_error e;
        ck_assert_msg(resurf_scene_build_lods(s, ratios, 1, &so, &lo, &r[shared], NULL, &e) == RESURF_OK, "%s",
                      e.message);
        input = r[shared].level_triangles[0];
        totals[shared] = r[shared].level_triangles[1];
        coarse_tris[shared] = 0;
        for (size_t p = 1; p < 2 + (size_t)split; ++p) {
            resurf_scene_primitive info;
            ck_assert_int_eq(resurf_scene_primitive_info(s, p, &info, NULL), RESURF_OK);
            coarse_tris[shared] += info.lod_count ? s->prims[p].lods[0]->triangle_count
                                                  : resurf_scene_primitive_mesh(s, p)->triangle_count;
        }
        resurf_mesh *w0 = NULL, *w1 = NULL;
        ck_assert_int_eq(resurf_scene_world_mesh(s, 0, NULL, &w0, NULL), RESURF_OK);
        ck_assert_int_eq(resurf_scene_world_mesh(s, 1, NULL, &w1, NULL), RESURF_OK);
        resurf_compare_options co = resurf_compare_options_default();
        co.samples = 200000;
        resurf_compare_report mt;
        ck_assert_int_eq(resurf_compare(w0, w1, &co, &mt, NULL, NULL), RESURF_OK);
        dense[shared] = mt.hausdorff;
        ck_assert_msg(fabs(r[shared].level_error[1] - mt.hausdorff) <= 0.2 * mt.hausdorff, "%d: %g, dense %g",
                      shared, r[shared].level_error[1], mt.hausdorff);
        resurf_mesh_free(w0);
        resurf_mesh_free(w1);
        resurf_scene_free(s);
    }
    /* The coarse sphere kept more, the scene still meets its ratio (or its count without sharing, were that
     * more), and its error fell. */
    ck_assert_uint_gt(coarse_tris[1], coarse_tris[0]);
    size_t allowed = (size_t)floor(ratios[0] * (double)input);
    ck_assert_uint_le(totals[1], totals[0] > allowed ? totals[0] : allowed);
    ck_assert_msg(dense[1] < 0.8 * dense[0], "shared %g, alone %g", dense[1], dense[0]);
    free(path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* An open cylinder x² + y² = 1, z in [−1, 1] (48 × 12 quads), u = θ / 2π, v = (z + 1) / 2, its UV seam at θ = 0
 * (the column of vertices there doubled: u = 0 on one side, 1 on the other), shown by two meshes over the same
 * accessors: meshes[0] with an untextured material, meshes[1] with one whose KHR_materials_clearcoat texture samples
 * TEXCOORD_0 (an extension's texture counts as the core's do). Returns the path (malloc'ed). */
static char *write_seamed_pair_gltf(const char *dir)
{
    enum { NTH = 48, NZ = 12 };
    size_t nv = (NTH + 1) * (NZ + 1), nt = 2 * NTH * NZ;
    size_t pos = 12 * nv, uv = 8 * nv, idx = 12 * nt, total = pos + uv + idx;
    unsigned char *buf = malloc(total);
    for (unsigned j = 0; j <= NZ; ++j)
        for (unsigned i = 0; i <= NTH; ++i) {
            size_t v = (size_t)j * (NTH + 1) + i;
            double th = 2 * M_PI * (i % NTH) / NTH, z = -1 + 2.0 * j / NZ;
            float p[3] = {(float)cos(th), (float)sin(th), (float)z}, t[2] = {(float)i / NTH, (float)(0.5 * (z + 1))};
            memcpy(buf + 12 * v, p, 12);
            memcpy(buf + pos + 8 * v, t, 8);
        }
    uint32_t *ix = malloc(idx);
    for (unsigned j = 0, k = 0; j < NZ; ++j)
        for (unsigned i = 0; i < NTH; ++i) {
            uint32_t a = j * (NTH + 1) + i, b = a + 1, c = a + NTH + 2, d = a + NTH + 1;
            ix[k++] = a, ix[k++] = b, ix[k++] = c, ix[k++] = a, ix[k++] = c, ix[k++] = d;
        }
    memcpy(buf + pos + uv, ix, idx);
    char *b64 = malloc(total / 3 * 4 + 8);
    base64(buf, total, b64);
    const char *prim = "{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},\"indices\":2,\"material\":%d}";
    char p0[128], p1[128];
    snprintf(p0, sizeof p0, prim, 0);
    snprintf(p1, sizeof p1, prim, 1);
    char *json = tu_strf(
        "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_materials_clearcoat\"],\"scene\":0,"
        "\"scenes\":[{\"nodes\":[0,1]}],\"nodes\":[{\"mesh\":0},{\"mesh\":1,\"translation\":[3,0,0]}],"
        "\"meshes\":[{\"primitives\":[%s]},{\"primitives\":[%s]}],"
        "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.1,0.1,0.7,1]}},"
        "{\"extensions\":{\"KHR_materials_clearcoat\":{\"clearcoatFactor\":1,\"clearcoatTexture\":{\"index\":0}}}}],"
        "\"textures\":[{}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\",\"min\":[-1,-1,-1],"
        "\"max\":[1,1,1]},{\"bufferView\":1,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC2\"},"
        "{\"bufferView\":2,\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":%zu},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}],"
        "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"data:application/octet-stream;base64,%s\"}]}",
        p0, p1, nv, nv, 3 * nt, pos, pos, uv, pos + uv, idx, total, b64);
    char *path = tu_path(dir, "seamed.gltf");
    ck_assert_int_eq(tu_write_file(path, json, strlen(json)), 0);
    free(json);
    free(b64);
    free(ix);
    free(buf);
    return path;
}

/* Texcoords that no texture samples hold no seam (resurf_simplify_options.unsampled_texcoords, set per mesh from
 * its materials): the untextured cylinder's level has one vertex per position, the textured one keeps its seam's
 * vertices doubled (more vertices than positions), and both levels still carry their texcoords. */
START_TEST(scene_lods_unsampled_texcoords_hold_no_seam)
{
    char *dir = tu_tempdir();
    char *path = write_seamed_pair_gltf(dir);
    resurf_scene *s = load(path);
    const double ratios[1] = {0.25};
    resurf_simplify_options so = fast_options();
    resurf_scene_lod_options lo = resurf_scene_lod_options_default();
    lo.share_triangles = false;
    resurf_error e;
    ck_assert_msg(resurf_scene_build_lods(s, ratios, 1, &so, &lo, NULL, NULL, &e) == RESURF_OK, "%s", e.message);
    for (size_t p = 0; p < 2; ++p) {
        ck_assert_uint_eq(s->prims[p].lod_count, 1);
        const resurf_mesh *level = s->prims[p].lods[0];
        ck_assert_ptr_nonnull(level->texcoords[0]);
        uint32_t *remap = malloc(level->vertex_count * sizeof *remap);
        size_t positions = 0;
        ck_assert_int_eq(resurfi_weld_exact(NULL, level->positions, level->vertex_count, remap, &positions),
                         RESURF_OK);
        free(remap);
        if (p == 0)
            ck_assert_uint_eq(level->vertex_count, positions);
        else
            ck_assert_uint_gt(level->vertex_count, positions);
    }
    resurf_scene_free(s);
    tu_rmtree(dir);
    free(path);
    free(dir);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("scene_lods");
    TCase *tc = tcase_create("scene_lods");
    tcase_add_test(tc, scene_lods_equal_per_primitive_chains);
    tcase_add_test(tc, scene_lods_cancel_leaves_scene_unchanged);
    tcase_add_test(tc, scene_lods_side_by_side_same_as_one_thread);
    tcase_add_test(tc, scene_lods_errors_named_and_scene_unchanged);
    tcase_add_test(tc, scene_lods_cli_max_triangles_and_errors);
    tcase_add_loop_test(tc, scene_lods_triangles_go_where_the_error_is, 0, 2);
    tcase_add_test(tc, scene_lods_unsampled_texcoords_hold_no_seam);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
