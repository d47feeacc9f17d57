/* bench-draco: the size of resurf's Draco-compressed glTF against Google's Draco tools at equal quantization
 * (positions 14 bits, normals 10, texture coordinates 12, colours 8, other attributes 12; compression level 7, that
 * is encoder and decoder speed 3), in two tables:
 *
 * 1. draco_transcoder (Debian package draco): each analytic shape, and each MESH argument, as one mesh, written by
 *    resurf as a plain .gltf and as a Draco .glb; the transcoder compresses the plain one. Target: resurf's payload
 *    within 5% of the transcoder's.
 * 2. gltf-transform draco (npm @gltf-transform/cli 4.5, run under node), issue 20 item 10: every level resurf
 *    writes. For each input (analytic shapes, the bundled dragon scans, glTF assets of Debian's assimp-testmodels,
 *    and each FILE argument) resurf_scene_build_lods() builds the chain --levels (default 0.5,0.25,0.1, as
 *    `resurf lod`) with the default options; then each level alone (resurf_scene_save, level k, as
 *    `resurf lod --layout files` writes it) is saved as a Draco .glb and as a plain .glb, and
 *      gltf-transform draco PLAIN OUT --quantize-position 14 --quantize-normal 10 --quantize-texcoord 12
 *                    --quantize-color 8 --quantize-generic 12 --encode-speed 3 --decode-speed 3
 *    compresses the same geometry. The row "chain" does the same with the whole MSFT_lod file (`resurf lod`'s
 *    default output, every level in one file; gltf-transform does not know MSFT_lod and leaves the extension off,
 *    keeping the level nodes). tools/gltf-sizes.mjs splits each file: the Draco payload (the bufferViews that
 *    KHR_draco_mesh_compression refers to) and the whole file (JSON, images, padding). Target: resurf's payload
 *    within 10% of gltf-transform's (ratio <= 1.10) on every level, with the same primitives in Draco (resurf
 *    leaves primitives with morph targets uncompressed, gltf-transform does not: such a level misses); the whole
 *    file's ratio is printed beside it.
 *
 * usage: bench-draco [--check] [--levels R1,R2,...] [--gltf-transform CLI] [--models DIR] [--scans DIR]
 *                    [--only SUBSTRING] [--no-transcoder] [MESH-OR-GLTF ...]
 * --check exits 1 when a target is missed. Inputs of table 2 that are not installed are skipped with a note
 * (tools/bench-setup-assets.sh installs assimp-testmodels and @gltf-transform/cli). */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>

#include "shapes.h"
#include "bench.h"
#include "resurf/resurf.h"

#ifndef BENCH_SOURCE_ROOT
#define BENCH_SOURCE_ROOT "."
#endif

enum { MAX_ROWS = 256, MAX_INPUTS = 64 };

static const char tool[] = "bench-draco";
static const double target_transcoder = 1.05, target_gltf_transform = 1.10;

/* ---- table 1: draco_transcoder --------------------------------------------------------------------------------- */

/* Total size and BIN chunk size of a .glb (0 when it cannot be read). */
static void glb_sizes(const char *path, size_t *total, size_t *bin)
{
    *total = *bin = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return;
    unsigned char h[20];
    if (fread(h, 1, 20, f) == 20) {
        uint32_t json = (uint32_t)h[12] | (uint32_t)h[13] << 8 | (uint32_t)h[14] << 16 | (uint32_t)h[15] << 24;
        unsigned char c[4];
        if (fseek(f, 20 + (long)json, SEEK_SET) == 0 && fread(c, 1, 4, f) == 4)
            *bin = (uint32_t)c[0] | (uint32_t)c[1] << 8 | (uint32_t)c[2] << 16 | (uint32_t)c[3] << 24;
        fseek(f, 0, SEEK_END);
        *total = (size_t)ftell(f);
    }
    fclose(f);
}

typedef struct row {
    char name[64];
    size_t triangles, ours_total, ours_bin, theirs_total, theirs_bin;
    double ours_s, theirs_s;
} row;

