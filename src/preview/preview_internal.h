/* What the preview's files share (src/preview/): the camera, a panel to draw into, the rasterizer, the bitmap
 * font, the heat colours and the PNG encoder. Not installed. The sheet (sheet.c) is the only caller. */
#ifndef RESURF_PREVIEW_INTERNAL_H
#define RESURF_PREVIEW_INTERNAL_H

#include <stdint.h>

#include "internal.h"
#include "vec3.h"

/* A perspective camera: the eye, its right/up/forward axes (orthonormal; forward points into the picture) and the
 * focal length in pixels. A world point p is at camera coordinates (x, y, z) = ((p - eye)·right, (p - eye)·up,
 * (p - eye)·forward) and at pixel (cx + focal·x/z, cy - focal·y/z) of its panel (pixel centres at i + 0.5). */
typedef struct rp_camera {
    vec3 eye, right, up, forward;
    double focal, cx, cy;
    double near;            /* triangles with a corner nearer than this (z <= near) are not drawn */
} rp_camera;

/* The camera for a panel of w × h pixels that sees the sphere (centre, radius) whole from direction
 * (yaw_deg about +y, pitch_deg up from the horizon; yaw 0 pitch 0 looks along -z), with a vertical field of view
 * of RP_FOV_DEG. radius <= 0 (an empty scene) is taken as 1. */
#define RP_FOV_DEG 30.0
rp_camera rp_camera_frame(vec3 centre, double radius, double yaw_deg, double pitch_deg, unsigned w, unsigned h);
/* Moves the eye along its view line so that every corner of mesh's triangles falls inside the w × h picture with a
 * 5% margin (the picture's aspect is used whole, unlike the sphere), but never into the scene's bounding sphere
 * about centre. Unchanged for a mesh without drawable triangles. */
void rp_camera_fit(rp_camera *c, vec3 centre, const resurf_mesh *mesh, unsigned w, unsigned h);

/* A w × h panel at (x0, y0) of an RGBA image `stride` pixels wide; depth holds w × h inverse depths (1/z; 0 = empty,
 * the rasterizer's far value). Optional (NULL, or w × h entries): position, the world point each covered pixel
 * shows (3 doubles), and shade, its lighting factor in [0, 1] (wireframe included), for the heat map's colours. */
typedef struct rp_panel {
    unsigned char *rgba;
    size_t stride;
    unsigned x0, y0, w, h;
    double *depth;
    double *position;
    float *shade;
} rp_panel;

/* A decoded texture: 8-bit RGBA, rows top to bottom (image_decode.c). */
#define RP_TEXTURE_MAX_SIDE 16384
#define RP_TEXTURE_MAX_PIXELS ((size_t)1 << 26)
typedef struct rp_texture {
    unsigned width, height;
    unsigned char *rgba;
} rp_texture;

/* Decodes a PNG or JPEG image (by its first bytes) into out (pixels from alloc). On failure *out is zeroed and why
 * says what is wrong: RESURF_ERR_UNSUPPORTED for another type, RESURF_ERR_PARSE for broken bytes,
 * RESURF_ERR_LIMIT for a side over RP_TEXTURE_MAX_SIDE or more than RP_TEXTURE_MAX_PIXELS pixels, RESURF_ERR_OUT_OF_MEMORY. */
resurf_status rp_texture_decode(const unsigned char *data, size_t size, const resurf_allocator *alloc,
                                rp_texture *out, char *why, size_t why_size);
void rp_texture_free(rp_texture *t, const resurf_allocator *alloc);

/* glTF's sampler wrap modes. */
enum { RP_WRAP_REPEAT = 10497, RP_WRAP_CLAMP = 33071, RP_WRAP_MIRROR = 33648 };

/* How a mesh is drawn: a colour lit by Lambert + ambient from a light fixed to the camera (upper left, in front),
 * both sides lit alike (no culling: open meshes show their inside). The colour is base, times the texture sampled
 * bilinearly at the pixel's texture coordinates (perspective-correct; set `texcoord` of the mesh) when there is
 * one. wireframe darkens pixels within RP_WIRE_PX of a triangle's edge. */
#define RP_WIRE_PX 0.6
typedef struct rp_style {
    double base[3];         /* 0..1 */
    int wireframe;
    const rp_texture *texture; /* NULL: none */
    unsigned texcoord;      /* the mesh's texture-coordinate set the texture uses (it must have it) */
    int wrap_s, wrap_t;     /* RP_WRAP_* (anything else repeats) */
} rp_style;

/* Draws the triangles of a mesh moved by world (NULL: the identity) into the panel: z-buffer, perspective-correct
 * interpolation of the mesh's normals (face normals when it has none), no culling. Triangles with non-finite
 * corners, zero screen area or a corner behind camera->near are skipped. Returns RESURF_ERR_OUT_OF_MEMORY
 * (camera-space copies of the vertices) or OK. */
resurf_status rp_draw_mesh(rp_panel *panel, const rp_camera *camera, const resurf_mesh *mesh, const affine3 *world,
                           const rp_style *style, const resurf_allocator *alloc);

/* ---- text (font.c) ------------------------------------------------------------------------------------------- */

/* The built-in 5 × 7 font: digits, letters (lower case drawn as upper case), space and . , : ; - + % ( ) / = _ < >
 * ' # *; anything else is drawn as '?'. Each glyph is scale × 5 wide, scale × 7 high, RP_ADVANCE × scale apart. */
#define RP_GLYPH_W 5
#define RP_GLYPH_H 7
#define RP_ADVANCE 6
/* Draws text with its top-left corner at (x, y), clipped to the image (w × h pixels). */
void rp_draw_text(unsigned char *rgba, unsigned w, unsigned h, int x, int y, unsigned scale, const char *text,
                  const unsigned char colour[3]);
/* Width in pixels text takes at scale. */
unsigned rp_text_width(const char *text, unsigned scale);

/* ---- heat colours (heatmap.c) -------------------------------------------------------------------------------- */

/* The colour of t in [0, 1] (clamped; NaN is 1): dark blue, blue, teal, yellow, red. */
void rp_heat_colour(double t, unsigned char out[3]);

/* ---- PNG (png_write.c) --------------------------------------------------------------------------------------- */

/* Encodes an 8-bit RGBA image as PNG into a new block of alloc (*out_data, *out_size) with fixed settings (zlib
 * level 6, filter and strategy fixed, no time or text chunks), so the bytes depend on the pixels alone. */
resurf_status rp_png_encode(const unsigned char *rgba, unsigned w, unsigned h, const resurf_allocator *alloc,
                            unsigned char **out_data, size_t *out_size, resurf_error *error);

#endif
