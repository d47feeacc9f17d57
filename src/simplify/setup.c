/* The simplifier's set-up: everything up to the first candidates. The input checked; positions welded (copies a
 * rounding apart too, weld_tolerance_rel) and attribute vertices with equal attributes merged into wedges; fins
 * dropped (drop_fins) and triangles with a repeated position; each position's corners threaded into a list; per
 * position (in parallel, beside the restorer's set-up): border, seam and non-manifold flags and the quadric; the
 * attribute charts; the restorer's homes; the wedges' attribute quadrics (attributes.c); the first candidates
 * (collapse.c) and the scheduler's buffers (schedule.c). */
#include <math.h>
#include <stdlib.h>

#include "simplify_internal.h"
#include "../union_find.h"


/* A triangle's plane enters its corners' quadrics weighted by its area, but by at least AREA_FLOOR × the mean
 * triangle area: with the area alone, a dense cluster of tiny triangles (a small sharp feature or a scanning
 * artefact) is erased at almost no cost, though the Hausdorff distance counts it fully. Measured with
 * bench_simplify on the dragon scan (871k triangles), two-sided Hausdorff over meshoptimizer's at 50%, 10%, 2%:
 * without the floor 1.04, 0.63, 0.88 (--restore none) and 1.65, 0.87, 0.90 (inline); at 0.75: 0.23, 0.46, 0.61 and
 * 1.43, 0.60, 0.77 (0.5 and 1 did worse on the scan or on the analytic cubic surface, whose mean distances at 10% and
 * 2% move by 1% or less at 0.75). */
static const double AREA_FLOOR = 0.75;

/* An edge whose two triangles' normals are further apart than this (cosine) folds the surface back onto itself, as
 * along the rim of a fin modelled as two sheets: the triangles' planes are nearly the same plane and do not hold the
 * rim, so the edge adds the planes through it perpendicular to its triangles, as a border edge does. */
static const double FOLD_COS = -0.866;

enum { SMALL_SORT = 24 }; /* fans up to this size are insertion-sorted */

static int pair_less(fan_pair p, fan_pair q) { return p.x < q.x || (p.x == q.x && p.slot < q.slot); }

static int pair_cmp(const void *a, const void *b)
{
    const fan_pair *p = a, *q = b;
    return pair_less(*p, *q) ? -1 : pair_less(*q, *p) ? 1 : 0;
}

/* The (neighbour, corner) pairs of fan `fan` of position v, sorted by neighbour: a run of length 1 is a border edge,
 * 2 a manifold edge, 3 or more a non-manifold edge. Returns the pair count, or SIZE_MAX when out of memory. */
size_t fan_pairs(const simplifier *s, const u32vec *fan, scratch *sc)
{
    size_t n = 2 * fan->count;
    if (n > sc->pairs_cap) {
        fan_pair *p = resurfi_realloc(s->alloc, sc->pairs, n, sizeof *p);
        uint32_t *uf = resurfi_realloc(s->alloc, sc->uf, fan->count, sizeof *uf);
        if (p)
            sc->pairs = p;
        if (uf)
            sc->uf = uf;
        if (!p || !uf)
            return SIZE_MAX;
        sc->pairs_cap = n;
    }
    for (size_t i = 0; i < fan->count; ++i) {
        uint32_t c = fan->data[i];
        sc->pairs[2 * i] = (fan_pair){TV(corner_next(c)), (uint32_t)(2 * i)};
        sc->pairs[2 * i + 1] = (fan_pair){TV(corner_prev(c)), (uint32_t)(2 * i + 1)};
    }
    if (n <= SMALL_SORT) {
        for (size_t i = 1; i < n; ++i) {
            fan_pair p = sc->pairs[i];
            size_t j = i;
            for (; j > 0 && pair_less(p, sc->pairs[j - 1]); --j)
                sc->pairs[j] = sc->pairs[j - 1];
            sc->pairs[j] = p;
        }
    } else {
        qsort(sc->pairs, n, sizeof *sc->pairs, pair_cmp);
    }
    return n;
}

/* ---- the working mesh ---------------------------------------------------------------------------------------- */

/* Do input vertices u and v carry the same attributes (bit for bit)? */
static int same_attributes(const resurf_mesh *m, uint32_t u, uint32_t v, uint32_t unsampled_texcoords)
{
    if (m->normals && memcmp(m->normals + 3 * (size_t)u, m->normals + 3 * (size_t)v, 3 * sizeof(double)))
        return 0;
    for (unsigned k = 0; k < m->texcoord_count && k < RESURF_MAX_TEXCOORD_SETS; ++k)
        if (m->texcoords[k] && !(unsampled_texcoords >> k & 1) &&
            memcmp(m->texcoords[k] + 2 * (size_t)u, m->texcoords[k] + 2 * (size_t)v, 2 * sizeof(double)))
            return 0;
    if (m->colors && memcmp(m->colors + 4 * (size_t)u, m->colors + 4 * (size_t)v, 4 * sizeof(double)))
        return 0;
    for (size_t e = 0; e < m->extra_count; ++e) {
        const resurf_attribute *a = &m->extras[e];
        if (a->data && memcmp(a->data + (size_t)a->components * u, a->data + (size_t)a->components * v,
                              a->components * sizeof(float)))
            return 0;
    }
    return 1;
}

