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

void resurfi_quadric_add(resurfi_quadric *q, const resurfi_quadric *r)
{
    for (int i = 0; i < 6; ++i)
        q->a[i] += r->a[i];
    for (int i = 0; i < 3; ++i)
        q->b[i] += r->b[i];
    q->c += r->c;
    q->w += r->w;
}

/* A·x for the symmetric A. */
static vec3 mul_a(const double a[6], vec3 x)
{
    return v3(a[0] * x.x + a[1] * x.y + a[2] * x.z, a[1] * x.x + a[3] * x.y + a[4] * x.z,
              a[2] * x.x + a[4] * x.y + a[5] * x.z);
}

double resurfi_quadric_eval(const resurfi_quadric *q, vec3 x)
{
    vec3 ax = mul_a(q->a, x);
    double e = v3_dot(x, ax) + 2.0 * (q->b[0] * x.x + q->b[1] * x.y + q->b[2] * x.z) + q->c;
    return e > 0 ? e : 0;
}

/* Cholesky factor of A + λI (symmetric, positive semidefinite A). Returns 0 when a pivot falls to `min_pivot` or
 * below: the system is too close to singular for the caller's purpose. */
typedef struct cholesky {
    double l00, l10, l20, l11, l21, l22;
} cholesky;

static int factor(const double a[6], double lambda, double min_pivot, cholesky *f)
{
    double a00 = a[0] + lambda, a11 = a[3] + lambda, a22 = a[5] + lambda;
    if (!(a00 > min_pivot))
        return 0;
    f->l00 = sqrt(a00);
    f->l10 = a[1] / f->l00;
    f->l20 = a[2] / f->l00;
    double d1 = a11 - f->l10 * f->l10;
    if (!(d1 > min_pivot))
        return 0;
    f->l11 = sqrt(d1);
    f->l21 = (a[4] - f->l20 * f->l10) / f->l11;
    double d2 = a22 - f->l20 * f->l20 - f->l21 * f->l21;
    if (!(d2 > min_pivot))
        return 0;
    f->l22 = sqrt(d2);
    return 1;
}

/* L Lᵀ x = r */
static vec3 solve(const cholesky *f, vec3 r)
{
    double y0 = r.x / f->l00;
    double y1 = (r.y - f->l10 * y0) / f->l11;
    double y2 = (r.z - f->l20 * y0 - f->l21 * y1) / f->l22;
    double x2 = y2 / f->l22;
    double x1 = (y1 - f->l21 * x2) / f->l11;
    double x0 = (y0 - f->l10 * x1 - f->l20 * x2) / f->l00;
    return v3(x0, x1, x2);
}

/* The gradient of Q / 2 at x: A x + b. */
static vec3 half_gradient(const resurfi_quadric *q, vec3 x) { return v3_add(mul_a(q->a, x), v3(q->b[0], q->b[1], q->b[2])); }

int resurfi_quadric_optimum(const resurfi_quadric *q, vec3 around, vec3 *out)
{
    *out = around;
    double trace = q->a[0] + q->a[3] + q->a[5];
    if (!(trace > 0) || !isfinite(trace))
        return 0;
    /* Solve for the step from `around` rather than for the point itself: the right-hand side is then the gradient
     * there, and the damped solve below shrinks the step, not the coordinates (which would pull towards 0). */
    double tau = RESURFI_QUADRIC_COND * trace;
    cholesky f;
    if (factor(q->a, 0.0, tau, &f)) {
        vec3 x = v3_sub(around, solve(&f, half_gradient(q, around)));
        if (!v3_finite(x))
            return 0;
        *out = x;
        return 1;
    }
    /* With λ = τ every pivot is at least τ for a positive semidefinite A, so this fails only on non-finite input.
     * One step of iterative refinement takes the well-determined directions from a relative error λ/μ to (λ/μ)²
     * (μ an eigenvalue there), while along the flat ones (μ << λ) the point hardly moves. */
    if (!factor(q->a, tau, 0.0, &f))
        return 0;
    vec3 x = v3_sub(around, solve(&f, half_gradient(q, around)));
    x = v3_sub(x, solve(&f, half_gradient(q, x)));
    if (!v3_finite(x))
        return 0;
    *out = x;
    return 2;
}
