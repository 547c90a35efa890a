#pragma once

#include "report_scene.h"

#include <librt/core/image.h>
#include <librt/film/camera.h>
#include <librt/film/film.h>
#include <librt/integrator/integrator.h>
#include <librt/integrator/integrators.h>
#include <librt/render/render_memory.h>
#include <librt/render/renderer.h>
#include <librt/sampling/sampler.h>
#include <librt/scene/scene.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

// Command-line plumbing shared by the rt_* apps: common options, error handling, and
// "render, check, write".

// CLI11's App, declared only: see CommandLine. The files that register options of their own
// types include <CLI/CLI.hpp> themselves.
namespace CLI {
class App;
}  // namespace CLI

namespace librt::apps {

/// Options every app has.
struct AppOptions {
    int width = 512;          ///< --width
    int height = 512;         ///< --height
    std::optional<int> size;  ///< --size: sets width and height when given
    int spp = 1;              ///< --spp, samples per pixel
    int bounces = 5;          ///< --bounces, scattering events per path
    /// --roulette: Russian roulette from this bounce on; -1 (the default) is off, the
    /// report's fixed-length paths.
    int roulette = -1;
    int threads = 0;                      ///< --threads, 0 = all cores
    std::uint64_t seed = 0;               ///< --seed
    std::string output;                   ///< -o/--output: .png, .pfm or .hdr
    float exposure = 1.0f;                ///< --exposure: multiplies kReportExposure
    float power = kDefaultPower;          ///< --power: total light power
    bool check = false;                   ///< --check: exit 2 if the image is black or has NaN/Inf
    bool quiet = false;                   ///< --quiet: no progress bar, no summary
    std::string sampler = "independent";  ///< --sampler: independent | sobol
    /// --filter: box | tent | gaussian | mitchell | blackman-harris | smallpt; empty = the app's
    /// own sub-pixel jitter (unchanged images).
    std::string filter;
    std::optional<float> filter_radius;  ///< --filter-radius in pixels; default: the filter's
    bool guiding = false;                ///< --guiding: path guiding (PathTracer apps)
    int guiding_passes = 5;              ///< --guiding-passes: training passes (1, 2, 4... spp)
    bool adaptive = false;               ///< --adaptive: spread samples by noise (--spp: mean)
};

/// Options of the apps that show a mesh.
struct MeshOptions {
    std::string path;                               ///< --mesh; empty = procedural teapot
    MeshPlacement placement;                        ///< from --mesh-fit/-scale/-offset/-rotate
    std::vector<float> offset{0.0f, -10.0f, 0.0f};  ///< --mesh-offset x y z
};

/// A one-line progress bar on stderr fed by the renderer's progress callback (fraction done,
/// elapsed and remaining time, and the noise estimate when the render gives one), shown only
/// on a terminal once the render has run for more than a second, redrawn at most ten times
/// a second; finish() (or the destructor) ends its line.
class ProgressBar {
public:
    /// A bar that draws when `wanted` and stderr is a terminal.
    explicit ProgressBar(bool wanted);
    ~ProgressBar();
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;
    /// Records a report and redraws when due.
    void update(const RenderProgress& p);
    /// Draws the last report and ends the line, if anything was drawn.
    void finish();

private:
    void draw(const RenderProgress& p);
    bool enabled_;
    RenderProgress last_;
    double last_draw_ = 0.0;
    bool drawn_ = false;
};

/// An app's command line, with CLI11 behind it: the report's small apps register their
/// options here and compile without CLI11. Why: CLI11 2.1 (Debian 12) is header-only, and a
/// file that builds a CLI::App compiles hundreds of its functions, most of a small app's
/// build time (about 20 s each under the sanitizers, every CI run; docs/robustness.md).
class CommandLine {
public:
    /// An app called `name`, described by `description` in --help.
    CommandLine(const std::string& description, const std::string& name);
    ~CommandLine();
    CommandLine(const CommandLine&) = delete;
    CommandLine& operator=(const CommandLine&) = delete;
    /// The CLI11 app itself, for the functions below that register on it.
    [[nodiscard]] CLI::App& app() { return *app_; }
    /// A flag that sets `value`.
    void add_flag(const std::string& name, bool& value, const std::string& help);
    /// An option parsed into `value`, its default shown by --help.
    void add_option(const std::string& name, float& value, const std::string& help);
    /// The same for an integer.
    void add_option(const std::string& name, int& value, const std::string& help);

private:
    std::unique_ptr<CLI::App> app_;
};

/// Peak resident memory of this process in MiB, for the apps' summaries.
[[nodiscard]] double peak_rss_mib();

/// The flag SIGINT / SIGTERM set while run()'s body runs: a render's `cancel`.
[[nodiscard]] const std::atomic<bool>* interrupt_flag();

/// Registers the common options on `app`, with `options`' current values as defaults.
void add_common_options(CLI::App& app, AppOptions& options);

/// Registers --sampler, --filter and --filter-radius (add_common_options does too), for an
/// app with options of its own.
void add_sampling_options(CLI::App& app, AppOptions& options);

/// Throws librt::Error "--option = value: rule" for a --sampler, --filter or
/// --filter-radius that cannot be used (validate() checks these too).
void validate_sampling(const AppOptions& options);

/// Registers --mesh, --mesh-fit, --mesh-scale, --mesh-offset and --mesh-rotate.
void add_mesh_options(CLI::App& app, MeshOptions& options);

/// Throws librt::Error "--option = value: rule", naming the option as typed, for any common
/// option that cannot be used (size, film, samples, threads, bounces, exposure, power).
/// Each app calls it first, before it loads or allocates anything.
void validate(const AppOptions& options);

/// Most memory the pixels of an app's render may take: the films, their copies, the image
/// and the output writer's buffers together (docs/robustness.md). The film's own limit.
inline constexpr std::uint64_t kMaxRenderBytes = Film::kMaxBytes;

/// Bytes per pixel the writer of `path` (by extension) allocates beside the linear image it
/// is given: a tone-mapped or scaled copy and the encoder's buffers; for EXR with `layers`,
/// the resolved AOV layers, their float planes, tinyexr's compressed blocks and its file
/// image (each at most the planes' size).
[[nodiscard]] std::uint64_t writer_bytes_per_pixel(const std::string& path, bool layers);

/// Throws librt::Error "option = value: the render would need N GiB (B bytes per pixel ...),
/// more than the 16 GiB limit" when width x height pixels of `bytes_per_pixel` exceed
/// kMaxRenderBytes (compared by division: no overflow). Nothing is allocated.
void check_render_memory(const std::string& option, const std::string& value, long long width,
                         long long height, std::uint64_t bytes_per_pixel);

/// The same for the mesh options (--mesh-fit, --mesh-scale, --mesh-offset, --mesh-rotate).
void validate(const MeshOptions& options);

/// The placement from the parsed mesh options.
[[nodiscard]] MeshPlacement placement_of(const MeshOptions& options);

/// The report's camera at the size given on the command line.
[[nodiscard]] CameraSettings camera_of(const AppOptions& options);

/// The sampler named by --sampler (validate() has checked it).
[[nodiscard]] SamplerKind sampler_kind(const AppOptions& options);

/// `camera` with the pixel filter of --filter / --filter-radius when given (filter
/// importance sampling, PixelJitter::Filter); unchanged otherwise.
[[nodiscard]] CameraSettings with_filter(CameraSettings camera, const AppOptions& options);

/// The path tracer's settings from the command line (--bounces).
[[nodiscard]] PathTracerSettings path_tracer_settings(const AppOptions& options);

/// Parses the command line (adding --version, and making every option take its last value
/// when repeated) and runs `body`. A librt::Error (or any other exception) is
/// printed on stderr and gives exit code 1; so does a bad command line (CLI11's message on
/// stderr); --help and --version exit 0.
/// Returns body's exit code otherwise. While body runs, SIGINT and SIGTERM request a
/// clean stop (render_and_write then returns 130 without writing); a second one kills.
[[nodiscard]] int run(CLI::App& app, int argc, char** argv, const std::function<int()>& body);

/// run() on a CommandLine's app.
[[nodiscard]] int run(CommandLine& command_line, int argc, char** argv,
                      const std::function<int()>& body);

/// Renders with the options' sample count, threads and seed (Ctrl-C or SIGTERM cancels:
/// nothing is written, exit 130; see docs/robustness.md), prints a summary, writes options.output
/// tone-mapped with the report's gamma and exposure, and with --check returns 2 when the image is
/// all black or has a non-finite pixel. `after_write`, when set, gets the linear image once it is
/// written (e.g. to write a zoomed crop). `scene` must be committed.
[[nodiscard]] int render_and_write(const Scene& scene, const CameraSettings& camera,
                                   Integrator& integrator, const AppOptions& options,
                                   const std::function<void(const Image&)>& after_write = {});

/// Writes a nearest-neighbour `zoom`x enlargement of the square crop of side `side`
/// pixels centred at (cx, cy) (clamped into the image), tone-mapped like the main image.
void write_zoomed_crop(const std::string& path, const Image& image, int cx, int cy, int side,
                       int zoom, float exposure);

}  // namespace librt::apps
