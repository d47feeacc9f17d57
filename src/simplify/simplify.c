/* Edge-collapse simplification with the new vertices restored onto the smooth surface of the ORIGINAL mesh.
 *
 * Sources: Garland & Heckbert, "Surface Simplification Using Quadric Error Metrics" (SIGGRAPH 1997) for the costs
 * and the placement (quadric.c); Hoppe, "New quadric metric for simplifying meshes with appearance attributes"
 * (1999) for wedges (attribute vertices that share a position); Dey, Edelsbrunner, Guha & Nekhayev, "Topology
 * preserving edge contraction" (1999) for the link condition; Semenova, Savchenko & Hagiwara, "Reconstruction of
 * Shapes Based on Normals Analysis", §4.2, for restoring every new vertex onto S as an intermediate step
 * (docs/restoring.md §8–§9).
 *
 * A call runs three phases: the first once, the other two for each target (one, or one per level of a LOD chain):
 *   simplify_start    (setup.c) the working mesh: positions welded exactly, attribute vertices with equal
 *                     attributes merged into wedges, fins and triangles with a repeated position dropped, each
 *                     position's corners threaded into a list; per position (in parallel) border, seam and
 *                     non-manifold flags and the quadric (area-weighted triangle planes, plus planes through
 *                     border and seam edges perpendicular to their triangles), beside the restorer's set-up; the
 *                     attribute charts; every edge's candidate collapse and cost, sorted (collapse.c, queue.c);
 *   collapse_until    (collapse.c) passes over the sorted candidates, each taking independent ones in cost order,
 *                     in chunks (schedule.c): planned again, checked (guards.c: link condition, flips and folds,
 *                     minimum angle, tip and bridge), restored, applied; at each level's target,
 *   build_output      (output.c) the result: wedges become vertices, POST restoration, vertices straddle S by the
 *                     sag offset, attributes are interpolated from the input; then (measure.c) the two-sided
 *                     distance between the level and the input measured, and its UV error.
 *
 * The files of src/simplify/, one concern each:
 *   simplify.c           this file: the public functions, the options and their checks, a call's life;
 *   simplify_internal.h  the working mesh, the per-concern state the simplifier holds, the small inline helpers;
 *   setup.c              weld, wedges, fins, corner lists, per-position analysis, charts, the set-up's order;
 *   attributes.c         the attribute quadrics of the wedges: built, priced, merged;
 *   curves.c             M's crease and border curves, and a collapse's place on them (restored along the curve);
 *   collapse.c           placement, cost, the vertex-kind rule (a table), applying a collapse, trying a candidate,
 *                        the pass loop;
 *   guards.h, guards.c   the guards of one collapse, and the contract of what a collapse in a parallel chunk may
 *                        read and write (checked in debug builds);
 *   queue.h, queue.c     the candidate queue: sorts, the refresh between passes and its parallel merge;
 *   schedule.c           passes, chunks, windows, stars, claims, lanes, prefetch: the only file of the collapse
 *                        loop that knows about threads;
 *   output.c             numbering, post restoration, sag offset, attributes;
 *   measure.c            the report's two-sided distances and UV error;
 *   facets.c             flat shading: a flat-shaded part's normals dropped for the call, its levels shaded flat;
 *   services.c           the services over M (restorer, tree over the input): built by the start, or once
 *                        beforehand and lent to several calls on one input (resurfi_simplify_lent).
 *
 * Collapses work on welded positions. A triangle corner keeps its wedge (the id of an input attribute vertex); when
 * a position disappears, each corner takes the wedge of the surviving position on its side of any seam, which is
 * why a seam vertex may only collapse along its seam (the rule table is kHeld in collapse.c).
 * Nothing here depends on the thread count: parallel phases write per-element results only, and the collapses
 * applied in parallel are those of a chunk with disjoint stars (guards.h), whose results are merged in the chunk's
 * order. */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>

#include "simplify_internal.h"

static void scratch_free(scratch *s)
{
    resurfi_free(s->alloc, s->fan.data);
    resurfi_free(s->alloc, s->shaped);
    for (int i = 0; i < 2 * GATHER_GROUP; ++i)
        resurfi_free(s->alloc, s->group[i].data);
    resurfi_free(s->alloc, s->pairs);
    resurfi_free(s->alloc, s->uf);
}

