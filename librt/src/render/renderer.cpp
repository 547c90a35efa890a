// The render loop (run_block) and the entry points built on it: render, render_block and
// render_progressive. Over 400 lines: the entry points share the loop's private
// types, so they stay in one file.

#include "film/camera_importance.h"
#include "render/aov.h"

#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/render/pass_combination.h>
#include <librt/render/renderer.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <ctime>
#include <exception>
#include <mutex>
#include <string>
#include <system_error>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace librt {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

/// CPU seconds the process has used (all threads). std::clock, not clock_gettime's
/// CLOCK_PROCESS_CPUTIME_ID: the same on Linux and portable.
double cpu_now() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

struct Tile {
    int x0, y0, x1, y1;  // pixel range [x0, x1) x [y0, y1)
};

void validate_threads_and_tiles(const RenderSettings& s) {
    if (s.threads < 0 || s.threads > 1024) {
        throw Error("threads = " + std::to_string(s.threads) + ": must be in [0, 1024]");
    }
    if (s.tile_size < 1) {
        throw Error("tile_size = " + std::to_string(s.tile_size) + ": must be >= 1");
    }
    if (s.sampler != SamplerKind::Independent && s.sampler != SamplerKind::Sobol) {
        throw Error("sampler = " + std::to_string(static_cast<int>(s.sampler)) +
                    ": must be SamplerKind::Independent or SamplerKind::Sobol");
    }
}

/// How run_block ended.
struct BlockOutcome {
    std::uint64_t samples = 0;    // Integrator::li (or li_splatting) calls
    std::uint64_t nonfinite = 0;  // of which non-finite
    bool complete = false;        // every pixel of the block got all its samples
    bool cancelled = false;       // settings.cancel stopped it
    bool aborted = false;         // `tick` stopped it
};

/// Called on the calling thread about ten times a second with the fraction of the
/// block's tiles done; returning true stops the block (as a cancellation would).
using Tick = std::function<bool(double fraction)>;

/// Where the samples of `film` splat to, for an integrator that splats (none otherwise):
/// film.splats, created over the whole camera image - splats land anywhere, whatever
/// region or sample range the block covers - or checked to be that size.
SplatTarget splat_target(const Camera& camera, const Integrator& integrator, Film& film) {
    if (!integrator.splats()) return {};
    if (!film.splats) {
        film.splats.emplace(camera.width(), camera.height(), splat_filter_settings(camera));
    } else if (film.splats->width() != camera.width() || film.splats->height() != camera.height()) {
        throw Error("film splats " + std::to_string(film.splats->width()) + " x " +
                    std::to_string(film.splats->height()) + ": must be the camera's " +
                    std::to_string(camera.width()) + " x " + std::to_string(camera.height()));
    }
    return {&camera, &*film.splats};
}

