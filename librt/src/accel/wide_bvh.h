#pragma once

// Private: the 8-wide node layout TriangleBvh traverses. Internal (never installed) so that
// the layout can change without touching the API; apps read its figures through BvhStats.

#include "core/large_page_allocator.h"

#include <librt/accel/bvh.h>
#include <librt/accel/bvh_stats.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/geometry/bbox.h>
#include <librt/geometry/hit.h>
#include <librt/geometry/triangle.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace librt::detail {

/// Children per wide node.
inline constexpr std::uint32_t kWideBvhWidth = 8;
/// Triangles per leaf block (tested together by one 4-lane SIMD test).
inline constexpr std::uint32_t kTriangleBlockSize = 4;
/// Most blocks one leaf child refers to; bigger leaves get a node of their own.
inline constexpr std::uint32_t kMaxLeafBlocks = 16;
/// Deepest wide tree collapse_to_wide produces: the binary tree's kMaxBvhDepth plus the
/// levels that split oversized leaves. Traversal stacks are sized by it.
inline constexpr std::uint32_t kMaxWideBvhDepth = kMaxBvhDepth + 16;

/// One node of an 8-wide BVH, 224 bytes (seven 32-byte rows, so AVX loads are aligned).
/// The children's boxes are stored as structure of arrays, so one instruction tests one
/// slab plane of all eight children:
///   bytes   0..191  bounds[plane][child] floats; planes lo.x, hi.x, lo.y, hi.y, lo.z, hi.z
///   bytes 192..223  child[8] references, see below
/// A child reference is
///   - an interior node: its index in WideBvh::nodes (bit 31 clear);
///   - a leaf: bit 31 set, bits 27..30 = block count - 1, bits 0..26 = first block in
///     WideBvh::blocks;
///   - unused: kEmptyChild, with an empty box (lo = +inf, hi = -inf) that no ray enters.
struct alignas(32) WideBvhNode {
    /// bounds[plane][i]: child i's box, one row per slab plane in the order lo.x, hi.x,
    /// lo.y, hi.y, lo.z, hi.z (see child_bounds()).
    float bounds[6][kWideBvhWidth];
    /// child[i]: child i's reference (node index, leaf or kEmptyChild, as above);
    /// collapse_to_wide puts the unused slots last.
    std::uint32_t child[kWideBvhWidth];

    /// Bit 31 of a reference: set for a leaf (and for kEmptyChild), clear for a node index.
    static constexpr std::uint32_t kLeafBit = 0x80000000u;
    /// The reference of an unused slot: all bits set (so is_leaf() is true); its box is
    /// empty, so traversal never reaches it.
    static constexpr std::uint32_t kEmptyChild = 0xffffffffu;
    /// Mask of bits 0..26 of a leaf reference (its first block), hence also the largest
    /// block index a leaf can start at.
    static constexpr std::uint32_t kMaxFirstBlock = (1u << 27) - 1;

    /// True for a leaf (or unused) reference.
    [[nodiscard]] static constexpr bool is_leaf(std::uint32_t ref) { return (ref & kLeafBit) != 0; }
    /// First block of a leaf reference.
    [[nodiscard]] static constexpr std::uint32_t first_block(std::uint32_t ref) {
        return ref & kMaxFirstBlock;
    }
    /// Number of blocks (1..kMaxLeafBlocks) of a leaf reference.
    [[nodiscard]] static constexpr std::uint32_t block_count(std::uint32_t ref) {
        return ((ref >> 27) & 15u) + 1;
    }
    /// The reference of a leaf of `count` blocks starting at block `first`.
    [[nodiscard]] static constexpr std::uint32_t make_leaf(std::uint32_t first,
                                                           std::uint32_t count) {
        return kLeafBit | ((count - 1) << 27) | first;
    }
    /// Child i's box.
    [[nodiscard]] BBox child_bounds(std::uint32_t i) const {
        return {{bounds[0][i], bounds[2][i], bounds[4][i]},
                {bounds[1][i], bounds[3][i], bounds[5][i]}};
    }
};
static_assert(sizeof(WideBvhNode) == 224, "WideBvhNode must stay 224 bytes");