/* Writes the mesh as plain .gltf and as Draco .glb with resurf, runs the transcoder on the plain one. */
static int measure(const resurf_mesh *mesh, const char *name, const char *dir, row *r)
{
    memset(r, 0, sizeof *r);
    snprintf(r->name, sizeof r->name, "%s", name);
    r->triangles = mesh->triangle_count;
    resurf_scene *scene = NULL;
    resurf_error e;
    if (resurf_scene_from_mesh(mesh, &scene, &e) != RESURF_OK) {
        fprintf(stderr, "bench-draco: %s: %s\n", name, e.message);
        return 1;
    }
    char plain[512], ours[512], theirs[512], cmd[2048];
    snprintf(plain, sizeof plain, "%s/plain.gltf", dir);
    snprintf(ours, sizeof ours, "%s/ours.glb", dir);
    snprintf(theirs, sizeof theirs, "%s/theirs.glb", dir);
    resurf_scene_save_options o = resurf_scene_save_options_default();
    int rc = 0;
    if (resurf_scene_save(scene, plain, &o, NULL, &e) != RESURF_OK)
        rc = 1;
    o.draco = true;
    double t0 = bench_now();
    if (!rc && resurf_scene_save(scene, ours, &o, NULL, &e) != RESURF_OK)
        rc = 1;
    r->ours_s = bench_now() - t0;
    if (rc)
        fprintf(stderr, "bench-draco: %s: %s\n", name, e.message);
    snprintf(cmd, sizeof cmd,
             "draco_transcoder -i '%s' -o '%s' -qp %d -qn %d -qt %d -qc %d -qg %d -qtg %d -qw %d >/dev/null 2>&1",
             plain, theirs, o.position_bits, o.normal_bits, o.texcoord_bits, o.color_bits, o.generic_bits,
             o.generic_bits, o.generic_bits);
    t0 = bench_now();
    if (!rc && system(cmd) != 0) {
        fprintf(stderr, "bench-draco: draco_transcoder failed on %s\n", name);
        rc = 1;
    }
    r->theirs_s = bench_now() - t0;
    glb_sizes(ours, &r->ours_total, &r->ours_bin);
    glb_sizes(theirs, &r->theirs_total, &r->theirs_bin);
    resurf_scene_free(scene);
    return rc;
}

/* Texture coordinates and colours on an analytic mesh, so that every quantized attribute kind is measured. */
static void add_uv_and_colors(resurf_mesh *m)
{
    m->texcoords[0] = malloc(m->vertex_count * 2 * sizeof(double));
    m->colors = malloc(m->vertex_count * 4 * sizeof(double));
    if (!m->texcoords[0] || !m->colors)
        exit(1);
    m->texcoord_count = 1;
    m->color_components = 3;
    for (size_t v = 0; v < m->vertex_count; ++v) {
        const double *p = m->positions + 3 * v;
        m->texcoords[0][2 * v] = 0.5 + 0.25 * p[0];
        m->texcoords[0][2 * v + 1] = 0.5 + 0.25 * p[1];
        for (int k = 0; k < 3; ++k)
            m->colors[4 * v + k] = 0.5 + 0.4 * p[k] / (1 + fabs(p[k]));
        m->colors[4 * v + 3] = 1;
    }
}


/* ---- table 2: gltf-transform draco, level by level -------------------------------------------------------------- */

typedef struct config {
    double ratios[RESURF_SCENE_MAX_LEVELS];
    size_t ratio_count;
    const char *gltf_transform, *models, *scans, *only;
    char sizes_script[1024];
} config;

/* Where a file's bytes go, as tools/gltf-sizes.mjs says. */
typedef struct split {
    double file, json, draco, images;
    size_t primitives;
} split;

typedef struct level_row {
    char input[48], level[12];
    size_t triangles;
    split r, g;
    double r_s, g_s; /* resurf's save, gltf-transform's run (node's start-up included) */
    char why[600];   /* why the row could not be measured */
} level_row;

/* A number after "key": in a JSON line (NAN when absent). */
static double json_number(const char *line, const char *key)
{
    char pattern[64];
    snprintf(pattern, sizeof pattern, "\"%s\":", key);
    const char *at = strstr(line, pattern);
    return at ? strtod(at + strlen(pattern), NULL) : NAN;
}

