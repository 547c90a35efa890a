#pragma once

#include <librt/core/image.h>
#include <librt/export.h>
#include <librt/film/camera.h>
#include <librt/film/film.h>
#include <librt/film/pixel_region.h>
#include <librt/integrator/integrator.h>
#include <librt/render/adaptive_sampling.h>
#include <librt/render/pass_combination.h>
#include <librt/sampling/sampler.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <span>

namespace librt {

class Scene;

/// Most samples a pixel may hold (and the largest samples_per_pixel): 2^20.
inline constexpr std::uint32_t kMaxSamplesPerPixel = std::uint32_t{1} << 20u;

/// Where a render is, for a progress display. The library draws nothing itself.
struct RenderProgress {
    double fraction = 0.0;  ///< of the planned work done, in [0, 1] (time too, with a time limit)
    double seconds = 0.0;   ///< since the render began
    int passes = 0;         ///< passes finished so far (a one-shot render is one pass)
    std::uint32_t samples_per_pixel = 0;  ///< samples per pixel of the finished passes
    /// render_progressive: the image's estimated relative error (NoiseEstimate, renewed as
    /// the pass level doubles), e.g. 0.02 for 2 %: the very number a noise target
    /// (ProgressiveSettings::noise_target) stops on, so a target can be read off it. -1
    /// until the level has doubled once, and from the other render functions.
    double noise = -1.0;
};

/// Receives progress reports on the thread that called the render function: about ten
/// times a second while it runs, and once at the end of every pass. An exception it
/// throws during a pass stops the render and is rethrown by the render function.
using ProgressCallback = std::function<void(const RenderProgress&)>;

/// How to spread given samples over threads, and which random numbers they use: all a
/// render of stated samples needs (render_block, whose block says the samples, and
/// render_block_to_counts, whose counts do). RenderSettings adds how many samples and how
/// they are spread over the pixels.
struct BlockSettings {
    int threads = 0;         ///< worker threads in [0, 1024]; 0 = hardware_concurrency()
    std::uint64_t seed = 0;  ///< varies every random number of the render
    /// Where each camera path's random numbers come from: Sobol (the default: less noise
    /// per sample and at equal time on every scene measured, docs/sampling.md) or
    /// Independent, the PCG32 streams librt drew before (the report's apps draw them).
    SamplerKind sampler = SamplerKind::Sobol;
    int tile_size =
        16;  ///< side of the square tiles handed to threads (>= 1; capped at the image size)
    ProgressCallback progress;  ///< progress reports (see ProgressCallback); empty = none
    const std::atomic<bool>* cancel =
        nullptr;  ///< when set and it becomes true, the render stops early
};

/// How to spread a render over pixels, samples and threads. The defaults are the best
/// measured (docs/render-your-own-scene.md, "The defaults"): Sobol' samples spread over the
/// pixels by adaptive sampling.
struct RenderSettings : BlockSettings {
    /// Samples averaged per pixel, in [1, 2^20]; with adaptive sampling, their mean.
    int samples_per_pixel = 1;
    /// Spread the samples over pixels by their noise, samples_per_pixel becoming the mean
    /// (adaptive_sampling.h; on by default): render(), render_progressive() and
    /// render_mpi(). Below 4 samples per pixel every pixel gets the same.
    AdaptiveSampling adaptive;
    /// The pixels to render (film/pixel_region.h; pbrt-v4's pixel bounds, Blender's render
    /// region); the default is the whole image. render() and render_progressive() keep the
    /// camera's film and image size and render the region's pixels alone, each exactly as
    /// the whole-image render does (same samples, same sums, same bits; crop() cuts them
    /// out). Pixels outside hold no samples, except with adaptive sampling: a pixel's count
    /// depends on the whole image's pilot (its noise sets the share of the budget), so the
    /// pilot is rendered over the whole image and the rest over the region. Training passes
    /// (path guiding) still learn over the whole image, but are not joined to a region's
    /// image (PassCombination weighs whole images), so an integrator that keeps them gives
    /// the region its own samples only. A splatting integrator is refused (its light paths
    /// land on any pixel: a region could not hold the whole render's pixels), as is
    /// render_mpi (its tiles say the pixels); render_block and render_block_to_counts take
    /// BlockSettings, which has none (their blocks say the pixels). Must be whole() or non-empty
    /// with x0, y0 >= 0 (validate), and lie within the camera's image (checked by the render).
    PixelRegion region;

