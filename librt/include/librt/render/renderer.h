#pragma once

#include <librt/core/image.h>
#include <librt/export.h>
#include <librt/render/camera.h>
#include <librt/render/integrator.h>

#include <atomic>
#include <cstdint>

namespace librt {

class Scene;

/// How to spread a render over pixels, samples and threads.
struct RenderSettings {
    int samples_per_pixel = 1;  ///< samples averaged per pixel, in [1, 2^20]
    int threads = 0;            ///< worker threads in [0, 1024]; 0 = hardware_concurrency()
    std::uint64_t seed = 0;     ///< varies every random number of the render
    int tile_size =
        16;  ///< side of the square tiles handed to threads (>= 1; capped at the image size)
    bool progress =
        true;  ///< progress bar on stderr (only if it is a terminal and the render takes > ~1 s)
    const std::atomic<bool>* cancel =
        nullptr;  ///< when set and it becomes true, the render stops early
};

/// What a render did.
struct RenderStats {
    double seconds = 0.0;                 ///< wall-clock time of the render (preprocess included)
    std::uint64_t samples = 0;            ///< camera samples taken (Integrator::li calls)
    std::uint64_t nonfinite_samples = 0;  ///< samples dropped because a channel was NaN or infinite
    bool cancelled = false;               ///< true when `cancel` stopped the render before the end
};

/// Throws librt::Error naming the first bad parameter of `settings` and its value.
LIBRT_API void validate(const RenderSettings& settings);

/// Renders `scene` through `camera` with `integrator`: calls integrator.preprocess(scene),
/// then threads take tiles from an atomic counter. Sample s of pixel (x, y) uses
/// Sampler(x, y, s, seed), and each pixel is the mean of its finite samples (non-finite
/// ones are dropped and counted; all dropped gives black), accumulated in sample order,
/// so the image is bit-identical for any thread count and tile size. Cancellation is
/// checked before every pixel and every 64 samples of a pixel, so a cancelled render
/// returns after at most 64 samples' work per thread; pixels not yet finished stay black
/// and stats->cancelled is set. Throws librt::Error for invalid settings or a film too
/// large to allocate (before allocating it); an exception thrown by the integrator stops
/// the render and is rethrown.
[[nodiscard]] LIBRT_API Image render(const Scene& scene, const Camera& camera,
                                     Integrator& integrator, const RenderSettings& settings,
                                     RenderStats* stats = nullptr);

}  // namespace librt
