/* The restoring projection: move points (the vertices of a processed mesh M') onto the smooth surface S that the
 * original mesh M approximates. Semenova, Savchenko, Hagiwara, "Reconstruction of Shapes Based on Normals
 * Analysis" (§3), with the open points fixed as in docs/restoring.md (§3–§7) and the normal-section variant of
 * its §9.
 *
 * Per point p, repeated `iterations` times (or until the step is below tolerance_rel × local edge length):
 *   1. the closest triangle T of M (BVH, exact);
 *   2. the optimal direction: the root of the cubic of optdir.c, inside T if possible (else the policy decides:
 *      search the triangles around T for a root inside them, take the least-outside root, or stop). Zero-area
 *      triangles and triangles with a corner without normal carry no root: the search goes around them;
 *   3. N_opt = normalize(Σ b_j N_j), and for each corner the gliding-normal displacement δ_j (glide.c), with the
 *      max/min side chosen by the principal curvatures at the corner (the paper) or by the local chord rule;
 *   4. p ← p + k Σ δ_j N_opt.
 * From the second step on, steps 1–2 start from the previous root's triangle: if Newton steps on its cubic find a
 * root still inside it, that root is used. Near S the lines p0 + t n(p0) of neighbouring triangles do not cross, so
 * an inside root is the only one and the closest-triangle search would find the same; it is run only when the root
 * has left the triangle. This saves a tree walk and a cubic solve per step (the paper's 5 steps cost little more
 * than one).
 *
 * Where S is not smooth (docs/restoring.md §7):
 *   - Creases: an edge whose faces' normals differ by more than crease_angle_deg (or, with input_normals, whose
 *     input normals are split along it) is a crease. At each vertex the incident faces are grouped into fans
 *     separated by crease (and non-manifold) edges; each fan gets its own normal and curvature, computed on the mesh
 *     split along the creases, and a triangle takes each corner's normal from its own fan. So a point next to a
 *     crease is restored with the normals of its own side and the crease is not rounded off.
 *   - Feature curves: boundary edges (with `boundary`) and crease edges. A point whose closest point on M lies on a
 *     feature edge (the barycentric of the opposite corner is 0), or on a vertex that has feature edges, is put on
 *     the feature curve instead: the curve between the edge's ends a, b is the blend (1 − u) A(u) + u B(u) of the
 *     circular arc through a and b tangent to the curve at a (A) and the one tangent at b (B), u being the
 *     parameter of p's projection on the chord (clamped to [0, 1]). The curve tangent at a vertex is that of the
 *     circle through it and its two curve neighbours, exact on circles (the 1-D analogue of Max's normals); at a
 *     curve end, a vertex with more than two feature edges, a vertex where boundary meets crease or where the curve
 *     turns by more than crease_angle_deg, the curve has a corner and the chord direction is used. A point at a
 *     feature vertex goes to the feature edge that points most towards it, or stays on the vertex.
 *   - Far points: farther from M than far_factor × the local edge length (the largest mean incident edge length of
 *     the closest triangle's corners) are left where they are.
 *   - A point that coincides with a vertex of M (to 1e-12 of the local edge length) is on S already (M's vertices
 *     sample S) and stays where it is: restoring M onto itself changes nothing.
 *
 * M is welded exactly first (resurfi_weld_exact) so that attribute seams neither split normals nor look like
 * boundaries. Each point's result depends only on its position and M, so results are the same whatever the thread
 * count and identical positions (seams of M') move together. */
#include <stdlib.h>
#include <string.h>

#include "restore_internal.h"

/* The services over M that a point reads (fans, normals, feature curves, quiet and usable triangles) are built once
 * by restore_setup.c. */

enum {
    CHUNK_VERTICES = 1 << 15, /* vertices between two progress reports */
    BLOCK_VERTICES = 256,     /* parallel block: small enough to balance, large enough to amortise the hand-out */
};

/* A barycentric at or below this is zero: the closest point lies on the opposite edge (Ericson's region test in
 * resurfi_closest_on_triangle gives exact zeros there). */
static const double foot_zero = 1e-12;

/* ---- one point ----------------------------------------------------------------------------------------------- */

/* The feature-curve tangent at position v (zero off curves and at corners). */
static vec3 tangent_at(const resurfi_restorer *r, uint32_t v)
{
    uint32_t first = r->feature_offset[v];
    return r->feature_offset[v + 1] - first == 2 ? v3_load(r->tangent + 3 * (size_t)first) : v3(0, 0, 0);
}

static vec3 corner_normal(const resurfi_restorer *r, uint32_t t, int k)
{
    return v3_load(r->split_normals + 3 * (size_t)r->corner_split[3 * (size_t)t + k]);
}

