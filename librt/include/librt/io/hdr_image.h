#pragma once

#include <librt/export.h>
#include <librt/light/environment_light.h>

#include <filesystem>

namespace librt {

/// Loads a Radiance .hdr (RGBE) file as linear radiance, rows top to bottom, for
/// EnvironmentLight::from_image. Throws librt::Error naming the file for a missing,
/// unreadable, oversized (more than 2^26 pixels) or undecodable file, one whose header
/// claims more pixels than its data can hold or whose data ends early, one whose decoding
/// would take more than 16 times its bytes plus 256 MiB (24 bytes a pixel; all checked
/// before decoding), for a pixel that is not finite, or when memory runs out.
[[nodiscard]] LIBRT_API EnvironmentImage load_hdr_image(const std::filesystem::path& path);

/// Loads an equirectangular environment by its extension (case-insensitive): .hdr through
/// load_hdr_image, .exr through read_exr (io/exr.h: its R, G, B channels, half or float, of a
/// single-part scan-line file). Throws librt::Error naming the file for any other extension,
/// the readers' errors, or a pixel that is not finite or is negative (its position named).
[[nodiscard]] LIBRT_API EnvironmentImage load_environment_image(const std::filesystem::path& path);

}  // namespace librt
