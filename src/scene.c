/* Scenes: loading glTF 2.0 (.gltf, .glb), raw Draco (.drc) and mesh files into a resurf_scene, decoding its
 * triangle primitives into resurf_meshes once scene_check.c has checked every index, range and reference of the
 * document, and the public resurf_scene_* calls other than saving (scene_save.c).
 *
 * Follows the Khronos glTF 2.0 specification (3.6 binary data, 3.7 geometry, 3.11 accessors' sparse storage, 4.4
 * GLB), KHR_draco_mesh_compression and KHR_mesh_quantization. The C++ shim (io/gltf_read.cpp) only parses: every
 * decision about what is acceptable is taken here and in scene_check.c, before any byte is read through an index
 * from the file. Draco payloads are decoded by io/draco.cpp only after their bufferView and byte range were
 * checked, and their attribute ids are checked against what the decoder found before any value is used. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "file.h"
#include "scene_internal.h"

/* ---- small helpers ------------------------------------------------------------------------------------------- */

size_t resurfi_gltf_component_size(int component_type)
{
    switch (component_type) {
    case RESURFI_GLTF_BYTE:
    case RESURFI_GLTF_UNSIGNED_BYTE: return 1;
    case RESURFI_GLTF_SHORT:
    case RESURFI_GLTF_UNSIGNED_SHORT: return 2;
    case RESURFI_GLTF_UNSIGNED_INT:
    case RESURFI_GLTF_FLOAT: return 4;
    default: return 0;
    }
}

int resurfi_ends_with_nocase(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    if (n < k)
        return 0;
    for (size_t i = 0; i < k; ++i) {
        char a = s[n - k + i], b = suffix[i];
        if (a >= 'A' && a <= 'Z')
            a = (char)(a - 'A' + 'a');
        if (a != b)
            return 0;
    }
    return 1;
}

resurf_status resurfi_scene_add_warning(resurf_scene *s, const char *text)
{
    char **list = resurfi_realloc(&s->alloc, s->warnings, s->warning_count + 1, sizeof *list);
    if (!list)
        return RESURF_ERR_OUT_OF_MEMORY;
    s->warnings = list;
    if (!(list[s->warning_count] = resurfi_strdup(&s->alloc, text)))
        return RESURF_ERR_OUT_OF_MEMORY;
    s->warning_count++;
    return RESURF_OK;
}

/* ---- the scene object ---------------------------------------------------------------------------------------- */

static void free_prim(resurfi_scene_prim *p, const resurf_allocator *alloc)
{
    resurf_mesh_free(p->mesh);
    resurfi_free(alloc, p->formats);
    for (size_t k = 0; k < p->lod_count; ++k)
        resurf_mesh_free(p->lods[k]);
    resurfi_free(alloc, p->lods);
}

void resurf_scene_free(resurf_scene *scene)
{
    if (!scene)
        return;
    const resurf_allocator alloc = scene->alloc; /* the struct holding it goes last */
    const resurf_allocator *a = &alloc;
    if (scene->prims)
        for (size_t i = 0; i < scene->prim_count; ++i)
            free_prim(&scene->prims[i], a);
    resurfi_free(a, scene->prims);
    if (scene->coverage)
        for (size_t m = 0; m < scene->mesh_count; ++m)
            resurfi_free(a, scene->coverage[m]);
    resurfi_free(a, scene->coverage);
    resurfi_free(a, scene->coverage_count);
    resurfi_free(a, scene->mesh_first);
    resurfi_free(a, scene->world);
    resurfi_free(a, scene->instance_first);
    resurfi_free(a, scene->instance_world);
    for (size_t i = 0; i < scene->warning_count; ++i)
        resurfi_free(a, scene->warnings[i]);
    resurfi_free(a, scene->warnings);
    resurfi_scene_free_images(scene);
    resurfi_gltf_doc_free(scene->doc);
    resurfi_free(a, scene);
}

/* A scene of mesh_count meshes and prim_count primitives, all zeroed, whose blocks come from alloc. */
static resurf_scene *scene_new(const resurf_allocator *alloc, size_t mesh_count, size_t prim_count)
{
    resurf_scene *s = resurfi_calloc(alloc, 1, sizeof *s);
    if (!s)
        return NULL;
    if (alloc)
        s->alloc = *alloc;
    s->mesh_count = mesh_count;
    s->prim_count = prim_count;
    s->mesh_first = resurfi_calloc(alloc, mesh_count + 1, sizeof *s->mesh_first);
    s->coverage = resurfi_calloc(alloc, mesh_count, sizeof *s->coverage);
    s->coverage_count = resurfi_calloc(alloc, mesh_count, sizeof *s->coverage_count);
    s->prims = resurfi_calloc(alloc, prim_count, sizeof *s->prims);
    if (!s->mesh_first || !s->coverage || !s->coverage_count || !s->prims) {
        resurf_scene_free(s);
        return NULL;
    }
    return s;
}

/* A one-mesh scene that takes ownership of mesh (freed on failure too). */
static resurf_status scene_of_mesh(resurf_mesh *mesh, resurf_scene **out, resurf_error *error)
{
    resurf_scene *s = scene_new(&mesh->allocator, 1, 1);
    if (!s) {
        resurf_mesh_free(mesh);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory creating a scene");
    }
    s->mesh_first[1] = 1;
    resurfi_scene_prim *p = &s->prims[0];
    p->mesh = mesh;
    snprintf(p->info.name, sizeof p->info.name, "meshes[0].primitives[0]");
    p->info.mode = 4;
    p->info.kind = RESURF_PRIMITIVE_TRIANGLES;
    for (size_t i = 0; i < mesh->extra_count; ++i)
        if (!strncmp(mesh->extras[i].name, RESURF_MORPH_TARGET_PREFIX, strlen(RESURF_MORPH_TARGET_PREFIX)))
            p->info.kind = RESURF_PRIMITIVE_MORPHED; /* its deltas are written as morph targets */
    p->info.instances = 1;
    *out = s;
    return RESURF_OK;
}

/* ---- decoding primitives ------------------------------------------------------------------------------------- */

/* glTF 2.0 3.11: normalized integers map to [0,1] (unsigned) or [-1,1] (signed, the minimum clamped to -1). */
static double normalize(double x, int type)
{
    switch (type) {
    case RESURFI_GLTF_BYTE: return fmax(x / 127.0, -1.0);
    case RESURFI_GLTF_UNSIGNED_BYTE: return x / 255.0;
    case RESURFI_GLTF_SHORT: return fmax(x / 32767.0, -1.0);
    case RESURFI_GLTF_UNSIGNED_SHORT: return x / 65535.0;
    default: return x;
    }
}

