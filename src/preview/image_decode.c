/* Decoding the base-colour textures the preview draws: PNG through libpng's simplified API, JPEG through libjpeg
 * (libjpeg-turbo on Debian), both to 8-bit RGBA. Nothing else is decoded: the preview draws a surface whose image
 * is of another type, or broken, untextured and says so in its report. Both libraries give the same pixels for
 * the same bytes on every machine with the same library versions (no dithering, no fancy scaling). */
#include <setjmp.h>
#include <stddef.h>
#include <stdio.h> /* before jpeglib.h, which uses size_t and FILE without including them */
#include <string.h>

#include <jpeglib.h>
#include <png.h>

#include "preview/preview_internal.h"

static int is_png(const unsigned char *d, size_t n)
{
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    return n >= 8 && !memcmp(d, sig, 8);
}

static int is_jpeg(const unsigned char *d, size_t n) { return n >= 3 && d[0] == 0xff && d[1] == 0xd8 && d[2] == 0xff; }

/* A bound on what a few hundred hostile bytes can make the decoder allocate: a side of 16384, 2^26 pixels. */
static int too_big(size_t w, size_t h)
{
    return w == 0 || h == 0 || w > RP_TEXTURE_MAX_SIDE || h > RP_TEXTURE_MAX_SIDE || w * h > RP_TEXTURE_MAX_PIXELS;
}

static resurf_status decode_png(const unsigned char *data, size_t size, const resurf_allocator *alloc,
                                rp_texture *out, char *why, size_t why_size)
{
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&img, data, size)) {
        snprintf(why, why_size, "PNG: %s", img.message);
        return RESURF_ERR_PARSE;
    }
    if (too_big(img.width, img.height)) {
        snprintf(why, why_size, "PNG of %u x %u pixels (at most %d a side, %lu in all)", img.width, img.height,
                 RP_TEXTURE_MAX_SIDE, (unsigned long)RP_TEXTURE_MAX_PIXELS);
        png_image_free(&img);
        return RESURF_ERR_LIMIT;
    }
    img.format = PNG_FORMAT_RGBA;
    unsigned char *rgba = resurfi_alloc(alloc, (size_t)img.width * img.height, 4);
    if (!rgba) {
        png_image_free(&img);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    if (!png_image_finish_read(&img, NULL, rgba, 0, NULL)) {
        snprintf(why, why_size, "PNG: %s", img.message);
        resurfi_free(alloc, rgba);
        png_image_free(&img);
        return RESURF_ERR_PARSE;
    }
    out->width = img.width, out->height = img.height, out->rgba = rgba;
    return RESURF_OK;
}

/* libjpeg reports a fatal error through error_exit, which must not return: it jumps back here with the message. */
typedef struct jpeg_failure {
    struct jpeg_error_mgr mgr;
    jmp_buf back;
    char message[JMSG_LENGTH_MAX];
} jpeg_failure;

static void jpeg_fail(j_common_ptr info)
{
    jpeg_failure *f = (jpeg_failure *)info->err;
    (*info->err->format_message)(info, f->message);
    longjmp(f->back, 1);
}

static void jpeg_quiet(j_common_ptr info, int level) { (void)info, (void)level; } /* warnings are not printed */

static resurf_status decode_jpeg(const unsigned char *data, size_t size, const resurf_allocator *alloc,
                                 rp_texture *out, char *why, size_t why_size)
{
    struct jpeg_decompress_struct info;
    jpeg_failure failure;
    /* Set before the jump point and read after it: volatile, so a longjmp cannot leave a stale register copy. */
    unsigned char *volatile rgba = NULL;
    unsigned char *volatile row = NULL;
    info.err = jpeg_std_error(&failure.mgr);
    failure.mgr.error_exit = jpeg_fail;
    failure.mgr.emit_message = jpeg_quiet;
    if (setjmp(failure.back)) {
        snprintf(why, why_size, "JPEG: %s", failure.message);
        jpeg_destroy_decompress(&info);
        resurfi_free(alloc, rgba);
        resurfi_free(alloc, row);
        return RESURF_ERR_PARSE;
    }
    jpeg_create_decompress(&info);
    jpeg_mem_src(&info, data, (unsigned long)size);
    jpeg_read_header(&info, TRUE);
    info.out_color_space = JCS_RGB;
    info.dct_method = JDCT_ISLOW; /* the exact integer transform: the same pixels everywhere */
    info.do_fancy_upsampling = TRUE;
    jpeg_start_decompress(&info);
    if (too_big(info.output_width, info.output_height) || info.output_components != 3) {
        snprintf(why, why_size, "JPEG of %u x %u pixels, %d components (at most %d a side, %lu in all, 3 components)",
                 info.output_width, info.output_height, info.output_components, RP_TEXTURE_MAX_SIDE,
                 (unsigned long)RP_TEXTURE_MAX_PIXELS);
        jpeg_destroy_decompress(&info);
        return RESURF_ERR_LIMIT;
    }
    size_t w = info.output_width, h = info.output_height;
    rgba = resurfi_alloc(alloc, w * h, 4);
    row = resurfi_alloc(alloc, w, 3);
    if (!rgba || !row) {
        jpeg_destroy_decompress(&info);
        resurfi_free(alloc, rgba);
        resurfi_free(alloc, row);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    while (info.output_scanline < info.output_height) {
        size_t y = info.output_scanline;
        JSAMPROW rows[1] = {row};
        if (jpeg_read_scanlines(&info, rows, 1) != 1)
            break;
        for (size_t x = 0; x < w; ++x) {
            unsigned char *p = rgba + 4 * (y * w + x);
            p[0] = row[3 * x], p[1] = row[3 * x + 1], p[2] = row[3 * x + 2], p[3] = 255;
        }
    }
    jpeg_finish_decompress(&info);
    jpeg_destroy_decompress(&info);
    resurfi_free(alloc, row);
    out->width = (unsigned)w, out->height = (unsigned)h, out->rgba = rgba;
    return RESURF_OK;
}

resurf_status rp_texture_decode(const unsigned char *data, size_t size, const resurf_allocator *alloc,
                                rp_texture *out, char *why, size_t why_size)
{
    memset(out, 0, sizeof *out);
    why[0] = 0;
    if (is_png(data, size))
        return decode_png(data, size, alloc, out, why, why_size);
    if (is_jpeg(data, size))
        return decode_jpeg(data, size, alloc, out, why, why_size);
    snprintf(why, why_size, "neither PNG nor JPEG");
    return RESURF_ERR_UNSUPPORTED;
}

void rp_texture_free(rp_texture *t, const resurf_allocator *alloc)
{
    resurfi_free(alloc, t->rgba);
    memset(t, 0, sizeof *t);
}
