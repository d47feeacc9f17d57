/* The chains of primitives of a mesh simplified together (resurf_scene_build_lods): the units (primitives that
 * shared positions link), each joined as groups of one mesh, one chain, each level split back. Kept apart from the
 * per-primitive chains of scene_lods.c because it is its own idea (which primitives qualify, the joined input the
 * scene budget reuses, the fallback to locked borders). */
#include <string.h>

#include "scene_lods_internal.h"

/* May these primitives, which shared positions link, be simplified as one surface, each primitive a
 * group whose border is a crease (src/mesh_parts.c)? When there are two or more, all triangles of one attribute
 * layout. Only linked primitives go together: primitives that share nothing cannot crack, and each keeps its own
 * ratio (joined, the cost moves triangles between them: an assimp export of two separate parts lost 4x in
 * Hausdorff at 25%). Measured by tools/bench-borders on the dragon-48k cut into 4 parts, against locking the shared
 * positions at the same triangle count: 1.00x Hausdorff and 0.90x mean at 10%, 0.21x and 0.24x at 2% (the locked
 * parts also stopped at twice their target). */
bool resurfi_scene_simplified_together(const resurf_scene *scene, const size_t *members, size_t n)
{
    if (n < 2)
        return false;
    for (size_t q = 0; q < n; ++q) {
        const resurfi_scene_prim *prim = &scene->prims[members[q]];
        if (prim->info.kind != RESURF_PRIMITIVE_TRIANGLES || !prim->mesh ||
            !resurfi_mesh_same_attributes(scene->prims[members[0]].mesh, prim->mesh))
            return false;
    }
    return true;
}

/* The units (w->unit, unit_members, unit_at, unit_size; allocated by the caller): each set of triangle primitives
 * of one attribute layout that shared positions link within a group of meshes (resurfi_scene_mesh_groups: a mesh
 * alone). The positions that primitives of different units share (a morphed primitive's, another layout's, a
 * primitive alone's) are locked (w->locks). Before units, a mesh went together only when shared positions linked
 * all of its primitives, else all of them were locked: Sweet Home 3D's smart car, whose body is eight linked
 * primitives and two apart, kept 2,548 of 3,730 triangles at 25%, its body blocked by the locks. */
resurf_status resurfi_scene_find_units(const resurf_scene *scene, resurfi_lod_work *w)
{
    size_t pc = scene->prim_count;
    size_t *group = resurfi_alloc(w->alloc, scene->mesh_count + 1, sizeof *group);
    size_t *linked = resurfi_alloc(w->alloc, pc + 1, sizeof *linked);
    size_t *size = resurfi_calloc(w->alloc, pc + 1, sizeof *size);  /* per set's first primitive: its primitives */
    size_t *at = resurfi_alloc(w->alloc, pc + 1, sizeof *at);       /* and where they start in `sets` */
    size_t *sets = resurfi_alloc(w->alloc, pc + 1, sizeof *sets);   /* the primitives, set by set, in order */
    resurf_status st = group && linked && size && at && sets ? RESURF_OK : RESURF_ERR_OUT_OF_MEMORY;
    for (size_t p = 0; p < pc; ++p)
        w->unit[p] = SIZE_MAX;
    if (st == RESURF_OK)
        st = resurfi_scene_mesh_groups(scene, &w->list, w->alloc, group);
    if (st == RESURF_OK)
        st = resurfi_scene_linked(scene, group, w->alloc, linked);
    for (size_t p = 0; st == RESURF_OK && p < pc; ++p)
        size[linked[p]]++;
    for (size_t p = 0, n = 0; st == RESURF_OK && p < pc; n += size[p++])
        at[p] = n;
    for (size_t p = 0, *fill = at; st == RESURF_OK && p < pc; ++p)
        sets[fill[linked[p]]++] = p; /* at[] now holds each set's end */
    for (size_t leader = 0, listed = 0; st == RESURF_OK && leader < pc; ++leader) {
        size_t n = size[leader];
        const size_t *members = sets + at[leader] - n;
        if (linked[leader] != leader || n < 2)
            continue; /* inside a set, or shares nothing */
        if (resurfi_scene_simplified_together(scene, members, n)) {
            memcpy(w->unit_members + listed, members, n * sizeof *members);
            w->unit_at[leader] = listed, w->unit_size[leader] = n;
            for (size_t q = 0; q < n; ++q)
                w->unit[members[q]] = leader;
            listed += n;
        }
    }
    if (st == RESURF_OK) /* what primitives of different units share (a morphed one's, another layout's) */
        st = resurfi_scene_lock_between_units(scene, group, w->unit, w->alloc, w->locks);
    resurfi_free(w->alloc, group);
    resurfi_free(w->alloc, linked);
    resurfi_free(w->alloc, size);
    resurfi_free(w->alloc, at);
    resurfi_free(w->alloc, sets);
    return st;
}