/* Splits two files with one node run; false when it failed. */
static bool split_files(const config *cfg, const char *a, const char *b, split *sa, split *sb)
{
    char cmd[4096], line[512];
    snprintf(cmd, sizeof cmd, "node '%s' '%s' && node '%s' '%s'", cfg->sizes_script, a, cfg->sizes_script, b);
    FILE *p = popen(cmd, "r");
    if (!p)
        return false;
    split *out[2] = {sa, sb};
    int got = 0;
    while (got < 2 && fgets(line, sizeof line, p)) {
        split *s = out[got++];
        s->file = json_number(line, "file");
        s->json = json_number(line, "json");
        s->draco = json_number(line, "draco");
        s->images = json_number(line, "images");
        double prims = json_number(line, "draco_primitives");
        s->primitives = isnan(prims) ? 0 : (size_t)prims;
    }
    return pclose(p) == 0 && got == 2 && !isnan(sa->draco) && !isnan(sb->draco);
}

static bool file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* Saves level (-1: the whole chain) as Draco and plain .glb, runs gltf-transform on the plain one, splits both. */
static void measure_level(const config *cfg, const resurf_scene *scene, int level, const char *dir, level_row *row)
{
    char ours[512], plain[512], theirs[512], log[512], cmd[4096];
    snprintf(ours, sizeof ours, "%s/ours.glb", dir);
    snprintf(plain, sizeof plain, "%s/plain.glb", dir);
    snprintf(theirs, sizeof theirs, "%s/theirs.glb", dir);
    snprintf(log, sizeof log, "%s/gltf-transform.log", dir);
    remove(theirs);
    resurf_scene_save_options o = resurf_scene_save_options_default();
    o.level = level;
    resurf_error e;
    if (resurf_scene_save(scene, plain, &o, NULL, &e) != RESURF_OK) {
        resurf_format_error(row->why, sizeof row->why, &e);
        return;
    }
    o.draco = true;
    double t0 = bench_now();
    if (resurf_scene_save(scene, ours, &o, NULL, &e) != RESURF_OK) {
        resurf_format_error(row->why, sizeof row->why, &e);
        return;
    }
    row->r_s = bench_now() - t0;
    snprintf(cmd, sizeof cmd,
             "'%s' draco '%s' '%s' --quantize-position %d --quantize-normal %d --quantize-texcoord %d "
             "--quantize-color %d --quantize-generic %d --encode-speed %d --decode-speed %d >'%s' 2>&1",
             cfg->gltf_transform, plain, theirs, o.position_bits, o.normal_bits, o.texcoord_bits, o.color_bits,
             o.generic_bits, 10 - o.compression_level, 10 - o.compression_level, log);
    t0 = bench_now();
    int rc = system(cmd);
    row->g_s = bench_now() - t0;
    if (rc != 0 || !file_exists(theirs)) {
        snprintf(row->why, sizeof row->why, "gltf-transform failed (log: %s)", log);
        return;
    }
    if (!split_files(cfg, ours, theirs, &row->r, &row->g))
        snprintf(row->why, sizeof row->why, "tools/gltf-sizes.mjs failed");
}

/* Builds the chain on scene and measures each level and the whole chain; returns the rows added. */
static size_t measure_scene(const config *cfg, resurf_scene *scene, const char *name, const char *dir,
                            level_row *rows, size_t room)
{
    resurf_scene_lod_report lr;
    resurf_error e;
    size_t n = 0;
    if (!room)
        return 0;
    if (resurf_scene_build_lods(scene, cfg->ratios, cfg->ratio_count, NULL, NULL, &lr, NULL, &e) != RESURF_OK) {
        level_row *row = &rows[n++];
        memset(row, 0, sizeof *row);
        snprintf(row->input, sizeof row->input, "%s", name);
        resurf_format_error(row->why, sizeof row->why, &e);
        return n;
    }
    for (int k = -1; k < (int)lr.levels && n < room; ++k) {
        if (k == -1 && lr.levels < 2)
            continue; /* no chain: level 0 alone is the whole file */
        level_row *row = &rows[n++];
        memset(row, 0, sizeof *row);
        snprintf(row->input, sizeof row->input, "%s", name);
        if (k < 0)
            snprintf(row->level, sizeof row->level, "chain");
        else
            snprintf(row->level, sizeof row->level, "%d", k);
        for (int j = k < 0 ? 0 : k; j <= (k < 0 ? (int)lr.levels - 1 : k); ++j)
            row->triangles += lr.level_triangles[j];
        measure_level(cfg, scene, k, dir, row);
    }
    return n;
}

