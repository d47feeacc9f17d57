/* Wavefront OBJ, read and write (the polygonal subset of the format: v, vt, vn, f, o/g/usemtl).
 *
 * OBJ indexes positions, texture coordinates and normals separately; resurf has one index per corner. Each
 * distinct (v, vt, vn) triple used by a face becomes one resurf vertex. Most positions are used with a single
 * triple, so the first triple of each position sits in an array indexed by the position (no hashing); further
 * triples at the same position (seams) go to an open-addressing hash table. When no position has a second
 * triple, resurf vertex i is OBJ vertex i (order and unreferenced vertices kept, so a saved file reads back
 * identically); otherwise vertices follow the order in which faces first use the triples, then the unused positions.
 *
 * Indices must refer to elements defined above the face (negative ones count back from the last one), as the
 * format specifies; this keeps the check exact and streaming. Extensions read: "v x y z r g b [a]" vertex colours.
 * Statements resurf does not use (mtllib, s, l, p, curves...) are skipped. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_internal.h"

#define NONE UINT32_MAX
#define INDEX_TOO_LARGE (1ll << 40) /* beyond any count resurf can hold */

typedef struct obj_slot {
    uint32_t v, vt, vn, key; /* key NONE: empty */
} obj_slot;

typedef struct obj_name_slot {
    uint64_t hash;
    uint32_t group; /* NONE: empty */
} obj_name_slot;

typedef struct obj_reader {
    resurfi_load *ld;
    resurfi_scanner s;
    double *pos;                 /* 3 per position */
    double *col;                 /* 4 per position, once a colour is seen */
    uint32_t *direct;            /* per position: its first key, or NONE */
    size_t nv, pos_cap;
    bool colors, alpha;
    double *tex;                 /* 2 per vt */
    size_t nvt, tex_cap;
    double *nrm;                 /* 3 per vn */
    size_t nvn, nrm_cap;
    uint32_t *key_v, *key_vt, *key_vn; /* the distinct triples, NONE for an absent vt/vn */
    size_t nkeys, key_cap;
    obj_slot *table;             /* triples that are not their position's first */
    size_t table_cap, table_used;
    uint32_t *tri;               /* 3 keys per triangle */
    size_t ntri, tri_cap;
    uint32_t *tri_group;         /* per triangle, once a group statement is seen */
    size_t tri_group_cap;
    uint32_t *face;              /* the keys of the face being read */
    size_t face_cap;
    char **names;                /* group names */
    size_t group_count, names_cap;
    obj_name_slot *name_table;
    size_t name_table_cap;
    bool grouped;                /* a group statement was seen */
    const char *pending;         /* name of the last group statement, not yet used by a face */
    size_t pending_len;
    bool has_pending;
    uint32_t group;              /* the current group */
} obj_reader;

/* Grows the array whose pointer is at `array` (any T **; elements of elem bytes, capacity *cap) to hold need
 * elements. The pointer is read and written with memcpy, which is valid for every object pointer type (POSIX
 * gives them one representation), where a cast to void ** would break the aliasing rules. */
static bool grow(const resurf_allocator *alloc, void *array, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap)
        return true;
    size_t n = *cap ? *cap : 256;
    while (n < need)
        n = n > SIZE_MAX / 4 ? need : n + n / 2 + n / 4;
    void *p;
    memcpy(&p, array, sizeof p);
    void *q = resurfi_realloc(alloc, p, n, elem);
    if (!q)
        return false;
    memcpy(array, &q, sizeof q);
    *cap = n;
    return true;
}

static uint64_t hash3(uint32_t a, uint32_t b, uint32_t c)
{
    uint64_t h = ((uint64_t)a << 32 | b) * 0x9e3779b97f4a7c15ull;
    h ^= (uint64_t)c * 0xc2b2ae3d27d4eb4full;
    h ^= h >> 29;
    h *= 0xbf58476d1ce4e5b9ull;
    return h ^ (h >> 32);
}

