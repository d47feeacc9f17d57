/* Checking a glTF document before anything is read through an index from the file (scene.c decodes it
 * afterwards): the JSON's depth, every bufferView and accessor against its buffer (sparse storage included), the
 * node graph, each primitive's mode, accessors and Draco references. Follows glTF 2.0 (3.6 binary data, 3.7
 * geometry, 3.11 sparse accessors) and KHR_draco_mesh_compression; every message names the element at fault. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_internal.h"

/* ---- the JSON ------------------------------------------------------------------------------------------------ */

long long resurfi_json_too_deep(const char *p, size_t size)
{
    int depth = 0, in_string = 0;
    for (size_t i = 0; i < size; ++i) {
        char c = p[i];
        if (in_string) {
            if (c == '\\')
                ++i;
            else if (c == '"')
                in_string = 0;
        } else if (c == '"') {
            in_string = 1;
        } else if (c == '[' || c == '{') {
            if (++depth > RESURFI_MAX_JSON_DEPTH)
                return (long long)i;
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return -1;
}

/* ---- buffers and accessors ----------------------------------------------------------------------------------- */

/* Does [offset, offset + count × stride − stride + size) fit in length? (count >= 1; no overflow) */
static int range_fits(uint64_t offset, uint64_t count, uint64_t stride, uint64_t size, uint64_t length)
{
    if (offset > length || size > length - offset)
        return 0;
    if (count <= 1)
        return 1;
    uint64_t room = length - offset - size;
    return stride == 0 || count - 1 <= room / stride;
}

static resurf_status check_buffer_views(load_ctx *c)
{
    const resurfi_gltf_view *v = c->v;
    for (size_t i = 0; i < v->buffer_view_count; ++i) {
        const resurfi_gltf_buffer_view *bv = &v->buffer_views[i];
        if (bv->buffer < 0 || (size_t)bv->buffer >= v->buffer_count)
            return FAIL(c, "bufferViews[%zu]: buffer %lld does not exist (%zu buffers)", i, bv->buffer,
                        v->buffer_count);
        size_t size = v->buffers[bv->buffer].size;
        if (!range_fits(bv->byte_offset, 1, 0, bv->byte_length, size))
            return FAIL(c, "bufferViews[%zu]: bytes %llu..%llu lie past the end of buffers[%lld] (%zu bytes)", i,
                        (unsigned long long)bv->byte_offset,
                        (unsigned long long)(bv->byte_offset + bv->byte_length), bv->buffer, size);
        if (bv->byte_stride && (bv->byte_stride < 4 || bv->byte_stride > 252 || bv->byte_stride % 4))
            return FAIL(c, "bufferViews[%zu]: byteStride %llu is not a multiple of 4 in 4..252", i,
                        (unsigned long long)bv->byte_stride);
    }
    return RESURF_OK;
}

/* The checks every accessor passes, used or not (the writer may copy any of them). Sparse indices are read to
 * check that they increase and stay below count. */
static resurf_status check_accessor(load_ctx *c, size_t i)
{
    const resurfi_gltf_view *v = c->v;
    const resurfi_gltf_accessor *a = &v->accessors[i];
    resurfi_gltf_element e = resurfi_gltf_element_of(a);
    if (e.component_size == 0)
        return FAIL(c, "accessors[%zu]: unknown componentType %d", i, a->component_type);
    if (a->components == 0)
        return FAIL(c, "accessors[%zu]: unknown type", i);
    if (a->normalized && (a->component_type == RESURFI_GLTF_FLOAT || a->component_type == RESURFI_GLTF_UNSIGNED_INT))
        return FAIL(c, "accessors[%zu]: normalized is not allowed for componentType %d", i, a->component_type);
    if (a->count < 1)
        return FAIL(c, "accessors[%zu]: count is 0", i);
    if (a->buffer_view != RESURFI_GLTF_NONE) {
        if (a->buffer_view < 0 || (size_t)a->buffer_view >= v->buffer_view_count)
            return FAIL(c, "accessors[%zu]: bufferView %lld does not exist (%zu bufferViews)", i, a->buffer_view,
                        v->buffer_view_count);
        const resurfi_gltf_buffer_view *bv = &v->buffer_views[a->buffer_view];
        uint64_t stride = bv->byte_stride ? bv->byte_stride : e.size;
        if (stride < e.size)
            return FAIL(c, "accessors[%zu]: byteStride %llu of bufferViews[%lld] is shorter than an element (%zu)", i,
                        (unsigned long long)stride, a->buffer_view, e.size);
        if ((a->byte_offset % e.component_size) || ((bv->byte_offset + a->byte_offset) % e.component_size))
            return FAIL(c, "accessors[%zu]: byteOffset %llu is not aligned to its %zu-byte components", i,
                        (unsigned long long)a->byte_offset, e.component_size);
        if (!range_fits(a->byte_offset, a->count, stride, e.size, bv->byte_length))
            return FAIL(c, "accessors[%zu]: %llu elements from byte %llu do not fit in bufferViews[%lld] (%llu bytes)",
                        i, (unsigned long long)a->count, (unsigned long long)a->byte_offset, a->buffer_view,
                        (unsigned long long)bv->byte_length);
    }
    if (!a->sparse)
        return RESURF_OK;
    if (a->sparse_count < 1 || (uint64_t)a->sparse_count > a->count)
        return FAIL(c, "accessors[%zu]: sparse count %lld is not in 1..%llu", i, a->sparse_count,
                    (unsigned long long)a->count);
    size_t isize = resurfi_gltf_component_size(a->sparse_indices_type);
    if (a->sparse_indices_type != RESURFI_GLTF_UNSIGNED_BYTE && a->sparse_indices_type != RESURFI_GLTF_UNSIGNED_SHORT &&
        a->sparse_indices_type != RESURFI_GLTF_UNSIGNED_INT)
        return FAIL(c, "accessors[%zu]: sparse indices have componentType %d (not an unsigned integer)", i,
                    a->sparse_indices_type);
    long long views[2] = {a->sparse_indices_view, a->sparse_values_view};
    long long offsets[2] = {a->sparse_indices_offset, a->sparse_values_offset};
    size_t sizes[2] = {isize, e.size};
    for (int k = 0; k < 2; ++k) {
        const char *what = k ? "values" : "indices";
        if (views[k] < 0 || (size_t)views[k] >= v->buffer_view_count)
            return FAIL(c, "accessors[%zu]: sparse %s bufferView %lld does not exist", i, what, views[k]);
        if (offsets[k] < 0 || !range_fits((uint64_t)offsets[k], (uint64_t)a->sparse_count, sizes[k], sizes[k],
                                          v->buffer_views[views[k]].byte_length))
            return FAIL(c, "accessors[%zu]: %lld sparse %s do not fit in bufferViews[%lld]", i, a->sparse_count,
                        what, views[k]);
        if (((uint64_t)offsets[k] + v->buffer_views[views[k]].byte_offset) % (k ? e.component_size : isize))
            return FAIL(c, "accessors[%zu]: sparse %s are not aligned", i, what);
    }
    const resurfi_gltf_buffer_view *iv = &v->buffer_views[a->sparse_indices_view];
    const unsigned char *p = v->buffers[iv->buffer].data + iv->byte_offset + a->sparse_indices_offset;
    double previous = -1;
    for (long long k = 0; k < a->sparse_count; ++k) {
        double index = resurfi_gltf_read_component(p + (size_t)k * isize, a->sparse_indices_type);
        if (index <= previous || index >= (double)a->count)
            return FAIL(c, "accessors[%zu]: sparse index %lld is %.0f (indices must increase and stay below %llu)",
                        i, k, index, (unsigned long long)a->count);
        previous = index;
    }
    return RESURF_OK;
}

resurf_status resurfi_scene_check_document(load_ctx *c)
{
    const resurfi_gltf_view *v = c->v;
    if (v->nonfinite_count)
        return FAIL(c, "%zu numbers of the JSON are not finite (the first at %s)", v->nonfinite_count,
                    v->first_nonfinite);
    for (size_t i = 0; i < v->buffer_count; ++i)
        c->buffer_bytes += v->buffers[i].size;
    resurf_status status = check_buffer_views(c);
    for (size_t i = 0; i < v->accessor_count && status == RESURF_OK; ++i)
        status = check_accessor(c, i);
    /* Only a document that breaks the schema, read leniently, gets here with one: nothing could write it back. */
    for (size_t i = 0; i < v->mesh_count && status == RESURF_OK; ++i)
        if (v->meshes[i].primitive_count == 0)
            status = FAIL(c, "meshes[%zu] has no primitives (glTF requires at least one)", i);
    for (size_t i = 0; i < v->ref_count && status == RESURF_OK; ++i)
        if (v->refs[i].index == RESURFI_GLTF_BAD)
            status = FAIL(c, "%s: not an index (a whole number is required)", v->refs[i].where);
        else if (v->refs[i].index < 0 || (uint64_t)v->refs[i].index >= v->refs[i].limit)
            status = FAIL(c, "%s: %lld does not exist (%zu to choose from)", v->refs[i].where, v->refs[i].index,
                          v->refs[i].limit);
    return status;
}

/* ---- extensions and nodes ------------------------------------------------------------------------------------ */

/* Local transform of a node, column-major: its matrix, or T · R · S. */
static void node_local(const resurfi_gltf_node *n, double m[16])
{
    if (n->matrix_count == 16) {
        memcpy(m, n->matrix, sizeof n->matrix);
        return;
    }
    double t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
    if (n->translation_count == 3)
        memcpy(t, n->translation, sizeof t);
    if (n->rotation_count == 4)
        memcpy(q, n->rotation, sizeof q);
    if (n->scale_count == 3)
        memcpy(s, n->scale, sizeof s);
    double x = q[0], y = q[1], z = q[2], w = q[3];
    double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
                   2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                   2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y)};
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row)
            m[4 * col + row] = r[3 * col + row] * s[col];
    m[3] = m[7] = m[11] = 0;
    m[12] = t[0], m[13] = t[1], m[14] = t[2], m[15] = 1;
}

