/* The text side of resurf's file I/O: a line-aware scanner with a fast, correctly rounded number parser, and a
 * buffered writer that prints numbers for the text formats.
 *
 * Number parsing follows Clinger (1990), "How to Read Floating Point Numbers Accurately": a decimal w × 10^e with
 * w < 2^53 and |e| <= 22 is one exact operation on two exact doubles, hence correctly rounded. Files written with
 * "%.17g" carry 17 digits (w up to 10^17 > 2^53), so a second fast path does the same in long double where it has
 * a 64-bit (or wider) significand: w and 10^e (|e| <= 27) are exact there, the operation rounds once, and the
 * conversion to double rounds correctly unless the long double result lies exactly halfway between two doubles
 * (the only case in which double rounding can differ; see the proof in parse_long_double). Anything else goes to
 * strtod, which the caller runs in the "C" locale (io.c switches the thread's locale for the duration of a call). */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "file.h"
#include "io_internal.h"

/* ---- scanner ------------------------------------------------------------------------------------------------- */

void resurfi_scan_init(resurfi_scanner *s, const char *data, size_t size)
{
    s->p = data;
    s->end = data + size;
    s->line = 1;
    s->continuation = false;
}

void resurfi_scan_next_line(resurfi_scanner *s)
{
    const char *nl = s->p < s->end ? memchr(s->p, '\n', (size_t)(s->end - s->p)) : NULL;
    if (nl) {
        s->p = nl + 1;
        ++s->line;
    } else
        s->p = s->end;
}

bool resurfi_scan_skip_space(resurfi_scanner *s, char comment)
{
    for (;;) {
        resurfi_scan_blanks(s);
        if (s->p >= s->end)
            return false;
        if (*s->p == '\n') {
            ++s->p;
            ++s->line;
        } else if (comment && *s->p == comment)
            resurfi_scan_next_line(s);
        else
            return true;
    }
}

size_t resurfi_scan_token(resurfi_scanner *s, const char **out_token)
{
    resurfi_scan_blanks(s);
    const char *q = s->p;
    while (q < s->end && *q != '\n' && !resurfi_is_blank(*q))
        ++q;
    *out_token = s->p;
    return (size_t)(q - s->p);
}

/* Does c end a number? */
static inline bool is_delimiter(char c) { return resurfi_is_blank(c) || c == '\n' || c == '/'; }

void resurfi_describe_token(const char *p, const char *end, char *dst, size_t dst_size)
{
    if (p >= end) {
        snprintf(dst, dst_size, "the end of the file");
        return;
    }
    const char *q = p;
    while (q < end && *q != '\n' && !resurfi_is_blank(*q))
        ++q;
    if (q == p) {
        snprintf(dst, dst_size, "the end of the line");
        return;
    }
    char text[40];
    size_t n = (size_t)(q - p), shown = n > 24 ? 24 : n;
    for (size_t i = 0; i < shown; ++i) {
        unsigned char c = (unsigned char)p[i];
        text[i] = (c >= 0x20 && c < 0x7f) ? (char)c : '?';
    }
    text[shown] = 0;
    snprintf(dst, dst_size, "'%s%s'", text, n > shown ? "..." : "");
}

/* ---- numbers ------------------------------------------------------------------------------------------------- */

