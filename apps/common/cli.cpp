// What every app shares: the common, sampling and mesh options with their checks, the
// progress bar, Ctrl-C handling and run() (errors to exit codes). Over 400 lines: one place
// keeps the apps' command lines and messages alike; each option is a few lines of
// registration plus its range check.

#include "cli.h"

#include "output_image.h"

#include <librt/accel/simd.h>
#include <librt/core/error.h>
#include <librt/core/tone_map.h>
#include <librt/integrator/integrators.h>
#include <librt/io/file_extension.h>
#include <librt/io/image_io.h>
#include <librt/render/renderer.h>
#include <librt/version.h>

#include <CLI/CLI.hpp>
#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <thread>
#include <utility>

#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#endif

namespace librt::apps {

namespace {

// Set by SIGINT / SIGTERM; lock-free, so the handler may store to it.
std::atomic<bool> g_cancel{false};
static_assert(std::atomic<bool>::is_always_lock_free);

// The first signal asks for a clean stop; a second one (the user insisting, e.g. while a
// huge mesh loads, which is not cancellable) gets the default action: immediate death.
extern "C" void on_interrupt(int signal) {
    if (g_cancel.exchange(true)) {
        std::signal(signal, SIG_DFL);
        std::raise(signal);
    }
}

/// Routes SIGINT and SIGTERM to on_interrupt while alive, restoring the previous
/// handlers on every exit path (return or exception).
class InterruptGuard {
public:
    InterruptGuard()
        : previous_int_(std::signal(SIGINT, on_interrupt)),
          previous_term_(std::signal(SIGTERM, on_interrupt)) {}
    ~InterruptGuard() {
        std::signal(SIGINT, previous_int_);
        std::signal(SIGTERM, previous_term_);
    }
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

private:
    void (*previous_int_)(int);
    void (*previous_term_)(int);
};

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

}  // namespace

ProgressBar::ProgressBar(bool wanted) : enabled_(wanted && stderr_is_terminal()) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(const RenderProgress& p) {
    if (!enabled_) return;
    last_ = p;
    if (p.seconds < 1.0 || p.seconds - last_draw_ < 0.1) return;
    draw(p);
}

void ProgressBar::finish() {
    if (!drawn_) return;
    draw(last_);
    std::fputc('\n', stderr);
    std::fflush(stderr);
    drawn_ = false;
}

void ProgressBar::draw(const RenderProgress& p) {
    constexpr int kWidth = 30;
    const double fraction = std::clamp(p.fraction, 0.0, 1.0);
    const int filled = static_cast<int>(fraction * kWidth);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, '.');
    // Remaining time by linear extrapolation: elapsed * (1 - f) / f.
    const std::string remaining =
        fraction > 0.0 ? format_duration(p.seconds * (1.0 - fraction) / fraction) : "?";
    // The noise estimate (RenderProgress::noise) once two passes have given one.
    char noise[32] = "";
    if (p.noise >= 0.0) std::snprintf(noise, sizeof noise, "  noise %.2g %%", 100.0 * p.noise);
    std::fprintf(stderr, "\r[%s] %3d%%  elapsed %s  remaining %s%s ", bar.c_str(),
                 static_cast<int>(fraction * 100.0), format_duration(p.seconds).c_str(),
                 remaining.c_str(), noise);
    std::fflush(stderr);
    last_draw_ = p.seconds;
    drawn_ = true;
}

const std::atomic<bool>* interrupt_flag() { return &g_cancel; }

