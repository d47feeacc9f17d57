// EXT_meshopt_compression or KHR_meshopt_compression in a document that requires it: its compressed bufferViews are
// decoded into the layout their parent bufferViews describe, so that the rest of the reader sees an ordinary
// document. The two extensions' JSON is the same; KHR's streams may also be of version 1 and use the colour filter.
//
// Two steps around tinygltf's reading. Before (meshopt_prepare, on the JSON): each compressed bufferView points at
// its compressed bytes for the time being, a placeholder buffer without data (no uri) gets a 4-byte data: URI, and
// the extension leaves extensionsUsed/Required. After (meshopt_decode, on the model): each placeholder gets its
// declared length of zeros, every compressed bufferView is decoded (src/meshopt_decode.c) into its place, and the
// bufferViews get their own buffer, offset, length and stride back. Nothing refers to the compressed bytes then,
// and the writer leaves them out.
#include "gltf_meshopt.hpp"

#include <cstring>
#include <set>

#include "../meshopt_decode.h"

namespace {

bool get_index(const nlohmann::json &o, const char *key, long long fallback, long long &out)
{
    auto it = o.find(key);
    if (it == o.end()) {
        out = fallback;
        return fallback >= 0;
    }
    if (!it->is_number_integer() && !it->is_number_unsigned())
        return false;
    out = it->get<long long>();
    return out >= 0;
}

// Is `name` among the strings of root[key] (extensionsUsed, extensionsRequired)?
bool listed(const nlohmann::json &root, const char *key, const char *name)
{
    auto names = root.find(key);
    if (names != root.end() && names->is_array())
        for (const nlohmann::json &e : *names)
            if (e.is_string() && e.get_ref<const std::string &>() == name)
                return true;
    return false;
}

// Takes `name` out of root[key]; true when it was there.
bool unlist(nlohmann::json &root, const char *key, const char *name)
{
    bool removed = false;
    auto names = root.find(key);
    if (names != root.end() && names->is_array())
        for (size_t i = names->size(); i-- > 0;)
            if ((*names)[i].is_string() && (*names)[i].get_ref<const std::string &>() == name) {
                names->erase(i);
                removed = true;
            }
    return removed;
}

// Takes extension `name` out of object x (and its extensions object when that is left empty); true when it was there.
bool erase_extension(nlohmann::json &x, const char *name)
{
    auto exts = x.is_object() ? x.find("extensions") : x.end();
    if (exts == x.end() || !exts->is_object() || !exts->erase(name))
        return false;
    if (exts->empty())
        x.erase("extensions");
    return true;
}

} // namespace

const char *const meshopt_extensions[2] = {"EXT_meshopt_compression", "KHR_meshopt_compression"};

bool meshopt_prepare(nlohmann::json &root, bool is_glb, std::vector<MeshoptView> &views,
                     std::vector<MeshoptPlaceholder> &holders, std::string &problem)
{
    const bool is_required[2] = {listed(root, "extensionsRequired", meshopt_extensions[0]),
                                 listed(root, "extensionsRequired", meshopt_extensions[1])};
    if (!is_required[0] && !is_required[1])
        return true;
    auto list = root.find("bufferViews");
    auto buffers = root.find("buffers");
    size_t buffer_count = buffers != root.end() && buffers->is_array() ? buffers->size() : 0;
    std::set<long long> parents;
    for (size_t i = 0; list != root.end() && list->is_array() && i < list->size(); ++i) {
        nlohmann::json &bv = (*list)[i];
        auto exts = bv.is_object() ? bv.find("extensions") : bv.end();
        int k = exts == bv.end() || !exts->is_object() ? -1
                : is_required[1] && exts->contains(meshopt_extensions[1]) ? 1
                : is_required[0] && exts->contains(meshopt_extensions[0]) ? 0
                                                                          : -1;
        if (k < 0)
            continue;
        const char *ext = meshopt_extensions[k];
        const nlohmann::json &e = (*exts)[ext];
        std::string where = "bufferViews[" + std::to_string(i) + "].extensions." + ext;
        if (exts->contains(meshopt_extensions[1 - k])) {
            problem = where + ": the bufferView uses both " + ext + " and " + meshopt_extensions[1 - k];
            return false;
        }
        MeshoptView v;
        v.view = i;
        v.khr = k == 1;
        long long count, stride, length;
        if (!e.is_object() || !get_index(e, "buffer", -1, v.source_buffer) ||
            !get_index(e, "byteOffset", 0, v.source_offset) || !get_index(e, "byteLength", -1, v.source_length) ||
            !get_index(e, "byteStride", -1, stride) || !get_index(e, "count", -1, count) ||
            !get_index(bv, "buffer", -1, v.buffer) || !get_index(bv, "byteOffset", 0, v.offset) ||
            !get_index(bv, "byteLength", -1, length)) {
            problem = where + ": buffer, byteLength, byteStride and count must be given as whole numbers >= 0 "
                              "(and the bufferView's buffer and byteLength)";
            return false;
        }
        if ((size_t)v.source_buffer >= buffer_count || (size_t)v.buffer >= buffer_count) {
            problem = where + ": names a buffer that does not exist";
            return false;
        }
        if (stride == 0 || stride > 256 || count > (1LL << 40) || stride * count != length) {
            problem = where + ": byteStride × count must equal the bufferView's byteLength (" +
                      std::to_string(length) + ")";
            return false;
        }
        long long own_stride;
        if (bv.contains("byteStride") && (!get_index(bv, "byteStride", -1, own_stride) || own_stride != stride)) {
            problem = where + ": its byteStride differs from the bufferView's";
            return false;
        }
        v.count = (size_t)count, v.stride = (size_t)stride, v.length = (size_t)length;
        v.had_stride = bv.contains("byteStride");
        std::string mode = e.contains("mode") && e["mode"].is_string() ? e["mode"].get<std::string>() : "";
        std::string filter =
            e.contains("filter") ? (e["filter"].is_string() ? e["filter"].get<std::string>() : "?") : "NONE";
        v.mode = mode == "ATTRIBUTES" ? 0 : mode == "TRIANGLES" ? 1 : mode == "INDICES" ? 2 : -1;
        v.filter = filter == "NONE"                 ? 0
                   : filter == "OCTAHEDRAL"         ? 1
                   : filter == "QUATERNION"         ? 2
                   : filter == "EXPONENTIAL"        ? 3
                   : filter == "COLOR" && v.khr     ? 4
                                                    : -1;
        if (v.mode < 0 || v.filter < 0) {
            problem = where + ": mode '" + mode + "' or filter '" + filter + "' is not one the extension defines";
            return false;
        }
        parents.insert(v.buffer);
        views.push_back(v);
        // For now the bufferView is its compressed bytes (a range of a buffer with data), without stride.
        bv["buffer"] = v.source_buffer;
        bv["byteOffset"] = v.source_offset;
        bv["byteLength"] = v.source_length;
        bv.erase("byteStride");
        erase_extension(bv, ext);
    }
    for (long long b : parents) {
        nlohmann::json &buffer = (*buffers)[(size_t)b];
        if (!buffer.is_object() || buffer.contains("uri") || (is_glb && b == 0))
            continue; // data of its own (a fallback, or the GLB chunk): decoded over in place
        long long length;
        if (!get_index(buffer, "byteLength", -1, length)) {
            problem = "buffers[" + std::to_string(b) + "]: byteLength must be a whole number";
            return false;
        }
        holders.push_back(MeshoptPlaceholder{b, (size_t)length});
        buffer["uri"] = "data:application/octet-stream;base64,AAAAAA==";
        buffer["byteLength"] = 4;
    }
    for (int k = 0; k < 2; ++k) {
        if (!is_required[k])
            continue;
        for (size_t b = 0; b < buffer_count; ++b)
            erase_extension((*buffers)[b], meshopt_extensions[k]);
        unlist(root, "extensionsUsed", meshopt_extensions[k]);
        unlist(root, "extensionsRequired", meshopt_extensions[k]);
    }
    return true;
}

