// Writing glTF 2.0 with tinygltf: a fresh document assembled from the loaded one and the plan scene_save.c built
// (gltf_shim.h). Nothing of the loaded model is re-saved as it is: tinygltf would write back whatever it holds, and
// the plan decides what the output contains.
//
// Layout of the output: one buffer. It holds, in this order, the source bufferViews that are still needed
// (animations, skins, images, untouched primitives), the images the plan embeds (external files, data: URIs), the
// plan's new accessors and the Draco payloads. Each bufferView starts on a 4-byte boundary (glTF 2.0, 3.6.2.4).
// MSFT_lod (Microsoft vendor extension) and the side-by-side copies are built here from the plan's level table.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <new>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "gltf_internal.hpp"

namespace {

struct Writer {
    const tinygltf::Model &src;
    const resurfi_gltf_doc *doc;
    const resurfi_gltf_plan &plan;
    tinygltf::Model out;
    std::vector<unsigned char> bin;
    std::vector<long long> accessor_map, view_map; // source index → output index, -1 when dropped
    std::map<const unsigned char *, int> draco_views;
    std::set<std::string> dropped; // extensions left off rewritten primitives

    Writer(const tinygltf::Model &s, const resurfi_gltf_doc *d, const resurfi_gltf_plan &p) : src(s), doc(d), plan(p) {}

    // Appends bytes on a 4-byte boundary and returns a new bufferView over them.
    int add_view(const void *data, size_t size, size_t stride, int target)
    {
        while (bin.size() % 4)
            bin.push_back(0);
        size_t offset = bin.size();
        const unsigned char *p = static_cast<const unsigned char *>(data);
        bin.insert(bin.end(), p, p + size);
        tinygltf::BufferView v;
        v.buffer = 0;
        v.byteOffset = offset;
        v.byteLength = size;
        v.byteStride = stride;
        v.target = target;
        out.bufferViews.push_back(v);
        return (int)out.bufferViews.size() - 1;
    }

    int map_accessor(long long a) const { return a < 0 ? -1 : (int)accessor_map.at((size_t)a); }
    int map_view(long long v) const { return v < 0 ? -1 : (int)view_map.at((size_t)v); }

    const DracoRecord *draco_of(size_t mesh, size_t prim) const
    {
        if (!doc)
            return nullptr;
        auto it = doc->draco.find(std::make_pair(mesh, prim));
        return it == doc->draco.end() ? nullptr : &it->second;
    }

    void mark_primitive(const tinygltf::Primitive &p, const DracoRecord *d, std::vector<char> &acc,
                        std::vector<char> &views)
    {
        for (const auto &a : p.attributes)
            acc.at((size_t)a.second) = 1;
        for (const auto &t : p.targets)
            for (const auto &a : t)
                acc.at((size_t)a.second) = 1;
        long long indices = d ? d->indices : p.indices;
        if (indices >= 0)
            acc.at((size_t)indices) = 1;
        if (d)
            views.at((size_t)d->view) = 1;
    }

    // The accessors a node's EXT_mesh_gpu_instancing names (checked by the reader: each exists).
    static std::vector<int> instancing_accessors(const tinygltf::Node &n)
    {
        std::vector<int> out;
        auto gi = n.extensions.find("EXT_mesh_gpu_instancing");
        if (gi != n.extensions.end() && gi->second.IsObject() && gi->second.Has("attributes"))
            for (const std::string &key : gi->second.Get("attributes").Keys())
                out.push_back(gi->second.Get("attributes").Get(key).GetNumberAsInt());
        return out;
    }

