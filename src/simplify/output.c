/* The simplifier's output: one snapshot of the working mesh turned into a resurf_mesh. Used positions are numbered
 * (number_output), placed (place_output: POST restoration, then the sag offset), given attributes from the input
 * (attribute_block: the closest input triangle on the vertex's side of any seam, find_sides; joints and weights
 * as influences, src/skin.c); measure.c then measures it. */
#include <math.h>

#include "simplify_internal.h"


/* One snapshot of the working mesh turned into a resurf_mesh. Used positions are numbered u = 0.. in order of
 * first use; output vertices are (position, wedge) pairs. */
typedef struct output {
    size_t nt, nu, nv;
    uint32_t *tris;       /* nt working triangles, in order */
    uint32_t *pos_index;  /* per position: its u, or NONE */
    uint32_t *upos;       /* per u: the position */
    uint32_t *ufirst;     /* per u: its first output vertex */
    uint32_t *ov_next, *ov_u, *ov_wedge; /* per output vertex */
    uint32_t *corner_ov;  /* 3 nt */
    vec3 *base;           /* per u: the position before the sag offset (on S with restoration) */
    vec3 *final;          /* per u: the output position */
    vec3 *normal;         /* per u: S's normal at base (sag offset only) */
    double *sag_sum;      /* per u */
    double *m_depth;      /* per u: how far M's facets lie under S where v is (sag offset only) */
    double *gap;          /* per output triangle: how far M lies above it on average, measured (sag offset only) */
    double *gap_sum;      /* per u: the sum of its triangles' gaps */
    double *len;          /* per u: longest incident edge */
    uint32_t *sag_count;
    uint8_t *outcome;     /* per u: POST restoration left it (1) */
    uint8_t *held;        /* per u: HELD_PLACE (locked or a corner: keeps the input's place), HELD_OFFSET (on a
                             crease: neither restored at the end nor offset), else 0 */
    uint32_t *side_tri;   /* per output vertex at a seam: the closest input triangle on its side, else NONE */
    double *side_bary;    /* 3 per output vertex: the barycentrics of that closest point */
    /* a double-sided sheet's back (mirror_sheets): output vertices nv.. and triangles nt.. */
    size_t mirror_nv, mirror_nt;
    uint32_t *mirror_front; /* per mirror vertex: the output vertex it mirrors */
    uint32_t *mirror_tris;  /* per mirror triangle: the output triangle it mirrors */
} output;

static void output_free(output *o, const resurf_allocator *alloc)
{
    resurfi_free(alloc, o->tris);
    resurfi_free(alloc, o->pos_index);
    resurfi_free(alloc, o->upos);
    resurfi_free(alloc, o->ufirst);
    resurfi_free(alloc, o->ov_next);
    resurfi_free(alloc, o->ov_u);
    resurfi_free(alloc, o->ov_wedge);
    resurfi_free(alloc, o->corner_ov);
    resurfi_free(alloc, o->base);
    resurfi_free(alloc, o->final);
    resurfi_free(alloc, o->normal);
    resurfi_free(alloc, o->sag_sum);
    resurfi_free(alloc, o->m_depth);
    resurfi_free(alloc, o->gap);
    resurfi_free(alloc, o->gap_sum);
    resurfi_free(alloc, o->len);
    resurfi_free(alloc, o->sag_count);
    resurfi_free(alloc, o->outcome);
    resurfi_free(alloc, o->held);
    resurfi_free(alloc, o->side_tri);
    resurfi_free(alloc, o->side_bary);
    resurfi_free(alloc, o->mirror_front);
    resurfi_free(alloc, o->mirror_tris);
}

enum { HELD_PLACE = 1, HELD_OFFSET = 2 };

typedef struct output_job {
    simplifier *s;
    output *o;
    resurf_mesh *m;
} output_job;

static int post_restore_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    output_job *j = ctx;
    for (size_t u = begin; u < end; ++u) {
        for (size_t k = 1; k <= 3 && u + k < end; ++k)
            prefetch_walk(j->s, j->o->upos[u + k], k);
        int left = 0;
        uint32_t t;
        if (!j->o->held[u])
            j->o->base[u] = restore_point(j->s, j->o->base[u], j->o->len[u], j->s->home[j->o->upos[u]], &left, &t);
        j->o->outcome[u] = (uint8_t)left;
    }
    return 0;
}

