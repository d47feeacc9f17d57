/* Meshes from and to the caller's vertex and index arrays (resurf_mesh_from_arrays, resurf_mesh_to_arrays): strided,
 * interleaved float or double vertex data, UNORM8/16 colours and texcoords (glTF's normalized integers, value/max),
 * 16- or 32-bit indices. No paper behind it; the layout rules follow glTF 2.0's accessors (byteStride, normalized
 * component types, TEXCOORD_n numbered without gaps).
 *
 * Both directions check everything first and only then allocate or write, so a failed call leaves no mesh behind
 * and writes no byte of the caller's memory. Components are read and written with memcpy: interleaved buffers are
 * often not aligned for double (a stride of 28 bytes), and memcpy is the defined way to access such data. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "internal.h"

/* ---- types and strides ---------------------------------------------------------------------------------------- */

static size_t component_size(resurf_component_type type)
{
    switch (type) {
    case RESURF_COMPONENT_FLOAT: return sizeof(float);
    case RESURF_COMPONENT_DOUBLE: return sizeof(double);
    case RESURF_COMPONENT_UNORM8: return sizeof(uint8_t);
    case RESURF_COMPONENT_UNORM16: return sizeof(uint16_t);
    default: return 0;
    }
}

static const char *component_name(resurf_component_type type)
{
    switch (type) {
    case RESURF_COMPONENT_FLOAT: return "float";
    case RESURF_COMPONENT_DOUBLE: return "double";
    case RESURF_COMPONENT_UNORM8: return "unorm8";
    case RESURF_COMPONENT_UNORM16: return "unorm16";
    default: return "unknown";
    }
}

/* What one attribute is: its name in messages, its component count, and whether integer (UNORM) types make sense
 * for it (colours and texcoords are in [0, 1] in resurf; positions and normals are not). */
typedef struct attr_kind {
    char name[16];
    unsigned components;
    int unorm_allowed;
} attr_kind;

/* Checks one array's type and stride; *out_stride receives the effective stride (0 means tightly packed). */
static resurf_status check_layout(const attr_kind *k, resurf_component_type type, size_t stride, size_t *out_stride,
                                  resurf_error *error)
{
    size_t size = component_size(type);
    if (size == 0)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "%s: unknown component type %d", k->name,
                             (int)type);
    if (!k->unorm_allowed && type != RESURF_COMPONENT_FLOAT && type != RESURF_COMPONENT_DOUBLE)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT,
                             "%s: component type %s is not allowed (float or double only)", k->name,
                             component_name(type));
    size_t element = k->components * size;
    if (stride != 0 && stride < element)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT,
                             "%s: stride %zu is smaller than one element (%zu bytes: %u %ss)", k->name, stride, element,
                             k->components, component_name(type));
    *out_stride = stride ? stride : element;
    return RESURF_OK;
}

/* The byte span vertex_count elements cover must be addressable: (n − 1) × stride + element must not overflow. */
static resurf_status check_span(const attr_kind *k, size_t vertex_count, size_t stride, resurf_error *error)
{
    if (vertex_count > 1 && stride > (SIZE_MAX - 64) / (vertex_count - 1))
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "%s: %zu vertices of stride %zu overflow memory",
                             k->name, vertex_count, stride);
    return RESURF_OK;
}

static double read_component(const unsigned char *p, resurf_component_type type)
{
    switch (type) {
    case RESURF_COMPONENT_FLOAT: {
        float f;
        memcpy(&f, p, sizeof f);
        return f;
    }
    case RESURF_COMPONENT_DOUBLE: {
        double d;
        memcpy(&d, p, sizeof d);
        return d;
    }
    case RESURF_COMPONENT_UNORM8: return p[0] / 255.0;
    case RESURF_COMPONENT_UNORM16: {
        uint16_t u;
        memcpy(&u, p, sizeof u);
        return u / 65535.0;
    }
    default: return 0;
    }
}

