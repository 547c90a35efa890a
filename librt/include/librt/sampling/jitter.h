#pragma once

#include <librt/sampling/warp.h>

#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

// Sub-pixel and lens offsets for anti-aliasing and depth of field. Pure functions of a
// uniform sample u in [0,1)^2.

namespace librt {

/// Two independent standard normals from u by Box-Muller, the report's formula: with
/// (r1, r2) = u, (cos(2 pi r1), sin(2 pi r1)) * sqrt(-2 ln r2). r2 is clamped to the
/// smallest normal float (radius <= 13.2) and the radicand to >= 0, so u = 0 or u > 1
/// give finite values, never inf or NaN.
[[nodiscard]] inline glm::vec2 box_muller(glm::vec2 u) {
    const float r2 = std::max(u.y, std::numeric_limits<float>::min());
    const float radius = std::sqrt(std::max(0.0f, -2.0f * std::log(r2)));
    const float phi = 2.0f * kPi * u.x;
    return {std::cos(phi) * radius, std::sin(phi) * radius};
}

/// Gaussian offset in pixels from the pixel centre; the report uses sigma = 0.5 pixel.
[[nodiscard]] inline glm::vec2 gaussian_pixel_jitter(glm::vec2 u, float sigma = 0.5f) {
    return sigma * box_muller(u);
}

/// Gaussian offset on the lens, in the camera's x-y plane units; the report uses sigma = 1.
[[nodiscard]] inline glm::vec2 gaussian_lens_jitter(glm::vec2 u, float sigma) {
    return sigma * box_muller(u);
}

/// Uniform offset on a disk lens of the given radius (concentric map: area-uniform).
[[nodiscard]] inline glm::vec2 disk_lens_jitter(glm::vec2 u, float radius) {
    return radius * sample_uniform_disk_concentric(u);
}

}  // namespace librt
