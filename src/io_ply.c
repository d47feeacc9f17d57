/* Stanford PLY (Turk 1994), read and write: ascii, binary_little_endian and binary_big_endian.
 *
 * Reading: the header is parsed into elements and properties first; every count is then checked against the bytes
 * after the header (each element needs at least its fixed-size part in binary, 2 bytes per number in ASCII) before
 * anything is allocated, so a header that declares billions of elements cannot make resurf allocate for them.
 * The vertex element's x y z, nx ny nz, u v (or s t, texture_u texture_v, texture_s texture_t) and red green blue
 * [alpha] properties become positions, normals, texcoord set 0 and colours (8-bit integers /255, 16-bit /65535,
 * 32-bit /(2^32-1), floats as they are); its other scalar properties become one-component extra attributes named
 * after them. The face element's vertex_indices (or vertex_index) list is fan-triangulated. Every other element
 * and property, lists included, is skipped.
 *
 * Writing: binary little-endian by default. Positions, normals and texcoords are written as double, so they come
 * back bit-exact; colours as uchar (RGB or RGBA as color_components says); extras as float, one property per
 * component ("name" or "name_0", "name_1", ...). ASCII prints doubles with 17 significant digits. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_internal.h"

typedef enum ply_type { PLY_NONE = 0, PLY_I8, PLY_U8, PLY_I16, PLY_U16, PLY_I32, PLY_U32, PLY_F32, PLY_F64 } ply_type;

static const unsigned type_size[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};

static const struct {
    const char *name;
    ply_type type;
} type_names[] = {
    {"char", PLY_I8},   {"int8", PLY_I8},    {"uchar", PLY_U8},   {"uint8", PLY_U8},     {"short", PLY_I16},
    {"int16", PLY_I16}, {"ushort", PLY_U16}, {"uint16", PLY_U16}, {"int", PLY_I32},      {"int32", PLY_I32},
    {"uint", PLY_U32},  {"uint32", PLY_U32}, {"float", PLY_F32},  {"float32", PLY_F32},  {"double", PLY_F64},
    {"float64", PLY_F64},
};

/* What a property becomes. */
typedef enum ply_role {
    ROLE_SKIP = 0,
    ROLE_X, ROLE_Y, ROLE_Z,
    ROLE_NX, ROLE_NY, ROLE_NZ,
    ROLE_U, ROLE_V,
    ROLE_R, ROLE_G, ROLE_B, ROLE_A,
    ROLE_EXTRA,
    ROLE_INDICES,
    ROLE_COUNT
} ply_role;

typedef struct ply_prop {
    const char *name;
    size_t name_len;
    ply_type type;       /* the value type (the item type of a list) */
    ply_type count_type; /* PLY_NONE for a scalar */
    ply_role role;
    size_t extra;        /* ROLE_EXTRA: index into mesh->extras */
} ply_prop;

typedef enum ply_kind { KIND_OTHER, KIND_VERTEX, KIND_FACE } ply_kind;

typedef struct ply_element {
    const char *name;
    size_t name_len;
    uint64_t count;
    long long line;      /* of its "element" line */
    ply_kind kind;
    ply_prop *props;
    size_t prop_count, prop_cap;
} ply_element;

typedef enum ply_format { PLY_ASCII, PLY_LITTLE, PLY_BIG } ply_format;

typedef struct ply_reader {
    resurfi_load *ld;
    ply_format format;
    ply_element *elements;
    size_t element_count, element_cap;
    size_t body;          /* offset of the first byte after the header */
    resurfi_scanner s;    /* over the whole file; line numbers for ASCII */
    resurf_mesh *mesh;
    size_t nv;
    uint32_t *indices;    /* 3 per triangle */
    size_t ntri, tri_cap;
    double color_divisor[4]; /* divided, not multiplied by 1/255: byte k gives the double nearest k/255 */
    bool roles_seen[ROLE_COUNT];
} ply_reader;

static void reader_free(ply_reader *r)
{
    for (size_t i = 0; i < r->element_count; ++i)
        resurfi_free(r->ld->alloc, r->elements[i].props);
    resurfi_free(r->ld->alloc, r->elements);
    resurfi_free(r->ld->alloc, r->indices);
    resurf_mesh_free(r->mesh);
}

static bool token_is(const char *tok, size_t len, const char *word)
{
    return strlen(word) == len && memcmp(tok, word, len) == 0;
}

static ply_type parse_type(const char *tok, size_t len)
{
    for (size_t i = 0; i < sizeof type_names / sizeof *type_names; ++i)
        if (token_is(tok, len, type_names[i].name))
            return type_names[i].type;
    return PLY_NONE;
}

