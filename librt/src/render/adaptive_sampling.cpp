#include <librt/core/error.h>
#include <librt/render/adaptive_sampling.h>
#include <librt/render/renderer.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace librt {

void validate(const AdaptiveSampling& s) {
    if (s.pilot_samples < 0 || s.pilot_samples % 2 != 0 ||
        s.pilot_samples > static_cast<int>(kMaxSamplesPerPixel)) {
        throw Error("adaptive.pilot_samples = " + std::to_string(s.pilot_samples) +
                    ": must be 0 (automatic) or even, in [2, 1048576]");
    }
    if (s.radius < 0 || s.radius > 16) {
        throw Error("adaptive.radius = " + std::to_string(s.radius) +
                    ": must be 0 (automatic) or in [1, 16]");
    }
    if (s.metric != AdaptiveMetric::Absolute && s.metric != AdaptiveMetric::Relative) {
        throw Error("adaptive.metric = " + std::to_string(static_cast<int>(s.metric)) +
                    ": must be Absolute or Relative");
    }
    if (!(std::isfinite(s.relative_floor) && s.relative_floor > 0.0)) {
        throw Error("adaptive.relative_floor = " + std::to_string(s.relative_floor) +
                    ": must be finite and > 0");
    }
    if (!(s.max_factor >= 1.0 && s.max_factor <= 1024.0)) {
        throw Error("adaptive.max_factor = " + std::to_string(s.max_factor) +
                    ": must be in [1, 1024]");
    }
}

int adaptive_radius(const AdaptiveSampling& s, int width, int height) {
    if (s.radius > 0) return s.radius;
    // Rounded larger side / 40: 3 at 128 pixels, 13 at 512, the best of each size measured.
    return std::clamp((std::max(width, height) + 20) / 40, 2, 16);
}

std::uint32_t adaptive_pilot_samples(const AdaptiveSampling& s, std::uint32_t samples_per_pixel) {
    std::uint32_t pilot = static_cast<std::uint32_t>(s.pilot_samples);
    if (pilot == 0) {
        pilot = 2;
        while (pilot * 2 <= samples_per_pixel / 4) pilot *= 2;
    }
    if (samples_per_pixel < 4 || pilot >= samples_per_pixel) return 0;
    return pilot;
}