    // Which source accessors and bufferViews the output still needs, and their new indices (source order kept).
    void keep_source_data()
    {
        std::vector<char> acc(src.accessors.size(), plan.keep_all_source_data ? 1 : 0);
        std::vector<char> views(src.bufferViews.size(), plan.keep_all_source_data ? 1 : 0);
        for (const tinygltf::Animation &a : src.animations)
            for (const tinygltf::AnimationSampler &s : a.samplers) {
                acc.at((size_t)s.input) = 1;
                acc.at((size_t)s.output) = 1;
            }
        for (const tinygltf::Skin &s : src.skins)
            if (s.inverseBindMatrices >= 0)
                acc.at((size_t)s.inverseBindMatrices) = 1;
        for (const tinygltf::Node &n : src.nodes)
            for (int a : instancing_accessors(n))
                acc.at((size_t)a) = 1;
        for (size_t m = 0; m < plan.mesh_count; ++m)
            for (size_t i = 0; i < plan.meshes[m].primitive_count; ++i) {
                const resurfi_gltf_out_primitive &p = plan.meshes[m].primitives[i];
                if (p.verbatim)
                    mark_primitive(src.meshes.at(p.source_mesh).primitives.at(p.source_primitive),
                                   draco_of(p.source_mesh, p.source_primitive), acc, views);
            }
        for (const tinygltf::Image &img : src.images)
            if (img.bufferView >= 0)
                views.at((size_t)img.bufferView) = 1;
        for (size_t a = 0; a < src.accessors.size(); ++a) {
            if (!acc[a])
                continue;
            const tinygltf::Accessor &x = src.accessors[a];
            if (x.bufferView >= 0)
                views.at((size_t)x.bufferView) = 1;
            if (x.sparse.isSparse) {
                views.at((size_t)x.sparse.indices.bufferView) = 1;
                views.at((size_t)x.sparse.values.bufferView) = 1;
            }
        }
        view_map.assign(src.bufferViews.size(), -1);
        for (size_t v = 0; v < src.bufferViews.size(); ++v) {
            if (!views[v])
                continue;
            const tinygltf::BufferView &bv = src.bufferViews[v];
            const tinygltf::Buffer &b = src.buffers.at((size_t)bv.buffer);
            int nv = add_view(b.data.data() + bv.byteOffset, bv.byteLength, bv.byteStride, bv.target);
            out.bufferViews[(size_t)nv].name = bv.name;
            out.bufferViews[(size_t)nv].extras = bv.extras;
            out.bufferViews[(size_t)nv].extensions = bv.extensions;
            view_map[v] = nv;
        }
        accessor_map.assign(src.accessors.size(), -1);
        for (size_t a = 0; a < src.accessors.size(); ++a) {
            if (!acc[a])
                continue;
            tinygltf::Accessor x = src.accessors[a];
            x.bufferView = map_view(x.bufferView);
            if (x.sparse.isSparse) {
                x.sparse.indices.bufferView = map_view(x.sparse.indices.bufferView);
                x.sparse.values.bufferView = map_view(x.sparse.values.bufferView);
            }
            out.accessors.push_back(x);
            accessor_map[a] = (long long)out.accessors.size() - 1;
        }
    }

    // Images as the plan says: bytes into the buffer (external files for a .glb, data: URIs always: a .glb
    // cannot hold data: URIs worth having), a new uri (a copy beside a .gltf), or the source's bufferView.
    void copy_images()
    {
        for (size_t i = 0; i < src.images.size(); ++i) {
            const tinygltf::Image &img = src.images[i];
            tinygltf::Image o;
            o.name = img.name;
            o.uri = img.uri;
            o.mimeType = img.mimeType;
            o.extras = img.extras;
            o.extensions = img.extensions;
            o.bufferView = map_view(img.bufferView);
            const resurfi_gltf_out_image *p = plan.images ? &plan.images[i] : nullptr;
            if (p && p->data) {
                o.uri.clear();
                o.mimeType = p->mime_type;
                o.bufferView = add_view(p->data, p->size, 0, 0);
            } else if (p && p->uri) {
                o.uri = p->uri;
            }
            out.images.push_back(o);
        }
    }

    int add_plan_accessors()
    {
        int first = (int)out.accessors.size();
        for (size_t i = 0; i < plan.accessor_count; ++i) {
            const resurfi_gltf_out_accessor &a = plan.accessors[i];
            tinygltf::Accessor x;
            x.componentType = a.component_type;
            x.normalized = a.normalized != 0;
            x.count = (size_t)a.count;
            x.type = a.components == 1   ? TINYGLTF_TYPE_SCALAR
                     : a.components == 2 ? TINYGLTF_TYPE_VEC2
                     : a.components == 3 ? TINYGLTF_TYPE_VEC3
                     : a.components == 4 ? TINYGLTF_TYPE_VEC4
                                         : TINYGLTF_TYPE_MAT4;
            x.byteOffset = 0;
            x.bufferView = a.data ? add_view(a.data, a.data_size, 0, a.target) : -1;
            if (a.has_bounds) {
                x.minValues.assign(a.min, a.min + a.components);
                x.maxValues.assign(a.max, a.max + a.components);
            }
            out.accessors.push_back(x);
        }
        return first;
    }

