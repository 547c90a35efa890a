#include "light/cos_minus.h"

#include <librt/light/light_bounds.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <variant>

namespace librt {
namespace {

using detail::cos_minus;

/// Mean over channels: what the power light sampler weighs by too.
float mean(const glm::vec3& v) { return (v.x + v.y + v.z) / 3.0f; }

/// The bounds' radius padded so that rounding in a light's own sample_li (its points and
/// directions are computed in float) can never put an emitting point outside the sphere:
/// a relative 1e-4 of the radius plus 1e-5 of the coordinates' magnitude.
float padded(const glm::vec3& centre, float radius) {
    const float magnitude =
        std::max({std::fabs(centre.x), std::fabs(centre.y), std::fabs(centre.z), radius});
    return radius * (1.0f + 1e-4f) + 1e-5f * magnitude;
}

LightBounds finite(const glm::vec3& centre, float radius, float phi) {
    LightBounds b;
    b.centre = centre;
    b.radius = padded(centre, radius);
    b.phi = phi;
    return b;
}

/// A planar emitter of normal `normal`: one-sided ones emit into its front hemisphere only,
/// with radiance times cos falling toward the plane.
void planar(LightBounds& b, const glm::vec3& normal, bool one_sided) {
    if (!one_sided) return;
    b.cone = true;
    b.axis = glm::normalize(normal);
    b.cos_cone = 0.0f;
    b.emitter_cosine = true;
}

LightBounds bounds_of(const PointLight& l, float phi) { return finite(l.position, 0.0f, phi); }

LightBounds bounds_of(const SphereLight& l, float phi) {
    return finite(l.sphere.center, l.sphere.radius, phi);
}

LightBounds bounds_of(const TriangleLight& l, float phi) {
    // Centroid and the farthest corner: not the smallest sphere, but it contains the triangle.
    const glm::vec3 c = (l.p0 + l.p1 + l.p2) / 3.0f;
    const float r = std::max({glm::length(l.p0 - c), glm::length(l.p1 - c), glm::length(l.p2 - c)});
    LightBounds b = finite(c, r, phi);
    const glm::vec3 n = glm::cross(l.p1 - l.p0, l.p2 - l.p0);
    // A degenerate triangle has no normal (and no power): no cone.
    planar(b, n, !l.two_sided && glm::dot(n, n) > 0.0f);
    return b;
}

LightBounds bounds_of(const QuadLight& l, float phi) {
    const glm::vec3 c = l.corner + 0.5f * (l.edge0 + l.edge1);
    // Half the longer diagonal reaches every corner from the centre.
    const float r = 0.5f * std::max(glm::length(l.edge0 + l.edge1), glm::length(l.edge0 - l.edge1));
    LightBounds b = finite(c, r, phi);
    planar(b, glm::cross(l.edge0, l.edge1), !l.two_sided);
    return b;
}

LightBounds bounds_of(const DiskLight& l, float phi) {
    LightBounds b = finite(l.center, l.radius, phi);
    planar(b, l.normal, !l.two_sided);
    return b;
}

LightBounds bounds_of(const SpotLight& l, float phi) {
    LightBounds b = finite(l.position, 0.0f, phi);
    b.cone = true;
    b.axis = glm::normalize(l.direction);
    // spot_falloff is 0 from the outer angle on; a 1e-4 slack keeps rounding conservative.
    b.cos_cone = std::cos(l.outer_angle) - 1e-4f;
    return b;
}

LightBounds bounds_of(const DirectionalLight& l, float phi) {
    LightBounds b;
    b.phi = phi;
    b.infinite = true;
    b.cone = true;
    b.axis = glm::normalize(l.to_light);
    // The cone of directions toward the sun's disk, widened by 1e-4 rad against rounding.
    b.cos_cone = std::cos(std::min(l.angular_radius + 1e-4f, 3.14159265f));
    return b;
}

LightBounds bounds_of(const EnvironmentLight& /*l*/, float phi) {
    LightBounds b;
    b.phi = phi;
    b.infinite = true;  // lights from every direction: never provably nothing
    return b;
}

}  // namespace

LightBounds light_bounds(const Light& light) {
    const float phi = std::max(0.0f, mean(power(light)));
    LightBounds b =
        std::visit([&](const auto& source) { return bounds_of(source, phi); }, light.source);
    if (!std::isfinite(b.phi)) b.phi = 0.0f;
    return b;
}

float importance(const LightBounds& b, const LightChoicePoint& at) {
    if (!(b.phi > 0.0f)) return 0.0f;
    if (b.infinite) {
        if (!b.cone || !at.reflect_only) return b.phi;
        // A sun: its directions lie within acos(cos_cone) of the axis.
        const float sin_cone = std::sqrt(std::max(0.0f, 1.0f - b.cos_cone * b.cos_cone));
        const float c = cos_minus(glm::dot(at.normal, b.axis), b.cos_cone, sin_cone);
        return c > 0.0f ? b.phi * c : 0.0f;
    }
    const glm::vec3 to_light = b.centre - at.point;
    const float d2 = glm::dot(to_light, to_light);
    const float r2 = b.radius * b.radius;
    if (b.cone && b.emitter_cosine) {
        // A planar one-sided emitter: behind its plane (which holds the centre) nothing, near
        // or far; a margin of 1e-5 of the distances keeps rounding on the safe side.
        const float side = -glm::dot(b.axis, to_light);
        if (side < -1e-5f * (std::sqrt(d2) + b.radius)) return 0.0f;
    }
    // Inside the bounding sphere no direction can be ruled out: the distance term alone,
    // with r^2 standing in for d^2 (a floor also keeps a point light at the point finite).
    if (!(d2 > r2)) return b.phi / std::max(r2, 1e-12f);
    const float d = std::sqrt(d2);
    const glm::vec3 w = to_light / d;
    // alpha: half the angle the bounding sphere subtends from the point.
    const float sin_a = b.radius / d;
    const float cos_a = std::sqrt(std::max(0.0f, 1.0f - sin_a * sin_a));
    float weight = b.phi / d2;
    if (at.reflect_only) {
        // The largest cosine any emitting point makes with the surface's normal.
        const float c = cos_minus(glm::dot(at.normal, w), cos_a, sin_a);
        if (!(c > 0.0f)) return 0.0f;
        weight *= c;
    }
    if (b.cone) {
        // The largest cosine between the emitter's axis and a direction from an emitting
        // point toward the shading point.
        const float c = cos_minus(-glm::dot(b.axis, w), cos_a, sin_a);
        if (!(c > b.cos_cone)) return 0.0f;
        if (b.emitter_cosine) weight *= c;
    }
    return weight;
}

}  // namespace librt