static void mat_mul(const double a[16], const double b[16], double out[16])
{
    double r[16];
    for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 4; ++row) {
            double x = 0;
            for (int k = 0; k < 4; ++k)
                x += a[4 * k + row] * b[4 * col + k];
            r[4 * col + row] = x;
        }
    memcpy(out, r, sizeof r);
}

size_t resurfi_scene_node_instances(const resurf_scene *s, size_t n)
{
    size_t count = s->instance_first ? s->instance_first[n + 1] - s->instance_first[n] : 0;
    return count ? count : 1;
}

const double *resurfi_scene_instance_world(const resurf_scene *s, size_t n, size_t j)
{
    int instanced = s->instance_first && s->instance_first[n + 1] > s->instance_first[n];
    return instanced ? s->instance_world[s->instance_first[n] + j] : s->world[n];
}

/* How many instances a node's EXT_mesh_gpu_instancing draws (its attributes' count), 0 without the extension. */
static size_t instances_of(const resurfi_gltf_view *v, const resurfi_gltf_node *node)
{
    for (int k = 0; k < 3 && node->has_instances && node->mesh >= 0; ++k)
        if (node->instance_attributes[k] != RESURFI_GLTF_NONE)
            return (size_t)v->accessors[node->instance_attributes[k]].count;
    return 0;
}

