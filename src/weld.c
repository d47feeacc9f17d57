/* Position welding: which attribute vertices share a position, exactly (a hash of the coordinate bits) or within
 * a tolerance (a uniform grid over the exactly-welded positions). No paper; the grid is the textbook spatial hash
 * (Teschner et al. 2003, "Optimized Spatial Hashing for Collision Detection of Deformable Objects").
 *
 * Rule for the tolerance weld, chosen to be deterministic and free of chaining: the distinct positions are visited
 * in order of first appearance; each joins the lowest-numbered earlier cluster whose *representative* (the first
 * position of that cluster) lies closer than the tolerance, or else starts a cluster of its own. So every member is
 * within the tolerance of its representative (a cluster's diameter stays below twice the tolerance, however dense
 * the points), and the outcome depends on the vertex order only through which position comes first. */
#include <stdlib.h>
#include <string.h>

#include "hash.h"
#include "internal.h"

/* The bits of a coordinate with −0.0 folded onto +0.0, so that the two zeros weld (they compare equal). */
static uint64_t coord_bits(double x)
{
    if (x == 0)
        x = 0; /* turns −0.0 into +0.0 */
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static uint64_t hash_position(const double *p)
{
    uint64_t h = resurfi_mix64(coord_bits(p[0]) + RESURFI_GOLDEN_GAMMA);
    h = resurfi_mix64(h ^ coord_bits(p[1]));
    return resurfi_mix64(h ^ coord_bits(p[2]) ^ 0x632be59bd9b4e019ull);
}

/* Do p and q hold the same position? Equal bits after folding the zeros: a NaN welds only with the same NaN. */
static int same_position(const double *p, const double *q)
{
    return coord_bits(p[0]) == coord_bits(q[0]) && coord_bits(p[1]) == coord_bits(q[1]) &&
           coord_bits(p[2]) == coord_bits(q[2]);
}

/* The smallest power of two >= 2n (load factor <= 1/2 keeps linear probing short). */
static size_t table_size_for(size_t n)
{
    size_t size = 16;
    while (size < 2 * n)
        size *= 2;
    return size;
}

resurf_status resurfi_weld_exact(const resurf_allocator *alloc, const double *positions, size_t vertex_count,
                                 uint32_t *remap, size_t *out_count)
{
    if (vertex_count > UINT32_MAX || (vertex_count && (!positions || !remap)))
        return RESURF_ERR_INVALID_ARGUMENT;
    size_t size = table_size_for(vertex_count), mask = size - 1;
    /* Each slot holds the first vertex of a position (+1; 0 marks an empty slot). */
    uint32_t *slot = resurfi_calloc(alloc, size, sizeof *slot);
    if (!slot)
        return RESURF_ERR_OUT_OF_MEMORY;
    size_t count = 0;
    for (size_t v = 0; v < vertex_count; ++v) {
        const double *p = positions + 3 * v;
        size_t i = (size_t)hash_position(p) & mask;
        for (;; i = (i + 1) & mask) {
            if (slot[i] == 0) {
                slot[i] = (uint32_t)v + 1;
                remap[v] = (uint32_t)count++;
                break;
            }
            uint32_t w = slot[i] - 1;
            if (same_position(positions + 3 * (size_t)w, p)) {
                remap[v] = remap[w];
                break;
            }
        }
    }
    resurfi_free(alloc, slot);
    if (out_count)
        *out_count = count;
    return RESURF_OK;
}

/* Grows the box [lo, hi] by the finite point p; returns whether p was finite. Plain comparisons, not fmin/fmax,
 * because this runs over every index of large meshes. */
static int grow_box(double lo[3], double hi[3], const double *p)
{
    if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
        return 0;
    for (int a = 0; a < 3; ++a) {
        lo[a] = p[a] < lo[a] ? p[a] : lo[a];
        hi[a] = p[a] > hi[a] ? p[a] : hi[a];
    }
    return 1;
}

double resurfi_finite_diagonal(const resurf_mesh *mesh)
{
    if (!mesh)
        return 0;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    size_t n = 0;
    for (size_t i = 0; i < 3 * mesh->triangle_count; ++i) {
        uint32_t v = mesh->indices[i];
        if (v < mesh->vertex_count)
            n += grow_box(lo, hi, mesh->positions + 3 * (size_t)v);
    }
    if (n == 0)
        for (size_t v = 0; v < mesh->vertex_count; ++v)
            n += grow_box(lo, hi, mesh->positions + 3 * v);
    if (n == 0)
        return 0;
    double d = v3_dist(v3_load(lo), v3_load(hi));
    return isfinite(d) ? d : 0; /* finite coordinates near DBL_MAX can still overflow the length */
}

/* ---- tolerance weld: a grid hash over cluster representatives ------------------------------------------------ */

typedef struct cell_key {
    int64_t c[3];
} cell_key;

typedef struct grid {
    size_t mask;
    cell_key *keys;
    uint32_t *head;    /* per slot: first representative in that cell (+1; 0 = empty slot) */
    uint32_t *next;    /* per distinct position: next representative of the same cell (+1; 0 = end) */
    vec3 origin;
    double inv_cell;
} grid;

/* Cell coordinate of x along one axis. Clamped so that absurdly small tolerances cannot overflow: clamping is
 * monotone and keeps neighbours within one cell, so it only crowds cells, never loses a match. */
static int64_t cell_coord(double x, double origin, double inv_cell)
{
    double c = floor((x - origin) * inv_cell);
    const double limit = 4.0e18;
    if (!(c > -limit))
        c = -limit;
    if (c > limit)
        c = limit;
    return (int64_t)c;
}

/* Teschner's prime-multiply hash, with one final mix: 8 probes per point make this the weld's hot spot. */
static uint64_t hash_cell(const cell_key *k)
{
    uint64_t h = (uint64_t)k->c[0] * 73856093ull ^ (uint64_t)k->c[1] * 19349663ull ^ (uint64_t)k->c[2] * 83492791ull;
    h ^= h >> 32;
    h *= 0xd6e8feb86659fd93ull;
    return h ^ (h >> 32);
}

/* The slot of cell k: where it is, or the empty slot where it would go. */
static size_t grid_find(const grid *g, const cell_key *k)
{
    size_t i = (size_t)hash_cell(k) & g->mask;
    while (g->head[i] &&
           (g->keys[i].c[0] != k->c[0] || g->keys[i].c[1] != k->c[1] || g->keys[i].c[2] != k->c[2]))
        i = (i + 1) & g->mask;
    return i;
}

/* Clusters the distinct positions `unique` (count of them, finite or not) into cluster ids numbered by first
 * appearance. Non-finite positions stay clusters of their own (they have no place in a grid). */
static resurf_status cluster_positions(const resurf_allocator *alloc, const double *unique, size_t count,
                                       double tolerance, uint32_t *cluster, size_t *out_clusters)
{
    grid g = {0};
    size_t size = table_size_for(count);
    g.mask = size - 1;
    g.keys = resurfi_alloc(alloc, size, sizeof *g.keys);
    g.head = resurfi_calloc(alloc, size, sizeof *g.head);
    g.next = resurfi_alloc(alloc, count, sizeof *g.next);
    if (!g.keys || !g.head || !g.next) {
        resurfi_free(alloc, g.keys);
        resurfi_free(alloc, g.head);
        resurfi_free(alloc, g.next);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (size_t i = 0; i < count; ++i) {
        vec3 p = v3_load(unique + 3 * i);
        if (v3_finite(p))
            lo = v3_min(lo, p), hi = v3_max(hi, p);
    }
    g.origin = v3_finite(lo) ? lo : v3(0, 0, 0);
    vec3 span = v3_finite(lo) ? v3_sub(hi, lo) : v3(0, 0, 0);
    double extent = fmax(span.x, fmax(span.y, span.z));
    /* Cells a little over twice the tolerance: the ball of radius tol around p then meets at most 2 cells per
     * axis, p's own and the neighbour on the side of the cell p is nearer to, so 8 cells hold every candidate.
     * The 1% margin and the floor of extent / 2^36 (at most 2^36 cells per axis) keep the rounding of the cell
     * coordinates far below that margin, so a point near a cell's middle cannot be misfiled. */
    double cell = fmax(2.02 * tolerance, extent * 0x1p-36);
    g.inv_cell = isfinite(cell) && cell > 0 ? 1.0 / cell : 0;
    const double tol2 = tolerance * tolerance;
    size_t clusters = 0;
    for (size_t i = 0; i < count; ++i) {
        vec3 p = v3_load(unique + 3 * i);
        if (!v3_finite(p)) {
            cluster[i] = (uint32_t)clusters++;
            continue;
        }
        const double x[3] = {p.x, p.y, p.z}, o[3] = {g.origin.x, g.origin.y, g.origin.z};
        int64_t base[3], step[3];
        for (int a = 0; a < 3; ++a) {
            base[a] = cell_coord(x[a], o[a], g.inv_cell);
            double frac = (x[a] - o[a]) * g.inv_cell - (double)base[a];
            step[a] = frac < 0.5 ? -1 : 1;
        }
        uint32_t best = UINT32_MAX; /* lowest representative (a distinct-position index) within the tolerance */
        for (int corner = 0; corner < 8; ++corner) {
            cell_key k;
            for (int a = 0; a < 3; ++a)
                k.c[a] = base[a] + ((corner >> a) & 1 ? step[a] : 0);
            size_t s = grid_find(&g, &k);
            for (uint32_t r = g.head[s]; r; r = g.next[r - 1]) {
                uint32_t rep = r - 1;
                if (rep < best && v3_dist2(v3_load(unique + 3 * (size_t)rep), p) < tol2)
                    best = rep;
            }
        }
        if (best != UINT32_MAX) {
            cluster[i] = cluster[best];
            continue;
        }
        cluster[i] = (uint32_t)clusters++;
        cell_key k = {{base[0], base[1], base[2]}};
        size_t s = grid_find(&g, &k);
        if (!g.head[s])
            g.keys[s] = k;
        g.next[i] = g.head[s];
        g.head[s] = (uint32_t)i + 1;
    }
    resurfi_free(alloc, g.keys);
    resurfi_free(alloc, g.head);
    resurfi_free(alloc, g.next);
    *out_clusters = clusters;
    return RESURF_OK;
}

resurf_status resurf_mesh_weld_map(const resurf_mesh *mesh, double tolerance_rel, uint32_t *out_position_of_vertex,
                                   size_t *out_position_count, resurf_error *error)
{
    return resurfi_weld_map(mesh ? &mesh->allocator : NULL, mesh, tolerance_rel, out_position_of_vertex,
                            out_position_count, error);
}

resurf_status resurfi_weld_map(const resurf_allocator *alloc, const resurf_mesh *mesh, double tolerance_rel,
                               uint32_t *out_position_of_vertex, size_t *out_position_count, resurf_error *error)
{
    if (!mesh || (!out_position_of_vertex && mesh->vertex_count) || (mesh->vertex_count && !mesh->positions))
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "mesh or out_position_of_vertex is NULL");
    if (!(tolerance_rel >= 0) || !isfinite(tolerance_rel))
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT,
                             "weld tolerance_rel must be a finite number >= 0 (got %g)", tolerance_rel);
    const size_t n = mesh->vertex_count;
    size_t unique_count = 0;
    resurf_status status = resurfi_weld_exact(alloc, mesh->positions, n, out_position_of_vertex, &unique_count);
    if (status != RESURF_OK)
        return resurfi_error(error, status, "welding %zu vertices: %s", n, resurf_status_string(status));
    const double tolerance = tolerance_rel * resurfi_finite_diagonal(mesh);
    if (tolerance > 0 && unique_count > 1) {
        /* Cluster the distinct positions (each stored once, in order of first appearance), then map through. */
        double *unique = resurfi_alloc(alloc, unique_count, 3 * sizeof(double));
        uint32_t *cluster = resurfi_alloc(alloc, unique_count, sizeof *cluster);
        status = RESURF_ERR_OUT_OF_MEMORY;
        size_t clusters = 0;
        if (unique && cluster) {
            size_t filled = 0;
            for (size_t v = 0; v < n; ++v)
                if (out_position_of_vertex[v] == filled)
                    memcpy(unique + 3 * filled++, mesh->positions + 3 * v, 3 * sizeof(double));
            status = cluster_positions(alloc, unique, unique_count, tolerance, cluster, &clusters);
        }
        if (status == RESURF_OK) {
            for (size_t v = 0; v < n; ++v)
                out_position_of_vertex[v] = cluster[out_position_of_vertex[v]];
            unique_count = clusters;
        }
        resurfi_free(alloc, unique);
        resurfi_free(alloc, cluster);
        if (status != RESURF_OK)
            return resurfi_error(error, status, "out of memory welding %zu vertices", n);
    }
    if (out_position_count)
        *out_position_count = unique_count;
    resurfi_clear_error(error);
    return RESURF_OK;
}
