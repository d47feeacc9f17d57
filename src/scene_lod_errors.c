/* The world errors of resurf_scene_build_lods's levels: composed from the primitives' own two-sided reports when
 * every instance is a similarity of its mesh, with each side's maximum over the whole scene measured only near the
 * instances that may hold it; else measured on the flattened world (resurfi_measure_level). Apart from the chains
 * because it only reads them. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene_lods_internal.h"
#include "vec3.h"

/* The largest scale of a world matrix (column-major; NULL = identity): its longest column, which is exact for the
 * translation · rotation · scale products of glTF node transforms. */
double resurfi_matrix_scale(const double *a)
{
    if (!a)
        return 1;
    double best = 0;
    for (int c = 0; c < 3; ++c)
        best = fmax(best, sqrt(a[4 * c] * a[4 * c] + a[4 * c + 1] * a[4 * c + 1] + a[4 * c + 2] * a[4 * c + 2]));
    return best > 0 ? best : 1;
}

/* Whether the world matrix a (column-major; NULL = identity) is a similarity, a rotation and a uniform scale and a
 * move, under which every distance is its scale (*scale) times the one in the primitive's units (to 1e-5). */
static int is_similarity(const double *a, double *scale)
{
    *scale = resurfi_matrix_scale(a);
    if (!a)
        return 1;
    vec3 c[3] = {v3(a[0], a[1], a[2]), v3(a[4], a[5], a[6]), v3(a[8], a[9], a[10])};
    double s2 = *scale * *scale, tol = 1e-5 * s2; /* float matrices of a file, multiplied down a hierarchy */
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j)
            if (fabs(v3_dot(c[i], c[j]) - (i == j ? s2 : 0)) > tol)
                return 0;
    return 1;
}

/* Adds what instance `item` shows at level k to *e from its primitives' own two-sided reports (reports[p × count
 * + j] for level j + 1 of primitive p; areas[p × (count + 1) + j] the area of primitive p's level j, 0 = full
 * detail): a primitive at full detail adds nothing but its area. 0 when the reports cannot say it: the transform is
 * not a similarity, or a shown level was not measured. The maxima bound the whole scene's from above (a point's
 * distance to all of level 0 is at most its distance to its own primitive's) and equal it where no other
 * primitive lies nearer than the error; the means are those of area-uniform samples, as resurf_compare's. */
int resurfi_add_instance(const resurf_scene *scene, const resurfi_lod_levels_view *v,
                         const resurfi_scene_instance *item, size_t k, resurfi_world_errors *e)
{
    double s;
    if (!is_similarity(item->world, &s))
        return 0;
    for (size_t p = scene->mesh_first[item->mesh]; p < scene->mesh_first[item->mesh + 1]; ++p) {
        if (!scene->prims[p].mesh)
            continue;
        size_t shown = v->chains[p] ? (k < v->kept[p] ? k : v->kept[p]) : 0;
        double full_area = s * s * v->areas[p * (v->count + 1)];
        double level_area = s * s * v->areas[p * (v->count + 1) + shown];
        e->from_area += full_area;
        e->to_area += level_area;
        if (shown == 0)
            continue;
        const resurf_simplify_report *r = &v->reports[p * v->count + shown - 1];
        if (!(isfinite(r->result_to_input_max) && isfinite(r->input_to_result_max) &&
              isfinite(r->result_to_input_mean) && isfinite(r->input_to_result_mean)))
            return 0;
        e->to_full = fmax(e->to_full, s * r->result_to_input_max);
        e->from_full = fmax(e->from_full, s * r->input_to_result_max);
        e->to_sum += s * r->result_to_input_mean * level_area;
        e->from_sum += s * r->input_to_result_mean * full_area;
    }
    return 1;
}

