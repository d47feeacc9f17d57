// Draco (google/draco 1.5) behind the C interface of gltf_shim.h: decoding a payload into plain arrays, encoding a
// triangle mesh with per-attribute quantization. KHR_draco_mesh_compression (Khronos) defines how glTF uses it.
//
// Decoding copies every attribute out per point, in point order, as raw numbers: the glTF side knows whether an
// accessor is normalized and applies that itself. Every attribute value index is checked against the attribute's
// storage before it is read, so a payload whose point-to-value map points outside fails instead of reading past it.
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <string>

#include <draco/compression/decode.h>
#include <draco/compression/expert_encode.h>
#include <draco/mesh/mesh.h>

#include "gltf_shim.h"

namespace {

// One raw value of a Draco data type as a double (integers up to 2^53 are exact).
double read_number(const unsigned char *p, draco::DataType type)
{
    switch (type) {
    case draco::DT_INT8: { int8_t x; std::memcpy(&x, p, 1); return x; }
    case draco::DT_UINT8: return p[0];
    case draco::DT_INT16: { int16_t x; std::memcpy(&x, p, 2); return x; }
    case draco::DT_UINT16: { uint16_t x; std::memcpy(&x, p, 2); return x; }
    case draco::DT_INT32: { int32_t x; std::memcpy(&x, p, 4); return x; }
    case draco::DT_UINT32: { uint32_t x; std::memcpy(&x, p, 4); return x; }
    case draco::DT_INT64: { int64_t x; std::memcpy(&x, p, 8); return (double)x; }
    case draco::DT_UINT64: { uint64_t x; std::memcpy(&x, p, 8); return (double)x; }
    case draco::DT_FLOAT32: { float x; std::memcpy(&x, p, 4); return x; }
    case draco::DT_FLOAT64: { double x; std::memcpy(&x, p, 8); return x; }
    case draco::DT_BOOL: return p[0] != 0;
    default: return 0;
    }
}

// Reads a LEB128 varint of at most 5 bytes (Draco's DecodeVarint<uint32_t>) at *at; false past the end or when it
// does not fit 32 bits.
bool read_varint(const unsigned char *p, size_t size, size_t *at, uint64_t *out)
{
    uint64_t x = 0;
    for (int k = 0; k < 5; ++k) {
        if (*at >= size)
            return false;
        unsigned char b = p[(*at)++];
        x |= (uint64_t)(b & 0x7f) << (7 * k);
        if (!(b & 0x80)) {
            *out = x;
            return x <= 0xffffffffu;
        }
    }
    return false;
}

// Edgebreaker's connectivity header claims counts of vertices and faces, and Draco reserves and allocates for them
// (the corner table, the processed corners) before it reads a symbol: a hundred bytes could make it allocate
// gigabytes. This reads them (draco/compression/mesh: the 11-byte header "DRACO", major, minor, encoder type, method,
// uint16 flags; the traversal decoder type byte; before bitstream 2.2 a count of new vertices; then the encoded
// vertices and the faces, uint32 before bitstream 2.0 and varints since) and refuses counts beyond 2^20 plus 256 per
// byte of payload: no real mesh compresses further, since each face costs its connectivity symbol and its vertices'
// values. Metadata (flag 0x8000 from bitstream 1.3) would come before these counts, with a layout of its own: such
// payloads are refused. Sequential meshes are checked by Draco (faces against the bytes left).
resurf_status check_edgebreaker_counts(const unsigned char *p, size_t size, resurf_error *error)
{
    if (size < 12 || p[8] != 1)
        return RESURF_OK; // too short for Draco to decode anyway, or not Edgebreaker
    unsigned version = (unsigned)p[5] << 8 | p[6];
    if (((p[9] | p[10] << 8) & 0x8000) && version >= 0x103)
        return resurfi_fail(error, RESURF_ERR_UNSUPPORTED, NULL, 0, -1, "Draco meshes with metadata are not supported");
    size_t at = 12;
    uint64_t counts[3] = {0, 0, 0}; // new vertices (before 2.2), encoded vertices, faces
    for (int k = version < 0x202 ? 0 : 1; k < 3; ++k) {
        if (version < 0x200) {
            if (size - at < 4)
                return resurfi_fail(error, RESURF_ERR_PARSE, NULL, 0, -1, "the Draco data is corrupt: cut short");
            counts[k] = (uint64_t)p[at] | (uint64_t)p[at + 1] << 8 | (uint64_t)p[at + 2] << 16 |
                        (uint64_t)p[at + 3] << 24;
            at += 4;
        } else if (!read_varint(p, size, &at, &counts[k])) {
            return resurfi_fail(error, RESURF_ERR_PARSE, NULL, 0, -1, "the Draco data is corrupt: bad count");
        }
    }
    uint64_t limit = ((uint64_t)1 << 20) + 256 * (uint64_t)size;
    for (int k = 0; k < 3; ++k)
        if (counts[k] > limit)
            return resurfi_fail(error, RESURF_ERR_LIMIT, NULL, 0, -1,
                                "the Draco data claims %llu %s, more than its %zu bytes can justify",
                                (unsigned long long)counts[k], k == 2 ? "faces" : "vertices", size);
    return RESURF_OK;
}

void free_mesh(resurfi_draco_mesh *m)
{
    if (!m)
        return;
    std::free(m->faces);
    for (size_t i = 0; i < m->attribute_count; ++i)
        std::free(m->attributes[i].values);
    std::free(m->attributes);
    std::free(m);
}

resurf_status decode(const void *data, size_t size, resurfi_draco_mesh **out, resurf_error *error)
{
    draco::DecoderBuffer buffer;
    buffer.Init(static_cast<const char *>(data), size);
    auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
    if (!type.ok())
        return resurfi_fail(error, RESURF_ERR_PARSE, NULL, 0, -1, "the Draco data is corrupt: %s",
                            type.status().error_msg());
    // Point clouds are never decoded: resurf has no use for one (a glTF points primitive is copied untouched), and
    // Draco sizes a point cloud's attributes from counts in its header before it reads a value, so that a hundred
    // bytes could make it allocate gigabytes.
    if (type.value() == draco::POINT_CLOUD)
        return resurfi_fail(error, RESURF_ERR_UNSUPPORTED, NULL, 0, -1, "the Draco data is a point cloud");
    resurf_status checked = check_edgebreaker_counts(static_cast<const unsigned char *>(data), size, error);
    if (checked != RESURF_OK)
        return checked;
    draco::Decoder decoder;
    std::unique_ptr<draco::PointCloud> cloud;
    const draco::Mesh *mesh = nullptr;
    if (type.value() == draco::TRIANGULAR_MESH) {
        auto r = decoder.DecodeMeshFromBuffer(&buffer);
        if (!r.ok())
            return resurfi_fail(error, RESURF_ERR_PARSE, NULL, 0, -1, "the Draco data is corrupt: %s",
                                r.status().error_msg());
        mesh = r.value().get();
        cloud = std::move(r).value();
    } else {
        return resurfi_fail(error, RESURF_ERR_PARSE, NULL, 0, -1, "the Draco data holds no mesh");
    }

    resurfi_draco_mesh *m = static_cast<resurfi_draco_mesh *>(std::calloc(1, sizeof *m));
    if (!m)
        throw std::bad_alloc();
    std::unique_ptr<resurfi_draco_mesh, void (*)(resurfi_draco_mesh *)> guard(m, free_mesh);
    m->point_count = cloud->num_points();
    size_t n = m->point_count;
    if (mesh) {
        m->face_count = mesh->num_faces();
        m->faces = static_cast<uint32_t *>(std::malloc(3 * m->face_count * sizeof(uint32_t) + 1));
        if (!m->faces)
            throw std::bad_alloc();
        // A corrupt payload can decode to faces on points that do not exist: refuse it here, for every caller.
        for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f)
            for (int c = 0; c < 3; ++c) {
                uint32_t point = mesh->face(f)[c].value();
                if (point >= n)
                    return resurfi_fail(error, RESURF_ERR_PARSE, NULL, 0, -1,
                                        "the Draco data is corrupt: face %u refers to point %u of %zu", f.value(),
                                        point, n);
                m->faces[3 * f.value() + c] = point;
            }
    }
    int count = cloud->num_attributes();
    m->attributes = static_cast<resurfi_draco_attribute *>(std::calloc((size_t)count + 1, sizeof *m->attributes));
    if (!m->attributes)
        throw std::bad_alloc();
    for (int a = 0; a < count; ++a) {
        const draco::PointAttribute *pa = cloud->attribute(a);
        resurfi_draco_attribute &o = m->attributes[m->attribute_count++];
        o.unique_id = (int)pa->unique_id();
        o.type = (int)pa->attribute_type();
        o.components = pa->num_components();
        draco::DataType dt = pa->data_type();
        o.integer = dt != draco::DT_FLOAT32 && dt != draco::DT_FLOAT64;
        switch (dt) {
        case draco::DT_INT8: o.integer_max = 127; break;
        case draco::DT_UINT8: o.integer_max = 255; break;
        case draco::DT_INT16: o.integer_max = 32767; break;
        case draco::DT_UINT16: o.integer_max = 65535; break;
        case draco::DT_INT32: o.integer_max = 2147483647.0; break;
        case draco::DT_UINT32: o.integer_max = 4294967295.0; break;
        case draco::DT_BOOL: o.integer_max = 1; break;
        default: o.integer_max = o.integer ? 9223372036854775807.0 : 0; break;
        }
        size_t width = (size_t)draco::DataTypeLength(dt);
        size_t stride = (size_t)pa->byte_stride();
        if (o.components < 1 || width == 0 || stride < width * (size_t)o.components)
            return resurfi_fail(error, RESURF_ERR_PARSE, NULL, 0, -1,
                                "the Draco data is corrupt: attribute %d has an unusable layout", o.unique_id);
        if (n > SIZE_MAX / sizeof(double) / (size_t)o.components)
            throw std::bad_alloc();
        o.values = static_cast<double *>(std::malloc(n * (size_t)o.components * sizeof(double) + 1));
        if (!o.values)
            throw std::bad_alloc();
        const draco::DataBuffer *storage = pa->buffer();
        size_t values = pa->size();
        if (!storage || (values && (size_t)storage->data_size() < (size_t)pa->byte_offset() + values * stride))
            return resurfi_fail(error, RESURF_ERR_PARSE, NULL, 0, -1,
                                "the Draco data is corrupt: attribute %d is shorter than its values", o.unique_id);
        const unsigned char *base = storage->data() + pa->byte_offset();
        for (size_t i = 0; i < n; ++i) {
            draco::AttributeValueIndex avi = pa->mapped_index(draco::PointIndex((uint32_t)i));
            if (avi.value() >= values)
                return resurfi_fail(error, RESURF_ERR_PARSE, NULL, 0, -1,
                                    "the Draco data is corrupt: point %zu of attribute %d has no value", i,
                                    o.unique_id);
            const unsigned char *p = base + (size_t)avi.value() * stride;
            for (int c = 0; c < o.components; ++c)
                o.values[i * (size_t)o.components + (size_t)c] = read_number(p + (size_t)c * width, dt);
        }
    }
    *out = guard.release();
    return RESURF_OK;
}

