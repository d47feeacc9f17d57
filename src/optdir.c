/* The "optimal direction" of the restoring projection (Semenova, Savchenko, Hagiwara, "Reconstruction of Shapes
 * Based on Normals Analysis", §3.1; docs/restoring.md §3): for a point p and a triangle (p_j, N_j), find t and
 * barycentrics b with p = Σ b_j (p_j + t N_j), i.e. the line through the foot p0 = Σ b_j p_j along the interpolated
 * normal Σ b_j N_j that passes through p.
 *
 * For fixed t the b are the barycentrics of p in the offset triangle q_j(t) = p_j + t N_j, so t must make p coplanar
 * with it: det(q2 − q1, q3 − q1, p − q1) = 0. Each column is linear in t (a_i + t b_i), so the determinant is a cubic
 * whose coefficients we expand exactly. It is solved in s = t / h (h = longest edge) so that its coefficients are
 * dimensionless and of order one; vanishing leading coefficients are dropped (equal normals make it linear: the
 * plain projection along the common normal), the roots come in closed form and are then polished by Newton steps on
 * the full cubic: when the normals nearly agree the other roots are huge (~1/angle) and the closed form loses the
 * small root's digits to cancellation, which Newton restores. */
#include <float.h>

#include "internal.h"

/* Leading coefficients at or below this fraction of the largest one are dropped: the root they carry lies beyond
 * ~1e13 edge lengths, where it means nothing, and keeping them would only cost accuracy in the closed forms. */
static const double drop_rel = 1e-13;

/* (area / longest side²)² of the offset triangle below which it counts as collapsed. */
static const double collapse_area2 = 1e-24;
/* sin² of the angle between p − q1 and the offset triangle's plane above which a root is not one. */
static const double coplanar_sin2 = 1e-18;

/* The largest of three (no libm call in the hot path; NaNs are caught by the callers' finiteness tests). */
static double max3(double a, double b, double c)
{
    double m = a > b ? a : b;
    return m > c ? m : c;
}

/* Polynomial c[0] + c[1] s + c[2] s² + c[3] s³ and its derivative. */
static double poly_eval(const double c[4], double s, double *out_derivative)
{
    *out_derivative = (3.0 * c[3] * s + 2.0 * c[2]) * s + c[1];
    return ((c[3] * s + c[2]) * s + c[1]) * s + c[0];
}

/* Real roots of a quadratic c0 + c1 s + c2 s² (c2 != 0), the cancellation-free way (Numerical Recipes §5.6).
 * A slightly negative discriminant (relative to the terms that make it) is rounding: a double root. */
static int solve_quadratic(double c0, double c1, double c2, double roots[2])
{
    double disc = c1 * c1 - 4.0 * c2 * c0;
    double scale = c1 * c1 + fabs(4.0 * c2 * c0);
    if (disc < 0) {
        if (disc < -1e-14 * scale)
            return 0;
        disc = 0;
    }
    double q = -0.5 * (c1 + copysign(sqrt(disc), c1));
    if (q == 0) { /* c1 = 0 and c0 = 0: a double root at 0 */
        roots[0] = 0;
        return 1;
    }
    roots[0] = q / c2;
    roots[1] = c0 / q;
    return 2;
}

/* Real roots of a monic cubic s³ + a s² + b s + c: trigonometric form for three real roots, Cardano (with the
 * larger-magnitude cube root taken first, so the sum does not cancel) for one. */
static int solve_cubic_monic(double a, double b, double c, double roots[3])
{
    double a3 = a / 3.0;
    double p = b - a * a3;                           /* depressed cubic y³ + p y + q, s = y − a/3 */
    double q = (2.0 * a3 * a3 - b) * a3 + c;
    double half_q = 0.5 * q, third_p = p / 3.0;
    double disc = half_q * half_q + third_p * third_p * third_p;
    if (disc > 0) {
        double u = cbrt(-half_q - copysign(sqrt(disc), half_q));
        double y = u != 0 ? u - third_p / u : 0.0;
        roots[0] = y - a3;
        return 1;
    }
    if (third_p >= 0) { /* disc <= 0 and p >= 0 means p = q = 0: a triple root */
        roots[0] = -a3;
        return 1;
    }
    double r = sqrt(-third_p);
    double cos_phi = -half_q / (r * r * r);
    cos_phi = cos_phi < -1 ? -1 : cos_phi > 1 ? 1 : cos_phi;
    double phi = acos(cos_phi);
    static const double two_pi_3 = 2.0943951023931954923;
    for (int k = 0; k < 3; ++k)
        roots[k] = 2.0 * r * cos(phi / 3.0 + two_pi_3 * k) - a3;
    return 3;
}

/* Real roots of the cubic c (c[3] != 0, coefficients of order one at most). The usual case in restoring is a
 * cubic that is nearly linear near 0 (normals that nearly agree): Newton from the linear estimate −c0/c1 finds its
 * small root in a few steps, and dividing that root out (forward deflation, stable when the smallest root goes
 * first) leaves a quadratic for the other two, with no trigonometry. When Newton does not settle quickly, the
 * closed form. */