resurf_simplify_options resurf_simplify_options_default(void)
{
    resurf_simplify_options o;
    memset(&o, 0, sizeof o);
    o.struct_size = sizeof o;
    o.placement = RESURF_PLACEMENT_QUADRIC;
    o.restore = RESURF_RESTORE_MEASURED;
    o.sag_offset = 1.0;
    o.max_normal_change_deg = 60;
    o.border_weight = 1;
    o.feature_angle_deg = 80;
    o.corner_angle_deg = 80;
    o.drop_fins = true;
    o.normal_weight = 0;
    o.texcoord_weight = 0.25;
    o.color_weight = 0.25;
    o.skin_weight = 1.4;
    o.morph_weight = 1;
    o.measure_samples = 20000;
    o.weld_tolerance_rel = 1e-8;
    return o;
}

static resurf_status check_options(const resurf_simplify_options *o, resurf_error *error)
{
    RESURFI_CHECK_OPTIONS_ALLOC(o, resurf_simplify_options, error);
    if (!o)
        return RESURF_OK;
    const char *bad = NULL;
    if (!(o->target_ratio >= 0 && o->target_ratio <= 1))
        bad = "target_ratio must be in [0, 1]";
    else if (!(o->max_error >= 0 && isfinite(o->max_error)))
        bad = "max_error must be finite and >= 0";
    else if (!(o->max_error_rel >= 0 && isfinite(o->max_error_rel)))
        bad = "max_error_rel must be finite and >= 0";
    else if ((unsigned)o->placement >= RESURF_PLACEMENT_COUNT)
        bad = "placement is not a resurf_placement";
    else if ((unsigned)o->restore >= RESURF_RESTORE_MODE_COUNT)
        bad = "restore is not a resurf_restore_mode";
    else if ((unsigned)o->attached_sheets >= RESURF_SHEETS_COUNT)
        bad = "attached_sheets is not a resurf_attached_sheets";
    else if (!(o->sag_offset >= 0 && o->sag_offset <= 4))
        bad = "sag_offset must be in [0, 4]";
    else if (!(o->min_angle_deg >= 0 && o->min_angle_deg < 60))
        bad = "min_angle_deg must be in [0, 60)";
    else if (!(o->max_normal_change_deg > 0 && o->max_normal_change_deg <= 180))
        bad = "max_normal_change_deg must be in (0, 180]";
    else if (!(o->feature_angle_deg > 0 && o->feature_angle_deg <= 180))
        bad = "feature_angle_deg must be in (0, 180]";
    else if (!(o->corner_angle_deg > 0 && o->corner_angle_deg <= 180))
        bad = "corner_angle_deg must be in (0, 180]";
    else if (!(o->border_weight >= 0 && isfinite(o->border_weight)))
        bad = "border_weight must be finite and >= 0";
    else if (!(o->normal_weight >= 0 && isfinite(o->normal_weight)) ||
             !(o->texcoord_weight >= 0 && isfinite(o->texcoord_weight)) ||
             !(o->color_weight >= 0 && isfinite(o->color_weight)) ||
             !(o->skin_weight >= 0 && isfinite(o->skin_weight)) ||
             !(o->morph_weight >= 0 && isfinite(o->morph_weight)))
        bad = "normal_weight, texcoord_weight, color_weight, skin_weight and morph_weight must be finite and >= 0";
    else if (!(o->weld_tolerance_rel >= 0 && o->weld_tolerance_rel <= 1e-3))
        bad = "weld_tolerance_rel must be in [0, 1e-3]";
    else if (o->restore_options && o->restore_options->struct_size != sizeof(resurf_restore_options))
        bad = "restore_options was not initialised by resurf_restore_options_default()";
    else if (o->thread_pool && !o->thread_pool->run)
        bad = "thread_pool has no run callback";
    if (bad)
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "resurf_simplify_options: %s", bad);
    return RESURF_OK;
}

