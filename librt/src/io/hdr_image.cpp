#include "io/file_io.h"

#include <librt/core/error.h>
#include <librt/io/hdr_image.h>

#include <stb/stb_image.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <new>
#include <string>
#include <string_view>

namespace librt {
namespace {

constexpr std::uint64_t kMaxHdrFileBytes = std::uint64_t{1} << 30;
constexpr std::uint64_t kMaxHdrPixels = std::uint64_t{1} << 26;

// stb_image (v2.27, stbi__hdr_load) reads a scanline run-length encoded ("new-style":
// 2, 2, width high, width low, then each of the 4 components as runs) only for widths in
// [8, 32767]; other widths, and files whose first scanline lacks that start, are flat:
// 4 bytes (R, G, B, E) per texel. It reads no old-style runs (a 1, 1, 1, n texel is taken
// as a colour), so these two are the only layouts.
bool rle_width(int w) { return w >= 8 && w < 32768; }

// The fewest data bytes stb can decode a w x h image from. A new-style scanline takes its
// 4-byte start, then per component at least one (count, value) pair per 127 texels (a
// count byte c > 128 repeats the next byte c - 128 times); a flat texel takes 4 bytes,
// more than that for any width stb run-length decodes.
std::uint64_t min_data_bytes(int w, int h) {
    const auto W = std::uint64_t(w), H = std::uint64_t(h);
    if (!rle_width(w)) return 4 * W * H;
    return H * (4 + 4 * 2 * ((W + 126) / 127));
}

// Where the texels start: after the "#?RADIANCE" line, the header lines up to a blank
// one and the resolution line, each ended by '\n' (as stb reads them); bytes.size() if
// the file ends before.
std::size_t data_offset(std::string_view bytes) {
    std::size_t pos = 0;
    const auto next_line = [&]() {
        const std::size_t end = bytes.find('\n', pos);
        const std::size_t length = (end == std::string_view::npos ? bytes.size() : end) - pos;
        pos = end == std::string_view::npos ? bytes.size() : end + 1;
        return length;
    };
    next_line();  // #?RADIANCE or #?RGBE
    while (pos < bytes.size() && next_line() != 0) {
    }
    next_line();  // -Y h +X w
    return pos;
}

// Walks the texel data as stbi__hdr_load will read it, without decoding, and returns why
// stb cannot decode it correctly, or "" if it can. stb does not check for the end of its
// input there: a run-length scanline cut short makes it loop forever (its byte reader
// returns 0 at the end, a run of 0 texels), and a file cut at a scanline's end comes back
// as a zero-filled image (a missing scanline start sends it back to texel 0 reading flat
// texels). A scanline without a run-length start after run-length ones sends it back to
// texel 0 too, so such a mix is refused as well.
std::string check_data(std::string_view data, int w, int h) {
    const auto W = std::uint64_t(w), H = std::uint64_t(h);
    const auto truncated = [&](std::uint64_t row) {
        return "truncated: the data ends in scanline " + std::to_string(row + 1) + " of " +
               std::to_string(h);
    };
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(data[i]); };
    const bool rle =
        rle_width(w) && data.size() >= 4 && byte(0) == 2 && byte(1) == 2 && (byte(2) & 0x80) == 0;
    if (!rle) {
        if (data.size() < 4 * W * H) return truncated(data.size() / (4 * W));
        return {};
    }
    std::size_t pos = 0;
    for (std::uint64_t row = 0; row < H; ++row) {
        if (data.size() - pos < 4) return truncated(row);
        if (byte(pos) != 2 || byte(pos + 1) != 2 || (byte(pos + 2) & 0x80) != 0)
            return "scanline " + std::to_string(row + 1) +
                   " is not run-length encoded while the first is (a mix stb cannot read)";
        if ((std::uint64_t(byte(pos + 2)) << 8 | byte(pos + 3)) != W)
            return "scanline " + std::to_string(row + 1) + " has a bad length";
        pos += 4;
        for (int component = 0; component < 4; ++component) {
            for (std::uint64_t x = 0; x < W;) {
                if (pos >= data.size()) return truncated(row);
                const unsigned count = byte(pos++);
                const std::uint64_t texels = count > 128 ? count - 128 : count;
                if (texels > W - x)
                    return "scanline " + std::to_string(row + 1) + ": a run past its end";
                const std::uint64_t stored = count > 128 ? 1 : count;
                if (data.size() - pos < stored) return truncated(row);
                pos += stored;
                x += texels;
            }
        }
    }
    return {};
}

// What the loader holds per texel at its peak: stb's float RGB and the EnvironmentImage
// made from it, both whole at once.
constexpr std::uint64_t kDecodedBytesPerTexel = 2 * 3 * sizeof(float);

EnvironmentImage load(const std::filesystem::path& path) {
    const std::string name = path.string();
    detail::ReadRequest request;
    request.what = "an HDR image file";
    request.max_bytes = kMaxHdrFileBytes;
    std::string bytes;
    try {
        bytes = detail::read_regular_file(path, request);
    } catch (const Error& e) {
        throw Error(std::string("cannot load HDR image ") + e.what());
    }
    const auto* encoded = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int size = int(bytes.size());
    if (stbi_is_hdr_from_memory(encoded, size) == 0)
        throw Error("cannot load HDR image " + name + ": not a Radiance .hdr file");
    int w = 0, h = 0, channels = 0;
    // The header first: refuse a huge image before stb allocates its pixels.
    if (stbi_info_from_memory(encoded, size, &w, &h, &channels) == 0 || w <= 0 || h <= 0 ||
        std::uint64_t(w) * std::uint64_t(h) > kMaxHdrPixels)
        throw Error("cannot load HDR image " + name + ": bad or oversized header (" +
                    std::to_string(w) + " x " + std::to_string(h) + ")");
    // Then the data, still before stb allocates: a header claiming more texels than the
    // file's bytes can encode, or data stb would misread (check_data).
    const std::string_view texels = std::string_view(bytes).substr(data_offset(bytes));
    if (texels.size() < min_data_bytes(w, h))
        throw Error("cannot load HDR image " + name + ": the header claims " + std::to_string(w) +
                    " x " + std::to_string(h) + " texels in a file of " +
                    std::to_string(bytes.size()) + " bytes (corrupt or truncated)");
    if (const std::string reason = check_data(texels, w, h); !reason.empty())
        throw Error("cannot load HDR image " + name + ": " + reason);
    // The loading memory bound (io/file_io.h): run-length coding lets a valid 4 MB file
    // decode to 8192^2 texels, 1.6 GB here; refused before anything is decoded.
    const std::uint64_t decoded = std::uint64_t(w) * std::uint64_t(h) * kDecodedBytesPerTexel;
    const std::uint64_t bound = detail::load_memory_bound(bytes.size());
    if (decoded > bound)
        throw Error("cannot load HDR image " + name + ": " + std::to_string(w) + " x " +
                    std::to_string(h) + " texels would take " + std::to_string(decoded) +
                    " bytes to decode, more than the " + std::to_string(bound) + " a file of " +
                    std::to_string(bytes.size()) +
                    " bytes may use (16 times its bytes plus 256 MiB)");
    std::unique_ptr<float, void (*)(void*)> data(
        stbi_loadf_from_memory(encoded, size, &w, &h, &channels, 3), stbi_image_free);
    if (!data) {
        const char* reason = stbi_failure_reason();
        // stb's malloc failed: the same message as any other allocation failure.
        if (reason != nullptr && std::string_view(reason) == "outofmem") throw std::bad_alloc();
        throw Error("cannot load HDR image " + name + ": " + (reason ? reason : "decoding failed"));
    }
    EnvironmentImage image;
    image.width = w;
    image.height = h;
    image.pixels.resize(std::size_t(w) * std::size_t(h));
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        const float* p = data.get() + 3 * i;
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
            throw Error("cannot load HDR image " + name + ": pixel " + std::to_string(i) +
                        " is not finite");
        image.pixels[i] = {p[0], p[1], p[2]};
    }
    return image;
}

}  // namespace

EnvironmentImage load_hdr_image(const std::filesystem::path& path) {
    try {
        return load(path);
    } catch (const std::bad_alloc&) {
        // The bound above leaves the rest to the machine: a process under a memory limit
        // gets an Error naming the file, never std::bad_alloc.
        throw Error("cannot load HDR image " + path.string() +
                    ": out of memory while loading (allocation failed)");
    }
}

}  // namespace librt