static int solve_cubic(const double c[4], double roots[3])
{
    double s = c[1] != 0 ? -c[0] / c[1] : 0.0;
    int converged = 0;
    for (int it = 0; it < 8; ++it) {
        double d, f = poly_eval(c, s, &d);
        if (f == 0) {
            converged = 1;
            break;
        }
        if (d == 0 || !isfinite(d))
            break;
        double step = f / d;
        s -= step;
        if (fabs(step) <= 1e-14 * (1.0 + fabs(s))) {
            converged = 1;
            break;
        }
    }
    if (!converged || !isfinite(s))
        return solve_cubic_monic(c[2] / c[3], c[1] / c[3], c[0] / c[3], roots);
    roots[0] = s;
    double q2 = c[3], q1 = c[2] + s * q2, q0 = c[1] + s * q1;
    return 1 + solve_quadratic(q0, q1, q2, roots + 1);
}

/* Real roots of the cubic c (degree <= 3). Returns the count, or -1 when the polynomial vanishes identically. */
static int solve_poly(const double c_in[4], double roots[3])
{
    double m = max3(max3(fabs(c_in[0]), fabs(c_in[1]), fabs(c_in[2])), fabs(c_in[3]), 0);
    if (!(m > 0) || !isfinite(m))
        return -1;
    double c[4] = {c_in[0] / m, c_in[1] / m, c_in[2] / m, c_in[3] / m};
    int degree = 3;
    while (degree > 0 && fabs(c[degree]) <= drop_rel)
        --degree;
    int n;
    switch (degree) {
    case 3: n = solve_cubic(c, roots); break;
    case 2: n = solve_quadratic(c[0], c[1], c[2], roots); break;
    case 1: roots[0] = -c[0] / c[1]; n = 1; break;
    default: return 0; /* a non-zero constant: no root */
    }
    /* Newton on the full cubic: restores what the closed forms lost to cancellation, and accounts for dropped terms.
     * Keep the best iterate by |f| so that a step near a turning point cannot make it worse. */
    for (int i = 0; i < n; ++i) {
        double s = roots[i], d;
        double f = poly_eval(c, s, &d);
        for (int it = 0; it < 4 && f != 0 && d != 0; ++it) {
            double s_next = s - f / d, d_next;
            double f_next = poly_eval(c, s_next, &d_next);
            if (!(fabs(f_next) < fabs(f)))
                break;
            s = s_next, f = f_next, d = d_next;
        }
        roots[i] = s;
    }
    return n;
}

/* Is root a ranked before root b? Inside roots first, by |t|; then by how far outside, then by |t|. */
static int ranks_before(const resurfi_optdir_root *a, const resurfi_optdir_root *b)
{
    int in_a = a->outside <= RESURFI_OPTDIR_INSIDE_TOL, in_b = b->outside <= RESURFI_OPTDIR_INSIDE_TOL;
    if (in_a != in_b)
        return in_a;
    if (!in_a && a->outside != b->outside)
        return a->outside < b->outside;
    return fabs(a->t) < fabs(b->t);
}

/* The equation for one point and triangle, in units of the longest edge h. */
typedef struct cubic_setup {
    double h, inv_h;
    vec3 A1, B1, A2, B2, A3, B3; /* columns e1 = A1 + s B1, e2 = A2 + s B2, w = A3 + s B3 (relative to q1) */
    double side_size, normal_size;
    double c[4];                 /* det(e1, e2, w) = c0 + c1 s + c2 s² + c3 s³ */
} cubic_setup;

/* Returns 0 for a triangle without extent (or non-finite corners). */
static int setup_cubic(vec3 p, const vec3 pj[3], const vec3 nj[3], cubic_setup *q)
{
    double h2 = max3(v3_dist2(pj[0], pj[1]), v3_dist2(pj[1], pj[2]), v3_dist2(pj[2], pj[0]));
    if (!(h2 > 0) || !isfinite(h2))
        return 0;
    q->h = sqrt(h2), q->inv_h = 1.0 / q->h;
    q->A1 = v3_scale(v3_sub(pj[1], pj[0]), q->inv_h), q->B1 = v3_sub(nj[1], nj[0]);
    q->A2 = v3_scale(v3_sub(pj[2], pj[0]), q->inv_h), q->B2 = v3_sub(nj[2], nj[0]);
    q->A3 = v3_scale(v3_sub(p, pj[0]), q->inv_h), q->B3 = v3_neg(nj[0]);
    q->side_size = v3_len(q->A1) + v3_len(q->A2);
    /* B1, B2 are differences of normals: their rounding error is relative to the normals, not to themselves */
    q->normal_size = 2 * sqrt(max3(v3_len2(nj[0]), v3_len2(nj[1]), v3_len2(nj[2])));
    /* (e1 × e2)·w with e1 × e2 = A1×A2 + s (A1×B2 + B1×A2) + s² B1×B2. */
    vec3 n0 = v3_cross(q->A1, q->A2);
    vec3 n1 = v3_add(v3_cross(q->A1, q->B2), v3_cross(q->B1, q->A2));
    vec3 n2 = v3_cross(q->B1, q->B2);
    q->c[0] = v3_dot(n0, q->A3);
    q->c[1] = v3_dot(n0, q->B3) + v3_dot(n1, q->A3);
    q->c[2] = v3_dot(n1, q->B3) + v3_dot(n2, q->A3);
    q->c[3] = v3_dot(n2, q->B3);
    return 1;
}

