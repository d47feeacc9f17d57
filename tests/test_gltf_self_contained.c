/* Tests of self-contained glTF output (issue 20; src/scene_save.c and the glTF shim in src/io/): external images
 * embedded in a .glb or copied beside a .gltf, a missing image as an error or (allowed) a warning, empty JSON objects
 * kept as objects, dropped triangulation extensions leaving no dead bytes, a skinned node keeping its place, and
 * `resurf info` on scenes.
 *
 * Independent checks: the Khronos glTF validator (tools/validate-gltf.js, npm gltf-validator), node scripts that
 * compare image bytes against their source files, and tests/gltf_dead_bytes.js, a byte accounting of every buffer
 * written by a parser of its own. */
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "testutil.h"

/* ---- issue 20: self-contained outputs, no dead bytes, JSON as it was ----------------------------------------- */

/* Warnings the Khronos validator finds (0 when it finds none). */
static int validator_warnings(const char *path)
{
    char *cmd = tu_strf("node '%s/tools/validate-gltf.js' '%s'", RESURF_SOURCE_DIR, path), *out = NULL;
    tu_run(cmd, &out);
    const char *p = out ? strstr(out, "numWarnings ") : NULL;
    ck_assert_msg(p != NULL, "the glTF validator did not run: %s", out ? out : "");
    int warnings = atoi(p + 12);
    free(cmd);
    free(out);
    return warnings;
}

/* Bytes of the output's buffers that nothing refers to, by tests/gltf_dead_bytes.js (its own parser). */
static long dead_bytes(const char *path)
{
    char *cmd = tu_strf("node '%s/tests/gltf_dead_bytes.js' '%s'", RESURF_SOURCE_DIR, path), *out = NULL;
    tu_run(cmd, &out);
    const char *p = out ? strstr(out, " dead ") : NULL;
    ck_assert_msg(p != NULL, "gltf_dead_bytes.js did not run: %s", out ? out : "");
    long dead = atol(p + 6);
    if (dead)
        fprintf(stderr, "%s", out);
    free(cmd);
    free(out);
    return dead;
}

/* A 1×1 PNG (signature, IHDR, IDAT, IEND). */
static const unsigned char tiny_png[70] =
    "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x00\x01\x00\x00\x00\x01\x08\x06\x00"
    "\x00\x00\x1f\x15\xc4\x89\x00\x00\x00\x0d\x49\x44\x41\x54\x78\xda\x63\xfc\xcf\xc0\x50\x0f\x00\x04\x85\x01\x80"
    "\x84\xa9\x8c\x21\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82";

/* DIR/in/tex.gltf: a textured tetrahedron whose two images are external files named the hard ways: uri
 * "./tex%20dir\\a.png" (dot segment, percent-encoded space, Windows separator) is DIR/in/tex dir/a.png, and
 * "../shared/b.png" is DIR/shared/b.png, outside the document's folder. b.png is a.png with one more byte, so
 * the two can be told apart. Returns the .gltf path. */
static char *textured_input(const char *dir, const char *first_uri)
{
    char *in = tu_path(dir, "in"), *texdir = tu_path(dir, "in/tex dir"), *shared = tu_path(dir, "shared");
    ck_assert_int_eq(mkdir(in, 0777), 0);
    ck_assert_int_eq(mkdir(texdir, 0777), 0);
    ck_assert_int_eq(mkdir(shared, 0777), 0);
    char *a = tu_path(texdir, "a.png"), *b = tu_path(shared, "b.png");
    ck_assert_int_eq(tu_write_file(a, tiny_png, sizeof tiny_png), 0);
    unsigned char longer[sizeof tiny_png + 1];
    memcpy(longer, tiny_png, sizeof tiny_png);
    longer[sizeof tiny_png] = 0;
    ck_assert_int_eq(tu_write_file(b, longer, sizeof longer), 0);
    tu_bytes bin = tu_tetra_bin(); /* 0..71, then texcoords 72..103 */
    for (int v = 0; v < 4; ++v)
        tu_put_f32(&bin, (float)(v & 1)), tu_put_f32(&bin, (float)(v >> 1));
    char *json = tu_strf(
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}},"
        "\"emissiveTexture\":{\"index\":1}}],"
        "\"textures\":[{\"source\":0},{\"source\":1}],"
        "\"images\":[{\"uri\":\"%s\"},{\"uri\":\"../shared/b.png\"}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":2},\"indices\":1,\"material\":0}]}],"
        "\"accessors\":[" TU_TETRA_ACCESSORS ",{\"bufferView\":2,\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"}],"
        "\"bufferViews\":[" TU_TETRA_VIEWS ",{\"buffer\":0,\"byteOffset\":72,\"byteLength\":32}],"
        "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"tex.bin\"}]}",
        first_uri, bin.size);
    char *path = tu_write_gltf(in, "tex", json, &bin);
    free(json);
    free(bin.data);
    free(a);
    free(b);
    free(in);
    free(texdir);
    free(shared);
    return path;
}

