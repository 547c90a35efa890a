#include <librt/render/pass_combination.h>

#include <cmath>
#include <cstddef>

namespace librt {

bool PassCombination::add(const Film& half, const Film& full) {
    const std::size_t n = full.pixels.size();
    if (n == 0 || half.pixels.size() != n) return false;
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
        const glm::dvec3 d = h.radiance / a - (f.radiance - h.radiance) / b;
        variance += (d.x * d.x + d.y * d.y + d.z * d.z) / (3.0 * (1.0 / a + 1.0 / b) * (a + b));
    }
    variance /= double(n);
    if (!(variance > 0.0) || !std::isfinite(variance)) return false;
    const double w = 1.0 / variance;
    if (sum_.empty()) sum_.assign(n, glm::dvec3(0.0));
    if (sum_.size() != n) return false;
    for (std::size_t i = 0; i < n; ++i) {
        const FilmPixel& f = full.pixels[i];
        sum_[i] += w * (f.radiance / double(f.finite));
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