draco::DataType draco_type(int t)
{
    switch (t) {
    case RESURFI_DRACO_U8: return draco::DT_UINT8;
    case RESURFI_DRACO_U16: return draco::DT_UINT16;
    case RESURFI_DRACO_U32: return draco::DT_UINT32;
    case RESURFI_DRACO_I8: return draco::DT_INT8;
    case RESURFI_DRACO_I16: return draco::DT_INT16;
    default: return draco::DT_FLOAT32;
    }
}

resurf_status encode(const resurfi_draco_input *in, resurfi_draco_output *out, resurf_error *error)
{
    if (in->attribute_count > sizeof out->unique_ids / sizeof out->unique_ids[0])
        return resurfi_fail(error, RESURF_ERR_UNSUPPORTED, NULL, 0, -1, "more than 32 attributes for Draco");
    if (in->vertex_count > UINT32_MAX / 2 || in->triangle_count > UINT32_MAX / 2)
        return resurfi_fail(error, RESURF_ERR_LIMIT, NULL, 0, -1, "the mesh is too large for Draco");
    std::unique_ptr<draco::PointCloud> geometry;
    draco::Mesh *mesh = nullptr;
    if (in->triangle_count) {
        mesh = new draco::Mesh();
        geometry.reset(mesh);
        mesh->SetNumFaces(in->triangle_count);
        for (size_t t = 0; t < in->triangle_count; ++t) {
            draco::Mesh::Face face;
            for (int c = 0; c < 3; ++c)
                face[c] = draco::PointIndex(in->indices[3 * t + (size_t)c]);
            mesh->SetFace(draco::FaceIndex((uint32_t)t), face);
        }
    } else {
        geometry.reset(new draco::PointCloud());
    }
    geometry->set_num_points((uint32_t)in->vertex_count);
    int ids[32];
    for (size_t a = 0; a < in->attribute_count; ++a) {
        const resurfi_draco_input_attribute &src = in->attributes[a];
        draco::DataType dt = draco_type(src.data_type);
        draco::GeometryAttribute ga;
        int64_t stride = (int64_t)draco::DataTypeLength(dt) * src.components;
        ga.Init(static_cast<draco::GeometryAttribute::Type>(src.type), nullptr, (uint8_t)src.components, dt,
                src.normalized != 0, stride, 0);
        int id = geometry->AddAttribute(ga, true, (uint32_t)in->vertex_count);
        if (id < 0)
            return resurfi_fail(error, RESURF_ERR_INTERNAL, NULL, 0, -1, "Draco refused attribute %zu", a);
        draco::PointAttribute *pa = geometry->attribute(id);
        const unsigned char *values = static_cast<const unsigned char *>(src.values);
        for (size_t v = 0; v < in->vertex_count; ++v)
            pa->SetAttributeValue(draco::AttributeValueIndex((uint32_t)v), values + v * (size_t)stride);
        ids[a] = id;
    }
    // Equal points become one, as Draco's own encoder and transcoder do before encoding: Edgebreaker then sees the
    // connectivity of the surface rather than of the attribute seams' copies.
    // Not with keep_order: uncompressed morph targets beside the payload index the points in the input's order.
    if (!in->keep_order) {
        geometry->DeduplicateAttributeValues();
        geometry->DeduplicatePointIds();
    }

    std::unique_ptr<draco::ExpertEncoder> encoder(mesh ? new draco::ExpertEncoder(*mesh)
                                                       : new draco::ExpertEncoder(*geometry));
    for (size_t a = 0; a < in->attribute_count; ++a)
        if (in->attributes[a].data_type == RESURFI_DRACO_F32 && in->attributes[a].quantization_bits > 0)
            encoder->SetAttributeQuantization(ids[a], in->attributes[a].quantization_bits);
    int speed = 10 - in->compression_level;
    encoder->SetSpeedOptions(speed, speed);
    encoder->SetTrackEncodedProperties(true);
    if (in->keep_order && mesh) // Edgebreaker renumbers the points as it walks the surface; sequential does not
        encoder->SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
    draco::EncoderBuffer buffer;
    draco::Status status = encoder->EncodeToBuffer(&buffer);
    if (!status.ok())
        return resurfi_fail(error, RESURF_ERR_INTERNAL, NULL, 0, -1, "Draco could not encode the mesh: %s",
                            status.error_msg());
    out->size = buffer.size();
    out->data = static_cast<unsigned char *>(std::malloc(out->size + 1));
    if (!out->data)
        throw std::bad_alloc();
    std::memcpy(out->data, buffer.data(), out->size);
    for (size_t a = 0; a < in->attribute_count; ++a)
        out->unique_ids[a] = (int)geometry->attribute(ids[a])->unique_id();
    out->encoded_points = encoder->num_encoded_points();
    out->encoded_faces = encoder->num_encoded_faces();
    return RESURF_OK;
}

} // namespace

