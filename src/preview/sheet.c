/* The preview sheet: the public calls. Gathers each level of the scene into one world-space mesh (scene_world.c),
 * measures its error against level 0, lays out one cell per level, draws it (raster.c), the heat map's distances (the BVH of level 0, per pixel), the labels (font.c) and the colour bar.
 * Memory: the image, level 0 and the level being drawn (plus level 0's BVH for a heat map). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "file.h"
#include "preview/preview_internal.h"
#include "scene_internal.h"

resurf_preview_options resurf_preview_options_default(void)
{
    return (resurf_preview_options){
        .struct_size = sizeof(resurf_preview_options),
        .width = 1600,
        .height = 900,
        .background = {255, 255, 255, 255},
        .measure = true,
        .compare_samples = 10000,
    };
}

void resurf_preview_image_free(resurf_preview_image *image)
{
    if (!image)
        return;
    resurfi_free(&image->allocator, image->rgba);
    memset(image, 0, sizeof *image);
}

/* ---- layout ------------------------------------------------------------------------------------------------ */

typedef struct layout {
    unsigned scale;         /* of the font */
    unsigned line_h;        /* a text line's height */
    unsigned cols, rows;    /* cells */
    unsigned cell_w, cell_h;
    unsigned panel_h;       /* each picture in a cell (two with a heat map) */
    unsigned label_h;
    unsigned footer_h;      /* the colour bar's strip */
} layout;

enum { LABEL_LINES = 3 };

/* The grid of cells whose pictures are largest (their smaller side), for `levels` cells. */
static layout make_layout(unsigned w, unsigned h, size_t levels, int heatmap)
{
    layout l = {.scale = w / levels >= 240 && h >= 400 ? 2 : 1}; /* labels of 20 characters at twice the size */
    l.line_h = (RP_GLYPH_H + 3) * l.scale;
    l.label_h = LABEL_LINES * l.line_h + 2 * l.scale;
    l.footer_h = heatmap ? 3 * l.line_h + 4 * l.scale : 0;
    unsigned pictures = heatmap ? 2 : 1;
    unsigned avail = h > l.footer_h ? h - l.footer_h : 0;
    long long best = -1;
    for (unsigned cols = 1; cols <= levels; ++cols) {
        unsigned rows = (unsigned)((levels + cols - 1) / cols);
        unsigned cell_w = w / cols, cell_h = avail / rows;
        unsigned panel_h = cell_h > l.label_h ? (cell_h - l.label_h) / pictures : 0;
        long long side = cell_w < panel_h ? cell_w : panel_h;
        if (side > best) {
            best = side;
            l.cols = cols;
            l.rows = rows;
            l.cell_w = cell_w;
            l.cell_h = cell_h;
            l.panel_h = panel_h;
        }
    }
    return l;
}

/* ---- text ---------------------------------------------------------------------------------------------------- */

/* n with thousands separators ("1,234,567"). */
static void thousands(char *dst, size_t size, size_t n)
{
    char digits[32];
    int len = snprintf(digits, sizeof digits, "%zu", n);
    size_t o = 0;
    for (int i = 0; i < len && o + 2 < size; ++i) {
        if (i > 0 && (len - i) % 3 == 0)
            dst[o++] = ',';
        dst[o++] = digits[i];
    }
    dst[o] = 0;
}

/* A line centred in [x, x + w) at row y, at scale. */
static void draw_line(resurf_preview_image *img, const layout *l, unsigned scale, unsigned x, unsigned w, unsigned y,
                      const char *text, const unsigned char ink[3])
{
    unsigned tw = rp_text_width(text, scale);
    int left = (int)x + (tw < w ? (int)(w - tw) / 2 : 0);
    int top = (int)y + (int)((l->line_h - RP_GLYPH_H * scale) / 2);
    rp_draw_text(img->rgba, img->width, img->height, left, top, scale, text, ink);
}

/* ---- heat map ------------------------------------------------------------------------------------------------ */

