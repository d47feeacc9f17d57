/* The services over the original M that a simplification only reads once it has started: the restorer (M's
 * normals, curvature and walks, restore_setup.c) and the tree over the input's triangles (bvh.c). A call builds
 * its own in simplify_start; resurfi_simplify_services_build makes them once for several calls on one input (the
 * scene budget's runs of a primitive, a chain made level by level), which then borrow them. They are the same
 * either way: the restorer welds the input's positions exactly as the simplifier does, and neither depends on the
 * thread count. */
#include "simplify_internal.h"

/* AUTO is Max's normals here, not the jet fit: a LOD's distance to S is set by the chord sag, not by the
 * restorer's last digits (the analytic benchmark's figures agree to 2%), and the fit costs about a second per
 * million triangles. */
resurf_restore_options services_restore_options(const resurf_simplify_options *o, const resurf_allocator *alloc)
{
    resurf_restore_options ro = o->restore_options ? *o->restore_options : resurf_restore_options_default();
    if (ro.normals == RESURF_NORMALS_AUTO)
        ro.normals = RESURF_NORMALS_MAX;
    ro.threads = 1;
    ro.progress = (resurf_progress){NULL, NULL};
    ro.allocator = alloc;
    return ro;
}

resurf_status services_build_restorer(const resurf_mesh *in, const resurf_simplify_options *o,
                                      const resurf_allocator *alloc, const uint32_t *remap, size_t positions,
                                      resurfi_restorer **out, resurf_error *error)
{
    resurf_restore_options ro = services_restore_options(o, alloc);
    /* Without its tree: every restored point has a triangle of M nearby to walk from (home). */
    return resurfi_restorer_create_ex(in, &ro, 0, remap, positions, out, error);
}

int services_need_bvh(const resurf_mesh *in, const resurf_simplify_options *o)
{
    return has_attributes(in) || o->measure_samples;
}

resurf_status services_build_bvh(const resurf_mesh *in, const resurf_simplify_options *o,
                                 const resurf_allocator *alloc, resurfi_bvh **out)
{
    /* With a host pool, no thread of ours: one. */
    return resurfi_bvh_build_threads(alloc, in->positions, in->vertex_count, in->indices, in->triangle_count,
                                     o->thread_pool ? 1 : o->threads, out);
}

resurf_status resurfi_simplify_services_build(const resurf_mesh *in, const resurf_simplify_options *options,
                                              resurfi_simplify_services **out, resurf_error *error)
{
    resurfi_clear_error(error);
    *out = NULL;
    resurf_simplify_options o = options ? *options : resurf_simplify_options_default();
    resurf_status st = simplify_check_input(in, error);
    if (st != RESURF_OK)
        return st;
    const resurf_allocator *alloc = resurfi_allocator_of(o.allocator, in);
    resurfi_simplify_services *sv = resurfi_calloc(alloc, 1, sizeof *sv);
    uint32_t *remap = resurfi_alloc(alloc, in->vertex_count + 1, sizeof *remap);
    if (!sv || !remap) {
        resurfi_free(alloc, sv);
        resurfi_free(alloc, remap);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    }
    sv->in = in;
    sv->alloc = *alloc;
    size_t positions = 0;
    if (o.restore != RESURF_RESTORE_NONE && in->triangle_count) {
        if ((st = resurfi_weld_exact(alloc, in->positions, in->vertex_count, remap, &positions)) != RESURF_OK)
            st = resurfi_error(error, st, "out of memory welding the input's positions");
        else
            st = services_build_restorer(in, &o, alloc, remap, positions, &sv->restorer, error);
    }
    resurfi_free(alloc, remap);
    if (st == RESURF_OK && in->triangle_count && services_need_bvh(in, &o) &&
        (st = services_build_bvh(in, &o, alloc, &sv->bvh)) != RESURF_OK)
        st = resurfi_error(error, st, "cannot build the input's BVH");
    if (st != RESURF_OK) {
        resurfi_simplify_services_free(sv);
        return st;
    }
    *out = sv;
    return RESURF_OK;
}

void resurfi_simplify_services_free(resurfi_simplify_services *sv)
{
    if (!sv)
        return;
    const resurf_allocator alloc = sv->alloc; /* the struct holding it goes last */
    resurfi_restorer_free(sv->restorer);
    resurfi_bvh_free(sv->bvh);
    resurfi_free(&alloc, sv);
}
