// Guiding's kept training passes (keep_training_samples) through every entry point: a
// film rendered by render_block in halves and joined by PassCombination::combined, and the
// final frame of render_progressive (in passes of any size, continued or not), equal
// render()'s image bit for bit. (render_mpi: tests/mpi/render_mpi_test.cpp. That the
// combination is unbiased is tested on render() in guiding_combination_test.cpp; equal
// bits carry it over.)

#include "integrator_test_util.h"

#include <librt/film/camera.h>
#include <librt/integrator/integrators.h>
#include <librt/render/pass_combination.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cstring>

namespace librt {
namespace {

PathTracerSettings kept_guiding() {
    PathTracerSettings s{5, false};
    s.guiding.enabled = true;
    s.guiding.keep_training_samples = true;
    s.guiding.training_passes = 3;  // 1 + 2 + 4 spp; passes 1 and 2 are kept
    s.guiding.spatial_threshold = 300;
    return s;
}

Scene room() {
    Scene scene;
    testing::add_room(scene);
    scene.add_sphere_light({{{-10, 20, 40}, 10}, glm::vec3(50.0f)});
    scene.commit();
    return scene;
}

Camera room_camera() {
    CameraSettings cs;
    cs.width = 20;
    cs.height = 14;
    cs.pixel_jitter = PixelJitter::Gaussian;
    return Camera(cs);
}

RenderSettings settings(int spp) {
    RenderSettings rs;
    rs.samples_per_pixel = spp;
    rs.seed = 17;
    rs.threads = 2;
    rs.adaptive.enabled = false;  // kept passes join an image of equal counts only
    return rs;
}

bool same_bits(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec3)) == 0;
}

Image reference(const Scene& scene, const Camera& camera, int spp) {
    PathTracer tracer(kept_guiding());
    return render(scene, camera, tracer, settings(spp));
}

// train() keeps the passes; the film is rendered by render_block in its two halves, each
// in two regions, with other threads and tiles than the reference: combined() is render().
TEST(KeptPasses, RenderBlockInHalvesEqualsRender) {
    const Scene scene = room();
    const Camera camera = room_camera();
    constexpr std::uint32_t kSpp = 7;  // halves of 3 and 4 samples
    const Image expected = reference(scene, camera, int(kSpp));

    PathTracer tracer(kept_guiding());
    tracer.preprocess(scene);
    RenderSettings rs = settings(int(kSpp));
    rs.threads = 1;
    rs.tile_size = 5;
    PassCombination kept;
    const RenderStats training = train(scene, camera, tracer, rs, &kept);
    EXPECT_EQ(training.training_passes, 3);
    EXPECT_EQ(kept.count(), 2);
    Film film(camera.width(), camera.height());
    const int w = camera.width(), h = camera.height();
    const auto both_regions = [&](std::uint32_t first, std::uint32_t count) {
        (void)render_block(scene, camera, tracer, film, {0, 0, w, h / 2, first, count}, rs.block());
        (void)render_block(scene, camera, tracer, film, {0, h / 2, w, h, first, count}, rs.block());
    };
    both_regions(0, kSpp / 2);
    const Film half = film;
    both_regions(kSpp / 2, kSpp - kSpp / 2);
    const Image image = kept.combined(half, film);
    EXPECT_TRUE(same_bits(image, expected));
    // Keeping changed the image: it is not the film alone.
    EXPECT_FALSE(same_bits(image, resolve(film)));
    // Without the passes (a combination that holds none) it is the film alone.
    EXPECT_TRUE(same_bits(PassCombination{}.combined(half, film), resolve(film)));
}

// render_progressive's last frame is render()'s image, whatever the pass size (a pass
// crossing half the samples ends there); the film itself holds the image's samples only.
TEST(KeptPasses, ProgressiveFinalFrameEqualsRender) {
    const Scene scene = room();
    const Camera camera = room_camera();
    const Image expected = reference(scene, camera, 8);
    for (const int pass : {1, 3, 8}) {
        PathTracer tracer(kept_guiding());
        ProgressiveSettings ps;
        ps.render = settings(8);
        ps.pass_samples = pass;
        Film film;
        Image image;
        const RenderStats stats = render_progressive(scene, camera, tracer, film, ps, &image);
        EXPECT_EQ(stats.samples_per_pixel, 8u);
        EXPECT_TRUE(same_bits(image, expected)) << "passes of " << pass;
        EXPECT_FALSE(same_bits(image, resolve(film))) << "passes of " << pass;
        // The film is the unkept render's film: the same samples.
        PathTracer unkept_tracer(kept_guiding());
        Film unkept;
        (void)render_progressive(scene, camera, unkept_tracer, unkept, ps);
        EXPECT_TRUE(same_bits(resolve(unkept), resolve(film))) << "passes of " << pass;
    }
}

// A film continued by a second call that starts at or before half the samples still ends
// at render()'s image (the second call trains again, identically); one continued from past
// the half has no record of its half and shows the film alone.
TEST(KeptPasses, ContinuedProgressiveFilm) {
    const Scene scene = room();
    const Camera camera = room_camera();
    const Image expected = reference(scene, camera, 8);
    for (const int start : {3, 4, 5}) {
        PathTracer tracer(kept_guiding());
        ProgressiveSettings ps;
        ps.render = settings(start);
        ps.pass_samples = 2;
        Film film;
        Image image;
        (void)render_progressive(scene, camera, tracer, film, ps, &image);
        EXPECT_TRUE(same_bits(image, reference(scene, camera, start))) << "first call " << start;
        ps.render.samples_per_pixel = 8;
        (void)render_progressive(scene, camera, tracer, film, ps, &image);
        if (start <= 4) {
            EXPECT_TRUE(same_bits(image, expected)) << "continued from " << start;
        } else {
            EXPECT_TRUE(same_bits(image, resolve(film))) << "continued from " << start;
        }
    }
}

// A render stopped by its time limit shows its film: the passes join only a finished image.
TEST(KeptPasses, ProgressiveStoppedEarlyShowsItsFilm) {
    const Scene scene = room();
    const Camera camera = room_camera();
    PathTracer tracer(kept_guiding());
    ProgressiveSettings ps;
    ps.render = settings(8);
    ps.pass_samples = 2;
    ps.time_limit = 1.0;
    double now = 0.0;
    ps.clock = [&now] { return now += 0.45; };  // the limit passes after 2 or 3 passes
    Film film;
    Image image;
    const RenderStats stats = render_progressive(scene, camera, tracer, film, ps, &image);
    ASSERT_TRUE(stats.time_limit_reached);
    ASSERT_LT(stats.samples_per_pixel, 8u);
    EXPECT_TRUE(same_bits(image, resolve(film)));
}

}  // namespace
}  // namespace librt
