/* The preview's rasterizer: triangles into a panel with a z-buffer, perspective-correct interpolation, Lambert +
 * ambient lighting from a light fixed to the camera, bilinear texture sampling and an optional wireframe. Everything runs in double precision
 * (+, -, *, /, sqrt: exact IEEE operations, no libm call) in a fixed order on one thread, so a panel's pixels depend
 * on the mesh and camera alone. */
#include <math.h>
#include <string.h>

#include "preview/preview_internal.h"

/* Camera-space corner: position, pixel position, and whether it can be drawn (finite, in front of the near
 * plane). */
typedef struct corner {
    vec3 w;                 /* world position */
    vec3 c;
    double sx, sy;
    int ok;
} corner;

static vec3 to_camera(const rp_camera *cam, vec3 p)
{
    vec3 d = v3_sub(p, cam->eye);
    return v3(v3_dot(d, cam->right), v3_dot(d, cam->up), v3_dot(d, cam->forward));
}

static vec3 dir_to_camera(const rp_camera *cam, vec3 n)
{
    return v3(v3_dot(n, cam->right), v3_dot(n, cam->up), v3_dot(n, cam->forward));
}

/* Twice the signed area of (u, v, p) in pixels: positive on one side of u→v, zero on the line. Evaluated from the
 * same endpoint whichever way the edge is walked, so that the two triangles sharing it get exactly opposite values
 * and no pixel centre near it is lost to rounding (a crack) or drawn twice. */
static double edge(const corner *u, const corner *v, double px, double py)
{
    if (u->sx > v->sx || (u->sx == v->sx && u->sy > v->sy))
        return -((u->sx - v->sx) * (py - v->sy) - (u->sy - v->sy) * (px - v->sx));
    return (v->sx - u->sx) * (py - u->sy) - (v->sy - u->sy) * (px - u->sx);
}

/* A pixel centre exactly on an edge belongs to one of the two triangles that share it: the edge's direction
 * decides, and the neighbour walks it the other way. */
static int owns_tie(const corner *u, const corner *v)
{
    double dx = v->sx - u->sx, dy = v->sy - u->sy;
    return dy > 0 || (dy == 0 && dx < 0);
}

static unsigned char to_byte(double v)
{
    v = v * 255 + 0.5;
    return v <= 0 ? 0 : v >= 255 ? 255 : (unsigned char)v;
}

/* A texel index under a wrap mode. */
static long wrap_index(long i, long n, int mode)
{
    if (mode == RP_WRAP_CLAMP)
        return i < 0 ? 0 : i >= n ? n - 1 : i;
    if (mode == RP_WRAP_MIRROR) {
        long period = 2 * n, k = ((i % period) + period) % period;
        return k < n ? k : period - 1 - k;
    }
    return ((i % n) + n) % n;
}

/* The texture's colour at (u, v) (glTF: v = 0 is the image's top row), bilinear between the four nearest texel
 * centres, 0..1 per channel. Coordinates are reduced to one period first so that huge values keep their fraction. */
