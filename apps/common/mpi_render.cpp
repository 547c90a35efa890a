// apps::render_over_ranks: rt_render's frame under mpirun (see mpi_job.h). Built with and
// without MPI alike: it uses MpiJob's interface only.
#include "cli.h"
#include "mpi_job.h"

#include <cstdio>
#include <iostream>

namespace librt::apps {

int render_over_ranks(const MpiJob& job, const Scene& scene, const Camera& camera,
                      Integrator& integrator, MpiJobSettings settings, bool quiet,
                      const std::string& output,
                      const std::function<void(const Film&, const Image&)>& write) {
    const bool root = job.rank() == 0;
    ProgressBar progress(!quiet && root);
    if (root)
        settings.render.progress = [&progress](const RenderProgress& p) { progress.update(p); };
    settings.render.cancel = interrupt_flag();
    MpiJobStats stats;
    Image image;
    const Film film = job.render(scene, camera, integrator, settings, stats, image);
    progress.finish();
    if (stats.cancelled || interrupt_flag()->load()) {
        if (root)
            std::cerr << "interrupted: nothing written (a frame shared by ranks is written whole "
                         "or not at all)\n";
        return 130;
    }
    if (!root) return 0;
    write(film, image);
    if (!quiet) {
        std::printf(
            "%dx%d, %d spp, %d ranks x %d threads: render %.2f s, peak memory of rank 0 "
            "%.0f MiB\n",
            film.width, film.height, settings.render.samples_per_pixel, job.size(),
            settings.render.threads, stats.seconds, peak_rss_mib());
        std::printf("tiles of %d px: %d, per rank:", settings.tile_size, stats.tiles);
        for (const int n : stats.tiles_per_rank) std::printf(" %d", n);
        std::printf("; gathered %llu bytes in %.4f s\nwrote %s\n",
                    static_cast<unsigned long long>(stats.gather_bytes), stats.gather_seconds,
                    output.c_str());
    }
    return 0;
}

}  // namespace librt::apps
