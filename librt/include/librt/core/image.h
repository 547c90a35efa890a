#pragma once

#include <librt/export.h>

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace librt {

/// A film of linear RGB radiance, row-major with the top row first (pixel (x, y) =
/// column x, row y, as the camera numbers them).
struct LIBRT_API Image {
    int width = 0;                  ///< pixels per row
    int height = 0;                 ///< number of rows
    std::vector<glm::vec3> pixels;  ///< width * height values, top row first

    /// An empty 0x0 image.
    Image() = default;
    /// A black width x height image. Throws librt::Error naming the size when a side
    /// is negative or the film would exceed kMaxBytes, before allocating anything.
    Image(int width, int height);

    /// Largest film Image(w, h) allocates: 4 GiB of pixels.
    static constexpr std::uint64_t kMaxBytes = std::uint64_t{4} << 30u;

    /// Pixel (x, y): column x, row y from the top. Unchecked.
    [[nodiscard]] glm::vec3& at(int x, int y) {
        return pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                      static_cast<std::size_t>(x)];
    }
    /// Pixel (x, y): column x, row y from the top. Unchecked.
    [[nodiscard]] const glm::vec3& at(int x, int y) const {
        return pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                      static_cast<std::size_t>(x)];
    }
};

/// Throws librt::Error naming the size when a width x height film is invalid (negative
/// side) or larger than Image::kMaxBytes (for any sides, no overflow); does nothing
/// otherwise.
LIBRT_API void check_image_size(long long width, long long height);

}  // namespace librt
