/*
 * resurf — a preview picture of every level.
 *
 * Part of the manual that include/resurf/resurf.h begins (its conventions hold here); resurf.h includes this
 * header, so `#include <resurf/resurf.h>` is all a caller needs.
 */
#ifndef RESURF_RESURF_H
#include "resurf.h" /* which includes this header at its end, in the manual's order */
#elif !defined(RESURF_PREVIEW_H)
#define RESURF_PREVIEW_H

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------------------------------------------- */
/* Preview: a picture of every level                                                                            */
/* ------------------------------------------------------------------------------------------------------------- */

/* A contact sheet of a scene's levels of detail, drawn by a software rasterizer (no GPU, no window): one cell per
 * level, all from the same perspective camera framing the whole scene (the bounding sphere of level 0), shaded with
 * each level's own normals (face normals where a primitive has none) by Lambert + ambient light fixed to the
 * camera, both sides of a face lit alike (no culling: open meshes show their inside). Under each cell: the level,
 * its triangles, its two-sided error (resurf_compare's hausdorff between level 0 and the level, relative to level
 * 0's diagonal and in scene units) and its MSFT_lod screen coverage. Every node that shows a mesh is drawn with its
 * world transform, as a viewer would; primitives with morph targets at rest; points and lines are not drawn.
 * Each primitive shows its material's base colour (baseColorFactor) times its base-colour texture, PNG or JPEG
 * (libpng, libjpeg), sampled bilinearly with its sampler's wrap modes at the texture coordinates the material names
 * (KHR_texture_transform is not applied); a primitive without a material is a warm grey. An image that cannot be
 * decoded leaves its surfaces with the colour alone and is counted in the report (textures_undrawn), never an error.
 * Deterministic: the same scene and options give the same pixels for any thread count and on any machine whose C
 * library computes the camera's sin, cos, tan and atan alike (the drawing itself uses exact IEEE operations only),
 * and, with the same libpng and zlib, the same PNG bytes. */

typedef enum resurf_preview_view {
    RESURF_PREVIEW_THREE_QUARTER = 0, /* default: yaw 35°, pitch 20° (in front, to the right, above) */
    RESURF_PREVIEW_FRONT,             /* from +z looking down -z (yaw 0, pitch 0) */
    RESURF_PREVIEW_SIDE,              /* from +x (yaw 90°) */
    RESURF_PREVIEW_TOP,               /* from +y (pitch 90°; -z is up on screen) */
    RESURF_PREVIEW_ISO,               /* yaw 45°, pitch 35.26° (the isometric direction (1, 1, 1)) */
    RESURF_PREVIEW_VIEW_COUNT
} resurf_preview_view;

#define RESURF_PREVIEW_MAX_SIDE 16384         /* width and height at most this */
#define RESURF_PREVIEW_MAX_PIXELS (1u << 26)  /* width × height at most this (256 MB of RGBA) */

typedef struct resurf_preview_options {
    size_t struct_size;
    unsigned width, height;   /* the sheet in pixels; 16..RESURF_PREVIEW_MAX_SIDE each, at most
                                 RESURF_PREVIEW_MAX_PIXELS in all (else RESURF_ERR_LIMIT); default 1600 × 900 */
    resurf_preview_view view; /* default RESURF_PREVIEW_THREE_QUARTER */
    double yaw_deg, pitch_deg;/* added to the view's angles (yaw about +y, pitch up from the horizon), finite; 0 */
    bool wireframe;           /* true: darken the triangles' edges; default false */
    bool heatmap;             /* true: under each level's picture a second one coloured by the distance from each
                                 visible point of the level to level 0's surface (exact, per pixel), one colour
                                 scale for all levels, with a colour bar in scene units at the bottom; default 0 */
    unsigned char background[4]; /* RGBA; default 255, 255, 255, 255 */
    bool measure;             /* true (default): measure each level's error with resurf_compare; false: skip it (the
                                 labels and report then say nothing about errors: NaN) */
    size_t compare_samples;   /* resurf_compare's samples for each level's error; default 10000; 0 = vertices */
    unsigned threads;         /* 0 = all cores (the error measure and the heat map's distances) */
    resurf_progress progress; /* RESURF_STAGE_PREVIEW; a cancel returns RESURF_ERR_CANCELLED */
    const resurf_allocator *allocator; /* NULL (default): the scene's; see resurf_allocator */
} resurf_preview_options;

RESURF_API resurf_preview_options resurf_preview_options_default(void);

/* An 8-bit RGBA image, rows top to bottom, no padding; rgba comes from `allocator` (freed by
 * resurf_preview_image_free). */
typedef struct resurf_preview_image {
    unsigned width, height;
    unsigned char *rgba;
    resurf_allocator allocator;
} resurf_preview_image;

/* What the sheet shows, in numbers. Levels count from 0 (full detail). */
typedef struct resurf_preview_report {
    size_t levels;                                   /* 1 + the most levels of detail any primitive has */
    size_t level_triangles[RESURF_SCENE_MAX_LEVELS]; /* triangles drawn (each instance counted) */
    double level_error[RESURF_SCENE_MAX_LEVELS];     /* two-sided error to level 0 in scene units (0 for level 0;
                                                        NaN when not measurable: a level without triangles) */
    double level_error_rel[RESURF_SCENE_MAX_LEVELS]; /* the same over level 0's bounding-box diagonal */
    double level_coverage[RESURF_SCENE_MAX_LEVELS];  /* MSFT_lod screen coverage from which the level shows (the
                                                        first node with levels: its file's values, its set values,
                                                        else the defaults resurf_scene_save writes), -1 with a single
                                                        level or when unknown */
    double diagonal;                                 /* of level 0's bounding box in world space */
    double heat_max;                                 /* the colour bar's top in scene units (0 without heatmap) */
    size_t textures_undrawn;                         /* base-colour images that could not be drawn (missing, not
                                                        PNG or JPEG, or broken): their surfaces show the material's
                                                        colour alone */
    char texture_warning[192];                       /* the first of them and why ("images[2] 'a.tga': neither
                                                        PNG nor JPEG"), "" when none */
} resurf_preview_report;

/* Draws the sheet of scene into *out_image (required; on failure it is zeroed). A node's levels are those set on
 * its mesh's primitives (resurf_scene_set_lods, resurf_scene_build_lods), else those its MSFT_lod extension names
 * in the loaded file (each level node's mesh, drawn with the transform of the node it stands in for, as resurf
 * writes them; an extension naming a node without a mesh is ignored), with extras.MSFT_screencoverage. A scene
 * without triangles gives empty panels; degenerate triangles are skipped. out_report may be NULL. */
RESURF_API resurf_status resurf_preview_render(const resurf_scene *scene, const resurf_preview_options *options,
                                               resurf_preview_image *out_image, resurf_preview_report *out_report,
                                               resurf_error *error);

/* Frees the image's pixels and zeroes it. NULL is allowed. */
RESURF_API void resurf_preview_image_free(resurf_preview_image *image);

/* Writes the image as an RGBA PNG (libpng, fixed settings), atomically: a temporary file in path's folder renamed
 * into place once complete, so a failure leaves no partial file. */
RESURF_API resurf_status resurf_preview_save_png(const resurf_preview_image *image, const char *path,
                                                 resurf_error *error);

#ifdef __cplusplus
}
#endif

#endif /* RESURF_PREVIEW_H */
