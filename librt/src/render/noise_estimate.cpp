#include <librt/render/noise_estimate.h>

#include <cmath>

namespace librt {

namespace {

/// Added to a pixel's squared mean in the relative error (relMSE's denominator).
constexpr double kDarkFloor = 0.01;

}  // namespace

void NoiseEstimate::observe(const Film& film, std::uint32_t level) {
    if (film.pixels.empty()) return;
    if (snapshot_.size() != film.pixels.size()) {  // the first look: only a snapshot
        snapshot_ = film.pixels;
        snapshot_level_ = level;
        relative_variance_.assign(film.pixels.size(), -1.0f);  // -1: not known yet
        return;
    }
    if (level < 2 * snapshot_level_ || level == 0) return;
    double sum = 0.0;
    std::size_t counted = 0;
    for (std::size_t i = 0; i < film.pixels.size(); ++i) {
        const FilmPixel& now = film.pixels[i];
        const FilmPixel& then = snapshot_[i];
        // Finite samples only: the means the film shows (dropped samples are rare).
        const double h = then.finite;
        const double added = double(now.finite) - h;
        if (h > 0.0 && added > 0.0) {
            const glm::dvec3 m1 = then.radiance / h;
            const glm::dvec3 m2 = (now.radiance - then.radiance) / added;
            const glm::dvec3 mean = now.radiance / double(now.finite);
            const glm::dvec3 d = m1 - m2;
            // Per-sample variance from two runs' means: d^2 / (1/h + 1/added).
            const double scale = 1.0 / (1.0 / h + 1.0 / added);
            double r = 0.0;
            for (int c = 0; c < 3; ++c) r += d[c] * d[c] * scale / (mean[c] * mean[c] + kDarkFloor);
            relative_variance_[i] = static_cast<float>(r / 3.0);
        }
        if (relative_variance_[i] >= 0.0f && now.finite > 0) {
            sum += double(relative_variance_[i]) / double(now.finite);
            ++counted;
        }
    }
    if (counted > 0) error_ = std::sqrt(sum / double(counted));
    snapshot_ = film.pixels;
    snapshot_level_ = level;
}

}  // namespace librt
