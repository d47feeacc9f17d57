/* One-call levels of detail for a whole scene (resurf_scene_build_lods): every triangle primitive gets a chain from
 * resurf_simplify_lods (simplification with inline restoration onto the primitive's ORIGINAL smooth surface,
 * Semenova et al. §4.2), or one resurf_simplify call per level when the levels have different error bounds; the
 * chain keeps only the levels that help; the levels are measured in world space over the whole scene
 * (scene_world.c), and every mesh that got levels gets its MSFT_lod screen coverage from its own world errors.
 *
 * The call is all or nothing: the chains of every primitive and the coverage arrays are made first, and only when
 * all of them exist (no error, no cancel, no allocation left to fail) are they moved into the scene, which
 * therefore never holds levels of only some primitives.
 *
 * Here: the entry and the chain of each primitive. Apart (scene_lods_internal.h): the shared borders
 * (scene_borders.c), the chains of a mesh whose primitives are simplified together (scene_joint.c), the world errors
 * of the levels (scene_lod_errors.c) and the scene's triangle budget (scene_budget.c). */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "scene_lods_internal.h"

resurf_scene_lod_options resurf_scene_lod_options_default(void)
{
    resurf_scene_lod_options o;
    memset(&o, 0, sizeof o);
    o.struct_size = sizeof o;
    o.set_screen_coverage = true;
    o.keep_shared_borders = true;
    o.share_triangles = true;
    o.pixels = 1;
    o.screen_height = 1080;
    return o;
}

/* MSFT_screencoverage from the measured errors (the derivation is in scene.h at resurf_scene_build_lods):
 * errors[k] is level k's error relative to the mesh's own world diagonal (errors[0], full detail, is not used), out
 * receives `levels` values. */
static void coverage_from_errors(const double *errors, size_t levels, double pixels, double height, double *out)
{
    for (size_t k = 1; k < levels; ++k) {
        double e = errors[k], c = e > 0 && isfinite(e) ? pow(pixels / (e * height), 2) : 1.0;
        c = c > 1 ? 1 : c;
        out[k - 1] = k > 1 && c > out[k - 2] ? out[k - 2] : c;
    }
    out[levels - 1] = 0;
}

/* The caller's progress over the whole scene: the primitive being simplified covers [base, base + span).
 * resurf_simplify_lods reports each stage from 0 to 1 (and RESURF_STAGE_SIMPLIFY once per level), so its fraction is
 * mapped to a share of the primitive by stage (setting up the services over the input is about a third of the work) and
 * never allowed to fall: the caller sees one fraction rising from 0 to 1 over the scene. */
typedef struct scene_progress {
    const resurf_progress *user;
    double base, span;
    double last;
} scene_progress;

static bool forward_progress(void *user, resurf_stage stage, double fraction)
{
    scene_progress *p = user;
    double local = fraction;
    if (stage == RESURF_STAGE_PREPARE)
        local = 0.3 * fraction;
    else if (stage == RESURF_STAGE_SIMPLIFY)
        local = 0.3 + 0.6 * fraction;
    else if (stage == RESURF_STAGE_FINISH)
        local = 0.9 + 0.1 * fraction;
    double f = p->base + p->span * local;
    if (f < p->last)
        f = p->last;
    if (f > 1)
        f = 1;
    p->last = f;
    return resurfi_progress(p->user, stage, f) != 0;
}

/* resurf_simplify_lods promises the input's attribute layout; resurf_scene_save relies on it. A level that broke
 * the promise would be a bug of the simplifier, caught here rather than as a broken file. */
static int same_layout(const resurf_mesh *a, const resurf_mesh *b)
{
    if (!!a->normals != !!b->normals || a->texcoord_count != b->texcoord_count || !!a->colors != !!b->colors ||
        a->extra_count != b->extra_count)
        return 0;
    for (unsigned k = 0; k < b->texcoord_count; ++k)
        if (!b->texcoords[k])
            return 0;
    return 1;
}

static void free_chains(const resurf_allocator *alloc, resurf_mesh ***chains, size_t prim_count, size_t count)
{
    if (!chains)
        return;
    for (size_t p = 0; p < prim_count; ++p) {
        if (!chains[p])
            continue;
        for (size_t k = 0; k < count; ++k)
            resurf_mesh_free(chains[p][k]);
        resurfi_free(alloc, chains[p]);
    }
    resurfi_free(alloc, chains);
}

/* A level misses its ratio when it keeps more than MISS_SLACK × its target + MISS_TRIANGLES triangles: a level
 * short of its target by less is still the level asked for (a guard may keep a few collapses from happening), one
 * that stays at several times its target is not (BoxTextured's 12 triangles at "10%"); the constant term keeps a
 * primitive of a few triangles, whose targets round to nearly nothing, from missing by one triangle. */
#define MISS_SLACK 1.5
#define MISS_TRIANGLES 2

/* Level k's error bound in world units from the options (0 = none). */
static double world_bound(const resurf_scene_lod_options *o, size_t k, double diagonal)
{
    double b = 0;
    if (o->level_max_error_rel && o->level_max_error_rel[k] > 0)
        b = o->level_max_error_rel[k] * diagonal;
    if (o->level_max_error && o->level_max_error[k] > 0 && (b == 0 || o->level_max_error[k] < b))
        b = o->level_max_error[k];
    return b;
}

/* The simplify options of a level: the caller's, with the level's bound (in the primitive's units) added. */
static resurf_simplify_options level_options(const resurf_simplify_options *sim, double bound)
{
    resurf_simplify_options o = *sim;
    o.target_triangles = 0;
    o.target_ratio = 0;
    if (bound > 0)
        o.max_error = o.max_error > 0 ? fmin(o.max_error, bound) : bound;
    return o;
}

/* Whether level k (0-based) of t triangles, stopped for `stop`, ends a chain whose level before it had `before`
 * (see resurf.h at resurf_scene_build_lods): 0 no, 1 it has no fewer triangles, 2 it missed its ratio. */
static int level_ends_chain(size_t input, size_t before, size_t t, const double *ratios, size_t k,
                            resurf_simplify_stop stop)
{
    if (t >= before)
        return 1;
    if (ratios && stop != RESURF_STOP_ERROR && (double)t > MISS_SLACK * ratios[k] * (double)input + MISS_TRIANGLES)
        return 2;
    return 0;
}

