#include "light/light_bounds.h"
#include "light/light_validation.h"

#include <librt/core/finite.h>
#include <librt/light/point_light.h>

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

LightLeSample sample_le(const PointLight& light, glm::vec2 /*u_pos*/, glm::vec2 u_dir) {
    if (!finite(light.position)) return {};
    LightLeSample s;
    s.origin = light.position;
    // Isotropic: uniform over the sphere of directions, so I / pdf_dir = 4 pi I, the power.
    s.direction = sample_uniform_sphere(u_dir);
    s.radiance = light.intensity;
    s.pdf_pos = 1.0f;
    s.pdf_dir = uniform_sphere_pdf();
    s.delta_position = true;
    return s;
}

LightLePdf pdf_le(const PointLight& /*light*/, const glm::vec3& /*origin*/,
                  const glm::vec3& /*normal*/, const glm::vec3& /*direction*/) {
    return {1.0f, uniform_sphere_pdf()};
}

LightBounds PointLight::bounds() const {
    return detail::finite_light_bounds(position, 0.0f, power(*this));
}

}  // namespace librt
