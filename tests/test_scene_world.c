/* Tests of the scene in world space: resurf_scene_world_mesh (src/scene_world.c) and what resurf_scene_build_lods
 * measures and decides with it (src/scene_lods.c): level errors over the whole scene in world units, levels that
 * help, no crack between the primitives of a mesh.
 * The truths: world positions and normals computed by hand from the node transforms; an error that scales with the
 * node's scale while its relative value stays; shared border positions compared bit for bit. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "testutil.h"

/* ---- a glTF of hand-made primitives ----------------------------------------------------------------------- */

/* A growing string. */
typedef struct text {
    char *s;
    size_t n;
} text;

static void put(text *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void put(text *t, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int len = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    t->s = realloc(t->s, t->n + (size_t)len + 1);
    ck_assert_ptr_nonnull(t->s);
    va_start(ap, fmt);
    vsnprintf(t->s + t->n, (size_t)len + 1, fmt, ap);
    va_end(ap);
    t->n += (size_t)len;
}

/* One bufferView + accessor of float components (or uint32 indices when components is 0). */
static void put_accessor(text *views, text *accs, tu_bytes *bin, size_t *count, const double *data, size_t n,
                         unsigned components, const uint32_t *indices)
{
    size_t at = bin->size;
    if (indices) {
        tu_put(bin, indices, 4 * n);
    } else {
        for (size_t i = 0; i < n * components; ++i)
            tu_put_f32(bin, (float)data[i]);
    }
    put(views, "%s{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}", *count ? "," : "", at, bin->size - at);
    if (indices) {
        put(accs, "%s{\"bufferView\":%zu,\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"}", *count ? "," : "",
            *count, n);
    } else if (components == 3 && !indices && data) {
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (size_t i = 0; i < 3 * n; ++i) {
            double f = (float)data[i];
            lo[i % 3] = fmin(lo[i % 3], f);
            hi[i % 3] = fmax(hi[i % 3], f);
        }
        put(accs,
            "%s{\"bufferView\":%zu,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\",\"min\":[%.9g,%.9g,%.9g],"
            "\"max\":[%.9g,%.9g,%.9g]}",
            *count ? "," : "", *count, n, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    } else {
        put(accs, "%s{\"bufferView\":%zu,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC%u\"}", *count ? "," : "",
            *count, n, components);
    }
    ++*count;
}

/* DIR/NAME.gltf with primitive p = prims[p] in glTF mesh prim_mesh[p] (non-decreasing from 0), POSITION, NORMAL
 * and TEXCOORD_0 as each mesh has them; nodes_json is the "nodes" array, and the one scene lists scene_nodes. */
static char *write_scene(const char *dir, const char *name, resurf_mesh *const *prims, const int *prim_mesh,
                         size_t prim_count, const char *nodes_json, const char *scene_nodes)
{
    text views = {0}, accs = {0}, meshes = {0};
    tu_bytes bin = {0};
    size_t count = 0;
    int mesh = -1;
    for (size_t p = 0; p < prim_count; ++p) {
        const resurf_mesh *m = prims[p];
        if (prim_mesh[p] != mesh) {
            put(&meshes, "%s{\"primitives\":[", mesh >= 0 ? "]}," : "");
            mesh = prim_mesh[p];
        } else {
            put(&meshes, ",");
        }
        size_t pos = count;
        put_accessor(&views, &accs, &bin, &count, m->positions, m->vertex_count, 3, NULL);
        put(&meshes, "{\"attributes\":{\"POSITION\":%zu", pos);
        if (m->normals) {
            put(&meshes, ",\"NORMAL\":%zu", count);
            put_accessor(&views, &accs, &bin, &count, m->normals, m->vertex_count, 0 + 3, NULL);
        }
        if (m->texcoord_count) {
            put(&meshes, ",\"TEXCOORD_0\":%zu", count);
            put_accessor(&views, &accs, &bin, &count, m->texcoords[0], m->vertex_count, 2, NULL);
        }
        put(&meshes, "},\"indices\":%zu}", count);
        put_accessor(&views, &accs, &bin, &count, NULL, 3 * m->triangle_count, 0, m->indices);
    }
    char *json = tu_strf("{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[%s]}],\"nodes\":%s,"
                         "\"meshes\":[%s]}],\"accessors\":[%s],\"bufferViews\":[%s],"
                         "\"buffers\":[{\"uri\":\"%s.bin\",\"byteLength\":%zu}]}",
                         scene_nodes, nodes_json, meshes.s, accs.s, views.s, name, bin.size);
    char *path = tu_write_gltf(dir, name, json, &bin);
    free(json);
    free(views.s);
    free(accs.s);
    free(meshes.s);
    free(bin.data);
    return path;
}

static resurf_mesh *world_ok(const resurf_scene *s, int level)
{
    resurf_mesh *w = NULL;
    resurf_error e;
    resurf_status st = resurf_scene_world_mesh(s, level, NULL, &w, &e);
    ck_assert_msg(st == RESURF_OK, "world mesh: %s", e.message);
    return w;
}

/* ---- resurf_scene_world_mesh ----------------------------------------------------------------------------- */

/* One triangle with a slanted normal and texcoords, shown by node 0 (translation (1, 2, 3)) and by its child node 1
 * (scale (2, 3, 4)): node 1's world matrix is T·S, so a corner p lands at (2x + 1, 3y + 2, 4z + 3) and a normal n at
 * S⁻¹n renormalised. */
START_TEST(world_mesh_applies_node_transforms)
{
    static const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 1};
    static const uint32_t idx[] = {0, 1, 2};
    resurf_mesh *m = tu_mesh(pos, 3, idx, 1), *with = NULL;
    ck_assert_int_eq(resurf_mesh_create(3, 1, RESURF_ATTR_NORMALS | RESURF_ATTR_TEXCOORD0, &with, NULL), RESURF_OK);
    memcpy(with->positions, pos, sizeof pos);
    memcpy(with->indices, idx, sizeof idx);
    for (size_t k = 0; k < 3; ++k) {
        for (size_t c = 0; c < 3; ++c)
            with->normals[3 * k + c] = 1 / sqrt(3.0);
        with->texcoords[0][2 * k] = 0.25 * (double)k;
        with->texcoords[0][2 * k + 1] = 0.5;
    }
    char *dir = tu_tempdir();
    int prim_mesh[] = {0};
    char *path = write_scene(dir, "two", &with, prim_mesh, 1,
                             "[{\"translation\":[1,2,3],\"children\":[1],\"mesh\":0},{\"scale\":[2,3,4],\"mesh\":0}]",
                             "0");
    resurf_scene *s = tu_load_scene_ok(path);
    resurf_mesh *w = world_ok(s, 0);
    ck_assert_uint_eq(w->vertex_count, 6);
    ck_assert_uint_eq(w->triangle_count, 2);
    ck_assert_ptr_nonnull(w->normals);
    ck_assert_uint_eq(w->texcoord_count, 1);
    static const double expect[] = {1, 2, 3, 2, 2, 3, 1, 3, 4, /* node 0: translated */
                                    1, 2, 3, 3, 2, 3, 1, 5, 7}; /* node 1: scaled, then translated */
    for (size_t i = 0; i < 18; ++i)
        ck_assert_double_eq_tol(w->positions[i], expect[i], 1e-6);
    double n1[3] = {1 / 2.0, 1 / 3.0, 1 / 4.0}, len = sqrt(n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]);
    for (size_t c = 0; c < 3; ++c) {
        ck_assert_double_eq_tol(w->normals[c], 1 / sqrt(3.0), 1e-6);
        ck_assert_double_eq_tol(w->normals[9 + c], n1[c] / len, 1e-6);
    }
    ck_assert_double_eq_tol(w->texcoords[0][2 * 4], 0.25, 1e-7);
    for (size_t k = 0; k < 6; ++k)
        ck_assert_uint_eq(w->indices[k], k);
    resurf_mesh_free(w);
    /* A level beyond the primitive's levels is its last: level 0 here. */
    w = world_ok(s, 3);
    ck_assert_uint_eq(w->vertex_count, 6);
    ck_assert_double_eq_tol(w->positions[17], 7, 1e-6);
    resurf_mesh_free(w);
    resurf_error e;
    ck_assert_int_eq(resurf_scene_world_mesh(s, -1, NULL, &w, &e), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(w);
    resurf_scene_free(s);
    resurf_mesh_free(with);
    resurf_mesh_free(m);
    free(path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* A scene made from a mesh has no nodes: the mesh untransformed, its normals absent. */
START_TEST(world_mesh_of_a_mesh_scene)
{
    resurf_mesh *m = tu_cube();
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(m, &s, NULL), RESURF_OK);
    resurf_mesh *w = world_ok(s, 0);
    ck_assert_uint_eq(w->vertex_count, m->vertex_count);
    ck_assert_uint_eq(w->triangle_count, m->triangle_count);
    ck_assert_ptr_null(w->normals);
    ck_assert_mem_eq(w->positions, m->positions, 3 * m->vertex_count * sizeof(double));
    resurf_mesh_free(w);
    resurf_scene_free(s);
    resurf_mesh_free(m);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("scene_world");
    TCase *tc = tcase_create("world");
    tcase_add_test(tc, world_mesh_applies_node_transforms);
    tcase_add_test(tc, world_mesh_of_a_mesh_scene);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
