/* What scene.c (loading, checking, decoding, the public scene calls) shares with scene_save.c (writing). Not
 * installed, not used elsewhere. */
#ifndef RESURF_SCENE_INTERNAL_H
#define RESURF_SCENE_INTERNAL_H

#include "internal.h"
#include "io/gltf_shim.h"

/* The component type an attribute had in the source, so that extras (JOINTS_n as bytes, WEIGHTS_n normalized
 * shorts, ...) are written back as they came. */
typedef struct resurfi_scene_format {
    char name[64];
    int component_type;     /* RESURFI_GLTF_* */
    int normalized;
    int components;
} resurfi_scene_format;

typedef struct resurfi_scene_prim {
    resurf_scene_primitive info;
    resurf_mesh *mesh;      /* decoded; NULL for RESURF_PRIMITIVE_OTHER */
    size_t format_count;
    resurfi_scene_format *formats;
    size_t lod_count;
    resurf_mesh **lods;     /* lods[k - 1] is level k */
} resurfi_scene_prim;

/* An image of the source (scene_images.c): an external file's bytes, read when the scene loads. */
typedef struct resurfi_scene_image {
    unsigned char *data;    /* the file's bytes; NULL when the image is in the document or missing */
    size_t size;
    char *path;             /* where it was read from */
    char *name;             /* its name beside a .gltf output (relative, inside the output's folder) */
    char *uri;              /* that name as a uri */
    char mime[32];          /* from its first bytes, else its mimeType, else its name; "" when unknown */
    int missing;            /* it could not be read (allowed by allow_missing_images) */
    int shared;             /* data belongs to an earlier image that names the same file */
} resurfi_scene_image;

struct resurf_scene {
    resurfi_gltf_doc *doc;  /* the loaded document, or NULL for a scene made from a mesh */
    const resurfi_gltf_view *view;
    size_t mesh_count;
    size_t *mesh_first;     /* mesh_count + 1: the primitives of mesh m are prims[mesh_first[m] .. mesh_first[m+1]) */
    double **coverage;      /* per mesh, NULL when unset */
    size_t *coverage_count;
    size_t prim_count;
    resurfi_scene_prim *prims;
    double (*world)[16];    /* per node: its world matrix (column-major) in the scene that first reaches it */
    int quantized;          /* the source declared KHR_mesh_quantization */
    int unknown_extensions; /* the source uses an extension that may refer to accessors or bufferViews */
    size_t warning_count;
    char **warnings;
    size_t image_count;     /* the source's images */
    resurfi_scene_image *images;
    resurf_allocator alloc; /* the scene's C blocks and meshes come from it (all zero: the C heap); the document
                               (doc, view) lives on the C++ heap */
};

/* The effective mesh of primitive p at level k (its last level when it has fewer). */
static inline const resurf_mesh *resurfi_scene_level_mesh(const resurfi_scene_prim *p, size_t level)
{
    if (level == 0 || p->lod_count == 0)
        return p->mesh;
    return p->lods[(level < p->lod_count ? level : p->lod_count) - 1];
}

/* Reads a whole regular file of at most max_bytes (NUL-terminated; *out from alloc). */
resurf_status resurfi_read_whole(const resurf_allocator *alloc, const char *path, uint64_t max_bytes,
                                 unsigned char **out, size_t *out_size, resurf_error *error);

/* Adds a load warning (a copy of text) to the scene; RESURF_ERR_OUT_OF_MEMORY when it cannot. */
resurf_status resurfi_scene_add_warning(resurf_scene *s, const char *text);

/* ---- extensions (scene_extensions.c) ---- */

/* Is the extension one resurf knows, so that whatever it refers to is kept? */
int resurfi_scene_extension_known(const char *name);
/* Does an unknown extension sit where it may refer to source accessors or bufferViews that the output must then
 * keep at their indices (anywhere but on a triangle primitive, which is rewritten without it)? */
int resurfi_scene_unknown_references(const resurf_scene *s);
/* The primitive extensions a rewritten primitive keeps (they hold whatever its triangles and vertices). */
extern const char *const resurfi_kept_primitive_extensions[];
extern const size_t resurfi_kept_primitive_extension_count;
/* Extensions of triangle primitives that their rewritten versions drop, counted per primitive. */
size_t resurfi_scene_dropped_extensions(const resurf_scene *s);
/* One load warning per extension dropped that way. */
resurf_status resurfi_scene_warn_dropped_extensions(resurf_scene *s);

/* ---- images (scene_images.c) ---- */

/* Reads the external images of a loaded document (dir: its folder, NULL for a document in memory). A missing or
 * unreadable image fails with RESURF_ERR_IO naming it, or with allow_missing is a warning. */
resurf_status resurfi_scene_load_images(resurf_scene *s, const char *dir, const char *doc_path, int allow_missing,
                                        resurf_error *error);
void resurfi_scene_free_images(resurf_scene *s);
/* How image i is written into the document at out_path: embedded (embed, or data the source had embedded), else
 * under its uri; *copy_to is then the file the caller writes the bytes to (from s->alloc), or NULL when nothing is
 * to be written (the image is in the document, or already there: the output is beside its own input). */
resurf_status resurfi_scene_out_image(const resurf_scene *s, size_t i, const char *out_path, int embed,
                                      resurfi_gltf_out_image *out, char **copy_to, resurf_error *error);
/* The mimeType that an image's first bytes show (PNG, JPEG, WebP, KTX2, DDS), or NULL. */
const char *resurfi_image_mime_type(const unsigned char *bytes, size_t size);
/* Creates the folders above path that do not exist. */
resurf_status resurfi_make_parent_folders(const char *path, resurf_error *error);

/* Does s end with suffix (given in lower case), ignoring ASCII case? */
int resurfi_ends_with_nocase(const char *s, const char *suffix);

/* Bytes of one component of a glTF component type, 0 for an unknown type. */
size_t resurfi_gltf_component_size(int component_type);

#endif
