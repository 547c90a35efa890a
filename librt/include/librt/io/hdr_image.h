#pragma once

#include <librt/export.h>
#include <librt/light/environment_light.h>

#include <filesystem>

namespace librt {

/// Loads a Radiance .hdr (RGBE) file as linear radiance, rows top to bottom, for
/// EnvironmentLight::from_image. Throws librt::Error naming the file for a missing,
/// unreadable, oversized (more than 2^26 pixels) or undecodable file, one whose header
/// claims more pixels than its data can hold or whose data ends early (both checked before
/// decoding), or for a pixel that is not finite.
[[nodiscard]] LIBRT_API EnvironmentImage load_hdr_image(const std::filesystem::path& path);

}  // namespace librt