typedef struct heat_job {
    const resurfi_bvh *bvh;
    const rp_panel *panel;
    float *distance;        /* the sheet's heat distances, width × height, NaN where nothing is shown */
    unsigned width;
} heat_job;

/* The distance from each covered pixel's world point to level 0's surface, row by row (each pixel is its own:
 * the result is the same for any split over threads). */
static int heat_rows(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    const heat_job *job = ctx;
    const rp_panel *p = job->panel;
    for (size_t j = begin; j < end; ++j)
        for (unsigned i = 0; i < p->w; ++i) {
            size_t at = j * p->w + i;
            if (!(p->depth[at] > 0))
                continue;
            double d2 = INFINITY;
            resurfi_bvh_closest(job->bvh, v3_load(p->position + 3 * at), INFINITY, NULL, NULL, &d2);
            job->distance[(p->y0 + j) * (size_t)job->width + p->x0 + i] = isfinite(d2) ? (float)sqrt(d2) : 0.0f;
        }
    return 0;
}

/* ---- the sheet ----------------------------------------------------------------------------------------------- */

typedef struct sheet {
    const resurf_scene *scene;
    resurf_preview_options o;
    const resurf_allocator *alloc;
    resurf_error *error;
    resurf_preview_image img;
    layout l;
    rp_camera camera;
    resurfi_scene_instances list;
    resurf_mesh *level0;
    resurfi_bvh *bvh;
    double *depth, *position;
    float *panel_shade;      /* heat map: a panel's lighting factors, */
    float *shade, *distance; /* and the sheet's, with the distances */
    unsigned char ink[3];
    rp_texture *textures;    /* per image of the document, decoded when first drawn */
    signed char *texture_state; /* per image: 0 not tried, 1 decoded, -1 cannot be drawn */
    resurf_preview_report *rep;
} sheet;

static void clear_panel(sheet *s, rp_panel *p)
{
    for (size_t k = 0; k < (size_t)p->w * p->h; ++k)
        s->depth[k] = 0;
}

/* A surface without a material. */
static const double base_colour[3] = {0.80, 0.78, 0.74};

/* The decoded image i, or NULL when it cannot be drawn (counted and, the first time, described in the report). */
static const rp_texture *texture_of(sheet *s, size_t i)
{
    if (!s->textures || i >= s->scene->view->image_count)
        return NULL;
    if (s->texture_state[i] == 0) {
        const unsigned char *data;
        size_t size;
        char why[128] = "";
        resurf_status st = resurfi_scene_image_bytes(s->scene, i, &data, &size);
        if (st == RESURF_OK)
            st = rp_texture_decode(data, size, s->alloc, &s->textures[i], why, sizeof why);
        else
            snprintf(why, sizeof why, "%s", st == RESURF_ERR_IO ? "missing" : "outside its buffer");
        s->texture_state[i] = st == RESURF_OK ? 1 : -1;
        if (st != RESURF_OK && s->rep->textures_undrawn++ == 0) {
            const char *uri = s->scene->view->images[i].uri;
            snprintf(s->rep->texture_warning, sizeof s->rep->texture_warning, "images[%zu]%s%.60s%s: %s", i,
                     uri[0] && strncmp(uri, "data:", 5) ? " '" : "", uri[0] && strncmp(uri, "data:", 5) ? uri : "",
                     uri[0] && strncmp(uri, "data:", 5) ? "'" : "", why);
        }
    }
    return s->texture_state[i] > 0 ? &s->textures[i] : NULL;
}

/* How primitive p is drawn: its material's base colour and base-colour texture (when its image decodes and the
 * primitive has the texture coordinates it names), else the sheet's grey. The heat pictures need no colour. */