/* Reads a checked accessor into out (count × components doubles), normalized as the accessor says. */
void resurfi_scene_read_accessor(const resurfi_gltf_view *v, const resurfi_gltf_accessor *a, double *out)
{
    resurfi_gltf_element e = resurfi_gltf_element_of(a);
    size_t n = (size_t)a->count, comps = (size_t)a->components;
    if (a->buffer_view == RESURFI_GLTF_NONE) {
        memset(out, 0, n * comps * sizeof *out);
    } else {
        const resurfi_gltf_buffer_view *bv = &v->buffer_views[a->buffer_view];
        size_t stride = bv->byte_stride ? (size_t)bv->byte_stride : e.size;
        const unsigned char *base = v->buffers[bv->buffer].data + bv->byte_offset + a->byte_offset;
        for (size_t i = 0; i < n; ++i)
            for (size_t col = 0; col < e.columns; ++col)
                for (size_t r = 0; r < e.rows; ++r)
                    out[i * comps + col * e.rows + r] =
                        resurfi_gltf_read_component(base + i * stride + col * e.column_stride + r * e.component_size,
                                       a->component_type);
    }
    if (a->sparse) {
        const resurfi_gltf_buffer_view *iv = &v->buffer_views[a->sparse_indices_view];
        const resurfi_gltf_buffer_view *vv = &v->buffer_views[a->sparse_values_view];
        const unsigned char *ip = v->buffers[iv->buffer].data + iv->byte_offset + a->sparse_indices_offset;
        const unsigned char *vp = v->buffers[vv->buffer].data + vv->byte_offset + a->sparse_values_offset;
        size_t isize = resurfi_gltf_component_size(a->sparse_indices_type);
        for (long long k = 0; k < a->sparse_count; ++k) {
            size_t i = (size_t)resurfi_gltf_read_component(ip + (size_t)k * isize, a->sparse_indices_type);
            for (size_t col = 0; col < e.columns; ++col)
                for (size_t r = 0; r < e.rows; ++r)
                    out[i * comps + col * e.rows + r] =
                        resurfi_gltf_read_component(vp + (size_t)k * e.size + col * e.column_stride + r * e.component_size,
                                       a->component_type);
        }
    }
    if (a->normalized)
        for (size_t i = 0; i < n * comps; ++i)
            out[i] = normalize(out[i], a->component_type);
}


/* The values of one attribute of a primitive, wherever they come from. */
typedef struct attr_values {
    const char *name;
    const resurfi_gltf_accessor *accessor;
    double *values;     /* count × components */
} attr_values;

static resurf_status oom(load_ctx *c) { return resurfi_fail(c->error, RESURF_ERR_OUT_OF_MEMORY, c->path, 0, -1, "out of memory decoding the scene"); }

/* Decodes the checked Draco payload of a primitive (NULL *out for a primitive without one) and checks the decoded
 * data against the primitive's accessors. */
static resurf_status decode_draco(load_ctx *c, const resurfi_gltf_primitive *gp, const char *where,
                                  resurfi_draco_mesh **out)
{
    const resurfi_gltf_view *v = c->v;
    *out = NULL;
    /* A points primitive is copied untouched; its payload, a point cloud, is never decoded (resurfi_draco_decode
     * refuses point clouds, whose header counts Draco trusts for its allocations). */
    if (!gp->draco || gp->mode == 0)
        return RESURF_OK;
    /* The view's range was checked against its buffer (resurfi_scene_check_document). */
    const resurfi_gltf_buffer_view *bv = &v->buffer_views[gp->draco_view];
    const unsigned char *bytes = v->buffers[bv->buffer].data + bv->byte_offset;
    resurf_error derr;
    resurf_status status = resurfi_draco_decode(bytes, (size_t)bv->byte_length, out, &derr);
    if (status != RESURF_OK)
        return resurfi_fail(c->error, status, c->path, 0, -1, "%s: bufferViews[%lld]: %s", where, gp->draco_view,
                            derr.message);
    resurfi_draco_mesh *dm = *out;
    for (size_t i = 0; i < gp->draco_attribute_count; ++i) {
        const resurfi_gltf_named *d = &gp->draco_attributes[i];
        const resurfi_draco_attribute *da = NULL;
        for (size_t k = 0; k < dm->attribute_count; ++k)
            if (dm->attributes[k].unique_id == d->index)
                da = &dm->attributes[k];
        if (!da)
            return FAIL(c, "%s: Draco attribute id %lld of %s is not in the Draco data", where, d->index, d->name);
        const resurfi_gltf_accessor *a = NULL;
        for (size_t k = 0; k < gp->attribute_count; ++k)
            if (!strcmp(gp->attributes[k].name, d->name))
                a = &v->accessors[gp->attributes[k].index];
        if (da->components != a->components)
            return FAIL(c, "%s: %s has %d components in the Draco data and %d in its accessor", where, d->name,
                        da->components, a->components);
        if (a->count != dm->point_count)
            return FAIL(c, "%s: the accessor of %s counts %llu vertices, the Draco data %zu", where, d->name,
                        (unsigned long long)a->count, dm->point_count);
    }
    if (gp->indices != RESURFI_GLTF_NONE && gp->mode == 4 && v->accessors[gp->indices].count != 3 * dm->face_count)
        return FAIL(c, "%s: the indices accessor counts %llu, the Draco data has %zu triangles", where,
                    (unsigned long long)v->accessors[gp->indices].count, dm->face_count);
    return RESURF_OK;
}

/* The triangle list of a primitive from its index list (or 0..n-1), converting strips and fans (glTF 2.0 3.7.2.1):
 * strip triangle i is (v_i, v_i+1+i%2, v_i+2-i%2); fan triangle i is (v_i+1, v_i+2, v_0).
 * The joining triangles of strips and fans (a repeated index) are dropped. */