static bool is_integer_type(ply_type t) { return t >= PLY_I8 && t <= PLY_U32; }

/* ---- header -------------------------------------------------------------------------------------------------- */

static resurf_status header_fail(ply_reader *r, const char *fmt, ...) RESURFI_PRINTF(2, 3);
static resurf_status header_fail(ply_reader *r, const char *fmt, ...)
{
    char message[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message, sizeof message, fmt, ap);
    va_end(ap);
    return resurfi_parse_fail(r->ld, r->s.line, -1, "%s", message);
}

/* The role of a vertex property, by name. */
static ply_role vertex_role(const char *name, size_t len)
{
    static const struct {
        const char *name;
        ply_role role;
    } names[] = {
        {"x", ROLE_X},         {"y", ROLE_Y},         {"z", ROLE_Z},           {"nx", ROLE_NX},
        {"ny", ROLE_NY},       {"nz", ROLE_NZ},       {"u", ROLE_U},           {"v", ROLE_V},
        {"s", ROLE_U},         {"t", ROLE_V},         {"texture_u", ROLE_U},   {"texture_v", ROLE_V},
        {"texture_s", ROLE_U}, {"texture_t", ROLE_V}, {"red", ROLE_R},         {"green", ROLE_G},
        {"blue", ROLE_B},      {"alpha", ROLE_A},     {"diffuse_red", ROLE_R}, {"diffuse_green", ROLE_G},
        {"diffuse_blue", ROLE_B},
    };
    for (size_t i = 0; i < sizeof names / sizeof *names; ++i)
        if (token_is(name, len, names[i].name))
            return names[i].role;
    return ROLE_EXTRA;
}

static resurf_status parse_header(ply_reader *r)
{
    resurfi_scanner *s = &r->s;
    const char *tok;
    size_t len = resurfi_scan_token(s, &tok);
    s->p = tok + len;
    if (!token_is(tok, len, "ply") || !resurfi_scan_eol(s, 0))
        return header_fail(r, "not a PLY file (the first line is not \"ply\")");
    resurfi_scan_next_line(s);
    bool have_format = false;
    for (;;) {
        if (s->p >= s->end)
            return header_fail(r, "the header has no end_header line");
        len = resurfi_scan_token(s, &tok);
        if (len == 0) {
            resurfi_scan_next_line(s); /* a blank line: tolerated */
            continue;
        }
        s->p = tok + len;
        if (token_is(tok, len, "comment") || token_is(tok, len, "obj_info")) {
            resurfi_scan_next_line(s);
            continue;
        }
        if (token_is(tok, len, "end_header")) {
            if (!resurfi_scan_eol(s, 0))
                return header_fail(r, "unexpected text after end_header");
            resurfi_scan_next_line(s);
            break;
        }
        if (token_is(tok, len, "format")) {
            len = resurfi_scan_token(s, &tok);
            s->p = tok + len;
            if (token_is(tok, len, "ascii"))
                r->format = PLY_ASCII;
            else if (token_is(tok, len, "binary_little_endian"))
                r->format = PLY_LITTLE;
            else if (token_is(tok, len, "binary_big_endian"))
                r->format = PLY_BIG;
            else {
                char found[64];
                resurfi_describe_token(tok, s->end, found, sizeof found);
                return resurfi_fail(r->ld->error, RESURF_ERR_UNSUPPORTED, r->ld->path, s->line, -1,
                                    "unknown PLY format %s (ascii, binary_little_endian or binary_big_endian)",
                                    found);
            }
            have_format = true;
            resurfi_scan_next_line(s); /* the version ("1.0") is not checked */
            continue;
        }
        if (token_is(tok, len, "element")) {
            if (!have_format)
                return header_fail(r, "an element comes before the format line");
            ply_element e = {.line = s->line};
            e.name_len = resurfi_scan_token(s, &e.name);
            s->p = e.name + e.name_len;
            if (e.name_len == 0)
                return header_fail(r, "an element needs a name and a count");
            long long count;
            resurfi_num n = resurfi_scan_int(s, &count);
            if (n == RESURFI_NUM_RANGE)
                return header_fail(r, "the count of element %.*s is too large", (int)e.name_len, e.name);
            if (n != RESURFI_NUM_OK || count < 0) {
                char found[64];
                resurfi_describe_token(s->p, s->end, found, sizeof found);
                return header_fail(r, "expected the count of element %.*s, found %s", (int)e.name_len, e.name,
                                   found);
            }
            e.count = (uint64_t)count;
            e.kind = token_is(e.name, e.name_len, "vertex") ? KIND_VERTEX
                     : token_is(e.name, e.name_len, "face") ? KIND_FACE
                                                            : KIND_OTHER;
            for (size_t i = 0; i < r->element_count; ++i)
                if (e.kind != KIND_OTHER && r->elements[i].kind == e.kind)
                    return header_fail(r, "a second %.*s element", (int)e.name_len, e.name);
            if (r->element_count == r->element_cap) {
                size_t cap = r->element_cap ? 2 * r->element_cap : 4;
                ply_element *el = resurfi_realloc(r->ld->alloc, r->elements, cap, sizeof *el);
                if (!el)
                    return resurfi_load_oom(r->ld, "header");
                r->elements = el;
                r->element_cap = cap;
            }
            r->elements[r->element_count++] = e;
        } else if (token_is(tok, len, "property")) {
            if (r->element_count == 0)
                return header_fail(r, "a property comes before any element");
            ply_element *e = &r->elements[r->element_count - 1];
            ply_prop p = {0};
            len = resurfi_scan_token(s, &tok);
            s->p = tok + len;
            if (token_is(tok, len, "list")) {
                len = resurfi_scan_token(s, &tok);
                s->p = tok + len;
                p.count_type = parse_type(tok, len);
                if (!is_integer_type(p.count_type))
                    return header_fail(r, "a list's count type must be an integer type, found '%.*s'",
                                       (int)(len > 32 ? 32 : len), tok);
                len = resurfi_scan_token(s, &tok);
                s->p = tok + len;
            }
            p.type = parse_type(tok, len);
            if (p.type == PLY_NONE)
                return header_fail(r, "unknown property type '%.*s'", (int)(len > 32 ? 32 : len), tok);
            p.name_len = resurfi_scan_token(s, &p.name);
            s->p = p.name + p.name_len;
            if (p.name_len == 0)
                return header_fail(r, "a property needs a name");
            if (e->prop_count == e->prop_cap) {
                size_t cap = e->prop_cap ? 2 * e->prop_cap : 8;
                ply_prop *props = resurfi_realloc(r->ld->alloc, e->props, cap, sizeof *props);
                if (!props)
                    return resurfi_load_oom(r->ld, "header");
                e->props = props;
                e->prop_cap = cap;
            }
            e->props[e->prop_count++] = p;
        } else {
            char found[64];
            resurfi_describe_token(tok, s->end, found, sizeof found);
            return header_fail(r, "unknown header line starting with %s", found);
        }
        if (!resurfi_scan_eol(s, 0))
            return header_fail(r, "unexpected text at the end of the header line");
        resurfi_scan_next_line(s);
    }
    if (!have_format)
        return header_fail(r, "the header has no format line");
    r->body = (size_t)(s->p - r->ld->data);
    return RESURF_OK;
}