static rp_style style_of(sheet *s, size_t p, int colour)
{
    rp_style st = {.base = {base_colour[0], base_colour[1], base_colour[2]}, .wireframe = s->o.wireframe};
    const resurfi_gltf_view *v = s->scene->view;
    if (!colour || !v)
        return st;
    const resurf_scene_primitive *info = &s->scene->prims[p].info;
    long long mi = v->meshes[info->mesh].primitives[info->primitive].material;
    if (mi < 0 || (size_t)mi >= v->material_count)
        return st;
    const resurfi_gltf_material *mat = &v->materials[mi];
    for (int c = 0; c < 3; ++c)
        st.base[c] = mat->base_color[c] < 0 ? 0 : mat->base_color[c] > 1 ? 1 : mat->base_color[c];
    long long ti = mat->base_color_texture;
    if (ti < 0 || (size_t)ti >= v->texture_count || v->textures[ti].source < 0 || mat->base_color_texcoord < 0)
        return st;
    st.texture = texture_of(s, (size_t)v->textures[ti].source);
    st.texcoord = (unsigned)mat->base_color_texcoord;
    st.wrap_s = v->textures[ti].wrap_s;
    st.wrap_t = v->textures[ti].wrap_t;
    return st;
}

/* Level k of every drawn node into the panel, primitive by primitive with its node's world transform. */
static resurf_status draw_scene(sheet *s, rp_panel *panel, size_t k, int colour)
{
    const resurf_scene *scene = s->scene;
    for (size_t i = 0; i < s->list.count; ++i) {
        size_t prim_level, mesh = resurfi_scene_instance_mesh(&s->list.items[i], k, &prim_level);
        affine3 world = affine3_from(s->list.items[i].world);
        for (size_t p = scene->mesh_first[mesh]; p < scene->mesh_first[mesh + 1]; ++p) {
            const resurf_mesh *m = scene->prims[p].mesh ? resurfi_scene_level_mesh(&scene->prims[p], prim_level)
                                                        : NULL;
            if (!m)
                continue;
            rp_style style = style_of(s, p, colour);
            if (rp_draw_mesh(panel, &s->camera, m, &world, &style, s->alloc) != RESURF_OK)
                return resurfi_error(s->error, RESURF_ERR_OUT_OF_MEMORY, "out of memory drawing level %zu", k);
        }
    }
    return RESURF_OK;
}

/* Level k's cell: its picture, its heat picture, its labels. */
static resurf_status draw_level(sheet *s, size_t k, resurf_preview_report *rep)
{
    const layout *l = &s->l;
    unsigned cx = (unsigned)(k % l->cols) * l->cell_w, cy = (unsigned)(k / l->cols) * l->cell_h;
    if (l->panel_h > 0 && l->cell_w > 0) {
        rp_panel p = {s->img.rgba, s->img.width, cx, cy, l->cell_w, l->panel_h, s->depth, NULL, NULL};
        clear_panel(s, &p);
        resurf_status status = draw_scene(s, &p, k, 1);
        if (status != RESURF_OK)
            return status;
        if (s->o.heatmap) {
            rp_panel h = {s->img.rgba, s->img.width, cx, cy + l->panel_h, l->cell_w, l->panel_h, s->depth,
                          s->position, s->panel_shade};
            clear_panel(s, &h);
            if ((status = draw_scene(s, &h, k, 0)) != RESURF_OK)
                return status;
            heat_job job = {s->bvh, &h, s->distance, s->img.width};
            if (s->bvh)
                resurfi_parallel_for(h.h, 8, s->o.threads, heat_rows, &job);
            /* The lighting factors move into the sheet-sized array, beside the distances. */
            for (unsigned j = 0; j < h.h; ++j)
                for (unsigned i = 0; i < h.w; ++i) {
                    size_t at = (size_t)j * h.w + i;
                    size_t sheet_at = (size_t)(h.y0 + j) * s->img.width + h.x0 + i;
                    if (h.depth[at] > 0)
                        s->shade[sheet_at] = h.shade[at];
                }
        }
    }
    char line[LABEL_LINES][96], count[32];
    thousands(count, sizeof count, rep->level_triangles[k]);
    snprintf(line[0], sizeof line[0], "LEVEL %zu  %s TRIS", k, count);
    if (k == 0)
        snprintf(line[1], sizeof line[1], "FULL DETAIL");
    else if (!s->o.measure)
        line[1][0] = 0;
    else if (isnan(rep->level_error[k]))
        snprintf(line[1], sizeof line[1], "ERROR N/A");
    else
        snprintf(line[1], sizeof line[1], "ERROR %.3g%% = %.3g", 100 * rep->level_error_rel[k], rep->level_error[k]);
    /* Level k shows from its coverage up to the previous level's (MSFT_lod). */
    double from = rep->level_coverage[k], to = k > 0 ? rep->level_coverage[k - 1] : 1;
    if (from < 0)
        line[2][0] = 0;
    else if (k == 0 || to >= 1)
        snprintf(line[2], sizeof line[2], "COVERAGE >= %.3g%%", 100 * from);
    else if (from <= 0)
        snprintf(line[2], sizeof line[2], "COVERAGE < %.3g%%", 100 * to);
    else
        snprintf(line[2], sizeof line[2], "COVERAGE %.3g-%.3g%%", 100 * from, 100 * to);
    unsigned pictures = s->o.heatmap ? 2 : 1;
    unsigned y = cy + pictures * l->panel_h + l->scale;
    /* One size for the cell's lines: the layout's, or the smallest when one of them would not fit. */
    unsigned scale = l->scale;
    for (int i = 0; i < LABEL_LINES; ++i)
        if (rp_text_width(line[i], scale) + 4 > l->cell_w)
            scale = 1;
    for (int i = 0; i < LABEL_LINES; ++i, y += l->line_h)
        draw_line(&s->img, l, scale, cx, l->cell_w, y, line[i], s->ink);
    return RESURF_OK;
}

