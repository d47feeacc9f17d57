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
 *   (`threads` option: 0 = all cores); their results do not depend on the thread count.
 * - The library never prints, never exits and never aborts on bad input.
 * - Progress: a resurf_progress {fn, user} is called at a bounded rate with a stage name and a fraction in [0,1].
 *   A non-zero return cancels the call: it returns RESURF_ERR_CANCELLED and leaves the caller's data valid.
 * - Units: lengths are in the mesh's own units unless a name ends in `_rel` (relative to the bounding-box
 *   diagonal of the reference mesh); angles end in `_deg`.
 */
#ifndef RESURF_RESURF_H
#define RESURF_RESURF_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define RESURF_VERSION_MAJOR 0
#define RESURF_VERSION_MINOR 1
#define RESURF_VERSION_PATCH 0
#define RESURF_VERSION_STRING "0.1.0"

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

/* Progress and cancel. fn may be NULL. stage is a static string ("load", "restore", ...); fraction is in [0,1].
 * Return 0 to continue, anything else to cancel. Called from the calling thread only. */
typedef struct resurf_progress {
    int (*fn)(void *user, const char *stage, double fraction);
    void *user;
} resurf_progress;

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

/* A deep copy of mesh. */
RESURF_API resurf_status resurf_mesh_clone(const resurf_mesh *mesh, resurf_mesh **out_mesh, resurf_error *error);

/* Frees the mesh and everything it owns. NULL is allowed. */
RESURF_API void resurf_mesh_free(resurf_mesh *mesh);

/* Adds an extra float attribute of `components` values per vertex (zero-filled) and returns it in *out (may be
 * NULL). The pointer stays valid until the next call that changes the mesh's attributes. */
RESURF_API resurf_status resurf_mesh_add_extra(resurf_mesh *mesh, const char *name, unsigned components,
                                               resurf_attribute **out, resurf_error *error);

/* Axis-aligned bounding box of the vertices referenced by triangles (all vertices when there are none).
 * Writes zeros for an empty mesh. Returns the diagonal length. */
RESURF_API double resurf_mesh_bounds(const resurf_mesh *mesh, double out_min[3], double out_max[3]);

/* The welded position topology. Vertex v and w share a position id iff their positions are equal (tolerance 0) or
 * closer than tolerance_rel × bounding-box diagonal. out_position_of_vertex receives vertex_count ids, numbered
 * 0..*out_position_count-1 in order of first appearance. An attribute seam is a position id with several vertices. */
RESURF_API resurf_status resurf_mesh_weld_map(const resurf_mesh *mesh, double tolerance_rel,
                                              uint32_t *out_position_of_vertex, size_t *out_position_count,
                                              resurf_error *error);

/* ------------------------------------------------------------------------------------------------------------- */
/* Validation and repair                                                                                         */
/* ------------------------------------------------------------------------------------------------------------- */

/* What resurf_mesh_validate() found. Topology counts are over welded positions (exact weld), so attribute seams
 * do not show up as boundaries. The first_* fields give an example index, or -1. */
typedef struct resurf_validation {
    size_t vertex_count, triangle_count, position_count; /* position_count: distinct positions */
    size_t nonfinite_vertices;        /* NaN or infinite coordinate (or attribute) */
    size_t out_of_range_indices;      /* index >= vertex_count */
    size_t degenerate_triangles;      /* a repeated index (after welding) */
    size_t zero_area_triangles;       /* three distinct positions on a line (area <= 1e-14 × diagonal²) */
    size_t boundary_edges;            /* edges with one triangle */
    size_t boundary_loops;
    size_t nonmanifold_edges;         /* edges with three or more triangles */
    size_t nonmanifold_vertices;      /* vertices whose triangles form more than one fan */
    size_t inconsistent_edges;        /* manifold edges used twice in the same direction (orientation flips) */
    size_t unreferenced_vertices;
    size_t components;                /* connected components of triangles (through shared positions) */
    long long first_nonfinite_vertex, first_out_of_range_triangle, first_degenerate_triangle,
        first_zero_area_triangle, first_nonmanifold_edge_vertex, first_inconsistent_triangle;
} resurf_validation;

/* Counts the problems of mesh. Never fails on a bad mesh (that is what it reports); fails only on NULL
 * arguments or out of memory. Out-of-range triangles are skipped by the topology counts. */
RESURF_API resurf_status resurf_mesh_validate(const resurf_mesh *mesh, resurf_validation *out, resurf_error *error);

/* True (1) when the mesh can be processed: finite positions and every index in range. */
RESURF_API int resurf_validation_ok(const resurf_validation *v);

