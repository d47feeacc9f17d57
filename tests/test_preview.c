/* Tests of the preview sheet (src/preview/): the rasterizer's coverage against analytic projections, the sheet's
 * determinism over thread counts, the heat map's range on an analytic sphere, and hostile input. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <jpeglib.h>

#include "preview/preview_internal.h"
#include "testutil.h"

/* Renders mesh into a w × h panel from camera; returns the number of covered pixels (and leaves the panel's
 * depth in *depth_out when not NULL). */
static size_t covered(const resurf_mesh *mesh, const rp_camera *cam, unsigned w, unsigned h, double **depth_out)
{
    unsigned char *rgba = calloc((size_t)w * h, 4);
    double *depth = calloc((size_t)w * h, sizeof *depth);
    ck_assert(rgba && depth);
    rp_panel panel = {rgba, w, 0, 0, w, h, depth, NULL, NULL};
    rp_style style = {.base = {0.8, 0.8, 0.8}};
    ck_assert_int_eq(rp_draw_mesh(&panel, cam, mesh, NULL, &style, NULL), RESURF_OK);
    size_t n = 0;
    for (size_t k = 0; k < (size_t)w * h; ++k) {
        n += depth[k] > 0;
        ck_assert_int_eq(depth[k] > 0, rgba[4 * k + 3] == 255); /* drawn where and only where depth was set */
    }
    free(rgba);
    if (depth_out)
        *depth_out = depth;
    else
        free(depth);
    return n;
}

/* A camera on the +z axis at distance D from the origin, looking down -z, for a w × h panel. */
static rp_camera axis_camera(double x, double y, double D, unsigned w, unsigned h)
{
    rp_camera c = rp_camera_frame(v3(0, 0, 0), 1, 0, 0, w, h);
    c.eye = v3(x, y, D);
    c.near = 1e-3;
    return c;
}

/* A sphere of radius R centred on the optical axis at distance D is seen inside the cone from the eye tangent to
 * it, of half-angle a with sin a = R / D. The cone cuts the image plane (at focal length f) in a circle of radius
 * f tan a = f R / sqrt(D² - R²), so the sphere covers π f² R² / (D² - R²) pixels. The mesh is inscribed in the
 * unit sphere (its flat triangles sag by ~1e-5 at 200k triangles): well inside the 1%. */
START_TEST(preview_sphere_covers_analytic_disc)
{
    resurf_mesh *sphere = shape_mesh(SHAPE_SPHERE, 200000, 0.2, 7, 1);
    ck_assert_ptr_nonnull(sphere);
    const double D = 4, R = 1;
    rp_camera cam = axis_camera(0, 0, D, 512, 512);
    size_t n = covered(sphere, &cam, 512, 512, NULL);
    double analytic = M_PI * cam.focal * cam.focal * R * R / (D * D - R * R);
    ck_assert_msg(fabs((double)n - analytic) <= 0.01 * analytic, "%zu pixels, analytic %.1f", n, analytic);
    /* Far and small, the same holds to within the pixels along the rim. */
    cam = axis_camera(0, 0, 12, 512, 512);
    n = covered(sphere, &cam, 512, 512, NULL);
    analytic = M_PI * cam.focal * cam.focal / (144 - 1);
    ck_assert_msg(fabs((double)n - analytic) <= 0.01 * analytic, "%zu pixels, analytic %.1f", n, analytic);
    resurf_mesh_free(sphere);
}
END_TEST

/* The unit cube [0,1]³ seen face-on from (0.5, 0.5, D): its face z = 1 at depth D - 1 projects to a square of side
 * f / (D - 1) about the panel's centre, and the side faces fall inside it. Exactly the pixels whose centres lie
 * in that square are covered, each with the face's depth. */
START_TEST(preview_cube_face_fills_square)
{
    resurf_mesh *cube = tu_cube();
    const unsigned w = 300, h = 200;
    const double D = 4.37;
    rp_camera cam = axis_camera(0.5, 0.5, D, w, h);
    double *depth = NULL;
    size_t n = covered(cube, &cam, w, h, &depth);
    double half = 0.5 * cam.focal / (D - 1);
    size_t expected = 0;
    for (unsigned j = 0; j < h; ++j)
        for (unsigned i = 0; i < w; ++i) {
            int inside = fabs(i + 0.5 - cam.cx) < half && fabs(j + 0.5 - cam.cy) < half;
            expected += inside;
            ck_assert_msg((depth[(size_t)j * w + i] > 0) == inside, "pixel %u %u", i, j);
            if (inside)
                ck_assert_double_eq_tol(depth[(size_t)j * w + i], 1 / (D - 1), 1e-12);
        }
    ck_assert_uint_eq(n, expected);
    ck_assert_uint_gt(expected, 1000);
    free(depth);
    resurf_mesh_free(cube);
}
END_TEST