/* Writes x as `type`. Narrowing to float rounds to nearest (the caller has checked the range); UNORM values are
 * clamped to [0, 1] and rounded, NaN giving 0, so k / max comes back as k. */
static void write_component(unsigned char *p, resurf_component_type type, double x)
{
    switch (type) {
    case RESURF_COMPONENT_FLOAT: {
        float f = (float)x;
        memcpy(p, &f, sizeof f);
        break;
    }
    case RESURF_COMPONENT_DOUBLE: memcpy(p, &x, sizeof x); break;
    case RESURF_COMPONENT_UNORM8:
    case RESURF_COMPONENT_UNORM16: {
        double max = type == RESURF_COMPONENT_UNORM8 ? 255.0 : 65535.0;
        double c = x > 0 ? (x < 1 ? x : 1) : 0; /* NaN fails x > 0: 0 */
        long q = lround(c * max);
        if (type == RESURF_COMPONENT_UNORM8) {
            p[0] = (uint8_t)q;
        } else {
            uint16_t u = (uint16_t)q;
            memcpy(p, &u, sizeof u);
        }
        break;
    }
    default: break;
    }
}

/* ---- from the caller's arrays ---------------------------------------------------------------------------------- */

resurf_mesh_arrays resurf_mesh_arrays_default(void)
{
    resurf_mesh_arrays a;
    memset(&a, 0, sizeof a);
    a.struct_size = sizeof a;
    a.color_components = 4;
    a.index_type = RESURF_INDEX_UINT32;
    return a;
}

/* One vertex source as the reader needs it: data, type, effective stride, components, name. */
typedef struct source {
    attr_kind kind;
    const unsigned char *data;
    resurf_component_type type;
    size_t stride;
} source;

static resurf_status prepare_source(source *s, const char *name, unsigned components, int unorm_allowed,
                                    const resurf_vertex_source *v, size_t vertex_count, resurf_error *error)
{
    memset(s, 0, sizeof *s);
    snprintf(s->kind.name, sizeof s->kind.name, "%s", name);
    s->kind.components = components;
    s->kind.unorm_allowed = unorm_allowed;
    s->data = v->data;
    s->type = v->type;
    if (!s->data)
        return RESURF_OK;
    resurf_status st = check_layout(&s->kind, v->type, v->stride, &s->stride, error);
    if (st == RESURF_OK)
        st = check_span(&s->kind, vertex_count, s->stride, error);
    return st;
}

/* Every value of a source must be finite: a NaN position poisons every distance computed from it, and the
 * caller learns about it here, with the vertex, rather than as a failure of a later call. */
static resurf_status check_finite(const source *s, size_t vertex_count, resurf_error *error)
{
    size_t size = component_size(s->type);
    if (s->type == RESURF_COMPONENT_UNORM8 || s->type == RESURF_COMPONENT_UNORM16)
        return RESURF_OK; /* integers are always finite */
    for (size_t v = 0; v < vertex_count; ++v) {
        const unsigned char *p = s->data + v * s->stride;
        for (unsigned c = 0; c < s->kind.components; ++c) {
            double x = read_component(p + c * size, s->type);
            if (!isfinite(x))
                return resurfi_error(error, RESURF_ERR_INVALID_MESH, "%s: vertex %zu, component %u is %s",
                                     s->kind.name, v, c, isnan(x) ? "nan" : x > 0 ? "inf" : "-inf");
        }
    }
    return RESURF_OK;
}

/* Copies a source into dst (dst_components doubles per vertex; the source's own components first). */
static void copy_source(const source *s, size_t vertex_count, double *dst, unsigned dst_components)
{
    size_t size = component_size(s->type);
    for (size_t v = 0; v < vertex_count; ++v) {
        const unsigned char *p = s->data + v * s->stride;
        for (unsigned c = 0; c < s->kind.components; ++c)
            dst[v * dst_components + c] = read_component(p + c * size, s->type);
    }
}