static void simplifier_free(simplifier *s)
{
    resurfi_free(s->alloc, s->remap);
    resurfi_free(s->alloc, s->tri);
    resurfi_free(s->alloc, s->src);
    resurfi_free(s->alloc, s->mirror);
    resurfi_free(s->alloc, s->P_mem);
    resurfi_free(s->alloc, s->mark);
    resurfi_free(s->alloc, s->charts.of_input_tri);
    resurfi_free(s->alloc, s->charts.of_wedge);
    resurfi_free(s->alloc, s->charts.first);
    resurfi_free(s->alloc, s->charts.tris);
    resurfi_free(s->alloc, s->attr.data);
    resurfi_free(s->alloc, s->attr.skin);
    resurfi_free(s->alloc, s->wedge_root);
    simp_queue_free(&s->queue);
    resurfi_free(s->alloc, s->gen);
    resurfi_free(s->alloc, s->home);
    curves_free(s);
    schedule_free(s);
    resurfi_restorer_free(s->own_restorer);
    resurfi_bvh_free(s->own_bvh);
    measure_free(s);
    resurfi_pool_free(s->pool);
    resurf_mesh_free(s->own_derived);
}

/* How one run treats attached sheets: CHOOSE is a choice between two runs, and one run alone drops them. */
static resurf_attached_sheets sheets_used(const resurf_simplify_options *o)
{
    return o->attached_sheets == RESURF_SHEETS_KEEP ? RESURF_SHEETS_KEEP : RESURF_SHEETS_DROP;
}

/* A run: one simplifier taken to one target after another, each no larger than the one before, with a snapshot at
 * each. A level a run passes is the one a call to its target makes (a pass that one target interrupts goes on at the
 * next), so a chain's levels come from one run, and the scene budget asks a kept run for a smaller count rather than
 * simplify the input again. */
struct resurfi_simplify_run {
    simplifier s;
    scratch *sc;
    size_t reached; /* the last target, SIZE_MAX before the first */
};

void resurfi_simplify_run_free(resurfi_simplify_run *r)
{
    if (!r)
        return;
    const resurf_allocator *alloc = r->s.alloc;
    for (unsigned w = 0; r->sc && w < r->s.threads; ++w)
        scratch_free(&r->sc[w]);
    resurfi_free(alloc, r->sc);
    simplifier_free(&r->s);
    resurfi_free(alloc, r);
}

/* The simplifier over `in` set up to its first collapse (simplify_start). */
static resurf_status run_open(const resurf_mesh *in, const resurf_simplify_options *options,
                              const resurfi_simplify_services *services, resurfi_simplify_run **out,
                              resurf_error *error)
{
    *out = NULL;
    const resurf_allocator *alloc = resurfi_allocator_of(options->allocator, in);
    resurfi_simplify_run *r = resurfi_calloc(alloc, 1, sizeof *r);
    if (!r)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory starting the simplification");
    simplifier *s = &r->s;
    s->in = in;
    s->lent = services;
    s->opt = *options;
    s->threads = resurfi_thread_count(s->opt.threads);
    s->alloc = alloc;
    s->queue.alloc = alloc;
    r->reached = SIZE_MAX;
    r->sc = resurfi_calloc(alloc, s->threads, sizeof *r->sc);
    if (!r->sc) {
        resurfi_free(alloc, r);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory starting the simplification");
    }
    for (unsigned w = 0; w < s->threads; ++w)
        r->sc[w].alloc = alloc;
    resurf_status st = resurfi_pool_create(alloc, s->threads, s->opt.thread_pool, &s->pool);
    if (st != RESURF_OK)
        st = resurfi_error(error, st, "out of memory starting the simplification");
    else if (resurfi_progress(&s->opt.progress, RESURF_STAGE_PREPARE, 0))
        st = resurfi_error(error, RESURF_ERR_CANCELLED, "simplification cancelled");
    if (st == RESURF_OK)
        st = simplify_start(s, r->sc, error);
    if (st != RESURF_OK) {
        resurfi_simplify_run_free(r);
        return st;
    }
    *out = r;
    return RESURF_OK;
}

/* The collapses from where the run stands to `target` triangles. */
static resurf_status run_collapse(resurfi_simplify_run *r, size_t target, resurf_error *error)
{
    r->reached = target;
    if (!r->s.tri_count) {
        r->s.rep.stop = RESURF_STOP_TARGET;
        return RESURF_OK;
    }
    return collapse_until(&r->s, target, r->sc, error);
}

/* The snapshot where the run stands, and its report (measured). */
static resurf_status run_output(resurfi_simplify_run *r, resurf_mesh **out, resurf_simplify_report *report,
                                resurf_error *error)
{
    resurf_simplify_report rep;
    resurf_status st = build_output(&r->s, out, &rep, error);
    if (st == RESURF_OK && report) {
        *report = rep;
        report->restore_used = r->s.opt.restore;
        report->attached_sheets_used = sheets_used(&r->s.opt);
    }
    return st;
}

