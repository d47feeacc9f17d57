/* Attribute quadrics: normals, texture coordinates and colours in the collapse cost (Hoppe, "New quadric metric
 * for simplifying meshes with appearance attributes", 1999, in the sparse form his attribute block allows).
 *
 * On each input triangle every weighed attribute component s is a linear function of the position,
 * s(x) = g·x + d, with g in the triangle's plane (docs/restoring.md §11 has the derivation). A wedge (an
 * attribute vertex: one side of a seam at one position) sums, over its triangles t with weights w_t (the
 * geometric quadric's: area, floored), the squared misfit Σ_t w_t Σ_j (s_j − g_tj·x − d_tj)² of an attribute
 * value s at a place x. Its minimum over s is reached at s_j = (G_j·x + D_j) / W, and what is left,
 *     E(x) = xᵀA x + 2 bᵀx + c − Σ_j (G_j·x + D_j)² / W,
 * with A = Σ w g gᵀ, b = Σ w d g, c = Σ w d² (summed over components too), G_j = Σ w g_j, D_j = Σ w d_j and
 * W = Σ w, is how far the attributes of the triangles merged into the wedge are from one linear field: what a
 * coarse triangle interpolating its corners' values cannot show. A collapse merges each wedge of the removed end
 * into its image at the kept end (the wedge map of collapse.c), so its attribute cost is the sum of E over the
 * merged wedges at the new place. Wedges on either side of a seam never mix: a seam's two sides are fitted apart.
 *
 * One record per wedge: 11 + 4 × (components) doubles (UVs alone: 152 bytes per wedge), allocated only when the
 * input has an attribute whose weight is above 0. A component enters scaled by its weight × the bounding-box
 * diagonal, so that a weight of 1 prices an attribute difference of 1 like a distance of one diagonal. The place
 * of a collapse stays the geometric quadric's (the restoration moves it onto S in any case); only the ranking
 * changes. */
#include <math.h>

#include "simplify_internal.h"

enum { ATTR_HEAD = 11 }; /* A (6), b (3), c, W; then G (3) and D per component */

/* Morph targets (extras "targets[t].POSITION", RESURF_MORPH_TARGET_PREFIX): their deltas are positions, so they
 * enter in geometric units, weight × 1 (docs/restoring.md §12): a delta that departs by L from one linear field over
 * the merged triangles counts like a distance L off the surface, which is what the level shows at morph weight 1.
 * At most ATTR_MORPH_TARGETS of them, those with the largest delta (ties: the first). */
static void choose_morph_components(simplifier *s)
{
    const resurf_mesh *in = s->in;
    attr_quadrics *q = &s->attr;
    if (!(s->opt.morph_weight > 0))
        return;
    size_t chosen[ATTR_MORPH_TARGETS];
    double peak[ATTR_MORPH_TARGETS];
    size_t n = 0;
    for (size_t e = 0; e < in->extra_count; ++e) {
        const resurf_attribute *x = &in->extras[e];
        size_t len = strlen(RESURF_MORPH_TARGET_PREFIX), name_len = strlen(x->name);
        if (strncmp(x->name, RESURF_MORPH_TARGET_PREFIX, len) || name_len < len + 10 ||
            strcmp(x->name + name_len - 10, "].POSITION") || x->components != 3 || !x->data)
            continue;
        double m = 0;
        for (size_t v = 0; v < in->vertex_count; ++v) {
            const float *d = x->data + 3 * v;
            double l2 = (double)d[0] * d[0] + (double)d[1] * d[1] + (double)d[2] * d[2];
            m = l2 > m ? l2 : m;
        }
        if (!(m > 0) || !isfinite(m))
            continue;
        size_t at = n < ATTR_MORPH_TARGETS ? n++ : ATTR_MORPH_TARGETS;
        if (at == ATTR_MORPH_TARGETS) { /* full: replace the smallest when this one is larger */
            size_t low = 0;
            for (size_t k = 1; k < n; ++k)
                low = peak[k] < peak[low] ? k : low;
            if (!(m > peak[low]))
                continue;
            at = low;
        }
        chosen[at] = e, peak[at] = m;
    }
    for (size_t k = 0; k < n; ++k)
        for (unsigned c = 0; c < 3; ++c)
            q->src[q->count] = NULL, q->srcf[q->count] = in->extras[chosen[k]].data, q->step[q->count] = 3,
            q->offset[q->count] = c, q->scale[q->count++] = s->opt.morph_weight;
}

