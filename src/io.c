/* Loading and saving meshes: format choice (by extension, by name, by content), reading a whole file into memory,
 * dispatch to the format readers and writers (io_obj.c, io_ply.c, io_off.c, io_stl.c), and the atomic save
 * (a temporary file in the target's folder, renamed over the target only once it is completely written).
 *
 * Both directions run in the "C" locale for their duration (uselocale: per thread, restored before returning), so
 * that strtod and printf read and write '.' as the decimal point whatever the application's locale is. */
#include <errno.h>
#include <fcntl.h>
#include <locale.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "io_internal.h"

#ifndef O_CLOEXEC
#define O_CLOEXEC 0
#endif

/* ---- formats ------------------------------------------------------------------------------------------------- */

static const char *const format_names[RESURF_FORMAT_COUNT] = {
    [RESURF_FORMAT_OBJ] = "obj",
    [RESURF_FORMAT_PLY] = "ply",
    [RESURF_FORMAT_OFF] = "off",
    [RESURF_FORMAT_STL] = "stl",
};

/* ASCII-only case-insensitive equality (locale-free, unlike strcasecmp). */
static bool equal_nocase(const char *a, const char *b)
{
    for (; *a && *b; ++a, ++b) {
        char x = (*a >= 'A' && *a <= 'Z') ? (char)(*a - 'A' + 'a') : *a;
        char y = (*b >= 'A' && *b <= 'Z') ? (char)(*b - 'A' + 'a') : *b;
        if (x != y)
            return false;
    }
    return *a == *b;
}

const char *resurf_format_name(resurf_format format)
{
    if ((unsigned)format >= RESURF_FORMAT_COUNT || format == RESURF_FORMAT_AUTO)
        return NULL;
    return format_names[format];
}

resurf_format resurf_format_from_name(const char *name)
{
    if (!name)
        return RESURF_FORMAT_AUTO;
    for (int f = RESURF_FORMAT_AUTO + 1; f < RESURF_FORMAT_COUNT; ++f)
        if (equal_nocase(name, format_names[f]))
            return (resurf_format)f;
    return RESURF_FORMAT_AUTO;
}

resurf_format resurf_format_from_path(const char *path)
{
    if (!path)
        return RESURF_FORMAT_AUTO;
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    if (!dot || dot == base)
        return RESURF_FORMAT_AUTO; /* no extension, or a hidden file's name such as ".ply" */
    return resurf_format_from_name(dot + 1);
}

/* Which format the bytes look like when the name does not tell: PLY and OFF by their magic word, STL by "solid" or
 * the binary size formula, OBJ by a first statement that only OBJ has. AUTO when none fits. */
static resurf_format sniff_format(const char *data, size_t size)
{
    if (size >= 4 && memcmp(data, "ply", 3) == 0 && (data[3] == '\n' || data[3] == '\r'))
        return RESURF_FORMAT_PLY;
    if (size >= 84) {
        uint32_t n = (uint32_t)(unsigned char)data[80] | (uint32_t)(unsigned char)data[81] << 8 |
                     (uint32_t)(unsigned char)data[82] << 16 | (uint32_t)(unsigned char)data[83] << 24;
        if (84 + 50 * (uint64_t)n == size)
            return RESURF_FORMAT_STL;
    }
    resurfi_scanner s;
    resurfi_scan_init(&s, data, size);
    if (!resurfi_scan_skip_space(&s, '#'))
        return RESURF_FORMAT_AUTO;
    const char *tok;
    size_t len = resurfi_scan_token(&s, &tok);
    /* [ST][C][N][4][n]OFF */
    if (len >= 3 && memcmp(tok + len - 3, "OFF", 3) == 0) {
        size_t i = 0;
        if (len - i >= 5 && memcmp(tok, "ST", 2) == 0)
            i += 2;
        while (i < len - 3 && tok[i] && strchr("CN4n", tok[i]))
            ++i;
        if (i == len - 3)
            return RESURF_FORMAT_OFF;
    }
    if (len >= 5 && memcmp(tok, "solid", 5) == 0)
        return RESURF_FORMAT_STL;
    static const char *const obj_words[] = {"v", "vt", "vn", "f", "o", "g", "mtllib", "usemtl", "s"};
    for (size_t k = 0; k < sizeof obj_words / sizeof *obj_words; ++k)
        if (len == strlen(obj_words[k]) && memcmp(tok, obj_words[k], len) == 0)
            return RESURF_FORMAT_OBJ;
    return RESURF_FORMAT_AUTO;
}