static uint32_t read_index(const void *indices, resurf_index_type type, size_t i)
{
    if (type == RESURF_INDEX_UINT16) {
        uint16_t u;
        memcpy(&u, (const unsigned char *)indices + i * sizeof u, sizeof u);
        return u;
    }
    uint32_t u;
    memcpy(&u, (const unsigned char *)indices + i * sizeof u, sizeof u);
    return u;
}

resurf_status resurf_mesh_from_arrays(const resurf_mesh_arrays *arrays, resurf_mesh **out_mesh, resurf_error *error)
{
    if (out_mesh)
        *out_mesh = NULL;
    if (!arrays || !out_mesh)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "arrays or out_mesh is NULL");
    RESURFI_CHECK_OPTIONS_ALLOC(arrays, resurf_mesh_arrays, error);
    const size_t n = arrays->vertex_count;
    if (n > UINT32_MAX)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "vertex_count %zu is above 2^32 - 1", n);
    if (arrays->index_count % 3)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT,
                             "index_count %zu is not a multiple of 3 (it counts indices, not triangles)",
                             arrays->index_count);
    const size_t triangles = arrays->index_count / 3;
    if (triangles > UINT32_MAX)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "%zu triangles is above 2^32 - 1", triangles);
    if (n && !arrays->positions.data)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "positions.data is NULL for %zu vertices", n);
    if (triangles && !arrays->indices)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "indices is NULL for index_count %zu",
                             arrays->index_count);
    if (arrays->index_type != RESURF_INDEX_UINT32 && arrays->index_type != RESURF_INDEX_UINT16)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "unknown index_type %d", (int)arrays->index_type);

    /* Layouts: every source's type and stride. */
    enum { MAX_SOURCES = 3 + RESURF_MAX_TEXCOORD_SETS };
    source sources[MAX_SOURCES];
    resurf_status st = prepare_source(&sources[0], "positions", 3, 0, &arrays->positions, n, error);
    if (st == RESURF_OK)
        st = prepare_source(&sources[1], "normals", 3, 0, &arrays->normals, n, error);
    if (st == RESURF_OK && arrays->colors.data && arrays->color_components != 3 && arrays->color_components != 4)
        st = resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "colors: color_components is %u (3 or 4)",
                           arrays->color_components);
    if (st == RESURF_OK)
        st = prepare_source(&sources[2], "colors", arrays->color_components, 1, &arrays->colors, n, error);
    unsigned texcoord_sets = 0;
    for (unsigned k = 0; k < RESURF_MAX_TEXCOORD_SETS && st == RESURF_OK; ++k) {
        char name[16];
        snprintf(name, sizeof name, "texcoords[%u]", k);
        st = prepare_source(&sources[3 + k], name, 2, 1, &arrays->texcoords[k], n, error);
        if (st == RESURF_OK && arrays->texcoords[k].data) {
            /* Sets are numbered without gaps, as glTF's TEXCOORD_n are, so that set k always means the k-th. */
            if (k != texcoord_sets)
                st = resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT,
                                   "texcoords[%u] is given without texcoords[%u] (sets must be numbered from 0)", k,
                                   texcoord_sets);
            texcoord_sets = k + 1;
        }
    }
    if (st != RESURF_OK)
        return st;

    /* Values: indices in range, then finite values; nothing is allocated before both pass. */
    for (size_t i = 0; i < arrays->index_count; ++i) {
        uint32_t v = read_index(arrays->indices, arrays->index_type, i);
        if (v >= n)
            return resurfi_error(error, RESURF_ERR_INVALID_MESH,
                                 "triangle %zu (indices %zu..%zu) refers to vertex %u, but there are %zu vertices",
                                 i / 3, i / 3 * 3, i / 3 * 3 + 2, v, n);
    }
    for (int s = 0; s < MAX_SOURCES; ++s)
        if (sources[s].data && (st = check_finite(&sources[s], n, error)) != RESURF_OK)
            return st;

    unsigned attributes = (arrays->normals.data ? RESURF_ATTR_NORMALS : 0u) |
                          (arrays->colors.data ? RESURF_ATTR_COLORS : 0u);
    for (unsigned k = 0; k < texcoord_sets; ++k)
        attributes |= RESURF_ATTR_TEXCOORD0 << k;
    resurf_mesh *m = NULL;
    if ((st = resurf_mesh_create_with(n, triangles, attributes, arrays->allocator, &m, error)) != RESURF_OK)
        return st;
    if (n) {
        copy_source(&sources[0], n, m->positions, 3);
        if (m->normals)
            copy_source(&sources[1], n, m->normals, 3);
        if (m->colors) {
            if (arrays->color_components == 3)
                for (size_t v = 0; v < n; ++v)
                    m->colors[4 * v + 3] = 1.0; /* opaque, as glTF reads an RGB COLOR_0 */
            copy_source(&sources[2], n, m->colors, 4);
            m->color_components = arrays->color_components;
        }
        for (unsigned k = 0; k < texcoord_sets; ++k)
            copy_source(&sources[3 + k], n, m->texcoords[k], 2);
    }
    for (size_t i = 0; i < arrays->index_count; ++i)
        m->indices[i] = read_index(arrays->indices, arrays->index_type, i);
    *out_mesh = m;
    resurfi_clear_error(error);
    return RESURF_OK;
}

