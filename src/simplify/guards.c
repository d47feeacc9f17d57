/* The guards of one collapse: what may refuse, defer or move a planned collapse after its plan (collapse.c) says it
 * is allowed. Each reads the 2-ring of the edge at most and writes nothing but its lane's marks (guards.h states
 * the contract for a whole collapse):
 *   link_ok          the link condition (the mesh stays a manifold);
 *   geometry_ok      no flip or fold beyond max_normal_change_deg, no zero area, the minimum-angle guard;
 *   distance_excess  the tip guard (an end's old place stays near its new triangles), the cover guard (a long new
 *                    triangle's middle stays near M) and the bridge guard (a long new edge stays near M), which
 *                    defer a collapse at a penalised cost (excess_penalty);
 *   restore_point    the restored point's plausibility (a projection that moved too far is not taken), the
 *                    rise limit and the distance gate (nor one that lands farther from M than it started);
 *   restore_keeps_reach  the reach gate (at a fan across a crease, a restored place that leaves M's corners
 *                    farther outside the new fan than the quadric's place did is not taken);
 *   facet_depth      how far a triangle of M lies under S (the gate's allowance, the sag offset's model). */
#include <float.h>
#include <math.h>

#include "simplify_internal.h"

/* The tip guard (tip_excess): an end's old position may lie TIP_GUARD × the edge's length, or TIP_ERROR × the
 * collapse's quadric error (RMS distance to the merged planes), whichever is more, from the triangles that replace
 * its own; beyond, the collapse is re-priced with TIP_PENALTY × its quadrics' weight × the excess² (large: such
 * collapses come last). Measured with bench_simplify on the Stanford dragon scan (871k triangles), Hausdorff and
 * mean distance over meshoptimizer's at 10% and 2%: 3.28/0.59 and 1.89/0.55 before, 0.80/0.59 and 0.89/0.56 after
 * (the 2% maximum is then a vertex off M, not a spike; without the error term 0.80 and 0.74, but coarse inputs
 * lose: bunny at 10% 0.73 -> 0.98, the 48k dragon's mean at 2% +16%; with it they keep their figures). Guards of
 * 0.2 and 0.3 did no better. The analytic surfaces of bench_simplify do not change. */
static const double TIP_GUARD = 0.25;
static const double TIP_ERROR = 2;
static const double TIP_PENALTY = 1e6;

/* A restored vertex rises over (or sinks under) the plane of M's triangle it was restored on by at most RISE_LIMIT ×
 * M's local edge length. On a smooth surface sampled so that an edge turns by angle hκ, S rises about hκ/6 of an edge
 * over a facet, so the limit binds only where M's normals turn by more than ~17° per edge: the 20k analytic shapes
 * rise 0.01 of an edge at most. But a scan's sharp ridges are such places, and there S, the smooth surface the
 * normals describe, bulges over the scanned points by up to 0.3 of an edge (the circle through a ridge triangle's
 * corners with their normals does too: the scan is sharper than its normals). Measured with bench_simplify on the
 * dragon scan (871k triangles), two-sided Hausdorff over meshoptimizer's at 50%: about 1.27 (no limit), 0.88 (0.07),
 * 0.75 (0.05), with the sag offset of place_output; the 20k analytic figures do not move. */
static const double RISE_LIMIT = 0.05;

/* The distance gate (restore_point): a restored point may lie farther from M than the unrestored one by at most
 * GATE_DEPTH × the depth of M's facet under S where it lands (facet_depth). On a smooth S the normals describe, a
 * point of S lies over M's facet by up to 4/3 of that mean depth (at an equilateral facet's centre), so a point
 * farther than that is off the surface M samples. Measured with `resurf simplify --samples 100000` (two-sided, ×10⁻⁴ of the
 * diagonal) on the full dragon scan at 25% (`none`: 1.83 / 0.143): without the gate 2.22 / 0.157; GATE_DEPTH 0:
 * 1.84 / 0.145; 1: 1.84 / 0.148; 2: 1.92 / 0.151; 3: 1.92 / 0.153. Below 2 the coarse 6k torus of
 * simplify_midpoint_placement keeps 85 (1.34) to 270 (1) midpoints up to 10⁻³ of its radius under S, where M's
 * own facets lie under S by that much: the paper's case, a coarse M of a smooth S. */
