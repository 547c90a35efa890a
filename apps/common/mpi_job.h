#pragma once

#include <librt/film/camera.h>
#include <librt/film/film.h>
#include <librt/integrator/integrator.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

// The MPI job an app may have been started in by mpirun, for apps that also run alone
// (rt_render). Built in two versions: mpi_job.cpp when CMake found MPI (librt::mpi), and
// mpi_job_none.cpp without it, where every process is a job of one. The app's code is the
// same in both, without #ifdef.

namespace librt::apps {

/// How a frame is spread over the ranks (librt::MpiRenderSettings without <mpi.h>).
struct MpiJobSettings {
    RenderSettings render;  ///< spp, seed, sampler, threads per rank, progress (rank 0), cancel
    int tile_size = 32;     ///< side of the tiles rank 0 hands out
    bool aovs = false;      ///< the film keeps AOV sums (for EXR layers)
};

/// What the distributed render did, as rank 0 saw it (librt::MpiRenderStats).
struct MpiJobStats {
    double seconds = 0.0;             ///< wall time of the render on this rank
    int tiles = 0;                    ///< tiles of the image
    std::vector<int> tiles_per_rank;  ///< rank 0: tiles each rank rendered
    std::uint64_t samples = 0;        ///< camera samples this rank took
    std::uint64_t nonfinite = 0;      ///< of which dropped as non-finite
    std::uint64_t gather_bytes = 0;   ///< rank 0: tile bytes received
    double gather_seconds = 0.0;      ///< rank 0: seconds spent receiving and copying them
    bool cancelled = false;           ///< a rank's cancel flag (Ctrl-C) stopped the render
};

/// MPI for the lifetime of the object: initialised (MPI_THREAD_FUNNELED) in the
/// constructor when this build has MPI and the process was started by an MPI launcher,
/// finalised in the destructor. Whether the process is one rank of several is then MPI's
/// answer (MPI_Comm_size of MPI_COMM_WORLD), not the environment's. The environment only
/// decides whether MPI is asked at all (OMPI_COMM_WORLD_SIZE, PMIX_RANK, PMI_RANK or
/// PMI_SIZE set, or LIBRT_MPI=1): Open MPI's singleton start-up costs ~0.75 s, which a
/// plain `rt_render scene.glb` should not pay.
class MpiJob {
public:
    /// Joins the MPI job this process belongs to, if any (see the class comment).
    MpiJob(int& argc, char**& argv);
    ~MpiJob();
    MpiJob(const MpiJob&) = delete;
    MpiJob& operator=(const MpiJob&) = delete;

    /// This process's rank in MPI_COMM_WORLD; 0 alone.
    [[nodiscard]] int rank() const { return rank_; }
    /// Processes in MPI_COMM_WORLD; 1 alone.
    [[nodiscard]] int size() const { return size_; }
    /// True when the frame is shared with other ranks (size() > 1).
    [[nodiscard]] bool distributed() const { return size_ > 1; }

    /// Runs the app's body (`body`: options, scene, render, write) and returns its exit
    /// code. In a distributed job, an exception before setup_succeeded() (a bad option, a
    /// scene file missing on this machine) is first shared with the other ranks, which wait
    /// in setup_succeeded(): every rank then throws "rank R: <message>" for the lowest
    /// failing rank R, so that no rank waits for one that stopped. Errors are printed by
    /// rank 0 only (the caller's apps::run prints what run() rethrows); the other ranks
    /// return 1 quietly. Alone: body() unchanged.
    [[nodiscard]] int run(const std::function<int()>& body) const;

    /// Collective, once, after this rank's set-up worked (the scene is loaded, the camera
    /// built): waits for every rank's set-up and throws like run() when one failed. Does
    /// nothing alone.
    void setup_succeeded() const;

    /// Collective, before setup_succeeded(): every rank passes what shapes its image, as
    /// (name, value) pairs ("--spp", "16"; "scene file", its digest), and when a rank's
    /// differ from rank 0's every rank throws librt::Error naming the rank and the item,
    /// "rank 1: --integrator differs from rank 0 (bdpt vs path)" (librt::check_same_job,
    /// mpi/same_job.h). A rank whose set-up failed before this call is reported first, as
    /// by setup_succeeded(). Does nothing alone.
    void check_same_job(const std::vector<std::pair<std::string, std::string>>& items) const;

    /// Collective: every rank passes the error of its set-up (empty when it worked). When
    /// any failed, throws librt::Error on every rank, "rank R: <message>" for the lowest
    /// failing rank R. Alone: throws `local_error` when not empty.
    void check_all_ranks(const std::string& local_error) const;

    /// Collective: renders the frame over the ranks with librt::render_mpi (rank 0 schedules
    /// tiles and renders too, the others render tiles onto tile-sized films). Returns the
    /// whole film on rank 0, an empty one elsewhere; the film equals a one-process render
    /// with the same settings bit for bit. `image` receives on rank 0 the image to write:
    /// resolve(film), or with kept training passes (--guiding) render()'s combination.
    /// Throws librt::Error on every rank when a rank failed, naming it. Only for
    /// distributed() jobs (throws otherwise).
    [[nodiscard]] Film render(const Scene& scene, const Camera& camera, Integrator& integrator,
                              const MpiJobSettings& settings, MpiJobStats& stats,
                              Image& image) const;

private:
    int rank_ = 0;
    int size_ = 1;
    bool initialised_ = false;            // we called MPI_Init_thread (and so MPI_Finalize)
    mutable bool setup_checked_ = false;  // this rank took part in the set-up check
};

/// A frame rendered over the ranks of `job` (distributed()) and written by rank 0 through
/// `write` (the film and its image, see MpiJob::render); rank 0 draws the progress bar and prints
/// the summary unless `quiet`. Returns the process's exit code: 0, or 130 when Ctrl-C
/// (apps::interrupt_flag) or a rank's cancel flag stopped the render; then nothing is written, as
/// tiles finished so far would hold different sample counts. Throws librt::Error on every rank when
/// a rank failed.
[[nodiscard]] int render_over_ranks(const MpiJob& job, const Scene& scene, const Camera& camera,
                                    Integrator& integrator, MpiJobSettings settings, bool quiet,
                                    const std::string& output,
                                    const std::function<void(const Film&, const Image&)>& write);

}  // namespace librt::apps
