// The portable wide-BVH kernel: one child box and one triangle at a time, with the very
// arithmetic of bbox.h's slab test and triangle.h's watertight test. Every other
// instruction set must agree with it.

#include "wide_kernels.h"
#include "wide_stream.h"
#include "wide_traversal.h"

#include <librt/geometry/bbox.h>
#include <librt/geometry/triangle.h>

#include <cmath>
#include <cstdint>

namespace librt::detail {
namespace {

/// The WideKernel policy of the scalar path.
struct ScalarKernel {
    /// Per-ray constants of the slab test: origin, safe inverse direction, and for each
    /// axis the bounds rows the ray enters and leaves through (lo first when the inverse is
    /// positive).
    struct NodeRay {
        float o[3];
        float inv[3];
        std::uint32_t near[3];
        std::uint32_t far[3];
    };
    using TriRay = WatertightRay;

    static NodeRay prepare_nodes(const Ray& ray) {
        NodeRay r{};
        const glm::vec3 inv = safe_inverse(ray.direction);
        for (std::uint32_t a = 0; a < 3; ++a) {
            r.o[a] = ray.origin[static_cast<int>(a)];
            r.inv[a] = inv[static_cast<int>(a)];
            const bool negative = std::signbit(r.inv[a]);
            r.near[a] = 2 * a + (negative ? 1 : 0);
            r.far[a] = 2 * a + (negative ? 0 : 1);
        }
        return r;
    }

    /// bbox.h's slab_test of the eight children, one at a time.
    static std::uint32_t intersect_node(const WideBvhNode& node, const NodeRay& r, float t_min,
                                        float t_max, float* t_enter) {
        std::uint32_t mask = 0;
        for (std::uint32_t i = 0; i < kWideBvhWidth; ++i) {
            float near[3], far[3];
            for (std::uint32_t a = 0; a < 3; ++a) {
                near[a] = node.bounds[r.near[a]][i];
                far[a] = node.bounds[r.far[a]][i];
            }
            float enter, exit;  // locals, so the store to t_enter cannot alias the planes
            slab_test(near, far, r.o, r.inv, t_min, t_max, enter, exit);
            t_enter[i] = enter;
            mask |= static_cast<std::uint32_t>(enter <= exit) << i;
        }
        return mask;
    }

    static TriRay prepare_triangles(const Ray& ray) { return prepare_watertight(ray); }

    static bool intersect_block(const TriangleBlock& block, const TriRay& w, float t_min,
                                float& t_max, std::uint32_t& lane, float& u, float& v) {
        bool found = false;
        for (std::uint32_t k = 0; k < kTriangleBlockSize; ++k) {
            const auto h = intersect(block.triangle(k), w, t_min, t_max);
            if (!h) continue;
            t_max = h->t;
            lane = k;
            u = h->u;
            v = h->v;
            found = true;
        }
        return found;
    }

    static bool occluded_block(const TriangleBlock& block, const TriRay& w, float t_min,
                               float t_max) {
        for (std::uint32_t k = 0; k < kTriangleBlockSize; ++k)
            if (intersect(block.triangle(k), w, t_min, t_max)) return true;
        return false;
    }
};
static_assert(WideKernel<ScalarKernel>);

PrimitiveHit scalar_intersect(const WideBvh& bvh, const Ray& ray) {
    return intersect_wide<ScalarKernel>(bvh, ray);
}
bool scalar_occluded(const WideBvh& bvh, const Ray& ray) {
    return occluded_wide<ScalarKernel>(bvh, ray);
}
PrimitiveHit scalar_intersect_normal(const WideBvh& bvh, const Ray& ray, glm::vec3& normal) {
    return intersect_normal_wide<ScalarKernel>(bvh, ray, normal);
}

void scalar_intersect_stream(const WideBvh& bvh, const Ray* rays, PrimitiveHit* hits,
                             std::size_t count) {
    traverse_wide_stream<ScalarKernel, false>(
        bvh, rays, hits, count, [](const Ray&) { return true; },
        [](const Ray&) { return PrimitiveHit{}; });
}
void scalar_occluded_stream(const WideBvh& bvh, const Ray* rays, std::uint8_t* blocked,
                            std::size_t count) {
    traverse_wide_stream<ScalarKernel, true>(
        bvh, rays, blocked, count, [](const Ray&) { return true; },
        [](const Ray&) { return std::uint8_t{0}; });
}

}  // namespace

WideKernels scalar_wide_kernels() {
    return {&scalar_intersect, &scalar_occluded, &scalar_intersect_normal, &scalar_intersect_stream,
            &scalar_occluded_stream};
}

TraversalCounts count_wide_traversal(const WideBvh& bvh, const Ray& ray, bool any_hit) {
    TraversalCounts counts;
    if (any_hit) {
        traverse_wide<ScalarKernel, true, true>(bvh, ray, nullptr, &counts);
    } else {
        PrimitiveHit hit;
        traverse_wide<ScalarKernel, false, true>(bvh, ray, &hit, &counts);
    }
    return counts;
}

}  // namespace librt::detail
