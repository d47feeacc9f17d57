/* Skin influences: the JOINTS_n / WEIGHTS_n extras of a mesh taken as one list of (joint, weight) influences per
 * vertex, never as numbers. A joint index interpolated between two corners names a joint neither corner had (or
 * none: 2.5), and weights interpolated apart from their joints no longer describe the same bones.
 *
 * resurfi_skin_combine: an output vertex taken at a point of an input triangle gets the influences of the three
 * corners, each weighted by its barycentric, equal joints merged, the strongest 4 per set kept (as many sets as the
 * input has, strongest first), renormalized to sum 1. Skinning is linear in the weights for a fixed set of joints,
 * so at a point inside a triangle whose corners share their joints this is exactly the interpolated skinning;
 * dropping the weakest influences and renormalizing is what every exporter does to fit 4 per set.
 *
 * resurfi_skin_snap: the values as a file will store them. Weights written as normalized integers (255 or 65535
 * units per 1) are rounded by largest remainder over all sets, so their integer sum is exactly one whole; float
 * weights get their largest weight recomputed in float as 1 minus the others. A joint whose weight came out 0 is
 * written as joint 0, as glTF asks of unused influences. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"

/* n of a name "PREFIXn" (n decimal digits only), else -1. */
static long set_number(const char *name, const char *prefix)
{
    size_t k = strlen(prefix);
    if (strncmp(name, prefix, k) || !name[k])
        return -1;
    long n = 0;
    for (const char *p = name + k; *p; ++p) {
        if (*p < '0' || *p > '9' || n > 100000)
            return -1;
        n = 10 * n + (*p - '0');
    }
    return n;
}

void resurfi_skin_find_sets(const resurf_mesh *m, resurfi_skin_sets *sets)
{
    memset(sets, 0, sizeof *sets);
    for (size_t w = 0; w < m->extra_count && sets->count < RESURFI_SKIN_MAX_SETS; ++w) {
        long n = set_number(m->extras[w].name, "WEIGHTS_");
        if (n < 0 || m->extras[w].components != 4 || !m->extras[w].data)
            continue;
        char joints[64];
        snprintf(joints, sizeof joints, "JOINTS_%ld", n);
        for (size_t j = 0; j < m->extra_count; ++j)
            if (!strcmp(m->extras[j].name, joints) && m->extras[j].components == 4 && m->extras[j].data) {
                sets->joints[sets->count] = j;
                sets->weights[sets->count++] = w;
                break;
            }
    }
}

int resurfi_skin_owns(const resurfi_skin_sets *sets, size_t extra)
{
    for (unsigned s = 0; s < sets->count; ++s)
        if (sets->joints[s] == extra || sets->weights[s] == extra)
            return 1;
    return 0;
}

typedef struct influence {
    double joint, weight;
} influence;

/* Stronger first; equal weights by lower joint, so the order never depends on the corners' order. */
static int stronger(const influence *a, const influence *b)
{
    return a->weight > b->weight || (a->weight == b->weight && a->joint < b->joint);
}

