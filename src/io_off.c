/* Geomview OFF, read and write, with the [ST][C][N]OFF variants (texture coordinates, colours, normals).
 *
 * A vertex line holds x y z, then nx ny nz (N), then r g b [a] (C), then s t (ST), in that order (Geomview's
 * object file formats manual). Colours written as integers are 0..255 (as MeshLab writes them); colours with a
 * decimal point or an exponent are taken as they are (0..1, as Geomview writes them). A face line holds its vertex
 * count, the indices, and optionally a face colour, which resurf ignores. Polygons are fan-triangulated. '#' starts
 * a comment anywhere. The OFF keyword itself is optional (the manual says so); 4OFF and nOFF are not supported.
 * Vertices and faces are one per line: the line structure is what tells how many colour values a vertex has.
 *
 * Writing: OFF, with the prefixes of the attributes present; doubles with 17 significant digits, colours as
 * integers 0..255 (RGB or RGBA as color_components says). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_internal.h"

typedef struct off_reader {
    resurfi_load *ld;
    resurfi_scanner s;
    bool st, c, n;      /* header prefixes */
} off_reader;

static resurf_status fail(off_reader *r, const char *fmt, ...) RESURFI_PRINTF(2, 3);
static resurf_status fail(off_reader *r, const char *fmt, ...)
{
    char message[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message, sizeof message, fmt, ap);
    va_end(ap);
    return resurfi_parse_fail(r->ld, r->s.line, -1, "%s", message);
}

static resurf_status fail_token(off_reader *r, const char *expected)
{
    char found[64];
    resurfi_describe_token(r->s.p, r->s.end, found, sizeof found);
    return fail(r, "expected %s, found %s", expected, found);
}

/* Reads the keyword, if there is one. */
static resurf_status read_keyword(off_reader *r)
{
    resurfi_scanner *s = &r->s;
    const char *tok;
    size_t len = resurfi_scan_token(s, &tok);
    size_t digits = 0;
    while (digits < len && tok[digits] >= '0' && tok[digits] <= '9')
        ++digits;
    if (len && digits == len)
        return RESURF_OK; /* no keyword: the counts come first */
    size_t i = 0;
    if (len >= 2 && memcmp(tok, "ST", 2) == 0)
        r->st = true, i = 2;
    if (i < len && tok[i] == 'C')
        r->c = true, ++i;
    if (i < len && tok[i] == 'N')
        r->n = true, ++i;
    if (i < len && (tok[i] == '4' || tok[i] == 'n') && len - i >= 3 && memcmp(tok + len - 3, "OFF", 3) == 0)
        return resurfi_fail(r->ld->error, RESURF_ERR_UNSUPPORTED, r->ld->path, s->line, -1,
                            "%.*s files (4D or n-dimensional) are not supported", (int)(len > 16 ? 16 : len), tok);
    if (len - i != 3 || memcmp(tok + i, "OFF", 3) != 0)
        return fail_token(r, "an OFF keyword (OFF, COFF, NOFF, STOFF, ...)");
    s->p = tok + len;
    return RESURF_OK;
}

/* One count of the header line(s); fails naming what. */
static resurf_status read_count(off_reader *r, const char *what, long long *out)
{
    if (!resurfi_scan_skip_space(&r->s, '#'))
        return fail(r, "the file ends before the %s count", what);
    resurfi_num n = resurfi_scan_int(&r->s, out);
    if (n == RESURFI_NUM_RANGE)
        return fail(r, "the %s count is too large", what);
    if (n != RESURFI_NUM_OK)
        return fail_token(r, what[0] == 'v' ? "the vertex count" : "the face count");
    if (*out < 0)
        return fail(r, "the %s count is negative (%lld)", what, *out);
    return RESURF_OK;
}

/* Does the token [a, b) look like a decimal fraction (not an integer)? */
static bool looks_fractional(const char *a, const char *b)
{
    for (; a < b; ++a)
        if (*a == '.' || *a == 'e' || *a == 'E' || *a == 'n' || *a == 'N' || *a == 'i' || *a == 'I')
            return true;
    return false;
}

