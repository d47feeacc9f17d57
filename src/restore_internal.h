/* What the restorer's two halves share: restore_setup.c builds the services over the original mesh M once (the
 * options, the weld, crease and boundary edges, fans, normals, feature curves, quiet and usable triangles), and
 * restore.c projects points with them. Not installed, not used elsewhere: callers use resurfi_restorer_* of
 * internal.h. */
#ifndef RESURF_RESTORE_INTERNAL_H
#define RESURF_RESTORE_INTERNAL_H

#include "internal.h"

enum { FEATURE_NONE = 0, FEATURE_BOUNDARY = 1, FEATURE_CREASE = 2 };

struct resurfi_restorer {
    resurf_restore_options opt;
    resurf_allocator alloc; /* a copy of the call's allocator: every block of the restorer comes from it */
    size_t position_count, triangle_count;
    const double *positions; /* M's positions: a position's id is its first vertex (see weld_original) */
    const uint32_t *tris;    /* 3 per triangle: position ids; own_tris, or M's indices when M has no duplicates */
    uint32_t *own_tris;
    resurfi_adjacency adj;  /* over welded ids; only the vertex-face lists are kept after set-up */
    resurfi_bvh *bvh;
    uint32_t *corner_split; /* 3 per triangle: the (vertex, fan) id of each corner */
    size_t split_count;
    double *split_normals;  /* 3 per split id */
    double *k1, *k2;        /* per split id (side rule CURVATURE with formula (2) only) */
    double *dir1, *dir2;    /* 3 per split id */
    double *local_length;   /* per position: mean length of its edges */
    uint8_t *edge_kind;     /* per edge: FEATURE_* (set-up only) */
    uint8_t *side_kind;     /* per triangle: FEATURE_* of side k (corners k, k + 1) in bits 2k, 2k + 1 */
    uint32_t *feature_offset, *feature_vertex; /* per position: the other ends of its feature edges (CSR) */
    uint8_t *feature_kind;  /* per feature slot: FEATURE_* of that edge */
    double *tangent;        /* 3 per position with two feature edges, at its first slot: the unit feature-curve
                               tangent, or 0 at a corner (so a position's tangent costs memory only on curves) */
    uint8_t *usable;        /* per triangle: has area and three corner normals (a root on it means something) */
    uint8_t *quiet;         /* per triangle: its corners' fans are closed discs turning gently (walk_closest) */
    /* set-up only */
    uint8_t *quiet_position;  /* per position: quiet_geometry_block's answer, for mark_quiet */
};

/* resurf_restore_options' checks (NULL: the defaults, fine), as resurf_restore() and resurfi_restorer_create make
 * them. */
resurf_status resurfi_restore_check_options(const resurf_restore_options *o, resurf_error *error);

static inline vec3 position(const resurfi_restorer *r, uint32_t v) { return v3_load(r->positions + 3 * (size_t)v); }

/* The corner of triangle t (attribute vertex indices in m) at position id v; the first such corner. */
static inline int corner_of(const resurfi_restorer *r, size_t t, uint32_t v)
{
    for (int k = 0; k < 3; ++k)
        if (r->tris[3 * t + k] == v)
            return k;
    return -1;
}

#endif
