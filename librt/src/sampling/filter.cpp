#include <librt/core/constants.h>
#include <librt/core/error.h>
#include <librt/sampling/filter.h>
#include <librt/sampling/jitter.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>

namespace librt {

namespace {

[[noreturn]] void fail(const char* name, float value, const char* rule) {
    std::ostringstream out;
    out << "filter " << name << " = " << value << ": " << rule;
    throw Error(out.str());
}

// The 1D filter in double, shared by evaluation and tabulation.
double filter_value(const FilterSettings& s, double x) {
    const double r = s.radius;
    const double ax = std::abs(x);
    if (!(ax <= r)) return 0.0;
    switch (s.kind) {
        case FilterKind::Box:
            return 1.0;
        case FilterKind::Tent:
            return 1.0 - ax / r;
        case FilterKind::Gaussian: {
            const double sigma = s.sigma;
            return std::exp(-x * x / (2.0 * sigma * sigma));
        }
        case FilterKind::Mitchell: {
            // Mitchell and Netravali 1988, "Reconstruction filters in computer graphics",
            // eq. 8: a cubic on |t| <= 2, here t = 2 x / radius.
            const double b = s.mitchell_b, c = s.mitchell_c;
            const double t = 2.0 * ax / r;
            if (t < 1.0) {
                return ((12.0 - 9.0 * b - 6.0 * c) * t * t * t +
                        (-18.0 + 12.0 * b + 6.0 * c) * t * t + (6.0 - 2.0 * b)) /
                       6.0;
            }
            return ((-b - 6.0 * c) * t * t * t + (6.0 * b + 30.0 * c) * t * t +
                    (-12.0 * b - 48.0 * c) * t + (8.0 * b + 24.0 * c)) /
                   6.0;
        }
        case FilterKind::BlackmanHarris: {
            // The 4-term Blackman-Harris window (Harris 1978, "On the use of windows for
            // harmonic analysis with the DFT", table 1: -92 dB), over t in [0, 1].
            const double t = (x + r) / (2.0 * r);
            const double w = 2.0 * kPiDouble * t;
            return 0.35875 - 0.48829 * std::cos(w) + 0.14128 * std::cos(2.0 * w) -
                   0.01168 * std::cos(3.0 * w);
        }
        case FilterKind::Smallpt:
            // smallpt's radiance loop (Kevin Beason's smallpt.cpp) puts a sample of pixel x
            // at x + (s + 0.5 + d) / 2, s in {0, 1} the sub-pixel column and d a tent on
            // [-1, 1]: from the pixel centre x + 0.5 that is -+0.25 + d / 2, an equal
            // mixture of two tents of half-width 0.5 centred at -+0.25. Their mean density
            // is 1 on |x| <= 0.25 (the two slopes cancel) and 1.5 - 2 |x| on
            // 0.25 <= |x| <= 0.75: a trapezoid, also a box of half-width 0.25 convolved
            // with one of half-width 0.5. Here stretched to the radius (0.75 is smallpt's);
            // at radius 0.75 this f is the normalised density itself.
            return ax <= r / 3.0 ? 1.0 : 1.5 * (1.0 - ax / r);
    }
    return 0.0;
}

// Inverse error function in float: Giles 2010 ("Approximating the erfinv function", GPU
// Computing Gems Jade), the single-precision polynomials, accurate to a few float ulps -
// as exact as the float offset it becomes, at a tenth of the cost of a Newton-refined
// double (measured by BM_PixelFilterSample).
float erfinv(float y) {
    float w = -std::log((1.0f - y) * (1.0f + y));
    float p;
    if (w < 5.0f) {
        w -= 2.5f;
        p = 2.81022636e-08f;
        p = 3.43273939e-07f + p * w;
        p = -3.5233877e-06f + p * w;
        p = -4.39150654e-06f + p * w;
        p = 0.00021858087f + p * w;
        p = -0.00125372503f + p * w;
        p = -0.00417768164f + p * w;
        p = 0.246640727f + p * w;
        p = 1.50140941f + p * w;
    } else {
        w = std::sqrt(w) - 3.0f;
        p = -0.000200214257f;
        p = 0.000100950558f + p * w;
        p = 0.00134934322f + p * w;
        p = -0.00367342844f + p * w;
        p = 0.00573950773f + p * w;
        p = -0.0076224613f + p * w;
        p = 0.00943887047f + p * w;
        p = 1.00167406f + p * w;
        p = 2.83297682f + p * w;
    }
    return p * y;
}

}  // namespace

FilterSettings default_filter_settings(FilterKind kind) {
    FilterSettings s;
    s.kind = kind;
    switch (kind) {
        case FilterKind::Box:
            s.radius = 0.5f;
            break;
        case FilterKind::Tent:
            s.radius = 1.0f;
            break;
        case FilterKind::Gaussian:
            s.radius = 1.5f;
            break;
        case FilterKind::Mitchell:
            s.radius = 2.0f;
            break;
        case FilterKind::BlackmanHarris:
            s.radius = 1.5f;
            break;
        case FilterKind::Smallpt:
            s.radius = 0.75f;
            break;
    }
    return s;
}

PixelFilter::PixelFilter(const FilterSettings& settings) : settings_(settings) {
    const FilterSettings& s = settings_;
    const int kind = static_cast<int>(s.kind);
    if (kind < static_cast<int>(FilterKind::Box) || kind > static_cast<int>(FilterKind::Smallpt)) {
        fail("kind", static_cast<float>(kind), "is not a FilterKind");
    }
    const bool infinite_ok =
        s.kind == FilterKind::Gaussian && s.radius == std::numeric_limits<float>::infinity();
    if (!(s.radius > 0.0f) || !(std::isfinite(s.radius) || infinite_ok)) {
        fail("radius", s.radius,
             s.kind == FilterKind::Gaussian ? "must be > 0 (or +infinity for a Gaussian)"
                                            : "must be finite and > 0");
    }
    if (s.kind == FilterKind::Gaussian && (!(s.sigma > 0.0f) || !std::isfinite(s.sigma))) {
        fail("sigma", s.sigma, "must be finite and > 0");
    }
    if (s.kind == FilterKind::Mitchell) {
        if (!std::isfinite(s.mitchell_b)) fail("mitchell_b", s.mitchell_b, "must be finite");
        if (!std::isfinite(s.mitchell_c)) fail("mitchell_c", s.mitchell_c, "must be finite");
    }
    if (s.kind == FilterKind::Mitchell || s.kind == FilterKind::BlackmanHarris) build_table();
    if (s.kind == FilterKind::Gaussian && std::isfinite(s.radius)) {
        gaussian_erf_radius_ = static_cast<float>(
            std::erf(static_cast<double>(s.radius) / (std::numbers::sqrt2 * s.sigma)));
    }
}

void PixelFilter::build_table() {
    const FilterSettings& s = settings_;
    const double r = s.radius;
    // 512 cells: the uniform-within-a-cell approximation moves probability by O(cell^2 f')
    // inside a cell and none between cells, far below what any test or image can see.
    constexpr int kCells = 512;
    edges_.clear();
    for (int i = 0; i <= kCells; ++i) edges_.push_back(-r + 2.0 * r * i / kCells);
    const auto f = [&](double x) { return filter_value(s, x); };
    // Extra edges where f changes sign (found by bisection) and, for Mitchell, at the
    // cubic's knots t = +-1, so every cell has one sign and a smooth |f|.
    std::vector<double> extra;
    for (int i = 0; i < kCells; ++i) {
        double a = edges_[i], b = edges_[i + 1];
        if (!(f(a) * f(b) < 0.0)) continue;
        for (int k = 0; k < 60; ++k) {
            const double m = 0.5 * (a + b);
            (f(a) * f(m) <= 0.0 ? b : a) = m;
        }
        extra.push_back(0.5 * (a + b));
    }
    if (s.kind == FilterKind::Mitchell) {
        extra.push_back(-0.5 * r);
        extra.push_back(0.5 * r);
    }
    edges_.insert(edges_.end(), extra.begin(), extra.end());
    std::sort(edges_.begin(), edges_.end());
    edges_.erase(std::unique(edges_.begin(), edges_.end()), edges_.end());

    // Each cell's exact mass of |f| by 5-point Gauss-Legendre (exact for polynomials up to
    // degree 9, so for Mitchell's cubic pieces; spectrally accurate for the cosines).
    static constexpr std::array<double, 5> kNodes{0.0, -0.5384693101056831, 0.5384693101056831,
                                                  -0.9061798459386640, 0.9061798459386640};
    static constexpr std::array<double, 5> kWeights{0.5688888888888889, 0.4786286704993665,
                                                    0.4786286704993665, 0.2369268850561891,
                                                    0.2369268850561891};
    const std::size_t n = edges_.size() - 1;
    cdf_.assign(n + 1, 0.0);
    sign_.assign(n, 1);
    double total_abs = 0.0, total_signed = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double half = 0.5 * (edges_[i + 1] - edges_[i]);
        const double mid = 0.5 * (edges_[i + 1] + edges_[i]);
        double mass = 0.0;
        for (std::size_t k = 0; k < kNodes.size(); ++k) {
            mass += kWeights[k] * std::abs(f(mid + half * kNodes[k]));
        }
        mass *= half;
        sign_[i] = f(mid) < 0.0 ? -1 : 1;
        total_abs += mass;
        total_signed += sign_[i] * mass;
        cdf_[i + 1] = total_abs;
    }
    if (!(total_signed > 0.0)) {
        fail("mitchell_b", s.mitchell_b, "with this C integrates to <= 0: cannot be normalised");
    }
    for (double& c : cdf_) c /= total_abs;
    cdf_.back() = 1.0;
    // E[sign] = total_signed / total_abs per axis; scaling by its inverse makes E[weight] = 1.
    const double scale = total_abs / total_signed;
    weight_scale_ = static_cast<float>(scale * scale);
}

