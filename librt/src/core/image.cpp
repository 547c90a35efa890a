#include <librt/core/error.h>
#include <librt/core/image.h>

#include <cstdio>
#include <string>

namespace librt {

void check_image_size(long long width, long long height) {
    const std::string size = std::to_string(width) + " x " + std::to_string(height);
    if (width < 0 || height < 0) {
        throw Error("image size " + size + ": width and height must be >= 0");
    }
    // Compared by division, so no product can wrap around (2^32 x 2^30 pixels of 12
    // bytes would wrap a 64-bit product to exactly 0).
    constexpr auto kMaxPixels = Image::kMaxBytes / sizeof(glm::vec3);
    const auto w = static_cast<unsigned long long>(width);
    const auto h = static_cast<unsigned long long>(height);
    if (w > 0 && h > kMaxPixels / w) {
        // For the message only: in double, which cannot overflow here.
        const double gib = double(w) * double(h) * double(sizeof(glm::vec3)) / double(1ull << 30u);
        char needs[64];
        std::snprintf(needs, sizeof needs, "%.4g GiB", gib);
        throw Error("image size " + size + ": the film would need " + needs +
                    ", more than the 4 GiB limit");
    }
}

Image::Image(int w, int h) : width(w), height(h) {
    check_image_size(w, h);
    pixels.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), glm::vec3(0.0f));
}

}  // namespace librt
