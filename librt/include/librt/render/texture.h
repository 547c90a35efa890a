#pragma once

#include <librt/export.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace librt {

/// An RGB image used as a surface's albedo, stored as linear floats (io/texture_io.h
/// load_texture reads one from a file).
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
