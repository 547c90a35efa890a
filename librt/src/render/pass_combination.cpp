#include <librt/render/pass_combination.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace librt {

namespace {

// Channels 3i .. 3i + 2 of splat sums, times `scale` (2^-fraction_bits / samples per pixel).
glm::dvec3 splat_value(const std::vector<std::int64_t>& sums, std::size_t i, double scale) {
    return glm::dvec3(double(sums[3 * i]), double(sums[3 * i + 1]), double(sums[3 * i + 2])) *
           scale;
}

// The splat sums of `full` minus those of `half` (the later samples' own), per channel.
glm::dvec3 splat_rest(const std::vector<std::int64_t>& full, const std::vector<std::int64_t>& half,
                      std::size_t i, double scale) {
    return glm::dvec3(double(full[3 * i] - half[3 * i]), double(full[3 * i + 1] - half[3 * i + 1]),
                      double(full[3 * i + 2] - half[3 * i + 2])) *
           scale;
}

}  // namespace

bool PassCombination::add(const Film& half, const Film& full) {
    const std::size_t n = full.pixels.size();
    if (n == 0 || half.pixels.size() != n) return false;
    // A splatting render's estimate is its pixel mean plus its splats over the samples per
    // pixel (resolve()); each half's splats are its own sums over its own samples.
    const bool splats = full.splats.has_value();
    if (splats && (!half.splats || full.splats->sums().size() != 3 * n ||
                   half.splats->sums().size() != 3 * n)) {
        return false;
    }
    const double unit = splats ? std::ldexp(1.0, -full.splats->fraction_bits()) : 0.0;
    const double spp_half = splats ? splat_samples_per_pixel(half) : 0.0;
    const double spp_full = splats ? splat_samples_per_pixel(full) : 0.0;
    if (splats && !(spp_half > 0.0 && spp_full > spp_half)) return false;
    // The variance of the render's pixel mean, averaged over pixels and channels. With a
    // pixel's halves of a and b samples, means m_a and m_b, and sample variance s^2:
    // Var(m_a - m_b) = s^2 (1/a + 1/b) and Var(mean of all) = s^2 / (a + b), so
    // (m_a - m_b)^2 / ((1/a + 1/b)(a + b)) estimates the latter without bias.
    double variance = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const FilmPixel& h = half.pixels[i];
        const FilmPixel& f = full.pixels[i];
        const double a = h.finite, b = double(f.finite) - double(h.finite);
        if (!(a >= 1.0 && b >= 1.0)) return false;
        glm::dvec3 d = h.radiance / a - (f.radiance - h.radiance) / b;
        if (splats) {
            d += splat_value(half.splats->sums(), i, unit / spp_half) -
                 splat_rest(full.splats->sums(), half.splats->sums(), i,
                            unit / (spp_full - spp_half));
        }
        variance += (d.x * d.x + d.y * d.y + d.z * d.z) / (3.0 * (1.0 / a + 1.0 / b) * (a + b));
    }
    variance /= double(n);
    if (!(variance > 0.0) || !std::isfinite(variance)) return false;
    const double w = 1.0 / variance;
    if (sum_.empty()) sum_.assign(n, glm::dvec3(0.0));
    if (sum_.size() != n) return false;
    for (std::size_t i = 0; i < n; ++i) {
        const FilmPixel& f = full.pixels[i];
        glm::dvec3 mean = f.radiance / double(f.finite);
        if (splats) mean += splat_value(full.splats->sums(), i, unit / spp_full);
        sum_[i] += w * mean;
    }
    weight_ += w;
    ++count_;
    return true;
}

Image PassCombination::image(int width, int height) const {
    Image image(width, height);
    for (std::size_t i = 0; i < sum_.size() && i < image.pixels.size(); ++i)
        image.pixels[i] = glm::vec3(sum_[i] / weight_);
    return image;
}

Image PassCombination::combined(const Film& half, const Film& full) const {
    if (count_ == 0) return resolve(full);
    PassCombination with_image = *this;
    return with_image.add(half, full) ? with_image.image(full.width, full.height) : resolve(full);
}

}  // namespace librt
