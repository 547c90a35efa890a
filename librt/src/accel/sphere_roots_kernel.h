#pragma once

// Private: the one sphere-root kernel (sphere_roots.h), shared by every instruction set
// through a lane policy (SphereLaneOps below), as wide_traversal.h shares the wide BVH's
// traversal. Each sphere_roots*.cpp defines its policy and entry point, and includes this
// header, under its instruction set's target (its dependencies included before, as baseline
// code): the kernel's instantiation with that file's policy (internal linkage, the policy
// being in an anonymous namespace) is then compiled for the target, and no vector crosses a
// call between baseline and vector code.

#include "accel/sphere_roots.h"

#include <concepts>
#include <cstdint>

namespace librt::detail {

/// What sphere_roots_lanes requires of a lane policy L (static members only), with L::Vec
/// kWidth doubles and L::Mask a per-lane truth value:
///   - set1, load, store: a value in every lane, kWidth doubles from / to memory (unaligned);
///   - add, sub, mul, div, sqrt: per lane, IEEE rounded like the scalar operations;
///   - min(a, b), max(a, b): a < b ? a : b and a > b ? a : b (minpd's and maxpd's order);
///   - ge, gt, lt (ordered), ne (unordered): per-lane comparisons;
///   - both(m, n): m and n; but_not(m, n): n and not m;
///   - select(m, a, b): a where m, else b;
///   - copysign(a, b): |a| with b's sign; negate(a): a with its sign flipped;
///   - bits(m): bit i set when lane i of m is.
template <class L>
concept SphereLaneOps = requires(typename L::Vec v, typename L::Mask m, double x, double* p) {
    { L::kWidth } -> std::convertible_to<std::uint32_t>;
    { L::set1(x) } -> std::same_as<typename L::Vec>;
    { L::load(p) } -> std::same_as<typename L::Vec>;
    L::store(p, v);
    { L::add(v, v) } -> std::same_as<typename L::Vec>;
    { L::sub(v, v) } -> std::same_as<typename L::Vec>;
    { L::mul(v, v) } -> std::same_as<typename L::Vec>;
    { L::div(v, v) } -> std::same_as<typename L::Vec>;
    { L::sqrt(v) } -> std::same_as<typename L::Vec>;
    { L::min(v, v) } -> std::same_as<typename L::Vec>;
    { L::max(v, v) } -> std::same_as<typename L::Vec>;
    { L::ge(v, v) } -> std::same_as<typename L::Mask>;
    { L::gt(v, v) } -> std::same_as<typename L::Mask>;
    { L::lt(v, v) } -> std::same_as<typename L::Mask>;
    { L::ne(v, v) } -> std::same_as<typename L::Mask>;
    { L::both(m, m) } -> std::same_as<typename L::Mask>;
    { L::but_not(m, m) } -> std::same_as<typename L::Mask>;
    { L::select(m, v, v) } -> std::same_as<typename L::Vec>;
    { L::copysign(v, v) } -> std::same_as<typename L::Vec>;
    { L::negate(v) } -> std::same_as<typename L::Vec>;
    { L::bits(m) } -> std::same_as<std::uint32_t>;
};

/// sphere_roots.h's kernel, L::kWidth spheres at a time. Each lane runs sphere.h's scalar
/// intersect(DoubleSphere, DoubleRay, t_min, t_max) in the same order of operations (the
/// library is compiled with -ffp-contract=off), its branches as masks.
template <SphereLaneOps L>
inline std::uint32_t sphere_roots_lanes(const SphereLanes& spheres, const DoubleRay& ray,
                                        double t_min, double t_max, double* roots) {
    using Vec = typename L::Vec;
    using Mask = typename L::Mask;
    const Vec ox = L::set1(ray.origin.x), oy = L::set1(ray.origin.y), oz = L::set1(ray.origin.z);
    const Vec dx = L::set1(ray.direction.x), dy = L::set1(ray.direction.y),
              dz = L::set1(ray.direction.z);
    const Vec a = L::set1(ray.a), inv_a = L::set1(ray.inv_a);
    const Vec lo = L::set1(t_min), hi = L::set1(t_max);
    const Vec zero = L::set1(0.0);
    const Vec none = L::set1(__builtin_nan(""));
    const Vec inf = L::set1(__builtin_inf());
    std::uint32_t mask = 0;
    for (std::uint32_t i = 0; i < spheres.count; i += L::kWidth) {
        const Vec r2 = L::load(spheres.r2 + i);
        // oc = o - c; b = oc . d; c = oc . oc - r^2 (glm's dot: (x + y) + z).
        const Vec ocx = L::sub(ox, L::load(spheres.cx + i));
        const Vec ocy = L::sub(oy, L::load(spheres.cy + i));
        const Vec ocz = L::sub(oz, L::load(spheres.cz + i));
        const Vec b = L::add(L::add(L::mul(ocx, dx), L::mul(ocy, dy)), L::mul(ocz, dz));
        const Vec c =
            L::sub(L::add(L::add(L::mul(ocx, ocx), L::mul(ocy, ocy)), L::mul(ocz, ocz)), r2);
        // Outside and moving away: no root (the scalar test's early return).
        const Mask away = L::both(L::ge(b, zero), L::gt(c, zero));
        // Half-chord^2 = r^2 - |oc - (b / a) d|^2.
        const Vec s = L::mul(b, inv_a);
        const Vec clx = L::sub(ocx, L::mul(s, dx));
        const Vec cly = L::sub(ocy, L::mul(s, dy));
        const Vec clz = L::sub(ocz, L::mul(s, dz));
        const Vec hc2 =
            L::sub(r2, L::add(L::add(L::mul(clx, clx), L::mul(cly, cly)), L::mul(clz, clz)));
        const Mask meets = L::but_not(away, L::ge(hc2, zero));
        // q = -(b + copysign(sqrt(hc2 a), b)); roots q / a and c / q (q / a when q = 0).
        const Vec q = L::negate(L::add(b, L::copysign(L::sqrt(L::mul(hc2, a)), b)));
        const Vec t_a = L::mul(q, inv_a);
        const Vec t_b = L::select(L::ne(q, zero), L::div(c, q), t_a);
        // std::min(t_a, t_b) is t_b < t_a ? t_b : t_a, which min(t_b, t_a) is; max likewise.
        const Vec near = L::min(t_b, t_a), far = L::max(t_b, t_a);
        const Mask near_in = L::both(L::gt(near, lo), L::lt(near, hi));
        const Mask far_in = L::both(L::gt(far, lo), L::lt(far, hi));
        const Vec t = L::select(near_in, near, L::select(far_in, far, none));
        const Vec result = L::select(meets, t, none);
        // A hit is a root >= 0 (TopLevel's test); the others become +inf.
        const Mask hit = L::ge(result, zero);
        L::store(roots + i, L::select(hit, result, inf));
        mask |= L::bits(hit) << i;
    }
    // Lanes past count (a count not a multiple of kWidth) hold the empty sphere: their bit is
    // never set.
    return mask;
}

}  // namespace librt::detail
