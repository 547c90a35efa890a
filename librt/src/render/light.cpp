#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/render/light.h>

#include <cmath>
#include <sstream>

namespace librt {
namespace {

bool non_negative(const glm::vec3& v) { return v.x >= 0.0f && v.y >= 0.0f && v.z >= 0.0f; }

[[noreturn]] void fail(const char* what, const glm::vec3& v, const char* rule) {
    std::ostringstream msg;
    msg << what << " = (" << v.x << ", " << v.y << ", " << v.z << "): " << rule;
    throw Error(msg.str());
}

}  // namespace

void validate(const PointLight& light) {
    if (!finite(light.position)) fail("point light position", light.position, "must be finite");
    if (!finite(light.intensity) || !non_negative(light.intensity))
        fail("point light intensity", light.intensity, "must be finite and >= 0");
}

void validate(const SphereLight& light) {
    if (!finite(light.sphere.center))
        fail("sphere light center", light.sphere.center, "must be finite");
    if (!std::isfinite(light.sphere.radius) || !(light.sphere.radius > 0.0f)) {
        std::ostringstream msg;
        msg << "sphere light radius = " << light.sphere.radius << ": must be finite and > 0";
        throw Error(msg.str());
    }
    if (!finite(light.radiance) || !non_negative(light.radiance))
        fail("sphere light radiance", light.radiance, "must be finite and >= 0");
}

}  // namespace librt
