#include "light_validation.h"

#include <librt/render/point_light.h>

#include <glm/geometric.hpp>

#include <cmath>

namespace librt {
void validate(const PointLight& light) {
    detail::require_finite("point light position", light.position);
    detail::require_finite_non_negative("point light intensity", light.intensity);
}

LightLiSample sample_li(const PointLight& light, const glm::vec3& ref, glm::vec2 /*u*/) {
    const glm::vec3 to_light = light.position - ref;
    const float d2 = glm::dot(to_light, to_light);
    if (!(d2 > 0.0f) || !std::isfinite(d2)) return {};
    const float d = std::sqrt(d2);
    // Inverse-square law: a point of intensity I gives irradiance I cos(theta) / d^2.
    return {to_light / d, light.intensity / d2, 1.0f, d, true};
}

}  // namespace librt