/// Four triangles as structure of arrays, 160 bytes, tested together:
///   bytes   0..143  p[corner][axis][lane] floats: corners p0, p1, p2; axes x, y, z; 4 lanes
///   bytes 144..159  id[lane]: the caller's triangle index, kInvalidId for padding
/// Padding lanes have NaN corners, which the watertight test rejects.
struct alignas(16) TriangleBlock {
    /// p[corner][axis][lane]: coordinate `axis` (x, y, z) of corner p0, p1 or p2 of the
    /// triangle in `lane`; NaN in padding lanes.
    float p[3][3][kTriangleBlockSize];
    /// id[lane]: the caller's index of the triangle in `lane`; kInvalidId in padding lanes.
    std::uint32_t id[kTriangleBlockSize];

    /// The triangle in a lane.
    [[nodiscard]] Triangle triangle(std::uint32_t lane) const {
        return {{p[0][0][lane], p[0][1][lane], p[0][2][lane]},
                {p[1][0][lane], p[1][1][lane], p[1][2][lane]},
                {p[2][0][lane], p[2][1][lane], p[2][2][lane]}};
    }
};
static_assert(sizeof(TriangleBlock) == 160, "TriangleBlock must stay 160 bytes");

/// An 8-wide BVH over triangles as plain data, the layout TriangleBvh traverses. The root
/// is nodes[0] (a non-empty tree always has a root node, even over one triangle); leaves
/// hold copies of their triangles in blocks, in traversal order.
struct WideBvh {
    /// The wide nodes, root at nodes[0]; empty for an empty tree.
    std::vector<WideBvhNode, LargePageAllocator<WideBvhNode>> nodes;
    /// The leaves' triangle blocks; a leaf reference names a run of consecutive blocks.
    std::vector<TriangleBlock, LargePageAllocator<TriangleBlock>> blocks;
    BBox bounds;                     ///< of all triangles
    std::size_t triangle_count = 0;  ///< triangles held (padding lanes aside)
    std::uint32_t depth = 0;         ///< wide levels below the root, at most kMaxWideBvhDepth

    /// True for a tree over no triangles (no nodes).
    [[nodiscard]] bool empty() const { return nodes.empty(); }
    /// Bytes held by nodes and blocks.
    [[nodiscard]] std::size_t memory_bytes() const {
        return nodes.size() * sizeof(WideBvhNode) + blocks.size() * sizeof(TriangleBlock);
    }
};

/// Collapses a binary BVH over triangles into an 8-wide one: each wide node takes a
/// binary node's children and keeps opening the one with the largest surface area until
/// it has eight (the usual greedy collapse, as in Embree's and Ylitie et al.'s wide BVHs).
/// triangles[i] is primitive i of the binary BVH. Leaves larger than kMaxLeafBlocks
/// blocks (the median builder's degenerate leaves) are split into extra nodes. Slots a node
/// still has free then go to its leaves of two blocks, each split into two leaves of one
/// block (fewer block tests per ray, no more nodes).
/// boxes[i] is bounds(triangles[i]) (the builder's input, reused to plan those splits).
[[nodiscard]] WideBvh collapse_to_wide(const Bvh& bvh, std::span<const Triangle> triangles,
                                       std::span<const BBox> boxes);

/// Node, leaf and depth figures of a wide BVH, by one walk over its nodes.
[[nodiscard]] BvhStats wide_bvh_stats(const WideBvh& wide);

}  // namespace librt::detail

namespace librt {

/// The tree a TriangleBvh traverses, or null for an empty one: for the library's own code
/// and the structure tests, which see the private layout.
[[nodiscard]] inline const detail::WideBvh* wide_bvh_of(const TriangleBvh& bvh) {
    return bvh.tree_.get();
}

}  // namespace librt