void resurfi_skin_combine(const resurf_mesh *in, const resurfi_skin_sets *sets, const uint32_t corner[3],
                          const double bary[3], resurf_mesh *out, size_t ov)
{
    enum { MAX = 3 * 4 * RESURFI_SKIN_MAX_SETS };
    influence inf[MAX];
    size_t n = 0;
    double total = 0;
    for (int i = 0; i < 3; ++i) {
        if (!(bary[i] > 0))
            continue;
        for (unsigned s = 0; s < sets->count; ++s) {
            const float *jv = in->extras[sets->joints[s]].data + 4 * (size_t)corner[i];
            const float *wv = in->extras[sets->weights[s]].data + 4 * (size_t)corner[i];
            for (int k = 0; k < 4; ++k) {
                double w = bary[i] * (double)wv[k], joint = (double)jv[k];
                if (!(w > 0) || !isfinite(w) || !isfinite(joint))
                    continue;
                size_t e = 0;
                while (e < n && inf[e].joint != joint)
                    ++e;
                if (e == n)
                    inf[n++] = (influence){joint, 0};
                inf[e].weight += w;
                total += w;
            }
        }
    }
    size_t keep = 4 * (size_t)sets->count;
    for (size_t a = 0; a < n && a < keep; ++a) /* selection: the strongest `keep`, in order */
        for (size_t b = a + 1; b < n; ++b)
            if (stronger(&inf[b], &inf[a])) {
                influence t = inf[a];
                inf[a] = inf[b];
                inf[b] = t;
            }
    if (n > keep)
        n = keep;
    double kept = 0;
    for (size_t e = 0; e < n; ++e)
        kept += inf[e].weight;
    if (!(kept > 0 && isfinite(total))) {
        /* No influence at all (an unskinned or broken input vertex): the nearest corner's values as they are. */
        int c = bary[1] > bary[0] ? 1 : 0;
        c = bary[2] > bary[c] ? 2 : c;
        for (unsigned s = 0; s < sets->count; ++s) {
            memcpy(out->extras[sets->joints[s]].data + 4 * ov, in->extras[sets->joints[s]].data + 4 * (size_t)corner[c],
                   4 * sizeof(float));
            memcpy(out->extras[sets->weights[s]].data + 4 * ov,
                   in->extras[sets->weights[s]].data + 4 * (size_t)corner[c], 4 * sizeof(float));
        }
        return;
    }
    for (unsigned s = 0; s < sets->count; ++s)
        for (int k = 0; k < 4; ++k) {
            size_t e = 4 * (size_t)s + (size_t)k;
            out->extras[sets->joints[s]].data[4 * ov + (size_t)k] = e < n ? (float)inf[e].joint : 0.0f;
            out->extras[sets->weights[s]].data[4 * ov + (size_t)k] = e < n ? (float)(inf[e].weight / kept) : 0.0f;
        }
}

/* The weights of vertex v over all sets (4 per set), normalized integers of `units` per 1 (0: float): in place. */
static void snap_vertex(double *w, size_t count, double units)
{
    double total = 0;
    size_t largest = 0;
    for (size_t i = 0; i < count; ++i) {
        w[i] = w[i] > 0 && isfinite(w[i]) ? w[i] : 0;
        total += w[i];
        largest = w[i] > w[largest] ? i : largest;
    }
    if (!(total > 0) || !isfinite(total))
        return; /* nothing to keep whole: written as it is */
    if (units == 0) {
        double rest = 0;
        for (size_t i = 0; i < count; ++i)
            if (i != largest)
                rest += (double)(float)(w[i] / total);
        for (size_t i = 0; i < count; ++i)
            w[i] = i == largest ? (double)(float)(1 - rest) : (double)(float)(w[i] / total);
        return;
    }
    double whole = 0, frac[4 * RESURFI_SKIN_MAX_SETS];
    for (size_t i = 0; i < count; ++i) {
        double x = w[i] / total * units;
        w[i] = floor(x);
        frac[i] = x - w[i];
        whole += w[i];
    }
    for (double left = units - whole; left > 0.5; left -= 1) { /* largest remainder; ties to the earlier slot */
        size_t best = 0;
        for (size_t i = 1; i < count; ++i)
            best = frac[i] > frac[best] ? i : best;
        w[best] += 1;
        frac[best] = -1;
    }
    for (size_t i = 0; i < count; ++i)
        w[i] /= units;
}

void resurfi_skin_snap(const resurf_mesh *m, const resurfi_skin_sets *sets, double units, float *const *joints_out,
                       float *const *weights_out)
{
    size_t nv = m->vertex_count;
    size_t count = 4 * (size_t)sets->count;
    for (size_t v = 0; v < nv; ++v) {
        double w[4 * RESURFI_SKIN_MAX_SETS];
        for (size_t i = 0; i < count; ++i)
            w[i] = (double)m->extras[sets->weights[i / 4]].data[4 * v + i % 4];
        snap_vertex(w, count, units);
        for (size_t i = 0; i < count; ++i) {
            float joint = m->extras[sets->joints[i / 4]].data[4 * v + i % 4];
            weights_out[i / 4][4 * v + i % 4] = (float)w[i];
            joints_out[i / 4][4 * v + i % 4] = w[i] > 0 ? joint : 0.0f;
        }
    }
}