/* ---- the "C" locale for the duration of a call --------------------------------------------------------------- */

typedef struct c_locale_scope {
    locale_t c, previous;
} c_locale_scope;

static void enter_c_locale(c_locale_scope *scope)
{
    scope->c = newlocale(LC_ALL_MASK, "C", (locale_t)0);
    scope->previous = scope->c ? uselocale(scope->c) : (locale_t)0;
}

static void leave_c_locale(c_locale_scope *scope)
{
    if (!scope->c)
        return;
    uselocale(scope->previous);
    freelocale(scope->c);
}

/* ---- helpers for the readers --------------------------------------------------------------------------------- */

resurf_status resurfi_load_progress(resurfi_load *ld, const char *pos)
{
    double fraction = ld->size ? (double)(pos - ld->data) / (double)ld->size : 1.0;
    if (resurfi_progress(ld->progress, "load", fraction))
        return resurfi_fail(ld->error, RESURF_ERR_CANCELLED, ld->path, 0, -1, "cancelled by the progress callback");
    return RESURF_OK;
}

resurf_status resurfi_check_triangle_limit(resurfi_load *ld, size_t triangle_count, long long line,
                                           long long offset)
{
    if (ld->max_triangles == 0 || triangle_count <= ld->max_triangles)
        return RESURF_OK;
    return resurfi_fail(ld->error, RESURF_ERR_LIMIT, ld->path, line, line > 0 ? -1 : offset,
                        "more than %zu triangles (the max_triangles limit)", ld->max_triangles);
}

resurf_status resurfi_parse_fail(resurfi_load *ld, long long line, long long offset, const char *fmt, ...)
{
    char message[sizeof ld->error->message];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message, sizeof message, fmt, ap);
    va_end(ap);
    return resurfi_fail(ld->error, RESURF_ERR_PARSE, ld->path, line, line > 0 ? -1 : offset, "%s", message);
}

resurf_status resurfi_load_oom(resurfi_load *ld, const char *what)
{
    return resurfi_fail(ld->error, RESURF_ERR_OUT_OF_MEMORY, ld->path, 0, -1, "out of memory reading the %s", what);
}

/* ---- loading ------------------------------------------------------------------------------------------------- */

resurf_load_options resurf_load_options_default(void)
{
    resurf_load_options o;
    memset(&o, 0, sizeof o);
    o.struct_size = sizeof o;
    o.format = RESURF_FORMAT_AUTO;
    o.max_triangles = 100000000;
    return o;
}

/* Parses bytes already in memory. name is for messages (may be NULL); format AUTO means "from name, else sniff". */
static resurf_status load_bytes(const char *data, size_t size, resurf_format format, const char *name,
                                const resurf_load_options *opts, resurf_mesh **out_mesh, resurf_error *error)
{
    if (size == 0)
        return resurfi_fail(error, RESURF_ERR_PARSE, name, 0, -1, "the file is empty");
    if (format == RESURF_FORMAT_AUTO)
        format = sniff_format(data, size);
    if (format == RESURF_FORMAT_AUTO)
        return resurfi_fail(error, RESURF_ERR_UNSUPPORTED, name, 0, -1,
                            "cannot tell the format from the name or the content (obj, ply, off or stl)");
    resurfi_load ld = {
        .data = data,
        .size = size,
        .path = name,
        .max_triangles = opts->max_triangles,
        .progress = &opts->progress,
        .alloc = opts->allocator,
        .error = error,
    };
    resurf_mesh *mesh = NULL;
    resurf_status status;
    c_locale_scope scope;
    enter_c_locale(&scope);
    switch (format) {
    case RESURF_FORMAT_OBJ: status = resurfi_read_obj(&ld, &mesh); break;
    case RESURF_FORMAT_PLY: status = resurfi_read_ply(&ld, &mesh); break;
    case RESURF_FORMAT_OFF: status = resurfi_read_off(&ld, &mesh); break;
    case RESURF_FORMAT_STL: status = resurfi_read_stl(&ld, &mesh); break;
    default:
        status = resurfi_fail(error, RESURF_ERR_INVALID_OPTIONS, name, 0, -1, "unknown format %d", (int)format);
        break;
    }
    leave_c_locale(&scope);
    if (status != RESURF_OK)
        return status;
    if (resurfi_progress(&opts->progress, "load", 1.0)) {
        resurf_mesh_free(mesh);
        return resurfi_fail(error, RESURF_ERR_CANCELLED, name, 0, -1, "cancelled by the progress callback");
    }
    *out_mesh = mesh;
    resurfi_clear_error(error);
    return RESURF_OK;
}

