/* libFuzzer harness: the preview's texture decoder (PNG through libpng, JPEG through libjpeg) on arbitrary bytes.
 * Every input must decode or fail with a reason, within the decoder's size bounds, and leak nothing. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "preview/preview_internal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    rp_texture t;
    char why[128];
    resurf_status s = rp_texture_decode(data, size, NULL, &t, why, sizeof why);
    if (s == RESURF_OK) {
        if (!t.rgba || t.width == 0 || t.height == 0 || (size_t)t.width * t.height > RP_TEXTURE_MAX_PIXELS)
            abort();
        volatile unsigned char sink = t.rgba[4 * ((size_t)t.width * t.height) - 1];
        (void)sink;
    } else if (!why[0] || t.rgba) {
        abort(); /* a failure always says why and hands out no pixels */
    }
    rp_texture_free(&t, NULL);
    return 0;
}
