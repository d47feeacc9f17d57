/* Analytic test shapes (see shapes.h). Irregularity comes from jittering a parameter grid; every vertex is then
 * mapped exactly onto the surface, so the only error left in a vertex is double rounding. Jitter is a pure
 * function of (seed, lattice point): duplicated lattice points (cube-sphere edges) land on identical positions and
 * are welded exactly. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "shapes.h"

static const double torus_R = 1.0, torus_r = 0.4;

static const char *const names[SHAPE_COUNT] = {"sphere", "torus", "cubic",  "cylinder",
                                                "saddle", "plane", "cube", "capped-cylinder"};

const char *shape_name(shape_kind kind) { return (unsigned)kind < SHAPE_COUNT ? names[kind] : "unknown"; }

shape_kind shape_from_name(const char *name)
{
    for (int k = 0; k < SHAPE_COUNT; ++k)
        if (name && strcmp(name, names[k]) == 0)
            return (shape_kind)k;
    return SHAPE_COUNT;
}

uint64_t shape_rand_u64(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

double shape_rand_unit(uint64_t *state) { return (double)(shape_rand_u64(state) >> 11) * 0x1.0p-53; }

/* A jitter in [−1, 1) that depends only on the seed, the lattice point and which coordinate it moves. */
static double lattice_jitter(uint64_t seed, long i, long j, long k, int which)
{
    uint64_t s = seed ^ ((uint64_t)i * 0x9e3779b97f4a7c15ull) ^ ((uint64_t)j * 0xc2b2ae3d27d4eb4full) ^
                 ((uint64_t)k * 0x165667b19e3779f9ull) ^ ((uint64_t)which * 0x27d4eb2f165667c5ull);
    return 2.0 * shape_rand_unit(&s) - 1.0;
}

/* ---- surfaces ------------------------------------------------------------------------------------------------ */

static double graph_f(shape_kind kind, double x, double y, double *fx, double *fy, double *fxx, double *fxy,
                      double *fyy)
{
    switch (kind) {
    case SHAPE_CUBIC: /* z = 0.5 (x³ − 3xy²) */
        *fx = 1.5 * (x * x - y * y);
        *fy = -3.0 * x * y;
        *fxx = 3.0 * x;
        *fxy = -3.0 * y;
        *fyy = -3.0 * x;
        return 0.5 * (x * x * x - 3.0 * x * y * y);
    case SHAPE_SADDLE: /* z = x² − y² */
        *fx = 2.0 * x;
        *fy = -2.0 * y;
        *fxx = 2.0;
        *fxy = 0.0;
        *fyy = -2.0;
        return x * x - y * y;
    default: /* plane z = 0 */
        *fx = *fy = *fxx = *fxy = *fyy = 0.0;
        return 0.0;
    }
}

static int is_graph(shape_kind kind) { return kind == SHAPE_CUBIC || kind == SHAPE_SADDLE || kind == SHAPE_PLANE; }

static double clamp1(double v) { return v < -1 ? -1 : v > 1 ? 1 : v; }

/* Projected Newton on g(x,y) = |(x, y, f(x,y)) − p|² / 2 over [−1,1]² from (x, y). Near the surface g is convex
 * and this converges quadratically; a gradient step guards indefinite Hessians. Returns g at the end point. */
static double graph_descend(shape_kind kind, const double p[3], double x, double y, double out[3])
{
    double fx, fy, fxx, fxy, fyy;
    for (int it = 0; it < 60; ++it) {
        double f = graph_f(kind, x, y, &fx, &fy, &fxx, &fxy, &fyy);
        double r = f - p[2];
        double gx = (x - p[0]) + r * fx, gy = (y - p[1]) + r * fy;
        double hxx = 1 + fx * fx + r * fxx, hxy = fx * fy + r * fxy, hyy = 1 + fy * fy + r * fyy;
        double det = hxx * hyy - hxy * hxy;
        double dx, dy;
        if (hxx > 0 && det > 1e-12 * (hxx * hyy + 1)) {
            dx = -(hyy * gx - hxy * gy) / det;
            dy = -(hxx * gy - hxy * gx) / det;
        } else {
            dx = -0.25 * gx;
            dy = -0.25 * gy;
        }
        double nx = clamp1(x + dx), ny = clamp1(y + dy);
        double moved = fabs(nx - x) + fabs(ny - y);
        x = nx;
        y = ny;
        if (moved < 1e-17)
            break;
    }
    out[0] = x;
    out[1] = y;
    out[2] = graph_f(kind, x, y, &fx, &fy, &fxx, &fxy, &fyy);
    return (x - p[0]) * (x - p[0]) + (y - p[1]) * (y - p[1]) + (out[2] - p[2]) * (out[2] - p[2]);
}

