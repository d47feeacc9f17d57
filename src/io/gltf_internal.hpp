// What gltf_read.cpp and gltf_write.cpp share (C++ only, never seen by C): the parsed document behind the opaque
// resurfi_gltf_doc, with the storage of its C view.
#ifndef RESURF_GLTF_INTERNAL_HPP
#define RESURF_GLTF_INTERNAL_HPP

#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <tiny_gltf.h>

#include "gltf_shim.h"

// A KHR_draco_mesh_compression extension taken out of the JSON before tinygltf saw it.
struct DracoRecord {
    long long view;
    long long indices; // the primitive's `indices`, also taken out
    bool malformed;
    std::vector<std::pair<std::string, long long>> attributes; // name → Draco unique id
};

struct resurfi_gltf_doc {
    tinygltf::Model model;
    std::map<std::pair<size_t, size_t>, DracoRecord> draco; // (mesh, primitive) → its Draco extension
    size_t nonfinite_count = 0;
    std::string first_nonfinite;
    std::vector<std::string> warnings;
    std::vector<std::string> outside_extensions; // found on anything but a primitive, each once
    // extensionsUsed and extensionsRequired as the file gives them (the reader takes out EXT_ and KHR_meshopt_compression,
    // which it decodes), for resurf_scene_describe.
    std::vector<std::string> file_extensions_used, file_extensions_required;

    // Storage of the view (each pointer in it points into one of these).
    resurfi_gltf_view view{};
    std::deque<std::string> strings;
    std::vector<resurfi_gltf_buffer> buffers;
    std::vector<resurfi_gltf_buffer_view> views;
    std::vector<resurfi_gltf_accessor> accessors;
    std::vector<resurfi_gltf_primitive> prims;
    std::vector<std::vector<resurfi_gltf_named>> named; // 3 per primitive: attributes, target attributes, Draco ids
    std::vector<std::vector<size_t>> target_begin;
    std::vector<resurfi_gltf_mesh> meshes;
    std::vector<std::vector<long long>> children;
    std::vector<resurfi_gltf_node> nodes;
    std::vector<std::vector<long long>> lod_ids;   // per node: MSFT_lod ids
    std::vector<std::vector<double>> coverage;     // per node: extras.MSFT_screencoverage
    std::vector<std::vector<long long>> scene_nodes;
    std::vector<resurfi_gltf_scene> scenes;
    std::vector<resurfi_gltf_ref> refs;
    std::vector<const char *> ext_used, ext_required, warning_ptrs, outside_ptrs;
    std::vector<std::vector<const char *>> prim_extensions;
    std::vector<resurfi_gltf_image> images;
    std::vector<resurfi_gltf_material> materials;
    std::vector<unsigned> material_texcoords; // per material: the TEXCOORD_n sets its textures sample (bit n)
    std::vector<resurfi_gltf_texture> textures;
};

#endif
