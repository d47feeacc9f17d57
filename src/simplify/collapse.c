/* The collapse core: where a collapse puts its vertex and what it costs, which collapses the ends' kinds allow (a
 * table), the first candidates, applying one collapse, trying one candidate, and the pass loop (collapse_until).
 * The guards a planned collapse must pass are in guards.c, the order and grouping of collapses in schedule.c. */
#include <float.h>
#include <math.h>

#include "simplify_internal.h"

/* ---- planning one collapse ----------------------------------------------------------------------------------- */

/* Counts n refused candidates in the report. */
static void count_blocks(resurf_simplify_report *r, int reason, size_t n)
{
    if (reason == BLOCK_SEAM)
        r->blocked_seam += n;
    else if (reason == BLOCK_BORDER)
        r->blocked_border += n;
    else if (reason == BLOCK_FEATURE)
        r->blocked_feature += n;
    else if (reason == BLOCK_NONMANIFOLD)
        r->blocked_nonmanifold += n;
}

/* A cost as the queue ranks it. Costs are squared lengths times areas: divided by diagonal⁴ so that floats neither
 * underflow nor overflow. */
static float scaled_cost(const simplifier *s, double cost)
{
    double d2 = s->diagonal * s->diagonal;
    double scaled = d2 > 0 ? cost / (d2 * d2) : cost;
    return scaled < FLT_MAX ? (float)scaled : FLT_MAX;
}

/* Where the free vertex of edge (a, b) goes. A seam edge keeps it on the segment (the minimiser of Q there): the
 * seam is a curve the restorer does not know, and off it the two sides' attributes would no longer meet. So does a
 * crease edge: off the segment the vertex would leave the crease's plane on one side (a flat face stays flat). */
static vec3 free_placement(const simplifier *s, const resurfi_quadric *q, vec3 pa, vec3 pb, int on_segment)
{
    vec3 mid = v3_scale(v3_add(pa, pb), 0.5);
    if (s->opt.placement == RESURF_PLACEMENT_MIDPOINT)
        return mid;
    if (on_segment) {
        vec3 d = v3_sub(pb, pa), a0 = v3_sub(pa, s->origin);
        vec3 ad = resurfi_quadric_mul(q, d);
        double dad = v3_dot(d, ad);
        if (!(dad > 0))
            return mid;
        double t = -(v3_dot(ad, a0) + q->b[0] * d.x + q->b[1] * d.y + q->b[2] * d.z) / dad;
        t = t < 0 ? 0 : t > 1 ? 1 : t;
        return t == 0 ? pa : t == 1 ? pb : v3_lerp(pa, pb, t);
    }
    vec3 x;
    if (resurfi_quadric_optimum(q, v3_sub(mid, s->origin), &x)) {
        x = v3_add(x, s->origin);
        if (v3_dist2(x, mid) <= v3_dist2(pa, pb))
            return x;
    }
    /* Singular, or the optimum lies outside the edge's neighbourhood (a nearly flat quadric extrapolating): the
     * best of the three obvious points. */
    double ea = qeval(s, q, pa), eb = qeval(s, q, pb), em = qeval(s, q, mid);
    return em <= ea && em <= eb ? mid : ea <= eb ? pa : pb;
}

/* THE RULE: which end of an edge may go. Removing x into y keeps every corner of x on a wedge: x's corners take
 * y's wedges, so x may go only where that map is defined and keeps the attribute sides apart. Its kind (from its
 * flags) and how the edge meets x decide whether x is held in place:
 *   x LOCKED / LOCKED_BORDER / COMPLEX        never
 *   x a CORNER (of creases or of a border)    never
 *   x on a border                             only along a border edge (so y is on the same border)
 *   x a seam vertex (two wedges)              only along one of its seam edges
 *   x on a CREASE                             anywhere: the quadric keeps it on its crease (holding it to the
 *                                             crease's edges was measured worse, docs/restoring.md §8)
 *   x inside a JUNCTION line                  only along the line (an edge of three triangles: the sheet's and
 *                                             the surface's two), to a point of that edge
 * and the wedge map decides the rest (map_ok): a seam vertex's two wedges need two distinct images (the edge's
 * triangles differ at y too), a single-wedge vertex a single one (the edge's triangles share y's wedge).
 * If both ends may go, the position is free (quadric or midpoint); if only x may go and y is held (y cannot leave
 * its border, seam or place), the position is y's.
 *
 * kHeld holds the first half, as meshoptimizer's kCanCollapse does for its vertex kinds: the reason x is held, by
 * x's kind and the edge seen from x. It is indexed by one end and the edge rather than by the two ends' kinds
 * because here the edge decides: a border vertex may go along its border but not across, a seam vertex along its
 * seam but not off it; the other end enters through the wedge map and the placement only. */