resurf_status resurfi_simplify_run_open(const resurf_mesh *in, const resurf_simplify_options *options,
                                        const resurfi_simplify_services *services, resurfi_simplify_run **out,
                                        resurf_error *error)
{
    resurfi_clear_error(error);
    if (!out || !in || !options)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "a run needs an input, options and out");
    *out = NULL;
    resurf_status st = check_options(options, error);
    if (st != RESURF_OK)
        return st;
    if (options->restore == RESURF_RESTORE_MEASURED)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "a run is one restoring mode, not the measured choice");
    if (services && services->in != in)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "the services were built for another mesh");
    return run_open(in, options, services, out, error);
}

size_t resurfi_simplify_run_reached(const resurfi_simplify_run *r) { return r ? r->reached : 0; }

void resurfi_simplify_run_reject_above(resurfi_simplify_run *r, double scale, double bound)
{
    r->s.measure.reject_scale = scale;
    r->s.measure.reject_bound = bound;
}

resurf_status resurfi_simplify_run_to(resurfi_simplify_run *r, size_t target, resurf_mesh **out,
                                      resurf_simplify_report *report, resurf_error *error)
{
    resurfi_clear_error(error);
    if (!r || !out)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "the run or out is NULL");
    *out = NULL;
    if (target > r->reached)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "a run cannot go back to %zu triangles from %zu",
                             target, r->reached);
    resurf_status st = run_collapse(r, target, error);
    if (st == RESURF_OK && resurfi_progress(&r->s.opt.progress, RESURF_STAGE_FINISH, 1))
        st = resurfi_error(error, RESURF_ERR_CANCELLED, "simplification cancelled");
    return st == RESURF_OK ? run_output(r, out, report, error) : st;
}

void resurfi_report_unmeasured(resurf_simplify_report *r)
{
    r->vertices = r->positions = 0;
    r->max_distance = r->mean_distance = NAN;
    r->max_distance_rel = r->mean_distance_rel = NAN;
    r->result_to_input_max = r->result_to_input_mean = NAN;
    r->input_to_result_max = r->input_to_result_mean = NAN;
    r->uv_error_mean = r->uv_error_p95 = NAN;
}

/* The shared worker: one run of collapses, a snapshot at each target (non-increasing). With `ends`, a level for
 * which ends() says so after its collapses ends the chain there: it gets a report without a mesh (triangles, stop
 * and blocked_* as they were; vertices, positions 0; distances NaN, not measured) and no later level is made.
 * *out_attached_sheets (when not NULL): the input's sheets attached along a line (setup.c), kept or not. */
static resurf_status simplify_levels(const resurf_mesh *in, const resurf_simplify_options *options,
                                     const size_t *targets, size_t count, resurf_mesh **outs,
                                     resurf_simplify_report *reports, const resurfi_chain_end *ends,
                                     const resurfi_simplify_services *services, size_t *out_attached_sheets,
                                     resurf_error *error)
{
    const resurf_simplify_options o = options ? *options : resurf_simplify_options_default();
    resurfi_simplify_run *r = NULL;
    resurf_status st = run_open(in, &o, services, &r, error);
    for (size_t i = 0; i < count && st == RESURF_OK; ++i) {
        simplifier *s = &r->s;
        st = run_collapse(r, targets[i], error);
        if (st == RESURF_OK && resurfi_progress(&s->opt.progress, RESURF_STAGE_FINISH, (double)i / (double)count))
            st = resurfi_error(error, RESURF_ERR_CANCELLED, "simplification cancelled");
        if (st == RESURF_OK && ends && ends->fn(ends->ctx, i, s->alive_tris, s->rep.stop)) {
            if (reports) {
                reports[i] = s->rep;
                reports[i].triangles = s->alive_tris;
                reports[i].restore_used = s->opt.restore;
                reports[i].attached_sheets_used = sheets_used(&s->opt);
                resurfi_report_unmeasured(&reports[i]);
            }
            break;
        }
        if (i + 1 == count) { /* no more collapses: the queue's memory goes before the output's comes */
            s->last_level = 1;
            simp_queue_free(&s->queue);
        }
        if (st == RESURF_OK)
            st = run_output(r, &outs[i], reports ? &reports[i] : NULL, error);
    }
    if (st == RESURF_OK && resurfi_progress(&o.progress, RESURF_STAGE_FINISH, 1))
        st = resurfi_error(error, RESURF_ERR_CANCELLED, "simplification cancelled");
    if (out_attached_sheets)
        *out_attached_sheets = r ? r->s.attached_sheets : 0;
    resurfi_simplify_run_free(r);
    if (st != RESURF_OK)
        for (size_t i = 0; i < count; ++i) {
            resurf_mesh_free(outs[i]);
            outs[i] = NULL;
        }
    return st;
}

