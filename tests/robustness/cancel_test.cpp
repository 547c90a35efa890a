// Cancellation (set from inside the render, at a counted sample), and many threads
// rendering one real scene. These are among the ThreadSanitizer preset's targets (its
// filter in CMakePresets.json).

#include "render/cancelling_integrator.h"

#include <librt/film/camera.h>
#include <librt/geometry/procedural.h>
#include <librt/integrator/integrators.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cstring>

using namespace librt;
using librt::testing::CancellingIntegrator;

namespace {

/// A closed mirror box around a diffuse teapot, lit by a sphere light: every path runs
/// to max_depth, so samples are slow and there are many of them.
Scene slow_scene() {
    Scene scene;
    const auto white = scene.add_material(Material::diffuse(glm::vec3(0.9f)));
    const auto chrome = scene.add_material(Material::mirror(glm::vec3(0.95f)));
    TriangleMesh box = make_box({-5, -5, -5}, {5, 5, 5});
    (void)scene.add_mesh(box, chrome);
    (void)scene.add_mesh(make_teapot(8), white);
    (void)scene.add_sphere_light({{{0, 3, 0}, 0.5f}, glm::vec3(10.0f)});
    scene.commit();
    return scene;
}

CameraSettings inside_camera(int size) {
    CameraSettings cs;
    cs.position = {0, 1, 4};
    cs.look_at = {0, 0, 0};
    cs.width = cs.height = size;
    cs.pixel_jitter = PixelJitter::Gaussian;
    return cs;
}

}  // namespace

// The render would take minutes (2^20 samples per pixel, 100 bounces); cancelled by its
// 200th sample, each thread must stop within 64 samples (the flag is honoured inside a
// pixel, not only between rows or tiles).
TEST(Cancellation, ASlowRenderStopsPromptly) {
    const Scene scene = slow_scene();
    const Camera camera(inside_camera(4));  // one tile, so only the per-pixel checks can stop it
    PathTracer tracer(PathTracerSettings{100, false});
    std::atomic<bool> cancel{false};
    CancellingIntegrator integrator(cancel, 200, &tracer);
    RenderSettings settings;
    settings.samples_per_pixel = 1 << 20;
    settings.threads = 2;
    settings.progress = nullptr;
    settings.cancel = &cancel;
    RenderStats stats;
    const Image image = render(scene, camera, integrator, settings, &stats);
    EXPECT_TRUE(stats.cancelled);
    EXPECT_GE(stats.samples, 200u);
    EXPECT_LE(stats.samples, integrator.max_samples(2, 64));
    EXPECT_EQ(image.width, 4);  // the partial image is still a whole film
}

TEST(Cancellation, CancelledBeforeTheStartRendersNothing) {
    const Scene scene = slow_scene();
    PathTracer integrator(PathTracerSettings{5, false});
    std::atomic<bool> cancel{true};
    RenderSettings settings;
    settings.samples_per_pixel = 64;
    settings.threads = 4;
    settings.progress = nullptr;
    settings.cancel = &cancel;
    RenderStats stats;
    const Image image = render(scene, Camera(inside_camera(64)), integrator, settings, &stats);
    EXPECT_TRUE(stats.cancelled);
    EXPECT_EQ(stats.samples, 0u);
    for (const glm::vec3& p : image.pixels) ASSERT_EQ(p, glm::vec3(0.0f));
}

// Cancelled by its 3000th sample, in the middle of the first tiles: every one of the 8
// threads (more than the cores) stops within 64 samples of its own.
TEST(Cancellation, ManyThreadsCancelledMidTile) {
    const Scene scene = slow_scene();
    PathTracer tracer(PathTracerSettings{20, false});
    std::atomic<bool> cancel{false};
    CancellingIntegrator integrator(cancel, 3000, &tracer);
    RenderSettings settings;
    settings.samples_per_pixel = 4096;
    settings.threads = 8;  // more threads than cores: cancellation must reach them all
    settings.tile_size = 3;
    settings.progress = nullptr;
    settings.cancel = &cancel;
    RenderStats stats;
    const Image image = render(scene, Camera(inside_camera(32)), integrator, settings, &stats);
    EXPECT_TRUE(stats.cancelled);
    EXPECT_GE(stats.samples, 3000u);
    EXPECT_LE(stats.samples, integrator.max_samples(8, 64));
    EXPECT_EQ(stats.nonfinite_samples, 0u);
    EXPECT_EQ(image.pixels.size(), 32u * 32u);
}

// The scene, its meshes' BVHs, the integrators' counters and the film shared by many
// threads: the image must not depend on how many there are (and ThreadSanitizer must
// find no race).
TEST(Multithreaded, RealSceneIsIdenticalForAnyThreadCount) {
    const Scene scene = slow_scene();
    const Camera camera(inside_camera(16));
    PathTracer integrator(PathTracerSettings{6, true, 2});
    RenderSettings settings;
    settings.samples_per_pixel = 3;
    settings.progress = nullptr;
    settings.seed = 9;
    settings.threads = 1;
    const Image reference = render(scene, camera, integrator, settings);
    for (const int threads : {2, 5}) {
        settings.threads = threads;
        settings.tile_size = threads + 1;
        const Image image = render(scene, camera, integrator, settings);
        ASSERT_EQ(image.pixels.size(), reference.pixels.size());
        EXPECT_EQ(std::memcmp(image.pixels.data(), reference.pixels.data(),
                              image.pixels.size() * sizeof(glm::vec3)),
                  0)
            << threads << " threads";
    }
    EXPECT_EQ(integrator.nonfinite_count(), 0u);
}