static uint64_t hash_name(const char *s, size_t n)
{
    uint64_t h = 0xcbf29ce484222325ull; /* FNV-1a */
    for (size_t i = 0; i < n; ++i)
        h = (h ^ (unsigned char)s[i]) * 0x100000001b3ull;
    return h;
}

static void reader_free(obj_reader *r)
{
    resurfi_free(r->ld->alloc, r->pos);
    resurfi_free(r->ld->alloc, r->col);
    resurfi_free(r->ld->alloc, r->direct);
    resurfi_free(r->ld->alloc, r->tex);
    resurfi_free(r->ld->alloc, r->nrm);
    resurfi_free(r->ld->alloc, r->key_v);
    resurfi_free(r->ld->alloc, r->key_vt);
    resurfi_free(r->ld->alloc, r->key_vn);
    resurfi_free(r->ld->alloc, r->table);
    resurfi_free(r->ld->alloc, r->tri);
    resurfi_free(r->ld->alloc, r->tri_group);
    resurfi_free(r->ld->alloc, r->face);
    for (size_t i = 0; i < r->group_count; ++i)
        resurfi_free(r->ld->alloc, r->names[i]);
    resurfi_free(r->ld->alloc, r->names);
    resurfi_free(r->ld->alloc, r->name_table);
}

static resurf_status fail(obj_reader *r, const char *fmt, ...) RESURFI_PRINTF(2, 3);
static resurf_status fail(obj_reader *r, const char *fmt, ...)
{
    char message[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message, sizeof message, fmt, ap);
    va_end(ap);
    return resurfi_parse_fail(r->ld, r->s.line, -1, "%s", message);
}

static resurf_status fail_token(obj_reader *r, const char *expected)
{
    char found[64];
    resurfi_describe_token(r->s.p, r->s.end, found, sizeof found);
    return fail(r, "expected %s, found %s", expected, found);
}

/* Reads up to max numbers to the end of the line into x; returns how many, or -1 after failing. */
static int read_numbers(obj_reader *r, double *x, int max, const char *what)
{
    int n = 0;
    while (!resurfi_scan_eol(&r->s, '#')) {
        if (n == max) {
            fail(r, "too many numbers for %s (at most %d)", what, max);
            return -1;
        }
        if (resurfi_scan_double(&r->s, &x[n]) != RESURFI_NUM_OK) {
            fail_token(r, "a number");
            return -1;
        }
        ++n;
    }
    return n;
}

/* ---- statements ---------------------------------------------------------------------------------------------- */

static resurf_status read_vertex(obj_reader *r)
{
    double x[7];
    int n = read_numbers(r, x, 7, "a vertex (x y z [w] or x y z r g b [a])");
    if (n < 0)
        return RESURF_ERR_PARSE;
    if (n < 3)
        return fail(r, "a vertex needs 3 coordinates, found %d", n);
    if (n == 5)
        return fail(r, "a vertex has 3, 4, 6 or 7 numbers (x y z [w] or x y z r g b [a]), found 5");
    if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2]))
        return fail(r, "vertex %zu has a non-finite coordinate", r->nv + 1);
    if (r->nv >= NONE - 1)
        return resurfi_fail(r->ld->error, RESURF_ERR_LIMIT, r->ld->path, r->s.line, -1, "more than %u vertices",
                            NONE - 1);
    if (r->nv == r->pos_cap) {
        /* positions, their first keys and their colours share one capacity */
        size_t cap = r->pos_cap;
        if (!grow(r->ld->alloc, &r->pos, &cap, r->nv + 1, 3 * sizeof(double)))
            return resurfi_load_oom(r->ld, "vertices");
        uint32_t *direct = resurfi_realloc(r->ld->alloc, r->direct, cap, sizeof(uint32_t));
        if (direct)
            r->direct = direct;
        double *col = r->col ? resurfi_realloc(r->ld->alloc, r->col, cap, 4 * sizeof(double)) : NULL;
        if (col)
            r->col = col;
        if (!direct || (r->col && !col))
            return resurfi_load_oom(r->ld, "vertices");
        r->pos_cap = cap;
    }
    if (n >= 6 && !r->col) {
        /* The first coloured vertex: earlier ones are white. */
        r->col = resurfi_alloc(r->ld->alloc, r->pos_cap, 4 * sizeof(double));
        if (!r->col)
            return resurfi_load_oom(r->ld, "vertex colours");
        for (size_t i = 0; i < 4 * r->nv; ++i)
            r->col[i] = 1.0;
        r->colors = true;
    }
    memcpy(r->pos + 3 * r->nv, x, 3 * sizeof(double));
    r->direct[r->nv] = NONE;
    if (r->col) {
        double *c = r->col + 4 * r->nv;
        if (n >= 6) {
            c[0] = x[3], c[1] = x[4], c[2] = x[5], c[3] = n == 7 ? x[6] : 1.0;
            r->alpha |= n == 7;
        } else
            c[0] = c[1] = c[2] = c[3] = 1.0;
    }
    ++r->nv;
    return RESURF_OK;
}