/* The unit's primitives joined as groups of one mesh (*joined), the options of its runs (*lock: the positions its
 * primitives share with other meshes, over the joined vertices, or NULL; its share of the samples) and its levels'
 * bounds in its units; returns its scale. For its chain and the scene budget's runs of it. */
double resurfi_joint_input(const resurfi_chain_job *job, size_t leader, const resurf_simplify_options *base,
                           resurf_mesh **joined, uint8_t **lock, resurf_simplify_options *sim, double *bounds,
                           resurf_status *st, resurf_error *e)
{
    const resurf_scene *scene = job->scene;
    const resurfi_lod_work *w = job->w;
    size_t m = scene->prims[leader].info.mesh, n;
    const size_t *members = resurfi_unit_members(w, leader, &n);
    const resurf_mesh *parts[64];
    const resurf_mesh **in = n <= 64 ? parts : resurfi_alloc(w->alloc, n, sizeof *in);
    double area = 0, scale = w->mesh_scale[m] > 0 ? w->mesh_scale[m] : 1;
    int any = 0;
    *joined = NULL, *lock = NULL;
    *st = in ? RESURF_OK : resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    for (size_t q = 0; *st == RESURF_OK && q < n; ++q)
        area += resurfi_mesh_area(in[q] = scene->prims[members[q]].mesh),
            any |= w->locks[members[q]] != NULL || w->held[members[q]];
    if (*st == RESURF_OK)
        *st = resurfi_mesh_join_parts(in, n, &in[0]->allocator, joined, e);
    if (*st == RESURF_OK && any && !(*lock = resurfi_calloc(w->alloc, (*joined)->vertex_count + 1, 1)))
        *st = resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    for (size_t q = 0, v0 = 0; *st == RESURF_OK && any && q < n; v0 += in[q++]->vertex_count)
        if (w->held[members[q]])
            memset(*lock + v0, 1, in[q]->vertex_count);
        else if (w->locks[members[q]]) /* in the order resurfi_mesh_join_parts puts the vertices */
            memcpy(*lock + v0, w->locks[members[q]], in[q]->vertex_count);
    resurfi_run_options(job, base, m, scale, area, *lock, sim, bounds);
    if (in != parts)
        resurfi_free(w->alloc, in);
    return scale;
}

/* Tries at holding the primitives a unit's level left without triangles (HOLD_TRIES runs of its chain at most). */
#define HOLD_TRIES 3

/* Frees the unit's chain, its split levels and its joined input: the state before a run of it. */
static void joint_free(resurfi_lod_work *w, const size_t *members, size_t n, size_t count, resurf_mesh **chain,
                       resurf_mesh **joined, uint8_t **joint_lock)
{
    for (size_t k = 0; k < count; ++k) {
        resurf_mesh_free(chain[k]);
        chain[k] = NULL;
    }
    for (size_t q = 0; q < n; ++q) {
        for (size_t k = 0; w->chains[members[q]] && k < count; ++k)
            resurf_mesh_free(w->chains[members[q]][k]);
        resurfi_free(w->alloc, w->chains[members[q]]);
        w->chains[members[q]] = NULL;
    }
    resurf_mesh_free(*joined);
    resurfi_free(w->alloc, *joint_lock);
    *joined = NULL, *joint_lock = NULL;
}

/* The chains of a unit's primitives, simplified together: the primitives joined as groups of one mesh, its chain,
 * and each level split back into the primitives. Every primitive of the unit gets the unit's reports, and one count
 * of levels that help, so that no level mixes one primitive's borders with another's. A level may not leave a
 * primitive without triangles: the chain is made again with the vertices of each primitive it emptied held still
 * (w->held, which the scene budget's runs of the unit hold too; Q3D_E-AT-AT's body of 10,526 triangles carries a
 * primitive of 2, which its 10% level took: the chain ended at 25%, 0.26 of the triangles at 10%). Should one
 * still empty one, the chain ends before that level; when that is the first level, the primitives lock their
 * shared borders instead (which cannot empty one) and are simplified apart. */
