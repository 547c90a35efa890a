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
};

/// The figures of a binary BVH, by one pass over its nodes.
[[nodiscard]] inline BvhStats bvh_stats(const Bvh& bvh) {
    BvhStats s;
    for (const BvhNode& n : bvh.nodes) {
        if (n.is_leaf()) {
            ++s.leaf_count;
            s.max_leaf_size = std::max(s.max_leaf_size, n.prim_count);
        } else {
            ++s.node_count;
        }
    }
    s.depth = bvh.depth;
    s.bytes = bvh.memory_bytes();
    return s;
}

}  // namespace librt