static resurf_status read_texcoord(obj_reader *r)
{
    double x[3] = {0, 0, 0};
    int n = read_numbers(r, x, 3, "a texture coordinate (u [v [w]])");
    if (n < 0)
        return RESURF_ERR_PARSE;
    if (n < 1)
        return fail(r, "a texture coordinate needs at least 1 number, found 0");
    if (r->nvt >= NONE - 1)
        return resurfi_fail(r->ld->error, RESURF_ERR_LIMIT, r->ld->path, r->s.line, -1,
                            "more than %u texture coordinates", NONE - 1);
    if (!grow(r->ld->alloc, &r->tex, &r->tex_cap, r->nvt + 1, 2 * sizeof(double)))
        return resurfi_load_oom(r->ld, "texture coordinates");
    r->tex[2 * r->nvt] = x[0];
    r->tex[2 * r->nvt + 1] = x[1];
    ++r->nvt;
    return RESURF_OK;
}

static resurf_status read_normal(obj_reader *r)
{
    double x[3];
    int n = read_numbers(r, x, 3, "a normal");
    if (n < 0)
        return RESURF_ERR_PARSE;
    if (n < 3)
        return fail(r, "a normal needs 3 numbers, found %d", n);
    if (r->nvn >= NONE - 1)
        return resurfi_fail(r->ld->error, RESURF_ERR_LIMIT, r->ld->path, r->s.line, -1, "more than %u normals",
                            NONE - 1);
    if (!grow(r->ld->alloc, &r->nrm, &r->nrm_cap, r->nvn + 1, 3 * sizeof(double)))
        return resurfi_load_oom(r->ld, "normals");
    memcpy(r->nrm + 3 * r->nvn, x, 3 * sizeof(double));
    ++r->nvn;
    return RESURF_OK;
}

/* A new key for (v, vt, vn), or NONE when out of memory or of key space. */
static uint32_t add_key(obj_reader *r, uint32_t v, uint32_t vt, uint32_t vn)
{
    if (r->nkeys >= NONE - 1)
        return NONE;
    if (r->nkeys == r->key_cap) {
        size_t c1 = r->key_cap, c2 = r->key_cap, c3 = r->key_cap;
        if (!grow(r->ld->alloc, &r->key_v, &c1, r->nkeys + 1, sizeof(uint32_t)) ||
            !grow(r->ld->alloc, &r->key_vt, &c2, r->nkeys + 1, sizeof(uint32_t)) ||
            !grow(r->ld->alloc, &r->key_vn, &c3, r->nkeys + 1, sizeof(uint32_t)))
            return NONE;
        r->key_cap = c1 < c2 ? (c1 < c3 ? c1 : c3) : (c2 < c3 ? c2 : c3);
    }
    r->key_v[r->nkeys] = v;
    r->key_vt[r->nkeys] = vt;
    r->key_vn[r->nkeys] = vn;
    return (uint32_t)r->nkeys++;
}

