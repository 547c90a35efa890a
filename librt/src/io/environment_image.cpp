#include <librt/core/error.h>
#include <librt/io/exr.h>
#include <librt/io/file_extension.h>
#include <librt/io/hdr_image.h>

#include <cmath>
#include <string>
#include <utility>

namespace librt {

EnvironmentImage load_environment_image(const std::filesystem::path& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".hdr") return load_hdr_image(path);
    if (ext != ".exr")
        throw Error(path.string() + ": unknown environment format '" + ext +
                    "' (expected .hdr or .exr)");
    ImageLayers layers = read_exr(path);
    EnvironmentImage env;
    env.width = layers.beauty.width;
    env.height = layers.beauty.height;
    env.pixels = std::move(layers.beauty.pixels);
    // load_hdr_image's rule, here with the file named (from_image's error would not say it).
    for (std::size_t i = 0; i < env.pixels.size(); ++i) {
        const glm::vec3& p = env.pixels[i];
        const bool good = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) &&
                          p.x >= 0.0f && p.y >= 0.0f && p.z >= 0.0f;
        if (!good) {
            const std::size_t w = std::size_t(env.width);
            throw Error(path.string() + ": pixel (" + std::to_string(i % w) + ", " +
                        std::to_string(i / w) +
                        ") is negative or not finite: an environment is radiance, >= 0");
        }
    }
    return env;
}

}  // namespace librt
