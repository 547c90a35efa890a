#include "integrator/guiding/quad_tree.h"

#include <librt/sampling/warp.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace librt::guiding {
namespace {

/// The largest float below 1: a rescaled u must stay in [0, 1).
constexpr float kBelowOne = 0x1.fffffep-1f;

/// p in [0, 1)^2 as 32-bit fixed point: the quadrant at each level is then the top bit of
/// each coordinate, and descending a level a shift (an integer chain of one cycle per
/// level, where p * 2 - q, clamped, was a chain of float operations). The same cells as
/// that float descent for the 20 levels a tree may have: p's 24-bit mantissa times 2^32
/// is exact for p >= 2^-8, and smaller p differ only below bit 32.
struct FixedPoint {
    std::uint32_t x, y;
    explicit FixedPoint(glm::vec2 p)
        : x(static_cast<std::uint32_t>(std::clamp(p.x, 0.0f, kBelowOne) * 4294967296.0f)),
          y(static_cast<std::uint32_t>(std::clamp(p.y, 0.0f, kBelowOne) * 4294967296.0f)) {}
    /// The quadrant at this level, then one level down.
    std::uint32_t descend() {
        const std::uint32_t q = (x >> 31u) | ((y >> 31u) << 1u);
        x <<= 1u;
        y <<= 1u;
        return q;
    }
};

/// A node's quadrant fractions of the total, for refined(): the real ones, or a leaf
/// cell's flux shared equally among four virtual children.
struct Fractions {
    std::array<float, 4> f{};
    std::array<std::uint32_t, 4> old_child{};  // 0 = none (a virtual node's quadrants)
};

void refine_node(const std::vector<QuadNode>& old, const Fractions& here, int level,
                 float threshold, int max_depth, std::size_t max_nodes, std::vector<QuadNode>& out,
                 std::uint32_t index) {
    for (std::uint32_t q = 0; q < 4; ++q) {
        if (!(here.f[q] > threshold) || level >= max_depth || out.size() >= max_nodes) continue;
        Fractions next;
        if (here.old_child[q] != 0) {
            const QuadNode& c = old[here.old_child[q]];
            const float sum = (c.flux[0] + c.flux[1]) + (c.flux[2] + c.flux[3]);
            for (std::uint32_t i = 0; i < 4; ++i) {
                // The child's cells as fractions of the whole tree's flux.
                next.f[i] = sum > 0.0f ? here.f[q] * (c.flux[i] / sum) : here.f[q] * 0.25f;
                next.old_child[i] = c.child[i];
            }
        } else {
            next.f.fill(here.f[q] * 0.25f);
        }
        const auto child = static_cast<std::uint32_t>(out.size());
        out.push_back(QuadNode{});
        out[index].child[q] = child;
        refine_node(old, next, level + 1, threshold, max_depth, max_nodes, out, child);
    }
}

}  // namespace

glm::vec2 direction_to_square(const glm::vec3& d) {
    // x = (cos theta + 1) / 2, y = phi / (2 pi) with phi in [0, 2 pi).
    const float cos_theta = std::clamp(d.z, -1.0f, 1.0f);
    float phi = std::atan2(d.y, d.x);
    if (phi < 0.0f) phi += 2.0f * kPi;
    const glm::vec2 p((cos_theta + 1.0f) * 0.5f, phi * (0.5f * kInvPi));
    return glm::clamp(p, glm::vec2(0.0f), glm::vec2(kBelowOne));
}