resurf_status resurfi_make_joint_chain(resurfi_chain_job *job, size_t leader, const resurf_simplify_options *base)
{
    const resurf_scene *scene = job->scene;
    resurfi_lod_work *w = job->w;
    size_t n, count = job->count;
    const size_t *members = resurfi_unit_members(w, leader, &n);
    resurf_error *e = &job->errors[leader];
    resurf_mesh *joined = NULL, **chain = resurfi_calloc(w->alloc, count, sizeof *chain);
    resurf_simplify_report *reports = resurfi_calloc(w->alloc, count, sizeof *reports);
    resurf_mesh *split[64];
    resurf_mesh **level = n <= 64 ? split : resurfi_alloc(w->alloc, n, sizeof *level);
    resurf_status st =
        chain && reports && level ? RESURF_OK : resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    size_t kept = 0, emptied = count; /* emptied: the first level that leaves a primitive without triangles */
    int why = 0;
    uint8_t *joint_lock = NULL;
    for (int tries = 0; st == RESURF_OK; ++tries) {
        resurf_simplify_options sim;
        double bounds[RESURF_SCENE_MAX_LEVELS - 1];
        resurfi_joint_input(job, leader, base, &joined, &joint_lock, &sim, bounds, &st, e);
        resurfi_plain_half *keep = st == RESURF_OK ? resurfi_half_to_keep(job, leader, true, &st, e) : NULL;
        if (st == RESURF_OK)
            st = resurfi_make_chain(joined, job->ratios, count, bounds, &sim, chain, reports, keep,
                                    resurfi_half_to_use(job, leader, true), e);
        if (st == RESURF_OK)
            kept = resurfi_levels_that_help(joined, reports, job->ratios, count, &why);
        /* Split every level into the primitives: w->chains[members[q]][k]. */
        for (size_t q = 0; st == RESURF_OK && q < n; ++q)
            if (!(w->chains[members[q]] = resurfi_calloc(w->alloc, count, sizeof **w->chains)))
                st = resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
        emptied = count;
        int hold = 0;
        for (size_t k = 0; st == RESURF_OK && k < count && chain[k]; ++k) { /* levels after its end are unmade */
            st = resurfi_mesh_split_parts(chain[k], n, &chain[k]->allocator, level, e);
            for (size_t q = 0; st == RESURF_OK && q < n; ++q) {
                size_t p = members[q];
                w->chains[p][k] = level[q];
                if (k < kept && level[q]->triangle_count == 0 && scene->prims[p].mesh->triangle_count > 0 &&
                    !w->held[p]) {
                    emptied = k < emptied ? k : emptied;
                    w->held[p] = 1, hold = 1;
                }
            }
        }
        if (st != RESURF_OK || !hold || tries + 1 == HOLD_TRIES)
            break;
        joint_free(w, members, n, count, chain, &joined, &joint_lock);
    }
    bool apart = emptied == 0 && kept > 0;
    if (emptied < kept)
        kept = emptied, why = 3;
    for (size_t k = 0; k < count && chain; ++k)
        resurf_mesh_free(chain[k]);
    resurfi_free(w->alloc, chain);
    resurfi_free(w->alloc, joint_lock);
    resurf_mesh_free(joined);
    if (level != split)
        resurfi_free(w->alloc, level);
    for (size_t q = 0; q < n; ++q) {
        size_t p = members[q];
        if (st == RESURF_OK && !apart) {
            /* The unit's report, with the primitive's own counts (the distances are the unit's). */
            resurf_simplify_report *own = job->reports + p * count;
            memcpy(own, reports, count * sizeof *reports);
            for (size_t k = 0; k < count && w->chains[p][k]; ++k) {
                own[k].input_triangles = scene->prims[p].mesh->triangle_count;
                own[k].triangles = w->chains[p][k]->triangle_count;
                own[k].vertices = w->chains[p][k]->vertex_count;
            }
            w->joint_kept[p] = kept + 1;
            w->joint_why[p] = why;
        } else if (w->chains[p]) {
            for (size_t k = 0; k < count; ++k)
                resurf_mesh_free(w->chains[p][k]);
            resurfi_free(w->alloc, w->chains[p]);
            w->chains[p] = NULL;
        }
        job->status[p] = st;
    }
    resurfi_free(w->alloc, reports);
    if (st == RESURF_OK && apart) {
        /* Lock the shared borders instead, primitive by primitive. */
        for (size_t q = 0; q < n; ++q)
            w->unit[members[q]] = SIZE_MAX, w->held[members[q]] = 0;
        if (resurfi_scene_lock_shared(scene, members, n, w->alloc, w->locks) != RESURF_OK)
            return job->status[leader] = resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
        for (size_t q = 0; q < n && st == RESURF_OK; ++q)
            st = resurfi_make_primitive_chain(job, members[q], base);
    }
    return st;
}