/* Closest point on the graph: the best of descents from the point below p and from four points around it, as far
 * out as p is from the graph, so that a start on a stationary point of g (a saddle above its centre) cannot trap
 * the search. */
static void graph_closest(shape_kind kind, const double p[3], double out[3])
{
    double fx, fy, fxx, fxy, fyy;
    double x0 = clamp1(p[0]), y0 = clamp1(p[1]);
    double r = fabs(p[2] - graph_f(kind, x0, y0, &fx, &fy, &fxx, &fxy, &fyy));
    static const double dir[5][2] = {{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    double best = INFINITY;
    for (int i = 0; i < 5; ++i) {
        double c[3];
        double g = graph_descend(kind, p, clamp1(x0 + r * dir[i][0]), clamp1(y0 + r * dir[i][1]), c);
        if (g < best) {
            best = g;
            out[0] = c[0], out[1] = c[1], out[2] = c[2];
        }
        if (r == 0)
            break;
    }
}

/* ---- the shapes with sharp features: which face is closest ----------------------------------------------------- */

/* The box [−1,1]³: outside it the closest point is p clamped to the box; inside, p moved onto the nearest face. The
 * face: the axis where p is farthest out (or least inside), the first one on a tie. */
static int cube_face(const double p[3], double out[3])
{
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (fabs(p[k]) > fabs(p[axis]))
            axis = k;
    for (int k = 0; k < 3; ++k)
        out[k] = clamp1(p[k]);
    if (fabs(p[axis]) <= 1)
        out[axis] = p[axis] < 0 ? -1 : 1;
    return p[axis] < 0 ? -(axis + 1) : axis + 1;
}

/* The capped cylinder: the closest of the wall's point and the two caps' (0 = wall, 1 = top, −1 = bottom). */
static int capped_cylinder_part(const double p[3], double out[3])
{
    double rho = hypot(p[0], p[1]);
    double cx = rho > 0 ? p[0] / rho : 1, cy = rho > 0 ? p[1] / rho : 0;
    double wall[3] = {cx, cy, clamp1(p[2])};
    double disk[3] = {rho <= 1 ? p[0] : cx, rho <= 1 ? p[1] : cy, p[2] < 0 ? -1 : 1};
    double dw = (p[0] - wall[0]) * (p[0] - wall[0]) + (p[1] - wall[1]) * (p[1] - wall[1]) +
                (p[2] - wall[2]) * (p[2] - wall[2]);
    double dd = (p[0] - disk[0]) * (p[0] - disk[0]) + (p[1] - disk[1]) * (p[1] - disk[1]) +
                (p[2] - disk[2]) * (p[2] - disk[2]);
    const double *best = dw <= dd ? wall : disk;
    out[0] = best[0], out[1] = best[1], out[2] = best[2];
    return dw <= dd ? 0 : p[2] < 0 ? -1 : 1;
}

void shape_closest(shape_kind kind, const double p[3], double out[3])
{
    switch (kind) {
    case SHAPE_CUBE:
        cube_face(p, out);
        return;
    case SHAPE_CAPPED_CYLINDER:
        capped_cylinder_part(p, out);
        return;
    case SHAPE_SPHERE: {
        double l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        if (l == 0) {
            out[0] = 0, out[1] = 0, out[2] = 1;
            return;
        }
        for (int i = 0; i < 3; ++i)
            out[i] = p[i] / l;
        return;
    }
    case SHAPE_TORUS: {
        double rho = hypot(p[0], p[1]);
        double cx = rho > 0 ? p[0] / rho : 1, cy = rho > 0 ? p[1] / rho : 0;
        double q = rho - torus_R, z = p[2];
        double l = hypot(q, z);
        double sq = l > 0 ? q / l : 1, sz = l > 0 ? z / l : 0;
        double ring = torus_R + torus_r * sq;
        out[0] = ring * cx, out[1] = ring * cy, out[2] = torus_r * sz;
        return;
    }
    case SHAPE_CYLINDER: {
        double rho = hypot(p[0], p[1]);
        double cx = rho > 0 ? p[0] / rho : 1, cy = rho > 0 ? p[1] / rho : 0;
        out[0] = cx, out[1] = cy, out[2] = clamp1(p[2]);
        return;
    }
    default:
        graph_closest(kind, p, out);
        return;
    }
}

double shape_distance(shape_kind kind, const double p[3])
{
    switch (kind) {
    case SHAPE_SPHERE:
        return fabs(sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 1.0);
    case SHAPE_TORUS: {
        double q = hypot(p[0], p[1]) - torus_R;
        return fabs(hypot(q, p[2]) - torus_r);
    }
    default: {
        double c[3];
        shape_closest(kind, p, c);
        return sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) + (p[2] - c[2]) * (p[2] - c[2]));
    }
    }
}

