#include "io/file_io.h"

#include <librt/core/error.h>
#include <librt/core/untrusted_text.h>
#include <librt/io/check_writable.h>
#include <librt/io/exr.h>
#include <librt/io/file_extension.h>
#include <librt/io/image_io.h>

#include <stb/stb_image_write.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace librt {

namespace fs = std::filesystem;

namespace {

using Bytes = std::vector<unsigned char>;

// A PFM file is at most the largest image (check_image_size: 4 GiB of float RGB) and a
// header, which is a few dozen bytes; 1 MiB of slack is plenty.
constexpr std::uint64_t kMaxPfmBytes = (std::uint64_t{4} << 30) + (std::uint64_t{1} << 20);

// The writers hand stb a film as a flat float array: three packed floats per pixel.
static_assert(sizeof(glm::vec3) == 3 * sizeof(float));

// Built by appending: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
std::string quoted(const fs::path& path) {
    std::string out(1, '\'');
    out += path.string();
    out += '\'';
    return out;
}

// Writes the encoded image through the library's one atomic writer (io/file_io.h).
void write_file_atomically(const fs::path& path, const Bytes& bytes) {
    detail::write_file_atomically(
        path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

void check_writable_image(const fs::path& path, const Image& image) {
    if (image.width < 1 || image.height < 1 ||
        image.pixels.size() !=
            static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height)) {
        throw Error("cannot write " + quoted(path) + ": image is " + std::to_string(image.width) +
                    " x " + std::to_string(image.height) + " with " +
                    std::to_string(image.pixels.size()) + " pixels");
    }
}

// stb_image_write's output callback: appends to a byte vector.
void append_bytes(void* context, void* data, int size) {
    auto* out = static_cast<Bytes*>(context);
    const auto* p = static_cast<const unsigned char*>(data);
    out->insert(out->end(), p, p + size);
}

void put_u32_le(Bytes& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
}

std::uint32_t get_u32(const unsigned char* p, bool little_endian) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) {
        const int shift = little_endian ? 8 * i : 8 * (3 - i);
        v |= std::uint32_t{p[i]} << shift;
    }
    return v;
}

// Reads the next whitespace-delimited token of a PFM header starting at `pos`.
std::string_view next_token(std::string_view data, std::size_t& pos) {
    const auto space = [&](std::size_t i) {
        return std::isspace(static_cast<unsigned char>(data[i]));
    };
    while (pos < data.size() && space(pos)) ++pos;
    const std::size_t start = pos;
    while (pos < data.size() && !space(pos)) ++pos;
    return data.substr(start, pos - start);
}

Image scaled(const Image& image, float factor) {
    Image out = image;
    for (glm::vec3& p : out.pixels) p *= factor;
    return out;
}

}  // namespace

void write_png(const fs::path& path, const Image& image, const ToneMap& tone_map) {
    check_writable_image(path, image);
    const std::vector<std::uint8_t> rgb = to_rgb8(image, tone_map);
    Bytes encoded;
    if (stbi_write_png_to_func(append_bytes, &encoded, image.width, image.height, 3, rgb.data(),
                               image.width * 3) == 0) {
        throw Error("cannot write " + quoted(path) + ": PNG encoding failed");
    }
    write_file_atomically(path, encoded);
}

void write_pfm(const fs::path& path, const Image& image) {
    check_writable_image(path, image);
    const std::string header =
        "PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1.0\n";
    Bytes out(header.begin(), header.end());
    out.reserve(header.size() + image.pixels.size() * 12);
    // PFM stores rows bottom to top; scale -1 means little-endian floats.
    for (int y = image.height - 1; y >= 0; --y) {
        for (int x = 0; x < image.width; ++x) {
            const glm::vec3& p = image.at(x, y);
            for (int c = 0; c < 3; ++c) {
                std::uint32_t bits = 0;
                std::memcpy(&bits, &p[c], sizeof bits);
                put_u32_le(out, bits);
            }
        }
    }
    write_file_atomically(path, out);
}

