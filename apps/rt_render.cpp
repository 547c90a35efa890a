// rt_render: renders a scene file the user brings, glTF 2.0 (.gltf, .glb) or OBJ (with its
// MTL), through loader/scene_file.h, progressively (render_progressive): Ctrl-C or the time
// limit ends the render and the finished passes are written, flagged as partial. PNG is
// sRGB-encoded after clamping (exposure 2^EV first); .hdr, .pfm and .exr stay linear
// (times 2^EV), .exr with AOV layers (albedo, world normal, planar depth Z, sample count).
// PNG output is denoised by default (render/denoiser.h); EXR gets a denoised layer.
// Under mpirun (a build with MPI) every rank loads the scene and the frame is shared by the
// ranks, byte for byte the one-process image (common/mpi_job.h, docs/distributed.md).
#include "common/cli.h"
#include "common/mpi_job.h"
#include "common/output_image.h"
#include "common/scene_app.h"

#include <librt/core/error.h>
#include <librt/core/untrusted_text.h>
#include <librt/film/framing.h>
#include <librt/film/pixel_region.h>
#include <librt/integrator/bdpt.h>
#include <librt/integrator/integrators.h>
#include <librt/io/file_digest.h>
#include <librt/io/file_extension.h>
#include <librt/io/hdr_image.h>
#include <librt/io/image_io.h>
#include <librt/light/environment_light.h>
#include <librt/loader/scene_file.h>
#include <librt/render/renderer.h>

#include <CLI/CLI.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

using namespace librt;

namespace {

/// --integrator.
enum class IntegratorKind { Path, Bidirectional, BruteForce };

/// --light-choice: one of LightChoice's, or Auto (decided by the scene's light count).
enum class LightChoiceOption { Auto, Power, Bounded };

/// A name on the command line and the value it stands for.
template <class Kind>
struct Named {
    const char* name;
    Kind kind;
};

constexpr std::array<Named<IntegratorKind>, 3> kIntegrators{{
    {"path", IntegratorKind::Path},
    {"bdpt", IntegratorKind::Bidirectional},
    {"brute", IntegratorKind::BruteForce},
}};

constexpr std::array<Named<ToneCurve>, 3> kToneCurves{{
    {"clamp", ToneCurve::Clamp},
    {"aces", ToneCurve::Aces},
    {"agx", ToneCurve::Agx},
}};

constexpr std::array<Named<LightChoiceOption>, 3> kLightChoices{{
    {"auto", LightChoiceOption::Auto},
    {"power", LightChoiceOption::Power},
    {"bounded", LightChoiceOption::Bounded},
}};

constexpr std::array<Named<PunctualLightUnits>, 2> kLightUnits{{
    {"watts", PunctualLightUnits::Watts},
    {"photometric", PunctualLightUnits::Photometric},
}};

/// --diffuse: the glTF materials' diffuse base (SceneFileOptions::diffuse_model).
constexpr std::array<Named<DiffuseModel>, 2> kDiffuseModels{{
    {"lambert", DiffuseModel::Lambert},
    {"burley", DiffuseModel::Burley},
}};

/// An option that names one of a few values: the text as typed and, when it names one, the
/// value (CLI11 parses it once, through Option::each). An unknown name is not CLI11's error
/// but check_choices', which names the text as the other rules do.
template <class Kind>
struct Choice {
    std::string typed;
    std::optional<Kind> kind;
};

/// The name of `kind` in `names`.
template <class Kind, std::size_t N>
std::string name_of(const std::array<Named<Kind>, N>& names, Kind kind) {
    for (const Named<Kind>& n : names) {
        if (n.kind == kind) return n.name;
    }
    return "?";
}

/// `choice` set to the default `kind`.
template <class Kind, std::size_t N>
Choice<Kind> choice_of(const std::array<Named<Kind>, N>& names, Kind kind) {
    return {name_of(names, kind), kind};
}

/// Registers `choice` as option `name`: each value given is looked up in `names` (exactly:
/// the names are lower case), the last one counting.
template <class Kind, std::size_t N>
CLI::Option* add_choice(CLI::App& app, const std::string& name, Choice<Kind>& choice,
                        const std::array<Named<Kind>, N>& names, const std::string& help) {
    return app.add_option(name, choice.typed, help)
        ->capture_default_str()
        ->each([&choice, &names](const std::string& text) {
            choice.kind.reset();
            for (const Named<Kind>& n : names) {
                if (text == n.name) choice.kind = n.kind;
            }
        });
}

struct Options {
    std::string scene;
    std::string output = "render.png";
    // The defaults are the best settings measured (docs/render-your-own-scene.md, "The
    // defaults"): Sobol' samples, adaptive sampling (Options() sets them in `sampling`),
    // paths ended by Russian roulette rather than a low cap.
    int spp = 16;
    std::string size;    // "WxH"; empty = the camera's aspect, long side 640
    std::string region;  // "X,Y,W,H": render and write only these pixels; empty = all
    std::string camera;
    std::string look_from;       // "X,Y,Z"; empty = the camera's
    std::string look_at;         // "X,Y,Z"; empty = the camera's (with --look-from: the centre)
    std::optional<float> fov;    // vertical, degrees
    std::optional<float> orbit;  // degrees about +y, auto framing
    int max_depth = -1;          // -1: the most the integrator allows (1000; bdpt 64)
    int gltf_scene = -1;         // --scene: which of a glTF's scenes; -1 = the file's default
    std::string variant;         // --variant: a KHR_materials_variants name; empty = none
    Choice<PunctualLightUnits> light_units = choice_of(kLightUnits, PunctualLightUnits::Watts);
    Choice<LightChoiceOption> light_choice = choice_of(kLightChoices, LightChoiceOption::Auto);
    Choice<IntegratorKind> integrator = choice_of(kIntegrators, IntegratorKind::Path);
    bool caustic_paths = false;  // the path tracer's caustics traced from the lights
    bool all_emitters = false;   // every emissive triangle a light (TriangleLightSettings 0)
    float light_paths = 1.0f;    // bdpt: fraction of samples tracing a light subpath
    int roulette_depth = -1;     // first rouletted bounce; -1 = the integrator's own
    int threads = 0;
    std::uint64_t seed = 0;
    double time_limit = 0.0;
    double noise_target = 0.0;   // stop at this estimated relative error; 0 = none
    std::string exposure = "0";  // EV stops, or "auto" (the PNG's, from its image)
    // PNG: a filmic curve by default (highlights roll off); the report apps keep the clamp.
    Choice<ToneCurve> tonemap = choice_of(kToneCurves, ToneCurve::Aces);
    int png_bits = 8;
    bool transparent_background = false;  // PNG alpha = coverage; the sky lights but is unseen
    bool exr_half = false;                // EXR colour channels as half floats (clamped to 65504)
    std::string env;                // equirectangular .hdr or .exr lighting the scene; empty = none
    float env_strength = 1.0f;      // scale of the environment's radiance
    float env_rotate = 0.0f;        // degrees about the up axis (+y)
    bool no_default_light = false;  // a file without lights stays unlit (its emitters alone)
    Choice<DiffuseModel> diffuse = choice_of(kDiffuseModels, DiffuseModel::Lambert);
    bool solid_transmission = false;  // glTF transmission without a volume: solid glass
    bool quiet = false;
    std::string preview;               // a PNG rewritten with the image so far as the passes finish
    bool allow_outside_files = false;  // the scene may read files outside its directory
    apps::AppOptions sampling;         // --sampler, --filter, --filter-radius, --guiding(-passes)
    int mpi_tile = 32;                 // under mpirun: side of the tiles rank 0 hands out
    // --denoise / --no-denoise; unset = the output's default (denoise_wanted).
    std::optional<bool> denoise;

