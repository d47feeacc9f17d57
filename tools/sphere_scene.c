/* The scene of sphere_scene.h, written as a .glb by hand. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>

#include "byte_buffer.h"
#include "sphere_scene.h"

/* Appends printf-formatted text to b. */
__attribute__((format(printf, 2, 3))) static void put_text(bytes *b, const char *format, ...)
{
    char text[512];
    va_list args;
    va_start(args, format);
    int n = vsnprintf(text, sizeof text, format, args);
    va_end(args);
    if (n < 0 || (size_t)n >= sizeof text)
        b->failed = 1;
    else
        put(b, text, (size_t)n);
}

unsigned char *sphere_scene_glb(unsigned count, unsigned around, unsigned rings, size_t *out_size)
{
    size_t nv = (size_t)around * (rings + 1), nt = 2 * (size_t)around * (rings - 1);
    if (around < 3 || rings < 2 || nv > 65536)
        return NULL;
    bytes bin = {0}, json = {0}, glb = {0};
    size_t vertex_bytes = 12 * nv, index_bytes = (6 * nt + 3) & ~(size_t)3;
    put_text(&json, "{\"asset\":{\"version\":\"2.0\",\"generator\":\"resurf tools/sphere_scene.c\"},\"scene\":0,"
                    "\"scenes\":[{\"nodes\":[");
    for (unsigned k = 0; k < count; ++k)
        put_text(&json, "%s%u", k ? "," : "", k);
    put_text(&json, "]}],\"nodes\":[");
    for (unsigned k = 0; k < count; ++k)
        put_text(&json, "%s{\"mesh\":%u,\"translation\":[%.1f,%.1f,0]}", k ? "," : "", k, 1.5 * (k % 20),
                 1.5 * (k / 20));
    put_text(&json, "],\"meshes\":[");
    for (unsigned k = 0; k < count; ++k)
        put_text(&json, "%s{\"primitives\":[{\"attributes\":{\"POSITION\":%u},\"indices\":%u}]}", k ? "," : "",
                 2 * k, 2 * k + 1);
    put_text(&json, "],\"accessors\":[");
    for (unsigned k = 0; k < count; ++k) {
        double radius = 0.4 + 0.05 * (k % 5), bulge = 0.05 * (k % 3), lo[3] = {INFINITY, INFINITY, INFINITY},
               hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (unsigned j = 0; j <= rings; ++j)
            for (unsigned i = 0; i < around; ++i) {
                double th = M_PI * j / rings, ph = 2 * M_PI * i / around;
                double r = radius * (1 + bulge * sin(3 * ph + 0.1 * k) * sin(th) * sin(th));
                float p[3] = {(float)(r * sin(th) * cos(ph)), (float)(r * cos(th)), (float)(r * sin(th) * sin(ph))};
                for (int a = 0; a < 3; ++a) {
                    put_f32(&bin, p[a]);
                    lo[a] = fmin(lo[a], p[a]), hi[a] = fmax(hi[a], p[a]);
                }
            }
        for (unsigned j = 0; j < rings; ++j)
            for (unsigned i = 0; i < around; ++i) {
                uint16_t a = (uint16_t)(j * around + i), b = (uint16_t)(j * around + (i + 1) % around);
                uint16_t c = (uint16_t)((j + 1) * around + (i + 1) % around), d = (uint16_t)((j + 1) * around + i);
                if (j > 0)
                    put_u16(&bin, a), put_u16(&bin, c), put_u16(&bin, b);
                if (j + 1 < rings)
                    put_u16(&bin, a), put_u16(&bin, d), put_u16(&bin, c);
            }
        if (6 * nt % 4)
            put_u16(&bin, 0);
        put_text(&json, "%s{\"bufferView\":%u,\"componentType\":5126,\"type\":\"VEC3\",\"count\":%zu,", k ? "," : "",
                 2 * k, nv);
        put_text(&json, "\"min\":[%.9g,%.9g,%.9g],\"max\":[%.9g,%.9g,%.9g]},", lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
        put_text(&json, "{\"bufferView\":%u,\"componentType\":5123,\"type\":\"SCALAR\",\"count\":%zu}", 2 * k + 1,
                 3 * nt);
    }
    put_text(&json, "],\"bufferViews\":[");
    for (unsigned k = 0; k < count; ++k) {
        size_t at = (size_t)k * (vertex_bytes + index_bytes);
        put_text(&json, "%s{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu,\"target\":34962},", k ? "," : "", at,
                 vertex_bytes);
        put_text(&json, "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu,\"target\":34963}", at + vertex_bytes,
                 6 * nt);
    }
    put_text(&json, "],\"buffers\":[{\"byteLength\":%zu}]}", bin.size);
    put_glb(&glb, (const char *)json.data, json.size, &bin);
    int failed = bin.failed || json.failed || glb.failed;
    free(bin.data);
    free(json.data);
    if (failed) {
        free(glb.data);
        return NULL;
    }
    *out_size = glb.size;
    return glb.data;
}