static int normal_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    output_job *j = ctx;
    for (size_t u = begin; u < end; ++u) {
        for (size_t k = 1; k <= 3 && u + k < end; ++k)
            prefetch_walk(j->s, j->o->upos[u + k], k);
        double bary[3], d2;
        uint32_t t = resurfi_restorer_closest_walk(j->s->restorer, j->o->base[u], j->s->home[j->o->upos[u]], bary,
                                                   &d2);
        j->o->normal[u] = t == NONE ? v3(0, 0, 0) : resurfi_restorer_normal(j->s->restorer, t, bary);
        j->o->m_depth[u] = t == NONE ? 0 : facet_depth(j->s, t);
    }
    return 0;
}

typedef struct chart_search {
    const uint32_t *chart_of_tri;
    uint32_t chart;
    uint32_t best;
    double best_d2;
    double bary[3];
} chart_search;

/* The point of M closest to p, found by walking from triangle `start` of M; p itself when none is found (*found 0). */
static vec3 closest_on_input(const simplifier *s, vec3 p, uint32_t start, int *found)
{
    double bary[3], d2;
    uint32_t t = resurfi_restorer_closest_walk(s->restorer, p, start, bary, &d2);
    *found = t != NONE;
    if (t == NONE)
        return p;
    const uint32_t *ix = s->in->indices + 3 * (size_t)t;
    vec3 q = v3(0, 0, 0);
    for (int k = 0; k < 3; ++k)
        q = v3_madd(q, v3_load(s->in->positions + 3 * (size_t)ix[k]), bary[k]);
    return q;
}

/* gap[i]: how far M lies above output triangle i (along its normal) on average, measured by the midpoint rule: the
 * mean of the signed offsets from the midpoints of its edges to M's closest points (exact for a gap that is
 * quadratic over the triangle, as a chord's sag under a smooth surface is). */
static int gap_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    output_job *j = ctx;
    output *o = j->o;
    for (size_t i = begin; i < end; ++i) {
        uint32_t u[3];
        for (int c = 0; c < 3; ++c)
            u[c] = o->ov_u[o->corner_ov[3 * i + c]];
        vec3 n = v3_normalize(v3_tri_cross(o->base[u[0]], o->base[u[1]], o->base[u[2]]));
        double sum = 0;
        int count = 0;
        for (int c = 0; c < 3; ++c) {
            vec3 mid = v3_scale(v3_add(o->base[u[c]], o->base[u[(c + 1) % 3]]), 0.5);
            int found;
            vec3 q = closest_on_input(j->s, mid, j->s->home[o->upos[u[c]]], &found);
            if (found) {
                sum += v3_dot(v3_sub(q, mid), n);
                ++count;
            }
        }
        o->gap[i] = count ? sum / count : 0;
    }
    return 0;
}

/* A chart of up to this many triangles is scanned for the closest of them rather than searched in the tree near
 * the vertex, whose reach (the distance to the closest triangle of any chart plus the vertex's longest edge) may
 * take in most of the mesh at a coarse level: on 2CylinderEngine at 25% and 10%, 872 searches (charts of 4 to
 * 3,700 triangles, reaches up to 0.93 of the primitive's diagonal) cost 470 M instructions, 7% of the call. */
#define CHART_SCAN 4096

static int chart_visit(void *ctx, uint32_t t, vec3 point, const double bary[3], double d2)
{
    (void)point;
    chart_search *cs = ctx;
    if (cs->chart_of_tri[t] != cs->chart)
        return 0;
    if (d2 < cs->best_d2 || (d2 == cs->best_d2 && t < cs->best)) {
        cs->best = t;
        cs->best_d2 = d2;
        memcpy(cs->bary, bary, sizeof cs->bary);
    }
    return 0;
}

/* The sides of the seams: for each output vertex at a position with two or more (a seam), the closest input
 * triangle with a corner whose wedge became or merged into the vertex's wedge. A chart alone cannot tell the sides
 * apart where a seam does not cut its chart in two (a cylinder's or a sphere's UV seam): both sides are one chart,
 * and the closest triangle of a vertex on the seam is as likely to lie across it. The wedges merged into a vertex
 * lie on its side, so their triangles do too. One pass over the input's triangles, in order: the answer does not
 * depend on the thread count. */
