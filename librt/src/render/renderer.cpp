#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/render/renderer.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#endif

namespace librt {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

bool stderr_is_terminal() {
#if defined(__unix__) || defined(__APPLE__)
    return ::isatty(::fileno(stderr)) != 0;
#else
    return false;
#endif
}

std::string format_duration(double seconds) {
    const auto total = static_cast<long long>(std::max(0.0, seconds) + 0.5);
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%lld:%02lld:%02lld", total / 3600, (total / 60) % 60,
                  total % 60);
    return buffer;
}

// A one-line progress bar on stderr, shown only on a terminal once the render has run
// for more than a second, redrawn at most ten times a second.
class ProgressBar {
public:
    ProgressBar(bool wanted, Clock::time_point start)
        : enabled_(wanted && stderr_is_terminal()), start_(start) {}

    void update(std::size_t done, std::size_t total) {
        if (!enabled_) return;
        const double elapsed = seconds_since(start_);
        if (elapsed < 1.0 || elapsed - last_draw_ < 0.1) return;
        draw(done, total, elapsed);
    }

    void finish(std::size_t done, std::size_t total) {
        if (!drawn_) return;
        draw(done, total, seconds_since(start_));
        std::fputc('\n', stderr);
        std::fflush(stderr);
    }

private:
    void draw(std::size_t done, std::size_t total, double elapsed) {
        constexpr int k_width = 30;
        const double fraction =
            total == 0 ? 1.0 : static_cast<double>(done) / static_cast<double>(total);
        const int filled = static_cast<int>(fraction * k_width);
        std::string bar(static_cast<std::size_t>(filled), '#');
        bar.resize(k_width, '.');
        // Remaining time by linear extrapolation: elapsed * (1 - f) / f.
        const std::string remaining =
            fraction > 0.0 ? format_duration(elapsed * (1.0 - fraction) / fraction) : "?";
        std::fprintf(stderr, "\r[%s] %3d%%  elapsed %s  remaining %s ", bar.c_str(),
                     static_cast<int>(fraction * 100.0), format_duration(elapsed).c_str(),
                     remaining.c_str());
        std::fflush(stderr);
        last_draw_ = elapsed;
        drawn_ = true;
    }

    bool enabled_;
    Clock::time_point start_;
    double last_draw_ = 0.0;
    bool drawn_ = false;
};

struct Tile {
    int x0, y0, x1, y1;  // pixel range [x0, x1) x [y0, y1)
};

}  // namespace

void validate(const RenderSettings& s) {
    if (s.samples_per_pixel < 1 || s.samples_per_pixel > (1 << 20)) {
        throw Error("samples_per_pixel = " + std::to_string(s.samples_per_pixel) +
                    ": must be in [1, 1048576]");
    }
    if (s.threads < 0 || s.threads > 1024) {
        throw Error("threads = " + std::to_string(s.threads) + ": must be in [0, 1024]");
    }
    if (s.tile_size < 1) {
        throw Error("tile_size = " + std::to_string(s.tile_size) + ": must be >= 1");
    }
}

Image render(const Scene& scene, const Camera& camera, Integrator& integrator,
             const RenderSettings& settings, RenderStats* stats) {
    const Clock::time_point start = Clock::now();
    validate(settings);
    Image image(camera.width(), camera.height());  // checks the film size before allocating

    integrator.preprocess(scene);

    // Tiles in row-major order; each is written by exactly one thread. A tile larger than
    // the image is the image (and keeps the index arithmetic below far from overflow).
    const int tile = std::min(settings.tile_size, std::max(image.width, image.height));
    const int tiles_x = (image.width + tile - 1) / tile;
    const int tiles_y = (image.height + tile - 1) / tile;
    const auto tile_count = static_cast<std::size_t>(tiles_x) * static_cast<std::size_t>(tiles_y);
    const auto tile_at = [&](std::size_t i) {
        const int tx = static_cast<int>(i % static_cast<std::size_t>(tiles_x));
        const int ty = static_cast<int>(i / static_cast<std::size_t>(tiles_x));
        return Tile{tx * tile, ty * tile, std::min(image.width, (tx + 1) * tile),
                    std::min(image.height, (ty + 1) * tile)};
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
    std::atomic<bool> failed{false};
    std::exception_ptr failure;
    std::mutex mutex;
    std::condition_variable finished_cv;
    unsigned workers_finished = 0;

    const auto stop_requested = [&] {
        if (failed.load(std::memory_order_relaxed)) return true;
        if (settings.cancel != nullptr && settings.cancel->load(std::memory_order_relaxed)) {
            cancelled.store(true, std::memory_order_relaxed);
            return true;
        }
        return false;
    };

    // Cancellation is checked before every pixel and every kCancelCheckSamples samples
    // within one, so even a pixel of 2^20 samples cannot hold up a cancelled render. A
    // pixel left unfinished stays black.
    constexpr int kCancelCheckSamples = 64;
    const auto render_tile = [&](const Tile& t, std::uint64_t& samples, std::uint64_t& nonfinite) {
        for (int y = t.y0; y < t.y1; ++y) {
            for (int x = t.x0; x < t.x1; ++x) {
                glm::dvec3 sum(0.0);
                std::uint32_t kept = 0;  // finite samples
                for (int s = 0; s < settings.samples_per_pixel; ++s) {
                    if (s % kCancelCheckSamples == 0 && stop_requested()) {
                        samples += static_cast<std::uint64_t>(s);
                        nonfinite += static_cast<std::uint64_t>(s) - kept;
                        return false;
                    }
                    Sampler sampler(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y),
                                    static_cast<std::uint32_t>(s), settings.seed);
                    const Ray ray = camera.generate_ray(x, y, sampler);
                    const glm::vec3 l = integrator.li(scene, ray, sampler);
                    if (finite(l)) {
                        sum += glm::dvec3(l);
                        ++kept;
                    }
                }
                samples += static_cast<std::uint64_t>(settings.samples_per_pixel);
                nonfinite += static_cast<std::uint64_t>(settings.samples_per_pixel) - kept;
                // Pixel estimate: the mean of its finite samples.
                image.at(x, y) =
                    kept > 0 ? glm::vec3(sum / static_cast<double>(kept)) : glm::vec3(0.0f);
            }
        }
        return true;
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

    // The calling thread watches: progress bar, and wakes as soon as all workers are done.
    ProgressBar progress(settings.progress, start);
    {
        std::unique_lock<std::mutex> lock(mutex);
        while (workers_finished < threads.size()) {
            finished_cv.wait_for(lock, std::chrono::milliseconds(100));
            lock.unlock();
            progress.update(tiles_done.load(std::memory_order_relaxed), tile_count);
            lock.lock();
        }
    }
    for (std::thread& t : threads) t.join();
    progress.finish(tiles_done.load(), tile_count);

    if (failure) std::rethrow_exception(failure);
    if (stats != nullptr) {
        stats->seconds = seconds_since(start);
        stats->samples = sample_total.load();
        stats->nonfinite_samples = nonfinite_total.load();
        stats->cancelled = cancelled.load() && tiles_done.load() < tile_count;
    }
    return image;
}

}  // namespace librt
