// The entry points built on the render loop (block_loop.h) and the pass sequence
// (pass_sequence.h): train, render, render_block, render_block_to_counts and
// render_progressive, with the checks of their settings, films and blocks.

#include "render/block_loop.h"
#include "render/pass_sequence.h"

#include <librt/core/error.h>
#include <librt/render/noise_estimate.h>
#include <librt/render/pass_combination.h>
#include <librt/render/renderer.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <functional>
#include <string>
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

void validate_threads_and_tiles(const BlockSettings& s) {
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

void check_film_matches(const Film& film, const Camera& camera) {
    if (film.width != camera.width() || film.height != camera.height()) {
        throw Error("film size " + std::to_string(film.width) + " x " +
                    std::to_string(film.height) + ": must be the camera's " +
                    std::to_string(camera.width()) + " x " + std::to_string(camera.height()));
    }
}

/// settings.region in the camera's image (the whole image by default); throws librt::Error
/// naming it when it leaves the image.
PixelRegion region_of(const RenderSettings& settings, const Camera& camera) {
    return region_in(settings.region, camera.width(), camera.height());
}

/// A region render's refusal of a splatting integrator (asked after preprocess()).
void check_region_integrator(const RenderSettings& settings, const Integrator& integrator) {
    if (!settings.region.whole() && integrator.splats()) {
        throw Error(
            "region: the integrator splats (light paths land on any pixel, so a region "
            "cannot hold the whole render's pixels): render the whole image");
    }
}

/// The radiance records of `region` alone (for the noise estimate of a region render).
Film region_records(const Film& film, const PixelRegion& region) {
    Film out;
    out.width = region.width();
    out.height = region.height();
    out.pixels.reserve(std::size_t(out.width) * std::size_t(out.height));
    for (int y = region.y0; y < region.y1; ++y) {
        for (int x = region.x0; x < region.x1; ++x) out.pixels.push_back(film.at(x, y));
    }
    return out;
}

/// The block of pass samples [first, first + count): over `region`, except adaptive
/// sampling's pilot (the uniform stage of a plan with one), which covers the whole film.
RenderBlock pass_block(const RenderPlan& plan, const PixelRegion& region, const Film& film,
                       std::uint32_t first, std::uint32_t count, const std::uint32_t* ends) {
    if (plan.pilot > 0 && ends == nullptr) return {0, 0, film.width, film.height, first, count};
    return {region.x0, region.y0, region.x1, region.y1, first, count};
}

}  // namespace

void validate(const BlockSettings& s) { validate_threads_and_tiles(s); }

void validate(const RenderSettings& s) {
    if (s.samples_per_pixel < 1 || s.samples_per_pixel > static_cast<int>(kMaxSamplesPerPixel)) {
        throw Error("samples_per_pixel = " + std::to_string(s.samples_per_pixel) +
                    ": must be in [1, 1048576]");
    }
    validate_threads_and_tiles(s);
    validate(s.adaptive);
    const PixelRegion& r = s.region;
    if (!r.whole() && (r.x0 < 0 || r.y0 < 0 || r.x1 <= r.x0 || r.y1 <= r.y0)) {
        throw Error("region [" + std::to_string(r.x0) + ", " + std::to_string(r.x1) + ") x [" +
                    std::to_string(r.y0) + ", " + std::to_string(r.y1) +
                    "): must be non-empty with x0, y0 >= 0 (or all 0: the whole image)");
    }
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
    if (!(s.noise_target >= 0.0 && s.noise_target <= 1.0)) {
        throw Error("noise_target = " + std::to_string(s.noise_target) +
                    ": must be in [0, 1] (0 = none)");
    }
}