/* The heat pictures' colours (one scale for all levels) and the colour bar under the cells. */
static void draw_heat(sheet *s, double heat_max)
{
    size_t n = (size_t)s->img.width * s->img.height;
    const float *shade = s->shade;
    for (size_t at = 0; at < n; ++at) {
        if (isnan(s->distance[at]))
            continue;
        unsigned char c[3];
        rp_heat_colour(heat_max > 0 ? s->distance[at] / heat_max : 0, c);
        double f = 0.35 + 0.65 * shade[at];
        unsigned char *px = s->img.rgba + 4 * at;
        for (int k = 0; k < 3; ++k)
            px[k] = (unsigned char)(c[k] * f + 0.5);
        px[3] = 255;
    }
    const layout *l = &s->l;
    if (l->footer_h > s->img.height) /* a sheet too small for the bar keeps the coloured pictures alone */
        return;
    unsigned w = s->img.width, top = s->img.height - l->footer_h;
    unsigned x0 = w / 5, x1 = w - w / 5, bar_h = l->line_h;
    draw_line(&s->img, l, l->scale, 0, w, top + l->scale, "DISTANCE TO LEVEL 0 (SCENE UNITS)", s->ink);
    unsigned bar_y = top + l->line_h + 2 * l->scale;
    for (unsigned x = x0; x < x1; ++x) {
        unsigned char c[3];
        rp_heat_colour((double)(x - x0) / (double)(x1 - x0 - 1), c);
        for (unsigned y = bar_y; y < bar_y + bar_h && y < s->img.height; ++y) {
            unsigned char *px = s->img.rgba + 4 * ((size_t)y * w + x);
            memcpy(px, c, 3);
            px[3] = 255;
        }
    }
    char text[48];
    unsigned ty = bar_y + bar_h + l->scale;
    unsigned tick_w = (x1 - x0) / 2;
    for (int k = 0; k < 3; ++k) {
        snprintf(text, sizeof text, "%.3g", heat_max * k / 2);
        unsigned centre = x0 + (unsigned)k * tick_w;
        unsigned half = tick_w / 2;
        draw_line(&s->img, l, l->scale, centre > half ? centre - half : 0, tick_w, ty, text, s->ink);
    }
}

