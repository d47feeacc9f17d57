/* The two-bone cylinder of skinned_cylinder.h, written as a .glb by hand: JSON chunk, then BIN chunk with
 * positions, joints, weights, indices and the inverse bind matrices. */
#include "skinned_cylinder.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "byte_buffer.h"

static double upper_weight(double y)
{
    double u = (y - SKINNED_CYLINDER_BLEND_LO) / (SKINNED_CYLINDER_BLEND_HI - SKINNED_CYLINDER_BLEND_LO);
    u = u < 0 ? 0 : u > 1 ? 1 : u;
    return u * u * (3 - 2 * u);
}

/* The influences of a vertex at height y, stronger first, as the file stores them (whole bytes when ubyte); a joint
 * whose stored weight is 0 is joint 0. */
static void influences(double y, int ubyte, unsigned char joint[4], double weight[4])
{
    double w1 = upper_weight(y), hi = w1 > 0.5 ? w1 : 1 - w1;
    weight[0] = ubyte ? (double)lrint(hi * 255) / 255 : (double)(float)hi;
    weight[1] = ubyte ? 1 - weight[0] : (double)(float)(1 - hi);
    weight[2] = weight[3] = 0;
    joint[0] = w1 > 0.5;
    joint[1] = weight[1] > 0 ? !joint[0] : 0;
    joint[2] = joint[3] = 0;
}

