#include <librt/core/error.h>
#include <librt/core/tone_map.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace librt {

void validate(const ToneMap& tone_map) {
    if (!(tone_map.exposure >= 0.0f) || !std::isfinite(tone_map.exposure)) {
        std::ostringstream msg;
        msg << "exposure = " << tone_map.exposure << ": must be finite and >= 0";
        throw Error(msg.str());
    }
    if (!(tone_map.gamma > 0.0f) || !std::isfinite(tone_map.gamma)) {
        std::ostringstream msg;
        msg << "gamma = " << tone_map.gamma << ": must be finite and > 0";
        throw Error(msg.str());
    }
}

std::uint8_t tone_map_channel(float radiance, const ToneMap& tone_map) {
    const float scaled = tone_map.exposure * radiance;
    if (std::isnan(scaled)) return 0;  // also catches 0 * inf
    // Display value: 255 * clamp(exposure * L, 0, 1)^gamma, rounded to nearest.
    const float v = 255.0f * std::pow(std::clamp(scaled, 0.0f, 1.0f), tone_map.gamma);
    return static_cast<std::uint8_t>(std::min(255.0f, v + 0.5f));
}

std::vector<std::uint8_t> to_rgb8(const Image& image, const ToneMap& tone_map) {
    validate(tone_map);
    std::vector<std::uint8_t> out;
    out.reserve(image.pixels.size() * 3);
    for (const glm::vec3& p : image.pixels) {
        out.push_back(tone_map_channel(p.r, tone_map));
        out.push_back(tone_map_channel(p.g, tone_map));
        out.push_back(tone_map_channel(p.b, tone_map));
    }
    return out;
}

}  // namespace librt