static resurf_status build_triangles(load_ctx *c, const char *where, int mode, const double *index_values,
                                     size_t index_count, size_t vertex_count, uint32_t **out, size_t *out_count)
{
    for (size_t i = 0; i < index_count; ++i)
        if (index_values[i] >= (double)vertex_count)
            return FAIL(c, "%s: index %zu is %.0f, past the %zu vertices", where, i, index_values[i], vertex_count);
    if (mode == 4 && index_count % 3)
        return FAIL(c, "%s: %zu indices are not a multiple of 3", where, index_count);
    size_t cap = mode == 4 ? index_count / 3 : index_count >= 3 ? index_count - 2 : 0;
    uint32_t *t = resurfi_alloc(c->alloc, cap, 3 * sizeof *t);
    if (!t)
        return oom(c);
    size_t n = 0;
    for (size_t i = 0; i < cap; ++i) {
        uint32_t a, b, d;
        if (mode == 4) {
            a = (uint32_t)index_values[3 * i], b = (uint32_t)index_values[3 * i + 1];
            d = (uint32_t)index_values[3 * i + 2];
        } else if (mode == 5) {
            a = (uint32_t)index_values[i], b = (uint32_t)index_values[i + 1 + (i & 1)];
            d = (uint32_t)index_values[i + 2 - (i & 1)];
        } else {
            a = (uint32_t)index_values[i + 1], b = (uint32_t)index_values[i + 2], d = (uint32_t)index_values[0];
        }
        if (mode != 4 && (a == b || b == d || a == d))
            continue;
        t[3 * n] = a, t[3 * n + 1] = b, t[3 * n + 2] = d;
        ++n;
    }
    *out = t;
    *out_count = n;
    return RESURF_OK;
}

/* Puts one attribute into the mesh: POSITION, NORMAL, TEXCOORD_0..3 (in order), COLOR_0, or an extra. */
static resurf_status store_attribute(load_ctx *c, const char *where, resurf_mesh *m, const attr_values *a)
{
    size_t n = m->vertex_count, comps = (size_t)a->accessor->components;
    int is_float = a->accessor->component_type == RESURFI_GLTF_FLOAT;
    if (is_float)
        for (size_t i = 0; i < n * comps; ++i)
            if (!isfinite(a->values[i]))
                return FAIL(c, "%s: %s of vertex %zu is not finite", where, a->name, i / comps);
    const char *name = a->name;
    int tex = -1;
    if (!strncmp(name, "TEXCOORD_", 9) && name[9] >= '0' && name[9] <= '3' && !name[10])
        tex = name[9] - '0';
    if (!strcmp(name, "POSITION") || !strcmp(name, "NORMAL")) {
        if (comps != 3 || a->accessor->matrix)
            return FAIL(c, "%s: %s is not VEC3", where, name);
        double *dst = name[0] == 'P' ? m->positions : m->normals;
        if (!dst && !(dst = m->normals = resurfi_alloc(&m->allocator, n, 3 * sizeof(double))))
            return oom(c);
        memcpy(dst, a->values, n * 3 * sizeof(double));
    } else if (tex >= 0 && (unsigned)tex == m->texcoord_count) {
        if (comps != 2 || a->accessor->matrix)
            return FAIL(c, "%s: %s is not VEC2", where, name);
        if (!(m->texcoords[tex] = resurfi_alloc(&m->allocator, n, 2 * sizeof(double))))
            return oom(c);
        memcpy(m->texcoords[tex], a->values, n * 2 * sizeof(double));
        m->texcoord_count = (unsigned)tex + 1;
    } else if (!strcmp(name, "COLOR_0")) {
        if ((comps != 3 && comps != 4) || a->accessor->matrix)
            return FAIL(c, "%s: COLOR_0 is not VEC3 or VEC4", where);
        if (!(m->colors = resurfi_alloc(&m->allocator, n, 4 * sizeof(double))))
            return oom(c);
        for (size_t i = 0; i < n; ++i)
            for (size_t k = 0; k < 4; ++k)
                m->colors[4 * i + k] = k < comps ? a->values[comps * i + k] : 1.0;
        m->color_components = (unsigned)comps;
    } else {
        if (strlen(name) >= sizeof m->extras[0].name)
            return FAIL(c, "%s: the attribute name '%.40s...' is longer than 63 bytes", where, name);
        resurf_attribute *x = NULL;
        if (resurf_mesh_add_extra(m, name, (unsigned)comps, &x, NULL) != RESURF_OK)
            return oom(c);
        for (size_t i = 0; i < n * comps; ++i)
            x->data[i] = (float)a->values[i];
    }
    return RESURF_OK;
}

/* A morphed primitive's targets become extras of its mesh, one per target attribute, named "targets[t].NAME"
 * (RESURF_MORPH_TARGET_PREFIX): the deltas travel with the vertices through every later step, and the writer turns
 * them back into targets (in float). Each must be SCALAR or VECn of finite numbers (VEC3 for POSITION, NORMAL,
 * TANGENT), in any component type (KHR_mesh_quantization allows integers, normalized or not). An accessor without
 * a bufferView is zeros (the glTF 2.0 spec, Accessors), sparse or not: exporters write a target that leaves an
 * attribute alone so. Its count is the primitive's vertex count (resurfi_scene_check_primitive). */
static resurf_status store_targets(load_ctx *c, const char *where, const resurfi_gltf_primitive *gp, resurf_mesh *m)
{
    size_t n = m->vertex_count;
    double *values = NULL;
    resurf_status status = RESURF_OK;
    for (size_t t = 0; t < gp->target_count && status == RESURF_OK; ++t)
        for (size_t i = gp->target_begin[t]; i < gp->target_begin[t + 1] && status == RESURF_OK; ++i) {
            const resurfi_gltf_named *na = &gp->target_attributes[i];
            const resurfi_gltf_accessor *a = &c->v->accessors[na->index];
            char name[sizeof m->extras[0].name];
            int vec3 = !strcmp(na->name, "POSITION") || !strcmp(na->name, "NORMAL") || !strcmp(na->name, "TANGENT");
            if (snprintf(name, sizeof name, RESURF_MORPH_TARGET_PREFIX "%zu].%s", t, na->name) >= (int)sizeof name)
                status = FAIL(c, "%s: targets[%zu]: the attribute name '%.30s...' is too long", where, t, na->name);
            else if (a->matrix || a->components < 1 || a->components > 4 || (vec3 && a->components != 3))
                status = FAIL(c, "%s: targets[%zu].%s is not %s", where, t, na->name,
                              vec3 ? "VEC3" : "SCALAR or VECn");
            if (status != RESURF_OK)
                break;
            size_t comps = (size_t)a->components;
            resurfi_free(c->alloc, values);
            if (!(values = resurfi_alloc(c->alloc, n ? n : 1, comps * sizeof *values))) {
                status = oom(c);
                break;
            }
            resurfi_scene_read_accessor(c->v, a, values);
            resurf_attribute *x = NULL;
            for (size_t k = 0; k < n * comps && status == RESURF_OK; ++k)
                if (!isfinite(values[k]) || !isfinite((float)values[k]))
                    status = FAIL(c, "%s: targets[%zu].%s of vertex %zu is not finite", where, t, na->name,
                                  k / comps);
            if (status == RESURF_OK && resurf_mesh_add_extra(m, name, (unsigned)comps, &x, NULL) != RESURF_OK)
                status = oom(c);
            for (size_t k = 0; status == RESURF_OK && k < n * comps; ++k)
                x->data[k] = (float)values[k];
        }
    resurfi_free(c->alloc, values);
    return status;
}

