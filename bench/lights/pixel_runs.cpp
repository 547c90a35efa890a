// How a few pixels' estimates spread over many short renders: is a pixel's error a heavy
// tail (rare samples carrying much of its mean, so most short runs read low: median below
// mean) or plain noise (median = mean)? And how much of its variance does a change of the
// scene remove (run it on a variant from scripts/glb_variant.py)?
//
//   librt_pixel_runs SCENE WxH RUNS SPP MAX_DEPTH SAMPLER SEED X,Y [X,Y ...]
//
// renders each pixel (X, Y) of SCENE (through its first camera, Gaussian pixel jitter as
// rt_render uses) with the MIS path tracer, RUNS times with SPP samples (seeds SEED,
// SEED + 1, ...; SAMPLER independent or sobol), one thread, and prints per pixel the mean
// over all RUNS x SPP samples (the mean of the channels), the standard deviation of the
// run means, the per-sample variance it implies (sd^2 SPP), the median of the run means
// over their mean and the fraction of runs below the mean.
// docs/light-targets.md uses it for cornell_pbr.glb's gold sphere and walls.

#include <librt/core/error.h>
#include <librt/film/film.h>
#include <librt/integrator/integrators.h>
#include <librt/loader/scene_file.h>
#include <librt/render/renderer.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

constexpr const char* kUsage =
    "usage: librt_pixel_runs SCENE WxH RUNS SPP MAX_DEPTH SAMPLER SEED X,Y [X,Y ...]\n"
    "  SAMPLER: independent or sobol; RUNS >= 2, SPP >= 1; pixels inside the image\n";

/// A whole decimal number in [lo, hi], or an error naming the parameter and its value.
long parse_int(const std::string& name, const std::string& text, long lo, long hi) {
    char* end = nullptr;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || v < lo || v > hi)
        throw librt::Error(name + " = '" + text + "': must be a whole number in [" +
                           std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
}

/// "AxB" (a size or a pixel) split at `sep` into two whole numbers in [lo, hi].
std::pair<int, int> parse_pair(const std::string& name, const std::string& text, char sep, long lo,
                               long hi) {
    const auto at = text.find(sep);
    if (at == std::string::npos)
        throw librt::Error(name + " = '" + text + "': expected A" + sep + "B");
    return {static_cast<int>(parse_int(name, text.substr(0, at), lo, hi)),
            static_cast<int>(parse_int(name, text.substr(at + 1), lo, hi))};
}

}  // namespace

int main(int argc, char** argv) try {
    if (argc < 9) {
        std::fputs(kUsage, stderr);
        return 1;
    }
    const std::string scene_path = argv[1];
    const auto [width, height] = parse_pair("WxH", argv[2], 'x', 1, 16384);
    const int runs = static_cast<int>(parse_int("RUNS", argv[3], 2, 1'000'000));
    const auto spp = static_cast<std::uint32_t>(parse_int("SPP", argv[4], 1, 1 << 20));
    const int max_depth = static_cast<int>(parse_int("MAX_DEPTH", argv[5], 0, 1000));
    const std::string sampler = argv[6];
    if (sampler != "independent" && sampler != "sobol")
        throw librt::Error("SAMPLER = '" + sampler + "': must be independent or sobol");
    const auto seed = static_cast<std::uint64_t>(parse_int("SEED", argv[7], 0, 1L << 40));
    std::vector<std::pair<int, int>> pixels;
    for (int i = 8; i < argc; ++i) {
        const auto p = parse_pair("X,Y", argv[i], ',', 0, 16383);
        if (p.first >= width || p.second >= height)
            throw librt::Error("X,Y = '" + std::string(argv[i]) + "': outside the " +
                               std::to_string(width) + "x" + std::to_string(height) + " image");
        pixels.push_back(p);
    }

    librt::SceneFileOptions options;
    options.width = width;
    options.height = height;
    // The file's own lights alone, as docs/light-targets.md measured cornell_pbr.glb.
    options.default_lighting = false;
    librt::LoadedScene loaded = librt::load_scene_file(scene_path, options);
    loaded.scene.commit();
    librt::CameraSettings view = loaded.camera;
    view.pixel_jitter = librt::PixelJitter::Gaussian;  // as rt_render
    const librt::Camera camera(view);
    librt::PathTracerSettings pt;
    pt.max_depth = max_depth;
    librt::PathTracer integrator(pt);
    integrator.preprocess(loaded.scene);

    std::printf("%s %dx%d, %d runs of %u spp, max depth %d, %s, seeds %llu..\n", scene_path.c_str(),
                width, height, runs, spp, max_depth, sampler.c_str(),
                static_cast<unsigned long long>(seed));
    for (const auto& [x, y] : pixels) {
        std::vector<double> means;
        means.reserve(static_cast<std::size_t>(runs));
        for (int r = 0; r < runs; ++r) {
            librt::Film film(width, height);
            librt::BlockSettings settings;
            settings.threads = 1;
            settings.seed = seed + static_cast<std::uint64_t>(r);
            settings.sampler =
                sampler == "sobol" ? librt::SamplerKind::Sobol : librt::SamplerKind::Independent;
            librt::render_block(loaded.scene, camera, integrator, film,
                                {x, y, x + 1, y + 1, 0, spp}, settings);
            const librt::FilmPixel& p = film.at(x, y);
            means.push_back((p.radiance.x + p.radiance.y + p.radiance.z) / (3.0 * p.samples));
        }
        double mean = 0.0;
        for (const double m : means) mean += m;
        mean /= runs;
        double var = 0.0;
        for (const double m : means) var += (m - mean) * (m - mean);
        var /= runs - 1;
        const auto below =
            std::count_if(means.begin(), means.end(), [&](double m) { return m < mean; });
        std::nth_element(means.begin(), means.begin() + runs / 2, means.end());
        const double median = means[static_cast<std::size_t>(runs / 2)];
        std::printf(
            "(%d, %d): mean %.4f  sd of runs %.4f  per-sample variance %.4g  "
            "median / mean %.4f  runs below the mean %.2f\n",
            x, y, mean, std::sqrt(var), var * spp, median / mean,
            static_cast<double>(below) / runs);
    }
    return 0;
} catch (const librt::Error& e) {
    std::fprintf(stderr, "librt_pixel_runs: %s\n", e.what());
    return 1;
}
