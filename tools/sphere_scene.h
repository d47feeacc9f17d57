/* A scene of many small meshes for the benchmarks (tools/sphere_scene.c), as a kit of props exports them: `count`
 * latitude-longitude spheres, each its own mesh and node, on a grid of 20 a row. A sphere has `around` vertices a
 * ring and `rings` bands, 2 × around × (rings − 1) triangles, with each pole a ring of copies as exporters write
 * them: the north pole's copies coincide (sin 0 = 0), the south pole's lie a rounding apart (sin π is not 0 in
 * floating point). Radii 0.4 to 0.6 and a bulge of up to 10% vary with the node, and the bulge turns by 0.1 radian
 * a node, so no two meshes are the same. Positions are floats, indices 16-bit. Not part of the library. */
#ifndef RESURF_SPHERE_SCENE_H
#define RESURF_SPHERE_SCENE_H

#include <stddef.h>

/* The .glb, malloc'ed; NULL when out of memory or when a sphere would need more than 65,536 vertices. */
unsigned char *sphere_scene_glb(unsigned count, unsigned around, unsigned rings, size_t *out_size);

#endif