    static tinygltf::Value draco_extension(int view, const std::vector<std::pair<std::string, long long>> &ids)
    {
        tinygltf::Value::Object attrs;
        for (const auto &a : ids)
            attrs[a.first] = tinygltf::Value((int)a.second);
        tinygltf::Value::Object ext;
        ext["bufferView"] = tinygltf::Value(view);
        ext["attributes"] = tinygltf::Value(attrs);
        return tinygltf::Value(ext);
    }

    tinygltf::Primitive build_primitive(const resurfi_gltf_out_primitive &p, int plan_base)
    {
        const tinygltf::Primitive *sp = nullptr;
        if (p.source_mesh < src.meshes.size() && p.source_primitive < src.meshes[p.source_mesh].primitives.size())
            sp = &src.meshes[p.source_mesh].primitives[p.source_primitive];
        tinygltf::Primitive o;
        if (p.verbatim) {
            const DracoRecord *d = draco_of(p.source_mesh, p.source_primitive);
            o = *sp;
            for (auto &a : o.attributes)
                a.second = map_accessor(a.second);
            for (auto &t : o.targets)
                for (auto &a : t)
                    a.second = map_accessor(a.second);
            o.indices = map_accessor(d ? d->indices : sp->indices);
            if (d)
                o.extensions["KHR_draco_mesh_compression"] = draco_extension(map_view(d->view), d->attributes);
            return o;
        }
        if (sp) {
            o.material = sp->material;
            o.extras = sp->extras;
            // Only the extensions that hold with new triangles and vertices stay (not FB_ngon_encoding, which
            // describes the source's triangle order, nor any that may).
            for (const auto &e : sp->extensions) {
                bool kept = false;
                for (size_t k = 0; k < plan.kept_extension_count && !kept; ++k)
                    kept = e.first == plan.kept_extensions[k];
                if (kept)
                    o.extensions.insert(e);
                else
                    dropped.insert(e.first);
            }
        }
        o.mode = TINYGLTF_MODE_TRIANGLES;
        for (size_t i = 0; i < p.attribute_count; ++i)
            o.attributes[p.attributes[i].name] = plan_base + (int)p.attributes[i].index;
        o.indices = p.indices < 0 ? -1 : plan_base + (int)p.indices;
        for (size_t t = 0; t < p.target_count; ++t) {
            std::map<std::string, int> target;
            for (size_t i = p.target_begin[t]; i < p.target_begin[t + 1]; ++i)
                target[p.target_attributes[i].name] = plan_base + (int)p.target_attributes[i].index;
            o.targets.push_back(target);
        }
        if (p.draco) {
            // A primitive shown at several levels shares one payload (and one bufferView).
            auto known = draco_views.find(p.draco);
            int view = known != draco_views.end() ? known->second : add_view(p.draco, p.draco_size, 0, 0);
            draco_views[p.draco] = view;
            std::vector<std::pair<std::string, long long>> ids;
            for (size_t i = 0; i < p.attribute_count; ++i)
                ids.emplace_back(p.draco_ids[i].name, p.draco_ids[i].index);
            o.extensions["KHR_draco_mesh_compression"] = draco_extension(view, ids);
        }
        return o;
    }

    void build_meshes(int plan_base)
    {
        for (size_t i = 0; i < plan.mesh_count; ++i) {
            const resurfi_gltf_out_mesh &pm = plan.meshes[i];
            tinygltf::Mesh m;
            if (pm.source_mesh < src.meshes.size()) {
                const tinygltf::Mesh &sm = src.meshes[pm.source_mesh];
                m.name = sm.name;
                m.weights = sm.weights;
                m.extras = sm.extras;
                m.extensions = sm.extensions;
            }
            if (pm.level > 0)
                m.name = (m.name.empty() ? "mesh" + std::to_string(pm.source_mesh) : m.name) + "_LOD" +
                         std::to_string(pm.level);
            for (size_t k = 0; k < pm.primitive_count; ++k)
                m.primitives.push_back(build_primitive(pm.primitives[k], plan_base));
            out.meshes.push_back(m);
        }
    }