int has_attributes(const resurf_mesh *m)
{
    if (m->normals || m->colors || m->extra_count)
        return 1;
    for (unsigned k = 0; k < m->texcoord_count && k < RESURF_MAX_TEXCOORD_SETS; ++k)
        if (m->texcoords[k])
            return 1;
    return 0;
}

resurf_status simplify_check_input(const resurf_mesh *in, resurf_error *error)
{
    if (in->triangle_count && !in->indices)
        return resurfi_error(error, RESURF_ERR_INVALID_MESH, "the mesh has triangles but no indices");
    if (in->vertex_count && !in->positions)
        return resurfi_error(error, RESURF_ERR_INVALID_MESH, "the mesh has vertices but no positions");
    if (in->triangle_count > (UINT32_MAX - 3) / 3 || in->vertex_count >= UINT32_MAX)
        return resurfi_error(error, RESURF_ERR_LIMIT, "%zu triangles and %zu vertices: simplification handles up to "
                             "%u triangles", in->triangle_count, in->vertex_count, (UINT32_MAX - 3) / 3);
    for (size_t t = 0; t < in->triangle_count; ++t)
        for (int k = 0; k < 3; ++k) {
            uint32_t v = in->indices[3 * t + k];
            if (v >= in->vertex_count)
                return resurfi_error(error, RESURF_ERR_INVALID_MESH, "triangle %zu refers to vertex %u of %zu", t, v,
                                     in->vertex_count);
            if (!v3_finite(resurfi_position(in, v)))
                return resurfi_error(error, RESURF_ERR_INVALID_MESH, "vertex %u has a non-finite position", v);
        }
    if (in->triangle_groups)
        for (size_t t = 0; t < in->triangle_count; ++t)
            if (in->triangle_groups[t] >= in->group_count && in->group_count)
                return resurfi_error(error, RESURF_ERR_INVALID_MESH, "triangle %zu is in group %u of %zu", t,
                                     in->triangle_groups[t], in->group_count);
    return RESURF_OK;
}

typedef struct zero_job {
    unsigned char *base;
    size_t bytes;
} zero_job;

enum { ZERO_BLOCK = 1 << 18 };

static int zero_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    const zero_job *j = ctx;
    size_t from = begin * ZERO_BLOCK, to = end * ZERO_BLOCK < j->bytes ? end * ZERO_BLOCK : j->bytes;
    memset(j->base + from, 0, to - from);
    return 0;
}

/* resurfi_calloc(count, size) with the zeroing on the pool's threads: the first touch of a large block's pages is
 * what costs, and the threads then share it. */
static void *calloc_shared(const simplifier *s, size_t count, size_t size)
{
    if (count == 0 || size > SIZE_MAX / count)
        return resurfi_calloc(s->alloc, count, size);
    zero_job j = {resurfi_alloc(s->alloc, count, size), count * size};
    if (j.base)
        resurfi_pool_for(s->pool, (j.bytes + ZERO_BLOCK - 1) / ZERO_BLOCK, 1, zero_block, &j);
    return j.base;
}

/* The positions of the input, welded: vertices closer than weld_tolerance_rel × the diagonal are one position (an
 * exporter's rounding leaves copies of a position a few units of the last place apart, as at a sphere's pole, where
 * sin π is not 0: welded exactly they are a hole whose rim the border guards hold, and the level stops far above
 * its target), numbered by first appearance. place[p] is the vertex whose coordinates position p takes: its first
 * vertex (the restorer's too), or its first locked one (vertex_lock: bit-exact in every level). A locked vertex at
 * another place than that one (two locked places a rounding apart) and its exact copies get a position of their
 * own. */
static resurf_status weld_positions(simplifier *s, uint32_t *remap, size_t *count, uint32_t **out_place,
                                    resurf_error *error)
{
    const resurf_mesh *in = s->in;
    size_t nv = in->vertex_count;
    const uint8_t *lock = s->opt.vertex_lock;
    *out_place = NULL;
    resurf_status st = resurfi_weld_map(s->alloc, in, s->opt.weld_tolerance_rel, remap, count, error);
    if (st != RESURF_OK)
        return st;
    /* Room for a split-off position per vertex at most. */
    uint32_t *place = resurfi_alloc(s->alloc, *count + nv + 1, sizeof *place), *exact = NULL, *own = NULL;
    size_t exact_count = 0;
    int tolerant = lock && s->opt.weld_tolerance_rel > 0;
    if (!place || (tolerant && (!(exact = resurfi_alloc(s->alloc, nv ? nv : 1, sizeof *exact)) ||
                                resurfi_weld_exact(s->alloc, in->positions, nv, exact, &exact_count) != RESURF_OK ||
                                !(own = resurfi_alloc(s->alloc, exact_count ? exact_count : 1, sizeof *own))))) {
        resurfi_free(s->alloc, place), resurfi_free(s->alloc, exact), resurfi_free(s->alloc, own);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory welding the mesh's positions");
    }
    memset(place, 0xff, *count * sizeof *place);
    for (size_t v = 0; v < nv; ++v) /* the first vertex, or the first locked one */
        if (place[remap[v]] == NONE || (lock && lock[v] && !lock[place[remap[v]]]))
            place[remap[v]] = (uint32_t)v;
    if (tolerant) {
        memset(own, 0xff, exact_count * sizeof *own);
        for (size_t v = 0; v < nv; ++v)
            if (lock[v] && exact[v] != exact[place[remap[v]]] && own[exact[v]] == NONE) {
                place[*count] = (uint32_t)v;
                own[exact[v]] = (uint32_t)(*count)++;
            }
        for (size_t v = 0; v < nv; ++v)
            if (own[exact[v]] != NONE)
                remap[v] = own[exact[v]];
    }
    resurfi_free(s->alloc, exact), resurfi_free(s->alloc, own);
    *out_place = place;
    return RESURF_OK;
}

