#pragma once

#include <librt/export.h>

#include <glm/vec2.hpp>

#include <vector>

// Pixel reconstruction filters applied by filter importance sampling (as pbrt-v4 does):
// the sub-pixel offset of a camera sample is drawn with density proportional to |f|, so
// each sample carries a constant weight and a pixel stays a plain mean of its samples -
// films from different threads, tiles or machines still merge exactly. Every filter here
// is separable, f(x, y) = f(x) f(y), and is sampled one axis per component of u, by a
// monotone inverse CDF, so a stratified u gives stratified offsets.

namespace librt {

/// The shape of a pixel filter.
enum class FilterKind {
    Box,       ///< constant on [-radius, radius]
    Tent,      ///< 1 - |x| / radius (a triangle)
    Gaussian,  ///< exp(-x^2 / (2 sigma^2)), cut off at the radius (or not, radius = inf)
    Mitchell,  ///< Mitchell-Netravali cubic (B, C) stretched to the radius; has negative lobes
    BlackmanHarris,  ///< the 4-term Blackman-Harris window over [-radius, radius]
    /// smallpt's sub-pixel filter, a trapezoid: flat on |x| <= radius / 3, falling linearly
    /// to 0 at the radius (default 0.75: flat over +-0.25 pixels, 0 at +-0.75).
    Smallpt,
};

/// Everything that defines a pixel filter; offsets and radii are in pixels.
struct FilterSettings {
    FilterKind kind = FilterKind::Box;  ///< the filter's shape
    /// Half-width of the support on each axis, finite and > 0; a Gaussian also accepts
    /// +infinity (not truncated, sampled by Box-Muller exactly like gaussian_pixel_jitter).
    float radius = 0.5f;
    float sigma = 0.5f;              ///< the Gaussian's standard deviation, finite and > 0
    float mitchell_b = 1.0f / 3.0f;  ///< Mitchell-Netravali B, finite
    float mitchell_c = 1.0f / 3.0f;  ///< Mitchell-Netravali C, finite
};

/// Customary settings of each kind: box radius 0.5 (the pixel), tent radius 1, Gaussian
/// sigma 0.5 radius 1.5, Mitchell B = C = 1/3 radius 2, Blackman-Harris radius 1.5, smallpt
/// radius 0.75 (smallpt's own).
[[nodiscard]] LIBRT_API FilterSettings default_filter_settings(FilterKind kind);

/// One sampled sub-pixel offset.
struct FilterSample {
    glm::vec2 offset{0.0f};  ///< from the pixel centre, in pixels, within the radius
    /// What the sample's radiance is multiplied by before the plain per-pixel mean: 1 for
    /// non-negative filters; for Mitchell sign(f(offset)) * (integral |f| / integral f), the
    /// constant making E[weight] = 1, so the mean is the normalised filter's estimate.
    float weight = 1.0f;
};

/// A pixel filter, ready to sample. Immutable after construction; safe to share.
class LIBRT_API PixelFilter {
public:
    /// Validates the settings (throws librt::Error naming the bad parameter and its value)
    /// and, for Mitchell and Blackman-Harris, tabulates |f| for sampling.
    explicit PixelFilter(const FilterSettings& settings = {});

    /// An offset with density |f(offset)| / integral |f| from a uniform u in [0, 1)^2:
    /// x from u.x and y from u.y. Box, tent, Gaussian and smallpt are inverted analytically;
    /// Mitchell and Blackman-Harris through a piecewise-constant table of |f| whose cells
    /// hold |f|'s exact integral (so every cell has the right probability; inside a cell
    /// the offset is uniform) and never straddle a zero of f (so a cell has one sign).
    [[nodiscard]] FilterSample sample(glm::vec2 u) const;

    /// The unnormalised filter f(offset.x) f(offset.y); 0 outside the radius.
    [[nodiscard]] float evaluate(glm::vec2 offset) const {
        return evaluate_1d(offset.x) * evaluate_1d(offset.y);
    }

    /// The unnormalised 1D filter f(x) (f(0) need not be 1); 0 for |x| > radius.
    [[nodiscard]] float evaluate_1d(float x) const;

    /// evaluate_1d in double, unrounded: for weights that must sum exactly (SplatFilm).
    [[nodiscard]] double evaluate_1d_precise(double x) const;

    /// The settings the filter was built from.
    [[nodiscard]] const FilterSettings& settings() const { return settings_; }

private:
    // One axis: an offset in [-radius, radius] and the sign of f there.
    [[nodiscard]] float sample_1d(float u, float& sign) const;
    void build_table();

    FilterSettings settings_;
    std::vector<double> edges_;         // cell boundaries, ascending, from -radius to radius
    std::vector<double> cdf_;           // cdf_[i]: probability of the cells before i; back() = 1
    std::vector<signed char> sign_;     // sign of f in each cell
    float weight_scale_ = 1.0f;         // (integral |f| / integral f)^2, the 2D weight's size
    float gaussian_erf_radius_ = 1.0f;  // erf(radius / (sigma sqrt 2)): the truncation's mass
};

}  // namespace librt
