#pragma once

#include <librt/accel/bvh.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace librt {

/// Size and shape figures of a BVH, for apps, benchmarks and tests; the node layout itself
/// stays private. For a binary Bvh a node has two children, for TriangleBvh eight.
struct BvhStats {
    /// Interior nodes: a binary Bvh that is one leaf has none, a TriangleBvh always has its
    /// root.
    std::size_t node_count = 0;
    std::size_t leaf_count = 0;       ///< leaves
    std::uint32_t depth = 0;          ///< levels below the root
    std::uint32_t max_leaf_size = 0;  ///< most primitives in one leaf
    std::size_t bytes = 0;            ///< memory held by nodes, leaves and index arrays
    /// Expected interior-node visits of a ray through the root's box that is never culled,
    /// by the surface-area model: the sum of node area / root area (root included). Embree
    /// prints the same figure for its tree ("getAABBNodes : sah = ...", device config
    /// verbose=2), so the two trees compare before any ray is traced.
    double node_sah = 0.0;
    /// The same for leaves: the sum of leaf area x leaf cost / root area, the leaf cost
    /// being its blocks of four triangles for a TriangleBvh (Embree's "leaves : sah") and its
    /// primitives for a binary Bvh.
    double leaf_sah = 0.0;
};

/// What one query did, from TriangleBvh::count_traversal: trees and traversals compared by
/// work rather than by time (the machine's load does not change it).
struct TraversalCounts {
    std::uint64_t nodes = 0;      ///< interior nodes whose children's boxes were tested
    std::uint64_t leaves = 0;     ///< leaf children entered
    std::uint64_t blocks = 0;     ///< leaf blocks of four triangles tested
    std::uint64_t triangles = 0;  ///< triangles in those blocks (padding lanes not counted)
    std::uint64_t pushes = 0;     ///< children deferred on the stack
    std::uint64_t culled = 0;     ///< deferred children dropped as beyond the nearest hit

    /// Adds another query's counts.
    TraversalCounts& operator+=(const TraversalCounts& o) {
        nodes += o.nodes;
        leaves += o.leaves;
        blocks += o.blocks;
        triangles += o.triangles;
        pushes += o.pushes;
        culled += o.culled;
        return *this;
    }
};

/// The figures of a binary BVH, by one pass over its nodes.
[[nodiscard]] inline BvhStats bvh_stats(const Bvh& bvh) {
    BvhStats s;
    const float root_area = bvh.empty() ? 0.0f : bvh.nodes.front().bounds.surface_area();
    for (const BvhNode& n : bvh.nodes) {
        const double area = root_area > 0.0f ? n.bounds.surface_area() / root_area : 0.0;
        if (n.is_leaf()) {
            ++s.leaf_count;
            s.max_leaf_size = std::max(s.max_leaf_size, n.prim_count);
            s.leaf_sah += area * n.prim_count;
        } else {
            ++s.node_count;
            s.node_sah += area;
        }
    }
    s.depth = bvh.depth;
    s.bytes = bvh.memory_bytes();
    return s;
}

}  // namespace librt