enum {
    RESURF_REPAIR_DROP_INVALID = 1u << 0,      /* drop triangles with out-of-range indices or non-finite corners */
    RESURF_REPAIR_DROP_DEGENERATE = 1u << 1,   /* drop triangles with a repeated index or a repeated position */
    RESURF_REPAIR_DROP_ZERO_AREA = 1u << 2,    /* drop triangles of zero area */
    RESURF_REPAIR_WELD = 1u << 3,              /* merge vertices with equal positions and equal attributes */
    RESURF_REPAIR_REMOVE_UNREFERENCED = 1u << 4,
    RESURF_REPAIR_ALL = 0x1f,
};

typedef struct resurf_repair_options {
    size_t struct_size;
    unsigned flags;          /* RESURF_REPAIR_*; default RESURF_REPAIR_ALL */
    double weld_tolerance_rel; /* with RESURF_REPAIR_WELD: 0 welds exact duplicates only; default 0 */
    int weld_ignore_attributes; /* 1: weld by position alone (attributes of the first vertex win); default 0 */
} resurf_repair_options;

RESURF_API resurf_repair_options resurf_repair_options_default(void);

typedef struct resurf_repair_report {
    size_t dropped_invalid, dropped_degenerate, dropped_zero_area, welded_vertices, removed_unreferenced;
} resurf_repair_report;

/* Repairs mesh in place as options say. out_report may be NULL. */
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
} resurf_load_options;

RESURF_API resurf_load_options resurf_load_options_default(void);

/* Loads a mesh. Polygons are triangulated (fan); STL is welded on load (exact positions). Indices are checked:
 * a file whose faces point outside its vertices fails with RESURF_ERR_PARSE and the face's line or offset.
 * Non-finite coordinates are refused. No allocation exceeds what the file's size can justify. */
RESURF_API resurf_status resurf_mesh_load(const char *path, const resurf_load_options *options,
                                          resurf_mesh **out_mesh, resurf_error *error);

/* Loads from memory; `name` is used in error messages only (may be NULL). */
RESURF_API resurf_status resurf_mesh_load_memory(const void *data, size_t size, resurf_format format,
                                                 const char *name, const resurf_load_options *options,
                                                 resurf_mesh **out_mesh, resurf_error *error);

typedef struct resurf_save_options {
    size_t struct_size;
    resurf_format format;       /* default AUTO */
    int binary;                 /* PLY and STL: 1 = binary little-endian (default), 0 = ASCII */
    int write_normals, write_texcoords, write_colors, write_extras; /* default 1: write what the format can hold */
    resurf_progress progress;
} resurf_save_options;

RESURF_API resurf_save_options resurf_save_options_default(void);

/* Saves a mesh. Text formats print 17 significant digits, so doubles round-trip exactly. The file is written to a
 * temporary file in the same folder and renamed into place: a failure leaves no partial file and an existing file
 * is replaced only as a whole. */
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
    RESURF_NORMALS_COUNT
} resurf_normal_scheme;

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

/* What a vertex whose optimal-direction root lies outside its closest triangle does. */
typedef enum resurf_outside_policy {
    RESURF_OUTSIDE_NEIGHBOURS = 0, /* try the triangles around the closest one; else use the least-outside root */
    RESURF_OUTSIDE_LEAST,          /* use the least-outside root of the closest triangle */
    RESURF_OUTSIDE_KEEP,           /* leave the vertex where it is (reported) */
    RESURF_OUTSIDE_COUNT
} resurf_outside_policy;

typedef struct resurf_restore_options {
    size_t struct_size;
    resurf_normal_scheme normals;      /* default: see resurf_restore_options_default() */
    resurf_side_rule side_rule;
    resurf_displacement displacement;
    double step;                       /* k: p ← p + k Σ δ_j N_opt; paper 1/6; 1/3 takes the average */
    unsigned iterations;               /* paper 5; with tolerance_rel > 0 the maximum number */
    double tolerance_rel;              /* stop a vertex once its step is below this × its local edge length; 0 = off */
    double crease_angle_deg;           /* dihedral angle above which an edge is a crease; default 60; 180 = none */
    int use_input_normals;             /* 1: split normals of M (different normals at one position) mark creases */
    double far_factor;                 /* vertices farther from M than this × local edge length stay; default 4 */
    resurf_outside_policy outside;
    int boundary;                      /* 1 (default): vertices nearest a boundary edge stay on the boundary curve */
    unsigned threads;                  /* 0 = all cores */
    resurf_progress progress;
} resurf_restore_options;