/* The root at s (a root of the cubic) with its barycentrics; 0 when it is spurious. */
static int make_root(const cubic_setup *q, double s, resurfi_optdir_root *out)
{
    if (!isfinite(s))
        return 0;
    /* Barycentrics of p in the offset triangle, measured with its own normal: the sub-triangle areas
     * (w × e2)·n and (e1 × w)·n over n·n, which stay accurate when p sits slightly off its plane. */
    vec3 e1 = v3_madd(q->A1, q->B1, s), e2 = v3_madd(q->A2, q->B2, s), w = v3_madd(q->A3, q->B3, s);
    vec3 nq = v3_cross(e1, e2);
    double nn = v3_len2(nq);
    /* The offset triangle collapses at this t (to a segment or a point, up to the rounding of its sides at
     * this t): every p solves the equation there, so the root is spurious and p has no barycentrics in it. */
    double size2 = max3(v3_len2(e1), v3_len2(e2), v3_dist2(e1, e2));
    double rounding = 64 * DBL_EPSILON * (q->side_size + fabs(s) * q->normal_size);
    if (!(nn > collapse_area2 * size2 * size2 && nn > rounding * rounding * size2))
        return 0;
    /* p must lie in the offset triangle's plane: near a collapse the plane is undefined and a root of the
     * rounded cubic can survive the test above (the sphere's centre, where all q_j(t) meet, is a double
     * root). p's distance from the plane, relative to its distance from q1 or the triangle's size, whichever is
     * larger (p may sit on a corner), is what a true root makes vanish. */
    double off_plane = v3_dot(w, nq);
    if (off_plane * off_plane > coplanar_sin2 * (v3_len2(w) + size2) * nn)
        return 0;
    double b2 = v3_dot(v3_cross(w, e2), nq) / nn;
    double b3 = v3_dot(v3_cross(e1, w), nq) / nn;
    double b1 = 1.0 - b2 - b3;
    *out = (resurfi_optdir_root){.t = s * q->h, .bary = {b1, b2, b3}};
    double lowest = b1 < b2 ? (b1 < b3 ? b1 : b3) : (b2 < b3 ? b2 : b3);
    out->outside = lowest < 0 ? -lowest : 0.0;
    return 1;
}

int resurfi_optdir_solve(vec3 p, const vec3 pj[3], const vec3 nj[3], resurfi_optdir_root roots[3])
{
    cubic_setup q;
    if (!setup_cubic(p, pj, nj, &q))
        return 0;
    double s_roots[3];
    int n = solve_poly(q.c, s_roots);
    int count = 0;
    for (int i = 0; i < n; ++i) {
        double s = s_roots[i];
        int duplicate = 0; /* a double root found twice */
        for (int k = 0; k < count; ++k)
            if (fabs(roots[k].t * q.inv_h - s) <= 1e-12 * (1.0 + fabs(s)))
                duplicate = 1;
        resurfi_optdir_root r;
        if (duplicate || !make_root(&q, s, &r))
            continue;
        /* insertion into the ranked list */
        int at = count;
        while (at > 0 && ranks_before(&r, &roots[at - 1])) {
            roots[at] = roots[at - 1];
            --at;
        }
        roots[at] = r;
        ++count;
    }
    return count;
}

int resurfi_optdir_near(vec3 p, const vec3 pj[3], const vec3 nj[3], double t_guess, resurfi_optdir_root *out)
{
    cubic_setup q;
    if (!setup_cubic(p, pj, nj, &q))
        return 0;
    double m = max3(max3(fabs(q.c[0]), fabs(q.c[1]), fabs(q.c[2])), fabs(q.c[3]), 0);
    if (!(m > 0) || !isfinite(m))
        return 0;
    double c[4] = {q.c[0] / m, q.c[1] / m, q.c[2] / m, q.c[3] / m};
    double s = t_guess * q.inv_h;
    for (int it = 0; it < 8; ++it) {
        double d, f = poly_eval(c, s, &d);
        if (f == 0)
            return make_root(&q, s, out);
        if (d == 0 || !isfinite(d))
            return 0;
        double step = f / d;
        s -= step;
        if (fabs(step) <= 1e-14 * (1.0 + fabs(s))) {
            /* one more step: the iterate is then as good as the closed forms' polished roots */
            double f2 = poly_eval(c, s, &d);
            if (d != 0 && isfinite(d))
                s -= f2 / d;
            return make_root(&q, s, out);
        }
    }
    return 0;
}