static resurf_status prepare_mesh(simplifier *s, resurf_error *error)
{
    const resurf_mesh *in = s->in;
    size_t nv = in->vertex_count;
    uint32_t *remap = resurfi_alloc(s->alloc, nv, sizeof *remap);
    uint32_t *rep = resurfi_alloc(s->alloc, nv, sizeof *rep);
    uint32_t *first = NULL, *chain = NULL, *place = NULL;
    uint8_t *drop = NULL;
    resurf_status st = RESURF_ERR_OUT_OF_MEMORY;
    if (!remap || !rep)
        goto done;
    size_t pc = 0;
    if ((st = weld_positions(s, remap, &pc, &place, error)) != RESURF_OK)
        goto done;
    st = RESURF_ERR_OUT_OF_MEMORY;
    s->pos_count = pc;
    s->remap = remap; /* for the restorer, which welds the same positions */

    /* Wedges: at each position, a vertex joins the lowest earlier vertex with equal attributes. Positions hold few
     * vertices, so the pairwise test is cheap. */
    if (!(first = resurfi_alloc(s->alloc, pc, sizeof *first)) || !(chain = resurfi_alloc(s->alloc, nv, sizeof *chain)))
        goto done;
    memset(first, 0xff, pc * sizeof *first);
    int attrs = has_attributes(in);
    for (size_t v = nv; v-- > 0;) {
        chain[v] = first[remap[v]];
        first[remap[v]] = (uint32_t)v;
    }
    for (size_t v = 0; v < nv; ++v) {
        rep[v] = (uint32_t)v;
        if (!attrs) {
            rep[v] = first[remap[v]];
            continue;
        }
        for (uint32_t u = first[remap[v]]; u < v; u = chain[u])
            if (same_attributes(in, u, (uint32_t)v, s->opt.unsampled_texcoords)) {
                rep[v] = rep[u];
                break;
            }
    }

    if (s->opt.drop_fins && (st = resurfi_find_fins(s, remap, &drop)) != RESURF_OK)
        goto done;
    st = RESURF_ERR_OUT_OF_MEMORY;
    size_t nt = 0, sheet = 0;
    for (size_t t = 0; t < in->triangle_count; ++t) {
        const uint32_t *i = in->indices + 3 * t;
        uint32_t a = remap[i[0]], b = remap[i[1]], c = remap[i[2]];
        nt += a != b && b != c && a != c && !resurfi_fin_left_out(drop, t);
        sheet += s->mirror && s->mirror[t] != NONE;
    }
    s->tri_count = nt;
    s->alive_tris = nt + sheet; /* the level's triangles: a sheet's mirrors count */
    s->tri = calloc_shared(s, nt, sizeof *s->tri);
    s->src = resurfi_alloc(s->alloc, nt, sizeof *s->src);
    /* the allocator promises malloc's alignment only: the block has room to align within */
    if (pc <= (SIZE_MAX - 63) / sizeof *s->P && (s->P_mem = calloc_shared(s, pc * sizeof *s->P + 63, 1)))
        s->P = (work_pos *)(((uintptr_t)s->P_mem + 63) & ~(uintptr_t)63);
    s->mark = resurfi_calloc(s->alloc, pc, sizeof *s->mark);
    if (!s->tri || !s->src || !s->P || !s->mark)
        goto done;
    nt = 0;
    double area = 0; /* for the quadrics' area floor (the input's positions: those of the working mesh) */
    for (size_t t = 0; t < in->triangle_count; ++t) {
        const uint32_t *i = in->indices + 3 * t;
        uint32_t a = remap[i[0]], b = remap[i[1]], c = remap[i[2]];
        if (a == b || b == c || a == c || resurfi_fin_left_out(drop, t))
            continue;
        for (int k = 0; k < 3; ++k) {
            TV(3 * nt + k) = remap[i[k]];
            TW(3 * nt + k) = rep[i[k]];
        }
        area += 0.5 * v3_len(v3_tri_cross(resurfi_position(in, i[0]), resurfi_position(in, i[1]),
                                          resurfi_position(in, i[2])));
        s->src[nt++] = (uint32_t)t;
    }
    s->area_floor = nt ? AREA_FLOOR * area / (double)nt : 0;
    for (size_t p = 0; p < pc; ++p)
        s->P[p].p = resurfi_position(in, place[p]);
    /* Lists in increasing triangle order: insert from the back. The heads are built in the (still unused) marks,
     * 4 bytes per position, not in the 128-byte records: 3 random writes per triangle then stay in the cache. */
    uint32_t *head = s->mark;
    memset(head, 0xff, pc * sizeof *head);
    for (size_t c = 3 * nt; c-- > 0;) {
        TNEXT(c) = head[TV(c)];
        head[TV(c)] = (uint32_t)c;
    }
    for (size_t p = 0; p < pc; ++p) {
        s->P[p].head = head[p];
        if (head[p] == NONE)
            s->P[p].flags = POS_DEAD;
        else
            s->alive_positions++;
    }
    memset(head, 0, pc * sizeof *head);
    st = RESURF_OK;
    if (attrs) { /* the wedges' forest starts as each vertex's wedge */
        s->wedge_root = rep;
        rep = NULL;
    }
done:
    if (s->remap != remap)
        resurfi_free(s->alloc, remap);
    resurfi_free(s->alloc, rep);
    resurfi_free(s->alloc, first);
    resurfi_free(s->alloc, chain);
    resurfi_free(s->alloc, drop);
    resurfi_free(s->alloc, place);
    if (st == RESURF_ERR_OUT_OF_MEMORY)
        return resurfi_error(error, st, "out of memory preparing %zu triangles for simplification",
                             in->triangle_count);
    if (st != RESURF_OK)
        return resurfi_error(error, st, "cannot weld the mesh's positions");
    return RESURF_OK;
}

