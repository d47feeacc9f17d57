/* Saving scenes: packs each triangle primitive at each level into glTF accessors or a Draco payload, checks every
 * payload by decoding it again, plans the output document (layouts of levels: MSFT_lod, one file per level, side
 * by side) for io/gltf_write.cpp, and writes the files atomically (temporary files renamed into place only when
 * all of them are complete).
 *
 * Follows glTF 2.0 (3.6-3.7: accessor types, min/max of POSITION, unit normals and tangents), KHR_draco_mesh_
 * compression (accessors of a compressed primitive describe the decoded data and have no bufferView) and the
 * Microsoft MSFT_lod extension. Draco quantization: a float attribute of range R stored in b bits is within
 * R / (2^b - 1) of its input after decoding; that bound is what the decode check enforces for positions. */
#include <errno.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "file.h"
#include "scene_internal.h"

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

/* ---- the save context: an arena of allocations freed together, and the plan's growing arrays ---------------- */

/* One primitive at one level, packed (cached: a level shown by several output meshes is packed once). */
typedef struct packed {
    int done, empty;
    size_t attribute_count;
    resurfi_gltf_named *attributes; /* name → plan accessor */
    long long indices;
    unsigned char *draco;
    size_t draco_size;
    resurfi_gltf_named *draco_ids;
    size_t target_count;    /* morph targets: target t has target_attributes[target_begin[t] .. target_begin[t+1]) */
    size_t *target_begin;
    resurfi_gltf_named *target_attributes;
    size_t bytes;
} packed;

/* A block freed at the end, with the allocator it came from (Draco's encoded bytes come from the C heap). */
typedef struct owned_block {
    void *block;
    const resurf_allocator *alloc;
} owned_block;

/* One Draco payload: its input, set by pack on the saving thread, and what encoding it, decoding it again and
 * checking what came back gave (draco_make, which touches only its job: payloads are made side by side). */
typedef struct draco_job {
    int prepared, made;
    const resurf_mesh *mesh;
    size_t attr_count;
    resurfi_draco_input_attribute in_attrs[32];
    char names[32][64];
    int components[32], integer[32];
    resurfi_draco_input in;
    int position_bits;
    /* made: */
    resurf_status status;   /* RESURF_OK, the encoder's failure, or RESURF_ERR_INTERNAL: it does not decode as meant */
    char message[256];      /* the failure, after "PRIMITIVE level K: " */
    resurfi_draco_output enc;
    size_t points, faces;
    double lo[3], hi[3];    /* the decoded positions' box */
} draco_job;

typedef struct save_ctx {
    const resurf_scene *s;
    const resurf_scene_save_options *o;
    const resurf_allocator *alloc; /* the call's: options, else the scene's */
    const char *path;
    resurf_error *error;
    owned_block *owned;
    size_t owned_count, owned_cap;
    resurfi_gltf_out_accessor *acc;
    size_t acc_count, acc_cap;
    packed *cache;          /* prim_count × RESURF_SCENE_MAX_LEVELS */
    draco_job *jobs;        /* the payloads made ahead (encode_ahead) */
    size_t *job_of;         /* prim_count × RESURF_SCENE_MAX_LEVELS: index into jobs + 1, or 0 */
    int preparing;          /* pack only fills the Draco job of what it packs */
    int draco_used, verbatim_any;
    size_t level_bytes[RESURF_SCENE_MAX_LEVELS];
} save_ctx;

static resurf_status oom(save_ctx *c)
{
    return resurfi_fail(c->error, RESURF_ERR_OUT_OF_MEMORY, c->path, 0, -1, "out of memory writing the scene");
}

/* Remembers p (a block of allocator a) for freeing at the end; NULL stays NULL (and frees p when the list cannot
 * grow). */
static void *own_from(save_ctx *c, void *p, const resurf_allocator *a)
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
static void *own(save_ctx *c, void *p) { return own_from(c, p, c->alloc); }

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

static char *own_string(save_ctx *c, const char *s)
{
    return own(c, resurfi_strdup(c->alloc, s));
}

