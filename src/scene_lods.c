/* One-call levels of detail for a whole scene (resurf_scene_build_lods): every triangle primitive gets a chain from
 * resurf_simplify_lods (simplification with inline restoration onto the primitive's ORIGINAL smooth surface,
 * Semenova et al. §4.2), and every mesh that got levels gets its MSFT_lod screen coverage from the measured errors.
 *
 * The call is all or nothing: the chains of every primitive and the coverage arrays are made first, and only when
 * all of them exist (no error, no cancel, no allocation left to fail) are they moved into the scene, which
 * therefore never holds levels of only some primitives. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene_internal.h"

resurf_scene_lod_options resurf_scene_lod_options_default(void)
{
    resurf_scene_lod_options o;
    memset(&o, 0, sizeof o);
    o.struct_size = sizeof o;
    o.set_screen_coverage = true;
    o.pixels = 1;
    o.screen_height = 1080;
    return o;
}

/* MSFT_screencoverage from the measured errors (the derivation is in resurf.h at resurf_scene_build_lods):
 * errors[k] is level k's relative error (errors[0], full detail, is not used), out receives `levels` values. */
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

resurf_status resurf_scene_build_lods(resurf_scene *scene, const double *ratios, size_t count,
                                      const resurf_simplify_options *simplify, const resurf_scene_lod_options *options,
                                      resurf_scene_lod_report *out_report,
                                      resurf_simplify_report *out_primitive_reports, resurf_error *error)
{
    if (!scene || !ratios)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "scene or ratios is NULL");
    RESURFI_CHECK_OPTIONS_ALLOC(simplify, resurf_simplify_options, error);
    RESURFI_CHECK_OPTIONS(options, resurf_scene_lod_options, error);
    if (count < 1 || count > RESURF_SCENE_MAX_LEVELS - 1)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "%zu levels of detail (1 to %d)", count,
                             RESURF_SCENE_MAX_LEVELS - 1);
    for (size_t k = 0; k < count; ++k)
        if (!(ratios[k] > 0 && ratios[k] <= 1) || (k && ratios[k] > ratios[k - 1]))
            return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT,
                                 "ratios[%zu] = %g: ratios must lie in (0, 1] and never increase", k, ratios[k]);
    const resurf_scene_lod_options o = options ? *options : resurf_scene_lod_options_default();
    if (!(o.pixels > 0 && isfinite(o.pixels)) || !(o.screen_height > 0 && isfinite(o.screen_height)))
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "pixels (%g) and screen_height (%g) must be positive",
                             o.pixels, o.screen_height);
    resurf_simplify_options sim = simplify ? *simplify : resurf_simplify_options_default();

    const size_t prim_count = scene->prim_count, mesh_count = scene->mesh_count, levels = count + 1;
    if (out_primitive_reports)
        memset(out_primitive_reports, 0, prim_count * count * sizeof *out_primitive_reports);
    resurf_scene_lod_report report;
    memset(&report, 0, sizeof report);
    report.levels = levels;

    /* The work of each primitive is taken as proportional to its triangles, for the progress fraction. */
    double total = 0;
    for (size_t p = 0; p < prim_count; ++p)
        if (scene->prims[p].info.kind == RESURF_PRIMITIVE_TRIANGLES)
            total += (double)scene->prims[p].mesh->triangle_count + 1;

    /* Everything here ends in the scene or is freed: the scene's allocator (the levels' meshes come from
     * simplify->allocator when it is set, else from the primitive's mesh, which is the scene's). */
    const resurf_allocator *alloc = &scene->alloc;
    resurf_mesh ***chains = resurfi_calloc(alloc, prim_count, sizeof *chains);
    double *errors = resurfi_calloc(alloc, mesh_count * levels, sizeof *errors); /* per mesh and level */
    double **coverage = resurfi_calloc(alloc, mesh_count, sizeof *coverage);
    resurf_status st = RESURF_OK;
    if (!chains || !errors || !coverage)
        st = resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory building levels of detail");

    /* Phase 1: the chains, one primitive after the other; the scene is only read. */
    scene_progress sp = {&o.progress, 0, 0, 0};
    sim.progress.fn = o.progress.fn ? forward_progress : NULL;
    sim.progress.user = &sp;
    double done = 0;
    for (size_t p = 0; p < prim_count && st == RESURF_OK; ++p) {
        const resurfi_scene_prim *prim = &scene->prims[p];
        if (prim->info.kind == RESURF_PRIMITIVE_MORPHED) {
            report.morphed++;
            for (size_t k = 0; k < levels; ++k)
                report.level_triangles[k] += prim->mesh->triangle_count;
            continue;
        }
        if (prim->info.kind != RESURF_PRIMITIVE_TRIANGLES) {
            report.other++;
            continue;
        }
        double weight = (double)prim->mesh->triangle_count + 1;
        sp.base = done / total;
        sp.span = weight / total;
        done += weight;
        resurf_simplify_report reports[RESURF_SCENE_MAX_LEVELS - 1];
        resurf_error e;
        if (!(chains[p] = resurfi_calloc(alloc, count, sizeof **chains))) {
            st = resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory building levels of detail");
            break;
        }
        st = resurf_simplify_lods(prim->mesh, ratios, count, &sim, chains[p], reports, &e);
        for (size_t k = 0; k < count && st == RESURF_OK; ++k)
            if (!same_layout(prim->mesh, chains[p][k]))
                st = resurfi_error(&e, RESURF_ERR_INTERNAL, "level %zu lost an attribute of the input", k + 1);
        if (st != RESURF_OK) {
            /* The primitive's name first, so that a scene of many primitives says which one failed. */
            resurfi_fail(error, st, e.path[0] ? e.path : NULL, e.line, e.offset, "%s: %s", prim->info.name,
                         e.message);
            break;
        }
        report.primitives++;
        report.level_triangles[0] += prim->mesh->triangle_count;
        for (size_t k = 0; k < count; ++k) {
            double err = reports[k].max_distance_rel;
            report.level_triangles[k + 1] += chains[p][k]->triangle_count;
            if (isfinite(err)) {
                double *mesh_err = &errors[prim->info.mesh * levels + k + 1];
                *mesh_err = fmax(*mesh_err, err);
                report.level_error_rel[k + 1] = fmax(report.level_error_rel[k + 1], err);
            }
            if (out_primitive_reports)
                out_primitive_reports[p * count + k] = reports[k];
        }
    }
    /* A cancel after the last progress call of the last primitive still cancels. */
    if (st == RESURF_OK && resurfi_progress(&o.progress, RESURF_STAGE_FINISH, 1.0))
        st = resurfi_error(error, RESURF_ERR_CANCELLED, "cancelled");

    /* Phase 2: the coverage of every mesh that got levels (a mesh of morphed or point primitives got none). */
    for (size_t m = 0; m < mesh_count && st == RESURF_OK && o.set_screen_coverage; ++m) {
        int has_levels = 0;
        for (size_t p = scene->mesh_first[m]; p < scene->mesh_first[m + 1]; ++p)
            has_levels |= chains[p] != NULL;
        if (!has_levels)
            continue;
        if (!(coverage[m] = resurfi_alloc(alloc, levels, sizeof **coverage))) {
            st = resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory building levels of detail");
            break;
        }
        coverage_from_errors(errors + m * levels, levels, o.pixels, o.screen_height, coverage[m]);
    }

    if (st != RESURF_OK) {
        if (out_primitive_reports)
            memset(out_primitive_reports, 0, prim_count * count * sizeof *out_primitive_reports);
        free_chains(alloc, chains, prim_count, count);
        for (size_t m = 0; coverage && m < mesh_count; ++m)
            resurfi_free(alloc, coverage[m]);
        resurfi_free(alloc, coverage);
        resurfi_free(alloc, errors);
        return st;
    }

    /* Phase 3: move everything into the scene; nothing can fail from here on. */
    for (size_t p = 0; p < prim_count; ++p) {
        if (!chains[p])
            continue;
        resurfi_scene_prim *prim = &scene->prims[p];
        for (size_t k = 0; k < prim->lod_count; ++k)
            resurf_mesh_free(prim->lods[k]);
        resurfi_free(alloc, prim->lods);
        prim->lods = chains[p];
        prim->lod_count = count;
        chains[p] = NULL;
    }
    for (size_t m = 0; m < mesh_count; ++m) {
        if (!coverage[m])
            continue;
        resurfi_free(alloc, scene->coverage[m]);
        scene->coverage[m] = coverage[m];
        scene->coverage_count[m] = levels;
    }
    resurfi_free(alloc, chains);
    resurfi_free(alloc, coverage);
    resurfi_free(alloc, errors);
    if (out_report)
        *out_report = report;
    resurfi_clear_error(error);
    return RESURF_OK;
}
