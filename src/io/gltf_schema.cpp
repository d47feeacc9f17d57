// The glTF 2.0 core schema as tables, and one walk that checks a document's JSON against them.
//
// tinygltf reads leniently: a property of the wrong type or an enum value it does not know is skipped or taken
// as given without a word ("name": 42 vanishes, a "primitives" object becomes a mesh without primitives, a
// texture "index": -1 reads as no texture). So the JSON is checked first, against the core schema's rules
// (KhronosGroup/glTF, specification/2.0/schema/*.schema.json): the JSON type of every property, the required
// ones, array lengths and unique items, enum values and numeric ranges. What the schema leaves open stays open:
// unknown properties, `extras` of any type, the content of an extension (each must be an object).
//
// Enums: the 2.0.1 schema lets most enums take any other integer or string as well ("anyOf" with a bare type),
// room for extensions to add values. The tables list the values the specification defines (the Khronos validator
// reports any other), plus those that an extension the document uses adds (KHR_animation_pointer's "pointer").
//
// Integers: JSON has one number type, and the schema counts 2.0 as an integer; tinygltf (nlohmann) does not and
// drops such a value silently. The walk rewrites an integral number where the schema wants an integer as an
// integer, so tinygltf reads what the file means.
#include "gltf_schema.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace {

enum Kind : unsigned char { INTEGER, NUMBER, STRING, BOOLEAN, OBJECT, ARRAY, ID_MAP };
// ID_MAP: an object whose values are glTF ids (a primitive's attributes, a morph target).

struct Enum {
    const char *what;        // "a glTF primitive mode"
    const char *list;        // the values as the message gives them: "0..6"
    const long long *ints;   // INTEGER enums
    const char *const *strings; // STRING enums (NULL-terminated)
    size_t int_count;
    const char *extension;   // a document that uses this extension may also give extension_value
    const char *extension_value;
};

struct Object;

struct Property {
    const char *name;
    Kind kind;
    Kind items = INTEGER;    // ARRAY: the kind of its items
    bool required = false;
    const Object *object = nullptr; // OBJECT, or ARRAY of OBJECT: its properties
    double min = -std::numeric_limits<double>::infinity(), max = std::numeric_limits<double>::infinity();
    bool exclusive_min = false;
    long long multiple_of = 0;
    size_t min_items = 0, max_items = 0; // ARRAY (max 0: no limit)
    size_t min_properties = 0;           // ID_MAP
    bool unique = false;
    const Enum *choices = nullptr;
};

// The properties of one kind of object (every glTF object may have `extensions` and `extras` as well).
struct Object {
    const Property *properties;
    size_t count;
};

template <size_t N> constexpr Object object_of(const Property (&p)[N]) { return Object{p, N}; }

// ---- building blocks --------------------------------------------------------------------------------------------

constexpr Property prop(const char *name, Kind kind)
{
    Property p{};
    p.name = name;
    p.kind = kind;
    return p;
}
constexpr Property required(Property p)
{
    p.required = true;
    return p;
}
constexpr Property integer(const char *name, double min) // glTF integers are never negative
{
    Property p = prop(name, INTEGER);
    p.min = min;
    return p;
}
constexpr Property id(const char *name) { return integer(name, 0); }
constexpr Property number(const char *name, double min = -std::numeric_limits<double>::infinity(),
                          double max = std::numeric_limits<double>::infinity())
{
    Property p = prop(name, NUMBER);
    p.min = min;
    p.max = max;
    return p;
}
constexpr Property positive(const char *name) // exclusiveMinimum 0
{
    Property p = prop(name, NUMBER);
    p.min = 0;
    p.exclusive_min = true;
    return p;
}
constexpr Property string(const char *name) { return prop(name, STRING); }
constexpr Property boolean(const char *name) { return prop(name, BOOLEAN); }
constexpr Property object(const char *name, const Object &o)
{
    Property p = prop(name, OBJECT);
    p.object = &o;
    return p;
}
constexpr Property one_of(Property p, const Enum &e)
{
    p.choices = &e;
    return p;
}
// An array of `items` with min..max of them (max 0: no limit).
constexpr Property array(const char *name, Kind items, size_t min, size_t max = 0)
{
    Property p = prop(name, ARRAY);
    p.items = items;
    p.min_items = min;
    p.max_items = max;
    return p;
}
constexpr Property objects(const char *name, const Object &o) // an array of at least one object
{
    Property p = array(name, OBJECT, 1);
    p.object = &o;
    return p;
}
constexpr Property ids(const char *name) // an array of at least one glTF id, each once
{
    Property p = array(name, INTEGER, 1);
    p.min = 0;
    p.unique = true;
    return p;
}
constexpr Property numbers(const char *name, size_t min, size_t max,
                           double lo = -std::numeric_limits<double>::infinity(),
                           double hi = std::numeric_limits<double>::infinity())
{
    Property p = array(name, NUMBER, min, max);
    p.min = lo;
    p.max = hi;
    return p;
}