/* Doubles the seam table (or creates it). */
static bool grow_table(obj_reader *r)
{
    size_t cap = r->table_cap ? 2 * r->table_cap : 1024;
    obj_slot *t = resurfi_alloc(r->ld->alloc, cap, sizeof *t);
    if (!t)
        return false;
    for (size_t i = 0; i < cap; ++i)
        t[i].key = NONE;
    for (size_t i = 0; i < r->table_cap; ++i) {
        obj_slot e = r->table[i];
        if (e.key == NONE)
            continue;
        size_t j = (size_t)hash3(e.v, e.vt, e.vn) & (cap - 1);
        while (t[j].key != NONE)
            j = (j + 1) & (cap - 1);
        t[j] = e;
    }
    resurfi_free(r->ld->alloc, r->table);
    r->table = t;
    r->table_cap = cap;
    return true;
}

/* The key of (v, vt, vn), created on first use; NONE when out of memory. */
static uint32_t key_of(obj_reader *r, uint32_t v, uint32_t vt, uint32_t vn)
{
    uint32_t k = r->direct[v];
    if (k == NONE)
        return r->direct[v] = add_key(r, v, vt, vn);
    if (r->key_vt[k] == vt && r->key_vn[k] == vn)
        return k;
    if (2 * (r->table_used + 1) > r->table_cap && !grow_table(r))
        return NONE;
    size_t mask = r->table_cap - 1, j = (size_t)hash3(v, vt, vn) & mask;
    for (;; j = (j + 1) & mask) {
        obj_slot *e = &r->table[j];
        if (e->key == NONE) {
            k = add_key(r, v, vt, vn);
            if (k != NONE) {
                *e = (obj_slot){v, vt, vn, k};
                ++r->table_used;
            }
            return k;
        }
        if (e->v == v && e->vt == vt && e->vn == vn)
            return e->key;
    }
}

/* Parses an index (optional sign, digits) at *pp without skipping blanks; false when none starts there. */
static inline bool parse_index(const char **pp, const char *end, long long *out)
{
    const char *p = *pp;
    bool negative = false;
    if (p < end && (*p == '-' || *p == '+'))
        negative = *p++ == '-';
    if (p >= end || (unsigned)(*p - '0') >= 10)
        return false;
    long long v = 0;
    for (; p < end && (unsigned)(*p - '0') < 10; ++p)
        v = v < INDEX_TOO_LARGE ? v * 10 + (*p - '0') : INDEX_TOO_LARGE; /* saturates: no overflow */
    *pp = p;
    *out = negative ? -v : v;
    return true;
}

/* The 0-based element an OBJ index names, given count elements defined so far; false when out of range. */
static inline bool resolve(long long index, size_t count, uint32_t *out)
{
    if (index > 0 && (unsigned long long)index <= count) {
        *out = (uint32_t)(index - 1);
        return true;
    }
    if (index < 0 && (unsigned long long)-index <= count) {
        *out = (uint32_t)(count - (size_t)-index);
        return true;
    }
    return false;
}

static resurf_status fail_index(obj_reader *r, long long index, const char *what, const char *plural, size_t count)
{
    if (index == 0)
        return fail(r, "%s index 0 is not valid (OBJ counts from 1)", what);
    if (index >= INDEX_TOO_LARGE || index <= -INDEX_TOO_LARGE)
        return fail(r, "face refers to a %s index too large to be valid", what);
    if (count == 0)
        return fail(r, "face refers to %s %lld, but no %s are defined above it", what, index, plural);
    return fail(r, "face refers to %s %lld, but only %zu %s %s defined above it", what, index, count,
                count == 1 ? what : plural, count == 1 ? "is" : "are");
}

