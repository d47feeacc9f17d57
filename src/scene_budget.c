/* The scene's triangles spent where the error is (resurf_scene_build_lods, after every primitive has its chain).
 *
 * Each primitive's chain stops at its own ratio, so a primitive that cannot reach its ratio without a large error
 * (a small CAD part whose positions are mostly corners and locks: 2CylinderEngine's connecting rod closes its bolt
 * hole at 25%) sets the whole scene's error, while the large parts beside it lie far under it. Per level, from the
 * primitives' own measured two-sided maxima in world units (their reports times their mesh's scale):
 *   1. the primitive of the largest error `top` is simplified again from its input with more triangles (twice as
 *      many, and again, up to one fewer than its level before, then 3 halvings of the interval) until its error is
 *      no more than the bound B = second^(1 - r) top^r, second being the largest error of the others;
 *   2. the triangles it gained are taken back from the primitives of the most triangles whose error stays within B
 *      when simplified again to fewer (none goes to or under its next level; a level its chain had ended at may
 *      come back so; at most DONOR_RUNS of them are tried);
 *   3. when they cannot all be taken back, within the larger of the level's ratio times the scene's triangles and
 *      the scene's count before (at this level and the later ones that show it), the step is undone; r = 0 is
 *      tried first, then r = 0.5 (0.8 as a third try changed nothing on 2CylinderEngine and cost 20% more time);
 *      when neither works the level is done, else the step repeats (at most BUDGET_STEPS times).
 * A mesh whose primitives are simplified together (scene_joint.c) is one unit here: its input is the primitives
 * joined (with the joined locks and sample share of its chain), a run simplifies that to a count and is split back
 * into the primitives, and its triangles and error are the sum and the mesh's; a run that would leave one of them
 * without triangles is not taken. (Counted but never made again, such a mesh set 2CylinderEngine's 10% level at
 * 1.361 times gltfpack's Hausdorff; as a unit, 0.526.)
 * The scene's maximum therefore never rises, its triangle count never exceeds that allowance, and every run is a
 * resurf_simplify call in primitive order: the outcome does not depend on the thread count. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene_internal.h"

/* Steps per level: each lowers the scene's maximum to the next primitive's error. */
#define BUDGET_STEPS 8
#define BISECTIONS 3
/* Donor runs per step: a scene of hundreds of primitives must not try them all (2CylinderEngine's steps take at most
 * 3). */
#define DONOR_RUNS 8
/* A run asked for c triangles leaves at least c - OVERSHOOT: it stops at the first collapse that reaches c, and a
 * collapse takes at most 2 triangles, 4 on a double-sided sheet (mirrors count). */
#define OVERSHOOT 4

static size_t shown_triangles(const resurfi_budget_prim *b, size_t k)
{
    size_t s = b->chain && *b->kept > k ? k + 1 : (b->chain ? *b->kept : 0);
    return s ? b->chain[s - 1]->triangle_count : b->input->triangle_count;
}

static size_t level_total(const resurfi_budget_prim *prims, size_t n, size_t k)
{
    size_t total = 0;
    for (size_t p = 0; p < n; ++p)
        total += shown_triangles(&prims[p], k);
    return total;
}

static double report_error(const resurfi_budget_prim *b, const resurf_simplify_report *r)
{
    return b->scale * fmax(r->result_to_input_max, r->input_to_result_max);
}

static double shown_error(const resurfi_budget_prim *b, size_t k)
{
    size_t s = b->chain && *b->kept > k ? k + 1 : (b->chain ? *b->kept : 0);
    return s ? report_error(b, &b->reports[s - 1]) : 0;
}

/* Runs already made at this level: a step that is undone and tried again with a larger reach, or a later step,
 * asks for many of the same (primitive, count) runs, and each is a whole resurf_simplify call. The memo owns its
 * meshes; callers get clones, so that what they keep or free stays theirs. */
typedef struct budget_run {
    const resurfi_budget_prim *prim;
    size_t t;
    resurf_mesh *mesh;
    resurf_simplify_report report;
    double above; /* > 0: the run was only measured as far as to show that its error exceeds this bound */
} budget_run;

