#pragma once

#include <librt/core/image.h>
#include <librt/core/tone_curve.h>
#include <librt/film/camera.h>
#include <librt/film/film.h>
#include <librt/film/pixel_region.h>
#include <librt/integrator/integrators.h>
#include <librt/render/render_memory.h>
#include <librt/sampling/sampler.h>
#include <librt/scene/scene.h>

#include <chrono>
#include <cstdint>
#include <string>

// What the apps that show a scene in today's display convention (rt_render, rt_materials)
// share, rather than the report's gamma-0.45 look: "WxH" sizes, progressive passes, a
// partial image on Ctrl-C or at the time limit, sRGB-encoded PNG after a clamp, linear
// HDR / PFM / EXR (EXR with AOV layers).

namespace librt::apps {

/// What render_progressively_and_write needs from the command line.
struct ProgressiveOutput {
    std::string output;                              ///< .png (sRGB), .hdr, .pfm or .exr (linear)
    int spp = 16;                                    ///< samples per pixel
    int threads = 0;                                 ///< worker threads, 0 = all cores
    std::uint64_t seed = 0;                          ///< random seed
    SamplerKind sampler = SamplerKind::Independent;  ///< --sampler
    double time_limit = 0.0;                         ///< seconds, 0 = none
    double noise_target = 0.0;  ///< --noise-target: stop at this relative error, 0 = none
    bool adaptive = false;      ///< --adaptive: spp is the mean; passes spread by noise
    float scale = 1.0f;         ///< exposure: the linear image is multiplied by this
    bool exr_half = false;      ///< --exr-half: EXR colour channels as half (clamped to 65504)
    ToneCurve curve = ToneCurve::Clamp;  ///< --tonemap: the PNG's curve after the exposure
    bool auto_exposure = false;          ///< --exposure auto: the PNG's exposure from its image
    int png_bits = 8;                    ///< --png-bits: 8 or 16 bits per PNG channel
    /// --transparent-background: the PNG gets the film's coverage as alpha (the films keep
    /// AOVs).
    bool alpha = false;
    bool quiet = false;  ///< no progress bar and no summary
    /// --denoise: PNG, .hdr and .pfm get the denoised image, EXR a denoised layer beside its
    /// unbiased beauty (render/denoiser.h). Needs 2 samples per pixel.
    bool denoise = false;
    /// --preview: a PNG rewritten (atomically, as every image writer) with the image so far
    /// after the first pass, then after a pass at most once a second, and at the end; empty =
    /// none.
    std::string preview;
    /// --region: only these pixels are rendered (RenderSettings::region), and the output, the
    /// preview and the denoiser see them alone, as an image of the region's size (the
    /// crop's edges are the denoiser's image edges). The default: the whole image.
    PixelRegion region;
    /// When the app started its work (the summary's "total" counts from here).
    std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
};

/// Parses --size: "WxH", or (when aspect > 0) a single width W with the height
/// round(W / aspect); each side in [1, 65536]. Throws librt::Error "--size = text: rule".
void parse_size(const std::string& text, float aspect, int& width, int& height);

/// The most bytes per pixel render_progressively_and_write holds at once for `output`
/// (AOVs for .exr) and `memory`'s other choices: render_progressive's films, copies and
/// image, or afterwards the film, the image and the writer's buffers, whichever is more;
/// with `denoise`, the films keep AOVs and the film part way and the denoiser's planes are
/// added.
[[nodiscard]] std::uint64_t progressive_output_bytes_per_pixel(const std::string& output,
                                                               RenderMemoryOptions memory,
                                                               bool denoise = false);

/// Renders `scene` through `camera` one sample per pixel per pass (render_progressive),
/// with a progress bar, until o.spp samples, Ctrl-C or the time limit; writes the finished
/// passes and prints a summary (render time, samples/s, total time, peak memory). Returns 0, or 130
/// when interrupted (the partial image written, flagged on stderr; nothing written when no pass had
/// finished). `scene` must be committed; `integrator` is the path tracer or the bidirectional one.
[[nodiscard]] int render_progressively_and_write(const Scene& scene, const Camera& camera,
                                                 GuardedIntegrator& integrator,
                                                 const ProgressiveOutput& o);

}  // namespace librt::apps
