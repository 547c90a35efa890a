// apps::MpiJob with MPI (this build found it): see mpi_job.h.
#include "mpi_job.h"

#include <librt/core/error.h>
#include <librt/mpi/render_mpi.h>
#include <librt/mpi/same_job.h>

#include <mpi.h>

#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

namespace librt::apps {

namespace {

/// True when an MPI launcher started this process: Open MPI's mpirun (OMPI_COMM_WORLD_SIZE),
/// any PMIx launcher (PMIX_RANK: Open MPI 4/5, Slurm with PMIx), MPICH / Intel MPI's Hydra
/// (PMI_RANK, PMI_SIZE), or LIBRT_MPI=1 for a launcher that sets none of these.
bool launched_by_mpi() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"}) {
        if (std::getenv(name) != nullptr) return true;
    }
    const char* forced = std::getenv("LIBRT_MPI");
    return forced != nullptr && std::strcmp(forced, "1") == 0;
}

}  // namespace

MpiJob::MpiJob(int& argc, char**& argv) {
    int already = 0;
    MPI_Initialized(&already);
    if (already == 0 && !launched_by_mpi()) return;
    if (already == 0) {
        int provided = 0;
        if (MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) return;
        initialised_ = true;
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiJob::~MpiJob() {
    if (initialised_) MPI_Finalize();
}

int MpiJob::run(const std::function<int()>& body) const {
    if (!distributed()) return body();
    try {
        try {
            return body();
        } catch (const std::exception& e) {
            // Failed before the set-up check: join it with this rank's message (which
            // throws on every rank, naming the lowest failing one).
            if (!setup_checked_) {
                setup_checked_ = true;
                const std::string what = e.what();
                check_all_ranks(what.empty() ? "set-up failed" : what);
            }
            throw;
        }
    } catch (...) {
        if (rank_ > 0) return 1;  // rank 0 says it
        throw;
    }
}

void MpiJob::setup_succeeded() const {
    if (!distributed() || setup_checked_) return;
    setup_checked_ = true;
    check_all_ranks({});
}

void MpiJob::check_same_job(const std::vector<std::pair<std::string, std::string>>& items) const {
    if (!distributed() || setup_checked_) return;
    // A rank that failed before this call (a bad option) joins the set-up check from run():
    // the others meet it in check_all_ranks below. Both calls throw on every rank alike, so
    // run() must then not start a check of its own (setup_checked_): no rank would join it.
    // Once both pass, setup_succeeded()'s check is still to come.
    std::vector<JobItem> job;
    job.reserve(items.size());
    for (const auto& [name, value] : items) job.push_back({name, value});
    setup_checked_ = true;
    check_all_ranks({});
    librt::check_same_job(MPI_COMM_WORLD, job);
    setup_checked_ = false;
}

void MpiJob::check_all_ranks(const std::string& local_error) const {
    if (!distributed()) {
        if (!local_error.empty()) throw Error(local_error);
        return;
    }
    librt::check_all_ranks(MPI_COMM_WORLD, local_error);
}

Film MpiJob::render(const Scene& scene, const Camera& camera, Integrator& integrator,
                    const MpiJobSettings& settings, MpiJobStats& stats, Image& image) const {
    if (!distributed()) throw Error("MpiJob::render: this process is not one of several ranks");
    MpiRenderSettings s;
    s.render = settings.render;
    s.tile_size = settings.tile_size;
    s.aovs = settings.aovs;
    MpiRenderStats st;
    Film film = render_mpi(MPI_COMM_WORLD, scene, camera, integrator, s, &st, &image);
    stats = MpiJobStats{};
    stats.seconds = st.seconds;
    stats.tiles = st.tiles;
    stats.tiles_per_rank = st.tiles_per_rank;
    stats.samples = st.samples;
    stats.nonfinite = st.nonfinite_samples;
    stats.gather_bytes = st.gather_bytes;
    stats.gather_seconds = st.gather_seconds;
    stats.cancelled = st.cancelled;
    return film;
}

}  // namespace librt::apps