void add_common_options(CLI::App& app, AppOptions& o) {
    app.add_option("--width", o.width, "Image width in pixels")->capture_default_str();
    app.add_option("--height", o.height, "Image height in pixels")->capture_default_str();
    app.add_option("--size", o.size, "Sets both width and height");
    app.add_option("--spp", o.spp, "Samples per pixel")->capture_default_str();
    app.add_option("--bounces", o.bounces,
                   "Scattering events per path (mirror/glass bounces for direct lighting)")
        ->capture_default_str();
    app.add_option("--roulette", o.roulette,
                   "Russian roulette from this bounce on, path-traced apps (-1 = off: the report's "
                   "fixed-length paths; the image's mean is the same)")
        ->capture_default_str();
    app.add_option("--threads", o.threads, "Worker threads, 0 = all cores")->capture_default_str();
    app.add_option("--seed", o.seed, "Random seed (the image is the same for any thread count)")
        ->capture_default_str();
    app.add_option("-o,--output", o.output,
                   "Output image: .png (tone-mapped), .pfm or .hdr (linear)")
        ->capture_default_str();
    app.add_option("--exposure", o.exposure,
                   "Multiplies the report's exposure 255^(-1/0.45) before gamma 0.45")
        ->capture_default_str();
    app.add_option("--power", o.power,
                   "Total light power (the report's 2.14e8 times its 80 summed samples)")
        ->capture_default_str();
    app.add_flag("--check", o.check,
                 "Exit with code 2 if the image is all black or has NaN/Inf pixels");
    app.add_flag("-q,--quiet", o.quiet, "No progress bar and no summary");
    add_sampling_options(app, o);
}

void add_sampling_options(CLI::App& app, AppOptions& o) {
    app.add_option("--sampler", o.sampler,
                   "Random numbers: independent (PCG32 streams) or sobol (Owen-scrambled Sobol')")
        ->capture_default_str();
    app.add_option("--filter", o.filter,
                   "Pixel filter by importance sampling: box, tent, gaussian, mitchell, "
                   "blackman-harris or smallpt (default: the app's own sub-pixel jitter)");
    app.add_flag("--guiding", o.guiding,
                 "Path guiding: learn the incident light in training passes, then sample "
                 "directions from it (path-traced apps)");
    app.add_option("--guiding-passes", o.guiding_passes,
                   "Training passes of --guiding; pass k renders 2^k spp (5: 31 spp)")
        ->capture_default_str();
    // The app's default (rt_render's is on, the report apps' off) as the help shows it.
    app.add_flag("--adaptive,!--no-adaptive", o.adaptive,
                 std::string("Adaptive sampling: a pilot of --spp / 4 samples per pixel, then "
                             "the rest where the noise is (--spp becomes the mean; pixels' "
                             "means stay unbiased); default ") +
                     (o.adaptive ? "on" : "off"));
    app.add_option("--filter-radius", o.filter_radius,
                   "The filter's radius in pixels (default: box 0.5, tent 1, gaussian 1.5, "
                   "mitchell 2, blackman-harris 1.5, smallpt 0.75)");
}

namespace {

/// The filter kind named by --filter; false when the name is unknown.
bool filter_kind_of(const std::string& name, FilterKind& kind) {
    static constexpr std::pair<const char*, FilterKind> kNames[] = {
        {"box", FilterKind::Box},
        {"tent", FilterKind::Tent},
        {"gaussian", FilterKind::Gaussian},
        {"mitchell", FilterKind::Mitchell},
        {"blackman-harris", FilterKind::BlackmanHarris},
        {"smallpt", FilterKind::Smallpt}};
    for (const auto& [n, k] : kNames) {
        if (name == n) {
            kind = k;
            return true;
        }
    }
    return false;
}

}  // namespace

SamplerKind sampler_kind(const AppOptions& o) {
    return o.sampler == "sobol" ? SamplerKind::Sobol : SamplerKind::Independent;
}

CameraSettings with_filter(CameraSettings camera, const AppOptions& o) {
    FilterKind kind{};
    if (o.filter.empty() || !filter_kind_of(o.filter, kind)) return camera;
    camera.pixel_jitter = PixelJitter::Filter;
    camera.pixel_filter = default_filter_settings(kind);
    if (o.filter_radius) camera.pixel_filter.radius = *o.filter_radius;
    return camera;
}

