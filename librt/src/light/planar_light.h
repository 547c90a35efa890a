#pragma once

// What the planar area lights (triangle, quad, disk) share: turning a point sampled
// uniformly on an area into a direction with its solid-angle density, and the inverse
// (where a direction meets the plane).

#include <librt/light/light_sample.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <limits>

namespace librt::planar {

/// The sample toward point p on a flat emitter of unit normal n and area `area`: pdf per
/// solid angle d^2 / (A |cos theta_light|) (area measure converted to solid angle, pbrt
/// 4th ed. eq. 4.12); invalid when ref lies in the plane, or behind it when one-sided.
inline LightLiSample toward(const glm::vec3& ref, const glm::vec3& p, const glm::vec3& n,
                            float area, const glm::vec3& radiance, bool two_sided) {
    const glm::vec3 d = p - ref;
    const float d2 = glm::dot(d, d);
    if (!(d2 > 0.0f) || !(area > 0.0f)) return {};
    const float dist = std::sqrt(d2);
    const glm::vec3 wi = d / dist;
    const float cos_l = -glm::dot(n, wi);  // > 0 when ref is in front
    if (!two_sided && !(cos_l > 0.0f)) return {};
    const float c = std::fabs(cos_l);
    if (!(c > 0.0f)) return {};
    const float pdf = d2 / (area * c);
    if (!(pdf < std::numeric_limits<float>::infinity())) return {};
    return {wi, radiance, pdf, dist, false};
}

/// Where the ray ref + t wi (t > 0) meets the plane through `origin` of unit normal n:
/// t and the point, or t <= 0 when it does not (parallel, behind, or one-sided and seen
/// from the back).
struct PlaneHit {
    float t = 0.0f;
    glm::vec3 point{0.0f};
    float cos_l = 0.0f;  ///< |cos| at the emitter
};
inline PlaneHit hit_plane(const glm::vec3& origin, const glm::vec3& n, const glm::vec3& ref,
                          const glm::vec3& wi, bool two_sided) {
    const float dn = glm::dot(wi, n);
    if (!(std::fabs(dn) > 0.0f) || (!two_sided && dn >= 0.0f)) return {};
    const float t = glm::dot(origin - ref, n) / dn;
    if (!(t > 0.0f) || !std::isfinite(t)) return {};
    return {t, ref + t * wi, std::fabs(dn)};
}

/// The solid-angle density of a uniform-area sample that the plane hit h lies on.
inline float pdf_of(const PlaneHit& h, float area) {
    const float pdf = h.t * h.t / (area * h.cos_l);
    return std::isfinite(pdf) ? pdf : 0.0f;
}

}  // namespace librt::planar
