// KHR_draco_mesh_compression: a primitive whose attributes and indices are one Draco
// stream in a buffer view, decoded with Debian's libdraco. Debian's tinygltf is a shared
// library built without TINYGLTF_ENABLE_DRACO (and librt gives it no buffer bytes), so
// librt decodes the stream itself. The stream is untrusted: the counts its header claims
// are checked against the primitive's accessors, whose memory is charged to the load's
// allowance, before Draco allocates anything.

#include "gltf/gltf_internal.h"

#include <librt/core/untrusted_text.h>

#include <draco/compression/decode.h>

#include <cmath>
#include <cstring>
#include <exception>
#include <new>
#include <string>

namespace librt::gltf_detail {

namespace {

using tinygltf::Value;

/// What a Draco stream's header and connectivity header claim.
struct DracoHeader {
    bool edgebreaker = false;    ///< method 1 (else 0, sequential)
    std::uint64_t faces = 0;     ///< triangles
    std::uint64_t points = 0;    ///< sequential: the point count
    std::uint64_t vertices = 0;  ///< edgebreaker: connectivity vertices (<= points)
};

/// Reads the fixed header and the first connectivity fields (Draco bitstream 2.2, as in
/// the Draco bitstream specification: "DRACO", major, minor, encoder type, method, u16
/// flags; then for sequential varint faces and points, for edgebreaker a traversal byte
/// and varint vertices and faces). Returns the reason when it cannot.
std::string read_header(std::string_view s, DracoHeader& h) {
    if (s.size() < 11 || s.substr(0, 5) != "DRACO") return "not a Draco stream (no 'DRACO' magic)";
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(s[i]); };
    if (byte(5) != 2 || byte(6) != 2)
        return "Draco bitstream version " + std::to_string(byte(5)) + "." +
               std::to_string(byte(6)) + ": only 2.2 (written by Draco 1.3 and later) is read";
    if (byte(7) != 1) return "a Draco point cloud, not a triangle mesh";
    if (byte(8) > 1) return "unknown Draco encoding method " + std::to_string(byte(8));
    const unsigned flags = unsigned(byte(9)) | unsigned(byte(10)) << 8u;
    // Metadata would lie between the header and the counts; glTF encoders write none.
    if ((flags & 0x8000u) != 0) return "Draco metadata is not read";
    h.edgebreaker = byte(8) == 1;
    std::size_t at = 11;
    const auto varint = [&](std::uint64_t& out) {
        out = 0;
        for (unsigned shift = 0; shift < 35; shift += 7) {
            if (at >= s.size()) return false;
            const unsigned char b = byte(at++);
            out |= std::uint64_t(b & 0x7Fu) << shift;
            if ((b & 0x80u) == 0) return true;
        }
        return false;
    };
    bool ok = false;
    if (h.edgebreaker) {
        ++at;  // traversal decoder type
        ok = varint(h.vertices) && varint(h.faces);
    } else {
        ok = varint(h.faces) && varint(h.points);
    }
    return ok ? std::string() : "truncated Draco header";
}

/// The bytes of buffer view `view` (decoded ones for EXT_meshopt_compression).
std::string_view view_bytes(const tinygltf::Model& model, int view, const std::string& path,
                            const Context& ctx) {
    check_index(ctx, path, view, model.bufferViews.size(), "buffer view");
    const tinygltf::BufferView& bv = model.bufferViews[std::size_t(view)];
    if (const auto* decoded = ctx.view_bytes(std::size_t(view)))
        return {reinterpret_cast<const char*>(decoded->data()), bv.byteLength};
    check_index(ctx, indexed("bufferViews", std::size_t(view)) + ".buffer", bv.buffer,
                ctx.buffer_count(), "buffer");
    const std::string_view buffer = ctx.buffer(std::size_t(bv.buffer));
    if (bv.byteOffset > buffer.size() || bv.byteLength > buffer.size() - bv.byteOffset)
        ctx.fail(indexed("bufferViews", std::size_t(view)), "lies outside its buffer's data");
    return buffer.substr(bv.byteOffset, bv.byteLength);
}

/// The divisor that maps a normalised integer of the accessor's componentType to [0, 1]
/// or [-1, 1] (glTF 2.0, section 3.11), or 0 for floats.
float normaliser(int component_type) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
            return 127.0f;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return 255.0f;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            return 32767.0f;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return 65535.0f;
        default:
            return 0.0f;
    }
}

}  // namespace

bool has_draco(const tinygltf::Primitive& prim) {
    return prim.extensions.count("KHR_draco_mesh_compression") != 0;
}

