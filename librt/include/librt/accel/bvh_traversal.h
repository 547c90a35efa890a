#pragma once

#include <librt/accel/bvh.h>
#include <librt/core/error.h>
#include <librt/geometry/bbox.h>
#include <librt/geometry/ray.h>

#include <glm/geometric.hpp>

#include <cassert>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

namespace librt {

/// True when a ray can hit anything: finite origin, a finite, non-zero direction and
/// t_min <= t_max (so a NaN t_min or t_max is not traceable either).
[[nodiscard]] inline bool is_traceable(const Ray& ray) {
    const float d2 = glm::dot(ray.direction, ray.direction);
    return std::isfinite(ray.origin.x + ray.origin.y + ray.origin.z) && std::isfinite(d2) &&
           d2 > 0.0f && ray.t_min <= ray.t_max;
}

/// Walks a BVH front to back. For each leaf slot it calls
/// `hit_slot(std::uint32_t slot, Ray& ray) -> bool`, which tests primitive
/// bvh.prim_indices[slot] and, on a hit, shrinks ray.t_max to it and returns true;
/// nodes beyond the nearest hit so far are pruned. With AnyHit the walk stops at the
/// first hit (shadow rays). Returns whether anything was hit. A ray that is not
/// is_traceable misses. The deferred-node stack holds kMaxBvhDepth entries, enough for
/// any tree the builders make; a hand-made Bvh whose `depth` says deeper throws
/// librt::Error instead of overflowing it.
template <bool AnyHit, class HitSlot>
bool traverse(const Bvh& bvh, Ray& ray, HitSlot&& hit_slot) {
    if (bvh.depth > kMaxBvhDepth) {
        throw Error("BVH depth " + std::to_string(bvh.depth) +
                    " exceeds kMaxBvhDepth = " + std::to_string(kMaxBvhDepth));
    }
    if (bvh.nodes.empty() || !is_traceable(ray)) return false;
    const SlabRay slab_ray(ray);
    const BvhNode* nodes = bvh.nodes.data();
    if (!intersect(nodes[0].bounds, slab_ray, ray.t_min, ray.t_max).hit()) return false;

    // Deferred far children with their entry distance: at most one per level.
    struct Deferred {
        std::uint32_t node;
        float t_enter;
    };
    Deferred stack[kMaxBvhDepth];
    std::uint32_t stack_size = 0;
    std::uint32_t current = 0;
    bool found = false;
    for (;;) {
        const BvhNode& node = nodes[current];
        if (node.is_leaf()) {
            const std::uint32_t end = node.index + node.prim_count;
            for (std::uint32_t slot = node.index; slot < end; ++slot) {
                if (hit_slot(slot, ray)) {
                    found = true;
                    if constexpr (AnyHit) return true;
                }
            }
        } else {
            std::uint32_t near = node.index, far = node.index + 1;
            const SlabInterval a = intersect(nodes[near].bounds, slab_ray, ray.t_min, ray.t_max);
            const SlabInterval b = intersect(nodes[far].bounds, slab_ray, ray.t_min, ray.t_max);
            const bool hit_a = a.hit(), hit_b = b.hit();
            if (hit_a && hit_b) {
                const bool swap = b.t_enter < a.t_enter;
                if (swap) std::swap(near, far);
                assert(stack_size < kMaxBvhDepth && "Bvh::depth understates the tree's depth");
                stack[stack_size++] = {far, swap ? a.t_enter : b.t_enter};
                current = near;
                continue;
            }
            if (hit_a || hit_b) {
                current = hit_a ? near : far;
                continue;
            }
        }
        // Pop the next deferred node that starts before the nearest hit so far.
        for (;;) {
            if (stack_size == 0) return found;
            const Deferred& next = stack[--stack_size];
            if (next.t_enter <= ray.t_max) {
                current = next.node;
                break;
            }
        }
    }
}

/// The naive alternative with the same contract: tests every slot 0..count-1.
template <bool AnyHit, class HitSlot>
bool traverse_linear(std::uint32_t count, Ray& ray, HitSlot&& hit_slot) {
    if (!is_traceable(ray)) return false;
    bool found = false;
    for (std::uint32_t slot = 0; slot < count; ++slot) {
        if (hit_slot(slot, ray)) {
            found = true;
            if constexpr (AnyHit) return true;
        }
    }
    return found;
}

}  // namespace librt
