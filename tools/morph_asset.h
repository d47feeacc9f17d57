/* An analytic morph for tests and the corpus: the unit sphere (tools/shapes.h) with one morph target that makes it
 * the ellipsoid of semi-axes a (x²/a₀² + y²/a₁² + z²/a₂² = 1): vertex p moves by (a₀p₀ − p₀, a₁p₁ − p₁, a₂p₂ − p₂),
 * so at morph weight w the vertices lie on the ellipsoid of semi-axes 1 + w(aᵢ − 1) (the target is linear in p:
 * the morph at any weight is the sphere scaled per axis). Not part of the library. */
#ifndef RESURF_MORPH_ASSET_H
#define RESURF_MORPH_ASSET_H

#include <stddef.h>
#include <stdint.h>

#include "resurf/resurf.h"

/* The ellipsoid of the bundled asset (data/morph-sphere.glb) and of the tests: stretched along x, squashed along z. */
static const double morph_asset_axes[3] = {1.5, 1.0, 0.6};

/* The sphere of shape_mesh(SHAPE_SPHERE, triangles, jitter, seed, normals) with the extras "targets[0].POSITION"
 * (the deltas above) and "targets[0].NORMAL" (the ellipsoid's unit normal at the moved vertex minus the sphere's).
 * NULL when out of memory. */
resurf_mesh *morph_sphere_mesh(size_t triangles, double jitter, uint64_t seed, const double axes[3]);

/* The sphere of shape_mesh(SHAPE_SPHERE, triangles, jitter, seed, 1) with one bulge target, "targets[0].POSITION":
 * δ(p) = height · exp(−|p − (0, 0, 1)|² / width²) p, a bump around the north pole (not linear in p, so a coarse
 * level cannot show it exactly: what morph_weight prices). NULL when out of memory. */
resurf_mesh *morph_bulge_mesh(size_t triangles, double jitter, uint64_t seed, double height, double width);

/* The semi-axes at morph weight w: 1 + w(aᵢ − 1). */
void morph_axes_at(const double axes[3], double w, double out[3]);

/* Unsigned distance from p to the ellipsoid of semi-axes a (all > 0): exact up to bisection (the closest point
 * x = (aᵢ² pᵢ / (t + aᵢ²)) with t the root of Σ (aᵢ pᵢ / (t + aᵢ²))² = 1), for points off the ellipsoid's medial
 * disc (any point within min aᵢ² / max aᵢ of the surface, and every point outside). */
double ellipsoid_distance(const double a[3], const double p[3]);

/* A .glb of mesh m (as morph_sphere_mesh makes it: normals and the two target extras) with one node, mesh weights
 * [0], the target named "ellipsoid" (extras.targetNames) and an animation that drives the weight 0 → 1 → 0 over
 * two seconds. malloc'ed; NULL when out of memory. */
unsigned char *morph_glb(const resurf_mesh *m, size_t *out_size);

#endif
