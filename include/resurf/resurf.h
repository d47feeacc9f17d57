/*
 * resurf — levels of detail whose vertices stay on the smooth surface.
 *
 * This header is the manual. Read the conventions once; every call follows them.
 *
 * Conventions
 * - Every call that can fail returns a resurf_status (RESURF_OK = 0). Its last parameter is an optional
 *   `resurf_error *error` (may be NULL) that receives the status, a one-line message and, where known, the file,
 *   the line or byte offset. resurf_format_error() turns it into "FILE:LINE: what is wrong".
 * - Options structs are filled by their `_default()` function, then edited. Passing NULL means the defaults.
 *   A struct whose `struct_size` is not the one this library was built with is refused (RESURF_ERR_INVALID_OPTIONS),
 *   which catches hand-zeroed or outdated structs.
 * - Ownership: a resurf_mesh returned by the library is owned by the caller and freed with resurf_mesh_free()
 *   (which accepts NULL). The library never keeps a pointer to caller data after a call returns.
 * - Threads: the library has no global state. Calls on different meshes may run at the same time from different
 *   threads; calls that modify a mesh need exclusive use of it. Some calls use worker threads of their own
 *   (`threads` option: 0 = all cores); their results do not depend on the thread count. A call's threads end
 *   before it returns (the simplifier keeps its own waiting, asleep, between its many short parallel steps; it
 *   can run them on the caller's job system instead: see resurf_thread_pool).
 * - The library never prints, never exits and never aborts on bad input.
 * - Progress: a resurf_progress {fn, user} is called at a bounded rate with a resurf_stage and a fraction in [0,1].
 *   Returning true cancels the call: it returns RESURF_ERR_CANCELLED and leaves the caller's data valid.
 * - Types and names: flags are bool, a choice among more than two is an enum. A call's options are resurf_X_options
 *   and what it fills in is resurf_X_report (resurf_mesh_validate, without options: resurf_validate_report). Calls
 *   take their inputs, then what to make, then the options, then the outputs (the text writers take dst first,
 *   like snprintf).
 * - Units: lengths are in the mesh's own units unless a name ends in `_rel` (relative to the bounding-box
 *   diagonal of the reference mesh); angles end in `_deg`.
 */
#ifndef RESURF_RESURF_H
#define RESURF_RESURF_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define RESURF_VERSION_MAJOR 0
#define RESURF_VERSION_MINOR 3
#define RESURF_VERSION_PATCH 0
#define RESURF_VERSION_STRING "0.3.0"

#if defined(RESURF_BUILDING) && defined(__GNUC__)
#define RESURF_API __attribute__((visibility("default")))
#else
#define RESURF_API
#endif

/* The library's version as "MAJOR.MINOR.PATCH"; compare with RESURF_VERSION_STRING to catch a header/library mismatch. */
RESURF_API const char *resurf_version(void);

/* ------------------------------------------------------------------------------------------------------------- */
/* Status and errors                                                                                             */
/* ------------------------------------------------------------------------------------------------------------- */

typedef enum resurf_status {
    RESURF_OK = 0,
    RESURF_ERR_INVALID_ARGUMENT, /* a NULL where data is needed, a count out of range */
    RESURF_ERR_INVALID_OPTIONS,  /* an options struct not made by its _default() function, or a value out of range */
    RESURF_ERR_INVALID_MESH,     /* the mesh breaks a precondition (indices out of range, NaN positions, ...) */
    RESURF_ERR_IO,               /* a file could not be opened, read, written or renamed */
    RESURF_ERR_PARSE,            /* a file's content is malformed, truncated or hostile */
    RESURF_ERR_UNSUPPORTED,      /* a format, variant or feature resurf does not handle */
    RESURF_ERR_OUT_OF_MEMORY,
    RESURF_ERR_LIMIT,            /* the input exceeds a configured limit (max_triangles, ...) */
    RESURF_ERR_CANCELLED,        /* the progress callback asked to stop */
    RESURF_ERR_INTERNAL,         /* a bug in resurf */
    RESURF_STATUS_COUNT
} resurf_status;

/* A short English name for a status ("parse error"). Never NULL. */
RESURF_API const char *resurf_status_string(resurf_status status);

/* Where and why a call failed. All fields are filled by the library; the caller only allocates it. */
typedef struct resurf_error {
    resurf_status status;
    char message[256];   /* what is wrong, one line, no file name ("face 12 refers to vertex 40 of 30") */
    char path[256];      /* the file involved, or "" */
    long long line;      /* 1-based line in a text file, or 0 */
    long long offset;    /* byte offset in a binary file, or -1 */
} resurf_error;

/* Writes "PATH:LINE: message" (or "PATH: byte N: message", or "PATH: message", or "message") into dst, always
 * NUL-terminated when dst_size > 0. Returns the length the full text needs, like snprintf. */
RESURF_API size_t resurf_format_error(char *dst, size_t dst_size, const resurf_error *error);

/* What a call is doing when it reports progress. */
typedef enum resurf_stage {
    RESURF_STAGE_LOAD = 0,  /* reading a mesh or a scene */
    RESURF_STAGE_SAVE,      /* writing one */
    RESURF_STAGE_RESTORE,   /* resurf_restore() */
    RESURF_STAGE_SMOOTH,    /* resurf_smooth() */
    RESURF_STAGE_COMPARE,   /* resurf_compare() */
    RESURF_STAGE_PREPARE,   /* the simplifier's set-up: checks, the services over the input, the first candidates */
    RESURF_STAGE_SIMPLIFY,  /* its collapses, towards the (current level's) target */
    RESURF_STAGE_FINISH,    /* its output: numbering, attributes, measuring, level after level */
    RESURF_STAGE_PREVIEW,   /* resurf_preview_render(), level after level */
    RESURF_STAGE_COUNT
} resurf_stage;

/* "load", "save", "restore", "smooth", "compare", "prepare", "simplify", "finish"; "unknown" for anything else.
 * Never NULL. */
RESURF_API const char *resurf_stage_name(resurf_stage stage);

/* Progress and cancel. fn may be NULL. fraction is in [0,1].
 * Return false to continue, true to cancel. Called from the calling thread only. */
typedef struct resurf_progress {
    bool (*fn)(void *user, resurf_stage stage, double fraction);
    void *user;
} resurf_progress;

/* Memory. Every heap block the C library allocates (meshes it creates, the call's temporaries) comes from an
 * allocator: options structs have `const resurf_allocator *allocator` (NULL = default) and a mesh remembers the
 * allocator it was made with. Which one a call uses:
 * - options->allocator when it is not NULL;
 * - else the allocator of the mesh the call works on (the first mesh argument: `original` for resurf_restore,
 *   `ref` for resurf_compare, `in` for resurf_simplify); calls without options (resurf_mesh_validate,
 *   resurf_mesh_weld_map, resurf_mesh_add_extra, resurf_mesh_clone) use the mesh's;
 * - else (loading, resurf_mesh_create, resurf_mesh_from_arrays) the C heap (malloc, realloc, free).
 * A mesh a call creates (loaded, cloned, simplified) records that allocator and is freed through it by
 * resurf_mesh_free(); arrays a call replaces inside a mesh (resurf_mesh_repair, resurf_mesh_add_extra) come from,
 * and go back to, the mesh's own allocator. The allocator struct and its user data must outlive every mesh made
 * with it; arrays a caller puts into a mesh must come from the mesh's allocator.
 * Scenes: a scene's own blocks and meshes come from options->allocator of resurf_scene_load(), or the mesh's
 * allocator for resurf_scene_from_mesh(); resurf_scene_set_lods() copies levels into the scene's allocator;
 * resurf_scene_build_lods() makes them with its simplify options' allocator, else the scene's (each mesh is freed
 * through its own); resurf_scene_save() uses its options' allocator, else the scene's.
 * The callbacks:
 * - allocate(user, size): a block of at least size bytes (size > 0), aligned for any type like malloc's.
 * - reallocate(user, block, size): like realloc, for a block of this allocator (never NULL), size > 0; on failure
 *   return NULL and leave the block as it was (a failed shrink is no error: the larger block is kept).
 * - release(user, block): frees a block of this allocator (never NULL).
 * All three are required; an allocator whose three are all NULL (a zeroed struct) names the C heap explicitly (to
 * copy an allocator's mesh onto the C heap, say); only some NULL is RESURF_ERR_INVALID_OPTIONS (INVALID_ARGUMENT
 * for resurf_mesh_create_with and resurf_mesh_clone_with). They are called from the call's worker threads at the
 * same time: they must be thread-safe. A NULL return from allocate or reallocate is out of memory: the call frees
 * what it holds and returns RESURF_ERR_OUT_OF_MEMORY, leaving the caller's data unchanged and valid (as for any
 * failure).
 * Not covered: the glTF and Draco code of scenes (tinygltf, Draco and resurf's C++ shim around them: the parsed
 * document a scene keeps, decoding, encoding and writing) allocates from the C++ heap (operator new) and the C
 * heap; worker threads' stacks come from the system (pthread_create), as do the C library's own internals
 * (locale objects, error strings). */
typedef struct resurf_allocator {
    void *(*allocate)(void *user, size_t size);
    void *(*reallocate)(void *user, void *block, size_t size);
    void (*release)(void *user, void *block);
    void *user;
} resurf_allocator;

/* ------------------------------------------------------------------------------------------------------------- */
/* Mesh                                                                                                          */
/* ------------------------------------------------------------------------------------------------------------- */

#define RESURF_MAX_TEXCOORD_SETS 4