/* Decodes primitive (mesh_index, prim_index) into out: every check first, then the mesh of a triangle primitive. */
static resurf_status decode_primitive(load_ctx *c, size_t mesh_index, size_t prim_index, resurfi_scene_prim *out)
{
    const resurfi_gltf_view *v = c->v;
    const resurfi_gltf_primitive *gp = &v->meshes[mesh_index].primitives[prim_index];
    char where[64];
    snprintf(where, sizeof where, "meshes[%zu].primitives[%zu]", mesh_index, prim_index);
    snprintf(out->info.name, sizeof out->info.name, "%s", where);
    snprintf(out->info.mesh_name, sizeof out->info.mesh_name, "%s", v->meshes[mesh_index].name);
    out->info.mesh = mesh_index;
    out->info.primitive = prim_index;
    out->info.mode = gp->mode;
    out->info.draco = gp->draco;
    uint64_t count = 0;
    resurf_status status = resurfi_scene_check_primitive(c, gp, where, &count);
    if (status != RESURF_OK)
        return status;
    out->info.kind = gp->mode < 4 ? RESURF_PRIMITIVE_OTHER
                     : gp->target_count ? RESURF_PRIMITIVE_MORPHED
                                        : RESURF_PRIMITIVE_TRIANGLES;

    resurfi_draco_mesh *dm = NULL;
    status = decode_draco(c, gp, where, &dm);
    if (status != RESURF_OK || out->info.kind == RESURF_PRIMITIVE_OTHER) {
        resurfi_draco_mesh_free(dm);
        return status;
    }

    /* A triangle primitive: its mesh. */
    size_t position = gp->attribute_count;
    for (size_t i = 0; i < gp->attribute_count; ++i)
        if (!strcmp(gp->attributes[i].name, "POSITION"))
            position = i;
    if (position == gp->attribute_count) {
        resurfi_draco_mesh_free(dm);
        return FAIL(c, "%s: a triangle primitive without POSITION", where);
    }
    if (count > UINT32_MAX - 1) {
        resurfi_draco_mesh_free(dm);
        return resurfi_fail(c->error, RESURF_ERR_LIMIT, c->path, 0, -1, "%s: more than 2^32 - 2 vertices", where);
    }
    size_t n = (size_t)count;
    attr_values *attrs = resurfi_calloc(c->alloc, gp->attribute_count, sizeof *attrs);
    double *index_values = NULL;
    uint32_t *triangles = NULL;
    size_t triangle_count = 0, index_count = 0;
    resurf_mesh *mesh = NULL;
    if (!attrs) {
        status = oom(c);
        goto done;
    }
    for (size_t i = 0; i < gp->attribute_count; ++i) {
        attr_values *a = &attrs[i];
        a->name = gp->attributes[i].name;
        a->accessor = &v->accessors[gp->attributes[i].index];
        const resurfi_draco_attribute *da = NULL;
        int in_draco = 0;
        for (size_t k = 0; dm && k < gp->draco_attribute_count; ++k)
            if (!strcmp(gp->draco_attributes[k].name, a->name)) {
                in_draco = 1;
                for (size_t j = 0; j < dm->attribute_count; ++j)
                    if (dm->attributes[j].unique_id == gp->draco_attributes[k].index)
                        da = &dm->attributes[j];
            }
        /* Outside Draco, an accessor without a bufferView is zeros (sparse or not), as the spec says. */
        if (!da && in_draco && a->accessor->buffer_view == RESURFI_GLTF_NONE && !a->accessor->sparse)
            status = FAIL(c, "%s: %s is named by the Draco extension but not in its payload", where, a->name);
        else if (!da && a->accessor->buffer_view == RESURFI_GLTF_NONE && a->accessor->count > c->buffer_bytes + 4096)
            status = resurfi_fail(c->error, RESURF_ERR_LIMIT, c->path, 0, -1,
                                  "%s: %s claims %llu zero vertices, more than the file's size can justify", where,
                                  a->name, (unsigned long long)a->accessor->count);
        if (status != RESURF_OK)
            goto done;
        size_t comps = (size_t)a->accessor->components;
        if (!(a->values = resurfi_alloc(c->alloc, n, comps * sizeof(double)))) {
            status = oom(c);
            goto done;
        }
        if (da) {
            for (size_t k = 0; k < n * comps; ++k) {
                double x = da->values[k];
                a->values[k] = a->accessor->normalized ? normalize(x, a->accessor->component_type) : x;
            }
        } else {
            resurfi_scene_read_accessor(v, a->accessor, a->values);
        }
    }
    if (dm && dm->face_count) {
        index_count = 3 * dm->face_count;
        if (!(index_values = resurfi_alloc(c->alloc, index_count, sizeof *index_values))) {
            status = oom(c);
            goto done;
        }
        for (size_t i = 0; i < index_count; ++i)
            index_values[i] = dm->faces[i];
    } else if (gp->indices != RESURFI_GLTF_NONE) {
        const resurfi_gltf_accessor *ia = &v->accessors[gp->indices];
        if (ia->buffer_view == RESURFI_GLTF_NONE && !ia->sparse) {
            status = FAIL(c, "%s: the indices accessor has no data", where);
            goto done;
        }
        if (ia->buffer_view == RESURFI_GLTF_NONE && ia->count > c->buffer_bytes + 4096) {
            status = resurfi_fail(c->error, RESURF_ERR_LIMIT, c->path, 0, -1,
                                  "%s: the indices claim %llu zeros, more than the file's size can justify", where,
                                  (unsigned long long)ia->count);
            goto done;
        }
        index_count = (size_t)ia->count;
        if (!(index_values = resurfi_alloc(c->alloc, index_count, sizeof *index_values))) {
            status = oom(c);
            goto done;
        }
        resurfi_scene_read_accessor(v, ia, index_values);
    } else {
        index_count = n;
        if (!(index_values = resurfi_alloc(c->alloc, n, sizeof *index_values))) {
            status = oom(c);
            goto done;
        }
        for (size_t i = 0; i < n; ++i)
            index_values[i] = (double)i;
    }
    status = build_triangles(c, where, gp->mode, index_values, index_count, n, &triangles, &triangle_count);
    if (status != RESURF_OK)
        goto done;
    c->triangles += triangle_count;
    if (c->max_triangles && c->triangles > c->max_triangles) {
        status = resurfi_fail(c->error, RESURF_ERR_LIMIT, c->path, 0, -1,
                              "more than %zu triangles (the max_triangles limit)", c->max_triangles);
        goto done;
    }
    if (resurf_mesh_create_with(n, triangle_count, 0, c->alloc, &mesh, NULL) != RESURF_OK) {
        status = oom(c);
        goto done;
    }
    memcpy(mesh->indices, triangles, triangle_count * 3 * sizeof *triangles);
    if (!(out->formats = resurfi_calloc(c->alloc, gp->attribute_count, sizeof *out->formats))) {
        status = oom(c);
        goto done;
    }
    /* POSITION first, then the texture coordinate sets in order (so TEXCOORD_1 never lands before TEXCOORD_0),
     * then everything else. */
    for (int pass = 0; pass < 3 && status == RESURF_OK; ++pass)
        for (size_t i = 0; i < gp->attribute_count && status == RESURF_OK; ++i) {
            int is_pos = i == position, is_tex = !strncmp(attrs[i].name, "TEXCOORD_", 9);
            if ((pass == 0) != is_pos || (pass == 1) != (is_tex && !is_pos))
                continue;
            status = store_attribute(c, where, mesh, &attrs[i]);
            resurfi_scene_format *f = &out->formats[out->format_count++];
            snprintf(f->name, sizeof f->name, "%s", attrs[i].name);
            f->component_type = attrs[i].accessor->component_type;
            f->normalized = attrs[i].accessor->normalized;
            f->components = attrs[i].accessor->components;
        }
    if (status == RESURF_OK)
        status = store_targets(c, where, gp, mesh);
    if (status == RESURF_OK) {
        out->mesh = mesh;
        mesh = NULL;
    }
done:
    if (attrs)
        for (size_t i = 0; i < gp->attribute_count; ++i)
            resurfi_free(c->alloc, attrs[i].values);
    resurfi_free(c->alloc, attrs);
    resurfi_free(c->alloc, index_values);
    resurfi_free(c->alloc, triangles);
    resurf_mesh_free(mesh);
    resurfi_draco_mesh_free(dm);
    return status;
}