/* Gives each property of the vertex and face elements its role, checks what is required, and checks each
 * element's count against the bytes left for it. */
static resurf_status plan_elements(ply_reader *r)
{
    const long long body_line = r->s.line; /* header_fail reports r->s.line: set to each element's line below */
    /* The last ASCII number may lack its separator: one byte of slack. */
    size_t remaining = r->ld->size - r->body + (r->format == PLY_ASCII ? 1 : 0);
    for (size_t i = 0; i < r->element_count; ++i) {
        ply_element *e = &r->elements[i];
        uint64_t min_bytes = 0;
        bool have_indices = false;
        for (size_t k = 0; k < e->prop_count; ++k) {
            ply_prop *p = &e->props[k];
            bool list = p->count_type != PLY_NONE;
            min_bytes += r->format == PLY_ASCII ? 2 : type_size[list ? p->count_type : p->type];
            if (e->kind == KIND_VERTEX && !list) {
                p->role = vertex_role(p->name, p->name_len);
                if (p->role != ROLE_EXTRA && r->roles_seen[p->role])
                    p->role = ROLE_EXTRA; /* a second "x": kept as an extra attribute */
                r->roles_seen[p->role] = true;
            } else if (e->kind == KIND_FACE && !have_indices &&
                       (token_is(p->name, p->name_len, "vertex_indices") ||
                        token_is(p->name, p->name_len, "vertex_index"))) {
                if (!list || !is_integer_type(p->type)) {
                    r->s.line = e->line;
                    return header_fail(r, "the face property %.*s must be a list of integers", (int)p->name_len,
                                       p->name);
                }
                p->role = ROLE_INDICES;
                have_indices = true;
            }
        }
        r->s.line = e->line;
        if (e->kind == KIND_VERTEX && (!r->roles_seen[ROLE_X] || !r->roles_seen[ROLE_Y] || !r->roles_seen[ROLE_Z]))
            return header_fail(r, "the vertex element has no %s property",
                               !r->roles_seen[ROLE_X] ? "x" : !r->roles_seen[ROLE_Y] ? "y" : "z");
        if (e->kind == KIND_FACE && !have_indices)
            return header_fail(r, "the face element has no vertex_indices list");
        if (e->kind == KIND_VERTEX && e->count > UINT32_MAX - 1)
            return resurfi_fail(r->ld->error, RESURF_ERR_LIMIT, r->ld->path, e->line, -1, "more than %u vertices",
                                UINT32_MAX - 1);
        if (e->kind == KIND_FACE && e->count > 0) {
            resurf_status st = resurfi_check_triangle_limit(r->ld, e->count, e->line, -1);
            if (st != RESURF_OK)
                return st;
        }
        if (min_bytes && e->count > remaining / min_bytes)
            return header_fail(r, "the header declares %llu %.*s elements, more than the %zu bytes after it can hold",
                               (unsigned long long)e->count, (int)e->name_len, e->name, r->ld->size - r->body);
        remaining -= (size_t)(e->count * min_bytes);
        if (e->kind == KIND_VERTEX)
            r->nv = (size_t)e->count;
    }
    r->s.line = body_line;
    return RESURF_OK;
}

