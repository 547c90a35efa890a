// Progressive, resumable rendering: a film split by pixel region or by sample range, then
// merged, must equal the one-shot render bit for bit (film.h says why it does).

#include "render/film_test_util.h"

#include <librt/core/error.h>
#include <librt/render/renderer.h>

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace librt;
using librt::testing::film_test_camera;
using librt::testing::film_test_scene;
using librt::testing::same_pixels;
using librt::testing::same_records;

namespace {

constexpr std::uint32_t kSpp = 10;

BlockSettings quiet_settings(int threads = 2, int tile = 16) {
    BlockSettings s;
    s.threads = threads;
    s.tile_size = tile;
    s.seed = 1234;
    return s;
}

class FilmTest : public ::testing::Test {
protected:
    FilmTest() : scene_(film_test_scene()), camera_(film_test_camera()) {
        integrator_.preprocess(scene_);
    }

    // Samples [first, first + count) of [x0, x1) x [y0, y1) onto `film`.
    void block(Film& film, int x0, int y0, int x1, int y1, std::uint32_t first, std::uint32_t count,
               const BlockSettings& settings = quiet_settings()) {
        const RenderStats stats = render_block(scene_, camera_, integrator_, film,
                                               {x0, y0, x1, y1, first, count}, settings);
        ASSERT_FALSE(stats.cancelled);
        ASSERT_EQ(stats.samples, std::uint64_t(x1 - x0) * std::uint64_t(y1 - y0) * count);
    }

    Film one_shot(std::uint32_t spp, bool aovs = true) {
        Film film(camera_.width(), camera_.height(), aovs);
        block(film, 0, 0, film.width, film.height, 0, spp);
        return film;
    }

    Scene scene_;
    Camera camera_;
    librt::testing::WideRangeIntegrator integrator_;
};

}  // namespace

// The one-shot film resolves to exactly what render() returns: render() is built on it.
TEST_F(FilmTest, OneShotFilmResolvesToTheRenderedImage) {
    const Film film = one_shot(kSpp);
    RenderSettings settings;
    static_cast<BlockSettings&>(settings) = quiet_settings();
    settings.samples_per_pixel = static_cast<int>(kSpp);
    settings.adaptive.enabled = false;  // every pixel the film's kSpp samples
    RenderStats stats;
    const Image image = render(scene_, camera_, integrator_, settings, &stats);
    EXPECT_TRUE(same_pixels(resolve(film), image));
    EXPECT_EQ(stats.passes, 1);
    EXPECT_EQ(stats.samples_per_pixel, kSpp);
    EXPECT_EQ(uniform_sample_count(film), kSpp);
    // Not a trivial image: the scene is lit.
    double total = 0.0;
    for (const FilmPixel& p : film.pixels) total += p.radiance.x;
    EXPECT_GT(total, 0.0);
}

TEST_F(FilmTest, RegionSplitsMergeBitIdentically) {
    const Film reference = one_shot(kSpp);
    // Four uneven regions and a one-pixel sliver, each on its own film (as on other machines).
    const std::vector<RenderBlock> regions = {{0, 0, 13, 7, 0, kSpp},
                                              {13, 0, 29, 7, 0, kSpp},
                                              {0, 7, 1, 19, 0, kSpp},
                                              {1, 7, 29, 18, 0, kSpp},
                                              {1, 18, 29, 19, 0, kSpp}};
    Film merged(camera_.width(), camera_.height(), true);
    for (const RenderBlock& r : regions) {
        Film part(camera_.width(), camera_.height(), true);
        block(part, r.x0, r.y0, r.x1, r.y1, 0, kSpp, quiet_settings(1, 5));
        merge(merged, part);
    }
    EXPECT_TRUE(same_records(merged, reference));
    EXPECT_TRUE(same_pixels(resolve(merged), resolve(reference)));
}