/* RESURF_RESTORE_MEASURED: the levels made inline, then again without restoration to the levels the first run
 * made; per level the restored one is kept where it is at least as near the input as the plain one in both the
 * two-sided maximum and the mean, else the plain one: a default that is never farther from the input than the
 * plain collapse, by either measure. A plain level is taken only within the level's target, or anywhere where the
 * inline level missed it too (two runs blocked short of a target stop apart: Q3D_WusonOrange's plain level at 10%,
 * 463 triangles against 451 restored, is 4.22% of the diagonal from the input where the restored one is 4.43%;
 * XGL_wuson_dxf's at 25%, 1,426 against 1,424, 0.069 against 0.165), and below the level before, so the chain's
 * counts never rise. */
/* May level alt replace level cur? Only within slack × the target (or anywhere where cur missed the target too),
 * and below the level before. */
static int within_target(const resurf_simplify_report *alt, const resurf_simplify_report *cur, size_t target,
                         double slack, size_t before)
{
    size_t within = (size_t)(slack * (double)target);
    return (alt->triangles <= within || cur->triangles > target) && alt->triangles < before;
}

/* Is a nearer to the input than b in the two-sided maximum or in the mean? */
static int nearer_somewhere(const resurf_simplify_report *a, const resurf_simplify_report *b)
{
    return !(b->max_distance <= a->max_distance && b->mean_distance <= a->mean_distance);
}

static int plain_is_better(const resurf_simplify_report *plain, const resurf_simplify_report *restored,
                           size_t target, size_t before)
{
    return within_target(plain, restored, target, 1.0, before) && nearer_somewhere(plain, restored);
}

/* A level that keeps the attached sheets replaces the one that drops them only where it is at least as near the
 * input in both the maximum and the mean: dropping is what a scan's stray fins need, and keeping holds a line
 * still. As for plain_is_better, within the level's target, but here with SHEETS_SLACK more triangles, the slack
 * within which resurf_scene_build_lods counts a level as reaching its ratio: the line held can stop a level short
 * of its target, while dropping takes surface the input shows. The handbag of Sweet Home 3D's furniture, a panel
 * written double-sided and attached to the body along 434 positions: kept, its 25% level stops blocked 4
 * triangles above the target at 6.4% of the diagonal, dropped it reaches the target at 17.3%; with the body as
 * one surface (its primitives a unit, scene_joint.c) the 10% level kept stops 7% above its target at 5.9%, and
 * dropped it reaches it at 17.3%, with holes in the body (a slack of 5% took that one). */
#define SHEETS_SLACK 1.5

static int kept_sheets_are_better(const resurf_simplify_report *kept, const resurf_simplify_report *dropped,
                                  size_t target, size_t before)
{
    return within_target(kept, dropped, target, SHEETS_SLACK, before) && nearer_somewhere(kept, dropped) &&
           !nearer_somewhere(dropped, kept);
}

/* The plain run's progress: the inline run has reported every stage to its end, so the plain one only asks the
 * caller's callback again at FINISH 1 (which stays monotonic), that a cancel still stops it. */
static bool plain_run_progress(void *user, resurf_stage stage, double fraction)
{
    (void)stage, (void)fraction;
    const resurf_progress *caller = user;
    return caller->fn(caller->user, RESURF_STAGE_FINISH, 1.0);
}

typedef int (*better_fn)(const resurf_simplify_report *alt, const resurf_simplify_report *cur, size_t target,
                         size_t before);