/* EXT_mesh_gpu_instancing: node n draws its mesh once per instance, at its world matrix times the instance's
 * T · R · S. The attributes are checked (shape, one count, finite values), then read into s->instance_world. */
static resurf_status read_instances(load_ctx *c, resurf_scene *s)
{
    static const char *const trs[3] = {"TRANSLATION", "ROTATION", "SCALE"};
    static const int components[3] = {3, 4, 3};
    const resurfi_gltf_view *v = c->v;
    size_t n = v->node_count, total = 0;
    for (size_t i = 0; i < n; ++i) {
        const resurfi_gltf_node *node = &v->nodes[i];
        uint64_t count = 0;
        for (int k = 0; k < 3 && node->has_instances && node->mesh >= 0; ++k) {
            long long id = node->instance_attributes[k];
            if (id == RESURFI_GLTF_NONE)
                continue;
            const resurfi_gltf_accessor *a = &v->accessors[id]; /* in range: a checked reference */
            if (a->matrix || a->components != components[k])
                return FAIL(c, "nodes[%zu].extensions.EXT_mesh_gpu_instancing.attributes.%s: not a VEC%d", i,
                            trs[k], components[k]);
            if (count && a->count != count)
                return FAIL(c, "nodes[%zu].extensions.EXT_mesh_gpu_instancing: its attributes count %llu and %llu "
                            "instances", i, (unsigned long long)count, (unsigned long long)a->count);
            if (a->buffer_view == RESURFI_GLTF_NONE && a->count > c->buffer_bytes + 4096)
                return resurfi_fail(c->error, RESURF_ERR_LIMIT, c->path, 0, -1,
                                    "nodes[%zu].extensions.EXT_mesh_gpu_instancing: %llu zero instances, more than "
                                    "the file's size can justify", i, (unsigned long long)a->count);
            count = a->count;
        }
        total += instances_of(v, node);
    }
    if (total == 0)
        return RESURF_OK;
    s->instance_first = resurfi_alloc(&s->alloc, n + 1, sizeof *s->instance_first);
    s->instance_world = resurfi_alloc(&s->alloc, total, sizeof *s->instance_world);
    double *values = resurfi_alloc(c->alloc, total, 4 * sizeof *values); /* one attribute of one node */
    if (!s->instance_first || !s->instance_world || !values) {
        resurfi_free(c->alloc, values);
        return resurfi_fail(c->error, RESURF_ERR_OUT_OF_MEMORY, c->path, 0, -1, "out of memory reading instances");
    }
    resurf_status status = RESURF_OK;
    size_t at = 0;
    for (size_t i = 0; i < n && status == RESURF_OK; ++i) {
        const resurfi_gltf_node *node = &v->nodes[i];
        s->instance_first[i] = at;
        size_t count = instances_of(v, node);
        /* Each instance's T, R, S as a node of its own (absent attributes: identity), whose local matrix goes
         * after the node's world matrix. */
        resurfi_gltf_node identity = {.translation_count = 3, .rotation_count = 4, .scale_count = 3,
                                      .rotation = {0, 0, 0, 1}, .scale = {1, 1, 1}};
        resurfi_gltf_node *local = count ? resurfi_alloc(c->alloc, count, sizeof *local) : NULL;
        if (count && !local) {
            status = resurfi_fail(c->error, RESURF_ERR_OUT_OF_MEMORY, c->path, 0, -1,
                                  "out of memory reading instances");
            break;
        }
        for (size_t j = 0; j < count; ++j)
            local[j] = identity;
        for (int k = 0; k < 3 && count && status == RESURF_OK; ++k) {
            long long id = node->instance_attributes[k];
            if (id == RESURFI_GLTF_NONE)
                continue;
            resurfi_scene_read_accessor(v, &v->accessors[id], values);
            for (size_t j = 0; j < count && status == RESURF_OK; ++j)
                for (int x = 0; x < components[k]; ++x) {
                    double value = values[j * (size_t)components[k] + (size_t)x];
                    if (!isfinite(value))
                        status = FAIL(c, "nodes[%zu].extensions.EXT_mesh_gpu_instancing.attributes.%s of instance "
                                      "%zu is not finite", i, trs[k], j);
                    double *field = k == 0 ? local[j].translation : k == 1 ? local[j].rotation : local[j].scale;
                    field[x] = value;
                }
        }
        for (size_t j = 0; j < count && status == RESURF_OK; ++j) {
            double m[16];
            node_local(&local[j], m);
            mat_mul(s->world[i], m, s->instance_world[at + j]);
        }
        resurfi_free(c->alloc, local);
        at += count;
    }
    s->instance_first[n] = at;
    resurfi_free(c->alloc, values);
    return status;
}

