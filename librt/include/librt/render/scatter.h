#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

// The specular scattering formulas shared by the integrators (and tested on their own).
// Directions are unit vectors; `d` always travels toward the surface.

namespace librt {

/// Mirror reflection about a unit normal (either orientation): d - 2 (d . n) n.
[[nodiscard]] inline glm::vec3 reflect(const glm::vec3& d, const glm::vec3& n) {
    return d - 2.0f * glm::dot(d, n) * n;
}

/// Schlick's Fresnel approximation for unpolarised light between indices n1 and n2:
/// R0 + (1 - R0) (1 - cos)^5 with R0 = ((n1 - n2) / (n1 + n2))^2, where cos is the cosine
/// of the angle on the side of the smaller index.
[[nodiscard]] inline float schlick_fresnel(float cos_theta, float n1, float n2) {
    const float r = (n1 - n2) / (n1 + n2);
    const float r0 = r * r;
    const float m = 1.0f - std::clamp(cos_theta, 0.0f, 1.0f);
    const float m2 = m * m;
    return r0 + (1.0f - r0) * (m2 * m2 * m);
}

/// What a smooth dielectric boundary did to a ray.
struct DielectricScatter {
    glm::vec3 direction{0.0f};               ///< unit outgoing direction
    bool transmitted = false;                ///< true: refracted through; false: reflected
    bool total_internal_reflection = false;  ///< reflected because no refraction exists
};

/// Scatters the unit direction d at a smooth boundary between the outside (index 1) and a
/// dielectric of index `ior`. `outward_normal` is the unit geometric normal pointing to the
/// outside; d . outward_normal < 0 means the ray enters. Snell's law gives the refracted
/// direction; when sin(theta_t) >= 1 the ray is totally reflected. Otherwise, with
/// `fresnel`, it reflects with probability F (Schlick) decided by u in [0, 1), else it
/// refracts; without `fresnel` it always refracts (the report's behaviour). Since the
/// choice is made with probability F and the reflected weight is F, the path weight is
/// unchanged either way.
[[nodiscard]] inline DielectricScatter scatter_dielectric(const glm::vec3& d,
                                                          const glm::vec3& outward_normal,
                                                          float ior, bool fresnel, float u) {
    const bool entering = glm::dot(d, outward_normal) < 0.0f;
    const glm::vec3 n = entering ? outward_normal : -outward_normal;  // faces the ray's side
    const float n1 = entering ? 1.0f : ior;
    const float n2 = entering ? ior : 1.0f;
    const float eta = n1 / n2;
    const float cos_i = std::clamp(-glm::dot(d, n), 0.0f, 1.0f);
    // Snell: sin(theta_t) = eta sin(theta_i), so sin^2(theta_t) = eta^2 (1 - cos^2(theta_i)).
    const float sin2_t = eta * eta * std::max(0.0f, 1.0f - cos_i * cos_i);
    if (sin2_t >= 1.0f) return {reflect(d, n), false, true};
    const float cos_t = std::sqrt(1.0f - sin2_t);
    if (fresnel) {
        const float f = schlick_fresnel(n1 <= n2 ? cos_i : cos_t, n1, n2);
        if (u < f) return {reflect(d, n), false, false};
    }
    // Refraction: t = eta d + (eta cos_i - cos_t) n, unit by construction (renormalised
    // against rounding).
    const glm::vec3 t = eta * d + (eta * cos_i - cos_t) * n;
    return {glm::normalize(t), true, false};
}

}  // namespace librt
