#pragma once

// Private: the cosine bound light_bounds.cpp and light_tree.cpp share.

#include <algorithm>
#include <cmath>

namespace librt::detail {

/// cos(max(0, theta - alpha)) from cos(theta) and alpha's cosine and sine: the largest
/// cosine between a direction and any direction within alpha of the one at theta (the
/// angle-difference identity cos(t - a) = cos t cos a + sin t sin a, no trigonometric call).
[[nodiscard]] inline float cos_minus(float cos_theta, float cos_alpha, float sin_alpha) {
    if (cos_theta >= cos_alpha) return 1.0f;
    const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
    return cos_theta * cos_alpha + sin_theta * sin_alpha;
}

}  // namespace librt::detail
