/* Saving scenes: each triangle primitive at each level packed into glTF accessors or a Draco payload checked by
 * decoding it again (scene_pack.c), then the output document planned (layouts of levels: MSFT_lod, one file per
 * level, side by side) for io/gltf_write.cpp, and the files written atomically (temporary files renamed into place
 * only when all of them are complete).
 *
 * Follows glTF 2.0 (3.6-3.7: accessor types, min/max of POSITION, unit normals and tangents), KHR_draco_mesh_
 * compression (accessors of a compressed primitive describe the decoded data and have no bufferView) and the
 * Microsoft MSFT_lod extension. Draco quantization: a float attribute of range R stored in b bits is within
 * R / (2^b - 1) of its input after decoding; that bound is what the decode check enforces for positions. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "file.h"
#include "scene_save_internal.h"

resurf_scene_save_options resurf_scene_save_options_default(void)
{
    resurf_scene_save_options o;
    memset(&o, 0, sizeof o);
    o.struct_size = sizeof o;
    o.draco = 0;
    o.position_bits = 14;
    o.normal_bits = 10;
    o.texcoord_bits = 12;
    o.color_bits = 8;
    o.generic_bits = 12;
    o.compression_level = 7;
    o.threads = 0;
    o.embed_buffers = 0;
    o.layout = RESURF_LOD_MSFT_LOD;
    o.spacing_rel = 0.25;
    o.level = -1;
    return o;
}

size_t resurf_scene_level_path(char *dst, size_t dst_size, const char *path, unsigned level)
{
    char empty = 0;
    if (!dst || dst_size == 0) {
        dst = &empty;
        dst_size = 1;
    }
    if (!path)
        path = "";
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    size_t stem = dot && dot != base ? (size_t)(dot - path) : strlen(path);
    int n = snprintf(dst, dst_size, "%.*s_lod%u%s", (int)stem, path, level, path + stem);
    return n < 0 ? 0 : (size_t)n;
}

/* ---- the save context ------------------------------------------------------------------------------------- */

resurf_status save_oom(save_ctx *c)
{
    return resurfi_fail(c->error, RESURF_ERR_OUT_OF_MEMORY, c->path, 0, -1, "out of memory writing the scene");
}

/* Remembers p (a block of allocator a) for freeing at the end; NULL stays NULL (and frees p when the list cannot
 * grow). */
void *save_own_from(save_ctx *c, void *p, const resurf_allocator *a)
{
    if (!p)
        return NULL;
    if (c->owned_count == c->owned_cap) {
        size_t cap = c->owned_cap ? 2 * c->owned_cap : 64;
        owned_block *list = resurfi_realloc(c->alloc, c->owned, cap, sizeof *list);
        if (!list) {
            resurfi_free(a, p);
            return NULL;
        }
        c->owned = list;
        c->owned_cap = cap;
    }
    c->owned[c->owned_count++] = (owned_block){p, a};
    return p;
}

/* The same for a block of the call's allocator. */
void *save_own(save_ctx *c, void *p) { return save_own_from(c, p, c->alloc); }

static void free_owned(save_ctx *c)
{
    for (size_t i = 0; i < c->owned_count; ++i)
        resurfi_free(c->owned[i].alloc, c->owned[i].block);
    resurfi_free(c->alloc, c->owned);
    resurfi_free(c->alloc, c->acc);
    resurfi_free(c->alloc, c->cache);
    resurfi_free(c->alloc, c->jobs);
    resurfi_free(c->alloc, c->job_of);
}

char *save_own_string(save_ctx *c, const char *s)
{
    return save_own(c, resurfi_strdup(c->alloc, s));
}

long long save_add_accessor(save_ctx *c, const resurfi_gltf_out_accessor *a)
{
    if (c->acc_count == c->acc_cap) {
        size_t cap = c->acc_cap ? 2 * c->acc_cap : 64;
        resurfi_gltf_out_accessor *list = resurfi_realloc(c->alloc, c->acc, cap, sizeof *list);
        if (!list)
            return -1;
        c->acc = list;
        c->acc_cap = cap;
    }
    c->acc[c->acc_count] = *a;
    return (long long)c->acc_count++;
}