static size_t measure_file(const config *cfg, const char *path, const char *name, const char *dir, level_row *rows,
                           size_t room)
{
    resurf_load_options lo = resurf_load_options_default();
    resurf_scene *scene = NULL;
    resurf_error e;
    if (resurf_scene_load(path, &lo, &scene, &e) != RESURF_OK) {
        memset(rows, 0, sizeof *rows);
        snprintf(rows->input, sizeof rows->input, "%s", name);
        resurf_format_error(rows->why, sizeof rows->why, &e);
        return 1;
    }
    size_t n = measure_scene(cfg, scene, name, dir, rows, room);
    resurf_scene_free(scene);
    return n;
}

static bool wanted(const config *cfg, const char *name)
{
    return !cfg->only || strstr(name, cfg->only);
}

static double ratio_of(double ours, double theirs)
{
    return theirs > 0 && !isnan(ours) ? ours / theirs : NAN;
}

/* Prints table 2; returns true when every measured level meets the target. */
static bool print_levels(const level_row *rows, size_t n)
{
    printf("\nDraco at equal quantization, level by level: resurf vs gltf-transform draco (--quantize-position 14 "
           "--quantize-normal 10\n--quantize-texcoord 12 --quantize-color 8 --quantize-generic 12 --encode-speed 3 "
           "--decode-speed 3)\n\n");
    printf("%-26s %5s %8s %5s %10s %10s %7s %10s %10s %7s %7s %7s %6s\n", "input", "level", "tris", "prims",
           "payload r", "payload g", "ratio", "file r", "file g", "ratio", "save r", "run g", "target");
    bool all = true;
    double worst = 0, worst_file = 0;
    size_t measured = 0, missed = 0;
    for (size_t i = 0; i < n; ++i) {
        const level_row *r = &rows[i];
        if (r->why[0]) {
            printf("%-26s %5s  not measured: %s\n", r->input, r->level, r->why);
            all = false;
            continue;
        }
        double pr = ratio_of(r->r.draco, r->g.draco), fr = ratio_of(r->r.file, r->g.file);
        /* A primitive that resurf leaves uncompressed (morph targets) and gltf-transform compresses makes the
         * payloads incomparable: the level misses the target. */
        bool same_primitives = r->r.primitives == r->g.primitives;
        bool met = pr <= target_gltf_transform && same_primitives;
        char prims[24];
        if (same_primitives)
            snprintf(prims, sizeof prims, "%zu", r->r.primitives);
        else
            snprintf(prims, sizeof prims, "%zu/%zu", r->r.primitives, r->g.primitives);
        all = all && met;
        ++measured;
        missed += !met;
        if (same_primitives && pr > worst)
            worst = pr;
        if (same_primitives && fr > worst_file)
            worst_file = fr;
        printf("%-26s %5s %8zu %5s %10.0f %10.0f %7.4f %10.0f %10.0f %7.4f %7.3f %7.3f %6s\n", r->input, r->level,
               r->triangles, prims, r->r.draco, r->g.draco, pr, r->r.file, r->g.file, fr, r->r_s, r->g_s,
               met ? "met" : "NOT");
    }
    printf("\nprims: triangle primitives in Draco (r/g when they differ: resurf leaves primitives with morph "
           "targets uncompressed);\npayload: the Draco bufferViews (bytes); file: the whole .glb (JSON, images, "
           "padding); r resurf, g gltf-transform;\nratio r/g; save r: resurf's Draco save (s), run g: "
           "gltf-transform's run with node's start-up (s).\n");
    printf("worst payload ratio %.4f, worst file ratio %.4f (where both compress the same primitives); target "
           "payload <= %.2f: %s (%zu of %zu rows missed it)\n", worst, worst_file, target_gltf_transform,
           all ? "met" : "NOT met", missed + (n - measured), n);
    return all;
}

static bool parse_ratios(const char *text, config *cfg)
{
    cfg->ratio_count = 0;
    for (const char *p = text; *p;) {
        char *end;
        double r = strtod(p, &end);
        if (end == p || !(r > 0 && r <= 1) || cfg->ratio_count == RESURF_SCENE_MAX_LEVELS - 1)
            return false;
        cfg->ratios[cfg->ratio_count++] = r;
        p = *end == ',' ? end + 1 : end;
        if (*end && *end != ',')
            return false;
    }
    return cfg->ratio_count > 0;
}