// The one render loop under every entry point: threads take the block's tiles from an
// atomic counter and render each pixel's samples onto its film record, in sample order.
// The calling thread watches (ticks) until the workers are done.
// With `ends` (adaptive sampling: one count per film pixel, film.pixels.size()), each pixel of the
// block is rendered from the samples it holds up to its own end instead of [first, first + count).
BlockOutcome run_block(const Scene& scene, const Camera& camera, const Integrator& integrator,
                       Film& film, FilmOrigin origin, const RenderBlock& block,
                       const RenderSettings& settings, const Tick& tick,
                       const std::uint32_t* ends = nullptr) {
    BlockOutcome outcome;
    const SplatTarget target = splat_target(camera, integrator, film);
    const int width = block.x1 - block.x0;
    const int height = block.y1 - block.y0;
    if (width <= 0 || height <= 0 || block.count == 0) {
        outcome.complete = true;
        return outcome;
    }
    // Tiles of the block in row-major order; each is written by exactly one thread. A tile
    // larger than the block is the block (and keeps the index arithmetic far from overflow).
    const int tile = std::min(settings.tile_size, std::max(width, height));
    const int tiles_x = (width + tile - 1) / tile;
    const int tiles_y = (height + tile - 1) / tile;
    const auto tile_count = static_cast<std::size_t>(tiles_x) * static_cast<std::size_t>(tiles_y);
    const auto tile_at = [&](std::size_t i) {
        const int tx = static_cast<int>(i % static_cast<std::size_t>(tiles_x));
        const int ty = static_cast<int>(i / static_cast<std::size_t>(tiles_x));
        return Tile{block.x0 + tx * tile, block.y0 + ty * tile,
                    block.x0 + std::min(width, (tx + 1) * tile),
                    block.y0 + std::min(height, (ty + 1) * tile)};
    };

    unsigned thread_count = settings.threads > 0 ? static_cast<unsigned>(settings.threads)
                                                 : std::thread::hardware_concurrency();
    thread_count = std::clamp<unsigned>(
        thread_count, 1u, static_cast<unsigned>(std::min<std::size_t>(tile_count, 1024)));

    std::atomic<std::size_t> next_tile{0};
    std::atomic<std::size_t> tiles_done{0};
    std::atomic<std::uint64_t> sample_total{0};
    std::atomic<std::uint64_t> nonfinite_total{0};
    std::atomic<bool> cancelled{false};
    std::atomic<bool> aborted{false};
    std::atomic<bool> failed{false};
    std::exception_ptr failure;
    std::mutex mutex;
    std::condition_variable finished_cv;
    unsigned workers_finished = 0;

    const auto stop_requested = [&] {
        if (failed.load(std::memory_order_relaxed) || aborted.load(std::memory_order_relaxed))
            return true;
        if (settings.cancel != nullptr && settings.cancel->load(std::memory_order_relaxed)) {
            cancelled.store(true, std::memory_order_relaxed);
            return true;
        }
        return false;
    };

    // Cancellation is checked before every pixel and every kCancelCheckSamples samples
    // within one, so even a pixel of 2^20 samples cannot hold up a cancelled render. A
    // pixel stopped part-way keeps the samples it took: its record stays consistent.
    constexpr std::uint32_t kCancelCheckSamples = 64;
    const bool with_aovs = film.has_aovs();
    const bool with_splats = target.film != nullptr;
    const std::uint32_t end = block.first + block.count;
    // The AOV sums and splatting as compile-time choices: the plain render's per-sample
    // loop then carries neither the branches nor the AOV code, and calls li() as it always
    // did (the loop runs once per camera sample, ~21 M times in the report's synthesis).
    const auto render_tile_with = [&](const Tile& t, std::uint64_t& samples,
                                      std::uint64_t& nonfinite, auto aovs_wanted,
                                      auto splats_wanted) {
        constexpr bool kAovs = decltype(aovs_wanted)::value;
        constexpr bool kSplats = decltype(splats_wanted)::value;
        const SamplerKind sampler_kind = settings.sampler;
        const std::uint64_t seed = settings.seed;
        for (int y = t.y0; y < t.y1; ++y) {
            for (int x = t.x0; x < t.x1; ++x) {
                const std::size_t index = film.index(x - origin.x, y - origin.y);
                // The running sums, continued in sample order (see film.h).
                FilmPixel pixel = film.pixels[index];
                AovPixel aov = kAovs ? film.aovs[index] : AovPixel{};
                const auto px = static_cast<std::uint32_t>(x);
                const auto py = static_cast<std::uint32_t>(y);
                const std::uint32_t first = ends != nullptr ? pixel.samples : block.first;
                const std::uint32_t last = ends != nullptr ? ends[index] : end;
                bool stopped = false;
                std::uint32_t taken = 0;
                std::uint32_t until_check = 0;  // samples left before the next cancel check
                for (std::uint32_t s = first; s < last; ++s) {
                    if (until_check-- == 0) {
                        if (stop_requested()) {
                            stopped = true;
                            break;
                        }
                        until_check = kCancelCheckSamples - 1;
                    }
                    Sampler sampler(sampler_kind, px, py, s, seed);
                    const CameraRay camera_ray = camera.sample_ray(x, y, sampler);
                    const Ray& ray = camera_ray.ray;
                    if constexpr (kAovs) {
                        const AovSample a = sample_aovs(scene, ray, px, py, s, seed);
                        // The albedo is filtered like the beauty: with the weight's sign
                        // (its size is one per filter; resolve_layers divides it out).
                        if (camera_ray.weight < 0.0f) {
                            aov.albedo -= glm::dvec3(a.albedo);
                            ++aov.negative;
                        } else {
                            aov.albedo += glm::dvec3(a.albedo);
                        }
                        aov.normal += glm::dvec3(a.normal);
                        if (a.hit) {
                            aov.depth += static_cast<double>(a.depth);
                            ++aov.hits;
                        }
                    }
                    // The filter weight makes the plain mean the filter's estimate (Mitchell's
                    // signed weights); x 1.0f is exact, so other filters are unchanged.
                    glm::vec3 l;
                    if constexpr (kSplats) {
                        l = integrator.li_splatting(scene, ray, sampler, target) *
                            camera_ray.weight;
                    } else {
                        l = integrator.li(scene, ray, sampler) * camera_ray.weight;
                    }
                    ++taken;
                    if (finite(l)) [[likely]] {
                        pixel.radiance += glm::dvec3(l);
                        ++pixel.finite;
                    }
                }
                // Counted per pixel, not per sample: the counters stay out of the sample loop.
                pixel.samples += taken;
                samples += taken;
                nonfinite += taken - (pixel.finite - film.pixels[index].finite);
                film.pixels[index] = pixel;
                if constexpr (kAovs) film.aovs[index] = aov;
                if (stopped) return false;
            }
        }
        return true;
    };
    const auto render_tile = [&](const Tile& t, std::uint64_t& samples, std::uint64_t& nonfinite) {
        if (with_splats) {
            return with_aovs
                       ? render_tile_with(t, samples, nonfinite, std::true_type{}, std::true_type{})
                       : render_tile_with(t, samples, nonfinite, std::false_type{},
                                          std::true_type{});
        }
        return with_aovs
                   ? render_tile_with(t, samples, nonfinite, std::true_type{}, std::false_type{})
                   : render_tile_with(t, samples, nonfinite, std::false_type{}, std::false_type{});
    };

    const auto worker = [&] {
        std::uint64_t samples = 0;
        std::uint64_t nonfinite = 0;
        try {
            for (;;) {
                if (stop_requested()) break;
                const std::size_t i = next_tile.fetch_add(1, std::memory_order_relaxed);
                if (i >= tile_count) break;
                if (!render_tile(tile_at(i), samples, nonfinite)) break;
                tiles_done.fetch_add(1, std::memory_order_relaxed);
            }
        } catch (...) {
            const std::lock_guard<std::mutex> lock(mutex);
            if (!failure) failure = std::current_exception();
            failed.store(true, std::memory_order_relaxed);
        }
        sample_total.fetch_add(samples, std::memory_order_relaxed);
        nonfinite_total.fetch_add(nonfinite, std::memory_order_relaxed);
        const std::lock_guard<std::mutex> lock(mutex);
        ++workers_finished;
        finished_cv.notify_one();
    };

    std::vector<std::thread> threads;
    threads.reserve(thread_count);
    try {
        for (unsigned i = 0; i < thread_count; ++i) threads.emplace_back(worker);
    } catch (const std::system_error& e) {
        failed.store(true);
        for (std::thread& t : threads) t.join();
        throw Error(std::string("cannot start render threads: ") + e.what());
    }

    // The calling thread watches: ticks about ten times a second, and wakes as soon as all
    // workers are done.
    {
        std::unique_lock<std::mutex> lock(mutex);
        while (workers_finished < threads.size()) {
            finished_cv.wait_for(lock, std::chrono::milliseconds(100));
            if (workers_finished == threads.size() || !tick) continue;
            lock.unlock();
            const double fraction =
                static_cast<double>(tiles_done.load(std::memory_order_relaxed)) /
                static_cast<double>(tile_count);
            try {
                if (tick(fraction)) aborted.store(true, std::memory_order_relaxed);
            } catch (...) {  // a throwing progress callback stops the render, then is rethrown
                const std::lock_guard<std::mutex> guard(mutex);
                if (!failure) failure = std::current_exception();
                failed.store(true, std::memory_order_relaxed);
            }
            lock.lock();
        }
    }
    for (std::thread& t : threads) t.join();

    if (failure) std::rethrow_exception(failure);
    outcome.samples = sample_total.load();
    outcome.nonfinite = nonfinite_total.load();
    outcome.complete = tiles_done.load() == tile_count;
    outcome.cancelled = !outcome.complete && cancelled.load();
    outcome.aborted = !outcome.complete && !outcome.cancelled && aborted.load();
    return outcome;
}

