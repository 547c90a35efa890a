// libFuzzer target: arbitrary bytes as an image file -> load_texture (stb_image: PNG,
// JPEG, BMP, TGA, PPM, ...) and read_pfm; a texture that loads is looked up, a PFM that
// reads is written back and compared. Any outcome but a result or a librt::Error is a bug.
// The decoding itself happens in Debian's prebuilt libstb, which is not instrumented:
// this target checks librt's handling around it (sizes, limits, errors, lookups).
// Run: ./build/fuzz/tests/fuzz/image_fuzz -max_total_time=60 tests/fuzz/corpus/image

#include <librt/core/error.h>
#include <librt/io/image_io.h>
#include <librt/io/texture_io.h>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

std::filesystem::path scratch_file(const char* extension) {
    return std::filesystem::temp_directory_path() /
           ("librt_image_fuzz_" + std::to_string(::getpid()) + extension);
}

void write(const std::filesystem::path& path, const std::uint8_t* data, std::size_t size) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::filesystem::path image_path = scratch_file(".img");
    static const std::filesystem::path pfm_path = scratch_file(".pfm");
    static const std::filesystem::path copy_path = scratch_file("_copy.pfm");
    write(image_path, data, size);
    try {
        const librt::ImageTexture texture = librt::load_texture(image_path);
        if (texture.width() < 1 || texture.height() < 1) __builtin_trap();
        for (const float u : {0.0f, 0.37f, 1.0f, -2.5f, 1e9f, NAN}) {
            const glm::vec3 c = texture.lookup({u, 1.0f - u});
            if (!std::isfinite(c.x) || c.x < 0.0f || c.x > 1.0f) __builtin_trap();
        }
    } catch (const librt::Error&) {
    }
    write(pfm_path, data, size);
    try {
        const librt::Image image = librt::read_pfm(pfm_path);
        if (image.pixels.size() != std::size_t(image.width) * std::size_t(image.height))
            __builtin_trap();
        librt::write_pfm(copy_path, image);
        const librt::Image back = librt::read_pfm(copy_path);
        if (back.width != image.width || back.height != image.height ||
            std::memcmp(back.pixels.data(), image.pixels.data(),
                        image.pixels.size() * sizeof(glm::vec3)) != 0)
            __builtin_trap();
    } catch (const librt::Error&) {
    }
    return 0;
}
