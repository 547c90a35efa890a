// write_display_png through libpng (Debian libpng-dev): stb_image_write, which writes the other
// PNGs, has no 16-bit output.
#include "io/file_io.h"

#include <librt/core/error.h>
#include <librt/io/image_io.h>

#include <png.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <string>
#include <vector>

namespace librt {

namespace {

/// libpng's output callback: appends to a byte string.
void append(png_structp png, png_bytep data, png_size_t size) {
    auto* out = static_cast<std::string*>(png_get_io_ptr(png));
    out->append(reinterpret_cast<const char*>(data), size);
}

void no_flush(png_structp) {}

/// Encodes `rows` (already in PNG's byte order) into `out`; false when libpng failed. Holds
/// no object with a destructor between setjmp and a longjmp out of libpng.
bool encode(std::string* out, png_structp png, png_infop info, int width, int height, int bits,
            int channels, std::vector<png_bytep>* rows) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_set_write_fn(png, out, append, no_flush);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), bits,
                 channels == 4 ? PNG_COLOR_TYPE_RGB_ALPHA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    // The values are sRGB-encoded (display_encode): said in the file, as viewers expect.
    png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(png, info);
    png_write_image(png, rows->data());
    png_write_end(png, nullptr);
    return true;
}

}  // namespace

void write_display_png(const std::filesystem::path& path, const Image& display, int bits,
                       const std::vector<float>* alpha) {
    // Built by appending: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
    std::string name(1, '\'');
    name += path.string();
    name += '\'';
    if (bits != 8 && bits != 16)
        throw Error("cannot write " + name + ": bits = " + std::to_string(bits) +
                    ": a PNG here has 8 or 16 bits per channel");
    const std::size_t pixels =
        std::size_t(std::max(0, display.width)) * std::size_t(std::max(0, display.height));
    if (display.width < 1 || display.height < 1 || display.pixels.size() != pixels)
        throw Error("cannot write " + name + ": image is " + std::to_string(display.width) + " x " +
                    std::to_string(display.height) + " with " +
                    std::to_string(display.pixels.size()) + " pixels");
    if (alpha != nullptr && alpha->size() != pixels)
        throw Error("cannot write " + name + ": " + std::to_string(alpha->size()) +
                    " alpha values for " + std::to_string(pixels) + " pixels");
    const int channels = alpha != nullptr ? 4 : 3;
    const std::size_t bytes = std::size_t(bits / 8);
    const std::size_t stride = std::size_t(display.width) * std::size_t(channels) * bytes;
    const float top = bits == 16 ? 65535.0f : 255.0f;
    std::vector<png_byte> data(stride * std::size_t(display.height));
    std::size_t at = 0;
    const auto put = [&](float v) {
        // Rounded to nearest; NaN and below 0 to 0, above 1 to the top.
        const float q = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f) * top + 0.5f;
        const auto n = std::uint32_t(q);
        if (bits == 16) data[at++] = png_byte(n >> 8);  // PNG is big-endian
        data[at++] = png_byte(n & 0xffu);
    };
    for (std::size_t i = 0; i < pixels; ++i) {
        const glm::vec3& p = display.pixels[i];
        put(p.x);
        put(p.y);
        put(p.z);
        if (alpha != nullptr) put((*alpha)[i]);
    }
    std::vector<png_bytep> rows(std::size_t(display.height));
    for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = data.data() + y * stride;

    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
    std::string encoded;
    const bool ok = info != nullptr && encode(&encoded, png, info, display.width, display.height,
                                              bits, channels, &rows);
    png_destroy_write_struct(&png, info != nullptr ? &info : nullptr);
    if (!ok) throw Error("cannot write " + name + ": PNG encoding failed");
    detail::write_file_atomically(path, encoded);
}

}  // namespace librt
