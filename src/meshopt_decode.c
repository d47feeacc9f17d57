/* EXT_meshopt_compression and KHR_meshopt_compression decoded (their specifications' Appendix A, bitstreams, and
 * B, filters; KHR's adds version 1 of the attribute bitstream and the colour filter). The streams are
 * untrusted: a reader that would step past its end or leave bytes over fails, and each write is inside out. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "meshopt_decode.h"

/* A stream being read: p from begin up to end (end excludes the stream's tail). */
typedef struct reader {
    const unsigned char *p, *end;
} reader;

static uint8_t unzigzag8(uint8_t v) { return (v & 1) ? (uint8_t)~(v >> 1) : (uint8_t)(v >> 1); }

static uint32_t get_le(const unsigned char *p, size_t bytes)
{
    uint32_t v = 0;
    for (size_t i = 0; i < bytes; ++i)
        v |= (uint32_t)p[i] << (8 * i);
    return v;
}

static void put_le(unsigned char *p, size_t bytes, uint32_t v)
{
    for (size_t i = 0; i < bytes; ++i)
        p[i] = (unsigned char)(v >> (8 * i));
}

/* Unsigned LEB128 of at most 32 bits. */
static int read_varint(reader *r, uint32_t *out)
{
    uint32_t v = 0;
    for (int shift = 0; shift < 35; shift += 7) {
        if (r->p == r->end)
            return 0;
        unsigned char b = *r->p++;
        v |= (uint32_t)(b & 0x7f) << shift;
        if (!(b & 0x80)) {
            *out = v;
            return 1;
        }
    }
    return 0;
}

/* ---- mode 0: attributes -------------------------------------------------------------------------------------- */

/* One group of 16 byte deltas of `bits` bits each (0: all zero, 8: the bytes themselves), sentinels (all bits set)
 * followed by their byte after the packed bits. 2- and 4-bit deltas are packed from the most significant bits of a
 * byte, 1-bit ones from the least. */
static int read_group(reader *r, unsigned bits, uint8_t deltas[16])
{
    if (bits == 0) {
        memset(deltas, 0, 16);
        return 1;
    }
    size_t packed = 16 * bits / 8;
    if ((size_t)(r->end - r->p) < packed)
        return 0;
    const unsigned char *bytes = r->p;
    r->p += packed;
    if (bits == 8) {
        memcpy(deltas, bytes, 16);
        return 1;
    }
    unsigned per_byte = 8 / bits, sentinel = (1u << bits) - 1;
    for (unsigned i = 0; i < 16; ++i) {
        unsigned shift = bits == 1 ? i % 8 : 8 - bits * (i % per_byte + 1);
        unsigned d = (bytes[i / per_byte] >> shift) & sentinel;
        if (d == sentinel) {
            if (r->p == r->end)
                return 0;
            d = *r->p++;
        }
        deltas[i] = (uint8_t)d;
    }
    return 1;
}

/* The bits of a group's deltas by its 2 header bits: version 0, and version 1's control modes 0 and 1. */
static const unsigned group_bits[3][4] = {{0, 2, 4, 8}, {0, 1, 2, 4}, {1, 2, 4, 8}};

/* Byte k's deltas of a block of `elements` elements, by its control mode (version 1; version 0 is control 0 of its
 * own table): header bits and groups of 16, nothing (all zero), or the deltas as bytes. */
static int read_byte_deltas(reader *r, int version, unsigned control, size_t elements, uint8_t *deltas)
{
    size_t groups = (elements + 15) / 16;
    if (control == 2) {
        memset(deltas, 0, 16 * groups);
        return 1;
    }
    if (control == 3) { /* the block's deltas as bytes, as many as it has elements */
        if ((size_t)(r->end - r->p) < elements)
            return 0;
        memcpy(deltas, r->p, elements);
        r->p += elements;
        return 1;
    }
    size_t header = (groups + 3) / 4;
    if ((size_t)(r->end - r->p) < header)
        return 0;
    const unsigned char *modes = r->p;
    r->p += header;
    const unsigned *bits = group_bits[version ? 1 + control : 0];
    for (size_t g = 0; g < groups; ++g)
        if (!read_group(r, bits[(modes[g / 4] >> (2 * (g % 4))) & 3], deltas + 16 * g))
            return 0;
    return 1;
}

