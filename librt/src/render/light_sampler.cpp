#include <librt/render/light_sampler.h>

#include <algorithm>
#include <cmath>

namespace librt {

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
        sum += weight[i] / total;
        cdf_[i] = float(sum);
        if (weight[i] > 0.0) last = i;
    }
    // Rounding must not leave u just below 1 without a light: the last chosen light ends at 1.
    for (std::size_t i = last; i < cdf_.size(); ++i) cdf_[i] = 1.0f;
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

}  // namespace librt
