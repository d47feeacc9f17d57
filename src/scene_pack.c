/* Packing a scene's primitives for saving: each triangle primitive at each level into glTF accessors (attributes
 * in their component types, skin weights snapped to sum exactly 1, morph targets beside them) or into a Draco
 * payload that is decoded again and checked (docs: scene_save.c's header). Draco payloads are made ahead, side by
 * side on the save's threads, before the plan takes them. */
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_save_internal.h"

/* ---- packing attributes -------------------------------------------------------------------------------------- */

/* One attribute as it is written: where its values come from and in which glTF and Draco form. */
typedef struct out_attr {
    char name[64];
    int component_type, normalized, components;
    int draco_type, bits;
    const double *d;        /* double source: value (v, k) = d[v * stride + k] */
    const float *f;         /* or float source (extras) */
    size_t stride;
    int unit_vector;        /* NORMAL, TANGENT: xyz made unit length (tangent w made ±1) */
    int clamp01;            /* COLOR_0 */
} out_attr;

static int is_semantic(const char *name)
{
    static const char *const prefixes[] = {"TEXCOORD_", "COLOR_", "JOINTS_", "WEIGHTS_"};
    if (name[0] == '_' || !strcmp(name, "TANGENT"))
        return 1;
    for (size_t i = 0; i < sizeof prefixes / sizeof *prefixes; ++i) {
        size_t n = strlen(prefixes[i]);
        if (!strncmp(name, prefixes[i], n) && name[n]) {
            const char *p = name + n;
            while (*p >= '0' && *p <= '9')
                ++p;
            if (!*p)
                return 1;
        }
    }
    return 0;
}

/* Is extra `name` a morph target's attribute ("targets[t].NAME")? Then *t and *attr (may be NULL) say which. */
static int is_target(const char *name)
{
    return !strncmp(name, RESURF_MORPH_TARGET_PREFIX, strlen(RESURF_MORPH_TARGET_PREFIX));
}

static int parse_target(const char *name, size_t *t, const char **attr)
{
    if (!is_target(name))
        return 0;
    const char *p = name + strlen(RESURF_MORPH_TARGET_PREFIX);
    size_t k = 0;
    if (*p < '0' || *p > '9')
        return 0;
    for (; *p >= '0' && *p <= '9' && k < 100000; ++p)
        k = 10 * k + (size_t)(*p - '0');
    if (p[0] != ']' || p[1] != '.' || !p[2])
        return 0;
    *t = k, *attr = p + 2;
    return 1;
}

static int draco_data_type(int component_type)
{
    switch (component_type) {
    case RESURFI_GLTF_UNSIGNED_BYTE: return RESURFI_DRACO_U8;
    case RESURFI_GLTF_UNSIGNED_SHORT: return RESURFI_DRACO_U16;
    case RESURFI_GLTF_UNSIGNED_INT: return RESURFI_DRACO_U32;
    case RESURFI_GLTF_BYTE: return RESURFI_DRACO_I8;
    case RESURFI_GLTF_SHORT: return RESURFI_DRACO_I16;
    default: return RESURFI_DRACO_F32;
    }
}

/* Does core glTF 2.0 allow attribute a's stored format, or only KHR_mesh_quantization (a quantized source's
 * TANGENT in normalized shorts, a TEXCOORD in signed or unnormalized integers)? POSITION and NORMAL are written
 * as floats; an application-specific attribute ("_NAME") may be any type. */
static int needs_quantization(const out_attr *a)
{
    int t = a->component_type;
    if (a->name[0] == '_' || t == RESURFI_GLTF_FLOAT)
        return 0;
    if (!strcmp(a->name, "TANGENT"))
        return 1;
    if (!strncmp(a->name, "JOINTS_", 7))
        return a->normalized || (t != RESURFI_GLTF_UNSIGNED_BYTE && t != RESURFI_GLTF_UNSIGNED_SHORT);
    return !a->normalized || (t != RESURFI_GLTF_UNSIGNED_BYTE && t != RESURFI_GLTF_UNSIGNED_SHORT);
}

