/* Tests of src/meshopt_decode.c, EXT_ and KHR_meshopt_compression's bitstreams and filters. The streams are written
 * by hand from the specifications' Appendix A, each decoded by hand there too; meshoptimizer 0.18's decoder
 * (meshopt_decodeVertexBuffer, meshopt_decodeIndexBuffer, meshopt_decodeIndexSequence) gave the same values for
 * the three of EXT when they were written, and the npm package meshoptimizer 1.2's (decodeVertexBuffer,
 * decodeGltfBuffer with COLOR) for KHR's version 1 stream and colours. The filters' cases are values whose decoding is exact. Then every stream
 * cut short, and stretched by a byte, must fail cleanly (the suite runs under ASan and valgrind). */
#include <string.h>

#include "testutil.h"

#include "../src/meshopt_decode.h"

/* Mode 0: two elements of 4 bytes over the baseline (10, 20, 30, 40) in the tail. Byte 0 in byte mode (deltas
 * +1, -1: zigzag 2, 1), byte 1 in 2-bit mode (+1 packed as 2, then a sentinel 3 whose byte 9 is -5), bytes 2 and
 * 3 unchanged (mode 0). So (11, 21, 30, 40) and (10, 16, 30, 40). */
static const unsigned char attributes[] = {
    0xa0,
    0x03, 0x02, 0x01, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, /* byte 0: header 3, 16 deltas */
    0x01, 0xb0, 0, 0, 0, 0x09,                                 /* byte 1: header 1, 4 packed bytes, a sentinel's */
    0x00,                                                      /* byte 2 */
    0x00,                                                      /* byte 3 */
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, /* tail: padding, */
    10, 20, 30, 40};                                                                      /* the baseline */
static const unsigned char attributes_want[8] = {11, 21, 30, 40, 10, 16, 30, 40};

/* Mode 1, five triangles, one per kind of code:
 * 0xfe + byte 0x00: next restarts at 0, (0, 1, 2);
 * 0x0f + varint 10 (zigzag +5 from last 0): the newest edge (0, 2) and 5, (0, 2, 5);
 * 0x1e: the edge before, (5, 2), and last + 1, (5, 2, 6);
 * 0x02: the newest edge (5, 6) and the third newest vertex (6, 5, 2: 2), (5, 6, 2);
 * 0xf1: codeaux[1] = 0x12: next (3), the newest vertex (6), the one before (5), (3, 6, 5). */
