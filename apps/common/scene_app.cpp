#include "scene_app.h"

#include "cli.h"
#include "output_image.h"

#include <librt/core/error.h>
#include <librt/io/exr.h>
#include <librt/io/file_extension.h>
#include <librt/io/image_io.h>
#include <librt/render/denoiser.h>
#include <librt/render/renderer.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
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
                                                 RenderMemoryOptions memory, bool denoise) {
    memory.aovs = memory.aovs || lower_extension(output) == ".exr" || denoise;
    const std::uint64_t film = sizeof(FilmPixel) + (memory.aovs ? sizeof(AovPixel) : 0) +
                               (memory.splats ? 3 * sizeof(std::int64_t) : 0);
    // The denoiser: the film part way (kept from the half on), then at its peak (the main
    // filter, after the albedo's and the emission's own filters) its input (11 images and
    // the shares: 136), the prefiltered albedo and the filtered emission (24), the halves
    // less their emission (24), the demodulated halves, spreads, variances, feature
    // tolerances and floored albedos (16 RGB: 192), the modulation, shares and emission
    // (28), its padded planes (34 floats and a scratch plane: 148, more at the image's
    // edges for a small image) and its output (12): 45 RGB pixels' worth (540 bytes).
    const std::uint64_t kept = denoise ? film : 0;
    const std::uint64_t denoising = denoise ? 45 * sizeof(glm::vec3) : 0;
    const std::uint64_t writing =
        film + kept + sizeof(glm::vec3) +
        std::max(writer_bytes_per_pixel(output, memory.aovs), denoising + sizeof(glm::vec3));
    return std::max(progressive_bytes_per_pixel(memory) + kept, writing);
}

namespace {

/// The look of o's output (and, in 8 bits, of its preview).
OutputLook png_look(const ProgressiveOutput& o) {
    OutputLook look = display_look(o.scale, o.exr_half);
    look.curve = o.curve;
    look.auto_exposure = o.auto_exposure;
    look.png_bits = o.png_bits;
    look.alpha = o.alpha;
    return look;
}

}  // namespace

