// The sampler and pixel filter wired into the renderer (issue 15, item 1), Russian
// roulette depth semantics and RenderStats::cpu_seconds (item 5).

#include "film_test_util.h"

#include <librt/core/error.h>
#include <librt/render/renderer.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace librt {
namespace {

using testing::film_test_camera;
using testing::film_test_scene;
using testing::same_pixels;

Image render_with(const Scene& scene, const Camera& camera, const PathTracerSettings& pt,
                  SamplerKind kind, int threads, int tile, int spp = 8) {
    PathTracer integrator(pt);
    RenderSettings rs;
    rs.samples_per_pixel = spp;
    rs.threads = threads;
    rs.tile_size = tile;
    rs.seed = 7;
    rs.sampler = kind;
    rs.adaptive.enabled = false;  // every pixel spp samples (MitchellWeight... recomputes them)
    return render(scene, camera, integrator, rs);
}

// Sobol paths with roulette through every material, a filter, depth of field: the same
// bytes for any thread count and tile size (seeded by pixel, sample and seed only).
TEST(SamplerRender, SobolBitIdenticalAcrossThreadsAndTiles) {
    const Scene scene = film_test_scene();
    CameraSettings cs = film_test_camera().settings();
    cs.pixel_jitter = PixelJitter::Filter;
    cs.pixel_filter = default_filter_settings(FilterKind::Mitchell);
    const Camera camera(cs);
    const PathTracerSettings pt{6, true, 1};
    const Image one = render_with(scene, camera, pt, SamplerKind::Sobol, 1, 16);
    EXPECT_TRUE(same_pixels(one, render_with(scene, camera, pt, SamplerKind::Sobol, 2, 3)));
    EXPECT_TRUE(same_pixels(one, render_with(scene, camera, pt, SamplerKind::Sobol, 3, 7)));
    EXPECT_TRUE(same_pixels(one, render_with(scene, camera, pt, SamplerKind::Sobol, 4, 1)));
    // The kind reaches the integrator: an independent render of the same scene differs.
    EXPECT_FALSE(same_pixels(one, render_with(scene, camera, pt, SamplerKind::Independent, 1, 16)));
}

// The default is the Sobol' sampler (the best measured, docs/sampling.md): a render that
// does not name the kind is the explicit Sobol' render, not the independent one.
TEST(SamplerRender, DefaultIsSobol) {
    EXPECT_EQ(RenderSettings{}.sampler, SamplerKind::Sobol);
    const Scene scene = film_test_scene();
    const Camera camera = film_test_camera();
    PathTracer integrator(PathTracerSettings{4, true, 1});
    RenderSettings unnamed;
    unnamed.samples_per_pixel = 8;
    unnamed.seed = 7;
    unnamed.adaptive.enabled = false;
    const Image image = render(scene, camera, integrator, unnamed);
    const PathTracerSettings pt{4, true, 1};
    EXPECT_TRUE(same_pixels(image, render_with(scene, camera, pt, SamplerKind::Sobol, 2, 16)));
    EXPECT_FALSE(
        same_pixels(image, render_with(scene, camera, pt, SamplerKind::Independent, 2, 16)));
    RenderSettings bad;
    bad.sampler = static_cast<SamplerKind>(9);
    EXPECT_THROW(validate(bad), Error);
}

// The filter weight multiplies the radiance: inside a uniformly glowing sphere every
// camera sample carries radiance L, so a Mitchell pixel is exactly L times the mean of
// the weights Camera::sample_ray returns for that pixel's samples (recomputed here with
// the same samplers), which is not L since the weights are signed.
TEST(SamplerRender, MitchellWeightMultipliesRadiance) {
    Scene scene;
    Material glow = Material::diffuse(glm::vec3(0.0f));
    glow.emission = glm::vec3(2.0f, 3.0f, 4.0f);
    (void)scene.add_sphere(Sphere{{0.0f, 0.0f, 0.0f}, 10.0f}, scene.add_material(glow));
    scene.commit();
    CameraSettings cs;
    cs.position = {0.0f, 0.0f, 0.0f};
    cs.look_at = {0.0f, 0.0f, -1.0f};
    cs.width = 6;
    cs.height = 5;
    cs.pixel_jitter = PixelJitter::Filter;
    cs.pixel_filter = default_filter_settings(FilterKind::Mitchell);
    const Camera camera(cs);
    for (const SamplerKind kind : {SamplerKind::Independent, SamplerKind::Sobol}) {
        const Image image =
            render_with(scene, camera, PathTracerSettings{2, false}, kind, 2, 4, 32);
        bool some_pixel_not_l = false;
        for (int y = 0; y < cs.height; ++y) {
            for (int x = 0; x < cs.width; ++x) {
                glm::dvec3 sum(0.0);
                for (std::uint32_t s = 0; s < 32; ++s) {
                    Sampler sampler(kind, std::uint32_t(x), std::uint32_t(y), s, 7);
                    sum += glm::dvec3(glow.emission * camera.sample_ray(x, y, sampler).weight);
                }
                const glm::vec3 expected(sum / 32.0);
                const glm::vec3 got = image.pixels[std::size_t(y * cs.width + x)];
                EXPECT_EQ(got, expected) << x << ", " << y;
                some_pixel_not_l = some_pixel_not_l || got != glow.emission;
            }
        }
        EXPECT_TRUE(some_pixel_not_l);
    }
}

// Roulette depth d leaves every path of at most d bounces untouched: with max_depth =
// d (bounces 0 .. d - 1) a roulette render is bit-identical to one without, and roulette
// from one bounce earlier changes it. Before the fix, depths 0 and 1 were the same. A
// glowing diffuse sphere (an emitter no light samples) makes the last bounce trace its
// BSDF ray, so roulette there shows.
TEST(SamplerRender, RouletteDepthCountsBounces) {
    Scene scene;
    const auto white = scene.add_material(Material::diffuse(glm::vec3(0.8f, 0.7f, 0.6f)));
    Material glow = Material::diffuse(glm::vec3(0.5f));
    glow.emission = glm::vec3(4.0f);
    (void)scene.add_sphere(Sphere{{0.0f, -1000.0f, 0.0f}, 999.0f}, white);
    (void)scene.add_sphere(Sphere{{-1.2f, 0.0f, 0.0f}, 0.8f}, scene.add_material(glow));
    (void)scene.add_sphere(Sphere{{1.2f, 0.0f, 0.5f}, 0.7f}, white);
    (void)scene.add_sphere_light({{{0.0f, 3.0f, 1.0f}, 0.5f}, glm::vec3(20.0f)});
    scene.commit();
    const Camera camera = film_test_camera(13, 9);
    for (const SamplerKind kind : {SamplerKind::Independent, SamplerKind::Sobol}) {
        for (int d = 1; d <= 3; ++d) {
            const Image plain = render_with(scene, camera, {d, false}, kind, 2, 16);
            EXPECT_TRUE(same_pixels(plain, render_with(scene, camera, {d, true, d}, kind, 2, 16)))
                << "depth " << d;
            EXPECT_FALSE(
                same_pixels(plain, render_with(scene, camera, {d, true, d - 1}, kind, 2, 16)))
                << "depth " << d;
        }
        // Depths 0 and 1 differ (they were identical before the fix).
        EXPECT_FALSE(same_pixels(render_with(scene, camera, {4, true, 0}, kind, 2, 16),
                                 render_with(scene, camera, {4, true, 1}, kind, 2, 16)));
    }
}

// CPU seconds are measured: positive for a render that does work, and no more than the
// threads could have used in the wall time (with slack for the clock's granularity).
TEST(SamplerRender, StatsCountCpuSeconds) {
    const Scene scene = film_test_scene();
    const Camera camera = film_test_camera(64, 48);
    PathTracer integrator(PathTracerSettings{5, false});
    RenderSettings rs;
    rs.samples_per_pixel = 16;
    rs.threads = 2;
    RenderStats stats;
    (void)render(scene, camera, integrator, rs, &stats);
    EXPECT_GT(stats.cpu_seconds, 0.0);
    EXPECT_LE(stats.cpu_seconds, 2.0 * stats.seconds + 0.05);
}

}  // namespace
}  // namespace librt
