/* STL (3D Systems' stereolithography format), read and write, binary and ASCII.
 *
 * STL is a triangle soup: every facet repeats its corners. Loading welds corners with exactly equal positions into
 * one vertex (resurfi_weld_exact, vertices numbered by first appearance), so a closed part comes back closed.
 * Facet normals are ignored on load (they are redundant and often wrong).
 *
 * Binary or ASCII? Many binary files begin their 80-byte header with "solid", so the word alone decides nothing.
 * A file whose size is exactly 84 + 50 n, n being the triangle count at byte 80, is binary; otherwise a file that
 * starts with "solid" is ASCII; otherwise it is binary (a size short of 84 + 50 n means it was cut off).
 *
 * Writing: binary by default (float32 positions, the face normal computed from the positions); ASCII prints
 * positions with 17 significant digits. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_internal.h"

/* Fills the mesh from a soup of corner positions (3 corners per triangle), welded exactly. */
static resurf_status weld_soup(resurfi_load *ld, const double *soup, size_t triangles, resurf_mesh **out)
{
    size_t corners = 3 * triangles, count = 0;
    if (corners > UINT32_MAX)
        return resurfi_fail(ld->error, RESURF_ERR_LIMIT, ld->path, 0, -1, "more than %u facet corners to weld",
                            UINT32_MAX);
    uint32_t *remap = resurfi_alloc(ld->alloc, corners, sizeof *remap);
    if (!remap)
        return resurfi_load_oom(ld, "facets");
    if (resurfi_weld_exact(ld->alloc, soup, corners, remap, &count) != RESURF_OK) {
        resurfi_free(ld->alloc, remap);
        return resurfi_load_oom(ld, "facets");
    }
    resurf_mesh *m = NULL;
    if (resurf_mesh_create_with(count, 0, 0, ld->alloc, &m, NULL) != RESURF_OK) {
        resurfi_free(ld->alloc, remap);
        return resurfi_load_oom(ld, "facets");
    }
    /* A vertex takes the position of its first corner (all its corners have the same one). */
    size_t next = 0;
    for (size_t i = 0; i < corners; ++i)
        if (remap[i] == next)
            memcpy(m->positions + 3 * next++, soup + 3 * i, 3 * sizeof(double));
    resurfi_free(ld->alloc, m->indices);
    m->indices = remap;
    m->triangle_count = triangles;
    *out = m;
    return RESURF_OK;
}

