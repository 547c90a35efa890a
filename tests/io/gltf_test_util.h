#pragma once

// Writing small glTF files in tests: a JSON document (nlohmann-json) plus buffer 0, saved
// as .glb, as .gltf with a data: URI, or as .gltf with an external .bin. Written here, by
// hand, so that the loader is checked against files it did not produce.

#include <nlohmann/json.hpp>
#include <stb/stb_image_write.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace librt::testing {

constexpr int kFloat = 5126, kU8 = 5121, kU16 = 5123, kU32 = 5125, kI16 = 5122, kI8 = 5120;

/// RFC 4648 base64 of bytes.
inline std::string base64(const std::string& bytes) {
    static const char* alphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const auto n = std::uint32_t(std::uint8_t(bytes[i])) << 16u |
                       std::uint32_t(std::uint8_t(bytes[i + 1])) << 8u | std::uint8_t(bytes[i + 2]);
        for (int k = 3; k >= 0; --k) out += alphabet[(n >> (6u * unsigned(k))) & 63u];
    }
    if (i + 1 == bytes.size()) {
        const auto n = std::uint32_t(std::uint8_t(bytes[i])) << 16u;
        out += alphabet[(n >> 18u) & 63u];
        out += alphabet[(n >> 12u) & 63u];
        out += "==";
    } else if (i + 2 == bytes.size()) {
        const auto n = std::uint32_t(std::uint8_t(bytes[i])) << 16u |
                       std::uint32_t(std::uint8_t(bytes[i + 1])) << 8u;
        out += alphabet[(n >> 18u) & 63u];
        out += alphabet[(n >> 12u) & 63u];
        out += alphabet[(n >> 6u) & 63u];
        out += '=';
    }
    return out;
}

/// A glTF document under construction, with its buffer 0.
struct GltfBuilder {
    nlohmann::json doc = {{"asset", {{"version", "2.0"}}}};
    std::string bin;  ///< buffer 0

    /// Appends bytes (4-byte aligned) as a new buffer view; returns its index.
    int add_view(const void* data, std::size_t size, int stride = 0) {
        while (bin.size() % 4 != 0) bin.push_back('\0');
        nlohmann::json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", size}};
        if (stride != 0) view["byteStride"] = stride;
        bin.append(static_cast<const char*>(data), size);
        doc["bufferViews"].push_back(view);
        return int(doc["bufferViews"].size()) - 1;
    }
    /// A buffer view plus an accessor over it; returns the accessor's index.
    template <class T>
    int add_accessor(const std::vector<T>& values, int component_type, const char* type,
                     std::size_t count, bool normalized = false) {
        const int view = add_view(values.data(), values.size() * sizeof(T));
        nlohmann::json a = {{"bufferView", view},
                            {"componentType", component_type},
                            {"count", count},
                            {"type", type}};
        if (normalized) a["normalized"] = true;
        doc["accessors"].push_back(a);
        return int(doc["accessors"].size()) - 1;
    }
    /// The JSON with buffer 0 declared (uri omitted when empty).
    [[nodiscard]] nlohmann::json with_buffer(const std::string& uri) const {
        nlohmann::json d = doc;
        nlohmann::json b = {{"byteLength", bin.size()}};
        if (!uri.empty()) b["uri"] = uri;
        if (!bin.empty()) d["buffers"] = nlohmann::json::array({b});
        return d;
    }
    /// The whole file as .gltf with buffer 0 in a data: URI.
    [[nodiscard]] std::string gltf() const {
        return with_buffer("data:application/octet-stream;base64," + base64(bin)).dump();
    }
    /// The whole file as .glb (JSON chunk, then BIN chunk when there is data).
    [[nodiscard]] std::string glb() const { return make_glb(with_buffer("").dump(), bin); }