vec3 resurfi_restorer_normal(const resurfi_restorer *r, uint32_t t, const double bary[3])
{
    vec3 n = v3(0, 0, 0);
    for (int k = 0; k < 3; ++k)
        n = v3_madd(n, corner_normal(r, t, k), bary[k]);
    return v3_normalize(n);
}

/* The local edge length at triangle t: the largest mean edge length of its corners. */
static double local_length(const resurfi_restorer *r, uint32_t t)
{
    const uint32_t *i = r->tris + 3 * (size_t)t;
    return dmax(dmax(r->local_length[i[0]], r->local_length[i[1]]), r->local_length[i[2]]);
}

/* Height above the chord, at chord coordinate x from its midpoint, of the circular arc through both chord ends
 * (length L) that leaves an end at angle φ to the chord: (L²/4 − x²) / (R (√(1 − x²/R²) + cos φ)) with
 * 1/R = 2 sin φ / L, a form that stays accurate as φ → 0. Tangents pointing backwards give a straight chord. */
static double arc_height(double L, double x, double sin_phi, double cos_phi)
{
    if (!(cos_phi > 0) || !(L > 0))
        return 0;
    double inv_r = 2 * sin_phi / L;
    double q = 1 - x * x * inv_r * inv_r;
    return (0.25 * L * L - x * x) * inv_r / (sqrt(q > 0 ? q : 0) + cos_phi);
}

/* The point of the feature curve over edge (a, b) at the projection of p on its chord (see the file comment). */
static vec3 curve_point(const resurfi_restorer *r, uint32_t a, uint32_t b, vec3 p)
{
    vec3 pa = position(r, a), pb = position(r, b);
    vec3 chord = v3_sub(pb, pa);
    double L = v3_len(chord);
    if (!(L > 0))
        return pa;
    vec3 e = v3_scale(chord, 1 / L);
    double u = v3_dot(v3_sub(p, pa), e) / L;
    u = u < 0 ? 0 : u > 1 ? 1 : u;
    vec3 q = v3_madd(pa, chord, u);
    if (u == 0)
        return pa;
    if (u == 1)
        return pb;
    double x = (u - 0.5) * L;
    for (int end = 0; end < 2; ++end) {
        vec3 t = tangent_at(r, end ? b : a);
        if (v3_len2(t) == 0)
            continue; /* a corner: no bend from this end */
        double c = v3_dot(t, e);
        if (c < 0) { /* the stored tangent has no orientation */
            t = v3_neg(t);
            c = -c;
        }
        vec3 side = v3_madd(t, e, -c); /* sin φ times the bulge direction (reversed at the far end) */
        double s = v3_len(side);
        if (!(s > 0))
            continue;
        double h = arc_height(L, x, s, c);
        double w = end ? u : 1 - u;
        q = v3_madd(q, side, (end ? -h : h) * w / s);
    }
    return q;
}

/* Where on triangle t the foot with barycentrics bary lies: returns 0 inside, 1 on an edge (side index in *which,
 * side k joins corners k and k+1), 2 at a corner (corner index in *which). */
static int foot_location(const double bary[3], int *which)
{
    int zeros = 0, zero = 0, nonzero = 0;
    for (int k = 0; k < 3; ++k) {
        if (bary[k] <= foot_zero)
            ++zeros, zero = k;
        else
            nonzero = k;
    }
    if (zeros == 1) {
        *which = (zero + 1) % 3;
        return 1;
    }
    if (zeros >= 2) {
        *which = nonzero;
        return 2;
    }
    return 0;
}

/* If the foot of p on triangle t lies on a feature curve, put p on it and say which kind (else FEATURE_NONE). */
static int restore_on_feature(const resurfi_restorer *r, uint32_t t, const double bary[3], vec3 p, vec3 *out)
{
    int which;
    int where = foot_location(bary, &which);
    if (where == 1) {
        int kind = (r->side_kind[t] >> (2 * which)) & 3;
        if (!kind)
            return FEATURE_NONE;
        uint32_t a = r->tris[3 * (size_t)t + which], b = r->tris[3 * (size_t)t + (which + 1) % 3];
        *out = curve_point(r, a < b ? a : b, a < b ? b : a, p); /* the edge's own order: both sides agree */
        return kind;
    }
    if (where == 2) {
        uint32_t v = r->tris[3 * (size_t)t + which];
        uint32_t first = r->feature_offset[v], last = r->feature_offset[v + 1];
        if (first == last)
            return FEATURE_NONE;
        /* the feature edge pointing most towards p, if any points towards it */
        vec3 pv = position(r, v);
        uint32_t best = first;
        double best_score = -INFINITY;
        for (uint32_t i = first; i < last; ++i) {
            vec3 d = v3_sub(position(r, r->feature_vertex[i]), pv);
            double l = v3_len(d);
            double score = l > 0 ? v3_dot(v3_sub(p, pv), d) / l : -INFINITY;
            if (score > best_score)
                best_score = score, best = i;
        }
        *out = best_score > 0 ? curve_point(r, v, r->feature_vertex[best], p) : pv;
        return r->feature_kind[best];
    }
    return FEATURE_NONE;
}

