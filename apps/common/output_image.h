#pragma once

#include <librt/core/image.h>
#include <librt/film/film.h>

#include <string>

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
};

/// The report's look at `exposure` (a multiple of kReportExposure): PNG gamma 0.45, .pfm and
/// .hdr scaled, EXR beauty as rendered.
[[nodiscard]] OutputLook report_look(float exposure);

/// The display convention at `scale` (2^EV): PNG clamped and sRGB-encoded, every linear format
/// scaled.
[[nodiscard]] OutputLook display_look(float scale, bool exr_half = false);

/// The display image: exposure `scale`, clamp to [0, 1] (NaN -> 0), sRGB-encoded.
[[nodiscard]] Image display_image(const Image& linear, float scale);

/// Writes `beauty` to `path` by its extension (case-insensitive), in `look`: .exr with the
/// other layers of `film` when one is given (albedo, normal, depth, sample count; else the
/// beauty alone, scaled) and `denoised` as its denoised layer when given (scaled like the
/// beauty), .png tone-mapped, .pfm and .hdr linear. Throws librt::Error naming the path.
void write_output(const std::string& path, const Image& beauty, const OutputLook& look,
                  const Film* film = nullptr, const Image* denoised = nullptr);

}  // namespace librt::apps