glm::vec3 square_to_direction(glm::vec2 p) {
    // cos theta = 2 x - 1, phi = 2 pi y (the inverse of direction_to_square).
    const float cos_theta = 2.0f * p.x - 1.0f;
    const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
    const float phi = 2.0f * kPi * p.y;
    return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

float QuadTree::pdf_square(glm::vec2 p) const {
    float pdf = 1.0f;
    std::uint32_t node = 0;
    FixedPoint f(p);
    for (;;) {
        const QuadNode& n = nodes_[node];
        const std::uint32_t q = f.descend();
        // A quadrant has a quarter of its node's area: density ratio 4 flux_q / sum.
        pdf *= 4.0f * n.share[q];
        if (n.child[q] == 0 || !(pdf > 0.0f)) return pdf;
        node = n.child[q];
    }
}

float QuadTree::pdf(const glm::vec3& d) const {
    return pdf_square(direction_to_square(d)) * (0.25f * kInvPi);
}

glm::vec2 QuadTree::sample_square(glm::vec2 u, float* pdf) const {
    float density = 1.0f;
    // u is not rescaled level by level (two dependent divisions per level): the interval
    // [lo, lo + w) of u-space that the cell chosen so far owns shrinks instead, by the
    // column's and the row's probabilities (multiplications only), and u is rescaled into
    // the last cell once. The same distribution: the cell holding u is chosen with
    // probability flux_q / sum at every level.
    glm::vec2 lo(0.0f), w(1.0f);
    glm::vec2 origin(0.0f);
    float size = 1.0f;
    std::uint32_t node = 0;
    for (;;) {
        const QuadNode& n = nodes_[node];
        // Column (x half) by its marginal share, then the row within it.
        const float p_left = n.share[0] + n.share[2];
        std::uint32_t qx = 0;
        const float split_x = lo.x + w.x * p_left;
        // Certain choices are made without comparing, so rounding never picks an empty half.
        if (p_left > 0.0f && (p_left >= 1.0f || u.x < split_x)) {
            w.x *= p_left;
        } else {
            qx = 1;
            w.x = lo.x + w.x - split_x;
            lo.x = split_x;
        }
        const float p_bottom = n.row[qx];
        std::uint32_t qy = 0;
        const float split_y = lo.y + w.y * p_bottom;
        if (p_bottom > 0.0f && (p_bottom >= 1.0f || u.y < split_y)) {
            w.y *= p_bottom;
        } else {
            qy = 1;
            w.y = lo.y + w.y - split_y;
            lo.y = split_y;
        }
        size *= 0.5f;
        origin += size * glm::vec2(float(qx), float(qy));
        const std::uint32_t q = qx + 2 * qy;
        // As pdf_square: a quadrant has a quarter of its node's area.
        density *= 4.0f * n.share[q];
        if (n.child[q] == 0) {
            if (pdf != nullptr) *pdf = density;
            // u's place in the cell's interval (rounding may put it a hair outside).
            const glm::vec2 t = glm::clamp((u - lo) / glm::max(w, glm::vec2(1e-30f)),
                                           glm::vec2(0.0f), glm::vec2(kBelowOne));
            return glm::min(origin + size * t, glm::vec2(kBelowOne));
        }
        node = n.child[q];
    }
}

std::uint32_t QuadTree::leaf_slot(glm::vec2 p) const {
    std::uint32_t node = 0;
    FixedPoint f(p);
    for (;;) {
        const std::uint32_t q = f.descend();
        if (nodes_[node].child[q] == 0) return 4 * node + q;
        node = nodes_[node].child[q];
    }
}

std::uint32_t QuadTree::leaf_slot(glm::vec2 p, float& size) const {
    std::uint32_t node = 0;
    size = 0.5f;
    FixedPoint f(p);
    for (;;) {
        const std::uint32_t q = f.descend();
        if (nodes_[node].child[q] == 0) return 4 * node + q;
        node = nodes_[node].child[q];
        size *= 0.5f;
    }
}

void QuadTree::set_leaf_flux(const std::vector<double>& flux) {
    // Children always come after their parent (refined() appends them depth first), so a
    // backward sweep sees every child's sums before its parent needs them.
    for (std::size_t i = nodes_.size(); i-- > 0;) {
        QuadNode& n = nodes_[i];
        for (std::uint32_t q = 0; q < 4; ++q) {
            if (n.child[q] == 0) {
                n.flux[q] = static_cast<float>(flux[4 * i + q]);
            } else {
                const QuadNode& c = nodes_[n.child[q]];
                n.flux[q] = (c.flux[0] + c.flux[1]) + (c.flux[2] + c.flux[3]);
            }
        }
        const float sum = (n.flux[0] + n.flux[1]) + (n.flux[2] + n.flux[3]);
        for (std::uint32_t q = 0; q < 4; ++q) n.share[q] = sum > 0.0f ? n.flux[q] / sum : 0.0f;
        // The bottom row's probability within each column (1/2 in an empty column, which
        // is never chosen).
        for (std::uint32_t qx = 0; qx < 2; ++qx) {
            const float column = n.flux[qx] + n.flux[qx + 2];
            n.row[qx] = column > 0.0f ? n.flux[qx] / column : 0.5f;
        }
    }
}

QuadTree QuadTree::refined(float threshold, int max_depth, std::size_t max_nodes) const {
    const float sum = total();
    QuadTree out;
    if (!(sum > 0.0f)) {
        out.nodes_ = nodes_;
        for (QuadNode& n : out.nodes_) {
            n.flux.fill(0.0f);
            n.share.fill(0.0f);
            n.row.fill(0.5f);
        }
        return out;
    }
    Fractions root;
    for (std::uint32_t q = 0; q < 4; ++q) {
        root.f[q] = nodes_[0].flux[q] / sum;
        root.old_child[q] = nodes_[0].child[q];
    }
    refine_node(nodes_, root, 1, threshold, max_depth, max_nodes, out.nodes_, 0);
    return out;
}

int QuadTree::depth() const {
    // Levels by a walk from the root (nodes are few: at most ~4 / threshold per level).
    std::vector<std::pair<std::uint32_t, int>> stack{{0u, 1}};
    int deepest = 1;
    while (!stack.empty()) {
        const auto [node, level] = stack.back();
        stack.pop_back();
        deepest = std::max(deepest, level);
        for (const std::uint32_t c : nodes_[node].child)
            if (c != 0) stack.emplace_back(c, level + 1);
    }
    return deepest;
}

}  // namespace librt::guiding