/* An extra per-vertex float attribute carried through untouched (PLY properties, glTF custom attributes). */
typedef struct resurf_attribute {
    char name[64];
    unsigned components;  /* 1..16 */
    float *data;          /* components * vertex_count values */
} resurf_attribute;

/* An indexed triangle mesh in double precision. Vertices are *attribute vertices*: two vertices may share a
 * position and differ in normal or texcoord (a seam); resurf_mesh_weld_map() tells which do.
 * Every pointer is owned by the mesh (allocated by the library); optional arrays are NULL when absent. */
typedef struct resurf_mesh {
    size_t vertex_count;
    double *positions;                          /* 3 * vertex_count */
    size_t triangle_count;
    uint32_t *indices;                          /* 3 * triangle_count, counter-clockwise seen from outside */

    double *normals;                            /* 3 * vertex_count, or NULL */
    unsigned texcoord_count;                    /* sets in use, 0..RESURF_MAX_TEXCOORD_SETS */
    double *texcoords[RESURF_MAX_TEXCOORD_SETS];/* 2 * vertex_count each */
    double *colors;                             /* 4 * vertex_count RGBA in [0,1], or NULL */
    unsigned color_components;                  /* 3 or 4 when colors is set: what the source held */
    size_t extra_count;
    resurf_attribute *extras;                   /* extra_count attributes, or NULL */

    uint32_t *triangle_groups;                  /* triangle_count group ids, or NULL (OBJ o/g/usemtl) */
    size_t group_count;
    char **group_names;                         /* group_count NUL-terminated names */

    resurf_allocator allocator;                 /* where the mesh and its arrays come from (all zero = the C heap);
                                                   set by the call that made the mesh; do not change it */
} resurf_mesh;

/* Which optional attributes resurf_mesh_create() allocates. */
enum {
    RESURF_ATTR_NORMALS = 1u << 0,
    RESURF_ATTR_COLORS = 1u << 1,
    RESURF_ATTR_TEXCOORD0 = 1u << 2, /* RESURF_ATTR_TEXCOORD0 << k allocates set k */
};

/* Creates a mesh with room for the given counts; positions and indices are zero-filled. attributes is a mask of
 * RESURF_ATTR_*. Returns RESURF_ERR_OUT_OF_MEMORY or RESURF_ERR_INVALID_ARGUMENT (counts above UINT32_MAX). */
RESURF_API resurf_status resurf_mesh_create(size_t vertex_count, size_t triangle_count, unsigned attributes,
                                            resurf_mesh **out_mesh, resurf_error *error);

/* The same with an allocator (NULL = the C heap) that the mesh records and resurf_mesh_free() uses. */
RESURF_API resurf_status resurf_mesh_create_with(size_t vertex_count, size_t triangle_count, unsigned attributes,
                                                 const resurf_allocator *allocator, resurf_mesh **out_mesh,
                                                 resurf_error *error);

/* A deep copy of mesh, made with mesh's own allocator. */
RESURF_API resurf_status resurf_mesh_clone(const resurf_mesh *mesh, resurf_mesh **out_mesh, resurf_error *error);
/* A deep copy made with `allocator` (NULL = mesh's own allocator), which the copy records. */
RESURF_API resurf_status resurf_mesh_clone_with(const resurf_mesh *mesh, const resurf_allocator *allocator,
                                                resurf_mesh **out_mesh, resurf_error *error);

/* Frees the mesh and everything it owns. NULL is allowed. */
RESURF_API void resurf_mesh_free(resurf_mesh *mesh);

/* Adds an extra float attribute of `components` values per vertex (zero-filled) and returns it in *out (may be
 * NULL). The pointer stays valid until the next call that changes the mesh's attributes. */
RESURF_API resurf_status resurf_mesh_add_extra(resurf_mesh *mesh, const char *name, unsigned components,
                                               resurf_attribute **out, resurf_error *error);

/* Axis-aligned bounding box of the vertices referenced by triangles (all vertices when there are none).
 * Writes zeros for an empty mesh. Returns the diagonal length. */
RESURF_API double resurf_mesh_bounds(const resurf_mesh *mesh, double out_min[3], double out_max[3]);

/* The welded position topology. With tolerance_rel = 0, vertices share a position id iff their positions are
 * equal (−0.0 equals +0.0; a NaN only the same NaN). With tolerance_rel > 0, the distinct positions are taken in
 * order of first appearance and each joins the lowest-numbered earlier cluster whose first position lies closer
 * than tol = tolerance_rel × bounding-box diagonal (finite positions, see resurf_mesh_bounds), else starts a new
 * cluster: members lie within tol of their cluster's first position (no chaining), equal positions always share
 * an id, non-finite positions never join others. Expected O(n).
 * out_position_of_vertex receives vertex_count ids, numbered 0..*out_position_count-1 in order of first
 * appearance (out_position_count may be NULL). An attribute seam is a position id with several vertices.
 * Fails with RESURF_ERR_INVALID_ARGUMENT for a negative or non-finite tolerance_rel. */
RESURF_API resurf_status resurf_mesh_weld_map(const resurf_mesh *mesh, double tolerance_rel,
                                              uint32_t *out_position_of_vertex, size_t *out_position_count,
                                              resurf_error *error);

/* ---- Meshes from and to the caller's arrays ------------------------------------------------------------------ */
/* A game tool usually holds its geometry as vertex buffers: interleaved floats with a stride, 16- or 32-bit
 * indices. resurf_mesh_from_arrays() makes a resurf_mesh from such arrays and resurf_mesh_to_arrays() writes a mesh
 * back into them, so the caller never has to touch resurf_mesh's double arrays.
 *
 * Why a copy: a resurf_mesh holds double-precision arrays that it owns (every resurf call that makes a mesh
 * allocates them, resurf_mesh_free() releases them, and callers may edit them in place), while vertex buffers are
 * usually float and interleaved. A mesh viewing the caller's memory would need the caller's layout to be exactly
 * resurf's (separate tightly packed double arrays, uint32 indices) and its lifetime to outlive every use, so both
 * calls copy, converting as they go. The copy is one pass over the data; the algorithms after it cost far more. */

/* The type of each component of a vertex array. */
typedef enum resurf_component_type {
    RESURF_COMPONENT_FLOAT = 0, /* 32-bit IEEE float */
    RESURF_COMPONENT_DOUBLE,    /* 64-bit IEEE double */
    RESURF_COMPONENT_UNORM8,    /* uint8_t, value / 255 (colours and texcoords only, like glTF's normalized ubyte) */
    RESURF_COMPONENT_UNORM16,   /* uint16_t, value / 65535 (colours and texcoords only) */
    RESURF_COMPONENT_TYPE_COUNT
} resurf_component_type;

/* The type of the indices. */
typedef enum resurf_index_type {
    RESURF_INDEX_UINT32 = 0,
    RESURF_INDEX_UINT16,
    RESURF_INDEX_TYPE_COUNT
} resurf_index_type;

/* One per-vertex array the caller reads from: vertex v's first component is at (const char *)data + v × stride,
 * its components follow each other tightly. data NULL = the attribute is absent. The data need not be aligned. */
typedef struct resurf_vertex_source {
    const void *data;
    resurf_component_type type; /* default RESURF_COMPONENT_FLOAT */
    size_t stride;              /* bytes from one vertex to the next; 0 = tightly packed (components × size); else
                                   at least one element (3 floats = 12 bytes for positions) */
} resurf_vertex_source;

/* The caller's arrays, read by resurf_mesh_from_arrays(). Fill with resurf_mesh_arrays_default(), then set the
 * fields. Interleaved buffers give every attribute the same stride and data pointers offset within one vertex:
 * for {float pos[3], normal[3], uv[2]} (32 bytes), positions.data = buf, normals.data = buf + 12,
 * texcoords[0].data = buf + 24, and all three strides 32. */
typedef struct resurf_mesh_arrays {
    size_t struct_size;
    size_t vertex_count;                                   /* at most UINT32_MAX */
    resurf_vertex_source positions;                        /* 3 components, FLOAT or DOUBLE; required */
    resurf_vertex_source normals;                          /* 3 components, FLOAT or DOUBLE; optional */
    resurf_vertex_source texcoords[RESURF_MAX_TEXCOORD_SETS]; /* 2 components each; optional, but set k needs
                                                              sets 0..k-1 (glTF's TEXCOORD_n rule) */
    resurf_vertex_source colors;                           /* color_components (3 RGB or 4 RGBA) in [0, 1] as
                                                              resurf keeps them; optional */
    unsigned color_components;                             /* 3 or 4 when colors is given; default 4 */
    const void *indices;                                   /* index_count indices, tightly packed, 3 per triangle
                                                              (counter-clockwise seen from outside); NULL only when
                                                              index_count is 0 */
    resurf_index_type index_type;                          /* default RESURF_INDEX_UINT32 */
    size_t index_count;                                    /* a multiple of 3 (the usual mistake: not the triangle
                                                              count) */
    const resurf_allocator *allocator;                     /* NULL (default): the C heap; the new mesh records it
                                                              (see resurf_allocator) */
} resurf_mesh_arrays;

RESURF_API resurf_mesh_arrays resurf_mesh_arrays_default(void);