/* The node graph: meshes, children and scene roots in range, one parent per node, no cycle, roots are roots.
 * Then the world matrices (every node has at most one parent, so each has one). */
resurf_status resurfi_scene_check_nodes(load_ctx *c, resurf_scene *s)
{
    const resurfi_gltf_view *v = c->v;
    size_t n = v->node_count;
    long long *parent = resurfi_alloc(c->alloc, n, sizeof *parent);
    unsigned char *state = resurfi_calloc(c->alloc, n, 1);
    s->world = resurfi_alloc(&s->alloc, n, sizeof *s->world);
    resurf_status status = RESURF_OK;
    if (!parent || !state || !s->world) {
        status = resurfi_fail(c->error, RESURF_ERR_OUT_OF_MEMORY, c->path, 0, -1, "out of memory checking nodes");
        goto done;
    }
    for (size_t i = 0; i < n; ++i)
        parent[i] = -1;
    for (size_t i = 0; i < n && status == RESURF_OK; ++i) {
        const resurfi_gltf_node *node = &v->nodes[i];
        if (node->mesh != RESURFI_GLTF_NONE && (node->mesh < 0 || (size_t)node->mesh >= v->mesh_count))
            status = FAIL(c, "nodes[%zu]: mesh %lld does not exist (%zu meshes)", i, node->mesh, v->mesh_count);
        else if ((node->matrix_count && node->matrix_count != 16) ||
                 (node->translation_count && node->translation_count != 3) ||
                 (node->rotation_count && node->rotation_count != 4) || (node->scale_count && node->scale_count != 3))
            status = FAIL(c, "nodes[%zu]: a transform has the wrong number of values", i);
        for (size_t k = 0; k < node->child_count && status == RESURF_OK; ++k) {
            long long child = node->children[k];
            if (child < 0 || (size_t)child >= n)
                status = FAIL(c, "nodes[%zu].children[%zu]: node %lld does not exist (%zu nodes)", i, k, child, n);
            else if (parent[child] != -1)
                status = FAIL(c, "nodes[%lld] has two parents (nodes[%lld] and nodes[%zu])", child, parent[child], i);
            else
                parent[child] = (long long)i;
        }
    }
    /* A cycle: walking up the parents from some node comes back to a node of the same walk (state 1). */
    for (size_t i = 0; i < n && status == RESURF_OK; ++i) {
        long long k = (long long)i;
        while (k != -1 && state[k] == 0) {
            state[k] = 1;
            k = parent[k];
        }
        if (k != -1 && state[k] == 1) {
            status = FAIL(c, "nodes[%lld] is its own ancestor: the node hierarchy has a cycle", k);
            break;
        }
        for (k = (long long)i; k != -1 && state[k] == 1; k = parent[k])
            state[k] = 2;
    }
    for (size_t i = 0; i < v->scene_count && status == RESURF_OK; ++i)
        for (size_t k = 0; k < v->scenes[i].node_count && status == RESURF_OK; ++k) {
            long long root = v->scenes[i].nodes[k];
            if (root < 0 || (size_t)root >= n)
                status = FAIL(c, "scenes[%zu].nodes[%zu]: node %lld does not exist (%zu nodes)", i, k, root, n);
            else if (parent[root] != -1)
                status = FAIL(c, "scenes[%zu].nodes[%zu]: nodes[%lld] is not a root (its parent is nodes[%lld])", i,
                              k, root, parent[root]);
        }
    if (status == RESURF_OK && v->default_scene != RESURFI_GLTF_NONE &&
        (v->default_scene < 0 || (size_t)v->default_scene >= v->scene_count))
        status = FAIL(c, "scene %lld does not exist (%zu scenes)", v->default_scene, v->scene_count);
    if (status != RESURF_OK)
        goto done;
    /* World matrices, each parent before its children: state 3 marks a finished node. */
    for (size_t i = 0; i < n; ++i) {
        while (state[i] != 3) {
            long long k = (long long)i; /* the highest unfinished ancestor */
            while (parent[k] != -1 && state[parent[k]] != 3)
                k = parent[k];
            double local[16];
            node_local(&v->nodes[k], local);
            if (parent[k] == -1)
                memcpy(s->world[k], local, sizeof local);
            else
                mat_mul(s->world[parent[k]], local, s->world[k]);
            state[k] = 3;
        }
    }
    status = read_instances(c, s);
done:
    resurfi_free(c->alloc, parent);
    resurfi_free(c->alloc, state);
    return status;
}

