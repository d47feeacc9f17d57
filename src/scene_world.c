/* The scene in world space: every node that shows a mesh (the instances), and one level of the whole scene
 * gathered into one mesh with each node's world transform applied. Used by resurf_scene_world_mesh(), by the level
 * errors of resurf_scene_build_lods() and by the preview sheet, so that all three see the same world. */
#include <string.h>

#include "scene_internal.h"
#include "vec3.h"

/* A node's MSFT_lod levels, when every id names a node with a mesh (else none: the node shows level 0 alone). */
static void read_msft_lod(const resurfi_gltf_view *v, const resurfi_gltf_node *node, resurfi_scene_instance *item)
{
    if (node->lod_count == 0 || node->lod_count > RESURF_SCENE_MAX_LEVELS - 1)
        return;
    for (size_t k = 0; k < node->lod_count; ++k) {
        long long id = node->lod_ids[k];
        if (id < 0 || (size_t)id >= v->node_count || v->nodes[id].mesh < 0)
            return;
        item->lod_mesh[k] = (size_t)v->nodes[id].mesh;
    }
    item->lod_count = node->lod_count;
    item->coverage_count = node->coverage_count;
    item->coverage = node->coverage;
}

resurf_status resurfi_scene_gather(const resurf_scene *scene, const resurf_allocator *alloc,
                                   resurfi_scene_instances *out)
{
    const resurfi_gltf_view *v = scene->view;
    size_t node_count = v ? v->node_count : 0;
    size_t shown = node_count + (scene->instance_first ? scene->instance_first[node_count] : 0);
    size_t cap = shown > scene->mesh_count ? shown : scene->mesh_count;
    out->count = 0;
    out->items = resurfi_calloc(alloc, cap ? cap : 1, sizeof *out->items);
    if (!out->items)
        return RESURF_ERR_OUT_OF_MEMORY;
    if (!v || node_count == 0) {
        for (size_t m = 0; m < scene->mesh_count; ++m)
            out->items[out->count++] = (resurfi_scene_instance){.mesh = m};
        return RESURF_OK;
    }
    /* Each node has at most one parent and the graph has no cycle (checked by the loader), so a walk visits each
     * node once and a stack of node_count entries holds it. */
    long long *stack = resurfi_alloc(alloc, node_count, sizeof *stack);
    unsigned char *is_child = resurfi_calloc(alloc, node_count, 1);
    if (!stack || !is_child) {
        resurfi_free(alloc, stack);
        resurfi_free(alloc, is_child);
        resurfi_free(alloc, out->items);
        out->items = NULL;
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    size_t top = 0;
    long long chosen = v->default_scene != RESURFI_GLTF_NONE ? v->default_scene : v->scene_count ? 0 : -1;
    if (chosen >= 0) {
        const resurfi_gltf_scene *sc = &v->scenes[chosen];
        for (size_t k = sc->node_count; k-- > 0 && top < node_count;)
            stack[top++] = sc->nodes[k];
    } else {
        for (size_t n = 0; n < node_count; ++n)
            for (size_t c = 0; c < v->nodes[n].child_count; ++c)
                is_child[v->nodes[n].children[c]] = 1;
        for (size_t n = node_count; n-- > 0;)
            if (!is_child[n])
                stack[top++] = (long long)n;
    }
    while (top > 0) {
        long long n = stack[--top];
        const resurfi_gltf_node *node = &v->nodes[n];
        for (size_t j = 0; node->mesh >= 0 && j < resurfi_scene_node_instances(scene, (size_t)n) && out->count < cap;
             ++j) {
            resurfi_scene_instance *item = &out->items[out->count++];
            *item = (resurfi_scene_instance){.mesh = (size_t)node->mesh,
                                             .world = resurfi_scene_instance_world(scene, (size_t)n, j)};
            read_msft_lod(v, node, item);
        }
        for (size_t c = node->child_count; c-- > 0 && top < node_count;)
            stack[top++] = node->children[c];
    }
    resurfi_free(alloc, stack);
    resurfi_free(alloc, is_child);
    return RESURF_OK;
}

size_t resurfi_scene_instance_mesh(const resurfi_scene_instance *item, size_t k, size_t *prim_level)
{
    *prim_level = item->lod_count ? 0 : k;
    if (k == 0 || item->lod_count == 0)
        return item->mesh;
    return item->lod_mesh[(k < item->lod_count ? k : item->lod_count) - 1];
}

/* Primitive p's mesh at level k (NULL for points and lines): from `levels` when it holds a chain for p. */
static const resurf_mesh *prim_mesh(const resurf_scene *scene, const resurfi_scene_levels *levels, size_t p,
                                    size_t k)
{
    const resurfi_scene_prim *prim = &scene->prims[p];
    if (!prim->mesh)
        return NULL;
    if (k > 0 && levels && levels->chains && levels->chains[p]) /* a chain that kept no level: full detail */
        return levels->counts[p] ? levels->chains[p][(k < levels->counts[p] ? k : levels->counts[p]) - 1]
                                 : prim->mesh;
    return resurfi_scene_level_mesh(prim, k);
}

/* Appends m moved by the world matrix a (column-major; NULL = identity) to w from vertex *vbase and triangle
 * *tbase: positions by the matrix, normals (when w has them) by its inverse transpose, renormalised; TEXCOORD_0
 * (when w has it) as it is. */
static void append(resurf_mesh *w, const resurf_mesh *m, const double *a, size_t *vbase, size_t *tbase)
{
    affine3 map = affine3_from(a);
    for (size_t k = 0; k < m->vertex_count; ++k) {
        v3_store(w->positions + 3 * (*vbase + k), affine3_point(&map, m->positions + 3 * k));
        if (w->normals)
            v3_store(w->normals + 3 * (*vbase + k), affine3_normal(&map, m->normals + 3 * k));
    }
    if (w->texcoord_count > 0)
        memcpy(w->texcoords[0] + 2 * *vbase, m->texcoords[0], 2 * m->vertex_count * sizeof(double));
    for (size_t k = 0; k < 3 * m->triangle_count; ++k)
        w->indices[3 * *tbase + k] = (uint32_t)(*vbase + m->indices[k]);
    *vbase += m->vertex_count;
    *tbase += m->triangle_count;
}

resurf_status resurfi_scene_flatten(const resurf_scene *scene, const resurfi_scene_instances *list, size_t level,
                                    const resurfi_scene_levels *levels, const resurf_allocator *alloc,
                                    resurf_mesh **out, resurf_error *error)
{
    size_t vertices = 0, triangles = 0;
    int normals = 1, texcoords = 1;
    for (size_t i = 0; i < list->count; ++i) {
        size_t k, mesh = resurfi_scene_instance_mesh(&list->items[i], level, &k);
        for (size_t p = scene->mesh_first[mesh]; p < scene->mesh_first[mesh + 1]; ++p) {
            const resurf_mesh *m = prim_mesh(scene, levels, p, k);
            if (!m)
                continue;
            vertices += m->vertex_count;
            triangles += m->triangle_count;
            normals = normals && m->normals;
            texcoords = texcoords && m->texcoord_count > 0 && m->texcoords[0];
            if (vertices > UINT32_MAX || triangles > UINT32_MAX)
                return resurfi_error(error, RESURF_ERR_LIMIT,
                                     "level %zu of the scene has more than 2^32 vertices or triangles", level);
        }
    }
    unsigned attributes = (normals ? RESURF_ATTR_NORMALS : 0) | (texcoords ? RESURF_ATTR_TEXCOORD0 : 0);
    resurf_mesh *w = NULL;
    resurf_status status = resurf_mesh_create_with(vertices, triangles, attributes, alloc, &w, error);
    if (status != RESURF_OK)
        return status;
    size_t vbase = 0, tbase = 0;
    for (size_t i = 0; i < list->count; ++i) {
        size_t k, mesh = resurfi_scene_instance_mesh(&list->items[i], level, &k);
        for (size_t p = scene->mesh_first[mesh]; p < scene->mesh_first[mesh + 1]; ++p) {
            const resurf_mesh *m = prim_mesh(scene, levels, p, k);
            if (m)
                append(w, m, list->items[i].world, &vbase, &tbase);
        }
    }
    *out = w;
    return RESURF_OK;
}

resurf_status resurf_scene_world_mesh(const resurf_scene *scene, int level, const resurf_allocator *alloc,
                                      resurf_mesh **out, resurf_error *error)
{
    if (out)
        *out = NULL;
    if (!scene || !out)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "scene or out is NULL");
    if (level < 0 || level >= RESURF_SCENE_MAX_LEVELS)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "level %d (0 to %d)", level,
                             RESURF_SCENE_MAX_LEVELS - 1);
    const resurf_allocator *a = alloc ? alloc : &scene->alloc;
    resurfi_scene_instances list;
    if (resurfi_scene_gather(scene, a, &list) != RESURF_OK)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory gathering the scene");
    resurf_status status = resurfi_scene_flatten(scene, &list, (size_t)level, NULL, a, out, error);
    resurfi_free(a, list.items);
    if (status == RESURF_OK)
        resurfi_clear_error(error);
    return status;
}
