#include "output_image.h"

#include <librt/core/error.h>
#include <librt/core/tone_curve.h>
#include <librt/core/tone_map.h>
#include <librt/io/exr.h>
#include <librt/io/file_extension.h>
#include <librt/io/image_io.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>

namespace librt::apps {

OutputLook report_look(float exposure) {
    OutputLook look;
    look.scale = exposure * kReportExposure;
    look.png_gamma = 0.45f;
    look.scale_exr = false;
    return look;
}

OutputLook display_look(float scale, bool exr_half) {
    OutputLook look;
    look.scale = scale;
    look.exr_half = exr_half;
    return look;
}

Image display_image(const Image& linear, float scale) {
    return display_encode(linear, scale, ToneCurve::Clamp);
}

std::vector<float> coverage(const Film& film) {
    if (!film.has_aovs()) throw Error("coverage: the film keeps no AOVs");
    std::vector<float> alpha(film.pixels.size(), 0.0f);
    for (std::size_t i = 0; i < alpha.size(); ++i) {
        const std::uint32_t n = film.pixels[i].samples;
        if (n > 0) alpha[i] = float(double(film.aovs[i].hits) / double(n));
    }
    return alpha;
}

namespace {

/// The display-convention PNG: `beauty` over the alpha of `film` when asked (the colour made
/// straight: divided by the coverage), exposed, through the curve, 8 or 16 bits.
void write_display(const std::string& path, const Image& beauty, const OutputLook& look,
                   const Film* film) {
    std::vector<float> alpha;
    Image colour = beauty;
    if (look.alpha) {
        if (film == nullptr) throw Error("cannot write '" + path + "': alpha needs the film");
        alpha = coverage(*film);
        for (std::size_t i = 0; i < alpha.size(); ++i)
            colour.pixels[i] = alpha[i] > 0.0f ? colour.pixels[i] / alpha[i] : glm::vec3(0.0f);
    }
    const float scale = look.auto_exposure ? look.scale * auto_exposure_scale(colour) : look.scale;
    // display_encode in place: one copy of the image, as writer_bytes_per_pixel counts.
    for (glm::vec3& p : colour.pixels) {
        const glm::vec3 d = apply_tone_curve(look.curve, scale * p);
        p = glm::vec3(srgb_encode(d.x), srgb_encode(d.y), srgb_encode(d.z));
    }
    write_display_png(path, colour, look.png_bits, look.alpha ? &alpha : nullptr);
}

}  // namespace

void write_output(const std::string& path, const Image& beauty, const OutputLook& look,
                  const Film* film, const Image* denoised) {
    const std::string ext = lower_extension(path);
    if (ext == ".exr" && film != nullptr) {
        ImageLayers layers = resolve_layers(*film);
        layers.beauty = beauty;
        if (denoised != nullptr) layers.denoised = *denoised;
        if (look.scale_exr) {
            for (glm::vec3& p : layers.beauty.pixels) p *= look.scale;
            for (glm::vec3& p : layers.denoised.pixels) p *= look.scale;
        }
        ExrWriteOptions options;
        options.colour = look.exr_half ? ExrPixelType::Half : ExrPixelType::Float;
        for (const std::string& w : write_exr(path, layers, options).warnings)
            std::cerr << "warning: " << w << '\n';
    } else if (ext == ".png" && look.png_gamma == 0.0f) {
        const bool plain = look.curve == ToneCurve::Clamp && !look.auto_exposure &&
                           look.png_bits == 8 && !look.alpha;
        // The plain look keeps stb's encoder (the bytes of every earlier image).
        if (plain)
            write_png(path, display_image(beauty, look.scale), ToneMap{1.0f, 1.0f});
        else
            write_display(path, beauty, look, film);
    } else {
        // write_image: PNG through the tone map, the linear formats times its exposure.
        write_image(path, beauty, ToneMap{look.scale, ext == ".png" ? look.png_gamma : 1.0f});
    }
}

}  // namespace librt::apps
