#pragma once

// The directional half of an SD-tree (Müller, Gross and Novák 2017, section 3.2): a
// quadtree over the unit square of the cylindrical map of the sphere, each cell holding
// the flux (integral of incident radiance) through it. It is a piecewise-constant density
// over directions: sample() descends choosing quadrants in proportion to their flux and
// pdf() multiplies the same ratios, so the two agree exactly.

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace librt::guiding {

/// The unit direction d on the unit square: ((cos theta + 1) / 2, phi / 2 pi) with theta
/// from +z. Lambert's cylindrical equal-area projection (Archimedes' hat-box theorem: the
/// sphere's area maps uniformly to the cylinder's), so a density on the square is 4 pi
/// times the density on the sphere.
[[nodiscard]] glm::vec2 direction_to_square(const glm::vec3& d);

/// The inverse of direction_to_square: p in [0, 1]^2 to a unit direction.
[[nodiscard]] glm::vec3 square_to_direction(glm::vec2 p);

/// One quadtree node: four quadrants, quadrant q = (x >= 1/2) + 2 (y >= 1/2) of the
/// node's square, each either a leaf cell or an inner node.
struct QuadNode {
    std::array<float, 4> flux{};  ///< flux through each quadrant (its subtree's sum)
    /// Each quadrant's share of the node's flux (0 when the node has none): set by
    /// set_leaf_flux, so pdf() multiplies instead of dividing at every level.
    std::array<float, 4> share{};
    /// The bottom quadrant's probability within each column, flux[qx] / (flux[qx] +
    /// flux[qx + 2]) (1/2 when the column is empty), for sample_square: set by
    /// set_leaf_flux. Two floats of padding make the node 64 bytes.
    std::array<float, 4> row{0.5f, 0.5f, 0.0f, 0.0f};
    std::array<std::uint32_t, 4> child{};  ///< node index of an inner quadrant; 0 = leaf cell
};

/// A directional quadtree: node 0 is the root (so 0 never names a child).
class QuadTree {
public:
    /// One node of four empty leaf cells.
    QuadTree() : nodes_(1) {}

    /// The flux through the whole sphere; 0 when nothing was recorded (no density).
    [[nodiscard]] float total() const {
        const auto& f = nodes_[0].flux;
        return (f[0] + f[1]) + (f[2] + f[3]);
    }

    /// Density on the unit square of point p (integrates to 1 over [0, 1]^2); 0 when total()
    /// is 0.
    [[nodiscard]] float pdf_square(glm::vec2 p) const;

    /// Solid-angle density of unit direction d: pdf_square / (4 pi), the equal-area map.
    [[nodiscard]] float pdf(const glm::vec3& d) const;

    /// A point of the unit square drawn with density pdf_square from u uniform in [0, 1)^2
    /// (continuous in u inside each cell, so stratified u stays stratified). Requires
    /// total() > 0. With `pdf`, also its pdf_square, from the same descent (a guided sample
    /// needs its density: this spares a second descent and the map's atan2).
    [[nodiscard]] glm::vec2 sample_square(glm::vec2 u, float* pdf = nullptr) const;

    /// A unit direction drawn with density pdf() (requires total() > 0).
    [[nodiscard]] glm::vec3 sample(glm::vec2 u) const {
        return square_to_direction(sample_square(u));
    }

    /// The leaf cell holding point p, as slot 4 * node + quadrant (see set_leaf_flux).
    [[nodiscard]] std::uint32_t leaf_slot(glm::vec2 p) const;

    /// leaf_slot(p), and in `size` the side of that cell (1/2 at the root's quadrants).
    [[nodiscard]] std::uint32_t leaf_slot(glm::vec2 p, float& size) const;

    /// Number of slots (4 per node); leaf cells own their slot, inner quadrants ignore it.
    [[nodiscard]] std::size_t slot_count() const { return nodes_.size() * 4; }

    /// Sets every leaf cell's flux to flux[slot] (values of inner quadrants' slots are
    /// ignored) and every inner quadrant's to the sum of its subtree.
    void set_leaf_flux(const std::vector<double>& flux);

    /// The same cells with zero flux, refined for the next pass (the paper's section 3.3):
    /// a cell holding more than `threshold` of total() is split into four (its flux shared
    /// equally among them, to decide on further splits), down to `max_depth` levels (the
    /// root is level 1); inner nodes holding less are merged into one leaf cell. No split
    /// is made once the tree has `max_nodes` nodes (depth first, so the same cells are
    /// split every time). With total() = 0 the cells are kept.
    [[nodiscard]] QuadTree refined(float threshold, int max_depth, std::size_t max_nodes) const;

    /// The nodes, root first.
    [[nodiscard]] const std::vector<QuadNode>& nodes() const { return nodes_; }

    /// Levels of the deepest cell (1: the root's four quadrants only).
    [[nodiscard]] int depth() const;

private:
    std::vector<QuadNode> nodes_;
};

}  // namespace librt::guiding
