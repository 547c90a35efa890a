#pragma once

// Private: bbox.h's slab test on the eight children of a wide node in one AVX test, the node
// half of the AVX2 and AVX-512 kernels. Compiled for AVX2 (a target pragma around this
// header's own code, not a -m flag on a file, so nothing leaks into baseline code); it runs
// only when simd_path_supported() says the CPU has it.

#include "slab4.h"
#include "wide_bvh.h"

#include <librt/geometry/bbox.h>
#include <librt/geometry/ray.h>

#include <immintrin.h>

#include <cmath>
#include <cstdint>

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,popcnt,bmi"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,popcnt,bmi")
#endif

namespace librt::detail {

/// Per-ray constants of slab_test8: origin and safe inverse direction broadcast to eight
/// lanes, and per axis the bounds rows the ray enters and leaves through (see SlabRay4).
struct SlabRay8 {
    __m256 origin[3];       ///< origin[a] in every lane
    __m256 inv[3];          ///< safe_inverse(direction)[a] in every lane
    std::uint32_t near[3];  ///< row of the plane the ray enters through along each axis
    std::uint32_t far[3];   ///< row of the plane it leaves through
};

/// The constants of slab_test8 for a ray.
inline SlabRay8 prepare_slab8(const Ray& ray) {
    SlabRay8 r;
    alignas(16) float inv[4];
    _mm_store_ps(inv, safe_inverse4(ray.direction));
    for (std::uint32_t a = 0; a < 3; ++a) {
        const float inv_a = inv[a];
        r.origin[a] = _mm256_set1_ps(ray.origin[static_cast<int>(a)]);
        r.inv[a] = _mm256_set1_ps(inv_a);
        const bool negative = std::signbit(inv_a);
        r.near[a] = 2 * a + (negative ? 1 : 0);
        r.far[a] = 2 * a + (negative ? 0 : 1);
    }
    return r;
}

/// Conservative slab test (bbox.h's slab_test) of a node's eight children: writes their
/// entry distances to t_enter (32-byte aligned) and the entry and exit vectors, a child
/// being hit where enter <= exit; each kernel turns that into a bit mask its own way.
inline void slab_test8(const WideBvhNode& node, const SlabRay8& r, float t_min, float t_max,
                       float* t_enter, __m256& enter, __m256& exit) {
    __m256 near[3], far[3];
    for (std::uint32_t a = 0; a < 3; ++a) {
        near[a] = _mm256_load_ps(node.bounds[r.near[a]]);
        far[a] = _mm256_load_ps(node.bounds[r.far[a]]);
    }
    slab_test(near, far, r.origin, r.inv, _mm256_set1_ps(t_min), _mm256_set1_ps(t_max), enter,
              exit);
    _mm256_store_ps(t_enter, enter);
}

/// The node half of the AVX2 and AVX-512 WideKernel policies (see wide_traversal.h) that
/// both share: the per-ray constants. Each kernel adds its own intersect_node, the one
/// place they differ (how slab_test8's lanes become a bit mask).
struct Slab8Nodes {
    using NodeRay = SlabRay8;

    static NodeRay prepare_nodes(const Ray& ray) { return prepare_slab8(ray); }
};

}  // namespace librt::detail

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
