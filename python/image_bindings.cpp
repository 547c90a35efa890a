// Images between NumPy and librt: the zero-copy view of a rendered image, reading and
// writing image files (with EXR layers) and the report's tone map.

#include "bindings.h"

#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/core/image_layers.h>
#include <librt/core/tone_curve.h>
#include <librt/core/tone_map.h>
#include <librt/io/exr.h>
#include <librt/io/hdr_image.h>
#include <librt/io/image_io.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>

namespace librt::python {

py::array_t<float> image_to_array(Image image) {
    auto* owned = new Image(std::move(image));
    const py::capsule owner(owned, [](void* p) { delete static_cast<Image*>(p); });
    const auto h = static_cast<py::ssize_t>(owned->height);
    const auto w = static_cast<py::ssize_t>(owned->width);
    const auto f = static_cast<py::ssize_t>(sizeof(float));
    static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
    return py::array_t<float>({h, w, py::ssize_t{3}}, {w * 3 * f, 3 * f, f},
                              reinterpret_cast<const float*>(owned->pixels.data()), owner);
}

py::array_t<float> plane_to_array(std::vector<float> values, int width, int height) {
    auto* owned = new std::vector<float>(std::move(values));
    const py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<float>*>(p); });
    if (owned->empty()) return py::array_t<float>(py::ssize_t{0});
    const auto f = static_cast<py::ssize_t>(sizeof(float));
    return py::array_t<float>({py::ssize_t{height}, py::ssize_t{width}},
                              {py::ssize_t{width} * f, f}, owned->data(), owner);
}

Image array_to_image(const py::array& array, const char* what) {
    const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(array);
    if (!a || (a.ndim() != 3 && a.ndim() != 2) || (a.ndim() == 3 && a.shape(2) != 3))
        throw Error(std::string(what) + ": expected a float array of shape (H, W, 3) or (H, W)");
    check_image_size(a.shape(1), a.shape(0));
    Image image;
    image.width = static_cast<int>(a.shape(1));
    image.height = static_cast<int>(a.shape(0));
    image.pixels.resize(static_cast<std::size_t>(a.shape(0) * a.shape(1)));
    if (a.ndim() == 3) {
        std::memcpy(image.pixels.data(), a.data(), image.pixels.size() * sizeof(glm::vec3));
    } else {
        for (std::size_t i = 0; i < image.pixels.size(); ++i)
            image.pixels[i] = glm::vec3(a.data()[i]);
    }
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        if (!finite(image.pixels[i]))
            throw Error(std::string(what) + ": pixel (" +
                        std::to_string(i % std::size_t(image.width)) + ", " +
                        std::to_string(i / std::size_t(image.width)) + ") is not finite");
    }
    return image;
}

