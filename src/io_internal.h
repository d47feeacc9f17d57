/* The I/O-only internal interface: what io.c (format choice, dispatch, the save) and io_common.c (the readers'
 * call-backs) share with the format parsers and writers (io_obj.c, io_ply.c, io_off.c, io_stl.c) and the text
 * scanner (io_text.c). Not installed, not used outside the io*.c files. */
#ifndef RESURF_IO_INTERNAL_H
#define RESURF_IO_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "internal.h"

/* ---- loading ------------------------------------------------------------------------------------------------- */

/* One load call: the whole file in memory, where errors go, and the limits. */
typedef struct resurfi_load {
    const char *data;       /* the file's bytes (not NUL-terminated) */
    size_t size;
    const char *path;       /* for messages: the path or name the caller gave, or NULL */
    size_t max_triangles;   /* 0 = no limit */
    const resurf_progress *progress;
    const resurf_allocator *alloc; /* the call's (NULL = C heap): the readers' temporaries and the new mesh */
    resurf_error *error;
    unsigned tick;          /* counts resurfi_load_tick() calls between progress reports */
} resurfi_load;

/* Each reader parses ld->data and on success stores a new mesh in *out. On failure *out is untouched and
 * ld->error says what is wrong and where (line for text, byte offset for binary). */
resurf_status resurfi_read_obj(resurfi_load *ld, resurf_mesh **out);
resurf_status resurfi_read_ply(resurfi_load *ld, resurf_mesh **out);
resurf_status resurfi_read_off(resurfi_load *ld, resurf_mesh **out);
resurf_status resurfi_read_stl(resurfi_load *ld, resurf_mesh **out);

/* ---- the readers' call-backs (io_common.c) ------------------------------------------------------------------- */

/* Reports progress every 2^16 calls (an element, a line); returns nonzero after filling ld->error when the
 * caller cancelled. pos is how far into the data the reader is. */
resurf_status resurfi_load_progress(resurfi_load *ld, const char *pos);
static inline resurf_status resurfi_load_tick(resurfi_load *ld, const char *pos)
{
    if ((++ld->tick & 0xffffu) != 0 || !ld->progress || !ld->progress->fn)
        return RESURF_OK;
    return resurfi_load_progress(ld, pos);
}

/* RESURF_ERR_LIMIT when triangle_count exceeds ld->max_triangles (line/offset say where, as for parse errors). */
resurf_status resurfi_check_triangle_limit(resurfi_load *ld, size_t triangle_count, long long line,
                                           long long offset);

/* A message for a parse error at a line (text) or byte offset (binary; pass line 0). */
resurf_status resurfi_parse_fail(resurfi_load *ld, long long line, long long offset, const char *fmt, ...)
    RESURFI_PRINTF(4, 5);
/* Out of memory while loading (what: "vertices", "triangles"...). */
resurf_status resurfi_load_oom(resurfi_load *ld, const char *what);

/* ---- the text scanner (io_text.c) ---------------------------------------------------------------------------- */

/* A cursor over text. Blanks are space, tab, \r, \v and \f: a line ends at \n, so "\r\n" files need no special
 * case. Number scanning never crosses a newline, so `line` stays exact. */
typedef struct resurfi_scanner {
    const char *p, *end;
    long long line;         /* 1-based line of p */
    bool continuation;      /* a backslash before the newline joins two lines (OBJ) */
} resurfi_scanner;

void resurfi_scan_init(resurfi_scanner *s, const char *data, size_t size);

static inline bool resurfi_is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/* Skips blanks (and, with continuation, a backslash-newline) on the current line. */
static inline void resurfi_scan_blanks(resurfi_scanner *s)
{
    for (;;) {
        while (s->p < s->end && resurfi_is_blank(*s->p))
            ++s->p;
        if (!s->continuation || s->p >= s->end || *s->p != '\\')
            return;
        const char *q = s->p + 1;
        while (q < s->end && *q == '\r')
            ++q;
        if (q >= s->end || *q != '\n')
            return;
        s->p = q + 1;
        ++s->line;
    }
}

/* Is the rest of the line blank (or a comment starting with `comment`, 0 for none)? Skips the blanks. */
static inline bool resurfi_scan_eol(resurfi_scanner *s, char comment)
{
    resurfi_scan_blanks(s);
    return s->p >= s->end || *s->p == '\n' || (comment && *s->p == comment);
}