/* Makes a new mesh (free with resurf_mesh_free) holding a copy of the caller's arrays, converted to double: float,
 * double and uint32 values are kept exactly, UNORM values become value / max. A 3-component colour gets alpha 1.
 * Everything is checked before anything is allocated, and the message names what is wrong:
 * - RESURF_ERR_INVALID_ARGUMENT: arrays or out_mesh NULL, positions.data NULL with vertex_count > 0, indices NULL
 *   with index_count > 0, index_count not a multiple of 3, a stride smaller than its element ("normals: stride 8
 *   is smaller than one element (12 bytes: 3 floats)"), an unknown or unsuitable component type, texcoord set k
 *   without set k - 1, color_components not 3 or 4, counts above UINT32_MAX;
 * - RESURF_ERR_INVALID_OPTIONS: arrays not made by resurf_mesh_arrays_default(), an allocator lacking a callback;
 * - RESURF_ERR_INVALID_MESH: an index out of range ("triangle 5 (indices 15..17) refers to vertex 40, but there are
 *   30 vertices") or a NaN or infinite value ("positions: vertex 12, component 1 is nan").
 * On error *out_mesh is NULL. The arrays are only read; the caller may free them as soon as the call returns.
 * Thread-safe: calls on different data may run at the same time. */
RESURF_API resurf_status resurf_mesh_from_arrays(const resurf_mesh_arrays *arrays, resurf_mesh **out_mesh,
                                                 resurf_error *error);

/* One per-vertex array the caller's memory receives (see resurf_vertex_source): vertex v's components are
 * written at (char *)data + v × stride and nothing between vertices is touched, so several attributes can be
 * written into one interleaved buffer. data NULL = not wanted. */
typedef struct resurf_vertex_dest {
    void *data;
    resurf_component_type type; /* default RESURF_COMPONENT_FLOAT */
    size_t stride;              /* bytes; 0 = tightly packed; else at least one element */
} resurf_vertex_dest;

/* Where resurf_mesh_to_arrays() writes. Fill with resurf_mesh_arrays_out_default(), then set what you want. */
typedef struct resurf_mesh_arrays_out {
    size_t struct_size;
    size_t vertex_capacity;                              /* vertices each given vertex array has room for; must be
                                                            >= mesh->vertex_count */
    resurf_vertex_dest positions, normals;               /* 3 components, FLOAT or DOUBLE */
    resurf_vertex_dest texcoords[RESURF_MAX_TEXCOORD_SETS]; /* 2 components */
    resurf_vertex_dest colors;                           /* color_components components */
    unsigned color_components;                           /* 3 (RGB, alpha dropped) or 4; default 4 */
    void *indices;                                       /* 3 × mesh->triangle_count indices, or NULL */
    resurf_index_type index_type;                        /* default RESURF_INDEX_UINT32 */
    size_t index_capacity;                               /* indices `indices` has room for: >= 3 × triangle_count */
} resurf_mesh_arrays_out;

RESURF_API resurf_mesh_arrays_out resurf_mesh_arrays_out_default(void);

/* Writes the mesh's vertices and indices into the caller's arrays (the sizes needed are mesh->vertex_count and
 * 3 × mesh->triangle_count), converting: double to float rounds to nearest (a mesh made from float arrays comes
 * back bit for bit), UNORM values are clamped to [0, 1] and rounded (NaN gives 0). Fails, writing nothing, with
 * RESURF_ERR_INVALID_ARGUMENT for a NULL argument, a bad stride or type, a capacity too small, or an attribute
 * asked for that the mesh lacks ("the mesh has no normals"); RESURF_ERR_INVALID_OPTIONS for an out struct not made
 * by its _default(); RESURF_ERR_LIMIT when a value does not fit the type asked for: a finite coordinate beyond
 * float's range, or a vertex number above 65535 with RESURF_INDEX_UINT16 (the message names it);
 * RESURF_ERR_INVALID_MESH for an index out of range. Non-finite values are copied as they are. The mesh is only
 * read: several threads may copy out of one mesh at once. */
RESURF_API resurf_status resurf_mesh_to_arrays(const resurf_mesh *mesh, const resurf_mesh_arrays_out *out,
                                               resurf_error *error);

/* ------------------------------------------------------------------------------------------------------------- */
/* Validation and repair                                                                                         */
/* ------------------------------------------------------------------------------------------------------------- */

/* What resurf_mesh_validate() found. Topology counts are over welded positions (exact weld), so attribute seams
 * do not show up as boundaries. Triangles with an out-of-range index or a repeated position take no part in the
 * topology. The first_* fields give the lowest index of an example, or -1 when there is none. */
typedef struct resurf_validate_report {
    size_t vertex_count, triangle_count, position_count; /* position_count: distinct positions */
    size_t nonfinite_vertices;        /* NaN or infinite coordinate (or attribute) */
    size_t nonfinite_positions;       /* NaN or infinite coordinate (a subset of nonfinite_vertices) */
    size_t out_of_range_indices;      /* indices (not triangles) >= vertex_count */
    size_t degenerate_triangles;      /* in range, with a repeated index or a repeated position */
    size_t zero_area_triangles;       /* three distinct finite positions with |(b−a)×(c−a)| <= 1e-14 × diagonal²
                                         (diagonal: resurf_mesh_bounds over finite positions) */
    size_t boundary_edges;            /* edges with one triangle */
    size_t boundary_loops;            /* closed chains of boundary edges, with each non-manifold vertex split into
                                         its fans first (so the two triangles of a bow-tie have two loops) */
    size_t nonmanifold_edges;         /* edges with three or more triangles */
    size_t nonmanifold_vertices;      /* positions on a non-manifold edge, or whose triangles form more than one fan
                                         (sets of triangles connected across manifold edges around it) */
    size_t inconsistent_edges;        /* manifold edges used twice in the same direction (orientation flips) */
    size_t unreferenced_vertices;     /* vertices no index refers to */
    size_t components;                /* connected components of triangles (through shared positions) */
    long long first_nonfinite_vertex, first_out_of_range_triangle, first_degenerate_triangle,
        first_zero_area_triangle;
    long long first_nonmanifold_edge_vertex; /* a vertex at a non-manifold position */
    long long first_inconsistent_triangle;   /* a triangle on an inconsistent edge */
} resurf_validate_report;

/* Counts the problems of mesh. Never fails on a bad mesh (that is what it reports); fails only on NULL
 * arguments or out of memory. Out-of-range triangles are skipped by the topology counts. */
RESURF_API resurf_status resurf_mesh_validate(const resurf_mesh *mesh, resurf_validate_report *out,
                                              resurf_error *error);

/* True when the mesh can be processed: finite positions and every index in range (non-finite attributes,
 * degenerate triangles and topology problems are reported but do not stop processing). False for NULL. */
RESURF_API bool resurf_validation_ok(const resurf_validate_report *v);

enum {
    RESURF_REPAIR_DROP_INVALID = 1u << 0,      /* drop triangles with out-of-range indices or non-finite corners */
    RESURF_REPAIR_DROP_DEGENERATE = 1u << 1,   /* drop triangles with a repeated index or a repeated position
                                                  (after the weld, if any) */
    RESURF_REPAIR_DROP_ZERO_AREA = 1u << 2,    /* drop what resurf_validate_report counts as zero_area_triangles */
    RESURF_REPAIR_WELD = 1u << 3,              /* merge vertices with equal positions and equal attributes */
    RESURF_REPAIR_REMOVE_UNREFERENCED = 1u << 4,
    RESURF_REPAIR_ALL = 0x1f,
};

typedef struct resurf_repair_options {
    size_t struct_size;
    unsigned flags;          /* RESURF_REPAIR_*; default RESURF_REPAIR_ALL; unknown bits: RESURF_ERR_INVALID_OPTIONS */
    double weld_tolerance_rel; /* with RESURF_REPAIR_WELD: 0 welds exact duplicates only; > 0 clusters positions as
                                  resurf_mesh_weld_map() does and moves every vertex (seams too) onto its cluster's
                                  first position; finite, >= 0; default 0 */
    bool weld_ignore_attributes; /* true: weld by position alone (attributes of the first vertex win); default
                                    false: only vertices whose attributes (normals, texcoords, colors, extras) are
                                    equal merge, so attribute seams stay */
    const resurf_allocator *allocator; /* NULL (default): the input mesh's (or the C heap); see resurf_allocator */
} resurf_repair_options;

RESURF_API resurf_repair_options resurf_repair_options_default(void);

typedef struct resurf_repair_report {
    size_t dropped_invalid, dropped_degenerate, dropped_zero_area, welded_vertices, removed_unreferenced;
} resurf_repair_report;

/* Repairs mesh in place as options say, in this order: drop invalid, weld, drop degenerate, drop zero-area, remove
 * unreferenced. Surviving triangles and vertices keep their relative order; every per-vertex array (normals,
 * texcoords, colors, extras) and triangle_groups follow. A welded vertex merges into the lowest-numbered vertex of
 * its group and is removed (counted in welded_vertices, whatever REMOVE_UNREFERENCED says). An out-of-range index
 * in a kept triangle (DROP_INVALID off) is lowered by the number of vertices removed, so it stays out of range.
 * out_report may be NULL. On failure (NULL mesh, bad options, out of memory) the mesh is unchanged. */
RESURF_API resurf_status resurf_mesh_repair(resurf_mesh *mesh, const resurf_repair_options *options,
                                            resurf_repair_report *out_report, resurf_error *error);

/* ------------------------------------------------------------------------------------------------------------- */
/* Files                                                                                                         */
/* ------------------------------------------------------------------------------------------------------------- */

typedef enum resurf_format {
    RESURF_FORMAT_AUTO = 0, /* from the file name's extension */
    RESURF_FORMAT_OBJ,
    RESURF_FORMAT_PLY,
    RESURF_FORMAT_OFF,
    RESURF_FORMAT_STL,
    RESURF_FORMAT_COUNT
} resurf_format;

