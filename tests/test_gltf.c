/* Tests of src/scene.c, src/scene_check.c, src/scene_save.c and the glTF/Draco shims (src/io/): round trips of
 * analytic meshes through .gltf/.glb/.drc with and without Draco, hand-written glTF documents whose decoded content
 * is known by construction (strips, fans, sparse accessors, normalized and quantized components, instancing, skins,
 * morph targets, points), the level-of-detail layouts, and hostile documents.
 *
 * Independent checks: the Khronos glTF validator (tools/validate-gltf.js, npm gltf-validator) on every file written,
 * Google's draco_decoder on Draco output, small node scripts that read the written JSON for structure the
 * validator does not check (MSFT_lod, image bytes against their source files), and tests/gltf_dead_bytes.js, a
 * byte accounting of every buffer written by a parser of its own. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "testutil.h"

/* ---- helpers ------------------------------------------------------------------------------------------------- */

static char *strf(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    char *s = malloc((size_t)n + 1);
    va_start(ap, fmt);
    vsnprintf(s, (size_t)n + 1, fmt, ap);
    va_end(ap);
    return s;
}

/* Errors the Khronos validator finds in a .gltf/.glb (fails the test when the validator cannot run). */
static int validator_errors(const char *path)
{
    char *cmd = strf("node '%s/tools/validate-gltf.js' '%s'", RESURF_SOURCE_DIR, path), *out = NULL;
    int rc = tu_run(cmd, &out);
    const char *p = out ? strstr(out, "numErrors ") : NULL;
    if (!p || rc == 2)
        ck_abort_msg("the glTF validator did not run (rc %d): %s", rc, out ? out : "");
    int errors = atoi(p + 10);
    if (errors)
        fprintf(stderr, "%s", out);
    free(cmd);
    free(out);
    return errors;
}

/* Runs a node script (JavaScript source) with the file as its argument; returns its trimmed stdout. */
static char *node_eval(const char *dir, const char *script, const char *file)
{
    char *js = tu_path(dir, "check.js");
    ck_assert_int_eq(tu_write_file(js, script, strlen(script)), 0);
    char *cmd = strf("node '%s' '%s'", js, file), *out = NULL;
    int rc = tu_run(cmd, &out);
    ck_assert_msg(rc == 0, "node script failed: %s", out);
    size_t n = strlen(out);
    while (n && (out[n - 1] == '\n' || out[n - 1] == ' '))
        out[--n] = 0;
    unlink(js);
    free(js);
    free(cmd);
    return out;
}

/* The JSON of a .gltf or of a .glb's first chunk, as a JavaScript expression `doc` in node scripts. */
#define JS_LOAD                                                                                                 \
    "const fs=require('fs');const b=fs.readFileSync(process.argv[2]);"                                        \
    "const doc=JSON.parse(b.slice(0,4).toString()==='glTF'?b.slice(20,20+b.readUInt32LE(12)).toString():b.toString());"

/* A growable byte buffer for hand-written .bin files (little-endian, as glTF requires). */
typedef struct bytes {
    unsigned char *data;
    size_t size;
} bytes;

static void put(bytes *b, const void *p, size_t n)
{
    b->data = realloc(b->data, b->size + n + 4);
    memcpy(b->data + b->size, p, n);
    b->size += n;
}
static void put_f32(bytes *b, float x) { put(b, &x, 4); }
static void put_u8(bytes *b, uint8_t x) { put(b, &x, 1); }
static void put_u16(bytes *b, uint16_t x) { put(b, &x, 2); }
static void put_i16(bytes *b, int16_t x) { put(b, &x, 2); }
static void align4(bytes *b)
{
    while (b->size % 4)
        put_u8(b, 0);
}

/* Writes DIR/NAME.gltf with the JSON and DIR/NAME.bin with the bytes; returns the .gltf path. */
static char *write_gltf(const char *dir, const char *name, const char *json, const bytes *bin)
{
    char *gltf = strf("%s/%s.gltf", dir, name), *binp = strf("%s/%s.bin", dir, name);
    ck_assert_int_eq(tu_write_file(gltf, json, strlen(json)), 0);
    if (bin)
        ck_assert_int_eq(tu_write_file(binp, bin->data, bin->size), 0);
    free(binp);
    return gltf;
}

static resurf_scene *load_ok(const char *path)
{
    resurf_scene *s = NULL;
    resurf_error e;
    resurf_status st = resurf_scene_load(path, NULL, &s, &e);
    char msg[600];
    resurf_format_error(msg, sizeof msg, &e);
    ck_assert_msg(st == RESURF_OK, "loading %s: %s", path, msg);
    return s;
}

static void save_ok(const resurf_scene *s, const char *path, const resurf_scene_save_options *o,
                    resurf_scene_save_report *r)
{
    resurf_error e;
    resurf_status st = resurf_scene_save(s, path, o, r, &e);
    char msg[600];
    resurf_format_error(msg, sizeof msg, &e);
    ck_assert_msg(st == RESURF_OK, "saving %s: %s", path, msg);
}

/* A sphere with exact normals, texcoords (longitude/latitude), RGBA colours and a float extra "temperature". */
static resurf_mesh *rich_sphere(size_t triangles)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, triangles, 0.2, 7, 1);
    ck_assert_ptr_nonnull(m);
    size_t n = m->vertex_count;
    m->texcoords[0] = malloc(n * 2 * sizeof(double));
    m->texcoord_count = 1;
    m->colors = malloc(n * 4 * sizeof(double));
    m->color_components = 4;
    resurf_attribute *t = NULL;
    ck_assert_int_eq(resurf_mesh_add_extra(m, "temperature", 1, &t, NULL), RESURF_OK);
    for (size_t v = 0; v < n; ++v) {
        const double *p = m->positions + 3 * v;
        m->texcoords[0][2 * v] = 0.5 + atan2(p[1], p[0]) / (2 * M_PI);
        m->texcoords[0][2 * v + 1] = 0.5 + asin(fmax(-1, fmin(1, p[2]))) / M_PI;
        for (int k = 0; k < 3; ++k)
            m->colors[4 * v + k] = 0.5 + 0.5 * p[k];
        m->colors[4 * v + 3] = 1.0;
        t->data[v] = (float)(20 + 10 * p[2]);
    }
    return m;
}

/* Over all vertices of b, the largest distance per coordinate to the nearest vertex of a (brute force). */
static double max_nearest(const double *a, size_t na, const double *b, size_t nb, size_t comps)
{
    double worst = 0;
    for (size_t i = 0; i < nb; ++i) {
        double best = INFINITY;
        for (size_t j = 0; j < na; ++j) {
            double d = 0;
            for (size_t k = 0; k < comps; ++k)
                d = fmax(d, fabs(a[j * comps + k] - b[i * comps + k]));
            best = fmin(best, d);
        }
        worst = fmax(worst, best);
    }
    return worst;
}

static double coordinate_range(const double *p, size_t n, size_t comps)
{
    double range = 0;
    for (size_t k = 0; k < comps; ++k) {
        double lo = INFINITY, hi = -INFINITY;
        for (size_t i = 0; i < n; ++i)
            lo = fmin(lo, p[i * comps + k]), hi = fmax(hi, p[i * comps + k]);
        range = fmax(range, hi - lo);
    }
    return range;
}

/* ---- round trips --------------------------------------------------------------------------------------------- */

/* Without Draco every value is written as a float: what comes back is the input rounded to float, exactly. */
START_TEST(gltf_roundtrip_plain_is_float_exact)
{
    char *dir = tu_tempdir();
    resurf_mesh *m = rich_sphere(1500);
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(m, &s, NULL), RESURF_OK);
    const char *names[] = {"plain.gltf", "plain.glb", "embedded.gltf"};
    for (int f = 0; f < 3; ++f) {
        char *path = tu_path(dir, names[f]);
        resurf_scene_save_options o = resurf_scene_save_options_default();
        o.embed_buffers = f == 2;
        save_ok(s, path, &o, NULL);
        ck_assert_int_eq(validator_errors(path), 0);
        resurf_scene *t = load_ok(path);
        ck_assert_uint_eq(resurf_scene_primitive_count(t), 1);
        const resurf_mesh *r = resurf_scene_primitive_mesh(t, 0);
        ck_assert_uint_eq(r->vertex_count, m->vertex_count);
        ck_assert_uint_eq(r->triangle_count, m->triangle_count);
        ck_assert_mem_eq(r->indices, m->indices, 3 * m->triangle_count * sizeof(uint32_t));
        ck_assert_ptr_nonnull(r->normals);
        ck_assert_uint_eq(r->texcoord_count, 1);
        ck_assert_ptr_nonnull(r->colors);
        ck_assert_uint_eq(r->color_components, 4);
        ck_assert_uint_eq(r->extra_count, 1);
        ck_assert_str_eq(r->extras[0].name, "_TEMPERATURE");
        for (size_t v = 0; v < m->vertex_count; ++v) {
            for (int k = 0; k < 3; ++k) {
                ck_assert(r->positions[3 * v + k] == (double)(float)m->positions[3 * v + k]);
                /* The exact normals are unit length already: rounding to float is the only change. */
                ck_assert(fabs(r->normals[3 * v + k] - m->normals[3 * v + k]) < 1e-7);
            }
            for (int k = 0; k < 2; ++k)
                ck_assert(r->texcoords[0][2 * v + k] == (double)(float)m->texcoords[0][2 * v + k]);
            for (int k = 0; k < 4; ++k)
                ck_assert(r->colors[4 * v + k] == (double)(float)m->colors[4 * v + k]);
            ck_assert(r->extras[0].data[v] == m->extras[0].data[v]);
        }
        resurf_scene_free(t);
        free(path);
    }
    /* Separate .bin beside plain.gltf; nothing else (no temporary file) in the folder. */
    char *bin = tu_path(dir, "plain.bin");
    ck_assert_int_eq(access(bin, F_OK), 0);
    ck_assert_int_eq(tu_count_entries(dir), 4);
    free(bin);
    resurf_scene_free(s);
    resurf_mesh_free(m);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* With Draco: same counts, positions within one quantization step (14 bits over the largest extent), normals
 * within 10-bit octahedral precision, texcoords within a 12-bit step. */
