/* Tests of src/meshopt_decode.c, EXT_meshopt_compression's bitstreams and filters. The streams are written by hand
 * from the specification's Appendix A, each decoded by hand there too; meshoptimizer 0.18's decoder
 * (meshopt_decodeVertexBuffer, meshopt_decodeIndexBuffer, meshopt_decodeIndexSequence) gave the same values for
 * all three when they were written. The filters' cases are values whose decoding is exact. Then every stream
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

START_TEST(meshopt_streams_decode)
{
    unsigned char out[64];
    ck_assert_ptr_null(resurfi_meshopt_decode(RESURFI_MESHOPT_ATTRIBUTES, RESURFI_MESHOPT_NONE, 2, 4, attributes,
                                              sizeof attributes, out));
    ck_assert_mem_eq(out, attributes_want, 8);
    ck_assert_ptr_null(resurfi_meshopt_decode(RESURFI_MESHOPT_TRIANGLES, RESURFI_MESHOPT_NONE, 15, 2, triangles,
                                              sizeof triangles, out));
    for (int i = 0; i < 15; ++i)
        ck_assert_uint_eq(out[2 * i] | out[2 * i + 1] << 8, triangles_want[i]);
    ck_assert_ptr_null(resurfi_meshopt_decode(RESURFI_MESHOPT_INDICES, RESURFI_MESHOPT_NONE, 4, 4, indices,
                                              sizeof indices, out));
    for (int i = 0; i < 4; ++i)
        ck_assert_uint_eq((uint32_t)out[4 * i] | (uint32_t)out[4 * i + 1] << 8 | (uint32_t)out[4 * i + 2] << 16 |
                              (uint32_t)out[4 * i + 3] << 24,
                          indices_want[i]);
}
END_TEST

/* Each filter on values whose decoding is exact, through a byte-mode stream of one element. */
static void filtered(resurfi_meshopt_filter filter, const unsigned char *element, size_t stride, unsigned char *out)
{
    unsigned char s[1 + 256 * 17 + 256 + 32];
    size_t n = 0;
    s[n++] = 0xa0;
    for (size_t k = 0; k < stride; ++k) { /* deltas from the baseline, itself the element: all zero */
        s[n++] = 0;
    }
    for (size_t i = stride; i < 32; ++i)
        s[n++] = 0;
    memcpy(s + n, element, stride);
    n += stride;
    ck_assert_ptr_null(resurfi_meshopt_decode(RESURFI_MESHOPT_ATTRIBUTES, filter, 1, stride, s, n, out));
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
                 {RESURFI_MESHOPT_INDICES, 4, 4, indices, sizeof indices}};
    for (size_t c = 0; c < 3; ++c) {
        for (size_t n = 0; n <= cases[c].n; ++n) {
            unsigned char *copy = malloc(n + 1), *out = malloc(cases[c].count * cases[c].stride);
            memcpy(copy, cases[c].s, n);
            if (n == cases[c].n) /* one byte more: the tail moves, a byte is left over or misread */
                copy[n] = 0;
            const char *why = resurfi_meshopt_decode(cases[c].mode, RESURFI_MESHOPT_NONE, cases[c].count,
                                                     cases[c].stride, copy, n == cases[c].n ? n + 1 : n, out);
            ck_assert_msg(why != NULL, "case %zu, %zu bytes: decoded", c, n);
            free(copy);
            free(out);
        }
    }
    unsigned char out[64], bad[sizeof attributes];
    memcpy(bad, attributes, sizeof bad);
    bad[0] = 0xa1;
    ck_assert_str_eq(
        resurfi_meshopt_decode(RESURFI_MESHOPT_ATTRIBUTES, RESURFI_MESHOPT_NONE, 2, 4, bad, sizeof bad, out),
        "the attribute stream's header is not 0xa0 (another version of the bitstream)");
    ck_assert_ptr_nonnull(resurfi_meshopt_decode(RESURFI_MESHOPT_ATTRIBUTES, RESURFI_MESHOPT_NONE, 2, 6, attributes,
                                                 sizeof attributes, out));
    ck_assert_ptr_nonnull(resurfi_meshopt_decode(RESURFI_MESHOPT_TRIANGLES, RESURFI_MESHOPT_NONE, 14, 2, triangles,
                                                 sizeof triangles, out));
    ck_assert_ptr_nonnull(resurfi_meshopt_decode(RESURFI_MESHOPT_INDICES, RESURFI_MESHOPT_QUATERNION, 4, 4, indices,
                                                 sizeof indices, out));
    ck_assert_ptr_nonnull(resurfi_meshopt_decode(RESURFI_MESHOPT_ATTRIBUTES, RESURFI_MESHOPT_QUATERNION, 2, 4,
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