/* ---- planning a document ------------------------------------------------------------------------------------- */

/* The number of levels of mesh m: 1 + the most levels of its primitives. */
static size_t mesh_levels(const resurf_scene *s, size_t m)
{
    size_t levels = 1;
    for (size_t i = s->mesh_first[m]; i < s->mesh_first[m + 1]; ++i)
        if (s->prims[i].lod_count + 1 > levels)
            levels = s->prims[i].lod_count + 1;
    return levels;
}

/* Output mesh (mesh m at level k): its primitives, packed or verbatim. */
static resurf_status plan_mesh(save_ctx *c, size_t m, size_t level, resurfi_gltf_out_mesh *out)
{
    const resurf_scene *s = c->s;
    size_t first = s->mesh_first[m], count = s->mesh_first[m + 1] - first;
    resurfi_gltf_out_primitive *prims = save_own(c, resurfi_calloc(c->alloc, count, sizeof *prims));
    if (!prims)
        return save_oom(c);
    size_t n = 0;
    for (size_t i = 0; i < count; ++i) {
        const resurfi_scene_prim *p = &s->prims[first + i];
        resurfi_gltf_out_primitive *o = &prims[n];
        o->source_mesh = s->doc ? m : SIZE_MAX;
        o->source_primitive = p->info.primitive;
        o->indices = -1;
        if (!resurfi_scene_rewritten(p)) {
            /* Points and lines are written from the source document as they are. */
            o->verbatim = 1;
            c->verbatim_any = 1;
            c->draco_used |= p->info.draco;
            ++n;
            continue;
        }
        packed *pk;
        resurf_status status = save_pack(c, first + i, level, &pk);
        if (status != RESURF_OK)
            return status;
        if (resurfi_progress(&c->o->progress, RESURF_STAGE_SAVE, 0.5))
            return resurfi_fail(c->error, RESURF_ERR_CANCELLED, c->path, 0, -1, "cancelled by the progress callback");
        if (pk->empty)
            continue;
        o->attribute_count = pk->attribute_count;
        o->attributes = pk->attributes;
        o->indices = pk->indices;
        o->draco = pk->draco;
        o->draco_size = pk->draco_size;
        o->draco_ids = pk->draco_ids;
        o->target_count = pk->target_count;
        o->target_begin = pk->target_begin;
        o->target_attributes = pk->target_attributes;
        c->draco_used |= pk->draco != NULL;
        c->quantized_any |= pk->quantized;
        ++n;
    }
    if (n == 0)
        return resurfi_fail(c->error, RESURF_ERR_INVALID_MESH, c->path, 0, -1,
                            "meshes[%zu] has no triangles left at level %zu", m, level);
    out->source_mesh = m;
    out->level = (unsigned)level;
    out->primitive_count = n;
    out->primitives = prims;
    return RESURF_OK;
}

/* x extent of the scene (world space, level 0), for spacing the side-by-side copies. */
static double scene_width(const resurf_scene *s)
{
    double lo = INFINITY, hi = -INFINITY, extent = 0;
    for (size_t node = 0; node < (s->doc ? s->view->node_count : 1); ++node) {
        long long mesh = s->doc ? s->view->nodes[node].mesh : 0;
        if (mesh < 0)
            continue;
        static const double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        for (size_t j = 0; j < (s->doc ? resurfi_scene_node_instances(s, node) : 1); ++j) {
            const double *w = s->doc ? resurfi_scene_instance_world(s, node, j) : identity;
            for (size_t i = s->mesh_first[mesh]; i < s->mesh_first[mesh + 1]; ++i) {
                const resurf_mesh *m = s->prims[i].mesh;
                if (!m || m->vertex_count == 0)
                    continue;
                double bmin[3], bmax[3];
                extent = fmax(extent, resurf_mesh_bounds(m, bmin, bmax));
                for (int corner = 0; corner < 8; ++corner) {
                    double p[3] = {corner & 1 ? bmax[0] : bmin[0], corner & 2 ? bmax[1] : bmin[1],
                                   corner & 4 ? bmax[2] : bmin[2]};
                    double x = w[0] * p[0] + w[4] * p[1] + w[8] * p[2] + w[12];
                    lo = fmin(lo, x), hi = fmax(hi, x);
                }
            }
        }
    }
    double width = hi - lo;
    return width > 0 && isfinite(width) ? width : extent > 0 ? extent : 1.0;
}