/* Creates the mesh with the attributes the vertex element holds; colour scales by the colour properties' types. */
static resurf_status create_mesh(ply_reader *r)
{
    const bool *seen = r->roles_seen;
    unsigned attrs = (seen[ROLE_NX] || seen[ROLE_NY] || seen[ROLE_NZ] ? RESURF_ATTR_NORMALS : 0) |
                     (seen[ROLE_U] || seen[ROLE_V] ? RESURF_ATTR_TEXCOORD0 : 0) |
                     (seen[ROLE_R] || seen[ROLE_G] || seen[ROLE_B] || seen[ROLE_A] ? RESURF_ATTR_COLORS : 0);
    if (resurf_mesh_create_with(r->nv, 0, attrs, r->ld->alloc, &r->mesh, NULL) != RESURF_OK)
        return resurfi_load_oom(r->ld, "vertices");
    resurf_mesh *m = r->mesh;
    if (m->colors) {
        m->color_components = seen[ROLE_A] ? 4 : 3;
        for (size_t v = 0; v < r->nv; ++v)
            m->colors[4 * v + 3] = 1.0;
    }
    for (size_t i = 0; i < r->element_count; ++i) {
        ply_element *e = &r->elements[i];
        if (e->kind != KIND_VERTEX)
            continue;
        for (size_t k = 0; k < e->prop_count; ++k) {
            ply_prop *p = &e->props[k];
            if (p->role >= ROLE_R && p->role <= ROLE_A) {
                static const double divisor[] = {1, 127, 255, 32767, 65535, 2147483647, 4294967295.0, 1, 1};
                r->color_divisor[p->role - ROLE_R] = divisor[p->type];
            }
            if (p->role != ROLE_EXTRA)
                continue;
            char name[64];
            snprintf(name, sizeof name, "%.*s", (int)p->name_len, p->name);
            p->extra = m->extra_count;
            if (resurf_mesh_add_extra(m, name, 1, NULL, NULL) != RESURF_OK)
                return resurfi_load_oom(r->ld, "vertex properties");
        }
    }
    /* Each face gives at least one triangle; polygons grow the array as they come. */
    size_t faces = 0;
    for (size_t i = 0; i < r->element_count; ++i)
        if (r->elements[i].kind == KIND_FACE)
            faces = (size_t)r->elements[i].count;
    r->tri_cap = faces;
    r->indices = resurfi_alloc(r->ld->alloc, faces, 3 * sizeof(uint32_t));
    if (!r->indices)
        return resurfi_load_oom(r->ld, "faces");
    return RESURF_OK;
}

/* ---- body ---------------------------------------------------------------------------------------------------- */

/* Stores one scalar vertex property value. */
static inline void store_vertex_value(ply_reader *r, const ply_prop *p, size_t v, double x)
{
    resurf_mesh *m = r->mesh;
    switch (p->role) {
    case ROLE_X: case ROLE_Y: case ROLE_Z: m->positions[3 * v + (p->role - ROLE_X)] = x; break;
    case ROLE_NX: case ROLE_NY: case ROLE_NZ: m->normals[3 * v + (p->role - ROLE_NX)] = x; break;
    case ROLE_U: case ROLE_V: m->texcoords[0][2 * v + (p->role - ROLE_U)] = x; break;
    case ROLE_R: case ROLE_G: case ROLE_B: case ROLE_A:
        m->colors[4 * v + (p->role - ROLE_R)] = x / r->color_divisor[p->role - ROLE_R];
        break;
    case ROLE_EXTRA: m->extras[p->extra].data[v] = (float)x; break;
    default: break;
    }
}