/* A sphere scene with two levels (simplified), for the sheet tests. */
static resurf_scene *sphere_scene(size_t triangles)
{
    resurf_mesh *sphere = shape_mesh(SHAPE_SPHERE, triangles, 0.3, 3, 1);
    resurf_scene *scene = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(sphere, &scene, NULL), RESURF_OK);
    resurf_simplify_options so = resurf_simplify_options_default();
    so.threads = 1;
    const double ratios[2] = {0.3, 0.05};
    ck_assert_int_eq(resurf_scene_build_lods(scene, ratios, 2, &so, NULL, NULL, NULL, NULL), RESURF_OK);
    resurf_mesh_free(sphere);
    return scene;
}

static unsigned char *encode(const resurf_preview_image *img, size_t *size)
{
    unsigned char *data = NULL;
    ck_assert_int_eq(rp_png_encode(img->rgba, img->width, img->height, NULL, &data, size, NULL), RESURF_OK);
    return data;
}

START_TEST(preview_same_bytes_for_any_thread_count)
{
    resurf_scene *scene = sphere_scene(6000);
    unsigned char *first = NULL;
    size_t first_size = 0;
    for (unsigned threads = 1; threads <= 4; threads += 3) {
        resurf_preview_options o = resurf_preview_options_default();
        o.width = 640;
        o.height = 480;
        o.heatmap = 1;
        o.wireframe = 1;
        o.compare_samples = 20000;
        o.threads = threads;
        resurf_preview_image img;
        resurf_preview_report rep;
        resurf_error err;
        ck_assert_int_eq(resurf_preview_render(scene, &o, &img, &rep, &err), RESURF_OK);
        ck_assert_uint_eq(rep.levels, 3);
        ck_assert(rep.level_error[2] > rep.level_error[1] && rep.level_error[1] > 0);
        ck_assert(rep.heat_max > 0);
        size_t size;
        unsigned char *png = encode(&img, &size);
        ck_assert_mem_eq(png, "\x89PNG\r\n\x1a\n", 8);
        if (!first) {
            first = png;
            first_size = size;
        } else {
            ck_assert_uint_eq(size, first_size);
            ck_assert_mem_eq(png, first, size);
            free(png);
        }
        resurf_preview_image_free(&img);
        ck_assert_ptr_null(img.rgba);
    }
    free(first);
    resurf_scene_free(scene);
}
END_TEST

/* The level's vertices lie on the unit sphere: each flat triangle dips below it most at the foot of the
 * perpendicular from the centre, by 1 - (distance of its plane from the centre). The heat map's top (what its
 * colour bar prints) is that dip for the triangles in view, no more than the largest dip of all, and the same
 * figure as the two-sided error. The original is a fine sphere inscribed in the same one, whose own dip (~1e-4)
 * is the allowance. */
