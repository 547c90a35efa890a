// RenderSettings::region (film/pixel_region.h): a render of part of the image gives its
// pixels exactly the records, and so the image bits, of the whole-image render with the same
// settings, whatever the threads and tiles, with and without adaptive sampling (whose pilot
// then covers the whole image) and AOVs, in render() and render_progressive(); crop() cuts
// them out; a region outside the image, an empty one, a splatting integrator and a resumed
// progressive film are refused with an error naming the region.

#include "render/film_test_util.h"

#include <librt/core/error.h>
#include <librt/film/pixel_region.h>
#include <librt/integrator/bdpt.h>
#include <librt/render/noise_estimate.h>
#include <librt/render/renderer.h>

#include <gtest/gtest.h>

#include <functional>
#include <string>

using namespace librt;
using librt::testing::film_test_camera;
using librt::testing::film_test_scene;
using librt::testing::same_pixels;
using librt::testing::same_records;

namespace {

RenderSettings settings_of(bool adaptive, SamplerKind sampler, int threads, int tile) {
    RenderSettings s;
    s.samples_per_pixel = 16;
    s.seed = 7;
    s.sampler = sampler;
    s.adaptive.enabled = adaptive;
    s.adaptive.radius = 2;
    s.threads = threads;
    s.tile_size = tile;
    return s;
}

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace

TEST(PixelRegion, RegionRenderHoldsTheWholeRendersRecords) {
    const Scene scene = film_test_scene();
    const Camera camera = film_test_camera();  // 29 x 19
    const PixelRegion region{5, 3, 17, 14};
    for (const bool adaptive : {false, true}) {
        for (const SamplerKind sampler : {SamplerKind::Independent, SamplerKind::Sobol}) {
            PathTracer integrator;
            Film whole(camera.width(), camera.height(), true);
            (void)render(scene, camera, integrator, whole, settings_of(adaptive, sampler, 1, 5));
            // Other threads and tiles for the region: its records cannot depend on them.
            RenderSettings s = settings_of(adaptive, sampler, 2, 8);
            s.region = region;
            Film part(camera.width(), camera.height(), true);
            const RenderStats stats = render(scene, camera, integrator, part, s);
            const std::string what = std::string(adaptive ? "adaptive" : "uniform") + ", " +
                                     (sampler == SamplerKind::Sobol ? "sobol" : "independent");
            EXPECT_TRUE(same_records(crop(part, region), crop(whole, region))) << what;
            // Outside: nothing, or (adaptive) the pilot over the whole image.
            const std::uint32_t outside = adaptive ? adaptive_pilot_samples(s.adaptive, 16) : 0;
            EXPECT_EQ(part.at(0, 0).samples, outside) << what;
            EXPECT_EQ(part.at(28, 18).samples, outside) << what;
            EXPECT_LT(stats.samples, 16u * 29u * 19u) << what;
            EXPECT_EQ(crop(resolve(part), region).pixels, resolve(crop(part, region)).pixels);
        }
    }
}

TEST(PixelRegion, RenderedImagesMatchInRenderAndRenderProgressive) {
    const Scene scene = film_test_scene();
    const Camera camera = film_test_camera();
    const PixelRegion region{0, 10, 29, 19};         // the bottom rows, to the image's edges
    librt::testing::WideRangeIntegrator integrator;  // summation order shows in its bits
    const RenderSettings whole_settings = settings_of(true, SamplerKind::Sobol, 2, 4);
    const Image whole = render(scene, camera, integrator, whole_settings);
    RenderSettings s = whole_settings;
    s.region = region;
    s.threads = 1;
    EXPECT_TRUE(
        same_pixels(crop(render(scene, camera, integrator, s), region), crop(whole, region)));
    ProgressiveSettings ps;
    ps.render = s;
    ps.pass_samples = 3;
    ps.aovs = true;
    Film film;
    Image image;
    const RenderStats stats = render_progressive(scene, camera, integrator, film, ps, &image);
    EXPECT_EQ(stats.samples_per_pixel, 16u);
    EXPECT_TRUE(same_pixels(crop(image, region), crop(whole, region)));
    EXPECT_EQ(film.width, camera.width());
}

TEST(PixelRegion, NoiseTargetLooksAtTheRegionAlone) {
    // A progressive render of a region with a noise target it cannot reach runs to its
    // samples; its estimate is the region's: the same as a render of the region's own film
    // when the rest of the image holds nothing (no adaptive pilot outside).
    const Scene scene = film_test_scene();
    const Camera camera = film_test_camera();
    PathTracer integrator;
    ProgressiveSettings ps;
    ps.render = settings_of(false, SamplerKind::Independent, 2, 8);
    ps.render.region = {3, 2, 20, 11};
    ps.noise_target = 1e-9;
    Film film;
    const RenderStats stats = render_progressive(scene, camera, integrator, film, ps);
    EXPECT_FALSE(stats.noise_target_reached);
    EXPECT_EQ(stats.samples_per_pixel, 16u);
    EXPECT_GT(stats.noise, 0.0);
    // The estimate over the region's records, from a NoiseEstimate fed the same levels.
    // Passes of 1: the snapshot is renewed at levels 1, 2, 4, 8, 16.
    ProgressiveSettings again = ps;
    Film part;
    NoiseEstimate estimate;
    again.pass_done = [&](const Film& f, std::uint32_t level) {
        estimate.observe(crop(f, ps.render.region), level);
    };
    (void)render_progressive(scene, camera, integrator, part, again);
    ASSERT_TRUE(estimate.relative_error().has_value());
    EXPECT_EQ(stats.noise, *estimate.relative_error());
}

TEST(PixelRegion, BadRegionsAndUsesAreRefused) {
    const Scene scene = film_test_scene();
    const Camera camera = film_test_camera();
    PathTracer integrator;
    RenderSettings s;
    s.region = {20, 0, 30, 5};  // one column past the 29-pixel width
    EXPECT_NE(message_of([&] { (void)render(scene, camera, integrator, s); })
                  .find("region [20, 30) x [0, 5): must be a non-empty rectangle within the 29 "
                        "x 19 image"),
              std::string::npos);
    s.region = {4, 4, 4, 9};  // empty
    EXPECT_NE(message_of([&] { validate(s); }).find("region [4, 4) x [4, 9): must be non-empty"),
              std::string::npos);
    s.region = {-1, 0, 3, 3};
    EXPECT_THROW(validate(s), Error);
    // A splatting integrator, render_block and a film holding samples.
    s.region = {1, 1, 5, 5};
    BidirectionalPathTracer bdpt;
    EXPECT_NE(message_of([&] {
                  (void)render(scene, camera, bdpt, s);
              }).find("region: the integrator splats"),
              std::string::npos);
    // render_block takes BlockSettings, which has no region (the block says the pixels):
    // a RenderSettings with one does not compile there (AdaptiveSampling's test says how).
    Film film(camera.width(), camera.height());
    RenderSettings one;
    integrator.preprocess(scene);
    (void)render_block(scene, camera, integrator, film,
                       {0, 0, camera.width(), camera.height(), 0, 1}, one.block());
    ProgressiveSettings ps;
    ps.render = s;
    EXPECT_NE(message_of([&] {
                  (void)render_progressive(scene, camera, integrator, film, ps);
              }).find("a progressive render of a region starts from an empty film"),
              std::string::npos);
}

TEST(PixelRegion, CropCutsImagesAndFilms) {
    Image image(4, 3);
    for (int i = 0; i < 12; ++i) image.pixels[i] = glm::vec3(float(i));
    const Image part = crop(image, {1, 1, 3, 3});
    ASSERT_EQ(part.width, 2);
    ASSERT_EQ(part.height, 2);
    EXPECT_EQ(part.at(0, 0), glm::vec3(5.0f));
    EXPECT_EQ(part.at(1, 1), glm::vec3(10.0f));
    EXPECT_TRUE(same_pixels(crop(image, PixelRegion{}), image));  // whole
    EXPECT_THROW((void)crop(image, {3, 0, 5, 1}), Error);
    Film film(4, 3, true);
    film.at(2, 1).samples = 9;
    film.aovs[film.index(2, 1)].hits = 4;
    const Film cut = crop(film, {2, 1, 4, 2});
    EXPECT_EQ(cut.width, 2);
    EXPECT_EQ(cut.height, 1);
    EXPECT_EQ(cut.at(0, 0).samples, 9u);
    EXPECT_EQ(cut.aovs[0].hits, 4u);
    film.splats = SplatFilm(4, 3);
    EXPECT_THROW((void)crop(film, {0, 0, 1, 1}), Error);
    const PixelRegion all = region_in({}, 7, 5);
    EXPECT_EQ(all.x1, 7);
    EXPECT_EQ(all.y1, 5);
}
