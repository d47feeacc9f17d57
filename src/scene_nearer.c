/* The default's levels against the plain ones (resurf_scene_build_lods with RESURF_RESTORE_MEASURED).
 *
 * Each primitive's default level is already the nearer of its inline and its plain level (simplify.c), by the
 * primitive's own measure. The scene's levels are not: the budget (scene_budget.c) spends the triangles by the
 * errors it sees, which differ between the modes, and the world measure sees more than a primitive's own (the
 * spider's ASCII export at 25%: 1.566e-2 of the diagonal by default, 1.461e-2 with `restore none`; WusonOrange's one
 * primitive at 10%, whose plain level the primitive's choice refused for its 463 triangles against 451: 4.43e-2
 * against 4.22e-2). So the levels are also made without restoration, as `restore none` makes them (its chains from
 * the plain halves the default's chains made already: only the budget's runs are new), and level by level the
 * default's is kept only where it is as near the input as the plain one in both the two-sided maximum and the mean,
 * or nearer by more than the measurement's noise; else the plain level is taken.
 *
 * Levels taken from both passes must still make every primitive a chain: each level a new mesh with fewer
 * triangles than its level before, or the same mesh as before, after which the primitive has ended. Where they do
 * not, the primitive takes its plain level in place of the default's nearest before the break, until they do.
 * Without such a repair, scene level k is exactly its pass's level k, and its errors are that pass's; with one, the
 * levels are measured again, and kept only where none is farther than the plain pass's; else the plain pass is
 * taken whole, which is never farther than itself. */
#include <math.h>
#include <string.h>

#include "scene_lods_internal.h"

/* The measured figures are sampled: the maximum is the largest distance the points found, which can miss the
 * farthest point by a few percent, and the mean's noise is under a percent. The default's level stays only where it
 * is as near as the plain one or nearer by more than that: ClearCoatTest's 25% level measured 0.963x the plain
 * one's maximum here and 1.0135x with 2M samples a side; Collada_human's mean 0.9996x here, 1.001x with the
 * benchmark's own samples. */
#define NEARER_MAX 0.95
#define NEARER_MEAN 0.99

static int not_farther(double mine, double plain, double by) { return mine == plain || mine <= by * plain; }

static int level_not_farther(const resurf_scene_lod_report *r, const resurf_scene_lod_report *plain, size_t k)
{
    if (k >= plain->levels || !isfinite(plain->level_error_rel[k]) || !isfinite(plain->level_mean_rel[k]))
        return 1;
    return not_farther(r->level_error_rel[k], plain->level_error_rel[k], NEARER_MAX) &&
           not_farther(r->level_mean_rel[k], plain->level_mean_rel[k], NEARER_MEAN);
}

/* Primitive p's level k (>= 1) in a pass: its last level up to k (index in its chain: *at), NULL for its input. */
static resurf_mesh *shown(const resurfi_lod_pass *pass, size_t p, size_t k, size_t *at)
{
    const resurfi_lod_work *w = pass->w;
    size_t s = w->kept[p] < k ? w->kept[p] : k;
    *at = s ? s - 1 : 0;
    return s && w->chains[p] ? w->chains[p][s - 1] : NULL;
}

/* The levels chosen, as borrowed meshes: per primitive its chain (chain[p × count + j]), the pass and index each
 * level comes from, and its length. */
typedef struct mix {
    resurf_mesh **chain;
    unsigned char *pass;
    size_t *index, *kept;
    int repaired;
} mix;

/* Walks primitive p's levels, level k from passes[src[k]]: 0 when they form a chain (each level a new mesh with
 * fewer triangles than the level before it, or the same mesh as before, after which the primitive has ended), else
 * the first level k that breaks it. With x, the chain goes into x on the way (each mesh once). */
static size_t walk_levels(const resurfi_lod_pass passes[2], const unsigned char *src, size_t levels, size_t count,
                          size_t p, size_t input_triangles, mix *x)
{
    const resurf_mesh *before = NULL;
    size_t triangles = input_triangles, n = 0, at;
    int ended = 0;
    for (size_t k = 1; k < levels; ++k) {
        resurf_mesh *m = shown(&passes[src[k]], p, k, &at);
        if (m == before) {
            ended = 1;
            continue;
        }
        if (ended || !m || m->triangle_count >= triangles)
            return k;
        if (x)
            x->chain[p * count + n] = m, x->pass[p * count + n] = src[k], x->index[p * count + n] = at;
        n++;
        before = m, triangles = m->triangle_count;
    }
    if (x)
        x->kept[p] = n;
    return 0;
}