/* How many levels of a chain help, from their reports; *why: 0 all of them, else level_ends_chain's answer for the
 * first that does not. */
size_t resurfi_levels_that_help(const resurf_mesh *in, const resurf_simplify_report *rep, const double *ratios,
                                size_t count, int *why)
{
    size_t before = in->triangle_count;
    *why = 0;
    for (size_t k = 0; k < count; ++k) {
        if ((*why = level_ends_chain(in->triangle_count, before, rep[k].triangles, ratios, k, rep[k].stop)))
            return k;
        before = rep[k].triangles;
    }
    return count;
}

/* The same rule asked by the simplifier after each level's collapses, so that a level that ends the chain is
 * neither built nor measured, nor any level after it (on 2CylinderEngine 14 of 34 primitives end early). */
typedef struct chain_rule {
    size_t input, before;
    const double *ratios;
} chain_rule;

static int ends_chain(void *ctx, size_t k, size_t triangles, resurf_simplify_stop stop)
{
    chain_rule *r = ctx;
    if (level_ends_chain(r->input, r->before, triangles, r->ratios, k, stop))
        return 1;
    r->before = triangles;
    return 0;
}

/* The chain a RESURF_RESTORE_NONE run of `in` makes, from the plain half that a measured chain with the same options
 * made (its levels moved out): the same levels, ended by the same rule. 0 when the half lacks a level it needs. */
static int chain_from_half(const resurf_mesh *in, const double *ratios, size_t count, resurfi_plain_half *half,
                           resurf_mesh **chain, resurf_simplify_report *reports)
{
    size_t before = in->triangle_count, end = count;
    for (size_t k = 0; k < count && end == count; ++k) {
        if (!half->levels[k])
            return 0;
        const resurf_simplify_report *r = &half->reports[k];
        if (level_ends_chain(in->triangle_count, before, r->triangles, ratios, k, r->stop))
            end = k;
        before = r->triangles;
    }
    for (size_t k = 0; k < count && k <= end; ++k) {
        reports[k] = half->reports[k];
        if (k == end)
            resurfi_report_unmeasured(&reports[k]);
        else
            chain[k] = half->levels[k], half->levels[k] = NULL;
    }
    return 1;
}

/* One primitive's chain: one resurf_simplify_lods run when every level has the same bound and a ratio, else one
 * resurf_simplify run per level from the original (a bound that grows from level to level cannot be one run: a
 * candidate skipped for its error leaves the queue). A measured run keeps its plain half in `keep`; a plain one
 * starts from `from` where that holds every level it needs (both optional). */
resurf_status resurfi_make_chain(const resurf_mesh *in, const double *ratios, size_t count, const double *bounds,
                                 const resurf_simplify_options *sim, resurf_mesh **chain,
                                 resurf_simplify_report *reports, resurfi_plain_half *keep, resurfi_plain_half *from,
                                 resurf_error *e)
{
    int one_run = ratios != NULL;
    for (size_t k = 1; k < count; ++k)
        one_run = one_run && bounds[k] == bounds[0];
    if (one_run) {
        resurf_simplify_options o = level_options(sim, bounds[0]);
        if (from && o.restore == RESURF_RESTORE_NONE && chain_from_half(in, ratios, count, from, chain, reports))
            return RESURF_OK;
        chain_rule rule = {in->triangle_count, in->triangle_count, ratios};
        resurfi_chain_end end = {ends_chain, &rule};
        return resurfi_simplify_lods_until(in, ratios, count, &o, &end, NULL,
                                           o.restore == RESURF_RESTORE_MEASURED ? keep : NULL, chain, reports, e);
    }
    /* The services over the original once for all the levels. */
    resurfi_simplify_services *services = NULL;
    resurf_status st = resurfi_simplify_services_build(in, sim, &services, e);
    size_t before = in->triangle_count;
    for (size_t k = 0; k < count && st == RESURF_OK; ++k) {
        resurf_simplify_options o = level_options(sim, bounds[k]);
        o.target_ratio = ratios ? ratios[k] : 0;
        if ((st = resurfi_simplify_lent(in, &o, services, &chain[k], &reports[k], e)) != RESURF_OK)
            break;
        /* A level that ends the chain leaves the later ones unmade (they would not be kept). */
        if (level_ends_chain(in->triangle_count, before, reports[k].triangles, ratios, k, reports[k].stop))
            break;
        before = reports[k].triangles;
    }
    resurfi_simplify_services_free(services);
    for (size_t j = 0; j < count && st != RESURF_OK; ++j) {
        resurf_mesh_free(chain[j]);
        chain[j] = NULL;
    }
    return st;
}

/* A monotonic clock in seconds, for the report's phase times. */
static double seconds_now(void)
{
    struct timespec t;
    return clock_gettime(CLOCK_MONOTONIC, &t) == 0 ? (double)t.tv_sec + 1e-9 * (double)t.tv_nsec : 0;
}

/* The area of a mesh's triangles, in its own units. */
double resurfi_mesh_area(const resurf_mesh *m)
{
    double a = 0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t *f = m->indices + 3 * t;
        a += 0.5 * v3_len(v3_tri_cross(resurfi_position(m, f[0]), resurfi_position(m, f[1]),
                                       resurfi_position(m, f[2])));
    }
    return a;
}

/* A primitive's share of the scene's measure_samples: the scene's budget spread by world area (the primitive's
 * area times its mesh's largest scale squared, over the sum of those), at least MIN_PRIMITIVE_SAMPLES and at most
 * the budget. A fixed count per primitive made a 200-triangle part cost as much to measure as a 20,000-triangle one:
 * on 2CylinderEngine (29 primitives) 29 x 100k samples per side and level, about 85% of the call's time. The samples
 * serve a primitive's mean (its maximum comes from the vertices, the facet points and the climb): on 15 converted
 * assets of 500 to 2,000 triangles, 250 samples gave the maxima of 100k and means within 5% (11% at worst). With
 * 1,000 a scene of 400 spheres of 224 triangles took 2.20 s, with 250 1.51 s (docs/performance.md, stop 43). */
#define MIN_PRIMITIVE_SAMPLES 250

