#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/render/point_light.h>

#include <glm/geometric.hpp>

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

void validate(const PointLight& light) {
    if (!finite(light.position)) fail("point light position", light.position, "must be finite");
    if (!finite(light.intensity) || light.intensity.x < 0.0f || light.intensity.y < 0.0f ||
        light.intensity.z < 0.0f)
        fail("point light intensity", light.intensity, "must be finite and >= 0");
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