START_TEST(gltf_roundtrip_draco_within_quantization)
{
    char *dir = tu_tempdir();
    resurf_mesh *m = rich_sphere(1500);
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(m, &s, NULL), RESURF_OK);
    const char *names[] = {"draco.glb", "draco.gltf", "draco.drc"};
    for (int f = 0; f < 3; ++f) {
        char *path = tu_path(dir, names[f]);
        resurf_scene_save_options o = resurf_scene_save_options_default();
        o.draco = true;
        resurf_scene_save_report rep;
        save_ok(s, path, &o, &rep);
        ck_assert_uint_eq(rep.levels, 1);
        ck_assert_uint_eq(rep.level_triangles[0], m->triangle_count);
        ck_assert_uint_gt(rep.level_bytes[0], 0);
        if (f < 2)
            ck_assert_int_eq(validator_errors(path), 0);
        resurf_scene *t = load_ok(path);
        const resurf_mesh *r = resurf_scene_primitive_mesh(t, 0);
        ck_assert_uint_eq(r->vertex_count, m->vertex_count);
        ck_assert_uint_eq(r->triangle_count, m->triangle_count);
        double step = coordinate_range(m->positions, m->vertex_count, 3) / ((1 << 14) - 1);
        ck_assert_double_le(max_nearest(m->positions, m->vertex_count, r->positions, r->vertex_count, 3), step);
        ck_assert_double_le(max_nearest(r->positions, r->vertex_count, m->positions, m->vertex_count, 3), step);
        ck_assert_ptr_nonnull(r->normals);
        ck_assert_ptr_nonnull(r->texcoords[0]);
        ck_assert_ptr_nonnull(r->colors);
        /* Attributes follow their vertex: compare at the nearest input position. */
        double tstep = coordinate_range(m->texcoords[0], m->vertex_count, 2) / ((1 << 12) - 1);
        for (size_t v = 0; v < r->vertex_count; ++v) {
            size_t best = 0;
            double bd = INFINITY;
            for (size_t j = 0; j < m->vertex_count; ++j) {
                double d = v3_dist2(v3_load(r->positions + 3 * v), v3_load(m->positions + 3 * j));
                if (d < bd)
                    bd = d, best = j;
            }
            double dot = v3_dot(v3_load(r->normals + 3 * v), v3_load(m->normals + 3 * best));
            ck_assert_double_gt(dot, cos(1.0 * M_PI / 180)); /* 10 bits: well under a degree */
            for (int k = 0; k < 2; ++k)
                ck_assert_double_le(fabs(r->texcoords[0][2 * v + k] - m->texcoords[0][2 * best + k]), tstep);
            for (int k = 0; k < 3; ++k)
                ck_assert_double_le(fabs(r->colors[4 * v + k] - m->colors[4 * best + k]), 1.0 / 255);
        }
        resurf_scene_free(t);
        free(path);
    }
    /* Google's own decoder reads the .drc: the same triangle count. */
    char *drc = tu_path(dir, "draco.drc"), *obj = tu_path(dir, "decoded.obj");
    char *cmd = strf("draco_decoder -i '%s' -o '%s'", drc, obj), *out = NULL;
    ck_assert_msg(tu_run(cmd, &out) == 0, "draco_decoder failed: %s", out);
    resurf_mesh *d = NULL;
    ck_assert_int_eq(resurf_mesh_load(obj, NULL, &d, NULL), RESURF_OK);
    ck_assert_uint_eq(d->triangle_count, m->triangle_count);
    resurf_mesh_free(d);
    free(out);
    free(cmd);
    free(obj);
    free(drc);
    resurf_scene_free(s);
    resurf_mesh_free(m);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* The Draco payload inside a .glb decodes with draco_decoder too (extracted through the bufferView the
 * extension names). */
START_TEST(gltf_draco_payload_decodes_with_draco_decoder)
{
    char *dir = tu_tempdir();
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 1200, 0.1, 3, 1);
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(m, &s, NULL), RESURF_OK);
    char *glb = tu_path(dir, "t.glb"), *drc = tu_path(dir, "payload.drc"), *obj = tu_path(dir, "payload.obj");
    resurf_scene_save_options o = resurf_scene_save_options_default();
    o.draco = true;
    save_ok(s, glb, &o, NULL);
    char *script = strf(JS_LOAD "const p=doc.meshes[0].primitives[0];const v=doc.bufferViews[p.extensions."
                        "KHR_draco_mesh_compression.bufferView];const bin=20+b.readUInt32LE(12)+8;"
                        "fs.writeFileSync('%s',b.slice(bin+(v.byteOffset||0),bin+(v.byteOffset||0)+v.byteLength));"
                        "console.log(doc.accessors[p.indices].count/3, doc.accessors[p.attributes.POSITION].count,"
                        "doc.extensionsRequired.join(','))",
                        drc);
    char *facts = node_eval(dir, script, glb);
    char *cmd = strf("draco_decoder -i '%s' -o '%s'", drc, obj), *out = NULL;
    ck_assert_msg(tu_run(cmd, &out) == 0, "draco_decoder failed: %s", out);
    resurf_mesh *d = NULL;
    ck_assert_int_eq(resurf_mesh_load(obj, NULL, &d, NULL), RESURF_OK);
    ck_assert_uint_eq(d->triangle_count, m->triangle_count);
    char *expect = strf("%zu %zu KHR_draco_mesh_compression", m->triangle_count, m->vertex_count);
    ck_assert_str_eq(facts, expect);
    free(expect);
    resurf_mesh_free(d);
    free(out);
    free(cmd);
    free(facts);
    free(script);
    free(obj);
    free(drc);
    free(glb);
    resurf_scene_free(s);
    resurf_mesh_free(m);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* A mesh file is a one-mesh scene. */