static resurf_status find_sides(simplifier *s, output *o)
{
    if (!s->wedge_root || !s->charts.of_wedge)
        return RESURF_OK;
    const resurf_mesh *in = s->in;
    uint32_t *root = s->wedge_root;
    for (size_t v = 0; v < in->vertex_count; ++v) { /* every vertex straight to its live wedge */
        uint32_t r = (uint32_t)v;
        while (root[r] != r)
            r = root[r];
        for (uint32_t x = (uint32_t)v; root[x] != r;) {
            uint32_t next = root[x];
            root[x] = r;
            x = next;
        }
    }
    uint32_t *ov_of_wedge = resurfi_alloc(s->alloc, in->vertex_count, sizeof *ov_of_wedge);
    o->side_tri = resurfi_alloc(s->alloc, o->nv, sizeof *o->side_tri);
    o->side_bary = resurfi_alloc(s->alloc, o->nv, 3 * sizeof *o->side_bary);
    double *best = resurfi_alloc(s->alloc, o->nv, sizeof *best);
    if (!ov_of_wedge || !o->side_tri || !o->side_bary || !best) {
        resurfi_free(s->alloc, ov_of_wedge);
        resurfi_free(s->alloc, best);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    memset(ov_of_wedge, 0xff, in->vertex_count * sizeof *ov_of_wedge);
    memset(o->side_tri, 0xff, o->nv * sizeof *o->side_tri);
    for (size_t u = 0; u < o->nu; ++u)
        if (o->ufirst[u] != NONE && o->ov_next[o->ufirst[u]] != NONE)
            for (uint32_t ov = o->ufirst[u]; ov != NONE; ov = o->ov_next[ov]) {
                ov_of_wedge[o->ov_wedge[ov]] = ov;
                best[ov] = INFINITY;
            }
    for (size_t t = 0; t < in->triangle_count; ++t) {
        const uint32_t *idx = in->indices + 3 * t;
        for (int k = 0; k < 3; ++k) {
            uint32_t ov = ov_of_wedge[root[idx[k]]];
            if (ov == NONE || o->side_tri[ov] == t)
                continue;
            double b[3];
            vec3 p = o->base[o->ov_u[ov]];
            vec3 q = resurfi_closest_on_triangle(p, resurfi_position(in, idx[0]), resurfi_position(in, idx[1]),
                                                 resurfi_position(in, idx[2]), b);
            double d2 = v3_dist2(p, q);
            if (d2 < best[ov]) {
                best[ov] = d2;
                o->side_tri[ov] = (uint32_t)t;
                memcpy(o->side_bary + 3 * (size_t)ov, b, sizeof b);
            }
        }
    }
    resurfi_free(s->alloc, ov_of_wedge);
    resurfi_free(s->alloc, best);
    return RESURF_OK;
}

/* The input triangle that gives output vertex ov its attributes, with barycentrics: at a seam, the closest one on
 * the vertex's side (find_sides); elsewhere the closest one on the vertex's side of any seam (its wedge's chart),
 * else the closest one. */
static uint32_t attribute_source(const simplifier *s, const output *o, uint32_t ov, double bary[3])
{
    if (o->side_tri && o->side_tri[ov] != NONE) {
        memcpy(bary, o->side_bary + 3 * (size_t)ov, 3 * sizeof *bary);
        return o->side_tri[ov];
    }
    uint32_t u = o->ov_u[ov];
    vec3 p = o->base[u];
    double d2;
    uint32_t t = resurfi_bvh_closest(s->bvh, p, INFINITY, NULL, bary, &d2);
    if (t == NONE || !s->charts.of_wedge)
        return t;
    uint32_t chart = s->charts.of_wedge[o->ov_wedge[ov]];
    if (chart == NONE || s->charts.of_input_tri[t] == chart)
        return t;
    double reach = sqrt(d2) + o->len[u];
    chart_search cs = {s->charts.of_input_tri, chart, NONE, INFINITY, {0, 0, 0}};
    uint32_t lo = s->charts.first[chart], hi = s->charts.first[chart + 1];
    if (hi - lo <= CHART_SCAN) {
        /* What the tree's search would find (bvh.c computes the same closest points and distances). */
        const resurf_mesh *in = s->in;
        for (uint32_t i = lo; i < hi; ++i) {
            const uint32_t *f = in->indices + 3 * (size_t)s->charts.tris[i];
            double b[3];
            vec3 q = resurfi_closest_on_triangle(p, resurfi_position(in, f[0]), resurfi_position(in, f[1]),
                                                 resurfi_position(in, f[2]), b);
            double q2 = v3_dist2(p, q);
            if (q2 <= reach * reach)
                chart_visit(&cs, s->charts.tris[i], q, b, q2);
        }
    } else {
        resurfi_bvh_within(s->bvh, p, reach * reach, chart_visit, &cs);
    }
    if (cs.best == NONE)
        return t;
    memcpy(bary, cs.bary, sizeof cs.bary);
    return cs.best;
}

/* The input corners a mirror vertex interpolates over: those of input triangle t's mirror, in the order of t's
 * corners (the same positions: the working mesh welds equal positions exactly), else t's own. */
static void mirror_corners(const simplifier *s, uint32_t t, uint32_t out[3])
{
    const uint32_t *f = s->in->indices + 3 * (size_t)t;
    memcpy(out, f, 3 * sizeof *out);
    if (!s->mirror || s->mirror[t] == NONE)
        return;
    const uint32_t *g = s->in->indices + 3 * (size_t)s->mirror[t];
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
            if (v3_dist2(resurfi_position(s->in, g[j]), resurfi_position(s->in, f[k])) == 0)
                out[k] = g[j];
}

/* Output vertex ov's attributes, interpolated at its source (attribute_source); a mirror vertex (ov >= nv) takes
 * its front vertex's source on the sheet's mirror, and its normal reversed. */
static void give_attributes(const simplifier *s, const output *o, resurf_mesh *m, const resurfi_skin_sets *skin,
                            uint32_t ov)
{
    const resurf_mesh *in = s->in;
    uint32_t front = ov < o->nv ? ov : o->mirror_front[ov - o->nv];
    double b[3];
    uint32_t t = attribute_source(s, o, front, b);
    uint32_t w = o->ov_wedge[front];
    uint32_t corners[3];
    const uint32_t *idx = NULL;
    if (t != NONE && ov >= o->nv) {
        mirror_corners(s, t, corners);
        idx = corners;
    } else if (t != NONE) {
        idx = in->indices + 3 * (size_t)t;
    }
    if (m->normals && v3_len2(v3_load(in->normals + 3 * (size_t)w)) == 0 && s->flat_shaded) {
        v3_store(m->normals + 3 * ov, v3(0, 0, 0)); /* shaded flat from the level's faces (facets_shade) */
    } else if (m->normals) {
        vec3 n = v3(0, 0, 0);
        const uint32_t *own = t == NONE ? NULL : in->indices + 3 * (size_t)t;
        if (own && s->restorer)
            n = resurfi_restorer_normal(s->restorer, t, b);
        else if (own)
            for (int k = 0; k < 3; ++k)
                n = v3_madd(n, v3_load(in->normals + 3 * (size_t)own[k]), b[k]);
        n = v3_normalize(n);
        if (v3_len2(n) == 0)
            n = v3_load(in->normals + 3 * (size_t)w);
        v3_store(m->normals + 3 * ov, ov < o->nv ? n : v3_neg(n));
    }
    for (unsigned k = 0; k < m->texcoord_count; ++k) {
        if (!m->texcoords[k])
            continue;
        const double *src = in->texcoords[k];
        for (int c = 0; c < 2; ++c) {
            double v = 0;
            if (idx)
                for (int i = 0; i < 3; ++i)
                    v += b[i] * src[2 * (size_t)idx[i] + c];
            else
                v = src[2 * (size_t)w + c];
            m->texcoords[k][2 * (size_t)ov + c] = v;
        }
    }
    if (m->colors)
        for (int c = 0; c < 4; ++c) {
            double v = 0;
            if (idx)
                for (int i = 0; i < 3; ++i)
                    v += b[i] * in->colors[4 * (size_t)idx[i] + c];
            else
                v = in->colors[4 * (size_t)w + c];
            m->colors[4 * (size_t)ov + c] = v;
        }
    if (skin->count) {
        const uint32_t own[3] = {w, w, w};
        const double whole[3] = {1, 0, 0};
        resurfi_skin_combine(in, skin, idx ? idx : own, idx ? b : whole, m, ov);
    }
    for (size_t e = 0; e < m->extra_count; ++e) {
        const resurf_attribute *a = &in->extras[e];
        unsigned nc = a->components;
        if (resurfi_skin_owns(skin, e))
            continue;
        for (unsigned c = 0; c < nc; ++c) {
            double v = 0;
            if (!a->data)
                break;
            if (idx)
                for (int i = 0; i < 3; ++i)
                    v += b[i] * (double)a->data[(size_t)nc * idx[i] + c];
            else
                v = a->data[(size_t)nc * w + c];
            m->extras[e].data[(size_t)nc * ov + c] = (float)v;
        }
    }
}

static int attribute_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    output_job *j = ctx;
    resurfi_skin_sets skin; /* joints and weights: combined as influences (skin.c), never as numbers */
    resurfi_skin_find_sets(j->s->in, &skin);
    for (size_t ov = begin; ov < end; ++ov)
        give_attributes(j->s, j->o, j->m, &skin, (uint32_t)ov);
    return 0;
}