static uint32_t rotate_right(uint32_t v, unsigned r) { return (v >> r) | (v << ((32 - r) & 31)); }

/* One element's 4-byte channel from the one before (last, updated) and its deltas (d[i] is byte i's): zigzag
 * deltas of its bytes (channel mode 0) or of two 16-bit values (1), or the XOR of the two 32-bit values that the
 * encoder rotated left by `rot` bits (2). */
static void undo_channel(unsigned mode, unsigned rot, const uint8_t d[4], unsigned char last[4])
{
    if (mode == 0) {
        for (int i = 0; i < 4; ++i)
            last[i] = (uint8_t)(last[i] + unzigzag8(d[i]));
    } else if (mode == 1) {
        for (int h = 0; h < 4; h += 2) {
            uint16_t z = (uint16_t)(d[h] | d[h + 1] << 8), delta = (z & 1) ? (uint16_t)~(z >> 1) : (uint16_t)(z >> 1);
            put_le(last + h, 2, (uint16_t)(get_le(last + h, 2) + delta));
        }
    } else {
        put_le(last, 4, get_le(last, 4) ^ rotate_right(get_le(d, 4), rot));
    }
}

/* Version 0 (EXT_meshopt_compression's, header 0xa0) or, with KHR_meshopt_compression, version 1 (0xa1: a control
 * mode per byte and block, a channel mode per 4 bytes in the tail). */
static const char *decode_attributes(int khr, size_t count, size_t stride, const unsigned char *src, size_t size,
                                     unsigned char *out)
{
    if (stride == 0 || stride > 256 || stride % 4)
        return "ATTRIBUTES needs a byteStride that is a multiple of 4, at most 256";
    if (size < 1)
        return "the stream is shorter than its header and tail";
    int version = src[0] == 0xa1 && khr ? 1 : 0;
    if (src[0] != 0xa0 && !version)
        return khr ? "the attribute stream's header is neither 0xa0 nor 0xa1 (another version of the bitstream)"
                   : "the attribute stream's header is not 0xa0 (another version of the bitstream)";
    size_t channels = stride / 4, tail_block = version ? stride + channels : stride;
    size_t tail = tail_block < (version ? 24u : 32u) ? (version ? 24u : 32u) : tail_block; /* padded */
    if (size < 1 + tail)
        return "the stream is shorter than its header and tail";
    unsigned char last[256];
    const unsigned char *channel_modes = src + size - tail_block + stride;
    memcpy(last, src + size - tail_block, stride);
    for (size_t c = 0; version && c < channels; ++c)
        if ((channel_modes[c] & 15) > 2 || ((channel_modes[c] & 15) < 2 && channel_modes[c] >> 4))
            return "a channel mode of the attribute stream is not one the bitstream defines";
    reader r = {src + 1, src + size - tail};
    size_t block_max = (8192 / stride) & ~(size_t)15;
    if (block_max > 256)
        block_max = 256;
    uint8_t deltas[8192]; /* a block's deltas, byte k's at k * 16 * groups (block_max × stride <= 8192) */
    for (size_t start = 0; start < count; start += block_max) {
        size_t block = count - start < block_max ? count - start : block_max, groups = (block + 15) / 16;
        const unsigned char *control = r.p;
        if (version && (size_t)(r.end - r.p) < channels)
            return "the stream ends inside an attribute block";
        r.p += version ? channels : 0;
        for (size_t k = 0; k < stride; ++k)
            if (!read_byte_deltas(&r, version, version ? (control[k / 4] >> (2 * (k % 4))) & 3 : 0, block,
                                  deltas + k * 16 * groups))
                return "the stream ends inside an attribute block";
        for (size_t i = 0; i < block; ++i)
            for (size_t c = 0; c < channels; ++c) {
                uint8_t d[4];
                for (int b = 0; b < 4; ++b)
                    d[b] = deltas[(4 * c + (size_t)b) * 16 * groups + i];
                unsigned mode = version ? channel_modes[c] & 15 : 0, rot = version ? channel_modes[c] >> 4 : 0;
                undo_channel(mode, rot, d, last + 4 * c);
                memcpy(out + (start + i) * stride + 4 * c, last + 4 * c, 4);
            }
    }
    return r.p == r.end ? NULL : "the attribute stream has bytes left over before its tail";
}

