#pragma once

// The noise of a film being rendered, estimated from its own samples: what
// ProgressiveSettings::noise_target (rt_render --noise-target) stops on and what the
// progress display shows.
//
// The estimate is the image's relative error as the denoising literature measures it
// (relMSE, Rousselle et al. 2011): e^2 = mean over pixels and channels of
// Var(pixel mean) / (mean^2 + 0.01), the 0.01 keeping dark pixels from dominating. A pixel's
// per-sample variance comes from two disjoint runs of its own samples: the snapshot at
// level H (its first H_p samples) and the samples added since (L_p - H_p); for independent
// samples E[(m1 - m2)^2] = sigma^2 (1 / H_p + 1 / (L_p - H_p)). The snapshot is renewed each
// time the render's level doubles, so each estimate uses the latest half of the samples.
// Sobol' samples are stratified, so the difference of two runs overstates the error of
// their mean: the estimate errs on the safe side (the render runs longer, never shorter).
// Each pixel's estimate has one degree of freedom and is noisy; their mean over the image
// is not (its relative spread is about sqrt(2 / pixels)).

#include <librt/export.h>
#include <librt/film/film.h>

#include <cstdint>
#include <optional>
#include <vector>

namespace librt {

/// Follows a film through the passes of a render and estimates its relative error.
class LIBRT_API NoiseEstimate {
public:
    /// Looks at `film` once every pixel holds the samples of render level `level` (the
    /// progressive pass level: samples per pixel, or adaptive sampling's level). Takes a
    /// snapshot the first time, and whenever `level` has doubled since the last one, after
    /// updating the estimate from the samples added since. Films of one render only.
    void observe(const Film& film, std::uint32_t level);

    /// The estimated relative RMS error of the film's pixel means (sqrt of the relMSE
    /// above) at its last observation; empty before the first renewal of the snapshot.
    [[nodiscard]] std::optional<double> relative_error() const { return error_; }

private:
    std::vector<FilmPixel> snapshot_;  // the film at snapshot_level_
    std::uint32_t snapshot_level_ = 0;
    // Per pixel: relative per-sample variance, mean over channels of sigma^2 / (mu^2 + 0.01);
    // kept for pixels that stopped (adaptive sampling) and so add no new samples.
    std::vector<float> relative_variance_;
    std::optional<double> error_;
};

}  // namespace librt