/* A primitive's simplification kept where its last run stopped: the budget mostly asks a primitive for fewer
 * triangles than the time before (the halvings toward the fewest that suffice, a donor giving more at each step),
 * and a kept run goes on from there to the same mesh and report a new one would make. At most LIVE_RUNS are kept
 * at a time, over at most LIVE_TRIANGLES input triangles in all besides the newest (each holds its primitive's
 * working mesh, about 200 bytes a triangle), the least recently asked giving way. */
#define LIVE_RUNS 16
#define LIVE_TRIANGLES ((size_t)1 << 21)

typedef struct live_run {
    resurfi_simplify_run *run;
    size_t prim, used;
    /* the options a level's runs of a primitive share: asked with others, the run is made again */
    resurf_restore_mode restore;
    resurf_attached_sheets sheets;
    double max_error;
} live_run;

typedef struct budget_memo {
    budget_run *runs;
    size_t count, capacity;
    const resurf_allocator *alloc;
    const resurfi_budget_prim *prims;
    resurfi_simplify_services **services; /* per primitive, built at its first run, kept for all levels */
    live_run live[LIVE_RUNS];             /* the kept runs (they serve the next level too) */
    size_t clock;
} budget_memo;

/* The runs made (their meshes and reports) are a level's: the next level's have other bounds. The kept runs may
 * serve it too (a run asked with other options is made again), and go with `live`. */
static void memo_clear(budget_memo *memo, int live)
{
    for (size_t i = 0; i < memo->count; ++i)
        resurf_mesh_free(memo->runs[i].mesh);
    memo->count = 0;
    for (int i = 0; live && i < LIVE_RUNS; ++i) {
        resurfi_simplify_run_free(memo->live[i].run);
        memo->live[i].run = NULL;
    }
}

/* A slot for a new run: the least recently asked runs give way while all LIVE_RUNS are kept or the kept ones hold
 * more than LIVE_TRIANGLES input triangles. */
static live_run *make_room(budget_memo *memo)
{
    for (;;) {
        live_run *free_slot = NULL, *oldest = NULL;
        size_t held = 0;
        for (int i = 0; i < LIVE_RUNS; ++i) {
            live_run *l = &memo->live[i];
            if (!l->run) {
                free_slot = free_slot ? free_slot : l;
                continue;
            }
            held += memo->prims[l->prim].input->triangle_count;
            oldest = !oldest || l->used < oldest->used ? l : oldest;
        }
        if (free_slot && held <= LIVE_TRIANGLES)
            return free_slot;
        resurfi_simplify_run_free(oldest->run);
        oldest->run = NULL;
    }
}

/* Primitive p's input simplified with options o to t triangles: by its kept run when that stands above t, else by a
 * new run (kept). Its report is the full one unless its error exceeds `bound` (see resurfi_simplify_run_reject_above):
 * the step turns such a run down whatever its figures. */
static resurf_status simplify_to(budget_memo *memo, size_t p, const resurf_simplify_options *o, size_t t,
                                 double bound, resurf_mesh **out, resurf_simplify_report *rep, resurf_error *e)
{
    const resurf_mesh *in = memo->prims[p].input;
    if (o->restore == RESURF_RESTORE_MEASURED) /* a choice between two runs: made whole */
        return resurfi_simplify_lent(in, o, memo->services[p], out, rep, e);
    live_run *slot = NULL;
    for (int i = 0; i < LIVE_RUNS && !slot; ++i)
        if (memo->live[i].run && memo->live[i].prim == p)
            slot = &memo->live[i];
    if (slot && (resurfi_simplify_run_reached(slot->run) < t || slot->restore != o->restore ||
                 slot->sheets != o->attached_sheets || slot->max_error != o->max_error)) { /* below t, or other */
        resurfi_simplify_run_free(slot->run);
        slot->run = NULL;
        slot = NULL;
    }
    if (!slot) {
        slot = make_room(memo);
        slot->prim = p, slot->restore = o->restore, slot->sheets = o->attached_sheets, slot->max_error = o->max_error;
        resurf_status st = resurfi_simplify_run_open(in, o, memo->services[p], &slot->run, e);
        if (st != RESURF_OK)
            return st;
    }
    slot->used = ++memo->clock;
    resurfi_simplify_run_reject_above(slot->run, memo->prims[p].scale, bound);
    return resurfi_simplify_run_to(slot->run, t, out, rep, e);
}