enum {
    KIND_MANIFOLD, KIND_CREASE, KIND_SEAM, KIND_COMPLEX, KIND_BORDER, KIND_BORDER_WEDGES, KIND_LOCKED_BORDER,
    KIND_CORNER, KIND_LOCKED, KIND_JUNCTION, KINDS
};
/* The edge as seen from x: EDGE_JUNCTION when it has three triangles, EDGE_BORDER one, EDGE_SEAM when its wedges
 * differ at x, EDGE_FEATURE a crease (feature_edge, only asked for a crease vertex), else interior. */
enum { EDGE_INTERIOR, EDGE_SEAM, EDGE_BORDER, EDGE_FEATURE, EDGE_JUNCTION, EDGE_KINDS };

static const uint8_t kHeld[KINDS][EDGE_KINDS] = {
    /*                       interior           seam at x          border edge        feature edge       junction */
    [KIND_MANIFOLD]      = {BLOCK_NONE,        BLOCK_NONE,        BLOCK_NONE,        BLOCK_NONE,        BLOCK_NONMANIFOLD},
    [KIND_CREASE]        = {BLOCK_NONE,        BLOCK_NONE,        BLOCK_NONE,        BLOCK_NONE,        BLOCK_NONMANIFOLD},
    [KIND_SEAM]          = {BLOCK_SEAM,        BLOCK_NONE,        BLOCK_SEAM,        BLOCK_SEAM,        BLOCK_NONMANIFOLD},
    [KIND_COMPLEX]       = {BLOCK_SEAM,        BLOCK_SEAM,        BLOCK_SEAM,        BLOCK_SEAM,        BLOCK_NONMANIFOLD},
    [KIND_BORDER]        = {BLOCK_BORDER,      BLOCK_BORDER,      BLOCK_NONE,        BLOCK_BORDER,      BLOCK_NONMANIFOLD},
    [KIND_BORDER_WEDGES] = {BLOCK_BORDER,      BLOCK_BORDER,      BLOCK_SEAM,        BLOCK_BORDER,      BLOCK_NONMANIFOLD},
    [KIND_LOCKED_BORDER] = {BLOCK_BORDER,      BLOCK_BORDER,      BLOCK_BORDER,      BLOCK_BORDER,      BLOCK_BORDER},
    [KIND_CORNER]        = {BLOCK_FEATURE,     BLOCK_FEATURE,     BLOCK_FEATURE,     BLOCK_FEATURE,     BLOCK_FEATURE},
    [KIND_LOCKED]        = {BLOCK_NONMANIFOLD, BLOCK_NONMANIFOLD, BLOCK_NONMANIFOLD, BLOCK_NONMANIFOLD, BLOCK_NONMANIFOLD},
    [KIND_JUNCTION]      = {BLOCK_NONMANIFOLD, BLOCK_NONMANIFOLD, BLOCK_NONMANIFOLD, BLOCK_NONMANIFOLD, BLOCK_NONE},
};

/* A position's kind: the first of its flags that applies. A seam vertex on a crease (a normal seam, or a crease
 * a texture seam follows) is a seam vertex: it goes along its seam. */
static int end_kind(pos_flags f)
{
    if (f & POS_LOCKED)
        return KIND_LOCKED;
    if (f & POS_CORNER)
        return KIND_CORNER;
    if (f & POS_LOCKED_BORDER)
        return KIND_LOCKED_BORDER;
    if (f & POS_BORDER)
        return f & (POS_COMPLEX | POS_SEAM) ? KIND_BORDER_WEDGES : KIND_BORDER;
    if (f & POS_COMPLEX)
        return KIND_COMPLEX;
    if (f & POS_SEAM)
        return KIND_SEAM;
    if (f & POS_JUNCTION)
        return KIND_JUNCTION;
    return f & POS_CREASE ? KIND_CREASE : KIND_MANIFOLD;
}

/* How the edge meets x, of kind `kind`, seam_x: its wedges differ at x. */
static int edge_kind(const simplifier *s, const plan *pl, int kind, int seam_x, uint32_t x, uint32_t y)
{
    if (pl->shared_count == 3)
        return EDGE_JUNCTION;
    if (pl->shared_count == 1)
        return EDGE_BORDER;
    if (seam_x)
        return EDGE_SEAM;
    if (kind == KIND_CREASE && feature_edge(s, pl->shared[0], pl->shared[1], x, y))
        return EDGE_FEATURE;
    return EDGE_INTERIOR;
}

/* Is x's wedge map defined? seam_y: the edge's triangles differ at the other end. */
static int map_ok(pos_flags fx, int seam_y) { return (fx & POS_SEAM) ? seam_y : !seam_y; }

/* Plans collapsing edge (a, b), given a's fan (live corners): the edge's triangles, which ends may go (the rule
 * above), where the vertex goes and at what cost (the quadric's, plus the attribute quadrics' of attributes.c). */