/* Level i of alt in place of level i of outs wherever better() says so (alt's meshes freed). */
static void keep_nearer(resurf_mesh **outs, resurf_simplify_report *reps, resurf_mesh **alt,
                        const resurf_simplify_report *alt_reps, const size_t *targets, size_t made, better_fn better)
{
    for (size_t i = 0, before = SIZE_MAX; i < made; before = reps[i++].triangles) {
        if (alt[i] && better(&alt_reps[i], &reps[i], targets[i], before)) {
            resurf_mesh *t = outs[i];
            outs[i] = alt[i], alt[i] = t;
            reps[i] = alt_reps[i];
        }
        resurf_mesh_free(alt[i]);
        alt[i] = NULL;
    }
}

/* The plain run of a pair on a thread of its own, beside the inline run (simplify_pair): to every target, since the
 * levels the inline run ends its chain at are not known yet (a run's level does not depend on the targets after it,
 * so the levels both make are the ones the plain run after the inline one makes). Its progress only asks whether
 * the inline run has stopped. */
typedef struct plain_beside {
    const resurf_mesh *in;
    resurf_simplify_options o;
    const size_t *targets;
    size_t count;
    resurf_mesh **outs;
    resurf_simplify_report *reps;
    const resurfi_simplify_services *services;
    atomic_int stop;
    resurf_status st;
    resurf_error error;
} plain_beside;

static bool plain_beside_stopped(void *user, resurf_stage stage, double fraction)
{
    (void)stage, (void)fraction;
    return atomic_load(&((plain_beside *)user)->stop) != 0;
}

static void *plain_beside_run(void *arg)
{
    plain_beside *pb = arg;
    pb->st = simplify_levels(pb->in, &pb->o, pb->targets, pb->count, pb->outs, pb->reps, NULL, pb->services, NULL,
                             &pb->error);
    return NULL;
}

/* The two runs of a pair go side by side, each on its share of the call's own threads, on inputs up to this size:
 * there a run's fork-join loops are short and its second thread gains it little (20k triangles: 0.7 of one
 * thread's time), while two runs on a thread each take the longer one's. Above it a run's threads pay, and the two
 * runs' working memory would be held at once. */
#define PAIR_BESIDE_MAX_TRIANGLES 262144

/* The levels made inline, then plain to the levels the first run made (to every target when keeping `half`), the
 * nearer of each kept (reps: count entries; *attached: the input's attached sheets, from the first run; `half`,
 * when given: a copy of the plain levels). With threads of its own and a small input, the plain run goes beside the
 * inline one, to every target: the same levels. */
static resurf_status simplify_pair(const resurf_mesh *in, const resurf_simplify_options *options,
                                   const size_t *targets, size_t count, resurf_mesh **outs,
                                   resurf_simplify_report *reps, const resurfi_chain_end *ends,
                                   const resurfi_simplify_services *services, size_t *attached,
                                   resurfi_plain_half *half, resurf_error *error)
{
    resurf_simplify_options o = *options;
    o.restore = RESURF_RESTORE_INLINE;
    const resurf_allocator *alloc = resurfi_allocator_of(o.allocator, in);
    resurf_simplify_report *plain_reps = resurfi_calloc(alloc, count ? count : 1, sizeof *plain_reps);
    resurf_mesh **plain = resurfi_calloc(alloc, count ? count : 1, sizeof *plain);
    resurf_status st = plain_reps && plain ? RESURF_OK
                                           : resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    const unsigned threads = resurfi_thread_count(o.threads);
    plain_beside pb = {.in = in, .o = o, .targets = targets, .count = count, .outs = plain, .reps = plain_reps,
                       .services = services};
    atomic_init(&pb.stop, 0);
    bool beside = st == RESURF_OK && threads > 1 && !o.thread_pool && o.measure_samples && count &&
                  in->triangle_count <= PAIR_BESIDE_MAX_TRIANGLES;
    pthread_t thread;
    if (beside) {
        pb.o.restore = RESURF_RESTORE_NONE;
        pb.o.threads = threads / 2;
        pb.o.progress = (resurf_progress){plain_beside_stopped, &pb};
        o.threads = threads - threads / 2;
        beside = pthread_create(&thread, NULL, plain_beside_run, &pb) == 0;
        if (!beside) /* after, as without threads */
            o.threads = options->threads;
    }
    if (st == RESURF_OK)
        st = simplify_levels(in, &o, targets, count, outs, reps, ends, services, attached, error);
    size_t made = 0;
    while (st == RESURF_OK && made < count && outs[made])
        made++;
    if (beside) {
        if (st != RESURF_OK)
            atomic_store(&pb.stop, 1);
        pthread_join(thread, NULL);
        if (st == RESURF_OK && pb.st != RESURF_OK) {
            st = pb.st;
            if (error)
                *error = pb.error;
        }
        /* As after a plain run that follows the inline one: the caller is asked once more, at FINISH 1. */
        if (st == RESURF_OK && options->progress.fn &&
            options->progress.fn(options->progress.user, RESURF_STAGE_FINISH, 1.0))
            st = resurfi_error(error, RESURF_ERR_CANCELLED, "simplification cancelled");
    } else if (st == RESURF_OK && (half ? count : made) && o.measure_samples) {
        const resurf_progress caller = options->progress;
        o.restore = RESURF_RESTORE_NONE;
        if (caller.fn)
            o.progress = (resurf_progress){plain_run_progress, (void *)&caller};
        st = simplify_levels(in, &o, targets, half ? count : made, plain, plain_reps, NULL, services, NULL, error);
    }
    /* The half keeps every plain level, also those after the inline chain's end: the plain pass's chain may go on
       where the inline one stopped (2CylinderEngine: two parts blocked short of 10% inline that the plain collapse
       reduces, which the plain pass otherwise simplified again from their input). Only the levels both made are
       compared. */
    for (size_t i = 0; half && st == RESURF_OK && i < count && plain[i]; ++i) {
        half->reports[i] = plain_reps[i];
        st = resurf_mesh_clone(plain[i], &half->levels[i], error);
    }
    if (st == RESURF_OK)
        keep_nearer(outs, reps, plain, plain_reps, targets, made, plain_is_better);
    for (size_t i = 0; plain && i < count; ++i)
        resurf_mesh_free(plain[i]);
    resurfi_free(alloc, plain);
    resurfi_free(alloc, plain_reps);
    return st;
}