void shape_normal(shape_kind kind, const double p[3], double n[3])
{
    double c[3];
    shape_closest(kind, p, c);
    switch (kind) {
    case SHAPE_SPHERE:
        n[0] = c[0], n[1] = c[1], n[2] = c[2];
        return;
    case SHAPE_TORUS: {
        double rho = hypot(c[0], c[1]);
        double ax = c[0] / rho * torus_R, ay = c[1] / rho * torus_R;
        n[0] = (c[0] - ax) / torus_r, n[1] = (c[1] - ay) / torus_r, n[2] = c[2] / torus_r;
        return;
    }
    case SHAPE_CYLINDER:
        n[0] = c[0], n[1] = c[1], n[2] = 0;
        return;
    case SHAPE_CUBE: {
        int face = cube_face(p, c);
        n[0] = n[1] = n[2] = 0;
        n[abs(face) - 1] = face < 0 ? -1 : 1;
        return;
    }
    case SHAPE_CAPPED_CYLINDER: {
        int part = capped_cylinder_part(p, c);
        n[0] = part ? 0 : c[0], n[1] = part ? 0 : c[1], n[2] = part;
        return;
    }
    default: {
        double fx, fy, fxx, fxy, fyy;
        graph_f(kind, c[0], c[1], &fx, &fy, &fxx, &fxy, &fyy);
        double l = sqrt(fx * fx + fy * fy + 1);
        n[0] = -fx / l, n[1] = -fy / l, n[2] = 1 / l;
        return;
    }
    }
}

/* ---- meshing ------------------------------------------------------------------------------------------------- */

typedef struct builder {
    double *positions;
    size_t vertex_count, vertex_capacity;
    double *params;       /* 2 per vertex: the (jittered) grid parameters, to orient quads */
    double period;        /* of the first parameter (2π on the torus and cylinder), 0 if none */
    uint32_t *indices;
    size_t triangle_count, triangle_capacity;
    int failed;
} builder;

static uint32_t add_vertex(builder *b, double x, double y, double z, double u, double v)
{
    if (b->vertex_count == b->vertex_capacity) {
        size_t cap = b->vertex_capacity ? 2 * b->vertex_capacity : 1024;
        double *p = realloc(b->positions, cap * 3 * sizeof(double));
        if (p)
            b->positions = p;
        double *q = realloc(b->params, cap * 2 * sizeof(double));
        if (q)
            b->params = q;
        if (!p || !q) {
            b->failed = 1;
            return 0;
        }
        b->vertex_capacity = cap;
    }
    double *p = b->positions + 3 * b->vertex_count;
    p[0] = x, p[1] = y, p[2] = z;
    b->params[2 * b->vertex_count] = u;
    b->params[2 * b->vertex_count + 1] = v;
    return (uint32_t)b->vertex_count++;
}

/* Is (a, c, d) counter-clockwise in parameter space? (The first parameter may wrap around.) */
static int param_ccw(const builder *b, uint32_t a, uint32_t c, uint32_t d)
{
    const double *pa = b->params + 2 * (size_t)a, *pc = b->params + 2 * (size_t)c, *pd = b->params + 2 * (size_t)d;
    double e[4] = {pc[0] - pa[0], pc[1] - pa[1], pd[0] - pa[0], pd[1] - pa[1]};
    if (b->period > 0)
        for (int i = 0; i < 4; i += 2)
            e[i] -= b->period * round(e[i] / b->period);
    return e[0] * e[3] - e[1] * e[2] > 0;
}