    /// The settings a block rendering takes (render_block, render_block_to_counts): these
    /// without samples_per_pixel, adaptive and region, which a block does not honour (it says its
    /// samples itself). Passing a RenderSettings there does not compile, so that dropping
    /// them is said, not silent.
    [[nodiscard]] const BlockSettings& block() const { return *this; }
};

/// What a render did.
struct RenderStats {
    double seconds = 0.0;  ///< wall-clock time of the render (preprocess included)
    /// CPU time of the whole process (all threads, std::clock) while the render ran: the
    /// cost measure of efficiency figures (error^2 x CPU seconds). Includes any other
    /// thread of the process working at the same time.
    double cpu_seconds = 0.0;
    std::uint64_t samples = 0;            ///< camera samples taken (li / li_splatting calls)
    std::uint64_t nonfinite_samples = 0;  ///< samples dropped because a channel was NaN or infinite
    bool cancelled = false;               ///< true when `cancel` stopped the render before the end
    bool time_limit_reached = false;      ///< render_progressive: stopped by its time limit
    bool noise_target_reached = false;    ///< render_progressive: stopped by its noise target
    /// render_progressive with a noise target or progress reports: the film's estimated
    /// relative error at the end (NoiseEstimate, as RenderProgress::noise; 0 when the render
    /// was too short to estimate it or estimated nothing).
    double noise = 0.0;
    int passes = 0;  ///< passes finished and kept in the film
    /// samples every pixel holds after a complete pass (adaptive sampling: the level the
    /// passes reached, of which the pixels' mean is at most)
    std::uint32_t samples_per_pixel = 0;
    int training_passes = 0;  ///< learning passes run before the image (train(): path guiding)
};

/// Throws librt::Error naming the first bad parameter of `settings` and its value.
LIBRT_API void validate(const BlockSettings& settings);

/// Throws librt::Error naming the first bad parameter of `settings` and its value.
LIBRT_API void validate(const RenderSettings& settings);

/// Runs the integrator's learning passes (Integrator::begin_training_pass; path guiding):
/// pass k renders integrator.begin_training_pass(k) samples per pixel of the whole image
/// with settings' threads, tile size and sampler onto a scratch film that is discarded,
/// then calls end_training_pass(k), until begin_training_pass returns 0. Pass k's seed is
/// derived from (settings.seed, k), so no training sample shares random numbers with the
/// image's samples (whose guide would otherwise be correlated with them). For an
/// integrator that learns nothing it does nothing. Call it after preprocess() and before
/// render_block; render(), render_progressive() and render_mpi() call it themselves.
/// Honours settings.cancel (stats.cancelled); progress is not reported.
///
/// A splatting integrator's training passes splat onto the scratch film's own splats,
/// which PassCombination counts (pass_combination.h).
///
/// Keeping the passes: when `kept` is not null and integrator.keeps_training_samples()
/// (path guiding's keep_training_samples), every pass of at least 2 samples per pixel is
/// rendered in two halves of its samples (the same sums as one run, so the same guide) and
/// added to *kept. To show them with an image rendered by render_block, render its samples
/// [0, spp / 2) first, copy the film (`half`), render [spp / 2, spp), and call
/// kept->combined(half, film): for the same settings that is render()'s image bit for bit.
LIBRT_API RenderStats train(const Scene& scene, const Camera& camera, Integrator& integrator,
                            const RenderSettings& settings, PassCombination* kept = nullptr);

/// Renders `scene` through `camera` with `integrator`: calls integrator.preprocess(scene)
/// and train(), then threads take tiles from an atomic counter. Sample s of pixel (x, y) uses
/// Sampler(settings.sampler, x, y, s, seed) and Camera::sample_ray, whose filter weight
/// multiplies the sample's radiance (1 except for a Mitchell pixel filter), and each
/// pixel is the mean of its finite weighted samples (non-finite
/// ones are dropped and counted; all dropped gives black), accumulated in sample order,
/// so the image is bit-identical for any thread count and tile size. It is render_block
/// of the whole image and samples [0, samples_per_pixel) onto an empty Film, resolved;
/// with kept training passes (train(); samples_per_pixel >= 2) the film is rendered in
/// its two halves and the image is PassCombination::combined of the passes and the film.
/// Splatting (integrator.splats(), asked once per block): each sample calls li_splatting
/// with a SplatTarget of the camera and the film's splats (Film::splats, created over the
/// whole image), and the image adds them divided by the samples per pixel (resolve()):
/// integer sums, so the same bits for any thread count and tile size too. An integrator
/// that does not splat is called through li() alone, as it always was.
/// Adaptive sampling (settings.adaptive.enabled): samples_per_pixel is the mean. A pilot of
/// adaptive_pilot_samples() per pixel is rendered in two halves, adaptive_sample_counts()
/// gives each pixel its own count from its neighbours' pilots, and every pixel is rendered
/// on to it, still in sample order (bit-identical for any thread count and tile size;
/// stats->samples is the total, at most samples_per_pixel per pixel on average). Training
/// passes are then not kept in the image (their combination assumes equal counts).
/// Cancellation is checked before every pixel and every 64 samples of a pixel, so a
/// cancelled render returns after at most 64 samples' work per thread; pixels not yet
/// finished stay black (the others show their mean plus the splats over the mean sample
/// count, splat_samples_per_pixel) and stats->cancelled is set. Throws librt::Error for invalid
/// settings or a film too large to allocate (before allocating it); an exception thrown
/// by the integrator stops the render and is rethrown.
[[nodiscard]] LIBRT_API Image render(const Scene& scene, const Camera& camera,
                                     Integrator& integrator, const RenderSettings& settings,
                                     RenderStats* stats = nullptr);

/// render() onto a film, which keeps what the image does not: each pixel's sample count
/// (adaptive sampling's allocation) and, for a film created with AOVs, the AOV sums. The
/// film must be empty (0x0: created at the camera's size, without AOVs) or of the camera's
/// size holding no samples; resolve(film) is then render()'s image, except that training
/// passes (path guiding's keep_training_samples) are never kept: the film holds the
/// image's own samples only. Throws librt::Error as render() does, and for a film of
/// another size or holding samples.
LIBRT_API RenderStats render(const Scene& scene, const Camera& camera, Integrator& integrator,
                             Film& film, const RenderSettings& settings);

/// A piece of a render: samples [first, first + count) of the pixels [x0, x1) x [y0, y1).
struct RenderBlock {
    int x0 = 0;               ///< first column
    int y0 = 0;               ///< first row
    int x1 = 0;               ///< one past the last column
    int y1 = 0;               ///< one past the last row
    std::uint32_t first = 0;  ///< first sample index
    std::uint32_t count = 0;  ///< number of samples per pixel
};

/// Renders `block` onto `film`, continuing each pixel's sums: every pixel of the block must
/// hold exactly block.first samples (the film header explains why this makes any split bit-
/// identical to the one-shot render). `integrator` must have been preprocessed (and, for
/// path guiding, trained by train(); train() says how kept training passes join a
/// film rendered this way) for `scene`. It takes BlockSettings: the block says the samples
/// (from a RenderSettings, pass settings.block()). The film must have the camera's size; with AOVs,
/// its AOV sums are rendered in the same pass. A splatting integrator's splats are added to
/// film.splats (created at the camera's size when empty; another size throws), over the whole image
/// whatever the block covers: blocks rendered onto one film, or onto several merged by merge(), sum
/// their splats exactly, and resolve() of the complete film is render()'s image. Threads, seeding,
/// progress and cancellation work as in render(); a cancelled block leaves every pixel holding some
/// number of samples in [first, first + count], its sums consistent with that count. Throws
/// librt::Error naming the parameter for an invalid block (outside the film, first + count > 2^20)
/// or a pixel holding a different number of samples, before rendering anything.
LIBRT_API RenderStats render_block(const Scene& scene, const Camera& camera,
                                   const Integrator& integrator, Film& film,
                                   const RenderBlock& block, const BlockSettings& settings);
/// Refused at compile time: a block cannot honour samples_per_pixel or adaptive sampling,
/// and would drop them silently. Pass settings.block() to say that is meant.
RenderStats render_block(const Scene&, const Camera&, const Integrator&, Film&, const RenderBlock&,
                         const RenderSettings&) = delete;

/// Where a film smaller than the image lies in it: the film's pixel (0, 0) is image pixel
/// (x, y), so it covers [x, x + film.width) x [y, y + film.height).
struct FilmOrigin {
    int x = 0;  ///< image column of the film's first column
    int y = 0;  ///< image row of the film's first row
};

/// render_block onto a film that holds only a region of the image (a tile), so that a
/// process rendering a few tiles of a large frame needs memory for those tiles only
/// (render_mpi's workers). `block` is in image pixels and must lie within the region
/// [origin.x, origin.x + film.width) x [origin.y, origin.y + film.height), which must lie
/// within the camera's image. Pixel (x, y) of the image is film.at(x - origin.x, y -
/// origin.y) and gets exactly the samples and sums it gets in a film of the whole image.
/// Splats still go to film.splats of the whole image (the camera's size: a region film
/// cannot be resolve()d with them until merged into a whole-image film; render_mpi sums
/// them across tiles and ranks itself). Everything else (threads, seeding, progress,
/// cancellation, errors) is as in render_block above, which is this function with origin
/// (0, 0) and a film of the camera's size.
LIBRT_API RenderStats render_block(const Scene& scene, const Camera& camera,
                                   const Integrator& integrator, Film& film, FilmOrigin origin,
                                   const RenderBlock& block, const BlockSettings& settings);
/// Refused at compile time, as above: pass settings.block().
RenderStats render_block(const Scene&, const Camera&, const Integrator&, Film&, FilmOrigin,
                         const RenderBlock&, const RenderSettings&) = delete;

/// render_block with a sample count of its own for each pixel: adaptive sampling split
/// over processes (render_mpi renders the pilot of every tile, computes the counts with
/// adaptive_sample_counts on rank 0 and sends each tile its counts). Every pixel of the
/// block must hold block.first samples; pixel (x, y) is rendered on, in sample order, to
/// ends[film.index(x - origin.x, y - origin.y)] samples (one entry per film pixel, each in
/// [block.first, 2^20]), so it gets the sums render()'s adaptive film gives it. block.count
/// is not used. A cancelled block leaves each pixel between its first and its end, its sums
/// consistent. Throws librt::Error as render_block does, and for an `ends` of the wrong size
/// or a count outside its range (naming the pixel), before rendering anything.
LIBRT_API RenderStats render_block_to_counts(const Scene& scene, const Camera& camera,
                                             const Integrator& integrator, Film& film,
                                             FilmOrigin origin, const RenderBlock& block,
                                             std::span<const std::uint32_t> ends,
                                             const BlockSettings& settings);
/// Refused at compile time, as render_block's: pass settings.block().
RenderStats render_block_to_counts(const Scene&, const Camera&, const Integrator&, Film&,
                                   FilmOrigin, const RenderBlock&, std::span<const std::uint32_t>,
                                   const RenderSettings&) = delete;

/// A render in passes, until a sample count or a time limit is reached.
struct ProgressiveSettings {
    /// Threads, seed, tile size, progress and cancellation; samples_per_pixel is the total
    /// each pixel should hold at the end.
    RenderSettings render;
    int pass_samples = 1;     ///< samples per pixel added by each pass, in [1, 2^20]
    double time_limit = 0.0;  ///< seconds (finite, >= 0) after which rendering stops; 0 = none
    /// Stop once the image's estimated relative error (NoiseEstimate: relMSE's square root)
    /// is at most this, in [0, 1]; 0 = none. Checked between passes from the doubling of
    /// the level on; render.samples_per_pixel stays the most a render takes.
    double noise_target = 0.0;
    bool aovs = false;  ///< a newly created film keeps AOV sums
    /// Seconds on a monotonic clock, for the time limit and progress reports; empty =
    /// std::chrono::steady_clock. Tests pass a fake one.
    std::function<double()> clock;
    /// Called on the calling thread after every complete pass with the film and the level
    /// the passes reached (every pixel holding that many samples; adaptive sampling: its
    /// share of them), e.g. to copy the film part way for the denoiser's half buffers
    /// (render/denoiser.h) or to write a preview image. An exception it throws stops the
    /// render and is rethrown. Empty = not called.
    std::function<void(const Film& film, std::uint32_t level)> pass_done;
};

/// Throws librt::Error naming the first bad parameter of `settings` and its value.
LIBRT_API void validate(const ProgressiveSettings& settings);

/// Renders passes of settings.pass_samples samples per pixel over the whole image onto
/// `film` until every pixel holds settings.render.samples_per_pixel samples, the time
/// limit has passed, or settings.render.cancel is set. An empty (0x0) film is created at
/// the camera's size (with AOVs if settings.aovs); a non-empty one must have the camera's
/// size and hold the same number of samples in every pixel, and is continued: rendering
/// is resumable. Each pass renders onto a copy of the film (memory for two films) that
/// replaces it only once the pass is complete, so the film always holds whole passes:
/// every pixel the mean of the same number of samples (stats.samples_per_pixel, over
/// stats.passes passes). The time limit is checked between passes and, while a pass runs,
/// about ten times a second: a pass still running at the limit is abandoned, except that
/// a film holding no samples always gets its first pass. The film equals a one-shot
/// render of the same total sample count bit for bit. Calls integrator.preprocess(scene)
/// and train() once, when there is something to render.
///
/// Adaptive sampling (settings.render.adaptive.enabled; the film must hold no samples):
/// uniform passes render the pilot, one of them ending at its half; adaptive_sample_counts
/// then gives every pixel its final count N_p, and each later pass takes every pixel to
/// pilot + floor((N_p - pilot) x (L - pilot) / (samples_per_pixel - pilot)) for the level
/// L = pilot + k x pass_samples it reaches (stats.samples_per_pixel). A film stopped
/// between passes holds every pixel's share, each count still chosen from the neighbours'
/// pilots alone; the complete film is render()'s (adaptive) film bit for bit. Training
/// passes are not kept.
///
/// `image`, when not null, receives the image to show: resolve(film), or, when the
/// integrator keeps its training passes (path guiding's keep_training_samples) and this
/// call took the film from at most half of samples_per_pixel (>= 2) to all of it, those
/// passes joined to the film as render() joins them (train()), so it equals render()'s
/// image bit for bit. The film itself only ever holds the image's own samples: shown
/// between passes, it is the plainer (noisier) estimate; a render stopped early (time
/// limit, cancel) or a film resumed past its half gives resolve(film). A splatting
/// integrator's splats travel with the film (Film::splats) from pass to pass; as the film
/// holds whole passes, they resolve over its uniform sample count. Keeping costs one
/// more film (the film at half the samples) and ends the pass that crosses the half there.
LIBRT_API RenderStats render_progressive(const Scene& scene, const Camera& camera,
                                         Integrator& integrator, Film& film,
                                         const ProgressiveSettings& settings,
                                         Image* image = nullptr);

}  // namespace librt