/* Everything about a parsed document, then its primitives. */
static resurf_status build_scene(load_ctx *c, resurfi_gltf_doc *doc, resurf_scene **out)
{
    const resurfi_gltf_view *v = resurfi_gltf_doc_view(doc);
    c->v = v;
    resurf_status status = resurfi_scene_check_document(c);
    if (status != RESURF_OK)
        return status;
    size_t prim_count = 0;
    for (size_t m = 0; m < v->mesh_count; ++m)
        prim_count += v->meshes[m].primitive_count;
    resurf_scene *s = scene_new(c->alloc, v->mesh_count, prim_count);
    if (!s)
        return oom(c);
    s->view = v;
    for (size_t i = 0; i < v->extension_used_count; ++i) {
        if (!strcmp(v->extensions_used[i], "KHR_mesh_quantization"))
            s->quantized = 1;
    }
    status = resurfi_scene_check_nodes(c, s);
    size_t k = 0;
    for (size_t m = 0; m < v->mesh_count && status == RESURF_OK; ++m) {
        s->mesh_first[m] = k;
        size_t instances = 0;
        for (size_t n = 0; n < v->node_count; ++n)
            if (v->nodes[n].mesh == (long long)m)
                instances += resurfi_scene_node_instances(s, n);
        for (size_t p = 0; p < v->meshes[m].primitive_count && status == RESURF_OK; ++p, ++k) {
            s->prims[k].info.instances = instances;
            status = decode_primitive(c, m, p, &s->prims[k]);
            if (status == RESURF_OK &&
                resurfi_progress(c->progress, RESURF_STAGE_LOAD, (double)(k + 1) / (double)(prim_count + 1)))
                status = resurfi_fail(c->error, RESURF_ERR_CANCELLED, c->path, 0, -1, "cancelled by the progress callback");
        }
    }
    s->mesh_first[v->mesh_count] = prim_count;
    for (size_t i = 0; i < v->warning_count && status == RESURF_OK; ++i)
        if (resurfi_scene_add_warning(s, v->warnings[i]) != RESURF_OK)
            status = oom(c);
    s->unknown_extensions = status == RESURF_OK && resurfi_scene_unknown_references(s);
    if (status == RESURF_OK && resurfi_scene_warn_dropped_extensions(s) != RESURF_OK)
        status = oom(c);
    if (status != RESURF_OK) {
        resurf_scene_free(s);
        return status;
    }
    s->doc = doc;
    *out = s;
    return RESURF_OK;
}