/* Numbers the output vertices and positions of the current working mesh. */
static resurf_status number_output(simplifier *s, output *o)
{
    size_t nt = 0; /* s->alive_tris counts a sheet's mirrors too */
    for (size_t t = 0; t < s->tri_count; ++t)
        nt += !s->tri[t].dead;
    o->nt = nt;
    o->tris = resurfi_alloc(s->alloc, nt, sizeof *o->tris);
    o->pos_index = resurfi_alloc(s->alloc, s->pos_count, sizeof *o->pos_index);
    size_t cap_u = 3 * nt < s->pos_count ? 3 * nt : s->pos_count;
    o->upos = resurfi_alloc(s->alloc, cap_u, sizeof *o->upos);
    o->ufirst = resurfi_alloc(s->alloc, cap_u, sizeof *o->ufirst);
    /* Output vertices: at most one per corner, and at most one per input vertex: a wedge is an input vertex and
     * stays with its position (a collapse gives the removed end's corners the kept end's wedges), so no two
     * positions share one. The second bound is the smaller for all but the coarsest levels. */
    size_t cap_v = 3 * nt < s->in->vertex_count ? 3 * nt : s->in->vertex_count;
    o->ov_next = resurfi_alloc(s->alloc, cap_v, sizeof *o->ov_next);
    o->ov_u = resurfi_alloc(s->alloc, cap_v, sizeof *o->ov_u);
    o->ov_wedge = resurfi_alloc(s->alloc, cap_v, sizeof *o->ov_wedge);
    o->corner_ov = resurfi_alloc(s->alloc, 3 * nt, sizeof *o->corner_ov);
    if (!o->tris || !o->pos_index || !o->upos || !o->ufirst || !o->ov_next || !o->ov_u || !o->ov_wedge ||
        !o->corner_ov)
        return RESURF_ERR_OUT_OF_MEMORY;
    memset(o->pos_index, 0xff, s->pos_count * sizeof *o->pos_index);
    size_t k = 0;
    for (size_t t = 0; t < s->tri_count; ++t)
        if (!s->tri[t].dead)
            o->tris[k++] = (uint32_t)t;
    for (size_t i = 0; i < nt; ++i)
        for (int c = 0; c < 3; ++c) {
            uint32_t p = TV(3 * o->tris[i] + c), w = TW(3 * o->tris[i] + c);
            uint32_t u = o->pos_index[p];
            if (u == NONE) {
                u = o->pos_index[p] = (uint32_t)o->nu++;
                o->upos[u] = p;
                o->ufirst[u] = NONE;
            }
            uint32_t ov = o->ufirst[u];
            while (ov != NONE && o->ov_wedge[ov] != w)
                ov = o->ov_next[ov];
            if (ov == NONE) {
                if (o->nv == cap_v)
                    return RESURF_ERR_INTERNAL; /* the bound above broken: a bug, never a write past the end */
                ov = (uint32_t)o->nv++;
                o->ov_u[ov] = u;
                o->ov_wedge[ov] = w;
                o->ov_next[ov] = o->ufirst[u];
                o->ufirst[u] = ov;
            }
            o->corner_ov[3 * i + c] = ov;
        }
    return RESURF_OK;
}

