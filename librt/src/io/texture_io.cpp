#include "io/file_io.h"
#include "io/image_decode_failure.h"
#include "io/png_check.h"

#include <librt/core/error.h>
#include <librt/io/texture_io.h>

#include <stb/stb_image.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <sstream>
#include <string>
#include <vector>

namespace librt {

namespace {

// An image file read for a texture: 512 MiB, far above any 8192^2 texture's encoding
// (kMaxTextureTexels), and below stb's int-sized memory interface.
constexpr std::uint64_t kMaxTextureFileBytes = std::uint64_t{512} << 20;

}  // namespace

ImageTexture load_texture(const std::filesystem::path& path, FileDigest* digest) {
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
    if (digest != nullptr) *digest = digest_of(bytes);
    const auto* encoded = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int encoded_size = static_cast<int>(bytes.size());  // <= kMaxTextureFileBytes
    // The header first: refuse a huge image before stb allocates its pixels.
    if (stbi_info_from_memory(encoded, encoded_size, &w, &h, &channels) != 0) {
        if (std::uint64_t(w) * std::uint64_t(h) > kMaxTextureTexels) {
            std::ostringstream msg;
            msg << "cannot load texture " << name << ": " << w << " x " << h
                << " texels, more than the limit of " << kMaxTextureTexels;
            throw Error(msg.str());
        }
        // A header that claims far more texels than the file could encode is corrupt or
        // truncated: stb would allocate for it and then decode zeros (JPEG, TGA, ...; for
        // binary PNM, uninitialised memory) at great length. Those formats hold no more
        // than 4096 texels per byte (a constant-colour JPEG about 1000), so that is the
        // bound; 64 Ki texels are always allowed. Not for PNG: stb inflates its data to
        // the size the header gives and fails when the zlib stream ends short, and a
        // valid PNG can hold far more (an 8192^2 1-bit image deflates to 8 KB), so the
        // texel limit above is its only bound.
        const std::uint64_t file_bytes = bytes.size();
        const std::uint64_t texels = std::uint64_t(w) * std::uint64_t(h);
        const bool png = bytes.size() >= 8 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0;
        if (!png && texels > 4096u * file_bytes + 65536u) {
            std::ostringstream msg;
            msg << "cannot load texture " << name << ": the header claims " << w << " x " << h
                << " texels in a file of " << file_bytes << " bytes (corrupt or truncated)";
            throw Error(msg.str());
        }
        if (png) {
            if (const auto check = detail::check_png_data(bytes); !check.problem.empty())
                throw Error("cannot load texture " + name + ": " + check.problem);
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
        stbi_load_from_memory(encoded, encoded_size, &w, &h, &channels, 4), stbi_image_free);
    if (!data)
        throw Error("cannot load texture " + name + ": " + detail::image_decode_failure(bytes));
    // Kept as 8 bits (ImageTexture::from_rgba8), sRGB-decoded at lookup. The file's alpha is
    // not a map_Kd's: every texel made opaque.
    const std::size_t bytes_of_texels = std::size_t(w) * std::size_t(h) * 4;
    stbi_uc* p = data.get();
    for (std::size_t i = 3; i < bytes_of_texels; i += 4) p[i] = 255;
    return ImageTexture::from_rgba8(w, h, std::span<const std::uint8_t>(p, bytes_of_texels),
                                    ColorSpace::Srgb);
}

}  // namespace librt
