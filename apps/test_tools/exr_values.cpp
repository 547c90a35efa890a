// exr_values: what an EXR file written by librt holds, for the apps' shell tests (built
// with the tests only). For each layer read_exr finds: its name, how many values, how many
// are not finite, and the largest finite one. Exit 1 (with the message) when the file
// cannot be read.
// Usage: exr_values <file.exr>
#include <librt/core/error.h>
#include <librt/io/exr.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

namespace {

void report(const char* layer, const std::vector<float>& values) {
    if (values.empty()) return;
    std::size_t not_finite = 0;
    float largest = -std::numeric_limits<float>::infinity();
    for (const float v : values) {
        if (!std::isfinite(v)) {
            ++not_finite;
        } else if (v > largest) {
            largest = v;
        }
    }
    std::printf("%s: %zu values, %zu not finite, max %.9g\n", layer, values.size(), not_finite,
                double(largest));
}

std::vector<float> flat(const librt::Image& image) {
    std::vector<float> values;
    values.reserve(image.pixels.size() * 3);
    for (const glm::vec3& p : image.pixels) values.insert(values.end(), {p.x, p.y, p.z});
    return values;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: exr_values <file.exr>\n");
        return 2;
    }
    try {
        const librt::ImageLayers layers = librt::read_exr(argv[1]);
        report("beauty", flat(layers.beauty));
        report("albedo", flat(layers.albedo));
        report("normal", flat(layers.normal));
        report("depth", layers.depth);
        report("sample_count", layers.sample_count);
    } catch (const librt::Error& e) {
        std::fprintf(stderr, "exr_values: %s\n", e.what());
        return 1;
    }
    return 0;
}