/* The format a path's extension names (case-insensitive), or RESURF_FORMAT_AUTO when unknown. */
RESURF_API resurf_format resurf_format_from_path(const char *path);
/* "obj", "ply", ... ; NULL for an unknown value. Parses names with resurf_format_from_name (AUTO when unknown). */
RESURF_API const char *resurf_format_name(resurf_format format);
RESURF_API resurf_format resurf_format_from_name(const char *name);

typedef struct resurf_load_options {
    size_t struct_size;
    resurf_format format;       /* default AUTO */
    size_t max_triangles;       /* refuse larger inputs with RESURF_ERR_LIMIT; default 100,000,000; 0 = no limit */
    resurf_progress progress;
    const resurf_allocator *allocator; /* NULL (default): the input mesh's (or the C heap); see resurf_allocator */
    /* glTF scenes */
    bool allow_missing_images;  /* true: an external image that cannot be read is a warning, and the output refers to
                                   it by its uri as it was; default false: an error naming it */
    bool lenient;               /* true: what the glTF 2.0 schema forbids is a warning, one per problem (the first
                                   100, then a count), and the document is read as far as it can be; default false:
                                   RESURF_ERR_PARSE naming the first problem. See resurf_scene_load() */
} resurf_load_options;

RESURF_API resurf_load_options resurf_load_options_default(void);

/* Loads a mesh. Polygons are triangulated (fan); STL is welded on load (exact positions). Indices are checked:
 * a file whose faces point outside its vertices fails with RESURF_ERR_PARSE and the face's line or offset.
 * Non-finite coordinates are refused. No allocation exceeds what the file's size can justify.
 * Folders, devices and sockets are refused (RESURF_ERR_IO) without being read. A pipe, whose size is not known
 * beforehand, is read up to 64 MiB + 1 KiB × max_triangles bytes (RESURF_ERR_LIMIT beyond; no bound when
 * max_triangles is 0); a FIFO that no process has open for writing reads as empty (the call never waits for a
 * writer). A read blocked on a pipe that a signal interrupts asks options->progress whether to go on.
 * The format comes from options->format, else the extension, else the content. Per format:
 * - OBJ: one vertex per distinct v/vt/vn triple used by faces (with positions only, vertex i is "v" line i);
 *   faces may refer only to elements defined above them (negative indices count back); o/g/usemtl become
 *   triangle groups ("default" before the first); "v x y z r g b [a]" gives colours.
 * - PLY (ascii, binary either endian): x y z, nx ny nz, u v / s t / texture_u texture_v, red green blue [alpha]
 *   (integers scaled to [0,1] by their type's maximum); other scalar vertex properties become 1-component extras.
 * - OFF ([ST][C][N]OFF): integer colours are 0..255, colours with a decimal point 0..1; face colours are ignored.
 * - STL: binary when the size is 84 + 50 n (even if the header starts with "solid"), else ASCII if it starts
 *   with "solid"; facet normals are ignored.
 * Messages count vertices and faces as the file does (OBJ from 1, the others from 0). */
RESURF_API resurf_status resurf_mesh_load(const char *path, const resurf_load_options *options,
                                          resurf_mesh **out_mesh, resurf_error *error);

/* Loads from memory. format AUTO means options->format, else the extension of `name`, else the content. `name`
 * (may be NULL) is also what error messages name. */
RESURF_API resurf_status resurf_mesh_load_memory(const void *data, size_t size, resurf_format format,
                                                 const char *name, const resurf_load_options *options,
                                                 resurf_mesh **out_mesh, resurf_error *error);

typedef struct resurf_save_options {
    size_t struct_size;
    resurf_format format;       /* default AUTO */
    bool binary;                /* PLY and STL: true = binary little-endian (default), false = ASCII */
    bool write_normals, write_texcoords, write_colors, write_extras; /* default true: write what the format can
                                                                         hold */
    resurf_progress progress;
    const resurf_allocator *allocator; /* NULL (default): the input mesh's (or the C heap); see resurf_allocator */
} resurf_save_options;

RESURF_API resurf_save_options resurf_save_options_default(void);

/* Saves a mesh. Text formats print 17 significant digits, so doubles round-trip exactly. The file is written to a
 * temporary file in the same folder and renamed into place: a failure leaves no partial file and an existing file
 * is replaced only as a whole (keeping its permissions). A mesh with an index out of range or a non-finite position
 * fails with RESURF_ERR_INVALID_MESH. What each format keeps: OBJ positions, normals, texcoord set 0, RGB colours
 * and groups; PLY positions, normals and texcoord set 0 as double (bit-exact in binary), colours as uchar RGB or
 * RGBA (per color_components), extras as float ("name", or "name_0", "name_1"... per component); OFF positions,
 * normals, texcoord set 0 and colours as 0..255; STL positions only (float32 in binary). */
RESURF_API resurf_status resurf_mesh_save(const resurf_mesh *mesh, const char *path,
                                          const resurf_save_options *options, resurf_error *error);

/* ------------------------------------------------------------------------------------------------------------- */
/* Restoring (Semenova, Savchenko, Hagiwara: "Reconstruction of Shapes Based on Normals Analysis")               */
/* ------------------------------------------------------------------------------------------------------------- */

/* How vertex normals of the original mesh M are estimated. */
typedef enum resurf_normal_scheme {
    RESURF_NORMALS_INVERSE_AREA = 0, /* Σ n_f / A_f, the paper's choice */
    RESURF_NORMALS_AREA,             /* Σ n_f A_f */
    RESURF_NORMALS_ANGLE,            /* Σ n_f θ_f */
    RESURF_NORMALS_MAX,              /* Max 1999: Σ (e1 × e2) / (|e1|² |e2|²), exact on spheres */
    RESURF_NORMALS_JET,              /* normal of a quadratic fitted to the 2-ring */
    RESURF_NORMALS_COUNT,            /* the number of schemes above */
    RESURF_NORMALS_AUTO = 0x100      /* the default: the calling function's choice (see resurf_restore_options) */
} resurf_normal_scheme;

/* What resurf_restore() makes of M's own normals, when it has them. */
typedef enum resurf_input_normals {
    RESURF_INPUT_NORMALS_IGNORE = 0,  /* they play no part */
    RESURF_INPUT_NORMALS_CREASES,     /* the default: an edge whose faces carry different normals (by more than 1°)
                                         at an end is a crease */
    RESURF_INPUT_NORMALS_USE,         /* creases as CREASES, and they are M's vertex normals (the scheme fills in
                                         corners whose input normal is zero) */
    RESURF_INPUT_NORMALS_COUNT
} resurf_input_normals;

/* Max or min algorithm per triangle corner. */
typedef enum resurf_side_rule {
    RESURF_SIDE_CURVATURE = 0, /* the paper: principal curvatures at the corner, normal curvature at saddles */
    RESURF_SIDE_LOCAL,         /* sign of (N_opt − N_j)·(p0 − p_j) */
    RESURF_SIDE_COUNT
} resurf_side_rule;

/* How each corner's displacement δ_j is computed. */
typedef enum resurf_displacement {
    RESURF_DISPLACEMENT_PAPER = 0,     /* formula (2) with the whole angle α_j between N_opt and N_j */
    RESURF_DISPLACEMENT_NORMAL_SECTION,/* α_j measured in the normal section plane (N_opt, chord); sign from the angle */
    RESURF_DISPLACEMENT_COUNT
} resurf_displacement;

/* What a vertex does whose optimal-direction root (the foot of the line through it along the interpolated normal)
 * lies outside its closest triangle, which happens where triangles tie (a vertex nearest an edge or a vertex of M)
 * and on strongly curved or badly shaped parts. */
typedef enum resurf_outside_policy {
    RESURF_OUTSIDE_NEIGHBOURS = 0, /* take a root inside one of the triangles around the closest one's corners
                                      (smallest |t|); else the least-outside root among them all */
    RESURF_OUTSIDE_LEAST,          /* take the least-outside root of the closest triangle (no search) */
    RESURF_OUTSIDE_KEEP,           /* search like NEIGHBOURS; with no inside root, leave the vertex where it is
                                      (counted in left_outside; a vertex that already moved stops there) */
    RESURF_OUTSIDE_COUNT
} resurf_outside_policy;

/* Options of resurf_restore(). Lengths are relative to the *local edge length* of M: at a triangle, the largest of
 * its corners' mean incident edge lengths. */
typedef struct resurf_restore_options {
    size_t struct_size;
    resurf_normal_scheme normals;      /* vertex normals of M; default AUTO: JET in resurf_restore() (the most
                                          accurate: see its default), MAX when the simplifier restores (as good
                                          for a LOD, whose error is the chord sag, and faster to set up than the
                                          jet fit) */
    resurf_side_rule side_rule;        /* max/min choice of formula (2); default CURVATURE (unused by NORMAL_SECTION) */
    resurf_displacement displacement;  /* default NORMAL_SECTION */
    double step;                       /* k in p ← p + k Σ_j δ_j N_opt, in (0, 1]; each δ_j estimates the whole
                                          displacement, so 1/3 takes their average (default); the paper uses 1/6 */
    unsigned iterations;               /* steps per vertex, 1..1000, each with the closest triangle and N_opt taken
                                          again at the new position; with tolerance_rel > 0 the most; default 10,
                                          paper 5 */
    double tolerance_rel;              /* stop a vertex once its step is below this × the local edge length;
                                          0 = always run `iterations` steps; default 1e-6 */
    double crease_angle_deg;           /* an edge whose two faces' normals differ by more than this is a crease
                                          (slivers with an angle over 150° take no part); a boundary or crease
                                          curve that turns by more than this at a vertex has a corner there;
                                          [0, 180], 180 = no creases; default 60 */
    resurf_input_normals input_normals; /* M's own normals, when it has them; default CREASES */
    double far_factor;                 /* a vertex farther from M than this × the local edge length is left where it
                                          is (counted in left_far); > 0, INFINITY = never; default 4 */
    resurf_outside_policy outside;     /* default NEIGHBOURS */
    bool boundary;                     /* true (default): a vertex whose closest point on M lies on a boundary edge
                                          (or a boundary vertex) is put on the boundary curve (circular arcs through
                                          the edge's end points, tangent to the boundary there); false: treated like
                                          others */
    unsigned threads;                  /* 0 = all cores; results are the same for every count */
    resurf_progress progress;          /* RESURF_STAGE_RESTORE, called between blocks of vertices */
    const resurf_allocator *allocator; /* NULL (default): the input mesh's (or the C heap); see resurf_allocator */
} resurf_restore_options;