static uint32_t load_u32le(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static double load_f32le(const unsigned char *p)
{
    uint32_t u = load_u32le(p);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static resurf_status read_binary(resurfi_load *ld, resurf_mesh **out)
{
    const unsigned char *data = (const unsigned char *)ld->data;
    if (ld->size < 84)
        return resurfi_parse_fail(ld, 0, (long long)ld->size,
                                  "the file ends inside the 84-byte header of a binary STL (%zu bytes)", ld->size);
    uint32_t n = load_u32le(data + 80);
    uint64_t need = 84 + 50 * (uint64_t)n;
    if (need > ld->size)
        return resurfi_parse_fail(ld, 0, 80, "a binary STL of %u triangles needs %llu bytes, the file has %zu", n,
                                  (unsigned long long)need, ld->size);
    resurf_status st = resurfi_check_triangle_limit(ld, n, 0, 80);
    if (st != RESURF_OK)
        return st;
    double *soup = resurfi_alloc(ld->alloc, n, 9 * sizeof(double));
    if (!soup)
        return resurfi_load_oom(ld, "facets");
    for (size_t t = 0; t < n && st == RESURF_OK; ++t) {
        const unsigned char *f = data + 84 + 50 * t;
        if ((st = resurfi_load_tick(ld, (const char *)f)) != RESURF_OK)
            break;
        for (int k = 0; k < 9; ++k) {
            double x = load_f32le(f + 12 + 4 * k); /* skip the 12-byte facet normal */
            if (!isfinite(x)) {
                st = resurfi_parse_fail(ld, 0, (long long)(f - data), "facet %zu has a non-finite coordinate", t);
                break;
            }
            soup[9 * t + k] = x;
        }
    }
    if (st == RESURF_OK)
        st = weld_soup(ld, soup, n, out);
    resurfi_free(ld->alloc, soup);
    return st;
}

/* ---- ASCII --------------------------------------------------------------------------------------------------- */

typedef struct stl_text {
    resurfi_load *ld;
    resurfi_scanner s;
    double *soup;          /* 9 per triangle */
    size_t ntri, cap;
    size_t facets;         /* read so far (a facet with more corners gives several triangles) */
    double corners[3 * 64];
} stl_text;

static resurf_status text_fail(stl_text *r, const char *fmt, ...) RESURFI_PRINTF(2, 3);
static resurf_status text_fail(stl_text *r, const char *fmt, ...)
{
    char message[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message, sizeof message, fmt, ap);
    va_end(ap);
    return resurfi_parse_fail(r->ld, r->s.line, -1, "%s", message);
}

/* Reads the next token and checks it is `word`. */
static resurf_status expect(stl_text *r, const char *word)
{
    resurfi_scan_skip_space(&r->s, 0);
    const char *tok;
    size_t len = resurfi_scan_token(&r->s, &tok);
    if (len != strlen(word) || memcmp(tok, word, len) != 0) {
        char found[64];
        resurfi_describe_token(tok, r->s.end, found, sizeof found);
        return text_fail(r, "expected '%s', found %s", word, found);
    }
    r->s.p = tok + len;
    return RESURF_OK;
}

/* Is the next token `word`? (Does not consume it.) */
static bool next_is(stl_text *r, const char *word)
{
    resurfi_scan_skip_space(&r->s, 0);
    const char *tok;
    size_t len = resurfi_scan_token(&r->s, &tok);
    return len == strlen(word) && memcmp(tok, word, len) == 0;
}

static resurf_status read_numbers(stl_text *r, double *x, int count)
{
    for (int i = 0; i < count; ++i) {
        resurfi_scan_skip_space(&r->s, 0);
        if (resurfi_scan_double(&r->s, &x[i]) != RESURFI_NUM_OK) {
            char found[64];
            resurfi_describe_token(r->s.p, r->s.end, found, sizeof found);
            return text_fail(r, "expected a number, found %s", found);
        }
    }
    return RESURF_OK;
}

/* facet normal n n n / outer loop / vertex x y z (3 or more) / endloop / endfacet; the polygon is fanned. */
static resurf_status read_facet(stl_text *r)
{
    double normal[3];
    resurf_status st;
    if ((st = expect(r, "normal")) != RESURF_OK || (st = read_numbers(r, normal, 3)) != RESURF_OK ||
        (st = expect(r, "outer")) != RESURF_OK || (st = expect(r, "loop")) != RESURF_OK)
        return st;
    size_t n = 0;
    const long long line = r->s.line;
    while (next_is(r, "vertex")) {
        if ((st = expect(r, "vertex")) != RESURF_OK)
            return st;
        if (n == 64)
            return text_fail(r, "facet %zu has more than 64 vertices", r->facets);
        if ((st = read_numbers(r, r->corners + 3 * n, 3)) != RESURF_OK)
            return st;
        const double *x = r->corners + 3 * n;
        if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2]))
            return text_fail(r, "facet %zu has a non-finite coordinate", r->facets);
        ++n;
    }
    if (n < 3)
        return text_fail(r, "facet %zu has %zu vertices, at least 3 are needed", r->facets, n);
    if ((st = expect(r, "endloop")) != RESURF_OK || (st = expect(r, "endfacet")) != RESURF_OK)
        return st;
    size_t added = n - 2;
    if ((st = resurfi_check_triangle_limit(r->ld, r->ntri + added, line, -1)) != RESURF_OK)
        return st;
    if (r->ntri + added > r->cap) {
        size_t cap = r->cap + r->cap / 2 + added + 64;
        double *soup = resurfi_realloc(r->ld->alloc, r->soup, cap, 9 * sizeof(double));
        if (!soup)
            return resurfi_load_oom(r->ld, "facets");
        r->soup = soup;
        r->cap = cap;
    }
    for (size_t i = 1; i + 1 < n; ++i) {
        double *t = r->soup + 9 * r->ntri++;
        memcpy(t, r->corners, 3 * sizeof(double));
        memcpy(t + 3, r->corners + 3 * i, 3 * sizeof(double));
        memcpy(t + 6, r->corners + 3 * (i + 1), 3 * sizeof(double));
    }
    ++r->facets;
    return RESURF_OK;
}