resurf_status resurf_mesh_load_memory(const void *data, size_t size, resurf_format format, const char *name,
                                      const resurf_load_options *options, resurf_mesh **out_mesh,
                                      resurf_error *error)
{
    if (!out_mesh || (!data && size))
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "data or out_mesh is NULL");
    *out_mesh = NULL;
    RESURFI_CHECK_OPTIONS_ALLOC(options, resurf_load_options, error);
    resurf_load_options opts = options ? *options : resurf_load_options_default();
    if ((unsigned)format >= RESURF_FORMAT_COUNT)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "unknown format %d", (int)format);
    if (format == RESURF_FORMAT_AUTO)
        format = opts.format;
    if ((unsigned)format >= RESURF_FORMAT_COUNT)
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "unknown format %d", (int)format);
    if (format == RESURF_FORMAT_AUTO && name)
        format = resurf_format_from_path(name);
    return load_bytes(data, size, format, name, &opts, out_mesh, error);
}

/* Bytes a stream (a pipe, or a file whose size the system does not know) may deliver before the load gives up:
 * 64 MiB plus 1 KiB per allowed triangle, far more than any format spends on a triangle (a text OBJ with normals
 * and texture coordinates needs about 150 bytes), so that an endless writer cannot eat all memory. */
static size_t stream_limit(size_t max_triangles)
{
    const size_t base = (size_t)64 << 20, per_triangle = 1024;
    if (max_triangles == 0 || max_triangles > (SIZE_MAX / 2 - base) / per_triangle)
        return SIZE_MAX / 2;
    return base + per_triangle * max_triangles;
}

/* Reads the whole file into one buffer (sized by fstat, so a regular file takes one read). Refuses folders,
 * devices and sockets; reads pipes up to stream_limit(). */
