#include <librt/core/constants.h>
#include <librt/geometry/sphere.h>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

#include <cmath>

namespace librt {

std::optional<float> intersect(const Sphere& sphere, const Ray& ray) {
    const DoubleRay r(ray);
    if (!(r.a > 0.0)) return std::nullopt;  // zero or NaN direction
    const double t = intersect(DoubleSphere(sphere), r, ray.t_min, ray.t_max);
    if (std::isnan(t)) return std::nullopt;
    return static_cast<float>(t);
}

glm::vec3 normal_at(const Sphere& sphere, const glm::vec3& point) {
    return (point - sphere.center) / sphere.radius;
}

glm::vec2 sphere_uv(const Sphere& sphere, const glm::vec3& point) {
    const glm::vec3 n = glm::normalize(point - sphere.center);
    const float phi = std::atan2(n.z, n.x);  // azimuth around +y
    const float theta = std::acos(glm::clamp(n.y, -1.0f, 1.0f));
    return {(phi + kPi) / (2.0f * kPi), theta / kPi};
}

}  // namespace librt