static size_t primitive_samples(size_t budget, double world_area, double scene_area)
{
    if (budget == 0)
        return 0;
    double share = scene_area > 0 && isfinite(scene_area) ? world_area / scene_area : 1;
    double n = fmax((double)MIN_PRIMITIVE_SAMPLES, share * (double)budget);
    return n < (double)budget ? (size_t)n : budget;
}

static void half_free(const resurf_allocator *alloc, resurfi_chain_half *h, size_t count)
{
    for (size_t k = 0; h->half.levels && k < count; ++k)
        resurf_mesh_free(h->half.levels[k]);
    resurfi_free(alloc, h->half.levels);
    resurfi_free(alloc, h->half.reports);
    memset(h, 0, sizeof *h);
}

static void lod_work_free(resurfi_lod_work *w, size_t prim_count, size_t mesh_count, size_t count)
{
    free_chains(w->alloc, w->chains, prim_count, count);
    for (size_t p = 0; w->locks && p < prim_count; ++p)
        resurfi_free(w->alloc, w->locks[p]);
    resurfi_free(w->alloc, w->locks);
    resurfi_free(w->alloc, w->unit);
    resurfi_free(w->alloc, w->joint_kept);
    resurfi_free(w->alloc, w->joint_why);
    resurfi_free(w->alloc, w->held);
    for (size_t m = 0; w->coverage && m < mesh_count; ++m)
        resurfi_free(w->alloc, w->coverage[m]);
    resurfi_free(w->alloc, w->coverage);
    resurfi_free(w->alloc, w->errors);
    resurfi_free(w->alloc, w->mesh_levels);
    resurfi_free(w->alloc, w->mesh_scale);
    resurfi_free(w->alloc, w->kept);
    resurf_mesh_free(w->full);
    resurfi_free(w->alloc, w->list.items);
    for (size_t p = 0; w->halves && p < prim_count; ++p)
        half_free(w->alloc, &w->halves[p], count);
    resurfi_free(w->alloc, w->halves);
}

/* ---- the chains of all primitives ---- */

/* The work of primitive p's chain, for progress: its triangles, or its unit's when it goes with others. */
static double chain_weight(const resurfi_chain_job *job, size_t p)
{
    const resurf_scene *scene = job->scene;
    size_t n, triangles = 0;
    if (job->w->unit[p] == SIZE_MAX)
        return (double)scene->prims[p].mesh->triangle_count + 1;
    const size_t *members = resurfi_unit_members(job->w, job->w->unit[p], &n);
    for (size_t q = 0; q < n; ++q)
        triangles += scene->prims[members[q]].mesh->triangle_count + 1;
    return (double)triangles;
}

/* The TEXCOORD_n sets (bit n) that no material of glTF mesh m samples: exporters write texcoords for untextured
 * materials, and their seams would hold the levels for nothing (Collada_teapot_instancenodes' 25% level, held by
 * the UV cost and seams of a blue material with no texture: 1.44x gltfpack's Hausdorff distance, which drops the
 * set). A mesh-file scene has no materials: nothing is known unsampled. */
static uint32_t unsampled_texcoords(const resurf_scene *scene, size_t m)
{
    const resurfi_gltf_view *v = scene->view;
    if (!v || m >= v->mesh_count)
        return 0;
    uint32_t sampled = 0;
    for (size_t q = 0; q < v->meshes[m].primitive_count; ++q) {
        long long mat = v->meshes[m].primitives[q].material;
        if (mat >= 0 && (size_t)mat < v->material_count)
            sampled |= v->materials[mat].texcoords_used;
    }
    return ~sampled;
}

/* A run's options over glTF mesh m (or one of its primitives) of this scale and area (its locks, its share of the
 * samples, the texcoord sets nothing samples), its bounds in its units. */
void resurfi_run_options(const resurfi_chain_job *job, const resurf_simplify_options *base, size_t m, double scale,
                         double area, const uint8_t *lock, resurf_simplify_options *sim, double *bounds)
{
    for (size_t k = 0; k < job->count; ++k)
        bounds[k] = world_bound(job->o, k, job->diagonal) / scale;
    *sim = *base;
    sim->vertex_lock = lock;
    sim->measure_samples = primitive_samples(job->sample_budget, area * scale * scale, job->scene_area);
    sim->unsampled_texcoords = unsampled_texcoords(job->scene, m);
}

/* The options of primitive p's runs (its locks and share of the samples) and its levels' bounds in its units. */
static double primitive_options(const resurfi_chain_job *job, size_t p, const resurf_simplify_options *base,
                                resurf_simplify_options *sim, double *bounds)
{
    const resurfi_scene_prim *prim = &job->scene->prims[p];
    double scale = job->w->mesh_scale[prim->info.mesh] > 0 ? job->w->mesh_scale[prim->info.mesh] : 1;
    resurfi_run_options(job, base, prim->info.mesh, scale, resurfi_mesh_area(prim->mesh), job->w->locks[p], sim,
                        bounds);
    return scale;
}

resurfi_plain_half *resurfi_half_to_keep(resurfi_chain_job *job, size_t p, bool joined, resurf_status *st,
                                         resurf_error *e)
{
    resurfi_lod_work *w = job->w;
    if (!w->halves)
        return NULL;
    resurfi_chain_half *h = &w->halves[p];
    half_free(w->alloc, h, job->count); /* a mesh that was to go joined and goes primitive by primitive */
    h->joined = joined;
    h->half.levels = resurfi_calloc(w->alloc, job->count, sizeof *h->half.levels);
    h->half.reports = resurfi_calloc(w->alloc, job->count, sizeof *h->half.reports);
    if (h->half.levels && h->half.reports)
        return &h->half;
    half_free(w->alloc, h, job->count);
    *st = resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    return NULL;
}

resurfi_plain_half *resurfi_half_to_use(resurfi_chain_job *job, size_t p, bool joined)
{
    resurfi_chain_half *h = job->from_halves ? &job->from_halves[p] : NULL;
    return h && h->half.levels && h->joined == joined ? &h->half : NULL;
}

/* Primitive p's chain with options sim (threads and progress as the caller chose): w->chains[p] and its reports, or
 * status[p] and errors[p]. The leader of a unit makes the chains of all its primitives. */
