// Reading glTF 2.0 with tinygltf, behind the C view of gltf_shim.h.
//
// Two passes over the JSON. The first (nlohmann::json) takes every KHR_draco_mesh_compression extension, and the
// `indices` of its primitive, out of the document and records them: tinygltf is compiled without Draco (see
// tinygltf_impl.cpp) and would otherwise refuse the indices accessor that has no bufferView. It also counts numbers
// that overflowed to infinity (1e999). The second pass is tinygltf's own load, with file callbacks that read
// regular files only and an image callback that keeps image bytes as they are.
//
// Before both, gltf_schema.cpp checks the JSON against the glTF 2.0 schema (types, required properties, enums,
// ranges): the first problem fails the load, or with `lenient` each becomes a warning. Beyond that nothing here
// judges the content: indices, ranges and references are copied into the view as the file gives them, and
// scene_check.c checks them (the Khronos glTF 2.0 specification, sections 3.6-3.7 and 5).
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <fstream>
#include <map>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "gltf_internal.hpp"
#include "gltf_meshopt.hpp"
#include "gltf_schema.hpp"

namespace {

// The first non-empty line of a tinygltf message, for a one-line error.
std::string first_line(const std::string &text)
{
    size_t begin = 0;
    while (begin < text.size()) {
        size_t end = text.find('\n', begin);
        if (end == std::string::npos)
            end = text.size();
        std::string line = text.substr(begin, end - begin);
        while (!line.empty() && (line.back() == '\r' || line.back() == ' '))
            line.pop_back();
        if (!line.empty())
            return line;
        begin = end + 1;
    }
    return std::string();
}

long long json_index(const nlohmann::json &j)
{
    if (j.is_number_integer())
        return j.get<long long>();
    if (j.is_number_unsigned()) {
        unsigned long long u = j.get<unsigned long long>();
        return u > (unsigned long long)INT64_MAX ? RESURFI_GLTF_BAD : (long long)u;
    }
    return RESURFI_GLTF_BAD;
}

// Counts non-finite numbers (JSON has no literal for them, but 1e999 parses as infinity) and remembers where the
// first one is, as a JSON pointer.
void find_nonfinite(const nlohmann::json &j, std::string &where, size_t &count, std::string &first)
{
    if (j.is_number_float()) {
        if (!std::isfinite(j.get<double>())) {
            if (count++ == 0)
                first = where.empty() ? "/" : where;
        }
    } else if (j.is_object()) {
        for (auto it = j.begin(); it != j.end(); ++it) {
            size_t n = where.size();
            where += "/" + it.key();
            find_nonfinite(it.value(), where, count, first);
            where.resize(n);
        }
    } else if (j.is_array()) {
        for (size_t i = 0; i < j.size(); ++i) {
            size_t n = where.size();
            where += "/" + std::to_string(i);
            find_nonfinite(j[i], where, count, first);
            where.resize(n);
        }
    }
}

// The first buffer whose uri names an external file (not a data: URI), for a document in memory, which has no
// folder to read it from; -1 when there is none. *uri gets that uri, shortened and made printable for a message.
long long external_buffer(const nlohmann::json &root, std::string *uri)
{
    auto buffers = root.find("buffers");
    if (buffers == root.end() || !buffers->is_array())
        return -1;
    for (size_t i = 0; i < buffers->size(); ++i) {
        const nlohmann::json &b = (*buffers)[i];
        if (!b.is_object())
            continue;
        auto u = b.find("uri");
        if (u == b.end() || !u->is_string())
            continue;
        const std::string &s = u->get_ref<const std::string &>();
        if (s.compare(0, 5, "data:") == 0)
            continue;
        uri->clear();
        for (size_t k = 0; k < s.size() && k < 200; ++k)
            uri->push_back((unsigned char)s[k] < 0x20 || s[k] == 0x7f ? '?' : s[k]);
        if (s.size() > 200)
            *uri += "...";
        return (long long)i;
    }
    return -1;
}

// The names of the extensions found anywhere but on a mesh primitive, each once: only those can refer to data
// that a rewritten primitive no longer carries. Extras are walked too (a name found there is kept, to be safe).
void add_extension_names(const nlohmann::json &j, std::vector<std::string> &out)
{
    auto e = j.find("extensions");
    if (e != j.end() && e->is_object())
        for (auto it = e->begin(); it != e->end(); ++it)
            if (std::find(out.begin(), out.end(), it.key()) == out.end())
                out.push_back(it.key());
}

void all_extensions(const nlohmann::json &j, std::vector<std::string> &out)
{
    if (j.is_object()) {
        add_extension_names(j, out);
        for (const nlohmann::json &x : j)
            all_extensions(x, out);
    } else if (j.is_array()) {
        for (const nlohmann::json &x : j)
            all_extensions(x, out);
    }
}

// The TEXCOORD_n sets a material's textures sample (bit n), wherever they are: every textureInfo (an object with
// an "index") of the material and of its extensions samples its "texCoord" (default 0), and KHR_texture_transform
// may name another.
void texcoords_sampled(const nlohmann::json &j, unsigned &bits)
{
    if (j.is_object()) {
        auto set = [&bits](const nlohmann::json &o) {
            auto tc = o.find("texCoord");
            long long n = tc == o.end() ? 0 : tc->is_number_integer() ? tc->get<long long>() : -1;
            if (n >= 0 && n < 32)
                bits |= 1u << n;
        };
        if (j.contains("index") && j["index"].is_number())
            set(j);
        auto transform = j.find("KHR_texture_transform");
        if (transform != j.end() && transform->is_object() && transform->contains("texCoord"))
            set(*transform);
    }
    if (j.is_object() || j.is_array())
        for (const nlohmann::json &x : j)
            texcoords_sampled(x, bits);
}

void material_texcoords(const nlohmann::json &root, std::vector<unsigned> &out)
{
    auto materials = root.find("materials");
    if (materials == root.end() || !materials->is_array())
        return;
    for (const nlohmann::json &mat : *materials) {
        unsigned bits = 0;
        texcoords_sampled(mat, bits);
        out.push_back(bits);
    }
}

void outside_extensions(const nlohmann::json &root, std::vector<std::string> &out)
{
    add_extension_names(root, out);
    for (auto it = root.begin(); it != root.end(); ++it) {
        if (it.key() != "meshes" || !it->is_array()) {
            all_extensions(it.value(), out);
            continue;
        }
        for (const nlohmann::json &mesh : *it) {
            if (!mesh.is_object())
                continue;
            add_extension_names(mesh, out);
            for (auto m = mesh.begin(); m != mesh.end(); ++m) {
                if (m.key() != "primitives" || !m->is_array()) {
                    all_extensions(m.value(), out);
                    continue;
                }
                for (const nlohmann::json &p : *m) // a primitive's own extensions are left out, not their content
                    if (p.is_object())
                        for (auto f = p.begin(); f != p.end(); ++f) {
                            if (f.key() != "extensions" || !f->is_object()) {
                                all_extensions(f.value(), out);
                                continue;
                            }
                            for (const nlohmann::json &x : *f)
                                all_extensions(x, out);
                        }
            }
        }
    }
}

// Takes the Draco extensions (and their primitives' indices) out of the document. Returns true when it changed.
bool take_draco(nlohmann::json &root, std::map<std::pair<size_t, size_t>, DracoRecord> &out)
{
    bool changed = false;
    auto meshes = root.find("meshes");
    if (meshes == root.end() || !meshes->is_array())
        return false;
    for (size_t m = 0; m < meshes->size(); ++m) {
        nlohmann::json &mesh = (*meshes)[m];
        if (!mesh.is_object())
            continue;
        auto prims = mesh.find("primitives");
        if (prims == mesh.end() || !prims->is_array())
            continue;
        for (size_t p = 0; p < prims->size(); ++p) {
            nlohmann::json &prim = (*prims)[p];
            if (!prim.is_object())
                continue;
            auto exts = prim.find("extensions");
            if (exts == prim.end() || !exts->is_object())
                continue;
            auto draco = exts->find("KHR_draco_mesh_compression");
            if (draco == exts->end())
                continue;
            DracoRecord rec;
            rec.view = RESURFI_GLTF_NONE;
            rec.indices = RESURFI_GLTF_NONE;
            rec.malformed = true;
            if (draco->is_object()) {
                auto view = draco->find("bufferView");
                if (view != draco->end())
                    rec.view = json_index(*view);
                auto attrs = draco->find("attributes");
                if (attrs != draco->end() && attrs->is_object()) {
                    rec.malformed = false;
                    for (auto a = attrs->begin(); a != attrs->end(); ++a)
                        rec.attributes.emplace_back(a.key(), json_index(a.value()));
                }
            }
            auto indices = prim.find("indices");
            if (indices != prim.end()) {
                rec.indices = json_index(*indices);
                prim.erase(indices);
            }
            exts->erase(draco);
            if (exts->empty())
                prim.erase("extensions");
            out[std::make_pair(m, p)] = std::move(rec);
            changed = true;
        }
    }
    return changed;
}

// ---- tinygltf callbacks ---------------------------------------------------------------------------------------

struct FsContext {
    uint64_t max_bytes;
    bool no_files;  // a document in memory: nothing is read from the file system (parse() refuses such URIs first)
};

bool fs_exists(const std::string &path, void *user)
{
    if (static_cast<const FsContext *>(user)->no_files)
        return false;
    struct stat st;
    return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

// URIs are used as they are: no ~, $VAR or command expansion (tinygltf's default runs wordexp()).
std::string fs_expand(const std::string &path, void *) { return path; }

bool fs_read(std::vector<unsigned char> *out, std::string *err, const std::string &path, void *user)
{
    const FsContext *ctx = static_cast<const FsContext *>(user);
    if (ctx->no_files) {
        if (err)
            *err += "'" + path + "': a document in memory cannot read files\n";
        return false;
    }
    struct stat st;
    if (stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) {
        if (err)
            *err += "'" + path + "' is not a regular file\n";
        return false;
    }
    if ((uint64_t)st.st_size > ctx->max_bytes) {
        if (err)
            *err += "'" + path + "' is larger than the limit\n";
        return false;
    }
    std::ifstream f(path, std::ios::binary);
    if (!f) {
        if (err)
            *err += "cannot open '" + path + "'\n";
        return false;
    }
    out->resize((size_t)st.st_size);
    if (!out->empty() && !f.read(reinterpret_cast<char *>(out->data()), (std::streamsize)out->size())) {
        if (err)
            *err += "cannot read '" + path + "'\n";
        return false;
    }
    return true;
}

bool fs_write(std::string *err, const std::string &, const std::vector<unsigned char> &, void *)
{
    if (err)
        *err += "resurf writes files itself\n";
    return false;
}

// Images are never decoded: the encoded bytes of an embedded (data: URI) image are kept for the writer; an image
// in a bufferView stays there (the writer copies the bufferView), so its bytes are not kept twice.
bool keep_image_bytes(tinygltf::Image *image, const int, std::string *, std::string *, int, int,
                      const unsigned char *bytes, int size, void *)
{
    if (image->bufferView >= 0)
        return true;
    if (size > 0)
        image->image.assign(bytes, bytes + size);
    image->width = image->height = -1;
    image->as_is = true;
    return true;
}

int components_of(int type)
{
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
    }
}

// ---- the C view ---------------------------------------------------------------------------------------------

void add_ref(resurfi_gltf_doc *doc, std::string where, long long index, size_t limit)
{
    doc->strings.push_back(std::move(where));
    resurfi_gltf_ref r;
    r.where = doc->strings.back().c_str();
    r.index = index;
    r.limit = limit;
    doc->refs.push_back(r);
}

const char *keep(resurfi_gltf_doc *doc, const std::string &s)
{
    doc->strings.push_back(s);
    return doc->strings.back().c_str();
}

void add_texture_ref(resurfi_gltf_doc *doc, const std::string &where, int index)
{
    if (index != -1)
        add_ref(doc, where + ".index", index, doc->model.textures.size());
}

void build_view(resurfi_gltf_doc *doc)
{
    const tinygltf::Model &m = doc->model;
    resurfi_gltf_view &v = doc->view;

    for (const tinygltf::Buffer &b : m.buffers)
        doc->buffers.push_back(resurfi_gltf_buffer{b.data.data(), b.data.size()});
    for (const tinygltf::BufferView &bv : m.bufferViews)
        doc->views.push_back(resurfi_gltf_buffer_view{bv.buffer, bv.byteOffset, bv.byteLength, bv.byteStride});
    for (const tinygltf::Accessor &a : m.accessors) {
        resurfi_gltf_accessor c;
        std::memset(&c, 0, sizeof c);
        c.buffer_view = a.bufferView;
        c.byte_offset = a.byteOffset;
        c.component_type = a.componentType;
        c.normalized = a.normalized;
        c.count = a.count;
        c.components = components_of(a.type);
        c.matrix = a.type == TINYGLTF_TYPE_MAT2 || a.type == TINYGLTF_TYPE_MAT3 || a.type == TINYGLTF_TYPE_MAT4;
        c.sparse = a.sparse.isSparse;
        if (c.sparse) {
            c.sparse_count = a.sparse.count;
            c.sparse_indices_view = a.sparse.indices.bufferView;
            c.sparse_indices_offset = a.sparse.indices.byteOffset;
            c.sparse_indices_type = a.sparse.indices.componentType;
            c.sparse_values_view = a.sparse.values.bufferView;
            c.sparse_values_offset = a.sparse.values.byteOffset;
        }
        doc->accessors.push_back(c);
    }

    // Primitives: named lists first (their addresses must not move), then the structs pointing into them.
    size_t prim_total = 0;
    for (const tinygltf::Mesh &mesh : m.meshes)
        prim_total += mesh.primitives.size();
    doc->prims.resize(prim_total);
    doc->prim_extensions.resize(prim_total);
    doc->named.resize(prim_total * 3);
    doc->target_begin.resize(prim_total);
    size_t k = 0;
    for (size_t mi = 0; mi < m.meshes.size(); ++mi) {
        const tinygltf::Mesh &mesh = m.meshes[mi];
        for (size_t pi = 0; pi < mesh.primitives.size(); ++pi, ++k) {
            const tinygltf::Primitive &p = mesh.primitives[pi];
            resurfi_gltf_primitive &c = doc->prims[k];
            std::memset(&c, 0, sizeof c);
            std::vector<resurfi_gltf_named> &attrs = doc->named[3 * k];
            for (const auto &a : p.attributes)
                attrs.push_back(resurfi_gltf_named{keep(doc, a.first), a.second});
            std::vector<resurfi_gltf_named> &targets = doc->named[3 * k + 1];
            std::vector<size_t> &begin = doc->target_begin[k];
            for (const auto &t : p.targets) {
                begin.push_back(targets.size());
                for (const auto &a : t)
                    targets.push_back(resurfi_gltf_named{keep(doc, a.first), a.second});
            }
            begin.push_back(targets.size());
            c.mode = p.mode;
            c.indices = p.indices;
            c.attribute_count = attrs.size();
            c.attributes = attrs.data();
            c.target_count = p.targets.size();
            c.target_begin = begin.data();
            c.target_attributes = targets.data();
            for (const auto &e : p.extensions)
                doc->prim_extensions[k].push_back(keep(doc, e.first));
            c.extension_count = doc->prim_extensions[k].size();
            c.extensions = doc->prim_extensions[k].data();
            c.material = p.material < 0 ? RESURFI_GLTF_NONE : p.material;
            if (p.material != -1)
                add_ref(doc, "meshes[" + std::to_string(mi) + "].primitives[" + std::to_string(pi) + "].material",
                        p.material, m.materials.size());
            auto d = doc->draco.find(std::make_pair(mi, pi));
            if (d != doc->draco.end()) {
                std::vector<resurfi_gltf_named> &ids = doc->named[3 * k + 2];
                for (const auto &a : d->second.attributes)
                    ids.push_back(resurfi_gltf_named{keep(doc, a.first), a.second});
                c.draco = 1;
                c.draco_malformed = d->second.malformed;
                c.draco_view = d->second.view;
                c.indices = d->second.indices;
                c.draco_attribute_count = ids.size();
                c.draco_attributes = ids.data();
            }
        }
    }
    k = 0;
    for (const tinygltf::Mesh &mesh : m.meshes) {
        doc->meshes.push_back(resurfi_gltf_mesh{keep(doc, mesh.name), mesh.primitives.size(), doc->prims.data() + k});
        k += mesh.primitives.size();
    }

    std::vector<char> animated(m.nodes.size(), 0);
    for (const tinygltf::Animation &a : m.animations)
        for (const tinygltf::AnimationChannel &c : a.channels)
            if (c.target_node >= 0 && (size_t)c.target_node < m.nodes.size() &&
                (c.target_path == "translation" || c.target_path == "rotation" || c.target_path == "scale"))
                animated[(size_t)c.target_node] = 1;
    doc->children.resize(m.nodes.size());
    doc->lod_ids.resize(m.nodes.size());
    doc->coverage.resize(m.nodes.size());
    for (size_t ni = 0; ni < m.nodes.size(); ++ni) {
        const tinygltf::Node &n = m.nodes[ni];
        resurfi_gltf_node c;
        std::memset(&c, 0, sizeof c);
        c.mesh = n.mesh;
        c.skin = n.skin;
        c.camera = n.camera;
        c.animated = animated[ni];
        doc->children[ni].assign(n.children.begin(), n.children.end());
        c.child_count = n.children.size();
        c.children = doc->children[ni].data();
        c.matrix_count = n.matrix.size();
        c.translation_count = n.translation.size();
        c.rotation_count = n.rotation.size();
        c.scale_count = n.scale.size();
        for (size_t i = 0; i < n.matrix.size() && i < 16; ++i)
            c.matrix[i] = n.matrix[i];
        for (size_t i = 0; i < n.translation.size() && i < 3; ++i)
            c.translation[i] = n.translation[i];
        for (size_t i = 0; i < n.rotation.size() && i < 4; ++i)
            c.rotation[i] = n.rotation[i];
        for (size_t i = 0; i < n.scale.size() && i < 3; ++i)
            c.scale[i] = n.scale[i];
        auto lod = n.extensions.find("MSFT_lod");
        if (lod != n.extensions.end() && lod->second.IsObject() && lod->second.Has("ids") &&
            lod->second.Get("ids").IsArray()) {
            const tinygltf::Value &ids = lod->second.Get("ids");
            for (size_t i = 0; i < ids.ArrayLen(); ++i)
                doc->lod_ids[ni].push_back(ids.Get((int)i).IsInt() ? (long long)ids.Get((int)i).GetNumberAsInt()
                                                                   : RESURFI_GLTF_BAD);
            if (n.extras.IsObject() && n.extras.Has("MSFT_screencoverage") &&
                n.extras.Get("MSFT_screencoverage").IsArray()) {
                const tinygltf::Value &cov = n.extras.Get("MSFT_screencoverage");
                for (size_t i = 0; i < cov.ArrayLen() && cov.Get((int)i).IsNumber(); ++i)
                    doc->coverage[ni].push_back(cov.Get((int)i).GetNumberAsDouble());
                if (doc->coverage[ni].size() != cov.ArrayLen())
                    doc->coverage[ni].clear();
            }
        }
        c.lod_count = doc->lod_ids[ni].size();
        c.lod_ids = doc->lod_ids[ni].data();
        c.coverage_count = doc->coverage[ni].size();
        c.coverage = doc->coverage[ni].data();
        std::string where = "nodes[" + std::to_string(ni) + "]";
        // EXT_mesh_gpu_instancing: every attribute is an accessor the writer keeps (a checked reference), and
        // TRANSLATION, ROTATION and SCALE place the instances in the world.
        c.instance_attributes[0] = c.instance_attributes[1] = c.instance_attributes[2] = RESURFI_GLTF_NONE;
        auto instancing = n.extensions.find("EXT_mesh_gpu_instancing");
        if (instancing != n.extensions.end() && instancing->second.IsObject() && instancing->second.Has("attributes")) {
            static const char *const trs[3] = {"TRANSLATION", "ROTATION", "SCALE"};
            const tinygltf::Value &at = instancing->second.Get("attributes");
            std::string w = where + ".extensions.EXT_mesh_gpu_instancing.attributes";
            if (!at.IsObject())
                add_ref(doc, w, RESURFI_GLTF_BAD, m.accessors.size());
            c.has_instances = at.IsObject();
            for (const std::string &key : at.IsObject() ? at.Keys() : std::vector<std::string>()) {
                long long id = at.Get(key).IsInt() ? (long long)at.Get(key).GetNumberAsInt() : RESURFI_GLTF_BAD;
                add_ref(doc, w + "." + key, id, m.accessors.size());
                for (int k = 0; k < 3; ++k)
                    if (key == trs[k])
                        c.instance_attributes[k] = id;
            }
        }
        doc->nodes.push_back(c);
        if (n.skin != -1)
            add_ref(doc, where + ".skin", n.skin, m.skins.size());
        if (n.camera != -1)
            add_ref(doc, where + ".camera", n.camera, m.cameras.size());
    }
    doc->scene_nodes.resize(m.scenes.size());
    for (size_t si = 0; si < m.scenes.size(); ++si) {
        doc->scene_nodes[si].assign(m.scenes[si].nodes.begin(), m.scenes[si].nodes.end());
        doc->scenes.push_back(resurfi_gltf_scene{doc->scene_nodes[si].size(), doc->scene_nodes[si].data()});
    }

    for (size_t i = 0; i < m.materials.size(); ++i) {
        const tinygltf::Material &mat = m.materials[i];
        std::string where = "materials[" + std::to_string(i) + "]";
        add_texture_ref(doc, where + ".pbrMetallicRoughness.baseColorTexture",
                        mat.pbrMetallicRoughness.baseColorTexture.index);
        add_texture_ref(doc, where + ".pbrMetallicRoughness.metallicRoughnessTexture",
                        mat.pbrMetallicRoughness.metallicRoughnessTexture.index);
        add_texture_ref(doc, where + ".normalTexture", mat.normalTexture.index);
        add_texture_ref(doc, where + ".occlusionTexture", mat.occlusionTexture.index);
        add_texture_ref(doc, where + ".emissiveTexture", mat.emissiveTexture.index);
        resurfi_gltf_material c{{1, 1, 1, 1}, RESURFI_GLTF_NONE, 0,
                                i < doc->material_texcoords.size() ? doc->material_texcoords[i] : 0};
        const std::vector<double> &factor = mat.pbrMetallicRoughness.baseColorFactor;
        for (size_t j = 0; j < 4 && j < factor.size(); ++j)
            c.base_color[j] = factor[j];
        const tinygltf::TextureInfo &base = mat.pbrMetallicRoughness.baseColorTexture;
        if (base.index >= 0) {
            c.base_color_texture = base.index;
            c.base_color_texcoord = base.texCoord;
        }
        doc->materials.push_back(c);
    }
    for (size_t i = 0; i < m.textures.size(); ++i) {
        std::string where = "textures[" + std::to_string(i) + "]";
        if (m.textures[i].source != -1)
            add_ref(doc, where + ".source", m.textures[i].source, m.images.size());
        if (m.textures[i].sampler != -1)
            add_ref(doc, where + ".sampler", m.textures[i].sampler, m.samplers.size());
        resurfi_gltf_texture c{m.textures[i].source < 0 ? RESURFI_GLTF_NONE : m.textures[i].source, 10497, 10497};
        int sampler = m.textures[i].sampler;
        if (sampler >= 0 && (size_t)sampler < m.samplers.size()) {
            c.wrap_s = m.samplers[sampler].wrapS;
            c.wrap_t = m.samplers[sampler].wrapT;
        }
        doc->textures.push_back(c);
    }
    for (size_t i = 0; i < m.images.size(); ++i) {
        const tinygltf::Image &img = m.images[i];
        if (img.bufferView != -1)
            add_ref(doc, "images[" + std::to_string(i) + "].bufferView", img.bufferView, m.bufferViews.size());
        resurfi_gltf_image c;
        c.uri = keep(doc, img.uri);
        c.mime_type = keep(doc, img.mimeType);
        c.buffer_view = img.bufferView < 0 ? RESURFI_GLTF_NONE : img.bufferView;
        c.data = img.bufferView < 0 && img.uri.empty() && !img.image.empty() ? img.image.data() : nullptr;
        c.size = c.data ? img.image.size() : 0;
        doc->images.push_back(c);
    }
    for (size_t i = 0; i < m.skins.size(); ++i) {
        const tinygltf::Skin &s = m.skins[i];
        std::string where = "skins[" + std::to_string(i) + "]";
        if (s.inverseBindMatrices != -1)
            add_ref(doc, where + ".inverseBindMatrices", s.inverseBindMatrices, m.accessors.size());
        if (s.skeleton != -1)
            add_ref(doc, where + ".skeleton", s.skeleton, m.nodes.size());
        for (size_t j = 0; j < s.joints.size(); ++j)
            add_ref(doc, where + ".joints[" + std::to_string(j) + "]", s.joints[j], m.nodes.size());
    }
    for (size_t i = 0; i < m.animations.size(); ++i) {
        const tinygltf::Animation &a = m.animations[i];
        std::string where = "animations[" + std::to_string(i) + "]";
        for (size_t j = 0; j < a.samplers.size(); ++j) {
            std::string w = where + ".samplers[" + std::to_string(j) + "]";
            add_ref(doc, w + ".input", a.samplers[j].input, m.accessors.size());
            add_ref(doc, w + ".output", a.samplers[j].output, m.accessors.size());
        }
        for (size_t j = 0; j < a.channels.size(); ++j) {
            std::string w = where + ".channels[" + std::to_string(j) + "]";
            add_ref(doc, w + ".sampler", a.channels[j].sampler, a.samplers.size());
            if (a.channels[j].target_node != -1)
                add_ref(doc, w + ".target.node", a.channels[j].target_node, m.nodes.size());
        }
    }

    for (const std::string &e : m.extensionsUsed)
        doc->ext_used.push_back(keep(doc, e));
    for (const std::string &e : m.extensionsRequired)
        doc->ext_required.push_back(keep(doc, e));
    for (const std::string &w : doc->warnings)
        doc->warning_ptrs.push_back(w.c_str());
    for (const std::string &e : doc->outside_extensions)
        doc->outside_ptrs.push_back(e.c_str());

    v.buffer_count = doc->buffers.size();
    v.buffers = doc->buffers.data();
    v.buffer_view_count = doc->views.size();
    v.buffer_views = doc->views.data();
    v.accessor_count = doc->accessors.size();
    v.accessors = doc->accessors.data();
    v.mesh_count = doc->meshes.size();
    v.meshes = doc->meshes.data();
    v.node_count = doc->nodes.size();
    v.nodes = doc->nodes.data();
    v.scene_count = doc->scenes.size();
    v.scenes = doc->scenes.data();
    v.default_scene = m.defaultScene;
    v.ref_count = doc->refs.size();
    v.refs = doc->refs.data();
    v.nonfinite_count = doc->nonfinite_count;
    v.first_nonfinite = doc->first_nonfinite.c_str();
    v.extension_used_count = doc->ext_used.size();
    v.extensions_used = doc->ext_used.data();
    v.extension_required_count = doc->ext_required.size();
    v.extensions_required = doc->ext_required.data();
    v.warning_count = doc->warning_ptrs.size();
    v.warnings = doc->warning_ptrs.data();
    v.image_count = doc->images.size();
    v.images = doc->images.data();
    v.material_count = doc->materials.size();
    v.materials = doc->materials.data();
    v.texture_count = doc->textures.size();
    v.textures = doc->textures.data();
    v.outside_extension_count = doc->outside_ptrs.size();
    v.outside_extensions = doc->outside_ptrs.data();
}

// Schema problems a lenient load lists one warning each; more are counted in one last warning.
constexpr size_t MAX_SCHEMA_WARNINGS = 100;

resurf_status parse(const char *json, size_t json_size, const unsigned char *bin, size_t bin_size, int is_glb,
                    const char *base_dir, const char *name, uint64_t max_external_bytes, int lenient,
                    resurfi_gltf_doc **out_doc, resurf_error *error)
{
    std::unique_ptr<resurfi_gltf_doc> doc(new resurfi_gltf_doc());

    nlohmann::json root;
    try {
        root = nlohmann::json::parse(json, json + json_size);
    } catch (const nlohmann::json::out_of_range &e) {
        // nlohmann refuses numbers that overflow a double (1e999): they would be infinite.
        std::string what = e.what();
        size_t at = what.find("parsing '");
        return resurfi_fail(error, RESURF_ERR_PARSE, name, 0, -1, "a number of the JSON is not finite: %s",
                            at == std::string::npos ? what.c_str() : what.c_str() + at + 8);
    } catch (const nlohmann::json::parse_error &e) {
        std::string what = e.what();
        size_t colon = what.rfind(": ");
        return resurfi_fail(error, RESURF_ERR_PARSE, name, 0, (long long)e.byte - (e.byte > 0),
                            "the JSON is malformed: %s", colon == std::string::npos ? what.c_str()
                                                                                    : what.c_str() + colon + 2);
    }
    if (!root.is_object())
        return resurfi_fail(error, RESURF_ERR_PARSE, name, 0, -1, "the JSON is not an object");
    std::vector<std::string> problems;
    bool integers_rewritten = false;
    size_t problem_count =
        resurfi_gltf_schema_check(root, lenient ? MAX_SCHEMA_WARNINGS : 1, &problems, &integers_rewritten);
    if (problem_count && !lenient)
        return resurfi_fail(error, RESURF_ERR_PARSE, name, 0, -1, "%s", problems[0].c_str());
    doc->warnings = std::move(problems);
    if (problem_count > doc->warnings.size())
        doc->warnings.push_back(std::to_string(problem_count - doc->warnings.size()) +
                                " more problems with the glTF schema");
    for (auto [key, out] : {std::make_pair("extensionsUsed", &doc->file_extensions_used),
                            std::make_pair("extensionsRequired", &doc->file_extensions_required)}) {
        auto names = root.find(key);
        for (size_t i = 0; names != root.end() && names->is_array() && i < names->size(); ++i)
            if ((*names)[i].is_string())
                out->push_back((*names)[i].get<std::string>());
    }
    // A required EXT_ or KHR_meshopt_compression is prepared for decoding after tinygltf's reading (gltf_meshopt.cpp).
    std::vector<MeshoptView> meshopt_views;
    std::vector<MeshoptPlaceholder> meshopt_holders;
    std::string meshopt_problem;
    if (!meshopt_prepare(root, is_glb != 0, meshopt_views, meshopt_holders, meshopt_problem))
        return resurfi_fail(error, RESURF_ERR_PARSE, name, 0, -1, "%s", meshopt_problem.c_str());
    // A required extension resurf cannot read refuses the document before tinygltf reads what it changes.
    auto required = root.find("extensionsRequired");
    if (required != root.end() && required->is_array())
        for (const nlohmann::json &e : *required)
            if (e.is_string() && !resurfi_scene_extension_known(e.get_ref<const std::string &>().c_str()))
                return resurfi_fail(error, RESURF_ERR_UNSUPPORTED, name, 0, -1,
                                    "the document requires the extension %s, which resurf does not support",
                                    e.get_ref<const std::string &>().c_str());
    if (!base_dir) {
        std::string uri;
        long long b = external_buffer(root, &uri);
        if (b >= 0)
            return resurfi_fail(error, RESURF_ERR_PARSE, name, 0, -1,
                                "buffers[%lld]: the uri '%s' names an external file, which a document loaded from "
                                "memory cannot refer to",
                                b, uri.c_str());
    }
    bool meshopt_dropped = drop_optional_meshopt(root);
    std::string where;
    find_nonfinite(root, where, doc->nonfinite_count, doc->first_nonfinite);
    outside_extensions(root, doc->outside_extensions);
    material_texcoords(root, doc->material_texcoords);
    std::string rewritten;
    if (take_draco(root, doc->draco) || integers_rewritten || meshopt_dropped || !meshopt_views.empty())
        rewritten = root.dump();
    root = nlohmann::json();

    tinygltf::TinyGLTF loader;
    FsContext fs_ctx{max_external_bytes, base_dir == nullptr};
    tinygltf::FsCallbacks fs = {&fs_exists, &fs_expand, &fs_read, &fs_write, &fs_ctx};
    loader.SetFsCallbacks(fs);
    loader.SetImageLoader(&keep_image_bytes, nullptr);
    loader.SetImageWriter(nullptr, nullptr);
    std::string err, warn;
    const char *text = rewritten.empty() ? json : rewritten.data();
    size_t text_size = rewritten.empty() ? json_size : rewritten.size();
    std::string dir = base_dir ? base_dir : "";
    bool ok;
    if (is_glb) {
        // tinygltf reads a .glb from memory only: put the (possibly rewritten) JSON and the BIN chunk back into a
        // container. The C side has checked the original container already.
        size_t json_padded = (text_size + 3) & ~(size_t)3, bin_padded = (bin_size + 3) & ~(size_t)3;
        uint64_t total = 12 + 8 + (uint64_t)json_padded + (bin_size ? 8 + (uint64_t)bin_padded : 0);
        if (total > 0xffffffffu)
            return resurfi_fail(error, RESURF_ERR_LIMIT, name, 0, -1, "the .glb is larger than 4 GiB");
        std::vector<unsigned char> glb((size_t)total, 0);
        auto put32 = [&](size_t at, uint32_t x) {
            for (int i = 0; i < 4; ++i)
                glb[at + i] = (unsigned char)(x >> (8 * i));
        };
        std::memcpy(glb.data(), "glTF", 4);
        put32(4, 2);
        put32(8, (uint32_t)total);
        put32(12, (uint32_t)json_padded);
        put32(16, 0x4E4F534Au);
        std::memcpy(glb.data() + 20, text, text_size);
        std::memset(glb.data() + 20 + text_size, ' ', json_padded - text_size);
        if (bin_size) {
            size_t at = 20 + json_padded;
            put32(at, (uint32_t)bin_padded);
            put32(at + 4, 0x004E4942u);
            std::memcpy(glb.data() + at + 8, bin, bin_size);
        }
        ok = loader.LoadBinaryFromMemory(&doc->model, &err, &warn, glb.data(), (unsigned)glb.size(), dir);
    } else {
        if (text_size > 0xffffffffu)
            return resurfi_fail(error, RESURF_ERR_LIMIT, name, 0, -1, "the JSON is larger than 4 GiB");
        ok = loader.LoadASCIIFromString(&doc->model, &err, &warn, text, (unsigned)text_size, dir);
    }
    if (!ok) {
        std::string line = first_line(err);
        return resurfi_fail(error, RESURF_ERR_PARSE, name, 0, -1, "%s",
                            line.empty() ? "tinygltf could not read the document" : line.c_str());
    }
    if (!meshopt_decode(doc->model, meshopt_views, meshopt_holders, meshopt_problem))
        return resurfi_fail(error, RESURF_ERR_PARSE, name, 0, -1, "%s", meshopt_problem.c_str());
    // The Draco records are keyed by the JSON's mesh and primitive positions: tinygltf must have kept them all.
    for (const auto &d : doc->draco)
        if (d.first.first >= doc->model.meshes.size() ||
            d.first.second >= doc->model.meshes[d.first.first].primitives.size())
            return resurfi_fail(error, RESURF_ERR_PARSE, name, 0, -1,
                                "meshes[%zu].primitives[%zu]: the primitive was not read", d.first.first,
                                d.first.second);
    for (size_t begin = 0; begin < warn.size();) {
        size_t end = warn.find('\n', begin);
        if (end == std::string::npos)
            end = warn.size();
        if (end > begin)
            doc->warnings.push_back("tinygltf: " + warn.substr(begin, end - begin));
        begin = end + 1;
    }
    build_view(doc.get());
    *out_doc = doc.release();
    return RESURF_OK;
}

} // namespace

extern "C" resurf_status resurfi_gltf_parse(const char *json, size_t json_size, const unsigned char *bin,
                                            size_t bin_size, int is_glb, const char *base_dir, const char *name,
                                            uint64_t max_external_bytes, int lenient, resurfi_gltf_doc **out_doc,
                                            resurf_error *error)
{
    *out_doc = nullptr;
    try {
        return parse(json, json_size, bin, bin_size, is_glb, base_dir, name, max_external_bytes, lenient, out_doc,
                     error);
    } catch (const std::bad_alloc &) {
        return resurfi_fail(error, RESURF_ERR_OUT_OF_MEMORY, name, 0, -1, "out of memory reading the glTF document");
    } catch (const std::exception &e) {
        return resurfi_fail(error, RESURF_ERR_PARSE, name, 0, -1, "the glTF document cannot be read: %s", e.what());
    } catch (...) {
        return resurfi_fail(error, RESURF_ERR_INTERNAL, name, 0, -1, "unexpected exception reading the document");
    }
}

extern "C" const resurfi_gltf_view *resurfi_gltf_doc_view(const resurfi_gltf_doc *doc) { return &doc->view; }

extern "C" void resurfi_gltf_doc_free(resurfi_gltf_doc *doc) { delete doc; }
