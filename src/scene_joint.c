/* The chains of a mesh whose primitives are simplified together (resurf_scene_build_lods): the primitives joined
 * as groups of one mesh, one chain, each level split back. Kept apart from the per-primitive chains of scene_lods.c
 * because it is its own idea (which meshes qualify, the joined input the scene budget reuses, the fallback to
 * locked borders). */
#include <string.h>

#include "scene_lods_internal.h"

/* May mesh m's primitives be simplified as one surface, each primitive a group whose border is a crease
 * (src/mesh_parts.c)? When it has two or more, all of them triangles of one attribute layout; they are when, also,
 * shared positions link them all (resurfi_scene_shared_positions): primitives that share nothing cannot crack, and
 * each keeps its own ratio (joined, the cost moves triangles between them: an assimp export of two separate parts lost
 * 4x in Hausdorff at 25%). Measured by
 * tools/bench-borders on the dragon-48k cut into 4 parts, against locking the shared positions at the same triangle
 * count: 1.00x Hausdorff and 0.90x mean at 10%, 0.21x and 0.24x at 2% (the locked parts also stopped at twice
 * their target). Other meshes lock the positions their primitives share (resurfi_scene_shared_positions). */
bool resurfi_scene_simplified_together(const resurf_scene *scene, size_t m)
{
    size_t first = scene->mesh_first[m], last = scene->mesh_first[m + 1];
    if (last - first < 2)
        return false;
    for (size_t p = first; p < last; ++p) {
        const resurfi_scene_prim *prim = &scene->prims[p];
        if (prim->info.kind != RESURF_PRIMITIVE_TRIANGLES || !prim->mesh ||
            !resurfi_mesh_same_attributes(scene->prims[first].mesh, prim->mesh))
            return false;
    }
    return true;
}

/* Mesh m's primitives joined as groups of one mesh (*joined), the options of its runs (*lock: the positions its
 * primitives share with other meshes, over the joined vertices, or NULL; its share of the samples) and its levels'
 * bounds in its units; returns its scale. For its chain and the scene budget's runs of it. */
double resurfi_joint_input(const resurfi_chain_job *job, size_t m, const resurf_simplify_options *base,
                           resurf_mesh **joined, uint8_t **lock, resurf_simplify_options *sim, double *bounds,
                           resurf_status *st, resurf_error *e)
{
    const resurf_scene *scene = job->scene;
    const resurfi_lod_work *w = job->w;
    size_t first = scene->mesh_first[m], n = scene->mesh_first[m + 1] - first;
    const resurf_mesh *parts[64];
    const resurf_mesh **in = n <= 64 ? parts : resurfi_alloc(w->alloc, n, sizeof *in);
    double area = 0, scale = w->mesh_scale[m] > 0 ? w->mesh_scale[m] : 1;
    int any = 0;
    *joined = NULL, *lock = NULL;
    *st = in ? RESURF_OK : resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    for (size_t q = 0; *st == RESURF_OK && q < n; ++q)
        area += resurfi_mesh_area(in[q] = scene->prims[first + q].mesh), any |= w->locks[first + q] != NULL;
    if (*st == RESURF_OK)
        *st = resurfi_mesh_join_parts(in, n, &in[0]->allocator, joined, e);
    if (*st == RESURF_OK && any && !(*lock = resurfi_calloc(w->alloc, (*joined)->vertex_count + 1, 1)))
        *st = resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    for (size_t q = 0, v0 = 0; *st == RESURF_OK && any && q < n; v0 += in[q++]->vertex_count)
        if (w->locks[first + q]) /* in the order resurfi_mesh_join_parts puts the vertices */
            memcpy(*lock + v0, w->locks[first + q], in[q]->vertex_count);
    resurfi_run_options(job, base, m, scale, area, *lock, sim, bounds);
    if (in != parts)
        resurfi_free(w->alloc, in);
    return scale;
}

/* The chains of mesh m's primitives, simplified together: the primitives joined as groups of one mesh, its chain,
 * and each level split back into the primitives. Every primitive of m gets the mesh's reports, and one count of
 * levels that help, so that no level mixes one primitive's borders with another's. A level that would leave a
 * primitive without triangles makes the mesh lock its shared borders instead (which cannot). */
