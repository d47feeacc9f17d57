/* libFuzzer harness: EXT_ and KHR_meshopt_compression's decoder (src/meshopt_decode.c) on arbitrary streams. The
 * first four bytes choose the call: mode, filter and extension (byte 0: mode % 3, filter / 3 % 5, KHR from 15 on),
 * byteStride - 1 (byte 1), the element count (bytes 2 and 3, little endian); the rest is the stream. Every read must stay in the stream and every write in the output (ASan), and a
 * failure must say why. */
#include <stdint.h>
#include <stdlib.h>

#include "meshopt_decode.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 4)
        return 0;
    resurfi_meshopt_mode mode = (resurfi_meshopt_mode)(data[0] % 3);
    resurfi_meshopt_filter filter = (resurfi_meshopt_filter)(data[0] / 3 % 5);
    int khr = data[0] >= 15;
    size_t stride = (size_t)data[1] + 1, count = (size_t)data[2] | (size_t)data[3] << 8;
    unsigned char *out = malloc(count * stride + 1);
    if (!out)
        return 0;
    const char *why = resurfi_meshopt_decode(khr, mode, filter, count, stride, data + 4, size - 4, out);
    if (why && !why[0])
        abort();
    free(out);
    return 0;
}
