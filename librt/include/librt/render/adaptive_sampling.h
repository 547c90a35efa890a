#pragma once

#include <librt/export.h>
#include <librt/film/film.h>

#include <cstdint>
#include <vector>

// Adaptive sampling: a render's samples spread over pixels by their noise, for a lower
// error of the whole image at the same number of samples (docs/sampling.md).
//
// A pilot of `pilot` samples in every pixel is rendered in two halves; the difference of
// a pixel's two half means estimates its noise. The rest of the budget goes where the
// noise is. Minimising sum_p w_p sigma_p^2 / n_p for a fixed total gives n_p proportional
// to sqrt(w_p) sigma_p (the Lagrange condition). With w = 1 (AdaptiveMetric::Absolute)
// that is the linear image's mean squared error, where bright pixels (emitters, their
// edges, highlights) weigh most; the default, AdaptiveMetric::Relative, weighs each pixel
// by 1 / (its brightness + a floor), the squared slope of a square-root encoding: the
// error of the image as displayed (sRGB is about x^(1 / 2.2), a tone curve compresses the
// highlights further), where an error in a shadow shows more than one beside a light.
//
// Unbiased, not only consistent: a pixel's count is computed from its *neighbours'* pilot
// halves, never its own. Pixels' samples are independent (seeded by pixel), so a pixel's
// count is independent of its own samples and its mean stays an unbiased estimate. A
// count computed from the pixel's own pilot would not be: a pilot that happened to catch a
// firefly would draw more samples, which dilute it, so bright outliers are shrunk and dark
// ones are not.
//
// One exception: an integrator that splats (bidirectional path tracing). A sample's light
// subpath both joins its own pixel's value, which steers its neighbours' counts, and
// splats anywhere, and the splats are divided by the mean count: the splatted part of the
// image is consistent (the bias falls with the samples) but not strictly unbiased.

namespace librt {

/// The image error that adaptive sampling's counts minimise.
enum class AdaptiveMetric {
    /// The mean squared error of the linear radiance (the counts before 7 December 2026).
    Absolute,
    /// Each pixel's squared error over (its brightness + relative_floor x the image's mean
    /// brightness): the error of the displayed image (see above). At equal samples it lowered
    /// the displayed error on every shared glTF scene (docs/benchmarks.md).
    Relative,
};

/// How render() spreads samples (RenderSettings::adaptive). On by default: at equal time it
/// lowered the error on every scene measured (docs/sampling.md, "Adaptive sampling").
struct AdaptiveSampling {
    bool enabled = true;  ///< spread samples by noise; samples_per_pixel is then the mean
    /// Samples every pixel gets before the noise is estimated (even, >= 2, below
    /// samples_per_pixel); 0 = the largest power of two <= samples_per_pixel / 4, at least
    /// 2 (a power of two keeps a Sobol' pilot a whole net in each half). It is also the
    /// fewest samples a pixel gets: a floor against noise the pilot did not see.
    int pilot_samples = 0;
    /// Pixels within this distance (a (2r + 1)^2 square, the pixel itself left out) whose
    /// pilots estimate a pixel's noise, in [1, 16], or 0: the image's larger side / 40,
    /// rounded, within [2, 16] (adaptive_radius). A pilot's noise estimate of one pixel is
    /// itself noisy, and a wide window blurs the noise of small features: radii 8-12 did
    /// best on the report's 512 x 512 synthesis, 2-3 on the 128 x 128 glTF scenes
    /// (docs/sampling.md, docs/benchmarks.md).
    int radius = 0;
    /// What the counts minimise (above).
    AdaptiveMetric metric = AdaptiveMetric::Relative;
    /// AdaptiveMetric::Relative: the brightness floor as a fraction of the pilot image's mean
    /// brightness (finite, > 0), so that black pixels do not take the whole budget and the
    /// counts do not change with the scene's units. Brightness: the mean of the channels.
    double relative_floor = 0.1;
    /// Most samples a pixel may get, as a multiple of samples_per_pixel, in [1, 1024].
    double max_factor = 8.0;
};

/// Throws librt::Error naming the first bad field and its value.
LIBRT_API void validate(const AdaptiveSampling& settings);

/// The neighbourhood radius used for a `width` x `height` image: the setting, or for 0 the
/// larger side / 40, rounded, clamped to [2, 16].
[[nodiscard]] LIBRT_API int adaptive_radius(const AdaptiveSampling& settings, int width,
                                            int height);

/// The pilot's samples per pixel for a render of `samples_per_pixel` (the mean): the
/// setting, or its default; 0 when the render is too small to adapt (below 4 samples per
/// pixel, or a pilot not below the mean), and render() then samples every pixel equally.
[[nodiscard]] LIBRT_API std::uint32_t adaptive_pilot_samples(const AdaptiveSampling& settings,
                                                             std::uint32_t samples_per_pixel);

/// The number of samples each pixel should hold (row-major, top row first): at least
/// `pilot.samples` of each pixel, at most max_factor x samples_per_pixel (and 2^20), the
/// rest in proportion to the (weighted, `settings.metric`) noise estimated from the
/// neighbours' pilots, all together at
/// most samples_per_pixel x pixels. `first_half` is the film after the first half of the
/// pilot's samples, `pilot` after all of them (each pixel holding the same count in each).
/// Deterministic: the same films give the same counts. Throws librt::Error when the films'
/// sizes differ or a pixel's count is not the pilot's.
[[nodiscard]] LIBRT_API std::vector<std::uint32_t> adaptive_sample_counts(
    const Film& first_half, const Film& pilot, std::uint32_t samples_per_pixel,
    const AdaptiveSampling& settings);

}  // namespace librt