/* Primitive p's levels: level k from passes[from[k]], except where that breaks its chain: there the default's
 * level nearest before the break gives way to the plain one, until none breaks (all plain is a chain). */
static void mix_primitive(const resurfi_lod_pass passes[2], const unsigned char *from, size_t levels, size_t count,
                          size_t p, size_t input_triangles, mix *x)
{
    unsigned char src[RESURF_SCENE_MAX_LEVELS];
    memcpy(src, from, sizeof src);
    for (size_t k; (k = walk_levels(passes, src, levels, count, p, input_triangles, NULL)) != 0;) {
        while (k > 0 && src[k] == 1)
            k--;
        if (k == 0) /* cannot happen: the plain pass's own levels form a chain */
            break;
        src[k] = 1;
        x->repaired = 1;
    }
    walk_levels(passes, src, levels, count, p, input_triangles, x);
}

/* Level k's figures from another pass's report. */
/* Level k's measured world errors, from one report into another. */
static void copy_measured(resurf_scene_lod_report *r, const resurf_scene_lod_report *from, size_t k)
{
    r->level_error_rel[k] = from->level_error_rel[k];
    r->level_error[k] = from->level_error[k];
    r->level_mean_rel[k] = from->level_mean_rel[k];
    r->level_to_full_rel[k] = from->level_to_full_rel[k];
    r->level_from_full_rel[k] = from->level_from_full_rel[k];
}

static void take_level(resurf_scene_lod_report *r, const resurf_scene_lod_report *from, size_t k, bool plain)
{
    r->level_triangles[k] = from->level_triangles[k];
    copy_measured(r, from, k);
    r->level_unreduced[k] = from->level_unreduced[k];
    r->level_missed[k] = from->level_missed[k];
    r->level_emptied[k] = from->level_emptied[k];
    r->level_plain[k] = plain;
}

/* The plain pass in place of the default's, whole (the caller frees what `plain` then holds). */
static void take_plain(const resurf_scene *scene, size_t count, resurfi_lod_pass *d, resurfi_lod_pass *plain)
{
    resurfi_lod_work t = *d->w;
    *d->w = *plain->w, *plain->w = t;
    memcpy(d->reports, plain->reports, scene->prim_count * count * sizeof *d->reports);
    for (size_t k = 1; k < RESURF_SCENE_MAX_LEVELS; ++k)
        take_level(d->report, plain->report, k, true);
    d->report->levels = plain->report->levels;
}

/* Each primitive's reports as its mixed chain is: each level's own, then from the level that ended it on, its
 * pass's (the level that did not help, first). */
static void mixed_reports(const resurf_scene *scene, size_t count, const resurfi_lod_pass passes[2], const mix *x,
                          resurf_simplify_report *out)
{
    for (size_t p = 0; p < scene->prim_count; ++p) {
        size_t kept = x->kept[p], last = kept ? x->pass[p * count + kept - 1] : 0;
        size_t after = kept ? x->index[p * count + kept - 1] + 1 : 0;
        for (size_t j = 0; j < count; ++j) {
            size_t i = after + (j - kept);
            const resurf_simplify_report *own = passes[j < kept ? x->pass[p * count + j] : last].reports + p * count;
            out[p * count + j] = j < kept ? own[x->index[p * count + j]] : i < count ? own[i] : (resurf_simplify_report){0};
        }
    }
}

/* The mixed levels become the default pass's: their meshes move out of both passes into new chains. */
static resurf_status commit(const resurf_scene *scene, size_t count, resurfi_lod_pass passes[2], const mix *x,
                            resurf_error *error)
{
    resurfi_lod_work *w = passes[0].w;
    const size_t prim_count = scene->prim_count;
    resurf_mesh ***chains = resurfi_calloc(w->alloc, prim_count + 1, sizeof *chains);
    int failed = !chains;
    for (size_t p = 0; !failed && p < prim_count; ++p)
        if (w->chains[p] || passes[1].w->chains[p])
            failed = !(chains[p] = resurfi_calloc(w->alloc, count, sizeof **chains));
    if (failed) {
        for (size_t p = 0; chains && p < prim_count; ++p)
            resurfi_free(w->alloc, chains[p]);
        resurfi_free(w->alloc, chains);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory building levels of detail");
    }
    for (size_t p = 0; p < prim_count; ++p) {
        if (!chains[p])
            continue;
        for (size_t j = 0; j < x->kept[p]; ++j) {
            chains[p][j] = x->chain[p * count + j];
            passes[x->pass[p * count + j]].w->chains[p][x->index[p * count + j]] = NULL;
        }
        for (int s = 0; s < 2; ++s) {
            resurfi_lod_work *ws = passes[s].w;
            for (size_t k = 0; ws->chains[p] && k < count; ++k)
                resurf_mesh_free(ws->chains[p][k]);
            resurfi_free(w->alloc, ws->chains[p]);
            ws->chains[p] = NULL;
        }
        w->chains[p] = chains[p];
        w->kept[p] = x->kept[p];
    }
    resurfi_free(w->alloc, chains);
    return RESURF_OK;
}