START_TEST(preview_heatmap_range_on_analytic_sphere)
{
    resurf_mesh *fine = shape_mesh(SHAPE_SPHERE, 120000, 0, 1, 1);
    resurf_mesh *coarse = shape_mesh(SHAPE_SPHERE, 400, 0, 1, 1);
    ck_assert(fine && coarse);
    resurf_scene *scene = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(fine, &scene, NULL), RESURF_OK);
    const resurf_mesh *levels[1] = {coarse};
    ck_assert_int_eq(resurf_scene_set_lods(scene, 0, levels, 1, NULL), RESURF_OK);
    resurf_preview_options o = resurf_preview_options_default();
    o.width = 800;
    o.height = 600;
    o.heatmap = 1;
    o.view = RESURF_PREVIEW_FRONT; /* from +z */
    resurf_preview_image img;
    resurf_preview_report rep;
    ck_assert_int_eq(resurf_preview_render(scene, &o, &img, &rep, NULL), RESURF_OK);
    double dip_all = 0, dip_seen = 0, fine_dip = 0;
    for (int pass = 0; pass < 2; ++pass) {
        const resurf_mesh *m = pass ? fine : coarse;
        for (size_t t = 0; t < m->triangle_count; ++t) {
            vec3 a = resurfi_position(m, m->indices[3 * t]), b = resurfi_position(m, m->indices[3 * t + 1]),
                 c = resurfi_position(m, m->indices[3 * t + 2]);
            vec3 n = v3_normalize(v3_cross(v3_sub(b, a), v3_sub(c, a)));
            double dip = 1 - fabs(v3_dot(n, a));
            if (pass) {
                fine_dip = fmax(fine_dip, dip);
                continue;
            }
            dip_all = fmax(dip_all, dip);
            if (n.z > 0.3) /* well in view from +z */
                dip_seen = fmax(dip_seen, dip);
        }
    }
    ck_assert_msg(rep.heat_max >= 0.97 * dip_seen - fine_dip && rep.heat_max <= dip_all * 1.001,
                  "heat max %g, dips seen %g all %g fine %g", rep.heat_max, dip_seen, dip_all, fine_dip);
    ck_assert_msg(fabs(rep.level_error[1] - dip_all) <= 0.1 * dip_all, "error %g, dip %g", rep.level_error[1],
                  dip_all);
    ck_assert_double_eq_tol(rep.level_error_rel[1], rep.level_error[1] / rep.diagonal, 1e-15);
    ck_assert_double_eq_tol(rep.diagonal, 2 * sqrt(3), 1e-3);
    /* The colour bar runs from the scale's bottom colour to its top along the sheet's bottom strip. */
    unsigned char lo[3], hi[3];
    rp_heat_colour(0, lo);
    rp_heat_colour(1, hi);
    int found_lo = 0, found_hi = 0;
    for (unsigned y = img.height - 80; y < img.height; ++y) {
        const unsigned char *left = img.rgba + 4 * ((size_t)y * img.width + img.width / 5);
        const unsigned char *right = img.rgba + 4 * ((size_t)y * img.width + img.width - img.width / 5 - 1);
        found_lo |= !memcmp(left, lo, 3);
        found_hi |= !memcmp(right, hi, 3);
    }
    ck_assert(found_lo && found_hi);
    resurf_preview_image_free(&img);
    resurf_scene_free(scene);
    resurf_mesh_free(fine);
    resurf_mesh_free(coarse);
}
END_TEST

START_TEST(preview_refuses_huge_sizes)
{
    resurf_mesh *cube = tu_cube();
    resurf_scene *scene = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(cube, &scene, NULL), RESURF_OK);
    static const unsigned sizes[][2] = {{100000, 100}, {16384, 16384}, {8, 600}, {0, 0}, {4294967295u, 4294967295u}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; ++i) {
        resurf_preview_options o = resurf_preview_options_default();
        o.width = sizes[i][0];
        o.height = sizes[i][1];
        resurf_preview_image img = {.width = 7};
        resurf_error err;
        ck_assert_int_eq(resurf_preview_render(scene, &o, &img, NULL, &err), RESURF_ERR_LIMIT);
        ck_assert_ptr_nonnull(strstr(err.message, "pixels"));
        ck_assert_ptr_null(img.rgba);
        ck_assert_uint_eq(img.width, 0);
    }
    resurf_preview_options o = resurf_preview_options_default();
    o.view = RESURF_PREVIEW_VIEW_COUNT;
    resurf_preview_image img;
    ck_assert_int_eq(resurf_preview_render(scene, &o, &img, NULL, NULL), RESURF_ERR_INVALID_OPTIONS);
    o = resurf_preview_options_default();
    o.yaw_deg = NAN;
    ck_assert_int_eq(resurf_preview_render(scene, &o, &img, NULL, NULL), RESURF_ERR_INVALID_OPTIONS);
    o.struct_size = 0;
    ck_assert_int_eq(resurf_preview_render(scene, &o, &img, NULL, NULL), RESURF_ERR_INVALID_OPTIONS);
    ck_assert_int_eq(resurf_preview_render(NULL, NULL, &img, NULL, NULL), RESURF_ERR_INVALID_ARGUMENT);
    resurf_scene_free(scene);
    resurf_mesh_free(cube);
}
END_TEST

