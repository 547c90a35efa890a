#include <librt/core/error.h>
#include <librt/io/texture_io.h>

#include <stb/stb_image.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace librt {

ImageTexture load_texture(const std::filesystem::path& path) {
    int w = 0, h = 0, channels = 0;
    const std::string name = path.string();
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (status.type() == std::filesystem::file_type::not_found)
        throw Error("cannot load texture " + name + ": no such file");
    if (std::filesystem::is_directory(status))
        throw Error("cannot load texture " + name + ": is a directory");
    // The header first: refuse a huge image before stb allocates its pixels.
    if (stbi_info(name.c_str(), &w, &h, &channels) != 0) {
        if (std::uint64_t(w) * std::uint64_t(h) > kMaxTextureTexels) {
            std::ostringstream msg;
            msg << "cannot load texture " << name << ": " << w << " x " << h
                << " texels, more than the limit of " << kMaxTextureTexels;
            throw Error(msg.str());
        }
        // A header that claims far more texels than the file could encode is corrupt or
        // truncated: stb would allocate for it and then decode zeros (or, for binary
        // PNM, return uninitialised memory) at great length. No format compresses a
        // texel into less than 1/4096 byte (deflate peaks near 1/344 for RGB, a
        // constant-colour JPEG near 1/1000), so that is the bound; 64 Ki texels are
        // always allowed.
        const std::uint64_t file_bytes = std::filesystem::file_size(path, ec);
        const std::uint64_t texels = std::uint64_t(w) * std::uint64_t(h);
        if (!ec && texels > 4096u * file_bytes + 65536u) {
            std::ostringstream msg;
            msg << "cannot load texture " << name << ": the header claims " << w << " x " << h
                << " texels in a file of " << file_bytes << " bytes (corrupt or truncated)";
            throw Error(msg.str());
        }
        // stb's binary PNM reader does not check for a short read: a truncated P5/P6
        // file would come back as uninitialised memory. Its raster is w h c bytes (two
        // per sample at 16 bits) after the header, so a shorter file is truncated.
        char magic[2] = {0, 0};
        std::ifstream probe(path, std::ios::binary);
        probe.read(magic, 2);
        if (magic[0] == 'P' && (magic[1] == '5' || magic[1] == '6')) {
            const std::uint64_t raster = std::uint64_t(w) * std::uint64_t(h) *
                                         std::uint64_t(channels) *
                                         (stbi_is_16_bit(name.c_str()) ? 2u : 1u);
            if (!ec && file_bytes < raster) {
                std::ostringstream msg;
                msg << "cannot load texture " << name << ": truncated (" << file_bytes
                    << " bytes for a raster of " << raster << ")";
                throw Error(msg.str());
            }
        }
    }
    std::unique_ptr<stbi_uc, void (*)(void*)> data(stbi_load(name.c_str(), &w, &h, &channels, 3),
                                                   stbi_image_free);
    if (!data) {
        const char* reason = stbi_failure_reason();
        throw Error("cannot load texture " + name + ": " + (reason ? reason : "unknown error"));
    }
    std::array<float, 256> to_linear{};
    for (int i = 0; i < 256; ++i) to_linear[std::size_t(i)] = srgb_to_linear(float(i) / 255.0f);
    std::vector<glm::vec3> texels(std::size_t(w) * std::size_t(h));
    const stbi_uc* p = data.get();
    for (std::size_t i = 0; i < texels.size(); ++i, p += 3)
        texels[i] = {to_linear[p[0]], to_linear[p[1]], to_linear[p[2]]};
    return ImageTexture(w, h, std::move(texels));
}

}  // namespace librt
