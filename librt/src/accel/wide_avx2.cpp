// AVX2 wide-BVH kernels: the eight child boxes of a node in one 8-lane test, four triangles per
// test. Only this file's kernels are compiled for the instruction set (a target pragma around them,
// not a -m flag on the file), so nothing here can leak into baseline code; they run only when
// simd_path_supported() says the CPU has it.

#include "wide_kernels.h"

#if defined(LIBRT_HAVE_X86_KERNELS)
#include <librt/accel/bvh_traversal.h>
#include <librt/geometry/triangle.h>

#include <immintrin.h>

#include <bit>
#include <cmath>
#include <cstdint>

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,popcnt,bmi"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,popcnt,bmi")
#endif

namespace librt::detail::avx2 {
namespace {

#include "block4_sse.inl"

struct Kernel : Block4Kernel {
    /// Per-ray constants of the slab test, broadcast; see wide_scalar.cpp.
    struct NodeRay {
        __m256 o[3];
        __m256 inv[3];
        std::uint32_t near[3];
        std::uint32_t far[3];
    };

    static NodeRay prepare_nodes(const Ray& ray) {
        NodeRay r;
        alignas(16) float inv[4];
        _mm_store_ps(inv, safe_inverse4(ray.direction));
        for (std::uint32_t a = 0; a < 3; ++a) {
            const float inv_a = inv[a];
            r.o[a] = _mm256_set1_ps(ray.origin[static_cast<int>(a)]);
            r.inv[a] = _mm256_set1_ps(inv_a);
            const bool negative = std::signbit(inv_a);
            r.near[a] = 2 * a + (negative ? 1 : 0);
            r.far[a] = 2 * a + (negative ? 0 : 1);
        }
        return r;
    }

    /// Slab test (Kay-Kajiya): t = (plane - o) / d per axis; enter = max of the near
    /// planes and t_min, exit = min of the far planes and t_max; hit when enter <= exit.
    static std::uint32_t intersect_node(const WideBvhNode& node, const NodeRay& r, float t_min,
                                        float t_max, float* t_enter) {
        __m256 tn[3], tf[3];
        for (std::uint32_t a = 0; a < 3; ++a) {
            tn[a] = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(node.bounds[r.near[a]]), r.o[a]),
                                  r.inv[a]);
            tf[a] = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(node.bounds[r.far[a]]), r.o[a]),
                                  r.inv[a]);
        }
        const __m256 enter =
            _mm256_max_ps(_mm256_max_ps(tn[0], tn[1]), _mm256_max_ps(tn[2], _mm256_set1_ps(t_min)));
        const __m256 exit =
            _mm256_min_ps(_mm256_mul_ps(_mm256_min_ps(_mm256_min_ps(tf[0], tf[1]), tf[2]),
                                        _mm256_set1_ps(kSlabExitScale)),
                          _mm256_set1_ps(t_max));
        _mm256_store_ps(t_enter, enter);
        return static_cast<std::uint32_t>(
            _mm256_movemask_ps(_mm256_cmp_ps(enter, exit, _CMP_LE_OQ)));
    }
};

#include "wide_traversal.inl"

}  // namespace

PrimitiveHit intersect(const WideBvh& bvh, const Ray& ray) {
    return intersect_with<Kernel>(bvh, ray);
}
bool occluded(const WideBvh& bvh, const Ray& ray) { return occluded_with<Kernel>(bvh, ray); }

}  // namespace librt::detail::avx2

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif
