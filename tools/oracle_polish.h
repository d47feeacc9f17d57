/* An oracle for the benchmark (tools/oracle_polish.c), not part of the library: a simplified mesh of an analytic
 * shape polished against the shape itself, which no simplifier has. Edges are flipped and vertices moved (along
 * the surface normal and across it) wherever that lowers the mesh's area-weighted mean distance to the analytic
 * surface, until nothing does. What is left is what the level's connectivity allows: the distance the best
 * possible vertex placement on those triangles would reach, an estimate from below of any placement rule's
 * (bench-simplify --oracle prints it beside the placements of resurf and CGAL's Lindstrom–Turk). */
#ifndef RESURF_ORACLE_POLISH_H
#define RESURF_ORACLE_POLISH_H

#include "shapes.h"

/* Polishes m in place (positions and, by flips, indices). Border edges are never flipped. Returns the number of
 * flips and moves made, or -1 when out of memory (m then partly polished). */
long oracle_polish(shape_kind kind, resurf_mesh *m);

#endif
