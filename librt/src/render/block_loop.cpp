// run_block in its steps: the block's tiles (TileGrid), how many threads (worker_count),
// what the threads share (BlockControl), one tile's pixels and samples (TileRenderer), and
// the calling thread watching them (watch_workers).

#include "render/block_loop.h"

#include "film/camera_importance.h"
#include "render/aov.h"

#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/scene/scene.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <string>
#include <system_error>
#include <thread>
#include <type_traits>
#include <vector>

namespace librt {

namespace {

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

struct Tile {
    int x0, y0, x1, y1;  // pixel range [x0, x1) x [y0, y1)
};

/// The tiles of a (non-empty) block in row-major order; each is written by exactly one
/// thread. A tile larger than the block is the block (and keeps the index arithmetic far
/// from overflow).
class TileGrid {
public:
    TileGrid(const RenderBlock& block, int tile_size)
        : block_(block),
          width_(block.x1 - block.x0),
          height_(block.y1 - block.y0),
          tile_(std::min(tile_size, std::max(width_, height_))),
          tiles_x_((width_ + tile_ - 1) / tile_),
          count_(static_cast<std::size_t>(tiles_x_) *
                 static_cast<std::size_t>((height_ + tile_ - 1) / tile_)) {}

    [[nodiscard]] std::size_t count() const { return count_; }

    [[nodiscard]] Tile at(std::size_t i) const {
        const int tx = static_cast<int>(i % static_cast<std::size_t>(tiles_x_));
        const int ty = static_cast<int>(i / static_cast<std::size_t>(tiles_x_));
        return Tile{block_.x0 + tx * tile_, block_.y0 + ty * tile_,
                    block_.x0 + std::min(width_, (tx + 1) * tile_),
                    block_.y0 + std::min(height_, (ty + 1) * tile_)};
    }

private:
    RenderBlock block_;
    int width_, height_, tile_, tiles_x_;
    std::size_t count_;
};

/// Threads for `tiles` tiles: settings.threads (0: the hardware's), at least 1, at most
/// one per tile and 1024.
unsigned worker_count(const BlockSettings& settings, std::size_t tiles) {
    const unsigned wanted = settings.threads > 0 ? static_cast<unsigned>(settings.threads)
                                                 : std::thread::hardware_concurrency();
    return std::clamp<unsigned>(wanted, 1u,
                                static_cast<unsigned>(std::min<std::size_t>(tiles, 1024)));
}

/// What the threads of one block share: the next tile, the counts, why they stop, the
/// first failure, and the calling thread's wake-up when all are done.
struct BlockControl {
    explicit BlockControl(const std::atomic<bool>* cancel_flag) : cancel(cancel_flag) {}

    /// Whether a thread should stop: a failure, `tick`'s abort, or settings.cancel.
    bool stop_requested() {
        if (failed.load(std::memory_order_relaxed) || aborted.load(std::memory_order_relaxed))
            return true;
        if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) {
            cancelled.store(true, std::memory_order_relaxed);
            return true;
        }
        return false;
    }

    /// Keeps the first exception (rethrown once every thread stopped) and stops the others.
    void fail(std::exception_ptr e) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!failure) failure = std::move(e);
        failed.store(true, std::memory_order_relaxed);
    }

    const std::atomic<bool>* cancel;
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
    unsigned workers_finished = 0;  // under `mutex`
};

/// One tile's pixels, each continued in sample order from its film record.
struct TileRenderer {
    const Scene& scene;
    const Camera& camera;
    const Integrator& integrator;
    Film& film;
    FilmOrigin origin;
    const BlockSettings& settings;
    SplatTarget target;
    std::uint32_t first;        // the block's first sample
    std::uint32_t end;          // one past its last
    const std::uint32_t* ends;  // each pixel's own end instead, or null
    BlockControl& control;

    /// Renders tile `t`, adding to `samples` and `nonfinite`; false when stopped part-way.
    bool render(const Tile& t, std::uint64_t& samples, std::uint64_t& nonfinite) const {
        const bool with_aovs = film.has_aovs();
        if (target.film != nullptr) {
            return with_aovs ? render_with<true, true>(t, samples, nonfinite)
                             : render_with<false, true>(t, samples, nonfinite);
        }
        return with_aovs ? render_with<true, false>(t, samples, nonfinite)
                         : render_with<false, false>(t, samples, nonfinite);
    }

private:
    // Cancellation is checked before every pixel and every kCancelCheckSamples samples
    // within one, so even a pixel of 2^20 samples cannot hold up a cancelled render. A
    // pixel stopped part-way keeps the samples it took: its record stays consistent.
    static constexpr std::uint32_t kCancelCheckSamples = 64;

