/* resurf_scene_describe(): what `resurf info` prints about a scene. The C side hands over what only it knows
 * (each primitive's decoded triangles and vertices, each external image's bytes); io/gltf_describe.cpp renders
 * the document. */
#include <stdio.h>
#include <string.h>

#include "scene_internal.h"

resurf_status resurf_scene_describe(const resurf_scene *scene, bool as_json, char *dst, size_t dst_size,
                                    size_t *out_length, resurf_error *error)
{
    if (!scene || !out_length || (!dst && dst_size))
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "scene or out_length is NULL");
    const resurf_allocator *a = &scene->alloc;
    resurfi_describe_prim *prims = resurfi_calloc(a, scene->prim_count + 1, sizeof *prims);
    resurfi_describe_image *images = resurfi_calloc(a, scene->image_count + 1, sizeof *images);
    const char *names[4 + RESURF_MAX_TEXCOORD_SETS + 64];
    static const char *const texcoords[] = {"TEXCOORD_0", "TEXCOORD_1", "TEXCOORD_2", "TEXCOORD_3",
                                            "TEXCOORD_4", "TEXCOORD_5", "TEXCOORD_6", "TEXCOORD_7"};
    if (!prims || !images) {
        resurfi_free(a, prims);
        resurfi_free(a, images);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory describing the scene");
    }
    for (size_t i = 0; i < scene->prim_count; ++i) {
        const resurf_mesh *m = scene->prims[i].mesh;
        prims[i].has_mesh = m != NULL;
        prims[i].triangles = m ? m->triangle_count : 0;
        prims[i].vertices = m ? m->vertex_count : 0;
        if (scene->doc || !m)
            continue;
        /* A .drc or a mesh file: the attribute names that saving would write. */
        size_t n = 0;
        names[n++] = "POSITION";
        if (m->normals)
            names[n++] = "NORMAL";
        for (unsigned k = 0; k < m->texcoord_count && k < sizeof texcoords / sizeof *texcoords; ++k)
            if (m->texcoords[k])
                names[n++] = texcoords[k];
        if (m->colors)
            names[n++] = "COLOR_0";
        for (size_t k = 0; k < m->extra_count && k < 64; ++k)
            names[n++] = m->extras[k].name;
        prims[i].attribute_count = n;
        prims[i].attributes = names;
    }
    for (size_t i = 0; i < scene->image_count; ++i) {
        const resurfi_gltf_image *g = &scene->view->images[i];
        const resurfi_scene_image *img = &scene->images[i];
        images[i].missing = img->missing;
        images[i].mime_type = img->data ? img->mime : NULL;
        images[i].bytes = img->data ? img->size
                          : g->data ? g->size
                          : g->buffer_view >= 0 && (size_t)g->buffer_view < scene->view->buffer_view_count
                              ? (size_t)scene->view->buffer_views[g->buffer_view].byte_length
                              : 0;
    }
    resurf_status status = resurfi_gltf_describe(scene->doc, prims, images, as_json, dst, dst_size, out_length,
                                                 error);
    resurfi_free(a, prims);
    resurfi_free(a, images);
    if (status == RESURF_OK)
        resurfi_clear_error(error);
    return status;
}