void plan_collapse(const simplifier *s, uint32_t a, uint32_t b, const u32vec *fan_a, plan *pl)
{
    memset(pl, 0, sizeof *pl);
    int n = 0;
    for (size_t i = 0; i < fan_a->count; ++i) {
        uint32_t c = fan_a->data[i];
        const uint32_t *v = s->tri[c / 3].v; /* a is one corner, so b is one of the others */
        if (v[0] == b || v[1] == b || v[2] == b) {
            if (n < 3)
                pl->shared[n] = c / 3;
            ++n;
        }
    }
    pl->shared_count = n;
    if (n == 0) {
        pl->block = BLOCK_STALE;
        return;
    }
    pos_flags fa = s->P[a].flags, fb = s->P[b].flags;
    /* An edge of three triangles goes only inside a junction line, and only where each end has one wedge on them
       (the wedge map below has one image) */
    if (n > 3 || (n == 3 && !((fa | fb) & POS_JUNCTION))) {
        pl->block = BLOCK_NONMANIFOLD;
        return;
    }
    int seam_a = 0, seam_b = 0;
    for (int k = 1; k < n; ++k) {
        seam_a |= TW(corner_at(s, pl->shared[0], a)) != TW(corner_at(s, pl->shared[k], a));
        seam_b |= TW(corner_at(s, pl->shared[0], b)) != TW(corner_at(s, pl->shared[k], b));
    }
    if (n == 3 && (seam_a || seam_b)) {
        pl->block = BLOCK_SEAM;
        return;
    }
    int kind_a = end_kind(fa), kind_b = end_kind(fb);
    int edge_a = edge_kind(s, pl, kind_a, seam_a, a, b), edge_b = edge_kind(s, pl, kind_b, seam_b, b, a);
    int reason_a = kHeld[kind_a][edge_a];
    int reason_b = kHeld[kind_b][edge_b];
    pl->a_removable = reason_a == BLOCK_NONE && map_ok(fa, seam_b);
    pl->b_removable = reason_b == BLOCK_NONE && map_ok(fb, seam_a);
    if (!pl->a_removable && !pl->b_removable) {
        int ra = reason_a != BLOCK_NONE ? reason_a : BLOCK_SEAM;
        int rb = reason_b != BLOCK_NONE ? reason_b : BLOCK_SEAM;
        pl->block = ra > rb ? ra : rb;
        return;
    }
    resurfi_quadric q = s->P[a].q;
    resurfi_quadric_add(&q, &s->P[b].q);
    vec3 pa = s->P[a].p, pb = s->P[b].p;
    int along_crease = edge_a == EDGE_FEATURE || edge_b == EDGE_FEATURE, along_junction = n == 3;
    int seam_edge = seam_a || seam_b || along_crease || along_junction;
    pl->feature = along_crease || along_junction ||
                  ((fa | fb) & (POS_CREASE | POS_CORNER | POS_TOUCHES_FEATURE | POS_JUNCTION)) != 0;
    if (pl->a_removable && pl->b_removable) {
        pl->p = free_placement(s, &q, pa, pb, seam_edge);
    } else if (pl->a_removable) {
        pl->pinned = reason_b != BLOCK_NONE;
        pl->p = pl->pinned ? pb : free_placement(s, &q, pa, pb, seam_edge);
    } else {
        pl->pinned = reason_a != BLOCK_NONE;
        pl->p = pl->pinned ? pa : free_placement(s, &q, pa, pb, seam_edge);
    }
    pl->curve = along_crease || n == 1 || ((fa | fb) & POS_CREASE) != 0;
    pl->attr_cost = attribute_cost(s, pl, a, b, pl->p);
    pl->cost = qeval(s, &q, pl->p) + pl->attr_cost;
}

static int push_fresh(const simplifier *s, lane *L, candidate c) { return simp_buf_append(s->alloc, &L->fresh, &c, 1); }

/* Plans the candidates of position a (fan given) to every neighbour except `except` and those flagged POS_RENEW
 * (which plan their own), for the next pass. Returns 0 when out of memory. */
static int push_edges(simplifier *s, lane *L, uint32_t a, const u32vec *fan, uint32_t except)
{
    uint32_t st = next_stamp(s, L);
    for (size_t i = 0; i < fan->count; ++i) {
        uint32_t xs[2];
        corner_others(s, fan->data[i], xs);
        for (int k = 0; k < 2; ++k) {
            uint32_t x = xs[k];
            if (L->mark[x] == st || x == except || (s->P[x].flags & POS_RENEW))
                continue;
            L->mark[x] = st;
            plan pl;
            plan_collapse(s, a, x, fan, &pl);
            if (pl.block != BLOCK_NONE) {
                count_blocks(&L->rep, pl.block, 1);
                continue;
            }
            candidate c = {scaled_cost(s, pl.cost), a, x, (s->gen[a] + s->gen[x]) & GEN};
            if (!push_fresh(s, L, c))
                return 0;
        }
    }
    return 1;
}

/* ---- the first candidates ------------------------------------------------------------------------------------ */

typedef struct seed_job {
    simplifier *s;
    scratch *scratch;
    const size_t *offset; /* per position: its slots in the list */
} seed_job;