void check_film_matches(const Film& film, const Camera& camera) {
    if (film.width != camera.width() || film.height != camera.height()) {
        throw Error("film size " + std::to_string(film.width) + " x " +
                    std::to_string(film.height) + ": must be the camera's " +
                    std::to_string(camera.width()) + " x " + std::to_string(camera.height()));
    }
}

}  // namespace

void validate(const RenderSettings& s) {
    if (s.samples_per_pixel < 1 || s.samples_per_pixel > static_cast<int>(kMaxSamplesPerPixel)) {
        throw Error("samples_per_pixel = " + std::to_string(s.samples_per_pixel) +
                    ": must be in [1, 1048576]");
    }
    validate_threads_and_tiles(s);
    validate(s.adaptive);
}

void validate(const ProgressiveSettings& s) {
    validate(s.render);
    if (s.pass_samples < 1 || s.pass_samples > static_cast<int>(kMaxSamplesPerPixel)) {
        throw Error("pass_samples = " + std::to_string(s.pass_samples) +
                    ": must be in [1, 1048576]");
    }
    if (!std::isfinite(s.time_limit) || s.time_limit < 0.0) {
        throw Error("time_limit = " + std::to_string(s.time_limit) +
                    ": must be finite and >= 0 seconds");
    }
}

namespace {

/// Renders `block` onto `film` in two runs, the first half of its samples and then the
/// rest, and returns the film as it was between them (for PassCombination). The same
/// samples in the same order per pixel as one run: the film's sums are identical.
BlockOutcome run_block_in_halves(const Scene& scene, const Camera& camera,
                                 const Integrator& integrator, Film& film, const RenderBlock& block,
                                 const RenderSettings& settings, const Tick& tick, Film& half) {
    RenderBlock first = block;
    first.count = block.count / 2;
    RenderBlock second = block;
    second.first = block.first + first.count;
    second.count = block.count - first.count;
    const Tick first_tick = tick ? Tick([&](double f) { return tick(0.5 * f); }) : Tick();
    const Tick second_tick = tick ? Tick([&](double f) { return tick(0.5 + 0.5 * f); }) : Tick();
    BlockOutcome a = run_block(scene, camera, integrator, film, {}, first, settings, first_tick);
    if (!a.complete) return a;
    half = film;
    const BlockOutcome b =
        run_block(scene, camera, integrator, film, {}, second, settings, second_tick);
    a.samples += b.samples;
    a.nonfinite += b.nonfinite;
    a.complete = b.complete;
    a.cancelled = b.cancelled;
    a.aborted = b.aborted;
    return a;
}

/// train(); with `keep`, every pass of at least 2 samples per pixel is rendered in halves
/// and added to it.
RenderStats train_passes(const Scene& scene, const Camera& camera, Integrator& integrator,
                         const RenderSettings& settings, PassCombination* keep) {
    const Clock::time_point start = Clock::now();
    const double cpu_start = cpu_now();
    validate_threads_and_tiles(settings);
    RenderStats stats;
    Film scratch;
    for (int pass = 0;; ++pass) {
        const std::uint32_t spp =
            std::min(integrator.begin_training_pass(pass), kMaxSamplesPerPixel);
        if (spp == 0) break;
        if (scratch.width == 0) {
            check_image_size(camera.width(), camera.height());
            scratch = Film(camera.width(), camera.height());
        } else {
            std::fill(scratch.pixels.begin(), scratch.pixels.end(), FilmPixel{});
            scratch.splats.reset();  // run_block makes a new one for an integrator that splats
        }
        RenderSettings rs = settings;
        rs.progress = nullptr;
        // A seed of its own per pass (splitmix64 of seed and pass, salted): the image's
        // samples (seed itself) never reuse a training sample's numbers.
        rs.seed = mix64(mix64(settings.seed ^ 0x7a11ed6a1de5eedULL) + std::uint64_t(pass));
        const RenderBlock whole{0, 0, scratch.width, scratch.height, 0, spp};
        const bool halves = keep != nullptr && spp >= 2;
        Film half;
        const BlockOutcome outcome =
            halves ? run_block_in_halves(scene, camera, integrator, scratch, whole, rs, {}, half)
                   : run_block(scene, camera, integrator, scratch, {}, whole, rs, {});
        stats.samples += outcome.samples;
        stats.nonfinite_samples += outcome.nonfinite;
        integrator.end_training_pass(pass);
        if (halves && outcome.complete) (void)keep->add(half, scratch);
        if (!outcome.complete) {
            stats.cancelled = outcome.cancelled;
            break;
        }
        ++stats.training_passes;
    }
    stats.seconds = seconds_since(start);
    stats.cpu_seconds = cpu_now() - cpu_start;
    return stats;
}

}  // namespace

