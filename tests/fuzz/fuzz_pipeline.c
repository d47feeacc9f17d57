/* libFuzzer harness for the whole pipeline on small meshes: bytes → mesh → validate → repair → a smoothed copy
 * restored onto the original → simplification with inline restoration (when the library has it) → save → load
 * back. Each stage may refuse its input, but with a clean status and a message; what it accepts it must turn into
 * a mesh that the next stage can take (indices in range, finite positions), and a saved file must load back with
 * the same counts. A broken promise traps, so libFuzzer keeps the input.
 *
 * Two encodings of the input, chosen by the first byte, so that the fuzzer reaches geometry quickly:
 *   - bit 7 set: the rest is OBJ text (the loader's own checks come first, at most 64 triangles);
 *   - else a direct decoding into at most 32 vertices and 48 triangles (below), whose coordinates lie on a coarse
 *     grid so that coincident points, collinear corners, slivers, folds and non-manifold fans come up often. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "resurf/resurf.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

enum { MAX_VERTICES = 32, MAX_TRIANGLES = 48 };

/* A stage's promise was broken: stop here so that libFuzzer records the input. */
#define REQUIRE(cond)                                                                                           \
    do {                                                                                                        \
        if (!(cond))                                                                                            \
            __builtin_trap();                                                                                   \
    } while (0)

/* A failed call must say why. */
static void require_reason(resurf_status s, const resurf_error *e)
{
    REQUIRE(s != RESURF_ERR_INTERNAL);
    REQUIRE(e->status == s && e->message[0] && !strchr(e->message, '\n'));
}

/* Can the mesh go into every stage? Indices in range and finite positions. */
static int processable(const resurf_mesh *m)
{
    for (size_t i = 0; i < 3 * m->triangle_count; ++i)
        if (m->indices[i] >= m->vertex_count)
            return 0;
    for (size_t i = 0; i < 3 * m->vertex_count; ++i)
        if (!isfinite(m->positions[i]))
            return 0;
    return 1;
}

/* Layout of the direct decoding (after the first byte, whose low bits pick options):
 *   byte: vertex count 3 + b % 30;   byte: triangle count 1 + b % 48;
 *   3 bytes per vertex: coordinates (int8) / 8;
 *   3 bytes per triangle: corner indices b % vertex_count, except b >= 250 which points past the vertices.
 * Missing bytes read as 0, so every input decodes. */
static resurf_mesh *decode_mesh(const uint8_t *p, size_t n)
{
    size_t at = 0;
#define NEXT() (at < n ? p[at++] : (uint8_t)0)
    size_t nv = 3 + NEXT() % (MAX_VERTICES - 2), nt = 1 + NEXT() % MAX_TRIANGLES;
    resurf_mesh *m = NULL;
    if (resurf_mesh_create(nv, nt, 0, &m, NULL) != RESURF_OK)
        return NULL;
    for (size_t i = 0; i < 3 * nv; ++i)
        m->positions[i] = (double)(int8_t)NEXT() / 8.0;
    for (size_t i = 0; i < 3 * nt; ++i) {
        uint8_t b = NEXT();
        m->indices[i] = b >= 250 ? (uint32_t)(nv + (b - 250u)) : (uint32_t)(b % nv);
    }
#undef NEXT
    return m;
}