float PixelFilter::evaluate_1d(float x) const {
    return static_cast<float>(filter_value(settings_, x));
}

double PixelFilter::evaluate_1d_precise(double x) const { return filter_value(settings_, x); }

float PixelFilter::sample_1d(float u, float& sign) const {
    const FilterSettings& s = settings_;
    const float r = s.radius;
    sign = 1.0f;
    switch (s.kind) {
        case FilterKind::Box:
            return r * (2.0f * u - 1.0f);
        case FilterKind::Tent:
            // Inverse CDF of the triangle: each half holds probability 1/2, and
            // F(x) = (1 + x/r)^2 / 2 on the left half.
            if (u < 0.5f) return r * (std::sqrt(2.0f * u) - 1.0f);
            return r * (1.0f - std::sqrt(2.0f - 2.0f * u));
        case FilterKind::Gaussian: {
            // Truncated normal by inversion: erf(x / (sigma sqrt 2)) uniform on
            // [-erf(r / (sigma sqrt 2)), erf(r / (sigma sqrt 2))].
            const float x = s.sigma * std::numbers::sqrt2_v<float> *
                            erfinv((2.0f * u - 1.0f) * gaussian_erf_radius_);
            return std::clamp(x, -r, r);
        }
        case FilterKind::Smallpt: {
            // Inverse CDF of the trapezoid in units of 4 r / 3 (where it is smallpt's, of
            // radius 0.75): F(x) = (x + 0.75)^2 on the left slope (mass 1/4), x + 0.5 on
            // the flat top (mass 1/2), 1 - (0.75 - x)^2 on the right slope. Monotone,
            // unlike smallpt's own draw (sub-pixel first, then tent), so that a stratified
            // u gives stratified offsets.
            float x;
            if (u < 0.25f) {
                x = std::sqrt(u) - 0.75f;
            } else if (u <= 0.75f) {
                x = u - 0.5f;
            } else {
                x = 0.75f - std::sqrt(1.0f - u);
            }
            return std::clamp(x * (r / 0.75f), -r, r);
        }
        case FilterKind::Mitchell:
        case FilterKind::BlackmanHarris:
            break;
    }
    const double ud = u;
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), ud);
    const std::size_t last = sign_.size() - 1;
    const std::size_t i = std::min(
        last, static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - cdf_.begin() - 1, 0)));
    const double mass = cdf_[i + 1] - cdf_[i];
    const double t = mass > 0.0 ? std::clamp((ud - cdf_[i]) / mass, 0.0, 1.0) : 0.5;
    sign = sign_[i];
    const double x = edges_[i] + t * (edges_[i + 1] - edges_[i]);
    return std::clamp(static_cast<float>(x), -r, r);
}

FilterSample PixelFilter::sample(glm::vec2 u) const {
    if (settings_.kind == FilterKind::Gaussian && std::isinf(settings_.radius)) {
        // Untruncated: the same expression as gaussian_pixel_jitter, so the camera's
        // PixelJitter::Gaussian and this filter draw bit-identical offsets.
        return {settings_.sigma * box_muller(u), 1.0f};
    }
    float sx = 1.0f, sy = 1.0f;
    const float x = sample_1d(u.x, sx);
    const float y = sample_1d(u.y, sy);
    return {{x, y}, sx * sy * weight_scale_};
}

}  // namespace librt
