#include <librt/core/error.h>
#include <librt/film/film.h>
#include <librt/film/splat_film.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace librt {

namespace {

// The bounds a sum saturates at; symmetric, so -(2^63) is never used.
constexpr std::int64_t kBound = std::numeric_limits<std::int64_t>::max();

static_assert(std::atomic_ref<std::int64_t>::required_alignment <= alignof(std::int64_t));
static_assert(std::atomic_ref<std::uint64_t>::required_alignment <= alignof(std::uint64_t));

// Pixels a splat reaches on one axis at most: 2 radius + 1 for the half-open support.
constexpr int kMaxSpan = 2 * static_cast<int>(SplatFilm::kMaxRadius) + 2;

// The support's half-width: the filter's radius, or for an infinite Gaussian the smallest
// multiple of sigma / 100 whose lost 2D mass 1 - erf(r / (sigma sqrt 2))^2 is below
// SplatFilm::kTruncatedMass.
double support_radius(const FilterSettings& f) {
    if (std::isfinite(f.radius)) return f.radius;
    int hundredths = 100;
    for (;; ++hundredths) {
        const double kept = std::erf(hundredths / 100.0 / std::numbers::sqrt2);
        if (1.0 - kept * kept < SplatFilm::kTruncatedMass) break;
    }
    return hundredths / 100.0 * f.sigma;
}

// Integral of the 1D filter over [-r, r]: 5-point Gauss-Legendre on 2048 equal cells
// (exact for box, tent and Mitchell, whose knots 0 and +-r/2 are cell edges and whose
// pieces are cubics; spectrally accurate for the Gaussian and Blackman-Harris; smallpt's
// knots +-r/3 fall inside cells, off by 6e-9 of the integral).
double integral_1d(const PixelFilter& filter, double r) {
    static constexpr std::array<double, 5> kNodes{0.0, -0.5384693101056831, 0.5384693101056831,
                                                  -0.9061798459386640, 0.9061798459386640};
    static constexpr std::array<double, 5> kWeights{0.5688888888888889, 0.4786286704993665,
                                                    0.4786286704993665, 0.2369268850561891,
                                                    0.2369268850561891};
    constexpr int kCells = 2048;
    const double half = r / kCells;  // half a cell's width
    double total = 0.0;
    for (int i = 0; i < kCells; ++i) {
        const double mid = -r + (2 * i + 1) * half;
        double cell = 0.0;
        for (std::size_t k = 0; k < kNodes.size(); ++k) {
            cell += kWeights[k] * filter.evaluate_1d_precise(mid + half * kNodes[k]);
        }
        total += cell * half;
    }
    return total;
}

// Adds q to the sum, saturating at +-kBound; a sum at a bound stays there. Returns true
// when anything of q was lost. Lock-free: a compare-and-swap loop on the one word.
bool saturating_add(std::int64_t& slot, std::int64_t q) {
    if (q == 0) return false;
    std::atomic_ref<std::int64_t> sum(slot);
    std::int64_t old = sum.load(std::memory_order_relaxed);
    for (;;) {
        if (old == kBound || old == -kBound) return true;
        // Overflow tests that cannot overflow themselves: |q| <= kBound.
        const bool over = (q > 0 && old > kBound - q) || (q < 0 && old < -kBound - q);
        const std::int64_t next = over ? (q > 0 ? kBound : -kBound) : old + q;
        if (sum.compare_exchange_weak(old, next, std::memory_order_relaxed)) return over;
    }
}

void count(std::uint64_t& counter) {
    std::atomic_ref<std::uint64_t>(counter).fetch_add(1, std::memory_order_relaxed);
}

}  // namespace

SplatFilm::SplatFilm(int width, int height, const FilterSettings& filter, int fraction_bits)
    : width_(width), height_(height), fraction_bits_(fraction_bits) {
    // The same size rule as Film: 3 sums of 8 bytes per pixel, under Film::kMaxBytes.
    const std::string size = std::to_string(width) + " x " + std::to_string(height);
    if (width < 0 || height < 0) {
        throw Error("splat film size " + size + ": width and height must be >= 0");
    }
    constexpr std::uint64_t kPerPixel = 3 * sizeof(std::int64_t);
    const auto w = static_cast<std::uint64_t>(width);
    const auto h = static_cast<std::uint64_t>(height);
    if (w > 0 && h > Film::kMaxBytes / kPerPixel / w) {
        throw Error("splat film size " + size + ": more than the 16 GiB limit");
    }
    if (fraction_bits < 0 || fraction_bits > 62) {
        throw Error("splat film fraction_bits = " + std::to_string(fraction_bits) +
                    ": must be in [0, 62]");
    }
    try {
        filter_ = PixelFilter(filter);
    } catch (const Error& e) {
        throw Error(std::string("splat film filter: ") + e.what());
    }
    radius_ = support_radius(filter);
    if (!(radius_ <= kMaxRadius)) {
        throw Error("splat film filter radius = " + std::to_string(radius_) +
                    ": must be <= 32 pixels");
    }
    // Separable: the 2D integral is the 1D one squared.
    const double area = integral_1d(filter_, radius_);
    inverse_area_ = 1.0 / (area * area);
    scale_ = std::ldexp(1.0, fraction_bits);
    sums_.assign(3 * static_cast<std::size_t>(w * h), 0);
}

