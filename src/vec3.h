/* Small inline vector math on doubles: the one vector header of resurf. */
#ifndef RESURF_VEC3_H
#define RESURF_VEC3_H

#include <math.h>

typedef struct vec3 {
    double x, y, z;
} vec3;

static inline vec3 v3(double x, double y, double z) { return (vec3){x, y, z}; }
static inline vec3 v3_load(const double *p) { return (vec3){p[0], p[1], p[2]}; }
static inline void v3_store(double *p, vec3 a) { p[0] = a.x; p[1] = a.y; p[2] = a.z; }
static inline vec3 v3_add(vec3 a, vec3 b) { return (vec3){a.x + b.x, a.y + b.y, a.z + b.z}; }
static inline vec3 v3_sub(vec3 a, vec3 b) { return (vec3){a.x - b.x, a.y - b.y, a.z - b.z}; }
static inline vec3 v3_scale(vec3 a, double s) { return (vec3){a.x * s, a.y * s, a.z * s}; }
static inline vec3 v3_madd(vec3 a, vec3 b, double s) { return (vec3){a.x + b.x * s, a.y + b.y * s, a.z + b.z * s}; }
static inline vec3 v3_neg(vec3 a) { return (vec3){-a.x, -a.y, -a.z}; }
static inline double v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vec3 v3_cross(vec3 a, vec3 b)
{
    return (vec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static inline double v3_len2(vec3 a) { return v3_dot(a, a); }
static inline double v3_len(vec3 a) { return sqrt(v3_dot(a, a)); }
static inline double v3_dist(vec3 a, vec3 b) { return v3_len(v3_sub(a, b)); }
static inline double v3_dist2(vec3 a, vec3 b) { return v3_len2(v3_sub(a, b)); }
/* min / max of `a` (never NaN) and `b`, whose NaN is ignored as fmin and fmax would: plain comparisons, because fmin
 * and fmax are calls (50 ms of bounds on a million triangles). v3_min / v3_max: of a box corner and a point. */
static inline double dmin(double a, double b) { return b < a ? b : a; }
static inline double dmax(double a, double b) { return b > a ? b : a; }
static inline vec3 v3_min(vec3 a, vec3 b) { return (vec3){dmin(a.x, b.x), dmin(a.y, b.y), dmin(a.z, b.z)}; }
static inline vec3 v3_max(vec3 a, vec3 b) { return (vec3){dmax(a.x, b.x), dmax(a.y, b.y), dmax(a.z, b.z)}; }
static inline vec3 v3_lerp(vec3 a, vec3 b, double t) { return v3_madd(a, v3_sub(b, a), t); }
static inline double v3_comp(vec3 a, int axis) { return axis == 0 ? a.x : axis == 1 ? a.y : a.z; }
static inline int v3_finite(vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

/* a / |a|, or the zero vector when |a| is 0 (callers test for that rather than divide by zero). */
static inline vec3 v3_normalize(vec3 a)
{
    double l = v3_len(a);
    return l > 0 ? v3_scale(a, 1.0 / l) : (vec3){0, 0, 0};
}

/* Twice the triangle's vector area: (b − a) × (c − a). */
static inline vec3 v3_tri_cross(vec3 a, vec3 b, vec3 c) { return v3_cross(v3_sub(b, a), v3_sub(c, a)); }

/* An affine map as a column-major 4 × 4 matrix (glTF's node matrices): columns c0, c1, c2 and the translation t. */
typedef struct affine3 {
    vec3 c0, c1, c2, t;
    vec3 n0, n1, n2; /* the inverse transpose's columns up to the determinant, whose sign alone matters to normals */
} affine3;

/* a: column-major 4 × 4, or NULL for the identity. */
static inline affine3 affine3_from(const double *a)
{
    static const double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    if (!a)
        a = identity;
    affine3 m = {.c0 = v3(a[0], a[1], a[2]), .c1 = v3(a[4], a[5], a[6]), .c2 = v3(a[8], a[9], a[10]),
                 .t = v3(a[12], a[13], a[14])};
    double sign = v3_dot(m.c0, v3_cross(m.c1, m.c2)) < 0 ? -1 : 1;
    m.n0 = v3_scale(v3_cross(m.c1, m.c2), sign);
    m.n1 = v3_scale(v3_cross(m.c2, m.c0), sign);
    m.n2 = v3_scale(v3_cross(m.c0, m.c1), sign);
    return m;
}

static inline vec3 affine3_point(const affine3 *m, const double *p)
{
    return v3_add(m->t, v3_add(v3_scale(m->c0, p[0]), v3_add(v3_scale(m->c1, p[1]), v3_scale(m->c2, p[2]))));
}

/* A normal under the map: by the inverse transpose, renormalised. */
static inline vec3 affine3_normal(const affine3 *m, const double *n)
{
    return v3_normalize(v3_add(v3_scale(m->n0, n[0]), v3_add(v3_scale(m->n1, n[1]), v3_scale(m->n2, n[2]))));
}

#endif