    // The AOV sums and splatting as compile-time choices: the plain render's per-sample
    // loop then carries neither the branches nor the AOV code, and calls li() as it always
    // did (the loop runs once per camera sample, ~21 M times in the report's synthesis).
    template <bool kAovs, bool kSplats>
    bool render_with(const Tile& t, std::uint64_t& samples, std::uint64_t& nonfinite) const {
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
                const std::uint32_t from = ends != nullptr ? pixel.samples : first;
                const std::uint32_t last = ends != nullptr ? ends[index] : end;
                bool stopped = false;
                std::uint32_t taken = 0;
                std::uint32_t until_check = 0;  // samples left before the next cancel check
                for (std::uint32_t s = from; s < last; ++s) {
                    if (until_check-- == 0) {
                        if (control.stop_requested()) {
                            stopped = true;
                            break;
                        }
                        until_check = kCancelCheckSamples - 1;
                    }
                    Sampler sampler(sampler_kind, px, py, s, seed);
                    const CameraRay camera_ray = camera.sample_ray(x, y, sampler);
                    const Ray& ray = camera_ray.ray;
                    if constexpr (kAovs) {
                        const AovSample a =
                            sample_aovs(scene, ray, camera.forward(), px, py, s, seed);
                        // The albedo is filtered like the beauty: with the weight's sign
                        // (its size is one per filter; resolve_layers divides it out).
                        if (camera_ray.weight < 0.0f) {
                            aov.albedo -= glm::dvec3(a.albedo);
                            ++aov.negative;
                        } else {
                            aov.albedo += glm::dvec3(a.albedo);
                        }
                        aov.normal += glm::dvec3(a.normal);
                        aov.emission += glm::dvec3(a.emission * camera_ray.weight);
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
    }
};

/// A thread's work: tiles from the shared counter until none is left or it must stop.
void work_on_tiles(const TileGrid& grid, const TileRenderer& renderer, BlockControl& control) {
    std::uint64_t samples = 0;
    std::uint64_t nonfinite = 0;
    try {
        for (;;) {
            if (control.stop_requested()) break;
            const std::size_t i = control.next_tile.fetch_add(1, std::memory_order_relaxed);
            if (i >= grid.count()) break;
            if (!renderer.render(grid.at(i), samples, nonfinite)) break;
            control.tiles_done.fetch_add(1, std::memory_order_relaxed);
        }
    } catch (...) {
        control.fail(std::current_exception());
    }
    control.sample_total.fetch_add(samples, std::memory_order_relaxed);
    control.nonfinite_total.fetch_add(nonfinite, std::memory_order_relaxed);
    const std::lock_guard<std::mutex> lock(control.mutex);
    ++control.workers_finished;
    control.finished_cv.notify_one();
}

/// The calling thread watches: ticks about ten times a second, and wakes as soon as all
/// `workers` are done. A throwing tick (progress callback) stops the block, and is rethrown.
void watch_workers(BlockControl& control, std::size_t workers, std::size_t tiles,
                   const Tick& tick) {
    std::unique_lock<std::mutex> lock(control.mutex);
    while (control.workers_finished < workers) {
        control.finished_cv.wait_for(lock, std::chrono::milliseconds(100));
        if (control.workers_finished == workers || !tick) continue;
        lock.unlock();
        const double fraction =
            static_cast<double>(control.tiles_done.load(std::memory_order_relaxed)) /
            static_cast<double>(tiles);
        try {
            if (tick(fraction)) control.aborted.store(true, std::memory_order_relaxed);
        } catch (...) {
            control.fail(std::current_exception());
        }
        lock.lock();
    }
}

}  // namespace

BlockOutcome run_block(const Scene& scene, const Camera& camera, const Integrator& integrator,
                       Film& film, FilmOrigin origin, const RenderBlock& block,
                       const BlockSettings& settings, const Tick& tick, const std::uint32_t* ends) {
    BlockOutcome outcome;
    const SplatTarget target = splat_target(camera, integrator, film);
    if (block.x1 <= block.x0 || block.y1 <= block.y0 || block.count == 0) {
        outcome.complete = true;
        return outcome;
    }
    const TileGrid grid(block, settings.tile_size);
    const unsigned thread_count = worker_count(settings, grid.count());
    BlockControl control(settings.cancel);
    const TileRenderer renderer{scene,  camera,      integrator,
                                film,   origin,      settings,
                                target, block.first, block.first + block.count,
                                ends,   control};

    std::vector<std::thread> threads;
    threads.reserve(thread_count);
    try {
        for (unsigned i = 0; i < thread_count; ++i)
            threads.emplace_back(work_on_tiles, std::cref(grid), std::cref(renderer),
                                 std::ref(control));
    } catch (const std::system_error& e) {
        control.failed.store(true);
        for (std::thread& t : threads) t.join();
        throw Error(std::string("cannot start render threads: ") + e.what());
    }
    watch_workers(control, threads.size(), grid.count(), tick);
    for (std::thread& t : threads) t.join();

    if (control.failure) std::rethrow_exception(control.failure);
    outcome.samples = control.sample_total.load();
    outcome.nonfinite = control.nonfinite_total.load();
    outcome.complete = control.tiles_done.load() == grid.count();
    outcome.cancelled = !outcome.complete && control.cancelled.load();
    outcome.aborted = !outcome.complete && !outcome.cancelled && control.aborted.load();
    return outcome;
}

}  // namespace librt
