#include <librt/geometry/sphere.h>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

#include <cmath>
#include <utility>

namespace librt {

std::optional<float> intersect(const Sphere& sphere, const Ray& ray) {
    const glm::dvec3 d(ray.direction);
    const glm::dvec3 oc = glm::dvec3(ray.origin) - glm::dvec3(sphere.center);
    const double r = sphere.radius;
    // Quadratic a t^2 + 2 b t + c = 0 in the ray parameter.
    const double a = glm::dot(d, d);
    if (!(a > 0.0)) return std::nullopt;  // zero or NaN direction
    const double b = glm::dot(oc, d);
    const double c = glm::dot(oc, oc) - r * r;
    // Discriminant via the closest point on the line (avoids b^2 - ac cancellation).
    const glm::dvec3 closest = oc - (b / a) * d;
    const double disc = a * (r * r - glm::dot(closest, closest));
    if (disc < 0.0) return std::nullopt;
    // Cancellation-free roots: q = -(b + sign(b) sqrt(disc)), t0 = q / a, t1 = c / q.
    const double q = -(b + std::copysign(std::sqrt(disc), b));
    double t0 = q / a;
    double t1 = (q != 0.0) ? c / q : t0;
    if (t0 > t1) std::swap(t0, t1);
    const double tmin = ray.t_min, tmax = ray.t_max;
    if (t0 > tmin && t0 < tmax) return static_cast<float>(t0);
    if (t1 > tmin && t1 < tmax) return static_cast<float>(t1);
    return std::nullopt;
}

glm::vec3 normal_at(const Sphere& sphere, const glm::vec3& point) {
    return (point - sphere.center) / sphere.radius;
}

glm::vec2 sphere_uv(const Sphere& sphere, const glm::vec3& point) {
    const glm::vec3 n = glm::normalize(point - sphere.center);
    const float phi = std::atan2(n.z, n.x);  // azimuth around +y
    const float theta = std::acos(glm::clamp(n.y, -1.0f, 1.0f));
    return {(phi + glm::pi<float>()) / glm::two_pi<float>(), theta / glm::pi<float>()};
}

}  // namespace librt