/* Builds the plan of one document: `level` >= 0 writes that level alone (PLAIN), else all levels in `layout`. */
static resurf_status build_plan(save_ctx *c, int level, resurfi_gltf_layout layout, resurfi_gltf_plan *plan)
{
    const resurf_scene *s = c->s;
    size_t meshes = s->mesh_count;
    size_t levels = 1;
    for (size_t m = 0; m < meshes; ++m)
        if (mesh_levels(s, m) > levels)
            levels = mesh_levels(s, m);
    if (level >= 0 || layout == RESURFI_GLTF_PLAIN)
        levels = 1;
    memset(plan, 0, sizeof *plan);
    plan->layout = levels > 1 ? layout : RESURFI_GLTF_PLAIN;
    plan->source_mesh_count = meshes;
    plan->level_count = levels;
    long long *table = save_own(c, resurfi_alloc(c->alloc, levels * meshes + 1, sizeof *table));
    resurfi_gltf_out_mesh *out = save_own(c, resurfi_calloc(c->alloc, levels * meshes + 1, sizeof *out));
    double *coverage = save_own(c, resurfi_calloc(c->alloc, levels * meshes + 1, sizeof *coverage));
    if (!table || !out || !coverage)
        return save_oom(c);
    size_t n = 0;
    for (size_t k = 0; k < levels; ++k)
        for (size_t m = 0; m < meshes; ++m) {
            size_t own_levels = mesh_levels(s, m);
            table[k * meshes + m] = RESURFI_GLTF_NONE;
            if (k == 0 || k < own_levels) {
                resurf_status status = plan_mesh(c, m, level >= 0 ? (size_t)level : k, &out[n]);
                if (status != RESURF_OK)
                    return status;
                table[k * meshes + m] = (long long)n++;
            } else if (layout == RESURFI_GLTF_SIDE_BY_SIDE) {
                table[k * meshes + m] = table[(own_levels - 1) * meshes + m]; /* shown at its last level */
            }
        }
    for (size_t m = 0; m < meshes && plan->layout == RESURFI_GLTF_MSFT_LOD; ++m) {
        size_t own_levels = mesh_levels(s, m);
        if (own_levels < 2)
            continue;
        if (s->coverage[m] && s->coverage_count[m] != own_levels)
            return resurfi_fail(c->error, RESURF_ERR_INVALID_ARGUMENT, c->path, 0, -1,
                                "meshes[%zu] has %zu levels but %zu screen coverage values", m, own_levels,
                                s->coverage_count[m]);
        for (size_t k = 0; k < own_levels; ++k)
            coverage[m * levels + k] = s->coverage[m] ? s->coverage[m][k]
                                       : k + 1 < own_levels ? ldexp(1.0, -(int)(k + 1))
                                                            : 0.0;
    }
    if (s->doc) {
        unsigned char *restructure = save_own(c, resurfi_calloc(c->alloc, s->view->node_count + 1, 1));
        if (!restructure)
            return save_oom(c);
        /* A node whose transform is animated, or whose children a viewer would hide with it when it swaps in a
         * level, moves its mesh into a child of its own, which carries MSFT_lod. A skinned mesh stays on its node
         * (a skinned child would not be a root) and its level nodes stand beside it. */
        for (size_t i = 0; i < s->view->node_count; ++i) {
            const resurfi_gltf_node *node = &s->view->nodes[i];
            restructure[i] = (node->animated || node->child_count > 0) && node->skin < 0;
        }
        plan->restructure = restructure;
    }
    if (plan->layout == RESURFI_GLTF_SIDE_BY_SIDE)
        plan->level_offset[0] = scene_width(s) * (1.0 + c->o->spacing_rel);
    plan->mesh_count = n;
    plan->meshes = out;
    plan->level_mesh = table;
    plan->coverage = coverage;
    plan->accessor_count = c->acc_count;
    plan->accessors = c->acc;
    plan->keep_all_source_data = s->unknown_extensions;
    plan->kept_extension_count = resurfi_kept_primitive_extension_count;
    plan->kept_extensions = resurfi_kept_primitive_extensions;
    plan->draco_used = c->draco_used;
    plan->quantization_used = s->quantized && (c->verbatim_any || c->quantized_any);
    plan->synthesize_graph = s->doc == NULL;
    plan->generator = "resurf " RESURF_VERSION_STRING;
    return RESURF_OK;
}

