#include "light/light_tree.h"

#include "light/importance_bound.h"

#include <librt/geometry/hit.h>
#include <librt/sampling/warp.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace librt::detail {
namespace {

/// The emission spread given a spot's hard edge, 1e-3 rad: an angle the float cosines of
/// importance() resolve (their rounding near 1 is ~5e-4 rad), so rounding never rules out
/// a point inside the cone.
constexpr float kSpotEdge = 1e-3f;
/// Widening of a merged cone against the rounding of its axis (radians).
constexpr float kConePad = 1e-4f;
/// From this depth on a node is split at its median: the rest of the tree is then at most
/// 32 levels deep, so a trail fits 64 bits.
constexpr int kMedianFromDepth = 32;
/// Bins per axis of the split search.
constexpr int kBins = 12;
/// An interior child is weighed by the sum of its own children's bounds, one level down:
/// they are tighter than its own, so fewer walks end at a node whose children are both
/// ruled out and the walk follows the light better. On librt_many_lights' 800 lights
/// (docs/light-targets.md) one level cuts the variance per sample 2.2x for 1.2x the time;
/// two and three levels cut it further but cost as much as they gain.
constexpr int kLookahead = 1;

/// The cone's cosines and sine, computed once per node rather than per importance().
void finish_cone(LightTreeBounds& b) {
    b.cos_o = std::cos(std::min(b.theta_o, kPi));
    b.sin_o = std::sin(std::min(b.theta_o, kPi));
    b.cos_e = std::cos(b.theta_e);
}

/// A light's own bounds in the tree's form.
LightTreeBounds tree_bounds(const LightBounds& b) {
    LightTreeBounds t;
    t.centre = b.centre;
    t.radius = b.radius;
    t.lo = b.centre - glm::vec3(b.radius);
    t.hi = b.centre + glm::vec3(b.radius);
    t.phi = b.phi;
    t.axis = b.axis;
    if (!b.cone) {
        t.theta_o = kPi;  // every direction (point, sphere, two-sided planar lights)
        t.theta_e = kPi / 2.0f;
    } else if (b.emitter_cosine) {
        t.theta_o = 0.0f;  // a one-sided planar emitter: its normal, then a cosine lobe
        t.theta_e = kPi / 2.0f;
    } else {
        t.theta_o = std::acos(std::clamp(b.cos_cone, -1.0f, 1.0f));  // a spot's cone
        t.theta_e = kSpotEdge;
    }
    finish_cone(t);
    return t;
}

/// The smallest sphere around two spheres, padded against rounding.
void merge_spheres(const LightTreeBounds& a, const LightTreeBounds& b, LightTreeBounds& out) {
    const glm::vec3 ab = b.centre - a.centre;
    const float d = glm::length(ab);
    if (d + b.radius <= a.radius) {
        out.centre = a.centre;
        out.radius = a.radius;
        return;
    }
    if (d + a.radius <= b.radius) {
        out.centre = b.centre;
        out.radius = b.radius;
        return;
    }
    const float r = 0.5f * (d + a.radius + b.radius);
    out.centre = a.centre + ((r - a.radius) / d) * ab;
    const float magnitude =
        std::max({std::fabs(out.centre.x), std::fabs(out.centre.y), std::fabs(out.centre.z), r});
    out.radius = r * (1.0f + 1e-5f) + 1e-6f * magnitude;
}

/// The cone holding both cones of directions (as pbrt-v4's DirectionCone Union).
void merge_cones(const LightTreeBounds& a, const LightTreeBounds& b, LightTreeBounds& out) {
    out.theta_e = std::max(a.theta_e, b.theta_e);
    out.axis = a.axis;
    out.theta_o = kPi;
    if (a.theta_o >= kPi || b.theta_o >= kPi) return;
    const float theta_d = std::acos(std::clamp(glm::dot(a.axis, b.axis), -1.0f, 1.0f));
    // One cone holds the other. acos rounds an angle below ~3.5e-4 rad to 0, so axes that
    // differ at all widen the kept cone by kConePad.
    const float pad = a.axis == b.axis ? 0.0f : kConePad;
    if (std::min(theta_d + b.theta_o, kPi) <= a.theta_o) {
        out.theta_o = std::min(a.theta_o + pad, kPi);
        return;
    }
    if (std::min(theta_d + a.theta_o, kPi) <= b.theta_o) {
        out.axis = b.axis;
        out.theta_o = std::min(b.theta_o + pad, kPi);
        return;
    }
    const float theta_o = 0.5f * (a.theta_o + theta_d + b.theta_o) + kConePad;
    if (theta_o >= kPi) return;
    // Turn a's axis toward b's by theta_o - theta_a, in the plane of both.
    const glm::vec3 side = b.axis - glm::dot(a.axis, b.axis) * a.axis;
    const float side_length = glm::length(side);
    if (!(side_length > 1e-6f)) return;  // (anti)parallel axes not caught above: any direction
    const float turn = theta_o - kConePad - a.theta_o;
    out.axis = glm::normalize(std::cos(turn) * a.axis + (std::sin(turn) / side_length) * side);
    out.theta_o = theta_o;
}

LightTreeBounds merge(const LightTreeBounds& a, const LightTreeBounds& b) {
    LightTreeBounds out;
    out.phi = a.phi + b.phi;
    merge_spheres(a, b, out);
    out.lo = glm::min(a.lo, b.lo);
    out.hi = glm::max(a.hi, b.hi);
    // The box's own sphere when it is the smaller one (padded as merge_spheres pads).
    const glm::vec3 box_centre = 0.5f * (out.lo + out.hi);
    const float box_radius = 0.5f * glm::length(out.hi - out.lo);
    const float magnitude = std::max(
        {std::fabs(box_centre.x), std::fabs(box_centre.y), std::fabs(box_centre.z), box_radius});
    const float padded_box = box_radius * (1.0f + 1e-5f) + 1e-6f * magnitude;
    if (padded_box < out.radius) {
        out.centre = box_centre;
        out.radius = padded_box;
    }
    merge_cones(a, b, out);
    finish_cone(out);
    return out;
}

/// The solid-angle measure of a node's emission (pbrt-v4's M_Omega): 4 pi for every
/// direction, 2 pi (1 - cos theta_o) plus the cosine lobe's rim otherwise.
float orientation_measure(const LightTreeBounds& b) {
    const float theta_o = std::min(b.theta_o, kPi);
    const float theta_w = std::min(theta_o + b.theta_e, kPi);
    return 2.0f * kPi * (1.0f - std::cos(theta_o)) +
           0.5f * kPi *
               (2.0f * theta_w * std::sin(theta_o) - std::cos(theta_o - 2.0f * theta_w) -
                2.0f * theta_o * std::sin(theta_o) + std::cos(theta_o));
}

/// The cost of a node in the split search: power times the room its lights spread over in
/// space (the sphere's r^2) and in direction (Conty Estevez & Kulla 2018's SAOH, with the
/// sphere standing in for the box).
float split_cost(const LightTreeBounds& b) {
    return b.phi * orientation_measure(b) * std::max(b.radius * b.radius, 1e-12f);
}

}  // namespace