/* Adds the fan of a face whose n indices are at idx (already range-checked). */
static resurf_status add_face(ply_reader *r, const uint32_t *idx, size_t n, long long line, long long offset)
{
    size_t added = n - 2;
    resurf_status st = resurfi_check_triangle_limit(r->ld, r->ntri + added, line, offset);
    if (st != RESURF_OK)
        return st;
    if (r->ntri + added > r->tri_cap) {
        size_t cap = r->tri_cap + r->tri_cap / 2 + added + 16;
        uint32_t *p = resurfi_realloc(r->ld->alloc, r->indices, cap, 3 * sizeof(uint32_t));
        if (!p)
            return resurfi_load_oom(r->ld, "faces");
        r->indices = p;
        r->tri_cap = cap;
    }
    uint32_t *t = r->indices + 3 * r->ntri;
    for (size_t i = 1; i + 1 < n; ++i, t += 3)
        t[0] = idx[0], t[1] = idx[i], t[2] = idx[i + 1];
    r->ntri += added;
    return RESURF_OK;
}

static inline uint64_t load_bits(const unsigned char *p, unsigned size, bool big)
{
    uint64_t x = 0;
    if (big)
        for (unsigned i = 0; i < size; ++i)
            x = x << 8 | p[i];
    else
        for (unsigned i = size; i-- > 0;)
            x = x << 8 | p[i];
    return x;
}

static inline double binary_value(const unsigned char *p, ply_type t, bool big)
{
    switch (t) {
    case PLY_I8: return (int8_t)p[0];
    case PLY_U8: return p[0];
    case PLY_I16: return (int16_t)(uint16_t)load_bits(p, 2, big);
    case PLY_U16: return (uint16_t)load_bits(p, 2, big);
    case PLY_I32: return (int32_t)(uint32_t)load_bits(p, 4, big);
    case PLY_U32: return (uint32_t)load_bits(p, 4, big);
    case PLY_F32: {
        uint32_t u = (uint32_t)load_bits(p, 4, big);
        float f;
        memcpy(&f, &u, sizeof f);
        return f;
    }
    case PLY_F64: {
        uint64_t u = load_bits(p, 8, big);
        double d;
        memcpy(&d, &u, sizeof d);
        return d;
    }
    default: return 0;
    }
}

static inline long long binary_int(const unsigned char *p, ply_type t, bool big)
{
    switch (t) {
    case PLY_I8: return (int8_t)p[0];
    case PLY_U8: return p[0];
    case PLY_I16: return (int16_t)(uint16_t)load_bits(p, 2, big);
    case PLY_U16: return (uint16_t)load_bits(p, 2, big);
    case PLY_I32: return (int32_t)(uint32_t)load_bits(p, 4, big);
    case PLY_U32: return (uint32_t)load_bits(p, 4, big);
    default: return -1;
    }
}

