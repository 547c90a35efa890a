#pragma once

#include <librt/geometry/ray.h>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace librt {

/// An axis-aligned bounding box. A default-constructed box is empty
/// (lo = +inf, hi = -inf) so that extending it with anything gives that thing.
struct BBox {
    glm::vec3 lo{std::numeric_limits<float>::infinity()};   ///< minimum corner; +inf if empty
    glm::vec3 hi{-std::numeric_limits<float>::infinity()};  ///< maximum corner; -inf if empty

    /// The empty box.
    BBox() = default;
    /// The box with corners lo_ (minimum) and hi_ (maximum), taken as given: lo_ > hi_
    /// on any axis makes an empty box.
    BBox(const glm::vec3& lo_, const glm::vec3& hi_) : lo(lo_), hi(hi_) {}

    /// Grows the box to contain a point.
    void extend(const glm::vec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    /// Grows the box to contain another box.
    void extend(const BBox& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    /// True when the box contains no point.
    [[nodiscard]] bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    /// Midpoint of the corners (meaningless for an empty box). Finite for any finite box:
    /// where lo + hi overflows (corners near +-3e38) the halves are added instead.
    [[nodiscard]] glm::vec3 center() const {
        const glm::vec3 c = 0.5f * (lo + hi);
        if (std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)) return c;
        return 0.5f * lo + 0.5f * hi;
    }
    /// hi - lo: the side lengths (negative components for an empty box).
    [[nodiscard]] glm::vec3 diagonal() const { return hi - lo; }
    /// Surface area, the SAH's measure of the chance a random ray hits the box; 0 if empty.
    [[nodiscard]] float surface_area() const {
        if (empty()) return 0.0f;
        const glm::vec3 d = diagonal();
        return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
    /// Index (0, 1, 2) of the longest side.
    [[nodiscard]] int largest_axis() const {
        const glm::vec3 d = diagonal();
        return (d.x >= d.y && d.x >= d.z) ? 0 : (d.y >= d.z ? 1 : 2);
    }
    /// True when p lies in the closed box (faces included); false for an empty box.
    [[nodiscard]] bool contains(const glm::vec3& p) const {
        return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z &&
               p.z <= hi.z;
    }
};

/// Componentwise 1/d for the slab test. A zero component becomes a huge finite
/// value of the same sign instead of inf, so (lo - o) * inv never computes 0 * inf = NaN
/// for a ray parallel to a slab; the slab then spans +-huge, i.e. all or nothing.
/// A zero component acts as an infinitesimal of its sign, so a ray lying in a box face
/// is inside one of the two boxes sharing that face, never outside both (the price: such
/// a ray lying in the hi face of a lone box, moving with +0 there, counts as outside).
[[nodiscard]] inline glm::vec3 safe_inverse(const glm::vec3& d) {
    constexpr float tiny = 1e-30f;
    auto inv = [](float x) { return 1.0f / (std::fabs(x) < tiny ? std::copysign(tiny, x) : x); };
    return {inv(d.x), inv(d.y), inv(d.z)};
}

/// Scale applied to a slab test's exit distance so that float rounding in (plane - o) * inv
/// never drops a box the ray really crosses: 1 + 2 gamma(3), gamma(n) = n eps / (1 - n eps)
/// the bound on n rounded operations (pbrt's conservative ray-box test). Without it a ray
/// that crosses a tiny box far from its origin can see exit < enter by an ulp.
inline constexpr float kSlabExitScale =
    1.0f + 2.0f * (3.0f * 0.5f * 1.1920929e-07f) / (1.0f - 3.0f * 0.5f * 1.1920929e-07f);

/// The parameter interval [t_enter, t_exit] in which a ray is inside a box,
/// clipped to the ray's [t_min, t_max]; empty when t_enter > t_exit.
struct SlabInterval {
    float t_enter;  ///< where the ray enters the box, at least the ray's t_min
    float t_exit;   ///< where it leaves it (widened by kSlabExitSlack), at most the ray's t_max
    /// True when the interval is not empty: the ray segment touches the box.
    [[nodiscard]] bool hit() const { return t_enter <= t_exit; }
};

/// Relative widening of a slab test's exit distance: 2 gamma(3), gamma(n) = n u / (1 - n u)
/// with u = 2^-24. Each slab distance (lo - o) * inv carries three roundings (the
/// subtraction, 1/d, the product), so computed entry and exit are each within gamma(3) of
/// the exact ones; widening the exit by twice that keeps every box the ray really touches
/// (pbrt's conservative slab test). Without it a ray through a box's face or edge could
/// compute entry a few ulps past exit and skip a triangle the watertight test would hit.
inline constexpr float kSlabExitSlack = 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);

/// Slab test (Kay-Kajiya): intersects the three slabs' parameter intervals, the exit
/// widened by kSlabExitSlack so rounding never loses a hit. inv_dir comes from
/// safe_inverse(ray.direction).
[[nodiscard]] inline SlabInterval intersect(const BBox& box, const glm::vec3& origin,
                                            const glm::vec3& inv_dir, float t_min, float t_max) {
    const glm::vec3 t0 = (box.lo - origin) * inv_dir;
    const glm::vec3 t1 = (box.hi - origin) * inv_dir;
    const glm::vec3 tnear = glm::min(t0, t1);
    const glm::vec3 tfar = glm::max(t0, t1);
    const float enter = std::max(std::max(tnear.x, tnear.y), std::max(tnear.z, t_min));
    float far = std::min(std::min(tfar.x, tfar.y), tfar.z);
    far += std::fabs(far) * kSlabExitSlack;
    const float exit = std::min(far, t_max);
    return {enter, exit};
}

/// Convenience overload for a whole ray.
[[nodiscard]] inline SlabInterval intersect(const BBox& box, const Ray& ray) {
    return intersect(box, ray.origin, safe_inverse(ray.direction), ray.t_min, ray.t_max);
}

}  // namespace librt
