#pragma once

#include <librt/geometry/ray.h>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

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

/// The one widening of the conservative slab test: 2 gamma(3), gamma(n) = n u / (1 - n u)
/// with u = 2^-24 (pbrt-v3 section 3.9.2, "conservative ray-bounds intersections"). Each
/// slab distance (plane - o) * inv carries three roundings (the subtraction, 1/d, the
/// product), so computed entry and exit are each within gamma(3) of the exact ones;
/// scaling the exit by 1 + 2 gamma(3) keeps every box the ray really touches. Without it a
/// ray through a box's face or edge far from its origin could compute entry an ulp past
/// exit and skip a triangle the watertight test would hit. Every box test of librt (binary
/// BVH, wide kernels, the scene's top level) widens by this constant through slab_test.
inline constexpr float kSlabExitSlack = 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);

/// The slab test (Kay and Kajiya 1986) of one box or of a SIMD vector of boxes: the one
/// implementation behind every box test of librt. V is float, or a GCC/Clang vector of
/// floats (__m128, __m256) holding one box per lane, so the wide kernels run this very
/// arithmetic lane by lane. For axis a, near[a] and far[a] are the planes the ray enters
/// and leaves through (lo and hi when inv[a] is positive, swapped when it is negative;
/// SlabRay picks them), origin[a] and inv[a] the ray's origin and safe_inverse direction.
/// Writes the entry distance, max(near distances, t_min), and the exit distance,
/// min(far distances, t_max); the box is hit when enter <= exit. With Robust, the exit is
/// widened by 1 + kSlabExitSlack first. That bound holds for an exit >= 0, i.e. for every
/// box a ray with t_min >= 0 can hit; an exit behind the origin is scaled the other way,
/// which only a ray with a negative t_min could notice. min and max are written as
/// `a < b ? a : b` (the semantics of SSE's minps: the second operand when one is NaN).
template <bool Robust = true, class V>
inline void slab_test(const V (&near)[3], const V (&far)[3], const V (&origin)[3],
                      const V (&inv)[3], const V& t_min, const V& t_max, V& enter, V& exit) {
    // Distances to the planes: t = (plane - o) / d = (plane - o) * inv.
    const V n0 = (near[0] - origin[0]) * inv[0], f0 = (far[0] - origin[0]) * inv[0];
    const V n1 = (near[1] - origin[1]) * inv[1], f1 = (far[1] - origin[1]) * inv[1];
    const V n2 = (near[2] - origin[2]) * inv[2], f2 = (far[2] - origin[2]) * inv[2];
    if constexpr (std::is_same_v<V, float>) {
        // std::max(b, a) is `a > b ? a : b`, std::min(b, a) is `a < b ? a : b`: the same
        // values as the vector form (ties and -0 included), which GCC keeps in registers
        // better here.
        enter = std::max(std::max(t_min, n2), std::max(n1, n0));
        float f = std::min(f2, std::min(f1, f0));
        if constexpr (Robust) f = f * (1.0f + kSlabExitSlack);
        exit = std::min(t_max, f);
    } else {
        const V n01 = n0 > n1 ? n0 : n1;
        const V n2t = n2 > t_min ? n2 : t_min;
        enter = n01 > n2t ? n01 : n2t;
        const V f01 = f0 < f1 ? f0 : f1;
        V f = f01 < f2 ? f01 : f2;
        if constexpr (Robust) f = f * (1.0f + kSlabExitSlack);
        exit = f < t_max ? f : t_max;
    }
}

/// The parameter interval [t_enter, t_exit] in which a ray is inside a box,
/// clipped to the ray's [t_min, t_max]; empty when t_enter > t_exit.
struct SlabInterval {
    float t_enter;  ///< where the ray enters the box, at least the ray's t_min
    float t_exit;   ///< where it leaves it (widened by kSlabExitSlack), at most the ray's t_max
    /// True when the interval is not empty: the ray segment touches the box.
    [[nodiscard]] bool hit() const { return t_enter <= t_exit; }
};

/// Per-ray constants of slab_test for one box at a time: the origin, the safe inverse
/// direction and, per axis, which corner of a box the ray enters through.
struct SlabRay {
    float origin[3];    ///< the ray's origin
    float inv_dir[3];   ///< safe_inverse(direction)
    bool enters_hi[3];  ///< true when inv_dir[a] is negative: the ray enters through hi[a]

    /// The constants of a ray with this origin and inverse direction (from safe_inverse).
    SlabRay(const glm::vec3& o, const glm::vec3& inv) {
        for (int a = 0; a < 3; ++a) {
            origin[a] = o[a];
            inv_dir[a] = inv[a];
            // A negative inverse enters through hi: (hi - o) * inv <= (lo - o) * inv.
            enters_hi[a] = std::signbit(inv[a]);
        }
    }
    /// The constants of a whole ray.
    explicit SlabRay(const Ray& ray) : SlabRay(ray.origin, safe_inverse(ray.direction)) {}
};

/// Conservative slab test of one box (slab_test with the exit widened by kSlabExitSlack),
/// clipped to [t_min, t_max]. An empty box (lo > hi) is never hit.
[[nodiscard]] inline SlabInterval intersect(const BBox& box, const SlabRay& r, float t_min,
                                            float t_max) {
    float near[3], far[3];
    for (int a = 0; a < 3; ++a) {
        near[a] = r.enters_hi[a] ? box.hi[a] : box.lo[a];
        far[a] = r.enters_hi[a] ? box.lo[a] : box.hi[a];
    }
    SlabInterval s;
    slab_test(near, far, r.origin, r.inv_dir, t_min, t_max, s.t_enter, s.t_exit);
    return s;
}

/// The same for a ray given by origin and safe_inverse direction.
[[nodiscard]] inline SlabInterval intersect(const BBox& box, const glm::vec3& origin,
                                            const glm::vec3& inv_dir, float t_min, float t_max) {
    return intersect(box, SlabRay(origin, inv_dir), t_min, t_max);
}

/// Convenience overload for a whole ray.
[[nodiscard]] inline SlabInterval intersect(const BBox& box, const Ray& ray) {
    return intersect(box, SlabRay(ray), ray.t_min, ray.t_max);
}

}  // namespace librt