/* resurf's default: AUTO normals (JET in resurf_restore), the normal-section displacement, k = 1/3, up to 10 steps
 * with tolerance 1e-6, crease angle 60°, boundaries kept, far factor 4. Chosen by measurement on the irregular
 * sphere and the cubic surface after Laplacian smoothing (see README). */
RESURF_API resurf_restore_options resurf_restore_options_default(void);
/* The paper's preset: inverse-area normals, curvature rule, formula (2), k = 1/6, 5 iterations, no tolerance (the
 * other fields as in the default). */
RESURF_API resurf_restore_options resurf_restore_options_paper(void);

typedef struct resurf_restore_report {
    size_t vertices;              /* vertices of the processed mesh (all are considered, referenced or not) */
    size_t moved;                 /* vertices whose position changed */
    double mean_displacement;     /* mean distance moved, over the vertices that moved */
    double max_displacement;
    size_t left_far;              /* left alone: farther from M than far_factor × local edge length, or its
                                   * restored point would have moved that far (normals of a fold) */
    size_t left_outside;          /* left alone: no root inside a triangle (RESURF_OUTSIDE_KEEP), or no root */
    size_t used_least_outside;    /* restored with a root outside its triangle (the last step's) */
    size_t on_boundary;           /* put on a boundary curve */
    size_t on_crease;             /* put on a crease curve */
    size_t left_nonfinite;        /* non-finite input position, left as it is */
} resurf_restore_report;

/* Moves the vertices of `processed` (M') onto the smooth surface S approximated by `original` (M), in place
 * (Semenova, Savchenko, Hagiwara, "Reconstruction of Shapes Based on Normals Analysis"). Connectivity and
 * attributes are unchanged; each vertex is handled on its own, so vertices at one position move together.
 * A vertex that coincides with a vertex of M stays where it is (M's vertices are taken to lie on S).
 * M is welded exactly first (attribute seams are not boundaries). original must have triangles, indices in range
 * and finite referenced positions (else RESURF_ERR_INVALID_MESH); processed may have non-finite positions (left as
 * they are) and no triangles. options NULL = resurf_restore_options_default(). out_report may be NULL.
 * On error or cancel, processed is unchanged. Memory: about 130–150 bytes per triangle of M at the peak (M's
 * positions are read in place), plus 25 per vertex of M'. */
RESURF_API resurf_status resurf_restore(const resurf_mesh *original, resurf_mesh *processed,
                                        const resurf_restore_options *options, resurf_restore_report *out_report,
                                        resurf_error *error);

/* ------------------------------------------------------------------------------------------------------------- */
/* Smoothing                                                                                                     */
/* ------------------------------------------------------------------------------------------------------------- */

/* Smoothing filters: each moves a vertex towards a weighted average of its neighbours (the "umbrella" operator
 * L(p) = Σ w_j (p_j − p) / Σ w_j over the one-ring), the M' of the paper's Table 1. */
typedef enum resurf_smooth_method {
    RESURF_SMOOTH_LAPLACIAN = 0, /* p ← p + λ L(p), uniform weights; shrinks curved surfaces */
    RESURF_SMOOTH_TAUBIN,        /* Taubin 1995: p ← p + λ L(p), then p ← p + μ L(p) (μ < −λ), uniform weights;
                                    a low-pass filter that hardly shrinks */
    RESURF_SMOOTH_TAUBIN_COT,    /* the same λ|μ pair with cotangent weights w = (cot α + cot β) / 2 (Desbrun 1999),
                                    taken from the input positions once (recomputing them every step makes the
                                    explicit flow unstable); an edge whose two opposite angles sum to more than 180°
                                    (non-Delaunay, from obtuse triangles) would get a negative weight and is clamped
                                    to 0, so the average stays convex; a vertex whose weights all vanish falls back
                                    to uniform weights */
    RESURF_SMOOTH_BILAPLACIAN,   /* bilaplacian flow (Kobbelt 1998, Desbrun 1999): p ← p − (λ/ν) L²(p) with the
                                    umbrella of the umbrella L²(p) = avg_j L(p_j) − L(p) and ν = 1 + avg_j 1/n_j its
                                    diagonal (n_j: valences); stable for λ <= 0.5 */
    RESURF_SMOOTH_COUNT
} resurf_smooth_method;

typedef struct resurf_smooth_options {
    size_t struct_size;
    resurf_smooth_method method; /* default RESURF_SMOOTH_LAPLACIAN */
    unsigned iterations;  /* default 10; a Taubin iteration is one λ step and one μ step; 0 leaves the mesh as is */
    double lambda;        /* step, in (0, 1]; 0 (default) = the method's own: 0.5 Laplacian, 0.33 Taubin and
                             Taubin-cot, 0.5 bilaplacian (at most 0.5 there: larger steps diverge) */
    double mu;            /* Taubin's negative step, in [−1, 0); 0 (default) = −0.34; ignored by the other methods */
    resurf_progress progress; /* RESURF_STAGE_SMOOTH, once per iteration; a cancel leaves the mesh unchanged */
    const resurf_allocator *allocator; /* NULL (default): the input mesh's (or the C heap); see resurf_allocator */
} resurf_smooth_options;

RESURF_API resurf_smooth_options resurf_smooth_options_default(void);
/* "laplacian", "taubin", "taubin-cot", "bilaplacian"; "unknown" for anything else. Never NULL. */
RESURF_API const char *resurf_smooth_method_name(resurf_smooth_method method);

/* Smooths positions in place. The filter runs on the exactly welded positions (resurf_mesh_weld_map with 0), so
 * attribute-seam duplicates move together and stay equal. Positions on a boundary edge, on a non-manifold edge or
 * vertex, and positions no triangle uses stay fixed. Updates are simultaneous (Jacobi), so the result does not
 * depend on the vertex order. Normals and other attributes are not touched (recompute normals if they matter).
 * Fails with RESURF_ERR_INVALID_MESH for an index out of range or a non-finite coordinate (the message names
 * it), RESURF_ERR_INVALID_OPTIONS for an unknown method or a step out of range, RESURF_ERR_CANCELLED (mesh
 * unchanged). */
RESURF_API resurf_status resurf_smooth(resurf_mesh *mesh, const resurf_smooth_options *options, resurf_error *error);

/* ------------------------------------------------------------------------------------------------------------- */
/* Metrics                                                                                                       */
/* ------------------------------------------------------------------------------------------------------------- */

/* Surface distances (in the spirit of Metro, Cignoni et al. 1998) with exact point–triangle distances, and the
 * triangle quality of a mesh. Deterministic: the same inputs, options and seed give bit-identical figures on any
 * number of threads. */
typedef struct resurf_compare_options {
    size_t struct_size;
    size_t samples;        /* area-uniform random points on each surface, in addition to its vertices and facet
                              points; at most 10^9; 0 measures from those alone (the mean then over the vertices);
                              default 200000 */
    uint64_t seed;         /* sample seed (any value); default 1 */
    unsigned threads;      /* 0 = all cores */
    resurf_progress progress; /* RESURF_STAGE_COMPARE; a cancel returns RESURF_ERR_CANCELLED and writes no output */
    const resurf_allocator *allocator; /* NULL (default): the input mesh's (or the C heap); see resurf_allocator */
} resurf_compare_options;

RESURF_API resurf_compare_options resurf_compare_options_default(void);

/* What resurf_compare() measures. Distances are in the meshes' units; divide by `diagonal` for relative figures
 * (what `resurf compare` prints as "rel"). Each one-sided figure is measured from the points of one surface (its
 * samples, the vertices its triangles use, and each triangle's centroid and edge midpoints, where a chord or a
 * coarse facet leaves the other surface farthest) to the nearest point of the other surface: the max over all those
 * points, the mean and RMS over the area-uniform samples (so that they estimate the area average; over the
 * vertices when samples is 0). */
typedef struct resurf_compare_report {
    double diagonal;                           /* of REF's bounding box (resurf_mesh_bounds) */
    double hausdorff;                          /* max(test_to_ref_max, ref_to_test_max) */
    double mean;                               /* (test_to_ref_mean + ref_to_test_mean) / 2 */
    double rms;                                /* sqrt of the mean of the two one-sided mean squares */
    double test_to_ref_max, test_to_ref_mean;  /* one-sided: TEST's surface to REF's */
    double ref_to_test_max, ref_to_test_mean;  /* one-sided: REF's surface to TEST's */
    double vertex_max, vertex_mean;            /* TEST's vertices (those triangles use) to REF's surface */
    double min_angle_deg, mean_min_angle_deg;  /* triangle quality of TEST, see resurf_triangle_quality() */
    double share_below_10deg;                  /* fraction of TEST's triangles whose smallest angle is under 10° */
    double mean_normal_deviation_deg;          /* area-weighted mean over TEST's faces of the angle between the face
                                                  normal and REF's face normal at the point of REF closest to the
                                                  face's centroid, in [0, 180] (orientation counts: a flipped face
                                                  is 180); faces of zero area are left out */
    double uv_error_mean, uv_error_p95;        /* when both carry texcoord set 0 (TEXCOORD_0): at each area-uniform
                                                  sample of TEST, the texture-space distance between TEST's UV
                                                  interpolated there and REF's at the closest point of REF; mean
                                                  and 95th percentile (nearest rank). NaN without UVs on either
                                                  or with samples 0 */
} resurf_compare_report;