static long long add_accessor(save_ctx *c, const resurfi_gltf_out_accessor *a)
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
                         a->component_type == RESURFI_GLTF_FLOAT;
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
        jv[s] = own(c, resurfi_alloc(c->alloc, m->vertex_count, 4 * sizeof(float)));
        wv[s] = own(c, resurfi_alloc(c->alloc, m->vertex_count, 4 * sizeof(float)));
        if (!jv[s] || !wv[s])
            return oom(c);
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
    unsigned char *data = own(c, resurfi_alloc(c->alloc, n, comps * csize));
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
    pk->target_begin = own(c, resurfi_calloc(c->alloc, count + 1, sizeof *pk->target_begin));
    pk->target_attributes = own(c, resurfi_alloc(c->alloc, n, sizeof *pk->target_attributes));
    if (!pk->target_begin || !pk->target_attributes)
        return oom(c);
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
            const char *name = own_string(c, attr);
            if (!data || !name)
                return oom(c);
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
            long long index = add_accessor(c, &acc);
            if (index < 0)
                return oom(c);
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
    draco_job now, *j = ahead ? &c->jobs[ahead - 1] : &now;
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
        if (j->enc.data && !own_from(c, j->enc.data, NULL)) /* malloc'ed by the Draco shim: the C heap */
            j->enc.data = NULL;
    }
    if (j->status != RESURF_OK)
        return resurfi_fail(c->error, j->status, c->path, 0, -1, "%s level %zu: %s", p->info.name, level,
                            j->message);
    if (!j->enc.data)
        return oom(c);
    resurfi_draco_output enc = j->enc;
    size_t points = j->points, faces = j->faces;
    const double *dlo = j->lo, *dhi = j->hi;

    out->draco = enc.data;
    out->draco_size = enc.size;
    out->attributes = own(c, resurfi_alloc(c->alloc, attr_count, sizeof *out->attributes));
    out->draco_ids = own(c, resurfi_alloc(c->alloc, attr_count, sizeof *out->draco_ids));
    if (!out->attributes || !out->draco_ids)
        return oom(c);
    for (size_t i = 0; i < attr_count; ++i) {
        resurfi_gltf_out_accessor a;
        memset(&a, 0, sizeof a);
        a.component_type = attrs[i].component_type;
        a.normalized = attrs[i].normalized;
        a.components = attrs[i].components;
        a.count = points;
        if (i == 0) {
            a.has_bounds = 1;
            for (int k = 0; k < 3; ++k)
                a.min[k] = dlo[k], a.max[k] = dhi[k];
        }
        const char *name = own_string(c, attrs[i].name);
        long long index = name ? add_accessor(c, &a) : -1;
        if (index < 0)
            return oom(c);
        out->attributes[i] = (resurfi_gltf_named){name, index};
        out->draco_ids[i] = (resurfi_gltf_named){name, enc.unique_ids[i]};
    }
    resurfi_gltf_out_accessor ia;
    memset(&ia, 0, sizeof ia);
    ia.component_type = points <= 65535 ? RESURFI_GLTF_UNSIGNED_SHORT : RESURFI_GLTF_UNSIGNED_INT;
    ia.components = 1;
    ia.count = 3 * (uint64_t)faces;
    if ((out->indices = add_accessor(c, &ia)) < 0)
        return oom(c);
    out->attribute_count = attr_count;
    out->bytes = enc.size;
    return RESURF_OK;
}

/* The level whose mesh primitive p shows at `level` (its last one when it has fewer). */
static size_t effective_level(const resurfi_scene_prim *p, size_t level)
{
    return level < p->lod_count ? level : p->lod_count;
}

