#pragma once

// Private: the light tree LightSampler chooses among many lights with (LightChoice::Bounded
// above LightSampler::kMaxBounded lights). The node layout can change without touching
// the API.

#include "light/light_bounds.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace librt::detail {

/// What every light below a tree node emits from and toward: a sphere around the emitting
/// points, their total power, and a cone of the directions light leaves in, written as
/// pbrt-v4's LightBounds is (a spread theta_o of the emitters' axes around `axis`, and the
/// spread theta_e of emission around each axis: pi/2 for a planar emitter, ~0 for a spot).
struct LightTreeBounds {
    glm::vec3 centre{0.0f};
    float radius = 0.0f;
    /// A box around the emitting points too: merged boxes stay tighter than merged spheres,
    /// so the test "wholly below the receiver's plane" uses it.
    glm::vec3 lo{0.0f}, hi{0.0f};
    float phi = 0.0f;
    glm::vec3 axis{0.0f, 0.0f, 1.0f};
    float theta_o = 0.0f;  ///< radians; >= pi: light leaves in every direction
    float theta_e = 0.0f;  ///< radians
    // cos and sin of theta_o and cos of theta_e, for importance(): set by finish_cone().
    float cos_o = -1.0f, sin_o = 0.0f, cos_e = 0.0f;
};

/// A binary tree over the finite lights of a scene (Conty Estevez & Kulla 2018, the tree
/// pbrt-v4's BVHLightSampler builds): a shading point walks from the root, at each node
/// choosing a child in proportion to a conservative bound of what the child's lights can
/// give it, so a light is chosen in O(depth) with a probability that follows distance,
/// orientation and power. Children that are single lights are weighed with the light's
/// own bound (importance() of light_bounds.h), the one the per-point choice of up to
/// LightSampler::kMaxBounded lights uses.
class LightTree {
public:
    /// A tree over `lights` (indices into `bounds`), each finite with phi > 0.
    LightTree(std::span<const LightBounds> bounds, std::span<const std::uint32_t> lights);

    /// The light chosen by u in [0, 1) for `at` and its probability within the tree; an
    /// invalid choice when every light below a node the walk reached is bounded by 0.
    struct Choice {
        std::uint32_t light;
        float pmf;
    };
    [[nodiscard]] Choice sample(float u, const LightChoicePoint& at) const;
    /// The probability that sample() chooses `light` for `at` (0 for a light not in the tree).
    [[nodiscard]] float pmf(std::uint32_t light, const LightChoicePoint& at) const;
    /// True when some light of the tree may give `at` something (the root's bound > 0).
    [[nodiscard]] bool reaches(const LightChoicePoint& at) const;

private:
    struct Node {
        LightTreeBounds bounds;
        /// Interior: index of the second child (the first is the next node). Leaf: the light.
        std::uint32_t index = 0;
        bool leaf = false;
    };
    /// The weight of node `n` at `at`: its light's importance() for a leaf; for an interior
    /// node the sum of its children's bounds (kLookahead levels down, light_tree.cpp).
    [[nodiscard]] float weight(const Node& n, const LightChoicePoint& at) const;
    /// Node `n`'s weight from the bounds `levels` levels below it (0: its own bound).
    [[nodiscard]] float weight_below(const Node& n, const LightChoicePoint& at, int levels) const;
    /// Builds the subtree over `lights` at `depth`, reached from the root by `trail`;
    /// returns its node index.
    std::uint32_t build(std::span<std::uint32_t> lights, int depth, std::uint64_t trail);

    std::vector<LightBounds> light_bounds_;  ///< every light's, indexed as the sampler's
    std::vector<LightTreeBounds> leaf_;      ///< during the build: each light's tree bounds
    std::vector<Node> nodes_;
    /// Per light (index into light_bounds_): the path from the root, bit d set when the walk
    /// takes the second child at depth d, and its length; depth 255 for a light not here.
    std::vector<std::uint64_t> trail_;
    std::vector<std::uint8_t> depth_;
};

/// A weight proportional to a conservative bound of what lights within `b` give `at`: 0 only
/// when none of them can give it anything (Conty Estevez & Kulla 2018, eq. 3, as pbrt-v4's
/// LightBounds::Importance).
[[nodiscard]] float importance(const LightTreeBounds& b, const LightChoicePoint& at);

}  // namespace librt::detail
