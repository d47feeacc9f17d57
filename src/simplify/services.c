/* The services over the original M that a simplification only reads once it has started: the restorer (M's
 * normals, curvature and walks, restore_setup.c) and the tree over the input's triangles (bvh.c). A call builds
 * its own in simplify_start; resurfi_simplify_services_build makes them once for several calls on one input (the
 * scene budget's runs of a primitive, a chain made level by level), which then borrow them. They are the same
 * either way: the restorer welds the input's positions exactly as the simplifier does, and neither depends on the
 * thread count. The first borrowing call also leaves its per-position analysis (flags, quadrics) with them, which a
 * later call with the same options copies rather than redoes (docs/performance.md). */
#include <pthread.h>

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

/* ---- the per-position analysis, kept by the first call and copied into the later ones ------------------------ */

/* What analyse_position reads of the options (besides the input): a later call with other values analyses anew. */
typedef struct analysis_key {
    double feature_angle_deg, corner_angle_deg, border_weight;
    int lock_border, drop_fins, keep_attached_sheets;
    uint32_t unsampled_texcoords; /* the wedges, hence the seams */
} analysis_key;

typedef struct analysis_entry {
    resurfi_quadric q;
    uint32_t up;
    pos_flags flags;
} analysis_entry;

struct services_analysis {
    pthread_mutex_t lock; /* over kept: calls borrowing the services may run side by side */
    int kept;
    analysis_key key;
    size_t pos_count;
    analysis_entry *entries; /* per working position; a dead one's flags are prepare_mesh's and stay the call's */
};

static analysis_key key_of(const resurf_simplify_options *o)
{
    analysis_key k;
    memset(&k, 0, sizeof k); /* compared with memcmp: no padding of stale bytes */
    k.feature_angle_deg = o->feature_angle_deg;
    k.corner_angle_deg = o->corner_angle_deg;
    k.border_weight = o->border_weight;
    k.lock_border = o->lock_border != 0;
    k.drop_fins = o->drop_fins != 0;
    k.keep_attached_sheets = o->attached_sheets == RESURF_SHEETS_KEEP;
    k.unsampled_texcoords = o->unsampled_texcoords;
    return k;
}

static struct services_analysis *analysis_of(const simplifier *s)
{
    return s->lent ? s->lent->analysis : NULL;
}

int services_take_analysis(simplifier *s)
{
    struct services_analysis *a = analysis_of(s);
    if (!a)
        return 0;
    analysis_key key = key_of(&s->opt);
    pthread_mutex_lock(&a->lock);
    int same = a->kept && a->pos_count == s->pos_count && !memcmp(&a->key, &key, sizeof key);
    pthread_mutex_unlock(&a->lock); /* once kept, never written again */
    if (!same)
        return 0;
    for (size_t p = 0; p < s->pos_count; ++p) {
        if (s->P[p].flags & POS_DEAD)
            continue;
        s->P[p].q = a->entries[p].q;
        s->P[p].up = a->entries[p].up;
        s->P[p].flags = a->entries[p].flags;
    }
    return 1;
}

void services_keep_analysis(const simplifier *s)
{
    struct services_analysis *a = analysis_of(s);
    if (!a)
        return;
    pthread_mutex_lock(&a->lock);
    if (!a->kept) {
        analysis_entry *e = resurfi_alloc(&s->lent->alloc, s->pos_count + 1, sizeof *e);
        if (e) { /* out of memory: the later calls analyse for themselves */
            for (size_t p = 0; p < s->pos_count; ++p)
                e[p] = (analysis_entry){s->P[p].q, s->P[p].up, s->P[p].flags};
            a->entries = e;
            a->pos_count = s->pos_count;
            a->key = key_of(&s->opt);
            a->kept = 1;
        }
    }
    pthread_mutex_unlock(&a->lock);
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
    if (facets_derive(in, alloc, &sv->derived) != RESURF_OK) {
        resurfi_free(alloc, sv);
        resurfi_free(alloc, remap);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    }
    if (sv->derived)
        in = sv->derived; /* the services are over the copy the calls simplify */
    if (!(sv->analysis = resurfi_calloc(alloc, 1, sizeof *sv->analysis))) {
        resurfi_free(alloc, sv);
        resurfi_free(alloc, remap);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    }
    pthread_mutex_init(&sv->analysis->lock, NULL);
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
    resurf_mesh_free(sv->derived);
    if (sv->analysis) {
        pthread_mutex_destroy(&sv->analysis->lock);
        resurfi_free(&alloc, sv->analysis->entries);
        resurfi_free(&alloc, sv->analysis);
    }
    resurfi_free(&alloc, sv);
}
