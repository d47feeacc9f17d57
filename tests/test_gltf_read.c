/* Tests of reading glTF (src/scene.c, src/scene_check.c and the glTF/Draco shims in src/io/): hand-written
 * documents whose decoded content is known by construction (strips, fans, sparse accessors, normalized and quantized
 * components, instancing, skins, morph targets, points, Draco primitives), what a save keeps of everything else, and
 * hostile documents, Draco payloads and .glb containers, which fail cleanly with their own messages.
 *
 * Independent checks: the Khronos glTF validator (tools/validate-gltf.js, npm gltf-validator) on every file written
 * and small node scripts that read the written JSON (tu_validator_errors, tu_node_eval in testutil.c). */
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "testutil.h"

/* ---- hand-written documents ---------------------------------------------------------------------------------- */

/* Six points on a zigzag, as a strip and as a fan:
 *   1---3---5        strip 0 1 2 3 4 5: (0,1,2) (1,3,2) (2,3,4) (3,5,4)   (glTF: odd triangles swap to keep
 *   |\  |\  |                                                              the winding)
 *   0---2---4        fan   0 1 2 3 4 5: (1,2,0) (2,3,0) (3,4,0) (4,5,0)                                      */
static char *zigzag_gltf(const char *dir, const char *name, int mode)
{
    tu_bytes b = {0};
    static const float p[6][3] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {2, 0, 0}, {2, 1, 0}};
    for (int i = 0; i < 6; ++i)
        for (int k = 0; k < 3; ++k)
            tu_put_f32(&b, p[i][k]);
    for (int i = 0; i < 6; ++i)
        tu_put_u16(&b, (uint16_t)i);
    tu_align4(&b);
    char *json = tu_strf("{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
                      "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,\"mode\":%d}]}],"
                      "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":6,\"type\":\"VEC3\","
                      "\"min\":[0,0,0],\"max\":[2,1,0]},"
                      "{\"bufferView\":1,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}],"
                      "\"bufferViews\":[{\"buffer\":0,\"byteLength\":72},{\"buffer\":0,\"byteOffset\":72,\"byteLength\":12}],"
                      "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s.bin\"}]}",
                      mode, b.size, name);
    char *path = tu_write_gltf(dir, name, json, &b);
    free(json);
    free(b.data);
    return path;
}