static resurf_status read_binary_element(ply_reader *r, ply_element *e, const unsigned char **pp)
{
    const bool big = r->format == PLY_BIG;
    const unsigned char *base = (const unsigned char *)r->ld->data, *end = base + r->ld->size, *p = *pp;
    uint32_t small[64], *idx = small;
    size_t idx_cap = 64;
    resurf_status st = RESURF_OK;
    for (uint64_t i = 0; i < e->count && st == RESURF_OK; ++i) {
        if ((st = resurfi_load_tick(r->ld, (const char *)p)) != RESURF_OK)
            break;
        const long long at = (long long)(p - base);
        for (size_t k = 0; k < e->prop_count; ++k) {
            const ply_prop *q = &e->props[k];
            if (q->count_type == PLY_NONE) {
                if ((size_t)(end - p) < type_size[q->type]) {
                    st = resurfi_parse_fail(r->ld, 0, at, "the file ends inside %.*s %llu of %llu",
                                            (int)e->name_len, e->name, (unsigned long long)i,
                                            (unsigned long long)e->count);
                    break;
                }
                if (e->kind == KIND_VERTEX && q->role != ROLE_SKIP)
                    store_vertex_value(r, q, (size_t)i, binary_value(p, q->type, big));
                p += type_size[q->type];
                continue;
            }
            const unsigned cs = type_size[q->count_type], is = type_size[q->type];
            const bool room = (size_t)(end - p) >= cs;
            long long n = room ? binary_int(p, q->count_type, big) : 0;
            if (!room || (n >= 0 && (uint64_t)n > (uint64_t)(end - p - cs) / is)) {
                st = resurfi_parse_fail(r->ld, 0, at, "the file ends inside %.*s %llu of %llu", (int)e->name_len,
                                        e->name, (unsigned long long)i, (unsigned long long)e->count);
                break;
            }
            if (n < 0) {
                st = resurfi_parse_fail(r->ld, 0, at, "%.*s %llu has a list of negative length %lld",
                                        (int)e->name_len, e->name, (unsigned long long)i, n);
                break;
            }
            p += cs;
            if (q->role == ROLE_INDICES) {
                if (n < 3) {
                    st = resurfi_parse_fail(r->ld, 0, at, "face %llu has %lld vertices, at least 3 are needed",
                                            (unsigned long long)i, n);
                    break;
                }
                if ((size_t)n > idx_cap) {
                    uint32_t *bigger = resurfi_alloc(r->ld->alloc, (size_t)n, sizeof *bigger);
                    if (!bigger) {
                        st = resurfi_load_oom(r->ld, "faces");
                        break;
                    }
                    if (idx != small)
                        resurfi_free(r->ld->alloc, idx);
                    idx = bigger;
                    idx_cap = (size_t)n;
                }
                for (long long j = 0; j < n; ++j) {
                    long long v = binary_int(p + (size_t)j * is, q->type, big);
                    if (v < 0 || (unsigned long long)v >= r->nv) {
                        st = resurfi_parse_fail(r->ld, 0, at, "face %llu refers to vertex %lld of %zu",
                                                (unsigned long long)i, v, r->nv);
                        break;
                    }
                    idx[j] = (uint32_t)v;
                }
                if (st == RESURF_OK)
                    st = add_face(r, idx, (size_t)n, 0, at);
                if (st != RESURF_OK)
                    break;
            }
            p += (size_t)n * is;
        }
        if (st == RESURF_OK && e->kind == KIND_VERTEX) {
            const double *x = r->mesh->positions + 3 * (size_t)i;
            if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2]))
                st = resurfi_parse_fail(r->ld, 0, at, "vertex %llu has a non-finite coordinate",
                                        (unsigned long long)i);
        }
    }
    if (idx != small)
        resurfi_free(r->ld->alloc, idx);
    *pp = p;
    return st;
}

/* The next ASCII number, across line ends; fails naming the element when there is none. */
static resurf_status ascii_value(ply_reader *r, const ply_element *e, uint64_t i, double *out)
{
    resurfi_scanner *s = &r->s;
    if (!resurfi_scan_skip_space(s, 0))
        return resurfi_parse_fail(r->ld, s->line, -1, "the file ends inside %.*s %llu of %llu", (int)e->name_len,
                                  e->name, (unsigned long long)i, (unsigned long long)e->count);
    if (resurfi_scan_double(s, out) != RESURFI_NUM_OK) {
        char found[64];
        resurfi_describe_token(s->p, s->end, found, sizeof found);
        return resurfi_parse_fail(r->ld, s->line, -1, "expected a number, found %s", found);
    }
    return RESURF_OK;
}

static resurf_status ascii_int(ply_reader *r, const ply_element *e, uint64_t i, long long *out)
{
    resurfi_scanner *s = &r->s;
    if (!resurfi_scan_skip_space(s, 0))
        return resurfi_parse_fail(r->ld, s->line, -1, "the file ends inside %.*s %llu of %llu", (int)e->name_len,
                                  e->name, (unsigned long long)i, (unsigned long long)e->count);
    resurfi_num n = resurfi_scan_int(s, out);
    if (n == RESURFI_NUM_RANGE) {
        *out = LLONG_MAX;
        return RESURF_OK; /* callers report it as out of range */
    }
    if (n != RESURFI_NUM_OK) {
        char found[64];
        resurfi_describe_token(s->p, s->end, found, sizeof found);
        return resurfi_parse_fail(r->ld, s->line, -1, "expected an integer, found %s", found);
    }
    return RESURF_OK;
}

