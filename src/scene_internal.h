/* What scene.c (loading, decoding, the public scene calls) shares with scene_check.c (checking a document) and
 * scene_save.c (writing). Not installed, not used elsewhere. */
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
    size_t *instance_first; /* node_count + 1, or NULL: node n's EXT_mesh_gpu_instancing instances are */
    double (*instance_world)[16]; /* instance_world[instance_first[n] .. instance_first[n + 1]), world matrices */
    int quantized;          /* the source declared KHR_mesh_quantization */
    int unknown_extensions; /* the source uses an extension that may refer to accessors or bufferViews */
    size_t warning_count;
    char **warnings;
    size_t image_count;     /* the source's images */
    resurfi_scene_image *images;
    resurf_allocator alloc; /* the scene's C blocks and meshes come from it (all zero: the C heap); the document
                               (doc, view) lives on the C++ heap */
};

/* ---- levels and helpers -------------------------------------------------------------------------------------- */

/* Does primitive p take levels of detail and get written from its mesh (triangles, with or without morph targets)? */
static inline int resurfi_scene_rewritten(const resurfi_scene_prim *p)
{
    return p->info.kind == RESURF_PRIMITIVE_TRIANGLES || p->info.kind == RESURF_PRIMITIVE_MORPHED;
}

/* The effective mesh of primitive p at level k (its last level when it has fewer). */
static inline const resurf_mesh *resurfi_scene_level_mesh(const resurfi_scene_prim *p, size_t level)
{
    if (level == 0 || p->lod_count == 0)
        return p->mesh;
    return p->lods[(level < p->lod_count ? level : p->lod_count) - 1];
}

/* ---- the scene in world space (scene_world.c) ---- */

/* One mesh as one node shows it, with its levels: those set on its primitives (resurf_scene_set_lods), or the
 * meshes of the level nodes its MSFT_lod extension names (a file written with levels), shown with the node's own
 * world transform (resurf writes level nodes with the transform of the node they stand in for). */
typedef struct resurfi_scene_instance {
    size_t mesh;
    const double *world;             /* column-major 4 x 4, or NULL for the identity */
    size_t lod_count;                /* MSFT_lod levels: lod_mesh[k - 1] is level k's mesh */
    size_t lod_mesh[RESURF_SCENE_MAX_LEVELS - 1];
    size_t coverage_count;           /* extras.MSFT_screencoverage, or 0 */
    const double *coverage;
} resurfi_scene_instance;

typedef struct resurfi_scene_instances {
    size_t count;
    resurfi_scene_instance *items;   /* from the allocator given to resurfi_scene_gather */
} resurfi_scene_instances;

/* Levels that stand in for those set on the primitives (resurf_scene_build_lods measures its chains before they are
 * moved into the scene): chains[p] (when not NULL) holds counts[p] levels of primitive p. */
typedef struct resurfi_scene_levels {
    resurf_mesh *const *const *chains;
    const size_t *counts;
} resurfi_scene_levels;

/* One primitive as the scene's triangle budget sees it (scene_budget.c): its input and chain (levels kept: *kept),
 * its reports, the options and per-level error bounds (its units) of one more run, and its mesh's world scale.
 * A unit of primitives simplified together is one entry (parts > 0): input is its primitives joined (the caller's),
 * chain, kept and reports are the budget's own joined levels, and for its primitives p = members[q],
 * part_chains[p], part_kept[p] and part_reports + p * levels are theirs, which the budget writes back. */
typedef struct resurfi_budget_prim {
    const resurf_mesh *input;
    resurf_mesh **chain;              /* NULL: no levels */
    size_t *kept;
    resurf_simplify_report *reports;  /* one per level asked for */
    resurf_simplify_options sim;      /* without targets, progress or bound */
    double bounds[RESURF_SCENE_MAX_LEVELS - 1];
    double scale;
    size_t parts;
    const size_t *members;
    resurf_mesh ***part_chains;
    size_t *part_kept;
    resurf_simplify_report *part_reports;
    resurf_mesh *joined, **made;      /* the caller's joined input; the budget's: its levels as first joined */
    uint8_t *joined_lock;             /* the caller's */
    size_t joined_kept;
} resurfi_budget_prim;

resurf_status resurfi_scene_budget(resurfi_budget_prim *prims, size_t n, const double *ratios, size_t count,
                                   const resurf_allocator *alloc, resurf_error *e);

/* Every node with a mesh that the default scene (else scene 0, else every root node) reaches, depth first; a scene
 * made from a mesh file (no nodes): each mesh once, untransformed. RESURF_ERR_OUT_OF_MEMORY is the only failure. */
resurf_status resurfi_scene_gather(const resurf_scene *scene, const resurf_allocator *alloc,
                                   resurfi_scene_instances *out);
/* The glTF mesh that level k of item shows, and the level of its primitives to take (a primitive with fewer levels
 * shows its last: resurfi_scene_level_mesh). */
size_t resurfi_scene_instance_mesh(const resurfi_scene_instance *item, size_t k, size_t *prim_level);
/* Level `level` of the instances of list in one world-space mesh (from alloc): every primitive with a mesh at that
 * level (its last when it has fewer; from `levels` when not NULL), positions by the world matrix, normals by its
 * inverse transpose (renormalised); normals and TEXCOORD_0 kept when every included primitive has them. */
resurf_status resurfi_scene_flatten(const resurf_scene *scene, const resurfi_scene_instances *list, size_t level,
                                    const resurfi_scene_levels *levels, const resurf_allocator *alloc,
                                    resurf_mesh **out, resurf_error *error);

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
/* The encoded bytes of image i wherever the source keeps them (a data: URI, a bufferView, the external file read at
 * load), borrowed from the scene: RESURF_ERR_IO when there are none (a missing image), RESURF_ERR_PARSE for a
 * bufferView out of its buffer. */
