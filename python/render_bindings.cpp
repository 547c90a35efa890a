// librt.load and librt.render: scene files as rt_render loads them, and renders to NumPy
// arrays with progress, cancellation (a callback or Ctrl-C) and the GIL released.

#include "bindings.h"

#include <librt/core/error.h>
#include <librt/core/image_layers.h>
#include <librt/film/film.h>
#include <librt/film/pixel_region.h>
#include <librt/integrator/bdpt.h>
#include <librt/integrator/integrators.h>
#include <librt/light/light_sampler.h>
#include <librt/loader/scene_file.h>
#include <librt/render/adaptive_sampling.h>
#include <librt/render/denoiser.h>
#include <librt/render/renderer.h>
#include <librt/sampling/filter.h>

#include <Python.h>

#include <array>
#include <atomic>
#include <bit>
#include <optional>
#include <tuple>
#include <utility>

namespace librt::python {

namespace {

py::tuple load(const std::string& path, const std::string& camera, const py::object& size,
               bool default_lighting, bool allow_outside_files, bool all_emitters) {
    SceneFileOptions options;
    options.camera = camera;
    options.default_lighting = default_lighting;
    options.allow_outside_files = allow_outside_files;
    if (!size.is_none()) {
        const auto wh = size.cast<std::pair<int, int>>();
        options.width = wh.first;
        options.height = wh.second;
    }
    auto scene = std::make_unique<PyScene>();
    CameraSettings settings;
    {
        py::gil_scoped_release release;
        LoadedScene loaded = load_scene_file(path, options);
        scene->scene = std::move(loaded.scene);
        // rt_render's --all-emitters: every emissive triangle of positive power a light.
        if (all_emitters) scene->scene.set_triangle_light_settings({0.0f, 0.0f});
        scene->warnings = std::move(loaded.warnings);
        scene->lighting_note = std::move(loaded.lighting_note);
        settings = loaded.camera;
    }
    settings.pixel_jitter = PixelJitter::Gaussian;  // anti-aliasing, as rt_render
    return py::make_tuple(py::cast(std::move(scene)), py::cast(settings));
}

/// The integrator `name` as rt_render's --integrator makes it (its defaults: Russian
/// roulette, the light choice by bound above LightSampler::kMaxBounded lights).
std::unique_ptr<Integrator> make_integrator(const std::string& name, int max_depth,
                                            std::size_t light_count) {
    if (name == "path") {
        PathTracerSettings pt;
        if (max_depth >= 0) pt.max_depth = max_depth;
        pt.light_choice =
            light_count > LightSampler::kMaxBounded ? LightChoice::Bounded : LightChoice::Power;
        return std::make_unique<PathTracer>(pt);
    }
    if (name == "bdpt") {
        BidirectionalSettings bd;
        bd.max_depth = max_depth >= 0 ? max_depth : BidirectionalSettings::kMaxDepth;
        return std::make_unique<BidirectionalPathTracer>(bd);
    }
    if (name == "brute") {
        PathTracerSettings brute;
        if (max_depth >= 0) brute.max_depth = max_depth;
        return std::make_unique<BruteForcePathTracer>(brute);
    }
    throw Error("integrator: '" + name + "' is none of path, bdpt, brute");
}

SamplerKind sampler_of(const std::string& name) {
    if (name == "sobol") return SamplerKind::Sobol;
    if (name == "independent") return SamplerKind::Independent;
    throw Error("sampler: '" + name + "' is neither sobol nor independent");
}

/// rt_render's --region X,Y,W,H as a (x, y, width, height) tuple; None: the whole image.
/// Whether it lies within the image, render() checks (librt::Error naming it).
PixelRegion region_of(const py::object& region) {
    if (region.is_none()) return {};
    const std::string bad = "region: " + std::string(py::str(py::repr(region))) +
                            " must be (x, y, width, height): whole numbers, x and y >= 0, "
                            "width and height >= 1 (pixels, origin top-left)";
    std::array<long long, 4> v{};
    try {
        const auto t = region.cast<std::tuple<long long, long long, long long, long long>>();
        v = {std::get<0>(t), std::get<1>(t), std::get<2>(t), std::get<3>(t)};
    } catch (const py::cast_error&) {
        throw Error(bad);
    }
    constexpr long long kMax = 65536;
    if (v[0] < 0 || v[1] < 0 || v[2] < 1 || v[3] < 1 || v[0] + v[2] > kMax || v[1] + v[3] > kMax)
        throw Error(bad);
    return {int(v[0]), int(v[1]), int(v[0] + v[2]), int(v[1] + v[3])};
}

FilterKind filter_of(const std::string& name) {
    static constexpr std::pair<const char*, FilterKind> kNames[] = {
        {"box", FilterKind::Box},
        {"tent", FilterKind::Tent},
        {"gaussian", FilterKind::Gaussian},
        {"mitchell", FilterKind::Mitchell},
        {"blackman-harris", FilterKind::BlackmanHarris},
        {"smallpt", FilterKind::Smallpt}};
    for (const auto& [n, k] : kNames)
        if (name == n) return k;
    throw Error("filter: '" + name +
                "' is none of box, tent, gaussian, mitchell, blackman-harris, smallpt");
}

/// What the progress hook shares with the render call: the Python callable, the cancel
/// flag the renderer polls, and the Python error (Ctrl-C's KeyboardInterrupt, or what the
/// callable raised) to raise once the render has returned.
struct ProgressState {
    py::object callable;
    std::atomic<bool> cancel{false};
    bool stopped_by_callable = false;
    std::optional<py::error_already_set> error;
};

/// The renderer's progress callback (called on the thread that called render, about ten
/// times a second): takes the GIL, checks for Ctrl-C (PyErr_CheckSignals runs Python's
/// SIGINT handler, which raises KeyboardInterrupt) and calls the Python callable. Either
/// stops the render through the cancel flag; the exception is raised after it returns.
ProgressCallback progress_hook(ProgressState& state) {
    return [&state](const RenderProgress& p) {
        if (state.cancel.load()) return;
        py::gil_scoped_acquire gil;
        try {
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            if (state.callable && !state.callable.is_none()) {
                const py::object r = state.callable(p);
                if (r.ptr() == Py_False) {
                    state.stopped_by_callable = true;
                    state.cancel = true;
                }
            }
        } catch (py::error_already_set& e) {
            state.error = std::move(e);
            state.cancel = true;
        }
    };
}

py::object render(const py::object& scene_object, CameraSettings settings, int spp,
                  const py::object& size, const py::object& integrator_arg,
                  const std::string& sampler, bool adaptive, int threads, std::uint64_t seed,
                  int max_depth, const py::object& filter, bool aovs, const py::object& progress,
                  const py::object& region_arg) {
    if (!size.is_none()) {
        const auto wh = size.cast<std::pair<int, int>>();
        settings.width = wh.first;
        settings.height = wh.second;
    }
    if (!filter.is_none()) {
        settings.pixel_jitter = PixelJitter::Filter;
        settings.pixel_filter = default_filter_settings(filter_of(filter.cast<std::string>()));
    }
    PyScene& self = scene_object.cast<PyScene&>();
    const Camera camera(settings);
    RenderSettings rs;
    rs.samples_per_pixel = spp;
    rs.threads = threads;
    rs.seed = seed;
    rs.sampler = sampler_of(sampler);
    rs.adaptive.enabled = adaptive;
    rs.region = region_of(region_arg);
    validate(rs);
    self.ensure_committed();
    // A string names one of librt's integrators; anything else is a librt.Integrator.
    const std::unique_ptr<Integrator> integrator =
        py::isinstance<py::str>(integrator_arg)
            ? make_integrator(integrator_arg.cast<std::string>(), max_depth,
                              self.scene.lights().size())
            : python_integrator(integrator_arg, scene_object);

    // Declared before the GIL is released, so that the Python error is destroyed with it held.
    ProgressState state;
    state.callable = progress;
    rs.progress = progress_hook(state);
    rs.cancel = &state.cancel;
    Image image;
    Film film;
    Film half;
    std::uint32_t half_at = 0;
    RenderStats stats;
    {
        const SceneInUse in_use(self);
        py::gil_scoped_release release;
        if (!aovs) {
            image = render(self.scene, camera, *integrator, rs, &stats);
        } else {
            // As rt_render renders for an EXR: passes of one sample, the film kept at half
            // the samples (half the pilot with adaptive sampling) for the denoiser, which
            // compares the two halves. The image is render()'s bit for bit.
            ProgressiveSettings ps;
            ps.render = rs;
            ps.pass_samples = 1;
            ps.aovs = true;
            const std::uint32_t pilot =
                adaptive ? adaptive_pilot_samples(rs.adaptive, std::uint32_t(spp)) : 0;
            const std::uint32_t half_level = pilot > 0 ? pilot / 2 : std::uint32_t(spp / 2);
            ps.pass_done = [&](const Film& f, std::uint32_t level) {
                if (level == half_level) {
                    half = f;
                    half_at = level;
                }
            };
            stats = render_progressive(self.scene, camera, *integrator, film, ps, &image);
        }
    }
    if (state.error) throw std::move(*state.error);
    if (state.stopped_by_callable || stats.cancelled) {
        PyErr_SetString(cancelled_type().ptr(), "render cancelled by the progress callback");
        throw py::error_already_set();
    }
    // A region: its pixels, as images and films of its own size (as rt_render writes them).
    if (!rs.region.whole()) {
        image = crop(image, rs.region);
        if (aovs) {
            film = crop(film, rs.region);
            if (half_at > 0) half = crop(half, rs.region);
        }
    }
    if (!aovs) return image_to_array(std::move(image));

    py::dict out;
    ImageLayers layers = resolve_layers(film);
    const int w = image.width;
    const int h = image.height;
    if (half_at > 0 && half_at < stats.samples_per_pixel) {
        py::gil_scoped_release release;
        DenoiserSettings ds;
        ds.threads = threads;
        layers.denoised = denoise(denoiser_input(half, film), ds);
    }
    out["beauty"] = image_to_array(std::move(image));
    out["albedo"] = image_to_array(std::move(layers.albedo));
    out["normal"] = image_to_array(std::move(layers.normal));
    out["depth"] = plane_to_array(std::move(layers.depth), w, h);
    out["sample_count"] = plane_to_array(std::move(layers.sample_count), w, h);
    if (!layers.denoised.pixels.empty())
        out["denoised"] = image_to_array(std::move(layers.denoised));
    return out;
}

}  // namespace

void bind_render(py::module_& m) {
    m.def("load", &load, py::arg("path"), py::arg("camera") = "", py::arg("size") = py::none(),
          py::arg("default_lighting") = true, py::arg("allow_outside_files") = false,
          py::arg("all_emitters") = false,
          "Loads a glTF (.gltf, .glb) or OBJ file as rt_render does: returns (scene, camera). "
          "camera: the file's camera by index or name ('' the first, 'auto' framing the "
          "model); size: (width, height), default the camera's aspect, long side 640; "
          "all_emitters: light-sample every emissive triangle of positive power (rt_render's "
          "--all-emitters; scene.set_triangle_light_settings). "
          "Raises librt.Error naming the file and the JSON path (or line).");
    py::class_<RenderProgress>(m, "Progress",
                               "Where a render is (the progress callback's argument)")
        .def_readonly("fraction", &RenderProgress::fraction)
        .def_readonly("seconds", &RenderProgress::seconds)
        .def_readonly("passes", &RenderProgress::passes)
        .def_readonly("samples_per_pixel", &RenderProgress::samples_per_pixel);
    m.def("render", &render, py::arg("scene"), py::arg("camera"), py::arg("spp") = 16,
          py::arg("size") = py::none(), py::arg("integrator") = "path",
          py::arg("sampler") = "sobol", py::arg("adaptive") = true, py::arg("threads") = 0,
          py::arg("seed") = 0, py::arg("max_depth") = -1, py::arg("filter") = py::none(),
          py::arg("aovs") = false, py::arg("progress") = py::none(), py::arg("region") = py::none(),
          "Renders the scene through the camera with rt_render's defaults; returns a float32 "
          "(H, W, 3) array of linear radiance, or with aovs=True a dict of arrays: beauty, "
          "albedo, normal, depth, sample_count and (spp >= 2) denoised. progress: a callable "
          "taking a librt.Progress about ten times a second; returning False cancels "
          "(librt.Cancelled), raising stops the render and propagates. Ctrl-C stops it with "
          "KeyboardInterrupt. The GIL is released while rendering. integrator: 'path', "
          "'bdpt', 'brute' or a librt.Integrator (Python, slow). region: (x, y, width, height) "
          "renders those pixels alone (rt_render's --region) and returns them as (height, "
          "width) arrays, each pixel the full render's bit for bit.");
}

}  // namespace librt::python
