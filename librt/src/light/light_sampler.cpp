#include "light/light_bounds.h"
#include "light/light_tree.h"

#include <librt/light/light_sampler.h>

#include <algorithm>
#include <cmath>

namespace librt {

LightSampler::LightSampler() = default;
LightSampler::LightSampler(const LightSampler& other) = default;
LightSampler::LightSampler(LightSampler&& other) noexcept = default;
LightSampler& LightSampler::operator=(const LightSampler& other) = default;
LightSampler& LightSampler::operator=(LightSampler&& other) noexcept = default;
LightSampler::~LightSampler() = default;

const LightBounds& LightSampler::bounds(std::uint32_t light) const { return bounds_[light]; }

LightSampler::LightSampler(std::span<const Light> lights) {
    std::vector<double> weight(lights.size());
    double total = 0.0;
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const glm::vec3 p = power(lights[i]);
        // The mean over channels: no colour is favoured.
        const double w = (double(p.x) + double(p.y) + double(p.z)) / 3.0;
        weight[i] = std::isfinite(w) && w > 0.0 ? w : 0.0;
        total += weight[i];
    }
    bounds_.reserve(lights.size());
    for (const Light& light : lights) bounds_.push_back(light_bounds(light));
    pmf_.assign(lights.size(), 0.0f);
    cdf_.assign(lights.size(), 0.0f);
    if (!(total > 0.0) || !std::isfinite(total)) {
        cdf_.clear();  // nothing to choose
        return;
    }
    double sum = 0.0;
    std::size_t last = 0;
    for (std::size_t i = 0; i < lights.size(); ++i) {
        pmf_[i] = float(weight[i] / total);
        if (!bounds_[i].infinite) finite_share_ += weight[i] / total;
        sum += weight[i] / total;
        cdf_[i] = float(sum);
        if (weight[i] > 0.0) last = i;
    }
    // Rounding must not leave u just below 1 without a light: the last chosen light ends at 1.
    for (std::size_t i = last; i < cdf_.size(); ++i) cdf_[i] = 1.0f;
    if (lights.size() > kMaxBounded) {
        std::vector<std::uint32_t> finite;
        for (std::uint32_t i = 0; i < lights.size(); ++i) {
            if (!(weight[i] > 0.0)) continue;  // never chosen
            (bounds_[i].infinite ? infinite_ : finite).push_back(i);
        }
        tree_ = std::make_shared<const detail::LightTree>(bounds_, finite);
    }
}

SampledLight LightSampler::search(float u) const {
    if (!any()) return {};
    // The first light whose cumulative probability exceeds u: lights of zero pmf have an
    // empty interval and are never returned.
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
    const auto i =
        std::uint32_t(std::min<std::ptrdiff_t>(it - cdf_.begin(), std::ptrdiff_t(cdf_.size()) - 1));
    return {i, pmf_[i]};
}

double LightSampler::point_weights(const LightChoicePoint& at, double* w) const {
    double finite_sum = 0.0;
    for (std::size_t i = 0; i < bounds_.size(); ++i) {
        const float imp = importance(bounds_[i], at);
        w[i] = double(imp);
        if (!bounds_[i].infinite) finite_sum += w[i];
    }
    // Finite lights share finite_share_ by their bounds; lights at infinity keep their
    // power-table probability unless their bound rules them out.
    const double scale = finite_sum > 0.0 ? finite_share_ / finite_sum : 0.0;
    double total = 0.0;
    for (std::size_t i = 0; i < bounds_.size(); ++i) {
        if (bounds_[i].infinite)
            w[i] = w[i] > 0.0 ? double(pmf_[i]) : 0.0;
        else
            w[i] *= scale;
        if (!std::isfinite(w[i])) w[i] = 0.0;
        total += w[i];
    }
    return total;
}

double LightSampler::group_weights(const LightChoicePoint& at, double& finite) const {
    finite = tree_->reaches(at) ? finite_share_ : 0.0;
    double total = finite;
    for (std::uint32_t i : infinite_)
        if (importance(bounds_[i], at) > 0.0f) total += double(pmf_[i]);
    return total;
}

SampledLight LightSampler::sample(float u, const LightChoicePoint& at) const {
    if (tree_) {
        if (!any()) return {};
        double finite = 0.0;
        const double total = group_weights(at, finite);
        if (!(total > 0.0)) return {};
        // The finite lights' share first (through the tree, u rescaled), then those at
        // infinity in order.
        const double target = double(u) * total;
        if (target < finite) {
            const float v = std::min(float(target / finite), 0x1.fffffep-1f);
            const detail::LightTree::Choice c = tree_->sample(v, at);
            if (c.light == kInvalidId || !(c.pmf > 0.0f)) return {};
            return {c.light, float(double(c.pmf) * finite / total)};
        }
        double sum = finite;
        std::uint32_t chosen = kInvalidId;
        for (std::uint32_t i : infinite_) {
            if (!(importance(bounds_[i], at) > 0.0f)) continue;
            chosen = i;
            sum += double(pmf_[i]);
            if (target < sum) break;
        }
        if (chosen == kInvalidId) return {};
        return {chosen, float(double(pmf_[chosen]) / total)};
    }
    double w[kMaxBounded];
    const double total = point_weights(at, w);
    if (!(total > 0.0)) return {};
    // The first light whose cumulative weight exceeds u * total; lights of weight 0 have an
    // empty interval. Rounding can leave u * total at the end: the last positive light.
    const double target = double(u) * total;
    double sum = 0.0;
    std::size_t chosen = bounds_.size();
    for (std::size_t i = 0; i < bounds_.size(); ++i) {
        if (!(w[i] > 0.0)) continue;
        chosen = i;
        sum += w[i];
        if (target < sum) break;
    }
    return {std::uint32_t(chosen), float(w[chosen] / total)};
}

float LightSampler::pmf(std::uint32_t light, const LightChoicePoint& at) const {
    if (light >= bounds_.size()) return 0.0f;
    if (tree_) {
        double finite = 0.0;
        const double total = group_weights(at, finite);
        if (!(total > 0.0)) return 0.0f;
        if (bounds_[light].infinite)
            return importance(bounds_[light], at) > 0.0f ? float(double(pmf_[light]) / total)
                                                         : 0.0f;
        if (!(finite > 0.0)) return 0.0f;
        return float(double(tree_->pmf(light, at)) * finite / total);
    }
    double w[kMaxBounded];
    const double total = point_weights(at, w);
    if (!(total > 0.0)) return 0.0f;
    return float(w[light] / total);
}

}  // namespace librt