int skinned_cylinder_write(const char *path, unsigned segments, unsigned rings, unsigned flags)
{
    int ubyte_weights = (flags & SKINNED_CYLINDER_UBYTE) != 0;
    const double radius = 0.2, height = 2.0, pi = 3.14159265358979323846;
    size_t nv = (size_t)segments * (rings + 1) + 2, nt = 2 * (size_t)segments * rings + 2 * (size_t)segments;
    if (segments < 3 || rings < 1 || nv > 65535)
        return -1;
    double *y_of = malloc(nv * sizeof *y_of);
    bytes bin = {0};
    if (!y_of)
        return -1;
    /* positions */
    float lo[3] = {0, 0, 0}, hi[3] = {0, (float)height, 0};
    for (unsigned r = 0; r <= rings; ++r)
        for (unsigned s = 0; s < segments; ++s) {
            double a = 2 * pi * s / segments, y = height * r / rings;
            float p[3] = {(float)(radius * cos(a)), (float)y, (float)(-radius * sin(a))};
            for (int k = 0; k < 3; ++k) {
                put_f32(&bin, p[k]);
                lo[k] = p[k] < lo[k] ? p[k] : lo[k];
                hi[k] = p[k] > hi[k] ? p[k] : hi[k];
            }
            y_of[(size_t)r * segments + s] = (double)p[1];
        }
    size_t bottom = (size_t)segments * (rings + 1), top = bottom + 1;
    put_f32(&bin, 0), put_f32(&bin, 0), put_f32(&bin, 0);
    put_f32(&bin, 0), put_f32(&bin, (float)height), put_f32(&bin, 0);
    y_of[bottom] = 0, y_of[top] = height;
    size_t joints_at = bin.size;
    for (size_t v = 0; v < nv; ++v) {
        unsigned char j[4];
        double w[4];
        influences(y_of[v], ubyte_weights, j, w);
        put(&bin, j, 4);
    }
    size_t weights_at = bin.size;
    for (size_t v = 0; v < nv; ++v) {
        unsigned char j[4], q[4];
        double w[4];
        influences(y_of[v], ubyte_weights, j, w);
        for (int k = 0; k < 4; ++k)
            if (ubyte_weights)
                q[k] = (unsigned char)lrint(w[k] * 255);
            else
                put_f32(&bin, (float)w[k]);
        if (ubyte_weights)
            put(&bin, q, 4);
    }
    size_t indices_at = bin.size;
    for (unsigned r = 0; r < rings; ++r)
        for (unsigned s = 0; s < segments; ++s) {
            uint16_t a = (uint16_t)(r * segments + s), b = (uint16_t)(r * segments + (s + 1) % segments);
            uint16_t c = (uint16_t)(a + segments), d = (uint16_t)(b + segments);
            put_u16(&bin, a), put_u16(&bin, b), put_u16(&bin, d);
            put_u16(&bin, a), put_u16(&bin, d), put_u16(&bin, c);
        }
    for (unsigned s = 0; s < segments; ++s) {
        uint16_t a = (uint16_t)s, b = (uint16_t)((s + 1) % segments);
        put_u16(&bin, (uint16_t)bottom), put_u16(&bin, b), put_u16(&bin, a);
        uint16_t c = (uint16_t)(rings * segments + s), d = (uint16_t)(rings * segments + (s + 1) % segments);
        put_u16(&bin, (uint16_t)top), put_u16(&bin, c), put_u16(&bin, d);
    }
    while (bin.size % 4)
        put(&bin, "", 1);
    size_t matrices_at = bin.size;
    for (int k = 0; k < 2; ++k)
        for (int i = 0; i < 16; ++i)
            put_f32(&bin, i % 5 == 0 ? 1.0f : k == 1 && i == 13 ? -1.0f : 0.0f);
    free(y_of);
    size_t weights_size = indices_at - weights_at, index_size = matrices_at - indices_at;
    double h = sin(SKINNED_CYLINDER_BEND_DEG * pi / 360), c = cos(SKINNED_CYLINDER_BEND_DEG * pi / 360);
    char json[4096];
    int n = snprintf(json, sizeof json,
        "{\"asset\":{\"version\":\"2.0\",\"generator\":\"resurf skinned_cylinder\"},\"scene\":0,"
        "\"scenes\":[{\"nodes\":[0,2]}],"
        "\"nodes\":[{\"name\":\"bone0\",\"children\":[1]},"
        "{\"name\":\"bone1\",\"translation\":[0,1,0],\"rotation\":[0,0,%.9f,%.9f]},"
        "{\"name\":\"cylinder\",%s\"mesh\":0,\"skin\":0}],"
        "\"skins\":[{\"joints\":[0,1],\"inverseBindMatrices\":4,\"skeleton\":0}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"JOINTS_0\":1,\"WEIGHTS_0\":2},\"indices\":3}]}],"
        "\"accessors\":["
        "{\"bufferView\":0,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\",\"min\":[%.9g,%.9g,%.9g],"
        "\"max\":[%.9g,%.9g,%.9g]},"
        "{\"bufferView\":1,\"componentType\":5121,\"count\":%zu,\"type\":\"VEC4\"},"
        "{\"bufferView\":2,\"componentType\":%d,%s\"count\":%zu,\"type\":\"VEC4\"},"
        "{\"bufferView\":3,\"componentType\":5123,\"count\":%zu,\"type\":\"SCALAR\"},"
        "{\"bufferView\":4,\"componentType\":5126,\"count\":2,\"type\":\"MAT4\"}],"
        "\"bufferViews\":["
        "{\"buffer\":0,\"byteOffset\":0,\"byteLength\":%zu,\"target\":34962},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu,\"target\":34962},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu,\"target\":34962},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu,\"target\":34963},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":128}],"
        "\"buffers\":[{\"byteLength\":%zu}]}",
        h, c, flags & SKINNED_CYLINDER_NODE_MOVED ? "\"translation\":[3,0,0]," : "", nv, (double)lo[0], (double)lo[1], (double)lo[2], (double)hi[0], (double)hi[1], (double)hi[2], nv,
        ubyte_weights ? 5121 : 5126, ubyte_weights ? "\"normalized\":true," : "", nv, 3 * nt, joints_at, joints_at, weights_at - joints_at,
        weights_at, weights_size, indices_at, index_size, matrices_at, bin.size);
    if (n < 0 || (size_t)n >= sizeof json || bin.failed) {
        free(bin.data);
        return -1;
    }
    bytes glb = {0};
    put_glb(&glb, json, (size_t)n, &bin);
    free(bin.data);
    FILE *f = glb.failed ? NULL : fopen(path, "wb");
    int ok = f && fwrite(glb.data, 1, glb.size, f) == glb.size;
    ok = f && fclose(f) == 0 && ok;
    free(glb.data);
    return ok ? 0 : -1;
}