/* ---- to the caller's arrays ------------------------------------------------------------------------------------ */

resurf_mesh_arrays_out resurf_mesh_arrays_out_default(void)
{
    resurf_mesh_arrays_out o;
    memset(&o, 0, sizeof o);
    o.struct_size = sizeof o;
    o.color_components = 4;
    o.index_type = RESURF_INDEX_UINT32;
    return o;
}

/* One destination as the writer needs it, with the mesh array it comes from. */
typedef struct dest {
    attr_kind kind;
    unsigned char *data;
    resurf_component_type type;
    size_t stride;
    const double *src;      /* the mesh's array */
    unsigned src_components;
} dest;

static resurf_status prepare_dest(dest *d, const char *name, unsigned components, int unorm_allowed,
                                  const resurf_vertex_dest *v, const double *src, unsigned src_components,
                                  size_t vertex_count, resurf_error *error)
{
    memset(d, 0, sizeof *d);
    snprintf(d->kind.name, sizeof d->kind.name, "%s", name);
    d->kind.components = components;
    d->kind.unorm_allowed = unorm_allowed;
    d->data = v->data;
    d->type = v->type;
    d->src = src;
    d->src_components = src_components;
    if (!d->data)
        return RESURF_OK;
    if (!src && vertex_count)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "the mesh has no %s", name);
    resurf_status st = check_layout(&d->kind, v->type, v->stride, &d->stride, error);
    if (st == RESURF_OK)
        st = check_span(&d->kind, vertex_count, d->stride, error);
    return st;
}

/* A float destination cannot hold a finite double beyond FLT_MAX (it would silently become infinite). */
static resurf_status check_fits(const dest *d, size_t vertex_count, resurf_error *error)
{
    if (d->type != RESURF_COMPONENT_FLOAT)
        return RESURF_OK;
    for (size_t v = 0; v < vertex_count; ++v)
        for (unsigned c = 0; c < d->kind.components; ++c) {
            double x = d->src[v * d->src_components + c];
            if (isfinite(x) && fabs(x) > FLT_MAX) /* checked before converting: the cast itself would be UB */
                return resurfi_error(error, RESURF_ERR_LIMIT,
                                     "%s: vertex %zu, component %u = %g is beyond float's range (ask for double)",
                                     d->kind.name, v, c, x);
        }
    return RESURF_OK;
}

static void write_dest(const dest *d, size_t vertex_count)
{
    size_t size = component_size(d->type);
    for (size_t v = 0; v < vertex_count; ++v) {
        unsigned char *p = d->data + v * d->stride;
        for (unsigned c = 0; c < d->kind.components; ++c)
            write_component(p + c * size, d->type, d->src[v * d->src_components + c]);
    }
}