// ---- the enums --------------------------------------------------------------------------------------------------

const long long component_types[] = {5120, 5121, 5122, 5123, 5125, 5126};
const Enum component_type{"a glTF component type", "5120, 5121, 5122, 5123, 5125, 5126", component_types, nullptr, 6,
                          nullptr, nullptr};
const long long index_types[] = {5121, 5123, 5125};
const Enum index_type{"a component type of sparse indices", "5121, 5123, 5125", index_types, nullptr, 3, nullptr,
                      nullptr};
const char *const accessor_types[] = {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4", nullptr};
const Enum accessor_type{"an accessor type", "SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3, MAT4", nullptr, accessor_types,
                         0, nullptr, nullptr};
const long long modes[] = {0, 1, 2, 3, 4, 5, 6};
const Enum mode{"a glTF primitive mode", "0..6", modes, nullptr, 7, nullptr, nullptr};
const long long targets[] = {34962, 34963};
const Enum target{"a bufferView target", "34962, 34963", targets, nullptr, 2, nullptr, nullptr};
const long long mag_filters[] = {9728, 9729};
const Enum mag_filter{"a magnification filter", "9728, 9729", mag_filters, nullptr, 2, nullptr, nullptr};
const long long min_filters[] = {9728, 9729, 9984, 9985, 9986, 9987};
const Enum min_filter{"a minification filter", "9728, 9729, 9984..9987", min_filters, nullptr, 6, nullptr, nullptr};
const long long wraps[] = {33071, 33648, 10497};
const Enum wrap{"a wrap mode", "33071, 33648, 10497", wraps, nullptr, 3, nullptr, nullptr};
const char *const camera_types[] = {"perspective", "orthographic", nullptr};
const Enum camera_type{"a camera type", "perspective, orthographic", nullptr, camera_types, 0, nullptr, nullptr};
const char *const paths[] = {"translation", "rotation", "scale", "weights", nullptr};
const Enum path{"an animated property", "translation, rotation, scale, weights", nullptr, paths, 0,
                "KHR_animation_pointer", "pointer"};
const char *const interpolations[] = {"LINEAR", "STEP", "CUBICSPLINE", nullptr};
const Enum interpolation{"an interpolation", "LINEAR, STEP, CUBICSPLINE", nullptr, interpolations, 0, nullptr, nullptr};
const char *const alpha_modes[] = {"OPAQUE", "MASK", "BLEND", nullptr};
const Enum alpha_mode{"an alpha mode", "OPAQUE, MASK, BLEND", nullptr, alpha_modes, 0, nullptr, nullptr};

// ---- the objects (glTF 2.0 schema, one table per *.schema.json) ------------------------------------------------

const Property asset_p[] = {string("copyright"), string("generator"), required(string("version")),
                            string("minVersion")};
const Object asset = object_of(asset_p);

const Property scene_p[] = {string("name"), ids("nodes")};
const Object scene = object_of(scene_p);

const Property node_p[] = {string("name"),
                           id("camera"),
                           ids("children"),
                           id("skin"),
                           numbers("matrix", 16, 16),
                           id("mesh"),
                           numbers("rotation", 4, 4, -1, 1),
                           numbers("scale", 3, 3),
                           numbers("translation", 3, 3),
                           numbers("weights", 1, 0)};
const Object node = object_of(node_p);

Property morph_targets()
{
    Property p = array("targets", ID_MAP, 1);
    p.min = 0;
    return p;
}
Property attributes()
{
    Property p = required(prop("attributes", ID_MAP));
    p.min = 0;
    p.min_properties = 1;
    return p;
}
const Property primitive_p[] = {attributes(), id("indices"), id("material"),
                                one_of(integer("mode", 0), mode), morph_targets()};
const Object primitive = object_of(primitive_p);

const Property mesh_p[] = {string("name"), required(objects("primitives", primitive)), numbers("weights", 1, 0)};
const Object mesh = object_of(mesh_p);

const Property sparse_indices_p[] = {required(id("bufferView")), integer("byteOffset", 0),
                                     required(one_of(integer("componentType", 0), index_type))};
const Object sparse_indices = object_of(sparse_indices_p);
const Property sparse_values_p[] = {required(id("bufferView")), integer("byteOffset", 0)};
const Object sparse_values = object_of(sparse_values_p);
const Property sparse_p[] = {required(integer("count", 1)), required(object("indices", sparse_indices)),
                             required(object("values", sparse_values))};
const Object sparse = object_of(sparse_p);

const Property accessor_p[] = {string("name"),
                               id("bufferView"),
                               integer("byteOffset", 0),
                               required(one_of(integer("componentType", 0), component_type)),
                               boolean("normalized"),
                               required(integer("count", 1)),
                               required(one_of(string("type"), accessor_type)),
                               numbers("max", 1, 16),
                               numbers("min", 1, 16),
                               object("sparse", sparse)};
const Object accessor = object_of(accessor_p);

Property byte_stride()
{
    Property p = integer("byteStride", 4);
    p.max = 252;
    p.multiple_of = 4;
    return p;
}
const Property buffer_view_p[] = {string("name"),
                                  required(id("buffer")),
                                  integer("byteOffset", 0),
                                  required(integer("byteLength", 1)),
                                  byte_stride(),
                                  one_of(integer("target", 0), target)};
const Object buffer_view = object_of(buffer_view_p);

const Property buffer_p[] = {string("name"), string("uri"), required(integer("byteLength", 1))};
const Object buffer = object_of(buffer_p);

const Property texture_info_p[] = {required(id("index")), integer("texCoord", 0)};
const Object texture_info = object_of(texture_info_p);
const Property normal_info_p[] = {required(id("index")), integer("texCoord", 0), number("scale")};
const Object normal_info = object_of(normal_info_p);
const Property occlusion_info_p[] = {required(id("index")), integer("texCoord", 0), number("strength", 0, 1)};
const Object occlusion_info = object_of(occlusion_info_p);

const Property pbr_p[] = {numbers("baseColorFactor", 4, 4, 0, 1), object("baseColorTexture", texture_info),
                          number("metallicFactor", 0, 1), number("roughnessFactor", 0, 1),
                          object("metallicRoughnessTexture", texture_info)};
const Object pbr = object_of(pbr_p);

const Property material_p[] = {string("name"),
                               object("pbrMetallicRoughness", pbr),
                               object("normalTexture", normal_info),
                               object("occlusionTexture", occlusion_info),
                               object("emissiveTexture", texture_info),
                               numbers("emissiveFactor", 3, 3, 0, 1),
                               one_of(string("alphaMode"), alpha_mode),
                               number("alphaCutoff", 0),
                               boolean("doubleSided")};
const Object material = object_of(material_p);

const Property texture_p[] = {string("name"), id("sampler"), id("source")};
const Object texture = object_of(texture_p);

const Property image_p[] = {string("name"), string("uri"), string("mimeType"), id("bufferView")};
const Object image = object_of(image_p);

const Property sampler_p[] = {string("name"), one_of(integer("magFilter", 0), mag_filter),
                              one_of(integer("minFilter", 0), min_filter), one_of(integer("wrapS", 0), wrap),
                              one_of(integer("wrapT", 0), wrap)};
const Object sampler = object_of(sampler_p);

const Property skin_p[] = {string("name"), id("inverseBindMatrices"), id("skeleton"), required(ids("joints"))};
const Object skin = object_of(skin_p);

const Property orthographic_p[] = {required(number("xmag")), required(number("ymag")), required(positive("zfar")),
                                   required(number("znear", 0))};
const Object orthographic = object_of(orthographic_p);
const Property perspective_p[] = {positive("aspectRatio"), required(positive("yfov")), positive("zfar"),
                                  required(positive("znear"))};
const Object perspective = object_of(perspective_p);
const Property camera_p[] = {string("name"), object("orthographic", orthographic), object("perspective", perspective),
                             required(one_of(string("type"), camera_type))};
const Object camera = object_of(camera_p);

const Property channel_target_p[] = {id("node"), required(one_of(string("path"), path))};
const Object channel_target = object_of(channel_target_p);
const Property channel_p[] = {required(id("sampler")), required(object("target", channel_target))};
const Object channel = object_of(channel_p);
const Property animation_sampler_p[] = {required(id("input")), one_of(string("interpolation"), interpolation),
                                        required(id("output"))};
const Object animation_sampler = object_of(animation_sampler_p);
const Property animation_p[] = {string("name"), required(objects("channels", channel)),
                                required(objects("samplers", animation_sampler))};
const Object animation = object_of(animation_p);

Property extension_names(const char *name)
{
    Property p = array(name, STRING, 1);
    p.unique = true;
    return p;
}
const Property root_p[] = {extension_names("extensionsUsed"),
                           extension_names("extensionsRequired"),
                           objects("accessors", accessor),
                           objects("animations", animation),
                           required(object("asset", asset)),
                           objects("buffers", buffer),
                           objects("bufferViews", buffer_view),
                           objects("cameras", camera),
                           objects("images", image),
                           objects("materials", material),
                           objects("meshes", mesh),
                           objects("nodes", node),
                           objects("samplers", sampler),
                           id("scene"),
                           objects("scenes", scene),
                           objects("skins", skin),
                           objects("textures", texture)};
const Object root_object = object_of(root_p);

// ---- the walk ---------------------------------------------------------------------------------------------------

// Text from the file for a message: at most `limit` bytes (cut before a UTF-8 sequence), control characters as
// '?', "..." when cut.
std::string printable(const std::string &s, size_t limit)
{
    size_t n = s.size();
    if (n > limit) {
        n = limit;
        while (n > 0 && ((unsigned char)s[n] & 0xc0) == 0x80)
            --n;
    }
    std::string out;
    for (size_t i = 0; i < n; ++i)
        out += (unsigned char)s[i] < 0x20 || s[i] == 0x7f ? '?' : s[i];
    return n < s.size() ? out + "..." : out;
}

std::string quoted(const std::string &s) { return "\"" + printable(s, 40) + "\""; }

// A key from the file, as part of a path.
std::string key_of(const std::string &s) { return printable(s, 60); }

const char *kind_name(Kind k)
{
    switch (k) {
    case INTEGER: return "an integer";
    case NUMBER: return "a number";
    case STRING: return "a string";
    case BOOLEAN: return "a boolean";
    case ARRAY: return "an array";
    default: return "an object";
    }
}

std::string number_text(double x)
{
    char text[40];
    std::snprintf(text, sizeof text, "%.17g", x);
    return text;
}

std::string number_text(const nlohmann::json &j)
{
    if (j.is_number_integer())
        return j.is_number_unsigned() ? std::to_string(j.get<unsigned long long>())
                                      : std::to_string(j.get<long long>());
    return number_text(j.get<double>());
}

// What a value is, for "must be an integer, not ...".
std::string value_text(const nlohmann::json &j)
{
    if (j.is_null())
        return "null";
    if (j.is_boolean())
        return j.get<bool>() ? "true" : "false";
    if (j.is_number())
        return "the number " + number_text(j);
    if (j.is_string())
        return "the string " + quoted(j.get_ref<const std::string &>());
    return j.is_array() ? "an array" : "an object";
}

struct Walk {
    size_t max, count = 0;
    std::vector<std::string> *problems;
    std::vector<std::string> used; // extensionsUsed
    bool rewrote = false;          // an integral number became an integer

    void problem(const std::string &where, const std::string &cause)
    {
        if (count++ < max)
            problems->push_back(where + ": " + cause);
    }

    bool is_used(const char *extension) const
    {
        return std::find(used.begin(), used.end(), extension) != used.end();
    }

    // An integral number where an integer belongs becomes an integer (see the top of the file).
    bool as_integer(nlohmann::json &j)
    {
        if (j.is_number_integer())
            return true;
        if (!j.is_number_float())
            return false;
        double x = j.get<double>();
        if (!(x == std::floor(x) && std::fabs(x) < 9.2e18))
            return false;
        j = (long long)x;
        rewrote = true;
        return true;
    }

    bool type_ok(nlohmann::json &j, Kind k)
    {
        switch (k) {
        case INTEGER: return as_integer(j);
        case NUMBER: return j.is_number();
        case STRING: return j.is_string();
        case BOOLEAN: return j.is_boolean();
        case ARRAY: return j.is_array();
        default: return j.is_object();
        }
    }

    // A scalar's range and enum (after its type is known to be right).
    void scalar(const nlohmann::json &j, const Property &p, const std::string &where)
    {
        if (j.is_number()) {
            double x = j.get<double>();
            std::string cause;
            if (p.exclusive_min ? !(x > p.min) : x < p.min)
                cause = (p.exclusive_min ? " is not above " : " is below the minimum of ") + number_text(p.min);
            else if (x > p.max)
                cause = " is above the maximum of " + number_text(p.max);
            else if (p.multiple_of && j.is_number_integer() && j.get<long long>() % p.multiple_of)
                cause = " is not a multiple of " + std::to_string(p.multiple_of);
            if (!cause.empty()) {
                problem(where, number_text(j) + cause);
                return;
            }
        }
        if (!p.choices)
            return;
        const Enum &e = *p.choices;
        bool ok = false;
        if (j.is_number_integer())
            for (size_t i = 0; i < e.int_count; ++i)
                ok |= j.get<long long>() == e.ints[i];
        if (j.is_string()) {
            const std::string &s = j.get_ref<const std::string &>();
            for (const char *const *c = e.strings; c && *c; ++c)
                ok |= s == *c;
            ok |= e.extension && s == e.extension_value && is_used(e.extension);
        }
        if (!ok)
            problem(where, (j.is_string() ? quoted(j.get_ref<const std::string &>()) : number_text(j)) + " is not " +
                               e.what + " (" + e.list + ")");
    }

    // A value of kind k (an array's item, or a property), where p gives its rules.
    void value(nlohmann::json &j, Kind k, const Property &p, const std::string &where)
    {
        if (!type_ok(j, k)) {
            problem(where, std::string("must be ") + kind_name(k) + ", not " + value_text(j));
            return;
        }
        if (k == OBJECT)
            walk_object(j, *p.object, where);
        else if (k == ID_MAP)
            id_map(j, p, where);
        else
            scalar(j, p, where);
    }

    void id_map(nlohmann::json &j, const Property &p, const std::string &where)
    {
        if (j.size() < p.min_properties)
            problem(where, "is empty (glTF wants at least one property)");
        for (auto it = j.begin(); it != j.end(); ++it) {
            std::string w = where + "." + key_of(it.key());
            if (!as_integer(it.value()))
                problem(w, "must be an integer, not " + value_text(it.value()));
            else
                scalar(it.value(), p, w);
        }
    }

    void array(nlohmann::json &j, const Property &p, const std::string &where)
    {
        size_t n = j.size();
        if (p.min_items == p.max_items && n != p.min_items)
            problem(where, "has " + std::to_string(n) + " items, not " + std::to_string(p.min_items));
        else if (n < p.min_items)
            problem(where, n == 0 ? std::string("is empty (glTF wants at least one item)")
                                  : "has " + std::to_string(n) + " items, fewer than " + std::to_string(p.min_items));
        else if (p.max_items && n > p.max_items)
            problem(where, "has " + std::to_string(n) + " items, more than " + std::to_string(p.max_items));
        for (size_t i = 0; i < n; ++i)
            value(j[i], p.items, p, where + "[" + std::to_string(i) + "]");
        if (!p.unique)
            return;
        std::vector<std::pair<nlohmann::json, size_t>> sorted; // by value, then index: a repeat follows its first
        for (size_t i = 0; i < n; ++i)
            sorted.emplace_back(j[i], i);
        std::sort(sorted.begin(), sorted.end());
        for (size_t i = 1; i < n; ++i)
            if (sorted[i].first == sorted[i - 1].first)
                problem(where + "[" + std::to_string(sorted[i].second) + "]", "repeats " + where + "[" +
                                                                               std::to_string(sorted[i - 1].second) +
                                                                               "] (the items must be unique)");
    }

    void walk_object(nlohmann::json &j, const Object &o, const std::string &where)
    {
        const std::string prefix = where.empty() ? "" : where + ".";
        for (size_t i = 0; i < o.count; ++i) {
            const Property &p = o.properties[i];
            auto it = j.find(p.name);
            if (it == j.end()) {
                if (p.required)
                    problem(prefix + p.name, "the property is required but missing");
                continue;
            }
            if (p.kind == ARRAY && it->is_array())
                array(*it, p, prefix + p.name);
            else
                value(*it, p.kind, p, prefix + p.name);
        }
        auto ext = j.find("extensions");
        if (ext != j.end()) {
            if (!ext->is_object())
                problem(prefix + "extensions", "must be an object, not " + value_text(*ext));
            else
                for (auto e = ext->begin(); e != ext->end(); ++e)
                    if (!e->is_object())
                        problem(prefix + "extensions." + key_of(e.key()), "must be an object, not " + value_text(*e));
        }
        if (&o == &camera)
            camera_projection(j, where);
    }

    // A camera has exactly the projection its type names (camera.schema.json: oneOf perspective, orthographic).
    void camera_projection(const nlohmann::json &j, const std::string &where)
    {
        auto type = j.find("type");
        if (type == j.end() || !type->is_string())
            return;
        bool persp = j.contains("perspective"), ortho = j.contains("orthographic");
        if (persp && ortho)
            problem(where, "has both perspective and orthographic (glTF allows one)");
        else if (*type == "perspective" && !persp)
            problem(where + ".perspective", "the property is required for a perspective camera but missing");
        else if (*type == "orthographic" && !ortho)
            problem(where + ".orthographic", "the property is required for an orthographic camera but missing");
    }
};

} // namespace

size_t resurfi_gltf_schema_check(nlohmann::json &root, size_t max, std::vector<std::string> *problems,
                                 bool *rewritten)
{
    Walk w;
    w.max = max;
    w.problems = problems;
    auto used = root.find("extensionsUsed");
    if (used != root.end() && used->is_array())
        for (const nlohmann::json &e : *used)
            if (e.is_string())
                w.used.push_back(e.get<std::string>());
    w.walk_object(root, root_object, "");
    *rewritten = w.rewrote;
    return w.count;
}
