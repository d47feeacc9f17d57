/* Extensions of the source document: which ones resurf knows, which ones force the output to keep all of the
 * source's accessors and bufferViews, and which ones a rewritten triangle primitive keeps.
 *
 * A triangle primitive is always written anew (new vertex order, new triangles, at every level). An extension on
 * it that describes its triangulation or vertex order (FB_ngon_encoding: the order of triangles encodes the
 * source's n-gons) would be wrong on the new primitive, and an unknown one may be; both are dropped, and so its
 * references cannot keep dead data alive. Known-safe ones stay (KHR_materials_variants maps materials, whatever the
 * triangles). */
#include <stdio.h>
#include <string.h>

#include "scene_internal.h"

int resurfi_scene_extension_known(const char *name)
{
    static const char *const exact[] = {
        "KHR_draco_mesh_compression", "KHR_mesh_quantization", "KHR_lights_punctual", "KHR_materials_variants",
        "KHR_xmp", "KHR_xmp_json_ld", "KHR_animation_pointer", "KHR_node_visibility", "MSFT_lod",
        "EXT_lights_image_based", "EXT_mesh_gpu_instancing",
    };
    static const char *const prefixes[] = {"KHR_materials_", "KHR_texture_", "EXT_texture_", "MSFT_texture_",
                                           "MSFT_packing_"};
    for (size_t i = 0; i < sizeof exact / sizeof *exact; ++i)
        if (!strcmp(name, exact[i]))
            return 1;
    for (size_t i = 0; i < sizeof prefixes / sizeof *prefixes; ++i)
        if (!strncmp(name, prefixes[i], strlen(prefixes[i])))
            return 1;
    return 0;
}

const char *const resurfi_kept_primitive_extensions[] = {"KHR_materials_variants"};
const size_t resurfi_kept_primitive_extension_count =
    sizeof resurfi_kept_primitive_extensions / sizeof *resurfi_kept_primitive_extensions;

static int kept_on_primitives(const char *name)
{
    for (size_t i = 0; i < resurfi_kept_primitive_extension_count; ++i)
        if (!strcmp(name, resurfi_kept_primitive_extensions[i]))
            return 1;
    return 0;
}

int resurfi_scene_unknown_references(const resurf_scene *s)
{
    const resurfi_gltf_view *v = s->view;
    if (!v)
        return 0;
    for (size_t i = 0; i < v->outside_extension_count; ++i)
        if (!resurfi_scene_extension_known(v->outside_extensions[i]))
            return 1;
    for (size_t i = 0; i < s->prim_count; ++i) {
        const resurfi_scene_prim *p = &s->prims[i];
        if (resurfi_scene_rewritten(p))
            continue; /* rewritten: its unknown extensions are dropped */
        const resurfi_gltf_primitive *g = &v->meshes[p->info.mesh].primitives[p->info.primitive];
        for (size_t e = 0; e < g->extension_count; ++e)
            if (!resurfi_scene_extension_known(g->extensions[e]))
                return 1;
    }
    return 0;
}

/* Primitive extension e of triangle primitive i when it is dropped, else NULL. */
static const char *dropped(const resurf_scene *s, size_t i, size_t e)
{
    const resurfi_scene_prim *p = &s->prims[i];
    if (!s->view || !resurfi_scene_rewritten(p))
        return NULL;
    const resurfi_gltf_primitive *g = &s->view->meshes[p->info.mesh].primitives[p->info.primitive];
    return e < g->extension_count && !kept_on_primitives(g->extensions[e]) ? g->extensions[e] : NULL;
}

static size_t extension_count(const resurf_scene *s, size_t i)
{
    const resurfi_scene_prim *p = &s->prims[i];
    return s->view ? s->view->meshes[p->info.mesh].primitives[p->info.primitive].extension_count : 0;
}

size_t resurfi_scene_dropped_extensions(const resurf_scene *s)
{
    size_t n = 0;
    for (size_t i = 0; i < s->prim_count; ++i)
        for (size_t e = 0; e < extension_count(s, i); ++e)
            n += dropped(s, i, e) != NULL;
    return n;
}

typedef struct dropped_name {
    const char *name;
    size_t count, first; /* primitives carrying it, the first of them */
} dropped_name;

resurf_status resurfi_scene_warn_dropped_extensions(resurf_scene *s)
{
    enum { MAX_NAMES = 32 }; /* distinct names warned about; more are counted under the last warning */
    dropped_name seen[MAX_NAMES];
    size_t names = 0, others = 0;
    for (size_t i = 0; i < s->prim_count; ++i)
        for (size_t e = 0; e < extension_count(s, i); ++e) {
            const char *name = dropped(s, i, e);
            if (!name)
                continue;
            size_t k = 0;
            while (k < names && strcmp(seen[k].name, name))
                ++k;
            if (k == names && names == MAX_NAMES) {
                ++others;
                continue;
            }
            if (k == names)
                seen[names++] = (dropped_name){name, 0, i};
            seen[k].count++;
        }
    for (size_t k = 0; k < names; ++k) {
        char text[500];
        snprintf(text, sizeof text,
                 "%.200s is dropped from the %zu triangle primitive%s that carry it (the first: %s): it may describe "
                 "the source's triangles or vertex order, which the written primitives do not keep%s",
                 seen[k].name, seen[k].count, seen[k].count == 1 ? "" : "s", s->prims[seen[k].first].info.name,
                 k + 1 == names && others ? " (and more extensions are)" : "");
        for (char *m = text; *m; ++m)
            if ((unsigned char)*m < 0x20 || *m == 0x7f)
                *m = '?';
        if (resurfi_scene_add_warning(s, text) != RESURF_OK)
            return RESURF_ERR_OUT_OF_MEMORY;
    }
    return RESURF_OK;
}
