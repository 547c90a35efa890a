#pragma once

// Private: sphere.h's double-precision ray-sphere test, intersect(DoubleSphere, DoubleRay,
// t_min, t_max), for all the spheres of a flat top level at once: two spheres per SSE2
// instruction, four per AVX instruction (sphere_roots_avx.cpp), eight per AVX-512 instruction
// (sphere_roots_avx512.cpp). Every lane
// runs the scalar function's double operations in the same order (the library is compiled
// with -ffp-contract=off, and the vector instructions round like the scalar ones), so each
// lane's root is the scalar root bit for bit; the branches of the scalar test become masks.

#include <librt/accel/simd.h>
#include <librt/geometry/sphere.h>

#include <cstdint>

namespace librt::detail {

/// Up to kLanes spheres in double as structure of arrays. Lanes past `count` hold a sphere of
/// squared radius -1, which no ray meets.
struct SphereLanes {
    static constexpr std::uint32_t kLanes = 16;  ///< TopLevel::kFlatObjectLimit
    alignas(64) double cx[kLanes];               ///< centre x
    alignas(64) double cy[kLanes];               ///< centre y
    alignas(64) double cz[kLanes];               ///< centre z
    alignas(64) double r2[kLanes];               ///< squared radius
    std::uint32_t count = 0;                     ///< spheres held

    /// Empties every lane (squared radius -1: no root).
    void clear() {
        for (std::uint32_t i = 0; i < kLanes; ++i) {
            cx[i] = cy[i] = cz[i] = 0.0;
            r2[i] = -1.0;
        }
        count = 0;
    }
    /// Puts a sphere into the next lane.
    void push(const DoubleSphere& s) {
        cx[count] = s.center.x;
        cy[count] = s.center.y;
        cz[count] = s.center.z;
        r2[count] = s.radius2;
        ++count;
    }
};

/// Writes, for every lane i < count (rounded up to the kernel's width), roots[i] =
/// intersect(sphere i, ray, t_min, t_max) when that root is >= 0 (a hit, TopLevel's test of
/// the scalar result), else +inf, and returns the mask of the hit lanes.
using SphereRootsFn = std::uint32_t (*)(const SphereLanes& spheres, const DoubleRay& ray,
                                        double t_min, double t_max, double* roots);

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
/// Two lanes per instruction (SSE2, part of x86-64).
std::uint32_t sphere_roots_sse2(const SphereLanes& spheres, const DoubleRay& ray, double t_min,
                                double t_max, double* roots);
/// Four lanes per instruction (AVX; call only when the CPU has it).
std::uint32_t sphere_roots_avx(const SphereLanes& spheres, const DoubleRay& ray, double t_min,
                               double t_max, double* roots);
/// Eight lanes per instruction (AVX-512 F; call only when the CPU has it).
std::uint32_t sphere_roots_avx512(const SphereLanes& spheres, const DoubleRay& ray, double t_min,
                                  double t_max, double* roots);
#endif

/// The kernel for a SIMD path: SSE2 for Sse, AVX for Avx2 (which implies AVX), AVX-512 for
/// Avx512;
/// nullptr for Scalar (and off x86-64), where TopLevel tests one sphere at a time during
/// its visit of the boxes, as it always did. The caller checks simd_path_supported(path).
SphereRootsFn sphere_roots_for(SimdPath path);

}  // namespace librt::detail