/* The roots of the optimal direction on triangle t. */
static int solve_on(const resurfi_restorer *r, uint32_t t, vec3 p, resurfi_optdir_root roots[3])
{
    vec3 pj[3], nj[3];
    for (int k = 0; k < 3; ++k) {
        pj[k] = position(r, r->tris[3 * (size_t)t + k]);
        nj[k] = corner_normal(r, t, k);
    }
    return resurfi_optdir_solve(p, pj, nj, roots);
}

/* The root on triangle t nearest the parameter t_guess (see resurfi_optdir_near). */
static int near_on(const resurfi_restorer *r, uint32_t t, vec3 p, double t_guess, resurfi_optdir_root *out)
{
    vec3 pj[3], nj[3];
    for (int k = 0; k < 3; ++k) {
        pj[k] = position(r, r->tris[3 * (size_t)t + k]);
        nj[k] = corner_normal(r, t, k);
    }
    return resurfi_optdir_near(p, pj, nj, t_guess, out);
}

typedef struct root_choice {
    uint32_t triangle; /* UINT32_MAX: none yet */
    resurfi_optdir_root root;
} root_choice;

static int is_inside(const resurfi_optdir_root *root) { return root->outside <= RESURFI_OPTDIR_INSIDE_TOL; }

/* Keeps the better of best and (t, root): inside before outside, then smallest |t| (inside) or least outside. */
static void consider(root_choice *best, uint32_t t, const resurfi_optdir_root *root)
{
    if (best->triangle != UINT32_MAX) {
        int in_new = is_inside(root), in_old = is_inside(&best->root);
        if (in_new != in_old ? !in_new
                             : in_new ? !(fabs(root->t) < fabs(best->root.t)) : !(root->outside < best->root.outside))
            return;
    }
    best->triangle = t;
    best->root = *root;
}

/* The optimal direction for p, starting at its closest triangle t: an inside root there, else (when the policy
 * searches) the best root over the triangles around t's corners (the ties of a point nearest a vertex or an edge).
 * Returns 0 when there is no root at all. */
static int choose_root(const resurfi_restorer *r, uint32_t t, vec3 p, root_choice *out)
{
    resurfi_optdir_root roots[3];
    out->triangle = UINT32_MAX;
    if (r->usable[t] && solve_on(r, t, p, roots) > 0) {
        consider(out, t, &roots[0]);
        if (is_inside(&roots[0]) || r->opt.outside == RESURF_OUTSIDE_LEAST)
            return 1;
    }
    const uint32_t *tri = r->tris + 3 * (size_t)t;
    for (int k = 0; k < 3; ++k) {
        uint32_t v = tri[k];
        const uint32_t *faces = r->adj.vertex_faces + r->adj.vertex_face_offset[v];
        uint32_t n = r->adj.vertex_face_offset[v + 1] - r->adj.vertex_face_offset[v];
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t f = faces[i];
            if (f == t)
                continue;
            int seen = 0; /* already visited through an earlier corner of t */
            for (int j = 0; j < k; ++j)
                seen |= corner_of(r, f, tri[j]) >= 0;
            if (seen || !r->usable[f])
                continue;
            if (solve_on(r, f, p, roots) > 0)
                consider(out, f, &roots[0]);
        }
    }
    return out->triangle != UINT32_MAX;
}