/* The same surface, byte for byte: its world errors are the same. */
static int same_surface(const resurf_mesh *a, const resurf_mesh *b)
{
    return a->vertex_count == b->vertex_count && a->triangle_count == b->triangle_count &&
           !memcmp(a->positions, b->positions, 3 * a->vertex_count * sizeof *a->positions) &&
           !memcmp(a->indices, b->indices, 3 * a->triangle_count * sizeof *a->indices);
}

/* The figures of a primitive's report that the world errors are composed from (resurfi_add_instance), as bits. */
static int same_figures(const resurf_simplify_report *a, const resurf_simplify_report *b)
{
    const double x[4] = {a->result_to_input_max, a->input_to_result_max, a->result_to_input_mean,
                         a->input_to_result_mean};
    const double y[4] = {b->result_to_input_max, b->input_to_result_max, b->result_to_input_mean,
                         b->input_to_result_mean};
    return !memcmp(x, y, sizeof x);
}

/* The plain pass's levels that are also the default's: where the default's budget left a primitive's level plain, or
 * there was no budget, the two passes show the same levels, and measuring them twice gave the same figures (the
 * main job's scan: its 50% and 25% levels, two of its three). */
void resurfi_find_twin_levels(const resurf_scene *scene, const resurfi_lod_levels_view *plain,
                              const resurfi_lod_levels_view *d, size_t levels, bool *twin)
{
    for (size_t k = 1; k < levels && k < RESURF_SCENE_MAX_LEVELS; ++k) {
        twin[k] = true;
        for (size_t p = 0; p < scene->prim_count && twin[k]; ++p) {
            size_t sp = plain->chains[p] ? (plain->kept[p] < k ? plain->kept[p] : k) : 0;
            size_t sd = d->chains[p] ? (d->kept[p] < k ? d->kept[p] : k) : 0;
            twin[k] = sp == sd && (!sp || (same_surface(plain->chains[p][sp - 1], d->chains[p][sp - 1]) &&
                                           same_figures(&plain->reports[p * plain->count + sp - 1],
                                                        &d->reports[p * d->count + sp - 1])));
        }
    }
}

/* The measured figures of the plain pass's twin levels, from the default's. */
static void copy_twin_levels(const resurf_scene *scene, size_t count, const resurfi_lod_pass *d,
                             resurfi_lod_pass *plain)
{
    resurf_scene_lod_report *r = plain->report;
    const resurf_scene_lod_report *from = d->report;
    for (size_t k = 1; k < r->levels; ++k) {
        if (!plain->w->twin_levels[k])
            continue;
        copy_measured(r, from, k);
        for (size_t m = 0; m < scene->mesh_count; ++m)
            if (k < plain->w->mesh_levels[m])
                plain->w->errors[m * (count + 1) + k] = d->w->errors[m * (count + 1) + k];
    }
}

/* Each mesh's count of levels (1 + its primitives' most), and the scene's. */
static size_t mesh_levels(const resurf_scene *scene, resurf_mesh **const *chains, const size_t *kept, size_t *out)
{
    size_t levels = 1;
    for (size_t m = 0; m < scene->mesh_count; ++m) {
        size_t ml = 1;
        for (size_t p = scene->mesh_first[m]; p < scene->mesh_first[m + 1]; ++p)
            ml = chains[p] && kept[p] + 1 > ml ? kept[p] + 1 : ml;
        out[m] = ml;
        levels = ml > levels ? ml : levels;
    }
    return levels;
}

