#pragma once

#include <librt/core/image.h>
#include <librt/export.h>
#include <librt/sampling/filter.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <vector>

// A film for contributions that land on arbitrary pixels (light tracing, the t = 1
// strategies of bidirectional path tracing), which many threads add to at once.
//
// Why integers. Film (film.h) stays bit-identical for any thread count because each pixel
// sums its own samples in sample order; a splat comes from any thread's light path in any
// order, and float or double sums depend on the order. Here every pixel and channel holds
// a signed 64-bit fixed-point sum: a splat is rounded once to a multiple of 2^-k (k =
// fraction_bits) and added as an integer. Integer addition is associative and exact, so
// the sums - and the resolved image - are the same bits whatever the order, thread count
// or split, and merging films is exact too. Adds are atomic (std::atomic_ref, relaxed:
// only the final sums matter, read after the threads are joined).
//
// The scale, k = 28 by default. A sum's rounding error is at most 2^-(k+1) per splat term,
// so a resolved pixel (sum / spp) is off by at most (terms per pixel / spp) 2^-(k+1): about
// the filter footprint (1 to 36 pixels) times 2^-29 = 1.9e-9, i.e. <= 6.7e-8 - below a
// float's own rounding of a value of 1 and 15 stops below a display's 8-bit step. The
// headroom is 2^(63-k) = 2^35 = 3.4e10 per sum: a mean of 5e5 at 65536 samples per pixel,
// beyond any directly seen emitter of the scenes here. Other trade-offs pass fraction_bits.
//
// Saturation. A splat term beyond the range is clipped to +-(2^63 - 1), and a sum that
// would pass a bound stays at it (sticky), so an overflowing pixel shows as the bound and
// not as wrapped-around garbage; clipped() counts the splats that lost anything this way.
// For non-negative splats (radiance, non-negative filters) the partial sums only grow, so
// a saturated pixel is the same bound in every order; only Mitchell's negative lobes could
// make saturation order-dependent, and they saturate only past the headroom above.
// Splats with a NaN or infinite raster position or value are counted (non_finite()) and
// dropped, never stored.
//
// Filtering. add(raster, v) gives pixel (j, i) the value v f(raster - centre(j, i)) /
// integral f, centre(j, i) = (j + 0.5, i + 0.5), f the separable pixel filter of
// sampling/filter.h over the half-open support [-r, r)^2 (so a box of radius 0.5 gives
// exactly the containing pixel, [j, j + 1) x [i, i + 1)). Dividing by the integral, not by
// the sum of the weights the splat lands on, makes pixel (j, i) the same filtered integral
// as filter importance sampling's camera samples; the weights of one splat then sum to 1
// exactly for box and tent (a partition of unity) and on average over the pixel for the
// others (a Gaussian of sigma 0.5 ripples by +-1.4% per axis, Poisson summation: 2
// exp(-2 pi^2 sigma^2)). A Gaussian of infinite radius (the camera's PixelJitter::Gaussian)
// is truncated at the smallest radius (a multiple of sigma / 100) where the 2D mass lost,
// 1 - erf(r / (sigma sqrt 2))^2, is below 1e-6 (r = 5.03 sigma), and normalised over it.
//
// Resolving (the convention). resolve(spp) is sum / spp per pixel. A light tracer that
// traces N = spp W H light paths and adds each connection's film estimate C (the integral
// over the whole film: camera_importance.h) gets sum / spp = (1 / N) sum C W H h: pixel
// values in the units of Film's. In bidirectional path tracing each of the spp W H camera
// samples brings one light path, so the same spp resolves its splats.

namespace librt {

/// Per-pixel fixed-point splat sums. add() is safe to call from many threads at once;
/// every other member needs the film to be left alone by other threads meanwhile.
class LIBRT_API SplatFilm {
public:
    /// Fraction bits of the default scale, 2^-28 (see the top of this header).
    static constexpr int kDefaultFractionBits = 28;
    /// Largest filter radius, in pixels, the film splats over.
    static constexpr float kMaxRadius = 32.0f;
    /// The lost 2D mass at which a Gaussian of infinite radius is truncated.
    static constexpr double kTruncatedMass = 1e-6;

    /// An empty 0x0 film.
    SplatFilm() = default;
    /// A zero width x height film splatting with `filter`, sums in units of
    /// 2^-fraction_bits. Throws librt::Error naming the bad parameter: a negative side, a
    /// film over Film::kMaxBytes, a filter PixelFilter rejects or wider than kMaxRadius,
    /// fraction_bits outside [0, 62].
    SplatFilm(int width, int height, const FilterSettings& filter = {},
              int fraction_bits = kDefaultFractionBits);

    /// Adds `value` at continuous raster position `raster` (pixel (j, i) covers [j, j + 1)
    /// x [i, i + 1)), spread by the filter; parts off the film are dropped. Thread-safe.
    void add(glm::vec2 raster, const glm::vec3& value);

    /// Adds every sum of `other` (integer additions: exact, saturating as add() does) and
    /// its counts; the clips of this merge count in clipped(). Throws librt::Error when the
    /// size, filter or fraction_bits differ; this film is then unchanged.
    void merge(const SplatFilm& other);

    /// merge() of raw sums: adds `sums` (another film's sums(), e.g. received from another
    /// process, of the same size, filter and fraction_bits - which this cannot check) and its
    /// counts. Throws librt::Error when sums.size() is not 3 width height; this film is then
    /// unchanged.
    void merge_sums(std::span<const std::int64_t> sums, std::uint64_t clipped,
                    std::uint64_t non_finite);

    /// The image: each pixel's sums times 2^-fraction_bits divided by samples_per_pixel
    /// (finite, > 0; throws librt::Error otherwise), as float.
    [[nodiscard]] Image resolve(double samples_per_pixel) const;

    /// Pixels per row.
    [[nodiscard]] int width() const { return width_; }
    /// Number of rows.
    [[nodiscard]] int height() const { return height_; }
    /// The filter the film was built with.
    [[nodiscard]] const FilterSettings& filter() const { return filter_.settings(); }
    /// The radius splats reach, in pixels: the filter's, or the truncation's.
    [[nodiscard]] double radius() const { return radius_; }
    /// How far outside the image, in pixels, a raster position can still reach a pixel
    /// centre: max(0, radius - 0.5). Pass it to raster_of / sample_wi as their margin.
    [[nodiscard]] float margin() const;
    /// The scale's exponent: sums are in units of 2^-fraction_bits.
    [[nodiscard]] int fraction_bits() const { return fraction_bits_; }
    /// The raw sums, 3 per pixel (r, g, b), row-major, top row first.
    [[nodiscard]] const std::vector<std::int64_t>& sums() const { return sums_; }
    /// Splats (and merged sums) that were clipped at a bound.
    [[nodiscard]] std::uint64_t clipped() const { return clipped_; }
    /// Splats dropped for a NaN or infinite raster position or value.
    [[nodiscard]] std::uint64_t non_finite() const { return non_finite_; }

private:
    int width_ = 0;
    int height_ = 0;
    int fraction_bits_ = kDefaultFractionBits;
    PixelFilter filter_;
    double radius_ = 0.5;             // the support's half-width, truncated for a Gaussian
    double inverse_area_ = 1.0;       // 1 / (integral of the 1D filter over the support)^2
    double scale_ = 0x1p28;           // 2^fraction_bits
    std::vector<std::int64_t> sums_;  // 3 per pixel; accessed through std::atomic_ref
    std::uint64_t clipped_ = 0;       // accessed through std::atomic_ref
    std::uint64_t non_finite_ = 0;    // accessed through std::atomic_ref
};

}  // namespace librt