/* Distances between the surfaces of ref and test, TEST's triangle quality and normal deviation.
 * ref, test: meshes with at least one triangle, indices in range and finite coordinates at the vertices triangles
 * use (else RESURF_ERR_INVALID_MESH naming "REF" or "TEST" and the element). options: NULL = defaults.
 * out_report: required. out_vertex_distance: NULL, or room for test->vertex_count distances of TEST's vertices to
 * REF's surface (every vertex, unused ones included; a non-finite unused vertex gets INFINITY). */
RESURF_API resurf_status resurf_compare(const resurf_mesh *ref, const resurf_mesh *test,
                                        const resurf_compare_options *options, resurf_compare_report *out_report,
                                        double *out_vertex_distance, resurf_error *error);

/* Triangle quality: the smallest angle of each triangle (a triangle with coincident corners or collinear corners
 * has 0°), and over all triangles their minimum, their mean and the fraction under 10°. An equilateral triangle
 * has 60°. All three are 0 for a mesh without triangles. Each output may be NULL.
 * RESURF_ERR_INVALID_MESH for an index out of range or a non-finite corner (the message names the triangle). */
RESURF_API resurf_status resurf_triangle_quality(const resurf_mesh *mesh, double *out_min_deg,
                                                 double *out_mean_min_deg, double *out_share_below_10,
                                                 resurf_error *error);

/* ------------------------------------------------------------------------------------------------------------- */
/* Simplification                                                                                                */
/* ------------------------------------------------------------------------------------------------------------- */

/* Where the vertex that replaces a collapsed edge goes (before restoration). */
typedef enum resurf_placement {
    RESURF_PLACEMENT_QUADRIC = 0, /* Garland–Heckbert optimum; where the quadric is flat in a direction the point stays
                                     at the midpoint along it; if it lands farther than the edge length from the
                                     midpoint, the best of the end points and the midpoint */
    RESURF_PLACEMENT_MIDPOINT,    /* the edge's midpoint (the paper's §4.2 setting) */
    RESURF_PLACEMENT_COUNT
} resurf_placement;

/* When the simplified mesh's vertices are moved onto the smooth surface S of the input (see resurf_restore). */
typedef enum resurf_restore_mode {
    RESURF_RESTORE_INLINE = 0, /* after every collapse, the new vertex is restored onto S of the ORIGINAL mesh */
    RESURF_RESTORE_POST,       /* once, at the end, every vertex of the result */
    RESURF_RESTORE_NONE,       /* plain edge collapse */
    RESURF_RESTORE_MEASURED,   /* the default: each level made both INLINE and NONE, and the INLINE one kept where
                                  its measured two-sided distance to the input is no larger in maximum and in mean,
                                  else the NONE one (INLINE when measure_samples is 0 and nothing is measured). The
                                  paper's S is the surface a smooth mesh approximates; on a noisy scan, at a
                                  shading-smoothed hard edge or on a CAD part it may lie farther from the input than
                                  the plain collapse does. About 1.8x the CPU time of INLINE with its report
                                  (twice that for an input with attached sheets, see attached_sheets); with
                                  threads of its own (no thread_pool) and up to 262,144 triangles the NONE run goes
                                  beside the INLINE one on a thread of its own: the same levels, in about the
                                  INLINE run's time. The report's restore_used says which was kept */
    RESURF_RESTORE_MODE_COUNT
} resurf_restore_mode;

/* What drop_fins does with a double-sided sheet joined to the rest of the mesh along a line (a crest, a fin or a
 * dewlap modelled as two sheets over the same positions, attached to a body): see
 * resurf_simplify_options.attached_sheets. */
typedef enum resurf_attached_sheets {
    RESURF_SHEETS_CHOOSE = 0, /* the default: with RESURF_RESTORE_MEASURED and an input that has such a sheet, each
                                 level is made both ways and the one measured nearer the input in maximum and mean
                                 is kept (as RESURF_RESTORE_MEASURED keeps INLINE or NONE); otherwise DROP */
    RESURF_SHEETS_DROP,       /* left out with the fins: the sheet is gone from every level */
    RESURF_SHEETS_KEEP,       /* kept like a free-standing sheet (one side simplified, written twice); where it
                                 meets the surface, the line's positions move only along the line */
    RESURF_SHEETS_COUNT
} resurf_attached_sheets;

/* A host thread pool: the caller's job system (a game tool's, say) on which resurf_simplify(),
 * resurf_simplify_lods() and resurf_scene_build_lods() run their parallel loops instead of threads of their own
 * (modelled on ufbx's ufbx_thread_pool). Put a pointer to one in resurf_simplify_options.thread_pool; the struct
 * and its user data must outlive the call. With a pool and threads >= 2 the call starts no thread: each parallel
 * loop becomes one call
 *     run(user, task, task_context, task_count)
 * from the thread that called resurf (never from inside a task, never two at once for one call), with task_count
 * = the options' `threads` (0 = all cores: set it to the pool's width). run calls task(task_context, i) for each
 * i in [0, task_count), on any threads, at the same time or one after another, and returns once every task it
 * started has returned. Tasks never wait for one another, so any schedule completes, even all of them one after
 * another on the calling thread; a task that run never starts is no error: the call does what is left of the loop
 * itself once run returns. Each task takes blocks of the loop's work from a shared counter until none is left;
 * which task does which block changes nothing: the result is byte-identical to that of resurf's own threads and
 * of one thread. Tasks use resurf_allocator from those threads (it must be thread-safe, as always). With
 * threads < 2 run is never called. The search tree that measures the result and carries attributes is built on
 * the calling thread alone when a pool is given. One exception to "no thread": with restore_options->normals =
 * RESURF_NORMALS_JET the restorer fits its jet normals on threads of its own (all cores). */
typedef struct resurf_thread_pool {
    void (*run)(void *user, void (*task)(void *task_context, unsigned task_index), void *task_context,
                unsigned task_count);
    void *user;
} resurf_thread_pool;