static resurf_status read_vertices(off_reader *r, resurf_mesh *m)
{
    resurfi_scanner *s = &r->s;
    const int base = 3 + (r->n ? 3 : 0) + (r->st ? 2 : 0);
    bool alpha = false;
    for (size_t v = 0; v < m->vertex_count; ++v) {
        resurf_status st = resurfi_load_tick(r->ld, s->p);
        if (st != RESURF_OK)
            return st;
        if (!resurfi_scan_skip_space(s, '#'))
            return fail(r, "the file ends after %zu of %zu vertices", v, m->vertex_count);
        double x[16];
        bool frac[16];
        int n = 0;
        while (!resurfi_scan_eol(s, '#')) {
            if (n == 16)
                return fail(r, "vertex %zu has too many numbers", v);
            const char *start = s->p;
            if (resurfi_scan_double(s, &x[n]) != RESURFI_NUM_OK)
                return fail_token(r, "a number");
            frac[n] = looks_fractional(start, s->p);
            ++n;
        }
        int colors = r->c ? n - base : 0;
        if (r->c ? (colors != 3 && colors != 4) : n != base)
            return fail(r, "vertex %zu has %d numbers, expected %d%s", v, n, base,
                        r->c ? " plus 3 or 4 colour values" : "");
        if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2]))
            return fail(r, "vertex %zu has a non-finite coordinate", v);
        memcpy(m->positions + 3 * v, x, 3 * sizeof(double));
        int k = 3;
        if (r->n) {
            memcpy(m->normals + 3 * v, x + k, 3 * sizeof(double));
            k += 3;
        }
        if (r->c) {
            /* Integers are 0..255, fractions 0..1. */
            bool fractional = false;
            for (int a = 0; a < colors; ++a)
                fractional |= frac[k + a];
            double divisor = fractional ? 1.0 : 255.0;
            double *c = m->colors + 4 * v;
            c[3] = 1.0;
            for (int a = 0; a < colors; ++a)
                c[a] = x[k + a] / divisor;
            alpha |= colors == 4;
            k += colors;
        }
        if (r->st)
            memcpy(m->texcoords[0] + 2 * v, x + k, 2 * sizeof(double));
        resurfi_scan_next_line(s);
    }
    if (r->c)
        m->color_components = alpha ? 4 : 3;
    return RESURF_OK;
}

