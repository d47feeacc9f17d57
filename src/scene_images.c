/* The images of a scene: external image files are read when the scene loads, so that every output is whole by
 * itself: a .glb (or a .gltf with embedded data) carries their bytes in a bufferView with the mimeType their first
 * bytes show, and a .gltf gets a copy of each beside itself under its relative name.
 *
 * A uri is a URI reference (glTF 2.0, 3.9; RFC 3986): percent-encoded, '/'-separated, relative to the document's
 * folder. Files written on Windows often carry '\' separators (".\x.jpg"), which are read as '/'. A name that
 * climbs out of the document's folder ("../textures/x.png") or is absolute is copied under its last component, so
 * that no copy lands outside the output's folder. */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "file.h"
#include "scene_internal.h"

void resurfi_scene_free_images(resurf_scene *s)
{
    for (size_t i = 0; i < s->image_count; ++i) {
        if (!s->images[i].shared)
            resurfi_free(&s->alloc, s->images[i].data);
        resurfi_free(&s->alloc, s->images[i].path);
        resurfi_free(&s->alloc, s->images[i].name);
        resurfi_free(&s->alloc, s->images[i].uri);
    }
    resurfi_free(&s->alloc, s->images);
    s->images = NULL;
    s->image_count = 0;
}

const char *resurfi_image_mime_type(const unsigned char *b, size_t n)
{
    if (n >= 8 && !memcmp(b, "\x89PNG\r\n\x1a\n", 8))
        return "image/png";
    if (n >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF)
        return "image/jpeg";
    if (n >= 12 && !memcmp(b, "RIFF", 4) && !memcmp(b + 8, "WEBP", 4))
        return "image/webp"; /* EXT_texture_webp */
    if (n >= 12 && !memcmp(b, "\xABKTX 20\xBB\r\n\x1a\n", 12))
        return "image/ktx2"; /* KHR_texture_basisu */
    if (n >= 4 && !memcmp(b, "DDS ", 4))
        return "image/vnd-ms.dds"; /* MSFT_texture_dds */
    return NULL;
}

/* The type a name's extension gives, when the bytes say nothing known. */
static const char *mime_of_name(const char *name)
{
    static const char *const table[][2] = {{".png", "image/png"},   {".jpg", "image/jpeg"}, {".jpeg", "image/jpeg"},
                                           {".webp", "image/webp"}, {".ktx2", "image/ktx2"}, {".dds", "image/vnd-ms.dds"}};
    for (size_t i = 0; i < sizeof table / sizeof *table; ++i)
        if (resurfi_ends_with_nocase(name, table[i][0]))
            return table[i][1];
    return NULL;
}

static int hex_digit(char c)
{
    return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
}

/* Does the uri start with a scheme ("http:", "file:") or a Windows drive ("C:")? Neither names a file of the
 * document's folder. */
static int has_scheme(const char *uri)
{
    size_t n = 0;
    while ((uri[n] >= 'a' && uri[n] <= 'z') || (uri[n] >= 'A' && uri[n] <= 'Z') ||
           (n > 0 && ((uri[n] >= '0' && uri[n] <= '9') || uri[n] == '+' || uri[n] == '-' || uri[n] == '.')))
        ++n;
    return n >= 1 && uri[n] == ':';
}

/* The decoded path of a uri ('%XX' decoded, '\' read as '/') into out (room for strlen(uri) + 1); 0 when it cannot
 * name a file (a scheme, a drive letter, an encoded NUL, a bad escape, nothing but separators). */
static int decode_uri(const char *uri, char *out)
{
    if (has_scheme(uri))
        return 0;
    size_t n = 0;
    for (const char *p = uri; *p; ++p) {
        char c = *p;
        if (c == '%') {
            int hi = hex_digit(p[1]), lo = hi < 0 ? -1 : hex_digit(p[2]);
            if (lo < 0 || (hi == 0 && lo == 0))
                return 0;
            c = (char)(hi * 16 + lo);
            p += 2;
        }
        out[n++] = c == '\\' ? '/' : c;
    }
    out[n] = 0;
    return n > 0 && out[n - 1] != '/';
}