/* ---- files --------------------------------------------------------------------------------------------------- */

typedef struct pending {
    char *path, *tmp;
} pending;

typedef struct pending_list {
    pending *items;
    size_t count, cap;
} pending_list;

/* Writes data to a new temporary file beside path (resurfi_temp_create) and records it. */
static resurf_status write_temp(save_ctx *c, pending_list *list, const char *path, const void *data, size_t size)
{
    if (list->count == list->cap) {
        size_t cap = list->cap ? 2 * list->cap : 2 * RESURF_SCENE_MAX_LEVELS;
        pending *items = resurfi_realloc(c->alloc, list->items, cap, sizeof *items);
        if (!items)
            return save_oom(c);
        list->items = items;
        list->cap = cap;
    }
    char *copy = resurfi_strdup(c->alloc, path), *tmp = NULL;
    int fd = -1;
    if (!copy)
        return save_oom(c);
    resurf_status status = resurfi_temp_create(c->alloc, path, &tmp, &fd, c->error);
    if (status != RESURF_OK) {
        resurfi_free(c->alloc, copy);
        return status;
    }
    int err = resurfi_write_all(fd, data, size);
    if (close(fd) != 0 && !err)
        err = errno ? errno : EIO;
    if (err) {
        resurfi_temp_discard(c->alloc, tmp);
        resurfi_free(c->alloc, copy);
        return resurfi_fail(c->error, RESURF_ERR_IO, path, 0, -1, "cannot write: %s", strerror(err));
    }
    list->items[list->count].path = copy;
    list->items[list->count].tmp = tmp;
    list->count++;
    return RESURF_OK;
}

/* Renames every temporary file into place, or (commit 0, or a failed rename) removes those not yet renamed.
 * Last written first: a .bin goes into place before the .gltf that names it. */
static resurf_status finish_files(save_ctx *c, pending_list *list, int commit)
{
    resurf_status status = RESURF_OK;
    for (size_t i = list->count; i-- > 0;) {
        if (commit && status == RESURF_OK)
            status = resurfi_temp_commit(c->alloc, list->items[i].tmp, list->items[i].path, c->error);
        else
            resurfi_temp_discard(c->alloc, list->items[i].tmp);
        resurfi_free(c->alloc, list->items[i].path);
    }
    list->count = 0;
    return status;
}

/* Has the call written (to a temporary file) `path` already? */
static int pending_has(const pending_list *list, const char *path)
{
    for (size_t i = 0; i < list->count; ++i)
        if (!strcmp(list->items[i].path, path))
            return 1;
    return 0;
}

