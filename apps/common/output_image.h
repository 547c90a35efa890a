#pragma once

#include <librt/core/image.h>
#include <librt/core/tone_curve.h>
#include <librt/film/film.h>

#include <string>
#include <vector>

// The one writer of the apps' images: what every app writes goes through write_output, in
// one of two looks (the report's gamma 0.45, or today's display convention).

namespace librt::apps {

/// How write_output encodes an image.
struct OutputLook {
    /// Multiplies the linear image: in .pfm and .hdr files, in PNG before its encoding, and in
    /// the EXR beauty when scale_exr.
    float scale = 1.0f;
    /// PNG: the report's look when > 0 (librt::ToneMap{scale, png_gamma}); 0 is the display
    /// convention: clamped to [0, 1] (NaN to 0) and sRGB-encoded.
    float png_gamma = 0.0f;
    /// Whether an EXR written with the film's layers has its beauty scaled too; else it holds
    /// the radiance as rendered.
    bool scale_exr = true;
    /// EXR colour channels as half floats (values beyond 65504 clamped and warned about on
    /// stderr); else 32-bit float.
    bool exr_half = false;
    /// Display convention PNG: the curve after the exposure (core/tone_curve.h).
    ToneCurve curve = ToneCurve::Clamp;
    /// Display convention PNG: the exposure is auto_exposure_scale of the image shown (its
    /// colour, before alpha), times `scale`; the linear formats keep `scale` alone.
    bool auto_exposure = false;
    /// Display convention PNG: 8 or 16 bits per channel.
    int png_bits = 8;
    /// Display convention PNG: an alpha channel, the film's coverage (the share of each
    /// pixel's camera samples that hit the scene), the colour divided by it (straight alpha).
    /// Needs the film, with AOVs.
    bool alpha = false;
};

/// The report's look at `exposure` (a multiple of kReportExposure): PNG gamma 0.45, .pfm and
/// .hdr scaled, EXR beauty as rendered.
[[nodiscard]] OutputLook report_look(float exposure);

/// The display convention at `scale` (2^EV): PNG clamped and sRGB-encoded, every linear format
/// scaled.
[[nodiscard]] OutputLook display_look(float scale, bool exr_half = false);

/// The display image: exposure `scale`, clamp to [0, 1] (NaN -> 0), sRGB-encoded.
[[nodiscard]] Image display_image(const Image& linear, float scale);

/// Each pixel's coverage: the share of its camera samples whose ray hit the scene (AovPixel
/// hits / FilmPixel samples; 0 for a pixel of no samples). Throws librt::Error for a film
/// without AOVs.
[[nodiscard]] std::vector<float> coverage(const Film& film);

/// Writes `beauty` to `path` by its extension (case-insensitive), in `look`: .exr with the
/// other layers of `film` when one is given (albedo, normal, depth, sample count; else the
/// beauty alone, scaled) and `denoised` as its denoised layer when given (scaled like the
/// beauty), .png tone-mapped (with an alpha channel from `film` when look.alpha), .pfm and
/// .hdr linear. Throws librt::Error naming the path.
void write_output(const std::string& path, const Image& beauty, const OutputLook& look,
                  const Film* film = nullptr, const Image* denoised = nullptr);

}  // namespace librt::apps
