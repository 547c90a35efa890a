#pragma once

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

// What the path tracer and the bidirectional tracer share to weigh their strategies.
// Private to the library.

namespace librt {

/// The largest channel: the throughput tests ("can this path still add anything?").
[[nodiscard]] inline float max_component(const glm::vec3& v) {
    return std::max(std::max(v.x, v.y), v.z);
}

/// The power heuristic with exponent 2 (Veach 1997, eq. 9.13, one sample per strategy):
/// the weight a^2 / (a^2 + b^2) of the strategy of density a against the one of density b,
/// written as 1 / (1 + (b/a)^2) so that huge densities (tiny lights) do not overflow.
[[nodiscard]] inline float power_heuristic(float a, float b) {
    if (!(a > 0.0f)) return 0.0f;
    if (std::isinf(a)) return std::isinf(b) ? 0.5f : 1.0f;
    const float r = b / a;
    return 1.0f / (1.0f + r * r);
}

}  // namespace librt