    long long level_mesh(size_t level, size_t mesh) const
    {
        return plan.level_mesh[level * plan.source_mesh_count + mesh];
    }

    static void copy_transform(const tinygltf::Node &from, tinygltf::Node &to)
    {
        to.matrix = from.matrix;
        to.translation = from.translation;
        to.rotation = from.rotation;
        to.scale = from.scale;
    }

    // Node extensions that say how the node's mesh is drawn: they go wherever the mesh goes (a level node, a
    // node's mesh moved into a child, a side-by-side copy), or a level would show one instance of many.
    static void copy_mesh_extensions(const tinygltf::Node &from, tinygltf::Node &to)
    {
        static const char *const drawn_with_mesh[] = {"EXT_mesh_gpu_instancing"};
        for (const char *e : drawn_with_mesh) {
            auto it = from.extensions.find(e);
            if (it != from.extensions.end())
                to.extensions[e] = it->second;
        }
    }

    // The animations that drive node `from`'s morph weights drive node `to`'s too (a level node shows the same
    // targets): one more channel on the same sampler.
    void drive_weights(int from, int to)
    {
        for (tinygltf::Animation &a : out.animations) {
            size_t count = a.channels.size();
            for (size_t i = 0; i < count; ++i)
                if (a.channels[i].target_node == from && a.channels[i].target_path == "weights") {
                    tinygltf::AnimationChannel c = a.channels[i];
                    c.target_node = to;
                    a.channels.push_back(c);
                }
        }
    }

    // MSFT_lod: the level nodes of every node that shows a mesh with levels.
    void add_msft_lod()
    {
        size_t node_count = out.nodes.size();
        bool used = false;
        for (size_t n = 0; n < node_count; ++n) {
            if (out.nodes[n].mesh < 0)
                continue;
            size_t mesh = (size_t)out.nodes[n].mesh;
            size_t levels = 1;
            while (levels < plan.level_count && level_mesh(levels, mesh) != RESURFI_GLTF_NONE)
                ++levels;
            if (levels == 1)
                continue;
            size_t target = n;
            bool moved = plan.restructure && plan.restructure[n];
            if (moved) {
                // The mesh moves into a new child that the level nodes can stand in for: the node keeps its
                // children and its (possibly animated) transform.
                tinygltf::Node child;
                child.name = out.nodes[n].name.empty() ? "mesh" : out.nodes[n].name + "_mesh";
                child.mesh = out.nodes[n].mesh;
                child.skin = out.nodes[n].skin;
                child.weights = out.nodes[n].weights;
                copy_mesh_extensions(out.nodes[n], child);
                for (const auto &e : child.extensions)
                    out.nodes[n].extensions.erase(e.first);
                out.nodes[n].mesh = -1;
                out.nodes[n].skin = -1;
                out.nodes[n].weights.clear();
                out.nodes.push_back(child);
                target = out.nodes.size() - 1;
                out.nodes[n].children.push_back((int)target);
                for (tinygltf::Animation &a : out.animations)
                    for (tinygltf::AnimationChannel &c : a.channels)
                        if (c.target_node == (int)n && c.target_path == "weights")
                            c.target_node = (int)target;
            }
            tinygltf::Value::Array ids;
            for (size_t k = 1; k < levels; ++k) {
                tinygltf::Node lod;
                const tinygltf::Node &t = out.nodes[target];
                lod.name = (t.name.empty() ? "node" + std::to_string(target) : t.name) + "_LOD" + std::to_string(k);
                lod.mesh = (int)level_mesh(k, mesh);
                lod.skin = t.skin;
                lod.weights = t.weights;
                copy_mesh_extensions(t, lod);
                // A skinned mesh ignores its node's transform (the joints place it): a copy would only repeat the
                // validator's NODE_SKINNED_MESH_LOCAL_TRANSFORMS warning on every level node.
                if (!moved && t.skin < 0)
                    copy_transform(t, lod);
                out.nodes.push_back(lod);
                ids.push_back(tinygltf::Value((int)out.nodes.size() - 1));
                drive_weights((int)target, (int)out.nodes.size() - 1);
            }
            tinygltf::Value::Object ext;
            ext["ids"] = tinygltf::Value(ids);
            tinygltf::Node &t = out.nodes[target];
            t.extensions["MSFT_lod"] = tinygltf::Value(ext);
            tinygltf::Value::Array coverage;
            for (size_t k = 0; k < levels; ++k) // one value per level: one more than ids
                coverage.push_back(tinygltf::Value(plan.coverage[mesh * plan.level_count + k]));
            tinygltf::Value::Object extras;
            if (t.extras.IsObject())
                extras = t.extras.Get<tinygltf::Value::Object>();
            extras["MSFT_screencoverage"] = tinygltf::Value(coverage);
            t.extras = tinygltf::Value(extras);
            used = true;
        }
        if (used)
            out.extensionsUsed.push_back("MSFT_lod");
    }

