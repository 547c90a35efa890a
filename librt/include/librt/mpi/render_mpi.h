#pragma once

#include <librt/core/image.h>
#include <librt/export.h>
#include <librt/film/camera.h>
#include <librt/film/film.h>
#include <librt/integrator/integrator.h>
#include <librt/render/renderer.h>

#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

// One image over the ranks of an MPI communicator (the optional librt::mpi library, built
// when CMake finds MPI). Rank 0 hands out square tiles on request (dynamic scheduling: a
// slow machine takes fewer tiles instead of holding the frame) and renders tiles itself on
// a thread of its own while its main thread answers requests; finished tiles stream back
// to rank 0 as they are done. Every pixel is computed from (pixel, sample, seed) alone and
// rendered onto an empty film region in sample order, so the film on rank 0 equals the one
// of a one-process render() with the same settings bit for bit (film.h says why). Only
// rank 0 holds a film of the whole frame; the others render each tile onto a film of the
// tile's size (render_block with a FilmOrigin), so their memory is the scene's.
//
// An integrator that splats (Integrator::splats) splats from every rank into a SplatFilm
// of the whole image: rank 0's own thread into the film's, each other rank into one it
// keeps over all its tiles (24 bytes per pixel; twice that with kept training passes) and
// sends to rank 0 once, after its last tile. Rank 0 adds them (integer sums: exact in any
// order), so the film's splats, like its records, are render()'s whatever the split.
//
// Threads and MPI: only the thread that calls render_mpi makes MPI calls; initialise MPI
// with MPI_Init_thread and at least MPI_THREAD_FUNNELED. Tile records travel as raw bytes:
// every rank must run on the same architecture (as a render farm does).

namespace librt {

class Scene;

/// How render_mpi spreads the image over the ranks.
struct MpiRenderSettings {
    /// samples_per_pixel, seed, threads (per rank), tile_size (threads' tiles within an MPI
    /// tile), progress (called on rank 0 only, the fraction being tiles gathered; with
    /// adaptive sampling also once as the pilot completes, every pilot in and the counts
    /// set: {pilot / samples_per_pixel, seconds, 0, pilot}, the one report whose
    /// samples_per_pixel is the pilot), cancel (on any rank: the whole job stops).
    RenderSettings render;
    int tile_size = 32;  ///< side of the square tiles rank 0 hands out, in [1, 1024]
    bool aovs = false;   ///< the film keeps AOV sums (albedo, normal, depth)
    /// Rank 0 renders tiles too (on one more thread, while its main thread schedules).
    /// Off: rank 0 only schedules and gathers (for a head node without spare cores).
    bool root_renders = true;
};

/// What render_mpi did, as seen from the calling rank.
struct MpiRenderStats {
    double seconds = 0.0;  ///< wall-clock time of render_mpi on this rank
    int tiles = 0;  ///< tiles of the image (adaptive sampling: twice, its pilot and its rest)
    int tiles_rendered = 0;               ///< tiles this rank rendered
    std::vector<int> tiles_per_rank;      ///< rank 0: tiles each rank rendered (others: empty)
    std::uint64_t samples = 0;            ///< camera samples this rank took
    std::uint64_t nonfinite_samples = 0;  ///< of which dropped as non-finite
    /// Rank 0: bytes of tile records received from the other ranks (others: bytes sent).
    std::uint64_t gather_bytes = 0;
    /// Rank 0: seconds its main thread spent receiving tiles and copying them into the
    /// film (the gather's cost; it overlaps the rendering). Others: seconds spent sending
    /// tiles and waiting for the next one.
    double gather_seconds = 0.0;
    bool cancelled = false;  ///< a rank's `cancel` flag stopped the render
};

/// Throws librt::Error naming the first bad parameter of `settings` and its value.
LIBRT_API void validate(const MpiRenderSettings& settings);

/// Renders `scene` through `camera` with `integrator` over the ranks of `comm`, a
/// collective call: every rank of `comm` must call it with the same scene, camera and
/// settings (each rank builds or loads its own copy). What it can see of that is checked
/// first (check_same_job, mpi/same_job.h): the image size, tile_size, samples_per_pixel,
/// seed, sampler, adaptive sampling, aovs and whether the integrator splats; a rank that
/// differs fails the call on every rank, "rank 1: integrator splats differs from rank 0
/// (yes vs no)". The scene and the integrator are the caller's to compare (an app hashes
/// its scene file and options, as rt_render does). Its messages travel on
/// a duplicate of `comm` (MPI_Comm_dup), so they never mix with the caller's or with those of the
/// next call (calls in a row, e.g. the frames of an animation, are safe). Calls
/// integrator.preprocess(scene) on each rank. Returns the whole film on rank 0 (every
/// pixel holding settings.render.samples_per_pixel samples, but see adaptive sampling; resolve() or
/// resolve_layers() it), an empty 0x0 film on the other ranks.
///
/// Failure: an exception on any rank (the integrator throws, bad settings, an allocation
/// fails) is sent to rank 0, which stops the other ranks; then render_mpi throws
/// librt::Error on every rank, on rank 0 "rank R failed: <its message>". No rank is left
/// waiting. A rank that dies without a word (killed) is beyond this: MPI's default error
/// handler (MPI_ERRORS_ARE_FATAL) and mpirun end the job. Cancellation (settings.render.cancel
/// set on any rank) stops every rank within about a tile; stats->cancelled is then set and
/// rank 0 returns the film as far as it got (tiles finished on rank 0 or received from the
/// others; every other pixel holds fewer samples than asked, often none). A cancelled
/// render's splats are rank 0's own and those of the ranks that had finished before (the
/// others never send theirs): resolve() divides them by the mean sample count all the
/// same, so such a film's splats are short of the light of the missing ranks.
///
/// Kept training passes: when the integrator keeps its training passes (path guiding's
/// keep_training_samples) and samples_per_pixel >= 2, rank 0 keeps them (train()) and every
/// tile is rendered in two halves of its samples, whose records at the half travel with the
/// tile (32 more bytes per pixel). `image`, when not null, then receives on rank 0 the passes
/// joined to the film (PassCombination::combined), bit for bit render()'s image with the
/// same settings whatever the rank count, tile size and threads; otherwise (or when
/// cancelled) resolve() of the returned film. The film itself holds the image's samples
/// only. Other ranks leave `image` unchanged.
///
/// Adaptive sampling (settings.render.adaptive): every tile's pilot is rendered first (in
/// its two halves, both of whose records travel to rank 0); once all are back, rank 0
/// computes each pixel's count from the whole image (adaptive_sample_counts) and hands out
/// each tile again with its pilot records and counts, continued by render_block_to_counts.
/// The film is then render()'s adaptive film bit for bit, its pixels holding their own
/// counts (samples_per_pixel on average), and stats->tiles counts each tile twice.
[[nodiscard]] LIBRT_API Film render_mpi(MPI_Comm comm, const Scene& scene, const Camera& camera,
                                        Integrator& integrator, const MpiRenderSettings& settings,
                                        MpiRenderStats* stats = nullptr, Image* image = nullptr);

/// A collective check after each rank's set-up (loading the scene, opening files): every
/// rank passes its error message, empty when it succeeded. When any rank failed, throws
/// librt::Error on every rank naming the lowest failing rank and its message ("rank R:
/// ..."), so that no rank goes on into render_mpi waiting for one that never comes.
LIBRT_API void check_all_ranks(MPI_Comm comm, const std::string& local_error);

}  // namespace librt
