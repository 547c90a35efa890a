#pragma once

// Private: the one traversal of the wide BVH, shared by every instruction set through a
// kernel policy (WideKernel below). The traversal is baseline code that only calls the
// policy; each wide_<isa>.cpp instantiates it in entry points compiled for its instruction
// set and marked flatten, so the traversal and the policy's node and leaf tests are inlined
// there with that instruction set's encoding.

#include "ablation.h"
#include "wide_bvh.h"

#include <librt/accel/bvh_stats.h>
#include <librt/accel/bvh_traversal.h>
#include <librt/geometry/hit.h>
#include <librt/geometry/ray.h>

#include <glm/geometric.hpp>

#include <bit>
#include <concepts>
#include <cstddef>
#include <cstdint>

namespace librt::detail {

/// What traverse_wide requires of a kernel policy K (static members only):
///   - K::NodeRay prepare_nodes(ray): per-ray constants of the node test;
///   - intersect_node(node, node_ray, t_min, t_max, t_enter): bit i set when child i's box is
///     entered within [t_min, t_max] (bbox.h's slab_test), t_enter[i] its entry distance;
///   - K::TriRay prepare_triangles(ray): per-ray constants of the leaf test;
///   - intersect_block(block, tri_ray, t_min, t_max, lane, u, v): true when a lane is hit in
///     (t_min, t_max); t_max, lane, u and v then become those of the nearest such lane;
///   - occluded_block(block, tri_ray, t_min, t_max): true when any lane is hit.
template <class K>
concept WideKernel = requires(const Ray& ray, const WideBvhNode& node, const TriangleBlock& block,
                              const typename K::NodeRay& node_ray,
                              const typename K::TriRay& tri_ray, float t, float& t_max,
                              std::uint32_t& lane, float* t_enter) {
    { K::prepare_nodes(ray) } -> std::same_as<typename K::NodeRay>;
    { K::intersect_node(node, node_ray, t, t, t_enter) } -> std::same_as<std::uint32_t>;
    { K::prepare_triangles(ray) } -> std::same_as<typename K::TriRay>;
    { K::intersect_block(block, tri_ray, t, t_max, lane, t_max, t_max) } -> std::same_as<bool>;
    { K::occluded_block(block, tri_ray, t, t) } -> std::same_as<bool>;
};

/// A deferred child: its reference and the distance at which the ray enters its box.
///   bytes 0..3  child reference (as in WideBvhNode::child)
///   bytes 4..7  entry distance
struct WideStackEntry {
    std::uint32_t ref;
    float t_enter;
};
static_assert(sizeof(WideStackEntry) == 8, "WideStackEntry must stay 8 bytes");

/// A node visit pushes at most eight entries and takes one back, so the stack never holds
/// more than seven per level above the current node plus eight.
inline constexpr std::uint32_t kWideStackSize =
    (kWideBvhWidth - 1) * kMaxWideBvhDepth + kWideBvhWidth;

/// Asks the memory system for the first four cache lines of a deferred child, so that they
/// are (likely) in cache when its turn comes while the nearer subtree is walked: all of a
/// node (224 bytes at 32-byte alignment spans four lines), or a leaf's first block (160 bytes
/// at 16-byte alignment spans at most four) and the start of the next one, which a leaf of
/// two blocks needs and a sibling leaf (a node's leaves are adjacent) often does. A fixed
/// count without a branch on the size: the loop over a child's exact lines cost ~90
/// instructions per incoherent ray (callgrind).
inline void prefetch_child(const WideBvhNode* nodes, const TriangleBlock* blocks,
                           std::uint32_t ref) {
    const char* p = WideBvhNode::is_leaf(ref)
                        ? reinterpret_cast<const char*>(blocks + WideBvhNode::first_block(ref))
                        : reinterpret_cast<const char*>(nodes + ref);
    __builtin_prefetch(p);
    __builtin_prefetch(p + 64);
    __builtin_prefetch(p + 128);
    __builtin_prefetch(p + 192);
}

/// Front-to-back traversal: the children a node's test hits are visited nearest first,
/// the others deferred with their entry distance and skipped when a nearer hit is known.
/// With AnyHit the children go in slot order instead and the walk stops at the first hit.
/// Fills *hit (closest hit only). With Count it
/// also adds what it did to *counts (a separate instantiation: the others count nothing).
/// With WindingNormal it also sets *normal on a hit: the hit triangle's cross(p1 - p0,
/// p2 - p0) from the leaf block's corners, which are in cache (the mesh's arrays are not).
template <WideKernel K, bool AnyHit, bool Count = false, bool WindingNormal = false>
inline bool traverse_wide(const WideBvh& bvh, const Ray& ray, PrimitiveHit* hit,
                          [[maybe_unused]] TraversalCounts* counts = nullptr,
                          [[maybe_unused]] glm::vec3* normal = nullptr) {
    if (bvh.nodes.empty() || !is_traceable(ray)) return false;
    const typename K::NodeRay node_ray = K::prepare_nodes(ray);
    const typename K::TriRay tri_ray = K::prepare_triangles(ray);
    const float t_min = ray.t_min;
    float t_max = ray.t_max;
    const WideBvhNode* nodes = bvh.nodes.data();
    const TriangleBlock* blocks = bvh.blocks.data();

    WideStackEntry stack[kWideStackSize];
    std::uint32_t sp = 0;
    std::uint32_t current = 0;  // the root node
    std::uint32_t hit_block = 0, hit_lane = 0;
    float hit_u = 0.0f, hit_v = 0.0f;
    bool found = false;
    for (;;) {
        if (!WideBvhNode::is_leaf(current)) {
            const WideBvhNode& node = nodes[current];
            if constexpr (Count) ++counts->nodes;
            alignas(32) float t_enter[kWideBvhWidth];
            std::uint32_t mask = K::intersect_node(node, node_ray, t_min, t_max, t_enter);
            if (mask != 0) {
                const auto i0 = static_cast<std::uint32_t>(std::countr_zero(mask));
                mask &= mask - 1;
                if (mask == 0) {  // one child: go down without touching the stack
                    current = node.child[i0];
                    continue;
                }
                if constexpr (AnyHit) {
                    // Any hit: any hit ends the walk and t_max does not shrink before it, so
                    // the children go in slot order without their distances (as Embree's
                    // any-hit walk): ~6 % more nodes visited than nearest first, ~6 % fewer
                    // instructions, 1.03-1.04x the rays per second (docs/benchmarks.md).
                    do {
                        const auto i = static_cast<std::uint32_t>(std::countr_zero(mask));
                        mask &= mask - 1;
                        prefetch_child(nodes, blocks, node.child[i]);
                        if constexpr (Count) ++counts->pushes;
                        stack[sp++] = {node.child[i], t_min};
                    } while (mask != 0);
                    current = node.child[i0];
                    continue;
                }
                const auto i1 = static_cast<std::uint32_t>(std::countr_zero(mask));
                mask &= mask - 1;
                if (mask == 0) {  // two: defer the farther
                    const bool swap = t_enter[i1] < t_enter[i0];
                    const std::uint32_t near = swap ? i1 : i0, far = swap ? i0 : i1;
                    prefetch_child(nodes, blocks, node.child[far]);
                    if constexpr (Count) ++counts->pushes;
                    stack[sp++] = {node.child[far], t_enter[far]};
                    current = node.child[near];
                    continue;
                }
                // Three or more: push them all (prefetching each as it goes: a second loop
                // over the new entries cost ~18 instructions per incoherent ray),
                // insertion-sort the new entries so the nearest is on top, and take it.
                const std::uint32_t base = sp;
                prefetch_child(nodes, blocks, node.child[i0]);
                prefetch_child(nodes, blocks, node.child[i1]);
                stack[sp++] = {node.child[i0], t_enter[i0]};
                stack[sp++] = {node.child[i1], t_enter[i1]};
                do {
                    const auto i = static_cast<std::uint32_t>(std::countr_zero(mask));
                    mask &= mask - 1;
                    prefetch_child(nodes, blocks, node.child[i]);
                    stack[sp++] = {node.child[i], t_enter[i]};
                } while (mask != 0);
                if constexpr (Count) counts->pushes += sp - base - 1;  // one is taken at once
                for (std::uint32_t k = base + 1; k < sp; ++k) {
                    const WideStackEntry e = stack[k];
                    std::uint32_t j = k;
                    for (; j > base && stack[j - 1].t_enter < e.t_enter; --j)
                        stack[j] = stack[j - 1];
                    stack[j] = e;
                }
                current = stack[--sp].ref;
                continue;
            }
        } else {
            const std::uint32_t first = WideBvhNode::first_block(current);
            const std::uint32_t end = first + WideBvhNode::block_count(current);
            if constexpr (Count) ++counts->leaves;
#if LIBRT_ABLATION == 2
            // Measurement build: no leaf test (the node test and the walk alone).
            for (std::uint32_t b = end; b < end; ++b) {
#else
            for (std::uint32_t b = first; b < end; ++b) {
#endif
                if constexpr (Count) {
                    ++counts->blocks;
                    for (const std::uint32_t id : blocks[b].id)
                        counts->triangles += id != kInvalidId;
                }
                if constexpr (AnyHit) {
                    if (K::occluded_block(blocks[b], tri_ray, t_min, t_max)) return true;
                } else if (K::intersect_block(blocks[b], tri_ray, t_min, t_max, hit_lane, hit_u,
                                              hit_v)) {
                    hit_block = b;
                    found = true;
                }
            }
        }
        // Take the next deferred child the ray enters before the nearest hit so far.
        for (;;) {
            if (sp == 0) {
                if (found && hit) *hit = {t_max, hit_u, hit_v, blocks[hit_block].id[hit_lane]};
                if constexpr (WindingNormal) {
                    if (found) {
                        const Triangle tri = blocks[hit_block].triangle(hit_lane);
                        *normal = glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0);
                    }
                }
                return found;
            }
            const WideStackEntry& e = stack[--sp];
            if (AnyHit || e.t_enter <= t_max) {  // (any hit: nothing is nearer yet)
                current = e.ref;
                break;
            }
            if constexpr (Count) ++counts->culled;
        }
    }
}

/// Closest hit through kernel K: what every wide_<isa>.cpp's intersect entry returns.
template <WideKernel K>
inline PrimitiveHit intersect_wide(const WideBvh& bvh, const Ray& ray) {
    PrimitiveHit hit;
    traverse_wide<K, false>(bvh, ray, &hit);
    return hit;
}

/// Closest hit through kernel K and the hit triangle's winding normal (see traverse_wide):
/// what every wide_<isa>.cpp's intersect_normal entry returns.
template <WideKernel K>
inline PrimitiveHit intersect_normal_wide(const WideBvh& bvh, const Ray& ray, glm::vec3& normal) {
    PrimitiveHit hit;
    traverse_wide<K, false, false, true>(bvh, ray, &hit, nullptr, &normal);
    return hit;
}

/// Any hit through kernel K: what every wide_<isa>.cpp's occluded entry returns.
template <WideKernel K>
inline bool occluded_wide(const WideBvh& bvh, const Ray& ray) {
    return traverse_wide<K, true>(bvh, ray, nullptr);
}

}  // namespace librt::detail