namespace {

/// Renders `block` onto `film` in two runs, the first half of its samples and then the
/// rest, and returns the film as it was between them (for PassCombination). The same
/// samples in the same order per pixel as one run: the film's sums are identical.
BlockOutcome run_block_in_halves(const Scene& scene, const Camera& camera,
                                 const Integrator& integrator, Film& film, const RenderBlock& block,
                                 const BlockSettings& settings, const Tick& tick, Film& half) {
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
        BlockSettings rs = settings.block();
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
    const PixelRegion region = region_of(settings, camera);
    integrator.preprocess(scene);
    check_region_integrator(settings, integrator);
    RenderPlan plan = plan_of(settings);
    // A region's image is not joined to kept passes: their weights are the whole image's.
    plan.keep = may_keep && settings.region.whole() && keeps_training_passes(plan, integrator);
    PassCombination kept;
    const RenderStats training =
        train(scene, camera, integrator, settings, plan.keep ? &kept : nullptr);
    // Progress: the uniform stage is the pilot's share of the work (all of it without
    // one), each of its halves half of that; the rest stage the remainder.
    const double pilot_share = plan.pilot > 0 ? double(plan.pilot) / double(plan.spp) : 1.0;
    const auto tick_over = [&](double from, double to) {
        if (!settings.progress) return Tick();
        return Tick([&settings, &start, from, to](double fraction) {
            settings.progress({from + (to - from) * fraction, seconds_since(start), 0, 0});
            return false;
        });
    };
    Film half;
    BlockOutcome outcome;
    PassRunner runner;
    runner.pass = [&](std::uint32_t first, std::uint32_t count, const std::uint32_t* ends) {
        Tick tick = ends != nullptr ? tick_over(pilot_share, 1.0) : tick_over(0.0, pilot_share);
        if (tick && ends == nullptr && plan.in_halves()) {
            tick = first == 0 ? Tick([tick](double f) { return tick(0.5 * f); })
                              : Tick([tick](double f) { return tick(0.5 + 0.5 * f); });
        }
        const BlockOutcome pass =
            run_block(scene, camera, integrator, film, {},
                      pass_block(plan, region, film, first, count, ends), settings, tick, ends);
        outcome.samples += pass.samples;
        outcome.nonfinite += pass.nonfinite;
        outcome.complete = pass.complete;
        outcome.cancelled = pass.cancelled;
        outcome.aborted = pass.aborted;
        return pass.complete;
    };
    runner.reached_half = [&] { half = film; };
    PassSequence sequence(plan, 0);
    (void)sequence.run(runner, half, film);
    const std::vector<std::uint32_t>& ends = sequence.counts();  // adaptive: each pixel's count
    const bool keep = plan.keep;
    const std::uint32_t spp = plan.spp;
    if (settings.progress && outcome.complete)
        settings.progress({1.0, seconds_since(start), 1, spp});

    // With kept passes: the image joins them, all weighted by inverse variance (an image
    // whose variance cannot be estimated, e.g. black, is shown alone).
    Image image = keep && outcome.complete ? kept.combined(half, film) : resolve(film);
    if (!outcome.complete) {
        // As before films: a pixel the cancellation stopped part-way stays black.
        for (std::size_t i = 0; i < film.pixels.size(); ++i) {
            const std::uint32_t wanted = ends.empty() ? plan.uniform_end() : ends[i];
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
    (void)region_of(settings, camera);                  // before allocating anything
    check_image_size(camera.width(), camera.height());  // likewise
    Film film(camera.width(), camera.height());
    return render_onto(scene, camera, integrator, film, settings, true, stats);
}

RenderStats render(const Scene& scene, const Camera& camera, Integrator& integrator, Film& film,
                   const RenderSettings& settings) {
    validate(settings);
    (void)region_of(settings, camera);
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
                         Film& film, const RenderBlock& block, const BlockSettings& settings) {
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
                                 const BlockSettings& settings) {
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
                         const BlockSettings& settings) {
    validate_threads_and_tiles(settings);
    check_block(camera, film, origin, block, nullptr);
    return render_checked_block(scene, camera, integrator, film, origin, block, nullptr, settings);
}

RenderStats render_block_to_counts(const Scene& scene, const Camera& camera,
                                   const Integrator& integrator, Film& film, FilmOrigin origin,
                                   const RenderBlock& block, std::span<const std::uint32_t> ends,
                                   const BlockSettings& settings) {
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
    const PixelRegion region = region_of(settings.render, camera);
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
    // pass moves every pixel the same fraction of the way to its own count (PassSequence),
    // so a film stopped between passes holds each pixel's share: counts still chosen from
    // the neighbours' pilots only, its means still unbiased.
    RenderPlan plan = plan_of(rs);
    if (plan.pilot > 0 && first != 0) {
        throw Error("film holds " + std::to_string(first) +
                    " samples per pixel: an adaptive progressive render starts from an empty "
                    "film (its pilot decides every pixel's count)");
    }
    if (!rs.region.whole() && first != 0) {
        throw Error("film holds " + std::to_string(first) +
                    " samples per pixel: a progressive render of a region starts from an "
                    "empty film");
    }
    RenderStats stats;
    stats.samples_per_pixel = first;
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
    PassCombination kept;
    // The film at the plan's half level (radiance and splats): kept passes' or the pilot's.
    Film half;
    if (first < target) {
        integrator.preprocess(scene);
        check_region_integrator(rs, integrator);
        plan.keep = image != nullptr && first <= target / 2 && rs.region.whole() &&
                    keeps_training_passes(plan, integrator);
        const RenderStats training =
            train(scene, camera, integrator, rs, plan.keep ? &kept : nullptr);
        stats.training_passes = training.training_passes;
        stats.cancelled = training.cancelled;
    }
    Film work;  // the pass in progress: a copy of `film` that replaces it once complete
    // The film's estimated relative error (NoiseEstimate: a snapshot of the pixels, 36 bytes
    // each, render_memory.h), for the noise target and the progress reports alike: what a
    // user reads on the progress display is what a target stops on.
    NoiseEstimate target_noise;
    const bool estimate_noise = settings.noise_target > 0.0 || static_cast<bool>(rs.progress);
    const auto noise = [&] { return target_noise.relative_error().value_or(-1.0); };
    PassRunner runner;
    runner.pass = [&](std::uint32_t n, std::uint32_t count, const std::uint32_t* ends) {
        // A film holding no samples always gets its first pass, whatever the limit.
        if (limit > 0.0 && n > 0 && elapsed() >= limit) {
            stats.time_limit_reached = true;
            return false;
        }
        if (settings.noise_target > 0.0 && target_noise.relative_error() &&
            *target_noise.relative_error() <= settings.noise_target) {
            stats.noise_target_reached = true;
            return false;
        }
        if (rs.cancel != nullptr && rs.cancel->load()) {
            stats.cancelled = true;
            return false;
        }
        work = film;
        const RenderBlock block = pass_block(plan, region, film, n, count, ends);
        const Tick tick = [&](double done) {
            if (rs.progress) {
                const double seconds = elapsed();
                rs.progress(
                    {fraction(n + done * count, seconds), seconds, stats.passes, n, noise()});
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
            return false;
        }
        std::swap(film, work);
        return true;
    };
    runner.reached_half = [&] {
        half.width = film.width;
        half.height = film.height;
        half.pixels = film.pixels;
        half.splats = film.splats;
    };
    runner.passed = [&](std::uint32_t n) {
        ++stats.passes;
        stats.samples_per_pixel = n;
        // A region's noise is its own: the pixels outside gain no samples.
        if (estimate_noise && rs.region.whole()) target_noise.observe(film, n);
        if (estimate_noise && !rs.region.whole())
            target_noise.observe(region_records(film, region), n);
        if (settings.pass_done) settings.pass_done(film, n);
        if (rs.progress) {
            const double seconds = elapsed();
            rs.progress({fraction(n, seconds), seconds, stats.passes, n, noise()});
        }
    };
    PassSequence sequence(plan, first, pass);
    (void)sequence.run(runner, half, film);
    const std::uint32_t n = sequence.level();
    const bool keep = plan.keep;
    if (image != nullptr) {
        *image =
            keep && n == target && !half.pixels.empty() ? kept.combined(half, film) : resolve(film);
    }
    stats.noise = target_noise.relative_error().value_or(0.0);
    stats.seconds = elapsed();
    stats.cpu_seconds = cpu_now() - cpu_start;
    return stats;
}

}  // namespace librt