/* RESURF_RESTORE_MEASURED: the pair above; with attached_sheets CHOOSE and an input that has attached sheets, a
 * second pair that keeps them, whose level is taken where kept_sheets_are_better. */
static resurf_status simplify_measured(const resurf_mesh *in, const resurf_simplify_options *options,
                                       const size_t *targets, size_t count, resurf_mesh **outs,
                                       resurf_simplify_report *reports, const resurfi_chain_end *ends,
                                       const resurfi_simplify_services *services, resurfi_plain_half *half,
                                       resurf_error *error)
{
    resurf_simplify_options o = *options;
    const resurf_allocator *alloc = resurfi_allocator_of(o.allocator, in);
    resurf_simplify_report *reps = resurfi_calloc(alloc, count ? 2 * count : 1, sizeof *reps); /* unmade levels: zero */
    resurf_mesh **alt = resurfi_calloc(alloc, count ? count : 1, sizeof *alt);
    resurf_status st = reps && alt ? RESURF_OK : resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    /* The runs read the same services over M (and the plain ones copy the first's analysis): built once here when
       the caller lent none. */
    resurfi_simplify_services *own = NULL;
    if (st == RESURF_OK && !services && o.measure_samples &&
        (st = resurfi_simplify_services_build(in, &o, &own, error)) == RESURF_OK)
        services = own;
    size_t attached = 0, made = 0;
    if (st == RESURF_OK)
        st = simplify_pair(in, &o, targets, count, outs, reps, ends, services, &attached, half, error);
    while (st == RESURF_OK && made < count && outs[made])
        made++;
    if (st == RESURF_OK && made && attached && o.measure_samples && o.attached_sheets == RESURF_SHEETS_CHOOSE) {
        const resurf_progress caller = options->progress;
        o.attached_sheets = RESURF_SHEETS_KEEP;
        if (caller.fn)
            o.progress = (resurf_progress){plain_run_progress, (void *)&caller};
        st = simplify_pair(in, &o, targets, made, alt, reps + count, NULL, services, NULL, NULL, error);
        if (st == RESURF_OK)
            keep_nearer(outs, reps, alt, reps + count, targets, made, kept_sheets_are_better);
    }
    for (size_t i = 0; alt && i < count; ++i)
        resurf_mesh_free(alt[i]);
    if (st != RESURF_OK)
        for (size_t i = 0; i < count; ++i)
            resurf_mesh_free(outs[i]), outs[i] = NULL;
    else if (reports)
        memcpy(reports, reps, count * sizeof *reports);
    resurfi_simplify_services_free(own);
    resurfi_free(alloc, alt);
    resurfi_free(alloc, reps);
    return st;
}