/* ---- mode 1: triangles --------------------------------------------------------------------------------------- */

typedef struct triangle_state {
    uint32_t edges[16][2], vertices[16];
    unsigned edge_at, vertex_at; /* where the next push goes */
    uint32_t next, last;
} triangle_state;

static void push_edge(triangle_state *s, uint32_t a, uint32_t b)
{
    s->edges[s->edge_at][0] = a, s->edges[s->edge_at][1] = b;
    s->edge_at = (s->edge_at + 1) & 15;
}

static void push_vertex(triangle_state *s, uint32_t v)
{
    s->vertices[s->vertex_at] = v;
    s->vertex_at = (s->vertex_at + 1) & 15;
}

static uint32_t recent_vertex(const triangle_state *s, unsigned i) { return s->vertices[(s->vertex_at - 1 - i) & 15]; }

/* An explicit index: a zigzag delta from `last`, which it becomes. */
static int explicit_index(reader *r, triangle_state *s, uint32_t *out)
{
    uint32_t v;
    if (!read_varint(r, &v))
        return 0;
    uint32_t delta = (v & 1) ? ~(v >> 1) : (v >> 1);
    *out = s->last += delta;
    return 1;
}

static const char *decode_triangles(size_t count, size_t stride, const unsigned char *src, size_t size,
                                    unsigned char *out)
{
    if ((stride != 2 && stride != 4) || count % 3)
        return "TRIANGLES needs a byteStride of 2 or 4 and a count divisible by 3";
    size_t triangles = count / 3;
    if (size < 1 + 16 || size - 1 - 16 < triangles)
        return "the stream is shorter than its header, codes and tail";
    if (src[0] != 0xe1)
        return "the triangle stream's header is not 0xe1 (another version of the bitstream)";
    const unsigned char *codes = src + 1, *codeaux = src + size - 16;
    reader r = {codes + triangles, codeaux};
    triangle_state s;
    memset(&s, 0, sizeof s);
    for (size_t t = 0; t < triangles; ++t) {
        unsigned code = codes[t], hi = code >> 4, lo = code & 15;
        uint32_t a, b, c;
        if (hi < 0xf) { /* a recent edge and a third vertex */
            a = s.edges[(s.edge_at - 1 - hi) & 15][0], b = s.edges[(s.edge_at - 1 - hi) & 15][1];
            if (lo == 0)
                c = s.next++;
            else if (lo < 0xd)
                c = recent_vertex(&s, lo);
            else if (lo < 0xf)
                c = s.last = lo == 0xd ? s.last - 1 : s.last + 1;
            else if (!explicit_index(&r, &s, &c))
                return "the stream ends inside a triangle's data";
            push_edge(&s, c, b);
            push_edge(&s, a, c);
            if (lo == 0 || lo >= 0xd)
                push_vertex(&s, c);
        } else { /* three vertices: from the lookup table, or given with an extra byte */
            unsigned zw;
            int explicit_a = 0;
            if (lo < 0xe)
                zw = codeaux[lo];
            else {
                if (r.p == r.end)
                    return "the stream ends inside a triangle's data";
                zw = *r.p++;
                if (zw == 0)
                    s.next = 0;
                explicit_a = lo == 0xf;
            }
            unsigned z = zw >> 4, w = zw & 15;
            if (explicit_a) {
                if (!explicit_index(&r, &s, &a))
                    return "the stream ends inside a triangle's data";
            } else
                a = s.next++;
            uint32_t *bc[2] = {&b, &c};
            unsigned which[2] = {z, w};
            for (int k = 0; k < 2; ++k) {
                if (which[k] == 0)
                    *bc[k] = s.next++;
                else if (which[k] < 0xf || lo < 0xe)
                    *bc[k] = recent_vertex(&s, which[k] - 1);
                else if (!explicit_index(&r, &s, bc[k]))
                    return "the stream ends inside a triangle's data";
            }
            push_edge(&s, b, a);
            push_edge(&s, c, b);
            push_edge(&s, a, c);
            push_vertex(&s, a);
            if (z == 0 || (z == 0xf && lo >= 0xe))
                push_vertex(&s, b);
            if (w == 0 || (w == 0xf && lo >= 0xe))
                push_vertex(&s, c);
        }
        put_le(out + (3 * t + 0) * stride, stride, a);
        put_le(out + (3 * t + 1) * stride, stride, b);
        put_le(out + (3 * t + 2) * stride, stride, c);
    }
    return r.p == r.end ? NULL : "the triangle stream has bytes left over before its tail";
}