RenderStats train(const Scene& scene, const Camera& camera, Integrator& integrator,
                  const RenderSettings& settings, PassCombination* kept) {
    return train_passes(scene, camera, integrator, settings,
                        integrator.keeps_training_samples() ? kept : nullptr);
}

namespace {

/// render() onto `film` (of the camera's size, holding no samples); kept training passes
/// only when `may_keep`.
Image render_onto(const Scene& scene, const Camera& camera, Integrator& integrator, Film& film,
                  const RenderSettings& settings, bool may_keep, RenderStats* stats) {
    const Clock::time_point start = Clock::now();
    const double cpu_start = cpu_now();
    integrator.preprocess(scene);
    const auto spp = static_cast<std::uint32_t>(settings.samples_per_pixel);
    // Adaptive sampling's pilot (0: every pixel gets spp samples).
    const std::uint32_t pilot =
        settings.adaptive.enabled ? adaptive_pilot_samples(settings.adaptive, spp) : 0;
    // The training passes kept in the image when the integrator allows it (guiding's
    // keep_training_samples) and the image has the 2 samples per pixel its own variance
    // estimate needs; not with adaptive sampling, whose pixels hold different counts.
    PassCombination kept;
    const bool keep = may_keep && pilot == 0 && integrator.keeps_training_samples() && spp >= 2;
    const RenderStats training = train(scene, camera, integrator, settings, keep ? &kept : nullptr);
    const RenderBlock whole{0, 0, film.width, film.height, 0, spp};
    const auto tick_over = [&](double from, double to) {
        if (!settings.progress) return Tick();
        return Tick([&settings, &start, from, to](double fraction) {
            settings.progress({from + (to - from) * fraction, seconds_since(start), 0, 0});
            return false;
        });
    };
    Film half;
    BlockOutcome outcome;
    std::vector<std::uint32_t> ends;  // adaptive sampling: each pixel's count
    if (pilot > 0) {
        // The pilot in two halves (their means' difference is the noise estimate), then
        // every pixel up to its own count.
        const double pilot_share = double(pilot) / double(spp);
        outcome = run_block_in_halves(scene, camera, integrator, film,
                                      {0, 0, film.width, film.height, 0, pilot}, settings,
                                      tick_over(0.0, pilot_share), half);
        if (outcome.complete) {
            ends = adaptive_sample_counts(half, film, spp, settings.adaptive);
            const BlockOutcome rest = run_block(scene, camera, integrator, film, {},
                                                {0, 0, film.width, film.height, pilot, spp - pilot},
                                                settings, tick_over(pilot_share, 1.0), ends.data());
            outcome.samples += rest.samples;
            outcome.nonfinite += rest.nonfinite;
            outcome.complete = rest.complete;
            outcome.cancelled = rest.cancelled;
        }
    } else {
        const Tick tick = tick_over(0.0, 1.0);
        outcome =
            keep ? run_block_in_halves(scene, camera, integrator, film, whole, settings, tick, half)
                 : run_block(scene, camera, integrator, film, {}, whole, settings, tick);
    }
    if (settings.progress && outcome.complete)
        settings.progress({1.0, seconds_since(start), 1, spp});

    // With kept passes: the image joins them, all weighted by inverse variance (an image
    // whose variance cannot be estimated, e.g. black, is shown alone).
    Image image = keep && outcome.complete ? kept.combined(half, film) : resolve(film);
    if (!outcome.complete) {
        // As before films: a pixel the cancellation stopped part-way stays black.
        for (std::size_t i = 0; i < film.pixels.size(); ++i) {
            const std::uint32_t wanted = ends.empty() ? (pilot > 0 ? pilot : spp) : ends[i];
            if (film.pixels[i].samples < wanted) image.pixels[i] = glm::vec3(0.0f);
        }
    }
    if (stats != nullptr) {
        *stats = RenderStats{};
        stats->seconds = seconds_since(start);
        stats->cpu_seconds = cpu_now() - cpu_start;
        stats->samples = outcome.samples;
        stats->nonfinite_samples = outcome.nonfinite;
        stats->cancelled = outcome.cancelled;
        stats->passes = outcome.complete ? 1 : 0;
        stats->samples_per_pixel = outcome.complete ? spp : 0;
        stats->training_passes = training.training_passes;
    }
    return image;
}

}  // namespace

