#pragma once

// Private: the ray-stream traversal of the wide BVH (TriangleBvh's span queries). A single
// incoherent ray's walk is a chain of dependent steps (load a node, test its boxes, pick a
// child, load it) whose latencies the out-of-order core cannot hide, because the next step
// needs the last one's result (docs/benchmarks.md, "Where the time goes, timed"). Here
// kStreamLanes rays are walked at once, one node or leaf visit of each in turn, so the
// core has independent chains to overlap. Each ray makes exactly the decisions of
// traverse_wide (wide_traversal.h): the same nodes in the same order, the same leaf tests,
// so the same hit bit for bit. Like that template it is baseline code that only calls the
// kernel policy; each wide_<isa>.cpp instantiates it in flatten entry points.

#include "wide_traversal.h"

#include <cstddef>
#include <cstdint>

namespace librt::detail {

/// Rays walked at once by the stream traversal: 8 gained 13-18 % over single rays on the
/// dragon and the 1M-triangle teapot (trees beyond the caches), 4 lanes 12-16 %, 2 lanes
/// 7-10 % (docs/benchmarks.md, "Ray streams"). Each lane's stack takes ~4.5 KB, so the walk
/// takes ~37 KB of the caller's stack.
inline constexpr std::uint32_t kStreamLanes = 8;

/// One ray's walk in progress: what traverse_wide keeps in locals.
template <WideKernel K>
struct StreamLane {
    typename K::NodeRay node_ray;
    typename K::TriRay tri_ray;
    float t_min = 0.0f, t_max = 0.0f;
    float hit_u = 0.0f, hit_v = 0.0f;
    std::uint32_t current = 0, sp = 0;
    std::uint32_t hit_block = 0, hit_lane = 0;
    bool found = false;
    std::size_t index = 0;  ///< the ray's position in the stream
    WideStackEntry stack[kWideStackSize];
};

/// Starts `lane` on `ray` (traceable, and accepted by the kernel) at the root.
template <WideKernel K>
inline void start_lane(StreamLane<K>& lane, const Ray& ray, std::size_t index) {
    lane.node_ray = K::prepare_nodes(ray);
    lane.tri_ray = K::prepare_triangles(ray);
    lane.t_min = ray.t_min;
    lane.t_max = ray.t_max;
    lane.current = 0;
    lane.sp = 0;
    lane.found = false;
    lane.index = index;
}

/// One visit of `lane`'s current node or leaf, then (if the walk does not go down from it)
/// the next deferred child as traverse_wide takes it. Returns true when the ray's walk is
/// over (its stack empty, or with AnyHit a hit found). The body is traverse_wide's loop body
/// with `continue` turned into a return.
template <WideKernel K, bool AnyHit>
inline bool step_lane(StreamLane<K>& lane, const WideBvhNode* nodes, const TriangleBlock* blocks) {
    const std::uint32_t current = lane.current;
    if (!WideBvhNode::is_leaf(current)) {
        const WideBvhNode& node = nodes[current];
        alignas(32) float t_enter[kWideBvhWidth];
        std::uint32_t mask =
            K::intersect_node(node, lane.node_ray, lane.t_min, lane.t_max, t_enter);
        if (mask != 0) {
            const auto i0 = static_cast<std::uint32_t>(std::countr_zero(mask));
            mask &= mask - 1;
            if (mask == 0) {
                lane.current = node.child[i0];
                return false;
            }
            WideStackEntry* stack = lane.stack;
            std::uint32_t sp = lane.sp;
            if constexpr (AnyHit) {
                do {
                    const auto i = static_cast<std::uint32_t>(std::countr_zero(mask));
                    mask &= mask - 1;
                    prefetch_child(nodes, blocks, node.child[i]);
                    stack[sp++] = {node.child[i], lane.t_min};
                } while (mask != 0);
                lane.sp = sp;
                lane.current = node.child[i0];
                return false;
            }
            const auto i1 = static_cast<std::uint32_t>(std::countr_zero(mask));
            mask &= mask - 1;
            if (mask == 0) {
                const bool swap = t_enter[i1] < t_enter[i0];
                const std::uint32_t near = swap ? i1 : i0, far = swap ? i0 : i1;
                prefetch_child(nodes, blocks, node.child[far]);
                stack[sp++] = {node.child[far], t_enter[far]};
                lane.sp = sp;
                lane.current = node.child[near];
                return false;
            }
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
            for (std::uint32_t k = base + 1; k < sp; ++k) {
                const WideStackEntry e = stack[k];
                std::uint32_t j = k;
                for (; j > base && stack[j - 1].t_enter < e.t_enter; --j) stack[j] = stack[j - 1];
                stack[j] = e;
            }
            lane.current = stack[--sp].ref;
            lane.sp = sp;
            return false;
        }
    } else {
        const std::uint32_t first = WideBvhNode::first_block(current);
        const std::uint32_t end = first + WideBvhNode::block_count(current);
        for (std::uint32_t b = first; b < end; ++b) {
            if constexpr (AnyHit) {
                if (K::occluded_block(blocks[b], lane.tri_ray, lane.t_min, lane.t_max)) {
                    lane.found = true;
                    return true;
                }
            } else if (K::intersect_block(blocks[b], lane.tri_ray, lane.t_min, lane.t_max,
                                          lane.hit_lane, lane.hit_u, lane.hit_v)) {
                lane.hit_block = b;
                lane.found = true;
            }
        }
    }
    // The next deferred child the ray enters before the nearest hit so far.
    std::uint32_t sp = lane.sp;
    while (sp != 0) {
        const WideStackEntry& e = lane.stack[--sp];
        if (AnyHit || e.t_enter <= lane.t_max) {
            lane.current = e.ref;
            lane.sp = sp;
            return false;
        }
    }
    lane.sp = 0;
    return true;
}

/// The stream traversal through kernel K: for every i < count, out[i] = the single-ray
/// query's answer for rays[i] (closest hit: a PrimitiveHit; AnyHit: 1 when occluded, else
/// 0). A traceable ray that `accept` refuses (a kernel's range limit) is answered by
/// `single(ray)`, the single-ray query of another kernel; an untraceable one misses.
template <WideKernel K, bool AnyHit, std::uint32_t Lanes = kStreamLanes, class Out, class Accept,
          class Single>
inline void traverse_wide_stream(const WideBvh& bvh, const Ray* rays, Out* out, std::size_t count,
                                 Accept&& accept, Single&& single) {
    auto miss = [&](std::size_t i) {
        if constexpr (AnyHit)
            out[i] = 0;
        else
            out[i] = PrimitiveHit{};
    };
    if (bvh.nodes.empty()) {
        for (std::size_t i = 0; i < count; ++i) miss(i);
        return;
    }
    const WideBvhNode* nodes = bvh.nodes.data();
    const TriangleBlock* blocks = bvh.blocks.data();
    std::size_t next = 0;
    // Starts `lane` on the next ray that needs a walk, answering the others on the way;
    // false when the stream is exhausted.
    auto refill = [&](StreamLane<K>& lane) {
        while (next < count) {
            const std::size_t i = next++;
            const Ray& ray = rays[i];
            if (!is_traceable(ray)) [[unlikely]] {
                miss(i);
            } else if (!accept(ray)) [[unlikely]] {
                out[i] = single(ray);
            } else {
                start_lane<K>(lane, ray, i);
                return true;
            }
        }
        return false;
    };
    auto finish = [&](const StreamLane<K>& lane) {
        if constexpr (AnyHit) {
            out[lane.index] = lane.found ? 1 : 0;
        } else if (lane.found) {
            out[lane.index] = {lane.t_max, lane.hit_u, lane.hit_v,
                               blocks[lane.hit_block].id[lane.hit_lane]};
        } else {
            out[lane.index] = PrimitiveHit{};
        }
    };
    StreamLane<K> lanes[Lanes];
    bool live[Lanes];
    std::uint32_t live_count = 0;
    for (std::uint32_t k = 0; k < Lanes; ++k) live_count += live[k] = refill(lanes[k]);
    while (live_count == Lanes) {
        // Every lane busy: advance each by one visit (the common case, no liveness tests).
        for (std::uint32_t k = 0; k < Lanes; ++k) {
            if (step_lane<K, AnyHit>(lanes[k], nodes, blocks)) {
                finish(lanes[k]);
                if (!refill(lanes[k])) {
                    live[k] = false;
                    --live_count;
                }
            }
        }
    }
    // The stream's tail: the lanes still walking, each to its end.
    for (std::uint32_t k = 0; k < Lanes; ++k) {
        if (!live[k]) continue;
        while (!step_lane<K, AnyHit>(lanes[k], nodes, blocks)) {
        }
        finish(lanes[k]);
    }
}

}  // namespace librt::detail
