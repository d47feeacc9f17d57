// EXT_meshopt_compression or KHR_meshopt_compression required by a document: prepared on the JSON before tinygltf reads it, decoded on the
// model after (gltf_meshopt.cpp). C++ only, for gltf_read.cpp.
#ifndef RESURF_GLTF_MESHOPT_HPP
#define RESURF_GLTF_MESHOPT_HPP

#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

// One compressed bufferView: where its compressed bytes are, and its own place and layout.
struct MeshoptView {
    size_t view;
    long long source_buffer, source_offset, source_length;
    long long buffer, offset;
    size_t length, count, stride;
    bool had_stride, khr; // khr: KHR_meshopt_compression's, else EXT_meshopt_compression's
    int mode, filter; // resurfi_meshopt_mode, resurfi_meshopt_filter
};

// A buffer without data (no uri) that compressed bufferViews decode into, and its declared byteLength.
struct MeshoptPlaceholder {
    long long buffer;
    size_t length;
};

// The two extensions' names, EXT's first.
extern const char *const meshopt_extensions[2];

// Does nothing unless the document requires EXT_meshopt_compression or KHR_meshopt_compression; else records its compressed bufferViews and
// placeholder buffers and rewrites the JSON as gltf_meshopt.cpp's header says. False with *problem (naming the
// JSON path) when the extension's JSON is malformed.
// is_glb: buffer 0 without a uri is the GLB's binary chunk, data of its own, not a placeholder.
bool meshopt_prepare(nlohmann::json &root, bool is_glb, std::vector<MeshoptView> &views,
                     std::vector<MeshoptPlaceholder> &holders, std::string &problem);
// EXT_ or KHR_meshopt_compression that the document does not require: every compressed bufferView keeps its bytes
// uncompressed in a fallback buffer (gltfpack -cf), and those are what resurf reads. The extension is taken out of
// the bufferViews, the buffers and extensionsUsed, so nothing written refers to the compressed bytes. Returns true
// when it changed the document.
bool drop_optional_meshopt(nlohmann::json &root);
// Decodes every recorded bufferView into its place in the model. False with *problem when a stream is malformed.
bool meshopt_decode(tinygltf::Model &model, const std::vector<MeshoptView> &views,
                    const std::vector<MeshoptPlaceholder> &holders, std::string &problem);

#endif