/* A .drc file: one mesh (POSITION, NORMAL, TEX_COORD, COLOR; other attributes as extras "_GENERICk"). */
static resurf_status load_drc(const unsigned char *data, size_t size, load_ctx *c, resurf_scene **out)
{
    resurfi_draco_mesh *dm = NULL;
    resurf_error derr;
    resurf_status status = resurfi_draco_decode(data, size, &dm, &derr);
    if (status != RESURF_OK)
        return resurfi_fail(c->error, status, c->path, 0, -1, "%s", derr.message);
    resurf_mesh *m = NULL;
    if (dm->face_count == 0)
        status = resurfi_fail(c->error, RESURF_ERR_UNSUPPORTED, c->path, 0, -1, "the Draco data is a point cloud");
    else if (c->max_triangles && dm->face_count > c->max_triangles)
        status = resurfi_fail(c->error, RESURF_ERR_LIMIT, c->path, 0, -1,
                              "more than %zu triangles (the max_triangles limit)", c->max_triangles);
    else if (resurf_mesh_create_with(dm->point_count, dm->face_count, 0, c->alloc, &m, NULL) != RESURF_OK)
        status = oom(c);
    size_t n = dm->point_count, generic = 0;
    int has_position = 0;
    for (size_t i = 0; i < dm->attribute_count && status == RESURF_OK; ++i) {
        const resurfi_draco_attribute *a = &dm->attributes[i];
        size_t comps = (size_t)a->components;
        double scale = a->integer && a->type != RESURFI_DRACO_GENERIC ? a->integer_max : 1.0;
        double *dst = NULL;
        if (a->type == RESURFI_DRACO_POSITION && comps == 3 && !has_position) {
            dst = m->positions;
            has_position = 1;
            scale = 1.0;
        } else if (a->type == RESURFI_DRACO_NORMAL && comps == 3 && !m->normals) {
            dst = m->normals = resurfi_alloc(&m->allocator, n, 3 * sizeof(double));
        } else if (a->type == RESURFI_DRACO_TEX_COORD && comps == 2 && m->texcoord_count < RESURF_MAX_TEXCOORD_SETS) {
            dst = m->texcoords[m->texcoord_count++] = resurfi_alloc(&m->allocator, n, 2 * sizeof(double));
        } else if (a->type == RESURFI_DRACO_COLOR && (comps == 3 || comps == 4) && !m->colors) {
            if ((m->colors = resurfi_alloc(&m->allocator, n, 4 * sizeof(double))))
                for (size_t v = 0; v < n; ++v)
                    for (size_t k = 0; k < 4; ++k)
                        m->colors[4 * v + k] = k < comps ? a->values[comps * v + k] / scale : 1.0;
            m->color_components = (unsigned)comps;
            if (!m->colors)
                status = oom(c);
            continue;
        } else if (comps <= 16) {
            char name[32];
            snprintf(name, sizeof name, "_GENERIC%zu", generic++);
            resurf_attribute *x = NULL;
            if (resurf_mesh_add_extra(m, name, (unsigned)comps, &x, NULL) != RESURF_OK)
                status = oom(c);
            else
                for (size_t k = 0; k < n * comps; ++k)
                    x->data[k] = (float)a->values[k];
            continue;
        } else {
            continue;
        }
        if (!dst) {
            status = oom(c);
            break;
        }
        for (size_t k = 0; k < n * comps; ++k) {
            dst[k] = a->values[k] / scale;
            if (!isfinite(dst[k]))
                status = FAIL(c, "the Draco data has a non-finite value in attribute %d", a->unique_id);
        }
    }
    if (status == RESURF_OK && !has_position)
        status = FAIL(c, "the Draco data has no POSITION attribute");
    if (status == RESURF_OK)
        for (size_t i = 0; i < 3 * dm->face_count; ++i)
            m->indices[i] = dm->faces[i];
    resurfi_draco_mesh_free(dm);
    if (status != RESURF_OK) {
        resurf_mesh_free(m);
        return status;
    }
    return scene_of_mesh(m, out, c->error);
}

/* ---- public calls -------------------------------------------------------------------------------------------- */

resurf_status resurf_scene_from_mesh(const resurf_mesh *mesh, resurf_scene **out_scene, resurf_error *error)
{
    if (!mesh || !out_scene)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "mesh or out_scene is NULL");
    *out_scene = NULL;
    resurf_mesh *copy = NULL;
    resurf_status status = resurf_mesh_clone(mesh, &copy, error);
    if (status != RESURF_OK)
        return status;
    status = scene_of_mesh(copy, out_scene, error);
    if (status == RESURF_OK)
        resurfi_clear_error(error);
    return status;
}

/* What a scene source holds. */
typedef enum scene_kind { KIND_MESH, KIND_GLTF, KIND_GLB, KIND_DRC } scene_kind;

/* glTF and Draco by their first bytes; anything else is taken for a mesh file. */
static scene_kind kind_of_content(const unsigned char *head, size_t got)
{
    size_t i = 0;
    while (i < got && (head[i] == ' ' || head[i] == '\n' || head[i] == '\r' || head[i] == '\t'))
        ++i;
    if (got >= 4 && !memcmp(head, "glTF", 4))
        return KIND_GLB;
    if (got >= 5 && !memcmp(head, "DRACO", 5))
        return KIND_DRC;
    if (i < got && head[i] == '{')
        return KIND_GLTF;
    return KIND_MESH;
}

/* Loads a glTF (.gltf, .glb) or Draco document from bytes, for resurf_scene_load() and resurf_scene_load_memory().
 * dir: the folder external buffers are read from, or NULL for a document in memory, which may refer to none;
 * path: the source for messages (NULL in memory). */
static resurf_status load_document(const unsigned char *data, size_t size, scene_kind kind, const char *dir,
                                   const char *path, const resurf_load_options *opts, resurf_scene **out_scene,
                                   resurf_error *error)
{
    resurf_status status = RESURF_OK;
    load_ctx c = {.path = path, .error = error, .max_triangles = opts->max_triangles, .progress = &opts->progress,
                  .alloc = opts->allocator};
    if (kind == KIND_DRC)
        return load_drc(data, size, &c, out_scene);

    /* The JSON, and a .glb's BIN chunk (glTF 2.0 4.4: header, then chunks of length, type and data). */
    const char *json = (const char *)data;
    size_t json_size = size, json_offset = 0;
    const unsigned char *bin = NULL;
    size_t bin_size = 0;
    if (kind == KIND_GLB) {
        if (size < 20 || memcmp(data, "glTF", 4))
            status = resurfi_fail(error, RESURF_ERR_PARSE, path, 0, 0, "not a .glb file (no glTF header)");
        else if (resurfi_get_u32le(data + 4) != 2)
            status = resurfi_fail(error, RESURF_ERR_UNSUPPORTED, path, 0, 4, "glTF binary version %u (resurf reads 2)",
                                  resurfi_get_u32le(data + 4));
        else if (resurfi_get_u32le(data + 8) > size || resurfi_get_u32le(data + 8) < 20)
            status = resurfi_fail(error, RESURF_ERR_PARSE, path, 0, 8, "the header says %u bytes, the file has %zu",
                                  resurfi_get_u32le(data + 8), size);
        else {
            size_t total = resurfi_get_u32le(data + 8), length = resurfi_get_u32le(data + 12);
            if (resurfi_get_u32le(data + 16) != 0x4E4F534Au)
                status = resurfi_fail(error, RESURF_ERR_PARSE, path, 0, 16, "the first chunk is not JSON");
            else if (length > total - 20)
                status = resurfi_fail(error, RESURF_ERR_PARSE, path, 0, 12, "the JSON chunk (%zu bytes) runs past the end",
                                      length);
            else {
                json = (const char *)data + 20;
                json_size = length;
                json_offset = 20;
                size_t at = 20 + ((length + 3) & ~(size_t)3);
                if (at + 8 <= total && resurfi_get_u32le(data + at + 4) == 0x004E4942u) {
                    size_t bin_length = resurfi_get_u32le(data + at);
                    if (bin_length > total - at - 8)
                        status = resurfi_fail(error, RESURF_ERR_PARSE, path, 0, (long long)at,
                                              "the BIN chunk (%zu bytes) runs past the end", bin_length);
                    bin = data + at + 8;
                    bin_size = bin_length;
                }
            }
        }
    }
    long long deep = status == RESURF_OK ? resurfi_json_too_deep(json, json_size) : -1;
    if (deep >= 0)
        status = resurfi_fail(error, RESURF_ERR_PARSE, path, 0, deep + (long long)json_offset,
                              "the JSON nests deeper than %d levels", RESURFI_MAX_JSON_DEPTH);
    resurfi_gltf_doc *doc = NULL;
    if (status == RESURF_OK) {
        status = resurfi_gltf_parse(json, json_size, bin, bin_size, kind == KIND_GLB, dir, path, (uint64_t)1 << 32,
                                    opts->lenient, &doc, error);
        if (status != RESURF_OK && error && error->offset >= 0)
            error->offset += (long long)json_offset;
    }
    if (status == RESURF_OK) {
        status = build_scene(&c, doc, out_scene);
        if (status != RESURF_OK)
            resurfi_gltf_doc_free(doc);
    }
    if (status == RESURF_OK) {
        status = resurfi_scene_load_images(*out_scene, dir, path, opts->allow_missing_images, error);
        if (status != RESURF_OK) {
            resurf_scene_free(*out_scene);
            *out_scene = NULL;
        }
    }
    /* Messages quote names from the document (extensions, attributes, JSON keys), which JSON escapes may fill
     * with line breaks and other control characters: the message stays one printable line. */
    if (status != RESURF_OK && error)
        for (char *m = error->message; *m; ++m)
            if ((unsigned char)*m < 0x20 || *m == 0x7f)
                *m = '?';
    return status;
}

