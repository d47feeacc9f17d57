/* The C interface over the C++ glTF and Draco code (gltf_read.cpp, gltf_write.cpp, draco.cpp). Only C types cross it:
 * no C++ type, exception or std::string. The C++ side parses, copies and serialises; it makes no accept/reject
 * decision about the content. scene_check.c checks every index, range and reference it gets here before anything
 * uses them (the reading side), and scene_save.c decides what is written (the writing side).
 *
 * Every function catches every exception and turns it into a resurf_status with a message. */
#ifndef RESURF_GLTF_SHIM_H
#define RESURF_GLTF_SHIM_H

#include <stddef.h>
#include <stdint.h>

#include "resurf/resurf.h"

#ifdef __cplusplus
extern "C" {
/* From src/internal.h, which C++ cannot include (its vector header uses C compound literals). */
resurf_status resurfi_fail(resurf_error *error, resurf_status status, const char *path, long long line,
                           long long offset, const char *fmt, ...) __attribute__((format(printf, 6, 7)));
/* From src/scene_internal.h (scene_extensions.c): is the extension one resurf reads or carries? */
int resurfi_scene_extension_known(const char *name);
#endif

/* ---- reading: a parsed document and a flat C view of it ---------------------------------------------------- */

/* glTF numbers used on both sides. */
enum {
    RESURFI_GLTF_BYTE = 5120,
    RESURFI_GLTF_UNSIGNED_BYTE = 5121,
    RESURFI_GLTF_SHORT = 5122,
    RESURFI_GLTF_UNSIGNED_SHORT = 5123,
    RESURFI_GLTF_UNSIGNED_INT = 5125,
    RESURFI_GLTF_FLOAT = 5126,
    RESURFI_GLTF_ARRAY_BUFFER = 34962,
    RESURFI_GLTF_ELEMENT_ARRAY_BUFFER = 34963,
};

/* An index as the file wrote it: RESURFI_GLTF_NONE when absent, RESURFI_GLTF_BAD when present but not an integer. */
#define RESURFI_GLTF_NONE (-1LL)
#define RESURFI_GLTF_BAD (-0x7fffffffffffffffLL)

typedef struct resurfi_gltf_buffer {
    const unsigned char *data; /* the bytes tinygltf loaded (GLB chunk, data: URI or external file) */
    size_t size;
} resurfi_gltf_buffer;

typedef struct resurfi_gltf_buffer_view {
    long long buffer;
    uint64_t byte_offset, byte_length, byte_stride; /* stride 0 = tightly packed */
} resurfi_gltf_buffer_view;

typedef struct resurfi_gltf_accessor {
    long long buffer_view;     /* RESURFI_GLTF_NONE: all zeros (before sparse values) */
    uint64_t byte_offset;
    int component_type;        /* RESURFI_GLTF_* as in the file (unchecked) */
    int normalized;
    uint64_t count;
    int components;            /* 1, 2, 3, 4 (VECn), 4, 9, 16 (MATn); 0 for an unknown type */
    int matrix;                /* 1 for MAT2/3/4 */
    int sparse;                /* 1 when sparse fields below are set */
    long long sparse_count;    /* the sparse fields as the file gives them (unchecked, may be negative) */
    long long sparse_indices_view, sparse_indices_offset;
    int sparse_indices_type;
    long long sparse_values_view, sparse_values_offset;
} resurfi_gltf_accessor;

/* A named index: an attribute (name → accessor) or a Draco attribute (name → Draco unique id). */
typedef struct resurfi_gltf_named {
    const char *name;
    long long index;
} resurfi_gltf_named;

typedef struct resurfi_gltf_primitive {
    int mode;                  /* as in the file (default 4) */
    long long indices;         /* accessor, or RESURFI_GLTF_NONE */
    size_t attribute_count;
    const resurfi_gltf_named *attributes;
    size_t target_count;       /* morph targets */
    const size_t *target_begin;/* target t has target_attributes[target_begin[t] .. target_begin[t + 1]) */
    const resurfi_gltf_named *target_attributes;
    int draco;                 /* 1 when it carries KHR_draco_mesh_compression */
    int draco_malformed;       /* 1 when that extension is not an object with an `attributes` object */
    long long draco_view;      /* its bufferView */
    size_t draco_attribute_count;
    const resurfi_gltf_named *draco_attributes; /* name → Draco unique id (RESURFI_GLTF_BAD: not an integer) */
    size_t extension_count;    /* the names of its other extensions (FB_ngon_encoding, KHR_materials_variants...) */
    const char *const *extensions;
    long long material;        /* RESURFI_GLTF_NONE when absent */
} resurfi_gltf_primitive;

typedef struct resurfi_gltf_mesh {
    const char *name;
    size_t primitive_count;
    const resurfi_gltf_primitive *primitives;
} resurfi_gltf_mesh;

typedef struct resurfi_gltf_node {
    long long mesh, skin, camera;
    int animated;              /* 1 when an animation channel targets its translation, rotation or scale */
    size_t child_count;
    const long long *children;
    size_t matrix_count, translation_count, rotation_count, scale_count; /* numbers the file gives (0: absent) */
    double matrix[16], translation[3], rotation[4], scale[3]; /* the first of them (matrix column-major) */
    size_t lod_count;          /* MSFT_lod: the level nodes' ids as the file gives them (unchecked; RESURFI_GLTF_BAD
                                  for a value that is not an integer), lod_count 0 without the extension */
    const long long *lod_ids;
    size_t coverage_count;     /* extras.MSFT_screencoverage's numbers (0 when absent or not all numbers) */
    const double *coverage;
    /* EXT_mesh_gpu_instancing: the accessors of its TRANSLATION, ROTATION and SCALE (RESURFI_GLTF_NONE when absent,
       RESURFI_GLTF_BAD when not an integer; unchecked, see refs); has_instances 0 without the extension */
    int has_instances;
    long long instance_attributes[3];
} resurfi_gltf_node;

typedef struct resurfi_gltf_scene {
    size_t node_count;
    const long long *nodes;
} resurfi_gltf_scene;

/* Any other index in the document: `where` names it ("skins[0].joints[3]"), `limit` is the size of the array it
 * points into (the index must be in [0, limit)). */
typedef struct resurfi_gltf_ref {
    const char *where;
    long long index;
    size_t limit;
} resurfi_gltf_ref;

/* An image as the file gives it. */
typedef struct resurfi_gltf_image {
    const char *uri;           /* "" when absent; a data: URI's bytes are in data */
    const char *mime_type;     /* "" when absent */
    long long buffer_view;     /* RESURFI_GLTF_NONE when absent */
    const unsigned char *data; /* the decoded bytes of a data: URI, else NULL */
    size_t size;
} resurfi_gltf_image;

/* What a material shows where it is lit (the preview draws it): pbrMetallicRoughness's base colour; and which
 * texcoord sets it uses at all. */
typedef struct resurfi_gltf_material {
    double base_color[4];      /* baseColorFactor (linear RGBA; default 1, 1, 1, 1) */
    long long base_color_texture; /* its baseColorTexture's texture, or RESURFI_GLTF_NONE */
    int base_color_texcoord;   /* ... and the TEXCOORD_n set it samples (default 0) */
    unsigned texcoords_used;   /* bit n: some texture of it (core or extension) samples TEXCOORD_n */
} resurfi_gltf_material;

/* A texture: its image and its sampler's wrap modes (glTF numbers: 10497 REPEAT (default), 33071 CLAMP_TO_EDGE,
 * 33648 MIRRORED_REPEAT). */
typedef struct resurfi_gltf_texture {
    long long source;          /* the image, or RESURFI_GLTF_NONE */
    int wrap_s, wrap_t;
} resurfi_gltf_texture;

typedef struct resurfi_gltf_view {
    size_t buffer_count, buffer_view_count, accessor_count, mesh_count, node_count, scene_count;
    const resurfi_gltf_buffer *buffers;
    const resurfi_gltf_buffer_view *buffer_views;
    const resurfi_gltf_accessor *accessors;
    const resurfi_gltf_mesh *meshes;
    const resurfi_gltf_node *nodes;
    const resurfi_gltf_scene *scenes;
    long long default_scene;   /* `scene`, or RESURFI_GLTF_NONE */
    size_t ref_count;
    const resurfi_gltf_ref *refs;
    size_t nonfinite_count;    /* numbers in the JSON that are not finite (1e999); first_nonfinite names one */
    const char *first_nonfinite;
    size_t extension_used_count, extension_required_count;
    const char *const *extensions_used;
    const char *const *extensions_required;
    size_t warning_count;      /* tinygltf's warnings and ours, one line each */
    const char *const *warnings;
    size_t image_count;
    const resurfi_gltf_image *images;
    size_t material_count, texture_count;
    const resurfi_gltf_material *materials;
    const resurfi_gltf_texture *textures;
    size_t outside_extension_count; /* extensions that appear on anything but a mesh primitive (each name once) */
    const char *const *outside_extensions;
} resurfi_gltf_view;

typedef struct resurfi_gltf_doc resurfi_gltf_doc;

/* Parses a glTF document. json/json_size: the JSON text (of a .gltf, or a .glb's JSON chunk); bin/bin_size: a .glb's
 * BIN chunk (NULL for .gltf or a .glb without one); base_dir: the folder external URIs are relative to ("" = cwd),
 * or NULL for a document in memory, which may not refer to external buffers (an error naming the uri);
 * name: for messages. KHR_draco_mesh_compression is never decoded here (the C side checks the references and
 * calls resurfi_draco_decode); external files are read only when regular and at most max_external_bytes long.
 * The JSON is checked against the glTF 2.0 schema first: the first problem fails with RESURF_ERR_PARSE naming the
 * JSON path and the cause, or (lenient) every problem becomes one of the view's warnings.
 * On success *out_doc owns the parsed document and its view. */
resurf_status resurfi_gltf_parse(const char *json, size_t json_size, const unsigned char *bin, size_t bin_size,
                                 int is_glb, const char *base_dir, const char *name, uint64_t max_external_bytes,
                                 int lenient, resurfi_gltf_doc **out_doc, resurf_error *error);
const resurfi_gltf_view *resurfi_gltf_doc_view(const resurfi_gltf_doc *doc);
void resurfi_gltf_doc_free(resurfi_gltf_doc *doc);

/* ---- writing: a plan built by scene_save.c --------------------------------------------------------------------- */

/* A new accessor with tightly packed data (or none, for a Draco primitive's accessor). */
typedef struct resurfi_gltf_out_accessor {
    int component_type, normalized;
    int components;            /* 1..4 (SCALAR, VECn) or 16 (MAT4) */
    uint64_t count;
    const void *data;          /* count × element bytes, or NULL (no bufferView: Draco) */
    size_t data_size;
    int target;                /* RESURFI_GLTF_ARRAY_BUFFER, RESURFI_GLTF_ELEMENT_ARRAY_BUFFER or 0 */
    int has_bounds;            /* min/max given (components values each) */
    double min[16], max[16];
} resurfi_gltf_out_accessor;

typedef struct resurfi_gltf_out_primitive {
    size_t source_mesh, source_primitive; /* material, extras, extensions and mode come from this primitive */
    int verbatim;              /* 1: write the source primitive as it is, with its own accessors (and Draco data) */
    size_t attribute_count;    /* the rest only when not verbatim: name → index into the plan's accessors */
    const resurfi_gltf_named *attributes;
    long long indices;         /* plan accessor (mode becomes triangles) */
    const unsigned char *draco;/* KHR_draco_mesh_compression payload, or NULL */
    size_t draco_size;
    const resurfi_gltf_named *draco_ids; /* attribute_count entries: glTF name → Draco unique id */
    size_t target_count;       /* morph targets: target t has target_attributes[target_begin[t] .. target_begin[t+1]) */
    const size_t *target_begin;
    const resurfi_gltf_named *target_attributes; /* name → index into the plan's accessors (never Draco) */
} resurfi_gltf_out_primitive;

/* One output mesh: source mesh `source_mesh` at one level. */
typedef struct resurfi_gltf_out_mesh {
    size_t source_mesh;
    unsigned level;            /* 0 keeps the source name; k > 0 appends "_LODk" */
    size_t primitive_count;
    const resurfi_gltf_out_primitive *primitives;
} resurfi_gltf_out_mesh;

/* How one source image is written. */
typedef struct resurfi_gltf_out_image {
    const unsigned char *data; /* bytes to embed in a bufferView of the output, with mime_type; NULL: see uri */
    size_t size;
    const char *mime_type;
    const char *uri;           /* data NULL: this uri (a file beside the output, or the source's own uri); both
                                  NULL: as the source has it (its bufferView) */
} resurfi_gltf_out_image;

typedef enum resurfi_gltf_layout {
    RESURFI_GLTF_PLAIN = 0,    /* level 0 meshes only */
    RESURFI_GLTF_MSFT_LOD,
    RESURFI_GLTF_SIDE_BY_SIDE,
} resurfi_gltf_layout;

typedef enum resurfi_gltf_container {
    RESURFI_GLTF_GLB = 0,      /* JSON + BIN chunk */
    RESURFI_GLTF_EMBEDDED,     /* JSON with a data: URI */
    RESURFI_GLTF_SEPARATE,     /* JSON naming bin_uri; the BIN bytes are returned for the caller to write */
} resurfi_gltf_container;

typedef struct resurfi_gltf_plan {
    size_t accessor_count;
    const resurfi_gltf_out_accessor *accessors;
    size_t source_mesh_count;  /* meshes of the source document (or of the synthesized graph) */
    size_t mesh_count;         /* output meshes, in this order: level 0 of every source mesh (these keep the source
                                  indices), then the higher levels */
    const resurfi_gltf_out_mesh *meshes;
    size_t level_count;        /* levels present (1 for PLAIN) */
    const long long *level_mesh; /* level_count × source mesh count: the output mesh of (level, mesh), or
                                    RESURFI_GLTF_NONE where the mesh has no such level */
    resurfi_gltf_layout layout;
    const double *coverage;    /* MSFT_LOD: per source mesh, level_count values, one per level (entries past a
                                  mesh's own levels are unused) */
    const unsigned char *restructure; /* MSFT_LOD: per node, 1 to move its mesh into a new child node */
    double level_offset[3];    /* SIDE_BY_SIDE: level k is translated by k × level_offset */
    int keep_all_source_data;  /* 1: keep every source accessor and bufferView at its index (an extension outside
                                  the known list may refer to them) */
    int draco_used, quantization_used; /* what extensionsUsed/Required must list */
    int synthesize_graph;      /* no source document: one scene, one node per level-0 mesh */
    const resurfi_gltf_out_image *images; /* one per source image */
    size_t kept_extension_count; /* rewritten primitives keep only these of their source's extensions */
    const char *const *kept_extensions;
    const char *generator;
    resurfi_gltf_container container;
    const char *bin_uri;       /* RESURFI_GLTF_SEPARATE */
} resurfi_gltf_plan;

/* Builds a fresh document from doc (may be NULL with synthesize_graph) and the plan, and serialises it: *out_json
 * (the .gltf text, or a whole .glb) and, for RESURFI_GLTF_SEPARATE, *out_bin. Both malloc'ed (free()). */
resurf_status resurfi_gltf_write(const resurfi_gltf_doc *doc, const resurfi_gltf_plan *plan,
                                 unsigned char **out_json, size_t *out_json_size, unsigned char **out_bin,
                                 size_t *out_bin_size, resurf_error *error);

/* ---- describing (gltf_describe.cpp) -------------------------------------------------------------------------- */

/* What the C side knows of each primitive (in file order). */
typedef struct resurfi_describe_prim {
    int has_mesh;              /* decoded into a mesh: triangles and vertices are its counts */
    size_t triangles, vertices;
    size_t attribute_count;    /* without a document only: the mesh's attribute names */
    const char *const *attributes;
} resurfi_describe_prim;

/* What the C side knows of each image of the document. */
typedef struct resurfi_describe_image {
    size_t bytes;
    int missing;
    const char *mime_type;     /* from its bytes, or NULL */
} resurfi_describe_image;

/* Describes the document (doc NULL: the one mesh prims[0]) as JSON (as_json) or text into dst, snprintf-like:
 * *out_length is the length of the whole description. */
resurf_status resurfi_gltf_describe(const resurfi_gltf_doc *doc, const resurfi_describe_prim *prims,
                                    const resurfi_describe_image *images, int as_json, char *dst, size_t dst_size,
                                    size_t *out_length, resurf_error *error);

/* ---- Draco (draco.cpp) -------------------------------------------------------------------------------------- */

enum {
    RESURFI_DRACO_POSITION = 0, /* draco::GeometryAttribute::Type values */
    RESURFI_DRACO_NORMAL = 1,
    RESURFI_DRACO_COLOR = 2,
    RESURFI_DRACO_TEX_COORD = 3,
    RESURFI_DRACO_GENERIC = 4,
};

/* A decoded attribute: raw numbers (integers are not normalized here) for each point, in point order. */
typedef struct resurfi_draco_attribute {
    int unique_id;
    int type;                  /* RESURFI_DRACO_* (or another draco type number) */
    int components;
    int integer;               /* 1 when stored as an integer type */
    double integer_max;        /* the largest value of that integer type (255 for uint8), 0 for floats */
    double *values;            /* point_count × components */
} resurfi_draco_attribute;

typedef struct resurfi_draco_mesh {
    size_t point_count, face_count;
    uint32_t *faces;           /* 3 × face_count point indices, each < point_count */
    size_t attribute_count;
    resurfi_draco_attribute *attributes;
} resurfi_draco_mesh;

/* Decodes a Draco mesh. Fails with RESURF_ERR_PARSE and Draco's message on a corrupt payload, and with
 * RESURF_ERR_UNSUPPORTED on a point cloud, which it does not decode (see draco.cpp). */
resurf_status resurfi_draco_decode(const void *data, size_t size, resurfi_draco_mesh **out, resurf_error *error);
void resurfi_draco_mesh_free(resurfi_draco_mesh *mesh);

enum { RESURFI_DRACO_F32 = 0, RESURFI_DRACO_U8, RESURFI_DRACO_U16, RESURFI_DRACO_U32, RESURFI_DRACO_I8,
       RESURFI_DRACO_I16 };

typedef struct resurfi_draco_input_attribute {
    int type;                  /* RESURFI_DRACO_POSITION .. GENERIC */
    int data_type;             /* RESURFI_DRACO_F32 .. I16 */
    int components;            /* 1..4 */
    int normalized;
    const void *values;        /* vertex_count × components of data_type */
    int quantization_bits;     /* float attributes: 1..30; ignored for integers */
} resurfi_draco_input_attribute;

typedef struct resurfi_draco_input {
    size_t vertex_count, triangle_count;
    const uint32_t *indices;   /* NULL with triangle_count 0: a point cloud */
    size_t attribute_count;
    const resurfi_draco_input_attribute *attributes;
    int compression_level;     /* 0..10 */
    int keep_order;            /* 1: the decoded points and triangles are the input's, in its order (sequential
                                  encoding, no points merged): for uncompressed morph targets beside the payload */
} resurfi_draco_input;

typedef struct resurfi_draco_output {
    unsigned char *data;       /* malloc'ed payload */
    size_t size;
    int unique_ids[32];        /* of attributes[i] */
    size_t encoded_points, encoded_faces; /* as the encoder tracked them */
} resurfi_draco_output;

/* Encodes a mesh (welding equal points first, as Draco's own tools do). At most 32 attributes. */
resurf_status resurfi_draco_encode(const resurfi_draco_input *in, resurfi_draco_output *out, resurf_error *error);

#ifdef __cplusplus
}
#endif

#endif
