/* Internal interfaces shared between resurf's source files. Not installed, not exported.
 * Names: resurfi_ for functions and types shared between files; single-file helpers are static. */
#ifndef RESURF_INTERNAL_H
#define RESURF_INTERNAL_H

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "resurf/resurf.h"
#include "vec3.h"

#if defined(__GNUC__)
#define RESURFI_PRINTF(f, a) __attribute__((format(printf, f, a)))
#else
#define RESURFI_PRINTF(f, a)
#endif

/* ---- errors (error.c) ---------------------------------------------------------------------------------------- */

/* Fills *error (if not NULL) and returns status. path may be NULL; line 0 and offset -1 mean "unknown". */
resurf_status resurfi_fail(resurf_error *error, resurf_status status, const char *path, long long line,
                           long long offset, const char *fmt, ...) RESURFI_PRINTF(6, 7);
/* The common case without a location. */
resurf_status resurfi_error(resurf_error *error, resurf_status status, const char *fmt, ...) RESURFI_PRINTF(3, 4);
/* Sets *error to RESURF_OK with empty fields. */
void resurfi_clear_error(resurf_error *error);

/* Returns nonzero when the caller asked to cancel. */
int resurfi_progress(const resurf_progress *progress, resurf_stage stage, double fraction);

/* An options pointer that is not NULL must carry the struct_size its _default() set. */
#define RESURFI_CHECK_OPTIONS(opts, type, error)                                                                \
    do {                                                                                                        \
        if ((opts) && (opts)->struct_size != sizeof(type))                                                      \
            return resurfi_error((error), RESURF_ERR_INVALID_OPTIONS,                                           \
                                 #type " was not initialised by its _default() function");                     \
    } while (0)
/* The same for an options struct with an allocator field, which must have all three callbacks or none. */
#define RESURFI_CHECK_OPTIONS_ALLOC(opts, type, error)                                                          \
    do {                                                                                                        \
        RESURFI_CHECK_OPTIONS(opts, type, error);                                                               \
        if ((opts) && !resurfi_allocator_ok((opts)->allocator))                                                 \
            return resurfi_error((error), RESURF_ERR_INVALID_OPTIONS,                                           \
                                 #type ": the allocator needs allocate, reallocate and release (or none)");     \
    } while (0)

/* ---- memory (mesh.c) ----------------------------------------------------------------------------------------- */

/* Every heap block of the library comes from these four, through the call's allocator `a` (NULL, or one whose
 * allocate is NULL such as a zeroed mesh field, = the C heap; this file holds the only malloc/realloc/free calls).
 * count*size is overflow-checked (NULL on overflow or failure); count 0 returns a valid 1-byte block.
 * resurfi_calloc zero-fills. resurfi_realloc leaves p valid on failure; a NULL p allocates. NULL p is fine to free.
 * A block must go back to the allocator it came from. Internal functions that allocate take the call's allocator
 * as their first parameter; objects that outlive one function (adjacency, BVH, restorer) keep a copy of it. */
void *resurfi_alloc(const resurf_allocator *a, size_t count, size_t size);
void *resurfi_calloc(const resurf_allocator *a, size_t count, size_t size);
void *resurfi_realloc(const resurf_allocator *a, void *p, size_t count, size_t size);
void resurfi_free(const resurf_allocator *a, void *p);
/* A copy of the NUL-terminated s, or NULL when out of memory. */
char *resurfi_strdup(const resurf_allocator *a, const char *s);
/* The allocator a call uses: its option's when not NULL, else the mesh's own (mesh may be NULL: the C heap). */
static inline const resurf_allocator *resurfi_allocator_of(const resurf_allocator *option, const resurf_mesh *mesh)
{
    return option ? option : mesh ? &mesh->allocator : NULL;
}
/* An allocator given in options has all three callbacks, or none (the C heap named explicitly). */
static inline int resurfi_allocator_ok(const resurf_allocator *a)
{
    return !a || (a->allocate && a->reallocate && a->release) || (!a->allocate && !a->reallocate && !a->release);
}

/* ---- mesh helpers (mesh.c, weld.c) --------------------------------------------------------------------------- */

/* Input normals closer than this (cosine of 1°) are one normal: the test for split normals (a normal seam). */
#define RESURFI_SAME_NORMAL_COS 0.99984769515639127

static inline vec3 resurfi_position(const resurf_mesh *m, uint32_t v) { return v3_load(m->positions + 3 * (size_t)v); }

/* Exact position weld: remap[v] = position id, positions numbered by first appearance. (weld.c)
 * Positions are equal when their coordinate bits are, with −0.0 taken as +0.0 (a NaN welds only with the same
 * NaN bits). Expected O(n) (hash table). Fails only with INVALID_ARGUMENT (over UINT32_MAX) or OUT_OF_MEMORY. */
resurf_status resurfi_weld_exact(const resurf_allocator *alloc, const double *positions, size_t vertex_count,
                                 uint32_t *remap, size_t *out_count);
/* resurf_mesh_weld_map() with the call's allocator for its temporaries. (weld.c) */
resurf_status resurfi_weld_map(const resurf_allocator *alloc, const resurf_mesh *mesh, double tolerance_rel,
                               uint32_t *out_position_of_vertex, size_t *out_position_count, resurf_error *error);
/* Bounding-box diagonal of the finite positions of the vertices that triangles reference (all vertices when none
 * is referenced); 0 when there are none. The reference length for *_rel tolerances. (weld.c) */
double resurfi_finite_diagonal(const resurf_mesh *mesh);

/* ---- meshes as parts of one mesh (mesh_parts.c) --------------------------------------------------------------- */

/* Whether a and b carry the same attributes: normals, texcoord sets, colours (and their components), extras by
 * name and components. Only such meshes join. */
bool resurfi_mesh_same_attributes(const resurf_mesh *a, const resurf_mesh *b);

/* The parts (of one layout) side by side as one mesh, made with alloc; triangle_groups[t] is the part of triangle
 * t (group_count = count, names NULL). */
resurf_status resurfi_mesh_join_parts(const resurf_mesh *const *parts, size_t count, const resurf_allocator *alloc,
                                      resurf_mesh **out, resurf_error *error);

/* A joined mesh (or a level of one) split by group into count meshes of its layout, made with alloc; a part
 * without triangles is an empty mesh. On failure every out_parts[p] is NULL. */
resurf_status resurfi_mesh_split_parts(const resurf_mesh *joined, size_t count, const resurf_allocator *alloc,
                                       resurf_mesh **out_parts, resurf_error *error);

/* ---- adjacency (adjacency.c) --------------------------------------------------------------------------------- */

/* Adjacency of a triangle list over vertex ids 0..vertex_count-1 (usually welded position ids).
 * Triangles with an out-of-range or repeated index are ignored (they have no edges). */
typedef struct resurfi_adjacency {
    size_t vertex_count, triangle_count;
    uint32_t *vertex_face_offset; /* vertex_count + 1: faces of v are vertex_faces[offset[v] .. offset[v+1]) */
    uint32_t *vertex_faces;
    uint32_t *vertex_edge_offset; /* vertex_count + 1: edges whose lower vertex is v are [offset[v], offset[v+1]) */
    size_t edge_count;
    uint32_t *edge_vertices;      /* 2 * edge_count, (a, b) with a < b, sorted */
    uint32_t *edge_face_offset;   /* edge_count + 1 */
    uint32_t *edge_faces;         /* faces of each edge */
    uint32_t *face_edges;         /* 3 * triangle_count: edge id of the side (t[i], t[(i+1)%3]); UINT32_MAX if none */
    uint8_t *vertex_flags;        /* RESURFI_VERTEX_* */
    size_t boundary_loop_count;   /* see resurfi_adjacency_boundary_loops */
    resurf_allocator alloc;       /* a copy of the build's allocator: every array (and components' temporary) */
} resurfi_adjacency;

enum {
    RESURFI_VERTEX_BOUNDARY = 1,     /* on an edge with one face */
    RESURFI_VERTEX_NONMANIFOLD = 2,  /* on an edge with >2 faces, or several fans */
    RESURFI_VERTEX_UNREFERENCED = 4,
};

/* Faces of a vertex and of an edge are listed in increasing triangle order. A fan is a set of faces around a
 * vertex connected across manifold edges ending there. Fails with OUT_OF_MEMORY, or LIMIT when 3 × triangle_count
 * does not fit 32 bits; *out is then empty (freeing it is allowed). */
resurf_status resurfi_adjacency_build(const resurf_allocator *alloc, const uint32_t *indices, size_t triangle_count,
                                      size_t vertex_count, resurfi_adjacency *out);
/* The same without vertex_flags (left NULL) and boundary_loop_count (left 0): only vertex → faces and the edge
 * tables, for holders that classify vertices their own way (the restorer). Cheaper by the fan search. */
resurf_status resurfi_adjacency_build_edges(const resurf_allocator *alloc, const uint32_t *indices,
                                            size_t triangle_count, size_t vertex_count, resurfi_adjacency *out);
void resurfi_adjacency_free(resurfi_adjacency *adj);
/* Frees the edge arrays, keeping the vertex-face lists and flags (for holders that only walk fans afterwards). */
void resurfi_adjacency_drop_edges(resurfi_adjacency *adj);
/* Edge id of (a, b) in either order, or UINT32_MAX. O(log degree). */
uint32_t resurfi_adjacency_find_edge(const resurfi_adjacency *adj, uint32_t a, uint32_t b);
static inline uint32_t resurfi_edge_face_count(const resurfi_adjacency *adj, uint32_t e)
{
    return adj->edge_face_offset[e + 1] - adj->edge_face_offset[e];
}
/* Connected components of triangles (via shared vertices); component[t] for each triangle (may be NULL).
 * Returns the number of components, numbered in order of their lowest triangle; ignored triangles get UINT32_MAX.
 * indices must be the ones the adjacency was built from. Returns SIZE_MAX only when component is NULL and the
 * temporary array cannot be allocated. */
size_t resurfi_adjacency_components(const resurfi_adjacency *adj, const uint32_t *indices, uint32_t *component);
/* Number of closed boundary loops (boundary edges chained at their vertices), counted on the surface obtained by
 * splitting each vertex into one copy per fan: the two triangles of a bow-tie have two loops, and on a manifold
 * mesh this is the plain number of boundary curves. Computed by the build. */
size_t resurfi_adjacency_boundary_loops(const resurfi_adjacency *adj);

/* The loops that jump around arrays far larger than the caches: where the next address is known a little ahead,
 * asking for it early overlaps the misses. */
#if defined(__GNUC__) || defined(__clang__)
#define PREFETCH(p) __builtin_prefetch(p)
#else
#define PREFETCH(p) ((void)(p))
#endif

/* ---- threads (parallel.c) ------------------------------------------------------------------------------------ */

/* Number of worker threads for a `threads` option (0 = all online cores), at least 1. */
unsigned resurfi_thread_count(unsigned requested);
/* Calls fn(ctx, begin, end, worker) over [0, count) split in contiguous blocks of block_size, on `threads` threads
 * (the calling thread included). Blocks are independent; fn must write only its own results, so the outcome does
 * not depend on the thread count. Returns nonzero if any call returned nonzero (the rest are then skipped). */
int resurfi_parallel_for(size_t count, size_t block_size, unsigned threads,
                         int (*fn)(void *ctx, size_t begin, size_t end, unsigned worker), void *ctx);

/* A call's own team of threads, for many short parallel loops in a row (the simplifier's chunks): starting and
 * joining a thread costs about 40 µs, handing a loop to a sleeping one a wake-up (a futex call). Waiting workers
 * sleep (they never spin). With a host pool (resurf_thread_pool) the team is the host's: each loop is handed to it as `threads`
 * tasks and no thread is started. Owned by one call, never shared between calls: no global state. */
typedef struct resurfi_pool resurfi_pool;
/* A pool of `threads` threads, the calling one included (threads - 1 are started, none with a host pool). *out is
 * NULL, and loops then run on the calling thread alone, when threads < 2 or no thread can be started. host: NULL,
 * or a pool whose run is set; it must outlive the pool. */
resurf_status resurfi_pool_create(const resurf_allocator *alloc, unsigned threads, const resurf_thread_pool *host,
                                  resurfi_pool **out);
void resurfi_pool_free(resurfi_pool *pool);
/* resurfi_parallel_for on the pool's threads (NULL: on the calling thread alone), from the thread that created
 * it. A pool of its own threads whose loops were kept waiting on a descheduled worker runs its later loops on the
 * calling thread alone (parallel.c): the same results. */
int resurfi_pool_for(resurfi_pool *pool, size_t count, size_t block_size,
                     int (*fn)(void *ctx, size_t begin, size_t end, unsigned worker), void *ctx);

/* ---- BVH over triangles (bvh.c) ------------------------------------------------------------------------------ */

typedef struct resurfi_bvh resurfi_bvh;

/* Builds an AABB tree over the triangles (binned SAH, O(n log n), leaves of <= 4 triangles) on all cores. The tree
 * keeps float copies of the corners and pointers to positions/indices (for exact distances): both arrays must
 * stay alive and unchanged while the tree is used. Triangles with out-of-range indices or
 * non-finite corners are skipped (never returned by queries). The tree is the same whatever the thread count.
 * RESURF_ERR_INVALID_ARGUMENT for NULL arrays with a nonzero count; RESURF_ERR_LIMIT above 2^31 triangles;
 * RESURF_ERR_OUT_OF_MEMORY. */
resurf_status resurfi_bvh_build(const resurf_allocator *alloc, const double *positions, size_t vertex_count,
                                const uint32_t *indices, size_t triangle_count, resurfi_bvh **out);
/* The same on `threads` threads (0 = all cores; see resurfi_thread_count). */
resurf_status resurfi_bvh_build_threads(const resurf_allocator *alloc, const double *positions, size_t vertex_count,
                                        const uint32_t *indices, size_t triangle_count, unsigned threads,
                                        resurfi_bvh **out);
void resurfi_bvh_free(resurfi_bvh *bvh); /* NULL is fine */
/* Number of triangles the tree holds (the valid ones). */
size_t resurfi_bvh_triangle_count(const resurfi_bvh *bvh);

/* The exact closest point on any triangle to p, searching within sqrt(max_dist2) (INFINITY = everywhere; a
 * triangle at exactly that distance counts). Returns the triangle index or UINT32_MAX when none lies within reach
 * (also for a non-finite p). Among triangles at exactly the same distance the lowest index wins, so the answer
 * equals a brute-force scan over all triangles with resurfi_closest_on_triangle. out_point, out_bary (barycentric
 * coordinates of the closest point, summing to 1) and out_dist2 may be NULL. Thread-safe (read-only). */
uint32_t resurfi_bvh_closest(const resurfi_bvh *bvh, vec3 p, double max_dist2, vec3 *out_point, double out_bary[3],
                             double *out_dist2);

/* resurfi_bvh_closest (everywhere) from a triangle near p: the same answer, found faster the nearer the hint (the
 * answer at a point a small step away, say). hint must be a triangle the tree holds (one it returned), or
 * UINT32_MAX for none. */
uint32_t resurfi_bvh_closest_near(const resurfi_bvh *bvh, vec3 p, uint32_t hint, vec3 *out_point, double out_bary[3],
                                  double *out_dist2);

/* Calls fn once for every triangle whose closest point to p is within sqrt(max_dist2), with that point, its
 * barycentrics and squared distance, in a deterministic (tree) order, not sorted by distance. fn returning nonzero
 * stops the walk; the return value is then 1, else 0. Thread-safe (read-only). For the restorer's searches of
 * every triangle near a point (ties at vertices and edges, the far test). */
int resurfi_bvh_within(const resurfi_bvh *bvh, vec3 p, double max_dist2,
                       int (*fn)(void *ctx, uint32_t triangle, vec3 point, const double bary[3], double dist2),
                       void *ctx);

/* Closest point on triangle (a, b, c) to p, with barycentrics (Ericson's region test; zero-area, collinear and
 * point-like triangles are handled as their edges; out_bary may be NULL, else it sums to 1 up to rounding). */
vec3 resurfi_closest_on_triangle(vec3 p, vec3 a, vec3 b, vec3 c, double out_bary[3]);

/* ---- measuring (metrics.c), for resurf_compare and the simplifier's report --------------------------------- */

/* Whether m carries texcoord set 0 (glTF's TEXCOORD_0). */
int resurfi_has_uv0(const resurf_mesh *m);
/* The texture-space distance between a's set-0 UV at barycentrics ba of triangle ta and b's at bb of tb. */
double resurfi_uv_distance(const resurf_mesh *a, uint32_t ta, const double ba[3], const resurf_mesh *b, uint32_t tb,
                           const double bb[3]);
/* The mean (summed in index order) and the 95th percentile (nearest rank) of n >= 1 values; sorts them. */
void resurfi_uv_summary(double *values, size_t n, double *out_mean, double *out_p95);

/* resurf_simplify_lods whose chain may end early: after level i's collapses (0-based), fn(ctx, i, its triangles,
 * its stop reason) returns nonzero when that level ends the chain. That level then gets no mesh (out_levels[i] and
 * later stay NULL) and a report that is not measured (distances NaN), and no later level is made: resurf_scene's
 * levels that do not help cost neither an output nor a measurement. */
typedef struct resurfi_chain_end {
    int (*fn)(void *ctx, size_t level, size_t triangles, resurf_simplify_stop stop);
    void *ctx;
} resurfi_chain_end;
/* What a simplification builds over its input before the first collapse and only reads afterwards: the restorer
 * over M and the tree over the input's triangles (the services over the original). Built once, they are lent to
 * every call on that input with options of the same restoring (restore, restore_options; threads and allocator
 * only say how they are built): a scene's levels made one by one and the scene budget's runs. The input must
 * outlive them; a call that borrows them does not depend on whether it did. */
typedef struct resurfi_simplify_services resurfi_simplify_services;
resurf_status resurfi_simplify_services_build(const resurf_mesh *in, const resurf_simplify_options *options,
                                              resurfi_simplify_services **out, resurf_error *error);
void resurfi_simplify_services_free(resurfi_simplify_services *services); /* NULL is fine */
/* With RESURF_RESTORE_MEASURED, the first pair's plain levels (simplify.c): what a RESURF_RESTORE_NONE run makes to
 * the targets the restored run reached, without the chain's end (levels[i] and reports[i], count entries each, the
 * caller's; NULL where not made). A scene that makes the RESTORE_NONE chain too starts from them. */
typedef struct resurfi_plain_half {
    resurf_mesh **levels;
    resurf_simplify_report *reports;
} resurfi_plain_half;
resurf_status resurfi_simplify_lods_until(const resurf_mesh *in, const double *ratios, size_t count,
                                          const resurf_simplify_options *options, const resurfi_chain_end *ends,
                                          const resurfi_simplify_services *services, resurfi_plain_half *half,
                                          resurf_mesh **out_levels, resurf_simplify_report *out_reports,
                                          resurf_error *error);
/* A report's measured figures as "not measured" (distances NaN; vertices, positions 0): a level that ended its
 * chain was not built. */
void resurfi_report_unmeasured(resurf_simplify_report *r);
/* resurf_simplify with services built by resurfi_simplify_services_build for `in` (or NULL: its own). */
resurf_status resurfi_simplify_lent(const resurf_mesh *in, const resurf_simplify_options *options,
                                    const resurfi_simplify_services *services, resurf_mesh **out,
                                    resurf_simplify_report *out_report, resurf_error *error);
/* A run kept alive between its levels: resurfi_simplify_run_to takes it to `target` triangles (at most the last
 * one) and returns the snapshot there with its measured report, the same mesh and report a call of that target
 * makes (resurfi_simplify_lent). One restoring mode (not RESURF_RESTORE_MEASURED); options as the call's, targets
 * given to run_to. The scene budget keeps a primitive's run to ask it for fewer triangles than before. */
typedef struct resurfi_simplify_run resurfi_simplify_run;
resurf_status resurfi_simplify_run_open(const resurf_mesh *in, const resurf_simplify_options *options,
                                        const resurfi_simplify_services *services, resurfi_simplify_run **out,
                                        resurf_error *error);
resurf_status resurfi_simplify_run_to(resurfi_simplify_run *run, size_t target, resurf_mesh **out,
                                      resurf_simplify_report *report, resurf_error *error);
size_t resurfi_simplify_run_reached(const resurfi_simplify_run *run); /* the last target; SIZE_MAX before one */
/* The run's next snapshots are measured only as far as needed to tell that scale times their two-sided maximum is
 * above bound: such a report has every maximum +INFINITY and every mean NaN. Any other is the full one. scale 0:
 * always the full one (the default). */
void resurfi_simplify_run_reject_above(resurfi_simplify_run *run, double scale, double bound);
void resurfi_simplify_run_free(resurfi_simplify_run *run);            /* NULL is fine */
/* A simplified surface's facet points, RESURFI_FACET_POINTS per triangle: its centroid, then the midpoints of its
 * edges that run from a lower to a higher vertex index (an edge two triangles share is taken once). Where a coarse
 * facet leaves the surface it spans, it leaves it most at those: a chord's sag peaks at its middle, a facet's at its
 * centre. Sets *out to point k (triangle k / RESURFI_FACET_POINTS) and returns 1, or returns 0 for an edge left to
 * the other triangle. */
enum { RESURFI_FACET_POINTS = 4 };
int resurfi_facet_point(const resurf_mesh *m, size_t k, vec3 *out);
/* Facet point k's triangle and barycentrics. */
void resurfi_facet_point_place(size_t k, uint32_t *t, double b[3]);

/* A side's maximum climbed to (max_climb.c): the points of largest distance, one a triangle, are offered as they
 * are measured; the climb moves each uphill inside its triangle and returns the largest distance found, at least
 * `max`. */
enum { RESURFI_MAX_STARTS = 4 };
typedef struct resurfi_max_start {
    double d, b[3];
    uint32_t t;
} resurfi_max_start;
typedef struct resurfi_max_starts {
    size_t count;
    resurfi_max_start start[RESURFI_MAX_STARTS]; /* by distance, largest first */
} resurfi_max_starts;
void resurfi_max_starts_offer(resurfi_max_starts *s, double d, uint32_t t, const double b[3]);
double resurfi_max_starts_climb(const resurfi_max_starts *s, const resurf_mesh *from, const resurfi_bvh *to,
                                double max);
/* The largest distance from `from` (samples area-uniform samples drawn from seed, then the vertices its triangles
 * use, as resurf_compare draws them, then with facet_points its facet points) to the surface under `to`; NaN for a
 * mesh without triangles. */
resurf_status resurfi_side_max(const resurf_allocator *alloc, const resurf_mesh *from, size_t samples, uint64_t seed,
                               int facet_points, const resurfi_bvh *to, unsigned threads, double *out_max);
/* The same to the surface of the mesh `to`, through a tree over only its triangles near `from` (side_nearby.c): the
 * same figure bit for bit, at a cost set by the triangles within `margin` of from's box (a guess of the answer; a
 * wrong one costs a second run, never a wrong figure). */
resurf_status resurfi_side_max_nearby(const resurf_allocator *alloc, const resurf_mesh *from, size_t samples,
                                      uint64_t seed, int facet_points, const resurf_mesh *to, double margin,
                                      unsigned threads, double *out_max);

/* ---- vertex normals (normals.c) ------------------------------------------------------------------------------ */

/* Unit vertex normals (3 * vertex_count) with the given scheme (see normals.c), on the index array as given (pass
 * welded indices to join seams). Faces with an out-of-range or repeated index, and faces of (nearly) zero area
 * (twice the area <= 1e-12 × longest edge²), contribute nothing; vertices of no such face get the zero vector.
 * RESURF_NORMALS_JET fits a weighted quadratic to the 2-ring (>= 6 neighbours, else or when ill-conditioned the
 * angle-weighted normal) on all cores; the result does not depend on the thread count.
 * RESURF_ERR_INVALID_ARGUMENT (NULL arrays with nonzero counts, unknown scheme), RESURF_ERR_OUT_OF_MEMORY. */
resurf_status resurfi_vertex_normals(const resurf_allocator *alloc, const double *positions, size_t vertex_count,
                                     const uint32_t *indices, size_t triangle_count, resurf_normal_scheme scheme,
                                     double *out_normals);
/* The same normals (scheme not JET) for vertices that split positions: corner k of triangle t is vertex
 * corner_vertex[3 t + k] (< vertex_count) at position tris[3 t + k] (a valid position index), every corner of a
 * vertex at the same position. Equal, bit for bit, to resurfi_vertex_normals on the positions copied per vertex
 * with corner_vertex as indices, without making that copy (the restorer's fans, split along creases). */
resurf_status resurfi_vertex_normals_split(const double *positions, const uint32_t *tris,
                                           const uint32_t *corner_vertex, size_t vertex_count,
                                           size_t triangle_count, resurf_normal_scheme scheme, double *out_normals);

/* ---- curvature (curvature.c) --------------------------------------------------------------------------------- */

/* Per-vertex principal curvatures (k1 >= k2) and directions, Rusinkiewicz 2004, against the given unit normals
 * (3 * vertex_count; exact normals give exact curvatures on spheres). Signs follow the normals: a convex closed
 * surface with outward normals has k > 0; negated normals negate k; the triangles' winding does not matter.
 * out_dir1/out_dir2 (3 * vertex_count, may be NULL) receive unit tangent directions with dir1 × dir2 = normal.
 * Vertices without a usable face (valid indices, nonzero area, nonzero normals) get k = 0 and zero directions.
 * RESURF_ERR_INVALID_ARGUMENT for NULL required arrays; RESURF_ERR_OUT_OF_MEMORY. */
resurf_status resurfi_principal_curvatures(const resurf_allocator *alloc, const double *positions, size_t vertex_count,
                                           const uint32_t *indices, size_t triangle_count, const double *normals,
                                           double *out_k1, double *out_k2, double *out_dir1, double *out_dir2);

/* ---- optimal direction (optdir.c) ---------------------------------------------------------------------------- */

/* Solves p = Σ b_j (p_j + t N_j) for barycentric b (Σ b_j = 1) and scalar t (docs/restoring.md §3): the line
 * through the foot p0 = Σ b_j p_j along the interpolated normal Σ b_j N_j passes through p. The cubic in t is
 * solved in closed form in units of the longest edge and polished by Newton steps. Returns the number of distinct real roots (0..3) in
 * roots[], ranked: roots inside the triangle (outside <= RESURFI_OPTDIR_INSIDE_TOL) first by |t|, then the others
 * by how far outside, ties by |t|. 0 roots for a triangle whose equation vanishes identically (zero area and equal
 * normals) or has no real solution. nj need not be unit vectors; t is not the distance to the triangle. */
typedef struct resurfi_optdir_root {
    double t;
    double bary[3];
    double outside; /* max(0, −min b_j): 0 inside the triangle */
} resurfi_optdir_root;
#define RESURFI_OPTDIR_INSIDE_TOL 1e-9
int resurfi_optdir_solve(vec3 p, const vec3 pj[3], const vec3 nj[3], resurfi_optdir_root roots[3]);
/* The root nearest t_guess, by Newton steps on the same cubic: for a point that moved a little since a root was
 * found (the restorer's later iterations). Returns 1 and the root (ranked fields as above) when Newton settles on
 * a genuine root, else 0 (then call resurfi_optdir_solve). */
int resurfi_optdir_near(vec3 p, const vec3 pj[3], const vec3 nj[3], double t_guess, resurfi_optdir_root *out);

/* ---- gliding-normal displacement (glide.c) ------------------------------------------------------------------- */

/* δ_j of formula (2), signed (docs/restoring.md §4): p' moves by δ along n_opt. side = +1 max-algorithm,
 * −1 min-algorithm (ignored by the normal-section variant, whose sign comes from the geometry). */
double resurfi_glide_paper(vec3 p, vec3 pj, vec3 nj, vec3 n_opt, int side);
double resurfi_glide_normal_section(vec3 p, vec3 pj, vec3 nj, vec3 n_opt);

/* ---- the restorer: M's geometry services, shared by restore.c and simplify/ (restore_setup.c, restore.c) ---- */

typedef struct resurfi_restorer resurfi_restorer;

/* What happened to one point (the last step's outcome when it took several). */
typedef enum resurfi_restore_outcome {
    RESURFI_RESTORED = 0,            /* with a root inside its triangle (or on a vertex of M already) */
    RESURFI_RESTORED_LEAST_OUTSIDE,  /* with the least-outside root (no triangle around had one inside) */
    RESURFI_RESTORED_BOUNDARY,       /* put on a boundary curve */
    RESURFI_RESTORED_CREASE,         /* put on a crease curve */
    RESURFI_LEFT_FAR,                /* farther than far_factor × the local edge length: unchanged */
    RESURFI_LEFT_OUTSIDE,            /* no root (or none inside with RESURF_OUTSIDE_KEEP) at the first step */
    RESURFI_LEFT_NONFINITE,          /* a non-finite point: unchanged */
} resurfi_restore_outcome;

/* Builds M's services (welded positions and topology, crease fans, normals, curvatures when the options need them,
 * feature curves, BVH) once. M's positions (and, without duplicate positions, its indices) are read in place:
 * `original` must stay unchanged while the restorer lives. Triangle indices are M's. The options are checked as resurf_restore() does (their progress is not used). Read-only afterwards: any
 * number of threads may query it at once. */
resurf_status resurfi_restorer_create(const resurf_mesh *original, const resurf_restore_options *options,
                                      resurfi_restorer **out, resurf_error *error);
/* The same, without the BVH when with_tree is 0: then only resurfi_restorer_point_walk and
 * resurfi_restorer_closest_walk find anything (the others leave every point, RESURFI_LEFT_FAR), and
 * resurfi_restorer_bvh returns NULL. About a third of the set-up's time and 60 bytes per triangle less. A caller
 * that has welded M's positions already (resurfi_weld_exact: remap, `distinct` positions) passes the weld;
 * remap NULL welds here. */
resurf_status resurfi_restorer_create_ex(const resurf_mesh *original, const resurf_restore_options *options,
                                         int with_tree, const uint32_t *remap, size_t distinct,
                                         resurfi_restorer **out, resurf_error *error);
void resurfi_restorer_free(resurfi_restorer *r); /* NULL is fine */

/* Restores one point onto S with the restorer's options (iterations, step, policies). out_point receives the
 * restored position (p itself when left alone). out_triangle and out_bary (each may be NULL) receive the triangle of
 * M and the barycentrics of the last step's root (for a point put on a feature curve or found on a vertex of M: its
 * closest triangle and closest point); out_triangle is UINT32_MAX when no triangle was reached (non-finite p). */
resurfi_restore_outcome resurfi_restorer_point(const resurfi_restorer *r, vec3 p, vec3 *out_point,
                                               uint32_t *out_triangle, double out_bary[3]);
/* The same with a triangle of M near p (e.g. the previous point's out_triangle; UINT32_MAX for none) that speeds
 * up the closest-triangle search. The result does not depend on the hint. */
resurfi_restore_outcome resurfi_restorer_point_near(const resurfi_restorer *r, vec3 p, uint32_t hint,
                                                    vec3 *out_point, uint32_t *out_triangle, double out_bary[3]);
/* The same, the closest triangle found by walking M from `start` (a triangle near p, e.g. where a neighbour of p
 * was restored) to the one p projects on (see walk_closest): the locally closest one, of the sheet `start` is on
 * where the shape is thin. No tree search. */
resurfi_restore_outcome resurfi_restorer_point_walk(const resurfi_restorer *r, vec3 p, uint32_t start,
                                                    vec3 *out_point, uint32_t *out_triangle, double out_bary[3]);
/* p's closest triangle of M as resurfi_restorer_point_walk finds it, from `start`, with the barycentrics of p's
 * closest point on it and the squared distance; UINT32_MAX for a non-finite p or no start. */
uint32_t resurfi_restorer_closest_walk(const resurfi_restorer *r, vec3 p, uint32_t start, double bary[3],
                                       double *dist2);

/* Asks the cache for what a walk from triangle t reads first, for a caller that knows its next starts a few points
 * ahead: stage 0 the corner ids, stage 1 (once those have arrived) the corners' positions, face lists and
 * normals. Any t is accepted; an out-of-range one is ignored. */
void resurfi_restorer_prefetch(const resurfi_restorer *r, uint32_t t, int stage);
/* The interpolated smooth unit normal of M at barycentrics bary of triangle t (crease-aware). */
vec3 resurfi_restorer_normal(const resurfi_restorer *r, uint32_t t, const double bary[3]);
/* The BVH over M (for closest-point queries by callers that already hold a restorer). */
const resurfi_bvh *resurfi_restorer_bvh(const resurfi_restorer *r);
/* q moved along the normal of M's triangle t until its height over t's plane is at most limit × the local edge
 * length there (t out of range: q itself). */
vec3 resurfi_restorer_limit_height(const resurfi_restorer *r, uint32_t t, vec3 q, double limit);
/* The local edge length of M at triangle t (the largest mean edge length of its corners); 0 for t out of range. */
double resurfi_restorer_edge_length(const resurfi_restorer *r, uint32_t t);

/* ---- skin influences (skin.c), for the simplifier's output and the glTF writer --------------------------------- */

/* The JOINTS_n / WEIGHTS_n pairs of a mesh's extras (both VEC4, matched by n), by extra index; at most
 * RESURFI_SKIN_MAX_SETS pairs (further ones stay plain extras). */
#define RESURFI_SKIN_MAX_SETS 8
typedef struct resurfi_skin_sets {
    unsigned count;
    size_t joints[RESURFI_SKIN_MAX_SETS], weights[RESURFI_SKIN_MAX_SETS];
} resurfi_skin_sets;
void resurfi_skin_find_sets(const resurf_mesh *m, resurfi_skin_sets *sets);
/* Is extra `extra` one of the pairs'? */
int resurfi_skin_owns(const resurfi_skin_sets *sets, size_t extra);
/* Output vertex ov of `out` (extras laid out like in's) gets the influences at the point with barycentrics bary of
 * the input triangle with corners `corner`: merged by joint, the strongest 4 per set, summing to 1, joints exact. */
void resurfi_skin_combine(const resurf_mesh *in, const resurfi_skin_sets *sets, const uint32_t corner[3],
                          const double bary[3], resurf_mesh *out, size_t ov);
/* The pairs of m as a file stores them, into arrays of 4 floats per vertex per set: weights summing to exactly one
 * whole of `units` (255 or 65535 for normalized integers, 0 for float), joints of zero weight 0. */
void resurfi_skin_snap(const resurf_mesh *m, const resurfi_skin_sets *sets, double units, float *const *joints_out,
                       float *const *weights_out);

/* ---- error quadrics (quadric.c), for the simplifier (simplify/) ---------------------------------------------- */

/* Garland–Heckbert quadric: Q(x) = xᵀ A x + 2 bᵀ x + c, a weighted sum of squared distances to planes, with the
 * total weight w (so sqrt(Q(x) / w) is an RMS distance). A is symmetric: a[0..5] = A00 A01 A02 A11 A12 A22. */
typedef struct resurfi_quadric {
    double a[6];
    double b[3];
    double c;
    double w;
} resurfi_quadric;

/* weight × (n·x + d)², n a unit vector (not checked: a non-unit n scales the distance). */
resurfi_quadric resurfi_quadric_plane(vec3 n, double d, double weight);
/* The plane of triangle (p0, p1, p2) weighted by its area; the zero quadric for a zero-area triangle. */
resurfi_quadric resurfi_quadric_triangle(vec3 p0, vec3 p1, vec3 p2);
/* q += r (weights too). Inline, like the two below: the simplifier calls them millions of times. */
static inline void resurfi_quadric_add(resurfi_quadric *q, const resurfi_quadric *r)
{
    for (int i = 0; i < 6; ++i)
        q->a[i] += r->a[i];
    for (int i = 0; i < 3; ++i)
        q->b[i] += r->b[i];
    q->c += r->c;
    q->w += r->w;
}
/* A·x. */
static inline vec3 resurfi_quadric_mul(const resurfi_quadric *q, vec3 x)
{
    const double *a = q->a;
    return v3(a[0] * x.x + a[1] * x.y + a[2] * x.z, a[1] * x.x + a[3] * x.y + a[4] * x.z,
              a[2] * x.x + a[4] * x.y + a[5] * x.z);
}
/* Q(x), clamped at 0 (rounding can make it slightly negative). */
static inline double resurfi_quadric_eval(const resurfi_quadric *q, vec3 x)
{
    double e = v3_dot(x, resurfi_quadric_mul(q, x)) + 2.0 * (q->b[0] * x.x + q->b[1] * x.y + q->b[2] * x.z) + q->c;
    return e > 0 ? e : 0;
}
/* The minimiser of Q nearest `around`. Where A is well conditioned (every pivot of its LDLᵀ factorisation above
 * RESURFI_QUADRIC_COND × trace A) this is the exact optimum. Otherwise Q is flat in some direction (a plane, a
 * cylinder, a straight border) and the step from `around` is damped there: (A + λI) δ = −(A·around + b) with
 * λ = RESURFI_QUADRIC_COND × trace A, plus one step of iterative refinement, so the point moves along the
 * well-determined directions only and stays near `around` along the flat ones. Returns 1 with the exact optimum, 2 with the damped one, 0 (and `around`) when A is
 * zero or the result is not finite. */
#define RESURFI_QUADRIC_COND 1e-3
int resurfi_quadric_optimum(const resurfi_quadric *q, vec3 around, vec3 *out);

#endif