namespace {

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

/// A (H, W) float plane copied out of an array, checked against the beauty's size.
std::vector<float> plane_of(const py::handle& value, const Image& beauty, const char* what) {
    const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
    if (!a || a.ndim() != 2 || a.shape(0) != beauty.height || a.shape(1) != beauty.width)
        throw Error(std::string("layers['") + what + "']: expected a float array of shape (" +
                    std::to_string(beauty.height) + ", " + std::to_string(beauty.width) + ")");
    return {a.data(), a.data() + a.size()};
}

/// rt_render's --tonemap name as a ToneCurve.
ToneCurve curve_of(const std::string& name) {
    for (const ToneCurve c : {ToneCurve::Clamp, ToneCurve::Aces, ToneCurve::Agx})
        if (name == to_string(c)) return c;
    throw Error("curve: '" + name + "' is none of clamp, aces, agx");
}

/// The gamma of the report's look, refused with a display curve (which encodes sRGB).
float report_gamma(const py::object& gamma, const py::object& curve) {
    if (curve.is_none()) return gamma.is_none() ? 0.45f : gamma.cast<float>();
    if (!gamma.is_none())
        throw Error("gamma: applies to the report's look (curve=None) only; curve='" +
                    curve.cast<std::string>() + "' encodes sRGB");
    return 0.0f;
}

void write(const std::string& path, const py::array& image, const py::object& layers,
           float exposure, const py::object& gamma_arg, bool half, const py::object& curve) {
    const float gamma = report_gamma(gamma_arg, curve);
    ImageLayers out;
    out.beauty = array_to_image(image, "image");
    const std::string ext = lower_extension(path);
    if (!curve.is_none() && ext != ".png")
        throw Error(path + ": curve applies to .png only (the other formats stay linear)");
    if (!layers.is_none()) {
        if (ext != ".exr") throw Error(path + ": layers need an .exr file");
        for (const auto& [key, value] : layers.cast<py::dict>()) {
            const std::string k = key.cast<std::string>();
            const py::array arr = py::array::ensure(value);
            if (k == "albedo")
                out.albedo = array_to_image(arr, "layers['albedo']");
            else if (k == "normal")
                out.normal = array_to_image(arr, "layers['normal']");
            else if (k == "denoised")
                out.denoised = array_to_image(arr, "layers['denoised']");
            else if (k == "depth")
                out.depth = plane_of(value, out.beauty, "depth");
            else if (k == "sample_count")
                out.sample_count = plane_of(value, out.beauty, "sample_count");
            else if (k != "beauty")
                throw Error("layers: '" + k +
                            "' is none of albedo, normal, depth, sample_count, denoised");
        }
    }
    py::gil_scoped_release release;
    if (ext == ".exr") {
        for (glm::vec3& p : out.beauty.pixels) p *= exposure;
        ExrWriteOptions options;
        options.colour = half ? ExrPixelType::Half : ExrPixelType::Float;
        (void)write_exr(path, out, options);
    } else if (!curve.is_none() && ext == ".png") {
        // rt_render's display convention: exposure, the curve, sRGB, 8 bits.
        write_display_png(path,
                          display_encode(out.beauty, exposure, curve_of(curve.cast<std::string>())),
                          8, nullptr);
    } else {
        write_image(path, out.beauty, ToneMap{exposure, gamma});
    }
}

py::object read(const std::string& path, bool layers) {
    const std::string ext = lower_extension(path);
    if (ext == ".pfm") {
        Image image;
        {
            py::gil_scoped_release release;
            image = read_pfm(path);
        }
        return image_to_array(std::move(image));
    }
    if (ext == ".hdr") {
        EnvironmentImage env;
        {
            py::gil_scoped_release release;
            env = load_hdr_image(path);
        }
        Image image;
        image.width = env.width;
        image.height = env.height;
        image.pixels = std::move(env.pixels);
        return image_to_array(std::move(image));
    }
    if (ext == ".exr") {
        ImageLayers l;
        {
            py::gil_scoped_release release;
            l = read_exr(path);
        }
        if (!layers) return image_to_array(std::move(l.beauty));
        const int w = l.beauty.width;
        const int h = l.beauty.height;
        py::dict out;
        out["beauty"] = image_to_array(std::move(l.beauty));
        if (!l.albedo.pixels.empty()) out["albedo"] = image_to_array(std::move(l.albedo));
        if (!l.normal.pixels.empty()) out["normal"] = image_to_array(std::move(l.normal));
        if (!l.denoised.pixels.empty()) out["denoised"] = image_to_array(std::move(l.denoised));
        if (!l.depth.empty()) out["depth"] = plane_to_array(std::move(l.depth), w, h);
        if (!l.sample_count.empty())
            out["sample_count"] = plane_to_array(std::move(l.sample_count), w, h);
        return out;
    }
    throw Error(path + ": can read .pfm, .hdr and .exr images");
}

py::array_t<std::uint8_t> tone_map(const py::array& image, float exposure,
                                   const py::object& gamma_arg, const py::object& curve) {
    const float gamma = report_gamma(gamma_arg, curve);
    const Image img = array_to_image(image, "image");
    std::vector<std::uint8_t> rgb;
    if (curve.is_none()) {
        rgb = to_rgb8(img, ToneMap{exposure, gamma});
    } else {
        // As write_display_png quantises: round(255 v) of each display value in [0, 1].
        const Image display = display_encode(img, exposure, curve_of(curve.cast<std::string>()));
        rgb.reserve(display.pixels.size() * 3);
        for (const glm::vec3& p : display.pixels)
            for (int c = 0; c < 3; ++c)
                rgb.push_back(
                    static_cast<std::uint8_t>(std::clamp(p[c], 0.0f, 1.0f) * 255.0f + 0.5f));
    }
    py::array_t<std::uint8_t> out(
        {py::ssize_t{img.height}, py::ssize_t{img.width}, py::ssize_t{3}});
    std::memcpy(out.mutable_data(), rgb.data(), rgb.size());
    return out;
}

}  // namespace

void bind_images(py::module_& m) {
    m.def(
        "write", &write, py::arg("path"), py::arg("image"), py::arg("layers") = py::none(),
        py::arg("exposure") = 1.0f, py::arg("gamma") = py::none(), py::arg("half") = false,
        py::arg("curve") = py::none(),
        "Writes an (H, W, 3) float image by extension: .png tone-mapped (exposure, gamma "
        "0.45: the report's look; or with curve='clamp', 'aces' or 'agx' rt_render's "
        "--tonemap: exposure, the curve, sRGB), "
        ".pfm, .hdr, .exr linear times exposure; .exr takes layers (a dict of albedo, "
        "normal, denoised (H, W, 3) and depth, sample_count (H, W), as render(aovs=True) "
        "returns) and half=True for 16-bit colour. Atomic: the file appears whole or not at all.");
    m.def("read", &read, py::arg("path"), py::arg("layers") = false,
          "Reads a .pfm, .hdr or .exr image as a float32 (H, W, 3) array; an .exr with "
          "layers=True as a dict of its layers");
    m.def("tone_map", &tone_map, py::arg("image"), py::arg("exposure") = 1.0f,
          py::arg("gamma") = py::none(), py::arg("curve") = py::none(),
          "uint8 (H, W, 3): the report's tone map 255 * clamp(exposure * L, 0, 1)^gamma "
          "(gamma 0.45 by default), or with curve='clamp', 'aces' or 'agx' rt_render's "
          "--tonemap: exposure * L through the curve, sRGB-encoded, as its PNG holds it");
}

}  // namespace librt::python
