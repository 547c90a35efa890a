#pragma once

#include <librt/geometry/bbox.h>

#include <cstdint>
#include <vector>

namespace librt {

/// Deepest tree the builders produce; traversal stacks are sized by it, so they
/// cannot overflow (the builders turn a node at this depth into a leaf).
inline constexpr std::uint32_t kMaxBvhDepth = 64;

/// One node of a flattened binary BVH, 32 bytes so two share a cache line:
///   bytes  0..23  bounds (lo.xyz, hi.xyz as floats)
///   bytes 24..27  index: first slot in Bvh::prim_indices (leaf) or left child (interior)
///   bytes 28..31  prim_count: number of primitives (leaf) or 0 (interior)
/// The right child of an interior node is always left + 1.
struct BvhNode {
    BBox bounds;                   ///< box around everything below the node
    std::uint32_t index = 0;       ///< leaf: first slot in Bvh::prim_indices; interior: left child
    std::uint32_t prim_count = 0;  ///< leaf: number of slots (at least 1); interior: 0

    /// True for a leaf (prim_count != 0).
    [[nodiscard]] bool is_leaf() const { return prim_count != 0; }
};
static_assert(sizeof(BvhNode) == 32, "BvhNode must stay 32 bytes");

/// A bounding volume hierarchy as plain data. It knows boxes only: leaves hold
/// slots, and slot i stands for the caller's primitive prim_indices[i]. The root is
/// nodes[0]; an empty BVH has no nodes.
struct Bvh {
    std::vector<BvhNode> nodes;               ///< root first; siblings are adjacent
    std::vector<std::uint32_t> prim_indices;  ///< per slot, the caller's primitive index
    std::uint32_t depth = 0;                  ///< levels below the root, at most kMaxBvhDepth

    /// True when the BVH has no nodes (built over no primitives).
    [[nodiscard]] bool empty() const { return nodes.empty(); }
    /// The root's box, or an empty box for an empty BVH.
    [[nodiscard]] BBox bounds() const { return nodes.empty() ? BBox{} : nodes.front().bounds; }
    /// Bytes held by nodes and index array.
    [[nodiscard]] std::size_t memory_bytes() const {
        return nodes.size() * sizeof(BvhNode) + prim_indices.size() * sizeof(std::uint32_t);
    }
};

}  // namespace librt