/* One run, or with RESURF_RESTORE_MEASURED the two it compares. */
static resurf_status simplify_chain(const resurf_mesh *in, const resurf_simplify_options *options,
                                    const size_t *targets, size_t count, resurf_mesh **outs,
                                    resurf_simplify_report *reports, const resurfi_chain_end *ends,
                                    const resurfi_simplify_services *services, resurfi_plain_half *half,
                                    resurf_error *error)
{
    resurf_simplify_options o = options ? *options : resurf_simplify_options_default();
    if (o.restore == RESURF_RESTORE_MEASURED)
        return simplify_measured(in, &o, targets, count, outs, reports, ends, services, half, error);
    return simplify_levels(in, &o, targets, count, outs, reports, ends, services, NULL, error);
}

resurf_status resurf_simplify(const resurf_mesh *in, const resurf_simplify_options *options, resurf_mesh **out,
                              resurf_simplify_report *out_report, resurf_error *error)
{
    return resurfi_simplify_lent(in, options, NULL, out, out_report, error);
}

resurf_status resurfi_simplify_lent(const resurf_mesh *in, const resurf_simplify_options *options,
                                    const resurfi_simplify_services *services, resurf_mesh **out,
                                    resurf_simplify_report *out_report, resurf_error *error)
{
    resurfi_clear_error(error);
    if (!out)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "out is NULL");
    *out = NULL;
    if (!in)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "the input mesh is NULL");
    resurf_status st = check_options(options, error);
    if (st != RESURF_OK)
        return st;
    resurf_simplify_options o = options ? *options : resurf_simplify_options_default();
    /* Whichever target comes first is the larger triangle count. */
    size_t target = 0;
    if (o.target_triangles)
        target = o.target_triangles;
    if (o.target_ratio > 0) {
        size_t r = (size_t)floor(o.target_ratio * (double)in->triangle_count * (1 + 1e-12));
        target = r > target ? r : target;
    }
    resurf_simplify_report rep;
    if (services && services->in != in)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "the services were built for another mesh");
    st = simplify_chain(in, &o, &target, 1, out, out_report ? &rep : NULL, NULL, services, NULL, error);
    if (st == RESURF_OK && out_report)
        *out_report = rep;
    return st;
}

resurf_status resurf_simplify_lods(const resurf_mesh *in, const double *ratios, size_t count,
                                   const resurf_simplify_options *options, resurf_mesh **out_levels,
                                   resurf_simplify_report *out_reports, resurf_error *error)
{
    return resurfi_simplify_lods_until(in, ratios, count, options, NULL, NULL, NULL, out_levels, out_reports, error);
}

resurf_status resurfi_simplify_lods_until(const resurf_mesh *in, const double *ratios, size_t count,
                                          const resurf_simplify_options *options, const resurfi_chain_end *ends,
                                          const resurfi_simplify_services *services, resurfi_plain_half *half,
                                          resurf_mesh **out_levels, resurf_simplify_report *out_reports,
                                          resurf_error *error)
{
    resurfi_clear_error(error);
    if (!out_levels || (count && !ratios))
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "%s is NULL", out_levels ? "ratios" : "out_levels");
    for (size_t i = 0; i < count; ++i)
        out_levels[i] = NULL;
    if (!in)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "the input mesh is NULL");
    resurf_status st = check_options(options, error);
    if (st != RESURF_OK)
        return st;
    const resurf_allocator *alloc = resurfi_allocator_of(options ? options->allocator : NULL, in);
    size_t *targets = resurfi_alloc(alloc, count, sizeof *targets);
    if (!targets)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    for (size_t i = 0; i < count; ++i) {
        if (!(ratios[i] > 0 && ratios[i] <= 1) || (i > 0 && ratios[i] > ratios[i - 1])) {
            resurfi_free(alloc, targets);
            return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT,
                                 "ratio %zu (%g) must be in (0, 1] and not above the previous one", i, ratios[i]);
        }
        targets[i] = (size_t)floor(ratios[i] * (double)in->triangle_count * (1 + 1e-12));
    }
    st = services && services->in != in
             ? resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "the services were built for another mesh")
             : simplify_chain(in, options, targets, count, out_levels, out_reports, ends, services, half, error);
    resurfi_free(alloc, targets);
    return st;
}