/* ---- mode 2: indices ----------------------------------------------------------------------------------------- */

static const char *decode_indices(size_t count, size_t stride, const unsigned char *src, size_t size,
                                  unsigned char *out)
{
    if (stride != 2 && stride != 4)
        return "INDICES needs a byteStride of 2 or 4";
    if (size < 1 + 4)
        return "the stream is shorter than its header and tail";
    if (src[0] != 0xd1)
        return "the index stream's header is not 0xd1 (another version of the bitstream)";
    reader r = {src + 1, src + size - 4};
    uint32_t last[2] = {0, 0};
    for (size_t i = 0; i < count; ++i) {
        uint32_t v;
        if (!read_varint(&r, &v))
            return "the stream ends inside an index";
        uint32_t delta = (v & 2) ? ~(v >> 2) : (v >> 2);
        put_le(out + i * stride, stride, last[v & 1] += delta);
    }
    return r.p == r.end ? NULL : "the index stream has bytes left over before its tail";
}

/* ---- filters ------------------------------------------------------------------------------------------------- */

static int32_t get_signed(const unsigned char *p, size_t bytes)
{
    uint32_t v = get_le(p, bytes), sign = 1u << (8 * bytes - 1);
    return (int32_t)(v ^ sign) - (int32_t)sign;
}

/* Unit vectors in octahedral encoding, 8- or 16-bit components; the third encodes 1.0 (its bit count). */
static void octahedral(unsigned char *data, size_t count, size_t stride)
{
    size_t bytes = stride / 4;
    float max = bytes == 1 ? 127.0f : 32767.0f;
    for (size_t i = 0; i < count; ++i) {
        unsigned char *e = data + i * stride;
        float one = (float)get_signed(e + 2 * bytes, bytes);
        if (one == 0) /* not a valid encoding: decoding it is unspecified, so it is left as it is */
            continue;
        float x = (float)get_signed(e, bytes) / one, y = (float)get_signed(e + bytes, bytes) / one;
        float z = 1.0f - fabsf(x) - fabsf(y), t = fminf(z, 0.0f);
        x -= copysignf(t, x), y -= copysignf(t, y);
        float len = sqrtf(x * x + y * y + z * z);
        float v[3] = {x / len, y / len, z / len};
        for (int k = 0; k < 3; ++k)
            put_le(e + (size_t)k * bytes, bytes, (uint32_t)(int32_t)lrintf(roundf(v[k] * max)));
    }
}

/* Unit quaternions as their three smallest components (scaled by sqrt 2) and the largest one's index. */
static void quaternion(unsigned char *data, size_t count)
{
    const float range = 1.0f / sqrtf(2.0f);
    for (size_t i = 0; i < count; ++i) {
        unsigned char *e = data + 8 * i;
        int32_t last = get_signed(e + 6, 2);
        float one = (float)(last | 3);
        float x = (float)get_signed(e, 2) / one * range, y = (float)get_signed(e + 2, 2) / one * range,
              z = (float)get_signed(e + 4, 2) / one * range;
        float w = sqrtf(fmaxf(0.0f, 1.0f - x * x - y * y - z * z));
        int max = last & 3;
        float q[4];
        q[(max + 1) % 4] = x, q[(max + 2) % 4] = y, q[(max + 3) % 4] = z, q[max] = w;
        for (int k = 0; k < 4; ++k)
            put_le(e + 2 * k, 2, (uint32_t)(int32_t)lrintf(roundf(q[k] * 32767.0f)));
    }
}

