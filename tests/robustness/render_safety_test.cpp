// Scenes that are legal but odd: nothing in them, the camera inside an object, a light
// inside a glass sphere. They render (finite, no crash, nothing dropped); what they show
// is what physics says. (NaN-provoking scenes: Integrators.FiniteOnHostileScenes and
// Integrators.FiniteOnDegenerateGeometry.)

#include "robustness/robustness_util.h"

#include <librt/film/camera.h>
#include <librt/geometry/procedural.h>
#include <librt/integrator/integrators.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

using namespace librt;

namespace {

/// One of each integrator, owned.
struct AllIntegrators {
    PathTracer path{PathTracerSettings{5, false}};
    PathTracer roulette{PathTracerSettings{20, true, 2}};
    DirectLighting direct;
    BruteForcePathTracer brute{PathTracerSettings{5, false}};
    AlbedoNormalIntegrator albedo{DebugView::Albedo};
    AlbedoNormalIntegrator normal{DebugView::Normal};
    std::vector<GuardedIntegrator*> all() {
        return {&path, &roulette, &direct, &brute, &albedo, &normal};
    }
};

struct Rendered {
    Image image;
    RenderStats stats;
};

Rendered render_small(const Scene& scene, Integrator& integrator, const glm::vec3& eye,
                      const glm::vec3& look_at, int spp = 4) {
    CameraSettings cs;
    cs.position = eye;
    cs.look_at = look_at;
    cs.width = cs.height = 8;
    cs.pixel_jitter = PixelJitter::Gaussian;
    RenderSettings settings;
    settings.samples_per_pixel = spp;
    settings.threads = 2;
    settings.progress = nullptr;
    Rendered r;
    r.image = render(scene, Camera(cs), integrator, settings, &r.stats);
    return r;
}

bool all_finite(const Image& image) {
    for (const glm::vec3& p : image.pixels)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
    return true;
}

glm::dvec3 mean(const Image& image) {
    glm::dvec3 sum(0.0);
    for (const glm::vec3& p : image.pixels) sum += glm::dvec3(p);
    return sum / double(image.pixels.size());
}

}  // namespace

TEST(OddScene, EmptySceneRendersBlack) {
    AllIntegrators integrators;
    Scene empty;
    empty.commit();
    Scene
        lights_only;  // lights but no surface: still nothing to see (a point light is no geometry)
    lights_only.add_point_light({{0, 5, 0}, glm::vec3(100.0f)});
    lights_only.commit();
    for (const Scene* scene : {&empty, &lights_only}) {
        for (GuardedIntegrator* integ : integrators.all()) {
            const Rendered r = render_small(*scene, *integ, {0, 0, 5}, {0, 0, 0});
            EXPECT_EQ(r.stats.nonfinite_samples, 0u);
            EXPECT_EQ(r.stats.samples, 8u * 8u * 4u);
            for (const glm::vec3& p : r.image.pixels) ASSERT_EQ(p, glm::vec3(0.0f));
        }
    }
    // An uncommitted scene cannot be rendered: an error, not a crash.
    Scene uncommitted;
    PathTracer path(PathTracerSettings{5, false});
    EXPECT_TRUE(librt::testing::has(librt::testing::error_of([&] {
                                        (void)render_small(uncommitted, path, {0, 0, 5}, {0, 0, 0});
                                    }),
                                    "commit"));
}

