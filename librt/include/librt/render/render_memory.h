#pragma once

#include <librt/export.h>

#include <cstdint>

// How much memory a render's pixels take: the films, their copies and the image, per pixel
// of the camera, from the sizes of the records themselves (FilmPixel, AovPixel, the splat
// sums, Image's pixels). An app multiplies it by the pixel count and refuses an image size
// whose render would not fit before anything is allocated. Scene, BVH and textures are not
// per pixel and are not counted.

namespace librt {

/// What decides a render's memory per pixel.
struct RenderMemoryOptions {
    bool aovs = false;            ///< the film keeps AOV sums (ProgressiveSettings::aovs)
    bool splats = false;          ///< the integrator splats (light tracing, bidirectional)
    bool adaptive = false;        ///< adaptive sampling (RenderSettings::adaptive)
    bool keeps_training = false;  ///< the integrator keeps its training passes (guiding)
    /// A noise target (ProgressiveSettings::noise_target > 0) or progress reports, which
    /// show the same estimate: NoiseEstimate's snapshot of the pixels and their variances.
    bool noise_estimate = false;
};

/// An upper bound of the bytes per pixel render() holds at once: its film (sums and
/// counts, plus splat sums), the image it returns, and with adaptive sampling the pilot's
/// half film and the per-pixel tables that pick the counts, or with kept training passes
/// the half film and the inverse-variance sums (and their copy while the image is joined).
[[nodiscard]] LIBRT_API std::uint64_t render_bytes_per_pixel(const RenderMemoryOptions& options);

/// The same for render_progressive with an `image`: the film and the copy each pass renders
/// onto (memory for two films, AOVs and splats included), the image, and the extras of
/// adaptive sampling (a third film and the tables) or of kept training passes, and the noise
/// estimate's snapshot (36: the pixels' sums and counts, a float variance).
[[nodiscard]] LIBRT_API std::uint64_t progressive_bytes_per_pixel(
    const RenderMemoryOptions& options);

}  // namespace librt
