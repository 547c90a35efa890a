#pragma once

#include <librt/core/image.h>
#include <librt/export.h>

#include <glm/vec3.hpp>

#include <string>

// How a display image is made from scene-linear radiance for an 8- or 16-bit file: an
// exposure, a tone curve that brings [0, inf) into [0, 1], then the sRGB encoding. The
// report's look (core/tone_map.h: clamp, gamma 0.45) is separate and unchanged.

namespace librt {

/// The curve taking exposed scene-linear RGB to display-linear RGB in [0, 1].
enum class ToneCurve {
    /// Each channel clamped to [0, 1]: exact below 1, highlights clipped (flat white).
    Clamp,
    /// A filmic curve: the ACES reference rendering and sRGB output transforms (RRT + ODT) in
    /// Stephen Hill's fitted form (2016; matrices into and out of the ACES working space,
    /// a rational fit of the tone scale), preceded by a gain that shows mid grey 0.18 as
    /// Clamp shows it. Highlights roll off and saturated lights desaturate toward white as
    /// film does, where Clamp cuts them flat.
    Aces,
    /// Troy Sobotka's AgX, Blender 4's default view, as its published description builds it:
    /// an inset matrix pulls every channel toward a weighted grey (purity attenuated before
    /// the curve, so bright saturated lights pass to white without skewing in hue), a log2
    /// encoding over a fixed range of 16.5 stops around mid grey (10 below, 6.5 above), a
    /// sigmoid contrast curve per channel (slope 2.4 at mid grey, toe and shoulder of power
    /// 1.5), decoded with the 2.4 exponent, then the outset matrix (the inset's inverse)
    /// restores the purity of the mid tones. Mid grey 0.18 is shown as Clamp shows it;
    /// scene values 10 stops or more below it are black, 6.5 stops or more above it white.
    Agx,
};

/// The curve's name as the apps spell it: "clamp", "aces", "agx".
[[nodiscard]] LIBRT_API std::string to_string(ToneCurve curve);

/// Display-linear RGB in [0, 1] of exposed scene-linear `rgb` through `curve`. NaN and
/// negative inputs count as 0; +inf as the curve's white.
[[nodiscard]] LIBRT_API glm::vec3 apply_tone_curve(ToneCurve curve, const glm::vec3& rgb);

/// IEC 61966-2-1 sRGB encoding of a display-linear value in [0, 1]: 12.92 c below
/// 0.0031308, else 1.055 c^(1/2.4) - 0.055.
[[nodiscard]] LIBRT_API float srgb_encode(float c);

/// The display image of `linear`: each pixel times `scale`, through `curve`, sRGB-encoded:
/// values in [0, 1], ready to quantise. Throws librt::Error for a scale that is not finite
/// and >= 0.
[[nodiscard]] LIBRT_API Image display_encode(const Image& linear, float scale, ToneCurve curve);

/// The exposure scale that puts the image's log-average luminance (Rec. 709 Y, the geometric
/// mean of 1e-4 + Y over its finite pixels) at mid grey 0.18: Reinhard et al. 2002's "key".
/// Clamped to [2^-20, 2^20]; 1 for an image with no finite pixel.
[[nodiscard]] LIBRT_API float auto_exposure_scale(const Image& linear);

}  // namespace librt