float SplatFilm::margin() const { return static_cast<float>(std::max(0.0, radius_ - 0.5)); }

void SplatFilm::add(glm::vec2 raster, const glm::vec3& value) {
    if (!std::isfinite(raster.x) || !std::isfinite(raster.y) || !std::isfinite(value.x) ||
        !std::isfinite(value.y) || !std::isfinite(value.z)) {
        count(non_finite_);
        return;
    }
    const double x = raster.x, y = raster.y, r = radius_;
    // Pixels whose centre c = j + 0.5 has x - c in [-r, r): j in (x - r - 0.5, x + r - 0.5].
    const double j_first = std::floor(x - r - 0.5) + 1.0, j_last = std::floor(x + r - 0.5);
    const double i_first = std::floor(y - r - 0.5) + 1.0, i_last = std::floor(y + r - 0.5);
    const int j0 = static_cast<int>(std::max(j_first, 0.0));
    const int j1 = static_cast<int>(std::min(j_last, width_ - 1.0));
    const int i0 = static_cast<int>(std::max(i_first, 0.0));
    const int i1 = static_cast<int>(std::min(i_last, height_ - 1.0));
    if (j0 > j1 || i0 > i1) return;  // entirely off the film (or an empty film)
    // The 1D weights once per axis (spans are <= kMaxSpan by the radius limit).
    std::array<double, kMaxSpan> wx{}, wy{};
    for (int j = j0; j <= j1; ++j) wx[j - j0] = filter_.evaluate_1d_precise(x - (j + 0.5));
    for (int i = i0; i <= i1; ++i) wy[i - i0] = filter_.evaluate_1d_precise(y - (i + 0.5));
    const std::array<double, 3> v{value.x, value.y, value.z};
    bool clipped = false;
    for (int i = i0; i <= i1; ++i) {
        for (int j = j0; j <= j1; ++j) {
            // This pixel's share, v f(dx) f(dy) / integral f, in units of 2^-k.
            const double w = wx[j - j0] * wy[i - i0] * inverse_area_ * scale_;
            const std::size_t base =
                3 * (static_cast<std::size_t>(i) * static_cast<std::size_t>(width_) +
                     static_cast<std::size_t>(j));
            for (int c = 0; c < 3; ++c) {
                const double term = v[c] * w;
                std::int64_t q;
                // 2^63 is the first double a int64 cannot hold.
                if (std::abs(term) < 0x1p63) {
                    q = std::llround(term);
                } else {
                    q = term > 0.0 ? kBound : -kBound;
                    clipped = true;
                }
                clipped |= saturating_add(sums_[base + c], q);
            }
        }
    }
    if (clipped) count(clipped_);
}

void SplatFilm::merge(const SplatFilm& other) {
    if (other.width_ != width_ || other.height_ != height_) {
        throw Error("cannot merge a " + std::to_string(other.width_) + " x " +
                    std::to_string(other.height_) + " splat film into a " + std::to_string(width_) +
                    " x " + std::to_string(height_) + " one");
    }
    const FilterSettings& a = filter_.settings();
    const FilterSettings& b = other.filter_.settings();
    const bool same_filter = a.kind == b.kind && a.radius == b.radius && a.sigma == b.sigma &&
                             a.mitchell_b == b.mitchell_b && a.mitchell_c == b.mitchell_c;
    if (!same_filter) throw Error("cannot merge splat films with different filters");
    if (other.fraction_bits_ != fraction_bits_) {
        throw Error("cannot merge splat films with fraction_bits " +
                    std::to_string(other.fraction_bits_) + " and " +
                    std::to_string(fraction_bits_));
    }
    merge_sums(other.sums_, other.clipped_, other.non_finite_);
}

void SplatFilm::merge_sums(std::span<const std::int64_t> sums, std::uint64_t clipped,
                           std::uint64_t non_finite) {
    if (sums.size() != sums_.size()) {
        throw Error("cannot merge " + std::to_string(sums.size()) + " splat sums into a " +
                    std::to_string(width_) + " x " + std::to_string(height_) +
                    " splat film (3 per pixel)");
    }
    for (std::size_t k = 0; k < sums_.size(); ++k) {
        if (saturating_add(sums_[k], sums[k])) ++clipped_;
    }
    clipped_ += clipped;
    non_finite_ += non_finite;
}

Image SplatFilm::resolve(double samples_per_pixel) const {
    if (!(samples_per_pixel > 0.0) || !std::isfinite(samples_per_pixel)) {
        throw Error("splat film samples_per_pixel = " + std::to_string(samples_per_pixel) +
                    ": must be finite and > 0");
    }
    Image image(width_, height_);
    // One factor, 2^-k / spp: the same double operations for every pixel.
    const double factor = 1.0 / (scale_ * samples_per_pixel);
    for (std::size_t p = 0; p < image.pixels.size(); ++p) {
        image.pixels[p] = glm::vec3(static_cast<float>(double(sums_[3 * p]) * factor),
                                    static_cast<float>(double(sums_[3 * p + 1]) * factor),
                                    static_cast<float>(double(sums_[3 * p + 2]) * factor));
    }
    return image;
}

}  // namespace librt