resurf_status resurf_mesh_to_arrays(const resurf_mesh *mesh, const resurf_mesh_arrays_out *out, resurf_error *error)
{
    if (!mesh || !out)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "mesh or out is NULL");
    RESURFI_CHECK_OPTIONS(out, resurf_mesh_arrays_out, error);
    const size_t n = mesh->vertex_count, index_count = 3 * mesh->triangle_count;
    if ((n && !mesh->positions) || (index_count && !mesh->indices))
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "the mesh has no positions or indices");
    int any_vertex_dest = out->positions.data || out->normals.data || out->colors.data;
    for (unsigned k = 0; k < RESURF_MAX_TEXCOORD_SETS; ++k)
        any_vertex_dest |= out->texcoords[k].data != NULL;
    if (any_vertex_dest && out->vertex_capacity < n)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT,
                             "vertex_capacity %zu is less than the mesh's %zu vertices", out->vertex_capacity, n);
    if (out->indices && out->index_capacity < index_count)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT,
                             "index_capacity %zu is less than the mesh's %zu indices (3 per triangle)",
                             out->index_capacity, index_count);
    if (out->index_type != RESURF_INDEX_UINT32 && out->index_type != RESURF_INDEX_UINT16)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "unknown index_type %d", (int)out->index_type);

    enum { MAX_DESTS = 3 + RESURF_MAX_TEXCOORD_SETS };
    dest dests[MAX_DESTS];
    resurf_status st = prepare_dest(&dests[0], "positions", 3, 0, &out->positions, mesh->positions, 3, n, error);
    if (st == RESURF_OK)
        st = prepare_dest(&dests[1], "normals", 3, 0, &out->normals, mesh->normals, 3, n, error);
    if (st == RESURF_OK && out->colors.data && out->color_components != 3 && out->color_components != 4)
        st = resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "colors: color_components is %u (3 or 4)",
                           out->color_components);
    if (st == RESURF_OK)
        st = prepare_dest(&dests[2], "colors", out->color_components, 1, &out->colors, mesh->colors, 4, n, error);
    for (unsigned k = 0; k < RESURF_MAX_TEXCOORD_SETS && st == RESURF_OK; ++k) {
        char name[16];
        snprintf(name, sizeof name, "texcoords[%u]", k);
        const double *src = k < mesh->texcoord_count ? mesh->texcoords[k] : NULL;
        st = prepare_dest(&dests[3 + k], name, 2, 1, &out->texcoords[k], src, 2, n, error);
    }
    for (int d = 0; d < MAX_DESTS && st == RESURF_OK; ++d)
        if (dests[d].data && n)
            st = check_fits(&dests[d], n, error);
    if (st != RESURF_OK)
        return st;
    if (out->indices) {
        for (size_t i = 0; i < index_count; ++i) {
            uint32_t v = mesh->indices[i];
            if (v >= n)
                return resurfi_error(error, RESURF_ERR_INVALID_MESH,
                                     "triangle %zu refers to vertex %u, but there are %zu vertices", i / 3, v, n);
            if (out->index_type == RESURF_INDEX_UINT16 && v > UINT16_MAX)
                return resurfi_error(error, RESURF_ERR_LIMIT,
                                     "triangle %zu refers to vertex %u, beyond uint16 indices (ask for uint32)", i / 3,
                                     v);
        }
    }

    /* Everything checked: write. */
    for (int d = 0; d < MAX_DESTS; ++d)
        if (dests[d].data && n)
            write_dest(&dests[d], n);
    if (out->indices) {
        unsigned char *p = out->indices;
        for (size_t i = 0; i < index_count; ++i) {
            if (out->index_type == RESURF_INDEX_UINT16) {
                uint16_t u = (uint16_t)mesh->indices[i];
                memcpy(p + i * sizeof u, &u, sizeof u);
            } else {
                memcpy(p + i * sizeof(uint32_t), &mesh->indices[i], sizeof(uint32_t));
            }
        }
    }
    resurfi_clear_error(error);
    return RESURF_OK;
}
