// SSE2 wide-BVH kernels: a node's eight children in two 4-lane halves, four triangles per
// test. SSE2 is part of x86-64, so this file needs no target switch.

#include "wide_kernels.h"

#if defined(LIBRT_HAVE_X86_KERNELS)
#include <librt/accel/bvh_traversal.h>
#include <librt/geometry/triangle.h>

#include <immintrin.h>

#include <bit>
#include <cmath>
#include <cstdint>

namespace librt::detail::sse {
namespace {

#include "block4_sse.inl"

struct Kernel : Block4Kernel {
    /// Per-ray constants of the slab test, broadcast; see wide_scalar.cpp.
    struct NodeRay {
        __m128 o[3];
        __m128 inv[3];
        std::uint32_t near[3];
        std::uint32_t far[3];
    };

    static NodeRay prepare_nodes(const Ray& ray) {
        NodeRay r;
        alignas(16) float inv[4];
        _mm_store_ps(inv, safe_inverse4(ray.direction));
        for (std::uint32_t a = 0; a < 3; ++a) {
            const float inv_a = inv[a];
            r.o[a] = _mm_set1_ps(ray.origin[static_cast<int>(a)]);
            r.inv[a] = _mm_set1_ps(inv_a);
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
        const __m128 tmin = _mm_set1_ps(t_min), tmax = _mm_set1_ps(t_max);
        std::uint32_t mask = 0;
        for (std::uint32_t h = 0; h < kWideBvhWidth; h += 4) {
            __m128 tn[3], tf[3];
            for (std::uint32_t a = 0; a < 3; ++a) {
                tn[a] = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(&node.bounds[r.near[a]][h]), r.o[a]),
                                   r.inv[a]);
                tf[a] = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(&node.bounds[r.far[a]][h]), r.o[a]),
                                   r.inv[a]);
            }
            const __m128 enter = _mm_max_ps(_mm_max_ps(tn[0], tn[1]), _mm_max_ps(tn[2], tmin));
            const __m128 exit = _mm_min_ps(_mm_mul_ps(_mm_min_ps(_mm_min_ps(tf[0], tf[1]), tf[2]),
                                                      _mm_set1_ps(kSlabExitScale)),
                                           tmax);
            _mm_store_ps(t_enter + h, enter);
            mask |= static_cast<std::uint32_t>(_mm_movemask_ps(_mm_cmple_ps(enter, exit))) << h;
        }
        return mask;
    }
};

#include "wide_traversal.inl"

}  // namespace

PrimitiveHit intersect(const WideBvh& bvh, const Ray& ray) {
    return intersect_with<Kernel>(bvh, ray);
}
bool occluded(const WideBvh& bvh, const Ray& ray) { return occluded_with<Kernel>(bvh, ray); }

}  // namespace librt::detail::sse
#endif