/* The margin of the part of the other surface that an instance is measured to, over the instance's own bound: its
 * points lie about that far from their own primitives' other surface, so usually the nearest triangles lie within
 * it; when not, resurfi_side_max_nearby measures again (the figure is the same either way). On 2CylinderEngine at
 * 25% and 10% the errors phase took 0.84 G instructions at 0.5 (retries), 0.65 G at 1.0, 0.69 G at 1.25, which
 * leaves room for a sampled maximum above the bound without a retry. */
#define NEAR_MARGIN 1.25

int resurfi_larger_bound_first(const void *a, const void *b)
{
    const resurfi_bound_item *x = a, *y = b;
    if (x->bound != y->bound)
        return x->bound > y->bound ? -1 : 1;
    return x->instance < y->instance ? -1 : x->instance > y->instance;
}

/* One side's maximum over the whole scene: the points of each instance as level `shown` shows it (resurf_compare's
 * points at `density` samples per world area, and the vertices) measured to the whole other surface `to`, the
 * instances taken by their own bound, largest first, until the next bound is no more than the largest distance
 * found. Each instance left lies within its bound of its own primitives' other surface, so of the whole scene's:
 * none of them can raise the maximum. Usually one or two instances are measured, each against the part of `to`
 * near it (resurfi_side_max_nearby, with its own bound as the guess of the margin). */
resurf_status resurfi_side_over_scene(const resurf_scene *scene, const resurfi_scene_instances *list, size_t shown,
                                      const resurfi_scene_levels *levels, const resurfi_bound_item *order,
                                      double density, uint64_t seed, int facet_points, const resurf_mesh *to,
                                      unsigned threads, const resurf_allocator *alloc, double *out_max,
                                      resurf_error *error)
{
    double best = 0;
    for (size_t j = 0; j < list->count && order[j].bound > best; ++j) {
        resurfi_scene_instances single = {1, &list->items[order[j].instance]};
        resurf_mesh *m = NULL;
        resurf_status st = resurfi_scene_flatten(scene, &single, shown, levels, alloc, &m, error);
        double d = NAN;
        double samples = st == RESURF_OK ? ceil(density * resurfi_mesh_area(m)) : 0;
        samples = samples > 0 ? fmin(samples, 1e9) : 0;
        if (st == RESURF_OK &&
            resurfi_side_max_nearby(alloc, m, (size_t)samples, seed + order[j].instance, facet_points, to,
                                    NEAR_MARGIN * order[j].bound, threads, &d) != RESURF_OK)
            st = resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory measuring the levels");
        resurf_mesh_free(m);
        if (st != RESURF_OK)
            return st;
        best = d > best ? d : best;
    }
    *out_max = best;
    return RESURF_OK;
}

/* Two-sided distances between level `level` of the instances in list and `full` (level 0 of the same instances),
 * in world units. A level without triangles is not measurable: *out gets NaN. */
resurf_status resurfi_measure_level(const resurf_scene *scene, const resurfi_scene_instances *list,
                                    const resurf_mesh *full, size_t level, const resurfi_scene_levels *levels,
                                    const resurf_compare_options *co, resurf_compare_report *out, resurf_error *error)
{
    resurf_mesh *w = NULL;
    resurf_status st = resurfi_scene_flatten(scene, list, level, levels, co->allocator, &w, error);
    if (st != RESURF_OK)
        return st;
    if (w->triangle_count == 0 || full->triangle_count == 0) {
        out->hausdorff = out->mean = out->test_to_ref_max = out->ref_to_test_max = NAN;
        out->diagonal = resurf_mesh_bounds(full, NULL, NULL);
        resurf_mesh_free(w);
        return RESURF_OK;
    }
    st = resurf_compare(full, w, co, out, NULL, error);
    resurf_mesh_free(w);
    return st;
}