/* ---- primitives ---------------------------------------------------------------------------------------------- */

resurf_status resurfi_scene_check_primitive(load_ctx *c, const resurfi_gltf_primitive *gp, const char *where,
                                            uint64_t *out_count)
{
    const resurfi_gltf_view *v = c->v;
    if (gp->mode < 0 || gp->mode > 6)
        return FAIL(c, "%s: mode %d is not a glTF primitive mode (0..6)", where, gp->mode);
    for (size_t i = 0; i < gp->attribute_count; ++i)
        if (gp->attributes[i].index < 0 || (size_t)gp->attributes[i].index >= v->accessor_count)
            return FAIL(c, "%s: attribute %s names accessor %lld, which does not exist (%zu accessors)", where,
                        gp->attributes[i].name, gp->attributes[i].index, v->accessor_count);
    for (size_t i = 0; i < gp->target_begin[gp->target_count]; ++i)
        if (gp->target_attributes[i].index < 0 || (size_t)gp->target_attributes[i].index >= v->accessor_count)
            return FAIL(c, "%s: a morph target's %s names accessor %lld, which does not exist", where,
                        gp->target_attributes[i].name, gp->target_attributes[i].index);
    if (gp->indices != RESURFI_GLTF_NONE) {
        if (gp->indices < 0 || (size_t)gp->indices >= v->accessor_count)
            return FAIL(c, "%s: indices names accessor %lld, which does not exist (%zu accessors)", where, gp->indices,
                        v->accessor_count);
        const resurfi_gltf_accessor *ia = &v->accessors[gp->indices];
        if (ia->components != 1 || ia->matrix || ia->normalized ||
            (ia->component_type != RESURFI_GLTF_UNSIGNED_BYTE && ia->component_type != RESURFI_GLTF_UNSIGNED_SHORT &&
             ia->component_type != RESURFI_GLTF_UNSIGNED_INT))
            return FAIL(c, "%s: the indices accessor %lld is not SCALAR of unsigned integers", where, gp->indices);
    }
    /* Every attribute counts the same vertices (glTF 2.0 3.7.2.1), morph targets included. */
    uint64_t count = 0;
    for (size_t i = 0; i < gp->attribute_count; ++i) {
        uint64_t n = v->accessors[gp->attributes[i].index].count;
        if (i && n != count)
            return FAIL(c, "%s: attribute %s counts %llu vertices, %s %llu", where, gp->attributes[i].name,
                        (unsigned long long)n, gp->attributes[0].name, (unsigned long long)count);
        count = n;
    }
    for (size_t i = 0; i < gp->target_begin[gp->target_count]; ++i)
        if (v->accessors[gp->target_attributes[i].index].count != count)
            return FAIL(c, "%s: a morph target's %s does not count the primitive's %llu vertices", where,
                        gp->target_attributes[i].name, (unsigned long long)count);
    *out_count = count;
    if (!gp->draco)
        return RESURF_OK;
    /* The Draco extension's references; its payload is checked as it is decoded (scene.c). */
    if (gp->draco_malformed)
        return FAIL(c, "%s: KHR_draco_mesh_compression is not an object with an `attributes` object", where);
    if (gp->draco_view < 0 || (size_t)gp->draco_view >= v->buffer_view_count)
        return FAIL(c, "%s: KHR_draco_mesh_compression names bufferView %lld, which does not exist (%zu bufferViews)",
                    where, gp->draco_view, v->buffer_view_count);
    if (gp->mode != 4 && gp->mode != 0)
        return FAIL(c, "%s: a Draco-compressed primitive must be triangles or points (mode %d)", where, gp->mode);
    for (size_t i = 0; i < gp->draco_attribute_count; ++i) {
        const resurfi_gltf_named *d = &gp->draco_attributes[i];
        if (d->index < 0 || d->index > INT32_MAX)
            return FAIL(c, "%s: KHR_draco_mesh_compression attribute %s has no valid Draco id", where, d->name);
        size_t k = 0;
        while (k < gp->attribute_count && strcmp(gp->attributes[k].name, d->name))
            ++k;
        if (k == gp->attribute_count)
            return FAIL(c, "%s: KHR_draco_mesh_compression compresses %s, which is not an attribute of the primitive",
                        where, d->name);
    }
    return RESURF_OK;
}
