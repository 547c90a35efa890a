#include "render/cancelling_integrator.h"

#include <librt/core/error.h>
#include <librt/integrator/integrators.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

using namespace librt;

namespace {

// A colour that depends on every random number the camera and the integrator draw, so
// any change in how samplers are seeded or consumed changes the image.
class HashIntegrator final : public Integrator {
public:
    void preprocess(const Scene& /*scene*/) override { ++preprocess_calls; }
    [[nodiscard]] glm::vec3 li(const Scene& /*scene*/, const Ray& ray,
                               Sampler& sampler) const override {
        const float a = sampler.next_1d();
        const glm::vec2 b = sampler.next_2d();
        return {a + ray.direction.x, b.x * ray.origin.y, b.y - ray.direction.y};
    }
    int preprocess_calls = 0;
};

// NaN on a random half of the left-hand samples, 1 elsewhere.
class SometimesNan final : public Integrator {
public:
    [[nodiscard]] glm::vec3 li(const Scene& /*scene*/, const Ray& ray,
                               Sampler& sampler) const override {
        if (ray.direction.x < 0.0f && sampler.next_1d() < 0.5f) {
            return {std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f};
        }
        return glm::vec3(1.0f);
    }
};

class Throwing final : public Integrator {
public:
    [[nodiscard]] glm::vec3 li(const Scene& /*scene*/, const Ray& ray,
                               Sampler& /*sampler*/) const override {
        if (ray.direction.x > 0.2f) throw std::runtime_error("integrator failure");
        return glm::vec3(0.5f);
    }
};

Camera small_camera(int w, int h, bool jitter = true) {
    CameraSettings s;
    s.width = w;
    s.height = h;
    s.position = {0.0f, 1.0f, 5.0f};
    if (jitter) {
        s.pixel_jitter = PixelJitter::Gaussian;
        s.lens = LensModel::Gaussian;
        s.lens_sigma = 0.3f;
    }
    return Camera(s);
}

Scene empty_scene() {
    Scene scene;
    scene.commit();
    return scene;
}

bool same_bytes(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec3)) == 0;
}

}  // namespace

TEST(Renderer, ImageIsIdenticalForAnyThreadCountAndTileSize) {
    const Scene scene = empty_scene();
    const Camera camera = small_camera(37, 23);
    HashIntegrator integrator;
    RenderSettings settings;
    settings.samples_per_pixel = 5;
    settings.seed = 42;
    settings.progress = nullptr;
    settings.threads = 1;
    RenderStats stats;
    const Image reference = render(scene, camera, integrator, settings, &stats);
    EXPECT_EQ(stats.samples, 37u * 23u * 5u);
    EXPECT_EQ(stats.nonfinite_samples, 0u);
    EXPECT_FALSE(stats.cancelled);
    for (const int threads : {2, 3, 0}) {
        for (const int tile : {1, 7, 16, 64}) {
            settings.threads = threads;
            settings.tile_size = tile;
            const Image image = render(scene, camera, integrator, settings);
            EXPECT_TRUE(same_bytes(image, reference)) << threads << " threads, tile " << tile;
        }
    }
    EXPECT_EQ(integrator.preprocess_calls, 13);
    // A different seed gives a different image.
    settings.seed = 43;
    EXPECT_FALSE(same_bytes(render(scene, camera, integrator, settings), reference));
}

TEST(Renderer, PixelIsTheMeanOfItsSamples) {
    const Scene scene = empty_scene();
    const Camera camera = small_camera(4, 3);
    HashIntegrator integrator;
    RenderSettings settings;
    settings.samples_per_pixel = 6;
    settings.seed = 7;
    settings.progress = nullptr;
    // Every pixel its 6 samples of Sampler(x, y, s, seed), the independent kind, as below.
    settings.sampler = SamplerKind::Independent;
    settings.adaptive.enabled = false;
    const Image image = render(scene, camera, integrator, settings);
    for (int y = 0; y < 3; ++y) {
        for (int x = 0; x < 4; ++x) {
            glm::dvec3 sum(0.0);
            for (std::uint32_t s = 0; s < 6; ++s) {
                Sampler sampler(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y), s, 7);
                const Ray ray = camera.generate_ray(x, y, sampler);
                sum += glm::dvec3(integrator.li(scene, ray, sampler));
            }
            const glm::vec3 expected(sum / 6.0);
            EXPECT_EQ(image.at(x, y), expected) << x << "," << y;
        }
    }
}

TEST(Renderer, NonFiniteSamplesAreDroppedAndCounted) {
    const Scene scene = empty_scene();
    const Camera camera = small_camera(16, 8, false);
    const SometimesNan integrator_const;
    SometimesNan integrator;
    RenderSettings settings;
    settings.samples_per_pixel = 8;
    settings.progress = nullptr;
    settings.threads = 2;
    // Every pixel its 8 samples of Sampler(x, y, s, 0), the independent kind, as below.
    settings.sampler = SamplerKind::Independent;
    settings.adaptive.enabled = false;
    RenderStats stats;
    const Image image = render(scene, camera, integrator, settings, &stats);
    std::uint64_t expected_nonfinite = 0;
    for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 16; ++x) {
            int finite = 0;
            for (std::uint32_t s = 0; s < 8; ++s) {
                Sampler sampler(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y), s, 0);
                const glm::vec3 l =
                    integrator_const.li(scene, camera.generate_ray(x, y, sampler), sampler);
                std::isfinite(l.x) ? ++finite : ++expected_nonfinite;
            }
            // The mean of the finite samples, which are all 1; black when none is left.
            EXPECT_EQ(image.at(x, y), glm::vec3(finite > 0 ? 1.0f : 0.0f));
        }
    }
    EXPECT_GT(expected_nonfinite, 0u);
    EXPECT_EQ(stats.nonfinite_samples, expected_nonfinite);
    EXPECT_EQ(stats.samples, 16u * 8u * 8u);
}