/* The save → load round trip keeps the counts (binary PLY keeps vertices and triangles as they are). */
static void save_and_reload(const resurf_mesh *m, unsigned flags)
{
    static char path[64];
    if (!path[0])
        snprintf(path, sizeof path, "/tmp/resurf-fuzz-pipeline-%ld.ply", (long)getpid());
    resurf_save_options so = resurf_save_options_default();
    so.binary = !(flags & 8);
    resurf_error e;
    resurf_status s = resurf_mesh_save(m, path, &so, &e);
    if (s != RESURF_OK) {
        require_reason(s, &e);
        REQUIRE(s == RESURF_ERR_IO); /* the mesh is processable, so only the disk may refuse */
        return;
    }
    resurf_mesh *back = NULL;
    s = resurf_mesh_load(path, NULL, &back, &e);
    unlink(path);
    if (m->triangle_count == 0) {
        /* A PLY without faces loads or is refused, but must not crash. */
        if (s == RESURF_OK)
            resurf_mesh_free(back);
        return;
    }
    REQUIRE(s == RESURF_OK);
    REQUIRE(back->vertex_count == m->vertex_count && back->triangle_count == m->triangle_count);
    REQUIRE(memcmp(back->indices, m->indices, 3 * m->triangle_count * sizeof *m->indices) == 0);
    resurf_mesh_free(back);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    const unsigned flags = data[0];
    resurf_mesh *mesh = NULL;
    resurf_error e;
    if (flags & 0x80) {
        resurf_load_options lo = resurf_load_options_default();
        lo.max_triangles = 64;
        resurf_status s = resurf_mesh_load_memory(data + 1, size - 1, RESURF_FORMAT_OBJ, "fuzz.obj", &lo, &mesh, &e);
        if (s != RESURF_OK) {
            require_reason(s, &e);
            return 0;
        }
        REQUIRE(processable(mesh)); /* the loader checks indices and coordinates */
    } else if (!(mesh = decode_mesh(data + 1, size - 1))) {
        return 0;
    }

    /* Validate: never fails on a bad mesh; its verdict must agree with the mesh. */
    resurf_validate_report v;
    resurf_status s = resurf_mesh_validate(mesh, &v, &e);
    REQUIRE(s == RESURF_OK);
    REQUIRE(resurf_validation_ok(&v) == processable(mesh));

    /* Repair everything: what remains must be processable. */
    resurf_repair_report rr;
    s = resurf_mesh_repair(mesh, NULL, &rr, &e);
    REQUIRE(s == RESURF_OK);
    REQUIRE(processable(mesh));
    s = resurf_mesh_validate(mesh, &v, &e);
    REQUIRE(s == RESURF_OK && resurf_validation_ok(&v));
    REQUIRE(v.degenerate_triangles == 0 && v.unreferenced_vertices == 0);

    if (mesh->triangle_count > 0) {
        /* A smoothed copy, restored onto the repaired original. */
        resurf_mesh *smoothed = NULL;
        REQUIRE(resurf_mesh_clone(mesh, &smoothed, NULL) == RESURF_OK);
        resurf_smooth_options so = resurf_smooth_options_default();
        so.method = (resurf_smooth_method)((flags >> 1) % RESURF_SMOOTH_COUNT);
        so.iterations = 1 + (flags & 3);
        s = resurf_smooth(smoothed, &so, &e);
        REQUIRE(s == RESURF_OK);
        REQUIRE(processable(smoothed));

        resurf_restore_options ro = (flags & 16) ? resurf_restore_options_paper() : resurf_restore_options_default();
        ro.normals = (resurf_normal_scheme)(flags % RESURF_NORMALS_COUNT);
        ro.outside = (resurf_outside_policy)((flags >> 2) % RESURF_OUTSIDE_COUNT);
        ro.threads = (flags & 32) ? 2 : 1;
        resurf_restore_report rep;
        s = resurf_restore(mesh, smoothed, &ro, &rep, &e);
        if (s != RESURF_OK)
            require_reason(s, &e);
        REQUIRE(processable(smoothed)); /* restored or untouched, never broken */
        save_and_reload(smoothed, flags);
        resurf_mesh_free(smoothed);

#ifdef FUZZ_HAVE_SIMPLIFY
        resurf_simplify_options sim = resurf_simplify_options_default();
        sim.target_ratio = (double)(1 + (flags & 7)) / 8.0;
        sim.restore = (resurf_restore_mode)((flags >> 3) % RESURF_RESTORE_MODE_COUNT);
        sim.measure_samples = 64;
        sim.threads = (flags & 32) ? 2 : 1;
        resurf_mesh *simple = NULL;
        resurf_simplify_report sr;
        s = resurf_simplify(mesh, &sim, &simple, &sr, &e);
        if (s == RESURF_OK) {
            REQUIRE(simple && processable(simple));
            REQUIRE(simple->triangle_count <= mesh->triangle_count);
            save_and_reload(simple, flags);
            resurf_mesh_free(simple);
        } else {
            require_reason(s, &e);
            REQUIRE(simple == NULL);
        }
#endif
    }
    save_and_reload(mesh, flags);
    resurf_mesh_free(mesh);
    return 0;
}
