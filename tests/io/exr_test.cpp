// EXR output: every layer read back with the same library (tinyexr) exactly for float,
// within half precision for half; bad input refused without leaving a file behind.

#include "io/temp_dir_test.h"
#include "render/film_test_util.h"

#include <librt/core/error.h>
#include <librt/io/exr.h>
#include <librt/render/renderer.h>
#include <librt/sampling/rng.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

using namespace librt;
namespace fs = std::filesystem;

namespace {

class ExrTest : public librt::testing::TempDirTest {};

// Layers of random values spanning many binades (and signs, for normals), with an
// infinite depth where nothing was hit.
ImageLayers random_layers(int w, int h) {
    Pcg32 rng(7, 11);
    const auto value = [&](float lo_exp, float hi_exp) {
        return std::exp2(lo_exp + (hi_exp - lo_exp) * rng.next_float());
    };
    ImageLayers layers;
    layers.beauty = Image(w, h);
    layers.albedo = Image(w, h);
    layers.normal = Image(w, h);
    for (std::size_t i = 0; i < layers.beauty.pixels.size(); ++i) {
        layers.beauty.pixels[i] = {value(-12, 14), value(-12, 14), 0.0f};
        layers.albedo.pixels[i] = {rng.next_float(), rng.next_float(), rng.next_float()};
        layers.normal.pixels[i] = {2 * rng.next_float() - 1, 2 * rng.next_float() - 1,
                                   -rng.next_float()};
        layers.depth.push_back(value(-4, 20));
        layers.sample_count.push_back(static_cast<float>(rng.next_u32() % 5000000u));
    }
    layers.depth[3] = std::numeric_limits<float>::infinity();
    return layers;
}

void expect_same(const std::vector<float>& a, const std::vector<float>& b, const char* layer) {
    ASSERT_EQ(a.size(), b.size()) << layer;
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << layer << " " << i;
}

void expect_same(const Image& a, const Image& b, const char* layer) {
    ASSERT_EQ(a.width, b.width) << layer;
    ASSERT_EQ(a.height, b.height) << layer;
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        EXPECT_EQ(a.pixels[i], b.pixels[i]) << layer << " " << i;
}

// Round to nearest half: a relative error of at most 2^-11 for normal halves, and half
// the subnormal spacing 2^-24 / 2 below them.
void expect_half_close(const Image& written, const Image& read, const char* layer) {
    ASSERT_EQ(written.pixels.size(), read.pixels.size()) << layer;
    for (std::size_t i = 0; i < written.pixels.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            const float a = written.pixels[i][c];
            const float b = read.pixels[i][c];
            EXPECT_LE(std::fabs(a - b), std::max(std::fabs(a) * 0x1p-11f, 0x1p-25f))
                << layer << " pixel " << i << " channel " << c << ": " << a << " -> " << b;
        }
    }
}

}  // namespace

TEST_F(ExrTest, FloatRoundTripIsExactForEveryLayer) {
    const ImageLayers layers = random_layers(17, 9);
    const fs::path path = dir_ / "all.exr";
    write_exr(path, layers, {ExrPixelType::Float});
    EXPECT_EQ(entries(), 1u);  // no temporary left behind
    const ImageLayers back = read_exr(path);
    expect_same(layers.beauty, back.beauty, "beauty");
    expect_same(layers.albedo, back.albedo, "albedo");
    expect_same(layers.normal, back.normal, "normal");
    expect_same(layers.depth, back.depth, "depth");
    expect_same(layers.sample_count, back.sample_count, "sample_count");
}

TEST_F(ExrTest, HalfRoundTripIsWithinHalfPrecision) {
    const ImageLayers layers = random_layers(23, 5);
    const fs::path path = dir_ / "half.exr";
    EXPECT_TRUE(write_exr(path, layers, {ExrPixelType::Half}).warnings.empty());
    const ImageLayers back = read_exr(path);
    expect_half_close(layers.beauty, back.beauty, "beauty");
    expect_half_close(layers.albedo, back.albedo, "albedo");
    expect_half_close(layers.normal, back.normal, "normal");
    // Depth and the sample count are stored as 32-bit floats in either mode.
    expect_same(layers.depth, back.depth, "depth");
    expect_same(layers.sample_count, back.sample_count, "sample_count");
    // Half really is smaller than float: the file is a half-precision one.
    write_exr(dir_ / "float.exr", layers, {ExrPixelType::Float});
    EXPECT_LT(fs::file_size(path), fs::file_size(dir_ / "float.exr"));
}

// Issue 37, defect 4: the beauty was written as half by default, so radiance above 65504
// (an emitter of strength 1e5 seen directly) became +inf in the file. The default is float:
// the value comes back as written, finite, and nothing is reported.
TEST_F(ExrTest, DefaultBeautyIsFloatAndKeepsValuesAboveTheHalfRange) {
    ImageLayers layers;
    layers.beauty = Image(3, 2);
    layers.beauty.at(1, 0) = {1e5f, 2e5f, 65520.0f};
    layers.beauty.at(2, 1) = {3e38f, 0.25f, 1.0f};
    const fs::path path = dir_ / "bright.exr";
    const ExrWriteResult result = write_exr(path, layers);
    EXPECT_TRUE(result.warnings.empty());
    const ImageLayers back = read_exr(path);
    expect_same(layers.beauty, back.beauty, "beauty");
    for (const glm::vec3& p : back.beauty.pixels)
        for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(p[c]));
}