TEST_F(FilmTest, SampleRangeSplitsContinueBitIdentically) {
    const Film reference = one_shot(kSpp);
    Film film(camera_.width(), camera_.height(), true);
    block(film, 0, 0, 29, 19, 0, 3);
    block(film, 0, 0, 29, 19, 3, 4, quiet_settings(3, 4));
    block(film, 0, 0, 29, 19, 7, 3, quiet_settings(1, 64));
    EXPECT_TRUE(same_records(film, reference));
}

TEST_F(FilmTest, OneSamplePassesAreBitIdenticalToOneShot) {
    const Film reference = one_shot(kSpp);
    Film film(camera_.width(), camera_.height(), true);
    for (std::uint32_t s = 0; s < kSpp; ++s) block(film, 0, 0, 29, 19, s, 1);
    EXPECT_TRUE(same_records(film, reference));
}

// Regions and sample ranges mixed: the left part advances in two ranges while the right
// part is rendered at once on another film, then merged.
TEST_F(FilmTest, RegionAndSampleSplitsTogether) {
    const Film reference = one_shot(kSpp);
    Film left(camera_.width(), camera_.height(), true);
    block(left, 0, 0, 11, 19, 0, 4);
    Film right(camera_.width(), camera_.height(), true);
    block(right, 11, 0, 29, 19, 0, kSpp);
    block(left, 0, 0, 11, 19, 4, kSpp - 4);
    merge(left, right);
    EXPECT_TRUE(same_records(left, reference));
}

TEST_F(FilmTest, FilmIsIdenticalForAnyThreadCountAndTileSize) {
    const Film reference = one_shot(4);
    for (const int threads : {1, 3, 0}) {
        for (const int tile : {1, 6, 64}) {
            Film film(camera_.width(), camera_.height(), true);
            block(film, 0, 0, 29, 19, 0, 4, quiet_settings(threads, tile));
            EXPECT_TRUE(same_records(film, reference)) << threads << " threads, tile " << tile;
        }
    }
}

// AOVs use their own random numbers: the radiance sums are the same with or without them.
TEST_F(FilmTest, AovsDoNotChangeTheBeauty) {
    const Film with = one_shot(6, true);
    const Film without = one_shot(6, false);
    EXPECT_FALSE(without.has_aovs());
    ASSERT_EQ(with.pixels.size(), without.pixels.size());
    EXPECT_EQ(std::memcmp(with.pixels.data(), without.pixels.data(),
                          with.pixels.size() * sizeof(FilmPixel)),
              0);
}