typedef struct resurf_simplify_options {
    size_t struct_size;
    /* Stopping: every one is unset (0) by default, and only those set count: the run stops at whichever of them
     * comes first. With none set the mesh is simplified as far as the guards allow. */
    size_t target_triangles;      /* stop once the result has at most this many triangles; default 0 (unset) */
    double target_ratio;          /* ... at most ratio × the input's triangles, in [0, 1]; default 0 (unset) */
    double max_error;             /* never collapse where the estimated error (RMS distance of the new vertex to the
                                     planes of the input triangles merged into it) exceeds this, in mesh units;
                                     default 0 (off) */
    double max_error_rel;         /* the same relative to the input's bounding-box diagonal; default 0 (off) */

    resurf_placement placement;   /* default RESURF_PLACEMENT_QUADRIC */
    resurf_restore_mode restore;  /* default RESURF_RESTORE_MEASURED */
    const resurf_restore_options *restore_options; /* how points are restored; NULL (default) =
                                     resurf_restore_options_default(), exactly (its AUTO normals are Max's here);
                                     its threads, progress and allocator are ignored: this call's are used */
    double sag_offset;            /* with restoration: once vertices lie on S, the facets between them cut inside
                                     convex parts of S by the chord sag (about h²κ/8 for an edge of length h where
                                     S bends by κ). Each output vertex is moved along S's normal by sag_offset × how
                                     far the input lies above its triangles on average (measured from their edges'
                                     midpoints to the input's closest points) so that the facets straddle the
                                     input's surface, which the report measures against. Not at a vertex touching
                                     a crease or corner (the chord-sag model holds on smooth surfaces only), and
                                     never more than twice the gap measured between the vertex's triangles and the
                                     input, nor of the other sign. 0 = vertices exactly on S; range [0, 4];
                                     default 1 */

    /* Guards. A candidate collapse that breaks one is skipped and counted in the report. The link condition (no
     * non-manifold result) and attribute seams (a seam vertex collapses only along its seam) always apply; vertices
     * that are non-manifold in the input never move. */
    bool lock_border;             /* true = border vertices never move or disappear; default false (borders are kept
                                     by boundary quadrics and collapse only along themselves) */
    const uint8_t *vertex_lock;   /* NULL (default), or one byte per input vertex: nonzero = that vertex's position
                                     (with every input vertex at exactly the same place) never moves nor
                                     disappears: it is in every level bit-exact, never restored onto S nor moved
                                     by the sag offset, as a non-manifold vertex is (refused collapses count in
                                     blocked_nonmanifold). For borders shared with other meshes. Read during the
                                     call only */
    double weld_tolerance_rel;    /* vertices closer than this × the input's bounding-box diagonal are one position
                                     for the collapses (the copies of a position that an exporter's rounding left a
                                     few units of the last place apart, as at a UV sphere's pole, where sin π is not
                                     0: apart, they are a hole whose rim the border guards hold). A welded position
                                     takes its first vertex's place; a locked vertex (vertex_lock) joins only its
                                     exact copies. 0 = exact copies only; in [0, 1e-3]; default 1e-8, far above
                                     such a pole's 1e-16 and below the float rounding of an exporter's vertices:
                                     measured on the 92 assets of bench-assets, 1e-7 welds some of 2CylinderEngine's
                                     (its 25% level's Hausdorff distance 7.70e-3 -> 8.76e-3 of the diagonal, 1.13
                                     times --restore none's) and 1e-6 parts of the Wuson meant to stay apart (10%
                                     level +20%) */
    double min_angle_deg;         /* skip collapses that leave a changed triangle with a smallest angle under this
                                     (unless that angle did not decrease); in [0, 60); 0 = off (default) */
    double max_normal_change_deg; /* skip collapses that turn a triangle's normal by more than this (flips and
                                     folds); in (0, 180]; default 60 */
    double feature_angle_deg;     /* an edge whose triangles' normals differ by more than this is a crease, and so
                                     is one along which the input's normals are split (a normal seam), where the
                                     surface around is smooth (every other edge at the vertex turning by less than
                                     a quarter of this: on a noisy scan sharp edges are noise). A vertex with three
                                     crease edges or more, or where a crease meets a border, is a corner. A corner
                                     holds its place until the level's error (the largest collapse error so far)
                                     reaches a quarter of its feature's size (of creases alone: the longest crease
                                     from it to the next corner; on a border: its connected part's bounding-box
                                     diagonal, so a large part's border corners never move), or until nothing else
                                     can be collapsed while its feature is a detail (at most 2% of the diagonal): a
                                     hard-surface model's small parts and a tuft's hair cards give way before they
                                     cost the rest of it its triangles (docs/restoring.md §8). A vertex touching a
                                     crease, and every vertex that absorbs one, is
                                     neither restored onto S nor moved by the sag offset: the facets keep the
                                     quadric's place, on the flat faces and their sharp edges. In (0, 180]; 180 =
                                     no crease by angle; default 80 (measured in docs/restoring.md §8). An edge
                                     between two triangle_groups (materials) is a crease at any angle and in any
                                     surface: the border between materials stays where it is, and where it turns by
                                     more than corner_angle_deg it has a corner */
    double corner_angle_deg;      /* a border that turns by more than this at a vertex makes it a corner (the
                                     corners of a flat panel, held as feature_angle_deg says; a crease's sharp turn
                                     is none: on scans such turns are noise); in (0, 180]; 180 = none; default 80 */
    double border_weight;         /* weight of the planes through border and seam edges, perpendicular to their
                                     triangles, relative to the triangles' own planes; >= 0; default 1 */
    bool drop_fins;               /* true (default): triangles over the same three positions as another are left out
                                     of the result: a pair with opposite orientations (a zero-thickness fin, which
                                     encloses nothing and makes its edges non-manifold, locking them) goes whole,
                                     a repeat with the same orientation goes alone. Scans hold them: the Stanford
                                     dragon's 48k reconstruction has 1,052 pairs, whose 2,094 non-manifold edges
                                     stopped its 10% level at 8,056 triangles (17%, error 1.8% of the diagonal);
                                     without them it reaches 4,778 (error 0.45%). false keeps every triangle.
                                     Only triangles of one group pair up: two sides in two materials stay. A
                                     double-sided sheet is pairs throughout (a leaf card, a flag): where the
                                     dropped pairs sharing positions would take 4 or more positions no other
                                     triangle uses, and share at most 2 with other triangles, one side (the one
                                     whose orientation continues the triangles around it, else the first
                                     written) is simplified and every level writes it twice: as simplified
                                     and mirrored (reversed triangles over the same positions, normals reversed,
                                     the other side's texture coordinates and attributes), so the sheet is neither
                                     lost nor one-sided, and its triangles count twice towards the targets */
    resurf_attached_sheets attached_sheets; /* a sheet as above (4 or more positions of its own) attached along more
                                     than 2 positions: kept, its line moving only along itself, or dropped.
                                     XGL_Wuson's dewlap (assimp's test models), 15 positions of its own hanging
                                     from 15 of the belly: kept, its 25% level is 0.70% of the diagonal from the
                                     input, dropped 1.66%. Default CHOOSE */

    /* Attributes in the cost (attribute quadrics, Hoppe 1999): each collapse also pays for how far the attributes of
     * the triangles merged into each of its wedges are from one linear field over them, so that collapses keep
     * vertices where an attribute bends (a texture's distortion, a colour's edge) and take them where it is
     * linear. A component counts its weight × the bounding-box diagonal: a weight of 1 prices an attribute
     * difference of 1 like a distance of one diagonal. The vertex's place and the error estimate (max_error)
     * stay geometric. Each side of an attribute seam is priced apart (a seam vertex still collapses only along
     * its seam). Memory: one record of 11 + 4 × (weighed components) doubles per input vertex, only when the input
     * has an attribute whose weight is above 0 (UVs alone: 152 bytes). >= 0 each; 0 = that attribute off.
     * Measured (UV error: texture-space distance of the level's UV to the input's at the closest point, 95th
     * percentile over 200k samples; geometric: the report's max / mean distance), weights 0 -> 0.25 -> 0.5:
     *   Collada duck (4,212 triangles) at 10%: UV 0.0087 -> 0.0085 -> 0.0079, max 1.50% -> 1.67% -> 1.68%;
     *   a sphere with a cylindrical UV map (earthCylindrical, 1,920) at 10%: UV 0.032 -> 0.022 -> 0.021, max
     *   0.98% -> 1.19% -> 1.25%, mean 0.22% -> 0.26% -> 0.27%; at 25%: UV 0.0115 -> 0.0092 -> 0.0083;
     *   gltfpack 1.3 at the same counts: UV 0.017 (duck) and 0.078 (sphere), so resurf is ahead without weights
     *   (its vertices take the input's UV at their closest point); the weights trade geometric error for UV
     *   error, and 0.25 takes most of the UV gain for the smallest geometric loss. Normals: 0.5 improved no UV or
     *   geometric figure (duck at 10%: max 1.50% -> 2.01%; the output's normals come from the smooth surface in
     *   any case), so they are off by default. On the analytic test grid of tests/test_attributes.c (48², 10%)
     *   the UV error falls 1.9× at 0.25 and 4× at 1, the colour error across a sharp edge 9.5× at 1. Meshes
     *   without attributes (scans, the benchmarks' analytic shapes) are unchanged, bit for bit, in the same time
     *   and memory. What the UV weight costs a textured mesh: on a UV-mapped cylinder of 256k triangles at 10%
     *   (one thread) 1.11–1.21 s -> 1.46 s of CPU and 89 -> 103 MB peak; at 1M triangles 341 -> 402 MB. */
    double normal_weight;         /* NORMAL (3 components); default 0 (off) */
    double texcoord_weight;       /* every texcoord set (2 components each); default 0.25 */
    uint32_t unsampled_texcoords; /* bit n set: no texture samples TEXCOORD_n (resurf_scene_build_lods sets it for
                                     each set its mesh's materials never sample, as exporters write texcoords for
                                     untextured materials): the set costs nothing and splits no vertex, so its
                                     seams hold nothing back; the levels still carry it, interpolated at each
                                     vertex's closest point of the input. Default 0 */
    double color_weight;          /* COLOR_0 (3 or 4 components); default 0.25 */
    double skin_weight;           /* JOINTS_n / WEIGHTS_n pairs (extras named so): the vertex's influences as one
                                     vector of weights over the joints, each weight times its joint's reach (half
                                     the diagonal of the box of the vertices the joint moves), seen through 4 fixed
                                     random projections (a pseudo-random unit-variance value per joint and field,
                                     so a field difference estimates the vectors' distance without one field per
                                     joint). A weight of 1 prices a vertex's whole weight moved from one joint to
                                     another like a displacement of the joints' reach; a 90-degree bend moves it by
                                     about √2 that, hence the default 1.4 (0 = off). Without it a collapse along a
                                     straight limb takes the rings where the weights blend (they cost no geometry).
                                     Measured in docs/reference.md (Changes in 0.3.0) */
    double morph_weight;          /* morph targets' POSITION deltas (extras "targets[t].POSITION", see
                                     RESURF_MORPH_TARGET_PREFIX; the 8 with the largest delta), in geometric units:
                                     the weight alone, not × the diagonal, so 1 prices a delta that departs by L from
                                     one linear field over the merged triangles like a distance L off the surface,
                                     what the level shows at morph weight 1. Default 1 (measured in
                                     docs/restoring.md §12); 0 = off */

    size_t measure_samples;       /* area-uniform samples of the result and of the input (plus the vertices of
                                     each, and the result's facet points) whose distances to the other surface are
                                     measured for the report (see resurf_simplify_report); default 20000; 0 = no
                                     measurement */
    unsigned threads;             /* 0 = all cores; the result is the same for any value */
    resurf_progress progress;     /* RESURF_STAGE_PREPARE, _SIMPLIFY, _FINISH; a cancel returns RESURF_ERR_CANCELLED */
    const resurf_allocator *allocator; /* NULL (default): the input mesh's (or the C heap); see resurf_allocator */
    const resurf_thread_pool *thread_pool; /* NULL (default): threads of the call's own; else the parallel loops
                                              run on this pool (run required, else RESURF_ERR_INVALID_OPTIONS) */
} resurf_simplify_options;

/* The defaults: no target (set one), quadric placement, measured restoration (inline with the restorer's defaults,
 * Max's normals, kept where it measures closer to the input than the plain collapse), sag_offset 1, feature_angle_deg 80, corner_angle_deg 80, max_normal_change_deg 60, min_angle_deg 0,
 * border_weight 1, normal_weight 0, texcoord_weight 0.25, color_weight 0.25, morph_weight 1, measure_samples 20000,
 * weld_tolerance_rel 1e-8, all cores.
 * Measured with tools/bench_simplify.c on the irregular analytic sphere, torus and cubic surface (20k triangles,
 * 10% and 2%): the mean distance of the LOD's surface to the true surface is lowest at sag_offset 1 (about 0.24–0.26,
 * 0.35–0.38 and 0.74–0.80 of meshoptimizer's; 0.86–0.89 with the offset at 0), as the chord-sag model predicts (the
 * mean depth of an equilateral facet under a sphere equals its edges' sag h²κ/8). Normal-change bounds from 40° to 90°
 * gave the same figures. */
