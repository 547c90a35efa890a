#pragma once

// Private: the factor a light path (bdpt's light subpath, the caustic paths) multiplies
// the BSDF by, since librt's BSDFs are written for radiance and are symmetric.

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace librt {

/// Veach's correction (1997, section 5.3.2) of the adjoint BSDF for shading normals at a
/// point with shading normal ns and geometric normal ng:
/// |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|), wo toward the light's side, wi the way light
/// leaves. Radiance needs none.
[[nodiscard]] inline float shading_correction(const glm::vec3& ns, const glm::vec3& ng,
                                              const glm::vec3& wo, const glm::vec3& wi) {
    const float denom = std::fabs(glm::dot(wo, ng)) * std::fabs(glm::dot(wi, ns));
    if (!(denom > 0.0f)) return 0.0f;
    return std::fabs(glm::dot(wo, ns)) * std::fabs(glm::dot(wi, ng)) / denom;
}

}  // namespace librt
