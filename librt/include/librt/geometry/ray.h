#pragma once

#include <glm/vec3.hpp>

#include <limits>

namespace librt {

/// A ray segment: the points origin + t * direction for t in [t_min, t_max].
/// Traversal shrinks t_max to the nearest hit found so far.
struct Ray {
    glm::vec3 origin{0.0f};
    glm::vec3 direction{0.0f, 0.0f, -1.0f};  ///< need not be unit length; t is in its units
    float t_min = 0.0f;
    float t_max = std::numeric_limits<float>::infinity();

    /// The point at parameter t.
    [[nodiscard]] glm::vec3 at(float t) const { return origin + t * direction; }
};

}  // namespace librt