std::vector<std::uint32_t> adaptive_sample_counts(const Film& first_half, const Film& pilot,
                                                  std::uint32_t samples_per_pixel,
                                                  const AdaptiveSampling& settings) {
    validate(settings);
    if (first_half.width != pilot.width || first_half.height != pilot.height ||
        first_half.pixels.size() != pilot.pixels.size()) {
        throw Error("adaptive sampling: the pilot's half film is " +
                    std::to_string(first_half.width) + " x " + std::to_string(first_half.height) +
                    ", its whole film " + std::to_string(pilot.width) + " x " +
                    std::to_string(pilot.height));
    }
    const int w = pilot.width;
    const int h = pilot.height;
    const std::size_t n = pilot.pixels.size();
    if (n == 0) return {};
    const std::uint32_t n0 = pilot.pixels[0].samples;
    const std::uint32_t half = first_half.pixels[0].samples;
    for (std::size_t i = 0; i < n; ++i) {
        if (pilot.pixels[i].samples != n0 || first_half.pixels[i].samples != half || half == 0 ||
            half >= n0) {
            throw Error("adaptive sampling: pilot pixel " + std::to_string(i % std::size_t(w)) +
                        ", " + std::to_string(i / std::size_t(w)) + " holds " +
                        std::to_string(first_half.pixels[i].samples) + " then " +
                        std::to_string(pilot.pixels[i].samples) +
                        " samples; every pixel must hold the same two counts, 0 < half < all");
        }
    }

    // Each pixel's squared difference of its two half means (mean of the channels): an
    // estimate of 4 sigma^2 / n0 with sigma^2 the variance of one sample (for independent
    // samples; a Sobol' pilot's halves differ less, as its means converge faster).
    std::vector<double> diff(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        const FilmPixel& a = first_half.pixels[i];
        const FilmPixel& all = pilot.pixels[i];
        const std::uint32_t b_finite = all.finite - a.finite;
        if (a.finite == 0 || b_finite == 0) continue;
        const glm::dvec3 d =
            a.radiance / double(a.finite) - (all.radiance - a.radiance) / double(b_finite);
        diff[i] = (d.x * d.x + d.y * d.y + d.z * d.z) / 3.0;
    }
    if (settings.metric == AdaptiveMetric::Relative) {
        // Weight w_q = 1 / (m_q + floor) on each pixel's squared difference, m_q its pilot
        // mean (channel mean): the neighbours' weighted noise gives n_p ~ sqrt(w) sigma.
        std::vector<double> brightness(n, 0.0);
        double mean = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            const FilmPixel& all = pilot.pixels[i];
            if (all.finite == 0) continue;
            const glm::dvec3 m = all.radiance / double(all.finite);
            brightness[i] = std::max(0.0, (m.x + m.y + m.z) / 3.0);
            mean += brightness[i];
        }
        mean /= double(n);
        const double floor = settings.relative_floor * mean;
        // A black pilot (mean 0) leaves no weight to give: the differences are 0 there too.
        for (std::size_t i = 0; i < n; ++i) {
            const double denominator = brightness[i] + floor;
            diff[i] = denominator > 0.0 ? diff[i] / denominator : 0.0;
        }
    }
    // Summed-area table, so each window's sum is four lookups.
    const auto ws = static_cast<std::size_t>(w) + 1;
    std::vector<double> table(ws * (static_cast<std::size_t>(h) + 1), 0.0);
    for (int y = 0; y < h; ++y) {
        double row = 0.0;
        for (int x = 0; x < w; ++x) {
            row += diff[std::size_t(y) * std::size_t(w) + std::size_t(x)];
            table[std::size_t(y + 1) * ws + std::size_t(x + 1)] =
                table[std::size_t(y) * ws + std::size_t(x + 1)] + row;
        }
    }
    // The noise scale of each pixel from its neighbours alone (see the header: unbiased).
    const int r = adaptive_radius(settings, w, h);
    std::vector<double> sigma(n, 0.0);
    for (int y = 0; y < h; ++y) {
        const int y0 = std::max(0, y - r);
        const int y1 = std::min(h, y + r + 1);
        for (int x = 0; x < w; ++x) {
            const int x0 = std::max(0, x - r);
            const int x1 = std::min(w, x + r + 1);
            const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
            const double sum = table[std::size_t(y1) * ws + std::size_t(x1)] -
                               table[std::size_t(y0) * ws + std::size_t(x1)] -
                               table[std::size_t(y1) * ws + std::size_t(x0)] +
                               table[std::size_t(y0) * ws + std::size_t(x0)] - diff[i];
            const int others = (y1 - y0) * (x1 - x0) - 1;
            // Rounding in the table can leave a tiny negative sum.
            sigma[i] = others > 0 ? std::sqrt(std::max(0.0, sum / others)) : 0.0;
        }
    }

    // n_p = clamp(floor(c sigma_p), n0, most): the largest c whose total fits the budget
    // (bisection: the total never decreases with c).
    const double most =
        std::min<double>(kMaxSamplesPerPixel, std::floor(settings.max_factor * samples_per_pixel));
    const double budget = double(samples_per_pixel) * double(n);
    const auto count_at = [&](double c, std::size_t i) {
        return std::clamp(std::floor(c * sigma[i]), double(n0), std::max(double(n0), most));
    };
    const auto total_at = [&](double c) {
        double t = 0.0;
        for (std::size_t i = 0; i < n; ++i) t += count_at(c, i);
        return t;
    };
    const double sigma_max = *std::max_element(sigma.begin(), sigma.end());
    std::vector<std::uint32_t> counts(n, n0);
    if (sigma_max <= 0.0) {  // no noise seen anywhere: spread the budget evenly
        std::fill(counts.begin(), counts.end(), std::max(n0, samples_per_pixel));
        return counts;
    }
    double sigma_min = sigma_max;  // the smallest noise seen (> 0)
    for (const double v : sigma) {
        if (v > 0.0) sigma_min = std::min(sigma_min, v);
    }
    // Between every pixel at the pilot's count and every noisy pixel at `most`, halving the
    // ratio hi / lo (the noise can span many orders of magnitude).
    double lo = double(n0) / sigma_max;
    double hi = 2.0 * most / sigma_min;
    if (total_at(hi) > budget) {
        for (int iteration = 0; iteration < 100 && hi > lo * (1.0 + 1e-12); ++iteration) {
            const double mid = std::sqrt(lo * hi);
            (total_at(mid) > budget ? hi : lo) = mid;
        }
    } else {
        lo = hi;
    }
    for (std::size_t i = 0; i < n; ++i) counts[i] = static_cast<std::uint32_t>(count_at(lo, i));
    return counts;
}

}  // namespace librt
