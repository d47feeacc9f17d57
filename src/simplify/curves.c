/* M's feature curves: the polylines of its crease, normal-seam, material-border and mesh-border edges, kept from the
 * start so that a vertex made by a collapse along such a curve is put back on it rather than left on the chord
 * between the two ends (docs/restoring.md §8, "Features: along the curve"). The 1-D analogue of the restoration:
 * the curve's tangents at M's polyline vertices (from their neighbours) and a cubic between them, whose bulge over
 * a chord is the curve's sag h²κ/8; a straight polyline has tangents along itself, and the cubic is the chord.
 * The same curves give each corner of creases its feature's size, below which it gives way (corners_start). */
#include <math.h>
#include <stdlib.h>

#include "simplify_internal.h"
#include "../union_find.h"

/* Steps walked along the curve from one end's vertex of M looking for the other's, each way. Where the surface is
 * decimated evenly by a ratio r, an edge of S spans about 1/√r edges of M (7 at 2%; the capped cylinder's rims keep
 * about 45 of their 152 vertices each there, 3 or 4 edges apart); 256 leaves room for curves decimated far more
 * than the surface around them. Ends farther apart keep the old rule. */
enum { CURVE_WALK = 256 };

/* The largest move onto the curve, as a fraction of the collapsed edge's length L: a curve bending by κ lies off the
 * chord by at most L²κ/8, so this allows a turn of Lκ = 0.4 (23°) over the edge. A larger move is no sag but a
 * different part of the curve (the ends of a short cut across a small hole's cap, a crease that folds back), and
 * the vertex keeps the quadric's place. Measured on 2CylinderEngine (bench-assets, Hausdorff / mean over gltfpack's,
 * geometric means of its two copies, 25% and 10%): without the bound 2.42 / 0.97 and 1.72 / 1.35, with 0.25 2.43 /
 * 0.97 and 1.72 / 1.35, with 0.05 2.17 / 1.00 and 1.52 / 1.39 (parent 2.37 / 1.13 and 1.47 / 1.50); the capped
 * cylinders do no worse with it (docs/restoring.md §8). */
static const double CURVE_MOVE = 0.05;

/* position a's neighbours along its curve, from its fan: the other ends of its feature edges (a crease), or of its
 * border edges (a border). Returns their count (up to 3: more is a corner). */
static int curve_neighbours(simplifier *s, uint32_t a, scratch *sc, uint32_t nb[3])
{
    if (!gather_fan(s, a, &sc->fan, 0))
        return -1;
    size_t n = fan_pairs(s, &sc->fan, sc);
    if (n == SIZE_MAX)
        return -1;
    int border = (s->P[a].flags & POS_BORDER) != 0, count = 0, groups = 0;
    uint32_t group_nb[3];
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && sc->pairs[j].x == sc->pairs[i].x)
            ++j;
        uint32_t x = sc->pairs[i].x;
        int on = 0;
        if (border) {
            on = j - i == 1;
        } else if (j - i == 2) {
            uint32_t ti = sc->fan.data[sc->pairs[i].slot / 2] / 3, tj = sc->fan.data[sc->pairs[i + 1].slot / 2] / 3;
            on = feature_edge(s, ti, tj, a, x);
            if (group_border(s, ti, tj) && groups < 3)
                group_nb[groups++] = x;
        }
        if (on && count < 3)
            nb[count++] = x;
        i = j;
    }
    if (!border && count != 2 && groups == 2) { /* a rough fan: only its material border counts (analyse_position) */
        nb[0] = group_nb[0], nb[1] = group_nb[1];
        count = 2;
    }
    return count;
}

