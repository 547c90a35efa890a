#include <librt/sampling/distribution.h>

#include <algorithm>
#include <cmath>

namespace librt {

Distribution1D::Distribution1D(std::span<const float> weights) {
    const std::size_t n = std::max<std::size_t>(weights.size(), 1);
    std::vector<double> w(n, 0.0);
    double total = 0.0;
    for (std::size_t i = 0; i < weights.size(); ++i) {
        const float x = weights[i];
        w[i] = std::isfinite(x) && x > 0.0f ? double(x) : 0.0;
        total += w[i];
    }
    integral_ = total / double(n);
    if (!(total > 0.0)) {
        std::fill(w.begin(), w.end(), 1.0);  // nothing to favour: uniform
        total = double(n);
    }
    pdf_.resize(n);
    cdf_.resize(n + 1);
    cdf_[0] = 0.0f;
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        pdf_[i] = float(w[i] / total * double(n));  // density per unit length
        sum += w[i] / total;
        cdf_[i + 1] = float(sum);
    }
    cdf_[n] = 1.0f;
}

Distribution1D::Sample Distribution1D::sample(float u) const {
    const std::size_t n = pdf_.size();
    // The last cell whose CDF start is <= u; cells of zero probability are never chosen.
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
    std::size_t i = std::size_t(std::max<std::ptrdiff_t>(it - cdf_.begin() - 1, 0));
    i = std::min(i, n - 1);
    while (i > 0 && !(pdf_[i] > 0.0f)) --i;  // u landing exactly on an empty cell's edge
    const float width = cdf_[i + 1] - cdf_[i];
    const float t = width > 0.0f ? std::clamp((u - cdf_[i]) / width, 0.0f, 1.0f) : 0.5f;
    float x = (float(i) + t) / float(n);
    x = std::min(x, std::nextafter(1.0f, 0.0f));
    return {x, pdf_[i], i};
}

Distribution2D::Distribution2D(std::span<const float> weights, int width, int height)
    : width_(std::max(width, 1)), height_(std::max(height, 1)) {
    const bool uniform = weights.size() != std::size_t(width_) * std::size_t(height_);
    std::vector<float> row_weight(std::size_t(height_), 1.0f);
    rows_.reserve(std::size_t(height_));
    for (int y = 0; y < height_; ++y) {
        if (uniform) {
            rows_.emplace_back();
            continue;
        }
        const auto row = weights.subspan(std::size_t(y) * std::size_t(width_), std::size_t(width_));
        rows_.emplace_back(row);
        row_weight[std::size_t(y)] = float(rows_.back().integral());
    }
    marginal_ = Distribution1D(row_weight);
}

Distribution2D::Sample Distribution2D::sample(glm::vec2 u) const {
    const Distribution1D::Sample v = marginal_.sample(u.y);
    const Distribution1D::Sample x = rows_[v.cell].sample(u.x);
    // p(u, v) = p(v) p(u | v).
    return {{x.x, v.x}, v.pdf * x.pdf};
}

float Distribution2D::pdf(glm::vec2 uv) const {
    const int y = std::clamp(int(uv.y * float(height_)), 0, height_ - 1);
    const Distribution1D& row = rows_[std::size_t(y)];
    const int x = std::clamp(int(uv.x * float(row.size())), 0, int(row.size()) - 1);
    return marginal_.pdf(std::size_t(y)) * row.pdf(std::size_t(x));
}

}  // namespace librt