    Options() {
        sampling.sampler = "sobol";
        sampling.adaptive = true;
    }

    /// Whether to denoise: as asked, else for PNG (the image a user looks at: the denoised
    /// one) and EXR (a denoised layer; the beauty stays the unbiased estimate), not for the
    /// linear .hdr and .pfm (measurements), and not under mpirun, where the ranks keep no
    /// film part way for the denoiser's noise estimate.
    [[nodiscard]] bool denoise_wanted(bool distributed) const {
        if (denoise) return *denoise;
        const std::string ext = lower_extension(output);
        return !distributed && (ext == ".png" || ext == ".exr");
    }
    /// --integrator, once check_choices has passed.
    [[nodiscard]] IntegratorKind integrator_kind() const { return *integrator.kind; }
    /// --exposure in stops (0 for auto), once check_output_options has passed.
    [[nodiscard]] float exposure_ev() const {
        return exposure == "auto" ? 0.0f : std::stof(exposure);
    }
    /// --light-choice, once check_choices has passed.
    [[nodiscard]] LightChoiceOption light_choice_kind() const { return *light_choice.kind; }
};

[[noreturn]] void bad(const std::string& option, const std::string& value, const char* rule) {
    throw Error(option + " = " + value + ": " + rule);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// What every rank of an MPI job must agree on before loading (MpiJob::check_same_job): every
// option that shapes the image or its file, the scene file's and the sky's bytes as digests
// (the files a glTF or OBJ refers to, .bin, .mtl, textures, are compared once loaded:
// file_items). Not --threads nor --quiet, which may differ between ranks. A new option that
// shapes the image goes here.
std::vector<std::pair<std::string, std::string>> job_items(const Options& o) {
    const auto exact = [](double v) {  // round-trips a float or double exactly
        char text[32];
        std::snprintf(text, sizeof text, "%.17g", v);
        return std::string(text);
    };
    const auto on = [](bool b) { return std::string(b ? "on" : "off"); };
    const auto given = [](const std::string& v) { return v.empty() ? "(none)" : v; };
    const apps::AppOptions& s = o.sampling;
    return {
        {"scene file", to_string(file_digest(o.scene))},
        {"--env", o.env.empty() ? "(none)" : to_string(file_digest(o.env))},
        {"--output", o.output},
        {"--spp", std::to_string(o.spp)},
        {"--size", given(o.size)},
        {"--region", given(o.region)},
        {"--camera", given(o.camera)},
        {"--look-from", given(o.look_from)},
        {"--look-at", given(o.look_at)},
        {"--fov", o.fov ? exact(*o.fov) : "(the camera's)"},
        {"--orbit", o.orbit ? exact(*o.orbit) : "(none)"},
        {"--scene", std::to_string(o.gltf_scene)},
        {"--variant", given(o.variant)},
        {"--light-units", o.light_units.typed},
        {"--max-depth", std::to_string(o.max_depth)},
        {"--light-choice", name_of(kLightChoices, o.light_choice_kind())},
        {"--integrator", name_of(kIntegrators, o.integrator_kind())},
        {"--caustic-paths", on(o.caustic_paths)},
        {"--all-emitters", on(o.all_emitters)},
        {"--light-paths", exact(o.light_paths)},
        {"--roulette-depth", std::to_string(o.roulette_depth)},
        {"--seed", std::to_string(o.seed)},
        {"--time-limit", exact(o.time_limit)},
        {"--noise-target", exact(o.noise_target)},
        {"--exposure", o.exposure},
        {"--tonemap", to_string(*o.tonemap.kind)},
        {"--png-bits", std::to_string(o.png_bits)},
        {"--transparent-background", on(o.transparent_background)},
        {"--env-strength", exact(o.env_strength)},
        {"--env-rotate", exact(o.env_rotate)},
        {"--no-default-light", on(o.no_default_light)},
        {"--diffuse", o.diffuse.typed},
        {"--solid-transmission", on(o.solid_transmission)},
        {"--sampler", s.sampler},
        {"--filter", given(s.filter)},
        {"--filter-radius", s.filter_radius ? exact(*s.filter_radius) : "(the filter's)"},
        {"--guiding", on(s.guiding)},
        {"--guiding-passes", std::to_string(s.guiding_passes)},
        {"--adaptive", on(s.adaptive)},
        {"--mpi-tile", std::to_string(o.mpi_tile)},
        {"--allow-outside-files", on(o.allow_outside_files)},
        {"--exr-half", on(o.exr_half)},
        {"--denoise", on(o.denoise_wanted(true))},
    };
}

// What every rank must agree on once the scene is loaded: the digest of every file it was
// made from (LoadedScene::files_read, from the bytes in memory). The scene file is "scene
// file", as before loading (its bytes may have changed since); each other file is named by
// its path relative to the scene file's directory, so that ranks whose scenes lie in
// different directories compare "textures/wood.png" with "textures/wood.png". A file
// outside that tree (--allow-outside-files) keeps its canonical path.
std::vector<std::pair<std::string, std::string>> file_items(const std::filesystem::path& scene,
                                                            const std::vector<FileRead>& files) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path dir = fs::weakly_canonical(fs::absolute(scene).parent_path(), ec);
    std::vector<std::pair<std::string, std::string>> items;
    for (const FileRead& f : files) {
        if (f.path == scene) {
            items.emplace_back("scene file", to_string(f.digest));
            continue;
        }
        fs::path shown = fs::weakly_canonical(f.path, ec);
        if (ec) shown = f.path;
        const fs::path relative = shown.lexically_relative(dir);
        if (!relative.empty() && *relative.begin() != "..") shown = relative;
        // The name comes from the scene file: escaped, whole (names must stay unique; a
        // path the system opened is at most PATH_MAX long).
        items.emplace_back("file '" + printable(shown.string()) + "'", to_string(f.digest));
    }
    return items;
}

// The rules, in the order a command line meets them (the first broken one is the error,
// "--option = value: rule"). render_file calls them before the scene is loaded.

/// --max-depth's range, then the names of --light-choice and --integrator.
void check_choices(const Options& o) {
    if (o.max_depth < -1 || o.max_depth > 1000)
        bad("--max-depth", std::to_string(o.max_depth), "must be in [0, 1000] (-1: the most)");
    if (!o.light_choice.kind)
        bad("--light-choice", o.light_choice.typed, "must be auto, power or bounded");
    if (!o.integrator.kind) bad("--integrator", o.integrator.typed, "must be path, bdpt or brute");
    if (!o.diffuse.kind) bad("--diffuse", o.diffuse.typed, "must be lambert or burley");
}

/// The integrator's own options: their ranges, and each only with the integrator it is for.
void check_integrator_options(const Options& o) {
    const IntegratorKind kind = o.integrator_kind();
    if (kind == IntegratorKind::Bidirectional && o.max_depth > BidirectionalSettings::kMaxDepth)
        bad("--max-depth", std::to_string(o.max_depth),
            "must be in [0, 64] with --integrator bdpt");
    static_assert(BidirectionalSettings::kMaxDepth == 64, "the message above");
    if (kind != IntegratorKind::Path && o.sampling.guiding)
        bad("--guiding", "on", "path guiding is the path tracer's: use --integrator path");
    if (o.sampling.guiding_passes < 1 || o.sampling.guiding_passes > 20)
        bad("--guiding-passes", std::to_string(o.sampling.guiding_passes), "must be in [1, 20]");
    if (o.caustic_paths && kind != IntegratorKind::Path)
        bad("--caustic-paths", "on",
            "caustic light paths are the path tracer's: use --integrator path");
    if (!(o.light_paths > 0.0f && o.light_paths <= 1.0f))
        bad("--light-paths", std::to_string(o.light_paths), "must be in (0, 1]");
    if (o.light_paths != 1.0f && kind != IntegratorKind::Bidirectional)
        bad("--light-paths", std::to_string(o.light_paths), "needs --integrator bdpt");
    if (o.roulette_depth < -1 || o.roulette_depth > 64)
        bad("--roulette-depth", std::to_string(o.roulette_depth),
            "must be in [0, 64] (or -1: the integrator's default)");
    if (o.caustic_paths && o.sampling.guiding)
        bad("--caustic-paths", "on", "cannot be combined with --guiding");
}

/// --time-limit: finite, and not under mpirun. Ranks render whole tiles with all their
/// samples, not passes over the image: a frame stopped by the clock would hold different
/// sample counts in different tiles.
void check_time_limit(const Options& o, bool distributed) {
    if (!std::isfinite(o.time_limit) || o.time_limit < 0.0)
        bad("--time-limit", std::to_string(o.time_limit), "must be finite and >= 0 (0 = none)");
    if (distributed && o.time_limit > 0.0)
        bad("--time-limit", std::to_string(o.time_limit),
            "is not available under mpirun (use --spp)");
    if (!(o.noise_target >= 0.0 && o.noise_target <= 1.0))
        bad("--noise-target", std::to_string(o.noise_target), "must be in [0, 1] (0 = none)");
    if (distributed && o.noise_target > 0.0)
        bad("--noise-target", std::to_string(o.noise_target),
            "is not available under mpirun (use --spp)");
}

/// --preview: a PNG, not the output itself (it would be overwritten by each pass and then by
/// the final image in another look), and not under mpirun, where ranks render whole tiles
/// rather than passes over the image.
void check_preview(const Options& o, bool distributed, bool root) {
    if (o.preview.empty()) return;
    if (lower_extension(o.preview) != ".png") bad("--preview", o.preview, "must be a .png file");
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::weakly_canonical(o.preview, ec) == fs::weakly_canonical(o.output, ec))
        bad("--preview", o.preview, "must differ from --output");
    if (distributed) bad("--preview", o.preview, "is not available under mpirun");
    if (root) check_image_path(o.preview);
}