static const double GATE_DEPTH = 2;

/* Does collapsing (a, b) keep the mesh a manifold? The link condition: the positions adjacent to both a and b must
 * be exactly the third corners of the edge's triangles. Also refused: collapses that leave a double-sided sheet
 * (both ends also share a triangle with those two corners: a tetrahedron) or no triangle at all. */
int link_ok(const simplifier *s, lane *L, const u32vec *fan_a, const u32vec *fan_b, uint32_t a, uint32_t b,
            const plan *pl)
{
    if (fan_a->count + fan_b->count <= 2 * (size_t)pl->shared_count)
        return 0;
    uint32_t st = next_stamp(s, L);
    for (size_t i = 0; i < fan_a->count; ++i) {
        uint32_t xs[2];
        corner_others(s, fan_a->data[i], xs);
        L->mark[xs[0]] = st;
        L->mark[xs[1]] = st;
    }
    int common = 0;
    for (size_t i = 0; i < fan_b->count; ++i) {
        uint32_t xs[2];
        corner_others(s, fan_b->data[i], xs);
        for (int k = 0; k < 2; ++k)
            if (xs[k] != a && L->mark[xs[k]] == st) {
                L->mark[xs[k]] = st + 1; /* count once */
                ++common;
            }
    }
    if (common != pl->shared_count)
        return 0;
    if (pl->shared_count == 2) {
        uint32_t o[2] = {NONE, NONE};
        for (int k = 0; k < 2; ++k) {
            uint32_t t = pl->shared[k];
            for (int i = 0; i < 3; ++i)
                if (TV(3 * t + i) != a && TV(3 * t + i) != b)
                    o[k] = TV(3 * t + i);
        }
        int has[2] = {0, 0};
        const u32vec *fans[2] = {fan_a, fan_b};
        for (int side = 0; side < 2; ++side)
            for (size_t i = 0; i < fans[side]->count; ++i) {
                uint32_t c = fans[side]->data[i];
                uint32_t x = TV(corner_next(c)), y = TV(corner_prev(c));
                if ((x == o[0] && y == o[1]) || (x == o[1] && y == o[0]))
                    has[side] = 1;
            }
        if (has[0] && has[1])
            return 0;
    }
    return 1;
}

/* The smallest angle of a triangle, in degrees (0 for a degenerate one). */
static double min_angle_deg(vec3 p0, vec3 p1, vec3 p2)
{
    vec3 p[3] = {p0, p1, p2};
    double best = 180;
    for (int k = 0; k < 3; ++k) {
        vec3 u = v3_sub(p[(k + 1) % 3], p[k]), v = v3_sub(p[(k + 2) % 3], p[k]);
        double ang = atan2(v3_len(v3_cross(u, v)), v3_dot(u, v)) * (180.0 / M_PI);
        best = ang < best ? ang : best;
    }
    return best;
}

/* Does triangle t change shape in collapse pl (it is not one of the two that vanish)? If so, its corners before
 * (old, may be NULL) and after (neu) the ends a and b move to p. */
static int moved_triangle(const simplifier *s, uint32_t t, uint32_t a, uint32_t b, vec3 p, const plan *pl,
                          vec3 old[3], vec3 neu[3])
{
    if (t == pl->shared[0] || (pl->shared_count >= 2 && t == pl->shared[1]) ||
        (pl->shared_count == 3 && t == pl->shared[2]))
        return 0;
    for (int k = 0; k < 3; ++k) {
        uint32_t v = TV(3 * t + k);
        if (old)
            old[k] = s->P[v].p;
        neu[k] = v == a || v == b ? p : s->P[v].p;
    }
    return 1;
}

/* Checks every triangle that changes (those of a and b except the edge's): no flip or fold beyond
 * max_normal_change_deg, no collapse to zero area, and the minimum-angle guard. Returns GEOMETRY_OK, or why
 * not. */