START_TEST(gltf_mesh_file_is_a_scene)
{
    char *dir = tu_tempdir();
    resurf_mesh *m = tu_cube();
    char *ply = tu_path(dir, "cube.ply"), *glb = tu_path(dir, "cube.glb");
    ck_assert_int_eq(resurf_mesh_save(m, ply, NULL, NULL), RESURF_OK);
    resurf_scene *s = load_ok(ply);
    ck_assert_uint_eq(resurf_scene_mesh_count(s), 1);
    ck_assert_uint_eq(resurf_scene_primitive_count(s), 1);
    resurf_scene_primitive info;
    ck_assert_int_eq(resurf_scene_primitive_info(s, 0, &info, NULL), RESURF_OK);
    ck_assert_str_eq(info.name, "meshes[0].primitives[0]");
    ck_assert_int_eq(info.kind, RESURF_PRIMITIVE_TRIANGLES);
    save_ok(s, glb, NULL, NULL);
    ck_assert_int_eq(validator_errors(glb), 0);
    resurf_scene *t = load_ok(glb);
    ck_assert_uint_eq(resurf_scene_primitive_mesh(t, 0)->triangle_count, 12);
    resurf_scene_free(t);
    resurf_scene_free(s);
    resurf_mesh_free(m);
    free(ply);
    free(glb);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* ---- hand-written documents ---------------------------------------------------------------------------------- */

/* Six points on a zigzag, as a strip and as a fan:
 *   1---3---5        strip 0 1 2 3 4 5: (0,1,2) (1,3,2) (2,3,4) (3,5,4)   (glTF: odd triangles swap to keep
 *   |\  |\  |                                                              the winding)
 *   0---2---4        fan   0 1 2 3 4 5: (1,2,0) (2,3,0) (3,4,0) (4,5,0)                                      */
static char *zigzag_gltf(const char *dir, const char *name, int mode)
{
    bytes b = {0};
    static const float p[6][3] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {2, 0, 0}, {2, 1, 0}};
    for (int i = 0; i < 6; ++i)
        for (int k = 0; k < 3; ++k)
            put_f32(&b, p[i][k]);
    for (int i = 0; i < 6; ++i)
        put_u16(&b, (uint16_t)i);
    align4(&b);
    char *json = strf("{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
                      "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,\"mode\":%d}]}],"
                      "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":6,\"type\":\"VEC3\","
                      "\"min\":[0,0,0],\"max\":[2,1,0]},"
                      "{\"bufferView\":1,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}],"
                      "\"bufferViews\":[{\"buffer\":0,\"byteLength\":72},{\"buffer\":0,\"byteOffset\":72,\"byteLength\":12}],"
                      "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s.bin\"}]}",
                      mode, b.size, name);
    char *path = write_gltf(dir, name, json, &b);
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
        resurf_scene *s = load_ok(path);
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
        char *out = strf("%s/out%d.glb", dir, mode);
        save_ok(s, out, NULL, NULL);
        ck_assert_int_eq(validator_errors(out), 0);
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
    bytes b = {0};
    static const float base[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    for (int i = 0; i < 9; ++i)
        put_f32(&b, base[i]); /* 0..35 */
    put_u16(&b, 0), put_u16(&b, 2); /* 36..39 sparse indices */
    static const float over[6] = {5, 5, 5, 7, 8, 9};
    for (int i = 0; i < 6; ++i)
        put_f32(&b, over[i]); /* 40..63 sparse values */
    static const uint8_t uv8[6] = {0, 255, 51, 102, 255, 0};
    for (int i = 0; i < 6; ++i)
        put_u8(&b, uv8[i]); /* 64..69 */
    align4(&b);              /* 72 */
    static const uint16_t uv16[6] = {0, 65535, 13107, 26214, 65535, 0};
    for (int i = 0; i < 6; ++i)
        put_u16(&b, uv16[i]); /* 72..83 */
    static const uint8_t rgb[12] = {255, 0, 0, 0, 0, 255, 0, 0, 0, 0, 255, 0}; /* VEC3 rows padded to 4 bytes */
    for (int i = 0; i < 12; ++i)
        put_u8(&b, rgb[i]); /* 84..95 */
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
    char *path = write_gltf(dir, "sparse", json, &b);
    resurf_scene *s = load_ok(path);
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
    save_ok(s, out, NULL, NULL);
    ck_assert_int_eq(validator_errors(out), 0);
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
    bytes b = {0};
    static const int16_t q[9] = {0, 0, 0, 1000, 0, 0, 0, -1000, 0};
    for (int i = 0; i < 3; ++i) { /* stride 8: x y z and 2 bytes of padding (vertex attributes align to 4) */
        put_i16(&b, q[3 * i]), put_i16(&b, q[3 * i + 1]), put_i16(&b, q[3 * i + 2]), put_i16(&b, 0);
    }
    for (int i = 0; i < 3; ++i) { /* normals (0, 0, 127) → (0, 0, 1), stride 4 */
        put_u8(&b, 0), put_u8(&b, 0), put_u8(&b, 127), put_u8(&b, 0);
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
    char *path = write_gltf(dir, "quant", json, &b);
    resurf_scene *s = load_ok(path);
    const resurf_mesh *m = resurf_scene_primitive_mesh(s, 0);
    for (int i = 0; i < 9; ++i)
        ck_assert(m->positions[i] == q[i]);
    for (int v = 0; v < 3; ++v)
        ck_assert(m->normals[3 * v] == 0 && m->normals[3 * v + 1] == 0 && m->normals[3 * v + 2] == 1.0);
    /* Written as floats: the extension is no longer used, the node scale still applies. */
    char *out = tu_path(dir, "out.glb");
    save_ok(s, out, NULL, NULL);
    ck_assert_int_eq(validator_errors(out), 0);
    char *facts = node_eval(dir, JS_LOAD "console.log(JSON.stringify(doc.extensionsRequired||[]),"
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

/* A tetrahedron (4 positions, 4 triangles) in a .bin: positions at 0..47, indices (uint16) at 48..71. */
static bytes tetra_bin(void)
{
    bytes b = {0};
    static const float p[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    static const uint16_t t[12] = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
    for (int i = 0; i < 12; ++i)
        put_f32(&b, p[i]);
    for (int i = 0; i < 12; ++i)
        put_u16(&b, t[i]);
    return b;
}

#define TETRA_ACCESSORS                                                                                        \
    "{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\"min\":[-1,-1,-1],\"max\":[1,1,1]}," \
    "{\"bufferView\":1,\"componentType\":5123,\"count\":12,\"type\":\"SCALAR\"}"
#define TETRA_VIEWS "{\"buffer\":0,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,\"byteLength\":24}"

/* One mesh shown by two nodes: one primitive, two instances, simplified and written once. */
START_TEST(gltf_instanced_mesh_is_handled_once)
{
    char *dir = tu_tempdir();
    bytes b = tetra_bin();
    const char *json = "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
                       "\"nodes\":[{\"mesh\":0},{\"mesh\":0,\"translation\":[3,0,0]}],"
                       "\"meshes\":[{\"name\":\"tetra\",\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
                       "\"accessors\":[" TETRA_ACCESSORS "],\"bufferViews\":[" TETRA_VIEWS "],"
                       "\"buffers\":[{\"byteLength\":72,\"uri\":\"inst.bin\"}]}";
    char *path = write_gltf(dir, "inst", json, &b);
    resurf_scene *s = load_ok(path);
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
    save_ok(s, out, NULL, NULL);
    ck_assert_int_eq(validator_errors(out), 0);
    /* Two meshes (full detail and one level, shared), both nodes with MSFT_lod pointing at nodes that show the
     * same level mesh. */
    char *facts = node_eval(dir, JS_LOAD
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
    bytes b = tetra_bin(); /* 0..71 */
    for (int v = 0; v < 4; ++v) { /* joints 72..87: vertex v uses joints (v%2, 1-v%2) */
        put_u8(&b, (uint8_t)(v % 2)), put_u8(&b, (uint8_t)(1 - v % 2)), put_u8(&b, 0), put_u8(&b, 0);
    }
    for (int v = 0; v < 4; ++v) { /* weights 88..151 */
        put_f32(&b, 0.75f), put_f32(&b, 0.25f), put_f32(&b, 0), put_f32(&b, 0);
    }
    for (int j = 0; j < 2; ++j) /* identity inverse bind matrices 152..279 */
        for (int i = 0; i < 16; ++i)
            put_f32(&b, i % 5 == 0 ? 1.0f : 0.0f);
    char *json = strf(
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
        "\"nodes\":[{\"mesh\":0,\"skin\":0},{\"children\":[2]},{\"translation\":[0,1,0]}],"
        "\"skins\":[{\"joints\":[1,2],\"inverseBindMatrices\":4}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"JOINTS_0\":2,\"WEIGHTS_0\":3},\"indices\":1}]}],"
        "\"accessors\":[" TETRA_ACCESSORS ",{\"bufferView\":2,\"componentType\":5121,\"count\":4,\"type\":\"VEC4\"},"
        "{\"bufferView\":3,\"componentType\":5126,\"count\":4,\"type\":\"VEC4\"},"
        "{\"bufferView\":4,\"componentType\":5126,\"count\":2,\"type\":\"MAT4\"}],"
        "\"bufferViews\":[" TETRA_VIEWS ",{\"buffer\":0,\"byteOffset\":72,\"byteLength\":16},"
        "{\"buffer\":0,\"byteOffset\":88,\"byteLength\":64},{\"buffer\":0,\"byteOffset\":152,\"byteLength\":128}],"
        "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"skin.bin\"}]}",
        b.size);
    char *path = write_gltf(dir, "skin", json, &b);
    resurf_scene *s = load_ok(path);
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
        char *out = strf("%s/out%d.glb", dir, draco);
        resurf_scene_save_options o = resurf_scene_save_options_default();
        o.draco = draco;
        save_ok(s, out, &o, NULL);
        ck_assert_int_eq(validator_errors(out), 0);
        char *facts = node_eval(dir, JS_LOAD
                                "const n=doc.nodes[0];const lod=doc.nodes[n.extensions.MSFT_lod.ids[0]];"
                                "const a=doc.meshes[lod.mesh].primitives[0].attributes;"
                                "console.log(doc.accessors[a.JOINTS_0].componentType, lod.skin, n.skin,"
                                "doc.skins[0].joints.join(','), doc.accessors[doc.skins[0].inverseBindMatrices].count)",
                                out);
        ck_assert_str_eq(facts, "5121 0 0 1,2 2");
        free(facts);
        resurf_scene *t = load_ok(out);
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

/* Morph targets: the primitive stays at full detail (set_lods refuses it) and its targets are written back.
 * A points primitive beside it passes through untouched. */
START_TEST(gltf_morph_targets_and_points_pass_through)
{
    char *dir = tu_tempdir();
    bytes b = tetra_bin(); /* 0..71 */
    for (int i = 0; i < 12; ++i)
        put_f32(&b, i % 3 == 2 ? 0.5f : 0.0f); /* target: +0.5 z, 72..119 */
    char *json = strf(
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
        "\"nodes\":[{\"mesh\":0},{\"mesh\":1}],"
        "\"meshes\":[{\"weights\":[0.5],\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,"
        "\"targets\":[{\"POSITION\":2}]}]},{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"mode\":0}]}],"
        "\"accessors\":[" TETRA_ACCESSORS ",{\"bufferView\":2,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
        "\"min\":[0,0,0.5],\"max\":[0,0,0.5]}],"
        "\"bufferViews\":[" TETRA_VIEWS ",{\"buffer\":0,\"byteOffset\":72,\"byteLength\":48}],"
        "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"morph.bin\"}]}",
        b.size);
    char *path = write_gltf(dir, "morph", json, &b);
    resurf_scene *s = load_ok(path);
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
    ck_assert_int_eq(resurf_scene_set_lods(s, 0, lods, 1, &e), RESURF_ERR_UNSUPPORTED);
    ck_assert_ptr_nonnull(strstr(e.message, "morph targets"));
    ck_assert_int_eq(resurf_scene_set_lods(s, 1, lods, 1, NULL), RESURF_ERR_UNSUPPORTED);
    char *out = tu_path(dir, "out.glb");
    resurf_scene_save_options o = resurf_scene_save_options_default();
    o.draco = true;
    save_ok(s, out, &o, NULL);
    ck_assert_int_eq(validator_errors(out), 0);
    char *facts = node_eval(dir, JS_LOAD "const p=[doc.meshes[0].primitives[0],doc.meshes[1].primitives[0]];"
                                         "console.log(p[0].targets.length, doc.accessors[p[0].targets[0].POSITION].count,"
                                         "doc.meshes[0].weights.join(','), p[1].mode, doc.accessors[p[1].attributes.POSITION].count,"
                                         "JSON.stringify(doc.extensionsUsed||[]))", out);
    ck_assert_str_eq(facts, "1 4 0.5 0 4 []");
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

/* A document with a material, a texture whose PNG is a data: URI, a camera, an animation of the node, extras and
 * an unknown extension: all of it is still there after a save (the image moved into the buffer). */
START_TEST(gltf_keeps_everything_else)
{
    char *dir = tu_tempdir();
    bytes b = tetra_bin(); /* 0..71 */
    put_f32(&b, 0), put_f32(&b, 1);                            /* times 72..79 */
    put_f32(&b, 0), put_f32(&b, 0), put_f32(&b, 0);            /* translations 80..103 */
    put_f32(&b, 0), put_f32(&b, 1), put_f32(&b, 0);
    /* A 1×1 PNG (signature, IHDR, IDAT, IEND), base64. */
    const char *png = "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAABJRU5ErkJggg==";
    char *json = strf(
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
        "\"accessors\":[" TETRA_ACCESSORS ",{\"bufferView\":2,\"componentType\":5126,\"count\":2,\"type\":\"SCALAR\","
        "\"min\":[0],\"max\":[1]},{\"bufferView\":3,\"componentType\":5126,\"count\":2,\"type\":\"VEC3\"},"
        "{\"bufferView\":4,\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"}],"
        "\"bufferViews\":[" TETRA_VIEWS ",{\"buffer\":0,\"byteOffset\":72,\"byteLength\":8},"
        "{\"buffer\":0,\"byteOffset\":80,\"byteLength\":24},{\"buffer\":0,\"byteOffset\":0,\"byteLength\":32}],"
        "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"all.bin\"}]}",
        png, b.size);
    char *path = write_gltf(dir, "all", json, &b);
    resurf_scene *s = load_ok(path);
    resurf_mesh *lod = NULL;
    ck_assert_int_eq(resurf_mesh_clone(resurf_scene_primitive_mesh(s, 0), &lod, NULL), RESURF_OK);
    lod->triangle_count = 2;
    const resurf_mesh *lods[1] = {lod};
    ck_assert_int_eq(resurf_scene_set_lods(s, 0, lods, 1, NULL), RESURF_OK);
    char *out = tu_path(dir, "out.glb");
    save_ok(s, out, NULL, NULL);
    ck_assert_int_eq(validator_errors(out), 0);
    /* The node has an animated translation: its mesh moves into a child that carries MSFT_lod. */
    char *facts = node_eval(dir, JS_LOAD
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

/* ---- levels of detail ---------------------------------------------------------------------------------------- */

/* Three levels of a sphere: the full mesh and two coarser analytic spheres with the same attributes. */
static resurf_scene *sphere_with_levels(resurf_mesh **levels)
{
    levels[0] = shape_mesh(SHAPE_SPHERE, 2000, 0.1, 1, 1);
    levels[1] = shape_mesh(SHAPE_SPHERE, 600, 0.1, 2, 1);
    levels[2] = shape_mesh(SHAPE_SPHERE, 150, 0.1, 3, 1);
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(levels[0], &s, NULL), RESURF_OK);
    const resurf_mesh *lods[2] = {levels[1], levels[2]};
    ck_assert_int_eq(resurf_scene_set_lods(s, 0, lods, 2, NULL), RESURF_OK);
    return s;
}

START_TEST(gltf_msft_lod_structure)
{
    char *dir = tu_tempdir();
    resurf_mesh *levels[3];
    resurf_scene *s = sphere_with_levels(levels);
    const double coverage[3] = {0.4, 0.1, 0.01};
    ck_assert_int_eq(resurf_scene_set_screen_coverage(s, 0, coverage, 3, NULL), RESURF_OK);
    for (int draco = 0; draco < 2; ++draco) {
        char *out = strf("%s/lod%d.gltf", dir, draco);
        resurf_scene_save_options o = resurf_scene_save_options_default();
        o.draco = draco;
        resurf_scene_save_report r;
        save_ok(s, out, &o, &r);
        ck_assert_uint_eq(r.levels, 3);
        for (int k = 0; k < 3; ++k) {
            ck_assert_uint_eq(r.level_triangles[k], levels[k]->triangle_count);
            ck_assert_uint_gt(r.level_bytes[k], 0);
        }
        ck_assert_uint_gt(r.level_bytes[0], r.level_bytes[1]);
        ck_assert_uint_gt(r.level_bytes[1], r.level_bytes[2]);
        ck_assert_int_eq(validator_errors(out), 0);
        /* The spec's structure: the extension on the full-detail node, ids of nodes that are in no scene, one
         * coverage value more than ids, and each id's mesh has that level's triangles. */
        char *facts = node_eval(dir, JS_LOAD
                                "const sc=doc.scenes[doc.scene].nodes;const n=doc.nodes[sc[0]];"
                                "const ids=n.extensions.MSFT_lod.ids;const inScene=ids.some(i=>doc.scenes.some(s=>s.nodes.includes(i)));"
                                "const tri=i=>{const p=doc.meshes[doc.nodes[i].mesh].primitives[0];return doc.accessors[p.indices].count/3;};"
                                "console.log(sc.length,ids.length,inScene,n.extras.MSFT_screencoverage.join(','),"
                                "tri(sc[0]),ids.map(tri).join(','),doc.extensionsUsed.includes('MSFT_lod'),"
                                "(doc.extensionsRequired||[]).includes('MSFT_lod'))",
                                out);
        char *want = strf("1 2 false 0.4,0.1,0.01 %zu %zu,%zu true false", levels[0]->triangle_count,
                          levels[1]->triangle_count, levels[2]->triangle_count);
        ck_assert_str_eq(facts, want);
        free(want);
        free(facts);
        free(out);
    }
    /* Coverage values that do not match the level count are refused at save; nothing is written. */
    const double two[2] = {0.5, 0.1};
    ck_assert_int_eq(resurf_scene_set_screen_coverage(s, 0, two, 2, NULL), RESURF_OK);
    char *bad = tu_path(dir, "bad.glb");
    int before = tu_count_entries(dir);
    ck_assert_int_eq(resurf_scene_save(s, bad, NULL, NULL, NULL), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(tu_count_entries(dir), before);
    free(bad);
    resurf_scene_free(s);
    for (int k = 0; k < 3; ++k)
        resurf_mesh_free(levels[k]);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(gltf_files_layout_one_file_per_level)
{
    char *dir = tu_tempdir();
    resurf_mesh *levels[3];
    resurf_scene *s = sphere_with_levels(levels);
    char *out = tu_path(dir, "ball.glb");
    resurf_scene_save_options o = resurf_scene_save_options_default();
    o.layout = RESURF_LOD_FILES;
    o.draco = true;
    resurf_scene_save_report r;
    save_ok(s, out, &o, &r);
    ck_assert_uint_eq(r.files, 3);
    ck_assert_int_eq(tu_count_entries(dir), 3);
    for (unsigned k = 0; k < 3; ++k) {
        char name[512];
        resurf_scene_level_path(name, sizeof name, out, k);
        char *want = strf("%s/ball_lod%u.glb", dir, k);
        ck_assert_str_eq(name, want);
        free(want);
        ck_assert_int_eq(validator_errors(name), 0);
        resurf_scene *t = load_ok(name);
        ck_assert_uint_eq(resurf_scene_primitive_mesh(t, 0)->triangle_count, levels[k]->triangle_count);
        resurf_scene_free(t);
    }
    /* One level alone as a plain scene. */
    char *one = tu_path(dir, "level1.gltf");
    o.level = 1;
    o.draco = false;
    save_ok(s, one, &o, NULL);
    resurf_scene *t = load_ok(one);
    ck_assert_uint_eq(resurf_scene_primitive_mesh(t, 0)->triangle_count, levels[1]->triangle_count);
    resurf_scene_free(t);
    free(one);
    free(out);
    resurf_scene_free(s);
    for (int k = 0; k < 3; ++k)
        resurf_mesh_free(levels[k]);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

START_TEST(gltf_side_by_side_layout)
{
    char *dir = tu_tempdir();
    resurf_mesh *levels[3];
    resurf_scene *s = sphere_with_levels(levels);
    char *out = tu_path(dir, "row.glb");
    resurf_scene_save_options o = resurf_scene_save_options_default();
    o.layout = RESURF_LOD_SIDE_BY_SIDE;
    save_ok(s, out, &o, NULL);
    ck_assert_int_eq(validator_errors(out), 0);
    /* Three roots: the original and one group per level, moved by k × width × 1.25 along x (width 2: a unit
     * sphere with vertices on it, up to the extremes the mesh reaches). */
    double lo[3], hi[3];
    resurf_mesh_bounds(levels[0], lo, hi);
    char *facts = node_eval(dir, JS_LOAD "const sc=doc.scenes[0].nodes;"
                                         "console.log(sc.length, sc.slice(1).map(i=>doc.nodes[i].translation[0].toFixed(6)).join(','))",
                            out);
    char *want = strf("3 %.6f,%.6f", (hi[0] - lo[0]) * 1.25, 2 * (hi[0] - lo[0]) * 1.25);
    ck_assert_str_eq(facts, want);
    free(want);
    free(facts);
    free(out);
    resurf_scene_free(s);
    for (int k = 0; k < 3; ++k)
        resurf_mesh_free(levels[k]);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* A level that lacks an attribute of the primitive is refused; the previous levels stay. */
START_TEST(gltf_set_lods_checks_levels)
{
    resurf_mesh *m = shape_mesh(SHAPE_SPHERE, 300, 0, 1, 1);
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(m, &s, NULL), RESURF_OK);
    resurf_mesh *bare = shape_mesh(SHAPE_SPHERE, 100, 0, 1, 0);
    const resurf_mesh *lods[1] = {bare};
    resurf_error e;
    ck_assert_int_eq(resurf_scene_set_lods(s, 0, lods, 1, &e), RESURF_ERR_INVALID_MESH);
    ck_assert_ptr_null(strchr(e.message, '\n'));
    bare->indices[0] = 100000;
    ck_assert_int_eq(resurf_scene_set_lods(s, 0, lods, 1, NULL), RESURF_ERR_INVALID_MESH);
    resurf_scene_primitive info;
    resurf_scene_primitive_info(s, 0, &info, NULL);
    ck_assert_uint_eq(info.lod_count, 0);
    resurf_mesh_free(bare);
    resurf_scene_free(s);
    resurf_mesh_free(m);
}
END_TEST

/* ---- hostile input ------------------------------------------------------------------------------------------- */

/* A .drc of a plain tetrahedron (POSITION only: Draco unique id 0), made by resurf. */
static bytes tetra_draco(const char *dir)
{
    resurf_mesh *t = tu_tetrahedron();
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(t, &s, NULL), RESURF_OK);
    char *drc = tu_path(dir, "tetra.drc");
    save_ok(s, drc, NULL, NULL);
    bytes b = {0};
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
    return strf("{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_draco_mesh_compression\"],"
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
    bytes d = tetra_draco(dir);
    align4(&d);
    size_t size = d.size;
    char *json = draco_json(size, "{\"bufferView\":0,\"attributes\":{\"POSITION\":0}}", "ok");
    char *path = write_gltf(dir, "ok", json, &d);
    resurf_scene *s = load_ok(path);
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
    "\"accessors\":[" TETRA_ACCESSORS "],\"bufferViews\":[" TETRA_VIEWS "],"                                   \
    "\"buffers\":[{\"byteLength\":72,\"uri\":\"h.bin\"}]}"
#define H_MESH "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"

static const hostile_case hostile_cases[] = {
    {"json syntax", "{\"asset\":{\"version\":\"2.0\"},,}", RESURF_ERR_PARSE, "JSON"},
    {"not an object", "[1,2,3]", RESURF_ERR_PARSE, "object"},
    {"no asset", "{\"scenes\":[]}", RESURF_ERR_PARSE, "asset"},
    {"bad accessor type", H_HEAD H_MESH "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,"
                          "\"type\":\"VEC7\"}],\"bufferViews\":[" TETRA_VIEWS "],\"buffers\":[{\"byteLength\":72,"
                          "\"uri\":\"h.bin\"}]}",
     RESURF_ERR_PARSE, "type"},
    {"indices accessor out of range", H_HEAD "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},"
                                      "\"indices\":99}]}]," H_TETRA_DATA,
     RESURF_ERR_PARSE, "indices"},
    {"attribute accessor out of range", H_HEAD "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":7}}]}],"
                                        H_TETRA_DATA,
     RESURF_ERR_PARSE, "7"},
    {"component type", H_HEAD H_MESH "\"accessors\":[{\"bufferView\":0,\"componentType\":5130,\"count\":4,"
                       "\"type\":\"VEC3\"},{\"bufferView\":1,\"componentType\":5123,\"count\":12,\"type\":\"SCALAR\"}],"
                       "\"bufferViews\":[" TETRA_VIEWS "],\"buffers\":[{\"byteLength\":72,\"uri\":\"h.bin\"}]}",
     RESURF_ERR_PARSE, "componentType"},
    {"bufferView past its buffer", H_HEAD H_MESH "\"accessors\":[" TETRA_ACCESSORS "],\"bufferViews\":[{\"buffer\":0,"
                                   "\"byteLength\":48},{\"buffer\":0,\"byteOffset\":60,\"byteLength\":24}],"
                                   "\"buffers\":[{\"byteLength\":72,\"uri\":\"h.bin\"}]}",
     RESURF_ERR_PARSE, "past the end"},
    {"accessor past its bufferView", H_HEAD H_MESH "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,"
                                     "\"count\":5,\"type\":\"VEC3\"},{\"bufferView\":1,\"componentType\":5123,"
                                     "\"count\":12,\"type\":\"SCALAR\"}],\"bufferViews\":[" TETRA_VIEWS "],"
                                     "\"buffers\":[{\"byteLength\":72,\"uri\":\"h.bin\"}]}",
     RESURF_ERR_PARSE, "do not fit"},
    {"buffer index", H_HEAD H_MESH "\"accessors\":[" TETRA_ACCESSORS "],\"bufferViews\":[{\"buffer\":5,"
                     "\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,\"byteLength\":24}],"
                     "\"buffers\":[{\"byteLength\":72,\"uri\":\"h.bin\"}]}",
     RESURF_ERR_PARSE, "buffer 5"},
    {"missing .bin", H_HEAD H_MESH "\"accessors\":[" TETRA_ACCESSORS "],\"bufferViews\":[" TETRA_VIEWS "],"
                     "\"buffers\":[{\"byteLength\":72,\"uri\":\"missing.bin\"}]}",
     RESURF_ERR_PARSE, "missing.bin"},
    {"short .bin", H_HEAD H_MESH "\"accessors\":[" TETRA_ACCESSORS "],\"bufferViews\":[" TETRA_VIEWS "],"
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
    {"required extension", H_HEAD "\"extensionsUsed\":[\"EXT_meshopt_compression\"],\"extensionsRequired\":"
                           "[\"EXT_meshopt_compression\"]," H_MESH H_TETRA_DATA,
     RESURF_ERR_UNSUPPORTED, "EXT_meshopt_compression"},
};

/* The same files from memory: a .glb, a .gltf with its buffer in a data: URI and a .drc written by the library,
 * read back with the format named and by content, give the mesh that was saved (float-exact without Draco, within
 * a 14-bit quantization step with it); OBJ text becomes a one-mesh scene. */
START_TEST(gltf_load_memory_reads_what_was_saved)
{
    char *dir = tu_tempdir();
    resurf_mesh *m = rich_sphere(300);
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(m, &s, NULL), RESURF_OK);
    const struct {
        const char *file;
        resurf_scene_format format;
        double tolerance;
    } cases[] = {{"m.glb", RESURF_SCENE_FORMAT_GLB, 0},
                 {"m.gltf", RESURF_SCENE_FORMAT_GLTF, 0},
                 {"m.drc", RESURF_SCENE_FORMAT_DRC, 2.0 / ((1 << 14) - 1)}}; /* extent 2 on a 14-bit grid */
    for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
        char *path = tu_path(dir, cases[i].file);
        resurf_scene_save_options o = resurf_scene_save_options_default();
        o.embed_buffers = true;
        save_ok(s, path, &o, NULL);
        size_t size = 0;
        char *data = tu_read_file(path, &size);
        ck_assert_ptr_nonnull(data);
        for (int by_content = 0; by_content < 2; ++by_content) {
            resurf_scene *t = NULL;
            resurf_error e;
            resurf_status st = resurf_scene_load_memory(data, size, by_content ? RESURF_SCENE_FORMAT_AUTO
                                                                               : cases[i].format,
                                                        NULL, &t, &e);
            ck_assert_msg(st == RESURF_OK, "%s: %s", cases[i].file, e.message);
            ck_assert_uint_eq(resurf_scene_primitive_count(t), 1);
            const resurf_mesh *r = resurf_scene_primitive_mesh(t, 0);
            ck_assert_uint_eq(r->vertex_count, m->vertex_count);
            ck_assert_uint_eq(r->triangle_count, m->triangle_count);
            ck_assert_ptr_nonnull(r->normals);
            ck_assert_uint_eq(r->texcoord_count, 1);
            if (cases[i].tolerance == 0) {
                ck_assert_mem_eq(r->indices, m->indices, 3 * m->triangle_count * sizeof(uint32_t));
                for (size_t k = 0; k < 3 * m->vertex_count; ++k)
                    ck_assert(r->positions[k] == (double)(float)m->positions[k]);
            } else {
                /* Draco may reorder vertices: every decoded vertex lies within a step of a saved one. */
                ck_assert(max_nearest(r->positions, r->vertex_count, m->positions, m->vertex_count, 3) <=
                          cases[i].tolerance);
            }
            resurf_scene_free(t);
        }
        free(data);
        free(path);
    }
    const char obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    resurf_scene *t = NULL;
    ck_assert_int_eq(resurf_scene_load_memory(obj, sizeof obj - 1, RESURF_SCENE_FORMAT_AUTO, NULL, &t, NULL),
                     RESURF_OK);
    ck_assert_uint_eq(resurf_scene_primitive_mesh(t, 0)->triangle_count, 1);
    resurf_scene_free(t);
    resurf_scene_free(s);
    resurf_mesh_free(m);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* A document in memory has no folder: a buffer uri that is not a data: URI is refused by name, even when a file of
 * that name exists in the current folder, and an unknown format value is refused. */
START_TEST(gltf_load_memory_refuses_external_files)
{
    const struct {
        const char *uri, *printed;
    } cases[] = {{"h.bin", "h.bin"}, {"/etc/passwd", "/etc/passwd"}, {"a\\nb.bin", "a?b.bin"}};
    for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
        char *json = strf(H_HEAD H_MESH "\"accessors\":[" TETRA_ACCESSORS "],\"bufferViews\":[" TETRA_VIEWS "],"
                          "\"buffers\":[{\"byteLength\":72,\"uri\":\"%s\"}]}",
                          cases[i].uri);
        char *expected = strf("buffers[0]: the uri '%s' names an external file, which a document loaded from memory "
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
    bytes b = tetra_bin();
    char *binp = tu_path(dir, "h.bin");
    ck_assert_int_eq(tu_write_file(binp, b.data, b.size), 0);
    for (size_t i = 0; i < sizeof hostile_cases / sizeof *hostile_cases; ++i) {
        const hostile_case *h = &hostile_cases[i];
        char *json = NULL;
        bytes bin = tetra_bin();
        char *name = strf("h%zu", i);
        if (!strcmp(h->name, "index past the vertices") || !strcmp(h->name, "infinite position")) {
            if (h->name[0] == 'i' && h->name[1] == 'n' && h->name[2] == 'd')
                ((uint16_t *)(bin.data + 48))[5] = 9;
            else {
                float inf = INFINITY;
                memcpy(bin.data + 4, &inf, 4);
            }
            char *raw = strf(H_HEAD H_MESH "\"accessors\":[" TETRA_ACCESSORS "],\"bufferViews\":[" TETRA_VIEWS "],"
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
            json = strf("%s", h->json);
        }
        char *path = write_gltf(dir, name, json, &bin);
        int before = tu_count_entries(dir);
        resurf_scene *s = NULL;
        resurf_error e;
        resurf_status st = resurf_scene_load(path, NULL, &s, &e);
        ck_assert_msg(st == h->status, "%s: status %d (%s), expected %d", h->name, st, e.message, h->status);
        ck_assert_ptr_null(s);
        ck_assert_msg(e.message[0] && !strchr(e.message, '\n'), "%s: message '%s'", h->name, e.message);
        ck_assert_msg(strstr(e.message, h->says), "%s: '%s' does not say '%s'", h->name, e.message, h->says);
        ck_assert_int_eq(tu_count_entries(dir), before);
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
    bytes good = tetra_draco(dir);
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
        bytes d = {0};
        put(&d, good.data, good.size);
        if (cases[i].damage == 1)
            for (size_t k = 8; k < d.size; ++k)
                d.data[k] = (unsigned char)(k * 37 + 11);
        if (cases[i].damage == 2)
            d.size = d.size / 2;
        size_t size = d.size;
        align4(&d);
        char *name = strf("d%zu", i);
        char *json = draco_json(size, cases[i].extension, name);
        char *path = write_gltf(dir, name, json, &d);
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
        char *path = strf("%s/tests/corpus-gltf/%s", RESURF_SOURCE_DIR, cases[i].file);
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
    save_ok(s, glb, NULL, NULL);
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
        char *bad = strf("%s/bad%zu.glb", dir, i);
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

/* Saving fails without leaving anything: a missing folder, a .bin that cannot be replaced, an unknown extension. */
START_TEST(gltf_save_failures_write_nothing)
{
    char *dir = tu_tempdir();
    resurf_mesh *m = tu_cube();
    resurf_scene *s = NULL;
    ck_assert_int_eq(resurf_scene_from_mesh(m, &s, NULL), RESURF_OK);
    char *missing = tu_path(dir, "no/such/dir/x.glb");
    ck_assert_int_eq(resurf_scene_save(s, missing, NULL, NULL, NULL), RESURF_ERR_IO);
    ck_assert_int_eq(tu_count_entries(dir), 0);
    /* x.bin is a folder: the .bin cannot be renamed into place, so x.gltf is not written either. */
    char *bin_dir = tu_path(dir, "x.bin"), *gltf = tu_path(dir, "x.gltf");
    ck_assert_int_eq(mkdir(bin_dir, 0700), 0);
    resurf_error e;
    ck_assert_int_eq(resurf_scene_save(s, gltf, NULL, NULL, &e), RESURF_ERR_IO);
    ck_assert_int_eq(tu_count_entries(dir), 1);
    char *wrong = tu_path(dir, "x.fbx");
    ck_assert_int_eq(resurf_scene_save(s, wrong, NULL, NULL, NULL), RESURF_ERR_UNSUPPORTED);
    resurf_scene_save_options o = resurf_scene_save_options_default();
    o.position_bits = 31;
    ck_assert_int_eq(resurf_scene_save(s, gltf, &o, NULL, NULL), RESURF_ERR_INVALID_OPTIONS);
    ck_assert_int_eq(tu_count_entries(dir), 1);
    free(wrong);
    free(gltf);
    free(bin_dir);
    free(missing);
    resurf_scene_free(s);
    resurf_mesh_free(m);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* The CLI: `resurf lod` on a mesh file writes a Draco MSFT_lod chain that validates, and its JSON table gives
 * each level's triangles (at most the ratio asked for) and bytes. */
START_TEST(gltf_cli_lod_writes_a_valid_chain)
{
    char *dir = tu_tempdir();
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 4000, 0.2, 5, 1);
    char *ply = tu_path(dir, "torus.ply"), *glb = tu_path(dir, "torus.glb");
    ck_assert_int_eq(resurf_mesh_save(m, ply, NULL, NULL), RESURF_OK);
    char *cmd = strf("'%s' lod '%s' -o '%s' --levels 0.5,0.2 --json", RESURF_CLI, ply, glb), *out = NULL;
    ck_assert_msg(tu_run(cmd, &out) == 0, "resurf lod failed: %s", out);
    ck_assert_int_eq(validator_errors(glb), 0);
    /* The JSON table, read back with node. */
    char *json = tu_path(dir, "table.json");
    ck_assert_int_eq(tu_write_file(json, out, strlen(out)), 0);
    char *facts = node_eval(dir, "const t=JSON.parse(require('fs').readFileSync(process.argv[2]));"
                                 "console.log(t.draco,t.layout,t.levels.length,"
                                 "t.levels.map(l=>l.triangles<=Math.floor(l.ratio*t.levels[0].triangles)+1).join(','),"
                                 "t.levels.every(l=>l.bytes>0),t.levels[2].error_rel>0)",
                            json);
    ck_assert_str_eq(facts, "true msft_lod 3 true,true,true true true");
    char *lods = node_eval(dir, JS_LOAD "console.log(doc.nodes[0].extensions.MSFT_lod.ids.length,"
                                        "doc.nodes[0].extras.MSFT_screencoverage.length)", glb);
    ck_assert_str_eq(lods, "2 3");
    free(lods);
    free(facts);
    free(json);
    free(out);
    free(cmd);
    free(glb);
    free(ply);
    resurf_mesh_free(m);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

/* ---- issue 20: self-contained outputs, no dead bytes, JSON as it was ----------------------------------------- */

/* Warnings the Khronos validator finds (0 when it finds none). */
static int validator_warnings(const char *path)
{
    char *cmd = strf("node '%s/tools/validate-gltf.js' '%s'", RESURF_SOURCE_DIR, path), *out = NULL;
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
    char *cmd = strf("node '%s/tests/gltf_dead_bytes.js' '%s'", RESURF_SOURCE_DIR, path), *out = NULL;
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
    bytes bin = tetra_bin(); /* 0..71, then texcoords 72..103 */
    for (int v = 0; v < 4; ++v)
        put_f32(&bin, (float)(v & 1)), put_f32(&bin, (float)(v >> 1));
    char *json = strf(
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}},"
        "\"emissiveTexture\":{\"index\":1}}],"
        "\"textures\":[{\"source\":0},{\"source\":1}],"
        "\"images\":[{\"uri\":\"%s\"},{\"uri\":\"../shared/b.png\"}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":2},\"indices\":1,\"material\":0}]}],"
        "\"accessors\":[" TETRA_ACCESSORS ",{\"bufferView\":2,\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"}],"
        "\"bufferViews\":[" TETRA_VIEWS ",{\"buffer\":0,\"byteOffset\":72,\"byteLength\":32}],"
        "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"tex.bin\"}]}",
        first_uri, bin.size);
    char *path = write_gltf(in, "tex", json, &bin);
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
    JS_LOAD "const path=require('path');"                                                                       \
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
    resurf_scene *s = load_ok(path);
    ck_assert_uint_eq(resurf_scene_warning_count(s), 0);
    add_one_level(s);
    char *outdir = tu_path(dir, "out"), *out = tu_path(dir, "out/t.glb");
    ck_assert_int_eq(mkdir(outdir, 0777), 0);
    save_ok(s, out, NULL, NULL);
    ck_assert_int_eq(tu_count_entries(outdir), 1); /* nothing beside the .glb */
    ck_assert_int_eq(validator_errors(out), 0);
    ck_assert_int_eq(dead_bytes(out), 0);
    char *script = strf(JS_IMAGES_AGAINST("%s/in/tex dir/a.png", "%s/shared/b.png"), dir, dir);
    char *facts = node_eval(dir, script, out);
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
    resurf_scene *s = load_ok(path);
    add_one_level(s);
    char *outdir = tu_path(dir, "out"), *out = tu_path(dir, "out/t.gltf");
    ck_assert_int_eq(mkdir(outdir, 0777), 0);
    resurf_scene_save_report r;
    save_ok(s, out, NULL, &r);
    ck_assert_uint_eq(r.files, 4); /* .gltf, .bin, two images */
    ck_assert_int_eq(tu_count_entries(dir), 3); /* in, shared, out: nothing new beside them */
    char *shared = tu_path(dir, "shared");
    ck_assert_int_eq(tu_count_entries(shared), 1);
    ck_assert_int_eq(validator_errors(out), 0);
    ck_assert_int_eq(dead_bytes(out), 0);
    char *script = strf(JS_IMAGES_AGAINST("%s/in/tex dir/a.png", "%s/shared/b.png"), dir, dir);
    char *facts = node_eval(dir, script, out);
    ck_assert_str_eq(facts, "tex%20dir/a.png:same b.png:same");
    free(facts);
    resurf_scene_save_options o = resurf_scene_save_options_default();
    o.embed_buffers = 1;
    char *embedded = tu_path(dir, "out/e.gltf");
    save_ok(s, embedded, &o, NULL);
    ck_assert_int_eq(validator_errors(embedded), 0);
    ck_assert_int_eq(dead_bytes(embedded), 0);
    facts = node_eval(dir, script, embedded);
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
    char *want = strf("%s: images[0]: the image '%s/in/gone/not-here.png' (uri 'gone%%2Fnot-here.png') cannot be "
                      "read: ", path, dir);
    ck_assert_msg(!strncmp(msg, want, strlen(want)), "message: %s", msg);
    ck_assert_ptr_null(strchr(msg, '\n'));
    resurf_load_options lo = resurf_load_options_default();
    lo.allow_missing_images = 1;
    ck_assert_int_eq(resurf_scene_load(path, &lo, &s, &e), RESURF_OK);
    ck_assert_uint_eq(resurf_scene_warning_count(s), 1);
    ck_assert_ptr_nonnull(strstr(resurf_scene_warning(s, 0), "images[0]: the image"));
    char *out = tu_path(dir, "t.glb");
    save_ok(s, out, NULL, NULL);
    char *facts = node_eval(dir, JS_LOAD "console.log(doc.images[0].uri,doc.images[1].mimeType)", out);
    ck_assert_str_eq(facts, "gone%2Fnot-here.png image/png");
    free(facts);
    resurf_scene_free(s);

    char *cmd = strf("'%s' lod '%s' -o '%s/c.glb' --levels 0.5 2>&1", RESURF_CLI, path, dir), *text = NULL;
    ck_assert_int_eq(tu_run(cmd, &text), 1);
    ck_assert_msg(strstr(text, "images[0]") && strstr(text, path) && strchr(text, '\n') == text + strlen(text) - 1,
                  "%s", text);
    free(text);
    free(cmd);
    cmd = strf("'%s' lod '%s' -o '%s/c.glb' --levels 0.5 --allow-missing-images 2>&1", RESURF_CLI, path, dir);
    ck_assert_int_eq(tu_run(cmd, &text), 0);
    ck_assert_ptr_nonnull(strstr(text, "resurf: warning: images[0]"));
    free(text);
    free(cmd);
    /* A uri that names no file of the folder (a scheme, an encoded NUL) is refused without being tried. */
    static const char *const foreign[] = {"http://example.com/a.png", "x%00.png", "C:\\\\a.png"};
    for (int k = 0; k < 3; ++k) {
        char *sub = strf("%s/h%d", dir, k);
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
    bytes b = tetra_bin();
    const char *json = "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_materials_unlit\"],\"scene\":0,"
                       "\"scenes\":[{\"nodes\":[0,1]},{}],\"nodes\":[{\"mesh\":0},{}],"
                       "\"materials\":[{\"extensions\":{\"KHR_materials_unlit\":{}},\"extras\":{}}],"
                       "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,\"material\":0}]}],"
                       "\"accessors\":[" TETRA_ACCESSORS "],\"bufferViews\":[" TETRA_VIEWS "],"
                       "\"buffers\":[{\"byteLength\":72,\"uri\":\"e.bin\"}]}";
    char *path = write_gltf(dir, "e", json, &b);
    resurf_scene *s = load_ok(path);
    char *out = tu_path(dir, "out.gltf");
    save_ok(s, out, NULL, NULL);
    char *text = tu_read_file(out, NULL);
    ck_assert_ptr_null(strstr(text, "null"));
    ck_assert_int_eq(validator_errors(out), 0);
    char *facts = node_eval(dir, JS_LOAD "const empty=x=>typeof x==='object'&&x!==null&&Object.keys(x).length===0;"
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
    bytes b = tetra_bin();
    for (int i = 0; i < 16; ++i) /* 72..87: a bufferView nothing uses */
        put_u8(&b, 0xEE);
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},"
        "\"extensionsUsed\":[\"FB_ngon_encoding\",\"EXT_resurf_unknown\",\"KHR_materials_variants\"],"
        "\"extensions\":{\"KHR_materials_variants\":{\"variants\":[{\"name\":\"plain\"}]}},"
        "\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],\"materials\":[{\"name\":\"m\"}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,\"extensions\":{"
        "\"FB_ngon_encoding\":{},\"EXT_resurf_unknown\":{\"view\":2},"
        "\"KHR_materials_variants\":{\"mappings\":[{\"material\":0,\"variants\":[0]}]}}}]}],"
        "\"accessors\":[" TETRA_ACCESSORS "],\"bufferViews\":[" TETRA_VIEWS ",{\"buffer\":0,\"byteOffset\":72,"
        "\"byteLength\":16}],\"buffers\":[{\"byteLength\":88,\"uri\":\"n.bin\"}]}";
    char *path = write_gltf(dir, "n", json, &b);
    ck_assert_int_eq(dead_bytes(path), 16);
    resurf_scene *s = load_ok(path);
    ck_assert_uint_eq(resurf_scene_warning_count(s), 2);
    ck_assert_ptr_nonnull(strstr(resurf_scene_warning(s, 0), "EXT_resurf_unknown is dropped from the 1"));
    ck_assert_ptr_nonnull(strstr(resurf_scene_warning(s, 1), "FB_ngon_encoding is dropped from the 1"));
    add_one_level(s);
    for (int draco = 0; draco < 2; ++draco) {
        char *out = strf("%s/out%d.glb", dir, draco);
        resurf_scene_save_options o = resurf_scene_save_options_default();
        o.draco = draco;
        resurf_scene_save_report r;
        save_ok(s, out, &o, &r);
        ck_assert_uint_eq(r.dropped_extensions, 2);
        ck_assert_int_eq(validator_errors(out), 0);
        ck_assert_int_eq(dead_bytes(out), 0);
        char *facts = node_eval(dir, JS_LOAD "console.log(doc.meshes.map(m=>Object.keys(m.primitives[0].extensions)"
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
    bytes b = tetra_bin(); /* 0..71 */
    for (int v = 0; v < 4; ++v) /* joints 72..87 */
        put_u8(&b, 0), put_u8(&b, 1), put_u8(&b, 0), put_u8(&b, 0);
    for (int v = 0; v < 4; ++v) /* weights 88..151 */
        put_f32(&b, 0.5f), put_f32(&b, 0.5f), put_f32(&b, 0), put_f32(&b, 0);
    for (int j = 0; j < 2; ++j) /* inverse bind matrices 152..279 */
        for (int i = 0; i < 16; ++i)
            put_f32(&b, i % 5 == 0 ? 1.0f : 0.0f);
    char *json = strf(
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
        "\"nodes\":[{\"mesh\":0,\"skin\":0,\"children\":[1]},{\"children\":[2]},{\"translation\":[0,1,0]}],"
        "\"skins\":[{\"joints\":[1,2],\"inverseBindMatrices\":4}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"JOINTS_0\":2,\"WEIGHTS_0\":3},\"indices\":1}]}],"
        "\"accessors\":[" TETRA_ACCESSORS ",{\"bufferView\":2,\"componentType\":5121,\"count\":4,\"type\":\"VEC4\"},"
        "{\"bufferView\":3,\"componentType\":5126,\"count\":4,\"type\":\"VEC4\"},"
        "{\"bufferView\":4,\"componentType\":5126,\"count\":2,\"type\":\"MAT4\"}],"
        "\"bufferViews\":[" TETRA_VIEWS ",{\"buffer\":0,\"byteOffset\":72,\"byteLength\":16},"
        "{\"buffer\":0,\"byteOffset\":88,\"byteLength\":64},{\"buffer\":0,\"byteOffset\":152,\"byteLength\":128}],"
        "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"skin.bin\"}]}",
        b.size);
    char *path = write_gltf(dir, "skin", json, &b);
    ck_assert_int_eq(validator_errors(path), 0);
    ck_assert_int_eq(validator_warnings(path), 0);
    resurf_scene *s = load_ok(path);
    add_one_level(s);
    char *out = tu_path(dir, "out.glb");
    save_ok(s, out, NULL, NULL);
    ck_assert_int_eq(validator_errors(out), 0);
    ck_assert_int_eq(validator_warnings(out), 0);
    char *facts = node_eval(dir, JS_LOAD "const n=doc.nodes[0];const l=doc.nodes[n.extensions.MSFT_lod.ids[0]];"
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
    char *morphed = strf("%.*s\"targets\":[{\"POSITION\":0}],%s", (int)(at - text), text, at);
    char *morph_path = tu_path(dir, "in/morph.gltf");
    ck_assert_int_eq(tu_write_file(morph_path, morphed, strlen(morphed)), 0);
    char *cmd = strf("'%s' info '%s' --json > '%s/info.json'", RESURF_CLI, morph_path, dir), *out = NULL;
    ck_assert_msg(tu_run(cmd, &out) == 0, "%s", out);
    char *json = tu_path(dir, "info.json");
    char *facts = node_eval(dir, "const d=JSON.parse(require('fs').readFileSync(process.argv[2])).scene;"
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
    cmd = strf("'%s' info '%s'", RESURF_CLI, morph_path);
    ck_assert_int_eq(tu_run(cmd, &out), 0);
    ck_assert_msg(strstr(out, "    primitives[0]: triangles 4, vertices 4, mode 4, material 0, attributes POSITION, "
                              "TEXCOORD_0, targets 1, target_attributes POSITION\n") &&
                      strstr(out, "  images[1]: uri ../shared/b.png, mimeType image/png, bytes 71\n"),
                  "%s", out);
    free(out);
    free(cmd);
    /* A .drc: one mesh, its triangles. */
    char *drc = tu_path(dir, "t.drc");
    cmd = strf("'%s' lod '%s' -o '%s' --layout files --levels 0.5 > /dev/null && '%s' info '%s/t_lod0.drc' --json",
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

Suite *make_suite(void)
{
    Suite *s = suite_create("gltf");
    TCase *round = tcase_create("roundtrip");
    tcase_add_test(round, gltf_roundtrip_plain_is_float_exact);
    tcase_add_test(round, gltf_roundtrip_draco_within_quantization);
    tcase_add_test(round, gltf_draco_payload_decodes_with_draco_decoder);
    tcase_add_test(round, gltf_mesh_file_is_a_scene);
    suite_add_tcase(s, round);
    TCase *read = tcase_create("read");
    tcase_add_test(read, gltf_strips_and_fans_become_lists);
    tcase_add_test(read, gltf_sparse_and_normalized_components);
    tcase_add_test(read, gltf_mesh_quantization_input);
    tcase_add_test(read, gltf_instanced_mesh_is_handled_once);
    tcase_add_test(read, gltf_skinned_primitive_keeps_joints_and_weights);
    tcase_add_test(read, gltf_morph_targets_and_points_pass_through);
    tcase_add_test(read, gltf_keeps_everything_else);
    tcase_add_test(read, gltf_draco_input_decodes);
    tcase_add_test(read, gltf_load_memory_reads_what_was_saved);
    tcase_add_test(read, gltf_load_memory_refuses_external_files);
    suite_add_tcase(s, read);
    TCase *lod = tcase_create("lod");
    tcase_add_test(lod, gltf_msft_lod_structure);
    tcase_add_test(lod, gltf_files_layout_one_file_per_level);
    tcase_add_test(lod, gltf_side_by_side_layout);
    tcase_add_test(lod, gltf_set_lods_checks_levels);
    tcase_add_test(lod, gltf_cli_lod_writes_a_valid_chain);
    suite_add_tcase(s, lod);
    TCase *hostile = tcase_create("hostile");
    tcase_add_test(hostile, gltf_hostile_documents_fail_cleanly);
    tcase_add_test(hostile, gltf_hostile_draco_fails_cleanly);
    tcase_add_test(hostile, gltf_hostile_glb_container);
    tcase_add_test(hostile, gltf_fuzz_findings_fail_with_their_messages);
    tcase_add_test(hostile, gltf_save_failures_write_nothing);
    suite_add_tcase(s, hostile);
    TCase *whole = tcase_create("self-contained");
    tcase_add_test(whole, gltf_glb_embeds_external_images);
    tcase_add_test(whole, gltf_gltf_copies_or_embeds_external_images);
    tcase_add_test(whole, gltf_missing_image_is_an_error);
    tcase_add_test(whole, gltf_empty_objects_stay_empty);
    tcase_add_test(whole, gltf_triangulation_extensions_dropped_no_dead_bytes);
    tcase_add_test(whole, gltf_skinned_node_keeps_its_place);
    tcase_add_test(whole, gltf_cli_info_describes_scenes);
    suite_add_tcase(s, whole);
    return s;
}

RESURF_TEST_MAIN()
