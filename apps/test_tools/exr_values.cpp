// exr_values: what an EXR file written by librt holds, for the apps' shell tests (built
// with the tests only). For each layer read_exr finds: its name, how many values, how many
// are not finite, and the largest finite one. Exit 1 (with the message) when the file
// cannot be read.
// With --crop-of: whether every layer of CROP (an .exr, or a .pfm's beauty) holds, bit for
// bit, the pixels of the same layer of FULL from column X, row Y on (rt_render --region);
// prints "same" (exit 0) or the first difference (exit 1).
// Usage: exr_values <file.exr>
//        exr_values --crop-of <full> <crop> <X> <Y>
#include <librt/core/error.h>
#include <librt/io/exr.h>
#include <librt/io/file_extension.h>
#include <librt/io/image_io.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
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

/// The file's layers: an EXR's, or a PFM as its beauty.
librt::ImageLayers read_layers(const char* path) {
    if (librt::lower_extension(path) == ".pfm") {
        librt::ImageLayers layers;
        layers.beauty = librt::read_pfm(path);
        return layers;
    }
    return librt::read_exr(path);
}

/// Whether `crop`'s values (`channels` per pixel, rows of `crop_width`) equal `full`'s (rows
/// of `full_width`) from pixel (x, y) on, bit for bit; names the first difference.
bool same_values(const char* layer, const float* full, std::size_t full_size, int full_width,
                 const float* crop, std::size_t crop_size, int crop_width, int channels, int x,
                 int y) {
    if ((crop_size == 0) != (full_size == 0)) {
        std::printf("%s: in one file only\n", layer);
        return false;
    }
    const std::size_t row = std::size_t(crop_width) * std::size_t(channels);
    const std::size_t rows = row == 0 ? 0 : crop_size / row;
    for (std::size_t r = 0; r < rows; ++r) {
        const std::size_t at = ((std::size_t(y) + r) * std::size_t(full_width) + std::size_t(x)) *
                               std::size_t(channels);
        if (at + row > full_size) {
            std::printf("%s: the crop's row %zu lies outside the full image\n", layer, r);
            return false;
        }
        if (std::memcmp(full + at, crop + r * row, row * sizeof(float)) != 0) {
            std::printf("%s: row %zu of the crop differs\n", layer, r);
            return false;
        }
    }
    return true;
}

int crop_of(const char* full_path, const char* crop_path, int x, int y) {
    const librt::ImageLayers full = read_layers(full_path);
    const librt::ImageLayers crop = read_layers(crop_path);
    const int fw = full.beauty.width;
    const int cw = crop.beauty.width;
    const auto rgb = [](const librt::Image& i) {
        return i.pixels.empty() ? nullptr : &i.pixels[0].x;
    };
    const auto size3 = [](const librt::Image& i) { return i.pixels.size() * 3; };
    bool same = same_values("beauty", rgb(full.beauty), size3(full.beauty), fw, rgb(crop.beauty),
                            size3(crop.beauty), cw, 3, x, y);
    same = same_values("albedo", rgb(full.albedo), size3(full.albedo), fw, rgb(crop.albedo),
                       size3(crop.albedo), cw, 3, x, y) &&
           same;
    same = same_values("normal", rgb(full.normal), size3(full.normal), fw, rgb(crop.normal),
                       size3(crop.normal), cw, 3, x, y) &&
           same;
    same = same_values("depth", full.depth.data(), full.depth.size(), fw, crop.depth.data(),
                       crop.depth.size(), cw, 1, x, y) &&
           same;
    same = same_values("sample_count", full.sample_count.data(), full.sample_count.size(), fw,
                       crop.sample_count.data(), crop.sample_count.size(), cw, 1, x, y) &&
           same;
    if (same) std::printf("same\n");
    return same ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc == 6 && std::strcmp(argv[1], "--crop-of") == 0) {
        try {
            return crop_of(argv[2], argv[3], std::atoi(argv[4]), std::atoi(argv[5]));
        } catch (const librt::Error& e) {
            std::fprintf(stderr, "exr_values: %s\n", e.what());
            return 1;
        }
    }
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
