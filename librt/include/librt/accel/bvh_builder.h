#pragma once

#include <librt/accel/bvh.h>
#include <librt/export.h>
#include <librt/geometry/bbox.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>

namespace librt {

/// The report's builder: split the node's box at its centre along its longest axis,
/// primitives going left or right by centroid; stop at max_leaf_size primitives or
/// when every centroid falls on one side.
struct MedianSplitConfig {
    std::uint32_t max_leaf_size = 5;  ///< the report's "fin - debut > 5"
};

/// Binned surface area heuristic (Wald 2007): for each axis, centroids are binned and
/// the split minimising traversal_cost + (A_L B(N_L) + A_R B(N_R)) / A * intersection_cost
/// is taken when it beats a leaf's intersection_cost * B(N), where B(n) = ceil(n / leaf_block_size)
/// counts the SIMD blocks a leaf of n primitives is tested in (Embree's block SAH; B(n) = n
/// for blocks of one). Subtrees are built in parallel; the tree does not depend on the
/// number of threads.
struct SahConfig {
    std::uint32_t bin_count = 32;     ///< bins per axis for large nodes (fewer for small ones)
    std::uint32_t max_leaf_size = 8;  ///< larger nodes are always split
    float traversal_cost = 1.0f;      ///< cost of visiting a node, relative to...
    float intersection_cost = 1.0f;   ///< ...the cost of testing one block of primitives
    std::uint32_t leaf_block_size =
        1;                           ///< primitives tested together in a leaf (4 for TriangleBvh)
    std::uint32_t thread_count = 0;  ///< build threads; 0 = std::thread::hardware_concurrency()
};

/// Which builder a caller wants.
enum class BvhBuilder { Median, Sah };

// Both builders throw librt::Error naming the primitive when boxes and centers differ in
// length, a centre is not finite or a box has a NaN corner; the tree is never deeper
// than kMaxBvhDepth (a node at that depth becomes a leaf, however many primitives it has).

/// Builds with the report's median split. boxes[i] and centers[i] describe primitive i.
[[nodiscard]] LIBRT_API Bvh build_median_bvh(std::span<const BBox> boxes,
                                             std::span<const glm::vec3> centers,
                                             const MedianSplitConfig& config = {});

/// Builds with binned SAH. boxes[i] and centers[i] describe primitive i.
[[nodiscard]] LIBRT_API Bvh build_sah_bvh(std::span<const BBox> boxes,
                                          std::span<const glm::vec3> centers,
                                          const SahConfig& config = {});

/// Builds with the chosen builder and its default settings.
[[nodiscard]] LIBRT_API Bvh build_bvh(BvhBuilder builder, std::span<const BBox> boxes,
                                      std::span<const glm::vec3> centers);

}  // namespace librt
