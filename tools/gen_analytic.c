/* resurf-gen-analytic: meshes of analytic surfaces with every vertex exactly on the surface (tools/shapes.h).
 *
 *   resurf-gen-analytic SHAPE TRIANGLES OUT [--jitter J] [--seed S] [--normals]
 *   resurf-gen-analytic morph-sphere TRIANGLES OUT.glb [--jitter J] [--seed S]
 *                                         the sphere with a morph target that makes an ellipsoid (morph_asset.h)
 *   resurf-gen-analytic --data DIR        the bundled set in data/ (what tools/make-data.sh runs)
 *   resurf-gen-analytic --skinned-cylinder OUT.glb [--ubyte-weights]   the two-bone cylinder of skinned_cylinder.h
 *   resurf-gen-analytic --sphere-scene N OUT.glb   N small latitude-longitude spheres, a mesh each (sphere_scene.h)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "morph_asset.h"
#include "shapes.h"
#include "skinned_cylinder.h"
#include "sphere_scene.h"

/* The bundled meshes: small, irregular, reproducible. */
static const struct {
    const char *file;
    shape_kind kind;
    size_t triangles;
    double jitter;
} bundled[] = {
    {"sphere.ply", SHAPE_SPHERE, 20000, 0.35},
    {"torus.ply", SHAPE_TORUS, 20000, 0.35},
    {"cubic.ply", SHAPE_CUBIC, 8000, 0.35},
};

static int write_shape(shape_kind kind, size_t triangles, double jitter, unsigned long long seed, int normals,
                       const char *out)
{
    resurf_mesh *m = shape_mesh(kind, triangles, jitter, seed, normals);
    if (!m) {
        fprintf(stderr, "resurf-gen-analytic: out of memory\n");
        return 1;
    }
    resurf_save_options options = resurf_save_options_default();
    resurf_error error;
    int rc = 0;
    if (resurf_mesh_save(m, out, &options, &error) != RESURF_OK) {
        char text[1024];
        resurf_format_error(text, sizeof text, &error);
        fprintf(stderr, "resurf-gen-analytic: %s\n", text);
        rc = 1;
    } else {
        printf("%-12s %-9s %8zu vertices %8zu triangles  jitter %.2f\n", out, shape_name(kind), m->vertex_count,
               m->triangle_count, jitter);
    }
    resurf_mesh_free(m);
    return rc;
}

static int write_morph(size_t triangles, double jitter, unsigned long long seed, const char *out)
{
    resurf_mesh *m = morph_sphere_mesh(triangles, jitter, seed, morph_asset_axes);
    size_t size = 0;
    unsigned char *glb = m ? morph_glb(m, &size) : NULL;
    FILE *f = glb ? fopen(out, "wb") : NULL;
    int rc = !f || fwrite(glb, 1, size, f) != size;
    if (f && fclose(f))
        rc = 1;
    if (rc)
        fprintf(stderr, "resurf-gen-analytic: cannot write %s\n", out);
    else
        printf("%-12s %-9s %8zu vertices %8zu triangles  jitter %.2f, one morph target (ellipsoid %g, %g, %g)\n",
               out, "morph", m->vertex_count, m->triangle_count, jitter, morph_asset_axes[0], morph_asset_axes[1],
               morph_asset_axes[2]);
    free(glb);
    resurf_mesh_free(m);
    return rc;
}

static int usage(void)
{
    fprintf(stderr, "usage: resurf-gen-analytic SHAPE TRIANGLES OUT [--jitter J] [--seed S] [--normals]\n"
                    "       resurf-gen-analytic morph-sphere TRIANGLES OUT.glb [--jitter J] [--seed S]\n"
                    "       resurf-gen-analytic --data DIR\n"
                    "       resurf-gen-analytic --skinned-cylinder OUT.glb [--ubyte-weights]\n"
                    "       resurf-gen-analytic --sphere-scene N OUT.glb\n"
                    "shapes: sphere torus cubic cylinder saddle plane\n");
    return 2;
}

int main(int argc, char **argv)
{
    if (argc == 3 && !strcmp(argv[1], "--data")) {
        int rc = 0;
        for (size_t i = 0; i < sizeof bundled / sizeof bundled[0]; ++i) {
            char path[4096];
            snprintf(path, sizeof path, "%s/%s", argv[2], bundled[i].file);
            rc |= write_shape(bundled[i].kind, bundled[i].triangles, bundled[i].jitter, 1, 0, path);
        }
        char path[4096];
        snprintf(path, sizeof path, "%s/morph-sphere.glb", argv[2]);
        return rc | write_morph(1200, 0.35, 1, path);
    }
    if (argc == 4 && !strcmp(argv[1], "--sphere-scene")) {
        char *end;
        unsigned long count = strtoul(argv[2], &end, 10);
        if (*end || count == 0 || count > 100000)
            return usage();
        size_t size = 0;
        unsigned char *glb = sphere_scene_glb((unsigned)count, 16, 8, &size);
        FILE *f = glb ? fopen(argv[3], "wb") : NULL;
        int rc = !f || fwrite(glb, 1, size, f) != size;
        if (f && fclose(f))
            rc = 1;
        free(glb);
        if (rc)
            fprintf(stderr, "resurf-gen-analytic: cannot write %s\n", argv[3]);
        return rc;
    }
    if ((argc == 3 || argc == 4) && !strcmp(argv[1], "--skinned-cylinder")) {
        int ubyte = argc == 4 && !strcmp(argv[3], "--ubyte-weights");
        if (argc == 4 && !ubyte)
            return usage();
        if (skinned_cylinder_write(argv[2], 24, 40, ubyte ? SKINNED_CYLINDER_UBYTE : 0)) {
            fprintf(stderr, "resurf-gen-analytic: cannot write %s\n", argv[2]);
            return 1;
        }
        return 0;
    }
    if (argc < 4)
        return usage();
    int morph = !strcmp(argv[1], "morph-sphere");
    shape_kind kind = morph ? SHAPE_SPHERE : shape_from_name(argv[1]);
    char *end;
    unsigned long long triangles = strtoull(argv[2], &end, 10);
    if (kind == SHAPE_COUNT || *end || triangles == 0)
        return usage();
    double jitter = 0.35;
    unsigned long long seed = 1;
    int normals = 0;
    for (int i = 4; i < argc; ++i) {
        if (!strcmp(argv[i], "--jitter") && i + 1 < argc)
            jitter = atof(argv[++i]);
        else if (!strcmp(argv[i], "--seed") && i + 1 < argc)
            seed = strtoull(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--normals"))
            normals = 1;
        else
            return usage();
    }
    if (morph)
        return write_morph((size_t)triangles, jitter, seed, argv[3]);
    return write_shape(kind, (size_t)triangles, jitter, seed, normals, argv[3]);
}