/* Max (+1) or min (−1) algorithm at corner k of triangle t (docs/restoring.md §5). */
static int corner_side(const resurfi_restorer *r, uint32_t t, int k, vec3 p, vec3 pj, vec3 nj, vec3 n_opt, vec3 p0)
{
    if (r->opt.side_rule == RESURF_SIDE_LOCAL || !r->k1)
        return v3_dot(v3_sub(n_opt, nj), v3_sub(p0, pj)) < 0 ? -1 : +1;
    /* the paper: convex (both curvatures > 0) max, concave min, otherwise the sign of the normal curvature in the
     * direction from the corner towards p, projected on the corner's tangent plane */
    size_t s = r->corner_split[3 * (size_t)t + k];
    double k1 = r->k1[s], k2 = r->k2[s];
    if (k2 > 0)
        return +1;
    if (k1 < 0)
        return -1;
    vec3 d = v3_sub(p, pj);
    d = v3_madd(d, nj, -v3_dot(d, nj));
    double c1 = v3_dot(d, v3_load(r->dir1 + 3 * s)), c2 = v3_dot(d, v3_load(r->dir2 + 3 * s));
    double kn = k1 * c1 * c1 + k2 * c2 * c2;
    if (c1 == 0 && c2 == 0)
        kn = k1 + k2;
    return kn < 0 ? -1 : +1;
}

/* The closest triangle to p. A triangle `hint` near p (or UINT32_MAX) bounds the tree walk by its distance: the
 * answer is the same (the tree returns the lowest-index triangle among those at the least distance, and the hint is
 * within reach), only found sooner. */
static uint32_t closest_triangle(const resurfi_restorer *r, vec3 p, uint32_t hint, double bary[3], double *dist2)
{
    double reach2 = INFINITY;
    if (hint != UINT32_MAX) {
        const uint32_t *i = r->tris + 3 * (size_t)hint;
        vec3 q = resurfi_closest_on_triangle(p, position(r, i[0]), position(r, i[1]), position(r, i[2]), NULL);
        reach2 = v3_dist2(p, q);
    }
    uint32_t t = resurfi_bvh_closest(r->bvh, p, reach2, NULL, bary, dist2);
    if (t == UINT32_MAX && reach2 < INFINITY) /* a hint in a part the tree skipped (non-finite corners) */
        t = resurfi_bvh_closest(r->bvh, p, INFINITY, NULL, bary, dist2);
    return t;
}

enum { WALK_STEPS = 64 };

/* The closest of the triangles around t's corners (t included) to p, and p's closest point on it. Each triangle is
 * measured once: at the first of t's corners it has (a third of the work of measuring t and its edge neighbours
 * again at each corner). */
static uint32_t closest_around(const resurfi_restorer *r, vec3 p, uint32_t t, double bary[3], double *dist2)
{
    const uint32_t *tri = r->tris + 3 * (size_t)t;
    uint32_t best = UINT32_MAX;
    *dist2 = INFINITY;
    for (int k = 0; k < 3; ++k) {
        const uint32_t *faces = r->adj.vertex_faces + r->adj.vertex_face_offset[tri[k]];
        uint32_t n = r->adj.vertex_face_offset[tri[k] + 1] - r->adj.vertex_face_offset[tri[k]];
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t f = faces[i];
            const uint32_t *c = r->tris + 3 * (size_t)f;
            int seen = 0;
            for (int j = 0; j < k; ++j)
                seen |= c[0] == tri[j] || c[1] == tri[j] || c[2] == tri[j];
            if (seen)
                continue;
            double b[3];
            vec3 q = resurfi_closest_on_triangle(p, position(r, c[0]), position(r, c[1]), position(r, c[2]), b);
            double d2 = v3_dist2(p, q);
            if (d2 < *dist2 || (d2 == *dist2 && f < best)) {
                best = f, *dist2 = d2;
                memcpy(bary, b, sizeof b);
            }
        }
    }
    return best;
}

/* The triangle across t's side (v1, v2): the one other face with both; UINT32_MAX when there is none or more. */
static uint32_t across(const resurfi_restorer *r, uint32_t t, uint32_t v1, uint32_t v2)
{
    const uint32_t *faces = r->adj.vertex_faces + r->adj.vertex_face_offset[v1];
    uint32_t nf = r->adj.vertex_face_offset[v1 + 1] - r->adj.vertex_face_offset[v1], next = UINT32_MAX;
    int shared = 0;
    for (uint32_t i = 0; i < nf; ++i)
        if (faces[i] != t && corner_of(r, faces[i], v2) >= 0)
            next = faces[i], ++shared;
    return shared == 1 ? next : UINT32_MAX;
}

/* Quiet triangle t (corners c, normal n unscaled) holds the projection q of p, and only side j (opposite c_j) is
 * nearer to q than p's height h over t. Around each corner the other faces project into the cone beside t's
 * (quiet_geometry_block). Around c_j that cone lies beyond two far sides; around either end a of side j, beyond
 * the face g across side j lies a cone bounded by the ray from a through g's third corner z (projected) and by t's
 * far side at a. So when q is farther than h from both such rays, only g can be nearer than t. Returns t when it
 * is the nearest (bary, dist2 as closest_around gives them), UINT32_MAX when that is not shown. */