/* The value of component j at input vertex v. */
static inline double component(const attr_quadrics *q, unsigned j, uint32_t v)
{
    size_t i = (size_t)q->step[j] * v + q->offset[j];
    return q->src[j] ? q->src[j][i] : (double)q->srcf[j][i];
}

/* The components the options weigh, from the input's arrays. */
static void choose_components(simplifier *s)
{
    const resurf_mesh *in = s->in;
    attr_quadrics *q = &s->attr;
    double d = s->diagonal > 0 ? s->diagonal : 1;
    q->count = 0;
    if (in->normals && s->opt.normal_weight > 0)
        for (unsigned k = 0; k < 3; ++k)
            q->src[q->count] = in->normals, q->step[q->count] = 3, q->offset[q->count] = k,
            q->scale[q->count++] = s->opt.normal_weight * d;
    for (unsigned t = 0; t < in->texcoord_count && t < RESURF_MAX_TEXCOORD_SETS; ++t)
        if (in->texcoords[t] && s->opt.texcoord_weight > 0)
            for (unsigned k = 0; k < 2; ++k)
                q->src[q->count] = in->texcoords[t], q->step[q->count] = 2, q->offset[q->count] = k,
                q->scale[q->count++] = s->opt.texcoord_weight * d;
    if (in->colors && s->opt.color_weight > 0)
        for (unsigned k = 0; k < (in->color_components == 3 ? 3u : 4u); ++k)
            q->src[q->count] = in->colors, q->step[q->count] = 4, q->offset[q->count] = k,
            q->scale[q->count++] = s->opt.color_weight * d;
    choose_morph_components(s);
    q->stride = ATTR_HEAD + 4 * (size_t)q->count;
}

/* Adds triangle t's attribute fields, weight w, to record r. */
static void add_triangle(const simplifier *s, uint32_t t, double *r)
{
    const attr_quadrics *q = &s->attr;
    vec3 x0 = v3_sub(s->P[TV(3 * t)].p, s->origin), x1 = v3_sub(s->P[TV(3 * t + 1)].p, s->origin),
         x2 = v3_sub(s->P[TV(3 * t + 2)].p, s->origin);
    vec3 e1 = v3_sub(x1, x0), e2 = v3_sub(x2, x0), n = v3_cross(e1, e2);
    double n2 = v3_len2(n);
    if (!(n2 > 0) || !isfinite(n2))
        return;
    double w = 0.5 * sqrt(n2);
    if (w < s->area_floor) /* the geometric quadric's weight (analyse_position) */
        w = s->area_floor;
    /* g·e1 = s1 − s0, g·e2 = s2 − s0, g·n = 0 */
    vec3 u = v3_scale(v3_cross(e2, n), 1 / n2), v = v3_scale(v3_cross(n, e1), 1 / n2);
    uint32_t w0 = TW(3 * t), w1 = TW(3 * t + 1), w2 = TW(3 * t + 2);
    r[10] += w;
    for (unsigned j = 0; j < q->count; ++j) {
        double s0 = q->scale[j] * component(q, j, w0), s1 = q->scale[j] * component(q, j, w1),
               s2 = q->scale[j] * component(q, j, w2);
        vec3 g = v3_add(v3_scale(u, s1 - s0), v3_scale(v, s2 - s0));
        double d = s0 - v3_dot(g, x0);
        if (!v3_finite(g) || !isfinite(d))
            continue;
        r[0] += w * g.x * g.x, r[1] += w * g.x * g.y, r[2] += w * g.x * g.z;
        r[3] += w * g.y * g.y, r[4] += w * g.y * g.z, r[5] += w * g.z * g.z;
        r[6] += w * d * g.x, r[7] += w * d * g.y, r[8] += w * d * g.z;
        r[9] += w * d * d;
        double *gd = r + ATTR_HEAD + 4 * j;
        gd[0] += w * g.x, gd[1] += w * g.y, gd[2] += w * g.z, gd[3] += w * d;
    }
}

typedef struct attr_job {
    simplifier *s;
    scratch *scratch;
} attr_job;

/* The records of the wedges of a block of positions: a wedge belongs to one position, so blocks write apart, and
 * each record sums its triangles in the fan's order whatever the thread count. */