int geometry_ok(const simplifier *s, const u32vec *fan_a, const u32vec *fan_b, uint32_t a, uint32_t b, vec3 p,
                const plan *pl)
{
    double cos_max = cos(s->opt.max_normal_change_deg * (M_PI / 180.0));
    const u32vec *fans[2] = {fan_a, fan_b};
    for (int side = 0; side < 2; ++side)
        for (size_t i = 0; i < fans[side]->count; ++i) {
            vec3 old[3], neu[3];
            if (!moved_triangle(s, fans[side]->data[i] / 3, a, b, p, pl, old, neu))
                continue;
            vec3 n0 = v3_tri_cross(old[0], old[1], old[2]), n1 = v3_tri_cross(neu[0], neu[1], neu[2]);
            double l0 = v3_len(n0), l1 = v3_len(n1);
            double longest = dmax(dmax(v3_dist2(neu[0], neu[1]), v3_dist2(neu[1], neu[2])), v3_dist2(neu[2], neu[0]));
            if (!(l1 > 1e-12 * longest))
                return GEOMETRY_FLIP;
            if (l0 > 0 && v3_dot(n0, n1) < cos_max * l0 * l1)
                return GEOMETRY_FLIP;
            if (s->opt.min_angle_deg > 0) {
                double after = min_angle_deg(neu[0], neu[1], neu[2]);
                if (after < s->opt.min_angle_deg && after < min_angle_deg(old[0], old[1], old[2]))
                    return GEOMETRY_ANGLE;
            }
        }
    return GEOMETRY_OK;
}

/* How far (beyond the bound described at TIP_GUARD) an end's old position lies from its own triangles after they
 * move to p; 0 when both stay near. A one-sided Hausdorff bound that quadrics cannot see at a thin spike: its faces
 * lie nearly parallel to its axis, so moving the tip down the axis costs almost nothing, and collapse after
 * collapse shortens the spike. An end without triangles left (a fin's tip) has no surface to stay near. */
static double tip_excess(const simplifier *s, const u32vec *fan_a, const u32vec *fan_b, uint32_t a, uint32_t b,
                         vec3 p, const plan *pl, double err)
{
    const u32vec *fans[2] = {fan_a, fan_b};
    double bound = TIP_GUARD * v3_dist(s->P[a].p, s->P[b].p);
    bound = fmax(bound, TIP_ERROR * err);
    double excess = 0, bound2 = bound * bound;
    for (int side = 0; side < 2; ++side) {
        vec3 end = s->P[side ? b : a].p;
        double near2 = INFINITY;
        /* The first triangle within the bound settles this end (sqrt of a correctly rounded bound² is the bound). */
        for (size_t i = 0; i < fans[side]->count && !(near2 <= bound2); ++i) {
            vec3 neu[3];
            if (!moved_triangle(s, fans[side]->data[i] / 3, a, b, p, pl, NULL, neu))
                continue;
            double d2 = v3_dist2(end, resurfi_closest_on_triangle(end, neu[0], neu[1], neu[2], NULL));
            near2 = d2 < near2 ? d2 : near2;
        }
        if (near2 < INFINITY && sqrt(near2) - bound > excess)
            excess = sqrt(near2) - bound;
    }
    return excess;
}

/* The reach of a collapse to p over M's corners: the largest distance from a corner of M's triangles t0 and t1 (NONE:
 * none) to the triangles that replace the ends' own. Where M lies farther from the new fan than it did at another
 * place, that place covered M better there: the part of the two-sided error the collapse can measure on M's side. */
static double corners_reach(const simplifier *s, const u32vec *fan_a, const u32vec *fan_b, uint32_t a, uint32_t b,
                            vec3 p, const plan *pl, uint32_t t0, uint32_t t1)
{
    double far2 = 0;
    uint32_t ts[2] = {t0, t1};
    const u32vec *fans[2] = {fan_a, fan_b};
    for (int k = 0; k < 2; ++k) {
        if (ts[k] == NONE)
            continue;
        for (int j = 0; j < 3; ++j) {
            vec3 c = v3_load(s->in->positions + 3 * (size_t)s->in->indices[3 * (size_t)ts[k] + j]);
            double near2 = INFINITY, side = 0;
            for (int f = 0; f < 2; ++f)
                for (size_t i = 0; i < fans[f]->count; ++i) {
                    vec3 neu[3];
                    if (!moved_triangle(s, fans[f]->data[i] / 3, a, b, p, pl, NULL, neu))
                        continue;
                    vec3 x = resurfi_closest_on_triangle(c, neu[0], neu[1], neu[2], NULL);
                    double d2 = v3_dist2(c, x);
                    if (d2 < near2) {
                        near2 = d2;
                        side = v3_dot(v3_sub(c, x), v3_tri_cross(neu[0], neu[1], neu[2]));
                    }
                }
            if (near2 < INFINITY && side > 0 && near2 > far2)
                far2 = near2;
        }
    }
    return sqrt(far2);
}

