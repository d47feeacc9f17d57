/* Analytic test shapes: meshes whose every vertex lies exactly on a known smooth surface, and that surface's exact
 * distance and normal. Used by the data generator, the tests and the benchmarks; not part of the library.
 *
 *   sphere    unit sphere, cube-sphere connectivity with jittered parameters (irregular, non-uniform)
 *   torus     R = 1, r = 0.4 around the z axis
 *   cubic     z = 0.5 (x³ − 3xy²) on [−1,1]²  (open; the paper's "cubic surface")
 *   cylinder  x² + y² = 1, z in [−1,1]  (open at both ends)
 *   saddle    z = x² − y² on [−1,1]²  (open)
 *   plane     z = 0 on [−1,1]²  (open)
 *   cube      the surface of the box [−1,1]³: flat faces, 12 sharp edges (90°), 8 corners (closed)
 *   capped-cylinder  x² + y² = 1, z in [−1,1], closed by the disks z = ±1: two circular creases (90°)
 * The last two have sharp features: their normal is that of the face (wall, cap) closest to p, the first in the
 * order above on a tie (a point on an edge).
 */
#ifndef RESURF_SHAPES_H
#define RESURF_SHAPES_H

#include <stdint.h>

#include "resurf/resurf.h"

typedef enum shape_kind {
    SHAPE_SPHERE,
    SHAPE_TORUS,
    SHAPE_CUBIC,
    SHAPE_CYLINDER,
    SHAPE_SADDLE,
    SHAPE_PLANE,
    SHAPE_CUBE,
    SHAPE_CAPPED_CYLINDER,
    SHAPE_COUNT
} shape_kind;

const char *shape_name(shape_kind kind);
/* SHAPE_COUNT when the name is unknown. */
shape_kind shape_from_name(const char *name);

/* A mesh of about `triangles` triangles (at least a few dozen) on the surface. jitter in [0, 0.45] moves each
 * interior parameter-grid point by up to that fraction of the grid spacing (0 = regular). Vertices are exactly on
 * the surface up to double rounding; closed shapes are watertight (shared vertices), orientation outward / +z.
 * with_normals attaches the exact unit normals. Deterministic for a seed. NULL only when out of memory. */
resurf_mesh *shape_mesh(shape_kind kind, size_t triangles, double jitter, uint64_t seed, int with_normals);

/* Unsigned distance from p to the (bounded) analytic surface; exact for sphere, torus, cylinder and plane,
 * Newton-accurate (to ~1e-15) for the graph surfaces near them. */
double shape_distance(shape_kind kind, const double p[3]);

/* Unit normal of the surface at its point closest to p (outward / +z side). */
void shape_normal(shape_kind kind, const double p[3], double out_normal[3]);

/* The point of the surface closest to p. */
void shape_closest(shape_kind kind, const double p[3], double out_point[3]);

/* A small deterministic random generator (splitmix64) for tests and tools. */
uint64_t shape_rand_u64(uint64_t *state);
double shape_rand_unit(uint64_t *state); /* uniform in [0, 1) */

#endif
