#pragma once

#include <librt/core/image_layers.h>
#include <librt/export.h>

#include <cstdint>
#include <filesystem>

// OpenEXR output with the layers external denoisers (Open Image Denoise) and compositors
// (Nuke, Blender) read: linear beauty and AOVs in one scan-line file, ZIP compressed.
// Written through a temporary file renamed into place, like every librt image writer.

namespace librt {

/// Storage of the colour and AOV channels: 16-bit half (what compositors default to; max
/// 65504, larger values become +inf, about 3 significant digits) or 32-bit float.
enum class ExrPixelType : std::uint8_t {
    Half,   ///< 16-bit IEEE half
    Float,  ///< 32-bit IEEE float, values written bit for bit
};

/// Writes `layers` as a single-part scan-line OpenEXR file (tinyexr, ZIP compression).
/// Channel names: beauty R, G, B; albedo.R/G/B; normal.X/Y/Z; depth Z (the OpenEXR name
/// for depth); sample_count. Depth and the sample count are always 32-bit float (exact
/// counts up to 2^24), whatever `type` says.
/// Throws librt::Error naming the file and the layer when a layer's size does not match
/// the beauty's, a value is NaN, or the file cannot be written; the target is then left
/// untouched (no partial file, no stray temporary).
LIBRT_API void write_exr(const std::filesystem::path& path, const ImageLayers& layers,
                         ExrPixelType type = ExrPixelType::Half);

/// Reads the layers write_exr writes (half channels are widened to float); channels it
/// does not know are ignored, and a layer is returned only when all its channels are
/// present. Throws librt::Error naming the file when it is missing, not a scan-line EXR,
/// or has no R, G, B channels.
[[nodiscard]] LIBRT_API ImageLayers read_exr(const std::filesystem::path& path);

}  // namespace librt
