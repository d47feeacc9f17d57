// What `resurf info` prints about a scene: its scenes, nodes, meshes and primitives (triangles, vertices,
// attributes, morph targets), materials, textures, images, skins, animations, cameras and extensions, as JSON
// (nlohmann::json) and as text rendered from that same JSON, so the two never disagree.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <new>
#include <string>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "gltf_internal.hpp"

namespace {

using nlohmann::json;

json names(const tinygltf::ExtensionMap &extensions)
{
    json out = json::array();
    for (const auto &e : extensions)
        out.push_back(e.first);
    return out;
}

void put_index(json &o, const char *key, int index)
{
    if (index >= 0)
        o[key] = index;
}

json describe_primitive(const resurfi_gltf_doc *doc, size_t m, size_t p, const resurfi_describe_prim &info)
{
    const tinygltf::Primitive &prim = doc->model.meshes[m].primitives[p];
    json o;
    o["mode"] = prim.mode;
    if (info.has_mesh) {
        o["triangles"] = info.triangles;
        o["vertices"] = info.vertices;
    }
    put_index(o, "material", prim.material);
    o["attributes"] = json::array();
    for (const auto &a : prim.attributes)
        o["attributes"].push_back(a.first);
    if (!prim.targets.empty()) {
        o["targets"] = prim.targets.size();
        json attrs = json::array();
        for (const auto &a : prim.targets[0])
            attrs.push_back(a.first);
        o["target_attributes"] = attrs;
    }
    o["draco"] = doc->draco.count(std::make_pair(m, p)) > 0;
    json ext = names(prim.extensions);
    if (o["draco"].get<bool>())
        ext.push_back("KHR_draco_mesh_compression");
    o["extensions"] = ext;
    return o;
}

json describe_document(const resurfi_gltf_doc *doc, const resurfi_describe_prim *prims,
                       const resurfi_describe_image *images)
{
    const tinygltf::Model &m = doc->model;
    json d;
    d["default_scene"] = m.defaultScene >= 0 ? json(m.defaultScene) : json();
    d["scenes"] = json::array();
    for (const tinygltf::Scene &s : m.scenes)
        d["scenes"].push_back({{"name", s.name}, {"nodes", s.nodes}, {"extensions", names(s.extensions)}});
    d["nodes"] = json::array();
    for (const tinygltf::Node &n : m.nodes) {
        json o = {{"name", n.name}};
        put_index(o, "mesh", n.mesh);
        put_index(o, "skin", n.skin);
        put_index(o, "camera", n.camera);
        json transform = json::array();
        if (!n.matrix.empty())
            transform.push_back("matrix");
        for (const auto &t : {std::make_pair("translation", &n.translation), std::make_pair("rotation", &n.rotation),
                              std::make_pair("scale", &n.scale)})
            if (!t.second->empty())
                transform.push_back(t.first);
        o["transform"] = transform;
        auto instancing = n.extensions.find("EXT_mesh_gpu_instancing"); // its accessors were checked by the load
        if (instancing != n.extensions.end() && instancing->second.IsObject() &&
            instancing->second.Has("attributes") && !instancing->second.Get("attributes").Keys().empty()) {
            const tinygltf::Value &at = instancing->second.Get("attributes");
            o["instances"] = m.accessors.at((size_t)at.Get(at.Keys()[0]).GetNumberAsInt()).count;
        }
        o["children"] = n.children;
        o["extensions"] = names(n.extensions);
        d["nodes"].push_back(o);
    }
    d["meshes"] = json::array();
    size_t k = 0;
    for (size_t mi = 0; mi < m.meshes.size(); ++mi) {
        json o = {{"name", m.meshes[mi].name}, {"primitives", json::array()}};
        if (!m.meshes[mi].weights.empty())
            o["weights"] = m.meshes[mi].weights.size();
        for (size_t pi = 0; pi < m.meshes[mi].primitives.size(); ++pi, ++k)
            o["primitives"].push_back(describe_primitive(doc, mi, pi, prims[k]));
        o["extensions"] = names(m.meshes[mi].extensions);
        d["meshes"].push_back(o);
    }
    d["materials"] = json::array();
    for (const tinygltf::Material &mat : m.materials) {
        json t = json::object();
        const tinygltf::PbrMetallicRoughness &pbr = mat.pbrMetallicRoughness;
        put_index(t, "baseColor", pbr.baseColorTexture.index);
        put_index(t, "metallicRoughness", pbr.metallicRoughnessTexture.index);
        put_index(t, "normal", mat.normalTexture.index);
        put_index(t, "occlusion", mat.occlusionTexture.index);
        put_index(t, "emissive", mat.emissiveTexture.index);
        d["materials"].push_back({{"name", mat.name}, {"textures", t}, {"extensions", names(mat.extensions)}});
    }
    d["textures"] = json::array();
    for (const tinygltf::Texture &t : m.textures) {
        json o = json::object();
        put_index(o, "source", t.source);
        put_index(o, "sampler", t.sampler);
        o["extensions"] = names(t.extensions);
        d["textures"].push_back(o);
    }
    d["images"] = json::array();
    for (size_t i = 0; i < m.images.size(); ++i) {
        const tinygltf::Image &img = m.images[i];
        json o = {{"name", img.name}};
        if (img.bufferView >= 0)
            o["bufferView"] = img.bufferView;
        else if (!img.uri.empty())
            o["uri"] = img.uri;
        else
            o["embedded"] = true;
        const char *mime = images[i].mime_type && images[i].mime_type[0] ? images[i].mime_type : img.mimeType.c_str();
        if (mime[0])
            o["mimeType"] = mime;
        if (images[i].missing)
            o["missing"] = true;
        else
            o["bytes"] = images[i].bytes;
        d["images"].push_back(o);
    }
    d["skins"] = json::array();
    for (const tinygltf::Skin &s : m.skins) {
        json o = {{"name", s.name}, {"joints", s.joints.size()}, {"inverseBindMatrices", s.inverseBindMatrices >= 0}};
        put_index(o, "skeleton", s.skeleton);
        d["skins"].push_back(o);
    }
    d["animations"] = json::array();
    for (const tinygltf::Animation &a : m.animations) {
        json paths = json::array();
        for (const tinygltf::AnimationChannel &c : a.channels)
            if (std::find(paths.begin(), paths.end(), c.target_path) == paths.end())
                paths.push_back(c.target_path);
        d["animations"].push_back(
            {{"name", a.name}, {"channels", a.channels.size()}, {"samplers", a.samplers.size()}, {"paths", paths}});
    }
    d["cameras"] = json::array();
    for (const tinygltf::Camera &c : m.cameras)
        d["cameras"].push_back({{"name", c.name}, {"type", c.type}});
    d["extensions"] = names(m.extensions);
    d["extensionsUsed"] = doc->file_extensions_used;
    d["extensionsRequired"] = doc->file_extensions_required;
    return d;
}

// A scene without a document (a .drc or a mesh file): one mesh, one primitive.
json describe_mesh(const resurfi_describe_prim &p)
{
    json prim = {{"mode", 4}, {"triangles", p.triangles}, {"vertices", p.vertices}, {"attributes", json::array()},
                 {"draco", false}, {"extensions", json::array()}};
    for (size_t i = 0; i < p.attribute_count; ++i)
        prim["attributes"].push_back(p.attributes[i]);
    json d;
    d["default_scene"] = json();
    d["scenes"] = json::array();
    d["nodes"] = json::array();
    d["meshes"] = json::array({{{"name", ""}, {"primitives", json::array({prim})}, {"extensions", json::array()}}});
    for (const char *key : {"materials", "textures", "images", "skins", "animations", "cameras", "extensions",
                            "extensionsUsed", "extensionsRequired"})
        d[key] = json::array();
    return d;
}

// A name from the document on one printable line.
std::string printable(std::string s)
{
    for (char &c : s)
        if ((unsigned char)c < 0x20 || c == 0x7f)
            c = '?';
    return s;
}

std::string dump(const json &x) { return x.dump(-1, ' ', false, json::error_handler_t::replace); }

std::string list(const json &a)
{
    std::string s;
    for (const json &x : a)
        s += (s.empty() ? "" : ", ") + (x.is_string() ? printable(x.get<std::string>()) : dump(x));
    return s;
}

std::string quoted_name(const json &o)
{
    return o.contains("name") && !o["name"].get<std::string>().empty() ? " " + dump(o["name"]) : "";
}

// "key value" pairs of an object, in a fixed order, those present only.
std::string fields(const json &o, std::initializer_list<const char *> keys)
{
    std::string s;
    for (const char *k : keys) {
        if (!o.contains(k))
            continue;
        const json &v = o[k];
        if (v.is_array() && v.empty())
            continue;
        if (v.is_boolean() && !v.get<bool>())
            continue;
        s += std::string(s.empty() ? "" : ", ") + k;
        if (!v.is_boolean())
            s += " " + (v.is_array() ? list(v) : v.is_string() ? printable(v.get<std::string>()) : dump(v));
    }
    return s.empty() ? "-" : s;
}

std::string text(const json &d)
{
    std::string out;
    auto line = [&](const std::string &s) { out += s + "\n"; };
    auto section = [&](const char *key, const std::string &extra) {
        line(std::string(key) + std::string(key[0] && std::strlen(key) < 19 ? 19 - std::strlen(key) : 1, ' ') + " " +
             std::to_string(d[key].size()) + extra);
    };
    section("scenes", d["default_scene"].is_null() ? "" : " (default " + d["default_scene"].dump() + ")");
    for (size_t i = 0; i < d["scenes"].size(); ++i)
        line("  scenes[" + std::to_string(i) + "]" + quoted_name(d["scenes"][i]) + ": " +
             fields(d["scenes"][i], {"nodes", "extensions"}));
    section("nodes", "");
    for (size_t i = 0; i < d["nodes"].size(); ++i)
        line("  nodes[" + std::to_string(i) + "]" + quoted_name(d["nodes"][i]) + ": " +
             fields(d["nodes"][i], {"mesh", "instances", "skin", "camera", "transform", "children", "extensions"}));
    section("meshes", "");
    for (size_t i = 0; i < d["meshes"].size(); ++i) {
        const json &m = d["meshes"][i];
        line("  meshes[" + std::to_string(i) + "]" + quoted_name(m) + ": " + std::to_string(m["primitives"].size()) +
             " primitive" + (m["primitives"].size() == 1 ? "" : "s") +
             (m.contains("weights") ? ", weights " + m["weights"].dump() : "") +
             (m["extensions"].empty() ? "" : ", extensions " + list(m["extensions"])));
        for (size_t p = 0; p < m["primitives"].size(); ++p)
            line("    primitives[" + std::to_string(p) + "]: " +
                 fields(m["primitives"][p], {"triangles", "vertices", "mode", "material", "attributes", "targets",
                                             "target_attributes", "draco", "extensions"}));
    }
    section("materials", "");
    for (size_t i = 0; i < d["materials"].size(); ++i) {
        const json &mat = d["materials"][i];
        std::string t;
        for (auto it = mat["textures"].begin(); it != mat["textures"].end(); ++it)
            t += (t.empty() ? "textures " : ", ") + it.key() + " " + dump(it.value());
        std::string e = fields(mat, {"extensions"});
        line("  materials[" + std::to_string(i) + "]" + quoted_name(mat) + ":" + (t.empty() ? "" : " " + t) +
             (e.empty() ? "" : (t.empty() ? " " : ", ") + e));
    }
    section("textures", "");
    for (size_t i = 0; i < d["textures"].size(); ++i)
        line("  textures[" + std::to_string(i) + "]: " + fields(d["textures"][i], {"source", "sampler", "extensions"}));
    section("images", "");
    for (size_t i = 0; i < d["images"].size(); ++i)
        line("  images[" + std::to_string(i) + "]" + quoted_name(d["images"][i]) + ": " +
             fields(d["images"][i], {"uri", "bufferView", "embedded", "mimeType", "bytes", "missing"}));
    section("skins", "");
    for (size_t i = 0; i < d["skins"].size(); ++i)
        line("  skins[" + std::to_string(i) + "]" + quoted_name(d["skins"][i]) + ": " +
             fields(d["skins"][i], {"joints", "inverseBindMatrices", "skeleton"}));
    section("animations", "");
    for (size_t i = 0; i < d["animations"].size(); ++i)
        line("  animations[" + std::to_string(i) + "]" + quoted_name(d["animations"][i]) + ": " +
             fields(d["animations"][i], {"channels", "samplers", "paths"}));
    section("cameras", "");
    for (size_t i = 0; i < d["cameras"].size(); ++i)
        line("  cameras[" + std::to_string(i) + "]" + quoted_name(d["cameras"][i]) + ": " +
             fields(d["cameras"][i], {"type"}));
    line("extensions used     " + (d["extensionsUsed"].empty() ? std::string("none") : list(d["extensionsUsed"])));
    line("extensions required " +
         (d["extensionsRequired"].empty() ? std::string("none") : list(d["extensionsRequired"])));
    if (!d["extensions"].empty())
        line("document extensions " + list(d["extensions"]));
    return out;
}

} // namespace

extern "C" resurf_status resurfi_gltf_describe(const resurfi_gltf_doc *doc, const resurfi_describe_prim *prims,
                                               const resurfi_describe_image *images, int as_json, char *dst,
                                               size_t dst_size, size_t *out_length, resurf_error *error)
{
    try {
        json d = doc ? describe_document(doc, prims, images) : describe_mesh(prims[0]);
        // Names come from the document: dump() escapes them; the text shows them as JSON strings too.
        std::string s = as_json ? dump(d) + "\n" : text(d);
        *out_length = s.size();
        if (dst && dst_size) {
            size_t n = s.size() < dst_size - 1 ? s.size() : dst_size - 1;
            std::memcpy(dst, s.data(), n);
            dst[n] = 0;
        }
        return RESURF_OK;
    } catch (const std::bad_alloc &) {
        return resurfi_fail(error, RESURF_ERR_OUT_OF_MEMORY, NULL, 0, -1, "out of memory describing the scene");
    } catch (const std::exception &e) {
        return resurfi_fail(error, RESURF_ERR_INTERNAL, NULL, 0, -1, "describing the scene failed: %s", e.what());
    }
}