static int seed_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    seed_job *j = ctx;
    simplifier *s = j->s;
    scratch *sc = &j->scratch[worker];
    for (size_t a = begin; a < end; ++a) {
        candidate *slot = s->queue.list.data + j->offset[a];
        size_t room = j->offset[a + 1] - j->offset[a], used = 0;
        if (!(s->P[a].flags & POS_DEAD)) {
            if (!gather_fan(s, (uint32_t)a, &sc->fan, 0))
                return 1;
            size_t n = fan_pairs(s, &sc->fan, sc);
            if (n == SIZE_MAX)
                return 1;
            for (size_t i = 0; i < n; ++i) {
                uint32_t b = sc->pairs[i].x;
                if (b <= a || (i > 0 && sc->pairs[i - 1].x == b))
                    continue;
                plan pl;
                plan_collapse(s, (uint32_t)a, b, &sc->fan, &pl);
                if (pl.block != BLOCK_NONE) {
                    sc->blocked[pl.block]++;
                    continue;
                }
                slot[used++] = (candidate){scaled_cost(s, pl.cost), (uint32_t)a, b, 0};
            }
        }
        for (; used < room; ++used)
            slot[used].a = NONE;
    }
    return 0;
}

/* The first list: each position's edges to the neighbours above it (P[].up of them, from analyse_position) in
 * its own slots. */