void add_mesh_options(CLI::App& app, MeshOptions& o) {
    app.add_option("--mesh", o.path,
                   "OBJ file (with its MTL); default: a procedural Utah teapot of ~5.5k triangles");
    app.add_option("--mesh-fit", o.placement.fit,
                   "Fit the mesh first: bottom centre to the origin, largest side to this many "
                   "units (0 = as in the file)")
        ->capture_default_str();
    app.add_option("--mesh-scale", o.placement.scale, "The report's scale, applied after fitting")
        ->capture_default_str();
    app.add_option("--mesh-offset", o.offset, "The report's offset x y z, applied after scaling")
        ->expected(3)
        ->capture_default_str();
    app.add_option("--mesh-rotate", o.placement.rotate_y_degrees,
                   "Turn about +y in degrees, before scaling")
        ->capture_default_str();
}

MeshPlacement placement_of(const MeshOptions& o) {
    MeshPlacement p = o.placement;
    if (o.offset.size() == 3) p.offset = {o.offset[0], o.offset[1], o.offset[2]};
    return p;
}

PathTracerSettings path_tracer_settings(const AppOptions& options) {
    PathTracerSettings settings;
    // The report's paths, explicitly: the library's defaults (long paths, roulette) differ.
    settings.max_depth = options.bounces;
    settings.russian_roulette = options.roulette >= 0;
    if (options.roulette >= 0) settings.russian_roulette_depth = options.roulette;
    settings.light_choice = LightChoice::Power;  // the report's, whatever the light count
    settings.guiding.enabled = options.guiding;
    settings.guiding.training_passes = options.guiding_passes;
    // Every render entry point can keep the training passes in the image (renderer.h).
    settings.guiding.keep_training_samples = options.guiding;
    return settings;
}

CameraSettings camera_of(const AppOptions& o) {
    return o.size ? report_camera(*o.size, *o.size) : report_camera(o.width, o.height);
}

namespace {

/// A value as the user would have typed it: shortest round-trip form.
std::string typed(float x) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
    return std::string(buffer, result.ptr);
}

[[noreturn]] void bad_option(const char* option, const std::string& value, const char* rule) {
    std::string message(option);
    message += " = ";
    message += value;
    message += ": ";
    message += rule;
    throw Error(message);
}

}  // namespace

void validate_sampling(const AppOptions& o) {
    if (o.sampler != "independent" && o.sampler != "sobol") {
        bad_option("--sampler", o.sampler, "must be independent or sobol");
    }
    FilterKind kind{};
    if (!o.filter.empty() && !filter_kind_of(o.filter, kind)) {
        bad_option("--filter", o.filter,
                   "must be box, tent, gaussian, mitchell, blackman-harris or smallpt");
    }
    if (o.filter_radius) {
        if (o.filter.empty())
            bad_option("--filter-radius", typed(*o.filter_radius), "needs --filter");
        if (!std::isfinite(*o.filter_radius) || !(*o.filter_radius > 0.0f)) {
            bad_option("--filter-radius", typed(*o.filter_radius), "must be finite and > 0");
        }
    }
}

std::uint64_t writer_bytes_per_pixel(const std::string& path, bool layers) {
    const std::string ext = lower_extension(path);
    constexpr std::uint64_t kLinear = sizeof(glm::vec3);  // an Image's pixel
    constexpr std::uint64_t kRgb8 = 3;
    if (ext == ".exr") {
        // ImageLayers: beauty, albedo, normal, depth, sample count; then as many bytes in
        // float planes, in tinyexr's compressed blocks and in its file image.
        const std::uint64_t planes = layers ? 3 * kLinear + 2 * sizeof(float) : kLinear + kLinear;
        return 4 * planes;
    }
    if (ext == ".png") {
        // The display copy, and the larger of: its 8-bit RGB, stb's filtered rows, its
        // deflate output and the encoded bytes; or (libpng: 16 bits, alpha) the coverage,
        // 16-bit RGBA and the encoded bytes.
        constexpr std::uint64_t kRgba16 = 8;
        return kLinear + std::max(4 * kRgb8, sizeof(float) + 2 * kRgba16);
    }
    return 2 * kLinear;  // .pfm, .hdr: the scaled copy and the encoded file (at most as large)
}