START_TEST(gltf_strips_and_fans_become_lists)
{
    char *dir = tu_tempdir();
    static const uint32_t strip[] = {0, 1, 2, 2, 1, 3, 2, 3, 4, 4, 3, 5};
    static const uint32_t fan[] = {1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5, 0};
    for (int mode = 5; mode <= 6; ++mode) {
        char *path = zigzag_gltf(dir, mode == 5 ? "strip" : "fan", mode);
        resurf_scene *s = tu_load_scene_ok(path);
        const resurf_mesh *m = resurf_scene_primitive_mesh(s, 0);
        ck_assert_uint_eq(m->triangle_count, 4);
        const uint32_t *want = mode == 5 ? strip : fan;
        for (int i = 0; i < 12; ++i) {
            /* Same triangle up to rotation of its corners (the winding is what matters). */
            int t = i / 3, ok = 0;
            for (int r = 0; r < 3; ++r)
                ok |= m->indices[3 * t] == want[3 * t + r] && m->indices[3 * t + 1] == want[3 * t + (r + 1) % 3] &&
                      m->indices[3 * t + 2] == want[3 * t + (r + 2) % 3];
            ck_assert_msg(ok, "mode %d triangle %d", mode, t);
        }
        resurf_scene_primitive info;
        resurf_scene_primitive_info(s, 0, &info, NULL);
        ck_assert_int_eq(info.mode, mode);
        /* Written back as a triangle list that the validator accepts. */
        char *out = tu_strf("%s/out%d.glb", dir, mode);
        tu_save_scene_ok(s, out, NULL, NULL);
        ck_assert_int_eq(tu_validator_errors(out), 0);
        free(out);
        resurf_scene_free(s);
        free(path);
    }
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* POSITION: 3 base vertices, then a sparse override of vertices 0 and 2; TEXCOORD_0 normalized uint8, TEXCOORD_1
 * normalized uint16, COLOR_0 normalized uint8 VEC3. */
START_TEST(gltf_sparse_and_normalized_components)
{
    char *dir = tu_tempdir();
    tu_bytes b = {0};
    static const float base[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    for (int i = 0; i < 9; ++i)
        tu_put_f32(&b, base[i]); /* 0..35 */
    tu_put_u16(&b, 0), tu_put_u16(&b, 2); /* 36..39 sparse indices */
    static const float over[6] = {5, 5, 5, 7, 8, 9};
    for (int i = 0; i < 6; ++i)
        tu_put_f32(&b, over[i]); /* 40..63 sparse values */
    static const uint8_t uv8[6] = {0, 255, 51, 102, 255, 0};
    for (int i = 0; i < 6; ++i)
        tu_put_u8(&b, uv8[i]); /* 64..69 */
    tu_align4(&b);              /* 72 */
    static const uint16_t uv16[6] = {0, 65535, 13107, 26214, 65535, 0};
    for (int i = 0; i < 6; ++i)
        tu_put_u16(&b, uv16[i]); /* 72..83 */
    static const uint8_t rgb[12] = {255, 0, 0, 0, 0, 255, 0, 0, 0, 0, 255, 0}; /* VEC3 rows padded to 4 bytes */
    for (int i = 0; i < 12; ++i)
        tu_put_u8(&b, rgb[i]); /* 84..95 */
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1,\"TEXCOORD_1\":2,"
        "\"COLOR_0\":3}}]}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],"
        "\"max\":[7,8,9],\"sparse\":{\"count\":2,\"indices\":{\"bufferView\":1,\"componentType\":5123},"
        "\"values\":{\"bufferView\":2}}},"
        "{\"bufferView\":3,\"componentType\":5121,\"normalized\":true,\"count\":3,\"type\":\"VEC2\"},"
        "{\"bufferView\":4,\"componentType\":5123,\"normalized\":true,\"count\":3,\"type\":\"VEC2\"},"
        "{\"bufferView\":5,\"componentType\":5121,\"normalized\":true,\"count\":3,\"type\":\"VEC3\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,\"byteLength\":4},"
        "{\"buffer\":0,\"byteOffset\":40,\"byteLength\":24},{\"buffer\":0,\"byteOffset\":64,\"byteLength\":6},"
        "{\"buffer\":0,\"byteOffset\":72,\"byteLength\":12},{\"buffer\":0,\"byteOffset\":84,\"byteLength\":12,"
        "\"byteStride\":4}],"
        "\"buffers\":[{\"byteLength\":96,\"uri\":\"sparse.bin\"}]}";
    char *path = tu_write_gltf(dir, "sparse", json, &b);
    resurf_scene *s = tu_load_scene_ok(path);
    const resurf_mesh *m = resurf_scene_primitive_mesh(s, 0);
    static const double want_p[9] = {5, 5, 5, 1, 0, 0, 7, 8, 9};
    for (int i = 0; i < 9; ++i)
        ck_assert(m->positions[i] == want_p[i]);
    ck_assert_uint_eq(m->triangle_count, 1);
    ck_assert_uint_eq(m->texcoord_count, 2);
    for (int i = 0; i < 6; ++i) {
        ck_assert(m->texcoords[0][i] == uv8[i] / 255.0);
        ck_assert(m->texcoords[1][i] == uv16[i] / 65535.0);
    }
    ck_assert_uint_eq(m->color_components, 3);
    for (int v = 0; v < 3; ++v)
        for (int k = 0; k < 4; ++k)
            ck_assert(m->colors[4 * v + k] == (k == 3 ? 1.0 : rgb[4 * v + k] / 255.0));
    char *out = tu_path(dir, "out.gltf");
    tu_save_scene_ok(s, out, NULL, NULL);
    ck_assert_int_eq(tu_validator_errors(out), 0);
    free(out);
    resurf_scene_free(s);
    free(path);
    free(b.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* KHR_mesh_quantization: SHORT positions (not normalized, scaled by the node) and normalized BYTE normals. */
START_TEST(gltf_mesh_quantization_input)
{
    char *dir = tu_tempdir();
    tu_bytes b = {0};
    static const int16_t q[9] = {0, 0, 0, 1000, 0, 0, 0, -1000, 0};
    for (int i = 0; i < 3; ++i) { /* stride 8: x y z and 2 bytes of padding (vertex attributes align to 4) */
        tu_put_i16(&b, q[3 * i]), tu_put_i16(&b, q[3 * i + 1]), tu_put_i16(&b, q[3 * i + 2]), tu_put_i16(&b, 0);
    }
    for (int i = 0; i < 3; ++i) { /* normals (0, 0, 127) → (0, 0, 1), stride 4 */
        tu_put_u8(&b, 0), tu_put_u8(&b, 0), tu_put_u8(&b, 127), tu_put_u8(&b, 0);
    }
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_mesh_quantization\"],"
        "\"extensionsRequired\":[\"KHR_mesh_quantization\"],\"scenes\":[{\"nodes\":[0]}],"
        "\"nodes\":[{\"mesh\":0,\"scale\":[0.001,0.001,0.001]}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1}}]}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5122,\"count\":3,\"type\":\"VEC3\",\"min\":[0,-1000,0],"
        "\"max\":[1000,0,0]},{\"bufferView\":1,\"componentType\":5120,\"normalized\":true,\"count\":3,"
        "\"type\":\"VEC3\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":24,\"byteStride\":8},"
        "{\"buffer\":0,\"byteOffset\":24,\"byteLength\":12,\"byteStride\":4}],"
        "\"buffers\":[{\"byteLength\":36,\"uri\":\"quant.bin\"}]}";
    char *path = tu_write_gltf(dir, "quant", json, &b);
    resurf_scene *s = tu_load_scene_ok(path);
    const resurf_mesh *m = resurf_scene_primitive_mesh(s, 0);
    for (int i = 0; i < 9; ++i)
        ck_assert(m->positions[i] == q[i]);
    for (int v = 0; v < 3; ++v)
        ck_assert(m->normals[3 * v] == 0 && m->normals[3 * v + 1] == 0 && m->normals[3 * v + 2] == 1.0);
    /* Written as floats: the extension is no longer used, the node scale still applies. */
    char *out = tu_path(dir, "out.glb");
    tu_save_scene_ok(s, out, NULL, NULL);
    ck_assert_int_eq(tu_validator_errors(out), 0);
    char *facts = tu_node_eval(dir, TU_JS_LOAD "console.log(JSON.stringify(doc.extensionsRequired||[]),"
                                         "doc.nodes[0].scale.join(','))", out);
    ck_assert_str_eq(facts, "[] 0.001,0.001,0.001");
    free(facts);
    free(out);
    resurf_scene_free(s);
    free(path);
    free(b.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST


/* KHR_mesh_quantization's TANGENT in normalized shorts: rewritten primitives keep the format and so keep the
 * extension (with and without Draco), and a level's tangents, shortened here to half length as interpolation
 * would, are written unit length. The validator rejects either mistake. */
START_TEST(gltf_quantized_tangents_keep_the_extension)
{
    char *dir = tu_tempdir();
    tu_bytes b = {0};
    static const float square[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    for (int i = 0; i < 12; ++i)
        tu_put_f32(&b, square[i]); /* 0..47 */
    for (int v = 0; v < 4; ++v) /* (1, 0, 0, 1) as normalized shorts, 48..79 */
        tu_put_i16(&b, 32767), tu_put_i16(&b, 0), tu_put_i16(&b, 0), tu_put_i16(&b, 32767);
    static const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    for (int i = 0; i < 6; ++i)
        tu_put_u16(&b, idx[i]); /* 80..91 */
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_mesh_quantization\"],"
        "\"extensionsRequired\":[\"KHR_mesh_quantization\"],\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TANGENT\":1},\"indices\":2}]}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\"min\":[0,0,0],"
        "\"max\":[1,1,0]},{\"bufferView\":1,\"componentType\":5122,\"normalized\":true,\"count\":4,"
        "\"type\":\"VEC4\"},{\"bufferView\":2,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,\"byteLength\":32},"
        "{\"buffer\":0,\"byteOffset\":80,\"byteLength\":12}],"
        "\"buffers\":[{\"byteLength\":92,\"uri\":\"qt.bin\"}]}";
    char *path = tu_write_gltf(dir, "qt", json, &b);
    resurf_scene *s = tu_load_scene_ok(path);
    resurf_mesh *level = NULL;
    ck_assert_int_eq(resurf_mesh_clone(resurf_scene_primitive_mesh(s, 0), &level, NULL), RESURF_OK);
    level->triangle_count = 1;
    resurf_attribute *t = NULL;
    for (size_t i = 0; i < level->extra_count; ++i)
        if (!strcmp(level->extras[i].name, "TANGENT"))
            t = &level->extras[i];
    ck_assert_ptr_nonnull(t);
    ck_assert(t->components == 4 && t->data[0] == 1.0f);
    for (size_t v = 0; v < level->vertex_count; ++v)
        t->data[4 * v] = 0.5f;
    const resurf_mesh *lods[1] = {level};
    ck_assert_int_eq(resurf_scene_set_lods(s, 0, lods, 1, NULL), RESURF_OK);
    for (int draco = 0; draco < 2; ++draco) {
        char *out = tu_strf("%s/out%d.glb", dir, draco);
        resurf_scene_save_options o = resurf_scene_save_options_default();
        o.draco = draco;
        tu_save_scene_ok(s, out, &o, NULL);
        ck_assert_int_eq(tu_validator_errors(out), 0);
        char *facts = tu_node_eval(dir, TU_JS_LOAD "console.log(JSON.stringify(doc.extensionsRequired.sort()),"
                                             "doc.accessors[doc.meshes[0].primitives[0].attributes.TANGENT]"
                                             ".componentType)", out);
        ck_assert_str_eq(facts, draco ? "[\"KHR_draco_mesh_compression\",\"KHR_mesh_quantization\"] 5122"
                                      : "[\"KHR_mesh_quantization\"] 5122");
        free(facts);
        free(out);
    }
    resurf_mesh_free(level);
    resurf_scene_free(s);
    free(path);
    free(b.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* One mesh shown by two nodes: one primitive, two instances, simplified and written once. */
START_TEST(gltf_instanced_mesh_is_handled_once)
{
    char *dir = tu_tempdir();
    tu_bytes b = tu_tetra_bin();
    const char *json = "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
                       "\"nodes\":[{\"mesh\":0},{\"mesh\":0,\"translation\":[3,0,0]}],"
                       "\"meshes\":[{\"name\":\"tetra\",\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
                       "\"accessors\":[" TU_TETRA_ACCESSORS "],\"bufferViews\":[" TU_TETRA_VIEWS "],"
                       "\"buffers\":[{\"byteLength\":72,\"uri\":\"inst.bin\"}]}";
    char *path = tu_write_gltf(dir, "inst", json, &b);
    resurf_scene *s = tu_load_scene_ok(path);
    ck_assert_uint_eq(resurf_scene_primitive_count(s), 1);
    resurf_scene_primitive info;
    resurf_scene_primitive_info(s, 0, &info, NULL);
    ck_assert_uint_eq(info.instances, 2);
    ck_assert_str_eq(info.mesh_name, "tetra");
    /* One level: three of the four triangles. */
    resurf_mesh *lod = tu_tetrahedron();
    lod->triangle_count = 3;
    const resurf_mesh *lods[1] = {lod};
    ck_assert_int_eq(resurf_scene_set_lods(s, 0, lods, 1, NULL), RESURF_OK);
    char *out = tu_path(dir, "lod.gltf");
    tu_save_scene_ok(s, out, NULL, NULL);
    ck_assert_int_eq(tu_validator_errors(out), 0);
    /* Two meshes (full detail and one level, shared), both nodes with MSFT_lod pointing at nodes that show the
     * same level mesh. */
    char *facts = tu_node_eval(dir, TU_JS_LOAD
                            "const ids=doc.nodes.slice(0,2).map(n=>n.extensions.MSFT_lod.ids[0]);"
                            "console.log(doc.meshes.length, ids.map(i=>doc.nodes[i].mesh).join(','),"
                            "doc.nodes[ids[1]].translation.join(','))", out);
    ck_assert_str_eq(facts, "2 1,1 3,0,0");
    free(facts);
    free(out);
    resurf_mesh_free(lod);
    resurf_scene_free(s);
    free(path);
    free(b.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST


/* A skinned tetrahedron: JOINTS_0 (ubyte) and WEIGHTS_0 (float) come in as extras and go out as they were, at
 * full detail and at a level; the skin, its joints and inverse bind matrices survive. */
START_TEST(gltf_skinned_primitive_keeps_joints_and_weights)
{
    char *dir = tu_tempdir();
    tu_bytes b = tu_tetra_bin(); /* 0..71 */
    for (int v = 0; v < 4; ++v) { /* joints 72..87: vertex v uses joints (v%2, 1-v%2) */
        tu_put_u8(&b, (uint8_t)(v % 2)), tu_put_u8(&b, (uint8_t)(1 - v % 2)), tu_put_u8(&b, 0), tu_put_u8(&b, 0);
    }
    for (int v = 0; v < 4; ++v) { /* weights 88..151 */
        tu_put_f32(&b, 0.75f), tu_put_f32(&b, 0.25f), tu_put_f32(&b, 0), tu_put_f32(&b, 0);
    }
    for (int j = 0; j < 2; ++j) /* identity inverse bind matrices 152..279 */
        for (int i = 0; i < 16; ++i)
            tu_put_f32(&b, i % 5 == 0 ? 1.0f : 0.0f);
    char *json = tu_strf(
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
        "\"nodes\":[{\"mesh\":0,\"skin\":0},{\"children\":[2]},{\"translation\":[0,1,0]}],"
        "\"skins\":[{\"joints\":[1,2],\"inverseBindMatrices\":4}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"JOINTS_0\":2,\"WEIGHTS_0\":3},\"indices\":1}]}],"
        "\"accessors\":[" TU_TETRA_ACCESSORS ",{\"bufferView\":2,\"componentType\":5121,\"count\":4,\"type\":\"VEC4\"},"
        "{\"bufferView\":3,\"componentType\":5126,\"count\":4,\"type\":\"VEC4\"},"
        "{\"bufferView\":4,\"componentType\":5126,\"count\":2,\"type\":\"MAT4\"}],"
        "\"bufferViews\":[" TU_TETRA_VIEWS ",{\"buffer\":0,\"byteOffset\":72,\"byteLength\":16},"
        "{\"buffer\":0,\"byteOffset\":88,\"byteLength\":64},{\"buffer\":0,\"byteOffset\":152,\"byteLength\":128}],"
        "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"skin.bin\"}]}",
        b.size);
    char *path = tu_write_gltf(dir, "skin", json, &b);
    resurf_scene *s = tu_load_scene_ok(path);
    const resurf_mesh *m = resurf_scene_primitive_mesh(s, 0);
    ck_assert_uint_eq(m->extra_count, 2);
    ck_assert_str_eq(m->extras[0].name, "JOINTS_0");
    ck_assert_str_eq(m->extras[1].name, "WEIGHTS_0");
    for (int v = 0; v < 4; ++v) {
        ck_assert(m->extras[0].data[4 * v] == v % 2 && m->extras[0].data[4 * v + 1] == 1 - v % 2);
        ck_assert(m->extras[1].data[4 * v] == 0.75f && m->extras[1].data[4 * v + 1] == 0.25f);
    }
    resurf_mesh *lod = NULL;
    ck_assert_int_eq(resurf_mesh_clone(m, &lod, NULL), RESURF_OK);
    lod->triangle_count = 2;
    const resurf_mesh *lods[1] = {lod};
    ck_assert_int_eq(resurf_scene_set_lods(s, 0, lods, 1, NULL), RESURF_OK);
    for (int draco = 0; draco < 2; ++draco) {
        char *out = tu_strf("%s/out%d.glb", dir, draco);
        resurf_scene_save_options o = resurf_scene_save_options_default();
        o.draco = draco;
        tu_save_scene_ok(s, out, &o, NULL);
        ck_assert_int_eq(tu_validator_errors(out), 0);
        char *facts = tu_node_eval(dir, TU_JS_LOAD
                                "const n=doc.nodes[0];const lod=doc.nodes[n.extensions.MSFT_lod.ids[0]];"
                                "const a=doc.meshes[lod.mesh].primitives[0].attributes;"
                                "console.log(doc.accessors[a.JOINTS_0].componentType, lod.skin, n.skin,"
                                "doc.skins[0].joints.join(','), doc.accessors[doc.skins[0].inverseBindMatrices].count)",
                                out);
        ck_assert_str_eq(facts, "5121 0 0 1,2 2");
        free(facts);
        resurf_scene *t = tu_load_scene_ok(out);
        const resurf_mesh *r = resurf_scene_primitive_mesh(t, 0);
        ck_assert_uint_eq(r->extra_count, 2);
        /* Joints are exact (integers are never quantized); weights within 12-bit steps with Draco. */
        for (size_t v = 0; v < r->vertex_count; ++v) {
            float j0 = r->extras[0].data[4 * v], j1 = r->extras[0].data[4 * v + 1];
            ck_assert((j0 == 0 && j1 == 1) || (j0 == 1 && j1 == 0));
            ck_assert(fabsf(r->extras[1].data[4 * v] - 0.75f) < 1e-3f);
        }
        resurf_scene_free(t);
        free(out);
    }
    resurf_mesh_free(lod);
    resurf_scene_free(s);
    free(json);
    free(path);
    free(b.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* Morph targets: the primitive's mesh carries the target as an extra, takes levels, and its targets are
 * written back. A points primitive beside it passes through untouched. */
START_TEST(gltf_morph_targets_and_points_pass_through)
{
    char *dir = tu_tempdir();
    tu_bytes b = tu_tetra_bin(); /* 0..71 */
    for (int i = 0; i < 12; ++i)
        tu_put_f32(&b, i % 3 == 2 ? 0.5f : 0.0f); /* target: +0.5 z, 72..119 */
    char *json = tu_strf(
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
        "\"nodes\":[{\"mesh\":0},{\"mesh\":1}],"
        "\"meshes\":[{\"weights\":[0.5],\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,"
        "\"targets\":[{\"POSITION\":2}]}]},{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"mode\":0}]}],"
        "\"accessors\":[" TU_TETRA_ACCESSORS ",{\"bufferView\":2,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
        "\"min\":[0,0,0.5],\"max\":[0,0,0.5]}],"
        "\"bufferViews\":[" TU_TETRA_VIEWS ",{\"buffer\":0,\"byteOffset\":72,\"byteLength\":48}],"
        "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"morph.bin\"}]}",
        b.size);
    char *path = tu_write_gltf(dir, "morph", json, &b);
    resurf_scene *s = tu_load_scene_ok(path);
    ck_assert_uint_eq(resurf_scene_primitive_count(s), 2);
    resurf_scene_primitive info;
    resurf_scene_primitive_info(s, 0, &info, NULL);
    ck_assert_int_eq(info.kind, RESURF_PRIMITIVE_MORPHED);
    ck_assert_uint_eq(resurf_scene_primitive_mesh(s, 0)->triangle_count, 4);
    resurf_scene_primitive_info(s, 1, &info, NULL);
    ck_assert_int_eq(info.kind, RESURF_PRIMITIVE_OTHER);
    ck_assert_ptr_null(resurf_scene_primitive_mesh(s, 1));
    resurf_mesh *lod = tu_tetrahedron();
    const resurf_mesh *lods[1] = {lod};
    resurf_error e;
    const resurf_mesh *full = resurf_scene_primitive_mesh(s, 0);
    ck_assert_uint_eq(full->extra_count, 1);
    ck_assert_str_eq(full->extras[0].name, "targets[0].POSITION");
    for (size_t v = 0; v < 4; ++v)
        ck_assert(full->extras[0].data[3 * v + 2] == 0.5f && full->extras[0].data[3 * v] == 0);
    ck_assert_int_eq(resurf_scene_set_lods(s, 0, lods, 1, &e), RESURF_ERR_INVALID_MESH); /* a level without it */
    ck_assert_ptr_nonnull(strstr(e.message, "targets[0].POSITION"));
    resurf_attribute *delta = NULL;
    ck_assert_int_eq(resurf_mesh_add_extra(lod, "targets[0].POSITION", 3, &delta, NULL), RESURF_OK);
    ck_assert_int_eq(resurf_scene_set_lods(s, 0, lods, 1, &e), RESURF_OK);
    ck_assert_int_eq(resurf_scene_set_lods(s, 0, lods, 0, &e), RESURF_OK);
    ck_assert_int_eq(resurf_scene_set_lods(s, 1, lods, 1, NULL), RESURF_ERR_UNSUPPORTED);
    char *out = tu_path(dir, "out.glb");
    resurf_scene_save_options o = resurf_scene_save_options_default();
    o.draco = true;
    tu_save_scene_ok(s, out, &o, NULL);
    ck_assert_int_eq(tu_validator_errors(out), 0);
    char *facts = tu_node_eval(dir, TU_JS_LOAD "const p=[doc.meshes[0].primitives[0],doc.meshes[1].primitives[0]];"
                                         "console.log(p[0].targets.length, doc.accessors[p[0].targets[0].POSITION].count,"
                                         "doc.meshes[0].weights.join(','), p[1].mode, doc.accessors[p[1].attributes.POSITION].count,"
                                         "JSON.stringify(doc.extensionsUsed||[]),"
                                         "doc.accessors[p[0].targets[0].POSITION].max.join(','))", out);
    ck_assert_str_eq(facts, "1 4 0.5 0 4 [\"KHR_draco_mesh_compression\"] 0,0,0.5");
    free(facts);
    free(out);
    resurf_mesh_free(lod);
    resurf_scene_free(s);
    free(json);
    free(path);
    free(b.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* An accessor without a bufferView is zeros, sparse or not (gltf-transform's `sparse` writes morph targets so):
 * target 0 moves vertex 2 by +0.25 z, target 1 moves nothing, and TEXCOORD_0 is (0, 0) everywhere. */
START_TEST(gltf_accessors_without_buffer_view_are_zeros)
{
    char *dir = tu_tempdir();
    tu_bytes b = tu_tetra_bin(); /* 0..71 */
    tu_put_u8(&b, 2), tu_align4(&b); /* sparse index, 72..75 */
    tu_put_f32(&b, 0), tu_put_f32(&b, 0), tu_put_f32(&b, 0.25f); /* sparse value, 76..87 */
    char *json = tu_strf(
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"weights\":[1,0.5],\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":4},"
        "\"indices\":1,\"targets\":[{\"POSITION\":2},{\"POSITION\":3}]}]}],"
        "\"accessors\":[" TU_TETRA_ACCESSORS ",{\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
        "\"min\":[0,0,0],\"max\":[0,0,0.25],\"sparse\":{\"count\":1,\"indices\":{\"bufferView\":2,"
        "\"componentType\":5121},\"values\":{\"bufferView\":3}}},"
        "{\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[0,0,0]},"
        "{\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"}],"
        "\"bufferViews\":[" TU_TETRA_VIEWS ",{\"buffer\":0,\"byteOffset\":72,\"byteLength\":1},"
        "{\"buffer\":0,\"byteOffset\":76,\"byteLength\":12}],"
        "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"zeros.bin\"}]}",
        b.size);
    char *path = tu_write_gltf(dir, "zeros", json, &b);
    resurf_scene *s = tu_load_scene_ok(path);
    const resurf_mesh *m = resurf_scene_primitive_mesh(s, 0);
    ck_assert_uint_eq(m->extra_count, 2);
    for (size_t i = 0; i < 2; ++i) {
        int moves = !strcmp(m->extras[i].name, "targets[0].POSITION");
        ck_assert(moves || !strcmp(m->extras[i].name, "targets[1].POSITION"));
        for (size_t k = 0; k < 12; ++k)
            ck_assert(m->extras[i].data[k] == (moves && k == 8 ? 0.25f : 0.0f));
    }
    ck_assert_uint_eq(m->texcoord_count, 1);
    for (size_t k = 0; k < 8; ++k)
        ck_assert(m->texcoords[0][k] == 0);
    char *out = tu_path(dir, "out.glb");
    tu_save_scene_ok(s, out, NULL, NULL);
    ck_assert_int_eq(tu_validator_errors(out), 0);
    free(out);
    resurf_scene_free(s);
    free(json);
    free(path);
    free(b.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* A document with a material, a texture whose PNG is a data: URI, a camera, an animation of the node, extras and
 * an unknown extension: all of it is still there after a save (the image moved into the buffer). */
START_TEST(gltf_keeps_everything_else)
{
    char *dir = tu_tempdir();
    tu_bytes b = tu_tetra_bin(); /* 0..71 */
    tu_put_f32(&b, 0), tu_put_f32(&b, 1);                            /* times 72..79 */
    tu_put_f32(&b, 0), tu_put_f32(&b, 0), tu_put_f32(&b, 0);            /* translations 80..103 */
    tu_put_f32(&b, 0), tu_put_f32(&b, 1), tu_put_f32(&b, 0);
    /* A 1×1 PNG (signature, IHDR, IDAT, IEND), base64. */
    const char *png = "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAABJRU5ErkJggg==";
    char *json = tu_strf(
        "{\"asset\":{\"version\":\"2.0\",\"copyright\":\"test\"},\"extensionsUsed\":[\"EXT_resurf_test\"],"
        "\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
        "\"nodes\":[{\"name\":\"body\",\"mesh\":0,\"extras\":{\"tag\":42},\"extensions\":{\"EXT_resurf_test\":{\"x\":1}}},"
        "{\"camera\":0,\"translation\":[0,0,5]}],"
        "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.8,\"znear\":0.1}}],"
        "\"materials\":[{\"name\":\"red\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[1,0,0,1],"
        "\"baseColorTexture\":{\"index\":0}}}],"
        "\"textures\":[{\"source\":0,\"sampler\":0}],\"samplers\":[{\"magFilter\":9728}],"
        "\"images\":[{\"uri\":\"data:image/png;base64,%s\"}],"
        "\"animations\":[{\"samplers\":[{\"input\":2,\"output\":3}],\"channels\":[{\"sampler\":0,"
        "\"target\":{\"node\":0,\"path\":\"translation\"}}]}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":4},\"indices\":1,\"material\":0}]}],"
        "\"accessors\":[" TU_TETRA_ACCESSORS ",{\"bufferView\":2,\"componentType\":5126,\"count\":2,\"type\":\"SCALAR\","
        "\"min\":[0],\"max\":[1]},{\"bufferView\":3,\"componentType\":5126,\"count\":2,\"type\":\"VEC3\"},"
        "{\"bufferView\":4,\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"}],"
        "\"bufferViews\":[" TU_TETRA_VIEWS ",{\"buffer\":0,\"byteOffset\":72,\"byteLength\":8},"
        "{\"buffer\":0,\"byteOffset\":80,\"byteLength\":24},{\"buffer\":0,\"byteOffset\":0,\"byteLength\":32}],"
        "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"all.bin\"}]}",
        png, b.size);
    char *path = tu_write_gltf(dir, "all", json, &b);
    resurf_scene *s = tu_load_scene_ok(path);
    resurf_mesh *lod = NULL;
    ck_assert_int_eq(resurf_mesh_clone(resurf_scene_primitive_mesh(s, 0), &lod, NULL), RESURF_OK);
    lod->triangle_count = 2;
    const resurf_mesh *lods[1] = {lod};
    ck_assert_int_eq(resurf_scene_set_lods(s, 0, lods, 1, NULL), RESURF_OK);
    char *out = tu_path(dir, "out.glb");
    tu_save_scene_ok(s, out, NULL, NULL);
    ck_assert_int_eq(tu_validator_errors(out), 0);
    /* The node has an animated translation: its mesh moves into a child that carries MSFT_lod. */
    char *facts = tu_node_eval(dir, TU_JS_LOAD
                            "const n=doc.nodes[0];const c=doc.nodes[n.children[0]];const img=doc.images[0];"
                            "console.log(doc.asset.copyright,n.extras.tag,n.extensions.EXT_resurf_test.x,"
                            "doc.cameras[0].perspective.yfov,doc.materials[0].name,"
                            "doc.meshes[c.mesh].primitives[0].material,doc.textures[0].source,img.mimeType,"
                            "doc.bufferViews[img.bufferView].byteLength,doc.animations[0].channels[0].target.node,"
                            "c.extensions.MSFT_lod.ids.length,c.extras.MSFT_screencoverage.length,"
                            "doc.extensionsUsed.sort().join(','))",
                            out);
    ck_assert_str_eq(facts, "test 42 1 0.8 red 0 0 image/png 70 0 1 2 EXT_resurf_test,MSFT_lod");
    free(facts);
    free(out);
    resurf_mesh_free(lod);
    resurf_scene_free(s);
    free(json);
    free(path);
    free(b.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* ---- hostile input ------------------------------------------------------------------------------------------- */

/* A .drc of a plain tetrahedron (POSITION only: Draco unique id 0), made by resurf. */
static tu_bytes tetra_draco(const char *dir)
{
    resurf_mesh *t = tu_tetrahedron();
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(t, &s, NULL), RESURF_OK);
    char *drc = tu_path(dir, "tetra.drc");
    tu_save_scene_ok(s, drc, NULL, NULL);
    tu_bytes b = {0};
    b.data = (unsigned char *)tu_read_file(drc, &b.size);
    unlink(drc);
    free(drc);
    resurf_scene_free(s);
    resurf_mesh_free(t);
    return b;
}

/* A Draco primitive document over a payload of `size` bytes (bufferView 0), with POSITION id `id`. */
static char *draco_json(size_t size, const char *extension, const char *name)
{
    return tu_strf("{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_draco_mesh_compression\"],"
                "\"extensionsRequired\":[\"KHR_draco_mesh_compression\"],\"scenes\":[{\"nodes\":[0]}],"
                "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,"
                "\"extensions\":{\"KHR_draco_mesh_compression\":%s}}]}],"
                "\"accessors\":[{\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\"min\":[-1,-1,-1],\"max\":[1,1,1]},"
                "{\"componentType\":5123,\"count\":12,\"type\":\"SCALAR\"}],"
                "\"bufferViews\":[{\"buffer\":0,\"byteLength\":%zu}],\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s.bin\"}]}",
                extension, size, (size + 3) & ~(size_t)3, name);
}

/* A document whose Draco references are valid loads, and decodes to the tetrahedron. */
START_TEST(gltf_draco_input_decodes)
{
    char *dir = tu_tempdir();
    tu_bytes d = tetra_draco(dir);
    tu_align4(&d);
    size_t size = d.size;
    char *json = draco_json(size, "{\"bufferView\":0,\"attributes\":{\"POSITION\":0}}", "ok");
    char *path = tu_write_gltf(dir, "ok", json, &d);
    resurf_scene *s = tu_load_scene_ok(path);
    resurf_scene_primitive info;
    resurf_scene_primitive_info(s, 0, &info, NULL);
    ck_assert_int_eq(info.draco, 1);
    const resurf_mesh *m = resurf_scene_primitive_mesh(s, 0);
    ck_assert_uint_eq(m->vertex_count, 4);
    ck_assert_uint_eq(m->triangle_count, 4);
    for (size_t i = 0; i < 12; ++i) /* ±1 coordinates: exact on the 14-bit grid */
        ck_assert(fabs(fabs(m->positions[i]) - 1) < 1e-4);
    resurf_scene_free(s);
    free(path);
    free(json);
    free(d.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

typedef struct hostile_case {
    const char *name;
    const char *json;        /* %zu: the .bin size; NULL for the Draco cases below */
    resurf_status status;
    const char *says;        /* a word the message must contain */
} hostile_case;

#define H_HEAD "{\"asset\":{\"version\":\"2.0\"},"
#define H_TETRA_DATA                                                                                           \
    "\"accessors\":[" TU_TETRA_ACCESSORS "],\"bufferViews\":[" TU_TETRA_VIEWS "],"                                   \
    "\"buffers\":[{\"byteLength\":72,\"uri\":\"h.bin\"}]}"
#define H_MESH "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"

static const hostile_case hostile_cases[] = {
    {"json syntax", "{\"asset\":{\"version\":\"2.0\"},,}", RESURF_ERR_PARSE, "JSON"},
    {"not an object", "[1,2,3]", RESURF_ERR_PARSE, "object"},
    {"no asset", "{\"scenes\":[]}", RESURF_ERR_PARSE, "asset"},
    {"bad accessor type", H_HEAD H_MESH "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,"
                          "\"type\":\"VEC7\"}],\"bufferViews\":[" TU_TETRA_VIEWS "],\"buffers\":[{\"byteLength\":72,"
                          "\"uri\":\"h.bin\"}]}",
     RESURF_ERR_PARSE, "type"},
    {"indices accessor out of range", H_HEAD "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},"
                                      "\"indices\":99}]}]," H_TETRA_DATA,
     RESURF_ERR_PARSE, "indices"},
    {"attribute accessor out of range", H_HEAD "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":7}}]}],"
                                        H_TETRA_DATA,
     RESURF_ERR_PARSE, "7"},
    {"instancing accessor out of range", H_HEAD "\"nodes\":[{\"mesh\":0,\"extensions\":{\"EXT_mesh_gpu_instancing\":"
                                         "{\"attributes\":{\"TRANSLATION\":7}}}}]," H_MESH H_TETRA_DATA,
     RESURF_ERR_PARSE, "EXT_mesh_gpu_instancing.attributes.TRANSLATION: 7 does not exist"},
    {"instancing rotation not a VEC4", H_HEAD "\"nodes\":[{\"mesh\":0,\"extensions\":{\"EXT_mesh_gpu_instancing\":"
                                       "{\"attributes\":{\"ROTATION\":0}}}}]," H_MESH H_TETRA_DATA,
     RESURF_ERR_PARSE, "attributes.ROTATION: not a VEC4"},
    {"instancing counts differ", H_HEAD "\"nodes\":[{\"mesh\":0,\"extensions\":{\"EXT_mesh_gpu_instancing\":"
                                 "{\"attributes\":{\"TRANSLATION\":0,\"SCALE\":2}}}}]," H_MESH
                                 "\"accessors\":[" TU_TETRA_ACCESSORS ",{\"bufferView\":0,\"componentType\":5126,"
                                 "\"count\":3,\"type\":\"VEC3\"}],\"bufferViews\":[" TU_TETRA_VIEWS "],"
                                 "\"buffers\":[{\"byteLength\":72,\"uri\":\"h.bin\"}]}",
     RESURF_ERR_PARSE, "its attributes count 4 and 3 instances"},
    {"instancing accessor not an index", H_HEAD "\"nodes\":[{\"mesh\":0,\"extensions\":{\"EXT_mesh_gpu_instancing\":"
                                         "{\"attributes\":{\"SCALE\":\"1\"}}}}]," H_MESH H_TETRA_DATA,
     RESURF_ERR_PARSE, "attributes.SCALE: not an index"},
    {"component type", H_HEAD H_MESH "\"accessors\":[{\"bufferView\":0,\"componentType\":5130,\"count\":4,"
                       "\"type\":\"VEC3\"},{\"bufferView\":1,\"componentType\":5123,\"count\":12,\"type\":\"SCALAR\"}],"
                       "\"bufferViews\":[" TU_TETRA_VIEWS "],\"buffers\":[{\"byteLength\":72,\"uri\":\"h.bin\"}]}",
     RESURF_ERR_PARSE, "componentType"},
    {"bufferView past its buffer", H_HEAD H_MESH "\"accessors\":[" TU_TETRA_ACCESSORS "],\"bufferViews\":[{\"buffer\":0,"
                                   "\"byteLength\":48},{\"buffer\":0,\"byteOffset\":60,\"byteLength\":24}],"
                                   "\"buffers\":[{\"byteLength\":72,\"uri\":\"h.bin\"}]}",
     RESURF_ERR_PARSE, "past the end"},
    {"accessor past its bufferView", H_HEAD H_MESH "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,"
                                     "\"count\":5,\"type\":\"VEC3\"},{\"bufferView\":1,\"componentType\":5123,"
                                     "\"count\":12,\"type\":\"SCALAR\"}],\"bufferViews\":[" TU_TETRA_VIEWS "],"
                                     "\"buffers\":[{\"byteLength\":72,\"uri\":\"h.bin\"}]}",
     RESURF_ERR_PARSE, "do not fit"},
    {"buffer index", H_HEAD H_MESH "\"accessors\":[" TU_TETRA_ACCESSORS "],\"bufferViews\":[{\"buffer\":5,"
                     "\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,\"byteLength\":24}],"
                     "\"buffers\":[{\"byteLength\":72,\"uri\":\"h.bin\"}]}",
     RESURF_ERR_PARSE, "buffer 5"},
    {"missing .bin", H_HEAD H_MESH "\"accessors\":[" TU_TETRA_ACCESSORS "],\"bufferViews\":[" TU_TETRA_VIEWS "],"
                     "\"buffers\":[{\"byteLength\":72,\"uri\":\"missing.bin\"}]}",
     RESURF_ERR_PARSE, "missing.bin"},
    {"short .bin", H_HEAD H_MESH "\"accessors\":[" TU_TETRA_ACCESSORS "],\"bufferViews\":[" TU_TETRA_VIEWS "],"
                   "\"buffers\":[{\"byteLength\":400,\"uri\":\"h.bin\"}]}",
     RESURF_ERR_PARSE, "size mismatch"},
    {"index past the vertices", NULL, RESURF_ERR_PARSE, "past the 4 vertices"}, /* built below: index 9 */
    {"infinite translation", H_HEAD "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0,\"translation\":[1e999,0,0]}],"
                             H_MESH H_TETRA_DATA,
     RESURF_ERR_PARSE, "not finite"},
    {"infinite position", NULL, RESURF_ERR_PARSE, "not finite"}, /* built below: an inf float */
    {"node cycle", H_HEAD "\"nodes\":[{\"children\":[1]},{\"children\":[0]}]," H_MESH H_TETRA_DATA, RESURF_ERR_PARSE,
     "cycle"},
    {"node is its own child", H_HEAD "\"nodes\":[{\"children\":[0]}]," H_MESH H_TETRA_DATA, RESURF_ERR_PARSE, "cycle"},
    {"two parents", H_HEAD "\"nodes\":[{\"children\":[2]},{\"children\":[2]},{}]," H_MESH H_TETRA_DATA,
     RESURF_ERR_PARSE, "two parents"},
    {"child out of range", H_HEAD "\"nodes\":[{\"children\":[42]}]," H_MESH H_TETRA_DATA, RESURF_ERR_PARSE, "42"},
    {"node mesh out of range", H_HEAD "\"nodes\":[{\"mesh\":9}]," H_MESH H_TETRA_DATA, RESURF_ERR_PARSE, "mesh 9"},
    {"scene node out of range", H_HEAD "\"scenes\":[{\"nodes\":[7]}],\"nodes\":[{}]," H_MESH H_TETRA_DATA,
     RESURF_ERR_PARSE, "7"},
    {"skin joint out of range", H_HEAD "\"nodes\":[{\"mesh\":0,\"skin\":0}],\"skins\":[{\"joints\":[99]}]," H_MESH
                                H_TETRA_DATA,
     RESURF_ERR_PARSE, "skins[0].joints[0]"},
    {"texture source out of range", H_HEAD "\"textures\":[{\"source\":3}]," H_MESH H_TETRA_DATA, RESURF_ERR_PARSE,
     "textures[0].source"},
    {"deep nesting", NULL, RESURF_ERR_PARSE, "deeper"}, /* built below */
    {"required extension", H_HEAD "\"extensionsUsed\":[\"EXT_resurf_unknown\"],\"extensionsRequired\":"
                           "[\"EXT_resurf_unknown\"]," H_MESH H_TETRA_DATA,
     RESURF_ERR_UNSUPPORTED, "requires the extension EXT_resurf_unknown, which resurf does not support"},
};

/* A document in memory has no folder: a buffer uri that is not a data: URI is refused by name, even when a file of
 * that name exists in the current folder, and an unknown format value is refused. */
START_TEST(gltf_load_memory_refuses_external_files)
{
    const struct {
        const char *uri, *printed;
    } cases[] = {{"h.bin", "h.bin"}, {"/etc/passwd", "/etc/passwd"}, {"a\\nb.bin", "a?b.bin"}};
    for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
        char *json = tu_strf(H_HEAD H_MESH "\"accessors\":[" TU_TETRA_ACCESSORS "],\"bufferViews\":[" TU_TETRA_VIEWS "],"
                          "\"buffers\":[{\"byteLength\":72,\"uri\":\"%s\"}]}",
                          cases[i].uri);
        char *expected = tu_strf("buffers[0]: the uri '%s' names an external file, which a document loaded from memory "
                              "cannot refer to",
                              cases[i].printed);
        resurf_scene *s = NULL;
        resurf_error e;
        ck_assert_int_eq(resurf_scene_load_memory(json, strlen(json), RESURF_SCENE_FORMAT_GLTF, NULL, &s, &e),
                         RESURF_ERR_PARSE);
        ck_assert_ptr_null(s);
        ck_assert_str_eq(e.message, expected);
        free(expected);
        free(json);
    }
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_load_memory("{}", 2, RESURF_SCENE_FORMAT_COUNT, NULL, &s, NULL),
                     RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurf_scene_load_memory(NULL, 4, RESURF_SCENE_FORMAT_GLB, NULL, &s, NULL),
                     RESURF_ERR_INVALID_ARGUMENT);
}
END_TEST

/* Every hostile document fails with the expected status and a one-line message, and loading writes nothing. */
START_TEST(gltf_hostile_documents_fail_cleanly)
{
    char *dir = tu_tempdir();
    tu_bytes b = tu_tetra_bin();
    char *binp = tu_path(dir, "h.bin");
    ck_assert_int_eq(tu_write_file(binp, b.data, b.size), 0);
    for (size_t i = 0; i < sizeof hostile_cases / sizeof *hostile_cases; ++i) {
        const hostile_case *h = &hostile_cases[i];
        char *json = NULL;
        tu_bytes bin = tu_tetra_bin();
        char *name = tu_strf("h%zu", i);
        if (!strcmp(h->name, "index past the vertices") || !strcmp(h->name, "infinite position")) {
            if (h->name[0] == 'i' && h->name[1] == 'n' && h->name[2] == 'd')
                ((uint16_t *)(bin.data + 48))[5] = 9;
            else {
                float inf = INFINITY;
                memcpy(bin.data + 4, &inf, 4);
            }
            char *raw = tu_strf(H_HEAD H_MESH "\"accessors\":[" TU_TETRA_ACCESSORS "],\"bufferViews\":[" TU_TETRA_VIEWS "],"
                             "\"buffers\":[{\"byteLength\":72,\"uri\":\"%s.bin\"}]}",
                             name);
            json = raw;
        } else if (!strcmp(h->name, "deep nesting")) {
            size_t depth = 5000;
            char *deep = malloc(2 * depth + 64);
            strcpy(deep, "{\"asset\":{\"version\":\"2.0\"},\"extras\":");
            size_t n = strlen(deep);
            for (size_t k = 0; k < depth; ++k)
                deep[n++] = '[';
            for (size_t k = 0; k < depth; ++k)
                deep[n++] = ']';
            deep[n++] = '}';
            deep[n] = 0;
            json = deep;
        } else {
            json = tu_strf("%s", h->json);
        }
        char *path = tu_write_gltf(dir, name, json, &bin);
        int before = tu_count_entries(dir);
        /* Strict, and lenient, where what the schema check refuses first reaches the later checks. */
        for (int lenient = 0; lenient < 2; ++lenient) {
            resurf_load_options o = resurf_load_options_default();
            o.lenient = lenient;
            resurf_scene *s = NULL;
            resurf_error e;
            resurf_status st = resurf_scene_load(path, &o, &s, &e);
            ck_assert_msg(st == h->status, "%s (lenient %d): status %d (%s), expected %d", h->name, lenient, st,
                          e.message, h->status);
            ck_assert_ptr_null(s);
            ck_assert_msg(e.message[0] && !strchr(e.message, '\n'), "%s: message '%s'", h->name, e.message);
            ck_assert_msg(strstr(e.message, h->says), "%s (lenient %d): '%s' does not say '%s'", h->name, lenient,
                          e.message, h->says);
            ck_assert_int_eq(tu_count_entries(dir), before);
        }
        free(path);
        free(name);
        free(json);
        free(bin.data);
    }
    free(binp);
    free(b.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* Draco: corrupt and truncated payloads, attribute ids pointing nowhere, a bufferView out of range, an attribute
 * the primitive does not have. None is handed to a decoder unchecked; each fails with its own message. */
START_TEST(gltf_hostile_draco_fails_cleanly)
{
    char *dir = tu_tempdir();
    tu_bytes good = tetra_draco(dir);
    struct {
        const char *name, *extension;
        int damage; /* 0 none, 1 garbage after the header, 2 truncated */
        const char *says;
    } cases[] = {
        {"corrupt", "{\"bufferView\":0,\"attributes\":{\"POSITION\":0}}", 1, "Draco"},
        {"truncated", "{\"bufferView\":0,\"attributes\":{\"POSITION\":0}}", 2, "Draco"},
        {"id nowhere", "{\"bufferView\":0,\"attributes\":{\"POSITION\":7}}", 0, "id 7"},
        {"negative id", "{\"bufferView\":0,\"attributes\":{\"POSITION\":-3}}", 0, "Draco id"},
        {"view out of range", "{\"bufferView\":9,\"attributes\":{\"POSITION\":0}}", 0, "bufferView 9"},
        {"no attributes object", "{\"bufferView\":0}", 0, "attributes"},
        {"unknown attribute", "{\"bufferView\":0,\"attributes\":{\"POSITION\":0,\"NORMAL\":1}}", 0, "NORMAL"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
        tu_bytes d = {0};
        tu_put(&d, good.data, good.size);
        if (cases[i].damage == 1)
            for (size_t k = 8; k < d.size; ++k)
                d.data[k] = (unsigned char)(k * 37 + 11);
        if (cases[i].damage == 2)
            d.size = d.size / 2;
        size_t size = d.size;
        tu_align4(&d);
        char *name = tu_strf("d%zu", i);
        char *json = draco_json(size, cases[i].extension, name);
        char *path = tu_write_gltf(dir, name, json, &d);
        int before = tu_count_entries(dir);
        resurf_scene *s = NULL;
        resurf_error e;
        resurf_status st = resurf_scene_load(path, NULL, &s, &e);
        ck_assert_msg(st == RESURF_ERR_PARSE, "%s: status %d (%s)", cases[i].name, st, e.message);
        ck_assert_msg(e.message[0] && !strchr(e.message, '\n'), "%s: '%s'", cases[i].name, e.message);
        ck_assert_msg(strstr(e.message, cases[i].says), "%s: '%s' does not say '%s'", cases[i].name, e.message,
                      cases[i].says);
        ck_assert_int_eq(tu_count_entries(dir), before);
        free(path);
        free(json);
        free(name);
        free(d.data);
    }
    free(good.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* A document that requires EXT_meshopt_compression or KHR_meshopt_compression: its bufferViews decode into their
 * place, and the output neither uses the extension nor keeps the compressed bytes (src/meshopt_decode.c's own cases
 * are in tests/test_meshopt_decode.c). The tetrahedron's positions are stored in the attribute codec's byte mode
 * (its deltas verbatim: version 0's header 3, or version 1's control mode 3 with byte channels) and its indices in
 * the index codec, both encoded here from the specifications; a stream cut short fails naming the bufferView. */
static unsigned char zigzag8(unsigned char d) { return (d & 0x80) ? (unsigned char)~(d << 1) : (unsigned char)(d << 1); }

static void meshopt_attributes_raw(tu_bytes *b, const unsigned char *data, size_t count, size_t stride, int version)
{
    tu_put_u8(b, version ? 0xa1 : 0xa0);
    for (size_t k = 0; version && k < stride / 4; ++k) /* one block (count <= 16 here): control 3 for each byte */
        tu_put_u8(b, 0xff);
    for (size_t k = 0; k < stride; ++k) {
        if (!version) /* one group, header 3: byte deltas */
            tu_put_u8(b, 3);
        unsigned char last = data[(count - 1) * stride + k]; /* the baseline: the last element, in the tail */
        for (size_t i = 0; i < (version ? count : 16); ++i) {
            unsigned char v = i < count ? data[i * stride + k] : last;
            tu_put_u8(b, zigzag8((unsigned char)(v - last)));
            last = v;
        }
    }
    size_t tail = version ? stride + stride / 4 : stride, least = version ? 24 : 32;
    for (size_t i = tail; i < least; ++i)
        tu_put_u8(b, 0);
    tu_put(b, data + (count - 1) * stride, stride);
    for (size_t k = 0; version && k < stride / 4; ++k) /* channel mode 0: byte deltas */
        tu_put_u8(b, 0);
}

static void meshopt_indices(tu_bytes *b, const uint16_t *idx, size_t count)
{
    tu_put_u8(b, 0xd1);
    uint32_t last = 0;
    for (size_t i = 0; i < count; ++i) {
        int32_t delta = (int32_t)idx[i] - (int32_t)last;
        uint32_t v = (delta >= 0 ? (uint32_t)delta << 1 : ((uint32_t)(-delta - 1) << 1) | 1) << 1; /* baseline 0 */
        for (; v >= 0x80; v >>= 7)
            tu_put_u8(b, (uint8_t)(v | 0x80));
        tu_put_u8(b, (uint8_t)v);
        last = idx[i];
    }
    for (int i = 0; i < 4; ++i)
        tu_put_u8(b, 0);
}

static void meshopt_document_decodes(const char *ext, int version)
{
    char *dir = tu_tempdir();
    tu_bytes tetra = tu_tetra_bin(), b = {0};
    meshopt_attributes_raw(&b, tetra.data, 4, 12, version);
    size_t positions = b.size;
    meshopt_indices(&b, (const uint16_t *)(tetra.data + 48), 12);
    size_t total = b.size;
    for (int cut = 0; cut < 2; ++cut) {
        char *json = tu_strf(
            "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"%s\"],"
            "\"extensionsRequired\":[\"%s\"],\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
            "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
            "\"accessors\":[" TU_TETRA_ACCESSORS "],"
            "\"bufferViews\":[{\"buffer\":1,\"byteLength\":48,\"byteStride\":12,\"extensions\":{"
            "\"%s\":{\"buffer\":0,\"byteLength\":%zu,\"byteStride\":12,\"count\":4,"
            "\"mode\":\"ATTRIBUTES\"}}},{\"buffer\":1,\"byteOffset\":48,\"byteLength\":24,\"extensions\":{"
            "\"%s\":{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu,\"byteStride\":2,"
            "\"count\":12,\"mode\":\"INDICES\"}}}],"
            "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"m.bin\"},"
            "{\"byteLength\":72,\"extensions\":{\"%s\":{\"fallback\":true}}}]}",
            ext, ext, ext, positions - cut, ext, positions, total - positions, total, ext);
        char *path = tu_write_gltf(dir, "m", json, &b);
        resurf_scene *s = NULL;
        resurf_error e;
        resurf_status st = resurf_scene_load(path, NULL, &s, &e);
        if (cut) {
            ck_assert_int_eq(st, RESURF_ERR_PARSE);
            ck_assert_ptr_null(s);
            /* Named by its bufferView; what is wrong depends on the version (version 1's tail holds the channel
               modes, so a stream one byte short reads another byte as one). */
            char *want = tu_strf("bufferViews[0].extensions.%s: ", ext);
            ck_assert_msg(strncmp(e.message, want, strlen(want)) == 0 && strlen(e.message) > strlen(want) + 10, "%s",
                          e.message);
            free(want);
        } else {
            ck_assert_msg(st == RESURF_OK, "%s", e.message);
            const resurf_mesh *m = resurf_scene_primitive_mesh(s, 0);
            ck_assert_uint_eq(m->vertex_count, 4);
            ck_assert_uint_eq(m->triangle_count, 4);
            for (size_t i = 0; i < 12; ++i) {
                float want;
                memcpy(&want, tetra.data + 4 * i, 4);
                ck_assert(m->positions[i] == want);
                ck_assert_uint_eq(m->indices[i], ((const uint16_t *)(tetra.data + 48))[i]);
            }
            /* `resurf info` tells the file as it is. */
            char text[4096];
            size_t length = 0;
            ck_assert_int_eq(resurf_scene_describe(s, false, text, sizeof text, &length, NULL), RESURF_OK);
            char *told = tu_strf("extensions required %s", ext);
            ck_assert_ptr_nonnull(strstr(text, told));
            free(told);
            char *out = tu_path(dir, "out.glb");
            tu_save_scene_ok(s, out, NULL, NULL);
            ck_assert_int_eq(tu_validator_errors(out), 0);
            char *facts = tu_node_eval(dir, TU_JS_LOAD "console.log(JSON.stringify(doc.extensionsUsed||[]),"
                                                 "JSON.stringify(doc.extensionsRequired||[]),doc.buffers.length)", out);
            ck_assert_str_eq(facts, "[] [] 1");
            free(facts);
            free(out);
            resurf_scene_free(s);
        }
        free(path);
        free(json);
    }
    free(b.data);
    free(tetra.data);
    tu_rmtree(dir);
    free(dir);
}

START_TEST(gltf_meshopt_compressed_input_decodes) { meshopt_document_decodes("EXT_meshopt_compression", 0); }
END_TEST

/* KHR_meshopt_compression (gltfpack -ce khr), with version 1 of the attribute bitstream. */
START_TEST(gltf_khr_meshopt_compressed_input_decodes) { meshopt_document_decodes("KHR_meshopt_compression", 1); }
END_TEST

/* Inputs the fuzz harnesses (tests/fuzz/fuzz_scene.c) found, kept in tests/corpus-gltf/: each fails with its status
 * and exact message, from its path and from memory alike. The messages were checked against the bytes by other
 * means: draco_decoder decodes drc_face_past_points.drc to 22 points with face 3 on point 249 (0-based); byte 7
 * of drc_point_cloud_claims_too_many.drc is 0 (a point cloud), whose bytes 11..14 claim 0x1fff0016 points: Draco
 * allocated 6 GB for them before a point cloud was refused without decoding; drc_edgebreaker_claims_too_many.drc
 * is an Edgebreaker mesh (byte 8 is 1) of bitstream 1.254, whose uint32 counts after the traversal byte claim
 * 0x29000806 new vertices and 0x29292929 faces (Draco reserved 2.7 GB for those); the JSON of
 * glb_extension_name_with_line_break.glb requires "KHR_draco_mesh_compressi\n" (a JSON escape), whose line break
 * once split the message. */
START_TEST(gltf_fuzz_findings_fail_with_their_messages)
{
    const struct {
        const char *file;
        resurf_scene_format format;
        resurf_status status;
        const char *message;
    } cases[] = {
        {"drc_face_past_points.drc", RESURF_SCENE_FORMAT_DRC, RESURF_ERR_PARSE,
         "the Draco data is corrupt: face 3 refers to point 249 of 22"},
        {"drc_point_cloud_claims_too_many.drc", RESURF_SCENE_FORMAT_DRC, RESURF_ERR_UNSUPPORTED,
         "the Draco data is a point cloud"},
        {"drc_edgebreaker_claims_too_many.drc", RESURF_SCENE_FORMAT_DRC, RESURF_ERR_LIMIT,
         "the Draco data claims 687867910 vertices, more than its 189 bytes can justify"},
        {"glb_extension_name_with_line_break.glb", RESURF_SCENE_FORMAT_GLB, RESURF_ERR_UNSUPPORTED,
         "the document requires the extension KHR_draco_mesh_compressi?, which resurf does not support"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
        char *path = tu_strf("%s/tests/corpus-gltf/%s", RESURF_SOURCE_DIR, cases[i].file);
        size_t size = 0;
        char *data = tu_read_file(path, &size);
        ck_assert_msg(data != NULL, "cannot read %s", path);
        for (int from_memory = 0; from_memory < 2; ++from_memory) {
            resurf_scene *s = NULL;
            resurf_error e;
            resurf_status st = from_memory ? resurf_scene_load_memory(data, size, cases[i].format, NULL, &s, &e)
                                           : resurf_scene_load(path, NULL, &s, &e);
            ck_assert_msg(st == cases[i].status, "%s: status %d (%s)", cases[i].file, st, e.message);
            ck_assert_ptr_null(s);
            ck_assert_str_eq(e.message, cases[i].message);
        }
        free(data);
        free(path);
    }
}
END_TEST

/* A .glb whose chunk lengths lie: refused before any parser sees it. */
START_TEST(gltf_hostile_glb_container)
{
    char *dir = tu_tempdir();
    resurf_mesh *m = tu_cube();
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(m, &s, NULL), RESURF_OK);
    char *glb = tu_path(dir, "c.glb");
    tu_save_scene_ok(s, glb, NULL, NULL);
    size_t size;
    unsigned char *data = (unsigned char *)tu_read_file(glb, &size);
    struct {
        size_t at;
        uint32_t value;
        const char *says;
    } lies[] = {
        {8, 0x7fffffff, "header says"},   /* total length */
        {8, 12, "header says"},           /* total length shorter than the header */
        {12, 0x7ffffff0, "JSON chunk"},   /* JSON chunk length */
        {4, 3, "version"},                /* version */
        {16, 0x12345678, "not JSON"},     /* first chunk type */
    };
    for (size_t i = 0; i < sizeof lies / sizeof *lies; ++i) {
        unsigned char *copy = malloc(size);
        memcpy(copy, data, size);
        memcpy(copy + lies[i].at, &lies[i].value, 4);
        char *bad = tu_strf("%s/bad%zu.glb", dir, i);
        ck_assert_int_eq(tu_write_file(bad, copy, size), 0);
        resurf_scene *t = NULL;
        resurf_error e;
        ck_assert_int_ne(resurf_scene_load(bad, NULL, &t, &e), RESURF_OK);
        ck_assert_msg(strstr(e.message, lies[i].says), "'%s' does not say '%s'", e.message, lies[i].says);
        ck_assert_ptr_null(t);
        free(bad);
        free(copy);
    }
    /* The BIN chunk cut short. */
    char *cut = tu_path(dir, "cut.glb");
    ck_assert_int_eq(tu_write_file(cut, data, size - 40), 0);
    resurf_scene *t = NULL;
    ck_assert_int_eq(resurf_scene_load(cut, NULL, &t, NULL), RESURF_ERR_PARSE);
    free(cut);
    free(data);
    free(glb);
    resurf_scene_free(s);
    resurf_mesh_free(m);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("gltf_read");
    TCase *read = tcase_create("read");
    tcase_add_test(read, gltf_strips_and_fans_become_lists);
    tcase_add_test(read, gltf_sparse_and_normalized_components);
    tcase_add_test(read, gltf_mesh_quantization_input);
    tcase_add_test(read, gltf_quantized_tangents_keep_the_extension);
    tcase_add_test(read, gltf_instanced_mesh_is_handled_once);
    tcase_add_test(read, gltf_skinned_primitive_keeps_joints_and_weights);
    tcase_add_test(read, gltf_morph_targets_and_points_pass_through);
    tcase_add_test(read, gltf_accessors_without_buffer_view_are_zeros);
    tcase_add_test(read, gltf_keeps_everything_else);
    tcase_add_test(read, gltf_draco_input_decodes);
    tcase_add_test(read, gltf_load_memory_refuses_external_files);
    suite_add_tcase(s, read);
    TCase *hostile = tcase_create("hostile");
    tcase_add_test(hostile, gltf_hostile_documents_fail_cleanly);
    tcase_add_test(hostile, gltf_hostile_draco_fails_cleanly);
    tcase_add_test(hostile, gltf_hostile_glb_container);
    tcase_add_test(hostile, gltf_meshopt_compressed_input_decodes);
    tcase_add_test(hostile, gltf_khr_meshopt_compressed_input_decodes);
    tcase_add_test(hostile, gltf_fuzz_findings_fail_with_their_messages);
    suite_add_tcase(s, hostile);
    return s;
}

RESURF_TEST_MAIN()
