// EXT_meshopt_compression: buffer views whose bytes are meshoptimizer streams, decoded
// (libmeshoptimizer-dev) before any accessor reads them. The view's own buffer may be the
// extension's fallback buffer, which holds no bytes; the stream lies in the extension's
// buffer, byteOffset and byteLength.

#include "gltf/gltf_internal.h"

#include <librt/core/untrusted_text.h>

#include <meshoptimizer.h>

#include <string>

namespace librt::gltf_detail {

namespace {

using tinygltf::Value;

/// A non-negative integer member of the extension object, or a failure naming it.
std::uint64_t size_member(const Value& ext, const char* key, bool required, std::uint64_t fallback,
                          const std::string& path, const Context& ctx) {
    if (!ext.Has(key)) {
        if (required) ctx.fail(path + "." + key, "missing");
        return fallback;
    }
    const Value& v = ext.Get(key);
    if (!v.IsNumber()) ctx.fail(path + "." + key, "must be an integer");
    const double d = v.GetNumberAsDouble();
    // Below 2^53: exact in a double, and sums of two cannot overflow 64 bits.
    if (!(d >= 0) || d > 9007199254740992.0 || d != double(std::uint64_t(d)))
        ctx.fail(path + "." + key, number_text(d) + ": must be a non-negative integer");
    return std::uint64_t(d);
}

std::string string_member(const Value& ext, const char* key, const std::string& fallback,
                          const std::string& path, const Context& ctx) {
    if (!ext.Has(key)) return fallback;
    const Value& v = ext.Get(key);
    if (!v.IsString()) ctx.fail(path + "." + key, "must be a string");
    return v.Get<std::string>();
}

void decode_view(const tinygltf::Model& model, std::size_t index, const Value& ext, Context& ctx) {
    const std::string path = indexed("bufferViews", index) + ".extensions.EXT_meshopt_compression";
    if (!ext.IsObject()) ctx.fail(path, "must be an object");
    const std::uint64_t buffer = size_member(ext, "buffer", true, 0, path, ctx);
    if (buffer >= ctx.buffer_count())
        ctx.fail(path + ".buffer", "buffer " + std::to_string(buffer) + " does not exist (" +
                                       std::to_string(ctx.buffer_count()) + " in the file)");
    const std::uint64_t offset = size_member(ext, "byteOffset", false, 0, path, ctx);
    const std::uint64_t length = size_member(ext, "byteLength", true, 0, path, ctx);
    const std::uint64_t stride = size_member(ext, "byteStride", true, 0, path, ctx);
    const std::uint64_t count = size_member(ext, "count", true, 0, path, ctx);
    const std::string mode = string_member(ext, "mode", "", path, ctx);
    const std::string filter = string_member(ext, "filter", "NONE", path, ctx);
    const std::string_view bytes = ctx.buffer(std::size_t(buffer));
    if (offset > bytes.size() || length > bytes.size() - offset)
        ctx.fail(path, "bytes [" + std::to_string(offset) + ", " + std::to_string(offset + length) +
                           ") lie outside buffers[" + std::to_string(buffer) + "]'s " +
                           std::to_string(bytes.size()) + " bytes of data");
    // The limits meshoptimizer's decoders assert on are checked here, as errors.
    if (mode == "ATTRIBUTES") {
        if (stride == 0 || stride % 4 != 0 || stride > 256)
            ctx.fail(path + ".byteStride",
                     std::to_string(stride) + ": ATTRIBUTES needs a multiple of 4 in [4, 256]");
    } else if (mode == "TRIANGLES" || mode == "INDICES") {
        if (stride != 2 && stride != 4)
            ctx.fail(path + ".byteStride", std::to_string(stride) + ": " + mode +
                                               " needs 2 or 4 (16- or 32-bit indices)");
        if (mode == "TRIANGLES" && count % 3 != 0)
            ctx.fail(path + ".count", std::to_string(count) + ": TRIANGLES needs a multiple of 3");
    } else {
        ctx.fail(path + ".mode",
                 quote_untrusted(mode) + ": must be ATTRIBUTES, TRIANGLES or INDICES");
    }
    if (filter != "NONE") {
        if (mode != "ATTRIBUTES") ctx.fail(path + ".filter", "filters apply to ATTRIBUTES only");
        const bool ok = filter == "OCTAHEDRAL"    ? (stride == 4 || stride == 8)
                        : filter == "QUATERNION"  ? stride == 8
                        : filter == "EXPONENTIAL" ? stride % 4 == 0
                                                  : false;
        if (!ok)
            ctx.fail(path + ".filter", quote_untrusted(filter) + " with byteStride " +
                                           std::to_string(stride) +
                                           " (OCTAHEDRAL: 4 or 8, QUATERNION: 8, EXPONENTIAL: a "
                                           "multiple of 4)");
    }
    const tinygltf::BufferView& bv = model.bufferViews[index];
    // The decoded bytes; count and stride are below 2^53, so a huge product is caught by
    // the allowance before it could overflow (stride <= 256, count < 2^53 / 256 checked).
    if (count > (std::uint64_t{1} << 53u) / 256)
        ctx.fail(path + ".count", std::to_string(count) + " is too large");
    const std::uint64_t decoded = count * stride;
    if (bv.byteLength > decoded)
        ctx.fail(path, "decodes to " + std::to_string(decoded) + " bytes (count " +
                           std::to_string(count) + " x byteStride " + std::to_string(stride) +
                           "), fewer than the buffer view's byteLength " +
                           std::to_string(bv.byteLength));
    ctx.spend(decoded, path);
    std::vector<unsigned char> out(decoded);
    const auto* stream = reinterpret_cast<const unsigned char*>(bytes.data()) + offset;
    int rc = 0;
    if (mode == "ATTRIBUTES")
        rc = meshopt_decodeVertexBuffer(out.data(), count, stride, stream, length);
    else if (mode == "TRIANGLES")
        rc = meshopt_decodeIndexBuffer(out.data(), count, stride, stream, length);
    else
        rc = meshopt_decodeIndexSequence(out.data(), count, stride, stream, length);
    if (rc != 0)
        ctx.fail(path, "the " + mode + " stream of " + std::to_string(length) +
                           " bytes does not decode (corrupt or truncated; meshoptimizer error " +
                           std::to_string(rc) + ")");
    if (filter == "OCTAHEDRAL") meshopt_decodeFilterOct(out.data(), count, stride);
    if (filter == "QUATERNION") meshopt_decodeFilterQuat(out.data(), count, stride);
    if (filter == "EXPONENTIAL") meshopt_decodeFilterExp(out.data(), count, stride);
    ctx.set_view_bytes(index, std::move(out));
}

}  // namespace

void decode_meshopt_views(const tinygltf::Model& model, Context& ctx) {
    for (std::size_t i = 0; i < model.bufferViews.size(); ++i) {
        const auto& extensions = model.bufferViews[i].extensions;
        const auto it = extensions.find("EXT_meshopt_compression");
        if (it != extensions.end()) decode_view(model, i, it->second, ctx);
    }
}

}  // namespace librt::gltf_detail