static void add_triangle(builder *b, uint32_t a, uint32_t c, uint32_t d)
{
    if (b->triangle_count == b->triangle_capacity) {
        size_t cap = b->triangle_capacity ? 2 * b->triangle_capacity : 1024;
        uint32_t *p = realloc(b->indices, cap * 3 * sizeof(uint32_t));
        if (!p) {
            b->failed = 1;
            return;
        }
        b->indices = p, b->triangle_capacity = cap;
    }
    uint32_t *t = b->indices + 3 * b->triangle_count++;
    t[0] = a, t[1] = c, t[2] = d;
}

/* Two triangles for the quad (a, c, d, e) counter-clockwise; the diagonal is picked by a hash so that the
 * connectivity is irregular too, unless the jitter made the quad non-convex: then only the diagonal through the
 * reflex corner keeps both triangles the right way round. */
static void add_quad(builder *b, uint32_t a, uint32_t c, uint32_t d, uint32_t e, uint64_t seed, long key)
{
    int first = lattice_jitter(seed, key, 7, 11, 3) < 0;
    int first_ok = param_ccw(b, a, c, d) && param_ccw(b, a, d, e);
    int second_ok = param_ccw(b, a, c, e) && param_ccw(b, c, d, e);
    if (first ? (first_ok || !second_ok) : (first_ok && !second_ok)) {
        add_triangle(b, a, c, d);
        add_triangle(b, a, d, e);
    } else {
        add_triangle(b, a, c, e);
        add_triangle(b, c, d, e);
    }
}

/* Jittered grid coordinate: index i of 0..n, interior ones moved by up to jitter × spacing. */
static double grid_coord(long i, long n, double jitter, double j)
{
    double u = (double)i;
    if (i > 0 && i < n)
        u += jitter * j;
    return -1.0 + 2.0 * u / (double)n;
}

static void mesh_sphere(builder *b, size_t triangles, double jitter, uint64_t seed)
{
    long n = (long)fmax(2, round(sqrt((double)triangles / 12.0)));
    /* Each face of the cube [−1,1]³: axis a, sign s; parameters along axes u, v with e_u × e_v = s e_a. */
    for (int a = 0; a < 3; ++a) {
        for (int s = -1; s <= 1; s += 2) {
            int u = (a + 1) % 3, v = (a + 2) % 3;
            if (s < 0) {
                int t = u;
                u = v;
                v = t;
            }
            uint32_t *ids = malloc((size_t)(n + 1) * (size_t)(n + 1) * sizeof(uint32_t));
            if (!ids) {
                b->failed = 1;
                return;
            }
            for (long j = 0; j <= n; ++j) {
                for (long i = 0; i <= n; ++i) {
                    long lat[3];
                    lat[a] = s > 0 ? n : 0;
                    lat[u] = i;
                    lat[v] = j;
                    double c[3];
                    for (int k = 0; k < 3; ++k)
                        c[k] = grid_coord(lat[k], n, jitter, lattice_jitter(seed, lat[0], lat[1], lat[2], k));
                    double l = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
                    ids[j * (n + 1) + i] = add_vertex(b, c[0] / l, c[1] / l, c[2] / l, c[u], c[v]);
                }
            }
            for (long j = 0; j < n; ++j)
                for (long i = 0; i < n; ++i)
                    add_quad(b, ids[j * (n + 1) + i], ids[j * (n + 1) + i + 1], ids[(j + 1) * (n + 1) + i + 1],
                             ids[(j + 1) * (n + 1) + i], seed, ((a * 2 + (s > 0)) * (n + 1) + j) * (n + 1) + i);
            free(ids);
        }
    }
}

static void mesh_torus(builder *b, size_t triangles, double jitter, uint64_t seed)
{
    /* Cells roughly square: nu / nv ≈ R / r. */
    double ratio = torus_R / torus_r;
    long nv = (long)fmax(3, round(sqrt((double)triangles / (2.0 * ratio))));
    long nu = (long)fmax(3, round((double)triangles / (2.0 * (double)nv)));
    for (long j = 0; j < nv; ++j) {
        for (long i = 0; i < nu; ++i) {
            double su = 2 * M_PI * (i + jitter * lattice_jitter(seed, i, j, 0, 0)) / (double)nu;
            double sv = 2 * M_PI * (j + jitter * lattice_jitter(seed, i, j, 0, 1)) / (double)nv;
            double ring = torus_R + torus_r * cos(sv);
            add_vertex(b, ring * cos(su), ring * sin(su), torus_r * sin(sv), su, sv);
        }
    }
    for (long j = 0; j < nv; ++j)
        for (long i = 0; i < nu; ++i) {
            uint32_t a = (uint32_t)(j * nu + i), c = (uint32_t)(j * nu + (i + 1) % nu);
            uint32_t d = (uint32_t)(((j + 1) % nv) * nu + (i + 1) % nu), e = (uint32_t)(((j + 1) % nv) * nu + i);
            add_quad(b, a, c, d, e, seed, j * nu + i);
        }
}

