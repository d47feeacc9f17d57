// The C++ twin of consumer.c: proves that <resurf/resurf.h> compiles as C++17 under -Wall -Wextra -Werror
// -pedantic and that the extern "C" linkage matches the installed library (a missing extern "C" would fail to
// link with mangled names). Usage: consumer_cpp EXPECTED_VERSION; prints "ok" and exits 0 on success.
#include <resurf/resurf.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

namespace {

struct MeshDeleter {
    void operator()(resurf_mesh *mesh) const { resurf_mesh_free(mesh); }
};
using MeshPtr = std::unique_ptr<resurf_mesh, MeshDeleter>;

int fail(const std::string &what, const resurf_error *error = nullptr)
{
    std::string text = "consumer_cpp: " + what;
    if (error)
        text += std::string(": ") + resurf_status_string(error->status) + ": " + error->message;
    std::fprintf(stderr, "%s\n", text.c_str());
    return 1;
}

} // namespace

int main(int argc, char **argv)
{
    if (argc != 2)
        return fail("usage: consumer_cpp EXPECTED_VERSION");

    const std::string header_version = RESURF_VERSION_STRING;
    const std::string parts = std::to_string(RESURF_VERSION_MAJOR) + "." + std::to_string(RESURF_VERSION_MINOR) +
                              "." + std::to_string(RESURF_VERSION_PATCH);
    if (parts != header_version)
        return fail("RESURF_VERSION_MAJOR/MINOR/PATCH disagree with RESURF_VERSION_STRING");
    if (header_version != resurf_version())
        return fail("resurf_version() differs from RESURF_VERSION_STRING (header and library mismatch)");
    if (header_version != argv[1])
        return fail("resurf.pc's Version differs from RESURF_VERSION_STRING");

    // The same regular tetrahedron as consumer.c, counter-clockwise seen from outside.
    static const double positions[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    static const uint32_t indices[12] = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
    resurf_error error{};
    resurf_mesh *raw = nullptr;
    if (resurf_mesh_create(4, 4, 0, &raw, &error) != RESURF_OK)
        return fail("resurf_mesh_create", &error);
    MeshPtr mesh(raw);
    std::memcpy(mesh->positions, positions, sizeof positions);
    std::memcpy(mesh->indices, indices, sizeof indices);

    resurf_validate_report v{};
    if (resurf_mesh_validate(mesh.get(), &v, &error) != RESURF_OK)
        return fail("resurf_mesh_validate", &error);
    if (v.boundary_edges != 0 || v.components != 1 || v.nonmanifold_edges != 0 || v.inconsistent_edges != 0)
        return fail("the tetrahedron is not one closed, consistently oriented component");

    const resurf_status status = resurf_mesh_validate(nullptr, &v, &error);
    if (status == RESURF_OK || error.status != status || std::strlen(resurf_status_string(status)) == 0)
        return fail("resurf_mesh_validate(nullptr) did not report an error");

    std::puts("ok");
    return 0;
}