static resurf_status check_options(const resurf_preview_options *o, resurf_error *error)
{
    if (o->width < 16 || o->height < 16 || o->width > RESURF_PREVIEW_MAX_SIDE || o->height > RESURF_PREVIEW_MAX_SIDE ||
        (uint64_t)o->width * o->height > RESURF_PREVIEW_MAX_PIXELS)
        return resurfi_error(error, RESURF_ERR_LIMIT,
                             "a sheet of %u x %u pixels: each side must be in 16..%d and the whole at most %u pixels",
                             o->width, o->height, RESURF_PREVIEW_MAX_SIDE, RESURF_PREVIEW_MAX_PIXELS);
    if ((unsigned)o->view >= RESURF_PREVIEW_VIEW_COUNT)
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "unknown view %d", (int)o->view);
    if (!isfinite(o->yaw_deg) || !isfinite(o->pitch_deg))
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "yaw and pitch must be finite");
    if (o->compare_samples > 1000000000)
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "compare_samples %zu is above 10^9",
                             o->compare_samples);
    return RESURF_OK;
}

/* The levels of item: 1 + its MSFT_lod levels, or 1 + the most levels set on its primitives. */
static size_t item_levels(const resurf_scene *scene, const resurfi_scene_instance *item)
{
    if (item->lod_count)
        return 1 + item->lod_count;
    size_t most = 0;
    for (size_t p = scene->mesh_first[item->mesh]; p < scene->mesh_first[item->mesh + 1]; ++p)
        if (scene->prims[p].lod_count > most)
            most = scene->prims[p].lod_count;
    return 1 + most;
}

/* The coverage from which level k shows, from the first item with levels: its file's MSFT_screencoverage, or the
 * values set on its mesh, or the defaults resurf_scene_save writes; -1 when unknown. */
static double coverage_of(const resurf_scene *scene, const resurfi_scene_instances *list, size_t k, size_t levels)
{
    if (levels < 2)
        return -1;
    for (size_t i = 0; i < list->count; ++i) {
        const resurfi_scene_instance *item = &list->items[i];
        size_t n = item_levels(scene, item);
        if (n < 2)
            continue;
        if (item->lod_count)
            return k < item->coverage_count ? item->coverage[k] : -1;
        size_t m = item->mesh;
        if (scene->coverage && scene->coverage[m] && k < scene->coverage_count[m])
            return scene->coverage[m][k];
        return k + 1 >= n ? 0 : ldexp(1, -(int)(k + 1));
    }
    return -1;
}