/* The images of a document at path (embedded, else copied beside it: each copy is written once per call). */
static resurf_status plan_images(save_ctx *c, pending_list *files, const char *path, const char *bin_path,
                                 int embed, resurfi_gltf_plan *plan, resurf_scene_save_report *report)
{
    const resurf_scene *s = c->s;
    if (!s->doc || s->image_count == 0)
        return RESURF_OK;
    resurfi_gltf_out_image *images = save_own(c, resurfi_calloc(c->alloc, s->image_count, sizeof *images));
    if (!images)
        return save_oom(c);
    for (size_t i = 0; i < s->image_count; ++i) {
        char *copy_to = NULL;
        resurf_status status = resurfi_scene_out_image(s, i, path, embed, &images[i], &copy_to, c->error);
        if (status == RESURF_OK && copy_to && (!strcmp(copy_to, path) || !strcmp(copy_to, bin_path)))
            status = resurfi_fail(c->error, RESURF_ERR_UNSUPPORTED, path, 0, -1,
                                  "images[%zu]: its copy would replace the output itself (%s): choose another "
                                  "name or embed the images", i, copy_to);
        if (status == RESURF_OK && copy_to && !pending_has(files, copy_to)) {
            status = resurfi_make_parent_folders(copy_to, c->error);
            if (status == RESURF_OK)
                status = write_temp(c, files, copy_to, s->images[i].data, s->images[i].size);
            if (status == RESURF_OK) {
                report->files++;
                report->total_bytes += s->images[i].size;
            }
        }
        resurfi_free(&s->alloc, copy_to);
        if (status != RESURF_OK)
            return status;
    }
    plan->images = images;
    return RESURF_OK;
}

