/* PNG encoding through libpng into memory. Every setting that changes the bytes is fixed here (zlib level and
 * strategy, filters, no time, gamma or text chunks), so equal pixels give equal files with the same libpng and
 * zlib. */
#include <png.h>
#include <setjmp.h>
#include <string.h>

#include "preview/preview_internal.h"

typedef struct png_sink {
    const resurf_allocator *alloc;
    unsigned char *data;
    size_t size, cap;
    char message[128];
} png_sink;

static void sink_write(png_structp png, png_bytep bytes, png_size_t n)
{
    png_sink *s = png_get_io_ptr(png);
    if (n > s->cap - s->size) {
        size_t cap = s->cap ? s->cap : 1 << 16;
        while (n > cap - s->size) {
            if (cap > SIZE_MAX / 2)
                png_error(png, "out of memory");
            cap *= 2;
        }
        unsigned char *grown = resurfi_realloc(s->alloc, s->data, cap, 1);
        if (!grown)
            png_error(png, "out of memory");
        s->data = grown;
        s->cap = cap;
    }
    memcpy(s->data + s->size, bytes, n);
    s->size += n;
}

static void sink_flush(png_structp png) { (void)png; }

static void on_error(png_structp png, png_const_charp message)
{
    png_sink *s = png_get_error_ptr(png);
    snprintf(s->message, sizeof s->message, "%s", message);
    png_longjmp(png, 1);
}

static void on_warning(png_structp png, png_const_charp message)
{
    (void)png;
    (void)message;
}

resurf_status rp_png_encode(const unsigned char *rgba, unsigned w, unsigned h, const resurf_allocator *alloc,
                            unsigned char **out_data, size_t *out_size, resurf_error *error)
{
    png_sink sink = {.alloc = alloc};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, on_error, on_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        png_destroy_write_struct(&png, &info);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory encoding the PNG");
    }
    /* After a longjmp only what was stored before setjmp is read: sink lives outside, and png/info are not
     * changed below. */
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        resurfi_free(alloc, sink.data);
        int oom = strstr(sink.message, "memory") != NULL;
        return resurfi_error(error, oom ? RESURF_ERR_OUT_OF_MEMORY : RESURF_ERR_INTERNAL, "encoding the PNG: %s",
                             sink.message);
    }
    png_set_write_fn(png, &sink, sink_write, sink_flush);
    png_set_compression_level(png, 6);
    png_set_compression_strategy(png, 0); /* Z_DEFAULT_STRATEGY */
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_ALL_FILTERS);
    png_set_IHDR(png, info, w, h, 8, PNG_COLOR_TYPE_RGBA, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_BASE,
                 PNG_FILTER_TYPE_BASE);
    png_write_info(png, info);
    for (unsigned y = 0; y < h; ++y)
        png_write_row(png, rgba + (size_t)y * w * 4);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    *out_data = sink.data;
    *out_size = sink.size;
    return RESURF_OK;
}