/* The group id of a name, created on first use; NONE when out of memory. */
static uint32_t group_of(obj_reader *r, const char *name, size_t len)
{
    if (len == 0)
        name = "default", len = 7;
    uint64_t h = hash_name(name, len);
    if (2 * (r->group_count + 1) > r->name_table_cap) {
        size_t cap = r->name_table_cap ? 2 * r->name_table_cap : 64;
        obj_name_slot *t = resurfi_alloc(r->ld->alloc, cap, sizeof *t);
        if (!t)
            return NONE;
        for (size_t i = 0; i < cap; ++i)
            t[i].group = NONE;
        for (size_t i = 0; i < r->name_table_cap; ++i) {
            if (r->name_table[i].group == NONE)
                continue;
            size_t j = (size_t)r->name_table[i].hash & (cap - 1);
            while (t[j].group != NONE)
                j = (j + 1) & (cap - 1);
            t[j] = r->name_table[i];
        }
        resurfi_free(r->ld->alloc, r->name_table);
        r->name_table = t;
        r->name_table_cap = cap;
    }
    size_t mask = r->name_table_cap - 1, j = (size_t)h & mask;
    for (;; j = (j + 1) & mask) {
        obj_name_slot *e = &r->name_table[j];
        if (e->group == NONE)
            break;
        if (e->hash == h && strlen(r->names[e->group]) == len && memcmp(r->names[e->group], name, len) == 0)
            return e->group;
    }
    if (!grow(r->ld->alloc, &r->names, &r->names_cap, r->group_count + 1, sizeof(char *)))
        return NONE;
    char *copy = resurfi_alloc(r->ld->alloc, len + 1, 1);
    if (!copy)
        return NONE;
    memcpy(copy, name, len);
    copy[len] = 0;
    r->names[r->group_count] = copy;
    r->name_table[j] = (obj_name_slot){h, (uint32_t)r->group_count};
    return (uint32_t)r->group_count++;
}

/* o NAME, g NAME..., usemtl NAME: the faces that follow form the group of that name. */
static resurf_status read_group(obj_reader *r)
{
    resurfi_scan_blanks(&r->s);
    const char *start = r->s.p, *q = start;
    while (q < r->s.end && *q != '\n')
        ++q;
    const char *stop = q;
    while (stop > start && resurfi_is_blank(stop[-1]))
        --stop;
    r->s.p = q;
    if (!r->grouped) {
        /* Faces before the first group statement form the group "default". */
        r->grouped = true;
        if (!grow(r->ld->alloc, &r->tri_group, &r->tri_group_cap, r->tri_cap, sizeof(uint32_t)))
            return resurfi_load_oom(r->ld, "groups");
        if (r->ntri) {
            uint32_t g = group_of(r, "default", 7);
            if (g == NONE)
                return resurfi_load_oom(r->ld, "groups");
            for (size_t t = 0; t < r->ntri; ++t)
                r->tri_group[t] = g;
        }
    }
    r->pending = start;
    r->pending_len = (size_t)(stop - start);
    r->has_pending = true;
    return RESURF_OK;
}