/* Packs primitive `prim` at `level` (cached by the level it really shows). */
static resurf_status pack(save_ctx *c, size_t prim, size_t level, packed **out)
{
    const resurfi_scene_prim *p = &c->s->prims[prim];
    level = effective_level(p, level);
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
    unsigned char *values[sizeof attrs / sizeof *attrs];
    double min[4], max[4];
    size_t ahead = c->job_of ? c->job_of[prim * RESURF_SCENE_MAX_LEVELS + level] : 0;
    int made = ahead && c->jobs[ahead - 1].made; /* its payload needs no values any more */
    for (size_t i = 0; i < n && !made; ++i)
        if (!(values[i] = pack_attribute(c, &attrs[i], m->vertex_count, i == 0 ? min : NULL, i == 0 ? max : NULL)))
            return oom(c);
    int morphed = p->info.kind == RESURF_PRIMITIVE_MORPHED;
    resurf_status st = RESURF_OK;
    if (c->o->draco) {
        st = pack_draco(c, p, prim, level, m, attrs, n, values, morphed, pk);
        return st == RESURF_OK && morphed && !c->preparing ? pack_targets(c, p, m, pk) : st;
    }

    pk->attributes = own(c, resurfi_alloc(c->alloc, n, sizeof *pk->attributes));
    if (!pk->attributes)
        return oom(c);
    for (size_t i = 0; i < n; ++i) {
        resurfi_gltf_out_accessor a;
        memset(&a, 0, sizeof a);
        a.component_type = attrs[i].component_type;
        a.normalized = attrs[i].normalized;
        a.components = attrs[i].components;
        a.count = m->vertex_count;
        a.data = values[i];
        a.data_size = m->vertex_count * (size_t)a.components * resurfi_gltf_component_size(a.component_type);
        a.target = RESURFI_GLTF_ARRAY_BUFFER;
        if (i == 0) {
            a.has_bounds = 1;
            for (int k = 0; k < 3; ++k)
                a.min[k] = min[k], a.max[k] = max[k];
        }
        const char *name = own_string(c, attrs[i].name);
        long long index = name ? add_accessor(c, &a) : -1;
        if (index < 0)
            return oom(c);
        pk->attributes[i] = (resurfi_gltf_named){name, index};
        pk->bytes += a.data_size;
    }
    /* Unsigned short indices while they fit: 65535 itself is the primitive-restart value, never an index. */
    int wide = m->vertex_count > 65535;
    size_t isize = wide ? 4 : 2;
    unsigned char *idx = own(c, resurfi_alloc(c->alloc, 3 * m->triangle_count, isize));
    if (!idx)
        return oom(c);
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
    if ((pk->indices = add_accessor(c, &ia)) < 0)
        return oom(c);
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
static resurf_status encode_ahead(save_ctx *c)
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
        size_t first = c->o->level >= 0 ? effective_level(prim, (size_t)c->o->level) : 0;
        size_t last = c->o->level >= 0 ? first : prim->lod_count;
        for (size_t level = first; level <= last; ++level) {
            c->job_of[p * RESURF_SCENE_MAX_LEVELS + level] = ++k;
            packed *pk;
            (void)pack(c, p, level, &pk);
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
        if (j->enc.data && !own_from(c, j->enc.data, NULL)) /* malloc'ed by the Draco shim: the C heap */
            j->enc.data = NULL;
    }
    resurfi_free(c->alloc, order);
    if (atomic_load(&run.cancelled))
        return resurfi_fail(c->error, RESURF_ERR_CANCELLED, c->path, 0, -1, "cancelled by the progress callback");
    return RESURF_OK;
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
    resurfi_gltf_out_primitive *prims = own(c, resurfi_calloc(c->alloc, count, sizeof *prims));
    if (!prims)
        return oom(c);
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
        resurf_status status = pack(c, first + i, level, &pk);
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
        const double *w = s->doc ? s->world[node] : identity;
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
    long long *table = own(c, resurfi_alloc(c->alloc, levels * meshes + 1, sizeof *table));
    resurfi_gltf_out_mesh *out = own(c, resurfi_calloc(c->alloc, levels * meshes + 1, sizeof *out));
    double *coverage = own(c, resurfi_calloc(c->alloc, levels * meshes + 1, sizeof *coverage));
    if (!table || !out || !coverage)
        return oom(c);
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
        unsigned char *restructure = own(c, resurfi_calloc(c->alloc, s->view->node_count + 1, 1));
        if (!restructure)
            return oom(c);
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
    plan->quantization_used = s->quantized && c->verbatim_any;
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
            return oom(c);
        list->items = items;
        list->cap = cap;
    }
    char *copy = resurfi_strdup(c->alloc, path), *tmp = NULL;
    int fd = -1;
    if (!copy)
        return oom(c);
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
    resurfi_gltf_out_image *images = own(c, resurfi_calloc(c->alloc, s->image_count, sizeof *images));
    if (!images)
        return oom(c);
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
    c->draco_used = c->verbatim_any = 0;
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
                const packed *pk = &c->cache[i * RESURF_SCENE_MAX_LEVELS + effective_level(p, lv)];
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
    resurf_status status = pack(c, prim, level, &pk);
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
    c.cache = resurfi_alloc(c.alloc, scene->prim_count * RESURF_SCENE_MAX_LEVELS + 1, sizeof *c.cache);
    if (!c.cache)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
    resurf_status status = encode_ahead(&c);
    resurf_scene_save_report report;
    memset(&report, 0, sizeof report);
    report.levels = levels;
    pending_list *files = resurfi_calloc(c.alloc, 1, sizeof *files);
    if (status == RESURF_OK && !files)
        status = oom(&c);
    resurfi_gltf_layout layout = o.layout == RESURF_LOD_SIDE_BY_SIDE ? RESURFI_GLTF_SIDE_BY_SIDE
                                                                     : RESURFI_GLTF_MSFT_LOD;
    for (size_t k = 0; k < (per_file ? levels : 1) && status == RESURF_OK; ++k) {
        size_t name_size = resurf_scene_level_path(NULL, 0, path, (unsigned)k) + 1;
        char *name = resurfi_alloc(c.alloc, name_size, 1);
        if (!name) {
            status = oom(&c);
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