static const unsigned char triangles[] = {0xe1, 0xfe, 0x0f, 0x1e, 0x02, 0xf1, 0x00, 0x0a,
                                          0x00, 0x12, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
static const uint16_t triangles_want[15] = {0, 1, 2, 0, 2, 5, 5, 2, 6, 5, 6, 2, 3, 6, 5};

/* Mode 2: 5 (+5 from baseline 0), 7 (+2 from it), 100 (+100 from baseline 1, a two-byte varint), 6 (-1 from
 * baseline 0). */
static const unsigned char indices[] = {0xd1, 0x14, 0x08, 0x91, 0x03, 0x02, 0, 0, 0, 0};
static const uint32_t indices_want[4] = {5, 7, 100, 6};

/* Mode 0, version 1 (KHR_meshopt_compression): two elements of 12 bytes, three channels over the baseline
 * (10, 20, 30, 40 | 1000, 0xfffe as 16-bit | 0x12345678). Channel modes in the tail: bytes (0), 16-bit deltas (1),
 * XOR rotated by 4 (0x42). Control modes (2 bits a byte, from the lowest): byte 0 control 0 with a 1-bit group
 * whose sentinel (bit 0 set) takes the byte 2 (+1 zigzagged); bytes 1, 2 control 2 (zero); byte 3 control 3, the
 * literal deltas 0 and 10 (+5); byte 4 control 1, a 4-bit group 6 then 5 (+3, -3 in 16 bits); byte 6 control 1,
 * a byte group 6 (+3 on 0xfffe: 0x0001); byte 8 control 0, a 2-bit group whose sentinel takes 0x10 (1 rotated left
 * by 4, so the XOR is 1); the rest control 2. So (11, 20, 30, 40 | 1003, 1 | 0x12345679) and (11, 20, 30, 45 |
 * 1000, 1 | 0x12345679). */
static const unsigned char attributes_v1[] = {
    0xa1, 0xe8, 0x99, 0xa8,                                        /* header, control modes */
    0x01, 0x01, 0x00, 0x02,                                        /* byte 0 */
    0x00, 0x0a,                                                    /* byte 3 */
    0x02, 0x65, 0, 0, 0, 0, 0, 0, 0,                               /* byte 4 */
    0x03, 0x06, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,       /* byte 6 */
    0x02, 0xc0, 0, 0, 0, 0x10,                                     /* byte 8 */
    0, 0, 0, 0, 0, 0, 0, 0, 0,                                     /* tail: padding to 24 bytes, */
    0x0a, 0x14, 0x1e, 0x28, 0xe8, 0x03, 0xfe, 0xff, 0x78, 0x56, 0x34, 0x12, /* the baseline, */
    0x00, 0x01, 0x42};                                             /* the channel modes */
static const unsigned char attributes_v1_want[24] = {11, 20, 30, 40, 0xeb, 0x03, 0x01, 0x00, 0x79, 0x56, 0x34, 0x12,
                                                     11, 20, 30, 45, 0xe8, 0x03, 0x01, 0x00, 0x79, 0x56, 0x34, 0x12};

START_TEST(meshopt_streams_decode)
{
    unsigned char out[64];
    ck_assert_ptr_null(resurfi_meshopt_decode(0, RESURFI_MESHOPT_ATTRIBUTES, RESURFI_MESHOPT_NONE, 2, 4, attributes,
                                              sizeof attributes, out));
    ck_assert_mem_eq(out, attributes_want, 8);
    ck_assert_ptr_null(resurfi_meshopt_decode(1, RESURFI_MESHOPT_ATTRIBUTES, RESURFI_MESHOPT_NONE, 2, 4, attributes,
                                              sizeof attributes, out)); /* KHR reads version 0 too */
    ck_assert_mem_eq(out, attributes_want, 8);
    ck_assert_ptr_null(resurfi_meshopt_decode(1, RESURFI_MESHOPT_ATTRIBUTES, RESURFI_MESHOPT_NONE, 2, 12,
                                              attributes_v1, sizeof attributes_v1, out));
    ck_assert_mem_eq(out, attributes_v1_want, 24);
    ck_assert_ptr_null(resurfi_meshopt_decode(0, RESURFI_MESHOPT_TRIANGLES, RESURFI_MESHOPT_NONE, 15, 2, triangles,
                                              sizeof triangles, out));
    for (int i = 0; i < 15; ++i)
        ck_assert_uint_eq(out[2 * i] | out[2 * i + 1] << 8, triangles_want[i]);
    ck_assert_ptr_null(resurfi_meshopt_decode(0, RESURFI_MESHOPT_INDICES, RESURFI_MESHOPT_NONE, 4, 4, indices,
                                              sizeof indices, out));
    for (int i = 0; i < 4; ++i)
        ck_assert_uint_eq((uint32_t)out[4 * i] | (uint32_t)out[4 * i + 1] << 8 | (uint32_t)out[4 * i + 2] << 16 |
                              (uint32_t)out[4 * i + 3] << 24,
                          indices_want[i]);
}
END_TEST

/* Each filter on values whose decoding is exact, through a byte-mode stream of one element. */
static void filtered_as(int khr, resurfi_meshopt_filter filter, const unsigned char *element, size_t stride,
                        unsigned char *out)
{
    unsigned char s[1 + 256 * 17 + 256 + 32];
    size_t n = 0;
    s[n++] = 0xa0;
    for (size_t k = 0; k < stride; ++k) /* deltas from the baseline, itself the element: all zero */
        s[n++] = 0;
    for (size_t i = stride; i < 32; ++i)
        s[n++] = 0;
    memcpy(s + n, element, stride);
    n += stride;
    ck_assert_ptr_null(resurfi_meshopt_decode(khr, RESURFI_MESHOPT_ATTRIBUTES, filter, 1, stride, s, n, out));
}

static void filtered(resurfi_meshopt_filter filter, const unsigned char *element, size_t stride, unsigned char *out)
{
    filtered_as(0, filter, element, stride, out);
}

static int16_t i16(const unsigned char *p) { return (int16_t)(p[0] | p[1] << 8); }

START_TEST(meshopt_filters_decode)
{
    unsigned char out[16];
    /* Octahedral, 16-bit: (x, y) = (1, 0) and (-1, 0) with 1.0 = 32767, the fourth component passed through. */
    static const unsigned char oct[8] = {0xff, 0x7f, 0, 0, 0xff, 0x7f, 77, 0};
    filtered(RESURFI_MESHOPT_OCTAHEDRAL, oct, 8, out);
    ck_assert(i16(out) == 32767 && i16(out + 2) == 0 && i16(out + 4) == 0 && i16(out + 6) == 77);
    static const unsigned char oct_neg[8] = {0x01, 0x80, 0, 0, 0xff, 0x7f, 0, 0};
    filtered(RESURFI_MESHOPT_OCTAHEDRAL, oct_neg, 8, out);
    ck_assert(i16(out) == -32767 && i16(out + 2) == 0 && i16(out + 4) == 0);
    /* 8-bit: the pole (0, 0), 1.0 = 127: (0, 0, 127). */
    static const unsigned char oct8[4] = {0, 0, 127, 9};
    filtered(RESURFI_MESHOPT_OCTAHEDRAL, oct8, 4, out);
    ck_assert(out[0] == 0 && out[1] == 0 && out[2] == 127 && out[3] == 9);
    /* Quaternion: three zero components, 1.0 = 32767 with the largest component's index in the low bits: the
     * identity with w (index 3) largest, and (1, 0, 0, 0) with x (index 0). */
    static const unsigned char quat_w[8] = {0, 0, 0, 0, 0, 0, 0xff, 0x7f};
    filtered(RESURFI_MESHOPT_QUATERNION, quat_w, 8, out);
    ck_assert(i16(out) == 0 && i16(out + 2) == 0 && i16(out + 4) == 0 && i16(out + 6) == 32767);
    static const unsigned char quat_x[8] = {0, 0, 0, 0, 0, 0, 0xfc, 0x7f};
    filtered(RESURFI_MESHOPT_QUATERNION, quat_x, 8, out);
    ck_assert(i16(out) == 32767 && i16(out + 2) == 0 && i16(out + 4) == 0 && i16(out + 6) == 0);
    /* Exponential: 2^-2 × 6 = 1.5 and 2^3 × -1 = -8. */
    static const unsigned char expo[8] = {6, 0, 0, 0xfe, 0xff, 0xff, 0xff, 3};
    filtered(RESURFI_MESHOPT_EXPONENTIAL, expo, 8, out);
    float f[2];
    memcpy(f, out, 8);
    ck_assert(f[0] == 1.5f && f[1] == -8.0f);
    /* Colour (KHR's alone), YCoCg with K bits given by alpha's highest bit. K = 8: Y 100, Co 10, Cg -5 give
     * (115, 95, 95), alpha 127 in 7 bits gives 255. K = 6: Y 40, Co 3, Cg -2 give (45, 38, 39) of 63, so
     * (182, 154, 158) of 255 rounded, alpha 31 in 5 bits 255. K = 16: Y 30000, Co 1000, Cg -500. */
    static const unsigned char col8[4] = {100, 10, 0xfb, 0xff}, col6[4] = {40, 3, 0xfe, 0x3f};
    filtered_as(1, RESURFI_MESHOPT_COLOR, col8, 4, out);
    ck_assert(out[0] == 115 && out[1] == 95 && out[2] == 95 && out[3] == 255);
    filtered_as(1, RESURFI_MESHOPT_COLOR, col6, 4, out);
    ck_assert(out[0] == 182 && out[1] == 154 && out[2] == 158 && out[3] == 255);
    static const unsigned char col16[8] = {0x30, 0x75, 0xe8, 0x03, 0x0c, 0xfe, 0xff, 0xff};
    filtered_as(1, RESURFI_MESHOPT_COLOR, col16, 8, out);
    ck_assert(i16(out) == 31500 && i16(out + 2) == 29500 && i16(out + 4) == 29500 && (uint16_t)i16(out + 6) == 65535);
}
END_TEST

/* Every prefix of each stream, and each stream with one byte more, fails with a message and writes nothing
 * outside its output; so do headers of other versions and layouts a mode does not allow. */
START_TEST(meshopt_malformed_streams_fail)
{
    struct {
        resurfi_meshopt_mode mode;
        size_t count, stride;
        const unsigned char *s;
        size_t n;
    } cases[] = {{RESURFI_MESHOPT_ATTRIBUTES, 2, 4, attributes, sizeof attributes},
                 {RESURFI_MESHOPT_TRIANGLES, 15, 2, triangles, sizeof triangles},
                 {RESURFI_MESHOPT_INDICES, 4, 4, indices, sizeof indices},
                 {RESURFI_MESHOPT_ATTRIBUTES, 2, 12, attributes_v1, sizeof attributes_v1}};
    for (size_t c = 0; c < 8; ++c) { /* each case as EXT's (c < 4) and as KHR's */
        int khr = c >= 4;
        for (size_t n = 0; n <= cases[c % 4].n; ++n) {
            size_t k = c % 4;
            unsigned char *copy = malloc(n + 1), *out = malloc(cases[k].count * cases[k].stride);
            memcpy(copy, cases[k].s, n);
            if (n == cases[k].n) /* one byte more: the tail moves, a byte is left over or misread */
                copy[n] = 0;
            const char *why = resurfi_meshopt_decode(khr, cases[k].mode, RESURFI_MESHOPT_NONE, cases[k].count,
                                                     cases[k].stride, copy, n == cases[k].n ? n + 1 : n, out);
            ck_assert_msg(why != NULL, "case %zu, %zu bytes: decoded", c, n);
            free(copy);
            free(out);
        }
    }
    unsigned char out[64], bad[sizeof attributes];
    memcpy(bad, attributes, sizeof bad);
    bad[0] = 0xa1;
    ck_assert_str_eq(
        resurfi_meshopt_decode(0, RESURFI_MESHOPT_ATTRIBUTES, RESURFI_MESHOPT_NONE, 2, 4, bad, sizeof bad, out),
        "the attribute stream's header is not 0xa0 (another version of the bitstream)");
    /* Version 1 and the colour filter are KHR's; a channel mode the bitstream does not define fails. */
    ck_assert_str_eq(resurfi_meshopt_decode(0, RESURFI_MESHOPT_ATTRIBUTES, RESURFI_MESHOPT_NONE, 2, 12, attributes_v1,
                                            sizeof attributes_v1, out),
                     "the attribute stream's header is not 0xa0 (another version of the bitstream)");
    ck_assert_ptr_nonnull(resurfi_meshopt_decode(0, RESURFI_MESHOPT_ATTRIBUTES, RESURFI_MESHOPT_COLOR, 2, 4, attributes,
                                                 sizeof attributes, out));
    unsigned char v1[sizeof attributes_v1];
    memcpy(v1, attributes_v1, sizeof v1);
    v1[sizeof v1 - 1] = 0x03;
    ck_assert_str_eq(resurfi_meshopt_decode(1, RESURFI_MESHOPT_ATTRIBUTES, RESURFI_MESHOPT_NONE, 2, 12, v1, sizeof v1,
                                            out),
                     "a channel mode of the attribute stream is not one the bitstream defines");
    v1[sizeof v1 - 1] = 0x42;
    v1[sizeof v1 - 2] = 0x11; /* 16-bit deltas with a rotation */
    ck_assert_ptr_nonnull(resurfi_meshopt_decode(1, RESURFI_MESHOPT_ATTRIBUTES, RESURFI_MESHOPT_NONE, 2, 12, v1,
                                                 sizeof v1, out));
    ck_assert_ptr_nonnull(resurfi_meshopt_decode(0, RESURFI_MESHOPT_ATTRIBUTES, RESURFI_MESHOPT_NONE, 2, 6, attributes,
                                                 sizeof attributes, out));
    ck_assert_ptr_nonnull(resurfi_meshopt_decode(0, RESURFI_MESHOPT_TRIANGLES, RESURFI_MESHOPT_NONE, 14, 2, triangles,
                                                 sizeof triangles, out));
    ck_assert_ptr_nonnull(resurfi_meshopt_decode(0, RESURFI_MESHOPT_INDICES, RESURFI_MESHOPT_QUATERNION, 4, 4, indices,
                                                 sizeof indices, out));
    ck_assert_ptr_nonnull(resurfi_meshopt_decode(0, RESURFI_MESHOPT_ATTRIBUTES, RESURFI_MESHOPT_QUATERNION, 2, 4,
                                                 attributes, sizeof attributes, out));
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("meshopt_decode");
    TCase *tc = tcase_create("meshopt_decode");
    tcase_add_test(tc, meshopt_streams_decode);
    tcase_add_test(tc, meshopt_filters_decode);
    tcase_add_test(tc, meshopt_malformed_streams_fail);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
