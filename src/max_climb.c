/* The largest distance of a side, climbed to from its best points.
 *
 * A measured side's maximum is the largest distance over a finite set of points (samples, vertices, facet points).
 * Between them the distance to the other surface rises and falls smoothly over a triangle, and the true maximum
 * usually lies a fraction of a sample spacing from the best point: on a torus's 2% level (400 triangles, 20,000
 * samples and the facet points) the report found 0.911 of the maximum that 1M samples find. So the few points of
 * largest distance, on distinct triangles, are moved uphill inside their triangle by a compass search in the
 * triangle's plane (a step that finds no higher point is halved). Every point visited lies on the triangle and is
 * measured exactly, so the figure is still a maximum over real points of the surface, never above the true one; it
 * can only rise. The search visits a fixed sequence of
 * points from its start, so it is deterministic, and the starts are kept in the order offered. */
#include <math.h>
#include <string.h>

#include "internal.h"

enum { CLIMB_DIRECTIONS = 16, CLIMB_EVALS = 300 };
#define CLIMB_FIRST_STEP 0.125 /* of the triangle's longest edge */
#define CLIMB_LAST_STEP (1.0 / 4096)

void resurfi_max_starts_offer(resurfi_max_starts *s, double d, uint32_t t, const double b[3])
{
    if (!(d > 0) || !isfinite(d))
        return;
    size_t at = s->count;
    for (size_t k = 0; k < s->count; ++k)
        if (s->start[k].t == t) { /* one start a triangle: the higher */
            if (d <= s->start[k].d)
                return;
            at = k;
            break;
        }
    if (at == s->count) {
        if (s->count < RESURFI_MAX_STARTS)
            s->count++;
        else if (d <= s->start[--at].d)
            return;
    }
    while (at > 0 && s->start[at - 1].d < d) { /* sorted by d, the earlier offer first on a tie */
        s->start[at] = s->start[at - 1];
        --at;
    }
    s->start[at].d = d;
    s->start[at].t = t;
    memcpy(s->start[at].b, b, sizeof s->start[at].b);
}

/* The distance at barycentrics b of from's triangle f; *near is the closest triangle of `to` at the last point
 * measured (a step away: the search starts from it), updated. */
static double distance_at(const resurf_mesh *from, const uint32_t *f, const double b[3], const resurfi_bvh *to,
                          uint32_t *near)
{
    vec3 p = v3_scale(resurfi_position(from, f[0]), b[0]);
    p = v3_madd(p, resurfi_position(from, f[1]), b[1]);
    p = v3_madd(p, resurfi_position(from, f[2]), b[2]);
    double d2;
    uint32_t c = resurfi_bvh_closest_near(to, p, *near, NULL, NULL, &d2);
    *near = c;
    return c == UINT32_MAX ? INFINITY : sqrt(d2);
}

/* A compass search with CLIMB_DIRECTIONS directions evenly spread in the triangle's plane (in space, not in
 * barycentrics, so that a thin triangle is searched as evenly as a round one): the largest distance is often a
 * ridge's peak, where two nearest features of the other surface are equally far, and only directions within a
 * narrow cone about the ridge climb it. The search tries the last direction that climbed first. */
static double climb(const resurf_mesh *from, const resurfi_max_start *start, const resurfi_bvh *to)
{
    const uint32_t *f = from->indices + 3 * (size_t)start->t;
    vec3 a = resurfi_position(from, f[0]), e1 = v3_sub(resurfi_position(from, f[1]), a),
         e2 = v3_sub(resurfi_position(from, f[2]), a);
    double g11 = v3_dot(e1, e1), g12 = v3_dot(e1, e2), g22 = v3_dot(e2, e2), det = g11 * g22 - g12 * g12;
    double size = sqrt(fmax(g11, fmax(g22, v3_len2(v3_sub(e2, e1)))));
    if (!(det > 1e-24 * g11 * g22) || !(size > 0))
        return start->d; /* a sliver: its facet points and samples stand for it */
    vec3 u = v3_scale(e1, 1 / sqrt(g11)), w = v3_sub(e2, v3_scale(u, v3_dot(e2, u)));
    w = v3_scale(w, 1 / v3_len(w));
    double du[CLIMB_DIRECTIONS], dv[CLIMB_DIRECTIONS]; /* a unit step in space, in barycentrics 1 and 2 */
    for (int k = 0; k < CLIMB_DIRECTIONS; ++k) {
        double angle = 2 * 3.14159265358979323846 * k / CLIMB_DIRECTIONS;
        vec3 d = v3_add(v3_scale(u, cos(angle)), v3_scale(w, sin(angle)));
        double r1 = v3_dot(e1, d), r2 = v3_dot(e2, d);
        du[k] = (g22 * r1 - g12 * r2) / det;
        dv[k] = (g11 * r2 - g12 * r1) / det;
    }
    double b[3] = {start->b[0], start->b[1], start->b[2]}, best = start->d;
    int evals = 0, last = 0;
    uint32_t near = UINT32_MAX;
    for (double h = CLIMB_FIRST_STEP * size; h >= CLIMB_LAST_STEP * size && evals < CLIMB_EVALS;) {
        int moved = 0;
        for (int i = 0; i < CLIMB_DIRECTIONS && evals < CLIMB_EVALS && !moved; ++i) {
            int k = (last + i) % CLIMB_DIRECTIONS;
            double nb[3] = {0, b[1] + h * du[k], b[2] + h * dv[k]};
            nb[0] = 1 - nb[1] - nb[2];
            if (nb[0] < 0 || nb[1] < 0 || nb[2] < 0)
                continue;
            double d = distance_at(from, f, nb, to, &near);
            ++evals;
            if (d > best && isfinite(d)) {
                best = d;
                memcpy(b, nb, sizeof b);
                moved = 1;
                last = k;
            }
        }
        if (!moved)
            h *= 0.5;
    }
    return best;
}

double resurfi_max_starts_climb(const resurfi_max_starts *s, const resurf_mesh *from, const resurfi_bvh *to,
                                double max)
{
    for (size_t k = 0; k < s->count; ++k)
        max = fmax(max, climb(from, &s->start[k], to));
    return max;
}
