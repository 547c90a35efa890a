#include "scene_app.h"

#include "cli.h"
#include "output_image.h"

#include <librt/core/error.h>
#include <librt/io/exr.h>
#include <librt/io/file_extension.h>
#include <librt/io/image_io.h>
#include <librt/render/renderer.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <thread>

namespace librt::apps {

void parse_size(const std::string& text, float aspect, int& width, int& height) {
    const auto bad = [&text](const char* rule) { throw Error("--size = " + text + ": " + rule); };
    const char* rule = aspect > 0.0f ? "must be WIDTHxHEIGHT or WIDTH, e.g. 1280x720 or 1280"
                                     : "must be WIDTHxHEIGHT, e.g. 1280x720";
    long w = 0, h = 0;
    char tail = 0;
    if (std::sscanf(text.c_str(), "%ld%*[xX]%ld%c", &w, &h, &tail) == 2) {
        // WxH
    } else if (aspect > 0.0f && std::sscanf(text.c_str(), "%ld%c", &w, &tail) == 1) {
        h = std::lround(double(w) / double(aspect));
    } else {
        bad(rule);
    }
    if (w < 1 || h < 1 || w > 65536 || h > 65536) bad("each side must be in [1, 65536]");
    width = int(w);
    height = int(h);
}

std::uint64_t progressive_output_bytes_per_pixel(const std::string& output,
                                                 RenderMemoryOptions memory) {
    memory.aovs = lower_extension(output) == ".exr";
    const std::uint64_t film = sizeof(FilmPixel) + (memory.aovs ? sizeof(AovPixel) : 0) +
                               (memory.splats ? 3 * sizeof(std::int64_t) : 0);
    const std::uint64_t writing =
        film + sizeof(glm::vec3) + writer_bytes_per_pixel(output, memory.aovs);
    return std::max(progressive_bytes_per_pixel(memory), writing);
}

int render_progressively_and_write(const Scene& scene, const Camera& camera,
                                   GuardedIntegrator& integrator, const ProgressiveOutput& o) {
    ProgressiveSettings ps;
    ps.render.samples_per_pixel = o.spp;
    ps.render.threads = o.threads;
    ps.render.seed = o.seed;
    ps.render.sampler = o.sampler;
    ps.render.cancel = interrupt_flag();
    ProgressBar progress(!o.quiet);
    ps.render.progress = [&progress](const RenderProgress& p) { progress.update(p); };
    // One sample per pixel per pass: a stop (Ctrl-C, time limit) loses at most one sample's
    // work; each pass costs one copy of the film, small next to rendering it.
    ps.pass_samples = 1;
    ps.time_limit = o.time_limit;
    ps.aovs = lower_extension(o.output) == ".exr";
    Film film;
    Image image;  // the film, joined to guiding's kept training passes when it completes
    ps.render.adaptive.enabled = o.adaptive;
    // The preview: written through write_output's atomic PNG writer, so an image viewer
    // never reads half a file. At most once a second (after the first pass): encoding a PNG
    // can cost as much as a one-sample pass of a small image.
    std::chrono::steady_clock::time_point last_preview{};
    bool previewed = false;
    const auto write_preview = [&](const Film& f) {
        write_output(o.preview, resolve(f), display_look(o.scale));
        last_preview = std::chrono::steady_clock::now();
        previewed = true;
    };
    if (!o.preview.empty()) {
        ps.pass_done = [&](const Film& f) {
            if (!previewed ||
                std::chrono::steady_clock::now() - last_preview >= std::chrono::seconds(1))
                write_preview(f);
        };
    }
    const RenderStats stats = render_progressive(scene, camera, integrator, film, ps, &image);
    progress.finish();
    const bool interrupted = stats.cancelled || interrupt_flag()->load();
    if (stats.passes == 0) {
        std::cerr << "interrupted before the first pass finished: nothing written\n";
        return 130;
    }
    write_output(o.output, image, display_look(o.scale, o.exr_half), &film);
    // The last preview is the image written (whatever its format), tone-mapped.
    if (!o.preview.empty()) write_output(o.preview, image, display_look(o.scale));
    const bool partial = stats.samples_per_pixel < std::uint32_t(o.spp);
    if (!o.quiet || partial) {
        const double rate = stats.seconds > 0.0 ? double(stats.samples) / stats.seconds : 0.0;
        std::printf(
            "%dx%d, %u of %d spp in %d passes, %u threads: render %.2f s (%.2f M "
            "samples/s), total %.2f s, peak memory %.0f MiB\n",
            camera.width(), camera.height(), stats.samples_per_pixel, o.spp, stats.passes,
            o.threads > 0 ? unsigned(o.threads) : std::max(1u, std::thread::hardware_concurrency()),
            stats.seconds, rate * 1e-6,
            std::chrono::duration<double>(std::chrono::steady_clock::now() - o.started).count(),
            peak_rss_mib());
    }
    if (stats.nonfinite_samples + integrator.nonfinite_count() > 0) {
        std::fprintf(stderr, "warning: %llu non-finite samples dropped\n",
                     static_cast<unsigned long long>(stats.nonfinite_samples +
                                                     integrator.nonfinite_count()));
    }
    if (interrupted) {
        std::cerr << "interrupted: wrote partial image " << o.output << " ("
                  << stats.samples_per_pixel << " of " << o.spp << " spp)\n";
        return 130;
    }
    if (partial) {
        std::cerr << "time limit reached: wrote partial image " << o.output << " ("
                  << stats.samples_per_pixel << " of " << o.spp << " spp)\n";
    } else if (!o.quiet) {
        std::printf("wrote %s\n", o.output.c_str());
    }
    return 0;
}

}  // namespace librt::apps