TEST_F(FilmTest, MergingTwoSampleRangesOfOnePixelIsRefused) {
    Film a(camera_.width(), camera_.height(), true);
    block(a, 0, 0, 10, 10, 0, 2);
    Film b(camera_.width(), camera_.height(), true);
    block(b, 9, 9, 12, 12, 0, 2);
    const Film before = a;
    try {
        merge(a, b);
        ADD_FAILURE() << "overlapping films merged";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("pixel (9, 9)"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(same_records(a, before));  // unchanged
    Film small(5, 5, true);
    EXPECT_THROW(merge(small, a), Error);
    Film no_aovs(camera_.width(), camera_.height(), false);
    EXPECT_THROW(merge(no_aovs, a), Error);
}

TEST_F(FilmTest, BadBlocksAreRejectedBeforeRendering) {
    Film film(camera_.width(), camera_.height(), false);
    block(film, 0, 0, 29, 19, 0, 2);
    const Film before = film;
    const auto expect_error = [&](const RenderBlock& b, const std::string& text) {
        try {
            (void)render_block(scene_, camera_, integrator_, film, b, quiet_settings());
            ADD_FAILURE() << text;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
        }
        EXPECT_TRUE(same_records(film, before)) << text;
    };
    expect_error({0, 0, 29, 19, 0, 2}, "film pixel (0, 0) holds 2 samples");  // not a continuation
    expect_error({0, 0, 29, 19, 3, 2}, "block.first = 3");
    expect_error({0, 0, 30, 19, 2, 1}, "must lie in the 29 x 19 film");
    expect_error({-1, 0, 5, 5, 2, 1}, "block [-1, 5)");
    expect_error({0, 0, 29, 19, 2, kMaxSamplesPerPixel}, "at most 1048576 samples");
    Film wrong_size(8, 8);
    EXPECT_THROW((void)render_block(scene_, camera_, integrator_, wrong_size, {0, 0, 8, 8, 0, 1},
                                    quiet_settings()),
                 Error);
    // An empty block renders nothing and is not an error.
    const RenderStats none =
        render_block(scene_, camera_, integrator_, film, {3, 3, 3, 9, 2, 5}, quiet_settings());
    EXPECT_EQ(none.samples, 0u);
}

TEST(Film, OversizedFilmIsRefusedBeforeAllocating) {
    try {
        const Film film(65536, 65536, true);
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("65536 x 65536"), std::string::npos) << e.what();
    }
    EXPECT_THROW(Film(-1, 4), Error);
    const Film empty;
    EXPECT_EQ(uniform_sample_count(empty), 0u);
}

TEST(Film, ResolveIsTheMeanOfTheFiniteSamplesAndTheAovMeans) {
    Film film(2, 1, true);
    film.at(0, 0) = FilmPixel{glm::dvec3(3.0, 6.0, 9.0), 4, 3};  // one sample was NaN
    film.aovs[0] = AovPixel{glm::dvec3(2.0), glm::dvec3(0.0, 0.0, 3.0), 10.0, 2, 0};
    // Pixel (1, 0) holds no samples: black, zero AOVs, infinite depth.
    const ImageLayers layers = resolve_layers(film);
    EXPECT_EQ(layers.beauty.at(0, 0), glm::vec3(1.0f, 2.0f, 3.0f));
    EXPECT_EQ(layers.albedo.at(0, 0), glm::vec3(0.5f));  // over all 4 samples
    EXPECT_EQ(layers.normal.at(0, 0), glm::vec3(0.0f, 0.0f, 0.75f));
    EXPECT_EQ(layers.depth[0], 5.0f);  // over the 2 hits
    EXPECT_EQ(layers.sample_count[0], 4.0f);
    EXPECT_EQ(layers.beauty.at(1, 0), glm::vec3(0.0f));
    EXPECT_EQ(layers.albedo.at(1, 0), glm::vec3(0.0f));
    EXPECT_TRUE(std::isinf(layers.depth[1]));
    EXPECT_EQ(layers.sample_count[1], 0.0f);
    EXPECT_THROW((void)uniform_sample_count(film), Error);
}

// Why merge() refuses two sample ranges of one pixel, and proof that the tests above could
// fail: summing samples [0, 3) and [3, 10) separately and adding the partial sums rounds
// differently from the in-order sum for some pixels of this very scene.
TEST_F(FilmTest, AddingPartialSumsWouldNotBeBitIdentical) {
    int differing = 0;
    for (int y = 0; y < camera_.height(); ++y) {
        for (int x = 0; x < camera_.width(); ++x) {
            glm::dvec3 in_order(0.0);
            glm::dvec3 head(0.0);
            glm::dvec3 tail(0.0);
            for (std::uint32_t s = 0; s < kSpp; ++s) {
                Sampler sampler(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y), s,
                                1234);
                const glm::dvec3 l(
                    integrator_.li(scene_, camera_.generate_ray(x, y, sampler), sampler));
                in_order += l;
                (s < 3 ? head : tail) += l;
            }
            const glm::dvec3 split = head + tail;
            if (std::memcmp(&split, &in_order, sizeof split) != 0) ++differing;
        }
    }
    EXPECT_GT(differing, 0);
    // The film, continued in order, matches the in-order sums exactly.
    const Film film = one_shot(kSpp);
    Sampler sampler(5, 4, 0, 1234);
    glm::dvec3 sum(integrator_.li(scene_, camera_.generate_ray(5, 4, sampler), sampler));
    for (std::uint32_t s = 1; s < kSpp; ++s) {
        Sampler next(5, 4, s, 1234);
        sum += glm::dvec3(integrator_.li(scene_, camera_.generate_ray(5, 4, next), next));
    }
    EXPECT_EQ(std::memcmp(&film.at(5, 4).radiance, &sum, sizeof sum), 0);
}