static resurf_status read_ascii_element(ply_reader *r, ply_element *e)
{
    resurfi_scanner *s = &r->s;
    uint32_t small[64], *idx = small;
    size_t idx_cap = 64;
    resurf_status st = RESURF_OK;
    for (uint64_t i = 0; i < e->count && st == RESURF_OK; ++i) {
        if ((st = resurfi_load_tick(r->ld, s->p)) != RESURF_OK)
            break;
        resurfi_scan_skip_space(s, 0);
        const long long line = s->line;
        for (size_t k = 0; k < e->prop_count && st == RESURF_OK; ++k) {
            const ply_prop *q = &e->props[k];
            if (q->count_type == PLY_NONE) {
                double x;
                if ((st = ascii_value(r, e, i, &x)) != RESURF_OK)
                    break;
                if (e->kind == KIND_VERTEX && q->role != ROLE_SKIP)
                    store_vertex_value(r, q, (size_t)i, x);
                continue;
            }
            long long n;
            if ((st = ascii_int(r, e, i, &n)) != RESURF_OK)
                break;
            if (n < 0) {
                st = resurfi_parse_fail(r->ld, s->line, -1, "%.*s %llu has a list of negative length %lld",
                                        (int)e->name_len, e->name, (unsigned long long)i, n);
                break;
            }
            /* Every item takes at least 2 bytes: a longer list cannot fit (and must not be allocated for). */
            if ((unsigned long long)n > (size_t)(s->end - s->p) / 2 + 1) {
                st = resurfi_parse_fail(r->ld, s->line, -1, "the file ends inside %.*s %llu of %llu",
                                        (int)e->name_len, e->name, (unsigned long long)i,
                                        (unsigned long long)e->count);
                break;
            }
            if (q->role != ROLE_INDICES) {
                for (long long j = 0; j < n && st == RESURF_OK; ++j) {
                    double x;
                    st = ascii_value(r, e, i, &x);
                }
                continue;
            }
            if (n < 3) {
                st = resurfi_parse_fail(r->ld, s->line, -1, "face %llu has %lld vertices, at least 3 are needed",
                                        (unsigned long long)i, n);
                break;
            }
            if ((size_t)n > idx_cap) {
                uint32_t *bigger = resurfi_alloc(r->ld->alloc, (size_t)n, sizeof *bigger);
                if (!bigger) {
                    st = resurfi_load_oom(r->ld, "faces");
                    break;
                }
                if (idx != small)
                    resurfi_free(r->ld->alloc, idx);
                idx = bigger;
                idx_cap = (size_t)n;
            }
            for (long long j = 0; j < n; ++j) {
                long long v;
                if ((st = ascii_int(r, e, i, &v)) != RESURF_OK)
                    break;
                if (v < 0 || (unsigned long long)v >= r->nv) {
                    st = resurfi_parse_fail(r->ld, s->line, -1, "face %llu refers to vertex %lld of %zu",
                                            (unsigned long long)i, v, r->nv);
                    break;
                }
                idx[j] = (uint32_t)v;
            }
            if (st == RESURF_OK)
                st = add_face(r, idx, (size_t)n, s->line, -1);
        }
        if (st == RESURF_OK && e->kind == KIND_VERTEX) {
            const double *x = r->mesh->positions + 3 * (size_t)i;
            if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2]))
                st = resurfi_parse_fail(r->ld, line, -1, "vertex %llu has a non-finite coordinate",
                                        (unsigned long long)i);
        }
    }
    if (idx != small)
        resurfi_free(r->ld->alloc, idx);
    return st;
}

resurf_status resurfi_read_ply(resurfi_load *ld, resurf_mesh **out)
{
    ply_reader r;
    memset(&r, 0, sizeof r);
    r.ld = ld;
    resurfi_scan_init(&r.s, ld->data, ld->size);
    resurf_status st = parse_header(&r);
    if (st == RESURF_OK)
        st = plan_elements(&r);
    if (st == RESURF_OK)
        st = create_mesh(&r);
    const unsigned char *p = (const unsigned char *)ld->data + r.body;
    for (size_t i = 0; i < r.element_count && st == RESURF_OK; ++i) {
        ply_element *e = &r.elements[i];
        if (e->prop_count == 0)
            continue; /* nothing to read, however large the count */
        if (r.format == PLY_ASCII)
            st = read_ascii_element(&r, e);
        else
            st = read_binary_element(&r, e, &p);
    }
    if (st == RESURF_OK) {
        resurf_mesh *m = r.mesh;
        resurfi_free(ld->alloc, m->indices);
        m->indices = r.indices;
        m->triangle_count = r.ntri;
        r.indices = NULL;
        r.mesh = NULL;
        *out = m;
    }
    reader_free(&r);
    return st;
}

/* ---- writing ------------------------------------------------------------------------------------------------- */

static unsigned char color_byte(double c)
{
    if (!(c > 0))
        return 0;
    if (c >= 1)
        return 255;
    return (unsigned char)(c * 255 + 0.5);
}

/* A property name without blanks (PLY names are single tokens). */
static void extra_name(char *dst, size_t size, const resurf_attribute *a, size_t index, unsigned component)
{
    if (a->name[0] && a->components == 1)
        snprintf(dst, size, "%s", a->name);
    else if (a->name[0])
        snprintf(dst, size, "%s_%u", a->name, component);
    else if (a->components == 1)
        snprintf(dst, size, "extra%zu", index);
    else
        snprintf(dst, size, "extra%zu_%u", index, component);
    for (char *c = dst; *c; ++c)
        if ((unsigned char)*c <= ' ' || *c == 0x7f)
            *c = '_';
}

