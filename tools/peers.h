/* The simplification benchmark's peers that are not C: CGAL's edge_collapse (tools/peer_cgal.cpp, C++, built only
 * when CGAL's headers are found) and the newest meshoptimizer from npm, run under node (tools/peer_meshopt_js.c
 * spawns tools/peer-meshopt.mjs). Benchmarks only: nothing here is ever linked into the library or the tests.
 *
 * Each call simplifies m to target_tris triangles (or as near as the peer gets), makes *out a new mesh of the
 * result (free it with resurf_mesh_free), sets *seconds to the wall time of the peer's simplification call alone
 * (not the conversion of the mesh into the peer's own structure, nor node's start-up) and returns 1; on failure it
 * writes why into why[why_size] and returns 0. A peer may also succeed with a note in why (why[0] != 0). */
#ifndef RESURF_TOOLS_PEERS_H
#define RESURF_TOOLS_PEERS_H

#include <stddef.h>

#include "resurf/resurf.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum peer_cgal_policy {
    PEER_CGAL_LINDSTROM_TURK,  /* LindstromTurk_cost + LindstromTurk_placement (CGAL's default) */
    PEER_CGAL_GARLAND_HECKBERT /* GarlandHeckbert_plane_policies: classic plane quadrics, optimal placement */
} peer_cgal_policy;

/* CGAL::Surface_mesh_simplification::edge_collapse on a Surface_mesh<Simple_cartesian<double>::Point_3>, stopped
 * when the face count reaches target_tris. A soup that is not a valid polygon mesh (non-manifold vertices or
 * edges, inconsistent orientation) is repaired first with CGAL's own orient_polygon_soup, which splits the
 * offending vertices; the note in why says so. */
int peer_cgal_simplify(const resurf_mesh *m, size_t target_tris, peer_cgal_policy policy, resurf_mesh **out,
                       double *seconds, char *why, size_t why_size);

typedef enum peer_meshopt_js_mode {
    PEER_MESHOPT_JS_SIMPLIFY, /* MeshoptSimplifier.simplify: the input's vertices, a new index buffer */
    PEER_MESHOPT_JS_UPDATE    /* MeshoptSimplifier.simplifyWithUpdate: moves the vertices it keeps */
} peer_meshopt_js_mode;

/* npm meshoptimizer's simplifier (wasm) under node, with the native call's settings: target index count
 * 3 × target_tris, target_error 1 (no bound), no flags. script is tools/peer-meshopt.mjs; node is found on PATH.
 * *seconds is the best of repeat calls, timed inside node around the call alone. */
int peer_meshopt_js(const char *script, const resurf_mesh *m, size_t target_tris, peer_meshopt_js_mode mode,
                    int repeat, resurf_mesh **out, double *seconds, char *why, size_t why_size);

#ifdef __cplusplus
}
#endif

#endif
