#include "output_image.h"

#include <librt/core/tone_map.h>
#include <librt/io/exr.h>
#include <librt/io/file_extension.h>
#include <librt/io/image_io.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>

namespace librt::apps {

namespace {

/// IEC 61966-2-1 sRGB encoding of a linear value in [0, 1]: 12.92 c below 0.0031308, else
/// 1.055 c^(1/2.4) - 0.055.
float srgb_encode(float c) {
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

}  // namespace

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
    Image out = linear;
    for (glm::vec3& p : out.pixels) {
        for (int c = 0; c < 3; ++c) {
            const float v = scale * p[c];
            p[c] = srgb_encode(v > 0.0f ? std::min(v, 1.0f) : 0.0f);
        }
    }
    return out;
}

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
        write_png(path, display_image(beauty, look.scale), ToneMap{1.0f, 1.0f});
    } else {
        // write_image: PNG through the tone map, the linear formats times its exposure.
        write_image(path, beauty, ToneMap{look.scale, ext == ".png" ? look.png_gamma : 1.0f});
    }
}

}  // namespace librt::apps
