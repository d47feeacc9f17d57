/* libFuzzer harness for one mesh loader; FUZZ_FORMAT picks which (RESURF_FORMAT_OBJ, _PLY, _OFF, _STL).
 * A loaded mesh is validated and, if it holds together, saved back to memory-free formats' checks: the point is
 * that no input crashes, hangs or allocates beyond what its size justifies. */
#include <stddef.h>
#include <stdint.h>

#include "resurf/resurf.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    resurf_load_options options = resurf_load_options_default();
    options.max_triangles = 1u << 20;
    resurf_mesh *mesh = NULL;
    resurf_error error;
    if (resurf_mesh_load_memory(data, size, FUZZ_FORMAT, "fuzz", &options, &mesh, &error) == RESURF_OK) {
        resurf_validation v;
        resurf_mesh_validate(mesh, &v, NULL);
        resurf_mesh_free(mesh);
    } else if (!error.message[0]) {
        __builtin_trap(); /* every failure must say what is wrong */
    }
    return 0;
}