DracoPrimitive decode_draco(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                            const std::string& prim_path, Context& ctx) {
    const std::string path = prim_path + ".extensions.KHR_draco_mesh_compression";
    const Value& ext = prim.extensions.at("KHR_draco_mesh_compression");
    if (!ext.IsObject() || !ext.Has("bufferView") || !ext.Get("bufferView").IsInt())
        ctx.fail(path + ".bufferView", "missing or not an integer");
    if (!ext.Has("attributes") || !ext.Get("attributes").IsObject())
        ctx.fail(path + ".attributes", "missing or not an object");
    const std::string_view stream =
        view_bytes(model, ext.Get("bufferView").Get<int>(), path + ".bufferView", ctx);

    // The counts the primitive's accessors declare bound what the stream may decode to.
    const auto pos = prim.attributes.find("POSITION");
    if (pos == prim.attributes.end()) ctx.fail(prim_path + ".attributes", "no POSITION");
    check_index(ctx, prim_path + ".attributes.POSITION", pos->second, model.accessors.size(),
                "accessor");
    const std::uint64_t points = accessor_count(model, pos->second);
    std::uint64_t corners = points;
    // The primitive's indices, moved here by check_json (tinygltf refuses an indices
    // accessor without a buffer view).
    if (ext.Has("librtIndices")) {
        const Value& indices = ext.Get("librtIndices");
        if (!indices.IsInt()) ctx.fail(prim_path + ".indices", "must be an integer");
        check_index(ctx, prim_path + ".indices", indices.Get<int>(), model.accessors.size(),
                    "accessor");
        corners = accessor_count(model, indices.Get<int>());
    }
    DracoHeader header;
    if (const std::string why = read_header(stream, header); !why.empty()) ctx.fail(path, why);
    const bool counts_agree =
        header.faces * 3 == corners &&
        (header.edgebreaker ? header.vertices <= points : header.points == points);
    if (!counts_agree)
        ctx.fail(path, "the Draco stream claims " + std::to_string(header.faces) +
                           " triangles and " +
                           std::to_string(header.edgebreaker ? header.vertices : header.points) +
                           (header.edgebreaker ? " vertices" : " points") +
                           ", the accessors declare " + std::to_string(corners) + " indices and " +
                           std::to_string(points) + " vertices");
    // Draco's own tables: a corner table of a few ints per corner and a copy of every
    // attribute (at most 4 components of 8 bytes per point): charged before decoding.
    // Both counts are below 2^53 (the pre-pass), so neither product overflows.
    ctx.spend(corners * 48, path);
    for (std::size_t k = 0; k <= ext.Get("attributes").Keys().size(); ++k)
        ctx.spend(points * 32, path);

    draco::DecoderBuffer buffer;
    buffer.Init(stream.data(), stream.size());
    draco::Decoder decoder;
    std::unique_ptr<draco::Mesh> mesh;
    try {
        auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
        if (!decoded.ok())
            ctx.fail(path, "the Draco stream does not decode: " +
                               printable(decoded.status().error_msg_string(), 200));
        mesh = std::move(decoded).value();
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        ctx.fail(path, std::string("the Draco stream does not decode: ") + e.what());
    }
    if (mesh == nullptr) ctx.fail(path, "the Draco stream decodes to no mesh");
    if (std::uint64_t(mesh->num_points()) != points ||
        std::uint64_t(mesh->num_faces()) * 3 != corners)
        ctx.fail(path, "decodes to " + std::to_string(mesh->num_points()) + " points and " +
                           std::to_string(mesh->num_faces()) + " triangles, not the accessors' " +
                           std::to_string(points) + " vertices and " + std::to_string(corners) +
                           " indices");

    DracoPrimitive out;
    ctx.spend(corners * sizeof(std::uint32_t), path);
    out.indices.resize(corners);
    for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f) {
        const draco::Mesh::Face& face = mesh->face(f);
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t index = face[std::size_t(k)].value();
            if (index >= points)
                ctx.fail(path, "triangle " + std::to_string(f.value()) + " names point " +
                                   std::to_string(index) + " of " + std::to_string(points));
            out.indices[std::size_t(f.value()) * 3 + std::size_t(k)] = index;
        }
    }
    const Value& ids = ext.Get("attributes");
    for (const std::string& name : ids.Keys()) {
        const std::string at = path + ".attributes." + name;
        const Value& id = ids.Get(name);
        if (!id.IsInt() || id.Get<int>() < 0) ctx.fail(at, "must be a non-negative integer");
        const auto use = prim.attributes.find(name);
        if (use == prim.attributes.end())
            ctx.fail(at, "names an attribute the primitive's attributes do not list");
        check_index(ctx, prim_path + ".attributes." + name, use->second, model.accessors.size(),
                    "accessor");
        const tinygltf::Accessor& accessor = model.accessors[std::size_t(use->second)];
        const draco::PointAttribute* attribute =
            mesh->GetAttributeByUniqueId(static_cast<std::uint32_t>(id.Get<int>()));
        if (attribute == nullptr)
            ctx.fail(at,
                     "Draco attribute " + std::to_string(id.Get<int>()) + " is not in the stream");
        const int components = type_components(accessor.type);
        if (components == 0 || attribute->num_components() != components)
            ctx.fail(at, "Draco attribute has " + std::to_string(attribute->num_components()) +
                             " components, the accessor's type " + std::to_string(components));
        // Values stay as the accessor describes them: normalised integers are mapped as
        // the accessor says unless Draco already did.
        const float divisor = accessor.normalized && !attribute->normalized()
                                  ? normaliser(accessor.componentType)
                                  : 0.0f;
        ctx.spend(points * std::uint64_t(components) * sizeof(float), at);
        std::vector<float> values(points * std::size_t(components));
        for (draco::PointIndex p(0); p < mesh->num_points(); ++p) {
            float* v = &values[std::size_t(p.value()) * std::size_t(components)];
            if (!attribute->ConvertValue<float>(attribute->mapped_index(p),
                                                static_cast<std::int8_t>(components), v))
                ctx.fail(at, "point " + std::to_string(p.value()) + " does not convert");
            for (int j = 0; j < components; ++j) {
                if (divisor != 0.0f) v[j] = std::max(v[j] / divisor, -1.0f);
                if (!std::isfinite(v[j]))
                    ctx.fail(at, "point " + std::to_string(p.value()) + " is not finite");
            }
        }
        out.attributes.emplace(name, std::move(values));
    }
    return out;
}

}  // namespace librt::gltf_detail
