// Integrators that splat (Integrator::splats) through every render entry point: images
// known in closed form (splats of 1 at each sample's own pixel resolve to 1; the sums of
// splats anywhere total their count), and the same bits from render(), render_block split
// by region and by sample range, render_progressive and the kept training passes, for any
// thread count and tile size. An integrator that does not splat renders through li() as
// before. (render_mpi: tests/mpi/render_mpi_test.cpp.)

#include "render/film_test_util.h"
#include "render/splat_test_util.h"

#include <librt/core/error.h>
#include <librt/render/pass_combination.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

namespace librt {
namespace {

using testing::OwnPixelSplatter;
using testing::RandomSplatter;
using testing::same_pixels;
using testing::same_records;
using testing::splat_test_camera;

Scene empty_scene() {
    Scene scene;
    scene.commit();
    return scene;
}

RenderSettings settings(int spp, int threads = 2, int tile = 16) {
    RenderSettings rs;
    rs.samples_per_pixel = spp;
    rs.seed = 31;
    rs.threads = threads;
    rs.tile_size = tile;
    rs.adaptive.enabled = false;  // render() against blocks of every pixel's samples
    return rs;
}

RandomSplatter::Options spread(bool trains = false) {
    RandomSplatter::Options o;
    o.margin = 3.0f;  // some splats fall partly or wholly off the film
    o.trains = trains;
    return o;
}

bool same_splats(const Film& a, const Film& b) {
    return a.splats.has_value() == b.splats.has_value() &&
           (!a.splats || a.splats->sums() == b.splats->sums());
}

// Every sample splats 1 at its own pixel centre with a box filter: each pixel's sum is its
// sample count exactly, so every pixel resolves to 1 (no rounding: 1 is a multiple of
// 2^-28), whatever the split.
TEST(SplatRender, OwnPixelSplatsResolveToOne) {
    const Scene scene = empty_scene();
    const Camera camera = splat_test_camera(13, 9, true);
    OwnPixelSplatter integrator;
    RenderStats stats;
    const Image image = render(scene, camera, integrator, settings(3), &stats);
    EXPECT_EQ(stats.samples, 13u * 9u * 3u);
    for (const glm::vec3& p : image.pixels) EXPECT_EQ(p, glm::vec3(1.0f));

    // A film split by region and sample range holds the same sums: spp per pixel.
    Film film(camera.width(), camera.height());
    const RenderSettings rs = settings(1, 1, 4);
    (void)render_block(scene, camera, integrator, film, {0, 0, 13, 4, 0, 3}, rs.block());
    (void)render_block(scene, camera, integrator, film, {0, 4, 13, 9, 0, 1}, rs.block());
    (void)render_block(scene, camera, integrator, film, {0, 4, 13, 9, 1, 2}, rs.block());
    ASSERT_TRUE(film.splats.has_value());
    EXPECT_EQ(film.splats->width(), 13);
    EXPECT_EQ(film.splats->height(), 9);
    const std::int64_t three = std::int64_t{3} << SplatFilm::kDefaultFractionBits;
    for (const std::int64_t sum : film.splats->sums()) EXPECT_EQ(sum, three);
    EXPECT_TRUE(same_pixels(resolve(film), image));
}

// A render stopped part-way divides the splats by the mean sample count
// (splat_samples_per_pixel): pixels holding 2 and 4 samples, mean 3, resolve to 2/3 and
// 4/3 - the light of 3 x (pixels) camera samples, each pixel's share as it was taken.
TEST(SplatRender, StoppedRenderDividesByTheMeanSampleCount) {
    const Scene scene = empty_scene();
    const Camera camera = splat_test_camera(8, 6, true);
    OwnPixelSplatter integrator;
    Film film(camera.width(), camera.height());
    (void)render_block(scene, camera, integrator, film, {0, 0, 8, 3, 0, 2}, settings(1).block());
    (void)render_block(scene, camera, integrator, film, {0, 3, 8, 6, 0, 4}, settings(1).block());
    EXPECT_EQ(splat_samples_per_pixel(film), 3.0);
    const Image image = resolve(film);
    for (int y = 0; y < 6; ++y) {
        for (int x = 0; x < 8; ++x) {
            const float expected = static_cast<float>((y < 3 ? 2.0 : 4.0) / 3.0);
            EXPECT_EQ(image.at(x, y), glm::vec3(expected)) << x << ", " << y;
        }
    }
    // A film of no samples resolves to black, splats or not.
    Film empty(camera.width(), camera.height());
    empty.splats.emplace(8, 6);
    EXPECT_EQ(splat_samples_per_pixel(empty), 0.0);
    for (const glm::vec3& p : resolve(empty).pixels) EXPECT_EQ(p, glm::vec3(0.0f));
}

// Splats of exactly (1, 1/2, 1/4) at uniform positions inside the image, box filter: every
// splat lands whole, so the sums total N (1, 1/2, 1/4) exactly for N camera samples, and
// the image total is N / spp (1, 1/2, 1/4) = W H (1, 1/2, 1/4) up to float rounding.
TEST(SplatRender, SplatsAtRandomPositionsTotalTheirCount) {
    const Scene scene = empty_scene();
    const Camera camera = splat_test_camera(11, 7, true);
    RandomSplatter::Options o;
    o.fixed = true;
    RandomSplatter integrator(o);
    constexpr int kSpp = 4;
    Film film(camera.width(), camera.height());
    (void)render_block(scene, camera, integrator, film, {0, 0, 11, 7, 0, kSpp},
                       settings(kSpp).block());
    ASSERT_TRUE(film.splats.has_value());
    const std::int64_t n = 11 * 7 * kSpp;
    std::int64_t total[3] = {0, 0, 0};
    const std::vector<std::int64_t>& sums = film.splats->sums();
    for (std::size_t i = 0; i < sums.size(); ++i) total[i % 3] += sums[i];
    const int k = SplatFilm::kDefaultFractionBits;
    EXPECT_EQ(total[0], n << k);
    EXPECT_EQ(total[1], n << (k - 1));
    EXPECT_EQ(total[2], n << (k - 2));
    EXPECT_EQ(film.splats->clipped(), 0u);

    // The splats' share of the image: resolve() minus the pixel means.
    Film means = film;
    means.splats.reset();
    const Image with = resolve(film);
    const Image without = resolve(means);
    glm::dvec3 image_total(0.0);
    for (std::size_t i = 0; i < with.pixels.size(); ++i)
        image_total += glm::dvec3(with.pixels[i]) - glm::dvec3(without.pixels[i]);
    EXPECT_NEAR(image_total.x, 77.0, 1e-4);
    EXPECT_NEAR(image_total.y, 38.5, 1e-4);
    EXPECT_NEAR(image_total.z, 19.25, 1e-4);
}

// Splats with a random factor anywhere (partly off the film), a Gaussian filter: the same
// bits for 1, 2 and 4 threads and any tile size.
TEST(SplatRender, ImageIsIdenticalForAnyThreadCountAndTileSize) {
    const Scene scene = empty_scene();
    const Camera camera = splat_test_camera(23, 17, false);
    RandomSplatter integrator(spread());
    const Image reference = render(scene, camera, integrator, settings(5, 1, 16));
    // The splats show: the image is not the pixel means alone.
    Film film(camera.width(), camera.height());
    (void)render_block(scene, camera, integrator, film, {0, 0, 23, 17, 0, 5}, settings(5).block());
    Film means = film;
    means.splats.reset();
    EXPECT_FALSE(same_pixels(resolve(means), reference));
    EXPECT_TRUE(same_pixels(resolve(film), reference));
    for (const int threads : {1, 2, 4}) {
        for (const int tile : {1, 4, 7, 64}) {
            const Image image = render(scene, camera, integrator, settings(5, threads, tile));
            EXPECT_TRUE(same_pixels(image, reference)) << threads << " threads, tile " << tile;
        }
    }
}

// render() equals render_block by region (onto one film and onto two films merged) and
// by sample range, and render_progressive in passes of any size, continued or not.
TEST(SplatRender, EveryEntryPointGivesRendersImage) {
    const Scene scene = empty_scene();
    const Camera camera = splat_test_camera(19, 14, false);
    RandomSplatter integrator(spread());
    constexpr std::uint32_t kSpp = 6;
    const Image expected = render(scene, camera, integrator, settings(int(kSpp)));
    const int w = camera.width(), h = camera.height();
    const RenderSettings rs = settings(1, 3, 5);

    Film regions(w, h);
    (void)render_block(scene, camera, integrator, regions, {0, 0, 7, h, 0, kSpp}, rs.block());
    (void)render_block(scene, camera, integrator, regions, {7, 0, w, h, 0, kSpp}, rs.block());
    EXPECT_TRUE(same_pixels(resolve(regions), expected));

    Film left(w, h), right(w, h);
    (void)render_block(scene, camera, integrator, left, {0, 0, 7, h, 0, kSpp}, rs.block());
    (void)render_block(scene, camera, integrator, right, {7, 0, w, h, 0, kSpp}, rs.block());
    merge(left, right);
    EXPECT_TRUE(same_records(left, regions));
    EXPECT_TRUE(same_splats(left, regions));
    EXPECT_TRUE(same_pixels(resolve(left), expected));

    Film ranges(w, h);
    (void)render_block(scene, camera, integrator, ranges, {0, 0, w, h, 0, 2}, rs.block());
    (void)render_block(scene, camera, integrator, ranges, {0, 0, w, h, 2, kSpp - 2}, rs.block());
    EXPECT_TRUE(same_splats(ranges, regions));
    EXPECT_TRUE(same_pixels(resolve(ranges), expected));

    for (const int pass : {1, 4, 6}) {
        ProgressiveSettings ps;
        ps.render = settings(int(kSpp), 2, 3);
        ps.pass_samples = pass;
        Film film;
        Image image;
        const RenderStats stats = render_progressive(scene, camera, integrator, film, ps, &image);
        EXPECT_EQ(stats.samples_per_pixel, kSpp);
        EXPECT_TRUE(same_pixels(image, expected)) << "passes of " << pass;
        EXPECT_TRUE(same_splats(film, regions)) << "passes of " << pass;
    }
    // Resumed: 2 samples, then on to 6.
    ProgressiveSettings ps;
    ps.render = settings(2);
    Film film;
    (void)render_progressive(scene, camera, integrator, film, ps);
    ps.render.samples_per_pixel = int(kSpp);
    Image image;
    (void)render_progressive(scene, camera, integrator, film, ps, &image);
    EXPECT_TRUE(same_pixels(image, expected));
}

// Kept training passes of a splatting integrator: train() keeps them with their splats, a
// film rendered by render_block in halves joined by combined() is render()'s image, and so
// is render_progressive's final frame.
TEST(SplatRender, KeptTrainingPassesGiveRendersImage) {
    const Scene scene = empty_scene();
    const Camera camera = splat_test_camera(17, 12, false);
    constexpr std::uint32_t kSpp = 5;
    RandomSplatter reference(spread(true));
    const Image expected = render(scene, camera, reference, settings(int(kSpp)));

    RandomSplatter integrator(spread(true));
    integrator.preprocess(scene);
    const RenderSettings rs = settings(int(kSpp), 1, 4);
    PassCombination kept;
    const RenderStats training = train(scene, camera, integrator, rs, &kept);
    EXPECT_EQ(training.training_passes, 2);
    EXPECT_EQ(kept.count(), 2);
    const int w = camera.width(), h = camera.height();
    Film film(w, h);
    (void)render_block(scene, camera, integrator, film, {0, 0, w, h, 0, kSpp / 2}, rs.block());
    const Film half = film;
    (void)render_block(scene, camera, integrator, film, {0, 0, w, h, kSpp / 2, kSpp - kSpp / 2},
                       rs.block());
    const Image image = kept.combined(half, film);
    EXPECT_TRUE(same_pixels(image, expected));
    EXPECT_FALSE(same_pixels(image, resolve(film)));  // the passes changed it

    // The splats count in the combination: the same passes without them give another image.
    Film half_means = half, film_means = film;
    half_means.splats.reset();
    film_means.splats.reset();
    EXPECT_FALSE(same_pixels(kept.combined(half_means, film_means), expected));

    for (const int pass : {1, 3}) {
        RandomSplatter progressive(spread(true));
        ProgressiveSettings ps;
        ps.render = settings(int(kSpp), 2, 7);
        ps.pass_samples = pass;
        Film pfilm;
        Image pimage;
        (void)render_progressive(scene, camera, progressive, pfilm, ps, &pimage);
        EXPECT_TRUE(same_pixels(pimage, expected)) << "passes of " << pass;
    }
}

// An integrator that does not splat renders through li() exactly as before: each pixel the
// float of the double sum of its weighted samples over their count, no splat film, and
// li_splatting (which would splat) is never called.
TEST(SplatRender, NonSplattingIntegratorRendersThroughLi) {
    class Plain final : public Integrator {
    public:
        [[nodiscard]] glm::vec3 li(const Scene& /*scene*/, const Ray& ray,
                                   Sampler& sampler) const override {
            const glm::vec2 b = sampler.next_2d();
            return {b.x + ray.direction.x, b.y * ray.origin.y, sampler.next_1d()};
        }
        [[nodiscard]] glm::vec3 li_splatting(const Scene& /*scene*/, const Ray& /*ray*/,
                                             Sampler& /*sampler*/,
                                             const SplatTarget& target) const override {
            target.film->add({0.5f, 0.5f}, glm::vec3(1.0f));  // would crash: no target
            return glm::vec3(-1.0f);
        }
    };
    const Scene scene = empty_scene();
    const Camera camera = splat_test_camera(9, 7, false);
    Plain integrator;
    RenderSettings rs = settings(4, 2, 3);
    rs.sampler = SamplerKind::Sobol;
    const Image image = render(scene, camera, integrator, rs);
    Image expected(9, 7);
    for (int y = 0; y < 7; ++y) {
        for (int x = 0; x < 9; ++x) {
            glm::dvec3 sum(0.0);
            for (std::uint32_t s = 0; s < 4; ++s) {
                Sampler sampler(rs.sampler, std::uint32_t(x), std::uint32_t(y), s, rs.seed);
                const CameraRay ray = camera.sample_ray(x, y, sampler);
                sum += glm::dvec3(integrator.li(scene, ray.ray, sampler) * ray.weight);
            }
            expected.at(x, y) = glm::vec3(sum / 4.0);
        }
    }
    EXPECT_TRUE(same_pixels(image, expected));
    Film film(9, 7);
    (void)render_block(scene, camera, integrator, film, {0, 0, 9, 7, 0, 4}, rs.block());
    EXPECT_FALSE(film.splats.has_value());
    EXPECT_TRUE(same_pixels(resolve(film), expected));
}

// A region film (FilmOrigin) keeps splats of the whole image, which resolve() refuses; a
// film whose splats are not the camera's size is refused before rendering; films whose
// splat films differ (here in scale) do not merge, and a refused merge changes nothing.
TEST(SplatRender, MismatchedSplatFilmsAreRefused) {
    const Scene scene = empty_scene();
    const Camera camera = splat_test_camera(10, 8, true);
    OwnPixelSplatter integrator;
    Film region(4, 3);
    (void)render_block(scene, camera, integrator, region, FilmOrigin{2, 2}, {2, 2, 6, 5, 0, 2},
                       settings(1).block());
    ASSERT_TRUE(region.splats.has_value());
    EXPECT_EQ(region.splats->width(), 10);
    EXPECT_THROW((void)resolve(region), Error);

    Film film(10, 8);
    film.splats.emplace(9, 8);  // not the camera's size
    EXPECT_THROW((void)render_block(scene, camera, integrator, film, {0, 0, 10, 8, 0, 1},
                                    settings(1).block()),
                 Error);
    EXPECT_EQ(film.pixels[0].samples, 0u);
    Film other(10, 8);
    (void)render_block(scene, camera, integrator, other, {0, 0, 5, 8, 0, 1}, settings(1).block());
    Film into(10, 8);
    into.splats.emplace(10, 8, FilterSettings{}, 20);
    EXPECT_THROW(merge(into, other), Error);
    EXPECT_EQ(into.pixels[0].samples, 0u);
}

}  // namespace
}  // namespace librt