static uint32_t nearest_beside_one_side(const resurfi_restorer *r, vec3 p, uint32_t t, const vec3 c[3], vec3 n,
                                        int j, double bary[3], double *dist2)
{
    const uint32_t *tri = r->tris + 3 * (size_t)t;
    uint32_t g = across(r, t, tri[(j + 1) % 3], tri[(j + 2) % 3]);
    if (g == UINT32_MAX)
        return UINT32_MAX;
    const uint32_t *gi = r->tris + 3 * (size_t)g;
    uint32_t zi = gi[3 - corner_of(r, g, tri[(j + 1) % 3]) - corner_of(r, g, tri[(j + 2) % 3])]; /* g's far corner */
    double n2 = v3_len2(n);
    vec3 q = v3_madd(p, n, -v3_dot(n, v3_sub(p, c[0])) / n2);
    vec3 z = position(r, zi);
    z = v3_madd(z, n, -v3_dot(n, v3_sub(z, c[0])) / n2);
    double h2 = v3_dist2(p, q) * (1 + 1e-8);
    for (int e = 1; e <= 2; ++e) {
        vec3 a = c[(j + e) % 3], w = v3_sub(z, a), u = v3_sub(q, a);
        double along = v3_dot(u, w), w2 = v3_len2(w);
        double ray2 = along <= 0 || !(w2 > 0) ? v3_len2(u) : v3_len2(u) - along * (along / w2);
        if (!(ray2 > h2))
            return UINT32_MAX;
    }
    /* t against g, as closest_around compares them (ties to the lower index) */
    double bt[3], bg[3];
    double dt = v3_dist2(p, resurfi_closest_on_triangle(p, c[0], c[1], c[2], bt));
    double dg = v3_dist2(p, resurfi_closest_on_triangle(p, position(r, gi[0]), position(r, gi[1]),
                                                        position(r, gi[2]), bg));
    if (!(dt < dg || (dt == dg && t < g)))
        return UINT32_MAX;
    memcpy(bary, bt, sizeof bt);
    *dist2 = dt;
    return t;
}

/* p's closest triangle found by walking M from `start` (a triangle near p) across the side opposite the most
 * negative barycentric of p's projection, to the triangle p projects on (where no triangle holds the projection,
 * at a convex vertex or a crease, the walk turns back; it also stops at a border, a non-manifold edge, a degenerate
 * triangle or after WALK_STEPS), then down to the nearest of the triangles around until none is nearer (where M is
 * concave, seen from p, a neighbour of the projection's triangle can be). For a point near S, far nearer than the
 * thickness of any part of the shape, that is its closest triangle; where the shape is thin it is the closest one
 * of the sheet `start` is on. The walk reads only the triangles on its way, where a tree search reads a path from
 * the root and the leaves around, mostly cache misses on a large mesh: the simplifier's inline restoration of a
 * 1M-triangle torus takes 2.9 s instead of 3.3. */
static uint32_t walk_closest(const resurfi_restorer *r, vec3 p, uint32_t start, double bary[3], double *dist2)
{
    uint32_t t = start, prev = UINT32_MAX;
    for (int step = 0; step < WALK_STEPS; ++step) {
        const uint32_t *tri = r->tris + 3 * (size_t)t;
        vec3 c[3] = {position(r, tri[0]), position(r, tri[1]), position(r, tri[2])};
        vec3 n = v3_tri_cross(c[0], c[1], c[2]);
        if (!(v3_len2(n) > 0))
            break;
        double lambda[3];
        for (int k = 0; k < 3; ++k) /* signed areas of the projection's sub-triangles (p's height drops out) */
            lambda[k] = v3_dot(n, v3_cross(v3_sub(c[(k + 1) % 3], p), v3_sub(c[(k + 2) % 3], p)));
        int k = lambda[0] <= lambda[1] && lambda[0] <= lambda[2] ? 0 : lambda[1] <= lambda[2] ? 1 : 2;
        if (lambda[k] >= 0) {
            /* The projection q is inside t. With t quiet, every other triangle around projects outside t
             * (quiet_geometry_block), so lies at least q's distance to t's sides from p: when that beats p's
             * height over t, t is the nearest and the descent would only confirm it. λ_k / |n| is twice the area
             * of q's sub-triangle, so q's distance to side k is λ_k / (|n| |side k|), its height |n·(p − c0)| / |n|. */
            if (r->quiet[t]) {
                double height = fabs(v3_dot(n, v3_sub(p, c[0]))) * (1 + 1e-9);
                int near = -1, near_count = 0;
                for (int j = 0; j < 3; ++j)
                    if (!(height * v3_dist(c[(j + 1) % 3], c[(j + 2) % 3]) < lambda[j]))
                        near = j, ++near_count;
                if (near_count == 0) {
                    *dist2 = v3_dist2(p, resurfi_closest_on_triangle(p, c[0], c[1], c[2], bary));
                    return t;
                }
                if (near_count == 1 && nearest_beside_one_side(r, p, t, c, n, near, bary, dist2) == t)
                    return t;
            }
            break;
        }
        uint32_t next = across(r, t, tri[(k + 1) % 3], tri[(k + 2) % 3]);
        if (next == UINT32_MAX || next == prev)
            break;
        prev = t;
        t = next;
    }
    /* Where M is concave (seen from p) a neighbour may be nearer: down to the nearest of the triangles around until
     * none is. */
    for (int round = 0; round < WALK_STEPS; ++round) {
        uint32_t u = closest_around(r, p, t, bary, dist2);
        if (u == t)
            break;
        t = u;
    }
    return t;
}