/* The back of each double-sided sheet (setup.c's keep_sheets): every output triangle whose input triangle has a
 * mirror is written again, reversed, over mirror vertices of its own (the same positions, the mirror's attributes,
 * the normal reversed), so a level shows both sides as the input did. */
static resurf_status mirror_sheets(simplifier *s, output *o)
{
    if (!s->mirror)
        return RESURF_OK;
    for (size_t i = 0; i < o->nt; ++i)
        o->mirror_nt += s->mirror[s->src[o->tris[i]]] != NONE;
    if (!o->mirror_nt)
        return RESURF_OK;
    uint32_t *mirror_of = resurfi_alloc(s->alloc, o->nv, sizeof *mirror_of);
    o->mirror_tris = resurfi_alloc(s->alloc, o->mirror_nt, sizeof *o->mirror_tris);
    o->mirror_front = resurfi_alloc(s->alloc, 3 * o->mirror_nt, sizeof *o->mirror_front);
    if (!mirror_of || !o->mirror_tris || !o->mirror_front) {
        resurfi_free(s->alloc, mirror_of);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    memset(mirror_of, 0xff, o->nv * sizeof *mirror_of);
    size_t k = 0;
    for (size_t i = 0; i < o->nt; ++i) {
        if (s->mirror[s->src[o->tris[i]]] == NONE)
            continue;
        o->mirror_tris[k++] = (uint32_t)i;
        for (int c = 0; c < 3; ++c) {
            uint32_t ov = o->corner_ov[3 * i + c];
            if (mirror_of[ov] == NONE) {
                mirror_of[ov] = (uint32_t)(o->nv + o->mirror_nv);
                o->mirror_front[o->mirror_nv++] = ov;
            }
        }
    }
    /* the mirror triangles' corners, reversed, after the front's */
    uint32_t *corners = resurfi_alloc(s->alloc, 3 * (o->nt + o->mirror_nt), sizeof *corners);
    if (!corners) {
        resurfi_free(s->alloc, mirror_of);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    memcpy(corners, o->corner_ov, 3 * o->nt * sizeof *corners);
    for (size_t j = 0; j < o->mirror_nt; ++j)
        for (int c = 0; c < 3; ++c)
            corners[3 * (o->nt + j) + (size_t)c] = mirror_of[o->corner_ov[3 * (size_t)o->mirror_tris[j] + 2 - c]];
    resurfi_free(s->alloc, mirror_of);
    resurfi_free(s->alloc, o->corner_ov);
    o->corner_ov = corners;
    return RESURF_OK;
}

/* len[u]: the longest edge at each used position (base positions). */
static void measure_edges(output *o)
{
    memset(o->len, 0, o->nu * sizeof *o->len);
    for (size_t i = 0; i < o->nt; ++i) {
        const uint32_t *c = o->corner_ov + 3 * i;
        for (int k = 0; k < 3; ++k) {
            uint32_t u = o->ov_u[c[k]], w = o->ov_u[c[(k + 1) % 3]];
            double l = v3_dist(o->base[u], o->base[w]);
            o->len[u] = l > o->len[u] ? l : o->len[u];
            o->len[w] = l > o->len[w] ? l : o->len[w];
        }
    }
}

/* Final positions: POST restoration, then the sag offset: each vertex moves along S's normal by sag_offset × (the
 * mean over its incident triangle corners of −n·(p_w − p_v)/4, less the depth of M's facets under S there). For a
 * vertex on S and a neighbour w at chord length h where S bends by κ, −n·(p_w − p_v) ≈ h²κ/2, so the term is the
 * chord's sag h²κ/8, the mean depth of the LOD's facets under S; M's facets lie under S by their own depth
 * (facet_depth), and the reported distances measure against M: the difference makes the LOD's facets straddle M.
 * Each side is measured along its own edges, so a LOD that kept M's spacing across the curvature (a cylinder's
 * first collapses are along its axis) is not offset. The model is then bounded by the measured gap (gap_block):
 * at most twice it, never of the other sign (docs/restoring.md §8 has the figures). */
static resurf_status place_output(simplifier *s, output *o)
{
    size_t nu = o->nu;
    o->base = resurfi_alloc(s->alloc, nu, sizeof *o->base);
    o->final = resurfi_alloc(s->alloc, nu, sizeof *o->final);
    o->len = resurfi_calloc(s->alloc, nu, sizeof *o->len);
    o->held = resurfi_alloc(s->alloc, nu, sizeof *o->held);
    if (!o->base || !o->final || !o->len || !o->held)
        return RESURF_ERR_OUT_OF_MEMORY;
    for (size_t u = 0; u < nu; ++u) {
        o->base[u] = s->P[o->upos[u]].p;
        pos_flags f = s->P[o->upos[u]].flags;
        o->held[u] = f & (POS_LOCKED | POS_CORNER) ? HELD_PLACE
                     : f & (POS_CREASE | POS_TOUCHES_FEATURE | POS_JUNCTION) ? HELD_OFFSET : 0;
    }
    if (s->last_level) { /* no more collapses: the working mesh goes before the output's arrays come */
        resurfi_free(s->alloc, s->P_mem);
        resurfi_free(s->alloc, s->tri);
        resurfi_free(s->alloc, s->mark);
        s->P_mem = NULL, s->P = NULL, s->tri = NULL, s->mark = NULL;
        schedule_drop_marks(s);
    }
    measure_edges(o);
    output_job job = {s, o, NULL};
    if (s->opt.restore == RESURF_RESTORE_POST && s->restorer) {
        if (!(o->outcome = resurfi_alloc(s->alloc, nu, 1)))
            return RESURF_ERR_OUT_OF_MEMORY;
        resurfi_pool_for(s->pool, nu, BLOCK_POSITIONS, post_restore_block, &job);
        for (size_t u = 0; u < nu; ++u) {
            s->rep.restored += !o->held[u];
            s->rep.restore_left += o->outcome[u];
        }
    }
    int offset = s->restorer && s->opt.restore != RESURF_RESTORE_NONE && s->opt.sag_offset > 0;
    if (offset) {
        o->normal = resurfi_alloc(s->alloc, nu, sizeof *o->normal);
        o->sag_sum = resurfi_calloc(s->alloc, nu, sizeof *o->sag_sum);
        o->sag_count = resurfi_calloc(s->alloc, nu, sizeof *o->sag_count);
        o->m_depth = resurfi_calloc(s->alloc, nu, sizeof *o->m_depth);
        o->gap = resurfi_alloc(s->alloc, o->nt ? o->nt : 1, sizeof *o->gap);
        o->gap_sum = resurfi_calloc(s->alloc, nu, sizeof *o->gap_sum);
        if (!o->normal || !o->sag_sum || !o->sag_count || !o->m_depth || !o->gap || !o->gap_sum)
            return RESURF_ERR_OUT_OF_MEMORY;
        resurfi_pool_for(s->pool, nu, BLOCK_POSITIONS, normal_block, &job);
    }
    if (s->opt.restore == RESURF_RESTORE_POST && s->restorer)
        measure_edges(o);
    if (offset)
        resurfi_pool_for(s->pool, o->nt, BLOCK_POSITIONS, gap_block, &job);
    for (size_t i = 0; i < o->nt && offset; ++i) {
        uint32_t u[3];
        for (int c = 0; c < 3; ++c)
            u[c] = o->ov_u[o->corner_ov[3 * i + c]];
        for (int c = 0; c < 3; ++c) {
            vec3 pv = o->base[u[c]];
            o->gap_sum[u[c]] += o->gap[i];
            for (int d = 1; d < 3; ++d) {
                vec3 pw = o->base[u[(c + d) % 3]];
                o->sag_sum[u[c]] -= v3_dot(o->normal[u[c]], v3_sub(pw, pv));
                o->sag_count[u[c]]++;
            }
        }
    }
    for (size_t u = 0; u < nu; ++u) {
        o->final[u] = o->base[u];
        if (!offset || !o->sag_count[u] || o->held[u])
            continue; /* a corner or a crease vertex: the model of a smooth surface around it does not hold */
        double sag = o->sag_sum[u] / (4.0 * o->sag_count[u]) - o->m_depth[u];
        /* The model holds where M is smooth at the LOD's scale; there it agrees with what M does around v. Where
         * not (a scan's noise, a ridge sharper than its normals), it is bounded by that: of the measured gap's
         * sign, at most twice it. */
        double measured = o->gap_sum[u] / (o->sag_count[u] / 2.0);
        double lo = measured < 0 ? 2 * measured : 0, hi = measured > 0 ? 2 * measured : 0;
        sag = s->opt.sag_offset * (sag < lo ? lo : sag > hi ? hi : sag);
        double cap = 0.25 * o->len[u]; /* a fold or a spike, not a sag */
        sag = sag > cap ? cap : sag < -cap ? -cap : sag;
        o->final[u] = v3_madd(o->base[u], o->normal[u], sag);
    }
    return RESURF_OK;
}

/* An empty mesh (or one of the given counts) with the input's attribute layout. */
static resurf_status create_like(const resurf_allocator *alloc, const resurf_mesh *in, size_t nv, size_t nt,
                                 resurf_mesh **out, resurf_error *error)
{
    unsigned attrs = 0;
    if (in->normals)
        attrs |= RESURF_ATTR_NORMALS;
    if (in->colors)
        attrs |= RESURF_ATTR_COLORS;
    for (unsigned k = 0; k < in->texcoord_count && k < RESURF_MAX_TEXCOORD_SETS; ++k)
        if (in->texcoords[k])
            attrs |= RESURF_ATTR_TEXCOORD0 << k;
    resurf_status st = resurf_mesh_create_with(nv, nt, attrs, alloc, out, error);
    if (st != RESURF_OK)
        return st;
    resurf_mesh *m = *out;
    m->texcoord_count = in->texcoord_count;
    if (in->colors)
        m->color_components = in->color_components;
    for (size_t e = 0; e < in->extra_count; ++e) {
        if ((st = resurf_mesh_add_extra(m, in->extras[e].name, in->extras[e].components, NULL, error)) != RESURF_OK)
            break;
    }
    if (st == RESURF_OK && in->triangle_groups && in->group_count) {
        m->triangle_groups = resurfi_calloc(&m->allocator, nt, sizeof *m->triangle_groups);
        m->group_names = resurfi_calloc(&m->allocator, in->group_count, sizeof *m->group_names);
        if (!m->triangle_groups || !m->group_names)
            st = RESURF_ERR_OUT_OF_MEMORY;
        else
            m->group_count = in->group_count;
        for (size_t g = 0; st == RESURF_OK && g < in->group_count; ++g) {
            const char *name = in->group_names[g] ? in->group_names[g] : "";
            size_t len = strlen(name);
            if (!(m->group_names[g] = resurfi_alloc(&m->allocator, len + 1, 1)))
                st = RESURF_ERR_OUT_OF_MEMORY;
            else
                memcpy(m->group_names[g], name, len + 1);
        }
        if (st == RESURF_ERR_OUT_OF_MEMORY)
            resurfi_error(error, st, "out of memory copying triangle groups");
    }
    if (st != RESURF_OK) {
        resurf_mesh_free(m);
        *out = NULL;
    }
    return st;
}

resurf_status build_output(simplifier *s, resurf_mesh **out, resurf_simplify_report *rep, resurf_error *error)
{
    output o;
    memset(&o, 0, sizeof o);
    resurf_mesh *m = NULL;
    resurf_status st = number_output(s, &o);
    if (st == RESURF_OK)
        st = place_output(s, &o);
    if (st == RESURF_OK)
        st = mirror_sheets(s, &o);
    size_t nv = o.nv + o.mirror_nv, nt = o.nt + o.mirror_nt;
    if (st == RESURF_OK && (st = create_like(s->alloc, s->in, nv, nt, &m, error)) != RESURF_OK) {
        output_free(&o, s->alloc);
        return st;
    }
    if (st == RESURF_OK) {
        for (size_t v = 0; v < nv; ++v)
            v3_store(m->positions + 3 * v, o.final[o.ov_u[v < o.nv ? v : o.mirror_front[v - o.nv]]]);
        memcpy(m->indices, o.corner_ov, 3 * nt * sizeof *m->indices);
        if (m->triangle_groups)
            for (size_t i = 0; i < nt; ++i) {
                uint32_t t = s->src[o.tris[i < o.nt ? i : o.mirror_tris[i - o.nt]]];
                m->triangle_groups[i] = s->in->triangle_groups[i < o.nt ? t : s->mirror[t]];
            }
        if (has_attributes(s->in) && s->bvh && (st = find_sides(s, &o)) == RESURF_OK) {
            output_job job = {s, &o, m};
            resurfi_pool_for(s->pool, nv, BLOCK_POSITIONS, attribute_block, &job);
        }
        *rep = s->rep;
        rep->triangles = nt;
        rep->vertices = nv;
        rep->positions = o.nu;
        if (st == RESURF_OK)
            st = measure_level(s, m, rep);
        if (st == RESURF_OK && s->flat_shaded && (st = facets_shade(m)) == RESURF_OK)
            rep->vertices = m->vertex_count;
    }
    output_free(&o, s->alloc);
    if (st != RESURF_OK) {
        resurf_mesh_free(m);
        return resurfi_error(error, st, st == RESURF_ERR_INTERNAL ? "internal error: a wedge at two positions"
                                                                  : "out of memory building the simplified mesh");
    }
    *out = m;
    return RESURF_OK;
}
