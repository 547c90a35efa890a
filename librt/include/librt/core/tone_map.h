#pragma once

#include <librt/core/image.h>
#include <librt/export.h>

#include <cstdint>
#include <vector>

namespace librt {

/// Scale that maps the report's radiance units to 8 bits the way the report did:
/// min(255, L^0.45) = 255 * min(1, kReportExposure * L)^0.45, i.e. 255^(-1/0.45).
inline constexpr float kReportExposure = 4.48882765e-06f;

/// Linear radiance to display values: v = 255 * clamp(exposure * L, 0, 1)^gamma.
struct ToneMap {
    float exposure = 1.0f;  ///< linear scale applied before clamping (finite, >= 0)
    float gamma = 0.45f;    ///< exponent after clamping, the report's 0.45 (finite, > 0)
};

/// Throws librt::Error naming the parameter when exposure or gamma is out of range.
LIBRT_API void validate(const ToneMap& tone_map);

/// One channel: 255 * clamp(exposure * L, 0, 1)^gamma, rounded to nearest; NaN gives 0.
/// Does not validate `tone_map`.
[[nodiscard]] LIBRT_API std::uint8_t tone_map_channel(float radiance, const ToneMap& tone_map);

/// The whole image as 8-bit RGB, width * height * 3 bytes, top row first.
/// Validates `tone_map` first.
[[nodiscard]] LIBRT_API std::vector<std::uint8_t> to_rgb8(const Image& image,
                                                          const ToneMap& tone_map);

}  // namespace librt