void check_render_memory(const std::string& option, const std::string& value, long long width,
                         long long height, std::uint64_t bytes_per_pixel) {
    const auto w = static_cast<unsigned long long>(std::max(width, 0LL));
    const auto h = static_cast<unsigned long long>(std::max(height, 0LL));
    const std::uint64_t max_pixels = kMaxRenderBytes / std::max<std::uint64_t>(bytes_per_pixel, 1);
    if (w == 0 || h <= max_pixels / w) return;  // by division: no product can wrap around
    std::uint64_t pixels = 0;
    std::uint64_t bytes = 0;
    const bool exact = !__builtin_mul_overflow(w, h, &pixels) &&
                       !__builtin_mul_overflow(pixels, bytes_per_pixel, &bytes);
    const double gib = double(w) * double(h) * double(bytes_per_pixel) / double(1ull << 30u);
    char text[300];
    std::snprintf(text, sizeof text,
                  "the render would need %s bytes (%.4g GiB: %llu x %llu pixels of %llu bytes, "
                  "for the films, their copies and the output), more than the %llu GiB limit",
                  exact ? std::to_string(bytes).c_str() : "over 2^64", gib, w, h,
                  static_cast<unsigned long long>(bytes_per_pixel),
                  static_cast<unsigned long long>(kMaxRenderBytes >> 30u));
    bad_option(option.c_str(), value, text);
}

void validate(const AppOptions& o) {
    constexpr int kMaxSide = 65536;  // the camera's limit
    const auto side = [&](const char* option, int v) {
        if (v < 1 || v > kMaxSide) bad_option(option, std::to_string(v), "must be in [1, 65536]");
    };
    if (o.size) {
        side("--size", *o.size);
    } else {
        side("--width", o.width);
        side("--height", o.height);
    }
    const CameraSettings camera = camera_of(o);
    // The film (and rt_mesh's BVH timing, a ray per pixel) must fit before anything is
    // allocated: 65536 x 65536 would need 48 GiB.
    check_image_size(camera.width, camera.height);
    // And everything render_and_write holds: render()'s films and image, then the image
    // and the writer's buffers.
    RenderMemoryOptions memory;
    memory.adaptive = o.adaptive;
    memory.keeps_training = o.guiding;
    const std::uint64_t per_pixel =
        std::max(render_bytes_per_pixel(memory),
                 sizeof(glm::vec3) + writer_bytes_per_pixel(o.output, false));
    if (o.size) {
        check_render_memory("--size", std::to_string(*o.size), camera.width, camera.height,
                            per_pixel);
    } else {
        check_render_memory("--width",
                            std::to_string(o.width) + ", --height = " + std::to_string(o.height),
                            camera.width, camera.height, per_pixel);
    }
    RenderSettings settings;
    settings.samples_per_pixel = o.spp;
    settings.threads = o.threads;
    librt::validate(settings);
    validate_sampling(o);
    if (o.guiding_passes < 1 || o.guiding_passes > 20)
        bad_option("--guiding-passes", std::to_string(o.guiding_passes), "must be in [1, 20]");
    if (o.bounces < 0 || o.bounces > 1000) {
        bad_option("--bounces", std::to_string(o.bounces), "must be in [0, 1000]");
    }
    if (o.roulette < -1 || o.roulette > 1000) {
        bad_option("--roulette", std::to_string(o.roulette), "must be -1 (off) or in [0, 1000]");
    }
    if (!std::isfinite(o.exposure) || !(o.exposure > 0.0f) ||
        !std::isfinite(o.exposure * kReportExposure) || !(o.exposure * kReportExposure > 0.0f)) {
        bad_option("--exposure", typed(o.exposure),
                   "must be finite and > 0 (and times the report's exposure still so)");
    }
    // The light's radiance, power / (4 pi^2 r^2), must be finite too.
    if (!std::isfinite(o.power) || o.power < 0.0f ||
        !std::isfinite(SphereLight::radiance_for_power(o.power, kLightRadius).x)) {
        bad_option("--power", typed(o.power),
                   "must be finite and >= 0, with the light's radiance still finite");
    }
    // The output last: its format and that its directory takes a file (a temporary is
    // created and removed), so an unwritable -o fails now, not after the render. Apps that
    // pick a default name later check it then.
    if (!o.output.empty()) check_image_path(o.output);
}

