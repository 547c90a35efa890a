#pragma once

// Private: the per-instruction-set traversal kernels of the wide BVH and their dispatch.

#include <librt/accel/simd.h>
#include <librt/accel/wide_bvh.h>
#include <librt/geometry/hit.h>
#include <librt/geometry/ray.h>

namespace librt::detail {

/// Closest-hit and any-hit traversal of a WideBvh for one instruction set.
struct WideKernels {
    PrimitiveHit (*intersect)(const WideBvh&, const Ray&);
    bool (*occluded)(const WideBvh&, const Ray&);
};

/// The kernels of `path`; the caller checks simd_path_supported(path) first.
[[nodiscard]] WideKernels wide_kernels(SimdPath path);

// One pair per instruction set, each in its own wide_<isa>.cpp.
#define LIBRT_DECLARE_WIDE_KERNELS(isa)                                       \
    namespace isa {                                                           \
    [[nodiscard]] PrimitiveHit intersect(const WideBvh& bvh, const Ray& ray); \
    [[nodiscard]] bool occluded(const WideBvh& bvh, const Ray& ray);          \
    }
LIBRT_DECLARE_WIDE_KERNELS(scalar)
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define LIBRT_HAVE_X86_KERNELS 1
LIBRT_DECLARE_WIDE_KERNELS(sse)
LIBRT_DECLARE_WIDE_KERNELS(avx2)
LIBRT_DECLARE_WIDE_KERNELS(avx512)
#endif
#undef LIBRT_DECLARE_WIDE_KERNELS

}  // namespace librt::detail
