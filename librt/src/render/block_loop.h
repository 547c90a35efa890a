#pragma once

// The one render loop under every entry point (renderer.cpp): run_block renders a block
// of pixels and samples onto a film, threads taking its tiles from an atomic counter.

#include <librt/film/camera.h>
#include <librt/film/film.h>
#include <librt/integrator/integrator.h>
#include <librt/render/renderer.h>

#include <cstdint>
#include <functional>

namespace librt {

class Scene;

/// How run_block ended.
struct BlockOutcome {
    std::uint64_t samples = 0;    ///< Integrator::li (or li_splatting) calls
    std::uint64_t nonfinite = 0;  ///< of which non-finite
    bool complete = false;        ///< every pixel of the block got all its samples
    bool cancelled = false;       ///< settings.cancel stopped it
    bool aborted = false;         ///< `tick` stopped it
};

/// Called on the calling thread about ten times a second with the fraction of the
/// block's tiles done; returning true stops the block (as a cancellation would).
using Tick = std::function<bool(double fraction)>;

/// Renders `block` onto `film` (placed at `origin` in the image), each pixel's samples in
/// sample order onto its record, so any split of pixels, samples and threads gives the same
/// sums. With `ends` (adaptive sampling: one count per film pixel, film.pixels.size()),
/// each pixel of the block is rendered from the samples it holds up to its own end instead
/// of [first, first + count). The block and settings are the caller's to check. A
/// splatting integrator's splats go to film.splats (created over the whole image when
/// empty). Rethrows an exception of the integrator or of `tick` once the threads stopped.
BlockOutcome run_block(const Scene& scene, const Camera& camera, const Integrator& integrator,
                       Film& film, FilmOrigin origin, const RenderBlock& block,
                       const BlockSettings& settings, const Tick& tick,
                       const std::uint32_t* ends = nullptr);

}  // namespace librt