/* The box: the cube-sphere's lattice without the projection. Points of an edge are jittered along it only. */
static void mesh_cube(builder *b, size_t triangles, double jitter, uint64_t seed)
{
    long n = (long)fmax(2, round(sqrt((double)triangles / 12.0)));
    for (int a = 0; a < 3; ++a)
        for (int s = -1; s <= 1; s += 2) {
            int u = (a + 1) % 3, v = (a + 2) % 3;
            if (s < 0) {
                int t = u;
                u = v;
                v = t;
            }
            uint32_t *ids = malloc((size_t)(n + 1) * (size_t)(n + 1) * sizeof(uint32_t));
            if (!ids) {
                b->failed = 1;
                return;
            }
            for (long j = 0; j <= n; ++j)
                for (long i = 0; i <= n; ++i) {
                    long lat[3];
                    lat[a] = s > 0 ? n : 0;
                    lat[u] = i;
                    lat[v] = j;
                    double c[3];
                    for (int k = 0; k < 3; ++k)
                        c[k] = grid_coord(lat[k], n, jitter, lattice_jitter(seed, lat[0], lat[1], lat[2], k));
                    ids[j * (n + 1) + i] = add_vertex(b, c[0], c[1], c[2], c[u], c[v]);
                }
            for (long j = 0; j < n; ++j)
                for (long i = 0; i < n; ++i)
                    add_quad(b, ids[j * (n + 1) + i], ids[j * (n + 1) + i + 1], ids[(j + 1) * (n + 1) + i + 1],
                             ids[(j + 1) * (n + 1) + i], seed, ((a * 2 + (s > 0)) * (n + 1) + j) * (n + 1) + i);
            free(ids);
        }
}

/* Point i of nu on the unit circle (at height z): computed from the index alone, so that the wall's rim and the
 * caps' rims are bit-identical and weld. */
static uint32_t add_rim_point(builder *b, long i, long nu, double z, double u, double v)
{
    double phi = 2 * M_PI * (double)(i % nu) / (double)nu;
    return add_vertex(b, cos(phi), sin(phi), z, u, v);
}

/* A cap: the square grid [−1,1]² (n even, jittered inside) mapped onto the unit disk by Shirley and Chiu's
 * concentric map, which takes the square's boundary points, evenly spaced, to evenly spaced angles: point k of the
 * rim is at angle 2πk/(4n), as on the wall. */
static void mesh_cap(builder *b, long n, double z, double jitter, uint64_t seed)
{
    uint32_t *ids = malloc((size_t)(n + 1) * (size_t)(n + 1) * sizeof(uint32_t));
    if (!ids) {
        b->failed = 1;
        return;
    }
    long nu = 4 * n;
    for (long j = 0; j <= n; ++j)
        for (long i = 0; i <= n; ++i) {
            double x = grid_coord(i, n, jitter, lattice_jitter(seed, i, j, z > 0 ? 5 : 6, 0));
            double y = grid_coord(j, n, jitter, lattice_jitter(seed, i, j, z > 0 ? 5 : 6, 1));
            double r, phi;
            if (fabs(x) >= fabs(y))
                r = x, phi = x == 0 ? 0 : (M_PI / 4) * (y / x);
            else
                r = y, phi = M_PI / 2 - (M_PI / 4) * (x / y);
            uint32_t id;
            if (i == 0 || j == 0 || i == n || j == n) {
                double angle = atan2(r * sin(phi), r * cos(phi));
                long k = lround(angle / (2 * M_PI / (double)nu));
                id = add_rim_point(b, (k % nu + nu) % nu, nu, z, x, y);
            } else {
                id = add_vertex(b, r * cos(phi), r * sin(phi), z, x, y);
            }
            ids[j * (n + 1) + i] = id;
        }
    size_t first = b->triangle_count;
    for (long j = 0; j < n; ++j)
        for (long i = 0; i < n; ++i)
            add_quad(b, ids[j * (n + 1) + i], ids[j * (n + 1) + i + 1], ids[(j + 1) * (n + 1) + i + 1],
                     ids[(j + 1) * (n + 1) + i], seed, (z > 0 ? 0 : n * n) + j * n + i);
    for (size_t t = first; z < 0 && !b->failed && t < b->triangle_count; ++t) { /* seen from below */
        uint32_t *tri = b->indices + 3 * t, x = tri[1];
        tri[1] = tri[2], tri[2] = x;
    }
    free(ids);
}

