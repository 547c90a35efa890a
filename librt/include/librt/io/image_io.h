#pragma once

#include <librt/core/image.h>
#include <librt/core/tone_map.h>
#include <librt/export.h>

#include <filesystem>
#include <vector>

// Image files. Every writer encodes in memory, writes a temporary file in the target's
// directory and renames it over the target, so a failed or interrupted write never
// leaves a half-written image behind: the target is either untouched or complete.
// All functions throw librt::Error naming the file on failure.

namespace librt {

/// 8-bit RGB PNG of the image tone-mapped by `tone_map` (stb_image_write).
LIBRT_API void write_png(const std::filesystem::path& path, const Image& image,
                         const ToneMap& tone_map = {});

/// A PNG of a display image (core/tone_curve.h, display_encode: values in [0, 1], clamped,
/// NaN as 0) with `bits` 8 or 16 per channel (16 keeps smooth gradients free of banding), RGB,
/// or RGBA when `alpha` is given: width * height coverage values in [0, 1], straight
/// (unassociated) alpha as PNG specifies. Through libpng, written atomically. Throws
/// librt::Error naming the file for other depths, an alpha of the wrong size, or a failed
/// write.
LIBRT_API void write_display_png(const std::filesystem::path& path, const Image& display,
                                 int bits = 8, const std::vector<float>* alpha = nullptr);

/// Linear float RGB PFM (Portable Float Map): "PF", little-endian (scale -1), rows
/// bottom to top as the format specifies. Values are written bit for bit.
LIBRT_API void write_pfm(const std::filesystem::path& path, const Image& image);

/// Reads a PFM: colour ("PF") or greyscale ("Pf", copied to all three channels), either
/// byte order; rows are returned top row first. Throws librt::Error naming the file
/// when it is missing, malformed or truncated.
[[nodiscard]] LIBRT_API Image read_pfm(const std::filesystem::path& path);

/// Linear Radiance RGBE (.hdr) via stb_image_write.
LIBRT_API void write_hdr(const std::filesystem::path& path, const Image& image);

/// Chooses the format by extension (case-insensitive): ".png" is tone-mapped with
/// `tone_map`; ".pfm", ".hdr" and ".exr" (io/exr.h, beauty only, 32-bit float) stay linear
/// but are multiplied by tone_map.exposure (no gamma, no clamp), so that 1.0 is display
/// white in HDR viewers. Any other extension throws librt::Error naming the path.
LIBRT_API void write_image(const std::filesystem::path& path, const Image& image,
                           const ToneMap& tone_map = {});
/// Checks, before any work, that write_image could write `path`: a known extension (.png,
/// .pfm, .hdr, .exr), not a directory, in an existing directory in which a file can be
/// created (check_writable: a temporary is created and removed). Throws librt::Error naming
/// the path and the problem; leaves nothing behind.
LIBRT_API void check_image_path(const std::filesystem::path& path);
}  // namespace librt
