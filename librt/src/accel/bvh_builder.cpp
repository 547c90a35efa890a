// The BVH builders' entry points, the input check and the median-split builder; the
// binned SAH builder is in bvh_sah_builder.cpp.

#include "accel/bvh_build_input.h"

#include <librt/accel/bvh_builder.h>
#include <librt/core/error.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

namespace librt {

namespace detail {

void check_build_sizes(std::span<const BBox> boxes, std::span<const glm::vec3> centers) {
    if (boxes.size() != centers.size())
        throw Error("BVH build: " + std::to_string(boxes.size()) + " boxes but " +
                    std::to_string(centers.size()) + " centres");
    if (boxes.size() >= std::numeric_limits<std::uint32_t>::max())
        throw Error("BVH build: too many primitives (" + std::to_string(boxes.size()) + ")");
}

void throw_bad_primitive(std::size_t i, const glm::vec3& c) {
    const bool finite = std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
    throw Error("BVH build: primitive " + std::to_string(i) +
                (finite ? " has a NaN box" : " has a non-finite centre"));
}

void check_build_input(std::span<const BBox> boxes, std::span<const glm::vec3> centers) {
    check_build_sizes(boxes, centers);
    for (std::size_t i = 0; i < centers.size(); ++i)
        if (!primitive_is_valid(boxes[i], centers[i])) throw_bad_primitive(i, centers[i]);
}

}  // namespace detail

namespace {

/// A node waiting to be split: its slot range [begin, end) and depth.
struct BuildTask {
    std::uint32_t node;
    std::uint32_t begin;
    std::uint32_t end;
    std::uint32_t depth;
};

BBox range_bounds(std::span<const BBox> boxes, const std::vector<std::uint32_t>& ids,
                  std::uint32_t begin, std::uint32_t end) {
    BBox b;
    for (std::uint32_t i = begin; i < end; ++i) b.extend(boxes[ids[i]]);
    return b;
}

/// Shared skeleton of both builders: a work stack of nodes; `choose_split` returns the
/// slot where the range is partitioned (begin or end meaning "make a leaf").
template <class ChooseSplit>
Bvh build_top_down(std::span<const BBox> boxes, ChooseSplit&& choose_split) {
    Bvh bvh;
    const auto count = static_cast<std::uint32_t>(boxes.size());
    if (count == 0) return bvh;
    bvh.prim_indices.resize(count);
    std::iota(bvh.prim_indices.begin(), bvh.prim_indices.end(), 0u);
    bvh.nodes.reserve(2 * std::size_t{count});
    bvh.nodes.push_back({range_bounds(boxes, bvh.prim_indices, 0, count), 0, 0});

    std::vector<BuildTask> tasks{{0, 0, count, 0}};
    while (!tasks.empty()) {
        const BuildTask task = tasks.back();
        tasks.pop_back();
        bvh.depth = std::max(bvh.depth, task.depth);
        const BBox node_bounds = bvh.nodes[task.node].bounds;
        std::uint32_t mid = task.begin;
        if (task.depth < kMaxBvhDepth)
            mid = choose_split(bvh.prim_indices, task.begin, task.end, node_bounds);
        if (mid <= task.begin || mid >= task.end) {
            bvh.nodes[task.node].index = task.begin;
            bvh.nodes[task.node].prim_count = task.end - task.begin;
            continue;
        }
        const auto left = static_cast<std::uint32_t>(bvh.nodes.size());
        bvh.nodes[task.node].index = left;
        bvh.nodes[task.node].prim_count = 0;
        bvh.nodes.push_back({range_bounds(boxes, bvh.prim_indices, task.begin, mid), 0, 0});
        bvh.nodes.push_back({range_bounds(boxes, bvh.prim_indices, mid, task.end), 0, 0});
        tasks.push_back({left, task.begin, mid, task.depth + 1});
        tasks.push_back({left + 1, mid, task.end, task.depth + 1});
    }
    bvh.nodes.shrink_to_fit();
    return bvh;
}

}  // namespace

Bvh build_median_bvh(std::span<const BBox> boxes, std::span<const glm::vec3> centers,
                     const MedianSplitConfig& config) {
    detail::check_build_input(boxes, centers);
    const std::uint32_t max_leaf = std::max(config.max_leaf_size, 1u);
    return build_top_down(boxes, [&](std::vector<std::uint32_t>& ids, std::uint32_t begin,
                                     std::uint32_t end, const BBox& node_bounds) {
        if (end - begin <= max_leaf) return begin;
        // The report's plane: the middle of the node box's longest side.
        const int axis = node_bounds.largest_axis();
        const float split = node_bounds.center()[axis];
        const auto it = std::partition(ids.begin() + begin, ids.begin() + end,
                                       [&](std::uint32_t id) { return centers[id][axis] < split; });
        return static_cast<std::uint32_t>(it - ids.begin());
    });
}

Bvh build_bvh(BvhBuilder builder, std::span<const BBox> boxes, std::span<const glm::vec3> centers) {
    return builder == BvhBuilder::Median ? build_median_bvh(boxes, centers)
                                         : build_sah_bvh(boxes, centers);
}

}  // namespace librt
