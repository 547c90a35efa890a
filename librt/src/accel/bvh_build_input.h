#pragma once

// Private: the input check both BVH builders run before any work.

#include <librt/geometry/bbox.h>

#include <glm/vec3.hpp>

#include <cmath>
#include <cstddef>
#include <span>

namespace librt::detail {

/// Throws librt::Error when boxes and centres differ in number, there are 2^32 - 1 or more,
/// a centre is not finite or a box has a NaN corner (it would poison every box above it).
void check_build_input(std::span<const BBox> boxes, std::span<const glm::vec3> centers);

/// The first half of check_build_input: the counts only (the SAH builder checks the
/// primitives in its own parallel pass over them).
void check_build_sizes(std::span<const BBox> boxes, std::span<const glm::vec3> centers);

/// Whether a primitive can be binned: a finite centre (bins are indexed from centroids,
/// a NaN would become an out-of-range bin) and no NaN corner.
[[nodiscard]] inline bool primitive_is_valid(const BBox& b, const glm::vec3& c) {
    return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) && !std::isnan(b.lo.x) &&
           !std::isnan(b.lo.y) && !std::isnan(b.lo.z) && !std::isnan(b.hi.x) &&
           !std::isnan(b.hi.y) && !std::isnan(b.hi.z);
}

/// Throws check_build_input's error for primitive i, whose centre is c.
[[noreturn]] void throw_bad_primitive(std::size_t i, const glm::vec3& c);

}  // namespace librt::detail
