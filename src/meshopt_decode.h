/* EXT_meshopt_compression's three bitstreams and three filters, and KHR_meshopt_compression's (the same, with
 * version 1 of the attribute bitstream and a fourth filter, colour), decoded (src/meshopt_decode.c) for the glTF
 * reader: a document that requires either extension has its compressed bufferViews decoded into their parent
 * bufferViews' layout before anything reads them. Written from the extensions' specifications (KhronosGroup/glTF,
 * extensions/2.0/Vendor/EXT_meshopt_compression and extensions/2.0/Khronos/KHR_meshopt_compression, Appendices A
 * and B). Not installed. */
#ifndef RESURF_MESHOPT_DECODE_H
#define RESURF_MESHOPT_DECODE_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum resurfi_meshopt_mode {
    RESURFI_MESHOPT_ATTRIBUTES,
    RESURFI_MESHOPT_TRIANGLES,
    RESURFI_MESHOPT_INDICES
} resurfi_meshopt_mode;

typedef enum resurfi_meshopt_filter {
    RESURFI_MESHOPT_NONE,
    RESURFI_MESHOPT_OCTAHEDRAL,
    RESURFI_MESHOPT_QUATERNION,
    RESURFI_MESHOPT_EXPONENTIAL,
    RESURFI_MESHOPT_COLOR /* KHR_meshopt_compression's alone */
} resurfi_meshopt_filter;

/* Decodes `size` bytes of src, count elements of `stride` bytes each, into out (count × stride bytes), as
 * KHR_meshopt_compression's stream (khr != 0) or EXT_meshopt_compression's. Every read stays inside src, every
 * write inside out. Returns NULL, or what is wrong (a static string): a stride or filter the mode does not allow,
 * an unknown header (another version of a bitstream), a stream too short or with bytes left over. */
const char *resurfi_meshopt_decode(int khr, resurfi_meshopt_mode mode, resurfi_meshopt_filter filter, size_t count,
                                   size_t stride, const unsigned char *src, size_t size, unsigned char *out);

#ifdef __cplusplus
}
#endif

#endif