int render_progressively_and_write(const Scene& scene, const Camera& camera,
                                   GuardedIntegrator& integrator, const ProgressiveOutput& o) {
    ProgressiveSettings ps;
    ps.render.samples_per_pixel = o.spp;
    ps.render.threads = o.threads;
    ps.render.seed = o.seed;
    ps.render.sampler = o.sampler;
    ps.render.cancel = interrupt_flag();
    ProgressBar progress(!o.quiet);
    // Only when shown: progress reports carry the noise estimate, which costs a snapshot
    // of the pixels (counted by progressive_output_bytes_per_pixel's caller).
    if (!o.quiet) ps.render.progress = [&progress](const RenderProgress& p) { progress.update(p); };
    // One sample per pixel per pass: a stop (Ctrl-C, time limit) loses at most one sample's
    // work; each pass costs one copy of the film, small next to rendering it.
    ps.pass_samples = 1;
    ps.time_limit = o.time_limit;
    ps.noise_target = o.noise_target;
    const bool exr = lower_extension(o.output) == ".exr";
    ps.aovs = exr || o.denoise || o.alpha;
    ps.render.adaptive.enabled = o.adaptive;
    ps.render.region = o.region;
    // The denoiser's first half: the film at spp / 2, or (for a render the time limit may
    // stop) at the last power of two below it, so that a stopped render still has a part
    // holding at least a quarter of its samples. Adaptive sampling: at half the pilot, the
    // last level every pixel is sure to exceed (a quiet pixel may get no more than it).
    Film half;
    std::uint32_t half_at = 0;  // the level `half` holds; 0 = none
    const std::uint32_t pilot =
        o.adaptive ? adaptive_pilot_samples(ps.render.adaptive, std::uint32_t(o.spp)) : 0;
    const std::uint32_t half_level = pilot > 0 ? pilot / 2 : std::uint32_t(o.spp / 2);
    const auto keep_half = [&half, &half_at, half_level](const Film& f, std::uint32_t level) {
        if (level == half_level || (level < half_level && std::has_single_bit(level))) {
            half = f;
            half_at = level;
        }
    };
    Film film;
    Image image;  // the film, joined to guiding's kept training passes when it completes
    // The preview: written through write_output's atomic PNG writer, so an image viewer
    // never reads half a file. At most once a second (after the first pass): encoding a PNG
    // can cost as much as a one-sample pass of a small image.
    std::chrono::steady_clock::time_point last_preview{};
    bool previewed = false;
    const auto write_preview = [&](const Film& f) {
        if (o.region.whole()) {
            write_output(o.preview, resolve(f), png_look(o), &f);
        } else {  // the region's pixels, as a film of its own size
            const Film shown = crop(f, o.region);
            write_output(o.preview, resolve(shown), png_look(o), &shown);
        }
        last_preview = std::chrono::steady_clock::now();
        previewed = true;
    };
    if (!o.preview.empty() || o.denoise) {
        ps.pass_done = [&](const Film& f, std::uint32_t level) {
            if (o.denoise) keep_half(f, level);
            if (!o.preview.empty() &&
                (!previewed ||
                 std::chrono::steady_clock::now() - last_preview >= std::chrono::seconds(1)))
                write_preview(f);
        };
    }
    const RenderStats stats = render_progressive(scene, camera, integrator, film, ps, &image);
    progress.finish();
    // A region: what is written and denoised is its pixels, as films of its own size.
    if (!o.region.whole()) {
        film = crop(film, o.region);
        image = crop(image, o.region);
        if (half_at != 0) half = crop(half, o.region);
    }
    const bool interrupted = stats.cancelled || interrupt_flag()->load();
    if (stats.passes == 0) {
        std::cerr << "interrupted before the first pass finished: nothing written\n";
        return 130;
    }
    Image denoised;
    if (o.denoise) {
        if (half_at == 0 || half_at >= stats.samples_per_pixel) {
            std::cerr << "warning: not denoised: the denoiser needs at least 2 samples per "
                         "pixel (it compares two halves of them)\n";
        } else {
            const auto t = std::chrono::steady_clock::now();
            DenoiserSettings ds;
            ds.threads = o.threads;
            denoised = denoise(denoiser_input(half, film), ds);
            if (!o.quiet) {
                std::printf(
                    "denoised in %.2f s\n",
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count());
            }
        }
    }
    const bool have_denoised = !denoised.pixels.empty();
    const Image& shown = have_denoised && !exr ? denoised : image;
    write_output(o.output, shown, png_look(o), &film, have_denoised && exr ? &denoised : nullptr);
    // The last preview is the image shown (whatever the output's format), tone-mapped.
    if (!o.preview.empty()) {
        OutputLook preview = png_look(o);
        preview.png_bits = 8;  // a quick look
        write_output(o.preview, shown, preview, &film);
    }
    const bool partial =
        stats.samples_per_pixel < std::uint32_t(o.spp) && !stats.noise_target_reached;
    if (!o.quiet || partial) {
        // The noise estimate exists with a target only (NoiseEstimate's snapshot).
        std::string noise_summary;
        if (o.noise_target > 0.0) {
            char text[96];
            std::snprintf(text, sizeof text, ", estimated relative error %.3g%s", stats.noise,
                          stats.noise_target_reached ? " (the --noise-target)" : "");
            noise_summary = text;
        }
        const double rate = stats.seconds > 0.0 ? double(stats.samples) / stats.seconds : 0.0;
        std::string region_summary;
        if (!o.region.whole()) {
            char text[96];
            std::snprintf(text, sizeof text, " (region at %d,%d of %dx%d)", o.region.x0,
                          o.region.y0, camera.width(), camera.height());
            region_summary = text;
        }
        std::printf(
            "%dx%d%s, %u of %d spp in %d passes, %u threads: render %.2f s (%.2f M "
            "samples/s)%s, total %.2f s, peak memory %.0f MiB\n",
            film.width, film.height, region_summary.c_str(), stats.samples_per_pixel, o.spp,
            stats.passes,
            o.threads > 0 ? unsigned(o.threads) : std::max(1u, std::thread::hardware_concurrency()),
            stats.seconds, rate * 1e-6, noise_summary.c_str(),
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