static void sample(const rp_style *st, double u, double v, double out[3])
{
    const rp_texture *t = st->texture;
    double x = u * t->width - 0.5, y = v * t->height - 0.5;
    if (!(fabs(x) < 1e9) || !(fabs(y) < 1e9)) {
        out[0] = out[1] = out[2] = 1;
        return;
    }
    double fx0 = floor(x), fy0 = floor(y), fx = x - fx0, fy = y - fy0;
    long x0 = (long)fx0, y0 = (long)fy0;
    long xs[2] = {wrap_index(x0, t->width, st->wrap_s), wrap_index(x0 + 1, t->width, st->wrap_s)};
    long ys[2] = {wrap_index(y0, t->height, st->wrap_t), wrap_index(y0 + 1, t->height, st->wrap_t)};
    double w[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
    for (int c = 0; c < 3; ++c) {
        double sum = 0;
        for (int k = 0; k < 4; ++k)
            sum += w[k] * t->rgba[4 * ((size_t)ys[k >> 1] * t->width + (size_t)xs[k & 1]) + c];
        out[c] = sum / 255;
    }
}

resurf_status rp_draw_mesh(rp_panel *panel, const rp_camera *cam, const resurf_mesh *mesh, const affine3 *world,
                           const rp_style *style, const resurf_allocator *alloc)
{
    const double *uv = style->texture && style->texcoord < mesh->texcoord_count ? mesh->texcoords[style->texcoord]
                                                                                 : NULL;
    if (!uv || !style->texture->rgba || !style->texture->width || !style->texture->height)
        uv = NULL;
    if (mesh->triangle_count == 0 || mesh->vertex_count == 0 || panel->w == 0 || panel->h == 0)
        return RESURF_OK;
    corner *corners = resurfi_alloc(alloc, mesh->vertex_count, sizeof *corners);
    if (!corners)
        return RESURF_ERR_OUT_OF_MEMORY;
    for (size_t v = 0; v < mesh->vertex_count; ++v) {
        corner *k = &corners[v];
        vec3 p = world ? affine3_point(world, mesh->positions + 3 * v) : v3_load(mesh->positions + 3 * v);
        k->w = p;
        k->c = to_camera(cam, p);
        k->ok = v3_finite(k->c) && k->c.z > cam->near;
        k->sx = k->ok ? cam->cx + cam->focal * k->c.x / k->c.z : 0;
        k->sy = k->ok ? cam->cy - cam->focal * k->c.y / k->c.z : 0;
        k->ok = k->ok && isfinite(k->sx) && isfinite(k->sy);
    }
    /* Towards the light: up and to the left of the eye, in camera coordinates (x right, y up, z into the
     * picture). */
    const vec3 light = v3_normalize(v3(-0.45, 0.6, -0.66));
    const double ambient = 0.25;
    for (size_t t = 0; t < mesh->triangle_count; ++t) {
        uint32_t id[3];
        memcpy(id, mesh->indices + 3 * t, sizeof id);
        if (id[0] >= mesh->vertex_count || id[1] >= mesh->vertex_count || id[2] >= mesh->vertex_count)
            continue;
        const corner *k[3] = {&corners[id[0]], &corners[id[1]], &corners[id[2]]};
        if (!k[0]->ok || !k[1]->ok || !k[2]->ok)
            continue;
        double area = edge(k[0], k[1], k[2]->sx, k[2]->sy);
        if (!(fabs(area) > 0) || !isfinite(area))
            continue;
        if (area < 0) { /* no culling: the other winding is drawn alike */
            const corner *s = k[1];
            k[1] = k[2];
            k[2] = s;
            uint32_t i = id[1];
            id[1] = id[2];
            id[2] = i;
            area = -area;
        }
        double minx = fmin(k[0]->sx, fmin(k[1]->sx, k[2]->sx)), maxx = fmax(k[0]->sx, fmax(k[1]->sx, k[2]->sx));
        double miny = fmin(k[0]->sy, fmin(k[1]->sy, k[2]->sy)), maxy = fmax(k[0]->sy, fmax(k[1]->sy, k[2]->sy));
        /* Pixel i has its centre at i + 0.5. */
        double i0 = ceil(minx - 0.5), i1 = floor(maxx - 0.5), j0 = ceil(miny - 0.5), j1 = floor(maxy - 0.5);
        if (i0 < 0)
            i0 = 0;
        if (j0 < 0)
            j0 = 0;
        if (i1 > panel->w - 1.0)
            i1 = panel->w - 1.0;
        if (j1 > panel->h - 1.0)
            j1 = panel->h - 1.0;
        if (i0 > i1 || j0 > j1)
            continue;
        /* The edge opposite corner m, its tie rule and its length (an edge function over it is the pixel's
         * distance from the edge). */
        int tie[3] = {owns_tie(k[1], k[2]), owns_tie(k[2], k[0]), owns_tie(k[0], k[1])};
        double len[3];
        for (int m = 0; m < 3; ++m) {
            const corner *u = k[(m + 1) % 3], *v = k[(m + 2) % 3];
            double dx = v->sx - u->sx, dy = v->sy - u->sy;
            len[m] = sqrt(dx * dx + dy * dy); /* sqrt is exact in IEEE arithmetic; hypot differs between libms */
        }
        vec3 face = v3_normalize(v3_cross(v3_sub(k[1]->c, k[0]->c), v3_sub(k[2]->c, k[0]->c)));
        vec3 normal[3];
        for (int m = 0; m < 3; ++m) {
            const double *n = mesh->normals ? mesh->normals + 3 * (size_t)id[m] : NULL;
            normal[m] = !n ? face : dir_to_camera(cam, world ? affine3_normal(world, n) : v3_load(n));
        }
        for (unsigned j = (unsigned)j0; j <= (unsigned)j1; ++j) {
            double py = j + 0.5;
            for (unsigned i = (unsigned)i0; i <= (unsigned)i1; ++i) {
                double px = i + 0.5;
                double e[3] = {edge(k[1], k[2], px, py), edge(k[2], k[0], px, py), edge(k[0], k[1], px, py)};
                int inside = 1;
                for (int m = 0; m < 3 && inside; ++m)
                    inside = e[m] > 0 || (e[m] == 0 && tie[m]);
                if (!inside)
                    continue;
                double b[3] = {e[0] / area, e[1] / area, e[2] / area};
                double inv_z = b[0] / k[0]->c.z + b[1] / k[1]->c.z + b[2] / k[2]->c.z;
                size_t at = (size_t)j * panel->w + i;
                if (!(inv_z > panel->depth[at]))
                    continue;
                panel->depth[at] = inv_z;
                /* Perspective-correct weights: screen barycentrics over depth, renormalised. */
                double w[3] = {b[0] / k[0]->c.z / inv_z, b[1] / k[1]->c.z / inv_z, b[2] / k[2]->c.z / inv_z};
                vec3 n = v3(0, 0, 0), p = v3(0, 0, 0);
                for (int m = 0; m < 3; ++m) {
                    n = v3_madd(n, normal[m], w[m]);
                    p = v3_madd(p, k[m]->c, w[m]);
                }
                n = v3_normalize(n);
                if (v3_dot(n, p) > 0) /* lit from the side that faces the eye */
                    n = v3_neg(n);
                double lambert = v3_dot(n, light);
                double shade = ambient + (1 - ambient) * (lambert > 0 ? lambert : 0);
                if (style->wireframe) {
                    double d = fmin(e[0] / len[0], fmin(e[1] / len[1], e[2] / len[2]));
                    if (d < RP_WIRE_PX)
                        shade *= 0.45;
                }
                double colour[3] = {style->base[0], style->base[1], style->base[2]};
                if (uv) {
                    double u = 0, v = 0, texel[3];
                    for (int m = 0; m < 3; ++m) {
                        u += uv[2 * (size_t)id[m]] * w[m];
                        v += uv[2 * (size_t)id[m] + 1] * w[m];
                    }
                    sample(style, u, v, texel);
                    for (int c = 0; c < 3; ++c)
                        colour[c] *= texel[c];
                }
                unsigned char *px8 = panel->rgba + 4 * ((size_t)(panel->y0 + j) * panel->stride + panel->x0 + i);
                for (int c = 0; c < 3; ++c)
                    px8[c] = to_byte(colour[c] * shade);
                px8[3] = 255;
                if (panel->shade)
                    panel->shade[at] = (float)shade;
                if (panel->position) {
                    vec3 q = v3(0, 0, 0);
                    for (int m = 0; m < 3; ++m)
                        q = v3_madd(q, k[m]->w, w[m]);
                    v3_store(panel->position + 3 * at, q);
                }
            }
        }
    }
    resurfi_free(alloc, corners);
    return RESURF_OK;
}
