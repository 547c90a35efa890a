#pragma once

#include <librt/export.h>
#include <librt/io/file_digest.h>
#include <librt/material/texture.h>

#include <cstdint>
#include <filesystem>

namespace librt {

/// Most texels load_texture accepts: 2^26 (8192 x 8192, 768 MiB as floats).
inline constexpr std::uint64_t kMaxTextureTexels = std::uint64_t{1} << 26u;

/// Reads a PNG, JPEG, BMP, TGA... with stb_image into a texture, converting its 8-bit sRGB
/// values to linear (an alpha channel is dropped, grey is replicated). Throws librt::Error
/// naming the path (and stb's reason) when the file is missing, a directory, unreadable,
/// cannot be decoded, has more than kMaxTextureTexels texels (checked from the header,
/// before decoding), is not a PNG and claims more than 4096 texels per byte of file (no
/// such format compresses that well: corrupt or truncated), or is a binary PPM/PGM shorter
/// than its raster (stb would return uninitialised memory as texels). A PNG whose data
/// ends short fails to decode (its zlib stream ends before the scanlines do).
/// When `digest` is given it receives the digest of the file's bytes (io/file_digest.h),
/// taken from the bytes read for decoding: the file is read once.
[[nodiscard]] LIBRT_API ImageTexture load_texture(const std::filesystem::path& path,
                                                  FileDigest* digest = nullptr);

}  // namespace librt