// Half on request: values beyond the largest half are clamped to +-65504 (never +inf) and
// each layer that had any is reported once, naming the file, the count and the largest.
TEST_F(ExrTest, HalfClampsToTheLargestHalfWithAWarning) {
    ImageLayers layers = random_layers(4, 3);
    layers.beauty.at(1, 0) = {1e5f, 70000.0f, 0.5f};
    layers.beauty.at(3, 2) = {std::numeric_limits<float>::infinity(), 65504.0f, 2.0f};
    layers.albedo.at(0, 0) = {-1e6f, 0.5f, 0.5f};  // not a real albedo: the clamp is per layer
    const fs::path path = dir_ / "half.exr";
    const ExrWriteResult result = write_exr(path, layers, {ExrPixelType::Half});
    ASSERT_EQ(result.warnings.size(), 2u);
    const std::string& beauty = result.warnings[0];
    EXPECT_NE(beauty.find("half.exr"), std::string::npos) << beauty;
    EXPECT_NE(beauty.find("3 beauty value(s) above 65504"), std::string::npos) << beauty;
    EXPECT_NE(beauty.find("(largest inf)"), std::string::npos) << beauty;
    EXPECT_NE(result.warnings[1].find("1 albedo value(s) above 65504"), std::string::npos)
        << result.warnings[1];
    EXPECT_NE(result.warnings[1].find("(largest 1e+06)"), std::string::npos) << result.warnings[1];
    const ImageLayers back = read_exr(path);
    EXPECT_EQ(back.beauty.at(1, 0), glm::vec3(65504.0f, 65504.0f, 0.5f));
    EXPECT_EQ(back.beauty.at(3, 2), glm::vec3(65504.0f, 65504.0f, 2.0f));
    EXPECT_EQ(back.albedo.at(0, 0).x, -65504.0f);
    for (const glm::vec3& p : back.beauty.pixels)
        for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(p[c]));
}

TEST_F(ExrTest, OptionalLayersAreOmitted) {
    ImageLayers layers;
    layers.beauty = Image(4, 3);
    layers.beauty.at(1, 2) = {0.5f, 1.5f, 2.5f};
    write_exr(dir_ / "beauty.exr", layers, {ExrPixelType::Float});
    const ImageLayers back = read_exr(dir_ / "beauty.exr");
    expect_same(layers.beauty, back.beauty, "beauty");
    EXPECT_TRUE(back.albedo.pixels.empty());
    EXPECT_TRUE(back.normal.pixels.empty());
    EXPECT_TRUE(back.depth.empty());
    EXPECT_TRUE(back.sample_count.empty());
}

// A rendered film's layers, beauty linear (not tone-mapped), survive the file exactly.
TEST_F(ExrTest, RenderedFilmLayersRoundTrip) {
    const Scene scene = librt::testing::film_test_scene();
    const Camera camera = librt::testing::film_test_camera(12, 8);
    PathTracer integrator(PathTracerSettings{3, false});
    ProgressiveSettings s;
    s.render.samples_per_pixel = 3;
    s.aovs = true;
    Film film;
    (void)render_progressive(scene, camera, integrator, film, s);
    const ImageLayers layers = resolve_layers(film);
    write_exr(dir_ / "render.exr", layers, {ExrPixelType::Float});
    const ImageLayers back = read_exr(dir_ / "render.exr");
    expect_same(resolve(film), back.beauty, "beauty");
    expect_same(layers.albedo, back.albedo, "albedo");
    expect_same(layers.normal, back.normal, "normal");
    expect_same(layers.depth, back.depth, "depth");
    for (const float n : back.sample_count) EXPECT_EQ(n, 3.0f);
}

TEST_F(ExrTest, BadLayersAreRefusedAndLeaveNothing) {
    const fs::path path = dir_ / "bad.exr";
    const auto expect_error = [&](const ImageLayers& layers, const std::string& text) {
        try {
            write_exr(path, layers);
            ADD_FAILURE() << text;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("bad.exr"), std::string::npos) << e.what();
        }
        EXPECT_EQ(entries(), 0u) << text;
    };
    ImageLayers layers = random_layers(6, 4);
    layers.depth.pop_back();
    expect_error(layers, "layer depth has 23 pixels, the beauty 24");
    layers = random_layers(6, 4);
    layers.albedo = Image(4, 6);
    layers.albedo.pixels.pop_back();
    expect_error(layers, "layer albedo");
    layers = random_layers(6, 4);
    layers.normal.at(2, 3).y = std::numeric_limits<float>::quiet_NaN();
    expect_error(layers, "channel normal.Y is NaN at pixel (2, 3)");
    expect_error(ImageLayers{}, "beauty is 0 x 0");
    // An existing file is left as it was when a write fails.
    { std::ofstream(path) << "old"; }
    layers = random_layers(6, 4);
    layers.sample_count.resize(3);
    EXPECT_THROW(write_exr(path, layers), Error);
    EXPECT_EQ(fs::file_size(path), 3u);
    EXPECT_EQ(entries(), 1u);
    // A directory that does not exist.
    EXPECT_THROW(write_exr(dir_ / "missing" / "x.exr", random_layers(2, 2)), Error);
}

TEST_F(ExrTest, ReadingBadFilesNamesTheFile) {
    const auto expect_error = [&](const fs::path& path) {
        try {
            (void)read_exr(path);
            ADD_FAILURE() << path;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(path.filename().string()), std::string::npos)
                << e.what();
        }
    };
    expect_error(dir_ / "nothing.exr");
    { std::ofstream(dir_ / "text.exr") << "this is not an OpenEXR file at all"; }
    expect_error(dir_ / "text.exr");
    // A valid file cut short.
    write_exr(dir_ / "whole.exr", random_layers(32, 32), {ExrPixelType::Float});
    fs::copy_file(dir_ / "whole.exr", dir_ / "cut.exr");
    fs::resize_file(dir_ / "cut.exr", fs::file_size(dir_ / "whole.exr") / 2);
    expect_error(dir_ / "cut.exr");
}
