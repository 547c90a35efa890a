#pragma once

#include <librt/export.h>
#include <librt/geometry/hit.h>
#include <librt/light/light.h>

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace librt {

struct LightBounds;  // src/light/light_bounds.h
namespace detail {
class LightTree;  // src/light/light_tree.h
}  // namespace detail

/// Where a light is to be chosen for: a shading point and what its BSDF can receive.
struct LightChoicePoint {
    glm::vec3 point{0.0f};  ///< the shading point (the light sample's reference point)
    /// Unit geometric normal on the side the path arrived from.
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    /// The BSDF only reflects (no transmission lobe): light from below the surface's
    /// geometric plane gives nothing, so a light wholly below it is worth nothing.
    bool reflect_only = false;
};

/// How a path tracer chooses the light it samples at a shading point.
enum class LightChoice : std::uint8_t {
    Power,    ///< by power alone, the same table everywhere (LightSampler::sample(u))
    Bounded,  ///< by power times a bound of the contribution at the point (each light's bounds())
    /// Bounded above LightSampler::kMaxBounded lights (through the light tree: 2.9-3.1x
    /// lower RMSE at equal time on 800 small lights), Power otherwise (with few lights the
    /// bound costs more than it saves: docs/benchmarks.md); decided per scene.
    Auto,
};

/// One light chosen by a LightSampler, with the probability of that choice.
struct SampledLight {
    std::uint32_t light = kInvalidId;  ///< index into the scene's lights; kInvalidId for none
    float pmf = 0.0f;                  ///< probability of having chosen it

    /// True when a light was chosen.
    [[nodiscard]] bool valid() const { return pmf > 0.0f; }
};

/// Chooses the one light a shading point samples, with probability proportional to its
/// power (the mean over channels). Why power and not uniform: a path tracer's shadow rays
/// should go where the light is, and with area lights made of many triangles of different
/// sizes (the next lights) uniform choice would spend as many rays on a dim speck as on a
/// bright panel; the pmf does not depend on the shading point, so an emitter hit by a BSDF
/// ray gets its MIS weight from pmf(light) alone. Lights of zero power are never chosen
/// (they add nothing). Choosing is a binary search in the cumulative distribution.
///
/// The overloads taking a LightChoicePoint choose by power times a bound of each light's
/// contribution at that point instead (each light's bounds(), src/light/light_bounds.h): a
/// light wholly below a reflecting
/// surface, or one facing away, gets probability 0 and costs no sample and no shadow ray;
/// near lights get more samples than far ones. With at most kMaxBounded lights the pmf
/// is computed per point (one bound per light: cheap, and exact to renormalise). Above
/// that the finite lights are chosen through a light tree (a binary tree over their
/// bounds, as pbrt-v4's BVHLightSampler; private, src/light/light_tree.h): the walk from
/// its root picks a child by the bound of all the lights below it, so the cost per
/// shading point grows with the tree's depth, not the number of lights. Lights at infinity
/// keep their share of the power table (their power has no distance to compare with a
/// finite light's), finite lights share the rest by their bounds; both then renormalised
/// over what is left.
class LIBRT_API LightSampler {
public:
    /// A sampler with no lights: sample() always returns an invalid choice.
    LightSampler();
    /// A sampler over `lights`, indexed as given.
    explicit LightSampler(std::span<const Light> lights);
    // Copies, moves and the destructor are out of line: LightBounds is private
    // (src/light/light_bounds.h), complete only there.
    /// A copy (the light tree is shared: immutable).
    LightSampler(const LightSampler& other);
    /// Takes other's tables.
    LightSampler(LightSampler&& other) noexcept;
    /// A copy (the light tree is shared: immutable).
    LightSampler& operator=(const LightSampler& other);
    /// Takes other's tables.
    LightSampler& operator=(LightSampler&& other) noexcept;
    ~LightSampler();

    /// The light chosen by u in [0, 1).
    [[nodiscard]] SampledLight sample(float u) const {
        if (cdf_.size() == 1) return {0, pmf_[0]};  // the common single light: no search
        return search(u);
    }
    /// Probability that sample() chooses light `light` (0 for an unknown index).
    [[nodiscard]] float pmf(std::uint32_t light) const {
        return light < pmf_.size() ? pmf_[light] : 0.0f;
    }
    /// The light chosen by u in [0, 1) for shading point `at`, by power times its bound.
    [[nodiscard]] SampledLight sample(float u, const LightChoicePoint& at) const;
    /// Probability that sample(u, at) chooses light `light` (0 for an unknown index):
    /// what the MIS weight of a BSDF-sampled ray that hits it from `at` must use.
    [[nodiscard]] float pmf(std::uint32_t light, const LightChoicePoint& at) const;
    /// The bounds of light `light` (index < size()); for the tests of the private
    /// src/light/light_bounds.h.
    [[nodiscard]] const LightBounds& bounds(std::uint32_t light) const;
    /// Up to this many lights the per-point choice renormalises over every light.
    static constexpr std::size_t kMaxBounded = 16;

    /// Number of lights, chosen or not.
    [[nodiscard]] std::size_t size() const { return pmf_.size(); }
    /// True when some light can be chosen.
    [[nodiscard]] bool any() const { return !cdf_.empty() && cdf_.back() > 0.0f; }

private:
    [[nodiscard]] SampledLight search(float u) const;
    /// Per-point weights of every light into w (size() <= kMaxBounded); their sum.
    double point_weights(const LightChoicePoint& at, double* w) const;
    /// Above kMaxBounded lights: the weights of the two groups at `at`, the finite lights
    /// (finite_share_ when the tree reaches the point, else 0) and those at infinity (their
    /// power-table pmfs, each where its bound allows); returns their sum.
    double group_weights(const LightChoicePoint& at, double& finite) const;

    std::vector<float> pmf_;  ///< per light
    std::vector<float> cdf_;  ///< cdf_[i] = pmf_[0] + ... + pmf_[i]; the last positive is 1
    std::vector<LightBounds> bounds_;  ///< per light
    double finite_share_ = 0.0;        ///< sum of pmf_ over the lights not at infinity
    /// Above kMaxBounded lights: the tree over the finite lights of positive power, and
    /// the lights at infinity. Shared by copies (immutable).
    std::shared_ptr<const detail::LightTree> tree_;
    std::vector<std::uint32_t> infinite_;
};

/// Whether `choice` chooses by bound for a scene of `light_count` lights (Auto resolved).
[[nodiscard]] inline bool chooses_by_bound(LightChoice choice, std::size_t light_count) {
    return choice == LightChoice::Bounded ||
           (choice == LightChoice::Auto && light_count > LightSampler::kMaxBounded);
}

}  // namespace librt
