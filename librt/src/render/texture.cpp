#include "io/file_io.h"

#include <librt/core/error.h>
#include <librt/render/texture.h>

#include <stb/stb_image.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <sstream>

namespace librt {
namespace {

// An image file read for a texture: 512 MiB, far above any 8192^2 texture's encoding
// (k_max_texels), and below stb's int-sized memory interface.
constexpr std::uint64_t kMaxTextureFileBytes = std::uint64_t{512} << 20;

// Position modulo n in [0, n) for any integer, negative ones included.
int wrap(int i, int n) {
    const int m = i % n;
    return m < 0 ? m + n : m;
}

}  // namespace

float srgb_to_linear(float c) {
    // sRGB decoding: linear segment near black, power 2.4 elsewhere.
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

ImageTexture::ImageTexture(int width, int height, std::vector<glm::vec3> linear_texels)
    : width_(width), height_(height), texels_(std::move(linear_texels)) {
    if (width <= 0 || height <= 0) {
        std::ostringstream msg;
        msg << "texture size " << width << " x " << height << ": must be positive";
        throw Error(msg.str());
    }
    if (texels_.size() != std::size_t(width) * std::size_t(height)) {
        std::ostringstream msg;
        msg << "texture of " << width << " x " << height << " given " << texels_.size()
            << " texels";
        throw Error(msg.str());
    }
}

ImageTexture ImageTexture::load(const std::filesystem::path& path) {
    int w = 0, h = 0, channels = 0;
    const std::string name = path.string();
    // Through the library's one reader (io/file_io.h): a regular file only (a FIFO would
    // block forever), at most kMaxTextureFileBytes; stb then decodes from memory.
    detail::ReadRequest request;
    request.what = "an image file";
    request.max_bytes = kMaxTextureFileBytes;
    std::string bytes;
    try {
        bytes = detail::read_regular_file(path, request);
    } catch (const Error& e) {
        throw Error(std::string("cannot load texture ") + e.what());
    }
    const auto* encoded = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int encoded_size = static_cast<int>(bytes.size());  // <= kMaxTextureFileBytes
    // The header first: refuse a huge image before stb allocates its pixels.
    if (stbi_info_from_memory(encoded, encoded_size, &w, &h, &channels) != 0) {
        if (std::uint64_t(w) * std::uint64_t(h) > k_max_texels) {
            std::ostringstream msg;
            msg << "cannot load texture " << name << ": " << w << " x " << h
                << " texels, more than the limit of " << k_max_texels;
            throw Error(msg.str());
        }
        // A header that claims far more texels than the file could encode is corrupt or
        // truncated: stb would allocate for it and then decode zeros (or, for binary
        // PNM, return uninitialised memory) at great length. No format compresses a
        // texel into less than 1/4096 byte (deflate peaks near 1/344 for RGB, a
        // constant-colour JPEG near 1/1000), so that is the bound; 64 Ki texels are
        // always allowed.
        const std::uint64_t file_bytes = bytes.size();
        const std::uint64_t texels = std::uint64_t(w) * std::uint64_t(h);
        if (texels > 4096u * file_bytes + 65536u) {
            std::ostringstream msg;
            msg << "cannot load texture " << name << ": the header claims " << w << " x " << h
                << " texels in a file of " << file_bytes << " bytes (corrupt or truncated)";
            throw Error(msg.str());
        }
        // stb's binary PNM reader does not check for a short read: a truncated P5/P6
        // file would come back as uninitialised memory. Its raster is w h c bytes (two
        // per sample at 16 bits) after the header, so a shorter file is truncated.
        if (bytes.size() >= 2 && bytes[0] == 'P' && (bytes[1] == '5' || bytes[1] == '6')) {
            const std::uint64_t raster =
                std::uint64_t(w) * std::uint64_t(h) * std::uint64_t(channels) *
                (stbi_is_16_bit_from_memory(encoded, encoded_size) ? 2u : 1u);
            if (file_bytes < raster) {
                std::ostringstream msg;
                msg << "cannot load texture " << name << ": truncated (" << file_bytes
                    << " bytes for a raster of " << raster << ")";
                throw Error(msg.str());
            }
        }
    }
    std::unique_ptr<stbi_uc, void (*)(void*)> data(
        stbi_load_from_memory(encoded, encoded_size, &w, &h, &channels, 3), stbi_image_free);
    if (!data) {
        const char* reason = stbi_failure_reason();
        throw Error("cannot load texture " + name + ": " + (reason ? reason : "unknown error"));
    }
    std::array<float, 256> to_linear{};
    for (int i = 0; i < 256; ++i) to_linear[std::size_t(i)] = srgb_to_linear(float(i) / 255.0f);
    std::vector<glm::vec3> texels(std::size_t(w) * std::size_t(h));
    const stbi_uc* p = data.get();
    for (std::size_t i = 0; i < texels.size(); ++i, p += 3)
        texels[i] = {to_linear[p[0]], to_linear[p[1]], to_linear[p[2]]};
    return ImageTexture(w, h, std::move(texels));
}

glm::vec3 ImageTexture::lookup(glm::vec2 uv) const {
    if (texels_.empty()) return glm::vec3(0.0f);
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return texels_.front();
    // Keep only the fractional part first, so huge coordinates do not overflow int.
    const float u = uv.x - std::floor(uv.x);
    const float v = uv.y - std::floor(uv.y);
    // Continuous texel coordinates, texel centres at integer + 0.5; v flipped (row 0 = top).
    const float x = u * float(width_) - 0.5f;
    const float y = (1.0f - v) * float(height_) - 0.5f;
    const float fx = std::floor(x), fy = std::floor(y);
    const float ax = x - fx, ay = y - fy;  // bilinear weights
    const int x0 = wrap(int(fx), width_), x1 = wrap(int(fx) + 1, width_);
    const int y0 = wrap(int(fy), height_), y1 = wrap(int(fy) + 1, height_);
    const glm::vec3 top = (1.0f - ax) * texel(x0, y0) + ax * texel(x1, y0);
    const glm::vec3 bottom = (1.0f - ax) * texel(x0, y1) + ax * texel(x1, y1);
    return (1.0f - ay) * top + ay * bottom;
}

}  // namespace librt
