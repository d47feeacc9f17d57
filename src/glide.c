/* The gliding-normal displacement of one triangle corner (Semenova, Savchenko, Hagiwara, §3.2 formula (2);
 * docs/restoring.md §4 and §9).
 *
 * The surface near the corner p_j is taken to be a circular arc that leaves p_j with normal N_j and meets the line
 * l = {p + δ N_opt} with normal N_opt. Write the chord c = p_j − p as c = (N_opt·c) N_opt + u, u ⟂ N_opt. The arc
 * through p_j whose normal turns by α from N_j to N_opt meets l at signed height
 *
 *     δ = N_opt·c + side · |u| · tan(α/2)
 *
 * above p, which is formula (2) (d cos β = N_opt·c, d sin β = |u|) with the paper's max (side = +1) and min
 * (side = −1) algorithms. On a sphere with exact normals every corner gives the exact displacement to the sphere.
 * Evaluated this way there is no division by d_j (a corner at p gives δ = N_opt·c = 0) and tan(α/2) is taken as
 * |N_opt × N_j| / (1 + N_opt·N_j), accurate for the small angles that matter.
 *
 * The normal-section variant (docs/restoring.md §9) keeps only the part of N_j in the plane spanned by N_opt and
 * u, the normal section of the chord: its angle α' to N_opt is signed (positive when N_j leans away from l
 * towards p_j, as on a convex surface), so the max/min choice comes out of the geometry, and the twist of the
 * normal across the chord (the part of N_j out of that plane), which formula (2) wrongly counts as bending, is
 * ignored. */
#include "internal.h"

/* A corner normal turned 90° or more from N_opt does not belong to the same smooth sheet as p (a fold, a flipped
 * or two-sided part of a scan): the arc model breaks down there (tan(α/2) grows without bound as α → 180°; a scan
 * of the Stanford dragon moved points by 6 times its size that way), so such a corner contributes only the
 * straight part N_opt·c. Below 90° the arc term is at most |u|, the corner's distance from the line. */
double resurfi_glide_paper(vec3 p, vec3 pj, vec3 nj, vec3 n_opt, int side)
{
    vec3 c = v3_sub(pj, p);
    double along = v3_dot(n_opt, c);
    double u = v3_len(v3_madd(c, n_opt, -along));
    /* tan(α/2) = sin α / (1 + cos α), scale-free in case a normal is not exactly unit */
    double len = v3_len(n_opt) * v3_len(nj);
    double cos_alpha = v3_dot(n_opt, nj);
    if (!(cos_alpha > 0))
        return along;
    double denom = len + cos_alpha;
    double tan_half = v3_len(v3_cross(n_opt, nj)) / denom;
    return along + (side < 0 ? -1.0 : 1.0) * u * tan_half;
}

double resurfi_glide_normal_section(vec3 p, vec3 pj, vec3 nj, vec3 n_opt)
{
    vec3 c = v3_sub(pj, p);
    double along = v3_dot(n_opt, c);
    vec3 u = v3_madd(c, n_opt, -along);
    double u_len = v3_len(u);
    if (!(u_len > 0))
        return along;
    /* N_j projected on the plane (u/|u|, N_opt): components x (towards p_j) and y (along N_opt). */
    double x = v3_dot(nj, u) / u_len, y = v3_dot(nj, n_opt);
    double r = hypot(x, y);
    if (!(y > 0))
        return along;
    /* |u| tan(α'/2) with tan(α'/2) = x / (r + y), signed */
    return along + u_len * x / (r + y);
}
