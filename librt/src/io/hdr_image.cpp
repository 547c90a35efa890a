#include "io/file_io.h"

#include <librt/core/error.h>
#include <librt/io/hdr_image.h>

#include <stb/stb_image.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

namespace librt {
namespace {

constexpr std::uint64_t kMaxHdrFileBytes = std::uint64_t{1} << 30;
constexpr std::uint64_t kMaxHdrPixels = std::uint64_t{1} << 26;

}  // namespace

EnvironmentImage load_hdr_image(const std::filesystem::path& path) {
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
    std::unique_ptr<float, void (*)(void*)> data(
        stbi_loadf_from_memory(encoded, size, &w, &h, &channels, 3), stbi_image_free);
    if (!data)
        throw Error("cannot load HDR image " + name + ": " +
                    (stbi_failure_reason() ? stbi_failure_reason() : "decoding failed"));
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

}  // namespace librt