// Cancelled from inside, by the integrator's 100th sample: the renderer checks the flag
// before every pixel (one sample each here), so each of the two threads stops after at
// most one more sample; unfinished pixels stay black.
TEST(Renderer, CancellationStopsAtTheNextPixel) {
    const Scene scene = empty_scene();
    const Camera camera = small_camera(256, 256, false);
    std::atomic<bool> cancel{false};
    librt::testing::CancellingIntegrator integrator(cancel, 100);
    RenderSettings settings;
    settings.threads = 2;
    settings.progress = nullptr;
    settings.cancel = &cancel;
    RenderStats stats;
    const Image image = render(scene, camera, integrator, settings, &stats);
    EXPECT_TRUE(stats.cancelled);
    EXPECT_EQ(stats.samples, integrator.calls());
    EXPECT_GE(stats.samples, 100u);
    EXPECT_LE(stats.samples, integrator.max_samples(2, 1));
    ASSERT_EQ(image.width, 256);
    std::uint64_t rendered = 0;  // pixels of the one sample, 1; the others black
    for (const glm::vec3& p : image.pixels) rendered += p == glm::vec3(1.0f) ? 1 : 0;
    EXPECT_EQ(rendered, stats.samples);

    // Cancelled before it starts: nothing rendered.
    settings.progress = [](const RenderProgress&) {};  // a callback must not change the result
    RenderStats none;
    const Image black = render(scene, camera, integrator, settings, &none);
    EXPECT_TRUE(none.cancelled);
    EXPECT_EQ(none.samples, 0u);
    EXPECT_EQ(black.at(128, 128), glm::vec3(0.0f));
}

// Within a pixel the flag is checked every 64 samples: a pixel of 2^20 samples cannot hold
// up a cancelled render.
TEST(Renderer, CancellationStopsWithinAPixel) {
    const Scene scene = empty_scene();
    const Camera camera = small_camera(2, 1, false);  // one pixel per thread
    std::atomic<bool> cancel{false};
    librt::testing::CancellingIntegrator integrator(cancel, 1000);
    RenderSettings settings;
    settings.samples_per_pixel = 1 << 20;
    settings.threads = 2;
    settings.tile_size = 1;
    settings.progress = nullptr;
    settings.cancel = &cancel;
    RenderStats stats;
    (void)render(scene, camera, integrator, settings, &stats);
    EXPECT_TRUE(stats.cancelled);
    EXPECT_GE(stats.samples, 1000u);
    EXPECT_LE(stats.samples, integrator.max_samples(2, 64));
}

TEST(Renderer, IntegratorExceptionIsRethrown) {
    const Scene scene = empty_scene();
    const Camera camera = small_camera(32, 32, false);
    Throwing integrator;
    RenderSettings settings;
    settings.threads = 2;
    settings.progress = nullptr;
    EXPECT_THROW((void)render(scene, camera, integrator, settings), std::runtime_error);
}

TEST(Renderer, InvalidSettingsNameTheParameter) {
    const Scene scene = empty_scene();
    const Camera camera = small_camera(2, 2, false);
    HashIntegrator integrator;
    const auto expect_error = [&](RenderSettings s, const std::string& name) {
        try {
            (void)render(scene, camera, integrator, s);
            ADD_FAILURE() << name;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        }
    };
    RenderSettings s;
    s.samples_per_pixel = 0;
    expect_error(s, "samples_per_pixel = 0");
    s = {};
    s.samples_per_pixel = (1 << 20) + 1;
    expect_error(s, "samples_per_pixel = 1048577");
    s = {};
    s.threads = -1;
    expect_error(s, "threads = -1");
    s = {};
    s.threads = 1025;
    expect_error(s, "threads = 1025");
    s = {};
    s.tile_size = 0;
    expect_error(s, "tile_size = 0");
    EXPECT_EQ(integrator.preprocess_calls, 0);  // validated before anything runs
}

TEST(Renderer, OversizedFilmIsRejectedBeforeAllocating) {
    const Scene scene = empty_scene();
    CameraSettings cs;
    cs.width = 65536;
    cs.height = 65536;  // 48 GiB of float RGB
    HashIntegrator integrator;
    try {
        (void)render(scene, Camera(cs), integrator, RenderSettings{});
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("65536 x 65536"), std::string::npos) << e.what();
    }
}

TEST(Renderer, RendersARealSceneWithoutNaN) {
    Scene scene;
    const std::uint32_t white = scene.add_material(Material::diffuse(glm::vec3(0.8f)));
    (void)scene.add_sphere(Sphere{{0.0f, 0.0f, 0.0f}, 1.0f}, white);
    scene.add_point_light(PointLight::from_power({0.0f, 5.0f, 5.0f}, 1000.0f));
    scene.commit();
    CameraSettings cs;
    cs.position = {0.0f, 0.0f, 5.0f};
    cs.width = 24;
    cs.height = 24;
    const Camera camera(cs);
    DirectLighting integrator;
    RenderSettings settings;
    settings.progress = nullptr;
    const Image image = render(scene, camera, integrator, settings);
    EXPECT_GT(image.at(12, 10).x, 0.0f);         // lit sphere in the middle
    EXPECT_EQ(image.at(0, 0), glm::vec3(0.0f));  // background
}