    // Copies the subtree of `root` for level k; returns the copy's index. Iterative: a deep hierarchy cannot
    // exhaust the stack.
    int copy_subtree(int root, size_t level, std::map<int, int> &copies)
    {
        std::vector<std::pair<int, int>> stack; // (source node, parent copy or -1)
        stack.emplace_back(root, -1);
        int top = -1;
        while (!stack.empty()) {
            auto [n, parent] = stack.back();
            stack.pop_back();
            const tinygltf::Node &s = out.nodes.at((size_t)n);
            tinygltf::Node c;
            c.name = (s.name.empty() ? "node" + std::to_string(n) : s.name) + "_LOD" + std::to_string(level);
            copy_transform(s, c);
            c.skin = s.skin;
            c.weights = s.weights;
            if (s.mesh >= 0) {
                c.mesh = (int)level_mesh(level, (size_t)s.mesh);
                copy_mesh_extensions(s, c);
            }
            std::vector<int> children = s.children;
            bool shows_mesh = s.mesh >= 0;
            out.nodes.push_back(c);
            int idx = (int)out.nodes.size() - 1;
            copies[n] = idx;
            if (shows_mesh)
                drive_weights(n, idx);
            if (parent >= 0)
                out.nodes[(size_t)parent].children.push_back(idx);
            else
                top = idx;
            for (auto it = children.rbegin(); it != children.rend(); ++it)
                stack.emplace_back(*it, idx);
        }
        return top;
    }

    // Side by side: every scene gets, per level k >= 1, a moved copy of its node trees showing level k meshes.
    void add_side_by_side()
    {
        size_t scene_count = out.scenes.size();
        std::vector<std::vector<int>> original_roots;
        for (const tinygltf::Scene &scene : out.scenes)
            original_roots.push_back(scene.nodes);
        for (size_t k = 1; k < plan.level_count; ++k) {
            for (size_t s = 0; s < scene_count; ++s) {
                std::map<int, int> copies;
                const std::vector<int> &roots = original_roots[s];
                tinygltf::Node group;
                group.name = "LOD" + std::to_string(k);
                group.translation = {plan.level_offset[0] * (double)k, plan.level_offset[1] * (double)k,
                                     plan.level_offset[2] * (double)k};
                for (int r : roots)
                    group.children.push_back(copy_subtree(r, k, copies));
                // Skins whose joints were all copied get a copy that moves with the copied joints.
                std::map<int, int> skin_copies;
                for (auto &entry : copies) {
                    tinygltf::Node &c = out.nodes[(size_t)entry.second];
                    if (c.skin < 0)
                        continue;
                    auto known = skin_copies.find(c.skin);
                    if (known == skin_copies.end()) {
                        tinygltf::Skin skin = out.skins.at((size_t)c.skin);
                        bool all = true;
                        for (int &j : skin.joints) {
                            auto m = copies.find(j);
                            if (m == copies.end())
                                all = false;
                            else
                                j = m->second;
                        }
                        if (skin.skeleton >= 0) {
                            auto m = copies.find(skin.skeleton);
                            skin.skeleton = m == copies.end() ? -1 : m->second;
                        }
                        int index = c.skin;
                        if (all) {
                            skin.name += "_LOD" + std::to_string(k);
                            out.skins.push_back(skin);
                            index = (int)out.skins.size() - 1;
                        }
                        known = skin_copies.emplace(c.skin, index).first;
                    }
                    c.skin = known->second;
                }
                out.nodes.push_back(group);
                out.scenes[s].nodes.push_back((int)out.nodes.size() - 1);
            }
        }
    }

