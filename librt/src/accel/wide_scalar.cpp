// The portable wide-BVH kernels: one child box and one triangle at a time, with the very
// arithmetic of bbox.h's slab test and triangle.h's watertight test. Every other
// instruction set must agree with these.

#include "wide_kernels.h"

#include <librt/accel/bvh_traversal.h>
#include <librt/geometry/triangle.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace librt::detail::scalar {
namespace {

struct Kernel {
    /// Per-ray constants of the slab test: origin, safe inverse direction, and for each
    /// axis the bounds plane the ray enters through (lo when the inverse is positive).
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
            // A negative inverse enters through hi: (hi - o) * inv <= (lo - o) * inv, so this
            // picks min/max of bbox.h's slab test without computing both.
            const bool negative = std::signbit(r.inv[a]);
            r.near[a] = 2 * a + (negative ? 1 : 0);
            r.far[a] = 2 * a + (negative ? 0 : 1);
        }
        return r;
    }

    /// Slab test (Kay-Kajiya) of the eight children, as bbox.h's intersect.
    static std::uint32_t intersect_node(const WideBvhNode& node, const NodeRay& r, float t_min,
                                        float t_max, float* t_enter) {
        std::uint32_t mask = 0;
        for (std::uint32_t i = 0; i < kWideBvhWidth; ++i) {
            float tn[3], tf[3];
            for (std::uint32_t a = 0; a < 3; ++a) {
                tn[a] = (node.bounds[r.near[a]][i] - r.o[a]) * r.inv[a];
                tf[a] = (node.bounds[r.far[a]][i] - r.o[a]) * r.inv[a];
            }
            const float enter = std::max(std::max(tn[0], tn[1]), std::max(tn[2], t_min));
            const float exit =
                std::min(std::min(std::min(tf[0], tf[1]), tf[2]) * kSlabExitScale, t_max);
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

#include "wide_traversal.inl"

}  // namespace

PrimitiveHit intersect(const WideBvh& bvh, const Ray& ray) {
    return intersect_with<Kernel>(bvh, ray);
}
bool occluded(const WideBvh& bvh, const Ray& ray) { return occluded_with<Kernel>(bvh, ray); }

}  // namespace librt::detail::scalar
