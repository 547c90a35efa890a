#include "integrator/guiding/sd_tree.h"

#include <librt/core/error.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <string>

namespace librt::guiding {
namespace {

/// Most spatial leaves, and most recording quadtree nodes over all leaves: they bound the
/// memory whatever spatial_threshold and flux_threshold say. A node costs 160 bytes (64 in
/// the sampling tree, 64 in the recording tree, 4 x 8 of counters), so 2^22 nodes are
/// 640 MiB at worst. The paper's settings stay far below: ~1000 leaves of a few hundred
/// nodes on a 1280 x 720 image.
constexpr std::size_t kMaxLeaves = std::size_t{1} << 15u;
constexpr std::size_t kMaxTotalNodes = std::size_t{1} << 22u;
/// Deepest spatial level: far below float's resolution of any scene's bounds.
constexpr std::uint32_t kMaxSpatialDepth = 60;
/// Fixed point: the previous pass's mean record maps to 2^24 units, and a record is
/// clamped to 2^44 (2^20 times that mean), so 2^20 such records still fit in 64 bits.
/// Clamping changes only what is learned, never the image's expectation.
constexpr int kMeanBits = 24;
constexpr double kMaxUnits = 17592186044416.0;  // 2^44
/// The largest float below 1.
constexpr float kBelowOneF = 0x1.fffffep-1f;

/// splitmix64's finaliser (Steele et al. 2014): a bijective 64-bit mix.
std::uint64_t mix_bits(std::uint64_t z) {
    z = (z ^ (z >> 30u)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27u)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31u);
}

/// A hash of a record's position and direction bits.
std::uint64_t hash_record(const glm::vec3& p, const glm::vec3& d) {
    std::uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (const float f : {p.x, p.y, p.z, d.x, d.y, d.z})
        h = mix_bits(h ^ std::bit_cast<std::uint32_t>(f));
    return h;
}

/// The low 21 bits of h as a float in [0, 1).
float unit_float(std::uint64_t h) { return float(h & 0x1fffffu) * 0x1p-21f; }

}  // namespace

void validate(const GuidingSettings& g) {
    if (g.training_passes < 1 || g.training_passes > 20)
        throw Error("guiding.training_passes = " + std::to_string(g.training_passes) +
                    ": must be in [1, 20]");
    if (g.max_quadtree_depth < 1 || g.max_quadtree_depth > 20)
        throw Error("guiding.max_quadtree_depth = " + std::to_string(g.max_quadtree_depth) +
                    ": must be in [1, 20]");
    if (!(g.bsdf_fraction > 0.0f && g.bsdf_fraction <= 1.0f))
        throw Error("guiding.bsdf_fraction = " + std::to_string(g.bsdf_fraction) +
                    ": must be in (0, 1]");
    if (!(g.flux_threshold > 0.0f && g.flux_threshold < 1.0f))
        throw Error("guiding.flux_threshold = " + std::to_string(g.flux_threshold) +
                    ": must be in (0, 1)");
    if (g.spatial_threshold < 1 || g.spatial_threshold > (1u << 30u))
        throw Error("guiding.spatial_threshold = " + std::to_string(g.spatial_threshold) +
                    ": must be in [1, 2^30]");
}

void DirLeaf::reset_counters() {
    const std::size_t n = recording.slot_count();
    flux = std::make_unique<std::atomic<std::uint64_t>[]>(n);
    for (std::size_t i = 0; i < n; ++i) flux[i].store(0, std::memory_order_relaxed);
    vertices.store(0, std::memory_order_relaxed);
}

