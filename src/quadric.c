/* Error quadrics for edge-collapse simplification (Garland & Heckbert, "Surface Simplification Using Quadric Error
 * Metrics", SIGGRAPH 1997): the squared distance to a plane is a quadratic form, a sum of them is one too, and its
 * minimiser is the solution of a 3×3 linear system. Where that system is singular (flat or cylindrical regions,
 * straight borders) the solve follows Lindstrom ("Out-of-core simplification of large polygonal models", 2000) in
 * spirit: move only along the directions the quadric determines, stay at the reference point along the others. */
#include <math.h>

#include "internal.h"

resurfi_quadric resurfi_quadric_plane(vec3 n, double d, double weight)
{
    resurfi_quadric q;
    q.a[0] = weight * n.x * n.x;
    q.a[1] = weight * n.x * n.y;
    q.a[2] = weight * n.x * n.z;
    q.a[3] = weight * n.y * n.y;
    q.a[4] = weight * n.y * n.z;
    q.a[5] = weight * n.z * n.z;
    q.b[0] = weight * d * n.x;
    q.b[1] = weight * d * n.y;
    q.b[2] = weight * d * n.z;
    q.c = weight * d * d;
    q.w = weight;
    return q;
}

resurfi_quadric resurfi_quadric_triangle(vec3 p0, vec3 p1, vec3 p2)
{
    vec3 cr = v3_tri_cross(p0, p1, p2);
    double len = v3_len(cr);
    if (!(len > 0) || !isfinite(len))
        return (resurfi_quadric){{0, 0, 0, 0, 0, 0}, {0, 0, 0}, 0, 0};
    vec3 n = v3_scale(cr, 1.0 / len);
    /* The plane through the centroid: its offset is less sensitive to rounding than through one corner. */
    vec3 centroid = v3_scale(v3_add(v3_add(p0, p1), p2), 1.0 / 3.0);
    return resurfi_quadric_plane(n, -v3_dot(n, centroid), 0.5 * len);
}

/* LDLᵀ factor of A + λI (symmetric, positive semidefinite A), kept as L and the reciprocals of the pivots D: no
 * square root and three divisions, where Cholesky needs three square roots and nine divisions. D holds the squares
 * of Cholesky's diagonal, so the pivot test is the same. Returns 0 when a pivot falls to `min_pivot` or below: the
 * system is too close to singular for the caller's purpose. */
typedef struct ldlt {
    double l10, l20, l21; /* the unit lower triangle */
    double r0, r1, r2;    /* 1 / D */
} ldlt;

static int factor(const double a[6], double lambda, double min_pivot, ldlt *f)
{
    double d0 = a[0] + lambda;
    if (!(d0 > min_pivot))
        return 0;
    f->r0 = 1.0 / d0;
    f->l10 = a[1] * f->r0;
    f->l20 = a[2] * f->r0;
    double d1 = a[3] + lambda - f->l10 * a[1];
    if (!(d1 > min_pivot))
        return 0;
    f->r1 = 1.0 / d1;
    double e21 = a[4] - f->l20 * a[1]; /* l21 × d1 */
    f->l21 = e21 * f->r1;
    double d2 = a[5] + lambda - f->l20 * a[2] - f->l21 * e21;
    if (!(d2 > min_pivot))
        return 0;
    f->r2 = 1.0 / d2;
    return 1;
}

/* L D Lᵀ x = r */
static vec3 solve(const ldlt *f, vec3 r)
{
    double y1 = r.y - f->l10 * r.x;
    double y2 = r.z - f->l20 * r.x - f->l21 * y1;
    double x2 = y2 * f->r2;
    double x1 = y1 * f->r1 - f->l21 * x2;
    double x0 = r.x * f->r0 - f->l10 * x1 - f->l20 * x2;
    return v3(x0, x1, x2);
}

int resurfi_quadric_optimum(const resurfi_quadric *q, vec3 around, vec3 *out)
{
    *out = around;
    double trace = q->a[0] + q->a[3] + q->a[5];
    if (!(trace > 0) || !isfinite(trace))
        return 0;
    /* Solve for the step from `around` rather than for the point itself: the right-hand side is then the gradient
     * of Q / 2 there, A·around + b, and the damped solve below shrinks the step, not the coordinates (which would
     * pull towards 0). */
    vec3 g = v3_add(resurfi_quadric_mul(q, around), v3(q->b[0], q->b[1], q->b[2]));
    double tau = RESURFI_QUADRIC_COND * trace;
    ldlt f;
    if (factor(q->a, 0.0, tau, &f)) {
        vec3 x = v3_sub(around, solve(&f, g));
        if (!v3_finite(x))
            return 0;
        *out = x;
        return 1;
    }
    /* With λ = τ every pivot is at least τ for a positive semidefinite A, so this fails only on non-finite input.
     * One step of iterative refinement takes the well-determined directions from a relative error λ/μ to (λ/μ)²
     * (μ an eigenvalue there), while along the flat ones (μ << λ) the point hardly moves. The first step δ solves
     * (A + λI) δ = g, so the gradient left after it, g − A δ, is exactly λ δ: the second step needs no product
     * with A. */
    if (!factor(q->a, tau, 0.0, &f))
        return 0;
    vec3 d = solve(&f, g);
    vec3 x = v3_sub(v3_sub(around, d), v3_scale(solve(&f, d), tau));
    if (!v3_finite(x))
        return 0;
    *out = x;
    return 2;
}