static resurf_status read_file(const char *path, const resurf_load_options *opts, char **out_data, size_t *out_size,
                               resurf_error *error)
{
    /* Look before opening: opening a device can have effects of its own (a tape rewinds, a tty becomes ours). */
    struct stat st;
    if (stat(path, &st) == 0) {
        if (S_ISDIR(st.st_mode))
            return resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "is a directory, not a mesh file");
        if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode))
            return resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "is a device or socket, not a mesh file");
    }
    /* O_NONBLOCK: opening a FIFO that no process writes to would wait for a writer forever. Reads block again
     * below, and a FIFO without a writer reads as the end of the file. */
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0)
        return resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "cannot open: %s", strerror(errno));
    int fl = fcntl(fd, F_GETFL);
    if (fstat(fd, &st) != 0 || fl < 0 || fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) != 0) {
        int e = errno;
        close(fd);
        return resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "cannot read: %s", strerror(e));
    }
    if (S_ISDIR(st.st_mode)) {
        close(fd);
        return resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "is a directory, not a mesh file");
    }
    if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode)) {
        close(fd);
        return resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "is a device or socket, not a mesh file");
    }
    if (S_ISREG(st.st_mode) && (uint64_t)st.st_size >= SIZE_MAX / 2) {
        close(fd);
        return resurfi_fail(error, RESURF_ERR_LIMIT, path, 0, -1, "the file is too large for this machine");
    }
    /* A regular file's size is known: the buffer it needs is justified by the file. Pipes (and files that report
     * size 0, such as those of /proc) grow the buffer as data comes, up to a limit. */
    const bool sized = S_ISREG(st.st_mode) && st.st_size > 0;
    const size_t limit = sized ? SIZE_MAX / 2 : stream_limit(opts->max_triangles);
    size_t cap = sized ? (size_t)st.st_size + 1 : 1 << 16, size = 0;
    char *data = resurfi_alloc(opts->allocator, cap, 1);
    if (!data) {
        close(fd);
        return resurfi_fail(error, RESURF_ERR_OUT_OF_MEMORY, path, 0, -1, "out of memory reading %zu bytes", cap);
    }
    resurf_status status = RESURF_OK;
    for (;;) {
        if (size == cap) {
            if (size >= limit) {
                status = resurfi_fail(error, RESURF_ERR_LIMIT, path, 0, -1,
                                      "the stream goes on past %zu bytes, more than the max_triangles limit (%zu "
                                      "triangles) can need",
                                      limit, opts->max_triangles);
                break;
            }
            size_t grown = cap < limit / 2 ? cap * 2 : limit;
            char *bigger = resurfi_realloc(opts->allocator, data, grown, 1);
            if (!bigger) {
                status = resurfi_fail(error, RESURF_ERR_OUT_OF_MEMORY, path, 0, -1, "out of memory reading the file");
                break;
            }
            data = bigger;
            cap = grown;
        }
        ssize_t n = read(fd, data + size, cap - size);
        if (n < 0 && errno == EINTR) {
            /* A signal interrupted a read that waits on a pipe: the caller may want to stop. */
            if (resurfi_progress(&opts->progress, "load", 0.0)) {
                status = resurfi_fail(error, RESURF_ERR_CANCELLED, path, 0, -1, "cancelled by the progress callback");
                break;
            }
            continue;
        }
        if (n < 0) {
            status = resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "cannot read: %s", strerror(errno));
            break;
        }
        if (n == 0)
            break;
        size += (size_t)n;
    }
    close(fd);
    if (status != RESURF_OK) {
        resurfi_free(opts->allocator, data);
        return status;
    }
    *out_data = data;
    *out_size = size;
    return RESURF_OK;
}

resurf_status resurf_mesh_load(const char *path, const resurf_load_options *options, resurf_mesh **out_mesh,
                               resurf_error *error)
{
    if (!path || !out_mesh)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "path or out_mesh is NULL");
    *out_mesh = NULL;
    RESURFI_CHECK_OPTIONS_ALLOC(options, resurf_load_options, error);
    resurf_load_options opts = options ? *options : resurf_load_options_default();
    if ((unsigned)opts.format >= RESURF_FORMAT_COUNT)
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "unknown format %d", (int)opts.format);
    resurf_format format = opts.format != RESURF_FORMAT_AUTO ? opts.format : resurf_format_from_path(path);
    char *data = NULL;
    size_t size = 0;
    c_locale_scope scope; /* so that strerror speaks the "C" locale too, like every other message */
    enter_c_locale(&scope);
    resurf_status status = read_file(path, &opts, &data, &size, error);
    leave_c_locale(&scope);
    if (status != RESURF_OK)
        return status;
    status = load_bytes(data, size, format, path, &opts, out_mesh, error);
    resurfi_free(opts.allocator, data);
    return status;
}

/* ---- saving -------------------------------------------------------------------------------------------------- */

resurf_save_options resurf_save_options_default(void)
{
    resurf_save_options o;
    memset(&o, 0, sizeof o);
    o.struct_size = sizeof o;
    o.format = RESURF_FORMAT_AUTO;
    o.binary = 1;
    o.write_normals = o.write_texcoords = o.write_colors = o.write_extras = 1;
    return o;
}

/* Can the mesh be written so that it loads back? Indices in range and finite positions (the readers refuse NaN). */
static resurf_status check_mesh(const resurf_mesh *m, resurf_error *error)
{
    if (m->vertex_count > UINT32_MAX || m->triangle_count > UINT32_MAX)
        return resurfi_error(error, RESURF_ERR_INVALID_MESH, "more than 2^32 vertices or triangles");
    if ((m->vertex_count && !m->positions) || (m->triangle_count && !m->indices))
        return resurfi_error(error, RESURF_ERR_INVALID_MESH, "the mesh has no positions or no indices");
    for (size_t i = 0; i < 3 * m->triangle_count; ++i)
        if (m->indices[i] >= m->vertex_count)
            return resurfi_error(error, RESURF_ERR_INVALID_MESH, "triangle %zu refers to vertex %u of %zu", i / 3,
                                 m->indices[i], m->vertex_count);
    for (size_t i = 0; i < 3 * m->vertex_count; ++i)
        if (!isfinite(m->positions[i]))
            return resurfi_error(error, RESURF_ERR_INVALID_MESH, "vertex %zu has a non-finite coordinate", i / 3);
    return RESURF_OK;
}

