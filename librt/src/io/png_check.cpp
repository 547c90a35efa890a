// check_png_data: the IDAT stream counted with zlib, never stored.

#include "io/png_check.h"

#include <zlib.h>

#include <array>
#include <cstdint>

namespace librt::detail {

namespace {

std::uint32_t be32(std::string_view b, std::size_t at) {
    // PNG integers are big-endian.
    const auto u = [&](std::size_t k) {
        return std::uint32_t(static_cast<unsigned char>(b[at + k]));
    };
    return u(0) << 24u | u(1) << 16u | u(2) << 8u | u(3);
}

/// Bytes of the filtered scanlines of a w x h sub-image: a filter byte and
/// ceil(w * bits / 8) bytes per row (PNG specification, section 7.2).
std::uint64_t raw_bytes(std::uint64_t w, std::uint64_t h, std::uint64_t bits) {
    if (w == 0 || h == 0) return 0;
    return h * (1 + (w * bits + 7) / 8);
}

}  // namespace

PngDataCheck check_png_data(std::string_view bytes) {
    PngDataCheck out;
    if (bytes.size() < 33 || bytes.substr(0, 8) != "\x89PNG\r\n\x1a\n" ||
        bytes.substr(12, 4) != "IHDR")
        return out;
    const std::uint64_t w = be32(bytes, 16), h = be32(bytes, 20);
    const unsigned depth = static_cast<unsigned char>(bytes[24]);
    const unsigned colour = static_cast<unsigned char>(bytes[25]);
    const bool interlaced = bytes[28] != 0;
    // Samples per pixel by colour type (section 11.2.2): grey, -, RGB, palette, grey+alpha,
    // -, RGBA.
    static constexpr std::array<unsigned, 7> kSamples = {1, 0, 3, 1, 2, 0, 4};
    if (colour >= kSamples.size() || kSamples[colour] == 0 || depth == 0 || depth > 16)
        return out;  // stb refuses these itself
    const std::uint64_t bits = std::uint64_t(kSamples[colour]) * depth;
    std::uint64_t expected = 0;
    if (!interlaced) {
        expected = raw_bytes(w, h, bits);
    } else {
        // Adam7 (section 8.2): pass p covers columns from x0 every dx, rows from y0 every dy.
        static constexpr std::array<unsigned, 7> x0 = {0, 4, 0, 2, 0, 1, 0},
                                                 dx = {8, 8, 4, 4, 2, 2, 1},
                                                 y0 = {0, 0, 4, 0, 2, 0, 1},
                                                 dy = {8, 8, 8, 4, 4, 2, 2};
        for (std::size_t p = 0; p < 7; ++p) {
            const std::uint64_t pw = w > x0[p] ? (w - x0[p] + dx[p] - 1) / dx[p] : 0;
            const std::uint64_t ph = h > y0[p] ? (h - y0[p] + dy[p] - 1) / dy[p] : 0;
            expected += raw_bytes(pw, ph, bits);
        }
    }
    out.raw_bytes = expected;
    z_stream z{};
    if (inflateInit(&z) != Z_OK) return out;
    struct End {
        z_stream* z;
        ~End() { inflateEnd(z); }
    } end{&z};
    std::array<unsigned char, 1u << 16u> scratch{};
    std::uint64_t produced = 0;
    // Chunks: u32 length, 4-byte type, data, u32 CRC (section 5.3).
    for (std::size_t at = 8; at + 12 <= bytes.size();) {
        const std::uint64_t length = be32(bytes, at);
        if (at + 12 + length > bytes.size()) break;  // a short file: stb reports it
        const std::string_view type = bytes.substr(at + 4, 4);
        if (type == "IEND") break;
        if (type == "IDAT") {
            z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data() + at + 8));
            z.avail_in = static_cast<uInt>(length);
            while (z.avail_in > 0) {
                z.next_out = scratch.data();
                z.avail_out = static_cast<uInt>(scratch.size());
                const int status = inflate(&z, Z_NO_FLUSH);
                produced += scratch.size() - z.avail_out;
                if (produced > expected) {
                    out.problem = "its image data inflates to more than the " +
                                  std::to_string(expected) + " bytes its header's " +
                                  std::to_string(w) + " x " + std::to_string(h) +
                                  " pixels hold (corrupt or hostile)";
                    return out;
                }
                // The end, or a broken stream (stb reports that).
                if (status != Z_OK) return out;
            }
        }
        at += 12 + length;
    }
    return out;
}

}  // namespace librt::detail
