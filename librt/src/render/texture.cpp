#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/render/texture.h>

#include <cmath>
#include <cstdint>
#include <sstream>

namespace librt {
namespace {

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

glm::vec3 ImageTexture::lookup(glm::vec2 uv) const {
    if (texels_.empty()) return glm::vec3(0.0f);
    if (!finite(uv)) return texels_.front();
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
