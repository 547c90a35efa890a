#pragma once

// The SD-tree of practical path guiding (Müller, Gross and Novák 2017, section 3): a
// binary tree over the scene's bounds, halved along x, y, z in turn, whose leaves each
// hold a directional quadtree. Training runs in passes: during pass k the paths sample
// from what pass k - 1 learned (`sampling`) and record into a second quadtree
// (`recording`); end_pass(k) turns the records into the next `sampling` and refines
// both trees.
//
// Recording is thread-safe and deterministic: a record adds a fixed-point integer to an
// atomic counter, and integer addition does not depend on the order, so the learned tree
// (and hence a guided image) is bit-identical for any thread count, tile size and tile
// order. Floating-point sums would differ in their last bits with the order threads
// happen to record in.

#include "integrator/guiding/quad_tree.h"

#include <librt/geometry/bbox.h>
#include <librt/integrator/guiding.h>

#include <glm/vec3.hpp>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace librt::guiding {

/// Throws librt::Error naming the first parameter of `settings` out of its range.
void validate(const GuidingSettings& settings);

/// A spatial leaf: its learned distribution and the counters of the pass running.
struct DirLeaf {
    QuadTree sampling;   ///< what the current pass samples from (frozen during a pass)
    QuadTree recording;  ///< the cells this pass records into (their flux is not used)
    /// Fixed-point flux per slot of `recording` (QuadTree::leaf_slot).
    std::unique_ptr<std::atomic<std::uint64_t>[]> flux;
    mutable std::atomic<std::uint64_t> vertices{0};  ///< path vertices recorded this pass

    /// Empty counters for `recording`'s cells.
    void reset_counters();
};

/// The SD-tree.
class SdTree {
public:
    /// A single leaf over `bounds` (made a cube, so halving along x, y, z in turn keeps
    /// cells near cubes), with empty distributions: nothing is guided before end_pass(0).
    /// The first pass also records the box of the path vertices, and end_pass(0) shrinks
    /// the cube to it: scenes whose bounds are mostly empty (the report's rooms are
    /// spheres of radius ~1000 around a room of ~100 units) would otherwise spend a dozen
    /// levels of the spatial tree before one split falls inside the room.
    SdTree(const BBox& bounds, const GuidingSettings& settings);

    /// The leaf whose cell holds p (points outside the bounds go to the nearest cell).
    [[nodiscard]] const DirLeaf& leaf_at(const glm::vec3& p) const;

    /// Records a path vertex at `p` in `leaf` whose direction `dir` (unit, world) got the
    /// flux estimate `flux` (incident radiance / the density it was sampled with).
    /// With filter_records the record goes to the leaf and cell at a jittered point
    /// instead (stochastic box filter; `leaf` is then not used). Thread-safe.
    void record(const DirLeaf& leaf, const glm::vec3& p, const glm::vec3& dir, float flux) const;

    /// Ends training pass `pass` (which rendered 2^pass samples per pixel): leaves that
    /// recorded more than c sqrt(2^pass) vertices are halved (children copy the learned
    /// quadtree), every leaf's records become its sampling distribution, and the recording
    /// quadtrees are refined by flux and emptied.
    void end_pass(int pass);

    /// Number of spatial leaves.
    [[nodiscard]] std::size_t leaf_count() const { return leaves_.size(); }

    /// Leaf i (for tests and statistics).
    [[nodiscard]] const DirLeaf& leaf(std::size_t i) const { return *leaves_[i]; }

private:
    /// The leaf whose cell holds p, and in `size` that cell's extent.
    [[nodiscard]] const DirLeaf& locate(const glm::vec3& p, glm::vec3& size) const;

    struct Node {
        std::uint32_t children = 0;  // index of the first of two children; 0 = a leaf
        std::uint32_t leaf = 0;      // index into leaves_ when a leaf
    };

    GuidingSettings settings_;
    glm::vec3 lo_{0.0f};
    float size_ = 1.0f;  // the cube's side
    std::vector<Node> nodes_;
    std::vector<std::unique_ptr<DirLeaf>> leaves_;
    double scale_ = 0.0;  // fixed-point units per unit of flux in the pass running
    // The box of the vertices recorded before the first end_pass (min and max are
    // order-independent, so the fitted cube is deterministic too).
    mutable std::atomic<float> seen_lo_[3];
    mutable std::atomic<float> seen_hi_[3];
    bool fitting_ = true;
};

}  // namespace librt::guiding