SdTree::SdTree(const BBox& bounds, const GuidingSettings& settings)
    : settings_(settings), scale_(std::ldexp(1.0, kMeanBits)) {
    // A cube around the bounds, a little larger so that points on the boundary are inside;
    // an empty or non-finite scene gets a unit cube (every point still finds a leaf).
    const glm::vec3 extent = bounds.hi - bounds.lo;
    if (!bounds.empty() && std::isfinite(extent.x) && std::isfinite(extent.y) &&
        std::isfinite(extent.z)) {
        size_ = std::max({extent.x, extent.y, extent.z, 1e-6f}) * 1.001f;
        lo_ = 0.5f * (bounds.lo + bounds.hi) - glm::vec3(0.5f * size_);
    } else {
        size_ = 1.0f;
        lo_ = glm::vec3(-0.5f);
    }
    for (int a = 0; a < 3; ++a) {
        seen_lo_[a].store(std::numeric_limits<float>::infinity(), std::memory_order_relaxed);
        seen_hi_[a].store(-std::numeric_limits<float>::infinity(), std::memory_order_relaxed);
    }
    nodes_.push_back(Node{});
    leaves_.push_back(std::make_unique<DirLeaf>());
    leaves_.back()->reset_counters();
}

const DirLeaf& SdTree::leaf_at(const glm::vec3& p) const {
    glm::vec3 size;
    return locate(p, size);
}

const DirLeaf& SdTree::locate(const glm::vec3& p, glm::vec3& size) const {
    // Descend halving along x, y, z in turn; p's coordinates are compared with the cell's
    // midpoint, so points outside the cube follow the nearest side.
    glm::vec3 lo = lo_;
    size = glm::vec3(size_);
    std::uint32_t node = 0;
    for (int axis = 0;; axis = axis == 2 ? 0 : axis + 1) {
        const Node& n = nodes_[node];
        if (n.children == 0) return *leaves_[n.leaf];
        size[axis] *= 0.5f;
        const float mid = lo[axis] + size[axis];
        if (p[axis] < mid) {
            node = n.children;
        } else {
            lo[axis] = mid;
            node = n.children + 1;
        }
    }
}

void SdTree::record(const DirLeaf& leaf, const glm::vec3& p, const glm::vec3& dir,
                    float flux) const {
    // Stochastic box filter (Müller 2019, "Practical Path Guiding in Production"): the
    // record moves uniformly within a box of its leaf's size around it, then within its
    // directional cell. The numbers hash the record itself, so where it lands does not
    // depend on threads.
    const DirLeaf* target = &leaf;
    std::uint64_t h = 0;
    if (settings_.filter_records) {
        glm::vec3 size;
        (void)locate(p, size);
        h = hash_record(p, dir);
        const glm::vec3 jitter(unit_float(h), unit_float(h >> 21u), unit_float(h >> 42u));
        target = &locate(p + (jitter - 0.5f) * size, size);
    }
    target->vertices.fetch_add(1, std::memory_order_relaxed);
    if (fitting_) {
        for (int a = 0; a < 3; ++a) {
            if (!std::isfinite(p[a])) continue;
            float lo = seen_lo_[a].load(std::memory_order_relaxed);
            while (p[a] < lo && !seen_lo_[a].compare_exchange_weak(lo, p[a])) {
            }
            float hi = seen_hi_[a].load(std::memory_order_relaxed);
            while (p[a] > hi && !seen_hi_[a].compare_exchange_weak(hi, p[a])) {
            }
        }
    }
    if (!(flux > 0.0f) || !std::isfinite(flux)) return;
    const double units = std::min(double(flux) * scale_, kMaxUnits);
    const auto q = static_cast<std::uint64_t>(std::llround(units));
    if (q == 0) return;
    glm::vec2 square = direction_to_square(dir);
    if (settings_.filter_records) {
        h = mix_bits(h ^ 0x51ed);
        float cell = 0.0f;
        (void)target->recording.leaf_slot(square, cell);
        // x (cos theta) clamps at the poles; y (phi) wraps around.
        square.x = std::clamp(square.x + (unit_float(h) - 0.5f) * cell, 0.0f, kBelowOneF);
        square.y += (unit_float(h >> 32u) - 0.5f) * cell;
        square.y = std::clamp(square.y - std::floor(square.y), 0.0f, kBelowOneF);
    }
    target->flux[target->recording.leaf_slot(square)].fetch_add(q, std::memory_order_relaxed);
}

