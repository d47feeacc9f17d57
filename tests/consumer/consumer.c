/* A C program that uses resurf the way an outside project does: it includes <resurf/resurf.h> and links the
 * *installed* library found through pkg-config (tests/test_install.sh builds it shared and static).
 * It builds a regular tetrahedron, validates it and checks that header and library agree on the version.
 * Usage: consumer EXPECTED_VERSION (the installed resurf.pc's Version). Prints "ok" and exits 0 on success. */
#include <resurf/resurf.h>

#include <stdio.h>
#include <string.h>

static int fail(const char *what, const resurf_error *error)
{
    fprintf(stderr, "consumer: %s", what);
    if (error)
        fprintf(stderr, ": %s: %s", resurf_status_string(error->status), error->message);
    fputc('\n', stderr);
    return 1;
}

int main(int argc, char **argv)
{
    if (argc != 2)
        return fail("usage: consumer EXPECTED_VERSION", NULL);

    /* Version: the macro, its parts, the library's answer and the package version must be one and the same. */
    char parts[64];
    snprintf(parts, sizeof parts, "%d.%d.%d", RESURF_VERSION_MAJOR, RESURF_VERSION_MINOR, RESURF_VERSION_PATCH);
    if (strcmp(parts, RESURF_VERSION_STRING) != 0)
        return fail("RESURF_VERSION_MAJOR/MINOR/PATCH disagree with RESURF_VERSION_STRING", NULL);
    if (strcmp(resurf_version(), RESURF_VERSION_STRING) != 0)
        return fail("resurf_version() differs from RESURF_VERSION_STRING (header and library mismatch)", NULL);
    if (strcmp(argv[1], RESURF_VERSION_STRING) != 0)
        return fail("resurf.pc's Version differs from RESURF_VERSION_STRING", NULL);

    /* A regular tetrahedron: the corners 0 = (1,1,1), 1 = (1,-1,-1), 2 = (-1,1,-1), 3 = (-1,-1,1) of the cube
     * [-1,1]^3; each face lists its corners counter-clockwise seen from outside. */
    static const double positions[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    static const uint32_t indices[12] = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
    resurf_error error;
    resurf_mesh *mesh = NULL;
    if (resurf_mesh_create(4, 4, 0, &mesh, &error) != RESURF_OK)
        return fail("resurf_mesh_create", &error);
    if (mesh->vertex_count != 4 || mesh->triangle_count != 4)
        return fail("resurf_mesh_create gave the wrong counts", NULL);
    memcpy(mesh->positions, positions, sizeof positions);
    memcpy(mesh->indices, indices, sizeof indices);

    resurf_validate_report v;
    if (resurf_mesh_validate(mesh, &v, &error) != RESURF_OK)
        return fail("resurf_mesh_validate", &error);
    resurf_mesh_free(mesh);
    if (v.boundary_edges != 0 || v.components != 1 || v.nonmanifold_edges != 0 || v.inconsistent_edges != 0)
        return fail("the tetrahedron is not one closed, consistently oriented component", NULL);

    /* A failing call reports through the status and the error struct. */
    resurf_status status = resurf_mesh_validate(NULL, &v, &error);
    if (status == RESURF_OK || error.status != status || resurf_status_string(status)[0] == '\0')
        return fail("resurf_mesh_validate(NULL) did not report an error", NULL);

    resurf_mesh_free(NULL);
    puts("ok");
    return 0;
}
