#pragma once

#include <librt/export.h>
#include <librt/geometry/bbox.h>
#include <librt/geometry/ray.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <optional>

namespace librt {

/// A sphere; the report's walls are spheres too (radius ~1000).
struct Sphere {
    glm::vec3 center{0.0f};  ///< centre, in world space
    float radius = 1.0f;     ///< radius, > 0
};

/// Nearest t in (ray.t_min, ray.t_max) where the ray meets the sphere, or nothing.
/// Both roots are considered, so a ray starting inside hits the far side.
/// Solved in double with the cancellation-free quadratic: the report's walls are
/// huge, and float loses the root's digits there.
[[nodiscard]] LIBRT_API std::optional<float> intersect(const Sphere& sphere, const Ray& ray);

/// Bounding box of a sphere.
[[nodiscard]] inline BBox bounds(const Sphere& s) {
    return {s.center - glm::vec3(s.radius), s.center + glm::vec3(s.radius)};
}

/// Outward unit normal at a point on the sphere.
[[nodiscard]] LIBRT_API glm::vec3 normal_at(const Sphere& sphere, const glm::vec3& point);

/// Spherical (u, v) in [0,1]^2 of a point on the sphere: u = azimuth around +y, v = polar from +y.
[[nodiscard]] LIBRT_API glm::vec2 sphere_uv(const Sphere& sphere, const glm::vec3& point);

}  // namespace librt