resurf_status resurfi_make_primitive_chain(resurfi_chain_job *job, size_t p, const resurf_simplify_options *base)
{
    if (job->w->unit[p] != SIZE_MAX)
        return resurfi_make_joint_chain(job, job->w->unit[p], base);

    const resurfi_scene_prim *prim = &job->scene->prims[p];
    resurfi_lod_work *w = job->w;
    size_t count = job->count;
    resurf_simplify_options sim;
    double bounds[RESURF_SCENE_MAX_LEVELS - 1];
    primitive_options(job, p, base, &sim, bounds);
    resurf_error *e = &job->errors[p];
    resurf_mesh **chain = resurfi_calloc(w->alloc, count, sizeof *chain);
    resurf_status st = chain ? RESURF_OK : resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    resurfi_plain_half *keep = st == RESURF_OK ? resurfi_half_to_keep(job, p, false, &st, e) : NULL;
    if (st == RESURF_OK)
        st = resurfi_make_chain(prim->mesh, job->ratios, count, bounds, &sim, chain, job->reports + p * count, keep,
                                resurfi_half_to_use(job, p, false), e);
    for (size_t k = 0; k < count && st == RESURF_OK; ++k)
        if (chain[k] && !same_layout(prim->mesh, chain[k]))
            st = resurfi_error(e, RESURF_ERR_INTERNAL, "level %zu lost an attribute of the input", k + 1);
    if (st != RESURF_OK && chain) {
        for (size_t k = 0; k < count; ++k)
            resurf_mesh_free(chain[k]);
        resurfi_free(w->alloc, chain);
        chain = NULL;
    }
    w->chains[p] = chain;
    job->status[p] = st;
    return st;
}

typedef struct by_size {
    size_t triangles, prim;
} by_size;

static int larger_first(const void *a, const void *b)
{
    const by_size *x = a, *y = b;
    if (x->triangles != y->triangles)
        return x->triangles > y->triangles ? -1 : 1;
    return x->prim < y->prim ? -1 : x->prim > y->prim;
}

/* One primitive of the side-by-side run, on one thread; then the caller's progress, one call at a time. Only a
 * cancel stops the run (a failure is reported in primitive order afterwards). */
static int chain_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    resurfi_chain_job *job = ctx;
    for (size_t i = begin; i < end; ++i) {
        if (atomic_load(&job->cancelled))
            return 1;
        size_t p = job->order[i];
        double weight = chain_weight(job, p);
        resurfi_make_primitive_chain(job, p, job->sim);
        pthread_mutex_lock(&job->lock);
        job->done += weight;
        double f = job->from + job->span * (job->total > 0 ? job->done / job->total : 1);
        /* Not asked again once a cancel was asked for. */
        int stop = atomic_load(&job->cancelled) ||
                   resurfi_progress(&job->o->progress, RESURF_STAGE_SIMPLIFY, f > 1 ? 1 : f) != 0;
        pthread_mutex_unlock(&job->lock);
        if (stop) {
            atomic_store(&job->cancelled, 1);
            return 1;
        }
    }
    return 0;
}

static resurf_status check_arguments(const double *ratios, size_t count, const resurf_simplify_options *sim,
                                     const resurf_scene_lod_options *o, resurf_error *error)
{
    if (count < 1 || count > RESURF_SCENE_MAX_LEVELS - 1)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "%zu levels of detail (1 to %d)", count,
                             RESURF_SCENE_MAX_LEVELS - 1);
    for (size_t k = 0; ratios && k < count; ++k)
        if (!(ratios[k] > 0 && ratios[k] <= 1) || (k && ratios[k] > ratios[k - 1]))
            return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT,
                                 "ratios[%zu] = %g: ratios must lie in (0, 1] and never increase", k, ratios[k]);
    if (!(o->pixels > 0 && isfinite(o->pixels)) || !(o->screen_height > 0 && isfinite(o->screen_height)))
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "pixels (%g) and screen_height (%g) must be positive",
                             o->pixels, o->screen_height);
    for (size_t k = 0; k < count; ++k) {
        double rel = o->level_max_error_rel ? o->level_max_error_rel[k] : 0;
        double abs = o->level_max_error ? o->level_max_error[k] : 0;
        if (!(rel >= 0 && isfinite(rel)) || !(abs >= 0 && isfinite(abs)))
            return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS,
                                 "level %zu: the error bounds must be finite and >= 0", k + 1);
        if (!ratios && rel == 0 && abs == 0 && !(sim->max_error > 0) && !(sim->max_error_rel > 0))
            return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT,
                                 "level %zu has neither a ratio nor an error bound", k + 1);
    }
    return RESURF_OK;
}

/* A restored level whose primitive's own measure finds it nearer than its plain half by more than this, in both the
 * maximum and the mean, is taken as the world measure would take it (that measure sees M's facet points too, and on
 * the 92 converted and glTF2 assets it chose the plain level only where the two were within 5%, or where the
 * primitive's choice had refused the plain level for a few more triangles). */
#define CLEARLY_NEARER 0.9

/* Whether the plain pass may change a level: always where a budget moves triangles between units (its runs make
 * levels of either kind after this is asked: Sweet Home 3D's bus, every level plain before its budget, came out
 * 1.13 times as far from the input in the mean as restore none's), else not where every kept level is the plain one
 * already, nor where every level that is not the plain one is clearly nearer than it by the primitive's own measure
 * (each level is then its chain's, the nearer of its pair). */
static int plain_pass_needed(const resurf_scene *scene, size_t count, const resurfi_lod_work *w,
                             const resurf_simplify_report *reports)
{
    if (w->budget_units > 1)
        return 1;
    for (size_t p = 0; p < scene->prim_count; ++p) {
        const resurfi_chain_half *h = &w->halves[p];
        if (!h->half.levels && w->unit[p] != SIZE_MAX) /* a unit keeps its half at its leader */
            h = &w->halves[w->unit[p]];
        for (size_t k = 0; w->chains[p] && k < w->kept[p] && k < count; ++k) {
            const resurf_simplify_report *r = &reports[p * count + k];
            if (r->restore_used == RESURF_RESTORE_NONE && r->attached_sheets_used != RESURF_SHEETS_KEEP)
                continue;
            if (!h->half.levels || !h->half.levels[k])
                return 1;
            const resurf_simplify_report *plain = &h->half.reports[k];
            if (!(r->max_distance <= CLEARLY_NEARER * plain->max_distance &&
                  r->mean_distance <= CLEARLY_NEARER * plain->mean_distance))
                return 1;
        }
    }
    return 0;
}