Image render(const Scene& scene, const Camera& camera, Integrator& integrator,
             const RenderSettings& settings, RenderStats* stats) {
    validate(settings);
    check_image_size(camera.width(), camera.height());  // before allocating anything
    Film film(camera.width(), camera.height());
    return render_onto(scene, camera, integrator, film, settings, true, stats);
}

RenderStats render(const Scene& scene, const Camera& camera, Integrator& integrator, Film& film,
                   const RenderSettings& settings) {
    validate(settings);
    if (film.width == 0 && film.height == 0) {
        check_image_size(camera.width(), camera.height());
        film = Film(camera.width(), camera.height());
    }
    check_film_matches(film, camera);
    if (uniform_sample_count(film) != 0 || film.splats) {
        throw Error(
            "film: must hold no samples (render() fills an empty film; "
            "render_block continues one)");
    }
    RenderStats stats;
    (void)render_onto(scene, camera, integrator, film, settings, false, &stats);
    return stats;
}

RenderStats render_block(const Scene& scene, const Camera& camera, const Integrator& integrator,
                         Film& film, const RenderBlock& block, const RenderSettings& settings) {
    check_film_matches(film, camera);
    return render_block(scene, camera, integrator, film, FilmOrigin{}, block, settings);
}

namespace {

// render_block's checks of the film's region and the block (before anything is rendered);
// with `ends`, each pixel's own end instead of block.first + block.count.
void check_block(const Camera& camera, const Film& film, FilmOrigin origin,
                 const RenderBlock& block, const std::span<const std::uint32_t>* ends) {
    // The film's region, in 64 bits: origin + size cannot overflow.
    const std::int64_t rx0 = origin.x;
    const std::int64_t ry0 = origin.y;
    const std::int64_t rx1 = rx0 + film.width;
    const std::int64_t ry1 = ry0 + film.height;
    if (rx0 < 0 || ry0 < 0 || rx1 > camera.width() || ry1 > camera.height()) {
        throw Error("film region [" + std::to_string(rx0) + ", " + std::to_string(rx1) + ") x [" +
                    std::to_string(ry0) + ", " + std::to_string(ry1) +
                    "): must lie in the camera's " + std::to_string(camera.width()) + " x " +
                    std::to_string(camera.height()) + " image");
    }
    if (block.x0 < rx0 || block.x0 > block.x1 || block.x1 > rx1 || block.y0 < ry0 ||
        block.y0 > block.y1 || block.y1 > ry1) {
        throw Error(
            "block [" + std::to_string(block.x0) + ", " + std::to_string(block.x1) + ") x [" +
            std::to_string(block.y0) + ", " + std::to_string(block.y1) + "): must lie in the " +
            std::to_string(film.width) + " x " + std::to_string(film.height) + " film" +
            (rx0 == 0 && ry0 == 0
                 ? std::string()
                 : " placed at (" + std::to_string(rx0) + ", " + std::to_string(ry0) + ")"));
    }
    if (ends == nullptr && std::uint64_t{block.first} + block.count > kMaxSamplesPerPixel) {
        throw Error("block samples [" + std::to_string(block.first) + ", " +
                    std::to_string(std::uint64_t{block.first} + block.count) +
                    "): a pixel holds at most 1048576 samples");
    }
    if (ends != nullptr && ends->size() != film.pixels.size()) {
        throw Error("ends: " + std::to_string(ends->size()) + " counts for a film of " +
                    std::to_string(film.pixels.size()) + " pixels (one per film pixel)");
    }
    for (int y = block.y0; y < block.y1; ++y) {
        for (int x = block.x0; x < block.x1; ++x) {
            const std::size_t i = film.index(x - origin.x, y - origin.y);
            const FilmPixel& pixel = film.pixels[i];
            if (pixel.samples != block.first) {
                throw Error("block.first = " + std::to_string(block.first) + ": film pixel (" +
                            std::to_string(x) + ", " + std::to_string(y) + ") holds " +
                            std::to_string(pixel.samples) +
                            " samples (a block continues a pixel's samples in order)");
            }
            if (ends != nullptr && ((*ends)[i] < block.first || (*ends)[i] > kMaxSamplesPerPixel)) {
                throw Error("ends: pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                            ") = " + std::to_string((*ends)[i]) + ": must be in [" +
                            std::to_string(block.first) + ", 1048576] (block.first, the samples " +
                            "it holds, to the most a pixel holds)");
            }
        }
    }
}

RenderStats render_checked_block(const Scene& scene, const Camera& camera,
                                 const Integrator& integrator, Film& film, FilmOrigin origin,
                                 const RenderBlock& block, const std::uint32_t* ends,
                                 const RenderSettings& settings) {
    const Clock::time_point start = Clock::now();
    const double cpu_start = cpu_now();
    Tick tick;
    if (settings.progress) {
        tick = [&](double fraction) {
            settings.progress({fraction, seconds_since(start), 0, block.first});
            return false;
        };
    }
    const BlockOutcome outcome =
        run_block(scene, camera, integrator, film, origin, block, settings, tick, ends);
    RenderStats stats;
    stats.seconds = seconds_since(start);
    stats.cpu_seconds = cpu_now() - cpu_start;
    stats.samples = outcome.samples;
    stats.nonfinite_samples = outcome.nonfinite;
    stats.cancelled = outcome.cancelled;
    stats.passes = outcome.complete ? 1 : 0;
    // With ends the pixels hold different counts: the level all of them reached.
    stats.samples_per_pixel =
        outcome.complete && ends == nullptr ? block.first + block.count : block.first;
    if (settings.progress && outcome.complete)
        settings.progress({1.0, stats.seconds, 1, stats.samples_per_pixel});
    return stats;
}

}  // namespace