resurf_status resurfi_scene_image_bytes(const resurf_scene *s, size_t i, const unsigned char **data, size_t *size);
/* The mimeType that an image's first bytes show (PNG, JPEG, WebP, KTX2, DDS), or NULL. */
const char *resurfi_image_mime_type(const unsigned char *bytes, size_t size);
/* Creates the folders above path that do not exist. */
resurf_status resurfi_make_parent_folders(const char *path, resurf_error *error);

/* Does s end with suffix (given in lower case), ignoring ASCII case? */
int resurfi_ends_with_nocase(const char *s, const char *suffix);

/* Bytes of one component of a glTF component type, 0 for an unknown type. */
size_t resurfi_gltf_component_size(int component_type);

/* ---- loading and checking (scene.c, scene_check.c) ----------------------------------------------------------- */

/* JSON nesting deeper than this is refused before any parser sees it (a glTF document needs about 10 levels;
 * extras may nest deeper, but not thousands of levels, which would exhaust a recursive parser's stack). */
#define RESURFI_MAX_JSON_DEPTH 128

/* One load: where errors go and the running totals. */
typedef struct load_ctx {
    const char *path;
    resurf_error *error;
    const resurfi_gltf_view *v;
    size_t max_triangles, triangles;
    uint64_t buffer_bytes;  /* all buffers together: what zero-filled accessors may claim at most */
    const resurf_progress *progress;
    const resurf_allocator *alloc; /* the call's: the scene, its meshes and the temporaries */
} load_ctx;

/* A parse error of the load, naming the file. */
#define FAIL(ctx, ...) resurfi_fail((ctx)->error, RESURF_ERR_PARSE, (ctx)->path, 0, -1, __VA_ARGS__)

/* Little-endian 32 bits, whatever the host. */
static inline uint32_t resurfi_get_u32le(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* The byte layout of one accessor element: matrices of 1- and 2-byte components pad each column to 4 bytes. */
typedef struct resurfi_gltf_element {
    size_t component_size, columns, rows, column_stride, size;
} resurfi_gltf_element;

static inline resurfi_gltf_element resurfi_gltf_element_of(const resurfi_gltf_accessor *a)
{
    resurfi_gltf_element e;
    e.component_size = resurfi_gltf_component_size(a->component_type);
    if (a->matrix) {
        e.columns = a->components == 4 ? 2 : a->components == 9 ? 3 : 4;
        e.rows = e.columns;
        e.column_stride = (e.rows * e.component_size + 3) & ~(size_t)3;
    } else {
        e.columns = 1;
        e.rows = (size_t)a->components;
        e.column_stride = e.rows * e.component_size;
    }
    e.size = e.columns * e.column_stride;
    return e;
}

/* One component of an accessor element, as a double. */
static inline double resurfi_gltf_read_component(const unsigned char *p, int type)
{
    switch (type) {
    case RESURFI_GLTF_BYTE: return (double)(int8_t)p[0];
    case RESURFI_GLTF_UNSIGNED_BYTE: return p[0];
    case RESURFI_GLTF_SHORT: return (double)(int16_t)(uint16_t)(p[0] | p[1] << 8);
    case RESURFI_GLTF_UNSIGNED_SHORT: return (double)(uint16_t)(p[0] | p[1] << 8);
    case RESURFI_GLTF_UNSIGNED_INT: return (double)resurfi_get_u32le(p);
    case RESURFI_GLTF_FLOAT: {
        uint32_t bits = resurfi_get_u32le(p);
        float f;
        memcpy(&f, &bits, 4);
        return f;
    }
    default: return 0;
    }
}

/* Is the JSON nested deeper than RESURFI_MAX_JSON_DEPTH? Strings (with escapes) are skipped. Returns the byte
 * offset of the first bracket too deep, or -1. */
long long resurfi_json_too_deep(const char *p, size_t size);

/* The checks of a parsed document (c->v) before any of its primitives is decoded: every number finite, every
 * bufferView and accessor in range (sparse indices included), every reference the shim recorded in range (the
 * required extensions were checked by the shim). Sets c->buffer_bytes. */
resurf_status resurfi_scene_check_document(load_ctx *c);
/* The node graph: meshes, children and scene roots in range, one parent per node, no cycle, roots are roots; then
 * each node's world matrix into s->world, and the world matrix of each of its EXT_mesh_gpu_instancing instances
 * (TRANSLATION VEC3, ROTATION VEC4, SCALE VEC3, one count) into s->instance_world. */
resurf_status resurfi_scene_check_nodes(load_ctx *c, resurf_scene *s);
/* How many times node n draws its mesh (its EXT_mesh_gpu_instancing instances, else once), and the world matrix of
 * the j-th time (column-major). */
size_t resurfi_scene_node_instances(const resurf_scene *s, size_t n);
const double *resurfi_scene_instance_world(const resurf_scene *s, size_t n, size_t j);
/* Reads a checked accessor into out (count × components doubles), normalized as the accessor says. */
void resurfi_scene_read_accessor(const resurfi_gltf_view *v, const resurfi_gltf_accessor *a, double *out);
/* The checks of one primitive (named `where` in messages) before it is decoded: its mode, its accessors (attributes,
 * morph targets, indices) and their counts, and its Draco extension's references. *out_count receives its vertex
 * count. */
resurf_status resurfi_scene_check_primitive(load_ctx *c, const resurfi_gltf_primitive *gp, const char *where,
                                            uint64_t *out_count);

#endif