resurf_status resurf_scene_load(const char *path, const resurf_load_options *options, resurf_scene **out_scene,
                                resurf_error *error)
{
    if (!path || !out_scene)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "path or out_scene is NULL");
    *out_scene = NULL;
    RESURFI_CHECK_OPTIONS_ALLOC(options, resurf_load_options, error);
    resurf_load_options opts = options ? *options : resurf_load_options_default();
    if ((unsigned)opts.format >= RESURF_FORMAT_COUNT)
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "unknown format %d", (int)opts.format);

    scene_kind kind = KIND_MESH;
    if (opts.format == RESURF_FORMAT_AUTO) {
        if (resurfi_ends_with_nocase(path, ".gltf"))
            kind = KIND_GLTF;
        else if (resurfi_ends_with_nocase(path, ".glb"))
            kind = KIND_GLB;
        else if (resurfi_ends_with_nocase(path, ".drc"))
            kind = KIND_DRC;
        else if (resurf_format_from_path(path) == RESURF_FORMAT_AUTO) {
            /* No known extension: glTF and Draco by their first bytes, anything else as a mesh file. */
            unsigned char head[8] = {0};
            FILE *f = fopen(path, "rb");
            size_t got = f ? fread(head, 1, sizeof head, f) : 0;
            if (f)
                fclose(f);
            kind = kind_of_content(head, got);
        }
    }
    if (kind == KIND_MESH) {
        resurf_mesh *mesh = NULL;
        resurf_status status = resurf_mesh_load(path, &opts, &mesh, error);
        if (status == RESURF_OK)
            status = scene_of_mesh(mesh, out_scene, error);
        return status;
    }

    char *bytes = NULL;
    size_t size = 0;
    resurf_status status =
        resurfi_read_file(opts.allocator, path, (uint64_t)1 << 32, opts.max_triangles, &opts.progress, &bytes, &size,
                          error);
    if (status != RESURF_OK)
        return status;
    unsigned char *data = (unsigned char *)bytes;
    /* External files are relative to the document's folder. */
    const char *slash = strrchr(path, '/');
    size_t dir_len = slash ? (size_t)(slash - path) + 1 : 0;
    char *dir = resurfi_alloc(opts.allocator, dir_len + 1, 1);
    if (!dir) {
        status = resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    } else {
        memcpy(dir, path, dir_len);
        dir[dir_len] = 0;
        status = load_document(data, size, kind, dir, path, &opts, out_scene, error);
        resurfi_free(opts.allocator, dir);
    }
    resurfi_free(opts.allocator, data);
    if (status == RESURF_OK)
        resurfi_clear_error(error);
    return status;
}

resurf_status resurf_scene_load_memory(const void *data, size_t size, resurf_scene_format format,
                                       const resurf_load_options *options, resurf_scene **out_scene,
                                       resurf_error *error)
{
    if (!out_scene || (!data && size))
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "data or out_scene is NULL");
    *out_scene = NULL;
    RESURFI_CHECK_OPTIONS_ALLOC(options, resurf_load_options, error);
    resurf_load_options opts = options ? *options : resurf_load_options_default();
    if ((unsigned)format >= RESURF_SCENE_FORMAT_COUNT)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "unknown scene format %d", (int)format);
    if ((unsigned)opts.format >= RESURF_FORMAT_COUNT)
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "unknown format %d", (int)opts.format);
    static const unsigned char nothing[1] = {0};
    const unsigned char *bytes = size ? data : nothing;
    scene_kind kind = format == RESURF_SCENE_FORMAT_GLTF  ? KIND_GLTF
                      : format == RESURF_SCENE_FORMAT_GLB ? KIND_GLB
                      : format == RESURF_SCENE_FORMAT_DRC ? KIND_DRC
                      : format == RESURF_SCENE_FORMAT_MESH || opts.format != RESURF_FORMAT_AUTO
                          ? KIND_MESH
                          : kind_of_content(bytes, size < 8 ? size : 8);
    resurf_status status;
    if (kind == KIND_MESH) {
        resurf_mesh *mesh = NULL;
        status = resurf_mesh_load_memory(bytes, size, RESURF_FORMAT_AUTO, NULL, &opts, &mesh, error);
        if (status == RESURF_OK)
            status = scene_of_mesh(mesh, out_scene, error);
        return status;
    }
    status = load_document(bytes, size, kind, NULL, NULL, &opts, out_scene, error);
    if (status == RESURF_OK)
        resurfi_clear_error(error);
    return status;
}

size_t resurf_scene_mesh_count(const resurf_scene *scene) { return scene ? scene->mesh_count : 0; }

size_t resurf_scene_primitive_count(const resurf_scene *scene) { return scene ? scene->prim_count : 0; }