static int attr_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    attr_job *j = ctx;
    simplifier *s = j->s;
    scratch *sc = &j->scratch[worker];
    size_t stride = s->attr.stride;
    for (size_t p = begin * BLOCK_POSITIONS; p < end * BLOCK_POSITIONS && p < s->pos_count; ++p) {
        if (s->P[p].flags & POS_DEAD)
            continue;
        if (!gather_fan(s, (uint32_t)p, &sc->fan, 0))
            return 1;
        for (size_t i = 0; i < sc->fan.count; ++i)
            memset(s->attr.data + stride * TW(sc->fan.data[i]), 0, stride * sizeof(double));
        for (size_t i = 0; i < sc->fan.count; ++i) {
            uint32_t c = sc->fan.data[i];
            add_triangle(s, c / 3, s->attr.data + stride * TW(c));
        }
    }
    return 0;
}

/* Builds the records, or none when no attribute is weighed. */
resurf_status attributes_start(simplifier *s, scratch *scratch)
{
    choose_components(s);
    if (s->attr.count == 0 || s->tri_count == 0)
        return RESURF_OK;
    if (!(s->attr.data = resurfi_alloc(s->alloc, s->in->vertex_count, s->attr.stride * sizeof(double))))
        return RESURF_ERR_OUT_OF_MEMORY;
    attr_job job = {s, scratch};
    size_t blocks = (s->pos_count + BLOCK_POSITIONS - 1) / BLOCK_POSITIONS;
    return resurfi_pool_for(s->pool, blocks, 1, attr_block, &job) ? RESURF_ERR_OUT_OF_MEMORY : RESURF_OK;
}

/* The quadric form of record r at x (relative to the origin). */
static double form(const double *r, vec3 x)
{
    return r[0] * x.x * x.x + r[3] * x.y * x.y + r[5] * x.z * x.z +
           2 * (r[1] * x.x * x.y + r[2] * x.x * x.z + r[4] * x.y * x.z) + 2 * (r[6] * x.x + r[7] * x.y + r[8] * x.z) +
           r[9];
}

/* E(x) of the sum of records r and t, without forming the sum: the form is linear in the record. */
static double merged_misfit(const attr_quadrics *q, const double *r, const double *t, vec3 x)
{
    double w = r[10] + t[10];
    if (!(w > 0))
        return 0;
    double fit = 0;
    for (unsigned j = 0; j < q->count; ++j) {
        const double *gr = r + ATTR_HEAD + 4 * j, *gt = t + ATTR_HEAD + 4 * j;
        double v = (gr[0] + gt[0]) * x.x + (gr[1] + gt[1]) * x.y + (gr[2] + gt[2]) * x.z + gr[3] + gt[3];
        fit += v * v;
    }
    double e = form(r, x) + form(t, x) - fit / w;
    return e > 0 ? e : 0; /* >= 0 exactly (Cauchy-Schwarz); rounding may cross */
}

/* The attribute cost of collapsing edge (a, b) planned in pl, the vertex at p: the misfit of each pair of wedges
 * the collapse merges (those of the edge's triangles at a and at b; the rule of collapse.c lets an end go only
 * when all its wedges lie on them). */
double attribute_cost(const simplifier *s, const plan *pl, uint32_t a, uint32_t b, vec3 p)
{
    const attr_quadrics *q = &s->attr;
    if (!q->data)
        return 0;
    vec3 x = v3_sub(p, s->origin);
    double cost = 0;
    uint32_t seen_a = NONE, seen_b = NONE;
    for (int k = 0; k < pl->shared_count; ++k) {
        uint32_t wa = TW(corner_at(s, pl->shared[k], a)), wb = TW(corner_at(s, pl->shared[k], b));
        if (wa == seen_a && wb == seen_b)
            continue;
        seen_a = wa, seen_b = wb;
        cost += merged_misfit(q, q->data + q->stride * wa, q->data + q->stride * wb, x);
    }
    return cost;
}

/* Wedge `from` (of the removed end) merges into wedge `to`. */
void attribute_merge(simplifier *s, uint32_t to, uint32_t from)
{
    attr_quadrics *q = &s->attr;
    if (!q->data || to == from)
        return;
    double *r = q->data + q->stride * to;
    const double *t = q->data + q->stride * from;
    for (size_t k = 0; k < q->stride; ++k)
        r[k] += t[k];
}
