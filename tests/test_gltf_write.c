/* Tests of writing glTF (src/scene_save.c and the glTF/Draco shims in src/io/): round trips of analytic meshes
 * through .gltf/.glb/.drc with and without Draco, from files and from memory, the level-of-detail layouts (MSFT_lod,
 * one file per level, side by side) and `resurf lod`, and saves that fail without leaving anything.
 *
 * Independent checks: the Khronos glTF validator (tools/validate-gltf.js, npm gltf-validator) on every file written,
 * Google's draco_decoder on Draco output, and small node scripts that read the written JSON for structure the
 * validator does not check (MSFT_lod). */
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "testutil.h"

/* ---- helpers ------------------------------------------------------------------------------------------------- */

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
        tu_save_scene_ok(s, path, &o, NULL);
        ck_assert_int_eq(tu_validator_errors(path), 0);
        resurf_scene *t = tu_load_scene_ok(path);
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
        tu_save_scene_ok(s, path, &o, &rep);
        ck_assert_uint_eq(rep.levels, 1);
        ck_assert_uint_eq(rep.level_triangles[0], m->triangle_count);
        ck_assert_uint_gt(rep.level_bytes[0], 0);
        if (f < 2)
            ck_assert_int_eq(tu_validator_errors(path), 0);
        resurf_scene *t = tu_load_scene_ok(path);
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
    char *cmd = tu_strf("draco_decoder -i '%s' -o '%s'", drc, obj), *out = NULL;
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
    tu_save_scene_ok(s, glb, &o, NULL);
    char *script = tu_strf(TU_JS_LOAD "const p=doc.meshes[0].primitives[0];const v=doc.bufferViews[p.extensions."
                        "KHR_draco_mesh_compression.bufferView];const bin=20+b.readUInt32LE(12)+8;"
                        "fs.writeFileSync('%s',b.slice(bin+(v.byteOffset||0),bin+(v.byteOffset||0)+v.byteLength));"
                        "console.log(doc.accessors[p.indices].count/3, doc.accessors[p.attributes.POSITION].count,"
                        "doc.extensionsRequired.join(','))",
                        drc);
    char *facts = tu_node_eval(dir, script, glb);
    char *cmd = tu_strf("draco_decoder -i '%s' -o '%s'", drc, obj), *out = NULL;
    ck_assert_msg(tu_run(cmd, &out) == 0, "draco_decoder failed: %s", out);
    resurf_mesh *d = NULL;
    ck_assert_int_eq(resurf_mesh_load(obj, NULL, &d, NULL), RESURF_OK);
    ck_assert_uint_eq(d->triangle_count, m->triangle_count);
    char *expect = tu_strf("%zu %zu KHR_draco_mesh_compression", m->triangle_count, m->vertex_count);
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
    resurf_scene *s = tu_load_scene_ok(ply);
    ck_assert_uint_eq(resurf_scene_mesh_count(s), 1);
    ck_assert_uint_eq(resurf_scene_primitive_count(s), 1);
    resurf_scene_primitive info;
    ck_assert_int_eq(resurf_scene_primitive_info(s, 0, &info, NULL), RESURF_OK);
    ck_assert_str_eq(info.name, "meshes[0].primitives[0]");
    ck_assert_int_eq(info.kind, RESURF_PRIMITIVE_TRIANGLES);
    tu_save_scene_ok(s, glb, NULL, NULL);
    ck_assert_int_eq(tu_validator_errors(glb), 0);
    resurf_scene *t = tu_load_scene_ok(glb);
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