    void build()
    {
        out.asset = src.asset;
        out.asset.version = "2.0";
        out.asset.minVersion.clear();
        out.asset.generator = plan.generator ? plan.generator : "resurf";
        out.defaultScene = src.defaultScene;
        out.scenes = src.scenes;
        out.nodes = src.nodes;
        out.cameras = src.cameras;
        out.materials = src.materials;
        out.textures = src.textures;
        out.samplers = src.samplers;
        out.skins = src.skins;
        out.animations = src.animations;
        out.lights = src.lights;
        out.extensions = src.extensions;
        out.extras = src.extras;

        keep_source_data();
        copy_images();
        for (tinygltf::Skin &s : out.skins)
            s.inverseBindMatrices = map_accessor(s.inverseBindMatrices);
        for (tinygltf::Node &n : out.nodes) {
            auto gi = n.extensions.find("EXT_mesh_gpu_instancing");
            if (gi == n.extensions.end() || !gi->second.IsObject() || !gi->second.Has("attributes"))
                continue;
            tinygltf::Value::Object ext = gi->second.Get<tinygltf::Value::Object>(), attributes;
            for (const std::string &key : gi->second.Get("attributes").Keys())
                attributes[key] = tinygltf::Value(map_accessor(gi->second.Get("attributes").Get(key).GetNumberAsInt()));
            ext["attributes"] = tinygltf::Value(attributes);
            gi->second = tinygltf::Value(ext);
        }
        for (tinygltf::Animation &a : out.animations)
            for (tinygltf::AnimationSampler &s : a.samplers) {
                s.input = map_accessor(s.input);
                s.output = map_accessor(s.output);
            }
        int plan_base = add_plan_accessors();
        build_meshes(plan_base);

        if (plan.synthesize_graph) {
            tinygltf::Scene scene;
            for (size_t m = 0; m < plan.source_mesh_count; ++m) { // the first meshes of the plan: one per source mesh
                tinygltf::Node node;
                node.mesh = (int)m;
                out.nodes.push_back(node);
                scene.nodes.push_back((int)out.nodes.size() - 1);
            }
            out.scenes.push_back(scene);
            out.defaultScene = 0;
        }

        // Extensions: what the source declared, minus what this plan decides itself and what was left off the
        // rewritten primitives and is found nowhere else.
        std::set<std::string> gone = dropped;
        if (doc)
            for (const std::string &e : doc->outside_extensions)
                gone.erase(e);
        for (const tinygltf::Mesh &m : out.meshes)
            for (const tinygltf::Primitive &p : m.primitives)
                for (const auto &e : p.extensions)
                    gone.erase(e.first);
        for (const std::string &e : src.extensionsUsed)
            if (e != "KHR_draco_mesh_compression" && e != "KHR_mesh_quantization" && e != "MSFT_lod" && !gone.count(e))
                out.extensionsUsed.push_back(e);
        for (const std::string &e : src.extensionsRequired)
            if (e != "KHR_draco_mesh_compression" && e != "KHR_mesh_quantization" && !gone.count(e))
                out.extensionsRequired.push_back(e);
        if (plan.draco_used) {
            out.extensionsUsed.push_back("KHR_draco_mesh_compression");
            out.extensionsRequired.push_back("KHR_draco_mesh_compression");
        }
        if (plan.quantization_used) {
            out.extensionsUsed.push_back("KHR_mesh_quantization");
            out.extensionsRequired.push_back("KHR_mesh_quantization");
        }
        bool msft_lod_in_source = false;
        for (const tinygltf::Node &n : src.nodes)
            msft_lod_in_source |= n.extensions.count("MSFT_lod") > 0;
        if (plan.level_count > 1 && plan_layout() == RESURFI_GLTF_MSFT_LOD)
            add_msft_lod();
        if (msft_lod_in_source &&
            std::find(out.extensionsUsed.begin(), out.extensionsUsed.end(), "MSFT_lod") == out.extensionsUsed.end())
            out.extensionsUsed.push_back("MSFT_lod");
        if (plan.level_count > 1 && plan_layout() == RESURFI_GLTF_SIDE_BY_SIDE)
            add_side_by_side();

        if (!bin.empty()) {
            while (bin.size() % 4)
                bin.push_back(0);
            tinygltf::Buffer b;
            b.data = std::move(bin);
            out.buffers.push_back(std::move(b));
        }
    }