static resurf_status read_face(obj_reader *r)
{
    resurfi_scanner *s = &r->s;
    size_t corners = 0;
    while (!resurfi_scan_eol(s, '#')) {
        long long iv, ivt = 0, ivn = 0;
        bool has_vt = false, has_vn = false;
        const char *p = s->p;
        if (!parse_index(&p, s->end, &iv))
            return fail_token(r, "a vertex index");
        uint32_t v, vt = NONE, vn = NONE;
        if (p < s->end && *p == '/') {
            ++p;
            if (p < s->end && *p != '/') {
                if (!parse_index(&p, s->end, &ivt)) {
                    s->p = p;
                    return fail_token(r, "a texture coordinate index");
                }
                has_vt = true;
            }
            if (p < s->end && *p == '/') {
                ++p;
                if (!parse_index(&p, s->end, &ivn)) {
                    s->p = p;
                    return fail_token(r, "a normal index");
                }
                has_vn = true;
            }
        }
        if (p < s->end && !resurfi_is_blank(*p) && *p != '\n' && *p != '#')
            return fail_token(r, "a face corner (v, v/vt, v//vn or v/vt/vn)");
        s->p = p;
        if (!resolve(iv, r->nv, &v))
            return fail_index(r, iv, "vertex", "vertices", r->nv);
        if (has_vt && !resolve(ivt, r->nvt, &vt))
            return fail_index(r, ivt, "texture coordinate", "texture coordinates", r->nvt);
        if (has_vn && !resolve(ivn, r->nvn, &vn))
            return fail_index(r, ivn, "normal", "normals", r->nvn);
        if (!grow(r->ld->alloc, &r->face, &r->face_cap, corners + 1, sizeof(uint32_t)))
            return resurfi_load_oom(r->ld, "faces");
        uint32_t k = key_of(r, v, vt, vn);
        if (k == NONE)
            return resurfi_load_oom(r->ld, "faces");
        r->face[corners++] = k;
    }
    if (corners < 3)
        return fail(r, "a face needs at least 3 vertices, found %zu", corners);
    size_t added = corners - 2;
    resurf_status st = resurfi_check_triangle_limit(r->ld, r->ntri + added, s->line, -1);
    if (st != RESURF_OK)
        return st;
    if (!grow(r->ld->alloc, &r->tri, &r->tri_cap, r->ntri + added, 3 * sizeof(uint32_t)))
        return resurfi_load_oom(r->ld, "faces");
    if (r->grouped) {
        if (r->has_pending) {
            r->group = group_of(r, r->pending, r->pending_len);
            r->has_pending = false;
            if (r->group == NONE)
                return resurfi_load_oom(r->ld, "groups");
        }
        if (!grow(r->ld->alloc, &r->tri_group, &r->tri_group_cap, r->tri_cap, sizeof(uint32_t)))
            return resurfi_load_oom(r->ld, "groups");
    }
    /* Fan triangulation: (0, i, i+1). */
    for (size_t i = 1; i + 1 < corners; ++i) {
        uint32_t *t = r->tri + 3 * r->ntri;
        t[0] = r->face[0], t[1] = r->face[i], t[2] = r->face[i + 1];
        if (r->grouped)
            r->tri_group[r->ntri] = r->group;
        ++r->ntri;
    }
    return RESURF_OK;
}

/* Skips a statement resurf does not use, with its continuation lines. */
static void skip_statement(resurfi_scanner *s)
{
    for (;;) {
        const char *line = s->p;
        resurfi_scan_next_line(s);
        const char *q = s->p;
        if (q == line || q[-1] != '\n')
            return;
        --q;
        while (q > line && (q[-1] == '\r' || q[-1] == ' ' || q[-1] == '\t'))
            --q;
        if (q == line || q[-1] != '\\')
            return;
    }
}