/* The other side of the tip guard, for new edges longer than BRIDGE_RATIO × M's local edge length (late in a run):
 * how far (beyond the same bound) the midpoint of a new edge from p lies from M. A long edge may bridge a groove
 * or a notch whose walls the quadrics see as planes through its ends. Measured by walking M from `start`, a
 * triangle of M near p (so only with a restorer). Measured with bench_simplify on the dragon scan (871k triangles),
 * two-sided Hausdorff over meshoptimizer's at 2%: 0.86 before, 0.73 after (mean +0.2%; the 10% LOD does not
 * change). The ratio spares walks: 3 did no better. Against the mean edge length of M instead of the local one
 * (no look-up), the edge that decided the figure, 12 local edges long, went unchecked. */
static const double BRIDGE_RATIO = 6;

static double bridge_excess(const simplifier *s, lane *L, const u32vec *fan_a, const u32vec *fan_b, uint32_t a,
                            uint32_t b, vec3 p, const plan *pl, double err, uint32_t start)
{
    if (!s->restorer || start == NONE)
        return 0;
    double longest = BRIDGE_RATIO * resurfi_restorer_edge_length(s->restorer, start);
    uint32_t st = next_stamp(s, L); /* each neighbour once */
    double excess = 0;
    const u32vec *fans[2] = {fan_a, fan_b};
    for (int side = 0; side < 2; ++side)
        for (size_t i = 0; i < fans[side]->count; ++i) {
            uint32_t c = fans[side]->data[i], t = c / 3;
            if (t == pl->shared[0] || (pl->shared_count >= 2 && t == pl->shared[1]) ||
                (pl->shared_count == 3 && t == pl->shared[2]))
                continue;
            uint32_t xs[2];
            corner_others(s, c, xs);
            for (int k = 0; k < 2; ++k) {
                uint32_t x = xs[k];
                if (x == a || x == b || L->mark[x] == st)
                    continue;
                L->mark[x] = st;
                double e = v3_dist(p, s->P[x].p);
                if (!(e > longest))
                    continue;
                double bary[3], d2 = INFINITY;
                vec3 mid = v3_scale(v3_add(p, s->P[x].p), 0.5);
                if (resurfi_restorer_closest_walk(s->restorer, mid, start, bary, &d2) == NONE)
                    continue;
                double over = sqrt(d2) - fmax(TIP_GUARD * e, TIP_ERROR * err);
                excess = over > excess ? over : excess;
            }
        }
    return excess;
}

/* How far input triangle t lies under S on average: (1/24) Σ over its corners j and the other corners k of
 * −N_j·(p_k − p_j), N_j S's normal at corner j (docs/restoring.md §8, the sag offset). */
double facet_depth(const simplifier *s, uint32_t t)
{
    const uint32_t *ix = s->in->indices + 3 * (size_t)t;
    vec3 p[3];
    for (int k = 0; k < 3; ++k)
        p[k] = v3_load(s->in->positions + 3 * (size_t)ix[k]);
    double sum = 0;
    for (int j = 0; j < 3; ++j) {
        double bary[3] = {j == 0, j == 1, j == 2};
        vec3 n = resurfi_restorer_normal(s->restorer, t, bary);
        for (int d = 1; d < 3; ++d)
            sum -= v3_dot(n, v3_sub(p[(j + d) % 3], p[j]));
    }
    return sum / 24.0;
}

