#pragma once

#include <librt/core/image_layers.h>
#include <librt/export.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

// OpenEXR output with the layers external denoisers (Open Image Denoise) and compositors
// (Nuke, Blender) read: linear beauty and AOVs in one scan-line file, ZIP compressed.
// Written through a temporary file renamed into place, like every librt image writer.

namespace librt {

/// Storage of a channel: 32-bit float or 16-bit half.
enum class ExrPixelType : std::uint8_t {
    Half,   ///< 16-bit IEEE half: at most 65504 in magnitude, about 3 significant digits
    Float,  ///< 32-bit IEEE float, values written bit for bit
};

/// How write_exr stores the layers.
struct ExrWriteOptions {
    /// Storage of the beauty, albedo, normal and denoised channels. Float (the default) writes
    /// every value bit for bit. Half makes a smaller file, but a half holds at most 65504: larger
    /// magnitudes (a bright emitter seen directly, a high exposure) would become infinite,
    /// so they are clamped to +-65504 and reported in ExrWriteResult::warnings. Depth and
    /// the sample count are always 32-bit float (half would round a depth of 1000 to a
    /// multiple of 0.5 and a count above 2048 to an even number).
    ExrPixelType colour = ExrPixelType::Float;
};

/// What write_exr reports besides the file.
struct ExrWriteResult {
    /// One line per layer whose values were clamped to the largest half, naming the file,
    /// the layer, how many values and the largest of them. Empty for float channels.
    std::vector<std::string> warnings;
};

/// Writes `layers` as a single-part scan-line OpenEXR file (tinyexr, ZIP compression).
/// Channel names: beauty R, G, B; albedo.R/G/B; normal.X/Y/Z (world space); denoised.R/G/B (the
/// denoised beauty); depth Z (the OpenEXR name for depth: planar camera depth, as Blender and Nuke
/// read it, not the ray's length); sample_count. Depth is +infinity where no sample hit anything
/// (as resolve_layers gives it); every other channel of a rendered film is finite. Throws
/// librt::Error naming the file and the layer when a layer's size does not match the beauty's, a
/// value is NaN, or the file cannot be written; the target is then left untouched (no partial file,
/// no stray temporary).
LIBRT_API ExrWriteResult write_exr(const std::filesystem::path& path, const ImageLayers& layers,
                                   const ExrWriteOptions& options = {});

/// Reads the layers write_exr writes (half channels are widened to float); channels it
/// does not know are ignored, and a layer is returned only when all its channels are
/// present. Throws librt::Error naming the file when it is missing, not a scan-line EXR,
/// or has no R, G, B channels.
[[nodiscard]] LIBRT_API ImageLayers read_exr(const std::filesystem::path& path);

}  // namespace librt
