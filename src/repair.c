/* Mesh repair in place: drops invalid, degenerate and zero-area triangles, welds duplicate vertices and removes
 * unreferenced ones, keeping the relative order of the triangles and vertices that survive and every per-vertex
 * array (normals, texcoords, colors, extras) and per-triangle array (groups) consistent.
 * No paper. Definitions match resurf_mesh_validate(), so a repaired mesh validates without the dropped defects.
 *
 * Phases: decide everything first with temporary arrays (nothing in the mesh changes), then commit in place with
 * no further allocation. An allocation failure therefore leaves the mesh exactly as it was. */
#include <stdlib.h>
#include <string.h>

#include "internal.h"

resurf_repair_options resurf_repair_options_default(void)
{
    resurf_repair_options o;
    memset(&o, 0, sizeof o);
    o.struct_size = sizeof o;
    o.flags = RESURF_REPAIR_ALL;
    o.weld_tolerance_rel = 0;
    o.weld_ignore_attributes = 0;
    return o;
}

/* ---- attribute-aware grouping for the weld -------------------------------------------------------------------- */

/* Bits of a double / float with −0 folded onto +0, for hashing values that compare equal to the same key. */
static uint64_t double_bits(double x)
{
    if (x == 0)
        x = 0;
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static uint32_t float_bits(float x)
{
    if (x == 0)
        x = 0;
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static uint64_t mix(uint64_t h, uint64_t x)
{
    h ^= x + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h ^= h >> 31;
    h *= 0xbf58476d1ce4e5b9ull;
    h ^= h >> 29;
    return h;
}

/* Are two doubles the same value? Equal, or the same NaN bits (so that a vertex always equals itself). */
static int same_double(double a, double b) { return a == b || double_bits(a) == double_bits(b); }
static int same_float(float a, float b) { return a == b || float_bits(a) == float_bits(b); }

static int same_doubles(const double *a, const double *b, int n)
{
    for (int i = 0; i < n; ++i)
        if (!same_double(a[i], b[i]))
            return 0;
    return 1;
}

static uint64_t hash_vertex(const resurf_mesh *m, const uint32_t *pos_id, size_t v)
{
    uint64_t h = mix(0x1234567u, pos_id[v]);
    if (m->normals)
        for (int i = 0; i < 3; ++i)
            h = mix(h, double_bits(m->normals[3 * v + i]));
    for (unsigned k = 0; k < RESURF_MAX_TEXCOORD_SETS; ++k)
        if (m->texcoords[k])
            for (int i = 0; i < 2; ++i)
                h = mix(h, double_bits(m->texcoords[k][2 * v + i]));
    if (m->colors)
        for (int i = 0; i < 4; ++i)
            h = mix(h, double_bits(m->colors[4 * v + i]));
    for (size_t e = 0; e < m->extra_count; ++e) {
        const resurf_attribute *a = &m->extras[e];
        if (a->data)
            for (unsigned i = 0; i < a->components; ++i)
                h = mix(h, float_bits(a->data[(size_t)a->components * v + i]));
    }
    return h;
}

/* Do vertices v and w have the same position id and equal attributes? */
static int same_vertex(const resurf_mesh *m, const uint32_t *pos_id, size_t v, size_t w)
{
    if (pos_id[v] != pos_id[w])
        return 0;
    if (m->normals && !same_doubles(m->normals + 3 * v, m->normals + 3 * w, 3))
        return 0;
    for (unsigned k = 0; k < RESURF_MAX_TEXCOORD_SETS; ++k)
        if (m->texcoords[k] && !same_doubles(m->texcoords[k] + 2 * v, m->texcoords[k] + 2 * w, 2))
            return 0;
    if (m->colors && !same_doubles(m->colors + 4 * v, m->colors + 4 * w, 4))
        return 0;
    for (size_t e = 0; e < m->extra_count; ++e) {
        const resurf_attribute *a = &m->extras[e];
        if (!a->data)
            continue;
        for (unsigned i = 0; i < a->components; ++i)
            if (!same_float(a->data[(size_t)a->components * v + i], a->data[(size_t)a->components * w + i]))
                return 0;
    }
    return 1;
}

/* group_first[v] = lowest vertex with v's position id and attributes (open addressing over vertex numbers). */
static resurf_status group_by_attributes(const resurf_allocator *alloc, const resurf_mesh *m, const uint32_t *pos_id,
                                         uint32_t *group_first)
{
    const size_t nv = m->vertex_count;
    size_t size = 16;
    while (size < 2 * nv)
        size *= 2;
    uint32_t *slot = resurfi_calloc(alloc, size, sizeof *slot); /* vertex + 1; 0 = empty */
    if (!slot)
        return RESURF_ERR_OUT_OF_MEMORY;
    for (size_t v = 0; v < nv; ++v) {
        size_t i = (size_t)hash_vertex(m, pos_id, v) & (size - 1);
        for (;; i = (i + 1) & (size - 1)) {
            if (!slot[i]) {
                slot[i] = (uint32_t)v + 1;
                group_first[v] = (uint32_t)v;
                break;
            }
            if (same_vertex(m, pos_id, slot[i] - 1, v)) {
                group_first[v] = slot[i] - 1;
                break;
            }
        }
    }
    resurfi_free(alloc, slot);
    return RESURF_OK;
}

/* ---- commit helpers -------------------------------------------------------------------------------------------- */

/* Moves the kept elements of an array of `width`-byte elements to the front, in order. */
static void compact_array(void *data, size_t width, const uint32_t *new_id, size_t count)
{
    unsigned char *p = data;
    if (!p)
        return;
    for (size_t v = 0; v < count; ++v)
        if (new_id[v] != UINT32_MAX && new_id[v] != v)
            memmove(p + new_id[v] * width, p + v * width, width);
}

/* Shrinks an owned array to its new size; a failed shrink keeps the larger, still valid block. */
static void *shrink(const resurf_allocator *alloc, void *p, size_t count, size_t width)
{
    if (!p)
        return NULL;
    void *q = resurfi_realloc(alloc, p, count, width);
    return q ? q : p;
}

/* Are the three corners of tri finite in the given positions? */
static int corners_finite(const double *positions_of, const uint32_t *tri)
{
    for (int i = 0; i < 3; ++i)
        if (!v3_finite(v3_load(positions_of + 3 * (size_t)tri[i])))
            return 0;
    return 1;
}

/* Why a triangle is dropped (0 = kept). */
enum { KEEP = 0, DROP_INVALID, DROP_DEGENERATE, DROP_ZERO_AREA };

resurf_status resurf_mesh_repair(resurf_mesh *mesh, const resurf_repair_options *options,
                                 resurf_repair_report *out_report, resurf_error *error)
{
    RESURFI_CHECK_OPTIONS_ALLOC(options, resurf_repair_options, error);
    const resurf_repair_options o = options ? *options : resurf_repair_options_default();
    if (o.flags & ~(unsigned)RESURF_REPAIR_ALL)
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "unknown repair flags 0x%x",
                             o.flags & ~(unsigned)RESURF_REPAIR_ALL);
    if (!(o.weld_tolerance_rel >= 0) || !isfinite(o.weld_tolerance_rel))
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS,
                             "weld_tolerance_rel must be a finite number >= 0 (got %g)", o.weld_tolerance_rel);
    if (!mesh)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "mesh is NULL");
    const size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
    if ((nv && !mesh->positions) || (nt && !mesh->indices))
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "mesh has counts but no positions or indices");
    if (nv > UINT32_MAX || nt > UINT32_MAX)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "more than 2^32 vertices or triangles");

    resurf_repair_report report;
    memset(&report, 0, sizeof report);
    const int weld = (o.flags & RESURF_REPAIR_WELD) != 0;
    const resurf_allocator *alloc = resurfi_allocator_of(o.allocator, mesh); /* the temporaries */
    const resurf_allocator *own = &mesh->allocator;                          /* the mesh's arrays */
    uint8_t *drop = resurfi_calloc(alloc, nt, 1);
    uint32_t *pos_id = resurfi_alloc(alloc, nv, sizeof *pos_id);
    uint32_t *first_of_pos = resurfi_alloc(alloc, nv, sizeof *first_of_pos);
    uint32_t *group_first = resurfi_alloc(alloc, nv, sizeof *group_first);
    uint32_t *new_id = resurfi_alloc(alloc, nv, sizeof *new_id);
    uint8_t *referenced = resurfi_calloc(alloc, nv, 1);
    double *snapped = NULL; /* positions after the weld's snap: read-only copy used by the decisions */
    resurf_status status = RESURF_ERR_OUT_OF_MEMORY;
    int error_set = 0; /* a failing step below that fills *error itself sets this */
    if (!drop || !pos_id || !first_of_pos || !group_first || !new_id || !referenced)
        goto done;

    /* 1. Invalid triangles: an index out of range or a non-finite corner. */
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *tri = mesh->indices + 3 * t;
        int bad = tri[0] >= nv || tri[1] >= nv || tri[2] >= nv || !corners_finite(mesh->positions, tri);
        if (bad && (o.flags & RESURF_REPAIR_DROP_INVALID))
            drop[t] = DROP_INVALID;
    }

    /* 2. Position ids (welded within the tolerance, or exact), and each vertex's merge target. */
    size_t position_count = 0;
    if (weld) {
        status = resurfi_weld_map(alloc, mesh, o.weld_tolerance_rel, pos_id, &position_count, error);
        error_set = 1;
    } else {
        status = resurfi_weld_exact(alloc, mesh->positions, nv, pos_id, &position_count);
    }
    if (status != RESURF_OK)
        goto done;
    error_set = 0;
    status = RESURF_ERR_OUT_OF_MEMORY;
    for (size_t v = 0, seen = 0; v < nv; ++v)
        if (pos_id[v] == seen)
            first_of_pos[seen++] = (uint32_t)v;
    /* A tolerance weld moves every vertex onto its cluster's first position, seams included, so no crack stays
     * between vertices kept apart by their attributes. */
    if (!(snapped = resurfi_alloc(alloc, nv, 3 * sizeof *snapped)))
        goto done;
    for (size_t v = 0; v < nv; ++v) {
        size_t from = weld ? first_of_pos[pos_id[v]] : v;
        memcpy(snapped + 3 * v, mesh->positions + 3 * from, 3 * sizeof(double));
    }
    if (!weld) {
        for (size_t v = 0; v < nv; ++v)
            group_first[v] = (uint32_t)v;
    } else if (o.weld_ignore_attributes) {
        for (size_t v = 0; v < nv; ++v)
            group_first[v] = first_of_pos[pos_id[v]];
    } else if ((status = group_by_attributes(alloc, mesh, pos_id, group_first)) != RESURF_OK) {
        goto done;
    }

    /* 3. Degenerate triangles: a repeated index or position after the weld. Triangles with an out-of-range index
     * are left to DROP_INVALID. */
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *tri = mesh->indices + 3 * t;
        if (drop[t] || tri[0] >= nv || tri[1] >= nv || tri[2] >= nv)
            continue;
        uint32_t a = pos_id[tri[0]], b = pos_id[tri[1]], c = pos_id[tri[2]];
        if ((a == b || b == c || a == c) && (o.flags & RESURF_REPAIR_DROP_DEGENERATE))
            drop[t] = DROP_DEGENERATE;
    }

    /* 4. Zero-area triangles, against the diagonal of what survived so far (as validation of the result sees it). */
    if (o.flags & RESURF_REPAIR_DROP_ZERO_AREA) {
        vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
        for (size_t t = 0; t < nt; ++t) {
            const uint32_t *tri = mesh->indices + 3 * t;
            if (drop[t] || tri[0] >= nv || tri[1] >= nv || tri[2] >= nv)
                continue;
            for (int i = 0; i < 3; ++i) {
                vec3 p = v3_load(snapped + 3 * (size_t)tri[i]);
                if (v3_finite(p))
                    lo = v3_min(lo, p), hi = v3_max(hi, p);
            }
        }
        double diagonal = v3_finite(lo) ? v3_dist(lo, hi) : 0;
        double limit = 1e-14 * diagonal * diagonal;
        for (size_t t = 0; t < nt; ++t) {
            const uint32_t *tri = mesh->indices + 3 * t;
            if (drop[t] || tri[0] >= nv || tri[1] >= nv || tri[2] >= nv || !corners_finite(snapped, tri))
                continue;
            uint32_t a = pos_id[tri[0]], b = pos_id[tri[1]], c = pos_id[tri[2]];
            if (a == b || b == c || a == c)
                continue; /* degenerate, not zero-area: kept when DROP_DEGENERATE is off */
            vec3 pa = v3_load(snapped + 3 * (size_t)tri[0]), pb = v3_load(snapped + 3 * (size_t)tri[1]),
                 pc = v3_load(snapped + 3 * (size_t)tri[2]);
            if (v3_len(v3_tri_cross(pa, pb, pc)) <= limit)
                drop[t] = DROP_ZERO_AREA;
        }
    }

    /* 5. Which vertices survive: the first of each weld group, if some kept triangle refers to it (or if
     * unreferenced vertices stay). */
    size_t kept_triangles = 0;
    for (size_t t = 0; t < nt; ++t) {
        report.dropped_invalid += drop[t] == DROP_INVALID;
        report.dropped_degenerate += drop[t] == DROP_DEGENERATE;
        report.dropped_zero_area += drop[t] == DROP_ZERO_AREA;
        if (drop[t])
            continue;
        ++kept_triangles;
        for (int i = 0; i < 3; ++i) {
            uint32_t v = mesh->indices[3 * t + i];
            if (v < nv)
                referenced[group_first[v]] = 1;
        }
    }
    size_t kept_vertices = 0;
    for (size_t v = 0; v < nv; ++v) {
        if (group_first[v] != v) {
            report.welded_vertices++;
            new_id[v] = UINT32_MAX;
        } else if (!referenced[v] && (o.flags & RESURF_REPAIR_REMOVE_UNREFERENCED)) {
            report.removed_unreferenced++;
            new_id[v] = UINT32_MAX;
        } else {
            new_id[v] = (uint32_t)kept_vertices++;
        }
    }

    /* 6. Commit: nothing below allocates or fails. */
    if (weld)
        memcpy(mesh->positions, snapped, nv * 3 * sizeof(double));
    size_t out = 0;
    for (size_t t = 0; t < nt; ++t) {
        if (drop[t])
            continue;
        for (int i = 0; i < 3; ++i) {
            uint32_t v = mesh->indices[3 * t + i];
            /* An out-of-range index (kept when DROP_INVALID is off) moves down by the number of vertices removed:
             * still out of range, and untouched when no vertex goes. */
            mesh->indices[3 * out + i] = v < nv ? new_id[group_first[v]] : (uint32_t)(v - (nv - kept_vertices));
        }
        if (mesh->triangle_groups)
            mesh->triangle_groups[out] = mesh->triangle_groups[t];
        ++out;
    }
    compact_array(mesh->positions, 3 * sizeof(double), new_id, nv);
    compact_array(mesh->normals, 3 * sizeof(double), new_id, nv);
    for (unsigned k = 0; k < RESURF_MAX_TEXCOORD_SETS; ++k)
        compact_array(mesh->texcoords[k], 2 * sizeof(double), new_id, nv);
    compact_array(mesh->colors, 4 * sizeof(double), new_id, nv);
    for (size_t e = 0; e < mesh->extra_count; ++e)
        compact_array(mesh->extras[e].data, mesh->extras[e].components * sizeof(float), new_id, nv);
    mesh->triangle_count = kept_triangles;
    mesh->vertex_count = kept_vertices;
    if (kept_triangles < nt) {
        mesh->indices = shrink(own, mesh->indices, kept_triangles, 3 * sizeof(uint32_t));
        mesh->triangle_groups = shrink(own, mesh->triangle_groups, kept_triangles, sizeof(uint32_t));
    }
    if (kept_vertices < nv) {
        mesh->positions = shrink(own, mesh->positions, kept_vertices, 3 * sizeof(double));
        mesh->normals = shrink(own, mesh->normals, kept_vertices, 3 * sizeof(double));
        for (unsigned k = 0; k < RESURF_MAX_TEXCOORD_SETS; ++k)
            mesh->texcoords[k] = shrink(own, mesh->texcoords[k], kept_vertices, 2 * sizeof(double));
        mesh->colors = shrink(own, mesh->colors, kept_vertices, 4 * sizeof(double));
        for (size_t e = 0; e < mesh->extra_count; ++e) {
            resurf_attribute *a = &mesh->extras[e];
            a->data = shrink(own, a->data, kept_vertices, a->components * sizeof(float));
        }
    }
    status = RESURF_OK;

done:
    resurfi_free(alloc, drop);
    resurfi_free(alloc, pos_id);
    resurfi_free(alloc, first_of_pos);
    resurfi_free(alloc, group_first);
    resurfi_free(alloc, new_id);
    resurfi_free(alloc, referenced);
    resurfi_free(alloc, snapped);
    if (status != RESURF_OK) {
        if (!error_set)
            resurfi_error(error, status, "repairing a mesh of %zu vertices and %zu triangles: %s", nv, nt,
                          resurf_status_string(status));
        return status;
    }
    if (out_report)
        *out_report = report;
    resurfi_clear_error(error);
    return RESURF_OK;
}