/* Moves to the start of the next line. */
void resurfi_scan_next_line(resurfi_scanner *s);

/* Skips blanks and newlines (counting them) and `comment` lines (0 for none). Returns false at the end. */
bool resurfi_scan_skip_space(resurfi_scanner *s, char comment);

/* The token at p (after blanks): a run of non-blank, non-newline bytes. len 0 at the end of the line. */
size_t resurfi_scan_token(resurfi_scanner *s, const char **out_token);

/* Outcome of a number scan. */
typedef enum resurfi_num {
    RESURFI_NUM_OK = 0,
    RESURFI_NUM_NONE,  /* nothing before the end of the line */
    RESURFI_NUM_BAD,   /* a token that is not a number (p is left at it) */
    RESURFI_NUM_RANGE, /* an integer too large for its type */
} resurfi_num;

/* Parses a double at p (after blanks), correctly rounded; "inf"/"nan" parse too (callers that need finite
 * values check). The number must end at a blank, a newline, the end, or (for OBJ) '/'. */
resurfi_num resurfi_scan_double(resurfi_scanner *s, double *out);
/* Parses a decimal integer (optional sign) at p (after blanks); ends like a double. */
resurfi_num resurfi_scan_int(resurfi_scanner *s, long long *out);

/* Parses a double from [p, end): returns the end of the number or NULL when no number starts at p; the number
 * must be followed by end or a delimiter (blank, newline, '/'). Locale-independent. */
const char *resurfi_parse_double(const char *p, const char *end, double *out);

/* Writes `'token'` (shortened, non-printable bytes as '?') for messages like "expected a number, found 'x'";
 * an empty token reads "the end of the line". */
void resurfi_describe_token(const char *p, const char *end, char *dst, size_t dst_size);

/* ---- saving -------------------------------------------------------------------------------------------------- */

/* A buffered writer to a file descriptor. The first failure is kept (errno in err) and later writes are no-ops,
 * so writers check once at the end; io.c turns err into the message. */
typedef struct resurfi_writer {
    int fd;
    char *buf;
    size_t len, cap;
    int err;                    /* errno of the first failed write, 0 while all is well */
    const resurf_progress *progress;
    unsigned tick;
    bool cancelled;
} resurfi_writer;

void resurfi_write(resurfi_writer *w, const void *data, size_t size);
void resurfi_write_str(resurfi_writer *w, const char *s);
void resurfi_writef(resurfi_writer *w, const char *fmt, ...) RESURFI_PRINTF(2, 3);
/* " %.17g" and friends, without a format string parse each time. */
void resurfi_write_double(resurfi_writer *w, char lead, double x);   /* lead: ' ' or 0 */
void resurfi_write_float9(resurfi_writer *w, char lead, double x);   /* %.9g: exact for floats */
void resurfi_write_uint(resurfi_writer *w, char lead, uint64_t x);
void resurfi_write_flush(resurfi_writer *w);
/* Progress every 2^16 calls (fraction done of `total` items); sets w->cancelled when the caller cancels. */
void resurfi_write_tick(resurfi_writer *w, size_t done, size_t total);

/* Little-endian stores, whatever the host. */
static inline void resurfi_put_u16le(unsigned char *p, uint16_t x) { p[0] = (unsigned char)x; p[1] = (unsigned char)(x >> 8); }
static inline void resurfi_put_u32le(unsigned char *p, uint32_t x)
{
    for (int i = 0; i < 4; ++i)
        p[i] = (unsigned char)(x >> (8 * i));
}
static inline void resurfi_put_u64le(unsigned char *p, uint64_t x)
{
    for (int i = 0; i < 8; ++i)
        p[i] = (unsigned char)(x >> (8 * i));
}

/* Each writer writes the mesh (already checked: indices in range, finite positions) to w. They return
 * RESURF_ERR_CANCELLED when the progress callback cancelled, RESURF_OK otherwise (I/O errors are in w->err). */
resurf_status resurfi_write_obj(resurfi_writer *w, const resurf_mesh *m, const resurf_save_options *o);
resurf_status resurfi_write_ply(resurfi_writer *w, const resurf_mesh *m, const resurf_save_options *o);
resurf_status resurfi_write_off(resurfi_writer *w, const resurf_mesh *m, const resurf_save_options *o);
resurf_status resurfi_write_stl(resurfi_writer *w, const resurf_mesh *m, const resurf_save_options *o);

#endif