/* Primitive b's level k (0-based) simplified again from its input to at most t triangles: *out and *rep, the report
 * a full one wherever its error (report_error) is within `bound`. */
static resurf_status rerun(budget_memo *memo, const resurfi_budget_prim *b, size_t k, size_t t, double bound,
                           resurf_mesh **out, resurf_simplify_report *rep, resurf_error *e)
{
    budget_run *run = NULL;
    for (size_t i = 0; i < memo->count && !run; ++i)
        if (memo->runs[i].prim == b && memo->runs[i].t == t)
            run = &memo->runs[i];
    if (run && run->above > 0 && bound > run->above) { /* known above a lower bound only: made again */
        resurf_mesh_free(run->mesh);
        *run = memo->runs[--memo->count];
        run = NULL;
    }
    if (!run) {
        if (memo->count == memo->capacity) {
            size_t grown = memo->capacity ? 2 * memo->capacity : 16;
            budget_run *runs = resurfi_realloc(memo->alloc, memo->runs, grown, sizeof *runs);
            if (!runs)
                return resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
            memo->runs = runs, memo->capacity = grown;
        }
        resurf_simplify_options o = b->sim;
        o.target_ratio = 0;
        o.target_triangles = t;
        /* A level is made again the way its chain's level was (inline or plain, its attached sheets kept or
           dropped): one run, not the measured choice's. */
        if (o.restore == RESURF_RESTORE_MEASURED && (b->reports[k].restore_used == RESURF_RESTORE_INLINE ||
                                                     b->reports[k].restore_used == RESURF_RESTORE_NONE)) {
            o.restore = b->reports[k].restore_used;
            o.attached_sheets = b->reports[k].attached_sheets_used;
        }
        if (b->bounds[k] > 0)
            o.max_error = o.max_error > 0 ? fmin(o.max_error, b->bounds[k]) : b->bounds[k];
        resurfi_simplify_services **services = &memo->services[b - memo->prims];
        if (!*services) {
            resurf_status st = resurfi_simplify_services_build(b->input, &o, services, e);
            if (st != RESURF_OK)
                return st;
        }
        run = &memo->runs[memo->count];
        run->prim = b, run->t = t, run->mesh = NULL;
        resurf_status st = simplify_to(memo, (size_t)(b - memo->prims), &o, t, bound, &run->mesh, &run->report, e);
        if (st != RESURF_OK)
            return st;
        run->above = run->report.max_distance == INFINITY ? bound : 0;
        memo->count++;
    }
    *rep = run->report;
    return resurf_mesh_clone(run->mesh, out, e);
}

/* A run of a mesh simplified together is taken only when it leaves every primitive that had triangles some. */
static int keeps_parts(const resurfi_budget_prim *b, const resurf_mesh *m)
{
    for (size_t g = 0; g < b->parts; ++g) {
        size_t had = 0, has = 0;
        for (size_t t = 0; t < b->input->triangle_count && !had; ++t)
            had = b->input->triangle_groups[t] == g;
        for (size_t t = 0; t < m->triangle_count && !has; ++t)
            has = m->triangle_groups[t] == g;
        if (had && !has)
            return 0;
    }
    return 1;
}

/* The levels of each mesh simplified together, joined as its chain: made[k] keeps level k as first joined (alive
 * until units_close, so that no later mesh can take its address), and units_close splits back only the levels the
 * budget made again. */
static resurf_status units_open(resurfi_budget_prim *prims, size_t n, size_t count, const resurf_allocator *alloc,
                                resurf_error *e)
{
    for (size_t p = 0; p < n; ++p) {
        resurfi_budget_prim *b = &prims[p];
        if (!b->parts)
            continue;
        b->chain = resurfi_calloc(alloc, 2 * count, sizeof *b->chain);
        b->reports = resurfi_calloc(alloc, count, sizeof *b->reports);
        const resurf_mesh *parts[64];
        const resurf_mesh **in = b->parts <= 64 ? parts : resurfi_alloc(alloc, b->parts, sizeof *in);
        if (!b->chain || !b->reports || !in)
            return resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
        b->made = b->chain + count;
        b->joined_kept = b->part_kept[b->members[0]], b->kept = &b->joined_kept;
        for (size_t k = 0; k < count; ++k) {
            b->reports[k] = b->part_reports[b->members[0] * count + k]; /* the distances are the unit's */
            int whole = 1;
            for (size_t q = 0; q < b->parts; ++q)
                whole &= (in[q] = b->part_chains[b->members[q]][k]) != NULL;
            resurf_status st = whole ? resurfi_mesh_join_parts(in, b->parts, alloc, &b->chain[k], e) : RESURF_OK;
            if (st != RESURF_OK) {
                if (in != parts)
                    resurfi_free(alloc, in);
                return st;
            }
            b->made[k] = b->chain[k];
        }
        if (in != parts)
            resurfi_free(alloc, in);
    }
    return RESURF_OK;
}

