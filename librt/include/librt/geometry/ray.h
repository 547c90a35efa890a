#pragma once

#include <glm/vec3.hpp>

#include <limits>

namespace librt {

/// A ray segment: the points origin + t * direction for t in [t_min, t_max].
/// Traversal shrinks t_max to the nearest hit found so far.
struct Ray {
    glm::vec3 origin{0.0f};                  ///< the point at t = 0
    glm::vec3 direction{0.0f, 0.0f, -1.0f};  ///< need not be unit length; t is in its units
    /// Start of the segment. Hits count only for t in the open range (t_min, t_max); box
    /// tests use the closed [t_min, t_max], so they never drop a box a hit could lie in.
    float t_min = 0.0f;
    /// End of the segment (+inf: unbounded), exclusive for hits; see t_min.
    float t_max = std::numeric_limits<float>::infinity();

    /// The point at parameter t.
    [[nodiscard]] glm::vec3 at(float t) const { return origin + t * direction; }
};

}  // namespace librt