/* ---- flags and quadrics per position ------------------------------------------------------------------------ */

/* The plane through edge (p, q) perpendicular to triangle normal n (unit), as a quadric of weight w. */
static resurfi_quadric edge_plane(vec3 p, vec3 q, vec3 n, double w)
{
    vec3 m = v3_normalize(v3_cross(v3_sub(q, p), n));
    return resurfi_quadric_plane(m, -v3_dot(m, p), w);
}

/* A triangle's normal can be judged by when none of its angles exceeds 150° (the restorer's reliable_normal, see
 * docs/restoring.md §7): a flat sliver's normal is that of the surface near its far-away circumcentre. */
static shaped_normal well_shaped(const simplifier *s, uint32_t t)
{
    vec3 p[3] = {s->P[TV(3 * t)].p, s->P[TV(3 * t + 1)].p, s->P[TV(3 * t + 2)].p};
    for (int k = 0; k < 3; ++k) {
        vec3 u = v3_sub(p[(k + 1) % 3], p[k]), v = v3_sub(p[(k + 2) % 3], p[k]);
        double uv = v3_dot(u, v), l2 = v3_len2(u) * v3_len2(v);
        if (!(l2 > 0) || (uv < 0 && uv * uv > SLIVER_COS2 * l2))
            return (shaped_normal){v3(0, 0, 0), 0};
    }
    return (shaped_normal){v3_tri_cross(p[0], p[1], p[2]), 1};
}

/* The cosine of the angle between two triangles' normals; 1 when one of them has no reliable normal. */
static double normals_cos(shaped_normal ni, shaped_normal nj)
{
    if (!ni.ok || !nj.ok)
        return 1;
    double l2 = v3_len2(ni.n) * v3_len2(nj.n);
    return l2 > 0 ? v3_dot(ni.n, nj.n) / sqrt(l2) : 1;
}

/* Do triangles ti and tj belong to different groups of the input (an OBJ usemtl/g border: another material)? */
int group_border(const simplifier *s, uint32_t ti, uint32_t tj)
{
    const uint32_t *g = s->in->triangle_groups;
    return g && g[s->src[ti]] != g[s->src[tj]];
}

/* Is edge (a, x), shared by triangles ti and tj, a feature edge: a border between two groups (materials), the
 * triangles' normals more than feature_angle_deg apart, or the input's normals split along it (a normal seam: its
 * wedges at an end carry normals more than about 1° apart)? */
/* feature_edge's tests but the angle: a border between groups, or a normal seam. */
static int marked_feature(const simplifier *s, uint32_t ti, uint32_t tj, uint32_t a, uint32_t x)
{
    if (group_border(s, ti, tj))
        return 1;
    const double *normals = s->in->normals;
    for (int end = 0; normals && end < 2; ++end) {
        uint32_t v = end ? x : a;
        uint32_t wi = TW(corner_at(s, ti, v)), wj = TW(corner_at(s, tj, v));
        if (wi == wj)
            continue;
        vec3 ni = v3_load(normals + 3 * (size_t)wi), nj = v3_load(normals + 3 * (size_t)wj);
        double l2 = v3_len2(ni) * v3_len2(nj), d = v3_dot(ni, nj);
        if (l2 > 0 && isfinite(l2) && d < RESURFI_SAME_NORMAL_COS * sqrt(l2))
            return 1;
    }
    return 0;
}

int feature_edge(const simplifier *s, uint32_t ti, uint32_t tj, uint32_t a, uint32_t x)
{
    return marked_feature(s, ti, tj, a, x) ||
           (s->feature_cos > -1 && normals_cos(well_shaped(s, ti), well_shaped(s, tj)) < s->feature_cos);
}