/* A scene with one reduced level on its one primitive (two of the four triangles). */
static void add_one_level(resurf_scene *s)
{
    resurf_mesh *lod = NULL;
    ck_assert_int_eq(resurf_mesh_clone(resurf_scene_primitive_mesh(s, 0), &lod, NULL), RESURF_OK);
    lod->triangle_count = 2;
    const resurf_mesh *lods[1] = {lod};
    ck_assert_int_eq(resurf_scene_set_lods(s, 0, lods, 1, NULL), RESURF_OK);
    resurf_mesh_free(lod);
}

/* Each image of a written document: "mimeType:same" when its bytes (in a bufferView, or the file its uri names
 * beside the document) equal the source file's, for images 0 and 1 against a.png and b.png. */
#define JS_IMAGES_AGAINST(A, B)                                                                                 \
    TU_JS_LOAD "const path=require('path');"                                                                       \
    "const bin=b.slice(0,4).toString()==='glTF'?b.slice(28+b.readUInt32LE(12)):"                              \
    "(doc.buffers[0].uri.startsWith('data:')?Buffer.from(doc.buffers[0].uri.split(',')[1],'base64'):"        \
    "fs.readFileSync(path.join(path.dirname(process.argv[2]),doc.buffers[0].uri)));"                          \
    "const want=['" A "','" B "'].map(f=>fs.readFileSync(f));"                                                 \
    "console.log(doc.images.map((im,i)=>{let got;if(im.bufferView!==undefined){const v=doc.bufferViews[im.bufferView];" \
    "got=bin.slice(v.byteOffset||0,(v.byteOffset||0)+v.byteLength);}else{"                                   \
    "got=fs.readFileSync(path.join(path.dirname(process.argv[2]),decodeURIComponent(im.uri)));}"              \
    "return (im.bufferView!==undefined?im.mimeType:im.uri)+':'+(Buffer.compare(got,want[i])===0?'same':'differ');}).join(' '))"