// The hooks of importance_bound for a node's bounds (importance_bound.h).

/// Wholly below a reflecting receiver's plane: the box corner farthest along the normal.
static bool ruled_out(const LightTreeBounds& b, const LightChoicePoint& at,
                      const glm::vec3& /*to_light*/, float /*d2*/) {
    if (!at.reflect_only) return false;
    const glm::vec3 far{at.normal.x > 0.0f ? b.hi.x : b.lo.x, at.normal.y > 0.0f ? b.hi.y : b.lo.y,
                        at.normal.z > 0.0f ? b.hi.z : b.lo.z};
    const glm::vec3 reach = far - at.point;
    const float margin = 1e-5f * (std::fabs(reach.x) + std::fabs(reach.y) + std::fabs(reach.z));
    return glm::dot(at.normal, reach) < -margin;
}

/// The distance term alone, to the centre (so the walk still leans toward where the point
/// is), floored at (r/2)^2.
static float inside_weight(const LightTreeBounds& b, float d2, float r2) {
    return b.phi / std::max(std::max(d2, 0.25f * r2), 1e-12f);
}

/// cos theta': theta' = max(0, theta_w - theta_o - theta_u), theta_w the angle between the
/// axis and the direction from the lights to the point, theta_u (here a) the sphere's
/// half angle; nothing beyond the emission spread theta_e.
static bool emitter_bound(const LightTreeBounds& b, const glm::vec3& w, float cos_a, float sin_a,
                          float& weight) {
    if (!(b.theta_o < kPi)) return true;
    const float c = cos_minus(cos_minus(-glm::dot(b.axis, w), b.cos_o, b.sin_o), cos_a, sin_a);
    if (!(c > b.cos_e)) return false;
    weight *= std::max(c, 0.0f);
    return true;
}