resurf_status resurf_scene_primitive_info(const resurf_scene *scene, size_t index, resurf_scene_primitive *out,
                                          resurf_error *error)
{
    if (!scene || !out)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "scene or out is NULL");
    if (index >= scene->prim_count)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "primitive %zu of %zu", index, scene->prim_count);
    *out = scene->prims[index].info;
    out->lod_count = scene->prims[index].lod_count;
    return RESURF_OK;
}

const resurf_mesh *resurf_scene_primitive_mesh(const resurf_scene *scene, size_t index)
{
    return scene && index < scene->prim_count ? scene->prims[index].mesh : NULL;
}

/* Can a level stand in for the primitive's mesh? Indices in range, finite positions, the same attributes. */
static resurf_status check_level(const resurfi_scene_prim *p, const resurf_mesh *m, size_t level, resurf_error *error)
{
    const char *name = p->info.name;
    if (!m || (m->vertex_count && !m->positions) || (m->triangle_count && !m->indices))
        return resurfi_error(error, RESURF_ERR_INVALID_MESH, "%s: level %zu is NULL or has no data", name, level);
    if (m->vertex_count > UINT32_MAX - 1 || m->triangle_count > UINT32_MAX)
        return resurfi_error(error, RESURF_ERR_INVALID_MESH, "%s: level %zu is too large", name, level);
    for (size_t i = 0; i < 3 * m->triangle_count; ++i)
        if (m->indices[i] >= m->vertex_count)
            return resurfi_error(error, RESURF_ERR_INVALID_MESH, "%s: level %zu: triangle %zu refers to vertex %u of %zu",
                                 name, level, i / 3, m->indices[i], m->vertex_count);
    for (size_t i = 0; i < 3 * m->vertex_count; ++i)
        if (!isfinite(m->positions[i]))
            return resurfi_error(error, RESURF_ERR_INVALID_MESH, "%s: level %zu: vertex %zu is not finite", name, level,
                                 i / 3);
    const resurf_mesh *src = p->mesh;
    if (!!src->normals != !!m->normals || src->texcoord_count != m->texcoord_count || !!src->colors != !!m->colors)
        return resurfi_error(error, RESURF_ERR_INVALID_MESH,
                             "%s: level %zu does not carry the same normals, texcoords and colors as the primitive",
                             name, level);
    for (unsigned k = 0; k < m->texcoord_count; ++k)
        if (!m->texcoords[k])
            return resurfi_error(error, RESURF_ERR_INVALID_MESH, "%s: level %zu lacks texcoord set %u", name, level, k);
    for (size_t i = 0; i < src->extra_count; ++i) {
        size_t k = 0;
        while (k < m->extra_count && strcmp(m->extras[k].name, src->extras[i].name))
            ++k;
        if (k == m->extra_count || m->extras[k].components != src->extras[i].components || !m->extras[k].data)
            return resurfi_error(error, RESURF_ERR_INVALID_MESH, "%s: level %zu lacks the attribute %s", name, level,
                                 src->extras[i].name);
    }
    return RESURF_OK;
}

resurf_status resurf_scene_set_lods(resurf_scene *scene, size_t index, const resurf_mesh *const *lods,
                                    size_t lod_count, resurf_error *error)
{
    if (!scene || (lod_count && !lods))
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "scene or lods is NULL");
    if (index >= scene->prim_count)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "primitive %zu of %zu", index, scene->prim_count);
    if (lod_count > RESURF_SCENE_MAX_LEVELS - 1)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "%zu levels of detail (at most %d)", lod_count,
                             RESURF_SCENE_MAX_LEVELS - 1);
    resurfi_scene_prim *p = &scene->prims[index];
    if (p->info.kind == RESURF_PRIMITIVE_OTHER)
        return resurfi_error(error, RESURF_ERR_UNSUPPORTED, "%s is not made of triangles: it stays as it is",
                             p->info.name);
    for (size_t k = 0; k < lod_count; ++k) {
        resurf_status status = check_level(p, lods[k], k + 1, error);
        if (status != RESURF_OK)
            return status;
    }
    const resurf_allocator *alloc = &scene->alloc;
    resurf_mesh **copies = lod_count ? resurfi_calloc(alloc, lod_count, sizeof *copies) : NULL;
    if (lod_count && !copies)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory copying levels of detail");
    for (size_t k = 0; k < lod_count; ++k) {
        resurf_status status = resurf_mesh_clone_with(lods[k], alloc, &copies[k], error);
        if (status != RESURF_OK) {
            for (size_t j = 0; j < k; ++j)
                resurf_mesh_free(copies[j]);
            resurfi_free(alloc, copies);
            return status;
        }
    }
    for (size_t k = 0; k < p->lod_count; ++k)
        resurf_mesh_free(p->lods[k]);
    resurfi_free(alloc, p->lods);
    p->lods = copies;
    p->lod_count = lod_count;
    resurfi_clear_error(error);
    return RESURF_OK;
}

resurf_status resurf_scene_set_screen_coverage(resurf_scene *scene, size_t mesh, const double *coverage,
                                               size_t count, resurf_error *error)
{
    if (!scene || (count && !coverage))
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "scene or coverage is NULL");
    if (mesh >= scene->mesh_count)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "mesh %zu of %zu", mesh, scene->mesh_count);
    if (count > RESURF_SCENE_MAX_LEVELS)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "%zu coverage values (at most %d)", count,
                             RESURF_SCENE_MAX_LEVELS);
    for (size_t k = 0; k < count; ++k)
        if (!(coverage[k] >= 0 && coverage[k] <= 1) || (k && coverage[k] > coverage[k - 1]))
            return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT,
                                 "coverage[%zu] = %g: values must lie in [0, 1] and never increase", k, coverage[k]);
    double *copy = NULL;
    if (count) {
        if (!(copy = resurfi_alloc(&scene->alloc, count, sizeof *copy)))
            return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
        memcpy(copy, coverage, count * sizeof *copy);
    }
    resurfi_free(&scene->alloc, scene->coverage[mesh]);
    scene->coverage[mesh] = copy;
    scene->coverage_count[mesh] = count;
    resurfi_clear_error(error);
    return RESURF_OK;
}

size_t resurf_scene_warning_count(const resurf_scene *scene) { return scene ? scene->warning_count : 0; }

const char *resurf_scene_warning(const resurf_scene *scene, size_t index)
{
    return scene && index < scene->warning_count ? scene->warnings[index] : NULL;
}