/* From memory: a .glb, a .gltf with its buffer in a data: URI and a .drc written by the library,
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
        tu_save_scene_ok(s, path, &o, NULL);
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
        char *out = tu_strf("%s/lod%d.gltf", dir, draco);
        resurf_scene_save_options o = resurf_scene_save_options_default();
        o.draco = draco;
        resurf_scene_save_report r;
        tu_save_scene_ok(s, out, &o, &r);
        ck_assert_uint_eq(r.levels, 3);
        for (int k = 0; k < 3; ++k) {
            ck_assert_uint_eq(r.level_triangles[k], levels[k]->triangle_count);
            ck_assert_uint_gt(r.level_bytes[k], 0);
        }
        ck_assert_uint_gt(r.level_bytes[0], r.level_bytes[1]);
        ck_assert_uint_gt(r.level_bytes[1], r.level_bytes[2]);
        ck_assert_int_eq(tu_validator_errors(out), 0);
        /* The spec's structure: the extension on the full-detail node, ids of nodes that are in no scene, one
         * coverage value more than ids, and each id's mesh has that level's triangles. */
        char *facts = tu_node_eval(dir, TU_JS_LOAD
                                "const sc=doc.scenes[doc.scene].nodes;const n=doc.nodes[sc[0]];"
                                "const ids=n.extensions.MSFT_lod.ids;const inScene=ids.some(i=>doc.scenes.some(s=>s.nodes.includes(i)));"
                                "const tri=i=>{const p=doc.meshes[doc.nodes[i].mesh].primitives[0];return doc.accessors[p.indices].count/3;};"
                                "console.log(sc.length,ids.length,inScene,n.extras.MSFT_screencoverage.join(','),"
                                "tri(sc[0]),ids.map(tri).join(','),doc.extensionsUsed.includes('MSFT_lod'),"
                                "(doc.extensionsRequired||[]).includes('MSFT_lod'))",
                                out);
        char *want = tu_strf("1 2 false 0.4,0.1,0.01 %zu %zu,%zu true false", levels[0]->triangle_count,
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
    tu_save_scene_ok(s, out, &o, &r);
    ck_assert_uint_eq(r.files, 3);
    ck_assert_int_eq(tu_count_entries(dir), 3);
    for (unsigned k = 0; k < 3; ++k) {
        char name[512];
        resurf_scene_level_path(name, sizeof name, out, k);
        char *want = tu_strf("%s/ball_lod%u.glb", dir, k);
        ck_assert_str_eq(name, want);
        free(want);
        ck_assert_int_eq(tu_validator_errors(name), 0);
        resurf_scene *t = tu_load_scene_ok(name);
        ck_assert_uint_eq(resurf_scene_primitive_mesh(t, 0)->triangle_count, levels[k]->triangle_count);
        resurf_scene_free(t);
    }
    /* One level alone as a plain scene. */
    char *one = tu_path(dir, "level1.gltf");
    o.level = 1;
    o.draco = false;
    tu_save_scene_ok(s, one, &o, NULL);
    resurf_scene *t = tu_load_scene_ok(one);
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
    tu_save_scene_ok(s, out, &o, NULL);
    ck_assert_int_eq(tu_validator_errors(out), 0);
    /* Three roots: the original and one group per level, moved by k × width × 1.25 along x (width 2: a unit
     * sphere with vertices on it, up to the extremes the mesh reaches). */
    double lo[3], hi[3];
    resurf_mesh_bounds(levels[0], lo, hi);
    char *facts = tu_node_eval(dir, TU_JS_LOAD "const sc=doc.scenes[0].nodes;"
                                         "console.log(sc.length, sc.slice(1).map(i=>doc.nodes[i].translation[0].toFixed(6)).join(','))",
                            out);
    char *want = tu_strf("3 %.6f,%.6f", (hi[0] - lo[0]) * 1.25, 2 * (hi[0] - lo[0]) * 1.25);
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

/* The CLI: `resurf lod` on a mesh file writes a Draco MSFT_lod chain that validates, and its JSON table gives
 * each level's triangles (at most the ratio asked for) and bytes. */
START_TEST(gltf_cli_lod_writes_a_valid_chain)
{
    char *dir = tu_tempdir();
    resurf_mesh *m = shape_mesh(SHAPE_TORUS, 4000, 0.2, 5, 1);
    char *ply = tu_path(dir, "torus.ply"), *glb = tu_path(dir, "torus.glb");
    ck_assert_int_eq(resurf_mesh_save(m, ply, NULL, NULL), RESURF_OK);
    char *cmd = tu_strf("'%s' lod '%s' -o '%s' --levels 0.5,0.2 --json", RESURF_CLI, ply, glb), *out = NULL;
    ck_assert_msg(tu_run(cmd, &out) == 0, "resurf lod failed: %s", out);
    ck_assert_int_eq(tu_validator_errors(glb), 0);
    /* The JSON table, read back with node. */
    char *json = tu_path(dir, "table.json");
    ck_assert_int_eq(tu_write_file(json, out, strlen(out)), 0);
    char *facts = tu_node_eval(dir, "const t=JSON.parse(require('fs').readFileSync(process.argv[2]));"
                                 "console.log(t.draco,t.layout,t.levels.length,"
                                 "t.levels.map(l=>l.triangles<=Math.floor(l.ratio*t.levels[0].triangles)+1).join(','),"
                                 "t.levels.every(l=>l.bytes>0),t.levels[2].error_rel>0)",
                            json);
    ck_assert_str_eq(facts, "true msft_lod 3 true,true,true true true");
    char *lods = tu_node_eval(dir, TU_JS_LOAD "console.log(doc.nodes[0].extensions.MSFT_lod.ids.length,"
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

/* ---- failures ------------------------------------------------------------------------------------------------ */

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

/* Whole numbers are written as integers ("1", not "1.0": the same JSON number, shorter); -0.0 keeps its sign and
 * extras stay as the source wrote them. The values read back are the source's. */
START_TEST(gltf_whole_numbers_are_written_as_integers)
{
    char *dir = tu_tempdir();
    tu_bytes b = tu_tetra_bin();
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
        "\"nodes\":[{\"mesh\":0,\"matrix\":[1.0,0.0,0.0,0.0,0.0,1.0,0.0,0.0,0.0,0.0,1.0,0.0,2.5,-0.0,3.0,1.0],"
        "\"extras\":{\"k\":[1.0,2.0]}}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,\"material\":0}]}],"
        "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[1.0,0.5,0.0,1.0],\"roughnessFactor\":0.0}}],"
        "\"accessors\":[" TU_TETRA_ACCESSORS "],\"bufferViews\":[" TU_TETRA_VIEWS "],"
        "\"buffers\":[{\"byteLength\":72,\"uri\":\"whole.bin\"}]}";
    char *path = tu_write_gltf(dir, "whole", json, &b);
    resurf_scene *s = tu_load_scene_ok(path);
    char *out = tu_strf("%s/out.glb", dir);
    tu_save_scene_ok(s, out, NULL, NULL);
    size_t size = 0;
    char *bytes = tu_read_file(out, &size);
    ck_assert(bytes && size > 20);
    uint32_t length = (uint32_t)(unsigned char)bytes[12] | (uint32_t)(unsigned char)bytes[13] << 8 |
                      (uint32_t)(unsigned char)bytes[14] << 16 | (uint32_t)(unsigned char)bytes[15] << 24;
    ck_assert_uint_le(20 + (size_t)length, size);
    char *text = tu_strf("%.*s", (int)length, bytes + 20);
    ck_assert_msg(strstr(text, "\"matrix\":[1,0,0,0,0,1,0,0,0,0,1,0,2.5,-0.0,3,1]"), "%s", text);
    ck_assert_msg(strstr(text, "\"baseColorFactor\":[1,0.5,0,1]"), "%s", text);
    ck_assert_msg(strstr(text, "\"roughnessFactor\":0"), "%s", text);
    ck_assert_msg(strstr(text, "\"max\":[1,1,1]") && strstr(text, "\"min\":[-1,-1,-1]"), "%s", text);
    ck_assert_msg(strstr(text, "\"k\":[1.0,2.0]"), "extras changed: %s", text);
    size_t fractions = 0; /* "X.0" before a ',' or ']': only -0.0 and the extras' two may be left */
    for (const char *at = text; (at = strstr(at, ".0")); at += 2)
        fractions += at[2] == ',' || at[2] == ']';
    ck_assert_msg(fractions == 3, "%zu whole numbers written with a fraction: %s", fractions, text);
    ck_assert_int_eq(tu_validator_errors(out), 0);
    free(text);
    free(bytes);
    free(out);
    resurf_scene_free(s);
    free(path);
    free(b.data);
    tu_rmtree(dir);
    free(dir);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("gltf_write");
    TCase *round = tcase_create("roundtrip");
    tcase_add_test(round, gltf_roundtrip_plain_is_float_exact);
    tcase_add_test(round, gltf_roundtrip_draco_within_quantization);
    tcase_add_test(round, gltf_draco_payload_decodes_with_draco_decoder);
    tcase_add_test(round, gltf_mesh_file_is_a_scene);
    tcase_add_test(round, gltf_load_memory_reads_what_was_saved);
    tcase_add_test(round, gltf_whole_numbers_are_written_as_integers);
    suite_add_tcase(s, round);
    TCase *lod = tcase_create("lod");
    tcase_add_test(lod, gltf_msft_lod_structure);
    tcase_add_test(lod, gltf_files_layout_one_file_per_level);
    tcase_add_test(lod, gltf_side_by_side_layout);
    tcase_add_test(lod, gltf_set_lods_checks_levels);
    tcase_add_test(lod, gltf_cli_lod_writes_a_valid_chain);
    suite_add_tcase(s, lod);
    TCase *failures = tcase_create("failures");
    tcase_add_test(failures, gltf_save_failures_write_nothing);
    suite_add_tcase(s, failures);
    return s;
}

RESURF_TEST_MAIN()
