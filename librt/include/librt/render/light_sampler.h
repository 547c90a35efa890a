#pragma once

#include <librt/export.h>
#include <librt/geometry/hit.h>
#include <librt/render/light.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace librt {

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
class LIBRT_API LightSampler {
public:
    /// A sampler with no lights: sample() always returns an invalid choice.
    LightSampler() = default;
    /// A sampler over `lights`, indexed as given.
    explicit LightSampler(std::span<const Light> lights);

    /// The light chosen by u in [0, 1).
    [[nodiscard]] SampledLight sample(float u) const {
        if (cdf_.size() == 1) return {0, pmf_[0]};  // the common single light: no search
        return search(u);
    }
    /// Probability that sample() chooses light `light` (0 for an unknown index).
    [[nodiscard]] float pmf(std::uint32_t light) const {
        return light < pmf_.size() ? pmf_[light] : 0.0f;
    }
    /// Number of lights, chosen or not.
    [[nodiscard]] std::size_t size() const { return pmf_.size(); }
    /// True when some light can be chosen.
    [[nodiscard]] bool any() const { return !cdf_.empty() && cdf_.back() > 0.0f; }

private:
    [[nodiscard]] SampledLight search(float u) const;

    std::vector<float> pmf_;  ///< per light
    std::vector<float> cdf_;  ///< cdf_[i] = pmf_[0] + ... + pmf_[i]; the last positive is 1
};

}  // namespace librt
