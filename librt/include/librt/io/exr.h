#pragma once

#include <librt/core/image.h>
#include <librt/export.h>

#include <cstdint>
#include <filesystem>
#include <vector>

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

/// The layers of an EXR file; every layer but `beauty` is optional (empty = not written),
/// and each present layer has the beauty's size. Channel names in the file: beauty
/// R, G, B; albedo.R/G/B; normal.X/Y/Z; depth Z (the OpenEXR name for depth); the sample
/// count `sample_count` (always 32-bit float, exact up to 2^24 samples).
struct ExrLayers {
    Image beauty;                     ///< linear RGB radiance, not tone-mapped
    Image albedo;                     ///< RGB albedo, or 0x0 for none
    Image normal;                     ///< shading normal (x, y, z in world space), or 0x0
    std::vector<float> depth;         ///< width * height camera distances, or empty
    std::vector<float> sample_count;  ///< width * height samples per pixel, or empty
};

/// Writes `layers` as a single-part scan-line OpenEXR file (tinyexr, ZIP compression).
/// Throws librt::Error naming the file and the layer when a layer's size does not match
/// the beauty's, a value is NaN, or the file cannot be written; the target is then left
/// untouched (no partial file, no stray temporary).
LIBRT_API void write_exr(const std::filesystem::path& path, const ExrLayers& layers,
                         ExrPixelType type = ExrPixelType::Half);

/// Reads the layers write_exr writes (half channels are widened to float); channels it
/// does not know are ignored, and a layer is returned only when all its channels are
/// present. Throws librt::Error naming the file when it is missing, not a scan-line EXR,
/// or has no R, G, B channels.
[[nodiscard]] LIBRT_API ExrLayers read_exr(const std::filesystem::path& path);

}  // namespace librt