/* The name of a .gltf's .bin, as a URI (percent-encoded) and as a path beside the .gltf. */
static void bin_names(const char *gltf_path, char *uri, size_t uri_size, char *path, size_t path_size)
{
    const char *slash = strrchr(gltf_path, '/');
    const char *base = slash ? slash + 1 : gltf_path;
    const char *dot = strrchr(base, '.');
    size_t stem = dot && dot != base ? (size_t)(dot - base) : strlen(base);
    snprintf(path, path_size, "%.*s%.*s.bin", (int)(base - gltf_path), gltf_path, (int)stem, base);
    size_t n = 0;
    static const char hex[] = "0123456789ABCDEF";
    for (size_t i = 0; i < stem && n + 4 < uri_size; ++i) {
        unsigned char ch = (unsigned char)base[i];
        if ((ch >= 'A' && ch <= 'Z') || (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || strchr("-._~", ch))
            uri[n++] = (char)ch;
        else
            uri[n++] = '%', uri[n++] = hex[ch >> 4], uri[n++] = hex[ch & 15];
    }
    snprintf(uri + n, uri_size - n, ".bin");
}

typedef enum out_format { OUT_GLTF, OUT_GLB, OUT_DRC } out_format;

/* Plans, serialises and writes (to temporary files) one glTF document. */
static resurf_status write_document(save_ctx *c, pending_list *files, const char *path, out_format format, int level,
                                    resurfi_gltf_layout layout, resurf_scene_save_report *report)
{
    c->acc_count = 0;
    c->draco_used = c->verbatim_any = c->quantized_any = 0;
    memset(c->cache, 0, c->s->prim_count * RESURF_SCENE_MAX_LEVELS * sizeof *c->cache);
    resurfi_gltf_plan plan;
    resurf_status status = build_plan(c, level, layout, &plan);
    if (status != RESURF_OK)
        return status;
    char uri[1024], bin_path[4096];
    bin_names(path, uri, sizeof uri, bin_path, sizeof bin_path);
    plan.container = format == OUT_GLB ? RESURFI_GLTF_GLB : c->o->embed_buffers ? RESURFI_GLTF_EMBEDDED
                                                                                : RESURFI_GLTF_SEPARATE;
    plan.bin_uri = uri;
    status = plan_images(c, files, path, bin_path, format == OUT_GLB || c->o->embed_buffers, &plan, report);
    if (status != RESURF_OK)
        return status;
    unsigned char *json = NULL, *bin = NULL;
    size_t json_size = 0, bin_size = 0;
    resurf_error werr;
    status = resurfi_gltf_write(c->s->doc, &plan, &json, &json_size, &bin, &bin_size, &werr);
    if (status != RESURF_OK)
        return resurfi_fail(c->error, status, path, 0, -1, "%s", werr.message);
    status = write_temp(c, files, path, json, json_size);
    if (status == RESURF_OK && bin)
        status = write_temp(c, files, bin_path, bin, bin_size);
    if (status == RESURF_OK) {
        report->files += 1 + (bin != NULL);
        report->total_bytes += json_size + bin_size;
        /* Geometry bytes per level: each primitive's packed data at each level it appears in. */
        for (size_t k = 0; k < plan.level_count; ++k)
            for (size_t i = 0; i < c->s->prim_count; ++i) {
                const resurfi_scene_prim *p = &c->s->prims[i];
                size_t lv = level >= 0 ? (size_t)level : k;
                size_t own_levels = mesh_levels(c->s, p->info.mesh);
                if (level < 0 && k >= own_levels)
                    continue;
                const packed *pk = &c->cache[i * RESURF_SCENE_MAX_LEVELS + save_effective_level(p, lv)];
                if (pk->done && !pk->empty)
                    report->level_bytes[lv] += pk->bytes;
            }
    }
    resurfi_free(NULL, json); /* malloc'ed by the glTF shim: the C heap */
    resurfi_free(NULL, bin);
    return status;
}

/* A .drc: the one triangle primitive at `level`. */
static resurf_status write_drc(save_ctx *c, pending_list *files, const char *path, size_t level,
                               resurf_scene_save_report *report)
{
    const resurf_scene *s = c->s;
    size_t prim = SIZE_MAX, with_mesh = 0;
    for (size_t i = 0; i < s->prim_count; ++i)
        if (s->prims[i].mesh) {
            prim = i;
            ++with_mesh;
        }
    if (with_mesh != 1 || s->prim_count != 1)
        return resurfi_fail(c->error, RESURF_ERR_UNSUPPORTED, path, 0, -1,
                            "a .drc file holds one triangle mesh; the scene has %zu primitives", s->prim_count);
    memset(c->cache, 0, s->prim_count * RESURF_SCENE_MAX_LEVELS * sizeof *c->cache);
    packed *pk;
    resurf_status status = save_pack(c, prim, level, &pk);
    if (status != RESURF_OK)
        return status;
    if (pk->empty)
        return resurfi_fail(c->error, RESURF_ERR_INVALID_MESH, path, 0, -1, "level %zu has no triangles", level);
    status = write_temp(c, files, path, pk->draco, pk->draco_size);
    if (status == RESURF_OK) {
        report->files++;
        report->total_bytes += pk->draco_size;
        report->level_bytes[level] += pk->draco_size;
    }
    return status;
}

resurf_status resurf_scene_save(const resurf_scene *scene, const char *path, const resurf_scene_save_options *options,
                                resurf_scene_save_report *out_report, resurf_error *error)
{
    if (!scene || !path || !*path)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "scene or path is NULL or empty");
    RESURFI_CHECK_OPTIONS_ALLOC(options, resurf_scene_save_options, error);
    resurf_scene_save_options o = options ? *options : resurf_scene_save_options_default();
    int bits[5] = {o.position_bits, o.normal_bits, o.texcoord_bits, o.color_bits, o.generic_bits};
    for (int i = 0; i < 5; ++i)
        if (bits[i] < 1 || bits[i] > 30)
            return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "quantization bits must be in 1..30 (got %d)",
                                 bits[i]);
    if (o.compression_level < 0 || o.compression_level > 10)
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "compression_level must be in 0..10");
    if ((unsigned)o.layout >= RESURF_LOD_LAYOUT_COUNT)
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "unknown layout %d", (int)o.layout);
    if (!(o.spacing_rel >= 0) || !isfinite(o.spacing_rel))
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "spacing_rel must be finite and >= 0");
    out_format format;
    if (resurfi_ends_with_nocase(path, ".gltf"))
        format = OUT_GLTF;
    else if (resurfi_ends_with_nocase(path, ".glb"))
        format = OUT_GLB;
    else if (resurfi_ends_with_nocase(path, ".drc"))
        format = OUT_DRC, o.draco = 1;
    else
        return resurfi_fail(error, RESURF_ERR_UNSUPPORTED, path, 0, -1,
                            "cannot tell the format from the name (use .gltf, .glb or .drc)");
    size_t levels = 1;
    for (size_t i = 0; i < scene->prim_count; ++i)
        if (scene->prims[i].lod_count + 1 > levels)
            levels = scene->prims[i].lod_count + 1;
    if (o.level < -1 || o.level >= (int)levels)
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "level %d: the scene has levels 0..%zu", o.level,
                             levels - 1);
    int per_file = o.level < 0 && o.layout == RESURF_LOD_FILES; /* even one level: the names stay */
    if (format == OUT_DRC && o.level < 0 && levels > 1 && !per_file)
        return resurfi_fail(error, RESURF_ERR_UNSUPPORTED, path, 0, -1,
                            "a .drc file holds one level: choose one or use the files layout");

    save_ctx c = {.s = scene, .o = &o, .alloc = o.allocator ? o.allocator : &scene->alloc, .path = path,
                  .error = error};
    c.cache = resurfi_calloc(c.alloc, scene->prim_count * RESURF_SCENE_MAX_LEVELS + 1, sizeof *c.cache);
    if (!c.cache)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    resurf_status status = save_encode_ahead(&c);
    resurf_scene_save_report report;
    memset(&report, 0, sizeof report);
    report.levels = levels;
    pending_list *files = resurfi_calloc(c.alloc, 1, sizeof *files);
    if (status == RESURF_OK && !files)
        status = save_oom(&c);
    resurfi_gltf_layout layout = o.layout == RESURF_LOD_SIDE_BY_SIDE ? RESURFI_GLTF_SIDE_BY_SIDE
                                                                     : RESURFI_GLTF_MSFT_LOD;
    for (size_t k = 0; k < (per_file ? levels : 1) && status == RESURF_OK; ++k) {
        size_t name_size = resurf_scene_level_path(NULL, 0, path, (unsigned)k) + 1;
        char *name = resurfi_alloc(c.alloc, name_size, 1);
        if (!name) {
            status = save_oom(&c);
            break;
        }
        if (per_file)
            resurf_scene_level_path(name, name_size, path, (unsigned)k);
        else
            snprintf(name, name_size, "%s", path);
        int level = per_file ? (int)k : o.level;
        if (format == OUT_DRC)
            status = write_drc(&c, files, name, level < 0 ? 0 : (size_t)level, &report);
        else
            status = write_document(&c, files, name, format, level, layout, &report);
        resurfi_free(c.alloc, name);
    }
    /* Triangles per level, each mesh once. */
    for (size_t k = 0; k < levels; ++k)
        for (size_t i = 0; i < scene->prim_count; ++i)
            if (scene->prims[i].mesh)
                report.level_triangles[k] += resurfi_scene_level_mesh(&scene->prims[i], k)->triangle_count;
    if (files) {
        status = finish_files(&c, files, status == RESURF_OK) == RESURF_OK ? status : RESURF_ERR_IO;
        resurfi_free(c.alloc, files->items);
    }
    resurfi_free(c.alloc, files);
    report.dropped_extensions = resurfi_scene_dropped_extensions(scene);
    free_owned(&c);
    if (status == RESURF_OK) {
        (void)resurfi_progress(&o.progress, RESURF_STAGE_SAVE, 1.0);
        if (out_report)
            *out_report = report;
        resurfi_clear_error(error);
    }
    return status;
}