TEST(OddScene, CameraInsideAnObject) {
    AllIntegrators integrators;
    Scene scene;
    const auto white = scene.add_material(Material::diffuse(glm::vec3(0.7f)));
    (void)scene.add_sphere({{0, 0, 0}, 2.0f}, white);  // the camera is inside this sphere
    (void)scene.add_mesh(make_box({4, -1, -1}, {6, 1, 1}), white);
    scene.add_point_light({{10, 0, 0}, glm::vec3(1000.0f)});  // outside: cannot reach the eye
    scene.add_sphere_light({{{0, 10, 0}, 1.0f}, glm::vec3(50.0f)});
    scene.commit();
    for (GuardedIntegrator* integ : integrators.all()) {
        const Rendered r = render_small(scene, *integ, {0, 0, 0.5f}, {0, 0, -1});
        EXPECT_EQ(r.stats.nonfinite_samples, 0u);
        ASSERT_TRUE(all_finite(r.image));
        if (integ != &integrators.albedo && integ != &integrators.normal) {
            // The inside of a closed sphere is lit by nothing: black.
            EXPECT_EQ(mean(r.image), glm::dvec3(0.0)) << "integrator " << integ;
        }
    }
    // Inside the box: the same.
    const Rendered r = render_small(scene, integrators.path, {5, 0, 0}, {5, 0, -1});
    EXPECT_EQ(mean(r.image), glm::dvec3(0.0));
    // The albedo view sees the inner wall everywhere.
    const Rendered a = render_small(scene, integrators.albedo, {0, 0, 0.5f}, {0, 0, -1});
    EXPECT_NEAR(mean(a.image).x, 0.7, 1e-6);
    for (GuardedIntegrator* integ : integrators.all()) EXPECT_EQ(integ->nonfinite_count(), 0u);
}

TEST(OddScene, CameraInsideAnEmitter) {
    Scene scene;
    (void)scene.add_sphere_light({{{0, 0, 0}, 3.0f}, glm::vec3(2.0f)});
    scene.commit();
    AllIntegrators integrators;
    // Seen from inside, the light's surface shows its radiance in every direction.
    for (GuardedIntegrator* integ : {static_cast<GuardedIntegrator*>(&integrators.path),
                                     static_cast<GuardedIntegrator*>(&integrators.direct),
                                     static_cast<GuardedIntegrator*>(&integrators.brute)}) {
        const Rendered r = render_small(scene, *integ, {0, 0, 1}, {0, 0, 0});
        for (const glm::vec3& p : r.image.pixels) ASSERT_EQ(p, glm::vec3(2.0f));
    }
}

TEST(OddScene, LightsInsideGlassSpheres) {
    Scene scene;
    const auto white = scene.add_material(Material::diffuse(glm::vec3(0.8f)));
    const auto glass = scene.add_material(Material::dielectric(1.5f));
    const auto glass_no_fresnel = scene.add_material(Material::dielectric(1.5f, false));
    scene.add_triangle({{-20, -1, -20}, {-20, -1, 20}, {20, -1, 20}}, white);
    scene.add_triangle({{-20, -1, -20}, {20, -1, 20}, {20, -1, -20}}, white);
    (void)scene.add_sphere({{-2, 1, 0}, 1.0f}, glass);
    (void)scene.add_sphere_light({{{-2, 1, 0}, 0.3f}, glm::vec3(30.0f)});
    (void)scene.add_sphere({{2, 1, 0}, 1.0f}, glass_no_fresnel);
    scene.add_point_light({{2, 1, 0}, glm::vec3(100.0f)});
    scene.commit();
    AllIntegrators integrators;
    for (GuardedIntegrator* integ : integrators.all()) {
        const Rendered r = render_small(scene, *integ, {0, 3, 8}, {0, 0, 0}, 8);
        EXPECT_EQ(r.stats.nonfinite_samples, 0u);
        ASSERT_TRUE(all_finite(r.image));
        EXPECT_EQ(integ->nonfinite_count(), 0u);
    }
    // Next-event estimation cannot see through glass (shadow rays stop at it), so with
    // direct lighting the floor gets nothing; the path tracers carry the light out by
    // refraction, which only random bounces find: the emitter seen through the glass.
    const Rendered path = render_small(scene, integrators.path, {0, 3, 8}, {0, 0, 0}, 16);
    EXPECT_GT(mean(path.image).x, 0.0);
}