/* Renders a one-mesh scene at 320 × 240 and returns how many pixels differ from the background. */
static size_t drawn_pixels(const resurf_mesh *mesh, resurf_preview_report *rep)
{
    resurf_scene *scene = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(mesh, &scene, NULL), RESURF_OK);
    resurf_preview_options o = resurf_preview_options_default();
    o.width = 320;
    o.height = 240;
    o.heatmap = 1;
    o.wireframe = 1;
    resurf_preview_image img;
    resurf_error err;
    ck_assert_msg(resurf_preview_render(scene, &o, &img, rep, &err) == RESURF_OK, "%s", err.message);
    ck_assert_uint_eq(img.width, 320);
    size_t n = 0;
    for (size_t k = 0; k < 320 * 240; ++k)
        n += memcmp(img.rgba + 4 * k, "\xff\xff\xff\xff", 4) != 0;
    resurf_preview_image_free(&img);
    resurf_scene_free(scene);
    return n;
}

START_TEST(preview_draws_empty_and_degenerate_meshes)
{
    /* No triangles: an empty panel with its label (some ink, no picture). */
    static const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    static const uint32_t none[3] = {0};
    resurf_mesh *empty = tu_mesh(p, 4, none, 0);
    resurf_preview_report rep;
    size_t ink = drawn_pixels(empty, &rep);
    ck_assert_uint_eq(rep.levels, 1);
    ck_assert_uint_eq(rep.level_triangles[0], 0);
    ck_assert_uint_gt(ink, 0);
    ck_assert_uint_lt(ink, 3000);
    /* Every triangle collapsed to a point or a line: drawn as nothing, labelled. */
    static const double q[] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 0, 2, 2, 2};
    static const uint32_t t[] = {0, 1, 2, 0, 3, 4, 3, 4, 0, 2, 2, 2};
    resurf_mesh *flat = tu_mesh(q, 5, t, 4);
    size_t flat_ink = drawn_pixels(flat, &rep);
    ck_assert_uint_eq(rep.level_triangles[0], 4);
    ck_assert_uint_lt(flat_ink, 3000);
    /* A single point as the whole scene (zero diagonal) and a huge coordinate range. */
    static const double r[] = {5, 5, 5, 5, 5, 5, 5, 5, 5};
    static const uint32_t u[] = {0, 1, 2};
    resurf_mesh *point = tu_mesh(r, 3, u, 1);
    (void)drawn_pixels(point, &rep);
    static const double s[] = {-1e300, 0, 0, 1e300, 0, 0, 0, 1e300, 0};
    resurf_mesh *huge = tu_mesh(s, 3, u, 1);
    (void)drawn_pixels(huge, &rep);
    /* The smallest sheets, with every option: drawn, no write out of the image (ASan, valgrind). */
    resurf_scene *scene = sphere_scene(2000);
    static const unsigned sizes[][2] = {{16, 16}, {16, 900}, {900, 16}, {17, 33}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; ++i) {
        resurf_preview_options o = resurf_preview_options_default();
        o.width = sizes[i][0];
        o.height = sizes[i][1];
        o.heatmap = o.wireframe = 1;
        o.compare_samples = 0;
        resurf_preview_image img;
        ck_assert_int_eq(resurf_preview_render(scene, &o, &img, &rep, NULL), RESURF_OK);
        ck_assert_uint_eq(img.width, sizes[i][0]);
        ck_assert_uint_eq(rep.levels, 3);
        resurf_preview_image_free(&img);
    }
    resurf_scene_free(scene);
    resurf_mesh_free(empty);
    resurf_mesh_free(flat);
    resurf_mesh_free(point);
    resurf_mesh_free(huge);
}
END_TEST