RenderStats render_block(const Scene& scene, const Camera& camera, const Integrator& integrator,
                         Film& film, FilmOrigin origin, const RenderBlock& block,
                         const RenderSettings& settings) {
    validate_threads_and_tiles(settings);
    check_block(camera, film, origin, block, nullptr);
    return render_checked_block(scene, camera, integrator, film, origin, block, nullptr, settings);
}

RenderStats render_block_to_counts(const Scene& scene, const Camera& camera,
                                   const Integrator& integrator, Film& film, FilmOrigin origin,
                                   const RenderBlock& block, std::span<const std::uint32_t> ends,
                                   const RenderSettings& settings) {
    validate_threads_and_tiles(settings);
    check_block(camera, film, origin, block, &ends);
    RenderBlock marked = block;
    marked.count = 1;  // run_block skips a block of no samples; with ends it reads no count
    return render_checked_block(scene, camera, integrator, film, origin, marked, ends.data(),
                                settings);
}

RenderStats render_progressive(const Scene& scene, const Camera& camera, Integrator& integrator,
                               Film& film, const ProgressiveSettings& settings, Image* image) {
    validate(settings);
    const std::function<double()> clock = settings.clock ? settings.clock : [] {
        return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
    };
    const double start = clock();
    const double cpu_start = cpu_now();
    const auto elapsed = [&] { return clock() - start; };
    if (film.width == 0 && film.height == 0) {
        check_image_size(camera.width(), camera.height());
        film = Film(camera.width(), camera.height(), settings.aovs);
    }
    check_film_matches(film, camera);
    const std::uint32_t first = uniform_sample_count(film);
    const auto target = static_cast<std::uint32_t>(settings.render.samples_per_pixel);
    const auto pass = static_cast<std::uint32_t>(settings.pass_samples);
    const RenderSettings& rs = settings.render;
    const double limit = settings.time_limit;
    // Adaptive sampling: uniform passes up to the pilot (one ending at its half), then each
    // pass moves every pixel the same fraction of the way to its own count, so a film
    // stopped between passes holds each pixel's share: counts still chosen from the
    // neighbours' pilots only, its means still unbiased.
    const std::uint32_t pilot =
        rs.adaptive.enabled ? adaptive_pilot_samples(rs.adaptive, target) : 0;
    if (pilot > 0 && first != 0) {
        throw Error("film holds " + std::to_string(first) +
                    " samples per pixel: an adaptive progressive render starts from an empty "
                    "film (its pilot decides every pixel's count)");
    }
    Film pilot_half;                    // the film at pilot / 2 samples
    std::vector<std::uint32_t> counts;  // each pixel's final count, once the pilot is done
    std::vector<std::uint32_t> goals;   // each pixel's count at the end of the current pass

    RenderStats stats;
    stats.samples_per_pixel = first;
    std::uint32_t n = first;  // samples every pixel of `film` holds
    // Fraction of the work done once every pixel holds `samples` (and, with a time limit,
    // of the time used, whichever is further).
    const auto fraction = [&](double samples, double seconds) {
        double f = target > first ? (samples - first) / double(target - first) : 1.0;
        if (limit > 0.0) f = std::max(f, seconds / limit);
        return std::clamp(f, 0.0, 1.0);
    };
    // Kept training passes (as render() keeps them) need the film as it was at half the
    // target, which this call sees only when the film starts at or before it. Whether the
    // integrator keeps them is known after preprocess().
    const std::uint32_t mid = target / 2;
    bool keep = false;
    PassCombination kept;
    Film half;  // the film at `mid` samples (radiance and splats)
    const auto snapshot_half = [&] {
        half.width = film.width;
        half.height = film.height;
        half.pixels = film.pixels;
        half.splats = film.splats;
    };
    if (n < target) {
        integrator.preprocess(scene);
        keep = pilot == 0 && image != nullptr && integrator.keeps_training_samples() &&
               target >= 2 && first <= mid;
        const RenderStats training = train(scene, camera, integrator, rs, keep ? &kept : nullptr);
        stats.training_passes = training.training_passes;
        stats.cancelled = training.cancelled;
    }
    if (keep && n == mid) snapshot_half();
    Film work;  // the pass in progress: a copy of `film` that replaces it once complete
    while (n < target) {
        // A film holding no samples always gets its first pass, whatever the limit.
        if (limit > 0.0 && n > 0 && elapsed() >= limit) {
            stats.time_limit_reached = true;
            break;
        }
        if (rs.cancel != nullptr && rs.cancel->load()) {
            stats.cancelled = true;
            break;
        }
        std::uint32_t count = std::min(pass, target - n);
        if (keep && n < mid) count = std::min(count, mid - n);  // a pass ends at the half
        const std::uint32_t* ends = nullptr;
        if (pilot > 0 && n < pilot) {  // the pilot: passes end at its half and at its end
            count = std::min(count, (n < pilot / 2 ? pilot / 2 : pilot) - n);
        } else if (pilot > 0) {
            // Level n + count of the way from the pilot to the target: pixel p holds
            // pilot + floor((N_p - pilot) (level - pilot) / (target - pilot)), N_p at the end.
            const std::uint64_t step = n + count - pilot;
            const std::uint64_t span = target - pilot;
            goals.resize(counts.size());
            for (std::size_t i = 0; i < counts.size(); ++i)
                goals[i] = pilot + std::uint32_t((counts[i] - pilot) * step / span);
            ends = goals.data();
        }
        work = film;
        const RenderBlock block{0, 0, film.width, film.height, n, count};
        const Tick tick = [&](double done) {
            if (rs.progress) {
                const double seconds = elapsed();
                rs.progress({fraction(n + done * count, seconds), seconds, stats.passes, n});
            }
            return limit > 0.0 && n > 0 && elapsed() >= limit;
        };
        const BlockOutcome outcome =
            run_block(scene, camera, integrator, work, {}, block, rs, tick, ends);
        stats.samples += outcome.samples;
        stats.nonfinite_samples += outcome.nonfinite;
        if (!outcome.complete) {  // the unfinished pass is dropped with `work`
            stats.cancelled = outcome.cancelled;
            stats.time_limit_reached = outcome.aborted;
            break;
        }
        std::swap(film, work);
        n += count;
        if (keep && n == mid) snapshot_half();
        if (pilot > 0 && n == pilot / 2) pilot_half = film;
        if (pilot > 0 && n == pilot)
            counts = adaptive_sample_counts(pilot_half, film, target, rs.adaptive);
        ++stats.passes;
        stats.samples_per_pixel = n;
        if (rs.progress) {
            const double seconds = elapsed();
            rs.progress({fraction(n, seconds), seconds, stats.passes, n});
        }
    }
    if (image != nullptr) {
        *image =
            keep && n == target && !half.pixels.empty() ? kept.combined(half, film) : resolve(film);
    }
    stats.seconds = elapsed();
    stats.cpu_seconds = cpu_now() - cpu_start;
    return stats;
}

}  // namespace librt
