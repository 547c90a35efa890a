#pragma once

#include <librt/export.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <vector>

namespace librt {

/// An RGB image used as a surface's albedo, stored as linear floats.
///
/// Lookups use OBJ texture coordinates: u runs left to right and v bottom to top (the
/// image's first row is v = 1), both wrapping around (repeat), with bilinear filtering
/// between the four nearest texel centres.
class LIBRT_API ImageTexture {
public:
    ImageTexture() = default;
    /// A texture from linear texels in row-major order, top row first; throws
    /// librt::Error if the size is not positive or texels.size() != width * height.
    ImageTexture(int width, int height, std::vector<glm::vec3> linear_texels);

    /// Most texels load() accepts: 2^26 (8192 x 8192, 768 MiB as floats).
    static constexpr std::uint64_t k_max_texels = std::uint64_t{1} << 26u;

    /// Loads a PNG, JPEG, BMP, TGA... with stb_image, converting its 8-bit sRGB values
    /// to linear (an alpha channel is dropped, grey is replicated). Throws librt::Error
    /// naming the path (and stb's reason) when the file is missing, a directory,
    /// unreadable, cannot be decoded, has more than k_max_texels texels (checked from
    /// the header, before decoding), claims more than 4096 texels per byte of file (no
    /// format compresses that well: corrupt or truncated), or is a binary PPM/PGM shorter
    /// than its raster (stb would return uninitialised memory as texels).
    [[nodiscard]] static ImageTexture load(const std::filesystem::path& path);

    /// Bilinearly filtered linear RGB at texture coordinates uv (repeat wrap, v up).
    /// A non-finite uv gives the texel at (0, 0) instead of NaN.
    [[nodiscard]] glm::vec3 lookup(glm::vec2 uv) const;

    /// The texel in column x, row y (row 0 at the top), without wrapping.
    [[nodiscard]] const glm::vec3& texel(int x, int y) const {
        return texels_[std::size_t(y) * std::size_t(width_) + std::size_t(x)];
    }
    [[nodiscard]] int width() const { return width_; }            ///< texels per row
    [[nodiscard]] int height() const { return height_; }          ///< number of rows
    [[nodiscard]] bool empty() const { return texels_.empty(); }  ///< true when default-made

private:
    int width_ = 0;
    int height_ = 0;
    std::vector<glm::vec3> texels_;
};

/// The sRGB transfer function inverted (IEC 61966-2-1): c / 12.92 below 0.04045, else
/// ((c + 0.055) / 1.055)^2.4, for c in [0, 1].
[[nodiscard]] LIBRT_API float srgb_to_linear(float c);

}  // namespace librt