int main(int argc, char **argv)
{
    bool check = false, transcoder = true;
    config cfg = {.ratios = {0.5, 0.25, 0.1}, .ratio_count = 3,
                  .gltf_transform = BENCH_SOURCE_ROOT "/tools/node/node_modules/.bin/gltf-transform",
                  .models = "/usr/share/assimp/models/glTF2", .scans = BENCH_SOURCE_ROOT "/data/scans"};
    snprintf(cfg.sizes_script, sizeof cfg.sizes_script, "%s/tools/gltf-sizes.mjs", BENCH_SOURCE_ROOT);
    const char *files[MAX_INPUTS];
    size_t file_count = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        bool more = i + 1 < argc;
        if (!strcmp(a, "--check"))
            check = true;
        else if (!strcmp(a, "--no-transcoder"))
            transcoder = false;
        else if (!strcmp(a, "--levels") && more) {
            if (!parse_ratios(argv[++i], &cfg)) {
                fprintf(stderr, "%s: --levels wants ratios in (0, 1], comma-separated\n", tool);
                return 2;
            }
        } else if (!strcmp(a, "--gltf-transform") && more)
            cfg.gltf_transform = argv[++i];
        else if (!strcmp(a, "--models") && more)
            cfg.models = argv[++i];
        else if (!strcmp(a, "--scans") && more)
            cfg.scans = argv[++i];
        else if (!strcmp(a, "--only") && more)
            cfg.only = argv[++i];
        else if (a[0] == '-') {
            fprintf(stderr, "usage: %s [--check] [--levels R1,R2,...] [--gltf-transform CLI] [--models DIR] "
                            "[--scans DIR] [--only SUBSTRING] [--no-transcoder] [FILE ...]\n", tool);
            return 2;
        } else if (file_count < MAX_INPUTS)
            files[file_count++] = a;
    }
    char dir[] = "/tmp/resurf-bench-draco-XXXXXX";
    if (!mkdtemp(dir))
        return 1;
    int failed = 0;
    bool met = true;

    if (transcoder) {
        if (system("command -v draco_transcoder >/dev/null") != 0) {
            fprintf(stderr, "%s: draco_transcoder is not installed (Debian package 'draco')\n", tool);
            return 1;
        }
        row rows[MAX_INPUTS + 8];
        size_t n = 0;
        struct {
            shape_kind kind;
            size_t triangles;
            int uv;
        } shapes[] = {
            {SHAPE_SPHERE, 20000, 0}, {SHAPE_SPHERE, 200000, 0}, {SHAPE_TORUS, 50000, 1},
            {SHAPE_CUBIC, 50000, 1},  {SHAPE_SADDLE, 20000, 0},
        };
        for (size_t i = 0; i < sizeof shapes / sizeof *shapes; ++i) {
            resurf_mesh *m = shape_mesh(shapes[i].kind, shapes[i].triangles, 0.2, 1, 1);
            if (!m)
                return 1;
            if (shapes[i].uv)
                add_uv_and_colors(m);
            char name[64];
            snprintf(name, sizeof name, "%s%s", shape_name(shapes[i].kind), shapes[i].uv ? "+uv+rgb" : "");
            if (wanted(&cfg, name))
                failed |= measure(m, name, dir, &rows[n++]);
            resurf_mesh_free(m);
        }
        for (size_t i = 0; i < file_count; ++i) {
            const char *base = strrchr(files[i], '/');
            base = base ? base + 1 : files[i];
            if (strstr(base, ".gltf") || strstr(base, ".glb"))
                continue; /* scenes: table 2 only */
            resurf_mesh *m = NULL;
            resurf_error e;
            if (resurf_mesh_load(files[i], NULL, &m, &e) != RESURF_OK) {
                fprintf(stderr, "%s: %s: %s\n", tool, files[i], e.message);
                failed = 1;
                continue;
            }
            failed |= measure(m, base, dir, &rows[n++]);
            resurf_mesh_free(m);
        }
        printf("Draco at equal quantization (qp 14, qn 10, qt 12, qc 8, qg 12, level 7): resurf vs "
               "draco_transcoder\n\n");
        printf("%-22s %10s %12s %12s %8s %12s %12s %9s %9s\n", "mesh", "triangles", "payload", "transcoder",
               "ratio", ".glb", "transcoder", "resurf s", "transc. s");
        for (size_t i = 0; i < n; ++i) {
            const row *r = &rows[i];
            double ratio = r->theirs_bin ? (double)r->ours_bin / (double)r->theirs_bin : 0;
            met = met && ratio <= target_transcoder && ratio > 0;
            printf("%-22s %10zu %12zu %12zu %8.4f %12zu %12zu %9.3f %9.3f\n", r->name, r->triangles, r->ours_bin,
                   r->theirs_bin, ratio, r->ours_total, r->theirs_total, r->ours_s, r->theirs_s);
        }
        printf("\nratio = resurf's BIN chunk (the Draco payload) / the transcoder's; target <= %.2f\n",
               target_transcoder);
    }

    if (!file_exists(cfg.gltf_transform)) {
        fprintf(stderr, "%s: %s is missing: run tools/bench-setup-assets.sh (npm @gltf-transform/cli)\n", tool,
                cfg.gltf_transform);
        return 1;
    }
    static level_row levels[MAX_ROWS];
    size_t n = 0;
    struct {
        shape_kind kind;
        size_t triangles;
        int uv;
    } shapes[] = {{SHAPE_SPHERE, 20000, 0}, {SHAPE_TORUS, 50000, 1}, {SHAPE_CUBE, 20000, 1}};
    for (size_t i = 0; i < sizeof shapes / sizeof *shapes; ++i) {
        char name[64];
        snprintf(name, sizeof name, "%s-%zuk%s", shape_name(shapes[i].kind), shapes[i].triangles / 1000,
                 shapes[i].uv ? "+uv+rgb" : "");
        if (!wanted(&cfg, name))
            continue;
        resurf_mesh *m = shape_mesh(shapes[i].kind, shapes[i].triangles, 0.2, 1, 1);
        if (!m)
            return 1;
        if (shapes[i].uv)
            add_uv_and_colors(m);
        resurf_scene *scene = NULL;
        resurf_error e;
        if (resurf_scene_from_mesh(m, &scene, &e) != RESURF_OK)
            bench_fail(tool, name, &e);
        n += measure_scene(&cfg, scene, name, dir, levels + n, MAX_ROWS - n);
        resurf_scene_free(scene);
        resurf_mesh_free(m);
    }
    /* The bundled scans and the glTF assets: a textured box, a textured scene of many small textured meshes, a
     * scene of 34 primitives (and its Draco-compressed copy as input), a skinned mesh, a mesh with morph targets. */
    const char *scans[] = {"dragon-11k.ply", "dragon-48k.ply", "dragon-200k.ply"};
    const char *models[] = {"BoxTextured-glTF-Binary/BoxTextured.glb", "textureTransform/TextureTransformTest.gltf",
                            "ClearCoat-glTF/ClearCoatTest.gltf", "2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
                            "draco/2CylinderEngine.gltf", "simple_skin/simple_skin.gltf",
                            "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf"};
    for (int set = 0; set < 3; ++set) {
        size_t count = set == 0 ? sizeof scans / sizeof *scans : set == 1 ? sizeof models / sizeof *models
                                                                          : file_count;
        for (size_t i = 0; i < count && n < MAX_ROWS; ++i) {
            char path[1024], name[48];
            const char *base;
            if (set == 2) {
                snprintf(path, sizeof path, "%s", files[i]);
                base = strrchr(files[i], '/');
                base = base ? base + 1 : files[i];
            } else {
                snprintf(path, sizeof path, "%s/%s", set == 0 ? cfg.scans : cfg.models, set == 0 ? scans[i]
                                                                                               : models[i]);
                base = set == 0 ? scans[i] : models[i];
            }
            const char *slash = strrchr(base, '/');
            snprintf(name, sizeof name, "%s", slash ? slash + 1 : base);
            if (!wanted(&cfg, path))
                continue;
            if (!file_exists(path)) {
                fprintf(stderr, "%s: skipped %s: not installed (tools/bench-setup-assets.sh)\n", tool, path);
                continue;
            }
            n += measure_file(&cfg, path, name, dir, levels + n, MAX_ROWS - n);
        }
    }
    met = print_levels(levels, n) && met;

    char cmd[256];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "%s: could not remove %s\n", tool, dir);
    return failed || (check && !met) ? 1 : 0;
}
