#pragma once

// A PNG's image data checked against its header before stb_image decodes it (private).

#include <cstdint>
#include <string>
#include <string_view>

namespace librt::detail {

/// What check_png_data found.
struct PngDataCheck {
    std::string problem;          ///< why it cannot be decoded within its header, or ""
    std::uint64_t raw_bytes = 0;  ///< the inflated data its header gives (stb holds it too)
};

/// Whether the PNG `bytes` can be decoded within its header's size. stb
/// inflates the IDAT stream into a buffer that grows without bound, so a few megabytes of
/// deflate (up to 1032:1) could take gigabytes whatever the header says; here the stream is
/// inflated into a small scratch buffer and counted, and refused once it passes the raw
/// size the header gives (PNG specification, sections 7.2 and 8.2: a filter byte per row,
/// per Adam7 pass when interlaced). An unreadable header or chunk layout is left to stb.
[[nodiscard]] PngDataCheck check_png_data(std::string_view bytes);

}  // namespace librt::detail
