#include <librt/core/error.h>
#include <librt/core/tone_curve.h>

#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>

namespace librt {

namespace {

/// Hill's fit of the ACES tone scale (RRT + sRGB ODT) on one channel of the working space.
float aces_tone_scale(float v) {
    return (v * (v + 0.0245786f) - 0.000090537f) / (v * (0.983729f * v + 0.4329510f) + 0.238081f);
}

/// sRGB (linear, D65) into the ACES working space with the RRT's saturation folded in, and
/// back out with the ODT's: Hill's published matrices (rows below; glm is column-major, so
/// each is transposed on use). Each row sums to 1: greys stay grey.
const glm::mat3 kAcesIn = glm::transpose(glm::mat3(0.59719f, 0.35458f, 0.04823f,  //
                                                   0.07600f, 0.90834f, 0.01566f,  //
                                                   0.02840f, 0.13383f, 0.83777f));
const glm::mat3 kAcesOut = glm::transpose(glm::mat3(1.60475f, -0.53108f, -0.07367f,  //
                                                    -0.10208f, 1.10813f, -0.00605f,  //
                                                    -0.00327f, -0.07276f, 1.07602f));

/// The input gain g with aces_tone_scale(0.18 g) = 0.18: mid grey shown as Clamp shows it.
/// The root of a quadratic (the fit is a ratio of quadratics), computed once.
float aces_mid_grey_gain() {
    // (v^2 + b v - c) = y (a v^2 + d v + e) with y = 0.18, solved for v > 0.
    const double y = 0.18, a = 1.0 - y * 0.983729, b = 0.0245786 - y * 0.4329510,
                 c = 0.000090537 + y * 0.238081;
    const double v = (-b + std::sqrt(b * b + 4.0 * a * c)) / (2.0 * a);
    return float(v / y);
}

float finite_or_zero(float x) { return std::isnan(x) || x < 0.0f ? 0.0f : x; }

}  // namespace

std::string to_string(ToneCurve curve) {
    switch (curve) {
        case ToneCurve::Clamp:
            return "clamp";
        case ToneCurve::Aces:
            return "aces";
    }
    return "?";
}

glm::vec3 apply_tone_curve(ToneCurve curve, const glm::vec3& rgb) {
    glm::vec3 c(finite_or_zero(rgb.x), finite_or_zero(rgb.y), finite_or_zero(rgb.z));
    if (curve == ToneCurve::Aces) {
        static const float gain = aces_mid_grey_gain();
        // An infinite channel would give inf - inf in the matrix: held at a value far past
        // the curve's shoulder (the fit is within 1e-6 of its limit there).
        c = glm::min(c * gain, glm::vec3(1e6f));
        c = kAcesIn * c;
        c = glm::vec3(aces_tone_scale(c.x), aces_tone_scale(c.y), aces_tone_scale(c.z));
        c = kAcesOut * c;
    }
    return glm::clamp(c, glm::vec3(0.0f), glm::vec3(1.0f));
}

float srgb_encode(float c) {
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

Image display_encode(const Image& linear, float scale, ToneCurve curve) {
    if (!(scale >= 0.0f) || !std::isfinite(scale))
        throw Error("display_encode: scale = " + std::to_string(scale) +
                    ": must be finite and >= 0");
    Image out = linear;
    for (glm::vec3& p : out.pixels) {
        const glm::vec3 d = apply_tone_curve(curve, scale * p);
        p = glm::vec3(srgb_encode(d.x), srgb_encode(d.y), srgb_encode(d.z));
    }
    return out;
}

float auto_exposure_scale(const Image& linear) {
    double log_sum = 0.0;
    std::size_t n = 0;
    for (const glm::vec3& p : linear.pixels) {
        // Rec. 709 / sRGB luminance.
        const double y = 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z;
        if (!std::isfinite(y)) continue;
        log_sum += std::log(1e-4 + std::max(0.0, y));
        ++n;
    }
    if (n == 0) return 1.0f;
    const double key = 0.18 / std::exp(log_sum / double(n));
    return float(std::clamp(key, std::ldexp(1.0, -20), std::ldexp(1.0, 20)));
}

}  // namespace librt