    resurfi_gltf_layout plan_layout() const { return plan.layout; }
};

unsigned char *copy_out(const void *data, size_t size)
{
    unsigned char *p = static_cast<unsigned char *>(std::malloc(size + 1));
    if (!p)
        throw std::bad_alloc();
    std::memcpy(p, data, size);
    p[size] = 0;
    return p;
}

uint32_t get32(const std::string &s, size_t at)
{
    uint32_t x = 0;
    for (int i = 0; i < 4; ++i)
        x |= (uint32_t)(unsigned char)s[at + (size_t)i] << (8 * i);
    return x;
}

std::string base64(const std::vector<unsigned char> &data)
{
    static const char table[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((data.size() + 2) / 3 * 4);
    for (size_t i = 0; i < data.size(); i += 3) {
        uint32_t x = (uint32_t)data[i] << 16;
        if (i + 1 < data.size())
            x |= (uint32_t)data[i + 1] << 8;
        if (i + 2 < data.size())
            x |= data[i + 2];
        out += table[(x >> 18) & 63];
        out += table[(x >> 12) & 63];
        out += i + 1 < data.size() ? table[(x >> 6) & 63] : '=';
        out += i + 2 < data.size() ? table[x & 63] : '=';
    }
    return out;
}

// An empty object comes out of tinygltf as null ("scenes":[null], a node {}, an extension {}, extras {}): null
// is no glTF value, so every null is an empty object again, except inside extras, where a null may be the
// source's own.
void nulls_to_objects(nlohmann::json &j)
{
    if (j.is_null()) {
        j = nlohmann::json::object();
    } else if (j.is_object()) {
        for (auto it = j.begin(); it != j.end(); ++it)
            if (it.key() != "extras")
                nulls_to_objects(it.value());
            else if (it->is_null())
                *it = nlohmann::json::object();
    } else if (j.is_array()) {
        for (nlohmann::json &x : j)
            nulls_to_objects(x);
    }
}

// tinygltf keeps every glTF number as a double, and nlohmann writes a whole double as "1.0": a whole number is
// written as an integer instead ("0.0" and "1.0" fill matrices, factors and min/max: 1.3 kB of the 41 kB of JSON
// of a 2CylinderEngine level). The same value to any JSON reader; -0.0 keeps its sign, and extras stay as the
// source wrote them.
void whole_numbers_as_integers(nlohmann::json &j)
{
    if (j.is_number_float()) {
        double x = j.get<double>();
        bool whole = std::isfinite(x) && x == std::trunc(x) && std::fabs(x) < 9007199254740992.0; // below 2^53
        if (whole && !(x == 0 && std::signbit(x)))
            j = (int64_t)x;
    } else if (j.is_object()) {
        for (auto it = j.begin(); it != j.end(); ++it)
            if (it.key() != "extras")
                whole_numbers_as_integers(it.value());
    } else if (j.is_array()) {
        for (nlohmann::json &x : j)
            whole_numbers_as_integers(x);
    }
}

// What tinygltf 2.7 serialises wrongly or longer than needed: empty objects (above), an absent perspective zfar
// (an infinite projection) comes out as 0, whole numbers as "1.0".
void fix_json(nlohmann::json &root)
{
    nulls_to_objects(root);
    whole_numbers_as_integers(root);
    auto cameras = root.find("cameras");
    if (cameras != root.end() && cameras->is_array())
        for (nlohmann::json &c : *cameras) {
            auto p = c.find("perspective");
            if (p != c.end() && p->is_object() && p->contains("zfar") && (*p)["zfar"] == 0)
                p->erase("zfar");
        }
}

resurf_status write(const resurfi_gltf_doc *doc, const resurfi_gltf_plan *plan, unsigned char **out_json,
                    size_t *out_json_size, unsigned char **out_bin, size_t *out_bin_size, resurf_error *error)
{
    static const tinygltf::Model empty;
    Writer w(doc ? doc->model : empty, doc, *plan);
    w.build();

    // tinygltf serialises into memory as a .glb (the buffer is not base64-encoded on the way); the JSON chunk is
    // then corrected and the container assembled here.
    tinygltf::TinyGLTF serializer;
    serializer.SetImageWriter(nullptr, nullptr);
    std::ostringstream stream;
    if (!serializer.WriteGltfSceneToStream(&w.out, stream, false, true) || !stream)
        return resurfi_fail(error, RESURF_ERR_INTERNAL, NULL, 0, -1, "tinygltf could not serialise the document");
    std::string glb = stream.str();
    if (glb.size() < 20 || 20 + (size_t)get32(glb, 12) > glb.size())
        return resurfi_fail(error, RESURF_ERR_INTERNAL, NULL, 0, -1, "tinygltf wrote a truncated container");
    size_t json_length = get32(glb, 12);
    nlohmann::json root = nlohmann::json::parse(glb.begin() + 20, glb.begin() + 20 + (long)json_length);
    glb.clear();
    fix_json(root);
    const std::vector<unsigned char> *data = w.out.buffers.empty() ? nullptr : &w.out.buffers[0].data;

    if (plan->container == RESURFI_GLTF_GLB) {
        std::string text = root.dump();
        size_t json_padded = (text.size() + 3) & ~(size_t)3;
        size_t bin_padded = data ? (data->size() + 3) & ~(size_t)3 : 0;
        size_t total = 12 + 8 + json_padded + (data ? 8 + bin_padded : 0);
        if (total > 0xffffffffu)
            return resurfi_fail(error, RESURF_ERR_LIMIT, NULL, 0, -1, "the .glb would be larger than 4 GiB");
        std::vector<unsigned char> out(total, 0);
        auto put32 = [&](size_t at, uint32_t x) {
            for (int i = 0; i < 4; ++i)
                out[at + (size_t)i] = (unsigned char)(x >> (8 * i));
        };
        std::memcpy(out.data(), "glTF", 4);
        put32(4, 2);
        put32(8, (uint32_t)total);
        put32(12, (uint32_t)json_padded);
        put32(16, 0x4E4F534Au);
        std::memcpy(out.data() + 20, text.data(), text.size());
        std::memset(out.data() + 20 + text.size(), ' ', json_padded - text.size());
        if (data) {
            size_t at = 20 + json_padded;
            put32(at, (uint32_t)bin_padded);
            put32(at + 4, 0x004E4942u);
            std::memcpy(out.data() + at + 8, data->data(), data->size());
        }
        *out_json = copy_out(out.data(), out.size());
        *out_json_size = out.size();
        return RESURF_OK;
    }
    if (data)
        root["buffers"][0]["uri"] = plan->container == RESURFI_GLTF_EMBEDDED
                                        ? "data:application/octet-stream;base64," + base64(*data)
                                        : std::string(plan->bin_uri);
    std::string text = root.dump(2) + "\n";
    *out_json = copy_out(text.data(), text.size());
    *out_json_size = text.size();
    if (data && plan->container == RESURFI_GLTF_SEPARATE) {
        *out_bin = copy_out(data->data(), data->size());
        *out_bin_size = data->size();
    }
    return RESURF_OK;
}

} // namespace

extern "C" resurf_status resurfi_gltf_write(const resurfi_gltf_doc *doc, const resurfi_gltf_plan *plan,
                                            unsigned char **out_json, size_t *out_json_size, unsigned char **out_bin,
                                            size_t *out_bin_size, resurf_error *error)
{
    *out_json = *out_bin = nullptr;
    *out_json_size = *out_bin_size = 0;
    resurf_status status;
    try {
        status = write(doc, plan, out_json, out_json_size, out_bin, out_bin_size, error);
    } catch (const std::bad_alloc &) {
        status = resurfi_fail(error, RESURF_ERR_OUT_OF_MEMORY, NULL, 0, -1, "out of memory writing the glTF document");
    } catch (const std::exception &e) {
        status = resurfi_fail(error, RESURF_ERR_INTERNAL, NULL, 0, -1, "writing the glTF document failed: %s",
                              e.what());
    } catch (...) {
        status = resurfi_fail(error, RESURF_ERR_INTERNAL, NULL, 0, -1, "unexpected exception writing the document");
    }
    if (status != RESURF_OK) {
        std::free(*out_json);
        std::free(*out_bin);
        *out_json = *out_bin = nullptr;
        *out_json_size = *out_bin_size = 0;
    }
    return status;
}