Image read_pfm(const fs::path& path) {
    // Only a regular file, of at most the largest image plus a header (no FIFO to block
    // on, no /dev/zero to read forever).
    detail::ReadRequest request;
    request.what = "a PFM file";
    request.max_bytes = kMaxPfmBytes;
    std::string data;
    try {
        data = detail::read_regular_file(path, request);
    } catch (const Error& e) {
        throw Error(std::string("cannot read ") + e.what());
    }
    const auto malformed = [&](const std::string& what) {
        return Error(quoted(path) + ": not a valid PFM file: " + what);
    };

    std::size_t pos = 0;
    const std::string_view magic = next_token(data, pos);
    int channels = 0;
    if (magic == "PF") {
        channels = 3;
    } else if (magic == "Pf") {
        channels = 1;
    } else {
        throw malformed("it does not start with PF or Pf");
    }
    long long size[2] = {0, 0};
    for (long long& v : size) {
        const std::string_view token = next_token(data, pos);
        const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
        if (ec != std::errc() || end != token.data() + token.size() || v < 1) {
            throw malformed("bad size " + quote_untrusted(token));
        }
    }
    const std::string_view scale_token = next_token(data, pos);
    double scale = 0.0;
    {
        const auto [end, ec] =
            std::from_chars(scale_token.data(), scale_token.data() + scale_token.size(), scale);
        if (ec != std::errc() || end != scale_token.data() + scale_token.size() || scale == 0.0 ||
            !std::isfinite(scale)) {
            throw malformed("bad scale " + quote_untrusted(scale_token));
        }
    }
    // Exactly one whitespace character separates the header from the raster.
    if (pos >= data.size() || !std::isspace(static_cast<unsigned char>(data[pos]))) {
        throw malformed("truncated header");
    }
    ++pos;

    check_image_size(size[0], size[1]);
    // The raster must be there before the film is allocated: a 20-byte file claiming
    // 10000 x 10000 pixels must not cost 1.2 GB.
    const std::size_t needed = static_cast<std::size_t>(size[0]) *
                               static_cast<std::size_t>(size[1]) *
                               static_cast<std::size_t>(channels) * 4;
    if (data.size() - pos < needed) {
        throw malformed("truncated raster: " + std::to_string(data.size() - pos) + " bytes for " +
                        std::to_string(needed));
    }
    Image image(static_cast<int>(size[0]), static_cast<int>(size[1]));
    const bool little_endian = scale < 0.0;
    const auto* p = reinterpret_cast<const unsigned char*>(data.data()) + pos;
    for (int y = image.height - 1; y >= 0; --y) {
        for (int x = 0; x < image.width; ++x) {
            glm::vec3& out = image.at(x, y);
            for (int c = 0; c < channels; ++c) {
                const std::uint32_t bits = get_u32(p, little_endian);
                p += 4;
                std::memcpy(&out[c], &bits, sizeof bits);
            }
            if (channels == 1) out = glm::vec3(out[0]);
        }
    }
    return image;
}

void write_hdr(const fs::path& path, const Image& image) {
    check_writable_image(path, image);
    Bytes encoded;
    if (stbi_write_hdr_to_func(append_bytes, &encoded, image.width, image.height, 3,
                               &image.pixels[0].x) == 0) {
        throw Error("cannot write " + quoted(path) + ": HDR encoding failed");
    }
    write_file_atomically(path, encoded);
}

void check_image_path(const fs::path& path) {
    const std::string ext = lower_extension(path);
    if (ext != ".png" && ext != ".pfm" && ext != ".hdr" && ext != ".exr") {
        throw Error("cannot write " + quoted(path) +
                    ": unknown image format (use .png, .pfm, .hdr or .exr)");
    }
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw Error("cannot write " + quoted(path) + ": a directory");
    const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    // The reason the system gives (a name too long, a component that is a file, no
    // permission), not "no directory" for every failure.
    const fs::file_status status = fs::status(dir, ec);
    if (ec && status.type() != fs::file_type::not_found)
        throw Error("cannot write " + quoted(path) + ": directory " + quoted(dir) + ": " +
                    ec.message());
    if (status.type() == fs::file_type::not_found)
        throw Error("cannot write " + quoted(path) + ": no directory " + quoted(dir));
    if (status.type() != fs::file_type::directory)
        throw Error("cannot write " + quoted(path) + ": directory " + quoted(dir) + ": " +
                    std::strerror(ENOTDIR));
    // A file name longer than the directory allows (NAME_MAX, 255 bytes on most file
    // systems) fails only when the file is created: said here, before a long render.
    const long name_max = ::pathconf(dir.c_str(), _PC_NAME_MAX);
    if (name_max > 0 && path.filename().native().size() > std::size_t(name_max))
        throw Error("cannot write " + quoted(path) + ": " + std::strerror(ENAMETOOLONG) +
                    " (its name has " + std::to_string(path.filename().native().size()) +
                    " bytes, the directory allows " + std::to_string(name_max) + ")");
    check_writable(path);
}

void write_image(const fs::path& path, const Image& image, const ToneMap& tone_map) {
    const std::string ext = lower_extension(path);
    if (ext == ".png") {
        write_png(path, image, tone_map);
    } else if (ext == ".pfm" || ext == ".hdr" || ext == ".exr") {
        validate(tone_map);
        Image out = tone_map.exposure == 1.0f ? image : scaled(image, tone_map.exposure);
        if (ext == ".pfm") {
            write_pfm(path, out);
        } else if (ext == ".hdr") {
            write_hdr(path, out);
        } else {
            ImageLayers layers;
            layers.beauty = std::move(out);
            write_exr(path, layers);
        }
    } else {
        throw Error("cannot write " + quoted(path) +
                    ": unknown image format (use .png, .pfm, .hdr or .exr)");
    }
}

}  // namespace librt