static uint64_t mix64(uint64_t h)
{
    h ^= h >> 31;
    h *= 0x9e3779b97f4a7c15ull;
    h ^= h >> 29;
    h *= 0xbf58476d1ce4e5b9ull;
    return h ^ (h >> 32);
}

/* Creates "<dir>/.<name>.tmp-XXXXXX" with O_EXCL (so the umask applies as for any new file; mkstemp would force
 * 0600) and returns its descriptor, or -1 with errno set. tmp receives the name. */
static int create_temp(const char *path, char *tmp, size_t tmp_size)
{
    const char *slash = strrchr(path, '/');
    int dir_len = slash ? (int)(slash - path) + 1 : 0; /* keeps the slash; "/x" stays in "/" */
    const char *name = slash ? slash + 1 : path;
    struct timespec now;
    clock_gettime(CLOCK_REALTIME, &now);
    uint64_t seed = mix64((uint64_t)now.tv_nsec ^ (uint64_t)now.tv_sec << 32 ^ (uint64_t)getpid() ^
                          (uint64_t)(uintptr_t)&now);
    static const char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
    for (int attempt = 0; attempt < 100; ++attempt) {
        uint64_t r = mix64(seed + (uint64_t)attempt * 0x9e3779b97f4a7c15ull);
        char suffix[7];
        for (int i = 0; i < 6; ++i, r /= 62)
            suffix[i] = alphabet[r % 62];
        suffix[6] = 0;
        int n = snprintf(tmp, tmp_size, "%.*s.%s.tmp-%s", dir_len, path, name, suffix);
        if (n < 0 || (size_t)n >= tmp_size) {
            errno = ENAMETOOLONG;
            return -1;
        }
        int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0 || errno != EEXIST)
            return fd;
    }
    errno = EEXIST;
    return -1;
}