resurf_status curves_start(simplifier *s, scratch *sc)
{
    s->curve_nb = resurfi_alloc(s->alloc, 2 * s->pos_count, sizeof *s->curve_nb);
    s->curve_at = resurfi_alloc(s->alloc, s->pos_count, sizeof *s->curve_at);
    s->curve_p = resurfi_alloc(s->alloc, s->pos_count, sizeof *s->curve_p);
    if (!s->curve_nb || !s->curve_at || !s->curve_p)
        return RESURF_ERR_OUT_OF_MEMORY;
    for (size_t p = 0; p < s->pos_count; ++p) {
        pos_flags f = s->P[p].flags;
        s->curve_p[p] = s->P[p].p;
        s->curve_nb[2 * p] = s->curve_nb[2 * p + 1] = NONE;
        s->curve_at[p] = NONE;
        if ((f & POS_DEAD) || !(f & (POS_CREASE | POS_BORDER | POS_CORNER)))
            continue;
        s->curve_at[p] = (uint32_t)p;
        if (f & (POS_CORNER | POS_LOCKED))
            continue; /* a corner ends every curve through it: it has no neighbours to walk on to */
        uint32_t nb[3];
        int count = curve_neighbours(s, (uint32_t)p, sc, nb);
        if (count < 0)
            return RESURF_ERR_OUT_OF_MEMORY;
        if (count == 2) {
            s->curve_nb[2 * p] = nb[0];
            s->curve_nb[2 * p + 1] = nb[1];
        }
    }
    return RESURF_OK;
}

void curves_free(simplifier *s)
{
    resurfi_free(s->alloc, s->curve_nb);
    resurfi_free(s->alloc, s->curve_at);
    resurfi_free(s->alloc, s->curve_p);
    resurfi_free(s->alloc, s->release);
}

/* ---- corners of small features ------------------------------------------------------------------------------- */

/* The length of the feature curve from corner c through its neighbour n to the next corner or end (at most
 * CURVE_WALK edges); -1 when out of memory. */
static double run_length(simplifier *s, scratch *sc, uint32_t c, uint32_t n)
{
    double len = v3_dist(s->P[c].p, s->P[n].p);
    uint32_t prev = c, cur = n;
    for (int step = 0; step < CURVE_WALK; ++step) {
        pos_flags f = s->P[cur].flags;
        if ((f & (POS_CORNER | POS_LOCKED)) || !(f & POS_CREASE))
            break;
        uint32_t nb[3];
        int count = curve_neighbours(s, cur, sc, nb);
        if (count < 0)
            return -1;
        uint32_t next = count != 2 ? NONE : nb[0] == prev ? nb[1] : nb[1] == prev ? nb[0] : NONE;
        if (next == NONE)
            break;
        len += v3_dist(s->P[cur].p, s->P[next].p);
        prev = cur, cur = next;
    }
    return len;
}

static int release_order(const void *a, const void *b)
{
    const corner_release *x = a, *y = b;
    if (x->size != y->size)
        return x->size < y->size ? -1 : 1;
    return x->position < y->position ? -1 : x->position > y->position;
}

/* A corner that may be released: where creases meet, or where a border turns (its feature: the whole part). */
static int releasable(pos_flags f) { return (f & (POS_CORNER | POS_LOCKED | POS_DEAD)) == POS_CORNER; }

/* Per position, the diagonal of the bounding box of its connected part of the working mesh (what a border corner
 * holds: a hair card, a rivet's open cap, a small panel), or NULL when out of memory. */
static double *part_sizes(simplifier *s)
{
    size_t pc = s->pos_count;
    uint32_t *root = resurfi_alloc(s->alloc, pc + 1, sizeof *root);
    double *box = resurfi_alloc(s->alloc, 6 * pc + 1, sizeof *box), *size = resurfi_alloc(s->alloc, pc + 1, sizeof *size);
    if (!root || !box || !size) {
        resurfi_free(s->alloc, root), resurfi_free(s->alloc, box), resurfi_free(s->alloc, size);
        return NULL;
    }
    for (size_t p = 0; p < pc; ++p)
        root[p] = (uint32_t)p;
    for (size_t t = 0; t < s->tri_count; ++t) {
        resurfi_uf_union(root, TV(3 * t), TV(3 * t + 1));
        resurfi_uf_union(root, TV(3 * t), TV(3 * t + 2));
    }
    for (size_t p = 0; p < pc; ++p)
        for (int k = 0; k < 3; ++k)
            box[6 * p + k] = INFINITY, box[6 * p + 3 + k] = -INFINITY;
    for (size_t p = 0; p < pc; ++p) {
        if (s->P[p].flags & POS_DEAD)
            continue;
        double *b = box + 6 * (size_t)resurfi_uf_find(root, (uint32_t)p), q[3] = {s->P[p].p.x, s->P[p].p.y, s->P[p].p.z};
        for (int k = 0; k < 3; ++k)
            b[k] = fmin(b[k], q[k]), b[3 + k] = fmax(b[3 + k], q[k]);
    }
    for (size_t p = 0; p < pc; ++p) {
        const double *b = box + 6 * (size_t)resurfi_uf_find(root, (uint32_t)p);
        size[p] = sqrt((b[3] - b[0]) * (b[3] - b[0]) + (b[4] - b[1]) * (b[4] - b[1]) + (b[5] - b[2]) * (b[5] - b[2]));
    }
    resurfi_free(s->alloc, root);
    resurfi_free(s->alloc, box);
    return size;
}

