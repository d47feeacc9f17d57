/* Meshes of one layout as the parts of one mesh, and back: the parts joined side by side with each triangle's part
 * as its group (so the simplifier sees one surface whose part borders are creases, src/simplify/setup.c), and a
 * joined mesh split by group into meshes of its own layout again. A scene simplifies a mesh's primitives together
 * this way (src/scene_joint.c): measured by tools/bench-borders, it keeps the borders closed at a lower error than
 * locking them. */
#include <string.h>

#include "internal.h"

/* Do a and b carry the same attributes (normals, texcoord sets, colours and their components, extras by name and
 * components)? */
bool resurfi_mesh_same_attributes(const resurf_mesh *a, const resurf_mesh *b)
{
    if (!!a->normals != !!b->normals || a->texcoord_count != b->texcoord_count || !!a->colors != !!b->colors ||
        (a->colors && a->color_components != b->color_components) || a->extra_count != b->extra_count)
        return false;
    for (unsigned k = 0; k < a->texcoord_count; ++k)
        if (!a->texcoords[k] != !b->texcoords[k])
            return false;
    for (size_t e = 0; e < a->extra_count; ++e)
        if (a->extras[e].components != b->extras[e].components || strcmp(a->extras[e].name, b->extras[e].name) ||
            !a->extras[e].data != !b->extras[e].data)
            return false;
    return true;
}

/* The attribute mask of resurf_mesh_create for m's layout. */
static unsigned layout_mask(const resurf_mesh *m)
{
    unsigned mask = (m->normals ? RESURF_ATTR_NORMALS : 0) | (m->colors ? RESURF_ATTR_COLORS : 0);
    for (unsigned k = 0; k < m->texcoord_count; ++k)
        if (m->texcoords[k])
            mask |= RESURF_ATTR_TEXCOORD0 << k;
    return mask;
}

/* An empty mesh of `like`'s layout with room for nv vertices and nt triangles. */
static resurf_status make_like(const resurf_mesh *like, size_t nv, size_t nt, const resurf_allocator *alloc,
                               resurf_mesh **out, resurf_error *error)
{
    resurf_status st = resurf_mesh_create_with(nv, nt, layout_mask(like), alloc, out, error);
    if (st != RESURF_OK)
        return st;
    (*out)->texcoord_count = like->texcoord_count;
    (*out)->color_components = like->color_components;
    for (size_t e = 0; e < like->extra_count && st == RESURF_OK; ++e)
        st = resurf_mesh_add_extra(*out, like->extras[e].name, like->extras[e].components, NULL, error);
    if (st != RESURF_OK) {
        resurf_mesh_free(*out);
        *out = NULL;
    }
    return st;
}

/* Vertex v of src into vertex w of dst (the same layout). */
static void copy_vertex(const resurf_mesh *src, size_t v, resurf_mesh *dst, size_t w)
{
    memcpy(dst->positions + 3 * w, src->positions + 3 * v, 3 * sizeof *dst->positions);
    if (src->normals)
        memcpy(dst->normals + 3 * w, src->normals + 3 * v, 3 * sizeof *dst->normals);
    for (unsigned k = 0; k < src->texcoord_count; ++k)
        if (src->texcoords[k])
            memcpy(dst->texcoords[k] + 2 * w, src->texcoords[k] + 2 * v, 2 * sizeof *dst->texcoords[k]);
    if (src->colors)
        memcpy(dst->colors + 4 * w, src->colors + 4 * v, 4 * sizeof *dst->colors);
    for (size_t e = 0; e < src->extra_count; ++e) {
        unsigned c = src->extras[e].components;
        if (src->extras[e].data)
            memcpy(dst->extras[e].data + (size_t)c * w, src->extras[e].data + (size_t)c * v,
                   c * sizeof *dst->extras[e].data);
    }
}