/* The relative name of a decoded path inside the output's folder (in place): "." and empty components go, ".."
 * removes the one before it; a path that is absolute or climbs above its folder keeps its last component. */
static void output_name(char *path)
{
    int escapes = path[0] == '/';
    char *w = path; /* the name so far ends at w; never past the component being read */
    for (char *r = path; *r;) {
        char *end = strchr(r, '/');
        size_t len = end ? (size_t)(end - r) : strlen(r);
        if (len == 2 && r[0] == '.' && r[1] == '.') {
            if (w == path)
                escapes = 1;
            while (w > path && w[-1] != '/')
                --w;
            if (w > path)
                --w;
        } else if (len > 0 && !(len == 1 && r[0] == '.')) {
            if (w > path)
                *w++ = '/';
            memmove(w, r, len);
            w += len;
        }
        r += len + (end != NULL);
    }
    *w = 0;
    if (escapes) {
        char *last = strrchr(path, '/');
        if (last)
            memmove(path, last + 1, strlen(last + 1) + 1);
    }
}

/* name, percent-encoded as a uri (unreserved characters and '/' as they are). */
static char *encode_uri(const resurf_allocator *a, const char *name)
{
    static const char hex[] = "0123456789ABCDEF";
    char *out = resurfi_alloc(a, 3 * strlen(name) + 1, 1);
    if (!out)
        return NULL;
    size_t n = 0;
    for (const unsigned char *p = (const unsigned char *)name; *p; ++p) {
        if ((*p >= 'A' && *p <= 'Z') || (*p >= 'a' && *p <= 'z') || (*p >= '0' && *p <= '9') || strchr("-._~/", *p))
            out[n++] = (char)*p;
        else
            out[n++] = '%', out[n++] = hex[*p >> 4], out[n++] = hex[*p & 15];
    }
    out[n] = 0;
    return out;
}

/* A uri from the document may hold control characters: a message stays one printable line. */
static void printable(char *text)
{
    for (char *m = text; *m; ++m)
        if ((unsigned char)*m < 0x20 || *m == 0x7f)
            *m = '?';
}

static resurf_status oom(resurf_error *error, const char *path)
{
    return resurfi_fail(error, RESURF_ERR_OUT_OF_MEMORY, path, 0, -1, "out of memory reading the images");
}

