/* libFuzzer harness for the scene loaders from memory; FUZZ_SCENE_FORMAT picks which (RESURF_SCENE_FORMAT_GLTF,
 * _GLB, _DRC). No input may crash, hang, read outside its bytes or the file system, or allocate beyond what its size
 * justifies (ASan and libFuzzer's -rss_limit_mb catch that). A scene that loads must keep the loader's promises:
 * every primitive's mesh has its indices in range, finite positions, attribute arrays as long as their counts say,
 * and passes validation, and its description (resurf_scene_describe) is as long as it says. A refusal must carry a
 * parse, unsupported or limit status and a one-line message. A morphed primitive's mesh carries its targets as
 * extras of 1 to 4 finite components ("targets[t].NAME"), and a small one goes through resurf_scene_build_lods (the
 * morph path of the simplifier and its cost): every level keeps every target extra. A skinned one's levels keep
 * their influences valid (weights summing to 1) wherever the original's are.
 * A broken promise traps, so libFuzzer keeps the input. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "resurf/resurf.h"
#include "scene_internal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static volatile double sink; /* keeps the loads of every value from being optimised away */

#define REQUIRE(cond)                                                                                           \
    do {                                                                                                        \
        if (!(cond))                                                                                            \
            __builtin_trap();                                                                                   \
    } while (0)

/* Sums every value of the mesh (so that ASan sees an array shorter than its count) after checking the promises. */
static double check_mesh(const resurf_mesh *m)
{
    for (size_t i = 0; i < 3 * m->triangle_count; ++i)
        REQUIRE(m->indices[i] < m->vertex_count);
    for (size_t i = 0; i < 3 * m->vertex_count; ++i)
        REQUIRE(isfinite(m->positions[i]));
    double sum = 0;
    for (size_t i = 0; m->normals && i < 3 * m->vertex_count; ++i)
        sum += m->normals[i];
    for (unsigned k = 0; k < m->texcoord_count; ++k)
        for (size_t i = 0; m->texcoords[k] && i < 2 * m->vertex_count; ++i)
            sum += m->texcoords[k][i];
    for (size_t i = 0; m->colors && i < 4 * m->vertex_count; ++i)
        sum += m->colors[i];
    for (size_t e = 0; e < m->extra_count; ++e)
        for (size_t i = 0; i < m->extras[e].components * m->vertex_count; ++i)
            sum += m->extras[e].data[i];
    resurf_validate_report v;
    REQUIRE(resurf_mesh_validate(m, &v, NULL) == RESURF_OK);
    REQUIRE(resurf_validation_ok(&v));
    REQUIRE(v.vertex_count == m->vertex_count && v.triangle_count == m->triangle_count);
    return sum;
}

/* A morphed primitive's target extras: present, 1 to 4 components, finite. Returns how many. */
static size_t check_targets(const resurf_mesh *m)
{
    size_t n = 0, len = strlen(RESURF_MORPH_TARGET_PREFIX);
    for (size_t e = 0; e < m->extra_count; ++e) {
        if (strncmp(m->extras[e].name, RESURF_MORPH_TARGET_PREFIX, len))
            continue;
        REQUIRE(m->extras[e].components >= 1 && m->extras[e].components <= 4);
        for (size_t i = 0; i < m->extras[e].components * m->vertex_count; ++i)
            REQUIRE(isfinite(m->extras[e].data[i]));
        ++n;
    }
    return n;
}

/* The extra named NAME of m, or NULL. */
static const resurf_attribute *extra_named(const resurf_mesh *m, const char *name)
{
    for (size_t e = 0; e < m->extra_count; ++e)
        if (!strcmp(m->extras[e].name, name))
            return &m->extras[e];
    return NULL;
}

/* Skin influences (JOINTS_n / WEIGHTS_n, VEC4, n = 0..3): when every vertex of the original has finite joints and
 * finite non-negative weights with a positive total over its sets, every vertex of each level has finite whole
 * joints and non-negative weights summing to 1 (within float rounding): the levels combine influences, never
 * numbers (src/skin.c). A broken original may have its values copied through, so nothing is asserted then. */
