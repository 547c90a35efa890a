// Cancellation from another thread, and many threads rendering one real scene. These are
// among the ThreadSanitizer preset's targets (its filter in CMakePresets.json).

#include <librt/geometry/procedural.h>
#include <librt/render/camera.h>
#include <librt/render/integrators.h>
#include <librt/render/renderer.h>
#include <librt/render/scene.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>

using namespace librt;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

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

// The render would take minutes (2^20 samples per pixel, 100 bounces); cancelled after
// 50 ms it must return within 2 s. The bound is about correctness (the flag is honoured
// inside a pixel, not only between rows or tiles), not speed.
TEST(Cancellation, ASlowRenderStopsPromptly) {
    const Scene scene = slow_scene();
    const Camera camera(inside_camera(4));  // one tile, so only the per-pixel checks can stop it
    PathTracer integrator(PathTracerSettings{100, false});
    std::atomic<bool> cancel{false};
    RenderSettings settings;
    settings.samples_per_pixel = 1 << 20;
    settings.threads = 2;
    settings.progress = nullptr;
    settings.cancel = &cancel;
    RenderStats stats;
    Clock::time_point cancelled_at;
    std::thread canceller([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        cancelled_at = Clock::now();
        cancel.store(true);
    });
    const Image image = render(scene, camera, integrator, settings, &stats);
    const Clock::time_point returned_at = Clock::now();
    canceller.join();
    EXPECT_TRUE(stats.cancelled);
    EXPECT_LT(std::chrono::duration<double>(returned_at - cancelled_at).count(), 2.0);
    EXPECT_GT(stats.samples, 0u);
    EXPECT_LT(stats.samples, std::uint64_t{16} << 20);
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
    const auto start = Clock::now();
    const Image image = render(scene, Camera(inside_camera(64)), integrator, settings, &stats);
    EXPECT_LT(seconds_since(start), 2.0);
    EXPECT_TRUE(stats.cancelled);
    EXPECT_EQ(stats.samples, 0u);
    for (const glm::vec3& p : image.pixels) ASSERT_EQ(p, glm::vec3(0.0f));
}

TEST(Cancellation, ManyThreadsCancelledMidTile) {
    const Scene scene = slow_scene();
    PathTracer integrator(PathTracerSettings{20, false});
    std::atomic<bool> cancel{false};
    RenderSettings settings;
    settings.samples_per_pixel = 4096;
    settings.threads = 8;  // more threads than cores: cancellation must reach them all
    settings.tile_size = 3;
    settings.progress = nullptr;
    settings.cancel = &cancel;
    RenderStats stats;
    std::thread canceller([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(30));
        cancel.store(true);
    });
    const auto start = Clock::now();
    const Image image = render(scene, Camera(inside_camera(32)), integrator, settings, &stats);
    canceller.join();
    EXPECT_LT(seconds_since(start), 5.0);
    EXPECT_TRUE(stats.cancelled);
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