/* The levels made again split back into the primitives, each with the mesh's report and its own counts. */
static resurf_status units_close(resurfi_budget_prim *prims, size_t n, size_t count, resurf_status st,
                                 const resurf_allocator *alloc, resurf_error *e)
{
    for (size_t p = 0; p < n; ++p) {
        resurfi_budget_prim *b = &prims[p];
        resurf_mesh *split[64];
        resurf_mesh **level = b->parts <= 64 ? split : resurfi_alloc(alloc, b->parts, sizeof *level);
        if (b->parts && !level && st == RESURF_OK)
            st = resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
        for (size_t k = 0; b->parts && b->chain && k < count; ++k) {
            if (st == RESURF_OK && b->chain[k] != b->made[k] &&
                (st = resurfi_mesh_split_parts(b->chain[k], b->parts, alloc, level, e)) == RESURF_OK)
                for (size_t q = 0; q < b->parts; ++q) {
                    size_t part = b->members[q];
                    resurf_simplify_report *own = &b->part_reports[part * count + k];
                    resurf_mesh_free(b->part_chains[part][k]);
                    b->part_chains[part][k] = level[q];
                    *own = b->reports[k];
                    own->input_triangles = b->part_reports[part * count].input_triangles;
                    own->triangles = level[q]->triangle_count;
                    own->vertices = level[q]->vertex_count;
                }
            if (b->chain[k] != b->made[k])
                resurf_mesh_free(b->made[k]);
            resurf_mesh_free(b->chain[k]);
        }
        for (size_t q = 0; b->parts && st == RESURF_OK && q < b->parts; ++q)
            b->part_kept[b->members[q]] = b->joined_kept;
        if (level != split)
            resurfi_free(alloc, level);
        if (b->parts)
            resurfi_free(alloc, b->chain), resurfi_free(alloc, b->reports);
    }
    return st;
}

/* What one step changed, to undo it. */
typedef struct budget_change {
    size_t prim, old_kept;
    resurf_mesh *old;
    resurf_simplify_report old_report;
} budget_change;

/* m becomes level k of b: in place of the one it had, or as a level added where its chain ended. */
static void apply(resurfi_budget_prim *b, size_t k, resurf_mesh *m, const resurf_simplify_report *rep,
                  budget_change *c, size_t prim)
{
    c->prim = prim;
    c->old_kept = *b->kept;
    c->old = b->chain[k];
    c->old_report = b->reports[k];
    b->chain[k] = m;
    b->reports[k] = *rep;
    if (*b->kept == k)
        *b->kept = k + 1;
}

static void undo(resurfi_budget_prim *prims, size_t k, budget_change *c, size_t n)
{
    while (n--) {
        resurfi_budget_prim *b = &prims[c[n].prim];
        resurf_mesh_free(b->chain[k]);
        b->chain[k] = c[n].old;
        b->reports[k] = c[n].old_report;
        *b->kept = c[n].old_kept;
    }
}

static int donor_first(const void *x, const void *y)
{
    const size_t *a = x, *b = y;
    if (a[0] != b[0])
        return a[0] > b[0] ? -1 : 1;
    return (a[1] > b[1]) - (a[1] < b[1]);
}

/* The most triangles a step at level k could pay back for the worst primitive's gain: the level's room left and
 * what each primitive that may donate (2. below: error under the bound, more than one triangle above its next
 * level) could give at most. */
static size_t pay_capacity(const resurfi_budget_prim *prims, size_t n, size_t k, size_t worst, double bound,
                           size_t allowed)
{
    size_t total = level_total(prims, n, k), capacity = total < allowed ? allowed - total : 0;
    for (size_t p = 0; p < n; ++p) {
        const resurfi_budget_prim *d = &prims[p];
        size_t now = shown_triangles(d, k), next = *d->kept > k + 1 ? d->chain[k + 1]->triangle_count : 0;
        if (p != worst && *d->kept >= k && now > next + 1 && shown_error(d, k) < bound)
            capacity += now - next - 1;
    }
    return capacity;
}