resurf_status resurfi_make_joint_chain(resurfi_chain_job *job, size_t m, const resurf_simplify_options *base)
{
    const resurf_scene *scene = job->scene;
    resurfi_lod_work *w = job->w;
    size_t first = scene->mesh_first[m], n = scene->mesh_first[m + 1] - first, count = job->count;
    resurf_error *e = &job->errors[first];
    resurf_mesh *joined = NULL, **chain = resurfi_calloc(w->alloc, count, sizeof *chain);
    resurf_simplify_report *reports = resurfi_calloc(w->alloc, count, sizeof *reports);
    resurf_status st = chain && reports ? RESURF_OK : resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    size_t kept = 0;
    int why = 0;
    uint8_t *joint_lock = NULL;
    resurf_simplify_options sim;
    double bounds[RESURF_SCENE_MAX_LEVELS - 1];
    if (st == RESURF_OK)
        resurfi_joint_input(job, m, base, &joined, &joint_lock, &sim, bounds, &st, e);
    resurfi_plain_half *keep = st == RESURF_OK ? resurfi_half_to_keep(job, first, true, &st, e) : NULL;
    if (st == RESURF_OK)
        st = resurfi_make_chain(joined, job->ratios, count, bounds, &sim, chain, reports, keep,
                                resurfi_half_to_use(job, first, true), e);
    if (st == RESURF_OK)
        kept = resurfi_levels_that_help(joined, reports, job->ratios, count, &why);
    /* Split every level into the primitives: w->chains[first + q][k]. */
    for (size_t q = 0; st == RESURF_OK && q < n; ++q)
        if (!(w->chains[first + q] = resurfi_calloc(w->alloc, count, sizeof **w->chains)))
            st = resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    resurf_mesh *split[64];
    resurf_mesh **level = n <= 64 ? split : resurfi_alloc(w->alloc, n, sizeof *level);
    int emptied = 0;
    for (size_t k = 0; st == RESURF_OK && k < count && chain[k]; ++k) { /* levels after the chain's end are unmade */
        if (!level) {
            st = resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
            break;
        }
        st = resurfi_mesh_split_parts(chain[k], n, &chain[k]->allocator, level, e);
        for (size_t q = 0; st == RESURF_OK && q < n; ++q) {
            w->chains[first + q][k] = level[q];
            emptied |= k < kept && level[q]->triangle_count == 0 && scene->prims[first + q].mesh->triangle_count > 0;
        }
    }
    for (size_t k = 0; k < count && chain; ++k)
        resurf_mesh_free(chain[k]);
    resurfi_free(w->alloc, chain);
    resurfi_free(w->alloc, joint_lock);
    resurf_mesh_free(joined);
    if (level != split)
        resurfi_free(w->alloc, level);
    for (size_t q = 0; q < n; ++q) {
        if (st == RESURF_OK && !emptied) {
            /* The mesh's report, with the primitive's own counts (the distances are the mesh's). */
            resurf_simplify_report *own = job->reports + (first + q) * count;
            memcpy(own, reports, count * sizeof *reports);
            for (size_t k = 0; k < count && w->chains[first + q][k]; ++k) {
                own[k].input_triangles = scene->prims[first + q].mesh->triangle_count;
                own[k].triangles = w->chains[first + q][k]->triangle_count;
                own[k].vertices = w->chains[first + q][k]->vertex_count;
            }
            w->joint_kept[first + q] = kept + 1;
            w->joint_why[first + q] = why;
        } else if (w->chains[first + q]) {
            for (size_t k = 0; k < count; ++k)
                resurf_mesh_free(w->chains[first + q][k]);
            resurfi_free(w->alloc, w->chains[first + q]);
            w->chains[first + q] = NULL;
        }
        job->status[first + q] = st;
    }
    resurfi_free(w->alloc, reports);
    if (st == RESURF_OK && emptied) {
        /* Lock the shared borders instead, primitive by primitive. */
        w->together[m] = false;
        if (resurfi_scene_shared_positions(scene, m, w->alloc, w->locks, NULL) != RESURF_OK)
            return job->status[first] = resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
        for (size_t q = 0; q < n && st == RESURF_OK; ++q)
            st = resurfi_make_primitive_chain(job, first + q, base);
    }
    return st;
}