float importance(const LightTreeBounds& b, const LightChoicePoint& at) {
    return importance_bound(b, at);
}

LightTree::LightTree(std::span<const LightBounds> bounds, std::span<const std::uint32_t> lights)
    : light_bounds_(bounds.begin(), bounds.end()),
      trail_(bounds.size(), 0),
      depth_(bounds.size(), 255) {
    if (lights.empty()) return;
    std::vector<std::uint32_t> order(lights.begin(), lights.end());
    leaf_.resize(light_bounds_.size());
    for (std::uint32_t l : order) leaf_[l] = tree_bounds(light_bounds_[l]);
    nodes_.reserve(2 * order.size() - 1);
    build(order, 0, 0);
    leaf_ = {};  // only the build needs them
}

std::uint32_t LightTree::build(std::span<std::uint32_t> lights, int depth, std::uint64_t trail) {
    const auto at = std::uint32_t(nodes_.size());
    nodes_.emplace_back();
    if (lights.size() == 1) {
        nodes_[at].leaf = true;
        nodes_[at].index = lights[0];
        nodes_[at].bounds = leaf_[lights[0]];
        trail_[lights[0]] = trail;
        depth_[lights[0]] = static_cast<std::uint8_t>(depth);
        return at;
    }
    // Centroid box: the axes to split along.
    glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-lo);
    for (std::uint32_t l : lights) {
        lo = glm::min(lo, light_bounds_[l].centre);
        hi = glm::max(hi, light_bounds_[l].centre);
    }
    const auto centre_of = [&](std::uint32_t l, int axis) { return light_bounds_[l].centre[axis]; };
    std::size_t mid = 0;
    if (depth < kMedianFromDepth) {
        // Binned SAOH: the bin boundary on any axis with the least cost of both sides.
        float best = std::numeric_limits<float>::infinity();
        int best_axis = -1, best_split = 0;
        for (int axis = 0; axis < 3; ++axis) {
            const float extent = hi[axis] - lo[axis];
            if (!(extent > 0.0f)) continue;
            std::array<LightTreeBounds, kBins> bin{};
            std::array<bool, kBins> used{};
            const auto bin_of = [&](std::uint32_t l) {
                const int b = int(float(kBins) * (centre_of(l, axis) - lo[axis]) / extent);
                return std::clamp(b, 0, kBins - 1);
            };
            for (std::uint32_t l : lights) {
                const int b = bin_of(l);
                bin[b] = used[b] ? merge(bin[b], leaf_[l]) : leaf_[l];
                used[b] = true;
            }
            std::array<float, kBins> below{};  // cost of bins [0, s)
            LightTreeBounds acc;
            bool any = false;
            for (int s = 1; s < kBins; ++s) {
                if (used[s - 1]) {
                    acc = any ? merge(acc, bin[s - 1]) : bin[s - 1];
                    any = true;
                }
                below[s] = any ? split_cost(acc) : -1.0f;
            }
            any = false;
            for (int s = kBins - 1; s >= 1; --s) {
                if (used[s]) {
                    acc = any ? merge(acc, bin[s]) : bin[s];
                    any = true;
                }
                if (!any || below[s] < 0.0f) continue;
                const float cost = below[s] + split_cost(acc);
                if (cost < best) {
                    best = cost;
                    best_axis = axis;
                    best_split = s;
                }
            }
        }
        if (best_axis >= 0) {
            const float extent = hi[best_axis] - lo[best_axis];
            const auto it = std::partition(lights.begin(), lights.end(), [&](std::uint32_t l) {
                const int b =
                    int(float(kBins) * (centre_of(l, best_axis) - lo[best_axis]) / extent);
                return std::clamp(b, 0, kBins - 1) < best_split;
            });
            mid = std::size_t(it - lights.begin());
        }
    }
    if (mid == 0 || mid == lights.size()) {
        // No useful bin split (all centres alike, or deep): halves by count along the
        // longest axis.
        const glm::vec3 extent = hi - lo;
        const int axis =
            extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
        mid = lights.size() / 2;
        std::nth_element(lights.begin(), lights.begin() + std::ptrdiff_t(mid), lights.end(),
                         [&](std::uint32_t a, std::uint32_t b) {
                             return centre_of(a, axis) < centre_of(b, axis) ||
                                    (centre_of(a, axis) == centre_of(b, axis) && a < b);
                         });
    }
    const std::uint32_t first = build(lights.first(mid), depth + 1, trail);
    const std::uint32_t second =
        build(lights.subspan(mid), depth + 1, trail | (std::uint64_t{1} << depth));
    nodes_[at].index = second;
    nodes_[at].bounds = merge(nodes_[first].bounds, nodes_[second].bounds);
    return at;
}