void SdTree::end_pass(int pass) {
    // What each leaf recorded, as quadtrees with flux (in the units of the flux recorded).
    std::vector<QuadTree> learned;
    std::vector<double> counts;
    learned.reserve(leaves_.size());
    counts.reserve(leaves_.size());
    double total_flux = 0.0, total_vertices = 0.0;
    for (const auto& leaf : leaves_) {
        std::vector<double> flux(leaf->recording.slot_count());
        for (std::size_t s = 0; s < flux.size(); ++s) {
            flux[s] = double(leaf->flux[s].load(std::memory_order_relaxed)) / scale_;
            total_flux += flux[s];
        }
        learned.push_back(leaf->recording);
        learned.back().set_leaf_flux(flux);
        counts.push_back(double(leaf->vertices.load(std::memory_order_relaxed)));
        total_vertices += counts.back();
    }

    if (fitting_) {
        fitting_ = false;
        // Shrink the cube to the vertices' box (only the root leaf exists yet, and its
        // records do not depend on the cube), keeping it when the box is not smaller.
        glm::vec3 lo, hi;
        for (int a = 0; a < 3; ++a) {
            lo[a] = seen_lo_[a].load();
            hi[a] = seen_hi_[a].load();
        }
        if (nodes_.size() == 1 && lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z) {
            const glm::vec3 extent = hi - lo;
            const float size = std::max({extent.x, extent.y, extent.z, 1e-6f}) * 1.02f;
            if (size < size_) {
                size_ = size;
                lo_ = 0.5f * (lo + hi) - glm::vec3(0.5f * size);
            }
        }
    }

    // Spatial refinement (section 3.4): halve a leaf holding more than c sqrt(2^k)
    // vertices, its children assumed to hold half each and halved again while that is
    // still too many; both children start from the parent's learned quadtree. Nodes are
    // visited in index order and children appended, so the tree does not depend on
    // anything but the counts.
    const double threshold =
        double(settings_.spatial_threshold) * std::sqrt(std::ldexp(1.0, std::clamp(pass, 0, 60)));
    std::vector<std::uint32_t> depth(nodes_.size(), 0);
    // Depths of the existing nodes, from their parents (parents precede children).
    for (std::size_t i = 0; i < nodes_.size(); ++i)
        if (nodes_[i].children != 0)
            depth[nodes_[i].children] = depth[nodes_[i].children + 1] = depth[i] + 1;
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        if (nodes_[i].children != 0) continue;
        const std::uint32_t leaf = nodes_[i].leaf;
        if (!(counts[leaf] > threshold) || depth[i] >= kMaxSpatialDepth ||
            leaves_.size() >= kMaxLeaves)
            continue;
        const auto first = static_cast<std::uint32_t>(nodes_.size());
        const auto second_leaf = static_cast<std::uint32_t>(leaves_.size());
        counts[leaf] *= 0.5;
        leaves_.push_back(std::make_unique<DirLeaf>());
        learned.push_back(learned[leaf]);
        counts.push_back(counts[leaf]);
        nodes_[i].children = first;
        nodes_.push_back(Node{0, leaf});
        nodes_.push_back(Node{0, second_leaf});
        depth.push_back(depth[i] + 1);
        depth.push_back(depth[i] + 1);
    }

    // Pass k's records guide pass k + 1; the recording cells follow the flux.
    const std::size_t max_nodes = std::max<std::size_t>(64, kMaxTotalNodes / leaves_.size());
    for (std::size_t i = 0; i < leaves_.size(); ++i) {
        DirLeaf& leaf = *leaves_[i];
        leaf.sampling = learned[i];
        leaf.recording =
            learned[i].refined(settings_.flux_threshold, settings_.max_quadtree_depth, max_nodes);
        leaf.reset_counters();
    }

    // The next pass's fixed point: its records are expected near this pass's mean.
    if (total_flux > 0.0 && total_vertices > 0.0) {
        const double mean = total_flux / total_vertices;
        const int e = std::clamp(kMeanBits - int(std::ceil(std::log2(mean))), -60, 80);
        scale_ = std::ldexp(1.0, e);
    }
}

}  // namespace librt::guiding