resurf_status seed_candidates(simplifier *s, scratch *scratch)
{
    size_t *offset = resurfi_alloc(s->alloc, s->pos_count + 1, sizeof *offset);
    if (!offset)
        return RESURF_ERR_OUT_OF_MEMORY;
    size_t total = 0;
    for (size_t p = 0; p < s->pos_count; ++p) {
        offset[p] = total;
        total += s->P[p].flags & POS_DEAD ? 0 : s->P[p].up;
    }
    offset[s->pos_count] = total;
    if (!simp_queue_reserve(&s->queue, total)) {
        resurfi_free(s->alloc, offset);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    seed_job job = {s, scratch, offset};
    if (resurfi_pool_for(s->pool, s->pos_count, BLOCK_POSITIONS, seed_block, &job)) {
        resurfi_free(s->alloc, offset);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    resurfi_free(s->alloc, offset);
    for (unsigned w = 0; w < s->threads; ++w)
        for (int reason = 0; reason < BLOCK_REASONS; ++reason)
            count_blocks(&s->rep, reason, scratch[w].blocked[reason]);
    simp_queue_seed(&s->queue, total);
    return RESURF_OK;
}

/* ---- applying one collapse ----------------------------------------------------------------------------------- */

/* Removes `gone` into `keep` at p, with the wedge map read from the edge's triangles. fan_keep and fan_gone are
 * the ends' fans before the collapse; L->fan_c receives keep's fan after it, L->touched the neighbours whose
 * flags must be recomputed (seam positions next to the edge) or whose blocked candidates are worth another try.
 * *refresh_keep is set when keep's flags must be recomputed from its fan. */
static int apply_collapse(simplifier *s, lane *L, uint32_t keep, uint32_t gone, vec3 p, const plan *pl,
                          const u32vec *fan_keep, const u32vec *fan_gone, int *refresh_keep)
{
    uint32_t from[3], to[3];
    int maps = pl->shared_count;
    for (int k = 0; k < maps; ++k) {
        from[k] = TW(corner_at(s, pl->shared[k], gone));
        to[k] = TW(corner_at(s, pl->shared[k], keep));
    }
    uint32_t opposite[3] = {NONE, NONE, NONE};
    for (int k = 0; k < maps; ++k) {
        uint32_t t = pl->shared[k];
        for (int i = 0; i < 3; ++i)
            if (TV(3 * t + i) != keep && TV(3 * t + i) != gone)
                opposite[k] = TV(3 * t + i);
        check_corner_write(s, L, 3 * t, keep, gone);
        s->tri[t].dead = 1;
        L->dead_tris += 1 + (s->mirror && s->mirror[s->src[t]] != NONE); /* a sheet's mirror goes with it */
    }
    for (int k = 0; k < maps; ++k) /* each wedge of gone into its image (once: the maps may be the same) */
        if (k == 0 || (from[k] != from[0] && (k == 1 || from[k] != from[1]))) {
            attribute_merge(s, to[k], from[k]);
            if (s->wedge_root)
                s->wedge_root[from[k]] = to[k];
        }
    /* Re-label gone's live corners. keep's list becomes its fan after the collapse, gone's live corners first
     * (the order of splicing gone's list in front of keep's), without the dead corners either list held. */
    L->fan_c.count = 0;
    const u32vec *fans[2] = {fan_gone, fan_keep};
    for (int side = 0; side < 2; ++side)
        for (size_t i = 0; i < fans[side]->count; ++i) {
            uint32_t c = fans[side]->data[i];
            if (s->tri[c / 3].dead)
                continue;
            check_corner_write(s, L, c, keep, gone);
            if (side == 0) {
                TV(c) = keep;
                uint32_t w = TW(c);
                TW(c) = maps == 1 || w == from[0] ? to[0] : w == from[1] ? to[1] : to[0];
            }
            if (!vec_push(s->alloc, &L->fan_c, c))
                return 0;
        }
    for (size_t i = 0; i < L->fan_c.count; ++i)
        TNEXT(L->fan_c.data[i]) = i + 1 < L->fan_c.count ? L->fan_c.data[i + 1] : NONE;
    check_position_write(s, L, keep);
    check_position_write(s, L, gone);
    s->P[keep].head = L->fan_c.count ? L->fan_c.data[0] : NONE;
    s->P[gone].head = NONE;
    s->P[keep].p = p;
    resurfi_quadric_add(&s->P[keep].q, &s->P[gone].q);
    /* Only wedges can change a position's flags here: the link condition keeps the mesh a manifold, a border vertex
     * goes only along its border (so keep was or becomes a border vertex) and the opposite corners keep their
     * border edges. Seam positions are analysed again. */
    pos_flags fk = s->P[keep].flags, fg = s->P[gone].flags;
    *refresh_keep = ((fk | fg) & (POS_SEAM | POS_COMPLEX)) != 0 || (fg & POS_CREASE); /* keep may join a crease */
    s->P[keep].flags = (pos_flags)(fk | (fg & (POS_BORDER | POS_TOUCHES_FEATURE)));
    s->P[gone].flags = POS_DEAD;
    bump_gen(s, keep);
    bump_gen(s, gone);
    L->dead_positions++;

    /* Flags that may have changed: keep's, and the opposite corners' (they lost a triangle). A changed flag changes
     * that position's candidates: it is planned again, like a blocked neighbour. */
    L->touched.count = 0;
    uint32_t st = next_stamp(s, L);
    for (size_t i = 0; i < L->fan_c.count; ++i) {
        uint32_t xs[2];
        corner_others(s, L->fan_c.data[i], xs);
        for (int k = 0; k < 2; ++k) {
            uint32_t x = xs[k];
            if (L->mark[x] == st)
                continue;
            L->mark[x] = st;
            int again = (s->P[x].flags & POS_BLOCKED) != 0;
            if ((x == opposite[0] || x == opposite[1] || x == opposite[2]) &&
                (s->P[x].flags & (POS_SEAM | POS_COMPLEX)))
                again = 1;
            if (again && !vec_push(s->alloc, &L->touched, x))
                return 0;
        }
    }
    return 1;
}

/* Recomputes the flags of `v` (static locks are kept). Returns 0 when out of memory, else 1; *changed is set when
 * the flags differ. */
static int refresh_flags(simplifier *s, lane *L, uint32_t v, scratch *sc, int *changed)
{
    check_position_write(s, L, v);
    pos_flags f;
    if (!analyse_position(s, v, sc, &f, NULL, NULL))
        return 0;
    pos_flags old = s->P[v].flags;
    pos_flags keep =
        old & (POS_LOCKED | POS_LOCKED_BORDER | POS_CORNER | POS_TOUCHES_FEATURE | POS_BLOCKED | POS_RELEASED);
    /* lock_border freezes the input's borders only: a border created later (none: collapses keep borders) would
     * otherwise be locked as well. */
    f = (pos_flags)((f & ~POS_LOCKED_BORDER) | keep);
    if (f & POS_RELEASED)
        f &= (pos_flags)~POS_CORNER;
    s->P[v].flags = f;
    *changed = (f & ~POS_BLOCKED) != (old & ~POS_BLOCKED);
    return 1;
}

/* Plans the edges of renewed neighbour x (flagged POS_RENEW) again, except the one to `keep`: its flags changed
 * or a blocked candidate of it deserves another try. Clears its flag. Returns 0 when out of memory. */
int plan_renewed(simplifier *s, lane *L, uint32_t x, uint32_t keep)
{
    s->P[x].flags &= (pos_flags)~POS_RENEW;
    return gather_fan(s, x, &L->fan_b, 1) && push_edges(s, L, x, &L->fan_b, keep);
}

/* ---- trying one candidate ------------------------------------------------------------------------------------ */

/* The ends' fans of pending q's candidate (a, b) into *fa, *fb: gathered with the chunk's stars when applied in
 * parallel (nothing in the star changed since), else the lane's two fans, gathered together. 0 when out of
 * memory. */
static int candidate_fans(simplifier *s, const pending *q, lane *L, uint32_t a, uint32_t b, int defer, u32vec *view,
                          const u32vec **fa, const u32vec **fb)
{
    if (defer && q->fans) {
        view[0] = (u32vec){q->fans, q->na, q->na};
        view[1] = (u32vec){q->fans + q->na, q->nb, q->nb};
        *fa = &view[0];
        *fb = &view[1];
        return 1;
    }
    u32vec pair[2] = {L->fan_a, L->fan_b};
    uint32_t ends[2] = {a, b};
    int ok = gather_fans(s, ends, 2, pair, 1);
    L->fan_a = pair[0];
    L->fan_b = pair[1];
    *fa = &L->fan_a;
    *fb = &L->fan_b;
    return ok;
}

/* The vertex's place: the plan's, restored onto S with inline restoration (from pending q when it was restored
 * ahead of the same placement); along a crease or border, onto M's curve there (*at: its vertex of M next to it),
 * never across it. */
static vec3 restored_place(const simplifier *s, const pending *q, uint32_t a, uint32_t b, const plan *pl,
                           int *restored, int *left, uint32_t *home, uint32_t *at)
{
    *restored = *left = 0;
    *home = *at = NONE;
    if (s->opt.restore != RESURF_RESTORE_INLINE || !s->restorer || pl->pinned)
        return pl->p;
    vec3 on;
    if (pl->curve && curve_place(s, a, b, pl->p, &on, at))
        return on;
    if (pl->feature)
        return pl->p;
    *restored = 1;
    if (q->restore && v3_dist2(q->p, pl->p) == 0) {
        *left = q->left;
        *home = q->home;
        return q->restored;
    }
    return restore_point(s, pl->p, v3_dist(s->P[a].p, s->P[b].p), s->home[a], left, home);
}

/* After collapsing into keep: keep's flags and the touched neighbours' (apply_collapse) brought up to date; the
 * neighbours whose flags changed or that were blocked go stale and are left at the front of L->touched, their
 * count returned (SIZE_MAX when out of memory). */
static size_t renew_neighbours(simplifier *s, lane *L, scratch *sc, uint32_t keep, int refresh_keep)
{
    int changed = 0;
    if (refresh_keep && !refresh_flags(s, L, keep, sc, &changed))
        return SIZE_MAX;
    size_t renew = 0;
    for (size_t i = 0; i < L->touched.count; ++i) {
        uint32_t x = L->touched.data[i];
        changed = 0;
        if ((s->P[x].flags & (POS_SEAM | POS_COMPLEX)) && !refresh_flags(s, L, x, sc, &changed))
            return SIZE_MAX;
        if (changed || (s->P[x].flags & POS_BLOCKED)) {
            check_position_write(s, L, x);
            s->P[x].flags &= (pos_flags)~POS_BLOCKED;
            bump_gen(s, x);
            L->touched.data[renew++] = x;
        }
    }
    return renew;
}

/* A guard refused the collapse of (a, b): both ends wait for their neighbourhood to change. */
static void block_ends(simplifier *s, lane *L, uint32_t a, uint32_t b)
{
    check_position_write(s, L, a);
    check_position_write(s, L, b);
    s->P[a].flags |= POS_BLOCKED;
    s->P[b].flags |= POS_BLOCKED;
}

/* A collapse's place within this fraction of its edge's length of every plane of M it merged (rms, by the
 * quadric) lies on M: it is not restored. Flat content gives exact zeros; a smooth surface's places are off by about
 * the edge length times its curvature there, far above it (the analytic and scanned meshes' outputs are unchanged
 * byte for byte). */
static const double EXACT_PLACE = 1e-9;

/* Tries the candidate of pending q: planned again on the current mesh, checked, restored, applied. A candidate
 * that is done or refused leaves the list; one whose cost went up, or that the tip guard defers, goes back in with
 * its new cost. New candidates, counters and scratch go to lane L. With `defer` (a chunk applied in parallel) the
 * neighbours to plan again are left in L->renew for after the chunk (their edges reach beyond the star); q->keep
 * receives the surviving end. Returns 0 when out of memory. */
int try_candidate(simplifier *s, pending *q, lane *L, scratch *sc, int defer)
{
    resurf_simplify_report *r = &L->rep;
    candidate *entry = &s->queue.list.data[q->index];
    candidate e = *entry;
    uint32_t a = e.a, b = e.b;
    entry->a = NONE;
    if (!candidate_current(s, e))
        return 1; /* an earlier collapse changed an end's flags: planned again */
    u32vec view[2];
    const u32vec *fa, *fb;
    if (!candidate_fans(s, q, L, a, b, defer, view, &fa, &fb))
        return 0;
    prefetch_ring(s, L, fa);
    prefetch_ring(s, L, fb);
    plan pl;
    plan_collapse(s, a, b, fa, &pl);
    if (pl.block != BLOCK_NONE) {
        count_blocks(r, pl.block, 1);
        return 1;
    }
    float now = scaled_cost(s, pl.cost);
    if (now > e.cost * 1.000001f + FLT_MIN)
        return push_fresh(s, L, (candidate){now, a, b, e.stamp});
    if (!link_ok(s, L, fa, fb, a, b, &pl)) {
        r->blocked_link++;
        block_ends(s, L, a, b);
        return 1;
    }
    /* Restored before the error and geometry checks: they judge the position the vertex will have. */
    resurfi_quadric qab = s->P[a].q;
    resurfi_quadric_add(&qab, &s->P[b].q);
    int restored, left;
    uint32_t home, at;
    vec3 p = restored_place(s, q, a, b, &pl, &restored, &left, &home, &at);
    /* The quadric's place is kept where it lies on every plane of M it merged (M is there, S is not needed) or
     * where it covers M better than the restored one (the reach gate, guards.c). */
    if (restored && !left &&
        ((qab.w > 0 && qeval(s, &qab, pl.p) <= EXACT_PLACE * EXACT_PLACE * v3_dist2(s->P[a].p, s->P[b].p) * qab.w) ||
         !restore_keeps_reach(s, fa, fb, a, b, &pl, p, home))) {
        p = pl.p;
        left = 1;
        home = NONE;
    }
    double err = qab.w > 0 ? sqrt(qeval(s, &qab, p) / qab.w) : 0;
    if (err > s->max_error) {
        r->skipped_error++;
        L->skipped_error = 1;
        return 1;
    }
    int g = geometry_ok(s, fa, fb, a, b, p, &pl);
    if (g == GEOMETRY_FLIP && !pl.pinned && pl.feature) {
        /* The free place folds a triangle: try the better end that does not (an end is already on S). Without this
         * the edge waits, and on a CAD part whose creases and seams hold most positions the few collapses left
         * late in a run are the costly ones: 2CylinderEngine's plate with a bolt hole closed the hole by a
         * diameter at 25% (its Hausdorff 0.093 of the part's diagonal; gltfpack 0.035). */
        vec3 ends[2] = {s->P[a].p, s->P[b].p};
        int first = qeval(s, &qab, ends[1]) < qeval(s, &qab, ends[0]);
        for (int k = 0; k < 2 && g == GEOMETRY_FLIP; ++k) {
            vec3 e2 = ends[first ^ k];
            if (v3_dist2(e2, p) == 0 || geometry_ok(s, fa, fb, a, b, e2, &pl) != GEOMETRY_OK)
                continue;
            double e2_err = qab.w > 0 ? sqrt(qeval(s, &qab, e2) / qab.w) : 0;
            if (e2_err > s->max_error)
                continue;
            pl.p = p = e2;
            pl.attr_cost = attribute_cost(s, &pl, a, b, p);
            pl.cost = qeval(s, &qab, p) + pl.attr_cost;
            float moved = scaled_cost(s, pl.cost);
            if (moved > e.cost * 1.000001f + FLT_MIN) /* costlier than its place in the list: wait for its turn */
                return push_fresh(s, L, (candidate){moved, a, b, e.stamp});
            err = e2_err;
            restored = left = 0;
            home = NONE;
            at = s->curve_at ? s->curve_at[first ^ k ? b : a] : NONE;
            g = GEOMETRY_OK;
        }
    }
    if (g != GEOMETRY_OK) {
        if (g == GEOMETRY_FLIP)
            r->blocked_flip++;
        else
            r->blocked_min_angle++;
        block_ends(s, L, a, b);
        return 1;
    }
    /* The tip guard defers rather than refuses: such a collapse goes back into the list at its penalised cost (and
     * is done when its turn comes again), so targets stay reachable. */
    uint32_t near = home != NONE ? home : s->home ? s->home[a] : NONE; /* a triangle of M near p */
    double excess = distance_excess(s, L, fa, fb, a, b, p, &pl, err, near);
    if (excess > 0) {
        float priced = scaled_cost(s, qeval(s, &qab, p) + pl.attr_cost + excess_penalty(&qab, excess));
        if (e.cost < priced * 0.999999f) {
            r->blocked_distance++;
            return push_fresh(s, L, (candidate){priced, a, b, e.stamp});
        }
    }
    /* Which end survives: the one that must (held in place or not removable), else the one with more triangles
     * (fewer corners to relabel), else the lower id. */
    uint32_t keep, gone;
    if (!pl.a_removable)
        keep = a, gone = b;
    else if (!pl.b_removable)
        keep = b, gone = a;
    else if (fb->count > fa->count)
        keep = b, gone = a;
    else
        keep = a, gone = b;
    r->restored += (size_t)restored;
    r->restore_left += (size_t)left;
    if (err > r->max_error_estimate)
        r->max_error_estimate = err;
    r->collapses++;
    s->P[keep].flags &= (pos_flags)~POS_BLOCKED;
    int refresh_keep;
    if (!apply_collapse(s, L, keep, gone, p, &pl, keep == a ? fa : fb, keep == a ? fb : fa, &refresh_keep))
        return 0;
    q->keep = keep;
    size_t renew = renew_neighbours(s, L, sc, keep, refresh_keep);
    if (renew == SIZE_MAX)
        return 0;
    if (home != NONE)
        s->home[keep] = home;
    if (at != NONE)
        s->curve_at[keep] = at;
    /* Planned now, while their fans are in the cache. keep's candidates first (they reach every neighbour), then
     * those of renewed neighbours to the rest; each edge between two renewed neighbours is planned by the later
     * one. */
    if (!push_edges(s, L, keep, &L->fan_c, NONE))
        return 0;
    if (defer) {
        for (size_t i = 0; i < renew; ++i)
            if (!vec_push(s->alloc, &L->renew, L->touched.data[i]))
                return 0;
        return 1;
    }
    for (size_t i = 0; i < renew; ++i)
        s->P[L->touched.data[i]].flags |= POS_RENEW;
    for (size_t i = 0; i < renew; ++i)
        if (!plan_renewed(s, L, L->touched.data[i], keep))
            return 0;
    return 1;
}

/* ---- the pass loop ------------------------------------------------------------------------------------------- */

/* A corner is released once the level's error (the largest collapse error so far) reaches this many times its
 * feature's size (corners_start in curves.c), or, when nothing else can be collapsed, once its feature is a detail:
 * at most DETAIL of the diagonal. */
static const double CORNER_RELEASE = 0.25, DETAIL = 0.02;

/* Between passes: the corners of features up to size `reached` are held no more, and their edges are planned for
 * the next pass. Returns 0 when out of memory. */
static int release_corners(simplifier *s, double reached)
{
    lane *L = &s->sched.lanes[0];
    for (; s->release_next < s->release_count && s->release[s->release_next].size <= reached; ++s->release_next) {
        uint32_t x = s->release[s->release_next].position;
        if ((s->P[x].flags & (POS_DEAD | POS_CORNER)) != POS_CORNER)
            continue;
        s->P[x].flags = (pos_flags)((s->P[x].flags & ~(POS_CORNER | POS_BLOCKED)) | POS_RELEASED);
        bump_gen(s, x);
        if (!gather_fan(s, x, &L->fan_b, 1) || !push_edges(s, L, x, &L->fan_b, NONE))
            return 0;
    }
    return merge_lane(s, L);
}

/* Reports the progress towards target (from start triangles); 1 when the caller cancelled. */
static int progress_cancelled(simplifier *s, size_t start, size_t target)
{
    double done = start > target ? (double)(start - s->alive_tris) / (double)(start - target) : 1;
    return resurfi_progress(&s->opt.progress, RESURF_STAGE_SIMPLIFY, done);
}

/* Collapses until at most `target` triangles are left or nothing can be collapsed.
 *
 * The priority queue is a sorted array with lazy invalidation (generation stamps, queue.h), taken in passes: a
 * pass takes the candidates in cost order up to a cost limit, each only if neither end was taken by an earlier one
 * of the same pass. A collapse changes only its ends' quadrics, so every other candidate's cost stays exact
 * through the pass and the order is the greedy one among independent collapses. The new candidates of a collapse
 * are planned at once and wait for the next pass. A pass is taken in chunks (schedule.c): applied on all threads
 * when their stars are disjoint and the chunk stays above the target, else one collapse after the other.
 * Nothing depends on the target but where the work stops: a pass interrupted at one level goes on at the next, so
 * a LOD chain's level is the mesh a single call to its target makes. */
resurf_status collapse_until(simplifier *s, size_t target, scratch *sc, resurf_error *error)
{
    size_t start = s->alive_tris;
    resurf_simplify_report *r = &s->rep;
    r->stop = RESURF_STOP_TARGET;
    s->skipped_error = 0;
    schedule *sched = &s->sched;
    while (s->alive_tris > target) {
        if (sched->pend_next < sched->pend_count) { /* the chunk's next collapse, alone */
            if (!apply_next_alone(s, sc))
                goto oom;
            if (sched->pend_next == sched->pend_count && progress_cancelled(s, start, target))
                goto cancelled;
            continue;
        }
        if (!sched->pass_open) { /* the next pass, if any candidate is left */
            if (!release_corners(s, s->rep.max_error_estimate / CORNER_RELEASE) || !open_pass(s))
                goto oom;
            /* none: the corners of the smallest details left, one size at a time, until some collapse can go on */
            while (!sched->pass_open && s->release_next < s->release_count &&
                   s->release[s->release_next].size <= DETAIL * s->diagonal)
                if (!release_corners(s, s->release[s->release_next].size) || !open_pass(s))
                    goto oom;
            if (!sched->pass_open) {
                r->stop = s->skipped_error ? RESURF_STOP_ERROR : RESURF_STOP_BLOCKED;
                break;
            }
        }
        if (!take_chunk(s, sc)) /* the pass's next chunk */
            goto oom;
        if (chunk_in_parallel(s, target)) { /* applied on all threads at once */
            if (!apply_chunk_parallel(s, sc))
                goto oom;
            if (progress_cancelled(s, start, target))
                goto cancelled;
            continue;
        }
        if (!restore_chunk_ahead(s, sc)) /* else alone, from the next iteration on */
            goto oom;
    }
    return RESURF_OK;
oom:
    return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory while simplifying");
cancelled:
    return resurfi_error(error, RESURF_ERR_CANCELLED, "simplification cancelled");
}