/* The plain pass (scene_nearer.c) on a thread of its own, started by the default pass once its chains are made and
 * run beside that pass's budget and world errors: it reads the scene and takes the default's plain halves, which
 * that pass no longer touches, and nothing else they share is written. Its progress only asks whether the call was
 * cancelled; the call's own progress is the default pass's. */
typedef struct plain_pass {
    resurf_scene *scene;
    const double *ratios;
    size_t count;
    resurf_simplify_options sim;
    resurf_scene_lod_options o;
    resurfi_chain_half *halves;
    resurfi_lod_levels_view twin; /* the default's levels, once final (no budget, or this pass after that one) */
    bool has_twin;
    resurfi_lod_work w;
    resurf_simplify_report *reports;
    resurf_scene_lod_report report;
    resurf_status st;
    resurf_error error;
    atomic_int cancel;
    pthread_t thread;
    bool needed, started, ran;
} plain_pass;

static resurf_status make_levels(resurf_scene *scene, const double *ratios, size_t count, resurf_simplify_options sim,
                                 const resurf_scene_lod_options *options, double from, double to, bool keep_halves,
                                 resurfi_chain_half *from_halves, const resurfi_lod_levels_view *twin,
                                 plain_pass *plain, resurfi_lod_work *wp, resurf_simplify_report **reports_out,
                                 resurf_scene_lod_report *out, resurf_error *error);

static bool plain_cancelled(void *user, resurf_stage stage, double fraction)
{
    (void)stage, (void)fraction;
    return atomic_load(&((plain_pass *)user)->cancel) != 0;
}

static void *plain_run(void *arg)
{
    plain_pass *pp = arg;
    pp->o.progress = (resurf_progress){plain_cancelled, pp};
    pp->st = make_levels(pp->scene, pp->ratios, pp->count, pp->sim, &pp->o, 0, 1, false, pp->halves,
                         pp->has_twin ? &pp->twin : NULL, NULL, &pp->w, &pp->reports, &pp->report, &pp->error);
    pp->ran = true;
    return NULL;
}

/* One pass of the levels with sim's restoring mode (phases 1 and 2): every primitive's chain, the scene's budget,
 * the world errors. *wp and *reports_out (count per primitive) are the caller's to free, also after a failure.
 * The caller's progress runs from `from` to `to`. The default pass that a plain one may follow keeps its chains'
 * plain halves (keep_halves) and starts `plain` beside its budget where that pass may change a level; the plain pass
 * starts its chains from them (from_halves) and leaves unmeasured its levels that are the default's (`twin`, when
 * those are final). */