bool drop_optional_meshopt(nlohmann::json &root)
{
    bool changed = false;
    for (const char *ext : meshopt_extensions) {
        if (listed(root, "extensionsRequired", ext))
            continue;
        for (const char *key : {"bufferViews", "buffers"}) {
            auto list = root.find(key);
            if (list != root.end() && list->is_array())
                for (nlohmann::json &x : *list)
                    changed |= erase_extension(x, ext);
        }
        changed |= unlist(root, "extensionsUsed", ext);
    }
    return changed;
}

bool meshopt_decode(tinygltf::Model &model, const std::vector<MeshoptView> &views,
                    const std::vector<MeshoptPlaceholder> &holders, std::string &problem)
{
    // A placeholder holds what its bufferViews decode to: at most 64 bytes per compressed byte of version 0 (2 header
    // bits per 16 bytes), 1,024 of KHR's version 1 (a block of 256 elements of zero deltas takes its control byte
    // for each 4 bytes alone), and a little more, so a hostile byteLength cannot claim the machine.
    for (const MeshoptPlaceholder &h : holders) {
        size_t most = 1u << 20;
        for (const MeshoptView &v : views)
            if (v.buffer == h.buffer)
                most += (v.khr ? 1024 : 64) * (size_t)v.source_length;
        if (h.length > most) {
            problem = "buffers[" + std::to_string(h.buffer) + "]: its byteLength " + std::to_string(h.length) +
                      " is more than its compressed bufferViews can decode to";
            return false;
        }
        model.buffers[(size_t)h.buffer].data.assign(h.length, 0);
    }
    for (const MeshoptView &v : views) {
        std::string where = "bufferViews[" + std::to_string(v.view) + "].extensions." + meshopt_extensions[v.khr];
        const std::vector<unsigned char> &src = model.buffers[(size_t)v.source_buffer].data;
        std::vector<unsigned char> &dst = model.buffers[(size_t)v.buffer].data;
        if ((size_t)v.source_offset > src.size() || (size_t)v.source_length > src.size() - (size_t)v.source_offset) {
            problem = where + ": its compressed bytes lie past the end of buffers[" +
                      std::to_string(v.source_buffer) + "]";
            return false;
        }
        if ((size_t)v.offset > dst.size() || v.length > dst.size() - (size_t)v.offset) {
            problem = where + ": the bufferView lies past the end of buffers[" + std::to_string(v.buffer) + "]";
            return false;
        }
        if (v.source_buffer == v.buffer) {
            problem = where + ": the compressed bytes are in the buffer they decode into";
            return false;
        }
        const char *why = resurfi_meshopt_decode(v.khr, (resurfi_meshopt_mode)v.mode, (resurfi_meshopt_filter)v.filter,
                                                 v.count, v.stride, src.data() + v.source_offset,
                                                 (size_t)v.source_length, dst.data() + v.offset);
        if (why) {
            problem = where + ": " + why;
            return false;
        }
        tinygltf::BufferView &bv = model.bufferViews[v.view];
        bv.buffer = (int)v.buffer;
        bv.byteOffset = (size_t)v.offset;
        bv.byteLength = v.length;
        bv.byteStride = v.had_stride ? v.stride : 0;
    }
    return true;
}
