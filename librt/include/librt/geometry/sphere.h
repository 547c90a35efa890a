#pragma once

#include <librt/export.h>
#include <librt/geometry/bbox.h>
#include <librt/geometry/ray.h>

#include <glm/ext/vector_double3.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
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

/// A ray in double precision, prepared once per query for many sphere tests.
struct DoubleRay {
    glm::dvec3 origin;     ///< the ray's origin
    glm::dvec3 direction;  ///< the ray's direction, not normalised (t keeps its units)
    double a;              ///< |direction|^2
    double inv_a;          ///< 1 / |direction|^2

    /// Converts the ray's origin and direction to double.
    explicit DoubleRay(const Ray& r)
        : origin(r.origin),
          direction(r.direction),
          a(glm::dot(direction, direction)),
          inv_a(1.0 / a) {}
};

/// A sphere's centre and squared radius in double, prepared once for intersect(DoubleSphere...).
struct DoubleSphere {
    glm::dvec3 center;  ///< the centre
    double radius2;     ///< the squared radius

    /// Converts the sphere to double.
    explicit DoubleSphere(const Sphere& s)
        : center(s.center), radius2(double(s.radius) * double(s.radius)) {}
    /// A sphere given in double: no float rounding of its inputs (smallpt's walls of
    /// radius 1e5, whose centres float would move by up to 0.004).
    DoubleSphere(const glm::dvec3& c, double radius) : center(c), radius2(radius * radius) {}
};

/// Bounding box of a sphere given in double, rounded outward to float so that it holds
/// the exact sphere.
[[nodiscard]] inline BBox bounds(const glm::dvec3& center, double radius) {
    const auto down = [](double v) {
        const auto f = static_cast<float>(v);
        return double(f) <= v ? f : std::nextafter(f, -std::numeric_limits<float>::infinity());
    };
    const auto up = [](double v) {
        const auto f = static_cast<float>(v);
        return double(f) >= v ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
    };
    return {{down(center.x - radius), down(center.y - radius), down(center.z - radius)},
            {up(center.x + radius), up(center.y + radius), up(center.z + radius)}};
}

/// Nearest root in (t_min, t_max) of the ray-sphere quadratic, in double, or NaN for none;
/// what the scene's top level runs per sphere.
/// The quadratic is a t^2 + 2 b t + c = 0 with a = |d|^2, b = oc . d, c = |oc|^2 - r^2. Its
/// discriminant / a is r^2 - |oc - (b/a) d|^2, the squared half-chord, free of the
/// cancellation of b^2 - a c; the roots are q / a and c / q with
/// q = -(b + sign(b) sqrt(disc)), without cancellation either (Press et al., Numerical
/// Recipes, 5.6). A zero or NaN direction gives no hit through the NaN comparisons.
[[nodiscard]] inline double intersect(const DoubleSphere& sphere, const DoubleRay& ray,
                                      double t_min, double t_max) {
    constexpr double kNoRoot = std::numeric_limits<double>::quiet_NaN();
    const glm::dvec3 oc = ray.origin - sphere.center;
    const double b = glm::dot(oc, ray.direction);
    const double c = glm::dot(oc, oc) - sphere.radius2;
    // Outside (c > 0) and moving away (b >= 0): both roots are <= 0 (their product c / a
    // is positive, their sum -2 b / a is not), so no hit. Every ray leaving a sphere's
    // outer surface ends here, without the square root: in the report's room that is each
    // ray from a wall, which starts inside its wall's bounding box.
    if (b >= 0.0 && c > 0.0) return kNoRoot;
    const glm::dvec3 closest = oc - (b * ray.inv_a) * ray.direction;
    const double half_chord2 = sphere.radius2 - glm::dot(closest, closest);
    if (!(half_chord2 >= 0.0)) return kNoRoot;  // misses (or NaN)
    const double q = -(b + std::copysign(std::sqrt(half_chord2 * ray.a), b));
    const double t_a = q * ray.inv_a;
    const double t_b = q != 0.0 ? c / q : t_a;
    const double near = std::min(t_a, t_b), far = std::max(t_a, t_b);
    if (near > t_min && near < t_max) return near;
    if (far > t_min && far < t_max) return far;
    return kNoRoot;
}

/// Bounding box of a sphere.
[[nodiscard]] inline BBox bounds(const Sphere& s) {
    return {s.center - glm::vec3(s.radius), s.center + glm::vec3(s.radius)};
}

/// Outward unit normal at a point on the sphere.
[[nodiscard]] LIBRT_API glm::vec3 normal_at(const Sphere& sphere, const glm::vec3& point);

/// Spherical (u, v) in [0,1]^2 of a point on the sphere: u = azimuth around +y, v = polar from +y.
[[nodiscard]] LIBRT_API glm::vec2 sphere_uv(const Sphere& sphere, const glm::vec3& point);

}  // namespace librt