static resurf_status make_levels(resurf_scene *scene, const double *ratios, size_t count, resurf_simplify_options sim,
                                 const resurf_scene_lod_options *options, double from, double to, bool keep_halves,
                                 resurfi_chain_half *from_halves, const resurfi_lod_levels_view *twin,
                                 plain_pass *plain, resurfi_lod_work *wp, resurf_simplify_report **reports_out,
                                 resurf_scene_lod_report *out, resurf_error *error)
{
    const resurf_scene_lod_options o = *options;
    const size_t prim_count = scene->prim_count, mesh_count = scene->mesh_count;
    resurf_status st = RESURF_OK;
    resurf_scene_lod_report report;
    memset(&report, 0, sizeof report);

    /* Everything here ends in the scene or is freed: the scene's allocator (the levels' meshes come from
     * simplify->allocator when it is set, else from the primitive's mesh, which is the scene's). */
    resurfi_lod_work w = {.alloc = &scene->alloc};
    const resurf_allocator *alloc = w.alloc;
    w.chains = resurfi_calloc(alloc, prim_count + 1, sizeof *w.chains);
    w.kept = resurfi_calloc(alloc, prim_count + 1, sizeof *w.kept);
    w.mesh_scale = resurfi_calloc(alloc, mesh_count + 1, sizeof *w.mesh_scale);
    w.mesh_levels = resurfi_calloc(alloc, mesh_count + 1, sizeof *w.mesh_levels);
    w.errors = resurfi_calloc(alloc, (mesh_count + 1) * (count + 1), sizeof *w.errors);
    w.coverage = resurfi_calloc(alloc, mesh_count + 1, sizeof *w.coverage);
    w.locks = resurfi_calloc(alloc, prim_count + 1, sizeof *w.locks);
    w.unit = resurfi_calloc(alloc, 4 * (prim_count + 1), sizeof *w.unit); /* and its lists, below */
    w.joint_kept = resurfi_calloc(alloc, prim_count + 1, sizeof *w.joint_kept);
    w.joint_why = resurfi_calloc(alloc, prim_count + 1, sizeof *w.joint_why);
    w.held = resurfi_calloc(alloc, prim_count + 1, 1);
    if (keep_halves)
        w.halves = resurfi_calloc(alloc, prim_count + 1, sizeof *w.halves);
    if (w.unit) {
        w.unit_members = w.unit + (prim_count + 1);
        w.unit_at = w.unit_members + (prim_count + 1);
        w.unit_size = w.unit_at + (prim_count + 1);
    }
    if (!w.chains || !w.locks || !w.unit || !w.held || !w.joint_kept || !w.joint_why || !w.kept || !w.mesh_scale ||
        !w.mesh_levels || !w.errors || !w.coverage || (keep_halves && !w.halves) ||
        resurfi_scene_gather(scene, alloc, &w.list) != RESURF_OK)
        st = resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory building levels of detail");
    /* The levels measured are the ones made here, not those an MSFT_lod extension of the input names. */
    for (size_t i = 0; st == RESURF_OK && i < w.list.count; ++i)
        w.list.items[i].lod_count = 0;
    if (st == RESURF_OK)
        st = resurfi_scene_flatten(scene, &w.list, 0, NULL, alloc, &w.full, error);
    if (st == RESURF_OK)
        report.diagonal = resurf_mesh_bounds(w.full, NULL, NULL);
    if (st == RESURF_OK && o.keep_shared_borders && resurfi_scene_find_units(scene, &w) != RESURF_OK)
        st = resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory finding shared borders");
    for (size_t p = 0; st == RESURF_OK && !o.keep_shared_borders && p < prim_count; ++p)
        w.unit[p] = SIZE_MAX; /* every primitive alone */
    if (st == RESURF_OK && o.keep_shared_borders &&
        resurfi_scene_shared_between_meshes(scene, &w.list, alloc, w.locks) != RESURF_OK)
        st = resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory finding shared borders");
    for (size_t i = 0; st == RESURF_OK && i < w.list.count; ++i) {
        double *sc = &w.mesh_scale[w.list.items[i].mesh];
        *sc = fmax(*sc, resurfi_matrix_scale(w.list.items[i].world));
    }

    /* The work of each primitive is taken as proportional to its triangles, for the progress fraction. */
    double total = 0, scene_area = 0;
    for (size_t p = 0; st == RESURF_OK && p < prim_count; ++p)
        if (resurfi_scene_rewritten(&scene->prims[p])) {
            const resurfi_scene_prim *prim = &scene->prims[p];
            double scale = w.mesh_scale[prim->info.mesh] > 0 ? w.mesh_scale[prim->info.mesh] : 1;
            total += (double)prim->mesh->triangle_count + 1;
            scene_area += resurfi_mesh_area(prim->mesh) * scale * scale;
        }
    const size_t sample_budget = sim.measure_samples;

    /* Phase 1: the chains and the levels of each that help; the scene is only read. Many primitives run side by
     * side, each on one thread (a small primitive's call is mostly fixed costs that its own threads cannot share);
     * else one after the other with simplify->threads each. The chains do not depend on the thread count, and the
     * results are taken in primitive order: the outcome is the same either way. */
    double chains_start = seconds_now();
    resurfi_chain_job job = {.scene = scene, .ratios = ratios, .count = count, .sim = &sim, .o = &o, .w = &w,
                     .diagonal = report.diagonal, .sample_budget = sample_budget, .scene_area = scene_area,
                     .total = total, .from = from, .span = to - from, .from_halves = from_halves};
    pthread_mutex_init(&job.lock, NULL);
    atomic_init(&job.cancelled, 0);
    job.reports = resurfi_calloc(alloc, prim_count * count + 1, sizeof *job.reports);
    job.status = resurfi_calloc(alloc, prim_count + 1, sizeof *job.status);
    job.errors = resurfi_calloc(alloc, prim_count + 1, sizeof *job.errors);
    size_t *order = resurfi_calloc(alloc, prim_count + 1, sizeof *order), tri_prims = 0;
    if (st == RESURF_OK && (!job.reports || !job.status || !job.errors || !order))
        st = resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory building levels of detail");
    size_t largest = 0;
    for (size_t p = 0; st == RESURF_OK && p < prim_count; ++p) {
        const resurfi_scene_prim *prim = &scene->prims[p];
        report.morphed += prim->info.kind == RESURF_PRIMITIVE_MORPHED;
        if (!resurfi_scene_rewritten(prim))
            report.other++;
        else if (w.unit[p] == SIZE_MAX || w.unit[p] == p) {
            order[tri_prims++] = p; /* a unit is one entry: its leader */
            double weight = chain_weight(&job, p);
            largest = weight > (double)largest ? (size_t)weight : largest;
        }
    }
    unsigned threads = resurfi_thread_count(sim.threads);
    /* Side by side when there are primitives enough for every thread and none holds most of the work. */
    int side_by_side = threads > 1 && !sim.thread_pool && tri_prims >= 2 * (size_t)threads &&
                       (double)largest <= 0.5 * total;
    if (st == RESURF_OK && side_by_side) {
        /* Largest first, so that no thread is left with a big one at the end (ties in primitive order). */
        job.order = order;
        by_size *sorted = resurfi_alloc(alloc, tri_prims, sizeof *sorted);
        if (sorted) { /* else in primitive order */
            for (size_t i = 0; i < tri_prims; ++i)
                sorted[i] = (by_size){(size_t)chain_weight(&job, order[i]), order[i]};
            qsort(sorted, tri_prims, sizeof *sorted, larger_first);
            for (size_t i = 0; i < tri_prims; ++i)
                order[i] = sorted[i].prim;
            resurfi_free(alloc, sorted);
        }
        resurf_simplify_options one = sim;
        one.threads = 1;
        one.progress.fn = NULL;
        job.sim = &one;
        resurfi_parallel_for(tri_prims, 1, threads, chain_block, &job);
        job.sim = &sim;
    } else if (st == RESURF_OK) {
        scene_progress sp = {&o.progress, 0, 0, from};
        sim.progress.fn = o.progress.fn ? forward_progress : NULL;
        sim.progress.user = &sp;
        double done = 0;
        for (size_t i = 0; i < tri_prims; ++i) {
            size_t p = order[i];
            double weight = chain_weight(&job, p);
            sp.base = from + (to - from) * done / total;
            sp.span = (to - from) * weight / total;
            done += weight;
            if (resurfi_make_primitive_chain(&job, p, &sim) != RESURF_OK)
                break;
        }
    }
    /* The outcomes in primitive order: the first failure is the one reported, whatever thread met it first (the
     * side-by-side run stops early only for a cancel). */
    for (size_t p = 0; st == RESURF_OK && p < prim_count; ++p) {
        const resurfi_scene_prim *prim = &scene->prims[p];
        if (!resurfi_scene_rewritten(prim) || job.status[p] == RESURF_OK)
            continue;
        /* The primitive's name first, so that a scene of many primitives says which one failed. */
        const resurf_error *e = &job.errors[p];
        st = job.status[p];
        resurfi_fail(error, st, e->path[0] ? e->path : NULL, e->line, e->offset, "%s: %s", prim->info.name,
                     e->message);
    }
    if (st == RESURF_OK && atomic_load(&job.cancelled))
        st = resurfi_error(error, RESURF_ERR_CANCELLED, "cancelled");
    resurfi_budget_prim *budget = st == RESURF_OK && o.share_triangles && ratios
                                      ? resurfi_calloc(alloc, prim_count + 1, sizeof *budget) : NULL;
    size_t budgeted = 0;
    sim.progress.fn = NULL; /* the budget's runs report no progress */
    if (st == RESURF_OK && o.share_triangles && ratios && !budget)
        st = resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory building levels of detail");
    for (size_t p = 0; st == RESURF_OK && p < prim_count; ++p) {
        const resurfi_scene_prim *prim = &scene->prims[p];
        if (!resurfi_scene_rewritten(prim))
            continue;
        const resurf_simplify_report *reports = job.reports + p * count;
        report.primitives++;
        int why = w.joint_why[p];
        size_t kept = w.joint_kept[p] ? w.joint_kept[p] - 1
                                      : resurfi_levels_that_help(prim->mesh, reports, ratios, count, &why);
        w.kept[p] = kept;
        w.joint_why[p] = why; /* counted below, where the budget has settled where the chain ends */
        if (budget && w.chains[p] && w.unit[p] == p) { /* a unit is one entry */
            resurfi_budget_prim *x = &budget[budgeted++];
            x->scale = resurfi_joint_input(&job, p, &sim, &x->joined, &x->joined_lock, &x->sim, x->bounds, &st, error);
            x->input = x->joined;
            x->members = resurfi_unit_members(&w, p, &x->parts);
            x->part_chains = w.chains, x->part_kept = w.kept, x->part_reports = job.reports;
        } else if (budget && w.chains[p] && w.unit[p] == SIZE_MAX) { /* triangles spent where the error is */
            resurfi_budget_prim *x = &budget[budgeted++];
            x->scale = primitive_options(&job, p, &sim, &x->sim, x->bounds);
            x->input = prim->mesh, x->chain = w.chains[p], x->kept = &w.kept[p];
            x->reports = job.reports + p * count;
        }
    }
    w.budget_units = budget ? budgeted : 0;
    if (st == RESURF_OK && plain && (plain->needed = plain_pass_needed(scene, count, &w, job.reports))) {
        plain->halves = w.halves;
        /* Without a budget these levels are final already: the plain pass may read them beside this pass. */
        plain->has_twin = w.budget_units <= 1;
        plain->twin = (resurfi_lod_levels_view){(resurf_mesh *const *const *)w.chains, w.kept, job.reports, NULL,
                                                count};
        /* Beside this pass only where the caller gave the call threads of its own: one thread, or a host's pool,
           runs it after. */
        if (resurfi_thread_count(sim.threads) > 1 && !sim.thread_pool)
            plain->started = pthread_create(&plain->thread, NULL, plain_run, plain) == 0; /* else run after */
    }
    /* The plain pass's thread holds a core: the budget's runs take the others (2CylinderEngine on 2 cores: 3.65 ->
       3.42 s, median of 6; a small run's fork-join loses more to a third thread than it gains from a second). */
    for (size_t i = 0; plain && plain->started && i < budgeted; ++i)
        budget[i].sim.threads = resurfi_thread_count(sim.threads) - 1;
    if (st == RESURF_OK && budget)
        st = resurfi_scene_budget(budget, budgeted, ratios, count, alloc, error);
    for (size_t i = 0; i < budgeted; ++i)
        resurf_mesh_free(budget[i].joined), resurfi_free(alloc, budget[i].joined_lock);
    resurfi_free(alloc, budget);
    for (size_t p = 0; st == RESURF_OK && p < prim_count; ++p) {
        const resurfi_scene_prim *prim = &scene->prims[p];
        if (!resurfi_scene_rewritten(prim))
            continue;
        size_t kept = w.kept[p], *ml = &w.mesh_levels[prim->info.mesh];
        *ml = *ml > kept + 1 ? *ml : kept + 1;
        if (kept < count && w.joint_why[p] == 1)
            report.level_unreduced[kept + 1]++;
        else if (kept < count && w.joint_why[p] == 2)
            report.level_missed[kept + 1]++;
        else if (kept < count && w.joint_why[p] == 3)
            report.level_emptied[kept + 1]++;
    }
    resurfi_free(alloc, order);
    resurfi_free(alloc, job.status);
    resurfi_free(alloc, job.errors);
    pthread_mutex_destroy(&job.lock);
    /* A cancel after the last progress call of the last primitive still cancels. */
    if (st == RESURF_OK && resurfi_progress(&o.progress, to < 1 ? RESURF_STAGE_SIMPLIFY : RESURF_STAGE_FINISH, to))
        st = resurfi_error(error, RESURF_ERR_CANCELLED, "cancelled");

    size_t levels = 1;
    for (size_t m = 0; st == RESURF_OK && m < mesh_count; ++m)
        levels = w.mesh_levels[m] > levels ? w.mesh_levels[m] : levels;
    for (size_t p = 0; st == RESURF_OK && p < prim_count; ++p) {
        const resurfi_scene_prim *prim = &scene->prims[p];
        for (size_t k = 0; prim->mesh && st == RESURF_OK && k < levels; ++k) {
            size_t e = k < w.kept[p] ? k : w.kept[p];
            report.level_triangles[k] += e && w.chains[p] ? w.chains[p][e - 1]->triangle_count
                                                          : prim->mesh->triangle_count;
        }
    }

    report.chains_seconds = seconds_now() - chains_start;
    double errors_start = seconds_now();
    /* Phase 2: the errors in world space, with the chains as they will be set. */
    report.levels = levels;
    if (st == RESURF_OK && twin) {
        resurfi_lod_levels_view mine = {(resurf_mesh *const *const *)w.chains, w.kept, job.reports, NULL, count};
        resurfi_find_twin_levels(scene, &mine, twin, levels, w.twin_levels);
    }
    if (st == RESURF_OK)
        st = resurfi_level_errors(scene, &w, job.reports, count, sample_budget, sim.threads, o.set_screen_coverage,
                                  &report, error);
    if (st == RESURF_OK && resurfi_progress(&o.progress, to < 1 ? RESURF_STAGE_SIMPLIFY : RESURF_STAGE_FINISH, to))
        st = resurfi_error(error, RESURF_ERR_CANCELLED, "cancelled");

    report.errors_seconds = seconds_now() - errors_start;
    *wp = w;
    *reports_out = job.reports;
    *out = report;
    return st;
}

