#pragma once

#include <librt/geometry/ray.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

namespace librt {

/// Relative part of the self-intersection offset: 2^-18, i.e. 32 to 64 float ulps of the
/// largest coordinate of the point.
inline constexpr float kRayOffsetRelative = 0x1p-18f;
/// Absolute floor of the self-intersection offset, for points near the origin.
inline constexpr float kRayOffsetAbsolute = 0x1p-20f;

/// Distance by which offset_ray_origin moves a point off its surface: an absolute floor
/// plus max(|p.x|, |p.y|, |p.z|) * 2^-18. A hit point computed in float lies within a few
/// ulps of its largest coordinate from the true surface (the ray parameter is rounded to
/// float, then o + t d rounds again), so 32+ ulps clears that error with a wide margin
/// while staying far below any feature of a sane scene: in the report's room (|p| ~ 100)
/// it is 4e-4, against the report's fixed 0.01; scaled by 1000 the scene gets 1000 times
/// the offset, which a fixed epsilon would not do. Geometry thinner than the offset (a
/// glass sheet of thickness ~1e-5 at that scale) can be stepped over.
[[nodiscard]] inline float ray_offset_scale(const glm::vec3& p) {
    const float m = std::max(std::max(std::fabs(p.x), std::fabs(p.y)), std::fabs(p.z));
    return kRayOffsetAbsolute + kRayOffsetRelative * m;
}

/// The origin of a ray leaving surface point `point` in `direction`: the point moved by
/// ray_offset_scale(point) along the unit geometric `normal`, to the side `direction`
/// goes (so a reflected ray starts above the surface and a refracted one below it).
/// Forced inline: g++ kept it out of line in the path loop (docs/benchmarks.md, "Code
/// shaped by measurement").
[[nodiscard, gnu::always_inline]] inline glm::vec3 offset_ray_origin(const glm::vec3& point,
                                                                     const glm::vec3& normal,
                                                                     const glm::vec3& direction) {
    const float offset = ray_offset_scale(point);
    return glm::dot(normal, direction) >= 0.0f ? point + offset * normal : point - offset * normal;
}

/// A ray leaving a surface point in a unit direction, its origin offset off the surface.
[[nodiscard]] inline Ray spawn_ray(const glm::vec3& point, const glm::vec3& normal,
                                   const glm::vec3& direction) {
    Ray r;
    r.origin = offset_ray_origin(point, normal, direction);
    r.direction = direction;
    return r;
}

}  // namespace librt
