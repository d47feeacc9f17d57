/* Tests of the glTF 2.0 schema check (src/io/gltf_schema.cpp): hand-written documents, each a valid tetrahedron
 * with one thing the schema forbids (a wrong JSON type, a missing required property, an enum value out of range,
 * a number below its minimum, an array of the wrong length), refused by default with a message naming the file,
 * the JSON path and the cause, and loaded with a warning (the same text) when resurf_load_options.lenient is set.
 * The expected messages are written out here from the glTF 2.0 schema's rules (specification/2.0/schema). */
#include <stdio.h>
#include <string.h>

#include "testutil.h"

/* The parts of the tetrahedron document a case replaces (NULL: the valid default). */
typedef struct doc_parts {
    const char *scenes, *node, *meshes, *accessors, *views, *buffers, *more;
} doc_parts;

static char *tetra_json(const doc_parts *p)
{
    return tu_strf("{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":%s,\"nodes\":[{\"mesh\":0%s}],"
                   "\"meshes\":%s,\"accessors\":%s,\"bufferViews\":%s,\"buffers\":%s%s}",
                   p->scenes ? p->scenes : "[{\"nodes\":[0]}]", p->node ? p->node : "",
                   p->meshes ? p->meshes : "[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}]",
                   p->accessors ? p->accessors : "[" TU_TETRA_ACCESSORS "]",
                   p->views ? p->views : "[" TU_TETRA_VIEWS "]",
                   p->buffers ? p->buffers : "[{\"byteLength\":72,\"uri\":\"tetra.bin\"}]", p->more ? p->more : "");
}

/* Writes DIR/NAME.gltf (and DIR/tetra.bin); returns the .gltf path. */
static char *write_tetra(const char *dir, const char *name, const doc_parts *p)
{
    tu_bytes b = tu_tetra_bin();
    char *json = tetra_json(p);
    char *path = tu_write_gltf(dir, name, json, NULL);
    char *bin = tu_path(dir, "tetra.bin");
    ck_assert_int_eq(tu_write_file(bin, b.data, b.size), 0);
    free(bin);
    free(json);
    free(b.data);
    return path;
}

/* The load fails with RESURF_ERR_PARSE, and the one-line error is exactly "PATH: message". */
static void assert_refused(const char *path, const resurf_load_options *o, const char *message)
{
    resurf_scene *s = NULL;
    resurf_error e;
    ck_assert_int_eq(resurf_scene_load(path, o, &s, &e), RESURF_ERR_PARSE);
    ck_assert_ptr_null(s);
    char line[600], *want = tu_strf("%s: %s", path, message);
    resurf_format_error(line, sizeof line, &e);
    ck_assert_str_eq(line, want);
    free(want);
}

typedef struct schema_case {
    const char *name;
    doc_parts parts;
    const char *message;         /* the schema's message */
    const char *lenient_failure; /* NULL: a lenient load succeeds with the message as its first warning; else the
                                    check that still stops it (what resurf cannot read even leniently) */
} schema_case;

