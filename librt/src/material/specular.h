#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

// Smooth-surface optics shared by the BSDFs: the mirror and smooth glass, and the rough
// kinds (conductor, rough glass, glTF metallic-roughness), which reflect and refract about a
// sampled microfacet normal and at roughness 0 are their smooth limits. Directions are unit
// vectors in any orthonormal coordinates.

namespace librt {

/// Mirror reflection of a direction d about a unit normal (either orientation):
/// d - 2 (d . n) n.
[[nodiscard]] inline glm::vec3 reflect(const glm::vec3& d, const glm::vec3& n) {
    return d - 2.0f * glm::dot(d, n) * n;
}

/// Schlick's Fresnel approximation for unpolarised light between indices n1 and n2:
/// R0 + (1 - R0) (1 - cos)^5 with R0 = ((n1 - n2) / (n1 + n2))^2, where cos is the cosine
/// of the angle on the side of the smaller index (Schlick 1994).
[[nodiscard]] inline float schlick_fresnel(float cos_theta, float n1, float n2) {
    const float r = (n1 - n2) / (n1 + n2);
    const float r0 = r * r;
    const float m = 1.0f - std::clamp(cos_theta, 0.0f, 1.0f);
    const float m2 = m * m;
    return r0 + (1.0f - r0) * (m2 * m2 * m);
}

/// Cosine of the refracted angle by Snell's law for a ray meeting a boundary at cosine
/// cos_i with relative index eta = n1 / n2: sqrt(1 - eta^2 (1 - cos_i^2)); a negative
/// value means total internal reflection (no refracted ray exists).
[[nodiscard]] inline float refracted_cos(float cos_i, float eta) {
    // Snell: sin(theta_t) = eta sin(theta_i), so sin^2(theta_t) = eta^2 (1 - cos^2(theta_i)).
    const float sin2_t = eta * eta * std::max(0.0f, 1.0f - cos_i * cos_i);
    return sin2_t >= 1.0f ? -1.0f : std::sqrt(1.0f - sin2_t);
}

/// The refracted direction of d (travelling toward the surface) through a boundary with
/// unit normal n facing d's side, relative index eta = n1 / n2, cos_i = -d . n and cos_t
/// from refracted_cos (>= 0): t = eta d + (eta cos_i - cos_t) n, unit by construction
/// (renormalised against rounding).
[[nodiscard]] inline glm::vec3 refract(const glm::vec3& d, const glm::vec3& n, float eta,
                                       float cos_i, float cos_t) {
    return glm::normalize(eta * d + (eta * cos_i - cos_t) * n);
}

}  // namespace librt
