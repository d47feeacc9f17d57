/* Loading and saving meshes: format choice (by extension, by name, by content), dispatch to the format readers
 * and writers (io_obj.c, io_ply.c, io_off.c, io_stl.c), and the save through a temporary file in the target's
 * folder, renamed over the target only once it is completely written (file.c reads and writes the files; the
 * readers' shared helpers are in io_common.c).
 *
 * Both directions run in the "C" locale for their duration (uselocale: per thread, restored before returning), so
 * that strtod and printf read and write '.' as the decimal point whatever the application's locale is. */
#include <errno.h>
#include <locale.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "file.h"
#include "io_internal.h"

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
    if (resurfi_progress(&opts->progress, RESURF_STAGE_LOAD, 1.0)) {
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
    resurf_status status =
        resurfi_read_file(opts.allocator, path, 0, opts.max_triangles, &opts.progress, &data, &size, error);
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
    char *tmp = NULL;
    resurfi_writer w = {.fd = -1, .cap = 1 << 18, .progress = &opts.progress};
    w.buf = resurfi_alloc(alloc, w.cap, 1);
    if (!w.buf) {
        status = resurfi_fail(error, RESURF_ERR_OUT_OF_MEMORY, path, 0, -1, "out of memory");
        goto done;
    }
    if ((status = resurfi_temp_create(alloc, path, &tmp, &w.fd, error)) != RESURF_OK)
        goto done;

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
    if (status == RESURF_OK) {
        status = resurfi_temp_commit(alloc, tmp, path, error);
        tmp = NULL;
    }
    if (status == RESURF_OK) {
        (void)resurfi_progress(&opts.progress, RESURF_STAGE_SAVE, 1.0); /* too late to cancel: the file is in place */
        resurfi_clear_error(error);
    }
done:
    resurfi_temp_discard(alloc, tmp); /* not renamed into place: removed */
    leave_c_locale(&scope);
    resurfi_free(alloc, w.buf);
    return status;
}