/* Does a border through a with edges to p and q turn by more than corner_angle_deg there? */
static int curve_turns(const simplifier *s, vec3 pa, vec3 p, vec3 q)
{
    vec3 in = v3_sub(pa, p), out = v3_sub(q, pa);
    return v3_dot(in, out) < s->corner_cos * sqrt(v3_len2(in) * v3_len2(out));
}

/* Classifies position a from its fan (see POS_*); with out_q, also its quadric, with out_up the number of its
 * neighbours above a (its edges in the first list). Returns 0 when out of memory. */
int analyse_position(simplifier *s, uint32_t a, scratch *sc, pos_flags *out_flags, resurfi_quadric *out_q,
                     uint32_t *out_up)
{
    if (!gather_fan(s, a, &sc->fan, 0))
        return 0;
    const u32vec *fan = &sc->fan;
    size_t n = fan_pairs(s, fan, sc);
    if (n == SIZE_MAX)
        return 0;
    if (fan->count > sc->shaped_cap) {
        shaped_normal *sh = resurfi_realloc(s->alloc, sc->shaped, fan->count, sizeof *sh);
        if (!sh)
            return 0;
        sc->shaped = sh;
        sc->shaped_cap = fan->count;
    }
    /* Each fan triangle's normal once: each of its two edges in the fan asks for it. */
    for (size_t i = 0; i < fan->count; ++i)
        sc->shaped[i] = well_shaped(s, fan->data[i] / 3);
    pos_flags f = 0;
    for (size_t i = 0; i < fan->count; ++i)
        sc->uf[i] = (uint32_t)i;
    int seam_edges = 0, group_edges = 0;
    uint32_t group_end[2] = {NONE, NONE}; /* the other ends of the first two material border edges */
    uint32_t wedges[3];
    int wedge_count = 0;
    for (size_t i = 0; i < fan->count && wedge_count < 3; ++i) {
        uint32_t w = TW(fan->data[i]);
        int seen = 0;
        for (int k = 0; k < wedge_count; ++k)
            seen |= wedges[k] == w;
        if (!seen)
            wedges[wedge_count++] = w;
    }
    resurfi_quadric q = {{0, 0, 0, 0, 0, 0}, {0, 0, 0}, 0, 0};
    if (out_q)
        for (size_t i = 0; i < fan->count; ++i) {
            uint32_t t = fan->data[i] / 3;
            resurfi_quadric tq = resurfi_quadric_triangle(v3_sub(s->P[TV(3 * t)].p, s->origin),
                                                          v3_sub(s->P[TV(3 * t + 1)].p, s->origin),
                                                          v3_sub(s->P[TV(3 * t + 2)].p, s->origin));
            if (tq.w > 0 && tq.w < s->area_floor) {
                double k = s->area_floor / tq.w;
                for (int j = 0; j < 6; ++j)
                    tq.a[j] *= k;
                for (int j = 0; j < 3; ++j)
                    tq.b[j] *= k;
                tq.c *= k;
                tq.w *= k;
            }
            resurfi_quadric_add(&q, &tq);
        }
    vec3 pa = s->P[a].p;
    uint32_t up = 0;
    int features = 0, borders = 0, rough = 0, junction_edges = 0;
    uint32_t border_end[2] = {NONE, NONE};
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && sc->pairs[j].x == sc->pairs[i].x)
            ++j;
        uint32_t x = sc->pairs[i].x;
        up += x > a;
        if (j - i == 1) {
            f |= POS_BORDER;
            if (borders < 2)
                border_end[borders] = x;
            ++borders;
            if (out_q) {
                uint32_t c = fan->data[sc->pairs[i].slot / 2];
                uint32_t t = c / 3;
                vec3 n0 = v3_normalize(
                    v3_tri_cross(s->P[TV(3 * t)].p, s->P[TV(3 * t + 1)].p, s->P[TV(3 * t + 2)].p));
                double len2 = v3_dist2(pa, s->P[x].p);
                resurfi_quadric eq = edge_plane(v3_sub(pa, s->origin), v3_sub(s->P[x].p, s->origin), n0,
                                                s->opt.border_weight * len2);
                resurfi_quadric_add(&q, &eq);
            }
        } else if (j - i == 2) {
            uint32_t si = sc->pairs[i].slot, sj = sc->pairs[i + 1].slot;
            if ((si & 1) == (sj & 1))
                f |= POS_LOCKED; /* the edge is used twice in the same direction: orientation flips here */
            uint32_t ci = fan->data[si / 2], cj = fan->data[sj / 2];
            uint32_t ti = ci / 3, tj = cj / 3;
            resurfi_uf_union(sc->uf, si / 2, sj / 2);
            int seam_here = TW(ci) != TW(cj);
            int seam_there = TW(corner_at(s, ti, x)) != TW(corner_at(s, tj, x));
            int material = group_border(s, ti, tj);
            seam_edges += seam_here;
            if (material && group_edges < 2)
                group_end[group_edges] = x;
            group_edges += material;
            double turn_cos = normals_cos(sc->shaped[si / 2], sc->shaped[sj / 2]); /* feature_edge's, and more */
            if (marked_feature(s, ti, tj, a, x) || (s->feature_cos > -1 && turn_cos < s->feature_cos))
                ++features;
            else if (turn_cos < s->smooth_cos)
                rough = 1;
            int fold = turn_cos < FOLD_COS;
            if (out_q && (seam_here || seam_there || material || fold)) {
                /* Each side's triangle adds its own perpendicular plane, at half weight. */
                double len2 = v3_dist2(pa, s->P[x].p);
                for (int side = 0; side < 2; ++side) {
                    uint32_t t = side ? tj : ti;
                    vec3 n0 = v3_normalize(
                        v3_tri_cross(s->P[TV(3 * t)].p, s->P[TV(3 * t + 1)].p, s->P[TV(3 * t + 2)].p));
                    resurfi_quadric eq = edge_plane(v3_sub(pa, s->origin), v3_sub(s->P[x].p, s->origin), n0,
                                                    0.5 * s->opt.border_weight * len2);
                    resurfi_quadric_add(&q, &eq);
                }
            }
        } else if (j - i == 3) {
            /* A junction edge: a sheet meets a surface (a panel written double-sided, one side kept by fins.c,
               joined to a single-sided body). Its three triangles are one fan here. */
            ++junction_edges;
            resurfi_uf_union(sc->uf, sc->pairs[i].slot / 2, sc->pairs[i + 1].slot / 2);
            resurfi_uf_union(sc->uf, sc->pairs[i].slot / 2, sc->pairs[i + 2].slot / 2);
        } else {
            f |= POS_LOCKED;
        }
        i = j;
    }
    /* Inside a junction line, a position may move along it (collapse.c); where the line ends, branches or meets a
       border it holds still. */
    if (junction_edges == 2 && !(f & POS_BORDER))
        f |= POS_JUNCTION;
    else if (junction_edges)
        f |= POS_LOCKED;
    /* More than one fan of triangles around a (a bow tie): non-manifold. */
    for (size_t i = 1; i < fan->count; ++i)
        if (resurfi_uf_find(sc->uf, (uint32_t)i) != resurfi_uf_find(sc->uf, 0))
            f |= POS_LOCKED;
    if (f & POS_LOCKED)
        f &= (pos_flags)~POS_JUNCTION;
    if (wedge_count == 2 && seam_edges == 2 && !(f & POS_BORDER))
        f |= POS_SEAM;
    else if (wedge_count >= 2)
        f |= POS_COMPLEX;
    if ((f & POS_BORDER) && s->opt.lock_border)
        f |= POS_LOCKED_BORDER;
    /* Features. A crease's end (one feature edge) is no corner: the crease may shorten there, as it fades into a
     * smooth part. Feature edges and border corners count only in smooth fans (every other edge at a turning by
     * less than a quarter of feature_angle_deg): on a noisy scan sharp edges and a ragged border are noise, not
     * features, and holding them would cost the quadric its freedom (measured: the dragon's 2% level stopped at
     * 444 triangles instead of 310; the cut dragon-notch.obj's 5% level went from 4.3% to 7.7% of the diagonal).
     * A crease that turns sharply with no third feature edge is no corner either: on the dragon scan such corners
     * raised the 2% level's mean distance from 25.9 to 31.3 ×1e-4 of the diagonal, and a box's corners have three
     * edges. A border between groups (materials) always counts: it is where the input says the surface changes; and
 * like a mesh border it has corners where it turns by more than corner_angle_deg (a decal's corners stay). */
    if (rough)
        features = group_edges; /* a material border is one however rough the surface around it */
    if (features >= 3 || (features >= 1 && borders > 0) ||
        (borders == 2 && !rough && curve_turns(s, pa, s->P[border_end[0]].p, s->P[border_end[1]].p)) ||
        (group_edges == 2 && curve_turns(s, pa, s->P[group_end[0]].p, s->P[group_end[1]].p)))
        f |= POS_CORNER;
    else if (features == 2)
        f |= POS_CREASE;
    if (features)
        f |= POS_TOUCHES_FEATURE;
    *out_flags = f;
    if (out_q)
        *out_q = q;
    if (out_up)
        *out_up = up;
    return 1;
}