void resurfi_restorer_prefetch(const resurfi_restorer *r, uint32_t t, int stage)
{
    if (t >= r->triangle_count)
        return;
    const uint32_t *tri = r->tris + 3 * (size_t)t;
    if (stage == 0) {
        PREFETCH(tri);
        return;
    }
    PREFETCH(r->corner_split + 3 * (size_t)t);
    for (int k = 0; k < 3; ++k) {
        PREFETCH(r->positions + 3 * (size_t)tri[k]);
        PREFETCH(r->adj.vertex_face_offset + tri[k]);
    }
}

uint32_t resurfi_restorer_closest_walk(const resurfi_restorer *r, vec3 p, uint32_t start, double bary[3],
                                       double *dist2)
{
    if (start >= r->triangle_count || !v3_finite(p))
        return UINT32_MAX;
    return walk_closest(r, p, start, bary, dist2);
}

resurfi_restore_outcome resurfi_restorer_point(const resurfi_restorer *r, vec3 p, vec3 *out_point,
                                               uint32_t *out_triangle, double out_bary[3])
{
    return resurfi_restorer_point_near(r, p, UINT32_MAX, out_point, out_triangle, out_bary);
}

static resurfi_restore_outcome restore_from(const resurfi_restorer *r, vec3 p, uint32_t hint, int walk,
                                            vec3 *out_point, uint32_t *out_triangle, double out_bary[3]);

resurfi_restore_outcome resurfi_restorer_point_near(const resurfi_restorer *r, vec3 p, uint32_t hint,
                                                    vec3 *out_point, uint32_t *out_triangle, double out_bary[3])
{
    return restore_from(r, p, hint, 0, out_point, out_triangle, out_bary);
}

resurfi_restore_outcome resurfi_restorer_point_walk(const resurfi_restorer *r, vec3 p, uint32_t start,
                                                    vec3 *out_point, uint32_t *out_triangle, double out_bary[3])
{
    return restore_from(r, p, start, 1, out_point, out_triangle, out_bary);
}