/* One step at level k toward the error second^(1 - reach) · top^reach (second: the largest but the worst's, top:
 * the worst's): 1 done (the maximum fell), 0 not possible, or -1 with *st set. */
static int step(resurfi_budget_prim *prims, size_t n, size_t k, size_t count, const size_t *allowed, double reach,
                budget_change *changes, size_t *donors, budget_memo *memo, resurf_status *st, resurf_error *e)
{
    size_t worst = SIZE_MAX;
    double top = 0, second = 0;
    for (size_t p = 0; p < n; ++p) {
        double err = shown_error(&prims[p], k);
        if (worst == SIZE_MAX || err > top)
            top = err, worst = p;
    }
    for (size_t p = 0; p < n; ++p)
        if (p != worst)
            second = fmax(second, shown_error(&prims[p], k));
    resurfi_budget_prim *w = worst == SIZE_MAX ? NULL : &prims[worst];
    if (!w || !(second > 0) || !(top > second) || *w->kept <= k)
        return 0;
    double bound = pow(second, 1 - reach) * pow(top, reach); /* the scene's maximum after the step */
    /* Whatever the worst gains must be paid back (2.) from the level's room left and the donors: the runs of a gain
       beyond that would all be undone (Collada_human's two primitives: 2.1 s of runs, its only donor's bound being
       its own error at r = 0), so the search stops as soon as the gain is sure to be too large. */
    size_t capacity = pay_capacity(prims, n, k, worst, bound, allowed[k]), t0 = w->chain[k]->triangle_count;
    if (!capacity)
        return 0;
    /* 1. More triangles for the worst, below its level before and no more than the others can pay for (a run asked
       for c leaves at most c: Collada_human's head, 26,756 triangles, doubled to 13,377 and 26,755 and halved three
       times toward a gain its eyes, 2,040 triangles, could never pay). */
    size_t before = k ? w->chain[k - 1]->triangle_count : w->input->triangle_count, payable = t0 + capacity;
    size_t t = w->chain[k]->triangle_count, used = 0;
    resurf_mesh *m = NULL;
    resurf_simplify_report rep;
    size_t low = t; /* the most triangles known to leave the error above the bound */
    while (t + 1 < before && t < payable) {
        t = 2 * t + 1 < before ? 2 * t + 1 : before - 1;
        t = t < payable ? t : payable;
        if ((*st = rerun(memo, w, k, t, bound, &m, &rep, e)) != RESURF_OK)
            return -1;
        if (report_error(w, &rep) <= bound && m->triangle_count < before && keeps_parts(w, m))
            break;
        resurf_mesh_free(m);
        m = NULL;
        low = t;
    }
    /* A run to count c leaves at least c - OVERSHOOT triangles, so every count the halvings can find gains more than
       low - OVERSHOOT - t0. */
    if (!m || (low > t0 + OVERSHOOT && low - OVERSHOOT - t0 > capacity)) {
        resurf_mesh_free(m);
        return 0;
    }
    /* Doubling overshoots: a few halvings of the interval toward the fewest triangles that suffice. */
    for (int i = 0; i < BISECTIONS && t > low + 1; ++i) {
        size_t mid = low + (t - low) / 2;
        resurf_mesh *m2 = NULL;
        resurf_simplify_report rep2;
        if ((*st = rerun(memo, w, k, mid, bound, &m2, &rep2, e)) != RESURF_OK) {
            resurf_mesh_free(m);
            return -1;
        }
        if (report_error(w, &rep2) <= bound && m2->triangle_count < before && keeps_parts(w, m2)) {
            resurf_mesh_free(m);
            m = m2, rep = rep2, t = mid;
        } else {
            resurf_mesh_free(m2);
            low = mid;
        }
    }
    if (m->triangle_count > t0 && m->triangle_count - t0 > capacity) {
        resurf_mesh_free(m);
        return 0;
    }
    apply(w, k, m, &rep, &changes[used++], worst);
    /* 2. The gain taken back from the largest primitives that can spare it. */
    size_t nd = 0;
    for (size_t p = 0; p < n; ++p)
        if (p != worst && *prims[p].kept >= k)
            donors[2 * nd] = shown_triangles(&prims[p], k), donors[2 * nd + 1] = p, nd++;
    qsort(donors, nd, 2 * sizeof *donors, donor_first);
    size_t total = level_total(prims, n, k);
    for (size_t i = 0, tried = 0; i < nd && total > allowed[k] && tried < DONOR_RUNS; ++i) {
        resurfi_budget_prim *d = &prims[donors[2 * i + 1]];
        size_t now = shown_triangles(d, k), next = *d->kept > k + 1 ? d->chain[k + 1]->triangle_count : 0;
        size_t excess = total - allowed[k];
        if (now <= excess || now - excess <= next || shown_error(d, k) >= bound)
            continue; /* fewer triangles would not stay within the bound */
        tried++;
        if ((*st = rerun(memo, d, k, now - excess, bound, &m, &rep, e)) != RESURF_OK) {
            undo(prims, k, changes, used);
            return -1;
        }
        if (report_error(d, &rep) > bound || m->triangle_count >= now || m->triangle_count <= next ||
            !keeps_parts(d, m)) {
            resurf_mesh_free(m);
            continue;
        }
        total -= now - m->triangle_count;
        apply(d, k, m, &rep, &changes[used++], donors[2 * i + 1]);
    }
    /* 3. Kept only within the allowance, at this level and the later ones that show it. */
    int over = 0;
    for (size_t j = k; j < count; ++j)
        over |= level_total(prims, n, j) > allowed[j];
    if (over) {
        undo(prims, k, changes, used);
        return 0;
    }
    for (size_t i = 0; i < used; ++i) {
        const resurfi_budget_prim *b = &prims[changes[i].prim];
        /* A unit's level as first joined stays until units_close tells the levels made again by it: freed here, its
           address could come back to a later run's mesh, which would then pass for it. */
        if (!(b->parts && changes[i].old == b->made[k]))
            resurf_mesh_free(changes[i].old);
    }
    return 1;
}