/* Charts: triangles connected across edges whose ends have the same wedges on both sides. A result vertex takes
 * its attributes from the closest input triangle of its wedge's chart, so texcoords never come from across a seam. */
static resurf_status find_charts(simplifier *s, scratch *sc)
{
    uint32_t *parent = resurfi_alloc(s->alloc, s->tri_count, sizeof *parent);
    s->charts.of_input_tri = resurfi_alloc(s->alloc, s->in->triangle_count, sizeof *s->charts.of_input_tri);
    s->charts.of_wedge = resurfi_alloc(s->alloc, s->in->vertex_count, sizeof *s->charts.of_wedge);
    if (!parent || !s->charts.of_input_tri || !s->charts.of_wedge) {
        resurfi_free(s->alloc, parent);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    for (size_t t = 0; t < s->tri_count; ++t)
        parent[t] = (uint32_t)t;
    for (size_t a = 0; a < s->pos_count; ++a) {
        if (s->P[a].flags & POS_DEAD)
            continue;
        if (!gather_fan(s, (uint32_t)a, &sc->fan, 0)) {
            resurfi_free(s->alloc, parent);
            return RESURF_ERR_OUT_OF_MEMORY;
        }
        size_t n = fan_pairs(s, &sc->fan, sc);
        if (n == SIZE_MAX) {
            resurfi_free(s->alloc, parent);
            return RESURF_ERR_OUT_OF_MEMORY;
        }
        for (size_t i = 0; i + 1 < n; ++i) {
            if (sc->pairs[i].x != sc->pairs[i + 1].x || sc->pairs[i].x < a ||
                (i + 2 < n && sc->pairs[i + 2].x == sc->pairs[i].x) || (i > 0 && sc->pairs[i - 1].x == sc->pairs[i].x))
                continue;
            uint32_t x = sc->pairs[i].x;
            uint32_t ci = sc->fan.data[sc->pairs[i].slot / 2], cj = sc->fan.data[sc->pairs[i + 1].slot / 2];
            uint32_t ti = ci / 3, tj = cj / 3;
            if (TW(ci) == TW(cj) && TW(corner_at(s, ti, x)) == TW(corner_at(s, tj, x))) {
                resurfi_uf_union(parent, ti, tj);
            }
        }
    }
    memset(s->charts.of_input_tri, 0xff, s->in->triangle_count * sizeof *s->charts.of_input_tri);
    memset(s->charts.of_wedge, 0xff, s->in->vertex_count * sizeof *s->charts.of_wedge);
    for (size_t t = 0; t < s->tri_count; ++t) {
        uint32_t c = resurfi_uf_find(parent, (uint32_t)t);
        s->charts.of_input_tri[s->src[t]] = c;
        for (int k = 0; k < 3; ++k)
            if (s->charts.of_wedge[TW(3 * t + k)] == NONE)
                s->charts.of_wedge[TW(3 * t + k)] = c;
    }
    resurfi_free(s->alloc, parent);
    /* Each chart's input triangles (chart ids are working triangles), for the output's scan of a small chart. */
    size_t nt = s->in->triangle_count;
    s->charts.first = resurfi_calloc(s->alloc, s->tri_count + 2, sizeof *s->charts.first);
    s->charts.tris = resurfi_alloc(s->alloc, nt + 1, sizeof *s->charts.tris);
    if (!s->charts.first || !s->charts.tris)
        return RESURF_ERR_OUT_OF_MEMORY;
    uint32_t *first = s->charts.first;
    for (size_t t = 0; t < nt; ++t)
        if (s->charts.of_input_tri[t] != NONE)
            first[s->charts.of_input_tri[t] + 2]++;
    for (size_t c = 2; c < s->tri_count + 2; ++c)
        first[c] += first[c - 1];
    for (size_t t = 0; t < nt; ++t) /* first[c + 1] runs over chart c's slots, ending at its end */
        if (s->charts.of_input_tri[t] != NONE)
            s->charts.tris[first[s->charts.of_input_tri[t] + 1]++] = (uint32_t)t;
    return RESURF_OK;
}



/* The analysis, BLOCK_POSITIONS positions a job, with the restorer's set-up beside it: the two share nothing, so the
 * calling thread (worker 0) builds the restorer first, its loops on that thread alone, while the other threads
 * analyse; then it joins them. */
typedef struct setup_job {
    simplifier *s;
    scratch *scratch;  /* one per worker */
    int build_restorer; /* still to be built */
    resurf_status restorer_status;
    resurf_error restorer_error;
} setup_job;

static int build_restorer(setup_job *j)
{
    simplifier *s = j->s;
    j->build_restorer = 0;
    j->restorer_status = services_build_restorer(s->in, &s->opt, s->alloc, s->remap, s->pos_count,
                                                 &s->own_restorer, &j->restorer_error);
    s->restorer = s->own_restorer;
    return j->restorer_status == RESURF_OK;
}

static int setup_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    setup_job *j = ctx;
    simplifier *s = j->s;
    if (worker == 0 && j->build_restorer && !build_restorer(j))
        return 1;
    for (size_t p = begin * BLOCK_POSITIONS; p < end * BLOCK_POSITIONS && p < s->pos_count; ++p) {
        if (s->P[p].flags & POS_DEAD)
            continue;
        pos_flags f;
        if (!analyse_position(s, (uint32_t)p, &j->scratch[worker], &f, &s->P[p].q, &s->P[p].up))
            return 1;
        s->P[p].flags = f;
    }
    return 0;
}