static resurfi_restore_outcome restore_from(const resurfi_restorer *r, vec3 p, uint32_t hint, int walk,
                                            vec3 *out_point, uint32_t *out_triangle, double out_bary[3])
{
    if (hint >= r->triangle_count)
        hint = UINT32_MAX;
    *out_point = p;
    if (out_triangle)
        *out_triangle = UINT32_MAX;
    if (!v3_finite(p))
        return RESURFI_LEFT_NONFINITE;
    const resurf_restore_options *o = &r->opt;
    resurfi_restore_outcome outcome = RESURFI_RESTORED;
    vec3 cur = p;
    uint32_t chosen = UINT32_MAX; /* the triangle of the previous step's root */
    double len = 0, t_guess = 0;
    /* The normal section's glides with the whole mean step (1/3 of the sum of three) land where the next iteration
     * would not move: the point moves along the root's line, so the root stays, and each glide drops by exactly the
     * distance moved (its part across n_opt does not change). From a root inside its triangle, that check is
     * skipped. */
    int full_step_rule = o->displacement == RESURF_DISPLACEMENT_NORMAL_SECTION && 3 * o->step == 1;
    for (unsigned it = 0; it < o->iterations; ++it) {
        root_choice c = {.triangle = UINT32_MAX};
        resurfi_optdir_root roots[3];
        /* After the first step, the previous root's triangle usually still holds the root: near S the lines
         * p0 + t n(p0) of neighbouring triangles do not cross, so a root inside a triangle is the only one and
         * finding it from the closest triangle would give the same answer at the price of a tree walk and a
         * cubic solve; a few Newton steps from the previous root find it. */
        if (chosen != UINT32_MAX && near_on(r, chosen, cur, t_guess, &roots[0]) && is_inside(&roots[0])) {
            c.triangle = chosen;
            c.root = roots[0];
            len = local_length(r, chosen);
        } else {
            double bary[3], dist2;
            uint32_t from = chosen != UINT32_MAX ? chosen : hint, t = UINT32_MAX;
            if (walk && from != UINT32_MAX)
                t = walk_closest(r, cur, from, bary, &dist2);
            else
                t = closest_triangle(r, cur, from, bary, &dist2);
            if (t == UINT32_MAX)
                return RESURFI_LEFT_FAR; /* an empty tree */
            len = local_length(r, t);
            if (it == 0 && dist2 > (o->far_factor * len) * (o->far_factor * len))
                return RESURFI_LEFT_FAR;
            if (out_triangle)
                *out_triangle = t;
            if (out_bary)
                memcpy(out_bary, bary, sizeof bary);
            vec3 on_curve;
            int feature = restore_on_feature(r, t, bary, cur, &on_curve);
            if (feature != FEATURE_NONE) {
                cur = on_curve;
                outcome = feature == FEATURE_BOUNDARY ? RESURFI_RESTORED_BOUNDARY : RESURFI_RESTORED_CREASE;
                break;
            }
            int which;
            if (foot_location(bary, &which) == 2 && dist2 <= 1e-24 * len * len)
                break; /* on a vertex of M, so on S */
            if (!choose_root(r, t, cur, &c) || (!is_inside(&c.root) && o->outside == RESURF_OUTSIDE_KEEP)) {
                if (it == 0)
                    return RESURFI_LEFT_OUTSIDE;
                break;
            }
        }
        outcome = is_inside(&c.root) ? RESURFI_RESTORED : RESURFI_RESTORED_LEAST_OUTSIDE;
        chosen = is_inside(&c.root) ? c.triangle : UINT32_MAX;
        int full_step = full_step_rule && chosen != UINT32_MAX;
        vec3 n_opt = resurfi_restorer_normal(r, c.triangle, c.root.bary);
        if (v3_len2(n_opt) == 0)
            break;
        vec3 pj[3], nj[3], p0 = v3(0, 0, 0);
        for (int k = 0; k < 3; ++k) {
            pj[k] = position(r, r->tris[3 * (size_t)c.triangle + k]);
            nj[k] = corner_normal(r, c.triangle, k);
            p0 = v3_madd(p0, pj[k], c.root.bary[k]);
        }
        double sum = 0;
        for (int k = 0; k < 3; ++k) {
            if (o->displacement == RESURF_DISPLACEMENT_NORMAL_SECTION)
                sum += resurfi_glide_normal_section(cur, pj[k], nj[k], n_opt);
            else
                sum += resurfi_glide_paper(cur, pj[k], nj[k], n_opt,
                                           corner_side(r, c.triangle, k, cur, pj[k], nj[k], n_opt, p0));
        }
        double step = o->step * sum;
        cur = v3_madd(cur, n_opt, step);
        t_guess = c.root.t + step; /* the line's parameter moves about as much as the point along it */
        if (out_triangle)
            *out_triangle = c.triangle;
        if (out_bary)
            memcpy(out_bary, c.root.bary, sizeof c.root.bary);
        if (fabs(step) < o->tolerance_rel * len || full_step)
            break;
    }
    /* A restored point near M moves by about the sag of M's facets, a fraction of the local edge length; one that
     * went farther met normals that do not describe one smooth sheet (a fold, a thin plate seen from both sides)
     * and is left where it was, as a far point is. */
    if (v3_dist2(cur, p) > (o->far_factor * len) * (o->far_factor * len))
        return RESURFI_LEFT_FAR;
    *out_point = cur;
    return outcome;
}

/* ---- the public call ----------------------------------------------------------------------------------------- */

typedef struct restore_job {
    const resurfi_restorer *r;
    const double *in;
    double *out;
    uint8_t *outcome;
} restore_job;

static int restore_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    restore_job *j = ctx;
    uint32_t hint = UINT32_MAX; /* the previous vertex's triangle: vertices in index order are usually neighbours */
    for (size_t v = begin; v < end; ++v) {
        vec3 q;
        uint32_t t;
        j->outcome[v] = (uint8_t)resurfi_restorer_point_near(j->r, v3_load(j->in + 3 * v), hint, &q, &t, NULL);
        if (t != UINT32_MAX)
            hint = t;
        v3_store(j->out + 3 * v, q);
    }
    return 0;
}

