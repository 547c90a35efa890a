#include "light/light_bounds.h"

#include "light/importance_bound.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <variant>

namespace librt {
namespace {

using detail::cos_minus;

/// Mean over channels, what the power light sampler weighs by too; 0 when negative or not
/// finite.
float phi_of(const glm::vec3& power) {
    const float phi = std::max(0.0f, (power.x + power.y + power.z) / 3.0f);
    return std::isfinite(phi) ? phi : 0.0f;
}

/// The bounds' radius padded so that rounding in a light's own sample_li (its points and
/// directions are computed in float) can never put an emitting point outside the sphere:
/// a relative 1e-4 of the radius plus 1e-5 of the coordinates' magnitude.
float padded(const glm::vec3& centre, float radius) {
    const float magnitude =
        std::max({std::fabs(centre.x), std::fabs(centre.y), std::fabs(centre.z), radius});
    return radius * (1.0f + 1e-4f) + 1e-5f * magnitude;
}

}  // namespace

namespace detail {

LightBounds finite_light_bounds(const glm::vec3& centre, float radius, const glm::vec3& power) {
    LightBounds b;
    b.centre = centre;
    b.radius = padded(centre, radius);
    b.phi = phi_of(power);
    return b;
}

LightBounds infinite_light_bounds(const glm::vec3& power) {
    LightBounds b;
    b.phi = phi_of(power);
    b.infinite = true;
    return b;
}

void bound_planar(LightBounds& b, const glm::vec3& normal, bool one_sided) {
    if (!one_sided) return;
    b.cone = true;
    b.axis = glm::normalize(normal);
    b.cos_cone = 0.0f;
    b.emitter_cosine = true;
}

}  // namespace detail

LightBounds light_bounds(const Light& light) {
    return std::visit([](const auto& source) { return source.bounds(); }, light.source);
}

// The hooks of detail::importance_bound for one light's bounds (importance_bound.h).

/// A planar one-sided emitter: behind its plane (which holds the centre) nothing, near or
/// far; a margin of 1e-5 of the distances keeps rounding on the safe side.
static bool ruled_out(const LightBounds& b, const LightChoicePoint& /*at*/,
                      const glm::vec3& to_light, float d2) {
    if (!(b.cone && b.emitter_cosine)) return false;
    const float side = -glm::dot(b.axis, to_light);
    return side < -1e-5f * (std::sqrt(d2) + b.radius);
}

/// The distance term alone, with r^2 standing in for d^2 (a floor also keeps a point light
/// at the point finite).
static float inside_weight(const LightBounds& b, float /*d2*/, float r2) {
    return b.phi / std::max(r2, 1e-12f);
}

/// The largest cosine between the emitter's axis and a direction from an emitting point
/// toward the shading point: outside the cone nothing, and a planar emitter's radiance
/// falls as that cosine.
static bool emitter_bound(const LightBounds& b, const glm::vec3& w, float cos_a, float sin_a,
                          float& weight) {
    if (!b.cone) return true;
    const float c = cos_minus(-glm::dot(b.axis, w), cos_a, sin_a);
    if (!(c > b.cos_cone)) return false;
    if (b.emitter_cosine) weight *= c;
    return true;
}

float importance(const LightBounds& b, const LightChoicePoint& at) {
    if (!b.infinite) return detail::importance_bound(b, at);
    if (!(b.phi > 0.0f)) return 0.0f;
    if (!b.cone || !at.reflect_only) return b.phi;
    // A sun: its directions lie within acos(cos_cone) of the axis.
    const float sin_cone = std::sqrt(std::max(0.0f, 1.0f - b.cos_cone * b.cos_cone));
    const float c = cos_minus(glm::dot(at.normal, b.axis), b.cos_cone, sin_cone);
    return c > 0.0f ? b.phi * c : 0.0f;
}

}  // namespace librt