/* Image i: reads its file into s->images[i], or (allow_missing) records a warning that it is missing. */
static resurf_status load_image(resurf_scene *s, size_t i, const char *dir, const char *doc_path, int allow_missing,
                                resurf_error *error)
{
    const resurfi_gltf_image *g = &s->view->images[i];
    resurfi_scene_image *img = &s->images[i];
    size_t uri_len = strlen(g->uri), dir_len = dir ? strlen(dir) : 0;
    img->path = resurfi_alloc(&s->alloc, dir_len + uri_len + 1, 1);
    img->name = resurfi_alloc(&s->alloc, uri_len + 1, 1);
    if (!img->path || !img->name)
        return oom(error, doc_path);
    img->path[0] = 0; /* until the uri names a file */
    char reason[300] = "";
    if (!decode_uri(g->uri, img->name)) {
        snprintf(reason, sizeof reason, "the uri names no file of the document's folder");
    } else if (!dir) {
        snprintf(reason, sizeof reason, "a document loaded from memory cannot refer to files");
    } else {
        snprintf(img->path, dir_len + uri_len + 1, "%s%s", img->name[0] == '/' ? "" : dir, img->name);
        output_name(img->name);
        resurf_error rerr;
        resurf_status status = RESURF_ERR_IO;
        for (size_t j = 0; j < i && status != RESURF_OK; ++j)
            if (s->images[j].data && !strcmp(s->images[j].path, img->path)) {
                /* One file named by several images is read once (a small document cannot make it read
                 * again and again). */
                img->data = s->images[j].data;
                img->size = s->images[j].size;
                img->shared = 1;
                status = RESURF_OK;
            }
        if (status != RESURF_OK)
            status = resurfi_read_file(&s->alloc, img->path, (uint64_t)1 << 32, 0, NULL, (char **)&img->data,
                                       &img->size, &rerr);
        if (status == RESURF_ERR_OUT_OF_MEMORY)
            return oom(error, doc_path);
        if (status == RESURF_OK) {
            const char *mime = resurfi_image_mime_type(img->data, img->size);
            if (!mime)
                mime = g->mime_type[0] ? g->mime_type : mime_of_name(img->name);
            snprintf(img->mime, sizeof img->mime, "%s", mime ? mime : "");
            if (!(img->uri = encode_uri(&s->alloc, img->name)))
                return oom(error, doc_path);
            if (mime)
                return RESURF_OK;
            char text[1200];
            snprintf(text, sizeof text, "images[%zu]: '%.800s' is no PNG, JPEG, WebP, KTX2 or DDS image: outputs "
                     "refer to a copy beside them instead of embedding it", i, img->path);
            printable(text);
            return resurfi_scene_add_warning(s, text) == RESURF_OK ? RESURF_OK : oom(error, doc_path);
        }
        snprintf(reason, sizeof reason, "%s", rerr.message);
    }
    img->missing = 1;
    char text[2400];
    if (img->path[0])
        snprintf(text, sizeof text, "images[%zu]: the image '%.800s' (uri '%.800s') cannot be read: %s", i, img->path,
                 g->uri, reason);
    else
        snprintf(text, sizeof text, "images[%zu]: the image of uri '%.800s' cannot be read: %s", i, g->uri, reason);
    printable(text);
    if (!allow_missing) /* I/O when a file was tried; else the document asks for what resurf does not do */
        return resurfi_fail(error, img->path[0] ? RESURF_ERR_IO : RESURF_ERR_UNSUPPORTED, doc_path, 0, -1, "%s",
                            text);
    return resurfi_scene_add_warning(s, text) == RESURF_OK ? RESURF_OK : oom(error, doc_path);
}

resurf_status resurfi_scene_load_images(resurf_scene *s, const char *dir, const char *doc_path, int allow_missing,
                                        resurf_error *error)
{
    const resurfi_gltf_view *v = s->view;
    s->images = resurfi_calloc(&s->alloc, v->image_count + 1, sizeof *s->images);
    if (!s->images)
        return oom(error, doc_path);
    s->image_count = v->image_count;
    for (size_t i = 0; i < v->image_count; ++i) {
        if (v->images[i].buffer_view != RESURFI_GLTF_NONE || v->images[i].data || !v->images[i].uri[0])
            continue; /* in the document */
        resurf_status status = load_image(s, i, dir, doc_path, allow_missing, error);
        if (status != RESURF_OK)
            return status;
        if (s->images[i].missing)
            continue;
        /* Two different files under one name: the later one is renamed by its index. */
        for (size_t j = 0; j < i; ++j) {
            const resurfi_scene_image *a = &s->images[j], *b = &s->images[i];
            if (!a->data || strcmp(a->name, b->name) || a->data == b->data ||
                (a->size == b->size && !memcmp(a->data, b->data, a->size)))
                continue;
            const char *base = strrchr(s->images[i].name, '/');
            base = base ? base + 1 : s->images[i].name;
            size_t size = strlen(base) + 32;
            char *name = resurfi_alloc(&s->alloc, size, 1);
            if (!name)
                return oom(error, doc_path);
            snprintf(name, size, "image%zu_%s", i, base);
            resurfi_free(&s->alloc, s->images[i].name);
            resurfi_free(&s->alloc, s->images[i].uri);
            s->images[i].name = name;
            if (!(s->images[i].uri = encode_uri(&s->alloc, name)))
                return oom(error, doc_path);
            break;
        }
    }
    return RESURF_OK;
}