float LightTree::weight(const Node& n, const LightChoicePoint& at) const {
    return weight_below(n, at, kLookahead);
}

float LightTree::weight_below(const Node& n, const LightChoicePoint& at, int levels) const {
    if (n.leaf) return librt::importance(light_bounds_[n.index], at);
    if (levels == 0) return importance(n.bounds, at);
    return weight_below(nodes_[std::size_t(&n - nodes_.data()) + 1], at, levels - 1) +
           weight_below(nodes_[n.index], at, levels - 1);
}

bool LightTree::reaches(const LightChoicePoint& at) const {
    return !nodes_.empty() && weight(nodes_[0], at) > 0.0f;
}

LightTree::Choice LightTree::sample(float u, const LightChoicePoint& at) const {
    if (nodes_.empty()) return {kInvalidId, 0.0f};
    std::uint32_t node = 0;
    float pmf = 1.0f;
    while (!nodes_[node].leaf) {
        const std::uint32_t first = node + 1, second = nodes_[node].index;
        const float w0 = weight(nodes_[first], at), w1 = weight(nodes_[second], at);
        const float total = w0 + w1;
        if (!(total > 0.0f) || !std::isfinite(total)) return {kInvalidId, 0.0f};
        const float p0 = w0 / total;
        if (u < p0) {
            u = std::min(u / p0, 0x1.fffffep-1f);
            pmf *= p0;
            node = first;
        } else {
            u = std::min((u - p0) / (1.0f - p0), 0x1.fffffep-1f);
            pmf *= w1 / total;
            node = second;
        }
    }
    // A single light: chosen when its bound allows.
    if (node == 0 && !(weight(nodes_[0], at) > 0.0f)) return {kInvalidId, 0.0f};
    return {nodes_[node].index, pmf};
}

float LightTree::pmf(std::uint32_t light, const LightChoicePoint& at) const {
    if (light >= depth_.size() || depth_[light] == 255) return 0.0f;
    std::uint32_t node = 0;
    float pmf = 1.0f;
    for (int d = 0; d < depth_[light]; ++d) {
        const std::uint32_t first = node + 1, second = nodes_[node].index;
        const float w0 = weight(nodes_[first], at), w1 = weight(nodes_[second], at);
        const float total = w0 + w1;
        if (!(total > 0.0f) || !std::isfinite(total)) return 0.0f;
        if ((trail_[light] >> d) & 1u) {
            pmf *= w1 / total;
            node = second;
        } else {
            pmf *= w0 / total;
            node = first;
        }
    }
    if (depth_[light] == 0 && !(weight(nodes_[0], at) > 0.0f)) return 0.0f;
    return pmf;
}

}  // namespace librt::detail