static resurf_status render(sheet *s, resurf_preview_report *rep)
{
    const resurf_scene *scene = s->scene;
    resurf_status status = resurfi_scene_gather(scene, s->alloc, &s->list);
    if (status != RESURF_OK)
        return resurfi_error(s->error, status, "out of memory gathering the scene");
    size_t levels = 1;
    for (size_t i = 0; i < s->list.count; ++i) {
        size_t n = item_levels(scene, &s->list.items[i]);
        levels = n > levels ? n : levels;
    }
    rep->levels = levels;
    size_t images = scene->view ? scene->view->image_count : 0;
    if (images) {
        s->textures = resurfi_calloc(s->alloc, images, sizeof *s->textures);
        s->texture_state = resurfi_calloc(s->alloc, images, 1);
        if (!s->textures || !s->texture_state)
            return resurfi_error(s->error, RESURF_ERR_OUT_OF_MEMORY, "out of memory for the textures");
    }
    status = resurfi_scene_flatten(scene, &s->list, 0, NULL, s->alloc, &s->level0, s->error);
    if (status != RESURF_OK)
        return status;
    double lo[3], hi[3];
    rep->diagonal = resurf_mesh_bounds(s->level0, lo, hi);
    vec3 centre = v3_scale(v3_add(v3_load(lo), v3_load(hi)), 0.5);
    s->l = make_layout(s->o.width, s->o.height, levels, s->o.heatmap);
    static const double angles[RESURF_PREVIEW_VIEW_COUNT][2] = {{35, 20}, {0, 0}, {90, 0}, {0, 90}, {45, 35.26439}};
    s->camera = rp_camera_frame(centre, 0.5 * rep->diagonal, angles[s->o.view][0] + s->o.yaw_deg,
                                angles[s->o.view][1] + s->o.pitch_deg, s->l.cell_w, s->l.panel_h ? s->l.panel_h : 1);
    rp_camera_fit(&s->camera, centre, s->level0, s->l.cell_w, s->l.panel_h ? s->l.panel_h : 1);

    size_t pixels = (size_t)s->o.width * s->o.height, panel = (size_t)s->l.cell_w * s->l.panel_h;
    s->img.rgba = resurfi_alloc(s->alloc, pixels, 4);
    s->depth = resurfi_alloc(s->alloc, panel ? panel : 1, sizeof *s->depth);
    if (s->o.heatmap) {
        s->position = resurfi_alloc(s->alloc, panel ? panel : 1, 3 * sizeof *s->position);
        s->panel_shade = resurfi_alloc(s->alloc, panel ? panel : 1, sizeof *s->panel_shade);
        s->shade = resurfi_alloc(s->alloc, pixels, sizeof *s->shade);
        s->distance = resurfi_alloc(s->alloc, pixels, sizeof *s->distance);
    }
    if (!s->img.rgba || !s->depth || (s->o.heatmap && (!s->position || !s->panel_shade || !s->shade || !s->distance)))
        return resurfi_error(s->error, RESURF_ERR_OUT_OF_MEMORY, "out of memory for a %u x %u sheet", s->o.width,
                             s->o.height);
    s->img.width = s->o.width;
    s->img.height = s->o.height;
    for (size_t k = 0; k < pixels; ++k)
        memcpy(s->img.rgba + 4 * k, s->o.background, 4);
    const unsigned char *bg = s->o.background;
    int dark = 299 * bg[0] + 587 * bg[1] + 114 * bg[2] < 128000 && bg[3] >= 128;
    memset(s->ink, dark ? 230 : 25, 3);
    if (s->o.heatmap) {
        for (size_t k = 0; k < pixels; ++k)
            s->distance[k] = NAN;
        if (s->level0->triangle_count > 0) {
            status = resurfi_bvh_build_threads(s->alloc, s->level0->positions, s->level0->vertex_count,
                                               s->level0->indices, s->level0->triangle_count, s->o.threads, &s->bvh);
            if (status != RESURF_OK)
                return resurfi_error(s->error, status, "out of memory building level 0's search tree");
        }
    }

    resurf_compare_options co = resurf_compare_options_default();
    co.samples = s->o.compare_samples;
    co.threads = s->o.threads;
    co.allocator = s->alloc;
    for (size_t k = 0; k < levels; ++k) {
        if (resurfi_progress(&s->o.progress, RESURF_STAGE_PREVIEW, (double)k / (double)levels))
            return resurfi_error(s->error, RESURF_ERR_CANCELLED, "cancelled by the progress callback");
        resurf_mesh *mesh = s->level0;
        if (k > 0) {
            status = resurfi_scene_flatten(scene, &s->list, k, NULL, s->alloc, &mesh, s->error);
            if (status != RESURF_OK)
                return status;
        }
        rep->level_triangles[k] = mesh->triangle_count;
        rep->level_coverage[k] = coverage_of(scene, &s->list, k, levels);
        if (k > 0 && s->o.measure && mesh->triangle_count > 0 && s->level0->triangle_count > 0) {
            resurf_compare_report m;
            status = resurf_compare(s->level0, mesh, &co, &m, NULL, s->error);
            if (status == RESURF_ERR_OUT_OF_MEMORY || status == RESURF_ERR_CANCELLED) {
                resurf_mesh_free(mesh);
                return status;
            }
            rep->level_error[k] = status == RESURF_OK ? m.hausdorff : NAN;
            rep->level_error_rel[k] = status == RESURF_OK && m.diagonal > 0 ? m.hausdorff / m.diagonal : NAN;
        } else {
            rep->level_error[k] = k == 0 ? 0 : NAN;
            rep->level_error_rel[k] = k == 0 ? 0 : NAN;
        }
        status = draw_level(s, k, rep);
        if (mesh != s->level0)
            resurf_mesh_free(mesh);
        if (status != RESURF_OK)
            return status;
    }
    if (s->o.heatmap) {
        /* Distances within rounding of the scene's size are none (level 0 against itself). */
        double heat_max = 0, noise = 1e-12 * rep->diagonal;
        for (size_t k = 0; k < pixels; ++k) {
            if (s->distance[k] <= noise)
                s->distance[k] = s->distance[k] >= 0 ? 0 : s->distance[k];
            if (s->distance[k] > heat_max)
                heat_max = s->distance[k];
        }
        rep->heat_max = heat_max;
        draw_heat(s, heat_max);
    }
    (void)resurfi_progress(&s->o.progress, RESURF_STAGE_PREVIEW, 1.0);
    return RESURF_OK;
}