resurf_status resurfi_write_ply(resurfi_writer *w, const resurf_mesh *m, const resurf_save_options *o)
{
    const bool binary = o->binary != 0;
    const bool normals = o->write_normals && m->normals;
    const bool tex = o->write_texcoords && m->texcoord_count > 0 && m->texcoords[0];
    const bool colors = o->write_colors && m->colors;
    const unsigned cc = m->color_components == 3 ? 3 : 4;
    const size_t extras = o->write_extras && m->extras ? m->extra_count : 0;
    const size_t nv = m->vertex_count, nt = m->triangle_count;
    const bool big_index = nv > INT32_MAX;

    resurfi_writef(w, "ply\nformat %s 1.0\ncomment written by resurf %s\nelement vertex %zu\n",
                   binary ? "binary_little_endian" : "ascii", RESURF_VERSION_STRING, nv);
    resurfi_write_str(w, "property double x\nproperty double y\nproperty double z\n");
    if (normals)
        resurfi_write_str(w, "property double nx\nproperty double ny\nproperty double nz\n");
    if (tex)
        resurfi_write_str(w, "property double s\nproperty double t\n");
    if (colors)
        resurfi_write_str(w, cc == 4 ? "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                                       "property uchar alpha\n"
                                     : "property uchar red\nproperty uchar green\nproperty uchar blue\n");
    for (size_t i = 0; i < extras; ++i)
        for (unsigned c = 0; c < m->extras[i].components; ++c) {
            char name[80];
            extra_name(name, sizeof name, &m->extras[i], i, c);
            resurfi_writef(w, "property float %s\n", name);
        }
    resurfi_writef(w, "element face %zu\nproperty list uchar %s vertex_indices\nend_header\n", nt,
                   big_index ? "uint" : "int");

    for (size_t v = 0; v < nv; ++v) {
        resurfi_write_tick(w, v, nv + nt);
        double d[8];
        int nd = 0;
        for (int a = 0; a < 3; ++a)
            d[nd++] = m->positions[3 * v + a];
        for (int a = 0; normals && a < 3; ++a)
            d[nd++] = m->normals[3 * v + a];
        for (int a = 0; tex && a < 2; ++a)
            d[nd++] = m->texcoords[0][2 * v + a];
        if (binary) {
            unsigned char buf[8 * 8 + 4];
            size_t n = 0;
            for (int a = 0; a < nd; ++a, n += 8) {
                uint64_t u;
                memcpy(&u, &d[a], sizeof u);
                resurfi_put_u64le(buf + n, u);
            }
            for (unsigned a = 0; colors && a < cc; ++a)
                buf[n++] = color_byte(m->colors[4 * v + a]);
            resurfi_write(w, buf, n);
            for (size_t i = 0; i < extras; ++i)
                for (unsigned c = 0; c < m->extras[i].components; ++c) {
                    float f = m->extras[i].data[(size_t)m->extras[i].components * v + c];
                    uint32_t u;
                    memcpy(&u, &f, sizeof u);
                    resurfi_put_u32le(buf, u);
                    resurfi_write(w, buf, 4);
                }
        } else {
            for (int a = 0; a < nd; ++a)
                resurfi_write_double(w, a ? ' ' : 0, d[a]);
            for (unsigned a = 0; colors && a < cc; ++a)
                resurfi_write_uint(w, ' ', color_byte(m->colors[4 * v + a]));
            for (size_t i = 0; i < extras; ++i)
                for (unsigned c = 0; c < m->extras[i].components; ++c)
                    resurfi_write_float9(w, ' ', m->extras[i].data[(size_t)m->extras[i].components * v + c]);
            resurfi_write(w, "\n", 1);
        }
    }
    for (size_t t = 0; t < nt; ++t) {
        resurfi_write_tick(w, nv + t, nv + nt);
        const uint32_t *tri = m->indices + 3 * t;
        if (binary) {
            unsigned char buf[13];
            buf[0] = 3;
            for (int c = 0; c < 3; ++c)
                resurfi_put_u32le(buf + 1 + 4 * c, tri[c]);
            resurfi_write(w, buf, sizeof buf);
        } else {
            resurfi_write(w, "3", 1);
            for (int c = 0; c < 3; ++c)
                resurfi_write_uint(w, ' ', tri[c]);
            resurfi_write(w, "\n", 1);
        }
    }
    return RESURF_OK;
}