START_TEST(preview_png_written_whole_or_not_at_all)
{
    char *dir = tu_tempdir();
    resurf_mesh *cube = tu_cube();
    resurf_scene *scene = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(cube, &scene, NULL), RESURF_OK);
    resurf_preview_options o = resurf_preview_options_default();
    o.width = 200;
    o.height = 100;
    resurf_preview_image img;
    ck_assert_int_eq(resurf_preview_render(scene, &o, &img, NULL, NULL), RESURF_OK);
    char *path = tu_path(dir, "sheet.png");
    ck_assert_int_eq(resurf_preview_save_png(&img, path, NULL), RESURF_OK);
    ck_assert_int_eq(tu_count_entries(dir), 1);
    size_t size, expected_size;
    char *bytes = tu_read_file(path, &size);
    unsigned char *expected = encode(&img, &expected_size);
    ck_assert_uint_eq(size, expected_size);
    ck_assert_mem_eq(bytes, expected, size);
    /* A folder that does not exist: an error naming the file, nothing written. */
    char *bad = tu_path(dir, "missing/sheet.png");
    resurf_error err;
    ck_assert_int_eq(resurf_preview_save_png(&img, bad, &err), RESURF_ERR_IO);
    ck_assert_str_eq(err.path, bad);
    ck_assert_int_eq(tu_count_entries(dir), 1);
    /* The path of a folder. */
    char *folder = tu_path(dir, "");
    ck_assert_int_eq(resurf_preview_save_png(&img, folder, NULL), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(tu_count_entries(dir), 1);
    resurf_preview_image none = {0};
    ck_assert_int_eq(resurf_preview_save_png(&none, path, NULL), RESURF_ERR_INVALID_ARGUMENT);
    free(bytes);
    free(expected);
    free(path);
    free(bad);
    free(folder);
    resurf_preview_image_free(&img);
    resurf_scene_free(scene);
    resurf_mesh_free(cube);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* A scene written with MSFT_lod and loaded again shows the same levels: their triangles and the screen coverage
 * the file carries. */
START_TEST(preview_reads_msft_lod_back)
{
    char *dir = tu_tempdir();
    char *glb = tu_path(dir, "sphere.glb");
    resurf_scene *scene = sphere_scene(6000);
    resurf_preview_options o = resurf_preview_options_default();
    o.width = 480;
    o.height = 240;
    o.compare_samples = 0;
    resurf_preview_image img;
    resurf_preview_report before, after;
    ck_assert_int_eq(resurf_preview_render(scene, &o, &img, &before, NULL), RESURF_OK);
    resurf_preview_image_free(&img);
    ck_assert_int_eq(resurf_scene_save(scene, glb, NULL, NULL, NULL), RESURF_OK);
    resurf_scene *loaded = NULL;
    ck_assert_int_eq(resurf_scene_load(glb, NULL, &loaded, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_preview_render(loaded, &o, &img, &after, NULL), RESURF_OK);
    ck_assert_uint_eq(after.levels, 3);
    for (size_t k = 0; k < 3; ++k) {
        ck_assert_uint_eq(after.level_triangles[k], before.level_triangles[k]);
        ck_assert_double_eq_tol(after.level_coverage[k], before.level_coverage[k], 1e-6);
        ck_assert_double_eq_tol(after.level_error[k], before.level_error[k], 1e-4); /* float positions in a file */
    }
    ck_assert(after.level_triangles[2] < after.level_triangles[1] && after.level_triangles[1] < 6000);
    resurf_preview_image_free(&img);
    resurf_scene_free(loaded);
    resurf_scene_free(scene);
    free(glb);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* The command line: a sheet from a mesh file, a refused size leaves no file, --help works. */
START_TEST(preview_cli)
{
    char *dir = tu_tempdir();
    char *obj = tu_path(dir, "cube.obj"), *png = tu_path(dir, "cube.png");
    resurf_mesh *cube = tu_cube();
    ck_assert_int_eq(resurf_mesh_save(cube, obj, NULL, NULL), RESURF_OK);
    char cmd[4096], *out = NULL;
    snprintf(cmd, sizeof cmd, "%s preview %s -o %s --size 100000x100000", RESURF_CLI, obj, png);
    ck_assert_int_eq(tu_run(cmd, &out), 1);
    ck_assert_ptr_nonnull(strstr(out, "pixels"));
    ck_assert_int_eq(tu_count_entries(dir), 1);
    free(out);
    snprintf(cmd, sizeof cmd, "%s preview %s -o %s --view iso --yaw 10 --wireframe --background 202020 --size 300x200",
             RESURF_CLI, obj, png);
    ck_assert_int_eq(tu_run(cmd, &out), 0);
    ck_assert_ptr_nonnull(strstr(out, "wrote"));
    ck_assert_int_eq(tu_count_entries(dir), 2);
    free(out);
    /* A glTF whose material's base-colour image is missing: drawn (untextured, as every surface is), with the
     * loader's warning about the image. */
    char *gltf = tu_path(dir, "textured.gltf");
    resurf_scene *scene = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(cube, &scene, NULL), RESURF_OK);
    resurf_scene_save_options so = resurf_scene_save_options_default();
    so.embed_buffers = 1;
    ck_assert_int_eq(resurf_scene_save(scene, gltf, &so, NULL, NULL), RESURF_OK);
    resurf_scene_free(scene);
    size_t size;
    char *json = tu_read_file(gltf, &size);
    char *last = strrchr(json, '}');
    ck_assert_ptr_nonnull(last);
    *last = 0;
    static const char material[] = ",\"images\":[{\"uri\":\"missing.png\"}],\"textures\":[{\"source\":0}],"
                                   "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}]}";
    char *edited = malloc(size + sizeof material);
    snprintf(edited, size + sizeof material, "%s%s", json, material);
    ck_assert_int_eq(tu_write_file(gltf, edited, strlen(edited)), 0);
    snprintf(cmd, sizeof cmd, "%s preview %s -o %s --size 200x100", RESURF_CLI, gltf, png);
    ck_assert_int_eq(tu_run(cmd, &out), 0);
    ck_assert_ptr_nonnull(strstr(out, "missing.png"));
    ck_assert_ptr_nonnull(strstr(out, "warning"));
    ck_assert_ptr_nonnull(strstr(out, "wrote"));
    free(out);
    free(json);
    free(edited);
    free(gltf);
    /* lod --preview: the sheet of the levels just made, beside the glTF; with --json, stdout stays JSON. */
    char *sphere = tu_path(dir, "sphere.ply"), *glb = tu_path(dir, "sphere.glb"), *sheet = tu_path(dir, "lod.png");
    resurf_mesh *ball = shape_mesh(SHAPE_SPHERE, 2000, 0.2, 1, 0);
    ck_assert_int_eq(resurf_mesh_save(ball, sphere, NULL, NULL), RESURF_OK);
    snprintf(cmd, sizeof cmd, "%s lod %s -o %s --levels 0.5,0.2 --json --preview %s --preview-size 400x200",
             RESURF_CLI, sphere, glb, sheet);
    ck_assert_int_eq(tu_run(cmd, &out), 0);
    ck_assert_msg(out[0] == '{' && strchr(out, '\n') == out + strlen(out) - 1, "%s", out);
    free(out);
    char *png_bytes = tu_read_file(sheet, &size);
    ck_assert_ptr_nonnull(png_bytes);
    ck_assert_mem_eq(png_bytes, "\x89PNG", 4);
    free(png_bytes);
    resurf_mesh_free(ball);
    free(sphere);
    free(glb);
    free(sheet);
    snprintf(cmd, sizeof cmd, "%s preview %s -o %s --size 3x", RESURF_CLI, obj, png);
    ck_assert_int_eq(tu_run(cmd, &out), 2);
    free(out);
    snprintf(cmd, sizeof cmd, "%s preview %s -o %s", RESURF_CLI, obj, obj);
    ck_assert_int_eq(tu_run(cmd, &out), 2); /* not a .png */
    free(out);
    resurf_mesh_free(cube);
    free(obj);
    free(png);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* ---- textures ------------------------------------------------------------------------------------------------ */

/* A side × side RGBA texture of four solid quadrants: red top left, green top right, blue bottom left, white
 * bottom right (rows top to bottom, as glTF's v = 0 is the image's top). */
static unsigned char *quadrant_texture(unsigned side)
{
    static const unsigned char colour[4][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 255}};
    unsigned char *rgba = malloc((size_t)side * side * 4);
    ck_assert(rgba);
    for (unsigned y = 0; y < side; ++y)
        for (unsigned x = 0; x < side; ++x) {
            const unsigned char *c = colour[(y >= side / 2) * 2 + (x >= side / 2)];
            unsigned char *p = rgba + 4 * ((size_t)y * side + x);
            p[0] = c[0], p[1] = c[1], p[2] = c[2], p[3] = 255;
        }
    return rgba;
}

/* The same texture as a baseline JPEG at quality 95, through libjpeg directly. */
static unsigned char *quadrant_jpeg(unsigned side, size_t *size)
{
    unsigned char *rgba = quadrant_texture(side), *rgb = malloc((size_t)side * 3);
    struct jpeg_compress_struct info;
    struct jpeg_error_mgr err;
    info.err = jpeg_std_error(&err);
    jpeg_create_compress(&info);
    unsigned char *out = NULL;
    unsigned long out_size = 0;
    jpeg_mem_dest(&info, &out, &out_size);
    info.image_width = side, info.image_height = side, info.input_components = 3, info.in_color_space = JCS_RGB;
    jpeg_set_defaults(&info);
    jpeg_set_quality(&info, 95, TRUE);
    jpeg_start_compress(&info, TRUE);
    for (unsigned y = 0; y < side; ++y) {
        for (unsigned x = 0; x < side; ++x)
            memcpy(rgb + 3 * x, rgba + 4 * ((size_t)y * side + x), 3);
        JSAMPROW row = rgb;
        jpeg_write_scanlines(&info, &row, 1);
    }
    jpeg_finish_compress(&info);
    jpeg_destroy_compress(&info);
    free(rgba);
    free(rgb);
    *size = out_size;
    return out;
}

/* A glTF of one quad [-1, 1]² in z = 0 facing +z, UV (0, 0) at its top left (-1, 1), whose material's base-colour
 * texture is the file `image` (size bytes of data) beside it; loaded. */
static resurf_scene *textured_quad(const char *dir, const unsigned char *data, size_t size)
{
    static const float pos[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    static const float nrm[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    static const float uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
    static const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    tu_bytes bin = {0};
    for (int i = 0; i < 12; ++i)
        tu_put_f32(&bin, pos[i]);
    for (int i = 0; i < 12; ++i)
        tu_put_f32(&bin, nrm[i]);
    for (int i = 0; i < 8; ++i)
        tu_put_f32(&bin, uv[i]);
    for (int i = 0; i < 6; ++i)
        tu_put_u16(&bin, idx[i]);
    tu_align4(&bin);
    char *image = tu_path(dir, "texture.img");
    ck_assert_int_eq(tu_write_file(image, data, size), 0);
    char *json = tu_strf(
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1,\"TEXCOORD_0\":2},"
        "\"indices\":3,\"material\":0}]}],"
        "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}],"
        "\"textures\":[{\"source\":0,\"sampler\":0}],\"samplers\":[{\"wrapS\":33071,\"wrapT\":33071}],"
        "\"images\":[{\"uri\":\"texture.img\"}],"
        "\"buffers\":[{\"uri\":\"quad.bin\",\"byteLength\":%zu}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":128},"
        "{\"buffer\":0,\"byteOffset\":128,\"byteLength\":12}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
        "\"min\":[-1,-1,0],\"max\":[1,1,0]},"
        "{\"bufferView\":0,\"byteOffset\":48,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"
        "{\"bufferView\":0,\"byteOffset\":96,\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"},"
        "{\"bufferView\":1,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}]}",
        bin.size);
    char *gltf = tu_write_gltf(dir, "quad", json, &bin);
    resurf_scene *scene = tu_load_scene_ok(gltf);
    free(gltf);
    free(json);
    free(image);
    free(bin.data);
    return scene;
}

/* The pixels of the sheet by colour: red-, green-, blue-dominant and grey (r = g = b, lit, not text nor
 * background), with their counts and centroids. */
typedef struct colour_classes {
    size_t n[4];
    double x[4], y[4];
} colour_classes;

static colour_classes classify(const resurf_preview_image *img, int tolerance)
{
    colour_classes c;
    memset(&c, 0, sizeof c);
    for (unsigned y = 0; y < img->height; ++y)
        for (unsigned x = 0; x < img->width; ++x) {
            const unsigned char *p = img->rgba + 4 * ((size_t)y * img->width + x);
            int r = p[0], g = p[1], b = p[2], k = -1;
            if (r > 40 && g <= tolerance && b <= tolerance)
                k = 0;
            else if (g > 40 && r <= tolerance && b <= tolerance)
                k = 1;
            else if (b > 40 && r <= tolerance && g <= tolerance)
                k = 2;
            else if (abs(r - g) <= tolerance && abs(g - b) <= tolerance && r > 60 && r < 250)
                k = 3;
            if (k < 0)
                continue;
            c.n[k]++, c.x[k] += x, c.y[k] += y;
        }
    for (int k = 0; k < 4; ++k)
        if (c.n[k])
            c.x[k] /= (double)c.n[k], c.y[k] /= (double)c.n[k];
    return c;
}

/* Seen from the front, the quad shows its texture the right way round: red top left, green top right, blue bottom
 * left, white bottom right, each over a quarter of the quad; a red texel stays pure red (bilinear inside a solid
 * quadrant, times the lighting). Once through PNG, once through JPEG (within its compression error). */
static void check_quadrants(const unsigned char *data, size_t size, int tolerance)
{
    char *dir = tu_tempdir();
    resurf_scene *scene = textured_quad(dir, data, size);
    resurf_preview_options o = resurf_preview_options_default();
    o.width = 240, o.height = 240, o.view = RESURF_PREVIEW_FRONT, o.measure = false;
    resurf_preview_image img;
    resurf_preview_report rep;
    ck_assert_int_eq(resurf_preview_render(scene, &o, &img, &rep, NULL), RESURF_OK);
    ck_assert_uint_eq(rep.textures_undrawn, 0);
    colour_classes c = classify(&img, tolerance);
    size_t total = c.n[0] + c.n[1] + c.n[2] + c.n[3];
    ck_assert_uint_gt(total, 2000);
    for (int k = 0; k < 4; ++k) /* each a quarter, give or take the boundary's blend */
        ck_assert_msg(fabs((double)c.n[k] / (double)total - 0.25) < 0.04, "class %d: %zu of %zu", k, c.n[k], total);
    ck_assert(c.x[0] < c.x[1] && c.x[2] < c.x[3]);   /* red left of green, blue left of white */
    ck_assert(c.y[0] < c.y[2] && c.y[1] < c.y[3]);   /* red above blue, green above white (y grows downwards) */
    resurf_preview_image_free(&img);
    resurf_scene_free(scene);
    tu_rmtree(dir);
    free(dir);
}

START_TEST(preview_draws_png_and_jpeg_textures)
{
    unsigned char *rgba = quadrant_texture(8), *png = NULL;
    size_t png_size = 0;
    ck_assert_int_eq(rp_png_encode(rgba, 8, 8, NULL, &png, &png_size, NULL), RESURF_OK);
    check_quadrants(png, png_size, 0);
    free(png);
    free(rgba);
    size_t jpeg_size = 0;
    unsigned char *jpeg = quadrant_jpeg(32, &jpeg_size);
    check_quadrants(jpeg, jpeg_size, 12);
    free(jpeg);
}
END_TEST

/* An image that is neither PNG nor JPEG, or a broken PNG: the quad is drawn with its material's colour alone (grey
 * under white light: no pixel of a texture's colours), and the report counts the image and says why. */
START_TEST(preview_undecodable_texture_is_drawn_plain)
{
    static const unsigned char broken_png[16] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H'};
    static const char not_an_image[] = "GIF89a and more";
    const unsigned char *inputs[2] = {broken_png, (const unsigned char *)not_an_image};
    size_t sizes[2] = {sizeof broken_png, sizeof not_an_image};
    const char *why[2] = {"PNG", "neither PNG nor JPEG"};
    for (int i = 0; i < 2; ++i) {
        char *dir = tu_tempdir();
        resurf_scene *scene = textured_quad(dir, inputs[i], sizes[i]);
        resurf_preview_options o = resurf_preview_options_default();
        o.width = 160, o.height = 160, o.view = RESURF_PREVIEW_FRONT, o.measure = false;
        resurf_preview_image img;
        resurf_preview_report rep;
        ck_assert_int_eq(resurf_preview_render(scene, &o, &img, &rep, NULL), RESURF_OK);
        ck_assert_uint_eq(rep.textures_undrawn, 1);
        ck_assert_msg(strstr(rep.texture_warning, "images[0]") && strstr(rep.texture_warning, why[i]), "%s",
                      rep.texture_warning);
        colour_classes c = classify(&img, 0);
        ck_assert_uint_eq(c.n[0] + c.n[1] + c.n[2], 0);
        ck_assert_uint_gt(c.n[3], 1000);
        resurf_preview_image_free(&img);
        resurf_scene_free(scene);
        tu_rmtree(dir);
        free(dir);
    }
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("preview");
    TCase *tc = tcase_create("preview");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, preview_sphere_covers_analytic_disc);
    tcase_add_test(tc, preview_cube_face_fills_square);
    tcase_add_test(tc, preview_same_bytes_for_any_thread_count);
    tcase_add_test(tc, preview_heatmap_range_on_analytic_sphere);
    tcase_add_test(tc, preview_refuses_huge_sizes);
    tcase_add_test(tc, preview_draws_empty_and_degenerate_meshes);
    tcase_add_test(tc, preview_png_written_whole_or_not_at_all);
    tcase_add_test(tc, preview_reads_msft_lod_back);
    tcase_add_test(tc, preview_cli);
    tcase_add_test(tc, preview_draws_png_and_jpeg_textures);
    tcase_add_test(tc, preview_undecodable_texture_is_drawn_plain);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