/* resurf's default (chosen by measurement, see README). */
RESURF_API resurf_restore_options resurf_restore_options_default(void);
/* The paper's preset: inverse-area normals, curvature rule, formula (2), k = 1/6, 5 iterations. */
RESURF_API resurf_restore_options resurf_restore_options_paper(void);

typedef struct resurf_restore_report {
    size_t vertices;              /* vertices considered */
    size_t moved;                 /* vertices that moved */
    double mean_displacement, max_displacement;
    size_t left_far;              /* left alone: farther from M than far_factor × local edge length */
    size_t left_outside;          /* left alone: no root inside a triangle (RESURF_OUTSIDE_KEEP) */
    size_t used_least_outside;    /* restored with a root outside its triangle */
    size_t on_boundary;           /* restored along a boundary curve */
    size_t on_crease;             /* restored along a crease */
    size_t left_nonfinite;        /* non-finite input position */
} resurf_restore_report;

/* Moves the vertices of `processed` (M') onto the smooth surface S approximated by `original` (M), in place.
 * Connectivity and attributes are unchanged. out_report may be NULL. On error or cancel, processed is unchanged. */
RESURF_API resurf_status resurf_restore(const resurf_mesh *original, resurf_mesh *processed,
                                        const resurf_restore_options *options, resurf_restore_report *out_report,
                                        resurf_error *error);

/* ------------------------------------------------------------------------------------------------------------- */
/* Smoothing                                                                                                     */
/* ------------------------------------------------------------------------------------------------------------- */

typedef enum resurf_smooth_method {
    RESURF_SMOOTH_LAPLACIAN = 0, /* umbrella operator, uniform weights, step lambda */
    RESURF_SMOOTH_TAUBIN,        /* λ|μ with uniform weights */
    RESURF_SMOOTH_TAUBIN_COT,    /* λ|μ with cotangent weights */
    RESURF_SMOOTH_BILAPLACIAN,   /* umbrella of the umbrella */
    RESURF_SMOOTH_COUNT
} resurf_smooth_method;

typedef struct resurf_smooth_options {
    size_t struct_size;
    resurf_smooth_method method;
    unsigned iterations;  /* default 10 */
    double lambda;        /* default 0.5 (Laplacian), 0.33 (Taubin) */
    double mu;            /* Taubin's negative step; default -0.34 */
    resurf_progress progress;
} resurf_smooth_options;

RESURF_API resurf_smooth_options resurf_smooth_options_default(void);
RESURF_API const char *resurf_smooth_method_name(resurf_smooth_method method);

/* Smooths positions in place; boundary vertices (over welded positions) stay fixed, seams move together. */
RESURF_API resurf_status resurf_smooth(resurf_mesh *mesh, const resurf_smooth_options *options, resurf_error *error);

/* ------------------------------------------------------------------------------------------------------------- */
/* Metrics                                                                                                       */
/* ------------------------------------------------------------------------------------------------------------- */

typedef struct resurf_compare_options {
    size_t struct_size;
    size_t samples;        /* area-uniform samples per surface, in addition to all vertices; default 200000 */
    uint64_t seed;         /* sample seed; default 1 */
    unsigned threads;      /* 0 = all cores */
    resurf_progress progress;
} resurf_compare_options;

RESURF_API resurf_compare_options resurf_compare_options_default(void);

typedef struct resurf_metrics {
    double diagonal;                           /* of REF's bounding box; the *_rel figures divide by it */
    double hausdorff, mean, rms;               /* two-sided surface distance */
    double test_to_ref_max, test_to_ref_mean;  /* one-sided: TEST's surface to REF's */
    double ref_to_test_max, ref_to_test_mean;
    double vertex_max, vertex_mean;            /* TEST's vertices to REF's surface */
    double min_angle_deg, mean_min_angle_deg;  /* triangle quality of TEST */
    double share_below_10deg;                  /* fraction of TEST's triangles with an angle under 10° */
    double mean_normal_deviation_deg;          /* TEST's face normals against REF's surface normal at the closest point */
} resurf_metrics;

/* Distances between the surfaces of ref and test. out_vertex_distance, if not NULL, receives test->vertex_count
 * distances of TEST's vertices to REF's surface. */
RESURF_API resurf_status resurf_compare(const resurf_mesh *ref, const resurf_mesh *test,
                                        const resurf_compare_options *options, resurf_metrics *out_metrics,
                                        double *out_vertex_distance, resurf_error *error);

#ifdef __cplusplus
}
#endif

#endif /* RESURF_RESURF_H */