static void check_skin_levels(const resurf_mesh *original, resurf_mesh *const *levels, size_t level_count)
{
    const resurf_attribute *oj[4], *ow[4];
    unsigned sets = 0;
    for (unsigned n = 0; n < 4; ++n) {
        char jn[16], wn[16];
        snprintf(jn, sizeof jn, "JOINTS_%u", n);
        snprintf(wn, sizeof wn, "WEIGHTS_%u", n);
        oj[sets] = extra_named(original, jn), ow[sets] = extra_named(original, wn);
        if (oj[sets] && ow[sets] && oj[sets]->components == 4 && ow[sets]->components == 4)
            ++sets;
    }
    if (!sets)
        return;
    for (size_t v = 0; v < original->vertex_count; ++v) {
        double total = 0;
        for (unsigned s = 0; s < sets; ++s)
            for (size_t k = 0; k < 4; ++k) {
                double j = oj[s]->data[4 * v + k], w = ow[s]->data[4 * v + k];
                if (!isfinite(j) || !isfinite(w) || w < 0)
                    return;
                total += w;
            }
        if (!(total > 0))
            return;
    }
    for (size_t l = 0; l < level_count; ++l) {
        const resurf_mesh *m = levels[l];
        for (unsigned s = 0; s < sets; ++s)
            REQUIRE(extra_named(m, oj[s]->name) && extra_named(m, ow[s]->name));
        for (size_t v = 0; v < m->vertex_count; ++v) {
            double total = 0;
            for (unsigned s = 0; s < sets; ++s) {
                const float *j = extra_named(m, oj[s]->name)->data + 4 * v, *w = extra_named(m, ow[s]->name)->data + 4 * v;
                for (int k = 0; k < 4; ++k) {
                    REQUIRE(isfinite(j[k]) && j[k] == floorf(j[k]) && isfinite(w[k]) && w[k] >= 0);
                    total += w[k];
                }
            }
            REQUIRE(fabs(total - 1) <= 1e-5);
        }
    }
}

/* Levels of the scene's small morphed primitives: each level carries the same target extras. */
static void morph_levels(resurf_scene *scene)
{
    size_t n = resurf_scene_primitive_count(scene), triangles = 0;
    for (size_t i = 0; i < n; ++i) {
        resurf_scene_primitive info;
        resurf_scene_primitive_info(scene, i, &info, NULL);
        const resurf_mesh *m = resurf_scene_primitive_mesh(scene, i);
        if (m)
            triangles += m->triangle_count;
        if (info.kind == RESURF_PRIMITIVE_MORPHED)
            REQUIRE(check_targets(m) > 0);
    }
    if (triangles > 4096)
        return; /* the fuzzer's time goes to the loader */
    resurf_simplify_options so = resurf_simplify_options_default();
    so.threads = 1;
    so.measure_samples = 0;
    const double ratio = 0.5;
    resurf_status s = resurf_scene_build_lods(scene, &ratio, 1, &so, NULL, NULL, NULL, NULL);
    REQUIRE(s == RESURF_OK || s == RESURF_ERR_INVALID_MESH || s == RESURF_ERR_LIMIT);
    for (size_t i = 0; s == RESURF_OK && i < n; ++i) {
        resurf_scene_primitive info;
        resurf_scene_primitive_info(scene, i, &info, NULL);
        const resurfi_scene_prim *p = &scene->prims[i];
        if (p->mesh && p->lod_count)
            check_skin_levels(p->mesh, p->lods, p->lod_count);
        if (info.kind != RESURF_PRIMITIVE_MORPHED)
            continue;
        for (size_t k = 0; k < p->lod_count; ++k) {
            check_mesh(p->lods[k]);
            REQUIRE(check_targets(p->lods[k]) == check_targets(p->mesh));
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    resurf_load_options options = resurf_load_options_default();
    options.max_triangles = 1u << 20;
    /* Odd sizes load leniently, so that documents the schema refuses still reach tinygltf and the index checks. */
    options.lenient = size & 1;
    resurf_scene *scene = NULL;
    resurf_error error;
    resurf_status s = resurf_scene_load_memory(data, size, FUZZ_SCENE_FORMAT, &options, &scene, &error);
    if (s != RESURF_OK) {
        REQUIRE(scene == NULL);
        REQUIRE(s == RESURF_ERR_PARSE || s == RESURF_ERR_UNSUPPORTED || s == RESURF_ERR_LIMIT);
        REQUIRE(error.status == s && error.message[0] && !strchr(error.message, '\n'));
        return 0;
    }
    REQUIRE(scene != NULL);
    double sum = 0;
    size_t n = resurf_scene_primitive_count(scene);
    for (size_t i = 0; i < n; ++i) {
        resurf_scene_primitive info;
        REQUIRE(resurf_scene_primitive_info(scene, i, &info, NULL) == RESURF_OK);
        REQUIRE(info.mesh < resurf_scene_mesh_count(scene));
        const resurf_mesh *m = resurf_scene_primitive_mesh(scene, i);
        REQUIRE((m == NULL) == (info.kind == RESURF_PRIMITIVE_OTHER));
        if (m)
            sum += check_mesh(m);
    }
    for (size_t i = 0; i < resurf_scene_warning_count(scene); ++i)
        REQUIRE(resurf_scene_warning(scene, i) != NULL && !strchr(resurf_scene_warning(scene, i), '\n'));
    /* resurf info's description, both forms: its length as promised, the text cut where dst ends. */
    for (int json = 0; json < 2; ++json) {
        size_t length = 0, again = 0;
        char small[64];
        REQUIRE(resurf_scene_describe(scene, json, small, sizeof small, &length, NULL) == RESURF_OK);
        REQUIRE(strlen(small) == (length < sizeof small ? length : sizeof small - 1));
        REQUIRE(resurf_scene_describe(scene, json, NULL, 0, &again, NULL) == RESURF_OK && again == length);
    }
    morph_levels(scene);
    resurf_scene_free(scene);
    sink = sum;
    return 0;
}