/* The cover guard, for moved triangles longer than COVER_RATIO × M's local edge length: how far (beyond the same
 * bound, of the triangle's longest edge) its centroid lies from M. The tip guard sees only the ends' old places and
 * the bridge guard only the midpoints of long edges; on a CAD part a late collapse can pull a long sliver across a
 * gap between two walls, its edges' ends and midpoints on M and its inside far from it (2CylinderEngine's
 * meshes[18] at 25%: a triangle 32 long, its middle 15 from M, 5% of the part's diagonal). Exact distances through
 * the BVH over M (with or without a restorer), after a look within the bound that ends at the first triangle.
 * Measured on the engine's meshes alone (OBJ exports, own diagonal, two-sided Hausdorff over gltfpack's at equal
 * triangles, docs/restoring.md §8): meshes[18] at 25% 2.54 -> 1.31, meshes[22] 1.70 -> 1.09, nothing else moved;
 * the analytic shapes and the scans do not change; 3.5% more instructions on the 48k dragon at 10% (1 at every
 * size: 4.8%, with the same figures). */
static const double COVER_RATIO = 2;

static int found_one(void *ctx, uint32_t t, vec3 point, const double bary[3], double dist2)
{
    (void)ctx, (void)t, (void)point, (void)bary, (void)dist2;
    return 1;
}

static double cover_excess(const simplifier *s, const u32vec *fan_a, const u32vec *fan_b, uint32_t a, uint32_t b,
                           vec3 p, const plan *pl, double err, uint32_t start)
{
    double local = s->restorer && start != NONE ? resurfi_restorer_edge_length(s->restorer, start) : 0;
    double least2 = COVER_RATIO * COVER_RATIO * local * local, excess = 0;
    const u32vec *fans[2] = {fan_a, fan_b};
    for (int side = 0; side < 2; ++side)
        for (size_t i = 0; i < fans[side]->count; ++i) {
            uint32_t t = fans[side]->data[i] / 3;
            vec3 neu[3];
            if (!moved_triangle(s, t, a, b, p, pl, NULL, neu))
                continue; /* (a triangle with corners at both ends is one of the edge's) */
            double longest2 = dmax(dmax(v3_dist2(neu[0], neu[1]), v3_dist2(neu[1], neu[2])), v3_dist2(neu[2], neu[0]));
            if (!(longest2 > least2))
                continue;
            vec3 c = v3_scale(v3_add(v3_add(neu[0], neu[1]), neu[2]), 1.0 / 3);
            double bound = fmax(TIP_GUARD * sqrt(longest2), TIP_ERROR * err), d2 = INFINITY;
            if (resurfi_bvh_within(s->bvh, c, bound * bound, found_one, NULL) ||
                resurfi_bvh_closest(s->bvh, c, INFINITY, NULL, NULL, &d2) == NONE)
                continue;
            excess = fmax(excess, sqrt(d2) - bound);
        }
    return excess;
}

/* Restores p onto S of the original; `scale` is the length of the edges around p. *left is set when p stays where
 * it is: the restorer left it, moved it implausibly far, or moved it farther from M than it was. A point near M moves
 * onto S by about its distance to M (M's own sag from S is far smaller), so a move beyond twice that distance plus
 * a quarter of the local edge length is a failure of the projection (seen near sliver triangles of scanned meshes),
 * not a restoration; the vertex then keeps its unrestored place rather than fold the mesh. Where S is smooth at the
 * scale of the collapse, the restored point lies over M by at most about M's own facet depth there; where it lies
 * farther from M than the unrestored place by more (GATE_DEPTH), S as the normals describe it is not the surface M
 * samples there (the noise of a scan, a ridge sharper than its normals), and the quadric's place is kept
 * (docs/restoring.md §8, the distance gate). `home` is a triangle of M near p: the search for p's closest triangle walks from there
 * (resurfi_restorer_point_walk). *out_home receives the triangle p was restored on (NONE when left). */