RESURF_API resurf_simplify_options resurf_simplify_options_default(void);

/* Why a simplification stopped. */
typedef enum resurf_simplify_stop {
    RESURF_STOP_TARGET = 0,   /* the triangle target was reached */
    RESURF_STOP_ERROR,        /* no collapse is left under max_error / max_error_rel (some were skipped for it) */
    RESURF_STOP_BLOCKED,      /* every remaining collapse is blocked by a guard (see the blocked_* counts) */
    RESURF_STOP_COUNT
} resurf_simplify_stop;

typedef struct resurf_simplify_report {
    size_t input_triangles;          /* triangles of the input that take part (a repeated position drops one, and
                                        so do fins and repeats with drop_fins) */
    size_t dropped_fins;             /* triangles left out by drop_fins */
    size_t input_positions;          /* distinct positions they use */
    size_t triangles, vertices;      /* the result's counts */
    size_t positions;                /* distinct positions of the result (vertices minus seam copies) */
    size_t collapses;                /* edge collapses done (cumulative over LOD levels) */
    resurf_simplify_stop stop;
    double max_error_estimate;       /* largest estimated error (see max_error) of a collapse done */

    /* Measured: the two-sided distance between the result's surface and the input's, as resurf_compare()
     * measures it (REF = the input, TEST = the result), with exact point–triangle distances through a BVH over
     * each surface. Result to input: the result's vertices, its facet points (each triangle's centroid and edge
     * midpoints, where a coarse facet or a long chord leaves the input most) and measure_samples area-uniform
     * samples of it, to the input's surface. Input to result: the vertices the input's triangles use and measure_samples area-uniform
     * samples of the input, to the result's surface; this is the side that sees what a level lost (a square of
     * two triangles reduced to one: 0 from the result, 0.316 of the diagonal from the input). Each side's max is
     * the largest at its points, its mean the mean over its samples (over its vertices when its surface has no
     * area). max_distance = max of the two maxima (the symmetric Hausdorff distance), mean_distance = the mean of
     * the two means. Sampled, so the maxima are lower bounds: the farthest point can lie between the points (on
     * the analytic torus, sphere, cubic and cylinder and two scans at 25%, 10% and 2%, the default's maximum is
     * 0.93–1.0 of a dense measurement at 2M samples per side, its mean within 1%). The *_rel figures divide by diagonal. All NaN when not measured (measure_samples = 0) or
     * the result is empty. Deterministic for any thread count. */
    double max_distance, mean_distance;
    double max_distance_rel, mean_distance_rel;
    double result_to_input_max, result_to_input_mean; /* one-sided, mesh units */
    double input_to_result_max, input_to_result_mean; /* one-sided, mesh units */
    /* UV error, when the input (and so the result) has texcoord set 0 (glTF's TEXCOORD_0): at each area-uniform
     * sample of the result, the texture-space distance between the result's UV interpolated there and the input's
     * UV interpolated at the closest point of the input's surface; the mean and the 95th percentile (nearest
     * rank) over the samples. Across a UV seam the closest point can fall on the other chart, so samples within
     * the distance error of a seam can count a chart's jump. NaN without UVs, when the set is one no texture
     * samples (unsampled_texcoords bit 0) or when nothing is measured. */
    double uv_error_mean, uv_error_p95;
    double diagonal;                 /* of the input's bounding box */

    /* Candidate collapses rejected by each guard. A candidate is counted each time it is taken up, so one edge can
     * be counted several times. */
    size_t blocked_link;             /* link condition: the result would be non-manifold or a double-sided sheet */
    size_t blocked_flip;             /* a triangle would flip, fold or degenerate (max_normal_change_deg) */
    size_t blocked_min_angle;        /* min_angle_deg */
    size_t blocked_distance;         /* deferred (re-queued at a much higher cost): an end's old position would lie
                                        farther from its new triangles than a quarter of the edge's length and twice
                                        the quadric error (a thin spike's tip, which quadrics let shrink); or, with
                                        restoration, the midpoint of a new edge over 6 of the original's local edges
                                        long would lie that far from the original (an edge bridging a notch) */
    size_t blocked_border;           /* a border vertex would leave its border, or lock_border */
    size_t blocked_seam;             /* a seam vertex would leave its seam */
    size_t blocked_feature;          /* a crease vertex would leave its crease, or a corner would move */
    size_t blocked_nonmanifold;      /* an end is a non-manifold vertex of the input, or the edge has > 2 triangles
                                        (3 along a junction line, where a sheet meets a surface, may go) */
    size_t skipped_error;            /* candidates over max_error / max_error_rel */

    size_t restored;                 /* points restored onto S (INLINE: one per collapse; POST: one per position) */
    size_t restore_left;             /* of those, points left unrestored: the restorer left them (too far, no
                                        root), moved them implausibly far (more than twice their distance to
                                        the input plus a quarter of the local edge length), or moved them farther
                                        from the input than they were by more than twice the input's own facet
                                        depth under S there (S is not smooth at the collapse's scale) */
    resurf_restore_mode restore_used; /* the mode this level was made with: options->restore, or with
                                        RESURF_RESTORE_MEASURED the one kept (INLINE or NONE) */
    resurf_attached_sheets attached_sheets_used; /* DROP or KEEP: how this level was made (see attached_sheets) */
} resurf_simplify_report;

/* Simplifies a mesh by edge collapses (Garland–Heckbert quadrics) over welded positions, restoring new vertices
 * onto the smooth surface the input approximates (Semenova et al., §4.2) as options->restore says. Cheapest
 * first: the candidate collapses, sorted by cost, are taken in passes of collapses that share no end (each pass up
 * to a cost limit), so every cost stays exact while a pass runs and a pass's placements can be restored on all
 * threads at once. A new vertex's closest triangle of the input is found by walking the input from the triangle
 * where its collapsed end was restored. A restored vertex stays within 0.05 × the input's local edge length of the
 * plane of the input triangle it was restored on: where the input's normals turn by more than about 17° per edge,
 * as at a scan's sharp ridges, S bulges over the input by up to 0.3 of an edge.
 * - in: finite positions where triangles refer, indices in range (else RESURF_ERR_INVALID_MESH naming the element);
 *   triangles with a repeated position are dropped; any topology is accepted (non-manifold vertices stay put).
 *   Not modified.
 * - options: NULL = defaults, which set no target: set one (see resurf_simplify_options).
 * - out: receives a new mesh (free with resurf_mesh_free) with the input's attribute layout: normals from S's
 *   smooth normal field at each vertex (without restoration: the input's normals interpolated), texcoords,
 *   colours and extras interpolated from the input at the vertex's closest input triangle on the same side of an
 *   attribute seam, and triangle groups from the input triangle each result triangle descends from. Triangles keep
 *   the input's relative order; vertices are numbered in order of first use. Flat shading is kept, not frozen: in
 *   a connected part of the input whose every corner carries its own face's normal (within 1°) and whose normals
 *   are split somewhere (an STL or any flat-shaded export), the normals say nothing the geometry does not, so they
 *   are no seams there, and the result's vertices there are split by face and given their faces' normals.
 * - out_report: may be NULL.
 * The result is byte-identical for the same input and options whatever options->threads is. On error or cancel
 * *out is NULL. Time about n log n for n triangles; peak memory about 150 bytes per input triangle without
 * restoration, about 210–230 with it (the restorer's services over the input take the difference). */
RESURF_API resurf_status resurf_simplify(const resurf_mesh *in, const resurf_simplify_options *options,
                                         resurf_mesh **out, resurf_simplify_report *out_report,
                                         resurf_error *error);

/* A chain of levels of detail. Level i has at most ratios[i] × the input's triangles and is simplified from level
 * i − 1 (the collapse sequence continues where the previous level stopped), yet every level is restored onto S of
 * the ORIGINAL input, never onto a previous level. The parameters come as in resurf_scene_build_lods(): the input,
 * what to make, the options, then the outputs. options' target_triangles and target_ratio are ignored;
 * max_error / max_error_rel still apply (a level that cannot go further equals the previous one).
 * - ratios: count values in (0, 1], non-increasing (else RESURF_ERR_INVALID_ARGUMENT).
 * - out_levels: room for count mesh pointers; each level is freed by the caller with resurf_mesh_free.
 * - out_reports: room for count reports, or NULL.
 * On error or cancel every out_levels[i] is NULL. The CLI writes level i (1-based, in the order given) of
 * `-o STEM.EXT` to STEM_lodI.EXT: `resurf simplify in.ply -o out.ply --levels 0.5,0.1` writes out_lod1.ply and
 * out_lod2.ply. */
RESURF_API resurf_status resurf_simplify_lods(const resurf_mesh *in, const double *ratios, size_t count,
                                              const resurf_simplify_options *options, resurf_mesh **out_levels,
                                              resurf_simplify_report *out_reports, resurf_error *error);

#ifdef __cplusplus
}
#endif

/* The manual goes on in two headers of their own, included here: */
#include "scene.h"   /* Scenes (glTF): load, levels of detail, save */
#include "preview.h" /* Preview: a picture of every level */

#endif /* RESURF_RESURF_H */