resurf_status resurf_preview_render(const resurf_scene *scene, const resurf_preview_options *options,
                                    resurf_preview_image *out_image, resurf_preview_report *out_report,
                                    resurf_error *error)
{
    if (out_image)
        memset(out_image, 0, sizeof *out_image);
    if (!scene || !out_image)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "scene or out_image is NULL");
    RESURFI_CHECK_OPTIONS_ALLOC(options, resurf_preview_options, error);
    sheet s = {.scene = scene, .o = options ? *options : resurf_preview_options_default(), .error = error};
    resurf_status status = check_options(&s.o, error);
    if (status != RESURF_OK)
        return status;
    s.alloc = s.o.allocator ? s.o.allocator : &scene->alloc;
    s.img.allocator = s.alloc->allocate ? *s.alloc : (resurf_allocator){0};
    resurf_preview_report rep;
    memset(&rep, 0, sizeof rep);
    s.rep = &rep;
    status = render(&s, &rep);
    for (size_t i = 0; s.textures && i < scene->view->image_count; ++i)
        rp_texture_free(&s.textures[i], s.alloc);
    resurfi_free(s.alloc, s.textures);
    resurfi_free(s.alloc, s.texture_state);
    resurfi_bvh_free(s.bvh);
    resurf_mesh_free(s.level0);
    resurfi_free(s.alloc, s.list.items);
    resurfi_free(s.alloc, s.depth);
    resurfi_free(s.alloc, s.position);
    resurfi_free(s.alloc, s.panel_shade);
    resurfi_free(s.alloc, s.shade);
    resurfi_free(s.alloc, s.distance);
    if (status != RESURF_OK) {
        resurfi_free(s.alloc, s.img.rgba);
        return status;
    }
    *out_image = s.img;
    if (out_report)
        *out_report = rep;
    resurfi_clear_error(error);
    return RESURF_OK;
}

resurf_status resurf_preview_save_png(const resurf_preview_image *image, const char *path, resurf_error *error)
{
    if (!image || !image->rgba || !path || !*path)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "image, its pixels or path is NULL or empty");
    if (image->width == 0 || image->height == 0 || image->width > RESURF_PREVIEW_MAX_SIDE ||
        image->height > RESURF_PREVIEW_MAX_SIDE || (uint64_t)image->width * image->height > RESURF_PREVIEW_MAX_PIXELS)
        return resurfi_error(error, RESURF_ERR_LIMIT, "an image of %u x %u pixels", image->width, image->height);
    unsigned char *data = NULL;
    size_t size = 0;
    resurf_status status = rp_png_encode(image->rgba, image->width, image->height, &image->allocator, &data, &size,
                                         error);
    if (status != RESURF_OK)
        return status;
    status = resurfi_save_file(&image->allocator, path, data, size, error);
    resurfi_free(&image->allocator, data);
    if (status == RESURF_OK)
        resurfi_clear_error(error);
    return status;
}
