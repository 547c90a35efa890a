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

// AgX (Troy Sobotka, 2022; Blender 4.0's default view "AgX", whose OCIO configuration
// publishes its parameters). Written from that description: inset, log2 encoding, sigmoid,
// 2.4-exponent decoding, outset.

/// The inset: every channel pulled a fraction a of the way to the grey w . c. Blender's
/// published sRGB-to-AgX inset matrix is, to 3-4 digits, (1 - a) I + a 1 w^T with these a
/// and w (its off-diagonal entries are nearly constant per column: a w_j); in this form
/// the outset, its exact inverse, has the closed form (I - a 1 w^T) / (1 - a) (Sherman-
/// Morrison, as w sums to 1), and both keep greys grey.
constexpr double kAgxInset = 0.2;
constexpr double kAgxGreyWeights[3] = {0.2118, 0.3922, 0.3960};  // sum 1

/// The log2 encoding's range in stops relative to mid grey 0.18: [-10, +6.5].
constexpr double kAgxStopsBelow = 10.0;
constexpr double kAgxStopsAbove = 6.5;
/// The sigmoid's slope at mid grey, and the powers of its toe and shoulder.
constexpr double kAgxSlope = 2.4;
constexpr double kAgxToePower = 1.5;
constexpr double kAgxShoulderPower = 1.5;
/// The exponent decoding the sigmoid's output to display-linear light.
constexpr double kAgxDisplayExponent = 2.4;

/// The sigmoid's limb: t / (1 + t^p)^(1/p), rising from 0 with slope 1 toward 1.
double agx_limb(double t, double p) { return t / std::pow(1.0 + std::pow(t, p), 1.0 / p); }

/// The scale S with S limb(A / S) = B: the limb stretched by S reaches height B where the
/// pivot's tangent reaches height A (A > B), so S = A / ((A / B)^p - 1)^(1/p).
double agx_limb_scale(double a, double b, double p) {
    return a / std::pow(std::pow(a / b, p) - 1.0, 1.0 / p);
}

/// The sigmoid on the log-encoded x in [0, 1]: through the pivot (mid grey's x, its display
/// value encoded with the 2.4 exponent) with slope kAgxSlope on both sides (continuous to the
/// first derivative), a toe down to (0, 0) and a shoulder up to (1, 1).
struct AgxSigmoid {
    double x_pivot = kAgxStopsBelow / (kAgxStopsBelow + kAgxStopsAbove);
    double y_pivot = std::pow(0.18, 1.0 / kAgxDisplayExponent);
    double toe_scale = agx_limb_scale(kAgxSlope * x_pivot, y_pivot, kAgxToePower);
    double shoulder_scale =
        agx_limb_scale(kAgxSlope * (1.0 - x_pivot), 1.0 - y_pivot, kAgxShoulderPower);

    [[nodiscard]] double operator()(double x) const {
        if (x <= 0.0) return 0.0;  // at or below the range: black, exactly
        if (x >= 1.0) return 1.0;
        if (x < x_pivot)
            return y_pivot -
                   toe_scale * agx_limb(kAgxSlope * (x_pivot - x) / toe_scale, kAgxToePower);
        return y_pivot + shoulder_scale * agx_limb(kAgxSlope * (x - x_pivot) / shoulder_scale,
                                                   kAgxShoulderPower);
    }
};

glm::vec3 agx(const glm::vec3& rgb) {
    static const AgxSigmoid sigmoid;
    const double* w = kAgxGreyWeights;
    // Inset (all coefficients >= 0: an infinite channel gives +inf, never inf - inf).
    const double grey_in = w[0] * rgb.x + w[1] * rgb.y + w[2] * rgb.z;
    const double lo = std::log2(0.18) - kAgxStopsBelow;
    double display[3];
    for (int c = 0; c < 3; ++c) {
        const double inset = (1.0 - kAgxInset) * double(rgb[c]) + kAgxInset * grey_in;
        // log2 over [lo, lo + 16.5] mapped to [0, 1] (log2(0) = -inf: black).
        const double x = (std::log2(inset) - lo) / (kAgxStopsBelow + kAgxStopsAbove);
        display[c] = std::pow(sigmoid(std::clamp(x, 0.0, 1.0)), kAgxDisplayExponent);
    }
    // Outset: the inset's inverse, in display-linear light.
    const double grey_out = w[0] * display[0] + w[1] * display[1] + w[2] * display[2];
    glm::vec3 out;
    for (int c = 0; c < 3; ++c)
        out[c] = float((display[c] - kAgxInset * grey_out) / (1.0 - kAgxInset));
    return out;
}

float finite_or_zero(float x) { return std::isnan(x) || x < 0.0f ? 0.0f : x; }

}  // namespace

std::string to_string(ToneCurve curve) {
    switch (curve) {
        case ToneCurve::Clamp:
            return "clamp";
        case ToneCurve::Aces:
            return "aces";
        case ToneCurve::Agx:
            return "agx";
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
    } else if (curve == ToneCurve::Agx) {
        c = agx(c);
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