resurf_status resurfi_mesh_join_parts(const resurf_mesh *const *parts, size_t count, const resurf_allocator *alloc,
                                      resurf_mesh **out, resurf_error *error)
{
    *out = NULL;
    size_t nv = 0, nt = 0;
    for (size_t p = 0; p < count; ++p) {
        if (!resurfi_mesh_same_attributes(parts[0], parts[p]))
            return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "part %zu has other attributes than part 0", p);
        nv += parts[p]->vertex_count;
        nt += parts[p]->triangle_count;
    }
    if (count == 0 || nv > UINT32_MAX)
        return resurfi_error(error, RESURF_ERR_LIMIT, "%zu vertices in %zu parts", nv, count);
    resurf_mesh *m = NULL;
    resurf_status st = make_like(parts[0], nv, nt, alloc, &m, error);
    if (st != RESURF_OK)
        return st;
    m->triangle_groups = resurfi_alloc(&m->allocator, nt + 1, sizeof *m->triangle_groups);
    m->group_names = resurfi_calloc(&m->allocator, count, sizeof *m->group_names);
    if (!m->triangle_groups || !m->group_names) {
        resurf_mesh_free(m);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory joining %zu parts", count);
    }
    m->group_count = count;
    size_t v0 = 0, t0 = 0;
    for (size_t p = 0; p < count; ++p) {
        const resurf_mesh *part = parts[p];
        for (size_t v = 0; v < part->vertex_count; ++v)
            copy_vertex(part, v, m, v0 + v);
        for (size_t i = 0; i < 3 * part->triangle_count; ++i)
            m->indices[3 * t0 + i] = (uint32_t)(part->indices[i] + v0);
        for (size_t t = 0; t < part->triangle_count; ++t)
            m->triangle_groups[t0 + t] = (uint32_t)p;
        v0 += part->vertex_count;
        t0 += part->triangle_count;
    }
    *out = m;
    return RESURF_OK;
}

resurf_status resurfi_mesh_split_parts(const resurf_mesh *joined, size_t count, const resurf_allocator *alloc,
                                       resurf_mesh **out_parts, resurf_error *error)
{
    for (size_t p = 0; p < count; ++p)
        out_parts[p] = NULL;
    if (!joined->triangle_groups && count > 1)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "the joined mesh has no groups");
    size_t nv = joined->vertex_count;
    uint32_t *map = resurfi_alloc(alloc, nv + 1, sizeof *map);
    size_t *tris = resurfi_calloc(alloc, count, sizeof *tris);
    resurf_status st = map && tris ? RESURF_OK
                                   : resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory splitting parts");
    for (size_t t = 0; st == RESURF_OK && t < joined->triangle_count; ++t) {
        uint32_t g = joined->triangle_groups ? joined->triangle_groups[t] : 0;
        if (g >= count)
            st = resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "triangle %zu is in part %u of %zu", t, g, count);
        else
            tris[g]++;
    }
    for (size_t p = 0; p < count && st == RESURF_OK; ++p) {
        /* The part's vertices in the order its triangles first use them (a vertex two parts use goes to both). */
        memset(map, 0xff, nv * sizeof *map);
        size_t used = 0;
        for (size_t t = 0; t < joined->triangle_count; ++t)
            if ((joined->triangle_groups ? joined->triangle_groups[t] : 0) == p)
                for (int k = 0; k < 3; ++k) {
                    uint32_t v = joined->indices[3 * t + k];
                    if (map[v] == UINT32_MAX)
                        map[v] = (uint32_t)used++;
                }
        resurf_mesh *m = NULL;
        if ((st = make_like(joined, used, tris[p], alloc, &m, error)) != RESURF_OK)
            break;
        for (size_t v = 0; v < nv; ++v)
            if (map[v] != UINT32_MAX)
                copy_vertex(joined, v, m, map[v]);
        size_t i = 0;
        for (size_t t = 0; t < joined->triangle_count; ++t)
            if ((joined->triangle_groups ? joined->triangle_groups[t] : 0) == p)
                for (int k = 0; k < 3; ++k)
                    m->indices[i++] = map[joined->indices[3 * t + k]];
        out_parts[p] = m;
    }
    if (st != RESURF_OK)
        for (size_t p = 0; p < count; ++p) {
            resurf_mesh_free(out_parts[p]);
            out_parts[p] = NULL;
        }
    resurfi_free(alloc, map);
    resurfi_free(alloc, tris);
    return st;
}
