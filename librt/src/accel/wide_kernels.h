#pragma once

// Private: the per-instruction-set entry points of the wide BVH traversal and their dispatch.

#include "wide_bvh.h"

#include <librt/accel/bvh_stats.h>
#include <librt/accel/simd.h>
#include <librt/geometry/hit.h>
#include <librt/geometry/ray.h>

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>

namespace librt::detail {

/// Closest-hit and any-hit traversal of a WideBvh for one instruction set.
struct WideKernels {
    PrimitiveHit (*intersect)(const WideBvh&, const Ray&);  ///< closest hit
    bool (*occluded)(const WideBvh&, const Ray&);           ///< any hit
    /// Closest hit and, on a hit, the triangle's winding normal cross(p1 - p0, p2 - p0)
    /// from the leaf's corners (intersect_normal_wide).
    PrimitiveHit (*intersect_normal)(const WideBvh&, const Ray&, glm::vec3&);
    /// Closest hits of a stream of rays (wide_stream.h): hits[i] = intersect(rays[i]).
    void (*intersect_stream)(const WideBvh&, const Ray* rays, PrimitiveHit* hits,
                             std::size_t count);
    /// Any hits of a stream: blocked[i] = occluded(rays[i]) ? 1 : 0.
    void (*occluded_stream)(const WideBvh&, const Ray* rays, std::uint8_t* blocked,
                            std::size_t count);
};

/// One query through the scalar kernel, counting what the traversal does. The SSE path makes
/// the same decisions (its node and leaf tests agree bit for bit); the AVX paths' fused node
/// test computes entry distances a few ulps apart, so their order and culling of children
/// can differ on rare near-ties (their hits do not).
[[nodiscard]] TraversalCounts count_wide_traversal(const WideBvh& bvh, const Ray& ray,
                                                   bool any_hit);

/// The kernels of `path`; the caller checks simd_path_supported(path) first.
[[nodiscard]] WideKernels wide_kernels(SimdPath path);

// One per instruction set, each defined in its own wide_<isa>.cpp.
[[nodiscard]] WideKernels scalar_wide_kernels();
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define LIBRT_HAVE_X86_KERNELS 1
[[nodiscard]] WideKernels sse_wide_kernels();
[[nodiscard]] WideKernels avx2_wide_kernels();
[[nodiscard]] WideKernels avx512_wide_kernels();
#endif

}  // namespace librt::detail
