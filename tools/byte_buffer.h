/* A growing little-endian byte buffer, for the tools that write .glb files by hand (morph_asset.c,
 * skinned_cylinder.c). A failed allocation sets `failed` and every later put is a no-op, so a writer checks once
 * at the end. */
#ifndef RESURF_TOOLS_BYTE_BUFFER_H
#define RESURF_TOOLS_BYTE_BUFFER_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct bytes {
    unsigned char *data;
    size_t size, cap;
    int failed;
} bytes;

static inline void put(bytes *b, const void *p, size_t n)
{
    if (b->failed)
        return;
    if (b->size + n > b->cap) {
        size_t cap = b->cap ? 2 * b->cap : 4096;
        while (cap < b->size + n)
            cap *= 2;
        unsigned char *d = realloc(b->data, cap);
        if (!d) {
            b->failed = 1;
            return;
        }
        b->data = d, b->cap = cap;
    }
    memcpy(b->data + b->size, p, n);
    b->size += n;
}

static inline void put_u16(bytes *b, uint16_t x)
{
    unsigned char c[2] = {(unsigned char)x, (unsigned char)(x >> 8)};
    put(b, c, 2);
}

static inline void put_u32(bytes *b, uint32_t x)
{
    unsigned char c[4] = {(unsigned char)x, (unsigned char)(x >> 8), (unsigned char)(x >> 16),
                          (unsigned char)(x >> 24)};
    put(b, c, 4);
}

static inline void put_f32(bytes *b, float f)
{
    uint32_t x;
    memcpy(&x, &f, 4);
    put_u32(b, x);
}

/* A .glb of the JSON text (json_len bytes, padded here with spaces) and the binary chunk (padded with zeros), framed
 * into glb: header, JSON chunk, BIN chunk. */
static inline void put_glb(bytes *glb, const char *json, size_t json_len, const bytes *bin)
{
    size_t json_padded = (json_len + 3) & ~(size_t)3, bin_padded = (bin->size + 3) & ~(size_t)3;
    put(glb, "glTF", 4);
    put_u32(glb, 2);
    put_u32(glb, (uint32_t)(12 + 8 + json_padded + 8 + bin_padded));
    put_u32(glb, (uint32_t)json_padded);
    put(glb, "JSON", 4);
    put(glb, json, json_len);
    for (size_t i = json_len; i < json_padded; ++i)
        put(glb, " ", 1);
    put_u32(glb, (uint32_t)bin_padded);
    put(glb, "BIN\0", 4);
    put(glb, bin->data, bin->size);
    for (size_t i = bin->size; i < bin_padded; ++i)
        put(glb, "", 1);
}

#endif