static resurf_status read_faces(off_reader *r, resurf_mesh *m, size_t faces, uint32_t **indices, size_t *cap,
                                size_t *ntri)
{
    resurfi_scanner *s = &r->s;
    uint32_t small[64], *idx = small;
    size_t idx_cap = 64;
    resurf_status st = RESURF_OK;
    for (size_t f = 0; f < faces && st == RESURF_OK; ++f) {
        if ((st = resurfi_load_tick(r->ld, s->p)) != RESURF_OK)
            break;
        if (!resurfi_scan_skip_space(s, '#')) {
            st = fail(r, "the file ends after %zu of %zu faces", f, faces);
            break;
        }
        long long n;
        resurfi_num num = resurfi_scan_int(s, &n);
        if (num != RESURFI_NUM_OK || n < 0) {
            st = num == RESURFI_NUM_OK || num == RESURFI_NUM_RANGE ? fail(r, "face %zu has a bad vertex count", f)
                                                                   : fail_token(r, "a face's vertex count");
            break;
        }
        if (n < 3) {
            st = fail(r, "face %zu has %lld vertices, at least 3 are needed", f, n);
            break;
        }
        /* Each index takes at least 2 bytes: a longer face cannot be in the file (nor be allocated for). */
        if ((unsigned long long)n > (size_t)(s->end - s->p) / 2) {
            st = fail(r, "face %zu has %lld vertices, more than the rest of the file holds", f, n);
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
        for (long long j = 0; j < n && st == RESURF_OK; ++j) {
            long long v;
            num = resurfi_scan_int(s, &v);
            if (num == RESURFI_NUM_NONE)
                st = fail(r, "face %zu has %lld of its %lld indices", f, j, n);
            else if (num == RESURFI_NUM_BAD)
                st = fail_token(r, "a vertex index");
            else if (num == RESURFI_NUM_RANGE)
                st = fail(r, "face %zu refers to a vertex index too large to read", f);
            else if (v < 0 || (unsigned long long)v >= m->vertex_count)
                st = fail(r, "face %zu refers to vertex %lld of %zu", f, v, m->vertex_count);
            else
                idx[j] = (uint32_t)v;
        }
        if (st != RESURF_OK)
            break;
        size_t added = (size_t)n - 2;
        if ((st = resurfi_check_triangle_limit(r->ld, *ntri + added, s->line, -1)) != RESURF_OK)
            break;
        if (*ntri + added > *cap) {
            size_t c = *cap + *cap / 2 + added + 16;
            uint32_t *p = resurfi_realloc(r->ld->alloc, *indices, c, 3 * sizeof(uint32_t));
            if (!p) {
                st = resurfi_load_oom(r->ld, "faces");
                break;
            }
            *indices = p;
            *cap = c;
        }
        uint32_t *t = *indices + 3 * *ntri;
        for (size_t i = 1; i + 1 < (size_t)n; ++i, t += 3)
            t[0] = idx[0], t[1] = idx[i], t[2] = idx[i + 1];
        *ntri += added;
        resurfi_scan_next_line(s); /* the rest of the line is the face colour, if any */
    }
    if (idx != small)
        resurfi_free(r->ld->alloc, idx);
    return st;
}

resurf_status resurfi_read_off(resurfi_load *ld, resurf_mesh **out)
{
    off_reader r;
    memset(&r, 0, sizeof r);
    r.ld = ld;
    resurfi_scan_init(&r.s, ld->data, ld->size);
    resurfi_scanner *s = &r.s;
    if (!resurfi_scan_skip_space(s, '#'))
        return resurfi_parse_fail(ld, s->line, -1, "the file holds no OFF header");
    resurf_status st = read_keyword(&r);
    long long nv = 0, nf = 0, ne = 0;
    if (st == RESURF_OK)
        st = read_count(&r, "vertex", &nv);
    if (st == RESURF_OK)
        st = read_count(&r, "face", &nf);
    if (st == RESURF_OK && !resurfi_scan_eol(s, '#'))
        st = read_count(&r, "edge", &ne); /* unused, and optional */
    if (st != RESURF_OK)
        return st;
    if (!resurfi_scan_eol(s, '#'))
        return fail_token(&r, "the end of the header line");
    const long long header_line = s->line;
    resurfi_scan_next_line(s);
    /* Before allocating: a vertex needs >= 3 numbers (+3 N, +3 C, +2 ST), a face >= 4, each >= 2 bytes (the
     * last may lack its separator). */
    size_t remaining = (size_t)(s->end - s->p) + 1;
    uint64_t vertex_bytes = 2 * (uint64_t)(3 + (r.n ? 3 : 0) + (r.c ? 3 : 0) + (r.st ? 2 : 0)), face_bytes = 8;
    if ((uint64_t)nv > UINT32_MAX - 1)
        return resurfi_fail(ld->error, RESURF_ERR_LIMIT, ld->path, header_line, -1, "more than %u vertices",
                            UINT32_MAX - 1);
    if ((uint64_t)nv > remaining / vertex_bytes ||
        (uint64_t)nf > (remaining - (size_t)nv * vertex_bytes) / face_bytes)
        return resurfi_parse_fail(ld, header_line, -1,
                                  "the header declares %lld vertices and %lld faces, more than the %zu bytes after "
                                  "it can hold",
                                  nv, nf, remaining - 1);
    if (nf > 0 && (st = resurfi_check_triangle_limit(ld, (size_t)nf, header_line, -1)) != RESURF_OK)
        return st;
    unsigned attrs = (r.n ? RESURF_ATTR_NORMALS : 0) | (r.c ? RESURF_ATTR_COLORS : 0) |
                     (r.st ? RESURF_ATTR_TEXCOORD0 : 0);
    resurf_mesh *m = NULL;
    if (resurf_mesh_create_with((size_t)nv, 0, attrs, ld->alloc, &m, NULL) != RESURF_OK)
        return resurfi_load_oom(ld, "vertices");
    size_t cap = (size_t)nf, ntri = 0;
    uint32_t *indices = resurfi_alloc(ld->alloc, cap, 3 * sizeof(uint32_t));
    if (!indices)
        st = resurfi_load_oom(ld, "faces");
    if (st == RESURF_OK)
        st = read_vertices(&r, m);
    if (st == RESURF_OK)
        st = read_faces(&r, m, (size_t)nf, &indices, &cap, &ntri);
    if (st != RESURF_OK) {
        resurfi_free(ld->alloc, indices);
        resurf_mesh_free(m);
        return st;
    }
    resurfi_free(ld->alloc, m->indices);
    m->indices = indices;
    m->triangle_count = ntri;
    *out = m;
    return RESURF_OK;
}

/* ---- writing ------------------------------------------------------------------------------------------------- */

static unsigned color_byte(double c)
{
    if (!(c > 0))
        return 0;
    if (c >= 1)
        return 255;
    return (unsigned)(c * 255 + 0.5);
}

resurf_status resurfi_write_off(resurfi_writer *w, const resurf_mesh *m, const resurf_save_options *o)
{
    const bool normals = o->write_normals && m->normals;
    const bool tex = o->write_texcoords && m->texcoord_count > 0 && m->texcoords[0];
    const bool colors = o->write_colors && m->colors;
    const unsigned cc = m->color_components == 3 ? 3 : 4;
    const size_t nv = m->vertex_count, nt = m->triangle_count;
    resurfi_writef(w, "%s%s%sOFF\n%zu %zu 0\n", tex ? "ST" : "", colors ? "C" : "", normals ? "N" : "", nv, nt);
    for (size_t v = 0; v < nv; ++v) {
        resurfi_write_tick(w, v, nv + nt);
        for (int a = 0; a < 3; ++a)
            resurfi_write_double(w, a ? ' ' : 0, m->positions[3 * v + a]);
        for (int a = 0; normals && a < 3; ++a)
            resurfi_write_double(w, ' ', m->normals[3 * v + a]);
        for (unsigned a = 0; colors && a < cc; ++a)
            resurfi_write_uint(w, ' ', color_byte(m->colors[4 * v + a]));
        for (int a = 0; tex && a < 2; ++a)
            resurfi_write_double(w, ' ', m->texcoords[0][2 * v + a]);
        resurfi_write(w, "\n", 1);
    }
    for (size_t t = 0; t < nt; ++t) {
        resurfi_write_tick(w, nv + t, nv + nt);
        resurfi_write(w, "3", 1);
        for (int c = 0; c < 3; ++c)
            resurfi_write_uint(w, ' ', m->indices[3 * t + c]);
        resurfi_write(w, "\n", 1);
    }
    return RESURF_OK;
}