static inline bool is_word_char(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

/* ---- assembly ------------------------------------------------------------------------------------------------ */

/* Turns keys into resurf vertices (see the file comment) and fills the mesh. */
static resurf_status build_mesh(obj_reader *r, resurf_mesh **out)
{
    bool identity = r->table_used == 0; /* every used position has exactly one (vt, vn) */
    bool has_tex = false, has_nrm = false;
    for (size_t k = 0; k < r->nkeys; ++k) {
        has_tex |= r->key_vt[k] != NONE;
        has_nrm |= r->key_vn[k] != NONE;
    }
    size_t unreferenced = 0;
    if (!identity)
        for (size_t v = 0; v < r->nv; ++v)
            unreferenced += r->direct[v] == NONE;
    size_t vertex_count = identity ? r->nv : r->nkeys + unreferenced;
    if (vertex_count > NONE - 1)
        return resurfi_fail(r->ld->error, RESURF_ERR_LIMIT, r->ld->path, 0, -1, "more than %u vertices", NONE - 1);
    unsigned attrs = (has_nrm ? RESURF_ATTR_NORMALS : 0) | (has_tex ? RESURF_ATTR_TEXCOORD0 : 0) |
                     (r->colors ? RESURF_ATTR_COLORS : 0);
    resurf_mesh *m = NULL;
    if (resurf_mesh_create_with(vertex_count, r->ntri, attrs, r->ld->alloc, &m, NULL) != RESURF_OK)
        return resurfi_load_oom(r->ld, "mesh");
    if (r->colors)
        m->color_components = r->alpha ? 4 : 3;
    /* vertex w takes position v and key k (NONE for a vertex no face uses) */
    size_t next_unused = 0; /* walks the positions for the unreferenced ones */
    for (size_t w = 0; w < vertex_count; ++w) {
        uint32_t v, k;
        if (identity) {
            v = (uint32_t)w;
            k = r->direct[v];
        } else if (w < r->nkeys) {
            k = (uint32_t)w;
            v = r->key_v[k];
        } else {
            while (r->direct[next_unused] != NONE)
                ++next_unused;
            v = (uint32_t)next_unused++;
            k = NONE;
        }
        memcpy(m->positions + 3 * w, r->pos + 3 * (size_t)v, 3 * sizeof(double));
        if (r->colors)
            memcpy(m->colors + 4 * w, r->col + 4 * (size_t)v, 4 * sizeof(double));
        if (k != NONE && has_nrm && r->key_vn[k] != NONE)
            memcpy(m->normals + 3 * w, r->nrm + 3 * (size_t)r->key_vn[k], 3 * sizeof(double));
        if (k != NONE && has_tex && r->key_vt[k] != NONE)
            memcpy(m->texcoords[0] + 2 * w, r->tex + 2 * (size_t)r->key_vt[k], 2 * sizeof(double));
    }
    for (size_t i = 0; i < 3 * r->ntri; ++i)
        m->indices[i] = identity ? r->key_v[r->tri[i]] : r->tri[i];
    if (r->grouped && r->group_count) {
        m->triangle_groups = r->tri_group;
        r->tri_group = NULL;
        m->group_names = r->names;
        m->group_count = r->group_count;
        r->names = NULL;
        r->group_count = 0;
    }
    *out = m;
    return RESURF_OK;
}

resurf_status resurfi_read_obj(resurfi_load *ld, resurf_mesh **out)
{
    obj_reader r;
    memset(&r, 0, sizeof r);
    r.ld = ld;
    resurfi_scan_init(&r.s, ld->data, ld->size);
    r.s.continuation = true;
    resurfi_scanner *s = &r.s;
    resurf_status st = RESURF_OK;
    while (st == RESURF_OK) {
        if ((st = resurfi_load_tick(ld, s->p)) != RESURF_OK)
            break;
        resurfi_scan_blanks(s);
        if (s->p >= s->end)
            break;
        if (*s->p == '\n') {
            ++s->p;
            ++s->line;
            continue;
        }
        if (*s->p == '#') {
            resurfi_scan_next_line(s);
            continue;
        }
        const char *word = s->p, *q = word;
        while (q < s->end && is_word_char(*q))
            ++q;
        size_t len = (size_t)(q - word);
        if (len == 0 || (q < s->end && *q != '\n' && !resurfi_is_blank(*q)) || (*word >= '0' && *word <= '9')) {
            st = fail_token(&r, "an OBJ statement");
            break;
        }
        s->p = q;
        if (len == 1 && word[0] == 'v')
            st = read_vertex(&r);
        else if (len == 1 && word[0] == 'f')
            st = read_face(&r);
        else if (len == 2 && word[0] == 'v' && word[1] == 't')
            st = read_texcoord(&r);
        else if (len == 2 && word[0] == 'v' && word[1] == 'n')
            st = read_normal(&r);
        else if ((len == 1 && (word[0] == 'o' || word[0] == 'g')) || (len == 6 && memcmp(word, "usemtl", 6) == 0))
            st = read_group(&r);
        else {
            skip_statement(s);
            continue;
        }
        if (st == RESURF_OK && !resurfi_scan_eol(s, '#'))
            st = fail_token(&r, "the end of the line");
        if (st == RESURF_OK)
            resurfi_scan_next_line(s);
    }
    if (st == RESURF_OK)
        st = build_mesh(&r, out);
    reader_free(&r);
    return st;
}

/* ---- writing ------------------------------------------------------------------------------------------------- */

/* "g NAME" with control characters replaced (a newline would end the statement). */
static void write_group(resurfi_writer *w, const resurf_mesh *m, uint32_t g)
{
    char name[256];
    if (g < m->group_count && m->group_names && m->group_names[g])
        snprintf(name, sizeof name, "%s", m->group_names[g]);
    else
        snprintf(name, sizeof name, "group%u", g);
    for (char *c = name; *c; ++c)
        if ((unsigned char)*c < 0x20 || *c == 0x7f)
            *c = '_';
    resurfi_write_str(w, "g ");
    resurfi_write_str(w, name);
    resurfi_write_str(w, "\n");
}

resurf_status resurfi_write_obj(resurfi_writer *w, const resurf_mesh *m, const resurf_save_options *o)
{
    const bool colors = o->write_colors && m->colors;
    const bool normals = o->write_normals && m->normals;
    const bool tex = o->write_texcoords && m->texcoord_count > 0 && m->texcoords[0];
    const size_t nv = m->vertex_count, nt = m->triangle_count;
    /* Progress counts every line written (v, vt, vn, f), so that a cancel is noticed within 2^16 lines. */
    const size_t vt_start = nv, vn_start = vt_start + (tex ? nv : 0), f_start = vn_start + (normals ? nv : 0);
    const size_t total = f_start + nt;
    resurfi_write_str(w, "# written by resurf " RESURF_VERSION_STRING "\n");
    for (size_t i = 0; i < nv; ++i) {
        const double *p = m->positions + 3 * i;
        resurfi_write(w, "v", 1);
        for (int a = 0; a < 3; ++a)
            resurfi_write_double(w, ' ', p[a]);
        if (colors)
            for (int a = 0; a < 3; ++a)
                resurfi_write_double(w, ' ', m->colors[4 * i + a]);
        resurfi_write(w, "\n", 1);
        resurfi_write_tick(w, i, total);
    }
    for (size_t i = 0; tex && i < nv; ++i) {
        resurfi_write(w, "vt", 2);
        resurfi_write_double(w, ' ', m->texcoords[0][2 * i]);
        resurfi_write_double(w, ' ', m->texcoords[0][2 * i + 1]);
        resurfi_write(w, "\n", 1);
        resurfi_write_tick(w, vt_start + i, total);
    }
    for (size_t i = 0; normals && i < nv; ++i) {
        resurfi_write(w, "vn", 2);
        for (int a = 0; a < 3; ++a)
            resurfi_write_double(w, ' ', m->normals[3 * i + a]);
        resurfi_write(w, "\n", 1);
        resurfi_write_tick(w, vn_start + i, total);
    }
    uint32_t group = NONE;
    for (size_t t = 0; t < nt; ++t) {
        if (m->triangle_groups && (t == 0 || m->triangle_groups[t] != group)) {
            group = m->triangle_groups[t];
            write_group(w, m, group);
        }
        resurfi_write(w, "f", 1);
        for (int c = 0; c < 3; ++c) {
            uint64_t v = (uint64_t)m->indices[3 * t + c] + 1;
            resurfi_write_uint(w, ' ', v);
            if (tex || normals) {
                resurfi_write(w, "/", 1);
                if (tex)
                    resurfi_write_uint(w, 0, v);
                if (normals)
                    resurfi_write_uint(w, '/', v);
            }
        }
        resurfi_write(w, "\n", 1);
        resurfi_write_tick(w, f_start + t, total);
    }
    return RESURF_OK;
}
