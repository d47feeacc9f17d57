/* Attribute quadrics: normals, texture coordinates, colours and skin influences in the collapse cost (Hoppe, "New
 * quadric metric for simplifying meshes with appearance attributes", 1999, in the sparse form his attribute block
 * allows).
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
 * changes.
 *
 * Skin influences (JOINTS_n / WEIGHTS_n) are a weight per joint, too many components for a record per wedge. They
 * enter as SKIN_FIELDS random projections of that vector (skin_fields): each is linear in the weights, so it is a
 * linear field wherever the skinning is, and the fields' misfit estimates the weight vectors' own. Without them a
 * straight limb's rings where the weights blend cost no geometry and go first. */
#include <math.h>

#include "../hash.h"
#include "simplify_internal.h"

enum { ATTR_HEAD = 11 }; /* A (6), b (3), c, W; then G (3) and D per component */

/* A joint's pseudo-random value in skin field f: uniform with unit variance (in ±√3), over √SKIN_FIELDS, so the
 * fields' squared difference between two weight vectors is, in expectation, their squared distance. */
static double joint_value(double joint, unsigned f)
{
    uint64_t x = resurfi_mix64((uint64_t)joint * SKIN_FIELDS + f + RESURFI_GOLDEN_GAMMA);
    double u = (double)(x >> 11) / 9007199254740992.0;
    return sqrt(3.0) * (2 * u - 1) / sqrt((double)SKIN_FIELDS);
}

/* The skin fields of every input vertex: Σ over its influences of weight × reach × joint_value, where a joint's
 * reach is half the diagonal of the box of the vertices it moves (at least 1e-3 of the mesh's diagonal). Linear in
 * the weights, so a triangle's fields interpolate like its skinning does. A weight moved from one joint to another
 * displaces a posed vertex by the weight × the distance between where the two joints put it, about the joints'
 * size for a bend of 70 to 90 degrees: the reach prices a finger's blend like a finger, not like the body. */
static resurf_status skin_fields(simplifier *s)
{
    const resurf_mesh *in = s->in;
    resurfi_skin_sets sets;
    resurfi_skin_find_sets(in, &sets);
    if (!sets.count || !(s->opt.skin_weight > 0))
        return RESURF_OK;
    enum { MAX_JOINT = 65535 }; /* glTF joints are unsigned bytes or shorts */
    size_t joints = 0;
    for (size_t v = 0; v < in->vertex_count; ++v)
        for (unsigned k = 0; k < 4 * sets.count; ++k) {
            double joint = in->extras[sets.joints[k / 4]].data[4 * v + k % 4];
            if (joint >= 0 && joint <= MAX_JOINT && (size_t)joint + 1 > joints)
                joints = (size_t)joint + 1;
        }
    double *box = resurfi_alloc(s->alloc, joints, 6 * sizeof *box);
    double *f = s->attr.skin = resurfi_calloc(s->alloc, in->vertex_count, SKIN_FIELDS * sizeof(double));
    if (!box || !f) {
        resurfi_free(s->alloc, box);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    for (size_t j = 0; j < joints; ++j)
        for (int c = 0; c < 3; ++c)
            box[6 * j + c] = INFINITY, box[6 * j + 3 + c] = -INFINITY;
    for (size_t v = 0; v < in->vertex_count; ++v)
        for (unsigned k = 0; k < 4 * sets.count; ++k) {
            double joint = in->extras[sets.joints[k / 4]].data[4 * v + k % 4];
            double weight = in->extras[sets.weights[k / 4]].data[4 * v + k % 4];
            if (weight > 0 && joint >= 0 && joint <= MAX_JOINT)
                for (int c = 0; c < 3; ++c) {
                    double x = in->positions[3 * v + (size_t)c];
                    double *lo = &box[6 * (size_t)joint + (size_t)c], *hi = lo + 3;
                    *lo = x < *lo ? x : *lo;
                    *hi = x > *hi ? x : *hi;
                }
        }
    double floor_reach = 1e-3 * (s->diagonal > 0 ? s->diagonal : 1);
    for (size_t j = 0; j < joints; ++j) { /* box[6 j] becomes the reach */
        double d2 = 0;
        for (int c = 0; c < 3; ++c) {
            double e = box[6 * j + 3 + (size_t)c] - box[6 * j + (size_t)c];
            d2 += e > 0 && isfinite(e) ? e * e : 0;
        }
        double reach = 0.5 * sqrt(d2);
        box[6 * j] = reach > floor_reach ? reach : floor_reach;
    }
    for (size_t v = 0; v < in->vertex_count; ++v)
        for (unsigned k = 0; k < 4 * sets.count; ++k) {
            double joint = in->extras[sets.joints[k / 4]].data[4 * v + k % 4];
            double weight = in->extras[sets.weights[k / 4]].data[4 * v + k % 4];
            if (weight > 0 && isfinite(weight) && joint >= 0 && joint <= MAX_JOINT)
                for (unsigned c = 0; c < SKIN_FIELDS; ++c)
                    f[SKIN_FIELDS * v + c] += weight * box[6 * (size_t)joint] * joint_value(floor(joint), c);
        }
    resurfi_free(s->alloc, box);
    return RESURF_OK;
}

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
        if (in->texcoords[t] && s->opt.texcoord_weight > 0 && !(s->opt.unsampled_texcoords >> t & 1))
            for (unsigned k = 0; k < 2; ++k)
                q->src[q->count] = in->texcoords[t], q->step[q->count] = 2, q->offset[q->count] = k,
                q->scale[q->count++] = s->opt.texcoord_weight * d;
    if (in->colors && s->opt.color_weight > 0)
        for (unsigned k = 0; k < (in->color_components == 3 ? 3u : 4u); ++k)
            q->src[q->count] = in->colors, q->step[q->count] = 4, q->offset[q->count] = k,
            q->scale[q->count++] = s->opt.color_weight * d;
    for (unsigned k = 0; q->skin && k < SKIN_FIELDS; ++k)
        q->src[q->count] = q->skin, q->step[q->count] = SKIN_FIELDS, q->offset[q->count] = k,
        q->scale[q->count++] = s->opt.skin_weight; /* the fields are lengths already (the joints' reach) */
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
    if (skin_fields(s) != RESURF_OK)
        return RESURF_ERR_OUT_OF_MEMORY;
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