vec3 restore_point(const simplifier *s, vec3 p, double scale, uint32_t home, int *left, uint32_t *out_home)
{
    vec3 q;
    uint32_t t;
    resurfi_restore_outcome o = resurfi_restorer_point_walk(s->restorer, p, home, &q, &t, NULL);
    *left = o >= RESURFI_LEFT_FAR;
    *out_home = *left ? NONE : t;
    if (*left)
        return p;
    double bary[3], p_d2 = INFINITY, q_d2 = INFINITY;
    resurfi_restorer_closest_walk(s->restorer, p, home, bary, &p_d2);
    double moved = v3_dist(p, q);
    if (!(moved <= 0.25 * scale || moved <= 2 * sqrt(p_d2) + 0.25 * scale)) {
        *left = 1;
        *out_home = NONE;
        return p;
    }
    q = resurfi_restorer_limit_height(s->restorer, *out_home, q, RISE_LIMIT);
    resurfi_restorer_closest_walk(s->restorer, q, *out_home, bary, &q_d2);
    if (q_d2 > p_d2 && sqrt(q_d2) > sqrt(p_d2) + GATE_DEPTH * fabs(facet_depth(s, *out_home))) {
        *left = 1;
        *out_home = NONE;
        return p;
    }
    return q;
}

/* The reach gate: may restoring the collapse's place pl->p to q (restored on M's triangle q_home) stand? Where one of
 * the new fan's triangles turns from S's normal at q by more than feature_angle_deg, the fan is no smooth one (the
 * chord-sag model does not hold there either): a scan's tip or a thin rim, sharper than its normals. There the restored place is kept only if it does not raise the local two-sided
 * error the collapse can measure, the larger of the place's distance to M and the reach of M's corners next to
 * pl->p and q outside the new fan (corners_reach), by more than q's own height over M. The bunny's ear at 10%: its
 * rim vertex, restored 0.07 inwards onto M, left M's tip 0.22 from the level instead of 0.20 (docs/restoring.md
 * §8). Where the fan is smooth the restoration stands: the paper's case. */
int restore_keeps_reach(const simplifier *s, const u32vec *fan_a, const u32vec *fan_b, uint32_t a, uint32_t b,
                        const plan *pl, vec3 q, uint32_t q_home)
{
    double bary[3], p_d2 = INFINITY, q_d2 = INFINITY;
    if (resurfi_restorer_closest_walk(s->restorer, q, q_home, bary, &q_d2) == NONE)
        return 1;
    vec3 n = resurfi_restorer_normal(s->restorer, q_home, bary);
    const u32vec *fans[2] = {fan_a, fan_b};
    int smooth = 1;
    for (int side = 0; side < 2 && smooth; ++side)
        for (size_t i = 0; i < fans[side]->count && smooth; ++i) {
            vec3 neu[3];
            if (!moved_triangle(s, fans[side]->data[i] / 3, a, b, q, pl, NULL, neu))
                continue;
            vec3 face = v3_tri_cross(neu[0], neu[1], neu[2]);
            smooth = v3_dot(face, n) >= s->feature_cos * v3_len(face);
        }
    if (smooth)
        return 1;
    uint32_t tp = resurfi_restorer_closest_walk(s->restorer, pl->p, s->home[a], bary, &p_d2);
    if (tp == NONE)
        return 1;
    double rq = fmax(corners_reach(s, fan_a, fan_b, a, b, q, pl, tp, q_home), sqrt(q_d2));
    double rp = fmax(corners_reach(s, fan_a, fan_b, a, b, pl->p, pl, tp, q_home), sqrt(p_d2));
    return !(rq > rp + sqrt(q_d2));
}

/* How far beyond their bounds the tip, cover and bridge guards find the collapse's new triangles (0: within); `near`
 * is a triangle of M near p, or NONE. */
double distance_excess(const simplifier *s, lane *L, const u32vec *fan_a, const u32vec *fan_b, uint32_t a,
                       uint32_t b, vec3 p, const plan *pl, double err, uint32_t near)
{
    double excess = tip_excess(s, fan_a, fan_b, a, b, p, pl, err);
    excess = fmax(excess, cover_excess(s, fan_a, fan_b, a, b, p, pl, err, near));
    return fmax(excess, bridge_excess(s, L, fan_a, fan_b, a, b, p, pl, err, near));
}

/* The cost a deferred collapse adds for its excess: TIP_PENALTY × its quadrics' weight × the excess². */
double excess_penalty(const resurfi_quadric *q, double excess) { return TIP_PENALTY * q->w * excess * excess; }