/* The attributes of mesh m as written for primitive p. */
static size_t list_attributes(const save_ctx *c, const resurfi_scene_prim *p, const resurf_mesh *m, out_attr *out)
{
    const resurf_scene_save_options *o = c->o;
    size_t n = 0;
    out_attr *a = &out[n++];
    memset(a, 0, sizeof *a);
    snprintf(a->name, sizeof a->name, "POSITION");
    a->component_type = RESURFI_GLTF_FLOAT, a->components = 3, a->d = m->positions, a->stride = 3;
    a->draco_type = RESURFI_DRACO_POSITION, a->bits = o->position_bits;
    if (m->normals) {
        a = &out[n++];
        memset(a, 0, sizeof *a);
        snprintf(a->name, sizeof a->name, "NORMAL");
        a->component_type = RESURFI_GLTF_FLOAT, a->components = 3, a->d = m->normals, a->stride = 3;
        a->draco_type = RESURFI_DRACO_NORMAL, a->bits = o->normal_bits, a->unit_vector = 1;
    }
    for (unsigned k = 0; k < m->texcoord_count; ++k) {
        a = &out[n++];
        memset(a, 0, sizeof *a);
        snprintf(a->name, sizeof a->name, "TEXCOORD_%u", k);
        a->component_type = RESURFI_GLTF_FLOAT, a->components = 2, a->d = m->texcoords[k], a->stride = 2;
        a->draco_type = RESURFI_DRACO_TEX_COORD, a->bits = o->texcoord_bits;
    }
    if (m->colors) {
        a = &out[n++];
        memset(a, 0, sizeof *a);
        snprintf(a->name, sizeof a->name, "COLOR_0");
        a->component_type = RESURFI_GLTF_FLOAT, a->components = m->color_components == 3 ? 3 : 4;
        a->d = m->colors, a->stride = 4, a->clamp01 = 1;
        a->draco_type = RESURFI_DRACO_COLOR, a->bits = o->color_bits;
    }
    for (size_t i = 0; i < m->extra_count; ++i) {
        const resurf_attribute *x = &m->extras[i];
        if (x->components < 1 || x->components > 4 || is_target(x->name))
            continue; /* glTF vertex attributes are SCALAR or VECn; morph targets go apart (pack_targets) */
        a = &out[n++];
        memset(a, 0, sizeof *a);
        if (is_semantic(x->name))
            snprintf(a->name, sizeof a->name, "%s", x->name);
        else {
            /* A custom attribute: "_" + the name in capitals, other bytes as '_'. */
            a->name[0] = '_';
            size_t k = 0;
            for (; x->name[k] && k + 2 < sizeof a->name; ++k) {
                char ch = x->name[k];
                if (ch >= 'a' && ch <= 'z')
                    ch = (char)(ch - 'a' + 'A');
                else if (!((ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9')))
                    ch = '_';
                a->name[k + 1] = ch;
            }
            a->name[k + 1] = 0;
        }
        a->components = (int)x->components;
        a->f = x->data, a->stride = x->components;
        a->component_type = !strncmp(x->name, "JOINTS_", 7) ? RESURFI_GLTF_UNSIGNED_SHORT : RESURFI_GLTF_FLOAT;
        for (size_t k = 0; k < p->format_count; ++k)
            if (!strcmp(p->formats[k].name, x->name) && p->formats[k].components == a->components) {
                a->component_type = p->formats[k].component_type;
                a->normalized = p->formats[k].normalized;
            }
        a->unit_vector = !strcmp(a->name, "TANGENT") && a->components == 4 &&
                         (a->component_type == RESURFI_GLTF_FLOAT || a->normalized);
        a->draco_type = RESURFI_DRACO_GENERIC, a->bits = o->generic_bits;
    }
    return n;
}

/* The JOINTS_n / WEIGHTS_n pairs of m as they will be stored (skin.c): weights whose sum is exactly one whole in
 * the stored type, joints of zero weight 0. Draco would quantize float weights, and quantized floats no longer sum
 * to 1, so under Draco with quantization they are written as normalized unsigned shorts, which it keeps exactly. */
static resurf_status snap_skin(save_ctx *c, const resurf_mesh *m, out_attr *attrs, size_t n)
{
    resurfi_skin_sets sets;
    resurfi_skin_find_sets(m, &sets);
    out_attr *joints[RESURFI_SKIN_MAX_SETS], *weights[RESURFI_SKIN_MAX_SETS];
    float *jv[RESURFI_SKIN_MAX_SETS], *wv[RESURFI_SKIN_MAX_SETS];
    double units = 0; /* the coarsest: 65535 = 255 × 257, so whole bytes are whole shorts too */
    for (unsigned s = 0; s < sets.count; ++s) {
        joints[s] = weights[s] = NULL;
        for (size_t i = 0; i < n; ++i) {
            if (!strcmp(attrs[i].name, m->extras[sets.joints[s]].name))
                joints[s] = &attrs[i];
            if (!strcmp(attrs[i].name, m->extras[sets.weights[s]].name))
                weights[s] = &attrs[i];
        }
        if (!joints[s] || !weights[s])
            return resurfi_fail(c->error, RESURF_ERR_INTERNAL, c->path, 0, -1, "skin attributes not listed");
        out_attr *w = weights[s];
        if (c->o->draco && w->component_type == RESURFI_GLTF_FLOAT && w->bits > 0)
            w->component_type = RESURFI_GLTF_UNSIGNED_SHORT, w->normalized = 1;
        double u = !w->normalized                                   ? 0
                   : w->component_type == RESURFI_GLTF_UNSIGNED_BYTE ? 255
                                                                     : 65535;
        units = u == 255 || units == 255 ? 255 : u > 0 ? u : units;
        jv[s] = save_own(c, resurfi_alloc(c->alloc, m->vertex_count, 4 * sizeof(float)));
        wv[s] = save_own(c, resurfi_alloc(c->alloc, m->vertex_count, 4 * sizeof(float)));
        if (!jv[s] || !wv[s])
            return save_oom(c);
    }
    if (!sets.count)
        return RESURF_OK;
    resurfi_skin_snap(m, &sets, units, jv, wv);
    for (unsigned s = 0; s < sets.count; ++s)
        joints[s]->f = jv[s], weights[s]->f = wv[s];
    return RESURF_OK;
}

static void put_value(unsigned char *p, int type, int normalized, double x)
{
    double lo = 0, hi = 0;
    switch (type) {
    case RESURFI_GLTF_FLOAT: {
        float f = (float)x;
        uint32_t bits;
        memcpy(&bits, &f, 4);
        for (int i = 0; i < 4; ++i)
            p[i] = (unsigned char)(bits >> (8 * i));
        return;
    }
    case RESURFI_GLTF_BYTE: lo = -128, hi = 127; break;
    case RESURFI_GLTF_UNSIGNED_BYTE: hi = 255; break;
    case RESURFI_GLTF_SHORT: lo = -32768, hi = 32767; break;
    case RESURFI_GLTF_UNSIGNED_SHORT: hi = 65535; break;
    default: hi = 4294967295.0; break;
    }
    if (normalized)
        x *= hi;
    x = isfinite(x) ? round(x) : 0;
    x = x < lo ? lo : x > hi ? hi : x;
    int64_t v = (int64_t)x;
    size_t size = resurfi_gltf_component_size(type);
    for (size_t i = 0; i < size; ++i)
        p[i] = (unsigned char)((uint64_t)v >> (8 * i));
}

/* Packs one attribute of n vertices in its component type (allocated, owned by c). bounds (may be NULL) receive
 * min/max of the values as written. */
static unsigned char *pack_attribute(save_ctx *c, const out_attr *a, size_t n, double *min, double *max)
{
    size_t csize = resurfi_gltf_component_size(a->component_type), comps = (size_t)a->components;
    unsigned char *data = save_own(c, resurfi_alloc(c->alloc, n, comps * csize));
    if (!data)
        return NULL;
    for (size_t k = 0; k < comps && min; ++k)
        min[k] = INFINITY, max[k] = -INFINITY;
    for (size_t v = 0; v < n; ++v) {
        double x[4];
        for (size_t k = 0; k < comps; ++k)
            x[k] = a->d ? a->d[v * a->stride + k] : (double)a->f[v * a->stride + k];
        if (a->unit_vector) {
            double l = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
            if (l > 0 && isfinite(l))
                x[0] /= l, x[1] /= l, x[2] /= l;
            else
                x[0] = 0, x[1] = 0, x[2] = 1;
            if (comps == 4)
                x[3] = x[3] < 0 ? -1.0 : 1.0;
        }
        for (size_t k = 0; k < comps; ++k) {
            if (a->clamp01)
                x[k] = x[k] < 0 ? 0 : x[k] > 1 ? 1 : x[k];
            put_value(data + (v * comps + k) * csize, a->component_type, a->normalized, x[k]);
            if (min) {
                double w = a->component_type == RESURFI_GLTF_FLOAT ? (double)(float)x[k] : x[k];
                min[k] = fmin(min[k], w), max[k] = fmax(max[k], w);
            }
        }
    }
    return data;
}

/* Morph targets of mesh m (its "targets[t].NAME" extras) as float accessors of `count` vertices: the mesh's own
 * vertex order, which a Draco payload with targets keeps (pack_draco). Targets must be numbered 0, 1, ... without
 * a gap (a glTF target is a non-empty object). */
static resurf_status pack_targets(save_ctx *c, const resurfi_scene_prim *p, const resurf_mesh *m, packed *pk)
{
    size_t count = 0, n = 0;
    for (size_t i = 0; i < m->extra_count; ++i) {
        size_t t;
        const char *attr;
        if (!is_target(m->extras[i].name))
            continue;
        if (!parse_target(m->extras[i].name, &t, &attr) || m->extras[i].components < 1 ||
            m->extras[i].components > 4 || !m->extras[i].data)
            return resurfi_fail(c->error, RESURF_ERR_INVALID_MESH, c->path, 0, -1,
                                "%s: the extra %s is not a morph target attribute (targets[t].NAME, 1 to 4 "
                                "components)", p->info.name, m->extras[i].name);
        count = t + 1 > count ? t + 1 : count;
        ++n;
    }
    if (n == 0)
        return RESURF_OK;
    pk->target_begin = save_own(c, resurfi_calloc(c->alloc, count + 1, sizeof *pk->target_begin));
    pk->target_attributes = save_own(c, resurfi_alloc(c->alloc, n, sizeof *pk->target_attributes));
    if (!pk->target_begin || !pk->target_attributes)
        return save_oom(c);
    size_t k = 0;
    for (size_t t = 0; t < count; ++t) {
        pk->target_begin[t] = k;
        for (size_t i = 0; i < m->extra_count; ++i) {
            size_t ti;
            const char *attr;
            if (!parse_target(m->extras[i].name, &ti, &attr) || ti != t)
                continue;
            const resurf_attribute *x = &m->extras[i];
            out_attr a;
            memset(&a, 0, sizeof a);
            a.component_type = RESURFI_GLTF_FLOAT, a.components = (int)x->components;
            a.f = x->data, a.stride = x->components;
            double min[4], max[4];
            unsigned char *data = pack_attribute(c, &a, m->vertex_count, min, max);
            const char *name = save_own_string(c, attr);
            if (!data || !name)
                return save_oom(c);
            resurfi_gltf_out_accessor acc;
            memset(&acc, 0, sizeof acc);
            acc.component_type = RESURFI_GLTF_FLOAT;
            acc.components = a.components;
            acc.count = m->vertex_count;
            acc.data = data;
            acc.data_size = m->vertex_count * (size_t)a.components * 4;
            acc.target = RESURFI_GLTF_ARRAY_BUFFER;
            acc.has_bounds = !strcmp(attr, "POSITION"); /* glTF 2.0 3.7.2.1: POSITION needs min and max */
            for (int j = 0; j < a.components; ++j)
                acc.min[j] = min[j], acc.max[j] = max[j];
            long long index = save_add_accessor(c, &acc);
            if (index < 0)
                return save_oom(c);
            pk->target_attributes[k++] = (resurfi_gltf_named){name, index};
            pk->bytes += acc.data_size;
        }
        if (k == pk->target_begin[t])
            return resurfi_fail(c->error, RESURF_ERR_INVALID_MESH, c->path, 0, -1,
                                "%s: morph target %zu has no attribute (targets must be numbered from 0 without "
                                "a gap)", p->info.name, t);
    }
    pk->target_begin[count] = k;
    pk->target_count = count;
    return RESURF_OK;
}

/* The accessor of attribute a over `count` vertices, without data (Draco's decoded attributes have none); the
 * first attribute, POSITION, carries the box glTF requires. */
static resurfi_gltf_out_accessor attribute_accessor(const out_attr *a, size_t count, int with_bounds,
                                                    const double lo[3], const double hi[3])
{
    resurfi_gltf_out_accessor acc;
    memset(&acc, 0, sizeof acc);
    acc.component_type = a->component_type;
    acc.normalized = a->normalized;
    acc.components = a->components;
    acc.count = count;
    if (with_bounds) {
        acc.has_bounds = 1;
        for (int k = 0; k < 3; ++k)
            acc.min[k] = lo[k], acc.max[k] = hi[k];
    }
    return acc;
}

/* Adds accessor acc to the plan as attribute `name` of a primitive. */
static resurf_status add_attribute(save_ctx *c, const char *name, const resurfi_gltf_out_accessor *acc,
                                   resurfi_gltf_named *out)
{
    const char *owned = save_own_string(c, name);
    long long index = owned ? save_add_accessor(c, acc) : -1;
    if (index < 0)
        return RESURF_ERR_OUT_OF_MEMORY;
    *out = (resurfi_gltf_named){owned, index};
    return RESURF_OK;
}

/* Encodes j's input, decodes the payload again and checks what came back against what was meant. */
static void draco_make(draco_job *j)
{
    const resurf_mesh *m = j->mesh;
    resurf_error derr;
    j->made = 1;
    j->status = resurfi_draco_encode(&j->in, &j->enc, &derr);
    if (j->status != RESURF_OK) {
        snprintf(j->message, sizeof j->message, "%s", derr.message);
        return;
    }
    if (!j->enc.data)
        return; /* out of memory, said by pack_draco */
    resurfi_draco_mesh *dm = NULL;
    if (resurfi_draco_decode(j->enc.data, j->enc.size, &dm, &derr) != RESURF_OK) {
        j->status = RESURF_ERR_INTERNAL;
        snprintf(j->message, sizeof j->message, "the Draco payload just written does not decode: %.200s",
                 derr.message);
        return;
    }
    char problem[160] = "";
    if (dm->point_count != j->enc.encoded_points || dm->face_count != j->enc.encoded_faces || dm->point_count == 0 ||
        dm->face_count == 0)
        snprintf(problem, sizeof problem, "decodes to %zu points and %zu triangles, the encoder wrote %zu and %zu",
                 dm->point_count, dm->face_count, j->enc.encoded_points, j->enc.encoded_faces);
    const resurfi_draco_attribute *found[32] = {0};
    for (size_t i = 0; i < j->attr_count && !problem[0]; ++i) {
        for (size_t k = 0; k < dm->attribute_count; ++k)
            if (dm->attributes[k].unique_id == j->enc.unique_ids[i])
                found[i] = &dm->attributes[k];
        if (!found[i] || found[i]->components != j->components[i] || found[i]->integer != j->integer[i])
            snprintf(problem, sizeof problem, "lost or changed attribute %.100s", j->names[i]);
    }
    double lo[3], hi[3], *dlo = j->lo, *dhi = j->hi;
    for (int k = 0; k < 3; ++k)
        dlo[k] = INFINITY, dhi[k] = -INFINITY;
    if (!problem[0]) {
        /* Positions: the decoded box lies within one quantization step of the input's box. */
        resurf_mesh_bounds(m, lo, hi);
        for (size_t v = 0; v < m->vertex_count; ++v)
            for (int k = 0; k < 3; ++k)
                lo[k] = fmin(lo[k], (float)m->positions[3 * v + k]), hi[k] = fmax(hi[k], (float)m->positions[3 * v + k]);
        double range = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
        double step = range / (double)((1u << j->position_bits) - 1) + 1e-6 * range + 1e-30;
        for (size_t v = 0; v < dm->point_count; ++v)
            for (int k = 0; k < 3; ++k) {
                double x = found[0]->values[3 * v + (size_t)k];
                dlo[k] = fmin(dlo[k], x), dhi[k] = fmax(dhi[k], x);
            }
        for (int k = 0; k < 3 && !problem[0]; ++k)
            if (!(dlo[k] >= lo[k] - step && dhi[k] <= hi[k] + step))
                snprintf(problem, sizeof problem, "positions decode outside the input's bounds by more than a "
                                                  "quantization step (axis %d)", k);
        /* With morph targets the decoded points must be the mesh's vertices in their order (the targets'
         * accessors use it): point v within a quantization step of vertex v, and the same triangles. */
        int keep_order = j->in.keep_order;
        if (keep_order && !problem[0] && (dm->point_count != m->vertex_count || dm->face_count != m->triangle_count))
            snprintf(problem, sizeof problem, "has %zu points and %zu triangles, not the %zu vertices and %zu "
                     "triangles its morph targets need", dm->point_count, dm->face_count, m->vertex_count,
                     m->triangle_count);
        for (size_t v = 0; keep_order && !problem[0] && v < dm->point_count; ++v)
            for (int k = 0; k < 3; ++k)
                if (!(fabs(found[0]->values[3 * v + (size_t)k] - (double)(float)m->positions[3 * v + (size_t)k]) <=
                      step))
                    snprintf(problem, sizeof problem, "changed the vertex order (point %zu), which its morph "
                             "targets need", v);
        for (size_t i = 0; keep_order && !problem[0] && i < 3 * dm->face_count; ++i)
            if (dm->faces[i] != m->indices[i])
                snprintf(problem, sizeof problem, "changed the triangles (index %zu), which its morph targets need",
                         i);
    }
    j->points = dm->point_count, j->faces = dm->face_count;
    resurfi_draco_mesh_free(dm);
    if (problem[0]) {
        j->status = RESURF_ERR_INTERNAL;
        snprintf(j->message, sizeof j->message, "the Draco payload %s", problem);
    }
}

/* Draco: the payload made ahead (encode_ahead), else made now; then its accessors. While preparing, only the job's
 * input is set. */
static resurf_status pack_draco(save_ctx *c, const resurfi_scene_prim *p, size_t prim, size_t level,
                                const resurf_mesh *m, const out_attr *attrs, size_t attr_count,
                                unsigned char **values, int keep_order, packed *out)
{
    if (attr_count > 32)
        return resurfi_fail(c->error, RESURF_ERR_UNSUPPORTED, c->path, 0, -1, "%s: more than 32 attributes for Draco",
                            p->info.name);
    size_t ahead = c->job_of ? c->job_of[prim * RESURF_SCENE_MAX_LEVELS + level] : 0;
    draco_job now = {0}, *j = ahead ? &c->jobs[ahead - 1] : &now; /* not made: a job of its own, made here */
    if (!j->made) {
        memset(j, 0, sizeof *j);
        j->mesh = m;
        j->attr_count = attr_count;
        j->position_bits = c->o->position_bits;
        for (size_t i = 0; i < attr_count; ++i) {
            j->in_attrs[i].type = attrs[i].draco_type;
            j->in_attrs[i].data_type = draco_data_type(attrs[i].component_type);
            j->in_attrs[i].components = attrs[i].components;
            j->in_attrs[i].normalized = attrs[i].normalized;
            j->in_attrs[i].values = values[i];
            j->in_attrs[i].quantization_bits = attrs[i].bits;
            memcpy(j->names[i], attrs[i].name, sizeof j->names[i]);
            j->components[i] = attrs[i].components;
            j->integer[i] = attrs[i].component_type != RESURFI_GLTF_FLOAT;
        }
        j->in = (resurfi_draco_input){
            .vertex_count = m->vertex_count,
            .triangle_count = m->triangle_count,
            .indices = m->indices,
            .attribute_count = attr_count,
            .attributes = j->in_attrs,
            .compression_level = c->o->compression_level,
            .keep_order = keep_order,
        };
        j->prepared = 1;
        if (c->preparing)
            return RESURF_OK;
        draco_make(j);
        if (j->enc.data && !save_own_from(c, j->enc.data, NULL)) /* malloc'ed by the Draco shim: the C heap */
            j->enc.data = NULL;
    }
    if (j->status != RESURF_OK)
        return resurfi_fail(c->error, j->status, c->path, 0, -1, "%s level %zu: %s", p->info.name, level,
                            j->message);
    if (!j->enc.data)
        return save_oom(c);
    resurfi_draco_output enc = j->enc;
    size_t points = j->points, faces = j->faces;
    const double *dlo = j->lo, *dhi = j->hi;

    out->draco = enc.data;
    out->draco_size = enc.size;
    out->attributes = save_own(c, resurfi_alloc(c->alloc, attr_count, sizeof *out->attributes));
    out->draco_ids = save_own(c, resurfi_alloc(c->alloc, attr_count, sizeof *out->draco_ids));
    if (!out->attributes || !out->draco_ids)
        return save_oom(c);
    for (size_t i = 0; i < attr_count; ++i) {
        resurfi_gltf_out_accessor a = attribute_accessor(&attrs[i], points, i == 0, dlo, dhi);
        if (add_attribute(c, attrs[i].name, &a, &out->attributes[i]) != RESURF_OK)
            return save_oom(c);
        out->draco_ids[i] = (resurfi_gltf_named){out->attributes[i].name, enc.unique_ids[i]};
    }
    resurfi_gltf_out_accessor ia;
    memset(&ia, 0, sizeof ia);
    ia.component_type = points <= 65535 ? RESURFI_GLTF_UNSIGNED_SHORT : RESURFI_GLTF_UNSIGNED_INT;
    ia.components = 1;
    ia.count = 3 * (uint64_t)faces;
    if ((out->indices = save_add_accessor(c, &ia)) < 0)
        return save_oom(c);
    out->attribute_count = attr_count;
    out->bytes = enc.size;
    return RESURF_OK;
}

/* The level whose mesh primitive p shows at `level` (its last one when it has fewer). */
size_t save_effective_level(const resurfi_scene_prim *p, size_t level)
{
    return level < p->lod_count ? level : p->lod_count;
}

/* Packs primitive `prim` at `level` (cached by the level it really shows). */
resurf_status save_pack(save_ctx *c, size_t prim, size_t level, packed **out)
{
    const resurfi_scene_prim *p = &c->s->prims[prim];
    level = save_effective_level(p, level);
    packed *pk = &c->cache[prim * RESURF_SCENE_MAX_LEVELS + level];
    *out = pk;
    if (pk->done)
        return RESURF_OK;
    const resurf_mesh *m = resurfi_scene_level_mesh(p, level);
    pk->done = 1;
    if (m->vertex_count == 0 || m->triangle_count == 0) {
        pk->empty = 1; /* glTF accessors cannot be empty: the primitive is left out at this level */
        return RESURF_OK;
    }
    out_attr attrs[4 + RESURF_MAX_TEXCOORD_SETS + 64];
    if (m->extra_count > 64)
        return resurfi_fail(c->error, RESURF_ERR_UNSUPPORTED, c->path, 0, -1, "%s: more than 64 extra attributes",
                            p->info.name);
    size_t n = list_attributes(c, p, m, attrs);
    resurf_status status = snap_skin(c, m, attrs, n);
    if (status != RESURF_OK)
        return status;
    for (size_t i = 0; i < n; ++i)
        pk->quantized |= needs_quantization(&attrs[i]);
    unsigned char *values[sizeof attrs / sizeof *attrs];
    double min[4], max[4];
    size_t ahead = c->job_of ? c->job_of[prim * RESURF_SCENE_MAX_LEVELS + level] : 0;
    int made = ahead && c->jobs[ahead - 1].made; /* its payload needs no values any more */
    for (size_t i = 0; i < n && !made; ++i)
        if (!(values[i] = pack_attribute(c, &attrs[i], m->vertex_count, i == 0 ? min : NULL, i == 0 ? max : NULL)))
            return save_oom(c);
    int morphed = p->info.kind == RESURF_PRIMITIVE_MORPHED;
    resurf_status st = RESURF_OK;
    if (c->o->draco) {
        st = pack_draco(c, p, prim, level, m, attrs, n, values, morphed, pk);
        return st == RESURF_OK && morphed && !c->preparing ? pack_targets(c, p, m, pk) : st;
    }

    pk->attributes = save_own(c, resurfi_alloc(c->alloc, n, sizeof *pk->attributes));
    if (!pk->attributes)
        return save_oom(c);
    for (size_t i = 0; i < n; ++i) {
        resurfi_gltf_out_accessor a = attribute_accessor(&attrs[i], m->vertex_count, i == 0, min, max);
        a.data = values[i];
        a.data_size = m->vertex_count * (size_t)a.components * resurfi_gltf_component_size(a.component_type);
        a.target = RESURFI_GLTF_ARRAY_BUFFER;
        if (add_attribute(c, attrs[i].name, &a, &pk->attributes[i]) != RESURF_OK)
            return save_oom(c);
        pk->bytes += a.data_size;
    }
    /* Unsigned short indices while they fit: 65535 itself is the primitive-restart value, never an index. */
    int wide = m->vertex_count > 65535;
    size_t isize = wide ? 4 : 2;
    unsigned char *idx = save_own(c, resurfi_alloc(c->alloc, 3 * m->triangle_count, isize));
    if (!idx)
        return save_oom(c);
    for (size_t i = 0; i < 3 * m->triangle_count; ++i)
        put_value(idx + i * isize, wide ? RESURFI_GLTF_UNSIGNED_INT : RESURFI_GLTF_UNSIGNED_SHORT, 0, m->indices[i]);
    resurfi_gltf_out_accessor ia;
    memset(&ia, 0, sizeof ia);
    ia.component_type = wide ? RESURFI_GLTF_UNSIGNED_INT : RESURFI_GLTF_UNSIGNED_SHORT;
    ia.components = 1;
    ia.count = 3 * (uint64_t)m->triangle_count;
    ia.data = idx;
    ia.data_size = 3 * m->triangle_count * isize;
    ia.target = RESURFI_GLTF_ELEMENT_ARRAY_BUFFER;
    if ((pk->indices = save_add_accessor(c, &ia)) < 0)
        return save_oom(c);
    pk->attribute_count = n;
    pk->bytes += ia.data_size;
    return morphed ? pack_targets(c, p, m, pk) : RESURF_OK;
}

/* ---- the Draco payloads, made ahead side by side ----------------------------------------------------------- */

typedef struct ahead_run {
    draco_job *jobs;
    const size_t *order;
    size_t count;
    atomic_size_t made;
    const resurf_progress *progress;
    atomic_int cancelled;
} ahead_run;

/* One payload; the calling thread (worker 0) also asks the caller's progress, and a cancel stops the run. */
static int make_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    ahead_run *r = ctx;
    for (size_t i = begin; i < end; ++i)
        draco_make(&r->jobs[r->order[i]]);
    double f = (double)(atomic_fetch_add(&r->made, end - begin) + end - begin) / (double)r->count;
    if (worker == 0 && resurfi_progress(r->progress, RESURF_STAGE_SAVE, 0.5 * f)) {
        atomic_store(&r->cancelled, 1);
        return 1;
    }
    return 0;
}

typedef struct job_size {
    size_t triangles, job;
} job_size;

static int more_triangles_first(const void *a, const void *b)
{
    const job_size *x = a, *y = b;
    if (x->triangles != y->triangles)
        return x->triangles > y->triangles ? -1 : 1;
    return (x->job > y->job) - (x->job < y->job);
}

/* Every Draco payload the call may write (each primitive at each level it shows, or at the one level asked for)
 * made before the plan asks for them, on o->threads threads, the largest first: encoding and decoding again are
 * most of a save, and each payload is one primitive's own work, so the bytes do not depend on the thread count.
 * pack then takes them as they are made; what cannot be prepared here (an allocation, a primitive Draco cannot
 * take) is left to pack, which says why in plan order, as without this pass. */
resurf_status save_encode_ahead(save_ctx *c)
{
    const resurf_scene *s = c->s;
    unsigned threads = resurfi_thread_count(c->o->threads);
    if (!c->o->draco || threads < 2)
        return RESURF_OK;
    size_t n = 0;
    for (size_t p = 0; p < s->prim_count; ++p)
        if (resurfi_scene_rewritten(&s->prims[p]))
            n += c->o->level >= 0 ? 1 : s->prims[p].lod_count + 1;
    if (n < 2)
        return RESURF_OK;
    c->jobs = resurfi_calloc(c->alloc, n, sizeof *c->jobs);
    c->job_of = resurfi_calloc(c->alloc, s->prim_count * RESURF_SCENE_MAX_LEVELS, sizeof *c->job_of);
    size_t *order = resurfi_alloc(c->alloc, n, sizeof *order);
    job_size *sizes = resurfi_alloc(c->alloc, n, sizeof *sizes);
    if (!c->jobs || !c->job_of || !order || !sizes) {
        resurfi_free(c->alloc, c->jobs);
        resurfi_free(c->alloc, c->job_of);
        resurfi_free(c->alloc, order);
        resurfi_free(c->alloc, sizes);
        c->jobs = NULL, c->job_of = NULL;
        return RESURF_OK;
    }
    /* pack fills each job's input; its failures are not this pass's to report. */
    resurf_error *error = c->error, scratch;
    c->error = &scratch;
    c->preparing = 1;
    size_t k = 0;
    for (size_t p = 0; p < s->prim_count; ++p) {
        const resurfi_scene_prim *prim = &s->prims[p];
        if (!resurfi_scene_rewritten(prim))
            continue;
        size_t first = c->o->level >= 0 ? save_effective_level(prim, (size_t)c->o->level) : 0;
        size_t last = c->o->level >= 0 ? first : prim->lod_count;
        for (size_t level = first; level <= last; ++level) {
            c->job_of[p * RESURF_SCENE_MAX_LEVELS + level] = ++k;
            packed *pk;
            (void)save_pack(c, p, level, &pk);
        }
    }
    c->preparing = 0;
    c->error = error;
    memset(c->cache, 0, s->prim_count * RESURF_SCENE_MAX_LEVELS * sizeof *c->cache);
    size_t prepared = 0;
    for (size_t i = 0; i < k; ++i)
        if (c->jobs[i].prepared)
            sizes[prepared++] = (job_size){c->jobs[i].mesh->triangle_count, i};
    qsort(sizes, prepared, sizeof *sizes, more_triangles_first);
    for (size_t i = 0; i < prepared; ++i)
        order[i] = sizes[i].job;
    resurfi_free(c->alloc, sizes);
    ahead_run run = {.jobs = c->jobs, .order = order, .count = prepared, .progress = &c->o->progress};
    atomic_init(&run.made, 0);
    atomic_init(&run.cancelled, 0);
    resurfi_parallel_for(prepared, 1, threads, make_block, &run);
    for (size_t i = 0; i < prepared; ++i) {
        draco_job *j = &c->jobs[order[i]];
        if (j->enc.data && !save_own_from(c, j->enc.data, NULL)) /* malloc'ed by the Draco shim: the C heap */
            j->enc.data = NULL;
    }
    resurfi_free(c->alloc, order);
    if (atomic_load(&run.cancelled))
        return resurfi_fail(c->error, RESURF_ERR_CANCELLED, c->path, 0, -1, "cancelled by the progress callback");
    return RESURF_OK;
}
