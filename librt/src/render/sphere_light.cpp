#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/render/sphere_light.h>

#include <cmath>
#include <sstream>

namespace librt {
namespace {

[[noreturn]] void fail(const char* what, const glm::vec3& v, const char* rule) {
    std::ostringstream msg;
    msg << what << " = (" << v.x << ", " << v.y << ", " << v.z << "): " << rule;
    throw Error(msg.str());
}

}  // namespace

void validate(const SphereLight& light) {
    if (!finite(light.sphere.center))
        fail("sphere light center", light.sphere.center, "must be finite");
    if (!std::isfinite(light.sphere.radius) || !(light.sphere.radius > 0.0f)) {
        std::ostringstream msg;
        msg << "sphere light radius = " << light.sphere.radius << ": must be finite and > 0";
        throw Error(msg.str());
    }
    if (!finite(light.radiance) || light.radiance.x < 0.0f || light.radiance.y < 0.0f ||
        light.radiance.z < 0.0f)
        fail("sphere light radiance", light.radiance, "must be finite and >= 0");
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