resurf_status resurfi_scene_out_image(const resurf_scene *s, size_t i, const char *out_path, int embed,
                                      resurfi_gltf_out_image *out, char **copy_to, resurf_error *error)
{
    const resurfi_gltf_image *g = &s->view->images[i];
    const resurfi_scene_image *img = &s->images[i];
    memset(out, 0, sizeof *out);
    *copy_to = NULL;
    const unsigned char *data = g->data ? g->data : img->data;
    size_t size = g->data ? g->size : img->size;
    if (!data) {
        if (img->missing)
            out->uri = g->uri; /* allowed to be missing: referenced as it was */
        return RESURF_OK;
    }
    if (g->data) { /* embedded in the source: embedded again, as it was */
        const char *mime = g->mime_type[0] ? g->mime_type : resurfi_image_mime_type(data, size);
        out->data = data;
        out->size = size;
        out->mime_type = mime ? mime : "";
        return RESURF_OK;
    }
    if (embed && img->mime[0]) {
        out->data = data;
        out->size = size;
        out->mime_type = img->mime;
        return RESURF_OK;
    }
    /* A .gltf's copy, or an image of a type no mimeType can name (a .tga): a copy beside the output. */
    out->uri = img->uri;
    const char *slash = strrchr(out_path, '/');
    size_t dir_len = slash ? (size_t)(slash - out_path) + 1 : 0, size_path = dir_len + strlen(img->name) + 1;
    char *target = resurfi_alloc(&s->alloc, size_path, 1);
    if (!target)
        return resurfi_fail(error, RESURF_ERR_OUT_OF_MEMORY, out_path, 0, -1, "out of memory writing the images");
    snprintf(target, size_path, "%.*s%s", (int)dir_len, out_path, img->name);
    struct stat a, b;
    if (stat(target, &a) == 0 && stat(img->path, &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino) {
        resurfi_free(&s->alloc, target); /* written beside its own input: already there */
        return RESURF_OK;
    }
    *copy_to = target;
    return RESURF_OK;
}

resurf_status resurfi_make_parent_folders(const char *path, resurf_error *error)
{
    size_t n = strlen(path);
    char buf[4096];
    if (n >= sizeof buf)
        return resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "the path is too long");
    memcpy(buf, path, n + 1);
    for (char *p = strchr(buf + 1, '/'); p; p = strchr(p + 1, '/')) {
        *p = 0;
        struct stat st;
        if (stat(buf, &st) != 0 && mkdir(buf, 0777) != 0 && errno != EEXIST)
            return resurfi_fail(error, RESURF_ERR_IO, buf, 0, -1, "cannot create the folder: %s", strerror(errno));
        *p = '/';
    }
    return RESURF_OK;
}

resurf_status resurfi_scene_image_bytes(const resurf_scene *s, size_t i, const unsigned char **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    if (!s->view || i >= s->view->image_count)
        return RESURF_ERR_INVALID_ARGUMENT;
    const resurfi_gltf_view *v = s->view;
    const resurfi_gltf_image *g = &v->images[i];
    if (g->data) {
        *data = g->data, *size = g->size;
    } else if (g->buffer_view != RESURFI_GLTF_NONE) {
        if (g->buffer_view < 0 || (size_t)g->buffer_view >= v->buffer_view_count)
            return RESURF_ERR_PARSE;
        const resurfi_gltf_buffer_view *bv = &v->buffer_views[g->buffer_view];
        if (bv->buffer < 0 || (size_t)bv->buffer >= v->buffer_count)
            return RESURF_ERR_PARSE;
        const resurfi_gltf_buffer *b = &v->buffers[bv->buffer];
        if (bv->byte_offset > b->size || bv->byte_length > b->size - bv->byte_offset)
            return RESURF_ERR_PARSE;
        *data = b->data + bv->byte_offset, *size = (size_t)bv->byte_length;
    } else if (i < s->image_count && s->images[i].data) {
        *data = s->images[i].data, *size = s->images[i].size;
    }
    return *data ? RESURF_OK : RESURF_ERR_IO;
}
