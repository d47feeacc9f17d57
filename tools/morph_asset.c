/* The analytic morph of morph_asset.h: a sphere whose one target makes an ellipsoid, as a mesh and as a .glb. */
#include "morph_asset.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "byte_buffer.h"
#include "shapes.h"

void morph_axes_at(const double axes[3], double w, double out[3])
{
    for (int i = 0; i < 3; ++i)
        out[i] = 1 + w * (axes[i] - 1);
}

resurf_mesh *morph_sphere_mesh(size_t triangles, double jitter, uint64_t seed, const double axes[3])
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, triangles, jitter, seed, 1);
    resurf_attribute *dp = NULL, *dn = NULL;
    if (!m || resurf_mesh_add_extra(m, "targets[0].POSITION", 3, &dp, NULL) != RESURF_OK ||
        resurf_mesh_add_extra(m, "targets[0].NORMAL", 3, &dn, NULL) != RESURF_OK) {
        resurf_mesh_free(m);
        return NULL;
    }
    dp = &m->extras[0]; /* the second add may have moved the first */
    for (size_t v = 0; v < m->vertex_count; ++v) {
        const double *p = m->positions + 3 * v, *n = m->normals + 3 * v;
        double g[3], len = 0;
        for (int i = 0; i < 3; ++i) {
            dp->data[3 * v + (size_t)i] = (float)((axes[i] - 1) * p[i]);
            g[i] = p[i] / axes[i]; /* ∇ of Σ xᵢ²/aᵢ² at x = a p, up to a factor */
            len += g[i] * g[i];
        }
        len = sqrt(len);
        for (int i = 0; i < 3; ++i)
            dn->data[3 * v + (size_t)i] = (float)(g[i] / len - n[i]);
    }
    return m;
}

resurf_mesh *morph_bulge_mesh(size_t triangles, double jitter, uint64_t seed, double height, double width)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, triangles, jitter, seed, 1);
    resurf_attribute *dp = NULL;
    if (!m || resurf_mesh_add_extra(m, "targets[0].POSITION", 3, &dp, NULL) != RESURF_OK) {
        resurf_mesh_free(m);
        return NULL;
    }
    for (size_t v = 0; v < m->vertex_count; ++v) {
        const double *p = m->positions + 3 * v;
        double q = p[0] * p[0] + p[1] * p[1] + (p[2] - 1) * (p[2] - 1), g = height * exp(-q / (width * width));
        for (int i = 0; i < 3; ++i)
            dp->data[3 * v + (size_t)i] = (float)(g * p[i]);
    }
    return m;
}

double ellipsoid_distance(const double a[3], const double p[3])
{
    double y[3], lo = -INFINITY, hi = 0, amax = 0;
    for (int i = 0; i < 3; ++i) {
        y[i] = fabs(p[i]);
        amax = a[i] > amax ? a[i] : amax;
        if (y[i] > 0 && -a[i] * a[i] > lo)
            lo = -a[i] * a[i];
        hi += y[i] * y[i];
    }
    if (hi == 0)
        return a[0] < a[1] ? (a[0] < a[2] ? a[0] : a[2]) : (a[1] < a[2] ? a[1] : a[2]);
    hi = amax * sqrt(hi); /* there each term aᵢyᵢ/(t + aᵢ²) <= yᵢ/|y|: F(hi) <= 0 */
    for (int it = 0; it < 200 && hi - lo > 1e-16 * (fabs(lo) + fabs(hi)); ++it) {
        double t = 0.5 * (lo + hi), f = -1;
        for (int i = 0; i < 3; ++i) {
            double r = a[i] * y[i] / (t + a[i] * a[i]);
            f += r * r;
        }
        if (f > 0)
            lo = t;
        else
            hi = t;
    }
    double t = 0.5 * (lo + hi), d2 = 0;
    for (int i = 0; i < 3; ++i) {
        double x = a[i] * a[i] * y[i] / (t + a[i] * a[i]);
        d2 += (x - y[i]) * (x - y[i]);
    }
    return sqrt(d2);
}

/* ---- the .glb ------------------------------------------------------------------------------------------------ */

/* Appends n VEC3 values (doubles or floats) and returns their min/max. */
static void put_vec3(bytes *b, const double *d, const float *f, size_t n, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; ++k)
        lo[k] = INFINITY, hi[k] = -INFINITY;
    for (size_t i = 0; i < 3 * n; ++i) {
        float x = d ? (float)d[i] : f[i];
        put_f32(b, x);
        lo[i % 3] = fmin(lo[i % 3], x), hi[i % 3] = fmax(hi[i % 3], x);
    }
}

