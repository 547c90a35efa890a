#include <librt/render/image.h>

#include <librt/core/error.h>

#include <string>

namespace librt {

void check_image_size(long long width, long long height) {
    const std::string size = std::to_string(width) + " x " + std::to_string(height);
    if (width < 0 || height < 0) {
        throw Error("image size " + size + ": width and height must be >= 0");
    }
    // Checked in 64 bits before the multiplication can overflow: each side <= 2^31.
    const auto bytes = static_cast<unsigned long long>(width) *
                       static_cast<unsigned long long>(height) * sizeof(glm::vec3);
    if (bytes > Image::k_max_bytes) {
        throw Error("image size " + size + ": the film would need " + std::to_string(bytes) +
                    " bytes, more than the 4 GiB limit");
    }
}

Image::Image(int w, int h) : width(w), height(h) {
    check_image_size(w, h);
    pixels.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), glm::vec3(0.0f));
}

}  // namespace librt