resurf_status resurfi_level_errors(const resurf_scene *scene, resurfi_lod_work *w,
                                   const resurf_simplify_report *reports, size_t count, size_t samples,
                                   int threads_option, bool per_mesh, resurf_scene_lod_report *report,
                                   resurf_error *error)
{
    const resurf_allocator *alloc = w->alloc;
    const size_t prim_count = scene->prim_count, mesh_count = scene->mesh_count, levels = report->levels;
    const unsigned threads = resurfi_thread_count(threads_option);
    resurf_status st = RESURF_OK;
    resurfi_scene_levels stand_in = {(resurf_mesh *const *const *)w->chains, w->kept};
    resurf_compare_options co = resurf_compare_options_default();
    co.samples = samples;
    co.threads = threads_option;
    co.allocator = alloc;
    /* Composed from the primitives' own two-sided reports when every instance is a similarity of its mesh (the
     * usual case): their points already cover the scene by area at the same budget, so measuring the world again
     * would only repeat them (on 2CylinderEngine that was 3 of the call's 4 CPU seconds). Else measured. */
    double *areas = st == RESURF_OK ? resurfi_calloc(alloc, prim_count * (count + 1) + 1, sizeof *areas) : NULL;
    resurfi_lod_levels_view view = {(resurf_mesh *const *const *)w->chains, w->kept, reports, areas, count};
    int composed = areas && reports && samples > 0;
    for (size_t p = 0; composed && p < prim_count; ++p) {
        if (!scene->prims[p].mesh)
            continue;
        areas[p * (count + 1)] = resurfi_mesh_area(scene->prims[p].mesh);
        for (size_t j = 0; w->chains[p] && j < w->kept[p]; ++j)
            areas[p * (count + 1) + j + 1] = resurfi_mesh_area(w->chains[p][j]);
    }
    resurfi_bound_item *to_order = composed ? resurfi_alloc(alloc, w->list.count + 1, 2 * sizeof *to_order) : NULL;
    resurfi_bound_item *from_order = to_order ? to_order + w->list.count + 1 : NULL;
    composed = to_order && w->full->triangle_count > 0;
    for (size_t k = 1; k < levels && composed && st == RESURF_OK; ++k) {
        resurfi_world_errors e = {0, 0, 0, 0, 0, 0};
        for (size_t i = 0; i < w->list.count && composed; ++i) {
            resurfi_world_errors one = {0, 0, 0, 0, 0, 0};
            composed = resurfi_add_instance(scene, &view, &w->list.items[i], k, &one);
            to_order[i] = (resurfi_bound_item){one.to_full, i};
            from_order[i] = (resurfi_bound_item){one.from_full, i};
            e.to_sum += one.to_sum, e.to_area += one.to_area, e.from_sum += one.from_sum, e.from_area += one.from_area;
        }
        if (w->twin_levels[k])
            continue; /* the default's figures, copied (whether the levels compose is asked all the same) */
        resurf_mesh *level = NULL;
        if (composed)
            st = resurfi_scene_flatten(scene, &w->list, k, &stand_in, alloc, &level, error);
        if (composed && st == RESURF_OK && level->triangle_count > 0) {
            qsort(to_order, w->list.count, sizeof *to_order, resurfi_larger_bound_first);
            qsort(from_order, w->list.count, sizeof *from_order, resurfi_larger_bound_first);
            double level_area = resurfi_mesh_area(level), full_area = resurfi_mesh_area(w->full);
            double to_density = level_area > 0 ? (double)samples / level_area : 0;
            double from_density = full_area > 0 ? (double)samples / full_area : 0;
            /* Both sides with their facet points, as resurf_compare: the full detail's too, once per level (on the
             * 871k-triangle dragon scan its 25% level's error rose from 2.15e-4 to the 2.56e-4 that compare finds;
             * lod's time 11.4 -> 14.2 s for two levels), where the primitives' own reports, run again and again by
             * the budget, measure M's vertices and samples only. */
            st = resurfi_side_over_scene(scene, &w->list, k, &stand_in, to_order, to_density, 1, 1, w->full, threads,
                                         alloc, &e.to_full, error);
            if (st == RESURF_OK)
                st = resurfi_side_over_scene(scene, &w->list, 0, NULL, from_order, from_density, 0x9e3779b9u, 1, level,
                                             threads, alloc, &e.from_full, error);
        } else if (composed && st == RESURF_OK) { /* a level without triangles: not measurable */
            e.to_full = e.from_full = e.to_sum = NAN;
        }
        resurf_mesh_free(level);
        double d = report->diagonal > 0 ? report->diagonal : NAN;
        report->level_to_full_rel[k] = e.to_full / d;
        report->level_from_full_rel[k] = e.from_full / d;
        report->level_error[k] = fmax(e.to_full, e.from_full);
        report->level_error_rel[k] = report->level_error[k] / d;
        report->level_mean_rel[k] = 0.5 * (e.to_area > 0 ? e.to_sum / e.to_area : NAN) / d +
                                   0.5 * (e.from_area > 0 ? e.from_sum / e.from_area : NAN) / d;
    }
    resurfi_free(alloc, to_order);
    for (size_t k = 1; k < levels && st == RESURF_OK && samples > 0 && !composed; ++k) {
        if (w->twin_levels[k])
            continue;
        resurf_compare_report m;
        st = resurfi_measure_level(scene, &w->list, w->full, k, &stand_in, &co, &m, error);
        if (st != RESURF_OK)
            break;
        double d = m.diagonal > 0 ? m.diagonal : NAN;
        report->level_error[k] = m.hausdorff;
        report->level_error_rel[k] = m.hausdorff / d;
        report->level_mean_rel[k] = m.mean / d;
        report->level_to_full_rel[k] = m.test_to_ref_max / d;
        report->level_from_full_rel[k] = m.ref_to_test_max / d;
    }
    size_t scene_triangles = w->full ? w->full->triangle_count : 0;
    for (size_t m = 0; m < mesh_count && st == RESURF_OK && samples > 0 && per_mesh; ++m) {
        if (w->mesh_levels[m] < 2)
            continue;
        double *err = w->errors + m * (count + 1);
        if (w->list.count == 1) { /* the scene is this one instance: its errors are the mesh's */
            for (size_t k = 1; k < w->mesh_levels[m]; ++k)
                err[k] = report->level_error_rel[k]; /* a twin level's is copied with the scene's */
            continue;
        }
        resurfi_scene_instance one = {.mesh = m};
        for (size_t i = 0; i < w->list.count; ++i)
            if (w->list.items[i].mesh == m) {
                one = w->list.items[i];
                break;
            }
        resurfi_scene_instances single = {1, &one};
        resurf_mesh *full = NULL;
        st = resurfi_scene_flatten(scene, &single, 0, NULL, alloc, &full, error);
        int mesh_composed = composed && st == RESURF_OK;
        for (size_t k = 1; k < w->mesh_levels[m] && mesh_composed; ++k) {
            resurfi_world_errors e = {0, 0, 0, 0, 0, 0};
            double d = resurf_mesh_bounds(full, NULL, NULL);
            mesh_composed = resurfi_add_instance(scene, &view, &one, k, &e);
            err[k] = d > 0 ? fmax(e.to_full, e.from_full) / d : NAN;
        }
        if (mesh_composed) {
            resurf_mesh_free(full);
            continue;
        }
        /* The scene's sample budget, spread by triangles (at least 1,000 samples a mesh). */
        resurf_compare_options mco = co;
        double share = st == RESURF_OK && scene_triangles ? (double)full->triangle_count / (double)scene_triangles
                                                           : 1;
        if (st == RESURF_OK)
            mco.samples = (size_t)fmin((double)co.samples, fmax(1000.0, share * (double)co.samples));
        for (size_t k = 1; k < w->mesh_levels[m] && st == RESURF_OK; ++k) {
            if (w->twin_levels[k])
                continue;
            resurf_compare_report r;
            st = resurfi_measure_level(scene, &single, full, k, &stand_in, &mco, &r, error);
            if (st == RESURF_OK)
                err[k] = r.diagonal > 0 ? r.hausdorff / r.diagonal : NAN;
        }
        resurf_mesh_free(full);
    }    resurfi_free(alloc, areas);
    return st;
}
