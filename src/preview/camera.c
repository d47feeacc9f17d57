/* The preview's camera: a direction from yaw and pitch, and a distance that frames the scene's bounding sphere in
 * the panel whatever its aspect. */
#include <math.h>

#include "preview/preview_internal.h"

rp_camera rp_camera_frame(vec3 centre, double radius, double yaw_deg, double pitch_deg, unsigned w, unsigned h)
{
    if (!(radius > 0) || !isfinite(radius))
        radius = 1;
    const double deg = 3.14159265358979323846 / 180;
    double yaw = yaw_deg * deg, pitch = pitch_deg * deg;
    /* dir points from the centre to the eye. right stays horizontal whatever the pitch, so a top view (pitch 90)
     * has -z up on screen and the basis never degenerates. */
    vec3 dir = v3(sin(yaw) * cos(pitch), sin(pitch), cos(yaw) * cos(pitch));
    rp_camera c;
    c.right = v3(cos(yaw), 0, -sin(yaw));
    c.up = v3_cross(dir, c.right);
    c.forward = v3_neg(dir);
    c.focal = 0.5 * (double)h / tan(0.5 * RP_FOV_DEG * deg);
    c.cx = 0.5 * (double)w;
    c.cy = 0.5 * (double)h;
    /* A sphere of radius r at distance D subtends a half-angle asin(r/D): it fits when that is at most the
     * narrower half field of view, with a 5% margin. */
    double half = atan(0.5 * (double)(w < h ? w : h) / c.focal);
    double distance = 1.05 * radius / sin(half);
    c.eye = v3_madd(centre, dir, distance);
    c.near = 1e-3 * distance;
    return c;
}

void rp_camera_fit(rp_camera *c, vec3 centre, const resurf_mesh *mesh, unsigned w, unsigned h)
{
    /* A corner at (x, y) across and d along the view from the centre is inside the picture, with the margin, when
     * the eye is at least |x| / tx - d (and |y| / ty - d) from the centre. */
    double tx = 0.5 * (double)w / c->focal / 1.05, ty = 0.5 * (double)h / c->focal / 1.05;
    vec3 dir = v3_neg(c->forward);
    double need = 0, reach = 0;
    int any = 0;
    for (size_t t = 0; t < mesh->triangle_count; ++t)
        for (int k = 0; k < 3; ++k) {
            uint32_t v = mesh->indices[3 * t + k];
            if (v >= mesh->vertex_count)
                continue;
            vec3 p = v3_sub(v3_load(mesh->positions + 3 * (size_t)v), centre);
            if (!v3_finite(p))
                continue;
            double x = fabs(v3_dot(p, c->right)), y = fabs(v3_dot(p, c->up)), d = v3_dot(p, c->forward);
            double n = fmax(x / tx - d, y / ty - d);
            need = fmax(need, n);
            reach = fmax(reach, v3_len(p));
            any = 1;
        }
    if (!any || !(need > 0) || !isfinite(need))
        return;
    /* Never nearer than just outside the scene's bounding sphere, so that every corner is in front. */
    double distance = fmax(need, 1.001 * reach);
    c->eye = v3_madd(centre, dir, distance);
    c->near = 1e-3 * distance;
}