resurf_status resurf_restore(const resurf_mesh *original, resurf_mesh *processed,
                             const resurf_restore_options *options, resurf_restore_report *out_report,
                             resurf_error *error)
{
    resurfi_clear_error(error);
    if (!original || !processed)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "%s mesh is NULL",
                             original ? "the processed" : "the original");
    resurf_status s = resurfi_restore_check_options(options, error);
    if (s != RESURF_OK)
        return s;
    resurf_restore_options opt = options ? *options : resurf_restore_options_default();
    if (resurfi_progress(&opt.progress, RESURF_STAGE_RESTORE, 0))
        return resurfi_error(error, RESURF_ERR_CANCELLED, "restore cancelled");
    resurfi_restorer *r = NULL;
    if ((s = resurfi_restorer_create(original, &opt, &r, error)) != RESURF_OK)
        return s;
    size_t n = processed->vertex_count;
    const resurf_allocator *alloc = resurfi_allocator_of(opt.allocator, original);
    double *out = resurfi_alloc(alloc, n, 3 * sizeof(double));
    uint8_t *outcome = resurfi_alloc(alloc, n, 1);
    if (!out || !outcome) {
        resurfi_free(alloc, out);
        resurfi_free(alloc, outcome);
        resurfi_restorer_free(r);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory restoring %zu vertices", n);
    }
    restore_job job = {r, processed->positions, out, outcome};
    unsigned threads = resurfi_thread_count(opt.threads);
    for (size_t begin = 0; begin < n; begin += CHUNK_VERTICES) {
        size_t count = n - begin < CHUNK_VERTICES ? n - begin : CHUNK_VERTICES;
        restore_job chunk = {r, job.in + 3 * begin, job.out + 3 * begin, job.outcome + begin};
        resurfi_parallel_for(count, BLOCK_VERTICES, threads, restore_block, &chunk);
        if (resurfi_progress(&opt.progress, RESURF_STAGE_RESTORE, (double)(begin + count) / (double)n)) {
            resurfi_free(alloc, out);
            resurfi_free(alloc, outcome);
            resurfi_restorer_free(r);
            return resurfi_error(error, RESURF_ERR_CANCELLED, "restore cancelled");
        }
    }
    resurf_restore_report rep;
    memset(&rep, 0, sizeof rep);
    rep.vertices = n;
    double total = 0;
    for (size_t v = 0; v < n; ++v) {
        double d = v3_dist(v3_load(out + 3 * v), v3_load(processed->positions + 3 * v));
        if (d > 0) /* d is NaN only for a non-finite input, which is left where it is */
            ++rep.moved, total += d;
        if (d > rep.max_displacement)
            rep.max_displacement = d;
        switch ((resurfi_restore_outcome)outcome[v]) {
        case RESURFI_RESTORED: break;
        case RESURFI_RESTORED_LEAST_OUTSIDE: ++rep.used_least_outside; break;
        case RESURFI_RESTORED_BOUNDARY: ++rep.on_boundary; break;
        case RESURFI_RESTORED_CREASE: ++rep.on_crease; break;
        case RESURFI_LEFT_FAR: ++rep.left_far; break;
        case RESURFI_LEFT_OUTSIDE: ++rep.left_outside; break;
        case RESURFI_LEFT_NONFINITE: ++rep.left_nonfinite; break;
        }
    }
    rep.mean_displacement = rep.moved ? total / (double)rep.moved : 0;
    memcpy(processed->positions, out, n * 3 * sizeof(double));
    resurfi_free(alloc, out);
    resurfi_free(alloc, outcome);
    resurfi_restorer_free(r);
    if (out_report)
        *out_report = rep;
    return RESURF_OK;
}

vec3 resurfi_restorer_limit_height(const resurfi_restorer *r, uint32_t t, vec3 q, double limit)
{
    if (t >= r->triangle_count)
        return q;
    const uint32_t *i = r->tris + 3 * (size_t)t;
    vec3 p0 = position(r, i[0]);
    vec3 n = v3_tri_cross(p0, position(r, i[1]), position(r, i[2]));
    double len2 = v3_len2(n);
    if (!(len2 > 0))
        return q;
    n = v3_scale(n, 1 / sqrt(len2));
    double h = v3_dot(n, v3_sub(q, p0)), cap = limit * local_length(r, t);
    if (fabs(h) <= cap)
        return q;
    return v3_madd(q, n, (h > 0 ? cap : -cap) - h);
}

double resurfi_restorer_edge_length(const resurfi_restorer *r, uint32_t t)
{
    return t < r->triangle_count ? local_length(r, t) : 0;
}