/// With --size: the render's films, copies and output buffers must fit, before any is
/// allocated.
void check_memory(const Options& o, const SceneFileOptions& file_options, bool distributed) {
    if (o.size.empty()) return;
    RenderMemoryOptions memory;
    memory.splats = o.integrator_kind() == IntegratorKind::Bidirectional || o.caustic_paths;
    memory.adaptive = o.sampling.adaptive;
    // The noise estimate of the target and of the progress bar (the same number).
    memory.noise_estimate = o.noise_target > 0.0 || !o.quiet;
    memory.keeps_training = o.sampling.guiding;
    memory.aovs = o.transparent_background;  // the coverage
    apps::check_render_memory(
        "--size", o.size, file_options.width, file_options.height,
        apps::progressive_output_bytes_per_pixel(o.output, memory, o.denoise_wanted(distributed)));
}

/// --mpi-tile, and the options of the image file and of the sky.
void check_output_options(const Options& o) {
    if (o.mpi_tile < 1 || o.mpi_tile > 1024)
        bad("--mpi-tile", std::to_string(o.mpi_tile), "must be in [1, 1024]");
    if (o.exposure != "auto") {
        std::size_t used = 0;
        float ev = NAN;
        try {
            ev = std::stof(o.exposure, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != o.exposure.size() || !std::isfinite(ev) || std::abs(ev) > 64.0f)
            bad("--exposure", o.exposure, "must be in [-64, 64] (EV stops) or auto");
    }
    if (!o.tonemap.kind) bad("--tonemap", o.tonemap.typed, "must be aces, agx or clamp");
    const bool png = lower_extension(o.output) == ".png";
    if (o.png_bits != 8 && o.png_bits != 16)
        bad("--png-bits", std::to_string(o.png_bits), "must be 8 or 16");
    if (o.png_bits != 8 && !png)
        bad("--png-bits", std::to_string(o.png_bits), "needs a .png output");
    if (o.transparent_background && !png)
        bad("--transparent-background", "on", "needs a .png output (its alpha channel)");
    if (o.exr_half && lower_extension(o.output) != ".exr")
        bad("--exr-half", "on", "needs an .exr output");
    if (!std::isfinite(o.env_strength) || o.env_strength < 0.0f)
        bad("--env-strength", std::to_string(o.env_strength), "must be finite and >= 0");
    if (o.env.empty() && o.env_strength != 1.0f)
        bad("--env-strength", std::to_string(o.env_strength), "needs --env");
    if (!std::isfinite(o.env_rotate) || std::abs(o.env_rotate) > 360.0f)
        bad("--env-rotate", std::to_string(o.env_rotate), "must be in [-360, 360] (degrees)");
    // The built-in sky is the same all around the up axis: turning it would do nothing.
    if (o.env.empty() && o.env_rotate != 0.0f)
        bad("--env-rotate", std::to_string(o.env_rotate), "needs --env");
}

/// --denoise needs two parts of every pixel's samples, which a frame shared by MPI ranks
/// does not keep.
void check_denoise(const Options& o, bool distributed) {
    if (distributed && o.denoise.value_or(false))
        bad("--denoise", "on", "is not available under mpirun (use --no-denoise)");
}

/// --region's text "X,Y,W,H" as the pixels [X, X + W) x [Y, Y + H): four whole numbers,
/// X and Y >= 0, W and H >= 1, within the largest image (65536 a side).
PixelRegion parse_region(const std::string& text) {
    long long v[4] = {0, 0, 0, 0};
    std::size_t at = 0;
    for (int i = 0; i < 4; ++i) {
        const std::size_t end = i < 3 ? text.find(',', at) : text.size();
        if (end == std::string::npos)
            bad("--region", text, "must be X,Y,W,H: four whole numbers (pixels, origin top-left)");
        const std::string part = text.substr(at, end - at);
        std::size_t used = 0;
        try {
            v[i] = std::stoll(part, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        // std::stoll would also take leading blanks and a '+'.
        const bool starts_well =
            !part.empty() && (std::isdigit(static_cast<unsigned char>(part[0])) || part[0] == '-');
        if (!starts_well || used != part.size())
            bad("--region", text, "must be X,Y,W,H: four whole numbers (pixels, origin top-left)");
        at = end + 1;
    }
    if (v[0] < 0 || v[1] < 0 || v[2] < 1 || v[3] < 1)
        bad("--region", text, "X and Y must be >= 0, W and H >= 1");
    if (v[0] + v[2] > 65536 || v[1] + v[3] > 65536)
        bad("--region", text, "must lie within the image (at most 65536 pixels a side)");
    return {int(v[0]), int(v[1]), int(v[0] + v[2]), int(v[1] + v[3])};
}

/// --region within the width x height image.
void check_region_fits(const Options& o, const PixelRegion& r, int width, int height) {
    if (r.x1 > width || r.y1 > height)
        bad("--region", o.region,
            ("must lie within the " + std::to_string(width) + "x" + std::to_string(height) +
             " image (X + W <= " + std::to_string(width) + ", Y + H <= " + std::to_string(height) +
             ")")
                .c_str());
}

/// --region: well formed, within --size when given, and only where a crop can hold the
/// whole render's pixels: not under mpirun (ranks render whole tiles of the frame), not
/// with light paths that land on any pixel (bdpt, --caustic-paths).
void check_region(const Options& o, const SceneFileOptions& file_options, bool distributed) {
    if (o.region.empty()) return;
    const PixelRegion r = parse_region(o.region);
    if (distributed) bad("--region", o.region, "is not available under mpirun");
    if (o.integrator_kind() == IntegratorKind::Bidirectional || o.caustic_paths)
        bad("--region", o.region,
            "needs camera paths alone (--integrator path or brute, no --caustic-paths): light "
            "paths land on any pixel, so a crop cannot hold the full render's pixels");
    if (!o.size.empty()) check_region_fits(o, r, file_options.width, file_options.height);
}

/// A point typed as "X,Y,Z" (three finite numbers).
glm::vec3 parse_point(const std::string& option, const std::string& text) {
    glm::vec3 p(0.0f);
    std::size_t at = 0;
    for (int i = 0; i < 3; ++i) {
        const std::size_t end = i < 2 ? text.find(',', at) : text.size();
        if (end == std::string::npos) bad(option, text, "must be three numbers X,Y,Z");
        const std::string part = text.substr(at, end - at);
        std::size_t used = 0;
        try {
            p[i] = std::stof(part, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (part.empty() || used != part.size() || !std::isfinite(p[i]))
            bad(option, text, "must be three finite numbers X,Y,Z");
        at = end + 1;
    }
    return p;
}

/// --look-from, --look-at, --fov and --orbit as the loader's ViewOptions (film/framing.h);
/// their ranges checked here, naming the option.
ViewOptions view_options(const Options& o) {
    ViewOptions view;
    if (!o.look_from.empty()) view.look_from = parse_point("--look-from", o.look_from);
    if (!o.look_at.empty()) view.look_at = parse_point("--look-at", o.look_at);
    if (o.fov && !(*o.fov > 0.0f && *o.fov < 179.0f))
        bad("--fov", std::to_string(*o.fov), "must be in (0, 179) (degrees)");
    view.vertical_fov_degrees = o.fov;
    if (o.orbit && !(std::abs(*o.orbit) <= 360.0f))
        bad("--orbit", std::to_string(*o.orbit), "must be in [-360, 360] (degrees)");
    if (o.orbit && (view.look_from || view.look_at))
        bad("--orbit", std::to_string(*o.orbit),
            "turns the auto-framed camera: not with --look-from or --look-at");
    if (view.look_from && view.look_at && *view.look_from == *view.look_at)
        bad("--look-from", o.look_from, "must differ from --look-at");
    view.orbit_degrees = o.orbit;
    return view;
}

/// Checks everything the user typed, before the scene is loaded; returns what the scene
/// file is loaded with.
SceneFileOptions check_command_line(const Options& o, const apps::MpiJob& job) {
    if (job.rank() == 0) check_image_path(o.output);  // alone, or the rank that writes
    SceneFileOptions file_options;
    file_options.camera = o.camera;
    file_options.allow_outside_files = o.allow_outside_files;
    file_options.view = view_options(o);
    // --env replaces the default lighting rather than adding to it.
    file_options.default_lighting = !o.no_default_light && o.env.empty();
    file_options.background_visible = !o.transparent_background;
    // What the scene file is read as: the loader checks the scene index and variant name
    // against the file; the light units' name is checked here.
    if (o.gltf_scene < -1) bad("--scene", std::to_string(o.gltf_scene), "must be >= 0");
    if (!o.light_units.kind)
        bad("--light-units", o.light_units.typed, "must be watts or photometric");
    file_options.scene = o.gltf_scene;
    file_options.variant = o.variant;
    file_options.light_units = *o.light_units.kind;
    file_options.solid_transmission = o.solid_transmission;
    if (!o.size.empty()) apps::parse_size(o.size, 0.0f, file_options.width, file_options.height);
    RenderSettings check;
    check.samples_per_pixel = o.spp;
    check.threads = o.threads;
    validate(check);
    check_choices(o);
    file_options.diffuse_model = *o.diffuse.kind;  // named by check_choices
    check_integrator_options(o);
    check_region(o, file_options, job.distributed());
    check_time_limit(o, job.distributed());
    check_preview(o, job.distributed(), job.rank() == 0);
    apps::validate_sampling(o.sampling);
    check_memory(o, file_options, job.distributed());
    check_output_options(o);
    check_denoise(o, job.distributed());
    return file_options;
}

/// --max-depth, -1 standing for the most the integrator allows: the path tracer's own
/// default (1000: paths end by roulette long before) or the bidirectional tracer's cap.
int max_depth_of(const Options& o) {
    if (o.max_depth >= 0) return o.max_depth;
    return o.integrator_kind() == IntegratorKind::Bidirectional ? BidirectionalSettings::kMaxDepth
                                                                : PathTracerSettings{}.max_depth;
}

/// The path tracer's settings. --light-choice auto: by bound
/// (through the light tree) when there are more lights than the bounded choice weighs one by
/// one, where power alone sends most shadow rays to far lights; by power otherwise, as before
/// the tree.
PathTracerSettings path_tracer_settings(const Options& o, std::size_t light_count) {
    PathTracerSettings pt;
    pt.max_depth = max_depth_of(o);
    const LightChoiceOption choice = o.light_choice_kind();
    const bool many_lights = light_count > LightSampler::kMaxBounded;
    pt.light_choice =
        choice == LightChoiceOption::Bounded || (choice == LightChoiceOption::Auto && many_lights)
            ? LightChoice::Bounded
            : LightChoice::Power;
    pt.guiding.enabled = o.sampling.guiding;
    pt.guiding.training_passes = o.sampling.guiding_passes;
    // Kept in the image, alone (render_progressive's final frame) and under mpirun alike.
    pt.guiding.keep_training_samples = o.sampling.guiding;
    pt.caustic_paths.enabled = o.caustic_paths;
    if (o.roulette_depth >= 0) pt.russian_roulette_depth = o.roulette_depth;
    return pt;
}

/// The integrator --integrator names, and only that one.
std::unique_ptr<GuardedIntegrator> make_integrator(const Options& o, std::size_t light_count) {
    switch (o.integrator_kind()) {
        case IntegratorKind::Path:
            return std::make_unique<PathTracer>(path_tracer_settings(o, light_count));
        case IntegratorKind::Bidirectional: {
            BidirectionalSettings bd;
            bd.max_depth = max_depth_of(o);
            bd.light_path_fraction = o.light_paths;
            if (o.roulette_depth >= 0) bd.russian_roulette_depth = o.roulette_depth;
            return std::make_unique<BidirectionalPathTracer>(bd);
        }
        case IntegratorKind::BruteForce: {
            // Only the settings it reads: it refuses the path tracer's own.
            PathTracerSettings brute;
            brute.max_depth = max_depth_of(o);
            if (o.roulette_depth >= 0) brute.russian_roulette_depth = o.roulette_depth;
            return std::make_unique<BruteForcePathTracer>(brute);
        }
    }
    throw Error("--integrator: unknown kind");  // unreachable: check_choices refused it
}

int render_file(const Options& o, const apps::MpiJob& job) {
    const bool root = job.rank() == 0;  // alone, or the rank that writes
    const SceneFileOptions file_options = check_command_line(o, job);
    const float scale = std::exp2(o.exposure_ev());
    // The PNG's look (also under mpirun, so that ranks write the one-process bytes).
    apps::OutputLook look = apps::display_look(scale, o.exr_half);
    look.curve = *o.tonemap.kind;
    look.auto_exposure = o.exposure == "auto";
    look.png_bits = o.png_bits;
    look.alpha = o.transparent_background;
    // Under mpirun: every rank was given the same job, before the long load.
    if (job.distributed()) job.check_same_job(job_items(o));
    // The sky is read before the scene, so a bad file fails before the long load.
    std::optional<EnvironmentLight> environment;
    if (!o.env.empty())
        environment = EnvironmentLight::from_image(load_environment_image(o.env),
                                                   rotation_about_up(o.env_rotate), o.env_strength);

    const auto t0 = std::chrono::steady_clock::now();
    LoadedScene loaded = load_scene_file(o.scene, file_options);
    const double load_seconds = seconds_since(t0);
    // Under mpirun: and every file the scene names (a .bin, an image) is the same on every
    // rank, before the BVH is built.
    if (job.distributed()) job.check_same_job(file_items(o.scene, loaded.files_read));
    if (root) {
        for (const std::string& w : loaded.warnings) std::cerr << "warning: " << w << '\n';
        // Said once, on stderr with the warnings: the image is not lit as the file alone
        // would light it.
        if (!loaded.lighting_note.empty())
            std::cerr << "note: " << loaded.lighting_note
                      << " (--no-default-light: none; --env FILE: your own)\n";
    }
    if (environment) loaded.scene.add_environment_light(*environment, !o.transparent_background);
    if (o.all_emitters) loaded.scene.set_triangle_light_settings({0.0f, 0.0f});
    const auto t1 = std::chrono::steady_clock::now();
    try {
        loaded.scene.commit();
    } catch (const Error& e) {
        // Out of memory building a loaded scene: say which file it was.
        throw Error(o.scene + ": " + e.what());
    }
    const double build_seconds = seconds_since(t1);
    CameraSettings camera_settings = loaded.camera;
    camera_settings.pixel_jitter = PixelJitter::Gaussian;  // anti-aliasing
    const Camera camera(apps::with_filter(camera_settings, o.sampling));
    // Without --size the image's size is the camera's, known only now.
    PixelRegion region;
    if (!o.region.empty()) {
        region = parse_region(o.region);
        check_region_fits(o, region, camera.width(), camera.height());
    }
    job.setup_succeeded();  // under mpirun: every rank's set-up worked (else this throws)
    if (!o.quiet && root) {
        std::printf(
            "%s: %zu triangles stored, %zu placed, %zu instances, %zu lights, BVH %.1f MiB; "
            "load %.2f s, build %.2f s; camera %s (%s) %dx%d\n",
            printable(o.scene).c_str(), loaded.triangles_stored, loaded.triangles_placed,
            loaded.scene.instance_count(), loaded.scene.lights().size(),
            double(loaded.scene.top_level().memory_bytes()) / (1024.0 * 1024.0), load_seconds,
            // The name is the file's, as it is: quoted as untrusted text (escaped, capped).
            build_seconds, quote_untrusted(loaded.camera_name).c_str(),
            camera_settings.projection == Projection::Orthographic ? "orthographic" : "perspective",
            camera.width(), camera.height());
        std::fflush(stdout);
    }

    const std::unique_ptr<GuardedIntegrator> integrator =
        make_integrator(o, loaded.scene.lights().size());
    if (job.distributed()) {
        apps::MpiJobSettings ms;
        ms.render.samples_per_pixel = o.spp;
        ms.render.threads = o.threads;
        ms.render.seed = o.seed;
        ms.render.sampler = apps::sampler_kind(o.sampling);
        ms.render.adaptive.enabled = o.sampling.adaptive;
        ms.tile_size = o.mpi_tile;
        ms.aovs = lower_extension(o.output) == ".exr" || o.transparent_background;
        return apps::render_over_ranks(job, loaded.scene, camera, *integrator, ms, o.quiet,
                                       o.output, [&](const Film& film, const Image& image) {
                                           apps::write_output(o.output, image, look, &film);
                                       });
    }
    apps::ProgressiveOutput out;
    out.output = o.output;
    out.spp = o.spp;
    out.threads = o.threads;
    out.seed = o.seed;
    out.sampler = apps::sampler_kind(o.sampling);
    out.time_limit = o.time_limit;
    out.noise_target = o.noise_target;
    out.adaptive = o.sampling.adaptive;
    out.scale = scale;
    out.curve = look.curve;
    out.auto_exposure = look.auto_exposure;
    out.png_bits = look.png_bits;
    out.alpha = look.alpha;
    out.exr_half = o.exr_half;
    out.quiet = o.quiet;
    out.denoise = o.denoise_wanted(false);
    out.preview = o.preview;
    out.region = region;
    out.started = t0;
    return apps::render_progressively_and_write(loaded.scene, camera, *integrator, out);
}

}  // namespace

int main(int argc, char** argv) {
    // Joins the MPI job when started by mpirun (a build with MPI), before anything else.
    apps::MpiJob job(argc, argv);
    CLI::App app{"Renders a glTF 2.0 (.gltf, .glb) or OBJ scene file with librt's path tracer",
                 "rt_render"};
    Options o;
    app.add_option("scene", o.scene, "Scene file: .gltf, .glb or .obj")->required();
    app.add_option("-o,--output", o.output,
                   "Output image: .png (exposure, clamp, sRGB), .hdr, .pfm (linear) or .exr "
                   "(linear, with albedo, normal, depth and sample-count layers)")
        ->capture_default_str();
    app.add_option("--spp", o.spp,
                   "Samples per pixel: with adaptive sampling (the default) their mean over the "
                   "image; with --noise-target, the most a render takes")
        ->capture_default_str();
    app.add_option("--size", o.size,
                   "Image size WIDTHxHEIGHT (default: the camera's aspect ratio, long side 640)");
    app.add_option("--region", o.region,
                   "Render only the pixels X,Y,W,H of the --size image (origin top-left): a "
                   "W x H output whose pixels are the full render's, bit for bit (its "
                   "denoising, --noise-target and --exposure auto see the crop alone)");
    app.add_option("--camera", o.camera,
                   "The file's camera: index (in node order) or name; default: the first; "
                   "auto: frame the model from the front, above (as a file without cameras "
                   "is)");
    app.add_option("--look-from", o.look_from,
                   "Camera position X,Y,Z (scene units), replacing the camera's; it looks at "
                   "--look-at, or the model's centre");
    app.add_option("--look-at", o.look_at, "The point X,Y,Z the camera looks at");
    app.add_option("--fov", o.fov,
                   "Vertical field of view in degrees (perspective cameras); with the "
                   "auto-framed camera the model still fills the frame");
    app.add_option("--orbit", o.orbit,
                   "Frame the model as --camera auto does, from a direction turned this many "
                   "degrees about the up axis (+y), counter-clockwise seen from above (90: from "
                   "+x, 180: from behind)");
    app.add_option("--scene", o.gltf_scene,
                   "glTF: which of the file's scenes to render (0, 1, ...); default: the "
                   "file's own");
    app.add_option("--variant", o.variant,
                   "glTF: the KHR_materials_variants variant (its name) whose materials to use");
    add_choice(app, "--light-units", o.light_units, kLightUnits,
               "glTF punctual lights: watts (the file's candela and lux / 683, as Blender's "
               "exporter writes them) or photometric (as they are, as web viewers show them)");
    app.add_option("--max-depth", o.max_depth,
                   "Most scattering events per path; -1: the most the integrator allows (1000, "
                   "bdpt 64), paths then ending by Russian roulette (--roulette-depth)")
        ->capture_default_str();
    add_choice(app, "--integrator", o.integrator, kIntegrators,
               "path (unidirectional, MIS), bdpt (bidirectional: paths from the camera and "
               "from the lights joined, for light that reaches the camera through small "
               "bright regions or caustics) or brute (no light sampling: a reference that "
               "point, spot and sun lights cannot light)");
    app.add_flag("--caustic-paths", o.caustic_paths,
                 "Path tracer: trace caustics (light reaching a seen surface through mirrors, "
                 "glass or smooth metal) from the lights and splat them");
    app.add_option("--light-paths", o.light_paths,
                   "bdpt: the fraction of samples that also trace a light subpath, in (0, 1]; "
                   "below 1 a sample costs less, for scenes where light subpaths matter only "
                   "for a few paths (docs/sampling.md)")
        ->capture_default_str();
    app.add_option("--roulette-depth", o.roulette_depth,
                   "Bounces before Russian roulette may end a path (path, brute and bdpt; -1: "
                   "the integrator's default, 3)")
        ->capture_default_str();
    app.add_flag("--all-emitters", o.all_emitters,
                 "Light-sample every emissive triangle of positive power; by default the "
                 "negligible ones (below 1 % of the emitters' mean power, or 100 times dimmer "
                 "than their typical radiance) are left to BSDF sampling (docs/"
                 "materials-and-lights.md)");
    add_choice(app, "--light-choice", o.light_choice, kLightChoices,
               "How a shading point chooses the light it samples: power (by power alone), "
               "bounded (by power times a bound of its contribution there; a light tree "
               "above 16 lights) or auto (bounded above 16 lights, else power)");
    app.add_option("--threads", o.threads, "Worker threads, 0 = all cores")->capture_default_str();
    app.add_option("--seed", o.seed, "Random seed")->capture_default_str();
    app.add_option("--time-limit", o.time_limit,
                   "Stop after this many seconds and write the finished passes (0 = none)")
        ->capture_default_str();
    app.add_option("--noise-target", o.noise_target,
                   "Stop once the image's estimated relative error (the square root of its "
                   "relMSE) is at most this, e.g. 0.02; --spp stays the most taken (0 = none)")
        ->capture_default_str();
    app.add_option("--exposure", o.exposure,
                   "Exposure in stops: the image is scaled by 2^EV; auto: the PNG's log-average "
                   "luminance is put at mid grey 0.18 (linear outputs stay unscaled)")
        ->capture_default_str();
    add_choice(app, "--tonemap", o.tonemap, kToneCurves,
               "PNG tone curve after the exposure: aces (filmic: highlights roll off, mid grey "
               "as clamp shows it), agx (Blender 4's default view: bright saturated lights "
               "pass to white, mid grey as clamp shows it) or clamp (values above 1 cut to "
               "white)");
    app.add_option("--png-bits", o.png_bits, "PNG bits per channel: 8 or 16")
        ->capture_default_str();
    app.add_flag("--transparent-background", o.transparent_background,
                 "PNG with an alpha channel: the share of each pixel's samples that hit the "
                 "model; the sky (--env or the default lighting's) still lights it but is not "
                 "seen behind it");
    app.add_flag("--exr-half", o.exr_half,
                 "EXR beauty, albedo and normal as 16-bit half floats (smaller file; values "
                 "above 65504 are clamped to it, with a warning); default 32-bit float");
    app.add_flag_callback(
           "--denoise", [&o] { o.denoise = true; },
           "Denoise (the default for .png and .exr): PNG, .hdr and .pfm get the denoised image, "
           "EXR a 'denoised' layer beside its unbiased beauty. An AOV-guided filter of our "
           "own; needs --spp 2 or more")
        ->excludes(app.add_flag_callback(
            "--no-denoise", [&o] { o.denoise = false; },
            "Write the noisy, unbiased estimate only (the default for .hdr and .pfm)"));
    app.add_option("--env", o.env,
                   "Equirectangular environment, Radiance .hdr or OpenEXR .exr, lighting the "
                   "scene from every direction (importance-sampled; seen by rays that leave "
                   "the scene); replaces the default lighting");
    app.add_option("--env-strength", o.env_strength, "Scale of the --env radiance")
        ->capture_default_str();
    app.add_option("--env-rotate", o.env_rotate,
                   "Turn the --env environment by this many degrees about the up axis (+y), "
                   "counter-clockwise seen from above")
        ->capture_default_str();
    app.add_flag("--no-default-light", o.no_default_light,
                 "A file without lights of its own (glTF: no punctual light) stays unlit but "
                 "for its emissive surfaces, instead of getting the default studio lighting "
                 "(a grey sky and a key light)");
    add_choice(app, "--diffuse", o.diffuse, kDiffuseModels,
               "Diffuse base of glTF materials: lambert (glTF's) or burley (Blender's "
               "Principled BSDF; brighter rough surfaces at grazing angles)");
    app.add_flag("--solid-transmission", o.solid_transmission,
                 "glTF transmission without KHR_materials_volume (thin-walled by the "
                 "specification) refracts as solid glass through closed meshes, as Blender "
                 "and Cycles show it");
    app.add_flag("-q,--quiet", o.quiet, "No progress bar and no summary");
    app.add_option("--preview", o.preview,
                   "A PNG rewritten with the image so far (tone-mapped as the PNG output) after "
                   "the first pass, then at most once a second, and at the end: watch a long "
                   "render in an image viewer (each write is atomic)");
    app.add_flag("--allow-outside-files", o.allow_outside_files,
                 "Let the scene read buffers, images and MTL files outside its own directory "
                 "tree (absolute paths, '..', symlinks leading out): only for a file you trust");
    apps::add_sampling_options(app, o.sampling);
    app.add_option("--mpi-tile", o.mpi_tile,
                   "Under mpirun: side of the square tiles rank 0 hands out to the ranks")
        ->capture_default_str();
    return apps::run(app, argc, argv, [&] { return job.run([&] { return render_file(o, job); }); });
}