/* The corners that may give way, each with the size of its feature: where crease curves meet, the longest of its
 * curves to the next corner or end; where a border turns, the diagonal of its part (a tail's tuft of 44 hair cards,
 * 4 to 8 triangles each, held every corner and took 200 of the 372 triangles of XGL_Wuson's 10% level). Once the
 * level's error is no longer small against that size, holding a detail the error has reached keeps triangles the
 * rest of the surface needs (a hard-surface model's greebles: docs/restoring.md §8), and the corner is left to the
 * quadric, whose planes through it price its move (collapse.c, release_corners). A border corner of a large part
 * never gets there: its part's size is the level's scale. */
resurf_status corners_start(simplifier *s, scratch *sc)
{
    size_t count = 0, borders = 0;
    for (size_t p = 0; p < s->pos_count; ++p) {
        count += releasable(s->P[p].flags);
        borders += releasable(s->P[p].flags) && (s->P[p].flags & POS_BORDER);
    }
    if (!count)
        return RESURF_OK;
    double *part = borders ? part_sizes(s) : NULL;
    if (!(s->release = resurfi_alloc(s->alloc, count, sizeof *s->release)) || (borders && !part)) {
        resurfi_free(s->alloc, part);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    for (size_t p = 0; p < s->pos_count; ++p) {
        if (!releasable(s->P[p].flags))
            continue;
        if (s->P[p].flags & POS_BORDER) {
            s->release[s->release_count++] = (corner_release){part[p], (uint32_t)p};
            continue;
        }
        uint32_t nb[3];
        int n = curve_neighbours(s, (uint32_t)p, sc, nb);
        double size = 0;
        for (int k = 0; k < n && size >= 0; ++k) {
            double len = run_length(s, sc, (uint32_t)p, nb[k]);
            size = len < 0 || len > size ? len : size;
        }
        if (n < 0 || size < 0) {
            resurfi_free(s->alloc, part);
            return RESURF_ERR_OUT_OF_MEMORY;
        }
        if (n > 0)
            s->release[s->release_count++] = (corner_release){size, (uint32_t)p};
    }
    resurfi_free(s->alloc, part);
    qsort(s->release, s->release_count, sizeof *s->release, release_order);
    return RESURF_OK;
}

/* The next vertex along the curve after cur, coming from prev (NONE where the curve ends at cur). */
static uint32_t curve_next(const simplifier *s, uint32_t cur, uint32_t prev)
{
    uint32_t n0 = s->curve_nb[2 * (size_t)cur], n1 = s->curve_nb[2 * (size_t)cur + 1];
    return n0 == prev ? n1 : n1 == prev ? n0 : NONE;
}

/* The curve's unit tangent at M's vertex v, oriented along d: that of the circle through v and its two neighbours
 * (exact on a circle however unevenly it is sampled; along the polyline where v ends it). */
static vec3 curve_tangent(const simplifier *s, uint32_t v, vec3 d)
{
    uint32_t n0 = s->curve_nb[2 * (size_t)v], n1 = s->curve_nb[2 * (size_t)v + 1];
    if (n0 == NONE || n1 == NONE)
        return v3_normalize(d);
    vec3 in = v3_sub(s->curve_p[v], s->curve_p[n0]), out = v3_sub(s->curve_p[n1], s->curve_p[v]);
    vec3 t = v3_normalize(v3_add(v3_scale(in, v3_len2(out)), v3_scale(out, v3_len2(in))));
    return v3_dot(t, d) < 0 ? v3_scale(t, -1) : t;
}

int curve_place(const simplifier *s, uint32_t a, uint32_t b, vec3 p, vec3 *out, uint32_t *out_at)
{
    if (!s->curve_at)
        return 0;
    uint32_t ia = s->curve_at[a], ib = s->curve_at[b];
    if (ia == NONE && ib == NONE)
        return 0;
    ia = ia == NONE ? ib : ia; /* an end off every curve: the collapse is across, the other end's curve near it */
    ib = ib == NONE ? ia : ib;
    /* The curve between the ends' vertices, the shorter way, with one more edge past each (an end may lie on it). */
    uint32_t path[CURVE_WALK + 4], walk[CURVE_WALK + 2];
    size_t len = 0;
    if (ia == ib) {
        path[len++] = ia;
    } else {
        for (int way = 0; way < 2; ++way) {
            uint32_t prev = ia, cur = s->curve_nb[2 * (size_t)ia + (size_t)way];
            size_t n = 0;
            walk[n++] = ia;
            while (cur != NONE && cur != ia && cur != ib && n < CURVE_WALK) {
                walk[n++] = cur;
                uint32_t next = curve_next(s, cur, prev);
                prev = cur, cur = next;
            }
            if (cur == ib && (len == 0 || n + 1 < len)) {
                walk[n++] = ib;
                memcpy(path, walk, n * sizeof *walk);
                len = n;
            }
        }
        if (len == 0)
            return 0;
    }
    /* extend by an edge past each end */
    uint32_t before = len > 1 ? curve_next(s, path[0], path[1]) : s->curve_nb[2 * (size_t)path[0]];
    uint32_t after = len > 1 ? curve_next(s, path[len - 1], path[len - 2]) : s->curve_nb[2 * (size_t)path[0] + 1];
    if (before != NONE && before != path[len - 1]) {
        memmove(path + 1, path, len * sizeof *path);
        path[0] = before;
        ++len;
    }
    if (after != NONE && after != path[0])
        path[len++] = after;
    if (len < 2)
        return 0;
    double best = INFINITY, best_t = 0;
    size_t best_i = 0;
    for (size_t i = 0; i + 1 < len; ++i) {
        vec3 u = s->curve_p[path[i]], d = v3_sub(s->curve_p[path[i + 1]], u);
        double dd = v3_len2(d);
        double t = dd > 0 ? v3_dot(v3_sub(p, u), d) / dd : 0;
        t = t < 0 ? 0 : t > 1 ? 1 : t;
        double e = v3_dist2(p, v3_add(u, v3_scale(d, t)));
        if (e < best)
            best = e, best_t = t, best_i = i;
    }
    uint32_t u = path[best_i], w = path[best_i + 1];
    vec3 pu = s->curve_p[u], d = v3_sub(s->curve_p[w], pu);
    double t = best_t;
    vec3 q = v3_add(pu, v3_scale(d, t));
    /* The cubic with the tangents at u and w, each of the chord's length, over the chord's point of the same
     * parameter: H(t) − lerp(t) = h10 (m_u − d) + h11 (m_w − d). Exactly zero in every coordinate that is constant along
     * the polyline (an axis-aligned box's crease keeps its face planes bit for bit). */
    double len_d = v3_len(d);
    vec3 mu = v3_sub(v3_scale(curve_tangent(s, u, d), len_d), d);
    vec3 mw = v3_sub(v3_scale(curve_tangent(s, w, d), len_d), d);
    double h10 = t * (1 - t) * (1 - t), h11 = -t * t * (1 - t);
    q = v3_add(q, v3_add(v3_scale(mu, h10), v3_scale(mw, h11)));
    if (!(v3_dist(q, p) <= CURVE_MOVE * v3_dist(s->P[a].p, s->P[b].p)))
        return 0;
    *out = q;
    *out_at = t < 0.5 ? u : w;
    return 1;
}