static const schema_case cases[] = {
    /* wrong JSON types */
    {"name_number", {.scenes = "[{\"nodes\":[0],\"name\":42}]"}, "scenes[0].name: must be a string, not the number 42",
     NULL},
    {"camera_string", {.node = ",\"name\":\"n\",\"camera\":\"0\""},
     "nodes[0].camera: must be an integer, not the string \"0\"", NULL},
    {"pbr_array", {.more = ",\"materials\":[{\"pbrMetallicRoughness\":[\"not an object\"]}]"},
     "materials[0].pbrMetallicRoughness: must be an object, not an array", NULL},
    {"double_sided_number", {.more = ",\"materials\":[{\"doubleSided\":1}]"},
     "materials[0].doubleSided: must be a boolean, not the number 1", NULL},
    {"extension_string", {.node = ",\"extensions\":{\"EXT_made_up\":\"on\"}"},
     "nodes[0].extensions.EXT_made_up: must be an object, not the string \"on\"", NULL},
    {"primitives_object", {.meshes = "[{\"primitives\":{\"attributes\":{\"POSITION\":0},\"indices\":1}}]"},
     "meshes[0].primitives: must be an array, not an object",
     "meshes[0] has no primitives (glTF requires at least one)"},
    /* missing required properties */
    {"texture_index_missing", {.more = ",\"materials\":[{\"normalTexture\":{\"scale\":2}}]"},
     "materials[0].normalTexture.index: the property is required but missing", NULL},
    {"attributes_missing", {.meshes = "[{\"primitives\":[{\"indices\":1}]}]"},
     "meshes[0].primitives[0].attributes: the property is required but missing",
     "meshes[0] has no primitives (glTF requires at least one)"}, /* tinygltf skips the primitive */
    /* enum values out of range */
    {"mode_9", {.meshes = "[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,\"mode\":9}]}]"},
     "meshes[0].primitives[0].mode: 9 is not a glTF primitive mode (0..6)",
     "meshes[0].primitives[0]: mode 9 is not a glTF primitive mode (0..6)"},
    {"alpha_mode", {.more = ",\"materials\":[{\"alphaMode\":\"GLOSSY\"}]"},
     "materials[0].alphaMode: \"GLOSSY\" is not an alpha mode (OPAQUE, MASK, BLEND)", NULL},
    {"wrap_mode", {.more = ",\"samplers\":[{\"wrapS\":1}]"},
     "samplers[0].wrapS: 1 is not a wrap mode (33071, 33648, 10497)", NULL},
    {"component_type",
     {.accessors = "[" TU_TETRA_ACCESSORS
                   ",{\"bufferView\":1,\"componentType\":5124,\"count\":1,\"type\":\"SCALAR\"}]"},
     "accessors[2].componentType: 5124 is not a glTF component type (5120, 5121, 5122, 5123, 5125, 5126)",
     "accessors[2]: unknown componentType 5124"},
    {"animation_path",
     {.more = ",\"animations\":[{\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":\"colour\"}}],"
              "\"samplers\":[{\"input\":1,\"output\":0}]}]"},
     "animations[0].channels[0].target.path: \"colour\" is not an animated property (translation, rotation, scale, "
     "weights)",
     NULL},
    /* numbers below their minimum (or above their maximum) */
    {"texture_index_negative", {.more = ",\"materials\":[{\"emissiveTexture\":{\"index\":-1}}]"},
     "materials[0].emissiveTexture.index: -1 is below the minimum of 0", NULL},
    {"byte_length_0", {.views = "[" TU_TETRA_VIEWS ",{\"buffer\":0,\"byteLength\":0}]"},
     "bufferViews[2].byteLength: 0 is below the minimum of 1", NULL},
    {"byte_stride_6", {.views = "[{\"buffer\":0,\"byteLength\":48,\"byteStride\":6},"
                                "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":24}]"},
     "bufferViews[0].byteStride: 6 is not a multiple of 4",
     "Invalid `byteStride' value. `byteStride' must be the multiple of 4 : 6"}, /* tinygltf's own refusal */
    {"count_0",
     {.accessors = "[" TU_TETRA_ACCESSORS
                   ",{\"bufferView\":1,\"componentType\":5123,\"count\":0,\"type\":\"SCALAR\"}]"},
     "accessors[2].count: 0 is below the minimum of 1", "accessors[2]: count is 0"},
    {"metallic_1_5", {.more = ",\"materials\":[{\"pbrMetallicRoughness\":{\"metallicFactor\":1.5}}]"},
     "materials[0].pbrMetallicRoughness.metallicFactor: 1.5 is above the maximum of 1", NULL},
    {"yfov_0", {.more = ",\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0,\"znear\":0.1}}]"},
     "cameras[0].perspective.yfov: 0 is not above 0", NULL},
    /* array lengths and unique items */
    {"matrix_15", {.node = ",\"matrix\":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0]"}, "nodes[0].matrix: has 15 items, not 16",
     "nodes[0]: a transform has the wrong number of values"},
    {"empty_animations", {.more = ",\"animations\":[]"}, "animations: is empty (glTF wants at least one item)", NULL},
    {"joints_twice", {.more = ",\"skins\":[{\"joints\":[0,0]}]"},
     "skins[0].joints[1]: repeats skins[0].joints[0] (the items must be unique)", NULL},
};

