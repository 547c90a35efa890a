#pragma once

// Private: the input check both BVH builders run before any work.

#include <librt/geometry/bbox.h>

#include <glm/vec3.hpp>

#include <span>

namespace librt::detail {

/// Throws librt::Error when boxes and centres differ in number, there are 2^32 - 1 or more,
/// a centre is not finite or a box has a NaN corner (it would poison every box above it).
void check_build_input(std::span<const BBox> boxes, std::span<const glm::vec3> centers);

}  // namespace librt::detail
