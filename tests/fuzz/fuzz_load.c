/* libFuzzer harness for one mesh loader; FUZZ_FORMAT picks which (RESURF_FORMAT_OBJ, _PLY, _OFF, _STL).
 * No input may crash, hang or allocate beyond what its size justifies (ASan's allocator and libFuzzer's -rss_limit_mb
 * catch that). What the loader accepts must keep the loader's promises (every index in range, finite positions,
 * attribute arrays where their counts say) and pass through validation; what it refuses must be refused with a
 * status that names a cause in the input and a one-line message. A broken promise traps, so libFuzzer keeps it. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "resurf/resurf.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define REQUIRE(cond)                                                                                           \
    do {                                                                                                        \
        if (!(cond))                                                                                            \
            __builtin_trap();                                                                                   \
    } while (0)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    resurf_load_options options = resurf_load_options_default();
    options.max_triangles = 1u << 20;
    resurf_mesh *mesh = NULL;
    resurf_error error;
    resurf_status s = resurf_mesh_load_memory(data, size, FUZZ_FORMAT, "fuzz", &options, &mesh, &error);
    if (s != RESURF_OK) {
        REQUIRE(mesh == NULL);
        REQUIRE(s == RESURF_ERR_PARSE || s == RESURF_ERR_UNSUPPORTED || s == RESURF_ERR_LIMIT);
        REQUIRE(error.status == s && error.message[0] && !strchr(error.message, '\n'));
        return 0;
    }
    REQUIRE(mesh != NULL);
    for (size_t i = 0; i < 3 * mesh->triangle_count; ++i)
        REQUIRE(mesh->indices[i] < mesh->vertex_count);
    for (size_t i = 0; i < 3 * mesh->vertex_count; ++i)
        REQUIRE(isfinite(mesh->positions[i]));
    /* Touch every attribute value, so that ASan sees any array shorter than its count. */
    double sum = 0;
    for (size_t i = 0; mesh->normals && i < 3 * mesh->vertex_count; ++i)
        sum += mesh->normals[i];
    for (unsigned k = 0; k < mesh->texcoord_count; ++k)
        for (size_t i = 0; mesh->texcoords[k] && i < 2 * mesh->vertex_count; ++i)
            sum += mesh->texcoords[k][i];
    for (size_t i = 0; mesh->colors && i < 4 * mesh->vertex_count; ++i)
        sum += mesh->colors[i];
    for (size_t e = 0; e < mesh->extra_count; ++e)
        for (size_t i = 0; i < mesh->extras[e].components * mesh->vertex_count; ++i)
            sum += mesh->extras[e].data[i];
    for (size_t t = 0; mesh->triangle_groups && t < mesh->triangle_count; ++t)
        REQUIRE(mesh->triangle_groups[t] < mesh->group_count);
    for (size_t g = 0; g < mesh->group_count; ++g)
        REQUIRE(mesh->group_names[g] != NULL);
    resurf_validate_report v;
    REQUIRE(resurf_mesh_validate(mesh, &v, NULL) == RESURF_OK);
    REQUIRE(resurf_validation_ok(&v));
    REQUIRE(v.vertex_count == mesh->vertex_count && v.triangle_count == mesh->triangle_count);
    resurf_mesh_free(mesh);
    volatile double sink = sum; /* keeps the loads above from being optimised away */
    (void)sink;
    return 0;
}