/* 32-bit values as 2^e × m: an 8-bit signed exponent over a 24-bit signed mantissa. */
static void exponential(unsigned char *data, size_t values)
{
    for (size_t i = 0; i < values; ++i) {
        uint32_t v = get_le(data + 4 * i, 4);
        int e = (int)(int8_t)(uint8_t)(v >> 24);
        int32_t m = (int32_t)(v & 0xffffff) - (int32_t)((v & 0x800000) << 1);
        float f = ldexpf((float)m, e);
        uint32_t bits;
        memcpy(&bits, &f, 4);
        put_le(data + 4 * i, 4, bits);
    }
}

/* Colours as YCoCg, 8- or 16-bit components: luma unsigned, the chroma signed, K bits each, and alpha in K - 1
 * bits under a set bit K - 1 that gives K. Out: RGBA as unsigned normalized integers. */
static void color(unsigned char *data, size_t count, size_t stride)
{
    size_t bytes = stride / 4;
    float max = bytes == 1 ? 255.0f : 65535.0f;
    for (size_t i = 0; i < count; ++i) {
        unsigned char *e = data + i * stride;
        uint32_t alpha = get_le(e + 3 * bytes, bytes);
        if (alpha == 0) /* no bit gives K: not a valid encoding, left as it is */
            continue;
        int msb = 31;
        while (!(alpha >> msb))
            --msb;
        int32_t scale = (int32_t)((2u << msb) - 1), y = (int32_t)get_le(e, bytes);
        int32_t co = get_signed(e + bytes, bytes), cg = get_signed(e + 2 * bytes, bytes);
        int32_t a = (int32_t)(alpha & (uint32_t)(scale >> 1));
        int32_t rgba[4] = {y + co - cg, y + cg, y - co - cg, (a << 1) | (a & 1)};
        float s = max / (float)scale;
        for (int k = 0; k < 4; ++k) {
            float v = roundf((float)rgba[k] * s); /* an encoder keeps these in range; a hostile one is clamped */
            put_le(e + (size_t)k * bytes, bytes, (uint32_t)fminf(fmaxf(v, 0.0f), max));
        }
    }
}

const char *resurfi_meshopt_decode(int khr, resurfi_meshopt_mode mode, resurfi_meshopt_filter filter, size_t count,
                                   size_t stride, const unsigned char *src, size_t size, unsigned char *out)
{
    if (filter == RESURFI_MESHOPT_COLOR && !khr)
        return "the COLOR filter is KHR_meshopt_compression's";
    if (mode != RESURFI_MESHOPT_ATTRIBUTES && filter != RESURFI_MESHOPT_NONE)
        return "a filter applies to ATTRIBUTES alone";
    if ((filter == RESURFI_MESHOPT_OCTAHEDRAL && stride != 4 && stride != 8) ||
        (filter == RESURFI_MESHOPT_QUATERNION && stride != 8) ||
        (filter == RESURFI_MESHOPT_EXPONENTIAL && stride % 4) ||
        (filter == RESURFI_MESHOPT_COLOR && stride != 4 && stride != 8))
        return "the filter does not allow this byteStride";
    const char *problem = mode == RESURFI_MESHOPT_ATTRIBUTES ? decode_attributes(khr, count, stride, src, size, out)
                          : mode == RESURFI_MESHOPT_TRIANGLES ? decode_triangles(count, stride, src, size, out)
                                                              : decode_indices(count, stride, src, size, out);
    if (problem)
        return problem;
    if (filter == RESURFI_MESHOPT_OCTAHEDRAL)
        octahedral(out, count, stride);
    else if (filter == RESURFI_MESHOPT_QUATERNION)
        quaternion(out, count);
    else if (filter == RESURFI_MESHOPT_EXPONENTIAL)
        exponential(out, count * stride / 4);
    else if (filter == RESURFI_MESHOPT_COLOR)
        color(out, count, stride);
    return NULL;
}