/* A .glb written to another folder holds both images, byte for byte, with the mimeType their bytes show. */
START_TEST(gltf_glb_embeds_external_images)
{
    char *dir = tu_tempdir();
    char *path = textured_input(dir, "./tex%20dir\\\\a.png");
    resurf_scene *s = tu_load_scene_ok(path);
    ck_assert_uint_eq(resurf_scene_warning_count(s), 0);
    add_one_level(s);
    char *outdir = tu_path(dir, "out"), *out = tu_path(dir, "out/t.glb");
    ck_assert_int_eq(mkdir(outdir, 0777), 0);
    tu_save_scene_ok(s, out, NULL, NULL);
    ck_assert_int_eq(tu_count_entries(outdir), 1); /* nothing beside the .glb */
    ck_assert_int_eq(tu_validator_errors(out), 0);
    ck_assert_int_eq(dead_bytes(out), 0);
    char *script = tu_strf(JS_IMAGES_AGAINST("%s/in/tex dir/a.png", "%s/shared/b.png"), dir, dir);
    char *facts = tu_node_eval(dir, script, out);
    ck_assert_str_eq(facts, "image/png:same image/png:same");
    free(facts);
    free(script);
    free(out);
    free(outdir);
    resurf_scene_free(s);
    free(path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* A .gltf written to another folder gets copies of the images under their relative names (b.png, outside the
 * input's folder, under its file name); with embed_buffers it holds them itself. Nothing is written outside the
 * output's folder. */
START_TEST(gltf_gltf_copies_or_embeds_external_images)
{
    char *dir = tu_tempdir();
    char *path = textured_input(dir, "tex%20dir/a.png"); /* as it is: the name is kept */
    resurf_scene *s = tu_load_scene_ok(path);
    add_one_level(s);
    char *outdir = tu_path(dir, "out"), *out = tu_path(dir, "out/t.gltf");
    ck_assert_int_eq(mkdir(outdir, 0777), 0);
    resurf_scene_save_report r;
    tu_save_scene_ok(s, out, NULL, &r);
    ck_assert_uint_eq(r.files, 4); /* .gltf, .bin, two images */
    ck_assert_int_eq(tu_count_entries(dir), 3); /* in, shared, out: nothing new beside them */
    char *shared = tu_path(dir, "shared");
    ck_assert_int_eq(tu_count_entries(shared), 1);
    ck_assert_int_eq(tu_validator_errors(out), 0);
    ck_assert_int_eq(dead_bytes(out), 0);
    char *script = tu_strf(JS_IMAGES_AGAINST("%s/in/tex dir/a.png", "%s/shared/b.png"), dir, dir);
    char *facts = tu_node_eval(dir, script, out);
    ck_assert_str_eq(facts, "tex%20dir/a.png:same b.png:same");
    free(facts);
    resurf_scene_save_options o = resurf_scene_save_options_default();
    o.embed_buffers = 1;
    char *embedded = tu_path(dir, "out/e.gltf");
    tu_save_scene_ok(s, embedded, &o, NULL);
    ck_assert_int_eq(tu_validator_errors(embedded), 0);
    ck_assert_int_eq(dead_bytes(embedded), 0);
    facts = tu_node_eval(dir, script, embedded);
    ck_assert_str_eq(facts, "image/png:same image/png:same");
    free(facts);
    free(embedded);
    free(script);
    free(shared);
    free(out);
    free(outdir);
    resurf_scene_free(s);
    free(path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* A missing image fails the load with one line naming the input, images[i], the path tried and the uri; allowed,
 * it is a warning and the output refers to the uri as it was. The CLI says the same, and --allow-missing-images
 * goes on. */
START_TEST(gltf_missing_image_is_an_error)
{
    char *dir = tu_tempdir();
    char *path = textured_input(dir, "gone%2Fnot-here.png");
    resurf_scene *s = NULL;
    resurf_error e;
    ck_assert_int_eq(resurf_scene_load(path, NULL, &s, &e), RESURF_ERR_IO);
    ck_assert_ptr_null(s);
    char msg[1200];
    resurf_format_error(msg, sizeof msg, &e);
    char *want = tu_strf("%s: images[0]: the image '%s/in/gone/not-here.png' (uri 'gone%%2Fnot-here.png') cannot be "
                      "read: ", path, dir);
    ck_assert_msg(!strncmp(msg, want, strlen(want)), "message: %s", msg);
    ck_assert_ptr_null(strchr(msg, '\n'));
    resurf_load_options lo = resurf_load_options_default();
    lo.allow_missing_images = 1;
    ck_assert_int_eq(resurf_scene_load(path, &lo, &s, &e), RESURF_OK);
    ck_assert_uint_eq(resurf_scene_warning_count(s), 1);
    ck_assert_ptr_nonnull(strstr(resurf_scene_warning(s, 0), "images[0]: the image"));
    char *out = tu_path(dir, "t.glb");
    tu_save_scene_ok(s, out, NULL, NULL);
    char *facts = tu_node_eval(dir, TU_JS_LOAD "console.log(doc.images[0].uri,doc.images[1].mimeType)", out);
    ck_assert_str_eq(facts, "gone%2Fnot-here.png image/png");
    free(facts);
    resurf_scene_free(s);

    char *cmd = tu_strf("'%s' lod '%s' -o '%s/c.glb' --levels 0.5 2>&1", RESURF_CLI, path, dir), *text = NULL;
    ck_assert_int_eq(tu_run(cmd, &text), 1);
    ck_assert_msg(strstr(text, "images[0]") && strstr(text, path) && strchr(text, '\n') == text + strlen(text) - 1,
                  "%s", text);
    free(text);
    free(cmd);
    cmd = tu_strf("'%s' lod '%s' -o '%s/c.glb' --levels 0.5 --allow-missing-images 2>&1", RESURF_CLI, path, dir);
    ck_assert_int_eq(tu_run(cmd, &text), 0);
    ck_assert_ptr_nonnull(strstr(text, "resurf: warning: images[0]"));
    free(text);
    free(cmd);
    /* A uri that names no file of the folder (a scheme, an encoded NUL) is refused without being tried. */
    static const char *const foreign[] = {"http://example.com/a.png", "x%00.png", "C:\\\\a.png"};
    for (int k = 0; k < 3; ++k) {
        char *sub = tu_strf("%s/h%d", dir, k);
        ck_assert_int_eq(mkdir(sub, 0777), 0);
        char *hostile = textured_input(sub, foreign[k]);
        ck_assert_int_eq(resurf_scene_load(hostile, NULL, &s, &e), RESURF_ERR_UNSUPPORTED);
        ck_assert_msg(strstr(e.message, "images[0]: the image of uri '") &&
                          strstr(e.message, "' cannot be read: the uri names no file of the document's folder"),
                      "%s", e.message);
        free(hostile);
        free(sub);
    }
    free(out);
    free(want);
    free(path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* Empty objects stay objects: a scene {}, a node {}, an extension {} (tinygltf writes them as null, which no glTF
 * property may be); empty extras are never null (tinygltf leaves them out). */
START_TEST(gltf_empty_objects_stay_empty)
{
    char *dir = tu_tempdir();
    tu_bytes b = tu_tetra_bin();
    const char *json = "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_materials_unlit\"],\"scene\":0,"
                       "\"scenes\":[{\"nodes\":[0,1]},{}],\"nodes\":[{\"mesh\":0},{}],"
                       "\"materials\":[{\"extensions\":{\"KHR_materials_unlit\":{}},\"extras\":{}}],"
                       "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,\"material\":0}]}],"
                       "\"accessors\":[" TU_TETRA_ACCESSORS "],\"bufferViews\":[" TU_TETRA_VIEWS "],"
                       "\"buffers\":[{\"byteLength\":72,\"uri\":\"e.bin\"}]}";
    char *path = tu_write_gltf(dir, "e", json, &b);
    resurf_scene *s = tu_load_scene_ok(path);
    char *out = tu_path(dir, "out.gltf");
    tu_save_scene_ok(s, out, NULL, NULL);
    char *text = tu_read_file(out, NULL);
    ck_assert_ptr_null(strstr(text, "null"));
    ck_assert_int_eq(tu_validator_errors(out), 0);
    char *facts = tu_node_eval(dir, TU_JS_LOAD "const empty=x=>typeof x==='object'&&x!==null&&Object.keys(x).length===0;"
                                         "console.log(empty(doc.scenes[1]),empty(doc.nodes[1]),"
                                         "empty(doc.materials[0].extensions.KHR_materials_unlit),"
                                         "!('extras' in doc.materials[0])||empty(doc.materials[0].extras))",
                            out);
    ck_assert_str_eq(facts, "true true true true");
    free(facts);
    free(text);
    free(out);
    resurf_scene_free(s);
    free(path);
    free(b.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* FB_ngon_encoding and an unknown primitive extension are dropped from the rewritten primitive (warned once
 * each, counted in the report) and no longer keep the source's bytes: nothing in the output is unreferenced.
 * KHR_materials_variants, which holds whatever the triangles, stays. The byte check itself finds the dead
 * bytes of an input that has some. */
START_TEST(gltf_triangulation_extensions_dropped_no_dead_bytes)
{
    char *dir = tu_tempdir();
    tu_bytes b = tu_tetra_bin();
    for (int i = 0; i < 16; ++i) /* 72..87: a bufferView nothing uses */
        tu_put_u8(&b, 0xEE);
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},"
        "\"extensionsUsed\":[\"FB_ngon_encoding\",\"EXT_resurf_unknown\",\"KHR_materials_variants\"],"
        "\"extensions\":{\"KHR_materials_variants\":{\"variants\":[{\"name\":\"plain\"}]}},"
        "\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],\"materials\":[{\"name\":\"m\"}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,\"extensions\":{"
        "\"FB_ngon_encoding\":{},\"EXT_resurf_unknown\":{\"view\":2},"
        "\"KHR_materials_variants\":{\"mappings\":[{\"material\":0,\"variants\":[0]}]}}}]}],"
        "\"accessors\":[" TU_TETRA_ACCESSORS "],\"bufferViews\":[" TU_TETRA_VIEWS ",{\"buffer\":0,\"byteOffset\":72,"
        "\"byteLength\":16}],\"buffers\":[{\"byteLength\":88,\"uri\":\"n.bin\"}]}";
    char *path = tu_write_gltf(dir, "n", json, &b);
    ck_assert_int_eq(dead_bytes(path), 16);
    resurf_scene *s = tu_load_scene_ok(path);
    ck_assert_uint_eq(resurf_scene_warning_count(s), 2);
    ck_assert_ptr_nonnull(strstr(resurf_scene_warning(s, 0), "EXT_resurf_unknown is dropped from the 1"));
    ck_assert_ptr_nonnull(strstr(resurf_scene_warning(s, 1), "FB_ngon_encoding is dropped from the 1"));
    add_one_level(s);
    for (int draco = 0; draco < 2; ++draco) {
        char *out = tu_strf("%s/out%d.glb", dir, draco);
        resurf_scene_save_options o = resurf_scene_save_options_default();
        o.draco = draco;
        resurf_scene_save_report r;
        tu_save_scene_ok(s, out, &o, &r);
        ck_assert_uint_eq(r.dropped_extensions, 2);
        ck_assert_int_eq(tu_validator_errors(out), 0);
        ck_assert_int_eq(dead_bytes(out), 0);
        char *facts = tu_node_eval(dir, TU_JS_LOAD "console.log(doc.meshes.map(m=>Object.keys(m.primitives[0].extensions)"
                                             ".filter(e=>e!=='KHR_draco_mesh_compression').join('+')).join(' '),"
                                             "doc.extensionsUsed.filter(e=>e!=='KHR_draco_mesh_compression').sort().join(','),"
                                             "doc.bufferViews.length)",
                                out);
        ck_assert_str_eq(facts, draco ? "KHR_materials_variants KHR_materials_variants KHR_materials_variants,MSFT_lod 2"
                                      : "KHR_materials_variants KHR_materials_variants KHR_materials_variants,MSFT_lod 4");
        free(facts);
        free(out);
    }
    resurf_scene_free(s);
    free(path);
    free(b.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* A skinned node with children (its joints, as in glTF2/simple_skin) keeps its mesh and carries MSFT_lod itself:
 * the output has no validator error and no warning (a skinned mesh on a child node would be
 * NODE_SKINNED_MESH_NON_ROOT). */
START_TEST(gltf_skinned_node_keeps_its_place)
{
    char *dir = tu_tempdir();
    tu_bytes b = tu_tetra_bin(); /* 0..71 */
    for (int v = 0; v < 4; ++v) /* joints 72..87 */
        tu_put_u8(&b, 0), tu_put_u8(&b, 1), tu_put_u8(&b, 0), tu_put_u8(&b, 0);
    for (int v = 0; v < 4; ++v) /* weights 88..151 */
        tu_put_f32(&b, 0.5f), tu_put_f32(&b, 0.5f), tu_put_f32(&b, 0), tu_put_f32(&b, 0);
    for (int j = 0; j < 2; ++j) /* inverse bind matrices 152..279 */
        for (int i = 0; i < 16; ++i)
            tu_put_f32(&b, i % 5 == 0 ? 1.0f : 0.0f);
    char *json = tu_strf(
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
        "\"nodes\":[{\"mesh\":0,\"skin\":0,\"children\":[1]},{\"children\":[2]},{\"translation\":[0,1,0]}],"
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
    ck_assert_int_eq(tu_validator_errors(path), 0);
    ck_assert_int_eq(validator_warnings(path), 0);
    resurf_scene *s = tu_load_scene_ok(path);
    add_one_level(s);
    char *out = tu_path(dir, "out.glb");
    tu_save_scene_ok(s, out, NULL, NULL);
    ck_assert_int_eq(tu_validator_errors(out), 0);
    ck_assert_int_eq(validator_warnings(out), 0);
    char *facts = tu_node_eval(dir, TU_JS_LOAD "const n=doc.nodes[0];const l=doc.nodes[n.extensions.MSFT_lod.ids[0]];"
                                         "const parents=doc.nodes.flatMap(x=>x.children||[]);"
                                         "console.log(n.mesh,n.skin,n.children.join(','),l.skin,l.mesh,"
                                         "doc.nodes.filter((x,i)=>x.skin!==undefined&&parents.includes(i)).length)",
                            out);
    ck_assert_str_eq(facts, "0 0 1 0 1 0");
    free(facts);
    free(out);
    resurf_scene_free(s);
    free(path);
    free(json);
    free(b.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* `resurf info` on a scene: counts read from the JSON it prints agree with the document written here (triangles
 * from the indices, attributes, the morph target, the image's type and size from its file, the material's
 * texture), the text has the same lines, and a .drc is one mesh with its triangles. */
START_TEST(gltf_cli_info_describes_scenes)
{
    char *dir = tu_tempdir();
    char *path = textured_input(dir, "tex%20dir/a.png");
    /* The same document with a morph target on the primitive (its POSITION accessor doubles as the deltas). */
    char *text = tu_read_file(path, NULL);
    char *at = strstr(text, "\"indices\":1,");
    ck_assert_ptr_nonnull(at);
    char *morphed = tu_strf("%.*s\"targets\":[{\"POSITION\":0}],%s", (int)(at - text), text, at);
    char *morph_path = tu_path(dir, "in/morph.gltf");
    ck_assert_int_eq(tu_write_file(morph_path, morphed, strlen(morphed)), 0);
    char *cmd = tu_strf("'%s' info '%s' --json > '%s/info.json'", RESURF_CLI, morph_path, dir), *out = NULL;
    ck_assert_msg(tu_run(cmd, &out) == 0, "%s", out);
    char *json = tu_path(dir, "info.json");
    char *facts = tu_node_eval(dir, "const d=JSON.parse(require('fs').readFileSync(process.argv[2])).scene;"
                                 "const p=d.meshes[0].primitives[0];"
                                 "console.log(d.scenes[0].nodes.join(','),d.nodes[0].mesh,p.triangles,p.vertices,"
                                 "p.attributes.join('+'),p.targets,p.target_attributes.join('+'),p.material,"
                                 "d.materials[0].textures.baseColor,d.materials[0].textures.emissive,"
                                 "d.images.map(i=>i.mimeType+':'+i.bytes+':'+i.uri).join(' '),d.skins.length)",
                            json);
    ck_assert_str_eq(facts, "0 0 4 4 POSITION+TEXCOORD_0 1 POSITION 0 0 1 "
                            "image/png:70:tex%20dir/a.png image/png:71:../shared/b.png 0");
    free(facts);
    free(out);
    free(cmd);
    cmd = tu_strf("'%s' info '%s'", RESURF_CLI, morph_path);
    ck_assert_int_eq(tu_run(cmd, &out), 0);
    ck_assert_msg(strstr(out, "    primitives[0]: triangles 4, vertices 4, mode 4, material 0, attributes POSITION, "
                              "TEXCOORD_0, targets 1, target_attributes POSITION\n") &&
                      strstr(out, "  images[1]: uri ../shared/b.png, mimeType image/png, bytes 71\n"),
                  "%s", out);
    free(out);
    free(cmd);
    /* A .drc: one mesh, its triangles. */
    char *drc = tu_path(dir, "t.drc");
    cmd = tu_strf("'%s' lod '%s' -o '%s' --layout files --levels 0.5 > /dev/null && '%s' info '%s/t_lod0.drc' --json",
               RESURF_CLI, path, drc, RESURF_CLI, dir);
    ck_assert_int_eq(tu_run(cmd, &out), 0);
    ck_assert_msg(strstr(out, "\"triangles\":4") && strstr(out, "\"attributes\":[\"POSITION\",\"TEXCOORD_0\"]"),
                  "%s", out);
    free(out);
    free(cmd);
    free(drc);
    free(json);
    free(morph_path);
    free(morphed);
    free(text);
    free(path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* EXT_mesh_gpu_instancing (required, as gltfpack -mi writes it) draws a node's mesh once per instance: every level
 * node carries it too (else a viewer that switches to a level shows one instance), where a node with children hands
 * its mesh to a child of its own the extension goes with the mesh, and the instances' accessors are kept, with
 * nothing else of the source's data. */
START_TEST(gltf_gpu_instancing_goes_with_the_levels)
{
    char *dir = tu_tempdir();
    tu_bytes b = tu_tetra_bin();
    static const float shifts[6] = {0, 0, 0, 5, 0, 0}; /* two instances' TRANSLATION, 72..95 */
    for (int i = 0; i < 6; ++i)
        tu_put_f32(&b, shifts[i]);
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"EXT_mesh_gpu_instancing\"],"
        "\"extensionsRequired\":[\"EXT_mesh_gpu_instancing\"],\"scene\":0,"
        "\"scenes\":[{\"nodes\":[0,1]}],\"nodes\":[{\"mesh\":0,\"extensions\":{\"EXT_mesh_gpu_instancing\":"
        "{\"attributes\":{\"TRANSLATION\":2}}}},{\"mesh\":0,\"children\":[2],\"extensions\":"
        "{\"EXT_mesh_gpu_instancing\":{\"attributes\":{\"TRANSLATION\":2}}}},{\"translation\":[0,3,0]}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
        "\"accessors\":[" TU_TETRA_ACCESSORS ",{\"bufferView\":2,\"componentType\":5126,\"count\":2,"
        "\"type\":\"VEC3\"}],\"bufferViews\":[" TU_TETRA_VIEWS ",{\"buffer\":0,\"byteOffset\":72,\"byteLength\":24}],"
        "\"buffers\":[{\"byteLength\":96,\"uri\":\"gi.bin\"}]}";
    char *path = tu_write_gltf(dir, "gi", json, &b);
    resurf_scene *s = tu_load_scene_ok(path);
    add_one_level(s);
    char *out = tu_path(dir, "lod.gltf");
    tu_save_scene_ok(s, out, NULL, NULL);
    ck_assert_int_eq(tu_validator_errors(out), 0);
    /* Per node showing the mesh: does it carry MSFT_lod, and do it and its level node draw the two instances? */
    char *facts = tu_node_eval(dir, TU_JS_LOAD
                            "const gi=n=>n.extensions&&n.extensions.EXT_mesh_gpu_instancing?"
                            "doc.accessors[n.extensions.EXT_mesh_gpu_instancing.attributes.TRANSLATION].count:0;"
                            "console.log(doc.nodes.filter(n=>n.mesh!==undefined&&n.extensions&&n.extensions.MSFT_lod)"
                            ".map(n=>gi(n)+'/'+gi(doc.nodes[n.extensions.MSFT_lod.ids[0]])).join(' '),"
                            "doc.nodes.filter(n=>n.mesh===undefined&&gi(n)).length)", out);
    ck_assert_str_eq(facts, "2/2 2/2 0");
    ck_assert_int_eq(dead_bytes(out), 0);
    free(facts);
    free(out);
    resurf_scene_free(s);
    free(path);
    free(b.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* EXT_meshopt_compression or KHR_meshopt_compression that the document does not require (gltfpack -cf, with -ce
 * khr): resurf reads the fallback buffer's uncompressed bytes, and the output neither uses the extension nor keeps
 * the compressed bytes, even where a source bufferView is kept (the points primitive, written as it was). */
static void optional_meshopt_reads_the_fallback(const char *ext)
{
    char *dir = tu_tempdir();
    tu_bytes b = tu_tetra_bin(); /* m.bin: the fallback's bytes */
    unsigned char packed[16]; /* c.bin: stands for the compressed bytes */
    memset(packed, 0xCC, sizeof packed);
    char *c_bin = tu_path(dir, "c.bin");
    ck_assert_int_eq(tu_write_file(c_bin, packed, sizeof packed), 0);
    free(c_bin);
    char *json = tu_strf(
        "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"%s\"],"
        "\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1},"
        "{\"attributes\":{\"POSITION\":0},\"mode\":0}]}],"
        "\"accessors\":[" TU_TETRA_ACCESSORS "],"
        "\"bufferViews\":[{\"buffer\":1,\"byteLength\":48,\"extensions\":{\"%s\":{\"buffer\":0,"
        "\"byteLength\":8,\"byteStride\":12,\"mode\":\"ATTRIBUTES\",\"count\":4}}},"
        "{\"buffer\":1,\"byteOffset\":48,\"byteLength\":24,\"extensions\":{\"%s\":{\"buffer\":0,"
        "\"byteOffset\":8,\"byteLength\":8,\"byteStride\":2,\"mode\":\"INDICES\",\"count\":12}}}],"
        "\"buffers\":[{\"byteLength\":16,\"uri\":\"c.bin\"},{\"byteLength\":72,\"uri\":\"m.bin\","
        "\"extensions\":{\"%s\":{\"fallback\":true}}}]}",
        ext, ext, ext, ext);
    char *path = tu_write_gltf(dir, "m", json, &b);
    resurf_scene *s = tu_load_scene_ok(path);
    const resurf_mesh *m = resurf_scene_primitive_mesh(s, 0);
    ck_assert_uint_eq(m->triangle_count, 4);
    ck_assert(m->positions[0] == 1 && m->positions[1] == 1 && m->positions[2] == 1);
    add_one_level(s);
    char *out = tu_path(dir, "out.glb");
    tu_save_scene_ok(s, out, NULL, NULL);
    ck_assert_int_eq(tu_validator_errors(out), 0);
    ck_assert_int_eq(dead_bytes(out), 0);
    char *facts = tu_node_eval(dir, TU_JS_LOAD "console.log(JSON.stringify(doc.extensionsUsed||[]),"
                                         "doc.bufferViews.filter(v=>v.extensions).length,"
                                         "doc.buffers.length)", out);
    ck_assert_str_eq(facts, "[\"MSFT_lod\"] 0 1");
    free(facts);
    free(out);
    resurf_scene_free(s);
    free(path);
    free(json);
    free(b.data);
    tu_rmtree(dir);
    free(dir);
}

START_TEST(gltf_optional_meshopt_reads_the_fallback)
{
    optional_meshopt_reads_the_fallback("EXT_meshopt_compression");
    optional_meshopt_reads_the_fallback("KHR_meshopt_compression");
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("gltf_self_contained");
    TCase *whole = tcase_create("self-contained");
    tcase_add_test(whole, gltf_glb_embeds_external_images);
    tcase_add_test(whole, gltf_gltf_copies_or_embeds_external_images);
    tcase_add_test(whole, gltf_missing_image_is_an_error);
    tcase_add_test(whole, gltf_empty_objects_stay_empty);
    tcase_add_test(whole, gltf_triangulation_extensions_dropped_no_dead_bytes);
    tcase_add_test(whole, gltf_skinned_node_keeps_its_place);
    tcase_add_test(whole, gltf_gpu_instancing_goes_with_the_levels);
    tcase_add_test(whole, gltf_optional_meshopt_reads_the_fallback);
    tcase_add_test(whole, gltf_cli_info_describes_scenes);
    suite_add_tcase(s, whole);
    return s;
}

RESURF_TEST_MAIN()
