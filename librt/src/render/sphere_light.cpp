#include "light_validation.h"

#include <librt/core/error.h>
#include <librt/render/sphere_light.h>

#include <cmath>
#include <sstream>

namespace librt {
void validate(const SphereLight& light) {
    detail::require_finite("sphere light center", light.sphere.center);
    if (!std::isfinite(light.sphere.radius) || !(light.sphere.radius > 0.0f)) {
        std::ostringstream msg;
        msg << "sphere light radius = " << light.sphere.radius << ": must be finite and > 0";
        throw Error(msg.str());
    }
    detail::require_finite_non_negative("sphere light radiance", light.radiance);
}

float pdf_li(const SphereLight& light, const glm::vec3& ref, const glm::vec3& wi) {
    const float p = sphere_visible_pdf(light.sphere.center, light.sphere.radius, ref, wi);
    return std::isfinite(p) ? p : 0.0f;
}

glm::vec3 power(const SphereLight& light) {
    // Uniform emitter: power = L * pi (cosine-weighted hemisphere) * 4 pi r^2 (area), in
    // double so that a tiny radius does not underflow before the product is formed.
    const double r = light.sphere.radius;
    const double k = 4.0 * double(k_pi) * double(k_pi) * r * r;
    return glm::vec3(glm::dvec3(light.radiance) * k);
}

}  // namespace librt