resurf_status resurf_mesh_save(const resurf_mesh *mesh, const char *path, const resurf_save_options *options,
                               resurf_error *error)
{
    if (!mesh || !path || !*path)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "mesh or path is NULL or empty");
    RESURFI_CHECK_OPTIONS_ALLOC(options, resurf_save_options, error);
    resurf_save_options opts = options ? *options : resurf_save_options_default();
    if ((unsigned)opts.format >= RESURF_FORMAT_COUNT)
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "unknown format %d", (int)opts.format);
    resurf_format format = opts.format != RESURF_FORMAT_AUTO ? opts.format : resurf_format_from_path(path);
    if (format == RESURF_FORMAT_AUTO)
        return resurfi_fail(error, RESURF_ERR_UNSUPPORTED, path, 0, -1,
                            "cannot tell the format from the name (use .obj, .ply, .off or .stl, or set format)");
    const char *slash = strrchr(path, '/');
    if (!(slash ? slash[1] : path[0]))
        return resurfi_fail(error, RESURF_ERR_INVALID_ARGUMENT, path, 0, -1, "the path names a folder, not a file");
    resurf_status status = check_mesh(mesh, error);
    if (status != RESURF_OK)
        return status;

    c_locale_scope scope;
    enter_c_locale(&scope);
    const resurf_allocator *alloc = resurfi_allocator_of(opts.allocator, mesh);
    size_t tmp_size = strlen(path) + 32;
    char *tmp = resurfi_alloc(alloc, tmp_size, 1);
    resurfi_writer w = {.fd = -1, .cap = 1 << 18, .progress = &opts.progress};
    w.buf = resurfi_alloc(alloc, w.cap, 1);
    if (!tmp || !w.buf) {
        status = resurfi_fail(error, RESURF_ERR_OUT_OF_MEMORY, path, 0, -1, "out of memory");
        goto done;
    }
    w.fd = create_temp(path, tmp, tmp_size);
    if (w.fd < 0) {
        int e = errno;
        int dir_len = slash ? (slash == path ? 1 : (int)(slash - path)) : 1;
        status = resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "cannot create a temporary file in '%.*s': %s",
                              dir_len, slash ? path : ".", strerror(e));
        goto done;
    }
    /* An existing file keeps its permissions. */
    struct stat st;
    if (stat(path, &st) == 0 && S_ISREG(st.st_mode))
        (void)fchmod(w.fd, st.st_mode & 07777);

    switch (format) {
    case RESURF_FORMAT_OBJ: status = resurfi_write_obj(&w, mesh, &opts); break;
    case RESURF_FORMAT_PLY: status = resurfi_write_ply(&w, mesh, &opts); break;
    case RESURF_FORMAT_OFF: status = resurfi_write_off(&w, mesh, &opts); break;
    case RESURF_FORMAT_STL: status = resurfi_write_stl(&w, mesh, &opts); break;
    default: status = RESURF_ERR_INTERNAL; break;
    }
    if (status == RESURF_OK && w.cancelled)
        status = RESURF_ERR_CANCELLED;
    if (status == RESURF_OK)
        resurfi_write_flush(&w);
    int fd = w.fd;
    w.fd = -1;
    if (close(fd) != 0 && !w.err && status == RESURF_OK)
        w.err = errno ? errno : EIO;
    if (status == RESURF_ERR_CANCELLED)
        status = resurfi_fail(error, status, path, 0, -1, "cancelled by the progress callback");
    else if (status != RESURF_OK)
        status = resurfi_fail(error, status, path, 0, -1, "internal error writing the file");
    else if (w.err)
        status = resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "cannot write: %s", strerror(w.err));
    else if (rename(tmp, path) != 0)
        status = resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "cannot replace the file: %s", strerror(errno));
    if (status != RESURF_OK)
        unlink(tmp);
    else {
        (void)resurfi_progress(&opts.progress, "save", 1.0); /* too late to cancel: the file is in place */
        resurfi_clear_error(error);
    }
done:
    leave_c_locale(&scope);
    resurfi_free(alloc, tmp);
    resurfi_free(alloc, w.buf);
    return status;
}

resurf_status resurfi_save_file(const char *path, const void *data, size_t size, const resurf_allocator *alloc,
                                resurf_error *error)
{
    const char *slash = strrchr(path, '/');
    if (!(slash ? slash[1] : path[0]))
        return resurfi_fail(error, RESURF_ERR_INVALID_ARGUMENT, path, 0, -1, "the path names a folder, not a file");
    size_t tmp_size = strlen(path) + 32;
    char *tmp = resurfi_alloc(alloc, tmp_size, 1);
    if (!tmp)
        return resurfi_fail(error, RESURF_ERR_OUT_OF_MEMORY, path, 0, -1, "out of memory");
    resurf_status status = RESURF_OK;
    int fd = create_temp(path, tmp, tmp_size);
    if (fd < 0) {
        int e = errno;
        int dir_len = slash ? (slash == path ? 1 : (int)(slash - path)) : 1;
        status = resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "cannot create a temporary file in '%.*s': %s",
                              dir_len, slash ? path : ".", strerror(e));
        resurfi_free(alloc, tmp);
        return status;
    }
    struct stat st;
    if (stat(path, &st) == 0 && S_ISREG(st.st_mode))
        (void)fchmod(fd, st.st_mode & 07777);
    int err = 0;
    for (const char *p = data, *end = p + size; p < end && !err;) {
        ssize_t n = write(fd, p, (size_t)(end - p));
        if (n > 0)
            p += n;
        else if (n < 0 && errno != EINTR)
            err = errno;
    }
    if (close(fd) != 0 && !err)
        err = errno ? errno : EIO;
    if (err)
        status = resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "cannot write: %s", strerror(err));
    else if (rename(tmp, path) != 0)
        status = resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "cannot replace the file: %s", strerror(errno));
    if (status != RESURF_OK)
        unlink(tmp);
    resurfi_free(alloc, tmp);
    return status;
}