    /// A .glb of the given JSON text and BIN payload, each padded to 4 bytes.
    static std::string make_glb(std::string json, std::string payload) {
        while (json.size() % 4 != 0) json.push_back(' ');
        while (payload.size() % 4 != 0) payload.push_back('\0');
        std::string out;
        auto u32 = [&out](std::uint32_t v) {
            for (int k = 0; k < 4; ++k) out.push_back(char((v >> (8u * unsigned(k))) & 0xFFu));
        };
        const std::size_t total = 12 + 8 + json.size() + (payload.empty() ? 0 : 8 + payload.size());
        out += "glTF";
        u32(2);
        u32(std::uint32_t(total));
        u32(std::uint32_t(json.size()));
        u32(0x4E4F534Au);
        out += json;
        if (!payload.empty()) {
            u32(std::uint32_t(payload.size()));
            u32(0x004E4942u);
            out += payload;
        }
        return out;
    }
};

/// Writes bytes to a file.
inline void write_file(const std::filesystem::path& p, const std::string& bytes) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

/// The whole content of a file ("" when it cannot be read).
inline std::string read_file(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Overwrites the little-endian u32 at `at` (.glb header and chunk fields).
inline void set_u32(std::string& bytes, std::size_t at, std::uint32_t v) {
    for (unsigned k = 0; k < 4; ++k) bytes[at + k] = char((v >> (8u * k)) & 0xFFu);
}

/// The little-endian u32 at `at`.
inline std::uint32_t get_u32(const std::string& bytes, std::size_t at) {
    std::uint32_t v = 0;
    for (unsigned k = 0; k < 4; ++k) v |= std::uint32_t(std::uint8_t(bytes[at + k])) << (8u * k);
    return v;
}

/// The JSON chunk of a .glb file, parsed (header 12 bytes, then the chunk's length at 12
/// and its data from 20, per the glTF 2.0 GLB layout).
inline nlohmann::json glb_json(const std::filesystem::path& p) {
    const std::string bytes = read_file(p);
    return nlohmann::json::parse(bytes.substr(20, get_u32(bytes, 12)));
}

/// A builder holding one triangle (positions only) in mesh 0, placed by node 0 of scene 0.
inline GltfBuilder one_triangle() {
    GltfBuilder b;
    const std::vector<float> p = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const int pos = b.add_accessor(p, kFloat, "VEC3", 3);
    b.doc["accessors"][pos]["min"] = {0, 0, 0};
    b.doc["accessors"][pos]["max"] = {1, 1, 0};
    b.doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", pos}}}}}}}};
    b.doc["nodes"] = {{{"mesh", 0}}};
    b.doc["scenes"] = {{{"nodes", {0}}}};
    b.doc["scene"] = 0;
    return b;
}

/// A w x h RGBA PNG of the given texels (row-major, 4 bytes each).
inline std::string rgba_png(int w, int h, const unsigned char* rgba) {
    std::string out;
    stbi_write_png_to_func(
        [](void* ctx, void* data, int size) {
            static_cast<std::string*>(ctx)->append(static_cast<const char*>(data),
                                                   std::size_t(size));
        },
        &out, w, h, 4, rgba, 4 * w);
    return out;
}

/// A 2 x 1 RGBA PNG: red, then half-transparent blue.
inline std::string tiny_png() {
    const unsigned char px[8] = {255, 0, 0, 255, 0, 0, 255, 128};
    return rgba_png(2, 1, px);
}

/// A w x h baseline JPEG of a colour gradient (quality 90): texture data that a truncated
/// copy of spoils.
inline std::string small_jpeg(int w, int h) {
    std::vector<unsigned char> px(std::size_t(w) * std::size_t(h) * 3);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            unsigned char* p = &px[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 3];
            p[0] = static_cast<unsigned char>(x * 255 / w);
            p[1] = static_cast<unsigned char>(y * 255 / h);
            p[2] = static_cast<unsigned char>((x ^ y) & 0xff);
        }
    }
    std::string out;
    stbi_write_jpg_to_func(
        [](void* ctx, void* data, int size) {
            static_cast<std::string*>(ctx)->append(static_cast<const char*>(data),
                                                   std::size_t(size));
        },
        &out, w, h, 3, px.data(), 90);
    return out;
}

}  // namespace librt::testing
