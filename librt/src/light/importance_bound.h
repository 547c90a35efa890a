#pragma once

// Private: the importance bound of Conty Estevez & Kulla 2018 (eq. 3; pbrt-v4's
// LightBounds::Importance), written once for both bounds types that use it: one light's
// (LightBounds, light_bounds.h) and a light-tree node's (LightTreeBounds, light_tree.h).
// Each type supplies, as overloads found by the template, what differs: what rules a
// point out before any distance (a one-sided emitter's plane, a node's box), the weight
// inside its sphere, and its emitter's cone.

#include <librt/light/light_sampler.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

namespace librt::detail {

/// cos(max(0, theta - alpha)) from cos(theta) and alpha's cosine and sine: the largest
/// cosine between a direction and any direction within alpha of the one at theta (the
/// angle-difference identity cos(t - a) = cos t cos a + sin t sin a, no trigonometric call).
[[nodiscard]] inline float cos_minus(float cos_theta, float cos_alpha, float sin_alpha) {
    if (cos_theta >= cos_alpha) return 1.0f;
    const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
    return cos_theta * cos_alpha + sin_theta * sin_alpha;
}

/// A weight proportional to a conservative bound of what the lights within `b` (a sphere
/// of centre b.centre and radius b.radius holding their emitting points, total power
/// b.phi) give `at`: phi / d^2, times the largest cosine any emitting point makes with a
/// reflecting receiver's normal, times what the emitters' directions allow. 0 only when
/// the lights provably give `at` nothing. Bounds supplies, found by overloading:
///   ruled_out(b, at, to_light, d2): true when `at` provably gets nothing, whatever the
///     distance (to_light = b.centre - at.point, d2 its squared length);
///   inside_weight(b, d2, r2): the weight of a point inside the sphere (d2 <= r2), where
///     no direction can be ruled out;
///   emitter_bound(b, w, cos_a, sin_a, weight): false when no emitter's direction reaches
///     the point along unit -w (w from the point to the centre; the sphere subtends the
///     half angle a), else true, having scaled `weight` by the emitters' cosine bound.
template <class Bounds>
[[nodiscard]] inline float importance_bound(const Bounds& b, const LightChoicePoint& at) {
    if (!(b.phi > 0.0f)) return 0.0f;
    const glm::vec3 to_light = b.centre - at.point;
    const float d2 = glm::dot(to_light, to_light);
    const float r2 = b.radius * b.radius;
    if (ruled_out(b, at, to_light, d2)) return 0.0f;
    if (!(d2 > r2)) return inside_weight(b, d2, r2);
    const float d = std::sqrt(d2);
    const glm::vec3 w = to_light / d;
    // a: half the angle the bounding sphere subtends from the point.
    const float sin_a = b.radius / d;
    const float cos_a = std::sqrt(std::max(0.0f, 1.0f - sin_a * sin_a));
    float weight = b.phi / d2;
    if (at.reflect_only) {
        // The largest cosine any emitting point makes with the surface's normal.
        const float c = cos_minus(glm::dot(at.normal, w), cos_a, sin_a);
        if (!(c > 0.0f)) return 0.0f;
        weight *= c;
    }
    if (!emitter_bound(b, w, cos_a, sin_a, weight)) return 0.0f;
    return weight;
}

}  // namespace librt::detail