static const double pow10_double[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                        1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

#if LDBL_MANT_DIG >= 64
/* 10^e = 2^e 5^e is exact in a 64-bit significand while 5^e < 2^64, i.e. e <= 27. */
static const long double pow10_long[28] = {1e0L,  1e1L,  1e2L,  1e3L,  1e4L,  1e5L,  1e6L,  1e7L,  1e8L,  1e9L,
                                           1e10L, 1e11L, 1e12L, 1e13L, 1e14L, 1e15L, 1e16L, 1e17L, 1e18L, 1e19L,
                                           1e20L, 1e21L, 1e22L, 1e23L, 1e24L, 1e25L, 1e26L, 1e27L};

/* w × 10^e correctly rounded to double, or false when this path cannot guarantee it.
 * Why it is exact: y = RN_ld(x) rounds once (w and 10^|e| exact). If RN_d(y) differed from RN_d(x), a double
 * midpoint m would separate x from y, or y would equal m; but m is representable in long double and rounding is
 * monotone, so x < m implies y <= m and x > m implies y >= m: only y == m is a problem, and that is tested. */
/* Does long double arithmetic carry its 64-bit significand here? Not under valgrind, which runs x87 code at double
 * precision: there this path would round twice, so strtod takes over. A volatile operand keeps the compiler from
 * folding the test; it costs a few nanoseconds per call and needs no global state. */
static bool long_double_is_extended(void)
{
    volatile long double one = 1;
    return one + LDBL_EPSILON != one;
}

static bool parse_long_double(uint64_t w, int e, double *out)
{
    if (e < -27 || e > 27 || !long_double_is_extended())
        return false;
    long double y = e >= 0 ? (long double)w * pow10_long[e] : (long double)w / pow10_long[-e];
    double z = (double)y;
    long double diff = y - (long double)z; /* exact: y and z are within a factor of 2 (Sterbenz) */
    if (diff != 0) {
        double n = nextafter(z, diff > 0 ? INFINITY : -INFINITY);
        if (2 * diff == (long double)n - (long double)z)
            return false; /* exactly halfway: the tie must be broken on the exact value */
    }
    *out = z;
    return true;
}
#else
static bool parse_long_double(uint64_t w, int e, double *out)
{
    (void)w, (void)e, (void)out;
    return false;
}
#endif

/* The slow path: the token up to the next delimiter, through strtod. */
static const char *parse_with_strtod(const char *start, const char *end, double *out)
{
    const char *q = start;
    while (q < end && !is_delimiter(*q))
        ++q;
    size_t len = (size_t)(q - start);
    char buf[512];
    if (len == 0 || len >= sizeof buf)
        return NULL;
    memcpy(buf, start, len);
    buf[len] = 0;
    char *stop = NULL;
    double v = strtod(buf, &stop);
    if (stop != buf + len)
        return NULL;
    *out = v;
    return q;
}

const char *resurfi_parse_double(const char *p, const char *end, double *out)
{
    const char *start = p;
    bool negative = false;
    if (p < end && (*p == '-' || *p == '+'))
        negative = *p++ == '-';
    uint64_t w = 0;
    int digits = 0, e10 = 0;
    bool any = false, slow = false;
    /* Leading zeros are not significant; more than 19 significant digits cannot be held in w. */
    for (; p < end && (unsigned)(*p - '0') < 10; ++p) {
        unsigned d = (unsigned)(*p - '0');
        any = true;
        if (w == 0 && d == 0)
            continue;
        if (digits >= 19) {
            slow = true;
            continue;
        }
        w = w * 10 + d;
        ++digits;
    }
    if (p < end && *p == '.') {
        for (++p; p < end && (unsigned)(*p - '0') < 10; ++p) {
            unsigned d = (unsigned)(*p - '0');
            any = true;
            if (digits >= 19) {
                slow = true;
                continue;
            }
            w = w * 10 + d;
            if (w)
                ++digits;
            --e10;
        }
    }
    if (any && p < end && (*p == 'e' || *p == 'E')) {
        const char *q = p + 1;
        bool eneg = false;
        if (q < end && (*q == '-' || *q == '+'))
            eneg = *q++ == '-';
        if (q < end && (unsigned)(*q - '0') < 10) {
            int x = 0;
            for (; q < end && (unsigned)(*q - '0') < 10; ++q)
                if (x < 100000)
                    x = x * 10 + (*q - '0');
            e10 += eneg ? -x : x;
            p = q;
        } else
            slow = true; /* "1e" or "1e+": let strtod decide (it rejects them as a whole token) */
    }
    if (!any || (p < end && !is_delimiter(*p)))
        slow = true; /* "inf", "nan", hex floats, or trailing letters */
    if (!slow) {
        double v;
        if (w == 0) {
            *out = negative ? -0.0 : 0.0;
            return p;
        }
        if (w <= (UINT64_C(1) << 53) && e10 >= -22 && e10 <= 22) {
            v = (double)w;
            v = e10 < 0 ? v / pow10_double[-e10] : v * pow10_double[e10];
            *out = negative ? -v : v;
            return p;
        }
        if (parse_long_double(w, e10, &v)) {
            *out = negative ? -v : v;
            return p;
        }
    }
    return parse_with_strtod(start, end, out);
}

resurfi_num resurfi_scan_double(resurfi_scanner *s, double *out)
{
    resurfi_scan_blanks(s);
    if (s->p >= s->end || *s->p == '\n')
        return RESURFI_NUM_NONE;
    const char *q = resurfi_parse_double(s->p, s->end, out);
    if (!q)
        return RESURFI_NUM_BAD;
    s->p = q;
    return RESURFI_NUM_OK;
}

resurfi_num resurfi_scan_int(resurfi_scanner *s, long long *out)
{
    resurfi_scan_blanks(s);
    const char *p = s->p, *end = s->end;
    if (p >= end || *p == '\n')
        return RESURFI_NUM_NONE;
    bool negative = false;
    if (*p == '-' || *p == '+')
        negative = *p++ == '-';
    if (p >= end || (unsigned)(*p - '0') >= 10)
        return RESURFI_NUM_BAD;
    unsigned long long v = 0;
    bool range = false;
    for (; p < end && (unsigned)(*p - '0') < 10; ++p) {
        unsigned d = (unsigned)(*p - '0');
        if (v > (ULLONG_MAX - d) / 10)
            range = true;
        else
            v = v * 10 + d;
    }
    if (p < end && !is_delimiter(*p))
        return RESURFI_NUM_BAD;
    if (range || v > (unsigned long long)LLONG_MAX)
        return RESURFI_NUM_RANGE;
    s->p = p;
    *out = negative ? -(long long)v : (long long)v;
    return RESURFI_NUM_OK;
}

/* ---- writer -------------------------------------------------------------------------------------------------- */

void resurfi_write_flush(resurfi_writer *w)
{
    if (!w->err)
        w->err = resurfi_write_all(w->fd, w->buf, w->len);
    w->len = 0;
}

/* Makes room for n bytes in the buffer (n <= cap); false after a failure. */
static bool reserve(resurfi_writer *w, size_t n)
{
    if (w->err || w->cancelled)
        return false;
    if (w->len + n > w->cap)
        resurfi_write_flush(w);
    return !w->err;
}

void resurfi_write(resurfi_writer *w, const void *data, size_t size)
{
    if (size > w->cap / 2) {
        if (!reserve(w, w->cap))
            return;
        resurfi_write_flush(w);
        const char *p = data;
        while (!w->err && size) {
            size_t n = size > w->cap ? w->cap : size;
            memcpy(w->buf, p, n);
            w->len = n;
            resurfi_write_flush(w);
            p += n, size -= n;
        }
        return;
    }
    if (!reserve(w, size))
        return;
    memcpy(w->buf + w->len, data, size);
    w->len += size;
}

void resurfi_write_str(resurfi_writer *w, const char *s) { resurfi_write(w, s, strlen(s)); }

void resurfi_writef(resurfi_writer *w, const char *fmt, ...)
{
    char text[1024];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    if (n > 0)
        resurfi_write(w, text, (size_t)n < sizeof text ? (size_t)n : sizeof text - 1);
}

static void write_number(resurfi_writer *w, char lead, const char *fmt, double x)
{
    if (!reserve(w, 40))
        return;
    char *dst = w->buf + w->len;
    if (lead)
        *dst++ = lead;
    int n = snprintf(dst, 38, fmt, x);
    if (n > 0 && n < 38)
        w->len += (size_t)n + (lead ? 1 : 0);
}

void resurfi_write_double(resurfi_writer *w, char lead, double x) { write_number(w, lead, "%.17g", x); }
void resurfi_write_float9(resurfi_writer *w, char lead, double x) { write_number(w, lead, "%.9g", x); }

void resurfi_write_uint(resurfi_writer *w, char lead, uint64_t x)
{
    if (!reserve(w, 24))
        return;
    char digits[24];
    int n = 0;
    do {
        digits[n++] = (char)('0' + x % 10);
        x /= 10;
    } while (x);
    char *dst = w->buf + w->len;
    if (lead)
        *dst++ = lead;
    for (int i = 0; i < n; ++i)
        dst[i] = digits[n - 1 - i];
    w->len += (size_t)n + (lead ? 1 : 0);
}

void resurfi_write_tick(resurfi_writer *w, size_t done, size_t total)
{
    if ((++w->tick & 0xffffu) != 0 || !w->progress || !w->progress->fn || w->cancelled)
        return;
    if (resurfi_progress(w->progress, RESURF_STAGE_SAVE, total ? (double)done / (double)total : 1.0))
        w->cancelled = true;
}