resurf_status resurfi_scene_budget(resurfi_budget_prim *prims, size_t n, const double *ratios, size_t count,
                                   const resurf_allocator *alloc, resurf_error *e)
{
    if (!ratios || n < 2)
        return RESURF_OK;
    size_t input = 0;
    for (size_t p = 0; p < n; ++p)
        input += prims[p].input->triangle_count;
    budget_change *changes = resurfi_alloc(alloc, n + 1, sizeof *changes);
    size_t *donors = resurfi_alloc(alloc, 2 * n + 2, sizeof *donors);
    resurfi_simplify_services **services = resurfi_calloc(alloc, n + 1, sizeof *services);
    resurf_status st = changes && donors && services ? RESURF_OK
                                                     : resurfi_error(e, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    if (st == RESURF_OK)
        st = units_open(prims, n, count, alloc, e);
    size_t allowed[RESURF_SCENE_MAX_LEVELS - 1];
    for (size_t k = 0; k < count; ++k) {
        size_t before = level_total(prims, n, k);
        double target = floor(ratios[k] * (double)input);
        allowed[k] = (double)before > target ? before : (size_t)target;
    }
    /* Toward the next error first; when the others cannot pay for that, part of the way. */
    static const double reach[] = {0, 0.5};
    budget_memo memo = {.alloc = alloc, .prims = prims, .services = services};
    for (size_t k = 0; k < count && st == RESURF_OK; ++k) {
        for (int s = 0, done = 1; s < BUDGET_STEPS && done == 1; ++s) {
            done = 0;
            for (size_t i = 0; i < sizeof reach / sizeof *reach && done == 0; ++i)
                done = step(prims, n, k, count, allowed, reach[i], changes, donors, &memo, &st, e);
        }
        memo_clear(&memo, 0);
    }
    memo_clear(&memo, 1);
    st = units_close(prims, n, count, st, alloc, e);
    resurfi_free(alloc, memo.runs);
    for (size_t p = 0; services && p < n; ++p)
        resurfi_simplify_services_free(services[p]);
    resurfi_free(alloc, services);
    resurfi_free(alloc, changes);
    resurfi_free(alloc, donors);
    return st;
}