static void mesh_capped_cylinder(builder *b, size_t triangles, double jitter, uint64_t seed)
{
    /* caps 2 × 2n², wall 2 × 4n × nz with nz ≈ 4n/π (square cells): about 14.2 n² triangles; n even */
    long n = 2 * (long)fmax(1, round(sqrt((double)triangles / 14.2) / 2));
    long nu = 4 * n, nz = (long)fmax(2, round(4.0 * (double)n / M_PI));
    b->period = 0; /* the wall's quads are oriented here, not by parameters */
    uint32_t *ids = malloc((size_t)(nz + 1) * (size_t)nu * sizeof(uint32_t));
    if (!ids) {
        b->failed = 1;
        return;
    }
    for (long j = 0; j <= nz; ++j)
        for (long i = 0; i < nu; ++i) {
            double z = grid_coord(j, nz, jitter, lattice_jitter(seed, i, j, 4, 1));
            if (j == 0 || j == nz) {
                ids[j * nu + i] = add_rim_point(b, i, nu, z, 0, 0);
                continue;
            }
            double su = 2 * M_PI * ((double)i + jitter * lattice_jitter(seed, i, j, 4, 0)) / (double)nu;
            ids[j * nu + i] = add_vertex(b, cos(su), sin(su), z, 0, 0);
        }
    for (long j = 0; j < nz; ++j)
        for (long i = 0; i < nu; ++i) {
            uint32_t a = ids[j * nu + i], c = ids[j * nu + (i + 1) % nu], d = ids[(j + 1) * nu + (i + 1) % nu],
                     e = ids[(j + 1) * nu + i];
            if (lattice_jitter(seed, i, j, 4, 3) < 0) { /* jitter is under half a cell: both diagonals are fine */
                add_triangle(b, a, c, d);
                add_triangle(b, a, d, e);
            } else {
                add_triangle(b, a, c, e);
                add_triangle(b, c, d, e);
            }
        }
    free(ids);
    mesh_cap(b, n, 1, jitter, seed);
    mesh_cap(b, n, -1, jitter, seed);
}

static void mesh_cylinder(builder *b, size_t triangles, double jitter, uint64_t seed)
{
    /* Circumference 2π, height 2: cells roughly square. */
    long nz = (long)fmax(2, round(sqrt((double)triangles / (2.0 * M_PI))));
    long nu = (long)fmax(3, round((double)triangles / (2.0 * (double)nz)));
    for (long j = 0; j <= nz; ++j)
        for (long i = 0; i < nu; ++i) {
            double su = 2 * M_PI * (i + jitter * lattice_jitter(seed, i, j, 1, 0)) / (double)nu;
            double z = grid_coord(j, nz, jitter, lattice_jitter(seed, i, j, 1, 1));
            add_vertex(b, cos(su), sin(su), z, su, z);
        }
    for (long j = 0; j < nz; ++j)
        for (long i = 0; i < nu; ++i) {
            uint32_t a = (uint32_t)(j * nu + i), c = (uint32_t)(j * nu + (i + 1) % nu);
            uint32_t d = (uint32_t)((j + 1) * nu + (i + 1) % nu), e = (uint32_t)((j + 1) * nu + i);
            add_quad(b, a, c, d, e, seed, j * nu + i);
        }
}

static void mesh_graph(builder *b, shape_kind kind, size_t triangles, double jitter, uint64_t seed)
{
    long n = (long)fmax(2, round(sqrt((double)triangles / 2.0)));
    for (long j = 0; j <= n; ++j)
        for (long i = 0; i <= n; ++i) {
            double x = grid_coord(i, n, jitter, lattice_jitter(seed, i, j, 2, 0));
            double y = grid_coord(j, n, jitter, lattice_jitter(seed, i, j, 2, 1));
            double fx, fy, fxx, fxy, fyy;
            add_vertex(b, x, y, graph_f(kind, x, y, &fx, &fy, &fxx, &fxy, &fyy), x, y);
        }
    for (long j = 0; j < n; ++j)
        for (long i = 0; i < n; ++i)
            add_quad(b, (uint32_t)(j * (n + 1) + i), (uint32_t)(j * (n + 1) + i + 1),
                     (uint32_t)((j + 1) * (n + 1) + i + 1), (uint32_t)((j + 1) * (n + 1) + i), seed, j * n + i);
}