/* The default (RESURF_RESTORE_MEASURED) against restore none's levels, measured in world space: see
 * resurfi_keep_nearer_levels. */
static int plain_pass_may_help(const resurf_simplify_options *sim)
{
    return sim->restore == RESURF_RESTORE_MEASURED && sim->measure_samples > 0;
}

resurf_status resurf_scene_build_lods(resurf_scene *scene, const double *ratios, size_t count,
                                      const resurf_simplify_options *simplify, const resurf_scene_lod_options *options,
                                      resurf_scene_lod_report *out_report,
                                      resurf_simplify_report *out_primitive_reports, resurf_error *error)
{
    if (!scene)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "scene is NULL");
    RESURFI_CHECK_OPTIONS_ALLOC(simplify, resurf_simplify_options, error);
    RESURFI_CHECK_OPTIONS(options, resurf_scene_lod_options, error);
    const resurf_scene_lod_options o = options ? *options : resurf_scene_lod_options_default();
    resurf_simplify_options sim = simplify ? *simplify : resurf_simplify_options_default();
    resurf_status st = check_arguments(ratios, count, &sim, &o, error);
    if (st != RESURF_OK)
        return st;

    const size_t prim_count = scene->prim_count, mesh_count = scene->mesh_count;
    const resurf_allocator *alloc = &scene->alloc;
    if (out_primitive_reports)
        memset(out_primitive_reports, 0, prim_count * count * sizeof *out_primitive_reports);
    /* With the default restoring, the plain pass beside this one (scene_nearer.c), on one thread. */
    plain_pass pp = {.scene = scene, .ratios = ratios, .count = count, .sim = sim, .o = o};
    pp.sim.restore = RESURF_RESTORE_NONE;
    pp.sim.threads = 1;
    pp.sim.thread_pool = NULL;
    pp.sim.progress.fn = NULL;
    atomic_init(&pp.cancel, 0);
    const bool plain_possible = plain_pass_may_help(&sim);
    resurfi_lod_work w;
    resurf_simplify_report *reports = NULL;
    resurf_scene_lod_report report;
    st = make_levels(scene, ratios, count, sim, &o, 0, plain_possible ? 0.95 : 1, plain_possible, NULL, NULL,
                     plain_possible ? &pp : NULL, &w, &reports, &report, error);
    if (pp.started) {
        if (st != RESURF_OK)
            atomic_store(&pp.cancel, 1);
        pthread_join(pp.thread, NULL);
    } else if (st == RESURF_OK && pp.needed) {
        pp.has_twin = true; /* after the default pass, whose levels are final */
        pp.twin = (resurfi_lod_levels_view){(resurf_mesh *const *const *)w.chains, w.kept, reports, NULL, count};
        plain_run(&pp);
    }
    if (st == RESURF_OK && pp.ran && pp.st != RESURF_OK) {
        st = pp.st;
        if (error)
            *error = pp.error;
    }
    if (st == RESURF_OK && pp.ran) {
        resurfi_level_measure how = {sim.measure_samples, sim.threads, o.set_screen_coverage};
        resurfi_lod_pass d = {&w, reports, &report}, n = {&pp.w, pp.reports, &pp.report};
        st = resurfi_keep_nearer_levels(scene, count, &how, &d, &n, error);
    }
    if (pp.ran) {
        lod_work_free(&pp.w, prim_count, mesh_count, count);
        resurfi_free(alloc, pp.reports);
    }
    if (st == RESURF_OK && plain_possible && resurfi_progress(&o.progress, RESURF_STAGE_FINISH, 1.0))
        st = resurfi_error(error, RESURF_ERR_CANCELLED, "cancelled");
    for (size_t p = 0; st == RESURF_OK && out_primitive_reports && p < prim_count; ++p)
        for (size_t k = 0; resurfi_scene_rewritten(&scene->prims[p]) && k < count && k <= w.kept[p]; ++k)
            out_primitive_reports[p * count + k] = reports[p * count + k];
    resurfi_free(alloc, reports);

    /* Phase 3: the coverage of every mesh that has levels. */
    for (size_t m = 0; m < mesh_count && st == RESURF_OK && o.set_screen_coverage; ++m) {
        if (w.mesh_levels[m] < 2)
            continue;
        if (!(w.coverage[m] = resurfi_alloc(alloc, w.mesh_levels[m], sizeof **w.coverage))) {
            st = resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory building levels of detail");
            break;
        }
        coverage_from_errors(w.errors + m * (count + 1), w.mesh_levels[m], o.pixels, o.screen_height,
                             w.coverage[m]);
    }

    if (st != RESURF_OK) {
        if (out_primitive_reports)
            memset(out_primitive_reports, 0, prim_count * count * sizeof *out_primitive_reports);
        lod_work_free(&w, prim_count, mesh_count, count);
        return st;
    }

    /* Phase 4: move everything into the scene; nothing can fail from here on. Levels that do not help are freed. */
    for (size_t p = 0; p < prim_count; ++p) {
        if (!w.chains[p])
            continue;
        resurfi_scene_prim *prim = &scene->prims[p];
        for (size_t k = 0; k < prim->lod_count; ++k)
            resurf_mesh_free(prim->lods[k]);
        resurfi_free(alloc, prim->lods);
        for (size_t k = w.kept[p]; k < count; ++k)
            resurf_mesh_free(w.chains[p][k]);
        prim->lods = w.kept[p] ? w.chains[p] : NULL;
        prim->lod_count = w.kept[p];
        if (!w.kept[p])
            resurfi_free(alloc, w.chains[p]);
        w.chains[p] = NULL;
    }
    for (size_t m = 0; m < mesh_count; ++m) {
        size_t own = 1;
        for (size_t p = scene->mesh_first[m]; p < scene->mesh_first[m + 1]; ++p)
            own = scene->prims[p].lod_count + 1 > own ? scene->prims[p].lod_count + 1 : own;
        if (!w.coverage[m] && (!scene->coverage[m] || scene->coverage_count[m] == own))
            continue;
        /* New values, or old ones that no longer fit the mesh's levels (the defaults are written then). */
        resurfi_free(alloc, scene->coverage[m]);
        scene->coverage[m] = w.coverage[m];
        scene->coverage_count[m] = w.coverage[m] ? own : 0;
        w.coverage[m] = NULL;
    }
    lod_work_free(&w, prim_count, mesh_count, count);
    if (out_report)
        *out_report = report;
    resurfi_clear_error(error);
    return RESURF_OK;
}