extern "C" resurf_status resurfi_draco_decode(const void *data, size_t size, resurfi_draco_mesh **out,
                                              resurf_error *error)
{
    *out = nullptr;
    try {
        return decode(data, size, out, error);
    } catch (const std::bad_alloc &) {
        return resurfi_fail(error, RESURF_ERR_OUT_OF_MEMORY, NULL, 0, -1, "out of memory decoding Draco data");
    } catch (const std::exception &e) {
        return resurfi_fail(error, RESURF_ERR_PARSE, NULL, 0, -1, "the Draco data cannot be decoded: %s", e.what());
    } catch (...) {
        return resurfi_fail(error, RESURF_ERR_INTERNAL, NULL, 0, -1, "unexpected exception decoding Draco data");
    }
}

extern "C" void resurfi_draco_mesh_free(resurfi_draco_mesh *mesh) { free_mesh(mesh); }

extern "C" resurf_status resurfi_draco_encode(const resurfi_draco_input *in, resurfi_draco_output *out,
                                              resurf_error *error)
{
    std::memset(out, 0, sizeof *out);
    try {
        resurf_status s = encode(in, out, error);
        if (s != RESURF_OK) {
            std::free(out->data);
            std::memset(out, 0, sizeof *out);
        }
        return s;
    } catch (const std::bad_alloc &) {
        std::free(out->data);
        std::memset(out, 0, sizeof *out);
        return resurfi_fail(error, RESURF_ERR_OUT_OF_MEMORY, NULL, 0, -1, "out of memory encoding Draco data");
    } catch (...) {
        std::free(out->data);
        std::memset(out, 0, sizeof *out);
        return resurfi_fail(error, RESURF_ERR_INTERNAL, NULL, 0, -1, "unexpected exception encoding Draco data");
    }
}
