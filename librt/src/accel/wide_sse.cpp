// SSE2 wide-BVH kernel: a node's eight children in two 4-lane halves (slab4.h), four
// triangles per test (block4_sse.h). SSE2 is part of x86-64, so this file needs no target
// switch.

#include "wide_kernels.h"

#if defined(LIBRT_HAVE_X86_KERNELS)
#include "block4_sse.h"
#include "slab4.h"
#include "wide_stream.h"
#include "wide_traversal.h"

#include <cstdint>

namespace librt::detail {
namespace {

/// The WideKernel policy of the SSE path.
struct SseKernel : Block4Triangles {
    using NodeRay = SlabRay4;

    static NodeRay prepare_nodes(const Ray& ray) { return prepare_slab4(ray); }

    /// slab_test4 on children 0..3, then 4..7 (bounds rows are kWideBvhWidth floats apart).
    static std::uint32_t intersect_node(const WideBvhNode& node, const NodeRay& r, float t_min,
                                        float t_max, float* t_enter) {
        const std::uint32_t lo =
            slab_test4(&node.bounds[0][0], kWideBvhWidth, r, t_min, t_max, t_enter);
        const std::uint32_t hi =
            slab_test4(&node.bounds[0][4], kWideBvhWidth, r, t_min, t_max, t_enter + 4);
        return lo | (hi << 4);
    }
};
static_assert(WideKernel<SseKernel>);

[[gnu::flatten]] PrimitiveHit sse_intersect(const WideBvh& bvh, const Ray& ray) {
    return intersect_wide<SseKernel>(bvh, ray);
}
[[gnu::flatten]] bool sse_occluded(const WideBvh& bvh, const Ray& ray) {
    return occluded_wide<SseKernel>(bvh, ray);
}
[[gnu::flatten]] PrimitiveHit sse_intersect_normal(const WideBvh& bvh, const Ray& ray,
                                                   glm::vec3& normal) {
    return intersect_normal_wide<SseKernel>(bvh, ray, normal);
}

[[gnu::flatten]] void sse_intersect_stream(const WideBvh& bvh, const Ray* rays, PrimitiveHit* hits,
                                           std::size_t count) {
    traverse_wide_stream<SseKernel, false>(
        bvh, rays, hits, count, [](const Ray&) { return true; },
        [](const Ray&) { return PrimitiveHit{}; });
}
[[gnu::flatten]] void sse_occluded_stream(const WideBvh& bvh, const Ray* rays,
                                          std::uint8_t* blocked, std::size_t count) {
    traverse_wide_stream<SseKernel, true>(
        bvh, rays, blocked, count, [](const Ray&) { return true; },
        [](const Ray&) { return std::uint8_t{0}; });
}

}  // namespace

WideKernels sse_wide_kernels() {
    return {&sse_intersect, &sse_occluded, &sse_intersect_normal, &sse_intersect_stream,
            &sse_occluded_stream};
}

}  // namespace librt::detail
#endif