static const resurf_attribute *extra(const resurf_mesh *m, const char *name)
{
    for (size_t i = 0; i < m->extra_count; ++i)
        if (!strcmp(m->extras[i].name, name) && m->extras[i].components == 3)
            return &m->extras[i];
    return NULL;
}

unsigned char *morph_glb(const resurf_mesh *m, size_t *out_size)
{
    const resurf_attribute *tp = extra(m, "targets[0].POSITION"), *tn = extra(m, "targets[0].NORMAL");
    if (!m->normals || !tp || !tn)
        return NULL;
    size_t nv = m->vertex_count, ni = 3 * m->triangle_count, vec = 12 * nv;
    bytes bin = {0}, glb = {0};
    double lo[4][3], hi[4][3];
    put_vec3(&bin, m->positions, NULL, nv, lo[0], hi[0]);
    put_vec3(&bin, m->normals, NULL, nv, lo[1], hi[1]);
    put_vec3(&bin, NULL, tp->data, nv, lo[2], hi[2]);
    put_vec3(&bin, NULL, tn->data, nv, lo[3], hi[3]);
    for (size_t i = 0; i < ni; ++i)
        put_u32(&bin, m->indices[i]);
    const float times[3] = {0, 1, 2}, weights[3] = {0, 1, 0};
    for (int i = 0; i < 3; ++i)
        put_f32(&bin, times[i]);
    for (int i = 0; i < 3; ++i)
        put_f32(&bin, weights[i]);
    size_t anim = 4 * vec + 4 * ni;
    char *json = malloc(4096);
    if (!json) {
        free(bin.data);
        return NULL;
    }
    int n = snprintf(
        json, 4096,
        "{\"asset\":{\"version\":\"2.0\",\"generator\":\"resurf tools/morph_asset.c\"},\"scene\":0,"
        "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"name\":\"morph-sphere\",\"mesh\":0}],"
        "\"meshes\":[{\"name\":\"morph-sphere\",\"weights\":[0],\"extras\":{\"targetNames\":[\"ellipsoid\"]},"
        "\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1},\"indices\":4,"
        "\"targets\":[{\"POSITION\":2,\"NORMAL\":3}]}]}],"
        "\"animations\":[{\"name\":\"breathe\",\"samplers\":[{\"input\":5,\"output\":6,\"interpolation\":\"LINEAR\"}],"
        "\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":\"weights\"}}]}],"
        "\"accessors\":["
        "{\"bufferView\":0,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\",\"min\":[%.9g,%.9g,%.9g],"
        "\"max\":[%.9g,%.9g,%.9g]},"
        "{\"bufferView\":0,\"byteOffset\":%zu,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\"},"
        "{\"bufferView\":0,\"byteOffset\":%zu,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\","
        "\"min\":[%.9g,%.9g,%.9g],\"max\":[%.9g,%.9g,%.9g]},"
        "{\"bufferView\":0,\"byteOffset\":%zu,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\"},"
        "{\"bufferView\":1,\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"},"
        "{\"bufferView\":2,\"componentType\":5126,\"count\":3,\"type\":\"SCALAR\",\"min\":[0],\"max\":[2]},"
        "{\"bufferView\":2,\"byteOffset\":12,\"componentType\":5126,\"count\":3,\"type\":\"SCALAR\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":%zu,\"byteStride\":12,\"target\":34962},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu,\"target\":34963},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":24}],"
        "\"buffers\":[{\"byteLength\":%zu}]}",
        nv, lo[0][0], lo[0][1], lo[0][2], hi[0][0], hi[0][1], hi[0][2], vec, nv, 2 * vec, nv, lo[2][0], lo[2][1],
        lo[2][2], hi[2][0], hi[2][1], hi[2][2], 3 * vec, nv, ni, 4 * vec, 4 * vec, 4 * ni, anim, bin.size);
    if (n < 0 || n >= 4096) {
        free(json);
        free(bin.data);
        return NULL;
    }
    put_glb(&glb, json, (size_t)n, &bin);
    free(json);
    int failed = bin.failed || glb.failed;
    free(bin.data);
    if (failed) {
        free(glb.data);
        return NULL;
    }
    *out_size = glb.size;
    return glb.data;
}