/* Exact weld by sorting: the generator's duplicates are bit-identical, so equal coordinates suffice. */
typedef struct sort_key {
    double p[3];
    uint32_t index;
} sort_key;

static int compare_key(const void *a, const void *b)
{
    const sort_key *p = a, *q = b;
    for (int k = 0; k < 3; ++k)
        if (p->p[k] != q->p[k])
            return p->p[k] < q->p[k] ? -1 : 1;
    return p->index < q->index ? -1 : 1;
}

static int weld_sorted(const double *positions, size_t n, uint32_t *remap, size_t *out_count)
{
    sort_key *keys = malloc((n ? n : 1) * sizeof *keys);
    uint32_t *first = malloc((n ? n : 1) * sizeof *first);
    if (!keys || !first) {
        free(keys);
        free(first);
        return -1;
    }
    for (size_t i = 0; i < n; ++i) {
        memcpy(keys[i].p, positions + 3 * i, sizeof keys[i].p);
        keys[i].index = (uint32_t)i;
    }
    qsort(keys, n, sizeof *keys, compare_key);
    for (size_t i = 0, j; i < n; i = j) {
        for (j = i; j < n && memcmp(keys[j].p, keys[i].p, sizeof keys[i].p) == 0; ++j)
            first[keys[j].index] = keys[i].index; /* keys[i] holds the lowest index of the run */
    }
    /* Number positions in order of first appearance, so the result does not depend on the sort. */
    size_t count = 0;
    for (size_t v = 0; v < n; ++v)
        remap[v] = first[v] == v ? (uint32_t)count++ : remap[first[v]];
    *out_count = count;
    free(first);
    free(keys);
    return 0;
}

resurf_mesh *shape_mesh(shape_kind kind, size_t triangles, double jitter, uint64_t seed, int with_normals)
{
    builder b = {0};
    if (jitter < 0)
        jitter = 0;
    if (jitter > 0.45)
        jitter = 0.45;
    switch (kind) {
    case SHAPE_SPHERE:
        mesh_sphere(&b, triangles, jitter, seed);
        break;
    case SHAPE_TORUS:
        b.period = 2 * M_PI;
        mesh_torus(&b, triangles, jitter, seed);
        break;
    case SHAPE_CYLINDER:
        b.period = 2 * M_PI;
        mesh_cylinder(&b, triangles, jitter, seed);
        break;
    case SHAPE_CUBE:
        mesh_cube(&b, triangles, jitter, seed);
        break;
    case SHAPE_CAPPED_CYLINDER:
        mesh_capped_cylinder(&b, triangles, jitter, seed);
        break;
    default:
        if (!is_graph(kind))
            return NULL;
        mesh_graph(&b, kind, triangles, jitter, seed);
        break;
    }
    resurf_mesh *m = NULL;
    uint32_t *remap = NULL;
    if (b.failed)
        goto done;
    /* Weld duplicated lattice points (the sphere's, the cube's and the capped cylinder's rims). */
    remap = malloc((b.vertex_count ? b.vertex_count : 1) * sizeof(uint32_t));
    size_t unique = 0;
    if (!remap || weld_sorted(b.positions, b.vertex_count, remap, &unique) != 0)
        goto done;
    if (resurf_mesh_create(unique, b.triangle_count, with_normals ? RESURF_ATTR_NORMALS : 0, &m, NULL) != RESURF_OK)
        goto done;
    for (size_t v = 0; v < b.vertex_count; ++v)
        memcpy(m->positions + 3 * (size_t)remap[v], b.positions + 3 * v, 3 * sizeof(double));
    for (size_t i = 0; i < 3 * b.triangle_count; ++i)
        m->indices[i] = remap[b.indices[i]];
    if (with_normals)
        for (size_t v = 0; v < unique; ++v)
            shape_normal(kind, m->positions + 3 * v, m->normals + 3 * v);
done:
    free(remap);
    free(b.positions);
    free(b.params);
    free(b.indices);
    return m;
}