void validate(const MeshOptions& o) {
    const MeshPlacement& p = o.placement;
    if (!std::isfinite(p.fit) || p.fit < 0.0f) {
        bad_option("--mesh-fit", typed(p.fit), "must be finite and >= 0 (0 = no fitting)");
    }
    if (!std::isfinite(p.scale) || !(p.scale > 0.0f)) {
        bad_option("--mesh-scale", typed(p.scale), "must be finite and > 0");
    }
    if (!std::isfinite(p.rotate_y_degrees)) {
        bad_option("--mesh-rotate", typed(p.rotate_y_degrees), "must be finite");
    }
    if (o.offset.size() == 3) {
        for (const float v : o.offset) {
            if (!std::isfinite(v)) {
                bad_option("--mesh-offset",
                           typed(o.offset[0]) + " " + typed(o.offset[1]) + " " + typed(o.offset[2]),
                           "must be finite");
            }
        }
    }
}

CommandLine::CommandLine(const std::string& description, const std::string& name)
    : app_(std::make_unique<CLI::App>(description, name)) {}

CommandLine::~CommandLine() = default;

void CommandLine::add_flag(const std::string& name, bool& value, const std::string& help) {
    app_->add_flag(name, value, help);
}

void CommandLine::add_option(const std::string& name, float& value, const std::string& help) {
    app_->add_option(name, value, help)->capture_default_str();
}

void CommandLine::add_option(const std::string& name, int& value, const std::string& help) {
    app_->add_option(name, value, help)->capture_default_str();
}

int run(CommandLine& command_line, int argc, char** argv, const std::function<int()>& body) {
    return run(command_line.app(), argc, argv, body);
}

int run(CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
    app.set_version_flag("--version",
                         std::string(app.get_name()) + " (librt " LIBRT_VERSION_STRING ")");
    // A repeated option takes its last value (`scripts/render.sh -o mine.png` appends to
    // the script's own -o), as most command-line tools do, instead of failing.
    for (CLI::Option* option : app.get_options()) {
        option->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // app.exit prints CLI11's message (or the help / version text) and returns CLI11's
        // own code (e.g. 109 for an unknown option); the apps' convention is 1 for any
        // bad command line (docs/robustness.md) and 0 for --help and --version.
        return app.exit(e) == 0 ? 0 : 1;
    }
    // The library chose its SIMD path without printing; a refused LIBRT_SIMD is said here.
    if (const std::string& note = librt::simd_path_note(); !note.empty())
        std::cerr << app.get_name() << ": " << note << '\n';
    // From here on Ctrl-C / SIGTERM only set g_cancel: a render in progress (or the next
    // one) stops at once, render_and_write writes nothing and returns 130.
    const InterruptGuard interrupts;
    try {
        return body();
    } catch (const librt::Error& e) {
        std::cerr << app.get_name() << ": " << e.what() << '\n';
    } catch (const std::exception& e) {
        std::cerr << app.get_name() << ": internal error: " << e.what() << '\n';
    }
    return 1;
}