static resurf_status read_ascii(resurfi_load *ld, resurf_mesh **out)
{
    stl_text r;
    memset(&r, 0, sizeof r);
    r.ld = ld;
    resurfi_scan_init(&r.s, ld->data, ld->size);
    resurf_status st = expect(&r, "solid");
    /* One or more solids, each "solid NAME ... endsolid NAME". */
    while (st == RESURF_OK) {
        resurfi_scan_next_line(&r.s); /* the solid's name */
        for (;;) {
            if ((st = resurfi_load_tick(ld, r.s.p)) != RESURF_OK)
                break;
            if (!resurfi_scan_skip_space(&r.s, 0)) {
                st = text_fail(&r, "the file ends without 'endsolid'");
                break;
            }
            if (next_is(&r, "endsolid"))
                break;
            if ((st = expect(&r, "facet")) != RESURF_OK || (st = read_facet(&r)) != RESURF_OK)
                break;
        }
        if (st != RESURF_OK)
            break;
        resurfi_scan_next_line(&r.s); /* "endsolid NAME" */
        if (!resurfi_scan_skip_space(&r.s, 0))
            break;
        st = expect(&r, "solid");
    }
    if (st == RESURF_OK)
        st = weld_soup(ld, r.soup, r.ntri, out);
    resurfi_free(ld->alloc, r.soup);
    return st;
}

/* Does the file begin with the word "solid" (after blanks)? */
static bool starts_with_solid(const char *p, size_t size)
{
    const char *end = p + size;
    while (p < end && (resurfi_is_blank(*p) || *p == '\n'))
        ++p;
    return end - p >= 5 && memcmp(p, "solid", 5) == 0 && (end - p == 5 || resurfi_is_blank(p[5]) || p[5] == '\n');
}

resurf_status resurfi_read_stl(resurfi_load *ld, resurf_mesh **out)
{
    if (ld->size >= 84) {
        uint32_t n = load_u32le((const unsigned char *)ld->data + 80);
        if (84 + 50 * (uint64_t)n == ld->size)
            return read_binary(ld, out);
    }
    if (starts_with_solid(ld->data, ld->size))
        return read_ascii(ld, out);
    return read_binary(ld, out);
}

/* ---- writing ------------------------------------------------------------------------------------------------- */

/* The unit normal of triangle t, or 0 for a degenerate one. */
static vec3 face_normal(const resurf_mesh *m, size_t t)
{
    const uint32_t *i = m->indices + 3 * t;
    vec3 a = resurfi_position(m, i[0]), b = resurfi_position(m, i[1]), c = resurfi_position(m, i[2]);
    vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
    double len = v3_len(n);
    return len > 0 && isfinite(len) ? v3_scale(n, 1 / len) : v3(0, 0, 0);
}

static void put_f32(unsigned char *p, double x)
{
    float f = (float)x;
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    resurfi_put_u32le(p, u);
}

resurf_status resurfi_write_stl(resurfi_writer *w, const resurf_mesh *m, const resurf_save_options *o)
{
    const size_t nt = m->triangle_count;
    if (o->binary) {
        unsigned char header[84];
        memset(header, ' ', 80);
        /* Must not begin with "solid": some readers would take the file for ASCII. */
        static const char text[] = "binary STL written by resurf " RESURF_VERSION_STRING;
        memcpy(header, text, sizeof text - 1);
        resurfi_put_u32le(header + 80, (uint32_t)nt);
        resurfi_write(w, header, sizeof header);
        for (size_t t = 0; t < nt; ++t) {
            resurfi_write_tick(w, t, nt);
            unsigned char f[50];
            vec3 n = face_normal(m, t);
            put_f32(f, n.x), put_f32(f + 4, n.y), put_f32(f + 8, n.z);
            for (int c = 0; c < 3; ++c)
                for (int a = 0; a < 3; ++a)
                    put_f32(f + 12 + 12 * c + 4 * a, m->positions[3 * (size_t)m->indices[3 * t + c] + a]);
            resurfi_put_u16le(f + 48, 0);
            resurfi_write(w, f, sizeof f);
        }
        return RESURF_OK;
    }
    resurfi_write_str(w, "solid resurf\n");
    for (size_t t = 0; t < nt; ++t) {
        resurfi_write_tick(w, t, nt);
        vec3 n = face_normal(m, t);
        resurfi_write_str(w, "facet normal");
        resurfi_write_float9(w, ' ', n.x);
        resurfi_write_float9(w, ' ', n.y);
        resurfi_write_float9(w, ' ', n.z);
        resurfi_write_str(w, "\n outer loop\n");
        for (int c = 0; c < 3; ++c) {
            resurfi_write_str(w, "  vertex");
            for (int a = 0; a < 3; ++a)
                resurfi_write_double(w, ' ', m->positions[3 * (size_t)m->indices[3 * t + c] + a]);
            resurfi_write_str(w, "\n");
        }
        resurfi_write_str(w, " endloop\nendfacet\n");
    }
    resurfi_write_str(w, "endsolid resurf\n");
    return RESURF_OK;
}
