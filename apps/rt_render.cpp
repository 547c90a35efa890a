// rt_render: renders a scene file the user brings, glTF 2.0 (.gltf, .glb) or OBJ (with its
// MTL), through io/scene_file.h, progressively (render_progressive): Ctrl-C or the time
// limit ends the render and the finished passes are written, flagged as partial. PNG is
// sRGB-encoded after clamping (exposure 2^EV first); .hdr, .pfm and .exr stay linear
// (times 2^EV), .exr with AOV layers (albedo, normal, depth, sample count).
#include "common/cli.h"

#include <librt/core/error.h>
#include <librt/core/image.h>
#include <librt/io/exr.h>
#include <librt/io/hdr_image.h>
#include <librt/io/image_io.h>
#include <librt/io/scene_file.h>
#include <librt/render/environment_light.h>
#include <librt/render/film.h>
#include <librt/render/integrators.h>
#include <librt/render/renderer.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <thread>

using namespace librt;

namespace {

struct Options {
    std::string scene;
    std::string output = "render.png";
    int spp = 16;
    std::string size;  // "WxH"; empty = the camera's aspect, long side 640
    std::string camera;
    int max_depth = 5;
    int threads = 0;
    std::uint64_t seed = 0;
    double time_limit = 0.0;
    float exposure_ev = 0.0f;
    std::string env;            // equirectangular .hdr lighting the scene; empty = none
    float env_strength = 1.0f;  // scale of the environment's radiance
    bool quiet = false;
    bool guiding = false;    // path guiding
    int guiding_passes = 5;  // its training passes
};

[[noreturn]] void bad(const std::string& option, const std::string& value, const char* rule) {
    throw Error(option + " = " + value + ": " + rule);
}

/// "WxH" -> width, height, each in [1, 65536].
void parse_size(const std::string& text, int& width, int& height) {
    const auto x = text.find_first_of("xX");
    int w = 0, h = 0;
    char tail = 0;
    if (x == std::string::npos || std::sscanf(text.c_str(), "%d%*[xX]%d%c", &w, &h, &tail) != 2) {
        bad("--size", text, "must be WIDTHxHEIGHT, e.g. 1280x720");
    }
    if (w < 1 || h < 1 || w > 65536 || h > 65536) {
        bad("--size", text, "each side must be in [1, 65536]");
    }
    width = w;
    height = h;
}

/// IEC 61966-2-1 sRGB encoding of a linear value in [0, 1]: 12.92 c below 0.0031308, else
/// 1.055 c^(1/2.4) - 0.055.
float srgb_encode(float c) {
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

/// The display image: exposure, clamp to [0, 1] (NaN -> 0), sRGB-encoded.
Image display_image(const Image& linear, float scale) {
    Image out = linear;
    for (glm::vec3& p : out.pixels) {
        for (int c = 0; c < 3; ++c) {
            const float v = scale * p[c];
            p[c] = srgb_encode(v > 0.0f ? std::min(v, 1.0f) : 0.0f);
        }
    }
    return out;
}

std::string lower_extension(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Peak resident memory of this process in MiB (Linux reports ru_maxrss in KiB).
double peak_rss_mib() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;
}

/// Writes the film: PNG display-encoded, EXR with its layers, HDR / PFM linear.
void write_output(const std::string& path, const Film& film, float scale) {
    const std::string ext = lower_extension(path);
    if (ext == ".exr") {
        ImageLayers layers = resolve_layers(film);
        for (glm::vec3& p : layers.beauty.pixels) p *= scale;
        write_exr(path, layers);
    } else if (ext == ".png") {
        write_png(path, display_image(resolve(film), scale), ToneMap{1.0f, 1.0f});
    } else {
        write_image(path, resolve(film), ToneMap{scale, 1.0f});
    }
}

int render_file(const Options& o) {
    // Everything the user typed is checked before the scene is loaded.
    check_image_path(o.output);
    SceneFileOptions file_options;
    file_options.camera = o.camera;
    if (!o.size.empty()) parse_size(o.size, file_options.width, file_options.height);
    RenderSettings check;
    check.samples_per_pixel = o.spp;
    check.threads = o.threads;
    validate(check);
    if (o.max_depth < 0 || o.max_depth > 1000)
        bad("--max-depth", std::to_string(o.max_depth), "must be in [0, 1000]");
    if (o.guiding_passes < 1 || o.guiding_passes > 20)
        bad("--guiding-passes", std::to_string(o.guiding_passes), "must be in [1, 20]");
    if (!std::isfinite(o.time_limit) || o.time_limit < 0.0)
        bad("--time-limit", std::to_string(o.time_limit), "must be finite and >= 0 (0 = none)");
    if (!std::isfinite(o.exposure_ev) || std::abs(o.exposure_ev) > 64.0f)
        bad("--exposure", std::to_string(o.exposure_ev), "must be in [-64, 64] (EV stops)");
    const float scale = std::exp2(o.exposure_ev);
    if (!std::isfinite(o.env_strength) || o.env_strength < 0.0f)
        bad("--env-strength", std::to_string(o.env_strength), "must be finite and >= 0");
    if (o.env.empty() && o.env_strength != 1.0f)
        bad("--env-strength", std::to_string(o.env_strength), "needs --env");
    // The sky is read before the scene, so a bad file fails before the long load.
    std::optional<EnvironmentLight> environment;
    if (!o.env.empty())
        environment =
            EnvironmentLight::from_image(load_hdr_image(o.env), glm::mat3(1.0f), o.env_strength);

    const auto t0 = std::chrono::steady_clock::now();
    LoadedScene loaded = load_scene_file(o.scene, file_options);
    const double load_seconds = seconds_since(t0);
    for (const std::string& w : loaded.warnings) std::cerr << "warning: " << w << '\n';
    if (environment) loaded.scene.add_environment_light(*environment);
    const auto t1 = std::chrono::steady_clock::now();
    loaded.scene.commit();
    const double build_seconds = seconds_since(t1);
    CameraSettings camera_settings = loaded.camera;
    camera_settings.pixel_jitter = PixelJitter::Gaussian;  // anti-aliasing
    const Camera camera(camera_settings);
    if (!o.quiet) {
        std::printf(
            "%s: %zu triangles stored, %zu placed, %zu instances, %zu lights, BVH %.1f MiB; "
            "load %.2f s, build %.2f s; camera '%s' %dx%d\n",
            o.scene.c_str(), loaded.triangles_stored, loaded.triangles_placed,
            loaded.scene.instance_count(), loaded.scene.lights().size(),
            double(loaded.scene.top_level().memory_bytes()) / (1024.0 * 1024.0), load_seconds,
            build_seconds, loaded.camera_name.c_str(), camera.width(), camera.height());
        std::fflush(stdout);
    }

    PathTracerSettings pt;
    pt.max_depth = o.max_depth;
    pt.guiding.enabled = o.guiding;
    pt.guiding.training_passes = o.guiding_passes;
    PathTracer integrator(pt);
    ProgressiveSettings ps;
    ps.render.samples_per_pixel = o.spp;
    ps.render.threads = o.threads;
    ps.render.seed = o.seed;
    ps.render.cancel = apps::interrupt_flag();
    apps::ProgressBar progress(!o.quiet);
    ps.render.progress = [&progress](const RenderProgress& p) { progress.update(p); };
    // One sample per pixel per pass: a stop (Ctrl-C, time limit) loses at most one sample's
    // work; each pass costs one copy of the film, small next to rendering it.
    ps.pass_samples = 1;
    ps.time_limit = o.time_limit;
    ps.aovs = lower_extension(o.output) == ".exr";
    Film film;
    const RenderStats stats = render_progressive(loaded.scene, camera, integrator, film, ps);
    progress.finish();
    const bool interrupted = stats.cancelled || apps::interrupt_flag()->load();
    if (stats.passes == 0) {
        std::cerr << "interrupted before the first pass finished: nothing written\n";
        return 130;
    }
    write_output(o.output, film, scale);
    const bool partial = stats.samples_per_pixel < std::uint32_t(o.spp);
    if (!o.quiet || partial) {
        const double rate = stats.seconds > 0.0 ? double(stats.samples) / stats.seconds : 0.0;
        std::printf(
            "%dx%d, %u of %d spp in %d passes, %u threads: render %.2f s (%.2f M "
            "samples/s), total %.2f s, peak memory %.0f MiB\n",
            camera.width(), camera.height(), stats.samples_per_pixel, o.spp, stats.passes,
            o.threads > 0 ? unsigned(o.threads) : std::max(1u, std::thread::hardware_concurrency()),
            stats.seconds, rate * 1e-6, seconds_since(t0), peak_rss_mib());
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

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Renders a glTF 2.0 (.gltf, .glb) or OBJ scene file with librt's path tracer",
                 "rt_render"};
    Options o;
    app.add_option("scene", o.scene, "Scene file: .gltf, .glb or .obj")->required();
    app.add_option("-o,--output", o.output,
                   "Output image: .png (exposure, clamp, sRGB), .hdr, .pfm (linear) or .exr "
                   "(linear, with albedo, normal, depth and sample-count layers)")
        ->capture_default_str();
    app.add_option("--spp", o.spp, "Samples per pixel")->capture_default_str();
    app.add_option("--size", o.size,
                   "Image size WIDTHxHEIGHT (default: the camera's aspect ratio, long side 640)");
    app.add_option("--camera", o.camera,
                   "The file's camera: index (in node order) or name; default: the first");
    app.add_option("--max-depth", o.max_depth, "Scattering events per path")->capture_default_str();
    app.add_option("--threads", o.threads, "Worker threads, 0 = all cores")->capture_default_str();
    app.add_option("--seed", o.seed, "Random seed")->capture_default_str();
    app.add_option("--time-limit", o.time_limit,
                   "Stop after this many seconds and write the finished passes (0 = none)")
        ->capture_default_str();
    app.add_option("--exposure", o.exposure_ev, "Exposure in stops: the image is scaled by 2^EV")
        ->capture_default_str();
    app.add_option("--env", o.env,
                   "Equirectangular Radiance .hdr lighting the scene from every direction "
                   "(importance-sampled; seen by rays that leave the scene)");
    app.add_option("--env-strength", o.env_strength, "Scale of the --env radiance")
        ->capture_default_str();
    app.add_flag("--guiding", o.guiding,
                 "Path guiding: learn the incident light in training passes (discarded), then "
                 "sample directions from it");
    app.add_option("--guiding-passes", o.guiding_passes,
                   "Training passes of --guiding; pass k renders 2^k spp (5: 31 spp)")
        ->capture_default_str();
    app.add_flag("-q,--quiet", o.quiet, "No progress bar and no summary");
    return apps::run(app, argc, argv, [&] { return render_file(o); });
}