START_TEST(gltf_schema_problem_is_refused_then_warned_when_lenient)
{
    const schema_case *c = &cases[_i];
    char *dir = tu_tempdir();
    char *path = write_tetra(dir, c->name, &c->parts);
    assert_refused(path, NULL, c->message);

    resurf_load_options o = resurf_load_options_default();
    o.lenient = true;
    if (c->lenient_failure) {
        assert_refused(path, &o, c->lenient_failure);
    } else {
        resurf_scene *s = NULL;
        resurf_error e;
        ck_assert_msg(resurf_scene_load(path, &o, &s, &e) == RESURF_OK, "%s: %s", c->name, e.message);
        ck_assert_uint_ge(resurf_scene_warning_count(s), 1);
        ck_assert_str_eq(resurf_scene_warning(s, 0), c->message);
        ck_assert_uint_eq(resurf_scene_primitive_mesh(s, 0)->triangle_count, 4); /* the tetrahedron was read */
        resurf_scene_free(s);
    }
    free(path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* The same check reads a .glb's JSON chunk. */
START_TEST(gltf_schema_checks_the_glb_json_chunk)
{
    char *dir = tu_tempdir();
    tu_bytes bin = tu_tetra_bin();
    doc_parts p = {.scenes = "[{\"nodes\":[0],\"name\":42}]", .buffers = "[{\"byteLength\":72}]"};
    char *json = tetra_json(&p);
    size_t json_size = (strlen(json) + 3) & ~(size_t)3, total = 12 + 8 + json_size + 8 + bin.size;
    tu_bytes glb = {0};
    uint32_t head[5] = {0x46546C67u, 2, (uint32_t)total, (uint32_t)json_size, 0x4E4F534Au}; /* "glTF", JSON */
    tu_put(&glb, head, sizeof head); /* the machine is little-endian, as glTF */
    tu_put(&glb, json, strlen(json));
    while (glb.size < 20 + json_size)
        tu_put_u8(&glb, ' ');
    uint32_t bin_head[2] = {(uint32_t)bin.size, 0x004E4942u}; /* BIN */
    tu_put(&glb, bin_head, sizeof bin_head);
    tu_put(&glb, bin.data, bin.size);
    char *path = tu_path(dir, "name.glb");
    ck_assert_int_eq(tu_write_file(path, glb.data, glb.size), 0);
    assert_refused(path, NULL, "scenes[0].name: must be a string, not the number 42");

    resurf_load_options o = resurf_load_options_default();
    o.lenient = true;
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_load(path, &o, &s, NULL), RESURF_OK);
    ck_assert_uint_eq(resurf_scene_warning_count(s), 1);
    ck_assert_str_eq(resurf_scene_warning(s, 0), "scenes[0].name: must be a string, not the number 42");
    resurf_scene_free(s);
    free(path);
    free(glb.data);
    free(json);
    free(bin.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* Lenient: every problem is a warning, in document order, the first 100 of them and then a count. */
START_TEST(gltf_schema_lenient_warns_each_problem)
{
    char *dir = tu_tempdir();
    doc_parts three = {.scenes = "[{\"nodes\":[0],\"name\":42}]", .node = ",\"weights\":[]",
                       .more = ",\"samplers\":[{\"magFilter\":9984}]"};
    char *path = write_tetra(dir, "three", &three);
    assert_refused(path, NULL, "nodes[0].weights: is empty (glTF wants at least one item)");
    resurf_load_options o = resurf_load_options_default();
    o.lenient = true;
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_load(path, &o, &s, NULL), RESURF_OK);
    ck_assert_uint_eq(resurf_scene_warning_count(s), 3);
    /* The walk follows the schema's order of the root's properties: nodes, samplers, scenes. */
    ck_assert_str_eq(resurf_scene_warning(s, 0), "nodes[0].weights: is empty (glTF wants at least one item)");
    ck_assert_str_eq(resurf_scene_warning(s, 1),
                     "samplers[0].magFilter: 9984 is not a magnification filter (9728, 9729)");
    ck_assert_str_eq(resurf_scene_warning(s, 2), "scenes[0].name: must be a string, not the number 42");
    resurf_scene_free(s);
    free(path);

    /* 150 nodes named by numbers. */
    size_t cap = 40 + 150 * 16;
    char *nodes = malloc(cap);
    size_t at = (size_t)snprintf(nodes, cap, ",\"name\":0}");
    for (int i = 1; i < 150; ++i)
        at += (size_t)snprintf(nodes + at, cap - at, ",{\"name\":%d}", i);
    nodes[at - 1] = 0; /* the template closes the last node; nodes[0] keeps its mesh */
    doc_parts many = {.node = nodes};
    path = write_tetra(dir, "many", &many);
    assert_refused(path, NULL, "nodes[0].name: must be a string, not the number 0");
    s = NULL;
    ck_assert_int_eq(resurf_scene_load(path, &o, &s, NULL), RESURF_OK);
    ck_assert_uint_eq(resurf_scene_warning_count(s), 101);
    ck_assert_str_eq(resurf_scene_warning(s, 99), "nodes[99].name: must be a string, not the number 99");
    ck_assert_str_eq(resurf_scene_warning(s, 100), "50 more problems with the glTF schema");
    resurf_scene_free(s);
    free(path);
    free(nodes);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* What the schema leaves open loads without a warning: extras of any type, unknown properties, extensions'
 * content, KHR_animation_pointer's "pointer" path where the document uses it. A number such as 0.0 where the schema
 * wants an integer is that integer (tinygltf alone would drop it: a node without its mesh, a primitive without
 * its indices, 4 vertices read as 1 triangle). */
START_TEST(gltf_schema_accepts_what_it_leaves_open)
{
    char *dir = tu_tempdir();
    doc_parts p = {.scenes = "[{\"nodes\":[0.0],\"extras\":7}]",
                   .node = ",\"extras\":\"text\",\"made_up\":[1,2],\"extensions\":{\"EXT_made_up\":{\"a\":[null]}}",
                   .meshes = "[{\"primitives\":[{\"attributes\":{\"POSITION\":0.0},\"indices\":1.0,\"mode\":4.0}]}]",
                   .more = ",\"extensionsUsed\":[\"KHR_animation_pointer\"],"
                           "\"animations\":[{\"channels\":[{\"sampler\":0,\"target\":{\"path\":\"pointer\","
                           "\"extensions\":{\"KHR_animation_pointer\":{\"pointer\":\"/nodes/0/translation\"}}}}],"
                           "\"samplers\":[{\"input\":1,\"output\":0}]}]"};
    char *path = write_tetra(dir, "open", &p);
    resurf_scene *s = tu_load_scene_ok(path);
    ck_assert_uint_eq(resurf_scene_warning_count(s), 0);
    ck_assert_uint_eq(resurf_scene_primitive_mesh(s, 0)->triangle_count, 4);
    resurf_scene_primitive info;
    ck_assert_int_eq(resurf_scene_primitive_info(s, 0, &info, NULL), RESURF_OK);
    ck_assert_uint_eq(info.instances, 1);
    resurf_scene_free(s);
    free(path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* The CLI: one line naming the file and the cause; --lenient prints the warning, and lod writes a valid file.
 * (Each command's stderr only: tu_run adds its own 2>&1 after the group.) */
START_TEST(gltf_schema_cli_refuses_and_lenient_warns)
{
    char *dir = tu_tempdir();
    doc_parts p = {.scenes = "[{\"nodes\":[0],\"name\":42}]"};
    char *path = write_tetra(dir, "name", &p), *out = NULL;
    char *cmd = tu_strf("{ %s info %s 2>&1 >/dev/null; }", RESURF_CLI, path);
    ck_assert_int_eq(tu_run(cmd, &out), 1);
    char *want = tu_strf("resurf: %s: scenes[0].name: must be a string, not the number 42\n", path);
    ck_assert_str_eq(out, want);
    free(want);
    free(out);
    free(cmd);
    cmd = tu_strf("{ %s info --lenient %s 2>&1 >/dev/null; }", RESURF_CLI, path);
    ck_assert_int_eq(tu_run(cmd, &out), 0);
    ck_assert_str_eq(out, "resurf: warning: scenes[0].name: must be a string, not the number 42\n");
    free(out);
    free(cmd);
    char *glb = tu_path(dir, "out.glb");
    cmd = tu_strf("{ %s lod --lenient --levels 0.5 %s -o %s 2>&1 >/dev/null; }", RESURF_CLI, path, glb);
    ck_assert_int_eq(tu_run(cmd, &out), 0);
    ck_assert_ptr_nonnull(strstr(out, "resurf: warning: scenes[0].name: must be a string, not the number 42\n"));
    ck_assert_int_eq(tu_validator_errors(glb), 0); /* tinygltf dropped the name */
    free(out);
    free(cmd);
    free(glb);
    free(path);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("gltf_schema");
    TCase *t = tcase_create("schema");
    tcase_add_loop_test(t, gltf_schema_problem_is_refused_then_warned_when_lenient, 0,
                        (int)(sizeof cases / sizeof *cases));
    tcase_add_test(t, gltf_schema_checks_the_glb_json_chunk);
    tcase_add_test(t, gltf_schema_lenient_warns_each_problem);
    tcase_add_test(t, gltf_schema_accepts_what_it_leaves_open);
    tcase_add_test(t, gltf_schema_cli_refuses_and_lenient_warns);
    suite_add_tcase(s, t);
    return s;
}

RESURF_TEST_MAIN()