resurf_status resurfi_keep_nearer_levels(const resurf_scene *scene, size_t count, const resurfi_level_measure *how,
                                         resurfi_lod_pass *d, resurfi_lod_pass *plain, resurf_error *error)
{
    d->report->chains_seconds += plain->report->chains_seconds;
    d->report->errors_seconds += plain->report->errors_seconds;
    copy_twin_levels(scene, count, d, plain);
    const size_t levels = d->report->levels, prim_count = scene->prim_count, mesh_count = scene->mesh_count;
    unsigned char from[RESURF_SCENE_MAX_LEVELS] = {0};
    int any = 0;
    for (size_t k = 1; k < levels; ++k)
        any |= from[k] = (unsigned char)!level_not_farther(d->report, plain->report, k);
    if (!any)
        return RESURF_OK;

    const resurf_allocator *alloc = d->w->alloc;
    resurfi_lod_pass passes[2] = {*d, *plain};
    mix x = {resurfi_calloc(alloc, prim_count * count + 1, sizeof *x.chain),
             resurfi_calloc(alloc, prim_count * count + 1, sizeof *x.pass),
             resurfi_calloc(alloc, prim_count * count + 1, sizeof *x.index),
             resurfi_calloc(alloc, prim_count + 1, sizeof *x.kept), 0};
    resurf_simplify_report *reports = resurfi_calloc(alloc, prim_count * count + 1, sizeof *reports);
    size_t *ml = resurfi_calloc(alloc, mesh_count + 1, sizeof *ml);
    double *errors = resurfi_calloc(alloc, (mesh_count + 1) * (count + 1), sizeof *errors);
    resurf_mesh ***view = resurfi_calloc(alloc, prim_count + 1, sizeof *view);
    resurf_status st = x.chain && x.pass && x.index && x.kept && reports && ml && errors && view
                           ? RESURF_OK
                           : resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory building levels of detail");
    for (size_t p = 0; st == RESURF_OK && p < prim_count; ++p)
        if (d->w->chains[p] || plain->w->chains[p]) {
            mix_primitive(passes, from, levels, count, p, scene->prims[p].mesh->triangle_count, &x);
            view[p] = x.chain + p * count;
        }
    resurf_scene_lod_report r = *d->report;
    if (st == RESURF_OK) {
        mixed_reports(scene, count, passes, &x, reports);
        r.levels = mesh_levels(scene, view, x.kept, ml);
        for (size_t k = 1; k < RESURF_SCENE_MAX_LEVELS; ++k)
            if (k < levels && from[k])
                take_level(&r, plain->report, k, true);
    }
    if (st == RESURF_OK && x.repaired) {
        /* A primitive took another level than its pass's: the levels are measured as they now are. */
        resurfi_lod_work mixed = *d->w;
        mixed.chains = view, mixed.kept = x.kept, mixed.mesh_levels = ml, mixed.errors = errors;
        for (size_t k = 0; k < r.levels; ++k) {
            r.level_triangles[k] = 0;
            for (size_t p = 0; p < prim_count; ++p) {
                size_t j = view[p] ? (k < x.kept[p] ? k : x.kept[p]) : 0;
                if (scene->prims[p].mesh)
                    r.level_triangles[k] += j ? view[p][j - 1]->triangle_count : scene->prims[p].mesh->triangle_count;
            }
        }
        st = resurfi_level_errors(scene, &mixed, reports, count, how->samples, how->threads, how->per_mesh, &r,
                                  error);
        for (size_t k = 1; st == RESURF_OK && k < r.levels; ++k)
            if (!level_not_farther(&r, plain->report, k)) {
                take_plain(scene, count, d, plain);
                goto done;
            }
    } else if (st == RESURF_OK) {
        /* Each level is its pass's: so are each mesh's errors there, where the mesh shows its level up to k. */
        for (size_t m = 0; m < mesh_count; ++m)
            for (size_t k = 1; k < ml[m]; ++k) {
                const resurfi_lod_work *ps = passes[from[k]].w;
                size_t j = ps->mesh_levels[m] > k ? k : ps->mesh_levels[m] - 1;
                errors[m * (count + 1) + k] = j ? ps->errors[m * (count + 1) + j] : 0;
            }
    }
    if (st == RESURF_OK)
        st = commit(scene, count, passes, &x, error);
    if (st == RESURF_OK) {
        memcpy(d->reports, reports, prim_count * count * sizeof *reports);
        memcpy(d->w->mesh_levels, ml, mesh_count * sizeof *ml);
        memcpy(d->w->errors, errors, mesh_count * (count + 1) * sizeof *errors);
        *d->report = r;
    }
done:
    resurfi_free(alloc, view);
    resurfi_free(alloc, errors);
    resurfi_free(alloc, ml);
    resurfi_free(alloc, reports);
    resurfi_free(alloc, x.kept);
    resurfi_free(alloc, x.index);
    resurfi_free(alloc, x.pass);
    resurfi_free(alloc, x.chain);
    return st;
}