/* ---- the whole set-up ---------------------------------------------------------------------------------------- */

/* Everything up to the first candidate: input checks, the working mesh, the restorer or a BVH, flags, quadrics,
 * charts, the first candidates and the scheduler's buffers. */
resurf_status simplify_start(simplifier *s, scratch *scratch, resurf_error *error)
{
    resurf_status st = simplify_check_input(s->in, error);
    if (st != RESURF_OK)
        return st;
    /* Flat-shaded parts are simplified without their normals (facets.c); lent services are over that copy already. */
    if (s->lent && s->lent->derived)
        s->in = s->lent->derived;
    else if (!s->lent && (st = facets_derive(s->in, s->alloc, &s->own_derived)) != RESURF_OK)
        return resurfi_error(error, st, "out of memory dropping flat shading");
    else if (s->own_derived)
        s->in = s->own_derived;
    s->flat_shaded = s->lent ? s->lent->derived != NULL : s->own_derived != NULL;
    double lo[3], hi[3];
    s->diagonal = resurf_mesh_bounds(s->in, lo, hi);
    s->origin = v3(0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2]));
    double bound = INFINITY;
    if (s->opt.max_error > 0)
        bound = s->opt.max_error;
    if (s->opt.max_error_rel > 0 && s->opt.max_error_rel * s->diagonal < bound)
        bound = s->opt.max_error_rel * s->diagonal;
    s->max_error = bound;
    s->feature_cos = s->opt.feature_angle_deg >= 180 ? -2 : cos(s->opt.feature_angle_deg * (M_PI / 180.0));
    s->corner_cos = cos(s->opt.corner_angle_deg * (M_PI / 180.0));
    s->smooth_cos = cos(0.25 * s->opt.feature_angle_deg * (M_PI / 180.0));
    if ((st = prepare_mesh(s, error)) != RESURF_OK)
        return st;
    s->rep.input_triangles = s->tri_count;
    s->rep.input_positions = s->alive_positions;
    s->rep.diagonal = s->diagonal;
    if (s->tri_count == 0)
        return RESURF_OK;
    setup_job sj = {.s = s, .scratch = scratch, .restorer_status = RESURF_OK};
    if (s->opt.restore != RESURF_RESTORE_NONE && s->lent && s->lent->restorer)
        s->restorer = s->lent->restorer;
    else
        sj.build_restorer = s->opt.restore != RESURF_RESTORE_NONE;
    if (resurfi_progress(&s->opt.progress, RESURF_STAGE_PREPARE, 0.5))
        return resurfi_error(error, RESURF_ERR_CANCELLED, "simplification cancelled");
    /* The analysis kept by an earlier call on these services, else made here (and kept for the later ones). */
    int kept = services_take_analysis(s);
    size_t blocks = kept ? 0 : (s->pos_count + BLOCK_POSITIONS - 1) / BLOCK_POSITIONS;
    int analysed = !resurfi_pool_for(s->pool, blocks, 1, setup_block, &sj);
    if (analysed && sj.build_restorer) /* the other threads took every block */
        build_restorer(&sj);
    if (!analysed || sj.restorer_status != RESURF_OK) {
        if (sj.restorer_status == RESURF_OK)
            return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory analysing the mesh");
        if (error)
            *error = sj.restorer_error;
        return sj.restorer_status;
    }
    if (!kept)
        services_keep_analysis(s);
    if (s->opt.vertex_lock) /* after the analysis, which writes every flag afresh */
        for (size_t v = 0; v < s->in->vertex_count; ++v)
            if (s->opt.vertex_lock[v] && !(s->P[s->remap[v]].flags & POS_DEAD))
                s->P[s->remap[v]].flags |= POS_LOCKED;
    if (s->restorer) {
        if (!(s->home = resurfi_alloc(s->alloc, s->pos_count, sizeof *s->home)))
            return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
        for (size_t p = 0; p < s->pos_count; ++p) /* the input triangle of its first corner */
            s->home[p] = s->P[p].head != NONE ? s->src[s->P[p].head / 3] : NONE;
        if (s->opt.restore == RESURF_RESTORE_INLINE && curves_start(s, &scratch[0]) != RESURF_OK)
            return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    }
    if (corners_start(s, &scratch[0]) != RESURF_OK)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    resurfi_free(s->alloc, s->remap);
    s->remap = NULL;
    if (services_need_bvh(s->in, &s->opt) && s->lent && s->lent->bvh) {
        s->bvh = s->lent->bvh;
    } else if (services_need_bvh(s->in, &s->opt)) {
        if ((st = services_build_bvh(s->in, &s->opt, s->alloc, &s->own_bvh)) != RESURF_OK)
            return resurfi_error(error, st, "cannot build the input's BVH");
        s->bvh = s->own_bvh;
    }
    int seams = 0;
    for (size_t p = 0; p < s->pos_count && !seams; ++p)
        seams = (s->P[p].flags & (POS_SEAM | POS_COMPLEX)) != 0;
    if (seams && has_attributes(s->in) && find_charts(s, &scratch[0]) != RESURF_OK)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory finding attribute charts");
    if (attributes_start(s, scratch) != RESURF_OK)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory building attribute quadrics");
    if (!(s->gen = resurfi_calloc(s->alloc, s->pos_count, sizeof *s->gen)))
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    st = seed_candidates(s, scratch);
    if (st != RESURF_OK)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory queueing %zu edges",
                             3 * s->tri_count / 2);
    if (schedule_init(s) != RESURF_OK)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    if (resurfi_progress(&s->opt.progress, RESURF_STAGE_PREPARE, 1))
        return resurfi_error(error, RESURF_ERR_CANCELLED, "simplification cancelled");
    return RESURF_OK;
}