int render_and_write(const Scene& scene, const CameraSettings& camera_settings,
                     Integrator& integrator, const AppOptions& o,
                     const std::function<void(const Image&)>& after_write) {
    const Camera camera(with_filter(camera_settings, o));
    const ToneMap tone_map{o.exposure * kReportExposure, 0.45f};
    validate(tone_map);  // fail before a long render, not after

    RenderSettings settings;
    settings.samples_per_pixel = o.spp;
    settings.threads = o.threads;
    settings.seed = o.seed;
    settings.sampler = sampler_kind(o);
    settings.adaptive.enabled = o.adaptive;
    ProgressBar progress(!o.quiet);
    settings.progress = [&progress](const RenderProgress& p) { progress.update(p); };
    settings.cancel = &g_cancel;
    // Ctrl-C (or SIGTERM) before the write starts: exit 130, nothing written. During the
    // (short) write it takes effect once the file is complete: image files only ever
    // appear whole, through a temporary renamed into place, so there is never a partial
    // file or a stray temporary either way.
    RenderStats stats;
    const Image image = render(scene, camera, integrator, settings, &stats);
    progress.finish();
    if (stats.cancelled || g_cancel.load()) {
        std::cerr << "interrupted: nothing written\n";
        return 130;
    }

    std::uint64_t guarded = 0;
    if (const auto* g = dynamic_cast<const GuardedIntegrator*>(&integrator))
        guarded = g->nonfinite_count();
    if (!o.quiet) {
        const double rate =
            stats.seconds > 0.0 ? static_cast<double>(stats.samples) / stats.seconds : 0.0;
        std::printf("%dx%d, %d spp, %u threads: %.2f s, %.2f CPU s (%.2f M samples/s)\n",
                    image.width, image.height, o.spp,
                    o.threads > 0 ? static_cast<unsigned>(o.threads)
                                  : std::max(1u, std::thread::hardware_concurrency()),
                    stats.seconds, stats.cpu_seconds, rate * 1e-6);
    }
    if (stats.nonfinite_samples + guarded > 0) {
        std::fprintf(stderr, "warning: %llu non-finite samples dropped\n",
                     static_cast<unsigned long long>(stats.nonfinite_samples + guarded));
    }

    write_output(o.output, image, report_look(o.exposure));
    if (!o.quiet) std::printf("wrote %s\n", o.output.c_str());
    if (g_cancel.load()) {
        std::cerr << "interrupted after " << o.output << " was written\n";
        return 130;
    }
    if (after_write) after_write(image);

    if (o.check) {
        const bool finite =
            std::all_of(image.pixels.begin(), image.pixels.end(), [](const glm::vec3& p) {
                return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
            });
        const std::vector<std::uint8_t> rgb = to_rgb8(image, tone_map);
        const bool black =
            std::all_of(rgb.begin(), rgb.end(), [](std::uint8_t v) { return v == 0; });
        if (!finite || black) {
            std::fprintf(stderr, "check failed: the image %s\n",
                         !finite ? "has non-finite pixels" : "is all black");
            return 2;
        }
    }
    return 0;
}

double peak_rss_mib() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;  // Linux reports ru_maxrss in KiB
}

void write_zoomed_crop(const std::string& path, const Image& image, int cx, int cy, int side,
                       int zoom, float exposure) {
    side = std::clamp(side, 1, std::min(image.width, image.height));
    zoom = std::clamp(zoom, 1, 64);
    const int x0 = std::clamp(cx - side / 2, 0, image.width - side);
    const int y0 = std::clamp(cy - side / 2, 0, image.height - side);
    Image crop(side * zoom, side * zoom);
    for (int y = 0; y < crop.height; ++y) {
        for (int x = 0; x < crop.width; ++x) crop.at(x, y) = image.at(x0 + x / zoom, y0 + y / zoom);
    }
    write_output(path, crop, report_look(exposure));
}

}  // namespace librt::apps
