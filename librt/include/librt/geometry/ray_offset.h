#pragma once

#include <librt/geometry/hit.h>
#include <librt/geometry/ray.h>

#include <glm/common.hpp>
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

/// The self-intersection offset of a point whose only error is its own rounding: an
/// absolute floor plus max(|p.x|, |p.y|, |p.z|) * 2^-18, 32+ ulps of its largest
/// coordinate, clearing that rounding with a wide margin while staying far below any
/// feature of a sane scene: in the report's room (|p| ~ 100) it is 4e-4, against the
/// report's fixed 0.01; scaled by 1000 the scene gets 1000 times the offset, which a fixed
/// epsilon would not do. A hit's error can be larger (a long ray's rounding of t, a large
/// triangle's vertices): Hit::offset adds it (docs/robustness.md, "Rays leaving
/// surfaces"). Geometry thinner than the offset (a glass sheet of thickness ~1e-5 at that
/// scale) can be stepped over.
[[nodiscard]] inline float ray_offset_scale(const glm::vec3& p) {
    const float m = std::max(std::max(std::fabs(p.x), std::fabs(p.y)), std::fabs(p.z));
    return kRayOffsetAbsolute + kRayOffsetRelative * m;
}

/// The offset a barycentric point b0 p0 + b1 p1 + b2 p2 computed in float needs:
/// ray_offset_scale of |b0 p0| + |b1 p1| + |b2 p2| (componentwise). The sum bounds the
/// point's rounding (pbrt-v4 bounds it by gamma(7) times the same sum, Physically Based
/// Rendering 4th ed., section 6.8), and, more to the point, the rounding of the next ray's
/// intersection test with the triangle, which translates the vertices by the ray's origin: a
/// triangle 1e5 across whose plane passes near the world origin is found again ~1e-2 off it by a
/// ray leaving it there, far beyond ray_offset_scale of the point itself (issue 41). For a triangle
/// small next to its distance from the origin the sum is about |p| and this is
/// ray_offset_scale(p).
[[nodiscard]] inline float barycentric_offset(float b0, const glm::vec3& p0, float b1,
                                              const glm::vec3& p1, float b2, const glm::vec3& p2) {
    return ray_offset_scale(glm::abs(b0 * p0) + glm::abs(b1 * p1) + glm::abs(b2 * p2));
}

/// The origin of a ray leaving surface point `point` in `direction`: the point moved by
/// `offset` along the unit geometric `normal`, to the side `direction` goes (so a
/// reflected ray starts above the surface and a refracted one below it). The one function
/// every ray leaving a surface goes through; `offset` is the hit's Hit::offset, or
/// ray_offset_scale(point) for a point no intersection made. Forced inline: g++ kept it
/// out of line in the path loop (docs/benchmarks.md, "Code shaped by measurement").
[[nodiscard, gnu::always_inline]] inline glm::vec3 offset_ray_origin(const glm::vec3& point,
                                                                     const glm::vec3& normal,
                                                                     float offset,
                                                                     const glm::vec3& direction) {
    return glm::dot(normal, direction) >= 0.0f ? point + offset * normal : point - offset * normal;
}

/// offset_ray_origin with the offset ray_offset_scale(point): for a surface point no
/// intersection made (a point on a sphere, a light's sample). A triangle's hit needs its
/// own Hit::offset.
[[nodiscard, gnu::always_inline]] inline glm::vec3 offset_ray_origin(const glm::vec3& point,
                                                                     const glm::vec3& normal,
                                                                     const glm::vec3& direction) {
    return offset_ray_origin(point, normal, ray_offset_scale(point), direction);
}

/// A ray leaving a hit in a unit direction, its origin offset off the surface by the hit's
/// own error bound (Hit::offset).
[[nodiscard]] inline Ray spawn_ray(const Hit& hit, const glm::vec3& direction) {
    Ray r;
    r.origin = offset_ray_origin(hit.point, hit.geometric_normal, hit.offset, direction);
    r.direction = direction;
    return r;
}

/// A ray leaving a surface point in a unit direction, its origin offset off the surface by
/// ray_offset_scale(point): for points no intersection made; a hit's ray is
/// spawn_ray(hit, direction).
[[nodiscard]] inline Ray spawn_ray(const glm::vec3& point, const glm::vec3& normal,
                                   const glm::vec3& direction) {
    Ray r;
    r.origin = offset_ray_origin(point, normal, direction);
    r.direction = direction;
    return r;
}

}  // namespace librt
